// SPDX-License-Identifier: MIT
// Curves: evaluation routes, derivatives, blossoms, closed curves, the exact circle, validation.
#include "cifs/nurbs/curve.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numeric>

#include "cifs/errors.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

/// The distinct knot values strictly inside the domain, with their multiplicities.
std::vector<std::pair<double, int>> interior_knots(const RandomCurve& r) {
  std::vector<std::pair<double, int>> out;
  for (double x : r.knots)
    if (x > r.lo && x < r.hi && (out.empty() || out.back().first != x))
      out.emplace_back(x, static_cast<int>(std::count(r.knots.begin(), r.knots.end(), x)));
  return out;
}

Curve unit_circle() {
  const double s = std::sqrt(0.5);
  Points P(9, 2);
  P << 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0;
  Eigen::VectorXd w(9);
  w << 1, s, 1, s, 1, s, 1, s, 1;
  return make_curve(2, {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}, P, w);
}

Curve closed_unit_circle() {
  const double s = std::sqrt(0.5);
  Points P(8, 2);
  P << 1, -1, 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1;
  Eigen::VectorXd w(8);
  w << s, 1, s, 1, s, 1, s, 1;
  return make_closed_curve(2, {0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1}, P, w);
}

}  // namespace

TEST_CASE("curves store the data they are given", "[nurbs][curve]") {
  for (int seed = 0; seed < 200; ++seed) {
    Rng rng(seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const Curve& c = r.c;
    CHECK(c.knots == r.knots);
    CHECK(c.P == r.H);
    CHECK(c.rational == r.rational);
    CHECK(c.closed == (r.kind == Kind::closed));
    CHECK(dimension(c) == r.cart.cols());
    CHECK(distinct_count(c) == r.cart.rows());
    CHECK(defining_knots(c) == (r.kind == Kind::closed ? r.breaks : r.knots));
    CHECK(diff(cartesian_points(c), r.cart) <= 4 * kEps * r.scale);
    const Eigen::VectorXd w = r.rational ? r.w : Eigen::VectorXd::Ones(r.cart.rows()).eval();
    CHECK(weights(c) == w);
    CHECK(domain(c).start == r.lo);
    CHECK(domain(c).end == r.hi);
    std::vector<double> b;
    for (double x : r.knots)
      if (x >= r.lo && x <= r.hi && (b.empty() || b.back() != x)) b.push_back(x);
    CHECK(segment_count(c) == static_cast<int>(b.size()) - 1);
    CHECK_NOTHROW(validate(c));
    const Point row = c.P.row(0);
    const Point cart = to_cartesian(c, row);
    CHECK(diff(cart, r.cart.row(0)) <= 4 * kEps * r.scale);
  }
}

TEST_CASE("de Boor, basis form, batch evaluation and the Cox–de Boor definition agree", "[nurbs][curve]") {
  for (int seed = 0; seed < 400; ++seed) {
    Rng rng(100 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const Curve& c = r.c;
    std::vector<double> us = probe_parameters(rng, r.knots, r.degree, 30);
    double e_deboor = 0, e_basis = 0, e_batch = 0, e_shuffled = 0;
    std::sort(us.begin(), us.end());
    const Points batch = evaluate(c, us);
    REQUIRE(batch.rows() == static_cast<Eigen::Index>(us.size()));
    REQUIRE(batch.cols() == r.cart.cols());
    std::vector<Point> refs;
    for (std::size_t i = 0; i < us.size(); ++i) {
      const Point ref = ref_point(r, us[i]);
      refs.push_back(ref);
      e_deboor = std::max(e_deboor, diff(evaluate(c, us[i]), ref));
      e_basis = std::max(e_basis, diff(evaluate_basis(c, us[i]), ref));
      e_batch = std::max(e_batch, diff(batch.row(static_cast<Eigen::Index>(i)), ref));
    }
    std::vector<std::size_t> order(us.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<double> shuffled;
    for (auto i : order) shuffled.push_back(us[i]);
    const Points batch2 = evaluate(c, shuffled);
    for (std::size_t i = 0; i < order.size(); ++i)
      e_shuffled = std::max(e_shuffled, diff(batch2.row(static_cast<Eigen::Index>(i)), refs[order[i]]));
    CHECK(e_deboor <= 1e-12 * r.scale);
    CHECK(e_basis <= 1e-12 * r.scale);
    CHECK(e_batch <= 1e-12 * r.scale);
    CHECK(e_shuffled <= 1e-12 * r.scale);
  }
}

TEST_CASE("batch evaluation: every column count and span search give evaluate_basis to the last bit",
          "[nurbs][curve]") {
  // The batch kernel is the basis form with the same arithmetic; its paths differ only in how they
  // find spans (the previous span for sorted input, a bucket table for long unordered batches, a
  // bisection otherwise) and in the column count (2, 3, 4 fixed, any other generic).
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(7300 + seed);
    const int d = uniform_int(rng, 1, 8);
    const auto kind = static_cast<Kind>(uniform_int(rng, 0, 2));
    const RandomCurve r =
        random_curve(rng, d, uniform_int(rng, 1, 5), coin(rng), kind, uniform_int(rng, 0, 40));
    INFO("seed " << seed << ": " << r.what);
    std::vector<double> us = probe_parameters(rng, r.knots, d, 0);
    // Long enough for the bucket table (8 parameters per knot), unless sorted.
    while (us.size() < 9 * r.knots.size()) us.push_back(uniform(rng, r.lo, r.hi));
    if (kind == Kind::closed)  // wrapped by whole periods, outside the domain
      for (std::size_t i = 0; i < us.size(); i += 7) us[i] += (r.hi - r.lo) * uniform_int(rng, -3, 3);
    const int order = uniform_int(rng, 0, 2);
    if (order == 1) std::sort(us.begin(), us.end());
    if (order == 2) std::shuffle(us.begin(), us.end(), rng);
    const Points batch = evaluate(r.c, us);
    REQUIRE(batch.rows() == static_cast<Eigen::Index>(us.size()));
    double differ = 0, worst = 0;
    for (std::size_t i = 0; i < us.size(); ++i) {
      const Point single = evaluate_basis(r.c, us[i]);
      differ = std::max(differ, diff(batch.row(static_cast<Eigen::Index>(i)), single));
      if (i % 5 == 0) worst = std::max(worst, diff(single, ref_point(r, domain_parameter(r.c, us[i]))));
    }
    CHECK(differ == 0.0);
    CHECK(worst <= 1e-12 * r.scale);
  }
}

TEST_CASE("batch evaluation on unordered parameters: four points a step, a span each, give de Boor",
          "[nurbs][curve][lanes]") {
  // Long shuffled batches take the span blocks (≥ 8 parameters per knot, blocks no larger than the
  // output), and for degrees 2 and 3 with 2–4 stored columns the AVX lanes: four consecutive
  // parameters a step, each lane with its own span. Every degree 1–5, 1–4 dimensions (every column
  // count the lanes store, rational rows divided in the lanes), every kind, rational and not;
  // the parameters include every knot, one ulp either side, and both ends. Against single-point
  // de Boor (another algorithm) to 1e-12, and evaluate_basis (the scalar basis form) to the last bit.
  for (int d = 1; d <= 5; ++d)
    for (int dim = 1; dim <= 4; ++dim)
      for (const bool rational : {false, true})
        for (const Kind kind : {Kind::clamped, Kind::unclamped, Kind::closed}) {
          Rng rng(static_cast<std::uint64_t>(9100 + 97 * d + 13 * dim + 3 * rational) +
                  static_cast<std::uint64_t>(kind));
          const RandomCurve r = random_curve(rng, d, dim, rational, kind, 20);
          INFO(r.what);
          std::vector<double> us = probe_parameters(rng, r.knots, d, 0);
          while (us.size() < 40 * r.knots.size()) us.push_back(uniform(rng, r.lo, r.hi));
          std::shuffle(us.begin(), us.end(), rng);
          const Points batch = evaluate(r.c, us);
          REQUIRE(batch.rows() == static_cast<Eigen::Index>(us.size()));
          double to_de_boor = 0, to_basis = 0;
          for (std::size_t i = 0; i < us.size(); ++i) {
            const auto row = batch.row(static_cast<Eigen::Index>(i));
            to_de_boor = std::max(to_de_boor, diff(row, evaluate(r.c, us[i])));
            to_basis = std::max(to_basis, diff(row, evaluate_basis(r.c, us[i])));
          }
          CHECK(to_de_boor <= 1e-12 * r.scale);
          CHECK(to_basis == 0.0);
        }
  // Subnormal knot intervals next to normal ones: the spans that read them have infinite reciprocals
  // and take the divisions; the lanes go on around them.
  const double h = 1e-320;
  for (int d = 1; d <= 5; ++d)
    for (const bool rational : {false, true}) {
      Rng rng(static_cast<std::uint64_t>(9300 + 2 * d + rational));
      Knots t(static_cast<std::size_t>(d), 0.0);
      for (double x : {0.0, h, 2 * h, 0.25, 0.5, 0.75}) t.push_back(x);
      t.insert(t.end(), static_cast<std::size_t>(d + 1), 1.0);
      const auto n = static_cast<Eigen::Index>(t.size()) - d - 1;
      const Points P = random_points(rng, n, 3);
      const Curve c = rational ? make_curve(d, t, P, random_weights(rng, n)) : make_curve(d, t, P);
      INFO("degree " << d << (rational ? ", rational" : ""));
      std::vector<double> us = probe_parameters(rng, t, d, 0);
      for (const double u : {h / 4, h / 2, 1.5 * h, 3 * h}) us.push_back(u);
      while (us.size() < 400) us.push_back(coin(rng, 0.2) ? uniform(rng, 0, 2 * h) : uniform(rng, 0, 1));
      std::shuffle(us.begin(), us.end(), rng);
      const Points batch = evaluate(c, us);
      double to_de_boor = 0, to_basis = 0;
      for (std::size_t i = 0; i < us.size(); ++i) {
        const auto row = batch.row(static_cast<Eigen::Index>(i));
        REQUIRE(row.allFinite());
        to_de_boor = std::max(to_de_boor, diff(row, evaluate(c, us[i])));
        to_basis = std::max(to_basis, diff(row, evaluate_basis(c, us[i])));
      }
      CHECK(to_de_boor <= 1e-12 * P.cwiseAbs().maxCoeff());
      CHECK(to_basis == 0.0);
    }
}

TEST_CASE("curves are continuous across every knot, one ulp either side, and closed curves wrap",
          "[nurbs][curve]") {
  for (int seed = 0; seed < 400; ++seed) {
    Rng rng(700 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const Curve& c = r.c;
    const int d = r.degree;
    double worst = 0;  // in units of the allowed error
    for (const auto& [x, mult] : interior_knots(r)) {
      const double below = std::nextafter(x, -HUGE_VAL), above = std::nextafter(x, HUGE_VAL);
      // Points: equal to the definition on both sides, and continuous up to round-off and slope·ulp.
      const Points dl = ref_derivatives(r, below, 1);
      const Points dr = ref_derivatives(r, x, 1);
      const double slope = std::max(dl.row(1).cwiseAbs().maxCoeff(), dr.row(1).cwiseAbs().maxCoeff());
      const double allowed = 1e-12 * r.scale + 4 * slope * (above - below);
      worst = std::max(worst, diff(evaluate(c, below), evaluate(c, x)) / allowed);
      worst = std::max(worst, diff(evaluate(c, above), evaluate(c, x)) / allowed);
      worst = std::max(worst, diff(evaluate(c, below), dl.row(0)) / (1e-12 * r.scale));
      worst = std::max(worst, diff(evaluate(c, x), dr.row(0)) / (1e-12 * r.scale));
      // Derivatives of order ≤ d − multiplicity are continuous too.
      const int smooth = d - mult;
      if (smooth >= 1) {
        const Points L = derivatives(c, below, smooth + 1), R = derivatives(c, x, smooth + 1);
        const auto M = magnitudes(r, x, smooth + 1);
        const auto Ml = magnitudes(r, below, smooth + 1);
        for (int k = 1; k <= smooth; ++k) {
          const double next =
              std::max(M[static_cast<std::size_t>(k + 1)], Ml[static_cast<std::size_t>(k + 1)]);
          const double tol =
              1e-11 * std::max(M[static_cast<std::size_t>(k)], Ml[static_cast<std::size_t>(k)]) +
              4 * next * (above - below);
          worst = std::max(worst, diff(L.row(k), R.row(k)) / tol);
        }
      }
    }
    CHECK(worst <= 1.0);
    if (r.kind == Kind::closed) {
      const double T = r.hi - r.lo;
      // The seam: C(b_0) = C(b_m), derivatives too up to the seam's continuity.
      const int seam = static_cast<int>(std::count(r.knots.begin(), r.knots.end(), r.lo));
      const int smooth = std::max(0, d - seam);
      // The knots on either side of the seam are translates by T only up to their rounding, so the
      // allowance includes the next derivative times a few ulps of the parameters.
      const Points A = derivatives(c, r.lo, smooth), B = derivatives(c, r.hi, smooth);
      const auto M = magnitudes(r, r.lo, smooth + 1);
      const double ulp = 8 * kEps * (std::abs(r.lo) + std::abs(r.hi));
      for (int k = 0; k <= smooth; ++k)
        CHECK(diff(A.row(k), B.row(k)) <=
              1e-11 * M[static_cast<std::size_t>(k)] + ulp * M[static_cast<std::size_t>(k + 1)]);
      // Any parameter maps into the period.
      double wrap = 0;
      for (int i = 0; i < 20; ++i) {
        const double u = uniform(rng, r.lo, r.hi);
        const Points D = ref_derivatives(r, u, 1);
        for (int k : {-3, -1, 1, 2, 7}) {
          const double v = u + k * T;
          const double allowed = 1e-12 * r.scale + 16 * kEps * (std::abs(v) + std::abs(r.lo) + T) *
                                                       D.row(1).cwiseAbs().maxCoeff();
          wrap = std::max(wrap, diff(evaluate(c, v), D.row(0)) / allowed);
          wrap = std::max(wrap, diff(evaluate_basis(c, v), D.row(0)) / allowed);
          const std::vector<double> one{v};
          wrap = std::max(wrap, diff(evaluate(c, one).row(0), D.row(0)) / allowed);
        }
      }
      CHECK(wrap <= 1.0);
      const double back = domain_parameter(c, r.hi + T);
      CHECK(back >= r.lo);
      CHECK(back <= r.hi);
      CHECK(std::min(std::abs(back - r.lo), std::abs(back - r.hi)) <= 8 * kEps * (std::abs(r.hi) + T));
    }
  }
}

TEST_CASE("curve derivatives: reference basis derivatives, Leibniz' rule and finite differences",
          "[nurbs][curve]") {
  for (int seed = 0; seed < 400; ++seed) {
    Rng rng(1500 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const Curve& c = r.c;
    const int d = r.degree;
    const int order = d + 1;
    double worst = 0, worst_zero = 0;
    for (double u : probe_parameters(rng, r.knots, d, 8)) {
      const Points D = derivatives(c, u, order);
      REQUIRE(D.rows() == order + 1);
      REQUIRE(D.cols() == r.cart.cols());
      const Points R = ref_derivatives(r, u, order);
      const auto M = magnitudes(r, u, order);
      for (int k = 0; k <= order; ++k) {
        if (!r.rational && k > d) {
          worst_zero = std::max(worst_zero, D.row(k).cwiseAbs().maxCoeff());
          continue;
        }
        worst = std::max(worst, diff(D.row(k), R.row(k)) / (M[static_cast<std::size_t>(k)] + 1e-300));
      }
      // Order 0 is the point.
      worst = std::max(worst, diff(D.row(0), evaluate(c, u)) / r.scale);
    }
    CHECK(worst <= 1e-12);
    CHECK(worst_zero == 0.0);
    // Finite differences of the derivative of order k − 1, in the middle of every span.
    double worst_fd = 0;
    const int top = std::min(4, r.rational ? d + 1 : d);
    for (int k = d; k + 1 < static_cast<int>(r.knots.size()) - d; ++k) {
      const double a = r.knots[static_cast<std::size_t>(k)], b = r.knots[static_cast<std::size_t>(k + 1)];
      if (!(a < b)) continue;
      const double u = a + uniform(rng, 0.3, 0.7) * (b - a), h = 1e-3 * (b - a);
      const Points D = derivatives(c, u, top);
      const auto M = magnitudes(r, u, top);
      for (int j = 1; j <= top; ++j) {
        auto f = [&](double x) -> Points { return derivatives(c, x, j - 1).row(j - 1); };
        worst_fd =
            std::max(worst_fd, diff(central_difference(f, u, h), D.row(j)) / M[static_cast<std::size_t>(j)]);
      }
    }
    CHECK(worst_fd <= 1e-6);
  }
}

TEST_CASE("blossoms: symmetric, multi-affine, diagonal = curve, consecutive knots = control points",
          "[nurbs][curve]") {
  for (int seed = 0; seed < 400; ++seed) {
    Rng rng(2500 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const Curve& c = r.c;
    const int d = r.degree;
    const auto& t = r.knots;
    const auto n = static_cast<int>(r.H.rows());
    const double hs = max_abs(r.H);
    double e_ref = 0, e_sym = 0, e_aff = 0, e_diag = 0, e_dual = 0;
    for (int k = d; k < n; ++k) {
      const double a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>(k + 1)];
      if (!(a < b)) continue;
      // Arguments anywhere in the span's window t_{k−d+1} .. t_{k+d}.
      const double lo = t[static_cast<std::size_t>(k - d + 1)], hi = t[static_cast<std::size_t>(k + d)];
      auto draw = [&] {
        std::vector<double> x(static_cast<std::size_t>(d));
        for (auto& v : x) v = uniform(rng, lo, hi);
        return x;
      };
      for (int rep = 0; rep < 3; ++rep) {
        std::vector<double> x = draw();
        double l1 = 0;
        const Point B = blossom(c, x, k);
        e_ref = std::max(e_ref, diff(B, ref_blossom(r, x, k, &l1)) / (hs * l1));
        // Symmetry: every argument order gives the same value.
        std::vector<double> y = x;
        std::shuffle(y.begin(), y.end(), rng);
        e_sym = std::max(e_sym, diff(blossom(c, y, k), B) / (hs * l1));
        if (d >= 2) {
          std::reverse(y.begin(), y.end());
          e_sym = std::max(e_sym, diff(blossom(c, y, k), B) / (hs * l1));
        }
        // Multi-affinity in argument q: b(..z..) = (β−z)/(β−α) b(..α..) + (z−α)/(β−α) b(..β..).
        const auto q = static_cast<std::size_t>(uniform_int(rng, 0, d - 1));
        std::vector<double> xa = x, xb = x;
        xa[q] = uniform(rng, lo, hi);
        xb[q] = uniform(rng, lo, hi);
        if (xa[q] != xb[q]) {
          const double z = x[q], al = xa[q], be = xb[q];
          double la = 0, lb = 0;
          ref_blossom(r, xa, k, &la);
          ref_blossom(r, xb, k, &lb);
          const double ca = (be - z) / (be - al), cb = (z - al) / (be - al);
          const Point comb = ca * blossom(c, xa, k) + cb * blossom(c, xb, k);
          e_aff = std::max(e_aff, diff(comb, B) / (hs * (l1 + std::abs(ca) * la + std::abs(cb) * lb)));
        }
      }
      // Diagonal.
      for (int rep = 0; rep < 3; ++rep) {
        const double u = rep == 0 ? a : uniform(rng, a, b);
        const std::vector<double> x(static_cast<std::size_t>(d), u);
        const Point ref = ref_homogeneous(ref_knots(r, u), d, r.H).cast<double>();
        e_diag = std::max(e_diag, diff(blossom(c, x, k), ref) / hs);
        e_diag = std::max(e_diag, diff(to_cartesian(c, blossom(c, x, k)), evaluate(c, u)) / r.scale);
      }
      // Consecutive knots t_{i+1..i+d}: P_i, for every i whose support contains the span. Closed
      // curves: only where they are breakpoints; the knots b_k ± T beyond the period are rounded,
      // and P_i is the blossom at the exact ones.
      for (int i = k - d; i <= k; ++i) {
        if (r.kind == Kind::closed && (i + 1 < d || i + d > n)) continue;
        const std::vector<double> x(t.begin() + i + 1, t.begin() + i + d + 1);
        e_dual = std::max(e_dual, diff(blossom(c, x, k), r.H.row(i)) / hs);
      }
    }
    CHECK(e_ref <= 1e-12);
    CHECK(e_sym <= 1e-12);
    CHECK(e_aff <= 1e-12);
    CHECK(e_diag <= 1e-12);
    CHECK(e_dual <= 1e-12);
  }
}

TEST_CASE("blossom without a span uses the span of the mean; closed curves shift by periods",
          "[nurbs][curve]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(3500 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const Curve& c = r.c;
    const int d = r.degree;
    const double hs = max_abs(r.H);
    double worst = 0, shifted = 0;
    for (int rep = 0; rep < 10; ++rep) {
      std::vector<double> x(static_cast<std::size_t>(d));
      const double centre = uniform(rng, r.lo, r.hi), width = 0.1 * (r.hi - r.lo);
      for (auto& v : x) v = centre + uniform(rng, -width, width);
      const double mean = std::accumulate(x.begin(), x.end(), 0.0) / d;
      if (mean < r.lo || mean >= r.hi) continue;
      const int k = definition_span(r.knots, d, mean);
      double l1 = 0;
      const Point ref = ref_blossom(r.knots, d, r.H, x, k, &l1);
      worst = std::max(worst, diff(blossom(c, x), ref) / (hs * l1));
      if (r.kind == Kind::closed) {
        // Arguments shifted by whole periods give the same blossom, up to the rounding of the shift
        // times the blossom's slope in each argument (exact differences by multi-affinity).
        const double T = r.hi - r.lo;
        double slope = 0;
        for (std::size_t q = 0; q < x.size(); ++q) {
          std::vector<double> z = x;
          z[q] += 1;
          slope += diff(ref_blossom(r.knots, d, r.H, z, k), ref);
        }
        for (int s : {-2, 1, 3}) {
          std::vector<double> y = x;
          for (auto& v : y) v += s * T;
          const double allowed =
              1e-12 * hs * l1 + slope * 8 * kEps * (std::abs(s) * T + std::abs(centre) + std::abs(r.lo) + T);
          shifted = std::max(shifted, diff(blossom(c, y), ref) / allowed);
        }
      }
    }
    CHECK(worst <= 1e-12);
    CHECK(shifted <= 1.0);
  }
}

TEST_CASE("the exact rational circle: radius one everywhere, tangent derivatives", "[nurbs][curve]") {
  for (const Curve& c : {unit_circle(), closed_unit_circle()}) {
    INFO("closed " << c.closed);
    std::vector<double> us;
    for (int i = 0; i <= 2000; ++i) us.push_back(i / 2000.0);
    for (double x : {0.25, 0.5, 0.75}) {
      us.push_back(std::nextafter(x, 0.0));
      us.push_back(std::nextafter(x, 1.0));
    }
    double radius = 0, basis_radius = 0, batch_radius = 0, tangent = 0, curvature = 0;
    const Points batch = evaluate(c, us);
    for (std::size_t i = 0; i < us.size(); ++i) {
      const double u = us[i];
      radius = std::max(radius, std::abs(evaluate(c, u).norm() - 1));
      basis_radius = std::max(basis_radius, std::abs(evaluate_basis(c, u).norm() - 1));
      batch_radius = std::max(batch_radius, std::abs(batch.row(static_cast<Eigen::Index>(i)).norm() - 1));
      const Points D = derivatives(c, u, 2);
      // |C|² = 1 ⇒ C·C' = 0 and C·C'' + |C'|² = 0.
      tangent = std::max(tangent, std::abs(D.row(0).dot(D.row(1))) / D.row(1).norm());
      curvature = std::max(
          curvature, std::abs(D.row(0).dot(D.row(2)) + D.row(1).squaredNorm()) / D.row(1).squaredNorm());
    }
    CHECK(radius <= 4 * kEps);
    CHECK(basis_radius <= 4 * kEps);
    CHECK(batch_radius <= 4 * kEps);
    CHECK(tangent <= 1e-14);
    CHECK(curvature <= 1e-13);
    // Quarter points.
    CHECK(diff(evaluate(c, 0.25), (Point(2) << 0, 1).finished()) <= kEps);
    CHECK(diff(evaluate(c, 0.5), (Point(2) << -1, 0).finished()) <= kEps);
    CHECK(diff(evaluate(c, 1.0), (Point(2) << 1, 0).finished()) <= kEps);
  }
}

TEST_CASE("uniform_parameters and domain_parameter", "[nurbs][curve]") {
  const Domain dom{-1.5, 2.25};
  const auto us = uniform_parameters(dom, 7);
  REQUIRE(us.size() == 7);
  CHECK(us.front() == dom.start);
  CHECK(us.back() == dom.end);
  for (std::size_t i = 0; i + 1 < us.size(); ++i) CHECK(us[i + 1] - us[i] == Approx(3.75 / 6).epsilon(1e-14));
  CHECK(uniform_parameters(dom, 1) == std::vector<double>{dom.start});
  CHECK(uniform_parameters(dom, 0).empty());
  const Curve open = make_curve(1, {0, 0, 1, 1}, Points::Identity(2, 2));
  CHECK(domain_parameter(open, 0.0) == 0.0);
  CHECK(domain_parameter(open, 1.0) == 1.0);
  const Curve closed = make_closed_curve(1, {0, 1, 3}, Points::Identity(2, 2));
  CHECK(domain_parameter(closed, 3.0) == 3.0);
  CHECK(domain_parameter(closed, 4.0) == Approx(1.0));
  CHECK(domain_parameter(closed, -0.5) == Approx(2.5));
  CHECK(domain_parameter(closed, -3.0) == Approx(0.0).margin(1e-15));
}

TEST_CASE("curve validation names the problem and its place", "[nurbs][curve]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Knots t{0, 0, 0, 1, 2, 2, 2};
  const Points P = Points::Random(4, 2);
  CHECK_NOTHROW(make_curve(2, t, P));
  // Degree and knots.
  CHECK_THROWS_WITH(make_curve(0, t, P), Contains("degree 0"));
  CHECK_THROWS_WITH(make_curve(2, {0, 0, 0, 1, nan, 2, 2}, P), Contains("knots[4]"));
  CHECK_THROWS_WITH(make_curve(2, {0, 0, 0, 3, 2, 2, 2}, P), Contains("knots[4]"));
  CHECK_THROWS_WITH(make_curve(2, {0, 0, 0, 2, 2, 2}, P), Contains("6 knots given"));
  CHECK_THROWS_WITH(make_curve(3, {0, 0, 0, 0, 1, 1, 1}, Points::Random(3, 2)), Contains("too few"));
  // Weights.
  CHECK_THROWS_WITH(make_curve(2, t, P, Eigen::VectorXd::Ones(3)),
                    Contains("weights") && Contains("3 weights"));
  for (double bad : {0.0, -1.0, nan, HUGE_VAL}) {
    Eigen::VectorXd w = Eigen::VectorXd::Ones(4);
    w(2) = bad;
    CHECK_THROWS_WITH(make_curve(2, t, P, w), Contains("weights[2]"));
  }
  // Coordinates.
  for (double bad : {nan, HUGE_VAL, -HUGE_VAL}) {
    Points Q = P;
    Q(1, 0) = bad;
    CHECK_THROWS_WITH(make_curve(2, t, Q), Contains("points[1][0]"));
    CHECK_THROWS_WITH(make_curve(2, t, Q, Eigen::VectorXd::Ones(4)), Contains("points[1][0]"));
  }
  CHECK_THROWS_WITH(make_curve(2, t, Points(4, 0)), Contains("no coordinates"));
  // A hand-made curve that breaks the closed invariant.
  Curve broken = make_closed_curve(2, {0, 1, 2, 3}, Points::Random(3, 2));
  CHECK_NOTHROW(validate(broken));
  broken.P(4, 1) += 1;
  CHECK_THROWS_WITH(validate(broken), Contains("points[4]"));
}

TEST_CASE("knots near the limits of double: refused when differences overflow, exact otherwise",
          "[nurbs][curve]") {
  const Points P = (Points(6, 3) << 0, 0, 0, 1, 2, 0, 3, 3, 1, 4, 0, 0, 6, 1, 2, 7, 3, 0).finished();
  const Eigen::VectorXd w = (Eigen::VectorXd(6) << 1, 2, 1, 0.5, 1, 1).finished();
  // The audit's case: every knot finite, the range 2e308 is not.
  CHECK_THROWS_WITH(make_curve(3, {-1e308, -1e308, -1e308, -1e308, 0, 1e307, 1e308, 1e308, 1e308, 1e308}, P),
                    Contains("wider than a double holds"));
  CHECK_THROWS_WITH(make_closed_curve(3, {0, 5e307, 1e308, 1.5e308, 1.7e308, 1.79e308}, P.topRows(5)),
                    Contains("wider than a double holds"));
  // An affine change of the knots leaves the curve as it is (basis functions are ratios of knot
  // differences): scaled by 2^1016 or 2^-996 and shifted, it is the unit curve at the mapped
  // parameter. Scales are powers of two and parameters dyadic, so that knots and parameters map exactly.
  const Knots unit{0, 0, 0, 0, 1, 2, 4, 4, 4, 4};
  const Curve reference = make_curve(3, unit, P, w);
  for (const auto& [scale, shift] :
       {std::pair{std::ldexp(1.0, 1016), -std::ldexp(1.0, 1017)},
        std::pair{std::ldexp(1.0, -996), std::ldexp(1.0, -993)}, std::pair{0.25, 1e6}}) {
    Knots t = unit;
    for (double& k : t) k = shift + scale * k;
    const Curve scaled = make_curve(3, t, P, w);
    for (const double u : {0.0, 0.3125, 1.0, 1.75, 2.0, 3.9921875, 4.0}) {
      const Point a = evaluate(reference, u), b = evaluate(scaled, shift + scale * u);
      INFO("scale " << scale << ", u " << u);
      CHECK((a - b).norm() <= 1e-13 * a.norm());
    }
  }
}

TEST_CASE("closed curve validation names the problem and its place", "[nurbs][curve]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Points P = Points::Random(4, 3);
  const Knots b{0, 1, 2, 3, 4};
  CHECK_NOTHROW(make_closed_curve(3, b, P));
  CHECK_THROWS_WITH(make_closed_curve(0, b, P), Contains("degree 0"));
  CHECK_THROWS_WITH(make_closed_curve(3, {0, 1}, Points::Random(1, 3)), Contains("at least 2"));
  CHECK_THROWS_WITH(make_closed_curve(3, {0, 1, 2, 3}, P), Contains("5 breakpoints"));
  CHECK_THROWS_WITH(make_closed_curve(3, {0, 1, nan, 3, 4}, P), Contains("knots[2]") && Contains("finite"));
  CHECK_THROWS_WITH(make_closed_curve(3, {0, 1, 0.5, 3, 4}, P), Contains("knots[2]") && Contains("less"));
  CHECK_THROWS_WITH(make_closed_curve(3, {2, 2, 2, 2, 2}, P), Contains("empty"));
  Eigen::VectorXd w = Eigen::VectorXd::Ones(4);
  w(3) = -2;
  CHECK_THROWS_WITH(make_closed_curve(3, b, P, w), Contains("weights[3]"));
  CHECK_THROWS_WITH(make_closed_curve(3, b, P, Eigen::VectorXd::Ones(5)), Contains("weights"));
  Points Q = P;
  Q(2, 1) = nan;
  CHECK_THROWS_WITH(make_closed_curve(3, b, Q), Contains("points[2][1]"));
  // Multiplicity above degree + 1, inside the period and across the seam, reported on the breakpoints.
  CHECK_THROWS_WITH(make_closed_curve(1, {0, 1, 1, 1, 2}, P),
                    Contains("knots[3]") && Contains("multiplicity"));
  CHECK_THROWS_WITH(make_closed_curve(1, {0, 0, 1, 2, 2}, P), Contains("knots[4]") && Contains("seam"));
  CHECK_THROWS_WITH(make_closed_curve(2, {0, 0, 0, 2, 2}, P),
                    Contains("knots[4]") && Contains("multiplicity 4"));
  CHECK_NOTHROW(make_closed_curve(1, {0, 1, 1, 2, 2}, P));
}

TEST_CASE("evaluation, derivatives and blossoms reject bad arguments", "[nurbs][curve]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Curve c = make_curve(2, {0, 0, 0, 1, 1, 2, 2, 2}, Points::Random(5, 2));
  for (double bad : {-1e-300, std::nextafter(2.0, 3.0), 7.0, nan, HUGE_VAL}) {
    INFO("u = " << bad);
    const std::string what =
        std::isfinite(bad) ? "outside the domain" : "the parameter is not a finite number";
    CHECK_THROWS_WITH(evaluate(c, bad), Contains(what));
    CHECK_THROWS_WITH(evaluate_basis(c, bad), Contains(what));
    const std::vector<double> us{0.5, bad};
    CHECK_THROWS_WITH(evaluate(c, us), Contains(what));
    CHECK_THROWS_WITH(derivatives(c, bad, 1), Contains(what));
  }
  CHECK_THROWS_WITH(derivatives(c, 0.5, -1), Contains("order -1 is outside 0 … 64"));
  CHECK_THROWS_WITH(derivatives(c, 0.5, 1000000), Contains("order 1000000 is outside 0 … 64"));
  CHECK(derivatives(c, 0.5, kMaxDegree).rows() == kMaxDegree + 1);
  CHECK(derivatives(c, 0.5, 0).rows() == 1);
  const std::vector<double> one{0.5}, three{0.5, 0.5, 0.5}, two{0.5, 0.5}, bad2{0.5, nan};
  CHECK_THROWS_WITH(blossom(c, one, 2), "the blossom of a degree-2 curve takes 2 arguments, 1 given");
  CHECK_THROWS_WITH(blossom(c, three, 2), Contains("takes 2 arguments, 3 given"));
  CHECK_THROWS_WITH(blossom(c, three), Contains("takes 2 arguments, 3 given"));
  CHECK_THROWS_WITH(blossom(c, bad2, 2), "blossom argument 1 is not a finite number");
  CHECK_THROWS_WITH(blossom(c, bad2), "the blossom's arguments are not all finite numbers");
  CHECK_THROWS_WITH(blossom(c, two, 3), Contains("span 3"));  // the empty span [1, 1]
  CHECK_THROWS_WITH(blossom(c, two, 1), Contains("span 1"));
  CHECK_THROWS_WITH(blossom(c, two, 5), Contains("span 5"));
  CHECK_NOTHROW(blossom(c, two, 2));
  CHECK_NOTHROW(blossom(c, two, 4));
  // Closed curves wrap instead of throwing, but still reject non-finite parameters.
  const Curve closed = make_closed_curve(2, {0, 1, 2, 3}, Points::Random(3, 2));
  CHECK_NOTHROW(evaluate(closed, -10.0));
  CHECK_THROWS_WITH(evaluate(closed, nan), Contains("not a finite number"));
  CHECK_THROWS_WITH(evaluate(closed, -nan), "the parameter is not a finite number");  // not "-nan"
}

TEST_CASE("uniform_bspline: closed cubic at breakpoints is (P_i + 4 P_{i+1} + P_{i+2}) / 6", "[nurbs]") {
  const Points P = Points::Random(7, 2);
  const nurbs::Curve c = nurbs::uniform_bspline(P, 3, true);
  CHECK(c.closed);
  for (Eigen::Index i = 0; i < 7; ++i) {
    const Eigen::RowVectorXd expected = (P.row(i) + 4 * P.row((i + 1) % 7) + P.row((i + 2) % 7)) / 6;
    const Point x = nurbs::evaluate(c, static_cast<double>(i));
    CHECK((x - expected).norm() <= 1e-15 * 6);
  }
  const nurbs::Curve open = nurbs::uniform_bspline(P, 3, false);
  CHECK(open.knots == nurbs::Knots{0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4});
  CHECK(nurbs::evaluate(open, 0.0) == P.row(0));
  CHECK(nurbs::evaluate(open, 4.0) == P.row(6));
  CHECK_THROWS_WITH(nurbs::uniform_bspline(P.topRows(3), 3, false),
                    Catch::Contains("at least 4 control points"));
  CHECK_THROWS_AS(nurbs::uniform_bspline(P.topRows(1), 3, true), InvalidInput);
}

TEST_CASE("Open curves at the edges of double: within γ_4p of the control points (docs/formats.md)",
          "[nurbs][reliability]") {
  // Knot ratios of 1e12, spans of 1e-300 and knots near 1e300, weights from 1e-3 to 1e3: open knots
  // are used as given, every coefficient is in [0, 1], so the error stays within 4p·u of the
  // largest control point whatever the ratios (long double Cox–de Boor from the definition).
  Rng rng(12);
  for (const int p : {2, 4, 10}) {
    const Eigen::Index n = p + 4;
    for (const auto& [origin, scale, ratio] :
         {std::tuple{0.0, 1.0, 1e12}, std::tuple{1e300, 1e290, 1e6}, std::tuple{1e-290, 1e-300, 1e3}}) {
      Knots t;
      for (int i = 0; i <= p; ++i) t.push_back(origin);
      double x = origin;
      for (Eigen::Index i = 0; i < n - p - 1; ++i) t.push_back(x += scale * (i % 2 ? ratio : 1));
      for (int i = 0; i <= p; ++i) t.push_back(x + scale);
      const Points cart = random_points(rng, n, 2);
      Eigen::VectorXd w(n);
      for (Eigen::Index i = 0; i < n; ++i) w[i] = i % 2 ? 1e3 : 1e-3;
      const Curve c = make_curve(p, t, cart, w);
      const double size = cart.cwiseAbs().maxCoeff();
      for (int k = 0; k <= 200; ++k) {
        const double u = t[static_cast<std::size_t>(p)] +
                         (t[static_cast<std::size_t>(n)] - t[static_cast<std::size_t>(p)]) * k / 200;
        const Point ref = ref_point(c.knots, p, c.P, true, u);
        INFO("degree " << p << ", origin " << origin << ", ratio " << ratio << ", u = " << u);
        CHECK((evaluate(c, u) - ref).cwiseAbs().maxCoeff() <= 4 * p * kEps * size * 2);
      }
    }
  }
}

TEST_CASE("Evaluation on subnormal knot intervals is exact, not NaN", "[nurbs][reliability]") {
  // Cox–de Boor divided 1 by the interval 1e-320 (inf), then inf · 0: eval printed [[nan]] (issue 33).
  const double h = 1e-320;
  const Curve line = make_curve(1, {0, 0, h, h}, (Points(2, 1) << 0, 2).finished());
  for (const double u : {0.0, h / 2, h}) {
    const double expected = 2 * (u / h);  // the ratio of two subnormals is exact here (multiples of 2^-1074)
    CHECK(evaluate(line, u)(0) == expected);
    CHECK(evaluate_basis(line, u)(0) == expected);
    CHECK(evaluate(line, std::vector<double>{u})(0, 0) == expected);
  }
  // Quadratic: the basis sums to 1 and matches de Boor.
  const Curve quad =
      make_curve(2, {0, 0, 0, h, 2 * h, 2 * h, 2 * h}, (Points(4, 1) << 0, 1, 3, 4).finished());
  for (const double u : {0.0, h / 4, h, 1.5 * h, 2 * h}) {
    INFO(u);
    CHECK(std::isfinite(evaluate_basis(quad, u)(0)));
    CHECK(evaluate_basis(quad, u)(0) == Approx(evaluate(quad, u)(0)).epsilon(1e-15));
  }
}

TEST_CASE("A weight whose product with its coordinate overflows is named as such", "[nurbs][reliability]") {
  // Weight 1e308 on the coordinate 2: the stored w·x is inf, and the message blamed the coordinate,
  // "points[0][0]: coordinate is not finite" (issue 33).
  const Points P = (Points(2, 1) << 2, 3).finished();
  CHECK_THROWS_WITH(make_curve(1, {0, 0, 1, 1}, P, (Eigen::VectorXd(2) << 1e308, 1).finished()),
                    Contains("points[0][0]: the coordinate times its weight (w·x) is not finite"));
  CHECK_NOTHROW(make_curve(1, {0, 0, 1, 1}, P, (Eigen::VectorXd(2) << 1e300, 1).finished()));
}
