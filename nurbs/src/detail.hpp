// SPDX-License-Identifier: MIT
// Internal kernels shared by the curve, surface and refinement sources.
#pragma once

#include <cmath>
#include <span>
#include <sstream>
#include <string_view>

#include "cifs/errors.hpp"
#include "cifs/nurbs/knots.hpp"
#include "cifs/types.hpp"

namespace cifs::nurbs::detail {

template <class... Parts>
[[noreturn]] void fail(Parts&&... parts) {
  std::ostringstream out;
  out.precision(17);
  (out << ... << parts);
  throw InvalidInput(out.str());
}

/// Cartesian points and optional weights → stored rows (homogeneous `(w·x, w)` when weighted).
inline Points homogeneous(const Points& points, const Eigen::VectorXd& weights, std::string_view where) {
  if (weights.size() == 0) return points;
  if (weights.size() != points.rows())
    fail("weights: ", weights.size(), " weights given for ", points.rows(), " ", where);
  Points H(points.rows(), points.cols() + 1);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {  // weights are checked by validate()
    H.row(i).head(points.cols()) = weights(i) * points.row(i);
    H(i, points.cols()) = weights(i);
  }
  return H;
}

/// `Σ N_j(u) P_{span−p+j}` into `out` (P.cols() values); no allocation.
inline void evaluate_homogeneous(std::span<const double> knots, int p, const Points& P, double u, int span,
                                 double* out) noexcept {
  double N[kMaxDegree + 1];
  basis_functions(knots, p, span, u, N);
  const Eigen::Index cols = P.cols();
  const double* base = P.data() + (span - p) * cols;
  for (Eigen::Index k = 0; k < cols; ++k) out[k] = N[0] * base[k];
  for (int j = 1; j <= p; ++j) {
    const double* row = base + j * cols;
    for (Eigen::Index k = 0; k < cols; ++k) out[k] += N[j] * row[k];
  }
}

/// Homogeneous derivatives `(order+1) by (dim+1)` → Cartesian derivatives by the quotient rule
/// (Piegl–Tiller A4.2).
inline Points rational_derivatives(const Points& H, int dim) {
  const Eigen::Index order = H.rows() - 1;
  Points C(H.rows(), dim);
  for (Eigen::Index k = 0; k <= order; ++k) {
    Point v = H.row(k).head(dim);
    double binom = 1;  // C(k, i)
    for (Eigen::Index i = 1; i <= k; ++i) {
      binom = binom * static_cast<double>(k - i + 1) / static_cast<double>(i);
      v -= binom * H(i, dim) * C.row(k - i);
    }
    C.row(k) = v / H(0, dim);
  }
  return C;
}

/// Blossom of the piece on `span` at `args`, as a row of the stored coordinates.
inline Point blossom_row(std::span<const double> knots, int p, const Points& P, std::span<const double> args,
                         int span) {
  double W[kMaxDegree + 1];
  blossom_weights(knots, p, span, args, W);
  Point out = Point::Zero(P.cols());
  for (int j = 0; j <= p; ++j) out += W[j] * P.row(span - p + j);
  return out;
}

}  // namespace cifs::nurbs::detail
