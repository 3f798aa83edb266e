// SPDX-License-Identifier: MIT
// Operations on surfaces' nets (knot removal, degree elevation and reduction, Bézier patches, reversal,
// u–v exchange, reparametrisation), degree reduction of curves and surface curvature: against the
// long-double reference evaluation, exact rationals, closed forms and curve routes.
#include <Eigen/Geometry>
#include <boost/multiprecision/cpp_int.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <tuple>

#include "cifs/errors.hpp"
#include "cifs/nurbs/measure.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/surface.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

using Rational = boost::multiprecision::cpp_rational;

/// Random parameters of one direction of r's domain, both ends and the domain's knots included.
std::vector<double> params(Rng& rng, const RandomSurface& r, int dir, int count) {
  const auto& t = r.knots[static_cast<std::size_t>(dir)];
  const int d = r.degree[static_cast<std::size_t>(dir)];
  const double lo = t[static_cast<std::size_t>(d)],
               hi = t[static_cast<std::size_t>(r.count[static_cast<std::size_t>(dir)])];
  std::vector<double> out{lo, hi};
  for (double x : t)
    if (x > lo && x < hi) out.push_back(x);
  for (int i = 0; i < count; ++i) out.push_back(uniform(rng, lo, hi));
  return out;
}

/// The largest distance between f(u, v) and r's reference point over a grid of r's parameters, less
/// `slack`·|∂S/∂t| in direction `dir` (a parameter that rounds moves the point by that).
template <class F>
double worst_against_reference(Rng& rng, const RandomSurface& r, F&& f, int count = 6, int dir = 0,
                               double slack = 0) {
  double worst = 0;
  for (double u : params(rng, r, 0, count))
    for (double v : params(rng, r, 1, count)) {
      const double moved = slack > 0 ? slack * derivatives(r.s, u, v, 1).row(dir == 0 ? 2 : 1).norm() : 0.0;
      worst = std::max(worst, diff(f(u, v), ref_surface_derivatives(r, u, v, 0).row(0)) - moved);
    }
  return worst;
}

/// A surface of revolution about z: the 9-point rational circle (u) times a rational profile in the
/// (radius, z) plane (v).
Surface revolution(const Points& profile, const Eigen::VectorXd& pw, const Knots& tv) {
  const double h = std::sqrt(0.5);
  Points c(9, 2);
  c << 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0;
  Eigen::VectorXd cw(9);
  cw << 1, h, 1, h, 1, h, 1, h, 1;
  const Eigen::Index m = profile.rows();
  Points P(9 * m, 3);
  Eigen::VectorXd w(9 * m);
  for (Eigen::Index i = 0; i < 9; ++i)
    for (Eigen::Index j = 0; j < m; ++j) {
      P.row(i * m + j) << profile(j, 0) * c(i, 0), profile(j, 0) * c(i, 1), profile(j, 1);
      w(i * m + j) = cw(i) * pw(j);
    }
  const int q = static_cast<int>(tv.size() - static_cast<std::size_t>(m)) - 1;
  return make_surface({2, q}, {Knots{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}, tv}, {9, m}, P, w);
}

/// The circle of radius r about (cx, cz) in the profile plane: 9 points, the full turn.
Surface torus(double R, double r) {
  const double h = std::sqrt(0.5);
  Points prof(9, 2);
  prof << R + r, 0, R + r, r, R, r, R - r, r, R - r, 0, R - r, -r, R, -r, R + r, -r, R + r, 0;
  Eigen::VectorXd pw(9);
  pw << 1, h, 1, h, 1, h, 1, h, 1;
  return revolution(prof, pw, Knots{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1});
}

Surface sphere(double r) {
  const double h = std::sqrt(0.5);
  Points prof(5, 2);  // the half circle from the south pole to the north pole
  prof << 0, -r, r, -r, r, 0, r, r, 0, r;
  return revolution(prof, Eigen::Vector<double, 5>(1, h, 1, h, 1), Knots{0, 0, 0, 0.5, 0.5, 1, 1, 1});
}

Surface cylinder(double r) {
  Points prof(2, 2);
  prof << r, -1, r, 1;
  return revolution(prof, Eigen::Vector2d(1, 1), Knots{0, 0, 1, 1});
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Net operations.

TEST_CASE("surface reverse, swap_uv, reparametrize and normalize_knots keep the surface",
          "[nurbs][surface][ops]") {
  for (int seed = 0; seed < 120; ++seed) {
    Rng rng(9100 + seed);
    const RandomSurface r = random_surface(rng);
    INFO("seed " << seed << ": " << r.what);
    const double tol = 1e-12 * r.scale;
    for (int dir = 0; dir < 2; ++dir) {
      const auto D = static_cast<Direction>(dir);
      const Domain dom = domain(r.s, D);
      const Surface back = reverse(r.s, D);
      CHECK_NOTHROW(validate(back));
      CHECK(domain(back, D).start == dom.start);
      CHECK(domain(back, D).end == dom.end);
      CHECK(reverse(back, D).P == r.s.P);  // twice: the same net
      const auto mirror = [&](double x) {
        return x == dom.start ? dom.end : x == dom.end ? dom.start : dom.start + dom.end - x;
      };
      // a + b − u rounds: the parameter moves by up to an ulp of |a| + |b|.
      const double ulps = 4 * kEps * (std::abs(dom.start) + std::abs(dom.end));
      CHECK(worst_against_reference(
                rng, r,
                [&](double u, double v) {
                  return dir == 0 ? evaluate(back, mirror(u), v) : evaluate(back, u, mirror(v));
                },
                6, dir, ulps) <= tol);
      const double a = uniform(rng, -5, 5), b = a + std::exp(uniform(rng, -3, 3));
      const Surface moved = reparametrize(r.s, D, a, b);
      CHECK(domain(moved, D).start == a);
      CHECK(domain(moved, D).end == b);
      CHECK(moved.P == r.s.P);
      const auto map = [&](double x) {
        return x == dom.end ? b : a + (x - dom.start) * ((b - a) / (dom.end - dom.start));
      };
      // The mapped knots and parameters round: a few ulps of both domains, in the old units.
      const double map_ulps = 8 * kEps *
                              (std::abs(dom.start) + std::abs(dom.end) +
                               (std::abs(a) + std::abs(b)) * (dom.end - dom.start) / (b - a));
      CHECK(worst_against_reference(
                rng, r,
                [&](double u, double v) {
                  return dir == 0 ? evaluate(moved, map(u), v) : evaluate(moved, u, map(v));
                },
                6, dir, map_ulps) <= tol);
    }
    const Surface swapped = swap_uv(r.s);
    CHECK_NOTHROW(validate(swapped));
    CHECK(swap_uv(swapped).P == r.s.P);
    CHECK(worst_against_reference(rng, r, [&](double u, double v) { return evaluate(swapped, v, u); }) <=
          tol);
    const Surface unit = normalize_knots(r.s);
    for (const Direction D : {Direction::u, Direction::v}) {
      CHECK(domain(unit, D).start == 0.0);
      CHECK(domain(unit, D).end == 1.0);
    }
  }
}

TEST_CASE("reparametrize by a power of two is exact; curves too, closed ones included",
          "[nurbs][surface][ops]") {
  const Surface s = make_surface({2, 1}, {Knots{0, 0, 0, 1, 3, 4, 4, 4}, Knots{-2, -2, 2, 2}}, {5, 2},
                                 Points::Random(10, 3));
  const Surface t = normalize_knots(s);
  CHECK(t.knots[0] == Knots{0, 0, 0, 0.25, 0.75, 1, 1, 1});
  CHECK(t.knots[1] == Knots{0, 0, 1, 1});
  CHECK(t.P == s.P);
  for (int seed = 0; seed < 200; ++seed) {
    Rng rng(9300 + seed);
    const auto kind = static_cast<Kind>(seed % 3);
    const RandomCurve r = random_curve(rng, uniform_int(rng, 1, 6), uniform_int(rng, 1, 3), coin(rng), kind);
    INFO("seed " << seed << ": " << r.what);
    const Curve c = normalize_knots(r.c);
    CHECK(domain(c).start == 0.0);
    CHECK(domain(c).end == 1.0);
    CHECK(c.closed == r.c.closed);
    CHECK(c.P == r.c.P);
    double worst = 0;
    for (int i = 0; i < 40; ++i) {
      const double u = uniform(rng, r.lo, r.hi);
      const double ulps = 8 * kEps * (std::abs(r.lo) + std::abs(r.hi) + (r.hi - r.lo));
      worst = std::max(worst, diff(evaluate(c, (u - r.lo) / (r.hi - r.lo)), ref_point(r, u)) -
                                  ulps * derivatives(r.c, u, 1).row(1).norm());
    }
    CHECK(worst <= 1e-12 * r.scale);  // beyond the parameter's rounding times |C'|, as above
  }
}

TEST_CASE("surface knot removal: insertion round trip, every line bounded, proven bound",
          "[nurbs][surface][ops]") {
  for (int seed = 0; seed < 150; ++seed) {
    Rng rng(9500 + seed);
    const RandomSurface r = random_surface(rng);
    INFO("seed " << seed << ": " << r.what);
    for (int dir = 0; dir < 2; ++dir) {
      const auto D = static_cast<Direction>(dir);
      const auto& t = r.knots[static_cast<std::size_t>(dir)];
      const int d = r.degree[static_cast<std::size_t>(dir)];
      const Domain dom = domain(r.s, D);
      double x = uniform(rng, dom.start, dom.end);
      if (std::count(t.begin(), t.end(), x) > 0) continue;
      const int times = uniform_int(rng, 1, d);
      const Surface up = insert_knot(r.s, D, x, times);
      // Tolerance: round-off of the homogeneous points, seen through the smallest weight.
      const double tol = 1e-9 * r.scale * (r.rational ? r.w.maxCoeff() / r.w.minCoeff() : 1.0);
      const SurfaceRemoval back = remove_knot(up, D, x, times, tol);
      INFO("direction " << dir << " knot " << x << " times " << times);
      CHECK(back.removed == times);
      CHECK(back.surface.knots == r.s.knots);
      CHECK(back.surface.count == r.s.count);
      CHECK(diff(back.surface.P, r.s.P) <= 1e-12 * max_abs(r.s.P));
      CHECK(back.deviation_bound <= tol);
      // A knot of the surface: what goes within a tolerance, and the bound against samples.
      std::vector<double> inner;
      for (double k : t)
        if (k > dom.start && k < dom.end) inner.push_back(k);
      if (inner.empty()) continue;
      x = inner[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(inner.size()) - 1))];
      const double tolerance = std::exp(uniform(rng, -8, 0)) * r.scale;
      const SurfaceRemoval rm = remove_knot(r.s, D, x, d, tolerance);
      CHECK(rm.deviation_bound <= tolerance);
      CHECK_NOTHROW(validate(rm.surface));
      const double sampled = worst_against_reference(
          rng, r, [&](double u, double v) { return evaluate(rm.surface, u, v); }, 10);
      CHECK(sampled <= rm.deviation_bound + 1e-12 * r.scale);
      // Each line alone as a curve: the surface removes no more copies than the line that keeps most.
      if (!r.rational) {
        const Eigen::Index nu = r.count[0], nv = r.count[1], lines = dir == 0 ? nv : nu,
                           n = dir == 0 ? nu : nv;
        int least = d;
        for (Eigen::Index l = 0; l < lines; ++l) {
          Points L(n, r.H.cols());
          for (Eigen::Index i = 0; i < n; ++i)
            L.row(i) = dir == 0 ? r.H.row(i * nv + l) : r.H.row(l * nv + i);
          least = std::min(least, remove_knot(make_curve(d, t, L), x, d, tolerance).removed);
        }
        CHECK(rm.removed <= least);
      }
    }
  }
}

TEST_CASE("surface degree elevation keeps the surface; Bézier patches elevate as the exact formula",
          "[nurbs][surface][ops]") {
  for (int seed = 0; seed < 120; ++seed) {
    Rng rng(9700 + seed);
    const RandomSurface r = random_surface(rng, 4);
    INFO("seed " << seed << ": " << r.what);
    for (int dir = 0; dir < 2; ++dir) {
      const auto D = static_cast<Direction>(dir);
      const int times = uniform_int(rng, 1, 2);
      const Surface e = elevate_degree(r.s, D, times);
      CHECK_NOTHROW(validate(e));
      CHECK(e.degree[static_cast<std::size_t>(dir)] == r.degree[static_cast<std::size_t>(dir)] + times);
      CHECK(e.knots[static_cast<std::size_t>(1 - dir)] == r.knots[static_cast<std::size_t>(1 - dir)]);
      CHECK(worst_against_reference(rng, r, [&](double u, double v) { return evaluate(e, u, v); }) <=
            1e-12 * r.scale);
    }
  }
  // A biquadratic Bézier patch of integers elevated in v: Q_j = (j/3)·P_{j−1} + (1 − j/3)·P_j, exactly.
  Points P(9, 2);
  Eigen::VectorXd w(9);
  for (int k = 0; k < 9; ++k) {
    P.row(k) << (k * 7) % 5 - 2, (k * k) % 7 - 3;
    w(k) = 1 + k % 3;
  }
  const Surface s = make_surface({2, 2}, {Knots{0, 0, 0, 1, 1, 1}, Knots{0, 0, 0, 1, 1, 1}}, {3, 3}, P, w);
  const Surface e = elevate_degree(s, Direction::v);
  REQUIRE(e.count == std::array<Eigen::Index, 2>{3, 4});
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k) {
        const Rational a(j, 3);
        const auto H = [&](int jj) {
          return Rational(k < 2 ? P(i * 3 + jj, k) * w(i * 3 + jj) : w(i * 3 + jj));
        };
        const Rational exact = (j > 0 ? a * H(j - 1) : Rational(0)) + (j < 3 ? (1 - a) * H(j) : Rational(0));
        worst = std::max(worst, std::abs(e.P(i * 4 + j, k) - static_cast<double>(exact)));
      }
  CHECK(worst <= 4 * kEps * 3);
}

TEST_CASE("surface Bézier patches: one per pair of spans, clamped, equal to the surface there",
          "[nurbs][surface][ops]") {
  for (int seed = 0; seed < 100; ++seed) {
    Rng rng(9900 + seed);
    const RandomSurface r = random_surface(rng, 4);
    INFO("seed " << seed << ": " << r.what);
    const auto spans = [&](int dir) {
      std::vector<double> b;
      for (double x : params(rng, r, dir, 0))
        if (std::find(b.begin(), b.end(), x) == b.end()) b.push_back(x);
      std::sort(b.begin(), b.end());
      return b;
    };
    const std::vector<double> bu = spans(0), bv = spans(1);
    const std::vector<Surface> patches = split_bezier(r.s);
    REQUIRE(patches.size() == (bu.size() - 1) * (bv.size() - 1));
    double worst = 0;
    for (std::size_t a = 0; a + 1 < bu.size(); ++a)
      for (std::size_t b = 0; b + 1 < bv.size(); ++b) {
        const Surface& patch = patches[a * (bv.size() - 1) + b];
        CHECK(patch.count == std::array<Eigen::Index, 2>{r.degree[0] + 1, r.degree[1] + 1});
        CHECK(patch.knots[0].front() == bu[a]);
        CHECK(patch.knots[0].back() == bu[a + 1]);
        CHECK(patch.knots[1].front() == bv[b]);
        CHECK(patch.knots[1].back() == bv[b + 1]);
        for (int i = 0; i < 4; ++i) {
          const double u = uniform(rng, bu[a], bu[a + 1]), v = uniform(rng, bv[b], bv[b + 1]);
          worst = std::max(worst, diff(evaluate(patch, u, v), ref_surface_derivatives(r, u, v, 0).row(0)));
        }
      }
    CHECK(worst <= 1e-12 * r.scale);
  }
}

TEST_CASE("surface operations refuse bad arguments in one line, naming the direction",
          "[nurbs][surface][ops]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Surface s =
      make_surface({1, 2}, {Knots{0, 0, 0.5, 1, 1}, Knots{0, 0, 0, 2, 2, 2}}, {3, 3}, Points::Random(9, 3));
  const auto bad = static_cast<Direction>(2);
  for (const auto& call : std::vector<std::function<void()>>{
           [&] { reverse(s, bad); }, [&] { elevate_degree(s, bad); }, [&] { remove_knot(s, bad, 0.5, 1, 0); },
           [&] { reparametrize(s, bad, 0, 1); }, [&] { reduce_degree(s, bad, 1); }})
    CHECK_THROWS_WITH(call(), Contains("direction 2 is neither u (0) nor v (1)"));
  CHECK_THROWS_WITH(remove_knot(s, Direction::u, 0.25, 1, 0),
                    Contains("direction u") && Contains("not a knot"));
  CHECK_THROWS_WITH(remove_knot(s, Direction::v, 2.0, 1, 0),
                    Contains("direction v") && Contains("not interior"));
  CHECK_THROWS_WITH(remove_knot(s, Direction::u, 0.5, -1, 0), Contains("times = -1"));
  CHECK_THROWS_WITH(remove_knot(s, Direction::u, 0.5, 1, nan), Contains("tolerance"));
  CHECK_THROWS_WITH(elevate_degree(s, Direction::v, -1), Contains("direction v") && Contains("negative"));
  CHECK_THROWS_WITH(elevate_degree(s, Direction::u, 64), Contains("direction u") && Contains("exceeds"));
  CHECK_THROWS_WITH(reparametrize(s, Direction::v, 1, 1), Contains("direction v") && Contains("[1, 1]"));
  CHECK_THROWS_WITH(reparametrize(s, Direction::u, 0, nan), Contains("direction u"));
  CHECK_THROWS_WITH(reduce_degree(s, Direction::u, 1), Contains("direction u") && Contains("degree 1"));
  CHECK_THROWS_WITH(reduce_degree(s, Direction::v, -1), Contains("tolerance -1"));
  // Two distinct knots that one double would hold at the new scale.
  const Curve c = make_curve(1, Knots{0, 0, 1e-300, 1, 1}, Points::Random(3, 2));
  CHECK_THROWS_WITH(reparametrize(c, 1, 2), Contains("reparametrize") && Contains("map to one value"));
  CHECK_THROWS_WITH(reparametrize(c, 0, -1), Contains("not an interval"));
}

// ------------------------------------------------------------------------------------------------
// Degree reduction.

TEST_CASE("reduce_degree undoes elevate_degree: the same knots and points", "[nurbs][reduce]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(10100 + seed);
    const auto kind = coin(rng) ? Kind::clamped : Kind::unclamped;
    const RandomCurve r = random_curve(rng, uniform_int(rng, 1, 8), uniform_int(rng, 1, 3), coin(rng), kind);
    INFO("seed " << seed << ": " << r.what);
    const Curve up = elevate_degree(r.c, 1);
    // The bound sees the round-off of homogeneous points through the smallest weight (as remove_knot's),
    // amplified by the route taken (blossoms away from their piece, or removal chains that divide by ½ at
    // each step): up to 2^d.
    const double tol =
        1e-13 * std::ldexp(r.scale, r.degree) * (r.rational ? r.w.maxCoeff() / r.w.minCoeff() : 1.0);
    const Reduction down = reduce_degree(up, tol);
    CHECK(down.deviation_bound <= tol);
    CHECK(down.curve.degree == r.degree);
    CHECK(down.curve.rational == r.rational);
    if (kind == Kind::clamped) {
      CHECK(down.curve.knots == r.knots);
      CHECK(diff(down.curve.P, r.c.P) <= 1e-12 * std::ldexp(max_abs(r.c.P), r.degree));
    }
    double worst = 0;
    for (int i = 0; i < 50; ++i) {
      const double u = uniform(rng, r.lo, r.hi);
      worst = std::max(worst, diff(evaluate(down.curve, u), ref_point(r, u)));
    }
    CHECK(worst <= tol);
  }
}

TEST_CASE("reduce_degree of an elevated Bézier of integers is exact", "[nurbs][reduce]") {
  // The cubic elevated from the quadratic (0,0), (3,6), (6,−3): points 0, (2,4), (4,3), (6,−3) exactly.
  const Curve cubic =
      make_curve(3, Knots{0, 0, 0, 0, 1, 1, 1, 1}, (Points(4, 2) << 0, 0, 2, 4, 4, 3, 6, -3).finished());
  const Reduction r = reduce_degree(cubic, 1e-14);
  CHECK(r.deviation_bound <= 1e-14);
  CHECK(r.curve.P == (Points(3, 2) << 0, 0, 3, 6, 6, -3).finished());
  CHECK(r.curve.knots == Knots{0, 0, 0, 1, 1, 1});
}

TEST_CASE("reduce_degree: the bound holds against samples and is the figure of a refusal",
          "[nurbs][reduce]") {
  int refused = 0;
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(10500 + seed);
    const auto kind = coin(rng) ? Kind::clamped : Kind::unclamped;
    const RandomCurve r =
        random_curve(rng, uniform_int(rng, 2, 7), uniform_int(rng, 1, 3), coin(rng), kind, 5);
    INFO("seed " << seed << ": " << r.what);
    Reduction red;
    try {
      red = reduce_degree(r.c, HUGE_VAL);
    } catch (const InvalidInput& e) {  // a reduced weight ≤ 0: named
      CHECK_THAT(e.what(), Contains("weight"));
      continue;
    }
    CHECK(red.curve.degree == r.degree - 1);
    CHECK_NOTHROW(validate(red.curve));
    double sampled = 0;
    for (int i = 0; i <= 2000; ++i) {
      const double u = i == 2000 ? r.hi : r.lo + (r.hi - r.lo) * i / 2000.0;
      sampled = std::max(sampled, (evaluate(red.curve, u) - ref_point(r, u)).norm());
    }
    CHECK(sampled <= red.deviation_bound * (1 + 1e-12) + 1e-13 * r.scale);
    CHECK(reduce_degree(r.c, red.deviation_bound).deviation_bound == red.deviation_bound);
    if (red.deviation_bound > 0) {
      ++refused;
      CHECK_THROWS_WITH(
          reduce_degree(r.c, 0.5 * red.deviation_bound),
          Contains("reduce_degree: the degree " + std::to_string(r.degree - 1) + " curve is within") &&
              Contains("more than the tolerance"));
    }
  }
  CHECK(refused > 100);
}

TEST_CASE("reduce_degree of surfaces: elevation round trip and the bound against samples",
          "[nurbs][reduce][surface]") {
  for (int seed = 0; seed < 100; ++seed) {
    Rng rng(10900 + seed);
    const RandomSurface r = random_surface(rng, 4);
    INFO("seed " << seed << ": " << r.what);
    for (int dir = 0; dir < 2; ++dir) {
      const auto D = static_cast<Direction>(dir);
      const double tol = 1e-10 * r.scale * (r.rational ? r.w.maxCoeff() / r.w.minCoeff() : 1.0);
      const SurfaceReduction back = reduce_degree(elevate_degree(r.s, D), D, tol);
      CHECK(back.surface.degree == r.s.degree);
      CHECK(worst_against_reference(
                rng, r, [&](double u, double v) { return evaluate(back.surface, u, v); }) <= 1e-10 * r.scale);
      if (r.degree[static_cast<std::size_t>(dir)] < 2) continue;
      SurfaceReduction red;
      try {
        red = reduce_degree(r.s, D, HUGE_VAL);
      } catch (const InvalidInput& e) {
        CHECK_THAT(e.what(), Contains("weight"));
        continue;
      }
      const double sampled = worst_against_reference(
          rng, r, [&](double u, double v) { return evaluate(red.surface, u, v); }, 12);
      CHECK(sampled <= red.deviation_bound * (1 + 1e-12) + 1e-13 * r.scale);
    }
  }
}

TEST_CASE("reduce_degree refuses what it cannot do, in one line", "[nurbs][reduce]") {
  const Curve line = make_curve(1, Knots{0, 0, 1, 1}, Points::Random(2, 2));
  CHECK_THROWS_WITH(reduce_degree(line, 1), Contains("degree 1 cannot be reduced"));
  const Curve quad = make_curve(2, Knots{0, 0, 0, 1, 1, 1}, Points::Random(3, 2));
  CHECK_THROWS_WITH(reduce_degree(quad, -1), Contains("tolerance -1"));
  CHECK_THROWS_WITH(reduce_degree(quad, std::numeric_limits<double>::quiet_NaN()), Contains("tolerance nan"));
  const Curve closed = make_closed_curve(2, Knots{0, 1, 2, 3}, Points::Random(3, 2));
  CHECK_THROWS_WITH(reduce_degree(closed, 1), Contains("closed"));
}

// ------------------------------------------------------------------------------------------------
// Curvature.

TEST_CASE("curvature of rational spheres, cylinders and tori: the closed forms",
          "[nurbs][surface][curvature]") {
  Rng rng(11100);
  for (double r : {1e-3, 0.5, 1.0, 7.0, 1e4}) {
    INFO("radius " << r);
    const Surface sph = sphere(r), cyl = cylinder(r);
    double e_sphere = 0, e_cyl = 0, e_dir = 0;
    for (int i = 0; i < 200; ++i) {
      const double u = uniform(rng, 0, 1), v = uniform(rng, 0.01, 0.99);
      const Curvature k = curvature(sph, u, v);
      const double side = k.normal.dot(k.point.normalized());  // ±1: outwards or inwards
      e_sphere = std::max({e_sphere, std::abs(k.gaussian * r * r - 1), std::abs(k.mean * r + side),
                           std::abs(k.principal[0] * r + side), std::abs(k.principal[1] * r + side)});
      const Curvature c = curvature(cyl, u, v);
      const Eigen::Vector3d radial = Eigen::Vector3d(c.point(0), c.point(1), 0).normalized();
      const double out = c.normal.dot(radial);
      e_cyl = std::max({e_cyl, std::abs(c.gaussian) * r * r, std::abs(c.mean * 2 * r + out),
                        std::abs(std::min(c.principal[0], c.principal[1]) * r + (out > 0 ? 1 : 0)),
                        std::abs(std::max(c.principal[0], c.principal[1]) * r - (out > 0 ? 0 : 1))});
      // The curved direction goes round the axis, the straight one along it; both tangent and orthogonal.
      const Eigen::Vector3d& straight = out > 0 ? c.directions[0] : c.directions[1];
      e_dir = std::max({e_dir, 1 - std::abs(straight.z()), std::abs(c.directions[0].dot(c.directions[1])),
                        std::abs(c.directions[0].dot(c.normal)), std::abs(c.directions[1].norm() - 1)});
    }
    CHECK(e_sphere <= 1e-12);
    CHECK(e_cyl <= 1e-12);
    CHECK(e_dir <= 1e-13);
    // The poles: S_u = 0, the first fundamental form is singular.
    CHECK_THROWS_WITH(
        curvature(sph, 0.3, 0.0),
        Contains("curvature: the first fundamental form is singular at (0.29999999999999999, 0)"));
    CHECK_THROWS_WITH(curvature(sph, 0.3, 1.0), Contains("singular"));
    // normal() refuses them too: S_u there is rounding (a z of 6e-15 for r = 7), not a direction.
    CHECK_THROWS_WITH(normal(sph, 0.3, 0.0), Contains("normal is undefined"));
    CHECK_THROWS_WITH(normal(sph, 0.7, 1.0), Contains("normal is undefined"));
  }
  for (const auto& [R, r] : {std::pair{3.0, 1.0}, std::pair{1.0, 0.25}, std::pair{10.0, 9.5}}) {
    INFO("torus " << R << ", " << r);
    const Surface t = torus(R, r);
    double worst = 0;
    for (int i = 0; i < 300; ++i) {
      const Curvature k = curvature(t, uniform(rng, 0, 1), uniform(rng, 0, 1));
      const double rho = std::hypot(k.point(0), k.point(1)), cosv = (rho - R) / r;
      const Eigen::Vector3d outward =
          (k.point - R * Eigen::Vector3d(k.point(0), k.point(1), 0) / rho).normalized();
      const double side = k.normal.dot(outward);
      // K = cos v / (r (R + r cos v)); the principal curvatures −side/r (the tube) and −side·cos v/ρ.
      const double k_tube = -side / r, k_ring = -side * cosv / rho;
      worst = std::max({worst, std::abs(k.gaussian - cosv / (r * rho)) * r * r,
                        std::abs(k.mean - 0.5 * (k_tube + k_ring)) * r,
                        std::abs(k.principal[0] - std::max(k_tube, k_ring)) * r,
                        std::abs(k.principal[1] - std::min(k_tube, k_ring)) * r});
    }
    CHECK(worst <= 1e-12);
  }
}

TEST_CASE("curvature of z = xy (bilinear): K = −1/(1+x²+y²)², H = −xy/(1+x²+y²)^{3/2}",
          "[nurbs][surface][curvature]") {
  const Surface s = make_surface({1, 1}, {Knots{-1, -1, 1, 1}, Knots{-1, -1, 1, 1}}, {2, 2},
                                 (Points(4, 3) << -1, -1, 1, -1, 1, -1, 1, -1, -1, 1, 1, 1).finished());
  const Curvature o = curvature(s, 0, 0);
  CHECK(o.gaussian == -1);
  CHECK(o.mean == 0);
  CHECK(o.principal == std::array<double, 2>{1, -1});
  CHECK((o.directions[0] - Eigen::Vector3d(1, 1, 0) / std::sqrt(2.0)).norm() <= 4 * kEps);
  CHECK((o.directions[1] - Eigen::Vector3d(-1, 1, 0) / std::sqrt(2.0)).norm() <= 4 * kEps);
  Rng rng(11300);
  double worst = 0;
  for (int i = 0; i < 500; ++i) {
    const double x = uniform(rng, -1, 1), y = uniform(rng, -1, 1), g = 1 + x * x + y * y;
    const Curvature k = curvature(s, x, y);
    worst = std::max({worst, std::abs(k.gaussian + 1 / (g * g)), std::abs(k.mean + x * y / std::pow(g, 1.5)),
                      std::abs(k.principal[0] * k.principal[1] - k.gaussian)});
  }
  CHECK(worst <= 1e-14);
}

TEST_CASE("curvature: the normal curvature of each iso-curve obeys Euler's formula",
          "[nurbs][surface][curvature]") {
  // An independent route: the iso-curves' Frenet frames (curve derivatives) give the normal curvature
  // κ·(N·n) along S_u and S_v, which must be k1 cos²θ + k2 sin²θ, θ the angle to the first direction.
  int checked = 0;
  for (int seed = 0; seed < 200; ++seed) {
    Rng rng(11500 + seed);
    RandomSurface r;
    do r = random_surface(rng, 4);
    while (dimension(r.s) != 3);
    INFO("seed " << seed << ": " << r.what);
    for (int i = 0; i < 5; ++i) {
      const Domain du = domain(r.s, Direction::u), dv = domain(r.s, Direction::v);
      const double u = uniform(rng, du.start, du.end), v = uniform(rng, dv.start, dv.end);
      Curvature k;
      try {
        k = curvature(r.s, u, v);
      } catch (const InvalidInput&) {
        continue;  // a singular point of a random net
      }
      const double scale = std::max(std::abs(k.principal[0]), std::abs(k.principal[1]));
      for (const auto& [dir, t, along] : {std::tuple{Direction::v, v, u}, std::tuple{Direction::u, u, v}}) {
        const Frenet f = frenet_frame(iso_curve(r.s, dir, t), along);
        const double kn =
            f.normal.size() ? f.curvature * Eigen::Vector3d(f.normal.transpose()).dot(k.normal) : 0.0;
        const double c = Eigen::Vector3d(f.tangent.transpose()).dot(k.directions[0]);
        const double euler = k.principal[0] * c * c + k.principal[1] * (1 - c * c);
        CHECK(std::abs(kn - euler) <= 1e-9 * scale);
        ++checked;
      }
    }
  }
  CHECK(checked > 1000);
}

TEST_CASE("curvature refuses a surface that is not 3-D and parameters outside the domain",
          "[nurbs][surface][curvature]") {
  const Surface flat =
      make_surface({1, 1}, {Knots{0, 0, 1, 1}, Knots{0, 0, 1, 1}}, {2, 2}, Points::Random(4, 2));
  CHECK_THROWS_WITH(curvature(flat, 0.5, 0.5), Contains("2-D"));
  const Surface s = cylinder(1);
  CHECK_THROWS_WITH(curvature(s, 1.5, 0.5), Contains("parameter u"));
  CHECK_THROWS_WITH(curvature(s, 0.5, std::numeric_limits<double>::quiet_NaN()), Contains("parameter v"));
  // A collapsed edge: two corners in one point.
  const Surface cone = make_surface({1, 1}, {Knots{0, 0, 1, 1}, Knots{0, 0, 1, 1}}, {2, 2},
                                    (Points(4, 3) << 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 1).finished());
  CHECK_THROWS_WITH(curvature(cone, 0.0, 0.5), Contains("singular"));
  CHECK_NOTHROW(curvature(cone, 0.5, 0.5));
}
