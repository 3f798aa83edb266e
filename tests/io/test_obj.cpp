// SPDX-License-Identifier: MIT
#include "cifs/io/obj.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "io/mesh_samples.hpp"

using namespace cifs;
using namespace cifs::io;
using Catch::Matchers::Contains;

namespace {

Mesh obj_mixed_polygons() {
  Mesh m;
  m.vertices.resize(9, 3);
  for (int k = 0; k < 9; ++k) m.vertices.row(k) << std::cos(k * 0.7), std::sin(k * 0.7), 0.01 * k * k;
  add_face(m, {0, 1, 2});
  add_face(m, {0, 2, 3, 4});
  add_face(m, {4, 5, 6, 7, 8});
  add_face(m, {8, 7, 6, 5, 3, 1});
  add_face(m, {1, 8, 0});
  return m;
}

void require_same_obj_mesh(const Mesh& a, const Mesh& b) {
  REQUIRE(a.vertices.rows() == b.vertices.rows());
  REQUIRE(a.vertices.cols() == b.vertices.cols());
  CHECK(std::memcmp(a.vertices.data(), b.vertices.data(), sizeof(double) * a.vertices.size()) == 0);
  CHECK(a.face_offsets == b.face_offsets);
  CHECK(a.face_vertices == b.face_vertices);
  REQUIRE(a.normals.rows() == b.normals.rows());
  // memcmp takes no null pointer, even for 0 bytes (UBSan): empty normals compare equal as they are.
  CHECK((a.normals.size() == 0 ||
         std::memcmp(a.normals.data(), b.normals.data(), sizeof(double) * a.normals.size()) == 0));
}

std::string obj_error_of(const std::string& text) {
  try {
    parse_mesh_obj(text, "m.obj");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("Segment OBJ parses back", "[io][obj]") {
  Segments s;
  s.vertices.resize(4, 2);
  s.vertices << 0, 0, 1, 0.1, 2, -0.3, 0.5, 7;
  s.segments = {{0, 1}, {1, 2}, {1, 3}};  // a branch at vertex 1 (tree-like support)
  s.states = {1, 2, 3};
  // OBJ: v and l lines, 1-based.
  std::istringstream obj(segments_obj(s));
  std::string line;
  std::vector<std::vector<double>> v;
  std::vector<std::pair<int, int>> l;
  while (std::getline(obj, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v") {
      double x, y, z;
      words >> x >> y >> z;
      v.push_back({x, y, z});
    } else if (key == "l") {
      int a, b;
      words >> a >> b;
      l.emplace_back(a, b);
    }
  }
  CHECK(v == std::vector<std::vector<double>>{{0, 0, 0}, {1, 0.1, 0}, {2, -0.3, 0}, {0.5, 7, 0}});
  CHECK(l == std::vector<std::pair<int, int>>{{1, 2}, {2, 3}, {2, 4}});
}

TEST_CASE("Mesh OBJ parses back, with normals as f v//n", "[io][obj]") {
  const Mesh m = io_test::sample_mesh(true, false);
  std::istringstream obj(mesh_obj(m));
  std::string line;
  int v = 0, vn = 0;
  std::vector<std::string> faces;
  while (std::getline(obj, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v" || key == "vn") {
      double x[3];
      words >> x[0] >> x[1] >> x[2];
      const Points& P = key == "v" ? m.vertices : m.normals;
      const int i = key == "v" ? v++ : vn++;
      for (int k = 0; k < 3; ++k) CHECK(x[k] == P(i, k));  // 17 digits: exact round trip
    } else if (key == "f") {
      faces.push_back(line);
    }
  }
  CHECK(v == 5);
  CHECK(vn == 5);
  CHECK(faces == std::vector<std::string>{"f 1//1 2//2 3//3", "f 3//3 4//4 5//5", "f 1//1 2//2 4//4 5//5"});
}

TEST_CASE("Polyline OBJ: v lines and one l element, closed back to the first point", "[io][obj]") {
  Points P(3, 2);
  P << 0, 0, 1, 0.5, 2, 0;
  CHECK(polyline_obj(P) == "# cifs polyline, 3 points\nv 0 0 0\nv 1 0.5 0\nv 2 0 0\nl 1 2 3\n");
  CHECK_THAT(polyline_obj(P, true), Catch::EndsWith("l 1 2 3 1\n"));
  CHECK_THROWS_AS(polyline_obj(Points::Zero(2, 4)), InvalidInput);
}

TEST_CASE("OBJ meshes read back bit for bit (cube, open grid, mixed polygons, normals)", "[io][obj]") {
  const std::vector<std::pair<const char*, Mesh>> meshes = {
      {"sample", io_test::sample_mesh(false, false)},
      {"sample with normals", io_test::sample_mesh(true, false)},
      {"cube", io_test::cube()},
      {"open grid", io_test::open_grid(6)},
      {"mixed polygons", obj_mixed_polygons()}};
  for (const auto& [what, m] : meshes) {
    INFO(what);
    const Mesh back = parse_mesh_obj(mesh_obj(m), "m.obj");
    require_same_obj_mesh(back, m);
    CHECK(mesh_obj(back) == mesh_obj(m));
  }
}

TEST_CASE("OBJ reader: other writers' files (references, negative indices, ignored statements)",
          "[io][obj]") {
  // Written by hand: vertex colours, texture and normal references of every form, negative indices,
  // a continued line, comments, groups, materials, lines and free-form statements.
  const std::string text =
      "# a square and a triangle\r\n"
      "mtllib x.mtl\n"
      "o thing\n"
      "v 0 0 0 1 0 0\n"
      "v 1 0 0\n"
      "v 1 1 0\n"
      "v 0 1 0.5  # a comment\n"
      "vt 0 0\nvt 1 0\nvt 1 1\n"
      "vn 0 0 1\n"
      "g front\nusemtl red\ns 1\n"
      "f 1/1/1 2/2/1 \\\n  3/3/1 4/1/1\n"
      "l 1 2\n"
      "f -4/1 -2/-1 -1/-2\n"
      "cstype bspline\n";
  const Mesh m = parse_mesh_obj(text, "hand.obj");
  Points expected(4, 3);
  expected << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.5;
  CHECK(m.vertices == expected);
  CHECK(m.face_offsets == std::vector<int>{0, 4, 7});
  CHECK(m.face_vertices == std::vector<int>{0, 1, 2, 3, 0, 2, 3});
  CHECK(m.normals.size() == 0);         // per-corner normals (all corners share normal 1) are not per vertex
  REQUIRE(m.face_varying.size() == 1);  // the vt rows and the corners' /vt: one channel "uv"
  CHECK(m.face_varying[0].name == "uv");
  CHECK(m.face_varying[0].values == (Points(3, 2) << 0, 0, 1, 0, 1, 1).finished());
  CHECK(m.face_varying[0].indices == std::vector<int>{0, 1, 2, 0, 0, 2, 1});
  // Normals that are per vertex (f a//a, one vn per v) are kept.
  const Mesh n =
      parse_mesh_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\nvn 1 0 0\nf 1//1 2//2 3//3\n", "n");
  REQUIRE(n.normals.rows() == 3);
  CHECK(n.normals.row(1) == Eigen::RowVector3d(0, 0, -1));
}

TEST_CASE("OBJ reader: bad input is a one-line error naming the file and the line", "[io][obj]") {
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  CHECK(obj_error_of(v + "f 1 2 3\n") == "(no error)");
  CHECK(obj_error_of(v + "f 1 2 4\n") ==
        "m.obj: line 4: vertex index 4 is out of range: 3 vertices are defined before this line");
  CHECK(obj_error_of(v + "f 1 2 -4\n") ==
        "m.obj: line 4: vertex index -4 is out of range: 3 vertices are defined before this line");
  CHECK(obj_error_of(v + "f 0 1 2\n") ==
        "m.obj: line 4: vertex index 0 is invalid (indices start at 1, negative ones count back)");
  CHECK(obj_error_of(v + "f 1 2\n") == "m.obj: line 4: f: 2 vertices, a face needs at least 3");
  CHECK(obj_error_of("v 0 nan 0\n" + v + "f 1 2 3\n") == "m.obj: line 1: v: 'nan' is not finite");
  CHECK(obj_error_of(v + "f 1 2 x\n") == "m.obj: line 4: f: expected an integer, got 'x'");
  CHECK(obj_error_of(v + "f 1 2 3/1/1/1\n") ==
        "m.obj: line 4: f: expected v, v/vt, v/vt/vn or v//vn, got '3/1/1/1'");
  CHECK(obj_error_of(v + "f 1 2 3//1\n") ==
        "m.obj: line 4: normal index 1 is out of range: 0 normals are defined before this line");
  CHECK(obj_error_of(v + "f 1 2 3/\n") == "m.obj: line 4: f: expected v, v/vt, v/vt/vn or v//vn, got '3/'");
  CHECK(obj_error_of(v) == "m.obj: no faces (f lines) in the file");
  CHECK(obj_error_of("v 1 2\n") == "m.obj: line 1: v: expected x y z [w], got 2 numbers");
}

TEST_CASE("OBJ writers refuse bad meshes and segments", "[io][obj]") {
  Mesh m = io_test::sample_mesh(false, false);
  m.face_vertices[8] = -1;
  CHECK_THROWS_AS(mesh_obj(m), InvalidInput);
  m = io_test::sample_mesh(false, false);
  m.vertices(3, 1) = std::nan("");
  CHECK_THROWS_WITH(mesh_obj(m), Contains("vertices[3] is not finite"));
  Segments s;
  s.vertices = Points::Zero(2, 4);
  s.segments = {{0, 1}};
  CHECK_THROWS_WITH(segments_obj(s), Contains("4 columns"));
}

namespace {

/// A 3 × 3 grid of quads with creases, corners, a hole, UVs (a seam: two values at vertices 1 and 5)
/// and every option away from its default: the tags and channel mesh_obj must write back.
Mesh tagged_grid() {
  Mesh m = io_test::open_grid(3);
  m.tags.creases = {{.a = 5, .b = 6, .sharpness = 2.5},
                    {.a = 1, .b = 5, .sharpness = 1.0 / 3},
                    {.a = 10, .b = 9, .sharpness = kInfiniteSharpness}};
  m.tags.corners = {{.vertex = 0, .sharpness = 0.1}, {.vertex = 15, .sharpness = 10}};
  m.tags.holes = {4, 7};
  m.tags.boundary = BoundaryRule::none;
  m.tags.crease_method = CreaseMethod::chaikin;
  m.tags.triangles = TriangleRule::smooth;
  m.tags.face_varying = FaceVaryingRule::corners_plus2;
  FaceVaryingChannel uv;
  uv.values.resize(17, 2);
  for (int k = 0; k < 17; ++k) uv.values.row(k) << std::sqrt(k + 0.5), 1.0 / (k + 3);
  uv.indices = m.face_vertices;
  uv.indices[1] = 16;  // face 0's corner at vertex 1 takes its own value
  m.face_varying.push_back(uv);
  return m;
}

void require_same_tags(const Mesh& a, const Mesh& b) {
  REQUIRE(a.tags.creases.size() == b.tags.creases.size());
  for (std::size_t i = 0; i < a.tags.creases.size(); ++i) {
    CHECK(a.tags.creases[i].a == b.tags.creases[i].a);
    CHECK(a.tags.creases[i].b == b.tags.creases[i].b);
    CHECK(std::memcmp(&a.tags.creases[i].sharpness, &b.tags.creases[i].sharpness, sizeof(double)) == 0);
  }
  REQUIRE(a.tags.corners.size() == b.tags.corners.size());
  for (std::size_t i = 0; i < a.tags.corners.size(); ++i) {
    CHECK(a.tags.corners[i].vertex == b.tags.corners[i].vertex);
    CHECK(std::memcmp(&a.tags.corners[i].sharpness, &b.tags.corners[i].sharpness, sizeof(double)) == 0);
  }
  CHECK(a.tags.holes == b.tags.holes);
  CHECK(a.tags.boundary == b.tags.boundary);
  CHECK(a.tags.crease_method == b.tags.crease_method);
  CHECK(a.tags.triangles == b.tags.triangles);
  CHECK(a.tags.face_varying == b.tags.face_varying);
  REQUIRE(a.face_varying.size() == b.face_varying.size());
  for (std::size_t i = 0; i < a.face_varying.size(); ++i) {
    CHECK(a.face_varying[i].name == b.face_varying[i].name);
    REQUIRE(a.face_varying[i].values.rows() == b.face_varying[i].values.rows());
    REQUIRE(a.face_varying[i].values.cols() == b.face_varying[i].values.cols());
    CHECK(std::memcmp(a.face_varying[i].values.data(), b.face_varying[i].values.data(),
                      sizeof(double) * static_cast<std::size_t>(a.face_varying[i].values.size())) == 0);
    CHECK(a.face_varying[i].indices == b.face_varying[i].indices);
  }
}

/// The grid of io_test::open_grid(1): one quad, vertices 1 to 4 in OBJ.
const std::string kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

}  // namespace

TEST_CASE("OBJ tags and UVs read back bit for bit", "[io][obj][tags]") {
  Mesh m = tagged_grid();
  const Mesh back = parse_mesh_obj(mesh_obj(m), "m.obj");
  require_same_obj_mesh(back, m);
  require_same_tags(back, m);
  CHECK(mesh_obj(back) == mesh_obj(m));
  // With normals too (f v/t/n), and with every option at its default (no option lines).
  m.normals = vertex_normals(m);
  m.tags.boundary = BoundaryRule::edge_only;
  m.tags.crease_method = CreaseMethod::uniform;
  m.tags.triangles = TriangleRule::catmark;
  m.tags.face_varying = FaceVaryingRule::all;
  const std::string text = mesh_obj(m);
  CHECK(text.find("t interpolateboundary") == std::string::npos);
  CHECK(text.find("f 1/1/1 2/17/2 6/6/6 5/5/5\n") != std::string::npos);
  const Mesh again = parse_mesh_obj(text, "m.obj");
  require_same_obj_mesh(again, m);
  require_same_tags(again, m);
}

TEST_CASE("OBJ tags as OpenSubdiv's shapes write them", "[io][obj][tags]") {
  // Pairs with one sharpness or one each, corners, holes, every option, RenderMan's "normal" method.
  const std::string grid = mesh_obj(io_test::open_grid(3));
  const Mesh m = parse_mesh_obj(grid +
                                    "t crease 2/1/0 5 6 3\n"
                                    "t crease 4/2/0 1 5 9 10 0.5 10\n"
                                    "t crease 2/1/0 6 5 1\n"  // the same edge again: replaces 3
                                    "t corner 1/1/0 0 2\n"
                                    "t corner 2/1/0 3 12 4\n"
                                    "t hole 2/0/0 4 8\n"
                                    "t interpolateboundary 1/0/0 1\n"
                                    "t facevaryinginterpolateboundary 1/0/0 2\n"
                                    "t facevaryingpropagatecorners 1/0/0 1\n"
                                    "t creasemethod 0/0/1 normal\n"
                                    "t smoothtriangles 0/0/1 smooth\n",
                                "m.obj");
  REQUIRE(m.tags.creases.size() == 3);
  CHECK((m.tags.creases[0].a == 6 && m.tags.creases[0].b == 5 && m.tags.creases[0].sharpness == 1));
  CHECK((m.tags.creases[1].a == 1 && m.tags.creases[1].b == 5 && m.tags.creases[1].sharpness == 0.5));
  CHECK((m.tags.creases[2].a == 9 && m.tags.creases[2].b == 10 && m.tags.creases[2].sharpness == 10));
  REQUIRE(m.tags.corners.size() == 3);
  CHECK((m.tags.corners[0].vertex == 0 && m.tags.corners[0].sharpness == 2));
  CHECK((m.tags.corners[2].vertex == 12 && m.tags.corners[2].sharpness == 4));
  CHECK(m.tags.holes == std::vector<int>{4, 8});
  CHECK(m.tags.boundary == BoundaryRule::edge_and_corner);
  CHECK(m.tags.face_varying == FaceVaryingRule::corners_plus2);  // corners+1 with propagate corners
  CHECK(m.tags.crease_method == CreaseMethod::uniform);
  CHECK(m.tags.triangles == TriangleRule::smooth);
  const Mesh c = parse_mesh_obj(grid + "t creasemethod 0/0/1 chaikin\nt interpolateboundary 1/0/0 0\n", "m");
  CHECK(c.tags.crease_method == CreaseMethod::chaikin);
  CHECK(c.tags.boundary == BoundaryRule::none);
  // cifs's own tags: Biermann–Levin–Zorin's rules and their concave corners, written back as read.
  const Mesh blz = parse_mesh_obj(kQuad + "t rules 0/0/1 blz\nt concave 2/0/0 0 2\n", "m");
  CHECK(blz.tags.rules == RuleSet::blz);
  CHECK(blz.tags.concave == std::vector<int>{0, 2});
  CHECK_THAT(mesh_obj(blz), Catch::Contains("t rules 0/0/1 blz\nt concave 2/0/0 0 2\n"));
  CHECK_THAT(mesh_obj(parse_mesh_obj(kQuad, "m")), !Catch::Contains("t rules"));  // the default: not written
}

TEST_CASE("OBJ unknown tags: a warning naming the tag and line, an error when strict", "[io][obj][tags]") {
  const std::string text = kQuad + "t vertexedit 4/2/1 0 1 2 3 0.5 1 value\nt faceedit 1/0/1 0 x\n";
  std::vector<std::string> warnings;
  const Mesh m = parse_mesh_obj(
      text, "m.obj", {.strict = false, .warn = [&](const std::string& w) { warnings.push_back(w); }});
  CHECK(face_count(m) == 1);
  CHECK(warnings == std::vector<std::string>{"m.obj: line 6: t vertexedit: unknown tag, ignored",
                                             "m.obj: line 7: t faceedit: unknown tag, ignored"});
  CHECK_THROWS_WITH(parse_mesh_obj(text, "m.obj", {.strict = true, .warn = {}}),
                    Catch::StartsWith("m.obj: line 6: t vertexedit: unknown tag (cifs reads crease, corner"));
  CHECK_THROWS_AS(parse_mesh_obj(text, "m.obj", {.strict = true, .warn = {}}), InvalidInput);
}

TEST_CASE("OBJ tags and UVs: bad input is a one-line error naming the file and the line", "[io][obj][tags]") {
  CHECK(obj_error_of(kQuad + "t crease 2/1/0 0 1 2\n") == "(no error)");
  CHECK(obj_error_of(kQuad + "t crease 2/1/0 0 1\n") ==
        "m.obj: line 6: t crease: 2/1/0 announces 3 arguments, got 2");
  CHECK(obj_error_of(kQuad + "t crease 3/1/0 0 1 2 1\n") ==
        "m.obj: line 6: t crease: expected vertex pairs and their sharpness (2/1/0, 4/2/0, 4/1/0, ...), got "
        "3/1/0");
  CHECK(obj_error_of(kQuad + "t crease 4/3/0 0 1 1 2 1 1 1\n") ==
        "m.obj: line 6: t crease: 3 sharpness values for 2 elements; give one for all or one each");
  CHECK(obj_error_of(kQuad + "t crease 2/1/0 0 1 -1\n") ==
        "m.obj: line 6: t crease: sharpness -1 is negative");
  CHECK(obj_error_of(kQuad + "t crease 2/1/0 0 1 nan\n") == "m.obj: line 6: t crease: 'nan' is not finite");
  CHECK(obj_error_of(kQuad + "t crease 2/1/0 0 2 1\n") ==
        "m.obj: line 6: t crease: no face has the edge 0 2");
  CHECK(obj_error_of(kQuad + "t crease 2/1/0 0 4 1\n") ==
        "m.obj: line 6: t crease: vertex 4 is out of range (4 vertices, numbered from 0)");
  CHECK(obj_error_of(kQuad + "t corner 1/1/0 7 1\n") ==
        "m.obj: line 6: t corner: vertex 7 is out of range (4 vertices, numbered from 0)");
  CHECK(obj_error_of(kQuad + "t corner 1/0/0 1\n") ==
        "m.obj: line 6: t corner: expected N/1/0 arguments, got 1/0/0");
  CHECK(obj_error_of(kQuad + "t hole 1/0/0 3\n") ==
        "m.obj: line 6: t hole: face 3 is out of range (1 faces, numbered from 0)");
  CHECK(obj_error_of(kQuad + "t hole 1/0/0 0\n") ==
        "m.obj: every face is a hole; nothing is left to refine or draw");
  CHECK(obj_error_of(kQuad + "t interpolateboundary 1/0/0 3\n") ==
        "m.obj: line 6: t interpolateboundary: 3 is not one of 0 to 2");
  CHECK(obj_error_of(kQuad + "t facevaryinginterpolateboundary 1/0/0 6\n") ==
        "m.obj: line 6: t facevaryinginterpolateboundary: 6 is not one of 0 to 5");
  CHECK(obj_error_of(kQuad + "t creasemethod 0/0/1 sharp\n") ==
        "m.obj: line 6: t creasemethod: expected normal or chaikin, got 'sharp'");
  CHECK(obj_error_of(kQuad + "t rules 0/0/1 zorin\n") ==
        "m.obj: line 6: t rules: unknown rule set 'zorin' (opensubdiv, blz)");
  CHECK_THAT(obj_error_of(kQuad + "t concave 1/0/0 4\n"),
             Catch::StartsWith("m.obj: line 6: t concave: vertex 4"));
  CHECK(obj_error_of(kQuad + "t smoothtriangles 1/0/0 1\n") ==
        "m.obj: line 6: t smoothtriangles: expected 0/0/1 arguments, got 1/0/0");
  CHECK(obj_error_of(kQuad + "t crease x/1/0 0 1 1\n") ==
        "m.obj: line 6: t crease: expected an integer, got 'x'");
  CHECK(obj_error_of(kQuad + "t crease\n") ==
        "m.obj: line 6: t: expected a name and ints/floats/strings counts");
  // UVs: every corner has one or none does; indices in range; rows of one size.
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n";
  CHECK(obj_error_of(v + "f 1/1 2/2 3/2\n") == "(no error)");
  CHECK(obj_error_of(v + "f 1/1 2/2 3\n") ==
        "m.obj: line 6: f: corner '3' has no texture index (v/vt) but earlier corners have one");
  CHECK(obj_error_of(v + "f 1 2 3\nf 1/1 2/2 3/1\n") ==
        "m.obj: line 7: f: corner '1/1' has a texture index (v/vt) but earlier corners have none");
  CHECK(obj_error_of(v + "f 1/1 2/2 3/3\n") ==
        "m.obj: line 6: texture index 3 is out of range: 2 texture coordinates (vt) are defined before this "
        "line");
  CHECK(obj_error_of(v + "vt 1 1 1\nf 1/1 2/2 3/3\n") ==
        "m.obj: line 6: vt: 3 numbers, the earlier vt lines have 2");
}

TEST_CASE("OBJ writer refuses what OBJ cannot hold", "[io][obj][tags]") {
  Mesh m = tagged_grid();
  m.face_varying.push_back(m.face_varying[0]);
  CHECK_THROWS_WITH(mesh_obj(m), "the mesh to write as OBJ has 2 face-varying channels; OBJ holds one (vt)");
}
