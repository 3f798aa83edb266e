// SPDX-License-Identifier: MIT
#include "cifs/ifs/affine_cifs.hpp"

#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/chaos.hpp"

using namespace cifs;
using namespace cifs::ifs;

namespace {

Points control_triangle() {
  Points T(3, 2);
  T << -0.3, 0.1, 1.7, -0.2, 0.4, 2.3;
  return T;
}

/// Grid cells of size h occupied by the points.
std::set<std::pair<long, long>> cells(const Points& P, double h) {
  std::set<std::pair<long, long>> out;
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    out.emplace(std::lround(std::floor(P(i, 0) / h)), std::lround(std::floor(P(i, 1) / h)));
  return out;
}

/// Cells of `a` without an occupied cell of `b` among their 3×3 neighbours.
std::size_t uncovered(const std::set<std::pair<long, long>>& a, const std::set<std::pair<long, long>>& b) {
  std::size_t count = 0;
  for (const auto& [x, y] : a) {
    bool found = false;
    for (long dx = -1; dx <= 1 && !found; ++dx)
      for (long dy = -1; dy <= 1 && !found; ++dy) found = b.count({x + dx, y + dy}) > 0;
    count += found ? 0 : 1;
  }
  return count;
}

}  // namespace

TEST_CASE("affine IFS as a one-state CIFS: leaf nets are the maps' compositions", "[affine]") {
  const Points T = control_triangle();
  for (const auto& maps : {barnsley_fern(), sierpinski_triangle(), koch_curve()}) {
    const automata::Automaton a = affine_automaton(maps, T);
    for (const automata::TransitionId e : edges(a.graph))
      CHECK((a.graph[e].matrix.rowwise().sum().array() - 1).abs().maxCoeff() <= 1e-14);
    int leaves = 0;
    for_each_leaf(a, std::span<const Points>(&T, 1), 4, [&](const Leaf& leaf) {
      // The net of word w1…wk is w1∘…∘wk applied to the corners (barycentric coordinates are
      // affine invariant), computed here from the maps alone.
      for (int i = 0; i < 3; ++i) {
        Point p = T.row(i);
        for (auto k = leaf.word.size(); k-- > 0;) p = apply(maps[static_cast<std::size_t>(leaf.word[k])], p);
        CHECK((leaf.net.row(i) - p).norm() <= 1e-12);
      }
      ++leaves;
    });
    CHECK(leaves == static_cast<int>(std::pow(maps.size(), 4)));
  }
}

TEST_CASE("affine IFS as a one-state CIFS: chaos game against the maps' iteration", "[affine]") {
  const Points T = control_triangle();
  for (const auto& maps : {sierpinski_triangle(), koch_curve(), barnsley_fern()}) {
    const automata::Automaton a = affine_automaton(maps, T);
    ChaosOptions options;
    options.samples = 20000;
    options.seed = 9;
    const Points cifs_points = chaos_game(a, std::span<const Points>(&T, 1), options).points;
    // Plain iteration x ← w_k(x) from the fixed point of w_0, maps drawn uniformly.
    std::mt19937_64 rng(4);
    std::uniform_int_distribution<std::size_t> pick(0, maps.size() - 1);
    const AffineMap& m0 = maps[0];
    Eigen::Matrix2d L;
    L << m0.a, m0.b, m0.c, m0.d;
    const Eigen::Vector2d fixed =
        Eigen::Matrix2d(Eigen::Matrix2d::Identity() - L).partialPivLu().solve(Eigen::Vector2d(m0.e, m0.f));
    Point x(2);
    x << fixed(0), fixed(1);
    Points iterated(200000, 2);
    for (Eigen::Index i = 0; i < iterated.rows(); ++i) iterated.row(i) = x = apply(maps[pick(rng)], x);
    const double h = 0.01 * (iterated.colwise().maxCoeff() - iterated.colwise().minCoeff()).norm();
    const auto c = cells(cifs_points, h), it = cells(iterated, h);
    CHECK(uncovered(c, it) == 0);  // every CIFS point lies on the attractor (within two cells)
    // and the CIFS attractor fills it: every attractor piece of the tolerance traversal has
    // diameter < h, so every attractor point is within h of its piece's start point.
    const auto F = end_functionals(a);
    std::vector<Point> starts;
    ToleranceOptions tolerance;
    tolerance.epsilon = h;
    const auto result = for_each_leaf_to_tolerance(
        a, std::span<const Points>(&T, 1), tolerance,
        [&](const ToleranceLeaf& t) { starts.push_back(F.start[t.leaf.state] * t.leaf.net); });
    CHECK(result.unconverged == 0);
    Points sample(static_cast<Eigen::Index>(starts.size()), 2);
    for (std::size_t k = 0; k < starts.size(); ++k) sample.row(static_cast<Eigen::Index>(k)) = starts[k];
    CHECK(uncovered(it, cells(sample, h)) == 0);
  }
}

TEST_CASE("affine_automaton refuses degenerate triangles", "[affine]") {
  Points flat(3, 2);
  flat << 0, 0, 1, 1, 2, 2;
  CHECK_THROWS_WITH(affine_automaton(sierpinski_triangle(), flat), Catch::Contains("degenerate"));
  CHECK_THROWS_AS(affine_automaton({}, control_triangle()), InvalidInput);
  CHECK_THROWS_AS(barycentric_matrix(sierpinski_triangle()[0], Points(2, 2)), InvalidInput);
}

TEST_CASE("named affine IFS: one registry for the experiment files, the runner and Python", "[affine]") {
  CHECK(ifs_names() == std::vector<std::string>{"fern", "sierpinski", "koch"});
  // Told apart by what defines them (map counts, Barnsley's probabilities, the ratios ½ and ⅓).
  const auto fern = named_ifs("fern");
  REQUIRE(fern.size() == 4);
  CHECK(fern[1].a == 0.85);
  CHECK(fern[0].probability == 0.01);
  const auto sierpinski = named_ifs("sierpinski");
  REQUIRE(sierpinski.size() == 3);
  CHECK(std::hypot(sierpinski[2].a, sierpinski[2].c) == Approx(0.5).epsilon(1e-15));
  const auto koch = named_ifs("koch");
  REQUIRE(koch.size() == 4);
  CHECK(std::hypot(koch[1].a, koch[1].c) == Approx(1.0 / 3).epsilon(1e-15));
  CHECK_THROWS_WITH(named_ifs("Fern"), "unknown IFS \"Fern\"; give one of fern, sierpinski, koch");
  CHECK_THROWS_AS(named_ifs(""), InvalidInput);
}
