// SPDX-License-Identifier: MIT
// Local subdivision matrices at tagged vertices (darts, creases, corners) and boundary vertices of
// any number of faces: the rules equal the tagged production refinement, the spectra split into
// sectors, the closed forms of the regular crease (cubic B-spline curve) hold, and the C1 verdicts
// per sector find the failures the spectra predict (docs/subdivision-surfaces.md, "Tagged vertices").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "subdivision/meshes.hpp"
#include "subdivision/spectra.hpp"
#include "support/sanitized.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using Catch::Matchers::Contains;
using cifs_test::check_same_spectrum;

namespace mesh_classes_test {

using Complex = std::complex<long double>;

/// a without one copy of each value of b (each must be there).
std::vector<Complex> without(std::vector<Complex> a, const std::vector<Complex>& b) {
  for (const Complex& x : b) {
    auto best = std::min_element(a.begin(), a.end(), [&](const Complex& p, const Complex& q) {
      return std::abs(p - x) < std::abs(q - x);
    });
    REQUIRE(std::abs(*best - x) < 1e-13L);
    a.erase(best);
  }
  return a;
}

LocalOptions crease(int k, bool corner = false) {
  return LocalOptions{.sharp = {0, k}, .corner = corner};
}

LocalOptions boundary(bool corner = false) {
  return LocalOptions{.boundary = true, .corner = corner};
}

void same_matrix(MeshScheme scheme, int n, const LocalOptions& o) {
  const LocalMatrix a = local_matrix(scheme, n, o);
  const LocalMatrix b = refined_local_matrix(scheme, n, o);
  INFO(scheme_name(scheme) << " valence " << n << " " << vertex_class(n, o));
  REQUIRE(a.values.rows() == b.values.rows());
  REQUIRE(a.labels == b.labels);
  // Exact weights: the refinement's doubles are within a rounding per summed term.
  CHECK((a.values - b.values).cwiseAbs().maxCoeff() < 1e-15L);
  if (a.exact)
    for (Eigen::Index i = 0; i < a.values.rows(); ++i)
      for (Eigen::Index j = 0; j < a.values.cols(); ++j)
        if ((*a.exact)(static_cast<int>(i), static_cast<int>(j)) == 0) REQUIRE(b.values(i, j) == 0);
  // Rows sum to 1 (affine).
  for (Eigen::Index i = 0; i < a.values.rows(); ++i) CHECK(std::abs(a.values.row(i).sum() - 1) < 1e-15L);
}

}  // namespace mesh_classes_test

using namespace mesh_classes_test;

TEST_CASE("tagged local matrices: the rules equal the tagged refinement, every class",
          "[subdivision][mesh_analysis][classes]") {
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop}) {
    for (int n = kMinValence; n <= 12; ++n) same_matrix(scheme, n, {.sharp = {0}});  // darts
    for (int n = kMinValence; n <= 9; ++n)
      for (int k = 1; k < n; ++k) {
        same_matrix(scheme, n, crease(k));
        same_matrix(scheme, n, crease(k, true));
      }
    for (int n = kMinBoundaryValence; n <= 10; ++n) same_matrix(scheme, n, boundary(true));
    for (int n = 4; n <= 7; ++n)  // a sharp edge inside a boundary vertex's fan: a corner
      for (int j = 1; j <= n - 2; ++j) same_matrix(scheme, n, {.boundary = true, .sharp = {j}});
    same_matrix(scheme, 6, {.sharp = {0, 2, 4}});  // three sharp edges: a corner
  }
}

TEST_CASE("tagged local matrices: classes, sectors, exact weights and refusals",
          "[subdivision][mesh_analysis][classes]") {
  CHECK(vertex_class(5, {}) == "interior");
  CHECK(vertex_class(5, {.sharp = {0}}) == "dart");
  CHECK(vertex_class(5, crease(2)) == "crease");
  CHECK(vertex_class(5, crease(2, true)) == "corner");
  CHECK(vertex_class(6, {.sharp = {0, 2, 4}}) == "corner");
  CHECK(vertex_class(4, boundary()) == "boundary");
  CHECK(vertex_class(4, boundary(true)) == "corner");
  CHECK(vertex_class(2, {.boundary = true, .rule = BoundaryRule::edge_and_corner}) == "corner");
  CHECK(sector_sizes(7, crease(3)) == std::vector<int>{3, 4});
  CHECK(sector_sizes(6, {.sharp = {0, 2, 4}}) == std::vector<int>{2, 2, 2});
  CHECK(sector_sizes(5, {.boundary = true, .sharp = {1}}) == std::vector<int>{1, 3});
  CHECK(sector_sizes(5, {.sharp = {0}}) == std::vector<int>{5});
  // The crease rule's weights are rational: Loop's crease is exact at every valence.
  const LocalMatrix loop = local_matrix(MeshScheme::loop, 7, crease(3));
  REQUIRE(loop.exact);
  CHECK((*loop.exact)(0, 0) == Rational(3, 4));
  CHECK((*loop.exact)(0, 1) == Rational(1, 8));
  CHECK((*loop.exact)(0, 4) == Rational(1, 8));
  CHECK((*loop.exact)(1, 0) == Rational(1, 2));                          // a sharp edge's point: its midpoint
  CHECK_FALSE(local_matrix(MeshScheme::loop, 7, {.sharp = {0}}).exact);  // a dart keeps the smooth β(7)

  CHECK_THROWS_WITH(
      local_matrix(MeshScheme::butterfly, 6, crease(3)),
      Contains("butterfly: sharp edges and corners are analysed for catmull-clark and loop only"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::loop, 6, crease(6)),
                    Contains("loop: sharp edge 6 is out of place; expected increasing edge numbers 0 to 5"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::loop, 6, {.sharp = {3, 1}}),
                    Contains("sharp edge 1 is out of place"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::catmull_clark, 4, {.boundary = true, .sharp = {0}}),
                    Contains("the boundary edges are sharp anyway"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::loop, 6, {.sharp = {0, 3}, .concave = true}),
                    Contains("concave is said of a corner"));
}

TEST_CASE("tagged local matrices: a crease or corner is its sectors, each a boundary vertex",
          "[subdivision][mesh_analysis][classes]") {
  // The rows of a sector read only the sector and the crease: the spectrum is the union of the
  // sectors' (boundary vertices of k1 and k2 faces) less one copy of the shared crease block
  // (c and the two sharp edges' points: 1, ½, ¼ under the crease rule; 1, ½, ½ under the corner's).
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop})
    for (int n = kMinValence; n <= 9; ++n)
      for (int k = 1; k < n; ++k)
        for (const bool corner : {false, true}) {
          INFO(scheme_name(scheme) << " valence " << n << " crease " << k << (corner ? " corner" : ""));
          const LocalSpectrum whole = local_spectrum(local_matrix(scheme, n, crease(k, corner)));
          std::vector<Complex> sectors =
              local_spectrum(local_matrix(scheme, k + 1, boundary(corner))).eigenvalues;
          const std::vector<Complex> other =
              local_spectrum(local_matrix(scheme, n - k + 1, boundary(corner))).eigenvalues;
          sectors.insert(sectors.end(), other.begin(), other.end());
          check_same_spectrum(whole.eigenvalues, without(sectors, {1.0L, 0.5L, corner ? 0.5L : 0.25L}),
                              1e-13L);
        }
}

TEST_CASE("tagged local matrices: the regular crease is the cubic B-spline curve",
          "[subdivision][mesh_analysis][classes]") {
  // Catmull–Clark, valence 4, two faces a side. By hand: the crease block (c, r_0, r_2: (1, 6, 1)/8
  // and midpoints) has 1, ½, ¼; each side's inner rows (r_1 or r_3: ⅜ on itself, 1/16 on its two
  // face corners; f_j: ¼ r + ¼ f) have ¼ (f_0 − f_1) and the 2 × 2 block [⅜ ⅛; ¼ ¼]: ½ and ⅛.
  const LocalSpectrum cc = local_spectrum(local_matrix(MeshScheme::catmull_clark, 4, crease(2)));
  check_same_spectrum(cc.eigenvalues, {1, 0.5L, 0.5L, 0.5L, 0.25L, 0.25L, 0.25L, 0.125L, 0.125L}, 1e-14L);
  // Loop, valence 6, three faces a side: each side's two inner ring points (tridiagonal ⅜; ⅛)
  // give ⅜ ± ⅛.
  const LocalSpectrum loop = local_spectrum(local_matrix(MeshScheme::loop, 6, crease(3)));
  check_same_spectrum(loop.eigenvalues, {1, 0.5L, 0.5L, 0.5L, 0.25L, 0.25L, 0.25L}, 1e-14L);
  // The limit position: the curve's (1, 4, 1)/6 on c and the two crease neighbours, 0 elsewhere
  // (CC numbering c, r0, f0, r1, f1, r2, …; Loop c, r0, …).
  for (const auto& [s, ends] :
       {std::pair{cc, std::array<int, 2>{1, 5}}, std::pair{loop, std::array<int, 2>{1, 4}}}) {
    for (Eigen::Index i = 0; i < s.limit_stencil.size(); ++i) {
      const long double expected = i == 0 ? 4.0L / 6 : (i == ends[0] || i == ends[1]) ? 1.0L / 6 : 0;
      CHECK(std::abs(s.limit_stencil(i) - expected) < 1e-15L);
    }
  }
  // A corner is interpolated: its limit stencil is c alone.
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop})
    for (int k = 1; k <= 6; ++k) {
      const LocalSpectrum corner = local_spectrum(local_matrix(scheme, k + 1, boundary(true)));
      CHECK(std::abs(corner.limit_stencil(0) - 1) < 1e-15L);
      CHECK(corner.limit_stencil.tail(corner.limit_stencil.size() - 1).cwiseAbs().maxCoeff() < 1e-15L);
    }
}

TEST_CASE("C1 verdicts per sector: smooth boundaries fail where two inner eigenvalues pass 1/2",
          "[subdivision][mesh_analysis][classes][c1]") {
  // Loop's boundary vertex of k faces: its inner ring is tridiagonal (⅜; ⅛) with ends on the curve,
  // eigenvalues ⅜ + ¼cos(πm/k), m = 1 … k − 1 (by hand). The second passes the curve's ½ when
  // cos(2π/k) > ½, k ≥ 7: both leading eigenvectors then vanish on the boundary, which the
  // characteristic map sends to 0 — not C1. At k = 6 it equals ½: no gap, left undecided.
  for (int k = 1; k <= 9; ++k) {
    INFO("loop, boundary vertex of " << k << " faces");
    const LocalMatrix S = local_matrix(MeshScheme::loop, k + 1, boundary());
    const C1Verdict v = c1_verdict(S, local_spectrum(S));
    REQUIRE(v.sectors.size() == 1);
    const long double second = 0.375L + std::cos(2 * std::numbers::pi_v<long double> / k) / 4;
    if (k >= 2 && second > 0.5L + 1e-12L) {
      CHECK_FALSE(v.c1);
      CHECK(v.sectors[0].verdict.through_centre);
    } else if (k == 6) {
      CHECK_FALSE(v.c1);
      CHECK_FALSE(v.sectors[0].verdict.decided);
    } else {
      CHECK(v.c1);
      CHECK(v.method == "sampled");
      if (k >= 2) CHECK(std::abs(v.sectors[0].verdict.angle - std::numbers::pi_v<long double>) < 1e-9L);
    }
  }
  // √3 over two steps (Kobbelt's boundary: kept, then trisected): the curve's ⅓ (its tangent) and
  // 1/9 against the inside's (2 + 2cos(πm/k))/9, m = 1 … k − 1 (test_mesh_analysis.cpp). C1 at 1–5
  // faces: k = 1 has the curve's ⅓ and 1/9 alone (its tangent and curvature: the osculating plane,
  // no μ); at 2 the curve's ⅓ leads the inside's 2/9; at 3, the regular boundary, ⅓ is double; at 4
  // and 5 the inside's m = 1 leads, vanishing on the boundary, and the curve's ⅓ follows. At 6 the
  // inside's m = 2 is ⅓ too, a Jordan block with the curve's: undecided. From 7 faces it passes ⅓:
  // both leading eigenvectors vanish on the boundary — not C1.
  for (int k = 1; k <= 9; ++k) {
    INFO("sqrt3, boundary vertex of " << k << " faces");
    const LocalMatrix S = local_matrix(MeshScheme::sqrt3, k + 1, boundary());
    const LocalSpectrum sp = local_spectrum(S);
    const C1Verdict v = c1_verdict(S, sp);
    REQUIRE(v.sectors.size() == 1);
    if (k <= 5) {
      CHECK(v.c1);
      CHECK(v.method == "sampled");
      if (k >= 2) CHECK(std::abs(v.sectors[0].verdict.angle - std::numbers::pi_v<long double>) < 1e-9L);
    } else if (k == 6) {
      CHECK_FALSE(v.c1);
      CHECK_FALSE(v.decided);
      CHECK_THAT(v.reason, Contains("a Jordan block"));
    } else {
      CHECK_FALSE(v.c1);
      CHECK(sp.second > 1.0L / 3);
      CHECK(v.sectors[0].verdict.through_centre);
    }
  }
  // Catmull–Clark: C1 at 2 and 3 faces; at 4 the inner block's second eigenvalue is the curve's ½
  // (undecided); from 5 faces on two inner eigenvalues pass ½ — not C1.
  for (int k = 2; k <= 9; ++k) {
    INFO("catmull-clark, boundary vertex of " << k << " faces");
    const LocalMatrix S = local_matrix(MeshScheme::catmull_clark, k + 1, boundary());
    const LocalSpectrum sp = local_spectrum(S);
    const C1Verdict v = c1_verdict(S, sp);
    CHECK(v.c1 == (k <= 3));
    if (k >= 5) {
      CHECK(sp.second > 0.5L);
      CHECK(v.sectors[0].verdict.through_centre);
    }
  }
}

TEST_CASE("C1 verdicts per sector: creases, darts, convex and concave corners",
          "[subdivision][mesh_analysis][classes][c1]") {
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop}) {
    INFO(scheme_name(scheme));
    // The regular crease: both sectors C1, each spanning π.
    const int regular = scheme == MeshScheme::catmull_clark ? 4 : 6;
    const LocalMatrix S = local_matrix(scheme, regular, crease(regular / 2));
    const C1Verdict v = c1_verdict(S, local_spectrum(S));
    CHECK(v.c1);
    REQUIRE(v.sectors.size() == 2);
    for (const auto& sector : v.sectors)
      CHECK(std::abs(sector.verdict.angle - std::numbers::pi_v<long double>) < 1e-9L);
    // A crease is C1 where both its sides are (as boundary vertices).
    for (const int k : {1, 2, 3}) {
      const LocalMatrix C = local_matrix(scheme, regular + 1, crease(k));
      const LocalMatrix B1 = local_matrix(scheme, k + 1, boundary());
      const LocalMatrix B2 = local_matrix(scheme, regular + 2 - k, boundary());
      CHECK(c1_verdict(C, local_spectrum(C)).c1 ==
            (c1_verdict(B1, local_spectrum(B1)).c1 && c1_verdict(B2, local_spectrum(B2)).c1));
    }
    // Darts: C1 at every valence tried (the smooth vertex rule, one edge's point a midpoint).
    for (int n = 3; n <= 8; ++n) {
      const LocalMatrix D = local_matrix(scheme, n, {.sharp = {0}});
      const C1Verdict d = c1_verdict(D, local_spectrum(D));
      CHECK(d.c1);
      CHECK(d.winding == 1);
    }
    // The corner of one face (a quad's or triangle's corner): convex, C1; asked to be concave, it
    // fails — the standard corner rule spans the convex cone of its two curves.
    const LocalMatrix K = local_matrix(scheme, 2, boundary(true));
    const C1Verdict convex = c1_verdict(K, local_spectrum(K));
    CHECK(convex.c1);
    CHECK(convex.sectors[0].verdict.angle < std::numbers::pi_v<long double>);
    LocalOptions concave = boundary(true);
    concave.concave = true;
    const LocalMatrix Q = local_matrix(scheme, 2, concave);
    const C1Verdict folded = c1_verdict(Q, local_spectrum(Q));
    CHECK_FALSE(folded.c1);
    CHECK_THAT(folded.reason, Contains("not C1 as a concave corner"));
  }
}

namespace mesh_classes_test {

Mesh classes_cube() {
  Points corners(8, 3);
  for (int i = 0; i < 8; ++i) corners.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  return uniform_mesh(corners, {0, 1, 3, 2, 4, 6, 7, 5, 0, 4, 5, 1, 2, 3, 7, 6, 0, 2, 6, 4, 1, 5, 7, 3}, 4);
}

}  // namespace mesh_classes_test

TEST_CASE("analyze_mesh: every irregular vertex, its class and verdict, each configuration once",
          "[subdivision][mesh_analysis][classes]") {
  Mesh cube = classes_cube();
  const MeshSmoothness plain = analyze_mesh(cube, MeshScheme::catmull_clark);
  CHECK(plain.vertices.size() == 8);  // valence 3 everywhere
  CHECK(plain.regular == 0);
  CHECK(plain.c1 == 8);
  CHECK(plain.analyses == 1);
  CHECK(plain.vertices[5].vertex_class == "interior");
  CHECK(plain.vertices[5].verdict.method == "bernstein");
  CHECK(plain.summary ==
        "catmull-clark: 8 vertices, 0 regular, 8 irregular: 8 C1, 0 not C1, 0 undecided (1 local analysis)");
  // Every edge infinitely sharp: three sharp edges at each vertex, a corner of three one-face sectors,
  // each the (convex) corner of a quad.
  for (int a = 0; a < 8; ++a)
    for (const int bit : {1, 2, 4})
      if ((a & bit) == 0) cube.tags.creases.push_back({a, a | bit, kInfiniteSharpness});
  const MeshSmoothness sharp = analyze_mesh(cube, MeshScheme::catmull_clark);
  REQUIRE(sharp.vertices.size() == 8);
  CHECK(sharp.vertices[0].vertex_class == "corner");
  CHECK(sharp.vertices[0].sectors == std::vector<int>{1, 1, 1});
  CHECK(sharp.c1 == 8);
  // The same verdict as the local analysis of that configuration.
  const LocalMatrix S = local_matrix(MeshScheme::catmull_clark, 3, {.sharp = {0, 1, 2}});
  CHECK(c1_verdict(S, local_spectrum(S)).c1);
  // A hole changes no rule: the vertices keep their verdicts; one only in holes is off the surface.
  cube.tags.holes = {0};
  CHECK(analyze_mesh(cube, MeshScheme::catmull_clark).c1 == 8);

  // A semi-sharp crease decays within ceil(s) levels: its ends are analysed as they are from then on
  // (valence-3 interior vertices here), and say so.
  Mesh semi = classes_cube();
  semi.tags.creases.push_back({0, 1, 1.5});
  const MeshSmoothness decayed = analyze_mesh(semi, MeshScheme::catmull_clark);
  CHECK(decayed.c1 == 8);
  CHECK(decayed.vertices[0].semi_sharp == 1.5);
  CHECK(decayed.vertices[0].vertex_class == "interior");
  CHECK_THAT(
      decayed.vertices[1].verdict.reason,
      Contains("semi-sharp (s = 1.5): analysed after 2 levels, class interior from then on; C1, proved"));
  CHECK(decayed.vertices[2].semi_sharp == 0);
  // Other schemes are refused with one line.
  CHECK_THROWS_WITH(analyze_mesh(classes_cube(), MeshScheme::bilinear), Contains("nothing to analyse"));
  // √3 (no tags, one boundary rule): a triangulated grid's irregular vertices are its corners, two of
  // one face and two of two (the other boundary vertices have the regular three), both C1; under
  // edge_and_corner the same (√3 keeps no corner). Tags are refused.
  Mesh grid = cifs_test::quad_grid(4, 3, true);
  for (const BoundaryRule rule : {BoundaryRule::edge_only, BoundaryRule::edge_and_corner}) {
    grid.tags.boundary = rule;
    const MeshSmoothness sqrt3 = analyze_mesh(grid, MeshScheme::sqrt3);
    CHECK(sqrt3.vertices.size() == 4);
    CHECK(sqrt3.c1 == 4);
    CHECK(sqrt3.analyses == 2);
    for (const VertexSmoothness& v : sqrt3.vertices) CHECK(v.vertex_class == "boundary");
  }
  grid.tags.creases = {{6, 7, kInfiniteSharpness}};
  CHECK_THROWS_WITH(analyze_mesh(grid, MeshScheme::sqrt3),
                    Contains("the mesh has a crease (6 7") && Contains("sqrt3 has no rules for creases"));
  CHECK_THROWS_WITH(analyze_mesh(classes_cube(), MeshScheme::loop),
                    Contains("loop runs on triangles; face 0 has 4"));
}

TEST_CASE("C1 verdicts per sector: the sampled verdicts do not depend on the net's level",
          "[subdivision][mesh_analysis][classes][c1]") {
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop})
    for (int k = 1; k <= 8; ++k)
      for (const bool corner : {false, true}) {
        if (cifs_test::skipped_when_sanitized(static_cast<std::size_t>(k - 1))) continue;  // k = 1, 4, 7
        INFO(scheme_name(scheme) << ", boundary vertex of " << k << " faces" << (corner ? ", corner" : ""));
        const LocalMatrix S = local_matrix(scheme, k + 1, boundary(corner));
        const LocalSpectrum sp = local_spectrum(S);
        const C1Verdict three = c1_verdict(S, sp, {.sampled = true, .levels = 3});
        const C1Verdict five = c1_verdict(S, sp, {.sampled = true, .levels = 5});
        CHECK(three.c1 == five.c1);
        CHECK(three.decided == five.decided);
        if (three.c1) CHECK(std::abs(three.sectors[0].verdict.angle - five.sectors[0].verdict.angle) < 0.2L);
      }
}
