// SPDX-License-Identifier: MIT
#include "cifs/nurbs/curve.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "cifs/cpu.hpp"
#include "cifs/errors.hpp"
#include "detail.hpp"

namespace cifs::nurbs {

Curve make_curve(int degree, Knots knots, const Points& points, const Eigen::VectorXd& weights) {
  Curve c{degree, std::move(knots), detail::homogeneous(points, weights, "points"), weights.size() > 0,
          false};
  validate(c);
  return c;
}

Curve uniform_bspline(const Points& polygon, int degree, bool closed) {
  validate_degree(degree);
  const Eigen::Index n = polygon.rows();
  Knots knots;
  if (closed) {
    for (Eigen::Index i = 0; i <= n; ++i) knots.push_back(static_cast<double>(i));
    return make_closed_curve(degree, std::move(knots), polygon);
  }
  if (n < degree + 1)
    detail::fail("points: a clamped curve of degree ", degree, " needs at least ", degree + 1,
                 " control points, got ", n);
  const Eigen::Index spans = n - degree;
  knots.assign(static_cast<std::size_t>(degree), 0.0);
  for (Eigen::Index i = 0; i <= spans; ++i) knots.push_back(static_cast<double>(i));
  knots.insert(knots.end(), static_cast<std::size_t>(degree), static_cast<double>(spans));
  return make_curve(degree, std::move(knots), polygon);
}

Curve make_closed_curve(int degree, Knots breakpoints, const Points& points, const Eigen::VectorXd& weights) {
  validate_degree(degree);
  const Eigen::Index m = points.rows();
  if (m < 2) detail::fail("points: a closed curve needs at least 2 control points, got ", m);
  if (static_cast<Eigen::Index>(breakpoints.size()) != m + 1)
    detail::fail("knots: a closed curve of ", m, " control points takes ", m + 1,
                 " breakpoints (one period), got ", breakpoints.size());
  for (std::size_t i = 0; i < breakpoints.size(); ++i) {
    if (!std::isfinite(breakpoints[i])) detail::fail("knots[", i, "]: knot is not finite");
    if (i > 0 && breakpoints[i] < breakpoints[i - 1])
      detail::fail("knots[", i, "]: ", breakpoints[i], " is less than the previous knot ",
                   breakpoints[i - 1]);
  }
  if (!(breakpoints.back() > breakpoints.front()))
    detail::fail("knots: the period [", breakpoints.front(), ", ", breakpoints.back(), "] is empty");
  // The periodic knot vector reaches up to one period past each end; its differences must be finite.
  const double period = breakpoints.back() - breakpoints.front();
  if (!std::isfinite(3 * period) || !std::isfinite(breakpoints.front() - period) ||
      !std::isfinite(breakpoints.back() + period))
    detail::fail("knots: the period [", breakpoints.front(), ", ", breakpoints.back(),
                 "] extended by one period on each side is wider than a double holds");
  // Multiplicities on the breakpoints as given, so that messages name the caller's index (the
  // periodic knot vector is longer); the seam counts the copies of b_0 and of b_m inside the period.
  const auto last = static_cast<std::size_t>(m);
  std::size_t lead = 1, trail = 0;
  while (breakpoints[lead] == breakpoints[0]) ++lead;
  while (breakpoints[last - 1 - trail] == breakpoints[last]) ++trail;
  if (static_cast<int>(lead + trail) > degree + 1)
    detail::fail("knots[", last, "]: the seam knot ", breakpoints[0], " (= ", breakpoints[last],
                 ") has multiplicity ", lead + trail, " > degree + 1 = ", degree + 1);
  for (std::size_t i = 1, run = 1; i < last; ++i) {
    run = breakpoints[i] == breakpoints[i - 1] ? run + 1 : 1;
    if (static_cast<int>(run) > degree + 1)
      detail::fail("knots[", i, "]: knot ", breakpoints[i], " has multiplicity ", run,
                   " > degree + 1 = ", degree + 1);
  }
  const Points H = detail::homogeneous(points, weights, "points");
  Points expanded(m + degree, H.cols());
  for (Eigen::Index i = 0; i < expanded.rows(); ++i) expanded.row(i) = H.row(i % m);
  Curve c{degree, periodic_knots(breakpoints, degree), std::move(expanded), weights.size() > 0, true};
  validate(c);
  return c;
}

void validate(const Curve& c) {
  validate_knots(c.knots, c.degree, c.P.rows());
  if (c.P.cols() < (c.rational ? 2 : 1)) detail::fail("points: control points have no coordinates");
  for (Eigen::Index i = 0; i < c.P.rows(); ++i) {
    const double w = c.rational ? c.P(i, c.P.cols() - 1) : 1.0;
    if (!(w > 0) || !std::isfinite(w))
      detail::fail("weights[", i, "]: weight ", w, " is not a positive finite number");
    for (Eigen::Index j = 0; j < c.P.cols(); ++j)
      if (!std::isfinite(c.P(i, j)))
        detail::fail("points[", i, "][", j, "]: ",
                     c.rational && j + 1 < c.P.cols()
                         ? "the coordinate times its weight (w·x) is not finite; "
                           "lower the weights (a common factor leaves the curve)"
                         : "coordinate is not finite");
  }
  if (c.closed) {
    const Eigen::Index m = c.P.rows() - c.degree;
    for (Eigen::Index i = 0; i < c.degree; ++i)
      if (c.P.row(m + i) != c.P.row(i % m))
        detail::fail("points[", m + i, "]: a closed curve must repeat its first ", c.degree, " points");
  }
}

Eigen::Index distinct_count(const Curve& c) noexcept {
  return c.closed ? c.P.rows() - c.degree : c.P.rows();
}

Knots defining_knots(const Curve& c) {
  if (!c.closed) return c.knots;
  const auto first = c.knots.begin() + c.degree;
  return Knots(first, first + distinct_count(c) + 1);
}

Points cartesian_points(const Curve& c) {
  const Eigen::Index n = distinct_count(c);
  const int dim = dimension(c);
  if (!c.rational) return c.P.topRows(n);
  Points out(n, dim);
  for (Eigen::Index i = 0; i < n; ++i) out.row(i) = c.P.row(i).head(dim) / c.P(i, dim);
  return out;
}

Eigen::VectorXd weights(const Curve& c) {
  const Eigen::Index n = distinct_count(c);
  if (!c.rational) return Eigen::VectorXd::Ones(n);
  return c.P.col(c.P.cols() - 1).head(n);
}

int segment_count(const Curve& c) noexcept {
  const Eigen::Index n = c.P.rows();
  int count = 0;
  for (Eigen::Index k = c.degree; k < n; ++k)
    count += c.knots[static_cast<std::size_t>(k)] < c.knots[static_cast<std::size_t>(k + 1)];
  return count;
}

double domain_parameter(const Curve& c, double u) {
  const Domain dom = domain(c);
  if (!std::isfinite(u)) detail::fail("the parameter is not a finite number");
  if (c.closed) {
    if (u >= dom.start && u <= dom.end) return u;
    const double period = dom.end - dom.start;
    const double wrapped = dom.start + (u - dom.start) - std::floor((u - dom.start) / period) * period;
    return std::min(std::max(wrapped, dom.start), dom.end);
  }
  if (u < dom.start || u > dom.end)
    detail::fail("parameter ", u, " is outside the domain [", dom.start, ", ", dom.end, "]");
  return u;
}

Point to_cartesian(const Curve& c, const Point& row) {
  if (!c.rational) return row;
  const int dim = dimension(c);
  return row.head(dim) / row(dim);
}

namespace {

/// The parameter in the domain: u itself when it lies there (no call), else domain_parameter.
double in_domain(const Curve& c, double u) {
  const Domain dom = domain(c);
  return u >= dom.start && u <= dom.end ? u : domain_parameter(c, u);
}

/// De Boor's triangle on the d + 1 points of u's span, projected into out (dim values). The working
/// points live on the stack for a fixed column count, in `scratch` ((d + 1)·cols values) otherwise.
template <int Cols>
void de_boor(const Curve& c, double u, double* out, double* scratch) noexcept {
  const int p = c.degree;
  const Eigen::Index cols = Cols > 0 ? Cols : c.P.cols();
  const int span = detail::find_span(c.knots.data(), p, static_cast<int>(c.P.rows()), u);
  double local[2 * kMaxDegree];
  const detail::SpanKnots knots = detail::span_knots(c, span, local);
  const double* t = knots.t.data();
  u -= knots.origin;
  double fixed[Cols > 0 ? (kMaxDegree + 1) * Cols : 1];
  double* d = Cols > 0 ? fixed : scratch;
  std::copy_n(c.P.data() + (span - p) * cols, (p + 1) * cols, d);
  for (int r = 1; r <= p; ++r)
    for (int j = p; j >= r; --j) {
      const int i = j + knots.span - p;
      // Both weights from their own differences: 1 − alpha would cancel next to a knot.
      const double hi = t[i + p + 1 - r], den = hi - t[i];
      const double left = (hi - u) / den, right = (u - t[i]) / den;
      double* dj = d + j * cols;
      for (Eigen::Index k = 0; k < cols; ++k) dj[k] = left * dj[k - cols] + right * dj[k];
    }
  detail::project<Cols>(d + p * cols, dimension(c), c.rational, out);
}

/// Everything a point needs from its span, one block a span, for unordered parameters (whose span
/// changes at almost every point, so that a span change is a pointer). The block of span s, `stride`
/// doubles: the 2p knots t_{s−p+1 … s+p} of span_knots (relative to origin[s] around a closed curve's
/// seam), the p(p + 1)/2 reciprocals of blossom_reciprocals, the p + 1 stored rows P_{s−p … s}, then
/// zeros up to a multiple of 4 (the AVX lanes load groups of four). A span with a subnormal knot
/// interval has infinite reciprocals and is marked.
struct SpanBlocks {
  detail::SpanTable table;
  std::size_t stride;
  std::vector<double> data;
  std::vector<double> origin;
  std::vector<char> finite;
  const double* block(int span) const noexcept {
    return data.data() + static_cast<std::size_t>(span) * stride;
  }
};

std::size_t span_block_stride(int p, Eigen::Index cols) noexcept {
  const auto size = static_cast<std::size_t>(2 * p + p * (p + 1) / 2 + (p + 1) * cols);
  return (size + 3) / 4 * 4;
}

SpanBlocks span_blocks(const Curve& c) {
  const int p = c.degree;
  const int n = static_cast<int>(c.P.rows());
  const Eigen::Index cols = c.P.cols();
  const std::size_t stride = span_block_stride(p, cols);
  const auto count = static_cast<std::size_t>(n);
  SpanBlocks b{detail::SpanTable(c.knots.data(), p, n), stride, std::vector<double>(count * stride),
               std::vector<double>(count), std::vector<char>(count, 0)};
  double local[2 * kMaxDegree];
  for (int span = p; span < n; ++span) {
    const auto s = static_cast<std::size_t>(span);
    double* knots = b.data.data() + s * stride;
    double* inv = knots + std::ptrdiff_t{2} * p;
    const detail::SpanKnots k = detail::span_knots(c, span, local);
    std::copy_n(k.t.data() + k.span - p + 1, 2 * p, knots);
    detail::blossom_reciprocals(knots, p, p - 1, inv);
    const int reciprocals = p * (p + 1) / 2;
    b.finite[s] =
        static_cast<char>(std::all_of(inv, inv + reciprocals, [](double x) { return std::isfinite(x); }));
    std::copy_n(c.P.data() + (span - p) * cols, (p + 1) * cols, inv + reciprocals);
    b.origin[s] = k.origin;
  }
  return b;
}

#if defined(CIFS_X86_AVX)
/// Four rows of D coordinates, coordinate k of row l in lane l of a[k], to D·4 consecutive doubles:
/// the transposition in registers.
template <int D>
__attribute__((target("avx"), always_inline)) inline void store_rows(const __m256d* a, double* out) noexcept {
  if constexpr (D == 1) {
    _mm256_storeu_pd(out, a[0]);
  } else if constexpr (D == 2) {
    const __m256d lo = _mm256_unpacklo_pd(a[0], a[1]);  // x0 y0 x2 y2
    const __m256d hi = _mm256_unpackhi_pd(a[0], a[1]);  // x1 y1 x3 y3
    _mm256_storeu_pd(out, _mm256_permute2f128_pd(lo, hi, 0x20));
    _mm256_storeu_pd(out + 4, _mm256_permute2f128_pd(lo, hi, 0x31));
  } else if constexpr (D == 3) {
    const __m256d xy = _mm256_unpacklo_pd(a[0], a[1]);                // x0 y0 x2 y2
    const __m256d zx = _mm256_shuffle_pd(a[2], a[0], 0b1010);         // z0 x1 z2 x3
    const __m256d yz = _mm256_unpackhi_pd(a[1], a[2]);                // y1 z1 y3 z3
    _mm256_storeu_pd(out, _mm256_permute2f128_pd(xy, zx, 0x20));      // x0 y0 z0 x1
    _mm256_storeu_pd(out + 4, _mm256_blend_pd(yz, xy, 0b1100));       // y1 z1 x2 y2
    _mm256_storeu_pd(out + 8, _mm256_permute2f128_pd(zx, yz, 0x31));  // z2 x3 y3 z3
  } else {
    static_assert(D == 4);
    const __m256d lo01 = _mm256_unpacklo_pd(a[0], a[1]), hi01 = _mm256_unpackhi_pd(a[0], a[1]);
    const __m256d lo23 = _mm256_unpacklo_pd(a[2], a[3]), hi23 = _mm256_unpackhi_pd(a[2], a[3]);
    _mm256_storeu_pd(out, _mm256_permute2f128_pd(lo01, lo23, 0x20));
    _mm256_storeu_pd(out + 4, _mm256_permute2f128_pd(hi01, hi23, 0x20));
    _mm256_storeu_pd(out + 8, _mm256_permute2f128_pd(lo01, lo23, 0x31));
    _mm256_storeu_pd(out + 12, _mm256_permute2f128_pd(hi01, hi23, 0x31));
  }
}

/// The four stored rows in `acc` (coordinate k of lane l in lane l of acc[k]), projected as
/// detail::project does (the same divisions), to four consecutive rows of out.
template <int Cols>
__attribute__((target("avx"), always_inline)) inline void store_lanes(const __m256d* acc, bool rational,
                                                                      double* out) noexcept {
  if constexpr (Cols > 1) {
    if (rational) {
      __m256d cartesian[Cols - 1];
      for (int k = 0; k < Cols - 1; ++k) cartesian[k] = _mm256_div_pd(acc[k], acc[Cols - 1]);
      store_rows<Cols - 1>(cartesian, out);
      return;
    }
  }
  store_rows<Cols>(acc, out);
}

/// The basis functions and the sum of evaluate_rows for four points, a point an AVX lane (chosen at
/// run time; the build targets baseline x86-64). The scalar code's multiplies and adds in its order,
/// never fused: the same bits. `in` gives each value of the lanes' span blocks as a vector, value i
/// of lane l's block in lane l: in.knot(i) of its 2p knots, in.inv(i) of its reciprocals, in.row(i)
/// of its (p + 1)·Cols coordinates. `u` holds the parameters relative to the spans' origins; the
/// four projected rows land in out (store_lanes).
template <int Cols, int Degree, class Lanes>
__attribute__((target("avx"), always_inline)) inline void lane_rows(const Lanes& in, __m256d u, bool rational,
                                                                    double* out) noexcept {
  const int p = Degree;
  __m256d N[Degree + 1], left[Degree + 1], right[Degree + 1];
  N[0] = _mm256_set1_pd(1.0);
  for (int j = 1; j <= p; ++j) {
    left[j] = _mm256_sub_pd(u, in.knot(p - j));       // u − t_{span+1−j}
    right[j] = _mm256_sub_pd(in.knot(p - 1 + j), u);  // t_{span+j} − u
    const int level = j * (j - 1) / 2;
    __m256d saved = _mm256_setzero_pd();
    for (int r = 0; r < j; ++r) {
      const __m256d temp = _mm256_mul_pd(N[r], in.inv(level + r));
      N[r] = _mm256_add_pd(saved, _mm256_mul_pd(right[r + 1], temp));
      saved = _mm256_mul_pd(left[j - r], temp);
    }
    N[j] = saved;
  }
  __m256d acc[Cols];
  for (int k = 0; k < Cols; ++k) {
    acc[k] = _mm256_mul_pd(N[0], in.row(k));
    for (int r = 1; r <= p; ++r) acc[k] = _mm256_add_pd(acc[k], _mm256_mul_pd(N[r], in.row(r * Cols + k)));
  }
  store_lanes<Cols>(acc, rational, out);
}

/// Lanes that share one span (sorted input, mostly): its values broadcast where they are used.
struct SharedSpan {
  const double* knots;  // the 2p knots t_{span−p+1 … span+p}
  const double* inverse;
  const double* base;
  __attribute__((target("avx"), always_inline)) __m256d knot(int i) const noexcept {
    return _mm256_set1_pd(knots[i]);
  }
  __attribute__((target("avx"), always_inline)) __m256d inv(int i) const noexcept {
    return _mm256_set1_pd(inverse[i]);
  }
  __attribute__((target("avx"), always_inline)) __m256d row(int i) const noexcept {
    return _mm256_set1_pd(base[i]);
  }
};

/// Lanes with a span each (unordered input): their span blocks transposed, vector i = value i of
/// every block.
struct SpanPerLane {
  const __m256d* v;
  int reciprocals_at, rows_at;
  __attribute__((target("avx"), always_inline)) __m256d knot(int i) const noexcept { return v[i]; }
  __attribute__((target("avx"), always_inline)) __m256d inv(int i) const noexcept {
    return v[reciprocals_at + i];
  }
  __attribute__((target("avx"), always_inline)) __m256d row(int i) const noexcept { return v[rows_at + i]; }
};

/// Four points of one span. `t` and `span` as from span_knots, `x` the four parameters relative to
/// its origin.
template <int Cols, int Degree>
__attribute__((target("avx"))) void four_points(const double* t, int span, const double* inv, const double* x,
                                                const double* base, bool rational, double* out) noexcept {
  lane_rows<Cols, Degree>(SharedSpan{t + span - Degree + 1, inv, base}, _mm256_loadu_pd(x), rational, out);
}

/// evaluate_unordered's points from `i` on, four consecutive points a step, each lane with its own
/// span: the lanes' span blocks transposed four doubles at a time, so that vector v[j] holds value j of
/// every lane's block. Returns where it stopped: the end (fewer than four points left) or a group of
/// four with a span whose reciprocals are not finite (a subnormal knot interval), for the caller to
/// evaluate one at a time.
template <int Cols, int Degree>
__attribute__((target("avx"))) std::size_t four_spans(std::span<const double> us, const SpanBlocks& blocks,
                                                      bool rational, double* out, std::size_t i) noexcept {
  constexpr int kReciprocalsAt = 2 * Degree, kRowsAt = kReciprocalsAt + Degree * (Degree + 1) / 2;
  constexpr int kStride = (kRowsAt + (Degree + 1) * Cols + 3) / 4 * 4;  // span_block_stride
  const int dim = Cols - static_cast<int>(rational);
  for (; i + 4 <= us.size(); i += 4) {
    const double* block[4];
    double x[4];
    char finite = 1;
    for (std::size_t lane = 0; lane < 4; ++lane) {
      const auto s = static_cast<std::size_t>(blocks.table.find(us[i + lane]));
      block[lane] = blocks.block(static_cast<int>(s));
      x[lane] = us[i + lane] - blocks.origin[s];
      finite &= blocks.finite[s];
    }
    if (finite == 0) break;
    __m256d v[kStride];
    for (int g = 0; g < kStride; g += 4) {
      const __m256d r0 = _mm256_loadu_pd(block[0] + g), r1 = _mm256_loadu_pd(block[1] + g);
      const __m256d r2 = _mm256_loadu_pd(block[2] + g), r3 = _mm256_loadu_pd(block[3] + g);
      const __m256d lo01 = _mm256_unpacklo_pd(r0, r1), hi01 = _mm256_unpackhi_pd(r0, r1);
      const __m256d lo23 = _mm256_unpacklo_pd(r2, r3), hi23 = _mm256_unpackhi_pd(r2, r3);
      v[g] = _mm256_permute2f128_pd(lo01, lo23, 0x20);
      v[g + 1] = _mm256_permute2f128_pd(hi01, hi23, 0x20);
      v[g + 2] = _mm256_permute2f128_pd(lo01, lo23, 0x31);
      v[g + 3] = _mm256_permute2f128_pd(hi01, hi23, 0x31);
    }
    lane_rows<Cols, Degree>(SpanPerLane{v, kReciprocalsAt, kRowsAt}, _mm256_loadu_pd(x), rational,
                            out + i * static_cast<std::size_t>(dim));
  }
  return i;
}

#endif

/// Σ_r N[r] · base[r·cols + k] for the p + 1 rows at `base`, in r order, projected into `out`.
template <int Cols>
inline void sum_rows(const double* N, int p, const double* base, Eigen::Index cols, double* acc, int dim,
                     bool rational, double* out) noexcept {
  if constexpr (Cols > 0) cols = Cols;
  for (Eigen::Index k = 0; k < cols; ++k) acc[k] = N[0] * base[k];
  for (int r = 1; r <= p; ++r)
    for (Eigen::Index k = 0; k < cols; ++k) acc[k] += N[r] * base[r * cols + k];
  detail::project<Cols>(acc, dim, rational, out);
}

/// Σ N_j(u) P_{span−p+j} for every parameter (all in the domain), projected into out (dim per row).
/// Span search: the previous span as the hint (sorted input), else a bisection. The basis functions
/// take the span's reciprocals, computed when the span changes: every point of a span shares its
/// divisors.
template <int Cols, int Degree = 0>
void evaluate_rows(const Curve& c, std::span<const double> us, double* out, double* scratch) noexcept {
  const int p = Degree > 0 ? Degree : c.degree;  // a constant: the basis and sum loops unroll
  const int n = static_cast<int>(c.P.rows());
  const Eigen::Index cols = Cols > 0 ? Cols : c.P.cols();
  const int dim = dimension(c);
  const double* t = c.knots.data();
  const double* P = c.P.data();
  double fixed[Cols > 0 ? Cols : 1];
  double* acc = Cols > 0 ? fixed : scratch;
  double N[kMaxDegree + 1], local[2 * kMaxDegree], inv[detail::kReciprocals];
  int span = -1;
  detail::SpanKnots knots;
  bool finite = true;  // the span's reciprocals (none of its knot intervals subnormal)
#if defined(CIFS_X86_AVX)
  const bool fast = cpu_has_avx();
#endif
  for (std::size_t i = 0; i < us.size(); ++i, out += dim) {
    const double u = us[i];
    const int previous = span;
    span = detail::find_span(t, p, n, u, std::max(span, p));
    if (span != previous) {
      knots = detail::span_knots(c, span, local);
      detail::blossom_reciprocals(knots.t.data(), p, knots.span, inv);
      finite = std::all_of(inv, inv + p * (p + 1) / 2, [](double x) { return std::isfinite(x); });
    }
#if defined(CIFS_X86_AVX)
    // The next three points in this span too (sorted input, mostly): a point an AVX lane.
    if constexpr (Cols > 0 && Degree > 0) {
      const auto inside = [&](std::size_t k) { return us[k] >= t[span] && us[k] < t[span + 1]; };
      if (finite && fast && i + 4 <= us.size() && inside(i + 3) && inside(i + 1) && inside(i + 2)) {
        const double x[4] = {u - knots.origin, us[i + 1] - knots.origin, us[i + 2] - knots.origin,
                             us[i + 3] - knots.origin};
        four_points<Cols, Degree>(knots.t.data(), knots.span, inv, x, P + (span - p) * cols, c.rational, out);
        i += 3;
        out += std::ptrdiff_t{3} * dim;  // the loop's increment passes the fourth
        continue;
      }
    }
#endif
    if (finite)
      detail::basis(knots.t.data(), p, knots.span, inv, u - knots.origin, N);
    else
      detail::basis(knots.t.data(), p, knots.span, u - knots.origin, N);
    sum_rows<Cols>(N, p, P + (span - p) * cols, cols, acc, dim, c.rational, out);
  }
}

/// evaluate_rows for unordered parameters, from the span blocks: the bucket table finds each span, and
/// a span change is a pointer. With AVX, four consecutive points a step, a point a lane, each lane with
/// its own span; the same bits as one point at a time.
template <int Cols, int Degree = 0>
void evaluate_unordered(const Curve& c, std::span<const double> us, const SpanBlocks& blocks, double* out,
                        double* scratch) noexcept {
  const int p = Degree > 0 ? Degree : c.degree;
  const Eigen::Index cols = Cols > 0 ? Cols : c.P.cols();
  const auto dim = static_cast<std::size_t>(dimension(c));
  const int rows_at = 2 * p + p * (p + 1) / 2;  // in a block: 2p knots, the reciprocals, the rows
  double fixed[Cols > 0 ? Cols : 1];
  double* acc = Cols > 0 ? fixed : scratch;
  const auto one = [&](std::size_t i) {
    double N[kMaxDegree + 1];
    const int span = blocks.table.find(us[i]);
    const auto s = static_cast<std::size_t>(span);
    const double* block = blocks.block(span);
    const double x = us[i] - blocks.origin[s];
    if (blocks.finite[s] != 0)
      detail::basis(block, p, p - 1, block + std::ptrdiff_t{2} * p, x, N);
    else
      detail::basis(block, p, p - 1, x, N);
    sum_rows<Cols>(N, p, block + rows_at, cols, acc, static_cast<int>(dim), c.rational, out + i * dim);
  };
  std::size_t i = 0;
#if defined(CIFS_X86_AVX)
  if constexpr (Cols > 0 && Degree > 0) {
    while (cpu_has_avx() && i + 4 <= us.size()) {
      i = four_spans<Cols, Degree>(us, blocks, c.rational, out, i);
      for (const std::size_t end = std::min(i + 4, us.size()); i < end; ++i) one(i);  // a subnormal interval
    }
  }
#endif
  for (; i < us.size(); ++i) one(i);
}

}  // namespace

Point evaluate(const Curve& c, double u) {
  u = in_domain(c, u);
  Point out(dimension(c));
  detail::with_cols(c.P.cols(), [&](auto cols) {
    std::vector<double> scratch = detail::scratch<cols>(c.P.cols(), c.degree + 1);
    de_boor<cols>(c, u, out.data(), scratch.data());
  });
  return out;
}

Point evaluate_basis(const Curve& c, double u) {
  u = in_domain(c, u);
  Point out(dimension(c));
  detail::with_cols(c.P.cols(), [&](auto cols) {  // the batch kernel on one point
    std::vector<double> scratch = detail::scratch<cols>(c.P.cols());
    evaluate_rows<cols>(c, std::span<const double>(&u, 1), out.data(), scratch.data());
  });
  return out;
}

Points evaluate(const Curve& c, std::span<const double> us) {
  const detail::Scan scan = detail::scan(us, domain(c));
  if (!scan.inside) {
    // Closed curves wrap the parameters into the period; open curves throw for the first one outside.
    std::vector<double> wrapped(us.size());
    for (std::size_t k = 0; k < us.size(); ++k) wrapped[k] = domain_parameter(c, us[k]);
    return evaluate(c, wrapped);
  }
  Points out(static_cast<Eigen::Index>(us.size()), dimension(c));
  // Unordered input: the span blocks and their bucket table once the parameters outnumber the knots
  // (they cost O(#knots) to build) and the blocks take no more memory than the output.
  // (Grouping the parameters by span first, for the AVX lanes, was tried: the scattered writes back
  // cost twice what the lanes save, 43.8 against 20.8 ns a point. Lanes with a span each (four_spans)
  // took their place.)
  std::optional<SpanBlocks> blocks;
  const std::size_t block_doubles =
      span_block_stride(c.degree, c.P.cols()) * static_cast<std::size_t>(c.P.rows());
  if (!scan.sorted && us.size() >= 8 * c.knots.size() &&
      block_doubles <= us.size() * static_cast<std::size_t>(dimension(c)))
    blocks = span_blocks(c);
  detail::with_cols(c.P.cols(), [&](auto cols) {
    std::vector<double> scratch = detail::scratch<cols>(c.P.cols());
    switch (c.degree) {  // the common degrees with their loops unrolled
      case 2:
        if (blocks) return evaluate_unordered<cols, 2>(c, us, *blocks, out.data(), scratch.data());
        return evaluate_rows<cols, 2>(c, us, out.data(), scratch.data());
      case 3:
        if (blocks) return evaluate_unordered<cols, 3>(c, us, *blocks, out.data(), scratch.data());
        return evaluate_rows<cols, 3>(c, us, out.data(), scratch.data());
      default:
        if (blocks) return evaluate_unordered<cols>(c, us, *blocks, out.data(), scratch.data());
        return evaluate_rows<cols>(c, us, out.data(), scratch.data());
    }
  });
  return out;
}

std::vector<double> uniform_parameters(Domain dom, int count) {
  return uniform_parameters(dom, count, 0, std::max(count, 0));
}

std::vector<double> uniform_parameters(Domain dom, int count, int first, int n) {
  std::vector<double> us(static_cast<std::size_t>(std::max(n, 0)));
  for (int k = 0; k < n; ++k) {
    const int i = first + k;
    us[static_cast<std::size_t>(k)] = count == 1       ? dom.start
                                      : i == count - 1 ? dom.end
                                                       : dom.start + (dom.end - dom.start) * i / (count - 1);
  }
  return us;
}

Points derivatives(const Curve& c, double u, int order) {
  detail::check_derivative_order(order);
  u = domain_parameter(c, u);
  const int p = c.degree;
  const int span = find_span(c.knots, p, u);
  double local[2 * kMaxDegree];
  const detail::SpanKnots knots = detail::span_knots(c, span, local);
  const Eigen::MatrixXd ders = basis_derivatives(knots.t, p, knots.span, u - knots.origin, order);
  Points H = ders * c.P.middleRows(span - p, p + 1);  // homogeneous derivatives
  if (!c.rational) return H;
  return detail::rational_derivatives(H, dimension(c));
}

Point blossom(const Curve& c, std::span<const double> args, int span) {
  const int p = c.degree;
  if (static_cast<int>(args.size()) != p)
    detail::fail("the blossom of a degree-", p, " curve takes ", p, " arguments, ", args.size(), " given");
  for (std::size_t i = 0; i < args.size(); ++i)
    if (!std::isfinite(args[i])) detail::fail("blossom argument ", i, " is not a finite number");
  if (span < p || span >= c.P.rows() ||
      !(c.knots[static_cast<std::size_t>(span)] < c.knots[static_cast<std::size_t>(span) + 1]))
    detail::fail("the blossom's span ", span, " is not a non-empty span of the domain");
  return detail::blossom_row(c, args, span);
}

Point blossom(const Curve& c, std::span<const double> args) {
  const int p = c.degree;
  if (static_cast<int>(args.size()) != p)
    detail::fail("the blossom of a degree-", p, " curve takes ", p, " arguments, ", args.size(), " given");
  double mean = 0;
  for (double a : args) mean += a / p;
  if (!std::isfinite(mean)) detail::fail("the blossom's arguments are not all finite numbers");
  std::vector<double> shifted(args.begin(), args.end());
  if (c.closed) {
    // The mean as an offset from the first argument: equal arguments give it exactly, so that
    // blossom(b_0, …, b_0) is not wrapped to the period's end by a rounding of Σ a / p.
    double offset = 0;
    for (double a : args) offset += (a - args[0]) / p;
    if (std::isfinite(args[0] + offset)) mean = args[0] + offset;
    const double shift = domain_parameter(c, mean) - mean;  // a whole number of periods
    for (double& a : shifted) a += shift;
    mean += shift;
  }
  const Domain dom = domain(c);
  const int span = find_span(c.knots, p, std::min(std::max(mean, dom.start), dom.end));
  return detail::blossom_row(c, shifted, span);
}

}  // namespace cifs::nurbs
