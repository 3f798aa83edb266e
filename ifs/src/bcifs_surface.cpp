// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs_surface.hpp"

#include <algorithm>
#include <array>
#include <deque>
#include <map>
#include <numeric>

#include "cifs/errors.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/ifs/junction.hpp"

namespace cifs::ifs {

using automata::StateId;

namespace {

using automata::kron;
using automata::v_label;

std::vector<std::pair<StateId, automata::TransitionId>> children(const automata::Graph& graph, StateId s) {
  std::vector<std::pair<StateId, automata::TransitionId>> out;
  for (auto [e, end] = out_edges(s, graph); e != end; ++e) out.emplace_back(target(*e, graph), *e);
  return out;
}

/// The product system as its phases build it.
struct Product {
  std::array<const Bcifs*, 2> curves;
  Bcifs sys;
  std::map<std::array<StateId, 2>, StateId> ids;  // factor cells → product cell
  std::vector<std::array<StateId, 2>> pair;       // product cell → factor cells
  /// Boundaries of each factor cell (indices into the curve system's boundaries).
  std::array<std::vector<std::vector<int>>, 2> factor_boundaries;
  /// Lifts of the factors' boundaries (key: factor boundary, the other factor's cell).
  std::array<std::map<std::pair<int, StateId>, int>, 2> lifted;
};

/// The cell of a pair of factor cells, added (and queued) when new.
StateId cell_of(Product& p, std::array<StateId, 2> c, std::deque<StateId>& todo) {
  const auto& gu = p.curves[0]->automaton.graph;
  const auto& gv = p.curves[1]->automaton.graph;
  const auto [it, added] = p.ids.try_emplace(c, 0);
  if (added) {
    it->second = add_vertex(automata::State{.size = gu[c[0]].size * gv[c[1]].size,
                                            .recurrent = false,
                                            .name = "(" + gu[c[0]].name + "," + gv[c[1]].name + ")"},
                            p.sys.automaton.graph);
    p.pair.push_back(c);
    p.sys.dimension.push_back(p.curves[0]->dimension[c[0]] + p.curves[1]->dimension[c[1]]);
    todo.push_back(it->second);
  }
  return it->second;
}

/// Cells: pairs closed under children and boundaries, from the patches.
void add_cells(Product& p) {
  const auto& gu = p.curves[0]->automaton.graph;
  const auto& gv = p.curves[1]->automaton.graph;
  const auto& iu = p.curves[0]->automaton.initial;
  const auto& iv = p.curves[1]->automaton.initial;
  std::deque<StateId> todo;
  for (int dir = 0; dir < 2; ++dir) {
    p.factor_boundaries[dir].resize(num_vertices(p.curves[dir]->automaton.graph));
    for (std::size_t b = 0; b < p.curves[dir]->boundaries.size(); ++b)
      p.factor_boundaries[dir][p.curves[dir]->boundaries[b].cell].push_back(static_cast<int>(b));
  }
  for (std::size_t a = 0; a < iu.size(); ++a)
    for (std::size_t b = 0; b < iv.size(); ++b) {
      p.sys.automaton.initial.push_back(
          automata::Initial{.segment = static_cast<int>(a * iv.size() + b),
                            .state = cell_of(p, {iu[a].state, iv[b].state}, todo)});
    }
  while (!todo.empty()) {
    const auto [x, y] = p.pair[todo.front()];
    todo.pop_front();
    for (const auto& [cx, ex] : children(gu, x))
      for (const auto& [cy, ey] : children(gv, y)) cell_of(p, {cx, cy}, todo);
    for (const int b : p.factor_boundaries[0][x]) cell_of(p, {p.curves[0]->boundaries[b].boundary, y}, todo);
    for (const int b : p.factor_boundaries[1][y]) cell_of(p, {x, p.curves[1]->boundaries[b].boundary}, todo);
  }
}

/// Transitions: kron of the factors' out-edges, u-major; free when both factors are.
void add_transitions(Product& p, const ProductOptions& options) {
  const auto& gu = p.curves[0]->automaton.graph;
  const auto& gv = p.curves[1]->automaton.graph;
  const auto is_free = [&](int dir, automata::StateId s, int c) {
    const auto& f = p.curves[dir]->free;
    return std::find(f.begin(), f.end(), TransitionRef{s, c}) != f.end();
  };
  for (StateId s = 0; s < p.pair.size(); ++s) {
    const auto [x, y] = p.pair[s];
    const auto cu = children(gu, x), cv = children(gv, y);
    for (std::size_t i = 0; i < cu.size(); ++i)
      for (std::size_t j = 0; j < cv.size(); ++j) {
        const auto& tu = gu[cu[i].second];
        const auto& tv = gv[cv[j].second];
        add_edge(s, p.ids.at({cu[i].first, cv[j].first}),
                 automata::Transition{tu.label + v_label(tv.label), kron(tu.matrix, tv.matrix)},
                 p.sys.automaton.graph);
        const bool fu = is_free(0, x, static_cast<int>(i)), fv = is_free(1, y, static_cast<int>(j));
        if (options.free_when_either ? fu || fv : fu && fv)
          p.sys.free.push_back(TransitionRef{s, static_cast<int>(i * cv.size() + j)});
      }
  }
}

/// Boundaries: lifts of the factors' and, on faces, their products (corners).
void add_boundaries(Product& p) {
  const auto& gu = p.curves[0]->automaton.graph;
  const auto& gv = p.curves[1]->automaton.graph;
  for (StateId s = 0; s < p.pair.size(); ++s) {
    const auto [x, y] = p.pair[s];
    const int sy = gv[y].size;
    const auto add = [&](const std::string& name, StateId to, const std::vector<int>& ri,
                         const std::vector<int>& rj) {
      BoundaryOperator op{name, s, to, {}};
      for (const int i : ri)
        for (const int j : rj) op.rows.push_back(i * sy + j);
      p.sys.boundaries.push_back(std::move(op));
      return static_cast<int>(p.sys.boundaries.size() - 1);
    };
    std::vector<int> all_u(static_cast<std::size_t>(gu[x].size)), all_v(static_cast<std::size_t>(sy));
    std::iota(all_u.begin(), all_u.end(), 0);
    std::iota(all_v.begin(), all_v.end(), 0);
    for (const int b : p.factor_boundaries[0][x]) {
      const auto& op = p.curves[0]->boundaries[b];
      p.lifted[0][{b, y}] = add("u" + op.name, p.ids.at({op.boundary, y}), op.rows, all_v);
    }
    for (const int b : p.factor_boundaries[1][y]) {
      const auto& op = p.curves[1]->boundaries[b];
      p.lifted[1][{b, x}] = add("v" + op.name, p.ids.at({x, op.boundary}), all_u, op.rows);
    }
    for (const int bu : p.factor_boundaries[0][x])
      for (const int bv : p.factor_boundaries[1][y]) {
        const auto& ou = p.curves[0]->boundaries[bu];
        const auto& ov = p.curves[1]->boundaries[bv];
        add("u" + ou.name + ".v" + ov.name, p.ids.at({ou.boundary, ov.boundary}), ou.rows, ov.rows);
      }
  }
}

/// A side F_0⋯F_k of a curve constraint (direction dir) lifted along the j-th child of the other
/// factor's cell y: it holds one transition; the other factor's cell is y before it (factors to
/// its right act first) and y's child after it.
std::vector<Factor> lift_side(const Product& p, int dir, const std::vector<Factor>& side, StateId y,
                              std::span<const std::pair<StateId, automata::TransitionId>> cy, std::size_t j) {
  const Bcifs& curve = *p.curves[dir];
  std::vector<Factor> out(side.size());
  StateId ycur = y;
  for (std::size_t k = side.size(); k-- > 0;) {
    const Factor& f = side[k];
    if (f.kind == Factor::Kind::boundary) {
      out[k] = Factor{Factor::Kind::boundary, p.lifted[dir].at({f.boundary, ycur}), {}};
      continue;
    }
    const StateId z = f.transition.from;
    const StateId cell = dir == 0 ? p.ids.at({z, ycur}) : p.ids.at({ycur, z});
    const int n_other = static_cast<int>(cy.size());
    const int n_z = static_cast<int>(out_degree(z, curve.automaton.graph));
    const int child = dir == 0 ? f.transition.child * n_other + static_cast<int>(j)
                               : static_cast<int>(j) * n_z + f.transition.child;
    out[k] = Factor{Factor::Kind::transition, 0, TransitionRef{cell, child}};
    ycur = cy[j].first;
  }
  return out;
}

/// Constraints: each factor constraint on x (on y) lifted along every child of y (of x).
void add_constraints(Product& p) {
  const auto& g = p.sys.automaton.graph;
  for (int dir = 0; dir < 2; ++dir) {
    const Bcifs& curve = *p.curves[dir];
    const auto& other = p.curves[1 - dir]->automaton.graph;
    std::vector<std::vector<std::size_t>> on_cell(num_vertices(curve.automaton.graph));
    for (std::size_t c = 0; c < curve.constraints.size(); ++c)
      on_cell[source_cell(curve, curve.constraints[c])].push_back(c);
    for (StateId s = 0; s < p.pair.size(); ++s) {
      const StateId x = p.pair[s][dir], y = p.pair[s][1 - dir];
      const auto cy = children(other, y);
      for (const std::size_t c : on_cell[x]) {
        const Constraint& con = curve.constraints[c];
        for (std::size_t j = 0; j < cy.size(); ++j) {
          const std::string what = con.name.substr(con.name.rfind('.') + 1);
          p.sys.constraints.push_back(
              Constraint{g[s].name + (dir == 0 ? ".u" : ".v") + what + "/" +
                             (dir == 0 ? v_label(other[cy[j].second].label) : other[cy[j].second].label),
                         lift_side(p, dir, con.left, y, cy, j), lift_side(p, dir, con.right, y, cy, j)});
        }
      }
    }
  }
}

}  // namespace

Bcifs surface_bcifs(const nurbs::TensorAutomaton& automaton, const SurfaceBcifsOptions& options) {
  const Bcifs cu = curve_bcifs(automaton.factors[0], false, {.free_vertices = options.free_knot_lines});
  const Bcifs cv = curve_bcifs(automaton.factors[1], false, {.free_vertices = options.free_knot_lines});
  if (automaton.product.initial.size() != cu.automaton.initial.size() * cv.automaton.initial.size())
    throw InvalidInput("the tensor automaton has " + std::to_string(automaton.product.initial.size()) +
                       " patches, its factors " + std::to_string(cu.automaton.initial.size()) + " × " +
                       std::to_string(cv.automaton.initial.size()));
  Bcifs sys = product_bcifs(cu, cv);
  // The tensor automaton's entries (patch order, segments) on the product's cells.
  for (std::size_t k = 0; k < sys.automaton.initial.size(); ++k) {
    automata::Initial init = automaton.product.initial[k];
    init.state = sys.automaton.initial[k].state;
    sys.automaton.initial[k] = init;
  }
  return sys;
}

Bcifs product_bcifs(const Bcifs& u, const Bcifs& v, const ProductOptions& options) {
  validate(u);
  validate(v);
  Product p{{&u, &v}, {}, {}, {}, {}, {}};
  add_cells(p);
  add_transitions(p, options);
  automata::mark_recurrent(p.sys.automaton);
  add_boundaries(p);
  add_constraints(p);
  return std::move(p.sys);
}

Bcifs surface_bcifs(const nurbs::Surface& surface, const SurfaceBcifsOptions& options) {
  return surface_bcifs(nurbs::tensor_automaton(surface), options);
}

}  // namespace cifs::ifs
