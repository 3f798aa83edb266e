// SPDX-License-Identifier: MIT
// Arc length, Frenet frames, closest points, intersections, bounding boxes and transforms: against
// closed forms (lines, circles as rational quadratics, the parabola, the twisted cubic), and against
// brute force on random curves (Simpson's rule per span on the reference derivatives, dense sampling
// refined by golden-section search, sign changes of dense samples).
#include "cifs/nurbs/measure.hpp"

#include <Eigen/Geometry>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/nurbs/refine.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

constexpr double kPi = std::numbers::pi;

/// The unit circle (radius r, centre (cx, cy)) as 4 rational quadratic quarters, u ∈ [0, 1], C(0) = (cx + r,
/// cy), counter-clockwise: quarter k covers the angles [kπ/2, (k+1)π/2] on u ∈ [k/4, (k+1)/4].
Curve rational_circle(double r = 1, double cx = 0, double cy = 0) {
  Points P(9, 2);
  P << 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0;
  P *= r;
  P.col(0).array() += cx;
  P.col(1).array() += cy;
  const double h = std::sqrt(0.5);
  Eigen::VectorXd w(9);
  w << 1, h, 1, h, 1, h, 1, h, 1;
  return make_curve(2, {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}, P, w);
}

/// A circular arc of angle θ < π as one rational quadratic (weights 1, cos(θ/2), 1), radius r.
Curve arc(double r, double theta) {
  Points P(3, 2);
  P << r, 0, r, r * std::tan(theta / 2), r * std::cos(theta), r * std::sin(theta);
  Eigen::VectorXd w(3);
  w << 1, std::cos(theta / 2), 1;
  return make_curve(2, {0, 0, 0, 1, 1, 1}, P, w);
}

double angle_of(const Point& x) {
  double a = std::atan2(x(1), x(0));
  return a < 0 ? a + 2 * kPi : a;
}

/// Adaptive Simpson per span on |C′| from the reference derivatives (long double Cox–de Boor), to
/// 1e-13 of the span's first estimate: an independent route to the length of a random curve.
double simpson_length(const RandomCurve& r, double a, double b) {
  std::vector<double> cuts{a};
  for (double t : r.knots)
    if (t > a && t < b && t != cuts.back()) cuts.push_back(t);
  cuts.push_back(b);
  double total = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double lo = cuts[k], hi = cuts[k + 1];
    // the span's own piece at its ends: evaluated just inside (the limit is the same)
    const auto speed = [&](double u) {
      const double v = std::clamp(u, lo + 1e-15 * (hi - lo), hi - 1e-15 * (hi - lo));
      return ref_derivatives(r, v, 1).row(1).norm();
    };
    const auto simpson = [&](double x0, double x1, double f0, double fm, double f1) {
      return (x1 - x0) * (f0 + 4 * fm + f1) / 6;
    };
    const auto adapt = [&](const auto& self, double x0, double x1, double f0, double fm, double f1,
                           double whole, double eps, int depth) -> double {
      const double m = 0.5 * (x0 + x1), fl = speed(0.5 * (x0 + m)), fr = speed(0.5 * (m + x1));
      const double left = simpson(x0, m, f0, fl, fm), right = simpson(m, x1, fm, fr, f1);
      if (depth > 40 || std::abs(left + right - whole) <= 15 * eps)
        return left + right + (left + right - whole) / 15;
      return self(self, x0, m, f0, fl, fm, left, eps / 2, depth + 1) +
             self(self, m, x1, fm, fr, f1, right, eps / 2, depth + 1);
    };
    const double f0 = speed(lo), fm = speed(0.5 * (lo + hi)), f1 = speed(hi);
    const double first = simpson(lo, hi, f0, fm, f1);
    total += adapt(adapt, lo, hi, f0, fm, f1, first, 1e-13 * std::max(first, 1e-300), 0);
  }
  return total;
}

/// A random curve of degree 2…5 in 2-D or 3-D: polynomial, or rational with weights in [0.5, 2]
/// (moderate weights keep Simpson's reference accurate).
RandomCurve test_curve(Rng& rng, bool rational, Kind kind) {
  const int d = uniform_int(rng, 2, 5);
  const int dim = uniform_int(rng, 2, 3);
  RandomCurve r = random_curve(rng, d, dim, false, kind, 6, 0);
  if (!rational) return r;
  r.w = Eigen::VectorXd(r.cart.rows());
  for (Eigen::Index i = 0; i < r.w.size(); ++i) r.w(i) = uniform(rng, 0.5, 2);
  r.rational = true;
  if (kind == Kind::closed) {
    r.c = make_closed_curve(d, r.breaks, r.cart, r.w);
    const Points distinct = to_rows(r.cart, r.w);
    r.H.resize(r.cart.rows() + d, distinct.cols());
    for (Eigen::Index i = 0; i < r.H.rows(); ++i) r.H.row(i) = distinct.row(i % r.cart.rows());
  } else {
    r.c = make_curve(d, r.knots, r.cart, r.w);
    r.H = to_rows(r.cart, r.w);
  }
  return r;
}

/// The global minimum distance from q to the curve by brute force: 400 samples per span, then golden-
/// section search around each sample that is a local minimum of the samples.
double brute_distance(const Curve& c, const Point& q) {
  const std::vector<double> bps = breakpoints(c.knots, c.degree);
  std::vector<double> us;
  for (std::size_t k = 0; k + 1 < bps.size(); ++k)
    for (int i = 0; i < 400; ++i) us.push_back(bps[k] + (bps[k + 1] - bps[k]) * i / 400.0);
  us.push_back(bps.back());
  const auto dist = [&](double u) { return (evaluate(c, u) - q).norm(); };
  std::vector<double> ds(us.size());
  for (std::size_t i = 0; i < us.size(); ++i) ds[i] = dist(us[i]);
  double best = *std::min_element(ds.begin(), ds.end());
  for (std::size_t i = 0; i < us.size(); ++i) {
    if ((i > 0 && ds[i - 1] < ds[i]) || (i + 1 < us.size() && ds[i + 1] < ds[i])) continue;
    double lo = us[i > 0 ? i - 1 : i], hi = us[i + 1 < us.size() ? i + 1 : i];
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 100; ++it) {
      const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      (dist(x1) < dist(x2) ? hi : lo) = dist(x1) < dist(x2) ? x2 : x1;
    }
    best = std::min(best, dist(0.5 * (lo + hi)));
  }
  return best;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Arc length.

TEST_CASE("arc_length: closed forms — line, circle arcs, full circle, parabola", "[nurbs][measure][length]") {
  SECTION("a cubic on a line, control points advancing unevenly: the distance between its ends") {
    Points P(4, 3);
    const Eigen::RowVector3d dir(2.0 / 7, 3.0 / 7, 6.0 / 7);
    const double at[] = {0, 0.1, 2.5, 4};
    for (int i = 0; i < 4; ++i) P.row(i) = at[i] * dir + Eigen::RowVector3d(1, -2, 3);
    const Curve c = make_curve(3, {0, 0, 0, 0, 1, 1, 1, 1}, P);
    const Length L = arc_length(c);
    CHECK(std::abs(L.value - 4) <= 1e-14 * 4);
    CHECK(L.error <= 1e-12 * 4);
  }
  SECTION("rational quadratic arcs: r·θ") {
    for (double theta : {0.1, 1.0, 2.0, 3.0})
      for (double r : {1e-3, 1.0, 7.5, 1e4}) {
        const Length L = arc_length(arc(r, theta));
        INFO("r " << r << " theta " << theta);
        CHECK(std::abs(L.value - r * theta) <= 1e-13 * r * theta);
        CHECK(std::abs(L.value - r * theta) <= std::max(L.error, 4e-16 * r * theta));
      }
  }
  SECTION("the full circle 2πr, and half of it between the knots 0.25 and 0.75") {
    const Curve c = rational_circle(3, 1, -2);
    const Length L = arc_length(c);
    CHECK(std::abs(L.value - 6 * kPi) <= 1e-13 * 6 * kPi);
    CHECK(std::abs(arc_length(c, 0.25, 0.75).value - 3 * kPi) <= 1e-13 * 3 * kPi);
    CHECK(arc_length(c, 0.4, 0.4).value == 0);
  }
  SECTION("the parabola (s, s²) on [a, b]: [s√(1+4s²)/2 + asinh(2s)/4]") {
    Points P(3, 2);
    P << 0, 0, 0.5, 0, 1, 1;
    const Curve c = make_curve(2, {0, 0, 0, 1, 1, 1}, P);
    const auto F = [](double s) { return s * std::sqrt(1 + 4 * s * s) / 2 + std::asinh(2 * s) / 4; };
    for (auto [a, b] : {std::pair{0.0, 1.0}, {0.2, 0.7}, {0.0, 1e-3}, {0.999, 1.0}}) {
      const Length L = arc_length(c, a, b);
      INFO(a << " " << b);
      CHECK(std::abs(L.value - (F(b) - F(a))) <= 1e-13 * (F(b) - F(a)));
    }
  }
}

TEST_CASE("arc_length: random curves against Simpson's rule on the reference derivatives",
          "[nurbs][measure][length]") {
  Rng rng(30'2001);
  for (int trial = 0; trial < 24; ++trial) {
    const bool rational = trial % 2 == 1;
    const auto kind = static_cast<Kind>(trial % 3);
    const RandomCurve r = test_curve(rng, rational, kind);
    INFO(r.what);
    const double a = r.lo + (r.hi - r.lo) * uniform(rng, 0, 0.3),
                 b = r.hi - (r.hi - r.lo) * uniform(rng, 0, 0.3);
    const Length L = arc_length(r.c, a, b, 1e-12);
    const double ref = simpson_length(r, a, b);
    CHECK(std::abs(L.value - ref) <= 1e-11 * ref);
    CHECK(L.error <= 1e-12 * L.value * 1.01);
    // additivity at an interior cut
    const double m = 0.5 * (a + b);
    CHECK(std::abs(arc_length(r.c, a, m).value + arc_length(r.c, m, b).value - L.value) <= 1e-12 * L.value);
  }
}

TEST_CASE("arc_length and parameter_at_length refuse bad input in one line", "[nurbs][measure][length]") {
  const Curve c = rational_circle();
  CHECK_THROWS_WITH(arc_length(c, -0.1, 0.5),
                    Contains("start -0.1") && Contains("outside the domain [0, 1]"));
  CHECK_THROWS_WITH(arc_length(c, 0.6, 0.5), Contains("after the end"));
  CHECK_THROWS_WITH(arc_length(c, 0, std::nan("")), Contains("end nan"));
  CHECK_THROWS_WITH(arc_length(c, 0, 1, 0), Contains("tolerance 0 is outside"));
  CHECK_THROWS_WITH(parameter_at_length(c, 7, 0), Contains("beyond the end"));
  CHECK_THROWS_WITH(parameter_at_length(c, -1, 0), Contains("length -1"));
  CHECK_THROWS_WITH(parameter_at_length(c, 1, 2), Contains("start 2"));
}

TEST_CASE("parameter_at_length: the circle's angle, and round trips on random curves",
          "[nurbs][measure][length]") {
  const double r = 2.5;
  const Curve c = rational_circle(r);
  for (double s : {0.0, 0.3, 1.0, kPi * r / 2, 7.0, 2 * kPi * r - 1e-9}) {
    const double u = parameter_at_length(c, s, 0);
    INFO("s " << s << " u " << u);
    CHECK(std::abs(angle_of(evaluate(c, u)) - s / r) <= 1e-12 * 2 * kPi);
  }
  CHECK(parameter_at_length(c, 2 * kPi * r, 0) == 1);
  CHECK(parameter_at_length(c, 0, 0.3) == 0.3);
  Rng rng(30'2002);
  for (int trial = 0; trial < 24; ++trial) {
    const RandomCurve rc = test_curve(rng, trial % 2 == 1, static_cast<Kind>(trial % 3));
    INFO(rc.what);
    const double start = rc.lo + (rc.hi - rc.lo) * uniform(rng, 0, 0.5);
    const double total = arc_length(rc.c, start, rc.hi).value;
    for (double f : {0.0, 0.1, 0.5, 0.9, 1.0}) {
      const double u = parameter_at_length(rc.c, f * total, start);
      CHECK(std::abs(arc_length(rc.c, start, u).value - f * total) <= 1e-11 * total);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Frenet frames.

TEST_CASE("frenet_frame: circles (κ = 1/r), the twisted cubic's κ and τ, lines, stops",
          "[nurbs][measure][frenet]") {
  SECTION("a circle in 2-D turns left at 1/r, its normal points to the centre") {
    const Curve c = rational_circle(4, 1, 2);
    for (double u : {0.0, 0.1, 0.25, 0.6, 0.99, 1.0}) {
      const Frenet f = frenet_frame(c, u);
      CHECK(std::abs(f.curvature - 0.25) <= 1e-14);
      const Point centre = (Point(2) << 1, 2).finished();
      CHECK((f.point + 4 * f.normal - centre).norm() <= 1e-13 * 4);
      CHECK(std::abs(f.tangent.dot(f.normal)) <= 1e-15);
    }
  }
  SECTION("a circle in 3-D: κ = 1/r, τ = 0, binormal the plane's normal") {
    Points P(9, 3);
    const Curve flat = rational_circle(0.5);
    const Eigen::VectorXd w = weights(flat);
    const Points X = cartesian_points(flat);
    P.leftCols(2) = X;
    P.col(2).setConstant(1);
    const Curve c = make_curve(2, flat.knots, P, w);
    for (double u : {0.05, 0.3, 0.7}) {
      const Frenet f = frenet_frame(c, u);
      CHECK(std::abs(f.curvature - 2) <= 1e-13);
      CHECK(std::abs(f.torsion) <= 1e-13);
      CHECK((f.binormal - (Point(3) << 0, 0, 1).finished()).norm() <= 1e-14);
    }
  }
  SECTION("the twisted cubic (u, u², u³): κ = 2√(9u⁴+9u²+1)/(1+4u²+9u⁴)^{3/2}, τ = 3/(9u⁴+9u²+1)") {
    Points P(4, 3);
    P << 0, 0, 0, 1.0 / 3, 0, 0, 2.0 / 3, 1.0 / 3, 0, 1, 1, 1;
    const Curve c = make_curve(3, {0, 0, 0, 0, 1, 1, 1, 1}, P);
    for (double u : {0.0, 0.2, 0.5, 0.8, 1.0}) {
      const Frenet f = frenet_frame(c, u);
      const double a = 9 * u * u * u * u + 9 * u * u + 1, s2 = 1 + 4 * u * u + 9 * u * u * u * u;
      const double kappa = 2 * std::sqrt(a) / std::pow(s2, 1.5), tau = 3 / a;
      INFO("u " << u);
      CHECK(std::abs(f.curvature - kappa) <= 1e-14 * kappa);
      CHECK(std::abs(f.torsion - tau) <= 1e-14 * tau);
      CHECK(std::abs(f.speed - std::sqrt(s2)) <= 1e-15 * std::sqrt(s2));
      CHECK(std::abs(f.normal.dot(f.tangent)) <= 1e-15);
      CHECK(std::abs(f.normal.dot(f.binormal)) <= 1e-15);
    }
  }
  SECTION("a straight 3-D curve has no normal (empty), curvature and torsion 0") {
    Points P(3, 3);
    P << 0, 0, 0, 1, 1, 1, 3, 3, 3;
    const Frenet f = frenet_frame(make_curve(2, {0, 0, 0, 1, 1, 1}, P), 0.3);
    CHECK(f.normal.size() == 0);
    CHECK(f.binormal.size() == 0);
    CHECK(f.curvature == 0);
    CHECK(f.torsion == 0);
    CHECK((f.tangent - Point::Constant(3, 1 / std::sqrt(3.0))).norm() <= 1e-15);
  }
  SECTION("where C′ = 0 the tangent is undefined: refused, naming u; other dimensions refused") {
    Points P(3, 2);
    P << 0, 0, 0, 0, 1, 1;
    CHECK_THROWS_WITH(frenet_frame(make_curve(2, {0, 0, 0, 1, 1, 1}, P), 0),
                      Contains("tangent is undefined at u = 0"));
    Points Q(2, 4);
    Q.setRandom();
    CHECK_THROWS_WITH(frenet_frame(make_curve(1, {0, 0, 1, 1}, Q), 0.5), Contains("4-D"));
    CHECK_THROWS_WITH(frenet_frame(rational_circle(), 1.5), Contains("outside the domain"));
  }
}

// ------------------------------------------------------------------------------------------------
// Closest points.

TEST_CASE("closest_point: exact cases — circle centre, symmetric pairs, inside and outside",
          "[nurbs][measure][closest]") {
  SECTION("the centre of a circle: every parameter, one interval") {
    const Curve c = rational_circle(2, 1, 1);
    const ClosestPoints cp = closest_point(c, (Point(2) << 1, 1).finished());
    CHECK(std::abs(cp.distance - 2) <= 1e-14);
    REQUIRE(cp.intervals.size() == 1);
    CHECK(cp.intervals[0][0] == 0);
    CHECK(cp.intervals[0][1] == 1);
    CHECK(cp.parameters.empty());
  }
  SECTION("a point off the centre: the one circle point on its ray") {
    const Curve c = rational_circle(2);
    for (double angle : {0.0, 0.3, kPi / 2, 2.0, 4.0, 6.0}) {
      for (double radius : {0.5, 1.9, 3.0, 100.0}) {
        const Point q = (Point(2) << radius * std::cos(angle), radius * std::sin(angle)).finished();
        const ClosestPoints cp = closest_point(c, q);
        INFO("angle " << angle << " radius " << radius);
        CHECK(std::abs(cp.distance - std::abs(radius - 2)) <= 1e-13 * 2);
        REQUIRE(!cp.parameters.empty());
        for (Eigen::Index i = 0; i < cp.points.rows(); ++i)
          CHECK((cp.points.row(i) - 2 * q / radius).norm() <= 1e-12);
        // angle 0 is the clamped circle's start and end: both ends of the open curve
        CHECK(cp.parameters.size() == (angle == 0 ? 2U : 1U));
      }
    }
  }
  SECTION("equal distances at both ends of a symmetric cubic, one minimum below it") {
    Points P(4, 2);
    P << -1, 1, -1.0 / 3, -1, 1.0 / 3, -1, 1, 1;
    const Curve c = make_curve(3, {0, 0, 0, 0, 1, 1, 1, 1}, P);
    const ClosestPoints above = closest_point(c, (Point(2) << 0, 5).finished());
    REQUIRE(above.parameters.size() == 2);
    CHECK(above.parameters[0] == 0);
    CHECK(above.parameters[1] == 1);
    CHECK(std::abs(above.distance - std::sqrt(17.0)) <= 1e-14 * 5);
    const ClosestPoints below = closest_point(c, (Point(2) << 0, -5).finished());
    REQUIRE(below.parameters.size() == 1);
    CHECK(std::abs(below.parameters[0] - 0.5) <= 1e-12);
    CHECK(std::abs(below.distance - 4.5) <= 1e-14 * 5);  // C(1/2) = (0, −1/2)
  }
  SECTION("bad input") {
    CHECK_THROWS_WITH(closest_point(rational_circle(), Point::Zero(3)),
                      Contains("3 coordinates, the curve 2"));
    CHECK_THROWS_WITH(closest_point(rational_circle(), (Point(2) << 0, std::nan("")).finished()),
                      Contains("not finite"));
  }
  SECTION("degree 0: no curve make_curve builds (test_curve.cpp), refused when made by hand") {
    // Piecewise constant: its "closest point" would be a jump, not a curve point. Made by hand (Curve is
    // plain data), it is refused as surfaces of degree 0 are, not answered from a layout of p = 0.
    Curve steps;
    steps.degree = 0;
    steps.knots = {0, 1, 2};
    steps.P = Points(2, 2);
    steps.P << 0, 0, 3, 0;
    CHECK_THROWS_WITH(closest_point(steps, (Point(2) << 2.9, 0).finished()), Contains("degree 0"));
  }
}

TEST_CASE("closest_point: random curves against dense sampling refined by golden section",
          "[nurbs][measure][closest]") {
  Rng rng(30'2003);
  for (int trial = 0; trial < 60; ++trial) {
    const RandomCurve r = test_curve(rng, trial % 2 == 1, static_cast<Kind>(trial % 3));
    INFO(r.what);
    const double size = std::max(r.scale, 1e-300);
    Point q = random_points(rng, 1, r.c.P.cols() - (r.rational ? 1 : 0)).row(0) * 1.5;
    const ClosestPoints cp = closest_point(r.c, q);
    const double brute = brute_distance(r.c, q);
    INFO("q " << q << " cifs " << cp.distance << " brute " << brute);
    CHECK(cp.distance <= brute + 1e-12 * size);
    CHECK(cp.distance >= brute - 1e-9 * size);  // brute force is the less accurate of the two
    REQUIRE(cp.parameters.size() + cp.intervals.size() >= 1);
    for (std::size_t i = 0; i < cp.parameters.size(); ++i)
      CHECK(std::abs((evaluate(r.c, cp.parameters[i]) - q).norm() - cp.distance) <= 1e-12 * size);
  }
}

TEST_CASE("closest_point: mirror-symmetric curves and points on the mirror give every minimum in pairs",
          "[nurbs][measure][closest]") {
  Rng rng(30'2008);
  for (int trial = 0; trial < 40; ++trial) {
    // Uniform clamped knots and control points mirrored in x = 0: C(1 − u) = (−x(u), y(u)).
    const int d = uniform_int(rng, 2, 4), n = d + 1 + uniform_int(rng, 0, 6);
    Points P(n, 2);
    for (int i = 0; i < n; ++i) {
      if (i < n - 1 - i) {
        P(i, 0) = uniform(rng, -2, 0.5);
        P(i, 1) = uniform(rng, -1, 1);
      } else if (i == n - 1 - i) {
        P(i, 0) = 0;
        P(i, 1) = uniform(rng, -1, 1);
      } else {
        P(i, 0) = -P(n - 1 - i, 0);
        P(i, 1) = P(n - 1 - i, 1);
      }
    }
    const Curve c = uniform_bspline(P, d, false);
    const Domain dom = domain(c);
    const Point q = (Point(2) << 0, uniform(rng, -3, 3)).finished();
    const ClosestPoints cp = closest_point(c, q);
    INFO("degree " << d << " points\n"
                   << P.format(Eigen::IOFormat(17)) << "\nq " << q.format(Eigen::IOFormat(17)) << " cifs "
                   << cp.distance << " brute " << brute_distance(c, q));
    CHECK(std::abs(cp.distance - brute_distance(c, q)) <= 1e-9 * 2);
    REQUIRE(!cp.parameters.empty());
    for (double u : cp.parameters) {
      const double mirror = dom.start + dom.end - u;
      const bool paired = std::any_of(cp.parameters.begin(), cp.parameters.end(), [&](double v) {
        return std::abs(v - mirror) <= 1e-7 * (dom.end - dom.start);
      });
      CHECK(paired);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Intersections.

TEST_CASE("intersect_plane: line × circle exactly, tangency once, curves in the plane",
          "[nurbs][measure][intersect]") {
  const Curve c = rational_circle();
  SECTION("x = 1/2 meets the unit circle at y = ±√3/2") {
    const PlaneIntersection hit = intersect_plane(c, (Point(2) << 2, 0).finished(), 1);
    REQUIRE(hit.parameters.size() == 2);
    CHECK(hit.intervals.empty());
    const Point a = evaluate(c, hit.parameters[0]), b = evaluate(c, hit.parameters[1]);
    CHECK(std::abs(a(0) - 0.5) <= 1e-15);
    CHECK(std::abs(a(1) - std::sqrt(3.0) / 2) <= 1e-15);
    CHECK(std::abs(b(1) + std::sqrt(3.0) / 2) <= 1e-15);
  }
  SECTION("y = 1 touches it once, at u = 1/4; y = 1 + 1e-6 misses") {
    const PlaneIntersection hit = intersect_plane(c, (Point(2) << 0, 1).finished(), 1);
    REQUIRE(hit.parameters.size() == 1);
    CHECK(std::abs(hit.parameters[0] - 0.25) <= 1e-7);
    CHECK(intersect_plane(c, (Point(2) << 0, 1).finished(), 1 + 1e-6).parameters.empty());
    // a tangency inside a span: the line x·cos a + y·sin a = 1
    const double an = 0.4;
    const PlaneIntersection t = intersect_plane(c, (Point(2) << std::cos(an), std::sin(an)).finished(), 1);
    REQUIRE(t.parameters.size() == 1);
    CHECK(std::abs(angle_of(evaluate(c, t.parameters[0])) - an) <= 1e-7);
  }
  SECTION("a planar 3-D curve lies in its plane: one interval, the domain") {
    Points P(4, 3);
    P << 0, 0, 2, 1, 3, 2, 2, -1, 2, 4, 0, 2;
    const Curve q = make_curve(3, {0, 0, 0, 0, 1, 1, 1, 1}, P);
    const PlaneIntersection hit = intersect_plane(q, (Point(3) << 0, 0, 1).finished(), 2);
    REQUIRE(hit.intervals.size() == 1);
    CHECK(hit.intervals[0] == std::array<double, 2>{0, 1});
    CHECK(hit.parameters.empty());
  }
  SECTION("bad input") {
    CHECK_THROWS_WITH(intersect_plane(c, Point::Zero(2), 1), Contains("normal is zero"));
    CHECK_THROWS_WITH(intersect_plane(c, Point::Ones(3), 1), Contains("3 coordinates, the curve 2"));
  }
}

TEST_CASE("intersect_plane: a root at a piece's end does not hide the root next to it",
          "[nurbs][measure][intersect]") {
  // y = s(s − 0.3) on a parabola: h = y is 0 at s = 0 exactly, and convex; its second root is 0.3.
  Points P(3, 2);
  P << 0, 0, 0.5, -0.15, 1, 0.7;
  const PlaneIntersection hit =
      intersect_plane(make_curve(2, {0, 0, 0, 1, 1, 1}, P), (Point(2) << 0, 1).finished(), 0);
  REQUIRE(hit.parameters.size() == 2);
  CHECK(hit.parameters[0] == 0);
  CHECK(std::abs(hit.parameters[1] - 0.3) <= 1e-15);
}

TEST_CASE("intersect_plane: random curves against sign changes of dense samples",
          "[nurbs][measure][intersect]") {
  Rng rng(30'2004);
  for (int trial = 0; trial < 60; ++trial) {
    const RandomCurve r = test_curve(rng, trial % 2 == 1, static_cast<Kind>(trial % 3));
    INFO(r.what);
    const int dim = static_cast<int>(r.cart.cols());
    const Point normal = random_points(rng, 1, dim).row(0);
    const double offset = (evaluate(r.c, uniform(rng, r.lo, r.hi)) * normal.transpose())(0);
    const PlaneIntersection hit = intersect_plane(r.c, normal, offset);
    // every root is on the plane
    for (double u : hit.parameters)
      CHECK(std::abs((evaluate(r.c, u) * normal.transpose())(0) - offset) <= 1e-11 * r.scale * normal.norm());
    // every sign change of 20000 samples brackets a root found
    const std::vector<double> us = uniform_parameters(domain(r.c), 20001);
    const Points X = evaluate(r.c, us);
    int changes = 0;
    for (std::size_t i = 0; i + 1 < us.size(); ++i) {
      const double f0 = (X.row(static_cast<Eigen::Index>(i)) * normal.transpose())(0) - offset;
      const double f1 = (X.row(static_cast<Eigen::Index>(i) + 1) * normal.transpose())(0) - offset;
      if ((f0 < 0) == (f1 < 0)) continue;
      ++changes;
      const bool found = std::any_of(hit.parameters.begin(), hit.parameters.end(),
                                     [&](double u) { return u >= us[i] && u <= us[i + 1]; });
      CHECK(found);
    }
    CHECK(static_cast<int>(hit.parameters.size()) >= changes);
  }
}

TEST_CASE("intersect_curves: line × circle, tangency once, random curves against polylines",
          "[nurbs][measure][intersect]") {
  const Curve c = rational_circle();
  SECTION("y = 1/2 crosses at x = ±√3/2; y = 1 touches once") {
    Points L(2, 2);
    L << -2, 0.5, 2, 0.5;
    const auto hits = intersect_curves(make_curve(1, {0, 0, 1, 1}, L), c);
    REQUIRE(hits.size() == 2);
    CHECK(std::abs(hits[0].point(0) + std::sqrt(3.0) / 2) <= 1e-14);
    CHECK(std::abs(hits[1].point(0) - std::sqrt(3.0) / 2) <= 1e-14);
    CHECK(std::abs(hits[0].point(1) - 0.5) <= 1e-14);
    L << -2, 1, 2, 1;
    const auto touch = intersect_curves(make_curve(1, {0, 0, 1, 1}, L), c);
    REQUIRE(touch.size() == 1);
    CHECK(std::abs(touch[0].point(0)) <= 1e-4);
  }
  SECTION("random 2-D curves: every crossing of their dense polylines is found") {
    Rng rng(30'2005);
    for (int trial = 0; trial < 20; ++trial) {
      RandomCurve a = random_curve(rng, uniform_int(rng, 1, 4), 2, coin(rng), Kind::clamped, 5, 0);
      RandomCurve b = random_curve(rng, uniform_int(rng, 1, 4), 2, false, Kind::clamped, 5, 0);
      INFO(a.what << " × " << b.what);
      const auto hits = intersect_curves(a.c, b.c);
      const double size = std::max(a.scale, b.scale);
      for (const auto& h : hits) CHECK((evaluate(a.c, h.u) - evaluate(b.c, h.v)).norm() <= 1e-9 * size * 2);
      const int n = 3000;
      const Points A = evaluate(a.c, uniform_parameters(domain(a.c), n + 1));
      const Points B = evaluate(b.c, uniform_parameters(domain(b.c), n + 1));
      const auto cross2 = [](Eigen::RowVector2d x, Eigen::RowVector2d y) {
        return x(0) * y(1) - x(1) * y(0);
      };
      // Segment pairs only within blocks of 50 whose boxes meet (no crossing is elsewhere): the same
      // test as every pair, 9·10⁶ of them a trial.
      constexpr int kBlock = 50;
      const auto box = [&](const Points& P, int first) {
        return Eigen::AlignedBox2d(P.middleRows(first, kBlock + 1).colwise().minCoeff().transpose(),
                                   P.middleRows(first, kBlock + 1).colwise().maxCoeff().transpose());
      };
      std::vector<std::array<int, 2>> pairs;
      for (int bi = 0; bi < n; bi += kBlock)
        for (int bj = 0; bj < n; bj += kBlock)
          if (box(A, bi).intersects(box(B, bj)))
            for (int i = bi; i < bi + kBlock; ++i)
              for (int j = bj; j < bj + kBlock; ++j) pairs.push_back({i, j});
      for (const auto [i, j] : pairs) {
        const Eigen::RowVector2d p = A.row(i), r = A.row(i + 1) - A.row(i), s0 = B.row(j),
                                 s = B.row(j + 1) - B.row(j);
        const double den = cross2(r, s);
        if (den == 0) continue;
        const double t = cross2(s0 - p, s) / den, v = cross2(s0 - p, r) / den;
        if (t < 0 || t > 1 || v < 0 || v > 1) continue;
        const Eigen::RowVector2d x = p + t * r;
        const bool found = std::any_of(hits.begin(), hits.end(), [&](const CurveIntersection& h) {
          return (h.point - x).norm() <= 1e-3 * size;
        });
        CHECK(found);
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Bounding boxes and transforms.

TEST_CASE("bounding_box: the circle's square, random curves against dense samples", "[nurbs][measure][box]") {
  const Box box = bounding_box(rational_circle(2, 1, -1));
  CHECK((box.lower - (Point(2) << -1, -3).finished()).norm() <= 1e-15);
  CHECK((box.upper - (Point(2) << 3, 1).finished()).norm() <= 1e-15);
  Rng rng(30'2006);
  for (int trial = 0; trial < 40; ++trial) {
    const RandomCurve r = test_curve(rng, trial % 2 == 1, static_cast<Kind>(trial % 3));
    INFO(r.what);
    const Box b = bounding_box(r.c);
    std::vector<double> us = uniform_parameters(domain(r.c), 200001);
    for (double t : breakpoints(r.c.knots, r.c.degree)) us.push_back(t);  // the corners of C0 curves
    const Points X = evaluate(r.c, us);
    const Point lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
    CHECK((lo - b.lower).maxCoeff() <= 1e-7 * r.scale);  // samples miss the extremes by O(h²)
    CHECK((b.upper - hi).maxCoeff() <= 1e-7 * r.scale);
    CHECK((b.lower - lo).maxCoeff() <= 1e-14 * r.scale);  // the box holds every sample
    CHECK((hi - b.upper).maxCoeff() <= 1e-14 * r.scale);
  }
}

TEST_CASE("transform: affine and projective maps of points, refusals", "[nurbs][measure][transform]") {
  Rng rng(30'2007);
  for (int trial = 0; trial < 20; ++trial) {
    const RandomCurve r = test_curve(rng, trial % 2 == 1, static_cast<Kind>(trial % 3));
    const int d = static_cast<int>(r.cart.cols());
    INFO(r.what);
    Eigen::MatrixXd M = Eigen::MatrixXd::Identity(d + 1, d + 1);
    M.topRows(d) = Eigen::MatrixXd::Random(d, d + 1);
    const bool projective = trial % 4 == 3;
    if (projective) M.row(d).head(d) = 0.1 * Eigen::RowVectorXd::Random(d) / std::max(r.scale, 1.0);
    const Curve t = transform(r.c, M);
    CHECK(t.rational == (r.rational || projective));
    for (double u : uniform_parameters(domain(r.c), 17)) {
      Eigen::VectorXd h(d + 1);
      h.head(d) = evaluate(r.c, u).transpose();
      h(d) = 1;
      const Eigen::VectorXd g = M * h;
      const Eigen::VectorXd expected = g.head(d) / g(d);
      CHECK((evaluate(t, u).transpose() - expected).norm() <= 1e-12 * std::max(1.0, expected.norm()) * 10);
    }
  }
  const Curve c = rational_circle();
  CHECK_THROWS_WITH(transform(c, Eigen::MatrixXd::Identity(4, 4)), Contains("takes a 3×3 matrix, got 4×4"));
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  M(2, 0) = 2;  // w' = w(1 + 2x): negative at x = −1
  CHECK_THROWS_WITH(transform(c, M), Contains("gets weight"));
}

// ------------------------------------------------------------------------------------------------
// Surfaces: split and iso-curves.

TEST_CASE("surface split and iso-curves equal the surface, against the reference evaluation",
          "[nurbs][measure][surface]") {
  Rng rng(30'2009);
  for (int trial = 0; trial < 30; ++trial) {
    const RandomSurface r = random_surface(rng);
    INFO(r.what);
    const double tol = 1e-13 * std::max(r.scale, 1e-300);
    const std::array<Domain, 2> dom{domain(r.s, Direction::u), domain(r.s, Direction::v)};
    const auto ref = [&](double u, double v) {
      const auto h = ref_surface_homogeneous(r, u, v, 0, 0);
      Point x(r.cart.cols());
      for (Eigen::Index k = 0; k < x.size(); ++k)
        x(k) = static_cast<double>(r.rational ? h(k) / h(h.size() - 1) : h(k));
      return x;
    };
    for (Direction dir : {Direction::u, Direction::v}) {
      const auto d = static_cast<std::size_t>(dir);
      const double t = dom[d].start + (dom[d].end - dom[d].start) * uniform(rng, 0.05, 0.95);
      const Curve iso = iso_curve(r.s, dir, t);
      const auto [left, right] = split(r.s, dir, t);
      CHECK(domain(left, dir).end == t);
      CHECK(domain(right, dir).start == t);
      for (int k = 0; k < 12; ++k) {
        const double a = dom[d].start + (dom[d].end - dom[d].start) * uniform(rng, 0, 1);
        const double b = dom[1 - d].start + (dom[1 - d].end - dom[1 - d].start) * uniform(rng, 0, 1);
        const double u = dir == Direction::u ? a : b, v = dir == Direction::u ? b : a;
        // the iso-curve at t, at the other parameter b
        const Point on_iso = evaluate(iso, b);
        const Point expected_iso = dir == Direction::u ? ref(t, b) : ref(b, t);
        CHECK((on_iso - expected_iso).norm() <= tol);
        const Surface& part = a <= t ? left : right;
        CHECK((evaluate(part, u, v) - ref(u, v)).norm() <= tol);
      }
    }
  }
  const RandomSurface r = random_surface(rng);
  CHECK_THROWS_WITH(split(r.s, Direction::v, domain(r.s, Direction::v).end), Contains("direction v"));
  CHECK_THROWS_WITH(iso_curve(r.s, Direction::u, 1e9), Contains("iso-curve: u = 1000000000 is outside"));
}
