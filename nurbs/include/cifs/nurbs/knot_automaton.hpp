// SPDX-License-Identifier: MIT
// cifs — the knot-doubling automaton of a NURBS curve: a generic automaton (cifs/automata) and the
// knot data that only NURBS shapes have (the windows of the states, the knot intervals and spans of
// the segments), kept beside it.
#pragma once

#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/doubling.hpp"

namespace cifs::nurbs {

/// A segment of a curve: its knot interval and its span in the knot vector; the segment's net is
/// rows `span − d … span` of the curve's points. Unset: (0, 0, −1).
struct KnotInterval {
  double start = 0, end = 0;
  int span = -1;
};

/// An automaton with the knot data of its states and initial entries. The engine (ifs, render,
/// analysis) takes `automaton`; building nets (initial_nets), the curve BC-IFS and the automaton
/// files read the rest. A generic automaton has no knot data (without_knots): empty windows, unset
/// intervals.
struct KnotAutomaton {
  automata::Automaton automaton;
  /// Per state (StateId): the inter-knot window normalised so that its centre is 1 (the key that
  /// identifies the state, compared exactly); empty for states that are not knot-doubling states.
  std::vector<Window> windows;
  /// Per entry of `automaton.initial`: the segment's interval and span.
  std::vector<KnotInterval> intervals;
};

/// The window of the curve's segment on the non-empty span `span`: segment_window of its knots for
/// an open curve; for a closed curve the cyclic differences `b_{k+1} − b_k` of its breakpoints, never
/// differences of the extended knots (`b_k ± T` are rounded: next to a short interval, the rounding
/// of a long period would be a relative error in every matrix).
Window segment_window(const Curve& curve, int span);

/// The knot-doubling automaton of a curve: one initial state per segment, states = windows up to
/// scale (shared between segments, e.g. the uniform state), transitions G and D with the matrices
/// of nurbs::subdivision_matrix; recurrent states marked. Built from the knots alone.
KnotAutomaton knot_automaton(const Curve& curve);

/// `automaton` with no knot data: one empty window per state, one unset interval per initial entry.
KnotAutomaton without_knots(automata::Automaton automaton);

/// automata::minimize, the knot data kept: a merged state has the window of the first state of its
/// class, initial entries keep their intervals.
KnotAutomaton minimize(const KnotAutomaton& automaton);

/// Control net of every initial entry of a knot automaton built from `curve`: `d+1 by cols`
/// rows of `curve.P` (homogeneous when rational). Throws InvalidInput when an entry has no span in
/// `curve`.
std::vector<Points> initial_nets(const KnotAutomaton& automaton, const Curve& curve);

}  // namespace cifs::nurbs
