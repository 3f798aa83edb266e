// SPDX-License-Identifier: MIT
// cifs — knot insertion, refinement, Bézier splitting, degree elevation and knot removal.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "cifs/nurbs/curve.hpp"

namespace cifs::nurbs {

/// Boehm insertion of `u` `times` times. The result is the same curve; throws InvalidInput when u
/// is outside the domain or its multiplicity would exceed the degree.
Curve insert_knot(const Curve& c, double u, int times = 1);

/// Inserts many knots at once (any order, repeats allowed). Every new point is the blossom
/// `Q_j = b(t'_{j+1}, …, t'_{j+d})` of a piece of its support; open curves keep `Σ P_i N_i` on the
/// whole knot range, as Boehm's insertion does, closed curves stay periodic. Open curves with few new
/// knots per span (at most max(16, d + 1) in any d + 1 consecutive spans: single insertions, midpoint
/// refinement) get them by Boehm's insertion (Piegl–Tiller A5.4), whose chains of convex combinations
/// are then that short; otherwise, and for closed curves, each blossom is computed on its own (Oslo's
/// accuracy, whatever the number of knots).
Curve refine(const Curve& c, std::span<const double> new_knots);

/// Inserts the midpoint of every non-empty span of the domain (one knot-doubling step).
Curve refine_midpoints(const Curve& c);

/// The polynomial pieces as clamped Bézier curves of the same degree, one per non-empty span, in order.
std::vector<Curve> split_bezier(const Curve& c);

/// The open curve cut at `u`, strictly inside the domain: the part on [start, u] and the part on [u, end],
/// each clamped at u (u inserted up to multiplicity degree) and keeping the parameters of the original.
/// Throws InvalidInput for a closed curve or u not strictly inside the domain.
std::array<Curve, 2> split(const Curve& c, double u);

/// The same curve traversed backwards: knots `t'_j = a + b − t_{N−1−j}` (a, b the domain's ends, kept
/// exactly), control points in reverse order, so that `C'(a + b − u) = C(u)`. Closed curves stay closed.
Curve reverse(const Curve& c);

/// The same curve on the domain [start, end]: every knot mapped by the affine map that sends the domain
/// onto it (the ends exactly; knots outside an unclamped domain too), so that C'(start + (u − a)·(end −
/// start)/(b − a)) = C(u). Closed curves stay closed. Throws InvalidInput unless start < end are finite, or
/// when two distinct knots would round to one value (the scale leaves no double between them).
Curve reparametrize(const Curve& c, double start, double end);

/// reparametrize(c, 0, 1).
Curve normalize_knots(const Curve& c);

/// Raises the degree by `times`; the curve is unchanged. Each knot value of the domain gains
/// `times` in multiplicity; control points are blossoms of the raised degree.
Curve elevate_degree(const Curve& c, int times = 1);

/// Result of a knot removal: the curve and how many copies of the knot went.
struct Removal {
  Curve curve;
  int removed = 0;
  /// Proven bound on the distance between the old and the new curve over the domain.
  double deviation_bound = 0;
};

/// Removes up to `times` copies of the interior knot `u` while the curve moves by at most
/// `tolerance`: one copy at a time with the equations of Piegl–Tiller A5.8, solved from both ends
/// and meeting where α crosses ½; then a bound proven by re-inserting the removed knots.
/// Open curves only: throws InvalidInput for closed curves and for knots that are not interior.
Removal remove_knot(const Curve& c, double u, int times, double tolerance);

/// Result of a degree reduction: the curve one degree lower and a proven bound on its distance to the
/// original.
struct Reduction {
  Curve curve;
  /// max over the domain of |reduced(u) − original(u)|, bounded by elevating the reduced curve back to
  /// the original degree and comparing control points on a common knot vector (exact up to rounding).
  double deviation_bound = 0;
};

/// Degree reduction by one (The NURBS Book §5.6): each Bézier piece reduced by the inverse of degree
/// elevation, solved from both ends (Piegl–Tiller eq. 5.41–5.42; odd degrees average the middle point),
/// onto the knots with every multiplicity one less (a simple knot goes), so that the continuity C^(d−m)
/// stays and reduce_degree(elevate_degree(c)) is c. Two routes, the smaller proven bound kept: each new
/// point the blossom of the reduced piece under the widest interval of its support (exact for an
/// elevated curve), or the pieces joined and every interior knot brought down by knot removal (which
/// spreads what the pieces disagree by). Unclamped curves come back clamped on the same domain; rational
/// curves are reduced in homogeneous coordinates. Throws InvalidInput for a closed curve, degree 1, a
/// tolerance that is negative or NaN, a reduced weight that is not positive, and when the bound exceeds
/// `tolerance` (the message names both).
Reduction reduce_degree(const Curve& c, double tolerance);

}  // namespace cifs::nurbs
