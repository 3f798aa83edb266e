// SPDX-License-Identifier: MIT
// Comparing two refined meshes whose vertices may be numbered differently: vertices are matched by
// position (a bijection within a relative tolerance), then faces are compared through the matching.
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <vector>

#include "cifs/mesh.hpp"

namespace cifs_test {

/// For every row of A, the row of B at the same place (|a − b| ≤ tol · scale); a bijection.
inline std::vector<int> match_vertices(const cifs::Points& A, const cifs::Points& B, double tol) {
  REQUIRE(A.rows() == B.rows());
  const double scale = std::max(A.cwiseAbs().maxCoeff(), 1e-300);
  std::vector<int> map(static_cast<std::size_t>(A.rows()), -1);
  std::vector<char> used(static_cast<std::size_t>(B.rows()), 0);
  double worst = 0;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    Eigen::Index at = -1;
    for (Eigen::Index j = 0; j < B.rows(); ++j) {
      const double d = (A.row(i) - B.row(j)).cwiseAbs().maxCoeff();
      if (d < best) best = d, at = j;
    }
    worst = std::max(worst, best);
    map[static_cast<std::size_t>(i)] = static_cast<int>(at);
    used[static_cast<std::size_t>(at)] += 1;
  }
  INFO("largest distance to the nearest vertex, relative: " << worst / scale);
  CHECK(worst <= tol * scale);
  CHECK(std::all_of(used.begin(), used.end(), [](char u) { return u == 1; }));
  return map;
}

/// Faces as cyclic vertex lists, each rotated to start at its smallest index, then sorted.
inline std::vector<std::vector<int>> canonical_faces(std::span<const int> offsets,
                                                     std::span<const int> corners,
                                                     const std::vector<int>* map = nullptr) {
  std::vector<std::vector<int>> faces;
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
    std::vector<int> face;
    for (int k = offsets[f]; k < offsets[f + 1]; ++k) {
      const int v = corners[static_cast<std::size_t>(k)];
      face.push_back(map ? (*map)[static_cast<std::size_t>(v)] : v);
    }
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
    faces.push_back(std::move(face));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

/// Same vertices (up to numbering) and the same faces with the same orientation.
inline void check_same_mesh(const cifs::Mesh& ours, const cifs::Mesh& theirs, double tol = 1e-12) {
  REQUIRE(cifs::face_count(ours) == cifs::face_count(theirs));
  const std::vector<int> map = match_vertices(ours.vertices, theirs.vertices, tol);
  CHECK(canonical_faces(ours.face_offsets, ours.face_vertices, &map) ==
        canonical_faces(theirs.face_offsets, theirs.face_vertices));
}

}  // namespace cifs_test
