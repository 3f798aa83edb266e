// SPDX-License-Identifier: MIT
// cifs — a scheme as an iterated function system: the left/right matrices of its mask, the
// one-state automaton they form, and limit curves of closed polygons as its attractor.
//
// For the mask a_0 … a_N the basic limit function is supported on [0, N]: the curve over one
// unit interval depends on N consecutive control points (a window). Halving that interval, the
// left (ε = 0) and right (ε = 1) halves depend on the N refined points
//   S_ε · W,  S_ε[s][r] = a_{s − 2r + N − 1 + ε}  (N by N, rows summing to 1),
// the refined window of coarse window k = (P_k … P_{k+N−1}) starting at the refined index
// 2k + N − 1 + ε of q_i = Σ_j a_{i−2j} P_j. Chaikin: S_0 = [[¾,¼,0],[¼,¾,0],[0,¾,¼]].
#pragma once

#include <Eigen/Core>
#include <array>
#include <span>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/junction.hpp"
#include "cifs/subdivision/scheme.hpp"
#include "cifs/types.hpp"

namespace cifs::subdivision {

/// S_ε of a mask given as doubles (N + 1 ≥ 2 coefficients), N by N.
Eigen::MatrixXd ifs_matrix(std::span<const double> mask, int epsilon);

/// {S_0, S_1} of the scheme.
std::array<Eigen::MatrixXd, 2> ifs_matrices(const Scheme& scheme);

/// {S_0, S_1} of the mask padded with zeros to `window` + 1 coefficients (⌊(window − N)/2⌋ in
/// front, the rest behind; window ≥ N): the same limit curve on wider windows, so that schemes of
/// different supports have cells of one size and can share them (docs/junctions.md). An odd
/// difference shifts the pieces by half an interval (the primal/dual offset of a quadratic in the
/// windows of a cubic).
std::array<Eigen::MatrixXd, 2> padded_ifs_matrices(const Scheme& scheme, int window);

/// The BC-IFS of an open curve of the scheme on windows of `window` points (0: N):
/// ifs::uniform_curve_bcifs of padded_ifs_matrices.
ifs::Bcifs scheme_bcifs(const Scheme& scheme, int window = 0, const ifs::UniformCurveOptions& options = {});

/// One state of size N with transitions "0" (S_0) and "1" (S_1) to itself, in that order (left
/// half first), and `segments` initial entries on it (segment k = k): the automaton whose
/// attractor, under the nets of closed_windows, is the limit curve of a closed polygon.
automata::Automaton scheme_automaton(const Scheme& scheme, int segments = 1);

/// The n windows of a closed polygon of n ≥ 1 points: net k = rows k … k + N − 1 (mod n), the
/// control net of the curve piece k.
std::vector<Points> closed_windows(const Scheme& scheme, const Points& P);

/// Points of the limit curve of a closed polygon through the IFS (ifs::attractor_points): piece k
/// (window k) contributes 2^depth points, at its parameters j/2^depth, pieces in order, the
/// curve closed (n·2^depth points). Piece k runs from the limit point of address 0^∞ of window k
/// to that of window k + 1.
Points limit_points(const Scheme& scheme, const Points& P, int depth);

}  // namespace cifs::subdivision
