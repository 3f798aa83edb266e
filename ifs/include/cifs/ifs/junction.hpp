// SPDX-License-Identifier: MIT
// cifs — junctions between shapes built by different schemes (Podkorytov, Gentil, Sokolov,
// Lanquetin 2014, in the BC-IFS formalism): two BC-IFS share boundary cells, the shared cells keep
// the subdivision operators of one side, and the constraints of the other side that meet them
// are solved again, so the junction is exact for every admissible (perturbed) choice of matrices.
// Also the systems the junctions are built from: uniform curve schemes with a junction layer, and
// tensor products of two curve systems (docs/junctions.md).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "cifs/ifs/bcifs.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

struct UniformCurveOptions {
  /// Initial entries (curve pieces, windows k … k + N − 1 of an open polygon of pieces + N − 1 points).
  int pieces = 1;
  /// Pieces at offsets 0 … layer − 1 from the curve's start get cells of their own ("a0", "a1", …)
  /// with free matrices, and so do the vertices between them ("w1", …; at most 4096, pieces ≤ 2^20): the room
  /// a junction at the start ("v0") needs to adapt without touching the interior ("e", "m").
  int layer = 0;
  /// Every transition free (a fractal curve with the scheme's topology).
  bool free = false;
};

/// The BC-IFS of an open curve of a uniform scheme given by its N by N IFS matrices S0, S1
/// (subdivision::ifs_matrices; rows summing to 1). Edge cells of N points: "e" (interior, G = S0,
/// D = S1), "a<p>" (layer); boundaries "start" (rows 0 … N − 2) and "end" (rows 1 … N − 1), the
/// overlap of neighbouring windows, onto vertex cells of N − 1 points: "v0" (the curve's start),
/// "w<q>" (layer), "m" (every other vertex), each with one transition "V" = S0 restricted to the
/// start rows (equal to S1 on the end rows for every uniform scheme). Constraints per edge cell as
/// curve_bcifs: "start", "end", "junction". Free: the layer (and everything with `free`). Throws
/// InvalidInput for matrices that are not N by N with N ≥ 2, or negative counts.
Bcifs uniform_curve_bcifs(const Eigen::MatrixXd& S0, const Eigen::MatrixXd& S1,
                          const UniformCurveOptions& options = {});

struct ProductOptions {
  /// A product transition is free when both factor transitions are (false, surface_bcifs' rule) or
  /// when either is (true: a layer of the u curve makes a strip of free faces and edges).
  bool free_when_either = false;
};

/// The tensor product of two curve systems (surface_bcifs is this product of the curve_bcifs of
/// a tensor automaton's factors): cells (x, y), transitions kron, boundaries and constraints
/// lifted as docs/bcifs.md describes. Initial entries: every pair of initial entries of `u` and
/// `v`, u-major (segment a·nv + b), so ifs::quad_mesh draws it with patches (a, b).
Bcifs product_bcifs(const Bcifs& u, const Bcifs& v, const ProductOptions& options = {});

/// A shared boundary: the boundary `b_boundary` of B's initial entry `b_entry` is the boundary
/// `a_boundary` of A's initial entry `a_entry` (e.g. A's curve ends where B's starts: "end" and
/// "start"; a surface's row of patches: "uend" and "ustart", one glue per patch).
struct Glue {
  std::size_t a_entry = 0;
  std::string a_boundary;
  std::size_t b_entry = 0;
  std::string b_boundary;
};

struct JoinOptions {
  /// A's free transitions stay free (false: A keeps its matrices, B alone adapts and perturbs).
  bool free_a = false;
  /// Prefixes of the state names ("A:e", "B:(a0,e)").
  std::string a_name = "A", b_name = "B";
  SolveOptions solve;
};

struct Junction {
  /// A's cells, transitions, boundaries and constraints, then B's, the shared cells being A's;
  /// initial entries A's then B's. Its free matrices are the projection of the given ones onto
  /// the admissible space (every constraint holds to 1e-12).
  Bcifs system;
  /// A's nets, then B's with the rows of each glued boundary replaced by A's rows.
  std::vector<Points> nets;
  /// The shared cells: (A's state, B's state), closed under children and boundaries.
  std::vector<std::pair<automata::StateId, automata::StateId>> shared;
  /// B's constraints that now read a shared cell's operator (the junction constraints).
  std::vector<std::string> junction_constraints;
  std::size_t free = 0;
  double residual = 0;
};

/// Joins B to A along the glued boundaries. The shared cells are found by closing the glued
/// pairs under children (k-th child with k-th child) and boundaries (by name); each B cell has one
/// A partner of the same size, dimension and number of children, and a boundary of the same name
/// and rows (InvalidInput otherwise, naming the cells). B's shared cells are dropped and every
/// reference to them (boundary operators, transitions into them, factors of constraints) now
/// reads A's, so B's incidence constraints on the cells along the junction bind B's matrices to
/// A's boundary operators; B's constraints on its own shared cells are dropped (A's hold). Then
/// the admissible space is solved and the free matrices projected onto it (dependent entries
/// solved with the free coefficients at their current values); InvalidInput when the constraints
/// have no common solution. Nets (optional, one per initial entry of each side) are joined too.
Junction join(const Bcifs& a, std::span<const Points> nets_a, const Bcifs& b, std::span<const Points> nets_b,
              std::span<const Glue> glue, const JoinOptions& options = {});

}  // namespace cifs::ifs
