// SPDX-License-Identifier: MIT
// cifs Python bindings — cifs.automata: hand-made and knot-doubling automata, tensor products.
// Python's Automaton is nurbs::KnotAutomaton: a generic automaton and its knot data, empty for
// hand-made automata (bindings.hpp reads a C++ automata::Automaton from it).
#include <cstdint>
#include <iterator>
#include <optional>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "cifs/automata/automaton.hpp"
#include "cifs/automata/tensor.hpp"
#include "cifs/errors.hpp"
#include "cifs/io/dot.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/svg.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"

namespace cifs::python {

namespace {

using automata::Automaton;
using automata::StateId;
using nurbs::KnotAutomaton;

/// A state as Python sees it: the generic state and its window (knot data).
struct StateView {
  int size = 0;
  nurbs::Window window;
  bool recurrent = false;
  std::string name;
};

/// An initial entry as Python sees it: the generic entry and its knot interval and span.
struct InitialView {
  int segment = 0;
  StateId state = 0;
  double start = 0, end = 0;
  int span = -1;
};

StateView state_view(const KnotAutomaton& k, StateId s) {
  const automata::State& st = k.automaton.graph[s];
  return {.size = st.size,
          .window = s < k.windows.size() ? k.windows[s] : nurbs::Window{},
          .recurrent = st.recurrent,
          .name = st.name};
}

std::vector<InitialView> initial_views(const KnotAutomaton& k) {
  std::vector<InitialView> out;
  for (std::size_t i = 0; i < k.automaton.initial.size(); ++i) {
    const automata::Initial& init = k.automaton.initial[i];
    const nurbs::KnotInterval interval = i < k.intervals.size() ? k.intervals[i] : nurbs::KnotInterval{};
    out.push_back({.segment = init.segment,
                   .state = init.state,
                   .start = interval.start,
                   .end = interval.end,
                   .span = interval.span});
  }
  return out;
}

/// One transition as Python sees it: the edge with its endpoints and its place among the out-edges.
struct TransitionView {
  StateId source = 0;
  int child = 0;
  StateId target = 0;
  std::string label;
  Eigen::MatrixXd matrix;
};

/// `id` as a state of `a`; ids come from Python ints, so negative ones are refused here too.
StateId state_id(const Automaton& a, std::int64_t id, const std::string& where) {
  if (id < 0 || static_cast<std::uint64_t>(id) >= num_vertices(a.graph))
    throw InvalidInput(where + ": state " + std::to_string(id) + " does not exist (the automaton has " +
                       std::to_string(num_vertices(a.graph)) + " states)");
  return static_cast<StateId>(id);
}

automata::TransitionId out_edge(const Automaton& a, StateId source, std::int64_t child,
                                const std::string& where) {
  const auto degree = out_degree(source, a.graph);
  if (child < 0 || static_cast<std::uint64_t>(child) >= degree)
    throw InvalidInput(where + ": child " + std::to_string(child) + " but state " + std::to_string(source) +
                       " has " + std::to_string(degree) + " children");
  return *std::next(out_edges(source, a.graph).first, static_cast<std::ptrdiff_t>(child));
}

/// A transition `source → target` carries a finite `size(target) by size(source)` matrix.
void check_matrix(const Automaton& a, StateId source, StateId target, const Eigen::MatrixXd& M,
                  const std::string& where) {
  const int rows = a.graph[target].size, cols = a.graph[source].size;
  if (M.rows() != rows || M.cols() != cols)
    throw InvalidInput(where + ": matrix is " + std::to_string(M.rows()) + " by " + std::to_string(M.cols()) +
                       ", expected " + std::to_string(rows) + " by " + std::to_string(cols) +
                       " (to.size by from.size)");
  if (!M.allFinite()) throw InvalidInput(where + ": matrix has a non-finite entry");
}

std::vector<TransitionView> transitions(const Automaton& a) {
  std::vector<TransitionView> out;
  for (StateId s = 0; s < num_vertices(a.graph); ++s) {
    int child = 0;
    for (auto [b, e] = out_edges(s, a.graph); b != e; ++b, ++child)
      out.push_back({s, child, target(*b, a.graph), a.graph[*b].label, a.graph[*b].matrix});
  }
  return out;
}

std::string state_repr(const StateView& s) {
  return "State(size=" + std::to_string(s.size) + ", window=" + std::to_string(s.window.size()) +
         " values, recurrent=" + (s.recurrent ? "True" : "False") + ", name='" + s.name + "')";
}

/// States, initial entries and transitions as Python reads them (copies).
void bind_automata_views(py::module_& m) {
  py::class_<StateView>(m, "State", "A state of an automaton: the control nets it holds have `size` points.")
      .def_readonly("size", &StateView::size, "Number of points of the nets of this state.")
      .def_readonly("window", &StateView::window,
                    "Knot-doubling states: the inter-knot window normalised so that its centre is 1 (list of "
                    "float, the state's key; C++ KnotAutomaton::windows); empty for hand-made states.")
      .def_readonly(
          "recurrent", &StateView::recurrent,
          "True when the state occurs at arbitrarily deep levels (on a cycle or reachable from one); "
          "set by mark_recurrent.")
      .def_readonly("name", &StateView::name,
                    "Name of the state (may be empty), used in messages and drawings.")
      .def("__repr__", &state_repr);

  py::class_<InitialView>(m, "Initial",
                          "Where a piece of the shape starts: an initial entry of an automaton.")
      .def_readonly("segment", &InitialView::segment,
                    "Index of the segment (or patch) this entry stands for.")
      .def_readonly("state", &InitialView::state, "Id of the state the piece starts in.")
      .def_readonly(
          "start", &InitialView::start,
          "Knot-doubling automata: start of the segment's knot interval (C++ KnotAutomaton::intervals).")
      .def_readonly("end", &InitialView::end, "Knot-doubling automata: end of the segment's knot interval.")
      .def_readonly("span", &InitialView::span,
                    "Knot-doubling automata: the segment's span in the curve's knot vector (-1: unset).")
      .def("__repr__", [](const InitialView& i) {
        return "Initial(segment=" + std::to_string(i.segment) + ", state=" + std::to_string(i.state) +
               ", start=" + py::repr(py::float_(i.start)).cast<std::string>() +
               ", end=" + py::repr(py::float_(i.end)).cast<std::string>() +
               ", span=" + std::to_string(i.span) + ")";
      });

  py::class_<TransitionView>(m, "Transition",
                             "A transition of an automaton: the child net is `matrix @ net` of the source "
                             "(`size(target) by size(source)`, rows summing to 1).")
      .def_readonly("source", &TransitionView::source, "Id of the state the transition leaves (C++ `from`).")
      .def_readonly("child", &TransitionView::child,
                    "Index of the transition among the out-edges of `source`.")
      .def_readonly("target", &TransitionView::target, "Id of the state the transition enters (C++ `to`).")
      .def_readonly("label", &TransitionView::label, "Label (\"G\", \"D\" for knot doubling; anything else).")
      .def_property_readonly(
          "matrix", [](const TransitionView& t) { return t.matrix; },
          "The matrix, float64 `(size(target), size(source))` (a copy).")
      .def("__repr__", [](const TransitionView& t) {
        return "Transition(" + std::to_string(t.source) + " -> " + std::to_string(t.target) + ", child " +
               std::to_string(t.child) + ", label='" + t.label + "', " + std::to_string(t.matrix.rows()) +
               "x" + std::to_string(t.matrix.cols()) + ")";
      });
}

/// Building: states, transitions and their matrices.
void bind_automaton_building(py::class_<KnotAutomaton>& automaton) {
  automaton.def(py::init<>(), "An empty automaton: no state, no transition, no initial entry.")
      .def(
          "add_state",
          [](KnotAutomaton& k, int size, const std::string& name) {
            if (size < 1)
              throw InvalidInput("add_state: size is " + std::to_string(size) +
                                 ", a state holds at least 1 point");
            k.windows.resize(num_vertices(k.automaton.graph) + 1);
            return add_vertex(automata::State{.size = size, .recurrent = false, .name = name},
                              k.automaton.graph);
          },
          py::arg("size"), py::arg("name") = "",
          "Adds a state whose nets have `size` (≥ 1) points; returns its id (0, 1, …).\n\n"
          "Raises InvalidInput for a size < 1.")
      .def(
          "add_transition",
          [](KnotAutomaton& k, std::int64_t source, std::int64_t target, const Eigen::MatrixXd& matrix,
             const std::string& label) {
            Automaton& a = k.automaton;
            const StateId s = state_id(a, source, "add_transition");
            const StateId t = state_id(a, target, "add_transition");
            check_matrix(a, s, t, matrix, "add_transition " + std::to_string(s) + " -> " + std::to_string(t));
            const auto child = out_degree(s, a.graph);
            add_edge(s, t, automata::Transition{label, matrix}, a.graph);
            return child;
          },
          py::arg("source"), py::arg("target"), py::arg("matrix"), py::arg("label") = "",
          "Adds the transition source → target after the existing children of `source`; returns its child "
          "index.\n\n"
          "matrix: float `(size(target), size(source))`, finite; the child net is `matrix @ net`.\n"
          "Raises InvalidInput for an unknown state id, a matrix of another shape or a non-finite entry.")
      .def(
          "matrix",
          [](const KnotAutomaton& k, std::int64_t source, std::int64_t child) -> Eigen::MatrixXd {
            const Automaton& a = k.automaton;
            const StateId s = state_id(a, source, "matrix");
            return a.graph[out_edge(a, s, child, "matrix")].matrix;
          },
          py::arg("source"), py::arg("child"),
          "The matrix of child `child` of state `source` (a copy, `(size(target), size(source))`).\n\n"
          "Raises InvalidInput for an unknown state or child.")
      .def(
          "set_matrix",
          [](KnotAutomaton& k, std::int64_t source, std::int64_t child, const Eigen::MatrixXd& matrix) {
            Automaton& a = k.automaton;
            const StateId s = state_id(a, source, "set_matrix");
            const auto e = out_edge(a, s, child, "set_matrix");
            check_matrix(a, s, target(e, a.graph), matrix,
                         "set_matrix " + std::to_string(s) + " child " + std::to_string(child));
            a.graph[e].matrix = matrix;
          },
          py::arg("source"), py::arg("child"), py::arg("matrix"),
          "Replaces the matrix of child `child` of state `source` (same checks as add_transition).");
}

/// Reading: states, children, labels, transitions.
void bind_automaton_reading(py::class_<KnotAutomaton>& automaton) {
  automaton
      .def(
          "state",
          [](const KnotAutomaton& k, std::int64_t id) {
            return state_view(k, state_id(k.automaton, id, "state"));
          },
          py::arg("id"), "The state `id` (a copy). Raises InvalidInput for an unknown id.")
      .def_property_readonly(
          "states",
          [](const KnotAutomaton& k) {
            std::vector<StateView> out;
            for (StateId s = 0; s < num_vertices(k.automaton.graph); ++s) out.push_back(state_view(k, s));
            return out;
          },
          "Every state, by id (list of State, copies).")
      .def_property_readonly(
          "state_count", [](const KnotAutomaton& k) { return num_vertices(k.automaton.graph); },
          "Number of states.")
      .def(
          "children",
          [](const KnotAutomaton& k, std::int64_t source) {
            const Automaton& a = k.automaton;
            const StateId s = state_id(a, source, "children");
            std::vector<StateId> out;
            for (auto [b, e] = out_edges(s, a.graph); b != e; ++b) out.push_back(target(*b, a.graph));
            return out;
          },
          py::arg("source"), "Target ids of the transitions out of `source`, in child order (list of int).")
      .def(
          "labels",
          [](const KnotAutomaton& k, std::int64_t source) {
            const Automaton& a = k.automaton;
            const StateId s = state_id(a, source, "labels");
            std::vector<std::string> out;
            for (auto [b, e] = out_edges(s, a.graph); b != e; ++b) out.push_back(a.graph[*b].label);
            return out;
          },
          py::arg("source"), "Labels of the transitions out of `source`, in child order (list of str).")
      .def_property_readonly(
          "transitions", [](const KnotAutomaton& k) { return transitions(k.automaton); },
          "Every transition, in state order then child order (list of Transition, copies).");
}

/// Initial entries, copies, repr.
void bind_automaton_entries(py::class_<KnotAutomaton>& automaton) {
  automaton
      .def(
          "add_initial",
          [](KnotAutomaton& k, std::int64_t state, std::optional<int> segment, double start, double end,
             int span) {
            Automaton& a = k.automaton;
            const StateId s = state_id(a, state, "add_initial");
            a.initial.push_back(
                automata::Initial{.segment = segment ? non_negative(*segment, "add_initial: segment")
                                                     : static_cast<int>(a.initial.size()),
                                  .state = s});
            k.intervals.resize(a.initial.size() - 1);
            k.intervals.push_back(nurbs::KnotInterval{.start = start, .end = end, .span = span});
            return a.initial.size() - 1;
          },
          py::arg("state"), py::arg("segment") = py::none(), py::arg("start") = 0.0, py::arg("end") = 0.0,
          py::arg("span") = -1,
          "Adds an initial entry (a piece of the shape starting in `state`); returns its index.\n\n"
          "segment: defaults to the entry's index; start, end, span: the knot interval and span of "
          "knot-doubling automata (informative for hand-made ones). Raises InvalidInput for an unknown "
          "state.")
      .def_property_readonly("initial", &initial_views, "The initial entries (list of Initial, copies).")
      .def(
          "copy", [](const KnotAutomaton& k) { return k; },
          "An independent copy (also copy.copy and copy.deepcopy).")
      .def(
          "__copy__", [](const KnotAutomaton& k) { return k; }, "An independent copy.")
      .def(
          "__deepcopy__", [](const KnotAutomaton& k, const py::dict&) { return k; }, py::arg("memo"),
          "An independent copy.")
      .def("__repr__", [](const KnotAutomaton& k) {
        const Automaton& a = k.automaton;
        return "Automaton(" + std::to_string(num_vertices(a.graph)) + " states, " +
               std::to_string(num_edges(a.graph)) + " transitions, " + std::to_string(a.initial.size()) +
               " initial entries)";
      });
}

/// The Automaton class.
void bind_automata_class(py::module_& m) {
  py::class_<KnotAutomaton> automaton(
      m, "Automaton",
      "An automaton whose transitions carry subdivision matrices (a controlled IFS).\n\n"
      "Automaton() is empty: add states, transitions (in the order of the children along the "
      "shape) and initial entries. knot_automaton and tensor_automaton build one from knots.\n"
      "Ids, matrix shapes and finiteness are checked as they are added (InvalidInput); rows "
      "summing to 1 and every state having a transition are checked by cifs.ifs.validate, "
      "which every engine function calls. Knot-doubling automata also hold the windows of their "
      "states and the knot intervals of their initial entries (C++ nurbs::KnotAutomaton).");
  bind_automaton_building(automaton);
  bind_automaton_reading(automaton);
  bind_automaton_entries(automaton);
  // Jupyter shows an object through its _repr_*_ methods: an automaton as its drawing.
  automaton.def(
      "_repr_svg_", [](const KnotAutomaton& a) { return io::to_svg(a.automaton); },
      "The drawing of to_svg(automaton), for notebooks (IPython's rich display).");
}

/// Knot automata, minimisation, initial nets, the writers.
void bind_automata_functions(py::module_& m) {
  using nurbs::TensorAutomaton;
  m.def("knot_automaton", &nurbs::knot_automaton, py::arg("curve"), py::call_guard<py::gil_scoped_release>(),
        "The knot-doubling automaton of a nurbs.Curve, from its knots alone: one initial entry per segment, "
        "transitions G and D with the subdivision matrices, recurrent states marked.");
  m.def("mark_recurrent", &automata::mark_recurrent, py::arg("automaton"),
        "Sets State.recurrent of every state of `automaton` (in place) from its strong components.");
  m.def(
      "minimize", py::overload_cast<const KnotAutomaton&>(&nurbs::minimize), py::arg("automaton"),
      py::call_guard<py::gil_scoped_release>(),
      "A new automaton whose states no control net can tell apart are merged (Moore partition refinement; "
      "labels and matrices compared exactly). Initial entries are kept, redirected to their class; a merged "
      "state keeps the window of the first state of its class.");
  m.def("initial_nets", py::overload_cast<const KnotAutomaton&, const nurbs::Curve&>(&nurbs::initial_nets),
        py::arg("automaton"), py::arg("curve"),
        "Control net of every initial entry of knot_automaton(curve): list of float64 `(d+1, cols)` arrays "
        "(homogeneous rows (w·x, w) when rational).");
  m.def(
      "initial_nets", py::overload_cast<const TensorAutomaton&, const nurbs::Surface&>(&nurbs::initial_nets),
      py::arg("automaton"), py::arg("surface"),
      "Control net of every patch of tensor_automaton(surface): list of float64 `((p+1)(q+1), cols)` arrays, "
      "row i·(q+1) + j = control point (span_u − p + i, span_v − q + j). Raises InvalidInput when the "
      "surface "
      "does not fit the automaton.");
  m.def(
      "initial_nets",
      py::overload_cast<const nurbs::VolumeAutomaton&, const nurbs::Volume&>(&nurbs::initial_nets),
      py::arg("automaton"), py::arg("volume"),
      "Control net of every cell of tensor_automaton(volume): list of float64 `((p+1)(q+1)(r+1), cols)` "
      "arrays, row (i·(q+1) + j)·(r+1) + k = control point (span_u − p + i, span_v − q + j, span_w − r + k). "
      "Raises InvalidInput when the volume does not fit the automaton.");
  // The writers live in io (one file per format); bound here too, where Python users look for them.
  m.def("to_json", py::overload_cast<const KnotAutomaton&>(&io::to_json), py::arg("automaton"),
        "The automaton as the JSON text of `cifs automaton --format json` (states, transitions, initial);\n"
        "cifs.io.parse_automaton_json reads it back.");
  m.def("to_dot", py::overload_cast<const KnotAutomaton&>(&io::to_dot), py::arg("automaton"),
        "The automaton as Graphviz DOT text.");
  m.def(
      "to_svg", py::overload_cast<const Automaton&>(&io::to_svg), py::arg("automaton"),
      "A self-contained SVG drawing of the automaton (text): states in columns by distance from the initial "
      "states, recurrent states shaded.");
}

/// Tensor-product automata.
void bind_automata_tensor(py::module_& m) {
  using nurbs::TensorAutomaton;
  py::class_<TensorAutomaton>(
      m, "TensorAutomaton",
      "The tensor-product automaton of a surface: pairs of u and v knot-doubling states, "
      "transitions GH, GB, DH, DB with Kronecker-product matrices.")
      .def_property_readonly(
          "product", [](const TensorAutomaton& t) { return t.product; },
          "The product automaton (Automaton, a copy): one initial entry per patch, u-major.")
      .def_property_readonly(
          "factors", [](const TensorAutomaton& t) { return py::make_tuple(t.factors[0], t.factors[1]); },
          "The knot automata of the u and v direction curves (tuple of 2 Automaton, copies).")
      .def_property_readonly(
          "factor_states", [](const TensorAutomaton& t) { return index_array(t.factor_states); },
          "Per product state, its (u, v) factor states: int array `(states, 2)`.")
      .def_property_readonly(
          "patches", [](const TensorAutomaton& t) { return index_array(t.patches); },
          "Per product initial entry, its (u segment, v segment): int array `(patches, 2)`.")
      .def("__repr__", [](const TensorAutomaton& t) {
        return "TensorAutomaton(" + std::to_string(num_vertices(t.product.graph)) + " product states, " +
               std::to_string(t.patches.size()) + " patches)";
      });

  using nurbs::VolumeAutomaton;
  py::class_<VolumeAutomaton>(
      m, "VolumeAutomaton",
      "The tensor-product automaton of a volume: triples of u, v and w knot-doubling states, transitions\n"
      "GHA, GHR, GBA, GBR, DHA, DHR, DBA, DBR (u halves G/D, v halves H/B, w halves A/R) with the matrices\n"
      "kron(kron(M_u, M_v), M_w).")
      .def_property_readonly(
          "product", [](const VolumeAutomaton& t) { return t.product; },
          "The product automaton (Automaton, a copy): one initial entry per cell, w fastest.")
      .def_property_readonly(
          "factors",
          [](const VolumeAutomaton& t) { return py::make_tuple(t.factors[0], t.factors[1], t.factors[2]); },
          "The knot automata of the u, v and w direction curves (tuple of 3, copies).")
      .def_property_readonly(
          "factor_states", [](const VolumeAutomaton& t) { return index_array(t.factor_states); },
          "Per product state, its (u, v, w) factor states: int array `(states, 3)`.")
      .def_property_readonly(
          "cells", [](const VolumeAutomaton& t) { return index_array(t.cells); },
          "Per product initial entry, its (u, v, w) segments: int array `(cells, 3)`.")
      .def("__repr__", [](const VolumeAutomaton& t) {
        return "VolumeAutomaton(" + std::to_string(num_vertices(t.product.graph)) + " product states, " +
               std::to_string(t.cells.size()) + " cells)";
      });
  m.def("tensor_automaton", py::overload_cast<const nurbs::Volume&>(&nurbs::tensor_automaton),
        py::arg("volume"), py::call_guard<py::gil_scoped_release>(),
        "The tensor-product automaton of a nurbs.Volume (from its knots alone); recurrent states marked.");
  m.def("w_label", &automata::w_label, py::arg("label"),
        "The w direction's name of a knot-doubling label: G → A (first half), D → R (second half); other "
        "labels unchanged.");
  m.def("tensor_automaton", py::overload_cast<const nurbs::Surface&>(&nurbs::tensor_automaton),
        py::arg("surface"), py::call_guard<py::gil_scoped_release>(),
        "The tensor-product automaton of a nurbs.Surface (from its knots alone); recurrent states marked.");
  m.def("kron", &automata::kron, py::arg("A"), py::arg("B"),
        "kron(A, B): entry (i·B.rows + k, j·B.cols + l) = A[i, j]·B[k, l], one product per entry (float64 "
        "array).");
  m.def("v_label", &automata::v_label, py::arg("label"),
        "The v direction's name of a knot-doubling label: G → H (first half), D → B (second half); other "
        "labels unchanged.");
}

}  // namespace

void bind_automata(py::module_& m) {
  bind_automata_views(m);
  bind_automata_class(m);
  bind_automata_tensor(m);  // before initial_nets, whose signature names TensorAutomaton
  bind_automata_functions(m);
}

}  // namespace cifs::python
