// SPDX-License-Identifier: MIT
// cifs subdivide, analyze, and info and automaton on polygon meshes, run as a user runs them.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "apps/cli_fixtures.hpp"
#include "apps/cli_runner.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "subdivision/meshes.hpp"

using namespace cifs;
using namespace cifs_test;
using nlohmann::json;

namespace {

/// A 4 × 4 grid of quads (vertex j·5 + i at (i, j, wave)) with semi-sharp and infinite creases, a
/// corner, a hole and UVs with a seam: the OBJ text the tagged-mesh tests read.
std::string tagged_grid_obj() {
  Mesh m;
  m.vertices.resize(25, 3);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) m.vertices.row(j * 5 + i) << i, j, 0.3 * std::sin(i + 2.0 * j);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) add_face(m, {j * 5 + i, j * 5 + i + 1, j * 5 + i + 6, j * 5 + i + 5});
  m.tags.creases = {{.a = 6, .b = 7, .sharpness = 2},
                    {.a = 7, .b = 8, .sharpness = 1.5},
                    {.a = 11, .b = 16, .sharpness = 10}};
  m.tags.corners = {{.vertex = 12, .sharpness = 3}};
  m.tags.holes = {15};
  FaceVaryingChannel uv;
  uv.values.resize(26, 2);
  for (int v = 0; v < 25; ++v) uv.values.row(v) << (v % 5) / 4.0, (v / 5) / 4.0;
  uv.values.row(25) << 0.6, 0.3;
  uv.indices = m.face_vertices;
  uv.indices[5] = 25;  // face 1's corner at vertex 2: a seam
  m.face_varying.push_back(uv);
  return io::mesh_obj(m);
}

}  // namespace

TEST_CASE("cifs subdivide writes the library's refinement, OBJ or PLY, or OBJ on stdout", "[cli][mesh]") {
  struct Case {
    const char* mesh;
    const char* scheme;
    subdivision::MeshScheme id;
  };
  for (const Case c : {Case{"open_grid.obj", "catmull-clark", subdivision::MeshScheme::catmull_clark},
                       Case{"icosahedron.obj", "loop", subdivision::MeshScheme::loop},
                       Case{"torus.obj", "doo-sabin", subdivision::MeshScheme::doo_sabin},
                       Case{"cube_triangles.obj", "butterfly", subdivision::MeshScheme::butterfly},
                       Case{"tetrahedron.obj", "sqrt3", subdivision::MeshScheme::sqrt3}}) {
    INFO(c.scheme);
    const Mesh input = io::read_mesh(example(c.mesh));
    const Mesh expected = subdivision::subdivide(input, c.id, 2);
    for (const char* ext : {".obj", ".ply"}) {
      const auto out = scratch() / (std::string("sub_") + c.scheme + ext);
      const Run r = cifs_cli("subdivide " + example(c.mesh) + " --scheme " + c.scheme + " --levels 2 -o " +
                             out.string());
      REQUIRE(r.status == 0);
      CHECK(r.out == "wrote " + out.string() + ": " + std::to_string(expected.vertices.rows()) +
                         " vertices, " + std::to_string(face_count(expected)) + " faces (" + c.scheme +
                         ", 2 levels)\n");
      const Mesh back = io::read_mesh(out);
      CHECK(back.vertices == expected.vertices);  // %.17g text and binary PLY both read back exactly
      CHECK(back.face_vertices == expected.face_vertices);
      CHECK(back.face_offsets == expected.face_offsets);
    }
  }
  const Run r = cifs_cli("subdivide " + example("cube.obj") + " --scheme catmull-clark");
  REQUIRE(r.status == 0);
  CHECK(r.out == io::encode(subdivision::catmull_clark(io::read_mesh(example("cube.obj")), 1), "obj"));
  // The corner rule keeps the open grid's four corners in place.
  const auto corners = scratch() / "corners.obj";
  REQUIRE(cifs_cli("subdivide " + example("open_grid.obj") + " --scheme catmull-clark --boundary corner -o " +
                   corners.string())
              .status == 0);
  const Mesh grid = io::read_mesh(example("open_grid.obj")), kept = io::read_mesh(corners);
  CHECK(kept.vertices.row(0) == grid.vertices.row(0));
}

TEST_CASE("cifs subdivide reads STL and OFF and writes STL, OFF and VTK PolyData", "[cli][mesh]") {
  const Mesh cube = io::read_mesh(example("cube_triangles.obj"));
  const auto stl = scratch() / "cube_in.stl", off = scratch() / "cube_in.off";
  io::write(stl, cube);
  io::write(off, cube);
  const Mesh expected = subdivision::subdivide(cube, subdivision::MeshScheme::loop, 1);
  for (const auto& in : {stl, off}) {
    INFO(in.string());
    // Welded back from the triangle soup (vertices numbered as they come), the STL cube subdivides as
    // the OBJ one: the same points (its coordinates are floats: 0 and 1), the same number of faces.
    const auto out = scratch() / "cube_out.off";
    REQUIRE(cifs_cli("subdivide " + in.string() + " --scheme loop -o " + out.string()).status == 0);
    const Mesh back = io::read_mesh(out);
    const auto sorted_rows = [](const Points& p) {
      std::vector<std::array<double, 3>> rows(static_cast<std::size_t>(p.rows()));
      for (Eigen::Index i = 0; i < p.rows(); ++i)
        rows[static_cast<std::size_t>(i)] = {p(i, 0), p(i, 1), p(i, 2)};
      std::sort(rows.begin(), rows.end());
      return rows;
    };
    CHECK(sorted_rows(back.vertices) == sorted_rows(expected.vertices));
    CHECK(face_count(back) == face_count(expected));
  }
  const auto vtp = scratch() / "cube_out.vtp";
  const Run r = cifs_cli("subdivide " + off.string() + " --scheme loop -o " + vtp.string());
  REQUIRE(r.status == 0);
  CHECK(read_file(vtp).find("<VTKFile type=\"PolyData\"") != std::string::npos);
  // What a format cannot hold is said, not dropped in silence.
  const auto tagged = scratch() / "tagged_out.stl";
  const Run t = cifs_cli("subdivide " + file("tagged_for_stl.obj", tagged_grid_obj()) +
                         " --scheme catmull-clark -o " + tagged.string());
  REQUIRE(t.status == 0);
  CHECK_THAT(t.err,
             Catch::Contains("tagged_out.stl: the .stl format does not hold") && Catch::Contains("creases"));
}

TEST_CASE("cifs subdivide and analyze --rules blz: Biermann-Levin-Zorin's rules", "[cli][mesh][blz]") {
  // subdivide writes the library's refinement under the rule set, which differs from the default
  // next to the extraordinary boundary vertex.
  Mesh fan = io::read_mesh(example("boundary_fan.obj"));
  const Mesh standard = subdivision::subdivide(fan, subdivision::MeshScheme::catmull_clark, 2);
  fan.tags.rules = RuleSet::blz;
  const Mesh expected = subdivision::subdivide(fan, subdivision::MeshScheme::catmull_clark, 2);
  CHECK((expected.vertices - standard.vertices).cwiseAbs().maxCoeff() > 1e-3);
  const auto out = scratch() / "blz_fan.obj";
  const Run r = cifs_cli("subdivide " + example("boundary_fan.obj") +
                         " --scheme catmull-clark --levels 2 --rules blz -o " + out.string());
  REQUIRE(r.status == 0);
  CHECK(io::read_mesh(out).vertices == expected.vertices);
  // The output carries the rule set (t rules): refining it once more is refining the fan 3 levels.
  const auto again = scratch() / "blz_fan_again.obj";
  REQUIRE(cifs_cli("subdivide " + out.string() + " --scheme catmull-clark -o " + again.string()).status == 0);
  const Mesh three = subdivision::subdivide(fan, subdivision::MeshScheme::catmull_clark, 3);
  CHECK((io::read_mesh(again).vertices - three.vertices).cwiseAbs().maxCoeff() < 1e-12);
  // analyze: the fan's centre, not C1 by default, C1 under blz.
  const auto centre = [&](const std::string& rules) {
    const Run a =
        cifs_cli("analyze " + example("boundary_fan.obj") + " --scheme catmull-clark --format json" + rules);
    REQUIRE(a.status == 0);
    return json::parse(a.out)["vertices"][0];
  };
  CHECK(centre("")["c1"] == "no");
  CHECK(centre(" --rules blz")["c1"] == "yes");
  const auto none = scratch() / "blz_none.obj";
  std::filesystem::remove(none);
  check_error(cifs_cli("subdivide " + example("boundary_fan.obj") +
                       " --scheme catmull-clark --rules zorin -o " + none.string()),
              "--rules zorin: unknown rule set 'zorin' (opensubdiv, blz)");
  check_error(cifs_cli("subdivide " + example("boundary_fan.obj") + " --scheme doo-sabin --rules blz -o " +
                       none.string()),
              "doo-sabin: the rule set 'blz' is built for catmull-clark and loop only");
  check_error(cifs_cli("subdivide " + example("boundary_fan.obj") +
                       " --scheme catmull-clark --factored --rules blz -o " + none.string()),
              "not the rule set 'blz'");
  CHECK_FALSE(std::filesystem::exists(none));
  check_error(cifs_cli("analyze " + example("boundary_fan.obj") + " --scheme catmull-clark --rules zorin"),
              "--rules zorin");
}

TEST_CASE("cifs info on a polygon mesh: counts, valences, boundary, Euler characteristic, genus",
          "[cli][mesh]") {
  const json torus = json::parse(cifs_cli("info " + example("torus.obj")).out);
  CHECK(torus["type"] == "mesh");
  CHECK(torus["vertices"] == 96);
  CHECK(torus["faces"] == 96);
  CHECK(torus["edges"] == 192);  // every quad has 4 edges, each shared by 2 quads
  CHECK(torus["euler_characteristic"] == 0);
  CHECK(torus["genus"] == 1);
  CHECK(torus["closed"] == true);
  CHECK(torus["valences"] == json{{"4", 96}});
  const json grid = json::parse(cifs_cli("info " + example("open_grid.obj")).out);
  CHECK(grid["boundary_loops"] == 1);
  CHECK(grid["closed"] == false);
  CHECK(!grid.contains("genus"));
  CHECK(grid["euler_characteristic"] == 1);                         // a disc
  CHECK(grid["valences"] == json{{"2", 4}, {"3", 16}, {"4", 15}});  // corners, sides (2·(6+4)−8), inside 5·3
  const json cube = json::parse(cifs_cli("info " + example("cube_triangles.obj")).out);
  CHECK(cube["valences"] == json{{"3", 4}, {"6", 4}});
  CHECK(cube["faces_by_corners"] == json{{"3", 12}});
}

TEST_CASE("cifs subdivide: bad meshes and requests exit 2 with one line and write nothing", "[cli][mesh]") {
  const auto out = scratch() / "never.obj";
  std::filesystem::remove(out);
  const std::string o = " -o " + out.string();
  check_error(cifs_cli("subdivide " + example("cube.obj") + " --scheme loop" + o),
              "loop: face 0 has 4 corners; this scheme runs on triangles");
  check_error(cifs_cli("subdivide " + example("cube.obj") + " --scheme kobbelt" + o),
              "unknown mesh scheme 'kobbelt'");
  check_error(cifs_cli("subdivide " + example("cube.obj") + " --scheme catmull-clark --levels 14" + o),
              "catmull-clark: 14 levels of 6 faces reach");
  check_error(cifs_cli("subdivide " + example("cube.obj") + " --scheme catmull-clark --boundary sharp" + o),
              "--boundary sharp: unknown boundary rule 'sharp' (none, edge, corner)");
  check_error(cifs_cli("subdivide " + example("cube.obj") + " --scheme catmull-clark -o x.gltf"),
              "-o x.gltf: expected a .obj, .ply, .stl, .off or .vtp file name");
  check_error(cifs_cli("subdivide " +
                       file("fan.obj",
                            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\n"
                            "f 1 2 3\nf 2 4 3\nf 2 3 5\n") +
                       " --scheme butterfly" + o),
              "edge");
  check_error(cifs_cli("subdivide " + file("nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n") +
                       " --scheme loop" + o),
              "nan.obj");
  check_error(cifs_cli("subdivide " + example("open_grid.obj") + " --scheme butterfly" + o),
              "butterfly: face 0 has 4 corners");
  check_error(cifs_cli("subdivide " +
                       file("uv_quad.obj",
                            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                            "f 1/1 2/2 3/3 4/4\n") +
                       " --scheme doo-sabin" + o),
              "doo-sabin: the mesh has a face-varying channel 'uv'; this scheme does not split faces");
  CHECK(!std::filesystem::exists(out));
}

TEST_CASE("cifs subdivide --factored writes the same mesh as the masks", "[cli][mesh]") {
  for (const char* scheme : {"catmull-clark", "loop"}) {
    const std::string mesh = example(std::string(scheme) == "loop" ? "icosahedron.obj" : "cube.obj");
    const auto out = scratch() / (std::string("factored_") + scheme + ".obj");
    const Run r = cifs_cli("subdivide " + mesh + " --scheme " + scheme +
                           " --levels 2 --factored --quiet -o " + out.string());
    REQUIRE(r.status == 0);
    CHECK(r.out.find("factored, 2 levels") != std::string::npos);
    const Mesh a = subdivision::subdivide(io::read_mesh(mesh), subdivision::named_mesh_scheme(scheme), 2);
    const Mesh b = io::read_mesh(out);
    CHECK(a.face_vertices == b.face_vertices);
    CHECK((a.vertices - b.vertices).cwiseAbs().maxCoeff() <= 1e-14 * a.vertices.cwiseAbs().maxCoeff());
  }
  check_error(cifs_cli("subdivide " + example("cube_triangles.obj") + " --scheme butterfly --factored"),
              "the factored form exists for catmull-clark and loop");
}

TEST_CASE("cifs subdivide keeps tags and UVs: refining its output once equals refining one level more",
          "[cli][mesh][tags]") {
  const std::string in = file("tagged.obj", tagged_grid_obj());
  const auto once = scratch() / "once.obj", twice = scratch() / "twice.obj", two = scratch() / "two.obj";
  REQUIRE(cifs_cli("subdivide " + in + " --scheme catmull-clark -o " + once.string()).status == 0);
  REQUIRE(cifs_cli("subdivide " + once.string() + " --scheme catmull-clark -o " + twice.string()).status ==
          0);
  REQUIRE(cifs_cli("subdivide " + in + " --scheme catmull-clark --levels 2 -o " + two.string()).status == 0);
  const Mesh a = io::read_mesh(twice), b = io::read_mesh(two);
  const Mesh direct = subdivision::subdivide(io::read_mesh(in), subdivision::MeshScheme::catmull_clark, 2);
  REQUIRE(b.vertices == direct.vertices);  // the file is the library's result, bit for bit
  REQUIRE(a.vertices.rows() == b.vertices.rows());
  CHECK((a.vertices - b.vertices).cwiseAbs().maxCoeff() <= 1e-12 * b.vertices.cwiseAbs().maxCoeff());
  CHECK(a.face_vertices == b.face_vertices);
  CHECK(a.face_offsets == b.face_offsets);
  CHECK(a.tags.holes == b.tags.holes);
  CHECK(!b.tags.holes.empty());
  REQUIRE(a.tags.creases.size() == b.tags.creases.size());
  CHECK(!b.tags.creases.empty());
  for (std::size_t i = 0; i < a.tags.creases.size(); ++i) {
    CHECK(a.tags.creases[i].a == b.tags.creases[i].a);
    CHECK(a.tags.creases[i].b == b.tags.creases[i].b);
    CHECK(a.tags.creases[i].sharpness == b.tags.creases[i].sharpness);
  }
  REQUIRE(a.face_varying.size() == 1);
  REQUIRE(b.face_varying.size() == 1);
  CHECK(a.face_varying[0].indices == b.face_varying[0].indices);
  CHECK((a.face_varying[0].values - b.face_varying[0].values).cwiseAbs().maxCoeff() <= 1e-12);
  // A smooth face-varying rule from the command line: the library's UVs, and the rule written back.
  const auto smooth_uv = scratch() / "smooth_uv.obj";
  REQUIRE(cifs_cli("subdivide " + in +
                   " --scheme catmull-clark --levels 2 --fvar-interpolation corners-only -o " +
                   smooth_uv.string())
              .status == 0);
  Mesh tagged = io::read_mesh(in);
  tagged.tags.face_varying = FaceVaryingRule::corners_only;
  const Mesh expected = subdivision::subdivide(tagged, subdivision::MeshScheme::catmull_clark, 2),
             got = io::read_mesh(smooth_uv);
  CHECK(got.tags.face_varying == FaceVaryingRule::corners_only);
  REQUIRE(got.face_varying.size() == 1);
  CHECK(got.face_varying[0].indices == expected.face_varying[0].indices);
  CHECK((got.face_varying[0].values - expected.face_varying[0].values).cwiseAbs().maxCoeff() <= 1e-15);
  CHECK((got.face_varying[0].values - b.face_varying[0].values).cwiseAbs().maxCoeff() > 1e-3);  // not linear
}

TEST_CASE("cifs subdivide -o .ply says what PLY leaves out of a tagged mesh", "[cli][mesh][tags]") {
  const std::string in = file("tagged_for_ply.obj", tagged_grid_obj());
  const auto ply = scratch() / "tagged.ply", plain = scratch() / "plain.ply";
  const auto r = cifs_cli("subdivide " + in + " --scheme catmull-clark -o " + ply.string());
  REQUIRE(r.status == 0);
  CHECK_THAT(r.err, Catch::StartsWith("cifs: warning: ") &&
                        Catch::Contains("tagged.ply: the .ply format does not hold") &&
                        Catch::Contains("hole faces") && Catch::Contains("creases") &&
                        Catch::Contains("face-varying channel 'uv'"));
  const auto quiet =
      cifs_cli("subdivide " + example("cube.obj") + " --scheme catmull-clark -o " + plain.string());
  REQUIRE(quiet.status == 0);
  CHECK(quiet.err.empty());  // nothing to leave out: no warning
}

TEST_CASE("cifs subdivide and info: unknown OBJ tags warn, --strict refuses", "[cli][mesh][tags]") {
  const std::string in = file("edits.obj", tagged_grid_obj() + "t vertexedit 1/1/1 0 0.5 add\n");
  const auto out = scratch() / "edits_out.obj";
  std::filesystem::remove(out);
  const Run warned = cifs_cli("subdivide " + in + " --scheme catmull-clark --quiet -o " + out.string());
  CHECK(warned.status == 0);
  CHECK_THAT(warned.err, Catch::Contains("cifs: warning: " + in + ": line ") &&
                             Catch::Contains(": t vertexedit: unknown tag, ignored\n"));
  CHECK(std::filesystem::exists(out));
  std::filesystem::remove(out);
  check_error(cifs_cli("subdivide " + in + " --scheme catmull-clark --strict -o " + out.string()),
              "t vertexedit: unknown tag (cifs reads crease");
  CHECK(!std::filesystem::exists(out));
  check_error(cifs_cli("info " + in + " --strict"), "t vertexedit: unknown tag");
  check_error(cifs_cli("subdivide " + file("bad_crease.obj", tagged_grid_obj() + "t crease 2/1/0 0 6 1\n") +
                       " --scheme catmull-clark -o " + out.string()),
              "bad_crease.obj: line ");
  CHECK(!std::filesystem::exists(out));
}

TEST_CASE("cifs info on a tagged mesh: creases, corners, holes, options, UV channels; non-manifold meshes",
          "[cli][mesh][tags]") {
  const json info = json::parse(cifs_cli("info " + file("tagged_info.obj", tagged_grid_obj())).out);
  CHECK(info["creases"] == json{{"count", 3}, {"sharpness", {1.5, 10}}, {"infinite", 1}});
  CHECK(info["corners"] == json{{"count", 1}, {"sharpness", {3, 3}}, {"infinite", 0}});
  CHECK(info["holes"] == 1);
  CHECK(info["boundary"] == "edge");
  CHECK(info["crease_method"] == "uniform");
  CHECK(info["fvar_interpolation"] == "all");
  CHECK(info["rules"] == "opensubdiv");
  CHECK(info["concave"] == json::array());
  const json blz = json::parse(
      cifs_cli("info " + file("blz_info.obj", tagged_grid_obj() + "t rules 0/0/1 blz\nt corner 1/1/0 0 10\n"
                                                                  "t concave 1/0/0 0\n"))
          .out);
  CHECK(blz["rules"] == "blz");
  CHECK(blz["concave"] == json::array({0}));
  CHECK(info["face_varying"] == json::array({{{"name", "uv"}, {"values", 26}, {"dimension", 2}}}));
  CHECK(info["manifold"] == true);
  CHECK(info["edges"] == 40);
  // Three triangles on one edge: the facts, and why adjacency is not built, instead of an error.
  const Run fan = cifs_cli("info " + file("fan3.obj",
                                          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                          "f 1 2 3\nf 2 1 4\nf 1 2 5\n"));
  REQUIRE(fan.status == 0);
  const json nonmanifold = json::parse(fan.out);
  CHECK(nonmanifold["manifold"] == false);
  CHECK(nonmanifold["faces"] == 3);
  CHECK_THAT(nonmanifold["topology_refused"].get<std::string>(), Catch::Contains("fan3.obj"));
}

TEST_CASE("cifs automaton MESH --scheme S: the mesh's surface automaton, JSON, DOT and SVG",
          "[cli][mesh][automaton]") {
  // A closed regular torus: one state, the four quarters of a bicubic patch looping on it.
  const Run torus = cifs_cli("automaton " + example("torus.obj") + " --scheme catmull-clark --format dot");
  REQUIRE(torus.status == 0);
  for (const char* quarter : {"GH", "GB", "DH", "DB"})
    CHECK(torus.out.find(std::string("0->0 [label=\"") + quarter + "\"]") != std::string::npos);
  // The icosahedron after a step under Loop: a regular state and the valence-5 corner's, one initial
  // entry per face (80), as the library builds it.
  const Run ico = cifs_cli("automaton " + example("icosahedron.obj") + " --scheme loop --levels 1");
  REQUIRE(ico.status == 0);
  const json a = json::parse(ico.out);
  CHECK(a["initial"].size() == 80);
  const Mesh refined = subdivision::loop(io::read_mesh(example("icosahedron.obj")), 1);
  CHECK(ico.out ==
        io::encode(subdivision::surface_automaton(refined, subdivision::MeshScheme::loop).automaton, "json"));
  const Run svg =
      cifs_cli("automaton " + example("icosahedron.obj") + " --scheme loop --levels 1 --format svg");
  CHECK(svg.out.starts_with("<svg"));
  // An open triangle mesh: Loop's boundary patches (the feature automaton), as the library builds it.
  const Run open = cifs_cli("automaton " + example("open_grid_triangles.obj") + " --scheme loop");
  INFO(open.err);
  REQUIRE(open.status == 0);
  CHECK(open.out ==
        io::encode(subdivision::surface_automaton(io::read_mesh(example("open_grid_triangles.obj")),
                                                  subdivision::MeshScheme::loop)
                       .automaton,
                   "json"));
  // Refusals, one line each.
  check_error(cifs_cli("automaton " + example("cube.obj")), "is a mesh: give --scheme catmull-clark or loop");
  check_error(cifs_cli("automaton " + example("cube.obj") + " --scheme catmull-clark"),
              "4 extraordinary corners (--levels 1 refines them apart)");
  check_error(cifs_cli("automaton " + example("cube.obj") + " --scheme catmull-clark --minimize"),
              "--minimize applies to shapes");
  check_error(cifs_cli("automaton " + example("cube.obj") + " --scheme catmull-clark --levels 9"),
              "--levels 9: expected 0 to 8");
  check_error(cifs_cli("automaton " CIFS_EXAMPLES_DIR "/shapes/hills.json --scheme loop"),
              "--scheme applies to meshes");
}

TEST_CASE("cifs automaton MESH --scheme catmull-clark on boundaries, creases, corners and holes; -o OUT",
          "[cli][mesh][automaton]") {
  // The creased box (infinite, semi-sharp creases, a corner, a hole): the library's automaton, to stdout
  // and to a file of each format; the format is the extension's.
  const std::string box = example("creased_box.obj");
  const Run json_run = cifs_cli("automaton " + box + " --scheme catmull-clark");
  REQUIRE(json_run.status == 0);
  const Mesh mesh = io::read_mesh(box);
  const subdivision::SurfaceAutomaton library =
      subdivision::surface_automaton(mesh, subdivision::MeshScheme::catmull_clark);
  CHECK(json_run.out == io::encode(library.automaton, "json"));
  CHECK(json::parse(json_run.out)["initial"].size() == library.nets.size());
  for (const char* format : {"json", "dot", "svg"}) {
    const auto out = scratch() / (std::string("box_automaton.") + format);
    const Run written = cifs_cli("automaton " + box + " --scheme catmull-clark -o " + out.string());
    REQUIRE(written.status == 0);
    CHECK(written.out.starts_with("wrote " + out.string() + ": "));
    CHECK(slurp(out) == io::encode(library.automaton, format));
  }
  // An open grid: its corners' boundary states, "B1".
  const Run grid = cifs_cli("automaton " + example("open_grid.obj") + " --scheme catmull-clark --format dot");
  REQUIRE(grid.status == 0);
  CHECK(grid.out.find("B1") != std::string::npos);
  // Refusals: one line, nothing written.
  const auto refused = scratch() / "refused_automaton.json";
  check_error(cifs_cli("automaton " + box + " --scheme catmull-clark -o " + (scratch() / "a.png").string()),
              "a.png: an automaton is written as");
  check_error(cifs_cli("automaton " + box + " --scheme catmull-clark --format dot -o " + refused.string()),
              "--format dot: -o " + refused.string() + " names json");
  check_error(cifs_cli("automaton " + example("cube.obj") + " --scheme catmull-clark -o " + refused.string()),
              "(--levels 1 refines them apart)");
  CHECK(!std::filesystem::exists(refused));
}

TEST_CASE("cifs analyze MESH --scheme S: which points are not smooth", "[cli][mesh_analysis]") {
  const std::string grid = std::string(CIFS_EXAMPLES_DIR) + "/meshes/open_grid.obj";
  const Run table = cifs_cli("analyze " + grid + " --scheme catmull-clark");
  REQUIRE(table.status == 0);
  // The grid's four corners: one face each, the smooth boundary rule — the curve's ¼ and the face's
  // form a Jordan block: undecided, said so; with the corner rule they are C1 corners.
  CHECK_THAT(table.out,
             Catch::Contains("catmull-clark: 35 vertices, 31 regular, 4 irregular: 0 C1, 0 not C1, "
                             "4 undecided (1 local analysis)"));
  const json corners = json::parse(cifs_cli("analyze " + grid +
                                            " --scheme catmull-clark --boundary corner "
                                            "--format json")
                                       .out);
  CHECK(corners["c1"] == 4);
  CHECK(corners["vertices"][0]["class"] == "corner");
  // --png: the surface with the four corners marked, written whole; nothing written when refused.
  const auto png = scratch() / "analyze.png";
  std::filesystem::remove(png);
  REQUIRE(cifs_cli("analyze " + grid + " --scheme catmull-clark --png " + png.string()).status == 0);
  std::ifstream in(png, std::ios::binary);
  std::string signature(8, '\0');
  in.read(signature.data(), 8);
  CHECK(signature == "\x89PNG\r\n\x1a\n");
  const auto refused = scratch() / "refused.png";
  check_error(cifs_cli("analyze " + grid + " --scheme loop --png " + refused.string()),
              "loop runs on triangles");
  CHECK_FALSE(std::filesystem::exists(refused));
  check_error(cifs_cli("analyze " + grid + " --scheme catmull-clark --format svg"), "--format 'svg'");

  // Butterfly: the 8-triangle boundary fan's centre is not C1 (its boundary rule: C1 at 2 and 3 faces).
  const std::string fan = std::string(CIFS_EXAMPLES_DIR) + "/meshes/boundary_fan_triangles.obj";
  const Run butterfly = cifs_cli("analyze " + fan + " --scheme butterfly");
  REQUIRE(butterfly.status == 0);
  CHECK_THAT(butterfly.out,
             Catch::Contains("butterfly: 10 vertices, 0 regular, 10 irregular: 7 C1, 1 not C1, "
                             "2 undecided (3 local analyses)"));
  // Doo–Sabin: points are face centres — the grid's corner faces, one interior corner each: C1 corners
  // of the surface, 90 degrees —, marked on the PNG at their centroids.
  const json dual = json::parse(cifs_cli("analyze " + grid + " --scheme doo-sabin --format json").out);
  REQUIRE(dual["vertices"].size() == 4);
  CHECK(dual["vertices"][0]["vertex"] == -1);
  CHECK(dual["vertices"][0]["face"] == 0);
  CHECK(dual["vertices"][0]["class"] == "boundary");
  CHECK(dual["c1"] == 4);
  std::filesystem::remove(png);
  REQUIRE(cifs_cli("analyze " + grid + " --scheme doo-sabin --png " + png.string()).status == 0);
  CHECK(std::filesystem::file_size(png) > 1000);
}
