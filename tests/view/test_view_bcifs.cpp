// SPDX-License-Identifier: MIT
// cifs view on BC-IFS and experiment files, and the perturbed shapes' interactive route: the geometry against
// experiment::evaluate of the experiment with the same source, depth and perturbation (the runner, read from
// a file the test writes), the coefficient ranges against ifs::contraction called apart, the request
// handler's refusals (a value outside its range, a non-finite or unknown one, a non-contractive edit: 422)
// and save.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/io/io.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/view/server.hpp"
#include "support/scratch.hpp"
#include "view/view_support.hpp"

using namespace cifs;

namespace {

const std::string kBcifsExamples = CIFS_EXAMPLES_DIR;

/// The runner's points for an experiment file written with this text (experiment::evaluate).
Points runner_points(const std::filesystem::path& folder, const nlohmann::json& experiment, int depth) {
  const std::filesystem::path file = folder / "runner.json";
  std::ofstream(file) << experiment.dump();
  return experiment::evaluate(io::read_experiment(file), depth).points;
}

/// Positions equal to the runner's points: float32 of the same doubles (the library's own calls), and to
/// 1e-12 relative before the conversion where the points are given as doubles.
void check_same_points(const view::Geometry& g, const Points& expected) {
  REQUIRE(g.positions.size() == 3 * static_cast<std::size_t>(expected.rows()));
  CHECK(g.positions == cifs_test::page_floats(expected));
}

}  // namespace

TEST_CASE("view opens a BC-IFS file: its free coefficients by name, their ranges, the runner's pieces",
          "[view][view_bcifs]") {
  cifs_test::ViewFixture f("automata/tree.json");
  const view::Document& d = f.session.document;
  REQUIRE(d.kind == view::Kind::bcifs);
  const io::BcifsFile file = io::read_bcifs(d.path);
  const ifs::AdmissibleSpace space = ifs::admissible_space(file.system);
  const std::vector<std::string> names = ifs::free_names(file.system, space);
  REQUIRE(d.coefficients.size() == names.size());  // 10: docs/bcifs.md's hand count
  CHECK(names.size() == 10);
  const Eigen::VectorXd values = ifs::free_values(file.system, space);
  for (std::size_t j = 0; j < names.size(); ++j) {
    const view::CoefficientRange& r = d.coefficients[j];
    CHECK(r.name == names[j]);
    CHECK(r.value == Approx(values(static_cast<Eigen::Index>(j))).epsilon(1e-12));
    CHECK(r.low <= r.value);
    CHECK(r.value <= r.high);
    // Both ends contractive, by the library's check called here on the matrices set apart.
    for (const double end : {r.low, r.high}) {
      Eigen::VectorXd c = values;
      c(static_cast<Eigen::Index>(j)) = end;
      CHECK_NOTHROW(
          ifs::contraction(ifs::with_free_values(file.system, space, c).automaton, {.bound = false}));
    }
  }
  SECTION("the ranges found with the kept failing paths are those found without, to the bit") {
    // open_document probes every range with one ifs::FailingPaths; here each is probed from cold.
    ifs::PerturbOptions base;
    base.contraction.bound = false;
    for (const view::CoefficientRange& r : d.coefficients) {
      const view::CoefficientRange cold = view::coefficient_range(*d.bcifs, r.name, base);
      CAPTURE(r.name);
      CHECK(std::bit_cast<std::uint64_t>(cold.low) == std::bit_cast<std::uint64_t>(r.low));
      CHECK(std::bit_cast<std::uint64_t>(cold.high) == std::bit_cast<std::uint64_t>(r.high));
      CHECK(cold.capped == r.capped);
    }
  }
  SECTION("a range ends where contractivity ends: a refused value within 2^-8 beyond it") {
    std::size_t checked = 0;
    for (std::size_t j = 0; j < names.size() && checked < 2; ++j) {
      const view::CoefficientRange& r = d.coefficients[j];
      if (r.capped) continue;
      ++checked;
      bool refused = false;
      for (int k = 1; k <= 16 && !refused; ++k) {
        Eigen::VectorXd c = values;
        c(static_cast<Eigen::Index>(j)) = r.high + k * (1.0 / 4096);
        try {
          (void)ifs::contraction(ifs::with_free_values(file.system, space, c).automaton, {.bound = false});
        } catch (const ifs::NotContractive&) {
          refused = true;
        }
      }
      CAPTURE(r.name, r.high);
      CHECK(refused);
    }
    CHECK(checked > 0);
  }
  SECTION("the geometry is the runner's: the file as read, then a coefficient set by name") {
    view::Params p = view::default_params(d);
    CHECK(p.depth == 8);  // 3^8 = 6,561 pieces, at most 10^4
    p.depth = 5;
    const view::Geometry smooth = view::geometry(d, p);
    check_same_points(smooth, runner_points(f.dir.path(), {{"automaton", d.path.string()}}, 5));
    CHECK(smooth.pieces == 243);
    CHECK(smooth.states.size() == 2 * 243);
    CHECK(smooth.contraction_length > 0);
    CHECK(smooth.contraction_delta < 1);
    const view::CoefficientRange& r = d.coefficients[3];
    p.values = {{r.name, 0.5 * (r.value + r.high)}};
    const view::Geometry moved = view::geometry(d, p);
    check_same_points(
        moved, runner_points(
                   f.dir.path(),
                   {{"automaton", d.path.string()},
                    {"perturbation", {{"amplitude", 0}, {"values", {{r.name, 0.5 * (r.value + r.high)}}}}}},
                   5));
    CHECK(moved.checksum != smooth.checksum);
  }
}

TEST_CASE("view handle on a BC-IFS file: values refused outside their ranges, 422 when not contractive, save",
          "[view][view_bcifs]") {
  cifs_test::ViewFixture f("automata/tree.json");
  const view::CoefficientRange r = f.session.document.coefficients[3];
  const auto body = [](const nlohmann::json& params) { return nlohmann::json{{"params", params}}.dump(); };
  const view::Response ok = f.post("/api/geometry", body({{"depth", 4}, {"values", {{r.name, r.value}}}}));
  REQUIRE(ok.status == 200);
  const auto document =
      nlohmann::json::parse(view::handle(f.session, {.method = "GET",
                                                     .target = "/api/document?token=" + f.session.token,
                                                     .host = "127.0.0.1:8765",
                                                     .body = {}})
                                .body);
  CHECK(document["kind"] == "bcifs");
  CHECK(document["coefficients"].size() == 10);
  CHECK(document["coefficients"][3]["name"] == r.name);

  const view::Response outside =
      f.post("/api/geometry", body({{"depth", 4}, {"values", {{r.name, r.high + 0.01}}}}));
  CHECK(outside.status == 400);
  CHECK(outside.body.starts_with("cifs view: " + r.name + " = "));
  CHECK(outside.body.find("outside its admissible range") != std::string::npos);
  CHECK(std::count(outside.body.begin(), outside.body.end(), '\n') == 1);
  const view::Response unknown = f.post("/api/geometry", body({{"values", {{"E/Q[0,0]", 0.1}}}}));
  CHECK(unknown.status == 400);
  CHECK(unknown.body.find("E/Q[0,0]") != std::string::npos);
  CHECK(f.post("/api/geometry", R"({"params": {"values": {"E/G[1,0]": 1e400}}})").status == 400);
  CHECK(f.post("/api/geometry", R"({"params": {"values": {"E/G[1,0]": "0.5"}}})").status == 400);
  CHECK(f.post("/api/geometry", R"({"params": {"values": [0.5]}})").status == 400);
  CHECK(f.post("/api/geometry", body({{"depth", 21}})).status == 400);
  // A random draw of amplitude 0.8 (seed 3) leaves the system non-contractive: 422, the library's δ in the
  // line.
  const view::Response refused =
      f.post("/api/geometry", body({{"depth", 4}, {"amplitude", 0.8}, {"seed", 3}}));
  CHECK(refused.status == 422);
  CHECK(refused.body.find("not contractive") != std::string::npos);
  CHECK(refused.body.find("δ = ") != std::string::npos);
  CHECK(f.post("/api/geometry", body({{"depth", 4}})).status == 200);  // still serving

  const double edited = 0.5 * (r.value + r.low);
  const view::Response saved = f.post(
      "/api/save",
      nlohmann::json{{"name", "tree-edited.json"}, {"params", {{"values", {{r.name, edited}}}}}}.dump());
  REQUIRE(saved.status == 200);
  const io::BcifsFile back = io::read_bcifs(f.dir.path() / "tree-edited.json");
  const ifs::AdmissibleSpace space = ifs::admissible_space(back.system);
  CHECK(ifs::free_values(back.system, space)(3) == Approx(edited).epsilon(1e-12));
  CHECK(back.nets.size() == 1);
  CHECK(f.post("/api/save",
               nlohmann::json{{"name", "x.json"}, {"params", {{"values", {{r.name, r.high + 1}}}}}}.dump())
            .status == 400);
  CHECK(!std::filesystem::exists(f.dir.path() / "x.json"));
}

TEST_CASE(
    "view perturbed shapes: the system built once, an amplitude edit re-perturbs it, the runner's points",
    "[view][view_bcifs]") {
  cifs_test::ScratchDir dir;
  const auto shape_runner = [&](const std::string& shape, double amplitude, std::uint64_t seed, int depth) {
    return runner_points(
        dir.path(), {{"shape", shape}, {"perturbation", {{"amplitude", amplitude}, {"seed", seed}}}}, depth);
  };
  SECTION("a curve") {
    const std::string path = kBcifsExamples + "/shapes/wave.json";
    const view::Document d = view::open_document(path);
    view::EditCache cache;
    view::Params p = view::default_params(d);
    p.depth = 7;
    p.amplitude = 0.1;
    p.seed = 7;
    const view::Geometry a = view::geometry(d, p, {}, &cache);
    check_same_points(a, shape_runner(path, 0.1, 7, 7));
    CHECK(a.states.size() == a.positions.size() / 3);
    const auto built = cache.system;
    REQUIRE(built);
    p.amplitude = 0.2;
    p.seed = 8;
    check_same_points(view::geometry(d, p, {}, &cache), shape_runner(path, 0.2, 8, 7));
    CHECK(cache.system == built);  // re-perturbed, not built again
    // A moved point: another shape, its system built again.
    const auto& curve = std::get<nurbs::Curve>(*d.shape);
    Points cartesian = nurbs::cartesian_points(curve);
    cartesian(2, 0) += 0.25;
    p.points = {{.index = 2, .position = {cartesian(2, 0), cartesian(2, 1)}}};
    const nurbs::Curve moved = nurbs::make_curve(curve.degree, curve.knots, cartesian, nurbs::weights(curve));
    const std::filesystem::path moved_file = dir.path() / "moved.json";
    io::write(moved_file, io::Shape(moved));
    check_same_points(view::geometry(d, p, {}, &cache), shape_runner(moved_file.string(), 0.2, 8, 7));
    CHECK(cache.system != built);
  }
  SECTION("a rational surface (2 × 1 biquadratic patches: small, so that the test stays fast)") {
    const std::string path = kBcifsExamples + "/shapes/saddle.json";
    const view::Document d = view::open_document(path);
    view::EditCache cache;
    view::Params p = view::default_params(d);
    p.depth = 3;
    p.amplitude = 0.05;
    const view::Geometry a = view::geometry(d, p, {}, &cache);
    check_same_points(a, shape_runner(path, 0.05, 1, 3));
    REQUIRE(a.grid[0] * a.grid[1] == a.positions.size() / 3);
    CHECK(a.states.size() == a.positions.size() / 3);
    const auto built = cache.system;
    p.seed = 2;
    check_same_points(view::geometry(d, p, {}, &cache), shape_runner(path, 0.05, 2, 3));
    CHECK(cache.system == built);
  }
}

TEST_CASE(
    "view opens an experiment file: its source, depth and perturbation as the runner's; save writes it back",
    "[view][view_bcifs]") {
  cifs_test::ScratchDir dir;
  const std::filesystem::path file = dir.path() / "wave_fractal.json";
  const nlohmann::json experiment = {{"name", "wave-fractal"},
                                     {"shape", kBcifsExamples + "/shapes/wave.json"},
                                     {"perturbation", {{"amplitude", 0.3}, {"seed", 7}}},
                                     {"evaluation", {{"depth", 6}}},
                                     {"render", {{"width", 300}, {"height", 200}}},
                                     {"outputs", {{"png", "wave_fractal.png"}}}};
  std::ofstream(file) << experiment.dump(2);
  view::Session session;
  view::open_session(session, file, "127.0.0.1", 8765);
  const view::Document& d = session.document;
  CHECK(d.kind == view::Kind::curve);
  REQUIRE(d.experiment);
  const view::Params p = view::default_params(d);
  CHECK(p.depth == 6);
  CHECK(p.amplitude == 0.3);
  CHECK(p.seed == 7);
  check_same_points(view::geometry(d, p), experiment::evaluate(io::read_experiment(file)).points);
  const auto post = [&](const std::string& path, const nlohmann::json& body) {
    return view::handle(session, {.method = "POST",
                                  .target = path + "?token=" + session.token,
                                  .host = "127.0.0.1:8765",
                                  .body = body.dump()});
  };
  const view::Response saved =
      post("/api/save",
           {{"name", "wave-edited.json"}, {"params", {{"amplitude", 0.2}, {"seed", 9}, {"depth", 5}}}});
  REQUIRE(saved.status == 200);
  const io::Experiment back = io::read_experiment(dir.path() / "wave-edited.json");
  REQUIRE(back.perturbation);
  CHECK(back.perturbation->amplitude == 0.2);
  CHECK(back.perturbation->seed == 9);
  CHECK(back.evaluation.depth == 5);
  CHECK(back.render.width == 300);  // the rest as written
  CHECK(back.outputs.png == "wave_fractal.png");
  // A moved control point: the experiment saved with its shape inline (the edited shape, as make_curve builds
  // it by hand here), and the runner's points of the saved file are those the view shows.
  const view::Response with_point =
      post("/api/save", {{"name", "wave-moved.json"}, {"params", {{"depth", 6}, {"points", {{0, 1, 2}}}}}});
  REQUIRE(with_point.status == 200);
  const io::Experiment back_moved = io::read_experiment(dir.path() / "wave-moved.json");
  const auto& file_curve = std::get<nurbs::Curve>(*d.shape);
  Points cartesian = nurbs::cartesian_points(file_curve);
  cartesian.row(0) << 1, 2;
  const nurbs::Curve by_hand =
      nurbs::make_curve(file_curve.degree, file_curve.knots, cartesian, nurbs::weights(file_curve));
  REQUIRE(back_moved.shape);
  CHECK(std::get<nurbs::Curve>(*back_moved.shape).P == by_hand.P);
  view::Params moved = p;
  moved.points = {{.index = 0, .position = {1, 2}}};
  check_same_points(view::geometry(d, moved), experiment::evaluate(back_moved).points);
  CHECK(back_moved.perturbation->amplitude == 0.3);
}

TEST_CASE(
    "view perturbed edits: a session's fast path gives the cold evaluation's bytes and the runner's points",
    "[view][view_bcifs]") {
  // Random amplitude and seed edits through one session (the kept system, surface mesh and failing paths,
  // the contractivity checked beside the evaluation) against a cold evaluation of each (no cache) and the
  // runner's points (experiment::evaluate: the system built, solved and perturbed from the file); a refused
  // edit is refused alike, with the same message.
  cifs_test::ScratchDir dir;
  std::mt19937_64 random(2026);
  int refusals = 0;
  for (const auto& [file, depth, top] :
       {std::tuple{"wave.json", 6, 0.8}, std::tuple{"saddle.json", 3, 0.3}}) {
    const std::string path = kBcifsExamples + "/shapes/" + file;
    INFO(path);
    const view::Document d = view::open_document(path);
    view::EditCache cache;
    view::Params p = view::default_params(d);
    p.depth = depth;
    int accepted = 0, refused = 0;
    for (int edit = 0; edit < 8; ++edit) {
      p.amplitude = std::uniform_real_distribution<double>(0, top)(random);
      p.seed = random() % 4 + 1;
      INFO("amplitude " << p.amplitude << ", seed " << p.seed);
      std::string fast_refusal, cold_refusal;
      view::Geometry fast, cold;
      try {
        fast = view::geometry(d, p, {}, &cache);
      } catch (const InvalidInput& e) {
        fast_refusal = e.what();
      }
      try {
        cold = view::geometry(d, p);
      } catch (const InvalidInput& e) {
        cold_refusal = e.what();
      }
      CHECK(fast_refusal == cold_refusal);
      if (!fast_refusal.empty()) {
        ++refused;
        continue;
      }
      ++accepted;
      CHECK(view::encode_geometry(fast) == view::encode_geometry(cold));
      CHECK(fast.contraction_length > 0);
      check_same_points(
          fast,
          runner_points(dir.path(),
                        {{"shape", path}, {"perturbation", {{"amplitude", p.amplitude}, {"seed", p.seed}}}},
                        depth));
    }
    CHECK(accepted > 0);
    refusals += refused;
  }
  CHECK(refusals > 0);  // the curve's amplitudes reach systems that are not contractive
}

TEST_CASE(
    "view BC-IFS nets: a moved point and its copies in the other nets give the runner's pieces of the "
    "edited file; refusals; save",
    "[view][view_bcifs]") {
  // A file of several nets, joined where neighbouring pieces' windows overlap, as cifs fit --fractal writes
  // one: the BC-IFS of cubic.json (3 segments: control point 2 is row 2, 1, 0 of nets 0, 1, 2) with the
  // knot automaton's nets.
  cifs_test::ScratchDir dir;
  const auto curve = std::get<nurbs::Curve>(io::read_shape(kBcifsExamples + "/shapes/cubic.json"));
  const ifs::Bcifs system = ifs::curve_bcifs(curve);
  const std::vector<Points> nets = nurbs::initial_nets(nurbs::knot_automaton(curve), curve);
  REQUIRE(nets.size() == 3);
  const std::filesystem::path file = dir.path() / "cubic_bcifs.json";
  io::write(file, io::BcifsFile{system, nets});
  view::Session session;
  view::open_session(session, file, "127.0.0.1", 8765);
  const view::Document& d = session.document;
  REQUIRE(d.kind == view::Kind::bcifs);
  const auto post = [&](const std::string& path, const nlohmann::json& body) {
    return view::handle(session, {.method = "POST",
                                  .target = path + "?token=" + session.token,
                                  .host = "127.0.0.1:8765",
                                  .body = body.dump()});
  };
  const auto params = [](const nlohmann::json& edits) {
    return nlohmann::json{{"depth", 5}, {"nets", edits}};
  };

  // The expected nets: those of the curve with control point 2 moved (the knot automaton's windows of the
  // edited polygon), and the runner's pieces of a file holding them beside the same system.
  Points polygon = curve.P;
  polygon.row(2) << 2.5, 3.75, -1.0;
  const nurbs::Curve moved = nurbs::make_curve(curve.degree, curve.knots, polygon);
  const std::vector<Points> expected = nurbs::initial_nets(nurbs::knot_automaton(moved), moved);
  REQUIRE(expected[1].row(1) == polygon.row(2));
  const std::filesystem::path edited_file = dir.path() / "expected.json";
  io::write(edited_file, io::BcifsFile{system, expected});
  const Points runner = runner_points(dir.path(), {{"automaton", edited_file.string()}}, 5);

  view::Params p = view::default_params(d);
  p.depth = 5;
  const view::Geometry before = view::geometry(d, p);
  {  // each of the point's three copies, dragged, moves all three: the runner's pieces of the edited file
    for (const auto& [net, index] : {std::pair{0, 2}, std::pair{1, 1}, std::pair{2, 0}}) {
      p.nets = {{.net = std::size_t(net), .index = std::size_t(index), .position = {2.5, 3.75, -1.0}}};
      CHECK(view::edited_nets(d, p) == expected);
      const view::Geometry g = view::geometry(d, p);
      check_same_points(g, runner);
      CHECK(g.checksum != before.checksum);
      std::vector<float> drawn;
      for (const Points& n : expected) {
        const std::vector<float> rows = cifs_test::page_floats(n);
        drawn.insert(drawn.end(), rows.begin(), rows.end());
      }
      CHECK(g.net == drawn);
      // The matrices are not read: the contractivity is the file's, to the bit.
      CHECK(g.contraction_length == before.contraction_length);
      CHECK(g.contraction_delta == before.contraction_delta);
    }
    // Through the handler: the bytes of the same geometry.
    const view::Response r = post("/api/geometry", {{"params", params({{1, 1, 2.5, 3.75, -1.0}})}});
    REQUIRE(r.status == 200);
    CHECK(r.body == view::encode_geometry(view::geometry(d, p)));
  }
  {  // refusals, one line each, and the server keeps serving
    const auto refused = [&](const nlohmann::json& body, const std::string& says) {
      const view::Response r = post("/api/geometry", body);
      CAPTURE(body.dump(), r.body);
      CHECK(r.status == 400);
      CHECK(r.body.find(says) != std::string::npos);
      CHECK(std::count(r.body.begin(), r.body.end(), '\n') == 1);
    };
    // Two positions for one joined point would pull the pieces apart.
    refused({{"params", params({{0, 2, 2.5, 3.75, -1}, {2, 0, 2.5, 3.75, -2}})}},
            "cubic_bcifs.json: net 2 point 0 and net 0 point 2 are one point of the file's nets");
    refused({{"params", params({{3, 0, 1, 2, 3}})}}, "net 3 point 0: the file has 3 control nets");
    refused({{"params", params({{1, 4, 1, 2, 3}})}}, "net 1 point 4: the net has 4 points");
    refused({{"params", params({{1, 1, 1, 2}})}}, "net 1 point 1: 2 coordinates for a 3-D point");
    refused({{"params", params({{1, 1, "1", 2, 3}})}}, "each edit of nets is [net, index, x, y(, z)]");
    refused({{"params", params({{-1, 1, 1, 2, 3}})}}, "each edit of nets is");
    refused({{"params", {{"points", {{1, 1, 2, 3}}}}}},
            "points: a BC-IFS file's control points are edited as nets");
    CHECK(view::handle(session, {.method = "POST",
                                 .target = "/api/geometry?token=" + session.token,
                                 .host = "127.0.0.1:8765",
                                 .body = R"({"params": {"nets": [[1, 1, 1e400, 2, 3]]}})"})
              .status == 400);
    // The same position twice for one point is one edit.
    CHECK(
        post("/api/geometry", {{"params", params({{0, 2, 2.5, 3.75, -1}, {1, 1, 2.5, 3.75, -1}})}}).status ==
        200);
    p.nets = {{.net = 0, .index = 2, .position = {1, std::nan(""), 0}}};
    CHECK_THROWS_WITH(view::edited_nets(d, p),
                      Catch::Contains("net 0 point 2: a coordinate is not a finite"));
    // A shape's file has no nets.
    cifs_test::ViewFixture wave("shapes/wave.json");
    const view::Response shape =
        wave.post("/api/geometry", nlohmann::json{{"params", params({{0, 0, 1, 2}})}}.dump());
    CHECK(shape.status == 400);
    CHECK(shape.body.find("has no BC-IFS nets") != std::string::npos);
  }
  {  // save writes the edited nets beside the file's matrices
    const view::Response saved =
        post("/api/save", {{"name", "cubic-edited.json"}, {"params", params({{2, 0, 2.5, 3.75, -1.0}})}});
    REQUIRE(saved.status == 200);
    const io::BcifsFile back = io::read_bcifs(dir.path() / "cubic-edited.json");
    CHECK(back.nets == expected);
    const ifs::AdmissibleSpace space = ifs::admissible_space(back.system);
    CHECK(ifs::free_values(back.system, space) == ifs::free_values(system, space));
  }
  {  // render and the dimension readout with moved nets (and a perturbation): what a session opened on the
     // file holding those nets answers without them — the runner reads the edited nets from memory
    view::Session saved;
    view::open_session(saved, edited_file, "127.0.0.1", 8765);
    const auto ask = [](view::Session& s, const std::string& path, const nlohmann::json& body) {
      return view::handle(s, {.method = "POST",
                              .target = path + "?token=" + s.token,
                              .host = "127.0.0.1:8765",
                              .body = body.dump()});
    };
    nlohmann::json moved_params = params({{1, 1, 2.5, 3.75, -1.0}});
    moved_params["amplitude"] = 0.01;
    const nlohmann::json plain_params = {{"depth", 5}, {"amplitude", 0.01}};
    const view::Response dimension = post("/api/dimension", {{"params", moved_params}});
    REQUIRE(dimension.status == 200);
    CHECK(dimension.body == ask(saved, "/api/dimension", {{"params", plain_params}}).body);
    CHECK(dimension.body != post("/api/dimension", {{"params", plain_params}}).body);  // the nets do count
    REQUIRE(post("/api/render", {{"name", "moved.png"}, {"params", moved_params}}).status == 200);
    REQUIRE(ask(saved, "/api/render", {{"name", "saved.png"}, {"params", plain_params}}).status == 200);
    const auto bytes = [&](const std::string& name) {
      std::ifstream in(dir.path() / name, std::ios::binary);
      return std::string(std::istreambuf_iterator<char>(in), {});
    };
    CHECK(bytes("moved.png").size() > 1000);
    CHECK(bytes("moved.png") == bytes("saved.png"));
  }
}
