// SPDX-License-Identifier: MIT
// The sampling API against the routes it replaces and against the geometry: a quarter circle from
// homogeneous rows (every point on the circle, consecutive points closer than the tolerance, which
// bounds every Cartesian piece), depth samples = attractor_points and the states of for_each_leaf.
#include "cifs/ifs/sample.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "ifs/helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using namespace ifs_test;

namespace {

/// Knots 0 0 0 1 1 1 and weights 1, √½, 1: a quarter of the unit circle, homogeneous rows (w·x, w).
std::vector<Points> quarter_circle() {
  const double w = std::sqrt(0.5);
  Points P(3, 3);
  P << 1, 0, 1,  //
      w, w, w,   //
      0, 1, 1;
  return {P};
}

/// The chunks of for_each_sample_chunk stacked (points and states), and the count announced.
Sample stacked(const Automaton& a, std::span<const Points> nets, const SampleOptions& o, std::size_t chunk,
               std::size_t& announced) {
  Sample out;
  std::vector<Points> pieces;
  const std::size_t n = for_each_sample_chunk(
      a, nets, o, chunk,
      [&](std::size_t count, int depth) {
        announced = count;
        out.depth = depth;
      },
      [&](const Eigen::Ref<const Points>& rows, std::span<const std::uint32_t> states) {
        CHECK(static_cast<std::size_t>(rows.rows()) <= std::max<std::size_t>(chunk, 256));
        pieces.emplace_back(rows);
        out.states.insert(out.states.end(), states.begin(), states.end());
      });
  Eigen::Index total = 0;
  for (const Points& p : pieces) total += p.rows();
  CHECK(static_cast<std::size_t>(total) == n);
  out.points.resize(total, pieces.empty() ? 0 : pieces[0].cols());
  Eigen::Index at = 0;
  for (const Points& p : pieces) {
    out.points.middleRows(at, p.rows()) = p;
    at += p.rows();
  }
  return out;
}

/// Distance from p to the polyline through the rows of `L`.
double polyline_distance(const Eigen::RowVectorXd& p, const Points& L) {
  double best = (p - L.row(0)).norm();
  for (Eigen::Index i = 1; i < L.rows(); ++i) {
    const Eigen::RowVectorXd a = L.row(i - 1), d = L.row(i) - L.row(i - 1);
    const double t = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (p - a - t * d).norm());
  }
  return best;
}

}  // namespace

TEST_CASE("sample_attractor to a depth: attractor_points, Cartesian, with the leaves' states",
          "[ifs][sample]") {
  std::mt19937_64 rng(31);
  const Automaton a = quadratic_automaton(0.3, 1.7, 4.0);
  const std::vector<Points> nets{random_points(3, 2, rng)};
  for (const int K : {0, 1, 6, 11})
    for (const bool closed : {false, true}) {
      INFO("depth " << K << ", closed " << closed);
      const Sample s = sample_attractor(a, nets, {.depth = K, .closed = closed, .states = true});
      CHECK(s.depth == K);
      CHECK(s.points == attractor_points(a, nets, K, {.closed = closed}));
      std::vector<std::uint32_t> states;
      for_each_leaf(a, nets, K,
                    [&](const Leaf& leaf) { states.push_back(static_cast<std::uint32_t>(leaf.state)); });
      CHECK(s.states == states);
      std::size_t announced = 0;
      const Sample c = stacked(a, nets, {.depth = K, .closed = closed, .states = true}, 100, announced);
      CHECK(announced == static_cast<std::size_t>(s.points.rows()));
      CHECK(c.points == s.points);
      CHECK(c.states == s.states);
    }
  // Homogeneous rows come back Cartesian, on the circle.
  const Sample circle =
      sample_attractor(quadratic_automaton(0, 1, 0), quarter_circle(), {.depth = 9, .homogeneous = true});
  REQUIRE(circle.points.cols() == 2);
  CHECK(circle.points.rows() == 513);
  CHECK((circle.points.rowwise().norm().array() - 1).abs().maxCoeff() <= 1e-14);
  CHECK(circle.states.empty());
}

TEST_CASE("sample_attractor to a tolerance: Cartesian pieces below it, on the curve", "[ifs][sample]") {
  const Automaton a = quadratic_automaton(0, 1, 0);
  const auto nets = quarter_circle();
  for (const double tolerance : {0.3, 1e-2, 1e-4}) {
    INFO("tolerance " << tolerance);
    const Sample s = sample_attractor(a, nets, {.tolerance = tolerance, .homogeneous = true, .states = true});
    REQUIRE(s.points.cols() == 2);
    REQUIRE(s.points.rows() >= 2);
    CHECK(s.states.size() == static_cast<std::size_t>(s.points.rows()) - 1);
    CHECK((s.points.rowwise().norm().array() - 1).abs().maxCoeff() <= 1e-14);
    CHECK((s.points.row(0) - Eigen::RowVector2d(1, 0)).norm() <= 1e-15);
    CHECK((s.points.bottomRows(1) - Eigen::RowVector2d(0, 1)).norm() <= 1e-15);
    // Consecutive points are the two ends of one piece: closer than the tolerance. The quarter arc is
    // π/2 long, so at least π/(2·tolerance) pieces.
    double gap = 0;
    for (Eigen::Index i = 1; i < s.points.rows(); ++i) {
      gap = std::max(gap, (s.points.row(i) - s.points.row(i - 1)).norm());
      CHECK(std::atan2(s.points(i, 1), s.points(i, 0)) > std::atan2(s.points(i - 1, 1), s.points(i - 1, 0)));
    }
    CHECK(gap < tolerance);
    CHECK(static_cast<double>(s.points.rows() - 1) >= std::numbers::pi / 2 / tolerance);
    std::size_t announced = 0;
    const Sample c =
        stacked(a, nets, {.tolerance = tolerance, .homogeneous = true, .states = true}, 7, announced);
    CHECK(announced == static_cast<std::size_t>(s.points.rows()));
    CHECK(c.points == s.points);
    CHECK(c.states == s.states);
    CHECK(c.depth == s.depth);
  }
}

TEST_CASE("sample_attractor refuses before the work, naming the caller's words", "[ifs][sample]") {
  const Automaton a = quadratic_automaton(0, 1, 0);
  const auto nets = quarter_circle();
  CHECK_THROWS_WITH(sample_attractor(a, nets, {.depth = 20, .homogeneous = true, .max_points = 1000}),
                    "depth 20 gives 1048577 points, above the limit of 1000; lower the depth");
  CHECK_THROWS_WITH(
      sample_attractor(a, nets, {.tolerance = 1e-12, .homogeneous = true, .max_points = 1000}),
      Catch::StartsWith("tolerance 1e-12: about ") &&
          Catch::EndsWith("points (estimated from coarser tolerances), above the limit of 1000; "
                          "give a larger tolerance"));
  // Counted exactly within the estimate's budget: the message gives the limit.
  CHECK_THROWS_WITH(
      sample_attractor(a, nets,
                       {.tolerance = 1e-2,
                        .homogeneous = true,
                        .max_points = 20,
                        .tolerance_name = "--tolerance",
                        .limit_hint = " held in memory"}),
      Catch::StartsWith("--tolerance 0.01") && Catch::EndsWith("above the limit of 20 held in memory"));
  CHECK_THROWS_WITH(sample_attractor(a, nets, {.tolerance = 1e-6, .homogeneous = true, .max_depth = 3}),
                    Catch::Contains("a piece is still") && Catch::Contains("wide at depth 3"));
  for (const double bad : {0.0, -1.0, std::nan("")})
    CHECK_THROWS_WITH(sample_attractor(a, nets, {.tolerance = bad}),
                      Catch::EndsWith("is not a positive number"));
  CHECK_THROWS_AS(sample_attractor(a, std::vector<Points>{Points::Zero(2, 3)}, {.depth = 2}), InvalidInput);
}

TEST_CASE(
    "depth_for_tolerance: every piece below epsilon at that depth, by the traversal or the global bound",
    "[ifs][sample]") {
  std::mt19937_64 rng(33);
  const Automaton a = quadratic_automaton(0.3, 1.7, 4.0);
  const std::vector<Points> nets{random_points(3, 2, rng)};
  for (const double epsilon : {0.1, 1e-3, 1e-5}) {
    const int traversal = depth_for_tolerance(a, nets, {.epsilon = epsilon});
    const int global = depth_for_tolerance(a, nets, {.epsilon = epsilon}, 1);  // at once past the budget
    INFO("epsilon " << epsilon << ": depths " << traversal << " and " << global);
    CHECK(global >= traversal);  // the global bound is the coarser one
    CHECK(global <= 64);
    // Consecutive attractor points are the ends of one piece: closer than its diameter.
    const Points P = attractor_points(a, nets, traversal);
    double gap = 0;
    for (Eigen::Index i = 1; i < P.rows(); ++i) gap = std::max(gap, (P.row(i) - P.row(i - 1)).norm());
    CHECK(gap < epsilon);
    // One level above the traversal's depth some piece is still too wide (it is the smallest depth):
    // at least one leaf of the traversal at that depth was not yet converged one level up.
    if (traversal > 0) {
      bool coarser_suffices = true;
      for_each_leaf_to_tolerance(
          a, nets, {.epsilon = epsilon, .max_depth = traversal - 1},
          [&](const ToleranceLeaf& t) { coarser_suffices = coarser_suffices && t.converged; });
      CHECK_FALSE(coarser_suffices);
    }
  }
  CHECK(depth_for_tolerance(a, nets, {.epsilon = 1e-300, .max_depth = 20}, 1) == 20);  // capped
}

TEST_CASE("Chordal tolerance: a polyline within the deviation of a quarter circle, with few points",
          "[ifs][sample]") {
  const Automaton a = quadratic_automaton(0, 1, 0);
  const auto nets = quarter_circle();
  for (const double deviation : {0.1, 1e-3, 1e-6}) {
    INFO("deviation " << deviation);
    const Sample s =
        sample_attractor(a, nets, {.tolerance = deviation, .chordal = true, .homogeneous = true});
    REQUIRE(s.points.rows() >= 2);
    CHECK((s.points.rowwise().norm().array() - 1).abs().maxCoeff() <= 1e-14);  // vertices on the circle
    // The chord between two points of the unit circle an angle θ apart strays 1 − cos(θ/2) from the arc.
    double sagitta = 0, angle = 0;
    for (Eigen::Index i = 1; i < s.points.rows(); ++i) {
      const Eigen::RowVector2d p = s.points.row(i - 1), q = s.points.row(i);
      const double theta = std::atan2(p(0) * q(1) - p(1) * q(0), p.dot(q));
      sagitta = std::max(sagitta, 1 - std::cos(theta / 2));
      angle += theta;
    }
    CHECK(sagitta <= deviation);
    CHECK(std::abs(angle - std::numbers::pi / 2) <= 1e-12);
    // Not wastefully conservative: at most 4 times the fewest chords of that sagitta (the hull of a
    // quadratic piece's net strays twice as far as the arc, and depths come in halvings).
    const double fewest = std::ceil(std::numbers::pi / 2 / (2 * std::acos(1 - deviation)));
    CHECK(static_cast<double>(s.points.rows() - 1) <= 4 * fewest);
  }
  // A piece size of 1e-4 needs ≥ π/2·10^4 pieces; a deviation of 1e-4 about 100.
  const auto chords = sample_attractor(a, nets, {.tolerance = 1e-4, .chordal = true, .homogeneous = true});
  const auto pieces = sample_attractor(a, nets, {.tolerance = 1e-4, .homogeneous = true});
  CHECK(pieces.points.rows() > 100 * chords.points.rows());
  // Streamed: the same points.
  std::size_t announced = 0;
  const Sample c = stacked(a, nets, {.tolerance = 1e-3, .chordal = true, .homogeneous = true}, 7, announced);
  CHECK(c.points ==
        sample_attractor(a, nets, {.tolerance = 1e-3, .chordal = true, .homogeneous = true}).points);
  CHECK(announced == static_cast<std::size_t>(c.points.rows()));
}

TEST_CASE("Chordal tolerance: a cubic B-spline within the deviation both ways (Cox–de Boor)",
          "[ifs][sample]") {
  std::mt19937_64 rng(31);
  const int d = 3, segments = 5;
  const Automaton a = uniform_automaton(d, segments);
  const Points P = random_points(segments + d, 2, rng);
  std::vector<Points> nets;
  for (int k = 0; k < segments; ++k) nets.push_back(P.middleRows(k, d + 1));
  for (const double deviation : {1e-2, 1e-4}) {
    INFO("deviation " << deviation);
    const Points L = sample_attractor(a, nets, {.tolerance = deviation, .chordal = true}).points;
    // Every curve point within the deviation of the polyline, and every chord's midpoint within it
    // (plus the sampling step) of the curve.
    const int n = 400;
    Points curve(segments * n + 1, 2);
    for (int j = 0; j <= segments * n; ++j) {
      const int k = std::min(j / n, segments - 1);
      const Eigen::RowVectorXd x = uniform_reference(P, d, k, static_cast<long double>(j - n * k) / n);
      curve(j, 0) =
          x(0);  // by coefficient: GCC 12 misreads a dynamic row stored into a row (stringop-overread)
      curve(j, 1) = x(1);
    }
    double far = 0;
    for (Eigen::Index j = 0; j < curve.rows(); ++j) far = std::max(far, polyline_distance(curve.row(j), L));
    CHECK(far <= deviation);
    double step = 0;
    for (Eigen::Index j = 1; j < curve.rows(); ++j)
      step = std::max(step, (curve.row(j) - curve.row(j - 1)).norm());
    double back = 0;
    for (Eigen::Index i = 1; i < L.rows(); ++i) {
      const Eigen::RowVectorXd mid = (L.row(i) + L.row(i - 1)) / 2;
      back = std::max(back, (curve.rowwise() - mid).rowwise().norm().minCoeff());
    }
    CHECK(back <= deviation + step);
    CHECK(far >= deviation / 64);  // proven, and still the tolerance asked for
  }
}

TEST_CASE("Chordal tolerance without the hull property: every point of a fractal curve within the deviation",
          "[ifs][sample]") {
  // De Casteljau's quadratic split with negative middle rows: G keeps the start, D the end and both
  // meet at the midpoint row, so the attractor is a continuous (fractal) curve from P0 to P2, and
  // the negative entries leave no hull property (the radius bound is the one used).
  Automaton a;
  const StateId s = add_state(a, 3, "mixed");
  Eigen::MatrixXd G(3, 3), D(3, 3);
  G << 1, 0, 0, 0.6, 0.6, -0.2, 0.25, 0.5, 0.25;
  D << 0.25, 0.5, 0.25, -0.2, 0.6, 0.6, 0, 0, 1;
  add_transition(a, s, s, G, "G");
  add_transition(a, s, s, D, "D");
  add_initial(a, s, 0);
  REQUIRE_FALSE(convex_states(a)[s]);
  std::mt19937_64 rng(5);
  const std::vector<Points> nets{random_points(3, 2, rng)};
  for (const double deviation : {0.05, 0.02, 0.005}) {
    INFO("deviation " << deviation);
    const Sample sample = sample_attractor(a, nets, {.tolerance = deviation, .chordal = true});
    const Points deep = attractor_points(a, nets, 14);  // attractor points, in curve order
    double far = 0;
    for (Eigen::Index j = 0; j < deep.rows(); ++j)
      far = std::max(far, polyline_distance(deep.row(j), sample.points));
    CHECK(far <= deviation);
  }
  CHECK_THROWS_WITH(sample_attractor(a, nets, {.tolerance = 1e-9, .chordal = true, .max_depth = 3}),
                    Catch::Contains("tolerance 1e-09: a piece still strays"));
}
