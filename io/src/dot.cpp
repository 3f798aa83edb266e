// SPDX-License-Identifier: MIT
// cifs — Graphviz DOT: automata, through Boost.Graph's write_graphviz.
#include "cifs/io/dot.hpp"

#include <boost/graph/graphviz.hpp>
#include <sstream>

#include "cifs/format.hpp"

namespace cifs::io {
namespace {}  // namespace

std::string to_dot(const nurbs::KnotAutomaton& k) {
  const automata::Automaton& a = k.automaton;
  std::vector<bool> is_initial(boost::num_vertices(a.graph), false);
  for (const automata::Initial& i : a.initial) is_initial[i.state] = true;
  std::ostringstream out;
  boost::write_graphviz(
      out, a.graph,
      [&](std::ostream& o, automata::StateId s) {
        const automata::State& st = a.graph[s];
        std::string label = "s" + std::to_string(s);
        if (s < k.windows.size() && !k.windows[s].empty()) {
          const nurbs::Window& window = k.windows[s];
          label += "\\n(";
          // Six significant digits: enough to tell windows apart at a glance.
          for (std::size_t i = 0; i < window.size(); ++i)
            label += (i ? ", " : "") + number_text(window[i], 6);
          label += ")";
        }
        o << "[label=\"" << label << "\"" << (st.recurrent ? ", peripheries=2" : "")
          << (is_initial[s] ? ", style=bold" : "") << "]";
      },
      [&](std::ostream& o, automata::TransitionId e) { o << "[label=\"" << a.graph[e].label << "\"]"; },
      [](std::ostream& o) { o << "rankdir=LR;\nnode [shape=circle, fontsize=10];\n"; });
  return out.str();
}

std::string to_dot(const automata::Automaton& a) {
  return to_dot(nurbs::without_knots(a));
}

}  // namespace cifs::io
