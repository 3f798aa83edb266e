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
  bool closed = false;             // interpolation only: a periodic curve
  std::filesystem::path output;    // shape file (.json, .obj); empty: the shape's JSON on stdout
};

/// With -o: a JSON summary (control points, distances); without: the curve as JSON.
std::string fit(const FitOptions& options);

}  // namespace cifs::cli
