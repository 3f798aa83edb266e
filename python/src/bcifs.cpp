// SPDX-License-Identifier: MIT
// cifs Python bindings — BC-IFS (cifs.ifs): cells, boundary operators, constraints, the admissible
// space of free coefficients, perturbation, edge pieces; BC-IFS files (cifs.io).
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "arrays.hpp"
#include "bindings.hpp"
#include "cifs/errors.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/ifs/bcifs_surface.hpp"
#include "cifs/ifs/fractal_fit.hpp"
#include "cifs/ifs/junction.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/fit.hpp"

namespace ifs = cifs::ifs;

// TransitionRef ↔ (source, child): a tuple of two non-negative integers (source state, position among
// its out-edges).
namespace pybind11::detail {
template <>
struct type_caster<ifs::TransitionRef> {
  PYBIND11_TYPE_CASTER(ifs::TransitionRef, const_name("tuple[int, int]"));

  bool load(handle src, bool convert) {
    if (!src || !isinstance<sequence>(src) || isinstance<str>(src)) return false;
    const auto seq = reinterpret_borrow<sequence>(src);
    if (seq.size() != 2) return false;
    make_caster<long long> from, child;
    if (!from.load(seq[0], convert) || !child.load(seq[1], convert)) return false;
    const auto f = cast_op<long long>(from), c = cast_op<long long>(child);
    if (f < 0 || c < 0 || c > std::numeric_limits<int>::max())
      throw cifs::InvalidInput("transition (" + std::to_string(f) + ", " + std::to_string(c) +
                               "): state and child are non-negative");
    value = {static_cast<cifs::automata::StateId>(f), static_cast<int>(c)};
    return true;
  }

  static handle cast(const ifs::TransitionRef& ref, return_value_policy, handle) {
    return make_tuple(ref.from, ref.child).release();
  }
};
}  // namespace pybind11::detail

namespace cifs::python {
namespace {

/// The admissible space with the names of its unknowns (read from the system it was solved for).
struct Space {
  ifs::AdmissibleSpace space;
  std::vector<std::string> unknown_names;
};

/// Refuses a space that does not fit `system` (solved for another one), before C++ indexes with it.
void check_space(const ifs::Bcifs& system, const Space& s, const char* where) {
  for (const ifs::Coefficient& u : s.space.unknowns) {
    const auto& M = system.automaton.graph[ifs::transition_id(system.automaton, u.transition)].matrix;
    if (u.row >= M.rows() || u.col >= M.cols() || u.row < 0 || u.col < 0 ||
        ifs::coefficient_name(system.automaton, u) != s.unknown_names[&u - s.space.unknowns.data()])
      throw InvalidInput(std::string(where) + ": the admissible space was solved for another system");
  }
}

std::string factor_repr(const ifs::Factor& f) {
  if (f.kind == ifs::Factor::Kind::boundary) return "Factor(boundary=" + std::to_string(f.boundary) + ")";
  return "Factor(transition=(" + std::to_string(f.transition.from) + ", " +
         std::to_string(f.transition.child) + "))";
}

/// Constraints: boundary operators, factors, constraints, coefficients.
void bind_bcifs_constraints(py::module_& m) {
  py::class_<ifs::BoundaryOperator>(
      m, "BoundaryOperator",
      R"doc(A 0/1 selection: the net of cell `boundary` is rows `rows` of the net of `cell`.

BoundaryOperator(name, cell, boundary, rows): name per cell ("start", "end", "u0", …), cell and
boundary state ids, rows: one row index of the cell per point of the boundary cell. Checked when
the Bcifs is built.)doc")
      .def(py::init([](std::string name, automata::StateId cell, automata::StateId boundary,
                       std::vector<int> rows) {
             return ifs::BoundaryOperator{std::move(name), cell, boundary, std::move(rows)};
           }),
           py::arg("name"), py::arg("cell"), py::arg("boundary"), py::arg("rows"),
           "Builds a boundary operator (validated with the Bcifs that uses it).")
      .def_readonly("name", &ifs::BoundaryOperator::name, "Name, unique per cell (e.g. 'start').")
      .def_readonly("cell", &ifs::BoundaryOperator::cell, "State id of the cell.")
      .def_readonly("boundary", &ifs::BoundaryOperator::boundary, "State id of the boundary cell.")
      .def_readonly("rows", &ifs::BoundaryOperator::rows, "Rows of the cell's net selected (list of int).")
      .def("__repr__", [](const ifs::BoundaryOperator& b) {
        return "BoundaryOperator('" + b.name + "', cell=" + std::to_string(b.cell) +
               ", boundary=" + std::to_string(b.boundary) + ")";
      });

  py::class_<ifs::Factor> factor(m, "Factor", R"doc(One factor of a constraint's operator product.

Factor(boundary=i): the boundary operator i of the Bcifs (index into Bcifs.boundaries);
Factor(transition=(source, child)): the matrix of that transition.)doc");
  py::enum_<ifs::Factor::Kind> kind(factor, "Kind", "What a factor is: a boundary operator or a transition.");
  kind.value("boundary", ifs::Factor::Kind::boundary, "a boundary operator")
      .value("transition", ifs::Factor::Kind::transition, "a transition matrix");
  kind.attr("value").attr("__doc__") = "The integer value of the kind.";
  factor
      .def(py::init([](int boundary) {
             return ifs::Factor{ifs::Factor::Kind::boundary, non_negative(boundary, "Factor: boundary"), {}};
           }),
           py::kw_only(), py::arg("boundary"), "A boundary-operator factor (index into Bcifs.boundaries).")
      .def(py::init([](ifs::TransitionRef transition) {
             return ifs::Factor{ifs::Factor::Kind::transition, 0, transition};
           }),
           py::kw_only(), py::arg("transition"), "A transition factor, transition = (source state, child).")
      .def_readonly("kind", &ifs::Factor::kind, "Factor.Kind.boundary or Factor.Kind.transition.")
      .def_readonly("boundary", &ifs::Factor::boundary, "Index of the boundary operator (boundary factors).")
      .def_readonly("transition", &ifs::Factor::transition,
                    "(source, child) of the transition (transition factors).")
      .def("__repr__", &factor_repr);

  py::class_<ifs::Constraint>(
      m, "Constraint", R"doc(A linear constraint `left == right`: each side a product F_0·F_1⋯F_k of Factors.

Constraint(name, left, right): F_k acts first on a net; both sides map the same source cell to the
same target cell and hold at most one free transition each (checked by the Bcifs).)doc")
      .def(py::init([](std::string name, std::vector<ifs::Factor> left, std::vector<ifs::Factor> right) {
             return ifs::Constraint{std::move(name), std::move(left), std::move(right)};
           }),
           py::arg("name"), py::arg("left"), py::arg("right"),
           "Builds a constraint from two lists of Factors.")
      .def_readonly("name", &ifs::Constraint::name, "Name of the constraint (e.g. 'junction').")
      .def_readonly("left", &ifs::Constraint::left, "Factors of the left side (list of Factor).")
      .def_readonly("right", &ifs::Constraint::right, "Factors of the right side (list of Factor).")
      .def("__repr__", [](const ifs::Constraint& c) {
        return "Constraint('" + c.name + "', " + std::to_string(c.left.size()) + " = " +
               std::to_string(c.right.size()) + " factors)";
      });

  py::class_<ifs::Coefficient>(m, "Coefficient", "An entry (row, col) of the matrix of a free transition.")
      .def(py::init([](ifs::TransitionRef transition, int row, int col) {
             return ifs::Coefficient{transition, non_negative(row, "Coefficient: row"),
                                     non_negative(col, "Coefficient: col")};
           }),
           py::arg("transition"), py::arg("row"), py::arg("col"),
           "Entry (row, col) of transition (source, child).")
      .def_readonly("transition", &ifs::Coefficient::transition, "(source, child) of the transition.")
      .def_readonly("row", &ifs::Coefficient::row, "Row of the entry.")
      .def_readonly("col", &ifs::Coefficient::col, "Column of the entry.")
      .def("__repr__", [](const ifs::Coefficient& c) {
        return "Coefficient((" + std::to_string(c.transition.from) + ", " +
               std::to_string(c.transition.child) + "), " + std::to_string(c.row) + ", " +
               std::to_string(c.col) + ")";
      });
}

/// The system: Bcifs, names, selections, residuals, admissibility.
void bind_bcifs_system(py::module_& m) {
  py::class_<ifs::Bcifs>(
      m, "Bcifs",
      R"doc(A boundary controlled IFS (docs/bcifs.md): cells, boundary operators, constraints, free transitions.

Bcifs(automaton, dimension, boundaries, constraints, free): automaton: cifs.automata.Automaton whose
states are the cells; dimension: one of 0 (vertex), 1 (edge), 2 (face) per state; boundaries: list
of BoundaryOperator; constraints: list of Constraint; free: list of (source, child) transitions
whose matrices are unknowns. Raises cifs.InvalidInput (ifs::validate) when the structure is
inconsistent: wrong dimension count, bad rows, factors that do not chain, two free transitions on
one side, a transition listed free twice …)doc")
      .def(py::init([](automata::Automaton automaton, std::vector<int> dimension,
                       std::vector<ifs::BoundaryOperator> boundaries,
                       std::vector<ifs::Constraint> constraints, std::vector<ifs::TransitionRef> free) {
             ifs::Bcifs system{std::move(automaton), std::move(dimension), std::move(boundaries),
                               std::move(constraints), std::move(free)};
             ifs::validate(system);
             return system;
           }),
           py::arg("automaton"), py::arg("dimension"), py::arg("boundaries"), py::arg("constraints"),
           py::arg("free").noconvert(), "Builds and validates a BC-IFS (see the class docstring).")
      .def_property_readonly(
          "automaton", [](const ifs::Bcifs& s) { return s.automaton; },
          "The automaton (a copy, so that the validated system cannot change): cells and transition "
          "matrices.")
      .def_readonly("dimension", &ifs::Bcifs::dimension, "Dimension of each cell, indexed by state id.")
      .def_readonly("boundaries", &ifs::Bcifs::boundaries,
                    "The boundary operators (list of BoundaryOperator).")
      .def_readonly("constraints", &ifs::Bcifs::constraints, "The constraints (list of Constraint).")
      .def_readonly("free", &ifs::Bcifs::free, "The free transitions, as (source, child) tuples.")
      .def("__repr__", [](const ifs::Bcifs& s) {
        return "Bcifs(cells=" + std::to_string(num_vertices(s.automaton.graph)) +
               ", boundaries=" + std::to_string(s.boundaries.size()) +
               ", constraints=" + std::to_string(s.constraints.size()) +
               ", free=" + std::to_string(s.free.size()) + ")";
      });

  m.def("transition_name", &ifs::transition_name, py::arg("automaton"), py::arg("transition"),
        "'E/G': the source state's name (or 's<id>'), '/', the label of transition (source, child). Raises "
        "cifs.InvalidInput when the transition does not exist.");
  m.def(
      "coefficient_name", &ifs::coefficient_name, py::arg("automaton"), py::arg("coefficient"),
      "'E/G[1,2]': the name of a Coefficient. Raises cifs.InvalidInput when its transition does not exist.");
  m.def(
      "selection_matrix",
      [](const ifs::Bcifs& system, int boundary) {
        if (boundary < 0 || static_cast<std::size_t>(boundary) >= system.boundaries.size())
          throw InvalidInput("selection_matrix: boundary " + std::to_string(boundary) + " does not exist (" +
                             std::to_string(system.boundaries.size()) + " boundary operators)");
        return ifs::selection_matrix(system, boundary);
      },
      py::arg("system"), py::arg("boundary"),
      "B of boundary operator `boundary` (index into system.boundaries): float64 (size(boundary), "
      "size(cell)), "
      "B[i, rows[i]] = 1. Raises cifs.InvalidInput for an index out of range.");
  m.def("constraint_residuals", &ifs::constraint_residuals, py::arg("system"),
        py::call_guard<py::gil_scoped_release>(),
        R"doc(Residual of each constraint and of each free matrix's row sums: list of (name, value).

Per constraint max |left − right| / max(1, largest |entry|); per free matrix ("<transition> row
sums") the largest |row sum − 1|.)doc");
  m.def("check_admissible", &ifs::check_admissible, py::arg("system"), py::arg("tolerance") = 1e-12,
        py::call_guard<py::gil_scoped_release>(),
        "Raises cifs.InvalidInput naming the worst constraint when a residual exceeds `tolerance`.");
}

/// Systems of NURBS curves and surfaces.
void bind_bcifs_builders(py::module_& m) {
  m.def(
      "curve_bcifs",
      [](const nurbs::Curve& curve, bool free_vertices) {
        return ifs::curve_bcifs(curve, ifs::CurveBcifsOptions{.free_vertices = free_vertices});
      },
      py::arg("curve"), py::kw_only(), py::arg("free_vertices").noconvert() = false,
      py::call_guard<py::gil_scoped_release>(),
      R"doc(The automatic BC-IFS of a NURBS curve (cifs.nurbs.Curve; docs/bcifs.md).

free_vertices: False keeps the vertex operators at the knots (the knot points stay on the curve),
True frees every vertex operator. The NURBS matrices satisfy every constraint.)doc");
  m.def(
      "curve_bcifs",
      [](const nurbs::KnotAutomaton& knots, bool closed, bool free_vertices) {
        return ifs::curve_bcifs(knots, closed, ifs::CurveBcifsOptions{.free_vertices = free_vertices});
      },
      py::arg("knots"), py::arg("closed").noconvert(), py::kw_only(),
      py::arg("free_vertices").noconvert() = false, py::call_guard<py::gil_scoped_release>(),
      "The same from a curve's knot automaton (cifs.automata.knot_automaton); `closed` joins the last "
      "segment to "
      "the first. Raises cifs.InvalidInput for states that are not knot-doubling states of one degree ≥ 1.");
  m.def(
      "surface_bcifs",
      [](const nurbs::Surface& surface, bool free_knot_lines) {
        return ifs::surface_bcifs(surface, ifs::SurfaceBcifsOptions{.free_knot_lines = free_knot_lines});
      },
      py::arg("surface"), py::kw_only(), py::arg("free_knot_lines").noconvert() = false,
      py::call_guard<py::gil_scoped_release>(),
      R"doc(The automatic BC-IFS of a NURBS surface (cifs.nurbs.Surface): products of the u and v curve systems.

free_knot_lines: False keeps the cells on knot lines (patch boundaries stay NURBS curves), True
frees every operator.)doc");
  m.def(
      "surface_bcifs",
      [](const nurbs::TensorAutomaton& automaton, bool free_knot_lines) {
        return ifs::surface_bcifs(automaton, ifs::SurfaceBcifsOptions{.free_knot_lines = free_knot_lines});
      },
      py::arg("automaton"), py::kw_only(), py::arg("free_knot_lines").noconvert() = false,
      py::call_guard<py::gil_scoped_release>(),
      "The same from a cifs.automata.TensorAutomaton (cifs.automata.tensor_automaton).");
}

/// The admissible space and the free coefficients.
void bind_bcifs_space(py::module_& m) {
  py::class_<Space>(m, "AdmissibleSpace", R"doc(The admissible matrices: every unknown entry is x = x0 + K·c.

c holds the values of the free coefficients (unknowns[free[j]]); K has a unit row at each free
index. Result of admissible_space.)doc")
      .def_property_readonly(
          "unknowns", [](const Space& s) { return s.space.unknowns; },
          "Every entry of every free matrix (list of Coefficient): free transitions in order, entries "
          "row-major.")
      .def_readonly("unknown_names", &Space::unknown_names, "Names of the unknowns ('E/G[1,2]'), same order.")
      .def_property_readonly(
          "free", [](const Space& s) { return vector_array(s.space.free); },
          "Indices into unknowns of the free coefficients (increasing integer array).")
      .def_property_readonly(
          "x0", [](const Space& s) { return Eigen::VectorXd(s.space.x0); },
          "float64 array (len(unknowns),): the particular solution.")
      .def_property_readonly(
          "K",
          [](const Space& s) {
            std::vector<long long> rows, cols;
            std::vector<double> values;
            for (int k = 0; k < s.space.K.outerSize(); ++k)
              for (Eigen::SparseMatrix<double>::InnerIterator it(s.space.K, k); it; ++it) {
                rows.push_back(it.row());
                cols.push_back(it.col());
                values.push_back(it.value());
              }
            return py::make_tuple(vector_array(rows), vector_array(cols), vector_array(values));
          },
          "K in COO form: a tuple (row, col, value) of arrays; K has shape `shape`.")
      .def_property_readonly(
          "shape", [](const Space& s) { return py::make_tuple(s.space.K.rows(), s.space.K.cols()); },
          "Shape of K: (len(unknowns), len(free)).")
      .def(
          "dense", [](const Space& s) { return Eigen::MatrixXd(s.space.K); },
          "K as a dense float64 array (len(unknowns), len(free)).")
      .def_property_readonly(
          "components", [](const Space& s) { return s.space.components; },
          "Number of connected components of the unknown/equation graph (each solved separately).")
      .def("__repr__", [](const Space& s) {
        return "AdmissibleSpace(unknowns=" + std::to_string(s.space.unknowns.size()) +
               ", free=" + std::to_string(s.space.free.size()) +
               ", components=" + std::to_string(s.space.components) + ")";
      });

  m.def(
      "admissible_space",
      [](const ifs::Bcifs& system, double threshold) {
        Space s{ifs::admissible_space(system, ifs::SolveOptions{.threshold = threshold}), {}};
        for (const ifs::Coefficient& u : s.space.unknowns)
          s.unknown_names.push_back(ifs::coefficient_name(system.automaton, u));
        return s;
      },
      py::arg("system"), py::kw_only(), py::arg("threshold") = ifs::SolveOptions{}.threshold,
      py::call_guard<py::gil_scoped_release>(),
      R"doc(Solves the constraints and row sums for the free matrices: the AdmissibleSpace.

threshold: relative rank threshold of the pivoted QR, in [0, 1). Raises cifs.InvalidInput for another
threshold and when the constraints
have no solution (naming the constraints of the inconsistent component and the residual).)doc");
  m.def(
      "free_names",
      [](const ifs::Bcifs& system, const Space& space) {
        check_space(system, space, "free_names");
        return ifs::free_names(system, space.space);
      },
      py::arg("system"), py::arg("space"),
      "Names of the free coefficients ('E/G[1,2]'), in the order of space.free.");
  m.def(
      "free_values",
      [](const ifs::Bcifs& system, const Space& space) {
        check_space(system, space, "free_values");
        return ifs::free_values(system, space.space);
      },
      py::arg("system"), py::arg("space"),
      "The current values of the free coefficients, read from the matrices: float64 array "
      "(len(space.free),).");
  m.def(
      "with_free_values",
      [](const ifs::Bcifs& system, const Space& space, const Eigen::VectorXd& c) {
        check_space(system, space, "with_free_values");
        return ifs::with_free_values(system, space.space, c);
      },
      py::arg("system"), py::arg("space"), py::arg("c"),
      "The system with every free matrix set to x0 + K·c (c: one value per free coefficient). Raises "
      "cifs.InvalidInput for a wrong number of values or a space solved for another system.");
}

/// Perturbation and edge pieces.
void bind_bcifs_perturbation(py::module_& m) {
  py::class_<ifs::Perturbation>(m, "Perturbation",
                                "Result of perturb: the perturbed system and how it was made.")
      .def_readonly("system", &ifs::Perturbation::system, "The perturbed Bcifs.")
      .def_readonly("values", &ifs::Perturbation::values,
                    "Every free coefficient and the value used: list of (name, value), in free order.")
      .def_readonly("residual", &ifs::Perturbation::residual,
                    "Largest constraint residual of the result (≤ 1e-12).")
      .def_readonly("contraction", &ifs::Perturbation::contraction,
                    "The contractivity witness of the result (cifs.ifs.Contraction).")
      .def("__repr__", [](const ifs::Perturbation& p) {
        return "Perturbation(values=" + std::to_string(p.values.size()) +
               ", residual=" + py::repr(py::float_(p.residual)).cast<std::string>() + ")";
      });

  m.def(
      "perturb",
      [](const ifs::Bcifs& system, double amplitude, std::uint64_t seed,
         const std::optional<std::map<std::string, double>>& values, double threshold, int max_length,
         bool tighten) {
        if (max_length < 1 || max_length > 16)
          throw InvalidInput("perturb: max_length is " + std::to_string(max_length) + ", must be in [1, 16]");
        ifs::PerturbOptions options;
        options.amplitude = amplitude;
        options.seed = seed;
        options.values = values.value_or(std::map<std::string, double>{});
        options.solve.threshold = threshold;
        options.contraction = ifs::ContractionOptions{.max_length = max_length, .tighten = tighten};
        return ifs::perturb(system, options);
      },
      py::arg("system"), py::kw_only(), py::arg("amplitude") = 0.0, py::arg("seed") = 1,
      py::arg("values") = py::none(), py::arg("threshold") = ifs::SolveOptions{}.threshold,
      py::arg("max_length") = ifs::ContractionOptions{}.max_length,
      py::arg("tighten").noconvert() = ifs::ContractionOptions{}.tighten,
      py::call_guard<py::gil_scoped_release>(),
      R"doc(Perturbs the free coefficients, solves the dependent ones and checks the result.

amplitude: each free coefficient gets current value + uniform in [−amplitude, amplitude], drawn
from the project's xoshiro256** seeded by `seed` (same seed, same values as the CLI's experiments);
values: dict name → value setting free coefficients instead of the draw; threshold: rank threshold
of the solver; max_length (1 … 16), tighten: options of the contraction check. Returns a
Perturbation. Raises cifs.InvalidInput for a negative or non-finite amplitude, unknown or dependent
names in values, residuals above 1e-12, or a non-contractive result.)doc");

  m.def("edge_end_functionals", &ifs::edge_end_functionals, py::arg("system"),
        R"doc(Start and end functionals of every reachable edge cell (cifs.ifs.EndFunctionals).

ℓ_V·B with B the cell's "start" (or "end") boundary operator and ℓ_V the fixed point of the vertex
cell it selects. Raises cifs.InvalidInput when an edge cell lacks a "start" or "end" boundary.)doc");

  py::class_<ifs::EdgePieces>(m, "EdgePieces",
                              "The pieces of an edge system at a depth (result of edge_pieces).")
      .def_readonly("start", &ifs::EdgePieces::start, "Start point of each piece: float64 (count, cols).")
      .def_readonly("end", &ifs::EdgePieces::end, "End point of each piece: float64 (count, cols).")
      .def_property_readonly(
          "state", [](const ifs::EdgePieces& p) { return vector_array(p.state); },
          "Cell (state id) of each piece: integer array (count,).")
      .def_property_readonly(
          "initial", [](const ifs::EdgePieces& p) { return vector_array(p.initial); },
          "Initial entry each piece descends from: integer array (count,).")
      .def_readonly("word", &ifs::EdgePieces::word,
                    "Child indices from the initial entry (list of lists of int).")
      .def("__repr__", [](const ifs::EdgePieces& p) {
        return "EdgePieces(count=" + std::to_string(p.start.rows()) + ")";
      });

  m.def(
      "edge_pieces",
      [](const ifs::Bcifs& system, const std::vector<Points>& nets, int depth) {
        return ifs::edge_pieces(system, nets, depth);
      },
      py::arg("system"), py::arg("nets"), py::arg("depth"), py::call_guard<py::gil_scoped_release>(),
      R"doc(Start and end points of every node of an edge system at `depth` (initial entries in order, children in order).

nets: one float64 array (size(state), cols) per initial entry. Returns EdgePieces. Raises
cifs.InvalidInput for nets that do not fit the entries, a negative depth, more than 2^26 pieces,
or a piece in a cell that is not an edge.)doc");
}

/// The fractal inverse problem (docs/fitting.md, "Fractal curves").
void bind_fractal_fit(py::module_& m) {
  py::class_<ifs::VertexHolder>(m, "VertexHolder",
                                "Pointwise Hölder exponent at the points of one vertex class.")
      .def_readonly("cell", &ifs::VertexHolder::cell, "The vertex cell's name.")
      .def_readonly("exponent", &ifs::VertexHolder::exponent,
                    "−log2 |λ|/k of its cycle product, capped at 1.")
      .def("__repr__", [](const ifs::VertexHolder& h) {
        return "VertexHolder(" + h.cell + ", " + py::repr(py::float_(h.exponent)).cast<std::string>() + ")";
      });
  py::class_<ifs::FractalFit>(m, "FractalFit",
                              "Result of fit_fractal: the fitted BC-IFS, its nets and how well it fits.")
      .def_readonly("system", &ifs::FractalFit::system, "The fitted cifs.ifs.Bcifs (free coefficients set).")
      .def_readonly("nets", &ifs::FractalFit::nets, "Its control nets, one float64 array per segment.")
      .def_readonly("control_points", &ifs::FractalFit::control_points,
                    "The control points the nets are made of.")
      .def_readonly("smooth", &ifs::FractalFit::smooth, "The least-squares uniform B-spline it started from.")
      .def_readonly("parameters", &ifs::FractalFit::parameters, "The data parameters in [0, 1].")
      .def_readonly("coefficients", &ifs::FractalFit::coefficients, "Every free coefficient and its value.")
      .def_readonly("rms", &ifs::FractalFit::rms, "Root mean square of |A(u_k) − Q_k| over the data.")
      .def_readonly("max_distance", &ifs::FractalFit::max_distance, "Largest |A(u_k) − Q_k|.")
      .def_readonly("smooth_rms", &ifs::FractalFit::smooth_rms, "The same for the smooth start.")
      .def_readonly("smooth_max_distance", &ifs::FractalFit::smooth_max_distance,
                    "The same for the smooth start.")
      .def_readonly("iterations", &ifs::FractalFit::iterations,
                    "Levenberg–Marquardt iterations run, all rounds.")
      .def_readonly("reparametrizations", &ifs::FractalFit::reparametrizations, "Parameter corrections kept.")
      .def_readonly("contraction", &ifs::FractalFit::contraction,
                    "The fitted system's contractivity witness.")
      .def_readonly("holder_bound", &ifs::FractalFit::holder_bound,
                    "Proven lower bound on the fitted curve's Hölder exponent (−log2(δ_8)/8).")
      .def_readonly("holder", &ifs::FractalFit::holder,
                    "Hölder exponent per vertex class (list of VertexHolder).")
      .def_readonly("dimension", &ifs::FractalFit::dimension, "Box-counting dimension (NaN: not measured).")
      .def_readonly("dimension_uncertainty", &ifs::FractalFit::dimension_uncertainty, "Its uncertainty.")
      .def_readonly("dimension_note", &ifs::FractalFit::dimension_note, "Why no dimension, when none.")
      .def("__repr__", [](const ifs::FractalFit& f) {
        return "FractalFit(rms=" + py::repr(py::float_(f.rms)).cast<std::string>() +
               ", smooth_rms=" + py::repr(py::float_(f.smooth_rms)).cast<std::string>() +
               ", coefficients=" + std::to_string(f.coefficients.size()) + ")";
      });
  m.def(
      "fit_fractal",
      [](const py::object& points, Eigen::Index control_points, int degree,
         const std::string& parametrization, bool closed, bool free_vertices, int depth, int max_iterations,
         double min_holder, int reparametrizations, std::size_t dimension_points) {
        ifs::FractalFitOptions o;
        o.degree = degree;
        o.control_points = control_points;
        o.parametrization = nurbs::parametrization_named(parametrization);
        o.closed = closed;
        o.free_vertices = free_vertices;
        o.depth = depth;
        o.max_iterations = max_iterations;
        o.min_holder = min_holder;
        o.reparametrizations = reparametrizations;
        o.dimension_points = dimension_points;
        const Points P = points_from(points, "points");
        const py::gil_scoped_release release;
        return ifs::fit_fractal(P, o);
      },
      py::arg("points"), py::kw_only(), py::arg("control_points"), py::arg("degree") = 3,
      py::arg("parametrization") = "chord_length", py::arg("closed").noconvert() = false,
      py::arg("free_vertices").noconvert() = true, py::arg("depth") = ifs::FractalFitOptions{}.depth,
      py::arg("max_iterations") = ifs::FractalFitOptions{}.max_iterations,
      py::arg("min_holder") = ifs::FractalFitOptions{}.min_holder,
      py::arg("reparametrizations") = ifs::FractalFitOptions{}.reparametrizations,
      py::arg("dimension_points") = ifs::FractalFitOptions{}.dimension_points,
      R"doc(Fits a fractal curve to points (n, dim): the BC-IFS of the uniform B-spline of `control_points`
control points whose free coefficients and control points minimise Σ|A(u_k) − Q_k|² (Guérin & Tosan 2005).

Starts from the least-squares B-spline; Levenberg–Marquardt with exact derivatives, the control points
projected out. free_vertices: the knot points' operators are free too. depth: data parameters rounded to
2^-depth of a segment. min_holder: every step keeps the curve provably Hölder of at least this exponent
(FractalFit.holder_bound; default 0.25, or the start's when lower). reparametrizations: rounds of
parameter correction (each inner point moved to the closest attractor point between its neighbours').
dimension_points: box-counting sample (0: none). Returns a FractalFit; write it with
cifs.io.write(path, fit.file). Raises cifs.InvalidInput for bad input.)doc");
}

/// Uniform curves, products and junctions.
void bind_bcifs_joining(py::module_& m) {
  m.def(
      "uniform_curve_bcifs",
      [](const Eigen::MatrixXd& S0, const Eigen::MatrixXd& S1, int pieces, int layer, bool free) {
        return ifs::uniform_curve_bcifs(S0, S1, {.pieces = pieces, .layer = layer, .free = free});
      },
      py::arg("S0"), py::arg("S1"), py::arg("pieces") = 1, py::arg("layer") = 0,
      py::arg("free").noconvert() = false,
      R"doc(BC-IFS of an open curve of a uniform scheme from its N by N IFS matrices (docs/junctions.md).

Edge cells "e" (interior) and "a0" … (a junction layer of `layer` pieces at the start, free), vertex
cells "v0" (the start), "w1" …, "m"; boundaries "start" (rows 0 … N−2) and "end" (rows 1 … N−1).)doc");
  m.def(
      "product_bcifs",
      [](const ifs::Bcifs& u, const ifs::Bcifs& v, bool free_when_either) {
        return ifs::product_bcifs(u, v, {.free_when_either = free_when_either});
      },
      py::arg("u"), py::arg("v"), py::arg("free_when_either").noconvert() = false,
      "Tensor product of two curve systems (faces, edges, corners; patches u-major).");

  py::class_<ifs::Junction>(m, "Junction", "Two BC-IFS joined along shared boundary cells (result of join).")
      .def_readonly("system", &ifs::Junction::system, "The joined cifs.ifs.Bcifs (A's entries, then B's).")
      .def_readonly("nets", &ifs::Junction::nets, "A's nets, then B's with the glued rows taken from A.")
      .def_readonly("shared", &ifs::Junction::shared, "Shared cells: list of (A state, B state).")
      .def_readonly("junction_constraints", &ifs::Junction::junction_constraints,
                    "Names of B's constraints that read a shared cell.")
      .def_readonly("free", &ifs::Junction::free, "Number of free coefficients of the joined system.")
      .def_readonly("residual", &ifs::Junction::residual, "Largest constraint residual after the projection.")
      .def("__repr__", [](const ifs::Junction& j) {
        return "Junction(shared=" + std::to_string(j.shared.size()) + ", free=" + std::to_string(j.free) +
               ")";
      });
  m.def(
      "join",
      [](const ifs::Bcifs& a, const std::vector<Points>& nets_a, const ifs::Bcifs& b,
         const std::vector<Points>& nets_b,
         const std::vector<std::tuple<std::size_t, std::string, std::size_t, std::string>>& glue,
         bool free_a) {
        std::vector<ifs::Glue> g;
        g.reserve(glue.size());
        for (const auto& [ea, ba, eb, bb] : glue) g.push_back({ea, ba, eb, bb});
        ifs::JoinOptions options;
        options.free_a = free_a;
        return ifs::join(a, nets_a, b, nets_b, g, options);
      },
      py::arg("a"), py::arg("nets_a"), py::arg("b"), py::arg("nets_b"), py::arg("glue"),
      py::arg("free_a").noconvert() = false,
      R"doc(Joins B to A along shared boundary cells (docs/junctions.md).

glue: list of (A entry, A boundary name, B entry, B boundary name), e.g. [(2, "end", 0, "start")].
The shared cells keep A's operators; B's constraints that meet them are solved again and the free
matrices projected onto the admissible space. Returns a Junction. Raises cifs.InvalidInput when
glued cells differ (size, dimension, children, boundaries) or the constraints have no solution.)doc");
}

}  // namespace

void bind_bcifs(py::module_& m) {
  bind_bcifs_constraints(m);
  bind_bcifs_system(m);
  bind_bcifs_builders(m);
  bind_bcifs_space(m);
  bind_bcifs_perturbation(m);
  bind_fractal_fit(m);
  bind_bcifs_joining(m);
}

void bind_bcifs_io(py::module_& m) {
  py::class_<io::BcifsFile>(m, "BcifsFile", "A BC-IFS and the control nets of its initial entries.")
      .def_readonly("system", &io::BcifsFile::system, "The cifs.ifs.Bcifs.")
      .def_readonly(
          "nets", &io::BcifsFile::nets,
          "One float64 array (size(state), cols) per initial entry (empty list when the file gives none).")
      .def("__repr__", [](const io::BcifsFile& f) {
        return "BcifsFile(cells=" + std::to_string(num_vertices(f.system.automaton.graph)) +
               ", nets=" + std::to_string(f.nets.size()) + ")";
      });
  // FractalFit.file is added here, once BcifsFile exists: its signature (docstring, stubs) names the
  // Python type, not `cifs::io::BcifsFile`.
  py::reinterpret_borrow<py::class_<ifs::FractalFit>>(py::type::of<ifs::FractalFit>())
      .def_property_readonly(
          "file",
          [](const ifs::FractalFit& f) {
            return io::BcifsFile{f.system, f.nets};
          },
          "System and nets as a cifs.io.BcifsFile: cifs.io.write('fit.json', fit.file) writes a BC-IFS "
          "file.");
  m.def("read_bcifs", &io::read_bcifs, py::arg("path"),
        "Reads a BC-IFS file (docs/formats.md) into a BcifsFile. Raises cifs.IoError (unreadable file, JSON "
        "syntax) or cifs.InvalidInput (content, with its JSON path).");
  m.def("parse_bcifs_json", &io::parse_bcifs_json, py::arg("text"), py::arg("where") = "<string>",
        "Parses BC-IFS JSON text; `where` prefixes error messages (a file name). Raises cifs.IoError or "
        "cifs.InvalidInput.");
  m.def(
      "to_json",
      [](const ifs::Bcifs& system, const std::vector<Points>& nets) { return io::to_json(system, nets); },
      py::arg("system"), py::arg("nets") = std::vector<Points>{},
      "BC-IFS JSON text of a cifs.ifs.Bcifs; nets: none, or one array per initial entry. Cell names must be "
      "free of "
      "'.' and '/'.");
}

}  // namespace cifs::python
