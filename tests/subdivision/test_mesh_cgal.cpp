// SPDX-License-Identifier: MIT
// Subdivision surfaces against CGAL's Subdivision_method_3 (Doo–Sabin, √3, Catmull–Clark, Loop),
// closed and open meshes. CGAL is GPL: this cross-check is a separate, optional executable
// (CIFS_CGAL_CHECK, built when libcgal-dev is installed) and no cifs library links it.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include <catch2/catch.hpp>

#include "cifs/subdivision/mesh.hpp"
#include "subdivision/mesh_compare.hpp"
#include "subdivision/meshes.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

SurfaceMesh to_cgal(const Mesh& m) {
  SurfaceMesh out;
  std::vector<SurfaceMesh::Vertex_index> handles;
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    handles.push_back(out.add_vertex({m.vertices(i, 0), m.vertices(i, 1), m.vertices(i, 2)}));
  for (std::size_t f = 0; f < face_count(m); ++f) {
    std::vector<SurfaceMesh::Vertex_index> corners;
    for (const int c : face(m, f)) corners.push_back(handles[static_cast<std::size_t>(c)]);
    REQUIRE(out.add_face(corners) != SurfaceMesh::null_face());
  }
  return out;
}

Mesh from_cgal(SurfaceMesh& m) {
  m.collect_garbage();
  Mesh out;
  out.vertices.resize(static_cast<Eigen::Index>(m.number_of_vertices()), 3);
  for (const auto v : m.vertices()) {
    const auto& p = m.point(v);
    for (int k = 0; k < 3; ++k) out.vertices(static_cast<Eigen::Index>(v.idx()), k) = p[k];
  }
  for (const auto f : m.faces()) {
    std::vector<int> corners;
    for (const auto v : CGAL::vertices_around_face(m.halfedge(f), m))
      corners.push_back(static_cast<int>(v.idx()));
    add_face(out, std::span<const int>(corners));
  }
  return out;
}

enum class Method { doo_sabin, sqrt3, catmull_clark, loop };

Mesh cgal_refine(const Mesh& m, Method method, int levels) {
  SurfaceMesh sm = to_cgal(m);
  const auto iterations = CGAL::parameters::number_of_iterations(static_cast<unsigned>(levels));
  switch (method) {
    case Method::doo_sabin:
      CGAL::Subdivision_method_3::DooSabin_subdivision(sm, iterations);
      break;
    case Method::sqrt3:
      CGAL::Subdivision_method_3::Sqrt3_subdivision(sm, iterations);
      break;
    case Method::catmull_clark:
      CGAL::Subdivision_method_3::CatmullClark_subdivision(sm, iterations);
      break;
    case Method::loop:
      CGAL::Subdivision_method_3::Loop_subdivision(sm, iterations);
      break;
  }
  return from_cgal(sm);
}

}  // namespace

TEST_CASE("Doo–Sabin and Catmull–Clark = CGAL, closed and open polygon meshes, levels 1–3",
          "[subdivision][mesh][cgal]") {
  const std::vector<std::pair<const char*, Mesh>> meshes{{"cube", cube()},
                                                         {"pyramid", pyramid()},
                                                         {"torus", torus(6, 5)},
                                                         {"grid", quad_grid(4, 3)},
                                                         {"tetrahedron", tetrahedron()},
                                                         {"open triangles", quad_grid(3, 2, true)},
                                                         {"fan", fan(5)}};
  for (const auto& [name, m] : meshes)
    for (int levels = 1; levels <= 3; ++levels) {
      INFO(name << ", level " << levels);
      check_same_mesh(doo_sabin(m, levels), cgal_refine(m, Method::doo_sabin, levels));
      check_same_mesh(catmull_clark(m, levels), cgal_refine(m, Method::catmull_clark, levels));
    }
}

TEST_CASE("√3 and Loop = CGAL, closed and open triangle meshes, levels 1–4", "[subdivision][mesh][cgal]") {
  const std::vector<std::pair<const char*, Mesh>> meshes{{"tetrahedron", tetrahedron()},
                                                         {"octahedron", octahedron()},
                                                         {"bipyramid", bipyramid()},
                                                         {"torus", torus(6, 5, true)},
                                                         {"open triangles", quad_grid(4, 3, true)},
                                                         {"fan", fan(5)},
                                                         {"strip", quad_grid(5, 1, true)}};
  for (const auto& [name, m] : meshes)
    for (int levels = 1; levels <= 4; ++levels) {
      INFO(name << ", level " << levels);
      check_same_mesh(sqrt3(m, levels), cgal_refine(m, Method::sqrt3, levels));
      check_same_mesh(loop(m, levels), cgal_refine(m, Method::loop, levels));
    }
}
