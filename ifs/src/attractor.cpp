// SPDX-License-Identifier: MIT
// cifs — leaves to a depth or a tolerance, and attractor points through stencil tables.
#include "cifs/ifs/attractor.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/memory.hpp"
#include "walk.hpp"

namespace cifs::ifs {

using automata::Automaton;
using automata::Graph;
using automata::StateId;

/// Depth from which a piece without a Cartesian bound is refused rather than subdivided further.
constexpr int kUnboundedDepth = 32;

Points cartesian(const Points& homogeneous) {
  const Eigen::Index c = homogeneous.cols();
  if (c < 2)
    throw InvalidInput("cartesian: homogeneous rows need at least 2 columns (w·x, w), got " +
                       std::to_string(c));
  Points out(homogeneous.rows(), c - 1);
  for (Eigen::Index i = 0; i < homogeneous.rows(); ++i) {
    const double w = homogeneous(i, c - 1);
    if (w == 0)
      throw InvalidInput("cartesian: row " + std::to_string(i) + " has weight 0 (a point at infinity)");
    out.row(i) = homogeneous.row(i).head(c - 1) / w;
  }
  return out;
}

void for_each_leaf(const Automaton& automaton, std::span<const Points> nets, int depth,
                   const LeafCallback& callback) {
  validate(automaton);
  detail::check_nets(automaton, nets, "for_each_leaf");
  if (depth < 0) throw InvalidInput("for_each_leaf: depth is " + std::to_string(depth) + ", must be ≥ 0");
  detail::depth_first(automaton, nets, depth,
                      [&](std::size_t i, StateId s, const Points& net, int d, std::span<const int> word) {
                        if (d < depth) return true;
                        callback(Leaf{i, s, net, d, word});
                        return false;
                      });
}

ToleranceResult for_each_leaf_to_tolerance(const Automaton& automaton, std::span<const Points> nets,
                                           const ToleranceOptions& options,
                                           const ToleranceCallback& callback) {
  validate(automaton);
  detail::check_nets(automaton, nets, "for_each_leaf_to_tolerance");
  if (!(options.epsilon > 0))
    throw InvalidInput("tolerance " + number_text(options.epsilon, 6) + " is not a positive number");
  if (options.max_depth < 0)
    throw InvalidInput("maximum depth " + std::to_string(options.max_depth) + " is negative");
  ToleranceResult result;
  result.contraction = contraction(automaton, ContractionOptions{options.max_length});
  if (options.homogeneous && nets.front().cols() < 2)
    throw InvalidInput("rational nets need at least 2 columns (w·x, w)");
  const PieceBounds bounds(automaton, result.contraction, options.homogeneous);
  detail::depth_first(
      automaton, nets, options.max_depth,
      [&](std::size_t i, StateId s, const Points& net, int d, std::span<const int> word) {
        const PieceBound b = bounds(s, net);
        // A missing bound (homogeneous rows whose weight is not bounded away from 0)
        // may appear near the root and vanish deeper, where the nets are small; one
        // that persists would expand every branch to max_depth (2^max_depth leaves).
        if (std::isnan(b.diameter) || (std::isinf(b.diameter) && d >= kUnboundedDepth))
          throw InvalidInput("the piece of state " + std::to_string(s) +
                             " has no Cartesian size bound at depth " + std::to_string(d) +
                             (options.homogeneous ? " (its weights come near 0); evaluate to a depth instead"
                                                  : " (its size overflows a double); scale the shape down"));
        const bool converged = b.diameter < options.epsilon;
        if (!converged && d < options.max_depth) return true;
        ++result.leaves;
        if (!converged) ++result.unconverged;
        result.deepest = std::max(result.deepest, d);
        callback(ToleranceLeaf{Leaf{i, s, net, d, word}, b.radius, converged, b.diameter});
        return false;
      });
  return result;
}

namespace {

constexpr std::size_t kSaturated = std::numeric_limits<std::size_t>::max();

std::size_t add_sat(std::size_t a, std::size_t b) noexcept {
  return a > kSaturated - b ? kSaturated : a + b;
}
std::size_t mul_sat(std::size_t a, std::size_t b) noexcept {
  return (a != 0 && b > kSaturated / a) ? kSaturated : a * b;
}

/// Node counts c_k(s) (paths of k transitions from s) for k = 0 … depth, by state; only the
/// levels k ≤ keep are returned (index k), the last one computed is `depth` and returned apart.
struct Counts {
  std::vector<std::vector<std::size_t>> low;  // low[k][s], k ≤ keep
  std::vector<std::size_t> at_depth;          // c_depth(s)
};

Counts node_counts(const Automaton& automaton, int depth, int keep) {
  const Graph& g = automaton.graph;
  const auto n = boost::num_vertices(g);
  const auto states = reachable_states(automaton);
  Counts out;
  std::vector<std::size_t> cur(n, 0), nxt(n, 0);
  for (const StateId s : states) cur[s] = 1;
  for (int k = 0;; ++k) {
    if (k <= keep) out.low.push_back(cur);
    if (k == depth) break;
    for (const StateId s : states) {
      std::size_t c = 0;
      for (auto [b, e] = boost::out_edges(s, g); b != e; ++b) c = add_sat(c, cur[boost::target(*b, g)]);
      nxt[s] = c;
    }
    std::swap(cur, nxt);
  }
  out.at_depth = std::move(cur);
  return out;
}

std::size_t total_count(const Automaton& automaton, const std::vector<std::size_t>& at_depth, bool closed) {
  std::size_t count = closed ? 0 : 1;
  for (const auto& init : automaton.initial) count = add_sat(count, at_depth[init.state]);
  return count;
}

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace

std::size_t attractor_point_count(const Automaton& automaton, int depth, bool closed) {
  validate(automaton);
  if (depth < 0)
    throw InvalidInput("attractor_point_count: depth is " + std::to_string(depth) + ", must be ≥ 0");
  const auto count = total_count(automaton, node_counts(automaton, depth, 0).at_depth, closed);
  if (count == kSaturated)
    throw InvalidInput("attractor_point_count: depth " + std::to_string(depth) +
                       " gives more points than fit in size_t");
  return count;
}

Points attractor_points(const Automaton& automaton, std::span<const Points> nets, int depth,
                        const PointsOptions& options) {
  validate(automaton);
  detail::check_nets(automaton, nets, "attractor_points");
  if (depth < 0) throw InvalidInput("attractor_points: depth is " + std::to_string(depth) + ", must be ≥ 0");
  const Graph& g = automaton.graph;
  const auto n = boost::num_vertices(g);
  const auto states = reachable_states(automaton);
  const int max_L = std::clamp(options.max_table_depth, 0, depth);
  const Counts counts = node_counts(automaton, depth, max_L);

  // Refuse before any work: the output is allocated once, exactly.
  const auto cols = static_cast<std::size_t>(nets[0].cols());
  const std::size_t count = total_count(automaton, counts.at_depth, options.closed);
  const std::size_t bytes = mul_sat(mul_sat(count, cols), sizeof(double));
  if (bytes > options.max_bytes) {
    std::ostringstream msg;
    msg << "attractor_points: depth " << depth << " gives ";
    if (count == kSaturated)
      msg << "more points than fit in size_t";
    else
      msg << count << " points of " << cols << " coordinates ("
          << static_cast<double>(bytes) / static_cast<double>(std::size_t{1} << 30) << " GiB)";
    msg << ", more than the limit of "
        << static_cast<double>(options.max_bytes) / static_cast<double>(std::size_t{1} << 30)
        << " GiB (PointsOptions::max_bytes); lower the depth or raise the limit";
    throw InvalidInput(msg.str());
  }

  // Table depth L: the tables (and, while building, the previous level) stay below half the
  // output, so that peak memory is ≤ 1.5× the output; L = 0 (one functional per state) always.
  const auto table_size = [&](int L) {
    std::size_t t = 0;
    for (const StateId s : states)
      t = add_sat(t,
                  mul_sat(counts.low[static_cast<std::size_t>(L)][s], static_cast<std::size_t>(g[s].size)));
    return t;
  };
  const std::size_t budget = count * cols / 2;
  int L = max_L;
  while (L > 0 && add_sat(table_size(L), table_size(L - 1)) > budget) --L;

  // Stencil tables F_s (`c_L(s) by size(s)`): row j is the start functional of the j-th depth-L
  // descendant of s composed with the path's matrices, so F_s·N are their start points in order.
  // Level 0 is the start functional itself; level ℓ stacks F_t^(ℓ−1)·M_e over the children e.
  const EndFunctionals functionals = end_functionals(automaton);
  std::vector<RowMatrix> table(n), next(n);
  for (const StateId s : states) table[s] = functionals.start[s];
  for (int l = 1; l <= L; ++l) {
    for (const StateId s : states) {
      RowMatrix& F = next[s];
      F.resize(static_cast<Eigen::Index>(counts.low[static_cast<std::size_t>(l)][s]), g[s].size);
      Eigen::Index row = 0;
      for (auto [b, e] = boost::out_edges(s, g); b != e; ++b) {
        const RowMatrix& child = table[boost::target(*b, g)];
        F.middleRows(row, child.rows()).noalias() = child * g[*b].matrix;
        row += child.rows();
      }
    }
    std::swap(table, next);
    for (auto& F : next) F.resize(0, 0);  // free the previous level
  }

  // Emit: the nodes at depth K − L write their c_L(s) points with one product each.
  Points out(static_cast<Eigen::Index>(count), static_cast<Eigen::Index>(cols));
  advise_huge_pages(out.data(), static_cast<std::size_t>(out.size()) * sizeof(double));
  double* cursor = out.data();
  detail::depth_first(automaton, nets, depth - L,
                      [&](std::size_t, StateId s, const Points& net, int d, std::span<const int>) {
                        if (d < depth - L) return true;
                        detail::emit(table[s].data(), table[s].rows(), table[s].cols(), net, cursor);
                        cursor += table[s].rows() * static_cast<Eigen::Index>(cols);
                        return false;
                      });
  if (!options.closed) {
    // The end of the very last node is the end of the last root (end functionals propagate).
    const StateId last = automaton.initial.back().state;
    out.row(out.rows() - 1) = functionals.end[last] * nets.back();
  }
  return out;
}

}  // namespace cifs::ifs
