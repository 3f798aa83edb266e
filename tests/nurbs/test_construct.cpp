// SPDX-License-Identifier: MIT
// Surfaces constructed from curves (make_compatible, ruled, extrude, revolve, loft, sweep): every surface
// point against the long-double reference evaluation of the input curves and closed forms (rotations by
// Rodrigues' formula, the rational arc's angle), and the refusals of bad input.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "cifs/errors.hpp"
#include "cifs/nurbs/construct.hpp"
#include "cifs/nurbs/refine.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

constexpr double kPi = std::numbers::pi;

/// A random open or closed curve of the given dimension, rational with weights in [1/spread, spread]
/// (lofts through curves whose weights differ much get negative weights, which they refuse).
RandomCurve section(Rng& rng, int max_degree, int dim, bool rational, Kind kind, double spread = 4) {
  RandomCurve r = random_curve(rng, uniform_int(rng, 1, max_degree), dim, false, kind, 6);
  if (!rational) return r;
  const Eigen::Index m = r.cart.rows();
  r.w.resize(m);
  for (Eigen::Index i = 0; i < m; ++i) r.w(i) = std::pow(spread, uniform(rng, -1, 1));
  r.rational = true;
  if (kind == Kind::closed) {
    r.c = make_closed_curve(r.degree, r.breaks, r.cart, r.w);
    const Points distinct = to_rows(r.cart, r.w);
    r.H.resize(m + r.degree, distinct.cols());
    for (Eigen::Index i = 0; i < r.H.rows(); ++i) r.H.row(i) = distinct.row(i % m);
  } else {
    r.c = make_curve(r.degree, r.knots, r.cart, r.w);
    r.H = to_rows(r.cart, r.w);
  }
  return r;
}

/// r scaled to points in [−1, 1] and moved by `shift` along the last axis (the sections of a loft).
void restack(RandomCurve& r, double shift) {
  r.cart /= r.scale;
  r.cart.col(r.cart.cols() - 1).array() += shift;
  r.scale = r.cart.cwiseAbs().maxCoeff();
  const Eigen::Index m = r.cart.rows();
  const Points distinct = to_rows(r.cart, r.w);
  r.H.resize(r.kind == Kind::closed ? m + r.degree : m, distinct.cols());
  for (Eigen::Index i = 0; i < r.H.rows(); ++i) r.H.row(i) = distinct.row(i % m);
  r.c = r.kind == Kind::closed ? make_closed_curve(r.degree, r.breaks, r.cart, r.w)
                               : make_curve(r.degree, r.knots, r.cart, r.w);
}

Kind any_kind(Rng& rng) {
  return static_cast<Kind>(uniform_int(rng, 0, 2));
}

/// u of r's domain mapped affinely onto [lo, hi] (as make_compatible maps a curve onto the first's domain).
double mapped(const RandomCurve& r, double u, double lo, double hi) {
  if (r.lo == lo && r.hi == hi) return u;
  return std::clamp(lo + (u - r.lo) * ((hi - lo) / (r.hi - r.lo)), lo, hi);
}

/// The tolerance of a point of r at u, reached on the domain [lo, hi] (r's own, or one it was mapped onto):
/// 1e-14 of the size of the terms, and the move of the point by the rounding of the map (a few ulps of
/// either domain's ends, in r's parameter units).
double point_tolerance(const RandomCurve& r, double u, double lo, double hi) {
  const std::vector<double> m = magnitudes(r, u, 1);
  if (lo == r.lo && hi == r.hi) return 1e-14 * m[0];
  const double own = std::max({std::abs(r.lo), std::abs(r.hi), std::abs(u)}),
               target = std::max(std::abs(lo), std::abs(hi)) * (r.hi - r.lo) / (hi - lo);
  return 1e-14 * m[0] + 8 * kEps * (own + target) * m[1];
}

std::vector<double> samples(Rng& rng, const RandomCurve& r, int count) {
  return probe_parameters(rng, r.knots, r.degree, count);
}

/// The point x turned by theta about the axis through o along the unit vector a (Rodrigues).
Eigen::Vector3d turned(const Eigen::Vector3d& x, const Eigen::Vector3d& o, const Eigen::Vector3d& a,
                       double theta) {
  return o + Eigen::AngleAxisd(theta, a) * (x - o);
}

}  // namespace

TEST_CASE("make_compatible keeps every curve's points on the mapped parameters", "[nurbs][construct]") {
  Rng rng(3001);
  double worst = 0;  // in units of the tolerance
  for (int trial = 0; trial < 60; ++trial) {
    const int dim = uniform_int(rng, 1, 3), count = uniform_int(rng, 1, 4);
    std::vector<RandomCurve> r;
    std::vector<Curve> curves;
    for (int k = 0; k < count; ++k) {
      r.push_back(section(rng, 5, dim, coin(rng, 0.3), any_kind(rng)));
      curves.push_back(r.back().c);
    }
    const std::vector<Curve> out = make_compatible(curves);
    REQUIRE(out.size() == curves.size());
    int degree = 0;
    bool rational = false;
    for (const RandomCurve& c : r) {
      degree = std::max(degree, c.degree);
      rational = rational || c.rational;
    }
    for (std::size_t k = 0; k < out.size(); ++k) {
      INFO(r[k].what);
      CHECK(out[k].degree == degree);
      CHECK(out[k].rational == rational);
      CHECK_FALSE(out[k].closed);
      CHECK(out[k].knots == out[0].knots);
      CHECK(out[k].P.rows() == out[0].P.rows());
      const Domain dom = domain(out[k]);
      CHECK(dom.start == r[0].lo);
      CHECK(dom.end == r[0].hi);
      for (double u : samples(rng, r[k], 20)) {
        const double error = diff(evaluate(out[k], mapped(r[k], u, r[0].lo, r[0].hi)), ref_point(r[k], u));
        const double tol = point_tolerance(r[k], u, r[0].lo, r[0].hi);
        worst = std::max(worst, error / tol);
        CHECK(error <= tol);
      }
    }
  }
  WARN("make_compatible: worst error " << worst << " of the tolerance");
}

TEST_CASE("make_compatible of exact data is exact", "[nurbs][construct]") {
  // A quadratic Bézier on [0, 1] and a line on [0, 2] with a knot at 1: the line mapped onto [0, 1] (×½, a
  // power of two: the knot goes to ½ exactly) and raised (its corner then a double knot: the corner
  // stays, the edges' midpoints join), the quadratic refined at ½ twice (de Casteljau at ½, then the
  // middle point repeated): every control point by hand.
  Points q(3, 2), l(3, 2);
  q << 0, 0, 2, 4, 4, 0;
  l << 0, 1, 2, 1, 4, 3;
  const Curve a = make_curve(2, {0, 0, 0, 1, 1, 1}, q), b = make_curve(1, {0, 0, 1, 2, 2}, l);
  const Curve ab[2] = {a, b};
  const std::vector<Curve> c = make_compatible(ab);
  CHECK(c[0].knots == Knots{0, 0, 0, 0.5, 0.5, 1, 1, 1});
  CHECK(c[1].knots == Knots{0, 0, 0, 0.5, 0.5, 1, 1, 1});
  Points qa(5, 2), lb(5, 2);
  qa << 0, 0, 1, 2, 2, 2, 3, 2, 4, 0;
  lb << 0, 1, 1, 1, 2, 1, 3, 2, 4, 3;
  CHECK(c[0].P == qa);
  CHECK(c[1].P == lb);
}

TEST_CASE("ruled surfaces are linear between the curves", "[nurbs][construct]") {
  Rng rng(3002);
  for (int trial = 0; trial < 40; ++trial) {
    const int dim = uniform_int(rng, 2, 3);
    const RandomCurve a = section(rng, 4, dim, coin(rng, 0.3), any_kind(rng)),
                      b = section(rng, 4, dim, coin(rng, 0.3), any_kind(rng));
    INFO(a.what << " / " << b.what);
    const Surface s = ruled(a.c, b.c);
    CHECK(s.degree[1] == 1);
    CHECK(domain(s, Direction::u).start == a.lo);
    CHECK(domain(s, Direction::u).end == a.hi);
    const double ratio = (b.hi - b.lo) / (a.hi - a.lo);
    for (double u : samples(rng, a, 10))
      CHECK(diff(evaluate(s, u, 0.0), ref_point(a, u)) <= 2 * point_tolerance(a, u, a.lo, a.hi));
    for (double ub : samples(rng, b, 10))
      CHECK(diff(evaluate(s, mapped(b, ub, a.lo, a.hi), 1.0), ref_point(b, ub)) <=
            2 * point_tolerance(b, ub, a.lo, a.hi));
    // In between, on the segment from a(u) to b at u mapped onto b's domain: at v in homogeneous
    // coordinates, (1 − v)·(w_a a, w_a) + v·(w_b b, w_b), the weights 1 for a non-rational curve.
    for (double u : samples(rng, a, 10)) {
      const double ub = std::clamp(b.lo + (u - a.lo) * ratio, b.lo, b.hi);
      const double wa =
          a.rational ? static_cast<double>(ref_homogeneous(ref_knots(a, u), a.degree, a.H)(dim)) : 1.0;
      const double wb =
          b.rational ? static_cast<double>(ref_homogeneous(ref_knots(b, ub), b.degree, b.H)(dim)) : 1.0;
      const double tol = 2 * point_tolerance(a, u, a.lo, a.hi) + 2 * point_tolerance(b, ub, a.lo, a.hi);
      for (double v : {0.25, 0.5, uniform(rng, 0, 1)}) {
        const Point expected =
            ((1 - v) * wa * ref_point(a, u) + v * wb * ref_point(b, ub)) / ((1 - v) * wa + v * wb);
        CHECK(diff(evaluate(s, u, v), expected) <= tol);
      }
    }
  }
}

TEST_CASE("extrusions translate the curve exactly", "[nurbs][construct]") {
  Rng rng(3003);
  for (int trial = 0; trial < 40; ++trial) {
    const int dim = uniform_int(rng, 2, 4);
    const RandomCurve c = section(rng, 5, dim, coin(rng), any_kind(rng));
    INFO(c.what);
    const Point d = random_points(rng, 1, dim).row(0);
    const Surface s = extrude(c.c, d);
    for (double u : samples(rng, c, 10))
      for (double v : {0.0, 1.0, 0.5, uniform(rng, 0, 1)})
        CHECK(diff(evaluate(s, u, v), ref_point(c, u) + v * d) <=
              point_tolerance(c, u, c.lo, c.hi) + 4 * kEps * d.norm());
  }
}

TEST_CASE("surfaces of revolution: every point at its profile point's distance, at the arc's angle",
          "[nurbs][construct]") {
  Rng rng(3004);
  double worst = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const RandomCurve c = section(rng, 4, 3, coin(rng), any_kind(rng));
    INFO(c.what);
    const Eigen::Vector3d o = random_points(rng, 1, 3).row(0).transpose(),
                          a = Eigen::Vector3d::Random().normalized() * std::pow(10.0, uniform(rng, -3, 3));
    const double angles[] = {2 * kPi, kPi / 2, kPi, 3 * kPi / 2, uniform(rng, 1e-3, 2 * kPi), 0.1};
    const double angle = angles[trial % 6];
    const Surface s = revolve(c.c, o, a, angle);
    const Eigen::Vector3d unit = a.normalized();
    const int arcs = static_cast<int>(std::ceil(angle / (kPi / 2) - 1e-12));
    const double phi = angle / arcs;
    // The size of the problem: the farthest control point from the axis point.
    const double size = (c.cart.rowwise() - o.transpose()).rowwise().norm().maxCoeff();
    const Knots& kv = s.knots[1];
    for (double u : samples(rng, c, 8))
      for (int k = 0; k < arcs; ++k)
        for (double t : {0.0, 0.25, 0.5, 1.0, uniform(rng, 0, 1)}) {
          const double v0 = kv[static_cast<std::size_t>(2 * k + 2)],
                       v1 = kv[static_cast<std::size_t>(2 * k + 3)];
          const double v = t == 1.0 ? v1 : v0 + t * (v1 - v0);
          const double local = (v - v0) / (v1 - v0);
          const double theta = k * phi + phi / 2 + 2 * std::atan(std::tan(phi / 4) * (2 * local - 1));
          const Eigen::Vector3d q = ref_point(c, u).transpose(), p = evaluate(s, u, v).transpose();
          const double error = (p - turned(q, o, unit, theta)).norm();
          const double tol = 1e-14 * std::max(size, magnitudes(c, u, 0)[0]) * 4;
          worst = std::max(worst, error / (tol / 4));
          CHECK(error <= tol);
          // The distance to the axis and the axial coordinate (the properties themselves).
          const auto radius = [&](const Eigen::Vector3d& x) {
            return ((x - o) - (x - o).dot(unit) * unit).norm();
          };
          CHECK(std::abs(radius(p) - radius(q)) <= tol);
          CHECK(std::abs((p - q).dot(unit)) <= tol);
        }
    if (angle == 2 * kPi) {  // closed exactly: the last column of the net is the first
      const Eigen::Index m = s.count[1];
      for (Eigen::Index i = 0; i < s.count[0]; ++i) CHECK(s.P.row(i * m) == s.P.row(i * m + m - 1));
    }
  }
  WARN("revolve: worst error " << worst << "e-14 of the size");
}

TEST_CASE("revolve: a quarter cylinder and a full sphere by hand", "[nurbs][construct]") {
  // The segment x = 1, z ∈ [0, 1] turned by π/2 about z: the quarter cylinder, a rational quadratic in v.
  Points seg(2, 3);
  seg << 1, 0, 0, 1, 0, 1;
  const Surface cyl = revolve(make_curve(1, {0, 0, 1, 1}, seg), {0, 0, 0}, {0, 0, 1}, kPi / 2);
  CHECK(cyl.count[1] == 3);
  CHECK(cyl.P(1 * 3 + 1, 3) == std::cos(kPi / 4));  // the middle weight
  const Point mid = evaluate(cyl, 0.5, 0.5);        // at 45°
  CHECK(std::abs(mid(0) - std::sqrt(0.5)) <= 2e-16);
  CHECK(std::abs(mid(1) - std::sqrt(0.5)) <= 2e-16);
  CHECK(mid(2) == 0.5);
  // A half circle in the xz-plane about z: the unit sphere.
  const double h = std::sqrt(0.5);
  Points half(5, 3);
  half << 0, 0, -1, 1, 0, -1, 1, 0, 0, 1, 0, 1, 0, 0, 1;
  Eigen::VectorXd w(5);
  w << 1, h, 1, h, 1;
  const Surface sphere =
      revolve(make_curve(2, {0, 0, 0, 0.5, 0.5, 1, 1, 1}, half, w), {0, 0, 0}, {0, 0, 2}, 2 * kPi);
  for (double u = 0; u <= 1; u += 1.0 / 16)
    for (double v = 0; v <= 1; v += 1.0 / 16) CHECK(std::abs(evaluate(sphere, u, v).norm() - 1) <= 4e-16);
}

TEST_CASE("loft: the iso-curve at each curve's parameter is that curve", "[nurbs][construct]") {
  Rng rng(3005);
  double worst = 0;
  int refused = 0, rational_lofts = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int dim = uniform_int(rng, 2, 3), count = uniform_int(rng, 2, 6);
    const bool rational = coin(rng, 0.4);
    std::vector<RandomCurve> r;
    std::vector<Curve> curves;
    for (int k = 0; k < count; ++k) {
      r.push_back(
          section(rng, 4, dim, rational && coin(rng), coin(rng, 0.8) ? Kind::clamped : any_kind(rng), 1.5));
      restack(r.back(), 2.0 * k);
      curves.push_back(r.back().c);
    }
    LoftOptions o;
    o.degree_v = uniform_int(rng, 1, count - 1);
    o.parametrization = static_cast<Parametrization>(uniform_int(rng, 0, 2));
    Surface s;
    try {
      s = loft(curves, o);
    } catch (const InvalidInput& e) {  // weights that differ too much for one column
      CHECK_THAT(e.what(), Contains("weight") && Contains("not positive"));
      ++refused;
      continue;
    }
    rational_lofts += s.rational ? 1 : 0;
    const std::vector<double> v = loft_parameters(curves, o.parametrization);
    REQUIRE(v.size() == curves.size());
    CHECK(v.front() == 0);
    CHECK(v.back() == 1);
    CHECK(s.degree[1] == o.degree_v);
    for (std::size_t k = 0; k < r.size(); ++k) {
      INFO(r[k].what << " degree_v " << o.degree_v);
      const Curve iso = iso_curve(s, Direction::v, v[k]);
      for (double u : samples(rng, r[k], 10)) {
        const double error = diff(evaluate(iso, mapped(r[k], u, r[0].lo, r[0].hi)), ref_point(r[k], u));
        // Interpolation through the columns: rounding of the size of the whole net at most.
        const double net = max_abs(cartesian_points(s));
        const double tol = 10 * point_tolerance(r[k], u, r[0].lo, r[0].hi) + 1e-13 * net;
        worst = std::max(worst, error / (1e-13 * net + point_tolerance(r[k], u, r[0].lo, r[0].hi)));
        CHECK(error <= tol);
      }
    }
  }
  // Homogeneous interpolation of weights that vary can give a control weight ≤ 0 (refused); most pass.
  CHECK(refused <= 10);
  CHECK(rational_lofts >= 5);
  WARN("loft: worst error " << worst << " of the tolerance; " << refused
                            << " of 40 refused (negative weights), " << rational_lofts << " rational lofts");
}

TEST_CASE("sweep: the translational sweep is C(u) + T(v) − T(v₀)", "[nurbs][construct]") {
  Rng rng(3006);
  for (int trial = 0; trial < 30; ++trial) {
    const int dim = uniform_int(rng, 2, 3);
    const RandomCurve c = section(rng, 4, dim, coin(rng), any_kind(rng)),
                      t = section(rng, 4, dim, coin(rng), any_kind(rng));
    INFO(c.what << " / " << t.what);
    const Sweep sw = sweep(c.c, t.c);
    CHECK(sw.deviation == 0);
    const Point t0 = ref_point(t, t.lo);
    for (double u : samples(rng, c, 6))
      for (double v : samples(rng, t, 6)) {
        const double tol =
            2 * (point_tolerance(c, u, c.lo, c.hi) + point_tolerance(t, v, t.lo, t.hi) + 1e-14 * t0.norm());
        CHECK(diff(evaluate(sw.surface, u, v), ref_point(c, u) + ref_point(t, v) - t0) <= tol);
      }
  }
}

TEST_CASE("sweep along a circle: the skinned instances approach the surface of revolution",
          "[nurbs][construct]") {
  // The trajectory: a rational quarter circle of radius 5 about z (frames of a planar curve keep the
  // plane's normal: the exact sweep turns the profile about z, by the arc's angle at v).
  const double h = std::sqrt(0.5);
  Points arc(3, 3);
  arc << 5, 0, 0, 5, 5, 0, 0, 5, 0;
  Eigen::VectorXd wa(3);
  wa << 1, h, 1;
  const Curve trajectory = make_curve(2, {0, 0, 0, 1, 1, 1}, arc, wa);
  Points prof(4, 3);  // a cubic in the plane normal to the start tangent (the xz-plane) around (5, 0, 0)
  prof << 6, 0, 0, 5, 0, 1, 4, 0, 0.5, 5, 0, -1;
  const Curve profile = make_curve(3, {0, 0, 0, 0, 1, 1, 1, 1}, prof);
  double last = 0;
  for (int instances : {5, 9, 17, 33}) {
    SweepOptions o;
    o.instances = instances;
    const Sweep sw = sweep(profile, trajectory, o);
    // The test's own measure: the exact position turns the profile point about z by the arc's angle
    // 2·atan(tan(π/8)(2v − 1)) + π/4, on a grid finer than the library's.
    double measured = 0;
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 400; ++j) {
        const double u = i / 40.0, v = j / 400.0;
        const double theta = kPi / 4 + 2 * std::atan(std::tan(kPi / 8) * (2 * v - 1));
        const Eigen::Vector3d exact = turned(evaluate(profile, u).transpose(), {0, 0, 0}, {0, 0, 1}, theta);
        measured = std::max(measured, (evaluate(sw.surface, u, v).transpose() - exact).norm());
      }
    INFO("instances " << instances << " reported " << sw.deviation << " measured " << measured);
    CHECK(sw.deviation <= 1.03 * measured);  // the two samples differ: 0.03 % to 0.6 % apart
    CHECK(sw.deviation >= 0.97 * measured);
    if (last > 0) CHECK(sw.deviation < last / 8);  // cubic skinning: about h⁴
    last = sw.deviation;
    WARN("sweep along a quarter circle, " << instances << " instances: deviation " << sw.deviation);
  }
}

TEST_CASE("rotation-minimizing frames do not turn about the tangent", "[nurbs][construct]") {
  Rng rng(3007);
  for (int trial = 0; trial < 10; ++trial) {
    // A smooth trajectory: one cubic Bézier piece whose tangent stays away from zero.
    RandomCurve c;
    c.degree = 3;
    c.knots = {0, 0, 0, 0, 1, 1, 1, 1};
    c.hi = 1;
    for (bool smooth = false; !smooth;) {
      c.cart = random_points(rng, 4, 3);
      c.rational = coin(rng);
      c.w = c.rational ? Eigen::VectorXd(Eigen::Vector4d(1, uniform(rng, 0.5, 2), uniform(rng, 0.5, 2), 1))
                       : Eigen::VectorXd();
      c.H = to_rows(c.cart, c.w);
      c.c = make_curve(3, c.knots, c.cart, c.w);
      smooth = true;
      for (int k = 0; k <= 100; ++k)
        smooth =
            smooth && ref_derivatives(c, k / 100.0, 1).row(1).norm() > 0.1 * c.cart.cwiseAbs().maxCoeff();
    }
    INFO(c.cart << " weights " << c.w.transpose());
    const int count = 401;
    const Points f = rotation_minimizing_frames(c.c, count, 16);
    for (Eigen::Index k = 0; k < count; ++k) {
      const Eigen::Vector3d t = f.row(k).head(3).transpose(), r = f.row(k).tail(3).transpose();
      CHECK(std::abs(t.norm() - 1) <= 1e-14);
      CHECK(std::abs(r.norm() - 1) <= 1e-14);
      CHECK(std::abs(t.dot(r)) <= 1e-14);
      const double u = c.lo + (c.hi - c.lo) * static_cast<double>(k) / (count - 1);
      const Points d = ref_derivatives(c, u, 1);
      CHECK((t - d.row(1).transpose().normalized()).norm() <= 1e-12);
    }
    // dr/ds has no component along t × r (a rotation-minimizing frame turns only about t × ... r's change is
    // along t): central differences, to O(h²).
    double worst = 0, scale = 0;
    for (Eigen::Index k = 1; k + 1 < count; ++k) {
      const Eigen::Vector3d t = f.row(k).head(3).transpose(), r = f.row(k).tail(3).transpose();
      const Eigen::Vector3d dr = f.row(k + 1).tail(3).transpose() - f.row(k - 1).tail(3).transpose();
      worst = std::max(worst, std::abs(dr.dot(t.cross(r))));
      scale = std::max(scale, dr.norm());
    }
    CHECK(worst <= 1e-2 * scale);
  }
  // A planar curve (in a turned plane): the frame's r starts in the plane and stays there.
  Points planar(5, 3);
  planar << 0, 0, 0, 1, 2, 0, 3, -1, 0, 4, 0, 0, 6, 3, 0;
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Curve c = make_curve(3, {0, 0, 0, 0, 0.5, 1, 1, 1, 1}, Points(planar * turn.transpose()));
  const Eigen::Vector3d n = turn.col(2);
  const Points f = rotation_minimizing_frames(c, 101);
  for (Eigen::Index k = 0; k < f.rows(); ++k) CHECK(std::abs(f.row(k).tail(3).dot(n.transpose())) <= 1e-13);
}

TEST_CASE("construction refuses bad input in one line", "[nurbs][construct]") {
  Points seg(2, 3);
  seg << 1, 0, 0, 1, 0, 1;
  const Curve line = make_curve(1, {0, 0, 1, 1}, seg);
  Points flat(2, 2);
  flat << 0, 0, 1, 0;
  const Curve line2 = make_curve(1, {0, 0, 1, 1}, flat);
  const Curve both[2] = {line, line2};
  CHECK_THROWS_WITH(make_compatible(both), Contains("curves[1]: dimension 2"));
  CHECK_THROWS_WITH(make_compatible(std::span<const Curve>()), Contains("curves: none given"));
  CHECK_THROWS_WITH(loft(std::span<const Curve>(&line, 1)), Contains("curves: 1 given"));
  const Curve two[2] = {line, line};
  CHECK_THROWS_WITH(loft(two, {}), Contains("loft: degree_v 3 is outside 1 … 1"));
  CHECK_THROWS_WITH(loft(two, {1, Parametrization::chord_length}),
                    Contains("loft: the curves coincide (every column of control points is one point)"));
  Points up = seg;
  up.col(0).array() += 1;
  const Curve twice[3] = {line, line, make_curve(1, {0, 0, 1, 1}, up)};
  CHECK_THROWS_WITH(loft(twice, {1, Parametrization::centripetal}),
                    Contains("loft: curves[0] and curves[1] coincide (equal compatible control points)"));
  CHECK_THROWS_WITH(extrude(line, Point::Zero(3)), Contains("direction: the zero vector"));
  CHECK_THROWS_WITH(extrude(line, Point::Ones(2)), Contains("direction: 2 coordinates"));
  Point nan = Point::Ones(3);
  nan(1) = std::nan("");
  CHECK_THROWS_WITH(extrude(line, nan), Contains("direction: a coordinate is not finite"));
  CHECK_THROWS_WITH(extrude(line, Point(Eigen::RowVector3d(0, 0, 2))), Contains("parallel"));
  CHECK_NOTHROW(extrude(line, Point(Eigen::RowVector3d(1e-10, 0, 1))));  // tilted by 1e-10: a thin surface
  Points dot(2, 3);
  dot << 1, 2, 3, 1, 2, 3;
  CHECK_THROWS_WITH(extrude(make_curve(1, {0, 0, 1, 1}, dot), Point(Eigen::RowVector3d(0, 0, 1))),
                    Contains("curve: a single point"));
  CHECK_THROWS_WITH(revolve(line, {0, 0, 0}, {0, 0, 0}, 1), Contains("axis_direction: the zero vector"));
  CHECK_THROWS_WITH(revolve(line, {0, 0, 0}, {0, 0, 1}, 0), Contains("angle: 0 is outside (0, 2π]"));
  CHECK_THROWS_WITH(revolve(line, {0, 0, 0}, {0, 0, 1}, 7), Contains("angle: 7 is outside"));
  CHECK_THROWS_WITH(revolve(line, {0, 0, 0}, {0, 0, 1}, std::nan("")), Contains("angle"));
  CHECK_THROWS_WITH(revolve(line, {1, 0, 0}, {0, 0, 1}, 1),
                    Contains("profile: every control point lies on the axis"));
  CHECK_THROWS_WITH(revolve(line2, {0, 0, 0}, {0, 0, 1}, 1), Contains("profile: dimension 2"));
  CHECK_THROWS_WITH(revolve(line, {0, std::nan(""), 0}, {0, 0, 1}, 1), Contains("axis_point"));
  SweepOptions o;
  o.instances = 1;
  CHECK_THROWS_WITH(sweep(line, line, o), Contains("instances: 1"));
  CHECK_THROWS_WITH(sweep(line, line2), Contains("trajectory: dimension 2"));
  o.instances = 3;
  CHECK_THROWS_WITH(sweep(line, line, o), Contains("sweep: degree_v 3 is outside 1 … 2"));
  o.instances = 1 << 30;
  CHECK_THROWS_WITH(sweep(line, line, o), Contains("instances: 1073741824 instances of the profile need") &&
                                              Contains("(half the memory)"));
  o.instances = 3;
  Points point(2, 3);
  point << 1, 1, 1, 1, 1, 1;
  o.degree_v = 2;
  CHECK_THROWS_WITH(sweep(line, make_curve(1, {0, 0, 1, 1}, point), o),
                    Contains("trajectory: the tangent vanishes"));
}
