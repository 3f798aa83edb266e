// SPDX-License-Identifier: MIT
// cifs CLI — one function per subcommand; each returns the text for stdout, so that an error
// leaves stdout empty. Point sets are the exception: they are streamed to stdout as computed (their
// size has no memory limit), after every check that can refuse them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cifs/experiment/dimension.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/subdivision/mesh.hpp"

namespace cifs::cli {

/// Standard output failed while a command streamed to it (a full disk, a closed pipe): exit status 1,
/// as when main's own write fails.
struct StdoutError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The shape readers' warnings, held until the command has succeeded: main then writes them on stderr,
/// so that a command that fails prints its one error line only.
std::vector<std::string>& pending_warnings();

/// `--index N` and `--ignore-trim`, on every command that reads a shape file.
struct ShapeSelection {
  std::optional<std::size_t> index;  // which shape of a file with several (0-based)
  bool ignore_trim = false;          // read trimmed surfaces whole, with a warning
};

struct EvalOptions {
  std::filesystem::path shape;
  ShapeSelection select;
  std::vector<std::string> at;  // "U" for curves, "U,V" for surfaces
  int samples = 0;              // uniform over the domain (surfaces: samples × samples)
  std::filesystem::path
      output;          // a point-set file (.json, .npy, .ply, .obj), written as computed; empty: stdout
  bool quiet = false;  // no progress bar
};
std::string eval(const EvalOptions& options);

struct ConvertOptions {
  std::filesystem::path input, output;  // formats by extension (io::read_shapes, io::write)
  ShapeSelection select;
};
/// Writes the shapes of `input` into `output`: a STEP or IGES output takes every shape of the input (or
/// the one --index picks), any other format one. Warns when curves or surfaces of 1 or 2 dimensions get
/// z = 0 in STEP or IGES. Prints nothing.
std::string convert(const ConvertOptions& options);

struct InsertOptions {
  std::filesystem::path shape;
  ShapeSelection select;
  std::vector<double> knots;
  std::string dir = "u";
  bool midpoints = false;
};
std::string insert(const InsertOptions& options);

/// Shapes (every shape of the file, one JSON object each, unless `select.index` picks one); polygon
/// meshes through mesh_info; control polygons (JSON "polygon") by points, edges, length and bounds.
std::string info(const std::filesystem::path& shape, const ShapeSelection& select = {},
                 const io::MeshReadOptions& mesh = {});

/// Counts, face sizes, valences, boundary loops, Euler characteristic (and genus when closed), as JSON.
std::string mesh_info(const std::filesystem::path& mesh, const io::MeshReadOptions& read = {});

struct SubdivideOptions {
  std::filesystem::path mesh;
  std::string scheme;  // subdivision::named_mesh_scheme
  int levels = 1;
  // Replace the file's tags when given ("" keeps them): option_name's spellings.
  std::string boundary, crease_method, triangles, fvar_interpolation, rules;
  bool factored = false;         // linear subdivision + averaging (catmull-clark, loop)
  bool strict = false;           // an OBJ tag cifs does not read is an error, not a warning
  bool quiet = false;            // no progress bar
  std::filesystem::path output;  // .obj, .ply, .stl, .off or .vtp; empty: OBJ on stdout
};
std::string subdivide(const SubdivideOptions& options);

/// `cifs limit`: the mesh after `levels` steps with its vertices on the limit surface.
struct LimitCommandOptions {
  std::filesystem::path mesh;
  std::string scheme;
  int levels = 1;
  std::string boundary;  // "" keeps the file's boundary rule
  bool normals = false;  // unit limit normals (PLY nx ny nz, OBJ vn; with `at`, per point)
  bool strict = false;   // an OBJ tag cifs does not read is an error, not a warning
  std::filesystem::path
      output;      // .obj, .ply, .stl, .off or .vtp; empty: OBJ on stdout (with `at`: .json, or stdout)
  std::string at;  // points "face,u,v;…" or a file of them: the limit surface there, as JSON
  bool partials = false;  // with `at`: ∂/∂u, ∂/∂v too
};
std::string limit(const LimitCommandOptions& options);

/// `cifs analyze`: every irregular vertex of a Catmull–Clark or Loop mesh, its class and C1 verdict.
struct AnalyzeOptions {
  std::filesystem::path mesh;
  std::string scheme;
  std::string format = "table";  // table | json
  std::string boundary;          // "" keeps the file's boundary rule
  std::string rules;             // "" keeps the file's rule set (opensubdiv, blz)
  bool strict = false;           // an OBJ tag cifs does not read is an error, not a warning
  std::filesystem::path png;     // optional: the surface (3 levels) with the irregular vertices marked
};
std::string analyze(const AnalyzeOptions& options);

struct AutomatonOptions {
  std::filesystem::path shape;  // a shape, or a mesh (OBJ faces, PLY) with `scheme`
  ShapeSelection select;
  std::string format;  // a writable format of io::formats(Content::automaton); empty: -o's, else json
  bool minimize = false;
  std::string scheme;            // a mesh's: catmull-clark or loop (the surface automaton)
  int levels = 0;                // a mesh's steps of refinement before its automaton is built
  std::filesystem::path output;  // its extension names the format; empty: stdout
};
std::string automaton(const AutomatonOptions& options);

struct AttractorOptions {
  std::filesystem::path shape;
  ShapeSelection select;
  int depth = -1;                // 2^depth leaves per segment, or
  double piece_size = 0;         // every leaf's piece smaller than this (Cartesian units), or
  double deviation = 0;          // curves: every piece within this of its chord (Cartesian units), or
  long long chaos = 0;           // that many chaos-game points
  std::uint64_t seed = 0;        // chaos game: 0 draws one (printed with the points)
  std::string format;            // a format of io::formats(Content::points), or svg; default json
  std::filesystem::path output;  // its extension names the format; streamed unless svg; empty: stdout
  bool quiet = false;            // no progress bar
};
std::string attractor(const AttractorOptions& options);

struct CheckOptions {
  std::filesystem::path shape;
  ShapeSelection select;
  int depth = 8;
  double relative_tolerance = 1e-12;  // of each deviation, relative to the largest control point
  bool json = false;
};
/// `status` becomes 1 when a deviation exceeds the tolerance.
std::string check(const CheckOptions& options, int& status);

struct RenderOptions {
  std::vector<std::filesystem::path> experiments;  // run in order; -o and --png take one
  std::filesystem::path exr, png, out_dir;
  std::optional<unsigned> threads;
  std::string max_memory;  // `--max-memory SIZE` (bytes, or with K, M, G, T); empty: the run's default
  bool quiet = false;
};
/// `--max-memory`: "4G", "3000M", "2.5G", "1000000" as bytes (powers of 1024); InvalidInput otherwise.
std::size_t memory_size(const std::string& text);
/// `cifs render`: runs the experiments, each read before any runs; returns the summaries (what was written).
std::string render(const RenderOptions& options);

struct DimensionOptions {
  std::filesystem::path input;  // experiment file, or shape file (.json with "curve"/"surface"/"shape", .obj)
  ShapeSelection select;        // shape files
  experiment::DimensionOptions measure;
  bool json = false;
};
/// `cifs dimension`: box-counting fit of the deterministic evaluation, and the similarity
/// (Moran / Mauldin–Williams) dimension when the maps are similarities.
std::string dimension(const DimensionOptions& options);

/// The main job on its built-in default: writes the example gallery into `out` from the example
/// files in `examples` (shapes, experiments), returns a summary.
std::string gallery(const std::filesystem::path& out, const std::filesystem::path& examples,
                    bool quiet = false);

}  // namespace cifs::cli
