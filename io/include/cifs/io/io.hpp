// SPDX-License-Identifier: MIT
// cifs — the one dispatcher of the io module: every kind of content, the formats it is read and
// written in (one table, which the CLI's --format, the experiment outputs and the Python bindings
// consult), and read/write by file extension. The formats themselves live one per file: json.hpp,
// obj.hpp, ply.hpp, svg.hpp, dot.hpp (docs/design.md: where a new file format goes).
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/files.hpp"
#include "cifs/io/bcifs_file.hpp"
#include "cifs/io/experiment.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/io/points.hpp"
#include "cifs/io/polygon.hpp"
#include "cifs/io/shape.hpp"
#include "cifs/mesh.hpp"
#include "cifs/nurbs/knot_automaton.hpp"

namespace cifs::io {

/// What io reads and writes (the C++ type in parentheses).
enum class Content {
  shape,       // a NURBS curve or surface (Shape)
  polygon,     // a control polygon or any polyline, open or closed (Polygon)
  mesh,        // a polygon mesh (cifs::Mesh)
  segments,    // a segment set (cifs::Segments)
  automaton,   // an automaton with matrices and its knot data, if any (nurbs::KnotAutomaton)
  bcifs,       // a BC-IFS and its initial nets (BcifsFile)
  experiment,  // an experiment file (Experiment)
  points,      // a point set (PointSet): cifs eval, cifs attractor; written in chunks by PointsFile
};

/// "a shape", "a mesh", "an automaton", …: the content in messages.
std::string_view content_name(Content content);

struct Format {
  std::string_view name;       // "obj": a --format value, an experiment output key
  std::string_view extension;  // ".obj"
  bool read = false, write = false;
  bool binary = false;  // the written bytes are not text (PLY)
};

/// The formats of `content`, in the table's fixed order (the order in which an experiment writes
/// its outputs).
std::vector<Format> formats(Content content);

/// The format called `name` that writes `content`. Otherwise InvalidInput
/// "`who` 'name': expected json, svg or dot" (the writable names, in table order).
Format writable_format(Content content, std::string_view name, std::string_view who);

/// The bytes of a file of `format` (a name of formats(content) that writes; InvalidInput naming the
/// writable ones otherwise). Polygons: json is the polygon file, obj and svg the polyline; PLY is
/// binary little-endian.
std::string encode(const Shape& shape, std::string_view format);
std::string encode(const Polygon& polygon, std::string_view format);
std::string encode(const Mesh& mesh, std::string_view format);
std::string encode(const Segments& segments, std::string_view format);
std::string encode(const PointSet& points, std::string_view format);
std::string encode(const nurbs::KnotAutomaton& automaton, std::string_view format);
std::string encode(const automata::Automaton& automaton, std::string_view format);  // without knot data
std::string encode(const BcifsFile& file, std::string_view format);
/// The same bytes handed to `out` a chunk at a time (an AtomicFile: the file is never whole in memory).
void encode(const Mesh& mesh, std::string_view format, ByteSink& out);
void encode(const Segments& segments, std::string_view format, ByteSink& out);
void encode(const nurbs::KnotAutomaton& automaton, std::string_view format, ByteSink& out);

/// The format of the path's extension among those that write `content`. Otherwise InvalidInput naming the
/// path and the extensions: "out.svg: a mesh is written as .obj or .ply".
Format format_of(const std::filesystem::path& path, Content content);

/// Writes the file of the format its extension names, atomically (cifs::AtomicFile, a chunk at a time).
/// An extension that the content is not written in is an InvalidInput naming the path and the
/// extensions it is written in: "out.svg: a mesh is written as .obj or .ply". Nothing is created
/// then.
void write(const std::filesystem::path& path, const Shape& shape);
/// Several shapes in one file: STEP and IGES hold any number (cifs/io/cad.hpp); any other format takes
/// exactly one (InvalidInput otherwise, naming --index).
void write(const std::filesystem::path& path, std::span<const Shape> shapes);
void write(const std::filesystem::path& path, const Polygon& polygon);
void write(const std::filesystem::path& path, const Mesh& mesh);
void write(const std::filesystem::path& path, const Segments& segments);
void write(const std::filesystem::path& path, const PointSet& points);
void write(const std::filesystem::path& path, const nurbs::KnotAutomaton& automaton);
void write(const std::filesystem::path& path, const automata::Automaton& automaton);  // without knot data
void write(const std::filesystem::path& path, const BcifsFile& file);

/// What a file to read holds, for the commands that take several kinds (cifs info, cifs dimension): by
/// extension, and for .obj and .json by content — a .ply is a mesh; an .obj a mesh when it has faces and no
/// free-form geometry (cstype, curv, surf), else a shape; a .json object a polygon when it holds "polygon",
/// a shape when it holds "curve" or "surface" or "shape" alone (geomdl), else an experiment. Any other
/// extension (and a .json that does not parse: its reader names the problem) is read as a shape. IoError
/// when the file cannot be read.
Content detect(const std::filesystem::path& path);

/// Reads a file in the format its extension names. Shapes, polygons, automata, BC-IFS files and
/// experiments, whose own format is JSON, read any other extension as JSON; meshes must be `.obj` or
/// `.ply` (IoError "m.stl: a mesh is read from .obj or .ply"). IoError naming the path when it
/// cannot be read; the format's errors otherwise.
/// Shapes: every curve and surface of the file (OBJ: all elements; JSON: one, or every entry of a
/// geomdl file; STEP and IGES, through cifs::occt: every B-spline curve and surface, cifs/io/cad.hpp), or the
/// one `options.index` selects (required when the file holds several).
std::vector<Shape> read_shapes(const std::filesystem::path& path, const ShapeReadOptions& options = {});
Shape read_shape(const std::filesystem::path& path, const ShapeReadOptions& options = {});
Polygon read_polygon(const std::filesystem::path& path);
/// Meshes: checked with check_mesh; `options` apply to OBJ (tags cifs does not read).
Mesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options = {});
/// Automata: with their knot data (windows, intervals) when the file has them.
nurbs::KnotAutomaton read_automaton(const std::filesystem::path& path);
BcifsFile read_bcifs(const std::filesystem::path& path);
/// Inputs (shape, automaton) are resolved against the file's folder; the name defaults to its stem.
Experiment read_experiment(const std::filesystem::path& path);
/// Any file `cifs render` takes as an experiment: an experiment file as read_experiment; a shape file (curve,
/// surface) as the experiment of its shape; a polygon mesh as the experiment of its Catmull–Clark surface
/// (Loop for a mesh of triangles) at 2 levels; a BC-IFS file as the experiment of its automaton — each with
/// the default evaluation, camera and style, the
/// control net drawn, and the outputs NAME.exr and NAME.png (NAME: the file's stem). InvalidInput for other
/// contents.
Experiment read_as_experiment(const std::filesystem::path& path);

}  // namespace cifs::io
