// SPDX-License-Identifier: MIT
// cifs — Wavefront OBJ: free-form B-spline curves and surfaces (read and written), polygon meshes
// (read and written), segment sets and polylines (written).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/files.hpp"
#include "cifs/io/shape.hpp"
#include "cifs/mesh.hpp"
#include "cifs/types.hpp"

namespace cifs::io {

/// OBJ free-form geometry (docs/formats.md): `cstype [rat] bspline` or `cstype [rat] bezier`, `deg`,
/// `curv`/`surf`, `parm u|v`, `end`, with `v x y z [w]` vertices. Every curve and surface of the file,
/// in order, each over the part of its knot domain that its range selects (a range reaching outside
/// the domain is clamped to it, with a warning). Trimmed surfaces: options.ignore_trim.
std::vector<Shape> parse_obj(std::string_view text, std::string_view where,
                             const ShapeReadOptions& options = {});
std::string to_obj(const Shape& shape);

/// Options of the mesh readers: what to do with what cifs does not represent.
struct MeshReadOptions {
  /// An OBJ tag cifs does not read (`t vertexedit`, `t edgeedit`, `t faceedit`, …) is an error
  /// (InvalidInput naming it and its line) instead of a warning.
  bool strict = false;
  /// Receives each warning (one line that starts with the file's name and line). Empty: the warning
  /// is written on stderr as "cifs: warning: …".
  std::function<void(const std::string&)> warn;
};

/// Passes `message` to options.warn, or writes it on stderr when that is empty.
void warn(const MeshReadOptions& options, const std::string& message);

/// A polygon mesh from OBJ text: `v x y z` (further numbers, a weight or a colour, are ignored),
/// `f` with references `v`, `v/vt`, `v/vt/vn` or `v//vn` (1-based, or negative counting back from
/// the latest vertex), faces of any size ≥ 3. The normals are kept when they are per vertex as
/// mesh_obj writes them (one `vn` per `v`, every corner `a//a`), dropped otherwise. `vt` rows (1 to 3
/// numbers, the same in every row) and the `/vt` of the corners are the face-varying channel "uv";
/// every corner has one, or none does. Tags as OpenSubdiv's shapes write them (docs/formats.md):
/// `t crease 2/1/0 a b s` (0-based vertex pairs, one sharpness or one per pair), `t corner`,
/// `t hole`, `t interpolateboundary`, `t facevaryinginterpolateboundary`,
/// `t facevaryingpropagatecorners`, `t creasemethod`, `t smoothtriangles`; a later tag of the same
/// edge or vertex replaces the earlier one. An unknown tag is a warning (options.warn), or an error
/// with options.strict. Other statements (`l`, `g`, `usemtl`, free-form geometry, …) are ignored.
/// Errors name `where` and the line ("m.obj: line 12: vertex index 9 is out of range: 8 vertices are
/// defined before this line"); a file without faces is refused. The result passes check_mesh.
Mesh parse_mesh_obj(std::string_view text, std::string_view where, const MeshReadOptions& options = {});

/// OBJ text: `v` rows (17 significant digits), `vt` rows of the face-varying channel, `vn` rows when
/// the mesh has normals, `f` lines (`f a/t/a …` with both), 1-based, then the tags: creases, corners,
/// holes, and the options that are not the default. parse_mesh_obj reads it back bit for bit.
/// InvalidInput for a mesh with more than one face-varying channel (OBJ holds one).
std::string mesh_obj(const Mesh& mesh);
void mesh_obj(const Mesh& mesh, ByteSink& out);  // the same bytes, a chunk at a time
/// OBJ text: `v` rows (missing z = 0) and one `l a b` line per segment.
std::string segments_obj(const Segments& segments);
void segments_obj(const Segments& segments, ByteSink& out);
/// OBJ: one `v` line per point (missing coordinates are 0, more than 3 are refused) and one `l`
/// element through them, closed back to the first point when `closed` (the obj point-set format of
/// PointsWriter, cifs/io/points.hpp).
std::string polyline_obj(const Points& points, bool closed = false);

}  // namespace cifs::io
