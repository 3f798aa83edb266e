// SPDX-License-Identifier: MIT
#include "cifs/ifs/junction.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <numeric>

#include "cifs/errors.hpp"

namespace cifs::ifs {

using automata::StateId;

namespace {

/// Index of the boundary `name` of `cell`, or −1.
int find_boundary(const Bcifs& sys, StateId cell, const std::string& name) {
  for (std::size_t i = 0; i < sys.boundaries.size(); ++i)
    if (sys.boundaries[i].cell == cell && sys.boundaries[i].name == name) return static_cast<int>(i);
  return -1;
}

StateId child_of(const Bcifs& sys, StateId s, int c) {
  return target(transition_id(sys.automaton, TransitionRef{s, c}), sys.automaton.graph);
}

std::string cell_text(const Bcifs& sys, StateId s) {
  const auto& name = sys.automaton.graph[s].name;
  return name.empty() ? "s" + std::to_string(s) : name;
}

}  // namespace

Bcifs uniform_curve_bcifs(const Eigen::MatrixXd& S0, const Eigen::MatrixXd& S1,
                          const UniformCurveOptions& options) {
  const Eigen::Index N = S0.rows();
  if (N < 2 || S0.cols() != N || S1.rows() != N || S1.cols() != N)
    throw InvalidInput("the subdivision matrices S0 and S1 must both be N by N with N ≥ 2");
  if (options.pieces < 0 || options.layer < 0)
    throw InvalidInput("the number of pieces and the layer must not be negative");
  if (options.pieces > (1 << 20) || options.layer > 4096)
    throw InvalidInput("at most 2^20 pieces and a layer of 4096 are supported; ask for fewer");
  const int L = options.layer;
  Bcifs sys;
  auto& g = sys.automaton.graph;
  const auto add = [&](const std::string& name, Eigen::Index size, int dimension) {
    const StateId s =
        add_vertex(automata::State{.size = static_cast<int>(size), .recurrent = true, .name = name}, g);
    sys.dimension.push_back(dimension);
    return s;
  };
  // Edge cells: a0 … a(L−1), then e; vertex cells: v0, w1 … w(L−1), m (position q ≥ L, or 0 when
  // there is no layer).
  std::vector<StateId> edge(static_cast<std::size_t>(L) + 1), vertex(static_cast<std::size_t>(L) + 1);
  for (int p = 0; p < L; ++p) edge[static_cast<std::size_t>(p)] = add("a" + std::to_string(p), N, 1);
  edge[static_cast<std::size_t>(L)] = add("e", N, 1);
  if (L > 0) vertex[0] = add("v0", N - 1, 0);
  for (int q = 1; q < L; ++q) vertex[static_cast<std::size_t>(q)] = add("w" + std::to_string(q), N - 1, 0);
  vertex[static_cast<std::size_t>(L)] = add("m", N - 1, 0);
  const auto edge_at = [&](int p) { return edge[static_cast<std::size_t>(std::min(p, L))]; };
  const auto vertex_at = [&](int q) { return vertex[static_cast<std::size_t>(std::min(q, L))]; };

  const Eigen::MatrixXd V = S0.topLeftCorner(N - 1, N - 1);
  for (int p = 0; p <= L; ++p) {
    const StateId s = edge_at(p);
    const bool interior = p == L;
    add_edge(s, edge_at(interior ? L : 2 * p), automata::Transition{"G", S0}, g);
    add_edge(s, edge_at(interior ? L : 2 * p + 1), automata::Transition{"D", S1}, g);
    if (options.free || !interior) {
      sys.free.push_back(TransitionRef{s, 0});
      sys.free.push_back(TransitionRef{s, 1});
    }
  }
  for (int q = 0; q <= L; ++q) {
    const StateId v = vertex_at(q);
    add_edge(v, vertex_at(q == L ? L : 2 * q), automata::Transition{"V", V}, g);
    if (options.free || (q > 0 && q < L)) sys.free.push_back(TransitionRef{v, 0});
  }
  std::vector<int> start_rows(static_cast<std::size_t>(N - 1)), end_rows(start_rows.size());
  std::iota(start_rows.begin(), start_rows.end(), 0);
  std::iota(end_rows.begin(), end_rows.end(), 1);
  for (int p = 0; p <= L; ++p) {
    sys.boundaries.push_back(BoundaryOperator{"start", edge_at(p), vertex_at(p == L ? L : p), start_rows});
    sys.boundaries.push_back(BoundaryOperator{"end", edge_at(p), vertex_at(p == L ? L : p + 1), end_rows});
  }
  const auto boundary = [](int p, int side) { return Factor{Factor::Kind::boundary, 2 * p + side, {}}; };
  const auto transition = [](StateId s, int c) {
    return Factor{Factor::Kind::transition, 0, TransitionRef{s, c}};
  };
  const auto index_of = [&](StateId s) {
    return static_cast<int>(std::find(edge.begin(), edge.end(), s) - edge.begin());
  };
  for (int p = 0; p <= L; ++p) {
    const StateId s = edge_at(p);
    const int t1 = index_of(child_of(sys, s, 0)), t2 = index_of(child_of(sys, s, 1));
    const StateId vs = sys.boundaries[2 * static_cast<std::size_t>(p)].boundary;
    const StateId ve = sys.boundaries[2 * static_cast<std::size_t>(p) + 1].boundary;
    const std::string name = g[s].name;
    sys.constraints.push_back(Constraint{
        name + ".start", {boundary(t1, 0), transition(s, 0)}, {transition(vs, 0), boundary(p, 0)}});
    sys.constraints.push_back(
        Constraint{name + ".end", {boundary(t2, 1), transition(s, 1)}, {transition(ve, 0), boundary(p, 1)}});
    sys.constraints.push_back(Constraint{
        name + ".junction", {boundary(t1, 1), transition(s, 0)}, {boundary(t2, 0), transition(s, 1)}});
  }
  for (int k = 0; k < options.pieces; ++k)
    sys.automaton.initial.push_back({.segment = k, .state = edge_at(k)});
  automata::mark_recurrent(sys.automaton);
  validate(sys);
  return sys;
}

namespace {

void check_join_nets(const Bcifs& a, std::span<const Points> nets_a, const Bcifs& b,
                     std::span<const Points> nets_b, std::span<const Glue> glue) {
  if (!nets_a.empty() && nets_a.size() != a.automaton.initial.size())
    throw InvalidInput(std::to_string(nets_a.size()) + " control nets given for A's " +
                       std::to_string(a.automaton.initial.size()) + " initial entries (one per entry)");
  if (!nets_b.empty() && nets_b.size() != b.automaton.initial.size())
    throw InvalidInput(std::to_string(nets_b.size()) + " control nets given for B's " +
                       std::to_string(b.automaton.initial.size()) + " initial entries (one per entry)");
  if (glue.empty()) throw InvalidInput("no boundary of A is glued to B; give at least one glue");
}

/// The glued boundaries: (A boundary index, B boundary index) per glue.
std::vector<std::pair<int, int>> glued_boundaries(const Bcifs& a, const Bcifs& b,
                                                  std::span<const Glue> glue) {
  std::vector<std::pair<int, int>> out;
  for (std::size_t k = 0; k < glue.size(); ++k) {
    const Glue& gl = glue[k];
    const std::string where = "join: glue[" + std::to_string(k) + "]";
    if (gl.a_entry >= a.automaton.initial.size() || gl.b_entry >= b.automaton.initial.size())
      throw InvalidInput(where + ": names an initial entry that does not exist");
    const StateId ca = a.automaton.initial[gl.a_entry].state, cb = b.automaton.initial[gl.b_entry].state;
    const int ba = find_boundary(a, ca, gl.a_boundary), bb = find_boundary(b, cb, gl.b_boundary);
    if (ba < 0)
      throw InvalidInput(where + ": A's cell " + cell_text(a, ca) + " has no boundary \"" + gl.a_boundary +
                         "\"");
    if (bb < 0)
      throw InvalidInput(where + ": B's cell " + cell_text(b, cb) + " has no boundary \"" + gl.b_boundary +
                         "\"");
    out.emplace_back(ba, bb);
  }
  return out;
}

/// B's shared cells and boundaries and their partners in A.
struct Sharing {
  std::map<StateId, StateId> partner;   // B cell → A cell
  std::map<int, int> boundary_partner;  // B boundary index → A boundary index (on shared cells)
};

/// The pair (xa, xb) is glued: it must hold alike, and its boundaries pair up by name.
void check_glued_pair(const Bcifs& a, StateId xa, const Bcifs& b, StateId xb) {
  const auto& ga = a.automaton.graph;
  const auto& gb = b.automaton.graph;
  const std::string pair = "A's " + cell_text(a, xa) + " and B's " + cell_text(b, xb);
  if (ga[xa].size != gb[xb].size)
    throw InvalidInput(pair + " are glued but hold " + std::to_string(ga[xa].size) + " and " +
                       std::to_string(gb[xb].size) + " points");
  if (a.dimension[xa] != b.dimension[xb])
    throw InvalidInput(pair + " are glued but have dimensions " + std::to_string(a.dimension[xa]) + " and " +
                       std::to_string(b.dimension[xb]));
  if (out_degree(xa, ga) != out_degree(xb, gb))
    throw InvalidInput(pair + " are glued but have " + std::to_string(out_degree(xa, ga)) + " and " +
                       std::to_string(out_degree(xb, gb)) + " children");
}

/// Shared cells: closure of the glued pairs under children and boundaries, in the order found.
Sharing share_cells(const Bcifs& a, const Bcifs& b, std::span<const std::pair<int, int>> glued,
                    std::vector<std::pair<StateId, StateId>>& shared) {
  const auto& gb = b.automaton.graph;
  Sharing out;
  std::deque<std::pair<StateId, StateId>> todo;
  for (const auto& [ba, bb] : glued)
    todo.emplace_back(a.boundaries[static_cast<std::size_t>(ba)].boundary,
                      b.boundaries[static_cast<std::size_t>(bb)].boundary);
  while (!todo.empty()) {
    const auto [xa, xb] = todo.front();
    todo.pop_front();
    const auto [it, added] = out.partner.try_emplace(xb, xa);
    if (!added) {
      if (it->second != xa)
        throw InvalidInput("B's cell " + cell_text(b, xb) + " would be both " + cell_text(a, it->second) +
                           " and " + cell_text(a, xa) +
                           " of A (the glued boundaries do not subdivide alike)");
      continue;
    }
    check_glued_pair(a, xa, b, xb);
    shared.emplace_back(xa, xb);
    for (int c = 0; c < static_cast<int>(out_degree(xb, gb)); ++c)
      todo.emplace_back(child_of(a, xa, c), child_of(b, xb, c));
    for (std::size_t i = 0; i < b.boundaries.size(); ++i) {
      const auto& op = b.boundaries[i];
      if (op.cell != xb) continue;
      const int j = find_boundary(a, xa, op.name);
      if (j < 0 || a.boundaries[static_cast<std::size_t>(j)].rows != op.rows)
        throw InvalidInput("A's " + cell_text(a, xa) + " and B's " + cell_text(b, xb) +
                           " are glued but A's has no boundary \"" + op.name + "\" with the same rows");
      out.boundary_partner[static_cast<int>(i)] = j;
      todo.emplace_back(a.boundaries[static_cast<std::size_t>(j)].boundary, op.boundary);
    }
  }
  return out;
}

/// The joined automaton's cells and transitions: A's as they are, then B's cells that are not
/// shared. Returns the joined id of every cell of B.
std::vector<StateId> join_cells(const Bcifs& a, const Bcifs& b, const Sharing& sharing,
                                const JoinOptions& options, Bcifs& sys) {
  const auto& ga = a.automaton.graph;
  const auto& gb = b.automaton.graph;
  auto& g = sys.automaton.graph;
  for (StateId s = 0; s < num_vertices(ga); ++s) {
    automata::State st = ga[s];
    st.name = options.a_name + ":" + cell_text(a, s);
    add_vertex(st, g);
    sys.dimension.push_back(a.dimension[s]);
  }
  std::vector<StateId> id(num_vertices(gb));
  for (StateId s = 0; s < num_vertices(gb); ++s) {
    if (const auto it = sharing.partner.find(s); it != sharing.partner.end()) {
      id[s] = it->second;
      continue;
    }
    automata::State st = gb[s];
    st.name = options.b_name + ":" + cell_text(b, s);
    id[s] = add_vertex(st, g);
    sys.dimension.push_back(b.dimension[s]);
  }
  for (const automata::TransitionId e : edges(ga)) add_edge(source(e, ga), target(e, ga), ga[e], g);
  for (StateId s = 0; s < num_vertices(gb); ++s) {
    if (sharing.partner.count(s)) continue;
    for (auto [e, end] = out_edges(s, gb); e != end; ++e) add_edge(id[s], id[target(*e, gb)], gb[*e], g);
  }
  return id;
}

/// A's boundary operators, then B's that are not shared. Returns the joined index of every
/// boundary of B.
std::vector<int> join_boundaries(const Bcifs& a, const Bcifs& b, const Sharing& sharing,
                                 std::span<const StateId> id, Bcifs& sys) {
  sys.boundaries = a.boundaries;
  std::vector<int> boundary_id(b.boundaries.size());
  for (std::size_t i = 0; i < b.boundaries.size(); ++i) {
    if (const auto it = sharing.boundary_partner.find(static_cast<int>(i));
        it != sharing.boundary_partner.end()) {
      boundary_id[i] = it->second;
      continue;
    }
    BoundaryOperator op = b.boundaries[i];
    op.cell = id[op.cell];
    op.boundary = id[op.boundary];
    boundary_id[i] = static_cast<int>(sys.boundaries.size());
    sys.boundaries.push_back(std::move(op));
  }
  return boundary_id;
}

/// A's constraints, then B's on cells that are not shared; B's that read a shared cell are the
/// junction constraints.
void join_constraints(const Bcifs& a, const Bcifs& b, const Sharing& sharing, std::span<const StateId> id,
                      std::span<const int> boundary_id, const JoinOptions& options, Junction& result) {
  Bcifs& sys = result.system;
  // A transition of B names its source by B's id; a shared source reads A's transition.
  const auto map_factor = [&](Factor f) {
    if (f.kind == Factor::Kind::boundary)
      f.boundary = boundary_id[static_cast<std::size_t>(f.boundary)];
    else
      f.transition.from = id[f.transition.from];
    return f;
  };
  for (Constraint c : a.constraints) {
    c.name = options.a_name + ":" + c.name;
    sys.constraints.push_back(std::move(c));
  }
  for (const Constraint& c : b.constraints) {
    if (sharing.partner.count(source_cell(b, c))) continue;  // on a shared cell: A's constraints hold
    Constraint out{options.b_name + ":" + c.name, {}, {}};
    bool reads_shared = false;
    for (int side = 0; side < 2; ++side)
      for (const Factor& f : side ? c.right : c.left) {
        (side ? out.right : out.left).push_back(map_factor(f));
        if (f.kind == Factor::Kind::transition
                ? sharing.partner.count(f.transition.from) > 0
                : sharing.boundary_partner.count(f.boundary) > 0 ||
                      sharing.partner.count(b.boundaries[static_cast<std::size_t>(f.boundary)].boundary) > 0)
          reads_shared = true;
      }
    if (reads_shared) result.junction_constraints.push_back(out.name);
    sys.constraints.push_back(std::move(out));
  }
}

/// Nets: A's, then B's with their glued rows replaced by A's.
std::vector<Points> glue_nets(const Bcifs& a, std::span<const Points> nets_a, const Bcifs& b,
                              std::span<const Points> nets_b, std::span<const Glue> glue,
                              std::span<const std::pair<int, int>> glued) {
  std::vector<Points> nets(nets_a.begin(), nets_a.end());
  std::vector<Points> nb(nets_b.begin(), nets_b.end());
  for (std::size_t k = 0; k < glue.size(); ++k) {
    const auto& ra = a.boundaries[static_cast<std::size_t>(glued[k].first)].rows;
    const auto& rb = b.boundaries[static_cast<std::size_t>(glued[k].second)].rows;
    const Points& Na = nets_a[glue[k].a_entry];
    Points& Nb = nb[glue[k].b_entry];
    if (Na.cols() != Nb.cols())
      throw InvalidInput("A's control nets have " + std::to_string(Na.cols()) + " columns, B's " +
                         std::to_string(Nb.cols()) + "; give both the same");
    for (std::size_t i = 0; i < ra.size(); ++i) Nb.row(rb[i]) = Na.row(ra[i]);
  }
  nets.insert(nets.end(), nb.begin(), nb.end());
  return nets;
}

}  // namespace

Junction join(const Bcifs& a, std::span<const Points> nets_a, const Bcifs& b, std::span<const Points> nets_b,
              std::span<const Glue> glue, const JoinOptions& options) {
  validate(a);
  validate(b);
  check_join_nets(a, nets_a, b, nets_b, glue);
  const std::vector<std::pair<int, int>> glued = glued_boundaries(a, b, glue);
  Junction result;
  const Sharing sharing = share_cells(a, b, glued, result.shared);

  // The joined system: A as it is, then B's cells that are not shared.
  Bcifs& sys = result.system;
  const std::vector<StateId> id = join_cells(a, b, sharing, options, sys);
  const std::vector<int> boundary_id = join_boundaries(a, b, sharing, id, sys);
  join_constraints(a, b, sharing, id, boundary_id, options, result);
  if (options.free_a) sys.free = a.free;
  for (const TransitionRef& t : b.free)
    if (!sharing.partner.count(t.from)) sys.free.push_back(TransitionRef{id[t.from], t.child});
  sys.automaton.initial = a.automaton.initial;
  for (automata::Initial init : b.automaton.initial) {
    init.state = id[init.state];
    sys.automaton.initial.push_back(init);
  }
  automata::mark_recurrent(sys.automaton);
  validate(sys);
  if (!nets_a.empty() && !nets_b.empty()) result.nets = glue_nets(a, nets_a, b, nets_b, glue, glued);

  // Project the free matrices onto the admissible space.
  const AdmissibleSpace space = admissible_space(sys, options.solve);
  sys = with_free_values(sys, space, free_values(sys, space));
  result.free = space.free.size();
  for (const auto& [name, r] : constraint_residuals(sys)) result.residual = std::max(result.residual, r);
  check_admissible(sys);
  return result;
}

}  // namespace cifs::ifs
