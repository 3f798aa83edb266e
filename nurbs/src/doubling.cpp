// SPDX-License-Identifier: MIT
#include "cifs/nurbs/doubling.hpp"

#include <cmath>

#include "cifs/nurbs/knots.hpp"
#include "detail.hpp"

namespace cifs::nurbs {
namespace {

/// Knots `T_0 … T_{2d}` of the window with the segment as span d, normalised so that the segment
/// is [0, 1]: the matrices depend only on the ratios, and knots near the segment keep full relative
/// precision whatever the window's absolute position. T_0 is a dummy that no blossom reads.
Knots window_knots(std::span<const double> window, int d) {
  const double centre = window[static_cast<std::size_t>(d - 1)];
  Knots T(window.size() + 2, 0.0);
  const auto sd = static_cast<std::size_t>(d);
  T[sd + 1] = 1.0;
  for (std::size_t i = sd + 1; i + 1 < T.size(); ++i) T[i + 1] = T[i] + window[i - 1] / centre;
  for (std::size_t i = sd; i > 1; --i) T[i - 1] = T[i] - window[i - 2] / centre;
  T[0] = T[1] - 1;
  return T;
}

}  // namespace

void validate_window(std::span<const double> window, int degree) {
  validate_degree(degree);
  const auto expected = static_cast<std::size_t>(2 * degree - 1);
  if (window.size() != expected)
    detail::fail("window: ", window.size(), " inter-knots given, degree ", degree, " takes ", expected);
  for (std::size_t i = 0; i < window.size(); ++i) {
    if (!std::isfinite(window[i]) || window[i] < 0)
      detail::fail("window[", i, "]: ", window[i], " is not a finite non-negative length");
  }
  if (!(window[static_cast<std::size_t>(degree - 1)] > 0))
    detail::fail("window[", degree - 1, "]: the central interval must be positive");
}

Window child_window(std::span<const double> window, int degree, Half half) {
  validate_window(window, degree);
  // Doubled sequence, scaled by 2: a non-empty u_i becomes two intervals u_i, a zero interval (a
  // repeated knot) stays one zero. The child keeps the d − 1 neighbours on either side of its half.
  Window doubled;
  std::size_t centre = 0;
  for (std::size_t i = 0; i < window.size(); ++i) {
    if (i == static_cast<std::size_t>(degree - 1)) centre = doubled.size() + static_cast<std::size_t>(half);
    doubled.insert(doubled.end(), window[i] > 0 ? 2 : 1, window[i]);
  }
  const auto first = doubled.begin() + static_cast<std::ptrdiff_t>(centre) - (degree - 1);
  return Window(first, first + (2 * static_cast<std::ptrdiff_t>(degree) - 1));
}

Eigen::MatrixXd subdivision_matrix(std::span<const double> window, int degree, Half half) {
  validate_window(window, degree);
  const int d = degree;
  const Knots T = window_knots(window, d);
  // Refined knots: the midpoint of every non-empty interval inserted; the central interval
  // [T_d, T_{d+1}] becomes spans j (G) and j + 1 (D) of S.
  Knots S{T[0]};
  int j = 0;
  for (std::size_t i = 1; i < T.size(); ++i) {
    if (i == static_cast<std::size_t>(d)) j = static_cast<int>(S.size());
    S.push_back(T[i]);
    if (i + 1 < T.size() && T[i] < T[i + 1]) S.push_back(0.5 * (T[i] + T[i + 1]));
  }
  j += static_cast<int>(half);
  // The half's points are Q_i = blossom(S_{j−d+1+i}, …, S_{j+i}), i = 0..d, of the window's piece.
  Eigen::MatrixXd M(d + 1, d + 1);
  double W[kMaxDegree + 1];
  for (int i = 0; i <= d; ++i) {
    const auto args = std::span<const double>(S).subspan(
        static_cast<std::size_t>(j) - static_cast<std::size_t>(d) + 1 + static_cast<std::size_t>(i),
        static_cast<std::size_t>(d));
    blossom_weights(T, d, d, args, W);
    for (int k = 0; k <= d; ++k) M(i, k) = W[k];
  }
  return M;
}

Window segment_window(std::span<const double> knots, int degree, int span) {
  Window w(static_cast<std::size_t>(2 * degree - 1));
  for (int i = 0; i < 2 * degree - 1; ++i) {
    const auto k =
        static_cast<std::size_t>(span) - static_cast<std::size_t>(degree) + 1 + static_cast<std::size_t>(i);
    w[static_cast<std::size_t>(i)] = knots[k + 1] - knots[k];
  }
  return w;
}

}  // namespace cifs::nurbs
