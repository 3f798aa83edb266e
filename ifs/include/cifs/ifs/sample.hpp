// SPDX-License-Identifier: MIT
// cifs — one sampling API: the attractor points of a shape to a depth or to a proven tolerance,
// with the states of their pieces, homogeneous (rational) nets handled once, and the output-size
// guard before any work. The CLI, the experiment runner, dimension and Python call it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

struct SampleOptions {
  /// ≥ 0: every node at this depth (attractor_points). Negative: sample to `tolerance`.
  int depth = -1;
  /// Proven piece size (depth < 0): every leaf's whole attractor piece has a diameter below it
  /// (for_each_leaf_to_tolerance), in the units of the points returned.
  double tolerance = 0;
  /// The tolerance bounds each piece's distance to its chord instead of its diameter
  /// (ToleranceOptions::chordal): the points, in order, are a polyline within the tolerance of the
  /// curve — what CAD calls a chordal deviation.
  bool chordal = false;
  /// Nets hold homogeneous rows `(w·x, w)`: the tolerance bounds Cartesian pieces (PieceBounds) and
  /// the points returned are Cartesian.
  bool homogeneous = false;
  /// No end point: the end of the last piece is the start of the first.
  bool closed = false;
  /// Record the state of the piece that starts at each point (Sample::states).
  bool states = false;
  /// Tolerance: a branch still above the tolerance at this depth is refused.
  int max_depth = 64;
  /// Refuse, before the points are computed, more points than this (in tolerance mode from an
  /// estimate at coarser tolerances, then from the count).
  std::size_t max_points = std::size_t{1} << 27;
  /// Tolerance mode: refuse on the estimate before the walk. Off when the caller has counted the
  /// leaves at this tolerance itself (an extrapolated estimate may overshoot a count within the
  /// limit); the count is still held to max_points during the walk.
  bool estimate = true;
  /// How messages name the tolerance ("tolerance", "--tolerance", "evaluation.tolerance") and what
  /// they add after the limit's figure (where the limit comes from, what to do instead; empty: "; lower
  /// the depth" or "; give a larger tolerance").
  std::string_view tolerance_name = "tolerance";
  std::string_view limit_hint = {};
};

struct Sample {
  Points points;                      // in curve order; Cartesian when homogeneous
  std::vector<std::uint32_t> states;  // with SampleOptions::states: one per piece (no end point)
  int depth = 0;                      // the depth, or the deepest leaf of the tolerance traversal
};

/// The sample: start points of the depth-K nodes or of the tolerance leaves (initial entries in
/// order, children in out-edge order), plus the end point of the last piece unless closed. Throws
/// InvalidInput for more than max_points points (before computing them), a tolerance that is not
/// a positive number, a branch unresolved at max_depth, and as attractor_points and
/// for_each_leaf_to_tolerance.
Sample sample_attractor(const automata::Automaton& automaton, std::span<const Points> nets,
                        const SampleOptions& options);

/// sample_attractor without holding the points: `count(n, depth)` is called once with the number
/// of points and Sample::depth, then `chunk(rows, states)` with consecutive rows (at most `chunk_points`, or
/// one stencil table's rows) and, with SampleOptions::states, the states of the pieces they start (the end
/// point has none). Returns the number of points. `max_points` applies as above.
using SampleCountCallback = std::function<void(std::size_t points, int depth)>;
using SampleChunkCallback =
    std::function<void(const Eigen::Ref<const Points>& rows, std::span<const std::uint32_t> states)>;
std::size_t for_each_sample_chunk(const automata::Automaton& automaton, std::span<const Points> nets,
                                  const SampleOptions& options, std::size_t chunk_points,
                                  const SampleCountCallback& count, const SampleChunkCallback& chunk);

/// The smallest depth at which every piece of the attractor is proven smaller than `epsilon`: the
/// deepest leaf of for_each_leaf_to_tolerance (a bound from each branch's own net). Past
/// `max_leaves` leaves (a surface at a fine tolerance: minutes) the traversal gives way to the
/// global bound, O(1) and deeper: every piece at depth j·m has diameter ≤ 2ρ·δ_m^j·diam(N)
/// (Contraction). Capped at `options.max_depth`. Throws as for_each_leaf_to_tolerance.
int depth_for_tolerance(const automata::Automaton& automaton, std::span<const Points> nets,
                        const ToleranceOptions& options, std::size_t max_leaves = std::size_t{1} << 20);

}  // namespace cifs::ifs
