// SPDX-License-Identifier: MIT
// cifs — running an experiment: build the automaton (NURBS knot doubling, tensor product, BC-IFS
// file or classic IFS), perturb its free coefficients, evaluate the attractor, render and export.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/io/experiment.hpp"
#include "cifs/mesh.hpp"
#include "cifs/render/partial.hpp"
#include "cifs/types.hpp"

namespace cifs::experiment {

struct RunOptions {
  /// Folder of the experiment's `outputs` (created when missing).
  std::filesystem::path out_dir = ".";
  /// Override `outputs.exr` / `outputs.png` (paths as given, not under out_dir; their folders must
  /// exist).
  std::filesystem::path exr, png;
  bool quiet = false;               // no progress bar
  std::optional<unsigned> threads;  // overrides render.threads
  /// Refuse (before any work) an image or geometry above this many bytes.
  std::size_t max_bytes = std::size_t{1} << 31;
  /// A distributed run (cifs render under mpirun; docs/scaling.md): this process draws only its
  /// part — the chaos game's chunks c ≡ index (mod count), or the rows of its bands
  /// (render::owns_row) of every other layer — and hands its share to `combine`, which every part
  /// calls once and which leaves the combined image in the share of part 0 (an MPI reduction).
  /// Part 0 alone reserves and writes the outputs; the others return after `combine`.
  render::Part part;
  std::function<void(render::Share&)> combine;
};

struct RunReport {
  std::vector<std::filesystem::path> written;
  int depth = 0;  // depth evaluated (chaos: depth of the sampled nodes)
  std::size_t free_coefficients = 0;
  double residual = 0;                // largest constraint residual after perturbation
  std::string summary;                // one line per fact, for the CLI
  std::vector<std::string> warnings;  // "outputs.svg: …": what an output drops (the CLI prints them)
};

/// Runs `experiment`. Its outputs are checked and their temporary files made before any work
/// (cifs::AtomicFiles: no output onto an input, a folder, a device or another output; the image
/// paths' folders must exist, the others are created), written — geometry and automaton files a
/// chunk at a time, never whole in memory — and renamed together at the end: all are written or
/// none is, never a partial one. Throws InvalidInput (bad content, too large,
/// two outputs naming one file), IoError (files).
RunReport run(const io::Experiment& experiment, const RunOptions& options = {});

/// The deterministic evaluation of an experiment's source, for analysis (cifs dimension).
struct Evaluation {
  /// `#P by dim` Cartesian points: curve points, mesh vertices, BC-IFS piece ends, or for a classic
  /// IFS the start points of the depth-K nodes of its one-state automaton (attractor points).
  Points points;
  int depth = 0;
  std::string kind;  // "NURBS curve", "classic IFS koch", …
  /// Bound on the diameter of the pieces the points stand for (ifs::PieceBounds, Cartesian): the
  /// largest bound over the depth-K pieces, or the tolerance of `sample`; infinite when unknown
  /// (a rational piece whose weights may vanish).
  double resolution = 0;
  /// Largest Cartesian diameter of the depth-K leaves' nets (evaluate only; 0 for sample): an
  /// estimate of the pieces' size, not a bound (the attractor piece may stick out of its net's hull
  /// when matrices are signed), finite where `resolution` is not; infinite when a leaf's weights
  /// reach 0.
  double estimated_resolution = 0;
  automata::Automaton automaton;  // the (perturbed) automaton; for a classic IFS its CIFS form
  std::vector<Points> nets;       // one per initial entry (homogeneous rows when `rational`)
  bool rational = false;
  std::vector<ifs::AffineMap> maps;  // classic IFS only
};

/// Builds the source of `experiment` as `run` does (shape, perturbation) and evaluates it to
/// `depth` (default: the file's evaluation.depth, whatever its mode). A Catmull–Clark or Loop mesh
/// experiment is its surface automaton (the mesh refined once, or twice where a face keeps two
/// extraordinary corners; fractal when the file perturbs it), `depth` counted below those levels
/// (default: the file's subdivision.levels less them), the points its welded attractor mesh's vertices.
/// Nothing is rendered or written. Throws InvalidInput as run, for a negative depth, and for a mesh
/// under another scheme (no automaton).
Evaluation evaluate(const io::Experiment& experiment, std::optional<int> depth = {},
                    const RunOptions& options = {});

/// What `run` draws of an experiment's source evaluated to a depth (cifs view shows it): the geometry of the
/// runner's scene, before any framing, drawing or writing.
struct Drawing {
  /// Surfaces, meshes (refined, limit or fractal: Experiment::mesh as run refines it) and junctions of
  /// surfaces (one quad mesh per side, appended), with a state per face when the automaton gives one.
  std::optional<Mesh> mesh;
  /// Curves, BC-IFS pieces and junctions of curves: the segments, a state per segment.
  std::optional<Segments> curves;
  Segments control;  // the control polygon, net or mesh (none for a classic IFS)
  /// Junctions: the colour of every automaton state (its side's, the file's `color`); else empty.
  std::vector<std::array<double, 3>> state_colors;
  automata::Automaton automaton;  // the (perturbed) automaton whose states `mesh` and `curves` give
  /// A classic IFS: its maps, drawn by run as their Hutchinson measure at the depth
  /// (render::hutchinson_measure; its points: render::hutchinson_points).
  std::vector<ifs::AffineMap> maps;
};

/// The runner's scene of `experiment` evaluated to `depth` (default: the file's evaluation.depth, whatever
/// its mode; a mesh source: its subdivision.levels, which `depth` replaces), as run draws it: the same
/// calls, the same doubles.
/// Throws InvalidInput as run, and for a negative depth.
Drawing draw(const io::Experiment& experiment, std::optional<int> depth = {}, const RunOptions& options = {});

struct SampleOptions {
  /// Piece diameter relative to the extent (diameter) of the Cartesian initial nets; 0: the
  /// largest 2^-j (j ≥ 4) within max_points (ifs::tolerance_sample).
  double tolerance = 0;
  /// Refuse (before allocating it) a sample of more points.
  std::size_t max_points = std::size_t{1} << 21;
  /// How refusals name the tolerance (`--relative-piece-size`, say) and what they advise above
  /// max_points (empty: raise the tolerance or the point limit).
  std::string_view tolerance_name = "tolerance";
  std::string_view limit_hint = {};
};

/// Builds the source of `experiment` as `run` does and samples its attractor to a tolerance
/// (ifs::tolerance_sample): one attractor point per piece, every piece proven smaller than
/// `resolution` = tolerance × extent; `depth` is the deepest piece. For any source (curve, surface,
/// BC-IFS, classic IFS, a mesh's surface automaton as in evaluate), whatever the file's evaluation mode.
/// Throws InvalidInput as run, for a tolerance < 0, as ifs::tolerance_sample, and as evaluate for meshes.
Evaluation sample(const io::Experiment& experiment, const SampleOptions& options = {},
                  const RunOptions& run_options = {});

}  // namespace cifs::experiment
