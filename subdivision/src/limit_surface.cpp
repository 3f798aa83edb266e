// SPDX-License-Identifier: MIT
// cifs — Catmull–Clark's limit surface at any (face, u, v): regular patches as bicubic B-splines,
// extraordinary ones through their controlled-IFS form (cifs/subdivision/limit.hpp).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "cifs/automata/tensor.hpp"
#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs_surface.hpp"
#include "cifs/nurbs/surface.hpp"
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

/// Value and partials (times `scale`) of the bicubic B-spline patch of a 16-point net (rows by i then
/// j) at (a, b), written into three rows of D = net.cols() doubles: the loop of every point, so no
/// allocation, separable sums (along j, then i) and, for D = 3, the sums in registers.
template <int D>
void bicubic_sums(const double* net, Eigen::Index d, const std::array<double, 4>& ba,
                  const std::array<double, 4>& da, const std::array<double, 4>& bb,
                  const std::array<double, 4>& db, double scale, double* value, double* du, double* dv) {
  for (Eigen::Index k = 0; k < (D > 0 ? D : d); ++k) {
    double v = 0, u_sum = 0, v_sum = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      const double* row = net + static_cast<Eigen::Index>(i * 4) * d + k;
      const double along_j = bb[0] * row[0] + bb[1] * row[d] + bb[2] * row[2 * d] + bb[3] * row[3 * d];
      const double along_dj = db[0] * row[0] + db[1] * row[d] + db[2] * row[2 * d] + db[3] * row[3 * d];
      v += ba[i] * along_j;
      u_sum += da[i] * along_j;
      v_sum += ba[i] * along_dj;
    }
    value[k] = v;
    du[k] = scale * u_sum;
    dv[k] = scale * v_sum;
  }
}

void bicubic(const Points& net, double a, double b, double scale, double* value, double* du, double* dv) {
  std::array<double, 4> ba{}, da{}, bb{}, db{};
  cubic_basis(a, ba, da);
  cubic_basis(b, bb, db);
  if (net.cols() == 3)
    bicubic_sums<3>(net.data(), 3, ba, da, bb, db, scale, value, du, dv);
  else
    bicubic_sums<0>(net.data(), net.cols(), ba, da, bb, db, scale, value, du, dv);
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

namespace {

/// The uniform cubic B-spline's halves (rows: the child's control points on the parent's).
Eigen::Matrix4d cubic_half(int half) {
  Eigen::Matrix4d G;
  G << 4, 4, 0, 0, 1, 6, 1, 0, 0, 4, 4, 0, 0, 1, 6, 1;
  G /= 8;
  return half == 0 ? G : Eigen::Matrix4d(G.reverse());  // D is G read backwards
}

/// Which corner of face f, if any, is extraordinary; InvalidInput (naming the face) for what the
/// surface automaton does not build.
int extraordinary_corner(const MeshTopology& t, int f) {
  const std::string where = "catmull-clark limit surface: face " + std::to_string(f);
  const auto corners = face(t, static_cast<std::size_t>(f));
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
    for (const int g : vertex_faces(t, v))
      if (face(t, static_cast<std::size_t>(g)).size() != 4)
        throw InvalidInput(where + ": a corner touches a face that is not a quad (refine one level first)");
  }
  if (extraordinary > 1)
    throw InvalidInput(where + ": " + std::to_string(extraordinary) +
                       " extraordinary corners (refine one level first)");
  return ev;
}

bool is_regular(const automata::Automaton& a, automata::StateId s) {
  return a.graph[s].name == "regular";
}

}  // namespace

namespace {

/// The automaton of the given faces (initial entry i is faces[i], `segment` the face's index).
SurfaceAutomaton catmull_clark_automaton(const Mesh& mesh, const MeshTopology& t,
                                         std::span<const int> faces) {
  SurfaceAutomaton out;
  automata::Graph& g = out.automaton.graph;
  const automata::StateId regular =
      boost::add_vertex(automata::State{.size = 16, .window = {}, .recurrent = false, .name = "regular"}, g);
  static constexpr std::array<const char*, 4> kLabels{"GH", "GB", "DH", "DB"};
  for (int c = 0; c < 4; ++c)
    boost::add_edge(regular, regular,
                    automata::Transition{kLabels[static_cast<std::size_t>(c)],
                                         automata::kron(cubic_half(c / 2), cubic_half(c % 2))},
                    g);
  std::map<int, automata::StateId> extraordinary;  // by valence
  const auto state_of = [&](int n) {
    if (const auto it = extraordinary.find(n); it != extraordinary.end()) return it->second;
    const ExtraordinaryPatch patch = catmull_clark_patch(n);
    const automata::StateId s = boost::add_vertex(
        automata::State{.size = 2 * n + 8, .window = {}, .recurrent = false, .name = "E" + std::to_string(n)},
        g);
    // Child 2·iu + iv: (0, 0) the corner's quarter, (0, 1) regular[2], (1, 0) regular[0], (1, 1) regular[1].
    boost::add_edge(s, s, automata::Transition{"GH", patch.subdivide}, g);
    boost::add_edge(s, regular, automata::Transition{"GB", patch.regular[2]}, g);
    boost::add_edge(s, regular, automata::Transition{"DH", patch.regular[0]}, g);
    boost::add_edge(s, regular, automata::Transition{"DB", patch.regular[1]}, g);
    return extraordinary.emplace(n, s).first->second;
  };
  const Eigen::Index d = mesh.vertices.cols();
  for (const int f : faces) {
    const int ev = extraordinary_corner(t, f);
    const int first = corner(t, f, std::max(ev, 0));
    std::vector<int> support;
    automata::StateId state = regular;
    if (ev < 0) {
      const std::array<int, 16> net = regular_net(t, f, first);
      support.assign(net.begin(), net.end());
    } else {
      const int n = valence(t, static_cast<std::size_t>(first));
      try {
        state = state_of(n);
      } catch (const InvalidInput& e) {
        throw InvalidInput("catmull-clark limit surface: face " + std::to_string(f) + ": " + e.what());
      }
      support = patch_support(t, f, first);
    }
    Points net(static_cast<Eigen::Index>(support.size()), d);
    for (std::size_t k = 0; k < support.size(); ++k)
      net.row(static_cast<Eigen::Index>(k)) = mesh.vertices.row(support[k]);
    out.automaton.initial.push_back(automata::Initial{.segment = f, .state = state});
    out.nets.push_back(std::move(net));
    const int e = corner_index(t, f, first);
    out.corners.push_back({first, corner(t, f, e + 1), corner(t, f, e + 2), corner(t, f, e + 3)});
  }
  return out;
}

}  // namespace

SurfaceAutomaton catmull_clark_automaton(const Mesh& mesh) {
  const MeshTopology t = build_topology(mesh);
  std::vector<int> faces(face_count(t));
  std::iota(faces.begin(), faces.end(), 0);
  return catmull_clark_automaton(mesh, t, faces);
}

SurfaceSample evaluate_limit_surface(const Mesh& mesh, std::span<const FacePoint> at) {
  const MeshTopology t = build_topology(mesh);
  const Eigen::Index d = mesh.vertices.cols();
  const auto F = static_cast<int>(face_count(t));
  for (std::size_t p = 0; p < at.size(); ++p) {  // the points first: a bad one is named before any work
    const FacePoint& q = at[p];
    const bool no_face = q.face < 0 || q.face >= F;
    if (!no_face && q.u >= 0 && q.u <= 1 && q.v >= 0 && q.v <= 1) continue;
    const std::string where =
        "catmull-clark limit: point " + std::to_string(p) + " (face " + std::to_string(q.face) + ")";
    if (no_face) throw InvalidInput(where + ": no such face; the mesh has " + std::to_string(F));
    throw InvalidInput(where + ": (u, v) = (" + std::to_string(q.u) + ", " + std::to_string(q.v) +
                       ") is outside [0, 1]²");
  }
  // Only the faces asked for: the others may be boundary faces.
  std::vector<int> faces, entry(static_cast<std::size_t>(F), -1);
  for (const FacePoint& q : at)
    if (entry[static_cast<std::size_t>(q.face)] < 0) {
      entry[static_cast<std::size_t>(q.face)] = static_cast<int>(faces.size());
      faces.push_back(q.face);
    }
  const SurfaceAutomaton s = catmull_clark_automaton(mesh, t, faces);
  const automata::Graph& g = s.automaton.graph;
  // The extraordinary point itself is the fixed point of the corner quarter (no partials there).
  const std::vector<Eigen::RowVectorXd> corner_point = ifs::repeated_child_functionals(s.automaton, 0);
  SurfaceSample out;
  const auto count = static_cast<Eigen::Index>(at.size());
  out.positions.resize(count, d);
  out.du.resize(count, d);
  out.dv.resize(count, d);
  std::vector<char> regular(boost::num_vertices(g));
  for (automata::StateId k = 0; k < regular.size(); ++k) regular[k] = is_regular(s.automaton, k) ? 1 : 0;
  // Per face, the nets met going down: the corner quarters' chain (level j: the corner quarter j levels
  // down, a net of its extraordinary state) and, per level, the other quarters' nets. Built once per
  // face and level, so a point costs one bicubic evaluation whatever its depth.
  struct Descent {
    std::vector<Points> chain;
    std::vector<automata::StateId> state;
    std::vector<std::array<Points, 4>> quarter;
  };
  std::vector<Descent> descents(faces.size());
  Eigen::RowVectorXd pa(d), pb(d);
  for (Eigen::Index p = 0; p < count; ++p) {
    const FacePoint& q = at[static_cast<std::size_t>(p)];
    const auto f = static_cast<std::size_t>(entry[static_cast<std::size_t>(q.face)]);
    // The patch's (s, t) is the face's (u, v) turned: its (0, 0) is the face's corner `turn`.
    const int turn = corner_index(t, q.face, s.corners[f][0]);
    const std::array<std::array<double, 2>, 4> st{
        {{q.u, q.v}, {q.v, 1 - q.u}, {1 - q.u, 1 - q.v}, {1 - q.v, q.u}}};
    double a = st[static_cast<std::size_t>(turn)][0], b = st[static_cast<std::size_t>(turn)][1];
    const automata::StateId first = s.automaton.initial[f].state;
    if (regular[first] != 0) {
      bicubic(s.nets[f], a, b, 1, out.positions.row(p).data(), pa.data(), pb.data());
    } else if (a == 0 && b == 0) {
      out.positions.row(p) = corner_point[first] * s.nets[f];
      pa.setZero();
      pb.setZero();
    } else {
      Descent& down = descents[f];
      if (down.chain.empty()) {
        down.chain.push_back(s.nets[f]);
        down.state.push_back(first);
      }
      std::size_t level = 0;
      double scale = 2;
      for (; std::max(a, b) < 0.5; ++level, a *= 2, b *= 2, scale *= 2)  // the corner's quarter
        if (level + 1 == down.chain.size()) {
          const auto edge = *boost::out_edges(down.state[level], g).first;
          down.chain.push_back(g[edge].matrix * down.chain[level]);
          down.state.push_back(boost::target(edge, g));
          if (regular[down.state.back()] != 0)
            throw std::logic_error("limit surface: the corner quarter of an extraordinary patch is regular");
        }
      if (down.quarter.size() <= level) down.quarter.resize(level + 1);
      const int iu = a >= 0.5 ? 1 : 0, iv = b >= 0.5 ? 1 : 0, c = 2 * iu + iv;
      Points& net = down.quarter[level][static_cast<std::size_t>(c)];
      if (net.size() == 0) {
        auto edge = boost::out_edges(down.state[level], g).first;
        std::advance(edge, c);
        if (regular[boost::target(*edge, g)] == 0)
          throw std::logic_error("limit surface: a side quarter of an extraordinary patch is not regular");
        net = g[*edge].matrix * down.chain[level];
      }
      bicubic(net, 2 * a - iu, 2 * b - iv, scale, out.positions.row(p).data(), pa.data(), pb.data());
    }
    // Back to the face's (u, v).
    switch (turn) {
      case 0:
        out.du.row(p) = pa, out.dv.row(p) = pb;
        break;
      case 1:
        out.du.row(p) = -pb, out.dv.row(p) = pa;
        break;
      case 2:
        out.du.row(p) = -pa, out.dv.row(p) = -pb;
        break;
      default:
        out.du.row(p) = pb, out.dv.row(p) = -pa;
        break;
    }
  }
  return out;
}

Mesh surface_automaton_mesh(const SurfaceAutomaton& surface, int depth, const ifs::MeshOptions& options) {
  const ifs::QuadMesh blocks = ifs::patch_meshes(surface.automaton, surface.nets, depth, options);
  // Node (I, J) of face f's block is shared with its neighbours when it lies on the block's border:
  // a mesh vertex at a corner, else a point of a mesh edge, named by the edge's end vertices (lower
  // index first) and its distance from the lower one in cells. Each gets the first block's vertex.
  const int side = 1 << depth, row = side + 1, block = row * row;
  std::map<std::array<int, 3>, int> shared;
  std::vector<int> index(static_cast<std::size_t>(blocks.vertices.rows()));
  int next = 0;
  const auto corner_node = [&](int I, int J) -> int {
    if (I == 0 && J == 0) return 0;
    if (I == side && J == 0) return 1;
    if (I == side && J == side) return 2;
    if (I == 0 && J == side) return 3;
    return -1;
  };
  for (std::size_t f = 0; f < surface.corners.size(); ++f) {
    const auto& c = surface.corners[f];
    for (int I = 0; I <= side; ++I)
      for (int J = 0; J <= side; ++J) {
        const std::size_t v = f * static_cast<std::size_t>(block) + static_cast<std::size_t>(I * row + J);
        std::array<int, 3> key{-1, -1, 0};
        if (const int k = corner_node(I, J); k >= 0) {
          key = {c[static_cast<std::size_t>(k)], -1, 0};
        } else if (I == 0 || I == side || J == 0 || J == side) {
          // Sides: J = 0 from corner 0 to 1 (I cells from 0), I = side from 1 to 2, J = side from 3
          // to 2, I = 0 from 0 to 3.
          int from = 0, to = 0, at = 0;
          if (J == 0)
            from = c[0], to = c[1], at = I;
          else if (I == side)
            from = c[1], to = c[2], at = J;
          else if (J == side)
            from = c[3], to = c[2], at = I;
          else
            from = c[0], to = c[3], at = J;
          key = from < to ? std::array{from, to, at} : std::array{to, from, side - at};
        }
        if (key[0] < 0) {
          index[v] = next++;
          continue;
        }
        const auto [it, fresh] = shared.emplace(key, next);
        index[v] = it->second;
        if (fresh) ++next;
      }
  }
  Mesh out;
  out.vertices.resize(next, blocks.vertices.cols());
  std::vector<bool> written(static_cast<std::size_t>(next), false);
  for (std::size_t v = 0; v < index.size(); ++v) {
    const auto w = static_cast<std::size_t>(index[v]);
    if (written[w]) continue;
    out.vertices.row(index[v]) = blocks.vertices.row(static_cast<Eigen::Index>(v));
    written[w] = true;
  }
  std::vector<int> corners;
  corners.reserve(4 * blocks.quads.size());
  for (const auto& q : blocks.quads)
    for (const int v : q) corners.push_back(index[static_cast<std::size_t>(v)]);
  out = uniform_mesh(out.vertices, std::move(corners), 4);
  out.states = blocks.quad_state;
  return out;
}

FractalSurface fractal_catmull_clark(const SurfaceAutomaton& smooth, const ifs::PerturbOptions& options) {
  // The uniform bicubic patch: 4 × 4 control points, knots 0 … 7, one patch whose sides all lie on knot
  // lines.
  nurbs::Knots knots(8);
  for (std::size_t k = 0; k < knots.size(); ++k) knots[k] = static_cast<double>(k);
  const nurbs::Surface patch = nurbs::make_surface({3, 3}, {knots, knots}, {4, 4}, Points::Zero(16, 3));
  const automata::TensorAutomaton tensor = automata::tensor_automaton(patch);
  FractalSurface out;
  out.perturbation = ifs::perturb(ifs::surface_bcifs(tensor), options);
  const automata::Automaton& cells = out.perturbation.system.automaton;
  // The new graph: the BC-IFS's cells, then the smooth automaton's extraordinary states with their
  // regular children led to the patch cell (the BC-IFS's one initial state).
  automata::Graph g = cells.graph;
  const automata::StateId root = cells.initial.at(0).state;
  const automata::Graph& old = smooth.automaton.graph;
  std::vector<automata::StateId> moved(boost::num_vertices(old), root);
  for (automata::StateId s = 0; s < boost::num_vertices(old); ++s)
    if (!is_regular(smooth.automaton, s)) moved[s] = boost::add_vertex(old[s], g);
  for (automata::StateId s = 0; s < boost::num_vertices(old); ++s) {
    if (is_regular(smooth.automaton, s)) continue;
    for (auto [e, end] = boost::out_edges(s, old); e != end; ++e)
      boost::add_edge(moved[s], moved[boost::target(*e, old)], old[*e], g);
  }
  out.surface.automaton.graph = g;  // boost::adjacency_list has no move assignment
  for (const automata::Initial& i : smooth.automaton.initial)
    out.surface.automaton.initial.push_back(automata::Initial{.segment = i.segment, .state = moved[i.state]});
  out.surface.nets = smooth.nets;
  out.surface.corners = smooth.corners;
  return out;
}

}  // namespace cifs::subdivision
