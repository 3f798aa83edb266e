// SPDX-License-Identifier: MIT
// Limit positions and normals from the left eigenvectors of S_n, checked against routes that do
// not use them: Cox–de Boor (value and normal of the bicubic surface), the refinement itself (a
// limit functional gives the same value at every level; vertices converge to it), geometry
// (outward normals of convex shapes). OpenSubdiv's Limit in test_mesh_oracles.cpp.
#include "cifs/subdivision/limit.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "subdivision/meshes.hpp"

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
      const LimitFrame f = evaluate_limit(limit_stencils(r.levels[static_cast<std::size_t>(level)], c.scheme),
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
        evaluate_limit(limit_stencils(r.levels[static_cast<std::size_t>(c.first_level)], c.scheme), x, false)
            .positions;
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

TEST_CASE("regular Catmull–Clark limit points and normals are the bicubic surface's",
          "[subdivision][limit]") {
  // As in test_mesh.cpp: the open grid is a uniform bicubic B-spline; level-2 vertices away from the
  // boundary have their limit at the dyadic parameter that the refinement of (i + 2, j + 2) gives.
  const int n = 10, m = 9, levels = 2;
  Mesh params = quad_grid(n, m), shape = params;
  Points grid((n + 1) * (m + 1), 3);
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i) {
      const auto r = static_cast<Eigen::Index>(j * (n + 1) + i);
      params.vertices.row(r) << i + 2.0, j + 2.0, 0.0;
      shape.vertices.row(r) << i + 0.3 * std::sin(1.7 * j), j + 0.2 * std::cos(0.9 * i + j),
          std::sin(1.3 * i) * std::cos(0.7 * j) + 0.1 * i * j;
      grid.row(static_cast<Eigen::Index>(i * (m + 1) + j)) = shape.vertices.row(r);
    }
  nurbs::Knots ku(static_cast<std::size_t>(n + 5)), kv(static_cast<std::size_t>(m + 5));
  for (std::size_t k = 0; k < ku.size(); ++k) ku[k] = static_cast<double>(k);
  for (std::size_t k = 0; k < kv.size(); ++k) kv[k] = static_cast<double>(k);
  const nurbs::Surface surface = nurbs::make_surface({3, 3}, {ku, kv}, {n + 1, m + 1}, grid);
  const MeshRefinement r = refine_topology(shape, MeshScheme::catmull_clark, levels);
  const LimitStencils st = limit_stencils(r.levels.back(), MeshScheme::catmull_clark);
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
  CHECK_THROWS_WITH(limit_stencils(build_topology(cube()), MeshScheme::doo_sabin),
                    Contains("doo-sabin: limit points belong to faces"));
  CHECK_THROWS_WITH(limit_stencils(build_topology(pyramid()), MeshScheme::catmull_clark),
                    Contains("catmull-clark: vertex 0 (valence 3) touches a face that is not a quad"));
  // Butterfly interpolates: every vertex is its own limit; its tangents are not built.
  const Mesh b = limit_mesh(bipyramid(), MeshScheme::butterfly, 2);
  CHECK(b.vertices == butterfly(bipyramid(), 2).vertices);
  CHECK_THROWS_WITH(limit_mesh(bipyramid(), MeshScheme::butterfly, 1, {.normals = true}),
                    Contains("butterfly: limit normals are not built"));
  CHECK_THROWS_WITH(limit_stencils(build_topology(fan(17)), MeshScheme::loop),
                    Contains("loop: vertex 0 (valence 17): loop: valence 17 is out of range"));
  CHECK_THROWS_WITH(limit_stencils(build_topology(fan(5)), MeshScheme::sqrt3),
                    Contains("is on the boundary"));
  CHECK_THROWS_WITH(limit_mesh(quad_grid(3, 3), MeshScheme::catmull_clark, 1, {.normals = true}),
                    Contains("limit normals at boundary vertices are not built"));
  // Positions on the boundary: the cubic B-spline limit (1, 4, 1)/6 of the boundary polygon.
  const Mesh grid = quad_grid(4, 3);
  const Mesh limit = limit_mesh(grid, MeshScheme::catmull_clark, 0);
  for (const int v : {1, 2, 3}) {  // the bottom row's inner vertices
    const Eigen::RowVector3d expected =
        (grid.vertices.row(v - 1) + 4 * grid.vertices.row(v) + grid.vertices.row(v + 1)) / 6;
    CHECK((limit.vertices.row(v) - expected).norm() <= 1e-15 * expected.norm() + 1e-15);
  }
}
