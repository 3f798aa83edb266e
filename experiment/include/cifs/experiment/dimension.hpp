// SPDX-License-Identifier: MIT
// cifs — the dimension of an experiment's attractor, measured as `cifs dimension` measures it: the choice
// of route (a proven tolerance sample, else a depth evaluation), the relaxation of the box-counting fit's
// requirements where they cannot hold, the comparison with a coarser sample that sizes the uncertainty,
// the proven cover's growth and the similarity dimension. The CLI and Python print what this returns.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cifs/experiment/run.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/io/experiment.hpp"

namespace cifs::experiment {

struct DimensionOptions {
  /// Evaluate to this depth (the proven piece bound, else the leaves' nets as an estimated resolution).
  std::optional<int> depth;
  /// Sample to a tolerance: every piece below this fraction of the control nets' extent (0: the smallest
  /// 2^-j within max_points). Neither: the route chooses itself.
  std::optional<double> relative_piece_size;
  /// Point budget of the sample (held in memory): 1 to 50 000 000.
  std::size_t max_points = std::size_t{1} << 21;
  /// Fit range (box levels; -1: automatic). A range given is fitted as given, never relaxed.
  int min_level = -1, max_level = -1;
  /// Automatic fit range: only levels with at least this many boxes.
  std::size_t min_boxes = 1000;
};

struct DimensionMeasurement {
  /// The sample measured: its points, depth, kind, automaton and nets.
  Evaluation sample;
  std::string route;        // "tolerance" or "depth"
  std::string description;  // the route in words: "proven tolerance sample (every piece < 0.001, deepest 12)"
  double resolution = 0;    // passed to the fit (0: none)
  bool estimated = false;   // resolution from the leaves' nets, not proven
  /// Why the automatic route left the proven tolerance sample, or why its strict fit was refused
  /// (route "tolerance"); empty when it did neither.
  std::string fallback;
  std::vector<std::string> relaxed;  // fit requirements dropped, in words
  ifs::BoxCountingResult fit;
  /// The same route on a sample 2–4× smaller (tolerance 2ε, or depth K − 1): its dimension, or why
  /// there is none (coarser_note).
  std::optional<double> coarser;
  std::string coarser_note;
  double uncertainty = 0;  // max(fit.uncertainty, |fit.dimension − coarser|)
  /// Growth of the proven cover (tolerance route), when its counts follow one power law: an upper
  /// estimate free of the box count's boundary term.
  std::optional<ifs::CoverExponent> cover;
  /// The range reported: the box count ± its uncertainty, widened up to the cover's growth where that
  /// lies above it (the box count's finite-scale bias is downward).
  std::array<double, 2> range{};
  /// The similarity (Moran / Mauldin–Williams) dimension when every map is a similarity, else why not.
  std::optional<double> similarity;
  std::string similarity_note;
};

/// Measures the box-counting dimension of `experiment`'s attractor (docs/dimension.md). Throws
/// InvalidInput for options that contradict each other or are out of range, and when no route gives
/// 3 fitted levels (the message says what to change); the errors of evaluate and sample.
DimensionMeasurement measure_dimension(const io::Experiment& experiment,
                                       const DimensionOptions& options = {});

}  // namespace cifs::experiment
