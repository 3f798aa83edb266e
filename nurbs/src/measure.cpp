// SPDX-License-Identifier: MIT
#include "cifs/nurbs/measure.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <queue>
#include <utility>

#include "detail.hpp"

namespace cifs::nurbs {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// ------------------------------------------------------------------------------------------------
// Bézier pieces: (p + 1) rows of `cols` stored coordinates (homogeneous (w·x, w) when rational) over a
// parameter interval, local parameter s ∈ [0, 1].

struct Layout {
  int p = 0;                // degree
  std::ptrdiff_t cols = 0;  // stored coordinates per row (a factor of offsets)
  int dim = 0;              // Cartesian coordinates
  bool rational = false;
  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>((p + 1) * cols); }
};

Layout layout(const Curve& c) {
  return {c.degree, c.P.cols(), dimension(c), c.rational};
}

/// The Bézier coefficients of every non-empty span of the domain, in order: the blossoms
/// b(t_k^{p−j}, t_{k+1}^j) of the span's piece.
struct Pieces {
  Layout l;
  std::vector<double> start, end;  // each span's parameter interval
  std::vector<double> coef;        // l.size() values per span
  [[nodiscard]] const double* at(std::size_t k) const { return coef.data() + k * l.size(); }
  [[nodiscard]] std::size_t count() const { return start.size(); }
};

/// The Bézier coefficients of the piece on the non-empty span k into out ((p + 1)·cols values).
void span_bezier(const Curve& c, int k, double* out) {
  const int p = c.degree;
  const Eigen::Index cols = c.P.cols();
  double local[2 * kMaxDegree], args[kMaxDegree], W[kMaxDegree + 1];
  const detail::SpanKnots knots = detail::span_knots(c, k, local);
  const double a = knots.t[static_cast<std::size_t>(knots.span)];
  const double b = knots.t[static_cast<std::size_t>(knots.span) + 1];
  std::fill_n(out, (p + 1) * cols, 0.0);
  for (int j = 0; j <= p; ++j) {
    for (int i = 0; i < p; ++i) args[i] = i < p - j ? a : b;
    detail::blossom_weights_increasing(knots.t.data(), p, knots.span, args, W);  // arguments in order
    double* dst = out + j * cols;
    for (int i = 0; i <= p; ++i) {
      const double* src = c.P.data() + (k - p + i) * cols;  // row-major rows
      for (Eigen::Index m = 0; m < cols; ++m) dst[m] += W[i] * src[m];
    }
  }
}

Pieces bezier_pieces(const Curve& c) {
  Pieces out{layout(c), {}, {}, {}};
  const int p = c.degree;
  out.coef.reserve(static_cast<std::size_t>(c.P.rows()) * out.l.size());
  for (int k = p; k < c.P.rows(); ++k) {
    const double t0 = c.knots[static_cast<std::size_t>(k)], t1 = c.knots[static_cast<std::size_t>(k) + 1];
    if (!(t0 < t1)) continue;
    out.start.push_back(t0);
    out.end.push_back(t1);
    out.coef.resize(out.coef.size() + out.l.size());
    span_bezier(c, k, out.coef.data() + out.coef.size() - out.l.size());
  }
  return out;
}

/// De Casteljau at s: the value and the s-derivatives up to `order` (≤ 2) in stored coordinates,
/// out[r·cols …]. `work` holds (p + 1)·cols values.
void bezier_eval(const double* B, int p, std::ptrdiff_t cols, double s, int order, double* out,
                 double* work) {
  const double t = 1 - s;
  std::copy_n(B, (p + 1) * cols, work);
  std::fill_n(out, (order + 1) * cols, 0.0);
  const auto capture = [&](int level) {
    const int m = p - level;  // work holds m + 1 points
    if (m == 2 && order >= 2)
      for (int k = 0; k < cols; ++k)
        out[2 * cols + k] = p * (p - 1) * (work[k] - 2 * work[cols + k] + work[2 * cols + k]);
    if (m == 1 && order >= 1)
      for (int k = 0; k < cols; ++k) out[cols + k] = p * (work[cols + k] - work[k]);
  };
  capture(0);
  for (int r = 1; r <= p; ++r) {
    for (int j = 0; j <= p - r; ++j)
      for (int k = 0; k < cols; ++k)
        work[j * cols + k] = t * work[j * cols + k] + s * work[(j + 1) * cols + k];
    capture(r);
  }
  std::copy_n(work, cols, out);
}

/// Stored-coordinate derivatives (rows of `cols`) → Cartesian ones (rows of dim), up to `order` ≤ 2,
/// by the quotient rule: C = A/w, C′ = (A′ − w′C)/w, C″ = (A″ − 2w′C′ − w″C)/w.
void cartesian(const double* H, const Layout& l, int order, double* C) {
  if (!l.rational) {
    for (int r = 0; r <= order; ++r) std::copy_n(H + r * l.cols, l.dim, C + std::ptrdiff_t{r} * l.dim);
    return;
  }
  const int d = l.dim;
  const std::ptrdiff_t n = l.cols;
  const double w = H[d];
  for (int k = 0; k < d; ++k) C[k] = H[k] / w;
  if (order >= 1)
    for (int k = 0; k < d; ++k) C[d + k] = (H[n + k] - H[n + d] * C[k]) / w;
  if (order >= 2)
    for (int k = 0; k < d; ++k)
      C[2 * d + k] = (H[2 * n + k] - 2 * H[n + d] * C[d + k] - H[2 * n + d] * C[k]) / w;
}

/// Splits the piece B at s into L (on [0, s]) and R (on [s, 1]).
void bezier_split(const double* B, int p, std::ptrdiff_t cols, double s, double* L, double* R, double* work) {
  const double t = 1 - s;
  std::copy_n(B, (p + 1) * cols, work);
  std::copy_n(work, cols, L);
  std::copy_n(work + p * cols, cols, R + p * cols);
  for (int r = 1; r <= p; ++r) {
    for (int j = 0; j <= p - r; ++j)
      for (int k = 0; k < cols; ++k)
        work[j * cols + k] = t * work[j * cols + k] + s * work[(j + 1) * cols + k];
    std::copy_n(work, cols, L + r * cols);
    std::copy_n(work + (p - r) * cols, cols, R + (p - r) * cols);
  }
}

/// The Cartesian control point j of a piece into x (dim values).
void control_point(const double* B, const Layout& l, int j, double* x) {
  detail::project(B + j * l.cols, l.dim, l.rational, x);
}

/// Bounding box of the Cartesian control points (which holds the piece: positive weights).
void control_box(const double* B, const Layout& l, double* lo, double* hi, double* x) {
  std::fill_n(lo, l.dim, HUGE_VAL);
  std::fill_n(hi, l.dim, -HUGE_VAL);
  for (int j = 0; j <= l.p; ++j) {
    control_point(B, l, j, x);
    for (int k = 0; k < l.dim; ++k) {
      lo[k] = std::min(lo[k], x[k]);
      hi[k] = std::max(hi[k], x[k]);
    }
  }
}

/// Whether a piece is flat: its Cartesian control points advance along the chord (each step has a
/// non-negative component along it) and lie within 2 % of the chord's length from its line. `x` holds
/// (p + 1)·dim values.
bool flat(const double* B, const Layout& l, double* x) {
  const int d = l.dim;
  for (int j = 0; j <= l.p; ++j) control_point(B, l, j, x + std::ptrdiff_t{j} * d);
  const double* a = x;
  const double* b = x + std::ptrdiff_t{l.p} * d;
  double len2 = 0;
  for (int k = 0; k < d; ++k) len2 += (b[k] - a[k]) * (b[k] - a[k]);
  if (!(len2 > 0)) return false;
  double prev_along = 0;
  for (int j = 1; j <= l.p; ++j) {
    double along = 0, dist2 = 0;
    const double* xj = x + std::ptrdiff_t{j} * d;
    for (int k = 0; k < d; ++k) along += (xj[k] - a[k]) * (b[k] - a[k]);
    if (along < prev_along) return false;
    prev_along = along;
    const double f = along / len2;
    for (int k = 0; k < d; ++k) {
      const double off = xj[k] - a[k] - f * (b[k] - a[k]);
      dist2 += off * off;
    }
    if (dist2 > 4e-4 * len2) return false;
  }
  return true;
}

/// The size the tolerances scale with: the larger of the control points' bounding-box diagonal and their
/// largest coordinate (the rounding of coordinates grows with it), 1 for a net at the origin. `P` holds
/// stored rows (homogeneous when rational) of d Cartesian coordinates.
double size_of(const Points& P, int d, bool rational) {
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(d, HUGE_VAL), hi = Eigen::VectorXd::Constant(d, -HUGE_VAL);
  double largest = 0;
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    for (int k = 0; k < d; ++k) {
      const double x = rational ? P(i, k) / P(i, d) : P(i, k);
      lo(k) = std::min(lo(k), x);
      hi(k) = std::max(hi(k), x);
      largest = std::max(largest, std::abs(x));
    }
  const double size = std::max((hi - lo).norm(), largest);
  return size > 0 ? size : 1.0;
}

double size_of(const Curve& c) {
  return size_of(c.P, dimension(c), c.rational);
}

void check_tolerance(double tolerance) {
  if (!(tolerance >= 1e-15 && tolerance < 1)) detail::fail("tolerance ", tolerance, " is outside [1e-15, 1)");
}

double norm(const double* x, int n) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += x[k] * x[k];
  return std::sqrt(s);
}

// ------------------------------------------------------------------------------------------------
// Arc length.

/// Gauss–Legendre nodes and weights of 8 points on [0, 1], by Newton's method on P_8.
struct Gauss {
  static constexpr int kPoints = 8;
  std::array<double, kPoints> x{}, w{};
  Gauss() {
    for (int i = 0; i < kPoints; ++i) {
      double z = std::cos(std::numbers::pi * (i + 0.75) / (kPoints + 0.5));
      double dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= kPoints; ++k) {
          const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = kPoints * (z * p1 - p0) / (z * z - 1);
        const double step = p1 / dp;
        z -= step;
        if (std::abs(step) < 1e-17) break;
      }
      x[static_cast<std::size_t>(i)] = (1 - z) / 2;
      w[static_cast<std::size_t>(i)] = 1 / ((1 - z * z) * dp * dp);  // 2/((1 − z²)P′²) on [−1, 1], halved
    }
  }
};

const Gauss& gauss_rule() {
  static const Gauss rule;
  return rule;
}

/// |dC/ds| on one Bézier piece and its adaptive integral.
class Speed {
 public:
  Speed(const double* B, const Layout& l)
      : piece_(B),
        l_(l),
        work_(l.size()),
        homogeneous_(static_cast<std::size_t>(2 * l.cols)),
        cartesian_(static_cast<std::size_t>(2 * l.dim)) {}

  [[nodiscard]] double operator()(double s) {
    bezier_eval(piece_, l_.p, l_.cols, s, 1, homogeneous_.data(), work_.data());
    cartesian(homogeneous_.data(), l_, 1, cartesian_.data());
    return norm(cartesian_.data() + l_.dim, l_.dim);
  }

  [[nodiscard]] double rule(double s0, double s1) {
    const Gauss& g = gauss_rule();
    double sum = 0;
    for (int i = 0; i < Gauss::kPoints; ++i) {
      const auto k = static_cast<std::size_t>(i);
      sum += g.w[k] * (*this)(s0 + (s1 - s0) * g.x[k]);
    }
    return sum * (s1 - s0);
  }

  /// ∫ over [s0, s1] given the rule's value there, halving until the halves agree with the whole to
  /// `budget` per unit of s (or to rounding). Adds the value and |whole − halves| to the sums.
  void adapt(double s0, double s1, double whole, double budget, int depth, double& value, double& error) {
    const double m = 0.5 * (s0 + s1);
    const double left = rule(s0, m), right = rule(m, s1);
    const double diff = std::abs(whole - left - right);
    if (diff <= budget * (s1 - s0) || diff <= 64 * kEps * (std::abs(left) + std::abs(right)) || depth >= 40 ||
        !(s0 < m && m < s1)) {
      value += left + right;
      error += diff;
      return;
    }
    adapt(s0, m, left, budget, depth + 1, value, error);
    adapt(m, s1, right, budget, depth + 1, value, error);
  }

  Length integral(double s0, double s1, double budget) {
    Length out;
    if (s1 > s0) adapt(s0, s1, rule(s0, s1), budget, 0, out.value, out.error);
    return out;
  }

 private:
  const double* piece_;
  Layout l_;
  std::vector<double> work_, homogeneous_, cartesian_;
};

void check_parameter(const Curve& c, double u, const char* what) {
  const Domain dom = domain(c);
  if (!std::isfinite(u) || u < dom.start || u > dom.end)
    detail::fail(what, " ", u, " is outside the domain [", dom.start, ", ", dom.end, "]");
}

/// The local interval of span k of the pieces that lies in [a, b] (empty: s0 ≥ s1).
std::array<double, 2> local_interval(const Pieces& P, std::size_t k, double a, double b) {
  const double t0 = P.start[k], t1 = P.end[k], h = t1 - t0;
  const double s0 = a <= t0 ? 0.0 : std::min(1.0, (a - t0) / h);
  const double s1 = b >= t1 ? 1.0 : std::max(0.0, (b - t0) / h);
  return {s0, s1};
}

// ------------------------------------------------------------------------------------------------
// Roots of scalar Bézier polynomials.

/// Scalar value and derivative of the polynomial with Bézier coefficients h at s.
std::array<double, 2> scalar_eval(const std::vector<double>& h, double s, std::vector<double>& work) {
  double out[2];
  bezier_eval(h.data(), static_cast<int>(h.size()) - 1, 1, s, 1, out, work.data());
  return {out[0], out[1]};
}

/// The root of h in [lo, hi] where h(lo) and h(hi) have opposite signs (or one is 0): Newton's method
/// kept in the bracket, bisection where it would leave it.
double bracketed_root(const std::vector<double>& h, double lo, double hi, std::vector<double>& work) {
  double flo = scalar_eval(h, lo, work)[0], fhi = scalar_eval(h, hi, work)[0];
  if (flo == 0) return lo;
  if (fhi == 0) return hi;
  double s = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const auto [f, df] = scalar_eval(h, s, work);
    if (f == 0) return s;
    if ((f < 0) == (flo < 0)) {
      lo = s;
      flo = f;
    } else {
      hi = s;
      fhi = f;
    }
    double next = df != 0 ? s - f / df : lo;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (hi - lo <= 4 * kEps || next == s) return next;
    s = next;
  }
  return s;
}

/// Roots and zero intervals of a scalar Bézier polynomial h on [u0, u1] (curve parameters), h within
/// `tol` of zero counting as zero (see intersect_plane).
struct Roots {
  std::vector<double> at;
  std::vector<std::array<double, 2>> intervals;
};

void bezier_roots(const std::vector<double>& h, double u0, double u1, double tol, int depth, Roots& out,
                  std::vector<double>& work) {
  const int m = static_cast<int>(h.size()) - 1;
  const auto to_u = [&](double s) { return s >= 1 ? u1 : u0 + s * (u1 - u0); };
  double lo = HUGE_VAL, hi = -HUGE_VAL, largest = 0;
  for (double x : h) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    largest = std::max(largest, std::abs(x));
  }
  if (largest <= tol) {
    out.intervals.push_back({u0, u1});
    return;
  }
  if (lo > 0 || hi < 0) return;  // one sign: no root
  bool up = true, down = true, convex = true, concave = true;
  for (int j = 0; j < m; ++j) {
    const double step = h[static_cast<std::size_t>(j) + 1] - h[static_cast<std::size_t>(j)];
    up = up && step >= 0;
    down = down && step <= 0;
    if (j + 1 < m) {
      const double second = h[static_cast<std::size_t>(j) + 2] - 2 * h[static_cast<std::size_t>(j) + 1] +
                            h[static_cast<std::size_t>(j)];
      convex = convex && second >= 0;
      concave = concave && second <= 0;
    }
  }
  const double h0 = h.front(), h1 = h.back();
  const auto root_between = [&](double a, double b) {
    out.at.push_back(to_u(bracketed_root(h, a, b, work)));
  };
  if (up || down) {  // monotone: one root where the ends differ in sign
    if ((h0 <= 0) != (h1 <= 0) || h0 == 0 || h1 == 0) root_between(0, 1);
    return;
  }
  if (convex || concave) {  // h′ monotone: one extremum at most, roots on either side of it
    if (h0 == 0) out.at.push_back(u0);
    if (h1 == 0) out.at.push_back(u1);
    thread_local std::vector<double> dh;  // no recursion below: one per thread
    dh.resize(static_cast<std::size_t>(m));
    for (int j = 0; j < m; ++j)
      dh[static_cast<std::size_t>(j)] =
          m * (h[static_cast<std::size_t>(j) + 1] - h[static_cast<std::size_t>(j)]);
    if ((dh.front() < 0) == (dh.back() < 0) || dh.front() == 0 || dh.back() == 0) {  // monotone after all
      if (h0 != 0 && h1 != 0 && (h0 < 0) != (h1 < 0)) root_between(0, 1);
      return;
    }
    const double se = bracketed_root(dh, 0, 1, work);
    const double v = scalar_eval(h, se, work)[0];
    if (std::abs(v) <= tol) {
      out.at.push_back(to_u(se));  // a tangential contact, once
      return;
    }
    if (h0 != 0 && (h0 < 0) != (v < 0)) root_between(0, se);
    if (h1 != 0 && (h1 < 0) != (v < 0)) root_between(se, 1);
    return;
  }
  if (depth >= 60) {
    const double v = scalar_eval(h, 0.5, work)[0];
    if (std::abs(v) <= tol) out.at.push_back(to_u(0.5));
    return;
  }
  // The halves, in storage kept per thread and depth (the caller's h is at depth − 1).
  // Sized once: growing it would move the vector the caller's h refers to (depth < 60 below).
  thread_local std::vector<std::vector<double>> halves(std::size_t{122});
  std::vector<double>& L = halves[2 * static_cast<std::size_t>(depth)];
  std::vector<double>& R = halves[2 * static_cast<std::size_t>(depth) + 1];
  L.resize(h.size());
  R.resize(h.size());
  bezier_split(h.data(), m, 1, 0.5, L.data(), R.data(), work.data());
  const double um = to_u(0.5);
  bezier_roots(L, u0, um, tol, depth + 1, out, work);
  bezier_roots(R, um, u1, tol, depth + 1, out, work);
}

/// Sorted parameters with those that `same` joins kept once, and those inside an interval dropped.
template <class Same>
std::vector<double> merge_roots(std::vector<double> at, std::vector<std::array<double, 2>>& intervals,
                                Same&& same) {
  std::sort(intervals.begin(), intervals.end());
  std::vector<std::array<double, 2>> joined;
  for (const auto& iv : intervals) {
    if (!joined.empty() && iv[0] <= joined.back()[1])
      joined.back()[1] = std::max(joined.back()[1], iv[1]);
    else
      joined.push_back(iv);
  }
  intervals = std::move(joined);
  std::sort(at.begin(), at.end());
  std::vector<double> out;
  for (double u : at) {
    const bool inside = std::any_of(intervals.begin(), intervals.end(),
                                    [&](const auto& iv) { return u >= iv[0] && u <= iv[1]; });
    if (inside) continue;
    if (!out.empty() && (u == out.back() || same(out.back(), u))) continue;
    out.push_back(u);
  }
  return out;
}

// ------------------------------------------------------------------------------------------------
// Critical points of the distance to a point.

/// Binomial coefficients C(n, k) for n ≤ 3·kMaxDegree, row n at n(n+1)/2.
double binomial(int n, int k) {
  static const auto row = [](int m) {
    return static_cast<std::size_t>(m) * static_cast<std::size_t>(m + 1) / 2;
  };
  static const std::vector<double> table = [] {
    std::vector<double> t;
    for (int m = 0; m <= 3 * kMaxDegree; ++m)
      for (int j = 0; j <= m; ++j) {
        const std::size_t above = m > 0 ? row(m - 1) + static_cast<std::size_t>(j) : 0;  // C(m − 1, j)
        t.push_back(j == 0 || j == m ? 1.0 : t[above - 1] + t[above]);
      }
    return t;
  }();
  return table[row(n) + static_cast<std::size_t>(k)];
}

/// out += factor · f·g in Bernstein form, times C(m + n, k) on coefficient k (finish_products divides):
/// f of degree m (stride sf), g of degree n (stride sg), out of degree m + n.
void add_product(const double* f, int m, std::ptrdiff_t sf, const double* g, int n, std::ptrdiff_t sg,
                 double factor, double* out) {
  double cf[kMaxDegree + 1], cg[2 * kMaxDegree + 1];
  for (int i = 0; i <= m; ++i) cf[i] = factor * binomial(m, i) * f[i * sf];
  for (int j = 0; j <= n; ++j) cg[j] = binomial(n, j) * g[j * sg];
  for (int i = 0; i <= m; ++i)
    for (int j = 0; j <= n; ++j) out[i + j] += cf[i] * cg[j];
}

/// Divides the coefficients of a product of degree `degree` accumulated by add_product by C(degree, k).
void finish_products(double* out, int degree) {
  for (int k = 0; k <= degree; ++k) out[k] /= binomial(degree, k);
}

/// The Bézier coefficients of a polynomial whose roots in [0, 1] are the critical points of |C(s) − q|²
/// on the piece B: (C − q)·C′ (degree 2p − 1) when polynomial, (A − q·w)·(A′w − A·w′) (degree 3p − 1)
/// when rational (C = A/w: the same roots, w > 0). `magnitude` gets the same sums of absolute values,
/// the scale of the rounding of `out`.
void critical_polynomial(const double* B, const Layout& l, const Point& q, std::vector<double>& out,
                         std::vector<double>& magnitude) {
  const int p = l.p, d = l.dim;
  const std::ptrdiff_t n = l.cols;
  const int degree = l.rational ? 3 * p - 1 : 2 * p - 1;
  out.assign(static_cast<std::size_t>(degree) + 1, 0.0);
  magnitude.assign(out.size(), 0.0);
  std::array<double, kMaxDegree + 1> e{}, de{}, ea{}, dea{}, dw{};
  std::array<double, std::size_t{2} * kMaxDegree> v{}, va{};
  if (l.rational)
    for (int j = 0; j < p; ++j) dw[static_cast<std::size_t>(j)] = p * (B[(j + 1) * n + d] - B[j * n + d]);
  for (int k = 0; k < d; ++k) {
    for (int j = 0; j <= p; ++j) {
      const double w = l.rational ? B[j * n + d] : 1.0;
      e[static_cast<std::size_t>(j)] = B[j * n + k] - q(k) * w;
      ea[static_cast<std::size_t>(j)] = std::abs(B[j * n + k]) + std::abs(q(k) * w);
    }
    for (int j = 0; j < p; ++j) {
      de[static_cast<std::size_t>(j)] = p * (B[(j + 1) * n + k] - B[j * n + k]);
      dea[static_cast<std::size_t>(j)] = std::abs(de[static_cast<std::size_t>(j)]);
    }
    if (!l.rational) {
      add_product(e.data(), p, 1, de.data(), p - 1, 1, 1.0, out.data());
      add_product(ea.data(), p, 1, dea.data(), p - 1, 1, 1.0, magnitude.data());
      continue;
    }
    // V = A′w − A·w′ in degree 2p − 1.
    std::fill_n(v.begin(), 2 * p, 0.0);
    add_product(de.data(), p - 1, 1, B + d, p, n, 1.0, v.data());
    add_product(dw.data(), p - 1, 1, B + k, p, n, -1.0, v.data());
    finish_products(v.data(), 2 * p - 1);
    for (std::size_t j = 0; j < 2 * static_cast<std::size_t>(p); ++j) va[j] = std::abs(v[j]);
    add_product(e.data(), p, 1, v.data(), 2 * p - 1, 1, 1.0, out.data());
    add_product(ea.data(), p, 1, va.data(), 2 * p - 1, 1, 1.0, magnitude.data());
  }
  finish_products(out.data(), degree);
  finish_products(magnitude.data(), degree);
}

}  // namespace

// ------------------------------------------------------------------------------------------------

Length arc_length(const Curve& c, double a, double b, double tolerance) {
  check_tolerance(tolerance);
  check_parameter(c, a, "arc length: start");
  check_parameter(c, b, "arc length: end");
  if (a > b) detail::fail("arc length: the start ", a, " is after the end ", b);
  Length total;
  if (a == b) return total;
  const Pieces P = bezier_pieces(c);
  std::vector<double> whole(P.count(), 0.0);
  double rough = 0;
  for (std::size_t k = 0; k < P.count(); ++k) {
    const auto [s0, s1] = local_interval(P, k, a, b);
    if (s0 < s1) whole[k] = Speed(P.at(k), P.l).rule(s0, s1);
    rough += whole[k];
  }
  const double per_u = tolerance * rough / (b - a);
  for (std::size_t k = 0; k < P.count(); ++k) {
    const auto [s0, s1] = local_interval(P, k, a, b);
    if (!(s0 < s1)) continue;
    Speed speed(P.at(k), P.l);
    speed.adapt(s0, s1, whole[k], per_u * (P.end[k] - P.start[k]), 0, total.value, total.error);
  }
  return total;
}

Length arc_length(const Curve& c, double tolerance) {
  const Domain dom = domain(c);
  return arc_length(c, dom.start, dom.end, tolerance);
}

double parameter_at_length(const Curve& c, double length, double start, double tolerance) {
  check_tolerance(tolerance);
  check_parameter(c, start, "parameter at length: start");
  if (!std::isfinite(length) || length < 0)
    detail::fail("parameter at length: length ", length, " is not a finite non-negative number");
  const Domain dom = domain(c);
  const Pieces P = bezier_pieces(c);
  double rough = 0;
  for (std::size_t k = 0; k < P.count(); ++k) {
    const auto [s0, s1] = local_interval(P, k, start, dom.end);
    if (s0 < s1) rough += Speed(P.at(k), P.l).rule(s0, s1);
  }
  const double absolute = tolerance * rough;
  const double per_u = dom.end > start ? absolute / (dom.end - start) : 0;
  double done = 0;
  for (std::size_t k = 0; k < P.count(); ++k) {
    const auto [s0, s1] = local_interval(P, k, start, dom.end);
    if (!(s0 < s1)) continue;
    const double h = P.end[k] - P.start[k];
    Speed speed(P.at(k), P.l);
    const double budget = per_u * h;
    const double piece = speed.integral(s0, s1, budget).value;
    if (done + piece < length - absolute) {
      done += piece;
      continue;
    }
    // Newton on F(s) = ∫_{s0}^{s} |C′| − r in the bracket [lo, hi], the integral carried from the last s.
    const double r = length - done;
    double lo = s0, hi = s1, s = s0 + (s1 - s0) * std::clamp(r / piece, 0.0, 1.0), at = s0, F = -r;
    for (int it = 0; it < 100; ++it) {
      F += s >= at ? speed.integral(at, s, budget).value : -speed.integral(s, at, budget).value;
      at = s;
      if (std::abs(F) <= absolute) break;
      if (F < 0)
        lo = s;
      else
        hi = s;
      const double v = speed(s);
      double next = v > 0 ? s - F / v : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (hi - lo <= 4 * kEps || next == s) break;
      s = next;
    }
    return s >= 1 ? P.end[k] : std::clamp(P.start[k] + s * h, P.start[k], P.end[k]);
  }
  if (length <= done + absolute) return dom.end;
  detail::fail("parameter at length: length ", length, " is beyond the end (", done, " from ", start, " to ",
               dom.end, ")");
}

Frenet frenet_frame(const Curve& c, double u) {
  const int dim = dimension(c);
  if (dim != 2 && dim != 3) detail::fail("Frenet frame: the curve is ", dim, "-D, not 2-D or 3-D");
  check_parameter(c, u, "Frenet frame: parameter");
  const Points D = derivatives(c, u, 3);
  Frenet f;
  f.point = D.row(0);
  const Eigen::Vector3d d1 =
      dim == 3 ? Eigen::Vector3d(D(1, 0), D(1, 1), D(1, 2)) : Eigen::Vector3d(D(1, 0), D(1, 1), 0);
  const Eigen::Vector3d d2 =
      dim == 3 ? Eigen::Vector3d(D(2, 0), D(2, 1), D(2, 2)) : Eigen::Vector3d(D(2, 0), D(2, 1), 0);
  const Eigen::Vector3d d3 =
      dim == 3 ? Eigen::Vector3d(D(3, 0), D(3, 1), D(3, 2)) : Eigen::Vector3d(D(3, 0), D(3, 1), 0);
  f.speed = d1.norm();
  if (!(f.speed > 0))
    detail::fail("Frenet frame: the tangent is undefined at u = ", u, " (the derivative vanishes)");
  const Eigen::Vector3d tangent = d1 / f.speed;
  f.tangent = tangent.head(dim).transpose();
  const Eigen::Vector3d cross = d1.cross(d2);
  const double speed3 = f.speed * f.speed * f.speed;
  if (dim == 2) {
    f.curvature = cross.z() / speed3;
    f.normal = Point(2);
    f.normal << -tangent.y(), tangent.x();
    return f;
  }
  const double turn = cross.norm();
  if (!(turn > 1e-12 * f.speed * d2.norm())) return f;  // straight here: no normal
  f.curvature = turn / speed3;
  const Eigen::Vector3d binormal = cross / turn;
  f.binormal = binormal.transpose();
  f.normal = binormal.cross(tangent).transpose();
  f.torsion = cross.dot(d3) / (turn * turn);
  return f;
}

ClosestPoints closest_point(const Curve& c, const Point& q, double tolerance) {
  check_tolerance(tolerance);
  // make_curve refuses degree 0; a curve made by hand with it would be read as spans of p + 1 = 1 point
  // whose critical points are roots of a polynomial of degree 2p − 1 = −1 (it crashed).
  if (c.degree < 1)
    detail::fail("closest point: the curve has degree ", c.degree, "; degree 0 is not continuous");
  const Layout l = layout(c);
  if (q.size() != l.dim)
    detail::fail("closest point: the point has ", q.size(), " coordinates, the curve ", l.dim);
  if (!q.allFinite()) detail::fail("closest point: the point is not finite");
  const double eq = tolerance * size_of(c);
  const int d = l.dim;
  const auto distance_to = [&](const double* x) {
    double s = 0;
    for (int k = 0; k < d; ++k) s += (x[k] - q(k)) * (x[k] - q(k));
    return std::sqrt(s);
  };
  std::vector<double> box_lo(static_cast<std::size_t>(d)), box_hi(box_lo),
      xs(static_cast<std::size_t>((l.p + 1) * d));
  /// A lower bound on the distance from q to the convex hull of the Cartesian points of `count` rows
  /// (l.cols values each): the larger of the distance to their bounding box and the distance to the
  /// segment between the first and the last, less the farthest point's distance from that segment
  /// (the hull lies within that of the segment, which is convex). The second is tight for flat pieces.
  const auto rows_box_distance = [&](const double* rows, int count) {
    std::fill(box_lo.begin(), box_lo.end(), HUGE_VAL);
    std::fill(box_hi.begin(), box_hi.end(), -HUGE_VAL);
    for (int j = 0; j < count; ++j) {
      double* x = xs.data() + std::ptrdiff_t{j} * d;
      detail::project(rows + j * l.cols, d, l.rational, x);
      for (int k = 0; k < d; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        box_lo[kk] = std::min(box_lo[kk], x[k]);
        box_hi[kk] = std::max(box_hi[kk], x[k]);
      }
    }
    double s = 0;
    for (int k = 0; k < d; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const double out = std::max({box_lo[kk] - q(k), q(k) - box_hi[kk], 0.0});
      s += out * out;
    }
    const double* a = xs.data();
    const double* b = xs.data() + std::ptrdiff_t{count - 1} * d;
    double len2 = 0;
    for (int k = 0; k < d; ++k) len2 += (b[k] - a[k]) * (b[k] - a[k]);
    // Distance from a point to the segment [a, b].
    const auto to_segment = [&](const double* y) {
      double t = 0;
      if (len2 > 0) {
        for (int k = 0; k < d; ++k) t += (y[k] - a[k]) * (b[k] - a[k]);
        t = std::clamp(t / len2, 0.0, 1.0);
      }
      double r = 0;
      for (int k = 0; k < d; ++k) {
        const double e = y[k] - a[k] - t * (b[k] - a[k]);
        r += e * e;
      }
      return std::sqrt(r);
    };
    double spread = 0;
    for (int j = 1; j + 1 < count; ++j)
      spread = std::max(spread, to_segment(xs.data() + std::ptrdiff_t{j} * d));
    return std::max(std::sqrt(s), to_segment(q.data()) - spread);
  };
  const auto box_distance = [&](const double* B) { return rows_box_distance(B, l.p + 1); };
  std::vector<double> work(l.size()), H(static_cast<std::size_t>(3 * l.cols)),
      C(static_cast<std::size_t>(3 * d));
  const auto point_at = [&](const double* B, double s) {
    bezier_eval(B, l.p, l.cols, s, 0, H.data(), work.data());
    cartesian(H.data(), l, 0, C.data());
  };

  double best = HUGE_VAL;
  struct Found {
    double u, dist;
  };
  std::vector<Found> found;                     // span ends and critical points
  std::vector<std::array<double, 3>> constant;  // spans at a constant distance: u0, u1, that distance
  // The spans by the hull of their p + 1 B-spline control points (the span's piece lies in it),
  // nearest first; a span's Bézier piece is made only when that bound is below the best distance.
  std::vector<std::pair<double, int>> order;
  for (int k = l.p; k < c.P.rows(); ++k)
    if (c.knots[static_cast<std::size_t>(k)] < c.knots[static_cast<std::size_t>(k) + 1])
      order.emplace_back(rows_box_distance(c.P.data() + (k - l.p) * l.cols, l.p + 1), k);
  std::sort(order.begin(), order.end());
  std::vector<double> B(l.size()), crit, crit_magnitude, crit_work;
  for (const auto& [span_bound, k] : order) {
    if (span_bound > best + eq) break;
    span_bezier(c, k, B.data());
    if (box_distance(B.data()) > best + eq) continue;  // the Bézier hull is tighter
    const double u0 = c.knots[static_cast<std::size_t>(k)], u1 = c.knots[static_cast<std::size_t>(k) + 1];
    const auto at = [&](double s) {
      point_at(B.data(), s);
      const double dist = distance_to(C.data());
      best = std::min(best, dist);
      found.push_back({s >= 1 ? u1 : u0 + s * (u1 - u0), dist});
      return dist;
    };
    const double d0 = at(0), d1 = at(1);
    // Every critical point of the distance on the span is a root of critical_polynomial; one that
    // vanishes on the whole span (to its rounding) means a constant distance (a circle about q).
    critical_polynomial(B.data(), l, q, crit, crit_magnitude);
    const double rounding = 1e3 * kEps * *std::max_element(crit_magnitude.begin(), crit_magnitude.end());
    Roots roots;
    crit_work.resize(crit.size());
    bezier_roots(crit, 0, 1, rounding, 0, roots, crit_work);
    for (const auto& iv : roots.intervals) roots.at.insert(roots.at.end(), {iv[0], iv[1]});
    for (double r : roots.at) (void)at(r);
    if (roots.intervals.size() == 1 && roots.intervals[0] == std::array<double, 2>{0, 1}) {
      point_at(B.data(), 0.5);
      constant.push_back({u0, u1, std::max({d0, d1, distance_to(C.data())})});
    }
  }

  ClosestPoints out;
  out.distance = best;
  for (const auto& iv : constant)
    if (iv[2] <= best + eq) out.intervals.push_back({iv[0], iv[1]});
  std::vector<double> at;
  for (const Found& f : found)
    if (f.dist <= best + eq) at.push_back(f.u);
  const Domain dom = domain(c);
  if (c.closed)
    for (double& u : at)
      if (u == dom.end) u = dom.start;
  const double close = 1e-9 * (dom.end - dom.start);
  out.parameters =
      merge_roots(std::move(at), out.intervals, [&](double a, double b) { return b - a <= close; });
  out.points.resize(static_cast<Eigen::Index>(out.parameters.size()), d);
  for (std::size_t i = 0; i < out.parameters.size(); ++i)
    out.points.row(static_cast<Eigen::Index>(i)) = evaluate(c, out.parameters[i]);
  return out;
}

PlaneIntersection intersect_plane(const Curve& c, const Point& normal, double offset, double tolerance) {
  check_tolerance(tolerance);
  const int d = dimension(c);
  if (normal.size() != d)
    detail::fail("plane: the normal has ", normal.size(), " coordinates, the curve ", d);
  if (!normal.allFinite() || !std::isfinite(offset))
    detail::fail("plane: the normal or offset is not finite");
  const double length = normal.norm();
  if (!(length > 0)) detail::fail("plane: the normal is zero");
  const Point n = normal / length;
  const double off = offset / length;
  const double absolute = tolerance * std::max(size_of(c), std::abs(off));
  const Pieces P = bezier_pieces(c);
  const Layout& l = P.l;
  Roots roots;
  std::vector<double> h(static_cast<std::size_t>(l.p + 1)), work(static_cast<std::size_t>(l.p + 1));
  for (std::size_t k = 0; k < P.count(); ++k) {
    const double* B = P.at(k);
    double wmin = HUGE_VAL;
    for (int j = 0; j <= l.p; ++j) {
      const double* row = B + j * l.cols;
      const double w = l.rational ? row[d] : 1.0;
      double v = -off * w;
      for (int m = 0; m < d; ++m) v += n(m) * row[m];
      h[static_cast<std::size_t>(j)] = v;
      wmin = std::min(wmin, w);
    }
    bezier_roots(h, P.start[k], P.end[k], absolute * wmin, 0, roots, work);
  }
  PlaneIntersection out;
  out.intervals = std::move(roots.intervals);
  const auto signed_distance = [&](double u) { return (evaluate(c, u) * n.transpose())(0) - off; };
  out.parameters = merge_roots(std::move(roots.at), out.intervals, [&](double a, double b) {
    return std::abs(signed_distance(0.5 * (a + b))) <= absolute;
  });
  if (c.closed && out.parameters.size() > 1 && out.parameters.back() == domain(c).end &&
      out.parameters.front() == domain(c).start)
    out.parameters.pop_back();
  return out;
}

std::vector<CurveIntersection> intersect_curves(const Curve& a, const Curve& b, double tolerance) {
  check_tolerance(tolerance);
  const int d = dimension(a);
  if (dimension(b) != d) detail::fail("intersect curves: the curves are ", d, "-D and ", dimension(b), "-D");
  if (d < 2) detail::fail("intersect curves: the curves are 1-D");
  const double absolute = tolerance * std::max(size_of(a), size_of(b));
  const Pieces PA = bezier_pieces(a), PB = bezier_pieces(b);
  const Layout &la = PA.l, &lb = PB.l;
  struct Item {
    std::vector<double> A, B;
    double a0, a1, b0, b1;
    int depth;
  };
  std::vector<Item> items;
  for (std::size_t i = 0; i < PA.count(); ++i)
    for (std::size_t j = 0; j < PB.count(); ++j)
      items.push_back({{PA.at(i), PA.at(i) + la.size()},
                       {PB.at(j), PB.at(j) + lb.size()},
                       PA.start[i],
                       PA.end[i],
                       PB.start[j],
                       PB.end[j],
                       0});
  std::vector<double> wa(la.size()), wb(lb.size()),
      H(static_cast<std::size_t>(3 * std::max(la.cols, lb.cols))), CA(static_cast<std::size_t>(3 * d)),
      CB(static_cast<std::size_t>(3 * d));
  const auto eval = [&](const std::vector<double>& piece, const Layout& l, std::vector<double>& work,
                        double s, std::vector<double>& out) {
    bezier_eval(piece.data(), l.p, l.cols, s, 1, H.data(), work.data());
    cartesian(H.data(), l, 1, out.data());
  };
  struct Found {
    double u, v, dist;
  };
  std::vector<Found> found;
  int leaves = 0;
  std::vector<double> loA(static_cast<std::size_t>(d)), hiA(loA), loB(loA), hiB(loA), xs(loA), F(loA);
  std::vector<double> flat_scratch(static_cast<std::size_t>((std::max(la.p, lb.p) + 1) * d));
  while (!items.empty()) {
    Item it = std::move(items.back());
    items.pop_back();
    control_box(it.A.data(), la, loA.data(), hiA.data(), xs.data());
    control_box(it.B.data(), lb, loB.data(), hiB.data(), xs.data());
    bool apart = false;
    double diagA = 0, diagB = 0;
    for (std::size_t k = 0; k < loA.size(); ++k) {
      apart = apart || loA[k] > hiB[k] + absolute || loB[k] > hiA[k] + absolute;
      diagA += (hiA[k] - loA[k]) * (hiA[k] - loA[k]);
      diagB += (hiB[k] - loB[k]) * (hiB[k] - loB[k]);
    }
    if (apart) continue;
    const bool flatA = flat(it.A.data(), la, flat_scratch.data()),
               flatB = flat(it.B.data(), lb, flat_scratch.data());
    const bool tinyA = diagA <= absolute * absolute, tinyB = diagB <= absolute * absolute;
    if (((flatA || tinyA) && (flatB || tinyB)) || it.depth >= 50) {
      if (++leaves > 4096)
        detail::fail("intersect curves: the curves overlap along an arc (near u = ", it.a0, ", v = ", it.b0,
                     ")");
      // Gauss–Newton on F(s, t) = A(s) − B(t) in [0, 1]².
      double s = 0.5, t = 0.5, dist = HUGE_VAL;
      for (int iter = 0; iter < 60; ++iter) {
        eval(it.A, la, wa, s, CA);
        eval(it.B, lb, wb, t, CB);
        double a11 = 0, a12 = 0, a22 = 0, r1 = 0, r2 = 0;
        for (int k = 0; k < d; ++k) {
          const auto kk = static_cast<std::size_t>(k);
          F[kk] = CA[kk] - CB[kk];
          const double ja = CA[static_cast<std::size_t>(d) + kk], jb = -CB[static_cast<std::size_t>(d) + kk];
          a11 += ja * ja;
          a12 += ja * jb;
          a22 += jb * jb;
          r1 -= ja * F[kk];
          r2 -= jb * F[kk];
        }
        dist = norm(F.data(), d);
        const double det = a11 * a22 - a12 * a12;
        if (dist == 0 || !(std::abs(det) > 1e-300)) break;
        const double ds = (a22 * r1 - a12 * r2) / det, dt = (a11 * r2 - a12 * r1) / det;
        const double ns = std::clamp(s + ds, 0.0, 1.0), nt = std::clamp(t + dt, 0.0, 1.0);
        if (ns == s && nt == t) break;
        s = ns;
        t = nt;
      }
      eval(it.A, la, wa, s, CA);
      eval(it.B, lb, wb, t, CB);
      for (int k = 0; k < d; ++k)
        F[static_cast<std::size_t>(k)] = CA[static_cast<std::size_t>(k)] - CB[static_cast<std::size_t>(k)];
      dist = norm(F.data(), d);
      if (dist <= absolute)
        found.push_back({s >= 1 ? it.a1 : it.a0 + s * (it.a1 - it.a0),
                         t >= 1 ? it.b1 : it.b0 + t * (it.b1 - it.b0), dist});
      continue;
    }
    const auto halve = [&](const std::vector<double>& piece, const Layout& l, std::vector<double>& work) {
      std::array<std::vector<double>, 2> halves{std::vector<double>(l.size()), std::vector<double>(l.size())};
      bezier_split(piece.data(), l.p, l.cols, 0.5, halves[0].data(), halves[1].data(), work.data());
      return halves;
    };
    const bool splitA = !(flatA || tinyA) && ((flatB || tinyB) || diagA >= diagB);
    if (splitA) {
      auto [L, R] = halve(it.A, la, wa);
      const double m = 0.5 * (it.a0 + it.a1);
      items.push_back({std::move(R), it.B, m, it.a1, it.b0, it.b1, it.depth + 1});
      items.push_back({std::move(L), std::move(it.B), it.a0, m, it.b0, it.b1, it.depth + 1});
    } else {
      auto [L, R] = halve(it.B, lb, wb);
      const double m = 0.5 * (it.b0 + it.b1);
      items.push_back({it.A, std::move(R), it.a0, it.a1, m, it.b1, it.depth + 1});
      items.push_back({std::move(it.A), std::move(L), it.a0, it.a1, it.b0, m, it.depth + 1});
    }
  }
  // One point per contact: found points whose midpoint pair is also within the tolerance are one.
  std::sort(found.begin(), found.end(),
            [](const Found& x, const Found& y) { return x.u < y.u || (x.u == y.u && x.v < y.v); });
  std::vector<CurveIntersection> out;
  for (const Found& f : found) {
    if (!out.empty()) {
      CurveIntersection& last = out.back();
      const double um = 0.5 * (last.u + f.u), vm = 0.5 * (last.v + f.v);
      if ((evaluate(a, um) - evaluate(b, vm)).norm() <= absolute) {
        if (f.dist < last.distance) last = {f.u, f.v, evaluate(a, f.u), f.dist};
        continue;
      }
    }
    out.push_back({f.u, f.v, evaluate(a, f.u), f.dist});
  }
  return out;
}

Box bounding_box(const Curve& c) {
  const Pieces P = bezier_pieces(c);
  const Layout& l = P.l;
  const int d = l.dim, p = l.p;
  Box box{Point::Constant(d, HUGE_VAL), Point::Constant(d, -HUGE_VAL)};
  std::vector<double> work(l.size()), H(static_cast<std::size_t>(l.cols)), x(static_cast<std::size_t>(d));
  const auto include = [&](const double* B, double s) {
    bezier_eval(B, p, l.cols, s, 0, H.data(), work.data());
    detail::project(H.data(), d, l.rational, x.data());
    for (int k = 0; k < d; ++k) {
      box.lower(k) = std::min(box.lower(k), x[static_cast<std::size_t>(k)]);
      box.upper(k) = std::max(box.upper(k), x[static_cast<std::size_t>(k)]);
    }
  };
  // Binomial coefficients for the product of Bernstein polynomials.
  const auto binom = [](int n, int k) {
    double r = 1;
    for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
    return r;
  };
  for (std::size_t piece = 0; piece < P.count(); ++piece) {
    const double* B = P.at(piece);
    include(B, 0);
    include(B, 1);
    if (p == 0) continue;
    for (int k = 0; k < d; ++k) {
      std::vector<double> num;
      const auto coord = [&](int j, int m) { return B[j * l.cols + m]; };
      if (!l.rational) {
        for (int j = 0; j < p; ++j) num.push_back(p * (coord(j + 1, k) - coord(j, k)));
      } else {
        // A′w − Aw′ in degree 2p − 1: A′, w′ have degree p − 1, A, w degree p.
        const int n1 = p - 1, n2 = p;
        num.assign(static_cast<std::size_t>(n1) + static_cast<std::size_t>(n2) + 1, 0.0);
        for (int i = 0; i <= n1; ++i)
          for (int j = 0; j <= n2; ++j) {
            const double dA = p * (coord(i + 1, k) - coord(i, k)), dw = p * (coord(i + 1, d) - coord(i, d));
            const double f = binom(n1, i) * binom(n2, j) / binom(n1 + n2, i + j);
            num[static_cast<std::size_t>(i) + static_cast<std::size_t>(j)] +=
                f * (dA * coord(j, d) - coord(j, k) * dw);
          }
      }
      double largest = 0;
      for (double v : num) largest = std::max(largest, std::abs(v));
      Roots roots;
      std::vector<double> rw(num.size());
      bezier_roots(num, 0, 1, 1e-15 * largest, 0, roots, rw);
      for (double s : roots.at) include(B, s);
    }
  }
  return box;
}

Curve transform(const Curve& c, const Eigen::MatrixXd& matrix) {
  const int d = dimension(c);
  if (matrix.rows() != d + 1 || matrix.cols() != d + 1)
    detail::fail("transform: a ", d, "-D curve takes a ", d + 1, "×", d + 1, " matrix, got ", matrix.rows(),
                 "×", matrix.cols());
  if (!matrix.allFinite()) detail::fail("transform: the matrix is not finite");
  bool affine = matrix(d, d) == 1;
  for (int k = 0; k < d; ++k) affine = affine && matrix(d, k) == 0;
  Curve out = c;
  out.rational = c.rational || !affine;
  out.P.resize(c.P.rows(), d + (out.rational ? 1 : 0));
  for (Eigen::Index i = 0; i < c.P.rows(); ++i) {
    Eigen::VectorXd h(d + 1);
    h.head(d) = c.P.row(i).head(d).transpose();
    h(d) = c.rational ? c.P(i, d) : 1.0;
    const Eigen::VectorXd g = matrix * h;
    if (out.rational && !(g(d) > 0))
      detail::fail("transform: control point ", i, " gets weight ", g(d),
                   " (the curve meets the plane the matrix sends to infinity)");
    out.P.row(i) = g.head(out.P.cols()).transpose();
  }
  validate(out);
  return out;
}

// ------------------------------------------------------------------------------------------------
// Closest points on surfaces.

namespace {

/// An index or count computed in int, as a size (the int arithmetic cannot overflow: degrees ≤ 64).
std::size_t as_size(int i) {
  return static_cast<std::size_t>(i);
}

/// A Bézier patch: (p + 1)·(q + 1) rows of `cols` stored coordinates (homogeneous (w·x, w) when
/// rational), row i·(q + 1) + j with i along u; local parameters (s, t) ∈ [0, 1]².
struct PatchLayout {
  int p = 0, q = 0;
  std::ptrdiff_t cols = 0;
  int dim = 0;
  bool rational = false;
  [[nodiscard]] std::size_t size() const {
    return static_cast<std::size_t>((p + 1) * (q + 1)) * static_cast<std::size_t>(cols);
  }
};

/// A polynomial in Bernstein form of degree (m, n) in (s, t): coefficient (i, j) at i·(n + 1) + j.
struct Bernstein2 {
  int m = 0, n = 0;
  std::vector<double> c;
  [[nodiscard]] std::size_t size() const { return as_size((m + 1) * (n + 1)); }
};

/// out += factor·f·g in Bernstein form, coefficient (i, j) of the product times C(M, i)·C(N, j)
/// (finish_products2 divides): f of degree (fm, fn), g of degree (gm, gn), out of degree (fm + gm, fn + gn).
void add_product2(const double* f, int fm, int fn, const double* g, int gm, int gn, double factor,
                  double* out, std::vector<double>& cf, std::vector<double>& cg) {
  const int N = fn + gn;
  cf.resize(as_size((fm + 1) * (fn + 1)));
  cg.resize(as_size((gm + 1) * (gn + 1)));
  for (int i = 0; i <= fm; ++i)
    for (int j = 0; j <= fn; ++j) {
      const auto at = as_size(i * (fn + 1) + j);
      cf[at] = factor * binomial(fm, i) * binomial(fn, j) * f[at];
    }
  for (int k = 0; k <= gm; ++k)
    for (int l = 0; l <= gn; ++l) {
      const auto at = as_size(k * (gn + 1) + l);
      cg[at] = binomial(gm, k) * binomial(gn, l) * g[at];
    }
  for (int i = 0; i <= fm; ++i)
    for (int j = 0; j <= fn; ++j) {
      const double a = cf[as_size(i * (fn + 1) + j)];
      if (a == 0) continue;
      for (int k = 0; k <= gm; ++k) {
        double* row = out + std::ptrdiff_t{i + k} * (N + 1) + j;
        const double* b = cg.data() + std::ptrdiff_t{k} * (gn + 1);
        for (int l = 0; l <= gn; ++l) row[l] += a * b[l];
      }
    }
}

void finish_products2(double* out, int M, int N) {
  for (int i = 0; i <= M; ++i)
    for (int j = 0; j <= N; ++j) out[i * (N + 1) + j] /= binomial(M, i) * binomial(N, j);
}

/// The critical polynomials of the distance on a patch: g_u = (S − q)·S_s and g_v = (S − q)·S_t (times w³
/// when rational, S = A/w: (A − q·w)·(A_s·w − A·w_s), the same zeros and signs), and the same sums of
/// absolute values (mu, mv: the scale of their rounding, as critical_polynomial for curves).
struct CriticalPair {
  Bernstein2 gu, gv, mu, mv;
};

CriticalPair surface_critical(const double* B, const PatchLayout& l, const Point& q) {
  const int p = l.p, r = l.q, d = l.dim;
  const std::ptrdiff_t n = l.cols;
  const auto row = [&](int i, int j) { return B + (i * (r + 1) + j) * n; };
  const int ku = l.rational ? 1 : 0;  // w³ adds p (and q) to the degrees
  CriticalPair out;
  out.gu = {2 * p - 1 + ku * p, 2 * r + ku * r, {}};
  out.gv = {2 * p + ku * p, 2 * r - 1 + ku * r, {}};
  out.gu.c.assign(out.gu.size(), 0.0);
  out.gv.c.assign(out.gv.size(), 0.0);
  out.mu = out.gu;
  out.mv = out.gv;
  const auto np = as_size((p + 1) * (r + 1));
  std::vector<double> e(np), ea(np), w(np), cf, cg;
  std::vector<double> du(static_cast<std::size_t>(p * (r + 1))), dv(static_cast<std::size_t>((p + 1) * r));
  std::vector<double> dua(du.size()), dva(dv.size()), wu(du.size()), wv(dv.size()), a(np);
  // V_s = A_s·w − A·w_s (degree (2p − 1, 2r)) and V_t (degree (2p, 2r − 1)) when rational.
  Bernstein2 Vu{2 * p - 1, 2 * r, {}}, Vv{2 * p, 2 * r - 1, {}};
  std::vector<double> vua, vva;
  if (l.rational) {
    for (int i = 0; i <= p; ++i)
      for (int j = 0; j <= r; ++j) w[as_size(i * (r + 1) + j)] = row(i, j)[d];
    for (int i = 0; i < p; ++i)
      for (int j = 0; j <= r; ++j) wu[as_size(i * (r + 1) + j)] = p * (row(i + 1, j)[d] - row(i, j)[d]);
    for (int i = 0; i <= p; ++i)
      for (int j = 0; j < r; ++j) wv[as_size(i * r + j)] = r * (row(i, j + 1)[d] - row(i, j)[d]);
  }
  for (int k = 0; k < d; ++k) {
    for (int i = 0; i <= p; ++i)
      for (int j = 0; j <= r; ++j) {
        const auto at = as_size(i * (r + 1) + j);
        const double wij = l.rational ? w[at] : 1.0;
        a[at] = row(i, j)[k];
        e[at] = a[at] - q(k) * wij;
        ea[at] = std::abs(a[at]) + std::abs(q(k) * wij);
      }
    for (int i = 0; i < p; ++i)
      for (int j = 0; j <= r; ++j) {
        const auto at = as_size(i * (r + 1) + j);
        du[at] = p * (row(i + 1, j)[k] - row(i, j)[k]);
        dua[at] = std::abs(du[at]);
      }
    for (int i = 0; i <= p; ++i)
      for (int j = 0; j < r; ++j) {
        const auto at = as_size(i * r + j);
        dv[at] = r * (row(i, j + 1)[k] - row(i, j)[k]);
        dva[at] = std::abs(dv[at]);
      }
    if (!l.rational) {
      add_product2(e.data(), p, r, du.data(), p - 1, r, 1.0, out.gu.c.data(), cf, cg);
      add_product2(ea.data(), p, r, dua.data(), p - 1, r, 1.0, out.mu.c.data(), cf, cg);
      add_product2(e.data(), p, r, dv.data(), p, r - 1, 1.0, out.gv.c.data(), cf, cg);
      add_product2(ea.data(), p, r, dva.data(), p, r - 1, 1.0, out.mv.c.data(), cf, cg);
      continue;
    }
    Vu.c.assign(Vu.size(), 0.0);
    add_product2(du.data(), p - 1, r, w.data(), p, r, 1.0, Vu.c.data(), cf, cg);
    add_product2(wu.data(), p - 1, r, a.data(), p, r, -1.0, Vu.c.data(), cf, cg);
    finish_products2(Vu.c.data(), Vu.m, Vu.n);
    Vv.c.assign(Vv.size(), 0.0);
    add_product2(dv.data(), p, r - 1, w.data(), p, r, 1.0, Vv.c.data(), cf, cg);
    add_product2(wv.data(), p, r - 1, a.data(), p, r, -1.0, Vv.c.data(), cf, cg);
    finish_products2(Vv.c.data(), Vv.m, Vv.n);
    vua.resize(Vu.size());
    vva.resize(Vv.size());
    for (std::size_t i = 0; i < Vu.size(); ++i) vua[i] = std::abs(Vu.c[i]);
    for (std::size_t i = 0; i < Vv.size(); ++i) vva[i] = std::abs(Vv.c[i]);
    add_product2(e.data(), p, r, Vu.c.data(), Vu.m, Vu.n, 1.0, out.gu.c.data(), cf, cg);
    add_product2(ea.data(), p, r, vua.data(), Vu.m, Vu.n, 1.0, out.mu.c.data(), cf, cg);
    add_product2(e.data(), p, r, Vv.c.data(), Vv.m, Vv.n, 1.0, out.gv.c.data(), cf, cg);
    add_product2(ea.data(), p, r, vva.data(), Vv.m, Vv.n, 1.0, out.mv.c.data(), cf, cg);
  }
  for (Bernstein2* b : {&out.gu, &out.gv, &out.mu, &out.mv}) finish_products2(b->c.data(), b->m, b->n);
  return out;
}

/// Splits a tensor array of (m + 1)·(n + 1) rows of `cols` values (row i·(n + 1) + j) at ½ in its first
/// (dir 0) or second parameter into L and R.
void split_half(const double* A, int m, int n, std::ptrdiff_t cols, int dir, double* L, double* R,
                std::vector<double>& work) {
  const std::ptrdiff_t line = (n + 1) * cols;
  if (dir == 0) {
    work.resize(static_cast<std::size_t>((m + 1) * line));
    bezier_split(A, m, line, 0.5, L, R, work.data());
    return;
  }
  work.resize(static_cast<std::size_t>(line));
  for (int i = 0; i <= m; ++i)
    bezier_split(A + i * line, n, cols, 0.5, L + i * line, R + i * line, work.data());
}

/// The Bernstein basis of degree p at s and its first two derivatives: N[k·(p + 1) + i], k = 0, 1, 2.
void bernstein_derivatives(int p, double s, double* N) {
  double b[kMaxDegree + 1], b1[kMaxDegree + 1], b2[kMaxDegree + 1];
  std::fill_n(b1, p + 1, 0.0);
  std::fill_n(b2, p + 1, 0.0);
  b[0] = 1;
  for (int k = 1; k <= p; ++k) {
    if (k == p - 1) std::copy_n(b, k, b2);  // degree p − 2: k values
    if (k == p) std::copy_n(b, k, b1);      // degree p − 1
    b[k] = s * b[k - 1];
    for (int i = k - 1; i >= 1; --i) b[i] = (1 - s) * b[i] + s * b[i - 1];
    b[0] = (1 - s) * b[0];
  }
  if (p == 1) b2[0] = 0;  // no degree −1
  if (p == 2) b2[0] = 1;  // degree 0
  const auto at = [](const double* x, int i, int size) { return i >= 0 && i < size ? x[i] : 0.0; };
  for (int i = 0; i <= p; ++i) {
    N[i] = b[i];
    N[p + 1 + i] = p * (at(b1, i - 1, p) - at(b1, i, p));
    N[2 * (p + 1) + i] =
        p < 2 ? 0.0 : p * (p - 1) * (at(b2, i - 2, p - 1) - 2 * at(b2, i - 1, p - 1) + at(b2, i, p - 1));
  }
}

/// The partial derivatives PatchEval gives, in its order: (k, l) = ∂^{k+l} / ∂s^k ∂t^l.
constexpr int kPartials[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};

/// A patch's Cartesian point and partial derivatives at (s, t): S, S_s, S_t, S_ss, S_st, S_tt (dim values
/// each, at k·dim), by the quotient rule when rational.
class PatchEval {
 public:
  explicit PatchEval(const PatchLayout& l)
      : l_(l),
        nu_(static_cast<std::size_t>(3 * (l.p + 1))),
        nv_(static_cast<std::size_t>(3 * (l.q + 1))),
        t_(static_cast<std::size_t>(std::ptrdiff_t{3} * (l.p + 1) * l.cols)),
        h_(static_cast<std::size_t>(6 * l.cols)),
        s_(static_cast<std::size_t>(6 * l.dim)) {}

  const double* operator()(const double* B, double s, double t) {
    const int p = l_.p, q = l_.q, d = l_.dim;
    const std::ptrdiff_t n = l_.cols;
    bernstein_derivatives(p, s, nu_.data());
    bernstein_derivatives(q, t, nv_.data());
    // T[l][i] = Σ_j Nv^(l)_j B_ij, then H(k, l) = Σ_i Nu^(k)_i T[l][i] for k + l ≤ 2.
    std::fill(t_.begin(), t_.end(), 0.0);
    for (int lv = 0; lv <= 2; ++lv)
      for (int i = 0; i <= p; ++i) {
        double* dst = t_.data() + (lv * (p + 1) + i) * n;
        for (int j = 0; j <= q; ++j) {
          const double f = nv_[as_size(lv * (q + 1) + j)];
          const double* src = B + (i * (q + 1) + j) * n;
          for (std::ptrdiff_t k = 0; k < n; ++k) dst[k] += f * src[k];
        }
      }
    std::fill(h_.begin(), h_.end(), 0.0);
    for (int slot = 0; slot < 6; ++slot) {
      const int ku = kPartials[slot][0], lv = kPartials[slot][1];
      double* dst = h_.data() + slot * n;
      for (int i = 0; i <= p; ++i) {
        const double f = nu_[as_size(ku * (p + 1) + i)];
        const double* src = t_.data() + (lv * (p + 1) + i) * n;
        for (std::ptrdiff_t k = 0; k < n; ++k) dst[k] += f * src[k];
      }
    }
    double* S = s_.data();
    const double* H = h_.data();
    if (!l_.rational) {
      for (int slot = 0; slot < 6; ++slot) std::copy_n(H + slot * n, d, S + std::ptrdiff_t{slot} * d);
      return S;
    }
    // slots: 0 S, 1 S_s, 2 S_t, 3 S_ss, 4 S_st, 5 S_tt; w's partials at H[slot·n + d].
    const auto w = [&](int slot) { return H[slot * n + d]; };
    const double w0 = w(0);
    for (int k = 0; k < d; ++k) {
      const auto h = [&](int slot) { return H[slot * n + k]; };
      const double s0 = h(0) / w0;
      const double su = (h(1) - w(1) * s0) / w0, sv = (h(2) - w(2) * s0) / w0;
      S[k] = s0;
      S[d + k] = su;
      S[2 * d + k] = sv;
      S[3 * d + k] = (h(3) - 2 * w(1) * su - w(3) * s0) / w0;
      S[4 * d + k] = (h(4) - w(1) * sv - w(2) * su - w(4) * s0) / w0;
      S[5 * d + k] = (h(5) - 2 * w(2) * sv - w(5) * s0) / w0;
    }
    return S;
  }

 private:
  PatchLayout l_;
  std::vector<double> nu_, nv_, t_, h_, s_;
};

/// A lower bound on the distance from q to the convex hull of `count` Cartesian points (dim values each):
/// the larger of the distance to their bounding box and, along the unit vector e from their centroid to q,
/// e·q less the largest e·x (the hull lies behind that plane).
double hull_bound(const double* xs, int count, int dim, const Point& q) {
  double box = 0, e2 = 0;
  double centroid[16];  // dims above 16: the box alone
  const bool slab = dim <= 16;
  for (int k = 0; k < dim; ++k) {
    double lo = HUGE_VAL, hi = -HUGE_VAL, sum = 0;
    for (int j = 0; j < count; ++j) {
      const double x = xs[j * dim + k];
      lo = std::min(lo, x);
      hi = std::max(hi, x);
      sum += x;
    }
    const double out = std::max({lo - q(k), q(k) - hi, 0.0});
    box += out * out;
    if (slab) {
      centroid[k] = q(k) - sum / count;
      e2 += centroid[k] * centroid[k];
    }
  }
  double bound = std::sqrt(box);
  if (!slab || !(e2 > 0)) return bound;
  const double inv = 1 / std::sqrt(e2);
  double eq = 0, most = -HUGE_VAL;
  for (int k = 0; k < dim; ++k) eq += centroid[k] * inv * q(k);
  for (int j = 0; j < count; ++j) {
    double ex = 0;
    for (int k = 0; k < dim; ++k) ex += centroid[k] * inv * xs[j * dim + k];
    most = std::max(most, ex);
  }
  return std::max(bound, eq - most);
}

/// The angular interval [lo, hi] (narrower than π) of the vectors of the box [x0, x1] × [y0, y1]; false
/// when the box holds the origin (every direction).
bool box_angles(double x0, double x1, double y0, double y1, double& lo, double& hi) {
  if (x0 <= 0 && x1 >= 0 && y0 <= 0 && y1 >= 0) return false;
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1), base = std::atan2(cy, cx);
  lo = HUGE_VAL;
  hi = -HUGE_VAL;
  for (const double x : {x0, x1})
    for (const double y : {y0, y1}) {
      const double a = std::atan2(cx * y - cy * x, cx * x + cy * y);  // relative to the centre's direction
      lo = std::min(lo, a);
      hi = std::max(hi, a);
    }
  lo += base - 1e-9;
  hi += base + 1e-9;
  return hi - lo < std::numbers::pi;
}

/// The box of the gradients (∂σ g, ∂τ g) of a Bernstein polynomial over its piece, widened by the
/// rounding `r` of its coefficients.
std::array<double, 4> gradient_box(const Bernstein2& g, double r) {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool any_x = false, any_y = false;
  const auto at = [&](int i, int j) { return g.c[as_size(i * (g.n + 1) + j)]; };
  for (int i = 0; i < g.m; ++i)
    for (int j = 0; j <= g.n; ++j) {
      const double x = g.m * (at(i + 1, j) - at(i, j));
      x0 = any_x ? std::min(x0, x) : x;
      x1 = any_x ? std::max(x1, x) : x;
      any_x = true;
    }
  for (int i = 0; i <= g.m; ++i)
    for (int j = 0; j < g.n; ++j) {
      const double y = g.n * (at(i, j + 1) - at(i, j));
      y0 = any_y ? std::min(y0, y) : y;
      y1 = any_y ? std::max(y1, y) : y;
      any_y = true;
    }
  const double slack_x = 2 * g.m * r, slack_y = 2 * g.n * r;
  return {x0 - slack_x, x1 + slack_x, y0 - slack_y, y1 + slack_y};
}

/// Elber and Kim's test: g_u and g_v have at most one common zero on a convex piece when no direction is
/// normal to a gradient of each (two zeros a ≠ b: each g has a gradient normal to b − a, by the mean
/// value theorem). Here: the angular intervals of both gradient boxes, taken modulo π, are disjoint.
bool one_zero_at_most(const Bernstein2& gu, double ru, const Bernstein2& gv, double rv) {
  const auto bu = gradient_box(gu, ru), bv = gradient_box(gv, rv);
  double a1 = 0, b1 = 0, a2 = 0, b2 = 0;
  if (!box_angles(bu[0], bu[1], bu[2], bu[3], a1, b1) || !box_angles(bv[0], bv[1], bv[2], bv[3], a2, b2))
    return false;
  const double pi = std::numbers::pi;
  const double k0 = std::round(((a1 + b1) - (a2 + b2)) / (2 * pi));  // I2 shifted by k0·π is nearest I1
  for (int k = -1; k <= 1; ++k) {
    const double shift = (k0 + k) * pi;
    if (a2 + shift <= b1 && a1 <= b2 + shift) return false;
  }
  return true;
}

/// The Bézier matrix of the non-empty span k of knots t (degree p): row j holds the weights of the span's
/// p + 1 control points in Bézier coefficient j (the blossom at a^{p−j} b^j, [a, b] the span).
void span_bezier_matrix(const double* t, int p, int k, double* M) {
  double args[kMaxDegree];
  for (int j = 0; j <= p; ++j) {
    for (int i = 0; i < p; ++i) args[i] = i < p - j ? t[k] : t[k + 1];
    detail::blossom_weights_increasing(t, p, k, args, M + std::ptrdiff_t{j} * (p + 1));
  }
}

/// `count` consecutive stored rows to Cartesian points xs (dim values each).
void project_rows(const double* rows, int count, const PatchLayout& l, double* xs) {
  for (int j = 0; j < count; ++j)
    detail::project(rows + j * l.cols, l.dim, l.rational, xs + std::ptrdiff_t{j} * l.dim);
}

}  // namespace

SurfaceClosestPoints closest_point(const Surface& s, const Point& q, double tolerance) {
  check_tolerance(tolerance);
  const int dim = dimension(s);
  if (q.size() != dim)
    detail::fail("closest point: the point has ", q.size(), " coordinates, the surface ", dim);
  if (!q.allFinite()) detail::fail("closest point: the point is not finite");
  if (s.degree[0] < 1 || s.degree[1] < 1)
    detail::fail("closest point: the surface has degree ", s.degree[0], " × ", s.degree[1],
                 "; degree 0 is not continuous");
  const PatchLayout l{s.degree[0], s.degree[1], s.P.cols(), dim, s.rational};
  const int p = l.p, pq = l.q;
  const double size = size_of(s.P, dim, s.rational), eq = tolerance * size;
  const Domain du = domain(s, Direction::u), dv = domain(s, Direction::v);
  const auto distance_to = [&](const double* x) {
    double sum = 0;
    for (int k = 0; k < dim; ++k) sum += (x[k] - q(k)) * (x[k] - q(k));
    return std::sqrt(sum);
  };

  // The non-empty spans of each direction: the Bézier patches are their pairs.
  std::array<std::vector<int>, 2> spans;
  for (int d = 0; d < 2; ++d) {
    const Knots& t = s.knots[static_cast<std::size_t>(d)];
    for (int k = s.degree[static_cast<std::size_t>(d)]; k < s.count[static_cast<std::size_t>(d)]; ++k)
      if (t[static_cast<std::size_t>(k)] < t[static_cast<std::size_t>(k) + 1])
        spans[static_cast<std::size_t>(d)].push_back(k);
  }
  const std::size_t nb = spans[1].size();
  struct Patch {
    int a = 0, b = 0;  // spans
    double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
    std::vector<double> B;
    double ru = 0, rv = 0;                // rounding of the critical polynomials
    bool zero_u = false, zero_v = false;  // a critical polynomial vanishes on the patch (to its rounding)
  };
  std::vector<Patch> patches(spans[0].size() * nb);

  // What was found: isolated points (domain parameters), and rectangles at a constant distance.
  struct Found {
    double u, v, dist;
  };
  struct Region {
    std::array<double, 4> r;  // u0, u1, v0, v1
    double dist;
  };
  std::vector<Found> found;
  std::vector<Region> regions;
  double upper = HUGE_VAL;  // the distance of some surface point: every nearest point is within it

  // The work queue, nearest lower bound first: edge curves, patches not yet made, pieces of patches.
  enum class Kind { edge, patch, piece };
  struct Entry {
    double bound;
    Kind kind;
    std::size_t index;
    bool operator>(const Entry& o) const { return bound > o.bound; }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;

  // Edges of the domain, and interior knot lines where the surface is not C¹ (multiplicity ≥ degree):
  // there a nearest point need not be a zero of F; the curve closest_point of the iso-curve finds it.
  struct Edge {
    Direction dir;  // the iso-curve at `at` of this direction, running along the other (made when needed)
    double at;
  };
  std::vector<Edge> edges;
  const Eigen::Index nv = s.count[1];
  std::vector<double> xs;
  for (const Direction dir : {Direction::u, Direction::v}) {
    const auto d = static_cast<std::size_t>(dir);
    const Knots& t = s.knots[d];
    const int degree = s.degree[d];
    const Domain dom = domain(s, dir);
    std::vector<double> lines{dom.start};
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t[k] > dom.start && t[k] < dom.end && t[k] != lines.back() && multiplicity(t, t[k]) >= degree)
        lines.push_back(t[k]);
    lines.push_back(dom.end);
    // The iso-curve's control points are convex combinations of the degree + 1 lines of the net under its
    // span (positive weights): the hull of those bounds it.
    const Eigen::Index across = s.count[1 - d];
    xs.resize(static_cast<std::size_t>((degree + 1) * across * dim));
    for (const double at : lines) {
      const int span = find_span(t, degree, at);
      for (int r = 0; r <= degree; ++r)
        for (Eigen::Index j = 0; j < across; ++j) {
          const Eigen::Index i = span - degree + r;
          const Eigen::Index row = dir == Direction::u ? i * nv + j : j * nv + i;
          detail::project(s.P.data() + row * l.cols, dim, s.rational, xs.data() + (r * across + j) * dim);
        }
      edges.push_back({dir, at});
      queue.push({hull_bound(xs.data(), static_cast<int>((degree + 1) * across), dim, q), Kind::edge,
                  edges.size() - 1});
    }
  }
  // The patches by the hull of their (p + 1)(q + 1) B-spline control points.
  xs.resize(as_size((p + 1) * (pq + 1) * dim));
  for (std::size_t ia = 0; ia < spans[0].size(); ++ia)
    for (std::size_t ib = 0; ib < nb; ++ib) {
      Patch& pt = patches[ia * nb + ib];
      pt.a = spans[0][ia];
      pt.b = spans[1][ib];
      pt.u0 = s.knots[0][static_cast<std::size_t>(pt.a)];
      pt.u1 = s.knots[0][static_cast<std::size_t>(pt.a) + 1];
      pt.v0 = s.knots[1][static_cast<std::size_t>(pt.b)];
      pt.v1 = s.knots[1][static_cast<std::size_t>(pt.b) + 1];
      for (int r = 0; r <= p; ++r)
        for (int c = 0; c <= pq; ++c)
          detail::project(s.P.data() + ((pt.a - p + r) * nv + (pt.b - pq + c)) * l.cols, dim, s.rational,
                          xs.data() + std::ptrdiff_t{r * (pq + 1) + c} * dim);
      queue.push({hull_bound(xs.data(), (p + 1) * (pq + 1), dim, q), Kind::patch, ia * nb + ib});
    }

  // Pieces of patches: a rectangle [s0, s1] × [t0, t1] of the patch's local parameters, its control rows
  // and critical polynomials (de Casteljau restrictions of the patch's).
  struct Piece {
    std::size_t patch = 0;
    double s0 = 0, s1 = 1, t0 = 0, t1 = 1;
    int depth = 0;
    std::vector<double> B;
    Bernstein2 gu, gv;
  };
  std::vector<Piece> pieces;
  constexpr int kMaxDepth = 40;  // 2^-40 of a span: below rounding of the parameters
  constexpr std::size_t kMaxPieces = 20000;
  PatchEval eval(l);
  // Local parameters to the domain's (lerp: exact at both ends, never beyond them).
  const auto to_u = [&](const Patch& pt, double sl) { return std::lerp(pt.u0, pt.u1, sl); };
  const auto to_v = [&](const Patch& pt, double tl) { return std::lerp(pt.v0, pt.v1, tl); };
  const auto patch_distance = [&](const Patch& pt, double sl, double tl) {
    return distance_to(eval(pt.B.data(), sl, tl));
  };
  const auto add_point = [&](const Patch& pt, double sl, double tl) {
    const double dist = patch_distance(pt, sl, tl);
    upper = std::min(upper, dist);
    found.push_back({to_u(pt, sl), to_v(pt, tl), dist});
  };
  const auto add_region = [&](const Patch& pt, double sa, double sb, double ta, double tb) {
    const double dist = patch_distance(pt, 0.5 * (sa + sb), 0.5 * (ta + tb));
    upper = std::min(upper, dist);
    regions.push_back({{to_u(pt, sa), to_u(pt, sb), to_v(pt, ta), to_v(pt, tb)}, dist});
  };

  // Newton's method on F = ((S − q)·S_s, (S − q)·S_t) on the patch, from the centre of the piece and kept
  // inside it: true with the zero (sl, tl) when the steps converge inside.
  const auto newton = [&](const Patch& pt, const Piece& pc, double& sl, double& tl) {
    sl = 0.5 * (pc.s0 + pc.s1);
    tl = 0.5 * (pc.t0 + pc.t1);
    const double slack_s = 1e-9 * (pc.s1 - pc.s0) + 1e-15, slack_t = 1e-9 * (pc.t1 - pc.t0) + 1e-15;
    double last = HUGE_VAL;
    for (int it = 0; it < 64; ++it) {
      const double* S = eval(pt.B.data(), sl, tl);
      double F1 = 0, F2 = 0, J11 = 0, J12 = 0, J22 = 0;
      for (int k = 0; k < dim; ++k) {
        const double r = S[k] - q(k), Ss = S[dim + k], St = S[2 * dim + k];
        F1 += r * Ss;
        F2 += r * St;
        J11 += Ss * Ss + r * S[3 * dim + k];
        J12 += Ss * St + r * S[4 * dim + k];
        J22 += St * St + r * S[5 * dim + k];
      }
      const double det = J11 * J22 - J12 * J12;
      const double ds = (J12 * F2 - J22 * F1) / det, dt = (J12 * F1 - J11 * F2) / det;
      if (!std::isfinite(ds) || !std::isfinite(dt)) return false;
      const double ns = sl + ds, nt = tl + dt;
      const bool inside =
          ns >= pc.s0 - slack_s && ns <= pc.s1 + slack_s && nt >= pc.t0 - slack_t && nt <= pc.t1 + slack_t;
      sl = std::clamp(ns, pc.s0, pc.s1);
      tl = std::clamp(nt, pc.t0, pc.t1);
      // Converged: a step below 1e-13 of the patch, or steps of rounding noise that stopped shrinking (a
      // nearly degenerate minimum, q near a focal point, where F/J rounds to ~1e-12).
      const double step = std::max(std::abs(ds), std::abs(dt));
      if (step <= 1e-13 || (step <= 1e-9 && step > 0.5 * last)) return inside;
      last = step;
    }
    return false;
  };

  std::vector<double> work, h, roots_work;
  std::size_t made = 0;
  const auto push_piece = [&](Piece&& pc) {
    if (++made > kMaxPieces)
      detail::fail("closest point: the nearest points are not isolated near (u, v) = (",
                   to_u(patches[pc.patch], pc.s0), ", ", to_v(patches[pc.patch], pc.t0),
                   "): a curve of them that no parameter line follows");
    xs.resize(as_size((p + 1) * (pq + 1) * dim));
    project_rows(pc.B.data(), (p + 1) * (pq + 1), l, xs.data());
    const double bound = hull_bound(xs.data(), (p + 1) * (pq + 1), dim, q);
    if (bound > upper + eq) return;
    pieces.push_back(std::move(pc));
    queue.push({bound, Kind::piece, pieces.size() - 1});
  };

  /// One side of a piece whose other critical polynomial vanishes: the distance depends on one local
  /// parameter only, and its nearest lines are the roots of g (its coefficients along one edge, `count`
  /// values at `stride`), and the piece's ends (where a root at the end may round to either side).
  const auto lines_of = [&](const Patch& pt, const Piece& pc, const Bernstein2& g, double r, bool along_u) {
    const int count = along_u ? g.m + 1 : g.n + 1;
    h.resize(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i)
      h[static_cast<std::size_t>(i)] = g.c[static_cast<std::size_t>(along_u ? i * (g.n + 1) : i)];
    const double a = along_u ? pc.s0 : pc.t0, b = along_u ? pc.s1 : pc.t1;
    Roots roots;
    roots_work.resize(h.size());
    bezier_roots(h, a, b, r, 0, roots, roots_work);
    roots.at.insert(roots.at.end(), {a, b});
    for (const auto& iv : roots.intervals) {
      if (along_u)
        add_region(pt, iv[0], iv[1], pc.t0, pc.t1);
      else
        add_region(pt, pc.s0, pc.s1, iv[0], iv[1]);
    }
    for (const double x : roots.at) {
      if (along_u)
        add_region(pt, x, x, pc.t0, pc.t1);
      else
        add_region(pt, pc.s0, pc.s1, x, x);
    }
  };

  const auto examine = [&](Piece& pc) {
    const Patch& pt = patches[pc.patch];
    // The corners are surface points: the best distance so far.
    xs.resize(static_cast<std::size_t>(dim));
    for (const int i : {0, p})
      for (const int j : {0, pq}) {
        detail::project(pc.B.data() + (i * (pq + 1) + j) * l.cols, dim, s.rational, xs.data());
        upper = std::min(upper, distance_to(xs.data()));
      }
    const auto [u_lo, u_hi] = std::minmax_element(pc.gu.c.begin(), pc.gu.c.end());
    const auto [v_lo, v_hi] = std::minmax_element(pc.gv.c.begin(), pc.gv.c.end());
    // Vanishing is decided on the whole patch (a polynomial that vanishes on a piece vanishes everywhere):
    // a small piece near a zero line of g is within g's rounding without g vanishing.
    const bool zero_u = pt.zero_u, zero_v = pt.zero_v;
    if (zero_u && zero_v) {  // every point critical: the distance is constant on the piece
      add_region(pt, pc.s0, pc.s1, pc.t0, pc.t1);
      return;
    }
    // A component of F that keeps its sign on the piece: no zero inside.
    if (!zero_u && (*u_lo > pt.ru || *u_hi < -pt.ru)) return;
    if (!zero_v && (*v_lo > pt.rv || *v_hi < -pt.rv)) return;
    if (zero_v) {  // the distance does not depend on t: lines of constant s
      lines_of(pt, pc, pc.gu, pt.ru, true);
      return;
    }
    if (zero_u) {
      lines_of(pt, pc, pc.gv, pt.rv, false);
      return;
    }
    double sl = 0, tl = 0;
    if (one_zero_at_most(pc.gu, pt.ru, pc.gv, pt.rv) && newton(pt, pc, sl, tl)) {
      add_point(pt, sl, tl);
      return;
    }
    if (pc.depth >= kMaxDepth) {  // below the rounding of the parameters: its centre
      add_point(pt, 0.5 * (pc.s0 + pc.s1), 0.5 * (pc.t0 + pc.t1));
      return;
    }
    // Four quarters: halves in s, then each in t.
    const double sm = 0.5 * (pc.s0 + pc.s1), tm = 0.5 * (pc.t0 + pc.t1);
    std::array<Piece, 4> kids;
    for (std::size_t k = 0; k < 4; ++k) {
      kids[k].patch = pc.patch;
      kids[k].depth = pc.depth + 1;
      kids[k].s0 = k < 2 ? pc.s0 : sm;
      kids[k].s1 = k < 2 ? sm : pc.s1;
      kids[k].t0 = k % 2 == 0 ? pc.t0 : tm;
      kids[k].t1 = k % 2 == 0 ? tm : pc.t1;
      kids[k].B.resize(l.size());
      kids[k].gu = {pc.gu.m, pc.gu.n, std::vector<double>(pc.gu.size())};
      kids[k].gv = {pc.gv.m, pc.gv.n, std::vector<double>(pc.gv.size())};
    }
    std::vector<double> L, R;
    const auto quarter = [&](const double* A, int m, int n, std::ptrdiff_t cols, auto member) {
      const auto total = static_cast<std::size_t>(std::ptrdiff_t{m + 1} * (n + 1) * cols);
      L.resize(total);
      R.resize(total);
      split_half(A, m, n, cols, 0, L.data(), R.data(), work);
      split_half(L.data(), m, n, cols, 1, member(kids[0]), member(kids[1]), work);
      split_half(R.data(), m, n, cols, 1, member(kids[2]), member(kids[3]), work);
    };
    quarter(pc.B.data(), p, pq, l.cols, [](Piece& k) { return k.B.data(); });
    quarter(pc.gu.c.data(), pc.gu.m, pc.gu.n, 1, [](Piece& k) { return k.gu.c.data(); });
    quarter(pc.gv.c.data(), pc.gv.m, pc.gv.n, 1, [](Piece& k) { return k.gv.c.data(); });
    for (Piece& k : kids) push_piece(std::move(k));
  };

  std::vector<double> Mu(static_cast<std::size_t>((p + 1) * (p + 1))),
      Mv(static_cast<std::size_t>((pq + 1) * (pq + 1))), T;
  while (!queue.empty()) {
    const Entry top = queue.top();
    queue.pop();
    if (top.bound > upper + eq) break;  // every other entry is farther
    if (top.kind == Kind::edge) {
      const Edge& e = edges[top.index];
      const Curve c = iso_curve(s, e.dir, e.at);
      // The curve's own tolerance scaled so that it keeps every point within eq of its nearest.
      const double tol = std::clamp(tolerance * size / size_of(c), 1e-15, 0.5);
      const ClosestPoints cp = closest_point(c, q, tol);
      upper = std::min(upper, cp.distance);
      for (const double x : cp.parameters)
        found.push_back(e.dir == Direction::u ? Found{e.at, x, cp.distance} : Found{x, e.at, cp.distance});
      for (const auto& iv : cp.intervals)
        regions.push_back({e.dir == Direction::u ? std::array<double, 4>{e.at, e.at, iv[0], iv[1]}
                                                 : std::array<double, 4>{iv[0], iv[1], e.at, e.at},
                           cp.distance});
      continue;
    }
    if (top.kind == Kind::patch) {
      Patch& pt = patches[top.index];
      // The Bézier rows: v contracted first (T, (p + 1)·(q + 1) rows), then u.
      span_bezier_matrix(s.knots[0].data(), p, pt.a, Mu.data());
      span_bezier_matrix(s.knots[1].data(), pq, pt.b, Mv.data());
      T.assign(l.size(), 0.0);
      pt.B.assign(l.size(), 0.0);
      for (int r = 0; r <= p; ++r)
        for (int j = 0; j <= pq; ++j) {
          double* dst = T.data() + (r * (pq + 1) + j) * l.cols;
          for (int c = 0; c <= pq; ++c) {
            const double f = Mv[as_size(j * (pq + 1) + c)];
            const double* src = s.P.data() + ((pt.a - p + r) * nv + (pt.b - pq + c)) * l.cols;
            for (std::ptrdiff_t k = 0; k < l.cols; ++k) dst[k] += f * src[k];
          }
        }
      for (int i = 0; i <= p; ++i)
        for (int r = 0; r <= p; ++r) {
          const double f = Mu[as_size(i * (p + 1) + r)];
          for (int j = 0; j <= pq; ++j) {
            double* dst = pt.B.data() + (i * (pq + 1) + j) * l.cols;
            const double* src = T.data() + (r * (pq + 1) + j) * l.cols;
            for (std::ptrdiff_t k = 0; k < l.cols; ++k) dst[k] += f * src[k];
          }
        }
      xs.resize(as_size((p + 1) * (pq + 1) * dim));
      project_rows(pt.B.data(), (p + 1) * (pq + 1), l, xs.data());
      if (hull_bound(xs.data(), (p + 1) * (pq + 1), dim, q) > upper + eq) continue;  // the tighter hull
      CriticalPair cr = surface_critical(pt.B.data(), l, q);
      pt.ru = 1e3 * kEps * *std::max_element(cr.mu.c.begin(), cr.mu.c.end());
      pt.rv = 1e3 * kEps * *std::max_element(cr.mv.c.begin(), cr.mv.c.end());
      const auto small = [](const Bernstein2& g, double r) {
        return std::all_of(g.c.begin(), g.c.end(), [&](double x) { return std::abs(x) <= r; });
      };
      pt.zero_u = small(cr.gu, pt.ru);
      pt.zero_v = small(cr.gv, pt.rv);
      Piece root;
      root.patch = top.index;
      root.B = pt.B;
      root.gu = std::move(cr.gu);
      root.gv = std::move(cr.gv);
      push_piece(std::move(root));
      continue;
    }
    Piece pc = std::move(pieces[top.index]);
    examine(pc);
  }

  // The answer: everything within eq of the smallest distance found.
  SurfaceClosestPoints out;
  double best = HUGE_VAL;
  for (const Found& f : found) best = std::min(best, f.dist);
  for (const Region& r : regions) best = std::min(best, r.dist);
  out.distance = best;
  const double close_u = 1e-9 * (du.end - du.start), close_v = 1e-9 * (dv.end - dv.start);
  const double same_point = 1e-8 * size;
  // Regions: merged where they share a side; one whose image is a single point (a pole) becomes a point.
  std::vector<std::array<double, 4>> kept;
  for (const Region& r : regions)
    if (r.dist <= best + eq) kept.push_back(r.r);
  const auto near = [](double a, double b, double gap) { return std::abs(a - b) <= gap; };
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < kept.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < kept.size() && !merged; ++j) {
        auto& a = kept[i];
        const auto& b = kept[j];
        const bool same_u = near(a[0], b[0], close_u) && near(a[1], b[1], close_u);
        const bool same_v = near(a[2], b[2], close_v) && near(a[3], b[3], close_v);
        const bool touch_v = b[2] <= a[3] + close_v && a[2] <= b[3] + close_v;
        const bool touch_u = b[0] <= a[1] + close_u && a[0] <= b[1] + close_u;
        const bool inside = b[0] >= a[0] - close_u && b[1] <= a[1] + close_u && b[2] >= a[2] - close_v &&
                            b[3] <= a[3] + close_v;
        const bool holds = a[0] >= b[0] - close_u && a[1] <= b[1] + close_u && a[2] >= b[2] - close_v &&
                           a[3] <= b[3] + close_v;
        if ((same_u && touch_v) || (same_v && touch_u) || inside || holds) {
          a = {std::min(a[0], b[0]), std::max(a[1], b[1]), std::min(a[2], b[2]), std::max(a[3], b[3])};
          kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
      }
  }
  std::vector<Found> candidates;
  for (const auto& r : kept) {
    const Point first = evaluate(s, r[0], r[2]);
    double spread = 0;
    for (const double a : {0.0, 0.25, 0.5, 0.75, 1.0})
      for (const double b : {0.0, 0.5, 1.0})
        spread = std::max(spread,
                          (evaluate(s, std::lerp(r[0], r[1], a), std::lerp(r[2], r[3], b)) - first).norm());
    if (spread <= eq)
      candidates.push_back({r[0], r[2], (first - q).norm()});
    else
      out.regions.push_back(r);
  }
  for (const Found& f : found)
    if (f.dist <= best + eq) candidates.push_back(f);
  std::sort(candidates.begin(), candidates.end(),
            [](const Found& a, const Found& b) { return a.u < b.u || (a.u == b.u && a.v < b.v); });
  std::vector<Found> isolated;
  std::vector<Point> at;
  for (const Found& f : candidates) {
    const bool inside = std::any_of(out.regions.begin(), out.regions.end(), [&](const auto& r) {
      return f.u >= r[0] - close_u && f.u <= r[1] + close_u && f.v >= r[2] - close_v && f.v <= r[3] + close_v;
    });
    if (inside) continue;
    Point x = evaluate(s, f.u, f.v);
    bool repeated = false;
    for (std::size_t i = 0; i < isolated.size() && !repeated; ++i)
      if ((at[i] - x).norm() <= same_point) {
        repeated = true;
        if (f.dist < isolated[i].dist) {
          isolated[i] = f;
          at[i] = x;
        }
      }
    if (!repeated) {
      isolated.push_back(f);
      at.push_back(std::move(x));
    }
  }
  out.points.resize(static_cast<Eigen::Index>(isolated.size()), dim);
  for (std::size_t i = 0; i < isolated.size(); ++i) {
    out.parameters.push_back({isolated[i].u, isolated[i].v});
    out.points.row(static_cast<Eigen::Index>(i)) = at[i];
  }
  return out;
}

}  // namespace cifs::nurbs
