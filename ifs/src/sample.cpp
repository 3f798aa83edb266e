// SPDX-License-Identifier: MIT
// cifs — the sampling API: attractor points to a depth or a proven tolerance.
#include "cifs/ifs/sample.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "walk.hpp"

namespace cifs::ifs {

using automata::Automaton;
using automata::Graph;
using automata::StateId;

namespace {

/// The states of the depth-K nodes in order, one at a time, without nets: a depth-first walk over
/// the automaton's edges that holds one out-edge iterator per level.
class StateWalk {
 public:
  StateWalk(const Automaton& automaton, int depth)
      : g_(automaton.graph), automaton_(automaton), depth_(depth) {
    stack_.reserve(static_cast<std::size_t>(depth) + 1);
  }

  StateId next() {
    for (;;) {
      if (stack_.empty()) {
        const StateId root = automaton_.initial[root_++].state;
        if (depth_ == 0) return root;
        stack_.push_back(out_edges(root, g_));
      }
      auto& [it, end] = stack_.back();
      if (it == end) {
        stack_.pop_back();
        continue;
      }
      const StateId s = target(*it++, g_);
      if (static_cast<int>(stack_.size()) == depth_) return s;
      stack_.push_back(out_edges(s, g_));
    }
  }

 private:
  const Graph& g_;
  const Automaton& automaton_;
  int depth_;
  std::size_t root_ = 0;
  std::vector<automata::OutEdges> stack_;  // (next, end) per level
};

[[noreturn]] void refuse(const SampleOptions& o, const std::string& what, std::string_view advice) {
  // Exact below a million, three digits above ("1.07e+09").
  const std::string limit = o.max_points < 1000000 ? std::to_string(o.max_points)
                                                   : number_text(static_cast<double>(o.max_points), 3);
  throw InvalidInput(what + ", above the limit of " + limit +
                     std::string(o.limit_hint.empty() ? advice : o.limit_hint));
}

std::string tolerance_text(const SampleOptions& o) {
  return std::string(o.tolerance_name) + " " + number_text(o.tolerance, 6);
}

ToleranceOptions tolerance_options(const SampleOptions& o) {
  return {
      .epsilon = o.tolerance, .max_depth = o.max_depth, .homogeneous = o.homogeneous, .chordal = o.chordal};
}

/// Tolerance mode: every leaf to `visit`, after an estimate, both against max_points — a traversal
/// that alone could run for hours is refused in bounded time with its figure.
template <class Visit>
ToleranceResult visit_leaves(const Automaton& a, std::span<const Points> nets, const SampleOptions& o,
                             Visit&& visit) {
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw InvalidInput(tolerance_text(o) + " is not a positive number");
  const ToleranceOptions to = tolerance_options(o);
  constexpr std::string_view kAdvice = "; give a larger tolerance";
  // A chordal piece costs its cover's refinement (up to 160 nodes): its estimate counts to 2^12 leaves,
  // not 2^16, so that a refusal stays within a second (--deviation 1e-15 took 2.5 s). Nor beyond
  // max_points + 1: a coarser tolerance's count above max_points already bounds this one's from below.
  const std::size_t budget = std::min(o.chordal ? std::size_t{1} << 12 : std::size_t{1} << 16,
                                      std::max<std::size_t>(o.max_points, 1) + 1);
  if (const ToleranceEstimate est =
          o.estimate ? estimate_tolerance_leaves(a, nets, to, budget) : ToleranceEstimate{};
      !est.exact && est.leaves > static_cast<double>(o.max_points))
    refuse(o,
           tolerance_text(o) +
               (std::isfinite(est.leaves) ? ": about " + number_text(est.leaves, 3)
                                          : std::string(": more than 1e+308")) +
               " points (estimated from coarser tolerances)",
           kAdvice);
  std::size_t n = o.closed ? 0 : 1;  // the end point
  return for_each_leaf_to_tolerance(a, nets, to, [&](const ToleranceLeaf& t) {
    if (!t.converged)
      throw InvalidInput(tolerance_text(o) + ": a piece " +
                         (o.chordal ? "still strays " + number_text(t.deviation, 3) + " from its chord"
                                    : "is still " + number_text(t.diameter, 3) + " wide") +
                         " at depth " + std::to_string(o.max_depth) + "; give a larger tolerance");
    if (++n > o.max_points)
      refuse(o, tolerance_text(o) + " gives more than " + std::to_string(o.max_points) + " points", kAdvice);
    visit(t);
  });
}

void check_input(const Automaton& a, std::span<const Points> nets, const SampleOptions& o) {
  validate(a);
  check_nets(a, nets);
  if (o.homogeneous && nets.front().cols() < 2)
    throw InvalidInput("rational nets need at least 2 columns (w·x, w)");
}

}  // namespace

std::size_t for_each_sample_chunk(const Automaton& automaton, std::span<const Points> nets,
                                  const SampleOptions& o, std::size_t chunk_points,
                                  const SampleCountCallback& count, const SampleChunkCallback& chunk) {
  check_input(automaton, nets, o);
  const auto emit = [&](const Eigen::Ref<const Points>& rows, std::span<const std::uint32_t> states) {
    if (o.homogeneous)
      chunk(cartesian(rows), states);
    else
      chunk(rows, states);
  };
  std::vector<std::uint32_t> states;
  if (o.depth >= 0) {
    const std::size_t n = attractor_point_count(automaton, o.depth, o.closed);
    if (n > o.max_points)
      refuse(o, "depth " + std::to_string(o.depth) + " gives " + std::to_string(n) + " points",
             "; lower the depth");
    count(n, o.depth);
    StateWalk walk(automaton, o.depth);
    std::size_t pieces = n - (o.closed ? 0 : 1), done = 0;
    for_each_attractor_chunk(automaton, nets, o.depth, {.closed = o.closed, .chunk_points = chunk_points},
                             [&](const Eigen::Ref<const Points>& rows) {
                               states.clear();
                               if (o.states)
                                 for (Eigen::Index r = 0; r < rows.rows() && done < pieces; ++r, ++done)
                                   states.push_back(static_cast<std::uint32_t>(walk.next()));
                               emit(rows, states);
                             });
    return n;
  }
  // A first walk counts (count() comes before the chunks), the second emits.
  const ToleranceResult counted = visit_leaves(automaton, nets, o, [](const ToleranceLeaf&) {});
  const std::size_t n = counted.leaves + (o.closed ? 0 : 1);
  count(n, counted.deepest);
  const EndFunctionals ends = end_functionals(automaton);
  Points rows(static_cast<Eigen::Index>(std::clamp<std::size_t>(std::min(chunk_points, n), 1, n)),
              nets.front().cols());
  Eigen::Index used = 0;
  const auto flush = [&] {
    if (used > 0) emit(rows.topRows(used), states);
    used = 0;
    states.clear();
  };
  Point last_end;  // the end of the last leaf closes an open curve
  for_each_leaf_to_tolerance(automaton, nets, tolerance_options(o), [&](const ToleranceLeaf& t) {
    if (used == rows.rows()) flush();
    rows.row(used++) = ends.start[t.leaf.state] * t.leaf.net;
    if (o.states) states.push_back(static_cast<std::uint32_t>(t.leaf.state));
    if (!o.closed) last_end = ends.end[t.leaf.state] * t.leaf.net;
  });
  if (!o.closed) {
    if (used == rows.rows()) flush();
    rows.row(used++) = last_end;
  }
  flush();
  return n;
}

Sample sample_attractor(const Automaton& automaton, std::span<const Points> nets, const SampleOptions& o) {
  Sample out;
  if (o.depth >= 0) {
    Eigen::Index at = 0;
    for_each_sample_chunk(
        automaton, nets, o, std::size_t{1} << 16,
        [&](std::size_t n, int depth) {
          out.depth = depth;
          out.points.resize(static_cast<Eigen::Index>(n), nets.front().cols() - (o.homogeneous ? 1 : 0));
          if (o.states) out.states.reserve(n);
        },
        [&](const Eigen::Ref<const Points>& rows, std::span<const std::uint32_t> states) {
          out.points.middleRows(at, rows.rows()) = rows;
          at += rows.rows();
          out.states.insert(out.states.end(), states.begin(), states.end());
        });
    return out;
  }
  // In memory one walk does: the rows grow (at most max_points of them), no counting walk first.
  // Row-major rows of fixed width grow by realloc (Eigen's conservativeResize), which glibc does
  // with mremap for large buffers: no copy and no second buffer, and pages beyond the rows written
  // are never touched. Homogeneous rows are divided by w as they come (cartesian()'s bits).
  check_input(automaton, nets, o);
  const EndFunctionals ends = end_functionals(automaton);
  const Eigen::Index D = nets.front().cols() - (o.homogeneous ? 1 : 0);
  Points& P = out.points;
  P.resize(0, D);
  Eigen::Index used = 0;
  const auto add = [&](const Point& p) {
    if (used == P.rows()) P.conservativeResize(std::max<Eigen::Index>(1024, 2 * used), D);
    if (!o.homogeneous) {
      P.row(used++) = p;
      return;
    }
    const double w = p(D);
    if (w == 0)
      throw InvalidInput("sample point " + std::to_string(used) +
                         " has weight 0 (a point at infinity); give the shape positive weights");
    P.row(used++) = p.head(D) / w;
  };
  Point last_end;  // the end of the last leaf closes an open curve
  out.depth = visit_leaves(automaton, nets, o, [&](const ToleranceLeaf& t) {
                add(ends.start[t.leaf.state] * t.leaf.net);
                if (o.states) out.states.push_back(static_cast<std::uint32_t>(t.leaf.state));
                if (!o.closed) last_end = ends.end[t.leaf.state] * t.leaf.net;
              }).deepest;
  if (!o.closed) add(last_end);
  P.conservativeResize(used, D);
  return out;
}

int depth_for_tolerance(const Automaton& automaton, std::span<const Points> nets,
                        const ToleranceOptions& options, std::size_t max_leaves) {
  struct OverBudget {};
  std::size_t leaves = 0;
  try {
    return for_each_leaf_to_tolerance(automaton, nets, options,
                                      [&](const ToleranceLeaf&) {
                                        if (++leaves > max_leaves) throw OverBudget{};
                                      })
        .deepest;
  } catch (const OverBudget&) {
  }
  const Contraction c = contraction(automaton, {.max_length = options.max_length});
  double diameter = 0;  // of the largest root net: each piece's bound starts from its own root
  for (const Points& N : nets) diameter = std::max(diameter, ifs::diameter(N));
  const double ratio = options.epsilon / (2 * c.radius * diameter);
  if (!(ratio < 1) || !(c.delta > 0)) return std::min(c.m, options.max_depth);
  const double j = std::ceil(std::log(ratio) / std::log(c.delta));
  return static_cast<int>(std::min(static_cast<double>(options.max_depth), std::max(1.0, j) * c.m));
}

}  // namespace cifs::ifs
