// SPDX-License-Identifier: MIT
#include "cifs/nurbs/measure.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

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
/// largest coordinate (the rounding of coordinates grows with it), 1 for a curve at the origin.
double size_of(const Curve& c) {
  const int d = dimension(c);
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(d, HUGE_VAL), hi = Eigen::VectorXd::Constant(d, -HUGE_VAL);
  double largest = 0;
  for (Eigen::Index i = 0; i < c.P.rows(); ++i)
    for (int k = 0; k < d; ++k) {
      const double x = c.rational ? c.P(i, k) / c.P(i, d) : c.P(i, k);
      lo(k) = std::min(lo(k), x);
      hi(k) = std::max(hi(k), x);
      largest = std::max(largest, std::abs(x));
    }
  const double size = std::max((hi - lo).norm(), largest);
  return size > 0 ? size : 1.0;
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

}  // namespace cifs::nurbs
