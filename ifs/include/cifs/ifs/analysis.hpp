// SPDX-License-Identifier: MIT
// cifs — analysis of a controlled IFS from its matrices alone: contraction of control nets, fixed
// points of words, the start/end functionals of every state, spectra of the transitions.
//
// Generic: any automaton whose transitions carry matrices with rows summing to 1 (affine
// combinations, `Q = M·P`, M is `to.size by from.size`); windows are never looked at.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

/// The states the engine works on: those reachable from the initial entries, or every state when
/// the automaton has no initial entry. Sorted.
std::vector<automata::StateId> reachable_states(const automata::Automaton& automaton);

/// Throws InvalidInput unless every reachable state holds at least one point and has at least one
/// transition, and every transition out of it carries a finite `to.size by from.size` matrix whose
/// rows sum to 1 (to 1e-10 of the row's 1-norm). Every engine entry point calls it.
void validate(const automata::Automaton& automaton);

/// Throws InvalidInput unless `nets` has one net per initial entry, each `size(state) by cols` with
/// one common cols ≥ 1, finite: the check of every route that takes nets. The messages name the
/// control nets; `who` is not printed (callers named internal functions) and may be left out.
void check_nets(const automata::Automaton& automaton, std::span<const Points> nets,
                std::string_view who = {});

/// Diameter of a net: the largest Euclidean distance between two of its rows (0 for < 2 rows).
double diameter(const Points& net) noexcept;

/// Diameter of all the rows of all the nets together (the control polygon's extent); with
/// `homogeneous` rows `(w·x, w)` of their Cartesian images. 0 for no rows. InvalidInput when the
/// extent is not a finite double (nothing relative to it could be computed).
double nets_diameter(std::span<const Points> nets, bool homogeneous = false);

/// Contraction coefficient of an affine map on nets: δ(M) = max_{i,j} ½‖M_i − M_j‖₁ over pairs of
/// rows of M (`r by n`). diam(M·N) ≤ δ(M)·diam(N) for every net N, and δ is the smallest such
/// constant (Dobrushin's ergodicity coefficient extended to signed rows), so δ(M·M') ≤ δ(M)·δ(M').
double delta(const Eigen::MatrixXd& M) noexcept;

struct ContractionOptions {
  /// Longest path length m tried.
  int max_length = 8;
  /// Also try longer paths (up to max_length, while the bound improves by > 5% and the paths of
  /// that length number ≤ 2^16 · (16/n)³ for states of size n > 16) for a smaller bound factor: for the
  /// uniform degree-6 B-spline the factor drops from 64 (m = 1) to about 1.1 (m = 5), saving six levels of
  /// subdivision.
  bool tighten = true;
  /// Compute A and `radius` (the piece bound of tolerance searches). Without, only contractivity is
  /// proved: m, delta and the worst path as with it, A and radius infinite, tighten ignored — and the
  /// scans skip every subtree whose δ cannot exceed the worst found (A would need them), which on
  /// perturbed bicubic surfaces (m = 6 to 8, up to 1.5 M paths) is most of the work.
  bool bound = true;
};

/// Result of the contractivity check: the products along every path of `m` transitions (from
/// every reachable state) shrink nets by at least `delta` < 1.
///
/// Bound (proved in analysis.cpp): if δ_k < 1 and A_k is the largest row 1-norm of the products
/// of all paths of length 0 … k, every attractor point of a state with net N, and every row of
/// every net below it, lies within `ρ_k·diam(N)` of the first row N_0, where
/// `ρ_k = (1 + A_k) / (2 (1 − δ_k))` ≤ A_k / (1 − δ_k). Hence the attractor piece of the state has
/// diameter ≤ `2·ρ_k·diam(N)`. `radius` is the smallest ρ_k found.
struct Contraction {
  int m = 0;              // smallest path length with δ_m < 1 (the contractivity witness)
  double delta = 0;       // δ_m = max over paths of length m of δ(product)
  double A = 1;           // A_m: max over paths of length 0 … m of the largest row 1-norm of the product
  double radius = 0;      // bound factor: min over the lengths k tried of ρ_k (ρ_m without tighten)
  int radius_length = 0;  // the k that gives `radius`
};

/// What contraction (and perturb) throw for a system that does not shrink nets: an InvalidInput whose
/// message names the state and path, with the figure itself for callers that show it (cifs view).
class NotContractive : public InvalidInput {
 public:
  NotContractive(const std::string& what, double worst_delta, int path_length)
      : InvalidInput(what), delta(worst_delta), length(path_length) {}
  double delta;  // δ_m of the worst path of the longest length tried (≥ 1)
  int length;    // that length m (ContractionOptions::max_length)
};

/// Finds the smallest m ≤ `max_length` with δ_m < 1. Throws NotContractive naming the state and the
/// path that fails when there is none ("not contractive: the 8-step products from state 3 do not
/// shrink nets (δ = 1 along the path 0 0 0 0 0 0 0 0 …)"), instead of letting iteration diverge.
Contraction contraction(const automata::Automaton& automaton, const ContractionOptions& options = {});

/// Per state (indexed by StateId): true when every transition on every path from the state
/// carries a matrix without negative entry. Products along such paths are stochastic, so every
/// row of every net below the state and every attractor point of it is a convex combination of
/// the rows of its net (hull property): the piece's diameter is at most the net's.
std::vector<bool> convex_states(const automata::Automaton& automaton);

/// A bound on one attractor piece: every point lies within `radius` of the first row of its net
/// (its Cartesian image for homogeneous rows), and any two points within `diameter` ≤ 2·radius.
/// Infinite when no bound is known (homogeneous rows whose weight may vanish on the piece).
struct PieceBound {
  double radius = 0;
  double diameter = 0;
};

/// Bounds on the attractor pieces of one automaton, per (state, net); proofs in analysis.cpp.
/// The smaller of the contraction bound (radius·diam(N)) and, for convex states, the hull bound
/// (max distance of the net's rows to its first row; diameter diam(N)). With `homogeneous` rows
/// `(w·x, w)` the bound is Cartesian: by the hull of the Cartesian net when the state is convex
/// and the weights have one sign, else from the homogeneous bound r around N₀ = (w₀x₀, w₀) as
/// r·√(1 + ‖x₀‖²) / (|w₀| − r) when |w₀| > r.
class PieceBounds {
 public:
  PieceBounds(const automata::Automaton& automaton, const Contraction& contraction, bool homogeneous);
  PieceBound operator()(automata::StateId state, const Points& net) const;
  /// A bound on the distance of every point of the piece to the segment [a, b] (Cartesian points,
  /// the piece's ends for a chordal tolerance): for convex states the largest distance of a
  /// (Cartesian) row of the net to the segment — distance to a convex set is a convex function, so
  /// its maximum over the hull is at a row — else the distance of the first row plus the piece's
  /// radius. Infinite when the piece has no bound.
  double chord_deviation(automata::StateId state, const Points& net, const Point& a, const Point& b) const;

 private:
  std::vector<bool> convex_;
  double factor_;
  bool homogeneous_;
};

/// Fixed point of a word: read the child indices `word` from `state` (the word must return to
/// `state`); the product `P = M_k ⋯ M_1` is `size by size`. Returns the row ℓ (`1 by size`) with
/// ℓ·P = ℓ and Σℓ = 1; the point of address word^∞ under a net N is ℓ·N. Throws InvalidInput
/// when a child index is out of range, the word does not return, or 1 is not a simple eigenvalue
/// of P.
Eigen::RowVectorXd fixed_point(const automata::Automaton& automaton, automata::StateId state,
                               std::span<const int> word);

/// Per state, the functionals of the two ends of its attractor piece: `start[s]·N` is the point of
/// address (first child)^∞ and `end[s]·N` the point of address (last child)^∞ under a net N of s.
/// Rows `1 by size(s)`, indexed by StateId; empty for states that are not reachable. For B-spline
/// automata `start[s]·N` is exactly the curve point at the start of the piece.
struct EndFunctionals {
  std::vector<Eigen::RowVectorXd> start;
  std::vector<Eigen::RowVectorXd> end;
};

/// Follows first (last) children until a state repeats, takes the fixed point of the cycle product
/// and propagates it back along the chain (λ_s = λ_child·M). Throws as fixed_point.
EndFunctionals end_functionals(const automata::Automaton& automaton);

/// Per state, the functional of the address k^∞ (child `child` repeated): `F[s]·N` is that point
/// of the attractor piece of s under a net N (`1 by size(s)`, indexed by StateId, empty for states
/// that are not reachable). For the four children GH, GB, DH, DB of a tensor-product automaton these
/// are the piece's corners (u, v) = (0, 0), (0, 1), (1, 0), (1, 1). Throws InvalidInput when a
/// reachable state has no child `child`, and as fixed_point.
std::vector<Eigen::RowVectorXd> repeated_child_functionals(const automata::Automaton& automaton, int child);

/// Eigenvalues of one transition matrix, sorted by decreasing modulus (ties: real part, then
/// imaginary part, decreasing).
struct TransitionSpectrum {
  automata::StateId from = 0, to = 0;
  int child = 0;  // index among the out-edges of `from`
  std::string label;
  /// Empty when the matrix is not square (the transition changes the net size).
  std::vector<std::complex<double>> eigenvalues;
};

/// Eigenvalues of a square matrix, sorted as above.
std::vector<std::complex<double>> eigenvalues(const Eigen::MatrixXd& M);

/// Spectra of every transition out of a reachable state, in state order then out-edge order.
std::vector<TransitionSpectrum> spectra(const automata::Automaton& automaton);

}  // namespace cifs::ifs
