// SPDX-License-Identifier: MIT
// cifs — private helpers of the ifs module: input checks and the depth-first walk over the
// subdivision tree that every traversal shares.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/cpu.hpp"
#include "cifs/row_combination.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs::detail {

using automata::Automaton;
using automata::Graph;
using automata::StateId;

/// "state 3" or "state 3 (uniform)" when the state is named.
std::string state_label(const Automaton& automaton, StateId state);

/// "0 1 1" for a word of child indices; "(empty)" when empty.
std::string word_text(std::span<const int> word);

/// C = A·B (C neither A nor B), the doubles of `C.noalias() = A * B`: with AVX where the CPU has it and A's
/// rows are a multiple of 4 (the 16 × 16 products of a surface's contractivity check and constraint
/// residuals, which cifs view makes for every edit of a perturbation), else by Eigen.
void multiply(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, Eigen::MatrixXd& C);

/// C = A·B for a net B of at most 4 columns (C neither A nor B), the doubles of `C.noalias() = A * B`: the
/// child nets of every walk (depth_first), whose 16 × 16 by 16 × 3 products took Eigen's blocked product,
/// ~4,400 instructions each (a depth-7 mesh of the hills walks 22,000 nodes with every edit).
void multiply(const Eigen::MatrixXd& A, const Points& B, Points& C);

/// repeated_child_functionals of an automaton validated already whose reachable states all have the child:
/// the mesh tables check both once for their four corners (a validation reads every matrix, ~4 M
/// instructions for a perturbed bicubic surface's, and an interactive edit meshes a new one every time).
std::vector<Eigen::RowVectorXd> repeated_child_functionals_unchecked(const Automaton& automaton, int child);

/// Depth-first walk over the nodes of the subdivision tree up to `max_depth`, one net per level.
/// `visit(initial, state, net, depth, word)` is called for every node in order (initial entries
/// in order, children in out-edge order) and returns whether to descend below it; nodes at
/// `max_depth` are never descended. The automaton must have been validated (every state has a
/// child and matrices of the right shape).
template <class Visit>
void depth_first(const Automaton& automaton, std::span<const Points> nets, int max_depth, Visit&& visit) {
  const Graph& g = automaton.graph;
  using OutIt = const automata::TransitionId*;
  struct Frame {
    OutIt it, end;
    int child;
  };
  // One net per level; level 0 reads the caller's net directly.
  std::vector<Points> level(static_cast<std::size_t>(max_depth) + 1);
  std::vector<Frame> stack;
  stack.reserve(static_cast<std::size_t>(max_depth) + 1);
  std::vector<int> word(static_cast<std::size_t>(max_depth));
  for (std::size_t i = 0; i < automaton.initial.size(); ++i) {
    const StateId root = automaton.initial[i].state;
    if (!visit(i, root, nets[i], 0, std::span<const int>{}) || max_depth == 0) continue;
    auto [b, e] = out_edges(root, g);
    stack.push_back(Frame{b, e, 0});
    while (!stack.empty()) {
      Frame& top = stack.back();
      if (top.it == top.end) {
        stack.pop_back();
        continue;
      }
      const auto edge = *top.it++;
      const int child = top.child++;
      const auto d = stack.size();  // depth of the child
      word[d - 1] = child;
      const Points& parent = d == 1 ? nets[i] : level[d - 1];
      Points& net = level[d];
      multiply(g[edge].matrix, parent, net);
      const StateId state = target(edge, g);
      const bool descend = visit(i, state, static_cast<const Points&>(net), static_cast<int>(d),
                                 std::span<const int>(word.data(), d));
      if (descend && static_cast<int>(d) < max_depth) {
        auto [cb, ce] = out_edges(state, g);
        stack.push_back(Frame{cb, ce, 0});  // no reallocation: reserved max_depth + 1
      }
    }
  }
}

/// out (`rows by C`, row-major, contiguous) = F (`rows by n`, row-major at `F`) · N (`n by C`): the
/// hot loop of the stencil-table routes, n·C multiply-adds per point, the point kept in registers.
/// N_ > 0 fixes n (cubic and quadratic curve nets) so that the k sum unrolls; the sums run in k order
/// either way, so both give the same bits. `Stream` writes with streaming stores (stream_store: an
/// output far larger than the cache is then written without first reading its lines).
template <int C, int N_, bool Stream>
void emit_fixed(const double* f, Eigen::Index rows, Eigen::Index n, const Points& N, double* out) noexcept {
  if constexpr (N_ > 0) n = N_;
  const double* p = N.data();
  for (Eigen::Index r = 0; r < rows; ++r, f += n, out += C) {
    double acc[C] = {};
    for (Eigen::Index k = 0; k < n; ++k)
      for (int c = 0; c < C; ++c) acc[c] += f[k] * p[k * C + c];
    for (int c = 0; c < C; ++c) {
      if constexpr (Stream)
        stream_store(out + c, acc[c]);
      else
        out[c] = acc[c];
    }
  }
}

template <int C, bool Stream>
void emit_cols(const double* f, Eigen::Index rows, Eigen::Index n, const Points& N, double* out) noexcept {
  switch (n) {
    case 3:
      return emit_fixed<C, 3, Stream>(f, rows, n, N, out);
    case 4:
      return emit_fixed<C, 4, Stream>(f, rows, n, N, out);
    default:
      return emit_fixed<C, 0, Stream>(f, rows, n, N, out);
  }
}

template <bool Stream>
void emit_as(const double* f, Eigen::Index rows, Eigen::Index n, const Points& N, double* out) noexcept {
  switch (N.cols()) {
    case 1:
      return emit_cols<1, Stream>(f, rows, n, N, out);
    case 2:
      return emit_cols<2, Stream>(f, rows, n, N, out);
    case 3:
      return emit_cols<3, Stream>(f, rows, n, N, out);
    case 4:
      return emit_cols<4, Stream>(f, rows, n, N, out);
    default: {
      const Eigen::Index C = N.cols();
      for (Eigen::Index r = 0; r < rows; ++r, f += n, out += C) {
        for (Eigen::Index c = 0; c < C; ++c) out[c] = 0;
        for (Eigen::Index k = 0; k < n; ++k)
          for (Eigen::Index c = 0; c < C; ++c) out[c] += f[k] * N(k, c);
      }
    }
  }
}

#if defined(CIFS_X86_AVX)
/// emit_as<false> for nets of 3 or 4 columns with AVX: a point's coordinates in one register (the fourth
/// lane idle for 3), each summed over k in order from +0 by a product and an addition — emit_fixed's sums,
/// the same doubles — at a third of its instructions (the vertices of the generic mesh route, ~250 a
/// vertex of a bicubic surface, were half of a mesh of the hills).
void emit_avx(const double* f, Eigen::Index rows, Eigen::Index n, const Points& N, double* out) noexcept;
#endif

/// emit_as<stream>; after streamed writes the caller calls stream_fence.
inline void emit(const double* f, Eigen::Index rows, Eigen::Index n, const Points& N, double* out,
                 bool stream = false) noexcept {
  if (stream) return emit_as<true>(f, rows, n, N, out);
#if defined(CIFS_X86_AVX)
  if ((N.cols() == 3 || N.cols() == 4) && cpu_has_avx()) return emit_avx(f, rows, n, N, out);
#endif
  return emit_as<false>(f, rows, n, N, out);
}

}  // namespace cifs::ifs::detail
