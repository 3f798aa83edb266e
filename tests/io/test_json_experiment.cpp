// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <filesystem>

#include "cifs/errors.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"

using namespace cifs;

namespace {

io::Experiment parse_experiment_text(const std::string& text) {
  return io::parse_experiment(text, "e.json", CIFS_SOURCE_DIR "/examples/shapes");
}

std::string experiment_error_of(const std::string& text) {
  try {
    parse_experiment_text(text);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

const std::string kCurveShape =
    R"("shape": {"curve": {"degree": 1, "knots": [0, 0, 1, 1], "points": [[0, 0], [1, 0]]}})";

}  // namespace

TEST_CASE("Experiments: every section read with its defaults", "[io][experiment]") {
  const io::Experiment e = parse_experiment_text("{" + kCurveShape + R"(,
      "perturbation": {"amplitude": 0.1, "seed": 7, "values": {"G[1,2]": 0.25}},
      "evaluation": {"chaos": 1000, "seed": 3},
      "camera": {"projection": "perspective", "eye": [1, 2, 3], "target": [0, 0, 0], "fov": 20},
      "render": {"width": 64, "height": 32, "line_width": 1.5, "color": [1, 0, 0], "threads": 2},
      "outputs": {"exr": "a.exr", "png": "img/a.png", "obj": "a.obj"}})");
  REQUIRE(e.shape);
  CHECK(std::holds_alternative<nurbs::Curve>(*e.shape));
  REQUIRE(e.perturbation);
  CHECK(e.perturbation->amplitude == 0.1);
  CHECK(e.perturbation->seed == 7);
  CHECK(e.perturbation->values.at("G[1,2]") == 0.25);
  CHECK(e.perturbation->keep_vertices);
  CHECK(e.evaluation.mode == io::EvaluationSpec::Mode::chaos);
  CHECK(e.evaluation.samples == 1000);
  CHECK(e.evaluation.seed == 3);
  CHECK(e.camera.projection == io::CameraSpec::Projection::perspective);
  CHECK(*e.camera.eye == std::array<double, 3>{1, 2, 3});
  CHECK(e.camera.fov_degrees == 20);
  CHECK(e.render.width == 64);
  CHECK(e.render.height == 32);
  CHECK(e.render.threads == 2);
  CHECK(e.render.background == std::array<double, 3>{1, 1, 1});
  CHECK(e.outputs.png == std::filesystem::path("img/a.png"));
  CHECK(e.outputs.geometry.count("ply") == 0);

  const io::Experiment b = parse_experiment_text(R"({"shape": {"polygon": "bone.json", "degree": 3}})");
  REQUIRE(b.shape);
  CHECK(std::get<nurbs::Curve>(*b.shape).closed);
  CHECK(std::get<nurbs::Curve>(*b.shape).degree == 3);

  const io::Experiment d = parse_experiment_text(R"({"ifs": "fern"})");
  REQUIRE(d.ifs);
  CHECK(d.ifs->name == "fern");
  CHECK(d.evaluation.mode == io::EvaluationSpec::Mode::depth);
  CHECK(d.camera.projection == io::CameraSpec::Projection::automatic);
  const io::Experiment m =
      parse_experiment_text(R"({"ifs": {"maps": [[0.5, 0, 0, 0.5, 0, 0], [0.5, 0, 0, 0.5, 0.5, 0, 2]]}})");
  REQUIRE(m.ifs);
  CHECK(m.ifs->maps[0][6] == 1);
  CHECK(m.ifs->maps[1][6] == 2);
}

TEST_CASE("Experiments: bad files name the file, the member and the problem", "[io][experiment]") {
  CHECK_THAT(experiment_error_of("{"), Catch::StartsWith("e.json: malformed JSON"));
  CHECK_THAT(experiment_error_of("[]"), Catch::Contains("expected an experiment object"));
  CHECK_THAT(experiment_error_of("{}"), Catch::Contains("exactly one of \"shape\", \"automaton\", \"ifs\""));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "evaluation": {"depth": 3}, "colour": 1})"),
             Catch::Contains("e.json: colour: unknown member"));
  // In every section: a misspelt option must not fall back to its default silently.
  for (const auto& [section, typo] : {std::pair{"evaluation", R"("depth": 3, "sed": 1)"},
                                      {"camera", R"("fov": 20, "eyes": [1, 1, 1])"},
                                      {"render", R"("width": 8, "hieght": 8)"},
                                      {"perturbation", R"("amplitude": 0.1, "keep_vertex": true)"}})
    CHECK_THAT(
        experiment_error_of("{" + kCurveShape + ", " +
                            (section == std::string("evaluation") ? "" : R"("evaluation": {"depth": 3}, )") +
                            "\"" + section + "\": {" + typo + "}}"),
        Catch::Contains(std::string("e.json: ") + section + ".") && Catch::Contains(": unknown member"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "evaluation": {"depth": 31}})"),
             Catch::Contains("evaluation.depth: 31 is outside [0, 30]"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "evaluation": {"depth": 3, "chaos": 5}})"),
             Catch::Contains("evaluation: expected exactly one"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "evaluation": {"chaos": -5}})"),
             Catch::Contains("evaluation.chaos: expected a non-negative integer"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "evaluation": {"chaos": 9007199254740992}})"),
             Catch::Contains("above the limit"));
  CHECK_NOTHROW(parse_experiment_text(R"({"ifs": "fern", "evaluation": {"chaos": 9007199254740991}})"));
  // Seeds outside 0 … 2^64 − 1 or not integers are refused, not clamped to 2^64 − 1 (issue 16 defect 10).
  for (const std::string seed : {"-1", "18446744073709551616", "1e23", "1.5", "\"7\""}) {
    CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "evaluation": {"chaos": 5, "seed": )" + seed + "}}"),
               Catch::Contains("e.json: evaluation.seed: expected a non-negative integer"));
    std::string perturbation = "{" + kCurveShape;
    perturbation += R"(, "perturbation": {"seed": )" + seed + "}}";
    CHECK_THAT(experiment_error_of(perturbation),
               Catch::Contains("e.json: perturbation.seed: expected a non-negative integer"));
  }
  CHECK(parse_experiment_text(R"({"ifs": "fern", "evaluation": {"chaos": 5, "seed": 18446744073709551615}})")
            .evaluation.seed == 18446744073709551615ULL);
  CHECK_THAT(experiment_error_of(R"({"ifs": "fractal"})"), Catch::Contains("ifs: unknown IFS \"fractal\""));
  CHECK_THAT(experiment_error_of(R"({"ifs": {"maps": [[1, 2, 3]]}})"),
             Catch::Contains("ifs.maps[0]: expected [a, b"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "perturbation": {}})"),
             Catch::Contains("perturbation: a classic IFS"));
  CHECK_THAT(experiment_error_of("{" + kCurveShape + R"(, "perturbation": {"amplitude": -1}})"),
             Catch::Contains("perturbation.amplitude: expected a number ≥ 0"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "camera": {"projection": "fisheye"}})"),
             Catch::Contains("camera.projection: expected"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "camera": {"eye": [1, 1, 1], "target": [1, 1, 1]}})"),
             Catch::Contains("camera: eye and target coincide"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "render": {"width": 0}})"),
             Catch::Contains("render.width: 0 is outside [1, 16384]"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "render": {"color": [2, 0, 0]}})"),
             Catch::Contains("render.color: colour components"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "outputs": {"exr": "../x.exr"}})"),
             Catch::Contains("outputs.exr: \"..\" would leave the output directory"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "outputs": {"png": "/tmp/x.png"}})"),
             Catch::Contains("outputs.png: expected a relative file name"));
  CHECK_THAT(experiment_error_of(R"({"shape": "no/such/shape.json"})"), Catch::Contains("e.json: shape: "));
  CHECK_THAT(experiment_error_of(R"({"shape": {"curve": {"degree": 0}}})"),
             Catch::Contains("e.json: shape: "));
  CHECK_THAT(experiment_error_of(R"({"shape": {"polygon": "bone.json", "degree": 0}})"),
             Catch::Contains("e.json: shape: degree"));
  CHECK_THAT(experiment_error_of(R"({"automaton": "missing.json"})"),
             Catch::Contains("automaton: no such file"));
}

TEST_CASE("Experiments: output keys are the formats of the format table", "[io][experiment]") {
  const io::Experiment e =
      parse_experiment_text(R"({"ifs": "fern", "outputs": {"obj": "g.obj", "ply": "g.ply", "svg": "g.svg",
      "automaton_json": "a.json", "automaton_dot": "a.dot", "automaton_svg": "a.svg"}})");
  CHECK(e.outputs.geometry ==
        std::map<std::string, std::filesystem::path>{{"obj", "g.obj"}, {"ply", "g.ply"}, {"svg", "g.svg"}});
  CHECK(e.outputs.automaton ==
        std::map<std::string, std::filesystem::path>{{"json", "a.json"}, {"dot", "a.dot"}, {"svg", "a.svg"}});
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "outputs": {"automaton_obj": "a.obj"}})"),
             Catch::Contains("outputs.automaton_obj: unknown member"));
  CHECK_THAT(experiment_error_of(R"({"ifs": "fern", "outputs": {"dot": "g.dot"}})"),
             Catch::Contains("outputs.dot: unknown member"));
}

TEST_CASE("Experiments: a polygon mesh and its subdivision scheme", "[io][experiment][mesh]") {
  const io::Experiment e = parse_experiment_text(R"({"mesh": "../meshes/open_grid.obj",
      "subdivision": {"scheme": "doo-sabin", "levels": 2, "boundary": "corner"}, "render": {"control_net": true}})");
  REQUIRE(e.mesh);
  CHECK_FALSE(e.shape);
  CHECK(e.mesh->path.filename() == "open_grid.obj");
  CHECK(e.mesh->mesh.vertices.rows() == 35);
  CHECK(e.mesh->scheme == subdivision::MeshScheme::doo_sabin);
  CHECK(e.mesh->levels == 2);
  CHECK(e.mesh->mesh.tags.boundary == BoundaryRule::edge_and_corner);
  CHECK(e.render.control_net);
  // Defaults: 3 levels, the edge rule.
  const io::Experiment d =
      parse_experiment_text(R"({"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "catmull-clark"}})");
  CHECK(d.mesh->levels == 3);
  CHECK(d.mesh->mesh.tags.boundary == BoundaryRule::edge_only);
}

TEST_CASE("Experiments: bad mesh sources are one line naming the file and the member",
          "[io][experiment][mesh]") {
  const std::string cube = R"("mesh": "../meshes/cube.obj")";
  const auto one_line = [](const std::string& message, const std::string& expected) {
    CHECK_THAT(message, Catch::StartsWith("e.json: ") && Catch::Contains(expected));
    CHECK(message.find('\n') == std::string::npos);
  };
  one_line(experiment_error_of("{" + cube + R"(, "subdivision": {"scheme": "kobbelt"}})"),
           "e.json: subdivision.scheme: unknown mesh scheme 'kobbelt' (catmull-clark, loop");
  one_line(experiment_error_of("{" + cube + R"(, "subdivision": {"scheme": "loop", "levels": 2}})"),
           "subdivision.scheme: loop refines triangles only; cube.obj has a face of 4 corners (face 0)");
  one_line(experiment_error_of("{" + cube + R"(, "subdivision": {"scheme": "catmull-clark", "levels": -1}})"),
           "e.json: subdivision.levels: -1 is outside [0, 16]");
  one_line(experiment_error_of("{" + cube +
                               R"(, "subdivision": {"scheme": "catmull-clark", "boundary": "crease"}})"),
           "e.json: subdivision.boundary: unknown boundary rule 'crease' (none, edge, corner)");
  one_line(experiment_error_of("{" + cube + R"(, "subdivision": {"scheme": "catmull-clark", "level": 2}})"),
           "e.json: subdivision.level: unknown member");
  one_line(experiment_error_of("{" + cube + R"(, "subdivision": {"levels": 2}})"),
           "e.json: subdivision: missing \"scheme\"");
  one_line(experiment_error_of("{" + cube + "}"), "e.json: missing \"subdivision\"");
  one_line(experiment_error_of(R"({"mesh": "../meshes/no_such.obj", "subdivision": {"scheme": "loop"}})"),
           "e.json: mesh: ");
  CHECK_THAT(experiment_error_of(R"({"mesh": "../meshes/no_such.obj", "subdivision": {"scheme": "loop"}})"),
             Catch::Contains("no_such.obj"));
  one_line(experiment_error_of("{" + cube + ", " + kCurveShape +
                               R"(, "subdivision": {"scheme": "catmull-clark"}})"),
           "e.json: expected exactly one of \"shape\", \"automaton\", \"ifs\", \"mesh\"");
  one_line(experiment_error_of("{" + kCurveShape + R"(, "subdivision": {"scheme": "loop"}})"),
           "e.json: subdivision: only with a \"mesh\" source");
  one_line(experiment_error_of(
               "{" + cube + R"(, "subdivision": {"scheme": "catmull-clark"}, "evaluation": {"depth": 2}})"),
           "e.json: evaluation: a mesh is refined by subdivision.levels");
  // Fractal subdivision surfaces and limit surfaces are Catmull–Clark's and Loop's.
  one_line(
      experiment_error_of(
          R"({"mesh": "../meshes/tetrahedron.obj", "subdivision": {"scheme": "butterfly"}, "perturbation": {}})"),
      "e.json: perturbation: fractal subdivision surfaces are built for catmull-clark and loop, not "
      "butterfly");
  CHECK(parse_experiment_text(
            R"({"mesh": "../meshes/tetrahedron.obj", "subdivision": {"scheme": "loop"}, "perturbation": {}})")
            .perturbation);
  one_line(experiment_error_of(
               "{" + cube +
               R"(, "subdivision": {"scheme": "catmull-clark"}, "perturbation": {"keep_vertices": false}})"),
           "e.json: perturbation.keep_vertices: NURBS sources only: a mesh's face boundaries always stay");
  one_line(
      experiment_error_of(
          "{" + cube + R"(, "subdivision": {"scheme": "catmull-clark", "limit": true}, "perturbation": {}})"),
      "e.json: perturbation: a fractal surface has no limit normals (drop subdivision.limit)");
  one_line(
      experiment_error_of(
          R"({"mesh": "../meshes/tetrahedron.obj", "subdivision": {"scheme": "butterfly", "limit": true}})"),
      "e.json: subdivision.limit: limit surfaces are built for catmull-clark and loop, not butterfly");
  CHECK(parse_experiment_text("{" + cube + R"(, "subdivision": {"scheme": "catmull-clark", "limit": true}})")
            .mesh->limit);
  one_line(experiment_error_of(R"({"mesh": "../shapes/hills.json", "subdivision": {"scheme": "loop"}})"),
           "e.json: mesh: ");
  // Fractal crease and boundary curves: members checked, the curves asked for must exist.
  const std::string torus =
      R"("mesh": "../meshes/creased_torus.obj", "subdivision": {"scheme": "catmull-clark"})";
  const io::Experiment creases = parse_experiment_text(
      "{" + torus +
      R"(, "perturbation": {"fractal_curves": {"amplitude": 0.5, "seed": 4, "values": {"a": 1}}}})");
  REQUIRE(creases.perturbation->fractal_curves);
  CHECK(creases.perturbation->fractal_curves->creases);
  CHECK_FALSE(creases.perturbation->fractal_curves->boundaries);
  CHECK(creases.perturbation->fractal_curves->amplitude == 0.5);
  CHECK(creases.perturbation->fractal_curves->seed == 4);
  CHECK(creases.perturbation->fractal_curves->values.at("a") == 1);
  one_line(experiment_error_of("{" + torus + R"(, "perturbation": {"fractal_curves": {"crease": true}}})"),
           "e.json: perturbation.fractal_curves.crease: unknown member");
  one_line(experiment_error_of("{" + torus + R"(, "perturbation": {"fractal_curves": {"creases": false}}})"),
           "e.json: perturbation.fractal_curves: neither creases nor boundaries: drop it");
  one_line(experiment_error_of("{" + torus + R"(, "perturbation": {"fractal_curves": {"amplitude": -1}}})"),
           "e.json: perturbation.fractal_curves.amplitude: expected a number ≥ 0");
  one_line(
      experiment_error_of("{" + cube + R"(, "subdivision": {"scheme": "catmull-clark"}, )" +
                          R"("perturbation": {"fractal_curves": {}}})"),
      "e.json: perturbation.fractal_curves.creases: cube.obj has no infinitely sharp crease (sharpness ≥ 10; "
      "semi-sharp creases stay smooth)");
  one_line(
      experiment_error_of("{" + torus + R"(, "perturbation": {"fractal_curves": {"boundaries": true}}})"),
      "e.json: perturbation.fractal_curves.boundaries: creased_torus.obj is closed: it has no boundary");
  one_line(experiment_error_of("{" + kCurveShape + R"(, "perturbation": {"fractal_curves": {}}})"),
           "e.json: perturbation.fractal_curves: mesh sources only (a mesh's creases and boundaries)");
}

TEST_CASE("Experiments list every file they read, so that no output overwrites one", "[io][experiment]") {
  const std::filesystem::path experiments = CIFS_SOURCE_DIR "/examples/experiments";
  const auto inputs = [&](const std::string& name) {
    return io::read_experiment(experiments / (name + ".json")).inputs;
  };
  using Paths = std::vector<std::filesystem::path>;
  CHECK(inputs("tree") == Paths{experiments / "tree.json", experiments / "../automata/tree.json"});
  CHECK(inputs("wave") == Paths{experiments / "wave.json", experiments / "../shapes/wave.json"});
  CHECK(inputs("bone") == Paths{experiments / "bone.json", experiments / "../shapes/bone.json"});
  CHECK(inputs("subdivision_torus") ==
        Paths{experiments / "subdivision_torus.json", experiments / "../meshes/torus.obj"});
  CHECK(inputs("fern") == Paths{experiments / "fern.json"});
}

TEST_CASE("Experiments: a junction of two sides, and bad descriptions one line each",
          "[io][experiment][junction]") {
  const std::string a = R"("a": {"scheme": "b-spline", "parameters": {"degree": 3}, "window": 6,
      "points": [[0, 0], [1, 1], [2, 0], [3, 1], [4, 0], [5, 1], [6, 0]], "boundary": "end"})";
  const std::string b4 =
      R"("scheme": "four-point", "window": 6, "points": [[4, 0], [5, 1], [6, 0], [7, 1], [8, 0], [9, 1]])";
  const io::Experiment e =
      parse_experiment_text(R"({"junction": {)" + a + R"(, "b": {)" + b4 +
                            R"(, "layer": 3, "boundary": "start", "color": [1, 0.5, 0]}}})");
  REQUIRE(e.junction);
  CHECK(e.junction->a.scheme->name == "b-spline");
  CHECK(e.junction->a.window == 6);
  CHECK(e.junction->a.points.rows() == 7);
  CHECK(e.junction->a.columns == 0);
  CHECK(e.junction->b.layer == 3);
  CHECK(e.junction->b.color == std::array<double, 3>{1, 0.5, 0});
  // A grid: lines of constant v; a NURBS side from a shape file, which becomes an input.
  const io::Experiment s =
      parse_experiment_text(R"({"junction": {"a": {"shape": "saddle.json", "boundary": "uend"},
      "b": {"scheme": "b-spline", "boundary": "ustart", "free": true,
            "points": [[[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]], [[1, 0, 0], [1, 1, 0], [1, 2, 0], [1, 3, 0]],
                       [[2, 0, 0], [2, 1, 0], [2, 2, 0], [2, 3, 0]], [[3, 0, 0], [3, 1, 0], [3, 2, 0], [3, 3, 0]],
                       [[4, 0, 0], [4, 1, 0], [4, 2, 0], [4, 3, 0]]]}}})");
  CHECK(s.junction->b.rows == 5);
  CHECK(s.junction->b.columns == 4);
  CHECK(s.junction->b.free);
  CHECK(std::holds_alternative<nurbs::Surface>(*s.junction->a.shape));
  CHECK(s.inputs.back().filename() == "saddle.json");

  const auto one_line = [](const std::string& message, const std::string& expected) {
    CHECK_THAT(message, Catch::StartsWith("e.json: ") && Catch::Contains(expected));
    CHECK(message.find('\n') == std::string::npos);
  };
  const auto with_b = [&](const std::string& b, const std::string& rest = "") {
    return experiment_error_of(R"({"junction": {)" + a + R"(, "b": {)" + b + "}}" + rest + "}");
  };
  one_line(with_b(b4), "junction.b: missing \"boundary\"");
  one_line(with_b(b4 + R"(, "boundary": "ustart")"),
           "junction.b.boundary: \"ustart\": expected \"start\" or \"end\" (a curve)");
  one_line(with_b(b4 + R"(, "boundary": "end", "layer": 2)"),
           "junction.b.layer: the junction layer lies at the start");
  one_line(with_b(R"("scheme": "five-point", "points": [[0, 0]], "boundary": "start")"),
           "junction.b.scheme: ");
  one_line(with_b(R"("scheme": "four-point", "window": 6, "points": [[0, 0], [1, 0]], "boundary": "start")"),
           "junction.b.points: 2 points; cells of 6 points need at least 6");
  one_line(with_b(R"("scheme": "four-point", "window": 3, "points": [[0, 0]], "boundary": "start")"),
           "junction.b.window: 3 is below the scheme's support 6");
  one_line(with_b(R"("scheme": "four-point", "boundary": "start")"), "junction.b: missing \"points\"");
  one_line(with_b(R"("shape": "saddle.json", "scheme": "four-point", "boundary": "start")"),
           "junction.b: expected exactly one of \"shape\"");
  one_line(with_b(R"("shape": "saddle.json", "points": [[0, 0]], "boundary": "ustart")"),
           "junction.b.points: only with \"scheme\"");
  one_line(with_b(R"("shape": "saddle.json", "boundary": "ustart")"),
           "junction: A is a curve and B a surface");
  one_line(with_b(b4 + R"(, "boundary": "start", "colour": [1, 0, 0])"), "junction.b.colour: unknown member");
  one_line(
      with_b(
          R"("scheme": "four-point", "points": [[[0, 0, 0], [1, 0, 0]], [[0, 1, 0]]], "boundary": "ustart")"),
      "junction.b.points[1]: 1 points, the first line has 2");
  one_line(
      with_b(
          R"("scheme": "four-point", "points": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0], [4, 0, 0], [5, 0, 0], [6, 0, 0]], "boundary": "start")"),
      "junction: A has 2 coordinates and B 3");
  one_line(with_b(b4 + R"(, "boundary": "start")", R"(, "perturbation": {"keep_vertices": false})"),
           "perturbation.keep_vertices: a junction's sides say which matrices are free");
  one_line(with_b(b4 + R"(, "boundary": "start")", R"(, "evaluation": {"relative_piece_size": 0.01})"),
           "evaluation.relative_piece_size: a junction is evaluated to a depth or by the chaos game");
  one_line(experiment_error_of(R"({"junction": {)" + a + "}}"), "junction: missing \"b\"");
  one_line(experiment_error_of(R"({"junction": {)" + a + R"(, "b": {}, "c": {}}})"),
           "junction.c: unknown member");
  one_line(experiment_error_of(R"({"junction": {)" + a + R"(, "b": {}}, "ifs": "fern"})"),
           "expected exactly one of \"shape\", \"automaton\", \"ifs\", \"mesh\", \"junction\"");
}
