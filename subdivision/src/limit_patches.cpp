// SPDX-License-Identifier: MIT
// cifs — the patches of a subdivision surface as controlled IFS: which mesh vertices control a
// face's limit patch (regular and extraordinary, Catmull–Clark and Loop), and the matrices taking
// an extraordinary patch's control points one level down (cifs/subdivision/limit.hpp).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <vector>

#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "limit_patches.hpp"
#include "local_mesh.hpp"

namespace cifs::subdivision {
namespace {

using detail::corner;
using detail::corner_index;
using detail::edge_between;
using detail::patch_support;
using detail::regular_net;
using detail::triangle_support;
using Net3 = std::array<std::array<int, 3>, 3>;

int position_of(std::span<const int> list, int value) {
  const auto it = std::find(list.begin(), list.end(), value);
  if (it == list.end()) throw std::logic_error("limit surface: an element is not where the walk expects it");
  return static_cast<int>(it - list.begin());
}

/// The 3 × 3 net around an interior vertex q of valence 4 with four quads, in the frame where face
/// f is quadrant `quadrant` (0: (+,+), 1: (−,+), 2: (−,−), 3: (+,−)); net[a][b], q at [1][1].
Net3 vertex_net(const MeshTopology& t, int q, int f, int quadrant) {
  const auto edges = vertex_edges(t, static_cast<std::size_t>(q));
  const auto faces = vertex_faces(t, static_cast<std::size_t>(q));
  const int at = position_of(faces, f);
  // Face k lies between edges k and k + 1 (counter-clockwise): with face `at` in `quadrant`, edge k
  // points along direction r = k − at + quadrant (+a, +b, −a, −b) and face k fills quadrant r.
  static constexpr std::array<std::array<int, 2>, 4> kAlong{{{2, 1}, {1, 2}, {0, 1}, {1, 0}}};
  static constexpr std::array<std::array<int, 2>, 4> kDiagonal{{{2, 2}, {0, 2}, {0, 0}, {2, 0}}};
  Net3 net{};
  net[1][1] = q;
  for (int k = 0; k < 4; ++k) {
    const auto r = static_cast<std::size_t>((k - at + quadrant + 8) % 4);
    const int face_k = faces[static_cast<std::size_t>(k)];
    net[static_cast<std::size_t>(kAlong[r][0])][static_cast<std::size_t>(kAlong[r][1])] =
        other_vertex(t, static_cast<std::size_t>(edges[static_cast<std::size_t>(k)]), q);
    net[static_cast<std::size_t>(kDiagonal[r][0])][static_cast<std::size_t>(kDiagonal[r][1])] =
        corner(t, face_k, corner_index(t, face_k, q) + 2);
  }
  return net;
}

/// Writes a 3 × 3 net into a grid at offset (di, dj), checking entries already there.
template <std::size_t N>
void place(std::array<std::array<int, N>, N>& grid, const Net3& net, int di, int dj) {
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 3; ++b) {
      int& cell = grid[a + static_cast<std::size_t>(di)][b + static_cast<std::size_t>(dj)];
      if (cell >= 0 && cell != net[a][b]) throw std::logic_error("limit surface: the corner nets disagree");
      cell = net[a][b];
    }
}

/// The face among v's that holds all of `corners`.
int face_with(const MeshTopology& t, int v, std::initializer_list<int> corners) {
  for (const int f : vertex_faces(t, static_cast<std::size_t>(v))) {
    const auto c = face(t, static_cast<std::size_t>(f));
    if (std::all_of(corners.begin(), corners.end(),
                    [&](int x) { return std::find(c.begin(), c.end(), x) != c.end(); }))
      return f;
  }
  throw std::logic_error("limit surface: no face holds the corners");
}

/// The face in which `b` follows `a` counter-clockwise.
int face_after(const MeshTopology& t, int a, int b) {
  for (const int f : vertex_faces(t, static_cast<std::size_t>(a)))
    if (corner(t, f, corner_index(t, f, a) + 1) == b) return f;
  throw std::logic_error("limit surface: no face has the edge in that direction");
}

/// The patch whose control points are `support` (level 0 of `stencils`) and whose children's nets
/// are `children[0]` (the corner's patch) and the three regular ones (level 1).
ExtraordinaryPatch patch_from(MeshScheme scheme, int n, const Stencils& stencils,
                              const std::vector<int>& support,
                              const std::vector<std::vector<int>>& children) {
  std::map<int, int> column;
  for (std::size_t k = 0; k < support.size(); ++k) column[support[k]] = static_cast<int>(k);
  const auto matrix = [&](const std::vector<int>& rows) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()),
                                              static_cast<Eigen::Index>(support.size()));
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (int k = stencils.offsets[static_cast<std::size_t>(rows[i])];
           k < stencils.offsets[static_cast<std::size_t>(rows[i]) + 1]; ++k) {
        const auto it = column.find(stencils.columns[static_cast<std::size_t>(k)]);
        if (it == column.end())
          throw std::logic_error("limit surface: a child reaches outside the patch's support");
        M(static_cast<Eigen::Index>(i), it->second) += stencils.weights[static_cast<std::size_t>(k)];
      }
    return M;
  };
  ExtraordinaryPatch out;
  out.valence = n;
  out.subdivide = matrix(children[0]);
  for (std::size_t k = 0; k < 3; ++k) out.regular[k] = matrix(children[k + 1]);
  const LongVector stencil = local_spectrum(local_matrix(scheme, n)).limit_stencil;
  out.limit = Eigen::RowVectorXd::Zero(static_cast<Eigen::Index>(support.size()));
  for (Eigen::Index k = 0; k < stencil.size(); ++k) out.limit(k) = static_cast<double>(stencil(k));
  return out;
}

}  // namespace

namespace detail {

/// The 16-point B-spline net of a regular quad, its corner `first` at (0, 0): [i][j] flattened by i,
/// i along first → next corner.
std::array<int, 16> regular_net(const MeshTopology& t, int f, int first) {
  std::array<std::array<int, 4>, 4> grid{};
  for (auto& row : grid) row.fill(-1);
  const int e = corner_index(t, f, first);
  // Corner k + e sits at grid (1, 1), (2, 1), (2, 2), (1, 2) with the face in quadrant k.
  static constexpr std::array<std::array<int, 2>, 4> kOffset{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
  for (int k = 0; k < 4; ++k)
    place(grid, vertex_net(t, corner(t, f, e + k), f, k), kOffset[static_cast<std::size_t>(k)][0],
          kOffset[static_cast<std::size_t>(k)][1]);
  std::array<int, 16> out{};
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) out[i * 4 + j] = grid[i][j];
  return out;
}

/// The 2n + 8 control points of a quad whose corner `ev` is extraordinary: the corner's
/// neighbourhood (c, r_j, f_j, sector 0 at the face's next corner), then the 7 outer points
/// (3, 0) … (3, 3) … (0, 3) of the grid where c is (1, 1) and the face [1, 2]².
std::vector<int> patch_support(const MeshTopology& t, int f, int ev) {
  const int e = corner_index(t, f, ev);
  std::vector<int> out = detail::neighbourhood(t, MeshScheme::catmull_clark, ev, corner(t, f, e + 1), false);
  std::array<std::array<int, 4>, 4> grid{};
  for (auto& row : grid) row.fill(-1);
  place(grid, vertex_net(t, corner(t, f, e + 1), f, 1), 1, 0);
  place(grid, vertex_net(t, corner(t, f, e + 2), f, 2), 1, 1);
  place(grid, vertex_net(t, corner(t, f, e + 3), f, 3), 0, 1);
  for (const auto [i, j] : {std::array{3, 0}, std::array{3, 1}, std::array{3, 2}, std::array{3, 3},
                            std::array{2, 3}, std::array{1, 3}, std::array{0, 3}})
    out.push_back(grid[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
  return out;
}

/// The n + 6 control points of a triangle whose corner `ev` has valence n (Loop): ev's
/// neighbourhood (ev, then its ring counter-clockwise from the face's next corner c1), then the 5
/// points beyond it: the 3rd to 5th neighbours of c1 and the 4th and 5th of the last corner c2,
/// each counted counter-clockwise from ev (c1 and c2 have valence 6). By position, not by vertex:
/// on a small mesh the same vertex may come twice.
std::vector<int> triangle_support(const MeshTopology& t, int f, int ev) {
  const int e = corner_index(t, f, ev);
  std::vector<int> out = detail::neighbourhood(t, MeshScheme::loop, ev, corner(t, f, e + 1), false);
  for (const auto& [k, from, to] : {std::array{1, 2, 5}, std::array{2, 3, 5}}) {
    const int c = corner(t, f, e + k);
    const auto edges = vertex_edges(t, static_cast<std::size_t>(c));
    if (edges.size() != 6)
      throw std::logic_error("limit surface: a Loop patch's other corners are not regular");
    const int start = position_of(edges, edge_between(t, c, ev));
    for (int j = from; j < to; ++j)
      out.push_back(
          other_vertex(t, static_cast<std::size_t>(edges[static_cast<std::size_t>((start + j) % 6)]), c));
  }
  return out;
}

}  // namespace detail

ExtraordinaryPatch catmull_clark_patch(int n) {
  const detail::LocalRefinement local = detail::refine_local(MeshScheme::catmull_clark, n, {}, 4);
  const MeshTopology& t0 = local.refinement.levels.front();
  const MeshTopology& t1 = local.refinement.levels.back();
  const int c = local.centre, r0 = local.start;
  const int F = face_after(t0, c, r0);  // sector 0: c, r0, f0, r1 counter-clockwise
  const std::vector<int> support0 = patch_support(t0, F, c);
  const int f0 = corner(t0, F, corner_index(t0, F, c) + 2), r1 = corner(t0, F, corner_index(t0, F, c) + 3);
  // Child numbering: vertex points keep their index, edge e's point is V + e, face f's V + E + f.
  const int V = t0.vertex_count, E = static_cast<int>(t0.edges.size());
  const auto edge_point = [&](int a, int b) { return V + edge_between(t0, a, b); };
  const int e0 = edge_point(c, r0), e1 = edge_point(c, r1), m01 = edge_point(r0, f0);
  const int mid = V + E + F;
  if (local.child_centre != c) throw std::logic_error("limit surface: the centre moved");
  const std::vector<int> support1 = patch_support(t1, face_with(t1, c, {c, e0, mid}), c);
  std::vector<std::vector<int>> rows{support1};
  for (const auto& [first, others] : {std::pair{e0, std::array{r0, mid}}, std::pair{mid, std::array{m01, f0}},
                                      std::pair{e1, std::array{mid, r1}}}) {
    const std::array<int, 16> net =
        regular_net(t1, face_with(t1, first, {first, others[0], others[1]}), first);
    rows.emplace_back(net.begin(), net.end());
  }
  return patch_from(MeshScheme::catmull_clark, n, local.stencils, support0, rows);
}

ExtraordinaryPatch loop_patch(int n) {
  const detail::LocalRefinement local = detail::refine_local(MeshScheme::loop, n, {}, 4);
  const MeshTopology& t0 = local.refinement.levels.front();
  const MeshTopology& t1 = local.refinement.levels.back();
  const int c = local.centre, r0 = local.start;
  const int F = face_after(t0, c, r0);
  const int r1 = corner(t0, F, corner_index(t0, F, c) + 2);
  // Child numbering: vertex points keep their index, edge e's point is V + e.
  const int V = t0.vertex_count;
  const auto edge_point = [&](int a, int b) { return V + edge_between(t0, a, b); };
  const int m01 = edge_point(c, r0), m02 = edge_point(c, r1), m12 = edge_point(r0, r1);
  if (local.child_centre != c) throw std::logic_error("limit surface: the centre moved");
  // The children (c, m01, m02), (m01, r0, m12), (m02, m12, r1), (m12, m02, m01), each from its corner 0.
  std::vector<std::vector<int>> rows;
  for (const auto& [first, second] :
       {std::pair{c, m01}, std::pair{m01, r0}, std::pair{m02, m12}, std::pair{m12, m02}})
    rows.push_back(triangle_support(t1, face_after(t1, first, second), first));
  return patch_from(MeshScheme::loop, n, local.stencils, triangle_support(t0, F, c), rows);
}

namespace {

using Lattice = std::array<int, 2>;

/// Where loop_patch(6)'s 12 points sit on the three-direction lattice of the patch's (s, t), corners
/// (0, 0), (1, 0), (0, 1), neighbours ±(1, 0), ±(0, 1), ±(1, −1): the corner, its ring counter-clockwise
/// from (1, 0), then the 3rd to 5th neighbours of (1, 0) and the 4th and 5th of (0, 1) counted from the
/// corner (triangle_support's order; tests/subdivision/test_fractal_loop.cpp rebuilds the four
/// children's matrices from Loop's rules on these points).
constexpr std::array<Lattice, 12> kLoopNet{
    {{0, 0}, {1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}, {2, -1}, {2, 0}, {1, 1}, {0, 2}, {-1, 2}}};

/// Lattice distance: the fewest edges between two vertices.
int steps(Lattice a, Lattice b) {
  const int s = a[0] - b[0], t = a[1] - b[1];
  return std::max({std::abs(s), std::abs(t), std::abs(s + t)});
}

int net_row(Lattice p) {
  const auto it = std::find(kLoopNet.begin(), kLoopNet.end(), p);
  if (it == kLoopNet.end()) throw std::logic_error("loop patch: a turned point left the net");
  return static_cast<int>(it - kLoopNet.begin());
}

}  // namespace

ifs::TrianglePatch loop_triangle_patch() {
  const ExtraordinaryPatch regular = loop_patch(6);
  ifs::TrianglePatch out{
      {regular.subdivide, regular.regular[0], regular.regular[1], regular.regular[2]}, {}, {}};
  // A point's box spline is positive inside the hexagon of lattice radius 2 around it and vanishes on
  // its border: side 0, from (0, 0) to (1, 0), reads the points within one step of one of its ends.
  std::vector<Lattice> side;
  for (const Lattice& p : kLoopNet)
    if (std::min(steps(p, {0, 0}), steps(p, {1, 0})) <= 1) side.push_back(p);
  // The third of a turn taking corner k to corner k + 1: (s, t) → (1 − s − t, s).
  for (std::size_t k = 0; k < 3; ++k) {
    for (Lattice& p : side) {
      if (k > 0) p = {1 - p[0] - p[1], p[0]};
      out.sides[k].push_back(net_row(p));
    }
  }
  // Back at side 0: the triangle across it sees its points turned by a half turn about (½, 0).
  for (Lattice& p : side) p = {1 - p[0] - p[1], p[0]};
  for (const Lattice& p : side)
    out.reverse.push_back(
        static_cast<int>(std::find(side.begin(), side.end(), Lattice{1 - p[0], -p[1]}) - side.begin()));
  return out;
}

}  // namespace cifs::subdivision
