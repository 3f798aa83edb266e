// SPDX-License-Identifier: MIT
// Rendering throughput (docs/rendering.md):
// - the point-IFS chaos game into a 1024² histogram, points/s on 1 and 2 threads; target (issue:
//   rendering) ≥ 100 M points/s per core, ≥ 1.8× that on 2 threads;
// - the CIFS chaos density of a cubic B-spline curve through a perspective camera, samples/s;
// - render_mesh of a 256² quad grid at 1024² with 16 samples per pixel, triangles/s.
#include <benchmark/benchmark.h>

#include <cmath>

#include "cifs/automata/automaton.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/render/chaos_density.hpp"
#include "cifs/render/point_ifs.hpp"
#include "cifs/render/raster.hpp"

namespace {

using namespace cifs;
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

/// A uniform cubic B-spline through 8 points of a helix: 5 segments sharing the uniform state.
void cifs_density(benchmark::State& state) {
  Points P(8, 3);
  for (int i = 0; i < 8; ++i) P.row(i) << std::cos(i * 0.9), std::sin(i * 0.9), 0.3 * i;
  nurbs::Knots knots;
  for (int i = 0; i < 12; ++i) knots.push_back(i);
  const nurbs::Curve curve = nurbs::make_curve(3, knots, P);
  const nurbs::KnotAutomaton k = nurbs::knot_automaton(curve);
  const automata::Automaton& a = k.automaton;
  const std::vector<Points> nets = nurbs::initial_nets(k, curve);
  FramingOptions framing;
  framing.width = framing.height = 1024;
  const Camera camera = frame(P, framing);
  ChaosDensityOptions options;
  options.samples = 64 * kDensityChunk;  // 4.2 M samples
  options.threads = static_cast<unsigned>(state.range(0));
  int depth = 0;
  for (auto _ : state) {
    Image image;
    depth = chaos_density(image, camera, a, nets, options).depth;
    benchmark::DoNotOptimize(image.channels.at("density").data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * options.samples));
  state.counters["threads"] = static_cast<double>(options.threads);
  state.counters["depth"] = depth;
}

void mesh(benchmark::State& state) {
  constexpr int n = 256;
  Mesh m;
  m.vertices.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = 2.0 * i / n - 1, y = 2.0 * j / n - 1;
      m.vertices.row(j * (n + 1) + i) << x, y, 0.2 * std::sin(4 * x) * std::cos(3 * y);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      add_face(m, {v, v + 1, v + n + 2, v + n + 1});
    }
  FramingOptions framing;
  framing.width = framing.height = 1024;
  const Camera camera = frame(m.vertices, framing);
  SurfaceStyle style;
  style.threads = static_cast<unsigned>(state.range(0));
  for (auto _ : state) {
    Image image;
    render_mesh(image, camera, m, style);
    benchmark::DoNotOptimize(image.channels.at("R").data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * 2 * n * n));
  state.counters["threads"] = static_cast<double>(style.threads);
}

// Real time: with 2 threads the CPU time of the calling thread alone would flatter the result.
BENCHMARK(fern)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(sierpinski)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(cifs_density)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(mesh)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
