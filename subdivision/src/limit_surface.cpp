// SPDX-License-Identifier: MIT
// cifs — Catmull–Clark's limit surface at any (face, u, v): regular patches as bicubic B-splines,
// extraordinary ones through their controlled-IFS form (cifs/subdivision/limit.hpp).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "local_mesh.hpp"

namespace cifs::subdivision {
namespace {

using detail::corner;
using detail::corner_index;
using detail::edge_between;
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

/// Uniform cubic B-spline basis on one segment and its derivative.
void cubic_basis(double t, std::array<double, 4>& b, std::array<double, 4>& d) {
  const double s = 1 - t;
  b = {s * s * s / 6, (3 * t * t * t - 6 * t * t + 4) / 6, (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6,
       t * t * t / 6};
  d = {-s * s / 2, (3 * t * t - 4 * t) / 2, (-3 * t * t + 2 * t + 1) / 2, t * t / 2};
}

/// Value and partials of the bicubic B-spline patch of a 16-point net (rows by i then j) at (a, b).
std::array<Eigen::RowVectorXd, 3> bicubic(const Eigen::MatrixXd& net, double a, double b) {
  std::array<double, 4> ba{}, da{}, bb{}, db{};
  cubic_basis(a, ba, da);
  cubic_basis(b, bb, db);
  std::array<Eigen::RowVectorXd, 3> out;
  for (auto& x : out) x = Eigen::RowVectorXd::Zero(net.cols());
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) {
      const auto row = net.row(static_cast<Eigen::Index>(i * 4 + j));
      out[0] += ba[i] * bb[j] * row;
      out[1] += da[i] * bb[j] * row;
      out[2] += ba[i] * db[j] * row;
    }
  return out;
}

}  // namespace

ExtraordinaryPatch catmull_clark_patch(int n) {
  const detail::LocalRefinement local = detail::refine_local(MeshScheme::catmull_clark, n, {}, 4);
  const MeshTopology& t0 = local.refinement.levels.front();
  const MeshTopology& t1 = local.refinement.levels.back();
  const int c = local.centre, r0 = local.start;
  const int F = face_with(t0, c, {c, r0});  // sector 0: c, r0, f0, r1 counter-clockwise
  if (corner(t0, F, corner_index(t0, F, c) + 1) != r0)
    throw std::logic_error("limit surface: sector 0 is not first");
  const std::vector<int> support0 = patch_support(t0, F, c);
  const int f0 = corner(t0, F, corner_index(t0, F, c) + 2), r1 = corner(t0, F, corner_index(t0, F, c) + 3);
  // Child numbering: vertex points keep their index, edge e's point is V + e, face f's V + E + f.
  const int V = t0.vertex_count, E = static_cast<int>(t0.edges.size());
  const auto edge_point = [&](int a, int b) { return V + edge_between(t0, a, b); };
  const int e0 = edge_point(c, r0), e1 = edge_point(c, r1), m01 = edge_point(r0, f0),
            m12 = edge_point(f0, r1);
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
  (void)m12;
  std::map<int, int> column;
  for (std::size_t k = 0; k < support0.size(); ++k) column[support0[k]] = static_cast<int>(k);
  const auto matrix = [&](const std::vector<int>& children) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(children.size()),
                                              static_cast<Eigen::Index>(support0.size()));
    const Stencils& s = local.stencils;
    for (std::size_t i = 0; i < children.size(); ++i)
      for (int k = s.offsets[static_cast<std::size_t>(children[i])];
           k < s.offsets[static_cast<std::size_t>(children[i]) + 1]; ++k) {
        const auto it = column.find(s.columns[static_cast<std::size_t>(k)]);
        if (it == column.end())
          throw std::logic_error("limit surface: a child reaches outside the patch's support");
        M(static_cast<Eigen::Index>(i), it->second) += s.weights[static_cast<std::size_t>(k)];
      }
    return M;
  };
  ExtraordinaryPatch out;
  out.valence = n;
  out.subdivide = matrix(rows[0]);
  for (std::size_t k = 0; k < 3; ++k) out.regular[k] = matrix(rows[k + 1]);
  const LongVector stencil = local_spectrum(local_matrix(MeshScheme::catmull_clark, n)).limit_stencil;
  out.limit = Eigen::RowVectorXd::Zero(static_cast<Eigen::Index>(support0.size()));
  for (Eigen::Index k = 0; k < stencil.size(); ++k) out.limit(k) = static_cast<double>(stencil(k));
  return out;
}

SurfaceSample evaluate_limit_surface(const Mesh& mesh, std::span<const FacePoint> at) {
  const MeshTopology t = build_topology(mesh);
  const Eigen::Index d = mesh.vertices.cols();
  SurfaceSample out;
  const auto count = static_cast<Eigen::Index>(at.size());
  out.positions.resize(count, d);
  out.du.resize(count, d);
  out.dv.resize(count, d);
  std::map<int, ExtraordinaryPatch> patches;
  const auto gather = [&](const auto& ids) {
    Eigen::MatrixXd x(static_cast<Eigen::Index>(ids.size()), d);
    for (std::size_t k = 0; k < ids.size(); ++k)
      x.row(static_cast<Eigen::Index>(k)) = mesh.vertices.row(ids[k]);
    return x;
  };
  for (Eigen::Index p = 0; p < count; ++p) {
    const FacePoint& q = at[static_cast<std::size_t>(p)];
    const std::string where =
        "catmull-clark limit: point " + std::to_string(p) + " (face " + std::to_string(q.face) + ")";
    if (q.face < 0 || static_cast<std::size_t>(q.face) >= face_count(t))
      throw InvalidInput(where + ": no such face; the mesh has " + std::to_string(face_count(t)));
    if (!(q.u >= 0 && q.u <= 1 && q.v >= 0 && q.v <= 1))
      throw InvalidInput(where + ": (u, v) = (" + std::to_string(q.u) + ", " + std::to_string(q.v) +
                         ") is outside [0, 1]²");
    const auto corners = face(t, static_cast<std::size_t>(q.face));
    if (corners.size() != 4) throw InvalidInput(where + ": not a quad (refine one level first)");
    int ev = -1, extraordinary = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const auto v = static_cast<std::size_t>(corners[k]);
      if (t.boundary_vertex[v])
        throw InvalidInput(where + ": touches the boundary; boundary patches are not built");
      if (valence(t, v) != 4) {
        ev = static_cast<int>(k);
        ++extraordinary;
      }
      for (const int f : vertex_faces(t, v))
        if (face(t, static_cast<std::size_t>(f)).size() != 4)
          throw InvalidInput(where + ": a corner touches a face that is not a quad (refine one level first)");
    }
    if (extraordinary > 1)
      throw InvalidInput(where + ": " + std::to_string(extraordinary) +
                         " extraordinary corners (refine one level first)");
    if (ev < 0) {
      const std::array<int, 16> net = regular_net(t, q.face, corners[0]);
      const auto [x, xu, xv] = bicubic(gather(net), q.u, q.v);
      out.positions.row(p) = x;
      out.du.row(p) = xu;
      out.dv.row(p) = xv;
      continue;
    }
    // Extraordinary corner at (s, t) = (0, 0), s towards the next corner, t towards the previous.
    const std::array<std::array<double, 2>, 4> st{
        {{q.u, q.v}, {q.v, 1 - q.u}, {1 - q.u, 1 - q.v}, {1 - q.v, q.u}}};
    double s = st[static_cast<std::size_t>(ev)][0], tt = st[static_cast<std::size_t>(ev)][1];
    const int n = valence(t, static_cast<std::size_t>(corners[static_cast<std::size_t>(ev)]));
    auto it = patches.find(n);
    if (it == patches.end()) {
      try {
        it = patches.emplace(n, catmull_clark_patch(n)).first;
      } catch (const InvalidInput& e) {
        throw InvalidInput(where + ": " + e.what());
      }
    }
    const ExtraordinaryPatch& patch = it->second;
    Eigen::MatrixXd x = gather(patch_support(t, q.face, corners[static_cast<std::size_t>(ev)]));
    Eigen::RowVectorXd ps = Eigen::RowVectorXd::Zero(d), pt = ps;
    if (s == 0 && tt == 0) {  // the extraordinary point itself: no parametric partials there
      out.positions.row(p) = patch.limit * x;
    } else {
      double scale = 2;
      while (std::max(s, tt) < 0.5) {  // the corner's quarter: one level down, same shape
        x = patch.subdivide * x;
        s *= 2;
        tt *= 2;
        scale *= 2;
      }
      const int k = s >= 0.5 ? (tt >= 0.5 ? 1 : 0) : 2;
      const double a = k == 2 ? 2 * s : 2 * s - 1, b = k == 0 ? 2 * tt : 2 * tt - 1;
      const auto [value, da, db] = bicubic(patch.regular[static_cast<std::size_t>(k)] * x, a, b);
      out.positions.row(p) = value;
      ps = scale * da;
      pt = scale * db;
    }
    // Back to the face's (u, v): s, t as functions of u, v for each position of the corner.
    switch (ev) {
      case 0:
        out.du.row(p) = ps, out.dv.row(p) = pt;
        break;
      case 1:
        out.du.row(p) = -pt, out.dv.row(p) = ps;
        break;
      case 2:
        out.du.row(p) = -ps, out.dv.row(p) = -pt;
        break;
      default:
        out.du.row(p) = pt, out.dv.row(p) = -ps;
        break;
    }
  }
  return out;
}

}  // namespace cifs::subdivision
