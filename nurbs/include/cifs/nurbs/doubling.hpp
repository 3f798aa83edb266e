// SPDX-License-Identifier: MIT
// cifs — knot doubling: the non-uniform G/D subdivision matrices of a segment from its window.
#pragma once

#include <Eigen/Core>
#include <array>
#include <span>
#include <vector>

namespace cifs::nurbs {

/// The 2d − 1 inter-knot lengths `u_0 … u_{2d−2}` around a segment of degree d; the segment is
/// the central interval `u_{d−1}` (non-zero), the others may be zero (repeated knots).
using Window = std::vector<double>;

/// Halves of a segment after inserting its midpoint: G (left) and D (right).
enum class Half { G = 0, D = 1 };

/// Throws InvalidInput unless the window has 2d − 1 finite non-negative entries and a positive
/// centre (then every knot it implies has multiplicity ≤ d: at most d − 1 zeros lie on each side).
void validate_window(std::span<const double> window, int degree);

/// Window of the G or D half after knot doubling, scaled by 2 (a window's matrices do not depend on
/// its scale): G keeps `u_{d'} … ` so that for degree 2 `G(u1,u2,u3) = (u1,u2,u2)`,
/// `D(u1,u2,u3) = (u2,u2,u3)`, and for degree 3 `G = (u1,u1,u2,u2,u3)`, `D = (u1,u2,u2,u3,u3)`.
Window child_window(std::span<const double> window, int degree, Half half);

/// `(d+1) by (d+1)` matrix M with `Q = M·P`: the d + 1 control points of the G or D half of the
/// segment from its d + 1 control points (rows sum to 1). Entries are blossom weights at the
/// refined knots; degree 2 reduces to the closed forms of Morlet et al., uniform knots to Chaikin
/// (¾, ¼) and to the Lane–Riesenfeld masks.
Eigen::MatrixXd subdivision_matrix(std::span<const double> window, int degree, Half half);

/// The segment's window in a knot vector of `degree` for the non-empty span `k`
/// (`u_i = t_{i+1} − t_i` for i = k−d+1 … k+d−1).
Window segment_window(std::span<const double> knots, int degree, int span);

}  // namespace cifs::nurbs
