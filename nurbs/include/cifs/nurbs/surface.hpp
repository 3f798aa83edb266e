// SPDX-License-Identifier: MIT
// cifs — tensor-product B-spline and NURBS surfaces: evaluation, partial derivatives, normals,
// knot insertion in u and in v.
#pragma once

#include <array>
#include <span>

#include "cifs/nurbs/curve.hpp"

namespace cifs::nurbs {

/// Parameter direction of a surface.
enum class Direction { u = 0, v = 1 };

/// A tensor-product surface, plain data; build it with make_surface, which validates.
/// `P` is `(nu·nv) by (dim + rational)`: control point (i, j) — i along u, j along v — is row
/// `i·nv + j`; homogeneous rows `(w·x, w)` when rational.
struct Surface {
  std::array<int, 2> degree{};
  std::array<Knots, 2> knots;
  std::array<Eigen::Index, 2> count{};  // nu, nv
  Points P;
  bool rational = false;
};

/// Validated surface. `points` is `(nu·nv) by dim` in the row order above; `weights` is empty or
/// nu·nv positive values in the same order.
Surface make_surface(std::array<int, 2> degree, std::array<Knots, 2> knots, std::array<Eigen::Index, 2> count,
                     const Points& points, const Eigen::VectorXd& weights = {});

void validate(const Surface& s);

inline int dimension(const Surface& s) noexcept {
  return static_cast<int>(s.P.cols()) - (s.rational ? 1 : 0);
}
inline Domain domain(const Surface& s, Direction dir) noexcept {
  return domain(s.knots[static_cast<int>(dir)], s.degree[static_cast<int>(dir)]);
}

Points cartesian_points(const Surface& s);
Eigen::VectorXd weights(const Surface& s);

/// Surface point (Cartesian). Throws InvalidInput outside the domain.
Point evaluate(const Surface& s, double u, double v);

/// Points on the grid `us × vs`: row `a·#vs + b` is S(us[a], vs[b]). The u-combination is done once
/// per grid row, so a grid costs O(#us·nv + #us·#vs) combinations of control points.
Points evaluate_grid(const Surface& s, std::span<const double> us, std::span<const double> vs);
/// The same into `out`, whose storage is reused when it already has the size (no page faults on
/// repeated calls; fresh storage is advised for huge pages). `out` must not be `s.P`.
void evaluate_grid(const Surface& s, std::span<const double> us, std::span<const double> vs, Points& out);

/// Partial derivatives `∂^{k+l} S / ∂u^k ∂v^l` for k + l ≤ order: row `k·(order+1) + l`
/// (rows with k + l > order are zero). Cartesian; quotient rule when rational.
/// Throws InvalidInput for an order outside 0 … kMaxDegree.
Points derivatives(const Surface& s, double u, double v, int order);

/// Unit normal `S_u × S_v / |S_u × S_v|` (3-D surfaces). Throws InvalidInput where the normal is
/// undefined (degenerate point, or a surface that is not 3-D).
Eigen::Vector3d normal(const Surface& s, double u, double v);

/// Knot insertion and refinement in one direction; the surface is unchanged.
Surface insert_knot(const Surface& s, Direction dir, double t, int times = 1);
Surface refine(const Surface& s, Direction dir, std::span<const double> new_knots);
Surface refine_midpoints(const Surface& s);

/// The surface cut at t in direction `dir`, strictly inside that domain: the parts on [start, t] and
/// [t, end], each clamped at t and keeping the original parameters (split of the direction curve).
/// Throws InvalidInput, naming the direction, for t not strictly inside.
std::array<Surface, 2> split(const Surface& s, Direction dir, double t);

/// The iso-parametric curve at parameter t of direction `dir`, running along the other direction:
/// `iso_curve(s, u, t)(v) = S(t, v)`, exactly (its net is the combination of the net's lines at t).
/// Throws InvalidInput for t outside the domain.
Curve iso_curve(const Surface& s, Direction dir, double t);

/// The curve of control rows along `dir`: row i of its points holds a whole line of the net
/// (nv or nu points, flattened), so every curve algorithm applies to surfaces direction by direction.
Curve direction_curve(const Surface& s, Direction dir);

}  // namespace cifs::nurbs
