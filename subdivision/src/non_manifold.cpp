// SPDX-License-Identifier: MIT
// cifs — non-manifold meshes through a manifold stand-in (non_manifold.hpp).
#include "non_manifold.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

#include "cifs/errors.hpp"

namespace cifs::subdivision::detail {
namespace {

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32) |
         static_cast<std::uint32_t>(std::max(a, b));
}

int find(std::vector<int>& parent, int x) {
  while (parent[static_cast<std::size_t>(x)] != x) {
    parent[static_cast<std::size_t>(x)] =
        parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    x = parent[static_cast<std::size_t>(x)];
  }
  return x;
}

}  // namespace

std::optional<ManifoldSplit> split_non_manifold(const Mesh& mesh, const std::string& who) {
  const std::size_t H = mesh.face_vertices.size(), F = face_count(mesh);
  const auto V = static_cast<int>(mesh.vertices.rows());
  std::vector<int> next(H), face_of(H);
  for (std::size_t f = 0; f < F; ++f)
    for (int h = mesh.face_offsets[f]; h < mesh.face_offsets[f + 1]; ++h) {
      next[static_cast<std::size_t>(h)] = h + 1 < mesh.face_offsets[f + 1] ? h + 1 : mesh.face_offsets[f];
      face_of[static_cast<std::size_t>(h)] = static_cast<int>(f);
    }
  check_faces(mesh.face_offsets, mesh.face_vertices, V, who);  // a repeated corner would break the fans
  const auto from = [&](std::size_t h) { return mesh.face_vertices[h]; };
  const auto to = [&](std::size_t h) { return mesh.face_vertices[static_cast<std::size_t>(next[h])]; };
  // Half-edges grouped by their undirected edge.
  std::unordered_map<std::uint64_t, std::vector<int>> groups;
  groups.reserve(H);
  for (std::size_t h = 0; h < H; ++h) groups[edge_key(from(h), to(h))].push_back(static_cast<int>(h));
  // Corners joined across manifold edges (two faces, opposite directions) form the fans.
  std::vector<int> fan(H);
  std::iota(fan.begin(), fan.end(), 0);
  std::vector<char> non_manifold_edge(H, 0);  // per half-edge: its edge is not manifold
  for (const auto& [key, hs] : groups) {
    const bool manifold = hs.size() == 1 || (hs.size() == 2 && from(static_cast<std::size_t>(hs[0])) ==
                                                                   to(static_cast<std::size_t>(hs[1])));
    if (!manifold) {
      for (const int h : hs) non_manifold_edge[static_cast<std::size_t>(h)] = 1;
      continue;
    }
    if (hs.size() == 2) {
      const auto h1 = static_cast<std::size_t>(hs[0]), h2 = static_cast<std::size_t>(hs[1]);
      fan[static_cast<std::size_t>(find(fan, hs[0]))] = find(fan, next[h2]);  // both corners at from(h1)
      fan[static_cast<std::size_t>(find(fan, next[h1]))] = find(fan, hs[1]);  // both at to(h1)
    }
  }
  // Per vertex: its fans, in order of first corner; fan 0 keeps the vertex's index.
  std::vector<int> copy_of_fan(H, -1), corner_vertex(H);
  std::vector<int> fans_at(static_cast<std::size_t>(V), 0), representative(static_cast<std::size_t>(V));
  std::iota(representative.begin(), representative.end(), 0);
  int count = V;
  for (std::size_t h = 0; h < H; ++h) {
    const int root = find(fan, static_cast<int>(h));
    int& copy = copy_of_fan[static_cast<std::size_t>(root)];
    if (copy < 0) {
      const int v = from(h);
      copy = fans_at[static_cast<std::size_t>(v)]++ == 0 ? v : count++;
      if (copy >= V) representative.push_back(v);
    }
    corner_vertex[h] = copy;
  }
  // Non-manifold vertices and OpenSubdiv's counts at them (on the input's configuration).
  std::vector<char> non_manifold(static_cast<std::size_t>(V), 0);
  for (int v = 0; v < V; ++v)
    non_manifold[static_cast<std::size_t>(v)] = fans_at[static_cast<std::size_t>(v)] > 1;
  for (std::size_t h = 0; h < H; ++h)
    if (non_manifold_edge[h])
      non_manifold[static_cast<std::size_t>(from(h))] = non_manifold[static_cast<std::size_t>(to(h))] = 1;
  if (std::none_of(non_manifold.begin(), non_manifold.end(), [](char c) { return c != 0; }))
    return std::nullopt;
  struct Counts {
    int edges = 0, faces = 0, non_manifold_edges = 0, boundary_edges = 0;
  };
  std::vector<Counts> counts(static_cast<std::size_t>(V));
  for (std::size_t h = 0; h < H; ++h) ++counts[static_cast<std::size_t>(from(h))].faces;
  std::map<std::uint64_t, double> user_sharpness;
  for (std::size_t i = 0; i < mesh.tags.creases.size(); ++i) {
    const EdgeSharpness& c = mesh.tags.creases[i];
    if (!groups.contains(edge_key(c.a, c.b)))
      throw InvalidInput(who + ": crease " + std::to_string(i) + " joins vertices " + std::to_string(c.a) +
                         " and " + std::to_string(c.b) + ", which are not an edge of the mesh");
    user_sharpness[edge_key(c.a, c.b)] = c.sharpness;
  }
  std::vector<char> untagged_boundary(static_cast<std::size_t>(V), 0);
  for (const auto& [key, hs] : groups) {
    const auto h = static_cast<std::size_t>(hs[0]);
    for (const int v : {from(h), to(h)}) {
      Counts& c = counts[static_cast<std::size_t>(v)];
      ++c.edges;
      c.non_manifold_edges += non_manifold_edge[h];
      c.boundary_edges += hs.size() == 1;
      const auto s = user_sharpness.find(key);
      if (hs.size() == 1 && (s == user_sharpness.end() || s->second < kInfiniteSharpness))
        untagged_boundary[static_cast<std::size_t>(v)] = 1;
    }
  }

  ManifoldSplit out;
  out.representative = std::move(representative);
  Mesh& m = out.mesh;
  m.vertices.resize(count, mesh.vertices.cols());
  for (int v = 0; v < count; ++v)
    m.vertices.row(v) = mesh.vertices.row(out.representative[static_cast<std::size_t>(v)]);
  m.face_offsets = mesh.face_offsets;
  m.face_vertices = corner_vertex;
  m.face_varying = mesh.face_varying;
  m.states = mesh.states;
  m.tags = mesh.tags;
  m.tags.creases.clear();
  m.tags.corners.clear();
  // Edges: the user's sharpness on every copy; non-manifold edges infinitely sharp.
  std::map<std::uint64_t, double> sharpness;
  for (std::size_t h = 0; h < H; ++h) {
    const auto key = edge_key(from(h), to(h));
    const auto s = user_sharpness.find(key);
    const double value = non_manifold_edge[h]        ? kInfiniteSharpness
                         : s == user_sharpness.end() ? 0.0
                                                     : s->second;
    if (value > 0)
      sharpness[edge_key(corner_vertex[h], corner_vertex[static_cast<std::size_t>(next[h])])] = value;
  }
  for (const auto& [key, s] : sharpness)
    m.tags.creases.push_back({static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffU), s});
  // Vertices: OpenSubdiv's corners, or the user's sharpness, on every copy.
  std::vector<double> vertex(static_cast<std::size_t>(V), 0);
  for (const VertexSharpness& c : mesh.tags.corners) vertex[static_cast<std::size_t>(c.vertex)] = c.sharpness;
  for (int v = 0; v < V; ++v) {
    const Counts& c = counts[static_cast<std::size_t>(v)];
    const bool crease_along = c.non_manifold_edges == 2 && c.boundary_edges == 0 && c.faces > c.edges;
    if (non_manifold[static_cast<std::size_t>(v)] && !crease_along)
      vertex[static_cast<std::size_t>(v)] = kInfiniteSharpness;
  }
  for (int v = 0; v < count; ++v)
    if (const double s = vertex[static_cast<std::size_t>(out.representative[static_cast<std::size_t>(v)])];
        s > 0)
      m.tags.corners.push_back({v, s});
  // The boundary rule `none` acts on the input's vertices: all their faces, whichever fan.
  if (mesh.tags.boundary == BoundaryRule::none) {
    std::vector<char> hole = hole_flags(mesh);
    for (std::size_t h = 0; h < H; ++h)
      if (untagged_boundary[static_cast<std::size_t>(from(h))])
        hole[static_cast<std::size_t>(face_of[h])] = 1;
    m.tags.holes.clear();
    for (std::size_t f = 0; f < F; ++f)
      if (hole[f]) m.tags.holes.push_back(static_cast<int>(f));
  }
  try {
    (void)build_topology(m, who);
  } catch (const InvalidInput& e) {
    throw InvalidInput(
        std::string(e.what()) +
        " — after splitting the mesh's non-manifold vertices and edges; this configuration is not "
        "refined");
  }
  return out;
}

Representatives initial_representatives(const MeshTopology& t, std::vector<int> vertex) {
  Representatives r{.vertex = std::move(vertex), .edge = std::vector<int>(t.edges.size())};
  std::unordered_map<std::uint64_t, int> first;
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    const auto [a, b] = t.edges[e];
    r.edge[e] =
        first
            .emplace(edge_key(r.vertex[static_cast<std::size_t>(a)], r.vertex[static_cast<std::size_t>(b)]),
                     static_cast<int>(e))
            .first->second;
  }
  return r;
}

std::vector<int> child_vertex_representatives(const MeshTopology& parent, const Representatives& r,
                                              int child_vertex_count) {
  const int V = parent.vertex_count, E = static_cast<int>(parent.edges.size());
  std::vector<int> out(static_cast<std::size_t>(child_vertex_count));
  std::iota(out.begin(), out.end(), 0);
  for (int v = 0; v < V; ++v) out[static_cast<std::size_t>(v)] = r.vertex[static_cast<std::size_t>(v)];
  for (int e = 0; e < E; ++e) {
    const int point = V + e;  // edge e's point
    out[static_cast<std::size_t>(point)] = V + r.edge[static_cast<std::size_t>(e)];
  }
  return out;
}

std::vector<int> child_edge_representatives(const MeshTopology& parent, const Representatives& r,
                                            const MeshTopology& child) {
  const int V = parent.vertex_count, E = static_cast<int>(parent.edges.size());
  // half[2e + k]: the child edge from parent edge e's end k to its edge point.
  std::vector<int> half(2 * static_cast<std::size_t>(E), -1), out(child.edges.size());
  std::iota(out.begin(), out.end(), 0);
  for (std::size_t c = 0; c < child.edges.size(); ++c) {
    auto [a, b] = child.edges[c];
    if (a >= V) std::swap(a, b);
    if (a >= V || b < V || b >= V + E) continue;
    const auto e = static_cast<std::size_t>(b - V);
    half[2 * e + (parent.edges[e][0] == a ? 0 : 1)] = static_cast<int>(c);
  }
  for (std::size_t e = 0; e < static_cast<std::size_t>(E); ++e) {
    const auto o = static_cast<std::size_t>(r.edge[e]);
    for (std::size_t k = 0; k < 2; ++k) {
      // The end of the representative edge standing for this end.
      const int end = r.vertex[static_cast<std::size_t>(parent.edges[e][k])];
      const std::size_t j = r.vertex[static_cast<std::size_t>(parent.edges[o][0])] == end ? 0 : 1;
      const int c = half[2 * e + k], stands_for = half[2 * o + j];
      if (c >= 0 && stands_for >= 0) out[static_cast<std::size_t>(c)] = stands_for;
    }
  }
  return out;
}

Mesh merge_copies(Mesh mesh, const std::vector<int>& representative) {
  const auto n = static_cast<int>(representative.size());
  std::vector<int> index(static_cast<std::size_t>(n), -1);
  int kept = 0;
  for (int v = 0; v < n; ++v)
    if (representative[static_cast<std::size_t>(v)] == v) index[static_cast<std::size_t>(v)] = kept++;
  const auto to = [&](int v) {
    return index[static_cast<std::size_t>(representative[static_cast<std::size_t>(v)])];
  };
  Points vertices(kept, mesh.vertices.cols());
  for (int v = 0; v < n; ++v)
    if (index[static_cast<std::size_t>(v)] >= 0)
      vertices.row(index[static_cast<std::size_t>(v)]) = mesh.vertices.row(v);
  mesh.vertices = std::move(vertices);
  for (int& v : mesh.face_vertices) v = to(v);
  std::map<std::uint64_t, double> creases;
  for (const EdgeSharpness& c : mesh.tags.creases) creases[edge_key(to(c.a), to(c.b))] = c.sharpness;
  mesh.tags.creases.clear();
  for (const auto& [key, s] : creases)
    mesh.tags.creases.push_back({static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffU), s});
  std::map<int, double> corners;
  for (const VertexSharpness& c : mesh.tags.corners) corners[to(c.vertex)] = c.sharpness;
  mesh.tags.corners.clear();
  for (const auto& [v, s] : corners) mesh.tags.corners.push_back({v, s});
  return mesh;
}

}  // namespace cifs::subdivision::detail
