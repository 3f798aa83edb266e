// SPDX-License-Identifier: MIT
// cifs — the quad-mesh attractor of a bicubic NURBS surface (separable and generic routes) against
// evaluating the same dyadic grid with the NURBS core (evaluate_grid, and de Boor per point) and with
// SISL's grid evaluator s1506. Licence: cifs code under MIT; with CIFS_HAVE_SISL the executable links
// SISL (GNU AGPL v3), see bench/CMakeLists.txt. `per_pt` is CPU ns per grid point.
//
// The argument is the number of patches per direction at depth 8: 2, 5, 8, 16 give 513², 1281²,
// 2049² and 4097² nodes, on both sides of glibc's 32 MiB mmap threshold. The cifs routes are timed
// twice: returning a fresh output (the default allocator: every output above the threshold is a
// fresh mmap, faulted in on each call) and writing into the caller's output (`_into`: storage reused,
// as SISL's buffer, allocated once outside the loop). The meshes also fill their quads and leaf
// states (20 bytes per quad), except `_keep` (MeshOptions::keep_faces: the mesh holds them from the
// previous call, only the vertices are written); the grid evaluators return points only.

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "cifs/ifs/mesh.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "sisl_adapters.hpp"

namespace {

using namespace cifs_bench;
namespace automata = cifs::automata;
namespace ifs = cifs::ifs;

constexpr int kDepth = 8;

/// Bicubic, (A + 3)² control points in [−10, 10]³, clamped non-uniform knots: A × A patches; the
/// mesh at depth 8 has (256·A + 1)² vertices (A = 5: 1281², the case of the earlier tables).
struct SurfaceCase {
  nurbs::Surface surface;
  nurbs::TensorAutomaton automaton;
  std::vector<Points> nets;
  std::vector<double> us, vs;  // the dyadic parameters of the mesh nodes, per direction
};

std::vector<double> node_parameters(const nurbs::Knots& t, int p) {
  const std::vector<double> b = nurbs::breakpoints(t, p);
  const double side = std::ldexp(1.0, kDepth);
  std::vector<double> out;
  for (std::size_t a = 0; a + 1 < b.size(); ++a)
    for (int j = 0; j < (1 << kDepth); ++j) out.push_back(b[a] + (b[a + 1] - b[a]) * (j / side));
  out.push_back(b.back());
  return out;
}

SurfaceCase make_case(int patches) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> coord(-10, 10), length(1, 4);
  const int p = 3, n = patches + p;
  std::array<nurbs::Knots, 2> knots;
  for (auto& t : knots) {
    t.assign(static_cast<std::size_t>(n + p + 1), 0.0);
    for (int i = p + 1; i <= n; ++i)
      t[static_cast<std::size_t>(i)] = t[static_cast<std::size_t>(i - 1)] + length(rng);
    for (int i = n + 1; i <= n + p; ++i) t[static_cast<std::size_t>(i)] = t[static_cast<std::size_t>(n)];
  }
  Points P(n * n, 3);
  for (Eigen::Index i = 0; i < P.size(); ++i) P.data()[i] = coord(rng);
  SurfaceCase c{nurbs::make_surface({p, p}, knots, {n, n}, P), {}, {}, {}, {}};
  c.automaton = nurbs::tensor_automaton(c.surface);
  c.nets = nurbs::initial_nets(c.automaton, c.surface);
  c.us = node_parameters(c.surface.knots[0], p);
  c.vs = node_parameters(c.surface.knots[1], p);
  // Cross-check once: both meshes are the surface at the dyadic nodes, in evaluate_grid's order.
  const Points E = nurbs::evaluate_grid(c.surface, c.us, c.vs);
  const Points A = ifs::surface_mesh(c.automaton, c.nets, kDepth).vertices;
  const Points G = ifs::quad_mesh(c.automaton.product, c.nets, c.automaton.patches, kDepth).vertices;
  const double gap = std::max((A - E).cwiseAbs().maxCoeff(), (G - E).cwiseAbs().maxCoeff());
  if (A.rows() != E.rows() || G.rows() != E.rows() || !(gap <= 1e-12 * 10)) {
    std::fprintf(stderr, "cifs_bench_surface: mesh and evaluation differ by %g\n", gap);
    std::abort();
  }
  return c;
}

const SurfaceCase& case_for(const benchmark::State& state) {
  static std::map<int, SurfaceCase> cases;
  const auto patches = static_cast<int>(state.range(0));
  auto it = cases.find(patches);
  if (it == cases.end()) it = cases.emplace(patches, make_case(patches)).first;
  return it->second;
}

void report(benchmark::State& state, std::size_t points) {
  const std::string side = std::to_string(256 * state.range(0) + 1);
  state.SetLabel(side + "x" + side);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points));
  state.counters["per_pt"] =
      benchmark::Counter(static_cast<double>(points),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

std::size_t point_count(const SurfaceCase& c) {
  return c.us.size() * c.vs.size();
}

void BM_surface_separable(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  for (auto _ : state) {
    cifs::Mesh m = ifs::surface_mesh(c.automaton, c.nets, kDepth);
    benchmark::DoNotOptimize(m.vertices.data());
  }
  report(state, point_count(c));
}

void BM_surface_separable_into(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  cifs::Mesh m;
  ifs::surface_mesh(c.automaton, c.nets, kDepth, m);  // faulted in once, as SISL's buffer
  for (auto _ : state) {
    ifs::surface_mesh(c.automaton, c.nets, kDepth, m);
    benchmark::DoNotOptimize(m.vertices.data());
  }
  report(state, point_count(c));
}

// The sweep case: the mesh holds the faces and states of the previous call (same automaton and
// depth), so only the vertices are written (MeshOptions::keep_faces).
void BM_surface_separable_keep(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  cifs::Mesh m;
  ifs::surface_mesh(c.automaton, c.nets, kDepth, m);  // faulted in once, as SISL's buffer
  for (auto _ : state) {
    ifs::surface_mesh(c.automaton, c.nets, kDepth, m, {.keep_faces = true});
    benchmark::DoNotOptimize(m.vertices.data());
  }
  report(state, point_count(c));
}

void BM_surface_generic(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  for (auto _ : state) {
    cifs::Mesh m = ifs::quad_mesh(c.automaton.product, c.nets, c.automaton.patches, kDepth);
    benchmark::DoNotOptimize(m.vertices.data());
  }
  report(state, point_count(c));
}

// The generic route's topology built once and applied to the nets into reused storage (the
// animation/sweep case): the mesh analogue of cifs_bench_attractor's table_apply.
void BM_surface_generic_table(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  const ifs::MeshStencilTable table =
      ifs::mesh_stencil_table(c.automaton.product, kDepth, {.patches = c.automaton.patches});
  cifs::Mesh m;
  ifs::apply_table(table, c.nets, m);
  for (auto _ : state) {
    ifs::apply_table(table, c.nets, m);
    benchmark::DoNotOptimize(m.vertices.data());
  }
  report(state, point_count(c));
}

void BM_surface_grid(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  for (auto _ : state) {
    Points E = nurbs::evaluate_grid(c.surface, c.us, c.vs);
    benchmark::DoNotOptimize(E.data());
  }
  report(state, point_count(c));
}

void BM_surface_grid_into(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  Points E;
  nurbs::evaluate_grid(c.surface, c.us, c.vs, E);  // faulted in once, as SISL's buffer
  for (auto _ : state) {
    nurbs::evaluate_grid(c.surface, c.us, c.vs, E);
    benchmark::DoNotOptimize(E.data());
  }
  report(state, point_count(c));
}

/// De Boor per point (nurbs::evaluate(s, u, v)) into a buffer allocated once.
void BM_surface_deboor(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  Points out(static_cast<Eigen::Index>(point_count(c)), 3);
  for (auto _ : state) {
    Eigen::Index row = 0;
    for (const double u : c.us)
      for (const double v : c.vs) out.row(row++) = nurbs::evaluate(c.surface, u, v);
    benchmark::DoNotOptimize(out.data());
  }
  report(state, point_count(c));
}

#ifdef CIFS_HAVE_SISL
void BM_surface_sisl_s1506(benchmark::State& state) {
  const SurfaceCase& c = case_for(state);
  const SislSurfPtr s = to_sisl(c.surface);
  std::vector<double> us = c.us, vs = c.vs;
  std::vector<double> out(point_count(c) * 3), normals(point_count(c) * 3);
  for (auto _ : state) {
    require_sisl_ok(sisl_grid(s.get(), us, vs, out.data(), normals.data()), "s1506");
    benchmark::DoNotOptimize(out.data());
  }
  report(state, point_count(c));
}
#endif

/// The sizes, in the order of a table row: SISL, then the cifs routes.
void sizes(benchmark::internal::Benchmark* b) {
  for (const int patches : {2, 5, 8, 16}) b->Arg(patches);
  b->Unit(benchmark::kMillisecond);
}
#ifdef CIFS_HAVE_SISL
BENCHMARK(BM_surface_sisl_s1506)->Apply(sizes);
#endif
BENCHMARK(BM_surface_separable)->Apply(sizes);
BENCHMARK(BM_surface_separable_into)->Apply(sizes);
BENCHMARK(BM_surface_separable_keep)->Apply(sizes);
BENCHMARK(BM_surface_grid)->Apply(sizes);
BENCHMARK(BM_surface_grid_into)->Apply(sizes);
BENCHMARK(BM_surface_deboor)->Apply(sizes);
BENCHMARK(BM_surface_generic)->Arg(5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_surface_generic_table)->Arg(5)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
