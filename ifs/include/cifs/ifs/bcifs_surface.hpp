// SPDX-License-Identifier: MIT
// cifs — the automatic BC-IFS of a NURBS surface: the product of the BC-IFS of its u and v
// direction curves (faces = edge × edge cells, edges = vertex × edge and edge × vertex cells,
// corners = vertex × vertex cells), so that perturbing it keeps every knot line (patch boundaries
// and the surface's boundary) and makes the interior fractal.
#pragma once

#include "cifs/ifs/bcifs.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"

namespace cifs::ifs {

struct SurfaceBcifsOptions {
  /// false: the cells on the surface's knot lines (edges and corners whose u or v factor is a
  /// vertex at a knot of that direction) keep their NURBS operators, so every patch boundary and
  /// the surface's boundary stay the NURBS curves; the edges and corners created inside the
  /// patches by subdivision are free. true: every operator is free (patches stay joined).
  bool free_knot_lines = false;
};

/// Cells and constraints of the surface of `automaton` (docs/bcifs.md), built from the curve
/// systems Cu = curve_bcifs(automaton.factors[0]) and Cv (open curves):
/// - cells: pairs (x, y) of Cu and Cv cells reachable from the patches, named "(x,y)", of
///   dimension dim x + dim y: faces (x, y edge cells: product states split by whether each of their
///   four sides lies on a knot line, the curves' a/b flags), edges along v (x a vertex), along u
///   (y a vertex), corners. Size size(x)·size(y), row (i, j) = i·size(y) + j;
/// - transitions: child (cx, cy) of (x, y) is child `cx·n_y + cy` (n_y children of y), label the
///   two labels with v's G, D read H, B, matrix kron(X, Y) (`size' by size`): faces have GH, GB,
///   DH, DB in TensorAutomaton order and matrices; initial entries = automaton.product.initial's
///   (patches in u-major order, same segments), so ifs::quad_mesh(result.automaton,
///   nurbs::initial_nets(automaton, surface), automaton.patches, depth) meshes the result;
/// - boundaries of (x, y): "u<name>" = x's boundary <name> ("ustart", "uend": rows of x's start or
///   end × every row of y, onto (vertex, y)), "v<name>" likewise, and on faces the corners
///   "ustart.vstart" … (rows of x's × rows of y's);
/// - constraints: every constraint of Cu on x lifted along each child of y (name
///   "(x,y).u<constraint>/<label of y's child>") and every constraint of Cv on y along each child of
///   x: incidence (a child's side on its parent's side is the parent's edge subdivided by the edge
///   operator) and adjacency (GH.uend = DH.ustart, GH.vend = GB.vstart, … and the edge's own
///   junction); corners follow from the edges' constraints;
/// - free: a transition is free when both factor transitions are free in Cu and Cv (faces always;
///   edges and corners unless one factor is a vertex at a knot, see SurfaceBcifsOptions).
/// The NURBS (kron) matrices satisfy every constraint.
Bcifs surface_bcifs(const nurbs::TensorAutomaton& automaton, const SurfaceBcifsOptions& options = {});

/// surface_bcifs(nurbs::tensor_automaton(surface), options).
Bcifs surface_bcifs(const nurbs::Surface& surface, const SurfaceBcifsOptions& options = {});

}  // namespace cifs::ifs
