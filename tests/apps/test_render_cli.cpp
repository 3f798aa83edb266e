// SPDX-License-Identifier: MIT
// cifs render, run as a user runs it: experiments on IFS, shapes, BC-IFS files, junctions and meshes,
// a shape or mesh file rendered as it is, density previews, and the experiments it refuses in one
// line before any work, naming what the user gave (docs/reliability.md).
#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "apps/cli_fixtures.hpp"
#include "apps/cli_runner.hpp"

#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/render/png.hpp"

using namespace cifs;
using nlohmann::json;

using namespace cifs_test;

namespace {

/// A one-edge BC-IFS file; `initial` is the JSON array of its initial entries.
std::string edge_bcifs(const std::string& name, const std::string& initial) {
  return file(name, R"({"bcifs": {"cells": [{"name": "E", "size": 2, "dimension": 1}],
    "transitions": [{"from": "E", "to": "E", "label": "G", "matrix": [[1, 0], [0.5, 0.5]]}],
    "boundaries": [], "constraints": [], "initial": )" +
                        initial + "}}");
}

/// examples/experiments/tree.json with `from` replaced by `to`, and its automaton path made absolute.
std::string tree_experiment(const std::string& name, const std::string& from, const std::string& to) {
  std::string text = slurp(kExamplesDir + "/experiments/tree.json");
  const std::string automaton = "../automata/tree.json";
  REQUIRE(text.find(automaton) != std::string::npos);
  text.replace(text.find(automaton), automaton.size(), kExamplesDir + "/automata/tree.json");
  REQUIRE(text.find(from) != std::string::npos);
  text.replace(text.find(from), from.size(), to);
  return file(name, text);
}

/// An experiment file in the scratch folder, its inputs resolved against the examples.
std::string experiment(const std::string& name, const std::string& body) {
  return file(name, body);
}

}  // namespace

TEST_CASE("cifs render: outputs where asked; bad experiments exit 2 and write nothing", "[cli]") {
  const auto dir = scratch() / "render";
  std::filesystem::create_directories(dir);
  const std::string exp = file("sierpinski.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 6},
      "render": {"width": 40, "height": 40}, "outputs": {"exr": "default.exr", "automaton_svg": "a.svg"}})");
  const Run r =
      cifs_cli("render " + exp + " -o " + (dir / "s.exr").string() + " --png " + (dir / "s.png").string());
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("classic IFS sierpinski, depth 6"));
  for (const char* name : {"s.exr", "s.png", "a.svg"}) CHECK(std::filesystem::is_regular_file(dir / name));
  CHECK(!std::filesystem::exists(dir / "default.exr"));  // -o replaces outputs.exr
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string bad =
      file("bad.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 6, "chaos": 10}})");
  check_error(cifs_cli("render " + bad + " -o " + (dir / "s.exr").string()),
              "bad.json: evaluation: expected exactly one");
  const std::string impossible =
      file("surface_svg.json", R"({"shape": ")" CIFS_EXAMPLES_DIR R"(/shapes/saddle.json",
      "render": {"width": 16, "height": 16}, "outputs": {"svg": "s.svg"}})");
  check_error(cifs_cli("render " + impossible + " -o " + (dir / "s.exr").string()),
              "outputs.svg: SVG is for curves");
  CHECK(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST_CASE("cifs render refuses junctions that cannot be joined, one line each", "[cli][junction]") {
  const std::string nurbs =
      R"({"shape": ")" CIFS_EXAMPLES_DIR R"(/shapes/junction_nurbs.json", "boundary": "uend"})";
  const auto experiment = [&](const std::string& name, const std::string& a, const std::string& b) {
    return file(name, R"({"junction": {"a": )" + a + R"(, "b": )" + b + R"(}, "evaluation": {"depth": 2},
      "render": {"width": 16, "height": 16}, "outputs": {"png": "junction_refused.png"}})");
  };
  const std::string grid = R"([[[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0], [0, 4, 0], [0, 5, 0]],
      [[1, 0, 0], [1, 1, 0], [1, 2, 0], [1, 3, 0], [1, 4, 0], [1, 5, 0]],
      [[2, 0, 0], [2, 1, 0], [2, 2, 0], [2, 3, 0], [2, 4, 0], [2, 5, 0]],
      [[3, 0, 0], [3, 1, 0], [3, 2, 0], [3, 3, 0], [3, 4, 0], [3, 5, 0]]])";
  const std::pair<std::string, std::string> cases[] = {
      // A junction layer of one piece: the four-point side cannot adapt to the B-spline.
      {experiment("junction_thin.json",
                  R"({"scheme": "b-spline", "window": 6, "boundary": "end",
                      "points": [[0, 0], [1, 1], [2, 0], [3, 1], [4, 0], [5, 1], [6, 0]]})",
                  R"({"scheme": "four-point", "window": 6, "layer": 1, "boundary": "start",
                      "points": [[2, 0], [3, 1], [4, 0], [5, 1], [6, 0], [7, 1], [8, 0]]})"),
       "junction: BC-IFS: the constraints \"B:a0.start\", \"B:a0.end\" have no common solution"},
      // A NURBS patch and a uniform scheme's: the boundaries do not subdivide alike.
      {experiment("junction_structure.json", nurbs,
                  R"({"scheme": "b-spline", "boundary": "ustart", "points": )" + grid + "}"),
       "junction: B's cell"},
      {experiment("junction_points.json", nurbs,
                  R"({"shape": ")" CIFS_EXAMPLES_DIR
                  R"(/shapes/junction_nurbs.json", "boundary": "ustart"})"),
       "junction: B's control points on the glued boundary differ from A's"},
      {experiment("junction_count.json", nurbs,
                  R"({"shape": ")" CIFS_EXAMPLES_DIR
                  R"(/shapes/junction_nurbs.json", "boundary": "vstart"})"),
       "junction: A's uend has 3 patches and B's vstart 2"},
      {experiment(
           "junction_kind.json", nurbs,
           R"({"scheme": "four-point", "boundary": "start", "points": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0], [4, 0, 0], [5, 0, 0]]})"),
       "junction_kind.json: junction: A is a surface and B a curve"}};
  for (const auto& [experiment_file, message] : cases) {
    INFO(experiment_file);
    check_error(cifs_cli("render --out-dir " + scratch().string() + " " + experiment_file), message);
  }
  CHECK(!std::filesystem::exists(scratch() / "junction_refused.png"));
}

TEST_CASE("cifs names the member of an experiment path the file system refuses", "[cli][reliability]") {
  // A path longer than the file system allows threw std::filesystem::filesystem_error out of the
  // experiment reader: a raw message without the member (found by fuzz_experiment, issue 33).
  const std::string experiment =
      file("long_automaton.json", R"({"name": "x", "automaton": ")" + std::string(5000, 'a') + R"(.json",
      "evaluation": {"depth": 1}, "outputs": {"png": "x.png"}})");
  const Run r = cifs_cli("render " + experiment);
  check_error(r, "long_automaton.json: automaton: cannot read");
  CHECK_THAT(r.err, Catch::Contains("(File name too long)"));
  CHECK(r.err.size() < 300);
}

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

TEST_CASE("cifs refuses unknown members of BC-IFS files by name", "[cli][reliability]") {
  // A typo "fre" for "free" made the transition fixed: 6 free coefficients instead of 9, exit 0.
  std::string tree = slurp(CIFS_EXAMPLES_DIR "/automata/tree.json");
  const std::string free = "\"free\": true";
  REQUIRE(tree.find(free) != std::string::npos);
  file("typo_tree.json", std::string(tree).replace(tree.find(free), free.size(), "\"fre\": true"));
  file("extra_tree.json", std::string(tree).replace(tree.find('{'), 1, "{\"comment\": \"x\", "));
  const std::pair<std::string, std::string> cases[] = {{"typo_tree.json", "bcifs.transitions["},
                                                       {"extra_tree.json", "comment"}};
  for (const auto& [bcifs, member] : cases) {
    const std::string exp = file("typo_exp.json", R"({"automaton": ")" + bcifs + R"(",
      "perturbation": {"amplitude": 0.1, "seed": 1}, "evaluation": {"depth": 2},
      "render": {"width": 8, "height": 8}, "outputs": {"exr": "typo.exr"}})");
    const std::string where = bcifs + ": ";
    check_error(cifs_cli("render --out-dir " + scratch().string() + " " + exp), where + member);
    check_error(cifs_cli("dimension " + exp), where + member);
  }
  CHECK(!std::filesystem::exists(scratch() / "typo.exr"));
}

TEST_CASE("cifs render refuses two outputs with one file", "[cli][reliability]") {
  // The PNG overwrote the EXR, exit status 0, "wrote ./same" printed twice.
  const auto dir = scratch() / "same_outputs";
  std::filesystem::create_directories(dir);
  const auto experiment = [&](const std::string& outputs) {
    return file("same_outputs/e.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 3},
      "render": {"width": 8, "height": 8}, "outputs": )" +
                                           outputs + "}");
  };
  check_error(
      cifs_cli("render " + experiment(R"({"exr": "same", "png": "same"})") + " --out-dir " + dir.string()),
      "outputs.png: " + (dir / "same").string() + " is also outputs.exr; give each output its own file");
  check_error(cifs_cli("render " + experiment(R"({"exr": "a.exr", "svg": "./a.exr"})") + " --out-dir " +
                       dir.string()),
              "outputs.svg: " + (dir / "./a.exr").string() + " is also outputs.exr");
  const std::string png = experiment(R"({"png": "a.png"})");
  check_error(cifs_cli("render " + png + " -o " + (dir / "a.png").string()), "outputs.png: ");
  check_error(
      cifs_cli("render " + png + " -o " + (dir / "b.exr").string() + " --png " + (dir / "b.exr").string()),
      "the PNG path: " + (dir / "b.exr").string() + " is also the EXR path");
  std::filesystem::remove(dir / "e.json");
  CHECK(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST_CASE("cifs render refuses an image path whose folder is missing", "[cli][reliability]") {
  // Both folders were created silently; subdivide -o already refused a missing folder.
  const auto missing = scratch() / "no_folder";
  const std::string exp = file("small_sierpinski.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 3},
      "render": {"width": 8, "height": 8}})");
  check_error(
      cifs_cli("render " + exp + " -o " + (missing / "sub/x.exr").string()),
      (missing / "sub/x.exr").string() + ": the folder " + (missing / "sub").string() + " does not exist");
  check_error(cifs_cli("render " + exp + " -o " + (scratch() / "x.exr").string() + " --png " +
                       (missing / "x.png").string()),
              "the folder " + missing.string() + " does not exist");
  CHECK(!std::filesystem::exists(missing));
  CHECK(!std::filesystem::exists(scratch() / "x.exr"));
}

TEST_CASE("cifs render refuses a BC-IFS that is not contractive, as dimension does", "[cli][reliability]") {
  // The tree with a branch B that keeps two rows fixed: B^k never shrinks nets. Rendered at depth
  // 12 with exit status 0, while dimension and the chaos game refused it.
  std::string tree = slurp(CIFS_EXAMPLES_DIR "/automata/tree.json");
  const std::string branch = "[[0.5, 0, 0.5], [0.28, 0.4, 0.32], [0.2, 0.76, 0.04]]";
  REQUIRE(tree.find(branch) != std::string::npos);
  tree.replace(tree.find(branch), branch.size(), "[[0.5, 0, 0.5], [0, 1, 0], [0, 0, 1]]");
  file("fixed_branch.json", tree);
  for (const std::string evaluation : {R"({"depth": 12})", R"({"chaos": 1000})"}) {
    const std::string exp = file(
        "fixed_branch_exp.json",
        R"({"automaton": "fixed_branch.json",
      "evaluation": )" +
            evaluation + R"(, "render": {"width": 8, "height": 8}, "outputs": {"exr": "fixed_branch.exr"}})");
    for (const std::string command : {"render ", "dimension "})
      check_error(cifs_cli(command + exp),
                  "not contractive: the 8-step products from state 0 (E) do not shrink nets");
  }
  CHECK(!std::filesystem::exists(scratch() / "fixed_branch.exr"));
}

TEST_CASE("cifs render: a chaos game is bounded before it starts", "[cli][reliability]") {
  const std::string hills = std::string(CIFS_EXAMPLES_DIR) + "/shapes/hills.json";
  const auto experiment = [&](const std::string& name, const std::string& samples) {
    return file(name + ".json", R"({"shape": ")" + hills + R"(", "evaluation": {"chaos": )" + samples +
                                    R"(}, "render": {"width": 64, "height": 64, "threads": 1},
      "outputs": {"exr": ")" + name +
                                    R"(.exr"}})");
  };
  // 2^32 − 1 samples was accepted (hours of work): refused with the figure and the largest count.
  check_error(cifs_cli("render " + experiment("chaos_huge", "4294967295") + " --quiet"), "samples × depth");
  CHECK(!std::filesystem::exists(scratch() / "chaos_huge.exr"));
  // The automatic depth of a surface in perspective walked tens of millions of pieces (minutes) before
  // the first sample; its traversal now gives way to the global contraction bound.
  const auto start = std::chrono::steady_clock::now();
  const Run r = cifs_cli("render " + experiment("chaos_small", "16") + " --quiet");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 60);
}

TEST_CASE("cifs render names the experiment's image size, not render:", "[cli][reliability][messages]") {
  const std::string exp = file("huge_image.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 3},
      "render": {"width": 16384, "height": 16384}})");
  // 16384² pixels × 44 bytes = 11.8 GB (hand computation), above the 1 GiB given.
  check_message(
      cifs_cli("render " + exp + " -o " + (scratch() / "huge.exr").string() + " --max-memory 1G"),
      "the image of 16384 × 16384 pixels (render.width × render.height) needs 11.8112 GB, above the "
      "limit of 1.07374 GB; lower the image size",
      "render: a 16384");
  CHECK(!std::filesystem::exists(scratch() / "huge.exr"));
}

TEST_CASE("cifs render names the perturbation, not perturb:", "[cli][reliability][messages]") {
  const std::string seed = R"("perturbation": {"amplitude": 0.0, "seed": 1})";
  // The tree's free coefficients, in the order of its file: E's G and D rows 1 and 2 (10 in all).
  check_message(
      cifs_cli("render " +
               tree_experiment("unknown_value.json", seed,
                               R"("perturbation": {"amplitude": 0.0, "seed": 1, "values": {"zzz": 1}})") +
               " --out-dir " + scratch().string()),
      "the perturbation value \"zzz\" is not an entry of a free matrix; the free coefficients are E/G[1,1], "
      "E/G[1,2], E/G[2,1], E/G[2,2], E/D[1,1], E/D[1,2], … (10 in all)",
      "perturb:");
  check_message(
      cifs_cli("render " +
               tree_experiment("strong.json", seed, R"("perturbation": {"amplitude": 50, "seed": 1})") +
               " --out-dir " + scratch().string()),
      "the perturbed system is not contractive with amplitude 50, seed 1: not contractive", "perturb:");
}

TEST_CASE("cifs render names the edge pieces of a deep BC-IFS, not edge_pieces:",
          "[cli][reliability][messages]") {
  // 3^24 = 282429536481 pieces (the tree's edge has three children).
  check_message(cifs_cli("render " +
                         tree_experiment("deep_tree.json", R"("evaluation": {"depth": 9})",
                                         R"("evaluation": {"depth": 24})") +
                         " --out-dir " + scratch().string()),
                "282429536481 edge pieces at depth 24 need", "edge_pieces");
}

TEST_CASE("cifs render names the chaos game's samples and the camera, not internal routines",
          "[cli][reliability][messages]") {
  const std::string chaos =
      file("many_samples.json", R"({"ifs": "sierpinski", "evaluation": {"chaos": 4294967296},
      "render": {"width": 8, "height": 8}})");
  check_message(
      cifs_cli("render " + chaos + " -o " + (scratch() / "chaos.exr").string()),
      "4294967296 chaos-game samples are too many for one histogram (below 2^32: uint32 counts); ask "
      "for fewer samples",
      "chaos_game_histogram");
  // Up along the view direction, pointing away: it was "camera: up …".
  const std::string camera = file("up_back.json", R"({"shape": ")" + kExamplesDir + R"(/shapes/saddle.json",
      "evaluation": {"depth": 2}, "camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, -3]},
      "render": {"width": 8, "height": 8}})");
  check_message(
      cifs_cli("render " + camera + " -o " + (scratch() / "camera.exr").string()),
      "the camera's up (0, 0, -3) is parallel to the viewing direction from eye to target; give an up "
      "vector across it",
      "camera: up");
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

TEST_CASE("cifs render refuses image paths whose extension names another format", "[cli][frictions]") {
  const std::string e = wave_experiment("ext.json", R"("png": "ext.png")");
  const auto png = scratch() / "foo.png";
  check_error(cifs_cli("render " + e + " -o " + png.string() + " --quiet"),
              "the EXR path: " + png.string() + ": the image is OpenEXR, written as .exr");
  const auto jpg = scratch() / "x.jpg";
  check_error(cifs_cli("render " + e + " --png " + jpg.string() + " --quiet"),
              "the PNG path: " + jpg.string() + ": the preview is PNG, written as .png");
  CHECK_FALSE(std::filesystem::exists(png));
  CHECK_FALSE(std::filesystem::exists(jpg));
}

TEST_CASE("cifs render refuses a chaos game's geometry output before the game", "[cli][frictions]") {
  // 5·10^8 samples (within the work limit): seconds of work if the output were checked after the game.
  const std::string e = file("chaos_ply.json", R"({"shape": ")" + kWave + R"(",
      "evaluation": {"chaos": 500000000}, "render": {"width": 32, "height": 32},
      "outputs": {"png": "c.png", "ply": "c.ply"}})");
  check_error(cifs_cli("render " + e + " --out-dir " + scratch().string() + " --quiet"),
              "outputs.ply: a chaos game gives a density, no geometry to export");
}

TEST_CASE("cifs render on a mesh experiment: the same files as cifs subdivide; bad ones exit 2",
          "[cli][mesh][experiment]") {
  const auto dir = scratch() / "mesh_render";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);  // render creates no folder for -o
  const std::string experiment = file("mesh_experiment.json", R"({"mesh": ")" CIFS_EXAMPLES_DIR
                                                              R"(/meshes/icosahedron.obj",
      "subdivision": {"scheme": "butterfly", "levels": 2}, "render": {"width": 64, "height": 48, "control_net": true},
      "outputs": {"obj": "ico.obj"}})");
  const Run r = cifs_cli("render " + experiment + " -o " + (dir / "ico.exr").string() + " --quiet");
  INFO("stderr: " << r.err);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::StartsWith("mesh_experiment: butterfly subdivision of icosahedron.obj, 2 levels"));
  const auto theirs = scratch() / "ico_subdivide.obj";
  REQUIRE(cifs_cli("subdivide " + example("icosahedron.obj") + " --scheme butterfly --levels 2 -o " +
                   theirs.string())
              .status == 0);
  CHECK(read_file(dir / "ico.obj") == read_file(theirs));
  CHECK(std::filesystem::file_size(dir / "ico.exr") > 0);
  std::filesystem::remove_all(dir);
  // One line naming the file and the member; nothing written.
  const std::string bad =
      file("bad_mesh.json", R"({"mesh": "no_such.obj", "subdivision": {"scheme": "loop"}})");
  check_error(cifs_cli("render " + bad + " -o " + (dir / "x.exr").string()), "bad_mesh.json: mesh: ");
  const std::string levels = file(
      "bad_levels.json", R"({"mesh": ")" CIFS_EXAMPLES_DIR
                         R"(/meshes/cube.obj", "subdivision": {"scheme": "catmull-clark", "levels": -2}})");
  check_error(cifs_cli("render " + levels + " -o " + (dir / "x.exr").string()),
              "bad_levels.json: subdivision.levels: -2 is outside [0, 16]");
  const std::string scheme =
      file("bad_scheme.json", R"({"mesh": ")" CIFS_EXAMPLES_DIR
                              R"(/meshes/cube.obj", "subdivision": {"scheme": "catmul-clark"}})");
  check_error(cifs_cli("render " + scheme + " -o " + (dir / "x.exr").string()),
              "bad_scheme.json: subdivision.scheme: unknown mesh scheme 'catmul-clark'");
  CHECK_FALSE(std::filesystem::exists(dir));
}
