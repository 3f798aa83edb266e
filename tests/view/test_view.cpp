// SPDX-License-Identifier: MIT
// cifs view without a browser: the document's geometry against the library's own calls, the
// checksum against values computed apart (Python's struct + FNV-1a), and the request handler as a
// function: tokens, Host headers, traversal, bad JSON and huge depths refused, the server still answering.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/ifs/shape_attractor.hpp"
#include "cifs/io/cad.hpp"
#include "cifs/io/io.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/view/server.hpp"
#include "support/scratch.hpp"
#include "view/view_support.hpp"

using namespace cifs;

namespace {

const std::string kExamples = CIFS_EXAMPLES_DIR;

}  // namespace

TEST_CASE("view geometry_checksum is FNV-1a a 32-bit word at a time over the float32 positions", "[view]") {
  // Python: FNV-1a over struct.unpack('<3I', struct.pack('<3f', 1.0, -2.5, 0.1)).
  CHECK(view::geometry_checksum({1.0F, -2.5F, 0.1F}) == 0xf2fd4100U);
  // One word 0x61 takes FNV-1a's one step for the byte 'a': the published test vector 0xe40c292c.
  float a = 0;
  const std::uint32_t bits = 0x61;
  std::memcpy(&a, &bits, 4);
  CHECK(view::geometry_checksum({a}) == 0xe40c292cU);
  CHECK(view::geometry_checksum({}) == 0x811c9dc5U);
}

TEST_CASE("view geometry is the library's: curves, surfaces, meshes", "[view]") {
  SECTION("a rational curve: ifs::attractor's points, one state per point, the net") {
    const view::Document d = view::open_document(kExamples + "/shapes/wave.json");
    REQUIRE(d.kind == view::Kind::curve);
    view::Params p = view::default_params(d);
    p.depth = 6;
    const view::Geometry g = view::geometry(d, p);
    const auto& curve = std::get<nurbs::Curve>(*d.shape);
    CHECK(g.positions == cifs_test::page_floats(ifs::attractor(curve, 6)));
    CHECK(g.states.size() == g.positions.size() / 3);
    CHECK(!g.closed);
    CHECK(g.checksum == view::geometry_checksum(g.positions));
    CHECK(g.net == cifs_test::page_floats(nurbs::cartesian_points(curve)));
  }
  SECTION("a moved control point: the curve made with that point, its weight kept") {
    const view::Document d = view::open_document(kExamples + "/shapes/wave.json");
    const auto& curve = std::get<nurbs::Curve>(*d.shape);
    Points cartesian = nurbs::cartesian_points(curve);
    cartesian.row(2) = Eigen::RowVector3d(0.25, -1.5, 0.75).head(cartesian.cols());
    std::vector<double> moved(cartesian.row(2).data(), cartesian.row(2).data() + cartesian.cols());
    const nurbs::Curve by_hand =
        nurbs::make_curve(curve.degree, curve.knots, cartesian, nurbs::weights(curve));
    view::Params p = view::default_params(d);
    p.depth = 5;
    p.points = {{.index = 2, .position = moved}};
    CHECK(view::geometry(d, p).positions == cifs_test::page_floats(ifs::attractor(by_hand, 5)));
    p.points = {{.index = 99, .position = moved}};
    CHECK_THROWS_WITH(view::geometry(d, p), Catch::Contains("point 99") && Catch::Contains("control points"));
  }
  SECTION("a surface: ifs::attractor's mesh as triangles, a state per vertex") {
    const view::Document d = view::open_document(kExamples + "/shapes/hills.json");
    REQUIRE(d.kind == view::Kind::surface);
    view::Params p = view::default_params(d);
    p.depth = 3;
    const view::Geometry g = view::geometry(d, p);
    const Mesh m = ifs::attractor(std::get<nurbs::Surface>(*d.shape), 3);
    CHECK(g.positions == cifs_test::page_floats(m.vertices));
    CHECK(g.triangles.empty());  // the page makes them from the grid
    REQUIRE(g.grid[0] * g.grid[1] == g.positions.size() / 3);
    for (std::size_t f = 0; f < m.states.size(); ++f) {  // the grid's cells are the mesh's faces
      const std::uint32_t v = g.grid[1] * static_cast<std::uint32_t>(f / (g.grid[1] - 1)) +
                              static_cast<std::uint32_t>(f % (g.grid[1] - 1));
      CHECK(m.face_vertices[4 * f] == static_cast<int>(v));
      CHECK(m.face_vertices[4 * f + 1] == static_cast<int>(v + g.grid[1]));
      CHECK(m.face_vertices[4 * f + 2] == static_cast<int>(v + g.grid[1] + 1));
      CHECK(m.face_vertices[4 * f + 3] == static_cast<int>(v + 1));
    }
    REQUIRE(g.states.size() == g.positions.size() / 3);
    for (const std::uint32_t s : g.states)
      CHECK(std::find(m.states.begin(), m.states.end(), s) != m.states.end());
  }
  SECTION("a mesh: subdivision::subdivide, quads as two triangles") {
    const view::Document d = view::open_document(kExamples + "/meshes/cube.obj");
    REQUIRE(d.kind == view::Kind::mesh);
    view::Params p = view::default_params(d);
    CHECK(p.scheme == "catmull-clark");
    p.levels = 2;
    const view::Geometry g = view::geometry(d, p);
    const Mesh m = subdivision::catmull_clark(d.mesh, 2);
    CHECK(g.positions == cifs_test::page_floats(m.vertices));
    CHECK(g.triangles.size() == 3 * 2 * (m.face_offsets.size() - 1));
    CHECK(g.net_lines.size() == 2 * 12);  // the cube's 12 edges, once each
  }
  SECTION("refused before any work: depth and levels beyond the limits, other files") {
    const view::Document d = view::open_document(kExamples + "/shapes/hills.json");
    view::Params p = view::default_params(d);
    p.depth = 40;
    CHECK_THROWS_WITH(view::geometry(d, p), "depth 40 is outside 0..10 (the view's limit)");
    p.depth = 9;  // within the range, above the point budget
    CHECK_THROWS_AS(view::geometry(d, p, {.max_points = 100000}), InvalidInput);
    CHECK_THROWS_WITH(view::open_document(kExamples + "/shapes/hepta.json"),
                      Catch::Contains("hepta.json: cifs view shows shapes"));
  }
}

TEST_CASE("view geometry with an amplitude: the perturbed BC-IFS, knot and end points kept", "[view]") {
  const view::Document d = view::open_document(kExamples + "/shapes/wave.json");
  view::Params p = view::default_params(d);
  p.depth = 6;
  const view::Geometry smooth = view::geometry(d, p);
  p.amplitude = 0.1;
  p.seed = 7;
  const view::Geometry fractal = view::geometry(d, p);
  REQUIRE(fractal.positions.size() == smooth.positions.size());
  // Point i·2^6 is the start of segment i (a knot point) or the end point: kept on the NURBS curve.
  const std::size_t points = smooth.positions.size() / 3, segment = std::size_t{1} << 6;
  std::size_t moved = 0;
  for (std::size_t i = 0; i < points; ++i) {
    const bool knot = i % segment == 0 || i + 1 == points;
    bool same = true;
    for (int k = 0; k < 3; ++k)
      same = same && std::abs(fractal.positions[3 * i + k] - smooth.positions[3 * i + k]) <=
                         1e-5F * (1 + std::abs(smooth.positions[3 * i + k]));
    if (knot) CHECK(same);
    moved += same ? 0 : 1;
  }
  CHECK(moved > points / 2);
  CHECK(fractal.states.size() == points);  // the perturbed automaton keeps the states
  p.seed = 8;
  CHECK(view::geometry(d, p).checksum != fractal.checksum);  // another seed, another fractal
  p.amplitude = 2;
  CHECK_THROWS_WITH(view::geometry(d, p), Catch::Contains("amplitude"));
  // A surface: the grid of its patches, 2^depth cells each way.
  const view::Document hills = view::open_document(kExamples + "/shapes/hills.json");
  view::Params h = view::default_params(hills);
  h.depth = 3;
  const view::Geometry flat = view::geometry(hills, h);
  h.amplitude = 0.05;
  const view::Geometry rough = view::geometry(hills, h);
  CHECK(rough.grid == flat.grid);
  CHECK(rough.positions.size() == flat.positions.size());
  CHECK(rough.checksum != flat.checksum);
}

TEST_CASE("view encode_geometry: header, then the arrays on 4-byte boundaries", "[view]") {
  const view::Document d = view::open_document(kExamples + "/shapes/cubic.json");
  view::Params p = view::default_params(d);
  p.depth = 2;
  const view::Geometry g = view::geometry(d, p);
  const std::string bytes = view::encode_geometry(g);
  REQUIRE(bytes.starts_with("CIFSVIEW"));
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 8, 4);
  CHECK((12 + length) % 4 == 0);
  const auto header = nlohmann::json::parse(bytes.substr(12, length));
  CHECK(header["checksum"] == g.checksum);
  std::vector<float> positions(g.positions.size());
  std::memcpy(positions.data(), bytes.data() + 12 + length, 4 * positions.size());
  CHECK(positions == g.positions);
  CHECK(bytes.size() == 12 + length +
                            4 * (g.positions.size() + g.triangles.size() + g.states.size() + g.net.size() +
                                 g.net_lines.size()));
}

TEST_CASE("view handle: hostile requests refused with a 4xx, the session still answers", "[view]") {
  cifs_test::ViewFixture f("shapes/hills.json");
  const std::string q = "?token=" + f.session.token;
  const auto good = [&] {
    const view::Response r = f.post("/api/geometry", R"({"params": {"depth": 2}})");
    CHECK(r.status == 200);
    CHECK(r.body.starts_with("CIFSVIEW"));
  };
  good();
  CHECK(f.get("/api/document" + q).status == 200);
  CHECK(f.get("/").body.find("view.js") != std::string::npos);  // the page itself needs no token

  SECTION("Host header and token") {
    const view::Response foreign = f.get("/api/document" + q, "evil.example");
    CHECK(foreign.status == 403);
    CHECK(foreign.body == "cifs view: Host 'evil.example' is not the address cifs view serves\n");
    CHECK(f.get("/", "127.0.0.1:9999").status == 403);  // another port: another origin
    CHECK(f.get("/api/document" + q, "localhost:8765").status == 200);
    CHECK(f.get("/api/document").status == 403);
    std::string wrong = f.session.token;
    wrong[0] = wrong[0] == '0' ? '1' : '0';  // one digit off
    CHECK(f.get("/api/document?token=" + wrong).status == 403);
    CHECK(f.get("/api/document?token=" + f.session.token + "x").status == 403);
  }
  SECTION("paths outside the page and the folder") {
    for (const std::string target :
         {"/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/%2E%2E%2Fetc%2Fpasswd",
          "/three/../../../etc/passwd", "/view.js%00", "/%zz"}) {
      const view::Response r = f.get(target);
      CAPTURE(target, r.body);
      CHECK(r.status >= 400);
      CHECK(r.status < 500);
    }
    CHECK(f.get("/etc/passwd").status == 404);
    for (const std::string name :
         {"../x.json", "/tmp/x.json", "..", ".hidden.json", "a/b.json", "%2e%2e%2fx.json"}) {
      const nlohmann::json body = {{"name", name}};
      CAPTURE(name);
      CHECK(f.post("/api/save", body.dump()).status == 403);
      CHECK(f.post("/api/open", body.dump()).status == 403);
    }
    std::filesystem::create_symlink("/etc/passwd", f.dir.path() / "link.json");
    CHECK(f.post("/api/open", R"({"name": "link.json"})").status == 403);
    CHECK(!std::filesystem::exists(f.dir.path().parent_path() / "x.json"));
  }
  SECTION("bad bodies and parameters") {
    const view::Response bad = f.post("/api/geometry", R"({"params": )");
    CHECK(bad.status == 400);
    CHECK(bad.body == "cifs view: /api/geometry: malformed JSON at byte 12\n");
    CHECK(f.post("/api/geometry", "[1, 2]").status == 400);
    CHECK(f.post("/api/geometry", R"({"params": {"depth": 1000000000000}})").status == 400);
    CHECK(f.post("/api/geometry", R"({"params": {"depth": "7"}})").status == 400);
    CHECK(f.post("/api/geometry", R"({"params": {"dpeth": 7}})").body ==
          "cifs view: /api/geometry: unknown parameter 'dpeth' (depth, scheme, levels, points, weights, "
          "knots, nets, amplitude, seed, values)\n");
    CHECK(f.post("/api/geometry", R"({"params": {"depth": 11}})").status == 400);
    CHECK(f.post("/api/geometry", R"({"params": {"points": [[0, 1e400, 0, 0]]}})").status == 400);
    CHECK(f.post("/api/geometry", R"({"params": {"points": [[0, 1, 2]]}})").status ==
          400);  // 2 of 3 coordinates
    CHECK(f.post("/api/geometry", R"({"params": {"points": [[-1, 1, 2, 3]]}})").status == 400);
    CHECK(f.post("/api/geometry", std::string(f.session.max_body + 1, ' ')).status == 413);
    CHECK(f.get("/api/geometry" + q).status == 404);  // GET of a POST route
  }
  good();
}

TEST_CASE("view handle: a session's edits write over its kept buffers, the bytes of a fresh session's",
          "[view]") {
  // One session (its EditCache, surface mesh and Geometry kept between requests) through a sequence — another
  // point, another depth, the perturbed route at the same depth and back, another file of another kind —
  // against each request answered by a session opened afresh for it (nothing kept): the same bytes. The
  // first edit's positions are also ifs::attractor's of the surface moved by hand.
  cifs_test::ViewFixture f("shapes/saddle.json");
  for (const char* other : {"shapes/cubic.json", "meshes/cube.obj"})
    std::filesystem::copy_file(kExamples + "/" + other,
                               f.dir.path() / std::filesystem::path(other).filename());
  const auto same_as_fresh = [&](const nlohmann::json& params) {
    CAPTURE(f.session.document.path.filename().string(), params.dump());
    const std::string body = nlohmann::json{{"params", params}}.dump();
    const view::Response kept = f.post("/api/geometry", body);
    REQUIRE(kept.status == 200);
    view::Session fresh;
    view::open_session(fresh, f.session.document.path, "127.0.0.1", 8765);
    const view::Response alone = view::handle(fresh, {.method = "POST",
                                                      .target = "/api/geometry?token=" + fresh.token,
                                                      .host = "127.0.0.1:8765",
                                                      .body = body});
    REQUIRE(alone.status == 200);
    CHECK(kept.body == alone.body);
  };
  same_as_fresh({{"depth", 3}, {"points", {{1, 0.25, 1.5, 0.75}}}});
  const auto& saddle = std::get<nurbs::Surface>(*f.session.document.shape);
  Points cartesian = nurbs::cartesian_points(saddle);
  cartesian.row(1) = Eigen::RowVector3d(0.25, 1.5, 0.75);
  const nurbs::Surface by_hand =
      nurbs::make_surface(saddle.degree, saddle.knots, saddle.count, cartesian, nurbs::weights(saddle));
  CHECK(f.session.geometry.positions == cifs_test::page_floats(ifs::attractor(by_hand, 3).vertices));
  same_as_fresh({{"depth", 3}, {"points", {{2, 0.5, 2, -0.25}}}});  // the mesh's faces kept
  same_as_fresh({{"depth", 4}});
  same_as_fresh({{"depth", 4}, {"amplitude", 0.05}});  // the generic route at the depth of the kept mesh
  same_as_fresh({{"depth", 4}, {"points", {{1, 0.25, 1.5, 0.75}}}});
  same_as_fresh({{"depth", 2}, {"amplitude", 0.05}, {"seed", 2}});
  same_as_fresh(
      {{"depth", 2}, {"amplitude", 0.08}, {"seed", 3}});  // the failing paths of the last edits kept
  REQUIRE(f.post("/api/open", R"({"name": "cubic.json"})").status == 200);
  same_as_fresh({{"depth", 6}});
  same_as_fresh({{"depth", 6}, {"points", {{1, 1, 2.5, 0}}}});
  same_as_fresh({{"depth", 5}, {"amplitude", 0.1}});
  REQUIRE(f.post("/api/open", R"({"name": "cube.obj"})").status == 200);
  same_as_fresh({{"levels", 1}});  // no states: a mesh after a curve
}

TEST_CASE("view handle: save writes the edited shape into the folder, atomically", "[view]") {
  cifs_test::ViewFixture f("shapes/cubic.json");
  const view::Response r =
      f.post("/api/save", R"({"name": "edited.json", "params": {"points": [[1, 0.5, 0.5, 0.5]]}})");
  REQUIRE(r.status == 200);
  const auto saved = std::get<nurbs::Curve>(io::read_shape(f.dir.path() / "edited.json"));
  CHECK(nurbs::cartesian_points(saved).row(1) == Eigen::RowVector3d(0.5, 0.5, 0.5));
  CHECK(f.post("/api/save", R"({"name": "edited.png"})").status == 400);
  // The opened file itself is an input of the run: cifs view's CLI refuses to overwrite it (RunInputs).
}

TEST_CASE("view handle: a geometry request overtaken while it waited is answered 204 unevaluated", "[view]") {
  cifs_test::ViewFixture f("shapes/hills.json");
  view::Response first, second;
  {
    std::unique_lock hold(f.session.evaluating);  // an evaluation in progress
    std::thread a([&] { first = f.post("/api/geometry", R"({"params": {"depth": 3}})"); });
    while (f.session.latest < 1) std::this_thread::yield();
    std::thread b([&] { second = f.post("/api/geometry", R"({"params": {"depth": 4}})"); });
    while (f.session.latest < 2) std::this_thread::yield();
    hold.unlock();
    a.join();
    b.join();
  }
  CHECK(first.status == 204);
  CHECK(first.body.empty());
  CHECK(second.status == 200);
}

TEST_CASE("view export_page writes the page, its geometry and three.js", "[view]") {
  cifs_test::ScratchDir dir;
  view::export_page(kExamples + "/shapes/wave.json", dir.path() / "page");
  for (const char* name :
       {"index.html", "view.js", "geometry.js", "three/three.min.js", "three/OrbitControls.js"})
    CHECK(std::filesystem::is_regular_file(dir.path() / "page" / name));
  std::ifstream in(dir.path() / "page" / "geometry.js");
  const std::string baked((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(baked.starts_with("window.cifsBaked = {document: {"));
  CHECK(baked.find("</") == std::string::npos);  // nothing that could close the script
}

TEST_CASE("view handle: the dimension readout and a render through the experiment runner", "[view]") {
  cifs_test::ViewFixture f("shapes/hills.json");
  const view::Response d = f.post("/api/dimension", R"({"params": {"depth": 4}})");
  REQUIRE(d.status == 200);
  const auto m = nlohmann::json::parse(d.body);
  // A smooth surface: 2, within three of the reported uncertainties (1.84 ± 0.075 at this small budget).
  CHECK(std::abs(m["dimension"].get<double>() - 2.0) <= 3 * m["uncertainty"].get<double>());
  const view::Response png = f.post("/api/render", R"({"name": "hills.png", "params": {"depth": 3}})");
  REQUIRE(png.status == 200);
  std::ifstream in(f.dir.path() / "hills.png", std::ios::binary);
  std::string magic(8, '\0');
  in.read(magic.data(), 8);
  CHECK(magic == "\x89PNG\r\n\x1a\n");
  CHECK(f.post("/api/render", R"({"name": "../hills.png"})").status == 403);
  CHECK(f.post("/api/render", R"({"name": "hills.svg"})").status == 400);
  cifs_test::ViewFixture curve("shapes/cubic.json");
  const auto c = nlohmann::json::parse(curve.post("/api/dimension", R"({"params": {"depth": 10}})").body);
  CHECK(std::abs(c["dimension"].get<double>() - 1.0) <=
        3 * c["uncertainty"].get<double>());  // a smooth curve
}

namespace {

/// The body a session opened afresh on `path` (nothing kept) answers to a geometry request.
std::string view_fresh_geometry(const std::filesystem::path& path, const std::string& body) {
  view::Session fresh;
  view::open_session(fresh, path, "127.0.0.1", 8765);
  const view::Response r = view::handle(fresh, {.method = "POST",
                                                .target = "/api/geometry?token=" + fresh.token,
                                                .host = "127.0.0.1:8765",
                                                .body = body});
  REQUIRE(r.status == 200);
  return r.body;
}

/// A refusal as the page shows it: a 4xx with one line "cifs view: …".
void check_view_refusal(const view::Response& r, const std::string& needle) {
  CAPTURE(r.status, r.body);
  CHECK(r.status >= 400);
  CHECK(r.status < 500);
  CHECK(r.body.starts_with("cifs view: "));
  CHECK(r.body.find('\n') == r.body.size() - 1);
  CHECK(r.body.find(needle) != std::string::npos);
}

}  // namespace

TEST_CASE("view handle: the folder's files to open from the page; a refused open keeps the shape", "[view]") {
  cifs_test::ViewFixture f("shapes/hills.json");
  const std::filesystem::path& dir = f.dir.path();
  for (const char* other : {"shapes/cubic.json", "meshes/cube.obj"})
    std::filesystem::copy_file(kExamples + "/" + other, dir / std::filesystem::path(other).filename());
  std::filesystem::copy_file(kExamples + "/meshes/cube.obj", dir / "CUBE.OBJ");  // extensions in any case
  for (const char* name : {"notes.txt", ".hidden.json", "50%.json"}) std::ofstream(dir / name) << "{}";
  std::ofstream(dir / "bad.json") << R"({"curve": {"degree": 3, "knots": [0, 1], "points": [[0, 0]]}})";
  std::filesystem::create_directory(dir / "folder.json");
  cifs_test::ScratchDir elsewhere;
  std::filesystem::copy_file(kExamples + "/shapes/cubic.json", elsewhere.path() / "away.json");
  std::filesystem::create_symlink(elsewhere.path() / "away.json", dir / "away.json");  // out of the folder
  std::filesystem::create_symlink(dir / "cubic.json", dir / "inside.json");            // a link within it
  const auto document = [&] {
    const view::Response r = f.get("/api/document?token=" + f.session.token);
    REQUIRE(r.status == 200);
    return nlohmann::json::parse(r.body);
  };
  // Plain names (no leading dot, no '%'), extensions cifs view reads, regular files in the folder, sorted.
  CHECK(document()["files"] ==
        nlohmann::json({"CUBE.OBJ", "bad.json", "cube.obj", "cubic.json", "hills.json", "inside.json"}));
  const std::string before = f.post("/api/geometry", R"({"params": {"depth": 2}})").body;
  REQUIRE(before.starts_with("CIFSVIEW"));
  check_view_refusal(f.post("/api/open", R"({"name": "bad.json"})"), "bad.json");
  check_view_refusal(f.post("/api/open", R"({"name": "notes.txt"})"), "notes.txt");
  check_view_refusal(f.post("/api/open", R"({"name": "folder.json"})"), "folder.json");
  check_view_refusal(f.post("/api/open", R"({"name": "away.json"})"), "links outside");
  check_view_refusal(f.post("/api/open", R"({"name": "sub/cubic.json"})"), "not a plain file name");
  check_view_refusal(f.post("/api/open", R"({"name": ".."})"), "not a plain file name");
  check_view_refusal(f.post("/api/open", R"({"name": "../hills.json"})"), "not a plain file name");
  check_view_refusal(f.post("/api/open", R"({"name": 7})"), "name is missing");
  CHECK(document()["name"] == "hills.json");  // the shape shown stays, and answers as before
  CHECK(f.post("/api/geometry", R"({"params": {"depth": 2}})").body == before);
  const view::Response opened = f.post("/api/open", R"({"name": "inside.json"})");
  REQUIRE(opened.status == 200);
  CHECK(nlohmann::json::parse(opened.body)["kind"] == "curve");
  CHECK(nlohmann::json::parse(opened.body)["files"] == document()["files"]);
}

TEST_CASE("view handle: the folder's list is what io reads: every listed file opens, no other does",
          "[view]") {
  // A file per extension io writes a shape, a mesh, a segment set or a point set in (written by io::write;
  // STEP and IGES, which cifs_tests cannot write, as a stub): the page lists the files of exactly the
  // extensions of which a file opens, or is refused for the build's want of OpenCASCADE alone. A listed
  // file that does not open is refused for what it holds (a point set in .json), never for its format
  // (.vtp is written as a mesh but not read; .svg and .npy are not read at all).
  cifs_test::ViewFixture f("shapes/cubic.json");
  const std::filesystem::path& dir = f.dir.path();
  std::vector<std::string> names{"cubic.json"};
  const auto write_each = [&](io::Content content, const std::string& stem, const auto& thing) {
    for (const io::Format& format : io::formats(content)) {
      if (!format.write) continue;
      const std::string name = stem + "_" + std::string(format.name) + std::string(format.extension);
      if (io::cad_format(name))
        std::ofstream(dir / name) << "stub";
      else
        io::write(dir / name, thing);
      names.push_back(name);
    }
  };
  write_each(io::Content::shape, "shape", io::read_shape(kExamples + "/shapes/wave.json"));
  write_each(io::Content::mesh, "mesh", io::read_mesh(kExamples + "/meshes/cube.obj"));
  write_each(io::Content::segments, "segments",
             Segments{.vertices = Points::Identity(2, 3), .segments = {{0, 1}}, .states = {}});
  write_each(io::Content::points, "points", io::PointSet{.points = Points::Identity(2, 3), .style = {}});
  const view::Response document = f.get("/api/document?token=" + f.session.token);
  REQUIRE(document.status == 200);
  const nlohmann::json listed = nlohmann::json::parse(document.body)["files"];
  std::map<std::string, bool> opens;  // by extension: a file of it opens, or wants OpenCASCADE alone
  std::map<std::string, std::string> refusals;
  for (const std::string& name : names) {
    const view::Response r = f.post("/api/open", nlohmann::json{{"name", name}}.dump());
    const bool cad = r.status == 400 && r.body.find("built without OpenCASCADE") != std::string::npos;
    opens[extension_of(name)] |= r.status == 200 || cad;
    if (r.status != 200 && !cad) refusals[name] = r.body;
  }
  for (const std::string& name : names) {
    CAPTURE(name, refusals[name]);
    const bool is_listed = std::count(listed.begin(), listed.end(), name) == 1;
    CHECK(is_listed == opens[extension_of(name)]);
    if (is_listed) CHECK(refusals[name].find(" is read from ") == std::string::npos);
  }
  CHECK(listed.size() == names.size() - 3);  // all but the .vtp mesh, the .svg segments and the .npy points
  CHECK(std::count_if(opens.begin(), opens.end(), [](const auto& e) { return e.second; }) == 9);
}

TEST_CASE("view handle: open A, edit, open B, open A again: each answer a fresh session's", "[view]") {
  // The session's kept automaton, system and mesh are dropped on open: A is read again (here rewritten in
  // between, its knots kept and a control point moved, so that anything kept from the first A is stale).
  cifs_test::ViewFixture f("shapes/saddle.json");
  const std::filesystem::path a = f.session.document.path, b = f.dir.path() / "wave.json";
  std::filesystem::copy_file(kExamples + "/shapes/wave.json", b);
  const std::string edit = R"({"params": {"depth": 3, "amplitude": 0.05, "points": [[1, 0.25, 1.5, 0.75]]}})";
  const std::string first = f.post("/api/geometry", edit).body;
  CHECK(first == view_fresh_geometry(a, edit));
  REQUIRE(f.post("/api/open", R"({"name": "wave.json"})").status == 200);
  CHECK(f.post("/api/geometry", R"({"params": {"depth": 5}})").body ==
        view_fresh_geometry(b, R"({"params": {"depth": 5}})"));
  std::string text = read_file(a);
  const std::size_t at = text.find("[1, 2, 0.5]");
  REQUIRE(at != std::string::npos);
  text.replace(at, 11, "[1, 2, 0.9]");
  std::ofstream(a) << text;
  REQUIRE(f.post("/api/open", R"({"name": "saddle.json"})").status == 200);
  const std::string again = f.post("/api/geometry", edit).body;
  CHECK(again == view_fresh_geometry(a, edit));
  CHECK(again != first);
}

TEST_CASE("view geometry with edited knots and weights: the library's shape edited by hand", "[view]") {
  const view::Document d = view::open_document(kExamples + "/shapes/wave.json");
  const auto& wave = std::get<nurbs::Curve>(*d.shape);
  view::Params p = view::default_params(d);
  p.depth = 5;
  view::EditCache cache;
  const view::Geometry file = view::geometry(d, p, {}, &cache);  // the cache holds the file's automaton
  SECTION("an open rational curve: new interior knots, a weight; the kept automaton is not reused") {
    p.knots = {{0, 0, 0, 0, 2, 2.5, 3.5, 6, 6, 6, 6}};
    p.weights = {{.index = 2, .weight = 2.5}};
    Eigen::VectorXd w = nurbs::weights(wave);
    w(2) = 2.5;
    const nurbs::Curve by_hand = nurbs::make_curve(3, p.knots[0], nurbs::cartesian_points(wave), w);
    const view::Geometry g = view::geometry(d, p, {}, &cache);
    CHECK(g.positions == cifs_test::page_floats(ifs::attractor(by_hand, 5)));
    CHECK(g.positions != file.positions);
    CHECK(g.net == file.net);  // a weight moves no control point
    p.weights.clear();         // the knots alone, through the same cache
    CHECK(view::geometry(d, p, {}, &cache).positions ==
          cifs_test::page_floats(ifs::attractor(
              nurbs::make_curve(3, p.knots[0], nurbs::cartesian_points(wave), nurbs::weights(wave)), 5)));
  }
  SECTION("a closed curve: its breakpoints; a non-rational curve given a weight") {
    const view::Document c = view::open_document(kExamples + "/shapes/closed_cubic.json");
    const auto& closed = std::get<nurbs::Curve>(*c.shape);
    view::Params q = view::default_params(c);
    q.depth = 4;
    (void)view::geometry(c, q, {}, &cache);
    CHECK(view::shape_knots(*c.shape) == std::vector<std::vector<double>>{{0, 1, 2, 3.5, 4, 6}});
    q.knots = {{0, 1.5, 2, 3, 4, 6}};
    q.weights = {{.index = 0, .weight = 3}};  // a point the closed curve's stored rows repeat
    const Eigen::VectorXd w = (Eigen::VectorXd(5) << 3, 1, 1, 1, 1).finished();
    const nurbs::Curve by_hand = nurbs::make_closed_curve(3, q.knots[0], nurbs::cartesian_points(closed), w);
    CHECK(view::geometry(c, q, {}, &cache).positions == cifs_test::page_floats(ifs::attractor(by_hand, 4)));
    q.knots = {{0, 0, 0, 0, 0, 6}};  // the seam's multiplicity above degree + 1 (make_closed_curve's check)
    CHECK_THROWS_WITH(view::geometry(c, q, {}, &cache),
                      Catch::Contains("closed_cubic.json: knots") && Catch::Contains("multiplicity"));
  }
  SECTION("a surface: knots in u and v, a weight; the perturbed route too") {
    const view::Document h = view::open_document(kExamples + "/shapes/saddle.json");
    const auto& saddle = std::get<nurbs::Surface>(*h.shape);
    view::Params q = view::default_params(h);
    q.depth = 3;
    (void)view::geometry(h, q, {}, &cache);
    q.knots = {{0, 0, 0, 0.5, 2, 2, 2}, {0, 0, 0, 1, 1, 1}};
    q.weights = {{.index = 0, .weight = 0.5}};
    Eigen::VectorXd w = nurbs::weights(saddle);
    w(0) = 0.5;
    const nurbs::Surface by_hand = nurbs::make_surface(saddle.degree, {q.knots[0], q.knots[1]}, saddle.count,
                                                       nurbs::cartesian_points(saddle), w);
    CHECK(view::geometry(h, q, {}, &cache).positions ==
          cifs_test::page_floats(ifs::attractor(by_hand, 3).vertices));
    // A non-rational surface given a weight, through a cache built for it non-rational.
    const view::Document hills = view::open_document(kExamples + "/shapes/hills.json");
    const auto& smooth = std::get<nurbs::Surface>(*hills.shape);
    view::Params r = view::default_params(hills);
    r.depth = 2;
    view::EditCache kept;
    (void)view::geometry(hills, r, {}, &kept);
    r.weights = {{.index = 24, .weight = 4}};
    Eigen::VectorXd ones = Eigen::VectorXd::Ones(49);
    ones(24) = 4;
    const nurbs::Surface weighted =
        nurbs::make_surface(smooth.degree, smooth.knots, smooth.count, nurbs::cartesian_points(smooth), ones);
    CHECK(view::geometry(hills, r, {}, &kept).positions ==
          cifs_test::page_floats(ifs::attractor(weighted, 2).vertices));
    q.amplitude = 0.05;  // the perturbed system of the edited shape, not of the file's
    const view::Geometry rough = view::geometry(h, q, {}, &cache);
    CHECK(rough.positions == view::geometry(h, q).positions);  // no cache: built for this request
    q.knots.clear();
    CHECK(view::geometry(h, q, {}, &cache).positions != rough.positions);
  }
  SECTION("refused edits name the knot or the weight; nothing is kept from them") {
    const auto refused = [&](view::Params bad, const std::string& needle) {
      CHECK_THROWS_WITH(view::geometry(d, bad, {}, &cache), Catch::Contains(needle));
      CHECK(view::geometry(d, p, {}, &cache).positions == file.positions);
    };
    view::Params bad = p;
    bad.knots = {{0, 0, 0, 0, 3, 1, 3.5, 6, 6, 6, 6}};
    refused(bad, "wave.json: knots[5]: 1 is less than the previous knot 3");
    bad.knots = {{0, 0, 0, 0, 3, 3, 3, 3, 3, 6, 6}};
    refused(bad, "has multiplicity 5 > degree + 1 = 4");
    bad.knots = {{0, 0, 0, 0, 1, 3, 3.5, 6, 6, 6}};
    refused(bad, "10 values, the file's 11");
    bad.knots = {{0, 0, 0, 0, 1, 3, 3.5, 6, 6, 6, 6}, {0, 1}};
    refused(bad, "2 lists for a curve");
    bad.knots.clear();
    bad.weights = {{.index = 1, .weight = 0}};
    refused(bad, "point 1: weight 0 is not a positive finite number");
    bad.weights = {{.index = 7, .weight = 1}};
    refused(bad, "point 7: the curve has 7 control points");
  }
}

TEST_CASE("view handle: knots and weights through the requests; save writes them, the automaton follows",
          "[view]") {
  cifs_test::ViewFixture f("shapes/wave.json");
  const std::string edit =
      R"({"params": {"depth": 5, "knots": [[0, 0, 0, 0, 2, 2.5, 3.5, 6, 6, 6, 6]], "weights": [[2, 2.5]]}})";
  const std::string plain = f.post("/api/geometry", R"({"params": {"depth": 5}})").body;
  const view::Response edited = f.post("/api/geometry", edit);
  REQUIRE(edited.status == 200);
  CHECK(edited.body == view_fresh_geometry(f.session.document.path, edit));
  const auto doc = nlohmann::json::parse(f.get("/api/document?token=" + f.session.token).body);
  CHECK(doc["knots"] == nlohmann::json::parse("[[0, 0, 0, 0, 1, 3, 3.5, 6, 6, 6, 6]]"));
  CHECK(doc["weights"] == nlohmann::json::parse("[1, 2, 0.5, 1, 3, 1, 1]"));
  CHECK(doc["degree"] == nlohmann::json::parse("[3]"));
  // A refused knot edit: one line, and the next request answers as before it.
  check_view_refusal(
      f.post("/api/geometry", R"({"params": {"depth": 5, "knots": [[0, 0, 0, 0, 3, 1, 3.5, 6, 6, 6, 6]]}})"),
      "knots[5]: 1 is less than the previous knot 3");
  check_view_refusal(f.post("/api/geometry", R"({"params": {"knots": [0, 1, 2]}})"), "list of lists");
  check_view_refusal(f.post("/api/geometry", R"({"params": {"weights": [[2, "x"]]}})"), "[index, weight]");
  check_view_refusal(f.post("/api/geometry", R"({"params": {"weights": [[2, -1]]}})"), "point 2: weight -1");
  CHECK(f.post("/api/geometry", R"({"params": {"depth": 5}})").body == plain);
  cifs_test::ViewFixture mesh("meshes/cube.obj");  // a mesh has neither
  check_view_refusal(mesh.post("/api/geometry", R"({"params": {"weights": [[0, 2]]}})"),
                     "knots, weights: cube.obj has none");
  // The automaton drawn: the edited knots' (a uniform interior has fewer distinct windows).
  const std::string svg = f.get("/api/automaton.svg?token=" + f.session.token).body;
  const std::string uniform =
      f.post("/api/automaton.svg", R"({"params": {"knots": [[0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4]]}})").body;
  const auto states = [](const std::string& s) {
    std::size_t n = 0;
    for (std::size_t at = s.find("<circle"); at != std::string::npos; at = s.find("<circle", at + 1)) ++n;
    return n;
  };
  const Eigen::Index expected =
      nurbs::knot_automaton(nurbs::make_curve(3, {0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4}, Points::Zero(7, 2)))
          .windows.size();
  CHECK(states(uniform) == static_cast<std::size_t>(expected));
  CHECK(states(uniform) != states(svg));
  // Save writes the knots and weights; the file reads back as the shape edited by hand.
  REQUIRE(
      f.post(
           "/api/save",
           R"({"name": "wave-knots.json", "params": {"knots": [[0, 0, 0, 0, 2, 2.5, 3.5, 6, 6, 6, 6]], "weights": [[2, 2.5]]}})")
          .status == 200);
  const auto saved = std::get<nurbs::Curve>(io::read_shape(f.dir.path() / "wave-knots.json"));
  CHECK(saved.knots == nurbs::Knots{0, 0, 0, 0, 2, 2.5, 3.5, 6, 6, 6, 6});
  CHECK(nurbs::weights(saved) == (Eigen::VectorXd(7) << 1, 2, 2.5, 1, 3, 1, 1).finished());
  CHECK(nurbs::cartesian_points(saved) ==
        nurbs::cartesian_points(std::get<nurbs::Curve>(*f.session.document.shape)));
}
