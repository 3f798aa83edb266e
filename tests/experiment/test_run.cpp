// SPDX-License-Identifier: MIT
// Experiments run end to end: every kind of source, the OpenEXR written and read back, the
// geometry files, the perturbation's record, and bad experiments that leave no file behind.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/junction.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/render/image.hpp"
#include "cifs/subdivision/ifs.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/topology.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using cifs_test::ScratchDir;

namespace {

io::Experiment parse_named_experiment(const std::string& text) {
  io::Experiment e = io::parse_experiment(text, "t.json", CIFS_EXAMPLES_DIR "/experiments");
  if (e.name.empty()) e.name = "t";
  return e;
}

experiment::RunReport run_in(const ScratchDir& dir, const std::string& text) {
  experiment::RunOptions o;
  o.out_dir = dir.path();
  o.quiet = true;
  o.threads = 2;
  return experiment::run(parse_named_experiment(text), o);
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
  CHECK(dir.names() == std::set<std::string>{"a.dot", "a.svg", "w.exr", "w.obj", "w.ply", "w.png", "w.svg"});
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
  const nurbs::KnotAutomaton a = io::read_automaton(dir.path() / "a.json");
  const io::Experiment e = parse_named_experiment(R"({"shape": "../shapes/wave.json"})");
  const nurbs::KnotAutomaton knots = nurbs::knot_automaton(std::get<nurbs::Curve>(*e.shape));
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
          parse_named_experiment(
              std::string("{") + source +
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
                    Catch::Contains("the perturbed system is not contractive with amplitude 50"));
  // An image that would not fit in memory is refused before any work.
  CHECK_THROWS_WITH(run_in(dir, R"({"ifs": "fern", "render": {"width": 16384, "height": 16384},
      "outputs": {"exr": "big.exr"}})"),
                    Catch::Contains("GB, above the limit"));
  // 3^25 pieces of the tree: refused from the out-degrees, before any evaluation.
  CHECK_THROWS_WITH(run_in(dir, R"({"automaton": "../automata/tree.json", "evaluation": {"depth": 25},
      "render": {"width": 8, "height": 8}, "outputs": {"exr": "t.exr"}})"),
                    Catch::Contains("847288609443 edge pieces at depth 25"));
  CHECK_THROWS_WITH(run_in(dir, R"({"ifs": "fern", "render": {"width": 8, "height": 8}})"),
                    Catch::Contains("no output"));
  CHECK(dir.names().empty());
}

TEST_CASE("Outputs and image paths are checked before any work", "[experiment]") {
  ScratchDir dir;
  experiment::RunOptions o;
  o.out_dir = dir.path();
  o.quiet = true;
  const auto refused = [&](const std::string& text) {
    try {
      experiment::run(parse_named_experiment(text), o);
    } catch (const InvalidInput& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  // Each of these sources fails in its evaluation (not contractive, a mesh too large): the outputs are
  // refused before it. A chaos game gives a density, a surface no segments.
  CHECK(refused(R"({"shape": "../shapes/wave.json", "perturbation": {"amplitude": 50},
      "evaluation": {"chaos": 1000000}, "outputs": {"png": "w.png", "ply": "w.ply"}})") ==
        "outputs.ply: a chaos game gives a density, no geometry to export");
  CHECK(refused(
            R"({"ifs": "fern", "evaluation": {"depth": 8}, "outputs": {"png": "f.png", "obj": "f.obj"}})") ==
        "outputs.obj: a classic IFS gives a density, no geometry to export");
  CHECK(refused(R"({"shape": "../shapes/saddle.json", "evaluation": {"depth": 30},
      "outputs": {"png": "s.png", "svg": "s.svg"}})") ==
        "outputs.svg: SVG is for curves; use obj, ply, stl, off or vtp for surfaces");
  // The image files are OpenEXR and PNG: another extension is refused, not written with the wrong bytes.
  CHECK(refused(R"({"shape": "../shapes/wave.json", "outputs": {"exr": "w.png"}})") ==
        "outputs.exr: w.png: the image is OpenEXR, written as .exr");
  CHECK(refused(R"({"shape": "../shapes/wave.json", "outputs": {"png": "w.jpg"}})") ==
        "outputs.png: w.jpg: the preview is PNG, written as .png");
  o.exr = dir.path() / "foo.png";
  CHECK(refused(R"({"shape": "../shapes/wave.json", "outputs": {"png": "w.png"}})") ==
        "the EXR path: " + (dir.path() / "foo.png").string() + ": the image is OpenEXR, written as .exr");
  o.exr.clear();
  o.png = dir.path() / "x.jpg";
  CHECK(refused(R"({"shape": "../shapes/wave.json", "outputs": {"exr": "w.exr"}})") ==
        "the PNG path: " + (dir.path() / "x.jpg").string() + ": the preview is PNG, written as .png");
  CHECK(dir.names().empty());
}

TEST_CASE("A mesh experiment: the subdivision surface shaded, its control mesh over it, OBJ and PLY",
          "[experiment][mesh]") {
  ScratchDir dir;
  const auto report = run_in(dir, R"({"name": "cube", "mesh": "../meshes/cube.obj",
      "subdivision": {"scheme": "catmull-clark", "levels": 3},
      "camera": {"projection": "perspective", "eye": [2.5, -1.3, 2.1], "target": [0.5, 0.5, 0.5]},
      "render": {"width": 120, "height": 90, "color": [0.8, 0.8, 0.8], "control_net": true},
      "outputs": {"exr": "c.exr", "png": "c.png", "obj": "c.obj", "ply": "c.ply"}})");
  CHECK(dir.names() == std::set<std::string>{"c.exr", "c.obj", "c.ply", "c.png"});
  CHECK(report.depth == 3);
  CHECK_THAT(report.summary,
             Catch::StartsWith("cube: catmull-clark subdivision of cube.obj, 3 levels, 384 faces"));
  const render::Image image = render::read_exr(dir.path() / "c.exr");
  for (const char* c : {"R", "G", "B", "A", "Z", "N.x", "N.y", "N.z"}) CHECK(image.channels.count(c) == 1);
  CHECK(image.attributes.at("source") == "catmull-clark subdivision of cube.obj");
  CHECK(image.attributes.at("evaluation") == "subdivision, 3 levels");
  CHECK(image.attributes.at("depth") == "3");
  // The framed surface covers a good part of the picture, and the corners stay empty.
  CHECK(covered(image) > 120 * 90 / 8);
  CHECK(image.channels.at("A")[0] == 0);
  // The files hold exactly the library's refinement of the same input.
  const Mesh cube = io::read_mesh(CIFS_EXAMPLES_DIR "/meshes/cube.obj");
  const Mesh refined = subdivision::subdivide(cube, subdivision::MeshScheme::catmull_clark, 3);
  CHECK(read_file(dir.path() / "c.obj") == io::encode(refined, "obj"));
  CHECK(read_file(dir.path() / "c.ply") == io::encode(refined, "ply"));

  // Without the control mesh (same camera) fewer pixels are dark: the lines are drawn over the
  // surface.
  ScratchDir plain;
  run_in(plain, R"({"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "catmull-clark", "levels": 3},
      "camera": {"projection": "perspective", "eye": [2.5, -1.3, 2.1], "target": [0.5, 0.5, 0.5]},
      "render": {"width": 120, "height": 90, "color": [0.8, 0.8, 0.8]}, "outputs": {"exr": "c.exr"}})");
  const render::Image bare = render::read_exr(plain.path() / "c.exr");
  const auto dark = [](const render::Image& im) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < im.width * im.height; ++i)
      n += im.channels.at("A")[i] > 0.5f && im.channels.at("R")[i] < 0.2f;
    return n;
  };
  CHECK(dark(image) > dark(bare) + 100);
  // Z is the nearest fragment: a line in front of the surface, else the surface (the lines' depth
  // bias does not leak into the EXR).
  std::size_t behind = 0;
  for (std::size_t i = 0; i < image.width * image.height; ++i)
    behind += image.channels.at("Z")[i] > bare.channels.at("Z")[i];
  CHECK(behind == 0);
}

TEST_CASE(
    "Mesh experiments: the limit surface with its normals, and the fractal Catmull–Clark and Loop surfaces",
    "[experiment][mesh]") {
  ScratchDir dir;
  // The limit surface: the library's limit mesh, normals included (PLY carries them).
  run_in(
      dir,
      R"({"mesh": "../meshes/torus.obj", "subdivision": {"scheme": "catmull-clark", "levels": 2, "limit": true},
      "render": {"width": 60, "height": 45}, "outputs": {"exr": "l.exr", "ply": "l.ply"}})");
  const Mesh torus = io::read_mesh(CIFS_EXAMPLES_DIR "/meshes/torus.obj");
  const Mesh limit =
      subdivision::limit_mesh(torus, subdivision::MeshScheme::catmull_clark, 2, {.normals = true});
  REQUIRE(limit.normals.rows() == limit.vertices.rows());
  CHECK(read_file(dir.path() / "l.ply") == io::encode(limit, "ply"));
  CHECK(covered(render::read_exr(dir.path() / "l.exr")) > 60 * 45 / 8);

  // The fractal surface: the cube refined once (each face then has one extraordinary corner), the
  // attractor of the perturbed automaton 3 levels further: 6·4^4 faces, closed like the cube.
  const auto report =
      run_in(dir, R"({"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "catmull-clark", "levels": 4},
      "perturbation": {"amplitude": 0.5, "seed": 3},
      "render": {"width": 60, "height": 45}, "outputs": {"exr": "f.exr", "obj": "f.obj"}})");
  CHECK(report.free_coefficients == 8);
  CHECK(report.residual <= 1e-12);
  const Mesh fractal = io::read_mesh(dir.path() / "f.obj");
  CHECK(face_count(fractal) == 6 * 256);
  CHECK(euler_characteristic(build_topology(fractal)) == 2);
  const Mesh smooth = subdivision::catmull_clark(io::read_mesh(CIFS_EXAMPLES_DIR "/meshes/cube.obj"), 4);
  CHECK(fractal.vertices.rows() == smooth.vertices.rows());
  // A pyramid has faces with two extraordinary corners after one level: refined twice first.
  run_in(dir,
         R"({"mesh": "../meshes/tetrahedron.obj", "subdivision": {"scheme": "catmull-clark", "levels": 3},
      "perturbation": {"amplitude": 0.2}, "render": {"width": 40, "height": 30}, "outputs": {"exr": "t.exr"}})");
  CHECK(covered(render::read_exr(dir.path() / "t.exr")) > 40 * 30 / 8);
  // An open mesh: its boundary patches are built too (docs/subdivision-surfaces.md); the fractal surface
  // has the refined grid's faces and, open like it, its Euler characteristic.
  run_in(dir, R"({"mesh": "../meshes/open_grid.obj", "subdivision": {"scheme": "catmull-clark", "levels": 3},
      "perturbation": {"amplitude": 0.2}, "render": {"width": 40, "height": 30}, "outputs": {"exr": "o.exr", "obj": "o.obj"}})");
  const Mesh grid = io::read_mesh(CIFS_EXAMPLES_DIR "/meshes/open_grid.obj");
  const Mesh open = io::read_mesh(dir.path() / "o.obj");
  CHECK(face_count(open) == face_count(grid) * 64);
  CHECK(euler_characteristic(build_topology(open)) == euler_characteristic(build_topology(grid)));
  // Loop: the icosahedron refined once (one extraordinary corner per triangle), the attractor of the
  // box-spline patch's perturbed BC-IFS 2 levels further: the faces of the mesh refined 3 times, closed.
  const auto loop_report =
      run_in(dir, R"({"mesh": "../meshes/icosahedron.obj", "subdivision": {"scheme": "loop", "levels": 3},
      "perturbation": {"amplitude": 0.3, "seed": 2}, "render": {"width": 40, "height": 30}, "outputs": {"exr": "i.exr", "obj": "i.obj"}})");
  CHECK(loop_report.free_coefficients > 0);
  CHECK(loop_report.residual <= 1e-12);
  const Mesh ico = io::read_mesh(dir.path() / "i.obj");
  CHECK(face_count(ico) == 20 * 64);
  CHECK(euler_characteristic(build_topology(ico)) == 2);
  CHECK(ico.vertices.rows() ==
        subdivision::loop(io::read_mesh(CIFS_EXAMPLES_DIR "/meshes/icosahedron.obj"), 3).vertices.rows());
  CHECK(covered(render::read_exr(dir.path() / "i.exr")) > 40 * 30 / 8);
}

TEST_CASE("Mesh experiments: every scheme, boundaries, and what a mesh cannot do", "[experiment][mesh]") {
  ScratchDir dir;
  for (
      const char* text :
      {R"({"mesh": "../meshes/tetrahedron.obj", "subdivision": {"scheme": "butterfly", "levels": 2}, "outputs": {"exr": "a.exr", "obj": "a.obj"}, "render": {"width": 40, "height": 30}})",
       R"({"mesh": "../meshes/open_grid_triangles.obj", "subdivision": {"scheme": "sqrt3", "levels": 2, "boundary": "corner"}, "outputs": {"exr": "a.exr", "obj": "a.obj"}, "render": {"width": 40, "height": 30, "control_net": true}})",
       R"({"mesh": "../meshes/open_grid.obj", "subdivision": {"scheme": "doo-sabin", "levels": 2}, "outputs": {"exr": "a.exr", "obj": "a.obj"}, "render": {"width": 40, "height": 30, "control_net": true}})"}) {
    const io::Experiment e = parse_named_experiment(text);
    run_in(dir, text);
    const Mesh refined = subdivision::subdivide(e.mesh->mesh, e.mesh->scheme, e.mesh->levels);
    CHECK(read_file(dir.path() / "a.obj") == io::encode(refined, "obj"));
    CHECK(covered(render::read_exr(dir.path() / "a.exr")) > 40 * 30 / 8);
  }
  ScratchDir empty;
  // A result above the memory limit is refused before any work, and no file is written.
  experiment::RunOptions o;
  o.out_dir = empty.path();
  o.quiet = true;
  o.max_bytes = 1 << 20;
  const io::Experiment big = parse_named_experiment(
      R"({"mesh": "../meshes/torus.obj", "subdivision": {"scheme": "catmull-clark", "levels": 9},
      "render": {"width": 8, "height": 8}, "outputs": {"exr": "t.exr", "obj": "t.obj"}})");
  try {
    experiment::run(big, o);
    FAIL("no error");
  } catch (const InvalidInput& error) {
    const std::string message = error.what();
    CHECK_THAT(message, Catch::StartsWith("subdivision.levels: torus.obj: "));
    CHECK(message.find('\n') == std::string::npos);
  }
  CHECK_THROWS_WITH(run_in(empty, R"({"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "loop"},
      "outputs": {"exr": "c.exr", "svg": "c.svg"}})"),
                    Catch::Contains("subdivision.scheme: loop refines triangles only"));
  CHECK_THROWS_WITH(run_in(empty, R"({"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "doo-sabin"},
      "render": {"width": 8, "height": 8}, "outputs": {"exr": "c.exr", "svg": "c.svg"}})"),
                    Catch::Contains("outputs.svg: SVG is for curves"));
  CHECK_THROWS_WITH(experiment::evaluate(parse_named_experiment(
                        R"({"mesh": "../meshes/tetrahedron.obj", "subdivision": {"scheme": "butterfly"}})")),
                    "mesh: tetrahedron.obj: a butterfly surface has no automaton to evaluate or sample "
                    "(catmull-clark and loop surfaces have)");
  CHECK_THROWS_WITH(experiment::sample(parse_named_experiment(
                        R"({"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "doo-sabin"}})")),
                    Catch::StartsWith("mesh: cube.obj: a doo-sabin surface has no automaton"));
  CHECK(empty.names().empty());
}

TEST_CASE(
    "evaluate and sample a subdivision surface: its surface automaton's attractor, perturbed as the file "
    "says",
    "[experiment][dimension]") {
  // What cifs dimension measures on a mesh experiment, against the automaton built here from the library's
  // parts: the mesh refined once (every face then has one extraordinary corner at most), its surface
  // automaton, perturbed with the file's amplitude and seed.
  const io::Experiment e = parse_named_experiment(R"({"mesh": "../meshes/icosahedron.obj",
      "subdivision": {"scheme": "loop", "levels": 4}, "perturbation": {"amplitude": 1.5, "seed": 3}})");
  const Mesh ico = io::read_mesh(CIFS_EXAMPLES_DIR "/meshes/icosahedron.obj");
  const subdivision::SurfaceAutomaton smooth =
      subdivision::surface_automaton(subdivision::loop(ico, 1), subdivision::MeshScheme::loop);
  ifs::PerturbOptions perturb;
  perturb.amplitude = 1.5;
  perturb.seed = 3;
  const subdivision::FractalSurface rough = subdivision::fractal_surface(smooth, perturb);
  const experiment::Evaluation ev = experiment::evaluate(e);
  CHECK(ev.depth == 3);  // the file's 4 levels, one spent on the automaton
  const Mesh expected = subdivision::surface_automaton_mesh(rough.surface, 3);
  REQUIRE(ev.points.rows() == expected.vertices.rows());
  const double scale = expected.vertices.cwiseAbs().maxCoeff();
  CHECK((ev.points - expected.vertices).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  // The perturbed attractor, not the smooth surface nor the subdivided mesh.
  const Mesh flat = subdivision::surface_automaton_mesh(smooth, 3);
  CHECK((ev.points - flat.vertices).cwiseAbs().maxCoeff() >= 1e-3 * scale);
  CHECK(ev.kind.find("fractal loop surface of icosahedron.obj") != std::string::npos);
  CHECK(ev.resolution > 0);
  // A tolerance sample of the same automaton: its points within the attractor's box (to the pieces' size).
  const experiment::Evaluation s = experiment::sample(e, {.tolerance = 0.25});
  CHECK(s.points.rows() > 0);
  const Eigen::RowVectorXd lo = expected.vertices.colwise().minCoeff(),
                           hi = expected.vertices.colwise().maxCoeff();
  bool inside = true;
  for (Eigen::Index p = 0; p < s.points.rows(); ++p)
    inside = inside && (s.points.row(p).array() >= lo.array() - s.resolution).all() &&
             (s.points.row(p).array() <= hi.array() + s.resolution).all();
  CHECK(inside);
  // Unperturbed: the smooth automaton (no BC-IFS), at an explicit depth.
  io::Experiment plain = e;
  plain.perturbation.reset();
  const experiment::Evaluation smooth_ev = experiment::evaluate(plain, 2);
  CHECK((smooth_ev.points - subdivision::surface_automaton_mesh(smooth, 2).vertices).cwiseAbs().maxCoeff() ==
        0);
}

namespace {

/// `"points": [...]` of a polygon or of a grid (lines of constant v).
std::string points_json(const Points& P, int columns = 0) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    if (columns > 0 && i % columns == 0)
      s += (i == 0 ? "[" : "], [");
    else if (i > 0)
      s += ", ";
    s += "[";
    for (Eigen::Index c = 0; c < P.cols(); ++c) s += (c ? ", " : "") + number_text(P(i, c));
    s += "]";
  }
  return s + (columns > 0 ? "]]" : "]");
}

/// Windows of N consecutive points, or of N × N points of a grid with `columns` points a line.
std::vector<Points> windows_of_grid(const Points& P, int N, int columns = 0) {
  std::vector<Points> nets;
  if (columns == 0) {
    for (Eigen::Index k = 0; k + N <= P.rows(); ++k) nets.push_back(P.middleRows(k, N));
    return nets;
  }
  const auto rows = static_cast<int>(P.rows()) / columns;
  for (int a = 0; a + N <= rows; ++a)
    for (int b = 0; b + N <= columns; ++b) {
      Points W(N * N, P.cols());
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) W.row(i * N + j) = P.row((a + i) * columns + b + j);
      nets.push_back(std::move(W));
    }
  return nets;
}

}  // namespace

TEST_CASE("A junction of curves: the experiment draws what ifs::join gives, the report its residual",
          "[experiment][junction]") {
  // One polygon: A (cubic B-spline, windows of 6) reads points 0 … 7, B (four-point, layer 3)
  // points 3 … 11, so B's first five points are A's last five.
  Points P(12, 2);
  for (int i = 0; i < 12; ++i) P.row(i) << i, std::sin(0.9 * i) + 0.1 * i;
  const Points PA = P.topRows(8), PB = P.bottomRows(9);
  const std::string text = R"({"junction": {
      "a": {"scheme": "b-spline", "parameters": {"degree": 3}, "window": 6, "boundary": "end", "points": )" +
                           points_json(PA) + R"(},
      "b": {"scheme": "four-point", "window": 6, "layer": 3, "boundary": "start", "points": )" +
                           points_json(PB) + R"(}},
      "evaluation": {"depth": 7}, "render": {"width": 200, "height": 100, "line_width": 3},
      "outputs": {"exr": "j.exr"}})";
  const int depth = 7;
  const experiment::Evaluation ev = experiment::evaluate(parse_named_experiment(text));
  // Library route: ifs::join of the two scheme systems, edge pieces at the same depth.
  const ifs::Bcifs A = subdivision::scheme_bcifs(subdivision::b_spline(3), 6, {.pieces = 3});
  const ifs::Bcifs B = subdivision::scheme_bcifs(subdivision::four_point(), 6, {.pieces = 4, .layer = 3});
  const std::vector<ifs::Glue> glue{{2, "end", 0, "start"}};
  const ifs::Junction j = ifs::join(A, windows_of_grid(PA, 6), B, windows_of_grid(PB, 6), glue);
  const ifs::EdgePieces pieces = ifs::edge_pieces(j.system, j.nets, depth);
  const Eigen::Index n = pieces.start.rows();
  REQUIRE(ev.points.rows() == 2 * n);
  CHECK((ev.points.topRows(n) - pieces.start).cwiseAbs().maxCoeff() == 0);
  CHECK((ev.points.bottomRows(n) - pieces.end).cwiseAbs().maxCoeff() == 0);
  // By hand: A's last piece (the cubic segment of P3 … P6) ends at (P4 + 4 P5 + P6)/6, where B starts.
  const Eigen::RowVector2d end = (P.row(4) + 4 * P.row(5) + P.row(6)) / 6;
  const Eigen::Index per = Eigen::Index{1} << depth;
  CHECK((ev.points.row(n + 3 * per - 1) - end).norm() <= 1e-12);
  CHECK((ev.points.row(3 * per) - end).norm() <= 1e-12);

  ScratchDir dir;
  const auto report = run_in(dir, text);
  CHECK(report.residual <= 1e-12);
  CHECK(report.free_coefficients == j.free);
  CHECK_THAT(report.summary,
             Catch::Contains("junction of a b-spline(degree = 3) curve and a four-point curve") &&
                 Catch::Contains("A's end = B's start") && Catch::Contains("residual"));
  const render::Image image = render::read_exr(dir.path() / "j.exr");
  CHECK_THAT(image.attributes.at("junction"), Catch::Contains("free coefficients"));
  CHECK(std::stod(image.attributes.at("residual")) <= 1e-12);
  // Each side in its own colour: blue (render.color) and orange pixels.
  std::size_t blue = 0, orange = 0;
  for (std::size_t i = 0; i < image.channels.at("A").size(); ++i) {
    const float a = image.channels.at("A")[i], r = image.channels.at("R")[i], b = image.channels.at("B")[i];
    blue += a > 0.9f && b > 2 * r;
    orange += a > 0.9f && r > 2 * b;
  }
  CHECK(blue > 100);
  CHECK(orange > 100);
}

TEST_CASE("A junction of a bicubic and a biquadratic patch: the experiment's mesh is ifs::join's",
          "[experiment][junction]") {
  // A grid of 9 × 5 points: A (bicubic) reads lines 0 … 4, B (biquadratic on windows of 4, layer 2)
  // lines 2 … 8.
  Points G(45, 3);
  for (int i = 0; i < 9; ++i)
    for (int k = 0; k < 5; ++k) G.row(i * 5 + k) << i, k, 0.6 * std::sin(0.7 * i) * std::cos(0.9 * k);
  const Points GA = G.topRows(25), GB = G.bottomRows(35);
  const std::string text = R"({"junction": {
      "a": {"scheme": "b-spline", "boundary": "uend", "points": )" +
                           points_json(GA, 5) + R"(},
      "b": {"scheme": "b-spline", "parameters": {"degree": 2}, "window": 4, "layer": 2, "boundary": "ustart",
            "points": )" + points_json(GB, 5) +
                           R"(}},
      "evaluation": {"depth": 3}})";
  const experiment::Evaluation ev = experiment::evaluate(parse_named_experiment(text));
  const auto curve = [](int degree, int window, int pieces, int layer) {
    return subdivision::scheme_bcifs(subdivision::b_spline(degree), window,
                                     {.pieces = pieces, .layer = layer});
  };
  const ifs::Bcifs A = ifs::product_bcifs(curve(3, 0, 2, 0), curve(3, 0, 2, 0));
  const ifs::Bcifs B = ifs::product_bcifs(curve(2, 4, 4, 2), curve(2, 4, 2, 0), {.free_when_either = true});
  std::vector<ifs::Glue> glue;
  for (std::size_t b = 0; b < 2; ++b) glue.push_back({2 + b, "uend", b, "ustart"});
  const ifs::Junction j = ifs::join(A, windows_of_grid(GA, 4, 5), B, windows_of_grid(GB, 4, 5), glue);
  CHECK(j.residual <= 1e-12);
  const auto side = [&](std::size_t first, std::size_t count, int nu, int nv) {
    automata::Automaton a = j.system.automaton;
    a.initial.assign(a.initial.begin() + static_cast<long>(first),
                     a.initial.begin() + static_cast<long>(first + count));
    std::vector<std::array<int, 2>> patches(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv));
    for (int p = 0; p < nu * nv; ++p) patches[static_cast<std::size_t>(p)] = {p / nv, p % nv};
    return ifs::quad_mesh(a, std::span(j.nets).subspan(first, count), patches, 3).vertices;
  };
  const Points a = side(0, 4, 2, 2), b = side(4, 8, 4, 2);
  REQUIRE(ev.points.rows() == a.rows() + b.rows());
  CHECK((ev.points.topRows(a.rows()) - a).cwiseAbs().maxCoeff() == 0);
  CHECK((ev.points.bottomRows(b.rows()) - b).cwiseAbs().maxCoeff() == 0);
  // By hand: the common boundary is the cubic B-spline of Q_k = (G_2k + 4 G_3k + G_4k)/6 (lines 2 … 4
  // of A), so B's first node line passes through (Q_k + 4 Q_k+1 + Q_k+2)/6 at A's knots.
  const auto Q = [&](int k) {
    return Eigen::RowVector3d((G.row(10 + k) + 4 * G.row(15 + k) + G.row(20 + k)) / 6);
  };
  for (int k = 0; k < 3; ++k)
    CHECK((b.row(8 * Eigen::Index{k}) - (Q(k) + 4 * Q(k + 1) + Q(k + 2)) / 6).norm() <= 1e-12);
}

TEST_CASE("The gallery's NURBS and fractal junction: B's boundary is A's NURBS boundary after perturbation",
          "[experiment][junction]") {
  const io::Experiment e = io::read_experiment(CIFS_EXAMPLES_DIR "/experiments/junction_fractal.json");
  REQUIRE(e.junction);
  io::Experiment small = e;
  small.evaluation.depth = 3;
  const experiment::Evaluation ev = experiment::evaluate(small);
  const auto& SA = std::get<nurbs::Surface>(*e.junction->a.shape);
  const auto& SB = std::get<nurbs::Surface>(*e.junction->b.shape);
  // A: 2 × 3 patches, (2·8 + 1) × (3·8 + 1) nodes; B's node line u = 0 follows.
  const Eigen::Index nv = 3 * 8 + 1, first_b = (2 * 8 + 1) * nv;
  double moved = 0;
  for (Eigen::Index J = 0; J < nv; ++J) {
    const double v = 3.0 + 3.0 * static_cast<double>(J) / static_cast<double>(nv - 1);
    const Eigen::RowVector3d exact = nurbs::evaluate(SA, 5.0, v);  // Cox–de Boor, A's end u = 5
    CHECK((ev.points.row(first_b + J) - exact).norm() <= 1e-12);
    CHECK((ev.points.row(first_b - nv + J) - exact).norm() <= 1e-12);
    // B away from the junction (its node line u = 1/2 of its first patch) left its B-spline.
    moved = std::max(moved, (ev.points.row(first_b + 4 * nv + J) - nurbs::evaluate(SB, 3.5, v)).norm());
  }
  CHECK(moved > 1e-3);
  ScratchDir dir;
  experiment::RunOptions o;
  o.out_dir = dir.path();
  o.quiet = true;
  small.outputs = {};
  o.png = dir.path() / "f.png";
  small.render.width = small.render.height = 64;
  CHECK(experiment::run(small, o).residual <= 1e-12);
}

namespace {

/// The empty border of an image's coverage (A > 0), as fractions of its size: {left, right, top, bottom}.
std::array<double, 4> empty_border(const render::Image& image) {
  const std::vector<float>& a = image.channels.at("A");
  std::size_t left = image.width, right = 0, top = image.height, bottom = 0;
  for (std::size_t y = 0; y < image.height; ++y)
    for (std::size_t x = 0; x < image.width; ++x)
      if (a[y * image.width + x] > 0)
        left = std::min(left, x), right = std::max(right, x), top = std::min(top, y),
        bottom = std::max(bottom, y);
  REQUIRE(right >= left);
  const double W = double(image.width), H = double(image.height);
  return {double(left) / W, double(image.width - 1 - right) / W, double(top) / H,
          double(image.height - 1 - bottom) / H};
}

}  // namespace

TEST_CASE("Surfaces and 3-D curves are framed by their projected extent", "[experiment][camera]") {
  // The hills seen from the default direction: the bounding sphere left 31 % of the rows above it and
  // 15–18 % of the columns on either side empty (at 1200 × 900, before the tight fit). Now the tighter
  // direction (here the width) has only the 2 % margin, and the other one is centred.
  ScratchDir dir;
  (void)run_in(dir, R"({"shape": "../shapes/hills.json", "evaluation": {"depth": 4},
      "camera": {"projection": "perspective", "margin": 0.02},
      "render": {"width": 240, "height": 180}, "outputs": {"exr": "h.exr"}})");
  const auto [left, right, top, bottom] = empty_border(render::read_exr(dir.path() / "h.exr"));
  INFO("empty border: left " << left << ", right " << right << ", top " << top << ", bottom " << bottom);
  const double pixel_w = 1.0 / 240, pixel_h = 1.0 / 180;
  CHECK(std::max(left, right) <= 0.02 + 2 * pixel_w);
  CHECK(std::min(left, right) >= 0.02 - 2 * pixel_w);
  CHECK(std::abs(top - bottom) <= 2 * pixel_h);
  CHECK(std::max(top, bottom) <= 0.16);  // the aspect ratio kept: the hills are wider than 4:3
  // A 3-D curve (and its control net), long and thin: the margin on the tighter side (it was 11 %
  // with the sphere), centred; its lines (3 px) may reach 2 px past the points.
  ScratchDir curve;
  (void)run_in(curve, R"({"shape": "../shapes/cubic.json", "evaluation": {"depth": 6},
      "camera": {"projection": "perspective", "margin": 0.05},
      "render": {"width": 200, "height": 200, "line_width": 3, "control_net": true}, "outputs": {"exr": "c.exr"}})");
  const auto c = empty_border(render::read_exr(curve.path() / "c.exr"));
  INFO("curve's empty border: " << c[0] << ", " << c[1] << ", " << c[2] << ", " << c[3]);
  const double p = 1.0 / 200;
  CHECK(std::min(std::max(c[0], c[1]), std::max(c[2], c[3])) <= 0.05 + 2 * p);
  CHECK(std::abs(c[0] - c[1]) <= 4 * p);
  CHECK(std::abs(c[2] - c[3]) <= 4 * p);
}
