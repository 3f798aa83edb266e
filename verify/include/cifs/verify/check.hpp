// SPDX-License-Identifier: MIT
// cifs — the daily check: the CIFS attractor of a NURBS curve or surface against knot insertion
// and Cox–de Boor evaluation through the NURBS core.
#pragma once

#include <array>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::verify {

struct CheckOptions {
  int depth = 8;
  double tolerance = 1e-12;  // relative, against the largest control point (and weight)
};

/// Largest and relative deviation of one comparison.
struct Deviation {
  double max_abs = 0;
  double max_rel = 0;
};

struct SegmentReport {
  int segment = 0;
  double start = 0, end = 0;
  Deviation nets;    // leaf control nets vs knot insertion of every dyadic knot
  Deviation points;  // attractor points vs Cox–de Boor at the dyadic parameters
};

struct CheckReport {
  int depth = 0;
  double tolerance = 0;
  std::vector<SegmentReport> segments;
  Deviation nets, points;  // over all segments
  bool pass = false;
};

/// Runs both comparisons for every segment. Each segment is checked in its own coordinates (knots
/// relative to the segment start, built from its window), so that the reference is as well
/// conditioned as the automaton: with absolute knots, interval ratios of 1e6 would cost the
/// reference itself six digits. The references are extended beyond the window so that knot
/// insertion splits every inter-knot of the window, as knot doubling does.
/// Throws InvalidInput for a depth outside [0, 30] or work beyond the memory limit.
CheckReport check_curve(const nurbs::Curve& curve, const CheckOptions& options);

struct PatchReport {
  std::array<int, 2> patch{};      // (u segment, v segment)
  std::array<double, 2> u{}, v{};  // its parameter intervals
  Deviation nets;                  // leaf control nets vs knot insertion of every dyadic knot in u and v
  Deviation points;                // mesh vertices it owns vs surface evaluation at the dyadic parameters
};

struct SurfaceCheckReport {
  int depth = 0;
  double tolerance = 0;
  std::vector<PatchReport> patches;  // u-major
  Deviation nets, points;            // over all patches
  bool pass = false;
};

/// check_curve for surfaces, on the tensor-product automaton: every patch in its own coordinates
/// (both directions' windows relative to the patch corner). (a) Every leaf net at `depth` against
/// the local surface refined by every dyadic knot of both windows (nurbs::refine in u, then in v);
/// (b) every vertex of ifs::surface_mesh against nurbs::evaluate_grid of the patch at the dyadic
/// parameters (each vertex checked in the patch that computes it). Deviations are relative to the
/// largest Cartesian control coordinate (and the largest weight, for weights).
/// Throws InvalidInput for a depth outside [0, 30] or references beyond the memory limit.
SurfaceCheckReport check_surface(const nurbs::Surface& surface, const CheckOptions& options);

}  // namespace cifs::verify
