// SPDX-License-Identifier: MIT
// Experiments run end to end: every kind of source, the OpenEXR written and read back, the
// geometry files, the perturbation's record, and bad experiments that leave no file behind.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/render/image.hpp"
#include "render/scratch.hpp"

using namespace cifs;
using render_test::ScratchDir;

namespace {

io::Experiment parse(const std::string& text) {
  io::Experiment e = io::parse_experiment(text, "t.json", CIFS_EXAMPLES_DIR "/experiments");
  if (e.name.empty()) e.name = "t";
  return e;
}

experiment::RunReport run_in(const ScratchDir& dir, const std::string& text) {
  experiment::RunOptions o;
  o.out_dir = dir.path();
  o.quiet = true;
  o.threads = 2;
  return experiment::run(parse(text), o);
}

std::size_t covered(const render::Image& image) {
  std::size_t n = 0;
  for (const float a : image.channels.at("A")) n += a > 0;
  return n;
}

}  // namespace

TEST_CASE("A NURBS curve experiment: EXR channels and header, PNG, SVG, PLY, automaton", "[experiment]") {
  ScratchDir dir;
  const auto report = run_in(dir, R"({"shape": "../shapes/wave.json", "evaluation": {"depth": 6},
      "render": {"width": 160, "height": 90, "control_net": true},
      "outputs": {"exr": "w.exr", "png": "w.png", "svg": "w.svg", "ply": "w.ply", "obj": "w.obj",
                  "automaton_svg": "a.svg", "automaton_dot": "a.dot"}})");
  CHECK(dir.files() ==
        std::vector<std::string>{"a.dot", "a.svg", "w.exr", "w.obj", "w.ply", "w.png", "w.svg"});
  CHECK(report.depth == 6);
  const render::Image image = render::read_exr(dir.path() / "w.exr");
  CHECK(image.width == 160);
  CHECK(image.height == 90);
  for (const char* c : {"R", "G", "B", "A", "Z"}) CHECK(image.channels.count(c) == 1);
  REQUIRE(image.state);
  CHECK(image.attributes.at("experiment") == "t");
  CHECK(image.attributes.at("depth") == "6");
  CHECK(image.attributes.count("seed") == 1);
  CHECK(covered(image) > 300);
  // Where the curve or the net covers a pixel, the state is a real automaton state.
  for (std::size_t i = 0; i < image.state->size(); ++i)
    if (image.channels.at("A")[i] > 0) CHECK((*image.state)[i] != 0xffffffffu);
  // The OBJ holds the 4 segments × 2^6 + 1 attractor points of the depth-6 evaluation.
  std::ifstream obj(dir.path() / "w.obj");
  std::size_t vertices = 0;
  for (std::string line; std::getline(obj, line);) vertices += line.rfind("v ", 0) == 0;
  CHECK(vertices == 4 * 64 + 1);
}

TEST_CASE("The automaton output in JSON is the evaluated automaton, readable", "[experiment]") {
  ScratchDir dir;
  run_in(dir, R"({"shape": "../shapes/wave.json", "evaluation": {"depth": 2},
      "render": {"width": 16, "height": 16}, "outputs": {"exr": "w.exr", "automaton_json": "a.json"}})");
  const automata::Automaton a = io::read_automaton(dir.path() / "a.json");
  const io::Experiment e = parse(R"({"shape": "../shapes/wave.json"})");
  const automata::Automaton knots = automata::knot_automaton(std::get<nurbs::Curve>(*e.shape));
  CHECK(io::to_json(a) == io::to_json(knots));
}

TEST_CASE("A surface experiment: normals in the EXR, watertight PLY counts", "[experiment]") {
  ScratchDir dir;
  run_in(dir, R"({"shape": "../shapes/saddle.json", "evaluation": {"depth": 3},
      "render": {"width": 64, "height": 48}, "outputs": {"exr": "s.exr", "obj": "s.obj"}})");
  const render::Image image = render::read_exr(dir.path() / "s.exr");
  for (const char* c : {"N.x", "N.y", "N.z"}) REQUIRE(image.channels.count(c) == 1);
  for (std::size_t i = 0; i < image.width * image.height; ++i) {
    if (image.channels.at("A")[i] < 1) continue;
    const double n =
        std::hypot(image.channels.at("N.x")[i], image.channels.at("N.y")[i], image.channels.at("N.z")[i]);
    CHECK(n == Approx(1).margin(1e-5));
  }
  // saddle.json has 2 × 1 patches: at depth 3 a (2·8 + 1) × (8 + 1) grid of shared vertices.
  std::ifstream obj(dir.path() / "s.obj");
  std::size_t v = 0, f = 0;
  for (std::string line; std::getline(obj, line);) {
    v += line.rfind("v ", 0) == 0;
    f += line.rfind("f ", 0) == 0;
  }
  CHECK(v == 17 * 9);
  CHECK(f == 16 * 8);
}

TEST_CASE("A perturbed curve keeps its end points; the header records the perturbation", "[experiment]") {
  ScratchDir dir;
  const auto report = run_in(dir, R"({"shape": {"polygon": "../shapes/hepta.json", "degree": 3},
      "perturbation": {"amplitude": 0.3, "seed": 5}, "evaluation": {"depth": 8},
      "render": {"width": 100, "height": 100}, "outputs": {"exr": "p.exr", "svg": "p.svg"}})");
  CHECK(report.free_coefficients > 0);
  CHECK(report.residual <= 1e-12);
  const render::Image image = render::read_exr(dir.path() / "p.exr");
  CHECK_THAT(image.attributes.at("perturbation"), Catch::Contains("seed 5"));
  CHECK(std::stod(image.attributes.at("residual")) <= 1e-12);
}

TEST_CASE("Chaos experiments: density channel; the same seed gives the same image on 1 and 2 threads",
          "[experiment]") {
  for (const char* source : {R"("ifs": "sierpinski")", R"("shape": "../shapes/wave.json")",
                             R"("automaton": "../automata/tree.json")"}) {
    std::vector<float> density[2];
    for (const unsigned threads : {1u, 2u}) {
      ScratchDir dir;
      experiment::RunOptions o;
      o.out_dir = dir.path();
      o.quiet = true;
      o.threads = threads;
      experiment::run(
          parse(std::string("{") + source +
                R"(, "evaluation": {"chaos": 200000, "seed": 9}, "render": {"width": 80, "height": 60},
                            "outputs": {"exr": "c.exr", "png": "c.png"}})"),
          o);
      const render::Image image = render::read_exr(dir.path() / "c.exr");
      REQUIRE(image.channels.count("density") == 1);
      CHECK(image.attributes.at("seed") == "9");
      density[threads - 1] = image.channels.at("density");
    }
    double total = 0;
    for (const float d : density[0]) total += d;
    CHECK(total > 0.9 * 200000);  // framed: (almost) every sample lands in the image
    CHECK(density[0] == density[1]);
  }
}

TEST_CASE("Bad experiments leave no file behind", "[experiment]") {
  ScratchDir dir;
  // Geometry export that the source cannot give: refused before anything is written.
  CHECK_THROWS_WITH(run_in(dir, R"({"ifs": "fern", "evaluation": {"chaos": 1000},
      "render": {"width": 32, "height": 32}, "outputs": {"exr": "f.exr", "png": "f.png", "obj": "f.obj"}})"),
                    Catch::Contains("outputs.obj"));
  CHECK_THROWS_WITH(run_in(dir, R"({"shape": "../shapes/saddle.json", "evaluation": {"depth": 2},
      "render": {"width": 32, "height": 32}, "outputs": {"exr": "s.exr", "svg": "s.svg"}})"),
                    Catch::Contains("outputs.svg"));
  // A perturbation so strong that the system stops contracting.
  CHECK_THROWS_WITH(run_in(dir, R"({"shape": "../shapes/wave.json", "perturbation": {"amplitude": 50},
      "render": {"width": 32, "height": 32}, "outputs": {"exr": "w.exr"}})"),
                    Catch::Contains("non-contractive"));
  // An image that would not fit in memory is refused before any work.
  CHECK_THROWS_WITH(run_in(dir, R"({"ifs": "fern", "render": {"width": 16384, "height": 16384},
      "outputs": {"exr": "big.exr"}})"),
                    Catch::Contains("GB, above the limit"));
  // 3^25 pieces of the tree: refused from the out-degrees, before any evaluation.
  CHECK_THROWS_WITH(run_in(dir, R"({"automaton": "../automata/tree.json", "evaluation": {"depth": 25},
      "render": {"width": 8, "height": 8}, "outputs": {"exr": "t.exr"}})"),
                    Catch::Contains("847288609443 pieces at depth 25"));
  CHECK_THROWS_WITH(run_in(dir, R"({"ifs": "fern", "render": {"width": 8, "height": 8}})"),
                    Catch::Contains("no image output"));
  CHECK(dir.files().empty());
}
