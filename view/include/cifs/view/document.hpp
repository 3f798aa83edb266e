// SPDX-License-Identifier: MIT
// cifs — what `cifs view` shows: a file opened as a document (a curve, a surface, a polygon mesh, a BC-IFS
// file, or an experiment file on any source), its editable parameters, and its geometry as the binary
// buffers the page draws, computed by the library calls of `cifs attractor`, `cifs subdivide` and the
// experiment runner of `cifs render` (no second evaluator).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/failing_paths.hpp"
#include "cifs/io/experiment.hpp"
#include "cifs/io/shape.hpp"
#include "cifs/mesh.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"

namespace cifs::view {

/// What a document shows. The last three are experiments drawn by the runner's own scene (experiment::draw):
/// on a polygon mesh (`subdivision`), a junction of two shapes, a classic IFS.
enum class Kind { curve, surface, mesh, bcifs, subdivision, junction, ifs };

/// "curve", "surface", "mesh", "bcifs", "subdivision", "junction", "ifs".
std::string_view kind_name(Kind kind) noexcept;

/// A BC-IFS ready to be perturbed again and again: the system (a BC-IFS file's, or the one the experiment
/// runner builds for a curve or surface: ifs::curve_bcifs, ifs::surface_bcifs), its admissible space solved
/// once (the costly part: 0.25 s for the hills surface), its free coefficients' names and the nets of its
/// initial entries. An edit of the amplitude, seed or values only re-perturbs (ifs::perturb with the space).
struct PerturbableSystem {
  ifs::Bcifs system;
  ifs::AdmissibleSpace space;
  std::vector<std::string> names;           // the free coefficients, in the order of space.free
  std::vector<Points> nets;                 // one per initial entry (homogeneous rows when rational)
  std::vector<std::array<int, 2>> patches;  // surfaces: the grid place of each initial entry
  bool rational = false;
  bool closed = false;  // curves
};

/// The BC-IFS the runner perturbs for `shape` (curve_scene, surface_scene of the experiment module):
/// `keep_vertices` as an experiment's perturbation (knot points, knot lines kept).
std::shared_ptr<const PerturbableSystem> shape_system(const io::Shape& shape, bool keep_vertices);

/// A free coefficient on the page: its name, its value in the opened file (with the file's perturbation),
/// and its admissible range: the interval around the value found by coefficient_range.
struct CoefficientRange {
  std::string name;
  double value = 0;
  double low = 0, high = 0;
  bool capped = false;  // an end is the search's cap (value ± RangeOptions::reach), not a refusal
};

struct RangeOptions {
  double reach = 4;              // searched up to this far from the value on each side
  double first_step = 1.0 / 64;  // the first probe's distance; doubled until a probe is refused
  int bisections = 10;           // then the step between the last accepted and the first refused is halved
};

/// The interval of `name`'s values, around its value under `base` (the other coefficients as `base` sets
/// them), that ifs::perturb accepts — the runner's criterion: the constraints met to 1e-12 and the system
/// contractive (ifs::contraction, paths up to 8 steps). Probes step away from the value doubling until one
/// is refused, then bisect: both ends are accepted values, within step/2^bisections of a refused one
/// (unless capped); the values between are not all probed. InvalidInput when `base` itself is refused.
CoefficientRange coefficient_range(const PerturbableSystem& system, const std::string& name,
                                   const ifs::PerturbOptions& base, const RangeOptions& options = {});

/// An opened file: what it holds, as read (the edits live in Params, so the file's own data stays
/// the reference).
struct Document {
  std::filesystem::path path;
  Kind kind = Kind::curve;
  std::optional<io::Shape> shape;                  // curve, surface
  Mesh mesh;                                       // mesh
  std::shared_ptr<const PerturbableSystem> bcifs;  // bcifs: the file's system
  /// An experiment file: the experiment as read, and its text (save writes it back with the edits).
  std::optional<io::Experiment> experiment;
  std::string experiment_text;
  /// The perturbation the file gives (an experiment's "perturbation"; none: amplitude 0, seed 1). With
  /// `perturbed`, the source goes through ifs::perturb even at amplitude 0 and no values, as the runner does.
  io::PerturbationSpec perturbation;
  bool perturbed = false;
  /// The free coefficients shown as sliders, with their ranges (BC-IFS sources: every one, up to
  /// Limits::max_sliders; shapes: those the experiment sets by name).
  std::vector<CoefficientRange> coefficients;
  /// The opened source's contractivity under the file's perturbation: empty when contractive, else the
  /// library's refusal (the page shows it; every edit is checked again).
  std::string refusal;
};

/// The admissible ranges of the parameters (the page's sliders), and the size guards behind them.
struct Limits {
  int max_depth_curve = 20;
  int max_depth_surface = 10;
  int max_depth_bcifs = 20;
  int max_depth_junction = 12;
  int max_levels = 6;
  /// Refused before any work: more points than this (the browser has to hold them); a classic IFS's
  /// depth slider stops at the deepest depth within it.
  std::size_t max_points = std::size_t{1} << 22;
  /// A BC-IFS with more free coefficients gets no sliders (their ranges cost ~40 perturbations each).
  std::size_t max_sliders = 64;
  /// The files of the folder listed for opening from the page (sorted; the first ones).
  std::size_t max_files = 1000;
};

/// Reads `path` (io::detect decides what it holds): a shape, a mesh, a BC-IFS file (with its nets), or an
/// experiment (on a shape, a BC-IFS file, a mesh, a junction or a classic IFS). InvalidInput for what the
/// view does not show (polygon files), naming the file and what to open instead, and for a BC-IFS file
/// without nets.
Document open_document(const std::filesystem::path& path, const Limits& limits = {});

/// The extensions of the files open_document reads, each once, in the order of io's format table: those of
/// the formats (io::formats) that read what it shows — shapes, meshes, BC-IFS and experiment files —, so that
/// a format added to io is offered on the page (the folder's files) and one io only writes (.vtp) is not.
std::vector<std::string_view> document_extensions();

/// One control point moved: index into the Cartesian control net (the distinct points of a closed
/// curve; surfaces: row i·nv + j) and its new Cartesian coordinates (as many as the shape's dimension).
struct PointEdit {
  std::size_t index = 0;
  std::vector<double> position;
};

/// One control point's weight changed: index as PointEdit's, the new weight (positive, finite). The point
/// stays where it is (its Cartesian position); a non-rational shape becomes rational.
struct WeightEdit {
  std::size_t index = 0;
  double weight = 1;
};

/// One point of a BC-IFS file's control nets moved: net `net` (the initial entry's, in the file's order), its
/// row `index`, and the row's new coordinates (as many as the nets' columns).
struct NetEdit {
  std::size_t net = 0;
  std::size_t index = 0;
  std::vector<double> position;
};

/// What the page may change. Defaults: default_params.
struct Params {
  int depth = 0;                    // curves, surfaces: the attractor's depth
  std::string scheme;               // meshes: subdivision::named_mesh_scheme
  int levels = 0;                   // meshes: subdivision steps
  std::vector<PointEdit> points;    // curves, surfaces, meshes: moved control points (mesh: vertices)
  std::vector<WeightEdit> weights;  // curves, surfaces: changed weights
  std::vector<NetEdit> nets;        // BC-IFS files: moved points of the control nets (edited_nets)
  /// Curves, surfaces: new knots, empty for the file's; else one list per direction (a surface: u, then
  /// v), each of as many values as the file's: an open curve's knot vector, a closed curve's breakpoints
  /// b_0 … b_m (nurbs::defining_knots). Validated by the library (nurbs::validate, make_closed_curve).
  std::vector<std::vector<double>> knots;
  /// Curves, surfaces: above 0, the shape's BC-IFS with its free coefficients perturbed (as an experiment's
  /// "perturbation": amplitude and seed, knot and end points kept), evaluated by experiment::evaluate.
  double amplitude = 0;
  std::uint64_t seed = 1;
  /// Free coefficients set by name (an experiment's "values"): BC-IFS files, perturbed shapes.
  std::map<std::string, double> values;
};

/// A depth giving about 10^4 points (curves) or 10^4 vertices (surfaces); one level for meshes, with
/// Catmull–Clark for meshes with a non-triangle face and Loop otherwise. An experiment: its file's depth (a
/// mesh source: its levels, its scheme) and perturbation, within the view's limits; a classic IFS evaluated
/// by the chaos game: the deepest depth with at most 10^5 points.
Params default_params(const Document& document);

/// The knots the page shows and edits: one list per direction (a closed curve: its breakpoints).
std::vector<std::vector<double>> shape_knots(const io::Shape& shape);

/// The shape with the edits applied — knots, then weights, then points — and validated again by the
/// library (InvalidInput naming the point, the weight or the knot of a bad edit). Rows not edited are
/// kept bit for bit.
io::Shape edited_shape(const Document& document, const Params& params);
/// A BC-IFS file's control nets with the edits of `params.nets` applied, checked by the library
/// (ifs::check_nets). The nets join where the file repeats a point in several nets, bit for bit (the overlap
/// of neighbouring pieces' windows, as nurbs::initial_nets and cifs fit --fractal write them): an edit moves
/// the point and its copies in the other nets, so the pieces stay joined. InvalidInput naming the net and
/// point for a net or point the file does not have, coordinates that are not finite or not as many as the
/// nets' columns, and two edits that give one joined point two positions (they would pull a junction apart).
/// The matrices are not read: an edit of the nets cannot change the system's contractivity.
std::vector<Points> edited_nets(const Document& document, const Params& params);
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
  /// BC-IFS: the positions are the start points of the `pieces` pieces, then their end points (piece i is
  /// the segment from point i to point pieces + i: experiment::evaluate's points, the runner's segments).
  std::uint32_t pieces = 0;
  /// Junctions: the colour of every automaton state (its side's, as the runner draws it; linear RGB), which
  /// the page uses for `states` instead of its own palette. Classic IFS: `states` is the map applied last
  /// (the top-level piece), coloured by the page.
  std::vector<std::array<double, 3>> state_colors;
  /// Perturbed sources and BC-IFS files: the runner's contractivity check (ifs::contraction, paths up to 8
  /// steps): the path length m and δ_m < 1 it found; 0 when not checked (a NURBS shape).
  int contraction_length = 0;
  double contraction_delta = 0;
};

/// The depth slider's top: the view's limit for the document's kind (a classic IFS: the deepest depth whose
/// (#maps)^depth points are within Limits::max_points); 0 for meshes.
int max_depth(const Document& document, const Limits& limits);

/// The amplitude slider's top: 1, and for an experiment on a mesh or a junction twice the file's amplitude
/// when that is more (the Loop examples perturb by 1.5; the runner refuses what is not contractive).
double max_amplitude(const Document& document);

/// Whether `params` evaluate the document's source through ifs::perturb (as the runner does for an
/// experiment with a "perturbation"): an amplitude, a value set by name, or the file's own perturbation.
bool perturbed(const Document& document, const Params& params);

/// What a session keeps between geometry requests (one per session, for its one document: opening
/// another file starts a new one), so that an edit redoes only what it changes and writes into memory
/// already faulted in (fresh buffers of ~10 MB an edit — page faults and zero fills — were half of a
/// control-point edit's time). Each entry is keyed on what it is made from, bit for bit:
/// - the shape's automaton, made from the knots, degrees and numbers of points alone (knot_automaton,
///   tensor_automaton): one serves every edit of points and weights; a knot edit builds it again;
/// - a perturbed shape's system: an amplitude, seed or value edit re-perturbs it (ifs::perturb with its
///   solved space); a moved control point, weight or knot builds it again;
/// - the last surface mesh: its storage reused, and its faces and states kept (ifs::MeshOptions::
///   keep_faces), with the state per node made from them, when the automaton, route and depth are those
///   they were made for;
/// - the paths that failed the last contractivity checks of a perturbed system (ifs::FailingPaths), tried
///   first by the next one: they settle the path lengths below the witness without a scan, the verdict
///   and (m, δ) unchanged. Hints only, never keyed: a path that no longer fits is ignored.
struct EditCache {
  std::string automaton_key;                     // the document and knots `knots` or `tensor` was built for
  std::optional<nurbs::KnotAutomaton> knots;     // curves
  std::optional<nurbs::TensorAutomaton> tensor;  // surfaces
  std::string key;  // the document and the edits of points, weights and knots `system` was built for
  std::shared_ptr<const PerturbableSystem> system;
  std::string mesh_key;  // the automaton's key, the route and depth of `mesh`'s faces; empty: none kept
  Mesh mesh;
  std::vector<std::uint32_t> node_states;  // of `mesh`'s grid nodes (Geometry::states)
  ifs::FailingPaths failing;
};

/// The geometry of the document with `params`, as experiment::evaluate computes it for the experiment with
/// that source, depth and perturbation (the same library calls): ifs::sample_attractor (curves, with the
/// states of the pieces; the points of ifs::attractor), ifs::attractor (surfaces), subdivision::subdivide
/// (meshes); perturbed: ifs::perturb of the shape's BC-IFS (shape_system, kept in `cache`), then
/// ifs::sample_attractor (curves) or ifs::quad_mesh (surfaces); BC-IFS files: ifs::perturb when perturbed,
/// ifs::contraction, ifs::edge_pieces. Experiments on a mesh, a junction or a classic IFS: experiment::draw
/// of the experiment with the page's levels or depth and perturbation (the runner's scene: the refined,
/// limit or fractal mesh; each side's pieces or quad mesh, with its colour per state), a classic IFS's
/// points render::hutchinson_points at the depth (what run bins), a state per point: the map applied last.
/// InvalidInput (before any work) for a parameter out of `limits` or a value outside its coefficient's range,
/// ifs::NotContractive for a non-contractive edit, and as those calls.
Geometry geometry(const Document& document, const Params& params, const Limits& limits = {},
                  EditCache* cache = nullptr);
/// The same into `out`, every field written; its buffers' storage is reused (an edit at the same depth
/// allocates nothing and zero-fills nothing: the positions are written over in place).
void geometry(const Document& document, const Params& params, const Limits& limits, EditCache* cache,
              Geometry& out);

/// FNV-1a (32-bit) taken a 32-bit word at a time over the float32 positions (h = (h ^ bits) · 16777619 from
/// 2166136261): what the page computes on the buffer it received, and a test from the library's points.
std::uint32_t geometry_checksum(const std::vector<float>& positions) noexcept;

/// The wire form: "CIFSVIEW", a little-endian uint32 header length, a JSON header (kind, counts,
/// checksum, grid), padding to 4 bytes, then positions, triangles, states, net, net_lines in that
/// order (the counts in the header).
std::string encode_geometry(const Geometry& geometry);

}  // namespace cifs::view
