// SPDX-License-Identifier: MIT
// cifs — mesh adjacency: half-edges grouped by origin, twins found in the (short) list of the
// other end, then one walk around every vertex.
#include "cifs/topology.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/memory.hpp"

namespace cifs {
namespace {

std::string pair_text(int a, int b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

}  // namespace

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
  std::vector<std::pair<std::ptrdiff_t, std::size_t>> seen;  // per vertex: the last large face and its corner
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
    const int size = offsets[f + 1] - offsets[f];
    if (size < 3)
      throw InvalidInput(who + ": face " + std::to_string(f) + " has " + std::to_string(std::max(size, 0)) +
                         " vertices, a face needs at least 3");
    const auto face = corners.subspan(static_cast<std::size_t>(offsets[f]), static_cast<std::size_t>(size));
    // Small faces compare their corners pairwise; a large one marks them per vertex (pairwise, a
    // 60,000-gon took a second).
    const bool large = face.size() > 32;
    if (large && seen.empty()) seen.assign(static_cast<std::size_t>(vertex_count), {-1, 0});
    for (std::size_t i = 0; i < face.size(); ++i) {
      if (face[i] < 0 || face[i] >= vertex_count)
        throw InvalidInput(who + ": face " + std::to_string(f) + " corner " + std::to_string(i) +
                           " is vertex " + std::to_string(face[i]) + ", out of range (" +
                           std::to_string(vertex_count) + " vertices)");
      std::size_t j = i;
      if (large) {
        auto& [face_seen, corner] = seen[static_cast<std::size_t>(face[i])];
        if (face_seen == static_cast<std::ptrdiff_t>(f)) j = corner;
        face_seen = static_cast<std::ptrdiff_t>(f);
        corner = i;
      } else {
        j = static_cast<std::size_t>(
            std::find(face.begin(), face.begin() + static_cast<std::ptrdiff_t>(i), face[i]) - face.begin());
      }
      if (j < i)
        throw InvalidInput(who + ": face " + std::to_string(f) + " repeats vertex " +
                           std::to_string(face[i]) + " (corners " + std::to_string(j) + " and " +
                           std::to_string(i) + ")");
    }
  }
}

MeshTopology build_topology(std::span<const int> face_offsets, std::span<const int> face_vertices,
                            int vertex_count, std::string_view who) {
  return build_topology(std::vector<int>(face_offsets.begin(), face_offsets.end()),
                        std::vector<int>(face_vertices.begin(), face_vertices.end()), vertex_count, who);
}

namespace {

/// Which face half-edge h is in, and where that face starts and ends in face_vertices: looked up for
/// any polygons (Polygons) or computed when every face has K corners (Uniform<4>: the quad split's
/// children, whose lookups were a tenth of a Catmull–Clark one-shot's instructions; Uniform<3>: the
/// triangle split's).
struct Polygons {
  std::span<const int> offsets;
  std::vector<int> face;  // per half-edge
  explicit Polygons(std::span<const int> face_offsets) : offsets(face_offsets) {
    assign_huge(face, static_cast<std::size_t>(face_offsets.back()), 0);
    for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
      std::fill(face.begin() + offsets[f], face.begin() + offsets[f + 1], static_cast<int>(f));
  }
  int face_of(std::size_t h) const { return face[h]; }
  std::size_t first(std::size_t h) const {
    return static_cast<std::size_t>(offsets[static_cast<std::size_t>(face[h])]);
  }
  std::size_t last(std::size_t h) const {
    return static_cast<std::size_t>(offsets[static_cast<std::size_t>(face[h]) + 1]) - 1;
  }
};

template <std::size_t K>
struct Uniform {
  static int face_of(std::size_t h) { return static_cast<int>(h / K); }
  static std::size_t first(std::size_t h) { return h - h % K; }
  static std::size_t last(std::size_t h) { return h - h % K + K - 1; }
};

/// Edges and rings from faces whose half-edges are paired (`twin[h]`, −1 on the boundary): the
/// part of build_topology after the twins are found. Throws unless the faces around every vertex
/// form one fan.
template <class Faces>
void assemble(MeshTopology& t, std::span<const int> twin, const Faces& faces, const std::string& who) {
  const std::span<const int> face_vertices(t.face_vertices);
  const std::size_t H = face_vertices.size();
  const auto V = static_cast<std::size_t>(t.vertex_count);

  // Edges in order of first appearance: a half-edge starts one unless its twin came first (twin is
  // an involution). Counted, then written in place (push_back's checks cost a fifth of the pass).
  // (Unsigned: −1 is above every half-edge, and the loop vectorises; H < 2^31, check_faces.)
  std::size_t E = 0;
  for (std::size_t h = 0; h < H; ++h)
    E += static_cast<std::uint32_t>(twin[h]) > static_cast<std::uint32_t>(h);
  assign_huge(t.face_edges, H, -1);
  assign_huge(t.edges, E, std::array<int, 2>{});
  assign_huge(t.edge_faces, E, std::array<int, 2>{});
  int e = 0;
  for (std::size_t h = 0; h < H; ++h) {
    if (t.face_edges[h] >= 0) continue;
    t.face_edges[h] = e;
    const std::size_t next = h == faces.last(h) ? faces.first(h) : h + 1;
    t.edges[static_cast<std::size_t>(e)] = {face_vertices[h], face_vertices[next]};
    const int g = twin[h];
    t.edge_faces[static_cast<std::size_t>(e)] = {faces.face_of(h),
                                                 g >= 0 ? faces.face_of(static_cast<std::size_t>(g)) : -1};
    if (g >= 0) t.face_edges[static_cast<std::size_t>(g)] = e;
    ++e;
  }

  // Where every vertex's walk starts: its outgoing half-edge on the boundary (no face before it),
  // else its first outgoing half-edge; and how many half-edges leave it (its faces).
  std::vector<int> start(V, -1);
  assign_huge(t.boundary_vertex, V, char{0});
  assign_huge(t.vertex_offsets_faces, V + 1, 0);
  for (std::size_t h = 0; h < H; ++h) {
    const auto v = static_cast<std::size_t>(face_vertices[h]);
    ++t.vertex_offsets_faces[v + 1];
    if (twin[h] < 0) t.boundary_vertex[v] = 1;
    if (start[v] < 0 || (twin[h] < 0 && twin[static_cast<std::size_t>(start[v])] >= 0))
      start[v] = static_cast<int>(h);
  }
  // A boundary vertex has one edge more than faces.
  assign_huge(t.vertex_offsets_edges, V + 1, 0);
  for (std::size_t v = 0; v < V; ++v) {
    t.vertex_offsets_edges[v + 1] =
        t.vertex_offsets_edges[v] + t.vertex_offsets_faces[v + 1] + t.boundary_vertex[v];
    t.vertex_offsets_faces[v + 1] += t.vertex_offsets_faces[v];
  }
  assign_huge(t.vertex_edge_list, static_cast<std::size_t>(t.vertex_offsets_edges[V]), 0);
  assign_huge(t.vertex_face_list, H, 0);

  // Around every vertex, counter-clockwise: the half-edge leaving v in face k is followed (in the
  // rotation) by the twin of face k's half-edge entering v.
  for (std::size_t v = 0; v < V; ++v) {
    const int degree = t.vertex_offsets_faces[v + 1] - t.vertex_offsets_faces[v];
    auto edge = static_cast<std::size_t>(t.vertex_offsets_edges[v]);
    auto slot = static_cast<std::size_t>(t.vertex_offsets_faces[v]);
    int count = 0;
    for (int h = start[v]; h >= 0;) {
      if (count == degree) {  // more faces around v than leave it: not one fan (guards the arrays)
        ++count;
        break;
      }
      const auto u = static_cast<std::size_t>(h);
      t.vertex_edge_list[edge++] = t.face_edges[u];
      t.vertex_face_list[slot++] = faces.face_of(u);
      ++count;
      const std::size_t entering = u == faces.first(u) ? faces.last(u) : u - 1;
      h = twin[entering];
      if (h < 0)  // the ring ends on a boundary edge: it is the last edge
        t.vertex_edge_list[edge] = t.face_edges[entering];
      if (h == start[v]) break;
    }
    if (count != degree) {
      throw InvalidInput(who + ": vertex " + std::to_string(v) + " is not manifold: its " +
                         std::to_string(degree) + " faces do not form one fan around it (" +
                         std::to_string(count) + " are reached walking around it)");
    }
  }
}

/// assemble over the faces' shape: all triangles or all quads by arithmetic, else looked up.
void assemble(MeshTopology& t, std::span<const int> twin, const std::string& who) {
  const std::span<const int> offsets(t.face_offsets);
  const auto all = [&](int k) {
    for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
      if (offsets[f + 1] - offsets[f] != k) return false;
    return true;
  };
  if (all(4))
    assemble(t, twin, Uniform<4>{}, who);
  else if (all(3))
    assemble(t, twin, Uniform<3>{}, who);
  else
    assemble(t, twin, Polygons(offsets), who);
}

/// twin[h] for every half-edge h (−1 on the boundary), found by searching the half-edges leaving
/// its target; two faces running along one edge in the same direction are not an oriented manifold.
std::vector<int> find_twins(std::span<const int> face_offsets, std::span<const int> face_vertices,
                            std::size_t V, const std::string& who) {
  const std::size_t F = face_offsets.size() - 1, H = face_vertices.size();
  std::vector<int> target(H), face_of(H);
  for (std::size_t f = 0; f < F; ++f) {
    const int b = face_offsets[f], e = face_offsets[f + 1];
    for (int h = b; h < e; ++h) {
      face_of[static_cast<std::size_t>(h)] = static_cast<int>(f);
      target[static_cast<std::size_t>(h)] = face_vertices[static_cast<std::size_t>(h + 1 < e ? h + 1 : b)];
    }
  }
  // Half-edges grouped by origin and, within an origin, by target, each group in corner order: two
  // stable counting sorts, so that the time is linear in the mesh whatever the valences (a search
  // of the other half-edges at each vertex was quadratic in its valence: 41 s for one vertex of
  // valence 100,000).
  const auto counting_sort = [&](const std::vector<int>& order, const auto& key) {
    std::vector<int> offsets(V + 1, 0), sorted(H);
    for (std::size_t h = 0; h < H; ++h) ++offsets[static_cast<std::size_t>(key(h)) + 1];
    for (std::size_t v = 0; v < V; ++v) offsets[v + 1] += offsets[v];
    for (const int h : order)
      sorted[static_cast<std::size_t>(
          offsets[static_cast<std::size_t>(key(static_cast<std::size_t>(h)))]++)] = h;
    return std::pair{std::move(sorted), std::move(offsets)};
  };
  std::vector<int> corner_order(H);
  for (std::size_t h = 0; h < H; ++h) corner_order[h] = static_cast<int>(h);
  const auto by_target = counting_sort(corner_order, [&](std::size_t h) { return target[h]; }).first;
  const auto by_origin = counting_sort(by_target, [&](std::size_t h) { return face_vertices[h]; });
  // Named references, not a structured binding: clang 14 (the fuzz build) cannot capture those.
  const std::vector<int>& out_list = by_origin.first;
  const std::vector<int>& out_end = by_origin.second;
  // out_end[v] is now where v's half-edges end (the counting sort advanced each start to its end).
  const auto begin_of = [&](std::size_t v) { return v == 0 ? 0 : out_end[v - 1]; };
  const auto target_of = [&](int h) { return target[static_cast<std::size_t>(h)]; };

  std::vector<int> twin(H, -1);
  for (std::size_t v = 0; v < V; ++v) {
    const auto b = out_list.begin() + begin_of(v), e = out_list.begin() + out_end[v];
    // Two faces that run along v → w in the same direction: either a third face on the edge or
    // inconsistent orientation. Named as the search in corner order found them: the earliest
    // half-edge that repeats an earlier one's target, and the first of those.
    const std::vector<int>::const_iterator none = e;
    auto repeat = none;
    for (auto it = b; it + 1 < e; ++it)
      if (target_of(*it) == target_of(*(it + 1)) && (repeat == none || *(it + 1) < *repeat)) repeat = it + 1;
    if (repeat != none) {
      auto g = repeat;
      while (g > b && target_of(*(g - 1)) == target_of(*repeat)) --g;
      const int w = target_of(*repeat);
      throw InvalidInput(who + ": faces " + std::to_string(face_of[static_cast<std::size_t>(*g)]) + " and " +
                         std::to_string(face_of[static_cast<std::size_t>(*repeat)]) + " both use edge " +
                         pair_text(static_cast<int>(v), w) +
                         " in the same direction (inconsistent orientation, or an edge of more than two "
                         "faces: not an oriented manifold)");
    }
    for (auto it = b; it < e; ++it) {
      // The half-edge w → v, if any: a binary search among w's half-edges, sorted by target.
      const auto w = static_cast<std::size_t>(target_of(*it));
      const auto wb = out_list.begin() + begin_of(w), we = out_list.begin() + out_end[w];
      const auto found = std::lower_bound(wb, we, static_cast<int>(v),
                                          [&](int g, int value) { return target_of(g) < value; });
      if (found != we && target_of(*found) == static_cast<int>(v))
        twin[static_cast<std::size_t>(*it)] = *found;
    }
  }
  return twin;
}

}  // namespace

MeshTopology build_topology(std::vector<int> offsets, std::vector<int> corners, int vertex_count,
                            std::string_view who_view) {
  const std::string who(who_view);
  check_faces(offsets, corners, vertex_count, who);
  const std::vector<int> twin = find_twins(offsets, corners, static_cast<std::size_t>(vertex_count), who);
  MeshTopology t;
  t.vertex_count = vertex_count;
  t.face_offsets = std::move(offsets);
  t.face_vertices = std::move(corners);
  assemble(t, twin, who);
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

int components(const MeshTopology& t) {
  // Union–find over the vertices, joined along the edges; a component is a root that is in a face.
  std::vector<int> parent(static_cast<std::size_t>(t.vertex_count));
  for (int v = 0; v < t.vertex_count; ++v) parent[static_cast<std::size_t>(v)] = v;
  const auto find = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  for (const auto& [a, b] : t.edges) parent[static_cast<std::size_t>(find(a))] = find(b);
  int count = 0;
  for (int v = 0; v < t.vertex_count; ++v)
    if (find(v) == v && valence(t, static_cast<std::size_t>(v)) > 0) ++count;
  return count;
}

MeshStatistics mesh_statistics(const MeshTopology& t) {
  MeshStatistics s;
  for (std::size_t f = 0; f < face_count(t); ++f) ++s.faces_by_corners[face(t, f).size()];
  for (int v = 0; v < t.vertex_count; ++v) {
    const int n = valence(t, static_cast<std::size_t>(v));
    if (n == 0)
      ++s.isolated_vertices;
    else
      ++s.valences[n];
  }
  s.boundary_loops = boundary_loops(t).size();
  s.components = components(t);
  s.euler_characteristic = euler_characteristic(t);
  if (s.boundary_loops == 0)
    s.genus = (2LL * s.components - (s.euler_characteristic - s.isolated_vertices)) / 2;
  return s;
}

}  // namespace cifs
