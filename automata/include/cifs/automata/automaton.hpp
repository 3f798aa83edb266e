// SPDX-License-Identifier: MIT
// cifs — automata whose transitions carry subdivision matrices (topology and stencils, no
// coordinates), on Boost.Graph; the knot-doubling automaton of a NURBS curve.
#pragma once

#include <Eigen/Core>
#include <boost/graph/adjacency_list.hpp>
#include <string>
#include <vector>

#include "cifs/nurbs/curve.hpp"

namespace cifs::automata {

/// A state: the control nets it holds have `size` points.
struct State {
  int size = 0;
  /// Knot-doubling states: the inter-knot window, normalised so that its centre is 1 (the key that
  /// identifies the state, compared exactly). Empty for hand-made automata.
  std::vector<double> window;
  /// True when the state occurs at arbitrarily deep levels: it lies on a cycle (a strong component
  /// with a cycle) or is reachable from one. For generic knots, 2d − 1 of a segment's 4(d − 1)
  /// states recur (Morlet et al.); the others are the transient states of the first levels.
  bool recurrent = false;
  std::string name;
};

/// A transition `from → to`: the child net is `Q = matrix · P`, `matrix` is
/// `to.size by from.size`, rows summing to 1 (affine combinations).
struct Transition {
  std::string label;  // "G", "D" for knot doubling; anything for hand-made automata
  Eigen::MatrixXd matrix;
};

/// Out-edges keep their insertion order, which is the order of the children along the shape
/// (G before D): the attractor is produced in curve order.
using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::bidirectionalS, State, Transition>;
using StateId = Graph::vertex_descriptor;
using TransitionId = Graph::edge_descriptor;

/// Where the shape's pieces start: one entry per segment (non-empty knot interval).
struct Initial {
  int segment = 0;
  StateId state = 0;
  /// Knot-doubling automata: the segment's knot interval and its span in the curve's knot
  /// vector; the segment's net is rows `span − d … span` of the curve's points.
  double start = 0, end = 0;
  int span = -1;
};

struct Automaton {
  Graph graph;
  std::vector<Initial> initial;
};

/// The knot-doubling automaton of a curve: one initial state per segment, states = windows up to
/// scale (shared between segments, e.g. the uniform state), transitions G and D with the matrices
/// of nurbs::subdivision_matrix; recurrent states marked. Built from the knots alone.
Automaton knot_automaton(const nurbs::Curve& curve);

/// Marks `recurrent` from the strong components (Boost.Graph) and reachability from them.
void mark_recurrent(Automaton& automaton);

/// Merges states that no control net can tell apart: same size and, transition by transition in
/// order, identical labels and matrices (exactly) leading to merged states (Moore partition
/// refinement). Initial states are kept (redirected to their class).
Automaton minimize(const Automaton& automaton);

/// Control net of every initial entry of a knot automaton built from `curve`: `d+1 by cols`
/// rows of `curve.P` (homogeneous when rational).
std::vector<Points> initial_nets(const Automaton& automaton, const nurbs::Curve& curve);

}  // namespace cifs::automata
