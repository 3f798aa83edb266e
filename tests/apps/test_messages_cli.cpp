// SPDX-License-Identifier: MIT
// Messages name what the user gave and what to do, never the routine that found the problem (issue 16
// item 13, docs/reliability.md#messages-name-what-the-user-gave): each case once printed an internal
// function name (`refine:`, `perturb:`, `edge_pieces:`, `check:`, …) through the CLI.
#include <catch2/catch.hpp>
#include <regex>

#include "apps/cli_runner.hpp"

using namespace cifs_test;

namespace {

const std::string kExamples = CIFS_EXAMPLES_DIR;

/// One stderr line, exit status 2 (check_error), the new wording, the old internal name gone, and no
/// `name:` prefix at all after "cifs: ".
void check_message(const Run& r, const std::string& wording, const std::string& old_name) {
  check_error(r, wording);
  INFO("stderr: " << r.err);
  CHECK(r.err.find(old_name) == std::string::npos);
  CHECK(!std::regex_search(r.err, std::regex("^cifs: [A-Za-z_]+: ")));
}

/// examples/experiments/tree.json with `from` replaced by `to`, and its automaton path made absolute.
std::string tree_experiment(const std::string& name, const std::string& from, const std::string& to) {
  std::string text = slurp(kExamples + "/experiments/tree.json");
  const std::string automaton = "../automata/tree.json";
  REQUIRE(text.find(automaton) != std::string::npos);
  text.replace(text.find(automaton), automaton.size(), kExamples + "/automata/tree.json");
  REQUIRE(text.find(from) != std::string::npos);
  text.replace(text.find(from), from.size(), to);
  return file(name, text);
}

std::string polygon_json(const std::string& name, const std::string& points) {
  return file(name, R"({"polygon": {"points": )" + points + R"(, "closed": false}})");
}

}  // namespace

TEST_CASE("cifs check names its depth and tolerance, not check_curve", "[cli][reliability][messages]") {
  const std::string cubic = kExamples + "/shapes/cubic.json";
  check_message(cifs_cli("check " + cubic + " --depth 31"), "the check depth 31 is outside [0, 30]",
                "check: depth");
  // An infinite tolerance would pass anything; it was printed as "(got inf)".
  check_message(cifs_cli("check " + cubic + " --relative-tolerance inf"),
                "the check tolerance is not a finite number; give a positive finite tolerance", "(got inf)");
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

TEST_CASE("cifs scheme --refine names the polygon and the steps, not refine:",
          "[cli][reliability][messages]") {
  check_message(cifs_cli("scheme four-point --refine " + polygon_json("one_point.json", "[[0, 0]]")),
                "an open polygon needs at least 2 points to refine, got 1", "refine:");
  const std::string two = polygon_json("two_points.json", "[[0, 0], [1, 1]]");
  check_message(cifs_cli("scheme four-point --refine " + two + " --steps 40"),
                "40 refinement steps of 2 points exceed the limit of 50000000 points; refine fewer steps",
                "refine:");
  check_message(cifs_cli("scheme corner-cutting --param a=0.1 --param b=0.6 --ends reflect --refine " + two),
                "the reflect end rule needs a symmetric mask (corner-cutting is not); use the keep rule",
                "refine:");
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
  const std::string camera = file("up_back.json", R"({"shape": ")" + kExamples + R"(/shapes/saddle.json",
      "evaluation": {"depth": 2}, "camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, -3]},
      "render": {"width": 8, "height": 8}})");
  check_message(
      cifs_cli("render " + camera + " -o " + (scratch() / "camera.exr").string()),
      "the camera's up (0, 0, -3) is parallel to the viewing direction from eye to target; give an up "
      "vector across it",
      "camera: up");
}
