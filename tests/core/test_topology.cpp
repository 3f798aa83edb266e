// SPDX-License-Identifier: MIT
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/mesh.hpp"
#include "cifs/topology.hpp"
#include "support/same_topology.hpp"
#include "support/sanitized.hpp"

using namespace cifs;

namespace {

Mesh faces_mesh(int vertices, const std::vector<std::vector<int>>& faces) {
  Mesh m;
  m.vertices = Points::Zero(vertices, 3);
  for (const auto& f : faces) add_face(m, f);
  return m;
}

Mesh topology_cube() {
  return faces_mesh(8, {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}});
}

/// n by m quads on a torus (both directions wrap).
Mesh topology_torus(int n, int m) {
  std::vector<std::vector<int>> faces;
  const auto id = [&](int i, int j) { return ((i + n) % n) * m + (j + m) % m; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return faces_mesh(n * m, faces);
}

/// n by m quads on a square (open: one boundary loop).
Mesh grid(int n, int m) {
  std::vector<std::vector<int>> faces;
  const auto id = [&](int i, int j) { return i * (m + 1) + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return faces_mesh((n + 1) * (m + 1), faces);
}

/// Checks every documented invariant of the rotation order around each vertex.
void check_rotation(const MeshTopology& t) {
  for (int v = 0; v < t.vertex_count; ++v) {
    const auto E = vertex_edges(t, static_cast<std::size_t>(v));
    const auto Fs = vertex_faces(t, static_cast<std::size_t>(v));
    const bool boundary = t.boundary_vertex[static_cast<std::size_t>(v)] != 0;
    if (Fs.empty()) {
      CHECK(E.empty());
      continue;
    }
    CHECK(E.size() == Fs.size() + (boundary ? 1 : 0));
    for (std::size_t k = 0; k < Fs.size(); ++k) {
      const auto f = static_cast<std::size_t>(Fs[k]);
      const auto corners = face(t, f);
      const auto edges = face_edges(t, f);
      const auto c = static_cast<std::size_t>(std::find(corners.begin(), corners.end(), v) - corners.begin());
      REQUIRE(c < corners.size());
      // Edge k is the face's outgoing edge at v, edge k + 1 its incoming one.
      CHECK(edges[c] == E[k]);
      CHECK(edges[(c + corners.size() - 1) % corners.size()] == E[(k + 1) % E.size()]);
    }
    if (boundary) {
      CHECK(is_boundary_edge(t, static_cast<std::size_t>(E.front())));
      CHECK(is_boundary_edge(t, static_cast<std::size_t>(E.back())));
    }
    for (const int e : E)
      CHECK((t.edges[static_cast<std::size_t>(e)][0] == v || t.edges[static_cast<std::size_t>(e)][1] == v));
  }
  // Every edge: its first face runs along it forwards, the other one backwards.
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    for (int side = 0; side < 2; ++side) {
      const int f = t.edge_faces[e][static_cast<std::size_t>(side)];
      if (f < 0) continue;
      const auto corners = face(t, static_cast<std::size_t>(f));
      const auto edges = face_edges(t, static_cast<std::size_t>(f));
      const auto it = std::find(edges.begin(), edges.end(), static_cast<int>(e));
      REQUIRE(it != edges.end());
      const auto i = static_cast<std::size_t>(it - edges.begin());
      const int a = corners[i], b = corners[(i + 1) % corners.size()];
      if (side == 0)
        CHECK((a == t.edges[e][0] && b == t.edges[e][1]));
      else
        CHECK((a == t.edges[e][1] && b == t.edges[e][0]));
    }
  }
}

/// The topology as the header documents it, by brute-force search over the corners (no twins, no
/// walk): edges in order of first appearance; around each vertex, the boundary edge leaving it first
/// (else its first corner's outgoing edge), then face k's incoming edge leads to face k + 1.
MeshTopology reference_topology(const Mesh& m) {
  MeshTopology t;
  t.vertex_count = static_cast<int>(m.vertices.rows());
  t.face_offsets = m.face_offsets;
  t.face_vertices = m.face_vertices;
  const std::size_t H = t.face_vertices.size();
  std::vector<int> face_of(H), next(H), prev(H);
  for (std::size_t f = 0; f + 1 < t.face_offsets.size(); ++f) {
    const int b = t.face_offsets[f], e = t.face_offsets[f + 1];
    for (int h = b; h < e; ++h) {
      face_of[static_cast<std::size_t>(h)] = static_cast<int>(f);
      next[static_cast<std::size_t>(h)] = h + 1 < e ? h + 1 : b;
      prev[static_cast<std::size_t>(h)] = h > b ? h - 1 : e - 1;
    }
  }
  const auto from = [&](int h) { return t.face_vertices[static_cast<std::size_t>(h)]; };
  const auto to = [&](int h) { return from(next[static_cast<std::size_t>(h)]); };
  const auto twin = [&](int h) {
    for (int g = 0; g < static_cast<int>(H); ++g)
      if (from(g) == to(h) && to(g) == from(h)) return g;
    return -1;
  };
  t.face_edges.assign(H, -1);
  for (int h = 0; h < static_cast<int>(H); ++h) {
    if (t.face_edges[static_cast<std::size_t>(h)] >= 0) continue;
    const int g = twin(h);
    t.face_edges[static_cast<std::size_t>(h)] = static_cast<int>(t.edges.size());
    if (g >= 0) t.face_edges[static_cast<std::size_t>(g)] = static_cast<int>(t.edges.size());
    t.edges.push_back({from(h), to(h)});
    t.edge_faces.push_back(
        {face_of[static_cast<std::size_t>(h)], g >= 0 ? face_of[static_cast<std::size_t>(g)] : -1});
  }
  t.boundary_vertex.assign(static_cast<std::size_t>(t.vertex_count), 0);
  for (int v = 0; v < t.vertex_count; ++v) {
    int start = -1;
    for (int h = 0; h < static_cast<int>(H); ++h)
      if (from(h) == v && (start < 0 || (twin(h) < 0 && twin(start) >= 0))) start = h;
    for (int h = start, count = 0; h >= 0 && count < 1000; ++count) {
      t.vertex_edge_list.push_back(t.face_edges[static_cast<std::size_t>(h)]);
      t.vertex_face_list.push_back(face_of[static_cast<std::size_t>(h)]);
      const int entering = prev[static_cast<std::size_t>(h)];
      h = twin(entering);
      if (h < 0) {
        t.vertex_edge_list.push_back(t.face_edges[static_cast<std::size_t>(entering)]);
        t.boundary_vertex[static_cast<std::size_t>(v)] = 1;
      }
      if (h == start) break;
    }
    t.vertex_offsets_edges.push_back(static_cast<int>(t.vertex_edge_list.size()));
    t.vertex_offsets_faces.push_back(static_cast<int>(t.vertex_face_list.size()));
  }
  return t;
}

/// Each quad split in two triangles.
Mesh triangulated(const Mesh& quads) {
  Mesh m;
  m.vertices = quads.vertices;
  for (std::size_t f = 0; f + 1 < quads.face_offsets.size(); ++f) {
    const int* c = quads.face_vertices.data() + quads.face_offsets[f];
    add_face(m, {c[0], c[1], c[2]});
    add_face(m, {c[0], c[2], c[3]});
  }
  return m;
}

}  // namespace

TEST_CASE("topology of all-quad, all-triangle and mixed meshes = the documented one, searched by brute force",
          "[core][topology]") {
  // build_topology computes a corner's face on all-quad and all-triangle meshes and looks it up on
  // others: each route against the definition.
  Mesh holed = grid(4, 3);  // a hole inside: a second boundary loop
  holed.face_offsets = {0};
  holed.face_vertices.clear();
  const Mesh g = grid(4, 3);
  for (std::size_t f = 0; f + 1 < g.face_offsets.size(); ++f)
    if (f != 4)
      add_face(holed, std::vector<int>(g.face_vertices.begin() + g.face_offsets[f],
                                       g.face_vertices.begin() + g.face_offsets[f + 1]));
  const std::vector<std::pair<const char*, Mesh>> meshes{
      {"cube", topology_cube()},
      {"torus", topology_torus(3, 5)},
      {"grid", grid(3, 2)},
      {"grid with a hole", holed},
      {"triangulated torus", triangulated(topology_torus(4, 3))},
      {"triangulated grid with a hole", triangulated(holed)},
      {"tetrahedron", faces_mesh(4, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}})},
      {"mixed", faces_mesh(7, {{0, 1, 2, 3, 4}, {1, 0, 5}, {2, 1, 5, 6}, {3, 2, 6}})}};
  for (const auto& [name, mesh] : meshes) {
    INFO(name);
    cifs_test::check_same_topology(build_topology(mesh), reference_topology(mesh));
  }
}

TEST_CASE("topology of closed meshes: counts, Euler characteristic, rotations", "[core][topology]") {
  SECTION("cube") {
    const MeshTopology t = build_topology(topology_cube());
    CHECK(t.edges.size() == 12);
    CHECK(face_count(t) == 6);
    CHECK(euler_characteristic(t) == 2);
    for (int v = 0; v < 8; ++v) CHECK(valence(t, static_cast<std::size_t>(v)) == 3);
    CHECK(boundary_loops(t).empty());
    check_rotation(t);
  }
  SECTION("tetrahedron") {
    const MeshTopology t = build_topology(faces_mesh(4, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}}));
    CHECK(t.edges.size() == 6);
    CHECK(euler_characteristic(t) == 2);
    check_rotation(t);
  }
  SECTION("torus") {
    const MeshTopology t = build_topology(topology_torus(5, 7));
    CHECK(euler_characteristic(t) == 0);
    CHECK(t.edges.size() == 70);
    for (int v = 0; v < 35; ++v) CHECK(valence(t, static_cast<std::size_t>(v)) == 4);
    check_rotation(t);
  }
  SECTION("mixed polygons: a pentagon, triangles and a quad") {
    const MeshTopology t =
        build_topology(faces_mesh(7, {{0, 1, 2, 3, 4}, {1, 0, 5}, {2, 1, 5, 6}, {3, 2, 6}}));
    CHECK(face_count(t) == 4);
    CHECK(euler_characteristic(t) == 1);  // a disc
    check_rotation(t);
    REQUIRE(boundary_loops(t).size() == 1);
  }
}

TEST_CASE("topology of open meshes: boundary flags and loops", "[core][topology]") {
  const MeshTopology t = build_topology(grid(3, 4));
  CHECK(euler_characteristic(t) == 1);
  check_rotation(t);
  int boundary = 0;
  for (int v = 0; v < t.vertex_count; ++v) boundary += t.boundary_vertex[static_cast<std::size_t>(v)];
  CHECK(boundary == 2 * (3 + 4));
  CHECK(valence(t, 0) == 2);          // corner
  CHECK(valence(t, 1) == 3);          // edge
  CHECK(valence(t, 1 * 5 + 1) == 4);  // interior
  const auto loops = boundary_loops(t);
  REQUIRE(loops.size() == 1);
  CHECK(loops[0].size() == 14);
  // The face is on the left of every boundary step: the loop runs 0 → 5 → 10 … (down the first
  // column, since face (0, 0) is 0, 5, 6, 1).
  CHECK(loops[0][0] == 0);
  CHECK(loops[0][1] == 5);
  SECTION("an annulus has two loops") {
    // Square with a square hole: 8 outer vertices ring, 8 inner, 8 quads.
    std::vector<std::vector<int>> faces;
    for (int k = 0; k < 8; ++k) faces.push_back({k, (k + 1) % 8, 8 + (k + 1) % 8, 8 + k});
    const MeshTopology a = build_topology(faces_mesh(16, faces));
    CHECK(boundary_loops(a).size() == 2);
    CHECK(euler_characteristic(a) == 0);
    check_rotation(a);
  }
  SECTION("isolated vertices are kept, with no edges") {
    Mesh m = grid(1, 1);
    m.vertices.conservativeResize(5, 3);
    const MeshTopology i = build_topology(m);
    CHECK(valence(i, 4) == 0);
    CHECK(vertex_faces(i, 4).empty());
    check_rotation(i);
  }
}

TEST_CASE("topology refuses what is not an oriented manifold, naming the element", "[core][topology]") {
  const auto fails = [](const Mesh& m, const std::string& part) {
    try {
      (void)build_topology(m, "m.obj");
      FAIL("accepted");
    } catch (const InvalidInput& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(part) != std::string::npos);
      CHECK(std::string(e.what()).rfind("m.obj: ", 0) == 0);
    }
  };
  fails(faces_mesh(4, {{0, 1, 2}, {0, 1, 3}}), "both use edge (0, 1) in the same direction");
  // Three triangles on edge (0, 1).
  fails(faces_mesh(5, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}), "edge (0, 1)");
  // Two triangles touching at vertex 0 only (a bow tie).
  fails(faces_mesh(5, {{0, 1, 2}, {0, 3, 4}}), "vertex 0 is not manifold");
  // Two closed cones sharing their apex: two tetrahedra glued at vertex 0.
  fails(
      faces_mesh(7, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 5, 4}, {0, 4, 6}, {4, 5, 6}, {5, 0, 6}}),
      "vertex 0 is not manifold");
  fails(faces_mesh(3, {{0, 1}}), "face 0 has 2 vertices");
  fails(faces_mesh(3, {{0, 1, 1}}), "face 0 repeats vertex 1");
  // Large faces mark their corners per vertex instead of comparing them pairwise: same message, and a
  // vertex of an earlier large face is no repeat.
  std::vector<int> big(40), other(40);
  for (int i = 0; i < 40; ++i) big[static_cast<std::size_t>(i)] = other[static_cast<std::size_t>(i)] = i;
  std::reverse(other.begin(), other.end());
  big[37] = 5;
  fails(faces_mesh(40, {other, big}), "face 1 repeats vertex 5 (corners 5 and 37)");
  big[37] = 37;
  big[38] = 37;
  fails(faces_mesh(40, {other, big}), "face 1 repeats vertex 37 (corners 37 and 38)");
  big[38] = 38;
  CHECK(build_topology(faces_mesh(40, {other, big})).edges.size() ==
        40);  // two faces glued: one disc each side
  fails(faces_mesh(3, {{0, 1, 7}}), "face 0 corner 2 is vertex 7, out of range (3 vertices)");
  fails(faces_mesh(3, {{0, -1, 2}}), "out of range");
}

TEST_CASE("topology is linear in the valence: a double pyramid of one vertex of valence 60,000",
          "[core][topology][reliability]") {
  // The twin search scanned every half-edge leaving a vertex for each one: 41 s for valence 100,000
  // (issue 33). Two apexes (0 above, 1 below) over a ring of n vertices: apex valence n, ring 4.
  const int n = 60000;
  std::vector<std::vector<int>> faces;
  for (int i = 0; i < n; ++i) {
    const int a = 2 + i, b = 2 + (i + 1) % n;
    faces.push_back({0, a, b});
    faces.push_back({1, b, a});
  }
  const Mesh m = faces_mesh(n + 2, faces);
  const auto start = std::chrono::steady_clock::now();
  const MeshTopology t = build_topology(m, "pyramid");
  // 0.05 s in Release (the quadratic search: ~5 s); the sanitizers slow it about 20 times.
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() <
        (cifs_test::kSanitized ? 30 : 2));
  CHECK(t.edges.size() == static_cast<std::size_t>(3 * n));
  CHECK(vertex_faces(t, 0).size() == static_cast<std::size_t>(n));
  CHECK(vertex_edges(t, 1).size() == static_cast<std::size_t>(n));
  for (std::size_t e = 0; e < t.edges.size(); ++e) CHECK(t.edge_faces[e][1] >= 0);  // closed
  // The rotations against their invariants on a smaller one (the checks are quadratic themselves).
  std::vector<std::vector<int>> small;
  for (int i = 0; i < 50; ++i) {
    const int a = 2 + i, b = 2 + (i + 1) % 50;
    small.push_back({0, a, b});
    small.push_back({1, b, a});
  }
  check_rotation(build_topology(faces_mesh(52, small), "small"));
}

TEST_CASE("meshes: faces, uniform meshes, checks and normals", "[core][mesh]") {
  Points v(4, 3);
  v << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  const Mesh quad = uniform_mesh(v, {0, 1, 2, 3}, 4);
  REQUIRE(face_count(quad) == 1);
  CHECK(face(quad, 0).size() == 4);
  const Points N = vertex_normals(quad);
  for (int i = 0; i < 4; ++i) CHECK(N.row(i).isApprox(Eigen::RowVector3d(0, 0, 1).cast<double>()));
  // A regular hexagon's Newell normal is its plane's normal.
  Mesh hex;
  hex.vertices.resize(6, 3);
  for (int k = 0; k < 6; ++k) hex.vertices.row(k) << std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 2.0;
  add_face(hex, {0, 1, 2, 3, 4, 5});
  const Points H = vertex_normals(hex);
  for (int i = 0; i < 6; ++i) CHECK((H.row(i) - Eigen::RowVector3d(0, 0, 1)).norm() < 1e-15);
  CHECK_THROWS_WITH(check_mesh(uniform_mesh(v, {0, 1, 9}, 3), "w"),
                    "w: face 0 corner 2 = 9 is out of range (4 vertices)");
  Mesh bad = quad;
  bad.states = {1, 2};
  CHECK_THROWS_WITH(check_mesh(bad, "w"), "w: 2 states for 1 faces");
}

TEST_CASE("mesh_statistics: components, genus, face sizes and valences counted by hand", "[core][topology]") {
  const MeshStatistics cube = mesh_statistics(build_topology(topology_cube()));
  CHECK(cube.faces_by_corners == std::map<std::size_t, std::size_t>{{4, 6}});
  CHECK(cube.valences == std::map<int, std::size_t>{{3, 8}});
  CHECK(cube.components == 1);
  CHECK(cube.boundary_loops == 0);
  CHECK(cube.euler_characteristic == 2);
  CHECK(cube.genus == 0);

  // Two tori (genus 1 each) and an isolated vertex: χ = 0 + 0 + 1 counts the vertex, the genus does not.
  Mesh two = topology_torus(3, 4);
  append(two, topology_torus(4, 3));
  two.vertices.conservativeResize(two.vertices.rows() + 1, 3);
  two.vertices.bottomRows(1).setZero();
  const MeshStatistics tori = mesh_statistics(build_topology(two));
  CHECK(tori.components == 2);
  CHECK(tori.isolated_vertices == 1);
  CHECK(tori.euler_characteristic == 1);
  CHECK(tori.genus == 2);
  CHECK(tori.valences == std::map<int, std::size_t>{{4, 24}});

  const MeshStatistics open = mesh_statistics(build_topology(grid(2, 3)));
  CHECK(open.boundary_loops == 1);
  CHECK_FALSE(open.genus);
  CHECK(open.valences == std::map<int, std::size_t>{{2, 4}, {3, 6}, {4, 2}});
}
