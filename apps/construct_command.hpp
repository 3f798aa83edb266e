// SPDX-License-Identifier: MIT
// cifs CLI — `cifs construct`: a surface from curve files (ruled, extrude, revolve, loft, sweep).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cifs::cli {

struct ConstructOptions {
  std::string kind;                              // ruled | extrude | revolve | loft | sweep
  std::vector<std::filesystem::path> curves;     // curve files, in order (each holds one curve)
  std::string direction;                         // extrude: "x,y,…"
  std::string axis_point = "0,0,0";              // revolve
  std::string axis = "0,0,1";                    // revolve: the axis direction
  double angle = 360;                            // revolve, in degrees, (0, 360]
  int degree_v = 3;                              // loft; sweep with instances
  std::string parametrization = "chord_length";  // loft
  int instances = 0;                             // sweep: 0 translational (exact), N ≥ 2 along the frames
  std::filesystem::path output;  // shape file (.json, .obj); empty: the shape's JSON on stdout
};

/// With -o: a JSON summary (degrees, net, sweep deviation); without: the surface as JSON.
std::string construct(const ConstructOptions& options);

}  // namespace cifs::cli
