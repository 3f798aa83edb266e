// SPDX-License-Identifier: MIT
// Fuzzing: the STL and OFF mesh readers (io::parse_mesh_stl: binary and ASCII, welded; io::parse_mesh_off),
// each given every input. Properties: an OFF mesh read writes OFF text that reads back to the same text;
// an STL mesh read, written and read again is a fixed point of writing (its positions are floats then).
#include "cifs/io/mesh_formats.hpp"
#include "fuzz.hpp"

// Named, not anonymous: the harnesses compile as unity batches (CIFS_UNITY), each in its own namespace.
namespace fuzz_mesh_exchange {

const cifs::io::MeshReadOptions kQuiet{.warn = [](const std::string&) {}};

std::string stl(const cifs::Mesh& mesh) {
  cifs::StringSink out;
  cifs::io::mesh_stl(mesh, out);
  return std::move(out.bytes);
}

std::string off(const cifs::Mesh& mesh) {
  cifs::StringSink out;
  cifs::io::mesh_off(mesh, out);
  return std::move(out.bytes);
}

CIFS_FUZZ_HARNESS(mesh_exchange) {
  using namespace cifs;
  const std::string_view bytes = fuzz::text(data, size);
  fuzz::refusals_allowed([&] {
    const std::string text = off(io::parse_mesh_off(bytes, "fuzz.off", kQuiet));
    fuzz::require(off(io::parse_mesh_off(text, "again.off", kQuiet)) == text, "OFF mesh round trip");
  });
  fuzz::refusals_allowed([&] {
    // Writing rounds to floats, which may weld corners apart before: one round first, then a fixed point.
    const std::string once =
        stl(io::parse_mesh_stl(stl(io::parse_mesh_stl(bytes, "fuzz.stl", kQuiet)), "a.stl", kQuiet));
    fuzz::require(stl(io::parse_mesh_stl(once, "b.stl", kQuiet)) == once, "STL mesh round trip");
  });
  return 0;
}

}  // namespace fuzz_mesh_exchange
