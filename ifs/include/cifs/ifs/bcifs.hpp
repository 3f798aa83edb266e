// SPDX-License-Identifier: MIT
// cifs — boundary controlled IFS (BC-IFS, Sokolov, Gouaty, Gentil, Mishkinis 2014): cells with
// boundary operators, linear constraints on the subdivision matrices, the affine space of
// admissible matrices with named free coefficients, seeded perturbation, edge-cell evaluation.
//
// Row convention throughout (docs/bcifs.md): nets are `size by cols` rows, a transition acts as
// Q = T·N (T is `size(to) by size(from)`, rows sum to 1), a boundary operator as B·N. The
// literature writes points as columns with the transposed matrices; its incidence constraint
// `T_i·B_k = B_m·T_j` reads here `B_k·T_i = T_j·B_m`.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <compare>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

/// A transition named by its source state and its position among the source's out-edges.
struct TransitionRef {
  automata::StateId from = 0;
  int child = 0;
  // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the 0 of a defaulted <=>'s expansion.
  friend auto operator<=>(const TransitionRef&, const TransitionRef&) = default;
};

/// A 0/1 selection: the net of cell `boundary` is rows `rows` of the net of `cell`, i.e. B·N with
/// B `size(boundary) by size(cell)`, B(i, rows[i]) = 1. Named per cell ("start", "end", "u0", …).
struct BoundaryOperator {
  std::string name;
  automata::StateId cell = 0;
  automata::StateId boundary = 0;
  std::vector<int> rows;
};

/// One factor of an operator product: a boundary operator (index into Bcifs::boundaries) or a
/// transition.
struct Factor {
  enum class Kind { boundary, transition };
  Kind kind = Kind::transition;
  int boundary = 0;
  TransitionRef transition;
};

/// `left == right` as matrices, each side the product F_0·F_1⋯F_k (F_k acts first on a net).
/// Both sides map the same source cell to the same target cell; each side holds at most one free
/// transition, so the constraint is linear in the free entries.
struct Constraint {
  std::string name;
  std::vector<Factor> left, right;
};

/// A BC-IFS: an automaton whose states are cells of a dimension (0 vertex, 1 edge, 2 face),
/// boundary operators, constraints, and the transitions whose matrices are unknowns.
struct Bcifs {
  automata::Automaton automaton;
  std::vector<int> dimension;  // per StateId
  std::vector<BoundaryOperator> boundaries;
  std::vector<Constraint> constraints;
  std::vector<TransitionRef> free;
};

/// The out-edge `ref` of the automaton; throws InvalidInput when it does not exist.
automata::TransitionId transition_id(const automata::Automaton& automaton, TransitionRef ref);

/// "E/G": the source state's name (or "s<id>" when unnamed), '/', the transition's label.
std::string transition_name(const automata::Automaton& automaton, TransitionRef ref);

/// B (`rows.size() by size(cell)`).
Eigen::MatrixXd selection_matrix(const Bcifs& system, int boundary);

/// Throws InvalidInput unless: one dimension per state in 0…2; boundary operators name existing
/// cells, have size(boundary) distinct rows inside the cell, a boundary of lower dimension, and
/// names unique per cell; out-edge labels unique per state (they name the transitions); factors
/// exist and chain (each factor reads the cell the next one produces); both sides of a constraint
/// map the same cells; at most one free transition per side; no transition listed free twice.
void validate(const Bcifs& system);

/// An entry of a free matrix.
struct Coefficient {
  TransitionRef transition;
  int row = 0, col = 0;
};

/// "E/G[1,2]".
std::string coefficient_name(const automata::Automaton& automaton, const Coefficient& c);

/// Per constraint, max |left − right| over the entries divided by max(1, largest |entry| of
/// either side); then, per free matrix, the largest |row sum − 1| (name "<transition> row sums").
std::vector<std::pair<std::string, double>> constraint_residuals(const Bcifs& system);

/// Throws InvalidInput naming the worst constraint and its residual when any residual of
/// constraint_residuals exceeds `tolerance`.
void check_admissible(const Bcifs& system, double tolerance = 1e-12);

/// The cell a constraint reads: the source of the last factor of its left side.
automata::StateId source_cell(const Bcifs& system, const Constraint& constraint);

struct SolveOptions {
  /// Relative rank threshold of the pivoted QR of each component (|r_kk| ≤ threshold·|r_00|), in
  /// [0, 1) (InvalidInput otherwise).
  double threshold = 1e-10;
};

/// The admissible matrices: every entry of every free matrix (`unknowns`, free transitions in
/// order, entries row-major) is x = x0 + K·c, where c holds the values of the free coefficients
/// `unknowns[free[j]]` themselves (K has a unit row at each free index). Constraints and row sums
/// (affine invariance) are split into connected components of the unknown/equation graph and each
/// is solved densely; the free coefficients are the non-pivot columns of a column-pivoted QR.
struct AdmissibleSpace {
  std::vector<Coefficient> unknowns;
  std::vector<std::size_t> free;  // increasing indices into unknowns
  Eigen::VectorXd x0;
  Eigen::SparseMatrix<double> K;  // `unknowns by free`
  std::size_t components = 0;
};

/// Throws InvalidInput (after validate) when the constraints have no solution: it names the
/// constraints of the inconsistent component and the least-squares residual.
AdmissibleSpace admissible_space(const Bcifs& system, const SolveOptions& options = {});

/// Names of the free coefficients, in the order of `space.free`.
std::vector<std::string> free_names(const Bcifs& system, const AdmissibleSpace& space);

/// The current values of the free coefficients (read from the matrices).
Eigen::VectorXd free_values(const Bcifs& system, const AdmissibleSpace& space);

/// The system with every free matrix set from x0 + K·c (`c` one value per free coefficient).
Bcifs with_free_values(const Bcifs& system, const AdmissibleSpace& space, const Eigen::VectorXd& c);

struct PerturbOptions {
  /// Each free coefficient gets current value + uniform in [−amplitude, amplitude].
  double amplitude = 0;
  /// Seeds cifs::Random (cifs/random.hpp, xoshiro256**): same seed, same values everywhere.
  std::uint64_t seed = 1;
  /// Free coefficients set by name to these values (instead of the random draw).
  std::map<std::string, double> values;
  SolveOptions solve;
  ContractionOptions contraction;
  /// Off: perturb returns the perturbed system unchecked (`residual` 0, `contraction` {}) for the caller to
  /// check with check_residual(Perturbation&) and check_contractive(Perturbation&, …) (failing_paths.hpp),
  /// refusing as perturb would in that order — cifs view runs the contractivity check on another thread
  /// beside the residuals and the evaluation, and shows the system only when both checks pass.
  bool check = true;
};

struct Perturbation {
  Bcifs system;
  /// Every free coefficient and the value used, in the order of AdmissibleSpace::free.
  std::vector<std::pair<std::string, double>> values;
  /// Largest entry of constraint_residuals of the result (≤ 1e-12 or perturb throws).
  double residual = 0;
  Contraction contraction;
};

/// Perturbs the free coefficients, solves the dependent ones and checks the result (unless `check` is off):
/// residual ≤ 1e-12 and contractive (ifs::contraction), else InvalidInput saying why.
/// Also throws for a negative or non-finite amplitude and for names in `values` that are not free
/// coefficients.
Perturbation perturb(const Bcifs& system, const PerturbOptions& options = {});
/// The same with the system's admissible space solved already (admissible_space(system, options.solve)):
/// an interactive edit of the amplitude, seed or values re-perturbs without solving the constraints again
/// (cifs view). `space` must be that system's.
Perturbation perturb(const Bcifs& system, const AdmissibleSpace& space, const PerturbOptions& options);

/// The residual check perturb makes: sets `perturbation.residual` to the largest constraint_residuals of its
/// system, or throws InvalidInput as perturb does when it is above 1e-12.
void check_residual(Perturbation& perturbation);

/// Start and end functionals of every edge cell (dimension 1) reachable from the initial
/// entries: ℓ_V·B where B is the cell's boundary operator "start" (or "end") and ℓ_V the fixed
/// point of the vertex cell V it selects (following V's first transition until a cell repeats).
/// Unlike ifs::end_functionals this does not assume the first and last children hold the ends,
/// so branches (a third child) do not move them. Throws InvalidInput when a reachable edge cell
/// lacks a "start" or "end" boundary onto a vertex cell.
EndFunctionals edge_end_functionals(const Bcifs& system);

/// The pieces of an edge system at `depth`: one per node, in order (initial entries in order,
/// children in out-edge order, branches included). `start`, `end` are `count by cols`.
struct EdgePieces {
  Points start, end;
  std::vector<automata::StateId> state;
  std::vector<std::size_t> initial;
  std::vector<std::vector<int>> word;
};

/// Evaluates the pieces of every node at `depth` (ifs::for_each_leaf with edge_end_functionals).
/// Throws InvalidInput before any work when the pieces would take more than `max_bytes`, and as
/// for_each_leaf.
EdgePieces edge_pieces(const Bcifs& system, std::span<const Points> nets, int depth,
                       std::size_t max_bytes = std::size_t{1} << 30);

}  // namespace cifs::ifs
