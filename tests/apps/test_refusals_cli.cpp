// SPDX-License-Identifier: MIT
// Inputs the CLI must refuse with one line and exit status 2 (docs/reliability.md), each a defect
// that once crashed, ran, or wrote something wrong instead (issue 16).
#include <catch2/catch.hpp>
#include <filesystem>

#include "apps/cli_runner.hpp"

using namespace cifs_test;

namespace {

/// A one-edge BC-IFS file; `initial` is the JSON array of its initial entries.
std::string edge_bcifs(const std::string& name, const std::string& initial) {
  return file(name, R"({"bcifs": {"cells": [{"name": "E", "size": 2, "dimension": 1}],
    "transitions": [{"from": "E", "to": "E", "label": "G", "matrix": [[1, 0], [0.5, 0.5]]}],
    "boundaries": [], "constraints": [], "initial": )" +
                        initial + "}}");
}

}  // namespace

TEST_CASE("cifs render refuses a BC-IFS file without initial entries", "[cli][reliability]") {
  // It dereferenced the first of no nets (segmentation fault); dimension refused it, by luck.
  const std::string bcifs = edge_bcifs("no_initial.json", "[]");
  const std::string exp = file("no_initial_exp.json", R"({"name": "s", "automaton": ")" + bcifs +
                                                          R"(", "evaluation": {"depth": 1},
      "outputs": {"exr": "no_initial.exr"}})");
  for (const std::string command : {"render ", "dimension "})
    check_error(cifs_cli(command + exp), "no_initial.json: bcifs.initial: no entry");
  CHECK(!std::filesystem::exists(scratch() / "no_initial.exr"));
}
