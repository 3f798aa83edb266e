// SPDX-License-Identifier: MIT
// cifs — VTK XML PolyData (.vtp) for ParaView: the XML header, then the arrays as raw appended bytes
// (each a UInt64 byte count and the little-endian values), so that large meshes stay compact.
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/io/mesh_formats.hpp"

namespace cifs::io {
namespace {

template <class T>
void put(std::string& out, T x) {
  const auto bits = std::bit_cast<std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>>(x);
  for (std::size_t i = 0; i < sizeof(T); ++i) out += static_cast<char>((bits >> (8 * i)) & 0xffu);
}

/// One array of the appended block: its XML element (offset into the block) and its byte size.
struct VtkArray {
  std::string element;
  std::uint64_t bytes;
};

}  // namespace

void mesh_vtp(const Mesh& mesh, ByteSink& sink) {
  check_mesh(mesh, "the mesh to write as VTK PolyData");
  if (!mesh.normal_indices.empty())
    throw InvalidInput(
        "the mesh to write as VTK PolyData has normals per face corner (several at crease and "
        "corner vertices); its point data holds one per vertex: write OBJ, or drop the normals");
  const std::vector<char> hole = hole_flags(mesh);
  std::vector<std::size_t> kept;
  std::uint64_t corners = 0;
  for (std::size_t f = 0; f < face_count(mesh); ++f)
    if (hole[f] == 0) {
      kept.push_back(f);
      corners += face(mesh, f).size();
    }
  const auto points = static_cast<std::uint64_t>(mesh.vertices.rows());
  const bool normals = mesh.normals.size() != 0, states = !mesh.states.empty();
  std::uint64_t offset = 0;
  const auto array = [&](const std::string& attributes, std::uint64_t bytes) {
    VtkArray a{
        "<DataArray " + attributes + " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>",
        bytes};
    offset += 8 + bytes;
    return a;
  };
  // In the order of the appended block.
  const VtkArray xyz = array("type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"", 24 * points);
  const VtkArray connectivity = array("type=\"Int64\" Name=\"connectivity\"", 8 * corners);
  const VtkArray offsets = array("type=\"Int64\" Name=\"offsets\"", 8 * kept.size());
  const VtkArray normal =
      normals ? array("type=\"Float64\" Name=\"Normals\" NumberOfComponents=\"3\"", 24 * points) : VtkArray{};
  const VtkArray state = states ? array("type=\"UInt32\" Name=\"state\"", 4 * kept.size()) : VtkArray{};

  ChunkBuffer buffer(sink);
  std::string& out = buffer.text;
  out +=
      "<?xml version=\"1.0\"?>\n<!-- cifs mesh -->\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <PolyData>\n    <Piece NumberOfPoints=\"" +
      std::to_string(points) +
      "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
      std::to_string(kept.size()) + "\">\n";
  if (normals)
    out += "      <PointData Normals=\"Normals\">\n        " + normal.element + "\n      </PointData>\n";
  if (states) out += "      <CellData Scalars=\"state\">\n        " + state.element + "\n      </CellData>\n";
  out += "      <Points>\n        " + xyz.element + "\n      </Points>\n      <Polys>\n        " +
         connectivity.element + "\n        " + offsets.element +
         "\n      </Polys>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
  put(out, xyz.bytes);
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    for (Eigen::Index c = 0; c < 3; ++c) put(out, mesh.vertices(i, c));
    buffer.spill();
  }
  put(out, connectivity.bytes);
  for (const std::size_t f : kept) {
    for (const int v : face(mesh, f)) put(out, std::int64_t{v});
    buffer.spill();
  }
  put(out, offsets.bytes);
  std::int64_t end = 0;
  for (const std::size_t f : kept) {
    end += static_cast<std::int64_t>(face(mesh, f).size());
    put(out, end);
    buffer.spill();
  }
  if (normals) {
    put(out, normal.bytes);
    for (Eigen::Index i = 0; i < mesh.normals.rows(); ++i) {
      for (Eigen::Index c = 0; c < 3; ++c) put(out, mesh.normals(i, c));
      buffer.spill();
    }
  }
  if (states) {
    put(out, state.bytes);
    for (const std::size_t f : kept) put(out, mesh.states[f]);
  }
  out += "\n  </AppendedData>\n</VTKFile>\n";
  buffer.flush();
}

}  // namespace cifs::io
