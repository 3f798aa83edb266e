// SPDX-License-Identifier: MIT
// Fuzzing: control polygon files (io::parse_polygon_json, what `cifs scheme --refine` reads).
// Property: a polygon read writes back (to_json) into text that reads back to the same text.
#include "cifs/io/json.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(polygon) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    const std::string json = io::to_json(io::parse_polygon_json(fuzz::text(data, size), "fuzz.json"));
    fuzz::require(io::to_json(io::parse_polygon_json(json, "again.json")) == json, "polygon JSON round trip");
  });
  return 0;
}
