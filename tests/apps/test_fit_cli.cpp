// SPDX-License-Identifier: MIT
// cifs fit: points files in every format read, the curve written and evaluated back through the data,
// and bad input refused in one line with exit status 2 and nothing written.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "apps/cli_runner.hpp"

using namespace cifs_test;

namespace {

/// The points of `cifs eval SHAPE --at U` for each parameter.
std::vector<std::vector<double>> eval_at(const std::string& shape, const std::vector<double>& us) {
  std::string args = "eval " + shape;
  for (double u : us) args += " --at " + std::to_string(u);
  const Run r = cifs_cli(args);
  REQUIRE(r.status == 0);
  return nlohmann::json::parse(r.out)["points"].get<std::vector<std::vector<double>>>();
}

}  // namespace

TEST_CASE("cifs fit interpolates the points of csv, json and obj files", "[cli][fit]") {
  // Uniform parameters 0, 1/4, …, 1: the curve passes through each point there.
  const std::string csv = file("fit.csv", "x,y\n0,0\n1,2\n2,1\n3,3 # comment\n\n4,0\n");
  const std::string json_file = file("fit_points.json", R"({"points": [[0,0],[1,2],[2,1],[3,3],[4,0]]})");
  const std::string obj = file("fit.obj", "v 0 0 0\nv 1 2 0\nv 2 1 0\nv 3 3 0\nv 4 0 0\n");
  for (const std::string& input : {csv, json_file, obj}) {
    const std::string out = (scratch() / "fitted.json").string();
    const Run r = cifs_cli("fit " + input + " --degree 3 --parametrization uniform -o " + out);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const auto summary = nlohmann::json::parse(r.out);
    CHECK(summary["control_points"] == 5);
    CHECK(summary["point_distance"].get<double>() <= 1e-14 * 4);
    const auto points = eval_at(out, {0, 0.25, 0.5, 0.75, 1});
    const double expected[5][2] = {{0, 0}, {1, 2}, {2, 1}, {3, 3}, {4, 0}};
    for (int k = 0; k < 5; ++k)
      for (int j = 0; j < 2; ++j) CHECK(std::abs(points[k][j] - expected[k][j]) <= 1e-13);
  }
}

TEST_CASE("cifs fit approximates by a count or a tolerance", "[cli][fit]") {
  std::string text;
  for (int k = 0; k <= 100; ++k) {
    const double x = k / 10.0;
    text += std::to_string(x) + " " + std::to_string(std::sin(x)) + "\n";
  }
  const std::string input = file("sine.txt", text);
  const Run count = cifs_cli("fit " + input + " --control-points 12");
  REQUIRE(count.status == 0);
  const auto curve = nlohmann::json::parse(count.out)["curve"];
  CHECK(curve["points"].size() == 12);
  const Run tol = cifs_cli("fit " + input + " --tolerance 1e-4 --parametrization uniform -o " +
                           (scratch() / "sine.json").string());
  REQUIRE(tol.status == 0);
  const auto summary = nlohmann::json::parse(tol.out);
  CHECK(summary["point_distance"].get<double>() <= 1e-4);
  CHECK(summary["control_points"].get<int>() < 50);
}

TEST_CASE("cifs fit refuses bad input in one line, writing nothing", "[cli][fit]") {
  const std::string out = (scratch() / "never.json").string();
  const std::string three = file("three.csv", "0 0\n1 1\n2 0\n");
  check_error(cifs_cli("fit " + three + " --degree 3 -o " + out),
              "three.csv: points: an interpolating curve of degree 3 needs at least 4 points, got 3");
  const std::string twice = file("twice.csv", "0 0\n1 1\n1 1\n2 0\n3 1\n");
  check_error(cifs_cli("fit " + twice + " -o " + out), "twice.csv: points[2]: coincides with points[1]");
  check_error(cifs_cli("fit " + three + " --degree 2 --control-points 9 -o " + out),
              "control_points: 9 is outside 3 … 3");
  check_error(cifs_cli("fit " + three + " --degree 1 --control-points 2 --tolerance 1 -o " + out),
              "not both");
  check_error(cifs_cli("fit " + three + " --degree 1 --control-points 2 --closed -o " + out),
              "closed curves are interpolated");
  check_error(cifs_cli("fit " + three + " --parametrization chordal"), "parametrization 'chordal'");
  check_error(cifs_cli("fit " + three + " -o " + (scratch() / "x.svg").string()),
              "a shape is written as .json, .obj, .step, .stp, .iges or .igs");
  check_error(cifs_cli("fit " + file("word.csv", "0 0\n1 x\n")), "word.csv:2: 'x' is not a number");
  check_error(cifs_cli("fit " + file("ragged.csv", "0 0\n1 1 1\n")),
              "ragged.csv:2: 3 values, the first point has 2");
  check_error(cifs_cli("fit " + file("p.dat", "0 0\n")), "points are read from");
  check_error(cifs_cli("fit " + three + " --degree 0"), "degree");
  CHECK(!std::filesystem::exists(out));
}
