// SPDX-License-Identifier: MIT
#include "cifs/nurbs/tensor_automaton.hpp"

#include <deque>
#include <map>

#include "cifs/errors.hpp"

namespace cifs::nurbs {

using automata::Graph;
using automata::Initial;
using automata::kron;
using automata::StateId;
using automata::v_label;

TensorAutomaton tensor_automaton(const nurbs::Surface& surface) {
  validate(surface);
  TensorAutomaton t;
  for (auto dir : {Direction::u, Direction::v})
    t.factors[static_cast<std::size_t>(dir)] = knot_automaton(direction_curve(surface, dir));
  const Graph& gu = t.factors[0].automaton.graph;
  const Graph& gv = t.factors[1].automaton.graph;

  std::map<std::array<StateId, 2>, StateId> ids;
  std::deque<StateId> todo;
  const auto state_of = [&](std::array<StateId, 2> pair) {
    const auto [it, added] = ids.try_emplace(pair, 0);
    if (added) {
      const StateId s =
          add_vertex(automata::State{.size = gu[pair[0]].size * gv[pair[1]].size,
                                     .recurrent = false,
                                     .name = "(" + gu[pair[0]].name + "," + gv[pair[1]].name + ")"},
                     t.product.graph);
      it->second = s;
      t.factor_states.push_back(pair);
      todo.push_back(s);
    }
    return it->second;
  };
  const auto nv_seg = static_cast<int>(t.factors[1].automaton.initial.size());
  for (const Initial& a : t.factors[0].automaton.initial)
    for (const Initial& b : t.factors[1].automaton.initial) {
      Initial init;
      init.segment = a.segment * nv_seg + b.segment;
      init.state = state_of({a.state, b.state});
      t.product.initial.push_back(init);
      t.patches.push_back({a.segment, b.segment});
    }
  while (!todo.empty()) {
    const StateId s = todo.front();
    todo.pop_front();
    const auto [p, q] = t.factor_states[s];
    for (auto [eu, eu_end] = out_edges(p, gu); eu != eu_end; ++eu)
      for (auto [ev, ev_end] = out_edges(q, gv); ev != ev_end; ++ev) {
        const StateId child = state_of({target(*eu, gu), target(*ev, gv)});
        add_edge(s, child,
                 automata::Transition{gu[*eu].label + v_label(gv[*ev].label),
                                      kron(gu[*eu].matrix, gv[*ev].matrix)},
                 t.product.graph);
      }
  }
  automata::mark_recurrent(t.product);
  return t;
}

std::vector<Points> initial_nets(const TensorAutomaton& t, const Surface& s) {
  const int p = s.degree[0], q = s.degree[1];
  if (t.patches.size() != t.product.initial.size())
    throw InvalidInput("the tensor automaton has " + std::to_string(t.product.initial.size()) +
                       " initial entries but " + std::to_string(t.patches.size()) +
                       " patches; build it with tensor_automaton from this surface");
  std::vector<Points> nets;
  nets.reserve(t.patches.size());
  for (std::size_t k = 0; k < t.patches.size(); ++k) {
    std::array<int, 2> span{};
    for (std::size_t dir = 0; dir < 2; ++dir) {
      const auto& initial = t.factors[dir].automaton.initial;
      const auto& intervals = t.factors[dir].intervals;
      const int segment = t.patches[k][dir];
      if (segment < 0 || static_cast<std::size_t>(segment) >= initial.size())
        throw InvalidInput("the tensor automaton's patch " + std::to_string(k) + " names segment " +
                           std::to_string(segment) + " of direction " + (dir ? "v" : "u") + ", which has " +
                           std::to_string(initial.size()));
      span[dir] = static_cast<std::size_t>(segment) < intervals.size()
                      ? intervals[static_cast<std::size_t>(segment)].span
                      : -1;
      if (span[dir] < s.degree[dir] || span[dir] >= s.count[dir])
        throw InvalidInput("the tensor automaton's patch " + std::to_string(k) +
                           " has no span in direction " + (dir ? "v" : "u") +
                           " of this surface; build it from this surface");
    }
    const StateId state = t.product.initial[k].state;
    if (t.product.graph[state].size != (p + 1) * (q + 1))
      throw InvalidInput("the tensor automaton's patch " + std::to_string(k) + " has a state of " +
                         std::to_string(t.product.graph[state].size) + " points but the surface's degrees (" +
                         std::to_string(p) + ", " + std::to_string(q) + ") give " +
                         std::to_string((p + 1) * (q + 1)));
    Points net((p + 1) * (q + 1), s.P.cols());
    for (int i = 0; i <= p; ++i)
      net.middleRows(Eigen::Index{i} * (q + 1), q + 1) =
          s.P.middleRows((span[0] - p + i) * s.count[1] + span[1] - q, q + 1);
    nets.push_back(std::move(net));
  }
  return nets;
}

}  // namespace cifs::nurbs
