// SPDX-License-Identifier: MIT
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/nurbs/doubling.hpp"
#include "cifs/nurbs/refine.hpp"

using namespace cifs;
using namespace cifs::nurbs;

namespace {

double max_abs_entry(const Eigen::MatrixXd& m) {
  return m.cwiseAbs().maxCoeff();
}

/// Independent reference in long double: de Boor's triangle with one argument per level on the
/// window's knots T = t_{k−d+1} … t_{k+d} (the blossom of the piece on span k), at `args`.
Eigen::RowVectorXd blossom_ld(const std::vector<long double>& T, const Points& P, int d, int k,
                              const std::vector<long double>& args) {
  const auto t = [&](int i) { return T[static_cast<std::size_t>(i - (k - d + 1))]; };
  // Level 1 of the triangle spans the widest intervals: far arguments first, near ones last.
  std::vector<long double> x = args;
  const long double a = t(k), b = t(k + 1);
  const auto far = [&](long double y) { return y < a ? a - y : (y > b ? y - b : 0.0L); };
  std::sort(x.begin(), x.end(), [&](long double y, long double z) { return far(y) > far(z); });
  std::vector<std::vector<long double>> q(static_cast<std::size_t>(d + 1));
  for (int j = 0; j <= d; ++j)
    for (Eigen::Index c = 0; c < P.cols(); ++c) q[static_cast<std::size_t>(j)].push_back(P(k - d + j, c));
  for (int r = 1; r <= d; ++r)
    for (int j = d; j >= r; --j) {
      const int i = j + k - d;
      const long double lo = t(i), hi = t(i + d + 1 - r);
      const long double alpha = (x[static_cast<std::size_t>(r - 1)] - lo) / (hi - lo);
      for (std::size_t c = 0; c < q[0].size(); ++c)
        q[static_cast<std::size_t>(j)][c] =
            (1 - alpha) * q[static_cast<std::size_t>(j - 1)][c] + alpha * q[static_cast<std::size_t>(j)][c];
    }
  Eigen::RowVectorXd out(P.cols());
  for (Eigen::Index c = 0; c < P.cols(); ++c)
    out(c) = static_cast<double>(q[static_cast<std::size_t>(d)][static_cast<std::size_t>(c)]);
  return out;
}

}  // namespace

TEST_CASE("Degree 2: the closed forms of Morlet et al.", "[nurbs][doubling]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> len(0.01, 10);
  for (int trial = 0; trial < 50; ++trial) {
    const double u1 = len(rng), u2 = len(rng), u3 = len(rng);
    const Window w{u1, u2, u3};
    Eigen::Matrix3d G, D;
    const double a = 2 * (u1 + u2), b = 2 * (u2 + u3);
    G << (u1 + 2 * u2) / a, u1 / a, 0,  //
        u2 / a, (2 * u1 + u2) / a, 0,   //
        0, (u2 + 2 * u3) / b, u2 / b;
    D << u2 / a, (2 * u1 + u2) / a, 0,  //
        0, (u2 + 2 * u3) / b, u2 / b,   //
        0, u3 / b, (2 * u2 + u3) / b;
    CHECK(max_abs_entry(subdivision_matrix(w, 2, Half::G) - G) <= 1e-14);
    CHECK(max_abs_entry(subdivision_matrix(w, 2, Half::D) - D) <= 1e-14);
    CHECK(child_window(w, 2, Half::G) == Window{u1, u2, u2});
    CHECK(child_window(w, 2, Half::D) == Window{u2, u2, u3});
  }
}

TEST_CASE("Uniform knots give Chaikin and the Lane-Riesenfeld masks", "[nurbs][doubling]") {
  Eigen::Matrix3d chaikin_G, chaikin_D;
  chaikin_G << 0.75, 0.25, 0, 0.25, 0.75, 0, 0, 0.75, 0.25;
  chaikin_D << 0.25, 0.75, 0, 0, 0.75, 0.25, 0, 0.25, 0.75;
  CHECK(max_abs_entry(subdivision_matrix(Window{1, 1, 1}, 2, Half::G) - chaikin_G) == 0);
  CHECK(max_abs_entry(subdivision_matrix(Window{1, 1, 1}, 2, Half::D) - chaikin_D) == 0);
  // Degree d uniform: rows are the binomial mask (1/2^d)·C(d+1, k) taken alternately.
  for (int d = 1; d <= 10; ++d) {
    const Window w(static_cast<std::size_t>(2 * d - 1), 1.0);
    std::vector<double> mask(static_cast<std::size_t>(d + 2), 1.0);
    for (int k = 1; k <= d + 1; ++k)
      mask[static_cast<std::size_t>(k)] = mask[static_cast<std::size_t>(k - 1)] * (d + 2 - k) / k;
    for (double& m : mask) m /= std::ldexp(1.0, d);
    for (Half h : {Half::G, Half::D}) {
      const Eigen::MatrixXd M = subdivision_matrix(w, d, h);
      CHECK(child_window(w, d, h) == w);
      for (int i = 0; i <= d; ++i)
        for (int k = 0; k <= d; ++k) {
          // S_ε[i][k] = a_{i − 2k + N − 1 + ε} with N = d + 1 (DESIGN.md; Chaikin for d = 2).
          const int idx = i - 2 * k + d + static_cast<int>(h);
          const double expected = idx >= 0 && idx <= d + 1 ? mask[static_cast<std::size_t>(idx)] : 0.0;
          CHECK(M(i, k) == Approx(expected).margin(1e-15));
        }
    }
  }
}

TEST_CASE("G/D matrices equal midpoint knot insertion on random curves", "[nurbs][doubling]") {
  std::mt19937_64 rng(2024);
  for (int d = 1; d <= 10; ++d)
    for (int trial = 0; trial < 5; ++trial) {
      // Random knots with interval ratios up to 1e6 and some repeats (multiplicity ≤ d).
      const int n = 4 * d + 2;
      std::uniform_real_distribution<double> logl(-3, 3), unit(0, 1);
      Knots t(static_cast<std::size_t>(n + d + 1));
      t[0] = 0;
      int run = 1;
      for (std::size_t i = 1; i < t.size(); ++i) {
        const bool repeat = unit(rng) < 0.2 && run < d;
        t[i] = t[i - 1] + (repeat ? 0.0 : std::pow(10.0, logl(rng)));
        run = repeat ? run + 1 : 1;
      }
      Points P = Points::Random(n, 3);
      const Curve c = make_curve(d, t, P);
      for (int k = d; k < n; ++k) {
        if (!(t[static_cast<std::size_t>(k)] < t[static_cast<std::size_t>(k + 1)])) continue;
        // The window's own knots in long double (T_{k−d+1+i} = Σ of the window's first i lengths),
        // then every non-empty interval halved (exact in long double).
        const Window w = segment_window(t, d, k);
        std::vector<long double> T{0.0L};
        for (double x : w) T.push_back(T.back() + x);
        std::vector<long double> S;
        std::size_t centre = 0;
        for (std::size_t i = 0; i < T.size(); ++i) {
          if (i == static_cast<std::size_t>(d - 1)) centre = S.size();
          S.push_back(T[i]);
          if (i + 1 < T.size() && T[i] < T[i + 1]) S.push_back((T[i] + T[i + 1]) / 2);
        }
        for (Half half : {Half::G, Half::D}) {
          const Eigen::MatrixXd M = subdivision_matrix(w, d, half);
          INFO("d = " << d << ", rowsum error "
                      << max_abs_entry(M.rowwise().sum() - Eigen::VectorXd::Ones(d + 1)));
          CHECK(max_abs_entry(M.rowwise().sum() - Eigen::VectorXd::Ones(d + 1)) <= 1e-13);
          const Points Q = M * P.middleRows(k - d, d + 1);
          // Point i of the half is the blossom at the d consecutive refined knots ending at span+i.
          const std::size_t j = centre + static_cast<std::size_t>(half);
          for (int i = 0; i <= d; ++i) {
            const std::vector<long double> args(S.begin() + static_cast<std::ptrdiff_t>(j) - d + 1 + i,
                                                S.begin() + static_cast<std::ptrdiff_t>(j) + 1 + i);
            CHECK(max_abs_entry(Q.row(i) - blossom_ld(T, P, d, k, args)) <= 1e-12 * (1 + max_abs_entry(P)));
          }
        }
      }
      // Where the window lies in the domain, knot insertion by the NURBS core agrees (its knots are
      // absolute, so allow for their conditioning).
      const Curve r = refine_midpoints(c);
      for (int k = 2 * d - 1; k <= n - d; ++k) {
        if (!(t[static_cast<std::size_t>(k)] < t[static_cast<std::size_t>(k + 1)])) continue;
        const Window w = segment_window(t, d, k);
        const double kappa = t.back() / w[static_cast<std::size_t>(d - 1)];
        const double mid = 0.5 * (t[static_cast<std::size_t>(k)] + t[static_cast<std::size_t>(k + 1)]);
        const int kg = find_span(r.knots, d, t[static_cast<std::size_t>(k)]);
        const int kd = find_span(r.knots, d, mid);
        for (auto [half, span] : {std::pair{Half::G, kg}, std::pair{Half::D, kd}}) {
          const Points Q = subdivision_matrix(w, d, half) * P.middleRows(k - d, d + 1);
          CHECK(max_abs_entry(Q - r.P.middleRows(span - d, d + 1)) <=
                1e-15 * kappa * (1 + max_abs_entry(P)) * d * d);
          // The child window is the refined segment's window, scaled by 2.
          Window child = segment_window(r.knots, d, span);
          for (double& x : child) x *= 2;
          const Window predicted = child_window(w, d, half);
          for (std::size_t i = 0; i < child.size(); ++i)
            CHECK(predicted[i] == Approx(child[i]).epsilon(1e-12).margin(1e-12));
        }
      }
    }
}

TEST_CASE("Windows are validated", "[nurbs][doubling]") {
  CHECK_THROWS_WITH(subdivision_matrix(Window{1, 1}, 2, Half::G),
                    Catch::Contains("2 inter-knots given, degree 2 takes 3"));
  CHECK_THROWS_WITH(subdivision_matrix(Window{1, 0, 1}, 2, Half::G),
                    Catch::Contains("central interval must be positive"));
  CHECK_THROWS_WITH(subdivision_matrix(Window{1, -1, 1}, 2, Half::G), Catch::Contains("window[1]"));
  CHECK_NOTHROW(subdivision_matrix(Window{0, 0, 1, 0, 0}, 3, Half::D));
  CHECK_THROWS_AS(child_window(Window{1, 1, 1}, 0, Half::G), InvalidInput);
}
