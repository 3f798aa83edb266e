// SPDX-License-Identifier: MIT
// Independent references for the nurbs tests: B-splines straight from the Cox–de Boor recursion
// (long double, 0/0 = 0), Boehm insertion from its textbook formula, random knot vectors, curves and
// surfaces, and error measures. Nothing here calls the algorithms under test.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs_test {

inline constexpr double kEps = std::numeric_limits<double>::epsilon();

/// The span of u straight from the definition: the last non-empty [t_j, t_{j+1}) with t_j ≤ u,
/// j in [d, n−1] (so the domain end belongs to the last non-empty span).
inline int definition_span(const cifs::nurbs::Knots& t, int d, double u) {
  const int n = static_cast<int>(t.size()) - d - 1;
  int k = d;
  for (int j = d; j < n; ++j)
    if (t[static_cast<std::size_t>(j)] <= u &&
        t[static_cast<std::size_t>(j)] < t[static_cast<std::size_t>(j + 1)])
      k = j;
  return k;
}

/// Catch prints doubles in fixed notation with 10 decimals, which shows an error of 3e-12 against a
/// tolerance of 1e-12 as "0.0 <= 0.0": print 20.
inline const int catch_double_precision = (Catch::StringMaker<double>::precision = 20, 0);

using cifs::Point;
using cifs::Points;
using cifs::nurbs::Curve;
using cifs::nurbs::Knots;
using cifs::nurbs::Surface;
using Real = long double;
using RealVec = std::vector<Real>;
using Rng = std::mt19937_64;

// ---------------------------------------------------------------------------------------------
// B-splines from the definition.

/// The k-th derivative of every N_{i,p}(u), i = 0..#t−p−2, by the Cox–de Boor recursion
/// N_{i,q} = (u−t_i)/(t_{i+q}−t_i) N_{i,q−1} + (t_{i+q+1}−u)/(t_{i+q+1}−t_{i+1}) N_{i+1,q−1} and its
/// derivative N'_{i,q} = q (N_{i,q−1}/(t_{i+q}−t_i) − N_{i+1,q−1}/(t_{i+q+1}−t_{i+1})), with 0/0 = 0.
/// Degree 0 is [t_i ≤ u < t_{i+1}] (right-continuous), or [t_i < u ≤ t_{i+1}] when `left` (the left
/// limit, which is how the domain end t_n is evaluated).
/// The knots as the reference reads them, in long double, and the parameter x among them: a knot
/// vector as stored and x = u, or (closed curves, ref_closed_knots) the exact periodic knots
/// relative to u and x = 0.
struct RefKnots {
  RealVec t;
  Real x = 0;
  bool left = false;  // evaluate by the left limit (the domain end)
  int span = -1;      // ≥ 0: the interval of x, decided outside (the degree-0 indicator)
};

inline RealVec ref_basis(const RefKnots& knots, int p, int k = 0) {
  const RealVec& t = knots.t;
  const bool left = knots.left;
  const int m = static_cast<int>(t.size());
  if (k > p) return RealVec(static_cast<std::size_t>(m - p - 1), Real(0));
  const Real x = knots.x;
  auto T = [&](int i) { return t[static_cast<std::size_t>(i)]; };
  auto ratio = [](Real num, Real den) { return den == 0 ? Real(0) : num / den; };
  RealVec N(static_cast<std::size_t>(m - 1));
  for (int i = 0; i + 1 < m; ++i)
    N[static_cast<std::size_t>(i)] = knots.span >= 0 ? i == knots.span
                                     : left          ? (T(i) < x && x <= T(i + 1))
                                                     : (T(i) <= x && x < T(i + 1));
  for (int q = 1; q <= p; ++q) {
    RealVec M(static_cast<std::size_t>(m - q - 1));
    for (int i = 0; i < m - q - 1; ++i) {
      const Real a = N[static_cast<std::size_t>(i)], b = N[static_cast<std::size_t>(i + 1)];
      const Real d0 = T(i + q) - T(i), d1 = T(i + q + 1) - T(i + 1);
      M[static_cast<std::size_t>(i)] = q <= p - k ? ratio(x - T(i), d0) * a + ratio(T(i + q + 1) - x, d1) * b
                                                  : q * (ratio(a, d0) - ratio(b, d1));
    }
    N = std::move(M);
  }
  return N;
}

inline RealVec ref_basis(const Knots& t, int p, double u, bool left, int k = 0) {
  return ref_basis(RefKnots{RealVec(t.begin(), t.end()), u, left}, p, k);
}

/// Whether the library evaluates u by the left limit: only at the domain end t_n.
inline bool at_end(const Knots& t, int p, double u) {
  return u == t[t.size() - static_cast<std::size_t>(p) - 1];
}

inline RefKnots plain_knots(const Knots& t, int p, double u) {
  return {RealVec(t.begin(), t.end()), u, at_end(t, p, u)};
}

/// Homogeneous k-th derivative Σ N_i^{(k)}(u) H_i over all control rows (long double).
inline Eigen::Matrix<Real, 1, Eigen::Dynamic> ref_homogeneous(const RefKnots& t, int p, const Points& H,
                                                              int k = 0) {
  const RealVec N = ref_basis(t, p, k);
  Eigen::Matrix<Real, 1, Eigen::Dynamic> out = Eigen::Matrix<Real, 1, Eigen::Dynamic>::Zero(H.cols());
  for (Eigen::Index i = 0; i < H.rows(); ++i) out += N[static_cast<std::size_t>(i)] * H.row(i).cast<Real>();
  return out;
}

inline Eigen::Matrix<Real, 1, Eigen::Dynamic> ref_homogeneous(const Knots& t, int p, const Points& H,
                                                              double u, int k = 0) {
  return ref_homogeneous(plain_knots(t, p, u), p, H, k);
}

inline double binomial(int n, int k) {
  double b = 1;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

/// Cartesian derivatives 0..order: non-rational directly, rational by Leibniz' rule on A = w·C.
inline Points ref_derivatives(const RefKnots& t, int p, const Points& H, bool rational, int order) {
  const Eigen::Index dim = H.cols() - (rational ? 1 : 0);
  std::vector<Eigen::Matrix<Real, 1, Eigen::Dynamic>> A;
  for (int k = 0; k <= order; ++k) A.push_back(ref_homogeneous(t, p, H, k));
  std::vector<Eigen::Matrix<Real, 1, Eigen::Dynamic>> C(static_cast<std::size_t>(order + 1));
  for (int k = 0; k <= order; ++k) {
    Eigen::Matrix<Real, 1, Eigen::Dynamic> v = A[static_cast<std::size_t>(k)].head(dim);
    if (rational) {
      for (int i = 1; i <= k; ++i)
        v -= static_cast<Real>(binomial(k, i)) * A[static_cast<std::size_t>(i)](dim) *
             C[static_cast<std::size_t>(k - i)];
      v /= A[0](dim);
    }
    C[static_cast<std::size_t>(k)] = v;
  }
  Points out(order + 1, dim);
  for (int k = 0; k <= order; ++k) out.row(k) = C[static_cast<std::size_t>(k)].cast<double>();
  return out;
}

inline Points ref_derivatives(const Knots& t, int p, const Points& H, bool rational, double u, int order) {
  return ref_derivatives(plain_knots(t, p, u), p, H, rational, order);
}

inline Point ref_point(const Knots& t, int p, const Points& H, bool rational, double u) {
  return ref_derivatives(t, p, H, rational, u, 0).row(0);
}

/// Knot vector of a periodic curve: t_j = b_{(j−d) mod m} + ⌊(j−d)/m⌋·T in exact arithmetic. In
/// floating point the period's own knots are the breakpoints as given, the neighbouring copies are
/// measured back from b_0 (t = b_0 − (b_m − b_i)) and forward from b_m (t = b_m + (b_i − b_0)) so that
/// the seam keeps its multiplicity, and further copies are the neighbouring period shifted by T.
inline Knots ref_periodic_knots(const Knots& b, int d) {
  const int m = static_cast<int>(b.size()) - 1;
  const double T = b.back() - b.front();
  std::map<int, double> t;  // by s = j − d
  for (int s = 0; s <= m; ++s) t[s] = b[static_cast<std::size_t>(s)];
  for (int s = -1; s >= -d; --s)
    t[s] = s >= -m ? b.front() - (b.back() - b[static_cast<std::size_t>(s + m)]) : t[s + m] - T;
  for (int s = m + 1; s <= m + d; ++s)
    t[s] = s <= 2 * m ? b.back() + (b[static_cast<std::size_t>(s - m)] - b.front()) : t[s - m] + T;
  Knots out;
  for (const auto& [s, x] : t) out.push_back(x);
  return out;
}

/// The exact periodic knots t_j = b_k + q·T of breakpoints b (k = (j − d) mod m, q = ⌊(j − d)/m⌋), relative
/// to u: (b_k − u) + q·(b_m − b_0) in long double, where the differences of doubles are exact and only
/// the sum rounds, relative to itself — unlike the stored knots, whose rounding u·|t| is a relative
/// error u·|t|/h next to an interval h (1e-9 for |t| = 3, h = 1e-6). x = 0. The interval of u is
/// found among the doubles (ref_periodic_knots: exact in the period), as the sums may round (u a
/// denormal next to b_m: b_k − u is not exact).
inline RefKnots ref_closed_knots(const Knots& b, int d, double u) {
  const int m = static_cast<int>(b.size()) - 1;
  const Real period = static_cast<Real>(b.back()) - static_cast<Real>(b.front());
  RefKnots out{RealVec(), 0, u == b.back()};
  const Knots t = ref_periodic_knots(b, d);
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
    if (out.left ? (t[i] < u && u <= t[i + 1]) : (t[i] <= u && u < t[i + 1])) out.span = static_cast<int>(i);
  for (int j = 0; j < m + 2 * d + 1; ++j) {
    const int s = j - d;
    const int q = s >= 0 ? s / m : -((m - 1 - s) / m);
    out.t.push_back((static_cast<Real>(b[static_cast<std::size_t>(s - q * m)]) - static_cast<Real>(u)) +
                    q * period);
  }
  return out;
}

/// The naive formula, rounded at every step, for an ulp-level comparison.
inline Knots naive_periodic_knots(const Knots& b, int d) {
  const int m = static_cast<int>(b.size()) - 1;
  const double T = b.back() - b.front();
  Knots t;
  for (int j = 0; j < m + 2 * d + 1; ++j) {
    const int s = j - d;
    const int q = static_cast<int>(std::floor(static_cast<double>(s) / m));
    t.push_back(b[static_cast<std::size_t>(s - q * m)] + q * T);
  }
  return t;
}

/// Blossom of the piece on span k by de Boor's triangle with argument x_r at level r, on the weights
/// of the d + 1 control rows (long double): returns W with blossom = Σ_j W_j H_{k−d+j}.
/// With `origin`: the knots are t − origin (ref_closed_knots) and so are the arguments.
inline RealVec ref_blossom_weights(const RealVec& t, int d, const std::vector<double>& x, int k,
                                   Real origin) {
  const auto D = static_cast<std::size_t>(d);
  std::vector<RealVec> c(D + 1, RealVec(D + 1, Real(0)));
  for (std::size_t j = 0; j <= D; ++j) c[j][j] = 1;
  for (int r = 1; r <= d; ++r)
    for (int j = d; j >= r; --j) {
      const int i = k - d + j;
      const Real ti = t[static_cast<std::size_t>(i)], tr = t[static_cast<std::size_t>(i + d + 1 - r)];
      const Real a = (static_cast<Real>(x[static_cast<std::size_t>(r - 1)]) - origin - ti) / (tr - ti);
      for (std::size_t q = 0; q <= D; ++q)
        c[static_cast<std::size_t>(j)][q] =
            (1 - a) * c[static_cast<std::size_t>(j - 1)][q] + a * c[static_cast<std::size_t>(j)][q];
    }
  return c[D];
}

inline RealVec ref_blossom_weights(const Knots& t, int d, const std::vector<double>& x, int k) {
  return ref_blossom_weights(RealVec(t.begin(), t.end()), d, x, k, 0);
}

/// The arguments reordered for a well-conditioned triangle: the farthest from the span [t_k, t_{k+1}]
/// at the first (widest) level, the nearest at the last (the blossom is symmetric).
inline std::vector<double> conditioned_order(const Knots& t, std::vector<double> x, int k) {
  const double a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>(k + 1)];
  auto dist = [&](double v) { return v < a ? a - v : v > b ? v - b : 0.0; };
  std::stable_sort(x.begin(), x.end(), [&](double p, double q) { return dist(p) > dist(q); });
  return x;
}

inline Point ref_blossom_of(const RealVec& W, int d, const Points& H, int k, double* l1) {
  Eigen::Matrix<Real, 1, Eigen::Dynamic> out = Eigen::Matrix<Real, 1, Eigen::Dynamic>::Zero(H.cols());
  Real sum = 0;
  for (int j = 0; j <= d; ++j) {
    out += W[static_cast<std::size_t>(j)] * H.row(k - d + j).cast<Real>();
    sum += std::abs(W[static_cast<std::size_t>(j)]);
  }
  if (l1) *l1 = static_cast<double>(sum);
  return out.cast<double>();
}

inline Point ref_blossom(const Knots& t, int d, const Points& H, const std::vector<double>& x, int k,
                         double* l1 = nullptr) {
  return ref_blossom_of(ref_blossom_weights(t, d, x, k), d, H, k, l1);
}

// ---------------------------------------------------------------------------------------------
// Boehm insertion (textbook formula, no span search): Q_i = α_i P_i + (1 − α_i) P_{i−1} with
// α_i = 1 if t_{i+p} ≤ u, 0 if t_i ≥ u, (u − t_i)/(t_{i+p} − t_i) otherwise.

struct RefSpline {
  int p;
  Knots t;
  Points P;
};

inline RefSpline ref_boehm(const RefSpline& s, double u) {
  const auto n = s.P.rows();
  RefSpline out{s.p, s.t, Points(n + 1, s.P.cols())};
  out.t.insert(std::upper_bound(out.t.begin(), out.t.end(), u), u);
  for (Eigen::Index i = 0; i <= n; ++i) {
    const double ti = s.t[static_cast<std::size_t>(i)];
    const double tip = s.t[static_cast<std::size_t>(i + s.p)];
    const double a = tip <= u ? 1.0 : ti >= u ? 0.0 : (u - ti) / (tip - ti);
    Point q = Point::Zero(s.P.cols());
    if (a != 0) q += a * s.P.row(i);
    if (a != 1) q += (1 - a) * s.P.row(i - 1);
    out.P.row(i) = q;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Random data.

inline double uniform(Rng& rng, double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(rng);
}
inline int uniform_int(Rng& rng, int a, int b) {
  return std::uniform_int_distribution<int>(a, b)(rng);
}
inline bool coin(Rng& rng, double p = 0.5) {
  return uniform(rng, 0, 1) < p;
}

/// Multiplicities in [1, maxmult] summing to `total` (mostly simple knots).
inline std::vector<int> random_mults(Rng& rng, int total, int maxmult) {
  std::vector<int> m;
  while (total > 0) {
    int k = maxmult > 1 && coin(rng, 0.25) ? uniform_int(rng, 2, maxmult) : 1;
    k = std::min(k, total);
    m.push_back(k);
    total -= k;
  }
  return m;
}

/// `count` + 1 increasing values: the last gap closes a period for closed curves. Several spacing
/// modes: integers, log-uniform gaps over 6 decades, gaps of 1 or 1e-6, near-uniform.
inline std::vector<double> random_values(Rng& rng, std::size_t count, int mode) {
  std::vector<double> v;
  double x = mode == 0 ? uniform_int(rng, -3, 3) : uniform(rng, -2, 2);
  for (std::size_t i = 0; i <= count; ++i) {
    v.push_back(x);
    switch (mode) {
      case 0:
        x += 1;
        break;
      case 1:
        x += std::pow(10.0, uniform(rng, -6, 0));
        break;
      case 2:
        x += coin(rng) ? 1.0 : 1e-6;
        break;
      default:
        x += uniform(rng, 0.5, 1.5);
        break;
    }
  }
  return v;
}

inline Knots expand(const std::vector<double>& values, const std::vector<int>& mults) {
  Knots t;
  for (std::size_t i = 0; i < mults.size(); ++i)
    t.insert(t.end(), static_cast<std::size_t>(mults[i]), values[i]);
  return t;
}

enum class Kind { clamped, unclamped, closed };

inline const char* kind_name(Kind k) {
  return k == Kind::clamped ? "clamped" : k == Kind::unclamped ? "unclamped" : "closed";
}

/// Knot vector of `n` control points: clamped (end multiplicity d+1) or unclamped; interior
/// multiplicities up to `maxmult` (default d). Retries until the domain is not empty.
inline Knots random_knots(Rng& rng, int d, int n, bool clamped, int maxmult = -1, int mode = -1) {
  if (maxmult < 0) maxmult = d;
  if (mode < 0) mode = uniform_int(rng, 0, 3);
  for (;;) {
    std::vector<int> mults;
    if (clamped) {
      mults.push_back(d + 1);
      const auto inner = random_mults(rng, n - d - 1, maxmult);
      mults.insert(mults.end(), inner.begin(), inner.end());
      mults.push_back(d + 1);
    } else {
      mults = random_mults(rng, n + d + 1, maxmult);
    }
    const Knots t = expand(random_values(rng, mults.size(), mode), mults);
    if (t[static_cast<std::size_t>(d)] < t[static_cast<std::size_t>(n)]) return t;
  }
}

/// Breakpoints of a closed curve of degree d: m + 1 values, multiplicities up to d (counting the
/// seam once); the seam's copies are sometimes split between the start and the end (b_{m−1} = b_m).
inline Knots random_breaks(Rng& rng, int d, int m_min, int m_max, int mode = -1) {
  if (mode < 0) mode = uniform_int(rng, 0, 3);
  for (;;) {
    const int m = uniform_int(rng, m_min, m_max);
    const auto mults = random_mults(rng, m, d);
    const auto v = random_values(rng, mults.size(), mode);  // v.back() closes the period
    const int a = coin(rng) ? mults[0] : uniform_int(rng, 1, mults[0]);
    Knots b(static_cast<std::size_t>(a), v[0]);
    for (std::size_t i = 1; i < mults.size(); ++i)
      b.insert(b.end(), static_cast<std::size_t>(mults[i]), v[i]);
    b.insert(b.end(), static_cast<std::size_t>(mults[0] - a + 1), v.back());
    if (static_cast<int>(b.size()) == m + 1 && m >= 2) return b;
  }
}

inline Points random_points(Rng& rng, Eigen::Index n, Eigen::Index dim) {
  const double scale = std::pow(10.0, uniform(rng, -3, 3));
  Points P(n, dim);
  for (Eigen::Index j = 0; j < dim; ++j) {
    const double centre = scale * uniform(rng, -2, 2);
    for (Eigen::Index i = 0; i < n; ++i) P(i, j) = centre + scale * uniform(rng, -1, 1);
  }
  return P;
}

inline Eigen::VectorXd random_weights(Rng& rng, Eigen::Index n) {
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) w(i) = std::pow(10.0, uniform(rng, -3, 3));
  return w;
}

/// Homogeneous rows (w·x, w), written out here so that the tests own their reference data.
inline Points to_rows(const Points& cart, const Eigen::VectorXd& w) {
  if (w.size() == 0) return cart;
  Points H(cart.rows(), cart.cols() + 1);
  for (Eigen::Index i = 0; i < cart.rows(); ++i) {
    H.row(i).head(cart.cols()) = w(i) * cart.row(i);
    H(i, cart.cols()) = w(i);
  }
  return H;
}

/// A random curve and the test's own copy of its data.
struct RandomCurve {
  Curve c;
  int degree = 0;
  Knots knots;   // full knot vector (periodic for closed curves)
  Knots breaks;  // closed curves: the period's breakpoints
  Points H;      // stored rows, expanded for closed curves
  Points cart;   // distinct Cartesian control points
  Eigen::VectorXd w;
  bool rational = false;
  Kind kind = Kind::clamped;
  double scale = 1;       // largest |Cartesian coordinate|: the scale of every curve point
  double lo = 0, hi = 1;  // domain
  std::string what;
};

/// `mode` picks the knot spacing (see random_values; −1: random).
inline RandomCurve random_curve(Rng& rng, int d, int dim, bool rational, Kind kind, int extra_max = 8,
                                int mode = -1) {
  RandomCurve r;
  r.degree = d;
  r.kind = kind;
  r.rational = rational;
  if (kind == Kind::closed) {
    r.breaks = random_breaks(rng, d, 2, 2 + extra_max, mode);
    const auto m = static_cast<Eigen::Index>(r.breaks.size()) - 1;
    r.cart = random_points(rng, m, dim);
    if (rational) r.w = random_weights(rng, m);
    r.c = cifs::nurbs::make_closed_curve(d, r.breaks, r.cart, r.w);
    r.knots = ref_periodic_knots(r.breaks, d);
    const Points distinct = to_rows(r.cart, r.w);
    r.H.resize(m + d, distinct.cols());
    for (Eigen::Index i = 0; i < m + d; ++i) r.H.row(i) = distinct.row(i % m);
  } else {
    const int n = d + 1 + uniform_int(rng, 0, extra_max);
    r.knots = random_knots(rng, d, n, kind == Kind::clamped, -1, mode);
    r.cart = random_points(rng, n, dim);
    if (rational) r.w = random_weights(rng, n);
    r.c = cifs::nurbs::make_curve(d, r.knots, r.cart, r.w);
    r.H = to_rows(r.cart, r.w);
  }
  r.scale = r.cart.cwiseAbs().maxCoeff();
  const auto n = static_cast<std::size_t>(r.H.rows());
  r.lo = r.knots[static_cast<std::size_t>(d)];
  r.hi = r.knots[n];
  std::ostringstream s;
  s.precision(17);
  s << kind_name(kind) << (rational ? " rational" : "") << " degree " << d << " dim " << dim << " n "
    << r.H.rows() << " knots [";
  for (double t : r.knots) s << t << ' ';
  s << "]";
  if (rational) s << " weights [" << r.w.transpose() << "]";
  r.what = s.str();
  return r;
}

/// The reference's knots of r at u: the exact periodic knots for a closed curve, the knot vector
/// otherwise.
inline RefKnots ref_knots(const RandomCurve& r, double u) {
  return r.kind == Kind::closed ? ref_closed_knots(r.breaks, r.degree, u) : plain_knots(r.knots, r.degree, u);
}
inline Points ref_derivatives(const RandomCurve& r, double u, int order) {
  return ref_derivatives(ref_knots(r, u), r.degree, r.H, r.rational, order);
}
inline Point ref_point(const RandomCurve& r, double u) {
  return ref_derivatives(r, u, 0).row(0);
}

/// ref_blossom of r's piece on span k: closed curves on the exact periodic knots relative to t_k.
inline Point ref_blossom(const RandomCurve& r, const std::vector<double>& x, int k, double* l1 = nullptr) {
  if (r.kind != Kind::closed) return ref_blossom(r.knots, r.degree, r.H, x, k, l1);
  const double origin = r.knots[static_cast<std::size_t>(k)];
  const RealVec t = ref_closed_knots(r.breaks, r.degree, origin).t;
  return ref_blossom_of(ref_blossom_weights(t, r.degree, x, k, origin), r.degree, r.H, k, l1);
}

/// A random curve of random kind, degree 1..max_degree, dimension 1..4.
inline RandomCurve any_curve(Rng& rng, int max_degree = 10) {
  const int d = uniform_int(rng, 1, max_degree);
  const int dim = uniform_int(rng, 1, 4);
  const auto kind = static_cast<Kind>(uniform_int(rng, 0, 2));
  return random_curve(rng, d, dim, coin(rng), kind);
}

/// Parameters that exercise a curve: both ends, every knot of the domain and one ulp on either side,
/// and `count` random values.
inline std::vector<double> probe_parameters(Rng& rng, const Knots& t, int d, int count) {
  const double lo = t[static_cast<std::size_t>(d)], hi = t[t.size() - static_cast<std::size_t>(d) - 1];
  std::vector<double> us{lo, hi};
  for (double k : t)
    if (k >= lo && k <= hi) {
      us.push_back(k);
      if (k > lo) us.push_back(std::nextafter(k, -HUGE_VAL));
      if (k < hi) us.push_back(std::nextafter(k, HUGE_VAL));
    }
  for (int i = 0; i < count; ++i) us.push_back(uniform(rng, lo, hi));
  return us;
}

/// A random surface and the test's own copy of its data.
struct RandomSurface {
  Surface s;
  std::array<int, 2> degree{};
  std::array<Knots, 2> knots;
  std::array<Eigen::Index, 2> count{};
  Points H;  // stored rows (i·nv + j)
  Points cart;
  Eigen::VectorXd w;
  bool rational = false;
  double scale = 1;
  std::string what;
};

inline RandomSurface random_surface(Rng& rng, int max_degree = 5, bool rational_ok = true) {
  RandomSurface r;
  for (int k = 0; k < 2; ++k) {
    const int d = uniform_int(rng, 1, max_degree);
    const int n = d + 1 + uniform_int(rng, 0, 4);
    r.degree[static_cast<std::size_t>(k)] = d;
    r.count[static_cast<std::size_t>(k)] = n;
    r.knots[static_cast<std::size_t>(k)] = random_knots(rng, d, n, coin(rng));
  }
  const int dim = uniform_int(rng, 1, 4);
  r.rational = rational_ok && coin(rng);
  r.cart = random_points(rng, r.count[0] * r.count[1], dim);
  if (r.rational) r.w = random_weights(rng, r.count[0] * r.count[1]);
  r.s = cifs::nurbs::make_surface(r.degree, r.knots, r.count, r.cart, r.w);
  r.H = to_rows(r.cart, r.w);
  r.scale = r.cart.cwiseAbs().maxCoeff();
  std::ostringstream s;
  s.precision(17);
  s << (r.rational ? "rational " : "") << "surface degree " << r.degree[0] << "x" << r.degree[1] << " net "
    << r.count[0] << "x" << r.count[1] << " dim " << dim;
  for (int k = 0; k < 2; ++k) {
    s << " knots[" << k << "] [";
    for (double t : r.knots[static_cast<std::size_t>(k)]) s << t << ' ';
    s << "]";
  }
  r.what = s.str();
  return r;
}

/// Homogeneous partial derivative ∂^{k+l}/∂u^k∂v^l of Σ_ij N_i(u) M_j(v) H_ij (long double).
inline Eigen::Matrix<Real, 1, Eigen::Dynamic> ref_surface_homogeneous(const RandomSurface& r, double u,
                                                                      double v, int k, int l) {
  const auto& tu = r.knots[0];
  const auto& tv = r.knots[1];
  const RealVec N = ref_basis(tu, r.degree[0], u, at_end(tu, r.degree[0], u), k);
  const RealVec M = ref_basis(tv, r.degree[1], v, at_end(tv, r.degree[1], v), l);
  Eigen::Matrix<Real, 1, Eigen::Dynamic> out = Eigen::Matrix<Real, 1, Eigen::Dynamic>::Zero(r.H.cols());
  for (Eigen::Index i = 0; i < r.count[0]; ++i)
    for (Eigen::Index j = 0; j < r.count[1]; ++j)
      out += N[static_cast<std::size_t>(i)] * M[static_cast<std::size_t>(j)] *
             r.H.row(i * r.count[1] + j).cast<Real>();
  return out;
}

/// Cartesian partials S^{(k,l)}, k + l ≤ order, as row k·(order+1) + l; Leibniz' rule on A = w·S
/// (A^{(k,l)} = Σ_{i≤k, j≤l} C(k,i) C(l,j) w^{(i,j)} S^{(k−i,l−j)}) when rational.
inline Points ref_surface_derivatives(const RandomSurface& r, double u, double v, int order) {
  const int w = order + 1;
  const Eigen::Index dim = r.H.cols() - (r.rational ? 1 : 0);
  std::vector<Eigen::Matrix<Real, 1, Eigen::Dynamic>> A(static_cast<std::size_t>(w * w)),
      S(static_cast<std::size_t>(w * w));
  for (int k = 0; k <= order; ++k)
    for (int l = 0; k + l <= order; ++l)
      A[static_cast<std::size_t>(k * w + l)] = ref_surface_homogeneous(r, u, v, k, l);
  Points out = Points::Zero(w * w, dim);
  for (int k = 0; k <= order; ++k)
    for (int l = 0; k + l <= order; ++l) {
      Eigen::Matrix<Real, 1, Eigen::Dynamic> val = A[static_cast<std::size_t>(k * w + l)].head(dim);
      if (r.rational) {
        for (int i = 0; i <= k; ++i)
          for (int j = 0; j <= l; ++j) {
            if (i == 0 && j == 0) continue;
            val -= static_cast<Real>(binomial(k, i) * binomial(l, j)) *
                   A[static_cast<std::size_t>(i * w + j)](dim) *
                   S[static_cast<std::size_t>((k - i) * w + l - j)];
          }
        val /= A[0](dim);
      }
      S[static_cast<std::size_t>(k * w + l)] = val;
      out.row(k * w + l) = val.cast<double>();
    }
  return out;
}

/// Size of the terms that make up the k-th Cartesian derivative of a random curve at u (k = 0..order):
/// the scale a relative tolerance applies to. a_k = Σ|N_i^(k)|·|H_i|, ω_k = Σ|N_i^(k)|·w_i, and for
/// rational curves M_k = (a_k + Σ_{i≥1} C(k,i) ω_i M_{k−i}) / w(u), the Leibniz terms.
inline std::vector<double> magnitudes(const RandomCurve& r, double u, int order) {
  const int d = r.degree;
  const bool left = at_end(r.knots, d, u);
  const Eigen::Index dim = r.H.cols() - (r.rational ? 1 : 0);
  std::vector<double> a, om, M;
  double w = 0;
  for (int k = 0; k <= order; ++k) {
    const RealVec N = ref_basis(r.knots, d, u, left, k);
    double ak = 0, ok = 0;
    for (Eigen::Index i = 0; i < r.H.rows(); ++i) {
      const double n = std::abs(static_cast<double>(N[static_cast<std::size_t>(i)]));
      ak += n * r.H.row(i).head(dim).cwiseAbs().maxCoeff();
      if (r.rational) ok += n * r.H(i, dim);
      if (k == 0 && r.rational) w += static_cast<double>(N[static_cast<std::size_t>(i)]) * r.H(i, dim);
    }
    a.push_back(ak);
    om.push_back(ok);
  }
  for (int k = 0; k <= order; ++k) {
    if (!r.rational) {
      M.push_back(a[static_cast<std::size_t>(k)]);
      continue;
    }
    double m = a[static_cast<std::size_t>(k)];
    for (int i = 1; i <= k; ++i)
      m += binomial(k, i) * om[static_cast<std::size_t>(i)] * M[static_cast<std::size_t>(k - i)];
    M.push_back(m / w);
  }
  return M;
}

// ---------------------------------------------------------------------------------------------
// Error measures.

inline double max_abs(const Points& A) {
  return A.size() == 0 ? 0.0 : A.cwiseAbs().maxCoeff();
}
/// Largest coordinate difference (any Eigen expressions of the same shape).
template <class A, class B>
double diff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return a.size() == 0 ? 0.0 : (a - b).cwiseAbs().maxCoeff();
}

/// Richardson-extrapolated central difference of f (a Points-valued function) at x with step h.
template <class F>
Points central_difference(F&& f, double x, double h) {
  const Points d1 = (f(x + h) - f(x - h)) / (2 * h);
  const Points d2 = (f(x + h / 2) - f(x - h / 2)) / h;
  return (4 * d2 - d1) / 3;
}

}  // namespace cifs_test
