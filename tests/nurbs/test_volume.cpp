// SPDX-License-Identifier: MIT
// Trivariate volumes: evaluation against the long-double triple sum of the Cox–de Boor basis, knot
// insertion in each direction against the volume before it, a trilinear volume exactly, and refusals.
#include <catch2/catch.hpp>
#include <cmath>

#include "cifs/errors.hpp"
#include "cifs/nurbs/volume.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

struct RandomVolume {
  Volume v;
  Points H;
  double scale = 1;
};

RandomVolume random_volume(Rng& rng) {
  std::array<int, 3> degree{};
  std::array<Knots, 3> knots;
  std::array<Eigen::Index, 3> count{};
  for (std::size_t d = 0; d < 3; ++d) {
    degree[d] = uniform_int(rng, 1, 4);
    count[d] = degree[d] + 1 + uniform_int(rng, 0, 3);
    knots[d] = random_knots(rng, degree[d], static_cast<int>(count[d]), coin(rng));
  }
  const Eigen::Index rows = count[0] * count[1] * count[2];
  const Points cart = random_points(rng, rows, uniform_int(rng, 1, 3));
  Eigen::VectorXd w;
  if (coin(rng)) {
    w.resize(rows);
    for (Eigen::Index i = 0; i < rows; ++i) w(i) = std::pow(2.0, uniform(rng, -1, 1));
  }
  return {make_volume(degree, knots, count, cart, w), to_rows(cart, w), cart.cwiseAbs().maxCoeff()};
}

/// Σ N_i(u) M_j(v) L_k(w) H_ijk in long double, projected when rational.
Point reference(const RandomVolume& r, double u, double v, double w) {
  const Volume& x = r.v;
  const double at[3] = {u, v, w};
  std::array<RealVec, 3> N;
  for (std::size_t d = 0; d < 3; ++d)
    N[d] = ref_basis(x.knots[d], x.degree[d], at[d], at_end(x.knots[d], x.degree[d], at[d]));
  Eigen::Matrix<Real, 1, Eigen::Dynamic> sum = Eigen::Matrix<Real, 1, Eigen::Dynamic>::Zero(r.H.cols());
  // Every term of the sum, the zero ones skipped (they add nothing; an Eigen row each under ASan).
  for (Eigen::Index i = 0; i < x.count[0]; ++i) {
    const Real ni = N[0][static_cast<std::size_t>(i)];
    if (ni == 0) continue;
    for (Eigen::Index j = 0; j < x.count[1]; ++j) {
      const Real nij = ni * N[1][static_cast<std::size_t>(j)];
      if (nij == 0) continue;
      for (Eigen::Index k = 0; k < x.count[2]; ++k)
        if (const Real n = nij * N[2][static_cast<std::size_t>(k)]; n != 0)
          sum += n * r.H.row((i * x.count[1] + j) * x.count[2] + k).cast<Real>();
    }
  }
  const Eigen::Index dim = dimension(x);
  if (!x.rational) return sum.cast<double>();
  return (sum.head(dim) / sum(dim)).cast<double>();
}

std::vector<double> probes(Rng& rng, const Volume& v, std::size_t d) {
  return probe_parameters(rng, v.knots[d], v.degree[d], 3);
}

/// The domain's ends and three random parameters of direction d (few: the operations' tests visit a grid).
std::vector<double> volume_samples(Rng& rng, const Volume& v, std::size_t d) {
  const Domain dom = domain(v.knots[d], v.degree[d]);
  return {dom.start, dom.end, uniform(rng, dom.start, dom.end), uniform(rng, dom.start, dom.end),
          uniform(rng, dom.start, dom.end)};
}

/// The largest distance between `changed` at map(u, v, w) and the reference of r at (u, v, w), over a
/// sample grid of r's domain, relative to the net's size.
template <class Map>
double volume_motion(Rng& rng, const RandomVolume& r, Map&& map) {
  double worst = 0;
  for (double u : volume_samples(rng, r.v, 0))
    for (double v : volume_samples(rng, r.v, 1))
      for (double w : volume_samples(rng, r.v, 2))
        worst = std::max(worst, diff(map(u, v, w), reference(r, u, v, w)));
  return worst / r.scale;
}

}  // namespace

TEST_CASE("volumes evaluate to the triple sum of their basis", "[nurbs][volume]") {
  Rng rng(3101);
  for (int trial = 0; trial < 30; ++trial) {
    const RandomVolume r = random_volume(rng);
    CAPTURE(trial, r.v.degree[0], r.v.degree[1], r.v.degree[2], r.v.rational);
    for (double u : probes(rng, r.v, 0))
      for (double v : probes(rng, r.v, 1))
        for (double w : probes(rng, r.v, 2))
          CHECK(diff(evaluate(r.v, u, v, w), reference(r, u, v, w)) <= 1e-13 * r.scale);
  }
}

TEST_CASE("volume knot insertion keeps the volume in every direction", "[nurbs][volume]") {
  Rng rng(3102);
  for (int trial = 0; trial < 30; ++trial) {
    const RandomVolume r = random_volume(rng);
    const int d = trial % 3;
    const auto sd = static_cast<std::size_t>(d);
    const Domain dom = domain(r.v.knots[sd], r.v.degree[sd]);
    const double t = uniform(rng, dom.start, dom.end);
    const int times = uniform_int(rng, 1, r.v.degree[sd]);
    CAPTURE(trial, d, t, times);
    const Volume x = insert_knot(r.v, d, t, times);
    CHECK(x.count[sd] == r.v.count[sd] + times);
    CHECK(multiplicity(x.knots[sd], t) == times);
    for (std::size_t o = 0; o < 3; ++o)
      if (o != sd) CHECK(x.count[o] == r.v.count[o]);
    for (double u : probes(rng, r.v, 0))
      for (double v : probes(rng, r.v, 1))
        for (double w : probes(rng, r.v, 2))
          CHECK(diff(evaluate(x, u, v, w), reference(r, u, v, w)) <= 1e-13 * r.scale);
  }
}

TEST_CASE("a trilinear volume is exact at dyadic parameters", "[nurbs][volume]") {
  // Corners (i, j, k) ↦ (i + 2j, 3k − j, i·j·k): the trilinear interpolant, by hand.
  Points corners(8, 3);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) corners.row((i * 2 + j) * 2 + k) << i + 2 * j, 3 * k - j, i * j * k;
  const Volume cube =
      make_volume({1, 1, 1}, {Knots{0, 0, 1, 1}, Knots{0, 0, 1, 1}, Knots{0, 0, 1, 1}}, {2, 2, 2}, corners);
  for (double u : {0.0, 0.25, 0.5, 1.0})
    for (double v : {0.0, 0.125, 0.75})
      for (double w : {0.0, 0.5, 1.0}) {
        Point expected(3);
        expected << u + 2 * v, 3 * w - v, u * v * w;
        CHECK(evaluate(cube, u, v, w) == expected);
        CHECK(evaluate(insert_knot(cube, 2, 0.5), u, v, w) == expected);
      }
}

TEST_CASE("volumes refuse bad input in one line", "[nurbs][volume]") {
  const Knots t{0, 0, 1, 1};
  const Points corners = Points::Zero(8, 3);
  CHECK_THROWS_WITH(make_volume({1, 1, 1}, {t, t, t}, {2, 2, 3}, corners),
                    Contains("points: 8 control points do not form a 2 by 2 by 3 net"));
  CHECK_THROWS_WITH(make_volume({1, 1, 2}, {t, t, t}, {2, 2, 2}, corners), Contains("knots[2]"));
  Eigen::VectorXd w = Eigen::VectorXd::Ones(8);
  w(5) = 0;
  CHECK_THROWS_WITH(make_volume({1, 1, 1}, {t, t, t}, {2, 2, 2}, corners, w),
                    Contains("weights[5]: weight 0"));
  const Volume cube = make_volume({1, 1, 1}, {t, t, t}, {2, 2, 2}, corners);
  CHECK_THROWS_WITH(evaluate(cube, 0.5, 1.5, 0), Contains("parameter v = 1.5 is outside the domain [0, 1]"));
  CHECK_THROWS_WITH(insert_knot(cube, 3, 0.5), Contains("direction 3 is not u (0), v (1) or w (2)"));
  CHECK_THROWS_WITH(insert_knot(cube, 1, 2.0), Contains("direction v: "));
}

TEST_CASE("volume refinement, elevation, reversal and reparametrisation keep the volume", "[nurbs][volume]") {
  Rng rng(3103);
  for (int trial = 0; trial < 24; ++trial) {
    const RandomVolume r = random_volume(rng);
    const int d = trial % 3;
    const auto sd = static_cast<std::size_t>(d);
    const Domain dom = domain(r.v.knots[sd], r.v.degree[sd]);
    CAPTURE(trial, d, r.v.rational);
    // Several knots at once, one of them repeated.
    const double t = uniform(rng, dom.start, dom.end);
    const std::vector<double> knots{t, uniform(rng, dom.start, dom.end),
                                    r.v.degree[sd] > 1 ? t : uniform(rng, dom.start, dom.end)};
    const Volume x = refine(r.v, d, knots);
    CHECK(x.count[sd] == r.v.count[sd] + 3);
    CHECK(volume_motion(rng, r, [&](double u, double v, double w) { return evaluate(x, u, v, w); }) <= 1e-12);
    const int times = uniform_int(rng, 1, 2);
    const Volume e = elevate_degree(r.v, d, times);
    CHECK(e.degree[sd] == r.v.degree[sd] + times);
    CHECK(volume_motion(rng, r, [&](double u, double v, double w) { return evaluate(e, u, v, w); }) <= 1e-12);
    // Reversed: V'(…, a + b − t, …) = V(…, t, …).
    const Volume b = reverse(r.v, d);
    CHECK(volume_motion(rng, r, [&](double u, double v, double w) {
            std::array<double, 3> at{u, v, w};
            at[sd] = dom.start + dom.end - at[sd];
            at[sd] = std::min(dom.end, std::max(dom.start, at[sd]));
            return evaluate(b, at[0], at[1], at[2]);
          }) <= 1e-12);
    // On [−1, 3] in d, then every direction on [0, 1].
    const Volume m = reparametrize(r.v, d, -1.0, 3.0);
    CHECK(domain(m.knots[sd], m.degree[sd]).start == -1.0);
    CHECK(domain(m.knots[sd], m.degree[sd]).end == 3.0);
    CHECK(volume_motion(rng, r, [&](double u, double v, double w) {
            std::array<double, 3> at{u, v, w};
            at[sd] = std::min(3.0, -1.0 + (at[sd] - dom.start) * 4.0 / (dom.end - dom.start));
            return evaluate(m, at[0], at[1], at[2]);
          }) <= 1e-12);
    const Volume n = normalize_knots(r.v);
    CHECK(volume_motion(rng, r, [&](double u, double v, double w) {
            std::array<double, 3> at{u, v, w};
            for (std::size_t o = 0; o < 3; ++o) {
              const Domain od = domain(r.v.knots[o], r.v.degree[o]);
              at[o] = std::min(1.0, (at[o] - od.start) / (od.end - od.start));
            }
            return evaluate(n, at[0], at[1], at[2]);
          }) <= 1e-12);
  }
}

TEST_CASE("volume split and iso-surfaces are the volume's pieces and sections", "[nurbs][volume]") {
  Rng rng(3104);
  for (int trial = 0; trial < 24; ++trial) {
    const RandomVolume r = random_volume(rng);
    const int d = trial % 3;
    const auto sd = static_cast<std::size_t>(d);
    const Domain dom = domain(r.v.knots[sd], r.v.degree[sd]);
    const double t =
        uniform(rng, dom.start + 0.1 * (dom.end - dom.start), dom.end - 0.1 * (dom.end - dom.start));
    CAPTURE(trial, d, t, r.v.rational);
    const std::array<Volume, 2> parts = split(r.v, d, t);
    CHECK(domain(parts[0].knots[sd], parts[0].degree[sd]).end == t);
    CHECK(domain(parts[1].knots[sd], parts[1].degree[sd]).start == t);
    CHECK(volume_motion(rng, r, [&](double u, double v, double w) {
            const std::array<double, 3> at{u, v, w};
            return evaluate(parts[at[sd] <= t ? 0 : 1], u, v, w);
          }) <= 1e-12);
    // The section at t: S(the other two parameters) = V with t in direction d.
    const double s = uniform(rng, dom.start, dom.end);
    const Surface iso = iso_surface(r.v, d, s);
    CHECK(iso.rational == r.v.rational);
    const std::size_t first = d == 0 ? 1 : 0, second = d == 2 ? 1 : 2;
    double worst = 0;
    for (double a : volume_samples(rng, r.v, first))
      for (double b : volume_samples(rng, r.v, second)) {
        std::array<double, 3> at{};
        at[sd] = s;
        at[first] = a;
        at[second] = b;
        worst = std::max(worst, diff(evaluate(iso, a, b), reference(r, at[0], at[1], at[2])));
      }
    CHECK(worst <= 1e-12 * r.scale);
  }
}

TEST_CASE("volume knot removal takes every line of the net at once and bounds the motion",
          "[nurbs][volume]") {
  Rng rng(3105);
  for (int trial = 0; trial < 24; ++trial) {
    const RandomVolume r = random_volume(rng);
    const int d = trial % 3;
    const auto sd = static_cast<std::size_t>(d);
    const Domain dom = domain(r.v.knots[sd], r.v.degree[sd]);
    const double t = uniform(rng, dom.start, dom.end);
    if (multiplicity(r.v.knots[sd], t) > 0) continue;
    const int times = uniform_int(rng, 1, r.v.degree[sd]);
    CAPTURE(trial, d, t, times, r.v.rational);
    // Copies that were inserted go again, within rounding.
    const VolumeRemoval back = remove_knot(insert_knot(r.v, d, t, times), d, t, times + 1, 1e-9 * r.scale);
    CHECK(back.removed == times);
    CHECK(back.volume.count == r.v.count);
    CHECK(back.deviation_bound <= 1e-9 * r.scale);
    // `times` bounds the copies removed, even where more could go.
    if (times > 1) {
      const VolumeRemoval one = remove_knot(insert_knot(r.v, d, t, times), d, t, 1, 1e-9 * r.scale);
      CHECK(one.removed == 1);
      CHECK(multiplicity(one.volume.knots[sd], t) == times - 1);
    }
    CHECK(volume_motion(
              rng, r, [&](double u, double v, double w) { return evaluate(back.volume, u, v, w); }) <= 1e-11);
    // A knot of random data: nothing goes at tolerance 0 (the volume is the same), everything at a tolerance
    // larger than the net, and the measured motion stays within the proven bound.
    const Volume x = insert_knot(r.v, d, t, 1);
    Volume y = x;
    // One point of one line moved: a new point of the insertion (index span − 1 along d), so that the line
    // no longer has t as a removable knot while every other line still has.
    std::array<Eigen::Index, 3> at{};
    for (std::size_t o = 0; o < 3; ++o) at[o] = uniform_int(rng, 0, static_cast<int>(y.count[o]) - 1);
    at[sd] = find_span(y.knots[sd], y.degree[sd], t) - 1;
    y.P.row((at[0] * y.count[1] + at[1]) * y.count[2] + at[2]).head(dimension(y)).array() += 0.3 * r.scale;
    const VolumeRemoval none = remove_knot(y, d, t, 1, 0.0);
    CHECK(none.removed == 0);
    CHECK(none.volume.P == y.P);
    const VolumeRemoval all = remove_knot(y, d, t, 1, 1e3 * r.scale);
    CHECK(all.removed == 1);
    double moved = 0;
    for (double u : volume_samples(rng, y, 0))
      for (double v : volume_samples(rng, y, 1))
        for (double w : volume_samples(rng, y, 2))
          moved = std::max(moved, diff(evaluate(all.volume, u, v, w), evaluate(y, u, v, w)));
    CHECK(moved <= all.deviation_bound * (1 + 1e-12) + 1e-14 * r.scale);
  }
}

namespace {

/// The Bernstein coefficient of t^e in degree n: C(i, e) / C(n, e).
double monomial_coefficient(int n, int e, int i) {
  return i < e ? 0.0 : binomial(i, e) / binomial(n, e);
}

/// ∂^a/∂t^a of t^e, written out.
double monomial_derivative(int e, int a, double t) {
  if (a > e) return 0;
  double f = 1;
  for (int i = 0; i < a; ++i) f *= e - i;
  return f * std::pow(t, e - a);
}

}  // namespace

TEST_CASE("volume derivatives of a polynomial volume are the closed forms", "[nurbs][volume]") {
  // x = u³v²w, y = uvw, z = w² + u as a Bézier volume of degrees (3, 2, 2), refined at random knots in
  // every direction (non-uniform spans).
  const std::array<std::array<int, 3>, 4> monomials{{{3, 2, 1}, {1, 1, 1}, {0, 0, 2}, {1, 0, 0}}};
  const std::array<int, 4> coordinate{0, 1, 2, 2};
  Points P = Points::Zero(4 * 3 * 3, 3);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (std::size_t m = 0; m < monomials.size(); ++m)
          P((i * 3 + j) * 3 + k, coordinate[m]) += monomial_coefficient(3, monomials[m][0], i) *
                                                   monomial_coefficient(2, monomials[m][1], j) *
                                                   monomial_coefficient(2, monomials[m][2], k);
  Volume vol = make_volume({3, 2, 2},
                           {Knots{0, 0, 0, 0, 1, 1, 1, 1}, Knots{0, 0, 0, 1, 1, 1}, Knots{0, 0, 0, 1, 1, 1}},
                           {4, 3, 3}, P);
  Rng rng(3106);
  for (int d = 0; d < 3; ++d) {
    const std::vector<double> knots{uniform(rng, 0, 1), uniform(rng, 0, 1), 0.5, 0.5};
    vol = refine(vol, d, knots);
  }
  const int order = 4;
  const int n = order + 1;
  for (int trial = 0; trial < 12; ++trial) {
    const double at[3] = {uniform(rng, 0, 1), trial == 0 ? 1.0 : uniform(rng, 0, 1),
                          trial == 1 ? 0.5 : uniform(rng, 0, 1)};
    const Points D = derivatives(vol, at[0], at[1], at[2], order);
    REQUIRE(D.rows() == n * n * n);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        for (int c = 0; c < n; ++c) {
          Point expected = Point::Zero(3);
          if (a + b + c <= order)
            for (std::size_t m = 0; m < monomials.size(); ++m)
              expected(coordinate[m]) += monomial_derivative(monomials[m][0], a, at[0]) *
                                         monomial_derivative(monomials[m][1], b, at[1]) *
                                         monomial_derivative(monomials[m][2], c, at[2]);
          CAPTURE(trial, a, b, c);
          // Rounding grows with the sizes of the basis functions' derivatives (1/span per order): the
          // tolerance is relative to Σ|N^(a)| Σ|M^(b)| Σ|L^(c)| (the control points are at most 1).
          double size = 1;
          const int k[3] = {a, b, c};
          for (std::size_t d = 0; d < 3; ++d) {
            const int span = find_span(vol.knots[d], vol.degree[d], at[d]);
            const Eigen::MatrixXd B = basis_derivatives(vol.knots[d], vol.degree[d], span, at[d], order);
            size *= B.row(k[d]).cwiseAbs().sum();
          }
          CHECK(diff(D.row((a * n + b) * n + c), expected) <= 1e-13 * (1 + expected.norm() + size));
        }
  }
}

TEST_CASE("rational volume derivatives: Leibniz with the weight gives the homogeneous ones, and differences",
          "[nurbs][volume]") {
  Rng rng(3107);
  int rational = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const RandomVolume r = random_volume(rng);
    const Volume& x = r.v;
    // The homogeneous rows as a polynomial volume of one more coordinate: its derivatives are ∂(w·V), ∂w.
    const Volume h = make_volume(x.degree, x.knots, x.count, x.P);
    const int order = 3, n = order + 1, dim = dimension(x);
    // Each parameter in the middle half of a random non-empty span of length span_length[d] (differences with
    // steps relative to it stay inside the span).
    double t[3], span_length[3];
    for (std::size_t d = 0; d < 3; ++d) {
      const std::vector<double> b = breakpoints(x.knots[d], x.degree[d]);
      const auto i = static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(b.size()) - 2));
      span_length[d] = b[i + 1] - b[i];
      t[d] = b[i] + uniform(rng, 0.25, 0.75) * span_length[d];
    }
    CAPTURE(trial, x.rational);
    const Points S = derivatives(x, t[0], t[1], t[2], order);
    const Points A = derivatives(h, t[0], t[1], t[2], order);
    const auto row = [n](int a, int b, int c) { return (a * n + b) * n + c; };
    if (x.rational) {
      ++rational;
      for (int a = 0; a <= order; ++a)
        for (int b = 0; a + b <= order; ++b)
          for (int c = 0; a + b + c <= order; ++c) {
            // ∂^α (w·V) = Σ_{β ≤ α} C(α, β) ∂^β w · ∂^{α−β} V.
            Eigen::Matrix<Real, 1, Eigen::Dynamic> sum = Eigen::Matrix<Real, 1, Eigen::Dynamic>::Zero(dim);
            Real size = 0;
            for (int i = 0; i <= a; ++i)
              for (int j = 0; j <= b; ++j)
                for (int k = 0; k <= c; ++k) {
                  const Real f =
                      Real(binomial(a, i) * binomial(b, j) * binomial(c, k)) * A(row(i, j, k), dim);
                  sum += f * S.row(row(a - i, b - j, c - k)).cast<Real>();
                  size += std::abs(f) * S.row(row(a - i, b - j, c - k)).cast<Real>().norm();
                }
            CAPTURE(a, b, c);
            CHECK(static_cast<double>((sum - A.row(row(a, b, c)).head(dim).cast<Real>()).norm()) <=
                  1e-12 * static_cast<double>(size + A.row(row(a, b, c)).head(dim).cast<Real>().norm()));
          }
    } else {
      CHECK(S == A);
    }
    // Central differences of the values (first partials) and of the first partials (mixed second ones).
    for (std::size_t d = 0; d < 3; ++d) {
      const double step = 1e-4 * span_length[d];
      double lo[3] = {t[0], t[1], t[2]}, hi[3] = {t[0], t[1], t[2]};
      lo[d] -= step;
      hi[d] += step;
      const int unit[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
      const Point fd = (evaluate(x, hi[0], hi[1], hi[2]) - evaluate(x, lo[0], lo[1], lo[2])) / (2 * step);
      const Point exact = S.row(row(unit[d][0], unit[d][1], unit[d][2]));
      CHECK(diff(fd, exact) <= 1e-6 * (r.scale / span_length[d] + exact.norm()));
      const Points Dlo = derivatives(x, lo[0], lo[1], lo[2], 1), Dhi = derivatives(x, hi[0], hi[1], hi[2], 1);
      const auto d1 = (d + 1) % 3;  // ∂_d ∂_{d+1}
      const auto first = [&](std::size_t e) { return (unit[e][0] * 2 + unit[e][1]) * 2 + unit[e][2]; };
      const Point mixed = (Dhi.row(first(d1)) - Dlo.row(first(d1))) / (2 * step);
      const Point exact2 =
          S.row(row(unit[d][0] + unit[d1][0], unit[d][1] + unit[d1][1], unit[d][2] + unit[d1][2]));
      CHECK(diff(mixed, exact2) <= 1e-6 * (r.scale / (span_length[d] * span_length[d1]) + exact2.norm()));
    }
  }
  CHECK(rational > 0);
}

TEST_CASE("volume grids are the volume at every grid point", "[nurbs][volume]") {
  Rng rng(3108);
  for (int trial = 0; trial < 12; ++trial) {
    const RandomVolume r = random_volume(rng);
    const std::vector<double> us = volume_samples(rng, r.v, 0), vs = volume_samples(rng, r.v, 1);
    const std::vector<double> ws{volume_samples(rng, r.v, 2)[2], volume_samples(rng, r.v, 2)[0]};
    const Points grid = evaluate_grid(r.v, us, vs, ws);
    REQUIRE(grid.rows() == static_cast<Eigen::Index>(us.size() * vs.size() * ws.size()));
    for (std::size_t a = 0; a < us.size(); ++a)
      for (std::size_t b = 0; b < vs.size(); ++b)
        for (std::size_t c = 0; c < ws.size(); ++c) {
          const auto row = static_cast<Eigen::Index>((a * vs.size() + b) * ws.size() + c);
          CHECK(diff(grid.row(row), reference(r, us[a], vs[b], ws[c])) <= 1e-13 * r.scale);
          CHECK(grid.row(row) == evaluate(r.v, us[a], vs[b], ws[c]));  // the same operations
        }
  }
}

TEST_CASE("volume operations refuse bad input naming the argument", "[nurbs][volume]") {
  const Knots t{0, 0, 0.5, 1, 1};
  const Volume cube = make_volume({1, 1, 1}, {t, t, t}, {3, 3, 3}, Points::Random(27, 3));
  const std::vector<double> half{0.5}, outside{2.0};
  CHECK_THROWS_WITH(refine(cube, 3, half), Contains("direction 3 is not u (0), v (1) or w (2)"));
  CHECK_THROWS_WITH(refine(cube, 2, outside), Contains("direction w: "));
  CHECK_THROWS_WITH(remove_knot(cube, -1, 0.5, 1, 0.0), Contains("direction -1 is not"));
  CHECK_THROWS_WITH(remove_knot(cube, 0, 0.5, -1, 0.0), Contains("times = -1 is negative"));
  CHECK_THROWS_WITH(remove_knot(cube, 0, 0.5, 1, -1.0), Contains("tolerance -1 must be non-negative"));
  CHECK_THROWS_WITH(remove_knot(cube, 1, 1.0, 1, 0.0), Contains("direction v: knot 1 is not interior"));
  CHECK_THROWS_WITH(remove_knot(cube, 2, 0.25, 1, 0.0), Contains("direction w: 0.25 is not a knot"));
  CHECK_THROWS_WITH(elevate_degree(cube, 1, -1), Contains("direction v: "));
  CHECK_THROWS_WITH(split(cube, 0, 1.0), Contains("direction u: "));
  CHECK_THROWS_WITH(iso_surface(cube, 2, 1.5), Contains("parameter w = 1.5 is outside the domain [0, 1]"));
  CHECK_THROWS_WITH(iso_surface(cube, 5, 0.5), Contains("direction 5 is not"));
  CHECK_THROWS_WITH(reverse(cube, 3), Contains("direction 3 is not"));
  CHECK_THROWS_WITH(reparametrize(cube, 1, 1.0, 0.0), Contains("reparametrize: direction v: "));
  CHECK_THROWS_WITH(derivatives(cube, 0.5, 0.5, 0.5, -1), Contains("derivative order -1"));
  CHECK_THROWS_WITH(derivatives(cube, 0.5, -0.5, 0.5, 1), Contains("parameter v = -0.5 is outside"));
  const std::vector<double> inside{0.5}, bad{0.5, std::nan("")};
  CHECK_THROWS_WITH(evaluate_grid(cube, inside, inside, bad), Contains("parameter w = nan is outside"));
}
