// SPDX-License-Identifier: MIT
// Fuzzing: BC-IFS files (io::parse_bcifs_json, then ifs::validate).
#include "cifs/io/json.hpp"
#include "fuzz.hpp"

// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cifs;
  fuzz::refusals_allowed([&] { io::parse_bcifs_json(fuzz::text(data, size), "fuzz.json"); });
  return 0;
}
