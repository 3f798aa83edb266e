// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs_curve.hpp"

#include <map>
#include <numeric>
#include <tuple>

#include "cifs/errors.hpp"
#include "union_find.hpp"

namespace cifs::ifs {

using automata::StateId;

namespace {

using Cell = std::tuple<StateId, bool, bool>;  // knot state, starts at a knot, ends at one

/// Edge cells: the knot automaton's states unfolded by two flags, "starts at a knot of the curve"
/// and "ends at one", so that the vertex cells at the curve's knots and those at the midpoints
/// created by subdivision are never the same cell. `origin[s]` is the cell of state s.
struct Unfolding {
  std::map<Cell, StateId> ids;
  std::vector<Cell> origin;
};

Unfolding unfold(const automata::Automaton& knots) {
  Unfolding u;
  const auto cell_of = [&](StateId k, bool a, bool b) {
    const auto [it, added] = u.ids.try_emplace({k, a, b}, u.origin.size());
    if (added) u.origin.emplace_back(k, a, b);
    return it->second;
  };
  for (const automata::Initial& init : knots.initial) cell_of(init.state, true, true);
  for (StateId s = 0; s < u.origin.size(); ++s) {
    const auto [k, a, b] = u.origin[s];
    cell_of(target(transition_id(knots, TransitionRef{k, 0}), knots.graph), a, false);
    cell_of(target(transition_id(knots, TransitionRef{k, 1}), knots.graph), false, b);
  }
  return u;
}

std::size_t window_size(const nurbs::KnotAutomaton& knots, StateId s) {
  return s < knots.windows.size() ? knots.windows[s].size() : 0;
}

/// The degree d of a knot automaton whose states are all knot-doubling states of degree d.
int knot_doubling_degree(const nurbs::KnotAutomaton& knot_automaton) {
  const automata::Automaton& knots = knot_automaton.automaton;
  if (knots.initial.empty())
    throw InvalidInput("the knot automaton has no segment, so there is no BC-IFS to build");
  const int d = knots.graph[knots.initial.front().state].size - 1;
  if (d < 1)
    throw InvalidInput("a curve of degree " + std::to_string(d) +
                       " has no edge to subdivide into a BC-IFS; elevate its degree");
  for (StateId s = 0; s < num_vertices(knots.graph); ++s)
    if (knots.graph[s].size != d + 1 ||
        window_size(knot_automaton, s) != static_cast<std::size_t>(2 * d - 1) ||
        out_degree(s, knots.graph) != 2)
      throw InvalidInput("the knot automaton's state " + std::to_string(s) +
                         " is not a knot-doubling state of degree " + std::to_string(d) +
                         " (d + 1 points, a window of 2d − 1 intervals, two children)");
  return d;
}

/// The edge cells, their initial entries and transitions; returns per vertex key 2s + side
/// whether the vertex is a knot of the curve.
std::vector<bool> add_edge_cells(const automata::Automaton& knots, const Unfolding& unfolding, Bcifs& sys) {
  auto& g = sys.automaton.graph;
  const auto& origin = unfolding.origin;
  std::vector<bool> at_knot;
  for (const auto& [k, a, b] : origin) {
    const auto& st = knots.graph[k];
    add_vertex(
        automata::State{
            .size = st.size, .recurrent = false, .name = st.name + (a ? "a" : "") + (b ? "b" : "")},
        g);
    at_knot.push_back(a);
    at_knot.push_back(b);
  }
  for (automata::Initial init : knots.initial) {
    init.state = unfolding.ids.at({init.state, true, true});
    sys.automaton.initial.push_back(init);
  }
  for (StateId s = 0; s < origin.size(); ++s) {
    const auto [k, a, b] = origin[s];
    for (int c = 0; c < 2; ++c) {
      const auto e = transition_id(knots, TransitionRef{k, c});
      const StateId t = c == 0 ? unfolding.ids.at({target(e, knots.graph), a, false})
                               : unfolding.ids.at({target(e, knots.graph), false, b});
      add_edge(s, t, knots.graph[e], g);
    }
  }
  return at_knot;
}

/// Rows of an edge net that its start (side 0) or end (side 1) point depends on.
std::vector<int> end_rows(const nurbs::KnotAutomaton& knot_automaton, const Unfolding& unfolding, int d,
                          StateId s, int side) {
  const auto& w = knot_automaton.windows[std::get<0>(unfolding.origin[s])];
  int m = 1;  // multiplicity of the knot: 1 + the zero intervals next to the centre
  if (side == 0)
    for (int i = d - 2; i >= 0 && w[static_cast<std::size_t>(i)] == 0; --i) ++m;
  else
    for (int i = d; i < 2 * d - 1 && w[static_cast<std::size_t>(i)] == 0; ++i) ++m;
  std::vector<int> rows(static_cast<std::size_t>(d - m + 1));
  std::iota(rows.begin(), rows.end(), side == 0 ? 0 : m);
  return rows;
}

StateId child_cell(const Bcifs& sys, StateId s, int c) {
  return target(transition_id(sys.automaton, TransitionRef{s, c}), sys.automaton.graph);
}

/// Vertex keys 2s + side; the child of a key follows G from a start, D from an end.
std::size_t child_key(const Bcifs& sys, std::size_t key) {
  const int side = static_cast<int>(key % 2);
  return 2 * child_cell(sys, key / 2, side) + static_cast<std::size_t>(side);
}

/// The vertex keys of the edge cells in classes of one vertex: the segments' junctions, the
/// midpoints, closed under children.
detail::UnionFind vertex_classes(const Bcifs& sys, std::size_t edges, bool closed) {
  detail::UnionFind classes(2 * edges);
  const auto& initial = sys.automaton.initial;
  for (std::size_t k = 0; k + 1 < initial.size(); ++k)
    classes.unite(2 * initial[k].state + 1, 2 * initial[k + 1].state);
  if (closed) classes.unite(2 * initial.back().state + 1, 2 * initial.front().state);
  // Interior junctions: the end of G(s) and the start of D(s) are one midpoint vertex.
  for (StateId s = 0; s < edges; ++s) classes.unite(2 * child_cell(sys, s, 0) + 1, 2 * child_cell(sys, s, 1));
  // Congruence: keys in one class have children in one class.
  for (bool changed = true; changed;) {
    changed = false;
    std::map<std::size_t, std::size_t> first_child;
    for (std::size_t key = 0; key < 2 * edges; ++key) {
      const auto [it, added] = first_child.try_emplace(classes.find(key), child_key(sys, key));
      if (!added) changed = classes.unite(it->second, child_key(sys, key)) || changed;
    }
  }
  return classes;
}

/// Vertex cells, one per class, after the edge cells; returns class representative → vertex cell.
std::map<std::size_t, StateId> add_vertex_cells(const nurbs::KnotAutomaton& knot_automaton,
                                                const Unfolding& unfolding, int d, std::size_t edges,
                                                detail::UnionFind& classes, Bcifs& sys) {
  auto& g = sys.automaton.graph;
  sys.dimension.assign(edges, 1);
  std::map<std::size_t, StateId> vertex;
  for (std::size_t key = 0; key < 2 * edges; ++key) {
    const std::size_t rep = classes.find(key);
    const int size =
        static_cast<int>(end_rows(knot_automaton, unfolding, d, key / 2, static_cast<int>(key % 2)).size());
    const auto [it, added] = vertex.try_emplace(rep, 0);
    if (added) {
      it->second = add_vertex(g);
      g[it->second].size = size;
      g[it->second].name = "v" + std::to_string(it->second - edges);
      sys.dimension.push_back(0);
    } else if (g[it->second].size != size) {
      throw InvalidInput("the BC-IFS vertex cell " + g[it->second].name + " is reached with " +
                         std::to_string(g[it->second].size) + " and with " + std::to_string(size) +
                         " rows (knot multiplicities disagree)");
    }
  }
  return vertex;
}

/// The transition V of each vertex cell: the rows of its edge's transition that map the end rows
/// to the child's; free unless the vertex is a knot of the curve (or free_vertices asks for all).
void add_vertex_transitions(const nurbs::KnotAutomaton& knot_automaton, const Unfolding& unfolding, int d,
                            const std::map<std::size_t, StateId>& vertex, const std::vector<bool>& at_knot,
                            bool free_vertices, detail::UnionFind& classes, Bcifs& sys) {
  auto& g = sys.automaton.graph;
  for (const auto& [rep, v] : vertex) {
    const StateId s = rep / 2;
    const int side = static_cast<int>(rep % 2);
    const auto from = end_rows(knot_automaton, unfolding, d, s, side),
               to = end_rows(knot_automaton, unfolding, d, child_cell(sys, s, side), side);
    const auto& T = g[transition_id(sys.automaton, TransitionRef{s, side})].matrix;
    Eigen::MatrixXd V(static_cast<Eigen::Index>(to.size()), static_cast<Eigen::Index>(from.size()));
    for (std::size_t i = 0; i < to.size(); ++i)
      for (std::size_t j = 0; j < from.size(); ++j)
        V(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = T(to[i], from[j]);
    add_edge(v, vertex.at(classes.find(child_key(sys, rep))), automata::Transition{"V", V}, g);
    if (free_vertices || !at_knot[rep]) sys.free.push_back(TransitionRef{v, 0});
  }
}

/// Boundaries, then the constraints of every edge cell.
void add_edge_constraints(const nurbs::KnotAutomaton& knot_automaton, const Unfolding& unfolding, int d,
                          std::size_t edges, const std::map<std::size_t, StateId>& vertex,
                          detail::UnionFind& classes, Bcifs& sys) {
  for (StateId s = 0; s < edges; ++s)
    for (int side = 0; side < 2; ++side)
      sys.boundaries.push_back(BoundaryOperator{side ? "end" : "start", s,
                                                vertex.at(classes.find(2 * s + side)),
                                                end_rows(knot_automaton, unfolding, d, s, side)});
  const auto boundary = [](StateId s, int side) {
    return Factor{Factor::Kind::boundary, static_cast<int>(2 * s) + side, {}};
  };
  const auto transition = [](StateId s, int c) {
    return Factor{Factor::Kind::transition, 0, TransitionRef{s, c}};
  };
  for (StateId s = 0; s < edges; ++s) {
    const std::string name = sys.automaton.graph[s].name;
    const StateId t1 = child_cell(sys, s, 0), t2 = child_cell(sys, s, 1);
    for (int side = 0; side < 2; ++side) {
      const StateId v = vertex.at(classes.find(2 * s + static_cast<std::size_t>(side)));
      sys.constraints.push_back(Constraint{name + (side ? ".end" : ".start"),
                                           {boundary(side ? t2 : t1, side), transition(s, side)},
                                           {transition(v, 0), boundary(s, side)}});
    }
    sys.constraints.push_back(Constraint{
        name + ".junction", {boundary(t1, 1), transition(s, 0)}, {boundary(t2, 0), transition(s, 1)}});
    sys.free.push_back(TransitionRef{s, 0});
    sys.free.push_back(TransitionRef{s, 1});
  }
}

}  // namespace

Bcifs curve_bcifs(const nurbs::Curve& curve, const CurveBcifsOptions& options) {
  nurbs::validate(curve);
  if (curve.degree < 1)
    throw InvalidInput("a curve of degree " + std::to_string(curve.degree) +
                       " has no edge to subdivide into a BC-IFS; elevate its degree");
  return curve_bcifs(nurbs::knot_automaton(curve), curve.closed, options);
}

Bcifs curve_bcifs(const nurbs::KnotAutomaton& knot_automaton, bool closed, const CurveBcifsOptions& options) {
  const int d = knot_doubling_degree(knot_automaton);
  Bcifs sys;
  const Unfolding unfolding = unfold(knot_automaton.automaton);
  const std::vector<bool> at_knot = add_edge_cells(knot_automaton.automaton, unfolding, sys);
  automata::mark_recurrent(sys.automaton);
  const std::size_t edges = num_vertices(sys.automaton.graph);
  detail::UnionFind classes = vertex_classes(sys, edges, closed);
  const std::map<std::size_t, StateId> vertex =
      add_vertex_cells(knot_automaton, unfolding, d, edges, classes, sys);
  add_vertex_transitions(knot_automaton, unfolding, d, vertex, at_knot, options.free_vertices, classes, sys);
  add_edge_constraints(knot_automaton, unfolding, d, edges, vertex, classes, sys);
  return sys;
}

nurbs::KnotAutomaton curve_bcifs_knots(automata::Automaton automaton, const nurbs::KnotAutomaton& knots) {
  const Unfolding unfolding = unfold(knots.automaton);
  if (num_vertices(automaton.graph) < unfolding.origin.size() ||
      automaton.initial.size() != knots.automaton.initial.size())
    throw InvalidInput("the automaton is not the BC-IFS of this knot automaton (" +
                       std::to_string(num_vertices(automaton.graph)) + " states and " +
                       std::to_string(automaton.initial.size()) + " initial entries for " +
                       std::to_string(unfolding.origin.size()) + " edge cells and " +
                       std::to_string(knots.automaton.initial.size()) + " segments)");
  nurbs::KnotAutomaton out = nurbs::without_knots(std::move(automaton));
  for (StateId s = 0; s < unfolding.origin.size(); ++s) {
    const StateId k = std::get<0>(unfolding.origin[s]);
    if (k < knots.windows.size()) out.windows[s] = knots.windows[k];
  }
  out.intervals = knots.intervals;
  out.intervals.resize(out.automaton.initial.size());
  return out;
}

}  // namespace cifs::ifs
