// SPDX-License-Identifier: MIT
// Fuzzing: JSON shape files (io::parse_shapes_json: cifs curves and surfaces, Rhino knots, geomdl).
// Property: every shape read writes back (to_json) into text that reads back to the same text.
#include "cifs/io/json.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(shape_json) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    const io::ShapeReadOptions options{.ignore_trim = false, .index = {}, .warn = [](const std::string&) {}};
    for (const io::Shape& shape : io::parse_shapes_json(fuzz::text(data, size), "fuzz.json", options)) {
      const std::string json = io::to_json(shape);
      fuzz::require(io::to_json(io::parse_shape_json(json, "again.json")) == json, "shape JSON round trip");
    }
  });
  return 0;
}
