// SPDX-License-Identifier: MIT
// Two topologies of the same faces compared array by array (edges, their faces, rings, boundary flags):
// what every route to a MeshTopology must agree on, orders included.
#pragma once

#include <catch2/catch.hpp>

#include "cifs/topology.hpp"

namespace cifs_test {

inline void check_same_topology(const cifs::MeshTopology& a, const cifs::MeshTopology& b) {
  CHECK(a.face_edges == b.face_edges);
  CHECK(a.edges == b.edges);
  CHECK(a.edge_faces == b.edge_faces);
  CHECK(a.vertex_offsets_edges == b.vertex_offsets_edges);
  CHECK(a.vertex_edge_list == b.vertex_edge_list);
  CHECK(a.vertex_offsets_faces == b.vertex_offsets_faces);
  CHECK(a.vertex_face_list == b.vertex_face_list);
  CHECK(a.boundary_vertex == b.boundary_vertex);
}

}  // namespace cifs_test
