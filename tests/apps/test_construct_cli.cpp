// SPDX-License-Identifier: MIT
// cifs construct: each kind writes a surface whose points (cifs eval) are the closed forms of the curves
// given, and bad input is refused in one line with exit status 2 and nothing written.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "apps/cli_runner.hpp"

using namespace cifs_test;

namespace {

/// The points of `cifs eval SHAPE --at U,V` for each (u, v).
std::vector<std::vector<double>> eval_at(const std::string& shape,
                                         const std::vector<std::array<double, 2>>& at) {
  std::string args = "eval " + shape;
  for (const auto& [u, v] : at) args += " --at " + std::to_string(u) + "," + std::to_string(v);
  const Run r = cifs_cli(args);
  INFO(r.err);
  REQUIRE(r.status == 0);
  return nlohmann::json::parse(r.out)["points"].get<std::vector<std::vector<double>>>();
}

double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double d2 = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d2 += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(d2);
}

const char* const kSegment = R"({"curve": {"degree": 1, "knots": [0,0,1,1], "points": [[2,0,0],[3,0,1]]}})";
const char* const kArc =
    R"({"curve": {"degree": 2, "knots": [0,0,0,1,1,1], "points": [[0,0,1],[1,1,1],[2,0,1]]}})";

}  // namespace

TEST_CASE("cifs construct: ruled, extrude, revolve, loft and sweep surfaces", "[cli][construct]") {
  const std::string seg = file("segment.json", kSegment), arc = file("arc.json", kArc);
  const auto out = [](const std::string& name) { return (scratch() / name).string(); };
  // The arc's point at u: (2u, 2u(1 − u), 1); the segment's (2 + u, 0, u).
  const auto arc_at = [](double u) { return std::vector<double>{2 * u, 2 * u * (1 - u), 1}; };
  const auto seg_at = [](double u) { return std::vector<double>{2 + u, 0, u}; };
  const std::vector<std::array<double, 2>> at{{0, 0}, {0.25, 0.5}, {0.5, 1}, {1, 0.75}};

  Run r = cifs_cli("construct ruled " + seg + " " + arc + " -o " + out("ruled.json"));
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(nlohmann::json::parse(r.out)["degree"] == nlohmann::json::array({2, 1}));
  auto points = eval_at(out("ruled.json"), at);
  for (std::size_t k = 0; k < at.size(); ++k) {
    const auto [u, v] = at[k];
    std::vector<double> expected(3);
    for (int j = 0; j < 3; ++j) expected[j] = (1 - v) * seg_at(u)[j] + v * arc_at(u)[j];
    CHECK(distance(points[k], expected) <= 1e-14);
  }
  // Two curves lofted at degree 1 are the ruled surface.
  REQUIRE(cifs_cli("construct loft " + seg + " " + arc + " --degree-v 1 -o " + out("loft.json")).status == 0);
  const auto lofted = eval_at(out("loft.json"), at);
  for (std::size_t k = 0; k < at.size(); ++k) CHECK(distance(lofted[k], points[k]) <= 1e-14);

  REQUIRE(cifs_cli("construct extrude " + arc + " --direction 0,0,2 -o " + out("extrude.json")).status == 0);
  points = eval_at(out("extrude.json"), at);
  for (std::size_t k = 0; k < at.size(); ++k) {
    std::vector<double> expected = arc_at(at[k][0]);
    expected[2] += 2 * at[k][1];
    CHECK(distance(points[k], expected) <= 1e-14);
  }

  // A quarter turn about z: at v = 1/2 the segment's point turned by 45°.
  r = cifs_cli("construct revolve " + seg + " --angle 90 -o " + out("revolve.json"));
  REQUIRE(r.status == 0);
  CHECK(nlohmann::json::parse(r.out)["rational"] == true);
  points = eval_at(out("revolve.json"), {{0.5, 0.5}, {1, 1}});
  const double h = std::sqrt(0.5);
  CHECK(distance(points[0], {2.5 * h, 2.5 * h, 0.5}) <= 1e-14);
  CHECK(distance(points[1], {0, 3, 1}) <= 1e-14);

  // The translational sweep of the segment along the arc: seg(u) + arc(v) − arc(0).
  REQUIRE(cifs_cli("construct sweep " + seg + " " + arc + " -o " + out("sweep.json")).status == 0);
  points = eval_at(out("sweep.json"), at);
  for (std::size_t k = 0; k < at.size(); ++k) {
    std::vector<double> expected = seg_at(at[k][0]);
    for (int j = 0; j < 3; ++j) expected[j] += arc_at(at[k][1])[j] - arc_at(0)[j];
    CHECK(distance(points[k], expected) <= 1e-14);
  }
  r = cifs_cli("construct sweep " + seg + " " + arc + " --instances 9 -o " + out("swept.json"));
  REQUIRE(r.status == 0);
  const double deviation = nlohmann::json::parse(r.out)["deviation"].get<double>();
  CHECK(deviation > 0);
  CHECK(deviation < 1e-2);
  // Without -o: the surface's JSON.
  r = cifs_cli("construct ruled " + seg + " " + arc);
  REQUIRE(r.status == 0);
  CHECK(nlohmann::json::parse(r.out).contains("surface"));
}

TEST_CASE("cifs construct refuses bad input in one line and writes nothing", "[cli][construct]") {
  const std::string seg = file("segment.json", kSegment), arc = file("arc.json", kArc);
  const std::string flat =
      file("flat.json", R"({"curve": {"degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1,0]]}})");
  const std::string out = (scratch() / "refused.json").string();
  std::filesystem::remove(out);
  const std::pair<std::string, std::string> cases[] = {
      {"construct spin " + seg, "construct 'spin': expected ruled, extrude, revolve, loft or sweep"},
      {"construct ruled " + seg, "construct ruled: 1 curve files given, 2 expected"},
      {"construct loft " + seg, "construct loft: 1 curve files given, at least 2 expected"},
      {"construct loft " + seg + " " + arc, "loft: degree_v 3 is outside 1 … 1"},
      {"construct ruled " + seg + " " + flat, "curves[1]: dimension 2"},
      {"construct extrude " + seg + " --direction 0,0,0", "direction: the zero vector"},
      {"construct extrude " + seg + " --direction 0,x,1", "--direction '0,x,1': expected finite numbers"},
      {"construct extrude " + seg, "--direction '': expected finite numbers"},
      {"construct revolve " + seg + " --angle 400", "--angle 400: outside (0, 360] degrees"},
      {"construct revolve " + seg + " --axis 0,0", "--axis '0,0': 2 numbers, expected 3"},
      {"construct revolve " + seg + " --axis-point 2,0,0 --axis 1,0,1",
       "every control point lies on the axis"},
      {"construct revolve " + flat, "profile: dimension 2, revolve needs 3"},
      {"construct sweep " + seg + " " + arc + " --instances 1", "instances: 1 is neither 0"},
      {"construct ruled " + seg + " " + (scratch() / "missing.json").string(), "missing.json"},
  };
  for (const auto& [args, message] : cases) {
    INFO(args);
    check_error(cifs_cli(args + " -o " + out), message);
    CHECK(!std::filesystem::exists(out));
  }
}
