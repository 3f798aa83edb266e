// SPDX-License-Identifier: MIT
// Fuzzing: OBJ polygon meshes (io::parse_mesh_obj). Property: a mesh read writes back (mesh_obj)
// into text that reads back to the same text.
#include "cifs/io/obj.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(mesh_obj) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    const std::string obj = io::mesh_obj(io::parse_mesh_obj(fuzz::text(data, size), "fuzz.obj"));
    fuzz::require(io::mesh_obj(io::parse_mesh_obj(obj, "again.obj")) == obj, "OBJ mesh round trip");
  });
  return 0;
}
