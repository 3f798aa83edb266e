// SPDX-License-Identifier: MIT
// cifs CLI — one function per subcommand; each returns the text for stdout, so that an error
// leaves stdout empty.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cifs::cli {

struct EvalOptions {
  std::filesystem::path shape;
  std::vector<std::string> at;  // "U" for curves, "U,V" for surfaces
  int samples = 0;              // uniform over the domain (surfaces: samples × samples)
};
std::string eval(const EvalOptions& options);

struct InsertOptions {
  std::filesystem::path shape;
  std::vector<double> knots;
  std::string dir = "u";
  bool midpoints = false;
};
std::string insert(const InsertOptions& options);

std::string info(const std::filesystem::path& shape);

/// The main job on its built-in default: writes the example gallery into `out`, returns a summary.
std::string gallery(const std::filesystem::path& out);

}  // namespace cifs::cli
