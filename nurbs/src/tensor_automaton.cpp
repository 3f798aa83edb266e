// SPDX-License-Identifier: MIT
#include "cifs/nurbs/tensor_automaton.hpp"

#include <deque>
#include <map>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"

namespace cifs::nurbs {

using automata::Graph;
using automata::Initial;
using automata::kron;
using automata::StateId;

namespace {

/// The label of a factor's half in direction d: u's G/D, v's H/B, w's A/R.
std::string direction_label(std::size_t d, const std::string& label) {
  return d == 0 ? label : d == 1 ? automata::v_label(label) : automata::w_label(label);
}

/// The product of N knot automata (surfaces: 2, volumes: 3): states = reachable N-tuples of factor
/// states, found breadth first from the initial tuples; out-edges of a tuple in mixed-radix order of
/// the factors' out-edges (the last factor fastest), label the factors' labels in order, matrix the
/// Kronecker product of the factors' matrices folded from the left; initial entries every tuple of
/// the factors' initial entries in the same order.
template <std::size_t N>
struct Product {
  automata::Automaton automaton;
  std::vector<std::array<StateId, N>> factor_states;
  std::vector<std::array<int, N>> segments;  // per initial entry
};

template <std::size_t N>
Product<N> product_of(const std::array<KnotAutomaton, N>& factors) {
  Product<N> out;
  std::map<std::array<StateId, N>, StateId> ids;
  std::deque<StateId> todo;
  const auto state_of = [&](const std::array<StateId, N>& tuple) {
    const auto [it, added] = ids.try_emplace(tuple, 0);
    if (added) {
      int size = 1;
      std::string name = "(";
      for (std::size_t d = 0; d < N; ++d) {
        const automata::State& s = factors[d].automaton.graph[tuple[d]];
        size *= s.size;
        name += (d ? "," : "") + s.name;
      }
      it->second = add_vertex(automata::State{.size = size, .recurrent = false, .name = name + ")"},
                              out.automaton.graph);
      out.factor_states.push_back(tuple);
      todo.push_back(it->second);
    }
    return it->second;
  };
  // Every tuple of indices below `radix`, the last fastest, passed to f.
  const auto for_each_tuple = [](const std::array<std::size_t, N>& radix, auto&& f) {
    for (std::size_t d = 0; d < N; ++d)
      if (radix[d] == 0) return;
    std::array<std::size_t, N> index{};
    while (true) {
      f(index);
      std::size_t d = N;
      while (d > 0 && ++index[d - 1] == radix[d - 1]) index[--d] = 0;
      if (d == 0) return;
    }
  };
  std::array<std::size_t, N> segments{};
  for (std::size_t d = 0; d < N; ++d) segments[d] = factors[d].automaton.initial.size();
  for_each_tuple(segments, [&](const std::array<std::size_t, N>& index) {
    std::array<StateId, N> tuple{};
    std::array<int, N> cell{};
    int segment = 0;
    for (std::size_t d = 0; d < N; ++d) {
      const Initial& init = factors[d].automaton.initial[index[d]];
      tuple[d] = init.state;
      cell[d] = init.segment;
      segment = segment * static_cast<int>(segments[d]) + init.segment;
    }
    Initial init;
    init.segment = segment;
    init.state = state_of(tuple);
    out.automaton.initial.push_back(init);
    out.segments.push_back(cell);
  });
  // The product of three factors grows fast (64 states each gave 57,214 triples and 15 GB of 64×64 matrices):
  // refused once its matrices pass half the memory, before they exhaust it.
  const std::uint64_t budget = largest_input();
  std::uint64_t bytes = 0;
  while (!todo.empty()) {
    const StateId s = todo.front();
    todo.pop_front();
    const std::array<StateId, N> tuple = out.factor_states[s];
    std::array<std::vector<automata::TransitionId>, N> edges;
    std::array<std::size_t, N> radix{};
    for (std::size_t d = 0; d < N; ++d) {
      const Graph& g = factors[d].automaton.graph;
      for (auto [e, end] = out_edges(tuple[d], g); e != end; ++e) edges[d].push_back(*e);
      radix[d] = edges[d].size();
    }
    for_each_tuple(radix, [&](const std::array<std::size_t, N>& index) {
      std::array<StateId, N> child{};
      automata::Transition t;
      for (std::size_t d = 0; d < N; ++d) {
        const Graph& g = factors[d].automaton.graph;
        const auto e = edges[d][index[d]];
        child[d] = target(e, g);
        t.label += direction_label(d, g[e].label);
        t.matrix = d == 0 ? g[e].matrix : kron(t.matrix, g[e].matrix);
      }
      bytes += static_cast<std::uint64_t>(t.matrix.size()) * sizeof(double);
      if (bytes > budget)
        throw InvalidInput("the tensor-product automaton needs more than " + std::to_string(budget >> 20) +
                           " MB of matrices (half the memory) after " +
                           std::to_string(num_vertices(out.automaton.graph)) +
                           " product states: too many distinct knot windows (fewer distinct knot spacings "
                           "make fewer states)");
      add_edge(s, state_of(child), std::move(t), out.automaton.graph);
    });
  }
  automata::mark_recurrent(out.automaton);
  return out;
}

/// The net of every initial entry of a product automaton: for each entry, the rows of `P` (N-dimensional
/// net of `count` points, the last direction fastest) under the segments' spans, in the same order.
/// `what` names the shape in messages ("surface", "volume").
template <std::size_t N>
std::vector<Points> product_nets(const automata::Automaton& product,
                                 const std::array<KnotAutomaton, N>& factors,
                                 const std::vector<std::array<int, N>>& segments,
                                 const std::array<int, N>& degree, const std::array<Eigen::Index, N>& count,
                                 const Points& P, const char* what) {
  constexpr const char* kName[3] = {"u", "v", "w"};
  if (segments.size() != product.initial.size())
    throw InvalidInput("the tensor automaton has " + std::to_string(product.initial.size()) +
                       " initial entries but " + std::to_string(segments.size()) + " " +
                       (N == 2 ? "patches" : "cells") + "; build it with tensor_automaton from this " + what);
  Eigen::Index size = 1;
  for (std::size_t d = 0; d < N; ++d) size *= degree[d] + 1;
  std::vector<Points> nets;
  nets.reserve(segments.size());
  for (std::size_t k = 0; k < segments.size(); ++k) {
    std::array<int, N> span{};
    for (std::size_t d = 0; d < N; ++d) {
      const auto& initial = factors[d].automaton.initial;
      const auto& intervals = factors[d].intervals;
      const int segment = segments[k][d];
      if (segment < 0 || static_cast<std::size_t>(segment) >= initial.size())
        throw InvalidInput(std::string("the tensor automaton's ") + (N == 2 ? "patch " : "cell ") +
                           std::to_string(k) + " names segment " + std::to_string(segment) +
                           " of direction " + kName[d] + ", which has " + std::to_string(initial.size()));
      span[d] = static_cast<std::size_t>(segment) < intervals.size()
                    ? intervals[static_cast<std::size_t>(segment)].span
                    : -1;
      if (span[d] < degree[d] || span[d] >= count[d])
        throw InvalidInput(std::string("the tensor automaton's ") + (N == 2 ? "patch " : "cell ") +
                           std::to_string(k) + " has no span in direction " + kName[d] + " of this " + what +
                           "; build it from this " + what);
    }
    const StateId state = product.initial[k].state;
    if (product.graph[state].size != size) {
      std::string degrees;
      for (std::size_t d = 0; d < N; ++d) degrees += (d ? ", " : "") + std::to_string(degree[d]);
      throw InvalidInput(std::string("the tensor automaton's ") + (N == 2 ? "patch " : "cell ") +
                         std::to_string(k) + " has a state of " + std::to_string(product.graph[state].size) +
                         " points but the " + what + "'s degrees (" + degrees + ") give " +
                         std::to_string(size));
    }
    // Net row r ↔ control point (span − degree + index): both mixed-radix, the last direction fastest.
    Points net(size, P.cols());
    for (Eigen::Index r = 0; r < size; ++r) {
      Eigen::Index rest = r, row = 0, stride = 1;
      for (std::size_t d = N; d-- > 0;) {
        const Eigen::Index i = rest % (degree[d] + 1);
        rest /= degree[d] + 1;
        row += (span[d] - degree[d] + i) * stride;
        stride *= count[d];
      }
      net.row(r) = P.row(row);
    }
    nets.push_back(std::move(net));
  }
  return nets;
}

}  // namespace

TensorAutomaton tensor_automaton(const nurbs::Surface& surface) {
  validate(surface);
  TensorAutomaton t;
  for (auto dir : {Direction::u, Direction::v})
    t.factors[static_cast<std::size_t>(dir)] = knot_automaton(direction_curve(surface, dir));
  Product<2> p = product_of(t.factors);
  t.product = std::move(p.automaton);
  t.factor_states = std::move(p.factor_states);
  t.patches = std::move(p.segments);
  return t;
}

std::vector<Points> initial_nets(const TensorAutomaton& t, const Surface& s) {
  return product_nets<2>(t.product, t.factors, t.patches, s.degree, s.count, s.P, "surface");
}

VolumeAutomaton tensor_automaton(const Volume& volume) {
  validate(volume);
  VolumeAutomaton t;
  for (int d = 0; d < 3; ++d)
    t.factors[static_cast<std::size_t>(d)] = knot_automaton(direction_curve(volume, d));
  Product<3> p = product_of(t.factors);
  t.product = std::move(p.automaton);
  t.factor_states = std::move(p.factor_states);
  t.cells = std::move(p.segments);
  return t;
}

std::vector<Points> initial_nets(const VolumeAutomaton& t, const Volume& v) {
  return product_nets<3>(t.product, t.factors, t.cells, v.degree, v.count, v.P, "volume");
}

}  // namespace cifs::nurbs
