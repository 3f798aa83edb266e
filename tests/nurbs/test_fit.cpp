// SPDX-License-Identifier: MIT
// Fitting: interpolation against the linear system solved in exact rationals, every data point hit to
// 1e-14; least squares against a dense QR of the textbook system (the reference's Cox–de Boor) and
// against data the spline space holds exactly; the distance bounds against dense sampling; the knot
// vectors against NURBS-Python's properties (its tests/test_fitting.py); bad input.
#include "cifs/nurbs/fit.hpp"

#include <Eigen/Dense>
#include <boost/multiprecision/cpp_int.hpp>
#include <catch2/catch.hpp>
#include <cmath>

#include "cifs/errors.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

using Rational = boost::multiprecision::cpp_rational;
using RationalVec = std::vector<Rational>;

/// Cox–de Boor in exact rationals (0/0 = 0): the values of every N_{i,p} at x, right-continuous,
/// except that x = the last knot takes the left limit.
RationalVec exact_basis(const RationalVec& t, int p, const Rational& x) {
  const int m = static_cast<int>(t.size());
  const bool end = x == t.back();
  RationalVec N(static_cast<std::size_t>(m - 1));
  for (int i = 0; i + 1 < m; ++i) {
    const Rational &a = t[static_cast<std::size_t>(i)], &b = t[static_cast<std::size_t>(i + 1)];
    N[static_cast<std::size_t>(i)] = (end ? (a < x && x <= b) : (a <= x && x < b)) ? 1 : 0;
  }
  for (int q = 1; q <= p; ++q)
    for (int i = 0; i < m - q - 1; ++i) {
      const auto T = [&](int j) { return t[static_cast<std::size_t>(j)]; };
      Rational v = 0;
      if (T(i + q) != T(i)) v += (x - T(i)) / (T(i + q) - T(i)) * N[static_cast<std::size_t>(i)];
      if (T(i + q + 1) != T(i + 1))
        v += (T(i + q + 1) - x) / (T(i + q + 1) - T(i + 1)) * N[static_cast<std::size_t>(i + 1)];
      N[static_cast<std::size_t>(i)] = v;
    }
  N.resize(static_cast<std::size_t>(m - p - 1));
  return N;
}

/// Solves A X = B exactly (Gauss–Jordan with a non-zero pivot search).
std::vector<RationalVec> exact_solve(std::vector<RationalVec> A, std::vector<RationalVec> B) {
  const std::size_t n = A.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t r = c;
    while (A[r][c] == 0) ++r;
    std::swap(A[r], A[c]);
    std::swap(B[r], B[c]);
    for (std::size_t i = 0; i < n; ++i) {
      if (i == c || A[i][c] == 0) continue;
      const Rational f = A[i][c] / A[c][c];
      for (std::size_t j = 0; j < n; ++j) A[i][j] -= f * A[c][j];
      for (std::size_t j = 0; j < B[i].size(); ++j) B[i][j] -= f * B[c][j];
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    for (auto& b : B[i]) b /= A[i][i];
  return B;
}

/// The interpolant's control points in exact rationals from integer points and exact parameters:
/// knots by averaging (The NURBS Book eq. 9.8), the collocation system solved exactly.
std::vector<RationalVec> exact_interpolant(const std::vector<std::vector<int>>& Q, const RationalVec& u,
                                           int p, RationalVec& knots) {
  const int m = static_cast<int>(Q.size());
  knots.assign(static_cast<std::size_t>(p + 1), Rational(0));
  for (int j = 1; j <= m - p - 1; ++j) {
    Rational sum = 0;
    for (int i = j; i < j + p; ++i) sum += u[static_cast<std::size_t>(i)];
    knots.push_back(sum / p);
  }
  knots.insert(knots.end(), static_cast<std::size_t>(p + 1), Rational(1));
  std::vector<RationalVec> A, B;
  for (int k = 0; k < m; ++k) {
    A.push_back(exact_basis(knots, p, u[static_cast<std::size_t>(k)]));
    B.emplace_back(Q[static_cast<std::size_t>(k)].begin(), Q[static_cast<std::size_t>(k)].end());
  }
  return exact_solve(A, B);
}

Points to_points(const std::vector<std::vector<int>>& Q) {
  Points P(static_cast<Eigen::Index>(Q.size()), static_cast<Eigen::Index>(Q[0].size()));
  for (std::size_t i = 0; i < Q.size(); ++i)
    for (std::size_t j = 0; j < Q[i].size(); ++j)
      P(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = Q[i][j];
  return P;
}

/// Largest distance between the data and the curve at the data's parameters, relative to the data's size.
double relative_miss(const Curve& c, const Points& Q, const std::vector<double>& u) {
  double worst = 0;
  for (Eigen::Index k = 0; k < Q.rows(); ++k)
    worst = std::max(worst, (evaluate(c, u[static_cast<std::size_t>(k)]) - Q.row(k)).norm());
  return worst / Q.cwiseAbs().maxCoeff();
}

/// Random points along a wavy path (no two consecutive ones coincide).
Points random_path(Rng& rng, Eigen::Index m, Eigen::Index dim) {
  Points Q(m, dim);
  Point x = Point::Zero(dim);
  for (Eigen::Index k = 0; k < m; ++k) {
    for (Eigen::Index j = 0; j < dim; ++j)
      x(j) += uniform(rng, 0.1, 1.0) *
              (j == 0 ? 1 : std::sin(0.7 * static_cast<double>(k) + static_cast<double>(j)));
    Q.row(k) = x;
  }
  return Q;
}

/// The curve's knots equal the exact ones to 1e-15, its control points the exact ones to 1e-14 of their size.
void check_exact(const Curve& curve, const RationalVec& knots, const std::vector<RationalVec>& exact) {
  REQUIRE(curve.knots.size() == knots.size());
  for (std::size_t i = 0; i < knots.size(); ++i)
    CHECK(std::abs(curve.knots[i] - knots[i].convert_to<double>()) <= 1e-15);
  double scale = 0, worst = 0;
  for (std::size_t i = 0; i < exact.size(); ++i)
    for (std::size_t j = 0; j < exact[i].size(); ++j) {
      const double x = exact[i][j].convert_to<double>();
      scale = std::max(scale, std::abs(x));
      worst =
          std::max(worst, std::abs(curve.P(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) - x));
    }
  CHECK(worst <= 1e-14 * scale);
}

}  // namespace

TEST_CASE("fit_parameters: uniform, chord length and centripetal", "[nurbs][fit]") {
  Points Q(4, 2);
  Q << 0, 0, 3, 4, 3, 13, 7, 16;  // chords 5, 9, 5
  auto close = [](const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) CHECK(std::abs(a[i] - b[i]) <= 1e-16);
  };
  close(fit_parameters(Q, Parametrization::uniform), {0, 1.0 / 3, 2.0 / 3, 1});
  close(fit_parameters(Q, Parametrization::chord_length), {0, 5.0 / 19, 14.0 / 19, 1});
  const double s5 = std::sqrt(5.0), total = 2 * s5 + 3;
  close(fit_parameters(Q, Parametrization::centripetal), {0, s5 / total, (s5 + 3) / total, 1});
  // Closed: the chord back to the first point (length 7·√(65)/… ) counts; the period is [0, 1].
  const auto closed = fit_parameters(Q, Parametrization::uniform, true);
  close(closed, {0, 0.25, 0.5, 0.75});
}

TEST_CASE("interpolate equals the collocation system solved in exact rationals", "[nurbs][fit]") {
  struct Case {
    std::vector<std::vector<int>> points;
    Parametrization kind;
  };
  // Chords 5, 13, 17, 25 (Pythagorean) for chord length; 25, 9, 16, 4 (squares) for centripetal.
  const std::vector<std::vector<int>> pythagorean{{0, 0}, {3, 4}, {8, 16}, {16, 1}, {9, 25}};
  const std::vector<std::vector<int>> squares{{1, 2}, {8, 26}, {8, 17}, {24, 17}, {24, 21}, {0, 28}};
  const std::vector<std::vector<int>> wavy{{0, 0, 1}, {1, 3, -2}, {2, -1, 0}, {4, 2, 5},
                                           {5, 0, 2}, {7, 1, 1},  {8, -3, 0}};
  const std::vector<Case> cases{{pythagorean, Parametrization::chord_length},
                                {squares, Parametrization::centripetal},
                                {wavy, Parametrization::uniform},
                                {squares, Parametrization::uniform}};
  for (const Case& c : cases)
    for (int p = 1; p < static_cast<int>(c.points.size()); ++p) {
      CAPTURE(p, static_cast<int>(c.kind));
      const int m = static_cast<int>(c.points.size());
      // Exact parameters: the chords of these points are whole numbers.
      RationalVec chord{0};
      for (int k = 1; k < m; ++k) {
        long long d2 = 0;
        for (std::size_t j = 0; j < c.points[0].size(); ++j) {
          const long long d =
              c.points[static_cast<std::size_t>(k)][j] - c.points[static_cast<std::size_t>(k - 1)][j];
          d2 += d * d;
        }
        long long d = std::llround(std::sqrt(static_cast<double>(d2)));
        if (c.kind == Parametrization::centripetal) d = std::llround(std::sqrt(static_cast<double>(d)));
        if (c.kind == Parametrization::uniform) d = 1;
        chord.push_back(chord.back() + d);
      }
      RationalVec u;
      for (const Rational& x : chord) u.push_back(x / chord.back());
      RationalVec knots;
      const auto exact = exact_interpolant(c.points, u, p, knots);

      InterpolateOptions options;
      options.degree = p;
      options.parametrization = c.kind;
      const Points Q = to_points(c.points);
      const Curve curve = interpolate(Q, options);
      check_exact(curve, knots, exact);
      std::vector<double> ud;
      for (const Rational& x : u) ud.push_back(x.convert_to<double>());
      CHECK(relative_miss(curve, Q, ud) <= 1e-14);
    }
}

TEST_CASE("interpolate at given parameters equals the exact rational interpolant", "[nurbs][fit]") {
  // Parameters that are not the points' chords (0, 1/8, 3/8, 1/2, 7/8, 1): the exact system in rationals.
  const std::vector<std::vector<int>> points{{0, 0}, {3, 4}, {8, 16}, {16, 1}, {9, 25}, {2, 2}};
  const RationalVec u{Rational(0),    Rational(1, 8), Rational(3, 8),
                      Rational(1, 2), Rational(7, 8), Rational(1)};
  std::vector<double> ud;
  for (const Rational& x : u) ud.push_back(x.convert_to<double>());
  const Points Q = to_points(points);
  for (int p = 1; p <= 5; ++p) {
    CAPTURE(p);
    RationalVec knots;
    const auto exact = exact_interpolant(points, u, p, knots);
    const Curve curve = interpolate(Q, ud, p);
    check_exact(curve, knots, exact);
    CHECK(relative_miss(curve, Q, ud) <= 1e-14);
  }
  CHECK_THROWS_WITH(interpolate(Q, std::vector<double>{0, 1}, 1),
                    Contains("parameters: 2 given for 6 points"));
  CHECK_THROWS_WITH(interpolate(Q, std::vector<double>{0, 0.5, 0.5, 0.6, 0.7, 1}, 1),
                    Contains("parameters[2]: 0.5 is not greater than parameters[1] = 0.5"));
  CHECK_THROWS_WITH(interpolate(Q, std::vector<double>{0, 0.1, NAN, 0.6, 0.7, 1}, 1),
                    Contains("parameters[2]: nan is not finite"));
  CHECK_THROWS_WITH(interpolate(Q, ud, 6), Contains("needs at least 7 points, got 6"));
}

TEST_CASE("interpolate hits every point to 1e-14, open and closed, any degree", "[nurbs][fit]") {
  Rng rng(30);
  for (int trial = 0; trial < 120; ++trial) {
    const int p = uniform_int(rng, 1, 9);
    const bool closed = coin(rng);
    const Eigen::Index m = uniform_int(rng, p + 1, 60), dim = uniform_int(rng, 1, 4);
    const auto kind = static_cast<Parametrization>(uniform_int(rng, 0, 2));
    CAPTURE(trial, p, closed, m, dim, static_cast<int>(kind));
    const Points Q = random_path(rng, m, dim);
    InterpolateOptions options{
        .degree = p, .parametrization = kind, .start_derivative = {}, .end_derivative = {}, .closed = closed};
    const Curve c = interpolate(Q, options);
    CHECK(c.closed == closed);
    CHECK(distinct_count(c) == m);
    CHECK(relative_miss(c, Q, fit_parameters(Q, kind, closed)) <= 1e-14);
  }
}

TEST_CASE("interpolate with end derivatives: points and derivatives hit", "[nurbs][fit]") {
  Rng rng(31);
  for (int trial = 0; trial < 60; ++trial) {
    const int p = uniform_int(rng, 2, 7);
    const bool s = coin(rng), e = !s || coin(rng);
    const Eigen::Index m = uniform_int(rng, std::max(2, p + 1 - s - e), 30), dim = uniform_int(rng, 1, 3);
    CAPTURE(trial, p, s, e, m, dim);
    const Points Q = random_path(rng, m, dim);
    InterpolateOptions options;
    options.degree = p;
    if (s) options.start_derivative = Point::Random(dim) * 5;
    if (e) options.end_derivative = Point::Random(dim) * 5;
    const Curve c = interpolate(Q, options);
    CHECK(distinct_count(c) == m + s + e);
    CHECK(relative_miss(c, Q, fit_parameters(Q, options.parametrization)) <= 1e-14);
    const double size = std::max(Q.cwiseAbs().maxCoeff(), 5.0);
    if (s) CHECK(diff(derivatives(c, 0.0, 1).row(1), options.start_derivative) <= 1e-12 * size);
    if (e) CHECK(diff(derivatives(c, 1.0, 1).row(1), options.end_derivative) <= 1e-12 * size);
  }
}

TEST_CASE("approximate with a number of control points: the dense least-squares solution", "[nurbs][fit]") {
  Rng rng(32);
  for (int trial = 0; trial < 60; ++trial) {
    const int p = uniform_int(rng, 1, 5);
    const Eigen::Index m = uniform_int(rng, p + 2, 80), dim = uniform_int(rng, 1, 3);
    const Eigen::Index n = uniform_int(rng, p + 1, static_cast<int>(m) - 1);
    const bool weighted = coin(rng), fixed = coin(rng);
    CAPTURE(trial, p, m, n, weighted, fixed);
    const Points Q = random_path(rng, m, dim);
    ApproximateOptions options;
    options.degree = p;
    options.control_points = n;
    options.fix_ends = fixed;
    Eigen::VectorXd w = Eigen::VectorXd::Ones(m);
    if (weighted) options.weights = w = Eigen::VectorXd::Random(m).array() + 1.5;
    const CurveFit fit = approximate(Q, options);
    REQUIRE(distinct_count(fit.curve) == n);
    // Independent route: the textbook system from the reference's Cox–de Boor, solved by dense QR.
    const Knots& t = fit.curve.knots;
    Eigen::MatrixXd A(m, n);
    for (Eigen::Index k = 0; k < m; ++k) {
      const RealVec N = ref_basis(t, p, fit.parameters[static_cast<std::size_t>(k)],
                                  at_end(t, p, fit.parameters[static_cast<std::size_t>(k)]));
      for (Eigen::Index i = 0; i < n; ++i) A(k, i) = static_cast<double>(N[static_cast<std::size_t>(i)]);
    }
    const Eigen::Index first = fixed ? 1 : 0, free = fixed ? n - 2 : n;
    Eigen::MatrixXd R = Q, P = Eigen::MatrixXd::Zero(n, dim);
    if (fixed) {
      P.row(0) = Q.row(0);
      P.row(n - 1) = Q.row(m - 1);
      R -= A.col(0) * Q.row(0) + A.col(n - 1) * Q.row(m - 1);
    }
    if (free > 0) {
      const Eigen::VectorXd sw = w.cwiseSqrt();
      const Eigen::MatrixXd Aw = sw.asDiagonal() * A.middleCols(first, free);
      P.middleRows(first, free) = Aw.colPivHouseholderQr().solve(Eigen::MatrixXd(sw.asDiagonal() * R));
    }
    const double scale = Q.cwiseAbs().maxCoeff();
    CHECK(diff(fit.curve.P, P) <= 1e-9 * scale);
    // The distances it reports, measured here.
    double worst = 0;
    for (Eigen::Index k = 0; k < m; ++k)
      worst = std::max(worst,
                       (evaluate(fit.curve, fit.parameters[static_cast<std::size_t>(k)]) - Q.row(k)).norm());
    CHECK(std::abs(fit.point_distance - worst) <= 1e-12 * scale);
  }
}

TEST_CASE("approximate reproduces data that the spline space holds", "[nurbs][fit]") {
  // Points of a polynomial curve at equally spaced parameters: every fit of its degree, with uniform
  // parameters, is the polynomial itself.
  for (int p = 1; p <= 5; ++p)
    for (Eigen::Index n : {p + 1, p + 3, p + 9}) {
      const Eigen::Index m = 40;
      Points Q(m, 2);
      for (Eigen::Index k = 0; k < m; ++k) {
        const double x = static_cast<double>(k) / (m - 1);
        Q(k, 0) = 2 + 3 * x - std::pow(x, p);
        Q(k, 1) = std::pow(1 - x, p) + x;
      }
      ApproximateOptions options;
      options.degree = p;
      options.control_points = n;
      options.parametrization = Parametrization::uniform;
      const CurveFit fit = approximate(Q, options);
      CAPTURE(p, n);
      CHECK(fit.point_distance <= 1e-13);
      CHECK(fit.polyline_bound <= 0.2);  // the polyline's own sagitta: not zero
    }
}

TEST_CASE("approximate to a tolerance: the bound holds and is tight", "[nurbs][fit]") {
  Rng rng(33);
  const Eigen::Index m = 200;
  Points Q(m, 2);
  for (Eigen::Index k = 0; k < m; ++k) {
    const double x = 6.0 * static_cast<double>(k) / (m - 1);
    Q(k, 0) = x;
    Q(k, 1) = std::sin(2 * x) + 0.3 * std::cos(7 * x);
  }
  // (Chord-length parameters of these points make x and y less smooth than the uniform ones, for
  // which x is linear: the uniform fit needs fewer control points.)
  for (FitMeasure measure : {FitMeasure::points, FitMeasure::polyline})
    for (auto kind : {Parametrization::uniform, Parametrization::chord_length})
      for (double tol : {1e-1, 1e-2, 1e-4, 1e-6}) {
        // The polyline is 2e-3 from any smooth curve through the points (its sagitta).
        if (measure == FitMeasure::polyline && tol < 1e-2) continue;
        ApproximateOptions options;
        options.tolerance = tol;
        options.measure = measure;
        options.parametrization = kind;
        CAPTURE(tol, static_cast<int>(measure), static_cast<int>(kind));
        const CurveFit fit = approximate(Q, options);
        CHECK((measure == FitMeasure::points ? fit.point_distance : fit.polyline_bound) <= tol);
        if (kind == Parametrization::uniform && tol >= 1e-4) CHECK(distinct_count(fit.curve) < m / 2);
        // Dense sampling of |C(u) − L(u)| never exceeds the bound, and reaches 98 % of it.
        double sampled = 0;
        for (Eigen::Index k = 0; k + 1 < m; ++k) {
          const double a = fit.parameters[static_cast<std::size_t>(k)],
                       b = fit.parameters[static_cast<std::size_t>(k + 1)];
          for (int s = 0; s <= 64; ++s) {
            const double f = s / 64.0, x = a + f * (b - a);
            const Point L = (1 - f) * Q.row(k) + f * Q.row(k + 1);
            sampled = std::max(sampled, (evaluate(fit.curve, x) - L).norm());
          }
        }
        CHECK(sampled <= fit.polyline_bound);
        CHECK(sampled >= 0.98 * fit.polyline_bound);
        CHECK(fit.point_distance <= fit.polyline_bound);
      }
  // Below what the polyline allows: interpolation does not reach it either, and says so.
  ApproximateOptions tight;
  tight.tolerance = 1e-9;
  tight.measure = FitMeasure::polyline;
  CHECK_THROWS_WITH(approximate(Q, tight), Contains("below the polyline distance"));
  // The points measure always reaches it: at worst by interpolation.
  tight.measure = FitMeasure::points;
  CHECK(approximate(Q, tight).point_distance <= 1e-9);
  (void)rng;
}

TEST_CASE("approximation_knots: NURBS-Python's knot vector properties", "[nurbs][fit]") {
  // tests/test_fitting.py of NURBS-Python: the right count, clamped on [0, 1] with nothing else at 0 and
  // 1, non-decreasing, a data parameter in every span, and reversal symmetry.
  Rng rng(1);
  const auto check = [](const std::vector<double>& u, int p, Eigen::Index n) {
    const Knots t = approximation_knots(u, p, n);
    REQUIRE(static_cast<Eigen::Index>(t.size()) == n + p + 1);
    for (int i = 0; i <= p; ++i) {
      CHECK(t[static_cast<std::size_t>(i)] == 0.0);
      CHECK(t[t.size() - 1 - static_cast<std::size_t>(i)] == 1.0);
    }
    for (std::size_t i = static_cast<std::size_t>(p) + 1; i + p + 1 < t.size(); ++i)
      CHECK((t[i] > 0 && t[i] < 1));
    CHECK(std::is_sorted(t.begin(), t.end()));
    for (std::size_t s = static_cast<std::size_t>(p); s + p + 1 < t.size(); ++s) {
      bool inside = false;
      for (std::size_t k = 1; k + 1 < u.size(); ++k) inside |= t[s] <= u[k] && u[k] <= t[s + 1];
      CHECK(inside);
    }
    std::vector<double> r;
    for (auto it = u.rbegin(); it != u.rend(); ++it) r.push_back(1 - *it);
    const Knots rt = approximation_knots(r, p, n);
    for (std::size_t i = 0; i < t.size(); ++i) CHECK(std::abs(t[i] - (1 - rt[t.size() - 1 - i])) < 1e-6);
  };
  for (int p = 2; p <= 5; ++p)
    for (int m : {2, 3, 4, 5, 10, 20, 30, 40, 100})
      for (Eigen::Index n = p + 1; n < m; ++n) {
        std::vector<double> u{0.0, 1.0};
        for (int k = 0; k < m - 2; ++k) u.push_back(uniform(rng, 0, 1));
        std::sort(u.begin(), u.end());
        CAPTURE(p, m, n);
        check(u, p, n);
      }
  // Their "known problem points": 89 points of a scanned path, degree 5, 88 control points.
  Points bad(12, 3);
  bad << 2.844226598739624, -11.780293452192772, 0.09999999336045856, 2.7841949334192995, -11.766323767032048,
      0.09999967816303046, 2.726926206709484, -11.752261321710279, 0.09999834367677496, 2.672275643786814,
      -11.73818458975435, 0.09999921155914912, 2.620158046052624, -11.72397519981413, 0.09999996191039656,
      2.570553374917445, -11.709268999929673, 0.09999962409195731, 2.5232627391815186, -11.694355010986328,
      0.10000000149011612, 2.478258938913115, -11.678929052642333, 0.09999946225906724, 2.435358747058011,
      -11.66315338641665, 0.09999991570513912, 2.394573211669922, -11.646668434143066, 0.10000000149011612,
      2.355729818344116, -11.629592895507812, 0.10000000149011612, 2.3187353452599866, -11.611833538564408,
      0.09999994560062432;
  const auto u = fit_parameters(bad, Parametrization::chord_length);
  check(u, 5, 11);
  ApproximateOptions options;
  options.degree = 5;
  options.control_points = 11;
  CHECK(approximate(bad, options).point_distance <= 1e-4);
}

TEST_CASE("interpolate_surface and approximate_surface", "[nurbs][fit]") {
  Rng rng(34);
  for (int trial = 0; trial < 20; ++trial) {
    const std::array<int, 2> p{uniform_int(rng, 1, 4), uniform_int(rng, 1, 4)};
    const std::array<Eigen::Index, 2> count{uniform_int(rng, p[0] + 1, 12), uniform_int(rng, p[1] + 1, 12)};
    CAPTURE(trial, p[0], p[1], count[0], count[1]);
    Grid g{Points(count[0] * count[1], 3), count};
    for (Eigen::Index i = 0; i < count[0]; ++i)
      for (Eigen::Index j = 0; j < count[1]; ++j)
        g.points.row(i * count[1] + j) << static_cast<double>(i) + uniform(rng, 0, 0.3),
            static_cast<double>(j) + uniform(rng, 0, 0.3), uniform(rng, -1, 1);
    SurfaceFitOptions options;
    options.degree = p;
    const Surface s = interpolate_surface(g, options);
    const auto uv = grid_parameters(g, options.parametrization);
    double worst = 0;
    for (Eigen::Index i = 0; i < count[0]; ++i)
      for (Eigen::Index j = 0; j < count[1]; ++j)
        worst = std::max(
            worst, diff(evaluate(s, uv[0][static_cast<std::size_t>(i)], uv[1][static_cast<std::size_t>(j)]),
                        g.points.row(i * count[1] + j)));
    CHECK(worst <= 1e-14 * g.points.cwiseAbs().maxCoeff());
    // The approximation with every point is the interpolation; with fewer it keeps the corners.
    options.control_points = count;
    CHECK(diff(approximate_surface(g, options).P, s.P) <= 1e-12 * g.points.cwiseAbs().maxCoeff());
    options.control_points = {p[0] + 1, p[1] + 1};
    const Surface a = approximate_surface(g, options);
    for (auto [i, j] : {std::pair<Eigen::Index, Eigen::Index>{0, 0},
                        {0, count[1] - 1},
                        {count[0] - 1, 0},
                        {count[0] - 1, count[1] - 1}})
      CHECK(diff(evaluate(a, uv[0][static_cast<std::size_t>(i)], uv[1][static_cast<std::size_t>(j)]),
                 g.points.row(i * count[1] + j)) <= 1e-13 * 12);
  }
  // A bilinear-in-parameters grid is reproduced by any approximation (uniform parameters).
  Grid plane{Points(36, 3), {6, 6}};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) plane.points.row(i * 6 + j) << i, 2 * j, i * j;
  SurfaceFitOptions o{
      .degree = {1, 2}, .parametrization = Parametrization::uniform, .control_points = {2, 4}};
  const Surface s = approximate_surface(plane, o);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      CHECK(diff(evaluate(s, i / 5.0, j / 5.0), plane.points.row(i * 6 + j)) <= 1e-13);
}

TEST_CASE("fitting refuses bad input in one line", "[nurbs][fit]") {
  Points Q(5, 2);
  Q << 0, 0, 1, 1, 1, 1, 2, 0, 3, 1;
  CHECK_THROWS_WITH(interpolate(Q), Contains("points[2]: coincides with points[1]"));
  InterpolateOptions uniform;  // equal points at two parameters: a curve through the point twice
  uniform.parametrization = Parametrization::uniform;
  CHECK(relative_miss(interpolate(Q, uniform), Q, fit_parameters(Q, Parametrization::uniform)) <= 1e-14);
  Points few(3, 2);
  few << 0, 0, 1, 1, 2, 0;
  CHECK_THROWS_WITH(interpolate(few), Contains("degree 3 needs at least 4 points, got 3"));
  InterpolateOptions closed;
  closed.closed = true;
  CHECK_THROWS_WITH(interpolate(few, closed), Contains("needs at least 4 points, got 3"));
  InterpolateOptions high;
  high.degree = 99;
  CHECK_THROWS_AS(interpolate(few, high), InvalidInput);
  Points nan = few;
  nan(1, 1) = NAN;
  CHECK_THROWS_WITH(interpolate(nan), Contains("points[1][1]: coordinate is not finite"));
  InterpolateOptions derivative;
  derivative.degree = 2;
  derivative.start_derivative = Point::Ones(3);
  CHECK_THROWS_WITH(interpolate(few, derivative), Contains("start_derivative: 3 coordinates"));
  derivative.degree = 1;
  derivative.start_derivative = Point::Ones(2);
  CHECK_THROWS_WITH(interpolate(few, derivative), Contains("degree 2 or more"));

  ApproximateOptions a;  // neither a count nor a tolerance: interpolation
  a.degree = 2;
  InterpolateOptions quadratic;
  quadratic.degree = 2;
  CHECK(diff(approximate(few, a).curve.P, interpolate(few, quadratic).P) == 0);
  a.closed = true;
  a.control_points = 3;
  CHECK_THROWS_WITH(approximate(few, a), Contains("closed curves are interpolated"));
  a.closed = false;
  a.degree = 3;
  a.tolerance = 1;
  CHECK_THROWS_WITH(approximate(few, a), Contains("both"));
  a.tolerance = 0;
  a.degree = 2;
  a.control_points = 4;
  CHECK_THROWS_WITH(approximate(few, a), Contains("control_points: 4 is outside 3 … 3"));
  a.control_points = 3;
  a.weights = Eigen::VectorXd::Ones(2);
  CHECK_THROWS_WITH(approximate(few, a), Contains("weights: 2 weights for 3 points"));
  a.weights = Eigen::VectorXd::Ones(3);
  a.weights(1) = -1;
  CHECK_THROWS_WITH(approximate(few, a), Contains("weights[1]"));

  CHECK_THROWS_WITH(interpolate_surface(Grid{Points(5, 3), {2, 3}}),
                    Contains("grid: 5 points for a 2 by 3 grid"));
  Grid flat{Points::Zero(9, 3), {3, 3}};
  SurfaceFitOptions o;
  o.degree = {2, 2};
  CHECK_THROWS_WITH(interpolate_surface(flat, o), Contains("has all its points equal"));
}
