// SPDX-License-Identifier: MIT
// cifs — automata whose transitions carry subdivision matrices (topology and stencils, no
// coordinates), on Boost.Graph. Generic: the knot-doubling automaton of a NURBS curve and its knot
// data (windows, intervals, spans) live in nurbs (cifs/nurbs/knot_automaton.hpp).
#pragma once

#include <Eigen/Core>
#include <boost/graph/adjacency_list.hpp>
#include <string>
#include <vector>

namespace cifs::automata {

/// A state: the control nets it holds have `size` points.
struct State {
  int size = 0;
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
};

struct Automaton {
  Graph graph;
  std::vector<Initial> initial;
};

/// Marks `recurrent` from the strong components (Boost.Graph) and reachability from them.
void mark_recurrent(Automaton& automaton);

/// Merges states that no control net can tell apart: same size and, transition by transition in
/// order, identical labels and matrices (exactly) leading to merged states (Moore partition
/// refinement). Initial states are kept (redirected to their class).
Automaton minimize(const Automaton& automaton);

/// The classes of minimize, per state, numbered in the order of their first state: class k is
/// state k of minimize's result and copies the first state of the class (for data kept beside
/// the automaton, e.g. nurbs::minimize's windows).
std::vector<std::size_t> minimize_classes(const Automaton& automaton);

}  // namespace cifs::automata
