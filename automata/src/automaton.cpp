// SPDX-License-Identifier: MIT
#include "cifs/automata/automaton.hpp"

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/strong_components.hpp>
#include <map>

namespace cifs::automata {
namespace {

std::vector<double> matrix_key(const Eigen::MatrixXd& M) {
  std::vector<double> key{static_cast<double>(M.rows()), static_cast<double>(M.cols())};
  key.insert(key.end(), M.data(), M.data() + M.size());
  return key;
}

}  // namespace

std::pair<TransitionId, bool> edge(StateId from, StateId to, const Graph& g) {
  for (const TransitionId e : out_edges(from, g))
    if (target(e, g) == to) return {e, true};
  return {TransitionId{}, false};
}

std::vector<TransitionId> edges(const Graph& g) {
  std::vector<TransitionId> out;
  out.reserve(num_edges(g));
  for (const std::vector<TransitionId>& list : g.out) out.insert(out.end(), list.begin(), list.end());
  return out;
}

void mark_recurrent(Automaton& a) {
  // A state recurs when it occurs at arbitrarily deep levels of the unfolded automaton: it lies on
  // a cycle (a strong component with more than one state or a self-loop) or below one.
  const auto n = num_vertices(a.graph);
  // Boost.Graph on a bare copy of the topology: the public Graph stays plain data, so that the
  // headers most of the library includes do not pull Boost.Graph in.
  boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS> topology(n);
  for (const Graph::Edge& e : a.graph.transitions) boost::add_edge(e.source, e.target, topology);
  std::vector<std::size_t> component(n);
  boost::strong_components(topology, boost::make_iterator_property_map(
                                         component.begin(), boost::get(boost::vertex_index, topology)));
  std::vector<int> members(n, 0);
  for (std::size_t c : component) ++members[c];
  std::vector<StateId> stack;
  for (StateId s = 0; s < n; ++s) {
    a.graph[s].recurrent = members[component[s]] > 1;
    for (auto [e, end] = out_edges(s, a.graph); e != end; ++e)
      a.graph[s].recurrent = a.graph[s].recurrent || target(*e, a.graph) == s;
    if (a.graph[s].recurrent) stack.push_back(s);
  }
  while (!stack.empty()) {
    const StateId s = stack.back();
    stack.pop_back();
    for (auto [e, end] = out_edges(s, a.graph); e != end; ++e) {
      const StateId t = target(*e, a.graph);
      if (!a.graph[t].recurrent) {
        a.graph[t].recurrent = true;
        stack.push_back(t);
      }
    }
  }
}

std::vector<std::size_t> minimize_classes(const Automaton& a) {
  const auto n = num_vertices(a.graph);
  // Initial classes: size and the ordered (label, matrix) of the out-edges.
  std::vector<std::size_t> cls(n);
  {
    std::map<std::vector<std::vector<double>>, std::size_t> first;
    std::map<std::vector<std::string>, std::size_t> labels;
    for (StateId s = 0; s < n; ++s) {
      std::vector<std::vector<double>> key{{static_cast<double>(a.graph[s].size)}};
      std::vector<std::string> label_key;
      for (auto [e, end] = out_edges(s, a.graph); e != end; ++e) {
        key.push_back(matrix_key(a.graph[*e].matrix));
        label_key.push_back(a.graph[*e].label);
      }
      key.push_back({static_cast<double>(labels.try_emplace(label_key, labels.size()).first->second)});
      cls[s] = first.try_emplace(key, first.size()).first->second;
    }
  }
  // Moore refinement: split classes by the classes of the children, until stable.
  for (std::size_t count = 0;;) {
    std::map<std::vector<std::size_t>, std::size_t> next_ids;
    std::vector<std::size_t> next(n);
    for (StateId s = 0; s < n; ++s) {
      std::vector<std::size_t> key{cls[s]};
      for (auto [e, end] = out_edges(s, a.graph); e != end; ++e) key.push_back(cls[target(*e, a.graph)]);
      next[s] = next_ids.try_emplace(key, next_ids.size()).first->second;
    }
    cls.swap(next);
    if (next_ids.size() == count) break;
    count = next_ids.size();
  }
  return cls;
}

Automaton minimize(const Automaton& a) {
  const auto n = num_vertices(a.graph);
  const std::vector<std::size_t> cls = minimize_classes(a);
  // Quotient: the first state of each class represents it.
  Automaton out;
  std::map<std::size_t, StateId> rep;
  for (StateId s = 0; s < n; ++s)
    if (rep.try_emplace(cls[s], 0).second) {
      rep[cls[s]] = add_vertex(a.graph[s], out.graph);
      out.graph[rep[cls[s]]].name = "s" + std::to_string(rep[cls[s]]);
    }
  std::vector<bool> done(rep.size(), false);
  for (StateId s = 0; s < n; ++s) {
    if (done[cls[s]]) continue;
    done[cls[s]] = true;
    for (auto [e, end] = out_edges(s, a.graph); e != end; ++e)
      add_edge(rep[cls[s]], rep[cls[target(*e, a.graph)]], a.graph[*e], out.graph);
  }
  for (Initial i : a.initial) {
    i.state = rep[cls[i.state]];
    out.initial.push_back(i);
  }
  mark_recurrent(out);
  return out;
}

}  // namespace cifs::automata
