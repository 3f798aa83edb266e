// SPDX-License-Identifier: MIT
// cifs view on experiments the runner draws from its own scene — on a polygon mesh, a junction of two shapes,
// a classic IFS —: the geometry against the library's calls made here (subdivision::subdivide and limit_mesh,
// experiment::evaluate, a classic IFS's words composed by hand), and through the request handler: the
// document, save (read back by the experiment reader), render, refusals.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/files.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/io/io.hpp"
#include "cifs/render/point_ifs.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/view/server.hpp"
#include "support/scratch.hpp"
#include "view/view_support.hpp"

using namespace cifs;

namespace {

const std::string kRunExamples = CIFS_EXAMPLES_DIR;

std::string experiment_path(const std::string& name) {
  return kRunExamples + "/experiments/" + name;
}

/// The experiment file as the runner reads it, its mesh's levels or its depth replaced.
io::Experiment read_with(const std::string& name, int levels_or_depth) {
  io::Experiment e = io::read_experiment(experiment_path(name));
  (e.mesh ? e.mesh->levels : e.evaluation.depth) = levels_or_depth;
  return e;
}

/// The header of an encoded geometry.
nlohmann::json header_of(const std::string& body) {
  std::uint32_t length = 0;
  std::memcpy(&length, body.data() + 8, 4);
  return nlohmann::json::parse(body.substr(12, length));
}

}  // namespace

TEST_CASE("view experiments on a mesh: the runner's refined, limit and fractal meshes at the page's levels",
          "[view]") {
  SECTION("Catmull–Clark on the cube: subdivision::subdivide's mesh, the control mesh's edges as the net") {
    const view::Document d = view::open_document(experiment_path("subdivision_cube_catmull_clark.json"));
    REQUIRE(d.kind == view::Kind::subdivision);
    view::Params p = view::default_params(d);
    CHECK(p.levels == d.experiment->mesh->levels);  // the file's
    p.levels = 2;
    const view::Geometry g = view::geometry(d, p);
    const Mesh m =
        subdivision::subdivide(d.experiment->mesh->mesh, subdivision::MeshScheme::catmull_clark, 2);
    CHECK(g.positions == cifs_test::page_floats(m.vertices));
    CHECK(g.triangles.size() == 3 * 2 * (m.face_offsets.size() - 1));  // quads as two triangles
    CHECK(g.net == cifs_test::page_floats(d.experiment->mesh->mesh.vertices));
    CHECK(g.net_lines.size() == 2 * 12);  // the cube's 12 edges
    CHECK(g.checksum == view::geometry_checksum(g.positions));
  }
  SECTION("the limit surface (subdivision.limit): subdivision::limit_mesh's vertices") {
    const view::Document d = view::open_document(experiment_path("subdivision_torus_limit.json"));
    view::Params p = view::default_params(d);
    p.levels = 1;
    const Mesh m = subdivision::limit_mesh(d.experiment->mesh->mesh, subdivision::MeshScheme::catmull_clark,
                                           1, {.normals = true});
    CHECK(view::geometry(d, p).positions == cifs_test::page_floats(m.vertices));
  }
  SECTION("a fractal Catmull–Clark surface: experiment::evaluate's points, the page's amplitude and seed") {
    const view::Document d = view::open_document(experiment_path("subdivision_cube_fractal.json"));
    view::Params p = view::default_params(d);
    CHECK(p.amplitude == 0.9);  // the file's perturbation
    CHECK(p.seed == 3);
    // (Below the file's 0.9, whose contractivity check alone takes a quarter of a second.)
    p.levels = 3;
    p.amplitude = 0.5;
    const view::Geometry g = view::geometry(d, p);
    io::Experiment e = read_with("subdivision_cube_fractal.json", 3);
    e.perturbation->amplitude = 0.5;
    CHECK(g.positions == cifs_test::page_floats(experiment::evaluate(e).points));
    CHECK(g.states.empty());  // drawn in one colour, as the runner draws a mesh
    p.amplitude = 0.3;
    p.seed = 5;
    e.perturbation->amplitude = 0.3;
    e.perturbation->seed = 5;
    CHECK(view::geometry(d, p).positions == cifs_test::page_floats(experiment::evaluate(e).points));
    p.amplitude = 1.9;  // the slider's top: 1, or twice the file's amplitude
    CHECK_THROWS_WITH(view::geometry(d, p), "amplitude 1.9 is outside 0..1.8");
    p.amplitude = 0.3;
    p.levels = 0;  // the runner's refusal, as cifs render gives it
    CHECK_THROWS_WITH(view::geometry(d, p), Catch::Contains("needs 1 level(s) or more"));
    p.levels = 7;
    CHECK_THROWS_WITH(view::geometry(d, p), "levels 7 is outside 0..6 (the view's limit)");
  }
  SECTION("fractal crease lines (perturbation.fractal_curves), the surface smooth") {
    const view::Document d = view::open_document(experiment_path("subdivision_torus_fractal_creases.json"));
    view::Params p = view::default_params(d);
    p.levels = 2;
    CHECK(view::geometry(d, p).positions ==
          cifs_test::page_floats(
              experiment::evaluate(read_with("subdivision_torus_fractal_creases.json", 2)).points));
  }
  SECTION("a fractal Loop surface at its file's amplitude (1.5, above 1)") {
    const view::Document d = view::open_document(experiment_path("subdivision_icosahedron_fractal.json"));
    view::Params p = view::default_params(d);
    CHECK(p.amplitude == 1.5);
    p.levels = 2;
    CHECK(view::geometry(d, p).positions ==
          cifs_test::page_floats(
              experiment::evaluate(read_with("subdivision_icosahedron_fractal.json", 2)).points));
  }
}

TEST_CASE("view experiments on a junction: both sides, each state its side's colour, the runner's points",
          "[view]") {
  SECTION("curves: the pieces of both sides") {
    const view::Document d = view::open_document(experiment_path("junction_curves.json"));
    REQUIRE(d.kind == view::Kind::junction);
    view::Params p = view::default_params(d);
    CHECK(p.depth == 8);  // the file's
    p.depth = 4;
    const view::Geometry g = view::geometry(d, p);
    const experiment::Evaluation runner = experiment::evaluate(read_with("junction_curves.json", 4));
    CHECK(g.positions == cifs_test::page_floats(runner.points));
    REQUIRE(g.pieces * 2 == g.positions.size() / 3);
    REQUIRE(g.states.size() == 2 * std::size_t{g.pieces});
    // A's states take the file's render.color (the default here), B's orange: both sides drawn.
    REQUIRE(g.state_colors.size() == num_vertices(runner.automaton.graph));
    bool a = false, b = false;
    for (const std::uint32_t s : g.states) {
      const bool side_b = runner.automaton.graph[s].name.starts_with("B:");
      CHECK(g.state_colors[s] == (side_b ? std::array{0.85, 0.40, 0.08} : std::array{0.12, 0.30, 0.65}));
      (side_b ? b : a) = true;
    }
    CHECK((a && b));
    CHECK(!g.net.empty());
  }
  SECTION("surfaces, and a perturbed junction at the page's amplitude") {
    const view::Document d = view::open_document(experiment_path("junction_surfaces.json"));
    view::Params p = view::default_params(d);
    p.depth = 2;
    const view::Geometry g = view::geometry(d, p);
    CHECK(g.positions ==
          cifs_test::page_floats(experiment::evaluate(read_with("junction_surfaces.json", 2)).points));
    CHECK(!g.triangles.empty());
    CHECK(g.states.size() == g.positions.size() / 3);

    const view::Document f = view::open_document(experiment_path("junction_fractal.json"));
    view::Params q = view::default_params(f);
    CHECK(q.amplitude == 0.4);
    q.depth = 2;
    q.amplitude = 0.2;
    io::Experiment e = read_with("junction_fractal.json", 2);
    e.perturbation->amplitude = 0.2;
    CHECK(view::geometry(f, q).positions == cifs_test::page_floats(experiment::evaluate(e).points));
    q.depth = 13;
    CHECK_THROWS_WITH(view::geometry(f, q), "depth 13 is outside 0..12 (the view's limit)");
  }
}

TEST_CASE("view classic IFS: the points of the Hutchinson measure at the depth, each with its last map",
          "[view]") {
  const view::Document d = view::open_document(experiment_path("koch.json"));
  REQUIRE(d.kind == view::Kind::ifs);
  view::Params p = view::default_params(d);
  CHECK(p.depth == 8);  // the file's
  p.depth = 3;
  const view::Geometry g = view::geometry(d, p);
  // By hand: the barycentre x̄ of the measure solves x̄ = Σ p_k·w_k(x̄); word (k1, k2, k3), in the walk's
  // order, puts its point at w_k3(w_k2(w_k1(x̄))), in the top-level piece w_k3(A).
  const std::vector<ifs::AffineMap> maps = ifs::named_ifs("koch");
  double total = 0;
  for (const ifs::AffineMap& m : maps) total += m.probability;
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (const ifs::AffineMap& m : maps) {
    A += m.probability / total * (Eigen::Matrix2d() << m.a, m.b, m.c, m.d).finished();
    b += m.probability / total * Eigen::Vector2d(m.e, m.f);
  }
  const Eigen::Matrix2d fixed = Eigen::Matrix2d::Identity() - A;
  const Eigen::Vector2d centre = fixed.partialPivLu().solve(b);
  const std::size_t n = maps.size();
  REQUIRE(g.positions.size() == 3 * n * n * n);
  REQUIRE(g.states.size() == n * n * n);
  for (std::size_t i = 0; i < n * n * n; ++i) {
    Eigen::Vector2d x = centre;
    for (const std::size_t k : {i / (n * n), i / n % n, i % n}) {
      const ifs::AffineMap& m = maps[k];
      x = (Eigen::Matrix2d() << m.a, m.b, m.c, m.d).finished() * x + Eigen::Vector2d(m.e, m.f);
    }
    CHECK(std::abs(g.positions[3 * i] - x.x()) <= 1e-6);
    CHECK(std::abs(g.positions[3 * i + 1] - x.y()) <= 1e-6);
    CHECK(g.positions[3 * i + 2] == 0.0F);
    CHECK(g.states[i] == i % n);
  }
  // The masses are the words' probabilities and sum to 1: what hutchinson_measure bins.
  const render::HutchinsonPoints h = render::hutchinson_points(maps, 3, 1000);
  double mass = 0;
  for (const double w : h.mass) mass += w;
  CHECK(mass == Approx(1).epsilon(1e-14));
  const std::vector<double> bins = render::hutchinson_measure(maps, 3, 1, 1, {-1, 2, -1, 2});
  CHECK(bins[0] == Approx(1).epsilon(1e-14));
  // The slider stops at the deepest depth within the point limit; beyond, refused before any work.
  CHECK(view::max_depth(d, {}) == 11);  // 4^11 = 2^22
  p.depth = 12;
  CHECK_THROWS_WITH(view::geometry(d, p), "depth 12 is outside 0..11 (the view's limit)");
  p.depth = 2;
  p.amplitude = 0.1;
  CHECK_THROWS_WITH(view::geometry(d, p),
                    Catch::Contains("koch.json: a classic IFS has no free coefficients"));
  CHECK_THROWS_WITH(render::hutchinson_points(maps, 5, 1000),
                    Catch::Contains("more than 1000; lower the depth"));
  // A chaos-game file (fern.json) opens at the deepest depth with at most 10^5 points.
  CHECK(view::default_params(view::open_document(experiment_path("fern.json"))).depth == 8);
}

TEST_CASE("view handle: experiments on a mesh, a junction, a classic IFS — document, geometry, save, render",
          "[view]") {
  cifs_test::ScratchDir dir;
  // The mesh experiment with its mesh's absolute path (the file is copied away from examples/meshes).
  nlohmann::ordered_json mesh =
      nlohmann::ordered_json::parse(read_file(experiment_path("subdivision_cube_fractal.json")));
  mesh["mesh"] = kRunExamples + "/meshes/cube.obj";
  write_file_atomically(dir.path() / "cube_fractal.json", mesh.dump());
  for (const char* name : {"koch.json", "junction_curves.json"})
    std::filesystem::copy_file(experiment_path(name), dir.path() / name);
  struct Case {
    const char* file;
    const char* kind;
    const char* params;  // the page's edit
    const char* range;
  };
  for (const Case& c :
       {Case{"koch.json", "ifs", R"({"depth": 4})", "depth"},
        Case{"junction_curves.json", "junction", R"({"depth": 3})", "depth"},
        Case{"cube_fractal.json", "subdivision", R"({"levels": 2, "amplitude": 0.5})", "levels"}}) {
    INFO(c.file);
    view::Session s;
    view::open_session(s, dir.path() / c.file, "127.0.0.1", 8765);
    const auto post = [&](const std::string& path, const std::string& body) {
      return view::handle(
          s,
          {.method = "POST", .target = path + "?token=" + s.token, .host = "127.0.0.1:8765", .body = body});
    };
    const view::Response doc = view::handle(
        s,
        {.method = "GET", .target = "/api/document?token=" + s.token, .host = "127.0.0.1:8765", .body = {}});
    REQUIRE(doc.status == 200);
    const auto j = nlohmann::json::parse(doc.body);
    CHECK(j["kind"] == c.kind);
    CHECK(j["points_editable"] == false);
    CHECK(j["automaton"] == (c.kind == std::string("junction")));
    CHECK(j["ranges"].contains(c.range));
    const std::string params = std::string(R"({"params": )") + c.params + "}";
    const view::Response r = post("/api/geometry", params);
    REQUIRE(r.status == 200);
    const nlohmann::json header = header_of(r.body);
    CHECK(header["kind"] == c.kind);
    CHECK(header["checksum"] == s.geometry.checksum);
    // Save: the experiment with the page's depth or levels (and perturbation), read back by the runner's
    // reader.
    const view::Response saved =
        post("/api/save", std::string(R"({"name": "saved.json", "params": )") + c.params + "}");
    REQUIRE(saved.status == 200);
    const io::Experiment back = io::read_experiment(dir.path() / "saved.json");
    if (back.mesh) {
      CHECK(back.mesh->levels == 2);
      CHECK(back.perturbation->amplitude == 0.5);
    } else {
      CHECK(back.evaluation.depth == nlohmann::json::parse(c.params)["depth"]);
    }
    // Render: the runner on the same experiment.
    const view::Response rendered =
        post("/api/render", std::string(R"({"name": "r.png", "params": )") + c.params + "}");
    CHECK(rendered.status == 200);
    CHECK(std::filesystem::file_size(dir.path() / "r.png") > 1000);
    // The saved file's runner geometry is the page's.
    const view::Document reopened = view::open_document(dir.path() / "saved.json");
    CHECK(view::geometry(reopened, view::default_params(reopened)).checksum == s.geometry.checksum);
    // Refusals, one line each; the session answers afterwards.
    const view::Response points = post("/api/geometry", R"({"params": {"points": [[0, 1, 2]]}})");
    CHECK(points.status == 400);
    CHECK(points.body.find("its points are not edited here") != std::string::npos);
    CHECK(post("/api/geometry", R"({"params": {"depth": 99, "levels": 99}})").status == 400);
    // The automaton beside the geometry: a junction's (its states are the pieces'), no other.
    const view::Response svg = view::handle(s, {.method = "GET",
                                                .target = "/api/automaton.svg?token=" + s.token,
                                                .host = "127.0.0.1:8765",
                                                .body = {}});
    CHECK(svg.status == (c.kind == std::string("junction") ? 200 : 404));
    if (svg.status == 200) CHECK(svg.body.find("B:") != std::string::npos);  // both sides' states
    CHECK(post("/api/geometry", params).status == 200);
  }
}
