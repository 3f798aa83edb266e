// SPDX-License-Identifier: MIT
// Fuzzing: PLY polygon meshes (io::parse_mesh_ply: ASCII and both binary encodings). Property: a
// mesh read writes back as binary PLY that reads back to the same bytes.
#include "cifs/io/ply.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(mesh_ply) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    const Mesh mesh = io::parse_mesh_ply(fuzz::text(data, size), "fuzz.ply");
    const std::string ply = io::mesh_ply(mesh, io::PlyFormat::binary_little_endian);
    fuzz::require(
        io::mesh_ply(io::parse_mesh_ply(ply, "again.ply"), io::PlyFormat::binary_little_endian) == ply,
        "PLY mesh round trip");
  });
  return 0;
}
