// SPDX-License-Identifier: MIT
// cifs — fractal dimension of attractors: box counting on a point sample (any evaluation), and
// the similarity dimension (Moran; Mauldin–Williams for graph-directed systems) when the maps are
// similarities.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

struct BoxCountingOptions {
  /// Largest diameter of the pieces the sample stands for (same units as the points; 0: unknown).
  /// Scales finer than 2·resolution are not fitted: below it the sample, not the set, is counted.
  double resolution = 0;
  /// Automatic fine limit: a fitted scale must hold at least this many points per occupied box
  /// on average (N(ε) ≤ #P / points_per_box), so that the sample fills its boxes.
  double points_per_box = 4;
  /// Automatic coarse limit: a fitted scale has at least this many occupied boxes.
  std::size_t min_boxes = 1000;
  /// Fit range given by the user (both ≥ 0, min_level + 2 ≤ max_level); -1: automatic.
  int min_level = -1, max_level = -1;
  /// Finest level counted (reported counts are for levels 0 … this); capped by 62 / dim.
  int levels = 20;
};

/// One scale: level k, box side ε = size·2^-k, N occupied boxes.
struct BoxCount {
  int level = 0;
  double epsilon = 0;
  std::size_t boxes = 0;
};

struct BoxCountingResult {
  double dimension = 0;  // least-squares slope of log N against log(1/ε) over the fit range
  double intercept = 0;  // of that line (natural logarithms)
  int min_level = 0;     // fit range (inclusive)
  int max_level = 0;
  double max_epsilon = 0;  // ε at min_level
  double min_epsilon = 0;  // ε at max_level
  double r_squared = 0;    // coefficient of determination of the fit
  double residual = 0;     // largest |log N − line| over the fit range
  /// Standard error of the slope (least squares over the m fitted levels, m − 2 degrees of freedom).
  double standard_error = 0;
  /// Largest |local slope − dimension| over the pairs of consecutive levels of the fit range
  /// (local slope log₂(N_{k+1}/N_k)): how much the slope drifts across the scales fitted.
  double spread = 0;
  /// max(standard_error, spread): the reported uncertainty of the dimension.
  double uncertainty = 0;
  double size = 0;               // side of the bounding cube of the points (ε at level 0)
  std::vector<BoxCount> counts;  // levels 0 … options.levels, whether fitted or not
};

/// Box-counting dimension of the set sampled by `points` (`#P by dim`, dim ≥ 1, finite).
///
/// Grid: boxes of side ε_k = size·2^-k, where size is the largest side of the bounding box; the
/// grid origin is the lower corner shifted by −γ_d·size per axis (γ_d = 0.1·√(d + 2) mod 1 for
/// axis d, irrational), so that no dyadic grid line meets the self-similar structure of a set
/// built on a dyadic frame (e.g. Sierpinski's corners). Counting: Morton keys of the finest
/// level, sorted once; the boxes of level k are the distinct keys shifted by dim·(levels − k) bits.
///
/// Automatic fit range: the levels k with N(ε_k) ≥ min_boxes, N(ε_k) ≤ #P / points_per_box and
/// ε_k ≥ 2·resolution. Throws InvalidInput for no points, a point that is not finite, all points
/// equal, a user range outside 0 … levels or of fewer than 3 levels, or an automatic range of
/// fewer than 3 levels (the message says to evaluate deeper).
BoxCountingResult box_counting(const Points& points, const BoxCountingOptions& options = {});

/// The number of pieces a tolerance traversal needs at one epsilon (each proven smaller than it).
struct CoverCount {
  double epsilon = 0;
  std::size_t leaves = 0;
};

/// A sample of an attractor whose resolution is proven: every attractor piece it stands for has
/// diameter < `resolution`.
struct ToleranceSample {
  Points points;           // `#P by dim` Cartesian: the start point (end_functionals) of every leaf
  double resolution = 0;   // the epsilon used (Cartesian units)
  int deepest = 0;         // largest leaf depth
  std::size_t leaves = 0;  // = #P
  /// The counts of the search for epsilon (epsilon 0: diam(nets)·2^-j, j = 4, 5, …), coarsest
  /// first, the sample's own last; one entry when epsilon was given.
  std::vector<CoverCount> cover;
};

/// Growth of the proven cover: the slope of log n(ε) against log(1/ε) over counts of a tolerance
/// search. A set covered by n(ε) pieces of diameter < ε meets at most 2^dim·n(ε) boxes of side
/// ε, so the limit of this slope bounds the upper box-counting dimension from above; unlike the
/// box count, it has no boundary term (pieces tile the attractor: a smooth patch gives 2, not
/// the 1.9 its boxes give at 10^6 points).
struct CoverExponent {
  double dimension = 0;  // least-squares slope over the fitted counts
  double spread = 0;     // largest |local slope − dimension| over consecutive fitted counts
  double max_epsilon = 0, min_epsilon = 0;  // fitted range
  int levels = 0;                           // counts fitted
};

/// The finest `levels` counts with at least `min_leaves` leaves (at least 3 of them, else
/// nullopt; counts must be in the order of ToleranceSample::cover).
std::optional<CoverExponent> cover_exponent(std::span<const CoverCount> counts, std::size_t min_leaves = 1000,
                                            int levels = 64);

struct ToleranceSampleOptions {
  /// Cartesian piece diameter; 0: the largest diam(nets)·2^-j (j ≥ 4) whose sample has at most
  /// max_points points (each halving of epsilon is tried on a traversal that counts leaves and
  /// stops at max_points, so the search costs about twice the final traversal).
  double epsilon = 0;
  /// Nets hold homogeneous rows `(w·x, w)` (rational shapes).
  bool homogeneous = false;
  /// Refuse (before allocating the sample) more points than this.
  std::size_t max_points = std::size_t{1} << 21;
  /// Depth cap of the traversal: a branch still unresolved there is refused.
  int max_depth = 64;
  /// How refusals name epsilon (a CLI option, say).
  std::string_view tolerance_name = "tolerance";
  /// The tolerance as its user gave it, for refusals (empty: tolerance_name and epsilon): a relative
  /// piece size is not the absolute epsilon it was scaled to.
  std::string_view tolerance_text = {};
  /// What refusals of a sample above max_points advise (empty: raise the tolerance or the point limit).
  std::string_view limit_hint = {};
};

/// Samples the attractor to a tolerance (for_each_leaf_to_tolerance with PieceBounds): one point
/// per leaf, the attractor point `end_functionals(a).start[state]·net` of its piece, every piece of
/// diameter < epsilon, so every attractor point lies within epsilon of the sample and the sample
/// lies on the attractor. Throws InvalidInput for epsilon < 0 or not finite, a sample above
/// max_points (before allocating it), a branch unresolved at max_depth, and as
/// for_each_leaf_to_tolerance and end_functionals.
ToleranceSample tolerance_sample(const automata::Automaton& automaton, std::span<const Points> nets,
                                 const ToleranceSampleOptions& options = {});

/// A sample of an attractor at one depth, with an estimated (not proven) resolution: the route
/// when no tolerance sample can be had (signed matrices whose proven bound is loose, rational
/// pieces without a Cartesian bound).
struct DepthSample {
  Points points;  // `#P by dim` Cartesian: attractor_points at `depth` (start points, and the end)
  int depth = 0;
  /// Largest Cartesian diameter of the depth-K nets: the size of the pieces if they stay near the
  /// hulls of their nets — an estimate, not a bound (signed matrices let a piece leave its hull).
  /// Infinite when a weight of a rational net is 0.
  double resolution = 0;
};

struct DepthSampleOptions {
  /// Nets hold homogeneous rows `(w·x, w)` (rational shapes).
  bool homogeneous = false;
  /// The deepest depth whose attractor_point_count is at most this many points.
  std::size_t max_points = std::size_t{1} << 21;
  /// Deepest depth tried (an automaton whose count never grows stops here).
  int max_depth = 40;
};

/// Attractor points at the deepest depth K ≤ max_depth with attractor_point_count(K) ≤ max_points
/// (counted from the out-degrees, nothing allocated before), and the estimated resolution (one
/// for_each_leaf at K). Throws InvalidInput when even depth 0 has more than max_points points, and
/// as attractor_points.
DepthSample depth_sample(const automata::Automaton& automaton, std::span<const Points> nets,
                         const DepthSampleOptions& options = {});

/// A map of a graph-directed system: from state `from` into state `to`, contracting by `ratio`.
struct SimilarityEdge {
  automata::StateId from = 0, to = 0;
  double ratio = 0;
};

/// Mauldin–Williams dimension (1988) of a graph-directed system of similarities on `states`
/// states: the s ≥ 0 with spectral radius ρ(A(s)) = 1, A(s)_{uv} = Σ_{e: u→v} ratio_e^s. On every
/// strongly connected component ρ decreases strictly in s; over the whole graph ρ is the largest
/// of the components' radii, so the s found is that of the component of largest dimension (the
/// dimension of the union of the attractors, under the open set condition). Bisection on s to
/// machine precision. 0 when ρ(A(0)) ≤ 1 (no branching: points). Throws InvalidInput for a ratio
/// that is not finite and > 0, a state out of range, a graph without cycle, or cycles that do not
/// contract (ρ(A(s)) ≥ 1 for s up to 1000).
double mauldin_williams_dimension(std::size_t states, std::span<const SimilarityEdge> edges);

/// Ratio of a similarity x ↦ x·L + b (L `dim by dim`, any dim ≥ 1): r with LᵀL = r²I to 1e-12 of
/// r², or -1 when L is not r times an orthogonal matrix.
double similarity_ratio(const Eigen::MatrixXd& L);

/// Similarity (Moran) dimension of a classic planar IFS: the s with Σ r_i^s = 1. Throws
/// InvalidInput for no map, or a map that is not a similarity (names it and gives LᵀL), or a
/// ratio ≥ 1.
double similarity_dimension(std::span<const AffineMap> maps);

/// Similarity dimension of the attractor of a CIFS automaton whose transitions act as
/// similarities: each reachable state gets a reference net (its initial net, else the image net
/// along its first reaching transition, breadth first); a transition e: u → v acts as the affine
/// map f_e with f_e(N_v) = M_e·N_u, which must exist (least squares residual ≤ 1e-12·diam) and be
/// a similarity of ratio r_e. Then the Mauldin–Williams dimension of the graph of the r_e. The
/// individual r_e depend on the reference nets, the dimension does not (another choice conjugates
/// A(s) by a positive diagonal matrix). `nets` as in attractor.hpp (one per initial entry, Cartesian
/// rows). Throws InvalidInput when a reference net does not span its space affinely, a transition
/// is not affine between the reference nets or not a similarity (naming it), and as
/// mauldin_williams_dimension.
double similarity_dimension(const automata::Automaton& automaton, std::span<const Points> nets);

}  // namespace cifs::ifs
