// SPDX-License-Identifier: MIT
// cifs — Graphviz DOT (written only): automata.
#pragma once

#include <string>

#include "cifs/automata/automaton.hpp"
#include "cifs/nurbs/knot_automaton.hpp"

namespace cifs::io {

/// The automaton for `dot -Tsvg`: left to right, states labelled `s<id>`, their name where it is not
/// that, and their window (knot automata), recurrent states with a double circle, initial states in bold,
/// transitions labelled.
std::string to_dot(const nurbs::KnotAutomaton& automaton);
/// A generic automaton (no windows): to_dot(nurbs::without_knots(automaton)).
std::string to_dot(const automata::Automaton& automaton);

}  // namespace cifs::io
