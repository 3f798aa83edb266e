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
      "f 1/1/1 2/2/1 \\\n  3/3/1 4//1\n"
      "l 1 2\n"
      "f -4/1 -2 -1\n"
      "cstype bspline\n";
  const Mesh m = parse_mesh_obj(text, "hand.obj");
  Points expected(4, 3);
  expected << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.5;
  CHECK(m.vertices == expected);
  CHECK(m.face_offsets == std::vector<int>{0, 4, 7});
  CHECK(m.face_vertices == std::vector<int>{0, 1, 2, 3, 0, 2, 3});
  CHECK(m.normals.size() == 0);  // per-corner normals (all corners share normal 1) are not per vertex
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
