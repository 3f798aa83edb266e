// SPDX-License-Identifier: MIT
// cifs — trivariate tensor-product B-spline and NURBS volumes: evaluation, partial derivatives, and the knot
// operations of curves (insertion, refinement, removal, degree elevation, splitting, reversal,
// reparametrisation) direction by direction, on direction_curve.
#pragma once

#include <array>
#include <span>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

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

/// Points on the grid `us × vs × ws`: row `(a·#vs + b)·#ws + c` is V(us[a], vs[b], ws[c]). The net is
/// combined along u once per u parameter (a surface net), then evaluated on `vs × ws` by the surface's
/// evaluate_grid. Throws InvalidInput for a parameter outside its domain, naming it.
Points evaluate_grid(const Volume& vol, std::span<const double> us, std::span<const double> vs,
                     std::span<const double> ws);

/// Partial derivatives `∂^{a+b+c} V / ∂u^a ∂v^b ∂w^c` for a + b + c ≤ order: row
/// `(a·(order+1) + b)·(order+1) + c` (rows with a + b + c > order are zero). Cartesian; the quotient rule
/// in three variables when rational. Throws InvalidInput for an order outside 0 … kMaxDegree or a
/// parameter outside its domain.
Points derivatives(const Volume& vol, double u, double v, double w, int order);

/// Inserts many knots in one direction at once (the curve refine on direction_curve); the volume is
/// unchanged.
Volume refine(const Volume& vol, int direction, std::span<const double> new_knots);

/// Result of a knot removal on a volume: the volume and how many copies of the knot went.
struct VolumeRemoval {
  Volume volume;
  int removed = 0;
  /// Proven bound on the distance between the old and the new volume over the domain.
  double deviation_bound = 0;
};

/// Removes up to `times` copies of the interior knot t of `direction` while the volume moves by at most
/// `tolerance`: the curve algorithm on every line of the net along that direction at once, as the surface's
/// remove_knot (a copy goes only when every line's residual is within the tolerance; the bound, proven by
/// re-inserting the removed copies, is the largest over lines). Throws InvalidInput, naming the argument,
/// for a direction outside 0 … 2, t not an interior knot, negative times or a tolerance that is negative
/// or NaN.
VolumeRemoval remove_knot(const Volume& vol, int direction, double t, int times, double tolerance);

/// Raises the degree of `direction` by `times` (every line of the net along it); the volume is unchanged.
Volume elevate_degree(const Volume& vol, int direction, int times = 1);

/// The volume cut at t of `direction`, strictly inside that domain: the parts on [start, t] and [t, end],
/// each clamped at t and keeping the original parameters.
std::array<Volume, 2> split(const Volume& vol, int direction, double t);

/// The surface at parameter t of `direction`, in the other two directions in order (u fixed: S(v, w);
/// v fixed: S(u, w); w fixed: S(u, v)), exactly: its net is the combination of the net's slabs at t.
Surface iso_surface(const Volume& vol, int direction, double t);

/// The same volume traversed backwards in `direction`: its knots mirrored in the domain, the net's lines
/// along it reversed (V'(…, a + b − t, …) = V(…, t, …)).
Volume reverse(const Volume& vol, int direction);

/// The same volume on [start, end] in `direction` (reparametrize of curves, on that direction's knots).
Volume reparametrize(const Volume& vol, int direction, double start, double end);

/// Every direction on [0, 1].
Volume normalize_knots(const Volume& vol);

}  // namespace cifs::nurbs
