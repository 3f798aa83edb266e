// SPDX-License-Identifier: MIT
// STL and OFF against OpenMesh's readers and writers (test-only oracle): what cifs writes OpenMesh
// reads as the same mesh, and what OpenMesh writes cifs reads as the same mesh.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/mesh_formats.hpp"
#include "io/mesh_samples.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using OmPoly = OpenMesh::PolyMesh_ArrayKernelT<>;
using OmTri = OpenMesh::TriMesh_ArrayKernelT<>;

namespace {

/// The faces of an OpenMesh mesh as corner lists, each rotated to start at its smallest index.
template <class OmMesh>
std::vector<std::vector<int>> om_faces(const OmMesh& om) {
  std::vector<std::vector<int>> faces;
  for (const auto f : om.faces()) {
    std::vector<int> c;
    for (const auto v : om.fv_range(f)) c.push_back(v.idx());
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    faces.push_back(c);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

std::vector<std::vector<int>> cifs_faces(const Mesh& m) {
  std::vector<std::vector<int>> faces;
  for (std::size_t f = 0; f < face_count(m); ++f) {
    std::vector<int> c(face(m, f).begin(), face(m, f).end());
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    faces.push_back(c);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

}  // namespace

TEST_CASE("OFF and STL written by cifs read by OpenMesh, and written by OpenMesh read by cifs",
          "[io][openmesh]") {
  cifs_test::ScratchDir dir;
  const Mesh grid = io_test::open_grid(4);

  // OFF: the same vertices (OpenMesh keeps floats) and faces.
  const auto off = dir.path() / "grid.off";
  io::write(off, grid);
  OmPoly poly;
  REQUIRE(OpenMesh::IO::read_mesh(poly, off.string()));
  REQUIRE(static_cast<Eigen::Index>(poly.n_vertices()) == grid.vertices.rows());
  for (const auto v : poly.vertices())
    for (int c = 0; c < 3; ++c) CHECK(poly.point(v)[c] == static_cast<float>(grid.vertices(v.idx(), c)));
  CHECK(om_faces(poly) == cifs_faces(grid));

  // STL: OpenMesh welds the triangle soup as cifs does.
  const auto stl = dir.path() / "grid.stl";
  io::write(stl, grid);
  OmTri tri;
  OpenMesh::IO::Options binary = OpenMesh::IO::Options::Binary;
  REQUIRE(OpenMesh::IO::read_mesh(tri, stl.string(), binary));
  const Mesh back = io::read_mesh(stl);
  REQUIRE(tri.n_vertices() == static_cast<std::size_t>(back.vertices.rows()));
  REQUIRE(tri.n_faces() == face_count(back));
  CHECK(back.vertices.rows() == grid.vertices.rows());
  for (const auto v : tri.vertices())
    for (int c = 0; c < 3; ++c) CHECK(tri.point(v)[c] == static_cast<float>(back.vertices(v.idx(), c)));
  CHECK(om_faces(tri) == cifs_faces(back));

  // The other way: OpenMesh's OFF and binary and ASCII STL, read by cifs.
  for (const auto& [name, options] :
       {std::pair{"om.off", OpenMesh::IO::Options()},
        std::pair{"om_binary.stl", OpenMesh::IO::Options(OpenMesh::IO::Options::Binary)},
        std::pair{"om_ascii.stl", OpenMesh::IO::Options()}}) {
    const auto path = dir.path() / name;
    REQUIRE(OpenMesh::IO::write_mesh(tri, path.string(), options, 9));  // 9 digits: floats exactly
    const Mesh read = io::read_mesh(path);
    INFO(name);
    REQUIRE(read.vertices.rows() == static_cast<Eigen::Index>(tri.n_vertices()));
    for (const auto v : tri.vertices())
      for (int c = 0; c < 3; ++c) CHECK(static_cast<float>(read.vertices(v.idx(), c)) == tri.point(v)[c]);
    CHECK(cifs_faces(read) == om_faces(tri));
  }
}
