// SPDX-License-Identifier: MIT
// The frictions of a new user (issue 15, items 8, 9, 10, 12, 14): surfaces in every command, runs
// without an image, polygons in `info`, several experiments per render, progress and --quiet, the
// colour of density previews, --max-memory, the gallery's examples.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "apps/cli_runner.hpp"

#include "cifs/io/io.hpp"
#include "cifs/mesh.hpp"
#include "cifs/nurbs/knots.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/render/png.hpp"

using namespace cifs;
using namespace cifs_test;
using nlohmann::json;

namespace {

const std::string kHills = CIFS_EXAMPLES_DIR "/shapes/hills.json";

/// The dyadic parameters of depth K over the breakpoints of one direction (the mesh's grid lines).
std::vector<double> dyadic(const std::vector<double>& breaks, int depth) {
  std::vector<double> out;
  const int n = 1 << depth;
  for (std::size_t a = 0; a + 1 < breaks.size(); ++a)
    for (int j = 0; j < n; ++j) out.push_back(breaks[a] + (breaks[a + 1] - breaks[a]) * j / n);
  out.push_back(breaks.back());
  return out;
}

/// An experiment file in the scratch folder, its inputs resolved against the examples.
std::string experiment(const std::string& name, const std::string& body) {
  return file(name, body);
}

}  // namespace

TEST_CASE("cifs automaton and attractor take surfaces", "[cli][newuser]") {
  const auto s = std::get<nurbs::Surface>(io::read_shape(kHills));
  const auto bu = nurbs::breakpoints(s.knots[0], s.degree[0]),
             bv = nurbs::breakpoints(s.knots[1], s.degree[1]);
  const std::size_t patches = (bu.size() - 1) * (bv.size() - 1);

  // The tensor-product automaton: one initial entry per patch, four children per state.
  const Run au = cifs_cli("automaton " + kHills);
  REQUIRE(au.status == 0);
  const json a = json::parse(au.out);
  CHECK(a["initial"].size() == patches);
  std::map<int, int> children;
  for (const json& t : a["transitions"]) ++children[t["from"].get<int>()];
  CHECK(children.size() == a["states"].size());
  for (const auto& [state, n] : children) CHECK(n == 4);
  CHECK_THAT(cifs_cli("automaton " + kHills + " --format dot").out, Catch::StartsWith("digraph"));

  // Depth 2: the grid of the quad mesh, u-major, against Cox–de Boor at the dyadic parameters.
  const Run at = cifs_cli("attractor " + kHills + " --depth 2");
  REQUIRE(at.status == 0);
  const json points = json::parse(at.out)["points"];
  const std::vector<double> us = dyadic(bu, 2), vs = dyadic(bv, 2);
  REQUIRE(points.size() == us.size() * vs.size());
  const double scale = nurbs::cartesian_points(s).cwiseAbs().maxCoeff();
  double worst = 0;
  for (std::size_t i = 0; i < us.size(); ++i)
    for (std::size_t j = 0; j < vs.size(); ++j) {
      const Point p = nurbs::evaluate(s, us[i], vs[j]);
      for (Eigen::Index k = 0; k < p.size(); ++k)
        worst = std::max(
            worst, std::abs(points[i * vs.size() + j][static_cast<std::size_t>(k)].get<double>() - p(k)));
    }
  CHECK(worst <= 1e-12 * scale);

  // OBJ and PLY: the mesh itself, streamed into the file; npy the grid.
  const auto obj = scratch() / "hills2.obj";
  REQUIRE(cifs_cli("attractor " + kHills + " --depth 2 -o " + obj.string()).status == 0);
  const Mesh mesh = io::read_mesh(obj);
  CHECK(mesh.vertices.rows() == static_cast<Eigen::Index>(us.size() * vs.size()));
  CHECK(face_count(mesh) == 16 * patches);
  const Run ply = cifs_cli("attractor " + kHills + " --depth 1 -o " + (scratch() / "hills1.ply").string());
  CHECK_THAT(ply.out, Catch::Contains("vertices") && Catch::Contains("quads"));

  // Chaos game and tolerance: unordered points, each on the surface's bounding box at least.
  const json chaos = json::parse(cifs_cli("attractor " + kHills + " --chaos 500 --seed 3").out);
  CHECK(chaos["points"].size() == 500);
  CHECK(chaos["seed"] == 3);
  const Run tol = cifs_cli("attractor " + kHills + " --piece-size 0.5");
  REQUIRE(tol.status == 0);
  CHECK(json::parse(tol.out)["points"].size() >= patches);
  check_error(cifs_cli("attractor " + kHills + " --depth 2 --format svg"), "draws curves");
  check_error(cifs_cli("attractor " + kHills + " --chaos 10 --format obj"), "unordered");
}

TEST_CASE("cifs render: geometry alone, several experiments, --max-memory", "[cli][newuser]") {
  const auto out = scratch() / "newuser_render";
  std::filesystem::remove_all(out);
  // Only a PLY: no image is made, the mesh is written.
  const std::string geometry = experiment("geometry.json", R"({"name": "geo", "shape": ")" + kHills + R"(",
      "evaluation": {"depth": 2}, "outputs": {"ply": "geo.ply"}})");
  const Run r = cifs_cli("render " + geometry + " --out-dir " + out.string());
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(io::read_mesh(out / "geo.ply").vertices.rows() == Eigen::Index{17} * 17);
  CHECK(std::filesystem::directory_iterator(out) != std::filesystem::directory_iterator());
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& f : std::filesystem::directory_iterator(out)) ++files;
  CHECK(files == 1);
  check_error(cifs_cli("render " + experiment("none.json", R"({"ifs": "fern"})")), "no output");

  // Two experiments: both run, each its own outputs.
  const std::string tri = experiment("tri.json", R"({"name": "tri", "ifs": "sierpinski",
      "evaluation": {"depth": 4}, "render": {"width": 16, "height": 16}, "outputs": {"png": "tri.png"}})");
  const Run two = cifs_cli("render " + geometry + " " + tri + " --out-dir " + out.string());
  REQUIRE(two.status == 0);
  CHECK_THAT(two.out, Catch::Contains("geo: NURBS surface") && Catch::Contains("tri: classic IFS"));
  CHECK(std::filesystem::is_regular_file(out / "tri.png"));
  check_error(cifs_cli("render " + geometry + " " + tri + " -o " + (out / "x.exr").string()),
              "one experiment");
  // A bad second file is refused before the first runs.
  std::filesystem::remove(out / "tri.png");
  check_error(cifs_cli("render " + tri + " " + experiment("bad.json", "{") + " --out-dir " + out.string()),
              "bad.json");
  CHECK(!std::filesystem::exists(out / "tri.png"));

  // --max-memory: a 1024² image (46 MB) under 10M is refused; a 7000² one (2.16 GB), refused by default,
  // passes the check under 3G (and is then refused for its missing folder, before any work).
  const std::string small =
      experiment("small.json", R"({"ifs": "fern", "render": {"width": 1024, "height": 1024},
      "outputs": {"png": "small.png"}})");
  check_error(cifs_cli("render " + small + " --max-memory 10M"), "above the limit of 0.0104858 GB");
  const std::string big = experiment("big.json", R"({"ifs": "fern", "render": {"width": 7000, "height": 7000},
      "outputs": {"png": "big.png"}})");
  const std::string missing = " -o /no/such/folder/big.exr";
  check_error(cifs_cli("render " + big + missing), "above the limit");
  const Run raised = cifs_cli("render " + big + missing + " --max-memory 3G");
  check_error(raised, "/no/such/folder");
  CHECK_THAT(raised.err, !Catch::Contains("limit"));
  check_error(cifs_cli("render " + small + " --max-memory 4X"), "--max-memory '4X'");
  check_error(cifs_cli("render " + small + " --max-memory -1G"), "--max-memory");
}

// The installed cifs reads the installed examples: tests/package/run.cmake.
TEST_CASE("cifs gallery: the build tree's cifs defaults to the source tree's examples", "[cli][newuser]") {
  const Run r = cifs_cli("gallery --help");
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("(default: " CIFS_EXAMPLES_DIR ":"));
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

TEST_CASE("Density previews take the experiment's colour, palette, gamma and exposure", "[cli][newuser]") {
  const auto out = scratch() / "newuser_colour";
  const auto run = [&](const std::string& name, const std::string& render) {
    const std::string path =
        experiment(name + ".json", R"({"name": ")" + name + R"(", "ifs": "sierpinski",
        "evaluation": {"chaos": 200000, "seed": 1}, "render": {"width": 48, "height": 48)" +
                                       render + R"(}, "outputs": {"png": ")" + name + R"(.png"}})");
    const Run r = cifs_cli("render " + path + " --out-dir " + out.string());
    INFO(r.err);
    REQUIRE(r.status == 0);
    return render::read_png(out / (name + ".png"), render::PixelFormat::rgb8);
  };
  // The densest pixel takes the colour, empty pixels the background (linear → sRGB: 0.5 is 188).
  const auto densest = [](const render::PngImage& png) {
    std::array<int, 3> best{255, 255, 255};
    for (std::size_t i = 0; i < png.pixels.size(); i += 3) {
      const std::array<int, 3> p{png.pixels[i], png.pixels[i + 1], png.pixels[i + 2]};
      if (p[0] + p[1] + p[2] < best[0] + best[1] + best[2]) best = p;
    }
    return best;
  };
  const auto red = run("red", R"(, "color": [0.5, 0, 0])");
  CHECK(densest(red) == std::array<int, 3>{188, 0, 0});
  CHECK((red.pixels[0] == 255 && red.pixels[1] == 255 && red.pixels[2] == 255));  // a corner: no hits
  // A palette: black at no density, green at the top.
  const auto green = run("green", R"(, "palette": [[0, 0, 0], [0, 1, 0]])");
  int top_green = 0;
  for (std::size_t i = 0; i < green.pixels.size(); i += 3) {
    CHECK(green.pixels[i] == 0);
    top_green = std::max<int>(top_green, green.pixels[i + 1]);
  }
  CHECK(top_green == 255);
  CHECK((green.pixels[0] == 0 && green.pixels[1] == 0));
  // Gamma lifts faint pixels; exposure saturates more of them.
  const auto count_above = [](const render::PngImage& png, int level) {
    int n = 0;
    for (std::size_t i = 1; i < png.pixels.size(); i += 3) n += png.pixels[i] >= level;
    return n;
  };
  const auto lifted = run("lifted", R"(, "palette": [[0, 0, 0], [0, 1, 0]], "gamma": 3)");
  const auto exposed = run("exposed", R"(, "palette": [[0, 0, 0], [0, 1, 0]], "exposure": 8)");
  CHECK(count_above(lifted, 200) > count_above(green, 200));
  CHECK(count_above(exposed, 255) > count_above(green, 255));
  check_error(cifs_cli("render " + experiment("g.json", R"({"ifs": "fern", "render": {"gamma": 0},
      "outputs": {"png": "g.png"}})")),
              "render.gamma");
}

TEST_CASE("Every command takes --quiet and progress shows only on a terminal", "[cli][newuser]") {
  const std::string mesh = CIFS_EXAMPLES_DIR "/meshes/cube.obj";
  // Small work each (the default check and dimension take seconds, half a minute under ASan).
  for (const std::string& command : std::vector<std::string>{
           "info " + kHills, "insert " + kHills + " --midpoints", "automaton " + kHills,
           "check " + kHills + " --depth 3", std::string("scheme --list"),
           "limit " + mesh + " --scheme catmull-clark",
           std::string("dimension " CIFS_EXAMPLES_DIR "/experiments/sierpinski.json --depth 9"),
           "eval " + kHills + " --samples 3", "attractor " + kHills + " --depth 1",
           "subdivide " + mesh + " --scheme loop --levels 0"}) {
    INFO(command);
    const Run r = cifs_cli(command + " --quiet");
    CHECK(r.err.find("--quiet") == std::string::npos);
  }
  // A stage over CIFS_PROGRESS_AFTER seconds (1 without it) shows its name and time on a terminal (script
  // gives the command one), and nothing when stderr is a file or with --quiet. 0 s: any stage shows.
  const std::string slow =
      "CIFS_PROGRESS_AFTER=0 " + std::string(CIFS_CLI_PATH) + " check " + kHills + " --depth 3";
  const auto log = scratch() / "tty.log";
  const auto on_terminal = [&](const std::string& command) {
    const std::string tty = "script -qec '" + command + " >/dev/null' " + log.string() + " >/dev/null 2>&1";
    REQUIRE(std::system(tty.c_str()) == 0);
    return slurp(log);
  };
  CHECK_THAT(on_terminal(slow), Catch::Contains("check  done"));
  CHECK_THAT(on_terminal(slow + " --quiet"), !Catch::Contains("check  done") && !Catch::Contains("check …"));
  // The default second: a check of milliseconds leaves no line.
  CHECK_THAT(on_terminal(std::string(CIFS_CLI_PATH) + " check " + kHills + " --depth 3"),
             !Catch::Contains("check  done") && !Catch::Contains("check …"));
  const Run plain = cifs_cli("check " + kHills + " --depth 3", "", "CIFS_PROGRESS_AFTER=0 ");
  CHECK(plain.status == 0);
  CHECK(plain.err.empty());
  // A malformed delay is refused by name, on a terminal, where it would be read.
  CHECK_THAT(on_terminal("CIFS_PROGRESS_AFTER=soon " + std::string(CIFS_CLI_PATH) + " check " + kHills +
                         " 2>&1; true"),
             Catch::Contains("CIFS_PROGRESS_AFTER: 'soon'"));
}

TEST_CASE("cifs render SHAPE or MESH: a look at the file with the default camera and style",
          "[cli][newuser]") {
  const auto out = scratch() / "render_file";
  std::filesystem::remove_all(out);
  const std::string examples = CIFS_EXAMPLES_DIR;
  // A mesh: its Catmull–Clark surface at 2 levels, as the experiment file that says so draws it.
  const Run mesh = cifs_cli("render " + examples + "/meshes/cube.obj --out-dir " + out.string());
  INFO(mesh.err);
  REQUIRE(mesh.status == 0);
  const std::string same = experiment("cube_default.json", R"({"name": "cube", "mesh": ")" + examples +
                                                               R"(/meshes/cube.obj",
      "subdivision": {"scheme": "catmull-clark", "levels": 2}, "render": {"control_net": true},
      "outputs": {"png": "by_file.png"}})");
  REQUIRE(cifs_cli("render " + same + " --out-dir " + out.string()).status == 0);
  CHECK(slurp(out / "cube.png") == slurp(out / "by_file.png"));
  CHECK(std::filesystem::is_regular_file(out / "cube.exr"));
  // A shape (the issue's "malformed JSON at byte 1" was an OBJ mesh; a shape JSON was "no output").
  const Run shape = cifs_cli("render " + examples + "/shapes/wave.json --out-dir " + out.string());
  INFO(shape.err);
  REQUIRE(shape.status == 0);
  CHECK(std::filesystem::is_regular_file(out / "wave.png"));
  CHECK(std::filesystem::is_regular_file(out / "wave.exr"));
  // A polygon file is not a shape to render: refused by name.
  check_error(cifs_cli("render " + examples + "/shapes/clover.json --out-dir " + out.string()),
              "clover.json");
}
