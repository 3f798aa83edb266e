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

TEST_CASE("cifs fit --fractal writes a BC-IFS file whose experiment renders and measures", "[cli][fit]") {
  // A Weierstrass-like graph (a = 0.6, b = 2): rough at every scale the data resolve.
  std::string text;
  for (int i = 0; i <= 256; ++i) {
    const double x = i / 256.0;
    double y = 0, a = 1;
    for (int k = 0; k < 10; ++k, a *= 0.6) y += a * std::cos(std::ldexp(M_PI, k) * x);
    text += std::to_string(x) + "," + std::to_string(0.3 * y) + "\n";
  }
  const std::string input = file("rough.csv", text);
  const std::string out = (scratch() / "rough_fit.json").string();
  const Run r =
      cifs_cli("fit " + input + " --control-points 7 --fractal --parametrization uniform -o " + out);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const auto summary = nlohmann::json::parse(r.out);
  CHECK(summary["rms"].get<double>() < 0.8 * summary["smooth_rms"].get<double>());
  CHECK(summary["holder_bound"].get<double>() >= 0.25);
  CHECK(summary["free_coefficients"].get<int>() > 0);
  // The file is a BC-IFS file: cifs info describes it, render draws it, dimension measures it, directly
  // and as an experiment's automaton.
  const Run info = cifs_cli("info " + out);
  REQUIRE(info.status == 0);
  CHECK(nlohmann::json::parse(info.out)["type"] == "bcifs");
  const std::string image = (scratch() / "rough_fit.exr").string();
  const Run drawn = cifs_cli("render " + out + " -o " + image + " --quiet");
  INFO(drawn.err);
  CHECK(drawn.status == 0);
  CHECK(std::filesystem::exists(image));
  const std::string experiment =
      file("rough_fit_experiment.json", R"({"automaton": ")" + out + R"(", "evaluation": {"depth": 8}})");
  for (const std::string& measured : {out, experiment}) {
    const Run dimension = cifs_cli("dimension " + measured + " --max-points 65536");
    INFO(dimension.err);
    CHECK(dimension.status == 0);
  }
  // cifs view opens it (its static page here: a served one runs until stopped).
  const Run page = cifs_cli("view " + out + " --export " + (scratch() / "rough_fit_page").string());
  INFO(page.err);
  CHECK(page.status == 0);
  CHECK(std::filesystem::exists(scratch() / "rough_fit_page" / "geometry.js"));
  // Without -o: the BC-IFS file on stdout.
  const Run printed = cifs_cli("fit " + input + " --control-points 7 --fractal --iterations 3");
  REQUIRE(printed.status == 0);
  CHECK(nlohmann::json::parse(printed.out).contains("bcifs"));
}

TEST_CASE("cifs fit --fractal refuses what it does not take", "[cli][fit]") {
  const std::string out = (scratch() / "never_fractal.json").string();
  const std::string points = file("fractal_points.csv", "0 0\n1 1\n2 0\n3 1\n4 0\n5 1\n6 0\n7 2\n");
  check_error(cifs_cli("fit " + points + " --fractal -o " + out), "--fractal needs --control-points N");
  check_error(cifs_cli("fit " + points + " --fractal --tolerance 0.1 -o " + out), "not --tolerance");
  check_error(cifs_cli("fit " + points + " --control-points 5 --depth 12 -o " + out),
              "--depth is for --fractal");
  check_error(cifs_cli("fit " + points + " --fractal --control-points 5 --measure polyline -o " + out),
              "--measure is for --tolerance");
  check_error(
      cifs_cli("fit " + points + " --fractal --control-points 5 -o " + (scratch() / "f.obj").string()),
      ".json");
  check_error(cifs_cli("fit " + points + " --fractal --control-points 9 -o " + out),
              "control_points 9 is outside 4 … 8");
  CHECK(!std::filesystem::exists(out));
}
