// SPDX-License-Identifier: MIT
// Fuzzing: the whole pipeline on small sizes. An experiment file (inputs resolved against
// examples/experiments) is parsed, its sizes capped (the constants below: depth 5, tolerance ≥ 2e-2,
// 1,000 chaos samples, 2 subdivision levels, perturbation amplitude ≤ 0.5, a 32 × 32 image, one thread,
// 64 MB of image or geometry) and run: automaton, perturbation, attractor, render, EXR, PNG and geometry
// outputs into a scratch folder; then evaluated at depth ≤ 4 as `cifs dimension` does (unless perturbed
// and already run). libFuzzer's -timeout and -rss_limit_mb (scripts/fuzz.sh) bound the time and memory
// of each input.
#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <string>

#include "cifs/experiment/run.hpp"
#include "cifs/io/json.hpp"
#include "fuzz.hpp"

// Named, not anonymous: the harnesses compile as unity batches (CIFS_UNITY), each in its own namespace.
namespace fuzz_pipeline {

// The work per input (each seed within 1 s of CPU in Release, docs/reliability.md).
constexpr int kSide = 32, kDepth = 5;
constexpr double kTolerance = 2e-2;
constexpr std::uint64_t kSamples = 1000;
// The contraction proof's paths lengthen steeply towards the edge of contractivity: the fractal cube at
// amplitude 0.9 costs 40 times its proof at 0.5 (1 s of CPU in Release, 24 under ASan).
constexpr double kAmplitude = 0.5;

const std::filesystem::path& scratch() {
  return cifs::fuzz::scratch("pipeline");
}

CIFS_FUZZ_HARNESS(pipeline) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    io::Experiment e =
        io::parse_experiment(fuzz::text(data, size), "fuzz.json", CIFS_EXAMPLES_DIR "/experiments");
    e.render.width = std::min(e.render.width, kSide);
    e.render.height = std::min(e.render.height, kSide);
    e.render.threads = 1;
    e.evaluation.depth = std::min(e.evaluation.depth, kDepth);
    e.evaluation.tolerance = std::max(e.evaluation.tolerance, kTolerance);
    e.evaluation.samples = std::min<std::uint64_t>(e.evaluation.samples, kSamples);
    if (e.mesh) e.mesh->levels = std::min(e.mesh->levels, 2);
    if (e.perturbation) e.perturbation->amplitude = std::min(e.perturbation->amplitude, kAmplitude);
    experiment::RunOptions options;
    options.out_dir = scratch();
    options.exr = scratch() / "image.exr";
    options.quiet = true;
    options.max_bytes = std::size_t{64} << 20;
    try {
      experiment::run(e, options);
      // A perturbed BC-IFS costs seconds to set up (its contraction bound): not twice per input.
      if (e.perturbation) return;
    } catch (const InvalidInput&) {  // a refused run may still evaluate (cifs dimension)
    }
    experiment::evaluate(e, std::min(e.evaluation.depth, 4), options);
  });
  return 0;
}

}  // namespace fuzz_pipeline
