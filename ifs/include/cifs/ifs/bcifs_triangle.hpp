// SPDX-License-Identifier: MIT
// cifs — the BC-IFS of a triangular patch split at its edges' midpoints into four (Loop's box-spline
// patch, any patch subdivided that way): face cells named by which of their sides lie on the patch's
// sides, edge cells on those sides (kept) and inside (free), so that perturbing it keeps the patch's
// boundary curves and makes the inside fractal (docs/bcifs.md, "Triangular patches").
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "cifs/ifs/bcifs.hpp"

namespace cifs::ifs {

/// A triangular patch whose net (`size` rows) goes one level down into four nets of the same layout:
/// children[0], [1], [2] the triangles at corners 0, 1, 2 ((s, t) → (2s, 2t), (2s − 1, 2t),
/// (2s, 2t − 1), corner 0 at (0, 0), 1 at (1, 0), 2 at (0, 1)) and children[3] the middle one turned
/// by a half turn ((s, t) → (1 − 2s, 1 − 2t)), each `size by size`, rows summing to 1.
/// sides[k]: the rows of the net that side k (from corner k to corner k + 1) depends on, as that side
/// reads them — side k's row i is side 0's row i turned by k thirds of a turn. reverse: the same side
/// read from the triangle across it (from corner k + 1 to corner k) is its row reverse[i] at i.
struct TrianglePatch {
  std::array<Eigen::MatrixXd, 4> children;
  std::array<std::vector<int>, 3> sides;
  std::vector<int> reverse;
};

/// Cells and constraints of the patch (docs/bcifs.md):
/// - face cells "T<sides>" (dimension 2, the patch's net), named by which of their sides lie on the
///   patch's sides: "T012" the patch (the one initial entry, segment 0), "T02", "T01", "T12" its corner
///   children, "T0" … and "T" inside; transitions C0, C1, C2, M (children[0 … 3]), all free;
/// - edge cells (dimension 1, sides[k].size() rows): "Eb" on the patch's sides, "Ei" inside, each with
///   transitions G and D (the side's first and second half: children[0] and [1] on side 0's rows); Eb's
///   stay fixed, Ei's are free;
/// - boundaries of every face cell: "s<k>" (sides[k]) and "s<k>r" (side k reversed), onto Eb or Ei;
/// - constraints of every face cell F: incidence — side k's halves are children k and k + 1's sides k,
///   in both readings (`s<k>(C_k)·C_k = G·s<k>(F)`, `s<k>(C_k+1)·C_k+1 = D·s<k>(F)`,
///   `s<k>r(C_k+1)·C_k+1 = G·s<k>r(F)`, `s<k>r(C_k)·C_k = D·s<k>r(F)`), so a side subdivides the same way
///   read from either triangle; adjacency — the middle child's side k is child k + 2's side k reversed
///   (`s<k>(M)·M = s<k>r(C_k+2)·C_k+2`).
/// Faces sharing an edge then share its net at every level, and a vertex's faces are joined through
/// their edges: the attractor is watertight; the patch's sides are the unperturbed patch's curves.
/// Throws InvalidInput for nets of unequal sizes, rows outside the net, sides of unequal lengths or
/// repeated rows, a reverse that is not an involution of a side's rows, children that mix rows outside a
/// side into it, and when the given matrices do not satisfy the constraints to 1e-12 (the sides or
/// reverse do not describe the patch).
Bcifs triangle_bcifs(const TrianglePatch& patch);

}  // namespace cifs::ifs
