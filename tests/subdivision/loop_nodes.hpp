// SPDX-License-Identifier: MIT
// A Loop surface automaton's faces one at a time (tests): a face's attractor nodes from its own net, the
// gap between the leaves of one face where they meet inside it, and the name of a node by the mesh (a
// vertex, a point of an edge, or inside the face), for the watertightness checks of fractal Loop surfaces.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "cifs/ifs/analysis.hpp"
#include "cifs/subdivision/limit.hpp"

namespace cifs_test {

/// Every face's attractor at `depth`, each from its own net (not welded: the faces are given corners of
/// their own, so surface_automaton_mesh shares no node): face f's node (i, j), i + j ≤ 2^depth, at row
/// Σ_{i' < i} (2^depth − i' + 1) + j of out[f] (loop_node).
inline std::vector<cifs::Points> loop_face_nodes(const cifs::subdivision::SurfaceAutomaton& s, int depth) {
  cifs::subdivision::SurfaceAutomaton apart = s;
  for (std::size_t f = 0; f < apart.corners.size(); ++f) {
    const int c = 3 * static_cast<int>(f);
    apart.corners[f] = {c, c + 1, c + 2, -1};
  }
  const cifs::Points all = cifs::subdivision::surface_automaton_mesh(apart, depth).vertices;
  const Eigen::Index per = ((1 << depth) + 1) * ((1 << depth) + 2) / 2;
  std::vector<cifs::Points> out;
  for (std::size_t f = 0; f < s.nets.size(); ++f)
    out.emplace_back(all.middleRows(static_cast<Eigen::Index>(f) * per, per));
  return out;
}

/// The largest distance between two leaves' corners at one grid node (i, j) of one face at `depth`, over
/// every face, each leaf's corners computed from its own net (the fixed points of its corner children):
/// zero when the faces' pieces meet along every edge created inside them. surface_automaton_mesh computes
/// each node once per face, so it would not see a crack there.
inline double loop_inner_gap(const cifs::subdivision::SurfaceAutomaton& s, int depth) {
  const cifs::automata::Graph& g = s.automaton.graph;
  std::array<std::vector<Eigen::RowVectorXd>, 3> fixed;
  for (std::size_t c = 0; c < 3; ++c)
    fixed[c] = cifs::ifs::repeated_child_functionals(s.automaton, static_cast<int>(c));
  std::map<std::array<int, 2>, Eigen::RowVectorXd> seen;
  double gap = 0;
  // As surface_automaton_mesh walks: a triangle's corner 0 at (i, j), corners 1 and 2 at ± h along i, j.
  const auto visit = [&](const auto& self, cifs::automata::StateId state, const cifs::Points& net, int i,
                         int j, int sign, int h) -> void {
    if (h == 1) {
      const std::array<std::array<int, 2>, 3> at{{{i, j}, {i + sign, j}, {i, j + sign}}};
      for (std::size_t k = 0; k < 3; ++k) {
        const Eigen::RowVectorXd p = fixed[k][state] * net;
        const auto [it, fresh] = seen.emplace(at[k], p);
        if (!fresh) gap = std::max(gap, (it->second - p).norm());
      }
      return;
    }
    const int half = h / 2;
    const std::array<std::array<int, 3>, 4> child{{{i, j, sign},
                                                   {i + sign * half, j, sign},
                                                   {i, j + sign * half, sign},
                                                   {i + sign * half, j + sign * half, -sign}}};
    std::size_t k = 0;
    for (auto [e, end] = out_edges(state, g); e != end; ++e, ++k)
      self(self, target(*e, g), cifs::Points(g[*e].matrix * net), child[k][0], child[k][1], child[k][2],
           half);
  };
  for (std::size_t f = 0; f < s.nets.size(); ++f) {
    seen.clear();
    visit(visit, s.automaton.initial[f].state, s.nets[f], 0, 0, 1, 1 << depth);
  }
  return gap;
}

inline int loop_node(int i, int j, int side) {
  return i * (side + 1) - i * (i - 1) / 2 + j;
}

/// The node (i, j) of face corners c as the mesh names it: a mesh vertex {v, −1, 0}, a point of a mesh
/// edge {lower, higher, cells from lower}, or {−1, −1, 0} inside the face.
inline std::array<int, 3> loop_node_key(const std::array<int, 4>& c, int i, int j, int side) {
  const auto on_edge = [&](int a, int b, int at) {
    return a < b ? std::array{a, b, at} : std::array{b, a, side - at};
  };
  if (i == 0 && j == 0) return {c[0], -1, 0};
  if (i == side) return {c[1], -1, 0};
  if (j == side) return {c[2], -1, 0};
  if (j == 0) return on_edge(c[0], c[1], i);
  if (i + j == side) return on_edge(c[1], c[2], j);
  if (i == 0) return on_edge(c[0], c[2], j);
  return {-1, -1, 0};
}

/// The face's (u, v) at the patch's (s, t) of initial entry i: the patch's corners are the face's turned
/// by the place of corners[0] among them, so the face's barycentric weights are the patch's turned.
inline cifs::subdivision::FacePoint loop_face_point(const cifs::subdivision::SurfaceAutomaton& s,
                                                    const cifs::MeshTopology& t, std::size_t i, double a,
                                                    double b) {
  const int f = s.automaton.initial[i].segment;
  const auto corners = cifs::face(t, static_cast<std::size_t>(f));
  const auto turn =
      static_cast<int>(std::find(corners.begin(), corners.end(), s.corners[i][0]) - corners.begin());
  const std::array<double, 3> patch{1 - a - b, a, b};  // at the patch's corners 0, 1, 2
  const auto w = [&](int k) { return patch[static_cast<std::size_t>((k - turn + 3) % 3)]; };
  return {.face = f, .u = w(1), .v = w(2)};
}

}  // namespace cifs_test
