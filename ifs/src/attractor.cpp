// SPDX-License-Identifier: MIT
// cifs — leaves to a depth or a tolerance, and attractor points through stencil tables.
#include "cifs/ifs/attractor.hpp"

#include <algorithm>
#include <cmath>
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

Points cartesian(const Eigen::Ref<const Points>& homogeneous) {
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

ToleranceEstimate estimate_tolerance_leaves(const Automaton& automaton, std::span<const Points> nets,
                                            const ToleranceOptions& options, std::size_t budget) {
  validate(automaton);
  detail::check_nets(automaton, nets, "the tolerance estimate");
  if (!(options.epsilon > 0))
    throw InvalidInput("tolerance " + number_text(options.epsilon, 6) + " is not a positive number");
  const Contraction c = contraction(automaton, ContractionOptions{options.max_length});
  if (options.homogeneous && nets.front().cols() < 2)
    throw InvalidInput("rational nets need at least 2 columns (w·x, w)");
  const PieceBounds bounds(automaton, c, options.homogeneous);
  // Leaves at tolerance e, or budget + 1 as soon as there are more.
  struct Full {};
  const auto count = [&](double e) {
    std::size_t n = 0;
    try {
      detail::depth_first(automaton, nets, options.max_depth,
                          [&](std::size_t, StateId s, const Points& net, int d, std::span<const int>) {
                            if (!(bounds(s, net).diameter < e) && d < options.max_depth) return true;
                            if (++n > budget) throw Full{};
                            return false;
                          });
    } catch (const Full&) {
    }
    return n;
  };
  // Coarsest tolerance of the ladder ε·2^k: above every root's bound (one leaf per root).
  double top = 0;
  for (std::size_t i = 0; i < nets.size(); ++i)
    top = std::max(top, bounds(automaton.initial[i].state, nets[i]).diameter);
  if (!std::isfinite(top)) top = 4 * nets_diameter(nets, options.homogeneous);
  int k = std::isfinite(top) && top > options.epsilon
              ? std::min(static_cast<int>(std::ceil(std::log2(top / options.epsilon))) + 1, 2100)
              : 0;
  // Halve the tolerance while the count stays within the budget; the last three counts give the
  // growth per halving (2^dimension of the pieces: 2 for curves, 4 for surfaces).
  std::vector<double> counts;
  for (; k >= 0; --k) {
    const std::size_t n = count(std::ldexp(options.epsilon, k));
    if (n > budget) break;
    counts.push_back(static_cast<double>(n));
  }
  ToleranceEstimate out;
  out.exact = k < 0;
  if (out.exact) {
    out.leaves = counts.back();
    return out;
  }
  // k + 1 halvings remain from the last count within the budget.
  const double last = counts.empty() ? 1 : counts.back();
  const std::size_t m = counts.size();
  const double growth =
      m >= 3 ? std::sqrt(counts[m - 1] / counts[m - 3]) : static_cast<double>(budget + 1) / last;
  out.leaves = last * std::pow(std::max(growth, 1.0), k + 1);
  return out;
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
    throw InvalidInput("depth " + std::to_string(depth) + " gives more than 2^64 points; lower the depth");
  return count;
}

namespace {

/// Stencil tables F_s (`c_L(s) by size(s)`): row j is the start functional of the j-th depth-L
/// descendant of s composed with the path's matrices, so F_s·N are their start points in order.
struct StencilTables {
  int L = 0;
  std::vector<RowMatrix> table;  // by state
  EndFunctionals functionals;
  std::size_t count = 0;      // points of the whole output
  Eigen::Index max_rows = 0;  // largest c_L(s)
};

/// Double entries the tables may hold besides the output's half: a streamed output keeps its memory
/// bounded by this (and the chunk), whatever the depth. Both routes choose L the same way, so that
/// they give the same bits.
constexpr std::size_t kTableBudget = std::size_t{1} << 21;

/// Validates, counts the points and builds the tables of depth L: the largest L ≤ max_table_depth
/// whose tables (and, while building, the previous level) stay below half the output and below
/// kTableBudget; L = 0 (one functional per state) always. `refuse(count, bytes)` may throw before
/// any work.
template <class Refuse>
StencilTables stencil_tables(const Automaton& automaton, std::span<const Points> nets, int depth,
                             const PointsOptions& options, const char* who, Refuse&& refuse) {
  validate(automaton);
  detail::check_nets(automaton, nets, who);
  if (depth < 0)
    throw InvalidInput(std::string(who) + ": depth is " + std::to_string(depth) + ", must be ≥ 0");
  const Graph& g = automaton.graph;
  const auto n = boost::num_vertices(g);
  const auto states = reachable_states(automaton);
  const int max_L = std::clamp(options.max_table_depth, 0, depth);
  const Counts counts = node_counts(automaton, depth, max_L);

  StencilTables out;
  const auto cols = static_cast<std::size_t>(nets[0].cols());
  out.count = total_count(automaton, counts.at_depth, options.closed);
  refuse(out.count, mul_sat(mul_sat(out.count, cols), sizeof(double)));

  const auto table_size = [&](int L) {
    std::size_t t = 0;
    for (const StateId s : states)
      t = add_sat(t,
                  mul_sat(counts.low[static_cast<std::size_t>(L)][s], static_cast<std::size_t>(g[s].size)));
    return t;
  };
  const std::size_t budget = std::min(mul_sat(out.count, cols) / 2, kTableBudget);
  int L = max_L;
  while (L > 0 && add_sat(table_size(L), table_size(L - 1)) > budget) --L;
  out.L = L;

  // Level 0 is the start functional itself; level ℓ stacks F_t^(ℓ−1)·M_e over the children e.
  out.functionals = end_functionals(automaton);
  std::vector<RowMatrix> next(n);
  out.table.resize(n);
  for (const StateId s : states) out.table[s] = out.functionals.start[s];
  for (int l = 1; l <= L; ++l) {
    for (const StateId s : states) {
      RowMatrix& F = next[s];
      F.resize(static_cast<Eigen::Index>(counts.low[static_cast<std::size_t>(l)][s]), g[s].size);
      Eigen::Index row = 0;
      for (auto [b, e] = boost::out_edges(s, g); b != e; ++b) {
        const RowMatrix& child = out.table[boost::target(*b, g)];
        F.middleRows(row, child.rows()).noalias() = child * g[*b].matrix;
        row += child.rows();
      }
    }
    std::swap(out.table, next);
    for (auto& F : next) F.resize(0, 0);  // free the previous level
  }
  for (const StateId s : states) out.max_rows = std::max(out.max_rows, out.table[s].rows());
  return out;
}

/// The emit walk shared by both routes: the nodes at depth K − L write their c_L(s) points with one
/// product each, at `place(rows)` (a pointer to room for that many rows); then the end point of the
/// very last node unless closed (the end of the last root: end functionals propagate).
template <class Place>
void emit_points(const Automaton& automaton, std::span<const Points> nets, int depth, const StencilTables& t,
                 bool closed, Place&& place) {
  detail::depth_first(automaton, nets, depth - t.L,
                      [&](std::size_t, StateId s, const Points& net, int d, std::span<const int>) {
                        if (d < depth - t.L) return true;
                        const RowMatrix& F = t.table[s];
                        detail::emit(F.data(), F.rows(), F.cols(), net, place(F.rows()));
                        return false;
                      });
  if (!closed) {
    const StateId last = automaton.initial.back().state;
    Eigen::Map<Point>(place(1), nets.back().cols()) = t.functionals.end[last] * nets.back();
  }
}

}  // namespace

void attractor_points(const Automaton& automaton, std::span<const Points> nets, int depth, Points& out,
                      const PointsOptions& options) {
  // Refuse before any work: the output is allocated once, exactly.
  const auto cols = nets.empty() ? 0 : nets[0].cols();
  const StencilTables t = stencil_tables(
      automaton, nets, depth, options, "attractor_points", [&](std::size_t count, std::size_t bytes) {
        if (bytes <= options.max_bytes) return;
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
      });
  resize_huge(out, static_cast<Eigen::Index>(t.count), cols);
  double* cursor = out.data();
  emit_points(automaton, nets, depth, t, options.closed, [&](Eigen::Index rows) {
    double* at = cursor;
    cursor += rows * cols;
    return at;
  });
}

Points attractor_points(const Automaton& automaton, std::span<const Points> nets, int depth,
                        const PointsOptions& options) {
  Points out;
  attractor_points(automaton, nets, depth, out, options);
  return out;
}

std::size_t for_each_attractor_chunk(const Automaton& automaton, std::span<const Points> nets, int depth,
                                     const PointsOptions& options, const PointsChunkCallback& callback) {
  const StencilTables t = stencil_tables(
      automaton, nets, depth, options, "for_each_attractor_chunk", [&](std::size_t count, std::size_t) {
        if (count == kSaturated)
          throw InvalidInput("for_each_attractor_chunk: depth " + std::to_string(depth) +
                             " gives more points than fit in size_t");
      });
  const Eigen::Index cols = nets[0].cols();
  const auto capacity = std::max({static_cast<Eigen::Index>(std::max<std::size_t>(options.chunk_points, 1)),
                                  t.max_rows, Eigen::Index{1}});
  Points chunk(capacity, cols);
  Eigen::Index used = 0;
  const auto flush = [&] {
    if (used > 0) callback(chunk.topRows(used));
    used = 0;
  };
  emit_points(automaton, nets, depth, t, options.closed, [&](Eigen::Index rows) {
    if (used + rows > capacity) flush();
    double* at = chunk.data() + used * cols;
    used += rows;
    return at;
  });
  flush();
  return t.count;
}

}  // namespace cifs::ifs
