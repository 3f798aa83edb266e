// SPDX-License-Identifier: MIT
// cifs — the chaos game of a controlled IFS (automaton + initial nets) rendered as a density image
// through a camera, multi-threaded and identical for any thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include "cifs/automata/automaton.hpp"
#include "cifs/render/camera.hpp"
#include "cifs/render/image.hpp"
#include "cifs/render/partial.hpp"
#include "cifs/render/raster.hpp"
#include "cifs/types.hpp"

namespace cifs::render {

/// Samples per chunk: the unit of determinism of chaos_density.
inline constexpr std::uint64_t kDensityChunk = std::uint64_t{1} << 16;

struct ChaosDensityOptions {
  /// Points drawn (each one independent, see chaos_density); below 2³² in each part (uint32 counts).
  std::uint64_t samples = 1'000'000;
  std::uint64_t seed = 1;
  /// Worker threads; 0 uses every core. The image does not depend on it.
  unsigned threads = 0;
  /// Depth of the sampled nodes; 0 picks the smallest depth at which every attractor piece is
  /// provably within `pixel_tolerance` pixels of its start point on screen (the deepest leaf of
  /// ifs::for_each_leaf_to_tolerance), capped at 64 — or, when that search would visit more leaves
  /// than `samples` (at least 2^12, at most 2^20), the deeper global bound of ifs::depth_for_tolerance.
  int depth = 0;
  double pixel_tolerance = 0.25;
  /// Nets hold homogeneous rows (w·x, w): points are divided by the last column. Needs an explicit
  /// `depth` (the automatic bound is for Cartesian nets).
  bool rational = false;
  /// R G B where points landed.
  Rgb color{1, 1, 1};
  /// Draw only this part's chunks (chunk c belongs to part c mod count): a distributed render whose
  /// parts' layers combine (combine_shares) into the single-process image.
  Part part;
  /// Called after every chunk with (samples done, samples of this part), serialised, from the
  /// workers (a ProgressBar fits).
  std::function<void(std::uint64_t, std::uint64_t)> progress;
};

struct ChaosDensityResult {
  std::uint64_t samples = 0;
  /// Points off screen or in front of the near plane (not in the density).
  std::uint64_t outside = 0;
  /// Depth used (chosen or given).
  int depth = 0;
};

/// Chaos game on a controlled IFS into the `density` channel of `image` (added to it), through
/// `camera` (nets: one per initial entry, `size(state) by 2|3`, or one more column when rational).
///
/// Each sample is an independent random descent: an initial entry drawn uniformly, then `depth`
/// children each drawn uniformly among the out-edges, and the start point `start[s]·N` of the node
/// reached (an exact attractor point; ifs::end_functionals). The node is drawn with probability
/// (1/#initial)·Π 1/out-degree, the same measure as ifs::chaos_game's walk, and its start point lies
/// within the node's piece, so the density is that measure binned, up to `pixel_tolerance`. The
/// point is computed backwards, r ← r·M from the leaf's start functional to the root, one
/// vector–matrix product per level.
///
/// Pixels with hits get: density += hits, A = 1, R G B = color, Z = depth of the nearest point and
/// `state` = the state reached by its last transition (between equally near points: the one drawn
/// last, by sample index). Points behind the image's Z are dropped.
///
/// Determinism: samples are cut into chunks of kDensityChunk; chunk c draws from its own
/// stream (seed, c) of cifs::Random; workers keep private counts, depths and states that
/// are merged by integer sums and by (depth, sample index), so a seed gives the same image for any
/// number of threads.
/// Throws InvalidInput for an invalid automaton or nets (ifs::validate), a system that is not
/// contractive (auto depth), ≥ 2³² samples in this part, depth outside 0 … 64, rational without depth, or an
/// image of another size than the camera.
ChaosDensityResult chaos_density(Image& image, const Camera& camera, const automata::Automaton& automaton,
                                 std::span<const Points> nets, const ChaosDensityOptions& options = {});

/// The same chaos game, its hits kept in `layer` (made the image's size) instead of composited:
/// `composite(image, layer, options.color)` then gives chaos_density's image. With options.part,
/// the hits of that part's chunks only (one process's share of a distributed render). `image` is
/// read for its depths (points behind its Z are dropped) and prepared as by chaos_density.
ChaosDensityResult chaos_density_layer(DensityLayer& layer, Image& image, const Camera& camera,
                                       const automata::Automaton& automaton, std::span<const Points> nets,
                                       const ChaosDensityOptions& options = {});

}  // namespace cifs::render
