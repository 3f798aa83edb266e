// SPDX-License-Identifier: MIT
// Internal kernels shared by the curve, surface and refinement sources.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knots.hpp"
#include "cifs/types.hpp"

namespace cifs::nurbs::detail {

/// Doubles go through the one number formatter (17 digits, "nan" without a sign).
template <class Part>
void append_part(std::ostringstream& out, const Part& part) {
  if constexpr (std::is_floating_point_v<Part>)
    out << number_text(static_cast<double>(part), 17);
  else
    out << part;
}

template <class... Parts>
[[noreturn]] void fail(Parts&&... parts) {
  std::ostringstream out;
  (append_part(out, parts), ...);
  throw InvalidInput(out.str());
}

/// Derivative orders 0 … kMaxDegree: higher ones of a polynomial piece vanish, and the result has
/// (order + 1) rows ((order + 1)² for surfaces), which an unchecked order could overflow.
inline void check_derivative_order(int order) {
  if (order < 0 || order > kMaxDegree) fail("derivative order ", order, " is outside 0 … ", kMaxDegree);
}

/// Cartesian points and optional weights → stored rows (homogeneous `(w·x, w)` when weighted).
inline Points homogeneous(const Points& points, const Eigen::VectorXd& weights, std::string_view where) {
  if (weights.size() == 0) return points;
  if (weights.size() != points.rows())
    fail("weights: ", weights.size(), " weights given for ", points.rows(), " ", where);
  Points H(points.rows(), points.cols() + 1);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {  // weights are checked by validate()
    H.row(i).head(points.cols()) = weights(i) * points.row(i);
    H(i, points.cols()) = weights(i);
  }
  return H;
}

// ------------------------------------------------------------------------------------------------
// Column counts. The kernels below are templates on the number of stored coordinates: for 2, 3 and 4
// the per-point accumulators are local arrays of known size, which the compiler keeps in registers;
// Cols = 0 is the same code for any count, with the accumulators in caller memory.

/// Calls f(std::integral_constant<int, P>{}) with P = degree for 1, 2 and 3, and 0 otherwise: the
/// degrees whose kernels unroll (loops over p + 1 basis functions and a 2p + 1 band).
template <class F>
decltype(auto) with_degree(int degree, F&& f) {
  switch (degree) {
    case 1:
      return f(std::integral_constant<int, 1>{});
    case 2:
      return f(std::integral_constant<int, 2>{});
    case 3:
      return f(std::integral_constant<int, 3>{});
    default:
      return f(std::integral_constant<int, 0>{});
  }
}

/// Calls f(std::integral_constant<int, Cols>{}) with Cols = cols for 2, 3 and 4, and 0 otherwise.
template <class F>
decltype(auto) with_cols(Eigen::Index cols, F&& f) {
  switch (cols) {
    case 2:
      return f(std::integral_constant<int, 2>{});
    case 3:
      return f(std::integral_constant<int, 3>{});
    case 4:
      return f(std::integral_constant<int, 4>{});
    default:
      return f(std::integral_constant<int, 0>{});
  }
}

/// Scratch doubles a Cols = 0 kernel needs per accumulator row (none for a fixed count).
template <int Cols>
std::vector<double> scratch(Eigen::Index cols, Eigen::Index rows = 1) {
  return std::vector<double>(Cols > 0 ? 0 : static_cast<std::size_t>(cols * rows));
}

// ------------------------------------------------------------------------------------------------
// Spans and bases.

/// Whether every value lies in [dom.start, dom.end] (NaN does not), and whether they are non-decreasing:
/// one pass without calls or branches, so that batch kernels need no per-point check.
struct Scan {
  bool inside;
  bool sorted;
};
inline Scan scan(std::span<const double> us, Domain dom) noexcept {
  int outside = 0, descents = 0;
  double previous = -HUGE_VAL;
  for (double u : us) {
    outside |= static_cast<int>(!(u >= dom.start)) | static_cast<int>(!(u <= dom.end));
    descents |= static_cast<int>(u < previous);
    previous = u;
  }
  return {outside == 0, descents == 0};
}

/// find_span on raw knots, n = number of control points: the last non-empty span at the domain end,
/// else upper_bound over t_{p+1..n−1} minus one, as a bisection whose only decision is a conditional
/// move (a fixed ⌈log₂⌉ steps: no mispredicted branches on unordered parameters).
inline int find_span(const double* t, int p, int n, double u) noexcept {
  if (u >= t[n]) {
    int k = n - 1;
    while (k > p && t[k] == t[n]) --k;
    return k;
  }
  const double* base = t + p + 1;
  std::ptrdiff_t len = n - p - 1;
  if (len <= 0) return p;
  while (len > 1) {
    const std::ptrdiff_t half = len / 2;
    base = base[half] <= u ? base + half : base;
    len -= half;
  }
  return static_cast<int>(base - t) + (*base <= u ? 1 : 0) - 1;
}

/// find_span starting from a guess: the guess itself, or the next span, else a bisection.
inline int find_span(const double* t, int p, int n, double u, int hint) noexcept {
  if (t[hint] <= u) {
    if (u < t[hint + 1]) return hint;
    if (hint + 2 <= n && u < t[hint + 2]) return hint + 1;
  }
  return find_span(t, p, n, u);
}

/// O(1) span search for unordered parameters in the domain: 4 buckets per span, each holding the span
/// of its left end; a lookup is a multiply, a load and rarely a step. It replaces the ⌈log₂⌉ dependent
/// loads of a bisection; building it costs O(#buckets + #knots), so batches use it only when the
/// parameters outnumber the knots.
class SpanTable {
 public:
  SpanTable(const double* t, int p, int n) : t_(t), p_(p), n_(n), start_(t[p]) {
    const int buckets = 4 * (n - p);
    scale_ = buckets / (t[n] - start_);
    first_.resize(static_cast<std::size_t>(buckets) + 2);  // x may round up to #buckets (+ spare)
    int k = p;
    for (std::size_t b = 0; b < first_.size(); ++b) {
      const double x = start_ + static_cast<double>(b) / scale_;
      while (k + 1 < n && t[k + 1] <= x) ++k;
      first_[b] = k;
    }
  }
  int find(double u) const noexcept {
    if (u >= t_[n_]) return find_span(t_, p_, n_, u);
    int k = first_[static_cast<std::size_t>((u - start_) * scale_)];
    // A bucket holds one knot at most, mostly: a conditional add, no branch that random parameters
    // mispredict. The loops run only for a bucket with more knots, or for the bucket's rounding.
    k += static_cast<int>(u >= t_[k + 1]);
    if (u >= t_[k + 1] || u < t_[k]) [[unlikely]] {
      while (u >= t_[k + 1]) ++k;  // stops before n: u < t_n
      while (k > p_ && u < t_[k]) --k;
    }
    return k;
  }

 private:
  const double* t_;
  int p_, n_;
  double start_, scale_ = 0;
  std::vector<int> first_;
};

/// The d + 1 non-zero basis functions on `span` (Piegl–Tiller A2.2); inline so that batch loops see
/// the degree loop. basis_functions calls it. P > 0: the degree known at compile time (= p), loops
/// unrolled.
template <int P = 0>
inline void basis(const double* t, int p, int span, double u, double* N) noexcept {
  double left[kMaxDegree + 1];
  double right[kMaxDegree + 1];
  const int d = P > 0 ? P : p;
  N[0] = 1.0;
  for (int j = 1; j <= d; ++j) {
    left[j] = u - t[span + 1 - j];
    right[j] = t[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double den = right[r + 1] + left[j - r];
      if (den >= std::numeric_limits<double>::min()) {
        const double temp = N[r] / den;
        N[r] = saved + right[r + 1] * temp;
        saved = left[j - r] * temp;
      } else {  // a subnormal knot interval: N[r] / den overflowed (inf · 0 = NaN); the ratios lie in [0, 1]
        const double n = N[r];
        N[r] = saved + right[r + 1] / den * n;
        saved = left[j - r] / den * n;
      }
    }
    N[j] = saved;
  }
}

/// basis() with the span's reciprocals 1 / (t_{span+1+r} − t_{span+1−j+r}) at inv[j(j−1)/2 + r]
/// (blossom_reciprocals): multiplications instead of the chain of divisions, for the many points a
/// batch evaluates on one span. The divisor comes from the knots directly (one rounding) instead of
/// (t_hi − u) + (u − t_lo); the results differ from basis() in the last bits only. The reciprocals
/// must be finite: a span with a knot interval below DBL_MIN takes basis().
inline void basis(const double* t, int p, int span, const double* inv, double u, double* N) noexcept {
  double left[kMaxDegree + 1];
  double right[kMaxDegree + 1];
  N[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - t[span + 1 - j];
    right[j] = t[span + j] - u;
    const double* level = inv + j * (j - 1) / 2;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = N[r] * level[r];
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
}

// ------------------------------------------------------------------------------------------------
// Closed curves: knots relative to a span.
//
// A closed curve stores its knots expanded (periodic_knots): beyond the period they are b_k ± T,
// rounded to u·|t|. Next to a short interval h that rounding is a relative error u·|t|/h in every
// coefficient (knots [0, 0.001, …, 1000.004]: 1e-10), and no knot vector of doubles avoids it
// (1000.004 + 0.001 has no exact double). Cox–de Boor, de Boor and blossoms are translation
// invariant, so the algorithms run instead on the knots relative to the span's own breakpoint, each
// a sum of differences of breakpoints that never cancel (below), and on parameters u − t_span.

/// Knot j of a periodic knot vector of degree p over m intervals is b_k + q·T: index k ∈ [0, m) of
/// the period's breakpoints and whole periods q.
struct PeriodicIndex {
  int k;
  int q;
};
inline PeriodicIndex periodic_index(int j, int p, int m) noexcept {
  const int s = j - p;
  const int q = s >= 0 ? s / m : -((m - 1 - s) / m);  // floor(s / m)
  return {s - q * m, q};
}

/// (x + q·T) − y for x, y in [b0, bm], T = bm − b0: for q ≠ 0 a sum of non-negative differences
/// ((x − b0) + (q − 1)·T + (bm − y) when q > 0), so the result is correct to a few roundings relative
/// to itself; for q = 0 the one rounding of x − y.
inline double periodic_difference(double x, int q, double y, double b0, double bm) noexcept {
  if (q == 0) return x - y;
  const double period = bm - b0;
  if (q > 0) return (x - b0) + (q - 1) * period + (bm - y);
  return -((bm - x) + (-q - 1) * period + (y - b0));
}

/// Knots of one span for an algorithm that is translation invariant: it reads t[span − p + 1 …
/// span + p] and takes its parameters and blossom arguments as x − origin.
struct SpanKnots {
  std::span<const double> t;
  int span = 0;
  double origin = 0;
};

/// The knots of `span` (a span of the domain) of a knot vector of degree p. Open vectors (m = 0):
/// the stored knots and origin 0, so that every result is bit-identical to the plain algorithm.
/// Periodic vectors over m intervals (periodic_knots, base breakpoints at t[p … p + m]): the 2p knots
/// t_{span−p+1 … span+p} − t_span by periodic_difference, written to `local`, with the span at p − 1.
inline SpanKnots span_knots(std::span<const double> t, int p, int m, int span, double* local) noexcept {
  if (m == 0) return {t, span, 0.0};
  const auto at = [&](int i) { return t[static_cast<std::size_t>(i)]; };
  const double b0 = at(p), bm = at(p + m), origin = at(span);
  for (int i = 0; i < 2 * p; ++i) {
    const PeriodicIndex pi = periodic_index(span - p + 1 + i, p, m);
    local[i] = periodic_difference(at(p + pi.k), pi.q, origin, b0, bm);
  }
  return {std::span<const double>(local, static_cast<std::size_t>(2 * p)), p - 1, origin};
}

/// The knots a kernel reads on a curve's span (`local` holds 2·degree values): relative ones only for
/// the spans of a closed curve that read a knot beyond the period (span − p + 1 < p or span + p > p + m:
/// the 2(p − 1) spans around the seam). Every other span reads breakpoints only, exact as given, and
/// keeps the plain arithmetic (no cost, the open-curve bound, the same bits as an open curve).
inline SpanKnots span_knots(const Curve& c, int span, double* local) noexcept {
  const int p = c.degree;
  const int m = c.closed ? static_cast<int>(c.P.rows()) - p : 0;
  const bool seam = m > 0 && (span - p + 1 < p || span + p > p + m);
  return span_knots(c.knots, p, seam ? m : 0, span, local);
}

// ------------------------------------------------------------------------------------------------
// Blossoms.

/// The blossom recursion on `span` with the arguments x in the order given, one per level.
inline void blossom_recurrence(const double* t, int p, int span, const double* x, double* W) noexcept {
  W[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    const double xj = x[j - 1];
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double lo = t[span + 1 - j + r], hi = t[span + 1 + r];
      const double temp = W[r] / (hi - lo);
      W[r] = saved + (hi - xj) * temp;
      saved = (xj - lo) * temp;
    }
    W[j] = saved;
  }
}

/// The arguments in blossom_weights' order — by distance to the span [a, b], then by value — for
/// non-decreasing args (consecutive knots): a merge outwards from the span, O(d) instead of a sort.
inline void nearest_first_increasing(const double* args, int p, double a, double b, double* x) noexcept {
  int lo = 0;
  while (lo < p && args[lo] < a) ++lo;  // args[0..lo) left of the span
  int hi = lo;
  while (hi < p && args[hi] <= b) ++hi;  // args[lo..hi) inside: distance 0, first
  for (int m = 0, i = lo, l = lo - 1, r = hi; m < p; ++m) {
    if (i < hi) {
      x[m] = args[i++];
    } else {
      const bool take_left = r == p || (l >= 0 && a - args[l] <= args[r] - b);
      x[m] = take_left ? args[l--] : args[r++];
    }
  }
}

/// blossom_weights for non-decreasing arguments: the same weights to the last bit.
inline void blossom_weights_increasing(const double* t, int p, int span, const double* args,
                                       double* W) noexcept {
  double x[kMaxDegree];
  nearest_first_increasing(args, p, t[span], t[span + 1], x);
  blossom_recurrence(t, p, span, x, W);
}

/// Size of the table of blossom_reciprocals.
inline constexpr int kReciprocals = kMaxDegree * (kMaxDegree + 1) / 2;

/// The divisors of the blossom recursion on `span` depend on the span only: their reciprocals
/// 1 / (t_{span+1+r} − t_{span+1−j+r}), level j = 1..p, r < j, at inv[j(j−1)/2 + r].
inline void blossom_reciprocals(const double* t, int p, int span, double* inv) noexcept {
  for (int j = 1, at = 0; j <= p; ++j)
    for (int r = 0; r < j; ++r) inv[at++] = 1.0 / (t[span + 1 + r] - t[span + 1 - j + r]);
}

/// blossom_recurrence with the span's reciprocals: multiplications instead of a chain of divisions,
/// for the many points that share a piece (refinement with many knots per span).
inline void blossom_recurrence(const double* t, int p, int span, const double* inv, const double* x,
                               double* W) noexcept {
  W[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    const double xj = x[j - 1];
    const double* level = inv + j * (j - 1) / 2;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double lo = t[span + 1 - j + r], hi = t[span + 1 + r];
      const double temp = W[r] * level[r];
      W[r] = saved + (hi - xj) * temp;
      saved = (xj - lo) * temp;
    }
    W[j] = saved;
  }
}

/// Blossom of the curve's piece on `span` at `args`, as a row of the stored coordinates.
inline Point blossom_row(const Curve& c, std::span<const double> args, int span) {
  const int p = c.degree;
  double local[2 * kMaxDegree], x[kMaxDegree], W[kMaxDegree + 1];
  const SpanKnots knots = span_knots(c, span, local);
  for (int i = 0; i < p; ++i) x[i] = args[static_cast<std::size_t>(i)] - knots.origin;
  blossom_weights(knots.t, p, knots.span, std::span<const double>(x, static_cast<std::size_t>(p)), W);
  Point out = Point::Zero(c.P.cols());
  for (int j = 0; j <= p; ++j) out += W[j] * c.P.row(span - p + j);
  return out;
}

// ------------------------------------------------------------------------------------------------
// Knot maps.

/// The same open curve with clamped ends: each end of the domain inserted up to multiplicity d, and the
/// knots and points beyond it dropped.
Curve clamped(const Curve& c);

/// The knots of the same spline traversed backwards, t'_j = a + b − t_{N−1−j}, the domain's ends a and b
/// kept exactly.
inline Knots mirrored_knots(std::span<const double> t, Domain dom) {
  const auto mirror = [&](double x) {
    return x == dom.start ? dom.end : x == dom.end ? dom.start : dom.start + dom.end - x;
  };
  Knots out(t.size());
  for (std::size_t j = 0; j < t.size(); ++j) out[j] = mirror(t[t.size() - 1 - j]);
  return out;
}

/// The knots mapped by the increasing affine map that sends `dom` onto [start, end], the ends exactly.
/// Each side of the domain is measured from its own end, and the inside is clamped to [start, end], so
/// that the rounded map stays non-decreasing. Throws when two distinct knots round to one value or a
/// knot overflows (the new scale has no double for it).
inline Knots mapped_knots(std::span<const double> t, Domain dom, double start, double end) {
  if (!std::isfinite(start) || !std::isfinite(end) || !(start < end))
    fail("the new domain [", start, ", ", end, "] is not an interval of finite numbers");
  const double scale = (end - start) / (dom.end - dom.start);
  if (!std::isfinite(scale) || !(scale > 0))
    fail("the map of [", dom.start, ", ", dom.end, "] onto [", start, ", ", end, "] has no finite scale");
  Knots out(t.size());
  for (std::size_t j = 0; j < t.size(); ++j) {
    const double x = t[j];
    out[j] = x == dom.start  ? start
             : x == dom.end  ? end
             : x < dom.start ? start + (x - dom.start) * scale
             : x > dom.end   ? end + (x - dom.end) * scale
                             : std::min(end, std::max(start, start + (x - dom.start) * scale));
    if (!std::isfinite(out[j])) fail("knots[", j, "] = ", x, " maps to ", out[j]);
    if (j > 0 && t[j - 1] < x && !(out[j - 1] < out[j]))
      fail("knots[", j - 1, "] = ", t[j - 1], " and knots[", j, "] = ", x, " map to one value ", out[j],
           ": the new domain is too small for them");
  }
  return out;
}

// ------------------------------------------------------------------------------------------------
// Rows.

/// A stored row → `dim` Cartesian coordinates (divided by w when rational).
inline void project(const double* row, int dim, bool rational, double* out) noexcept {
  if (rational)
    for (int k = 0; k < dim; ++k) out[k] = row[k] / row[dim];
  else
    for (int k = 0; k < dim; ++k) out[k] = row[k];
}

/// project for a stored column count known at compile time (Cols > 0; then dim = Cols − rational):
/// loops of fixed length, where a run-time `dim` made the copy a call to memcpy. Cols = 0: project.
template <int Cols>
[[gnu::always_inline]] inline void project(const double* row, int dim, bool rational, double* out) noexcept {
  if constexpr (Cols > 0) {
    if (rational)
      for (int k = 0; k < Cols - 1; ++k) out[k] = row[k] / row[Cols - 1];
    else
      for (int k = 0; k < Cols; ++k) out[k] = row[k];
  } else {
    project(row, dim, rational, out);
  }
}

/// Homogeneous derivatives `(order+1) by (dim+1)` → Cartesian derivatives by the quotient rule
/// (Piegl–Tiller A4.2).
inline Points rational_derivatives(const Points& H, int dim) {
  const Eigen::Index order = H.rows() - 1;
  Points C(H.rows(), dim);
  for (Eigen::Index k = 0; k <= order; ++k) {
    Point v = H.row(k).head(dim);
    double binom = 1;  // C(k, i)
    for (Eigen::Index i = 1; i <= k; ++i) {
      binom = binom * static_cast<double>(k - i + 1) / static_cast<double>(i);
      v -= binom * H(i, dim) * C.row(k - i);
    }
    C.row(k) = v / H(0, dim);
  }
  return C;
}

}  // namespace cifs::nurbs::detail
