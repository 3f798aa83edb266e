// SPDX-License-Identifier: MIT
// Subdivision surfaces against independent implementations: OpenSubdiv Far (Catmull–Clark, Loop,
// boundaries both ways) and OpenMesh's uniform subdividers (Loop, √3, modified Butterfly, closed and
// open meshes). Both are permissive licences, linked into this test executable only.
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <Eigen/Geometry>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/ModifiedButterFlyT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/Sqrt3T.hh>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <memory>

#include "cifs/subdivision/limit.hpp"
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

/// OpenSubdiv's refinement of m's positions by `levels` steps.
struct OsdRefined {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::vector<OsdVertex> vertices;  // every level's, one level after another
  std::size_t last = 0;             // where the last level's begin
};

OsdRefined osd_interpolate(const Mesh& m, Sdc::SchemeType type, BoundaryRule boundary, int levels,
                           bool full_topology = false) {
  OsdRefined r{.refiner = osd_refiner(with_boundary(m, boundary), type, levels, full_topology)};
  REQUIRE(r.refiner);
  r.vertices.resize(static_cast<std::size_t>(r.refiner->GetNumVerticesTotal()));
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    for (int k = 0; k < 3; ++k) r.vertices[static_cast<std::size_t>(i)].p[k] = m.vertices(i, k);
  Far::PrimvarRefinerReal<double> primvars(*r.refiner);
  for (int level = 1; level <= levels; ++level) {
    const std::size_t next =
        r.last + static_cast<std::size_t>(r.refiner->GetLevel(level - 1).GetNumVertices());
    OsdVertex *src = r.vertices.data() + r.last,
              *dst = r.vertices.data() + next;  // Interpolate takes lvalues
    primvars.Interpolate(level, src, dst);
    r.last = next;
  }
  return r;
}

Mesh osd_refine(const Mesh& m, Sdc::SchemeType type, BoundaryRule boundary, int levels) {
  const OsdRefined r = osd_interpolate(m, type, boundary, levels);
  const Far::TopologyLevel& last = r.refiner->GetLevel(levels);
  Mesh out;
  out.vertices.resize(last.GetNumVertices(), 3);
  for (int i = 0; i < last.GetNumVertices(); ++i)
    for (int k = 0; k < 3; ++k) out.vertices(i, k) = r.vertices[r.last + static_cast<std::size_t>(i)].p[k];
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    const auto corners = last.GetFaceVertices(f);
    std::vector<int> face(corners.begin(), corners.end());
    add_face(out, std::span<const int>(face));
  }
  return out;
}

/// OpenSubdiv's refined positions, limit positions and unit normals (du × dv) after `levels` steps.
std::array<Points, 3> osd_limit(const Mesh& m, Sdc::SchemeType type, BoundaryRule boundary, int levels) {
  const OsdRefined r = osd_interpolate(m, type, boundary, levels, true);
  const int n = r.refiner->GetLevel(levels).GetNumVertices();
  std::vector<OsdVertex> pos(static_cast<std::size_t>(n)), du(pos.size()), dv(pos.size());
  const OsdVertex* last = r.vertices.data() + r.last;
  OsdVertex *p = pos.data(), *u = du.data(), *v = dv.data();
  Far::PrimvarRefinerReal<double>(*r.refiner).Limit(last, p, u, v);
  Points refined(n, 3), positions(n, 3), normals(n, 3);
  for (int i = 0; i < n; ++i) {
    const auto at = static_cast<std::size_t>(i);
    const OsdVertex& s = r.vertices[r.last + at];
    refined.row(i) << s.p[0], s.p[1], s.p[2];
    const Eigen::Vector3d a(du[at].p[0], du[at].p[1], du[at].p[2]), b(dv[at].p[0], dv[at].p[1], dv[at].p[2]);
    positions.row(i) << pos[at].p[0], pos[at].p[1], pos[at].p[2];
    normals.row(i) = a.cross(b).normalized().transpose();
  }
  return {refined, positions, normals};
}

/// Our limit mesh against OpenSubdiv's, vertices matched by their refined positions.
void check_same_limit(const Mesh& m, MeshScheme scheme, Sdc::SchemeType type, BoundaryRule rule, int levels,
                      bool normals) {
  const Mesh ours = limit_mesh(with_boundary(m, rule), scheme, levels, {.normals = normals});
  const auto [refined, positions, osd_normals] = osd_limit(m, type, rule, levels);
  const std::vector<int> to_osd =
      match_vertices(subdivide(with_boundary(m, rule), scheme, levels).vertices, refined, 1e-12);
  const double scale = m.vertices.cwiseAbs().maxCoeff();
  double position_error = 0, normal_error = 0;
  for (std::size_t i = 0; i < to_osd.size(); ++i) {
    const auto a = static_cast<Eigen::Index>(i), b = static_cast<Eigen::Index>(to_osd[i]);
    position_error =
        std::max(position_error, (ours.vertices.row(a) - positions.row(b)).cwiseAbs().maxCoeff());
    if (normals)
      normal_error = std::max(normal_error, (ours.normals.row(a) - osd_normals.row(b)).cwiseAbs().maxCoeff());
  }
  CHECK(position_error <= 1e-12 * scale);
  CHECK(normal_error <= 1e-12);
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
        check_same_mesh(catmull_clark(with_boundary(m, rule), levels),
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
        check_same_mesh(loop(with_boundary(m, rule), levels), osd_refine(m, Sdc::SCHEME_LOOP, rule, levels));
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

TEST_CASE("limit positions and normals = OpenSubdiv Far's Limit, valences 3–8, closed and open",
          "[subdivision][limit][oracle]") {
  struct Case {
    const char* name;
    Mesh mesh;
    MeshScheme scheme;
    Sdc::SchemeType type;
    int levels;
  };
  std::vector<Case> cases{{"cube", cube(), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, 1},
                          {"torus", torus(6, 5), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, 1},
                          {"tetrahedron", tetrahedron(), MeshScheme::loop, Sdc::SCHEME_LOOP, 1},
                          {"octahedron", octahedron(), MeshScheme::loop, Sdc::SCHEME_LOOP, 2}};
  for (int k = 5; k <= 8; ++k) {
    cases.push_back({"bipyramid", bipyramid_of(k), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, 1});
    cases.push_back({"bipyramid", bipyramid_of(k), MeshScheme::loop, Sdc::SCHEME_LOOP, 1});
  }
  for (const auto& c : cases)
    for (int levels = c.levels; levels <= c.levels + 1; ++levels) {
      INFO(c.name << " (" << c.mesh.vertices.rows() << " vertices), " << scheme_name(c.scheme) << ", level "
                  << levels);
      check_same_limit(c.mesh, c.scheme, c.type, BoundaryRule::edge_only, levels, true);
    }
  // Open meshes: positions on the boundary too, under both rules (normals are not built there).
  for (const BoundaryRule rule : {BoundaryRule::edge_only, BoundaryRule::edge_and_corner}) {
    check_same_limit(quad_grid(4, 3), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, rule, 1, false);
    check_same_limit(quad_grid(3, 2, true), MeshScheme::loop, Sdc::SCHEME_LOOP, rule, 1, false);
  }
}

TEST_CASE("limit positions and normals = OpenSubdiv Far's Limit at poles of valence 64 and 360",
          "[subdivision][limit][oracle]") {
  // Smooth interior vertices: Far's masks are exact there, as cifs's closed forms (no eigensolver).
  for (const int k : {64, 360}) {
    INFO("valence " << k);
    check_same_limit(bipyramid_of(k), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, BoundaryRule::edge_only,
                     1, true);
    check_same_limit(bipyramid_of(k), MeshScheme::loop, Sdc::SCHEME_LOOP, BoundaryRule::edge_only, 1, true);
  }
}

TEST_CASE("limit positions = OpenSubdiv Far's Limit under infinitely sharp creases and corners",
          "[subdivision][limit][oracle]") {
  // Far is exact where every sharpness is infinite and no dart is present (it applies the smooth mask at
  // darts and the sharp one where sharpness is left to spend; test_mesh_limit_classes.cpp checks those
  // against deep refinement).
  Mesh box = cube();
  box.tags.creases = {{4, 5, 10}, {5, 6, 10}, {6, 7, 10}, {7, 4, 10}};
  box.tags.corners = {{0, 10}};
  Mesh ring = torus(6, 5);
  for (int i = 0; i < 6; ++i) ring.tags.creases.push_back({i, (i + 1) % 6, 10});
  Mesh belt = octahedron();
  belt.tags.creases = {{0, 2, 10}, {2, 1, 10}, {1, 3, 10}, {3, 0, 10}};
  Mesh grid = quad_grid(5, 4), trigrid = quad_grid(5, 4, true);
  for (Mesh* g : {&grid, &trigrid}) {
    for (int i = 6; i < 11; ++i) g->tags.creases.push_back({i, i + 1, 10});  // across, boundary to boundary
    g->tags.corners = {{14, 10}};
  }
  for (int levels = 1; levels <= 2; ++levels) {
    INFO("level " << levels);
    check_same_limit(box, MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, BoundaryRule::edge_only, levels,
                     false);
    check_same_limit(ring, MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, BoundaryRule::edge_only, levels,
                     false);
    check_same_limit(belt, MeshScheme::loop, Sdc::SCHEME_LOOP, BoundaryRule::edge_only, levels, false);
    for (const BoundaryRule rule : {BoundaryRule::edge_only, BoundaryRule::edge_and_corner}) {
      check_same_limit(grid, MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK, rule, levels, false);
      check_same_limit(trigrid, MeshScheme::loop, Sdc::SCHEME_LOOP, rule, levels, false);
    }
  }
}

TEST_CASE("the limit surface at (face, u, v) = OpenSubdiv Bfr, positions and partials, valences 3–8",
          "[subdivision][limit][oracle]") {
  // Bfr evaluates regular patches exactly and approximates irregular ones below its approximation
  // level (2 by default: off by 5e-4 next to an extraordinary vertex); at level 10 the approximated
  // region is far below these points, and both must agree in double.
  namespace Bfr = OpenSubdiv::Bfr;
  struct Case {
    const char* name;
    Mesh mesh;
    MeshScheme scheme;
    Sdc::SchemeType type;
  };
  std::vector<Case> cases{{"cube", catmull_clark(cube(), 1), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK},
                          {"torus", torus(6, 5), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK},
                          {"tetrahedron", loop(tetrahedron(), 1), MeshScheme::loop, Sdc::SCHEME_LOOP},
                          {"octahedron", loop(octahedron(), 1), MeshScheme::loop, Sdc::SCHEME_LOOP},
                          {"torus", torus(6, 5, true), MeshScheme::loop, Sdc::SCHEME_LOOP}};
  for (int k = 5; k <= 8; ++k) {
    cases.push_back(
        {"bipyramid", catmull_clark(bipyramid_of(k), 2), MeshScheme::catmull_clark, Sdc::SCHEME_CATMARK});
    cases.push_back({"bipyramid", loop(bipyramid_of(k), 1), MeshScheme::loop, Sdc::SCHEME_LOOP});
  }
  for (const auto& c : cases) {
    INFO(c.name << ", " << scheme_name(c.scheme));
    const bool triangles = c.scheme == MeshScheme::loop;
    std::vector<FacePoint> points;
    for (int f = 0; f < static_cast<int>(face_count(c.mesh)); ++f)
      for (const auto [u, v] : {std::array{0.0, 0.0}, std::array{0.013, 0.021}, std::array{0.3, 0.1},
                                std::array{0.12, 0.55}, std::array{0.5, 0.5}, std::array{0.7, 0.2}})
        points.push_back({.face = f, .u = u, .v = triangles && u + v > 1 ? 1 - u : v});
    const SurfaceSample ours = evaluate_limit_surface(c.mesh, c.scheme, points);
    const auto refiner = osd_refiner(c.mesh, c.type, 0);
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(10);
    const Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    Bfr::Surface<double> surface;
    std::vector<double> patch;
    const Bfr::Surface<double>::PointDescriptor desc(3);
    const double scale = c.mesh.vertices.cwiseAbs().maxCoeff();
    double position = 0, partials = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const FacePoint& q = points[i];
      REQUIRE(factory.InitVertexSurface(q.face, &surface));
      patch.resize(static_cast<std::size_t>(surface.GetNumPatchPoints()) * 3);
      surface.PreparePatchPoints(c.mesh.vertices.data(), desc, patch.data(), desc);
      const double uv[2] = {q.u, q.v};
      std::array<double, 3> p{}, du{}, dv{};
      surface.Evaluate(uv, patch.data(), desc, p.data(), du.data(), dv.data());
      const auto r = static_cast<Eigen::Index>(i);
      const Eigen::RowVector3d P(p[0], p[1], p[2]), Du(du[0], du[1], du[2]), Dv(dv[0], dv[1], dv[2]);
      position = std::max(position, (ours.positions.row(r) - P).norm());
      if (q.u == 0 && q.v == 0) continue;  // no partials at a corner that may be extraordinary
      partials = std::max({partials, (ours.du.row(r) - Du).norm(), (ours.dv.row(r) - Dv).norm()});
    }
    CHECK(position <= 1e-12 * scale);
    CHECK(partials <= 1e-11 * scale);
  }
}
