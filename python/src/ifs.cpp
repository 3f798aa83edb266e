// SPDX-License-Identifier: MIT
// cifs Python bindings — cifs.ifs: analysis, attractors, chaos game, meshes, classic affine IFS,
// fractal dimension (BC-IFS: bcifs.cpp).
#include <complex>
#include <cstdint>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"
#include "cifs/errors.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/ifs/affine_cifs.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"

namespace cifs::python {

namespace {

using automata::Automaton;
using automata::StateId;
using ifs::AffineMap;

/// A subdivision-tree node copied out of the C++ callback (whose references die with it).
struct LeafView {
  std::size_t initial = 0;
  StateId state = 0;
  Points net;
  int depth = 0;
  std::vector<int> word;
};

struct ToleranceLeafView {
  LeafView leaf;
  double radius = 0;
  double diameter = 0;
  bool converged = false;
  double deviation = 0;
};

LeafView view(const ifs::Leaf& leaf) {
  return {leaf.initial, leaf.state, leaf.net, leaf.depth,
          std::vector<int>(leaf.word.begin(), leaf.word.end())};
}

std::string num(double x) {
  return py::repr(py::float_(x)).cast<std::string>();
}

/// An edge of mauldin_williams_dimension: a SimilarityEdge or a (from, to, ratio) sequence.
ifs::SimilarityEdge similarity_edge(const py::handle& item, std::size_t index) {
  if (py::isinstance<ifs::SimilarityEdge>(item)) return item.cast<ifs::SimilarityEdge>();
  const auto where = "mauldin_williams_dimension: edges[" + std::to_string(index) + "]";
  if (!py::isinstance<py::sequence>(item) || py::len(item) != 3)
    throw InvalidInput(where + " is neither a SimilarityEdge nor a (from, to, ratio) triple");
  const auto t = item.cast<py::sequence>();
  const auto from = t[0].cast<std::int64_t>(), to = t[1].cast<std::int64_t>();
  if (from < 0 || to < 0)
    throw InvalidInput(where + ": state " + std::to_string(from < 0 ? from : to) + " is negative");
  return {static_cast<StateId>(from), static_cast<StateId>(to), t[2].cast<double>()};
}

/// Analysis: reachable states, validation, contraction, end functionals, spectra.
void bind_analysis(py::module_& m) {
  const auto release = py::call_guard<py::gil_scoped_release>();
  m.def("reachable_states", &ifs::reachable_states, py::arg("automaton"),
        "Ids of the states reachable from the initial entries (every state when there is none), sorted.");
  m.def("validate", py::overload_cast<const automata::Automaton&>(&ifs::validate), py::arg("automaton"),
        "Raises InvalidInput unless every reachable state holds a point and has a transition, and every "
        "transition carries a finite `size(to) by size(from)` matrix whose rows sum to 1.");
  m.def("diameter", &ifs::diameter, py::arg("net"),
        "Largest Euclidean distance between two rows of `net` (float `(n, dim)`); 0 for fewer than 2 rows.");
  m.def("delta", &ifs::delta, py::arg("M"),
        "Contraction coefficient δ(M) = max over pairs of rows of ½‖M_i − M_j‖₁ (M float `(r, n)`): "
        "diam(M @ N) ≤ δ(M)·diam(N).");

  py::class_<ifs::Contraction>(
      m, "Contraction",
      "Result of the contractivity check: every path of `m` transitions shrinks nets by "
      "at least `delta` < 1.")
      .def_readonly("m", &ifs::Contraction::m, "Smallest path length with δ_m < 1.")
      .def_readonly("delta", &ifs::Contraction::delta,
                    "δ_m: largest δ of the products along paths of length m.")
      .def_readonly("A", &ifs::Contraction::A,
                    "Largest row 1-norm of the products along the paths of length 0 … m.")
      .def_readonly("radius", &ifs::Contraction::radius,
                    "Bound factor ρ: the attractor piece of a net N lies within ρ·diam(N) of N's first row.")
      .def_readonly("radius_length", &ifs::Contraction::radius_length, "Path length that gives `radius`.")
      .def("__repr__", [](const ifs::Contraction& c) {
        return "Contraction(m=" + std::to_string(c.m) + ", delta=" + num(c.delta) + ", A=" + num(c.A) +
               ", radius=" + num(c.radius) + ", radius_length=" + std::to_string(c.radius_length) + ")";
      });

  m.def(
      "contraction",
      [](const Automaton& a, int max_length, bool tighten) {
        return ifs::contraction(a, ifs::ContractionOptions{.max_length = max_length, .tighten = tighten});
      },
      py::arg("automaton"), py::kw_only(), py::arg("max_length") = 8, py::arg("tighten").noconvert() = true,
      release,
      "Finds the smallest path length m ≤ max_length whose products all shrink nets (δ_m < 1).\n\n"
      "tighten: also try longer paths for a smaller bound factor `radius`. Returns a Contraction. Raises "
      "InvalidInput when there is none (the message names the state and the path that fails), for "
      "max_length < 1, and as validate.");
  m.def(
      "fixed_point",
      [](const Automaton& a, std::int64_t state, const std::vector<int>& word) {
        if (state < 0) throw InvalidInput("fixed_point: state " + std::to_string(state) + " does not exist");
        return ifs::fixed_point(a, static_cast<StateId>(state), word);
      },
      py::arg("automaton"), py::arg("state"), py::arg("word"),
      "Fixed point of a word of child indices read from `state` (the word must return to `state`).\n\n"
      "Returns the row ℓ (float `(size,)`, summing to 1) with ℓ @ P = ℓ for the word's product P: the point "
      "of address word^∞ under a net N is ℓ @ N. Raises InvalidInput for an unknown state, a child index out "
      "of range, a word that does not return, or 1 not a simple eigenvalue of P.");

  py::class_<ifs::EndFunctionals>(m, "EndFunctionals",
                                  "Per state, the functionals of the two ends of its attractor piece.")
      .def_readonly(
          "start", &ifs::EndFunctionals::start,
          "List indexed by state id of float `(size,)` arrays: start[s] @ N is the point of address "
          "(first child)^∞ under a net N of s; empty arrays for states that are not reachable.")
      .def_readonly("end", &ifs::EndFunctionals::end,
                    "As start, for the address (last child)^∞: end[s] @ N ends the piece.")
      .def("__repr__", [](const ifs::EndFunctionals& e) {
        return "EndFunctionals(" + std::to_string(e.start.size()) + " states)";
      });
  m.def("end_functionals", &ifs::end_functionals, py::arg("automaton"),
        "Start and end functionals of every state (EndFunctionals). Raises InvalidInput as fixed_point.");
  m.def("repeated_child_functionals", &ifs::repeated_child_functionals, py::arg("automaton"),
        py::arg("child"),
        "Per state id, the functional (float `(size,)`) of the address child^∞; empty arrays for states that "
        "are not reachable. Raises InvalidInput when a reachable state has no child `child`, and as "
        "fixed_point.");
  m.def(
      "eigenvalues", [](const Eigen::MatrixXd& M) { return vector_array(ifs::eigenvalues(M)); }, py::arg("M"),
      "Eigenvalues of a square matrix as a complex array, by decreasing modulus (ties: real, then imaginary "
      "part, decreasing). Raises InvalidInput for a matrix that is not square.");

  py::class_<ifs::TransitionSpectrum>(m, "TransitionSpectrum", "Eigenvalues of one transition matrix.")
      .def_readonly("source", &ifs::TransitionSpectrum::from,
                    "Id of the state the transition leaves (C++ `from`).")
      .def_readonly("target", &ifs::TransitionSpectrum::to, "Id of the state it enters (C++ `to`).")
      .def_readonly("child", &ifs::TransitionSpectrum::child, "Index among the out-edges of `source`.")
      .def_readonly("label", &ifs::TransitionSpectrum::label, "Label of the transition.")
      .def_property_readonly(
          "eigenvalues", [](const ifs::TransitionSpectrum& s) { return vector_array(s.eigenvalues); },
          "Complex array sorted as eigenvalues(); empty when the matrix is not square.")
      .def("__repr__", [](const ifs::TransitionSpectrum& s) {
        return "TransitionSpectrum(" + std::to_string(s.from) + " -> " + std::to_string(s.to) + ", child " +
               std::to_string(s.child) + ", label='" + s.label + "', " +
               std::to_string(s.eigenvalues.size()) + " eigenvalues)";
      });
  m.def("spectra", &ifs::spectra, py::arg("automaton"),
        "Spectra of every transition out of a reachable state, in state order then child order (list of "
        "TransitionSpectrum).");
}

/// Attractors: Cartesian rows, the subdivision tree and its leaves.
void bind_leaves(py::module_& m) {
  m.def("cartesian", &ifs::cartesian, py::arg("homogeneous"),
        "Homogeneous rows (w·x, w), float `(n, dim+1)` → Cartesian rows x, `(n, dim)` (an ifs.Rows). Raises "
        "InvalidInput for fewer than 2 columns, a zero weight, or rows known to be Cartesian (ifs.Rows: the "
        "nets of a shape that is not rational and the points made from them; curve.attractor(depth) gives "
        "the points of any curve).");

  py::class_<LeafView>(m, "Leaf", "A node of the subdivision tree, as handed to callbacks (copies).")
      .def_readonly("initial", &LeafView::initial,
                    "Index of the initial entry (and net) the node descends from.")
      .def_readonly("state", &LeafView::state, "Id of the node's state.")
      .def_property_readonly(
          "net", [](const LeafView& l) { return l.net; },
          "The node's control net, float `(size(state), cols)`.")
      .def_readonly("depth", &LeafView::depth, "Depth of the node (number of child indices in `word`).")
      .def_readonly("word", &LeafView::word, "Child indices from the root to the node (list of int).")
      .def("__repr__", [](const LeafView& l) {
        return "Leaf(initial=" + std::to_string(l.initial) + ", state=" + std::to_string(l.state) +
               ", depth=" + std::to_string(l.depth) + ")";
      });

  m.def(
      "for_each_leaf",
      // The automaton is taken by value: a callback that edits it cannot pull the graph from under the walk.
      // NOLINTNEXTLINE(performance-unnecessary-value-param): the copy is the point (above).
      [](const Automaton a, const std::vector<Points>& nets, int depth, const py::function& callback) {
        ifs::for_each_leaf(a, nets, depth, [&](const ifs::Leaf& leaf) { callback(view(leaf)); });
      },
      py::arg("automaton"), py::arg("nets"), py::arg("depth"), py::arg("callback"),
      "Calls callback(Leaf) for every node at `depth` (≥ 0), initial entries in order, children in child "
      "order, depth first.\n\n"
      "nets: one float `(size(initial[i].state), cols)` array per initial entry. Raises InvalidInput for a "
      "negative depth, nets that do not fit, and as validate; exceptions of the callback propagate.");

  py::class_<ToleranceLeafView>(
      m, "ToleranceLeaf",
      "A leaf of for_each_leaf_to_tolerance: every attractor point below it lies within "
      "`radius` of leaf.net[0] (its Cartesian image with homogeneous=True), any two within `diameter`.")
      .def_readonly("leaf", &ToleranceLeafView::leaf, "The node (Leaf).")
      .def_readonly("radius", &ToleranceLeafView::radius,
                    "Bound on the distance of the piece's points to net[0] (PieceBounds).")
      .def_readonly("diameter", &ToleranceLeafView::diameter,
                    "Bound on the piece's diameter (PieceBounds), ≤ 2·radius.")
      .def_readonly("converged", &ToleranceLeafView::converged,
                    "True when diameter < epsilon (deviation < epsilon with chordal=True); False when the "
                    "branch stopped at max_depth.")
      .def_readonly(
          "deviation", &ToleranceLeafView::deviation,
          "With chordal=True: bound on the distance of the piece's points to its chord (0 otherwise).")
      .def("__repr__", [](const ToleranceLeafView& t) {
        return "ToleranceLeaf(depth=" + std::to_string(t.leaf.depth) + ", diameter=" + num(t.diameter) +
               ", converged=" + (t.converged ? "True" : "False") + ")";
      });
  py::class_<ifs::ToleranceResult>(m, "ToleranceResult", "Summary of for_each_leaf_to_tolerance.")
      .def_readonly("contraction", &ifs::ToleranceResult::contraction, "The Contraction used for the bounds.")
      .def_readonly("leaves", &ifs::ToleranceResult::leaves, "Number of leaves visited.")
      .def_readonly("unconverged", &ifs::ToleranceResult::unconverged, "Leaves cut by max_depth.")
      .def_readonly("deepest", &ifs::ToleranceResult::deepest, "Largest leaf depth.")
      .def("__repr__", [](const ifs::ToleranceResult& r) {
        return "ToleranceResult(leaves=" + std::to_string(r.leaves) +
               ", unconverged=" + std::to_string(r.unconverged) + ", deepest=" + std::to_string(r.deepest) +
               ")";
      });
  m.def(
      "for_each_leaf_to_tolerance",
      // NOLINTNEXTLINE(performance-unnecessary-value-param): a copy, as for for_each_leaf.
      [](const Automaton a, const std::vector<Points>& nets, const py::function& callback, double epsilon,
         int max_depth, int max_length, bool homogeneous, bool chordal) {
        return ifs::for_each_leaf_to_tolerance(
            a, nets,
            ifs::ToleranceOptions{.epsilon = epsilon,
                                  .max_depth = max_depth,
                                  .max_length = max_length,
                                  .homogeneous = homogeneous,
                                  .chordal = chordal},
            [&](const ifs::ToleranceLeaf& t) {
              callback(ToleranceLeafView{view(t.leaf), t.radius, t.diameter, t.converged, t.deviation});
            });
      },
      py::arg("automaton"), py::arg("nets"), py::arg("callback"), py::kw_only(), py::arg("epsilon") = 1e-6,
      py::arg("max_depth") = 64, py::arg("max_length") = 8, py::arg("homogeneous").noconvert() = false,
      py::arg("chordal").noconvert() = false,
      "Depth-first traversal that stops a branch once its attractor piece is proved smaller than epsilon "
      "(PieceBounds: the hull of the net where every path is non-negative, else the contraction bound); "
      "calls callback(ToleranceLeaf) per leaf and returns a ToleranceResult.\n\n"
      "nets as for_each_leaf; epsilon: absolute target diameter; max_depth: branches stop there (reported as "
      "unconverged); max_length: for the contraction check; homogeneous: rows are (w·x, w) and epsilon and "
      "the bounds are Cartesian. Raises InvalidInput for epsilon ≤ 0, a negative max_depth, a system that is "
      "not contractive, and as for_each_leaf.");
}

/// Attractors: convex states, piece bounds and tolerance samples.
void bind_piece_bounds(py::module_& m) {
  m.def("convex_states", &ifs::convex_states, py::arg("automaton"),
        "Per state id: True when every matrix on every path from the state has no negative entry, so each "
        "attractor piece lies in the convex hull of its net (hull property).");
  py::class_<ifs::PieceBound>(m, "PieceBound", "A bound on one attractor piece (PieceBounds).")
      .def_readonly("radius", &ifs::PieceBound::radius,
                    "Every point lies within radius of the net's first row (Cartesian image if homogeneous).")
      .def_readonly("diameter", &ifs::PieceBound::diameter,
                    "Any two points lie within diameter (≤ 2·radius).")
      .def("__repr__", [](const ifs::PieceBound& b) {
        return "PieceBound(radius=" + num(b.radius) + ", diameter=" + num(b.diameter) + ")";
      });
  py::class_<ifs::PieceBounds>(
      m, "PieceBounds",
      "Proven bounds on attractor pieces, per (state, net): the smaller of the "
      "contraction bound and, for convex states, the hull bound (docs/dimension.md).")
      .def(py::init([](const Automaton& a, int max_length, bool homogeneous) {
             return ifs::PieceBounds(a, ifs::contraction(a, {.max_length = max_length, .tighten = true}),
                                     homogeneous);
           }),
           py::arg("automaton"), py::kw_only(), py::arg("max_length") = 8,
           py::arg("homogeneous").noconvert() = false,
           "Bounds for `automaton` (contraction found with paths up to max_length); homogeneous: nets hold "
           "(w·x, w) rows and the bounds are Cartesian. Raises InvalidInput for a system that is not "
           "contractive.")
      .def(
          "__call__",
          [](const ifs::PieceBounds& bounds, const Automaton& a, std::int64_t state, const Points& net) {
            if (state < 0 || state >= static_cast<std::int64_t>(num_vertices(a.graph)))
              throw InvalidInput("PieceBounds: state " + std::to_string(state) + " does not exist");
            if (net.rows() != a.graph[static_cast<StateId>(state)].size)
              throw InvalidInput("PieceBounds: the net has " + std::to_string(net.rows()) + " rows, state " +
                                 std::to_string(state) + " holds " +
                                 std::to_string(a.graph[static_cast<StateId>(state)].size));
            return bounds(static_cast<StateId>(state), net);
          },
          py::arg("automaton"), py::arg("state"), py::arg("net"),
          "The PieceBound of the piece of `state` under `net` (`(size(state), cols)`); `automaton` is the "
          "one the bounds were built for (to check the state and the net's size).");
  py::class_<ifs::ToleranceSample>(m, "ToleranceSample",
                                   "A sample of an attractor of proven resolution (tolerance_sample).")
      .def_property_readonly(
          "points", [](const ifs::ToleranceSample& t) { return t.points; },
          "Float (n, dim) Cartesian: the start point of every leaf (a point of the attractor).")
      .def_readonly("resolution", &ifs::ToleranceSample::resolution,
                    "Every piece the points stand for has a diameter below this (Cartesian units).")
      .def_readonly("deepest", &ifs::ToleranceSample::deepest, "Largest leaf depth.")
      .def_readonly("leaves", &ifs::ToleranceSample::leaves, "Number of leaves (= number of points).")
      .def_property_readonly(
          "cover",
          [](const ifs::ToleranceSample& t) {
            py::list out;
            for (const ifs::CoverCount& c : t.cover) out.append(py::make_tuple(c.epsilon, c.leaves));
            return out;
          },
          "The search's (epsilon, leaves) counts, coarsest first, this sample's last (cover_exponent).")
      .def("__repr__", [](const ifs::ToleranceSample& t) {
        return "ToleranceSample(leaves=" + std::to_string(t.leaves) + ", resolution=" + num(t.resolution) +
               ", deepest=" + std::to_string(t.deepest) + ")";
      });
  py::class_<ifs::CoverExponent>(m, "CoverExponent", "Growth of a proven cover (cover_exponent).")
      .def_readonly("dimension", &ifs::CoverExponent::dimension,
                    "Least-squares slope of log n against log(1/ε).")
      .def_readonly("spread", &ifs::CoverExponent::spread,
                    "Largest |local slope − dimension| over consecutive fitted counts.")
      .def_readonly("max_epsilon", &ifs::CoverExponent::max_epsilon, "Coarsest fitted ε.")
      .def_readonly("min_epsilon", &ifs::CoverExponent::min_epsilon, "Finest fitted ε.")
      .def_readonly("levels", &ifs::CoverExponent::levels, "Counts fitted.")
      .def("__repr__", [](const ifs::CoverExponent& e) {
        return "CoverExponent(dimension=" + num(e.dimension) + ", spread=" + num(e.spread) +
               ", levels=" + std::to_string(e.levels) + ")";
      });
  m.def(
      "cover_exponent",
      [](const std::vector<std::pair<double, std::int64_t>>& counts, std::int64_t min_leaves, int levels) {
        std::vector<ifs::CoverCount> c;
        c.reserve(counts.size());
        for (const auto& [epsilon, leaves] : counts)
          c.push_back({epsilon, count_arg(leaves, "cover_exponent: leaves")});
        return ifs::cover_exponent(c, count_arg(min_leaves, "cover_exponent: min_leaves"),
                                   non_negative(levels, "cover_exponent: levels"));
      },
      py::arg("counts"), py::arg("min_leaves") = 1000, py::arg("levels") = 64,
      "Growth of a proven cover: the slope of log n(ε) against log(1/ε) over the finest `levels` counts "
      "(epsilon, leaves) with at least `min_leaves` leaves, in ToleranceSample.cover's order; None with "
      "fewer than 3. Its limit bounds the upper box-counting dimension from above; it has no boundary term.");
  m.def(
      "tolerance_sample",
      [](const Automaton& a, const std::vector<Points>& nets, double epsilon, bool homogeneous,
         std::int64_t max_points, int max_depth) {
        const ifs::ToleranceSampleOptions o{
            .epsilon = epsilon,
            .homogeneous = homogeneous,
            .max_points = count_arg(max_points, "tolerance_sample: max_points"),
            .max_depth = max_depth};
        py::gil_scoped_release unlocked;
        return ifs::tolerance_sample(a, nets, o);
      },
      py::arg("automaton"), py::arg("nets"), py::kw_only(), py::arg("epsilon") = 0.0,
      py::arg("homogeneous").noconvert() = false, py::arg("max_points") = std::int64_t{1} << 21,
      py::arg("max_depth") = 64,
      "Samples the attractor to a tolerance: one attractor point per leaf of for_each_leaf_to_tolerance, "
      "every "
      "piece proven smaller than epsilon (the sample's resolution, for box_counting).\n\n"
      "epsilon: Cartesian piece diameter, 0 picks the largest diam(nets)·2^-j (j ≥ 4) within max_points; "
      "homogeneous: nets hold (w·x, w) rows. Returns a ToleranceSample. Raises InvalidInput for a bad "
      "epsilon, "
      "a sample above max_points (before allocating it), a branch unresolved at max_depth, and as "
      "for_each_leaf_to_tolerance.");
}

/// Attractors: points to a depth or a tolerance, stencil tables.
void bind_samples(py::module_& m) {
  py::class_<ifs::Sample>(m, "Sample", "Attractor points to a depth or a tolerance (sample_attractor).")
      .def_property_readonly(
          "points", [](const ifs::Sample& s) { return s.points; },
          "float `(n, dim)` in curve order; Cartesian when homogeneous.")
      .def_property_readonly(
          "states", [](const ifs::Sample& s) { return s.states; },
          "With states=True: the state of the piece each point starts (none for the end point).")
      .def_readonly("depth", &ifs::Sample::depth,
                    "The depth, or the deepest leaf of the tolerance traversal.");
  m.def(
      "sample_attractor",
      [](const Automaton& a, const std::vector<Points>& nets, int depth, double tolerance, bool chordal,
         bool homogeneous, bool closed, bool states, int max_depth, std::int64_t max_points) {
        const ifs::SampleOptions o{.depth = depth,
                                   .tolerance = tolerance,
                                   .chordal = chordal,
                                   .homogeneous = homogeneous,
                                   .closed = closed,
                                   .states = states,
                                   .max_depth = non_negative(max_depth, "sample_attractor: max_depth"),
                                   .max_points = count_arg(max_points, "sample_attractor: max_points")};
        py::gil_scoped_release unlocked;
        return ifs::sample_attractor(a, nets, o);
      },
      py::arg("automaton"), py::arg("nets"), py::kw_only(), py::arg("depth") = -1, py::arg("tolerance") = 0.0,
      py::arg("chordal").noconvert() = false, py::arg("homogeneous").noconvert() = false,
      py::arg("closed").noconvert() = false, py::arg("states").noconvert() = false, py::arg("max_depth") = 64,
      py::arg("max_points") = std::int64_t{1} << 27,
      "The attractor's points to `depth` (≥ 0) or, when depth is negative, to a proven `tolerance`: every "
      "piece's diameter below it (Cartesian with homogeneous nets, whose points come back Cartesian), plus "
      "the end point unless closed. chordal=True: every piece within `tolerance` of its chord instead — the "
      "points are a polyline proven within the tolerance of the curve (chordal deviation), with far fewer "
      "points. Returns a Sample. Raises InvalidInput for more than max_points points "
      "(before computing them, from an estimate in tolerance mode), a tolerance that is not positive, a "
      "branch unresolved at max_depth, and as attractor_points.");
  m.def("attractor_point_count", &ifs::attractor_point_count, py::arg("automaton"), py::arg("depth"),
        py::arg("closed").noconvert() = false,
        "Number of points attractor_points returns: the nodes at `depth` plus 1 unless closed. Raises "
        "InvalidInput for a negative depth or an overflow.");
  m.def(
      "attractor_points",
      [](const Automaton& a, const std::vector<Points>& nets, int depth, bool closed, std::int64_t max_bytes,
         int max_table_depth) {
        const ifs::PointsOptions o{
            .closed = closed,
            .max_bytes = count_arg(max_bytes, "attractor_points: max_bytes"),
            .max_table_depth = non_negative(max_table_depth, "attractor_points: max_table_depth")};
        py::gil_scoped_release unlocked;
        return ifs::attractor_points(a, nets, depth, o);
      },
      py::arg("automaton"), py::arg("nets"), py::arg("depth"), py::kw_only(),
      py::arg("closed").noconvert() = false, py::arg("max_bytes") = std::int64_t{1} << 30,
      py::arg("max_table_depth") = 8,
      "Attractor points to depth K in curve order: float `(count, cols)`, the start point of every node at "
      "`depth` plus the end of the last one unless `closed`.\n\n"
      "nets as for_each_leaf; max_bytes: refuse a larger output before any work; max_table_depth: depth of "
      "the precomposed stencil tables. Raises InvalidInput for a negative depth, an output above max_bytes, "
      "nets that do not fit, and as validate.");

  py::class_<ifs::StencilTable>(
      m, "StencilTable",
      "The attractor points of one depth as functionals of the initial nets, built once (stencil_table) and "
      "applied to any nets of the automaton: animations and parameter sweeps pay the table once.")
      .def_readonly("depth", &ifs::StencilTable::depth, "Depth K of the attractor points.")
      .def_readonly("table_depth", &ifs::StencilTable::table_depth, "Depth L of the precomposed tables.")
      .def_readonly("closed", &ifs::StencilTable::closed,
                    "No end point: the last piece ends where the first starts.")
      .def_readonly("points", &ifs::StencilTable::points, "Rows of every application.")
      .def(
          "apply",
          [](const ifs::StencilTable& t, const std::vector<Points>& nets, std::int64_t max_bytes) {
            const std::size_t limit = count_arg(max_bytes, "StencilTable.apply: max_bytes");
            py::gil_scoped_release unlocked;
            return ifs::apply_table(t, nets, limit);
          },
          py::arg("nets"), py::kw_only(), py::arg("max_bytes") = std::int64_t{1} << 30,
          "The points of these nets: float `(points, cols)`, the same as attractor_points. Several net sets "
          "side by side (columns) give their points side by side. Raises InvalidInput for nets that do not "
          "fit and an output above max_bytes.")
      .def("__repr__", [](const ifs::StencilTable& t) {
        return "StencilTable(depth " + std::to_string(t.depth) + ", table depth " +
               std::to_string(t.table_depth) + ", " + std::to_string(t.points) + " points)";
      });
  m.def(
      "stencil_table",
      [](const Automaton& a, int depth, bool closed, int max_table_depth) {
        py::gil_scoped_release unlocked;
        return ifs::stencil_table(
            a, depth,
            {.closed = closed,
             .max_table_depth = non_negative(max_table_depth, "stencil_table: max_table_depth")});
      },
      py::arg("automaton"), py::arg("depth"), py::kw_only(), py::arg("closed").noconvert() = false,
      py::arg("max_table_depth") = 8,
      "Builds the StencilTable of `automaton` at `depth` (checks, counts, end functionals, tables: the work "
      "that depends on the automaton alone). Raises InvalidInput for an invalid automaton, a negative depth "
      "or a count that overflows.");
}

/// Attractors: the chaos game.
void bind_chaos(py::module_& m) {
  py::class_<ifs::ChaosResult>(m, "ChaosResult", "Result of the chaos game.")
      .def_property_readonly(
          "points", [](const ifs::ChaosResult& r) { return r.points; },
          "The sample, float `(samples, cols)`, every point on the attractor.")
      .def_readonly("seed", &ifs::ChaosResult::seed,
                    "The seed used (drawn when 0 was given): reproduces the run.")
      .def_property_readonly(
          "address", [](const ifs::ChaosResult& r) { return vector_array(r.address); },
          "With record_address: per point, `initial + t` with t ∈ [0, 1] the equal-split parameter of its "
          "address (float `(samples,)`); otherwise empty.")
      .def("__repr__", [](const ifs::ChaosResult& r) {
        return "ChaosResult(" + std::to_string(r.points.rows()) + " points, seed=" + std::to_string(r.seed) +
               ")";
      });
  m.def(
      "chaos_game",
      [](const Automaton& a, const std::vector<Points>& nets, std::int64_t samples, std::uint64_t seed,
         double restart_diameter, bool record_address, std::int64_t max_bytes) {
        const ifs::ChaosOptions o{.samples = count_arg(samples, "chaos_game: samples"),
                                  .seed = seed,
                                  .restart_diameter = restart_diameter,
                                  .record_address = record_address,
                                  .max_bytes = count_arg(max_bytes, "chaos_game: max_bytes")};
        py::gil_scoped_release unlocked;
        return ifs::chaos_game(a, nets, o);
      },
      py::arg("automaton"), py::arg("nets"), py::kw_only(), py::arg("samples") = 100000, py::arg("seed") = 0,
      py::arg("restart_diameter") = 1e-9, py::arg("record_address").noconvert() = false,
      py::arg("max_bytes") = ifs::ChaosOptions{}.max_bytes,
      "Random walk over the automaton (uniform child at each step) emitting one attractor point per step; "
      "returns a ChaosResult.\n\n"
      "nets as for_each_leaf; seed: of the project's generator (xoshiro256**), 0 draws one; "
      "restart_diameter: restart at a root "
      "when "
      "the net has shrunk below this fraction of the root's diameter. Raises InvalidInput for a system that "
      "is not contractive, restart_diameter outside (0, 1), negative samples, an output (8 bytes per "
      "coordinate\n"
      "and address) above max_bytes (checked before allocating), and as for_each_leaf.");
}

/// The `out` mesh of the mesh routes, checked: with keep_faces it must hold the faces and states of an
/// earlier call (`initial` patches of 4^depth quads each); the C++ route would silently rewrite other sizes,
/// Python refuses them, before any work. Returns the mesh to write into (out, or `fresh`).
Mesh& out_mesh(Mesh* out, Mesh& fresh, bool keep_faces, std::size_t initial, int depth,
               const std::string& who) {
  if (!out) {
    if (keep_faces) throw InvalidInput(who + ": keep_faces: needs the mesh of an earlier call as out=");
    return fresh;
  }
  if (keep_faces && depth >= 0 && depth < 24) {
    const std::size_t faces = initial << (2 * depth);
    if (out->face_offsets.size() != faces + 1 || out->face_vertices.size() != 4 * faces ||
        out->states.size() != faces)
      throw InvalidInput(
          who +
          ": out: keep_faces needs the faces and states of an earlier call with the same "
          "automaton and depth (" +
          std::to_string(faces) + " quads), out has " + std::to_string(out->states.size()) + " states and " +
          std::to_string(out->face_offsets.empty() ? 0 : out->face_offsets.size() - 1) + " faces");
  }
  return *out;
}

/// The result of a mesh route: `out` itself (the same Python object) or the new mesh.
py::object mesh_result(Mesh* out, Mesh&& fresh) {
  return out ? py::cast(out, py::return_value_policy::reference) : py::cast(std::move(fresh));
}

/// Meshes.
void bind_meshes(py::module_& m) {
  m.def(
      "mesh_bytes",
      [](std::int64_t vertices, std::int64_t cols, std::int64_t quads) {
        return ifs::mesh_bytes(count_arg(vertices, "mesh_bytes: vertices"),
                               count_arg(cols, "mesh_bytes: cols"), count_arg(quads, "mesh_bytes: quads"));
      },
      py::arg("vertices"), py::arg("cols"), py::arg("quads"),
      "Bytes of a mesh of `vertices` nodes with `cols` coordinates and `quads` quads (saturating). Raises "
      "InvalidInput for a negative count.");
  m.def(
      "surface_mesh",
      [](const nurbs::TensorAutomaton& a, const std::vector<Points>& nets, int depth, bool homogeneous,
         std::int64_t max_bytes, int max_table_depth, Mesh* out, bool keep_faces) {
        const ifs::MeshOptions o{
            .homogeneous = homogeneous,
            .max_bytes = count_arg(max_bytes, "surface_mesh: max_bytes"),
            .max_table_depth = non_negative(max_table_depth, "surface_mesh: max_table_depth"),
            .keep_faces = keep_faces};
        Mesh fresh;
        Mesh& mesh = out_mesh(out, fresh, keep_faces,
                              a.factors[0].automaton.initial.size() * a.factors[1].automaton.initial.size(),
                              depth, "surface_mesh");
        {
          py::gil_scoped_release unlocked;
          ifs::surface_mesh(a, nets, depth, mesh, o);
        }
        return mesh_result(out, std::move(fresh));
      },
      py::arg("automaton"), py::arg("nets"), py::arg("depth"), py::kw_only(),
      py::arg("homogeneous").noconvert() = false, py::arg("max_bytes") = std::int64_t{1} << 30,
      py::arg("max_table_depth") = 6, py::arg("out") = py::none(), py::arg("keep_faces") = false,
      "The attractor at `depth` of a TensorAutomaton as one io.Mesh of quads (separable route): node (I, J) "
      "of "
      "the global grid is vertex I·(B·2^K + 1) + J, cell (I, J) face I·(B·2^K) + J with corners (I, J), "
      "(I+1, J), (I+1, J+1), (I, J+1) (counter-clockwise in (u, v)), `states` the leaf state of each "
      "face.\n\n"
      "nets: automata.initial_nets(automaton, surface); homogeneous: the nets hold (w·x, w) rows, vertices "
      "are divided by w; max_bytes: refuse a larger mesh. Raises InvalidInput for a negative depth, nets "
      "that "
      "do not fit, or a mesh above max_bytes.\n\n"
      "out: an io.Mesh written in place and returned (its storage reused: a sweep or an animation); "
      "keep_faces: "
      "out holds the faces and states of an earlier call with the same automaton and depth, only the "
      "vertices "
      "are written (InvalidInput for an out of other sizes).");
  m.def(
      "quad_mesh",
      [](const Automaton& a, const std::vector<Points>& nets, const std::vector<std::array<int, 2>>& patches,
         int depth, bool homogeneous, std::int64_t max_bytes, int max_table_depth, Mesh* out,
         bool keep_faces) {
        const ifs::MeshOptions o{
            .homogeneous = homogeneous,
            .max_bytes = count_arg(max_bytes, "quad_mesh: max_bytes"),
            .max_table_depth = non_negative(max_table_depth, "quad_mesh: max_table_depth"),
            .keep_faces = keep_faces};
        Mesh fresh;
        Mesh& mesh = out_mesh(out, fresh, keep_faces, patches.size(), depth, "quad_mesh");
        {
          py::gil_scoped_release unlocked;
          ifs::quad_mesh(a, nets, patches, depth, mesh, o);
        }
        return mesh_result(out, std::move(fresh));
      },
      py::arg("automaton"), py::arg("nets"), py::arg("patches"), py::arg("depth"), py::kw_only(),
      py::arg("homogeneous").noconvert() = false, py::arg("max_bytes") = std::int64_t{1} << 30,
      py::arg("max_table_depth") = 6, py::arg("out") = py::none(), py::arg("keep_faces") = false,
      "The attractor at `depth` of any automaton with four children per state (GH, GB, DH, DB) as an "
      "io.Mesh of quads laid out as surface_mesh's.\n\n"
      "patches: per initial entry its (a, b) place in a grid they fill exactly once (int `(n, 2)` or list of "
      "pairs); other arguments (out, keep_faces too) as surface_mesh. Raises InvalidInput as surface_mesh, "
      "and "
      "for a state without four children or patches that do not tile a grid.");
  py::class_<ifs::MeshStencilTable>(
      m, "MeshStencilTable",
      "quad_mesh's (patch_meshes') topology built once (mesh_stencil_table) and applied to any nets of the "
      "automaton: the mesh analogue of StencilTable.")
      .def_readonly("depth", &ifs::MeshStencilTable::depth, "Depth K of the mesh.")
      .def_readonly("table_depth", &ifs::MeshStencilTable::table_depth, "Depth L of the precomposed tables.")
      .def(
          "apply",
          [](const ifs::MeshStencilTable& t, const std::vector<Points>& nets, bool homogeneous,
             std::int64_t max_bytes, Mesh* out, bool keep_faces) {
            const ifs::MeshOptions o{.homogeneous = homogeneous,
                                     .max_bytes = count_arg(max_bytes, "MeshStencilTable.apply: max_bytes"),
                                     .keep_faces = keep_faces};
            Mesh fresh;
            Mesh& mesh = out_mesh(out, fresh, keep_faces, t.automaton.initial.size(), t.depth,
                                  "MeshStencilTable.apply");
            {
              py::gil_scoped_release unlocked;
              ifs::apply_table(t, nets, mesh, o);
            }
            return mesh_result(out, std::move(fresh));
          },
          py::arg("nets"), py::kw_only(), py::arg("homogeneous").noconvert() = false,
          py::arg("max_bytes") = std::int64_t{1} << 30, py::arg("out") = py::none(),
          py::arg("keep_faces") = false,
          "The io.Mesh of these nets, the same as quad_mesh (patch_meshes). out, keep_faces: as "
          "surface_mesh's. "
          "Raises InvalidInput for nets that do not fit and a mesh above max_bytes.")
      .def("__repr__", [](const ifs::MeshStencilTable& t) {
        return "MeshStencilTable(depth " + std::to_string(t.depth) + ", table depth " +
               std::to_string(t.table_depth) + ", " +
               (t.patches.empty() ? "separate patches" : "a patch grid") + ")";
      });
  m.def(
      "mesh_stencil_table",
      [](const Automaton& a, int depth, const std::optional<std::vector<std::array<int, 2>>>& patches,
         int max_table_depth) {
        py::gil_scoped_release unlocked;
        return ifs::mesh_stencil_table(
            a, depth,
            {.patches = patches.value_or(std::vector<std::array<int, 2>>{}),
             .max_table_depth = non_negative(max_table_depth, "mesh_stencil_table: max_table_depth")});
      },
      py::arg("automaton"), py::arg("depth"), py::kw_only(), py::arg("patches") = py::none(),
      py::arg("max_table_depth") = 6,
      "Builds the MeshStencilTable of `automaton` at `depth`: patches as quad_mesh's, or None for "
      "patch_meshes' layout (each initial entry on its own). Raises InvalidInput as quad_mesh.");
}

/// Classic affine IFS.
void bind_classic(py::module_& m) {
  py::class_<AffineMap>(
      m, "AffineMap",
      "w(x, y) = (a·x + b·y + e, c·x + d·y + f), chosen with weight `probability` (Barnsley).")
      .def(py::init([](double a, double b, double c, double d, double e, double f, double probability) {
             return AffineMap{a, b, c, d, e, f, probability};
           }),
           py::kw_only(), py::arg("a") = 0.0, py::arg("b") = 0.0, py::arg("c") = 0.0, py::arg("d") = 0.0,
           py::arg("e") = 0.0, py::arg("f") = 0.0, py::arg("probability") = 1.0,
           "The map with these coefficients (keywords; unnamed ones are 0, probability 1).")
      .def_readonly("a", &AffineMap::a, "Coefficient of x in the new x.")
      .def_readonly("b", &AffineMap::b, "Coefficient of y in the new x.")
      .def_readonly("c", &AffineMap::c, "Coefficient of x in the new y.")
      .def_readonly("d", &AffineMap::d, "Coefficient of y in the new y.")
      .def_readonly("e", &AffineMap::e, "Translation in x.")
      .def_readonly("f", &AffineMap::f, "Translation in y.")
      .def_readonly("probability", &AffineMap::probability, "Weight of the map in Barnsley's chaos game.")
      .def("__repr__", [](const AffineMap& w) {
        return "AffineMap(a=" + num(w.a) + ", b=" + num(w.b) + ", c=" + num(w.c) + ", d=" + num(w.d) +
               ", e=" + num(w.e) + ", f=" + num(w.f) + ", probability=" + num(w.probability) + ")";
      });
  m.def("barnsley_fern", &ifs::barnsley_fern, "Barnsley's fern: 4 AffineMap (stem, leaflets, left, right).");
  m.def("sierpinski_triangle", &ifs::sierpinski_triangle,
        "Sierpinski's triangle on (0, 0), (1, 0), (½, √3/2): 3 AffineMap of ratio ½.");
  m.def("koch_curve", &ifs::koch_curve, "Koch's curve from (0, 0) to (1, 0): 4 AffineMap of ratio ⅓.");
  m.def("ifs_names", &ifs::ifs_names,
        "Names of the classic IFS above, in order: 'fern', 'sierpinski', 'koch' (an experiment file's "
        "\"ifs\").");
  m.def("named_ifs", &ifs::named_ifs, py::arg("name"),
        "The AffineMap list of a name in ifs_names(). Raises cifs.InvalidInput for another name (listing "
        "them).");
  m.def(
      "apply",
      [](const AffineMap& map, const Point& p) {
        if (p.size() != 2)
          throw InvalidInput("apply: the point has " + std::to_string(p.size()) +
                             " values, expected 2 (x, y)");
        return Point(ifs::apply(map, p));
      },
      py::arg("map"), py::arg("p"),
      "The image of the point p (2 values) under `map`, float `(2,)`. Raises InvalidInput for another size.");
  m.def("barycentric_matrix", &ifs::barycentric_matrix, py::arg("map"), py::arg("triangle"),
        "The `3 by 3` matrix M (rows summing to 1) with M @ triangle = the images of the triangle's "
        "corners.\n\n"
        "triangle: float `(3, 2)`, non-degenerate. Raises InvalidInput for another shape, a non-finite or "
        "degenerate triangle, or a non-finite coefficient.");
  m.def(
      "affine_automaton",
      [](const std::vector<AffineMap>& maps, const Points& triangle) {
        return ifs::affine_automaton(maps, triangle);
      },
      py::arg("maps"), py::arg("triangle"),
      "The one-state CIFS of a planar affine IFS on a control triangle: one transition \"w<i>\" per map, one "
      "initial entry whose net is `triangle`. Raises InvalidInput as barycentric_matrix, or for no map.");
}

/// Dimension: box counting.
void bind_box_counting(py::module_& m) {
  py::class_<ifs::BoxCount>(m, "BoxCount", "One scale of box counting: level k, box side ε, occupied boxes.")
      .def_readonly("level", &ifs::BoxCount::level, "Level k (box side size·2^-k).")
      .def_readonly("epsilon", &ifs::BoxCount::epsilon, "Box side ε.")
      .def_readonly("boxes", &ifs::BoxCount::boxes, "Number of occupied boxes N(ε).")
      .def("__repr__", [](const ifs::BoxCount& c) {
        return "BoxCount(level=" + std::to_string(c.level) + ", epsilon=" + num(c.epsilon) +
               ", boxes=" + std::to_string(c.boxes) + ")";
      });
  py::class_<ifs::BoxCountingResult>(m, "BoxCountingResult", "Result of box_counting.")
      .def_readonly("dimension", &ifs::BoxCountingResult::dimension,
                    "Least-squares slope of log N against log(1/ε) over the fit range.")
      .def_readonly("intercept", &ifs::BoxCountingResult::intercept, "Intercept of that line (natural logs).")
      .def_readonly("min_level", &ifs::BoxCountingResult::min_level, "First level of the fit range.")
      .def_readonly("max_level", &ifs::BoxCountingResult::max_level,
                    "Last level of the fit range (inclusive).")
      .def_readonly("max_epsilon", &ifs::BoxCountingResult::max_epsilon, "ε at min_level.")
      .def_readonly("min_epsilon", &ifs::BoxCountingResult::min_epsilon, "ε at max_level.")
      .def_readonly("r_squared", &ifs::BoxCountingResult::r_squared,
                    "Coefficient of determination of the fit.")
      .def_readonly("residual", &ifs::BoxCountingResult::residual,
                    "Largest |log N − line| over the fit range.")
      .def_readonly("standard_error", &ifs::BoxCountingResult::standard_error,
                    "Standard error of the slope (m − 2 degrees of freedom).")
      .def_readonly("spread", &ifs::BoxCountingResult::spread,
                    "Largest |local slope − dimension| over consecutive levels of the fit range.")
      .def_readonly("uncertainty", &ifs::BoxCountingResult::uncertainty,
                    "max(standard_error, spread): the reported uncertainty of the dimension.")
      .def_readonly("size", &ifs::BoxCountingResult::size,
                    "Side of the bounding cube of the points (ε at level 0).")
      .def_readonly("counts", &ifs::BoxCountingResult::counts, "List of BoxCount for levels 0 … levels.")
      .def_property_readonly(
          "count_levels",
          [](const ifs::BoxCountingResult& r) {
            std::vector<int> v;
            for (const auto& c : r.counts) v.push_back(c.level);
            return vector_array(v);
          },
          "The counts' levels as an int array.")
      .def_property_readonly(
          "count_epsilons",
          [](const ifs::BoxCountingResult& r) {
            std::vector<double> v;
            for (const auto& c : r.counts) v.push_back(c.epsilon);
            return vector_array(v);
          },
          "The counts' box sides as a float array.")
      .def_property_readonly(
          "count_boxes",
          [](const ifs::BoxCountingResult& r) {
            std::vector<std::uint64_t> v;
            for (const auto& c : r.counts) v.push_back(c.boxes);
            return vector_array(v);
          },
          "The counts' occupied boxes as an int array.")
      .def("__repr__", [](const ifs::BoxCountingResult& r) {
        return "BoxCountingResult(dimension=" + num(r.dimension) + " ± " + num(r.uncertainty) + ", levels " +
               std::to_string(r.min_level) + "…" + std::to_string(r.max_level) +
               ", r_squared=" + num(r.r_squared) + ")";
      });
  m.def(
      "box_counting",
      [](const Points& points, double resolution, double points_per_box, std::int64_t min_boxes,
         int min_level, int max_level, int levels) {
        const ifs::BoxCountingOptions o{.resolution = resolution,
                                        .points_per_box = points_per_box,
                                        .min_boxes = count_arg(min_boxes, "box counting: min_boxes"),
                                        .min_level = min_level,
                                        .max_level = max_level,
                                        .levels = levels};
        py::gil_scoped_release unlocked;
        return ifs::box_counting(points, o);
      },
      py::arg("points"), py::kw_only(), py::arg("resolution") = 0.0, py::arg("points_per_box") = 4.0,
      py::arg("min_boxes") = 1000, py::arg("min_level") = -1, py::arg("max_level") = -1,
      py::arg("levels") = 20,
      "Box-counting dimension of the set sampled by `points` (float `(n, dim)`, finite); a "
      "BoxCountingResult.\n\n"
      "resolution: largest diameter of the pieces the sample stands for (0: unknown); points_per_box and "
      "min_boxes: the automatic fit range's fine and coarse limits; min_level, max_level: a fit range given "
      "by the user (-1: automatic); levels: finest level counted. Raises InvalidInput for no points, a "
      "non-finite point, all points equal, a bad range, or fewer than 3 reliable levels.");
}

/// Dimension: similarity and Mauldin–Williams dimensions.
void bind_similarity(py::module_& m) {
  py::class_<ifs::SimilarityEdge>(
      m, "SimilarityEdge", "A map of a graph-directed system: from state `source` into `target`, ratio.")
      .def(py::init([](std::int64_t source, std::int64_t target, double ratio) {
             if (source < 0 || target < 0)
               throw InvalidInput("SimilarityEdge: state " + std::to_string(source < 0 ? source : target) +
                                  " is negative");
             return ifs::SimilarityEdge{static_cast<StateId>(source), static_cast<StateId>(target), ratio};
           }),
           py::arg("source"), py::arg("target"), py::arg("ratio"),
           "The edge source → target of ratio `ratio`.")
      .def_readonly("source", &ifs::SimilarityEdge::from, "State the map leaves (C++ `from`).")
      .def_readonly("target", &ifs::SimilarityEdge::to, "State the map enters (C++ `to`).")
      .def_readonly("ratio", &ifs::SimilarityEdge::ratio, "Contraction ratio of the similarity.")
      .def("__repr__", [](const ifs::SimilarityEdge& e) {
        return "SimilarityEdge(" + std::to_string(e.from) + " -> " + std::to_string(e.to) +
               ", ratio=" + num(e.ratio) + ")";
      });
  m.def(
      "mauldin_williams_dimension",
      [](std::int64_t states, const py::iterable& edges) {
        std::vector<ifs::SimilarityEdge> list;
        for (const py::handle item : edges) list.push_back(similarity_edge(item, list.size()));
        const auto n = count_arg(states, "mauldin_williams_dimension: states");
        py::gil_scoped_release unlocked;
        return ifs::mauldin_williams_dimension(n, list);
      },
      py::arg("states"), py::arg("edges"),
      "Mauldin–Williams dimension of a graph-directed system of similarities on `states` states: the s ≥ 0 "
      "with spectral radius ρ(A(s)) = 1.\n\n"
      "edges: SimilarityEdge objects or (from, to, ratio) tuples. Raises InvalidInput for a ratio that is "
      "not "
      "finite and > 0, a state out of range, a graph without cycle, or cycles that do not contract.");
  m.def(
      "similarity_ratio", &ifs::similarity_ratio, py::arg("L"),
      "Ratio r of the similarity x ↦ x·L + b (L float `(dim, dim)`): LᵀL = r²I to 1e-12 of r², or -1 when L "
      "is not r times an orthogonal matrix.");
  m.def(
      "similarity_dimension",
      [](const std::vector<AffineMap>& maps) { return ifs::similarity_dimension(maps); }, py::arg("maps"),
      "Similarity (Moran) dimension of a planar IFS (list of AffineMap): the s with Σ r_i^s = 1. Raises "
      "InvalidInput for no map, a map that is not a similarity (named, with its LᵀL) or a ratio ≥ 1.");
  m.def(
      "similarity_dimension",
      [](const Automaton& a, const std::vector<Points>& nets) {
        py::gil_scoped_release unlocked;
        return ifs::similarity_dimension(a, nets);
      },
      py::arg("automaton"), py::arg("nets"),
      "Similarity dimension of the attractor of a CIFS whose transitions act as similarities on the nets "
      "(one Cartesian net per initial entry): the Mauldin–Williams dimension of their ratios. Raises "
      "InvalidInput when a transition is not a similarity between the reference nets (named), and as "
      "mauldin_williams_dimension.");
}

}  // namespace

void bind_ifs(py::module_& m) {
  bind_analysis(m);
  bind_leaves(m);
  bind_piece_bounds(m);
  bind_samples(m);
  bind_chaos(m);
  bind_meshes(m);
  bind_classic(m);
  bind_box_counting(m);
  bind_similarity(m);
}

}  // namespace cifs::python
