// SPDX-License-Identifier: MIT
// cifs — running an experiment: build the automaton (NURBS knot doubling, tensor product, BC-IFS
// file or classic IFS), perturb its free coefficients, evaluate the attractor, render and export.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cifs/io/experiment.hpp"

namespace cifs::experiment {

struct RunOptions {
  /// Folder of the experiment's `outputs` (created when missing).
  std::filesystem::path out_dir = ".";
  /// Override `outputs.exr` / `outputs.png` (paths as given, not under out_dir).
  std::filesystem::path exr, png;
  bool quiet = false;               // no progress bar
  std::optional<unsigned> threads;  // overrides render.threads
  /// Refuse (before any work) an image or geometry above this many bytes.
  std::size_t max_bytes = std::size_t{1} << 31;
};

struct RunReport {
  std::vector<std::filesystem::path> written;
  int depth = 0;  // depth evaluated (chaos: depth of the sampled nodes)
  std::size_t free_coefficients = 0;
  double residual = 0;  // largest constraint residual after perturbation
  std::string summary;  // one line per fact, for the CLI
};

/// Runs `experiment`. Every output is computed in memory first and then written through a
/// temporary file and a rename, so a failure leaves no output file behind (and never a partial
/// one). Throws InvalidInput (bad content, too large), IoError (files).
RunReport run(const io::Experiment& experiment, const RunOptions& options = {});

}  // namespace cifs::experiment
