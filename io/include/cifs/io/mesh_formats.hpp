// SPDX-License-Identifier: MIT
// cifs — the tessellation exchange formats beside OBJ and PLY: STL (3-D printing, CAD exports), OFF
// (geometry processing: CGAL, Geomview) and VTK XML PolyData (ParaView, with point and cell data).
#pragma once

#include <string>
#include <string_view>

#include "cifs/files.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/mesh.hpp"

namespace cifs::io {

/// Binary STL: every face as the triangles of its fan (0, i, i + 1), holes left out, each with the
/// unit normal of its corners (zero for a degenerate triangle). STL stores float32: InvalidInput for a
/// coordinate beyond the float range; others are rounded to the nearest float.
void mesh_stl(const Mesh& mesh, ByteSink& out);

/// A mesh from STL, binary (84 + 50·n bytes) or ASCII (`solid` … `endsolid`): corners at the same
/// position (the same float, or the same number in ASCII) become one vertex, so that the triangles are
/// connected again; the stored normals are not read (the corners' order gives each triangle's side).
/// A triangle two of whose corners coincide is left out, with a warning counting them (options.warn).
/// Errors name `where` (and the line, in ASCII).
Mesh parse_mesh_stl(std::string_view bytes, std::string_view where, const MeshReadOptions& options = {});

/// OFF text: `OFF` (or `NOFF` with per-vertex normals), the counts, the vertices (17 significant
/// digits), one `n i j …` line per face; holes left out. InvalidInput for normals per face corner.
void mesh_off(const Mesh& mesh, ByteSink& out);

/// A mesh from OFF text: `OFF`, `NOFF` (normals after each vertex), `COFF`/`NCOFF`/`CNOFF` (colours,
/// not read: a warning), `#` comments; other variants (`4OFF`, `nOFF`, `STOFF`) and colours on face
/// lines are named. Errors name `where` and the line.
Mesh parse_mesh_off(std::string_view text, std::string_view where, const MeshReadOptions& options = {});

/// VTK XML PolyData (`.vtp`), binary appended data: points (Float64), polygons (Int64 connectivity and
/// offsets), point data `Normals` when the mesh has per-vertex normals and cell data `state` when it
/// has states; holes left out. InvalidInput for normals per face corner.
void mesh_vtp(const Mesh& mesh, ByteSink& out);

/// What writing `mesh` as `format` ("obj", "ply", "stl", "off", "vtp") leaves out, in words ("2
/// creases, 1 hole face and the face-varying channel 'uv'"), or "" when the format holds all of it.
std::string mesh_left_out(const Mesh& mesh, std::string_view format);

}  // namespace cifs::io
