// SPDX-License-Identifier: MIT
// Subdivision surfaces against independent implementations: OpenSubdiv Far (Catmull–Clark, Loop,
// boundaries both ways) and OpenMesh's uniform subdividers (Loop, √3, modified Butterfly, closed and
// open meshes). Both are permissive licences, linked into this test executable only.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/ModifiedButterFlyT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/Sqrt3T.hh>
#include <catch2/catch.hpp>
#include <memory>

#include "cifs/subdivision/mesh.hpp"
#include "subdivision/mesh_compare.hpp"
#include "subdivision/meshes.hpp"
#include "subdivision/osd_refiner.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

Mesh osd_refine(const Mesh& m, Sdc::SchemeType type, BoundaryRule boundary, int levels) {
  const auto refiner =
      osd_refiner(m, type,
                  boundary == BoundaryRule::edge_only ? Sdc::Options::VTX_BOUNDARY_EDGE_ONLY
                                                      : Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER,
                  levels);
  REQUIRE(refiner);
  std::vector<OsdVertex> verts(static_cast<std::size_t>(refiner->GetNumVerticesTotal()));
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    for (int k = 0; k < 3; ++k) verts[static_cast<std::size_t>(i)].p[k] = m.vertices(i, k);
  Far::PrimvarRefinerReal<double> primvars(*refiner);
  OsdVertex* src = verts.data();
  for (int level = 1; level <= levels; ++level) {
    OsdVertex* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
    primvars.Interpolate(level, src, dst);
    src = dst;
  }
  const Far::TopologyLevel& last = refiner->GetLevel(levels);
  Mesh out;
  out.vertices.resize(last.GetNumVertices(), 3);
  for (int i = 0; i < last.GetNumVertices(); ++i)
    for (int k = 0; k < 3; ++k) out.vertices(i, k) = src[i].p[k];
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    const auto corners = last.GetFaceVertices(f);
    std::vector<int> face(corners.begin(), corners.end());
    add_face(out, std::span<const int>(face));
  }
  return out;
}

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

template <class Subdivider>
Mesh openmesh_refine(const Mesh& m, int levels) {
  TriMesh om;
  std::vector<TriMesh::VertexHandle> handles;
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    handles.push_back(om.add_vertex(TriMesh::Point(m.vertices(i, 0), m.vertices(i, 1), m.vertices(i, 2))));
  for (std::size_t f = 0; f < face_count(m); ++f) {
    const auto c = face(m, f);
    om.add_face(handles[static_cast<std::size_t>(c[0])], handles[static_cast<std::size_t>(c[1])],
                handles[static_cast<std::size_t>(c[2])]);
  }
  Subdivider subdivider;
  subdivider.attach(om);
  subdivider(static_cast<std::size_t>(levels));
  subdivider.detach();
  Mesh out;
  out.vertices.resize(static_cast<Eigen::Index>(om.n_vertices()), 3);
  for (const auto v : om.vertices()) {
    const auto p = om.point(v);
    for (int k = 0; k < 3; ++k) out.vertices(v.idx(), k) = p[k];
  }
  for (const auto f : om.faces()) {
    std::vector<int> corners;
    for (const auto v : om.fv_range(f)) corners.push_back(v.idx());
    add_face(out, std::span<const int>(corners));
  }
  return out;
}

}  // namespace

TEST_CASE("Catmull–Clark = OpenSubdiv Far, closed and open meshes, both boundary rules, levels 1–4",
          "[subdivision][mesh][oracle]") {
  const std::vector<std::pair<const char*, Mesh>> meshes{
      {"cube", cube()},          {"pyramid", pyramid()},         {"torus", torus(6, 5)},
      {"grid", quad_grid(4, 3)}, {"tetrahedron", tetrahedron()}, {"open triangles", quad_grid(3, 2, true)}};
  for (const auto& [name, m] : meshes)
    for (const BoundaryRule rule : {BoundaryRule::edge_only, BoundaryRule::edge_and_corner})
      for (int levels = 1; levels <= 4; ++levels) {
        INFO(name << ", level " << levels << ", corners " << (rule == BoundaryRule::edge_and_corner));
        check_same_mesh(catmull_clark(m, levels, {.boundary = rule}),
                        osd_refine(m, Sdc::SCHEME_CATMARK, rule, levels));
      }
}

TEST_CASE("Loop = OpenSubdiv Far, closed and open meshes, both boundary rules, levels 1–4",
          "[subdivision][mesh][oracle]") {
  const std::vector<std::pair<const char*, Mesh>> meshes{{"tetrahedron", tetrahedron()},
                                                         {"octahedron", octahedron()},
                                                         {"bipyramid", bipyramid()},
                                                         {"torus", torus(6, 5, true)},
                                                         {"open triangles", quad_grid(4, 3, true)}};
  for (const auto& [name, m] : meshes)
    for (const BoundaryRule rule : {BoundaryRule::edge_only, BoundaryRule::edge_and_corner})
      for (int levels = 1; levels <= 4; ++levels) {
        INFO(name << ", level " << levels << ", corners " << (rule == BoundaryRule::edge_and_corner));
        check_same_mesh(loop(m, levels, {.boundary = rule}), osd_refine(m, Sdc::SCHEME_LOOP, rule, levels));
      }
}

TEST_CASE(
    "Loop, √3 and modified Butterfly = OpenMesh's uniform subdividers, closed and open meshes, levels 1–4",
    "[subdivision][mesh][oracle]") {
  const std::vector<std::pair<const char*, Mesh>> meshes{{"tetrahedron", tetrahedron()},
                                                         {"octahedron", octahedron()},
                                                         {"bipyramid", bipyramid()},
                                                         {"torus", torus(6, 5, true)},
                                                         {"open triangles", quad_grid(4, 3, true)},
                                                         {"open fan", fan(5)},
                                                         {"open strip", quad_grid(5, 1, true)}};
  for (const auto& [name, m] : meshes)
    for (int levels = 1; levels <= 4; ++levels) {
      INFO(name << ", level " << levels);
      check_same_mesh(loop(m, levels),
                      openmesh_refine<OpenMesh::Subdivider::Uniform::LoopT<TriMesh, double>>(m, levels));
      check_same_mesh(sqrt3(m, levels),
                      openmesh_refine<OpenMesh::Subdivider::Uniform::Sqrt3T<TriMesh, double>>(m, levels));
      check_same_mesh(
          butterfly(m, levels),
          openmesh_refine<OpenMesh::Subdivider::Uniform::ModifiedButterflyT<TriMesh, double>>(m, levels));
    }
}
