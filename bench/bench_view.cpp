// SPDX-License-Identifier: MIT
// cifs — `cifs view`'s edit round trip inside cifs: a geometry request (a moved control point) through
// view::handle — the JSON parsed, the edited shape validated, its attractor computed by the library,
// the binary buffers encoded with their checksum — for the hills surface at depth 7 (513² vertices) and
// a cubic curve at depth 16. Target (issue 31): ≤ 20 ms. Run on one core: taskset -c 1.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <string>
#include <vector>

#include "cifs/experiment/run.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/failing_paths.hpp"
#include "cifs/io/io.hpp"
#include "cifs/view/server.hpp"

namespace {

/// One timed request, apart for callgrind (--toggle-collect='*timed_edit*'): the edits alone, not the
/// session's first request.
template <class Request>
[[gnu::noinline]] cifs::view::Response timed_edit(const Request& request, int k) {
  return request(k);
}

/// Geometry requests on a session of examples/shapes/`example`, the body of each from `body(k)` (a new edit
/// every time, as a drag or a slider sends).
template <class Body>
void requests(benchmark::State& state, const char* example, Body body) {
  cifs::view::Session session;
  cifs::view::open_session(session, std::string(CIFS_EXAMPLES_DIR) + "/shapes/" + example, "127.0.0.1", 8765);
  const auto request = [&](int k) {
    return cifs::view::handle(session, {.method = "POST",
                                        .target = "/api/geometry?token=" + session.token,
                                        .host = "127.0.0.1:8765",
                                        .body = body(k)});
  };
  // The page's first request (the geometry it loads with) before the timed edits: it builds what a session
  // keeps (the automaton, a perturbed shape's system: ~0.5 s for the hills), which a run of a few
  // iterations of 0.3 s would otherwise count as an edit.
  if (const cifs::view::Response r = request(0); r.status != 200) state.SkipWithError(r.body.c_str());
  int k = 0;
  std::size_t bytes = 0;
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
  for (auto _ : state) {
    const cifs::view::Response r = timed_edit(request, ++k);
    if (r.status != 200) state.SkipWithError(r.body.c_str());
    bytes = r.body.size();
    benchmark::DoNotOptimize(r.body.data());
  }
  state.counters["MB"] = static_cast<double>(bytes) / 1e6;
  // Page faults per request (fresh memory written: ~2,500 an edit of the hills before the session kept its
  // buffers), a figure that the machine's load does not blur.
  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  state.counters["faults"] = benchmark::Counter(static_cast<double>(after.ru_minflt - before.ru_minflt),
                                                benchmark::Counter::kAvgIterations);
}

void edit(benchmark::State& state, const char* example, int depth) {
  requests(state, example, [depth](int k) {
    return "{\"params\": {\"depth\": " + std::to_string(depth) + ", \"points\": [[2, " +
           std::to_string(0.5 + 1e-3 * k) + ", 0.5, 0.5]]}}";
  });
}

void BM_view_edit_hills_depth7(benchmark::State& state) {
  edit(state, "hills.json", 7);
}
void BM_view_edit_cubic_depth16(benchmark::State& state) {
  edit(state, "cubic.json", 16);
}
BENCHMARK(BM_view_edit_hills_depth7)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_view_edit_cubic_depth16)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The amplitude slider: the shape's BC-IFS perturbed (an experiment's "perturbation"), a new amplitude
/// with every request, as a slider sends; the depth fixed.
void amplitude_edit(benchmark::State& state, const char* example, int depth, double amplitude) {
  requests(state, example, [depth, amplitude](int k) {
    return "{\"params\": {\"depth\": " + std::to_string(depth) +
           ", \"amplitude\": " + std::to_string(amplitude * (1 + 1e-3 * (k % 16))) + "}}";
  });
}

void BM_view_amplitude_hills_depth6(benchmark::State& state) {
  amplitude_edit(state, "hills.json", 6, 0.05);
}
void BM_view_amplitude_hills_depth7(benchmark::State& state) {
  amplitude_edit(state, "hills.json", 7, 0.05);
}
void BM_view_amplitude_cubic_depth16(benchmark::State& state) {
  amplitude_edit(state, "cubic.json", 16, 0.1);
}
/// The same edits through experiment::evaluate (the runner: the BC-IFS built, solved and perturbed with every
/// call), which the view called for every amplitude edit before the system was kept: the figure to compare
/// with.
void runner_amplitude(benchmark::State& state, const char* example, int depth, double amplitude) {
  cifs::io::Experiment e;
  e.shape = cifs::io::read_shape(std::string(CIFS_EXAMPLES_DIR) + "/shapes/" + example);
  int k = 0;
  for (auto _ : state) {
    e.perturbation = cifs::io::PerturbationSpec{.amplitude = amplitude * (1 + 1e-3 * (k++ % 16)),
                                                .seed = 1,
                                                .values = {},
                                                .keep_vertices = true,
                                                .fractal_curves = std::nullopt};
    benchmark::DoNotOptimize(cifs::experiment::evaluate(e, depth).points.data());
  }
}
void BM_runner_amplitude_hills_depth6(benchmark::State& state) {
  runner_amplitude(state, "hills.json", 6, 0.05);
}
void BM_runner_amplitude_cubic_depth16(benchmark::State& state) {
  runner_amplitude(state, "cubic.json", 16, 0.1);
}
BENCHMARK(BM_runner_amplitude_hills_depth6)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_runner_amplitude_cubic_depth16)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The contractivity check of those amplitude edits alone (ifs::contraction, contractivity only, as the
/// runner checks a perturbed system), on the hills' BC-IFS perturbed at the benchmark's 16 amplitudes (made
/// before the timing): from cold, and with the failing paths of the previous checks kept (ifs::FailingPaths,
/// as a view session keeps them). Counters: the witness length m and the lengths a kept path settled, per
/// check. The timed loop alone, apart for callgrind (--toggle-collect='*check_edits*'): the checks, the sum
/// of their m.
[[gnu::noinline]] double check_edits(benchmark::State& state,
                                     const std::vector<cifs::automata::Automaton>& edits,
                                     cifs::ifs::FailingPaths* failing) {
  const cifs::ifs::ContractionOptions check{.bound = false};
  std::size_t k = 0;
  double m = 0;
  for (auto _ : state) {
    const auto& a = edits[k++ % edits.size()];
    m += (failing != nullptr ? cifs::ifs::contraction(a, check, *failing) : cifs::ifs::contraction(a, check))
             .m;
  }
  return m;
}

void contraction_check(benchmark::State& state, bool warm) {
  const auto system = cifs::view::shape_system(
      cifs::io::read_shape(std::string(CIFS_EXAMPLES_DIR) + "/shapes/hills.json"), true);
  std::vector<cifs::automata::Automaton> edits;
  for (int k = 0; k < 16; ++k) {
    cifs::ifs::PerturbOptions o;
    o.amplitude = 0.05 * (1 + 1e-3 * k);
    o.contraction.bound = false;
    edits.push_back(cifs::ifs::perturb(system->system, system->space, o).system.automaton);
  }
  cifs::ifs::FailingPaths failing;
  (void)cifs::ifs::contraction(edits.back(), {.bound = false}, failing);  // the previous edit
  failing.settled = 0;
  const double m = check_edits(state, edits, warm ? &failing : nullptr);
  state.counters["m"] = benchmark::Counter(m, benchmark::Counter::kAvgIterations);
  state.counters["settled"] = benchmark::Counter(failing.settled, benchmark::Counter::kAvgIterations);
}
void BM_contraction_hills_cold(benchmark::State& state) {
  contraction_check(state, false);
}
void BM_contraction_hills_warm(benchmark::State& state) {
  contraction_check(state, true);
}
BENCHMARK(BM_contraction_hills_cold)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_contraction_hills_warm)->Unit(benchmark::kMillisecond)->UseRealTime();

// The CPU column counts every thread's (an amplitude edit checks contractivity on a second one); the time,
// the latency.
BENCHMARK(BM_view_amplitude_hills_depth6)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();
BENCHMARK(BM_view_amplitude_hills_depth7)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();
BENCHMARK(BM_view_amplitude_cubic_depth16)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
