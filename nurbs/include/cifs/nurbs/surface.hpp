// SPDX-License-Identifier: MIT
// cifs — tensor-product B-spline and NURBS surfaces: evaluation, partial derivatives, normals,
// knot insertion in u and in v.
#pragma once

#include <array>
#include <span>
#include <vector>

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

/// Result of a knot removal on a surface: the surface and how many copies of the knot went.
struct SurfaceRemoval {
  Surface surface;
  int removed = 0;
  /// Proven bound on the distance between the old and the new surface over the domain.
  double deviation_bound = 0;
};

/// Removes up to `times` copies of the interior knot t of direction `dir` while the surface moves by at
/// most `tolerance`: the curve algorithm (remove_knot) on every line of the net along `dir` at once, each
/// copy removed only when every line's residual is within the tolerance; the bound, proven by
/// re-inserting the removed copies, is the largest control-point difference (rational: through the
/// weights, as for curves). Throws InvalidInput, naming the direction, for t not an interior knot, negative
/// times or a tolerance that is negative or NaN.
SurfaceRemoval remove_knot(const Surface& s, Direction dir, double t, int times, double tolerance);

/// Raises the degree of direction `dir` by `times` (every line of the net along it, as elevate_degree
/// raises a curve); the surface is unchanged.
Surface elevate_degree(const Surface& s, Direction dir, int times = 1);

/// Result of a degree reduction of a surface: the surface one degree lower in one direction and a proven
/// bound on its distance to the original.
struct SurfaceReduction {
  Surface surface;
  double deviation_bound = 0;
};

/// reduce_degree of every line of the net along `dir` (the curve algorithm, one bound over all lines).
/// Throws InvalidInput as the curve's, naming the direction.
SurfaceReduction reduce_degree(const Surface& s, Direction dir, double tolerance);

/// The Bézier patches, one per pair of non-empty spans: patch (a, b) — the a-th span of u, the b-th of v —
/// at index a·(spans of v) + b, each clamped on its spans with the degrees of the surface.
std::vector<Surface> split_bezier(const Surface& s);

/// The same surface traversed backwards in `dir`: its knots mirrored in the domain (S'(a + b − u, v) =
/// S(u, v) for u), the lines of the net along `dir` reversed.
Surface reverse(const Surface& s, Direction dir);

/// The same surface with u and v exchanged: S'(v, u) = S(u, v) (the normal turns over).
Surface swap_uv(const Surface& s);

/// The same surface on [start, end] in direction `dir` (reparametrize of curves, on that direction's knots).
Surface reparametrize(const Surface& s, Direction dir, double start, double end);

/// Both directions on [0, 1].
Surface normalize_knots(const Surface& s);

/// Curvatures of a 3-D surface at a point, from the first fundamental form (E, F, G of S_u, S_v) and the
/// second (L, M, N of S_uu, S_uv, S_vv on the unit normal n = S_u × S_v / |S_u × S_v|). Curvatures are
/// positive where the surface bends towards n (a sphere whose n points outwards has K = 1/r², H = −1/r).
struct Curvature {
  Eigen::Vector3d point, normal;
  double gaussian = 0;  // K = (LN − M²) / (EG − F²) = k1·k2
  double mean = 0;      // H = (EN − 2FM + GL) / (2(EG − F²)) = (k1 + k2) / 2
  /// k1 ≥ k2, the eigenvalues of the shape operator, and their unit directions in space (tangent,
  /// orthogonal; directions[1] = n × directions[0]). At an umbilic (k1 = k2 within rounding) every
  /// direction is principal: directions[0] is then S_u's.
  std::array<double, 2> principal{};
  std::array<Eigen::Vector3d, 2> directions;
};

/// Throws InvalidInput for (u, v) outside the domain, a surface that is not 3-D, or where the first
/// fundamental form is singular (S_u × S_v = 0: a pole, a cusp, a collapsed edge; the message names the
/// point).
Curvature curvature(const Surface& s, double u, double v);

/// The curve of control rows along `dir`: row i of its points holds a whole line of the net
/// (nv or nu points, flattened), so every curve algorithm applies to surfaces direction by direction.
Curve direction_curve(const Surface& s, Direction dir);

}  // namespace cifs::nurbs
