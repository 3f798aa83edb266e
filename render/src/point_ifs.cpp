// SPDX-License-Identifier: MIT
// cifs — classic affine IFS and the chaos game into a histogram, deterministic for any thread count.
#include "cifs/render/point_ifs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <numbers>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/random.hpp"
#include "parallel.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cifs::render {

namespace {

struct Linear {
  double a, b, c, d, e, f;
};

/// One column of Vose's alias table: keep `self` when the coin is below `threshold` (out of 2³²).
struct Column {
  std::uint64_t threshold;
  std::uint32_t self;
  std::uint32_t alias;
};

/// Validated maps ready for the inner loop.
struct Prepared {
  std::vector<Linear> maps;
  std::vector<double> probability;  // normalised
  std::vector<Column> table;
  double x0 = 0, y0 = 0;  // fixed point of the first map: a point of the attractor
};

std::string where(std::size_t i) {
  return "affine map " + std::to_string(i);
}

Prepared prepare(std::span<const AffineMap> maps) {
  if (maps.empty()) throw InvalidInput("the IFS has no affine map; give at least one");
  if (maps.size() > (std::size_t{1} << 31))
    throw InvalidInput("the IFS has " + std::to_string(maps.size()) + " affine maps, more than 2^31");
  Prepared p;
  double total = 0;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const AffineMap& m = maps[i];
    for (const double v : {m.a, m.b, m.c, m.d, m.e, m.f, m.probability})
      if (!std::isfinite(v)) throw InvalidInput(where(i) + " has a coefficient that is not finite");
    if (m.probability < 0) throw InvalidInput("the probability of " + where(i) + " is negative");
    // Spectral norm of [[a, b], [c, d]]: σ² = (s + √(s² − 4·det²)) / 2 with s the squared
    // Frobenius norm. A map with σ ≥ 1 may throw the walk out of any bounds.
    const double s = m.a * m.a + m.b * m.b + m.c * m.c + m.d * m.d;
    const double det = m.a * m.d - m.b * m.c;
    const double sigma2 = (s + std::sqrt(std::max(0.0, s * s - 4 * det * det))) / 2;
    if (!(sigma2 < 1))
      throw InvalidInput(where(i) + " is not a contraction (spectral norm " +
                         number_text(std::sqrt(sigma2), 6) + "); scale its linear part below 1");
    p.maps.push_back({m.a, m.b, m.c, m.d, m.e, m.f});
    total += m.probability;
  }
  if (!(total > 0))
    throw InvalidInput("the probabilities of the affine maps sum to 0; give one a positive probability");
  for (const AffineMap& m : maps) p.probability.push_back(m.probability / total);

  // Vose's alias method: column i keeps i with probability q_i = n·p_i and gives the rest to a
  // large column. Built once, in a fixed order, so the table (and the images) are reproducible.
  const std::size_t n = maps.size();
  std::vector<double> q(n);
  std::vector<std::uint32_t> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    q[i] = p.probability[i] * static_cast<double>(n);
    (q[i] < 1 ? small : large).push_back(static_cast<std::uint32_t>(i));
  }
  p.table.resize(n);
  constexpr double kTwo32 = 4294967296.0;
  while (!small.empty() && !large.empty()) {
    const std::uint32_t s = small.back(), l = large.back();
    small.pop_back();
    p.table[s] = {static_cast<std::uint64_t>(std::llround(q[s] * kTwo32)), s, l};
    q[l] -= 1 - q[s];
    if (q[l] < 1) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // What remains is 1 up to rounding: keep the column always.
  for (const std::uint32_t i : small) p.table[i] = {std::uint64_t{1} << 32, i, i};
  for (const std::uint32_t i : large) p.table[i] = {std::uint64_t{1} << 32, i, i};

  const Linear& m = p.maps.front();
  // (I − A)·x = t; invertible because A is a contraction.
  const double det = (1 - m.a) * (1 - m.d) - m.b * m.c;
  p.x0 = ((1 - m.d) * m.e + m.b * m.f) / det;
  p.y0 = (m.c * m.e + (1 - m.a) * m.f) / det;
  return p;
}

void check_grid(std::size_t width, std::size_t height, const Bounds& b) {
  if (width == 0 || height == 0)
    throw InvalidInput("the image size " + std::to_string(width) + " by " + std::to_string(height) +
                       " is empty");
  if (width > (std::size_t{1} << 16) || height > (std::size_t{1} << 16))
    throw InvalidInput("the image size " + std::to_string(width) + " by " + std::to_string(height) +
                       " is larger than 65536 pixels on a side");
  if (!(std::isfinite(b.x_min) && std::isfinite(b.x_max) && std::isfinite(b.y_min) &&
        std::isfinite(b.y_max)) ||
      !(b.x_max > b.x_min) || !(b.y_max > b.y_min))
    throw InvalidInput("the image bounds are empty or not finite");
}

/// Pixel addressing shared by the chaos game and the Hutchinson measure, so both bin alike.
struct Grid {
  double x_min, y_max, sx, sy, w, h;
  std::size_t width, height;
  Grid(std::size_t columns, std::size_t rows, const Bounds& b)
      : x_min(b.x_min),
        y_max(b.y_max),
        sx(static_cast<double>(columns) / (b.x_max - b.x_min)),
        sy(static_cast<double>(rows) / (b.y_max - b.y_min)),
        w(static_cast<double>(columns)),
        h(static_cast<double>(rows)),
        width(columns),
        height(rows) {}
  /// Pixel index, or SIZE_MAX outside. The window is closed: points on its right or bottom edge
  /// go to the last column or row (attractors touch their frames: a walk that starts at a vertex
  /// of Sierpinski's triangle sits on y = y_min for a few steps). The comparisons are on doubles,
  /// so no out-of-range float-to-integer conversion can happen.
  std::size_t index(double x, double y) const noexcept {
    const double px = (x - x_min) * sx, py = (y_max - y) * sy;
    if (!(px >= 0 && px <= w && py >= 0 && py <= h)) return SIZE_MAX;
    const std::size_t ix = std::min(static_cast<std::size_t>(px), width - 1);
    const std::size_t iy = std::min(static_cast<std::size_t>(py), height - 1);
    return iy * width + ix;
  }
};

/// One chunk of the walk. The hot loop: one 64-bit draw, an alias lookup, the affine map, the
/// pixel and one increment; no virtual calls and no data-dependent branch but the (almost always
/// taken) bounds check.
std::uint64_t run_chunk(const Prepared& p, const Grid& grid, std::uint64_t seed, std::uint64_t chunk,
                        std::uint64_t points, std::uint64_t burn_in, std::uint32_t* counts) noexcept {
  Random rng(seed, chunk);
  const std::uint64_t n = p.maps.size();
  std::uint64_t outside = 0;
#if defined(__SSE2__)
  // (x, y) in one register, every step on both lanes: (x, y) ← (a, c)·x + (b, d)·y + (e, f) rounds
  // each lane as the scalar expressions a·x + b·y + e and c·x + d·y + f do, and the pixel is
  // Grid::index's: ((x − x_min)·sx, (y − y_max)·(−sy)) is ((x − x_min)·sx, (y_max − y)·sy) exactly,
  // the closed window is two compares, and clamping to the last pixel before truncating equals
  // clamping after. Same points, same pixels, about 20 instructions fewer per point
  // (docs/performance.md, "Chaos loop").
  struct alignas(16) Packed {
    double column0[2], column1[2], translation[2];
  };
  // The alias table as three arrays indexed by the column (scaled addressing, no multiply by a
  // row size): keep `self` when the 32-bit coin is ≤ `last_kept` (Column keeps it below
  // threshold ≤ 2³²; a column that never keeps it gets self = alias); byte offsets into `maps`.
  std::vector<Packed> maps(n);
  std::vector<std::uint32_t> table(3 * n);
  std::uint32_t* last_kept = table.data();
  std::uint32_t* self = last_kept + n;
  std::uint32_t* alias = self + n;
  for (std::size_t k = 0; k < n; ++k) {
    const Linear& m = p.maps[k];
    maps[k] = {{m.a, m.c}, {m.b, m.d}, {m.e, m.f}};
    const Column& c = p.table[k];
    alias[k] = static_cast<std::uint32_t>(c.alias * sizeof(Packed));
    self[k] = c.threshold == 0 ? alias[k] : static_cast<std::uint32_t>(c.self * sizeof(Packed));
    last_kept[k] = c.threshold == 0 ? 0 : static_cast<std::uint32_t>(c.threshold - 1);
  }
  const char* base = reinterpret_cast<const char*>(maps.data());
  __m128d point = _mm_set_pd(p.y0, p.x0);
  const auto step = [&]() noexcept {
    const std::uint64_t r = rng();
    const std::uint64_t column = ((r >> 32) * n) >> 32;
    // Both offsets loaded, then a select: a conditional move, not a branch taken half the time.
    const std::uint32_t keep = self[column], other = alias[column];
    const auto& m = *reinterpret_cast<const Packed*>(
        base + (static_cast<std::uint32_t>(r) <= last_kept[column] ? keep : other));
    const __m128d x = _mm_unpacklo_pd(point, point), y = _mm_unpackhi_pd(point, point);
    point =
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_load_pd(m.column0), x), _mm_mul_pd(_mm_load_pd(m.column1), y)),
                   _mm_load_pd(m.translation));
  };
  for (std::uint64_t i = 0; i < burn_in; ++i) step();
  const __m128d origin = _mm_set_pd(grid.y_max, grid.x_min), scale = _mm_set_pd(-grid.sy, grid.sx);
  const __m128d zero = _mm_setzero_pd(), size = _mm_set_pd(grid.h, grid.w);
  const __m128d last = _mm_set_pd(grid.h - 1, grid.w - 1);
  const std::size_t width = grid.width;
#pragma GCC unroll 2
  for (std::uint64_t i = 0; i < points; ++i) {
    step();
    const __m128d q = _mm_mul_pd(_mm_sub_pd(point, origin), scale);
    if (_mm_movemask_pd(_mm_and_pd(_mm_cmpge_pd(q, zero), _mm_cmple_pd(q, size))) == 3) [[likely]] {
      const auto pixel = static_cast<std::uint64_t>(_mm_cvtsi128_si64(_mm_cvttpd_epi32(_mm_min_pd(q, last))));
      ++counts[(pixel >> 32) * width + (pixel & 0xFFFFFFFFULL)];
    } else {
      ++outside;
    }
  }
#else
  const Linear* maps = p.maps.data();
  const Column* table = p.table.data();
  double x = p.x0, y = p.y0;
  const auto step = [&]() noexcept {
    const std::uint64_t r = rng();
    const Column& col = table[((r >> 32) * n) >> 32];
    const std::uint32_t k = (r & 0xFFFFFFFFULL) < col.threshold ? col.self : col.alias;
    const Linear& m = maps[k];
    const double nx = m.a * x + m.b * y + m.e;
    y = m.c * x + m.d * y + m.f;
    x = nx;
  };
  for (std::uint64_t i = 0; i < burn_in; ++i) step();
  for (std::uint64_t i = 0; i < points; ++i) {
    step();
    const std::size_t at = grid.index(x, y);
    if (at != SIZE_MAX)
      ++counts[at];
    else
      ++outside;
  }
#endif
  return outside;
}

}  // namespace

Histogram chaos_game_histogram(std::span<const AffineMap> maps, const ChaosHistogramOptions& options) {
  const Prepared p = prepare(maps);
  check_grid(options.width, options.height, options.bounds);
  if (options.burn_in > kChaosChunk)  // dropped in every chunk
    throw InvalidInput("the chaos game's burn-in of " + std::to_string(options.burn_in) +
                       " points is above 2^20; lower it");

  Histogram result;
  result.width = options.width;
  result.height = options.height;
  result.bounds = options.bounds;
  result.samples = options.samples;
  const std::size_t pixels = options.width * options.height;
  const Grid grid(options.width, options.height, options.bounds);
  check_part(options.part);
  // This part's chunks: part.index, part.index + part.count, …
  const Part part = options.part;
  const PartChunks dealt = part_chunks(part, options.samples, kChaosChunk);
  const std::uint64_t chunks = dealt.mine, part_samples = dealt.samples;
  // Counts are uint32: a part draws fewer than 2^32 points (more are drawn by more parts).
  if (part_samples >= (std::uint64_t{1} << 32))
    throw InvalidInput(part.count == 1
                           ? std::to_string(part_samples) +
                                 " chaos-game samples are too many for one histogram (below 2^32: uint32 "
                                 "counts); ask for fewer samples, or sum several histograms"
                           : "part " + std::to_string(part.index) + " of " + std::to_string(part.count) +
                                 " draws " + std::to_string(part_samples) +
                                 " points, at most 2^32 - 1 per part (uint32 counts)");
  const unsigned threads = detail::worker_count(options.threads, chunks);

  // The calling thread (the last worker) bins straight into the result; the others into private
  // histograms, allocated (first touched) by the worker that fills them. Which worker runs a chunk
  // does not matter: a chunk's points depend only on (seed, chunk index) and the sums are of
  // integers.
  result.counts.assign(pixels, 0);
  std::vector<std::vector<std::uint32_t>> local(threads - 1);
  std::vector<std::uint64_t> outside(threads, 0);
  std::mutex progress_mutex;
  std::uint64_t done = 0;
  detail::run_chunks(
      chunks, threads,
      [&](unsigned t) {
        if (t + 1 < threads) local[t].assign(pixels, 0);
      },
      [&](unsigned t, std::uint64_t mine) {
        const std::uint64_t c = part.index + mine * part.count;
        const std::uint64_t points = std::min(kChaosChunk, options.samples - c * kChaosChunk);
        std::uint32_t* counts = t + 1 < threads ? local[t].data() : result.counts.data();
        outside[t] += run_chunk(p, grid, options.seed, c, points, options.burn_in, counts);
        if (options.progress) {
          const std::lock_guard lock(progress_mutex);
          done += points;
          options.progress(done, part_samples);
        }
      });
  for (const auto& counts : local)
    for (std::size_t i = 0; i < pixels; ++i) result.counts[i] += counts[i];
  for (const std::uint64_t o : outside) result.outside += o;
  return result;
}

Bounds estimate_bounds(std::span<const AffineMap> maps, double margin, std::uint64_t points) {
  const Prepared p = prepare(maps);
  if (!(margin >= 0) || !std::isfinite(margin))
    throw InvalidInput("the bounds margin must be a finite number ≥ 0");
  if (points >= (std::uint64_t{1} << 32))
    throw InvalidInput("the bounds estimate's " + std::to_string(points) + " points are not below 2^32");
  Random rng(0x5EED, 0);
  double x = p.x0, y = p.y0;
  Bounds b{x, x, y, y};
  const std::uint64_t n = p.maps.size();
  for (std::uint64_t i = 0; i < points; ++i) {
    const std::uint64_t r = rng();
    const Column& col = p.table[((r >> 32) * n) >> 32];
    const Linear& m = p.maps[(r & 0xFFFFFFFFULL) < col.threshold ? col.self : col.alias];
    const double nx = m.a * x + m.b * y + m.e;
    y = m.c * x + m.d * y + m.f;
    x = nx;
    b.x_min = std::min(b.x_min, x);
    b.x_max = std::max(b.x_max, x);
    b.y_min = std::min(b.y_min, y);
    b.y_max = std::max(b.y_max, y);
  }
  // A flat attractor (a segment) still needs a window of positive size.
  double dx = b.x_max - b.x_min, dy = b.y_max - b.y_min;
  const double size = std::max({dx, dy, 1e-12});
  dx = std::max(dx, size * 1e-3);
  dy = std::max(dy, size * 1e-3);
  const double cx = (b.x_min + b.x_max) / 2, cy = (b.y_min + b.y_max) / 2;
  return {cx - dx * (0.5 + margin), cx + dx * (0.5 + margin), cy - dy * (0.5 + margin),
          cy + dy * (0.5 + margin)};
}

namespace {

/// The walk of the depth-k Hutchinson measure: `leaf(x, y, mass, map)` for every word of k maps of non-zero
/// probability, at the image of the measure's barycentre under the word, with the word's mass and the map
/// applied last (the top-level piece w_map(A) the point lies in; 0 at depth 0). Depth-first: memory
/// O(depth), and a fixed visiting order, so sums over it are reproducible.
template <class Leaf>
void hutchinson_walk(const Prepared& p, unsigned depth, Leaf&& leaf) {
  const auto descend = [&](auto&& self, double x, double y, double weight, unsigned level,
                           std::uint32_t last) -> void {
    if (level == depth) {
      leaf(x, y, weight, last);
      return;
    }
    for (std::size_t k = 0; k < p.maps.size(); ++k) {
      if (p.probability[k] == 0) continue;
      const Linear& m = p.maps[k];
      self(self, m.a * x + m.b * y + m.e, m.c * x + m.d * y + m.f, weight * p.probability[k], level + 1,
           static_cast<std::uint32_t>(k));
    }
  };
  // Start at the barycentre x̄ of the invariant measure μ: x̄ = Σ p_k·w_k(x̄) (μ is invariant and
  // the maps are affine). Its image under a word is the barycentre of that piece's share of μ, so
  // each piece's mass lands at its own centre of mass, not on a corner shared with a neighbour.
  double sa = 0, sb = 0, sc = 0, sd = 0, se = 0, sf = 0;
  for (std::size_t k = 0; k < p.maps.size(); ++k) {
    const Linear& m = p.maps[k];
    const double q = p.probability[k];
    sa += q * m.a, sb += q * m.b, sc += q * m.c, sd += q * m.d, se += q * m.e, sf += q * m.f;
  }
  const double det = (1 - sa) * (1 - sd) - sb * sc;
  descend(descend, ((1 - sd) * se + sb * sf) / det, (sc * se + (1 - sa) * sf) / det, 1.0, 0, 0);
}

/// Refuses, before any work, a measure of more than `limit` points (#maps^depth counts the words of
/// zero probability too: a bound).
void check_words(const Prepared& p, unsigned depth, double limit, const std::string& limit_text) {
  const double words = std::pow(static_cast<double>(p.maps.size()), depth);
  if (words > limit)
    throw InvalidInput("the measure at depth " + std::to_string(depth) + " needs " +
                       std::to_string(p.maps.size()) + "^" + std::to_string(depth) + " points, more than " +
                       limit_text + "; lower the depth");
}

}  // namespace

std::vector<double> hutchinson_measure(std::span<const AffineMap> maps, unsigned depth, std::size_t width,
                                       std::size_t height, const Bounds& bounds) {
  const Prepared p = prepare(maps);
  check_grid(width, height, bounds);
  check_words(p, depth, static_cast<double>(std::uint64_t{1} << 28), "2^28");
  const Grid grid(width, height, bounds);
  std::vector<double> mass(width * height, 0.0);
  hutchinson_walk(p, depth, [&](double x, double y, double weight, std::uint32_t) {
    const std::size_t at = grid.index(x, y);
    if (at != SIZE_MAX) mass[at] += weight;
  });
  return mass;
}

HutchinsonPoints hutchinson_points(std::span<const AffineMap> maps, unsigned depth, std::size_t max_points) {
  const Prepared p = prepare(maps);
  check_words(p, depth, static_cast<double>(max_points), std::to_string(max_points));
  HutchinsonPoints out;
  const auto n = static_cast<std::size_t>(
      std::pow(static_cast<double>(
                   std::count_if(p.probability.begin(), p.probability.end(), [](double q) { return q > 0; })),
               depth));
  out.points.resize(static_cast<Eigen::Index>(n), 2);
  out.mass.reserve(n);
  out.map.reserve(n);
  Eigen::Index at = 0;
  hutchinson_walk(p, depth, [&](double x, double y, double weight, std::uint32_t map) {
    out.points(at, 0) = x;
    out.points(at, 1) = y;
    ++at;
    out.mass.push_back(weight);
    out.map.push_back(map);
  });
  return out;
}

}  // namespace cifs::render
