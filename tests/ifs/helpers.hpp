// SPDX-License-Identifier: MIT
// Test helpers of the ifs tests: hand-made automata (Boost, directly) and an independent
// Cox–de Boor reference in long double.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/nurbs/doubling.hpp"
#include "cifs/types.hpp"

namespace ifs_test {

using cifs::Points;
using cifs::automata::Automaton;
using cifs::automata::StateId;
using cifs::automata::Transition;

inline StateId add_state(Automaton& a, int size, const std::string& name = {}) {
  const StateId s = add_vertex(a.graph);
  a.graph[s].size = size;
  a.graph[s].name = name;
  return s;
}

inline void add_transition(Automaton& a, StateId from, StateId to, const Eigen::MatrixXd& M,
                           const std::string& label) {
  add_edge(from, to, Transition{label, M}, a.graph);
}

inline void add_initial(Automaton& a, StateId s, int segment = 0) {
  cifs::automata::Initial init;
  init.segment = segment;
  init.state = s;
  a.initial.push_back(init);
}

/// Uniform B-spline of degree d: one state of d + 1 points, G and D from the all-ones window;
/// `segments` initial entries share it.
inline Automaton uniform_automaton(int d, int segments = 1) {
  Automaton a;
  const StateId s = add_state(a, d + 1, "uniform");
  const cifs::nurbs::Window ones(static_cast<std::size_t>(2 * d - 1), 1.0);
  add_transition(a, s, s, cifs::nurbs::subdivision_matrix(ones, d, cifs::nurbs::Half::G), "G");
  add_transition(a, s, s, cifs::nurbs::subdivision_matrix(ones, d, cifs::nurbs::Half::D), "D");
  for (int k = 0; k < segments; ++k) add_initial(a, s, k);
  return a;
}

/// The 4-state quadratic automaton of a window (u1, u2, u3): S0 = (u1,u2,u3) → G (u1,u2,u2),
/// D (u2,u2,u3); (u1,u2,u2) → G itself, D uniform; (u2,u2,u3) → G uniform, D itself; uniform → itself.
inline Automaton quadratic_automaton(double u1, double u2, double u3) {
  using cifs::nurbs::Half;
  using cifs::nurbs::subdivision_matrix;
  Automaton a;
  const cifs::nurbs::Window w0{u1, u2, u3}, w1{u1, u2, u2}, w2{u2, u2, u3}, w3{1, 1, 1};
  const StateId s0 = add_state(a, 3, "S0"), s1 = add_state(a, 3, "G"), s2 = add_state(a, 3, "D"),
                s3 = add_state(a, 3, "uniform");
  add_transition(a, s0, s1, subdivision_matrix(w0, 2, Half::G), "G");
  add_transition(a, s0, s2, subdivision_matrix(w0, 2, Half::D), "D");
  add_transition(a, s1, s1, subdivision_matrix(w1, 2, Half::G), "G");
  add_transition(a, s1, s3, subdivision_matrix(w1, 2, Half::D), "D");
  add_transition(a, s2, s3, subdivision_matrix(w2, 2, Half::G), "G");
  add_transition(a, s2, s2, subdivision_matrix(w2, 2, Half::D), "D");
  add_transition(a, s3, s3, subdivision_matrix(w3, 2, Half::G), "G");
  add_transition(a, s3, s3, subdivision_matrix(w3, 2, Half::D), "D");
  add_initial(a, s0);
  return a;
}

inline Points random_points(Eigen::Index rows, Eigen::Index cols, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Points P(rows, cols);
  for (Eigen::Index i = 0; i < P.size(); ++i) P.data()[i] = u(rng);
  return P;
}

/// Random affine map (`rows by cols`, rows summing to 1, negative entries) with δ = `target`:
/// M = 1·vᵀ + α(R − 1·vᵀ) for a probability row v; δ(M) = α·δ(R).
inline Eigen::MatrixXd random_contraction(Eigen::Index rows, Eigen::Index cols, double target,
                                          std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.6, 1.0), p(0.1, 1.0);
  Eigen::MatrixXd R(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) R(i, j) = u(rng);
    R.row(i) /= R.row(i).sum();  // may amplify: fine, α rescales
    if (!R.row(i).allFinite() || std::abs(R.row(i).sum() - 1) > 1e-12)
      R.row(i).setConstant(1.0 / static_cast<double>(cols));
  }
  Eigen::RowVectorXd v(cols);
  for (Eigen::Index j = 0; j < cols; ++j) v(j) = p(rng);
  v /= v.sum();
  const Eigen::MatrixXd V = Eigen::VectorXd::Ones(rows) * v;
  double d = 0;
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = i + 1; j < rows; ++j) d = std::max(d, (R.row(i) - R.row(j)).cwiseAbs().sum() / 2);
  const double alpha = d > 0 ? target / d : 0;
  return V + alpha * (R - V);
}

/// Cox–de Boor (Piegl & Tiller A2.2) in long double on the span `span` (fixed, so that the right
/// end of the span evaluates the same polynomial piece): the point Σ_r N_{span−d+r,d}(t)·P_{span−d+r},
/// with P indexed globally by `row(i)`.
template <class Row>
Eigen::RowVectorXd de_boor_reference(const std::vector<long double>& U, int d, int span, long double t,
                                     Row row, Eigen::Index cols) {
  std::vector<long double> N(static_cast<std::size_t>(d + 1)), left(N.size()), right(N.size());
  N[0] = 1;
  for (int j = 1; j <= d; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    left[uj] = t - U[static_cast<std::size_t>(span + 1 - j)];
    right[uj] = U[static_cast<std::size_t>(span + j)] - t;
    long double saved = 0;
    for (int r = 0; r < j; ++r) {
      const auto ur = static_cast<std::size_t>(r);
      const long double temp = N[ur] / (right[ur + 1] + left[uj - ur]);
      N[ur] = saved + right[ur + 1] * temp;
      saved = left[uj - ur] * temp;
    }
    N[uj] = saved;
  }
  Eigen::RowVectorXd out(cols);
  for (Eigen::Index c = 0; c < cols; ++c) {
    long double acc = 0;
    for (int r = 0; r <= d; ++r)
      acc += N[static_cast<std::size_t>(r)] * static_cast<long double>(row(span - d + r)(c));
    out(c) = static_cast<double>(acc);
  }
  return out;
}

/// Uniform B-spline of degree d with the control polygon `P` (knots 0, 1, …): the point at
/// parameter `t` of the segment `k` (span d + k, t ∈ [0, 1] local).
inline Eigen::RowVectorXd uniform_reference(const Points& P, int d, int k, long double t) {
  std::vector<long double> U(static_cast<std::size_t>(P.rows() + d + 1));
  for (std::size_t i = 0; i < U.size(); ++i) U[i] = static_cast<long double>(i);
  return de_boor_reference(
      U, d, d + k, static_cast<long double>(d + k) + t, [&](int i) { return P.row(i); }, P.cols());
}

/// Quadratic B-spline on the knots 0, 1, 1+u1, 1+u1+u2, 1+u1+u2+u3, 2+u1+u2+u3 (the segment
/// [1+u1, 1+u1+u2] has the window (u1,u2,u3)) at local parameter t ∈ [0, 1].
inline Eigen::RowVectorXd quadratic_reference(const Points& P, double u1, double u2, double u3,
                                              long double t) {
  const long double a = u1, b = u2, c = u3;
  const std::vector<long double> U{0, 1, 1 + a, 1 + a + b, 1 + a + b + c, 2 + a + b + c};
  return de_boor_reference(
      U, 2, 2, 1 + a + t * b, [&](int i) { return P.row(i); }, P.cols());
}

inline double scale_of(const Points& P) {
  return std::max(1.0, P.cwiseAbs().maxCoeff());
}

}  // namespace ifs_test
