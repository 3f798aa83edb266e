// SPDX-License-Identifier: MIT
// The point-IFS chaos game into a 1024² histogram: points/s on 1 and 2 threads (docs/rendering.md).
// Target (issue: rendering): ≥ 100 M points/s per core, ≥ 1.8× that on 2 threads.
#include <benchmark/benchmark.h>

#include "cifs/render/point_ifs.hpp"

namespace {

using namespace cifs::render;

void run(benchmark::State& state, const std::vector<AffineMap>& maps) {
  ChaosHistogramOptions options;
  options.samples = 32 * kChaosChunk;  // 33.5 M points: allocation and the final sum are < 2 %
  options.threads = static_cast<unsigned>(state.range(0));
  options.width = options.height = 1024;
  options.bounds = estimate_bounds(maps);
  std::uint64_t seed = 1;
  for (auto _ : state) {
    options.seed = seed++;
    const Histogram h = chaos_game_histogram(maps, options);
    benchmark::DoNotOptimize(h.counts.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * options.samples));
  state.counters["threads"] = static_cast<double>(options.threads);
}

void fern(benchmark::State& state) {
  run(state, barnsley_fern());
}
void sierpinski(benchmark::State& state) {
  run(state, sierpinski_triangle());
}

// Real time: with 2 threads the CPU time of the calling thread alone would flatter the result.
BENCHMARK(fern)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(sierpinski)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
