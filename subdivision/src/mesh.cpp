// SPDX-License-Identifier: MIT
// cifs — subdivision surfaces: one step of each scheme as (child faces, weights), levels by repeating
// it, vertex data by replaying the weights (cifs/subdivision/mesh.hpp; rules: docs/subdivision-surfaces.md).
#include "cifs/subdivision/mesh.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <utility>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/memory.hpp"
#include "face_varying.hpp"
#include "local_mesh.hpp"
#include "non_manifold.hpp"

namespace cifs::subdivision {
namespace {

/// Where a step's rows go: kept as weights (the default), applied to `input` as they are made
/// (one-shot subdivision: no weights in memory), or dropped (topology only: the primal schemes do
/// not even make them).
struct RowSink {
  const Points* input = nullptr;
  bool drop = false;
};

struct Step {
  std::vector<int> face_offsets{0};
  std::vector<int> face_vertices;
  int vertex_count = 0;
  RowSink sink;
  Stencils stencils;  // the weights, when the sink keeps them
  Points output;      // the rows applied to sink.input
};

/// out = Σ_k weights[k] · in(columns[k]) (d columns): the kernel of apply.
inline void weighted_row(const double* in, Eigen::Index d, const int* columns, const double* weights,
                         int count, double* out) {
  if (d == 3) {  // positions: the common case, kept in registers
    double x = 0, y = 0, z = 0;
    for (int k = 0; k < count; ++k) {
      const double* p = in + 3 * static_cast<std::ptrdiff_t>(columns[k]);
      x += weights[k] * p[0];
      y += weights[k] * p[1];
      z += weights[k] * p[2];
    }
    out[0] = x;
    out[1] = y;
    out[2] = z;
    return;
  }
  std::fill(out, out + d, 0.0);
  for (int k = 0; k < count; ++k) {
    const double* p = in + d * static_cast<std::ptrdiff_t>(columns[k]);
    for (Eigen::Index c = 0; c < d; ++c) out[c] += weights[k] * p[c];
  }
}

/// Adds face f's centroid, weighted, as its corners.
template <class Writer>
[[gnu::always_inline]] inline void add_corners(const MeshTopology& t, std::size_t f, double weight,
                                               Writer& row) {
  const auto corners = face(t, f);
  const double w = weight / static_cast<double>(corners.size());
  for (const int c : corners) row.add(c, w);
}

/// Makes one stencil row at a time, kept as the step's weights (or dropped: topology only); a column
/// given twice is summed (face points expanded into corners meet the ring's own vertices), columns in
/// order of first appearance. A step's writers share one protocol: `auto&& row = out.row();`, then
/// row.add / row.add_face_point, then `out.finish(row)`, which starts the next row.
class RowWriter {
 public:
  static constexpr bool kApplies = false;
  RowWriter(Step& s, int old_vertex_count)
      : s_(s),
        slot_(static_cast<std::size_t>(old_vertex_count)),
        row_of_(static_cast<std::size_t>(old_vertex_count), -1) {}
  [[gnu::always_inline]] void add(int column, double weight) {
    // A column seen before in this row is found through row_of_/slot_ in O(1).
    const auto c = static_cast<std::size_t>(column);
    if (row_of_[c] == row_) {
      weights_[slot_[c]] += weight;
      return;
    }
    if (count_ == columns_.size()) [[unlikely]]
      grow();
    row_of_[c] = row_;
    slot_[c] = count_;
    columns_[count_] = column;
    weights_[count_++] = weight;
  }
  /// The centroid of parent face f, weighted: its corners (stencils are over the parent's vertices).
  void add_face_point(const MeshTopology& t, std::size_t f, double weight) {
    add_corners(t, f, weight, *this);
  }
  /// The row being made: this writer itself (its columns live here between rows).
  RowWriter& row() { return *this; }
  void finish(RowWriter& /*row*/) {
    if (!s_.sink.drop) {
      Stencils& out = s_.stencils;
      out.columns.insert(out.columns.end(), columns_.begin(),
                         columns_.begin() + static_cast<std::ptrdiff_t>(count_));
      out.weights.insert(out.weights.end(), weights_.begin(),
                         weights_.begin() + static_cast<std::ptrdiff_t>(count_));
      out.offsets.push_back(static_cast<int>(out.columns.size()));
    }
    count_ = 0;
    ++row_;
  }

 private:
  // Out of line: keeps add() small enough to inline.
  [[gnu::noinline]] void grow() {
    columns_.resize(2 * count_ + 16);
    weights_.resize(2 * count_ + 16);
  }

  Step& s_;
  std::vector<int> columns_;  // the row so far: count_ entries
  std::vector<double> weights_;
  std::size_t count_ = 0;
  std::vector<std::size_t> slot_;     // per old vertex: its place in columns_ ...
  std::vector<Eigen::Index> row_of_;  // ... valid when it was added in this row
  Eigen::Index row_ = 0;
};

/// Applies each row to the step's input as it is made (one-shot subdivision: no weights in memory,
/// no columns kept; a column given twice adds twice). Same rows as RowWriter's, summed in another
/// order: the same points to round-off. The input is 3-D positions (subdivide's check_mesh).
class PointWriter {
 public:
  static constexpr bool kApplies = true;
  /// One point being summed. A value on the step's stack, not a member: its sums stay in registers
  /// (members of a writer whose address the step's lambdas hold went through memory on every term:
  /// a sixth of a Catmull–Clark one-shot's instructions).
  struct Row {
    const double* in;
    const double* faces;  // make_face_points: the child face points
    double x = 0, y = 0, z = 0;
    [[gnu::always_inline]] void add(int column, double weight) {
      add_point(in + 3 * static_cast<std::ptrdiff_t>(column), weight);
    }
    /// The centroid of parent face f, weighted: the child face point when made first, else its corners.
    [[gnu::always_inline]] void add_face_point(const MeshTopology& t, std::size_t f, double weight) {
      if (faces)
        add_point(faces + 3 * static_cast<std::ptrdiff_t>(f), weight);
      else
        add_corners(t, f, weight, *this);
    }
    [[gnu::always_inline]] void add_point(const double* p, double weight) {
      x += weight * p[0];
      y += weight * p[1];
      z += weight * p[2];
    }
  };

  /// `s.vertex_count` is set: the output is sized from it.
  PointWriter(Step& s, int /*old_vertex_count*/) : in_(s.sink.input->data()) {
    s.output.resize(s.vertex_count, 3);
    advise_huge_pages(s.output.data(), static_cast<std::size_t>(s.output.size()) * sizeof(double));
    out_ = s.output.data();
    rows_ = s.vertex_count;
  }
  [[gnu::always_inline]] Row row() const { return {.in = in_, .faces = faces_}; }
  /// Writes the point and starts the next one in `r`.
  [[gnu::always_inline]] void finish(Row& r) {
    double* out = out_ + 3 * row_++;
    out[0] = r.x;
    out[1] = r.y;
    out[2] = r.z;
    r.x = r.y = r.z = 0;
  }
  /// Quad split: the child face points — the step's last rows, the centroids of the parent faces —
  /// made first, so that add_face_point weighs a face's centre as one point, not its corners
  /// (OpenSubdiv's order; a fifth of a creased Catmull–Clark one-shot's instructions, with RowWriter).
  void make_face_points(const MeshTopology& t) {
    const auto F = static_cast<Eigen::Index>(face_count(t));
    const Eigen::Index row_before = row_;
    row_ = rows_ - F;
    for (Eigen::Index f = 0; f < F; ++f) {
      Row r = row();
      add_corners(t, static_cast<std::size_t>(f), 1, r);
      finish(r);
    }
    row_ = row_before;
    faces_ = out_ + 3 * (rows_ - F);
  }

 private:
  const double* in_;
  double* out_ = nullptr;
  Eigen::Index rows_ = 0, row_ = 0;
  const double* faces_ = nullptr;  // make_face_points: the child face points
};

/// Reserves a step's weights from its counts (growing them by doubling costs copies and page faults
/// at these sizes).
void reserve_rows(Step& s, std::size_t rows, std::size_t entries) {
  if (s.sink.input || s.sink.drop) return;
  reserve_huge(s.stencils.offsets, rows + 1);
  reserve_huge(s.stencils.columns, entries);
  reserve_huge(s.stencils.weights, entries);
}

void add_face(Step& s, std::initializer_list<int> corners) {
  s.face_vertices.insert(s.face_vertices.end(), corners);
  s.face_offsets.push_back(static_cast<int>(s.face_vertices.size()));
}

std::span<const int> ring_edges(const MeshTopology& t, int v) {
  return vertex_edges(t, static_cast<std::size_t>(v));
}

bool on_boundary(const MeshTopology& t, int v) {
  return t.boundary_vertex[static_cast<std::size_t>(v)] != 0;
}

/// The two half-edges of every edge: {the one running along it (in edge_faces[e][0]), the one running
/// against it (−1 on the boundary)}; and which of the two half-edge h is.
int side_of(const MeshTopology& t, std::size_t h) {
  return t.face_vertices[h] == t.edges[static_cast<std::size_t>(t.face_edges[h])][0] ? 0 : 1;
}
std::vector<std::array<int, 2>> edge_sides(const MeshTopology& t) {
  std::vector<std::array<int, 2>> sides;
  assign_huge(sides, t.edges.size(), std::array<int, 2>{-1, -1});
  for (std::size_t h = 0; h < t.face_vertices.size(); ++h)
    sides[static_cast<std::size_t>(t.face_edges[h])][side_of(t, h)] = static_cast<int>(h);
  return sides;
}

/// Catmull–Clark's split (vertex points, then edge points, then face points): face f's corner i
/// becomes the quad (vertex i, edge i, face, edge i − 1), counter-clockwise; the quad of parent
/// half-edge h is child face h.
void split_polygons(const MeshTopology& t, Step& s) {
  // Face points come after the V + E vertex and edge points (s.vertex_count is set: the edge list
  // may be gone, see subdivide).
  const int V = t.vertex_count, E = s.vertex_count - V - static_cast<int>(face_count(t));
  const std::size_t H = t.face_vertices.size();
  // Written in place (add_face's inserts were half of the split's instructions).
  assign_huge(s.face_offsets, H + 1, 0);
  for (std::size_t h = 0; h <= H; ++h) s.face_offsets[h] = static_cast<int>(4 * h);
  assign_huge(s.face_vertices, 4 * H, 0);
  int* out = s.face_vertices.data();
  for (int f = 0; f < static_cast<int>(face_count(t)); ++f) {
    const auto corners = face(t, static_cast<std::size_t>(f));
    const auto edges = face_edges(t, static_cast<std::size_t>(f));
    int before = edges.back();  // edge i − 1
    for (std::size_t i = 0; i < corners.size(); ++i, out += 4) {
      out[0] = corners[i];
      out[1] = V + edges[i];
      out[2] = V + E + f;
      out[3] = V + before;
      before = edges[i];
    }
  }
}

/// Child half-edge x of a split (faces of K corners; y its twin, −1 on the boundary): the next edge e
/// unless its twin came first — edges in order of first appearance, as build_topology numbers them.
template <int K>
void number_half_edge(MeshTopology& t, int x, int y, int& e) {
  const auto ux = static_cast<std::size_t>(x);
  if (y >= 0 && y < x) {
    t.face_edges[ux] = t.face_edges[static_cast<std::size_t>(y)];
    return;
  }
  t.face_edges[ux] = e;
  const std::size_t first = ux - ux % K;
  t.edges[static_cast<std::size_t>(e)] = {t.face_vertices[ux], t.face_vertices[first + (ux - first + 1) % K]};
  t.edge_faces[static_cast<std::size_t>(e)] = {x / K, y < 0 ? -1 : y / K};
  ++e;
}

/// The ring offsets and boundary flags of a split's child (then its ring arrays, sized): vertex points
/// keep their parent vertex's ring; an edge point has `faces` faces inside, `boundary_faces` and one more
/// edge on the boundary; face points (with_face_points) one face and edge per corner of their face.
void size_split_rings(const MeshTopology& p, MeshTopology& t, int faces, int boundary_faces,
                      bool with_face_points) {
  const auto V = static_cast<std::size_t>(p.vertex_count), E = p.edges.size();
  const auto Vc = static_cast<std::size_t>(t.vertex_count);
  assign_huge(t.vertex_offsets_faces, Vc + 1, 0);
  assign_huge(t.vertex_offsets_edges, Vc + 1, 0);
  assign_huge(t.boundary_vertex, Vc, char{0});
  for (std::size_t v = 0; v < V; ++v) {
    t.vertex_offsets_faces[v + 1] = p.vertex_offsets_faces[v + 1];
    t.vertex_offsets_edges[v + 1] = p.vertex_offsets_edges[v + 1];
    t.boundary_vertex[v] = p.boundary_vertex[v];
  }
  for (std::size_t x = 0; x < E; ++x) {
    const bool open = is_boundary_edge(p, x);
    const std::size_t v = V + x;
    t.vertex_offsets_faces[v + 1] = t.vertex_offsets_faces[v] + (open ? boundary_faces : faces);
    t.vertex_offsets_edges[v + 1] = t.vertex_offsets_edges[v] + (open ? boundary_faces + 1 : faces);
    t.boundary_vertex[v] = open ? 1 : 0;
  }
  if (with_face_points)
    for (std::size_t f = 0; f < face_count(p); ++f) {
      const std::size_t v = V + E + f;
      const int k = p.face_offsets[f + 1] - p.face_offsets[f];
      t.vertex_offsets_faces[v + 1] = t.vertex_offsets_faces[v] + k;
      t.vertex_offsets_edges[v + 1] = t.vertex_offsets_edges[v] + k;
    }
  assign_huge(t.vertex_face_list, static_cast<std::size_t>(t.vertex_offsets_faces[Vc]), 0);
  assign_huge(t.vertex_edge_list, static_cast<std::size_t>(t.vertex_offsets_edges[Vc]), 0);
}

/// The adjacency of split_polygons' child faces, by formula from the parent's: what build_topology
/// finds from the child faces by search, to the entry (edges in order of first appearance,
/// rings from the same start; test_mesh.cpp), without its passes over the child half-edges (a
/// quarter of a Catmull–Clark one-shot's instructions). The quad of parent half-edge h (corner i of
/// face f) is child face h: (vertex i, edge point i, face point, edge point i − 1), child half-edges
/// 4h … 4h + 3.
MeshTopology quad_split_topology(const MeshTopology& p, Step& s) {
  const int V = p.vertex_count, E = static_cast<int>(p.edges.size()), F = static_cast<int>(face_count(p));
  const std::size_t H = p.face_vertices.size();
  const std::vector<std::array<int, 2>> sides = edge_sides(p);
  MeshTopology t;
  t.vertex_count = s.vertex_count;
  t.face_offsets = std::move(s.face_offsets);
  t.face_vertices = std::move(s.face_vertices);

  // Edges: each parent edge in two, an edge from each edge point i to the face point.
  assign_huge(t.face_edges, 4 * H, -1);
  assign_huge(t.edges, 2 * static_cast<std::size_t>(E) + H, std::array<int, 2>{});
  assign_huge(t.edge_faces, t.edges.size(), std::array<int, 2>{});
  int* const fe = t.face_edges.data();
  int e = 0;
  for (int f = 0; f < F; ++f) {
    const int b = p.face_offsets[static_cast<std::size_t>(f)],
              end = p.face_offsets[static_cast<std::size_t>(f) + 1];
    for (int h = b; h < end; ++h) {
      const int next = h + 1 < end ? h + 1 : b, prev = h > b ? h - 1 : end - 1;
      const auto across = [&](int x) {
        const auto ux = static_cast<std::size_t>(x);
        const auto ex = static_cast<std::size_t>(p.face_edges[ux]);
        const int side = side_of(p, ux);
        return std::pair{sides[ex][1 - side], p.edge_faces[ex][1 - side]};  // half-edge, its face
      };
      // Vertex i → edge point: across the edge, the quad of the corner after the twin ends with
      // edge point → vertex i. Edge point i − 1 → vertex i: the quad of the previous edge's twin.
      const auto [a, g] = across(h);
      const int a_next = a < 0 ? -1
                               : (a + 1 < p.face_offsets[static_cast<std::size_t>(g) + 1]
                                      ? a + 1
                                      : p.face_offsets[static_cast<std::size_t>(g)]);
      const int before = across(prev).first;
      const std::array<int, 4> twin{a < 0 ? -1 : 4 * a_next + 3, 4 * next + 2, 4 * prev + 1,
                                    before < 0 ? -1 : 4 * before};
      for (int j = 0; j < 4; ++j) number_half_edge<4>(t, 4 * h + j, twin[static_cast<std::size_t>(j)], e);
    }
  }

  // Rings, counter-clockwise, each from where build_topology's walk starts (the outgoing boundary
  // half-edge, else the first outgoing one). A vertex point's is its parent vertex's, face by face;
  // an edge point has 4 faces (2 on the boundary); a face point one per corner of its face.
  size_split_rings(p, t, 4, 2, true);
  int* const faces = t.vertex_face_list.data();
  int* const ring = t.vertex_edge_list.data();
  const auto next_in_face = [&](int h, int f) {
    return h + 1 < p.face_offsets[static_cast<std::size_t>(f) + 1]
               ? h + 1
               : p.face_offsets[static_cast<std::size_t>(f)];
  };
  for (int v = 0; v < V; ++v) {  // vertex points: face k of v's ring is child face h_k
    const auto uv = static_cast<std::size_t>(v);
    const auto pe = vertex_edges(p, uv);
    const std::size_t n = vertex_faces(p, uv).size();
    int* fo = faces + t.vertex_offsets_faces[uv];
    int* eo = ring + t.vertex_offsets_edges[uv];
    std::ptrdiff_t h = -1;
    for (std::size_t k = 0; k < n; ++k) {
      const auto x = static_cast<std::size_t>(pe[k]);  // leaves v in face k
      h = sides[x][p.edges[x][0] == v ? 0 : 1];
      fo[k] = static_cast<int>(h);
      eo[k] = fe[4 * h];
    }
    if (pe.size() > n) eo[n] = fe[4 * h + 3];  // the boundary edge entering v, in the last face
  }
  for (int x = 0; x < E; ++x) {  // edge points
    const auto ux = static_cast<std::size_t>(x);
    const auto v = static_cast<std::size_t>(V) + ux;
    int* fo = faces + t.vertex_offsets_faces[v];
    int* eo = ring + t.vertex_offsets_edges[v];
    const int s0 = sides[ux][0], n0 = next_in_face(s0, p.edge_faces[ux][0]);
    if (is_boundary_edge(p, ux)) {  // from the boundary half towards edges[x][1]
      fo[0] = n0;
      fo[1] = s0;
      eo[0] = fe[4 * n0 + 3];
      eo[1] = fe[4 * s0 + 1];
      eo[2] = fe[4 * static_cast<std::ptrdiff_t>(s0)];
      continue;
    }
    const int s1 = sides[ux][1], n1 = next_in_face(s1, p.edge_faces[ux][1]);
    // Around the edge point: child faces s0, n1, s1, n0, leaving it by half-edges 4s0 + 1, 4n1 + 3,
    // 4s1 + 1, 4n0 + 3; from the lowest of these.
    const std::array<int, 4> around{s0, n1, s1, n0};
    const std::array<int, 4> leaving{4 * s0 + 1, 4 * n1 + 3, 4 * s1 + 1, 4 * n0 + 3};
    const auto first =
        static_cast<std::size_t>(std::min_element(leaving.begin(), leaving.end()) - leaving.begin());
    for (std::size_t k = 0; k < 4; ++k) {
      fo[k] = around[(first + k) % 4];
      eo[k] = fe[leaving[(first + k) % 4]];
    }
  }
  for (int f = 0; f < F; ++f) {  // face points: child faces in the order of the corners
    const auto v = static_cast<std::size_t>(V) + static_cast<std::size_t>(E) + static_cast<std::size_t>(f);
    int* fo = faces + t.vertex_offsets_faces[v];
    int* eo = ring + t.vertex_offsets_edges[v];
    for (int h = p.face_offsets[static_cast<std::size_t>(f)], k = 0;
         h < p.face_offsets[static_cast<std::size_t>(f) + 1]; ++h, ++k) {
      fo[k] = h;
      eo[k] = fe[4 * h + 2];
    }
  }
  return t;
}

/// The corner of triangle f that is not on edge e: the corners' sum less the edge's ends.
[[gnu::always_inline]] inline int opposite_corner(const MeshTopology& t, int f, int e) {
  const int* c = t.face_vertices.data() + t.face_offsets[static_cast<std::size_t>(f)];
  const auto [a, b] = t.edges[static_cast<std::size_t>(e)];
  return static_cast<int>(std::int64_t{c[0]} + c[1] + c[2] - a - b);
}

/// Loop and Butterfly split every triangle in four at its edge points (vertex points first):
/// triangle f becomes children 4f … 4f + 3, the corner triangles then the middle one.
void split_triangles(const MeshTopology& t, Step& s) {
  const int V = t.vertex_count;
  const std::size_t F = face_count(t);
  // Written in place: no vector inserts (four per triangle were 29 % of Loop's topology-only work).
  assign_huge(s.face_offsets, 4 * F + 1, 0);
  for (std::size_t f = 0; f <= 4 * F; ++f) s.face_offsets[f] = static_cast<int>(3 * f);
  assign_huge(s.face_vertices, 12 * F, 0);
  int* out = s.face_vertices.data();
  for (std::size_t f = 0; f < F; ++f, out += 12) {
    const int* c = t.face_vertices.data() + 3 * f;
    const int* e = t.face_edges.data() + 3 * f;  // e[i] joins c[i] → c[i + 1]
    const int ab = V + e[0], bc = V + e[1], ca = V + e[2];
    const std::array<int, 12> children{c[0], ab, ca, ab, c[1], bc, ca, bc, c[2], ab, bc, ca};
    std::copy(children.begin(), children.end(), out);
  }
}

/// The adjacency of split_triangles' child faces by formula from the parent's, as quad_split_topology.
/// Triangle f's children 4f … 4f + 2 are its corners' (c_i, e_i, e_{i−1}) with c_i as corner i, 4f + 3
/// the middle one (e_0, e_1, e_2) (e_i the edge point of edge i, c_i → c_{i+1}); child half-edge
/// 12f + 3k + m runs from corner m of child k to its next corner.
MeshTopology triangle_split_topology(const MeshTopology& p, Step& s) {
  const int V = p.vertex_count, E = static_cast<int>(p.edges.size()), F = static_cast<int>(face_count(p));
  const std::vector<std::array<int, 2>> sides = edge_sides(p);
  MeshTopology t;
  t.vertex_count = s.vertex_count;
  t.face_offsets = std::move(s.face_offsets);
  t.face_vertices = std::move(s.face_vertices);
  // Across parent edge i of f: the corner j of triangle g where the twin starts (g < 0: boundary).
  const auto across = [&](int f, int i) {
    const auto h = 3 * static_cast<std::size_t>(f) + static_cast<std::size_t>(i);
    const auto x = static_cast<std::size_t>(p.face_edges[h]);
    const int a = sides[x][1 - side_of(p, h)];
    return a < 0 ? std::pair{-1, 0} : std::pair{a / 3, a % 3};
  };

  // Edges: each parent edge in two, three inside each triangle (the middle child's sides).
  assign_huge(t.face_edges, 12 * static_cast<std::size_t>(F), -1);
  assign_huge(t.edges, 2 * static_cast<std::size_t>(E) + 3 * static_cast<std::size_t>(F),
              std::array<int, 2>{});
  assign_huge(t.edge_faces, t.edges.size(), std::array<int, 2>{});
  int* const fe = t.face_edges.data();
  int e = 0;
  for (int f = 0; f < F; ++f) {
    std::array<int, 12> twin{};
    // Corner i → edge point i is 12f + 4i; edge point i → corner i + 1 is 12f + 3((i + 1) mod 3) + i.
    // Across parent edge i (corner j of triangle g) they pair with g's.
    for (int i = 0; i < 3; ++i) {
      const auto [g, j] = across(f, i);
      const auto ui = static_cast<std::size_t>(i);
      twin[4 * ui] = g < 0 ? -1 : 12 * g + 3 * ((j + 1) % 3) + j;
      twin[3 * ((ui + 1) % 3) + ui] = g < 0 ? -1 : 12 * g + 4 * j;
    }
    for (const auto& [x, y] :
         {std::pair{1, 11}, std::pair{5, 9}, std::pair{6, 10}}) {  // the middle one's sides
      twin[static_cast<std::size_t>(x)] = 12 * f + y;
      twin[static_cast<std::size_t>(y)] = 12 * f + x;
    }
    for (int k = 0; k < 12; ++k) number_half_edge<3>(t, 12 * f + k, twin[static_cast<std::size_t>(k)], e);
  }

  // Rings (counter-clockwise, from build_topology's starts): a vertex point's is its parent vertex's, child
  // by child; an edge point has 6 faces (3 on the boundary).
  size_split_rings(p, t, 6, 3, false);
  int* const faces = t.vertex_face_list.data();
  int* const ring = t.vertex_edge_list.data();
  for (int v = 0; v < V; ++v) {  // vertex points: corner i of parent face f becomes child 4f + i
    const auto uv = static_cast<std::size_t>(v);
    const auto pe = vertex_edges(p, uv);
    const std::size_t n = vertex_faces(p, uv).size();
    int* fo = faces + t.vertex_offsets_faces[uv];
    int* eo = ring + t.vertex_offsets_edges[uv];
    int f = 0, i = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const auto x = static_cast<std::size_t>(pe[k]);  // leaves v in face k
      const int h = sides[x][p.edges[x][0] == v ? 0 : 1];
      f = h / 3;
      i = h % 3;
      fo[k] = 4 * f + i;
      eo[k] = fe[12 * f + 4 * i];
    }
    if (pe.size() > n) eo[n] = fe[12 * f + 3 * i + (i + 2) % 3];  // edge point i − 1 → c_i: the boundary
  }
  // Around edge point i of triangle f, counter-clockwise: child i + 1 (leaving by e_i → c_{i+1}), the
  // middle child (e_i → e_{i+1}), child i (e_i → e_{i−1}); then the same in the triangle across.
  const auto fan = [](int f, int i, int* fo, int* leaving) {
    const int next = (i + 1) % 3;
    fo[0] = 4 * f + next;
    leaving[0] = 12 * f + 3 * next + i;  // e_i is corner i of child i + 1
    fo[1] = 4 * f + 3;
    leaving[1] = 12 * f + 9 + i;
    fo[2] = 4 * f + i;
    leaving[2] = 12 * f + 3 * i + next;  // e_i is corner i + 1 of child i
  };
  for (int x = 0; x < E; ++x) {
    const auto ux = static_cast<std::size_t>(x);
    const auto v = static_cast<std::size_t>(V) + ux;
    int* fo = faces + t.vertex_offsets_faces[v];
    int* eo = ring + t.vertex_offsets_edges[v];
    const int s0 = sides[ux][0];
    std::array<int, 6> around{}, leaving{};
    fan(s0 / 3, s0 % 3, around.data(), leaving.data());
    if (is_boundary_edge(p, ux)) {  // from the boundary half towards edges[x][1]; c_i → e_i last
      for (std::size_t k = 0; k < 3; ++k) {
        fo[k] = around[k];
        eo[k] = fe[leaving[k]];
      }
      eo[3] = fe[12 * (s0 / 3) + 4 * (s0 % 3)];
      continue;
    }
    const int s1 = sides[ux][1];
    fan(s1 / 3, s1 % 3, around.data() + 3, leaving.data() + 3);
    const auto first =
        static_cast<std::size_t>(std::min_element(leaving.begin(), leaving.end()) - leaving.begin());
    for (std::size_t k = 0; k < 6; ++k) {
      fo[k] = around[(first + k) % 6];
      eo[k] = fe[leaving[(first + k) % 6]];
    }
  }
  return t;
}

/// Loop's β(n) = (1/n)(5/8 − (3/8 + ¼cos(2π/n))²); the seed's α_n = (40 − (3 + 2cos(2π/n))²)/64 is
/// n·β(n) written over 64.
double loop_beta(int n) {
  const double c = 0.375 + 0.25 * std::cos(2 * std::numbers::pi / n);
  return (0.625 - c * c) / n;
}

/// Whether a level's features are all smooth.
bool smooth_level(const LevelFeatures& L) {
  return L.edge_sharpness.empty() && L.vertex_sharpness.empty();
}

/// What Biermann–Levin–Zorin's rules (RuleSet::blz) change at a crease or corner vertex c, seen from
/// one of its smooth edges (the edge point's one-sided rule) or one of its faces (Catmull–Clark's
/// face point): the shift δ from the far end to c, and on a concave corner's sector the flatness s
/// towards c + ½x₁(e0 − c) + ½x₂(ek − c).
struct BlzSide {
  int centre = -1;  // −1: c is not a crease or corner vertex
  double shift = 0, flatness = 0, x1 = 0, x2 = 0;
  int e0 = -1, ek = -1;
};

/// The BlzSide of every half of every edge (2e + (c == edges[e][1])) and of every face corner (the
/// face's half-edges, Catmull–Clark), from the sectors of each crease or corner vertex: the faces
/// between consecutive sharp edges (a boundary's edges are sharp). A corner with fewer than two sharp
/// edges has no sectors and keeps the standard rules.
struct BlzSides {
  std::vector<BlzSide> edges, corners;
};
BlzSides blz_sides(MeshScheme scheme, const MeshTopology& t, const LevelFeatures& L, const MeshTags& tags) {
  BlzSides out;
  out.edges.resize(2 * t.edges.size());
  if (scheme == MeshScheme::catmull_clark) out.corners.resize(t.face_vertices.size());
  std::vector<char> concave(static_cast<std::size_t>(t.vertex_count), 0);
  for (const int v : tags.concave) concave[static_cast<std::size_t>(v)] = 1;
  std::vector<int> sharp;
  for (int v = 0; v < t.vertex_count; ++v) {
    const auto uv = static_cast<std::size_t>(v);
    const auto ring = ring_edges(t, v);
    const auto faces = vertex_faces(t, uv);
    const int n = static_cast<int>(ring.size());
    sharp.clear();
    for (int j = 0; j < n; ++j)
      if (edge_sharpness(L, static_cast<std::size_t>(ring[static_cast<std::size_t>(j)])) > 0)
        sharp.push_back(j);
    const VertexRule rule = vertex_rule(vertex_sharpness(L, uv), static_cast<int>(sharp.size()));
    if (concave[uv] && (rule != VertexRule::corner || sharp.size() < 2))
      throw InvalidInput(std::string(scheme_name(scheme)) + ": vertex " + std::to_string(v) +
                         " is tagged concave but is not a corner with two or more sharp edges here " +
                         "(a concave corner must stay one: infinitely sharp)");
    if ((rule != VertexRule::crease && rule != VertexRule::corner) || sharp.size() < 2) continue;
    const bool open = on_boundary(t, v);
    const double theta = blz_sector_angle(rule, concave[uv] != 0);
    const double flatness = concave[uv] ? kBlzConcaveFlatness : 0.0;
    const auto ring_at = [&](int j) { return ring[static_cast<std::size_t>(j % n)]; };
    for (std::size_t p = 0; p + (open ? 1 : 0) < sharp.size(); ++p) {
      const int a = sharp[p], b = p + 1 < sharp.size() ? sharp[p + 1] : sharp.front() + n;
      const int k = b - a;
      const double theta_k = theta / k;
      const double shift = blz_edge_shift(scheme, std::cos(theta_k));
      const int e0 = other_vertex(t, static_cast<std::size_t>(ring_at(a)), v);
      const int ek = other_vertex(t, static_cast<std::size_t>(ring_at(b)), v);
      // The subdominant eigenvectors at ring position i (edge i of the sector; its faces: i, i + 1).
      const auto x1 = [&](int i) { return std::sin((k - i) * theta_k) / std::sin(theta); };
      const auto x2 = [&](int i) { return std::sin(i * theta_k) / std::sin(theta); };
      for (int i = 1; i < k; ++i) {
        const int e = ring_at(a + i);
        const auto ue = static_cast<std::size_t>(e);
        out.edges[2 * ue + (t.edges[ue][0] == v ? 0 : 1)] = {
            .centre = v, .shift = shift, .flatness = flatness, .x1 = x1(i), .x2 = x2(i), .e0 = e0, .ek = ek};
      }
      if (scheme != MeshScheme::catmull_clark || flatness == 0) continue;
      for (int i = 0; i < k; ++i) {
        const auto f = static_cast<std::size_t>(faces[static_cast<std::size_t>((a + i) % n)]);
        const auto corners = face(t, f);
        const auto h =
            static_cast<std::size_t>(t.face_offsets[f]) +
            static_cast<std::size_t>(std::find(corners.begin(), corners.end(), v) - corners.begin());
        out.corners[h] = {.centre = v,
                          .shift = 0,
                          .flatness = flatness,
                          .x1 = x1(i) + x1(i + 1),
                          .x2 = x2(i) + x2(i + 1),
                          .e0 = e0,
                          .ek = ek};
      }
    }
  }
  return out;
}

/// Adds weight · (the flatness part of a BlzSide): s(c + ½x₁(e0 − c) + ½x₂(ek − c)).
template <class Writer>
void add_flat(const BlzSide& b, double weight, Writer& row) {
  const double w = weight * b.flatness;
  row.add(b.centre, w * (1 - 0.5 * b.x1 - 0.5 * b.x2));
  row.add(b.e0, w * 0.5 * b.x1);
  row.add(b.ek, w * 0.5 * b.x2);
}

/// Catmull–Clark, Loop and bilinear (the primal schemes with OpenSubdiv's rules): a vertex point per
/// vertex, an edge point per edge and, for the quad split, a face point per face, each from the
/// rules' masks (cifs/subdivision/rules.hpp). `halves[2e + k]` receives the sharpness after the step
/// of edge e's half at its end k (edges[e][k]); left empty on a smooth level.
template <class Writer>
Step primal_step(MeshScheme scheme, const MeshTopology& t, const LevelFeatures& L, const MeshTags& tags,
                 RowSink sink, std::vector<double>& halves) {
  const bool quads = traits(scheme).split == Split::quads;
  const int V = t.vertex_count, E = static_cast<int>(t.edges.size()), F = static_cast<int>(face_count(t));
  Step s;
  s.sink = sink;
  s.vertex_count = V + E + (quads ? F : 0);  // vertex points, edge points, face points
  const std::size_t H = t.face_vertices.size();
  // Vertex rows: itself, n neighbours, the corners of n faces; edge rows: both faces' corners.
  reserve_rows(
      s, static_cast<std::size_t>(s.vertex_count),
      quads ? static_cast<std::size_t>(V) + 5 * H : static_cast<std::size_t>(V) + 6 * t.edges.size());
  Writer out(s, s.sink.drop ? 0 : t.vertex_count);  // dropped rows are not made at all
  const bool smooth = smooth_level(L);
  halves.assign(smooth ? 0 : 2 * t.edges.size(), 0.0);
  // Vertices with a sharp edge or a sharpness of their own: flagged from the edges once (a search of
  // every vertex's ring cost more than the creased vertices' rules).
  std::vector<char> sharp_vertex;
  if (!smooth) {
    sharp_vertex.assign(static_cast<std::size_t>(V), 0);
    for (std::size_t e = 0; e < L.edge_sharpness.size(); ++e)
      if (L.edge_sharpness[e] > 0)
        for (const int x : t.edges[e]) sharp_vertex[static_cast<std::size_t>(x)] = 1;
    for (std::size_t v = 0; v < L.vertex_sharpness.size(); ++v)
      if (L.vertex_sharpness[v] > 0) sharp_vertex[v] = 1;
  }
  std::vector<double> pe, ce;  // sharpness of a vertex's edges before and after the step
  // The smooth rule depends on the face count alone: computed once per count.
  std::vector<std::optional<VertexMask>> smooth_masks;
  const auto smooth_mask = [&](const VertexNeighbourhood& n) -> const VertexMask& {
    const auto k = static_cast<std::size_t>(n.faces);
    if (k >= smooth_masks.size()) smooth_masks.resize(k + 1);
    if (!smooth_masks[k]) smooth_masks[k] = vertex_mask(scheme, tags.crease_method, n);
    return *smooth_masks[k];
  };
  const BlzSides blz = tags.rules == RuleSet::blz && !smooth && scheme != MeshScheme::bilinear && !s.sink.drop
                           ? blz_sides(scheme, t, L, tags)
                           : BlzSides{};
  if (s.sink.drop && smooth) return s;  // topology only on a smooth level: nothing to compute
  if constexpr (Writer::kApplies)
    if (quads) out.make_face_points(t);  // BLZ's flattened ones are made again below
  for (int v = 0; v < V; ++v) {
    auto&& row = out.row();
    const auto ring = ring_edges(t, v);
    const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
    VertexMask m;  // a vertex without faces stays
    if (!ring.empty()) {
      VertexNeighbourhood n;
      n.faces = static_cast<int>(faces.size());  // smooth level: no sharpness
      const bool sharp_here = !smooth && sharp_vertex[static_cast<std::size_t>(v)] != 0;
      if (sharp_here) {  // else the smooth rule, as on a smooth level (same bits), and halves stay 0
        pe.clear();
        for (const int e : ring) pe.push_back(edge_sharpness(L, static_cast<std::size_t>(e)));
        ce.resize(pe.size());
        child_edge_sharpness(tags.crease_method, pe, ce);
        for (std::size_t i = 0; i < ring.size(); ++i) {
          const auto e = static_cast<std::size_t>(ring[i]);
          halves[2 * e + (t.edges[e][0] == v ? 0 : 1)] = ce[i];
        }
        n.edges = pe;
        n.child_edges = ce;
        n.sharpness = vertex_sharpness(L, static_cast<std::size_t>(v));
        n.child_sharpness = decremented_sharpness(n.sharpness);
      }
      if (s.sink.drop) continue;
      m = sharp_here ? vertex_mask(scheme, tags.crease_method, n) : smooth_mask(n);
    }
    if (s.sink.drop) continue;
    if (m.face != 0)
      for (const int f : faces) row.add_face_point(t, static_cast<std::size_t>(f), m.face);
    if (m.edge != 0)
      for (const int e : ring) row.add(other_vertex(t, static_cast<std::size_t>(e), v), m.edge);
    if (m.crease_ends[0] >= 0)
      for (const int k : m.crease_ends)
        row.add(other_vertex(t, static_cast<std::size_t>(ring[static_cast<std::size_t>(k)]), v), m.crease);
    row.add(v, m.vertex);
    out.finish(row);
  }
  if (s.sink.drop) return s;  // topology only: the halves are all the child tags need
  const bool triangle_sizes = scheme == MeshScheme::catmull_clark && tags.triangles == TriangleRule::smooth;
  EdgeNeighbourhood last_edge{.face_sizes = {-1, -1}};  // matches no edge
  EdgeMask last_edge_mask;
  for (int e = 0; e < E; ++e) {
    auto&& row = out.row();
    const auto ue = static_cast<std::size_t>(e);
    const int a = t.edges[ue][0], b = t.edges[ue][1];  // not bindings: the lambdas below capture them
    const int f0 = t.edge_faces[ue][0], f1 = t.edge_faces[ue][1];
    // The masks read whether a face is there and, under the smooth triangle rule alone, whether it
    // is a triangle: other sizes are not looked up (4 stands for any).
    const auto size = [&](int f) {
      return f < 0             ? 0
             : !triangle_sizes ? 4
                               : t.face_offsets[static_cast<std::size_t>(f) + 1] -
                                     t.face_offsets[static_cast<std::size_t>(f)];
    };
    const EdgeNeighbourhood n{
        .sharpness = edge_sharpness(L, ue),
        .child_sharpness = {smooth ? 0 : halves[2 * ue], smooth ? 0 : halves[2 * ue + 1]},
        .face_sizes = {size(f0), size(f1)}};
    if (!(n == last_edge)) {  // neighbouring edges mostly share theirs: the mask is kept
      last_edge = n;
      last_edge_mask = edge_mask(scheme, tags.triangles, n);
    }
    const EdgeMask& m = last_edge_mask;
    const auto add_face = [&](int f, double w) __attribute__((always_inline)) {
      if (quads)
        row.add_face_point(t, static_cast<std::size_t>(f), w);
      else
        row.add(opposite_corner(t, f, e), w);
    };
    const auto standard = [&](double w) __attribute__((always_inline)) {
      if (m.face != 0) {
        add_face(f0, w * m.face);
        if (f1 >= 0) add_face(f1, w * m.face);
      }
      row.add(a, w * m.end);
      row.add(b, w * m.end);
    };
    // BLZ: the mean of the one-sided rules of the ends that are crease or corner vertices (as
    // Subdivide 2.0 does; after one step no smooth edge joins two such vertices).
    const BlzSide* sides[2] = {nullptr, nullptr};
    int tagged = 0;
    if (!blz.edges.empty() && edge_sharpness(L, ue) == 0)
      for (int k = 0; k < 2; ++k)
        if (blz.edges[2 * ue + static_cast<std::size_t>(k)].centre >= 0)
          sides[tagged++] = &blz.edges[2 * ue + static_cast<std::size_t>(k)];
    if (tagged == 0) {
      standard(1);
    } else {
      for (int k = 0; k < tagged; ++k) {
        const BlzSide& side = *sides[k];
        const double w = 1.0 / tagged, keep = w * (1 - side.flatness);
        standard(keep);
        row.add(side.centre, keep * side.shift);
        row.add(side.centre == a ? b : a, -keep * side.shift);
        if (side.flatness > 0) add_flat(side, w, row);
      }
    }
    out.finish(row);
  }
  if (quads && !(Writer::kApplies && blz.corners.empty()))
    for (int f = 0; f < F; ++f) {
      auto&& row = out.row();
      // BLZ: at concave corners, the mean of the face point flattened towards each.
      int flattened = 0;
      if (!blz.corners.empty())
        for (int h = t.face_offsets[static_cast<std::size_t>(f)];
             h < t.face_offsets[static_cast<std::size_t>(f) + 1]; ++h)
          flattened += blz.corners[static_cast<std::size_t>(h)].centre >= 0 ? 1 : 0;
      if (flattened == 0) {
        row.add_face_point(t, static_cast<std::size_t>(f), 1);
      } else {
        for (int h = t.face_offsets[static_cast<std::size_t>(f)];
             h < t.face_offsets[static_cast<std::size_t>(f) + 1]; ++h) {
          const BlzSide& side = blz.corners[static_cast<std::size_t>(h)];
          if (side.centre < 0) continue;
          row.add_face_point(t, static_cast<std::size_t>(f), (1 - side.flatness) / flattened);
          add_flat(side, 1.0 / flattened, row);
        }
      }
      out.finish(row);
    }
  return s;
}

/// The edge of face f joining x and y.
int edge_between(const MeshTopology& t, int f, int x, int y) {
  for (const int e : face_edges(t, static_cast<std::size_t>(f))) {
    const auto [a, b] = t.edges[static_cast<std::size_t>(e)];
    if ((a == x && b == y) || (a == y && b == x)) return e;
  }
  return -1;  // unreachable: callers pass two corners of f
}

/// The other boundary neighbour of boundary vertex v, seen from its boundary edge e.
int boundary_neighbour(const MeshTopology& t, int v, int e) {
  const auto ring = ring_edges(t, v);
  return other_vertex(t, static_cast<std::size_t>(ring.front() == e ? ring.back() : ring.front()), v);
}

/// The size of a ring (Butterfly) or face (Doo–Sabin) from which a one-shot step sums its dense stencils
/// (every point of the ring or face weighs on every other: k² terms, 46 s at valence 50,000) through
/// their low-rank form: O(k). Below it the direct sums, in the kept rows' order, cost no more.
constexpr int kRankFormFrom = 16;

/// Zorin–Schröder–Sweldens' stencil for an edge point next to a vertex of valence k ≠ 6: ¾ on the
/// centre and s_j on ring vertex j (j = 0 the edge's other end). The seed writes s_j without the
/// 1/k and mixes n and k; k = 3: 5/12, −1/12, −1/12; k = 4: 3/8, 0, −1/8, 0;
/// k ≥ 5: s_j = (1/k)(¼ + cos(2πj/k) + ½cos(4πj/k)).
double butterfly_ring_weight(int k, int j) {
  if (k == 3) return j == 0 ? 5.0 / 12 : -1.0 / 12;
  if (k == 4) return j == 0 ? 0.375 : (j == 2 ? -0.125 : 0.0);
  return (0.25 + std::cos(2 * std::numbers::pi * j / k) + 0.5 * std::cos(4 * std::numbers::pi * j / k)) / k;
}

/// The rings of the interior vertices of valence k ≠ 6 (ZSS's extraordinary ends) with their weights
/// s_j, and each of their edges' place in its ring, by edge: an edge point reads its places in order
/// instead of searching a ring (k searches of a ring of k edges, and k² cosines, were quadratic in the
/// valence: 46 s at valence 50,000). A one-shot step also keeps five sums per ring of kRankFormFrom or
/// more (`moments`): s_j is of rank 5 in (edge, ring vertex), so each edge point costs O(1), not O(k).
struct ButterflyRings {
  struct Ring {
    int centre, size;
    std::size_t offset;  // vertices[offset … offset + size): counter-clockwise, as ring_edges
  };
  struct Place {
    int edge, ring, index;  // edge is ring_edges(centre)[index]
  };
  std::vector<Ring> rings;
  std::vector<int> vertices;
  std::vector<double> weights;  // s_j of each ring, j = 0 … size − 1
  std::vector<Place> places;    // sorted by edge: two at most per edge
  /// Per ring of kRankFormFrom or more: Σ d_m, Σ cos(mθ) d_m, Σ sin(mθ) d_m, Σ cos(2mθ) d_m, Σ sin(2mθ) d_m,
  /// where θ = 2π/k and d_m = p_m − centre (relative: the sums cancel less), 3 coordinates each.
  std::vector<std::array<double, 15>> moments;
};

/// An end whose edges take ZSS's ring stencil: interior, valence ≠ 6.
bool butterfly_extraordinary(const MeshTopology& t, int v) {
  return !on_boundary(t, v) && valence(t, static_cast<std::size_t>(v)) != 6;
}

/// The rings of `centres` (butterfly_extraordinary vertices).
ButterflyRings butterfly_rings(const MeshTopology& t, std::span<const int> centres) {
  ButterflyRings r;
  for (const int v : centres) {
    const auto ring = ring_edges(t, v);
    const int k = static_cast<int>(ring.size()), ring_id = static_cast<int>(r.rings.size());
    r.rings.push_back({.centre = v, .size = k, .offset = r.vertices.size()});
    for (int m = 0; m < k; ++m) {
      const int e = ring[static_cast<std::size_t>(m)];
      r.vertices.push_back(other_vertex(t, static_cast<std::size_t>(e), v));
      r.weights.push_back(butterfly_ring_weight(k, m));
      r.places.push_back({.edge = e, .ring = ring_id, .index = m});
    }
  }
  std::sort(r.places.begin(), r.places.end(), [](const auto& x, const auto& y) {
    return x.edge != y.edge ? x.edge < y.edge : x.ring < y.ring;
  });
  return r;
}

/// The rings of every extraordinary vertex of the level.
ButterflyRings butterfly_rings(const MeshTopology& t) {
  std::vector<int> centres;
  for (int v = 0; v < t.vertex_count; ++v)
    if (butterfly_extraordinary(t, v)) centres.push_back(v);
  return butterfly_rings(t, centres);
}

/// Fills r.moments from the level's 3-D positions (one-shot steps).
void add_moments(ButterflyRings& r, const double* in) {
  r.moments.resize(r.rings.size());
  for (std::size_t g = 0; g < r.rings.size(); ++g) {
    const auto& ring = r.rings[g];
    auto& mu = r.moments[g];
    mu.fill(0.0);
    if (ring.size < kRankFormFrom) continue;
    const double* c = in + 3 * static_cast<std::ptrdiff_t>(ring.centre);
    for (int m = 0; m < ring.size; ++m) {
      const double* p =
          in + 3 * static_cast<std::ptrdiff_t>(r.vertices[ring.offset + static_cast<std::size_t>(m)]);
      const double a = 2 * std::numbers::pi * m / ring.size;
      const std::array<double, 5> f{1.0, std::cos(a), std::sin(a), std::cos(2 * a), std::sin(2 * a)};
      for (std::size_t q = 0; q < 5; ++q)
        for (std::size_t x = 0; x < 3; ++x) mu[3 * q + x] += f[q] * (p[x] - c[x]);
    }
  }
}

/// The ring stencil of the edge at `place`, weighted by `scale` (½ when both ends are extraordinary).
/// With moments (a one-shot step, rings of kRankFormFrom or more): cos((m − i)θ) = cos mθ cos iθ + sin mθ sin
/// iθ turns Σ_m s_{m−i} d_m into the ring's five sums, so the point is centre + (1/k)(¼Σd + cos iθ·C₁ + sin
/// iθ·S₁ + ½(cos 2iθ·C₂ + sin 2iθ·S₂)) (¾ + Σ s_j = 1).
template <class Row>
void add_ring_stencil(const ButterflyRings& r, const ButterflyRings::Place& place, double scale, Row& row) {
  const auto& ring = r.rings[static_cast<std::size_t>(place.ring)];
  const int k = ring.size, i = place.index;
  if constexpr (requires(Row & x, const double* p) { x.add_point(p, 1.0); }) {
    if (!r.moments.empty() && k >= kRankFormFrom) {
      const auto& mu = r.moments[static_cast<std::size_t>(place.ring)];
      const double a = 2 * std::numbers::pi * i / k;
      const std::array<double, 5> f{0.25, std::cos(a), std::sin(a), 0.5 * std::cos(2 * a),
                                    0.5 * std::sin(2 * a)};
      std::array<double, 3> sum{};
      for (std::size_t q = 0; q < 5; ++q)
        for (std::size_t x = 0; x < 3; ++x) sum[x] += f[q] * mu[3 * q + x];
      row.add(ring.centre, scale);
      row.add_point(sum.data(), scale / k);
      return;
    }
  }
  row.add(ring.centre, 0.75 * scale);
  for (int j = 0; j < k; ++j) {
    const std::size_t m = ring.offset + static_cast<std::size_t>((i + j) % k);
    row.add(r.vertices[m], r.weights[ring.offset + static_cast<std::size_t>(j)] * scale);
  }
}

/// The 10-point stencil of edge a–b (w = 1/16): ends ½, the opposite corners o of the two faces
/// ⅛, and −1/16 on each wing — the far corner of the triangle across edge (x, o), x ∈ {a, b}. A
/// wing missing at the boundary is the reflection x + o − (the other end), as OpenMesh does.
template <class Row>
void butterfly_regular(const MeshTopology& t, int e, Row& row) {
  const auto [a, b] = t.edges[static_cast<std::size_t>(e)];
  row.add(a, 0.5);
  row.add(b, 0.5);
  for (const int f : t.edge_faces[static_cast<std::size_t>(e)]) {
    const int o = opposite_corner(t, f, e);
    row.add(o, 0.125);
    for (const auto& [x, z] : {std::pair{a, b}, std::pair{b, a}}) {
      const int side = edge_between(t, f, x, o);
      const auto [g0, g1] = t.edge_faces[static_cast<std::size_t>(side)];
      const int g = g0 == f ? g1 : g0;
      if (g >= 0) {
        row.add(opposite_corner(t, g, side), -0.0625);
      } else {
        row.add(x, -0.0625);
        row.add(o, -0.0625);
        row.add(z, 0.0625);
      }
    }
  }
}

/// The edge point of edge e: the 4-point rule (−1, 9, 9, −1)/16 along boundary edges; inside, the
/// 10-point stencil unless an end is an interior vertex of valence ≠ 6 (its place in `rings`:
/// `places`, none, one or two), whose ring stencil is then used (the mean of the two when both are).
/// Boundary ends count as regular (OpenMesh's rule; ZSS's boundary tables are not implemented). The one
/// rule of the step and of the limit's first step (detail::butterfly_edge_stencil).
template <class Row>
void butterfly_edge_point(const MeshTopology& t, int e, const ButterflyRings& rings,
                          std::span<const ButterflyRings::Place> places, Row& row) {
  const auto [a, b] = t.edges[static_cast<std::size_t>(e)];
  if (is_boundary_edge(t, static_cast<std::size_t>(e))) {
    row.add(a, 0.5625);
    row.add(b, 0.5625);
    row.add(boundary_neighbour(t, a, e), -0.0625);
    row.add(boundary_neighbour(t, b, e), -0.0625);
  } else if (places.empty()) {
    butterfly_regular(t, e, row);
  } else {
    const double scale = places.size() == 2 ? 0.5 : 1;
    for (const auto& place : places) add_ring_stencil(rings, place, scale, row);
  }
}

/// Old vertices stay (interpolating); an edge point per edge (butterfly_edge_point).
template <class Writer>
Step butterfly_step(const MeshTopology& t, RowSink sink) {
  const int V = t.vertex_count, E = static_cast<int>(t.edges.size());
  Step s;
  s.sink = sink;
  s.vertex_count = V + E;
  ButterflyRings rings = butterfly_rings(t);
  if constexpr (Writer::kApplies) add_moments(rings, sink.input->data());
  Writer out(s, t.vertex_count);
  auto&& row = out.row();
  for (int v = 0; v < V; ++v) {
    row.add(v, 1);
    out.finish(row);
  }
  auto place = rings.places.begin();
  for (int e = 0; e < E; ++e) {
    const auto first = place;
    while (place != rings.places.end() && place->edge == e) ++place;
    butterfly_edge_point(t, e, rings, {first, place}, row);
    out.finish(row);
  }
  return s;
}

/// Kobbelt's √3: a vertex at every face centroid, interior vertices relaxed by
/// α_n = (4 − 2cos(2π/n))/9 (v' = (1 − α)v + (α/n)Σ neighbours), interior edges flipped to join
/// the new vertices on their two sides. Two steps are a triadic refinement. Boundary (Kobbelt
/// 2000 §5, as CGAL and OpenMesh): on even steps (0, 2, …) boundary vertices stay and boundary
/// edges are kept; on odd steps each boundary edge p_a → p_b (p_− before it, p_+ after it) is
/// trisected by (p_− + 16p_a + 10p_b)/27 and (10p_a + 16p_b + p_+)/27 in place of its face's
/// centroid, and boundary vertices move to (4p_− + 19p + 4p_+)/27. After an even step every
/// boundary face has exactly one boundary edge, which the odd step relies on.
template <class Writer>
Step sqrt3_step(const MeshTopology& t, bool refine_boundary, RowSink sink) {
  const int V = t.vertex_count, F = static_cast<int>(face_count(t));
  Step s;
  s.sink = sink;
  s.vertex_count = V + F;  // and one more point per boundary face when it is trisected
  if (refine_boundary)
    for (std::size_t e = 0; e < t.edges.size(); ++e) s.vertex_count += is_boundary_edge(t, e) ? 1 : 0;
  Writer out(s, t.vertex_count);
  auto&& row = out.row();
  for (int v = 0; v < V; ++v) {
    const auto ring = ring_edges(t, v);
    if (ring.empty() || (on_boundary(t, v) && !refine_boundary)) {
      row.add(v, 1);
    } else if (on_boundary(t, v)) {
      row.add(v, 19.0 / 27);
      row.add(other_vertex(t, static_cast<std::size_t>(ring.front()), v), 4.0 / 27);
      row.add(other_vertex(t, static_cast<std::size_t>(ring.back()), v), 4.0 / 27);
    } else {
      const double n = static_cast<double>(ring.size()),
                   alpha = (4 - 2 * std::cos(2 * std::numbers::pi / n)) / 9;
      row.add(v, 1 - alpha);
      for (const int e : ring) row.add(other_vertex(t, static_cast<std::size_t>(e), v), alpha / n);
    }
    out.finish(row);
  }
  // apex[corner slot of edge i in face f]: the new vertex that edge i's flip joins on f's side.
  std::vector<int> apex(t.face_vertices.size());
  int next = V;
  for (int f = 0; f < F; ++f) {
    const auto corners = face(t, static_cast<std::size_t>(f));
    const auto edges = face_edges(t, static_cast<std::size_t>(f));
    const int base = t.face_offsets[static_cast<std::size_t>(f)];
    std::size_t split = 3;  // the boundary edge's slot when this face is trisected
    if (refine_boundary)
      for (std::size_t i = 0; i < 3; ++i)
        if (is_boundary_edge(t, static_cast<std::size_t>(edges[i]))) split = i;
    if (split == 3) {
      row.add_face_point(t, static_cast<std::size_t>(f), 1);
      out.finish(row);
      for (std::size_t i = 0; i < 3; ++i) apex[static_cast<std::size_t>(base) + i] = next;
      ++next;
      continue;
    }
    const int e = edges[split], a = corners[split], b = corners[(split + 1) % 3];
    const int before = boundary_neighbour(t, a, e), after = boundary_neighbour(t, b, e);
    row.add(before, 1.0 / 27);
    row.add(a, 16.0 / 27);
    row.add(b, 10.0 / 27);
    out.finish(row);
    row.add(a, 10.0 / 27);
    row.add(b, 16.0 / 27);
    row.add(after, 1.0 / 27);
    out.finish(row);
    // Edge b → o meets the point near b, edge o → a the point near a.
    apex[static_cast<std::size_t>(base) + (split + 1) % 3] = next + 1;
    apex[static_cast<std::size_t>(base) + (split + 2) % 3] = next;
    apex[static_cast<std::size_t>(base) + split] = -1;
    add_face(s, {next, next + 1, corners[(split + 2) % 3]});
    next += 2;
  }
  const auto apex_of = [&](int f, int e) {
    const auto edges = face_edges(t, static_cast<std::size_t>(f));
    const auto i = std::find(edges.begin(), edges.end(), e) - edges.begin();
    return apex[static_cast<std::size_t>(t.face_offsets[static_cast<std::size_t>(f)] + i)];
  };
  // Edge a → b between faces f0 (left) and f1 (right) becomes the triangles (a, c1, c0), (b, c0, c1);
  // a boundary edge kept by an even step becomes (a, b, c0).
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    const auto [a, b] = t.edges[e];
    const auto [f0, f1] = t.edge_faces[e];
    const int c0 = apex_of(f0, static_cast<int>(e));
    if (f1 >= 0) {
      const int c1 = apex_of(f1, static_cast<int>(e));
      add_face(s, {a, c1, c0});
      add_face(s, {b, c0, c1});
    } else if (!refine_boundary) {
      add_face(s, {a, b, c0});
    }
  }
  return s;
}

/// A Doo–Sabin face of k ≥ kRankFormFrom corners in a one-shot step. α_m = ¼δ_m + (3 + 2cos mθ)/(4k),
/// θ = 2π/k, and cos((j − i)θ) = cos jθ cos iθ + sin jθ sin iθ: with d_j = p_j − p_0 (relative: the
/// sums cancel less), corner point i = ¾p_0 + ¼p_i + (3Σd + 2(cos iθ·Σcos jθ d_j + sin iθ·Σsin jθ d_j))/(4k).
template <class Writer, class Row>
void doo_sabin_large_face(std::span<const int> corners, Writer& out, Row& row) {
  const int k = static_cast<int>(corners.size());
  const auto point = [&](int i) {
    return row.in + 3 * static_cast<std::ptrdiff_t>(corners[static_cast<std::size_t>(i)]);
  };
  std::array<double, 9> mu{};  // Σd, Σcos jθ d_j, Σsin jθ d_j
  for (int j = 0; j < k; ++j) {
    const double a = 2 * std::numbers::pi * j / k;
    const std::array<double, 3> f{1.0, std::cos(a), std::sin(a)};
    for (std::size_t q = 0; q < 3; ++q)
      for (std::size_t x = 0; x < 3; ++x) mu[3 * q + x] += f[q] * (point(j)[x] - point(0)[x]);
  }
  for (int i = 0; i < k; ++i) {
    const double a = 2 * std::numbers::pi * i / k;
    const std::array<double, 3> f{3.0, 2 * std::cos(a), 2 * std::sin(a)};
    std::array<double, 3> sum{};
    for (std::size_t q = 0; q < 3; ++q)
      for (std::size_t x = 0; x < 3; ++x) sum[x] += f[q] * mu[3 * q + x];
    row.add(corners[0], 0.75);
    row.add(corners[static_cast<std::size_t>(i)], 0.25);
    row.add_point(sum.data(), 0.25 / k);
    out.finish(row);
  }
}

/// Doo–Sabin: a new point for every corner of every face, Σ_j α_{j−i} v_j with
/// α_0 = ¼ + 5/(4k), α_m = (3 + 2cos(2πm/k))/(4k); then a face per face (its corner points), per
/// interior edge (a quad) and per interior vertex (its corner points around it). Boundary edges
/// and vertices make no face, so the surface shrinks away from the boundary (CGAL's rule:
/// corner points are the same at the boundary).
template <class Writer>
Step doo_sabin_step(const MeshTopology& t, RowSink sink) {
  Step s;
  s.sink = sink;
  s.vertex_count = static_cast<int>(t.face_vertices.size());  // corner (f, i) → face_offsets[f] + i
  Writer out(s, t.vertex_count);
  auto&& row = out.row();
  std::vector<double> alpha;  // α_m of the last face size
  for (std::size_t f = 0; f < face_count(t); ++f) {
    const auto corners = face(t, f);
    const int k = static_cast<int>(corners.size());
    if (alpha.size() != corners.size()) {
      alpha.resize(corners.size());
      for (int m = 0; m < k; ++m)
        alpha[static_cast<std::size_t>(m)] =
            (m == 0 ? 0.25 : 0.0) + (3 + 2 * std::cos(2 * std::numbers::pi * m / k)) / (4 * k);
    }
    if constexpr (Writer::kApplies) {
      if (k >= kRankFormFrom) {  // α is ¼δ plus rank 3: each corner point in O(1), not O(k)
        doo_sabin_large_face(corners, out, row);
        continue;
      }
    }
    for (int i = 0; i < k; ++i) {
      for (int m = 0; m < k; ++m)
        row.add(corners[static_cast<std::size_t>((i + m) % k)], alpha[static_cast<std::size_t>(m)]);
      out.finish(row);
    }
  }
  // Child corner points by half-edge: corner h of the parent is child point h.
  const std::vector<std::array<int, 2>> sides = edge_sides(t);
  const auto next = [&](int h, int f) {
    return h + 1 == t.face_offsets[static_cast<std::size_t>(f) + 1]
               ? t.face_offsets[static_cast<std::size_t>(f)]
               : h + 1;
  };
  for (std::size_t f = 0; f < face_count(t); ++f) {  // F-faces
    const int begin = t.face_offsets[f], end = t.face_offsets[f + 1];
    for (int c = begin; c < end; ++c) s.face_vertices.push_back(c);
    s.face_offsets.push_back(static_cast<int>(s.face_vertices.size()));
  }
  for (std::size_t e = 0; e < t.edges.size(); ++e) {  // E-faces: f0 on the left of a → b
    const auto [f0, f1] = t.edge_faces[e];
    if (f1 < 0) continue;
    const int along = sides[e][0], against = sides[e][1];  // a → b in f0, b → a in f1
    add_face(s, {next(against, f1), against, next(along, f0), along});
  }
  for (int v = 0; v < t.vertex_count; ++v) {  // V-faces, counter-clockwise around v
    if (vertex_faces(t, static_cast<std::size_t>(v)).empty() || on_boundary(t, v)) continue;
    // Face j around v lies after edge j, v's outgoing edge in it: its corner at v is that half-edge.
    for (const int e : ring_edges(t, v))
      s.face_vertices.push_back(
          sides[static_cast<std::size_t>(e)][t.edges[static_cast<std::size_t>(e)][0] == v ? 0 : 1]);
    s.face_offsets.push_back(static_cast<int>(s.face_vertices.size()));
  }
  return s;
}

/// The adjacency of a step's child faces (taken over from it): by formula from the parent's for the
/// quad and the triangle split, searched otherwise.
MeshTopology child_topology(MeshScheme scheme, const MeshTopology& parent, Step& s, const std::string& who) {
  switch (traits(scheme).split) {
    case Split::quads:
      return quad_split_topology(parent, s);
    case Split::triangles:
      return triangle_split_topology(parent, s);
    case Split::dual:
    case Split::sqrt3:
      break;
  }
  return build_topology(std::move(s.face_offsets), std::move(s.face_vertices), s.vertex_count, who);
}

/// Whether a scheme's child faces are a split of the parent's faces alone, made after the rows
/// (the quad split, the triangle split).
bool splits_faces(MeshScheme scheme) {
  const Split split = traits(scheme).split;
  return split == Split::quads || split == Split::triangles;
}

/// Makes the child faces of a scheme that splits_faces.
void split_faces(MeshScheme scheme, const MeshTopology& t, Step& s) {
  if (traits(scheme).split == Split::quads)
    split_polygons(t, s);
  else
    split_triangles(t, s);
}

/// The rows of step `level` of a scheme, made by Writer.
template <class Writer>
Step rows_step(MeshScheme scheme, const MeshTopology& t, const LevelFeatures& L, const MeshTags& tags,
               int level, std::vector<double>& halves, RowSink sink) {
  switch (scheme) {
    case MeshScheme::catmull_clark:
    case MeshScheme::loop:
    case MeshScheme::bilinear:
      return primal_step<Writer>(scheme, t, L, tags, sink, halves);
    case MeshScheme::butterfly:
      return butterfly_step<Writer>(t, sink);
    case MeshScheme::doo_sabin:
      return doo_sabin_step<Writer>(t, sink);
    case MeshScheme::sqrt3:
      return sqrt3_step<Writer>(t, level % 2 == 1, sink);
  }
  return {};
}

/// Step `level` (0 for the first) of a refinement: its rows — applied to sink.input when given
/// (PointWriter), else kept or dropped (RowWriter) — and, unless `faces` is false for a scheme that
/// splits_faces (then split_faces makes them), its child faces. `halves` as primal_step.
Step step(MeshScheme scheme, const MeshTopology& t, const LevelFeatures& L, const MeshTags& tags, int level,
          std::vector<double>& halves, RowSink sink = {}, bool faces = true) {
  Step s = sink.input ? rows_step<PointWriter>(scheme, t, L, tags, level, halves, sink)
                      : rows_step<RowWriter>(scheme, t, L, tags, level, halves, sink);
  if (faces && splits_faces(scheme)) split_faces(scheme, t, s);
  return s;
}

/// Counts of a mesh, as doubles (they are estimates before the work).
struct Counts {
  double vertices, edges, faces, corners;
};

/// The counts after one step, by formula (closed meshes where the scheme requires them).
Counts next_counts(MeshScheme scheme, const Counts& c) {
  switch (traits(scheme).split) {
    case Split::quads:
      return {c.vertices + c.edges + c.faces, 2 * c.edges + c.corners, c.corners, 4 * c.corners};
    case Split::triangles:
      return {c.vertices + c.edges, 2 * c.edges + 3 * c.faces, 4 * c.faces, 12 * c.faces};
    case Split::dual:
      return {c.corners, 2 * c.corners, c.faces + c.edges + c.vertices, c.corners + 6 * c.edges};
    case Split::sqrt3:
      return {c.vertices + c.faces, c.edges + 3 * c.faces, 3 * c.faces, 9 * c.faces};
  }
  return c;
}

void check_scheme_input(const MeshTopology& t, const Mesh& mesh, MeshScheme scheme) {
  const std::string who(scheme_name(scheme));
  if (triangles_only(scheme))
    for (std::size_t f = 0; f < face_count(t); ++f)
      if (face(t, f).size() != 3)
        throw InvalidInput(
            who + ": face " + std::to_string(f) + " has " + std::to_string(face(t, f).size()) +
            " corners; this scheme runs on triangles (triangulate first, or use catmull-clark)");
  // Doo–Sabin makes a face of n corners for each interior vertex of valence n: at valence 2 a face of two
  // corners, which neither the next level's check nor a mesh file takes (it was refused as "face 21 has
  // 2 vertices" of a level the user never saw, or by the writer).
  if (scheme == MeshScheme::doo_sabin)
    for (int v = 0; v < t.vertex_count; ++v)
      if (t.boundary_vertex[static_cast<std::size_t>(v)] == 0 && valence(t, static_cast<std::size_t>(v)) == 2)
        throw InvalidInput(who + ": vertex " + std::to_string(v) +
                           " is inside the mesh on two faces only: its vertex face would have 2 corners "
                           "(remove the vertex, joining its two edges, or use catmull-clark)");
  if (mesh.tags.rules == RuleSet::blz && scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
    throw InvalidInput(who + ": the rule set 'blz' is built for catmull-clark and loop only");
  if (!mesh.tags.concave.empty() && mesh.tags.rules != RuleSet::blz)
    throw InvalidInput(who + ": concave corners are a part of the rule set 'blz'; ask for it (--rules blz)");
  for (const int v : mesh.tags.concave)
    if (v < 0 || v >= t.vertex_count)
      throw InvalidInput(who + ": concave corner " + std::to_string(v) + " is not a vertex (the mesh has " +
                         std::to_string(t.vertex_count) + ")");
  if (!traits(scheme).sharpness)
    if (const std::string tag = first_feature(mesh.tags); !tag.empty())
      throw InvalidInput(who + ": the mesh has " + tag +
                         "; this scheme has no rules for creases, corners, holes " +
                         "or the boundary rule 'none' (catmull-clark, loop and bilinear have)");
}

/// The features of a level from its tags, as OpenSubdiv's factory prepares its base level: boundary
/// edges infinitely sharp; under `edge_and_corner` a boundary vertex with one face an infinitely sharp
/// corner; under `none` (schemes with rules beyond the face itself) the faces around a boundary vertex
/// with a boundary edge not tagged infinitely sharp become holes.
LevelFeatures level_features(const MeshTopology& t, const MeshTags& tags, MeshScheme scheme,
                             const std::string& who) {
  LevelFeatures L;
  const bool boundary =
      std::any_of(t.boundary_vertex.begin(), t.boundary_vertex.end(), [](char b) { return b != 0; });
  if (tags.creases.empty() && tags.corners.empty() && tags.holes.empty() && !boundary)
    return L;  // a plain closed level: smooth rules everywhere, nothing to allocate
  const std::size_t V = static_cast<std::size_t>(t.vertex_count), E = t.edges.size(), F = face_count(t);
  std::vector<double> es, vs;
  std::vector<char> holes;
  assign_huge(es, E, 0.0);
  assign_huge(vs, V, 0.0);
  assign_huge(holes, F, char{0});
  if (!tags.creases.empty()) {
    for (std::size_t i = 0; i < tags.creases.size(); ++i) {
      const EdgeSharpness& c = tags.creases[i];
      const int e = find_edge(t, c.a, c.b);
      if (e < 0)
        throw InvalidInput(who + ": crease " + std::to_string(i) + " joins vertices " + std::to_string(c.a) +
                           " and " + std::to_string(c.b) + ", which are not an edge of the mesh");
      es[static_cast<std::size_t>(e)] = held_sharpness(c.sharpness);
    }
  }
  for (const VertexSharpness& c : tags.corners)
    vs[static_cast<std::size_t>(c.vertex)] = held_sharpness(c.sharpness);
  for (const int f : tags.holes) holes[static_cast<std::size_t>(f)] = 1;
  if (boundary && tags.boundary == BoundaryRule::none && scheme != MeshScheme::bilinear)
    for (std::size_t v = 0; v < V; ++v) {
      if (!t.boundary_vertex[v]) continue;
      const auto ring = vertex_edges(t, v);
      if (std::any_of(ring.begin(), ring.end(), [&](int e) {
            return is_boundary_edge(t, static_cast<std::size_t>(e)) &&
                   es[static_cast<std::size_t>(e)] < kInfiniteSharpness;
          }))
        for (const int f : vertex_faces(t, v)) holes[static_cast<std::size_t>(f)] = 1;
    }
  if (boundary)
    for (std::size_t e = 0; e < E; ++e)
      if (is_boundary_edge(t, e)) es[e] = kInfiniteSharpness;
  if (boundary && tags.boundary == BoundaryRule::edge_and_corner)
    for (std::size_t v = 0; v < V; ++v)
      if (vertex_faces(t, v).size() == 1 && vertex_edges(t, v).size() == 2) vs[v] = kInfiniteSharpness;
  const auto any = [](const auto& x) {
    return std::any_of(x.begin(), x.end(), [](auto y) { return y > 0; });
  };
  if (any(es) || any(vs)) {
    L.edge_sharpness = std::move(es);
    L.vertex_sharpness = std::move(vs);
  }
  if (any(holes)) L.holes = std::move(holes);
  return L;
}

/// The tags after a step of a primal scheme (vertex points first, then edge points): each sharp
/// edge's two halves with their sharpness after the step, corners decremented, the children of holes
/// (a quad per parent corner, four triangles per triangle). Boundary edges are listed only under
/// the boundary rule `none`, where level_features must not make new holes of them.
MeshTags child_tags(MeshScheme scheme, const MeshTopology& t, const LevelFeatures& L,
                    const std::vector<double>& halves, const MeshTags& tags) {
  MeshTags out = tags;
  out.creases.clear();
  out.corners.clear();
  out.holes.clear();
  const int V = t.vertex_count;
  if (!halves.empty())
    for (std::size_t e = 0; e < t.edges.size(); ++e) {
      // A smooth edge's halves are smooth (the one load most edges need).
      if (edge_sharpness(L, e) <= 0 || (halves[2 * e] <= 0 && halves[2 * e + 1] <= 0) ||
          (is_boundary_edge(t, e) && tags.boundary != BoundaryRule::none))
        continue;
      const int mid = V + static_cast<int>(e);
      if (halves[2 * e] > 0) out.creases.push_back({t.edges[e][0], mid, halves[2 * e]});
      if (halves[2 * e + 1] > 0) out.creases.push_back({mid, t.edges[e][1], halves[2 * e + 1]});
    }
  for (std::size_t v = 0; v < L.vertex_sharpness.size(); ++v) {
    if (L.vertex_sharpness[v] <= 0) continue;  // most vertices
    const double s = decremented_sharpness(L.vertex_sharpness[v]);
    if (s > 0 && vertex_faces(t, v).size() > 0 &&
        !(tags.boundary == BoundaryRule::edge_and_corner && vertex_faces(t, v).size() == 1 &&
          vertex_edges(t, v).size() == 2))  // made sharp again by the boundary rule
      out.corners.push_back({static_cast<int>(v), s});
  }
  if (!L.holes.empty()) {
    const bool quads = traits(scheme).split == Split::quads;
    for (std::size_t f = 0; f < face_count(t); ++f) {
      if (!L.holes[f]) continue;
      if (quads)
        for (int h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h) out.holes.push_back(h);
      else
        for (int k = 0; k < 4; ++k) out.holes.push_back(4 * static_cast<int>(f) + k);
    }
  }
  return out;
}

}  // namespace

namespace {

/// The input's topology, checked for the scheme, after refusing (before any work) a refinement
/// whose memory would pass options.max_bytes: ~40 bytes a corner and ~190 a vertex for a level's
/// topology and weights, summed over the levels when they are all kept (`keep_levels`).
MeshTopology checked_input(const Mesh& mesh, MeshScheme scheme, int levels, const MeshOptions& options,
                           bool keep_levels) {
  const std::string who(scheme_name(scheme));
  if (levels < 0) throw InvalidInput(who + ": " + std::to_string(levels) + " levels; expected 0 or more");
  check_mesh(mesh, who);
  MeshTopology t0 = build_topology(mesh, who);
  check_scheme_input(t0, mesh, scheme);
  Counts c{static_cast<double>(t0.vertex_count), static_cast<double>(t0.edges.size()),
           static_cast<double>(face_count(t0)), static_cast<double>(t0.face_vertices.size())};
  // Dense stencils take k² weights: Butterfly's at a vertex of valence k ≠ 6 (k ring stencils of k
  // entries), Doo–Sabin's at a k-gon (and, from the second level, at a vertex of valence k: its face);
  // k keeps at every level. Catmull–Clark's at a k-gon, on the first level only (its k edge points and
  // k vertex points each weigh the k corners of its face point; then every face is a quad). A few large
  // ones can outweigh the mesh; one-shot steps keep none.
  double dense_entries = 0, dense_first = 0;
  if (keep_levels && options.weights) {
    const auto dense = [](double k) { return k >= kRankFormFrom ? k * k : 0.0; };
    if (scheme == MeshScheme::catmull_clark)
      for (std::size_t f = 0; f < face_count(t0); ++f)
        dense_first += 2 * dense(static_cast<double>(face(t0, f).size()));
    if (scheme == MeshScheme::butterfly)
      for (int v = 0; v < t0.vertex_count; ++v)
        if (butterfly_extraordinary(t0, v)) dense_entries += dense(valence(t0, static_cast<std::size_t>(v)));
    if (scheme == MeshScheme::doo_sabin) {
      for (std::size_t f = 0; f < face_count(t0); ++f)
        dense_entries += dense(static_cast<double>(face(t0, f).size()));
      for (int v = 0; v < t0.vertex_count; ++v)
        if (!on_boundary(t0, v)) dense_entries += dense(valence(t0, static_cast<std::size_t>(v)));
    }
  }
  double bytes = 0, dense_bytes = 0;
  for (int level = 0; level < levels; ++level) {
    c = next_counts(scheme, c);
    const double level_dense = 12 * (dense_entries + (level == 0 ? dense_first : 0));
    const double level_bytes = 40 * c.corners + 190 * c.vertices + level_dense;
    bytes = keep_levels ? bytes + level_bytes : level_bytes;
    dense_bytes += level_dense;
    if (bytes > static_cast<double>(options.max_bytes) || c.corners > INT_MAX)
      throw InvalidInput(
          who + ": " + std::to_string(levels) + (levels == 1 ? " level of " : " levels of ") +
          std::to_string(face_count(t0)) + " faces reach " + number_text(c.faces, 3) + " faces and " +
          number_text(c.vertices, 3) + " vertices at level " + std::to_string(level + 1) + ", about " +
          number_text(bytes, 3) + " bytes (limit " + number_text(static_cast<double>(options.max_bytes), 3) +
          ")" +
          (dense_bytes > 0
               ? ", " + number_text(dense_bytes, 3) + " of them the weights of faces or vertices of " +
                     std::to_string(kRankFormFrom) + " or more sides (k² each or more; subdivide keeps none)"
               : std::string()) +
          (dense_bytes > 0 && level == 0 ? "" : "; ask for fewer levels"));
  }
  return t0;
}

/// Reports levels done to options.progress, weighted by their face counts.
class LevelProgress {
 public:
  LevelProgress(const MeshTopology& t0, MeshScheme scheme, int levels, const MeshOptions& options)
      : report_(options.progress) {
    if (!report_) return;
    Counts c{static_cast<double>(t0.vertex_count), static_cast<double>(t0.edges.size()),
             static_cast<double>(face_count(t0)), static_cast<double>(t0.face_vertices.size())};
    for (int level = 0; level < levels; ++level) {
      c = next_counts(scheme, c);
      faces_.push_back(static_cast<std::uint64_t>(c.faces));
      total_ += faces_.back();
    }
  }
  void level_done(int level) {
    if (!report_) return;
    done_ += faces_[static_cast<std::size_t>(level)];
    report_(done_, total_);
  }

 private:
  const std::function<void(std::uint64_t, std::uint64_t)>& report_;
  std::vector<std::uint64_t> faces_;
  std::uint64_t done_ = 0, total_ = 0;
};

}  // namespace

MeshRefinement refine_topology(const Mesh& mesh, MeshScheme scheme, int levels, const MeshOptions& options) {
  const std::string who(scheme_name(scheme));
  MeshRefinement r{
      .scheme = scheme, .options = options, .levels = {}, .features = {}, .tags = {}, .steps = {}};
  try {
    r.levels.push_back(checked_input(mesh, scheme, levels, options, true));
  } catch (const InvalidInput& e) {
    if (traits(scheme).sharpness && detail::split_non_manifold(mesh, who))
      throw InvalidInput(std::string(e.what()) + "; subdivide refines non-manifold meshes, refine_topology " +
                         "(a replayable refinement) does not yet");
    throw;
  }
  r.tags.push_back(mesh.tags);
  r.features.push_back(level_features(r.levels.back(), r.tags.back(), scheme, who));
  std::vector<double> halves;
  for (int level = 0; level < levels; ++level) {
    const MeshTopology& t = r.levels.back();
    Step s = step(scheme, t, r.features.back(), r.tags.back(), level, halves,
                  {.input = nullptr, .drop = !options.weights});
    if (options.weights) r.steps.push_back(std::move(s.stencils));
    r.tags.push_back(traits(scheme).sharpness
                         ? child_tags(scheme, t, r.features.back(), halves, r.tags.back())
                         : r.tags.back());
    if (level + 1 == levels && !options.last_level_adjacency) {
      MeshTopology faces;
      faces.vertex_count = s.vertex_count;
      faces.face_offsets = std::move(s.face_offsets);
      faces.face_vertices = std::move(s.face_vertices);
      r.levels.push_back(std::move(faces));
    } else {
      r.levels.push_back(child_topology(scheme, t, s, who));
      r.features.push_back(level_features(r.levels.back(), r.tags.back(), scheme, who));
    }
  }
  return r;
}

namespace {

/// Refuses a refinement made without weights (MeshOptions::weights) for `what`, which replays them.
void check_weights(const MeshRefinement& r, const std::string& what) {
  if (r.steps.size() + 1 != r.levels.size())
    throw InvalidInput(what + ": the refinement was made without its weights (MeshOptions::weights = false)");
}

}  // namespace

void apply(const Stencils& step, const Points& vertices, Points& out) {
  const auto rows = static_cast<Eigen::Index>(row_count(step));
  const Eigen::Index d = vertices.cols();
  if (out.rows() != rows || out.cols() != d) {  // else the storage is reused
    out.resize(rows, d);
    advise_huge_pages(out.data(), static_cast<std::size_t>(out.size()) * sizeof(double));
  }
  for (Eigen::Index i = 0; i < rows; ++i) {
    const int begin = step.offsets[static_cast<std::size_t>(i)];
    weighted_row(vertices.data(), d, step.columns.data() + begin, step.weights.data() + begin,
                 step.offsets[static_cast<std::size_t>(i) + 1] - begin, out.data() + d * i);
  }
}

Points apply(const Stencils& step, const Points& vertices) {
  Points out;
  apply(step, vertices, out);
  return out;
}

Stencils stencil_table(const MeshRefinement& refinement) {
  check_weights(refinement, "stencil_table");
  const int base = refinement.levels.front().vertex_count;
  Stencils table;  // identity on the base vertices
  for (int v = 0; v < base; ++v) {
    table.columns.push_back(v);
    table.weights.push_back(1);
    table.offsets.push_back(v + 1);
  }
  // Gustavson's row-by-row sparse product: next row = Σ_k w_k · (row c_k of the table so far).
  std::vector<double> sum(static_cast<std::size_t>(base), 0);
  std::vector<char> listed(static_cast<std::size_t>(base), 0);
  std::vector<int> touched;
  for (const Stencils& step : refinement.steps) {
    Stencils next;
    next.offsets.reserve(step.offsets.size());
    for (std::size_t i = 0; i + 1 < step.offsets.size(); ++i) {
      for (int k = step.offsets[i]; k < step.offsets[i + 1]; ++k) {
        const auto row = static_cast<std::size_t>(step.columns[static_cast<std::size_t>(k)]);
        const double w = step.weights[static_cast<std::size_t>(k)];
        for (int j = table.offsets[row]; j < table.offsets[row + 1]; ++j) {
          const auto c = static_cast<std::size_t>(table.columns[static_cast<std::size_t>(j)]);
          if (!listed[c]) {
            listed[c] = 1;
            touched.push_back(static_cast<int>(c));
          }
          sum[c] += w * table.weights[static_cast<std::size_t>(j)];
        }
      }
      std::sort(touched.begin(), touched.end());
      for (const int c : touched) {
        const auto u = static_cast<std::size_t>(c);
        if (sum[u] != 0) {  // exact cancellations (Butterfly's zero weights) leave no entry
          next.columns.push_back(c);
          next.weights.push_back(sum[u]);
        }
        sum[u] = 0;
        listed[u] = 0;
      }
      touched.clear();
      next.offsets.push_back(static_cast<int>(next.columns.size()));
    }
    table = std::move(next);
  }
  return table;
}

Points apply(const MeshRefinement& refinement, const Points& vertices) {
  check_weights(refinement, "apply");
  if (vertices.rows() != refinement.levels.front().vertex_count)
    throw InvalidInput(std::to_string(vertices.rows()) + " vertex rows given for a refinement of a mesh of " +
                       std::to_string(refinement.levels.front().vertex_count) + " vertices");
  Points P = vertices;
  for (const Stencils& s : refinement.steps) P = apply(s, P);
  return P;
}

Mesh subdivide(const Mesh& mesh, MeshScheme scheme, int levels, const MeshOptions& options) {
  const std::string who(scheme_name(scheme));
  check_mesh(mesh, who);
  // A non-manifold mesh is refined through its manifold stand-in (non_manifold.hpp), whose copies of
  // vertices are merged back at the end.
  std::optional<detail::ManifoldSplit> split;
  MeshTopology t;
  try {
    t = checked_input(mesh, scheme, levels, options, false);
  } catch (const InvalidInput&) {
    if (!traits(scheme).sharpness || !(split = detail::split_non_manifold(mesh, who))) throw;
    t = checked_input(split->mesh, scheme, levels, options, false);
  }
  const Mesh& source = split ? split->mesh : mesh;
  detail::check_channels(source, scheme, who, split.has_value());
  detail::Representatives same;  // of the stand-in's vertices and edges, level by level
  if (split) same = detail::initial_representatives(t, std::move(split->representative));
  MeshTags tags = source.tags;
  LevelFeatures features = level_features(t, tags, scheme, who);
  LevelProgress progress(t, scheme, levels, options);
  Mesh out;
  out.vertices = source.vertices;
  out.face_offsets = source.face_offsets;
  out.face_vertices = source.face_vertices;
  std::vector<detail::ChannelLevel> channels;
  for (const FaceVaryingChannel& c : source.face_varying)
    channels.push_back(detail::analyse_channel(t, features, tags, c));
  std::vector<double> halves;
  for (int level = 0; level < levels; ++level) {
    const bool last = level + 1 == levels, split_last = last && splits_faces(scheme);
    Step s =
        step(scheme, t, features, tags, level, halves, {.input = &out.vertices, .drop = false}, !split_last);
    out.vertices = std::move(s.output);
    s.output = Points();  // the parent's positions, swapped in by the move
    for (detail::ChannelLevel& c : channels) c = detail::refine_channel(scheme, t, features, halves, tags, c);
    if (traits(scheme).sharpness) tags = child_tags(scheme, t, features, halves, tags);
    std::vector<int> child_vertices;
    if (split) child_vertices = detail::child_vertex_representatives(t, same, s.vertex_count);
    if (split_last) {
      // Only the faces are left to make, from the parent's faces and face_edges: free its rings
      // and edge lists first, so that they, the parent's positions and the whole output never
      // live together (peak memory).
      for (std::vector<int>* rings :
           {&t.vertex_offsets_edges, &t.vertex_edge_list, &t.vertex_offsets_faces, &t.vertex_face_list})
        std::vector<int>().swap(*rings);
      std::vector<std::array<int, 2>>().swap(t.edges);
      std::vector<std::array<int, 2>>().swap(t.edge_faces);
      split_faces(scheme, t, s);
    }
    if (last) {
      out.face_offsets = std::move(s.face_offsets);
      out.face_vertices = std::move(s.face_vertices);
    } else {
      MeshTopology child = child_topology(scheme, t, s, who);
      if (split) same.edge = detail::child_edge_representatives(t, same, child);  // the parent's vertices
      t = std::move(child);
      features = level_features(t, tags, scheme, who);
    }
    if (split) same.vertex = std::move(child_vertices);
    progress.level_done(level);
  }
  out.tags = std::move(tags);
  for (detail::ChannelLevel& c : channels) out.face_varying.push_back(std::move(c.channel));
  if (split) return detail::merge_copies(std::move(out), same.vertex);
  return out;  // moved: the conditional expression copied the whole mesh
}

namespace {

/// One step of the factored form (Warren–Weimer; seed 003 §3–4): linear subdivision (old vertices,
/// edge midpoints and, for Catmull–Clark, face centroids, on the same split as the masks), then one
/// averaging pass over the split mesh's faces. An interior vertex of valence n moves to
/// (1 − w_n)·x + w_n·(mean of its faces' centroids), w_n = 4/n for Catmull–Clark and 3α_n for
/// Loop (α_n the seed's, 9/8 at n = 6). The seed's plain mean (w = 1) is Catmull–Clark only at
/// n = 4 and never Loop; these weights make both forms equal. A boundary vertex of the split mesh
/// moves to x/2 + (x₋ + x₊)/4 along the boundary (the curve's linear-then-average form of
/// (1, 6, 1)/8 and midpoints), or stays when it has one face under `edge_and_corner`.
Points factored_step(const MeshTopology& t, MeshScheme scheme, BoundaryRule boundary, const Points& P,
                     MeshTopology& split, const std::string& who) {
  const bool cc = scheme == MeshScheme::catmull_clark;
  const int V = t.vertex_count, E = static_cast<int>(t.edges.size()), F = static_cast<int>(face_count(t));
  Step s;
  s.vertex_count = cc ? V + E + F : V + E;
  split_faces(scheme, t, s);
  Points linear(s.vertex_count, P.cols());
  linear.topRows(V) = P;
  for (int e = 0; e < E; ++e) {
    const auto [a, b] = t.edges[static_cast<std::size_t>(e)];
    linear.row(V + e) = 0.5 * (P.row(a) + P.row(b));
  }
  if (cc)
    for (int f = 0; f < F; ++f) {
      const auto corners = face(t, static_cast<std::size_t>(f));
      linear.row(V + E + f).setZero();
      for (const int c : corners) linear.row(V + E + f) += P.row(c);
      linear.row(V + E + f) /= static_cast<double>(corners.size());
    }
  split = child_topology(scheme, t, s, who);
  Points centroid_sum = Points::Zero(linear.rows(), linear.cols());
  for (std::size_t f = 0; f < face_count(split); ++f) {
    const auto corners = face(split, f);
    Eigen::RowVectorXd c = Eigen::RowVectorXd::Zero(linear.cols());
    for (const int v : corners) c += linear.row(v);
    c /= static_cast<double>(corners.size());
    for (const int v : corners) centroid_sum.row(v) += c;
  }
  Points out(linear.rows(), linear.cols());
  for (int v = 0; v < split.vertex_count; ++v) {
    const auto faces = vertex_faces(split, static_cast<std::size_t>(v));
    const auto ring = ring_edges(split, v);
    if (faces.empty() ||
        (on_boundary(split, v) && faces.size() == 1 && boundary == BoundaryRule::edge_and_corner)) {
      out.row(v) = linear.row(v);
    } else if (on_boundary(split, v)) {
      out.row(v) = 0.5 * linear.row(v) +
                   0.25 * (linear.row(other_vertex(split, static_cast<std::size_t>(ring.front()), v)) +
                           linear.row(other_vertex(split, static_cast<std::size_t>(ring.back()), v)));
    } else {
      const int n = static_cast<int>(ring.size());
      const double w = cc ? 4.0 / n : 3 * n * loop_beta(n);
      out.row(v) = (1 - w) * linear.row(v) + (w / static_cast<double>(faces.size())) * centroid_sum.row(v);
    }
  }
  return out;
}

}  // namespace

Mesh factored_subdivide(const Mesh& mesh, MeshScheme scheme, int levels, const MeshOptions& options) {
  const std::string who = std::string(scheme_name(scheme)) + " (factored)";
  if (!traits(scheme).factored)
    throw InvalidInput(who + ": the factored form exists for catmull-clark and loop");
  check_mesh(mesh, who);
  if (mesh.tags.rules == RuleSet::blz)
    throw InvalidInput(who + ": the factored form has OpenSubdiv's boundary rules only, not the rule set " +
                       "'blz' (subdivide without --factored)");
  if (const std::string tag = first_feature(mesh.tags); !tag.empty())
    throw InvalidInput(who + ": the mesh has " + tag +
                       "; the factored form has only the smooth and boundary " +
                       "rules (subdivide without --factored)");
  if (!mesh.face_varying.empty())
    throw InvalidInput(
        who + ": the factored form does not refine face-varying channels (subdivide without --factored)");
  MeshTopology t = checked_input(mesh, scheme, levels, options, false);
  if (scheme == MeshScheme::catmull_clark)
    for (std::size_t f = 0; f < face_count(t); ++f)
      if (face(t, f).size() != 4)
        throw InvalidInput(who + ": face " + std::to_string(f) + " has " + std::to_string(face(t, f).size()) +
                           " corners; the factored form runs on quads (one step of the masks makes them)");
  LevelProgress progress(t, scheme, levels, options);
  Points P = mesh.vertices;
  for (int level = 0; level < levels; ++level) {
    MeshTopology split;
    P = factored_step(t, scheme, mesh.tags.boundary, P, split, who);
    t = std::move(split);
    progress.level_done(level);
  }
  Mesh out;
  out.vertices = std::move(P);
  out.face_offsets = std::move(t.face_offsets);
  out.face_vertices = std::move(t.face_vertices);
  return out;
}

Mesh catmull_clark(const Mesh& mesh, int levels, const MeshOptions& options) {
  return subdivide(mesh, MeshScheme::catmull_clark, levels, options);
}
Mesh loop(const Mesh& mesh, int levels, const MeshOptions& options) {
  return subdivide(mesh, MeshScheme::loop, levels, options);
}
Mesh doo_sabin(const Mesh& mesh, int levels, const MeshOptions& options) {
  return subdivide(mesh, MeshScheme::doo_sabin, levels, options);
}
Mesh butterfly(const Mesh& mesh, int levels, const MeshOptions& options) {
  return subdivide(mesh, MeshScheme::butterfly, levels, options);
}
Mesh sqrt3(const Mesh& mesh, int levels, const MeshOptions& options) {
  return subdivide(mesh, MeshScheme::sqrt3, levels, options);
}
Mesh bilinear(const Mesh& mesh, int levels, const MeshOptions& options) {
  return subdivide(mesh, MeshScheme::bilinear, levels, options);
}

Eigen::SparseMatrix<double, Eigen::RowMajor> subdivision_matrix(const Stencils& step, int old_vertex_count) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(step.weights.size());
  for (std::size_t i = 0; i < row_count(step); ++i)
    for (int k = step.offsets[i]; k < step.offsets[i + 1]; ++k)
      entries.emplace_back(static_cast<int>(i), step.columns[static_cast<std::size_t>(k)],
                           step.weights[static_cast<std::size_t>(k)]);
  Eigen::SparseMatrix<double, Eigen::RowMajor> S(static_cast<Eigen::Index>(row_count(step)),
                                                 old_vertex_count);
  S.setFromTriplets(entries.begin(), entries.end());
  return S;
}

namespace detail {

void butterfly_edge_stencil(const MeshTopology& t, int edge, std::vector<std::pair<int, double>>& out) {
  struct Append {
    std::vector<std::pair<int, double>>& out;
    void add(int column, double weight) { out.emplace_back(column, weight); }
  } row{out};
  const auto [a, b] = t.edges[static_cast<std::size_t>(edge)];
  std::vector<int> centres;
  for (const int v : {a, b})
    if (butterfly_extraordinary(t, v)) centres.push_back(v);
  const ButterflyRings rings = butterfly_rings(t, centres);
  std::vector<ButterflyRings::Place> places;
  for (const auto& place : rings.places)
    if (place.edge == edge) places.push_back(place);
  butterfly_edge_point(t, edge, rings, places, row);
}

}  // namespace detail

}  // namespace cifs::subdivision
