// SPDX-License-Identifier: MIT
// Test meshes for the subdivision surfaces: closed and open, regular and with extraordinary vertices.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "cifs/mesh.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/topology.hpp"

namespace cifs_test {

inline cifs::Mesh make_mesh(const std::vector<std::array<double, 3>>& points,
                            const std::vector<std::vector<int>>& faces) {
  cifs::Mesh m;
  m.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k)
      m.vertices(static_cast<Eigen::Index>(i), k) = points[i][static_cast<std::size_t>(k)];
  for (const auto& f : faces) cifs::add_face(m, std::span<const int>(f));
  return m;
}

/// Unit cube, outward quads (valence 3 everywhere).
inline cifs::Mesh cube() {
  return make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
                   {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}});
}

inline cifs::Mesh tetrahedron() {
  return make_mesh({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
                   {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}});
}

inline cifs::Mesh octahedron() {
  return make_mesh({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                   {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
}

/// Pentagonal bipyramid, slightly irregular: valences 4 (equator) and 5 (poles).
inline cifs::Mesh bipyramid() {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * std::numbers::pi * i / 5;
    p.push_back({std::cos(a) * (1 + 0.1 * i), std::sin(a), 0.05 * i});
  }
  p.push_back({0.1, 0, 1.3});
  p.push_back({0, -0.1, -1});
  std::vector<std::vector<int>> f;
  for (int i = 0; i < 5; ++i) {
    f.push_back({i, (i + 1) % 5, 5});
    f.push_back({(i + 1) % 5, i, 6});
  }
  return make_mesh(p, f);
}

/// A bipyramid over a k-gon: apexes of valence k, equator vertices of valence 4 (a little
/// irregular, so that no symmetry hides an error).
inline cifs::Mesh bipyramid_of(int k) {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < k; ++i) {
    const double a = 2 * std::numbers::pi * i / k;
    p.push_back({std::cos(a) * (1 + 0.05 * i), std::sin(a), 0.03 * i});
  }
  p.push_back({0.1, 0, 1.2});
  p.push_back({0, -0.1, -0.9});
  std::vector<std::vector<int>> f;
  for (int i = 0; i < k; ++i) {
    f.push_back({i, (i + 1) % k, k});
    f.push_back({(i + 1) % k, i, k + 1});
  }
  return make_mesh(p, f);
}

/// Square pyramid: one quad and four triangles (Catmull–Clark on mixed polygons; valence 4 apex).
inline cifs::Mesh pyramid() {
  return make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.4, 0.6, 0.9}},
                   {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
}

/// An n × m grid of quads over a wavy height field, open (boundary with valence-2 corners).
inline cifs::Mesh quad_grid(int n, int m, bool triangles = false) {
  std::vector<std::array<double, 3>> p;
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i)
      p.push_back({1.0 * i, 1.0 * j, std::sin(1.3 * i) * std::cos(0.7 * j) + 0.1 * i * j});
  std::vector<std::vector<int>> f;
  const auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      if (triangles) {
        f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return make_mesh(p, f);
}

/// An open grid of quads that is, read as control points, a uniform bicubic B-spline with knots
/// 0, 1, …: control point (i, j) spans [i, i + 4] × [j, j + 4], so grid face (i, j) is the
/// parameter square [i + 2, i + 3] × [j + 2, j + 3]. `params` is the same mesh with vertex (i, j)
/// at its parameter (i + 2, j + 2, 0): a scheme that reproduces linear functions maps it to the
/// parameters of its own points.
struct BicubicGrid {
  cifs::Mesh shape, params;
  cifs::nurbs::Surface surface;
};

inline BicubicGrid bicubic_grid(int n, int m) {
  BicubicGrid g{.shape = quad_grid(n, m), .params = quad_grid(n, m), .surface = {}};
  cifs::Points net((n + 1) * (m + 1), 3);
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i) {
      const auto r = static_cast<Eigen::Index>(j * (n + 1) + i);
      g.params.vertices.row(r) << i + 2.0, j + 2.0, 0.0;
      g.shape.vertices.row(r) << i + 0.3 * std::sin(1.7 * j), j + 0.2 * std::cos(0.9 * i + j),
          std::sin(1.3 * i) * std::cos(0.7 * j) + 0.1 * i * j;
      net.row(static_cast<Eigen::Index>(i * (m + 1) + j)) =
          g.shape.vertices.row(r);  // Surface order: i·nv + j
    }
  const auto uniform = [](int count) {
    cifs::nurbs::Knots k(static_cast<std::size_t>(count));
    for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<double>(i);
    return k;
  };
  g.surface = cifs::nurbs::make_surface({3, 3}, {uniform(n + 5), uniform(m + 5)}, {n + 1, m + 1}, net);
  return g;
}

/// A disc of triangles around a centre of valence k: a first ring of k vertices (valence 6), a
/// boundary ring of 2k; heights not symmetric.
inline cifs::Mesh fan(int k) {
  std::vector<std::array<double, 3>> p{{0, 0, 1}};
  for (int ring = 1; ring <= 2; ++ring)
    for (int i = 0; i < ring * k; ++i) {
      const double a = 2 * std::numbers::pi * i / (ring * k);
      p.push_back({ring * std::cos(a), ring * std::sin(a), 0.3 * std::sin(3 * a + ring) / ring});
    }
  const auto inner = [&](int i) { return 1 + i % k; };
  const auto outer = [&](int i) { return 1 + k + i % (2 * k); };
  std::vector<std::vector<int>> f;
  for (int i = 0; i < k; ++i) {
    f.push_back({0, inner(i), inner(i + 1)});
    f.push_back({inner(i), outer(2 * i), outer(2 * i + 1)});
    f.push_back({inner(i), outer(2 * i + 1), inner(i + 1)});
    f.push_back({inner(i + 1), outer(2 * i + 1), outer(2 * i + 2)});
  }
  return make_mesh(p, f);
}

/// A torus of n × m quads (or 2nm triangles), every vertex regular.
inline cifs::Mesh torus(int n, int m, bool triangles = false) {
  std::vector<std::array<double, 3>> p;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      const double r = 1 + 0.1 * std::sin(3 * u);  // not a surface of revolution: no symmetric ties
      p.push_back(
          {(3 + r * std::cos(v)) * std::cos(u), (3 + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  std::vector<std::vector<int>> f;
  const auto id = [&](int i, int j) { return (j % m) * n + (i % n); };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      if (triangles) {
        f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return make_mesh(p, f);
}

/// The unit cube with semi-sharp and sharp edges and corners of every kind: an edge at 0.3 (blended
/// from the first level), 1 (sharp one level), 1.7, 2.25, a chain at 3 and 10 (infinite), corners at
/// 0.5 and 2.
inline cifs::Mesh creased_cube() {
  cifs::Mesh m = cube();
  m.tags.creases = {{0, 1, 0.3}, {1, 2, 1.0}, {2, 3, 1.7}, {4, 5, 2.25}, {5, 6, 3}, {6, 7, 3}, {3, 7, 10}};
  m.tags.corners = {{0, 0.5}, {6, 2}};
  return m;
}

/// An open n × m grid (quads or triangles) over a wavy height field.
inline cifs::Mesh wavy_grid(int n, int m, bool triangles) {
  cifs::Mesh g = quad_grid(n, m, triangles);
  for (Eigen::Index i = 0; i < g.vertices.rows(); ++i)
    g.vertices(i, 2) = 0.3 * std::sin(1.3 * g.vertices(i, 0) + 0.7 * g.vertices(i, 1));
  return g;
}

/// Every edge of `m` as a vertex pair.
/// The mesh with each face's corner list turned by f mod `ways` places, so that patches' (s, t) meet the
/// faces' (u, v) in all four ways (quads; 3 for triangles).
inline cifs::Mesh turned_faces(cifs::Mesh m, std::size_t ways = 4) {
  for (std::size_t f = 0; f < cifs::face_count(m); ++f) {
    const auto b = m.face_vertices.begin() + m.face_offsets[f],
               e = m.face_vertices.begin() + m.face_offsets[f + 1];
    std::rotate(b, b + static_cast<std::ptrdiff_t>(f % ways), e);
  }
  return m;
}

inline std::vector<std::array<int, 2>> edges_of(const cifs::Mesh& m) {
  const cifs::MeshTopology t = cifs::build_topology(m);
  return t.edges;
}

/// Random tags: about a third of the edges creased, a few corners, a hole (when `holes`), with
/// sharpness drawn from values that floats do not hold exactly as well as from dyadic ones.
inline void random_tags(cifs::Mesh& m, std::mt19937& rng, bool holes) {
  constexpr double values[] = {0.1, 0.3, 0.5, 0.75, 1, 1.2, 1.5, 1.7, 2, 2.25, 2.9, 3.5, 4, 10, 12};
  std::uniform_int_distribution<int> pick(0, std::size(values) - 1), third(0, 2), coin(0, 1);
  m.tags.creases.clear();
  m.tags.corners.clear();
  m.tags.holes.clear();
  for (const auto& [a, b] : edges_of(m))
    if (third(rng) == 0) m.tags.creases.push_back({a, b, values[pick(rng)]});
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(m.vertices.rows()) - 1),
      face(0, static_cast<int>(cifs::face_count(m)) - 1);
  for (int k = 0; k < 3; ++k) {
    const int v = vertex(rng);
    if (std::none_of(m.tags.corners.begin(), m.tags.corners.end(),
                     [&](const auto& c) { return c.vertex == v; }))
      m.tags.corners.push_back({v, values[pick(rng)]});
  }
  if (holes) m.tags.holes.push_back(face(rng));
  m.tags.boundary = static_cast<cifs::BoundaryRule>(third(rng));
  m.tags.crease_method = coin(rng) ? cifs::CreaseMethod::chaikin : cifs::CreaseMethod::uniform;
}

/// A channel with seams along random edges (about one in four): around each vertex every run of faces
/// between seams (and the boundary) gets its own value — a dart where a seam ends inside the mesh,
/// three or more values where seams meet — and now and then two runs of a vertex share one value
/// (a value on faces that do not touch). Values: the vertex's (x, y) moved by the run's offset.
inline cifs::FaceVaryingChannel random_seams(const cifs::Mesh& m, std::mt19937& rng) {
  const cifs::MeshTopology t = cifs::build_topology(m);
  std::uniform_int_distribution<int> quarter(0, 3), tenth(0, 9);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  std::vector<char> seam(t.edges.size());
  for (char& s : seam) s = quarter(rng) == 0 ? 1 : 0;
  cifs::FaceVaryingChannel c;
  c.indices.assign(m.face_vertices.size(), -1);
  std::vector<std::array<double, 2>> values;
  for (int v = 0; v < t.vertex_count; ++v) {
    const auto edges = vertex_edges(t, static_cast<std::size_t>(v));
    const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
    const bool boundary = t.boundary_vertex[static_cast<std::size_t>(v)] != 0;
    const int first_value = static_cast<int>(values.size());
    int current = -1;
    for (std::size_t k = 0; k < faces.size(); ++k) {
      if (current < 0 || seam[static_cast<std::size_t>(edges[k])] != 0 || (boundary && k == 0)) {
        if (current >= first_value + 1 && tenth(rng) == 0) {
          current = first_value;  // back to the vertex's first value
        } else {
          current = static_cast<int>(values.size());
          values.push_back({m.vertices(v, 0) + offset(rng), m.vertices(v, 1) + offset(rng)});
        }
      }
      const auto f = static_cast<std::size_t>(faces[k]);
      for (int h = m.face_offsets[f]; h < m.face_offsets[f + 1]; ++h)
        if (m.face_vertices[static_cast<std::size_t>(h)] == v)
          c.indices[static_cast<std::size_t>(h)] = current;
    }
    // An interior ring whose last run reaches its first across an edge that is not a seam: one run.
    if (!boundary && !faces.empty() && seam[static_cast<std::size_t>(edges[0])] == 0 &&
        current != first_value) {
      for (const int f : faces)
        for (int h = m.face_offsets[static_cast<std::size_t>(f)];
             h < m.face_offsets[static_cast<std::size_t>(f) + 1]; ++h)
          if (c.indices[static_cast<std::size_t>(h)] == current)
            c.indices[static_cast<std::size_t>(h)] = first_value;
    }
  }
  c.values.resize(static_cast<Eigen::Index>(values.size()), 2);
  for (std::size_t i = 0; i < values.size(); ++i)
    c.values.row(static_cast<Eigen::Index>(i)) << values[i][0], values[i][1];
  return c;
}

}  // namespace cifs_test
