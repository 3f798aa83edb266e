// SPDX-License-Identifier: MIT
// cifs — the geometry every module shares: polygon meshes (faces of any size in compact arrays)
// and segment sets. Plain data; adjacency lives apart, in cifs/topology.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/types.hpp"

namespace cifs {

/// Sharpness at and above which a crease or corner is infinitely sharp (OpenSubdiv's
/// Sdc::Crease::SHARPNESS_INFINITE); 0 is smooth, values between are semi-sharp (DeRose, Kass, Truong
/// 1998: the sharp rules for that many levels, then a blend, then the smooth rules).
inline constexpr double kInfiniteSharpness = 10;

/// How boundary vertices are refined (OpenSubdiv's VtxBoundaryInterpolation). Boundary edges are
/// always infinitely sharp; `edge_and_corner` also makes a boundary vertex with one face an
/// infinitely sharp corner; `none` leaves the faces around boundary vertices out of the surface (they
/// become holes: the surface stops one face short of the boundary).
enum class BoundaryRule { none, edge_only, edge_and_corner };
/// How semi-sharp edge sharpness decays per level: by 1 (`uniform`), or Chaikin's rule (¾ of the
/// edge's own sharpness + ¼ of its semi-sharp neighbours' at each end, then − 1), which smooths
/// sharpness that varies along a crease.
enum class CreaseMethod { uniform, chaikin };
/// Catmull–Clark's edge rule next to triangles: `catmark` (the plain rule) or `smooth` (OpenSubdiv's
/// TRI_SUB_SMOOTH: face weight 0.47 for a triangle, a rounder limit on triangle-heavy meshes).
enum class TriangleRule { catmark, smooth };
/// Where face-varying data (UVs) is interpolated linearly instead of smoothly (OpenSubdiv's
/// FVarLinearInterpolation): nowhere, at corners only, corners plus 1 or 2 (also at seam junctions),
/// along boundaries, or everywhere (`all`, OpenSubdiv's default: UVs follow the faces bilinearly).
enum class FaceVaryingRule { none, corners_only, corners_plus1, corners_plus2, boundaries, all };
/// The rules at creases, boundaries and corners of Catmull–Clark and Loop: OpenSubdiv's (`opensubdiv`,
/// what files expect), or those of Biermann, Levin and Zorin 2000 (`blz`): the edge point of a smooth
/// edge at a crease or corner vertex leans by the faces of its sector, which makes boundaries and
/// creases of any valence C¹, and concave corners (MeshTags::concave) are flattened so that they do
/// not fold (docs/subdivision-surfaces.md, "Biermann–Levin–Zorin rules").
enum class RuleSet { opensubdiv, blz };

/// The options' names as files, the CLI and Python spell them ("none", "edge", "corner"; "uniform",
/// "chaikin"; "catmark", "smooth"; "none", "corners-only", "corners+1", "corners+2", "boundaries",
/// "all"; "opensubdiv", "blz"), and back: InvalidInput naming the choices for any other name.
std::string_view option_name(BoundaryRule rule) noexcept;
std::string_view option_name(CreaseMethod method) noexcept;
std::string_view option_name(TriangleRule rule) noexcept;
std::string_view option_name(FaceVaryingRule rule) noexcept;
std::string_view option_name(RuleSet rules) noexcept;
BoundaryRule named_boundary_rule(std::string_view name);
CreaseMethod named_crease_method(std::string_view name);
TriangleRule named_triangle_rule(std::string_view name);
FaceVaryingRule named_face_varying_rule(std::string_view name);
RuleSet named_rule_set(std::string_view name);

/// A sharp edge, given by its two vertices (either order).
struct EdgeSharpness {
  int a = 0, b = 0;
  double sharpness = 0;
};
/// A sharp vertex (a corner when its sharpness is positive).
struct VertexSharpness {
  int vertex = 0;
  double sharpness = 0;
};

/// What a production mesh carries beside its faces (OpenSubdiv's topology tags and Sdc::Options):
/// topology data, no coordinates. Read from OBJ `t` lines and JSON, written back after refinement.
struct MeshTags {
  std::vector<EdgeSharpness> creases;  // each edge at most once; sharpness ≥ 0, finite
  std::vector<VertexSharpness> corners;
  std::vector<int> holes;  // faces left out of the surface (with their descendants)
  BoundaryRule boundary = BoundaryRule::edge_only;
  CreaseMethod crease_method = CreaseMethod::uniform;
  TriangleRule triangles = TriangleRule::catmark;
  FaceVaryingRule face_varying = FaceVaryingRule::all;
  RuleSet rules = RuleSet::opensubdiv;
  /// Corners (by vertex) whose sectors are concave, for the `blz` rules: each sector spans 3π/2.
  std::vector<int> concave;
};

/// The first tag that makes a mesh refine differently from a plain one, in words for messages ("a
/// crease (3 7, sharpness 2)", "a corner (vertex 5, sharpness 10)", "a hole (face 4)", "the boundary
/// rule 'none'"), or "" when there is none. Zero sharpness does not count; the options `edge_and_corner`,
/// the crease method and the triangle rule are not features.
std::string first_feature(const MeshTags& tags);

/// Face-varying data: a value per face corner through its own indices (UVs: `vt` rows and the `/t`
/// of OBJ face corners), so that a seam can give one vertex several values.
struct FaceVaryingChannel {
  std::string name = "uv";
  Points values;             // `#values by dim`
  std::vector<int> indices;  // parallel to Mesh::face_vertices: corner k's value row
};

/// A polygon mesh. Face f has the corners `face_vertices[face_offsets[f] … face_offsets[f + 1])`,
/// 0-based rows of `vertices`, counter-clockwise seen from the side the normal points to (the
/// layout of OpenSubdiv's Far::TopologyDescriptor, with offsets instead of counts).
/// Renderers split a face into the fan (0, i, i + 1): a quad along its 0–2 diagonal.
struct Mesh {
  Points vertices;                   // `#V by dim` (3 for renderers and exporters)
  std::vector<int> face_offsets{0};  // `#F + 1`, starting at 0, non-decreasing
  std::vector<int> face_vertices;    // the corners of every face, face after face
  /// Optional normals: empty, or `#V by 3` (per vertex) when normal_indices is empty, else any number of
  /// rows that normal_indices picks from.
  Points normals;
  /// Empty (normals per vertex), or parallel to face_vertices: corner k's normals row (OBJ's `f v//n`), for
  /// surfaces with several normals at a vertex (limit normals at a crease: one per side).
  std::vector<int> normal_indices;
  /// Optional per-face state (the automaton state that produced the face): empty or one per face.
  std::vector<std::uint32_t> states;
  /// Creases, corners, holes and the refinement options a production mesh carries.
  MeshTags tags;
  /// Face-varying channels (UVs), refined with the faces.
  std::vector<FaceVaryingChannel> face_varying;
};

/// Options given beside a mesh file (CLI flags, Python keywords) that replace the file's own.
struct TagOverrides {
  std::optional<BoundaryRule> boundary;
  std::optional<CreaseMethod> crease_method;
  std::optional<TriangleRule> triangles;
  std::optional<FaceVaryingRule> face_varying;
  std::optional<RuleSet> rules;
};
void apply(const TagOverrides& overrides, MeshTags& tags);

/// Whether face f is a hole (listed in mesh.tags.holes); renderers and exporters skip holes.
std::vector<char> hole_flags(const Mesh& mesh);

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
/// normals empty or `#V by 3` and finite, states empty or one per face; tags: vertex and face indices in
/// range, sharpness finite and ≥ 0, no edge or vertex tagged twice, not every face a hole; face-varying
/// channels: one index per corner, in range, finite values. Adjacency (manifold, orientation) is
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
