// SPDX-License-Identifier: MIT
// cifs — the CIFS attractor of a cubic NURBS curve against evaluating the same dyadic parameters
// with the NURBS core (de Boor per point, and the batch basis form) and with SISL's s1227.
// Licence: cifs code under MIT; with CIFS_HAVE_SISL the executable links SISL (GNU AGPL v3), see
// bench/CMakeLists.txt. Points per second via items/s; `per_pt` is CPU ns per point.
//
// Depths 12 … 20 (17·2^K + 1 points: 1.7 MB to 428 MB) cross glibc's 32 MiB mmap threshold at 18.
// attractor_points is timed returning a fresh output (the default allocator: above the threshold
// every call maps and faults in fresh pages) and writing into the caller's output (`_into`: storage
// reused, as SISL's and de Boor's buffers, allocated once outside the loop). `table_apply` applies a stencil
// table built once (the sweep case) into a reused output; `table_build` is the table alone.
//
// BM_attractor_memory forks a child that computes the attractor and reports its peak resident
// memory above the child's starting point, divided by the output size (target ≤ 1.5).

#include <benchmark/benchmark.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "sisl_adapters.hpp"

namespace {

using namespace cifs_bench;
namespace automata = cifs::automata;
namespace ifs = cifs::ifs;

/// Cubic, 20 control points in [−10, 10]³, clamped non-uniform knots: 17 segments.
struct AttractorCase {
  nurbs::Curve curve;
  automata::Automaton automaton;
  std::vector<Points> nets;
  std::vector<double> params;  // the dyadic parameters of depth K, in attractor order
};

AttractorCase make_case(int depth) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> coord(-10, 10), length(1, 4);
  const int n = 20, p = 3;
  nurbs::Knots t(static_cast<std::size_t>(n + p + 1), 0.0);
  for (int i = p + 1; i <= n; ++i)
    t[static_cast<std::size_t>(i)] = t[static_cast<std::size_t>(i - 1)] + length(rng);
  for (int i = n + 1; i <= n + p; ++i) t[static_cast<std::size_t>(i)] = t[static_cast<std::size_t>(n)];
  Points P(n, 3);
  for (Eigen::Index i = 0; i < P.size(); ++i) P.data()[i] = coord(rng);
  AttractorCase c{nurbs::make_curve(p, t, P), {}, {}, {}};
  const nurbs::KnotAutomaton knots = nurbs::knot_automaton(c.curve);
  c.automaton = knots.automaton;
  c.nets = nurbs::initial_nets(knots, c.curve);
  const double leaves = std::ldexp(1.0, depth);
  for (const nurbs::KnotInterval& init : knots.intervals)
    for (long long j = 0; j < static_cast<long long>(leaves); ++j)
      c.params.push_back(init.start + (init.end - init.start) * (static_cast<double>(j) / leaves));
  c.params.push_back(knots.intervals.back().end);
  // Cross-check once: the attractor is the curve at the dyadic parameters.
  const Points A = ifs::attractor_points(c.automaton, c.nets, depth);
  const Points E = nurbs::evaluate(c.curve, c.params);
  const double gap = (A - E).cwiseAbs().maxCoeff();
  if (A.rows() != E.rows() || !(gap <= 1e-12 * 10)) {
    std::fprintf(stderr, "cifs_bench_attractor: attractor and evaluation differ by %g\n", gap);
    std::abort();
  }
  return c;
}

const AttractorCase& case_for(int depth) {
  static std::map<int, AttractorCase> cases;
  auto it = cases.find(depth);
  if (it == cases.end()) it = cases.emplace(depth, make_case(depth)).first;
  return it->second;
}

void report(benchmark::State& state, std::size_t points) {
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points));
  state.counters["per_pt"] =
      benchmark::Counter(static_cast<double>(points),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_attractor_automaton(benchmark::State& state) {
  const AttractorCase& c = case_for(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    Points A = ifs::attractor_points(c.automaton, c.nets, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(A.data());
  }
  report(state, c.params.size());
}

void BM_attractor_automaton_into(benchmark::State& state) {
  const AttractorCase& c = case_for(static_cast<int>(state.range(0)));
  Points A;
  ifs::attractor_points(c.automaton, c.nets, static_cast<int>(state.range(0)), A);  // faulted in once
  for (auto _ : state) {
    ifs::attractor_points(c.automaton, c.nets, static_cast<int>(state.range(0)), A);
    benchmark::DoNotOptimize(A.data());
  }
  report(state, c.params.size());
}

/// The animation/sweep case: the stencil table is built once from the automaton and the depth, then
/// applied to new nets (here the same ones) into a reused output.
void BM_attractor_table_apply(benchmark::State& state) {
  const AttractorCase& c = case_for(static_cast<int>(state.range(0)));
  const ifs::StencilTable table = ifs::stencil_table(c.automaton, static_cast<int>(state.range(0)));
  Points A;
  ifs::apply_table(table, c.nets, A);  // faulted in once
  for (auto _ : state) {
    ifs::apply_table(table, c.nets, A);
    benchmark::DoNotOptimize(A.data());
  }
  report(state, c.params.size());
}

/// Building the table alone: what every attractor_points call pays besides the points.
void BM_attractor_table_build(benchmark::State& state) {
  const AttractorCase& c = case_for(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const ifs::StencilTable table = ifs::stencil_table(c.automaton, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(table.tables.data());
  }
  report(state, c.params.size());
}

void BM_attractor_deboor(benchmark::State& state) {
  const AttractorCase& c = case_for(static_cast<int>(state.range(0)));
  Points out(static_cast<Eigen::Index>(c.params.size()), 3);
  for (auto _ : state) {
    for (std::size_t k = 0; k < c.params.size(); ++k)
      out.row(static_cast<Eigen::Index>(k)) = nurbs::evaluate(c.curve, c.params[k]);
    benchmark::DoNotOptimize(out.data());
  }
  report(state, c.params.size());
}

void BM_attractor_batch(benchmark::State& state) {
  const AttractorCase& c = case_for(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    Points E = nurbs::evaluate(c.curve, c.params);
    benchmark::DoNotOptimize(E.data());
  }
  report(state, c.params.size());
}

#ifdef CIFS_HAVE_SISL
void BM_attractor_sisl(benchmark::State& state) {
  const AttractorCase& c = case_for(static_cast<int>(state.range(0)));
  const SislCurvePtr s = to_sisl(c.curve);
  std::vector<double> out(c.params.size() * 3);
  for (auto _ : state) {
    require_sisl_ok(sisl_curve_points<true>(s.get(), c.params, out.data()), "s1227");
    benchmark::DoNotOptimize(out.data());
  }
  report(state, c.params.size());
}
#endif

/// Depths 12, 14, 16, 18, 20.
void depths(benchmark::internal::Benchmark* b) {
  for (const int depth : {12, 14, 16, 18, 20}) b->Arg(depth);
  b->Unit(benchmark::kMillisecond);
}
#ifdef CIFS_HAVE_SISL
BENCHMARK(BM_attractor_sisl)->Apply(depths);
#endif
BENCHMARK(BM_attractor_automaton)->Apply(depths);
BENCHMARK(BM_attractor_automaton_into)->Apply(depths);
BENCHMARK(BM_attractor_table_apply)->Apply(depths);
BENCHMARK(BM_attractor_table_build)->Apply(depths);
BENCHMARK(BM_attractor_deboor)->Apply(depths);
BENCHMARK(BM_attractor_batch)->Apply(depths);

/// Peak resident kB of this process (VmHWM) and current (VmRSS).
std::pair<long, long> memory_kb() {
  std::ifstream status("/proc/self/status");
  std::string key;
  long hwm = 0, rss = 0;
  while (status >> key) {
    if (key == "VmHWM:") status >> hwm;
    if (key == "VmRSS:") status >> rss;
  }
  return {hwm, rss};
}

void BM_attractor_memory(benchmark::State& state) {
  const int depth = static_cast<int>(state.range(0));
  double ratio = 0;
  for (auto _ : state) {
    int fd[2];
    if (pipe(fd) != 0) std::abort();
    const pid_t child = fork();
    if (child == 0) {
      // A fresh case in the child, so that nothing is cached; the baseline is taken after the
      // automaton and nets exist (they are inputs, not output).
      AttractorCase c = make_case(4);
      const auto base = memory_kb().second;
      Points A = ifs::attractor_points(c.automaton, c.nets, depth);
      benchmark::DoNotOptimize(A.data());
      const double output_kb = static_cast<double>(A.size()) * sizeof(double) / 1024.0;
      const double r = static_cast<double>(memory_kb().first - base) / output_kb;
      if (write(fd[1], &r, sizeof r) != sizeof r) _exit(1);
      _exit(0);
    }
    close(fd[1]);
    if (read(fd[0], &ratio, sizeof ratio) != sizeof ratio) ratio = -1;
    close(fd[0]);
    waitpid(child, nullptr, 0);
  }
  state.counters["peak_over_output"] = ratio;
}
BENCHMARK(BM_attractor_memory)->Arg(18)->Arg(20)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
