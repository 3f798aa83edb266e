// SPDX-License-Identifier: MIT
// cifs — an experiment's source built into a scene (sources.cpp): its automaton and nets, control net and,
// when asked, its geometry at the file's evaluation. Shared by run (framing, drawing and writing: run.cpp)
// and by the measurements (evaluate, sample: measure.cpp). Internal to the module.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cifs/experiment/run.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/render/image.hpp"

namespace cifs::experiment::detail {

/// A source built (and evaluated when asked), ready to frame, draw and export.
struct Scene {
  automata::Automaton automaton;  // the (perturbed) automaton: drawn, and sampled by the chaos game
  /// NURBS curves: `automaton` with its knot data (windows, intervals), for the automaton outputs.
  std::optional<nurbs::KnotAutomaton> knots;
  std::vector<Points> nets;
  bool rational = false;  // nets hold homogeneous rows
  std::optional<Mesh> mesh;
  std::optional<Segments> curves;
  std::optional<Segments> control;
  std::vector<ifs::AffineMap> maps;  // classic IFS
  Points extent;                     // points that the camera must show
  int depth = 0;
  /// Junctions: the colour of every automaton state (its side's), for faces and segments.
  std::vector<render::Rgb> state_colors;
  std::string junction;  // junctions: what was glued, for the summary and the EXR header
};

/// Whether build_source evaluates the source's geometry (curves, meshes, pieces: at the file's evaluation,
/// none in chaos mode) or builds only its automaton, nets and control net (tolerance sampling).
enum class Geometry { evaluated, skipped };

/// The scene of any source (NURBS shape, BC-IFS file, mesh, junction, classic IFS), perturbed as the file
/// asks; `kind` names the source for summaries.
Scene build_source(const io::Experiment& e, const RunOptions& o, RunReport& report, std::string& kind,
                   Geometry geometry);

/// evaluate and sample measure attractors: a Catmull–Clark or Loop surface is its surface automaton's
/// (fractal when the file perturbs it), after the one or two levels of refinement the automaton needs.
/// With `meshed`, its welded attractor mesh at `depth` below those levels (unset: the file's levels less
/// them). Other schemes have no automaton: refused, naming the mesh.
Scene mesh_attractor(const io::Experiment& e, bool meshed, std::optional<int> depth, const RunOptions& o,
                     RunReport& report, std::string& kind);

/// Rows with 2 or 3 columns for the rasterisers (a 1-D shape lies on the x axis).
Points drawable(const Points& P, const std::string& what);

/// Cartesian rows of homogeneous ones `(w·x, w)` when `rational`, else P.
Points cartesian_if(const Points& P, bool rational);

}  // namespace cifs::experiment::detail
