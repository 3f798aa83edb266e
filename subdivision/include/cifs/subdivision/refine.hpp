// SPDX-License-Identifier: MIT
// cifs — direct polygon refinement by a scheme's mask, for closed and open polygons.
//
// Polygons are `#P by dim` rows (any dim ≥ 1; homogeneous rows refine unchanged).
//
// Closed polygons (n ≥ 1 points, indices mod n): one step gives 2n points,
//   out[m] = Σ_j a_{m + h − 2j} P_{j mod n},  h = ⌈N/2⌉,
// so that for symmetric masks out[2i] sits at P_i (primal schemes: interpolating ones keep
// out[2i] = P_i) or a quarter of an edge after it (dual schemes: Chaikin gives
// out[2i] = ¾P_i + ¼P_{i+1}, out[2i+1] = ¼P_i + ¾P_{i+1} as in seed 001).
//
// Open polygons (n ≥ 2 points): the end rules keep the two end points (docs/schemes.md).
// - Ends::reflect (symmetric masks): the polygon is extended beyond each end point E by point
//   reflection through E (P_{−j} = 2P_0 − P_j, P_{n−1+j} = 2P_{n−1} − P_{n−1−j}, continued
//   periodically with the drift 2(P_{n−1} − P_0) for short polygons), refined as if it were
//   infinite, and the new points that lie strictly between the end points are kept, plus the end
//   points themselves. Every step is the same rule, so refine(refine(P)) = refine(P, 2).
//   Primal masks: 2n − 1 points; the new point at an end point equals it (by symmetry), and the
//   result is exactly the limit of the reflected polygon, so the curve is point-symmetric about
//   each end: its second derivative vanishes there and, for B-splines of degree ≤ 3, it leaves
//   along the end edge. Dual masks: 2n points, the end points re-inserted at every step (a
//   boundary rule: the curve ends at the end point). For Chaikin and symmetric corner cutting the
//   reflected points are never used and the rule is the classic one: every edge is cut, the end
//   points stay, the curve leaves along the end edge.
// - Ends::keep (any mask): only the new points whose whole stencil lies in the polygon, plus the
//   end points. For corner cutting with b ≠ 1 − a this is again "cut every edge, keep the ends".
// - Ends::automatic: reflect for symmetric masks, keep otherwise.
#pragma once

#include <cstddef>

#include "cifs/subdivision/scheme.hpp"
#include "cifs/types.hpp"

namespace cifs::subdivision {

enum class Ends { automatic, reflect, keep };

struct RefineOptions {
  Ends ends = Ends::automatic;
  /// Refuse (before any work) a result with more points than this.
  std::size_t max_points = std::size_t{1} << 27;
};

/// h = ⌈N/2⌉, the alignment of closed refinement above.
inline int closed_offset(const Scheme& scheme) {
  return (mask_degree(scheme) + 1) / 2;
}

/// True when a_k = a_{N−k} for every k (exactly).
bool is_symmetric(const Scheme& scheme);

/// One step of closed refinement into `out` (resized to 2n by dim). The kernel the benchmark
/// times: no allocation when `out` already has the right shape. `P` must have n ≥ 1 rows and must
/// not alias `out`.
void refine_closed(const Scheme& scheme, const Points& P, Points& out);

/// One step (closed or open). Throws InvalidInput for an empty polygon, an open polygon of fewer
/// than 2 points, Ends::reflect with an asymmetric mask, or a result beyond `max_points`.
Points refine(const Scheme& scheme, const Points& P, bool closed, const RefineOptions& options = {});

/// `steps` ≥ 0 steps (each one as above).
Points refine(const Scheme& scheme, const Points& P, bool closed, int steps,
              const RefineOptions& options = {});

}  // namespace cifs::subdivision
