// SPDX-License-Identifier: MIT
// The exact rational p / d that the subdivision tests write their masks and eigenvalues with, and exact
// ranks of local matrices (one definition for the files that share a unity batch, tests/CMakeLists.txt).
#pragma once

#include <utility>
#include <vector>

#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/subdivision/scheme.hpp"

namespace cifs_test {

inline cifs::subdivision::Rational q(long long p, long long d = 1) {
  return cifs::subdivision::Rational(p) / cifs::subdivision::Rational(d);
}

using cifs::subdivision::Rational;
using cifs::subdivision::RationalMatrix;

/// The rank of an exact matrix (Gaussian elimination in rationals): a proof of an eigenvalue's
/// geometric multiplicity, N − rank(S − λI), with no round-off.
inline int exact_rank(std::vector<std::vector<Rational>> a) {
  int rank = 0;
  const std::size_t rows = a.size(), cols = rows == 0 ? 0 : a[0].size();
  for (std::size_t col = 0; col < cols && static_cast<std::size_t>(rank) < rows; ++col) {
    std::size_t pivot = static_cast<std::size_t>(rank);
    while (pivot < rows && a[pivot][col] == 0) ++pivot;
    if (pivot == rows) continue;
    std::swap(a[pivot], a[static_cast<std::size_t>(rank)]);
    const std::vector<Rational>& p = a[static_cast<std::size_t>(rank)];
    for (std::size_t r = 0; r < rows; ++r) {
      if (r == static_cast<std::size_t>(rank) || a[r][col] == 0) continue;
      const Rational f = a[r][col] / p[col];
      for (std::size_t c = col; c < cols; ++c) a[r][c] -= f * p[c];
    }
    ++rank;
  }
  return rank;
}

/// (S − λI)^power of an exact local matrix, as rows.
inline std::vector<std::vector<Rational>> shifted_power(const RationalMatrix& S, const Rational& lambda,
                                                        int power) {
  const auto N = static_cast<std::size_t>(S.rows);
  std::vector<std::vector<Rational>> A(N, std::vector<Rational>(N)), P(N, std::vector<Rational>(N));
  for (std::size_t i = 0; i < N; ++i) {
    P[i][i] = 1;
    for (std::size_t j = 0; j < N; ++j)
      A[i][j] = S(static_cast<int>(i), static_cast<int>(j)) - (i == j ? lambda : Rational(0));
  }
  for (int k = 0; k < power; ++k) {
    std::vector<std::vector<Rational>> Q(N, std::vector<Rational>(N));
    for (std::size_t i = 0; i < N; ++i)
      for (std::size_t m = 0; m < N; ++m)
        if (P[i][m] != 0)
          for (std::size_t j = 0; j < N; ++j) Q[i][j] += P[i][m] * A[m][j];
    P = std::move(Q);
  }
  return P;
}

}  // namespace cifs_test
