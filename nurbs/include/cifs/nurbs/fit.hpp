// SPDX-License-Identifier: MIT
// cifs — fitting (The NURBS Book ch. 9): global interpolation of curves through points and of surfaces
// through grids, least-squares approximation with a given number of control points or to a tolerance.
#pragma once

#include <array>
#include <span>
#include <string_view>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::nurbs {

/// How data points get their parameters in [0, 1].
enum class Parametrization {
  uniform,       // equally spaced
  chord_length,  // proportional to the distances between consecutive points
  centripetal,   // proportional to their square roots (Lee 1989)
};

/// "uniform", "chord_length" (or "chord-length"), "centripetal"; InvalidInput naming them otherwise.
Parametrization parametrization_named(std::string_view name);

/// Parameters `ū_0 = 0 < … < ū_{m−1} = 1` of the rows of `points` (`m by dim`). Closed: the chord from
/// the last point back to the first counts too, and the m values are `ū_0 = 0 < … < ū_{m−1} < 1`
/// (the period is [0, 1]). Throws InvalidInput for fewer than 2 points, a coordinate that is not
/// finite, or (chord length, centripetal) two consecutive points that coincide.
std::vector<double> fit_parameters(const Points& points, Parametrization kind, bool closed = false);

/// Knots of the interpolating curve of `degree` through data at `parameters` (The NURBS Book eq. 9.8,
/// averaging): clamped on [ū_0, ū_{m−1}], m control points; every span holds a parameter, so the
/// collocation matrix is invertible (Schoenberg–Whitney). `extra` (0, 1 or 2) end derivatives add as
/// many control points: the parameter of each derivative's end counts twice in the averages (eq. 9.22
/// for 2); `end_only` says that one derivative is at the end, not the start.
Knots averaged_knots(std::span<const double> parameters, int degree, int extra = 0, bool end_only = false);

/// Knots of a least-squares fit by `count` control points of data at `parameters` (m values,
/// degree + 1 ≤ count < m): the interior knots lie at the fractional data indices `j·(m−1)/(count−degree)`,
/// interpolated between parameters. Reversing the data reverses the knots, and every span holds a
/// parameter strictly inside it (the Schoenberg–Whitney condition holds, so the normal equations
/// are positive definite).
Knots approximation_knots(std::span<const double> parameters, int degree, Eigen::Index count);

struct InterpolateOptions {
  int degree = 3;
  Parametrization parametrization = Parametrization::chord_length;
  /// Optional derivatives dC/du at the first and the last point (u ∈ [0, 1]; a unit tangent times the
  /// polygon's length is the natural size). Empty: none. Open curves of degree ≥ 2 only.
  Point start_derivative, end_derivative;
  /// A closed (periodic) curve through the points; a last point equal to the first is dropped.
  bool closed = false;
};

/// The curve of the options' degree through every row of `points` (`m by dim`): `C(ū_k) = Q_k` with
/// ū = fit_parameters. Open: clamped on [0, 1] with averaged_knots; closed: periodic of period 1, the
/// breakpoints cyclic averages of p parameters (the domain is [b_0, b_0 + 1], b_0 within a parameter gap
/// of 0; a closed curve wraps any parameter, so C(ū_k) = Q_k still). Throws
/// InvalidInput for too few points (degree + 1, one more per derivative), coincident consecutive
/// points, a derivative of the wrong size, or a system that is singular.
Curve interpolate(const Points& points, const InterpolateOptions& options = {});

/// The curve of `degree` through the rows of `points` at the given parameters (one a row, finite and
/// increasing): `C(ū_k) = Q_k`, clamped on [ū_0, ū_{m−1}] with averaged_knots. Throws InvalidInput for a
/// count mismatch, parameters not finite or not increasing, or fewer than degree + 1 points.
Curve interpolate(const Points& points, std::span<const double> parameters, int degree);

/// What an approximation's tolerance measures.
enum class FitMeasure {
  points,    // max_k |C(ū_k) − Q_k|: each data point's distance to the curve is at most this
  polyline,  // sup_u |C(u) − L(u)|, L the data polyline on its parameters: bounds the Hausdorff distance
};

/// "points", "polyline"; InvalidInput naming them otherwise.
FitMeasure fit_measure_named(std::string_view name);

struct ApproximateOptions {
  int degree = 3;
  Parametrization parametrization = Parametrization::chord_length;
  /// > 0: that many control points (degree + 1 … #points; #points interpolates).
  Eigen::Index control_points = 0;
  /// > 0 (with control_points = 0): knots are inserted where the error is largest until it is below
  /// this. Neither: the interpolating curve.
  double tolerance = 0;
  FitMeasure measure = FitMeasure::points;
  /// Weight of each data point in the sum of squares (empty: all 1; else #points positive values).
  Eigen::VectorXd weights;
  /// The curve starts at the first point and ends at the last (The NURBS Book A9.7).
  bool fix_ends = true;
  /// Interpolation only (neither control_points nor tolerance): a closed curve, as InterpolateOptions.
  bool closed = false;
};

/// A fitted curve and how far it is from its data.
struct CurveFit {
  Curve curve;
  std::vector<double> parameters;  // ū_k of each data point
  /// max_k |C(ū_k) − Q_k|, evaluated: a bound on the distance of every data point to the curve.
  double point_distance = 0;
  /// Proven bound on sup_u |C(u) − L(u)| over [ū_0, ū_{m−1}], L the data polyline with vertex Q_k at ū_k:
  /// the maximum over the Bézier coefficients of C − L on each interval between consecutive parameters
  /// and knots (convex hull property), subdivided until it is within 1 % of the sampled maximum. Hence
  /// the curve and the polyline are within this (Hausdorff) distance of each other.
  double polyline_bound = 0;
};

/// Least-squares approximation of `points` (`m by dim`): with `control_points` on
/// approximation_knots, or with the fewest knots found by insertion (the median parameter of every
/// span whose error exceeds the tolerance) so that the measured distance is at most `tolerance`;
/// interpolation when nothing less reaches it, or when neither is given (then `closed` may be set).
/// Throws InvalidInput for both control_points and tolerance, too few points, a count outside
/// degree + 1 … m, bad weights, closed with either, and for the polyline measure a tolerance below
/// what interpolation reaches.
CurveFit approximate(const Points& points, const ApproximateOptions& options);

/// The distances of a curve to data on given parameters (as CurveFit reports them).
CurveFit measure_fit(const Curve& curve, const Points& points, std::vector<double> parameters);

/// Grid data for surfaces: point (i, j) — i along u, j along v — is row `i·count[1] + j` of `points`
/// (the order of Surface::P).
struct Grid {
  Points points;
  std::array<Eigen::Index, 2> count{};
};

/// Parameters of a grid in each direction: the parameters of every line of points along that direction,
/// averaged over the lines (lines whose points all coincide, such as a pole, are left out). Throws
/// InvalidInput for a grid that does not hold count[0]·count[1] points, or a direction in which every
/// line is degenerate.
std::array<std::vector<double>, 2> grid_parameters(const Grid& grid, Parametrization kind);

struct SurfaceFitOptions {
  std::array<int, 2> degree{3, 3};
  Parametrization parametrization = Parametrization::chord_length;
  /// approximate_surface: control points in u and v (each degree + 1 … count in that direction;
  /// the count itself interpolates in that direction).
  std::array<Eigen::Index, 2> control_points{0, 0};
};

/// The surface through every point of the grid: `S(ū_i, v̄_j) = Q_ij`, clamped on [0, 1]², averaged
/// knots; curves through the lines in u, then through the control lines in v (The NURBS Book A9.4).
Surface interpolate_surface(const Grid& grid, const SurfaceFitOptions& options = {});

/// Least-squares surface with `control_points` in each direction: the fit with fixed ends applied in u,
/// then in v (The NURBS Book §9.4.1); the corner points are interpolated.
Surface approximate_surface(const Grid& grid, const SurfaceFitOptions& options);

}  // namespace cifs::nurbs
