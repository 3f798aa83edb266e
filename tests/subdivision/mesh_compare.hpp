// SPDX-License-Identifier: MIT
// Comparing two refined meshes whose vertices may be numbered differently: vertices are matched by
// position (a bijection within a relative tolerance), then faces are compared through the matching.
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "cifs/mesh.hpp"

namespace cifs_test {

/// For every row of A, the row of B at the same place (|a − b| ≤ tol · scale); a bijection. B's rows are
/// sorted by their first coordinate: every row within tolerance lies in a window of that order (the
/// nearest one too, when it is within tolerance), so a match costs a binary search, not a scan of B; a
/// row with nothing in its window is measured against all of B for the message.
inline std::vector<int> match_vertices(const cifs::Points& A, const cifs::Points& B, double tol) {
  REQUIRE(A.rows() == B.rows());
  REQUIRE(A.cols() == B.cols());
  const double scale = std::max(A.cwiseAbs().maxCoeff(), 1e-300);
  const double reach = tol * scale;
  std::vector<int> by_x(static_cast<std::size_t>(B.rows()));
  for (std::size_t j = 0; j < by_x.size(); ++j) by_x[j] = static_cast<int>(j);
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) { return B(a, 0) < B(b, 0); });
  const auto distance = [&](Eigen::Index i, Eigen::Index j) {
    double d = 0;
    for (Eigen::Index c = 0; c < A.cols(); ++c) d = std::max(d, std::abs(A(i, c) - B(j, c)));
    return d;
  };
  std::vector<int> map(static_cast<std::size_t>(A.rows()), -1);
  std::vector<char> used(static_cast<std::size_t>(B.rows()), 0);
  double worst = 0;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    Eigen::Index at = -1;
    const auto first = std::lower_bound(by_x.begin(), by_x.end(), A(i, 0) - reach,
                                        [&](int j, double x) { return B(j, 0) < x; });
    for (auto j = first; j != by_x.end() && B(*j, 0) <= A(i, 0) + reach; ++j)
      if (const double d = distance(i, *j); d < best) best = d, at = *j;
    if (!(best <= reach))  // nothing within tolerance: the nearest row anywhere, for the message
      for (Eigen::Index j = 0; j < B.rows(); ++j)
        if (const double d = distance(i, j); d < best) best = d, at = j;
    if (at < 0) FAIL("vertex " << i << " has a coordinate that is not a number");
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
