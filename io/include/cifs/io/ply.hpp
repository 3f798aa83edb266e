// SPDX-License-Identifier: MIT
// cifs — PLY (Stanford polygon files): meshes and segment sets written as ASCII or binary, polygon
// meshes read from ASCII and binary (either byte order) files. Point sets are written as binary
// point clouds through io::PointsWriter (cifs/io/points.hpp).
#pragma once

#include <string>
#include <string_view>

#include "cifs/files.hpp"
#include "cifs/mesh.hpp"

namespace cifs::io {

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

/// PLY: `element vertex` (double x y z, plus double nx ny nz when the mesh has normals) and
/// `element face` (list uchar int vertex_indices — list uint int when a face has more than 255
/// corners —, plus uint state when the mesh has states). Binary files have the byte order their
/// format names, whatever the host. PLY holds no tags or UVs: hole faces are left out (the surface
/// without them, as renderers draw it); creases, corners, options and face-varying channels are not
/// written (OBJ keeps them; mesh_left_out says what is left out).
std::string mesh_ply(const Mesh& mesh, PlyFormat format = PlyFormat::ascii);
void mesh_ply(const Mesh& mesh, PlyFormat format, ByteSink& out);  // the same bytes, a chunk at a time
/// PLY: `element vertex` (double x y z; z = 0 for planar vertices) and `element edge` (int vertex1,
/// int vertex2, plus uint state when present).
std::string segments_ply(const Segments& segments, PlyFormat format = PlyFormat::ascii);
void segments_ply(const Segments& segments, PlyFormat format, ByteSink& out);

/// A polygon mesh from PLY bytes (ascii, binary_little_endian or binary_big_endian 1.0):
/// `element vertex` with x y z (and nx ny nz, read as normals when all three are there), `element
/// face` with a list `vertex_indices` (or `vertex_index`) of any count and index types (and an
/// integer `state`, read as the face states). Every scalar type of the format is read; other
/// properties and elements are skipped. The result is checked with check_mesh.
///
/// Errors name `where` and the place: IoError for the header ("m.ply: header line 3: …"), truncated
/// data and bytes left over ("m.ply: the data ends in face 7 of 12"), InvalidInput for content
/// ("m.ply: vertex 4: y is not finite", "m.ply: face 2 corner 1 = 9 is out of range (8 vertices)").
Mesh parse_mesh_ply(std::string_view bytes, std::string_view where);

}  // namespace cifs::io
