// SPDX-License-Identifier: MIT
// cifs — C¹ at extraordinary vertices: Reif's characteristic map, its Jacobian bounded in
// Bernstein form and its winding (cifs/subdivision/mesh_analysis.hpp; docs/subdivision-surfaces.md).
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "local_mesh.hpp"

namespace cifs::subdivision {
namespace {

using detail::corner;
using detail::corner_index;
using detail::edge_between;
using Vec2 = Eigen::Matrix<long double, 2, 1>;

constexpr long double kPiL = std::numbers::pi_v<long double>;
constexpr int kMapDegree =
    4;  // patches from limit values: interpolated at the 5 × 5 or 15 dyadic points of two steps
constexpr int kMaxSplits = 8;            // de Casteljau splits of one patch's Jacobian before it is undecided
constexpr long double kMargin = 1e-12L;  // of the largest Jacobian coefficient: below it, no sign is claimed
/// The net is scaled to coordinates ≤ 1, so the Jacobian's coefficients are O(1) for a healthy map;
/// below this (double round-off of the net) no sign is claimed either.
constexpr long double kFloor = 1e-13L;

long double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

long double binomial(int n, int k) {
  long double r = 1;
  for (int i = 1; i <= k; ++i) r = r * static_cast<long double>(n - k + i) / static_cast<long double>(i);
  return r;
}

long double multinomial(int n, int i, int j) {
  return binomial(n, i) * binomial(n - i, j);
}

// ------------------------------------------------------------------------------------------------
// Bernstein polynomials. A tensor patch of degree d stores c[i (d + 1) + j], i along u, j along v,
// over the corners (0,0), (1,0), (1,1), (0,1); a triangular one stores c[tri(i, j)], i and j the
// exponents of corners 1 and 2 (corner 0's is d − i − j), over the corners (0,0), (1,0), (0,1).

/// Entry (i, j) of a row-major (d + 1) × (d + 1) array.
std::size_t flat(int i, int d, int j) {
  return static_cast<std::size_t>(i) * static_cast<std::size_t>(d + 1) + static_cast<std::size_t>(j);
}

int tri(int i, int j, int d) {
  // Rows by i: row i holds j = 0 … d − i.
  return i * (d + 1) - i * (i - 1) / 2 + j;
}

template <class T>
struct Bernstein {
  bool triangle = false;
  int degree = 0;
  std::vector<T> c;
  T& at(int i, int j) {
    return c[static_cast<std::size_t>(triangle ? tri(i, j, degree) : i * (degree + 1) + j)];
  }
  const T& at(int i, int j) const {
    return c[static_cast<std::size_t>(triangle ? tri(i, j, degree) : i * (degree + 1) + j)];
  }
};

template <class T>
Bernstein<T> make(bool triangle, int degree) {
  const int size = triangle ? (degree + 1) * (degree + 2) / 2 : (degree + 1) * (degree + 1);
  return Bernstein<T>{
      .triangle = triangle, .degree = degree, .c = std::vector<T>(static_cast<std::size_t>(size))};
}

/// The Jacobian det(∂u Φ, ∂v Φ) of a planar patch, in Bernstein form of degree 2d − 1 (tensor; the
/// same in u and v) or 2d − 2 (triangle, u and v along the edges from corner 0).
Bernstein<long double> jacobian(const Bernstein<Vec2>& p) {
  const int d = p.degree;
  const auto dl = static_cast<long double>(d);
  if (p.triangle) {
    Bernstein<long double> J = make<long double>(true, 2 * d - 2);
    for (int i = 0; i < d; ++i)
      for (int j = 0; i + j < d; ++j)
        for (int k = 0; k < d; ++k)
          for (int l = 0; k + l < d; ++l) {
            const Vec2 du = dl * (p.at(i + 1, j) - p.at(i, j)), dv = dl * (p.at(k, l + 1) - p.at(k, l));
            J.at(i + k, j + l) += multinomial(d - 1, i, j) * multinomial(d - 1, k, l) /
                                  multinomial(2 * d - 2, i + k, j + l) * cross(du, dv);
          }
    return J;
  }
  Bernstein<long double> J = make<long double>(false, 2 * d - 1);
  for (int i = 0; i < d; ++i)
    for (int j = 0; j <= d; ++j)
      for (int k = 0; k <= d; ++k)
        for (int l = 0; l < d; ++l) {
          const Vec2 du = dl * (p.at(i + 1, j) - p.at(i, j)), dv = dl * (p.at(k, l + 1) - p.at(k, l));
          J.at(i + k, j + l) += binomial(d - 1, i) * binomial(d, k) / binomial(2 * d - 1, i + k) *
                                binomial(d, j) * binomial(d - 1, l) / binomial(2 * d - 1, j + l) *
                                cross(du, dv);
        }
  return J;
}

/// The same polynomial over a sub-triangle (barycentric corners q0, q1, q2) or sub-square
/// ([u0, u1] × [v0, v1]): by the blossom, de Casteljau with q0 (d − i − j) times, q1 i times, q2 j times.
Bernstein<long double> sub_triangle(const Bernstein<long double>& p,
                                    const std::array<Eigen::Vector3d, 3>& q) {
  const int d = p.degree;
  Bernstein<long double> out = make<long double>(true, d);
  for (int i = 0; i <= d; ++i)
    for (int j = 0; i + j <= d; ++j) {
      Bernstein<long double> b = p;
      for (int step = 0; step < d; ++step) {
        const Eigen::Vector3d& x = step < i ? q[1] : step < i + j ? q[2] : q[0];
        Bernstein<long double> next = make<long double>(true, b.degree - 1);
        for (int a = 0; a < b.degree; ++a)
          for (int e = 0; a + e < b.degree; ++e)
            next.at(a, e) = static_cast<long double>(x[0]) * b.at(a, e) +
                            static_cast<long double>(x[1]) * b.at(a + 1, e) +
                            static_cast<long double>(x[2]) * b.at(a, e + 1);
        b = std::move(next);
      }
      out.at(i, j) = b.c.front();
    }
  return out;
}

/// Halves of a Bézier coefficient sequence by de Casteljau at ½.
template <class T>
std::array<std::vector<T>, 2> halves(std::vector<T> b) {
  const std::size_t n = b.size();
  std::vector<T> left(n), right(n);
  for (std::size_t k = 0; k < n; ++k) {
    left[k] = b.front();
    right[n - 1 - k] = b[n - 1 - k];
    for (std::size_t i = 0; i + 1 < n - k; ++i) b[i] = (b[i] + b[i + 1]) / 2;
  }
  return {left, right};
}

std::array<Bernstein<long double>, 4> split(const Bernstein<long double>& p) {
  if (p.triangle) {
    const Eigen::Vector3d A(1, 0, 0), B(0, 1, 0), C(0, 0, 1);
    const Eigen::Vector3d ab = (A + B) / 2, bc = (B + C) / 2, ca = (C + A) / 2;
    return {sub_triangle(p, {A, ab, ca}), sub_triangle(p, {ab, B, bc}), sub_triangle(p, {ca, bc, C}),
            sub_triangle(p, {bc, ca, ab})};
  }
  const int d = p.degree;
  std::array<Bernstein<long double>, 4> out;
  out.fill(make<long double>(false, d));
  std::array<Bernstein<long double>, 2> by_u{make<long double>(false, d), make<long double>(false, d)};
  for (int j = 0; j <= d; ++j) {
    std::vector<long double> column;
    for (int i = 0; i <= d; ++i) column.push_back(p.at(i, j));
    const auto h = halves(column);
    for (int s = 0; s < 2; ++s)
      for (int i = 0; i <= d; ++i)
        by_u[static_cast<std::size_t>(s)].at(i, j) =
            h[static_cast<std::size_t>(s)][static_cast<std::size_t>(i)];
  }
  for (int s = 0; s < 2; ++s)
    for (int i = 0; i <= d; ++i) {
      const auto& q = by_u[static_cast<std::size_t>(s)];
      std::vector<long double> row;
      for (int j = 0; j <= d; ++j) row.push_back(q.at(i, j));
      const auto h = halves(row);
      for (int t = 0; t < 2; ++t)
        for (int j = 0; j <= d; ++j)
          out[2 * static_cast<std::size_t>(s) + static_cast<std::size_t>(t)].at(i, j) =
              h[static_cast<std::size_t>(t)][static_cast<std::size_t>(j)];
    }
  return out;
}

/// The sign of a polynomial on its whole domain, proved by its Bernstein coefficients (the
/// polynomial lies between their min and max; the corner coefficients are its values there),
/// splitting where they do not decide.
struct Sign {
  int sign = 0;           // +1, −1; 0: both signs occur; 2: undecided
  long double bound = 0;  // sign > 0: a lower bound of |p|
  int depth = 0;
};

Sign sign_of(const Bernstein<long double>& p, long double tolerance, int depth) {
  const auto [lo, hi] = std::minmax_element(p.c.begin(), p.c.end());
  if (*lo > tolerance) return {.sign = 1, .bound = *lo, .depth = depth};
  if (*hi < -tolerance) return {.sign = -1, .bound = -*hi, .depth = depth};
  const int d = p.degree;
  const std::vector<long double> corners =
      p.triangle ? std::vector<long double>{p.at(0, 0), p.at(d, 0), p.at(0, d)}
                 : std::vector<long double>{p.at(0, 0), p.at(d, 0), p.at(d, d), p.at(0, d)};
  const bool positive =
      std::any_of(corners.begin(), corners.end(), [&](long double x) { return x > tolerance; });
  const bool negative =
      std::any_of(corners.begin(), corners.end(), [&](long double x) { return x < -tolerance; });
  if (positive && negative) return {.sign = 0, .bound = 0, .depth = depth};
  if (depth == kMaxSplits) return {.sign = 2, .bound = 0, .depth = depth};
  Sign out{.sign = 0, .bound = 0, .depth = depth};
  bool first = true;
  for (const auto& part : split(p)) {
    const Sign s = sign_of(part, tolerance, depth + 1);
    out.depth = std::max(out.depth, s.depth);
    if (s.sign == 2 || s.sign == 0) return {.sign = s.sign, .bound = 0, .depth = out.depth};
    if (first) {
      out.sign = s.sign;
      out.bound = s.bound;
      first = false;
    } else if (s.sign != out.sign) {
      return {.sign = 0, .bound = 0, .depth = out.depth};
    }
    out.bound = std::min(out.bound, s.bound);
  }
  return out;
}

/// The angle a Bézier curve sweeps around 0: exact once its control points lie in an open wedge of
/// opening < π (the curve stays in their hull); halved until they do. Nothing if it passes near 0.
std::optional<long double> swept_angle(const std::vector<Vec2>& b, int depth = 0) {
  long double lo = 0, hi = 0;
  bool inside = true;
  for (const Vec2& p : b) {
    if (p.norm() < 1e-300L) inside = false;
    const long double a = std::atan2(cross(b.front(), p), b.front().dot(p));
    lo = std::min(lo, a);
    hi = std::max(hi, a);
  }
  if (inside && hi - lo < kPiL - 1e-6L)
    return std::atan2(cross(b.front(), b.back()), b.front().dot(b.back()));
  if (depth == 40) return std::nullopt;
  const auto h = halves(b);
  const auto first = swept_angle(h[0], depth + 1), second = swept_angle(h[1], depth + 1);
  if (!first || !second) return std::nullopt;
  return *first + *second;
}

// ------------------------------------------------------------------------------------------------
// The characteristic net: the eigenvector pair on the canonical region of the local mesh.

struct CharacteristicNet {
  detail::LocalRefinement local;
  Points X;                 // level-0 vertex data (2 columns); 0 outside the region
  std::vector<char> known;  // per level-0 vertex: inside the region, where X is the eigen-extension
};

/// `lambdas`: the eigenvalue of each column of `pair` (any number of columns; the characteristic
/// map's two, or an eigenspace whose eigenfunctions are tested).
CharacteristicNet characteristic_net(MeshScheme scheme, int n, const LocalOptions& options,
                                     const std::vector<long double>& lambdas, const LongMatrix& pair) {
  const bool dual = scheme == MeshScheme::doo_sabin;
  CharacteristicNet net{
      .local = detail::refine_local(scheme, n, options, dual ? 5 : 7), .X = {}, .known = {}};
  const auto& local = net.local;
  const MeshTopology& t0 = local.refinement.levels.front();
  const MeshTopology& t1 = local.refinement.levels.back();
  const int depth = dual ? 4 : 6;
  const std::vector<int> order = detail::canonical_order(t0, scheme, local.centre, local.start, depth);
  const std::vector<int> child =
      detail::canonical_order(t1, scheme, local.child_centre, local.child_start, depth);
  if (child.size() != order.size())
    throw std::logic_error("characteristic map: the two levels differ around the centre");
  const auto K = static_cast<Eigen::Index>(order.size());
  std::vector<int> position(static_cast<std::size_t>(t0.vertex_count), -1);
  for (Eigen::Index k = 0; k < K; ++k)
    position[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = static_cast<int>(k);
  // S on the region, in the canonical order: new vertex k from old vertices.
  LongMatrix S = LongMatrix::Zero(K, K);
  const Stencils& st = local.stencils;
  for (Eigen::Index k = 0; k < K; ++k) {
    const auto row = static_cast<std::size_t>(child[static_cast<std::size_t>(k)]);
    for (int e = st.offsets[row]; e < st.offsets[row + 1]; ++e) {
      const int column = position[static_cast<std::size_t>(st.columns[static_cast<std::size_t>(e)])];
      if (column < 0) throw std::logic_error("characteristic map: the region is not invariant");
      S(k, column) += st.weights[static_cast<std::size_t>(e)];
    }
  }
  const std::vector<int> nb = detail::neighbourhood(t0, scheme, local.centre, local.start, options.boundary);
  if (static_cast<Eigen::Index>(nb.size()) != pair.rows())
    throw std::logic_error("characteristic map: the eigenvectors do not fit the neighbourhood");
  std::vector<char> in_nb(static_cast<std::size_t>(K), 0);
  const Eigen::Index columns = pair.cols();
  LongMatrix XK = LongMatrix::Zero(K, columns);
  for (std::size_t i = 0; i < nb.size(); ++i) {
    const int k = position[static_cast<std::size_t>(nb[i])];
    in_nb[static_cast<std::size_t>(k)] = 1;
    XK.row(k) = pair.row(static_cast<Eigen::Index>(i));
  }
  // Outside the neighbourhood, the eigen-equation: (λ − S_OO) X_O = S_ON X_N.
  std::vector<Eigen::Index> outer, inner;
  for (Eigen::Index k = 0; k < K; ++k) (in_nb[static_cast<std::size_t>(k)] ? inner : outer).push_back(k);
  const auto O = static_cast<Eigen::Index>(outer.size());
  for (Eigen::Index column = 0; column < columns; ++column) {
    const long double lambda = lambdas[static_cast<std::size_t>(column)];
    LongMatrix A(O, O);
    LongVector B = LongVector::Zero(O);
    for (Eigen::Index a = 0; a < O; ++a) {
      for (Eigen::Index b = 0; b < O; ++b)
        A(a, b) =
            (a == b ? lambda : 0) - S(outer[static_cast<std::size_t>(a)], outer[static_cast<std::size_t>(b)]);
      for (const Eigen::Index j : inner) B(a) += S(outer[static_cast<std::size_t>(a)], j) * XK(j, column);
    }
    const LongVector XO = A.fullPivLu().solve(B);
    for (Eigen::Index a = 0; a < O; ++a) XK(outer[static_cast<std::size_t>(a)], column) = XO(a);
  }
  // Scale to a unit box: the margins below are relative anyway, this keeps doubles well away from underflow.
  XK /= XK.cwiseAbs().maxCoeff();
  net.X = Points::Zero(t0.vertex_count, columns);
  net.known.assign(static_cast<std::size_t>(t0.vertex_count), 0);
  for (Eigen::Index k = 0; k < K; ++k) {
    const auto v = static_cast<Eigen::Index>(order[static_cast<std::size_t>(k)]);
    net.X.row(v) = XK.row(k).cast<double>();
    net.known[static_cast<std::size_t>(v)] = 1;
  }
  return net;
}

/// Which rows of a step depend on known data only.
std::vector<char> known_after(const Stencils& s, const std::vector<char>& known) {
  std::vector<char> out(row_count(s), 1);
  for (std::size_t r = 0; r < row_count(s); ++r)
    for (int e = s.offsets[r]; e < s.offsets[r + 1]; ++e)
      if (s.weights[static_cast<std::size_t>(e)] != 0 &&
          !known[static_cast<std::size_t>(s.columns[static_cast<std::size_t>(e)])])
        out[r] = 0;
  return out;
}

/// A patch of the ring in Bernstein form; `labels` name its corners (mesh vertices, Doo–Sabin:
/// faces) counter-clockwise, so that the inner boundary can be found.
struct Patch {
  Bernstein<Vec2> bezier;
  std::vector<int> labels;
};

/// The corner labels of the ring's inner boundary: the centre's one-ring (vertices of its faces;
/// Doo–Sabin: the faces around the centre face) without the centre itself.
std::vector<char> inner_labels(const MeshTopology& t, MeshScheme scheme, int centre) {
  if (scheme == MeshScheme::doo_sabin) {
    std::vector<char> out(face_count(t), 0);
    for (const int g : face(t, static_cast<std::size_t>(centre)))
      for (const int f : vertex_faces(t, static_cast<std::size_t>(g))) out[static_cast<std::size_t>(f)] = 1;
    out[static_cast<std::size_t>(centre)] = 0;
    return out;
  }
  std::vector<char> out(static_cast<std::size_t>(t.vertex_count), 0);
  for (const int f : vertex_faces(t, static_cast<std::size_t>(centre)))
    for (const int v : face(t, static_cast<std::size_t>(f))) out[static_cast<std::size_t>(v)] = 1;
  out[static_cast<std::size_t>(centre)] = 0;
  return out;
}

/// The level-2 vertices over a level-0 face at its dyadic points, [i (d + 1) + j] with i along
/// corner 0 → 1 and j along corner 0 → 3 (triangles: 0 → 2; −1 off the triangle): each level's
/// grid refined by the child numbering (vertex points keep their index, edge e's point is V + e,
/// Catmull–Clark's face f's V + E + f).
std::vector<int> dyadic_grid(const MeshRefinement& r, std::span<const int> corners, bool quads) {
  int m = 1;
  std::vector<int> grid = quads ? std::vector<int>{corners[0], corners[3], corners[1], corners[2]}
                                : std::vector<int>{corners[0], corners[2], corners[1], -1};
  for (std::size_t l = 0; l < 2; ++l) {
    const MeshTopology& t = r.levels[l];
    const int M = 2 * m, V = t.vertex_count, E = static_cast<int>(t.edges.size());
    std::vector<int> next(static_cast<std::size_t>((M + 1) * (M + 1)), -1);
    const auto g = [&](int i, int j) { return grid[flat(i, m, j)]; };
    const auto set = [&](int i, int j, int v) { next[flat(i, M, j)] = v; };
    const auto inside = [&](int i, int j) { return j >= 0 && (quads ? i <= m && j <= m : i + j <= m); };
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j <= m; ++j) {
        if (!inside(i, j)) continue;
        set(2 * i, 2 * j, g(i, j));
        for (const auto [di, dj] : {std::array{1, 0}, std::array{0, 1}, std::array{1, -1}})
          if (inside(i + di, j + dj) && !(quads && dj == -1))
            set(2 * i + di, 2 * j + dj, V + edge_between(t, g(i, j), g(i + di, j + dj)));
        if (quads && i < m && j < m) {
          int shared = -1;
          for (const int a : vertex_faces(t, static_cast<std::size_t>(g(i, j))))
            for (const int b : vertex_faces(t, static_cast<std::size_t>(g(i + 1, j + 1))))
              if (a == b) shared = a;
          set(2 * i + 1, 2 * j + 1, V + E + shared);
        }
      }
    grid = std::move(next);
    m = M;
  }
  return grid;
}

/// Bernstein coefficients of degree kMapDegree from values at the dyadic points k/4: the inverse
/// collocation matrix, per direction (tensor) or over the 15 points (triangle).
class Collocation {
 public:
  static constexpr int kPoints = (kMapDegree + 1) * (kMapDegree + 2) / 2;  // on a triangle
  using Line = Eigen::Matrix<long double, kMapDegree + 1, kMapDegree + 1>;
  using Triangle = Eigen::Matrix<long double, kPoints, kPoints>;

  Collocation() {
    Line line;
    for (int k = 0; k <= kMapDegree; ++k)
      for (int i = 0; i <= kMapDegree; ++i) {
        const long double t = static_cast<long double>(k) / kMapDegree;
        line(k, i) = binomial(kMapDegree, i) * std::pow(t, i) * std::pow(1 - t, kMapDegree - i);
      }
    line_inverse_ = line.inverse();
    Triangle triangle;
    for (int i = 0; i <= kMapDegree; ++i)
      for (int j = 0; i + j <= kMapDegree; ++j)
        for (int a = 0; a <= kMapDegree; ++a)
          for (int b = 0; a + b <= kMapDegree; ++b) {
            const long double u = static_cast<long double>(i) / kMapDegree,
                              v = static_cast<long double>(j) / kMapDegree;
            triangle(tri(i, j, kMapDegree), tri(a, b, kMapDegree)) = multinomial(kMapDegree, a, b) *
                                                                     std::pow(u, a) * std::pow(v, b) *
                                                                     std::pow(1 - u - v, kMapDegree - a - b);
          }
    triangle_inverse_ = triangle.inverse();
  }

  /// `values` in the patch's coefficient order (tensor i (kMapDegree + 1) + j; triangle tri(i, j)).
  Bernstein<Vec2> patch(bool triangle, const Eigen::Matrix<long double, Eigen::Dynamic, 2>& values) const {
    Bernstein<Vec2> out = make<Vec2>(triangle, kMapDegree);
    for (int k = 0; k < 2; ++k) {
      Eigen::Matrix<long double, Eigen::Dynamic, 1> c;
      if (triangle) {
        c = triangle_inverse_ * values.col(k);
      } else {
        const Eigen::Matrix<long double, Eigen::Dynamic, 1> column = values.col(k);
        const Line V =
            Eigen::Map<const Eigen::Matrix<long double, kMapDegree + 1, kMapDegree + 1, Eigen::RowMajor>>(
                column.data());
        const Eigen::Matrix<long double, kMapDegree + 1, kMapDegree + 1, Eigen::RowMajor> C =
            line_inverse_ * V * line_inverse_.transpose();
        c = Eigen::Map<const Eigen::Matrix<long double, (kMapDegree + 1) * (kMapDegree + 1), 1>>(C.data());
      }
      for (Eigen::Index i = 0; i < c.size(); ++i) out.c[static_cast<std::size_t>(i)][k] = c(i);
    }
    return out;
  }

 private:
  Line line_inverse_;
  Triangle triangle_inverse_;
};

/// Catmull–Clark and Loop: each face of the local mesh not at the centre whose limit is known, as
/// the polynomial through its limit values at the dyadic points two steps down (bicubic or
/// quartic: of degree ≤ 4 in each variable, so these points determine it).
std::vector<Patch> limit_patches(MeshScheme scheme, const CharacteristicNet& net) {
  const bool quads = scheme == MeshScheme::catmull_clark;
  const int regular = quads ? 4 : 6;
  const MeshRefinement r =
      refine_topology(net.local.mesh, scheme, 2, MeshOptions{.max_bytes = 1'000'000'000});
  const Points X2 = apply(r, net.X);
  const std::vector<char> known2 = known_after(r.steps[1], known_after(r.steps[0], net.known));
  const MeshTopology& t2 = r.levels[2];
  const LongVector stencil = local_spectrum(local_matrix(scheme, regular)).limit_stencil;
  const auto limit_at = [&](int v) -> std::optional<Vec2> {
    if (t2.boundary_vertex[static_cast<std::size_t>(v)] ||
        valence(t2, static_cast<std::size_t>(v)) != regular)
      return std::nullopt;
    const int start =
        other_vertex(t2, static_cast<std::size_t>(vertex_edges(t2, static_cast<std::size_t>(v))[0]), v);
    const std::vector<int> nb = detail::neighbourhood(t2, scheme, v, start, false);
    Vec2 x = Vec2::Zero();
    for (std::size_t i = 0; i < nb.size(); ++i) {
      if (!known2[static_cast<std::size_t>(nb[i])]) return std::nullopt;
      x += stencil(static_cast<Eigen::Index>(i)) * X2.row(nb[i]).transpose().cast<long double>();
    }
    return x;
  };
  const Collocation collocation;
  std::vector<Patch> out;
  const MeshTopology& t0 = r.levels[0];
  for (std::size_t f = 0; f < face_count(t0); ++f) {
    const auto corners = face(t0, f);
    if (std::find(corners.begin(), corners.end(), net.local.centre) != corners.end()) continue;
    const std::vector<int> grid = dyadic_grid(r, corners, quads);
    Eigen::Matrix<long double, Eigen::Dynamic, 2> values(
        quads ? (kMapDegree + 1) * (kMapDegree + 1) : Collocation::kPoints, 2);
    bool complete = true;
    for (int i = 0; i <= kMapDegree && complete; ++i)
      for (int j = 0; j <= (quads ? kMapDegree : kMapDegree - i) && complete; ++j) {
        const auto x = limit_at(grid[flat(i, kMapDegree, j)]);
        complete = x.has_value();
        if (complete) values.row(quads ? i * (kMapDegree + 1) + j : tri(i, j, kMapDegree)) = x->transpose();
      }
    if (complete)
      out.push_back(Patch{.bezier = collocation.patch(!quads, values),
                          .labels = std::vector<int>(corners.begin(), corners.end())});
  }
  return out;
}

/// Doo–Sabin: every regular vertex (valence 4, four quads) in the region, off the centre face: the
/// biquadratic B-spline patch of its 3 × 3 net, in Bézier form.
std::vector<Patch> net_patches(const CharacteristicNet& net) {
  const MeshTopology& t = net.local.refinement.levels.front();
  const auto centre_corners = face(t, static_cast<std::size_t>(net.local.centre));
  std::vector<Patch> out;
  for (int v = 0; v < t.vertex_count; ++v) {
    if (t.boundary_vertex[static_cast<std::size_t>(v)] || valence(t, static_cast<std::size_t>(v)) != 4 ||
        std::find(centre_corners.begin(), centre_corners.end(), v) != centre_corners.end())
      continue;
    const auto edges = vertex_edges(t, static_cast<std::size_t>(v));
    const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
    if (std::any_of(faces.begin(), faces.end(),
                    [&](int f) { return face(t, static_cast<std::size_t>(f)).size() != 4; }))
      continue;
    // Edge k points along +u, +v, −u, −v; face k (between edges k and k + 1) is the quadrant
    // (+,+), (−,+), (−,−), (+,−).
    std::array<std::array<int, 3>, 3> g{};
    g[1][1] = v;
    const std::array<std::array<int, 2>, 4> along{{{2, 1}, {1, 2}, {0, 1}, {1, 0}}},
        quadrant{{{2, 2}, {0, 2}, {0, 0}, {2, 0}}};
    for (std::size_t k = 0; k < 4; ++k) {
      g[static_cast<std::size_t>(along[k][0])][static_cast<std::size_t>(along[k][1])] =
          other_vertex(t, static_cast<std::size_t>(edges[k]), v);
      g[static_cast<std::size_t>(quadrant[k][0])][static_cast<std::size_t>(quadrant[k][1])] =
          corner(t, faces[k], corner_index(t, faces[k], v) + 2);
    }
    bool complete = true;
    for (const auto& row : g)
      for (const int w : row) complete = complete && net.known[static_cast<std::size_t>(w)];
    if (!complete) continue;
    // Quadratic B-spline segment (P0, P1, P2) → Bézier ((P0 + P1)/2, P1, (P1 + P2)/2), in u and v.
    const std::array<std::array<long double, 3>, 3> M{{{0.5L, 0.5L, 0}, {0, 1, 0}, {0, 0.5L, 0.5L}}};
    Patch patch{.bezier = make<Vec2>(false, 2), .labels = {faces[2], faces[3], faces[0], faces[1]}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Vec2 x = Vec2::Zero();
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            x += M[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)] *
                 M[static_cast<std::size_t>(j)][static_cast<std::size_t>(b)] *
                 net.X.row(g[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)])
                     .transpose()
                     .cast<long double>();
        patch.bezier.at(i, j) = x;
      }
    out.push_back(std::move(patch));
  }
  return out;
}

/// The Bézier control points of a patch's edge from corner k to corner k + 1.
std::vector<Vec2> edge_curve(const Bernstein<Vec2>& p, int k) {
  const int d = p.degree;
  std::vector<Vec2> out;
  for (int s = 0; s <= d; ++s) {
    if (p.triangle) {
      const std::array<std::array<int, 2>, 3> from{{{s, 0}, {d - s, s}, {0, d - s}}};
      out.push_back(p.at(from[static_cast<std::size_t>(k)][0], from[static_cast<std::size_t>(k)][1]));
    } else {
      const std::array<std::array<int, 2>, 4> from{{{s, 0}, {d, s}, {d - s, d}, {0, d - s}}};
      out.push_back(p.at(from[static_cast<std::size_t>(k)][0], from[static_cast<std::size_t>(k)][1]));
    }
  }
  return out;
}

C1Verdict bernstein_verdict(MeshScheme scheme, const CharacteristicNet& net) {
  const std::vector<Patch> patches =
      scheme == MeshScheme::doo_sabin ? net_patches(net) : limit_patches(scheme, net);
  const MeshTopology& t0 = net.local.refinement.levels.front();
  const std::vector<char> inner = inner_labels(t0, scheme, net.local.centre);
  C1Verdict out;
  out.method = "bernstein";
  out.pieces = static_cast<int>(patches.size());
  // The ring must be there whole: every patch with an inner-boundary edge, 3 per sector.
  std::vector<Bernstein<long double>> jacobians;
  long double scale = 0;
  for (const Patch& p : patches) {
    jacobians.push_back(jacobian(p.bezier));
    for (const long double c : jacobians.back().c) scale = std::max(scale, std::abs(c));
  }
  int sign = 0;
  out.regular = true;
  out.margin = scale;
  long double angle = 0;
  int inner_edges = 0;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const Sign s = sign_of(jacobians[i], std::max(kMargin * scale, kFloor), 0);
    out.splits = std::max(out.splits, s.depth);
    if (s.sign == 2) out.decided = false;
    if (s.sign == 0 || (sign != 0 && s.sign != 2 && s.sign != sign)) out.regular = false;
    if (s.sign == 1 || s.sign == -1) {
      if (sign == 0) sign = s.sign;
      out.margin = std::min(out.margin, s.bound);
    }
    const auto& labels = patches[i].labels;
    const int k = static_cast<int>(labels.size());
    for (int e = 0; e < k; ++e) {
      const int a = labels[static_cast<std::size_t>(e)], b = labels[static_cast<std::size_t>((e + 1) % k)];
      if (!inner[static_cast<std::size_t>(a)] || !inner[static_cast<std::size_t>(b)]) continue;
      ++inner_edges;
      const auto swept = swept_angle(edge_curve(patches[i].bezier, e));
      if (!swept) {
        out.decided = false;
        continue;
      }
      angle += *swept;
    }
  }
  const int expected_inner = scheme == MeshScheme::loop ? 1 : 2;
  const int n = static_cast<int>(
      scheme == MeshScheme::doo_sabin
          ? face(t0, static_cast<std::size_t>(net.local.centre)).size()
          : static_cast<std::size_t>(valence(t0, static_cast<std::size_t>(net.local.centre))));
  if (inner_edges != expected_inner * n)
    throw std::logic_error("characteristic map: the ring's inner boundary is not whole");
  out.margin /= scale;
  if (!out.regular) out.margin = 0;
  // The patches run round the inner boundary clockwise (they lie outside it).
  const long double turns = -angle / (2 * kPiL);
  out.winding = static_cast<int>(std::lround(turns));
  if (out.decided && std::abs(turns - static_cast<long double>(out.winding)) > 1e-6L)
    throw std::logic_error("characteristic map: the inner boundary does not close");
  out.winding *= sign == 0 ? 1 : sign;  // counted in the map's own orientation: +1 when injective
  return out;
}

/// Butterfly and √3 (any scheme on request): the net after `levels` steps, each face's signed
/// area and the winding of the ring round the centre there (its neighbours; Doo–Sabin: the centre
/// face's corners, kept as face 0 by the F-faces coming first) — evidence only.
C1Verdict sampled_verdict(MeshScheme scheme, int n, const CharacteristicNet& net, int levels) {
  const MeshRefinement r =
      refine_topology(net.local.mesh, scheme, levels, MeshOptions{.max_bytes = 1'000'000'000});
  const Points X = apply(r, net.X);
  std::vector<char> known = net.known;
  for (const Stencils& s : r.steps) known = known_after(s, known);
  const MeshTopology& t = r.levels.back();
  const bool dual = scheme == MeshScheme::doo_sabin;
  const int centre = net.local.centre;  // vertex points keep their index, F-faces theirs
  std::vector<int> ring;
  if (dual) {
    const auto corners = face(t, static_cast<std::size_t>(centre));
    ring.assign(corners.begin(), corners.end());
  } else {
    for (const int e : vertex_edges(t, static_cast<std::size_t>(centre)))
      ring.push_back(other_vertex(t, static_cast<std::size_t>(e), centre));
  }
  if (static_cast<int>(ring.size()) != n) throw std::logic_error("characteristic map: lost the centre");
  const bool open = !dual && t.boundary_vertex[static_cast<std::size_t>(centre)];
  const auto x = [&](int v) { return Vec2(X.row(v).transpose().cast<long double>()); };
  C1Verdict out;
  out.method = "sampled";
  out.levels = levels;
  long double smallest = 0, largest = 0;
  int positive = 0, negative = 0;
  for (std::size_t f = 0; f < face_count(t); ++f) {
    const auto c = face(t, f);
    if (dual ? static_cast<int>(f) == centre : std::find(c.begin(), c.end(), centre) != c.end()) continue;
    if (!std::all_of(c.begin(), c.end(), [&](int v) { return known[static_cast<std::size_t>(v)] != 0; }))
      continue;
    long double area = 0;
    for (std::size_t i = 0; i < c.size(); ++i) area += cross(x(c[i]), x(c[(i + 1) % c.size()])) / 2;
    (area > 0 ? positive : negative) += 1;
    smallest = out.pieces == 0 ? std::abs(area) : std::min(smallest, std::abs(area));
    largest = std::max(largest, std::abs(area));
    ++out.pieces;
  }
  out.regular =
      out.pieces > 0 && (positive == 0 || negative == 0) && smallest > std::max(kMargin * largest, kFloor);
  out.margin = out.regular ? smallest / largest : 0;
  // The ring round the centre (on an open fan from one boundary edge to the other): the angle it
  // sweeps, unless a point of it sits on 0 (relative to the ring's size).
  long double angle = 0, nearest = std::numeric_limits<long double>::max(), farthest = 0;
  for (const int v : ring) {
    nearest = std::min(nearest, x(v).norm());
    farthest = std::max(farthest, x(v).norm());
  }
  out.through_centre = !(nearest > 1e-9L * farthest);
  for (std::size_t k = 0; k + (open ? 1 : 0) < ring.size(); ++k) {
    const Vec2 a = x(ring[k]), b = x(ring[(k + 1) % ring.size()]);
    angle += std::atan2(cross(a, b), a.dot(b));
  }
  const int orientation = negative > 0 ? -1 : 1;
  out.angle = open ? angle * static_cast<long double>(orientation) : 0;
  out.winding = open ? 0 : static_cast<int>(std::lround(angle / (2 * kPiL))) * orientation;
  return out;
}

}  // namespace

namespace {

constexpr long double kSpectralTolerance = 1e-12L;

/// The eigenfunctions of an eigenspace (the columns of `basis`, eigenvalue `lambda`) at a boundary
/// vertex: their limit values at every vertex two steps down whose limit is the regular one (an
/// interior vertex of the regular valence, or a boundary vertex of the regular boundary valence:
/// the boundary curve's (1, 4, 1)/6; Butterfly: every vertex, its own limit), off the centre. An eigenvector
/// whose eigenfunction is 0 — its limit values all vanish — does not shape the surface (the third ½ of a
/// regular corner: c stays, the two curves are straight in the characteristic map, and the quad between them
/// reproduces the plane). Returns the live combinations: the basis times the right singular
/// vectors of the limit values above 1e-9 (the net is scaled to 1).
LongMatrix live_eigenfunctions(MeshScheme scheme, int n, const LocalOptions& options, long double lambda,
                               const LongMatrix& basis) {
  const CharacteristicNet net = characteristic_net(
      scheme, n, options, std::vector<long double>(static_cast<std::size_t>(basis.cols()), lambda), basis);
  const MeshRefinement r =
      refine_topology(net.local.mesh, scheme, 2, MeshOptions{.max_bytes = 1'000'000'000});
  const Points X = apply(r, net.X);
  const std::vector<char> known = known_after(r.steps[1], known_after(r.steps[0], net.known));
  const MeshTopology& t = r.levels[2];
  const int regular = scheme == MeshScheme::catmull_clark ? 4 : 6;
  const LongVector stencil = local_spectrum(local_matrix(scheme, regular)).limit_stencil;
  std::vector<LongVector> rows;
  for (int v = 0; v < t.vertex_count; ++v) {
    if (v == net.local.centre) continue;
    const auto ring = vertex_edges(t, static_cast<std::size_t>(v));
    const auto around = [&](std::size_t e) { return other_vertex(t, static_cast<std::size_t>(ring[e]), v); };
    std::vector<std::pair<int, long double>> weights;
    if (scheme == MeshScheme::butterfly) {  // interpolating: every vertex is its own limit
      weights = {{v, 1.0L}};
    } else if (t.boundary_vertex[static_cast<std::size_t>(v)]) {
      if (static_cast<int>(ring.size()) != regular / 2 + 1) continue;
      weights = {{v, 4.0L / 6}, {around(0), 1.0L / 6}, {around(ring.size() - 1), 1.0L / 6}};
    } else {
      if (static_cast<int>(ring.size()) != regular) continue;
      const std::vector<int> nb = detail::neighbourhood(t, scheme, v, around(0), false);
      for (std::size_t i = 0; i < nb.size(); ++i)
        weights.emplace_back(nb[i], stencil(static_cast<Eigen::Index>(i)));
    }
    if (!std::all_of(weights.begin(), weights.end(),
                     [&](const auto& w) { return known[static_cast<std::size_t>(w.first)] != 0; }))
      continue;
    LongVector row = LongVector::Zero(basis.cols());
    for (const auto& [u, w] : weights) row += w * X.row(u).transpose().cast<long double>();
    rows.push_back(row);
  }
  LongMatrix L(static_cast<Eigen::Index>(rows.size()), basis.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) L.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
  const Eigen::JacobiSVD<LongMatrix> svd(L, Eigen::ComputeFullV);
  Eigen::Index live = 0;
  while (live < svd.singularValues().size() && svd.singularValues()(live) > 1e-9L) ++live;
  return basis * svd.matrixV().leftCols(live);
}

/// The spectral conditions; nothing when they hold, else the verdict that says which fails.
/// `pair`: λ1 = λ2 required (an untagged interior vertex), else only both real and positive.
std::optional<C1Verdict> spectral_failure(const LocalSpectrum& spectrum, bool pair) {
  C1Verdict out;
  if (!spectrum.dominant_simple) {
    out.reason = "not C1: the eigenvalue 1 is not simple and dominant (no convergence to a point)";
  } else if (pair && !spectrum.subdominant_pair) {
    out.reason = "not C1: the subdominant eigenvalue " +
                 number_text(static_cast<double>(spectrum.subdominant), 3) +
                 " is not a real double eigenvalue (no tangent plane for generic data)";
  } else if (!pair && (std::abs(spectrum.eigenvalues[1].imag()) > kSpectralTolerance ||
                       std::abs(spectrum.eigenvalues[2].imag()) > kSpectralTolerance ||
                       spectrum.second <= kSpectralTolerance)) {
    out.reason =
        "not C1: lambda1 and lambda2 are not both real and positive (no tangent plane for generic data)";
  } else if (!spectrum.gap) {
    out.reason = "not C1: no gap below lambda2 (|lambda3| = lambda2 = " +
                 number_text(static_cast<double>(spectrum.second), 3) +
                 "): the tangent plane depends on the data";
  } else {
    return std::nullopt;
  }
  return out;
}

/// No gap at a sector (|λ3| = λ2): the eigenvalues that share λ2 may belong to eigenfunctions that
/// vanish (live_eigenfunctions). Nothing when exactly two live eigenfunctions lead — the spectrum's
/// subdominant basis and gap are then replaced by them — else the verdict.
std::optional<C1Verdict> shared_subdominant(const LocalMatrix& S, LocalSpectrum& spectrum) {
  C1Verdict out;
  const auto& ev = spectrum.eigenvalues;
  const long double l1 = spectrum.subdominant, l2 = spectrum.second;
  const auto real_positive = [&](const std::complex<long double>& z) {
    return std::abs(z.imag()) < kSpectralTolerance && z.real() > kSpectralTolerance;
  };
  // The eigenvalues equal to λ2 (real, positive), and what follows them.
  std::size_t first = 1;
  while (first < ev.size() && std::abs(ev[first] - l2) > kSpectralTolerance) ++first;
  std::size_t last = first;
  while (last < ev.size() && std::abs(ev[last] - l2) < kSpectralTolerance) ++last;
  const bool next_smaller = last >= ev.size() || std::abs(ev[last]) < l2 - kSpectralTolerance;
  if (!real_positive(ev[1]) || !real_positive(ev[2]) || !next_smaller) {
    out.decided = false;
    out.reason =
        "undecided: |lambda3| = lambda2 = " + number_text(static_cast<double>(l2), 3) +
        " and the eigenvalues there are not all real and equal (their eigenfunctions are not tested)";
    return out;
  }
  const auto N = S.values.rows();
  const auto d = static_cast<Eigen::Index>(last - first);
  const LongMatrix I = LongMatrix::Identity(N, N);
  const Eigen::JacobiSVD<LongMatrix> svd(S.values - l2 * I, Eigen::ComputeFullV);
  const LongMatrix space = svd.matrixV().rightCols(d);
  if ((S.values * space - l2 * space).cwiseAbs().maxCoeff() > 1e-12L) {
    out.decided = false;
    out.reason = "undecided: lambda2 = " + number_text(static_cast<double>(l2), 3) +
                 " is defective (a Jordan block): its eigenfunctions are not tested";
    return out;
  }
  const LongMatrix live = live_eigenfunctions(S.scheme, S.valence, S.options, l2, space);
  const Eigen::Index needed = first == 1 ? 2 : 1;  // λ1 = λ2: both from this eigenspace
  if (live.cols() > needed) {
    out.reason = "not C1: " + std::to_string(live.cols()) +
                 " live eigenfunctions share lambda2 = " + number_text(static_cast<double>(l2), 3) +
                 " beside lambda1 (no gap: the tangent plane depends on the data)";
    return out;
  }
  if (live.cols() < needed) {
    out.decided = false;
    out.reason = "undecided: the eigenfunctions of lambda2 = " + number_text(static_cast<double>(l2), 3) +
                 " vanish; the next eigenvalues are not tested";
    return out;
  }
  // Exactly the two leading eigenfunctions: λ1's (when it is another eigenvalue) and the live one.
  LongMatrix basis(N, 2);
  if (needed == 2) {
    basis = live;
  } else {
    basis.col(0) = spectrum.subdominant_basis.col(0);
    basis.col(1) = live.col(0);
  }
  spectrum.subdominant_basis = basis;
  (void)l1;
  return std::nullopt;
}

/// λ1 = λ2 with one eigenvector (a Jordan block: Butterfly's ½ at a boundary vertex of 6 faces, the
/// curve's tangent and the inside's): local_spectrum's basis is then not two eigenvectors (its residual
/// shows it). With v the eigenvector and w a generalized one ((S − λ)w = v), S^k x = λ^k(kγv + γw + βv)
/// + o(λ^k) for data x (γ, β vectors): the points lie in the plane of γ and β at the coordinates
/// (kv + w, v) — a shear of (w, v) growing with k, which keeps its Jacobian —, so the map (w, v) decides
/// like a characteristic map. Butterfly interpolates (control values are limit values): a neighbour where
/// both vanish maps to the centre at every level, not injective — not C1 (6 faces: the middle neighbour,
/// both being antisymmetric; deep refinement in docs/subdivision-surfaces.md). The rest stays undecided
/// (the net of a generalized eigenvector is not built).
C1Verdict defective_subdominant(const LocalMatrix& S, const LocalSpectrum& spectrum) {
  C1Verdict out;
  out.decided = false;
  const long double lambda = spectrum.subdominant;
  out.reason = "undecided: lambda1 = lambda2 = " + number_text(static_cast<double>(lambda), 3) +
               " is defective (a Jordan block): its eigenfunctions are not tested";
  if (S.scheme != MeshScheme::butterfly) return out;
  const auto N = S.values.rows();
  const LongMatrix A = S.values - lambda * LongMatrix::Identity(N, N);
  const Eigen::JacobiSVD<LongMatrix> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const LongVector v = svd.matrixV().col(N - 1);
  const LongVector w = svd.solve(v);
  const auto& sigma = svd.singularValues();
  if (sigma(N - 2) < 1e-9L || (A * w - v).cwiseAbs().maxCoeff() > 1e-9L) return out;  // not one 2-block
  const long double scale = std::max(v.cwiseAbs().maxCoeff(), w.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 1; i < N; ++i)
    if (std::abs(v(i)) < 1e-12L * scale && std::abs(w(i) - w(0)) < 1e-12L * scale) {
      out.decided = true;
      out.spectral = true;
      out.through_centre = true;
      out.reason = "not C1: lambda1 = lambda2 = " + number_text(static_cast<double>(lambda), 3) +
                   " is a Jordan block, the limit follows lambda^k (k v + w) (v its eigenvector, w a "
                   "generalized one), and (w, v) sends " +
                   S.labels[static_cast<std::size_t>(i)] + " to the centre (not injective)";
      return out;
    }
  return out;
}

/// The verdict of a characteristic net (the reason included); `corner`/`concave`: the sector angle
/// asked of a corner sector.
C1Verdict net_verdict(MeshScheme scheme, int valence, const CharacteristicNet& net, const C1Options& options,
                      bool polynomial, bool corner, bool concave) {
  if (options.levels < 1 || options.levels > 6)
    throw InvalidInput("characteristic map: levels " + std::to_string(options.levels) +
                       " is out of range; expected 1 to 6");
  C1Verdict out =
      polynomial ? bernstein_verdict(scheme, net) : sampled_verdict(scheme, valence, net, options.levels);
  out.spectral = true;
  const bool open =
      net.local.refinement.levels.front().boundary_vertex[static_cast<std::size_t>(net.local.centre)] &&
      scheme != MeshScheme::doo_sabin;
  const std::string pieces = std::to_string(out.pieces) + (polynomial ? " patches" : " faces of the net");
  const std::string degrees = number_text(static_cast<double>(out.angle * 180 / kPiL), 4) + " degrees";
  if (!out.decided) {
    out.reason =
        "undecided: a patch's Jacobian or the boundary's winding stayed inconclusive after the splits";
  } else if (out.through_centre) {
    out.reason =
        "not C1: the characteristic map sends a vertex next to the centre to the centre (the "
        "eigenvectors vanish on the sharp edges: the sector's curves shrink faster than its inside, "
        "not injective)";
  } else if (!out.regular) {
    out.reason =
        "not C1: the characteristic map is singular or folds (its Jacobian takes both signs on the " +
        pieces + ")";
  } else if (!open && out.winding != 1) {
    out.reason = "not C1: the characteristic map winds " + std::to_string(std::abs(out.winding)) +
                 " times around the centre (not injective)";
  } else if (open && (out.angle <= 1e-9L || out.angle >= 2 * kPiL)) {  // 0: the ring goes out and back
    out.reason = "not C1: the sector's image spans " + degrees + ", outside (0, 360) (not injective)";
  } else if (open && corner && concave && out.angle <= kPiL) {
    out.reason = "not C1 as a concave corner: the sector's image spans " + degrees +
                 " (a convex cone; a concave corner needs more than 180): the surface folds over";
  } else if (open && corner && !concave && out.angle >= kPiL) {
    out.reason = "not C1 as a convex corner: the sector's image spans " + degrees + " (at least 180)";
  } else {
    out.c1 = true;
    out.reason = std::string(polynomial ? "C1, proved: " : "C1 (sampled, not a proof): ") +
                 "Jacobian of one sign on " + pieces +
                 (polynomial ? " (Bernstein bound " : " (smallest area ") +
                 number_text(static_cast<double>(out.margin), 3) + " of the largest), " +
                 (open ? "sector image spans " + degrees : std::string("inner boundary winds once"));
  }
  return out;
}

/// Each sector of a boundary, crease or corner vertex as the boundary vertex of as many faces.
C1Verdict sector_verdicts(const LocalMatrix& matrix, const C1Options& options) {
  const bool corner = vertex_class(matrix.valence, matrix.options) == "corner";
  C1Verdict out;
  out.method = "sampled";
  out.spectral = true;
  out.c1 = true;
  const std::vector<int> sizes = sector_sizes(matrix.valence, matrix.options);
  std::string failed, undecided;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const LocalOptions o{.boundary = true,
                         .rule = BoundaryRule::edge_only,
                         .sharp = {},
                         .corner = corner,
                         .concave = corner && matrix.options.concave,
                         .rules = matrix.options.rules};
    C1Verdict::Sector sector{.faces = sizes[i], .spectrum = {}, .verdict = {}};
    const LocalMatrix S = local_matrix(matrix.scheme, sizes[i] + 1, o);
    sector.spectrum = local_spectrum(S);
    auto failure = spectral_failure(sector.spectrum, false);
    if (failure && sector.spectrum.dominant_simple && !sector.spectrum.gap)
      failure = shared_subdominant(S, sector.spectrum);
    if (!failure && sector.spectrum.residual > kSpectralTolerance)
      failure = defective_subdominant(S, sector.spectrum);
    if (failure) {
      sector.verdict = std::move(*failure);
    } else {
      const LongMatrix& basis = sector.spectrum.subdominant_basis;
      const CharacteristicNet net = characteristic_net(
          matrix.scheme, sizes[i] + 1, o, {sector.spectrum.subdominant, sector.spectrum.second}, basis);
      sector.verdict = net_verdict(matrix.scheme, sizes[i] + 1, net, options, false, corner, o.concave);
      if (!sector.spectrum.gap && sector.verdict.c1)
        sector.verdict.reason +=
            "; lambda2 is shared with eigenvectors whose eigenfunctions vanish (their "
            "limit values two steps down are 0)";
    }
    out.spectral = out.spectral && sector.verdict.spectral;
    out.regular = (i == 0 || out.regular) && sector.verdict.regular;
    out.levels = sector.verdict.levels;
    out.pieces += sector.verdict.pieces;
    std::string& first = sector.verdict.decided ? failed : undecided;
    if (!sector.verdict.c1 && first.empty())
      first = "sector " + std::to_string(i) + " (" + std::to_string(sizes[i]) +
              (sizes[i] == 1 ? " face): " : " faces): ") + sector.verdict.reason;
    out.c1 = out.c1 && sector.verdict.c1;
    out.sectors.push_back(std::move(sector));
  }
  // Not C1 when a sector is not; undecided when none fails but one is undecided.
  out.decided = out.c1 || !failed.empty();
  out.reason = out.c1 ? "C1 (sampled, not a proof) on each of the " + std::to_string(sizes.size()) +
                            (sizes.size() == 1 ? " sector" : " sectors")
               : !failed.empty() ? failed
                                 : undecided;
  return out;
}

}  // namespace

C1Verdict characteristic_map_verdict(MeshScheme scheme, int valence, long double lambda,
                                     const LongMatrix& pair, const C1Options& options) {
  const LocalMatrix shape = local_matrix(scheme, valence);  // checks the valence
  if (pair.rows() != shape.values.rows() || pair.cols() != 2)
    throw InvalidInput("characteristic map: expected " + std::to_string(shape.values.rows()) +
                       " by 2 eigenvectors");
  const CharacteristicNet net = characteristic_net(scheme, valence, {}, {lambda, lambda}, pair);
  const bool polynomial = !options.sampled && (scheme == MeshScheme::catmull_clark ||
                                               scheme == MeshScheme::loop || scheme == MeshScheme::doo_sabin);
  return net_verdict(scheme, valence, net, options, polynomial, false, false);
}

C1Verdict doo_sabin_boundary_verdict(const C1Verdict& interior, const std::vector<char>& interior_corners) {
  const std::vector<int> runs = sector_sizes(static_cast<int>(interior_corners.size()),
                                             {.boundary = true, .interior_corners = interior_corners});
  const int k = static_cast<int>(interior_corners.size());
  C1Verdict out = interior;
  out.sectors.clear();
  const std::string gon = std::to_string(k) + "-gon's";
  if (!interior.c1) {
    out.reason = "the interior " + gon + " verdict: " + interior.reason;
    return out;
  }
  if (runs.size() != 1) {
    out.c1 = false;
    out.reason = "not C1: the surface pinches — " + std::to_string(runs.size()) +
                 " sectors (runs of interior corners) touch at the face's centre only; each is C1 on its own";
    return out;
  }
  const int m = runs.front();
  std::string degrees = std::to_string(std::round(3600.0 * m / k) / 10);  // one decimal
  degrees = degrees.substr(0, degrees.find('.') + 2) + " degrees";
  out.angle = 2 * std::numbers::pi_v<long double> * m / k;
  out.reason = "C1 on one sector: the interior " + gon + " characteristic map (" + interior.method +
               ") restricted to the patches of its " + std::to_string(m) + " interior corner" +
               (m == 1 ? "" : "s") + ", spanning " + degrees;
  return out;
}

C1Verdict c1_verdict(const LocalMatrix& matrix, const LocalSpectrum& spectrum, const C1Options& options) {
  if (matrix.scheme == MeshScheme::doo_sabin && matrix.options.boundary) {
    const LocalMatrix whole = local_matrix(MeshScheme::doo_sabin, matrix.valence);
    return doo_sabin_boundary_verdict(c1_verdict(whole, local_spectrum(whole), options),
                                      matrix.options.interior_corners);
  }
  const std::string type = vertex_class(matrix.valence, matrix.options);
  if (type == "interior" && !matrix.options.boundary) {
    if (auto failure = spectral_failure(spectrum, true)) return *failure;
    return characteristic_map_verdict(matrix.scheme, matrix.valence, spectrum.subdominant,
                                      spectrum.subdominant_basis, options);
  }
  if (type == "dart") {
    if (auto failure = spectral_failure(spectrum, false)) return *failure;
    const CharacteristicNet net =
        characteristic_net(matrix.scheme, matrix.valence, matrix.options,
                           {spectrum.subdominant, spectrum.second}, spectrum.subdominant_basis);
    return net_verdict(matrix.scheme, matrix.valence, net, options, false, false, false);
  }
  return sector_verdicts(matrix, options);
}

}  // namespace cifs::subdivision
