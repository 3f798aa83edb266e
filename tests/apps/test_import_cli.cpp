// SPDX-License-Identifier: MIT
// Shapes from other tools on the command line: OBJ as Blender writes it, several shapes in one file
// (--index), trimmed surfaces (--ignore-trim), knots in the Rhino convention, geomdl exports.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "apps/cli_runner.hpp"

using nlohmann::json;
using namespace cifs_test;

namespace {

const char* kBlenderCurve =
    "# Blender v2.79 (sub 0) OBJ File\no NurbsCurve\nv -1 0 0\nv -0.5 0.5 0\nv 0.5 0.5 0\nv 1 0 0\n"
    "g NurbsCurve\ncstype bspline\ndeg 3\ncurv 0.0 1.0 -4 -3 -2 -1\n"
    "parm u 0.000000 0.142857 0.285714 0.428571 0.571429 0.714286 0.857143 1.000000\nend\n";

// Two curves with relative indices: a line (0,0,0)–(2,0,0) and a quadratic.
const char* kTwoCurves =
    "v 0 0 0\nv 2 0 0\ncstype bspline\ndeg 1\ncurv 0 1 -2 -1\nparm u 0 0 1 1\nend\n"
    "v 0 0 0\nv 1 2 0\nv 2 0 0\ndeg 2\ncurv 0 1 -3 -2 -1\nparm u 0 0 0 1 1 1\nend\n";

// A bilinear patch with a trimming loop (a curv2 triangle in its parameter space).
const char* kTrimmed =
    "vp 0.2 0.2\nvp 0.8 0.2\nvp 0.5 0.8\ncstype bspline\ndeg 1\ncurv2 1 2 3 1\nparm u 0 0 1 2 3 3\nend\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\nparm u 0 0 1 1\nparm v 0 0 1 1\n"
    "trim 0 3 1\nend\n";

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

}  // namespace

TEST_CASE("cifs reads Blender's OBJ curves over their knot domain, with a warning", "[cli]") {
  const std::string path = file("blender.obj", kBlenderCurve);
  const Run r = cifs_cli("info " + path);
  REQUIRE(r.status == 0);
  const json info = json::parse(r.out);
  CHECK(info["domain"] == json::array({0.428571, 0.571429}));
  CHECK(lines(r.err) == 1);
  CHECK(r.err == "cifs: warning: " + path +
                     ": line 10: curv: parameter range u [0, 1] reaches outside the knot domain [0.428571, "
                     "0.571429]: read over [0.428571, 0.571429]\n");
  // Evaluated over the domain: the samples run from (P0 + 4 P1 + P2)/6 (uniform cubic, almost).
  const json pts = json::parse(cifs_cli("eval " + path + " --samples 3").out)["points"];
  REQUIRE(pts.size() == 3);
  CHECK(pts[0][0].get<double>() == Approx(-2.5 / 6).margin(1e-5));
  CHECK(pts[0][1].get<double>() == Approx(2.5 / 6).margin(1e-5));
}

TEST_CASE("cifs takes one shape of several with --index, and info lists them all", "[cli]") {
  const std::string path = file("two.obj", kTwoCurves);
  const json all = json::parse(cifs_cli("info " + path).out);
  REQUIRE(all.is_array());
  REQUIRE(all.size() == 2);
  CHECK(all[0]["index"] == 0);
  CHECK(all[0]["degree"] == 1);
  CHECK(all[1]["index"] == 1);
  CHECK(all[1]["degree"] == 2);
  const json one = json::parse(cifs_cli("info " + path + " --index 1").out);
  CHECK(one["degree"] == 2);
  CHECK_FALSE(one.contains("index"));

  check_error(cifs_cli("eval " + path + " --samples 3"),
              path + ": holds 2 shapes (curves and surfaces): choose one with --index N, N from 0 to 1");
  check_error(cifs_cli("eval " + path + " --samples 3 --index 2"),
              path + ": --index 2 is out of range: the file holds 2 shapes (0 to 1)");
  check_error(cifs_cli("eval " + path + " --samples 3 --index -1"), "--index");
  // The quadratic at 1/2: (P0 + 2 P1 + P2)/4 = (1, 1, 0).
  const Run e = cifs_cli("eval " + path + " --index 1 --at 0.5");
  REQUIRE(e.status == 0);
  CHECK(json::parse(e.out)["points"][0] == json::array({1.0, 1.0, 0.0}));
  CHECK(cifs_cli("check " + path + " --index 0").status == 0);
  CHECK(cifs_cli("automaton " + path + " --index 1").status == 0);
  CHECK(cifs_cli("attractor " + path + " --index 1 --depth 2").status == 0);
  CHECK(cifs_cli("insert " + path + " --index 1 --midpoints").status == 0);
  CHECK(cifs_cli("dimension " + path + " --index 1 --depth 16").status == 0);
  check_error(cifs_cli("dimension " CIFS_EXAMPLES_DIR "/experiments/circle.json --index 0"),
              "--index and --ignore-trim apply to shape files, not experiments");
}

TEST_CASE("cifs refuses trimmed surfaces, or reads them whole with --ignore-trim", "[cli]") {
  const std::string path = file("trimmed.obj", kTrimmed);
  check_error(
      cifs_cli("info " + path),
      path +
          ": line 17: trim: trimmed surfaces are not supported; --ignore-trim (ignore_trim) reads the "
          "whole untrimmed surface");
  const Run r = cifs_cli("eval " + path + " --ignore-trim --at 1,1 --at 0.5,0.5");
  REQUIRE(r.status == 0);
  CHECK(json::parse(r.out)["points"] ==
        json::array({json::array({1.0, 1.0, 1.0}), json::array({0.5, 0.5, 0.25})}));
  CHECK(r.err ==
        "cifs: warning: " + path +
            ": line 17: the trimming loops of the surf at line 14 are ignored: the whole untrimmed surface "
            "is read\n");
  // A command that fails prints its error only, not the warnings of the file it read.
  check_error(cifs_cli("eval " + path + " --ignore-trim --at 2,2"), "outside the domain");
}

TEST_CASE("cifs reads knots in the Rhino convention and geomdl exports", "[cli]") {
  const std::string points =
      R"("points": [[0, 0], [1, 3], [2.5, -1], [4, 2], [6, 0.5]], "weights": [1, 2, 1, 0.5, 1])";
  const std::string rhino =
      file("rhino.json", R"({"curve": {"degree": 3, "knots": [0, 1, 2.5, 3, 4, 6, 7], )" + points + "}}");
  const std::string full = file(
      "full.json", R"({"curve": {"degree": 3, "knots": [0, 0, 1, 2.5, 3, 4, 6, 7, 7], )" + points + "}}");
  const Run a = cifs_cli("eval " + rhino + " --samples 50"), b = cifs_cli("eval " + full + " --samples 50");
  REQUIRE(a.status == 0);
  CHECK(a.err.empty());
  CHECK(a.out == b.out);

  const json info = json::parse(cifs_cli("info " CIFS_EXAMPLES_DIR "/shapes/geomdl_curve.json").out);
  CHECK(info["type"] == "curve");
  CHECK(info["dimension"] == 2);
  CHECK(info["rational"] == true);
  CHECK(info["segments"] == 4);
  CHECK(
      json::parse(cifs_cli("info " CIFS_EXAMPLES_DIR "/shapes/geomdl_surface.json").out)["control_points"] ==
      json::array({2, 9}));
  CHECK(cifs_cli("check " CIFS_EXAMPLES_DIR "/shapes/geomdl_curve.json").status == 0);
  // dimension tells a geomdl file from an experiment (both have a "shape" member).
  const Run d = cifs_cli("dimension " CIFS_EXAMPLES_DIR "/shapes/geomdl_curve.json --depth 16 --json");
  REQUIRE(d.status == 0);
  CHECK_THAT(json::parse(d.out)["kind"].get<std::string>(), Catch::Contains("curve"));
}
