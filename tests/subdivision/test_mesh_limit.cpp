// SPDX-License-Identifier: MIT
// Limit positions and normals from the left eigenvectors of S_n, checked against routes that do
// not use them: Cox–de Boor (value and normal of the bicubic surface), the refinement itself (a
// limit functional gives the same value at every level; vertices converge to it), geometry
// (outward normals of convex shapes). OpenSubdiv's Limit in test_mesh_oracles.cpp.
#include "cifs/subdivision/limit.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "subdivision/dyadic.hpp"
#include "subdivision/meshes.hpp"
#include "support/sanitized.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

Eigen::RowVector3d normal_at(const Points& u, const Points& v, Eigen::Index i) {
  const Eigen::Vector3d a = u.row(i).transpose(), b = v.row(i).transpose();
  const Eigen::Vector3d n = a.cross(b);
  return n.normalized().transpose();
}

/// A closed mesh with extraordinary vertices for each primal scheme, refined once where the
/// stencils need it (Catmull–Clark: quads; Butterfly: regular neighbours).
struct Case {
  const char* name;
  MeshScheme scheme;
  Mesh mesh;
  int first_level;
};

std::vector<Case> cases() {
  return {{"catmull-clark cube (valence 3)", MeshScheme::catmull_clark, cube(), 0},
          {"catmull-clark bipyramid (valences 5, 4, 3)", MeshScheme::catmull_clark, bipyramid(), 1},
          {"loop bipyramid (valences 5, 4)", MeshScheme::loop, bipyramid(), 0},
          {"loop tetrahedron (valence 3)", MeshScheme::loop, tetrahedron(), 0},
          {"sqrt3 bipyramid", MeshScheme::sqrt3, bipyramid(), 0}};
}

}  // namespace

TEST_CASE("limit stencils: the same limit position and normal at every level", "[subdivision][limit]") {
  for (const Case& c : cases()) {
    INFO(c.name);
    // Levels first_level … first_level + 3 (√3: even steps apart, its stencils span two steps).
    const int span = c.scheme == MeshScheme::sqrt3 ? 2 : 1;
    const MeshRefinement r = refine_topology(c.mesh, c.scheme, c.first_level + 3 * span);
    std::vector<Points> data{c.mesh.vertices};
    for (const Stencils& s : r.steps) data.push_back(apply(s, data.back()));
    const auto at_level = [&](int level) {
      const LimitFrame f = evaluate_limit(limit_stencils(refine_topology(c.mesh, c.scheme, level)),
                                          data[static_cast<std::size_t>(level)]);
      return std::array<Points, 3>{f.positions, f.tangent_u, f.tangent_v};
    };
    const auto base = at_level(c.first_level);
    const double scale = c.mesh.vertices.cwiseAbs().maxCoeff();
    for (int k = 1; k <= 3; ++k) {
      const auto finer = at_level(c.first_level + k * span);
      // Vertex points keep their index: the old vertices are the first rows.
      for (Eigen::Index v = 0; v < base[0].rows(); ++v) {
        CHECK((finer[0].row(v) - base[0].row(v)).norm() <= 1e-13 * scale);
        CHECK((normal_at(finer[1], finer[2], v) - normal_at(base[1], base[2], v)).norm() <= 1e-12);
      }
    }
  }
}

TEST_CASE("limit stencils: vertices converge to their limit positions geometrically",
          "[subdivision][limit]") {
  for (const Case& c : cases()) {
    INFO(c.name);
    const int steps = 7;
    const MeshRefinement r = refine_topology(c.mesh, c.scheme, c.first_level + steps);
    Points x = c.mesh.vertices;
    for (int l = 0; l < c.first_level; ++l) x = apply(r.steps[static_cast<std::size_t>(l)], x);
    const Points limit =
        evaluate_limit(limit_stencils(refine_topology(c.mesh, c.scheme, c.first_level)), x, false).positions;
    std::vector<double> error;
    for (int l = c.first_level; l <= c.first_level + steps; ++l) {
      if (l > c.first_level) x = apply(r.steps[static_cast<std::size_t>(l - 1)], x);
      error.push_back((x.topRows(limit.rows()) - limit).rowwise().norm().maxCoeff());
    }
    // Each step shrinks the distance at least by the largest subdominant eigenvalue of the
    // valences present (< 0.62 up to valence 8 for every scheme), once past the first steps.
    for (std::size_t k = 3; k < error.size(); ++k) CHECK(error[k] <= 0.62 * error[k - 1] + 1e-15);
    CHECK(error.back() <= 0.05 * error.front());
  }
}

TEST_CASE("limit stencils next to a valence-2 vertex: its two faces share a far corner",
          "[subdivision][limit]") {
  // OpenSubdiv's catmark_val2_interior: vertex 16 has valence 2, its faces (12, 13, 14, 16) and
  // (12, 16, 14, 15) share the corner 14 across from 12 and 12 across from 14 — one vertex twice in
  // their rings, a ring that grows when refined (it was refused: "a stationary ring changed size").
  // The limit computed at level 0 equals the one at levels 1 and 2, and the refined vertices converge
  // to it.
  const Mesh m = make_mesh({{-1.75, 0, 0.75},
                            {-1.42, 0, 0.75},
                            {-1.08, 0, 0.75},
                            {-0.75, 0, 0.75},
                            {-0.75, 0, 1.08},
                            {-0.75, 0, 1.42},
                            {-0.75, 0, 1.75},
                            {-1.08, 0, 1.75},
                            {-1.42, 0, 1.75},
                            {-1.75, 0, 1.75},
                            {-1.75, 0, 1.42},
                            {-1.75, 0, 1.08},
                            {-1.42, 0, 1.08},
                            {-1.08, 0, 1.08},
                            {-1.08, 0, 1.42},
                            {-1.42, 0, 1.42},
                            {-1.25, -0.5, 1.25}},
                           {{0, 1, 12, 11},
                            {1, 2, 13, 12},
                            {2, 3, 4, 13},
                            {13, 4, 5, 14},
                            {14, 5, 6, 7},
                            {15, 14, 7, 8},
                            {10, 15, 8, 9},
                            {11, 12, 15, 10},
                            {12, 13, 14, 16},
                            {12, 16, 14, 15}});
  for (const MeshScheme scheme : {MeshScheme::catmull_clark}) {
    const Mesh l0 = limit_mesh(m, scheme, 0);
    for (const int levels : {1, 2}) {
      const Mesh l = limit_mesh(m, scheme, levels);
      CHECK((l.vertices.topRows(l0.vertices.rows()) - l0.vertices).cwiseAbs().maxCoeff() <= 1e-13);
    }
    const Mesh deep = subdivide(m, scheme, 10);
    CHECK((deep.vertices.topRows(l0.vertices.rows()) - l0.vertices).cwiseAbs().maxCoeff() <= 1e-5);
  }
}

TEST_CASE("limit normals point out of convex closed shapes", "[subdivision][limit]") {
  for (const Case& c : cases()) {
    INFO(c.name);
    const Mesh m = limit_mesh(c.mesh, c.scheme, c.first_level + 1, {.normals = true});
    const Eigen::RowVector3d centre = m.vertices.colwise().mean();
    for (Eigen::Index v = 0; v < m.vertices.rows(); ++v) {
      CHECK(std::abs(m.normals.row(v).norm() - 1) < 1e-14);
      if (c.mesh.vertices.rows() != 8) CHECK(m.normals.row(v).dot(m.vertices.row(v) - centre) > 0);
    }
  }
}

TEST_CASE("limits near the largest doubles: normals from the scaled mesh, tangents refused, never inf",
          "[subdivision][limit]") {
  // Tangents are differences of up to the valence times the coordinates: at 2^1023 they overflow.
  // limit_mesh's normals do not depend on the scale (computed at a power of two below 1, exactly);
  // evaluate_limit's tangents cannot be returned and are refused, where they came back inf (issue 33).
  int refused = 0;
  for (const Case& c : cases()) {
    INFO(c.name);
    Mesh big = c.mesh;
    big.vertices *= std::ldexp(1.0, 1023);
    const Mesh unit = limit_mesh(c.mesh, c.scheme, c.first_level + 1, {.normals = true});
    const Mesh huge = limit_mesh(big, c.scheme, c.first_level + 1, {.normals = true});
    REQUIRE(huge.vertices.allFinite());
    REQUIRE(huge.normals.allFinite());
    CHECK(huge.normals == unit.normals);
    CHECK(huge.vertices == unit.vertices * std::ldexp(1.0, 1023));
    // Where a tangent leaves the range (Catmull–Clark's masks weigh more than Loop's and √3's), a refusal
    // naming it; elsewhere finite tangents.
    const MeshRefinement r = refine_topology(big, c.scheme, c.first_level + 1);
    try {
      const LimitFrame f = evaluate_limit(limit_stencils(r), apply(r, big.vertices));
      CHECK((f.positions.allFinite() && f.tangent_u.allFinite() && f.tangent_v.allFinite()));
    } catch (const InvalidInput& e) {
      CHECK_THAT(e.what(), Contains("limit: a tangent exceeds the range of doubles") &&
                               Contains("scale the mesh down"));
      ++refused;
    }
    CHECK(evaluate_limit(limit_stencils(r), apply(r, big.vertices), false).positions.allFinite());
  }
  CHECK(refused >= 2);  // the Catmull–Clark cases
}

TEST_CASE("regular Catmull–Clark limit points and normals are the bicubic surface's",
          "[subdivision][limit]") {
  // The open grid is a uniform bicubic B-spline (`bicubic_grid`); level-2 vertices away from the
  // boundary have their limit at the dyadic parameter that the refinement of (i + 2, j + 2) gives.
  const int n = 10, m = 9, levels = 2;
  const auto [shape, params, surface] = bicubic_grid(n, m);
  const MeshRefinement r = refine_topology(shape, MeshScheme::catmull_clark, levels);
  const LimitStencils st = limit_stencils(r);
  const Points uv = evaluate_limit(st, apply(r, params.vertices), false).positions;
  const LimitFrame f = evaluate_limit(st, apply(r, shape.vertices));
  const Points &p = f.positions, &tu = f.tangent_u, &tv = f.tangent_v;
  int checked = 0;
  for (Eigen::Index v = 0; v < p.rows(); ++v) {
    // Dyadic parameters, as the linear data's limit gives them up to round-off.
    const double s = std::round(4 * uv(v, 0)) / 4, t = std::round(4 * uv(v, 1)) / 4;
    if (s < 5 || s > n - 1 || t < 5 || t > m - 1) continue;
    REQUIRE(std::abs(s - uv(v, 0)) + std::abs(t - uv(v, 1)) < 1e-12);
    INFO("vertex " << v << " at (" << s << ", " << t << ")");
    const Point expected = nurbs::evaluate(surface, s, t);
    CHECK((p.row(v) - expected).norm() <= 1e-12 * expected.norm());
    CHECK((normal_at(tu, tv, v) - nurbs::normal(surface, s, t).transpose()).norm() <= 1e-12);
    ++checked;
  }
  CHECK(checked == (4 * (n - 6) + 1) * (4 * (m - 6) + 1));
}

TEST_CASE("limit stencils: what is not built is refused, naming the vertex", "[subdivision][limit]") {
  CHECK_THROWS_WITH(limit_stencils(refine_topology(cube(), MeshScheme::doo_sabin, 0)),
                    Contains("doo-sabin: limit points belong to faces"));
  // Butterfly interpolates: every vertex is its own limit (its normals: test_butterfly_limit.cpp).
  const Mesh b = limit_mesh(bipyramid(), MeshScheme::butterfly, 2);
  CHECK((b.vertices - butterfly(bipyramid(), 2).vertices).cwiseAbs().maxCoeff() <=
        1e-15);  // replay vs one-shot
  CHECK_THROWS_WITH(limit_stencils(refine_topology(fan(17), MeshScheme::sqrt3, 0)),
                    Contains("sqrt3: vertex 0 (valence 17): valence 17 is out of range"));
  // √3's boundary vertices of 6 faces and more have no plane their spectrum proves
  // (test_mesh_limit_classes.cpp); a fan of 6 faces around an open vertex has one.
  Mesh open_fan = fan(7);
  open_fan.face_offsets.resize(open_fan.face_offsets.size() - 4);  // drop the last sector's 4 faces
  open_fan.face_vertices.resize(static_cast<std::size_t>(open_fan.face_offsets.back()));
  CHECK_THROWS_WITH(limit_mesh(open_fan, MeshScheme::sqrt3, 0, {.normals = true}),
                    Contains("sqrt3: vertex 0 (valence 7) has no tangent plane") &&
                        Contains("no pair of real subdominant eigenvalues above the rest"));
  // Positions on the boundary: the cubic B-spline limit (1, 4, 1)/6 of the boundary polygon.
  const Mesh grid = quad_grid(4, 3);
  const Mesh limit = limit_mesh(grid, MeshScheme::catmull_clark, 0);
  for (const int v : {1, 2, 3}) {  // the bottom row's inner vertices
    const Eigen::RowVector3d expected =
        (grid.vertices.row(v - 1) + 4 * grid.vertices.row(v) + grid.vertices.row(v + 1)) / 6;
    CHECK((limit.vertices.row(v) - expected).norm() <= 1e-15 * expected.norm() + 1e-15);
  }
}

TEST_CASE("√3 on open meshes: a boundary vertex's limit is the boundary's cubic B-spline at every level",
          "[subdivision][limit]") {
  // Kobbelt's boundary rule (2000, §5) keeps the boundary on odd steps and trisects it on even ones with
  // the ternary cubic B-spline's masks: the boundary is that spline of the boundary polygon, and a boundary
  // vertex's limit is (a + 4v + b)/6. Routes: the limits of a level's vertices are the same at every later
  // level (vertices keep their index); the refined boundary vertices reach them by 1/9 every two steps
  // (the ternary cubic's third eigenvalue: the second, 1/3, is the tangent's, 0 at a symmetric vertex),
  // the interior ones too, by the valences' subdominant eigenvalues squared.
  for (const auto& [name, m] : std::vector<std::pair<const char*, Mesh>>{
           {"fan of 5 (boundary valences 3 and 4)", fan(5)}, {"triangulated grid", quad_grid(4, 3, true)}}) {
    INFO(name);
    const MeshTopology t = build_topology(m, name);
    const MeshRefinement r = refine_topology(m, MeshScheme::sqrt3, 8);
    std::vector<Points> data{m.vertices};
    for (const Stencils& step : r.steps) data.push_back(apply(step, data.back()));
    const Points limit = limit_mesh(m, MeshScheme::sqrt3, 0).vertices;
    const double scale = m.vertices.cwiseAbs().maxCoeff();
    int boundary = 0;
    for (int v = 0; v < t.vertex_count; ++v) {
      if (t.boundary_vertex[static_cast<std::size_t>(v)] == 0) continue;
      ++boundary;
      Eigen::RowVector3d expected = 4 * m.vertices.row(v);
      for (const int e : vertex_edges(t, static_cast<std::size_t>(v)))
        if (t.edge_faces[static_cast<std::size_t>(e)][1] < 0)
          expected += m.vertices.row(other_vertex(t, static_cast<std::size_t>(e), v));
      CHECK((limit.row(v) - expected / 6).norm() <= 1e-15 * scale);
    }
    CHECK(boundary > 5);
    for (int level = 1; level <= 4; ++level) {
      INFO("level " << level);
      const LimitFrame later = evaluate_limit(limit_stencils(refine_topology(m, MeshScheme::sqrt3, level)),
                                              data[static_cast<std::size_t>(level)], false);
      CHECK((later.positions.topRows(limit.rows()) - limit).cwiseAbs().maxCoeff() <= 1e-13 * scale);
    }
    std::vector<double> on_boundary, inside;
    for (std::size_t level = 0; level < data.size(); level += 2) {
      double b = 0, i = 0;
      for (int v = 0; v < t.vertex_count; ++v) {
        double& worst = t.boundary_vertex[static_cast<std::size_t>(v)] != 0 ? b : i;
        worst = std::max(worst, (data[level].row(v) - limit.row(v)).norm());
      }
      on_boundary.push_back(b);
      inside.push_back(i);
    }
    for (std::size_t k = 1; k + 1 < on_boundary.size(); ++k) {
      INFO("levels " << 2 * k << " and " << 2 * k + 2 << ": " << on_boundary[k] << ", "
                     << on_boundary[k + 1]);
      CHECK(std::abs(on_boundary[k] / on_boundary[k + 1] - 9) < 0.2);
      CHECK(inside[k + 1] <= 0.25 * inside[k]);  // (4 − cos 2π/n)²/81 ≤ 0.21 up to valence 16
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Catmull–Clark at any (face, u, v).

TEST_CASE("Catmull–Clark at (face, u, v): extraordinary patches equal the limits of refined vertices",
          "[subdivision][limit]") {
  // Each face of these refined meshes has at most one extraordinary corner (the cube's valence 3;
  // the bipyramid's 5, 4 and its faces' 3, refined twice as one level of triangles leaves quads with
  // two; the torus none). At the dyadic points (i, j)/8 of every face the surface is the limit of
  // the vertex three levels down there: limit_stencils on the refined mesh, another route.
  const std::vector<Mesh> meshes{catmull_clark(cube(), 1), catmull_clark(bipyramid(), 2),
                                 catmull_clark(torus(6, 5), 1)};
  for (const Mesh& m : meshes) {
    const int levels = 3, N = 1 << levels;
    const MeshRefinement r = refine_topology(m, MeshScheme::catmull_clark, levels);
    const LimitFrame limit = evaluate_limit(limit_stencils(r), apply(r, m.vertices));
    std::vector<FacePoint> points;
    std::vector<int> expected;
    for (int f = 0; f < static_cast<int>(face_count(m)); ++f) {
      const std::vector<int> ids = dyadic_vertices(r, f, levels);
      for (int i = 0; i <= N; ++i)
        for (int j = 0; j <= N; ++j) {
          points.push_back({.face = f, .u = static_cast<double>(i) / N, .v = static_cast<double>(j) / N});
          expected.push_back(ids[static_cast<std::size_t>(i * (N + 1) + j)]);
        }
    }
    const SurfaceSample got = evaluate_limit_surface(m, MeshScheme::catmull_clark, points);
    const double scale = m.vertices.cwiseAbs().maxCoeff();
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto p = static_cast<Eigen::Index>(k), v = static_cast<Eigen::Index>(expected[k]);
      INFO("face " << points[k].face << " at (" << points[k].u << ", " << points[k].v << ")");
      CHECK((got.positions.row(p) - limit.positions.row(v)).norm() <= 1e-12 * scale);
      if (points[k].u == 0 && points[k].v == 0) continue;  // a corner may be extraordinary: no partials there
      if ((points[k].u == 0 || points[k].u == 1) && (points[k].v == 0 || points[k].v == 1)) continue;
      // The partials span the limit tangent plane: their normal is the vertex's limit normal.
      CHECK((normal_at(got.du, got.dv, p) - normal_at(limit.tangent_u, limit.tangent_v, v)).norm() <= 1e-10);
    }
  }
}

TEST_CASE("Catmull–Clark at (face, u, v): regular patches are the bicubic surface, partials included",
          "[subdivision][limit]") {
  const int n = 8, m = 7;
  const BicubicGrid g = bicubic_grid(n, m);
  const Mesh& shape = g.shape;
  const nurbs::Surface& surface = g.surface;
  // Face (i, j) of the grid is the parameter square [i + 2, i + 3] × [j + 2, j + 3]; the interior
  // faces have no boundary corner.
  std::vector<FacePoint> points;
  std::vector<std::array<double, 2>> params;
  for (int j = 1; j < m - 1; ++j)
    for (int i = 1; i < n - 1; ++i)
      for (const auto [u, v] :
           {std::array{0.0, 0.0}, std::array{0.3, 0.7}, std::array{1.0, 0.45}, std::array{0.9, 0.1}}) {
        points.push_back({.face = j * n + i, .u = u, .v = v});
        params.push_back({i + 2 + u, j + 2 + v});
      }
  const SurfaceSample got = evaluate_limit_surface(shape, MeshScheme::catmull_clark, points);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto p = static_cast<Eigen::Index>(k);
    // Rows k·2 + l: S, S_v, S_u, S_uv.
    const Points d = nurbs::derivatives(surface, params[k][0], params[k][1], 1);
    INFO("face " << points[k].face << " at (" << points[k].u << ", " << points[k].v << ")");
    CHECK((got.positions.row(p) - d.row(0)).norm() <= 1e-12 * d.row(0).norm());
    CHECK((got.du.row(p) - d.row(2)).norm() <= 1e-12 * d.row(2).norm());
    CHECK((got.dv.row(p) - d.row(1)).norm() <= 1e-12 * d.row(1).norm());
  }
}

namespace {

/// The uniform cubic B-spline patch of a 4 × 4 net ([a][b], a along u) on its middle cell: value and
/// both partials (Cox–de Boor's segment polynomials written out).
std::array<Eigen::RowVector3d, 3> bspline_patch(const std::array<std::array<Eigen::RowVector3d, 4>, 4>& net,
                                                double u, double v) {
  const auto basis = [](double t) {
    const double s = 1 - t;
    return std::pair{
        std::array{s * s * s / 6, (3 * t * t * t - 6 * t * t + 4) / 6,
                   (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6, t * t * t / 6},
        std::array{-s * s / 2, (3 * t * t - 4 * t) / 2, (-3 * t * t + 2 * t + 1) / 2, t * t / 2}};
  };
  const auto [bu, du] = basis(u);
  const auto [bv, dv] = basis(v);
  std::array<Eigen::RowVector3d, 3> out{Eigen::RowVector3d::Zero(), Eigen::RowVector3d::Zero(),
                                        Eigen::RowVector3d::Zero()};
  for (std::size_t a = 0; a < 4; ++a)
    for (std::size_t b = 0; b < 4; ++b) {
      out[0] += bu[a] * bv[b] * net[a][b];
      out[1] += du[a] * bv[b] * net[a][b];
      out[2] += bu[a] * dv[b] * net[a][b];
    }
  return out;
}

}  // namespace

TEST_CASE(
    "Catmull–Clark at (face, u, v): boundary, crease and corner patches are B-splines with phantom points",
    "[subdivision][limit]") {
  // On an open grid (boundary rule edge_and_corner) with an infinitely sharp crease across it, the
  // patch of a face whose corners are regular except on a boundary or the crease is the bicubic
  // B-spline of its 4 × 4 net with the missing row reflected, P(x, −1) = 2 P(x, 0) − P(x, 1) (both
  // sides at a corner: 4 P00 − 2 P10 − 2 P01 + P11) — the rules of the boundary curve (1, 6, 1)/8 and
  // (1, 1)/2 are those of the reflected B-spline. Value and partials to 1e-12.
  const int n = 7, m = 6, c = 3;  // the crease runs along the grid line j = c
  Mesh g = quad_grid(n, m);
  g.tags.boundary = BoundaryRule::edge_and_corner;
  const auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int i = 0; i < n; ++i) g.tags.creases.push_back({id(i, c), id(i + 1, c), 10});
  const auto P = [&](int i, int j) -> Eigen::RowVector3d { return g.vertices.row(id(i, j)); };
  // The net point (i, j) of the side of the crease that holds row `side` (j ≤ c or j ≥ c), reflected
  // across the grid's border and the crease.
  const auto net_point = [&](int i, int j, int lo, int hi) -> Eigen::RowVector3d {
    const auto column = [&](int x) -> Eigen::RowVector3d {
      if (j < lo) return 2 * P(x, lo) - P(x, lo + 1);
      if (j > hi) return 2 * P(x, hi) - P(x, hi - 1);
      return P(x, j);
    };
    if (i < 0) return 2 * column(0) - column(1);
    if (i > n) return 2 * column(n) - column(n - 1);
    return column(i);
  };
  std::vector<FacePoint> points;
  std::vector<std::array<Eigen::RowVector3d, 3>> expected;
  for (int j0 = 0; j0 < m; ++j0)
    for (int i0 = 0; i0 < n; ++i0) {
      const int lo = j0 < c ? 0 : c, hi = j0 < c ? c : m;  // the face's side of the crease
      std::array<std::array<Eigen::RowVector3d, 4>, 4> net;
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          net[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] =
              net_point(i0 - 1 + a, j0 - 1 + b, lo, hi);
      for (const auto [u, v] : {std::array{0.0, 0.0}, std::array{0.3, 0.7}, std::array{1.0, 0.45},
                                std::array{0.9, 0.1}, std::array{0.5, 0.0}}) {
        points.push_back({.face = j0 * n + i0, .u = u, .v = v});
        expected.push_back(bspline_patch(net, u, v));
      }
    }
  const SurfaceSample got = evaluate_limit_surface(g, MeshScheme::catmull_clark, points);
  const double scale = g.vertices.cwiseAbs().maxCoeff();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto p = static_cast<Eigen::Index>(k);
    INFO("face " << points[k].face << " at (" << points[k].u << ", " << points[k].v << ")");
    CHECK((got.positions.row(p) - expected[k][0]).norm() <= 1e-12 * scale);
    CHECK((got.du.row(p) - expected[k][1]).norm() <= 1e-12 * scale);
    CHECK((got.dv.row(p) - expected[k][2]).norm() <= 1e-12 * scale);
  }
}

TEST_CASE("Catmull–Clark at (face, u, v): points off the surface are refused, naming the point",
          "[subdivision][limit]") {
  const Mesh cube1 = catmull_clark(cube(), 1);
  const std::vector<FacePoint> outside{{.face = 0, .u = 1.5, .v = 0}};
  CHECK_THROWS_WITH(evaluate_limit_surface(cube1, MeshScheme::catmull_clark, outside),
                    Contains("point 0 (face 0): (u, v) = (1.5"));
  const std::vector<FacePoint> no_face{{.face = 99, .u = 0, .v = 0}};
  CHECK_THROWS_WITH(evaluate_limit_surface(cube1, MeshScheme::catmull_clark, no_face),
                    Contains("no such face; the mesh has 24"));
  // A hole has no surface; an n-gon's domain is OpenSubdiv's sub-faces, [i mod D, + ½] × [i div D, + ½].
  Mesh holed = quad_grid(3, 3);
  holed.tags.holes = {4};
  const std::vector<FacePoint> in_hole{{.face = 4, .u = 0.5, .v = 0.5}};
  CHECK_THROWS_WITH(evaluate_limit_surface(holed, MeshScheme::catmull_clark, in_hole),
                    Contains("point 0 (face 4): the face is a hole"));
  const std::vector<FacePoint> between{{.face = 1, .u = 0.75, .v = 0.25}};  // the triangle's sub-faces: 3
  CHECK_THROWS_WITH(evaluate_limit_surface(pyramid(), MeshScheme::catmull_clark, between),
                    Contains("(u, v) = (0.75, 0.25) is outside the 3-gon's sub-faces"));
  const std::vector<FacePoint> fourth{{.face = 1, .u = 1.25, .v = 1.25}};
  CHECK_THROWS_WITH(evaluate_limit_surface(pyramid(), MeshScheme::catmull_clark, fourth),
                    Contains("outside the 3-gon's sub-faces"));
  // The whole-surface automaton (attractor meshes, fractal surfaces) reads the tags: a tagged mesh is
  // not taken for a smooth one (its patches: test_surface_automaton_features.cpp).
  const Mesh smooth = catmull_clark(cube(), 1);
  Mesh creased = smooth;
  creased.tags.creases = {{0, 8, 10}};
  const Mesh plain = surface_automaton_mesh(surface_automaton(smooth, MeshScheme::catmull_clark), 2);
  const Mesh sharp = surface_automaton_mesh(surface_automaton(creased, MeshScheme::catmull_clark), 2);
  REQUIRE(plain.vertices.rows() == sharp.vertices.rows());
  CHECK((plain.vertices - sharp.vertices).cwiseAbs().maxCoeff() >= 1e-2);
}

namespace {

/// Closed quad meshes whose faces have at most one extraordinary corner: valences 3 (cube), 3 and 4
/// (pyramid), 3, 4 and 5 (bipyramid), with regular faces besides.
/// Each face's corner list is turned by f mod 4 places, so that the patches' (s, t) meet the
/// faces' (u, v) in all four ways.
std::vector<std::pair<const char*, Mesh>> automaton_meshes() {
  return {{"cube", turned_faces(catmull_clark(cube(), 1))},
          {"pyramid", turned_faces(catmull_clark(pyramid(), 2))},
          {"bipyramid", turned_faces(catmull_clark(bipyramid(), 2))}};
}

/// Index of the row of `P` nearest to `x`, and its distance.
std::pair<Eigen::Index, double> nearest(const Points& P, const Eigen::RowVectorXd& x) {
  Eigen::Index best = 0;
  const double d = (P.rowwise() - x).rowwise().squaredNorm().minCoeff(&best);
  return {best, std::sqrt(d)};
}

}  // namespace

TEST_CASE("the surface automaton's attractor is the limit surface: every node a refined vertex's limit",
          "[subdivision][limit]") {
  // Independent route: the limit stencils (left eigenvectors of S_n) on the mesh refined `depth`
  // times more. The welded attractor mesh has exactly the refined mesh's vertices and faces, and each
  // of its nodes is one of those limit points.
  const int depth = 3;
  for (const auto& [name, m] : automaton_meshes()) {
    INFO(name);
    const SurfaceAutomaton s = surface_automaton(m, MeshScheme::catmull_clark);
    const Mesh attractor = surface_automaton_mesh(s, depth);
    const Mesh limit = limit_mesh(m, MeshScheme::catmull_clark, depth);
    REQUIRE(attractor.vertices.rows() == limit.vertices.rows());
    REQUIRE(face_count(attractor) == face_count(limit));
    CHECK(euler_characteristic(build_topology(attractor)) == euler_characteristic(build_topology(m)));
    const double scale = limit.vertices.cwiseAbs().maxCoeff();
    std::vector<bool> hit(static_cast<std::size_t>(limit.vertices.rows()), false);
    double worst = 0;
    for (Eigen::Index v = 0; v < attractor.vertices.rows(); ++v) {
      const auto [k, d] = nearest(limit.vertices, attractor.vertices.row(v));
      worst = std::max(worst, d);
      hit[static_cast<std::size_t>(k)] = true;
    }
    CHECK(worst <= 1e-12 * scale);
    CHECK(std::all_of(hit.begin(), hit.end(), [](bool b) { return b; }));
  }
}

TEST_CASE("the chaos game on the surface automaton lands on the limit surface at its addresses",
          "[subdivision][limit]") {
  // A chaos point is the corner (0, 0) of the node it stands on; its recorded address holds the face
  // (integer part) and the base-4 digits 2·iu + iv of the quarters, i.e. the dyadic (s, t) of that
  // corner. evaluate_limit_surface there, through the face's (u, v), must give the same point.
  for (const auto& [name, m] : automaton_meshes()) {
    INFO(name);
    const SurfaceAutomaton s = surface_automaton(m, MeshScheme::catmull_clark);
    // Restarts by 2^-18: at most 18 digits (36 bits) below the face number, exact in a double.
    const ifs::ChaosResult chaos = ifs::chaos_game(
        s.automaton, s.nets, {.samples = 3000, .seed = 7, .restart_diameter = 1e-5, .record_address = true});
    const MeshTopology t = build_topology(m);
    std::vector<FacePoint> at;
    for (const double address : chaos.address) at.push_back(address_point(s, t, address));
    const SurfaceSample expected = evaluate_limit_surface(m, MeshScheme::catmull_clark, at);
    const double scale = m.vertices.cwiseAbs().maxCoeff();
    for (Eigen::Index p = 0; p < chaos.points.rows(); ++p) {
      INFO("sample " << p << ", face " << at[static_cast<std::size_t>(p)].face);
      CHECK((chaos.points.row(p) - expected.positions.row(p)).norm() <= 1e-12 * scale);
    }
  }
}

TEST_CASE("fractal Catmull–Clark: faces keep the smooth surface's boundary curves, the inside moves",
          "[subdivision][limit]") {
  const Mesh m = catmull_clark(bipyramid(), 2);
  const SurfaceAutomaton smooth = surface_automaton(m, MeshScheme::catmull_clark);
  const int depth = 4, side = 1 << depth, row = side + 1;
  const Mesh flat = ifs::patch_meshes(smooth.automaton, smooth.nets, depth);
  // No perturbation: the BC-IFS's bicubic cells are the B-spline's, the same surface.
  ifs::PerturbOptions perturb;
  perturb.amplitude = 0;
  const FractalSurface same = fractal_surface(smooth, perturb);
  const Mesh same_mesh = ifs::patch_meshes(same.surface.automaton, same.surface.nets, depth);
  const double scale = flat.vertices.cwiseAbs().maxCoeff();
  CHECK((same_mesh.vertices - flat.vertices).cwiseAbs().maxCoeff() <= 1e-13 * scale);

  perturb.amplitude = 0.3;
  perturb.seed = 5;
  const FractalSurface rough = fractal_surface(smooth, perturb);
  CHECK(rough.perturbation.residual <= 1e-12);
  CHECK(!rough.perturbation.values.empty());
  const Mesh fractal = ifs::patch_meshes(rough.surface.automaton, rough.surface.nets, depth);
  // Per face block: the border nodes (the face's boundary curves) are the smooth surface's; inside,
  // the surface moved.
  double border = 0, inside = 0;
  for (Eigen::Index v = 0; v < fractal.vertices.rows(); ++v) {
    const auto I = static_cast<int>(v % (row * row)) / row, J = static_cast<int>(v % (row * row)) % row;
    const double d = (fractal.vertices.row(v) - flat.vertices.row(v)).norm();
    if (I == 0 || J == 0 || I == side || J == side)
      border = std::max(border, d);
    else
      inside = std::max(inside, d);
  }
  CHECK(border <= 1e-12 * scale);
  CHECK(inside >= 1e-3 * scale);
  // Welded by the topology, the fractal surface is closed like the mesh.
  const Mesh welded = surface_automaton_mesh(rough.surface, depth);
  CHECK(euler_characteristic(build_topology(welded)) == euler_characteristic(build_topology(m)));
}

// ------------------------------------------------------------------------------------------------
// Loop at any (face, u, v), and its surface automaton.

namespace {

/// Closed triangle meshes whose faces have at most one extraordinary corner, valences 3 … 8 and
/// regular faces; each face's corner list turned by f mod 3 places, so that the patches' (s, t)
/// meet the faces' (u, v) in all three ways.
std::vector<std::pair<const char*, Mesh>> loop_meshes() {
  return {{"tetrahedron (3)", turned_faces(loop(tetrahedron(), 1), 3)},
          {"octahedron (4)", turned_faces(loop(octahedron(), 1), 3)},
          {"bipyramid (4, 5)", turned_faces(loop(bipyramid(), 1), 3)},
          {"bipyramid (4, 7)", turned_faces(loop(bipyramid_of(7), 1), 3)},
          {"bipyramid (4, 8)", turned_faces(loop(bipyramid_of(8), 1), 3)},
          {"torus (6)", turned_faces(torus(6, 5, true), 3)}};
}

}  // namespace

TEST_CASE("Loop at (face, u, v): every patch equals the limits of refined vertices, normals included",
          "[subdivision][limit]") {
  // At the points (i, j)/2^7 of a face the surface is the limit of the vertex seven levels down
  // there: limit_stencils on the refined mesh, another route. Checked on the grid (i, j)/8 of every
  // face (45 points on a quartic patch determine it) and at every point within 4/2^7 of a corner,
  // where extraordinary patches go 5 to 7 levels down their corner chain.
  const auto meshes = loop_meshes();
  for (std::size_t index = 0; index < meshes.size(); ++index) {
    if (cifs_test::skipped_when_sanitized(index, 2)) continue;
    const auto& [name, m] = meshes[index];
    INFO(name);
    const int levels = 7, N = 1 << levels;
    const MeshRefinement r = refine_topology(m, MeshScheme::loop, levels);
    const LimitFrame limit = evaluate_limit(limit_stencils(r), apply(r, m.vertices));
    std::vector<FacePoint> points;
    std::vector<int> expected;
    for (int f = 0; f < static_cast<int>(face_count(m)); ++f) {
      const std::vector<int> ids = dyadic_triangle_vertices(r, f, levels);
      for (int i = 0; i <= N; ++i)
        for (int j = 0; i + j <= N; ++j) {
          const bool grid = i % (N / 8) == 0 && j % (N / 8) == 0;
          const bool corner = i + j <= 4 || N - i + j <= 4 || i + N - j <= 4;
          if (!grid && !corner) continue;
          points.push_back({.face = f, .u = static_cast<double>(i) / N, .v = static_cast<double>(j) / N});
          expected.push_back(ids[static_cast<std::size_t>(i * (N + 1) + j)]);
        }
    }
    const SurfaceSample got = evaluate_limit_surface(m, MeshScheme::loop, points);
    const double scale = m.vertices.cwiseAbs().maxCoeff();
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto p = static_cast<Eigen::Index>(k), v = static_cast<Eigen::Index>(expected[k]);
      INFO("face " << points[k].face << " at (" << points[k].u << ", " << points[k].v << ")");
      CHECK((got.positions.row(p) - limit.positions.row(v)).norm() <= 1e-12 * scale);
      const int corner_index = points[k].u == 0 && points[k].v == 0 ? 0
                               : points[k].u == 1                   ? 1
                               : points[k].v == 1                   ? 2
                                                                    : -1;
      if (corner_index >= 0) continue;  // a corner may be extraordinary: no partials there
      CHECK((normal_at(got.du, got.dv, p) - normal_at(limit.tangent_u, limit.tangent_v, v)).norm() <= 1e-10);
    }
  }
}

TEST_CASE("Loop at (face, u, v): the partials are the derivatives of the positions", "[subdivision][limit]") {
  // Central differences of the evaluated positions, at points off the dyadic grid and off the
  // extraordinary corners (the patch is smooth there): agreement to the differences' own error.
  for (const auto& [name, m] : loop_meshes()) {
    INFO(name);
    std::vector<FacePoint> points;
    const double h = 1e-5;
    for (int f = 0; f < static_cast<int>(face_count(m)); f += 3)
      for (const auto [u, v] : {std::array{0.21, 0.13}, std::array{0.6, 0.3}, std::array{0.05, 0.8},
                                std::array{0.33, 0.35}, std::array{0.02, 0.03}})
        for (const auto [du, dv] : {std::array{0.0, 0.0}, std::array{h, 0.0}, std::array{-h, 0.0},
                                    std::array{0.0, h}, std::array{0.0, -h}})
          points.push_back({.face = f, .u = u + du, .v = v + dv});
    const SurfaceSample s = evaluate_limit_surface(m, MeshScheme::loop, points);
    for (Eigen::Index p = 0; p < s.positions.rows(); p += 5) {
      INFO("face " << points[static_cast<std::size_t>(p)].face << " at ("
                   << points[static_cast<std::size_t>(p)].u << ", " << points[static_cast<std::size_t>(p)].v
                   << ")");
      const Eigen::RowVectorXd fu = (s.positions.row(p + 1) - s.positions.row(p + 2)) / (2 * h),
                               fv = (s.positions.row(p + 3) - s.positions.row(p + 4)) / (2 * h);
      CHECK((s.du.row(p) - fu).norm() <= 1e-6 * s.du.row(p).norm());
      CHECK((s.dv.row(p) - fv).norm() <= 1e-6 * s.dv.row(p).norm());
    }
  }
}

TEST_CASE("Loop at (face, u, v): points off the surface are refused, naming the point",
          "[subdivision][limit]") {
  const Mesh tet1 = loop(tetrahedron(), 1);
  const std::vector<FacePoint> outside{{.face = 2, .u = 0.6, .v = 0.6}};
  CHECK_THROWS_WITH(evaluate_limit_surface(tet1, MeshScheme::loop, outside),
                    Contains("point 0 (face 2): (u, v) = (0.6") && Contains("outside the triangle"));
  const std::vector<FacePoint> first{{.face = 0, .u = 0.25, .v = 0.25}};
  CHECK_THROWS_WITH(evaluate_limit_surface(cube(), MeshScheme::loop, first), Contains("runs on triangles"));
  Mesh holed = tet1;
  holed.tags.holes = {0};
  CHECK_THROWS_WITH(evaluate_limit_surface(holed, MeshScheme::loop, first), Contains("the face is a hole"));
  CHECK_THROWS_WITH(evaluate_limit_surface(tet1, MeshScheme::doo_sabin, first),
                    Contains("doo-sabin is not built"));
}

TEST_CASE("Loop's surface automaton: its attractor mesh is the limit surface, its chaos game lands on it",
          "[subdivision][limit]") {
  const int depth = 3;
  for (const auto& [name, m] : loop_meshes()) {
    INFO(name);
    const SurfaceAutomaton s = surface_automaton(m, MeshScheme::loop);
    // The welded attractor mesh has exactly the refined mesh's vertices and faces, each node one of
    // the limit points (limit stencils of the mesh refined `depth` times: another route).
    const Mesh attractor = surface_automaton_mesh(s, depth);
    const Mesh limit = limit_mesh(m, MeshScheme::loop, depth, {.normals = true});
    REQUIRE(attractor.vertices.rows() == limit.vertices.rows());
    REQUIRE(face_count(attractor) == face_count(limit));
    CHECK(euler_characteristic(build_topology(attractor)) == euler_characteristic(build_topology(m)));
    const double scale = limit.vertices.cwiseAbs().maxCoeff();
    std::vector<bool> hit(static_cast<std::size_t>(limit.vertices.rows()), false);
    std::vector<Eigen::Index> same(static_cast<std::size_t>(attractor.vertices.rows()));
    double worst = 0;
    for (Eigen::Index v = 0; v < attractor.vertices.rows(); ++v) {
      const auto [k, d] = nearest(limit.vertices, attractor.vertices.row(v));
      worst = std::max(worst, d);
      hit[static_cast<std::size_t>(k)] = true;
      same[static_cast<std::size_t>(v)] = k;
    }
    CHECK(worst <= 1e-12 * scale);
    CHECK(std::all_of(hit.begin(), hit.end(), [](bool b) { return b; }));
    // Orientation: the triangles turn as the mesh's faces — each one's normal points to the side of
    // the limit normal at its first corner.
    int flipped = 0;
    for (std::size_t f = 0; f < face_count(attractor); ++f) {
      const auto c = face(attractor, f);
      const Eigen::Vector3d A = attractor.vertices.row(c[0]).transpose(),
                            B = attractor.vertices.row(c[1]).transpose(),
                            C = attractor.vertices.row(c[2]).transpose();
      const Eigen::Vector3d n = limit.normals.row(same[static_cast<std::size_t>(c[0])]).transpose();
      if ((B - A).cross(C - A).dot(n) <= 0) ++flipped;
    }
    CHECK(flipped == 0);
    // A chaos point is corner (0, 0) of its node; the address's base-4 digits name the children
    // C0, C1, C2, M, which place that corner in the patch's (s, t).
    const ifs::ChaosResult chaos = ifs::chaos_game(
        s.automaton, s.nets, {.samples = 2000, .seed = 11, .restart_diameter = 1e-5, .record_address = true});
    const MeshTopology t = build_topology(m);
    std::vector<FacePoint> at;
    for (const double address : chaos.address) {
      const int f = static_cast<int>(std::floor(address));
      double rest = address - f, a = 0, b = 0, h = 1, sign = 1;
      for (int k = 0; k < 26 && rest > 0; ++k) {
        rest *= 4;
        const int digit = static_cast<int>(std::floor(rest));
        rest -= digit;
        h /= 2;
        if (digit == 1) a += sign * h;
        if (digit == 2) b += sign * h;
        if (digit == 3) a += sign * h, b += sign * h, sign = -sign;
      }
      REQUIRE(rest == 0);
      const auto corners = face(t, static_cast<std::size_t>(f));
      const auto turn = std::find(corners.begin(), corners.end(), s.corners[static_cast<std::size_t>(f)][0]) -
                        corners.begin();
      // (s, t) → the face's (u, v): corners[0] is face corner `turn`.
      const std::array<std::array<double, 2>, 3> uv{{{a, b}, {1 - a - b, a}, {b, 1 - a - b}}};
      at.push_back({.face = f,
                    .u = uv[static_cast<std::size_t>(turn)][0],
                    .v = uv[static_cast<std::size_t>(turn)][1]});
    }
    const SurfaceSample expected = evaluate_limit_surface(m, MeshScheme::loop, at);
    for (Eigen::Index p = 0; p < chaos.points.rows(); ++p) {
      INFO("sample " << p << ", face " << at[static_cast<std::size_t>(p)].face);
      CHECK((chaos.points.row(p) - expected.positions.row(p)).norm() <= 1e-12 * scale);
    }
  }
}

TEST_CASE("limit meshes carry UVs under the rule 'all', which are their own limit; other rules are refused",
          "[subdivision][limit][uv]") {
  Mesh m = torus(6, 5);
  std::mt19937 rng(5);
  m.face_varying = {random_seams(m, rng)};
  const Mesh limit = limit_mesh(m, MeshScheme::catmull_clark, 2),
             deep = subdivide(m, MeshScheme::catmull_clark, 4);
  REQUIRE(limit.face_varying.size() == 1);
  // Each level-2 vertex's values (a vertex point keeps its vertex's index): two levels more leave them.
  const auto values_at = [&](const Mesh& x) {
    std::vector<std::set<std::pair<double, double>>> out(static_cast<std::size_t>(limit.vertices.rows()));
    const FaceVaryingChannel& c = x.face_varying.at(0);
    for (std::size_t k = 0; k < x.face_vertices.size(); ++k)
      if (const auto v = static_cast<std::size_t>(x.face_vertices[k]); v < out.size())
        out[v].emplace(c.values(c.indices[k], 0), c.values(c.indices[k], 1));
    return out;
  };
  const auto at_limit = values_at(limit);
  CHECK(at_limit == values_at(deep));
  CHECK(std::any_of(at_limit.begin(), at_limit.end(), [](const auto& s) { return s.size() > 1; }));  // seams
  m.tags.face_varying = FaceVaryingRule::corners_only;
  CHECK_THROWS_WITH(
      limit_mesh(m, MeshScheme::catmull_clark, 2),
      Catch::Contains("the limit of face-varying channel 'uv' under the rule 'corners-only' is not built"));
}
