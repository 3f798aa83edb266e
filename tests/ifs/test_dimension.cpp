// SPDX-License-Identifier: MIT
#include "cifs/ifs/dimension.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "cifs/errors.hpp"
#include "cifs/ifs/affine_cifs.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/io/io.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "ifs/helpers.hpp"

using namespace cifs;
using Catch::Matchers::Contains;

namespace {

Points unit_triangle() {
  Points T(3, 2);
  T << 0, 0, 1, 0, 0.5, std::sqrt(3.0) / 2;
  return T;
}

/// The depth-K start points of the classic IFS's one-state automaton: 3^K (Sierpinski), 4^K
/// (Koch) points of the attractor.
Points classic_points(const std::vector<ifs::AffineMap>& maps, int depth) {
  const Points T = unit_triangle();
  const automata::Automaton a = ifs::affine_automaton(maps, T);
  const std::vector<Points> nets{T};
  return ifs::attractor_points(a, nets, depth);
}

/// A smooth bicubic Bézier patch over [0, 3]², heights 0.6·sin(i + 2j).
nurbs::Surface wavy_bicubic_patch() {
  Points Q(16, 3);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) Q.row(4 * i + j) << i, j, 0.6 * std::sin(i + 2.0 * j);
  return nurbs::make_surface(
      {3, 3}, {nurbs::Knots{0, 0, 0, 0, 1, 1, 1, 1}, nurbs::Knots{0, 0, 0, 0, 1, 1, 1, 1}}, {4, 4}, Q);
}

/// Rotation by `angle` scaled by r, optionally reflected, then translated.
ifs::AffineMap similarity(double r, double angle, bool reflect, double e, double f) {
  const double c = r * std::cos(angle), s = r * std::sin(angle), m = reflect ? -1 : 1;
  return {c, -s * m, s, c * m, e, f, 1};
}

}  // namespace

TEST_CASE("similarity dimension: Moran's equation for Sierpinski and Koch", "[ifs][dimension]") {
  const double sierpinski = std::log(3.0) / std::log(2.0), koch = std::log(4.0) / std::log(3.0);
  CHECK(ifs::similarity_dimension(ifs::sierpinski_triangle()) == Approx(sierpinski).epsilon(1e-12));
  CHECK(ifs::similarity_dimension(ifs::koch_curve()) == Approx(koch).epsilon(1e-12));
  // The same through the one-state automaton on a triangle (maps recovered from the nets).
  const std::vector<Points> nets{unit_triangle()};
  CHECK(ifs::similarity_dimension(ifs::affine_automaton(ifs::sierpinski_triangle(), nets[0]), nets) ==
        Approx(sierpinski).epsilon(1e-12));
  CHECK(ifs::similarity_dimension(ifs::affine_automaton(ifs::koch_curve(), nets[0]), nets) ==
        Approx(koch).epsilon(1e-12));
  // Unequal ratios, reflections: ½^s + ¼^s + ¼^s = 1 ⇔ x + 2x² = 1 with x = 2^-s ⇔ x = ½, s = 1.
  const std::vector<ifs::AffineMap> mixed{similarity(0.5, 0.3, true, 0, 0),
                                          similarity(0.25, 1.0, false, 1, 0),
                                          similarity(0.25, -2.0, true, 0, 1)};
  CHECK(ifs::similarity_dimension(mixed) == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("Mauldin–Williams dimension of hand-solved graphs", "[ifs][dimension]") {
  // u → u (½), u → v (½), v → u (½): det(I − A(s)) = 1 − x − x² with x = 2^-s, whose root
  // x = (√5 − 1)/2 = 1/φ gives s = log₂ φ.
  const double phi = (1 + std::sqrt(5.0)) / 2;
  const std::vector<ifs::SimilarityEdge> golden{{0, 0, 0.5}, {0, 1, 0.5}, {1, 0, 0.5}};
  CHECK(ifs::mauldin_williams_dimension(2, golden) == Approx(std::log2(phi)).epsilon(1e-12));
  // States without edges change nothing, and cost nothing (no states² matrix).
  CHECK(ifs::mauldin_williams_dimension(std::size_t{1} << 40, golden) ==
        Approx(std::log2(phi)).epsilon(1e-12));
  // Two edges u → v of ratio ½ and two v → u of ratio ⅓: A(s) = [0 2·2^-s; 2·3^-s 0] has
  // ρ = 2·6^(-s/2), which is 1 at s = log 4 / log 6.
  const std::vector<ifs::SimilarityEdge> bipartite{
      {0, 1, 0.5}, {0, 1, 0.5}, {1, 0, 1.0 / 3}, {1, 0, 1.0 / 3}};
  CHECK(ifs::mauldin_williams_dimension(2, bipartite) ==
        Approx(std::log(4.0) / std::log(6.0)).epsilon(1e-12));
  // A transient state feeding a component: the dimension is the component's (Sierpinski's).
  const std::vector<ifs::SimilarityEdge> feeding{{0, 1, 0.9}, {1, 1, 0.5}, {1, 1, 0.5}, {1, 1, 0.5}};
  CHECK(ifs::mauldin_williams_dimension(2, feeding) == Approx(std::log2(3.0)).epsilon(1e-12));
  // One map: a point.
  const std::vector<ifs::SimilarityEdge> single{{0, 0, 0.5}};
  CHECK(ifs::mauldin_williams_dimension(1, single) == 0);
}

TEST_CASE("similarity dimension of a two-state automaton of similarities", "[ifs][dimension]") {
  // The golden graph above with actual maps: state u has three points, v too; the matrix of an
  // edge u → v acting as f is barycentric_matrix(f, T) when both reference nets are T.
  const Points T = unit_triangle();
  const ifs::AffineMap f = similarity(0.5, 0.2, false, 0, 0), g = similarity(0.5, 1.1, true, 0.5, 0),
                       h = similarity(0.5, -0.4, false, 0.2, 0.4);
  automata::Automaton a;
  const auto u = ifs_test::add_state(a, 3, "u"), v = ifs_test::add_state(a, 3, "v");
  ifs_test::add_transition(a, u, u, ifs::barycentric_matrix(f, T), "f");
  ifs_test::add_transition(a, u, v, ifs::barycentric_matrix(g, T), "g");
  ifs_test::add_transition(a, v, u, ifs::barycentric_matrix(h, T), "h");
  ifs_test::add_initial(a, u);
  ifs_test::add_initial(a, v);
  const double expected = std::log2((1 + std::sqrt(5.0)) / 2);
  const std::vector<Points> both{T, T};
  CHECK(ifs::similarity_dimension(a, both) == Approx(expected).epsilon(1e-12));
  // Only u initial: v's reference net is g(T), so the edge ratios become 1 (g) and ¼ (h∘g); the
  // cycle products, hence the dimension, are unchanged.
  a.initial.pop_back();
  const std::vector<Points> one{T};
  CHECK(ifs::similarity_dimension(a, one) == Approx(expected).epsilon(1e-12));
}

TEST_CASE("similarity dimension refuses what is not a similarity", "[ifs][dimension]") {
  CHECK_THROWS_WITH(ifs::similarity_dimension(ifs::barnsley_fern()), Contains("map 0 is not a similarity"));
  CHECK_THROWS_AS(ifs::similarity_dimension(std::vector<ifs::AffineMap>{}), InvalidInput);
  const std::vector<ifs::AffineMap> expanding{similarity(1.5, 0, false, 0, 0)};
  CHECK_THROWS_WITH(ifs::similarity_dimension(expanding), Contains("ratio 1.5"));
  // A cubic B-spline: its subdivision matrices are not affine maps of the plane on a 4-point net.
  const automata::Automaton bspline = ifs_test::uniform_automaton(3);
  Points N(4, 2);
  N << 0, 0, 1, 2, 3, -1, 4, 1;
  const std::vector<Points> nets{N};
  CHECK_THROWS_WITH(ifs::similarity_dimension(bspline, nets), Contains("not an affine map"));
  // A collinear net does not determine the map.
  Points line(4, 2);
  line << 0, 0, 1, 0, 2, 0, 3, 0;
  const std::vector<Points> flat{line};
  CHECK_THROWS_WITH(ifs::similarity_dimension(bspline, flat), Contains("does not span"));
  // The fern's automaton: affine, not similar.
  const std::vector<Points> tri{unit_triangle()};
  CHECK_THROWS_WITH(ifs::similarity_dimension(ifs::affine_automaton(ifs::barnsley_fern(), tri[0]), tri),
                    Contains("not a similarity"));
  const std::vector<ifs::SimilarityEdge> bad_ratio{{0, 0, 0.0}}, bad_state{{0, 3, 0.5}}, acyclic{{0, 1, 0.5}},
      expanding_cycle{{0, 0, 0.5}, {0, 0, 1.0}};
  CHECK_THROWS_AS(ifs::mauldin_williams_dimension(1, bad_ratio), InvalidInput);
  CHECK_THROWS_AS(ifs::mauldin_williams_dimension(2, bad_state), InvalidInput);
  CHECK_THROWS_WITH(ifs::mauldin_williams_dimension(2, acyclic), Contains("no cycle"));
  CHECK_THROWS_WITH(ifs::mauldin_williams_dimension(1, expanding_cycle), Contains("do not contract"));
}

TEST_CASE("box counting: Sierpinski and Koch from the deterministic evaluation", "[ifs][dimension]") {
  // The counts converge slowly (N(ε) = a·3^k + O(2^k) on an offset grid: the local slopes approach
  // log₂ 3 like (2/3)^k), hence depth 12 for 0.03; depth 9 gives 1.54 (docs/dimension.md).
  const Points sierpinski = classic_points(ifs::sierpinski_triangle(), 12);
  const ifs::BoxCountingResult s = ifs::box_counting(sierpinski);
  INFO("Sierpinski: " << s.dimension << " over levels " << s.min_level << " … " << s.max_level);
  CHECK(std::abs(s.dimension - std::log2(3.0)) < 0.03);
  CHECK(s.max_level - s.min_level >= 2);
  const ifs::BoxCountingResult k = ifs::box_counting(classic_points(ifs::koch_curve(), 9));
  INFO("Koch: " << k.dimension << " over levels " << k.min_level << " … " << k.max_level);
  CHECK(std::abs(k.dimension - std::log(4.0) / std::log(3.0)) < 0.03);
  // Counts: one box at most 2^dim at level 0, never decreasing, never above the points.
  CHECK(s.counts.front().boxes <= 4);
  for (std::size_t i = 1; i < s.counts.size(); ++i) {
    CHECK(s.counts[i].boxes >= s.counts[i - 1].boxes);
    CHECK(s.counts[i].epsilon == s.counts[i - 1].epsilon / 2);
  }
  CHECK(s.counts.back().boxes <= std::size_t(sierpinski.rows()));
  CHECK(s.r_squared > 0.99);
}

TEST_CASE("box counting: smooth curve 1, surface mesh 2", "[ifs][dimension]") {
  Points P(5, 2);
  P << 0, 0, 1, 2, 3, -1, 4, 1, 6, 0;
  const nurbs::Curve c = nurbs::make_curve(3, {0, 0, 0, 0, 0.4, 1, 1, 1, 1}, P);
  const nurbs::KnotAutomaton ka = nurbs::knot_automaton(c);
  const automata::Automaton& a = ka.automaton;
  const Points curve = ifs::attractor_points(a, nurbs::initial_nets(ka, c), 15);
  const ifs::BoxCountingResult r = ifs::box_counting(curve);
  INFO("curve: " << r.dimension << " over levels " << r.min_level << " … " << r.max_level);
  CHECK(std::abs(r.dimension - 1) < 0.02);

  const nurbs::Surface s = wavy_bicubic_patch();
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  // Boundary boxes bias the slope by about perimeter·ε/area: depth 10 gives 1.947, 11 gives 1.959.
  const Mesh mesh = ifs::surface_mesh(t, nurbs::initial_nets(t, s), 11);
  const ifs::BoxCountingResult m = ifs::box_counting(mesh.vertices);
  INFO("surface: " << m.dimension << " over levels " << m.min_level << " … " << m.max_level);
  CHECK(std::abs(m.dimension - 2) < 0.05);
}

TEST_CASE("box counting: fit ranges and bad input", "[ifs][dimension]") {
  const Points sierpinski = classic_points(ifs::sierpinski_triangle(), 7);
  ifs::BoxCountingOptions o;
  o.min_level = 2;
  o.max_level = 5;
  const ifs::BoxCountingResult r = ifs::box_counting(sierpinski, o);
  CHECK(r.min_level == 2);
  CHECK(r.max_level == 5);
  CHECK(r.max_epsilon == r.size / 4);
  CHECK(r.min_epsilon == r.size / 32);
  // The slope is the least-squares slope of the reported counts (independent formula:
  // Σ(x − x̄)(y − ȳ)/Σ(x − x̄)² with x = k·log 2).
  double sx = 0, sy = 0, sxy = 0, sxx = 0;
  for (int k = 2; k <= 5; ++k) {
    const double x = k * std::log(2.0), y = std::log(double(r.counts[std::size_t(k)].boxes));
    sx += x, sy += y, sxy += x * y, sxx += x * x;
  }
  CHECK(r.dimension == Approx((4 * sxy - sx * sy) / (4 * sxx - sx * sx)).epsilon(1e-12));
  // Resolution: boxes below twice the pieces are not fitted.
  o = {};
  o.min_boxes = 10;
  CHECK(ifs::box_counting(sierpinski, o).max_level == 5);  // 357 boxes at level 5, 1045 at 6
  o.resolution = r.size / 32;
  CHECK(ifs::box_counting(sierpinski, o).max_level == 4);

  CHECK_THROWS_WITH(ifs::box_counting(Points(0, 2)), Contains("no points"));
  Points same(3, 2);
  same.setOnes();
  CHECK_THROWS_WITH(ifs::box_counting(same), Contains("all points are equal"));
  Points nan = sierpinski;
  nan(1, 1) = std::nan("");
  CHECK_THROWS_WITH(ifs::box_counting(nan), Contains("not finite"));
  CHECK_THROWS_WITH(ifs::box_counting(classic_points(ifs::sierpinski_triangle(), 3)),
                    Contains("evaluate deeper"));
  o = {};
  o.min_level = 4;
  o.max_level = 5;
  CHECK_THROWS_WITH(ifs::box_counting(sierpinski, o), Contains("at least 3 levels"));
}

TEST_CASE("piece bounds hold: hull, contraction and Cartesian (rational) bounds", "[ifs][dimension]") {
  std::mt19937_64 rng(11);
  // The true piece: attractor points 8 levels below the node (Cartesian for homogeneous rows).
  const auto check = [](const automata::Automaton& a, const std::vector<Points>& nets, bool homogeneous) {
    const ifs::PieceBounds bounds(a, ifs::contraction(a), homogeneous);
    int finite = 0;
    for (const int depth : {0, 2, 4})
      ifs::for_each_leaf(a, nets, depth, [&](const ifs::Leaf& leaf) {
        const ifs::PieceBound b = bounds(leaf.state, leaf.net);
        CHECK(b.diameter <= 2 * b.radius * (1 + 1e-12));
        if (!std::isfinite(b.diameter)) return;
        ++finite;
        automata::Automaton sub = a;
        sub.initial.clear();
        ifs_test::add_initial(sub, leaf.state);
        const std::vector<Points> sub_nets{leaf.net};
        Points X = ifs::attractor_points(sub, sub_nets, 8);
        Points N0 = leaf.net.topRows(1);
        if (homogeneous) X = ifs::cartesian(X), N0 = ifs::cartesian(N0);
        CHECK(ifs::diameter(X) <= b.diameter * (1 + 1e-12));
        for (Eigen::Index i = 0; i < X.rows(); ++i) CHECK((X.row(i) - N0).norm() <= b.radius * (1 + 1e-12));
      });
    CHECK(finite > 0);
  };
  SECTION("non-negative matrices: the hull bound, diam(net)") {
    const automata::Automaton a = ifs_test::uniform_automaton(3);
    CHECK(ifs::convex_states(a) == std::vector<bool>{true});
    const std::vector<Points> nets{ifs_test::random_points(4, 2, rng)};
    check(a, nets, false);
    const ifs::PieceBounds bounds(a, ifs::contraction(a), false);
    CHECK(bounds(0, nets[0]).diameter == ifs::diameter(nets[0]));
    // Rational: positive weights keep the Cartesian hull property.
    Points H(4, 3);
    for (Eigen::Index i = 0; i < 4; ++i) {
      const double w = 0.5 + std::abs(nets[0](i, 0));
      H.row(i) << w * nets[0](i, 0), w * nets[0](i, 1), w;
    }
    check(a, {H}, true);
  }
  SECTION("signed matrices: the contraction bound, Cartesian through the weight bound") {
    automata::Automaton a;
    const automata::StateId s = ifs_test::add_state(a, 3), t = ifs_test::add_state(a, 3);
    Eigen::MatrixXd A = ifs_test::random_contraction(3, 3, 0.4, rng);
    A.row(0) << 1.1, -0.3, 0.2;  // a negative entry, δ still < 1
    ifs_test::add_transition(a, s, s, A, "a");
    ifs_test::add_transition(a, s, t, ifs_test::random_contraction(3, 3, 0.4, rng), "b");
    ifs_test::add_transition(a, t, t, nurbs::subdivision_matrix(nurbs::Window(3, 1.0), 2, nurbs::Half::G),
                             "c");
    ifs_test::add_transition(a, t, t, nurbs::subdivision_matrix(nurbs::Window(3, 1.0), 2, nurbs::Half::D),
                             "d");
    ifs_test::add_initial(a, s);
    CHECK(ifs::convex_states(a) == std::vector<bool>{false, true});
    check(a, {ifs_test::random_points(3, 2, rng)}, false);
    Points H = ifs_test::random_points(3, 3, rng);
    H.col(2).setConstant(1);
    H.col(2) += 0.1 * ifs_test::random_points(3, 1, rng);
    check(a, {H}, true);
  }
}

TEST_CASE("tolerance sample: Sierpinski and Koch within 0.01, a smooth curve 1", "[ifs][dimension]") {
  const auto dimension_of = [](const automata::Automaton& a, const std::vector<Points>& nets,
                               bool homogeneous, std::size_t budget) {
    ifs::ToleranceSampleOptions so;
    so.max_points = budget;
    so.homogeneous = homogeneous;
    const ifs::ToleranceSample s = ifs::tolerance_sample(a, nets, so);
    CHECK(s.leaves == static_cast<std::size_t>(s.points.rows()));
    CHECK(s.leaves <= budget);
    ifs::BoxCountingOptions bo;
    bo.resolution = s.resolution;
    bo.points_per_box = 1;
    const ifs::BoxCountingResult r = ifs::box_counting(s.points, bo);
    CHECK(r.min_epsilon >= 2 * s.resolution);
    return r.dimension;
  };
  const Points T = unit_triangle();
  CHECK(std::abs(dimension_of(ifs::affine_automaton(ifs::sierpinski_triangle(), T), {T}, false, 1u << 20) -
                 std::log(3.0) / std::log(2.0)) < 0.01);
  CHECK(std::abs(dimension_of(ifs::affine_automaton(ifs::koch_curve(), T), {T}, false, 1u << 20) -
                 std::log(4.0) / std::log(3.0)) < 0.01);
  std::mt19937_64 rng(3);
  CHECK(std::abs(dimension_of(ifs_test::uniform_automaton(3), {ifs_test::random_points(4, 2, rng)}, false,
                              1u << 18) -
                 1) < 0.02);
  SECTION("budget and bad input") {
    ifs::ToleranceSampleOptions so;
    so.epsilon = 1e-6;
    so.max_points = 1000;
    CHECK_THROWS_WITH(ifs::tolerance_sample(ifs_test::uniform_automaton(3),
                                            std::vector<Points>{ifs_test::random_points(4, 2, rng)}, so),
                      Contains("needs more than 1000 points"));
    so.epsilon = -1;
    CHECK_THROWS_WITH(ifs::tolerance_sample(ifs_test::uniform_automaton(3),
                                            std::vector<Points>{ifs_test::random_points(4, 2, rng)}, so),
                      Contains("tolerance -1 is not a finite number ≥ 0"));
    // Nets of two widths: nets_diameter stacked them past the end of its matrix (found by the Python
    // robustness test under ASan, through the automatic tolerance before any other check).
    so.epsilon = 0;
    CHECK_THROWS_WITH(ifs::nets_diameter(std::vector<Points>{Points::Zero(4, 2), Points::Zero(3, 3)}),
                      Contains("control net 1 has 3 columns, control net 0 has 2"));
  }
}

TEST_CASE("depth sample: deepest depth within the budget, nets' diameters, uncertainty", "[ifs][dimension]") {
  // Sierpinski: 3^K + 1 points at depth K, each depth-K net the unit triangle scaled by 2^-K.
  const Points T = unit_triangle();
  const automata::Automaton a = ifs::affine_automaton(ifs::sierpinski_triangle(), T);
  const std::vector<Points> nets{T};
  ifs::DepthSampleOptions o;
  o.max_points = 6562;  // 3^8 + 1
  ifs::DepthSample s = ifs::depth_sample(a, nets, o);
  CHECK(s.depth == 8);
  CHECK(s.points.rows() == 6562);
  CHECK(s.resolution == Approx(std::ldexp(1.0, -8)).epsilon(1e-12));
  o.max_points = 6561;
  CHECK(ifs::depth_sample(a, nets, o).depth == 7);
  o.max_points = 1;
  CHECK_THROWS_WITH(ifs::depth_sample(a, nets, o), Contains("even depth 0 has more than 1 points"));

  // The uncertainty: local slopes log2(N_{k+1}/N_k) recomputed from the counts, and log 3/log 2
  // within it on a depth-13 sample (3^13 points).
  o.max_points = std::size_t{1} << 22;
  s = ifs::depth_sample(a, nets, o);
  CHECK(s.depth == 13);
  const ifs::BoxCountingResult r = ifs::box_counting(s.points);
  double spread = 0;
  for (int k = r.min_level; k < r.max_level; ++k) {
    const auto n = [&](int level) {
      return static_cast<double>(r.counts[static_cast<std::size_t>(level)].boxes);
    };
    spread = std::max(spread, std::abs(std::log2(n(k + 1) / n(k)) - r.dimension));
  }
  CHECK(r.spread == Approx(spread).epsilon(1e-9));
  CHECK(r.uncertainty == std::max(r.spread, r.standard_error));
  CHECK(r.standard_error > 0);
  CHECK(std::abs(r.dimension - std::log2(3.0)) <= r.uncertainty);
}

TEST_CASE("tolerance sample: the tolerance its search counted is sampled, whatever the estimate says",
          "[ifs][dimension]") {
  // hills.json at a budget of 500000: the search counts its leaves within the budget at a tolerance
  // where the estimate from coarser tolerances is above it; the sample used to be refused there.
  const auto s = std::get<nurbs::Surface>(io::read_shape(CIFS_EXAMPLES_DIR "/shapes/hills.json"));
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const std::vector<Points> nets = nurbs::initial_nets(t, s);
  const std::size_t budget = 500000;
  const ifs::ToleranceSample sample =
      ifs::tolerance_sample(t.product, nets, {.homogeneous = s.rational, .max_points = budget});
  CHECK(sample.leaves <= budget);
  const ifs::ToleranceEstimate estimate = ifs::estimate_tolerance_leaves(
      t.product, nets, {.epsilon = sample.resolution, .homogeneous = s.rational});
  CHECK_FALSE(estimate.exact);
  CHECK(estimate.leaves > static_cast<double>(budget));
  // The walk is still held to the limit: the same tolerance with fewer points allowed is refused.
  CHECK_THROWS_WITH(ifs::sample_attractor(t.product, nets,
                                          {.tolerance = sample.resolution,
                                           .homogeneous = s.rational,
                                           .closed = true,
                                           .max_points = sample.leaves - 1,
                                           .estimate = false}),
                    Catch::Contains("gives more than"));
}

TEST_CASE("proven cover: the pieces' growth is the dimension, without the boxes' boundary term",
          "[ifs][dimension]") {
  SECTION("the slope of exact power laws, and too few counts") {
    std::vector<ifs::CoverCount> counts;
    for (int j = 0; j < 8; ++j)
      counts.push_back({std::ldexp(1.0, -j), static_cast<std::size_t>(std::llround(std::pow(3.0, j + 4)))});
    const std::optional<ifs::CoverExponent> e = ifs::cover_exponent(counts, 1000);
    REQUIRE(e);
    CHECK(std::abs(e->dimension - std::log2(3.0)) < 1e-12);
    CHECK(e->spread < 1e-12);
    CHECK(e->levels == 5);  // 3^7 … 3^11 have ≥ 1000 leaves
    CHECK(e->min_epsilon == std::ldexp(1.0, -7));
    CHECK(e->max_epsilon == std::ldexp(1.0, -3));
    const std::optional<ifs::CoverExponent> finest = ifs::cover_exponent(counts, 1000, 4);
    REQUIRE(finest);
    CHECK(finest->levels == 4);
    CHECK(finest->max_epsilon == std::ldexp(1.0, -4));
    CHECK_FALSE(ifs::cover_exponent(std::span(counts).first(5), 1000));  // 3^7, 3^8 only ≥ 1000
  }
  const auto cover_of = [](const automata::Automaton& a, const std::vector<Points>& nets,
                           std::size_t budget) {
    ifs::ToleranceSampleOptions so;
    so.max_points = budget;
    const ifs::ToleranceSample s = ifs::tolerance_sample(a, nets, so);
    // The search's counts: ε halves from diam·2^-4, the sample's own count last.
    REQUIRE(s.cover.size() >= 2);
    CHECK(s.cover.back().leaves == s.leaves);
    CHECK(s.cover.back().epsilon == s.resolution);
    for (std::size_t i = 1; i < s.cover.size(); ++i) {
      CHECK(s.cover[i].epsilon == s.cover[i - 1].epsilon / 2);
      CHECK(s.cover[i].leaves >= s.cover[i - 1].leaves);
    }
    const std::optional<ifs::CoverExponent> e = ifs::cover_exponent(s.cover);
    REQUIRE(e);
    return e->dimension;
  };
  // Sierpinski: the pieces at depth k are the 3^k triangles of side 2^-k, so each halving of ε
  // triples the count exactly.
  const Points T = unit_triangle();
  CHECK(std::abs(cover_of(ifs::affine_automaton(ifs::sierpinski_triangle(), T), {T}, 1u << 20) -
                 std::log2(3.0)) < 1e-12);
  std::mt19937_64 rng(3);
  CHECK(std::abs(cover_of(ifs_test::uniform_automaton(3), {ifs_test::random_points(4, 2, rng)}, 1u << 18) -
                 1) < 0.01);
  // A smooth bicubic patch: the boxes read 1.95 at this budget (the boundary term, see "box
  // counting: smooth curve 1, surface mesh 2"); the proven pieces tile it and grow as ε^-2.
  const nurbs::Surface s = wavy_bicubic_patch();
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const double surface = cover_of(t.product, nurbs::initial_nets(t, s), 1u << 20);
  CHECK(std::abs(surface - 2) < 0.02);
}
