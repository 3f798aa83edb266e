// SPDX-License-Identifier: MIT
// cifs — one refinement step of a closed polygon of 10^6 points for every named curve scheme,
// against plain copies of the same bytes. Throughput is reported as bytes read + written per
// second (Google Benchmark's bytes_per_second): 16 MB read + 32 MB written for 2-D points.
//
// Baselines: `duplicate` writes every input point twice (the refinement's exact memory traffic,
// no arithmetic); `memcpy` copies 24 MB to 24 MB (the same 48 MB moved by the C library).
// The target is that each scheme stays within 2× of the duplicate copy (memory-bound).

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "cifs/subdivision/refine.hpp"
#include "cifs/subdivision/scheme.hpp"

namespace {

namespace sd = cifs::subdivision;
using cifs::Points;

constexpr Eigen::Index kPoints = 1'000'000;

Points polygon(int dim) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-10, 10);
  Points P(kPoints, dim);
  for (Eigen::Index i = 0; i < P.size(); ++i) P.data()[i] = u(rng);
  return P;
}

double traffic(const Points& P) {
  return 3.0 * static_cast<double>(P.size()) * sizeof(double);
}

void refine_step(benchmark::State& state, const sd::Scheme& scheme, int dim) {
  const Points P = polygon(dim);
  Points out(2 * P.rows(), P.cols());
  sd::refine_closed(scheme, P, out);  // warm: pages touched once
  for (auto _ : state) {
    sd::refine_closed(scheme, P, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(static_cast<double>(state.iterations()) * traffic(P)));
  state.counters["taps_per_point"] = static_cast<double>(scheme.mask.size()) / 2;
}

void duplicate(benchmark::State& state) {
  const int dim = static_cast<int>(state.range(0));
  const Points P = polygon(dim);
  Points out(2 * P.rows(), P.cols());
  for (auto _ : state) {
    const double* in = P.data();
    double* o = out.data();
    for (Eigen::Index i = 0; i < P.rows(); ++i)
      for (int c = 0; c < dim; ++c) o[2 * i * dim + c] = o[(2 * i + 1) * dim + c] = in[i * dim + c];
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(static_cast<double>(state.iterations()) * traffic(P)));
}

void copy(benchmark::State& state) {
  const int dim = static_cast<int>(state.range(0));
  const std::size_t bytes =
      static_cast<std::size_t>(kPoints) * static_cast<std::size_t>(dim) * sizeof(double) * 3 / 2;
  std::vector<char> a(bytes, 1), b(bytes, 0);
  for (auto _ : state) {
    std::memcpy(b.data(), a.data(), bytes);
    benchmark::DoNotOptimize(b.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * 2 * bytes));
}

void register_all() {
  benchmark::RegisterBenchmark("copy/duplicate/dim:2", duplicate)->Arg(2)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("copy/memcpy/dim:2", copy)->Arg(2)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("copy/duplicate/dim:3", duplicate)->Arg(3)->Unit(benchmark::kMillisecond);
  const std::vector<std::pair<std::string, sd::Scheme>> schemes = {
      {"chaikin", sd::chaikin()},
      {"corner-cutting(0.1,0.6)", sd::corner_cutting(sd::Rational(1) / 10, sd::Rational(3) / 5)},
      {"four-point", sd::four_point()},
      {"generalized-four-point(0.1)", sd::generalized_four_point(sd::Rational(1) / 10)},
      {"six-point", sd::six_point()},
      {"lane-riesenfeld(3)", sd::lane_riesenfeld(3)},
      {"lane-riesenfeld(5)", sd::lane_riesenfeld(5)},
      {"lane-riesenfeld(9)", sd::lane_riesenfeld(9)},
      {"lr-four-point(1)", sd::lr_four_point(1)},
      {"lr-four-point(3)", sd::lr_four_point(3)},
      {"lr-six-point(1)", sd::lr_six_point(1)},
      {"two-tension(3,0.05,-0.1)", sd::two_tension(3, sd::Rational(1) / 20, sd::Rational(-1) / 10)},
      {"j-spline(2)", sd::j_spline(2)},
      {"dual-four-point", sd::dual_four_point()},
  };
  for (const auto& [name, scheme] : schemes)
    benchmark::RegisterBenchmark(("refine/" + name + "/dim:2").c_str(), [scheme =
                                                                             scheme](benchmark::State& s) {
      refine_step(s, scheme, 2);
    })->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("refine/four-point/dim:3", [](benchmark::State& s) {
    refine_step(s, sd::four_point(), 3);
  })->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
