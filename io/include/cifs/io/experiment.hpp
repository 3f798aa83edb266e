// SPDX-License-Identifier: MIT
// cifs — experiment files (docs/experiments.md): what to build, how to perturb and evaluate it,
// how to look at it and what to write. Plain data (read by io::parse_experiment in
// cifs/io/json.hpp, io::read_experiment in cifs/io/io.hpp); cifs::experiment runs them.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/io/bcifs_file.hpp"
#include "cifs/io/shape.hpp"
#include "cifs/mesh.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/scheme.hpp"

namespace cifs::io {

/// A planar affine IFS: a named one ("fern", "sierpinski", "koch") or explicit maps
/// `(a, b, c, d, e, f, p)`: w(x, y) = (a·x + b·y + e, c·x + d·y + f), drawn with weight p.
struct ClassicIfs {
  std::string name;
  std::vector<std::array<double, 7>> maps;
};

/// Free coefficients of the BC-IFS moved away from the NURBS (or file) values: uniform random
/// offsets in [−amplitude, amplitude] from `seed`, then the explicit `values` by coefficient name.
/// Mesh sources: which feature curves become fractal on their own, and their curve BC-IFS's
/// perturbation (subdivision::FractalFeatureOptions; "fractal_curves" in the experiment file).
struct FractalCurvesSpec {
  bool creases = true;      // the infinitely sharp creases
  bool boundaries = false;  // the boundary curves
  double amplitude = 0;
  std::uint64_t seed = 1;
  std::map<std::string, double> values;
};

struct PerturbationSpec {
  double amplitude = 0;
  std::uint64_t seed = 1;
  std::map<std::string, double> values;
  /// NURBS sources: keep the vertex operators (knot points and end points stay on the NURBS).
  bool keep_vertices = true;
  std::optional<FractalCurvesSpec> fractal_curves;  // mesh sources only
};

/// A polygon mesh and the subdivision scheme that refines it (docs/subdivision-surfaces.md). The
/// mesh is read and its topology checked when the experiment is parsed; `run` refines it.
struct MeshSource {
  std::filesystem::path path;  // as resolved against the experiment's folder
  Mesh mesh;                   // the control mesh
  subdivision::MeshScheme scheme = subdivision::MeshScheme::catmull_clark;
  int levels = 3;
  /// Draw the limit surface itself: the refined vertices at their limit positions, with the limit
  /// normals on closed meshes (Catmull–Clark and Loop; subdivision/limit.hpp).
  bool limit = false;
};

/// One side of a junction (docs/junctions.md): a NURBS curve or surface, or a uniform subdivision
/// scheme on its control points (a polygon for a curve; a grid for the tensor-product surface of
/// the scheme in u and v).
struct JunctionSideSpec {
  std::optional<Shape> shape;
  std::optional<subdivision::Scheme> scheme;
  Points points;              // scheme sides: the polygon, or the grid u-major (row i·columns + j)
  int rows = 0, columns = 0;  // scheme surfaces: the grid's lines of constant v × of constant u; 0: a curve
  int window = 0;             // scheme sides: points per cell (0: the scheme's support N)
  /// Scheme sides: cells of their own, with free matrices, for the first `layer` pieces from the
  /// glued start (ifs::UniformCurveOptions::layer; across the junction for surfaces).
  int layer = 0;
  /// Scheme sides: every matrix free (ifs::UniformCurveOptions::free); NURBS sides: the vertex
  /// operators (curves) or knot lines (surfaces) free too.
  bool free = false;
  /// The glued boundary: "start", "end" (curves); "ustart", "uend", "vstart", "vend" (surfaces).
  std::string boundary;
  std::optional<std::array<double, 3>> color;  // unset: render.color for A, orange for B
};

/// Two shapes joined along a shared boundary (ifs::join): A keeps its matrices, B adapts.
struct JunctionSpec {
  JunctionSideSpec a, b;
};

struct EvaluationSpec {
  enum class Mode { depth, tolerance, chaos };
  Mode mode = Mode::depth;
  int depth = 8;
  double tolerance = 1e-3;             // relative to the shape's control-net diameter
  std::uint64_t samples = 10'000'000;  // chaos game
  std::uint64_t seed = 1;
};

struct CameraSpec {
  enum class Projection { automatic, orthographic, perspective };
  /// automatic: orthographic top view for planar shapes, perspective for 3-D ones.
  Projection projection = Projection::automatic;
  /// Unset: framed automatically from the shape's bounds.
  std::optional<std::array<double, 3>> eye, target;
  std::array<double, 3> up{0, 0, 1};
  double fov_degrees = 35;
  double margin = 0.05;  // fraction of the image left around the framed shape
};

struct RenderSettings {
  int width = 1024;
  int height = 1024;
  double line_width = 2;  // pixels
  std::array<double, 3> color{0.12, 0.30, 0.65};
  std::array<double, 3> background{1, 1, 1};
  bool control_net = false;  // also draw the control polygon / net / mesh
  unsigned threads = 0;      // 0: every hardware thread
  /// Density (chaos-game, Hutchinson) previews: colour stops from the lowest to the highest density
  /// (linear RGB). Empty: from the background to `color` when the file gives a colour
  /// (`color_given`), else the default ramp (render::ToneMapOptions).
  std::vector<std::array<double, 3>> palette;
  bool color_given = false;
  double gamma = 1;     // density previews: v ↦ v^(1/gamma) after the log mapping (> 1 lifts faint parts)
  double exposure = 1;  // previews: shaded colours × exposure; densities saturate at max / exposure
};

/// Output files, relative to the output directory given at run time (empty: not written).
struct Outputs {
  std::filesystem::path exr, png;  // the image and its preview
  /// The evaluated geometry (a mesh or a segment set) by format name ("obj", "ply", "svg": the
  /// formats of io::formats(Content::mesh / segments); file key "obj").
  std::map<std::string, std::filesystem::path> geometry;
  /// The evaluated automaton by format name (io::formats(Content::automaton); file key
  /// "automaton_svg" for "svg").
  std::map<std::string, std::filesystem::path> automaton;
};

struct Experiment {
  std::string name;  // default: the file's stem
  std::string description;
  /// Exactly one source: a NURBS shape (a shape file, an inline shape, or the uniform B-spline of a
  /// polygon file), a BC-IFS automaton file, a classic IFS, a polygon mesh to subdivide, or a
  /// junction of two shapes.
  std::optional<Shape> shape;
  std::filesystem::path automaton;  // absolute (resolved against the experiment's folder)
  /// The BC-IFS file's content when it is given in memory (cifs view's moved nets): read instead of the
  /// file `automaton` names, which still names the source. Not written with the experiment.
  std::optional<BcifsFile> bcifs;
  std::optional<ClassicIfs> ifs;
  std::optional<MeshSource> mesh;
  std::optional<JunctionSpec> junction;
  std::optional<PerturbationSpec> perturbation;
  EvaluationSpec evaluation;
  CameraSpec camera;
  RenderSettings render;
  Outputs outputs;
  /// Every file the experiment reads: the experiment file itself (io::read_experiment), its shape,
  /// polygon, mesh or BC-IFS file. Outputs onto them are refused (cifs::OutputOptions::inputs).
  std::vector<std::filesystem::path> inputs;
};

}  // namespace cifs::io
