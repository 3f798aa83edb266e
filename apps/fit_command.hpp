// SPDX-License-Identifier: MIT
// cifs CLI — `cifs fit`: a curve through or near the points of a file (interpolation, least squares).
#pragma once

#include <filesystem>
#include <string>

namespace cifs::cli {

struct FitOptions {
  std::filesystem::path points;  // .csv, .txt, .xyz, .npy, .json, .obj (io::read_points)
  int degree = 3;
  long long control_points = 0;  // least squares with this many control points, or
  double tolerance = 0;          // least squares to this distance (points), or neither: interpolation
  std::string parametrization = "chord_length";
  std::string measure = "points";  // what the tolerance bounds: points | polyline
  bool closed = false;             // interpolation (or --fractal): a periodic curve
  /// The fractal inverse problem (ifs::fit_fractal): a BC-IFS file instead of a shape.
  bool fractal = false;
  bool fixed_knot_points = false;  // --fractal: only the vertices subdivision creates move
  int depth = 30;                  // --fractal: data parameters rounded to 2^-depth of a segment
  int iterations = 100;            // --fractal: Levenberg–Marquardt iterations
  double min_holder = 0.25;        // --fractal: the proven Hölder exponent every step keeps
  std::filesystem::path
      output;  // shape file (.json, .obj), BC-IFS file (.json) with --fractal; empty: stdout
};

/// With -o: a JSON summary (control points, distances; with --fractal the roughness too); without: the
/// curve (or the BC-IFS file) as JSON.
std::string fit(const FitOptions& options);

}  // namespace cifs::cli
