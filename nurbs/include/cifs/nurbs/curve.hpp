// SPDX-License-Identifier: MIT
// cifs — B-spline and NURBS curves of any degree and dimension: evaluation, derivatives, blossoms.
#pragma once

#include <span>

#include "cifs/nurbs/knots.hpp"
#include "cifs/types.hpp"

namespace cifs::nurbs {

/// A B-spline or NURBS curve, plain data. Build it with make_curve / make_closed_curve, which
/// validate; every algorithm below assumes a valid curve.
///
/// `P` is `n by (dim + rational)`: Cartesian rows, or homogeneous rows `(w·x, w)` when rational.
/// A closed (periodic) curve of m distinct control points is stored expanded: `n = m + d` rows whose
/// last d repeat the first d, and `periodic_knots` of its breakpoints; its domain is one period.
struct Curve {
  int degree = 0;
  Knots knots;
  Points P;
  bool rational = false;
  bool closed = false;
};

/// Validated open curve (clamped or unclamped). `points` is `n by dim`; `weights` is empty
/// (non-rational) or n positive finite values.
Curve make_curve(int degree, Knots knots, const Points& points, const Eigen::VectorXd& weights = {});

/// Validated closed curve from m distinct control points and the period's breakpoints `b_0..b_m`
/// (m + 1 non-decreasing values, `b_m > b_0`).
Curve make_closed_curve(int degree, Knots breakpoints, const Points& points,
                        const Eigen::VectorXd& weights = {});

/// The uniform B-spline of degree d on a control polygon (`n by dim`): closed → periodic with
/// breakpoints 0, 1, …, n (n ≥ 2); open → clamped with interior knots 1, 2, …, n − d − 1
/// (n ≥ d + 1). The closed one is what Lane–Riesenfeld subdivision of order d + 1 converges to.
Curve uniform_bspline(const Points& polygon, int degree, bool closed);

/// Throws InvalidInput unless the curve satisfies every invariant above.
void validate(const Curve& curve);

inline int dimension(const Curve& c) noexcept {
  return static_cast<int>(c.P.cols()) - (c.rational ? 1 : 0);
}
inline Domain domain(const Curve& c) noexcept {
  return domain(c.knots, c.degree);
}

/// Number of distinct control points: n, or m for a closed curve.
Eigen::Index distinct_count(const Curve& c) noexcept;

/// Closed curves: the m + 1 breakpoints of the period. Open curves: the knots.
Knots defining_knots(const Curve& c);

/// Cartesian control points (`distinct_count by dim`) and weights (ones when non-rational).
Points cartesian_points(const Curve& c);
Eigen::VectorXd weights(const Curve& c);

/// Number of non-empty spans in the domain (polynomial segments).
int segment_count(const Curve& c) noexcept;

/// Maps `u` into the domain: wraps it by the period for closed curves; throws InvalidInput for an
/// open curve when `u` is outside the domain or not finite.
double domain_parameter(const Curve& c, double u);

/// Curve point (Cartesian, `dim` values) by de Boor's algorithm.
Point evaluate(const Curve& c, double u);

/// Curve point by the basis form `Σ N_i(u) P_i` (rational: projected after summing).
Point evaluate_basis(const Curve& c, double u);

/// Points at many parameters (`#us by dim`, in order). Sorted parameters reuse the previous span.
Points evaluate(const Curve& c, std::span<const double> us);

/// `count` parameters evenly spaced over the domain, both ends included (count ≥ 2; 1 gives the start).
std::vector<double> uniform_parameters(Domain dom, int count);
/// Parameters `first` … `first + n − 1` of uniform_parameters(dom, count), the same doubles: for
/// callers that take them a chunk at a time. Requires 0 ≤ first and first + n ≤ count.
std::vector<double> uniform_parameters(Domain dom, int count, int first, int n);

/// Derivatives of order 0..`order` at u: `(order+1) by dim`, Cartesian (quotient rule when rational).
/// Throws InvalidInput for an order outside 0 … kMaxDegree.
Points derivatives(const Curve& c, double u, int order);

/// Blossom (polar form) of the polynomial piece on `span`, at `degree` arguments, in the stored
/// coordinates (homogeneous when rational). Symmetric, multi-affine, `blossom(u,…,u) = C(u)`, and
/// `blossom(t_{i+1},…,t_{i+d}) = P_i` for any span of the support of `N_i`.
Point blossom(const Curve& c, std::span<const double> args, int span);

/// Blossom on the span that contains the mean of the arguments (for closed curves, after wrapping).
Point blossom(const Curve& c, std::span<const double> args);

/// Cartesian projection of a stored-coordinate row (divides by w when rational).
Point to_cartesian(const Curve& c, const Point& row);

}  // namespace cifs::nurbs
