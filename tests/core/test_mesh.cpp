// SPDX-License-Identifier: MIT
#include "cifs/mesh.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "cifs/errors.hpp"

using namespace cifs;

TEST_CASE("Vertex normals: area-weighted, oriented by the faces", "[core][mesh]") {
  // A unit cube with outward (counter-clockwise from outside) quads: corner normals (±1,±1,±1)/√3.
  Mesh cube;
  cube.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) cube.vertices.row(i) << (i & 1), ((i >> 1) & 1), ((i >> 2) & 1);
  for (const auto& q : std::vector<std::vector<int>>{
           {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
    add_face(cube, q);
  const Points N = vertex_normals(cube);
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k)
      CHECK(N(i, k) == Approx((cube.vertices(i, k) - 0.5) * 2 / std::sqrt(3.0)).epsilon(1e-14));
  // A triangle fan in the plane z = 2 (counter-clockwise seen from +z): every normal is +z.
  Mesh fan;
  fan.vertices.resize(4, 3);
  fan.vertices << 0, 0, 2, 3, 0, 2, 3, 1, 2, -1, 5, 2;
  add_face(fan, {0, 1, 2});
  add_face(fan, {0, 2, 3});
  const Points F = vertex_normals(fan);
  for (int i = 0; i < 4; ++i) CHECK(F.row(i) == Eigen::RowVector3d(0, 0, 1));
}

TEST_CASE("Segments: polylines, appending, checks", "[core][mesh]") {
  Points P(3, 2);
  P << 0, 0, 1, 0, 1, 1;
  const Segments open = polyline_segments(P, false, 4);
  CHECK(open.segments == std::vector<std::array<int, 2>>{{0, 1}, {1, 2}});
  CHECK(open.states == std::vector<std::uint32_t>{4, 4});
  const Segments closed = polyline_segments(P, true);
  CHECK(closed.segments.back() == std::array<int, 2>{2, 0});
  Segments all;
  append(all, open);
  Segments bare;
  bare.vertices = P;
  bare.segments = {{2, 0}};
  append(all, bare);  // states kept where one side has them: the other's become 0
  CHECK(all.vertices.rows() == 6);
  CHECK(all.segments == std::vector<std::array<int, 2>>{{0, 1}, {1, 2}, {5, 3}});
  CHECK(all.states == std::vector<std::uint32_t>{4, 4, 0});
  CHECK_THROWS_WITH(append(all, polyline_segments(Points::Zero(2, 3))),
                    "segments with 2 and with 3 coordinates cannot be drawn together");
  bare.segments = {{0, 3}};
  CHECK_THROWS_WITH(check_segments(bare, "w"), "w: segments[0][1] = 3 is out of range (3 vertices)");
}

TEST_CASE("Meshes appended: indices shifted, states and normals kept when both have them", "[core][mesh]") {
  Mesh a;
  a.vertices.resize(3, 3);
  a.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  add_face(a, {0, 1, 2});
  a.states = {7};
  Mesh b;
  b.vertices.resize(4, 3);
  b.vertices << 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
  add_face(b, {0, 1, 2, 3});
  add_face(b, {0, 2, 3});
  b.states = {8, 9};
  Mesh m;
  append(m, a);
  append(m, b);
  CHECK(m.vertices.rows() == 7);
  CHECK(m.vertices.bottomRows(4) == b.vertices);
  CHECK(m.face_offsets == std::vector<int>{0, 3, 7, 10});
  CHECK(m.face_vertices == std::vector<int>{0, 1, 2, 3, 4, 5, 6, 3, 5, 6});
  CHECK(m.states == std::vector<std::uint32_t>{7, 8, 9});
  CHECK(m.normals.size() == 0);
  check_mesh(m, "appended");
  // Normals only when both have them; states dropped when one mesh has none.
  a.normals = vertex_normals(a);
  b.normals = vertex_normals(b);
  b.states.clear();
  Mesh n = a;
  append(n, b);
  CHECK(n.normals.rows() == 7);
  CHECK(n.normals.bottomRows(4) == b.normals);
  CHECK(n.states.empty());
  check_mesh(n, "appended");
}
