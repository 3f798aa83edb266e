// SPDX-License-Identifier: MIT
// cifs — leaves to a depth or a tolerance, and attractor points through stencil tables.
#include "cifs/ifs/attractor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/memory.hpp"
#include "saturating.hpp"
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
    throw InvalidInput("homogeneous points need at least 2 columns (w·x, w), got " + std::to_string(c));
  Points out(homogeneous.rows(), c - 1);
  for (Eigen::Index i = 0; i < homogeneous.rows(); ++i) {
    const double w = homogeneous(i, c - 1);
    if (w == 0)
      throw InvalidInput("homogeneous point " + std::to_string(i) +
                         " has weight 0 (a point at infinity): it has no Cartesian coordinates");
    out.row(i) = homogeneous.row(i).head(c - 1) / w;
  }
  return out;
}

namespace {

/// "the tolerance -1 is not a positive number" (a NaN or infinity named as such, not printed).
std::string tolerance_refusal(double epsilon) {
  if (!std::isfinite(epsilon)) return "the tolerance is not a finite number";
  return "the tolerance " + number_text(epsilon, 6) + " is not a positive number";
}

/// What for_each_leaf_to_tolerance compares with epsilon: the bound on the piece's diameter, or
/// with `chordal` a bound on its distance to the chord between its end points (end_functionals,
/// Cartesian with homogeneous rows; a weight 0 at an end leaves the piece unbounded).
///
/// The chordal bound covers the piece by the pieces of its descendants and takes the largest
/// PieceBounds::chord_deviation over the cover, refining only the descendants whose bound is not
/// yet below epsilon. One net's hull is not enough: a B-spline net reaches beyond the piece's
/// ends by half a control leg, a first-order overshoot, while the piece itself strays from its
/// chord to second order; the first and last descendants near the ends shrink it, the others are
/// accepted at once.
class PieceMeasure {
 public:
  struct Value {
    PieceBound bound;
    double deviation = 0;  // chordal only
    double size = 0;       // compared with epsilon
  };

  PieceMeasure(const Automaton& automaton, const Contraction& c, const ToleranceOptions& o)
      : automaton_(automaton),
        bounds_(automaton, c, o.homogeneous),
        chordal_(o.chordal),
        homogeneous_(o.homogeneous) {
    if (chordal_) ends_ = end_functionals(automaton);
  }

  Value operator()(StateId s, const Points& net, double epsilon) const {
    const PieceBound bound = bounds_(s, net);
    if (!chordal_) return {.bound = bound, .size = bound.diameter};
    const Point a = ends_.start[s] * net, b = ends_.end[s] * net;
    double deviation = std::numeric_limits<double>::infinity();
    if (!homogeneous_) {
      deviation = cover_deviation(s, net, a, b, epsilon);
    } else if (const Eigen::Index c = net.cols() - 1; a(c) != 0 && b(c) != 0) {
      deviation = cover_deviation(s, net, a.head(c) / a(c), b.head(c) / b(c), epsilon);
    }
    return {.bound = bound, .deviation = deviation, .size = deviation};
  }

 private:
  /// Nodes of the cover refined per piece before the bound is reported as not below epsilon (the
  /// traversal then splits the piece: sound either way, only the number of chords changes).
  static constexpr int kCoverNodes = 160;

  /// The largest bound over the cover (below epsilon), or the first bound at or above epsilon
  /// that the refinement budget leaves.
  double cover_deviation(StateId s, const Points& net, const Point& a, const Point& b, double epsilon) const {
    const Graph& g = automaton_.graph;
    double worst = 0;
    int nodes = 0;
    std::vector<std::pair<StateId, Points>> stack{{s, net}};
    while (!stack.empty()) {
      auto [t, N] = std::move(stack.back());
      stack.pop_back();
      const double d = bounds_.chord_deviation(t, N, a, b);
      if (d < epsilon) {
        worst = std::max(worst, d);
        continue;
      }
      if (!(d < std::numeric_limits<double>::infinity()) || ++nodes > kCoverNodes) return d;
      for (auto [e, end] = out_edges(t, g); e != end; ++e)
        stack.emplace_back(target(*e, g), g[*e].matrix * N);
    }
    return worst;
  }

  const Automaton& automaton_;
  PieceBounds bounds_;
  EndFunctionals ends_;
  bool chordal_;
  bool homogeneous_;
};

}  // namespace

void for_each_leaf(const Automaton& automaton, std::span<const Points> nets, int depth,
                   const LeafCallback& callback) {
  validate(automaton);
  check_nets(automaton, nets);
  if (depth < 0) throw InvalidInput("the depth " + std::to_string(depth) + " is negative; give a depth ≥ 0");
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
  check_nets(automaton, nets);
  if (!(options.epsilon > 0)) throw InvalidInput(tolerance_refusal(options.epsilon));
  if (options.max_depth < 0)
    throw InvalidInput("maximum depth " + std::to_string(options.max_depth) + " is negative");
  ToleranceResult result;
  result.contraction = contraction(automaton, ContractionOptions{.max_length = options.max_length});
  if (options.homogeneous && nets.front().cols() < 2)
    throw InvalidInput("rational nets need at least 2 columns (w·x, w)");
  const PieceMeasure measure(automaton, result.contraction, options);
  detail::depth_first(
      automaton, nets, options.max_depth,
      [&](std::size_t i, StateId s, const Points& net, int d, std::span<const int> word) {
        const PieceMeasure::Value v = measure(s, net, options.epsilon);
        const PieceBound& b = v.bound;
        // A missing bound (homogeneous rows whose weight is not bounded away from 0)
        // may appear near the root and vanish deeper, where the nets are small; one
        // that persists would expand every branch to max_depth (2^max_depth leaves).
        if (std::isnan(v.size) || (std::isinf(v.size) && d >= kUnboundedDepth))
          throw InvalidInput("the piece of state " + std::to_string(s) +
                             " has no Cartesian size bound at depth " + std::to_string(d) +
                             (options.homogeneous ? " (its weights come near 0); evaluate to a depth instead"
                                                  : " (its size overflows a double); scale the shape down"));
        const bool converged = v.size < options.epsilon;
        if (!converged && d < options.max_depth) return true;
        ++result.leaves;
        if (!converged) ++result.unconverged;
        result.deepest = std::max(result.deepest, d);
        callback(ToleranceLeaf{Leaf{i, s, net, d, word}, b.radius, converged, b.diameter, v.deviation});
        return false;
      });
  return result;
}

ToleranceEstimate estimate_tolerance_leaves(const Automaton& automaton, std::span<const Points> nets,
                                            const ToleranceOptions& options, std::size_t budget) {
  validate(automaton);
  check_nets(automaton, nets);
  if (!(options.epsilon > 0)) throw InvalidInput(tolerance_refusal(options.epsilon));
  const Contraction c = contraction(automaton, ContractionOptions{.max_length = options.max_length});
  if (options.homogeneous && nets.front().cols() < 2)
    throw InvalidInput("rational nets need at least 2 columns (w·x, w)");
  const PieceMeasure measure(automaton, c, options);
  // Leaves at tolerance e, or budget + 1 as soon as there are more.
  struct Full {};
  const auto count = [&](double e) {
    std::size_t n = 0;
    try {
      detail::depth_first(automaton, nets, options.max_depth,
                          [&](std::size_t, StateId s, const Points& net, int d, std::span<const int>) {
                            if (!(measure(s, net, e).size < e) && d < options.max_depth) return true;
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
    top = std::max(top, measure(automaton.initial[i].state, nets[i], options.epsilon).size);
  if (!std::isfinite(top)) top = 4 * nets_diameter(nets, options.homogeneous);
  // log2(top) − log2(ε), not log2(top / ε): the quotient overflows for a subnormal ε (3e-308, and
  // casting its infinite log to int was undefined: the ladder was skipped).
  int k = std::isfinite(top) && top > options.epsilon
              ? std::min(static_cast<int>(std::ceil(std::log2(top) - std::log2(options.epsilon))) + 1, 2100)
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

/// Node counts c_k(s) (paths of k transitions from s) for k = 0 … depth, by state; only the
/// levels k ≤ keep are returned (index k), the last one computed is `depth` and returned apart.
struct Counts {
  std::vector<std::vector<std::size_t>> low;  // low[k][s], k ≤ keep
  std::vector<std::size_t> at_depth;          // c_depth(s)
};

Counts node_counts(const Automaton& automaton, int depth, int keep) {
  const Graph& g = automaton.graph;
  const auto n = num_vertices(g);
  const auto states = reachable_states(automaton);
  Counts out;
  std::vector<std::size_t> cur(n, 0), nxt(n, 0);
  for (const StateId s : states) cur[s] = 1;
  for (int k = 0;; ++k) {
    if (k <= keep) out.low.push_back(cur);
    if (k == depth) break;
    for (const StateId s : states) {
      std::size_t c = 0;
      for (auto [b, e] = out_edges(s, g); b != e; ++b) c = add_sat(c, cur[target(*b, g)]);
      nxt[s] = c;
    }
    // Saturated (a knot automaton by depth 64) or stationary: every deeper level is the same, so a
    // depth of 10^9 is counted, and refused, at once.
    if (std::ranges::equal(cur, nxt)) {
      while (static_cast<int>(out.low.size()) <= std::min(keep, depth)) out.low.push_back(cur);
      break;
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
  if (depth < 0) throw InvalidInput("the depth " + std::to_string(depth) + " is negative; give a depth ≥ 0");
  const auto count = total_count(automaton, node_counts(automaton, depth, 0).at_depth, closed);
  if (count == kSaturated)
    throw InvalidInput("depth " + std::to_string(depth) + " gives more than 2^64 points; lower the depth");
  return count;
}

namespace {

/// Double entries the tables may hold besides the output's half: a streamed output keeps its memory
/// bounded by this (and the chunk), whatever the depth. Both attractor routes choose L the same way,
/// so that they give the same bits.
constexpr std::size_t kTableBudget = std::size_t{1} << 21;

/// out (`child.rows() by M.cols()`, row-major) = child·M, each entry summed in k order. The rows are
/// many and M is small (a transition, 4 by 4 for cubics): a row at a time against M's rows, which
/// vectorises over the columns; Eigen's general product packed the whole child table per call. K and
/// N > 0 fix M's shape (square transitions of quadratics and cubics), which keeps M in registers.
template <int K, int N>
void stack_rows_fixed(const RowMatrix& child, const RowMatrix& Mr, double* __restrict out) noexcept {
  const Eigen::Index k_end = K > 0 ? K : Mr.rows(), n = N > 0 ? N : Mr.cols();
  const double* m = Mr.data();
  for (Eigen::Index i = 0; i < child.rows(); ++i, out += n) {
    const double* c = child.data() + i * k_end;
    for (Eigen::Index j = 0; j < n; ++j) out[j] = c[0] * m[j];
    for (Eigen::Index k = 1; k < k_end; ++k)
      for (Eigen::Index j = 0; j < n; ++j) out[j] += c[k] * m[k * n + j];
  }
}

void stack_rows(const RowMatrix& child, const Eigen::MatrixXd& M, double* out) {
  const RowMatrix Mr = M;  // rows of M contiguous
  if (M.rows() == 3 && M.cols() == 3) return stack_rows_fixed<3, 3>(child, Mr, out);
  if (M.rows() == 4 && M.cols() == 4) return stack_rows_fixed<4, 4>(child, Mr, out);
  switch (M.cols()) {
    case 3:
      return stack_rows_fixed<0, 3>(child, Mr, out);
    case 4:
      return stack_rows_fixed<0, 4>(child, Mr, out);
    default:
      return stack_rows_fixed<0, 0>(child, Mr, out);
  }
}

/// The functional of the address (last child)^∞ from state s, the end point of its piece: the fixed
/// point of the last-child cycle the chain from s enters, carried back along the chain (λ_v = λ_child·M).
Eigen::RowVectorXd last_child_functional(const Automaton& automaton, StateId s) {
  const Graph& g = automaton.graph;
  std::vector<StateId> path;
  std::vector<automata::TransitionId> steps;
  std::vector<std::ptrdiff_t> at(num_vertices(g), -1);
  for (StateId v = s; at[v] < 0;) {
    at[v] = static_cast<std::ptrdiff_t>(path.size());
    path.push_back(v);
    const auto [b, e] = out_edges(v, g);
    steps.push_back(*(e - 1));
    v = target(steps.back(), g);
  }
  const StateId entry = target(steps.back(), g);  // the cycle starts where the chain came back
  const auto c = static_cast<std::size_t>(at[entry]);
  std::vector<int> word;
  for (std::size_t k = c; k < path.size(); ++k) word.push_back(static_cast<int>(out_degree(path[k], g)) - 1);
  Eigen::RowVectorXd F = fixed_point(automaton, entry, word);
  for (std::size_t k = c; k-- > 0;) F = (F * g[steps[k]].matrix).eval();
  return F;
}

/// at[k][s]: whether a node at depth `from + k` of the tree (from the initial entries) is in state s,
/// for k = 0 … to − from. Level ℓ of the tables is needed only for the states at depth K − ℓ: the
/// walk emits at depth K − L, and a level-ℓ table is stacked from its children's, one level deeper.
std::vector<std::vector<char>> states_at_depths(const Automaton& automaton, int from, int to) {
  const Graph& g = automaton.graph;
  const auto n = num_vertices(g);
  std::vector<char> cur(n, 0), nxt(n, 0);
  for (const auto& init : automaton.initial) cur[init.state] = 1;
  std::vector<std::vector<char>> out;
  for (int d = 0; d <= to; ++d) {
    if (d >= from) out.push_back(cur);
    if (d == to) break;
    std::fill(nxt.begin(), nxt.end(), 0);
    for (StateId s = 0; s < n; ++s)
      if (cur[s])
        for (auto [b, e] = out_edges(s, g); b != e; ++b) nxt[target(*b, g)] = 1;
    // A repeated set repeats for ever (as node_counts stops): depth 10^9 is not walked level by level.
    if (nxt == cur) {
      while (static_cast<int>(out.size()) < to - from + 1) out.push_back(cur);
      break;
    }
    std::swap(cur, nxt);
  }
  return out;
}

/// Counts the points and builds the tables of depth L of a validated automaton (without its copy):
/// the largest L ≤ max_table_depth whose tables (and, while building, the previous level) stay
/// within `entries(count)` doubles; L = 0 (one functional per state) always. Only the states of the
/// depth-(K − L) nodes get a table (the others' are empty). `entries` may throw (a refusal) before
/// any work on the tables.
template <class Entries>
StencilTable build_table(const Automaton& automaton, int depth, bool closed, int max_table_depth,
                         Entries&& entries) {
  if (depth < 0) throw InvalidInput("the depth " + std::to_string(depth) + " is negative; give a depth ≥ 0");
  const Graph& g = automaton.graph;
  const auto n = num_vertices(g);
  const int max_L = std::clamp(max_table_depth, 0, depth);
  const Counts counts = node_counts(automaton, depth, max_L);
  // needed[K − d]: the states at depth d, for d = K − max_L … K.
  auto needed = states_at_depths(automaton, depth - max_L, depth);
  std::reverse(needed.begin(), needed.end());  // needed[ℓ]: the states whose level-ℓ table is used

  StencilTable out;
  out.depth = depth;
  out.closed = closed;
  out.points = total_count(automaton, counts.at_depth, closed);
  const std::size_t budget = entries(out.points);

  const auto table_size = [&](int l) {
    const auto level = static_cast<std::size_t>(l);
    std::size_t t = 0;
    for (StateId s = 0; s < n; ++s)
      if (needed[level][s])
        t = add_sat(t, mul_sat(counts.low[level][s], static_cast<std::size_t>(g[s].size)));
    return t;
  };
  int L = max_L;
  while (L > 0 && add_sat(table_size(L), table_size(L - 1)) > budget) --L;
  out.table_depth = L;

  // Level 0 is the start functional itself; level ℓ stacks F_t^(ℓ−1)·M_e over the children e. Of the
  // end functionals only the last root's is needed (end_functionals chains every state's: twice the cycles).
  const std::vector<Eigen::RowVectorXd> start = repeated_child_functionals(automaton, 0);
  if (!closed) out.end = last_child_functional(automaton, automaton.initial.back().state);
  std::vector<RowMatrix> next(n);
  out.tables.resize(n);
  for (StateId s = 0; s < n; ++s)
    if (needed[0][s]) out.tables[s] = start[s];
  for (int l = 1; l <= L; ++l) {
    for (StateId s = 0; s < n; ++s) {
      if (!needed[static_cast<std::size_t>(l)][s]) continue;
      RowMatrix& F = next[s];
      F.resize(static_cast<Eigen::Index>(counts.low[static_cast<std::size_t>(l)][s]), g[s].size);
      Eigen::Index row = 0;
      for (auto [b, e] = out_edges(s, g); b != e; ++b) {
        const RowMatrix& child = out.tables[target(*b, g)];
        stack_rows(child, g[*b].matrix, F.data() + row * F.cols());
        row += child.rows();
      }
    }
    std::swap(out.tables, next);
    for (auto& F : next) F.resize(0, 0);  // free the previous level
  }
  for (const auto& F : out.tables) out.max_rows = std::max(out.max_rows, F.rows());
  return out;
}

/// The emit walk shared by every route: the nodes at depth K − L write their c_L(s) points with one
/// product each, at `place(rows)` (a pointer to room for that many rows); then the end point of the
/// very last node unless closed (the end of the last root: end functionals propagate).
template <class Place>
void emit_points(const Automaton& automaton, std::span<const Points> nets, const StencilTable& t, bool stream,
                 Place&& place) {
  const int walk_depth = t.depth - t.table_depth;
  detail::depth_first(automaton, nets, walk_depth,
                      [&](std::size_t, StateId s, const Points& net, int d, std::span<const int>) {
                        if (d < walk_depth) return true;
                        const RowMatrix& F = t.tables[s];
                        detail::emit(F.data(), F.rows(), F.cols(), net, place(F.rows()), stream);
                        return false;
                      });
  if (!t.closed) Eigen::Map<Point>(place(1), nets.back().cols()) = t.end * nets.back();
}

/// Every point into `out` (`t.points by cols`, storage reused when it has the size). A reused output
/// larger than the cache is written with streaming stores (fresh pages are zeroed by the kernel on
/// the first write, in the cache: streaming over them is slower).
void emit_into(const Automaton& automaton, std::span<const Points> nets, const StencilTable& t, Points& out) {
  const auto cols = nets[0].cols();
  const auto rows = static_cast<Eigen::Index>(t.points);
  const bool stream = out.rows() == rows && out.cols() == cols &&
                      static_cast<std::size_t>(out.size()) * sizeof(double) >= kStreamBytes;
  resize_huge(out, rows, cols);
  double* cursor = out.data();
  emit_points(automaton, nets, t, stream, [&](Eigen::Index n) {
    double* at = cursor;
    cursor += n * cols;
    return at;
  });
  if (stream) stream_fence();
}

/// "depth 20 gives 17825793 points of 3 coordinates (0.4 GiB), more than the limit of 1 GiB (…)".
[[noreturn]] void refuse_output(int depth, std::size_t count, Eigen::Index cols, std::size_t bytes,
                                std::size_t max_bytes) {
  const auto gib = [](std::size_t b) {
    return static_cast<double>(b) / static_cast<double>(std::size_t{1} << 30);
  };
  std::ostringstream msg;
  msg << "depth " << depth << " gives ";
  if (count == kSaturated)
    msg << "more points than fit in size_t";
  else
    msg << count << " points of " << cols << " coordinates (" << gib(bytes) << " GiB)";
  msg << ", more than the limit of " << gib(max_bytes) << " GiB held in memory; lower the depth";
  throw InvalidInput(msg.str());
}

std::size_t output_bytes(std::size_t count, Eigen::Index cols) {
  return mul_sat(mul_sat(count, static_cast<std::size_t>(cols)), sizeof(double));
}

/// Throws unless `t` is a table stencil_table could have built for its automaton (so that a table
/// whose fields were edited cannot write out of bounds) and the nets fit it.
void check_table(const StencilTable& t, std::span<const Points> nets) {
  const Automaton& a = t.automaton;
  validate(a);
  check_nets(a, nets);
  const Graph& g = a.graph;
  bool fits = t.depth >= 0 && t.table_depth >= 0 && t.table_depth <= t.depth &&
              t.tables.size() == num_vertices(g) && (t.closed || t.end.size() == nets.back().rows());
  if (fits) {
    // Every table is empty or of its state's shape, and those of the walk's states are not empty.
    const Counts counts = node_counts(a, t.depth, t.table_depth);
    const std::vector<char> walked = states_at_depths(a, t.depth - t.table_depth, t.depth - t.table_depth)[0];
    fits = t.points == total_count(a, counts.at_depth, t.closed);
    for (StateId s = 0; s < num_vertices(g); ++s) {
      const RowMatrix& F = t.tables[s];
      const bool empty = F.size() == 0 && !walked[s];
      fits = fits && (empty || (F.cols() == g[s].size &&
                                static_cast<std::size_t>(F.rows()) ==
                                    counts.low[static_cast<std::size_t>(t.table_depth)][s] &&
                                F.rows() <= t.max_rows));
    }
  }
  if (!fits) throw InvalidInput("the stencil table does not fit its automaton; build it with stencil_table");
}

}  // namespace

void attractor_points(const Automaton& automaton, std::span<const Points> nets, int depth, Points& out,
                      const PointsOptions& options) {
  validate(automaton);
  check_nets(automaton, nets);
  // Refuse before any work: the output is allocated once, exactly.
  const auto cols = nets[0].cols();
  const StencilTable t =
      build_table(automaton, depth, options.closed, options.max_table_depth, [&](std::size_t count) {
        const std::size_t bytes = output_bytes(count, cols);
        if (bytes > options.max_bytes) refuse_output(depth, count, cols, bytes, options.max_bytes);
        return std::min(mul_sat(count, static_cast<std::size_t>(cols)) / 2, kTableBudget);
      });
  emit_into(automaton, nets, t, out);
}

Points attractor_points(const Automaton& automaton, std::span<const Points> nets, int depth,
                        const PointsOptions& options) {
  Points out;
  attractor_points(automaton, nets, depth, out, options);
  return out;
}

namespace {

/// Chunks of at most `chunk_points` rows (or one table's rows) through `callback`.
std::size_t emit_in_chunks(const Automaton& automaton, std::span<const Points> nets, const StencilTable& t,
                           std::size_t chunk_points, const PointsChunkCallback& callback) {
  const Eigen::Index cols = nets[0].cols();
  const auto capacity = std::max(
      {static_cast<Eigen::Index>(std::max<std::size_t>(chunk_points, 1)), t.max_rows, Eigen::Index{1}});
  Points chunk(capacity, cols);
  Eigen::Index used = 0;
  const auto flush = [&] {
    if (used > 0) callback(chunk.topRows(used));
    used = 0;
  };
  emit_points(automaton, nets, t, false, [&](Eigen::Index rows) {
    if (used + rows > capacity) flush();
    double* at = chunk.data() + used * cols;
    used += rows;
    return at;
  });
  flush();
  return t.points;
}

void refuse_saturated(int depth, std::size_t count) {
  if (count == kSaturated)
    throw InvalidInput("depth " + std::to_string(depth) +
                       " gives more points than fit in size_t; lower the depth");
}

}  // namespace

std::size_t for_each_attractor_chunk(const Automaton& automaton, std::span<const Points> nets, int depth,
                                     const PointsOptions& options, const PointsChunkCallback& callback) {
  validate(automaton);
  check_nets(automaton, nets);
  const auto cols = static_cast<std::size_t>(nets[0].cols());
  const StencilTable t =
      build_table(automaton, depth, options.closed, options.max_table_depth, [&](std::size_t count) {
        refuse_saturated(depth, count);
        return std::min(mul_sat(count, cols) / 2, kTableBudget);
      });
  return emit_in_chunks(automaton, nets, t, options.chunk_points, callback);
}

StencilTable stencil_table(const Automaton& automaton, int depth, const StencilOptions& options) {
  validate(automaton);
  StencilTable t =
      build_table(automaton, depth, options.closed, options.max_table_depth, [&](std::size_t count) {
        refuse_saturated(depth, count);
        return options.max_entries;
      });
  t.automaton = automaton;
  return t;
}

void apply_table(const StencilTable& table, std::span<const Points> nets, Points& out,
                 std::size_t max_bytes) {
  check_table(table, nets);
  const auto cols = nets[0].cols();
  const std::size_t bytes = output_bytes(table.points, cols);
  if (bytes > max_bytes) refuse_output(table.depth, table.points, cols, bytes, max_bytes);
  emit_into(table.automaton, nets, table, out);
}

Points apply_table(const StencilTable& table, std::span<const Points> nets, std::size_t max_bytes) {
  Points out;
  apply_table(table, nets, out, max_bytes);
  return out;
}

std::size_t apply_table_in_chunks(const StencilTable& table, std::span<const Points> nets,
                                  std::size_t chunk_points, const PointsChunkCallback& callback) {
  check_table(table, nets);
  return emit_in_chunks(table.automaton, nets, table, chunk_points, callback);
}

}  // namespace cifs::ifs
