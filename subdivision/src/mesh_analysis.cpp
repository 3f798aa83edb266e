// SPDX-License-Identifier: MIT
// cifs — local subdivision matrices at extraordinary vertices and their spectra
// (cifs/subdivision/mesh_analysis.hpp; docs/subdivision-surfaces.md).
#include "cifs/subdivision/mesh_analysis.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "cifs/errors.hpp"
#include "cifs/topology.hpp"
#include "local_mesh.hpp"

namespace cifs::subdivision {

using detail::corner;
using detail::corner_index;
using detail::edge_between;
using detail::face_across;
using detail::neighbourhood;
using detail::weight;
using detail::wrap;

namespace {

constexpr long double kPi = std::numbers::pi_v<long double>;

VertexRule centre_rule(int n, const LocalOptions& o);

void check_valence(MeshScheme scheme, int valence, const LocalOptions& o) {
  const std::string who(scheme_name(scheme));
  if (scheme == MeshScheme::bilinear)
    throw InvalidInput(who +
                       ": the limit surface is the refined mesh itself (C0 at every vertex, its vertices "
                       "interpolated); there is no local subdivision matrix to analyse");
  const bool tagged = !o.sharp.empty() || o.corner;
  if (tagged && scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
    throw InvalidInput(who + ": sharp edges and corners are analysed for catmull-clark and loop only");
  if (o.concave && centre_rule(valence, o) != VertexRule::corner)
    throw InvalidInput(who + ": concave is said of a corner (a sharp vertex on a boundary or crease)");
  if (o.rules == RuleSet::blz && scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
    throw InvalidInput(who + ": the rule set 'blz' is built for catmull-clark and loop only");
  if (o.rules == RuleSet::blz && o.concave && o.sharp.size() + (o.boundary ? 2 : 0) < 2)
    throw InvalidInput(who + ": a concave corner of the rule set 'blz' needs two or more sharp edges");
  const int first = o.boundary ? 1 : 0, last = o.boundary ? valence - 2 : valence - 1;
  for (std::size_t i = 0; i < o.sharp.size(); ++i)
    if (o.sharp[i] < first || o.sharp[i] > last || (i > 0 && o.sharp[i] <= o.sharp[i - 1]))
      throw InvalidInput(who + ": sharp edge " + std::to_string(o.sharp[i]) +
                         " is out of place; expected increasing edge numbers " + std::to_string(first) +
                         " to " + std::to_string(last) +
                         (o.boundary ? " (the boundary edges are sharp anyway)" : ""));
  if (!o.interior_corners.empty() && !(scheme == MeshScheme::doo_sabin && o.boundary))
    throw InvalidInput(who + ": interior corners are said of a doo-sabin face touching the boundary");
  if (o.boundary) {
    if (scheme == MeshScheme::doo_sabin)
      throw InvalidInput(who +
                         ": boundary vertices make no face; a face touching the boundary is analysed from "
                         "which of its corners are interior (interior_corners; cifs scheme doo-sabin "
                         "--boundary-valence K or --interior-corners PATTERN)");
    if (scheme == MeshScheme::sqrt3 && o.rule != BoundaryRule::edge_only)
      throw InvalidInput(who + ": the boundary has one rule under this scheme (Kobbelt's ternary cubic " +
                         "B-spline), the rule edge; a boundary vertex of one face is no corner");
    if (scheme == MeshScheme::butterfly && o.rule != BoundaryRule::edge_only)
      throw InvalidInput(who + ": the boundary has one rule under this scheme (the 4-point curve), the " +
                         "rule edge; a boundary vertex of one face is no corner");
    if (valence < kMinBoundaryValence || valence > kMaxBoundaryValence)
      throw InvalidInput(who + ": boundary valence " + std::to_string(valence) +
                         " is out of range; expected " + std::to_string(kMinBoundaryValence) + " to " +
                         std::to_string(kMaxBoundaryValence));
    return;
  }
  if (valence < kMinValence || valence > kMaxValence)
    throw InvalidInput(who + ": valence " + std::to_string(valence) + " is out of range; expected " +
                       std::to_string(kMinValence) + " to " + std::to_string(kMaxValence));
}

// ------------------------------------------------------------------------------------------------
// Route (a): the rules, in any scalar type that holds the weights.

/// cos(2πm/n) as a rational when it is one (Niven: the reduced denominator of m/n is 1, 2, 3, 4
/// or 6), otherwise nothing.
std::optional<Rational> exact_cos(int m, int n) {
  int p = ((m % n) + n) % n, q = n;
  const int g = std::gcd(p, q);
  p /= g;
  q /= g;
  switch (q) {
    case 1:
      return Rational(1);
    case 2:
      return Rational(-1);
    case 3:
      return Rational(-1, 2);
    case 4:
      return Rational(0);
    case 6:
      return Rational(1, 2);
    default:
      return std::nullopt;
  }
}

long double long_cos(int m, int n) {
  return std::cos(2 * kPi * static_cast<long double>(m) / static_cast<long double>(n));
}

/// Row-major, n rows by `cols` columns (square unless asked: √3's one-step matrices at a boundary
/// vertex change the ring's size).
template <class T>
struct Dense {
  int n = 0;
  int cols = 0;
  std::vector<T> a;
  explicit Dense(int size) : Dense(size, size) {}
  Dense(int rows, int columns)
      : n(rows), cols(columns), a(static_cast<std::size_t>(rows) * static_cast<std::size_t>(columns), T(0)) {}
  T& operator()(int i, int j) {
    return a[static_cast<std::size_t>(i) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(j)];
  }
  const T& operator()(int i, int j) const {
    return a[static_cast<std::size_t>(i) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(j)];
  }
};

template <class T>
Dense<T> product(const Dense<T>& A, const Dense<T>& B) {
  Dense<T> C(A.n, B.cols);
  for (int i = 0; i < A.n; ++i)
    for (int k = 0; k < A.cols; ++k) {
      if (A(i, k) == 0) continue;
      for (int j = 0; j < B.cols; ++j) C(i, j) += A(i, k) * B(k, j);
    }
  return C;
}

/// The sharp edges c r_j at a vertex of valence n, by j: the boundary's two and the tagged ones.
std::vector<int> sharp_edges(int n, const LocalOptions& o) {
  std::vector<int> out;
  if (o.boundary) out.push_back(0);
  out.insert(out.end(), o.sharp.begin(), o.sharp.end());
  if (o.boundary) out.push_back(n - 1);
  return out;
}

/// The rule of the centre (rules.hpp's vertex_rule on the local options).
VertexRule centre_rule(int n, const LocalOptions& o) {
  const bool sharp_vertex = o.corner || (o.boundary && n == 2 && o.rule == BoundaryRule::edge_and_corner);
  return vertex_rule(sharp_vertex ? kInfiniteSharpness : 0, static_cast<int>(sharp_edges(n, o).size()));
}

bool is_sharp(int n, const LocalOptions& o, int j) {
  const std::vector<int> sharp = sharp_edges(n, o);
  return std::find(sharp.begin(), sharp.end(), j) != sharp.end();
}

/// The centre's row when it follows the crease or corner rule (¾c + ⅛ on the two sharp ends, or c);
/// false for the smooth and dart rules, which the schemes write themselves.
template <class T, class Neighbour>
bool sharp_centre(Dense<T>& S, int n, const LocalOptions& o, Neighbour r) {
  const VertexRule rule = centre_rule(n, o);
  if (rule == VertexRule::corner) {
    S(0, 0) = T(1);
  } else if (rule == VertexRule::crease) {  // (1, 6, 1)/8 along the crease
    const std::vector<int> ends = sharp_edges(n, o);
    S(0, 0) = T(3) / 4;
    S(0, r(ends[0])) += T(1) / 8;
    S(0, r(ends[1])) += T(1) / 8;
  }
  return rule == VertexRule::corner || rule == VertexRule::crease;
}

/// Biermann–Levin–Zorin at the centre (rules.hpp, RuleSet::blz), written as the paper writes it:
/// for the smooth edge c r_j inside a sector of k faces spanning θ, θ_k = θ/k = 2πm/q and γ (the
/// weight of r_j; c gets ¾ − γ); on a concave corner's sector the flatness s and the subdominant
/// eigenvectors x₁ = sin((k − i)θ_k)/sin θ, x₂ = sin(iθ_k)/sin θ at ring position i (edge i of the
/// sector; face i has x(i) + x(i + 1)), e0 = r_a and ek = r_b the sector's sharp edges' ends.
template <class T>
struct BlzSector {
  bool on = false;
  int a = 0, b = 0, i = 0, k = 0;
  T gamma{}, flatness{}, x1_edge{}, x2_edge{}, x1_face{}, x2_face{};
};

/// The sector of ring edge j (smooth) at the centre under the blz rules; `on` false otherwise.
template <class T, class Cos>
BlzSector<T> blz_sector(MeshScheme scheme, int n, const LocalOptions& o, int j, Cos cos_of) {
  BlzSector<T> out;
  const VertexRule rule = centre_rule(n, o);
  const std::vector<int> sharp = sharp_edges(n, o);
  if (o.rules != RuleSet::blz || (rule != VertexRule::crease && rule != VertexRule::corner) ||
      sharp.size() < 2)
    return out;
  // The last sharp edge at or before j (cyclically around an interior vertex) and the next one.
  int a = sharp.back() - n, b = sharp.front();
  for (const int x : sharp)
    if (x <= j) a = x;
  for (auto it = sharp.rbegin(); it != sharp.rend(); ++it)
    if (*it > j) b = *it;
  if (b <= j) b = sharp.front() + n;
  out.on = true;
  out.a = a;
  out.b = b;
  out.k = b - a;
  out.i = j - a;
  // θ_k = 2πm/q: crease π/k (m = 1, q = 2k), convex corner π/(2k) (1, 4k), concave 3π/(2k) (3, 4k).
  const bool corner = rule == VertexRule::corner;
  const int m = corner && o.concave ? 3 : 1, q = corner ? 4 * out.k : 2 * out.k;
  const T one(1);
  const T base = scheme == MeshScheme::loop ? T(one / 2) : T(3 * one / 8);
  out.gamma = T(base - T(cos_of(m, q)) / 4);
  if (!(corner && o.concave)) return out;
  out.flatness = T(kBlzConcaveFlatness);
  const auto sin_of = [&](int mm, int qq) { return cos_of(qq - 4 * mm, 4 * qq); };  // sin(2πmm/qq)
  const T sin_theta = -one;                                                         // sin(3π/2)
  const auto x1 = [&](int i) { return T(T(sin_of(m * (out.k - i), q)) / sin_theta); };
  const auto x2 = [&](int i) { return T(T(sin_of(m * i, q)) / sin_theta); };
  out.x1_edge = x1(out.i);
  out.x2_edge = x2(out.i);
  out.x1_face = T(x1(out.i) + x1(out.i + 1));
  out.x2_face = T(x2(out.i) + x2(out.i + 1));
  return out;
}

/// Row i := (1 − s)·row i + s(c + ½x₁(e0 − c) + ½x₂(ek − c)): the flatness of a concave sector.
template <class T>
void flatten(Dense<T>& S, int i, const T& s, const T& x1, const T& x2, int e0, int ek) {
  const T keep = T(1) - s;
  for (int col = 0; col < S.cols; ++col) S(i, col) *= keep;
  S(i, 0) += T(s * T(T(1) - x1 / 2 - x2 / 2));
  S(i, e0) += T(s * x1 / 2);
  S(i, ek) += T(s * x2 / 2);
}

/// Catmull–Clark at a vertex of valence n (on the boundary: n − 1 faces).
template <class T, class Cos>
Dense<T> catmull_clark_rules(int n, const LocalOptions& o, Cos cos_of) {
  const T one(1), half = one / 2, quarter = one / 4;
  const T nn(n);
  const int N = o.boundary ? 2 * n : 2 * n + 1;
  const int faces = o.boundary ? n - 1 : n;
  Dense<T> S(N);
  const auto r = [&](int j) { return 1 + 2 * (o.boundary ? j : wrap(j, n)); };
  const auto f = [&](int j) { return 2 + 2 * (o.boundary ? j : wrap(j, n)); };
  // Face point of quad j = (c + r_j + f_j + r_{j+1})/4, added with weight w to row i.
  const auto face_point = [&](int i, int j, const T& w) {
    for (const int v : {0, r(j), f(j), r(j + 1)}) S(i, v) += w / 4;
  };
  if (!sharp_centre(S, n, o, r)) {  // (n − 2)/n on c, 1/n² on each neighbour and each face point
    S(0, 0) = (nn - 2) / nn;
    for (int j = 0; j < n; ++j) {
      S(0, r(j)) += one / (nn * nn);
      face_point(0, j, one / (nn * nn));
    }
  }
  for (int j = 0; j < n; ++j) {
    if (is_sharp(n, o, j)) {  // sharp edge: its midpoint
      S(r(j), 0) += half;
      S(r(j), r(j)) += half;
      continue;
    }
    if (const auto blz = blz_sector<T>(MeshScheme::catmull_clark, n, o, j, cos_of); blz.on) {
      // (¾ − γ)c + γ r_j + 1/16 on r_{j−1}, f_{j−1}, r_{j+1}, f_j.
      S(r(j), 0) += T(3 * quarter - blz.gamma);
      S(r(j), r(j)) += blz.gamma;
      for (const int v : {r(j - 1), f(j - 1), r(j + 1), f(j)}) S(r(j), v) += T(quarter / 4);
      continue;
    }
    S(r(j), 0) += quarter;
    S(r(j), r(j)) += quarter;
    face_point(r(j), j - 1, quarter);
    face_point(r(j), j, quarter);
  }
  for (int j = 0; j < faces; ++j) face_point(f(j), j, one);
  // A concave sector's flatness, on its edge points and on its face points (face j's sector is
  // that of edge j, sharp or not).
  for (int j = 0; j < n; ++j) {
    const auto blz = blz_sector<T>(MeshScheme::catmull_clark, n, o, j, cos_of);
    if (!blz.on || blz.flatness == T(0)) continue;
    if (!is_sharp(n, o, j)) flatten(S, r(j), blz.flatness, blz.x1_edge, blz.x2_edge, r(blz.a), r(blz.b));
    if (j < faces) flatten(S, f(j), blz.flatness, blz.x1_face, blz.x2_face, r(blz.a), r(blz.b));
  }
  return S;
}

/// Loop at a vertex of valence n.
template <class T, class Cos>
Dense<T> loop_rules(int n, const LocalOptions& o, Cos cos_of) {
  const T one(1), half = one / 2, quarter = one / 4, eighth = one / 8;
  const T nn(n);
  Dense<T> S(n + 1);
  const auto r = [&](int j) { return 1 + (o.boundary ? j : wrap(j, n)); };
  if (!sharp_centre(S, n, o, r)) {  // β = (5/8 − (3/8 + ¼cos(2π/n))²)/n
    const T a = 3 * eighth + quarter * cos_of(1, n);
    const T beta = (5 * eighth - a * a) / nn;
    S(0, 0) = one - nn * beta;
    for (int j = 0; j < n; ++j) S(0, r(j)) += beta;
  }
  for (int j = 0; j < n; ++j) {
    if (is_sharp(n, o, j)) {
      S(r(j), 0) += half;
      S(r(j), r(j)) += half;
      continue;
    }
    const auto blz = blz_sector<T>(MeshScheme::loop, n, o, j, cos_of);
    const T gamma = blz.on ? blz.gamma : T(3 * eighth);  // (¾ − γ)c + γ r_j + ⅛(r_{j−1} + r_{j+1})
    S(r(j), 0) += T(6 * eighth - gamma);
    S(r(j), r(j)) += gamma;
    S(r(j), r(j - 1)) += eighth;
    S(r(j), r(j + 1)) += eighth;
    if (blz.on && blz.flatness != T(0))
      flatten(S, r(j), blz.flatness, blz.x1_edge, blz.x2_edge, r(blz.a), r(blz.b));
  }
  return S;
}

/// The modified Butterfly at a vertex of valence n (ZSS's stencils).
template <class T, class Cos>
Dense<T> butterfly_rules(int n, Cos cos_of) {
  const T one(1), half = one / 2, quarter = one / 4, eighth = one / 8, sixteenth = one / 16;
  const T nn(n);
  Dense<T> S(3 * n + 1);
  const auto r = [&](int j) { return 1 + 3 * wrap(j, n); };
  const auto p = [&](int j) { return 2 + 3 * wrap(j, n); };
  const auto q = [&](int j) { return 3 + 3 * wrap(j, n); };
  S(0, 0) = one;  // interpolating: old vertices stay (c, and r_j becomes p_j)
  for (int j = 0; j < n; ++j) {
    S(p(j), r(j)) = one;
    // Edge c r_j: ZSS's stencil of the extraordinary end, or the 10-point one at n = 6.
    if (n == 6) {
      S(r(j), 0) += half;
      S(r(j), r(j)) += half;
      S(r(j), r(j - 1)) += eighth;
      S(r(j), r(j + 1)) += eighth;
      for (const int w : {r(j - 2), r(j + 2), q(j), q(j - 1)}) S(r(j), w) -= sixteenth;
    } else {
      S(r(j), 0) += 3 * quarter;
      for (int m = 0; m < n; ++m) {
        T s(0);
        if (n == 3)
          s = m == 0 ? T(5) / 12 : T(-1) / 12;
        else if (n == 4)
          s = m == 0 ? 3 * eighth : (m == 2 ? -eighth : T(0));
        else
          s = (quarter + cos_of(m, n) + half * cos_of(2 * m, n)) / nn;
        S(r(j), r(j + m)) += s;
      }
    }
    // Edge r_j r_{j+1}: both ends regular, the 10-point stencil (opposite corners c and q_j;
    // wings r_{j−1}, r_{j+2}, p_j, p_{j+1}).
    S(q(j), r(j)) += half;
    S(q(j), r(j + 1)) += half;
    S(q(j), 0) += eighth;
    S(q(j), q(j)) += eighth;
    for (const int w : {r(j - 1), r(j + 2), p(j), p(j + 1)}) S(q(j), w) -= sixteenth;
  }
  return S;
}

/// The modified Butterfly at a boundary vertex of valence n (n − 1 faces) under mesh.cpp's rule: the
/// 4-point rule (−1, 9, 9, −1)/16 on the boundary edges c r_0 and c r_{n−1} (its far points: the
/// other boundary edge's end and p_j, r_j's next boundary vertex); inside, the 10-point stencil
/// whatever n (a boundary end counts as regular), a wing across a boundary edge reflected: the wing
/// across (x, o) in the face of edge x z becomes x + o − z. Every weight is rational.
template <class T>
Dense<T> butterfly_boundary_rules(int n) {
  const T one(1), half = one / 2, eighth = one / 8, sixteenth = one / 16;
  const int faces = n - 1;
  Dense<T> S(3 * n);
  const auto r = [&](int j) { return 1 + 3 * j; };
  const auto p = [&](int j) { return 2 + 3 * j; };
  const auto q = [&](int j) { return 3 + 3 * j; };
  // Edge x z, its face's third corner o; the wing across (x, o) is `wing`, or missing (−1).
  const auto wing = [&](int row, int x, int o, int z, int beyond) {
    if (beyond >= 0) {
      S(row, beyond) -= sixteenth;
    } else {
      S(row, x) -= sixteenth;
      S(row, o) -= sixteenth;
      S(row, z) += sixteenth;
    }
  };
  // r_m for m inside the fan, −1 past its boundary edges (the wing across c r_m's neighbour is missing).
  const auto ring = [&](int m) { return m >= 0 && m <= faces ? r(m) : -1; };
  S(0, 0) = one;  // interpolating: old vertices stay (c, and r_j becomes p_j)
  for (int j = 0; j < n; ++j) S(p(j), r(j)) = one;
  for (const auto& [j, other] : {std::pair{0, faces}, std::pair{faces, 0}}) {
    S(r(j), 0) += 9 * sixteenth;
    S(r(j), r(j)) += 9 * sixteenth;
    S(r(j), r(other)) -= sixteenth;
    S(r(j), p(j)) -= sixteenth;
  }
  for (int j = 1; j < faces; ++j) {  // interior edge c r_j: faces j − 1 (o = r_{j−1}) and j (o = r_{j+1})
    S(r(j), 0) += half;
    S(r(j), r(j)) += half;
    S(r(j), r(j - 1)) += eighth;
    S(r(j), r(j + 1)) += eighth;
    wing(r(j), 0, r(j - 1), r(j), j - 1 > 0 ? ring(j - 2) : -1);
    wing(r(j), 0, r(j + 1), r(j), j + 1 < faces ? ring(j + 2) : -1);
    S(r(j), q(j - 1)) -= sixteenth;
    S(r(j), q(j)) -= sixteenth;
  }
  for (int j = 0; j < faces; ++j) {  // edge r_j r_{j+1}: opposite corners c and q_j
    S(q(j), r(j)) += half;
    S(q(j), r(j + 1)) += half;
    S(q(j), 0) += eighth;
    S(q(j), q(j)) += eighth;
    wing(q(j), r(j), 0, r(j + 1), j > 0 ? ring(j - 1) : -1);
    wing(q(j), r(j + 1), 0, r(j), j + 1 < faces ? ring(j + 2) : -1);
    S(q(j), p(j)) -= sixteenth;
    S(q(j), p(j + 1)) -= sixteenth;
  }
  return S;
}

/// Two steps of √3 at a vertex of valence n (one step leaves a ring of face points).
template <class T, class Cos>
Dense<T> sqrt3_rules(int n, Cos cos_of) {
  const T one(1);
  const T nn(n);
  // One step: c¹ = (1 − α)c + (α/n)Σ r_j, α = (4 − 2cos(2π/n))/9, and a ring point per face,
  // the centroid (c + r_j + r_{j+1})/3 (first step) — on the second step numbered so that
  // (c¹ + m_{j−1} + m_j)/3 is ring point j.
  const T alpha = (4 - 2 * cos_of(1, n)) / 9;
  const auto one_step = [&](int shift) {
    Dense<T> A(n + 1);
    A(0, 0) = one - alpha;
    for (int j = 0; j < n; ++j) {
      A(0, 1 + j) += alpha / nn;
      A(1 + j, 0) += one / 3;
      A(1 + j, 1 + wrap(j + shift, n)) += one / 3;
      A(1 + j, 1 + wrap(j + shift + 1, n)) += one / 3;
    }
    return A;
  };
  return product(one_step(-1), one_step(0));
}

/// One √3 step at a boundary vertex of `faces` faces (Kobbelt 2000 §5, as mesh.cpp's sqrt3_step), on
/// c, r_0 … r_faces (c r_0 and c r_faces the boundary edges), into the child's ring, c first.
/// Steps 0, 2, … (`trisect` false): c and the boundary stay, a centroid m_j per face; the child ring
/// is r_0, m_0 … m_{faces−1}, r_faces (faces + 1 faces). Steps 1, 3, … (`trisect`; faces ≥ 2, every
/// boundary face with one boundary edge, as after any even step): c → (4r_0 + 19c + 4r_faces)/27;
/// the boundary faces are trisected, their points next to c (r_faces + 16c + 10r_0)/27 and its
/// mirror, the faces between get their centroids; the child ring is t_0, g_1 … g_{faces−2},
/// t_faces (faces − 1 faces). Both read c's one-ring only (the trisection's far points, which read
/// two boundary vertices away, are not in c's child ring), so two steps map the ring onto itself.
template <class T>
Dense<T> sqrt3_boundary_rows(int faces, bool trisect) {
  const T one(1), third = one / 3, d(27);
  const int columns = faces + 2, last = faces + 1;  // r_j is column 1 + j
  const auto centroid = [&](Dense<T>& M, int row, int j) {
    for (const int v : {0, 1 + j, 2 + j}) M(row, v) += third;
  };
  if (!trisect) {
    Dense<T> A(faces + 3, columns);
    A(0, 0) = one;
    A(1, 1) = one;
    for (int j = 0; j < faces; ++j) centroid(A, 2 + j, j);
    A(faces + 2, last) = one;
    return A;
  }
  Dense<T> B(faces + 1, columns);
  for (const auto& [row, next_to, beyond] : {std::array{1, 1, last}, std::array{faces, last, 1}}) {
    B(row, 0) += T(16) / d;
    B(row, next_to) += T(10) / d;
    B(row, beyond) += one / d;
  }
  B(0, 0) = T(19) / d;
  B(0, 1) = T(4) / d;
  B(0, last) = T(4) / d;
  for (int j = 1; j + 1 < faces; ++j) centroid(B, 1 + j, j);
  return B;
}

/// Two √3 steps at a boundary vertex of valence n (n − 1 faces), from an even level: keep, then trisect.
template <class T>
Dense<T> sqrt3_boundary_rules(int n) {
  return product(sqrt3_boundary_rows<T>(n, true), sqrt3_boundary_rows<T>(n - 1, false));
}

/// Doo–Sabin at an n-gon face.
template <class T, class Cos>
Dense<T> doo_sabin_rules(int n, Cos cos_of) {
  const T one(1), quarter = one / 4;
  const int k = n;
  Dense<T> S(4 * k);
  const auto g = [&](int i) { return 4 * wrap(i, k); };
  const auto a = [&](int i) { return 4 * wrap(i, k) + 1; };
  const auto b = [&](int i) { return 4 * wrap(i, k) + 2; };
  const auto cq = [&](int i) { return 4 * wrap(i, k) + 3; };
  // Corner point of a face with corners v_0 … v_{m−1} at corner i: Σ_j α_{j−i} v_j,
  // α_0 = ¼ + 5/(4m), α_d = (3 + 2cos(2πd/m))/(4m).
  const auto corner_point = [&](int row, const std::vector<int>& corners, int i) {
    const int m = static_cast<int>(corners.size());
    for (int d = 0; d < m; ++d)
      S(row, corners[static_cast<std::size_t>(wrap(i + d, m))]) +=
          (d == 0 ? quarter : T(0)) + (3 + 2 * cos_of(d, m)) / (4 * T(m));
  };
  std::vector<int> gon(static_cast<std::size_t>(k));
  for (int i = 0; i < k; ++i) gon[static_cast<std::size_t>(i)] = g(i);
  for (int i = 0; i < k; ++i) {
    corner_point(g(i), gon, i);
    corner_point(a(i), {g(i + 1), g(i), a(i), b(i)}, 1);    // edge quad i at g_i
    corner_point(b(i), {g(i + 1), g(i), a(i), b(i)}, 0);    // edge quad i at g_{i+1}
    corner_point(cq(i), {g(i), b(i - 1), cq(i), a(i)}, 0);  // corner quad at g_i
  }
  return S;
}

/// The rules of each scheme on its neighbourhood; `cos_of(m, n)` gives cos(2πm/n) in T.
template <class T, class Cos>
Dense<T> rules(MeshScheme scheme, int n, const LocalOptions& o, Cos cos_of) {
  switch (scheme) {
    case MeshScheme::catmull_clark:
      return catmull_clark_rules<T>(n, o, cos_of);
    case MeshScheme::loop:
      return loop_rules<T>(n, o, cos_of);
    case MeshScheme::butterfly:
      return o.boundary ? butterfly_boundary_rules<T>(n) : butterfly_rules<T>(n, cos_of);
    case MeshScheme::sqrt3:
      return o.boundary ? sqrt3_boundary_rules<T>(n) : sqrt3_rules<T>(n, cos_of);
    case MeshScheme::doo_sabin:
      return doo_sabin_rules<T>(n, cos_of);
    case MeshScheme::bilinear:  // refused by check_valence
      break;
  }
  return Dense<T>(0);
}

/// The rules in exact rationals, or nothing when a cosine they need is irrational.
std::optional<Dense<Rational>> exact_rules(MeshScheme scheme, int n, const LocalOptions& o) {
  bool rational = true;
  const auto cosine = [&](int m, int k) {
    const std::optional<Rational> c = exact_cos(m, k);
    if (!c) rational = false;
    return c.value_or(Rational(0));
  };
  Dense<Rational> S = rules<Rational>(scheme, n, o, cosine);
  if (!rational) return std::nullopt;
  return S;
}

std::vector<std::string> labels(MeshScheme scheme, int n, const LocalOptions& o) {
  std::vector<std::string> out;
  const auto add = [&](const char* name, int j) { out.push_back(name + std::to_string(j)); };
  if (scheme == MeshScheme::doo_sabin) {
    for (int i = 0; i < n; ++i) {
      add("g", i);
      add("a", i);
      add("b", i);
      add("c", i);
    }
    return out;
  }
  out.emplace_back("c");
  for (int j = 0; j < n; ++j) {
    add("r", j);
    if (scheme == MeshScheme::catmull_clark && (!o.boundary || j < n - 1)) add("f", j);
    if (scheme == MeshScheme::butterfly) {
      add("p", j);
      if (!o.boundary || j < n - 1) add("q", j);
    }
  }
  return out;
}

LocalMatrix empty_matrix(MeshScheme scheme, int valence, const LocalOptions& o) {
  return LocalMatrix{.scheme = scheme,
                     .valence = valence,
                     .options = o,
                     .steps = scheme == MeshScheme::sqrt3 ? 2 : 1,
                     .labels = labels(scheme, valence, o),
                     .exact = std::nullopt,
                     .values = {}};
}

// ------------------------------------------------------------------------------------------------
// Route (b): the general refinement of a local mesh.

/// Vertex ids of a lattice wedge layout: sector s holds the points (i, j) with i ≥ 1 (its ray j = 0
/// included), point (0, j) of sector s is point (j, 0) of sector s + 1, (0, 0) the centre.
class WedgeVertices {
 public:
  WedgeVertices(int sectors, bool closed, int n) : sectors_(sectors), closed_(closed), n_(n) {}
  int id(int s, int i, int j, Points& positions) {
    if (i == 0 && j == 0) return at({0, 0, 0}, 0, 0, 0, positions);
    if (i == 0) return id(s + 1, j, 0, positions);
    const int key_s = closed_ ? wrap(s, sectors_) : s;
    return at({key_s, i, j}, key_s, i, j, positions);
  }

 private:
  int at(const std::array<int, 3>& key, int s, int i, int j, Points& positions) {
    const auto [it, added] = index_.try_emplace(key, static_cast<int>(index_.size()));
    if (added) {
      // Planar positions (any will do: the weights depend on the topology only).
      const long double step = closed_ ? 2 * kPi / n_ : kPi / n_;
      const auto dir = [&](int t) {
        return Eigen::RowVector3d(static_cast<double>(std::cos(step * t)),
                                  static_cast<double>(std::sin(step * t)), 0.0);
      };
      positions.conservativeResize(it->second + 1, 3);
      positions.row(it->second) = i * dir(s) + j * dir(s + 1);
    }
    return it->second;
  }
  int sectors_;
  bool closed_;
  int n_;
  std::map<std::array<int, 3>, int> index_;
};

Mesh primal_local_mesh(bool quads, int n, bool boundary, int rings) {
  const int sectors = boundary ? n - 1 : n;
  WedgeVertices ids(sectors, !boundary, n);
  Mesh m;
  m.vertices.resize(0, 3);
  ids.id(0, 0, 0, m.vertices);  // the centre is vertex 0
  ids.id(0, 1, 0, m.vertices);  // r_0 is vertex 1
  for (int s = 0; s < sectors; ++s)
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < rings; ++j) {
        const auto v = [&](int a, int b) { return ids.id(s, a, b, m.vertices); };
        if (quads) {
          add_face(m, {v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
          continue;
        }
        if (i + j + 1 <= rings) add_face(m, {v(i, j), v(i + 1, j), v(i, j + 1)});
        if (i + j + 2 <= rings) add_face(m, {v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
      }
  return m;
}

/// The dual of a closed-around-the-centre quad mesh: a face per interior vertex (its faces in
/// counter-clockwise order), a vertex per face (its centroid); the centre vertex 0 becomes face 0.
Mesh dual_mesh(const Mesh& primal) {
  const MeshTopology t = build_topology(primal, "local mesh");
  Mesh m;
  m.vertices.resize(static_cast<Eigen::Index>(face_count(t)), 3);
  for (std::size_t f = 0; f < face_count(t); ++f) {
    m.vertices.row(static_cast<Eigen::Index>(f)).setZero();
    for (const int c : face(t, f)) m.vertices.row(static_cast<Eigen::Index>(f)) += primal.vertices.row(c) / 4;
  }
  for (int v = 0; v < t.vertex_count; ++v) {
    if (t.boundary_vertex[static_cast<std::size_t>(v)]) continue;
    const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
    add_face(m, faces);
  }
  return m;
}

}  // namespace

namespace detail {

LongMatrix sqrt3_boundary_step(int faces, bool trisect) {
  if (faces < (trisect ? 2 : 1)) throw std::logic_error("sqrt3 boundary step: too few faces for the step");
  const Dense<Rational> M = sqrt3_boundary_rows<Rational>(faces, trisect);
  LongMatrix out(M.n, M.cols);
  for (int i = 0; i < M.n; ++i)
    for (int j = 0; j < M.cols; ++j) out(i, j) = M(i, j).convert_to<long double>();
  return out;
}

int wrap(int j, int n) {
  return ((j % n) + n) % n;
}

int edge_between(const MeshTopology& t, int a, int b) {
  for (const int e : vertex_edges(t, static_cast<std::size_t>(a)))
    if (other_vertex(t, static_cast<std::size_t>(e), a) == b) return e;
  throw std::logic_error("local mesh: no edge between two neighbourhood vertices");
}

int corner_index(const MeshTopology& t, int f, int v) {
  const auto corners = face(t, static_cast<std::size_t>(f));
  const auto it = std::find(corners.begin(), corners.end(), v);
  if (it == corners.end()) throw std::logic_error("local mesh: vertex not on the face");
  return static_cast<int>(it - corners.begin());
}

int corner(const MeshTopology& t, int f, int i) {
  const auto corners = face(t, static_cast<std::size_t>(f));
  return corners[static_cast<std::size_t>(wrap(i, static_cast<int>(corners.size())))];
}

int face_across(const MeshTopology& t, int e, int f) {
  const auto [f0, f1] = t.edge_faces[static_cast<std::size_t>(e)];
  return f0 == f ? f1 : f0;
}

/// The neighbourhood of vertex `centre` (Doo–Sabin: face) in the header's numbering, sector 0 at
/// `start` (a neighbour; Doo–Sabin: a corner; ignored on the boundary, where edge 0 starts).
void neighbourhood(const MeshTopology& t, MeshScheme scheme, int centre, int start, bool boundary,
                   std::vector<int>& out) {
  out.clear();
  if (scheme == MeshScheme::doo_sabin) {
    const int k = static_cast<int>(face(t, static_cast<std::size_t>(centre)).size());
    const int s = corner_index(t, centre, start);
    std::vector<int> g(static_cast<std::size_t>(k)), edge_quad(static_cast<std::size_t>(k));
    for (int i = 0; i < k; ++i) g[static_cast<std::size_t>(i)] = corner(t, centre, s + i);
    for (int i = 0; i < k; ++i)
      edge_quad[static_cast<std::size_t>(i)] = face_across(
          t, edge_between(t, g[static_cast<std::size_t>(i)], g[static_cast<std::size_t>((i + 1) % k)]),
          centre);
    for (int i = 0; i < k; ++i) {
      const int gi = g[static_cast<std::size_t>(i)], quad = edge_quad[static_cast<std::size_t>(i)];
      const int previous = edge_quad[static_cast<std::size_t>((i + k - 1) % k)];
      int corner_quad = -1;
      for (const int f : vertex_faces(t, static_cast<std::size_t>(gi)))
        if (f != centre && f != quad && f != previous) corner_quad = f;
      const int ci = corner_index(t, quad, gi);
      out.insert(out.end(), {gi, corner(t, quad, ci + 1), corner(t, quad, ci + 2),
                             corner(t, corner_quad, corner_index(t, corner_quad, gi) + 2)});
    }
    return;
  }
  const auto ring = vertex_edges(t, static_cast<std::size_t>(centre));
  const auto faces = vertex_faces(t, static_cast<std::size_t>(centre));
  const int n = static_cast<int>(ring.size()), F = static_cast<int>(faces.size());
  int s = 0;
  if (!boundary)
    while (s < n &&
           other_vertex(t, static_cast<std::size_t>(ring[static_cast<std::size_t>(s)]), centre) != start)
      ++s;
  const auto r = [&](int j) {
    return other_vertex(t, static_cast<std::size_t>(ring[static_cast<std::size_t>(wrap(s + j, n))]), centre);
  };
  const auto face_j = [&](int j) { return faces[static_cast<std::size_t>(wrap(s + j, F))]; };
  out.push_back(centre);
  for (int j = 0; j < n; ++j) {
    out.push_back(r(j));
    if (scheme == MeshScheme::catmull_clark && j < F)
      out.push_back(corner(t, face_j(j), corner_index(t, face_j(j), centre) + 2));
    if (scheme == MeshScheme::butterfly) {
      // p_j: opposite c in r_j's ring; at a boundary r_j (four edges), its other boundary neighbour.
      const int rj = r(j);
      const auto rj_ring = vertex_edges(t, static_cast<std::size_t>(rj));
      const int to_centre = edge_between(t, rj, centre);
      const auto at = std::find(rj_ring.begin(), rj_ring.end(), to_centre) - rj_ring.begin();
      const bool rim = t.boundary_vertex[static_cast<std::size_t>(rj)];
      if (rj_ring.size() != (rim ? 4U : 6U))
        throw std::logic_error("local mesh: a ring vertex is not regular");
      const int beyond = rim ? (at == 0 ? 3 : 0) : static_cast<int>((at + 3) % 6);
      out.push_back(other_vertex(t, static_cast<std::size_t>(rj_ring[static_cast<std::size_t>(beyond)]), rj));
      if (j >= F) continue;
      const int across = face_across(t, edge_between(t, rj, r(j + 1)), face_j(j));
      out.push_back(corner(t, across, corner_index(t, across, rj) + 1));
    }
  }
}

std::vector<int> neighbourhood(const MeshTopology& t, MeshScheme scheme, int centre, int start,
                               bool boundary) {
  std::vector<int> out;
  neighbourhood(t, scheme, centre, start, boundary, out);
  return out;
}

/// Weight of `column` in row `row` of the stencils.
double weight(const Stencils& s, int row, int column) {
  double w = 0;
  for (int k = s.offsets[static_cast<std::size_t>(row)]; k < s.offsets[static_cast<std::size_t>(row) + 1];
       ++k)
    if (s.columns[static_cast<std::size_t>(k)] == column) w += s.weights[static_cast<std::size_t>(k)];
  return w;
}

/// The candidate weighing most on `column` (ties: the first).
int heaviest(const Stencils& s, const std::vector<int>& candidates, int column) {
  int best = -1;
  double best_weight = -1;
  for (const int c : candidates) {
    const double w = weight(s, c, column);
    if (w > best_weight) {
      best_weight = w;
      best = c;
    }
  }
  return best;
}

}  // namespace detail

LocalMatrix local_matrix(MeshScheme scheme, int valence, const LocalOptions& options) {
  if (scheme == MeshScheme::doo_sabin && options.boundary && !options.interior_corners.empty()) {
    if (!options.sharp.empty() || options.corner || options.concave || options.rules != RuleSet::opensubdiv)
      throw InvalidInput(
          "doo-sabin: sharp edges, corners and rule sets are analysed for catmull-clark and loop "
          "only");
    if (static_cast<int>(options.interior_corners.size()) != valence)
      throw InvalidInput("doo-sabin: a face of " + std::to_string(valence) +
                         " corners touching the boundary needs " + std::to_string(valence) +
                         " interior-corner flags; " + std::to_string(options.interior_corners.size()) +
                         " given");
    return doo_sabin_boundary_matrix(options.interior_corners);
  }
  check_valence(scheme, valence, options);
  LocalMatrix out = empty_matrix(scheme, valence, options);
  if (const auto exact = exact_rules(scheme, valence, options)) {
    out.exact = RationalMatrix{.rows = exact->n, .cols = exact->n, .entries = exact->a};
    out.values.resize(exact->n, exact->n);
    for (int i = 0; i < exact->n; ++i)
      for (int j = 0; j < exact->n; ++j) out.values(i, j) = (*exact)(i, j).convert_to<long double>();
    return out;
  }
  const Dense<long double> S = rules<long double>(scheme, valence, options, long_cos);
  out.values = Eigen::Map<const Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      S.a.data(), S.n, S.n);
  return out;
}

LocalMatrix doo_sabin_boundary_matrix(const std::vector<char>& inner) {
  const int k = static_cast<int>(inner.size());
  const auto interior_count = std::count_if(inner.begin(), inner.end(), [](char c) { return c != 0; });
  if (k >= kMinValence && k <= kMaxValence && (interior_count == 0 || interior_count == k))
    throw InvalidInput("doo-sabin: a face touching the boundary has an interior corner and a boundary one; " +
                       std::string(interior_count == 0 ? "none" : "every one") + " of the " +
                       std::to_string(k) + " is interior");
  const LocalMatrix whole = local_matrix(MeshScheme::doo_sabin, k);
  const auto interior = [&](int i) { return inner[static_cast<std::size_t>(wrap(i, k))] != 0; };
  std::vector<int> keep;
  for (int i = 0; i < k; ++i) {
    keep.push_back(4 * i);
    if (interior(i) || interior(i + 1)) keep.insert(keep.end(), {4 * i + 1, 4 * i + 2});
    if (interior(i)) keep.push_back(4 * i + 3);
  }
  LocalMatrix out = whole;
  out.options.boundary = true;
  out.options.interior_corners.clear();
  for (const char c : inner) out.options.interior_corners.push_back(c != 0 ? 1 : 0);
  const auto N = static_cast<int>(keep.size());
  out.labels.clear();
  out.values.resize(N, N);
  for (int i = 0; i < N; ++i) {
    out.labels.push_back(whole.labels[static_cast<std::size_t>(keep[static_cast<std::size_t>(i)])]);
    for (int j = 0; j < N; ++j)
      out.values(i, j) = whole.values(keep[static_cast<std::size_t>(i)], keep[static_cast<std::size_t>(j)]);
  }
  if (whole.exact) {
    out.exact = RationalMatrix{.rows = N, .cols = N, .entries = {}};
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j)
        out.exact->entries.push_back(
            (*whole.exact)(keep[static_cast<std::size_t>(i)], keep[static_cast<std::size_t>(j)]));
  }
  return out;
}

std::string vertex_class(int valence, const LocalOptions& options) {
  switch (centre_rule(valence, options)) {
    case VertexRule::smooth:
      return "interior";
    case VertexRule::dart:
      return "dart";
    case VertexRule::crease:
      return options.boundary ? "boundary" : "crease";
    case VertexRule::corner:
      return "corner";
  }
  return "";
}

std::vector<int> sector_sizes(int valence, const LocalOptions& options) {
  if (!options.interior_corners.empty()) {  // Doo–Sabin: the runs of interior corners
    const std::vector<char>& inner = options.interior_corners;
    const auto k = inner.size();
    std::vector<int> runs;
    for (std::size_t i = 0; i < k; ++i)
      if (inner[i] != 0 && inner[(i + k - 1) % k] == 0) {
        int m = 0;
        while (inner[(i + static_cast<std::size_t>(m)) % k] != 0) ++m;
        runs.push_back(m);
      }
    return runs;
  }
  const std::vector<int> sharp = sharp_edges(valence, options);
  if (sharp.size() < 2 && !options.boundary) return {valence};
  std::vector<int> out;
  for (std::size_t i = 0; i + 1 < sharp.size(); ++i) out.push_back(sharp[i + 1] - sharp[i]);
  if (!options.boundary) out.push_back(valence - sharp.back() + sharp.front());
  return out;
}

Mesh local_mesh(MeshScheme scheme, int valence, const LocalOptions& options, int rings) {
  check_valence(scheme, valence, options);
  Mesh m;
  switch (scheme) {
    case MeshScheme::catmull_clark:
      m = primal_local_mesh(true, valence, options.boundary, rings);
      break;
    case MeshScheme::doo_sabin:
      return dual_mesh(primal_local_mesh(true, valence, false, rings + 1));
    default:
      m = primal_local_mesh(false, valence, options.boundary, rings);
  }
  // The sharp edges run out along their rays (vertex j + 1 … of the ray: r_j is vertex j + 1 on the
  // closed fan by construction, found by the walk below on either fan).
  m.tags.boundary = options.rule;
  m.tags.rules = options.rules;
  if (options.concave && options.rules == RuleSet::blz) m.tags.concave = {0};
  if (options.corner) m.tags.corners.push_back({0, kInfiniteSharpness});
  if (!options.sharp.empty()) {
    const MeshTopology t = build_topology(m, "local mesh");
    const auto ring = vertex_edges(t, 0);
    for (const int j : options.sharp) {
      int previous = 0, v = other_vertex(t, static_cast<std::size_t>(ring[static_cast<std::size_t>(j)]), 0);
      m.tags.creases.push_back({previous, v, kInfiniteSharpness});
      // Straight on: the edge opposite the one we came by (valence 4 or 6 ring vertices).
      for (int step = 1; step < rings; ++step) {
        const auto around = vertex_edges(t, static_cast<std::size_t>(v));
        const int m_edges = static_cast<int>(around.size());
        if (t.boundary_vertex[static_cast<std::size_t>(v)]) break;
        const int back = edge_between(t, v, previous);
        const auto at = static_cast<int>(std::find(around.begin(), around.end(), back) - around.begin());
        const int next = other_vertex(
            t, static_cast<std::size_t>(around[static_cast<std::size_t>((at + m_edges / 2) % m_edges)]), v);
        m.tags.creases.push_back({v, next, kInfiniteSharpness});
        previous = v;
        v = next;
      }
    }
  }
  return m;
}

namespace detail {

LocalRefinement refine_local(MeshScheme scheme, int n, const LocalOptions& options, int rings) {
  LocalRefinement out;
  out.mesh = local_mesh(scheme, n, options, rings);
  const int steps = scheme == MeshScheme::sqrt3 ? 2 : 1;
  out.refinement = refine_topology(out.mesh, scheme, steps, MeshOptions{.max_bytes = 1'000'000'000});
  const MeshRefinement& r = out.refinement;
  out.stencils = steps == 1 ? r.steps.front() : stencil_table(r);
  const Stencils& stencils = out.stencils;
  const MeshTopology& t0 = r.levels.front();
  const MeshTopology& t1 = r.levels.back();
  out.start = scheme == MeshScheme::doo_sabin ? face(t0, 0)[0] : 1;
  if (scheme == MeshScheme::doo_sabin) {
    double best = -1;
    for (std::size_t f = 0; f < face_count(t1); ++f) {
      if (face(t1, f).size() != static_cast<std::size_t>(n)) continue;
      double w = 0;
      for (const int c : face(t1, f))
        for (const int g : face(t0, 0)) w += weight(stencils, c, g);
      if (w > best) {
        best = w;
        out.child_centre = static_cast<int>(f);
      }
    }
    const auto corners = face(t1, static_cast<std::size_t>(out.child_centre));
    out.child_start = heaviest(stencils, std::vector<int>(corners.begin(), corners.end()), out.start);
    return out;
  }
  std::vector<int> candidates;
  for (int v = 0; v < t1.vertex_count; ++v)
    if (valence(t1, static_cast<std::size_t>(v)) == n &&
        t1.boundary_vertex[static_cast<std::size_t>(v)] == t0.boundary_vertex[0])
      candidates.push_back(v);
  // Catmull–Clark's and Loop's vertex points keep their vertices' indices; elsewhere the child
  // weighing most on the centre (a concave corner's flattened edge points may weigh more than 1 on it).
  out.child_centre = scheme == MeshScheme::catmull_clark || scheme == MeshScheme::loop
                         ? 0
                         : heaviest(stencils, candidates, 0);
  std::vector<int> ring;
  for (const int e : vertex_edges(t1, static_cast<std::size_t>(out.child_centre)))
    ring.push_back(other_vertex(t1, static_cast<std::size_t>(e), out.child_centre));
  out.child_start = heaviest(stencils, ring, out.start);
  return out;
}

std::vector<int> canonical_order(const MeshTopology& t, MeshScheme scheme, int centre, int start, int depth) {
  std::vector<int> order, distance(static_cast<std::size_t>(t.vertex_count), -1);
  std::vector<int> reached_from;  // parallel to order
  const auto visit = [&](int v, int from, int d) {
    distance[static_cast<std::size_t>(v)] = d;
    order.push_back(v);
    reached_from.push_back(from);
  };
  if (scheme == MeshScheme::doo_sabin) {
    const int k = static_cast<int>(face(t, static_cast<std::size_t>(centre)).size());
    const int s = corner_index(t, centre, start);
    for (int i = 0; i < k; ++i) visit(corner(t, centre, s + i), corner(t, centre, s + i + 1), 0);
  } else {
    visit(centre, start, 0);
  }
  // Around a boundary vertex the local mesh is an open fan: its boundary is the real one (its outer
  // rim lies beyond `depth` by construction).
  const bool open = scheme != MeshScheme::doo_sabin && t.boundary_vertex[static_cast<std::size_t>(centre)];
  for (std::size_t q = 0; q < order.size(); ++q) {
    const int v = order[q];
    if (distance[static_cast<std::size_t>(v)] == depth) continue;
    if (!open && t.boundary_vertex[static_cast<std::size_t>(v)])
      throw std::logic_error("local mesh: too few rings for the region asked");
    const auto ring = vertex_edges(t, static_cast<std::size_t>(v));
    const int m = static_cast<int>(ring.size());
    int at = 0;
    while (at < m && other_vertex(t, static_cast<std::size_t>(ring[static_cast<std::size_t>(at)]), v) !=
                         reached_from[q])
      ++at;
    if (at == m) throw std::logic_error("local mesh: a vertex is not next to the one it was reached from");
    for (int i = 0; i < m; ++i) {
      const int w =
          other_vertex(t, static_cast<std::size_t>(ring[static_cast<std::size_t>((at + i) % m)]), v);
      if (distance[static_cast<std::size_t>(w)] < 0) visit(w, v, distance[static_cast<std::size_t>(v)] + 1);
    }
  }
  return order;
}

}  // namespace detail

LocalMatrix refined_local_matrix(MeshScheme scheme, int n, const LocalOptions& options) {
  LocalMatrix out = empty_matrix(scheme, n, options);
  const detail::LocalRefinement local = detail::refine_local(scheme, n, options, 3);
  const Stencils& stencils = local.stencils;
  const MeshTopology& t0 = local.refinement.levels.front();
  const MeshTopology& t1 = local.refinement.levels.back();
  const std::vector<int> old = neighbourhood(t0, scheme, local.centre, local.start, options.boundary);
  const std::vector<int> child =
      neighbourhood(t1, scheme, local.child_centre, local.child_start, options.boundary);
  std::map<int, int> position;
  for (std::size_t j = 0; j < old.size(); ++j) position[old[j]] = static_cast<int>(j);
  const auto N = static_cast<Eigen::Index>(old.size());
  out.values = LongMatrix::Zero(N, N);
  for (Eigen::Index i = 0; i < N; ++i) {
    const int row = child[static_cast<std::size_t>(i)];
    for (int k = stencils.offsets[static_cast<std::size_t>(row)];
         k < stencils.offsets[static_cast<std::size_t>(row) + 1]; ++k) {
      const auto it = position.find(stencils.columns[static_cast<std::size_t>(k)]);
      const double w = stencils.weights[static_cast<std::size_t>(k)];
      if (it == position.end()) {
        if (w != 0) throw std::logic_error("local matrix: the neighbourhood is not invariant");
        continue;
      }
      out.values(i, it->second) += w;
    }
  }
  return out;
}

namespace {

std::string curvature_verdict(std::optional<long double> ratio) {
  if (!ratio || *ratio > 1 + 1e-9L) return "zero";
  if (*ratio < 1 - 1e-9L) return "unbounded";
  return "bounded";
}

/// A multiple eigenvalue with a Jordan block of size m comes out of a backward-stable solver as m
/// values scattered by ~ε^{1/m} around it (3e-7 for m = 3 in long double; Butterfly's ¼ at
/// valence 6), while their mean stays within ~ε. Values closer than kCluster (single linkage) are
/// taken as one multiple eigenvalue and each replaced by the mean.
constexpr long double kCluster = 1e-6L;

std::vector<std::complex<long double>> cluster_means(std::vector<std::complex<long double>> values) {
  const std::size_t N = values.size();
  std::vector<std::size_t> cluster(N);
  std::iota(cluster.begin(), cluster.end(), 0);
  const auto root = [&](std::size_t i) {
    while (cluster[i] != i) i = cluster[i];
    return i;
  };
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i + 1; j < N; ++j)
      if (std::abs(values[i] - values[j]) < kCluster) cluster[root(j)] = root(i);
  std::vector<std::complex<long double>> sum(N, 0);
  std::vector<int> count(N, 0);
  for (std::size_t i = 0; i < N; ++i) {
    sum[root(i)] += values[i];
    ++count[root(i)];
  }
  for (std::size_t i = 0; i < N; ++i) {
    const std::size_t r = root(i);
    // The mean of a cluster of conjugate pairs is real: drop its round-off imaginary part.
    std::complex<long double> mean = sum[r] / static_cast<long double>(count[r]);
    if (std::abs(mean.imag()) < kCluster) mean.imag(0);
    values[i] = mean;
  }
  return values;
}

/// The last `count` right singular vectors of A: an orthonormal basis of its kernel when its
/// dimension is `count`.
LongMatrix kernel(const LongMatrix& A, Eigen::Index count) {
  const Eigen::JacobiSVD<LongMatrix> svd(A, Eigen::ComputeFullV);
  return svd.matrixV().rightCols(count);
}

}  // namespace

LocalSpectrum local_spectrum(const LocalMatrix& matrix) {
  const LongMatrix& S = matrix.values;
  const auto N = S.rows();
  LocalSpectrum out;
  const long double tol = out.tolerance;
  const Eigen::EigenSolver<LongMatrix> solver(S, false);
  const auto& ev = solver.eigenvalues();
  out.eigenvalues = cluster_means(std::vector<std::complex<long double>>(ev.data(), ev.data() + N));
  std::sort(out.eigenvalues.begin(), out.eigenvalues.end(),
            [&](const std::complex<long double>& a, const std::complex<long double>& b) {
              if (std::abs(std::abs(a) - std::abs(b)) > tol) return std::abs(a) > std::abs(b);
              if (std::abs(a.real() - b.real()) > tol) return a.real() > b.real();
              return a.imag() > b.imag();
            });
  const auto lambda = [&](std::size_t i) {
    return i < out.eigenvalues.size() ? out.eigenvalues[i] : std::complex<long double>(0);
  };
  out.dominant_simple = std::abs(lambda(0) - 1.0L) < tol && std::abs(lambda(1)) < 1 - tol;
  out.subdominant = lambda(1).real();
  out.second = lambda(2).real();
  const bool real_positive =
      std::abs(lambda(1).imag()) < tol && std::abs(lambda(2).imag()) < tol && out.second > tol;
  out.subdominant_pair = real_positive && std::abs(lambda(1) - lambda(2)) < tol;
  out.mu = lambda(3);
  out.gap = real_positive && std::abs(out.mu) < out.second - tol;
  if (std::abs(out.mu) > tol) out.curvature_ratio = out.second * out.second / std::abs(out.mu);
  out.curvature = curvature_verdict(out.curvature_ratio);

  const LongMatrix I = LongMatrix::Identity(N, N);
  if (out.subdominant_pair) {
    out.subdominant_basis = kernel(S - out.subdominant * I, 2);
  } else {
    out.subdominant_basis.resize(N, 2);
    out.subdominant_basis.col(0) = kernel(S - out.subdominant * I, 1);
    out.subdominant_basis.col(1) = kernel(S - out.second * I, 1);
  }
  out.limit_stencil = kernel((S - I).transpose(), 1);
  out.limit_stencil /= out.limit_stencil.sum();
  const LongVector values = (LongVector(2) << out.subdominant, out.second).finished();
  out.residual =
      (S * out.subdominant_basis - out.subdominant_basis * values.asDiagonal()).cwiseAbs().maxCoeff();
  out.residual =
      std::max(out.residual,
               (out.limit_stencil.transpose() * S - out.limit_stencil.transpose()).cwiseAbs().maxCoeff());
  return out;
}

}  // namespace cifs::subdivision
