// SPDX-License-Identifier: MIT
// cifs — mesh adjacency: half-edges grouped by origin, twins found in the (short) list of the
// other end, then one walk around every vertex.
#include "cifs/topology.hpp"

#include <algorithm>
#include <climits>
#include <string>

#include "cifs/errors.hpp"

namespace cifs {
namespace {

std::string pair_text(int a, int b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

/// Checks the face arrays themselves: offsets, sizes, indices, no repeated corner.
void check_faces(std::span<const int> offsets, std::span<const int> corners, int vertex_count,
                 const std::string& who) {
  if (vertex_count < 0) throw InvalidInput(who + ": negative vertex count");
  if (offsets.empty() || offsets[0] != 0)
    throw InvalidInput(who + ": face offsets must start with 0 (" + std::to_string(offsets.size()) +
                       " given)");
  if (static_cast<std::size_t>(offsets.back()) != corners.size())
    throw InvalidInput(who + ": the face offsets end at " + std::to_string(offsets.back()) + " but " +
                       std::to_string(corners.size()) + " corners are given");
  if (corners.size() > static_cast<std::size_t>(INT_MAX / 2))
    throw InvalidInput(who + ": " + std::to_string(corners.size()) +
                       " corners, more than 32-bit indices hold");
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
    const int size = offsets[f + 1] - offsets[f];
    if (size < 3)
      throw InvalidInput(who + ": face " + std::to_string(f) + " has " + std::to_string(std::max(size, 0)) +
                         " vertices, a face needs at least 3");
    const auto face = corners.subspan(static_cast<std::size_t>(offsets[f]), static_cast<std::size_t>(size));
    for (std::size_t i = 0; i < face.size(); ++i) {
      if (face[i] < 0 || face[i] >= vertex_count)
        throw InvalidInput(who + ": face " + std::to_string(f) + " corner " + std::to_string(i) +
                           " is vertex " + std::to_string(face[i]) + ", out of range (" +
                           std::to_string(vertex_count) + " vertices)");
      for (std::size_t j = 0; j < i; ++j)
        if (face[j] == face[i])
          throw InvalidInput(who + ": face " + std::to_string(f) + " repeats vertex " +
                             std::to_string(face[i]) + " (corners " + std::to_string(j) + " and " +
                             std::to_string(i) + ")");
    }
  }
}

}  // namespace

MeshTopology build_topology(std::span<const int> face_offsets, std::span<const int> face_vertices,
                            int vertex_count, std::string_view who) {
  return build_topology(std::vector<int>(face_offsets.begin(), face_offsets.end()),
                        std::vector<int>(face_vertices.begin(), face_vertices.end()), vertex_count, who);
}

MeshTopology build_topology(std::vector<int> offsets, std::vector<int> corners, int vertex_count,
                            std::string_view who_view) {
  const std::string who(who_view);
  check_faces(offsets, corners, vertex_count, who);
  MeshTopology t;
  t.vertex_count = vertex_count;
  t.face_offsets = std::move(offsets);
  t.face_vertices = std::move(corners);
  const std::span<const int> face_offsets(t.face_offsets), face_vertices(t.face_vertices);
  const std::size_t F = face_offsets.size() - 1, H = face_vertices.size();
  const auto V = static_cast<std::size_t>(vertex_count);

  // Half-edge h is corner h of face_vertices going to the next corner of its face.
  std::vector<int> face_of(H), next(H), prev(H);
  for (std::size_t f = 0; f < F; ++f) {
    const int b = face_offsets[f], e = face_offsets[f + 1];
    for (int h = b; h < e; ++h) {
      face_of[static_cast<std::size_t>(h)] = static_cast<int>(f);
      next[static_cast<std::size_t>(h)] = h + 1 < e ? h + 1 : b;
      prev[static_cast<std::size_t>(h)] = h > b ? h - 1 : e - 1;
    }
  }
  const auto origin = [&](int h) { return face_vertices[static_cast<std::size_t>(h)]; };
  const auto target = [&](int h) {
    return face_vertices[static_cast<std::size_t>(next[static_cast<std::size_t>(h)])];
  };

  // Half-edges grouped by origin (CSR), in corner order.
  std::vector<int> out_offsets(V + 1, 0), out_list(H);
  for (std::size_t h = 0; h < H; ++h) ++out_offsets[static_cast<std::size_t>(face_vertices[h]) + 1];
  for (std::size_t v = 0; v < V; ++v) out_offsets[v + 1] += out_offsets[v];
  {
    std::vector<int> fill(out_offsets.begin(), out_offsets.end() - 1);
    for (std::size_t h = 0; h < H; ++h)
      out_list[static_cast<std::size_t>(fill[static_cast<std::size_t>(face_vertices[h])]++)] =
          static_cast<int>(h);
  }
  // Twins: the half-edge b → a for a → b; two a → b half-edges or two twins are not manifold.
  std::vector<int> twin(H, -1);
  for (std::size_t v = 0; v < V; ++v) {
    for (int k = out_offsets[v]; k < out_offsets[v + 1]; ++k) {
      const int h = out_list[static_cast<std::size_t>(k)];
      const int b = target(h);
      for (int j = out_offsets[v]; j < k; ++j) {
        const int g = out_list[static_cast<std::size_t>(j)];
        if (target(g) == b) {
          // Two faces run along v → b in the same direction: either a third face on the edge or
          // inconsistent orientation.
          throw InvalidInput(who + ": faces " + std::to_string(face_of[static_cast<std::size_t>(g)]) +
                             " and " + std::to_string(face_of[static_cast<std::size_t>(h)]) +
                             " both use edge " + pair_text(static_cast<int>(v), b) +
                             " in the same direction (inconsistent orientation, or an edge of more than two "
                             "faces: not an oriented manifold)");
        }
      }
      for (int j = out_offsets[static_cast<std::size_t>(b)]; j < out_offsets[static_cast<std::size_t>(b) + 1];
           ++j) {
        const int g = out_list[static_cast<std::size_t>(j)];
        if (target(g) == static_cast<int>(v)) twin[static_cast<std::size_t>(h)] = g;
      }
    }
  }

  // Edges in order of first appearance.
  t.face_edges.assign(H, -1);
  t.edges.reserve(H / 2 + 1);
  t.edge_faces.reserve(H / 2 + 1);
  for (std::size_t h = 0; h < H; ++h) {
    if (t.face_edges[h] >= 0) continue;
    const int e = static_cast<int>(t.edges.size());
    t.face_edges[h] = e;
    t.edges.push_back({origin(static_cast<int>(h)), target(static_cast<int>(h))});
    const int g = twin[h];
    t.edge_faces.push_back({face_of[h], g >= 0 ? face_of[static_cast<std::size_t>(g)] : -1});
    if (g >= 0) t.face_edges[static_cast<std::size_t>(g)] = e;
  }

  // Around every vertex, counter-clockwise: the half-edge leaving v in face k is followed (in the
  // rotation) by the twin of face k's half-edge entering v. Start at the outgoing half-edge whose
  // edge is on the boundary (no face before it), if any.
  t.boundary_vertex.assign(V, 0);
  t.vertex_offsets_edges.assign(V + 1, 0);
  t.vertex_offsets_faces.assign(V + 1, 0);
  t.vertex_edge_list.reserve(H + H / 4);
  t.vertex_face_list.reserve(H);
  t.vertex_corner_list.reserve(H);
  for (std::size_t v = 0; v < V; ++v) {
    const int begin = out_offsets[v], end = out_offsets[v + 1];
    int start = -1;
    for (int k = begin; k < end && start < 0; ++k) {
      const int h = out_list[static_cast<std::size_t>(k)];
      if (twin[static_cast<std::size_t>(h)] < 0) start = h;
    }
    const bool boundary = start >= 0;
    if (!boundary && begin < end) start = out_list[static_cast<std::size_t>(begin)];
    int faces = 0;
    for (int h = start; h >= 0 && (faces == 0 || h != start);) {
      t.vertex_edge_list.push_back(t.face_edges[static_cast<std::size_t>(h)]);
      t.vertex_face_list.push_back(face_of[static_cast<std::size_t>(h)]);
      t.vertex_corner_list.push_back(
          h - face_offsets[static_cast<std::size_t>(face_of[static_cast<std::size_t>(h)])]);
      ++faces;
      const int entering = prev[static_cast<std::size_t>(h)];
      const int after = twin[static_cast<std::size_t>(entering)];
      if (after < 0) {  // the ring ends on a boundary edge: it is the last edge
        t.vertex_edge_list.push_back(t.face_edges[static_cast<std::size_t>(entering)]);
        break;
      }
      h = after;
      if (faces > end - begin) break;  // cannot happen on valid input; guards the loop
    }
    if (faces != end - begin) {
      throw InvalidInput(who + ": vertex " + std::to_string(v) + " is not manifold: its " +
                         std::to_string(end - begin) + " faces do not form one fan around it (" +
                         std::to_string(faces) + " are reached walking around it)");
    }
    t.boundary_vertex[v] = boundary ? 1 : 0;
    t.vertex_offsets_edges[v + 1] = static_cast<int>(t.vertex_edge_list.size());
    t.vertex_offsets_faces[v + 1] = static_cast<int>(t.vertex_face_list.size());
  }
  return t;
}

std::vector<std::vector<int>> boundary_loops(const MeshTopology& t) {
  // Boundary edges run in the direction of their one face: edges[e][0] → edges[e][1].
  const auto V = static_cast<std::size_t>(t.vertex_count);
  std::vector<int> next_edge(V, -1);
  for (std::size_t e = 0; e < t.edges.size(); ++e)
    if (t.edge_faces[e][1] < 0) next_edge[static_cast<std::size_t>(t.edges[e][0])] = static_cast<int>(e);
  std::vector<std::vector<int>> loops;
  std::vector<char> seen(V, 0);
  for (std::size_t v = 0; v < V; ++v) {
    if (next_edge[v] < 0 || seen[v]) continue;
    std::vector<int> loop;
    for (int u = static_cast<int>(v); !seen[static_cast<std::size_t>(u)];) {
      seen[static_cast<std::size_t>(u)] = 1;
      loop.push_back(u);
      u = t.edges[static_cast<std::size_t>(next_edge[static_cast<std::size_t>(u)])][1];
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace cifs
