// SPDX-License-Identifier: MIT
// The refined vertices at the dyadic points of a face (tests): which vertex of a refinement's level
// sits at (i, j)/2^levels of a face, found by refining the face's grid of vertex indices by the child
// numbering (vertex points keep their index, edge e's point is V + e, Catmull–Clark's face f's V + E +
// f) — independent of the surface automaton's child conventions.
#pragma once

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"

namespace cifs_test {

/// The edge joining a and b of a refined level (they are neighbours by construction).
inline int dyadic_edge(const cifs::MeshTopology& t, int a, int b) {
  const int e = cifs::find_edge(t, a, b);
  if (e < 0) FAIL("no edge");
  return e;
}

/// The vertices of `levels` Catmull–Clark steps after level `start` at the points (i, j)/2^levels of
/// the quad whose corners (at level `start`) are `c` (counter-clockwise, c[0] at (0, 0), c[1] at
/// (1, 0)), [i][j] flattened by i.
inline std::vector<int> dyadic_quad_vertices(const cifs::subdivision::MeshRefinement& r, std::array<int, 4> c,
                                             int start, int levels) {
  int m = 1;
  std::vector<int> grid{c[0], c[3], c[1], c[2]};  // [i][j], i along corner 0 → 1
  for (int l = start; l < start + levels; ++l) {
    const cifs::MeshTopology& t = r.levels[static_cast<std::size_t>(l)];
    const int M = 2 * m, V = t.vertex_count, E = static_cast<int>(t.edges.size());
    std::vector<int> next(static_cast<std::size_t>((M + 1) * (M + 1)));
    const auto g = [&](int i, int j) { return grid[static_cast<std::size_t>(i * (m + 1) + j)]; };
    const auto set = [&](int i, int j, int v) { next[static_cast<std::size_t>(i * (M + 1) + j)] = v; };
    const auto edge = [&](int a, int b) { return dyadic_edge(t, a, b); };
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j <= m; ++j) {
        set(2 * i, 2 * j, g(i, j));
        if (i < m) set(2 * i + 1, 2 * j, V + edge(g(i, j), g(i + 1, j)));
        if (j < m) set(2 * i, 2 * j + 1, V + edge(g(i, j), g(i, j + 1)));
        if (i < m && j < m)
          for (const int a : cifs::vertex_faces(t, static_cast<std::size_t>(g(i, j))))
            for (const int b : cifs::vertex_faces(t, static_cast<std::size_t>(g(i + 1, j + 1))))
              if (a == b) set(2 * i + 1, 2 * j + 1, V + E + a);
      }
    grid = std::move(next);
    m = M;
  }
  return grid;
}

/// The same for quad f of level 0.
inline std::vector<int> dyadic_vertices(const cifs::subdivision::MeshRefinement& r, int f, int levels) {
  const auto c = cifs::face(r.levels[0], static_cast<std::size_t>(f));
  return dyadic_quad_vertices(r, {c[0], c[1], c[2], c[3]}, 0, levels);
}

/// The vertices of `levels` more Loop steps at the points (i, j)/2^levels of triangle f of level 0
/// (corner 1 at (1, 0), 2 at (0, 1)), [i][j] flattened by i over a square (−1 beyond the triangle).
inline std::vector<int> dyadic_triangle_vertices(const cifs::subdivision::MeshRefinement& r, int f,
                                                 int levels) {
  const auto c = cifs::face(r.levels[0], static_cast<std::size_t>(f));
  int m = 1;
  std::vector<int> grid{c[0], c[2], c[1], -1};  // [i][j], i along corner 0 → 1
  for (int l = 0; l < levels; ++l) {
    const cifs::MeshTopology& t = r.levels[static_cast<std::size_t>(l)];
    const int M = 2 * m, V = t.vertex_count;
    std::vector<int> next(static_cast<std::size_t>((M + 1) * (M + 1)), -1);
    const auto g = [&](int i, int j) { return grid[static_cast<std::size_t>(i * (m + 1) + j)]; };
    const auto set = [&](int i, int j, int v) { next[static_cast<std::size_t>(i * (M + 1) + j)] = v; };
    const auto edge = [&](int a, int b) { return dyadic_edge(t, a, b); };
    for (int i = 0; i <= m; ++i)
      for (int j = 0; i + j <= m; ++j) {
        set(2 * i, 2 * j, g(i, j));
        if (i + j == m) continue;
        set(2 * i + 1, 2 * j, V + edge(g(i, j), g(i + 1, j)));
        set(2 * i, 2 * j + 1, V + edge(g(i, j), g(i, j + 1)));
        set(2 * i + 1, 2 * j + 1, V + edge(g(i + 1, j), g(i, j + 1)));
      }
    grid = std::move(next);
    m = M;
  }
  return grid;
}

/// The face point of a quad surface automaton's chaos-game address: the initial entry (integer part) and the
/// base-4 digits 2·iu + iv of the quarters, i.e. the dyadic (s, t) of the corner (0, 0) of the node a point
/// stands on, turned to the face's (u, v) by the place of the entry's corners[0] among the face's corners.
inline cifs::subdivision::FacePoint address_point(const cifs::subdivision::SurfaceAutomaton& s,
                                                  const cifs::MeshTopology& t, double address) {
  const auto entry = static_cast<std::size_t>(std::floor(address));
  double rest = address - static_cast<double>(entry), a = 0, b = 0, unit = 0.5;
  for (int k = 0; k < 26 && rest > 0; ++k, unit /= 2) {
    rest *= 4;
    const int digit = static_cast<int>(std::floor(rest));
    rest -= digit;
    a += unit * (digit / 2);
    b += unit * (digit % 2);
  }
  REQUIRE(rest == 0);
  const int f = s.automaton.initial[entry].segment;
  const auto corners = cifs::face(t, static_cast<std::size_t>(f));
  const auto turn = static_cast<std::size_t>(std::find(corners.begin(), corners.end(), s.corners[entry][0]) -
                                             corners.begin());
  const std::array<std::array<double, 2>, 4> uv{{{a, b}, {1 - b, a}, {1 - a, 1 - b}, {b, 1 - a}}};
  return {.face = f, .u = uv[turn][0], .v = uv[turn][1]};
}

}  // namespace cifs_test
