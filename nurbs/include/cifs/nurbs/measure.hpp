// SPDX-License-Identifier: MIT
// cifs — measuring curves: arc length and its inverse, Frenet frames, closest points, intersections with
// hyperplanes and with other curves, tight bounding boxes, projective transforms; closest points on
// surfaces.
//
// The global searches (closest point, intersections, bounding box) work on the Bézier pieces of the
// curve's spans: a piece lies in the convex hull of its control points (projected when rational: the
// weights are positive), so a piece whose hull misses what is sought is dropped; the roots of a scalar
// Bézier polynomial are isolated by halving until it is monotone or has one extremum, then found by
// Newton's method kept in a bracket.
#pragma once

#include <array>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::nurbs {

/// An arc length and an estimate of its error.
struct Length {
  double value = 0;
  /// Σ over the accepted intervals of |G(I) − G(I_left) − G(I_right)|, G the 8-point Gauss–Legendre rule
  /// of |C′|: the difference between one rule and the same rule on the halves. `value` is the sum on the
  /// halves, whose error is smaller than that difference by about 2^16 where |C′| is smooth, so this
  /// over-estimates the error; it is an estimate, not a proof (a cusp, C′ = 0, slows the convergence but
  /// the intervals around it are halved until their difference is small too).
  double error = 0;
};

/// Length of the curve between the parameters a ≤ b of its domain (closed curves: within the period,
/// no wrap), to `tolerance` relative to the length: every span is integrated by adaptive Gauss–Legendre
/// (8 points, halving an interval until its two estimates differ by less than its share of the
/// tolerance). Throws InvalidInput for a or b outside the domain, a > b, or a tolerance not in
/// [1e-15, 1).
Length arc_length(const Curve& c, double a, double b, double tolerance = 1e-12);
/// The length of the whole domain.
Length arc_length(const Curve& c, double tolerance = 1e-12);

/// The parameter u ≥ start with arc_length(c, start, u) = `length` (to `tolerance` relative to the
/// curve's length): the span where the cumulated length reaches it, then Newton's method on the length
/// (dL/du = |C′(u)|) kept inside a bracket that bisection shrinks where Newton would leave it or |C′|
/// vanishes. Where the curve stands still (C′ = 0 on an interval) the first such parameter is returned.
/// Throws InvalidInput for start outside the domain, a negative length, or a length beyond the end.
double parameter_at_length(const Curve& c, double length, double start, double tolerance = 1e-12);

/// The Frenet frame of a 2-D or 3-D curve at u. 2-D curves: the normal turns the tangent by +90° when
/// the curve turns left (signed curvature), there is no binormal and the torsion is 0.
struct Frenet {
  Point point, tangent;  // C(u) and C′/|C′|
  /// Empty where the curvature is zero (|C′ × C″| ≤ 1e-12·|C′|·|C″|, or C″ = 0): the normal is undefined.
  Point normal, binormal;
  double speed = 0;      // |C′(u)|
  double curvature = 0;  // |C′ × C″| / |C′|³ (2-D: signed)
  double torsion = 0;    // (C′ × C″)·C‴ / |C′ × C″|² (3-D, where the normal is defined; else 0)
};

/// Throws InvalidInput for u outside the domain, a curve that is not 2-D or 3-D, or where C′(u) = 0 (the
/// tangent is undefined; the message names u).
Frenet frenet_frame(const Curve& c, double u);

/// Every point of a curve nearest to a given point.
struct ClosestPoints {
  double distance = 0;
  /// The parameters of the isolated nearest points, ascending (a closed curve's seam counts once, at the
  /// domain start); `points` holds the curve points, one row each.
  std::vector<double> parameters;
  Points points;
  /// Parameter intervals on which the curve stays at the nearest distance (a circle about the point):
  /// merged spans on which (C − q)·C′ vanishes to its rounding (the distance is constant there).
  std::vector<std::array<double, 2>> intervals;
};

/// The points of the curve nearest to q (dim values), all of them whose distance is within
/// `tolerance`·size of the smallest (size: the larger of the control points' bounding-box diagonal and
/// their largest coordinate). Global: the spans are taken nearest first by the hull of their p + 1
/// B-spline control points, and a span whose hull is farther than the best distance found so far is
/// dropped (the bound: the points' box, and their chord less their spread about it; then the same on
/// the tighter Bézier control points). On each remaining span every critical point of the distance is
/// a root of the polynomial (C − q)·C′ (times w³ when rational: degree 2p − 1, or 3p − 1), found by
/// the root finder of intersect_plane, so no minimum is missed where a span holds several.
/// Throws InvalidInput for q of the wrong size or not finite, or a tolerance not in [1e-15, 1).
ClosestPoints closest_point(const Curve& c, const Point& q, double tolerance = 1e-12);

/// Every point of a surface nearest to a given point.
struct SurfaceClosestPoints {
  double distance = 0;
  /// The (u, v) parameters of the isolated nearest points, ascending in u then v; `points` holds the
  /// surface points, one row each. A collapsed edge (the pole of a sphere of revolution) is one point,
  /// reported once.
  std::vector<std::array<double, 2>> parameters;
  Points points;
  /// Parameter rectangles {u0, u1, v0, v1} on which the surface stays at the nearest distance: the whole
  /// domain for the centre of a sphere; a segment (u0 = u1 or v0 = v1) for a circle, such as the inner
  /// equator of a torus seen from its centre. Adjacent rectangles are merged; points inside are not
  /// repeated in `parameters`.
  std::vector<std::array<double, 4>> regions;
};

/// The points of the surface nearest to q (dim values), all of them whose distance is within
/// `tolerance`·size of the smallest (size as for curves, on the control net). Global: a nearest point
/// is either on an edge of the domain (or on an interior knot line where the surface is not C¹: a
/// multiplicity ≥ the degree), where the curve closest_point of that iso-curve finds it, or inside,
/// where it is a zero of F = ((S − q)·S_u, (S − q)·S_v). The Bézier patches are taken nearest first by
/// the hull of their control points (projected when rational: weights > 0), dropped when that bound
/// exceeds the best distance found; the two components of F (times w³ when rational) are Bézier
/// polynomials, and a piece of a patch is dropped when one of them keeps a sign on it, solved by Newton's
/// method kept inside it when their gradient cones show it holds at most one zero (Elber and Kim's test:
/// no direction is normal to both), else cut in four (de Casteljau in u and v). A piece on which one
/// component vanishes (to its rounding) depends on one parameter only: its nearest lines are the roots of
/// the other along an edge (a region); where both vanish the distance is constant (a region).
/// Throws InvalidInput for q of the wrong size or not finite, a tolerance not in [1e-15, 1), and a
/// continuum of nearest points that no parameter line follows (more than 20000 pieces: a non-isolated set
/// of critical points).
SurfaceClosestPoints closest_point(const Surface& s, const Point& q, double tolerance = 1e-12);

/// Where a curve meets the hyperplane {x : normal·x = offset}.
struct PlaneIntersection {
  std::vector<double> parameters;  // ascending; a tangential contact once
  /// Parameter intervals on which the curve lies in the plane (within the tolerance).
  std::vector<std::array<double, 2>> intervals;
};

/// Every parameter where the curve meets the hyperplane (normal: dim values, not zero), to within
/// `tolerance`·size in distance. Per span, the signed distance times the weight is a Bézier polynomial
/// h; a piece whose coefficients all have one sign is dropped, a piece where h is monotone holds one root
/// (found by Newton inside its bracket), a piece where h′ is monotone holds one extremum: a tangential
/// contact when |h| there is within the tolerance (reported once), else the roots on either side.
PlaneIntersection intersect_plane(const Curve& c, const Point& normal, double offset,
                                  double tolerance = 1e-12);

/// A point where two curves meet.
struct CurveIntersection {
  double u = 0;         // parameter on the first curve
  double v = 0;         // parameter on the second
  Point point;          // the first curve's point
  double distance = 0;  // |A(u) − B(v)| (≤ the tolerance)
};

/// Every point where the curves (same dimension, 2-D or more) come within `tolerance`·size of each
/// other (size: the larger bounding-box diagonal), by pairs of pieces whose control boxes overlap,
/// halved until flat, then Gauss–Newton on A(u) − B(v); points closer than the tolerance to each other
/// are one (tangential contacts once), ordered by u. Throws InvalidInput for curves of different
/// dimensions, and for curves that overlap along an arc (more than 4096 pieces survive).
std::vector<CurveIntersection> intersect_curves(const Curve& a, const Curve& b, double tolerance = 1e-9);

/// An axis-aligned box: lower and upper corners (dim values each).
struct Box {
  Point lower, upper;
};

/// The smallest box that holds the curve: per span and coordinate, the values at the span's ends and at
/// the roots of the coordinate's derivative (numerator A′w − Aw′ when rational, a Bézier polynomial of
/// degree 2d − 2), found as intersect_plane finds roots.
Box bounding_box(const Curve& c);

/// The curve mapped by the (dim + 1)² matrix M acting on homogeneous points (x, 1): every stored row
/// (w·x, w) becomes M·(w·x, w). An affine M (last row 0 … 0 1) keeps a polynomial curve polynomial and
/// the weights; a projective M makes it rational. Exact for every M whose new weights stay positive;
/// throws InvalidInput for a matrix of the wrong size or not finite, or a weight that becomes ≤ 0 (the
/// curve crosses the plane sent to infinity).
Curve transform(const Curve& c, const Eigen::MatrixXd& matrix);

}  // namespace cifs::nurbs
