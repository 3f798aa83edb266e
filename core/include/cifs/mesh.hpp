// SPDX-License-Identifier: MIT
// cifs — the geometry every module shares: polygon meshes (faces of any size in compact arrays)
// and segment sets. Plain data; adjacency lives apart, in cifs/topology.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string_view>
#include <vector>

#include "cifs/types.hpp"

namespace cifs {

/// A polygon mesh. Face f has the corners `face_vertices[face_offsets[f] … face_offsets[f + 1])`,
/// 0-based rows of `vertices`, counter-clockwise seen from the side the normal points to (the
/// layout of OpenSubdiv's Far::TopologyDescriptor, with offsets instead of counts).
/// Renderers split a face into the fan (0, i, i + 1): a quad along its 0–2 diagonal.
struct Mesh {
  Points vertices;                   // `#V by dim` (3 for renderers and exporters)
  std::vector<int> face_offsets{0};  // `#F + 1`, starting at 0, non-decreasing
  std::vector<int> face_vertices;    // the corners of every face, face after face
  /// Optional per-vertex normals: empty, or `#V by 3`.
  Points normals;
  /// Optional per-face state (the automaton state that produced the face): empty or one per face.
  std::vector<std::uint32_t> states;
};

/// Number of faces (`face_offsets.size() − 1`).
inline std::size_t face_count(const Mesh& mesh) noexcept {
  return mesh.face_offsets.empty() ? 0 : mesh.face_offsets.size() - 1;
}

/// The corners of face f.
inline std::span<const int> face(const Mesh& mesh, std::size_t f) noexcept {
  const auto begin = static_cast<std::size_t>(mesh.face_offsets[f]);
  const auto end = static_cast<std::size_t>(mesh.face_offsets[f + 1]);
  return std::span<const int>(mesh.face_vertices).subspan(begin, end - begin);
}

/// Appends a face (its corners in order).
void add_face(Mesh& mesh, std::span<const int> corners);
inline void add_face(Mesh& mesh, std::initializer_list<int> corners) {
  add_face(mesh, std::span<const int>(corners.begin(), corners.size()));
}

/// A mesh whose faces all have `arity` corners, given as `#F·arity` indices (quads of a grid,
/// triangles of a triangulation).
Mesh uniform_mesh(Points vertices, std::vector<int> corners, int arity);

/// Appends `more`'s vertices and faces to `into` (its indices shifted past `into`'s vertices), with
/// their normals and states when both meshes have them (dropped otherwise). Vertices are not welded.
void append(Mesh& into, const Mesh& more);

/// Throws InvalidInput (the message starts with `who`, what the mesh is to the user: "the mesh to
/// render") unless the mesh is well formed: vertices `#V by 3` and finite, offsets starting at 0 and
/// non-decreasing up to the number of corners, every face with at least 3 corners, every index in [0, #V),
/// normals empty or `#V by 3` and finite, states empty or one per face. Adjacency (manifold, orientation) is
/// checked by build_topology, not here: renderers and exporters take any polygon soup.
void check_mesh(const Mesh& mesh, std::string_view who);

/// Area-weighted vertex normals (`#V by 3`): each face adds its vector area to its corners
/// (triangle ½(b−a)×(c−a), quad ½(c−a)×(d−b), larger polygons ½Σ v_i×v_{i+1}, Newell), then rows
/// are normalised. A vertex whose sum is zero (isolated, or only on degenerate faces) gets a zero
/// row. Orientation follows the faces' corner order.
Points vertex_normals(const Mesh& mesh);

/// Independent segments over vertex rows (polylines, tree-like supports, wire frames).
struct Segments {
  Points vertices;  // `#V by 2` (plane) or `#V by 3`
  std::vector<std::array<int, 2>> segments;
  /// Optional per-segment state: empty or one per segment.
  std::vector<std::uint32_t> states;
};

/// The segments (i, i + 1) of a polyline (`#P by 2|3`), plus (last, 0) when closed; every segment
/// gets `state`.
Segments polyline_segments(const Points& polyline, bool closed = false, std::uint32_t state = 0);

/// Appends `more` to `into` (vertices, segments re-indexed, states). Both must have the same number
/// of columns; states are kept when both or neither carry them, otherwise missing ones become 0.
void append(Segments& into, const Segments& more);

/// Throws InvalidInput (the message starts with `who`, what the segments are to the user) unless:
/// vertices `#V by 2|3` and finite, indices in range, states empty or one per segment.
void check_segments(const Segments& segments, std::string_view who);

}  // namespace cifs
