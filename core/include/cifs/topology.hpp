// SPDX-License-Identifier: MIT
// cifs — adjacency of a polygon mesh, from its faces alone (no coordinates): edges, the faces of
// every edge, the faces and edges around every vertex in order, boundary flags. What subdivision
// rules run on; built once and shared by any number of vertex data sets.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/mesh.hpp"

namespace cifs {

/// Topology of an oriented 2-manifold mesh, possibly with boundary.
///
/// Edges are numbered in order of first appearance (faces in order, corners in order); edge e
/// joins `edges[e][0] → edges[e][1]` in the direction of the first face that has it, which is
/// `edge_faces[e][0]`; `edge_faces[e][1]` is the face on the other side, or −1 on the boundary.
/// `face_edges` runs parallel to `face_vertices`: corner i of a face is followed by the edge from
/// corner i to corner i + 1.
///
/// Around vertex v, `vertex_edges(v)` and `vertex_faces(v)` are in counter-clockwise order (seen
/// from the normal side): face k lies between edge k and edge k + 1, edge k being the face's
/// outgoing edge at v (from v to the next corner). An interior vertex has as many edges as faces
/// (the ring closes: face n − 1 lies between edge n − 1 and edge 0); a boundary vertex has one more
/// edge than faces, edges 0 and n − 1 being its two boundary edges. Isolated vertices have no edges
/// and faces.
struct MeshTopology {
  int vertex_count = 0;
  std::vector<int> face_offsets{0};  // as Mesh
  std::vector<int> face_vertices;
  std::vector<int> face_edges;                 // parallel to face_vertices
  std::vector<std::array<int, 2>> edges;       // vertex pairs
  std::vector<std::array<int, 2>> edge_faces;  // second entry −1 on the boundary
  std::vector<int> vertex_offsets_edges{0};    // `#V + 1` into vertex_edge_list
  std::vector<int> vertex_edge_list;
  std::vector<int> vertex_offsets_faces{0};  // `#V + 1` into vertex_face_list
  std::vector<int> vertex_face_list;
  std::vector<char> boundary_vertex;  // per vertex: on a boundary edge
};

inline std::size_t face_count(const MeshTopology& t) noexcept {
  return t.face_offsets.size() - 1;
}
inline std::size_t edge_count(const MeshTopology& t) noexcept {
  return t.edges.size();
}
inline std::span<const int> face(const MeshTopology& t, std::size_t f) noexcept {
  const auto b = static_cast<std::size_t>(t.face_offsets[f]),
             e = static_cast<std::size_t>(t.face_offsets[f + 1]);
  return std::span<const int>(t.face_vertices).subspan(b, e - b);
}
inline std::span<const int> face_edges(const MeshTopology& t, std::size_t f) noexcept {
  const auto b = static_cast<std::size_t>(t.face_offsets[f]),
             e = static_cast<std::size_t>(t.face_offsets[f + 1]);
  return std::span<const int>(t.face_edges).subspan(b, e - b);
}
inline std::span<const int> vertex_edges(const MeshTopology& t, std::size_t v) noexcept {
  const auto b = static_cast<std::size_t>(t.vertex_offsets_edges[v]);
  const auto e = static_cast<std::size_t>(t.vertex_offsets_edges[v + 1]);
  return std::span<const int>(t.vertex_edge_list).subspan(b, e - b);
}
inline std::span<const int> vertex_faces(const MeshTopology& t, std::size_t v) noexcept {
  const auto b = static_cast<std::size_t>(t.vertex_offsets_faces[v]);
  const auto e = static_cast<std::size_t>(t.vertex_offsets_faces[v + 1]);
  return std::span<const int>(t.vertex_face_list).subspan(b, e - b);
}
/// Number of edges at v (its valence).
inline int valence(const MeshTopology& t, std::size_t v) noexcept {
  return t.vertex_offsets_edges[v + 1] - t.vertex_offsets_edges[v];
}
inline bool is_boundary_edge(const MeshTopology& t, std::size_t e) noexcept {
  return t.edge_faces[e][1] < 0;
}
/// The vertex of edge e other than v.
inline int other_vertex(const MeshTopology& t, std::size_t e, int v) noexcept {
  return t.edges[e][0] == v ? t.edges[e][1] : t.edges[e][0];
}

/// The edge joining vertices a and b, or −1 (a walk around a: no index to build).
inline int find_edge(const MeshTopology& t, int a, int b) noexcept {
  if (a < 0 || a >= t.vertex_count) return -1;
  for (const int e : vertex_edges(t, static_cast<std::size_t>(a)))
    if (other_vertex(t, static_cast<std::size_t>(e), a) == b) return e;
  return -1;
}

/// Builds the adjacency of faces over `vertex_count` vertices. Throws InvalidInput naming the
/// offending element unless the mesh is an oriented 2-manifold: every face has ≥ 3 corners, in
/// range, without a repeated vertex; every edge has one or two faces, and two faces use it in
/// opposite directions (consistent orientation); the faces around every vertex form one fan (no
/// two cones meeting at a vertex). Errors start with `who`.
/// Checks the face arrays alone, in time linear in the corners: offsets from 0 to the corner count,
/// faces of 3 corners or more, vertex indices in range, no vertex twice in a face. Errors start with `who`.
void check_faces(std::span<const int> offsets, std::span<const int> corners, int vertex_count,
                 const std::string& who);
MeshTopology build_topology(std::span<const int> face_offsets, std::span<const int> face_vertices,
                            int vertex_count, std::string_view who = "mesh");
/// The same, taking the face arrays over (no copy: the refinement passes each level's faces on).
MeshTopology build_topology(std::vector<int> face_offsets, std::vector<int> face_vertices, int vertex_count,
                            std::string_view who = "mesh");
inline MeshTopology build_topology(const Mesh& mesh, std::string_view who = "mesh") {
  return build_topology(mesh.face_offsets, mesh.face_vertices, static_cast<int>(mesh.vertices.rows()), who);
}

/// Boundary loops: each a closed list of vertices along boundary edges, in the direction of the
/// faces (the face is on the left). Loops start at their smallest vertex; loops in order of it.
std::vector<std::vector<int>> boundary_loops(const MeshTopology& topology);

/// V − E + F.
inline long long euler_characteristic(const MeshTopology& t) noexcept {
  return static_cast<long long>(t.vertex_count) - static_cast<long long>(t.edges.size()) +
         static_cast<long long>(face_count(t));
}

/// Connected components of the faces (faces that share a vertex are connected); isolated vertices are
/// none.
int components(const MeshTopology& topology);

/// What `cifs info` reports of a mesh's topology.
struct MeshStatistics {
  std::map<std::size_t, std::size_t> faces_by_corners;  // corners → faces
  std::map<int, std::size_t> valences;                  // valence → vertices (isolated vertices apart)
  int isolated_vertices = 0;                            // in no face
  std::size_t boundary_loops = 0;
  int components = 0;
  long long euler_characteristic = 0;  // V − E + F, isolated vertices counted
  /// Closed meshes: the total genus g of the oriented surface, from χ = 2c − 2g over the vertices in faces.
  std::optional<long long> genus;
};
MeshStatistics mesh_statistics(const MeshTopology& topology);

}  // namespace cifs
