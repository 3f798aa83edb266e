// SPDX-License-Identifier: MIT
// cifs — SVG pictures (written only): segment sets and polylines, several styled polylines in one
// figure with a legend, and automata drawn without Graphviz.
#pragma once

#include <string>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/files.hpp"
#include "cifs/mesh.hpp"
#include "cifs/types.hpp"

namespace cifs::io {

struct SvgOptions {
  /// Picture width in pixels; the height follows the aspect ratio of the drawing.
  int width = 800;
  /// Stroke width in pixels (round caps and joins).
  double stroke = 1.5;
  std::string color = "#1f4e9c";
};

/// SVG of the x, y coordinates (y up, as in the plane; z is dropped), fitted with a 5 % margin:
/// one path of `M … L …` pieces, consecutive segments that share a vertex drawn as one run.
std::string segments_svg(const Segments& segments, const SvgOptions& options = {});
void segments_svg(const Segments& segments, const SvgOptions& options, ByteSink& out);  // a chunk at a time

/// SVG of the x, y coordinates of a polyline (`#P by ≥ 2`), fitted with a margin into a
/// `width`-pixel-wide picture; a stroke width in pixels. The writer is segments_svg on
/// polyline_segments.
std::string polyline_svg(const Points& points, bool closed = false, int width = 800, double stroke = 1.5);

/// The warning due when an SVG of these points (`#P by ≥ 2`) drops information: empty when every
/// coordinate after x and y is 0 (plane drawings), else "the SVG is a top view: z (from A to B) is
/// dropped; write json, npy, ply or obj to keep it". The writers above stay silent (tests and the
/// gallery draw top views on purpose); the command line prints it.
std::string svg_dropped_coordinates(const Eigen::Ref<const Points>& points);

/// One polyline of a figure and its style.
struct Stroke {
  Points points;  // `#P by ≥ 2`: x, y are drawn
  bool closed = true;
  std::string colour = "#1f77b4";
  double width = 1.5;
  std::string dash;   // SVG stroke-dasharray, empty for solid
  std::string label;  // shown in the legend below the figure; empty: not listed
};

/// Several polylines in one SVG, fitted together (y up) into `width` pixels, a title above and a
/// legend of the labelled strokes below (the subdivision figures of the gallery).
std::string strokes_svg(const std::vector<Stroke>& strokes, const std::string& title, int width = 800);

/// A self-contained drawing of an automaton (no Graphviz needed): states in columns by
/// breadth-first distance from the initial states (bold outline), recurrent states shaded,
/// transitions as labelled arrows (parallel ones share an arrow, "G,D").
std::string to_svg(const automata::Automaton& automaton);

}  // namespace cifs::io
