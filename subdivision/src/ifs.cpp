// SPDX-License-Identifier: MIT
#include "cifs/subdivision/ifs.hpp"

#include <algorithm>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"

namespace cifs::subdivision {

Eigen::MatrixXd ifs_matrix(std::span<const double> mask, int epsilon) {
  const int N = static_cast<int>(mask.size()) - 1;
  if (N < 1) throw InvalidInput("a subdivision mask needs at least 2 coefficients");
  if (epsilon != 0 && epsilon != 1)
    throw InvalidInput("the IFS matrix index epsilon " + std::to_string(epsilon) + " is neither 0 nor 1");
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(N, N);
  for (int s = 0; s < N; ++s)
    for (int r = 0; r < N; ++r) {
      const int k = s - 2 * r + N - 1 + epsilon;
      if (k >= 0 && k <= N) S(s, r) = mask[static_cast<std::size_t>(k)];
    }
  return S;
}

std::array<Eigen::MatrixXd, 2> ifs_matrices(const Scheme& scheme) {
  return {ifs_matrix(scheme.weights, 0), ifs_matrix(scheme.weights, 1)};
}

std::array<Eigen::MatrixXd, 2> padded_ifs_matrices(const Scheme& scheme, int window) {
  const int N = mask_degree(scheme);
  if (window < N)
    throw InvalidInput("a window of " + std::to_string(window) + " points is narrower than the " +
                       std::to_string(N) + " of the scheme");
  if (window >= kMaxMaskSize)
    throw InvalidInput("a window of " + std::to_string(window) + " points is wider than " +
                       std::to_string(kMaxMaskSize - 1));
  std::vector<double> mask(static_cast<std::size_t>(window) + 1, 0.0);
  std::copy(scheme.weights.begin(), scheme.weights.end(), mask.begin() + (window - N) / 2);
  return {ifs_matrix(mask, 0), ifs_matrix(mask, 1)};
}

ifs::Bcifs scheme_bcifs(const Scheme& scheme, int window, const ifs::UniformCurveOptions& options) {
  const auto S = padded_ifs_matrices(scheme, window == 0 ? mask_degree(scheme) : window);
  return ifs::uniform_curve_bcifs(S[0], S[1], options);
}

automata::Automaton scheme_automaton(const Scheme& scheme, int segments) {
  if (segments < 0) throw InvalidInput("the number of segments " + std::to_string(segments) + " is negative");
  automata::Automaton a;
  automata::State state;
  state.size = mask_degree(scheme);
  state.recurrent = true;
  state.name = scheme.name;
  const auto s = add_vertex(state, a.graph);
  const auto S = ifs_matrices(scheme);
  add_edge(s, s, automata::Transition{"0", S[0]}, a.graph);
  add_edge(s, s, automata::Transition{"1", S[1]}, a.graph);
  for (int k = 0; k < segments; ++k) a.initial.push_back({.segment = k, .state = s});
  return a;
}

std::vector<Points> closed_windows(const Scheme& scheme, const Points& P) {
  const Eigen::Index n = P.rows(), N = mask_degree(scheme);
  if (n < 1) throw InvalidInput("the closed polygon has no point");
  std::vector<Points> nets;
  nets.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) {
    Points W(N, P.cols());
    for (Eigen::Index r = 0; r < N; ++r) W.row(r) = P.row((k + r) % n);
    nets.push_back(std::move(W));
  }
  return nets;
}

Points limit_points(const Scheme& scheme, const Points& P, int depth) {
  const auto automaton = scheme_automaton(scheme, static_cast<int>(P.rows()));
  const auto nets = closed_windows(scheme, P);
  ifs::PointsOptions options;
  options.closed = true;
  return ifs::attractor_points(automaton, nets, depth, options);
}

}  // namespace cifs::subdivision
