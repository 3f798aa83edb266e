// SPDX-License-Identifier: MIT
// Fuzzing: BC-IFS files (io::parse_bcifs_json, then ifs::validate).
#include "cifs/io/json.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(bcifs) {
  using namespace cifs;
  fuzz::refusals_allowed([&] { io::parse_bcifs_json(fuzz::text(data, size), "fuzz.json"); });
  return 0;
}
