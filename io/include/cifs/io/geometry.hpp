// SPDX-License-Identifier: MIT
// cifs — plain mesh and segment-set data (what renderers draw and exporters write) and their OBJ, PLY
// and SVG files.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/types.hpp"

namespace cifs::io {

/// Triangles and quads over vertex rows. Indices are 0-based rows of `vertices`; quads are split
/// along their 0–2 diagonal where a renderer needs triangles. Faces are ordered triangles first,
/// then quads: face f < #triangles is triangles[f], the others quads[f − #triangles].
struct Mesh {
  Points vertices;  // `#V by 3`
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 4>> quads;
  /// Optional per-vertex normals: empty, or `#V by 3`.
  Points normals;
  /// Optional per-face state (the automaton state that produced the face): empty or one per face.
  std::vector<std::uint32_t> states;
};

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

/// Throws InvalidInput (the message starts with `who`) unless the mesh is well formed: vertices
/// `#V by 3` and finite, every index in [0, #V), normals empty or `#V by 3` and finite, states
/// empty or one per face.
void check_mesh(const Mesh& mesh, std::string_view who);
/// Same for segments: vertices `#V by 2|3` and finite, indices in range, states empty or one per
/// segment.
void check_segments(const Segments& segments, std::string_view who);

/// Area-weighted vertex normals (`#V by 3`): each face adds its vector area (triangle
/// ½(b−a)×(c−a), quad ½(c−a)×(d−b)) to its vertices, then rows are normalised. A vertex whose sum
/// is zero (isolated, or only on degenerate faces) gets a zero row. Orientation follows the
/// faces' vertex order (counter-clockwise seen from the side the normal points to).
Points vertex_normals(const Mesh& mesh);

/// OBJ text: `v` rows (17 significant digits), `vn` rows when the mesh has normals, `f` lines
/// (`f a//a b//b c//c` with normals), 1-based.
std::string mesh_obj(const Mesh& mesh);
/// OBJ text: `v` rows (missing z = 0) and one `l a b` line per segment.
std::string segments_obj(const Segments& segments);

enum class PlyFormat { ascii, binary_little_endian };

/// PLY: `element vertex` (double x y z, plus double nx ny nz when the mesh has normals) and
/// `element face` (list uchar int vertex_indices, plus uint state when the mesh has states).
/// Binary files are little-endian whatever the host.
std::string mesh_ply(const Mesh& mesh, PlyFormat format = PlyFormat::ascii);
/// PLY: `element vertex` (double x y z; z = 0 for planar vertices) and `element edge` (int vertex1,
/// int vertex2, plus uint state when present).
std::string segments_ply(const Segments& segments, PlyFormat format = PlyFormat::ascii);

struct SvgOptions {
  /// Picture width in pixels; the height follows the aspect ratio of the drawing.
  int width = 800;
  /// Stroke width in pixels (round caps and joins).
  double stroke = 1.5;
  std::string color = "#1f4e9c";
};

/// SVG of the x, y coordinates (y up, as in the plane; z is dropped), fitted with a 5 % margin:
/// one path of `M … L …` pieces, consecutive segments that share a vertex drawn as one run.
std::string segments_svg(const Segments& segments, const SvgOptions& options = {});

}  // namespace cifs::io
