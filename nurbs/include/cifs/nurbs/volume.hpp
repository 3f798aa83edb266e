// SPDX-License-Identifier: MIT
// cifs — trivariate tensor-product B-spline and NURBS volumes: evaluation and knot insertion per direction.
#pragma once

#include <array>

#include "cifs/nurbs/curve.hpp"

namespace cifs::nurbs {

/// A trivariate tensor-product volume, plain data; build it with make_volume, which validates.
/// `P` is `(nu·nv·nw) by (dim + rational)`: control point (i, j, k) — i along u, j along v, k along w —
/// is row `(i·nv + j)·nw + k`; homogeneous rows `(w·x, w)` when rational.
struct Volume {
  std::array<int, 3> degree{};
  std::array<Knots, 3> knots;
  std::array<Eigen::Index, 3> count{};
  Points P;
  bool rational = false;
};

/// Validated volume. `points` is `(nu·nv·nw) by dim` in the row order above; `weights` is empty or
/// nu·nv·nw positive values in the same order.
Volume make_volume(std::array<int, 3> degree, std::array<Knots, 3> knots, std::array<Eigen::Index, 3> count,
                   const Points& points, const Eigen::VectorXd& weights = {});

void validate(const Volume& v);

inline int dimension(const Volume& v) noexcept {
  return static_cast<int>(v.P.cols()) - (v.rational ? 1 : 0);
}

/// Volume point (Cartesian) at (u, v, w): the net combined along u, then v, then w (homogeneous rows
/// when rational, projected last). Throws InvalidInput for a parameter outside its domain.
Point evaluate(const Volume& vol, double u, double v, double w);

/// The curve of control rows along `direction` (0: u, 1: v, 2: w): row i holds the whole slab of the net at
/// index i of that direction (flattened, the other two directions in order), so every curve algorithm
/// applies to volumes direction by direction.
Curve direction_curve(const Volume& vol, int direction);

/// Boehm insertion of t `times` times in one direction (the curve insertion on direction_curve); the
/// volume is unchanged. Throws InvalidInput for a direction outside 0 … 2, and as the curve's insert_knot.
Volume insert_knot(const Volume& vol, int direction, double t, int times = 1);

}  // namespace cifs::nurbs
