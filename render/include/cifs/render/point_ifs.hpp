// SPDX-License-Identifier: MIT
// cifs — classic 2-D affine IFS (Barnsley's fern, Sierpinski's triangle, Koch's curve) and a fast,
// thread-count-independent chaos game into a histogram.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "cifs/ifs/affine.hpp"
#include "cifs/render/part.hpp"
#include "cifs/types.hpp"

namespace cifs::render {

// The maps and the named IFS live in ifs/affine.hpp (the CIFS framework builds their automata).
using ifs::AffineMap;
using ifs::barnsley_fern;
using ifs::koch_curve;
using ifs::sierpinski_triangle;

/// Closed axis-aligned window of the plane; the histogram's row 0 is at y_max (images are y down).
/// Pixel (col, row) covers [x_min + col·Δx, x_min + (col+1)·Δx) × (y_max − (row+1)·Δy, y_max − row·Δy];
/// points on the right or bottom edge of the window fall into the last column or row.
struct Bounds {
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
};

/// Bounding box of `points` chaos-game points (serial, fixed seed), widened by `margin` times its
/// size on every side: a framing helper, not a proof that the whole attractor is inside. Throws
/// InvalidInput for invalid maps, a negative margin or points ≥ 2^32.
Bounds estimate_bounds(std::span<const AffineMap> maps, double margin = 0.02, std::uint64_t points = 100000);

/// Points per chunk: the unit of determinism (see chaos_game_histogram).
inline constexpr std::uint64_t kChaosChunk = std::uint64_t{1} << 20;

struct ChaosHistogramOptions {
  /// Points binned (after burn-in); below 2³² in each part, so that no count can overflow.
  std::uint64_t samples = 10'000'000;
  std::uint64_t seed = 1;
  /// Worker threads; 0 uses std::thread::hardware_concurrency().
  unsigned threads = 1;
  std::size_t width = 1024;
  std::size_t height = 1024;
  Bounds bounds;
  /// Points dropped at the start of every chunk. Each chunk starts at the fixed point of the first
  /// map, which lies on the attractor, so 0 is exact; raise it only for a custom start. At most
  /// kChaosChunk (InvalidInput otherwise).
  std::uint64_t burn_in = 0;
  /// Run only this part's chunks (chunk c belongs to part c mod count): the parts' histograms sum
  /// to the single-process one (a distributed render).
  Part part;
  /// Called after every chunk with (points done, points of this part), serialised under a mutex,
  /// from the worker threads. Keep it cheap (a ProgressBar is).
  std::function<void(std::uint64_t, std::uint64_t)> progress;
};

struct Histogram {
  std::size_t width = 0;
  std::size_t height = 0;
  Bounds bounds;
  /// Hits per pixel, row-major, `height by width`, row 0 at bounds.y_max.
  std::vector<std::uint32_t> counts;
  /// Points generated and points that fell outside the bounds (not in counts).
  std::uint64_t samples = 0;
  std::uint64_t outside = 0;
};

/// The chaos game: x_{n+1} = w_k(x_n) with map k drawn with its probability, every point binned.
/// Determinism: the samples are cut into chunks of kChaosChunk points; chunk i runs its own
/// stream (seed, i) of cifs::Random (cifs/random.hpp) and starts at the fixed point of the
/// first map; threads take chunks dynamically into private histograms that are summed at the end.
/// Integer sums do not depend on the order, so a seed gives the same histogram for any number of
/// threads. Maps are drawn from an alias table (one 64-bit draw per point: 32 bits pick a column,
/// 32 bits the coin), so the cost does not depend on the number of maps.
/// Throws InvalidInput for no maps, non-finite coefficients, negative or all-zero probabilities, a
/// map whose linear part is not a contraction (spectral norm ≥ 1), an empty image, bounds with
/// x_max ≤ x_min or y_max ≤ y_min, or ≥ 2³² points in this part.
Histogram chaos_game_histogram(std::span<const AffineMap> maps, const ChaosHistogramOptions& options);

/// The deterministic invariant measure at depth k (Hutchinson): every word of k maps carries the
/// product of its maps' (normalised) probabilities, placed at the image of the measure's
/// barycentre x̄ = Σ p_i·w_i(x̄) under the word (the piece's own centre of mass), binned on the
/// histogram grid. Returns `height·width` masses (row 0 at y_max)
/// summing to the mass inside the bounds. Its resolution is the size of the depth-k pieces of the
/// attractor. Cost: (#maps)^depth points; throws InvalidInput beyond 2²⁸ points.
std::vector<double> hutchinson_measure(std::span<const AffineMap> maps, unsigned depth, std::size_t width,
                                       std::size_t height, const Bounds& bounds);

/// The points that hutchinson_measure bins, in the order of its walk: the image of the measure's barycentre
/// under every word of `depth` maps of non-zero probability, with the word's mass (the product of its maps'
/// normalised probabilities) and the map applied last (the top-level piece w_map(A) that holds the point;
/// 0 at depth 0). What cifs view draws of a classic IFS. Throws InvalidInput as hutchinson_measure, and
/// before any work when (#maps)^depth exceeds `max_points`.
struct HutchinsonPoints {
  Points points;                   // n by 2
  std::vector<double> mass;        // per point, summing to 1
  std::vector<std::uint32_t> map;  // per point
};
HutchinsonPoints hutchinson_points(std::span<const AffineMap> maps, unsigned depth, std::size_t max_points);

}  // namespace cifs::render
