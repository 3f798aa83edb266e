// SPDX-License-Identifier: MIT
// cifs — the limit surface at any (face, u, v) of any mesh the production refiner takes (creases,
// corners, holes, boundaries, non-quads), through an automaton of local configurations
// (cifs/subdivision/limit.hpp, evaluate_limit_surface; docs/subdivision-surfaces.md, "The limit
// surface at any (face, u, v)").
//
// A state is a face's configuration: the face and the one-rings of its corners, with the tags the
// rules read there (the sharpness of the edges at its corners and of the corners, holes, the crease
// method and triangle rule; under Chaikin's method also the far ends of its semi-sharp edges with their
// rings), in an order that only depends on the topology seen from the face's first corner — its key. The
// children of a state are the configurations of the face's children after one step of the production refiner
// run on the configuration itself (the vertex data the identity: the step's rows are the child's control
// points on the parent's). Every child's configuration lies in the refined configuration, with correct rows:
// its vertices are vertex points of the face's corners, edge points of their edges and face points of their
// faces, which read nothing outside.
//
// A state whose patch is a polynomial (bicubic, quartic on triangles) is a leaf: the regular interior
// patch, and also the regular boundary, crease and corner patches. Which states are is proved, not
// assumed: the polynomial through the limit points at the 16 (15) points (a, b)/4 of the state's
// domain is fitted (Bernstein basis), and every state reachable from it must be fitted too and agree
// with it on the child's domain (coefficients of the restriction = the child's, on the parent's
// control points). Then the control points of every level are those of the polynomial's restrictions, and the
// limit is the polynomial at every dyadic point: the patch. A state with sharpness left to spend, an
// extraordinary vertex, a dart or a smooth boundary corner fails the check and is descended; at such
// a corner itself the value is its limit point (limit_stencils' route) and the partials are the face's
// edges' parts in the tangent plane of the corner's sector (CornerTangents).
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <deque>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cifs/automata/tensor.hpp"
#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/memory.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/rules.hpp"
#include "sector_plane.hpp"
#include "surface_states.hpp"

namespace cifs::subdivision {
namespace {

int corner_of(std::span<const int> corners, int v) {
  return static_cast<int>(std::find(corners.begin(), corners.end(), v) - corners.begin());
}

/// A face's configuration: its local mesh (the face first, from its first corner, so that vertices
/// 0 … n − 1 are its corners; then, corner after corner, the faces around it counter-clockwise from
/// the face, each from the corner it was met at), the level's vertex of each local vertex, and the
/// key. A vertex away from the face's corners met by faces that share no edge at it there (a small
/// mesh folding back) is one local vertex per fan: only its position is read, never its rule.
struct Configuration {
  Mesh mesh;
  std::vector<int> vertices;
  std::string key;
};

template <typename T>
void put(std::string& key, T x) {
  key.append(reinterpret_cast<const char*>(&x), sizeof x);
}

Configuration configuration(const MeshTopology& t, const LevelFeatures& f, const MeshTags& options, int face0,
                            int first) {
  std::vector<int> faces{face0}, start{first};
  const auto c0 = face(t, static_cast<std::size_t>(face0));
  const auto n = static_cast<int>(c0.size());
  const auto index_of = [&](int g) {
    return static_cast<int>(std::find(faces.begin(), faces.end(), g) - faces.begin());
  };
  for (int k = 0; k < n; ++k) {
    const int v = c0[static_cast<std::size_t>((first + k) % n)];
    const auto around = vertex_faces(t, static_cast<std::size_t>(v));
    const auto m = around.size();
    const auto at = static_cast<std::size_t>(std::find(around.begin(), around.end(), face0) - around.begin());
    for (std::size_t i = 1; i < m; ++i) {
      const int g = around[(at + i) % m];
      if (index_of(g) < static_cast<int>(faces.size())) continue;
      faces.push_back(g);
      start.push_back(corner_of(face(t, static_cast<std::size_t>(g)), v));
    }
  }
  // Under Chaikin's crease method the point of a semi-sharp edge also reads the other semi-sharp edges
  // at its far end (its half there decays with their mean): that vertex comes with its one-ring too,
  // from the face left of the edge.
  std::vector<int> full;  // the vertices whose one-ring is in the configuration, beyond the corners
  if (options.crease_method == CreaseMethod::chaikin)
    for (int k = 0; k < n; ++k) {
      const int v = c0[static_cast<std::size_t>((first + k) % n)];
      for (const int e : vertex_edges(t, static_cast<std::size_t>(v))) {
        const double s = edge_sharpness(f, e);
        const int x = other_vertex(t, static_cast<std::size_t>(e), v);
        if (s <= 0 || s >= kInfiniteSharpness || corner_of(c0, x) < n ||
            std::find(full.begin(), full.end(), x) != full.end())
          continue;
        full.push_back(x);
        const int left = t.edges[static_cast<std::size_t>(e)][0] == v
                             ? t.edge_faces[static_cast<std::size_t>(e)][0]
                             : t.edge_faces[static_cast<std::size_t>(e)][1];
        const auto around = vertex_faces(t, static_cast<std::size_t>(x));
        const auto at =
            static_cast<std::size_t>(std::find(around.begin(), around.end(), left) - around.begin());
        for (std::size_t i = 0; i < around.size(); ++i) {
          const int g = around[(at + i) % around.size()];
          if (index_of(g) < static_cast<int>(faces.size())) continue;
          faces.push_back(g);
          start.push_back(corner_of(face(t, static_cast<std::size_t>(g)), x));
        }
      }
    }
  // Corner items (face j, corner i from its start), joined across the edges two support faces share.
  std::vector<int> offset{0};
  for (const int g : faces)
    offset.push_back(offset.back() + static_cast<int>(face(t, static_cast<std::size_t>(g)).size()));
  std::vector<int> parent(static_cast<std::size_t>(offset.back()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[static_cast<std::size_t>(x)] != x)
      x = parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  };
  const auto unite = [&](int a, int b) { parent[static_cast<std::size_t>(find(a))] = find(b); };
  // Item of face j's corner at mesh corner index `c` (the face's own numbering).
  const auto item = [&](std::size_t j, int c) {
    const auto size = offset[j + 1] - offset[j];
    return offset[j] + (c - start[j] + size) % size;
  };
  for (std::size_t j = 0; j < faces.size(); ++j) {
    const auto g = static_cast<std::size_t>(faces[j]);
    const auto corners = face(t, g);
    const auto edges = face_edges(t, g);
    const auto size = static_cast<int>(corners.size());
    for (int c = 0; c < size; ++c) {
      const auto e = static_cast<std::size_t>(edges[static_cast<std::size_t>(c)]);
      const int h = t.edge_faces[e][0] == faces[j] ? t.edge_faces[e][1] : t.edge_faces[e][0];
      if (h < 0) continue;
      const auto jh = static_cast<std::size_t>(index_of(h));
      if (jh >= faces.size() || jh <= j) continue;
      const auto hc = face(t, static_cast<std::size_t>(h));
      const int x = corners[static_cast<std::size_t>(c)],
                y = corners[static_cast<std::size_t>((c + 1) % size)];
      unite(item(j, c), item(jh, corner_of(hc, x)));
      unite(item(j, (c + 1) % size), item(jh, corner_of(hc, y)));
    }
  }
  Configuration out;
  std::vector<int> slot(parent.size(), -1);
  std::string& key = out.key;
  put(key, static_cast<int>(faces.size()));
  for (std::size_t j = 0; j < faces.size(); ++j) {
    const auto corners = face(t, static_cast<std::size_t>(faces[j]));
    const auto size = static_cast<int>(corners.size());
    put(key, size);
    for (int i = 0; i < size; ++i) {
      int& s = slot[static_cast<std::size_t>(find(offset[j] + i))];
      if (s < 0) {
        s = static_cast<int>(out.vertices.size());
        out.vertices.push_back(corners[static_cast<std::size_t>((start[j] + i) % size)]);
      }
      out.mesh.face_vertices.push_back(s);
      put(key, s);
    }
    out.mesh.face_offsets.push_back(static_cast<int>(out.mesh.face_vertices.size()));
  }
  out.mesh.vertices = Points::Zero(static_cast<Eigen::Index>(out.vertices.size()), 3);
  // The tags the rules read: edges at the face's corners (boundary edges are sharp by the topology),
  // the corners' sharpness, holes; the boundary rule's effects are in the level's features already.
  MeshTags& tags = out.mesh.tags;
  tags.boundary = BoundaryRule::edge_only;
  tags.crease_method = options.crease_method;
  tags.triangles = options.triangles;
  std::vector<int> seen;
  for (std::size_t j = 0; j < faces.size(); ++j) {
    const auto g = static_cast<std::size_t>(faces[j]);
    const auto edges = face_edges(t, g);
    const auto size = static_cast<int>(edges.size());
    const auto base = static_cast<std::size_t>(offset[j]);
    for (int i = 0; i < size; ++i) {
      const int a = out.mesh.face_vertices[base + static_cast<std::size_t>(i)],
                b = out.mesh.face_vertices[base + static_cast<std::size_t>((i + 1) % size)];
      const int e = edges[static_cast<std::size_t>((start[j] + i) % size)];
      const auto ringed = [&](int local, int vertex) {
        return local < n || std::find(full.begin(), full.end(), vertex) != full.end();
      };
      if (!ringed(a, out.vertices[static_cast<std::size_t>(a)]) &&
          !ringed(b, out.vertices[static_cast<std::size_t>(b)]))
        continue;
      const double s = edge_sharpness(f, e);
      if (s <= 0 || is_boundary_edge(t, static_cast<std::size_t>(e)) ||
          std::find(seen.begin(), seen.end(), e) != seen.end())
        continue;
      seen.push_back(e);
      tags.creases.push_back({.a = a, .b = b, .sharpness = s});
      put(key, a), put(key, b), put(key, s);
    }
  }
  put(key, -1);
  for (int k = 0; k < n; ++k)
    if (const double s = vertex_sharpness(f, out.vertices[static_cast<std::size_t>(k)]); s > 0) {
      tags.corners.push_back({.vertex = k, .sharpness = s});
      put(key, k), put(key, s);
    }
  put(key, -1);
  for (std::size_t j = 0; j < faces.size(); ++j)
    if (is_hole(f, faces[j])) {
      tags.holes.push_back(static_cast<int>(j));
      put(key, static_cast<int>(j));
    }
  return out;
}

bool quad_scheme(MeshScheme scheme) {
  return scheme == MeshScheme::catmull_clark;
}

/// Where a child's parameters come from: (s, t) = A (u, v) + b on the parent's.
struct ChildMap {
  std::array<double, 4> A;  // row-major
  std::array<double, 2> b;
  [[nodiscard]] std::array<double, 2> operator()(double u, double v) const {
    return {A[0] * u + A[1] * v + b[0], A[2] * u + A[3] * v + b[1]};
  }
};

/// Quads: child k at corner k (corner (0, 0), (1, 0), (1, 1), (0, 1)), its corner 0 the corner's vertex
/// point, its corner 1 the edge point after it: the quarter turned by k. Triangles: child k at corner k
/// the same way (corners (0, 0), (1, 0), (0, 1)), child 3 the middle one with its corner 0 at (½, ½).
ChildMap child_map(bool quad, int k) {
  if (quad) {
    switch (k) {
      case 0:
        return {{2, 0, 0, 2}, {0, 0}};
      case 1:  // (s, t) = (v', 1 − u') with u' = 2u − 1, v' = 2v
        return {{0, 2, -2, 0}, {0, 2}};
      case 2:  // (1 − u', 1 − v'), u' = 2u − 1, v' = 2v − 1
        return {{-2, 0, 0, -2}, {2, 2}};
      default:  // (1 − v', u'), u' = 2u, v' = 2v − 1
        return {{0, -2, 2, 0}, {2, 0}};
    }
  }
  switch (k) {
    case 0:
      return {{2, 0, 0, 2}, {0, 0}};
    case 1:  // (v', 1 − u' − v'), u' = 2u − 1, v' = 2v
      return {{0, 2, -2, -2}, {0, 2}};
    case 2:  // (1 − u' − v', u'), u' = 2u, v' = 2v − 1
      return {{-2, -2, 2, 0}, {2, 0}};
    default:
      return {{-2, 0, 0, -2}, {1, 1}};
  }
}

/// The child holding (u, v) of a quad or triangle domain.
int child_at(bool quad, double u, double v) {
  if (quad) {
    const bool iu = u >= 0.5, iv = v >= 0.5;
    return iu ? (iv ? 2 : 1) : (iv ? 3 : 0);
  }
  if (u >= 0.5) return 1;
  if (v >= 0.5) return 2;
  return u + v < 0.5 ? 0 : 3;
}

/// The patch polynomial: bicubic (16 coefficients, index 4a + b for the a-th in u and b-th in v) or
/// quartic on the triangle (15, index tri(a, b) for u^a v^b). Fitted and restricted in the Bernstein
/// basis (well conditioned), evaluated per point in the monomial basis by Horner's scheme.
int basis_size(bool quad) {
  return quad ? 16 : 15;
}

/// Index of the quartic coefficient of u^a v^b (Bernstein: u^a v^b w^(4 − a − b), w = 1 − u − v).
constexpr int tri(int a, int b) {
  return a * (11 - a) / 2 + b;
}

/// The Bernstein polynomials (`monomials`: the monomials) at (u, v).
void basis(bool quad, bool monomials, double u, double v, double* b) {
  static constexpr std::array<double, 5> kFactorial{1, 1, 2, 6, 24};
  const int degree = quad ? 3 : 4;
  const auto power = [](double x, int k) { return std::pow(x, k); };
  for (int a = 0; a <= degree; ++a)
    for (int c = 0; c <= degree && (quad || a + c <= degree); ++c) {
      const int k = quad ? 4 * a + c : tri(a, c);
      if (monomials) {
        b[k] = power(u, a) * power(v, c);
      } else if (quad) {
        const auto cubic = [&](double t, int i) {
          return kFactorial[3] /
                 (kFactorial[static_cast<std::size_t>(i)] * kFactorial[static_cast<std::size_t>(3 - i)]) *
                 power(t, i) * power(1 - t, 3 - i);
        };
        b[k] = cubic(u, a) * cubic(v, c);
      } else {
        const int r = 4 - a - c;
        b[k] = kFactorial[4] /
               (kFactorial[static_cast<std::size_t>(a)] * kFactorial[static_cast<std::size_t>(c)] *
                kFactorial[static_cast<std::size_t>(r)]) *
               power(u, a) * power(v, c) * power(1 - u - v, r);
      }
    }
}

/// Value and partials of a patch from its monomial rows (`coefficients`, basis_size rows of d), by
/// Horner's scheme in v, then in u, one coordinate at a time, the partials taken to the face's (u, v) by J.
template <bool Quad>
void patch_sums(const double* coefficients, Eigen::Index d, double u, double v,
                const std::array<double, 4>& J, double* value, double* du, double* dv) {
  constexpr int kDegree = Quad ? 3 : 4;
  for (Eigen::Index k = 0; k < d; ++k) {
    double x = 0, xu = 0, xv = 0;
    for (int a = kDegree; a >= 0; --a) {  // q_a(v) = Σ_b c_ab v^b and q_a'(v), then one Horner step in u
      const int top = Quad ? 3 : kDegree - a;
      const double* c = coefficients + static_cast<Eigen::Index>(Quad ? 4 * a : tri(a, 0)) * d + k;
      double q = c[top * d], r = 0;
      for (int b = top - 1; b >= 0; --b) {
        r = r * v + q;
        q = q * v + c[b * d];
      }
      xu = xu * u + x;
      x = x * u + q;
      xv = xv * u + r;
    }
    value[k] = x;  // ∂/∂u = ∂s/∂u ∂/∂s + ∂t/∂u ∂/∂t, J = ∂(s, t)/∂(u, v)
    du[k] = J[0] * xu + J[2] * xv;
    dv[k] = J[1] * xu + J[3] * xv;
  }
}

/// 3-D data stored 4 columns a row (the fourth 0): a row of coefficients is two pairs of doubles (GCC/Clang
/// vector extensions: an SSE2 register each), so the three coordinates' chains run together.
using Pair = double __attribute__((vector_size(16)));
struct Row4 {
  Pair a, b;
};
inline Row4 load4(const double* p) {
  Row4 out;
  std::memcpy(&out, p, sizeof out);
  return out;
}
inline Row4 fma4(const Row4& x, double s, const Row4& y) {
  return {x.a * s + y.a, x.b * s + y.b};
}

/// Horner's steps in u for rows A, A − 1, …, 0 of the coefficients, each row's q_a(v) = Σ_b c_ab v^b and
/// q_a'(v) of fixed length (compile-time recursion: unrolled and inlined, the sums kept in registers).
template <bool Quad, int A>
inline void horner_rows(const double* coefficients, double u, double v, Row4& x, Row4& xu, Row4& xv) {
  constexpr std::ptrdiff_t kTop = Quad ? 3 : 4 - A, kRow = Quad ? 4 * A : tri(A, 0);
  const double* c = coefficients + 4 * kRow;
  Row4 q = load4(c + 4 * kTop), r{};
  for (std::ptrdiff_t b = kTop - 1; b >= 0; --b) {
    r = fma4(r, v, q);
    q = fma4(q, v, load4(c + 4 * b));
  }
  xu = fma4(xu, u, x);
  x = fma4(x, u, q);
  xv = fma4(xv, u, r);
  if constexpr (A > 0) horner_rows<Quad, A - 1>(coefficients, u, v, x, xu, xv);
}

/// patch_sums for 3-D data stored 4 columns a row.
template <bool Quad>
void patch_sums_3d(const double* coefficients, double u, double v, const std::array<double, 4>& J,
                   double* value, double* du, double* dv) {
  Row4 x{}, xu{}, xv{};
  horner_rows<Quad, Quad ? 3 : 4>(coefficients, u, v, x, xu, xv);
  const Row4 pu = fma4(xu, J[0], Row4{xv.a * J[2], xv.b * J[2]}),  // J = ∂(s, t)/∂(u, v)
      pv = fma4(xu, J[1], Row4{xv.a * J[3], xv.b * J[3]});
  value[0] = x.a[0], value[1] = x.a[1], value[2] = x.b[0];
  du[0] = pu.a[0], du[1] = pu.a[1], du[2] = pu.b[0];
  dv[0] = pv.a[0], dv[1] = pv.a[1], dv[2] = pv.b[0];
}

/// The points where the polynomial is fitted: (a, b)/4, a, b ∈ {0, 1, 3, 4} on quads (a tensor grid),
/// a + b ≤ 4 on triangles (the principal lattice).
std::vector<std::array<int, 2>> fit_points(bool quad) {
  std::vector<std::array<int, 2>> out;
  if (quad) {
    for (const int a : {0, 1, 3, 4})
      for (const int b : {0, 1, 3, 4}) out.push_back({a, b});
  } else {
    for (int a = 0; a <= 4; ++a)
      for (int b = 0; a + b <= 4; ++b) out.push_back({a, b});
  }
  return out;
}

}  // namespace

/// The tangent plane at a corner that never becomes a polynomial patch, from the spectrum of the
/// corner's sector (the faces around it between sharp edges, the face's among them): its two
/// subdominant eigenvalues λ_i, their left eigenvectors l_i on the state's slots and the right
/// eigenvectors' entries r_i(e) at the face's two edge neighbours e (corners 1 and n − 1),
/// biorthonormal (l_i · r_j = δ_ij). The part of edge e in the tangent plane at level k,
/// Σ_i r_i(e) (l_i · net_k), shrinks by λ_i a level: Σ_i r_i(e) λ_i^−k (l_i · net_k) is the same at
/// every level (the vertex's, not the face's), and at a regular vertex it is the parametric derivative
/// along e.
struct CornerTangents {
  bool known = false;
  std::string refused;  // why the sector has no tangent plane its spectrum proves (then nothing else)
  std::array<double, 2> lambda{};
  Eigen::MatrixXd left;   // 2 × slots
  Eigen::Matrix2d along;  // row: the edge (s, then t); column i: r_i there
};

namespace detail {

/// The automaton of configurations, built lazily and cached by key.
class SurfaceStates {
 public:
  using Step = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  struct State {
    Mesh mesh;
    int sides = 0;
    bool expanded = false;
    std::vector<int> child;
    std::vector<Step> to_child;  // child's slots × this state's (sparse: a vertex of valence
                                 // n reads 2n + 1 slots of up to 2n + 8)
    std::vector<int> quarter;    // quarters(): a quad's children not turned
    std::vector<Step> to_quarter;
    Eigen::RowVectorXd corner;  // the limit at corner 0 on the slots (empty until asked)
    int polynomial = -1;        // unknown, 0, 1
    Eigen::MatrixXd bezier;     // basis_size × slots when polynomial: Bernstein
    Eigen::MatrixXd monomials;  // the same in the monomial basis
    CornerTangents tangents;    // at corner 0 of a state that is its own child there (once asked)
  };

  explicit SurfaceStates(MeshScheme scheme) : scheme_(scheme), quad_(quad_scheme(scheme)) {
    const auto points = fit_points(quad_);
    const int N = basis_size(quad_);
    Eigen::MatrixXd colloc(N, N);
    Eigen::MatrixXd monomials(N, N);
    std::vector<double> b(static_cast<std::size_t>(N));
    for (std::size_t p = 0; p < points.size(); ++p) {
      basis(quad_, false, points[p][0] / 4.0, points[p][1] / 4.0, b.data());
      for (int k = 0; k < N; ++k) colloc(static_cast<Eigen::Index>(p), k) = b[static_cast<std::size_t>(k)];
      basis(quad_, true, points[p][0] / 4.0, points[p][1] / 4.0, b.data());
      for (int k = 0; k < N; ++k) monomials(static_cast<Eigen::Index>(p), k) = b[static_cast<std::size_t>(k)];
    }
    solve_ = colloc.fullPivLu().inverse();
    // Bernstein to monomial coefficients: an integer matrix (binomials with signs), rounded exact.
    to_monomials_ = monomials.fullPivLu().solve(colloc).array().round().matrix();
    // Restriction to child k: the child's coefficients from the parent's, through the values at the
    // fit points mapped into the parent (the inverse of child_map).
    const int children = 4;
    for (int k = 0; k < children; ++k) {
      const ChildMap m = child_map(quad_, k);
      const double det = m.A[0] * m.A[3] - m.A[1] * m.A[2];
      Eigen::MatrixXd values(N, N);
      for (std::size_t p = 0; p < points.size(); ++p) {
        const double s = points[p][0] / 4.0 - m.b[0], t = points[p][1] / 4.0 - m.b[1];
        const double u = (m.A[3] * s - m.A[1] * t) / det, v = (-m.A[2] * s + m.A[0] * t) / det;
        basis(quad_, false, u, v, b.data());
        for (int q = 0; q < N; ++q) values(static_cast<Eigen::Index>(p), q) = b[static_cast<std::size_t>(q)];
      }
      restrict_[static_cast<std::size_t>(k)] = solve_ * values;
    }
  }

  [[nodiscard]] bool quad() const { return quad_; }

  /// The Bernstein coefficients of the polynomial with the given values at the fit points (rows).
  [[nodiscard]] Eigen::MatrixXd bezier_of(const Eigen::MatrixXd& values) const { return solve_ * values; }

  int state(Configuration&& c) {
    const auto [it, fresh] = index_.try_emplace(std::move(c.key), static_cast<int>(states_.size()));
    if (fresh) {
      State s;
      s.sides = static_cast<int>(face(c.mesh, 0).size());
      s.mesh = std::move(c.mesh);
      states_.push_back(std::move(s));
    }
    return it->second;
  }

  const State& at(int s) const { return states_[static_cast<std::size_t>(s)]; }

  /// The state's children, made on first use.
  const State& expand(int s) {
    if (states_[static_cast<std::size_t>(s)].expanded) return at(s);
    auto [child, to_child] = children(s, false);
    State& x = states_[static_cast<std::size_t>(s)];
    x.child = std::move(child);
    x.to_child = std::move(to_child);
    x.expanded = true;
    return x;
  }

  /// A state's quarters not turned, the layout of the whole-surface automaton. Quads (ifs::patch_meshes):
  /// k = 0 … 3 at corner k ((0, 0), (1, 0), (1, 1), (0, 1)), each child face started at its corner at the
  /// quarter's (0, 0), so that its (s, t) is 2 (u, v) minus the quarter's offset. Triangles (the layout of
  /// loop_patch and ifs::triangle_bcifs): k = 0, 1, 2 the corner triangles at (0, 0), (½, 0), (0, ½), their
  /// (s, t) = 2 (u, v) minus that offset; k = 3 the middle one turned by a half turn, (1 − 2u, 1 − 2v).
  /// Made on first use.
  const State& quarters(int s) {
    if (!states_[static_cast<std::size_t>(s)].quarter.empty()) return at(s);
    auto [child, to_child] = children(s, true);
    State& x = states_[static_cast<std::size_t>(s)];
    x.quarter = std::move(child);
    x.to_quarter = std::move(to_child);
    return x;
  }

  /// The tangent plane at corner 0 of a state that is its own child there (CornerTangents).
  const CornerTangents& tangents(int s) {
    auto& x = states_[static_cast<std::size_t>(s)];
    if (!x.tangents.known) {
      CornerTangents out = corner_tangents(s);
      out.known = true;
      states_[static_cast<std::size_t>(s)].tangents = std::move(out);
    }
    return states_[static_cast<std::size_t>(s)].tangents;
  }

  /// The limit at the state's corner 0 as weights on its slots: limit_stencils on the corner's
  /// one-ring cut out with its tags.
  const Eigen::RowVectorXd& corner(int s) {
    if (states_[static_cast<std::size_t>(s)].corner.size() == 0) {
      Eigen::RowVectorXd weights = ring_limit(s);
      states_[static_cast<std::size_t>(s)].corner = std::move(weights);
    }
    return states_[static_cast<std::size_t>(s)].corner;
  }

 private:
  /// The state's children after one step of the production refiner run on its configuration: Catmull–Clark's
  /// face 0's corner k becomes child face k from the corner's vertex point (`unturned`: from its corner at
  /// the quarter's (0, 0), (4 − k) mod 4); Loop's corner triangles (from the corner; `unturned`: from their
  /// first corner as split_triangles makes them, the one nearest the parent's (0, 0)) then the middle one
  /// (from the edge point of edge 1 → 2).
  std::pair<std::vector<int>, std::vector<Step>> children(int s, bool unturned) {
    const MeshRefinement r = refine_topology(states_[static_cast<std::size_t>(s)].mesh, scheme_, 1);
    const Stencils& step = r.steps[0];
    const int slots = static_cast<int>(states_[static_cast<std::size_t>(s)].mesh.vertices.rows());
    const int sides = states_[static_cast<std::size_t>(s)].sides;
    std::vector<int> child;
    std::vector<Step> to_child;
    const int count = quad_ ? sides : 4;
    for (int k = 0; k < count; ++k) {
      const int first = quad_ ? (unturned ? (4 - k) % 4 : 0) : (k == 3 ? 1 : (unturned ? 0 : k));
      Configuration c = configuration(r.levels[1], r.features[1], r.tags[1], k, first);
      std::vector<Eigen::Triplet<double>> entries;
      for (std::size_t i = 0; i < c.vertices.size(); ++i) {
        const auto w = static_cast<std::size_t>(c.vertices[i]);
        for (int q = step.offsets[w]; q < step.offsets[w + 1]; ++q)
          entries.emplace_back(static_cast<int>(i), step.columns[static_cast<std::size_t>(q)],
                               step.weights[static_cast<std::size_t>(q)]);
      }
      Step M(static_cast<Eigen::Index>(c.vertices.size()), slots);
      M.setFromTriplets(entries.begin(), entries.end());
      to_child.push_back(std::move(M));
      child.push_back(state(std::move(c)));
    }
    return {std::move(child), std::move(to_child)};
  }

  /// The tangent plane of the corner's sector (detail::sector_plane: the faces around it between sharp
  /// edges, the face's among them) and the face's two edges' parts in it; refused where the sector has no
  /// plane its spectrum proves, and where the face's two edges have parallel parts in the plane.
  CornerTangents corner_tangents(int s) {
    const State& x = expand(s);
    CornerTangents out;
    const MeshTopology t = build_topology(x.mesh, "limit surface state");
    const auto faces = vertex_faces(t, 0);
    const int position = static_cast<int>(std::find(faces.begin(), faces.end(), 0) - faces.begin());
    const std::vector<Sector> sectors = sectors_around(t, x.mesh.tags);
    const Sector& sector = *std::find_if(sectors.begin(), sectors.end(), [&](const Sector& c) {
      return std::find(c.faces.begin(), c.faces.end(), position) != c.faces.end();
    });
    const SectorPlane plane = sector_plane(Eigen::MatrixXd(x.to_child[0]), t, sector);
    if (!plane.refused.empty()) {
      out.refused = plane.refused;
      return out;
    }
    const auto n = static_cast<int>(face(t, 0).size());
    out.along.row(0) = plane.right.row(1);
    out.along.row(1) = plane.right.row(n - 1);
    constexpr double kTight = 1e-9;
    if (std::abs(out.along.determinant()) <= kTight * out.along.row(0).norm() * out.along.row(1).norm()) {
      out.refused = "the face's two edges have parallel parts in its tangent plane";
      return out;
    }
    out.lambda = plane.lambda;
    out.left = plane.left;
    return out;
  }

  /// The limit at a state's corner 0 from the one-ring there.
  Eigen::RowVectorXd ring_limit(int s) {
    const State& x = at(s);
    const MeshTopology t = build_topology(x.mesh, "limit surface state");
    Mesh ring;
    std::vector<int> local(static_cast<std::size_t>(t.vertex_count), -1), global;
    const auto slot = [&](int v) {
      int& l = local[static_cast<std::size_t>(v)];
      if (l < 0) {
        l = static_cast<int>(global.size());
        global.push_back(v);
      }
      return l;
    };
    slot(0);
    for (const int g : vertex_faces(t, 0)) {
      for (const int v : face(t, static_cast<std::size_t>(g))) ring.face_vertices.push_back(slot(v));
      ring.face_offsets.push_back(static_cast<int>(ring.face_vertices.size()));
    }
    ring.vertices = Points::Zero(static_cast<Eigen::Index>(global.size()), 3);
    ring.tags.boundary = BoundaryRule::edge_only;
    ring.tags.crease_method = x.mesh.tags.crease_method;
    ring.tags.triangles = x.mesh.tags.triangles;
    for (const EdgeSharpness& c : x.mesh.tags.creases)
      if (c.a == 0 || c.b == 0)
        ring.tags.creases.push_back({.a = slot(c.a), .b = slot(c.b), .sharpness = c.sharpness});
    for (const VertexSharpness& c : x.mesh.tags.corners)
      if (c.vertex == 0) ring.tags.corners.push_back({.vertex = 0, .sharpness = c.sharpness});
    const LimitStencils st = limit_stencils(refine_topology(ring, scheme_, 0));
    const LimitMask& m = st.masks[static_cast<std::size_t>(st.mask_of[0])];
    Eigen::RowVectorXd out = Eigen::RowVectorXd::Zero(x.mesh.vertices.rows());
    for (int q = st.offsets[0]; q < st.offsets[1]; ++q)
      out(global[static_cast<std::size_t>(st.columns[static_cast<std::size_t>(q)])]) +=
          m.position[static_cast<std::size_t>(q - st.offsets[0])];
    return out;
  }

 public:
  /// Whether the state's patch is a polynomial (proved on the states it reaches, see the top).
  bool polynomial(int s) {
    if (states_[static_cast<std::size_t>(s)].polynomial >= 0)
      return states_[static_cast<std::size_t>(s)].polynomial == 1;
    std::vector<int> closure{s};
    std::map<int, Eigen::MatrixXd> fitted;
    bool ok = true;
    for (std::size_t i = 0; ok && i < closure.size(); ++i) {
      const int x = closure[i];
      if (!fit(x, fitted)) {
        ok = false;
        break;
      }
      const State& X = expand(x);
      const std::vector<int> kids = X.child;
      for (std::size_t k = 0; k < kids.size(); ++k) {
        const int y = kids[k];
        if (at(y).polynomial == 0 || !fit(y, fitted)) {
          ok = false;
          break;
        }
        const Eigen::MatrixXd lhs = fitted.at(y) * at(x).to_child[k];
        const Eigen::MatrixXd rhs = restrict_[k] * fitted.at(x);
        if ((lhs - rhs).cwiseAbs().maxCoeff() > 1e-11 * std::max(1.0, rhs.cwiseAbs().maxCoeff())) {
          ok = false;
          break;
        }
        if (std::find(closure.begin(), closure.end(), y) == closure.end()) closure.push_back(y);
      }
    }
    if (!ok) {
      states_[static_cast<std::size_t>(s)].polynomial = 0;
      return false;
    }
    for (const int x : closure) {
      states_[static_cast<std::size_t>(x)].polynomial = 1;
      states_[static_cast<std::size_t>(x)].bezier = fitted.at(x);
      states_[static_cast<std::size_t>(x)].monomials = to_monomials_ * fitted.at(x);
    }
    return true;
  }

 private:
  /// The candidate polynomial of a state (false when it cannot be one: wrong face, sharpness left).
  bool fit(int s, std::map<int, Eigen::MatrixXd>& fitted) {
    if (fitted.count(s) != 0) return true;
    const State& x = at(s);
    if (x.polynomial == 1) {
      fitted[s] = x.bezier;
      return true;
    }
    if (x.sides != (quad_ ? 4 : 3)) return false;
    for (const EdgeSharpness& c : x.mesh.tags.creases)
      if (c.sharpness < kInfiniteSharpness) return false;
    for (const VertexSharpness& c : x.mesh.tags.corners)
      if (c.sharpness < kInfiniteSharpness) return false;
    const auto points = fit_points(quad_);
    Eigen::MatrixXd values(static_cast<Eigen::Index>(points.size()), x.mesh.vertices.rows());
    for (std::size_t p = 0; p < points.size(); ++p)
      values.row(static_cast<Eigen::Index>(p)) = functional(s, points[p][0] / 4.0, points[p][1] / 4.0);
    fitted[s] = solve_ * values;
    return true;
  }

  /// The limit at a dyadic point of a state's domain as weights on its slots.
  Eigen::RowVectorXd functional(int s, double u, double v) {
    if (u == 0 && v == 0) return corner(s);
    const int k = child_at(quad_, u, v);
    const auto [a, b] = child_map(quad_, k)(u, v);
    const State& x = expand(s);
    const int y = x.child[static_cast<std::size_t>(k)];
    const Step M = x.to_child[static_cast<std::size_t>(k)];
    return functional(y, a, b) * M;
  }

  MeshScheme scheme_;
  bool quad_;
  std::map<std::string, int> index_;
  std::deque<State> states_;
  Eigen::MatrixXd solve_;
  std::array<Eigen::MatrixXd, 4> restrict_;
  Eigen::MatrixXd to_monomials_;
};

}  // namespace detail

namespace {

/// OpenSubdiv's parametrisation of an n-gon under Catmull–Clark (Bfr::Parameterization, quad
/// sub-faces): sub-face i, the quad of corner i after one step, is the square [x, x + ½] × [y, y + ½],
/// x = i mod D, y = i div D, D = 2 for triangles, 3 for 5 … 9 corners, 1 + ⌊√(n − 1)⌋ from 10; its own
/// (s, t) = 2 (u − x, v − y), s towards the edge after corner i.
int tiles(int n) {
  return n < 10 ? (n > 4 ? 3 : 2) : 1 + static_cast<int>(std::sqrt(static_cast<double>(n - 1)));
}

/// Whether (u, v) lies in the domain of a face with n corners: the triangle (u + v may pass 1 by a
/// rounding of the caller's sum), the unit square, an n-gon's sub-faces.
bool inside(bool quad, int n, double u, double v) {
  if (!(u >= 0 && v >= 0)) return false;  // NaN too
  if (!quad) return u + v <= 1 + 1e-12;
  if (n == 4) return u <= 1 && v <= 1;
  const int D = tiles(n);
  if (!(u < D + 1.0 && v < n)) return false;
  const int x = std::min(static_cast<int>(u + 0.25), D - 1), y = static_cast<int>(v + 0.25);
  return y * D + x < n && u >= x && u - x <= 0.5 && v >= y && v - y <= 0.5;
}

/// Why point p is refused: no such face, not numbers, a hole, outside the face's domain (n corners).
[[noreturn]] void refuse_point(MeshScheme scheme, std::size_t p, const FacePoint& q, int F, bool hole,
                               int n) {
  const std::string where = std::string(scheme_name(scheme)) + " limit: point " + std::to_string(p) +
                            " (face " + std::to_string(q.face) + ")";
  if (q.face < 0 || q.face >= F)
    throw InvalidInput(where + ": no such face; the mesh has " + std::to_string(F));
  if (!std::isfinite(q.u) || !std::isfinite(q.v))
    throw InvalidInput(where + ": (u, v) is not a pair of finite numbers");
  if (hole)
    throw InvalidInput(
        where +
        ": the face is a hole (tagged, or next to the boundary under the boundary rule 'none'): "
        "it has no limit surface");
  std::string domain = "the triangle u, v ≥ 0, u + v ≤ 1";
  if (quad_scheme(scheme) && n == 4) {
    domain = "[0, 1]²";
  } else if (quad_scheme(scheme)) {
    const std::string D = std::to_string(tiles(n));
    domain = "the " + std::to_string(n) + "-gon's sub-faces [i mod " + D + ", + ½] × [i div " + D +
             ", + ½] (OpenSubdiv's parametrisation)";
  }
  throw InvalidInput(where + ": (u, v) = (" + number_text(q.u, 6) + ", " + number_text(q.v, 6) +
                     ") is outside " + domain);
}

/// Per face, the tree of nets met going down (built once per node, so that a point costs its
/// descent and one polynomial evaluation).
struct Node {
  int state = 0;
  Points net;         // the state's slots
  Points polynomial;  // its monomial coefficients when the state is a polynomial (3-D: padded to 4 columns)
  std::vector<int> kids;
};

}  // namespace

SurfaceSample evaluate_limit_surface(const Mesh& mesh, MeshScheme scheme, std::span<const FacePoint> at,
                                     const SurfaceOptions& options) {
  SurfaceSample out;
  evaluate_limit_surface(mesh, scheme, at, out, options);
  return out;
}

void evaluate_limit_surface(const Mesh& mesh, MeshScheme scheme, std::span<const FacePoint> at,
                            SurfaceSample& out, const SurfaceOptions& options) {
  if (scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
    throw InvalidInput("limit surface: " + std::string(scheme_name(scheme)) +
                       " is not built (catmull-clark and loop are)");
  const std::string who = std::string(scheme_name(scheme)) + " limit surface";
  if (mesh.tags.rules == RuleSet::blz)
    throw InvalidInput(who +
                       ": the rule set 'blz' is not built for the limit surface (its patches are "
                       "OpenSubdiv's rules'); subdivide with --rules blz instead");
  // Topology and tags only: the vertex data may have any number of columns.
  Mesh shape;
  shape.vertices = Points::Zero(mesh.vertices.rows(), 3);
  shape.face_offsets = mesh.face_offsets;
  shape.face_vertices = mesh.face_vertices;
  shape.tags = mesh.tags;
  const MeshRefinement r = refine_topology(shape, scheme, 0);
  const MeshTopology& t = r.levels[0];
  const LevelFeatures& features = r.features[0];
  const bool quad = quad_scheme(scheme);
  const auto F = static_cast<int>(face_count(t));
  // The points first: a bad one is named before any work.
  for (std::size_t p = 0; p < at.size(); ++p) {
    const FacePoint& q = at[p];
    const bool known = q.face >= 0 && q.face < F;
    const int n = known ? static_cast<int>(face(t, static_cast<std::size_t>(q.face)).size()) : 0;
    if (known && !is_hole(features, q.face) && inside(quad, n, q.u, q.v)) continue;
    refuse_point(scheme, p, q, F, known && is_hole(features, q.face), n);
  }
  const Eigen::Index d = mesh.vertices.cols();
  detail::SurfaceStates states(scheme);
  std::vector<std::vector<Node>> trees(static_cast<std::size_t>(F));
  const auto count = static_cast<Eigen::Index>(at.size());
  const bool partials = options.partials || options.normals;
  if (options.normals && d != 3)
    throw InvalidInput(who + ": normals need 3-D vertices, not " + std::to_string(d) + "-D");
  for (Points* P : {&out.positions, &out.du, &out.dv, &out.normals}) {
    if ((!partials && P != &out.positions) || (!options.normals && P == &out.normals)) {
      P->resize(0, d);
      continue;
    }
    if (P->rows() == count && P->cols() == d) continue;  // storage reused: no page faults on repeated calls
    P->resize(count, d);
    advise_huge_pages(P->data(), static_cast<std::size_t>(P->size()) * sizeof(double));
  }
  std::vector<int> sides(static_cast<std::size_t>(F));
  for (std::size_t f = 0; f < sides.size(); ++f) sides[f] = static_cast<int>(face(t, f).size());
  // A leaf's monomial coefficients; 3-D data padded to 4 columns for patch_sums_3d.
  const auto leaf = [&](const Eigen::MatrixXd& monomials, const Points& net) {
    if (d != 3) return Points(monomials * net);
    Points padded = Points::Zero(monomials.rows(), 4);
    padded.leftCols(3) = monomials * net;
    return padded;
  };
  const auto kid = [&](std::vector<Node>& tree, std::size_t node, int k) {
    if (tree[node].kids.empty()) tree[node].kids.assign(states.expand(tree[node].state).child.size(), -1);
    if (const int existing = tree[node].kids[static_cast<std::size_t>(k)]; existing >= 0) return existing;
    const auto& x = states.expand(tree[node].state);
    Node child;
    child.state = x.child[static_cast<std::size_t>(k)];
    child.net = x.to_child[static_cast<std::size_t>(k)] * tree[node].net;
    if (states.polynomial(child.state)) child.polynomial = leaf(states.at(child.state).monomials, child.net);
    tree.push_back(std::move(child));
    tree[node].kids[static_cast<std::size_t>(k)] = static_cast<int>(tree.size()) - 1;
    return static_cast<int>(tree.size()) - 1;
  };
  std::vector<double> scratch(2 * static_cast<std::size_t>(d));  // partials not asked for
  for (Eigen::Index p = 0; p < count; ++p) {
    const FacePoint& q = at[static_cast<std::size_t>(p)];
    std::vector<Node>& tree = trees[static_cast<std::size_t>(q.face)];
    if (tree.empty()) {
      Node root;
      Configuration c = configuration(t, features, r.tags[0], q.face, 0);
      root.net.resize(static_cast<Eigen::Index>(c.vertices.size()), d);
      for (std::size_t i = 0; i < c.vertices.size(); ++i)
        root.net.row(static_cast<Eigen::Index>(i)) = mesh.vertices.row(c.vertices[i]);
      root.state = states.state(std::move(c));
      if (states.polynomial(root.state)) root.polynomial = leaf(states.at(root.state).monomials, root.net);
      tree.push_back(std::move(root));
    }
    double u = q.u, v = q.v;
    std::array<double, 4> J{1, 0, 0, 1};  // ∂(s, t)/∂(u, v), row-major
    int node = 0;
    const int n = sides[static_cast<std::size_t>(q.face)];
    if (quad && n != 4) {  // the sub-face holding (u, v), in its own (s, t)
      const int D = tiles(n);
      const int x = std::min(static_cast<int>(u + 0.25), D - 1), y = static_cast<int>(v + 0.25);
      node = kid(tree, 0, y * D + x);
      u = 2 * (u - x), v = 2 * (v - y);
      J = {2, 0, 0, 2};
    }
    double* value = out.positions.row(p).data();
    double* du = partials ? out.du.row(p).data() : scratch.data();
    double* dv = partials ? out.dv.row(p).data() : scratch.data() + d;
    for (int depth = 0;; ++depth) {
      const Node& here = tree[static_cast<std::size_t>(node)];
      if (here.polynomial.size() > 0) {
        const double* c = here.polynomial.data();
        if (d == 3)
          quad ? patch_sums_3d<true>(c, u, v, J, value, du, dv)
               : patch_sums_3d<false>(c, u, v, J, value, du, dv);
        else
          quad ? patch_sums<true>(c, d, u, v, J, value, du, dv)
               : patch_sums<false>(c, d, u, v, J, value, du, dv);
        break;
      }
      if (depth > 64)
        throw std::logic_error(who + ": face " + std::to_string(q.face) +
                               ": no polynomial patch after 64 levels");
      // At the corner: down the corner's children while they change (sharpness being spent, other
      // corners left behind); once the corner's child is its own state, the corner never becomes a
      // polynomial patch — its limit point, and as partials the parts of the face's edges in the
      // tangent plane (CornerTangents) taken to the face's (u, v) by J's turn.
      if (u == 0 && v == 0 && states.expand(here.state).child[0] == here.state) {
        if (!partials) {
          out.positions.row(p) = states.corner(here.state) * here.net;
          break;
        }
        const CornerTangents& tangent = states.tangents(here.state);
        if (!tangent.refused.empty())
          throw InvalidInput(who + ": point " + std::to_string(p) + " (face " + std::to_string(q.face) +
                             ") at (" + number_text(q.u, 6) + ", " + number_text(q.v, 6) +
                             "): the vertex there has no tangent plane its spectrum proves (" +
                             tangent.refused + "): no partials");
        out.positions.row(p) = states.corner(here.state) * here.net;
        const double scale = std::sqrt(std::abs(J[0] * J[3] - J[1] * J[2]));  // 2^k, k levels down
        const double k = std::round(std::log2(scale));
        Eigen::MatrixXd parts = tangent.left * here.net;  // 2 × d
        for (int i = 0; i < 2; ++i) parts.row(i) *= std::pow(tangent.lambda[static_cast<std::size_t>(i)], -k);
        const Eigen::MatrixXd along = tangent.along * parts;  // the edges s, t
        out.du.row(p) = (J[0] * along.row(0) + J[2] * along.row(1)) / scale;
        out.dv.row(p) = (J[1] * along.row(0) + J[3] * along.row(1)) / scale;
        break;
      }
      const int k = child_at(quad, u, v);
      const ChildMap m = child_map(quad, k);
      const auto [s2, t2] = m(u, v);
      u = s2, v = t2;
      J = {m.A[0] * J[0] + m.A[1] * J[2], m.A[0] * J[1] + m.A[1] * J[3], m.A[2] * J[0] + m.A[3] * J[2],
           m.A[2] * J[1] + m.A[3] * J[3]};
      node = kid(tree, static_cast<std::size_t>(node), k);
    }
  }
  if (!options.normals) return;
  for (Eigen::Index p = 0; p < count; ++p) {
    const Eigen::Vector3d a = out.du.row(p).transpose(), b = out.dv.row(p).transpose();
    const Eigen::Vector3d n = a.cross(b);
    if (!(n.norm() > 1e-10 * a.norm() * b.norm())) {
      const FacePoint& q = at[static_cast<std::size_t>(p)];
      throw InvalidInput(
          who + ": point " + std::to_string(p) + " (face " + std::to_string(q.face) + ") at (" +
          number_text(q.u, 6) + ", " + number_text(q.v, 6) +
          "): du and dv are parallel there (the face's edges leave the point along one curve, a "
          "straight crease or boundary): no normal");
    }
    out.normals.row(p) = n.normalized().transpose();
  }
}

}  // namespace cifs::subdivision

namespace cifs::subdivision::detail {
namespace {

/// The class of corner v of a configuration (surface_states.hpp): "" where regular — R faces and no sharp
/// edge (R = 4 for quads, 6 for triangles), R/2 on a boundary, R/2 + R/2 about a crease — else class,
/// faces and, where sharp edges part the faces, the place of the configuration's face 0 among them.
std::string corner_class(const MeshTopology& t, const MeshTags& tags, int v, int R) {
  const auto edges = vertex_edges(t, static_cast<std::size_t>(v));
  const auto n = static_cast<int>(vertex_faces(t, static_cast<std::size_t>(v)).size());
  std::vector<int> sharp;  // positions of the sharp edges in vertex_edges
  double left = 0;         // the largest finite sharpness still to spend
  for (std::size_t j = 0; j < edges.size(); ++j) {
    const auto e = static_cast<std::size_t>(edges[j]);
    if (is_boundary_edge(t, e)) {
      sharp.push_back(static_cast<int>(j));
      continue;
    }
    const int w = other_vertex(t, e, v);
    for (const EdgeSharpness& c : tags.creases)
      if (((c.a == v && c.b == w) || (c.a == w && c.b == v)) && c.sharpness > 0) {
        sharp.push_back(static_cast<int>(j));
        if (c.sharpness < kInfiniteSharpness) left = std::max(left, c.sharpness);
      }
  }
  bool corner = false;
  for (const VertexSharpness& c : tags.corners)
    if (c.vertex == v && c.sharpness > 0) {
      corner = true;
      if (c.sharpness < kInfiniteSharpness) left = std::max(left, c.sharpness);
    }
  std::string out;
  if (corner || sharp.size() > 2)
    out = "C" + std::to_string(n);
  else if (sharp.empty())
    out = n == R ? "" : "E" + std::to_string(n);
  else if (sharp.size() == 1)
    out = "D" + std::to_string(n);
  else if (t.boundary_vertex[static_cast<std::size_t>(v)] != 0)
    out = n == R / 2 ? "" : "B" + std::to_string(n);
  else if (const int a = sharp[1] - sharp[0]; a != R / 2 || n - a != R / 2)
    out = "K" + std::to_string(a) + "," + std::to_string(n - a);
  // Sharp edges tell the faces apart: which one face 0 is, counted counter-clockwise from the first.
  if (!out.empty() && !sharp.empty() && n > 1) {
    const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
    const auto k = static_cast<int>(std::find(faces.begin(), faces.end(), 0) - faces.begin());
    out += ":" + std::to_string((k - sharp[0] + n) % n);
  }
  if (left > 0) out += "~" + number_text(left, 6);
  return out;
}

/// Faces around a regular interior vertex.
int regular_valence(MeshScheme scheme) {
  return quad_scheme(scheme) ? 4 : 6;
}

/// A state's name from its corners' classes (surface_states.hpp).
std::string state_name(const Mesh& configuration, MeshScheme scheme) {
  const MeshTopology t = build_topology(configuration, "limit surface state");
  const auto sides = static_cast<int>(face(t, 0).size());
  std::vector<std::string> classes(static_cast<std::size_t>(sides));
  for (int k = 0; k < sides; ++k)
    classes[static_cast<std::size_t>(k)] = corner_class(t, configuration.tags, k, regular_valence(scheme));
  if (std::all_of(classes.begin() + 1, classes.end(), [](const std::string& c) { return c.empty(); }) &&
      !classes[0].empty())
    return classes[0];
  std::string out = "[";
  for (std::size_t k = 0; k < classes.size(); ++k)
    out += (k > 0 ? "|" : "") + (classes[k].empty() ? "-" : classes[k]);
  return out + "]";
}

/// The uniform bicubic B-spline net of a bicubic polynomial from its Bernstein coefficients (both indexed
/// 4a + b, a along s): per direction P0 = 6b0 − 7b1 + 2b2, P1 = 2b1 − b2, P2 = 2b2 − b1, P3 = 6b3 + 2b1 −
/// 7b2, the inverse of the B-spline's Bézier points (P0 + 4P1 + P2)/6, (4P1 + 2P2)/6, … — integers, exact.
Eigen::MatrixXd bspline_from_bezier() {
  Eigen::Matrix4d B;
  B << 6, -7, 2, 0, 0, 2, -1, 0, 0, -1, 2, 0, 0, 2, -7, 6;
  return automata::kron(B, B);
}

/// The Bernstein coefficients (15 × 12) of the regular Loop patch on its net: its values at the fit points
/// found down the automaton's state `regular` (children C0, C1, C2, M at (2u, 2v), (2u − 1, 2v), (2u, 2v −
/// 1), (1 − 2u, 1 − 2v); at a corner the fixed point of that corner's child), fitted. The box splines are
/// independent on a triangle: 12 of the 15 quartics.
Eigen::MatrixXd box_spline_bezier(const automata::Automaton& a, automata::StateId regular,
                                  const SurfaceStates& states) {
  std::array<Eigen::RowVectorXd, 3> fixed;
  for (std::size_t c = 0; c < 3; ++c)
    fixed[c] = ifs::repeated_child_functionals(a, static_cast<int>(c))[regular];
  std::array<Eigen::MatrixXd, 4> child;
  std::size_t k = 0;
  for (auto [e, end] = out_edges(regular, a.graph); e != end; ++e) child.at(k++) = a.graph[*e].matrix;
  const auto value = [&](const auto& self, double u, double v) -> Eigen::RowVectorXd {
    if (u == 0 && v == 0) return fixed[0];
    if (u == 1) return fixed[1];
    if (v == 1) return fixed[2];
    if (u >= 0.5) return self(self, 2 * u - 1, 2 * v) * child[1];
    if (v >= 0.5) return self(self, 2 * u, 2 * v - 1) * child[2];
    if (u + v < 0.5) return self(self, 2 * u, 2 * v) * child[0];
    return self(self, 1 - 2 * u, 1 - 2 * v) * child[3];
  };
  const auto points = fit_points(false);
  Eigen::MatrixXd values(static_cast<Eigen::Index>(points.size()), child[0].cols());
  for (std::size_t p = 0; p < points.size(); ++p)
    values.row(static_cast<Eigen::Index>(p)) = value(value, points[p][0] / 4.0, points[p][1] / 4.0);
  return states.bezier_of(values);
}

}  // namespace

void add_feature_faces(const Mesh& mesh, MeshScheme scheme, automata::StateId regular,
                       SurfaceAutomaton& out) {
  const std::string who = std::string(scheme_name(scheme)) + " surface automaton";
  const bool quad = quad_scheme(scheme);
  const int sides = quad ? 4 : 3;
  Mesh shape;  // topology and tags only
  shape.vertices = Points::Zero(mesh.vertices.rows(), 3);
  shape.face_offsets = mesh.face_offsets;
  shape.face_vertices = mesh.face_vertices;
  shape.tags = mesh.tags;
  const MeshRefinement r = refine_topology(shape, scheme, 0);
  const MeshTopology& t = r.levels[0];
  const LevelFeatures& features = r.features[0];
  SurfaceStates states(scheme);
  automata::Graph& g = out.automaton.graph;
  // A polynomial patch as the regular state's net: Catmull–Clark's B-spline net of its Bernstein
  // coefficients, exactly; Loop's box-spline net, where the quartic is one of the box splines' (the
  // regular interior, boundary and crease patches: the net of phantom points) — proved here, to rounding:
  // the net's quartic must give back the state's. Else (none known) the state is descended like the others.
  Eigen::MatrixXd to_net, box;
  if (quad) {
    to_net = bspline_from_bezier();
  } else {
    box = box_spline_bezier(out.automaton, regular, states);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> solve(box);
    if (solve.rank() != box.cols()) throw std::logic_error(who + ": the box splines are not independent");
    to_net = solve.pseudoInverse();
  }
  const auto net_of = [&](int s) -> Eigen::MatrixXd {  // empty where the state is no regular patch
    if (!states.polynomial(s)) return {};
    const Eigen::MatrixXd& bezier = states.at(s).bezier;
    Eigen::MatrixXd net = to_net * bezier;
    if (!quad &&
        (box * net - bezier).cwiseAbs().maxCoeff() > 1e-11 * std::max(1.0, bezier.cwiseAbs().maxCoeff()))
      return {};
    return net;
  };
  std::map<int, automata::StateId> node;  // configuration → automaton state
  std::map<std::string, int> names;
  std::vector<int> todo;
  const auto enter = [&](int s) {
    if (const auto it = node.find(s); it != node.end()) return it->second;
    std::string name = state_name(states.at(s).mesh, scheme);
    if (const int seen = names[name]++; seen > 0) name += "#" + std::to_string(seen + 1);
    const automata::StateId id = add_vertex(
        automata::State{
            .size = static_cast<int>(states.at(s).mesh.vertices.rows()), .recurrent = false, .name = name},
        g);
    todo.push_back(s);
    return node.emplace(s, id).first->second;
  };
  const Eigen::Index d = mesh.vertices.cols();
  for (int f = 0; f < static_cast<int>(face_count(t)); ++f) {
    if (is_hole(features, f)) continue;
    const auto corners = face(t, static_cast<std::size_t>(f));
    if (static_cast<int>(corners.size()) != sides)
      throw InvalidInput(who + ": face " + std::to_string(f) + ": not a " +
                         (quad ? "quad (refine one level first)" : "triangle (loop runs on triangles)"));
    // A face whose patch is not a polynomial is turned so that its first irregular corner is at (0, 0): a
    // corner that never becomes regular is then mostly met at its states' corner 0.
    int first = 0;
    Configuration c = configuration(t, features, r.tags[0], f, 0);
    if (!states.polynomial(states.state(Configuration(c)))) {
      const MeshTopology local = build_topology(c.mesh, "limit surface state");
      while (first < sides && corner_class(local, c.mesh.tags, first, regular_valence(scheme)).empty())
        ++first;
      if (first % sides != 0) c = configuration(t, features, r.tags[0], f, first % sides);
      first %= sides;
    }
    Points rows(static_cast<Eigen::Index>(c.vertices.size()), d);
    for (std::size_t i = 0; i < c.vertices.size(); ++i)
      rows.row(static_cast<Eigen::Index>(i)) = mesh.vertices.row(c.vertices[i]);
    const int s = states.state(std::move(c));
    automata::StateId state = regular;
    if (const Eigen::MatrixXd net = net_of(s); net.size() > 0)
      rows = (net * rows).eval();
    else
      state = enter(s);
    out.automaton.initial.push_back(automata::Initial{.segment = f, .state = state});
    out.nets.push_back(std::move(rows));
    std::array<int, 4> at{-1, -1, -1, -1};
    for (int k = 0; k < sides; ++k)
      at[static_cast<std::size_t>(k)] = corners[static_cast<std::size_t>((first + k) % sides)];
    out.corners.push_back(at);
  }
  // Quarters in the automaton's layout: quads' child 2·iu + iv is the quarter at corner 0, 3, 1, 2;
  // triangles' children C0, C1, C2, M are the quarters in their order.
  const std::array<int, 4> place = quad ? std::array<int, 4>{0, 3, 1, 2} : std::array<int, 4>{0, 1, 2, 3};
  const std::array<const char*, 4> label = quad ? std::array<const char*, 4>{"GH", "GB", "DH", "DB"}
                                                : std::array<const char*, 4>{"C0", "C1", "C2", "M"};
  for (std::size_t next = 0; next < todo.size(); ++next) {  // breadth first: names numbered by depth
    const int s = todo[next];
    const automata::StateId from = node.at(s);
    for (std::size_t c = 0; c < 4; ++c) {
      const auto k = static_cast<std::size_t>(place[c]);
      const int y = states.quarters(s).quarter[k];
      const Eigen::MatrixXd M(states.at(s).to_quarter[k]);
      if (const Eigen::MatrixXd net = net_of(y); net.size() > 0)
        add_edge(from, regular, automata::Transition{label[c], net * M}, g);
      else
        add_edge(from, enter(y), automata::Transition{label[c], M}, g);
    }
  }
}

}  // namespace cifs::subdivision::detail
