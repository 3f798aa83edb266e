// SPDX-License-Identifier: MIT
// The CIFS attractor of NURBS curves against knot insertion and Cox–de Boor, on random curves.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/verify/check.hpp"

using namespace cifs;

namespace {

struct CurveKind {
  bool clamped, rational, closed;
};

/// A random curve: interval lengths 10^[-3, 3] (ratios up to 1e6), weights 10^[-3, 3].
nurbs::Curve random_checked_curve(std::mt19937_64& rng, int d, int dim, CurveKind kind) {
  std::uniform_real_distribution<double> exponent(-3, 3);
  const int n = d + 4;
  const Points P = Points::Random(n, dim) * 10;
  Eigen::VectorXd w(n);
  for (int i = 0; i < n; ++i) w(i) = std::pow(10.0, exponent(rng));
  const Eigen::VectorXd weights = kind.rational ? w : Eigen::VectorXd();
  if (kind.closed) {
    nurbs::Knots b(static_cast<std::size_t>(n + 1));
    for (std::size_t i = 1; i < b.size(); ++i) b[i] = b[i - 1] + std::pow(10.0, exponent(rng));
    return nurbs::make_closed_curve(d, b, P, weights);
  }
  nurbs::Knots t(static_cast<std::size_t>(n + d + 1));
  for (std::size_t i = 1; i < t.size(); ++i) {
    const bool end = kind.clamped && (i <= static_cast<std::size_t>(d) || i > static_cast<std::size_t>(n));
    t[i] = end ? t[i - 1] : t[i - 1] + std::pow(10.0, exponent(rng));
  }
  return nurbs::make_curve(d, t, P, weights);
}

}  // namespace

TEST_CASE("Attractor = knot insertion = Cox-de Boor, degrees 1-10, ratios 1e6, weights 1e-3..1e3",
          "[verify]") {
  std::mt19937_64 rng(20261121);
  const CurveKind kinds[] = {{true, false, false}, {false, false, false}, {true, true, false},
                             {false, true, false}, {false, false, true},  {false, true, true}};
  for (int d = 1; d <= 10; ++d)
    for (const CurveKind& kind : kinds) {
      const nurbs::Curve c = random_checked_curve(rng, d, 1 + d % 4, kind);
      const verify::CheckReport r = verify::check_curve(c, {.depth = d <= 3 ? 10 : 7, .tolerance = 1e-12});
      INFO("degree " << d << " clamped " << kind.clamped << " rational " << kind.rational << " closed "
                     << kind.closed << ": nets " << r.nets.max_rel << ", points " << r.points.max_rel);
      CHECK(r.pass);
      CHECK(r.segments.size() == static_cast<std::size_t>(nurbs::segment_count(c)));
    }
}

TEST_CASE("A deep check of a cubic", "[verify]") {
  std::mt19937_64 rng(3);
  const verify::CheckReport r = verify::check_curve(random_checked_curve(rng, 3, 3, {false, true, false}),
                                                    {.depth = 14, .tolerance = 1e-12});
  INFO("nets " << r.nets.max_rel << ", points " << r.points.max_rel);
  CHECK(r.pass);
  CHECK(r.depth == 14);
}

TEST_CASE("Junctions: the end of G is the start of D, neighbouring segments agree", "[verify]") {
  std::mt19937_64 rng(11);
  for (int d = 2; d <= 6; ++d) {
    const nurbs::Curve c = random_checked_curve(rng, d, 2, {false, true, false});
    const nurbs::KnotAutomaton ka = nurbs::knot_automaton(c);
    const automata::Automaton& a = ka.automaton;
    const ifs::EndFunctionals f = ifs::end_functionals(a);
    const std::vector<Points> nets = nurbs::initial_nets(ka, c);
    const double scale = c.P.cwiseAbs().maxCoeff();
    for (std::size_t i = 0; i < nets.size(); ++i) {
      std::vector<automata::StateId> child;
      std::vector<Points> child_net;
      for (auto [e, end] = out_edges(a.initial[i].state, a.graph); e != end; ++e) {
        child.push_back(target(*e, a.graph));
        child_net.push_back(a.graph[*e].matrix * nets[i]);
      }
      CHECK((f.end[child[0]] * child_net[0] - f.start[child[1]] * child_net[1]).norm() <= 1e-12 * scale);
      if (i + 1 < nets.size())
        CHECK((f.end[a.initial[i].state] * nets[i] - f.start[a.initial[i + 1].state] * nets[i + 1]).norm() <=
              1e-12 * scale);
    }
  }
}

TEST_CASE("Chaos-game points lie on the curve at their recorded parameter", "[verify]") {
  std::mt19937_64 rng(17);
  const nurbs::Curve c = random_checked_curve(rng, 3, 3, {true, true, false});
  const nurbs::KnotAutomaton ka = nurbs::knot_automaton(c);
  const automata::Automaton& a = ka.automaton;
  ifs::ChaosOptions options;
  options.samples = 2000;
  options.seed = 42;
  options.record_address = true;
  const ifs::ChaosResult r = ifs::chaos_game(a, nurbs::initial_nets(ka, c), options);
  const Points P = ifs::cartesian(r.points);
  const double scale = nurbs::cartesian_points(c).cwiseAbs().maxCoeff();
  for (Eigen::Index k = 0; k < P.rows(); ++k) {
    const double address = r.address[static_cast<std::size_t>(k)];
    const auto i =
        static_cast<std::size_t>(std::min(std::floor(address), static_cast<double>(a.initial.size() - 1)));
    const double u = ka.intervals[i].start +
                     (address - static_cast<double>(i)) * (ka.intervals[i].end - ka.intervals[i].start);
    CHECK((P.row(k) - nurbs::evaluate(c, u)).norm() <= 1e-9 * scale);
  }
}

TEST_CASE("check refuses bad depths and work beyond its budget", "[verify]") {
  std::mt19937_64 rng(1);
  const nurbs::Curve c = random_checked_curve(rng, 3, 2, {true, false, false});
  CHECK_THROWS_WITH(verify::check_curve(c, {.depth = -1, .tolerance = 1e-12}),
                    Catch::Contains("depth -1 is outside [0, 30]"));
  CHECK_THROWS_WITH(verify::check_curve(c, {.depth = 24, .tolerance = 1e-12}),
                    Catch::Contains("would insert"));
  CHECK_THROWS_WITH(verify::check_curve(c, {.depth = 4, .tolerance = 0}),
                    "the check tolerance 0 is not positive; give a positive finite tolerance");
  // An infinite tolerance would pass anything.
  CHECK_THROWS_WITH(verify::check_curve(c, {.depth = 4, .tolerance = INFINITY}),
                    "the check tolerance is not a finite number; give a positive finite tolerance");
}

namespace {

/// A random surface of `degree` (1 … 6 per direction): interval lengths 10^[-3, 3] (ratios up to
/// 1e6), weights 10^[-3, 3], clamped or not.
nurbs::Surface random_checked_surface(std::mt19937_64& rng, std::array<int, 2> degree, bool clamped,
                                      bool rational) {
  std::uniform_real_distribution<double> exponent(-3, 3);
  std::array<nurbs::Knots, 2> knots;
  std::array<Eigen::Index, 2> count{};
  for (std::size_t dir = 0; dir < 2; ++dir) {
    const int d = degree[dir], n = d + 2;
    count[dir] = n;
    nurbs::Knots& t = knots[dir];
    t.assign(static_cast<std::size_t>(n + d + 1), 0.0);
    for (std::size_t i = 1; i < t.size(); ++i) {
      const bool end = clamped && (i <= static_cast<std::size_t>(d) || i > static_cast<std::size_t>(n));
      t[i] = end ? t[i - 1] : t[i - 1] + std::pow(10.0, exponent(rng));
    }
  }
  const Points P = Points::Random(count[0] * count[1], 3) * 10;
  Eigen::VectorXd w(count[0] * count[1]);
  for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = std::pow(10.0, exponent(rng));
  return nurbs::make_surface(degree, knots, count, P, rational ? w : Eigen::VectorXd());
}

}  // namespace

TEST_CASE("Surface attractor = knot insertion = evaluation, degrees 1-6, ratios 1e6, weights 1e-3..1e3",
          "[verify][surface]") {
  // Rational nets mix (p+1)(q+1) homogeneous rows whose weights differ by up to 1e6: a Cartesian
  // row carries rounding up to eps·w_max/w_min ≈ 2e-10 in the worst case, on either route. Over
  // 2000 random rational surfaces the largest deviation seen was 3.3e-12 (the Boehm reference
  // itself agrees with long double to 1e-15), so rational surfaces get 5e-12 here.
  std::mt19937_64 rng(31);
  for (int p = 1; p <= 6; ++p)
    for (int q = 1; q <= 6; ++q) {
      const bool clamped = (p + q) % 2 == 0, rational = (p * q) % 3 != 1;
      const nurbs::Surface s = random_checked_surface(rng, {p, q}, clamped, rational);
      const double tolerance = rational ? 5e-12 : 1e-12;
      const verify::SurfaceCheckReport r = verify::check_surface(s, {.depth = 3, .tolerance = tolerance});
      INFO("degrees " << p << ", " << q << ", clamped " << clamped << ", rational " << rational << ": nets "
                      << r.nets.max_rel << ", points " << r.points.max_rel);
      CHECK(r.pass);
      CHECK(r.patches.size() == 4);
      CHECK(r.nets.max_rel <= tolerance);
      CHECK(r.points.max_rel <= tolerance);
    }
}

TEST_CASE("Surface check: a deeper rational bicubic", "[verify][surface]") {
  std::mt19937_64 rng(37);
  const nurbs::Surface s = random_checked_surface(rng, {3, 3}, false, true);
  const verify::SurfaceCheckReport r = verify::check_surface(s, {.depth = 6, .tolerance = 5e-12});
  CHECK(r.pass);
  CHECK(r.patches[3].patch == std::array<int, 2>{1, 1});
  CHECK(r.patches[3].u[0] == s.knots[0][4]);
}

TEST_CASE("Surface check refuses bad depths and work beyond its budget", "[verify][surface]") {
  std::mt19937_64 rng(41);
  const nurbs::Surface s = random_checked_surface(rng, {3, 3}, true, false);
  CHECK_THROWS_AS(verify::check_surface(s, {.depth = -1, .tolerance = 1e-12}), InvalidInput);
  CHECK_THROWS_AS(verify::check_surface(s, {.depth = 31, .tolerance = 1e-12}), InvalidInput);
  CHECK_THROWS_WITH(verify::check_surface(s, {.depth = 12, .tolerance = 1e-12}),
                    Catch::Contains("lower the depth"));
  // The largest depth gives the figure (2^30 leaves overflowed a long long: "-9223372036854775808").
  CHECK_THROWS_WITH(verify::check_surface(s, {.depth = 30}), Catch::Contains("needs references of ") &&
                                                                 !Catch::Contains("-9") &&
                                                                 Catch::Contains("e+"));
  CHECK_THROWS_AS(verify::check_surface(s, {.depth = 2, .tolerance = 0}), InvalidInput);
}

TEST_CASE("check measures deviations near the largest doubles without overflow", "[verify][reliability]") {
  // Coordinates near ±1.7e308 agree to 16 digits, deviations ~1e292: their squares overflowed in
  // norm() and check reported inf and FAIL for a shape eval, attractor and insert handle (issue 33).
  cifs::Points P(5, 2);
  P << -1.7e308, 0, -1e308, 1.7e308, 0, -1.7e308, 1e308, 1.7e308, 1.7e308, 0;
  const cifs::nurbs::Curve c = cifs::nurbs::make_curve(3, {0, 0, 0, 0, 1, 2, 2, 2, 2}, P);
  const cifs::verify::CheckReport r = cifs::verify::check_curve(c, {.depth = 4, .tolerance = 1e-12});
  CHECK(r.pass);
  CHECK(std::isfinite(r.nets.max_abs));
  CHECK(r.nets.max_rel < 1e-14);
  CHECK(r.points.max_rel < 1e-14);
}

TEST_CASE("check names a depth finer than a subnormal knot interval holds", "[verify][reliability]") {
  // Knots [0, 0, 1e-320, 1e-320]: the 2^8 dyadic knots of one interval coincided, and check said
  // "knot … would reach multiplicity 2 > degree 1", as if the shape were at fault (issue 33).
  const cifs::nurbs::Curve c =
      cifs::nurbs::make_curve(1, {0, 0, 1e-320, 1e-320}, (cifs::Points(2, 1) << 0, 2).finished());
  CHECK_THROWS_WITH(
      cifs::verify::check_curve(c, {.depth = 8, .tolerance = 1e-12}),
      Catch::Contains("the check depth 8 splits a knot interval of length 9.99989e-321 into 256 "
                      "pieces, more than the doubles it holds; lower the depth"));
}
