// SPDX-License-Identifier: MIT
// The chaos game's inner loop against a minimal one (docs/performance.md, "Chaos loop"): run both
// under callgrind with bench/chaos_loop_ratio.py, which prints instructions per point and the ratio.
//
// The minimal loop is the reference: xoshiro256** (cifs::Random), a map drawn by multiply-shift
// (uniformly, no alias table), the affine map, and a histogram increment behind one unsigned bounds
// check — what any chaos game must do, built with the same flags. The library's loop adds the draw
// with the maps' probabilities and the closed window (points on the right and bottom edges count).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cifs/random.hpp"
#include "cifs/render/point_ifs.hpp"

namespace {

using cifs::render::AffineMap;
using cifs::render::Bounds;

/// The reference loop; noinline so that callgrind can count it alone (--toggle-collect).
[[gnu::noinline]] std::uint64_t minimal_chaos_loop(const std::vector<AffineMap>& maps, const Bounds& b,
                                                   std::size_t width, std::size_t height,
                                                   std::uint64_t points, std::uint32_t* counts) {
  cifs::Random rng(1, 0);
  const AffineMap* m = maps.data();
  const std::uint64_t n = maps.size();
  const double sx = static_cast<double>(width) / (b.x_max - b.x_min);
  const double sy = static_cast<double>(height) / (b.y_max - b.y_min);
  double x = 0, y = 0;
  std::uint64_t outside = 0;
  for (std::uint64_t i = 0; i < points; ++i) {
    const AffineMap& w = m[((rng() >> 32) * n) >> 32];
    const double nx = w.a * x + w.b * y + w.e;
    y = w.c * x + w.d * y + w.f;
    x = nx;
    // The attractor lies in a bounded window, so the conversions stay in range here.
    const auto ix = static_cast<std::uint64_t>(static_cast<std::int64_t>((x - b.x_min) * sx));
    const auto iy = static_cast<std::uint64_t>(static_cast<std::int64_t>((b.y_max - y) * sy));
    if (ix < width && iy < height)
      ++counts[iy * width + ix];
    else
      ++outside;
  }
  return outside;
}

}  // namespace

int main(int argc, char** argv) {
  const std::uint64_t points = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : std::uint64_t{1} << 22;
  const std::vector<AffineMap> maps = cifs::render::barnsley_fern();
  cifs::render::ChaosHistogramOptions options;
  options.samples = points;
  options.threads = 1;
  options.width = options.height = 1024;
  options.bounds = cifs::render::estimate_bounds(maps);
  const cifs::render::Histogram h = cifs::render::chaos_game_histogram(maps, options);
  std::vector<std::uint32_t> counts(options.width * options.height, 0);
  const std::uint64_t outside =
      minimal_chaos_loop(maps, options.bounds, options.width, options.height, points, counts.data());
  std::printf("%llu points: library %llu outside, minimal loop %llu outside\n",
              static_cast<unsigned long long>(points), static_cast<unsigned long long>(h.outside),
              static_cast<unsigned long long>(outside));
  return 0;
}
