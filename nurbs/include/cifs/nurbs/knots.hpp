// SPDX-License-Identifier: MIT
// cifs — knot vectors, span search and B-spline basis functions (Cox–de Boor).
#pragma once

#include <Eigen/Core>
#include <span>
#include <string_view>
#include <vector>

namespace cifs::nurbs {

using Knots = std::vector<double>;

/// Largest degree the library accepts: kernels keep d+1 values on the stack.
inline constexpr int kMaxDegree = 64;

/// The parameter interval `[t_d, t_n]` on which the basis functions sum to one.
struct Domain {
  double start = 0;
  double end = 0;
};

/// Throws InvalidInput unless `knots` is a knot vector of `count` control points of `degree`:
/// finite, non-decreasing, `count + degree + 1` values, multiplicities ≤ degree + 1 and a non-empty
/// domain. `where` prefixes the message (a file path, "knots[1]" for a surface direction, ...).
void validate_knots(std::span<const double> knots, int degree, Eigen::Index count,
                    std::string_view where = "knots");

/// Throws InvalidInput unless the basis functions of `degree` on `span` are defined (basis_functions,
/// basis_derivatives, blossom_weights): 0 ≤ degree ≤ kMaxDegree, finite non-decreasing knots, degree ≤
/// span, span + degree < #knots and a non-empty span `t_span < t_{span+1}`. The multiplicities of the
/// other knots do not matter: the recursion divides only by the lengths of intervals that contain the
/// span (degree 1 on a clamped quadratic knot vector is defined).
void validate_span_query(std::span<const double> knots, int degree, int span);

/// Throws InvalidInput unless 1 ≤ degree ≤ kMaxDegree.
void validate_degree(int degree, std::string_view where = "degree");

/// Number of control points a knot vector of `degree` serves: `size − degree − 1`.
inline Eigen::Index control_count(std::span<const double> knots, int degree) noexcept {
  return static_cast<Eigen::Index>(knots.size()) - degree - 1;
}

/// `[t_d, t_n]` with `n = control_count`.
Domain domain(std::span<const double> knots, int degree) noexcept;

/// The span `k ∈ [d, n−1]` with `t_k ≤ u < t_{k+1}`. The domain end `u = t_n` belongs to the
/// last non-empty span. No epsilon: a parameter one ulp left of a knot stays in the span before it.
/// Precondition: `u` in the domain (values outside are clamped to the first/last span).
int find_span(std::span<const double> knots, int degree, double u) noexcept;

/// As find_span, starting from a guess (sorted parameters walk forward in O(1) amortised).
int find_span(std::span<const double> knots, int degree, double u, int hint) noexcept;

/// Multiplicity of the value `u` in `knots` (0 when absent).
int multiplicity(std::span<const double> knots, double u) noexcept;

/// Distinct knot values inside the domain, in order (breakpoints of the piecewise polynomial).
std::vector<double> breakpoints(std::span<const double> knots, int degree);

/// The `degree + 1` non-zero basis functions `N_{k−d..k}(u)` on span `k` (Piegl–Tiller A2.2).
void basis_functions(std::span<const double> knots, int degree, int span, double u, double* N) noexcept;

/// Weights `W_0..W_d` with `blossom(x_1..x_d) = Σ_j W_j P_{span−d+j}` for the piece on `span`: the
/// basis recursion with one argument per level (all arguments equal to u give basis_functions). The
/// arguments may come in any order; the weights do not depend on it, to the last bit.
void blossom_weights(std::span<const double> knots, int degree, int span, std::span<const double> args,
                     double* W) noexcept;

/// Non-zero basis functions and their derivatives up to `order`: `(order+1) by (degree+1)`,
/// row r holds the r-th derivatives of `N_{k−d..k}` (Piegl–Tiller A2.3; zero for r > degree).
Eigen::MatrixXd basis_derivatives(std::span<const double> knots, int degree, int span, double u, int order);

/// Knot vector of a closed (periodic) curve of `degree` with period breakpoints `b_0..b_m`
/// (`b_m = b_0 + T`): `m + 2d + 1` knots `t_j = b_{(j−d) mod m} + ⌊(j−d)/m⌋·T`, domain `[b_0, b_m]`.
Knots periodic_knots(std::span<const double> breakpoints, int degree);

}  // namespace cifs::nurbs
