// SPDX-License-Identifier: MIT
// Inputs the CLI test files share (tests/apps: one file per command, test_common_cli.cpp for the CLI
// as a whole): small shapes the tests write into the scratch folder, and paths of the shipped examples.
#pragma once

#include <string>

#include "apps/cli_runner.hpp"

namespace cifs_test {

/// A rational cubic of three segments over [0, 4] in 3-D (one interval twice as long as the others).
inline const char* const kCurve = R"({"curve": {"degree": 3, "knots": [0,0,0,0,1,2,4,4,4,4],
  "points": [[0,0,0],[1,2,0],[3,3,1],[4,0,0],[6,1,2],[7,3,0]], "weights": [1,2,1,0.5,1,1]}})";

/// One patch, quadratic in u and linear in v, over [0, 1]².
inline const char* const kSurface = R"({"surface": {"degree": [2, 1], "knots": [[0,0,0,1,1,1],[0,0,1,1]],
  "points": [[[0,0,0],[0,1,0]], [[1,0,1],[1,1,1]], [[2,0,0],[2,1,3]]]}})";

/// A non-rational cubic of two segments over [0, 2] in 3-D.
inline const std::string kCubic = R"({"curve": {"degree": 3, "knots": [0, 0, 0, 0, 1, 2, 2, 2, 2],
    "points": [[0, 0, 0], [1, 2, 0], [2, 0, 1], [3, 1, 0], [4, 0, 0]]}})";

/// The shipped examples (of the source tree: the build tree's cifs reads them by default).
inline const std::string kExamplesDir = CIFS_EXAMPLES_DIR;
inline const std::string kWave = kExamplesDir + "/shapes/wave.json";
inline const std::string kCube = kExamplesDir + "/meshes/cube.obj";
inline const std::string kHills = CIFS_EXAMPLES_DIR "/shapes/hills.json";

/// The path of examples/meshes/`name`.
inline std::string example(const std::string& name) {
  return std::string(CIFS_EXAMPLES_DIR) + "/meshes/" + name;
}

/// A small experiment of the wave curve in the scratch folder (its shape path absolute).
inline std::string wave_experiment(const std::string& name, const std::string& outputs) {
  return file(name, R"({"shape": ")" + kWave + R"(", "evaluation": {"depth": 4},
      "render": {"width": 32, "height": 32}, "outputs": {)" +
                        outputs + "}}");
}

}  // namespace cifs_test
