// SPDX-License-Identifier: MIT
// cifs — analysis of a uniform binary scheme from its mask: symbol, support, primal or dual,
// interpolating or approximating, polynomial generation and reproduction, continuity C^k proved by
// Dyn's difference-scheme test in exact rationals, a Hölder exponent bracket, and the spectra of
// its IFS matrices.
//
// Let a(z) = (1+z)^m b(z) with b(−1) ≠ 0 (m ≥ 1 for a convergent scheme).
// - Generation degree m − 1: the scheme generates polynomials of degree < m.
// - Reproduction degree (Conti–Hormann): the largest d ≤ m − 1 with a^{(j)}(1) = 2 Π_{i<j}(τ − i)
//   for j = 0 … d, τ = a'(1)/2.
// - Continuity (Dyn): with d_k(z) = 2^k a(z)/(1+z)^{k+1} (k ≤ m − 1), the scheme is C^k when the
//   scheme of d_k is contractive: ‖S_{d_k}^L‖_∞ < 1 for some L ≥ 1, where ‖S_c^L‖_∞ is the largest
//   sum of |coefficients| of c^{[L]}(z) = Π_{i<L} c(z^{2^i}) over one residue class mod 2^L. The
//   largest k proved with L ≤ max_power is reported; the norm at the proving L is exact (integer
//   arithmetic on the common denominator).
// - Hölder exponent α ∈ [low, high]: low = k + min(ν, 1) with ν = −log2 min_L ‖S_{d_k}^L‖^{1/L} at
//   the largest proved k (norms of powers); high = (m − 1) − log2 max_w ρ(T_w)^{1/|w|} over the
//   products T_w of the IFS matrices of d_{m−1} along primitive words of length ≤
//   max_word_length (spectral radii of products; their limit is the same joint spectral radius
//   that the norms bound from above).
#pragma once

#include <array>
#include <complex>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cifs/subdivision/scheme.hpp"

namespace cifs::subdivision {

struct AnalysisOptions {
  /// Largest power L of the difference schemes tried (norms and Dyn's test).
  int max_power = 20;
  /// L is also capped so that c^{[L]} keeps at most this many coefficients (memory and time).
  std::size_t max_coefficients = std::size_t{1} << 22;
  /// Longest word whose product's spectral radius enters the upper Hölder bound (lowered to 6
  /// for matrices larger than 48 by 48).
  int max_word_length = 10;
};

/// The certificate of "continuity": ‖S_{d_k}^L‖_∞ = norm < 1.
struct ContinuityProof {
  int k = -1;
  int power = 0;
  Rational norm = 0;
};

struct SchemeAnalysis {
  Polynomial mask;             // a_0 … a_N
  int support = 0;             // N: the basic limit function lives on [0, N]
  bool symmetric = false;      // a_k = a_{N−k}
  std::string kind;            // "primal" (symmetric, N even), "dual" (symmetric, N odd), "asymmetric"
  bool interpolating = false;  // one parity of the mask is a single 1
  int multiplicity = 0;        // m, the power of (1+z) in a(z)
  int generation_degree = -1;  // m − 1
  int reproduction_degree = -1;
  int continuity = -1;  // C^k proved; −1: not even convergence proved
  ContinuityProof proof;
  std::optional<double> holder_low;   // absent when no continuity is proved
  std::optional<double> holder_high;  // absent when m = 0
  int holder_low_power = 0;           // the L of the best norm
  std::vector<int> holder_high_word;  // the word of the largest ρ(T_w)^{1/|w|}
  std::string symbol;                 // expanded, e.g. "(-1+9z^2+16z^3+9z^4-z^6)/16"
  std::string symbol_factored;        // e.g. "(1+z)^4*(-1+4z-z^2)/16" (parse_symbol reads both)
  std::array<std::vector<std::complex<double>>, 2> eigenvalues;  // of S_0 and S_1
};

/// Everything above. Deterministic; cost grows with 2^max_power only for schemes whose
/// contractivity is decided late.
SchemeAnalysis analyze(const Scheme& scheme, const AnalysisOptions& options = {});

/// d_k(z) = 2^k a(z)/(1+z)^{k+1}; InvalidInput unless (1+z)^{k+1} divides a(z).
Polynomial difference_mask(const Polynomial& a, int k);

/// ‖S_c^L‖_∞ exactly, for any mask c (L ≥ 1). Throws InvalidInput when c^{[L]} would have more
/// than `max_coefficients` coefficients.
Rational power_norm(const Polynomial& c, int L, std::size_t max_coefficients = std::size_t{1} << 22);

/// Expanded text of a polynomial with a common denominator: "(1+3z+3z^2+z^3)/4".
std::string polynomial_text(const Polynomial& p);

}  // namespace cifs::subdivision
