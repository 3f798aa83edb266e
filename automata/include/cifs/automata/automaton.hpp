// SPDX-License-Identifier: MIT
// cifs — automata whose transitions carry subdivision matrices (topology and stencils, no
// coordinates), as plain data: Boost.Graph stays inside the algorithms' sources (strong
// components), out of this header, which most of the library includes. Generic: the knot-doubling automaton
// of a NURBS curve and its knot data (windows, intervals, spans) live in nurbs
// (cifs/nurbs/knot_automaton.hpp).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
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

using StateId = std::size_t;

/// A transition's index in `Graph::transitions` (its insertion rank). A distinct type so that
/// `graph[state]` and `graph[transition]` overload.
struct TransitionId {
  std::size_t index = 0;
  friend bool operator==(TransitionId, TransitionId) = default;
  friend auto operator<=>(TransitionId, TransitionId) = default;
};

/// The states and transitions, with each state's out-transitions in insertion order, which is
/// the order of the children along the shape (G before D): the attractor is produced in curve
/// order. The free functions below keep the names and semantics of the Boost.Graph
/// (adjacency_list<vecS, vecS, bidirectionalS>) calls the library was written against.
struct Graph {
  struct Edge {
    StateId source = 0, target = 0;
    Transition transition;
  };
  std::vector<State> states;
  std::vector<Edge> transitions;
  std::vector<std::vector<TransitionId>> out;  // per state, in insertion order

  State& operator[](StateId s) { return states[s]; }
  const State& operator[](StateId s) const { return states[s]; }
  Transition& operator[](TransitionId e) { return transitions[e.index].transition; }
  const Transition& operator[](TransitionId e) const { return transitions[e.index].transition; }
};

/// A state's out-transitions: a range, and (first, second) like Boost's iterator pairs.
struct OutEdges {
  const TransitionId* first = nullptr;
  const TransitionId* second = nullptr;
  const TransitionId* begin() const { return first; }
  const TransitionId* end() const { return second; }
};

inline std::size_t num_vertices(const Graph& g) {
  return g.states.size();
}
inline std::size_t num_edges(const Graph& g) {
  return g.transitions.size();
}
inline StateId source(TransitionId e, const Graph& g) {
  return g.transitions[e.index].source;
}
inline StateId target(TransitionId e, const Graph& g) {
  return g.transitions[e.index].target;
}
inline std::size_t out_degree(StateId s, const Graph& g) {
  return g.out[s].size();
}
inline OutEdges out_edges(StateId s, const Graph& g) {
  return {g.out[s].data(), g.out[s].data() + g.out[s].size()};
}

inline StateId add_vertex(State state, Graph& g) {
  g.states.push_back(std::move(state));
  g.out.emplace_back();
  return g.states.size() - 1;
}
inline StateId add_vertex(Graph& g) {
  return add_vertex(State{}, g);
}

/// Appends `from → to` after the other out-transitions of `from`; the bool is always true
/// (parallel transitions allowed). As in Boost (vecS), states up to `max(from, to)` are added.
inline std::pair<TransitionId, bool> add_edge(StateId from, StateId to, Transition transition, Graph& g) {
  if (const StateId n = std::max(from, to) + 1; n > g.states.size()) {
    g.states.resize(n);
    g.out.resize(n);
  }
  const TransitionId e{g.transitions.size()};
  g.transitions.push_back({from, to, std::move(transition)});
  g.out[from].push_back(e);
  return {e, true};
}

/// The first transition `from → to` in `from`'s out-order, and whether there is one.
std::pair<TransitionId, bool> edge(StateId from, StateId to, const Graph& g);

/// All transitions, state by state in out-order (Boost's `edges` order on vecS, which the JSON
/// writer relies on) — not insertion order.
std::vector<TransitionId> edges(const Graph& g);

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
