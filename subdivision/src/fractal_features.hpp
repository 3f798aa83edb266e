// SPDX-License-Identifier: MIT
// cifs — the displacement a fractal feature curve adds to the faces beside it (limit.hpp,
// FractalFeatures): internal to the attractor meshes of limit_surface.cpp.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <map>

#include "cifs/subdivision/limit.hpp"

namespace cifs::subdivision::detail {

/// Per fractal feature edge, Δ = the perturbed curve minus the smooth one at the 2^depth + 1 nodes
/// of the edge from its lower vertex; added to a face's node by the face's corners and the node's
/// place (every side of the face that is such an edge contributes φ(distance)·Δ(along)).
class FeatureDisplacement {
 public:
  FeatureDisplacement(const FractalFeatures& features, int depth);
  bool empty() const noexcept { return delta_.empty(); }
  /// Whether a face with these corners (quads: 4; triangles: the first 3) has a fractal side.
  bool touches(const std::array<int, 4>& corners, bool quad) const;
  /// Adds the displacement at node (I, J) of a quad face's (2^depth + 1)² block (I along s, corners
  /// at (0, 0), (side, 0), (side, side), (0, side)) to `p`.
  void add_quad(const std::array<int, 4>& corners, int I, int J, Eigen::RowVectorXd& p) const;
  /// Adds the displacement at node (i, j), i + j ≤ side, of a triangle (corners at (0, 0), (side, 0),
  /// (0, side)) to `p`.
  void add_triangle(const std::array<int, 4>& corners, int i, int j, Eigen::RowVectorXd& p) const;

 private:
  /// Δ at `at` cells from `from` along the edge from `from` to `to`, times `weight`; nothing when the
  /// edge is not fractal.
  void add(int from, int to, int at, double weight, Eigen::RowVectorXd& p) const;
  int side_;
  std::map<std::array<int, 2>, Points> delta_;
};

}  // namespace cifs::subdivision::detail
