// SPDX-License-Identifier: MIT
// cifs — attractors of a controlled IFS: leaves to a depth or to a tolerance (streamed, depth
// first), attractor points in curve order through precomposed stencil tables.
//
// Nets: one per `automaton.initial` entry, `size(initial[i].state) by cols`, all with the same
// `cols`. Coordinates are opaque rows: rational curves pass homogeneous rows `(w·x, w)` and call
// `cartesian` on the result.
#pragma once

#include <cstddef>
#include <functional>
#include <span>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

/// `#P by (dim+1)` homogeneous rows `(w·x, w)` → `#P by dim` Cartesian rows `x`. Throws
/// InvalidInput for fewer than 2 columns or a zero weight.
Points cartesian(const Eigen::Ref<const Points>& homogeneous);

/// A node of the subdivision tree handed to callbacks. `net` is `size(state) by cols`; `word`
/// holds the child indices (out-edge positions) from the root, `depth` of them. The references
/// are valid during the callback only.
struct Leaf {
  std::size_t initial;  // index into automaton.initial (and nets)
  automata::StateId state;
  const Points& net;
  int depth;
  std::span<const int> word;
};

using LeafCallback = std::function<void(const Leaf&)>;

/// Visits every node at `depth` (≥ 0) in order — initial entries in order, children in out-edge
/// order — depth first, keeping one net per level: memory O(depth · net), never a whole level.
void for_each_leaf(const automata::Automaton& automaton, std::span<const Points> nets, int depth,
                   const LeafCallback& callback);

struct ToleranceOptions {
  /// Target diameter of each attractor piece, in the units of the nets' rows (absolute; for
  /// homogeneous rows it bounds the homogeneous piece unless `homogeneous` is set).
  double epsilon = 1e-6;
  /// Branches stop here even when not converged (reported).
  int max_depth = 64;
  /// For the contractivity check (ContractionOptions::max_length).
  int max_length = 8;
  /// Rows are homogeneous `(w·x, w)` and epsilon, radius and diameter are Cartesian (PieceBounds).
  bool homogeneous = false;
  /// epsilon bounds the distance of every point of a piece to its chord — the segment between the
  /// piece's end points (end_functionals) — instead of its diameter (PieceBounds::chord_deviation).
  /// The polyline through the leaves' end points then holds every attractor point within epsilon,
  /// and, when the pieces are connected (curves), lies within epsilon of the attractor: a proven
  /// chordal (Hausdorff) deviation, with far fewer leaves than a piece size on smooth curves.
  bool chordal = false;
};

/// A leaf of the tolerance traversal. Every attractor point below it lies within `radius` of
/// `leaf.net.row(0)` (of its Cartesian image with `homogeneous`), any two of them within
/// `diameter` (PieceBounds), and with `chordal` within `deviation` of its chord; `converged` when
/// `diameter < epsilon` (`deviation < epsilon`), otherwise the branch stopped at `max_depth`.
struct ToleranceLeaf {
  Leaf leaf;
  double radius;
  bool converged;
  double diameter;
  double deviation = 0;  // chordal only
};

using ToleranceCallback = std::function<void(const ToleranceLeaf&)>;

struct ToleranceResult {
  Contraction contraction;
  std::size_t leaves = 0;
  std::size_t unconverged = 0;  // leaves cut by max_depth
  int deepest = 0;              // largest leaf depth
};

/// Depth-first traversal that stops a branch as soon as its whole attractor piece is known to have
/// diameter < epsilon (with `chordal`: to lie within epsilon of its chord): by PieceBounds, the hull of the
/// net for states whose paths carry only non-negative matrices, else `2·radius·diam(N)` with `radius` from
/// `contraction` (sound also for matrices with negative entries). Throws InvalidInput for epsilon ≤ 0, a
/// negative max_depth or a system that is not contractive.
ToleranceResult for_each_leaf_to_tolerance(const automata::Automaton& automaton, std::span<const Points> nets,
                                           const ToleranceOptions& options,
                                           const ToleranceCallback& callback);

/// An estimate of the size of for_each_leaf_to_tolerance, made in a bounded time before it, so
/// that a tolerance whose sample would take hours or fill the memory is refused with its figure.
struct ToleranceEstimate {
  double leaves = 0;   // the leaves at epsilon: exact when `exact`, else extrapolated (may be +inf)
  bool exact = false;  // the traversal at epsilon has at most `budget` leaves (then counted)
};

/// Counts the leaves of the traversal at the tolerances ε·2^k, k = K, K − 1, …, from one above
/// every root's piece bound (one leaf per root) down to ε, stopping at the first count above
/// `budget` (the work is about 2·budget leaves). When ε itself is reached the count is exact;
/// otherwise the leaves grow by a factor g per halving of the tolerance (g = 2^d for pieces of
/// dimension d: 2 on curves, 4 on surfaces), g taken from the last three counts within the budget
/// (the mean growth of two halvings) and extrapolated over the k + 1 halvings left. Throws as
/// for_each_leaf_to_tolerance.
ToleranceEstimate estimate_tolerance_leaves(const automata::Automaton& automaton,
                                            std::span<const Points> nets, const ToleranceOptions& options,
                                            std::size_t budget = 1 << 16);

struct PointsOptions {
  /// Closed shapes: the end of the last piece equals the start of the first, so it is omitted.
  bool closed = false;
  /// attractor_points: refuse (before any work) an output larger than this many bytes.
  std::size_t max_bytes = std::size_t{1} << 30;
  /// Depth L of the precomposed stencil tables (lowered automatically so that tables stay below
  /// half of the output and below 2^21 entries).
  int max_table_depth = 8;
  /// for_each_attractor_chunk: points per chunk (more only when one stencil table has more rows).
  std::size_t chunk_points = std::size_t{1} << 16;
};

/// Number of points attractor_points returns: the number of depth-`depth` nodes (from the
/// out-degrees) plus 1 unless closed. Throws InvalidInput on overflow or a negative depth.
std::size_t attractor_point_count(const automata::Automaton& automaton, int depth, bool closed = false);

/// Attractor points to depth K in curve order (`count by cols`): the start point of every node at
/// depth K (initial entries in order, children in out-edge order), plus the end point of the very
/// last one unless `closed`. Pieces are assumed to join (the end of initial i is the start of
/// initial i + 1), so junctions are not repeated. For a binary automaton of one initial entry the
/// points are those of parameters j/2^K, j = 0 … 2^K.
///
/// Uses stencil tables: for every state s the start functionals of its depth-L descendants as a
/// `c_L(s) by size(s)` matrix F_s, so each node at depth K − L emits its c_L(s) points with one
/// product F_s·N. The output is allocated once; peak memory stays ≤ 1.5× the output (plus a
/// constant). Throws InvalidInput when the output would exceed `options.max_bytes`.
Points attractor_points(const automata::Automaton& automaton, std::span<const Points> nets, int depth,
                        const PointsOptions& options = {});
/// The same into `out`, whose storage is reused when it already has the size: repeated calls of one
/// size fault its pages in once (fresh storage is advised for huge pages). `out` must not be one of
/// the nets. A refusal (InvalidInput) leaves it unchanged.
void attractor_points(const automata::Automaton& automaton, std::span<const Points> nets, int depth,
                      Points& out, const PointsOptions& options = {});

/// Consecutive rows of attractor points (`rows by cols`); valid during the call only.
using PointsChunkCallback = std::function<void(const Eigen::Ref<const Points>& rows)>;

/// The attractor points of depth K as linear functionals of the initial nets, built once from the
/// topology (an automaton and a depth) and applied to any nets of that automaton, as many times as
/// wanted (animations, parameter sweeps, several net sets side by side) — OpenSubdiv's
/// `Far::StencilTable` for controlled IFS. It holds its own copy of the automaton, the stencil
/// tables F_s of depth L (`c_L(s) by size(s)`, row j the start functional of the j-th depth-L
/// descendant of s composed with the path's matrices) and the end functional of the last root:
/// applying it walks the tree to depth K − L (one net product per node) and emits each node's
/// c_L(s) points as F_s·N. Building does every check and product that depends on the automaton
/// alone (validation, counts, end functionals, the tables), so applying costs the output's
/// multiply-adds and little more. Same points, bit for bit, as attractor_points with the same L.
struct StencilTable {
  automata::Automaton automaton;
  int depth = 0;        // K
  int table_depth = 0;  // L ≤ K
  bool closed = false;
  std::size_t points = 0;  // rows of every application (attractor_point_count)
  // F_s by state; empty for the states of no depth-(K − L) node (the walk never reads them)
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> tables;
  Eigen::RowVectorXd end;     // end functional of the last root (empty when closed)
  Eigen::Index max_rows = 0;  // largest c_L(s)
};

struct StencilOptions {
  /// The end of the last piece is the start of the first: no end point (PointsOptions::closed).
  bool closed = false;
  /// Largest table depth L (lowered to the depth K, and until the tables fit in max_entries).
  int max_table_depth = 8;
  /// Doubles the tables may hold (and, while building, the previous level besides): the largest
  /// L ≤ max_table_depth within it is taken, L = 0 (one functional per state) always.
  std::size_t max_entries = std::size_t{1} << 21;
};

/// Builds the table of `automaton` at depth K. Throws InvalidInput for an invalid automaton, a
/// negative depth or more points than fit in size_t.
StencilTable stencil_table(const automata::Automaton& automaton, int depth,
                           const StencilOptions& options = {});

/// `table.points by cols` points of the nets (one per initial entry of the table's automaton, each
/// `size(state) by cols`, any common cols: several net sets side by side give their points side by
/// side) into `out`, whose storage is reused when it already has the size (it must not be one of
/// the nets). Throws InvalidInput for nets that do not fit or a table that is not one
/// stencil_table built (its fields edited), leaving `out` unchanged.
/// An output above `max_bytes` is refused before any work.
void apply_table(const StencilTable& table, std::span<const Points> nets, Points& out,
                 std::size_t max_bytes = std::size_t{1} << 30);
Points apply_table(const StencilTable& table, std::span<const Points> nets,
                   std::size_t max_bytes = std::size_t{1} << 30);

/// apply_table without holding the output: the same points in chunks of at most `chunk_points` rows (or
/// one table's rows, when larger). Returns table.points.
std::size_t apply_table_in_chunks(const StencilTable& table, std::span<const Points> nets,
                                  std::size_t chunk_points, const PointsChunkCallback& callback);

/// attractor_points without holding the output: the same points, bit for bit and in the same order,
/// handed to `callback` in chunks of at most `options.chunk_points` rows (or one stencil table's
/// rows, when larger). Memory is the chunk, the tables and one net per level, whatever the depth;
/// `max_bytes` does not apply. Returns the number of points (attractor_point_count). Throws as
/// attractor_points, and for more points than fit in size_t.
std::size_t for_each_attractor_chunk(const automata::Automaton& automaton, std::span<const Points> nets,
                                     int depth, const PointsOptions& options,
                                     const PointsChunkCallback& callback);

}  // namespace cifs::ifs
