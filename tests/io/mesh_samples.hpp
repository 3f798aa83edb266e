// SPDX-License-Identifier: MIT
// Meshes the OBJ and PLY tests write and read back: values that need 17 digits, a closed cube and an
// open grid with irrational coordinates.
#pragma once

#include <cmath>
#include <vector>

#include "cifs/mesh.hpp"

namespace io_test {

/// Two triangles and a skew quad with values that need 17 digits.
inline cifs::Mesh sample_mesh(bool normals, bool states) {
  cifs::Mesh m;
  m.vertices.resize(5, 3);
  m.vertices << 0.1, 0.2, 0.3, 1.0 / 3, -2.5e-7, 1e10, 1, 1, 0, 0, 1, 0.7, -0.5, 0.25, std::sqrt(2.0);
  add_face(m, {0, 1, 2});
  add_face(m, {2, 3, 4});
  add_face(m, {0, 1, 3, 4});
  if (normals) m.normals = vertex_normals(m);
  if (states) m.states = {7, 4000000000u, 0};
  return m;
}

/// A closed unit cube of outward quads.
inline cifs::Mesh cube() {
  cifs::Mesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.vertices.row(i) << (i & 1), ((i >> 1) & 1), ((i >> 2) & 1);
  for (const auto& q : std::vector<std::vector<int>>{
           {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
    add_face(m, q);
  return m;
}

/// An open n × n grid of quads over a wavy height field (irrational coordinates).
inline cifs::Mesh open_grid(int n) {
  cifs::Mesh m;
  m.vertices.resize(static_cast<Eigen::Index>(n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.vertices.row(j * (n + 1) + i) << i / 3.0, j / 7.0, std::sin(i * 0.7) * std::cos(j * 1.3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      add_face(m, {v, v + 1, v + n + 2, v + n + 1});
    }
  return m;
}

}  // namespace io_test
