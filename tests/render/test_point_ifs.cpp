// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <numeric>

#include "cifs/errors.hpp"
#include "cifs/render/point_ifs.hpp"

using namespace cifs;
using namespace cifs::render;

namespace {

struct PlanePoint {
  double x, y;
};

PlanePoint apply(const AffineMap& m, PlanePoint p) {
  return {m.a * p.x + m.b * p.y + m.e, m.c * p.x + m.d * p.y + m.f};
}

/// Similarity of ratio r: the columns of the linear part are orthogonal and of length r.
bool is_similarity(const AffineMap& m, double r) {
  const double tol = 1e-14;
  return std::abs(m.a * m.a + m.c * m.c - r * r) < tol && std::abs(m.b * m.b + m.d * m.d - r * r) < tol &&
         std::abs(m.a * m.b + m.c * m.d) < tol;
}

bool near(PlanePoint p, PlanePoint q) {
  return std::abs(p.x - q.x) < 1e-14 && std::abs(p.y - q.y) < 1e-14;
}

/// The right-angled Sierpinski triangle on (0, 0), (1, 0), (0, 1): its depth-k pieces are exactly
/// the dyadic squares [i, i+1]·2⁻ᵏ × [j, j+1]·2⁻ᵏ with i & j = 0, each of mass 3⁻ᵏ. Affinely
/// equivalent to sierpinski_triangle(), and aligned with a pixel grid.
std::vector<AffineMap> right_sierpinski() {
  return {{0.5, 0, 0, 0.5, 0, 0, 1}, {0.5, 0, 0, 0.5, 0.5, 0, 1}, {0.5, 0, 0, 0.5, 0, 0.5, 1}};
}

/// Sums `values` (`n by n`, row 0 at the top) over blocks: returns `cells by cells`, indexed
/// [i + j·cells] with i the column and j the row counted from the BOTTOM (y up), as the dyadic
/// squares are.
template <typename T>
std::vector<double> coarse(const std::vector<T>& values, std::size_t n, std::size_t cells) {
  std::vector<double> sums(cells * cells, 0.0);
  const std::size_t block = n / cells;
  for (std::size_t row = 0; row < n; ++row)
    for (std::size_t col = 0; col < n; ++col) {
      const std::size_t i = col / block, j = cells - 1 - row / block;
      sums[i + j * cells] += static_cast<double>(values[row * n + col]);
    }
  return sums;
}

}  // namespace

TEST_CASE("Named point IFS match the literature", "[render]") {
  SECTION("Barnsley's fern") {
    const auto fern = barnsley_fern();
    REQUIRE(fern.size() == 4);
    CHECK(fern[0].probability == 0.01);
    CHECK(fern[1].probability == 0.85);
    CHECK(fern[2].probability == 0.07);
    CHECK(fern[3].probability == 0.07);
    CHECK(fern[1].a == 0.85);
    CHECK(fern[1].b == 0.04);
    CHECK(fern[1].c == -0.04);
    CHECK(fern[1].f == 1.6);
    CHECK(fern[3].f == 0.44);
    // The tip of the fern, the fixed point of the main map, is the well-known (2.6556, 9.9585).
    const AffineMap& m = fern[1];
    const double det = (1 - m.a) * (1 - m.d) - m.b * m.c;
    CHECK(((1 - m.d) * m.e + m.b * m.f) / det == Approx(2.6556).margin(1e-4));
    CHECK((m.c * m.e + (1 - m.a) * m.f) / det == Approx(9.9585).margin(1e-4));
    const Bounds frame = estimate_bounds(fern, 0);
    CHECK_THROWS_WITH(estimate_bounds(fern, 0, std::uint64_t{1} << 32), Catch::Contains("below 2^32"));
    // The frame of the fern: −2.1820 < x < 2.6558, 0 ≤ y < 9.9983.
    CHECK(frame.x_min == Approx(-2.1820).margin(0.05));
    CHECK(frame.x_max == Approx(2.6558).margin(0.05));
    CHECK(frame.y_max == Approx(9.9983).margin(0.05));
    CHECK(frame.y_min == Approx(0).margin(1e-9));
  }
  SECTION("Sierpinski's triangle: three halvings, each fixing a vertex") {
    const auto s = sierpinski_triangle();
    REQUIRE(s.size() == 3);
    const PlanePoint vertex[3] = {{0, 0}, {1, 0}, {0.5, std::numbers::sqrt3 / 2}};
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(is_similarity(s[i], 0.5));
      CHECK(s[i].a == 0.5);
      CHECK(s[i].d == 0.5);
      CHECK(near(apply(s[i], vertex[i]), vertex[i]));
      CHECK(s[i].probability == Approx(1.0 / 3));
    }
  }
  SECTION("Koch's curve: four thirds following the polyline, the middle ones rotated by ±60°") {
    const auto k = koch_curve();
    REQUIRE(k.size() == 4);
    const PlanePoint polyline[5] = {
        {0, 0}, {1.0 / 3, 0}, {0.5, std::numbers::sqrt3 / 6}, {2.0 / 3, 0}, {1, 0}};
    for (std::size_t i = 0; i < 4; ++i) {
      CHECK(is_similarity(k[i], 1.0 / 3));
      CHECK(near(apply(k[i], {0, 0}), polyline[i]));
      CHECK(near(apply(k[i], {1, 0}), polyline[i + 1]));
      CHECK(k[i].probability == 0.25);
    }
    // Orientation-preserving rotations: the angle of the image of (1, 0) is 0, +60°, −60°, 0.
    const double angle[4] = {0, 60, -60, 0};
    for (std::size_t i = 0; i < 4; ++i)
      CHECK(std::atan2(k[i].c, k[i].a) * 180 / std::numbers::pi == Approx(angle[i]).margin(1e-12));
  }
}

TEST_CASE("Chaos game density within tolerance of the deterministic (Hutchinson) measure", "[render]") {
  const auto maps = right_sierpinski();
  const std::size_t n = 256;
  const Bounds unit{0, 1, 0, 1};
  ChaosHistogramOptions options;
  options.samples = (std::uint64_t{1} << 22) + 777;
  options.seed = 2024;
  options.threads = 2;
  options.width = options.height = n;
  options.bounds = unit;
  // Each chunk starts at the corner (0, 0), and its first points have short binary expansions:
  // they lie exactly on the dyadic lines between cells, where pixel ownership (half-open, y down)
  // is a convention. A burn-in of 64 steps leaves points on a level-k line with probability
  // (2/3)^(53−k).
  options.burn_in = kChaosChunk + 1;  // dropped in every chunk: refused
  CHECK_THROWS_WITH(chaos_game_histogram(maps, options),
                    "the chaos game's burn-in of 1048577 points is above 2^20; lower it");
  options.burn_in = 64;
  const Histogram h = chaos_game_histogram(maps, options);
  CHECK(h.outside == 0);
  CHECK(std::accumulate(h.counts.begin(), h.counts.end(), std::uint64_t{0}) == options.samples);

  const std::vector<double> mass = hutchinson_measure(maps, 8, n, n, unit);
  CHECK(std::accumulate(mass.begin(), mass.end(), 0.0) == Approx(1).epsilon(1e-12));
  for (const unsigned level : {3u, 5u}) {
    INFO("level " << level);
    const std::size_t cells = std::size_t{1} << level;
    const double piece = std::pow(3.0, -static_cast<double>(level));
    const std::vector<double> deterministic = coarse(mass, n, cells);
    const std::vector<double> hits = coarse(h.counts, n, cells);
    const double N = static_cast<double>(options.samples);
    double worst = 0;
    for (std::size_t j = 0; j < cells; ++j)
      for (std::size_t i = 0; i < cells; ++i) {
        // The Hutchinson iteration reproduces the exact measure: 3^-k on the squares with i & j = 0.
        const double exact = (i & j) == 0 ? piece : 0.0;
        REQUIRE(deterministic[i + j * cells] == Approx(exact).margin(1e-12));
        const double count = hits[i + j * cells];
        if (exact == 0) {
          CHECK(count == 0);
          continue;
        }
        // Multinomial σ, widened by √k: a point's depth-k cell is fixed by its last k maps, so
        // counts are sums of k-dependent indicators, not independent ones.
        const double sigma = std::sqrt(N * exact * (1 - exact) * level);
        worst = std::max(worst, std::abs(count - N * exact) / sigma);
      }
    CHECK(worst < 6);
  }
}

TEST_CASE("Chaos game: the same seed gives the same histogram with 1, 2 or 3 threads", "[render]") {
  const auto fern = barnsley_fern();
  ChaosHistogramOptions options;
  options.samples = 3 * kChaosChunk + 12345;  // a ragged last chunk
  options.seed = 77;
  options.width = 160;
  options.height = 120;
  options.bounds = estimate_bounds(fern);
  std::vector<std::pair<std::uint64_t, std::uint64_t>> calls;
  options.threads = 1;
  options.progress = [&](std::uint64_t done, std::uint64_t total) { calls.emplace_back(done, total); };
  const Histogram one = chaos_game_histogram(fern, options);
  REQUIRE(calls.size() == 4);
  for (std::size_t i = 1; i < calls.size(); ++i) CHECK(calls[i].first > calls[i - 1].first);
  CHECK(calls.back() == std::make_pair(options.samples, options.samples));
  CHECK(std::accumulate(one.counts.begin(), one.counts.end(), std::uint64_t{0}) + one.outside ==
        options.samples);
  CHECK(one.outside < options.samples / 1000);  // the estimated frame holds (nearly) the whole fern

  options.progress = nullptr;
  for (const unsigned threads : {2u, 3u}) {
    options.threads = threads;
    const Histogram many = chaos_game_histogram(fern, options);
    CHECK(many.counts == one.counts);
    CHECK(many.outside == one.outside);
  }
  options.seed = 78;
  const Histogram other = chaos_game_histogram(fern, options);
  CHECK(other.counts != one.counts);
}

TEST_CASE("Chaos game: the named systems stay in their frames", "[render]") {
  ChaosHistogramOptions options;
  options.samples = 200000;
  options.width = options.height = 64;
  SECTION("Sierpinski: nothing in the removed middle triangle") {
    options.bounds = {0, 1, 0, std::numbers::sqrt3 / 2};
    const Histogram h = chaos_game_histogram(sierpinski_triangle(), options);
    CHECK(h.outside == 0);
    // The pixel around the centroid (½, √3/6) lies inside the removed triangle.
    const std::size_t col = 32, row = static_cast<std::size_t>((1 - 1.0 / 3) * 64);
    CHECK(h.counts[row * 64 + col] == 0);
  }
  SECTION("Koch: within the triangle under the curve") {
    options.bounds = {0, 1, 0, std::numbers::sqrt3 / 6};
    const Histogram h = chaos_game_histogram(koch_curve(), options);
    CHECK(h.outside == 0);
  }
}

TEST_CASE("Chaos game: invalid input", "[render]") {
  ChaosHistogramOptions options;
  options.samples = 10;
  const auto fern = barnsley_fern();
  CHECK_THROWS_AS(chaos_game_histogram(std::vector<AffineMap>{}, options), InvalidInput);
  CHECK_THROWS_AS(chaos_game_histogram(std::vector<AffineMap>{{1.1, 0, 0, 0.5, 0, 0, 1}}, options),
                  InvalidInput);
  CHECK_THROWS_AS(chaos_game_histogram(std::vector<AffineMap>{{0.5, 0, 0, 0.5, 0, 0, 0}}, options),
                  InvalidInput);
  CHECK_THROWS_AS(chaos_game_histogram(std::vector<AffineMap>{{0.5, 0, 0, 0.5, 0, 0, -1}}, options),
                  InvalidInput);
  ChaosHistogramOptions bad = options;
  bad.bounds = {1, 0, 0, 1};
  CHECK_THROWS_AS(chaos_game_histogram(fern, bad), InvalidInput);
  bad = options;
  bad.width = 0;
  CHECK_THROWS_AS(chaos_game_histogram(fern, bad), InvalidInput);
  bad = options;
  bad.samples = std::uint64_t{1} << 32;
  CHECK_THROWS_AS(chaos_game_histogram(fern, bad), InvalidInput);
  CHECK_THROWS_AS(hutchinson_measure(fern, 20, 8, 8, Bounds{}), InvalidInput);
}
