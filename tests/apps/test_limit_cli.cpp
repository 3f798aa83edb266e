// SPDX-License-Identifier: MIT
// cifs limit on polygon meshes, run as a user runs it: limit points and normals against closed forms,
// the limit surface at points (--at), streamed, and what is refused in one line.
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

/// A wavy 5 × 4 grid of quads with an infinitely sharp crease across it (boundary corners kept), as an
/// OBJ file in the scratch folder.
std::string creased_grid() {
  const auto path = scratch() / "creased_grid.obj";
  if (!std::filesystem::exists(path)) {
    Mesh grid = cifs_test::quad_grid(5, 4);
    for (int i = 6; i < 11; ++i) grid.tags.creases.push_back({i, i + 1, kInfiniteSharpness});
    grid.tags.boundary = BoundaryRule::edge_and_corner;
    io::write(path, grid);
  }
  return path.string();
}

}  // namespace

TEST_CASE("cifs limit: the cube's corners go to Halstead's limit point, normals along the diagonal",
          "[cli][mesh][limit]") {
  // Catmull–Clark limit of a valence-n vertex: (n²v + 4Σ edge neighbours + Σ diagonal corners) /
  // (n(n + 5)) (Halstead, Kass and DeRose 1993). For the unit cube's corner at 0, n = 3: the
  // neighbours sum to (1, 1, 1), the diagonals to (2, 2, 2): (6, 6, 6)/24 = ¼(1, 1, 1). By symmetry
  // the normal there points along −(1, 1, 1).
  const auto out = scratch() / "limit_cube.ply";
  const Run r = cifs_cli("limit " + example("cube.obj") + " --scheme catmull-clark --levels 0 --normals -o " +
                         out.string());
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("8 limit points with normals, 6 faces"));
  const Mesh limit = io::read_mesh(out);
  REQUIRE(limit.normals.rows() == 8);
  for (Eigen::Index v = 0; v < 8; ++v) {
    const Eigen::RowVector3d corner = io::read_mesh(example("cube.obj")).vertices.row(v);
    const Eigen::RowVector3d expected = Eigen::RowVector3d::Constant(0.25) + 0.5 * corner;  // ¼ inwards
    CHECK((limit.vertices.row(v) - expected).norm() < 1e-15);
    const Eigen::RowVector3d outward = (corner - Eigen::RowVector3d::Constant(0.5)).normalized();
    CHECK((limit.normals.row(v) - outward).norm() < 1e-15);
  }
  // On stdout as OBJ, at level 2: as many vertices as the subdivided mesh.
  const Run obj = cifs_cli("limit " + example("icosahedron.obj") + " --scheme loop --levels 2");
  REQUIRE(obj.status == 0);
  const Mesh refined = subdivision::loop(io::read_mesh(example("icosahedron.obj")), 2);
  std::size_t vertices = 0;
  for (std::size_t at = 0; (at = obj.out.find("\nv ", at)) != std::string::npos; ++at) ++vertices;
  CHECK(vertices + (obj.out.rfind("v ", 0) == 0 ? 1 : 0) ==
        static_cast<std::size_t>(refined.vertices.rows()));
}

TEST_CASE("cifs limit: what is not built exits 2 with one line", "[cli][mesh][limit]") {
  const auto out = scratch() / "never_limit.ply";
  std::filesystem::remove(out);
  const std::string o = " -o " + out.string();
  // Normals per sector are per face corner, which PLY cannot hold; where a sector's spectrum proves no
  // plane (the creased box's crease turns at a corner of the box: a face alone between two crease edges
  // of one smooth curve) they are refused, naming the vertex.
  check_error(cifs_cli("limit " + creased_grid() + " --scheme catmull-clark --normals" + o),
              "the mesh to write as PLY has normals per face corner");
  check_error(cifs_cli("limit " + example("creased_box.obj") + " --scheme catmull-clark --normals" + o),
              "catmull-clark: vertex 0 (valence 3): its sector of face 0 has no tangent plane that its "
              "spectrum proves");
  check_error(cifs_cli("limit " + example("cube.obj") + " --scheme doo-sabin" + o),
              "doo-sabin: limit points belong to faces");
  CHECK(!std::filesystem::exists(out));
}

TEST_CASE("cifs limit --scheme sqrt3 --normals on an open mesh: boundary vertices take normals too",
          "[cli][mesh][limit]") {
  // √3's boundary normals come from the two-step boundary matrix (docs/subdivision-surfaces.md; against
  // deep refinement in test_mesh_limit_classes.cpp). A planar grid's limit surface is its plane: every
  // normal is +z (its faces counter-clockwise), boundary vertices of 1, 2 and 3 faces included, at an odd
  // level (through the trisecting step). The wavy example grid, at an even level: the library's normals,
  // written and read back.
  const auto planar = scratch() / "planar_triangle_grid.obj";
  Mesh grid = cifs_test::quad_grid(4, 3, true);
  grid.vertices.col(2).setZero();
  io::write(planar, grid);
  const auto flat = scratch() / "planar_sqrt3_limit.ply";
  REQUIRE(cifs_cli("limit " + planar.string() + " --scheme sqrt3 --normals --levels 1 -o " + flat.string())
              .status == 0);
  const Mesh limit = io::read_mesh(flat);
  REQUIRE(limit.normals.rows() == limit.vertices.rows());
  for (Eigen::Index v = 0; v < limit.normals.rows(); ++v)
    CHECK((limit.normals.row(v) - Eigen::RowVector3d(0, 0, 1)).norm() < 1e-15);
  const auto out = scratch() / "open_grid_sqrt3_limit.ply";
  const Run run = cifs_cli("limit " + example("open_grid_triangles.obj") +
                           " --scheme sqrt3 --normals --levels 2 -o " + out.string());
  REQUIRE(run.status == 0);
  const Mesh ours = subdivision::limit_mesh(io::read_mesh(example("open_grid_triangles.obj")),
                                            subdivision::MeshScheme::sqrt3, 2, {.normals = true});
  const Mesh back = io::read_mesh(out);
  REQUIRE(back.normals.rows() == ours.normals.rows());
  CHECK((back.normals - ours.normals).cwiseAbs().maxCoeff() < 1e-15);
}

TEST_CASE("cifs limit --scheme butterfly --normals: boundary vertices not proved C1 refused in one line",
          "[cli][mesh][limit]") {
  // Butterfly interpolates: the limit points are the refined vertices; the normals are the library's
  // (against deep refinement in tests/subdivision/test_butterfly_limit.cpp), written and read back.
  const auto out = scratch() / "torus_butterfly_limit.ply";
  const Run run = cifs_cli("limit " + example("torus_triangles.obj") +
                           " --scheme butterfly --normals --levels 1 -o " + out.string());
  REQUIRE(run.status == 0);
  const Mesh torus = io::read_mesh(example("torus_triangles.obj"));
  const Mesh back = io::read_mesh(out);
  CHECK(back.vertices == subdivision::butterfly(torus, 1).vertices);
  const Mesh ours = subdivision::limit_mesh(torus, subdivision::MeshScheme::butterfly, 1, {.normals = true});
  REQUIRE(back.normals.rows() == back.vertices.rows());
  CHECK((back.normals - ours.normals).cwiseAbs().maxCoeff() < 1e-15);
  check_error(
      cifs_cli("limit " + example("open_grid_triangles.obj") + " --scheme butterfly --normals -o " +
               out.string()),
      "butterfly: vertex 6 (valence 2) is on the boundary with 1 face (lambda1 = 0.5, lambda2 = 0.25), where "
      "the local analysis finds undecided: lambda2 = 0.25 is defective (a Jordan block)");
}

TEST_CASE("cifs limit --normals on creases and corners: a normal per sector, OBJ f v//n",
          "[cli][mesh][limit]") {
  // A grid with a sharp crease across: its OBJ has more vn than v, and some vertex takes two normals (one
  // per side of the crease); read back, the faces are the same. The normals themselves:
  // test_mesh_limit_classes.cpp and test_limit_surface_features.cpp.
  const auto out = scratch() / "grid_normals.obj";
  const Run run =
      cifs_cli("limit " + creased_grid() + " --scheme catmull-clark --normals -o " + out.string());
  REQUIRE(run.status == 0);
  CHECK_THAT(run.out, Catch::Contains("normals (per sector at creases and corners)"));
  const std::string text = slurp(out);
  std::size_t v = 0, vn = 0;
  for (std::size_t at = 0; (at = text.find('\n', at)) != std::string::npos; ++at) {
    v += text.compare(at + 1, 2, "v ") == 0 ? 1 : 0;
    vn += text.compare(at + 1, 3, "vn ") == 0 ? 1 : 0;
  }
  CHECK(vn > v);
  std::map<int, std::set<int>> normals_of;  // vertex → the normals its corners take
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (!line.starts_with("f ")) continue;
    std::istringstream corners(line.substr(2));
    for (std::string c; corners >> c;) {
      const auto slash = c.find("//");
      REQUIRE(slash != std::string::npos);
      normals_of[std::stoi(c.substr(0, slash))].insert(std::stoi(c.substr(slash + 2)));
    }
  }
  CHECK(
      std::any_of(normals_of.begin(), normals_of.end(), [](const auto& x) { return x.second.size() == 2; }));
  const Mesh back = io::read_mesh(out);
  CHECK(back.face_vertices.size() == 4 * io::read_mesh(creased_grid()).face_vertices.size());
}

TEST_CASE("cifs limit --at: the limit surface at points, as JSON", "[cli][mesh][limit]") {
  // The cube under Catmull–Clark: at a face's corners Halstead's limit point ¼(1, 1, 1) + ½ corner with
  // the outward diagonal as the normal and du × dv along it (valence-3 vertices: du, dv the directions of
  // the tangent plane); at the centre of face 2 (y = 0), by symmetry, x = z = ½ and the normal −y. The same
  // points from a file (comments, blank lines, commas or blanks) give the same JSON.
  const Mesh cube = io::read_mesh(example("cube.obj"));
  const Run r =
      cifs_cli("limit " + example("cube.obj") +
               " --scheme catmull-clark --at '0,0,0;0,1,0;3,1,1;5,0,1;2,0.5,0.5' --partials --normals");
  REQUIRE(r.status == 0);
  const json j = json::parse(r.out);
  CHECK(j["scheme"] == "catmull-clark");
  REQUIRE(j["points"].size() == 5);
  const auto vec = [](const json& a) {
    return Eigen::Vector3d(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
  };
  for (int i = 0; i < 4; ++i) {
    const json& p = j["points"][static_cast<std::size_t>(i)];
    const subdivision::FacePoint q{p["face"].get<int>(), p["u"].get<double>(), p["v"].get<double>()};
    const auto corners = face(cube, static_cast<std::size_t>(q.face));
    const int corner = corners[static_cast<std::size_t>(q.u == 0 ? (q.v == 0 ? 0 : 3) : (q.v == 0 ? 1 : 2))];
    const Eigen::Vector3d at = cube.vertices.row(corner).transpose();
    CHECK((vec(p["position"]) - (Eigen::Vector3d::Constant(0.25) + 0.5 * at)).norm() < 1e-15);
    CHECK((vec(p["normal"]) - (at - Eigen::Vector3d::Constant(0.5)).normalized()).norm() < 1e-14);
    CHECK(vec(p["du"]).cross(vec(p["dv"])).normalized().dot(vec(p["normal"])) > 1 - 1e-14);
  }
  const json& centre = j["points"][4];  // face 2 is y = 0: its centre's normal is −y
  CHECK((vec(centre["normal"]) - Eigen::Vector3d(0, -1, 0)).norm() < 1e-14);
  CHECK(std::abs(vec(centre["position"]).x() - 0.5) < 1e-15);
  CHECK(std::abs(vec(centre["position"]).z() - 0.5) < 1e-15);
  const std::string points =
      file("limit_points.txt", "# face u v\n0 0 0\n0, 1, 0\n\n3 1 1;5,0,1\n2 0.5 0.5 # the centre\n");
  const Run from_file = cifs_cli("limit " + example("cube.obj") + " --scheme catmull-clark --at " + points +
                                 " --partials --normals");
  REQUIRE(from_file.status == 0);
  CHECK(from_file.out == r.out);
  // Positions only by default; -o writes the JSON atomically and prints one line.
  const Run plain = cifs_cli("limit " + example("cube.obj") + " --scheme catmull-clark --at '2,0.5,0.5'");
  REQUIRE(plain.status == 0);
  CHECK(!json::parse(plain.out)["points"][0].contains("du"));
  CHECK(json::parse(plain.out)["points"][0]["position"] == centre["position"]);
  const auto out = scratch() / "limit_at.json";
  const Run written = cifs_cli("limit " + example("cube.obj") +
                               " --scheme catmull-clark --at '2,0.5,0.5' -o " + out.string());
  REQUIRE(written.status == 0);
  CHECK_THAT(written.out, Catch::Contains("wrote ") && Catch::Contains("at 1 points"));
  CHECK(json::parse(slurp(out)) == json::parse(plain.out));
}

TEST_CASE("cifs limit --at: a million points are streamed, in memory well below their text",
          "[cli][mesh][limit]") {
  // The JSON was once built as a tree (1.75 GB of memory and 12.6 s for a million points with partials and
  // normals, 334 MB of text): under a 1 GiB address space that ran out of memory. Under ASan (no cap: its
  // shadow memory reserves terabytes) fewer points.
  const int count = cifs_test::kSanitized ? 100000 : 1000000;
  std::string text;
  for (int i = 0; i < count; ++i)
    text += std::to_string(i % 6) + "," + std::to_string((i % 997) / 996.0) + "," +
            std::to_string((i % 991) / 990.0) + "\n";
  const std::string points = file("million_points.txt", text);
  const auto out = scratch() / "million.json";
  const Run r =
      cifs_cli("limit " + example("cube.obj") + " --scheme catmull-clark --partials --normals --at " +
                   points + " -o " + out.string(),
               "", address_space_cap(1));
  INFO(r.err);
  REQUIRE(r.status == 0);
  std::ifstream in(out);
  std::string line, last;
  int lines = 0;
  for (; std::getline(in, line); ++lines) {
    if (lines == 1) {
      const json first = json::parse(line.substr(0, line.size() - 1));  // without the comma
      CHECK(first["face"] == 0);
      CHECK(first["normal"].size() == 3);
    }
    last = line;
  }
  CHECK(lines == count + 2);
  CHECK(last == "]}");
}

TEST_CASE("cifs limit --at: bad points exit 2 with one line, nothing written", "[cli][mesh][limit]") {
  const auto out = scratch() / "never_at.json";
  std::filesystem::remove(out);
  const std::string cube =
      "limit " + example("cube.obj") + " --scheme catmull-clark -o " + out.string() + " --at ";
  check_error(cifs_cli(cube + "'7,0.5,0.5'"), "point 0 (face 7): no such face; the mesh has 6");
  check_error(cifs_cli(cube + "'0,0.5,0.5;0,1.5,0.5'"),
              "point 1 (face 0): (u, v) = (1.5, 0.5) is outside [0, 1]²");
  check_error(cifs_cli(cube + "'0,-0.1,0.5'"), "is outside [0, 1]²");
  check_error(cifs_cli(cube + "'0,x,0.5'"), "--at: point 0 '0,x,0.5': 'x' is not a number");
  check_error(cifs_cli(cube + "'0.5,0,0'"), "the face '0.5' is not a whole number");
  check_error(cifs_cli(cube + "'0,0'"), "expected face,u,v");
  check_error(cifs_cli(cube + "';'"), "--at: no points");
  check_error(cifs_cli("limit " + example("creased_box.obj") + " --scheme catmull-clark -o " + out.string() +
                       " --at '13,0.5,0.5'"),
              "point 0 (face 13): the face is a hole");
  check_error(cifs_cli("limit " + example("creased_box.obj") + " --scheme catmull-clark -o " + out.string() +
                       " --at '0,0,0' --partials"),
              "point 0 (face 0) at (0, 0): the vertex there has no tangent plane its spectrum proves");
  check_error(cifs_cli("limit " + example("cube.obj") + " --scheme catmull-clark --at '0,0,0' -o " +
                       (scratch() / "never_at.obj").string()),
              "expected a .json file name (--at writes JSON)");
  check_error(
      cifs_cli("limit " + example("cube.obj") + " --scheme butterfly --at '0,0,0' -o " + out.string()),
      "limit surface: butterfly is not built");
  check_error(cifs_cli("limit " + example("cube.obj") + " --scheme catmull-clark --levels 2 --at '0,0,0'"),
              "--levels excludes --at");
  CHECK(!std::filesystem::exists(out));
}
