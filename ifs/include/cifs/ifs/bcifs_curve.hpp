// SPDX-License-Identifier: MIT
// cifs — the automatic BC-IFS of a NURBS curve: edge cells from the knot-doubling automaton,
// vertex cells at their ends, incidence and adjacency constraints, junctions between segments.
#pragma once

#include "cifs/ifs/bcifs.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"

namespace cifs::ifs {

struct CurveBcifsOptions {
  /// false: the vertex operators at the curve's knots (and its end points) stay fixed, so those
  /// points stay on the NURBS curve; the vertex operators at the midpoints created by subdivision
  /// are free, so the geometry between knots can become fractal. true: every vertex operator is
  /// free (segments stay joined: neighbours share their vertex cell).
  bool free_vertices = false;
};

/// Cells and constraints of `curve` (docs/bcifs.md):
/// - edge cells: the states of nurbs::knot_automaton(curve) unfolded by whether the piece
///   starts (suffix "a") and ends ("b") at a knot of the curve: "s3ab", "s5a", "s5". `d+1` points,
///   transitions G, D (free), the knot automaton's initial entries (nets from
///   nurbs::initial_nets);
/// - boundary "start": rows 0 … d−m of the edge net, m the multiplicity of the knot at its start
///   (read from the window); "end": rows m' … d, m' that of the end knot: the rows whose
///   B-splines do not vanish at that knot, so the end point depends on them only;
/// - vertex cells "v<k>" (dimension 0), one transition "V" each: the rows of G (D) that the start
///   (end) of the child selects, restricted to the parent's start (end) rows. Neighbouring
///   segments (and the last and first of a closed curve) share their vertex cell, the two
///   children of a cell share their middle one, and so do the cells below them (congruence);
/// - per edge cell s, with children t1 = G(s), t2 = D(s): "s.start": start(t1)·G = V·start(s);
///   "s.end": end(t2)·D = V'·end(s); "s.junction": end(t1)·G = start(t2)·D.
/// The NURBS matrices satisfy every constraint (an admissible point).
Bcifs curve_bcifs(const nurbs::Curve& curve, const CurveBcifsOptions& options = {});

/// The same from the curve's knot automaton (nurbs::knot_automaton; e.g. a factor of a
/// TensorAutomaton); `closed` joins the last segment's end to the first one's start. Throws
/// InvalidInput for states that are not knot-doubling states of one degree ≥ 1 (a window of 2d − 1
/// intervals each). The nets of its initial entries: nurbs::initial_nets(knots, curve).
Bcifs curve_bcifs(const nurbs::KnotAutomaton& knots, bool closed, const CurveBcifsOptions& options = {});

/// The knot data of the automaton of curve_bcifs(knots, …), or of a perturbation of it (which keeps
/// the states): each edge cell has the window of the knot state it unfolds, the vertex cells none,
/// the initial entries the intervals of their segments. Throws InvalidInput when `automaton` has
/// fewer states than the edge cells or another number of initial entries.
nurbs::KnotAutomaton curve_bcifs_knots(automata::Automaton automaton, const nurbs::KnotAutomaton& knots);

}  // namespace cifs::ifs
