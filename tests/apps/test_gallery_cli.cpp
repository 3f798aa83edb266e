// SPDX-License-Identifier: MIT
// cifs gallery: every example experiment run into one folder with its index page, warnings naming the
// experiment, every file checked before anything is written, --quiet.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "apps/cli_fixtures.hpp"
#include "apps/cli_runner.hpp"

#include "cifs/files.hpp"

using nlohmann::json;

using namespace cifs_test;

TEST_CASE("cifs gallery runs every example experiment", "[cli]") {
  const auto out = scratch() / "gallery";
  const Run r = cifs_cli("gallery " + out.string());  // its summary: no bar, stderr is not a terminal
  REQUIRE(r.status == 0);
  // One EXR and one PNG per experiment file, plus what each asks for.
  std::size_t experiments = 0;
  for (const auto& entry : std::filesystem::directory_iterator(CIFS_EXAMPLES_DIR "/experiments"))
    experiments += entry.path().extension() == ".json";
  std::size_t exr = 0, png = 0;
  for (const auto& entry : std::filesystem::directory_iterator(out)) {
    exr += entry.path().extension() == ".exr";
    png += entry.path().extension() == ".png";
  }
  CHECK(experiments >= 10);
  CHECK(exr == experiments);
  CHECK(png == experiments);
  for (const char* name : {"wave.automaton.svg", "hills.ply", "tree.svg", "schemes/lr_bone_degree3.svg",
                           "junction_curves.svg", "junction_surfaces.ply", "junction_fractal.ply"})
    CHECK(std::filesystem::is_regular_file(out / name));
  CHECK_THAT(r.out, Catch::Contains("wave-fractal: NURBS curve") && Catch::Contains("free coefficients"));
  // The three junctions of docs/junctions.md, each with its residual.
  for (const char* name :
       {"junction-curves: junction of a b-spline(degree = 3) curve and a four-point curve",
        "junction-surfaces: junction of a b-spline(degree = 3) surface and a b-spline(degree = 2)",
        "junction-fractal: junction of a rational NURBS surface and a rational NURBS surface"})
    CHECK_THAT(r.out, Catch::Contains(name));
  // The five mesh schemes on the example meshes: closed, open (boundary) and genus 1.
  for (const char* name :
       {"subdivision_cube_catmull_clark", "subdivision_cube_doo_sabin", "subdivision_tetrahedron_loop",
        "subdivision_tetrahedron_butterfly", "subdivision_tetrahedron_sqrt3", "subdivision_open_grid",
        "subdivision_open_grid_triangles", "subdivision_torus", "subdivision_rings_loop"})
    for (const char* ext : {".exr", ".png", ".obj"})
      CHECK(std::filesystem::is_regular_file(out / (std::string(name) + ext)));
  CHECK_THAT(r.out, Catch::Contains(
                        "subdivision-torus: catmull-clark subdivision of torus.obj, 3 levels, 6144 faces") &&
                        Catch::Contains("sqrt3 subdivision of tetrahedron.obj, 6 levels"));
  // index.html: every experiment's description (read here from its file), every image the gallery
  // wrote shown, every other file linked, relative to the folder (the shipped names need no encoding).
  const std::string page = cifs::read_file(out / "index.html");
  for (const auto& entry : std::filesystem::directory_iterator(CIFS_EXAMPLES_DIR "/experiments")) {
    if (entry.path().extension() != ".json") continue;
    std::string expected;
    for (const char c : json::parse(cifs::read_file(entry.path()))["description"].get<std::string>())
      expected += c == '\''  ? std::string("&#39;")
                  : c == '"' ? std::string("&quot;")
                  : c == '&' ? std::string("&amp;")
                  : c == '<' ? std::string("&lt;")
                  : c == '>' ? std::string("&gt;")
                             : std::string(1, c);
    CHECK_THAT(page, Catch::Contains("<p>" + expected + "</p>"));
  }
  std::size_t images = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(out)) {
    if (!entry.is_regular_file() || entry.path().filename() == "index.html") continue;
    const std::string name = entry.path().lexically_relative(out).generic_string();
    const bool image = entry.path().extension() == ".png" || entry.path().extension() == ".svg";
    images += image;
    INFO(name);
    CHECK_THAT(page, Catch::Contains((image ? "src=\"" : "href=\"") + name + "\""));
  }
  CHECK(images >= 2 * experiments);
  CHECK_THAT(r.out, Catch::Contains("gallery: wrote " + (out / "index.html").string()));
  std::filesystem::remove_all(out);
  // A wrong examples folder is one clear error.
  check_error(cifs_cli("gallery " + out.string() + " --examples /no/such/folder"), "/no/such/folder");
}

TEST_CASE("cifs gallery says what an experiment's output drops, naming the experiment", "[cli]") {
  // An examples folder of one experiment: a 3-D cubic drawn as SVG (the SVG keeps x and y only).
  const auto examples = scratch() / "gallery_warn_examples";
  std::filesystem::create_directories(examples / "experiments");
  for (const char* sub : {"shapes", "polygons", "meshes"})
    std::filesystem::create_directory_symlink(std::filesystem::path(CIFS_EXAMPLES_DIR) / sub, examples / sub);
  cifs::write_file_atomically(examples / "experiments" / "flat.json",
                              R"({"name": "flat", "shape": "../shapes/cubic.json", "evaluation": {"depth": 4},
                                  "render": {"width": 32, "height": 24},
                                  "outputs": {"exr": "flat.exr", "svg": "flat.svg"}})");
  const auto out = scratch() / "gallery_warn";
  const Run r = cifs_cli("gallery " + out.string() + " --examples " + examples.string() + " --quiet");
  REQUIRE(r.status == 0);
  CHECK(std::filesystem::is_regular_file(out / "flat.svg"));
  CHECK_THAT(r.err, Catch::Contains("cifs: warning: flat.json: outputs.svg: "));
  // The same experiment through cifs render says it too (the gallery adds the file's name).
  const Run one = cifs_cli("render " + (examples / "experiments" / "flat.json").string() + " --out-dir " +
                           out.string() + " -o " + (out / "one.exr").string() + " --quiet");
  REQUIRE(one.status == 0);
  CHECK_THAT(one.err, Catch::Contains("cifs: warning: outputs.svg: "));
}

TEST_CASE("cifs gallery checks every experiment before it writes anything", "[cli][reliability]") {
  // An invalid later file left the outputs of the earlier ones, and an empty OUT/ (issue 33).
  const auto examples = scratch() / "gallery_examples";
  std::filesystem::create_directories(examples / "experiments");
  file("gallery_examples/experiments/a.json",
       R"({"name": "a", "ifs": "sierpinski", "evaluation": {"depth": 3},
      "render": {"width": 16, "height": 16}, "outputs": {"png": "a.png"}})");
  file("gallery_examples/experiments/b.json",
       R"({"name": "b", "ifs": "sierpinski", "evaluation": {"depht": 3}})");
  // Not the --quiet case's gallery_out: both run in one process, in one scratch folder.
  const auto out = scratch() / "gallery_checked_out";
  check_error(cifs_cli("gallery " + out.string() + " --examples " + examples.string() + " --quiet"),
              "b.json: evaluation.depht: unknown member");
  CHECK(!std::filesystem::exists(out));
}

// The installed cifs reads the installed examples: tests/package/run.cmake.
TEST_CASE("cifs gallery: the build tree's cifs defaults to the source tree's examples", "[cli][newuser]") {
  const Run r = cifs_cli("gallery --help");
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("(default: " CIFS_EXAMPLES_DIR ":"));
}

TEST_CASE("cifs gallery --quiet prints nothing but errors and warnings", "[cli][frictions]") {
  const auto examples = scratch() / "quiet_gallery_examples";
  std::filesystem::create_directories(examples / "experiments");
  std::filesystem::create_directory_symlink(kExamplesDir + "/shapes", examples / "shapes");
  std::ofstream(examples / "experiments" / "wave.json")
      << R"({"shape": "../shapes/wave.json", "evaluation": {"depth": 4},
      "render": {"width": 32, "height": 32}, "outputs": {"png": "wave.png"}})";
  const auto out = scratch() / "gallery_out";
  const Run quiet = cifs_cli("gallery " + out.string() + " --examples " + examples.string() + " --quiet");
  INFO(quiet.err);
  CHECK(quiet.status == 0);
  CHECK(quiet.out.empty());
  CHECK(quiet.err.empty());
  CHECK(std::filesystem::exists(out / "index.html"));
  const Run loud = cifs_cli("gallery " + out.string() + " --examples " + examples.string());
  CHECK(loud.status == 0);
  CHECK_THAT(loud.out, Catch::Contains("gallery: wrote"));
}
