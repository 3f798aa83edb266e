// SPDX-License-Identifier: MIT
// Internal: the curve algorithms whose results need a bound, on "lines". A curve of lines is a Curve
// whose every stored row holds m control points of `cols` stored coordinates each (homogeneous when
// rational) and whose own `rational` flag is false: a curve is one line, and a surface's direction
// curve (direction_curve) holds every line of its net along that direction, so that one kernel serves
// both and bounds the motion of every line.
#pragma once

#include "cifs/nurbs/refine.hpp"

namespace cifs::nurbs::detail {

/// The points of a row: `cols` stored coordinates each, homogeneous `(w·x, w)` when rational.
struct Layout {
  Eigen::Index cols = 0;
  bool rational = false;
};

/// A bound on the distance between the shapes that two nets of the same basis functions of `degree` (in
/// the rows' direction) describe: `from` and `to`, the same shape of matrix, rows of points as `layout`
/// says. Non-rational: the largest distance between corresponding control points (the basis functions are
/// non-negative and sum to one). Rational, window by window of degree + 1 rows (those under one span):
/// S_to − S_from = Σ B_i (ΔA_i − S_to·Δw_i) / w_from, S_to in the hull of the window's points, so the
/// largest |ΔA_i − S·Δw_i| over that hull divided by the window's smallest weight (`to`'s weights > 0).
double deviation_bound(const Points& from, const Points& to, int degree, Layout layout);

/// remove_knot on a curve of lines (valid open curve, u an interior knot, times ≥ 0, tolerance ≥ 0):
/// each removal's residual is the largest over the lines' points, and the bound the largest over lines.
Removal remove_knot(const Curve& lines, double u, int times, double tolerance, Layout layout);

/// reduce_degree on a curve of lines (valid open curve of degree ≥ 2): every line reduced by one degree,
/// the bound over all of them. Throws InvalidInput (the message without a prefix) when a weight of the
/// reduced curve is not positive; the caller compares the bound with its tolerance.
Reduction reduce_degree(const Curve& lines, Layout layout);

}  // namespace cifs::nurbs::detail
