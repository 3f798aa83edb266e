// SPDX-License-Identifier: MIT
// Knot insertion, refinement, Bézier splitting, degree elevation and knot removal: the curve never
// moves, and the new control points match Boehm's formula and the blossom at consecutive knots.
#include "cifs/nurbs/refine.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>

#include "cifs/errors.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

/// Largest distance between the curve and the test's reference of the original curve, over the
/// probes of both knot vectors, in units of the allowed error: 1e-12 of the scale of the control
/// points (closed curves too: the reference is their exact periodic curve, ref_closed_knots).
double moved(const RandomCurve& r, const Curve& c2, Rng& rng) {
  std::vector<double> us = probe_parameters(rng, r.knots, r.degree, 40);
  const auto more = probe_parameters(rng, c2.knots, c2.degree, 0);
  us.insert(us.end(), more.begin(), more.end());
  double worst = 0;
  for (double u : us) {
    const Point ref = ref_point(r, u);
    worst = std::max(worst, diff(evaluate(c2, u), ref));
    worst = std::max(worst, diff(evaluate_basis(c2, u), ref));
  }
  return worst / (1e-12 * r.scale);
}

/// Multiplicity of every knot value as seen in the full knot vector.
std::map<double, int> multiplicities(const Knots& t) {
  std::map<double, int> m;
  for (double x : t) ++m[x];
  return m;
}

/// Random insertion knots: random values, existing knots, repeats of earlier picks and the domain
/// ends, keeping every multiplicity ≤ d. Closed curves take values in [lo, hi).
std::vector<double> random_insertions(Rng& rng, const RandomCurve& r, int count) {
  auto mult = multiplicities(r.knots);
  const bool closed = r.kind == Kind::closed;
  std::vector<double> X;
  for (int tries = 0; static_cast<int>(X.size()) < count && tries < 20 * count; ++tries) {
    double x = 0;
    switch (uniform_int(rng, 0, 3)) {
      case 0:
        x = uniform(rng, r.lo, r.hi);
        break;
      case 1:
        x = r.knots[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(r.knots.size()) - 1))];
        break;
      case 2:
        x = X.empty() ? r.lo
                      : X[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(X.size()) - 1))];
        break;
      default:
        x = coin(rng) ? r.lo : r.hi;
        break;
    }
    if (x < r.lo || x > r.hi || (closed && x == r.hi)) continue;
    if (mult[x] + 1 > r.degree) continue;
    ++mult[x];
    X.push_back(x);
  }
  return X;
}

/// The sorted merge of the old knot vector (closed: breakpoints) and the insertions.
Knots merged(const RandomCurve& r, std::vector<double> X) {
  std::sort(X.begin(), X.end());
  if (r.kind != Kind::closed) {
    Knots out;
    std::merge(r.knots.begin(), r.knots.end(), X.begin(), X.end(), std::back_inserter(out));
    return out;
  }
  Knots out;
  std::merge(r.breaks.begin(), r.breaks.end() - 1, X.begin(), X.end(), std::back_inserter(out));
  out.push_back(r.breaks.back());
  return out;
}

/// Compares an open refinement with Boehm's formula (one knot at a time, in the given order) and
/// with the blossom of the old curve at consecutive new knots. Returns the two relative errors.
std::pair<double, double> check_open_points(const RandomCurve& r, const Curve& c2,
                                            const std::vector<double>& X) {
  RefSpline s{r.degree, r.knots, r.H};
  for (double x : X) s = ref_boehm(s, x);
  const double hs = max_abs(r.H);
  double e_boehm = diff(s.P, c2.P) / hs;
  if (s.t != c2.knots || s.P.rows() != c2.P.rows()) e_boehm = HUGE_VAL;
  // Blossoms: Q_j = b(t'_{j+1..j+d}) on any old span under a new interval of the support of N'_j
  // inside the domain; the test takes the best-conditioned one (long double, arguments ordered).
  const int d = r.degree;
  const auto& t2 = c2.knots;
  const int n2 = static_cast<int>(c2.P.rows());
  double e_blossom = 0;
  for (int j = 0; j < n2; ++j) {
    const std::vector<double> args(t2.begin() + j + 1, t2.begin() + j + d + 1);
    double best = HUGE_VAL;
    Point ref;
    for (int k = std::max(j, d); k <= std::min(j + d, n2 - 1); ++k) {
      const double a = t2[static_cast<std::size_t>(k)], b = t2[static_cast<std::size_t>(k + 1)];
      if (!(a < b)) continue;
      const int K = definition_span(r.knots, d, 0.5 * (a + b));
      double l1 = 0;
      const Point v = ref_blossom(r.knots, d, r.H, conditioned_order(r.knots, args, K), K, &l1);
      if (l1 < best) best = l1, ref = v;
    }
    if (best == HUGE_VAL) continue;  // N'_j vanishes on the domain
    e_blossom = std::max(e_blossom, diff(ref, c2.P.row(j)) / (hs * best));
  }
  return {e_boehm, e_blossom};
}

/// Piegl–Tiller A5.4 as printed (RefineKnotVectCurve), on the stored rows, X sorted: refine's Boehm
/// branch must give these points to the last bit.
RefSpline textbook_refine(const RefSpline& s, const std::vector<double>& X) {
  const int p = s.p;
  const int n = static_cast<int>(s.P.rows()) - 1, m = n + p + 1, r = static_cast<int>(X.size()) - 1;
  const auto U = [&](int i) { return s.t[static_cast<std::size_t>(i)]; };
  const auto x = [&](int j) { return X[static_cast<std::size_t>(j)]; };
  RefSpline out{p, Knots(static_cast<std::size_t>(m + r + 2)), Points(n + r + 2, s.P.cols())};
  const auto Ub = [&](int i) -> double& { return out.t[static_cast<std::size_t>(i)]; };
  const int a = definition_span(s.t, p, x(0)), b = definition_span(s.t, p, x(r)) + 1;
  for (int j = 0; j <= a - p; ++j) out.P.row(j) = s.P.row(j);
  for (int j = b - 1; j <= n; ++j) out.P.row(j + r + 1) = s.P.row(j);
  for (int j = 0; j <= a; ++j) Ub(j) = U(j);
  for (int j = b + p; j <= m; ++j) Ub(j + r + 1) = U(j);
  int i = b + p - 1, k = b + p + r;
  for (int j = r; j >= 0; --j) {
    while (x(j) <= U(i) && i > a) {
      out.P.row(k - p - 1) = s.P.row(i - p - 1);
      Ub(k) = U(i);
      --k;
      --i;
    }
    out.P.row(k - p - 1) = out.P.row(k - p);
    for (int l = 1; l <= p; ++l) {
      const int ind = k - p + l;
      double alpha = Ub(k + l) - x(j);
      if (alpha == 0.0) {
        out.P.row(ind - 1) = out.P.row(ind);
      } else {
        alpha = alpha / (Ub(k + l) - U(i - p + l));
        out.P.row(ind - 1) = alpha * out.P.row(ind - 1) + (1.0 - alpha) * out.P.row(ind);
      }
    }
    Ub(k) = x(j);
    --k;
  }
  return out;
}

/// The refined points in long double, the definition of what refine computes: the old spline padded
/// with d knots and d zero points on each side (Σ P_i N_i on the whole knot range), and Q_j its blossom
/// at t'_{j+1..j+d} on the best-conditioned piece under the support of N'_j. Returns the largest
/// difference to Q, relative to max |P|.
double refined_error(const RandomCurve& r, const Curve& c2) {
  const int d = r.degree;
  const double front = r.knots.front(), back = r.knots.back(), pad = back - front;
  Knots t;
  for (int i = d; i >= 1; --i) t.push_back(front - i * pad);
  t.insert(t.end(), r.knots.begin(), r.knots.end());
  for (int i = 1; i <= d; ++i) t.push_back(back + i * pad);
  Points H = Points::Zero(r.H.rows() + 2 * d, r.H.cols());
  H.middleRows(d, r.H.rows()) = r.H;
  const auto& t2 = c2.knots;
  double worst = 0;
  for (Eigen::Index j = 0; j < c2.P.rows(); ++j) {
    const std::vector<double> args(t2.begin() + j + 1, t2.begin() + j + d + 1);
    double best = HUGE_VAL;
    Point ref;
    for (Eigen::Index k = j; k <= j + d; ++k) {
      const double a = t2[static_cast<std::size_t>(k)], b = t2[static_cast<std::size_t>(k + 1)];
      if (!(a < b)) continue;
      const int K = definition_span(t, d, 0.5 * (a + b));
      double l1 = 0;
      const Point v = ref_blossom(t, d, H, conditioned_order(t, args, K), K, &l1);
      if (l1 < best) best = l1, ref = v;
    }
    worst = std::max(worst, diff(ref, c2.P.row(j)));
  }
  return worst / max_abs(r.H);
}

/// `per` sorted insertions in each of the given old spans (values strictly inside).
std::vector<double> knots_in_spans(Rng& rng, const Knots& t, const std::vector<int>& spans, int per) {
  std::vector<double> X;
  for (int s : spans) {
    const double a = t[static_cast<std::size_t>(s)], b = t[static_cast<std::size_t>(s + 1)];
    for (int k = 0; k < per; ++k) {
      const double x = uniform(rng, a, b);
      if (x > a) X.push_back(x);
    }
  }
  std::sort(X.begin(), X.end());
  return X;
}

/// The non-empty spans of the domain.
std::vector<int> domain_spans(const RandomCurve& r) {
  std::vector<int> spans;
  for (int k = r.degree; k < r.H.rows(); ++k)
    if (r.knots[static_cast<std::size_t>(k)] < r.knots[static_cast<std::size_t>(k + 1)]) spans.push_back(k);
  return spans;
}

}  // namespace

TEST_CASE("insert_knot 1..d times: same curve, merged knots, Boehm's points, blossom points",
          "[nurbs][refine]") {
  for (int seed = 0; seed < 400; ++seed) {
    Rng rng(seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const auto X1 = random_insertions(rng, r, 1);
    if (X1.empty()) continue;
    const double u = X1[0];
    const int room = r.degree - multiplicities(r.knots)[u];
    const int times = uniform_int(rng, 1, room);
    INFO("insert " << u << " x" << times);
    const Curve c2 = insert_knot(r.c, u, times);
    CHECK_NOTHROW(validate(c2));
    CHECK(c2.degree == r.degree);
    CHECK(c2.rational == r.rational);
    CHECK(c2.closed == r.c.closed);
    CHECK(distinct_count(c2) == distinct_count(r.c) + times);
    const std::vector<double> X(static_cast<std::size_t>(times), u);
    CHECK(defining_knots(c2) == merged(r, X));
    CHECK(moved(r, c2, rng) <= 1.0);
    if (r.kind != Kind::closed) {
      const auto [e_boehm, e_blossom] = check_open_points(r, c2, X);
      CHECK(e_boehm <= 1e-12);
      CHECK(e_blossom <= 1e-12);
    }
  }
}

TEST_CASE("refine with many knots in any order, repeats included: same curve, Boehm's points",
          "[nurbs][refine]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(1000 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const auto X = random_insertions(rng, r, uniform_int(rng, 1, 25));
    INFO(X.size() << " knots");
    const Curve c2 = refine(r.c, X);
    CHECK_NOTHROW(validate(c2));
    CHECK(distinct_count(c2) == distinct_count(r.c) + static_cast<Eigen::Index>(X.size()));
    CHECK(defining_knots(c2) == merged(r, X));
    CHECK(c2.closed == r.c.closed);
    CHECK(moved(r, c2, rng) <= 1.0);
    if (r.kind != Kind::closed) {
      const auto [e_boehm, e_blossom] = check_open_points(r, c2, X);
      CHECK(e_boehm <= 1e-12);
      CHECK(e_blossom <= 1e-12);
    }
    // No knots: the same curve.
    const Curve same = refine(r.c, std::vector<double>{});
    CHECK(same.knots == r.c.knots);
    CHECK(same.P == r.c.P);
  }
}

TEST_CASE("refine_midpoints doubles every span and keeps the curve", "[nurbs][refine]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(2000 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    std::vector<double> b;
    for (double x : r.knots)
      if (x >= r.lo && x <= r.hi && (b.empty() || b.back() != x)) b.push_back(x);
    std::vector<double> mids;
    for (std::size_t i = 0; i + 1 < b.size(); ++i) mids.push_back(0.5 * (b[i] + b[i + 1]));
    const Curve c2 = refine_midpoints(r.c);
    CHECK_NOTHROW(validate(c2));
    CHECK(defining_knots(c2) == merged(r, mids));
    CHECK(segment_count(c2) == 2 * segment_count(r.c));
    CHECK(moved(r, c2, rng) <= 1.0);
    if (r.kind != Kind::closed) {
      const auto [e_boehm, e_blossom] = check_open_points(r, c2, mids);
      CHECK(e_boehm <= 1e-12);
      CHECK(e_blossom <= 1e-12);
    }
  }
}

// refine has two branches for open curves (see nurbs/src/refine.cpp): Boehm's insertion (A5.4) when
// its chains of combinations are short, S ≤ max(16, d + 1), S being the largest number of new knots
// in d + 1 consecutive old intervals; blossoms otherwise. Both must give the padded spline's blossoms.

TEST_CASE("refine: both branches give the long-double blossoms of the padded spline to 1e-14",
          "[nurbs][refine]") {
  double worst_boehm = 0, worst_blossom = 0;
  for (int seed = 0; seed < 400; ++seed) {
    Rng rng(8000 + seed);
    const int d = uniform_int(rng, 1, 10);
    const auto kind = coin(rng) ? Kind::clamped : Kind::unclamped;
    const RandomCurve r = random_curve(rng, d, uniform_int(rng, 1, 4), coin(rng), kind, 12);
    // 1..6 knots in every span, or up to 40 in a few: both sides of the limit.
    const auto spans = domain_spans(r);
    std::vector<int> chosen;
    for (int s : spans)
      if (coin(rng, 0.7)) chosen.push_back(s);
    if (chosen.empty()) chosen.push_back(spans.front());
    const int per = coin(rng) ? uniform_int(rng, 1, 6) : uniform_int(rng, 1, 40);
    const std::vector<double> X = knots_in_spans(rng, r.knots, chosen, per);
    INFO("seed " << seed << ": " << X.size() << " knots, " << per << " per span: " << r.what);
    const Curve c2 = refine(r.c, X);
    CHECK(defining_knots(c2) == merged(r, X));
    const double e = refined_error(r, c2);
    CHECK(e <= 1e-14);
    const RefSpline boehm = textbook_refine(RefSpline{d, r.knots, r.H}, X);
    (boehm.P == c2.P ? worst_boehm : worst_blossom) =
        std::max(boehm.P == c2.P ? worst_boehm : worst_blossom, e);
  }
  INFO("largest errors: Boehm " << worst_boehm << ", blossoms " << worst_blossom);
  CHECK(worst_boehm > 0);  // both branches ran
  CHECK(worst_blossom > 0);
}

TEST_CASE("refine takes Boehm's branch up to the chain limit and blossoms beyond", "[nurbs][refine]") {
  // All new knots in one span make S their number. Up to the limit the points are A5.4's to the last
  // bit; one more, and they are blossoms, whose rounding differs from A5.4's somewhere.
  for (int seed = 0; seed < 120; ++seed) {
    Rng rng(9000 + seed);
    const int d = uniform_int(rng, 1, 20);
    const auto kind = coin(rng) ? Kind::clamped : Kind::unclamped;
    const RandomCurve r = random_curve(rng, d, uniform_int(rng, 1, 4), coin(rng), kind, 6, 3);
    const auto spans = domain_spans(r);
    const int span = spans[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(spans.size()) - 1))];
    const int limit = std::max(16, d + 1);
    INFO("seed " << seed << " span " << span << " limit " << limit << ": " << r.what);
    for (int count : {limit, limit + 1}) {
      std::vector<double> X;
      const double a = r.knots[static_cast<std::size_t>(span)],
                   b = r.knots[static_cast<std::size_t>(span + 1)];
      for (int k = 1; k <= count; ++k) X.push_back(a + (b - a) * k / (count + 1));
      const Curve c2 = refine(r.c, X);
      const RefSpline boehm = textbook_refine(RefSpline{d, r.knots, r.H}, X);
      INFO(count << " knots");
      CHECK(c2.knots == boehm.t);
      CHECK((c2.P == boehm.P) == (count == limit));
      CHECK(refined_error(r, c2) <= 1e-14);
    }
  }
}

TEST_CASE("refine: 65 535 knots in one span take the blossom branch and stay within 1e-14",
          "[nurbs][refine]") {
  // Boehm's chains would run through all of them (A5.4: about 1e-12 here).
  Rng rng(65535);
  const RandomCurve r = random_curve(rng, 3, 3, true, Kind::unclamped, 4, 3);
  const int span = domain_spans(r)[1];
  const double a = r.knots[static_cast<std::size_t>(span)], b = r.knots[static_cast<std::size_t>(span + 1)];
  std::vector<double> X;
  for (int k = 1; k < 65536; ++k) X.push_back(a + (b - a) * k / 65536);
  const Curve c2 = refine(r.c, X);
  const RefSpline boehm = textbook_refine(RefSpline{3, r.knots, r.H}, X);
  const double e = refined_error(r, c2), e_boehm = diff(boehm.P, c2.P) / max_abs(r.H);
  INFO(r.what << ": refine " << e << ", A5.4 differs by " << e_boehm);
  CHECK(e <= 1e-14);
  CHECK(e_boehm > 10 * e);
  Rng probe(1);
  CHECK(moved(r, c2, probe) <= 1.0);
}

TEST_CASE("split_bezier: one clamped piece per span, equal to the curve there, joined", "[nurbs][refine]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(3000 + seed);
    const RandomCurve r = any_curve(rng);
    INFO("seed " << seed << ": " << r.what);
    const int d = r.degree;
    const auto pieces = split_bezier(r.c);
    REQUIRE(static_cast<int>(pieces.size()) == segment_count(r.c));
    std::vector<double> b;
    for (double x : r.knots)
      if (x >= r.lo && x <= r.hi && (b.empty() || b.back() != x)) b.push_back(x);
    double worst = 0, joins = 0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const Curve& p = pieces[i];
      CHECK_NOTHROW(validate(p));
      CHECK(p.degree == d);
      CHECK(p.rational == r.rational);
      CHECK_FALSE(p.closed);
      Knots expected(static_cast<std::size_t>(d + 1), b[i]);
      expected.insert(expected.end(), static_cast<std::size_t>(d + 1), b[i + 1]);
      CHECK(p.knots == expected);
      for (int k = 0; k <= 20; ++k) {
        const double u = k == 20 ? b[i + 1] : b[i] + (b[i + 1] - b[i]) * k / 20;
        // The piece on [b_i, b_{i+1}] is the curve's polynomial there (left limit at its end).
        const Points D = ref_derivatives(r, u == b[i + 1] ? std::nextafter(u, -HUGE_VAL) : u, 1);
        const double allowed =
            1e-12 * r.scale + 4 * D.row(1).cwiseAbs().maxCoeff() * (std::nextafter(u, HUGE_VAL) - u);
        worst = std::max(worst, diff(evaluate(p, u), D.row(0)) / allowed);
      }
      if (i > 0) joins = std::max(joins, diff(pieces[i - 1].P.bottomRows(1), p.P.topRows(1)) / max_abs(r.H));
    }
    CHECK(worst <= 1.0);
    CHECK(joins <= 1e-12);
  }
}

TEST_CASE("elevate_degree 1..3 times: same curve, each domain knot gains the same multiplicity",
          "[nurbs][refine]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(4000 + seed);
    const int d = uniform_int(rng, 1, 7);
    const auto kind = static_cast<Kind>(uniform_int(rng, 0, 2));
    const RandomCurve r = random_curve(rng, d, uniform_int(rng, 1, 4), coin(rng), kind, 6);
    const int times = uniform_int(rng, 1, 3);
    INFO("seed " << seed << " times " << times << ": " << r.what);
    const Curve c2 = elevate_degree(r.c, times);
    CHECK_NOTHROW(validate(c2));
    CHECK(c2.degree == d + times);
    CHECK(c2.closed == r.c.closed);
    CHECK(c2.rational == r.rational);
    CHECK(domain(c2).start == r.lo);
    CHECK(domain(c2).end == r.hi);
    // Multiplicities: +times for every value of the domain (the seam counted once). Open curves keep
    // as many knots before and after the domain, taken from the old outer values.
    const auto before = multiplicities(r.knots);
    const auto after = multiplicities(c2.knots);
    bool mult_ok = true;
    for (const auto& [x, m] : before)
      if (x >= r.lo && (kind == Kind::closed ? x < r.hi : x <= r.hi) &&
          (after.count(x) ? after.at(x) : 0) != m + times)
        mult_ok = false;
    if (kind != Kind::closed) {
      auto outside = [&](const Knots& t, bool low) {
        return std::count_if(t.begin(), t.end(), [&](double x) { return low ? x < r.lo : x > r.hi; });
      };
      mult_ok = mult_ok && outside(c2.knots, true) == outside(r.knots, true) &&
                outside(c2.knots, false) == outside(r.knots, false);
      for (const auto& [x, m] : after)
        if (!before.count(x)) mult_ok = false;
    }
    CHECK(mult_ok);
    CHECK(moved(r, c2, rng) <= 1.0);
    CHECK(elevate_degree(r.c, 0).P == r.c.P);
  }
}

namespace {

/// Inserts a knot 1..d−s times into a random open curve and removes it again: all copies go, the
/// old knots and points come back (points within 1e-12), and the removal keeps its promises.
void round_trip(int seed, int mode) {
  Rng rng(seed);
  const auto kind = coin(rng) ? Kind::clamped : Kind::unclamped;
  const RandomCurve r =
      random_curve(rng, uniform_int(rng, 1, 10), uniform_int(rng, 1, 4), coin(rng), kind, 8, mode);
  INFO("seed " << seed << ": " << r.what);
  auto mult = multiplicities(r.knots);
  double u = uniform(rng, r.lo, r.hi);
  if (coin(rng)) {
    std::vector<double> inner;
    for (double x : r.knots)
      if (x > r.lo && x < r.hi) inner.push_back(x);
    if (!inner.empty())
      u = inner[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(inner.size()) - 1))];
  }
  if (!(u > r.lo && u < r.hi) || mult[u] >= r.degree) return;
  const int times = uniform_int(rng, 1, r.degree - mult[u]);
  INFO("u " << u << " x" << times);
  const Curve c2 = insert_knot(r.c, u, times);
  // Tolerance: round-off of the homogeneous points, seen through the smallest weight.
  const double wr = r.rational ? r.w.maxCoeff() / r.w.minCoeff() : 1.0;
  const double tol = 1e-9 * r.scale * wr;
  const Removal back = remove_knot(c2, u, times, tol);
  CHECK(back.deviation_bound <= tol);
  CHECK_NOTHROW(validate(back.curve));
  CHECK(back.curve.P.rows() == c2.P.rows() - back.removed);
  CHECK(back.removed == times);
  CHECK(back.curve.knots == r.knots);
  REQUIRE(back.curve.P.rows() == r.H.rows());
  CHECK(diff(back.curve.P, r.H) / (1e-12 * max_abs(r.H)) <= 1.0);
  // Equal homogeneous points within δ move a rational curve by up to δ·(1 + |C|)/w_min.
  CHECK(moved(r, back.curve, rng) <= (r.rational ? wr * (1 + r.scale) * (1 + r.scale) / r.scale : 1.0));
}

}  // namespace

TEST_CASE("elevating a Bézier curve gives the textbook points", "[nurbs][refine]") {
  // One span: Q_i = (i/(p+1)) P_{i−1} + (1 − i/(p+1)) P_i, and again for the next degree.
  for (int seed = 0; seed < 100; ++seed) {
    Rng rng(7000 + seed);
    const int p = uniform_int(rng, 1, 10);
    const double a = uniform(rng, -2, 0), b = a + std::pow(10.0, uniform(rng, -3, 1));
    Knots t(static_cast<std::size_t>(p + 1), a);
    t.insert(t.end(), static_cast<std::size_t>(p + 1), b);
    const bool rational = coin(rng);
    const Points cart = random_points(rng, p + 1, uniform_int(rng, 1, 4));
    const Eigen::VectorXd w = rational ? random_weights(rng, p + 1) : Eigen::VectorXd();
    const Curve c = make_curve(p, t, cart, w);
    const int times = uniform_int(rng, 1, 3);
    Points Q = to_rows(cart, w);
    for (int k = 0; k < times; ++k) {
      const int q = p + k;  // current degree
      Points R = Points::Zero(q + 2, Q.cols());
      for (int i = 0; i <= q + 1; ++i) {
        const double f = static_cast<double>(i) / (q + 1);
        if (i > 0) R.row(i) += f * Q.row(i - 1);
        if (i <= q) R.row(i) += (1 - f) * Q.row(i);
      }
      Q = R;
    }
    INFO("seed " << seed << " degree " << p << " times " << times);
    const Curve e = elevate_degree(c, times);
    Knots expected(static_cast<std::size_t>(p + times + 1), a);
    expected.insert(expected.end(), static_cast<std::size_t>(p + times + 1), b);
    CHECK(e.knots == expected);
    REQUIRE(e.P.rows() == Q.rows());
    CHECK(diff(e.P, Q) / (1e-12 * max_abs(Q)) <= 1.0);
  }
}

TEST_CASE("remove_knot removes a knot inserted next to a knot of multiplicity d", "[nurbs][refine]") {
  // Regression: solving the removal equations from both ends towards the middle divides by
  // α = (u − 1)/(t_{i+p+1} − 1) ≈ 0.02 at every step on the left here.
  for (int d : {5, 7, 9}) {
    Knots t(static_cast<std::size_t>(d + 1), 0.0);
    t.insert(t.end(), static_cast<std::size_t>(d), 1.0);
    t.insert(t.end(), {2.0, 3.0});
    t.insert(t.end(), static_cast<std::size_t>(d + 1), 4.0);
    Rng rng(static_cast<std::uint64_t>(d));
    const Points P = random_points(rng, static_cast<Eigen::Index>(t.size()) - d - 1, 3);
    const Curve c = make_curve(d, t, P);
    for (int times = 1; times <= d - 1; ++times) {
      INFO("degree " << d << " times " << times);
      const Curve c2 = insert_knot(c, 1.05, times);
      const Removal back = remove_knot(c2, 1.05, times, 1e-9 * max_abs(P));
      CHECK(back.removed == times);
      CHECK(back.curve.knots == t);
      CHECK(diff(back.curve.P, P) / (1e-12 * max_abs(P)) <= 1.0);
    }
  }
}

TEST_CASE("remove_knot round-trips insert_knot", "[nurbs][refine]") {
  for (int seed = 0; seed < 600; ++seed) round_trip(5000 + seed, seed % 4);
}

TEST_CASE("remove_knot keeps essential knots at tolerance 0 and respects a tolerance", "[nurbs][refine]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(6000 + seed);
    const auto kind = coin(rng) ? Kind::clamped : Kind::unclamped;
    const RandomCurve r = random_curve(rng, uniform_int(rng, 1, 8), uniform_int(rng, 1, 4), coin(rng), kind);
    INFO("seed " << seed << ": " << r.what);
    std::vector<double> inner;
    for (double x : r.knots)
      if (x > r.lo && x < r.hi && (inner.empty() || inner.back() != x)) inner.push_back(x);
    if (inner.empty()) continue;
    const double u = inner[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(inner.size()) - 1))];
    const int s = static_cast<int>(std::count(r.knots.begin(), r.knots.end(), u));
    INFO("u " << u << " multiplicity " << s);
    // Random control points make every knot essential.
    const Removal none = remove_knot(r.c, u, s, 0.0);
    CHECK(none.removed == 0);
    CHECK(none.deviation_bound == 0.0);
    CHECK(none.curve.knots == r.c.knots);
    CHECK(none.curve.P == r.c.P);
    // With a tolerance: the bound holds, and the sampled deviation stays under the bound.
    const double tol = r.scale * std::pow(10.0, uniform(rng, -4, 0.5));
    const int times = uniform_int(rng, 1, s + 1);
    const Removal some = remove_knot(r.c, u, times, tol);
    CHECK(some.removed >= 0);
    CHECK(some.removed <= std::min(times, s));
    CHECK(some.deviation_bound <= tol);
    CHECK_NOTHROW(validate(some.curve));
    CHECK(std::count(some.curve.knots.begin(), some.curve.knots.end(), u) == s - some.removed);
    CHECK(some.curve.P.rows() == r.H.rows() - some.removed);
    double dev = 0;
    for (double x : probe_parameters(rng, r.knots, r.degree, 200))
      dev = std::max(dev, (evaluate(some.curve, x) - ref_point(r, x)).norm());
    CHECK(dev <= some.deviation_bound * (1 + 1e-9) + 1e-12 * r.scale);
  }
}

TEST_CASE("refinement, elevation and splitting keep the circle exact", "[nurbs][refine]") {
  const double s = std::sqrt(0.5);
  Points P(9, 2);
  P << 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0;
  Eigen::VectorXd w(9);
  w << 1, s, 1, s, 1, s, 1, s, 1;
  const Curve circle = make_curve(2, {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}, P, w);
  // The same circle, closed: 8 distinct points, a double knot at every quarter (the seam too).
  Points Pc(8, 2);
  Pc << 1, -1, 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1;
  Eigen::VectorXd wc(8);
  wc << s, 1, s, 1, s, 1, s, 1;
  const Curve closed = make_closed_curve(2, {0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1}, Pc, wc);
  std::vector<Curve> shapes{refine_midpoints(refine_midpoints(circle)),
                            elevate_degree(circle, 2),
                            insert_knot(circle, 0.3, 2),
                            refine(circle, std::vector<double>{0.1, 0.6, 0.6, 0.9}),
                            closed,
                            refine_midpoints(closed),
                            elevate_degree(closed, 3),
                            insert_knot(closed, 0.1),
                            refine(closed, std::vector<double>{0.1, 0.6, 0.6, 1.9})};
  for (const Curve& p : split_bezier(circle)) shapes.push_back(p);
  for (const Curve& c : shapes) {
    double radius = 0;
    const Domain dom = domain(c);
    for (int i = 0; i <= 500; ++i)
      radius =
          std::max(radius, std::abs(evaluate(c, dom.start + (dom.end - dom.start) * i / 500).norm() - 1));
    CHECK(radius <= 8 * kEps);
  }
}

TEST_CASE("insertion, refinement, elevation and removal reject bad arguments", "[nurbs][refine]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Curve c = make_curve(3, {0, 0, 0, 0, 1, 2, 2, 3, 3, 3, 3}, Points::Random(7, 2));
  // Outside the domain and not finite.
  CHECK_THROWS_WITH(insert_knot(c, -0.5), Contains("outside the domain"));
  CHECK_THROWS_WITH(insert_knot(c, std::nextafter(3.0, 4.0)), Contains("outside the domain"));
  CHECK_THROWS_WITH(insert_knot(c, nan), Contains("not finite"));
  CHECK_THROWS_WITH(insert_knot(c, HUGE_VAL), Contains("not finite"));
  CHECK_THROWS_WITH(refine(c, std::vector<double>{0.5, 1.5, nan}),
                    Contains("knot 2") && Contains("not finite"));
  CHECK_THROWS_WITH(refine(c, std::vector<double>{0.5, 4.0}), Contains("knot 4"));
  // Multiplicity above the degree.
  CHECK_THROWS_WITH(insert_knot(c, 2.0, 2), Contains("multiplicity 4"));
  CHECK_THROWS_WITH(insert_knot(c, 0.0), Contains("multiplicity"));  // clamped end
  CHECK_THROWS_WITH(insert_knot(c, 1.5, 4), Contains("multiplicity"));
  CHECK_THROWS_WITH(refine(c, std::vector<double>{1.0, 0.5, 1.0, 1.0}), Contains("multiplicity"));
  CHECK_NOTHROW(insert_knot(c, 2.0, 1));
  CHECK_NOTHROW(insert_knot(c, 1.5, 3));
  CHECK_THROWS_WITH(insert_knot(c, 1.5, 0), Contains("times"));
  // Closed curves wrap the knots into the period, but keep the multiplicity limit (seam included).
  const Curve closed = make_closed_curve(2, {0, 0, 1, 2, 3}, Points::Random(4, 2));
  CHECK_THROWS_WITH(insert_knot(closed, 3.0), Contains("multiplicity"));
  CHECK_THROWS_WITH(insert_knot(closed, 0.0), Contains("multiplicity"));
  CHECK_THROWS_WITH(insert_knot(closed, nan), Contains("not finite"));
  CHECK_NOTHROW(insert_knot(closed, 4.5));
  CHECK(defining_knots(insert_knot(closed, 4.5)) == Knots{0, 0, 1, 1.5, 2, 3});
  // Elevation.
  CHECK_THROWS_WITH(elevate_degree(c, -1), Contains("negative"));
  CHECK_THROWS_WITH(elevate_degree(c, kMaxDegree), Contains("exceeds"));
  // Removal.
  CHECK_THROWS_WITH(remove_knot(closed, 1.0, 1, 0.0), Contains("closed"));
  CHECK_THROWS_WITH(remove_knot(c, 0.0, 1, 0.0), Contains("not interior"));
  CHECK_THROWS_WITH(remove_knot(c, 3.0, 1, 0.0), Contains("not interior"));
  CHECK_THROWS_WITH(remove_knot(c, 5.0, 1, 0.0), Contains("not interior"));
  CHECK_THROWS_WITH(remove_knot(c, nan, 1, 0.0), Contains("not interior"));
  CHECK_THROWS_WITH(remove_knot(c, 1.5, 1, 0.0), Contains("not a knot"));
  CHECK_THROWS_WITH(remove_knot(c, 1.0, -1, 0.0), Contains("negative"));
  CHECK_THROWS_WITH(remove_knot(c, 1.0, 1, -1.0), Contains("tolerance"));
  CHECK_THROWS_WITH(remove_knot(c, 1.0, 1, nan), Contains("tolerance"));
  CHECK(remove_knot(c, 1.0, 0, 1.0).removed == 0);
}

TEST_CASE("insert_knot refuses a count above the degree before making the copies", "[nurbs][reliability]") {
  // times = 10^9 allocated 8 GB of copies before refine refused them (issue 33).
  const Curve c = make_curve(3, {0, 0, 0, 0, 1, 2, 2, 2, 2}, Points::Random(5, 2));
  CHECK_THROWS_WITH(insert_knot(c, 1.5, 1000000000),
                    "knot 1.5 would reach multiplicity 1000000000 > degree 3");
  CHECK_THROWS_WITH(insert_knot(c, 1, 3), "knot 1 would reach multiplicity 4 > degree 3");
  CHECK(insert_knot(c, 1.5, 3).P.rows() == 8);
}

TEST_CASE("split: both parts are the curve, clamped at the cut", "[nurbs][refine][split]") {
  Rng rng(3030);
  for (int trial = 0; trial < 300; ++trial) {
    const int d = uniform_int(rng, 1, 7);
    const Kind kind = coin(rng) ? Kind::clamped : Kind::unclamped;
    const RandomCurve r = random_curve(rng, d, uniform_int(rng, 1, 3), coin(rng, 0.3), kind);
    CAPTURE(trial, r.what);
    // A knot of the curve or any parameter inside the domain.
    double u = uniform(rng, r.lo, r.hi);
    if (coin(rng, 0.3))
      u = r.knots[static_cast<std::size_t>(uniform_int(rng, d, static_cast<int>(r.H.rows())))];
    if (!(u > r.lo && u < r.hi)) continue;
    const auto [left, right] = split(r.c, u);
    CHECK(domain(left).start == r.lo);
    CHECK(domain(left).end == u);
    CHECK(domain(right).start == u);
    CHECK(domain(right).end == r.hi);
    CHECK(multiplicity(left.knots, u) == d + 1);
    CHECK(multiplicity(right.knots, u) == d + 1);
    for (int s = 0; s <= 8; ++s) {
      const double a = s == 8 ? u : r.lo + (u - r.lo) * s / 8, b = s == 8 ? r.hi : u + (r.hi - u) * s / 8;
      CHECK(diff(evaluate(left, a), ref_point(r, a)) <= 1e-12 * r.scale);
      CHECK(diff(evaluate(right, b), ref_point(r, b)) <= 1e-12 * r.scale);
    }
  }
  const RandomCurve closed = random_curve(rng, 3, 2, false, Kind::closed);
  CHECK_THROWS_WITH(split(closed.c, 0.5 * (closed.lo + closed.hi)), Contains("closed curve"));
  const RandomCurve open = random_curve(rng, 2, 2, false, Kind::clamped);
  CHECK_THROWS_WITH(split(open.c, open.lo), Contains("not strictly inside the domain"));
  CHECK_THROWS_WITH(split(open.c, NAN), Contains("not strictly inside the domain"));
}

TEST_CASE("reverse: C'(a + b − u) = C(u), open and closed, twice is the identity",
          "[nurbs][refine][reverse]") {
  Rng rng(3031);
  for (int trial = 0; trial < 300; ++trial) {
    const int d = uniform_int(rng, 1, 7);
    const auto kind = static_cast<Kind>(uniform_int(rng, 0, 2));
    const RandomCurve r = random_curve(rng, d, uniform_int(rng, 1, 3), coin(rng, 0.3), kind);
    CAPTURE(trial, r.what);
    const Curve back = reverse(r.c);
    CHECK(domain(back).start == r.lo);
    CHECK(domain(back).end == r.hi);
    CHECK(back.closed == r.c.closed);
    for (int s = 0; s <= 16; ++s) {
      const double u = s == 16 ? r.hi : r.lo + (r.hi - r.lo) * s / 16;
      const double mirrored = s == 0 ? r.hi : s == 16 ? r.lo : r.lo + r.hi - u;
      // a + b − u rounds: the parameter moves by up to an ulp of |a| + |b|, the point by that times |C'|.
      const double slack =
          4 * kEps * (std::abs(r.lo) + std::abs(r.hi)) * derivatives(r.c, u, 1).row(1).norm();
      CHECK(diff(evaluate(back, mirrored), ref_point(r, u)) <= 1e-12 * r.scale + slack);
    }
    CHECK(reverse(back).P == r.c.P);
  }
}
