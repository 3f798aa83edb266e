// SPDX-License-Identifier: MIT
// Fuzzing: OBJ free-form geometry (io::parse_obj: curv, surf, bspline and rat bspline, trims).
// Property: every shape read writes back as OBJ (to_obj) that reads back to the same text.
#include "cifs/io/obj.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(obj_freeform) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    const io::ShapeReadOptions options{
        .ignore_trim = size % 2 == 0, .index = {}, .warn = [](const std::string&) {}};
    for (const io::Shape& shape : io::parse_obj(fuzz::text(data, size), "fuzz.obj", options)) {
      const std::string obj = io::to_obj(shape);
      const std::vector<io::Shape> again = io::parse_obj(obj, "again.obj");
      fuzz::require(again.size() == 1 && io::to_obj(again.front()) == obj, "OBJ free-form round trip");
    }
  });
  return 0;
}
