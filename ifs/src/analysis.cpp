// SPDX-License-Identifier: MIT
// cifs — contraction of nets, fixed points of words, end functionals and spectra.
//
// Soundness of the tolerance bound (used by for_each_leaf_to_tolerance and the chaos game).
//
// Lemma 1. If Σ_k a_k = 0 then ‖Σ_k a_k N_k‖ ≤ ½‖a‖₁·diam(N) for any norm.
//   Write a = a⁺ − a⁻ (positive and negative parts); Σa⁺ = Σa⁻ = h = ½‖a‖₁. If h = 0 the sum is 0.
//   Otherwise Σ a_k N_k = h(x − y) with x = Σ (a⁺_k/h) N_k and y = Σ (a⁻_k/h) N_k convex
//   combinations of the rows, i.e. points of their convex hull, whose diameter equals the diameter
//   of the rows (the distance to a fixed point is convex, so its maximum over the hull is reached
//   at a vertex; apply twice). Hence ‖h(x − y)‖ ≤ h·diam(N).
//
// Corollary. Rows of M sum to 1, so (M·N)_i − (M·N)_j = (M_i − M_j)·N has coefficients summing to
//   0 and diam(M·N) ≤ δ(M)·diam(N) with δ(M) = max_{i,j} ½‖M_i − M_j‖₁. (δ is exactly the
//   operator bound: for one-dimensional nets N_k ∈ {0, 1} chosen on the positive part of
//   M_i − M_j the inequality is an equality; so δ is submultiplicative.)
//
// Theorem. Let δ_m < 1 be the max of δ over the products of all paths of m transitions starting
//   at any reachable state, and A ≥ 1 the max row 1-norm over the products of all paths of length
//   0 … m (length 0 is the identity). Then for a state s with net N, every row of every net below
//   s and every attractor point of s lie within ρ = ½(1 + A)·diam(N)/(1 − δ_m) of N_0.
//   Proof. Follow any path from s; N^(k) is the net after k steps. Blocks of m steps are paths of
//   length m from reachable states, so diam(N^(qm)) ≤ δ_m^q·diam(N). For k = qm + j, 0 ≤ j < m,
//   with R the product of the last j steps (a path of length j, R = I when j = 0):
//     ‖N^(k)_i − N^(qm)_0‖ = ‖(R_i − e_0)·N^(qm)‖ ≤ ½(‖R_i‖₁ + 1)·diam(N^(qm)) ≤ ½(1 + A)·δ_m^q·diam(N)
//   by Lemma 1 (R_i − e_0 sums to 0). The same with j = m bounds each block step
//   ‖N^((r+1)m)_0 − N^(rm)_0‖ ≤ ½(1 + A)·δ_m^r·diam(N). Telescoping,
//     ‖N^(k)_i − N_0‖ ≤ ½(1 + A)·diam(N)·Σ_{r=0}^{q} δ_m^r < ρ.
//   The rows form Cauchy sequences with diam(N^(k)) → 0 (the bound above with the geometric
//   tail), so they converge to the attractor point of the path's address, which is within ρ as
//   a limit of points within ρ. Two points of the piece are then within 2ρ of each other.
//   Since ½(1 + A) ≤ A, ρ is at most the bound A·diam(N)/(1 − δ_m). Nothing requires m to be the
//   smallest length with δ_m < 1: any such m gives a sound ρ, and `contraction` keeps the smallest.
//
// Hull bound (convex_states, PieceBounds). If every matrix on every path from s is non-negative
//   with rows summing to 1, every product P along a path is too (sums and products of
//   non-negative numbers; P·1 = 1), so each row of a net below s is a convex combination of the
//   rows of N, i.e. lies in their convex hull H; attractor points are limits of such rows (the
//   theorem above) and H is closed. The distance to N_0 is convex, so its maximum over H is
//   max_i ‖N_i − N_0‖ (a vertex), and diam(H) = diam(N) (Lemma 1's argument). Both are ≤ the
//   contraction bound, since ρ ≥ ½(1 + 1)/1 = 1.
//
// Homogeneous rows h = (w·x, w) (rational nets), Cartesian point x = h_x / h_w.
//   (a) Convex state and weights w_k of N all > 0 (or all < 0): a piece point is Σ c_k N_k with
//       c ≥ 0, Σc = 1, hence x = Σ (c_k w_k / Σ_j c_j w_j)·x_k, a convex combination of the
//       Cartesian rows x_k: the hull bound applies to the Cartesian net.
//   (b) Otherwise, with r the homogeneous radius around N_0 = (w_0 x_0, w_0): every piece point
//       p = (p_x, w_p) has |w_p − w_0| ≤ ‖p − N_0‖ ≤ r, so |w_p| ≥ |w_0| − r > 0 when |w_0| > r,
//       and x_p − x_0 = (p_x − w_p x_0)/w_p = ((p_x − w_0 x_0) − (w_p − w_0)·x_0)/w_p. By
//       Cauchy–Schwarz ‖a − b·x_0‖ ≤ ‖(a, b)‖·√(1 + ‖x_0‖²), so
//       ‖x_p − x_0‖ ≤ r·√(1 + ‖x_0‖²) / (|w_0| − r).
//
// Floating point: the lemma needs Σa = 0 exactly; rows summing to 1 up to η add η·‖N_0‖ per step,
// far below any tolerance that is meaningful in double precision.
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "cifs/cpu.hpp"
#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/failing_paths.hpp"
#include "walk.hpp"

namespace cifs::ifs {

using automata::Automaton;
using automata::Graph;
using automata::StateId;

namespace detail {

std::string state_label(const Automaton& automaton, StateId state) {
  std::string out = "state " + std::to_string(state);
  const auto& name = automaton.graph[state].name;
  if (!name.empty()) out += " (" + name + ")";
  return out;
}

std::string word_text(std::span<const int> word) {
  if (word.empty()) return "(empty)";
  std::string out;
  for (std::size_t k = 0; k < word.size(); ++k) {
    if (k) out += ' ';
    out += std::to_string(word[k]);
  }
  return out;
}

}  // namespace detail

// The messages name the nets, not `who`: callers passed their own function names, which users of
// the CLI and of Python never called.
void check_nets(const Automaton& automaton, std::span<const Points> nets, std::string_view /*who*/) {
  const auto fail = [&](const std::string& what) { throw InvalidInput(what); };
  if (nets.size() != automaton.initial.size())
    fail(std::to_string(nets.size()) + " control nets given for the automaton's " +
         std::to_string(automaton.initial.size()) + " initial entries (one net per entry)");
  if (nets.empty()) fail("the automaton has no initial entry, so there is nothing to draw; add one");
  const Eigen::Index cols = nets[0].cols();
  if (cols < 1) fail("control net 0 has no coordinate column");
  for (std::size_t i = 0; i < nets.size(); ++i) {
    const StateId s = automaton.initial[i].state;
    if (s >= num_vertices(automaton.graph))
      fail("initial[" + std::to_string(i) + "] names state " + std::to_string(s) + ", which does not exist");
    const int size = automaton.graph[s].size;
    if (nets[i].rows() != size)
      fail("control net " + std::to_string(i) + " has " + std::to_string(nets[i].rows()) +
           " points but its initial " + detail::state_label(automaton, s) + " holds " + std::to_string(size));
    if (nets[i].cols() != cols)
      fail("control net " + std::to_string(i) + " has " + std::to_string(nets[i].cols()) +
           " columns, control net 0 has " + std::to_string(cols));
    if (!nets[i].allFinite())
      fail("control net " + std::to_string(i) + " has a coordinate that is not finite");
  }
}

std::vector<StateId> reachable_states(const Automaton& automaton) {
  const Graph& g = automaton.graph;
  const auto n = num_vertices(g);
  std::vector<char> seen(n, 0);
  std::vector<StateId> todo;
  if (automaton.initial.empty()) {
    for (StateId s = 0; s < n; ++s) todo.push_back(s);
  } else {
    for (const auto& init : automaton.initial)
      if (init.state < n) todo.push_back(init.state);
  }
  while (!todo.empty()) {
    const StateId s = todo.back();
    todo.pop_back();
    if (seen[s]) continue;
    seen[s] = 1;
    for (auto [b, e] = out_edges(s, g); b != e; ++b) todo.push_back(target(*b, g));
  }
  std::vector<StateId> out;
  for (StateId s = 0; s < n; ++s)
    if (seen[s]) out.push_back(s);
  return out;
}

void validate(const Automaton& automaton) {
  const Graph& g = automaton.graph;
  const auto n = num_vertices(g);
  for (std::size_t i = 0; i < automaton.initial.size(); ++i)
    if (automaton.initial[i].state >= n)
      throw InvalidInput("initial[" + std::to_string(i) + "] names state " +
                         std::to_string(automaton.initial[i].state) + ", which does not exist");
  for (const StateId s : reachable_states(automaton)) {
    // Labels and places are strings built only for a message: valid automata have many transitions.
    const auto label = [&] { return detail::state_label(automaton, s); };
    if (g[s].size < 1)
      throw InvalidInput(label() + " holds no point (size " + std::to_string(g[s].size) + ")");
    if (out_degree(s, g) == 0)
      throw InvalidInput(label() + " has no transition: its attractor would be empty");
    int child = 0;
    for (auto [b, e] = out_edges(s, g); b != e; ++b, ++child) {
      const auto& M = g[*b].matrix;
      const StateId t = target(*b, g);
      const auto where = [&] {
        return "transition " + std::to_string(child) + " of " + label() + " (to " +
               detail::state_label(automaton, t) + ")";
      };
      if (M.rows() != g[t].size || M.cols() != g[s].size)
        throw InvalidInput(where() + ": matrix is " + std::to_string(M.rows()) + " by " +
                           std::to_string(M.cols()) + ", expected " + std::to_string(g[t].size) + " by " +
                           std::to_string(g[s].size) + " (to.size by from.size)");
      if (!M.allFinite()) throw InvalidInput(where() + ": matrix has a non-finite entry");
      for (Eigen::Index r = 0; r < M.rows(); ++r) {
        const double sum = M.row(r).sum(), norm = M.row(r).cwiseAbs().sum();
        if (!(std::abs(sum - 1) <= 1e-10 * std::max(1.0, norm))) {
          throw InvalidInput(where() + ": row " + std::to_string(r) + " sums to " + number_text(sum, 17) +
                             ", not 1 (rows are affine combinations)");
        }
      }
    }
  }
}

double diameter(const Points& net) noexcept {
  double best = 0;
  for (Eigen::Index i = 0; i < net.rows(); ++i)
    for (Eigen::Index j = i + 1; j < net.rows(); ++j)
      best = std::max(best, (net.row(i) - net.row(j)).squaredNorm());
  return std::sqrt(best);
}

double nets_diameter(std::span<const Points> nets, bool homogeneous) {
  Eigen::Index rows = 0;
  const Eigen::Index cols = nets.empty() ? 0 : nets.front().cols();
  for (std::size_t i = 0; i < nets.size(); ++i) {
    // Stacked below: nets of other widths wrote past the rows (the robustness test's mismatched
    // nets under ASan, called from tolerance_sample before any other check).
    if (nets[i].cols() != cols)
      throw InvalidInput("control net " + std::to_string(i) + " has " + std::to_string(nets[i].cols()) +
                         " columns, control net 0 has " + std::to_string(cols) +
                         "; every net needs the same");
    rows += nets[i].rows();
  }
  Points all(rows, cols);
  rows = 0;
  for (const Points& N : nets) {
    all.middleRows(rows, N.rows()) = N;
    rows += N.rows();
  }
  if (homogeneous) all = cartesian(all);
  // Scaled to the largest coordinate first: squared distances of coordinates above ~1e154 would
  // overflow although the diameter itself is a double.
  const double scale = all.size() ? all.cwiseAbs().maxCoeff() : 0.0;
  const double extent = scale > 0 && std::isfinite(scale) ? scale * diameter(all / scale) : diameter(all);
  if (!std::isfinite(extent))
    throw InvalidInput("the control points span more than a double holds (" +
                       (std::isfinite(scale) ? "coordinates up to " + number_text(scale, 3)
                                             : std::string("a weight so small that x/w overflows")) +
                       "); scale the shape down");
  return extent;
}

#if defined(CIFS_X86_AVX)
namespace {

/// |a_k − b_k| for a broadcast entry a_k of one row and four entries b_k of four rows (lanes not in `lanes`
/// are not read, and count 0).
__attribute__((target("avx"), always_inline)) inline __m256d row_distances(const double* a, const double* b,
                                                                           __m256i lanes) noexcept {
  return _mm256_andnot_pd(_mm256_set1_pd(-0.0),  // |x|: x with the sign bit cleared
                          _mm256_sub_pd(_mm256_broadcast_sd(a), _mm256_maskload_pd(b, lanes)));
}

/// Lane by lane, the larger of `best` and the sum (s0 + s2) + (s1 + s3) of four partial sums, as
/// std::max(best, sum): a sum that is NaN (a NaN entry) leaves `best` as it was. Lanes not in `lanes` count
/// 0.
__attribute__((target("avx"), always_inline)) inline __m256d larger(__m256d best, __m256d s0, __m256d s1,
                                                                    __m256d s2, __m256d s3,
                                                                    __m256i lanes) noexcept {
  const __m256d sum = _mm256_add_pd(_mm256_add_pd(s0, s2), _mm256_add_pd(s1, s3));
  return _mm256_max_pd(_mm256_and_pd(sum, _mm256_castsi256_pd(lanes)), best);
}

/// The largest ‖M_i − M_j‖₁ over pairs of rows of M, whose columns are a multiple of 4, with AVX: rows i and
/// i + 1 against four rows j at a time (one per lane, read down M's contiguous columns: no transpose, each
/// load serving both rows), each sum in the order of Eigen's SSE2 sum of a vector, which the generic loop of
/// delta gets — four partial sums over the entries k ≡ 0, 1, 2, 3 (mod 4), then (s0 + s2) + (s1 + s3) —, so
/// δ is the same double either way (tests/ifs/test_analysis.cpp). The blocks of rows j start at a multiple
/// of 4, so a block may hold rows j ≤ i + 1: their sums are those of pairs met elsewhere (|a − b| = |b − a|,
/// summed in the same order) or 0, and the largest is unchanged; lanes beyond the last row count 0. δ of
/// 16 × 16 products was half of a contractivity check's instructions, its transpose a fifth of that.
__attribute__((target("avx"))) double largest_distance_avx(const Eigen::MatrixXd& M) noexcept {
  const Eigen::Index n = M.rows(), cols = M.cols();
  __m256d best = _mm256_setzero_pd();
  for (Eigen::Index i = 0; i + 1 < n; i += 2) {
    const double* a = M.data() + i;  // a[k * n]: M(i, k), a[k * n + 1]: M(i + 1, k) (when i + 1 < n)
    for (Eigen::Index j = (i + 1) / 4 * 4; j < n; j += 4) {
      const __m256i lanes = _mm256_set_epi64x(j + 3 < n ? -1 : 0, j + 2 < n ? -1 : 0, j + 1 < n ? -1 : 0, -1);
      const double* b = M.data() + j;  // b[k * n + q]: M(j + q, k)
      __m256d s0 = row_distances(a, b, lanes), s1 = row_distances(a + n, b + n, lanes),
              s2 = row_distances(a + 2 * n, b + 2 * n, lanes),
              s3 = row_distances(a + 3 * n, b + 3 * n, lanes);
      __m256d t0 = row_distances(a + 1, b, lanes), t1 = row_distances(a + 1 + n, b + n, lanes),
              t2 = row_distances(a + 1 + 2 * n, b + 2 * n, lanes),
              t3 = row_distances(a + 1 + 3 * n, b + 3 * n, lanes);
      for (Eigen::Index k = 4; k < cols; k += 4) {
        const double *x = a + k * n, *y = b + k * n;
        s0 = _mm256_add_pd(s0, row_distances(x, y, lanes));
        t0 = _mm256_add_pd(t0, row_distances(x + 1, y, lanes));
        s1 = _mm256_add_pd(s1, row_distances(x + n, y + n, lanes));
        t1 = _mm256_add_pd(t1, row_distances(x + 1 + n, y + n, lanes));
        s2 = _mm256_add_pd(s2, row_distances(x + 2 * n, y + 2 * n, lanes));
        t2 = _mm256_add_pd(t2, row_distances(x + 1 + 2 * n, y + 2 * n, lanes));
        s3 = _mm256_add_pd(s3, row_distances(x + 3 * n, y + 3 * n, lanes));
        t3 = _mm256_add_pd(t3, row_distances(x + 1 + 3 * n, y + 3 * n, lanes));
      }
      best = larger(best, s0, s1, s2, s3, lanes);
      best = larger(best, t0, t1, t2, t3, lanes);
    }
  }
  alignas(32) double lane[4];
  _mm256_store_pd(lane, best);
  return std::max(std::max(lane[0], lane[1]), std::max(lane[2], lane[3]));
}

/// C = A·B, A's rows a multiple of 4, with AVX: four rows of a column of C at a time, each entry summed
/// over k in order from 0 by a product and an addition (no fused multiply-add), the doubles of Eigen's
/// product in this build (the residual and δ tests compare with it), without its packing of both
/// operands, which took a third of a 16 × 16 product.
__attribute__((target("avx"))) void multiply_avx(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                                 Eigen::MatrixXd& C) noexcept {
  const Eigen::Index n = A.rows(), depth = A.cols();
  if (n == 16) {  // a column of C in four registers, each column of A read once per column of C
    for (Eigen::Index j = 0; j < B.cols(); ++j) {
      __m256d s0 = _mm256_setzero_pd(), s1 = s0, s2 = s0, s3 = s0;
      for (Eigen::Index k = 0; k < depth; ++k) {
        const double* a = A.data() + k * 16;
        const __m256d b = _mm256_set1_pd(B(k, j));
        s0 = _mm256_add_pd(s0, _mm256_mul_pd(_mm256_loadu_pd(a), b));
        s1 = _mm256_add_pd(s1, _mm256_mul_pd(_mm256_loadu_pd(a + 4), b));
        s2 = _mm256_add_pd(s2, _mm256_mul_pd(_mm256_loadu_pd(a + 8), b));
        s3 = _mm256_add_pd(s3, _mm256_mul_pd(_mm256_loadu_pd(a + 12), b));
      }
      double* c = C.data() + j * 16;
      _mm256_storeu_pd(c, s0);
      _mm256_storeu_pd(c + 4, s1);
      _mm256_storeu_pd(c + 8, s2);
      _mm256_storeu_pd(c + 12, s3);
    }
    return;
  }
  for (Eigen::Index j = 0; j < B.cols(); ++j)
    for (Eigen::Index i = 0; i < n; i += 4) {
      __m256d sum = _mm256_setzero_pd();
      for (Eigen::Index k = 0; k < depth; ++k)
        sum =
            _mm256_add_pd(sum, _mm256_mul_pd(_mm256_loadu_pd(A.data() + k * n + i), _mm256_set1_pd(B(k, j))));
      _mm256_storeu_pd(C.data() + j * n + i, sum);
    }
}

/// multiply_net's four-row blocks with AVX: rows i … i + 3 of a column of A in one register, the sums as
/// multiply_net_scalar's (a product and an addition per term, no fused multiply-add: the same doubles).
template <int Cols>
__attribute__((target("avx"))) void multiply_net_avx(const double* A, Eigen::Index r, Eigen::Index n,
                                                     const double* N, double* out) noexcept {
  constexpr int kSplit = Cols < 4 ? Cols / 2 * 2 : 0;
  const Eigen::Index peeled = n / 8 * 8;
  for (Eigen::Index i = 0; i + 4 <= r; i += 4) {
    __m256d even[Cols], odd[Cols];
    for (int c = 0; c < Cols; ++c) even[c] = odd[c] = _mm256_setzero_pd();
    Eigen::Index k = 0;
    for (; k < peeled; k += 2) {
      const __m256d a0 = _mm256_loadu_pd(A + k * r + i), a1 = _mm256_loadu_pd(A + (k + 1) * r + i);
      for (int c = 0; c < Cols; ++c) {
        even[c] = _mm256_add_pd(even[c], _mm256_mul_pd(a0, _mm256_set1_pd(N[k * Cols + c])));
        __m256d& second = c < kSplit ? odd[c] : even[c];
        second = _mm256_add_pd(second, _mm256_mul_pd(a1, _mm256_set1_pd(N[(k + 1) * Cols + c])));
      }
    }
    for (int c = 0; c < kSplit; ++c) even[c] = _mm256_add_pd(even[c], odd[c]);
    for (; k < n; ++k) {
      const __m256d a = _mm256_loadu_pd(A + k * r + i);
      for (int c = 0; c < Cols; ++c)
        even[c] = _mm256_add_pd(even[c], _mm256_mul_pd(a, _mm256_set1_pd(N[k * Cols + c])));
    }
    alignas(32) double column[Cols][4];
    for (int c = 0; c < Cols; ++c) _mm256_store_pd(column[c], even[c]);
    for (int q = 0; q < 4; ++q)
      for (int c = 0; c < Cols; ++c) out[(i + q) * Cols + c] = column[c][q];
  }
}

}  // namespace

__attribute__((target("avx"))) void detail::emit_avx(const double* f, Eigen::Index rows, Eigen::Index n,
                                                     const Points& N, double* out) noexcept {
  const Eigen::Index C = N.cols();
  const __m256i lanes = _mm256_set_epi64x(C == 4 ? -1 : 0, -1, -1, -1);
  const double* p = N.data();
  Eigen::Index r = 0;
  // Four points at a time share each row of the net (one load for four products).
  for (; r + 4 <= rows; r += 4, f += 4 * n, out += 4 * C) {
    __m256d s0 = _mm256_setzero_pd(), s1 = s0, s2 = s0, s3 = s0;
    for (Eigen::Index k = 0; k < n; ++k) {
      const __m256d q = _mm256_maskload_pd(p + k * C, lanes);
      s0 = _mm256_add_pd(s0, _mm256_mul_pd(_mm256_broadcast_sd(f + k), q));
      s1 = _mm256_add_pd(s1, _mm256_mul_pd(_mm256_broadcast_sd(f + n + k), q));
      s2 = _mm256_add_pd(s2, _mm256_mul_pd(_mm256_broadcast_sd(f + 2 * n + k), q));
      s3 = _mm256_add_pd(s3, _mm256_mul_pd(_mm256_broadcast_sd(f + 3 * n + k), q));
    }
    _mm256_maskstore_pd(out, lanes, s0);
    _mm256_maskstore_pd(out + C, lanes, s1);
    _mm256_maskstore_pd(out + 2 * C, lanes, s2);
    _mm256_maskstore_pd(out + 3 * C, lanes, s3);
  }
  for (; r < rows; ++r, f += n, out += C) {
    __m256d sum = _mm256_setzero_pd();
    for (Eigen::Index k = 0; k < n; ++k)
      sum =
          _mm256_add_pd(sum, _mm256_mul_pd(_mm256_broadcast_sd(f + k), _mm256_maskload_pd(p + k * C, lanes)));
    _mm256_maskstore_pd(out, lanes, sum);
  }
}
#endif

void detail::multiply(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, Eigen::MatrixXd& C) {
#if defined(CIFS_X86_AVX)
  if (A.rows() % 4 == 0 && cpu_has_avx()) {
    C.resize(A.rows(), B.cols());
    multiply_avx(A, B, C);
    return;
  }
#endif
  C.noalias() = A * B;
}

namespace {

/// out (r × Cols, row-major) = A (r × n) · N (n × Cols, row-major), the doubles of Eigen 3.4's product in
/// this build (SSE2), which sums in three orders (tests/ifs/test_analysis.cpp compares shapes up to
/// 47 × 47 with it): below 20 of r + n + Cols, Eigen's coefficient-wise product, each entry from its
/// first term in k order; else its blocked product on the transposed problem (no blocking below 48),
/// each entry from +0 in k order, but for the first two columns when Cols is 2 or 3 in rows of whole
/// groups of four, which its one-packet kernel sums in two accumulators — even and odd k over the first
/// 8·⌊n/8⌋ terms —, added, then the other terms in order. Rows from `first_row` on.
template <int Cols>
void multiply_net_scalar(const double* A, Eigen::Index r, Eigen::Index n, const double* N, double* out,
                         Eigen::Index first_row) noexcept {
  const bool coefficient_wise = r + n + Cols < 20;
  constexpr int kSplit = Cols < 4 ? Cols / 2 * 2 : 0;
  const Eigen::Index peeled = n / 8 * 8, groups = r / 4 * 4;
  for (Eigen::Index i = first_row; i < r; ++i)
    for (int c = 0; c < Cols; ++c) {
      double sum = coefficient_wise ? A[i] * N[c] : 0;
      Eigen::Index k = coefficient_wise ? 1 : 0;
      if (!coefficient_wise && c < kSplit && i < groups) {
        double odd = 0;
        for (; k < peeled; k += 2) {
          sum += A[k * r + i] * N[k * Cols + c];
          odd += A[(k + 1) * r + i] * N[(k + 1) * Cols + c];
        }
        sum += odd;
      }
      for (; k < n; ++k) sum += A[k * r + i] * N[k * Cols + c];
      out[i * Cols + c] = sum;
    }
}

template <int Cols>
void multiply_net(const Eigen::MatrixXd& A, const Points& B, Points& C) {
  const Eigen::Index r = A.rows(), n = A.cols();
  Eigen::Index done = 0;
#if defined(CIFS_X86_AVX)
  if (r + n + Cols >= 20 && cpu_has_avx()) {
    multiply_net_avx<Cols>(A.data(), r, n, B.data(), C.data());
    done = r / 4 * 4;
  }
#endif
  multiply_net_scalar<Cols>(A.data(), r, n, B.data(), C.data(), done);
}

}  // namespace

void detail::multiply(const Eigen::MatrixXd& A, const Points& B, Points& C) {
  C.resize(A.rows(), B.cols());
  if (A.rows() < 48 && A.cols() < 48 && A.cols() > 0) {
    switch (B.cols()) {
      case 1:
        return multiply_net<1>(A, B, C);
      case 2:
        return multiply_net<2>(A, B, C);
      case 3:
        return multiply_net<3>(A, B, C);
      case 4:
        return multiply_net<4>(A, B, C);
      default:
        break;
    }
  }
  C.noalias() = A * B;
}

double delta(const Eigen::MatrixXd& M) noexcept {
#if defined(CIFS_X86_AVX)
  if (M.cols() % 4 == 0 && M.cols() > 0 && cpu_has_avx()) return largest_distance_avx(M) / 2;
#endif
  // Rows as contiguous columns: the pairs loop vectorises (strided rows made δ of 65 × 65 products
  // as slow as the products themselves).
  const Eigen::MatrixXd T = M.transpose();
  double best = 0;
  for (Eigen::Index i = 0; i < T.cols(); ++i)
    for (Eigen::Index j = i + 1; j < T.cols(); ++j)
      best = std::max(best, (T.col(i) - T.col(j)).cwiseAbs().sum());
  return best / 2;
}

std::vector<bool> convex_states(const Automaton& automaton) {
  const Graph& g = automaton.graph;
  const auto n = num_vertices(g);
  // A state is not convex when it has a negative matrix or reaches such a state: propagate
  // backwards from the states with a negative out-transition.
  std::vector<std::vector<StateId>> into(n);
  std::vector<StateId> todo;
  std::vector<bool> convex(n, true);
  for (StateId s = 0; s < n; ++s)
    for (auto [b, e] = out_edges(s, g); b != e; ++b) {
      into[target(*b, g)].push_back(s);
      if (convex[s] && (g[*b].matrix.array() < 0).any()) {
        convex[s] = false;
        todo.push_back(s);
      }
    }
  while (!todo.empty()) {
    const StateId s = todo.back();
    todo.pop_back();
    for (const StateId u : into[s])
      if (convex[u]) {
        convex[u] = false;
        todo.push_back(u);
      }
  }
  return convex;
}

PieceBounds::PieceBounds(const Automaton& automaton, const Contraction& contraction, bool homogeneous)
    : convex_(convex_states(automaton)), factor_(contraction.radius), homogeneous_(homogeneous) {}

namespace {

/// max_i ‖N_i − N_0‖ and diam(N): the hull bound (analysis.cpp header).
PieceBound hull_bound(const Points& net) {
  double far = 0;
  for (Eigen::Index i = 1; i < net.rows(); ++i) far = std::max(far, (net.row(i) - net.row(0)).squaredNorm());
  return {std::sqrt(far), diameter(net)};
}

/// Distance from p to the segment [a, b] (to a when a = b).
double segment_distance(const Eigen::Ref<const Point>& p, const Point& a, const Point& b) {
  // Expressions, no Point temporary: this runs per row of every piece of a tolerance search, where a
  // heap allocation per call was a third of the instructions (9 s under ASan for one refusal).
  const auto d = b - a;
  const double length2 = d.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(d) / length2, 0.0, 1.0) : 0.0;
  return (p - a - t * d).norm();
}

double farthest_from_segment(const Points& rows, const Point& a, const Point& b) {
  double far = 0;
  for (Eigen::Index i = 0; i < rows.rows(); ++i) far = std::max(far, segment_distance(rows.row(i), a, b));
  return far;
}

}  // namespace

PieceBound PieceBounds::operator()(StateId state, const Points& net) const {
  const bool convex = state < convex_.size() && convex_[state];
  if (!homogeneous_) {
    const double r = factor_ * diameter(net);
    return convex ? hull_bound(net) : PieceBound{r, 2 * r};
  }
  const Eigen::Index c = net.cols() - 1;
  const auto w = net.col(c);
  if (convex && ((w.array() > 0).all() || (w.array() < 0).all())) {
    Points X = net.leftCols(c);
    X.array().colwise() /= w.array();
    return hull_bound(X);
  }
  const double r = factor_ * diameter(net), w0 = std::abs(net(0, c));
  if (!(w0 > r)) return {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  const double x0 = net.row(0).head(c).norm() / w0;
  const double radius = r * std::sqrt(1 + x0 * x0) / (w0 - r);
  return {radius, 2 * radius};
}

double PieceBounds::chord_deviation(StateId state, const Points& net, const Point& a, const Point& b) const {
  const bool convex = state < convex_.size() && convex_[state];
  if (!homogeneous_)
    return convex ? farthest_from_segment(net, a, b)
                  : segment_distance(net.row(0), a, b) + factor_ * diameter(net);
  const Eigen::Index c = net.cols() - 1;
  const auto w = net.col(c);
  if (convex && ((w.array() > 0).all() || (w.array() < 0).all())) {
    Points X = net.leftCols(c);
    X.array().colwise() /= w.array();
    return farthest_from_segment(X, a, b);
  }
  const PieceBound bound = (*this)(state, net);  // around the Cartesian first row
  if (!std::isfinite(bound.radius)) return std::numeric_limits<double>::infinity();
  const Point x0 = net.row(0).head(c) / net(0, c);
  return segment_distance(x0, a, b) + bound.radius;
}

namespace {

/// The transition `child` of `s` (out-edge position).
automata::TransitionId out_edge(const Graph& g, StateId s, std::size_t child) {
  auto [b, e] = out_edges(s, g);
  std::advance(b, static_cast<std::ptrdiff_t>(child));
  return *b;
}

/// Per state t, bounds over the paths of `length` transitions from t: the largest δ of their
/// products and the largest ∞-norm of the products of their prefixes (the empty one included, so ≥ 1).
/// Also, per state, the δ and ∞-norm of each path of `length` from it, in the order a scan visits them: a
/// scan of 2·length transitions bounds its nodes of depth `length`, whose products are those very paths'
/// (the same products, computed the same way), and reads their δ here instead of making them again.
struct SuffixBounds {
  int length = 0;
  std::vector<double> delta, norm;                 // by state
  std::vector<std::vector<double>> deltas, norms;  // by state, by path
  std::vector<std::vector<double>> step;           // by state, by out-edge: δ of the transition's matrix
};

/// Enumerates the paths of exactly `length` transitions from every reachable state, with the
/// products along the way (`size(target) by size(start)`).
///
/// With `suffix` (length h < `length`), a branch and bound: δ and the ∞-norm are submultiplicative on
/// products whose rows sum to 1 (δ is the norm induced by ‖·‖₁ on the row vectors summing to 0, which
/// such products map into themselves), so below a node at depth `length − h` in state t with product
/// P, every path's product B·P has δ ≤ δ(P)·delta[t] and every prefix ‖B·P‖∞ ≤ ‖P‖∞·norm[t]. When
/// both bounds are within what the scan has found, the subtree cannot change `worst` or `A` (beyond
/// rounding: A takes the bound, a sound upper bound) and is skipped. On the 369-state perturbed bicubic
/// surface (m = 6: 1.5 M paths) 98 % of the depth-3 subtrees are skipped.
/// Without `norms` (ContractionOptions::bound off) A is not tracked and only δ bounds the skipping.
struct PathScan {
  explicit PathScan(const Automaton& a, int len, bool stop, const SuffixBounds* bounds = nullptr,
                    bool with_norms = true)
      : automaton(a), length(len), stop_at_first_failure(stop), suffix(bounds), norms(with_norms) {}
  const Automaton& automaton;
  int length = 0;
  bool stop_at_first_failure = false;
  const SuffixBounds* suffix = nullptr;
  bool norms = true;
  // Results.
  double A = 1, worst = 0;
  StateId worst_state = 0;
  std::vector<int> worst_word;
  bool record = false;  // keep every path's δ and ∞-norm (SuffixBounds::deltas, norms)
  std::vector<double> leaf_delta, leaf_norm;
  std::size_t met = 0;  // the nodes of depth length − h met from the current start state
  // Work space: product and word per level.
  std::vector<Eigen::MatrixXd> product;
  std::vector<int> word;

  // Returns false to abandon the scan (a failure found and stop_at_first_failure). `bounded`: a node of depth
  // length − h whose skip was decided (not skipped) by its parent, on the δ and norm it would compute.
  bool descend(StateId from, StateId s, int k, bool bounded = false) {
    const Graph& g = automaton.graph;
    const auto& P = product[static_cast<std::size_t>(k)];
    const double norm = norms ? P.cwiseAbs().rowwise().sum().maxCoeff() : 1.0;
    A = std::max(A, norm);
    if (k == length) {
      const double d = delta(P);
      if (record) {
        leaf_delta.push_back(d);
        leaf_norm.push_back(norm);
      }
      if (d > worst || worst_word.empty()) {
        worst = d;
        worst_state = from;
        worst_word.assign(word.begin(), word.begin() + k);
      }
      return !(stop_at_first_failure && d >= 1);
    }
    if (suffix && k == length - suffix->length && !bounded && skips(delta(P), norm, s)) return true;
    // The parent of leaves: a leaf's δ is at most δ(M)·δ(P) (M its transition; submultiplicative, as the
    // subtrees' bounds), so a leaf whose bound is within the worst found cannot change it: its product and δ
    // are not made. Without norms only (a skipped leaf would not raise A), and not when recording.
    const double leaves =
        suffix && !norms && !record && k + 1 == length && !worst_word.empty() ? delta(P) : -1;
    // Children at depth h of a scan of 2h: their δ and norm are the suffix scan's, the product is made
    // only for a child that is not skipped (whose δ is then not made again: skips would answer the same).
    const bool known = suffix && k + 1 == suffix->length && length == 2 * suffix->length;
    int child = 0;
    for (auto [b, e] = out_edges(s, g); b != e; ++b, ++child) {
      word[static_cast<std::size_t>(k)] = child;
      if (leaves >= 0 && leaves * suffix->step[s][static_cast<std::size_t>(child)] <= worst) continue;
      if (known) {
        const std::size_t i = met++;
        const double n = norms ? suffix->norms[from][i] : 1.0;
        A = std::max(A, n);
        if (skips(suffix->deltas[from][i], n, target(*b, g))) continue;
      }
      times(g[*b].matrix, k, product);
      if (!descend(from, target(*b, g), k + 1, known)) return false;
    }
    return true;
  }

  /// Whether the subtree below a node of depth length − h in state s, whose product has δ `d` and ∞-norm
  /// `norm` (A already raised to it), is skipped: it cannot change `worst`, nor `A` beyond its bound.
  bool skips(double d, double norm, StateId s) {
    if (worst_word.empty()) return false;
    const double norm_bound = norms ? norm * suffix->norm[s] : 1.0;
    if (d * suffix->delta[s] <= worst && norm_bound <= A * (1 + 1e-12)) {
      A = std::max(A, norm_bound);
      return true;
    }
    return false;
  }

  /// Whether a scan that stops at the first failure would stop, settled by one path (a kept failing
  /// path, FailingPaths): true when `path` starts at a state of `states` (sorted), fits the automaton,
  /// its product — computed as `descend` computes it — has δ ≥ 1, and no bound can skip it: the bound at
  /// its depth `length − h` node is ≥ 1, above any `worst` of a scan that has not stopped. Then the scan
  /// reaches it or stops at an earlier failure. False says nothing: the scan must run.
  bool fails_along(const std::vector<StateId>& states, const FailingPaths::Path& path) {
    const Graph& g = automaton.graph;
    if (!stop_at_first_failure || path.word.size() != static_cast<std::size_t>(length) ||
        !std::binary_search(states.begin(), states.end(), path.state))
      return false;
    product.resize(static_cast<std::size_t>(length) + 1);
    product[0] = Eigen::MatrixXd::Identity(g[path.state].size, g[path.state].size);
    StateId s = path.state;
    for (int k = 0; k < length; ++k) {
      const auto& P = product[static_cast<std::size_t>(k)];
      if (suffix && k == length - suffix->length && !(delta(P) * suffix->delta[s] >= 1)) return false;
      const int child = path.word[static_cast<std::size_t>(k)];
      if (child < 0 || static_cast<std::size_t>(child) >= out_degree(s, g)) return false;
      const automata::TransitionId t = out_edge(g, s, static_cast<std::size_t>(child));
      times(g[t].matrix, k, product);
      s = target(t, g);
    }
    return delta(product[static_cast<std::size_t>(length)]) >= 1;
  }

  /// product[k + 1] = M · product[k]; at k = 0 (the identity) M itself: the value of M · I, whose terms
  /// but one are ±0 (exact, up to the sign of a zero, which no δ or norm reads), without the product.
  static void times(const Eigen::MatrixXd& M, int k, std::vector<Eigen::MatrixXd>& product) {
    auto& next = product[static_cast<std::size_t>(k) + 1];
    if (k == 0)
      next = M;
    else
      detail::multiply(M, product[static_cast<std::size_t>(k)], next);
  }

  bool run(const std::vector<StateId>& states) {
    product.resize(static_cast<std::size_t>(length) + 1);
    word.assign(static_cast<std::size_t>(length), 0);
    for (const StateId s : states) {
      const int n = automaton.graph[s].size;
      product[0] = Eigen::MatrixXd::Identity(n, n);
      met = 0;
      if (!descend(s, s, 0)) return false;
    }
    return true;
  }
};

/// The suffix bounds of paths of `length` transitions from every state in `states` (exact maxima: one
/// full scan per state, about 1/out-degree of the work of a scan one level longer); the norms only
/// `with_norms` (the scans they bound track A: ContractionOptions::bound), else 1.
SuffixBounds suffix_bounds(const Automaton& automaton, const std::vector<StateId>& states, int length,
                           bool with_norms) {
  const auto n = num_vertices(automaton.graph);
  SuffixBounds out{.length = length,
                   .delta = std::vector<double>(n, 0),
                   .norm = std::vector<double>(n, 1),
                   .deltas = std::vector<std::vector<double>>(n),
                   .norms = std::vector<std::vector<double>>(n),
                   .step = std::vector<std::vector<double>>(n)};
  for (const StateId s : states) {
    PathScan scan(automaton, length, false, nullptr, with_norms);
    scan.record = true;
    scan.run({s});
    out.delta[s] = scan.worst;
    out.norm[s] = scan.A;
    out.deltas[s] = std::move(scan.leaf_delta);
    out.norms[s] = std::move(scan.leaf_norm);
    for (auto [b, e] = out_edges(s, automaton.graph); b != e; ++b)
      out.step[s].push_back(delta(automaton.graph[*b].matrix));
  }
  return out;
}

/// ℓ with ℓ·P = ℓ, Σℓ = 1, for a square P whose rows sum to 1 (P·1 = 1).
/// K = I − P + 1·1ᵀ is invertible exactly when 1 is an algebraically simple eigenvalue of P: if
/// K·x = 0 then, multiplying by the left eigenvector ℓ (ℓ·1 ≠ 0 when simple), 1ᵀx = 0, so
/// (I − P)x = 0, x ∥ 1 and x = 0; conversely a second eigenvector or a Jordan chain y with
/// (I − P)y = 1 gives a kernel vector. Then ℓ = 1ᵀ·K⁻¹ satisfies ℓ(I − P) + (ℓ·1)1ᵀ = 1ᵀ; times 1
/// gives ℓ·1 = 1, hence ℓ(I − P) = 0.
///
/// K counts as singular when its singular values give σ_min ≤ 1e-12·n·σ_max. An SVD took 90 % of the
/// instructions of a fixed point (the corner functionals of a mesh: a hundred per edit of the hills), so
/// it is made only when a cheaper sufficient condition fails: with X the inverse of Kᵀ from its LU (which
/// the solve below uses anyway) and R = I − X·Kᵀ, ‖R‖_F ≤ ½ gives ‖K⁻¹‖₂ ≤ ‖X‖₂ / (1 − ‖R‖₂) ≤ 2‖X‖_F,
/// so κ₂(K) ≤ 2‖K‖_F‖X‖_F; at most 2·10⁶ (R's rounding, ~n·ε·κ, moves the 2 by less than 1 %) the SVD's
/// σ_min/σ_max, which it computes to ~n·ε·κ relative error, is above 4·10⁻⁷ > 1e-12·n for every
/// n < 10⁵: the same verdict, which the SVD still gives whenever the condition fails.
Eigen::RowVectorXd unit_fixed_point(const Eigen::MatrixXd& P, const std::string& context) {
  const Eigen::Index n = P.rows();
  const Eigen::MatrixXd K = Eigen::MatrixXd::Identity(n, n) - P + Eigen::MatrixXd::Ones(n, n);
  const auto lu = K.transpose().fullPivLu();
  const auto well_conditioned = [&] {
    if (n >= 100000 || !lu.isInvertible()) return false;
    const Eigen::MatrixXd X = lu.inverse();
    const double residual = (Eigen::MatrixXd::Identity(n, n) - X * K.transpose()).norm();
    return residual <= 0.5 && 2 * K.norm() * X.norm() <= 2e6;
  };
  const auto singular_by_svd = [&] {
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(K).singularValues();
    return !(sv(n - 1) > 1e-12 * static_cast<double>(n) * sv(0));
  };
  if (!well_conditioned() && singular_by_svd()) {
    std::string msg = context + ": 1 is not a simple eigenvalue of the product (eigenvalues";
    for (const auto& z : eigenvalues(P))
      msg += ' ' + number_text(z.real(), 6) + (z.imag() >= 0 ? "+" : "") + number_text(z.imag(), 6) + 'i';
    throw InvalidInput(msg + "), so its fixed point is not unique");
  }
  // ℓᵀ solves Kᵀ·ℓᵀ = 1.
  Eigen::RowVectorXd l = lu.solve(Eigen::VectorXd::Ones(n)).transpose();
  l /= l.sum();  // Σℓ = 1 already up to rounding; make it exact to the last bit or so
  // Polish by ℓ ← ℓ·P: the solve leaves eps-sized entries where ℓ is exactly 0 (a B-spline's basis
  // function vanishing at the end of its piece), and for rational shapes such an entry multiplies a
  // weight up to 1e6 times the others; the iteration damps them at the rate of the subdominant
  // eigenvalues. Kept only when its residual stays at rounding level (a product whose other
  // eigenvalues do not shrink could make it drift).
  Eigen::RowVectorXd polished = l, next(n);
  for (int k = 0; k < 64; ++k) {
    next.noalias() = polished * P;  // no temporary per step: this runs for every cycle of every table build
    polished.swap(next);
  }
  polished /= polished.sum();
  const auto residual = [&](const Eigen::RowVectorXd& x) { return (x * P - x).cwiseAbs().maxCoeff(); };
  const double floor = 4 * std::numeric_limits<double>::epsilon() * static_cast<double>(n) *
                       l.cwiseAbs().sum() * P.cwiseAbs().rowwise().sum().maxCoeff();
  return polished.allFinite() && residual(polished) <= std::max(residual(l), floor) ? polished : l;
}

}  // namespace

namespace {

/// contraction, with the failing paths of earlier checks when `failing` is not null.
Contraction check_contraction(const Automaton& automaton, const ContractionOptions& options,
                              FailingPaths* failing) {
  validate(automaton);
  if (options.max_length < 1)
    throw InvalidInput("the contraction check's path length " + std::to_string(options.max_length) +
                       " is below 1; give at least 1");
  const auto states = reachable_states(automaton);
  // Iterative deepening: the shortest m wins, and paths of length < max_length stop at the first
  // failing product (their A is not needed); the last length is scanned fully for the message.
  Contraction out;
  // Scans longer than 3 transitions skip the subtrees that cannot change their result, by the bounds of
  // suffixes of length h = min(m/2, 3). The suffixes cost d + d² + … + d^h products per state (d the
  // out-degree) and the scan d + … + d^(m−h) to the nodes it bounds: h = 3 at m = 4 spent 84 products
  // per state of the hills' surface on bounds for its 4 nodes of depth 1, most of a check (h = 2: 20).
  std::array<std::optional<SuffixBounds>, 4> suffixes;  // by h
  const auto bounds_for = [&](int m) -> const SuffixBounds* {
    if (m <= 3) return nullptr;
    auto& suffix = suffixes[static_cast<std::size_t>(std::min(m / 2, 3))];
    if (!suffix) suffix = suffix_bounds(automaton, states, std::min(m / 2, 3), options.bound);
    return &*suffix;
  };
  if (failing && failing->by_length.size() < static_cast<std::size_t>(options.max_length))
    failing->by_length.resize(static_cast<std::size_t>(options.max_length));
  for (int m = 1; m <= options.max_length; ++m) {
    PathScan scan(automaton, m, m < options.max_length, bounds_for(m), options.bound);
    // A kept failing path settles a length below the last one as its scan would (the last length is
    // always scanned in full, for its δ or the message).
    if (failing && scan.fails_along(states, failing->by_length[static_cast<std::size_t>(m) - 1])) {
      ++failing->settled;
      continue;
    }
    const bool complete = scan.run(states);
    if (failing && !complete)  // the path the scan stopped at
      failing->by_length[static_cast<std::size_t>(m) - 1] = {scan.worst_state, scan.worst_word};
    if (complete && scan.worst < 1) {
      out.m = m;
      out.delta = scan.worst;
      out.A = options.bound ? scan.A : std::numeric_limits<double>::infinity();
      out.radius = options.bound ? (1 + scan.A) / (2 * (1 - scan.worst)) : out.A;
      out.radius_length = m;
      break;
    }
    if (m == options.max_length) {
      throw NotContractive("not contractive: the " + std::to_string(m) + "-step products from " +
                               detail::state_label(automaton, scan.worst_state) +
                               " do not shrink nets (δ = " + number_text(scan.worst, 6) + " along the path " +
                               detail::word_text(scan.worst_word) + "; no path length ≤ " +
                               std::to_string(m) + " gives δ < 1)",
                           scan.worst, m);
    }
  }
  if (!options.tighten || !options.bound) return out;
  // Longer blocks usually give a much smaller factor (δ_k decays geometrically while A_k grows
  // slowly); every k with δ_k < 1 gives a sound bound, so keep the smallest.
  const Graph& g = automaton.graph;
  // Each path costs a product and a δ, ~n³ each for the largest state size n: the scans stop at
  // 2^16 paths of bicubic patches (n = 16) and shrink with n³ (a degree-64 Bézier, n = 65: ~1,000
  // paths, not 2^16 × 65³ flops, which took 12 s).
  double n = 1;
  for (const StateId s : states) n = std::max(n, static_cast<double>(g[s].size));
  const double max_paths = std::max(1.0, 65536 * std::pow(16 / std::max(n, 16.0), 3));
  std::vector<double> paths(num_vertices(g), 1.0), next_paths(paths.size());
  for (int k = 1; k <= out.m; ++k) {
    for (const StateId s : states) {
      next_paths[s] = 0;
      for (auto [b, e] = out_edges(s, g); b != e; ++b) next_paths[s] += paths[target(*b, g)];
    }
    std::swap(paths, next_paths);
  }
  for (int k = out.m + 1; k <= options.max_length; ++k) {
    double total = 0;
    for (const StateId s : states) {
      next_paths[s] = 0;
      for (auto [b, e] = out_edges(s, g); b != e; ++b) next_paths[s] += paths[target(*b, g)];
      total += next_paths[s];
    }
    std::swap(paths, next_paths);
    if (total > max_paths) break;  // the scan would cost more than the levels it saves
    PathScan scan(automaton, k, true, bounds_for(k));
    if (!scan.run(states) || !(scan.worst < 1)) continue;
    const double radius = (1 + scan.A) / (2 * (1 - scan.worst));
    const bool improves = radius < 0.95 * out.radius;
    if (radius < out.radius) {
      out.radius = radius;
      out.radius_length = k;
    }
    if (!improves) break;
  }
  return out;
}

}  // namespace

Contraction contraction(const Automaton& automaton, const ContractionOptions& options) {
  return check_contraction(automaton, options, nullptr);
}

Contraction contraction(const Automaton& automaton, const ContractionOptions& options,
                        FailingPaths& failing) {
  return check_contraction(automaton, options, &failing);
}

Eigen::RowVectorXd fixed_point(const Automaton& automaton, StateId state, std::span<const int> word) {
  validate(automaton);
  const Graph& g = automaton.graph;
  if (state >= num_vertices(g))
    throw InvalidInput("state " + std::to_string(state) + " does not exist (the automaton has " +
                       std::to_string(num_vertices(g)) + " states)");
  const std::string context = "the fixed point of the word " + detail::word_text(word) + " from " +
                              detail::state_label(automaton, state);
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(g[state].size, g[state].size);
  StateId s = state;
  for (std::size_t k = 0; k < word.size(); ++k) {
    const auto degree = out_degree(s, g);
    if (word[k] < 0 || static_cast<std::size_t>(word[k]) >= degree)
      throw InvalidInput(context + ": child index " + std::to_string(word[k]) + " at position " +
                         std::to_string(k) + " but " + detail::state_label(automaton, s) + " has " +
                         std::to_string(degree) + " children");
    const auto e = out_edge(g, s, static_cast<std::size_t>(word[k]));
    P = (g[e].matrix * P).eval();
    s = target(e, g);
  }
  if (s != state)
    throw InvalidInput(context + ": the word ends at " + detail::state_label(automaton, s) +
                       ", not where it started, so it has no fixed point");
  return unit_fixed_point(P, context);
}

namespace {

/// Per reachable state s, the functional λ_s of the address c(s)^∞ (child c(s) repeated, c chosen
/// per state): follows the chosen children until a state repeats, takes the fixed point of the
/// cycle product and propagates it back along the chain (λ_s = λ_child·M).
template <class Child>
std::vector<Eigen::RowVectorXd> chain_functionals(const Automaton& automaton, Child child_of,
                                                  const std::string& what) {
  const Graph& g = automaton.graph;
  const auto n = num_vertices(g);
  std::vector<Eigen::RowVectorXd> F(n);
  std::vector<char> done(n, 0);
  const auto next = [&](StateId s) { return out_edge(g, s, child_of(s)); };
  std::vector<std::ptrdiff_t> pos(n, -1);  // position of a state on the current chain
  for (const StateId s0 : reachable_states(automaton)) {
    if (done[s0]) continue;
    // Follow the chain until a known state or a repetition.
    std::vector<StateId> path;
    StateId v = s0;
    while (!done[v] && pos[v] < 0) {
      pos[v] = static_cast<std::ptrdiff_t>(path.size());
      path.push_back(v);
      v = target(next(v), g);
    }
    for (const StateId p : path) pos[p] = -1;
    std::ptrdiff_t skip = -1;
    if (!done[v]) {
      // v = path[c] starts a cycle: its functional is the fixed point of the cycle product.
      const auto c = static_cast<std::ptrdiff_t>(std::find(path.begin(), path.end(), v) - path.begin());
      Eigen::MatrixXd P = Eigen::MatrixXd::Identity(g[v].size, g[v].size);
      std::vector<int> word;
      for (auto k = static_cast<std::size_t>(c); k < path.size(); ++k) {
        P = (g[next(path[k])].matrix * P).eval();
        word.push_back(static_cast<int>(child_of(path[k])));
      }
      F[v] = unit_fixed_point(P, what + " functional: the cycle " + detail::word_text(word) + " from " +
                                     detail::state_label(automaton, v));
      done[v] = 1;
      skip = c;
    }
    // Back along the chain: the point of s is the point of its chosen child, λ_s·N = λ_child·(M·N).
    for (auto k = static_cast<std::ptrdiff_t>(path.size()) - 1; k >= 0; --k) {
      if (k == skip) continue;
      const auto e = next(path[static_cast<std::size_t>(k)]);
      F[path[static_cast<std::size_t>(k)]] = F[target(e, g)] * g[e].matrix;
      done[path[static_cast<std::size_t>(k)]] = 1;
    }
  }
  return F;
}

}  // namespace

EndFunctionals end_functionals(const Automaton& automaton) {
  validate(automaton);
  const Graph& g = automaton.graph;
  return EndFunctionals{chain_functionals(
                            automaton, [](StateId) { return std::size_t{0}; }, "start"),
                        chain_functionals(
                            automaton, [&](StateId s) { return out_degree(s, g) - 1; }, "end")};
}

std::vector<Eigen::RowVectorXd> repeated_child_functionals(const Automaton& automaton, int child) {
  validate(automaton);
  const Graph& g = automaton.graph;
  for (const StateId s : reachable_states(automaton))
    if (child < 0 || static_cast<std::size_t>(child) >= out_degree(s, g))
      throw InvalidInput("child " + std::to_string(child) +
                         " does not exist: " + detail::state_label(automaton, s) + " has " +
                         std::to_string(out_degree(s, g)) + " children");
  return detail::repeated_child_functionals_unchecked(automaton, child);
}

std::vector<Eigen::RowVectorXd> detail::repeated_child_functionals_unchecked(const Automaton& automaton,
                                                                             int child) {
  return chain_functionals(
      automaton, [&](StateId) { return static_cast<std::size_t>(child); }, "child-" + std::to_string(child));
}

std::vector<std::complex<double>> eigenvalues(const Eigen::MatrixXd& M) {
  if (M.rows() != M.cols())
    throw InvalidInput("a " + std::to_string(M.rows()) + " by " + std::to_string(M.cols()) +
                       " matrix has no eigenvalues: it is not square");
  if (M.rows() == 0) return {};
  if (!M.allFinite()) throw InvalidInput("a matrix entry is not finite: it has no eigenvalues");
  // Solved on M / max|M_ij| and scaled back: entries of 1e300 overflowed inside the QR iteration,
  // which then did not converge (corner-cutting a=1e300).
  const double scale = M.cwiseAbs().maxCoeff();
  if (scale == 0) return std::vector<std::complex<double>>(static_cast<std::size_t>(M.rows()));
  Eigen::EigenSolver<Eigen::MatrixXd> solver(M / scale, false);
  if (solver.info() != Eigen::Success)
    throw InvalidInput("the eigenvalues of a " + std::to_string(M.rows()) + " by " +
                       std::to_string(M.cols()) + " matrix (entries up to " + number_text(scale, 6) +
                       ") did not converge in the QR iteration; check the matrices for extreme entries");
  std::vector<std::complex<double>> out(solver.eigenvalues().begin(), solver.eigenvalues().end());
  for (auto& z : out) z *= scale;
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    if (std::abs(a) != std::abs(b)) return std::abs(a) > std::abs(b);
    if (a.real() != b.real()) return a.real() > b.real();
    return a.imag() > b.imag();
  });
  return out;
}

std::vector<TransitionSpectrum> spectra(const Automaton& automaton) {
  validate(automaton);
  const Graph& g = automaton.graph;
  std::vector<TransitionSpectrum> out;
  for (const StateId s : reachable_states(automaton)) {
    int child = 0;
    for (auto [b, e] = out_edges(s, g); b != e; ++b, ++child) {
      TransitionSpectrum t;
      t.from = s;
      t.to = target(*b, g);
      t.child = child;
      t.label = g[*b].label;
      if (g[*b].matrix.rows() == g[*b].matrix.cols()) t.eigenvalues = eigenvalues(g[*b].matrix);
      out.push_back(std::move(t));
    }
  }
  return out;
}

}  // namespace cifs::ifs
