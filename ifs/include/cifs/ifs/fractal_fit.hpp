// SPDX-License-Identifier: MIT
// cifs — the fractal inverse problem for curves (Guérin & Tosan, "Fractal inverse problem: approximation
// formulation and differential methods", 2005): the BC-IFS of a uniform B-spline whose free coefficients
// and control points minimise the distance between its attractor and rough data. Differential method:
// Levenberg–Marquardt on the free coefficients with the control points projected out (variable
// projection, Kaufman's Jacobian), every derivative exact (products along the data's addresses, fixed
// points of the vertex operators differentiated through their linear systems).
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/fit.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

struct FractalFitOptions {
  int degree = 3;
  /// Control points of the model: degree + 1 … #points (open), degree + 1 … #points (closed, distinct
  /// ones). Each segment of the uniform knots must hold data (Schoenberg–Whitney), so fewer is safer.
  Eigen::Index control_points = 0;
  nurbs::Parametrization parametrization = nurbs::Parametrization::chord_length;
  /// A closed (periodic) model; a last data point equal to the first is dropped.
  bool closed = false;
  /// Free the vertex operators at the knots too (curve_bcifs' free_vertices): the roughness reaches the
  /// knot points. false: only the vertices subdivision creates move.
  bool free_vertices = true;
  /// Each data parameter is rounded to a multiple of 2^-depth of its segment, where the attractor point
  /// is exact (the start of the node at that depth): 1 … 52.
  int depth = 30;
  /// Levenberg–Marquardt iterations (each with an exact Jacobian): ≥ 0; 0 returns the smooth fit.
  int max_iterations = 100;
  /// A step is taken only when the fitted curve stays provably Hölder continuous of at least this
  /// exponent, in (0, 1]: every product of 8 levels shrinks nets by 2^(−8·min_holder) (δ, analysis.hpp).
  /// Without it the fit drifts to matrices that barely contract, whose attractor grows spikes between
  /// the data's parameters. The uniform B-spline's own bound (holder_bound at the start) is 1, 0.75,
  /// 0.61, 0.51, 0.43 for degrees 1 … 5; below min_holder, the start's bound is the floor instead.
  double min_holder = 0.25;
  /// Rounds of parameter correction: each inner data point moves to the closest attractor point among
  /// the dyadic parameters between its neighbours' (a grid 8× finer than the data), then the descent runs
  /// again; a round that does not lower the sum of squares ends them. ≥ 0.
  int reparametrizations = 3;
  /// Stop when an accepted step lowers the sum of squares by less than this fraction of it.
  double relative_decrease = 1e-10;
  /// Box-counting sample of the fitted attractor (points; 0: no dimension measured).
  std::size_t dimension_points = std::size_t{1} << 18;
  /// Refuse (before any work) a fit whose Jacobian, #points·dim·#free doubles, would exceed this.
  std::size_t max_bytes = std::size_t{1} << 30;
};

/// The pointwise Hölder exponent at the points of one vertex class: −log2 |λ|/k, λ the largest
/// eigenvalue other than 1 of the class's k-step cycle product (each step halves the parameter), capped
/// at 1 (the attractor is Lipschitz there).
struct VertexHolder {
  std::string cell;
  double exponent = 0;
};

struct FractalFit {
  /// The fitted BC-IFS (free coefficients set) and its control nets, one per segment: a BC-IFS file's
  /// content (io::to_json(system, nets)).
  Bcifs system;
  std::vector<Points> nets;
  /// The control points (`n by dim`; distinct ones when closed) the nets are made of.
  Points control_points;
  /// The least-squares uniform B-spline on the same knots and parameters: the starting point.
  nurbs::Curve smooth;
  /// Data parameters ū_k in [0, 1]: nurbs::fit_parameters', then as the corrections moved them.
  std::vector<double> parameters;
  /// Every free coefficient and its fitted value, in the order of the admissible space.
  std::vector<std::pair<std::string, double>> coefficients;
  /// |A(ū_k) − Q_k| over the data, A the attractor at the dyadic parameter of ū_k: root mean square,
  /// largest. The same for the smooth fit.
  double rms = 0, max_distance = 0;
  double smooth_rms = 0, smooth_max_distance = 0;
  int iterations = 0;          // Levenberg–Marquardt iterations, all rounds
  int reparametrizations = 0;  // parameter corrections kept
  Contraction contraction;
  /// Proven lower bound on the Hölder exponent of the fitted curve, at every point: −log2(δ_8)/8, δ_8 the
  /// largest δ of the products along the paths of 8 levels.
  double holder_bound = 0;
  /// Per vertex class reached: its points' exponent, an upper bound of the curve's.
  std::vector<VertexHolder> holder;
  /// Box-counting dimension of the fitted attractor's points at the deepest depth within
  /// FractalFitOptions::dimension_points, and its uncertainty (the local slopes' drift; an estimate:
  /// no piece bound is used). NaN when not measured, `dimension_note` then says why.
  double dimension = 0, dimension_uncertainty = 0;
  std::string dimension_note;
};

/// Fits the fractal curve of `options` to `points` (`m by dim`). Throws InvalidInput for fewer than
/// 2 points, coordinates that are not finite, coincident consecutive points (chord parametrisations),
/// a control point count outside its range, a segment without data, options out of range, and when
/// the smooth start is already singular.
FractalFit fit_fractal(const Points& points, const FractalFitOptions& options);

/// Points of a curve system's attractor and their derivatives in the free coefficients: the differential
/// fit_fractal descends with. `system` = curve_bcifs(shape, …) (non-rational), `space` its admissible
/// space, `c` the free coefficients' values; `parameters` in the shape's domain (closed shapes wrap), each
/// rounded to 2^-depth of its segment. `derivatives[j]` is ∂points/∂c_j (#parameters by dim).
struct CurvePointDerivatives {
  Points points;
  std::vector<Points> derivatives;
};

CurvePointDerivatives curve_point_derivatives(const nurbs::Curve& shape, const Bcifs& system,
                                              const AdmissibleSpace& space, const Eigen::VectorXd& c,
                                              std::span<const double> parameters, int depth);

}  // namespace cifs::ifs
