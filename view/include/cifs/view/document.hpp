// SPDX-License-Identifier: MIT
// cifs — what `cifs view` shows: a file opened as a document (a curve, a surface or a polygon mesh),
// its editable parameters, and its geometry as the binary buffers the page draws, computed by the
// library calls of `cifs attractor` and `cifs subdivide` (no second evaluator).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/io/shape.hpp"
#include "cifs/mesh.hpp"

namespace cifs::view {

enum class Kind { curve, surface, mesh };

/// "curve", "surface", "mesh".
std::string_view kind_name(Kind kind) noexcept;

/// An opened file: what it holds, as read (the edits live in Params, so the file's own data stays
/// the reference).
struct Document {
  std::filesystem::path path;
  Kind kind = Kind::curve;
  std::optional<io::Shape> shape;  // curve, surface
  Mesh mesh;                       // mesh
};

/// Reads `path` (io::detect decides what it holds). InvalidInput for what the view does not show yet
/// (BC-IFS, experiment and polygon files), naming the file and what to open instead.
Document open_document(const std::filesystem::path& path);

/// One control point moved: index into the Cartesian control net (the distinct points of a closed
/// curve; surfaces: row i·nv + j) and its new Cartesian coordinates (as many as the shape's dimension).
struct PointEdit {
  std::size_t index = 0;
  std::vector<double> position;
};

/// What the page may change. Defaults: default_params.
struct Params {
  int depth = 0;                  // curves, surfaces: the attractor's depth
  std::string scheme;             // meshes: subdivision::named_mesh_scheme
  int levels = 0;                 // meshes: subdivision steps
  std::vector<PointEdit> points;  // curves, surfaces, meshes: moved control points (mesh: vertices)
  /// Curves, surfaces: above 0, the shape's BC-IFS with its free coefficients perturbed (as an experiment's
  /// "perturbation": amplitude and seed, knot and end points kept), evaluated by experiment::evaluate.
  double amplitude = 0;
  std::uint64_t seed = 1;
};

/// The admissible ranges of the parameters (the page's sliders), and the size guards behind them.
struct Limits {
  int max_depth_curve = 20;
  int max_depth_surface = 10;
  int max_levels = 6;
  /// Refused before any work: more points than this (the browser has to hold them).
  std::size_t max_points = std::size_t{1} << 22;
};

/// A depth giving about 10^4 points (curves) or 10^4 vertices (surfaces); one level for meshes, with
/// Catmull–Clark for meshes with a non-triangle face and Loop otherwise.
Params default_params(const Document& document);

/// The shape with the edits applied (validated again: InvalidInput naming the point for a bad edit).
io::Shape edited_shape(const Document& document, const Params& params);
/// The mesh with the edits applied (before subdivision).
Mesh edited_mesh(const Document& document, const Params& params);

/// The buffers the page draws, little-endian on the wire (encode_geometry).
struct Geometry {
  Kind kind = Kind::curve;
  std::vector<float> positions;  // x, y, z per point (2-D shapes get z = 0)
  bool closed = false;           // curves: the points in order are a polyline, closed back to the first one
  std::vector<std::uint32_t> triangles;  // meshes: index triples (polygons as fans)
  /// Surfaces: rows × cols nodes, node (I, J) at I·cols + J, each cell two triangles (I, J), (I+1, J),
  /// (I+1, J+1) and (I, J), (I+1, J+1), (I, J+1): the page makes them (ifs::surface_mesh's layout).
  std::array<std::uint32_t, 2> grid{};
  std::vector<std::uint32_t> states;     // per point: the automaton state of its piece (empty for meshes)
  std::vector<float> net;                // the (edited) control net's points, x, y, z
  std::vector<std::uint32_t> net_lines;  // the net's edges, index pairs
  std::uint32_t checksum = 0;            // geometry_checksum(positions)
};

/// The geometry of the document with `params`: ifs::sample_attractor (curves, with the states of the
/// pieces; the points of ifs::attractor), ifs::attractor (surfaces), subdivision::subdivide (meshes);
/// with an amplitude, experiment::evaluate of the perturbed shape (no states), as `cifs render` evaluates it.
/// InvalidInput (before any work) for a parameter out of `limits`, and as those calls.
Geometry geometry(const Document& document, const Params& params, const Limits& limits = {});

/// FNV-1a (32-bit) taken a 32-bit word at a time over the float32 positions (h = (h ^ bits) · 16777619 from
/// 2166136261): what the page computes on the buffer it received, and a test from the library's points.
std::uint32_t geometry_checksum(const std::vector<float>& positions) noexcept;

/// The wire form: "CIFSVIEW", a little-endian uint32 header length, a JSON header (kind, counts,
/// checksum, grid), padding to 4 bytes, then positions, triangles, states, net, net_lines in that
/// order (the counts in the header).
std::string encode_geometry(const Geometry& geometry);

}  // namespace cifs::view
