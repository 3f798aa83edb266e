// SPDX-License-Identifier: MIT
// cifs eval, insert and info on NURBS shapes and polygons, run as a user runs them, and the shapes of
// other tools read: OBJ as Blender writes it, several shapes in one file (--index), trimmed surfaces
// (--ignore-trim), knots in the Rhino convention, geomdl exports.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli_fixtures.hpp"
#include "apps/cli_runner.hpp"

#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"

using namespace cifs;
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

TEST_CASE("cifs eval prints the points in parameter order", "[cli]") {
  const std::string shape = file("c.json", kCurve);
  const auto c = std::get<nurbs::Curve>(io::read_shape(shape));
  const Run r = cifs_cli("eval " + shape + " --at 4 --at 0.25 --at 1");
  REQUIRE(r.status == 0);
  const json pts = json::parse(r.out)["points"];
  REQUIRE(pts.size() == 3);
  const double us[] = {4, 0.25, 1};
  for (int i = 0; i < 3; ++i) {
    const Point p = nurbs::evaluate_basis(c, us[i]);
    for (int k = 0; k < 3; ++k)
      CHECK(pts[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)].get<double>() == p(k));
  }
  const json samples = json::parse(cifs_cli("eval " + shape + " --samples 5").out)["points"];
  REQUIRE(samples.size() == 5);
  CHECK(samples[4][0].get<double>() == 7.0);  // the domain end is the last control point
}

TEST_CASE("cifs eval on a surface takes U,V and grids", "[cli]") {
  const std::string shape = file("s.json", kSurface);
  const Run r = cifs_cli("eval " + shape + " --at 1,1 --at 0.5,0.25");
  REQUIRE(r.status == 0);
  const json pts = json::parse(r.out)["points"];
  CHECK(pts[0] == json::array({2.0, 1.0, 3.0}));
  CHECK(json::parse(cifs_cli("eval " + shape + " --samples 3").out)["points"].size() == 9);
}

TEST_CASE("cifs eval streams a grid whose rows are longer than a chunk in bounded memory", "[cli][stream]") {
  const std::string shape = file("s.json", kSurface);
  const auto s = std::get<nurbs::Surface>(io::read_shape(shape));
  // 2·10^9 × 2·10^9 points to a pipe: `head` keeps the first 65,540 points of row 0 (a chunk boundary at
  // 65,536), then cifs meets the closed pipe. Under a 1 GiB address space: the parameters of a whole
  // row (16 GB) were once made first.
  const int n = 2000000000;
  const Run r =
      cifs_cli("eval " + shape + " --samples " + std::to_string(n) + " 2>/dev/null | head -c 4000000", "",
               address_space_cap(1));
  REQUIRE_THAT(r.out, Catch::StartsWith("{\"points\":[["));
  std::istringstream text(r.out.substr(std::string("{\"points\":[").size()));
  const nurbs::Domain u = nurbs::domain(s, nurbs::Direction::u), v = nurbs::domain(s, nurbs::Direction::v);
  const double u0 = nurbs::uniform_parameters(u, n, 0, 1)[0];
  const int want = 65540;
  int row = 0;
  for (char c = 0; row < want && text >> c && c == '[';) {
    double x = 0, y = 0, z = 0;
    char comma1 = 0, comma2 = 0, close = 0, next = 0;
    if (!(text >> x >> comma1 >> y >> comma2 >> z >> close >> next)) break;
    const Point p = nurbs::evaluate(s, u0, nurbs::uniform_parameters(v, n, row, 1)[0]);
    INFO("point " << row);
    CHECK(std::abs(x - p(0)) <= 1e-12);
    CHECK(std::abs(y - p(1)) <= 1e-12);
    CHECK(std::abs(z - p(2)) <= 1e-12);
    ++row;
  }
  CHECK(row == want);
}

TEST_CASE("cifs insert prints the same curve with more knots", "[cli]") {
  const std::string shape = file("c.json", kCurve);
  const Run r = cifs_cli("insert " + shape + " --knot 1.5 --knot 3 --knot 3");
  REQUIRE(r.status == 0);
  const auto refined = std::get<nurbs::Curve>(io::parse_shape_json(r.out, "stdout"));
  const auto c = std::get<nurbs::Curve>(io::read_shape(shape));
  CHECK(refined.knots.size() == c.knots.size() + 3);
  for (double u : nurbs::uniform_parameters(nurbs::domain(c), 41))
    CHECK((nurbs::evaluate(refined, u) - nurbs::evaluate(c, u)).norm() <= 1e-12 * 7);
  const std::string surface = file("s.json", kSurface);
  const Run rs = cifs_cli("insert " + surface + " --dir v --knot 0.5");
  REQUIRE(rs.status == 0);
  CHECK(std::get<nurbs::Surface>(io::parse_shape_json(rs.out, "stdout")).count[1] == 3);
}

TEST_CASE("cifs info describes the shape", "[cli]") {
  const json info = json::parse(cifs_cli("info " + file("c.json", kCurve)).out);
  CHECK(info["type"] == "curve");
  CHECK(info["degree"] == 3);
  CHECK(info["control_points"] == 6);
  CHECK(info["segments"] == 3);
  CHECK(info["rational"] == true);
  CHECK(info["domain"] == json::array({0.0, 4.0}));
}

TEST_CASE("cifs reports bad input on one line and exits 2", "[cli]") {
  const std::string good = file("c.json", kCurve);
  check_error(cifs_cli("eval /nonexistent.json --at 0"), "/nonexistent.json: cannot open");
  check_error(cifs_cli("eval " + file("bad.json", "{\"curve\": ") + " --at 0"), "malformed JSON");
  check_error(
      cifs_cli("eval " +
               file("dec.json", R"({"curve": {"degree": 1, "knots": [0,0,2,1], "points": [[0],[1]]}})") +
               " --at 0"),
      "curve.knots[3]: 1 is less than the previous knot 2");
  // Seeds out of range are refused, not clamped to 2^64 − 1.
  for (const std::string seed : {"-1", "18446744073709551616", "1e23", "7x"})
    check_error(cifs_cli("attractor " + good + " --chaos 3 --seed " + seed),
                "--seed: '" + seed + "' is not an integer from 0 to 18446744073709551615");
  const json top = json::parse(cifs_cli("attractor " + good + " --chaos 3 --seed 18446744073709551615").out);
  CHECK(top["seed"].get<std::uint64_t>() == 18446744073709551615ULL);
  check_error(cifs_cli("eval " +
                       file("inf.json",
                            R"({"curve": {"degree": 1, "knots": [0,0,1e400,1e400], "points": [[0],[1]]}})") +
                       " --at 0"),
              "number overflow parsing '1e400'");
  check_error(
      cifs_cli("eval " +
               file("cnt.json", R"({"curve": {"degree": 2, "knots": [0,0,1,1], "points": [[0],[1]]}})") +
               " --at 0"),
      "too few");
  check_error(
      cifs_cli(
          "eval " +
          file("w.json",
               R"({"curve": {"degree": 1, "knots": [0,0,1,1], "points": [[0],[1]], "weights": [1,-1]}})") +
          " --at 0"),
      "weights[1]");
  check_error(cifs_cli("eval " + good + " --at 4.5"), "parameter 4.5 is outside the domain [0, 4]");
  check_error(cifs_cli("eval " + good + " --at nan"), "--at 'nan': not a finite number");
  check_error(cifs_cli("eval " + good + " --at 1,2"), "a curve takes one parameter");
  check_error(cifs_cli("eval " + good), "give --at U");
  check_error(cifs_cli("eval " + good + " --samples -3"), "--samples -3");
  // Points are streamed to stdout as to a file; a stdout redirected to a file is held to the disk's
  // free space before any work, as -o is (2·10^9 squared grid points: about 4·10^19 bytes).
  // Refused before the 2·10^9 parameters are made (they once were: 16 GB and a minute of page faults).
  check_error(
      cifs_cli("eval " + file("big.json", kSurface) + " --samples 2000000000", "", address_space_cap(1)),
      "stdout: the file needs about ");
  check_error(cifs_cli("eval " + file("s.json", kSurface) + " --at 0.5"), "a surface takes U,V");
  check_error(cifs_cli("insert " + good + " --knot 9"), "knot 9 is outside the domain");
  check_error(cifs_cli("insert " + good + " --knot 1 --knot 1 --knot 1"), "multiplicity 4 > degree 3");
  check_error(cifs_cli("insert " + good + " --dir w --knot 1"), "--dir 'w'");
  check_error(cifs_cli("frobnicate"), "unknown command 'frobnicate'");
  check_error(cifs_cli("eval"), "shape");
  check_error(cifs_cli("info " + scratch().string()), "is a directory");
}

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

TEST_CASE("cifs eval on a subnormal knot interval gives the point, not NaN", "[cli][reliability]") {
  // The basis divided 1 by the interval 1e-320 (inf), then inf · 0: {"points":[[nan]]}, exit 0.
  const std::string tiny = file("subnormal_knots.json", R"({"curve": {"degree": 1,
      "knots": [0, 0, 1e-320, 1e-320], "points": [[0], [2]]}})");
  const Run r = cifs_cli("eval " + tiny + " --at 5e-321");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK(r.out == "{\"points\":[[1]]}\n");  // halfway along [0, 2]: exact in binary
}

TEST_CASE("cifs info describes a control polygon", "[cli][newuser]") {
  const Run r = cifs_cli("info " CIFS_EXAMPLES_DIR "/shapes/hepta.json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json info = json::parse(r.out);
  CHECK(info["type"] == "polygon");
  CHECK(info["points"] == 7);
  CHECK(info["closed"] == true);
  CHECK(info["edges"] == 7);
  // A regular heptagon on the unit circle: perimeter 14·sin(π/7).
  CHECK(info["length"].get<double>() == Approx(14 * std::sin(std::numbers::pi / 7)).epsilon(1e-12));
}

TEST_CASE("cifs info describes an experiment file: source, evaluation, perturbation, outputs", "[cli]") {
  const Run mesh = cifs_cli("info " CIFS_EXAMPLES_DIR "/experiments/subdivision_cube_fractal.json");
  INFO(mesh.err);
  REQUIRE(mesh.status == 0);
  const json m = json::parse(mesh.out);
  CHECK(m["type"] == "experiment");
  CHECK(m["source"] == json{{"type", "mesh"},
                            {"file", "cube.obj"},
                            {"scheme", "catmull-clark"},
                            {"levels", 5},
                            {"limit", false}});
  CHECK(!m.contains("evaluation"));  // a mesh is refined, not evaluated
  CHECK(m["perturbation"]["amplitude"] == 0.9);
  CHECK(m["outputs"] == json{"exr", "png", "obj"});
  const json fern = json::parse(cifs_cli("info " CIFS_EXAMPLES_DIR "/experiments/fern.json").out);
  CHECK(fern["source"] == json{{"type", "ifs"}, {"maps", "fern"}});
  CHECK(fern["evaluation"] == json{{"chaos", 33554432}});
  const json junction =
      json::parse(cifs_cli("info " CIFS_EXAMPLES_DIR "/experiments/junction_curves.json").out);
  CHECK(junction["source"] == json{{"type", "junction"}, {"a", "end"}, {"b", "start"}});
  CHECK(junction["evaluation"] == json{{"depth", 8}});
}

TEST_CASE("A parameter or knot outside the domain names the shape file", "[cli][frictions][messages]") {
  const std::string hills = kExamplesDir + "/shapes/hills.json";
  check_error(cifs_cli("eval " + hills + " --at -0.5,0.5"),
              "cifs: " + hills + ": parameter u = -0.5 is outside");
  check_error(cifs_cli("eval " + kWave + " --at 7"),
              "cifs: " + kWave + ": parameter 7 is outside the domain");
  check_error(cifs_cli("insert " + kWave + " --knot 9"), "cifs: " + kWave + ": knot 9 is outside the domain");
}
