// SPDX-License-Identifier: MIT
// cifs — surfaces constructed from curves (The NURBS Book ch. 8 and 10): compatible curves, ruled
// surfaces, extrusions, surfaces of revolution, lofts (skinning) and sweeps.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/fit.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::nurbs {

/// The curves made compatible, each the same point set on the same parameters up to an affine map:
/// clamped (closed curves opened at their seam), rational when any is (weights 1 added), raised to the
/// largest degree, mapped onto the first curve's domain (curves already on it are not touched) and
/// refined to the union of the knot vectors (each value with its largest multiplicity). Then they share
/// degree, knots and number of control points. Throws InvalidInput for no curve or a dimension mismatch.
std::vector<Curve> make_compatible(std::span<const Curve> curves);

/// The ruled surface between a and b: linear in v on [0, 1], `S(u, 0) = a(u)` and `S(u, 1) = b(u')`
/// with u' the parameter of b mapped affinely onto a's domain (make_compatible), u on a's domain.
Surface ruled(const Curve& a, const Curve& b);

/// The translational surface `S(u, v) = C(u) + v·direction`, v ∈ [0, 1]; exact (rational curves too: each
/// control point moved with its weight). Throws InvalidInput for a direction that is not finite, of the
/// wrong size, zero, or parallel to a straight curve (a surface without area: every control point within
/// 1e-14 of the curve's size of the line along the direction), and for a curve that is one point.
Surface extrude(const Curve& curve, const Point& direction);

/// The surface of revolution of a 3-D profile about the axis through `axis_point` along `axis_direction`,
/// turned by `angle` ∈ (0, 2π] (counter-clockwise about the direction): u is the profile's parameter, v ∈ [0,
/// 1] goes round in ⌈angle/(π/2)⌉ equal rational quadratic arcs (The NURBS Book A8.1, weight cos(φ/2) in the
/// middle of an arc of φ), exact: every point is at its profile point's distance from the axis, at the
/// angle `kφ + φ/2 + 2·atan(tan(φ/4)·(2s − 1))` on arc k at its local parameter s ∈ [0, 1]. A full turn
/// closes exactly (the last column of the net is the first). Throws InvalidInput for a profile that is not
/// 3-D or lies on the axis, an axis that is zero or not finite, and an angle outside (0, 2π].
Surface revolve(const Curve& profile, const Eigen::Vector3d& axis_point,
                const Eigen::Vector3d& axis_direction, double angle);

struct LoftOptions {
  /// Degree across the curves (v): at most the number of curves − 1.
  int degree_v = 3;
  /// How the curves get their v-parameters: those of each column of the compatible control points (the
  /// i-th point of every curve), averaged over the columns; a column that is one point (a pole) is left
  /// out (The NURBS Book eq. 10.8 for chord length).
  Parametrization parametrization = Parametrization::chord_length;
};

/// The surface through the curves (skinning, The NURBS Book §10.3): made compatible, then each column of
/// control points (homogeneous for rational curves) interpolated through the v-parameters (averaged_knots,
/// clamped on [0, 1]). The iso-curve at the k-th curve's v-parameter is that curve (make_compatible's
/// parameters). Throws InvalidInput for fewer than 2 curves, degree_v outside 1 … curves − 1, two
/// consecutive curves that coincide (equal compatible control points), and an interpolated weight that
/// is not positive (rational curves whose weights differ too much).
Surface loft(std::span<const Curve> curves, const LoftOptions& options = {});

/// The v-parameters that loft gives the curves (one per curve, from 0 to 1).
std::vector<double> loft_parameters(std::span<const Curve> curves, Parametrization parametrization);

struct SweepOptions {
  /// 0: the translational sweep `S(u, v) = C(u) + T(v) − T(v₀)` (exact: the tensor product of the two nets).
  /// ≥ 2: the profile carried by the trajectory's rotation-minimizing frames, skinned through that many
  /// instances at equally spaced trajectory parameters (an approximation; see Sweep::deviation).
  int instances = 0;
  /// Degree in v of the skinned sweep (at most instances − 1).
  int degree_v = 3;
};

/// A swept surface and how far it may be from the exact sweep.
struct Sweep {
  Surface surface;
  /// Translational: 0 (exact). Skinned: the largest `|S(u, v) − S*(u, v)|` over a sample (8 trajectory
  /// parameters between consecutive instances, 8 profile parameters per profile span), S* the profile
  /// carried by the frames at v (a sampled figure, not a bound).
  double deviation = 0;
};

/// The profile (positioned at the start of the trajectory) swept along the trajectory, v on the
/// trajectory's domain. Frames: rotation-minimizing (the double reflection method of Wang, Jüttler, Zheng
/// and Liu 2008, 64 steps between instances), so the swept profile does not twist; the frame's choice at
/// the start does not matter. Throws InvalidInput for a dimension mismatch, instances of 1 or negative,
/// frames of a trajectory that is not 3-D or whose tangent vanishes.
Sweep sweep(const Curve& profile, const Curve& trajectory, const SweepOptions& options = {});

/// The rotation-minimizing frames of a 3-D curve at `count` equally spaced parameters of its domain
/// (double reflection with `steps` steps between consecutive parameters): row k holds the unit tangent,
/// then the unit reference vector r (normal to it), 6 values. The first r is the Frenet normal where the
/// curvature is not zero, else a unit vector normal to the tangent.
Points rotation_minimizing_frames(const Curve& curve, int count, int steps = 64);

}  // namespace cifs::nurbs
