// SPDX-License-Identifier: MIT
// A new user's frictions (issue 32): image paths that name another format, geometry outputs refused
// before the work, "did you mean" for mistyped options, commands and scheme names, a quiet gallery.
#include <catch2/catch.hpp>

#include "apps/cli_runner.hpp"

using namespace cifs_test;

namespace {

const std::string kFrictionExamples = CIFS_EXAMPLES_DIR;
const std::string kWave = kFrictionExamples + "/shapes/wave.json";
const std::string kCube = kFrictionExamples + "/meshes/cube.obj";

/// A small experiment of the wave curve in the scratch folder (its shape path absolute).
std::string wave_experiment(const std::string& name, const std::string& outputs) {
  return file(name, R"({"shape": ")" + kWave + R"(", "evaluation": {"depth": 4},
      "render": {"width": 32, "height": 32}, "outputs": {)" +
                        outputs + "}}");
}

}  // namespace

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

TEST_CASE("Mistyped options, commands and scheme names get a suggestion", "[cli][frictions]") {
  check_error(cifs_cli("subdivide " + kCube + " --scheme catmull-clark --level 2"),
              "unknown option '--level' of subdivide; did you mean --levels?");
  check_error(cifs_cli("subdivide " + kCube + " --scheme catmull_clark"),
              "unknown mesh scheme 'catmull_clark'; did you mean catmull-clark?");
  check_error(cifs_cli("scheme catmul-clark --valence 5 --analyze"),
              "unknown scheme 'catmul-clark'; did you mean catmull-clark?");
  check_error(cifs_cli("scheme chaikn --analyze"), "unknown scheme 'chaikn'; did you mean chaikin?");
  check_error(cifs_cli("evl " + kWave), "unknown command 'evl'; did you mean eval?");
  // A second value after an option that takes one: the option and what it takes, not "not expected".
  const Run at = cifs_cli("eval " + kWave + " --at 0.5 0.5");
  check_error(at, "eval: unexpected argument '0.5' after --at 0.5: --at takes one value");
  CHECK_THAT(at.err, Catch::Contains("U,V"));
}

TEST_CASE("cifs gallery --quiet prints nothing but errors and warnings", "[cli][frictions]") {
  const auto examples = scratch() / "quiet_gallery_examples";
  std::filesystem::create_directories(examples / "experiments");
  std::filesystem::create_directory_symlink(kFrictionExamples + "/shapes", examples / "shapes");
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

TEST_CASE("cifs --version is the project's version", "[cli][frictions]") {
  const std::string cmake = slurp(CIFS_SOURCE_DIR "/CMakeLists.txt");
  const auto start = cmake.find("project(cifs VERSION ") + std::string("project(cifs VERSION ").size();
  REQUIRE(start > 30);
  CHECK(cifs_cli("--version").out == "cifs " + cmake.substr(start, cmake.find(' ', start) - start) + "\n");
}

TEST_CASE("A parameter or knot outside the domain names the shape file", "[cli][frictions][messages]") {
  const std::string hills = kFrictionExamples + "/shapes/hills.json";
  check_error(cifs_cli("eval " + hills + " --at -0.5,0.5"),
              "cifs: " + hills + ": parameter u = -0.5 is outside");
  check_error(cifs_cli("eval " + kWave + " --at 7"),
              "cifs: " + kWave + ": parameter 7 is outside the domain");
  check_error(cifs_cli("insert " + kWave + " --knot 9"), "cifs: " + kWave + ": knot 9 is outside the domain");
}

TEST_CASE("Extensions are read in any case: .OBJ, .JSON, .PLY, .PNG", "[cli][frictions]") {
  // Files from Windows tools often carry upper-case extensions; the format is the same.
  const auto cube = scratch() / "CUBE.OBJ", ply = scratch() / "OUT.PLY";
  std::filesystem::copy_file(kCube, cube, std::filesystem::copy_options::overwrite_existing);
  const Run sub =
      cifs_cli("subdivide " + cube.string() + " --scheme catmull-clark --levels 1 -o " + ply.string());
  INFO(sub.err);
  REQUIRE(sub.status == 0);
  CHECK(slurp(ply).rfind("ply\n", 0) == 0);
  const auto wave = scratch() / "WAVE.JSON";
  std::filesystem::copy_file(kWave, wave, std::filesystem::copy_options::overwrite_existing);
  const Run info = cifs_cli("info " + wave.string());
  INFO(info.err);
  CHECK(info.status == 0);
  CHECK_THAT(info.out, Catch::Contains("\"curve\""));
  const std::string e = wave_experiment("upper.json", R"("png": "UPPER.PNG")");
  const Run render = cifs_cli("render " + e + " --out-dir " + scratch().string() + " --quiet");
  INFO(render.err);
  CHECK(render.status == 0);
  CHECK(std::filesystem::exists(scratch() / "UPPER.PNG"));
}
