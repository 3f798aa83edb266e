// SPDX-License-Identifier: MIT
#include "cifs/nurbs/knot_automaton.hpp"

#include <deque>
#include <map>
#include <string>

#include "cifs/errors.hpp"
#include "detail.hpp"

namespace cifs::nurbs {
namespace {

using automata::StateId;

constexpr const char* kHalfLabel[2] = {"G", "D"};

}  // namespace

Window segment_window(const Curve& curve, int span) {
  const int d = curve.degree;
  if (!curve.closed) return segment_window(curve.knots, d, span);
  const int m = static_cast<int>(curve.P.rows()) - d;
  const auto b = [&](int k) {
    return curve.knots[static_cast<std::size_t>(d) + static_cast<std::size_t>(k)];
  };
  Window w(static_cast<std::size_t>(2 * d - 1));
  for (int i = 0; i < 2 * d - 1; ++i) {
    const int k = detail::periodic_index(span - d + 1 + i, d, m).k;
    w[static_cast<std::size_t>(i)] = b(k + 1) - b(k);
  }
  return w;
}

KnotAutomaton knot_automaton(const Curve& curve) {
  const int d = curve.degree;
  KnotAutomaton k;
  automata::Automaton& a = k.automaton;
  std::map<Window, StateId> ids;  // normalised window → state
  std::deque<StateId> todo;
  const auto state_of = [&](Window window) {
    const auto [it, added] = ids.try_emplace(window, 0);
    if (added) {
      it->second = add_vertex(automata::State{.size = d + 1, .recurrent = false, .name = ""}, a.graph);
      a.graph[it->second].name = "s" + std::to_string(it->second);
      k.windows.push_back(std::move(window));
      todo.push_back(it->second);
    }
    return it->second;
  };
  int segment = 0;
  for (int span = d; span < curve.P.rows(); ++span) {
    const double lo = curve.knots[static_cast<std::size_t>(span)],
                 hi = curve.knots[static_cast<std::size_t>(span) + 1];
    if (!(lo < hi)) continue;
    Window w = segment_window(curve, span);
    const double centre = w[static_cast<std::size_t>(d - 1)];
    for (double& x : w) x /= centre;  // up to scale: the centre is 1 (exactly)
    a.initial.push_back(automata::Initial{.segment = segment++, .state = state_of(std::move(w))});
    k.intervals.push_back(KnotInterval{.start = lo, .end = hi, .span = span});
  }
  // Children of a normalised window are made of its own entries and keep a unit centre, so the
  // keys stay exact: no arithmetic happens after the first normalisation.
  while (!todo.empty()) {
    const StateId s = todo.front();
    todo.pop_front();
    const Window window = k.windows[s];
    for (auto half : {Half::G, Half::D}) {
      const StateId child = state_of(child_window(window, d, half));
      add_edge(s, child,
               automata::Transition{kHalfLabel[static_cast<int>(half)], subdivision_matrix(window, d, half)},
               a.graph);
    }
  }
  automata::mark_recurrent(a);
  return k;
}

KnotAutomaton without_knots(automata::Automaton automaton) {
  KnotAutomaton k;
  k.windows.resize(num_vertices(automaton.graph));
  k.intervals.resize(automaton.initial.size());
  k.automaton = std::move(automaton);
  return k;
}

KnotAutomaton minimize(const KnotAutomaton& k) {
  KnotAutomaton out{.automaton = automata::minimize(k.automaton), .windows = {}, .intervals = k.intervals};
  const std::vector<std::size_t> cls = automata::minimize_classes(k.automaton);
  out.windows.resize(num_vertices(out.automaton.graph));
  std::vector<bool> done(out.windows.size(), false);
  for (std::size_t s = 0; s < cls.size() && s < k.windows.size(); ++s)
    if (!done[cls[s]]) {
      done[cls[s]] = true;
      out.windows[cls[s]] = k.windows[s];
    }
  return out;
}

std::vector<Points> initial_nets(const KnotAutomaton& k, const Curve& curve) {
  std::vector<Points> nets;
  for (std::size_t i = 0; i < k.automaton.initial.size(); ++i) {
    const int span = i < k.intervals.size() ? k.intervals[i].span : -1;
    if (span < curve.degree || span >= curve.P.rows())
      throw InvalidInput("the knot automaton's segment " + std::to_string(k.automaton.initial[i].segment) +
                         " has no span in this curve; build it with knot_automaton from this curve");
    nets.push_back(curve.P.middleRows(span - curve.degree, curve.degree + 1));
  }
  return nets;
}

}  // namespace cifs::nurbs
