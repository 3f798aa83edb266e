// SPDX-License-Identifier: MIT
// cifs — Graphviz DOT: automata, written by hand in the layout of Boost.Graph's write_graphviz
// (which wrote it before the automaton became plain data), so that files stay byte-identical.
#include "cifs/io/dot.hpp"

#include <cmath>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs::io {
namespace {

/// A DOT quoted string's contents: `"` and `\` escaped, a newline as DOT's `\n` (a label may be any
/// text of an automaton file).
std::string dot_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

}  // namespace

std::string to_dot(const nurbs::KnotAutomaton& k) {
  const automata::Automaton& a = k.automaton;
  std::vector<bool> is_initial(num_vertices(a.graph), false);
  for (const automata::Initial& i : a.initial) is_initial[i.state] = true;
  std::string out = "digraph G {\nrankdir=LR;\nnode [shape=circle, fontsize=10];\n";
  for (automata::StateId s = 0; s < num_vertices(a.graph); ++s) {
    const automata::State& st = a.graph[s];
    std::string label = "s" + std::to_string(s);
    // A name that says more than the id (a surface automaton's "E5", "B3"; a tensor pair's "(s0,s1)").
    if (!st.name.empty() && st.name != label) label += "\\n" + dot_escape(st.name);
    if (s < k.windows.size() && !k.windows[s].empty()) {
      const nurbs::Window& window = k.windows[s];
      for (const double x : window)
        if (!std::isfinite(x))
          throw InvalidInput("the automaton's state " + std::to_string(s) +
                             ": a value of its window is not a finite number; nothing is written");
      label += "\\n(";
      // Six significant digits: enough to tell windows apart at a glance.
      for (std::size_t i = 0; i < window.size(); ++i) label += (i ? ", " : "") + number_text(window[i], 6);
      label += ")";
    }
    out += std::to_string(s) + "[label=\"" + label + "\"" + (st.recurrent ? ", peripheries=2" : "") +
           (is_initial[s] ? ", style=bold" : "") + "];\n";
  }
  // State by state in out-order, as write_graphviz visited them.
  for (const automata::TransitionId e : edges(a.graph))
    out += std::to_string(source(e, a.graph)) + "->" + std::to_string(target(e, a.graph)) + " [label=\"" +
           dot_escape(a.graph[e].label) + "\"];\n";
  out += "}\n";
  return out;
}

std::string to_dot(const automata::Automaton& a) {
  return to_dot(nurbs::without_knots(a));
}

}  // namespace cifs::io
