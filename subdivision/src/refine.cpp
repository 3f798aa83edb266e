// SPDX-License-Identifier: MIT
#include "cifs/subdivision/refine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs::subdivision {
namespace {

using Index = Eigen::Index;

/// out[2i + e] = Σ_t w_t·P[i + offset_t] for the taps of parity e.
struct Taps {
  std::vector<Index> offset;
  std::vector<double> weight;
  Index low = 0, high = 0;  // smallest and largest offset
};

std::array<Taps, 2> taps(const Scheme& scheme) {
  const int N = mask_degree(scheme), h = closed_offset(scheme);
  std::array<Taps, 2> t;
  for (int e = 0; e < 2; ++e) {
    for (int k = 0; k <= N; ++k) {
      if ((k - e - h) % 2 != 0 || scheme.weights[static_cast<std::size_t>(k)] == 0) continue;
      t[e].offset.push_back((e + h - k) / 2);
      t[e].weight.push_back(scheme.weights[static_cast<std::size_t>(k)]);
    }
    // Parities without taps cannot happen for a valid mask (each parity sums to 1).
    t[e].low = *std::min_element(t[e].offset.begin(), t[e].offset.end());
    t[e].high = *std::max_element(t[e].offset.begin(), t[e].offset.end());
  }
  return t;
}

/// Rows `begin … end−1` of the coarse index i, reading P (rows of `dim` doubles, indices
/// i + offset always in range) and writing out rows 2i, 2i + 1.
template <int D>
void kernel(const double* P, double* out, Index dim_runtime, Index begin, Index end,
            const std::array<Taps, 2>& t) noexcept {
  const Index dim = D > 0 ? D : dim_runtime;
  for (int e = 0; e < 2; ++e) {
    const Index count = static_cast<Index>(t[e].offset.size());
    const Index* offset = t[e].offset.data();
    const double* weight = t[e].weight.data();
    for (Index i = begin; i < end; ++i) {
      double* o = out + (2 * i + e) * dim;
      if constexpr (D > 0) {
        double acc[D] = {};
        for (Index k = 0; k < count; ++k) {
          const double* p = P + (i + offset[k]) * D;
          for (int c = 0; c < D; ++c) acc[c] += weight[k] * p[c];
        }
        for (int c = 0; c < D; ++c) o[c] = acc[c];
      } else {
        for (Index c = 0; c < dim; ++c) o[c] = 0;
        for (Index k = 0; k < count; ++k) {
          const double* p = P + (i + offset[k]) * dim;
          for (Index c = 0; c < dim; ++c) o[c] += weight[k] * p[c];
        }
      }
    }
  }
}

/// Dense form of the taps over their common span: out[2i + e] = Σ_{k < T} w_e[k]·P[i + low + k]
/// with T compile-time (zero weights pad the shorter parity), so that each input row is loaded once
/// for both new points, the loops unroll and the D coordinates vectorise (the benchmark's hot path).
template <int D, int T>
void fixed_kernel(const double* P, double* out, Index begin, Index end, Index low, const double* w0_in,
                  const double* w1_in) noexcept {
  double w0[T], w1[T];
  for (int k = 0; k < T; ++k) w0[k] = w0_in[k], w1[k] = w1_in[k];
  for (Index i = begin; i < end; ++i) {
    const double* p = P + (i + low) * D;
    double a[D] = {}, b[D] = {};
#pragma GCC unroll 16
    for (int k = 0; k < T; ++k) {
#pragma GCC unroll 4
      for (int c = 0; c < D; ++c) {
        a[c] += w0[k] * p[k * D + c];
        b[c] += w1[k] * p[k * D + c];
      }
    }
    double* o = out + 2 * i * D;
    for (int c = 0; c < D; ++c) o[c] = a[c];
    for (int c = 0; c < D; ++c) o[D + c] = b[c];
  }
}

/// Per-parity form: out[2i + e] = Σ_{k < T_e} w_e[k]·P[i + low_e + k] (faster than the common span
/// when the parities' spans are short or differ, as for interpolating schemes).
template <int D, int T0, int T1>
void parity_kernel(const double* P, double* out, Index begin, Index end, Index low0, Index low1,
                   const double* w0_in, const double* w1_in) noexcept {
  double w0[T0], w1[T1];
  for (int k = 0; k < T0; ++k) w0[k] = w0_in[k];
  for (int k = 0; k < T1; ++k) w1[k] = w1_in[k];
  for (Index i = begin; i < end; ++i) {
    const double* p0 = P + (i + low0) * D;
    const double* p1 = P + (i + low1) * D;
    double a[D] = {}, b[D] = {};
#pragma GCC unroll 8
    for (int k = 0; k < T0; ++k)
#pragma GCC unroll 4
      for (int c = 0; c < D; ++c) a[c] += w0[k] * p0[k * D + c];
#pragma GCC unroll 8
    for (int k = 0; k < T1; ++k)
#pragma GCC unroll 4
      for (int c = 0; c < D; ++c) b[c] += w1[k] * p1[k * D + c];
    double* o = out + 2 * i * D;
    for (int c = 0; c < D; ++c) o[c] = a[c];
    for (int c = 0; c < D; ++c) o[D + c] = b[c];
  }
}

constexpr int kMaxParitySpan = 6;

template <int D, int T0, int T1 = 1>
bool dispatch_parity_second(Index span1, const double* P, double* out, Index begin, Index end, Index low0,
                            Index low1, const double* w0, const double* w1) noexcept {
  if (span1 == T1) return parity_kernel<D, T0, T1>(P, out, begin, end, low0, low1, w0, w1), true;
  if constexpr (T1 < kMaxParitySpan)
    return dispatch_parity_second<D, T0, T1 + 1>(span1, P, out, begin, end, low0, low1, w0, w1);
  return false;
}

template <int D, int T0 = 1>
bool dispatch_parity(Index span0, Index span1, const double* P, double* out, Index begin, Index end,
                     Index low0, Index low1, const double* w0, const double* w1) noexcept {
  if (span0 == T0) return dispatch_parity_second<D, T0>(span1, P, out, begin, end, low0, low1, w0, w1);
  if constexpr (T0 < kMaxParitySpan)
    return dispatch_parity<D, T0 + 1>(span0, span1, P, out, begin, end, low0, low1, w0, w1);
  return false;
}

constexpr int kMaxFixedSpan = 12;

template <int D, int T = 1>
bool dispatch_span(Index span, const double* P, double* out, Index begin, Index end, Index low,
                   const double* w0, const double* w1) noexcept {
  if (span == T) return fixed_kernel<D, T>(P, out, begin, end, low, w0, w1), true;
  if constexpr (T < kMaxFixedSpan) return dispatch_span<D, T + 1>(span, P, out, begin, end, low, w0, w1);
  return false;
}

bool run_fixed(const double* P, double* out, Index dim, Index begin, Index end,
               const std::array<Taps, 2>& t) noexcept {
  const Index low = std::min(t[0].low, t[1].low), span = std::max(t[0].high, t[1].high) - low + 1;
  if (dim != 2 && dim != 3) return false;
  const Index span0 = t[0].high - t[0].low + 1, span1 = t[1].high - t[1].low + 1;
  // Measured (bench_schemes): the per-parity form wins for short spans and for interpolating
  // schemes (one tap on one parity), the common span for long ones.
  const bool parity = std::max(span0, span1) <= 4 || std::abs(span0 - span1) >= 2;
  if (parity && span0 <= kMaxParitySpan && span1 <= kMaxParitySpan) {
    double w[2][kMaxParitySpan] = {};
    for (int e = 0; e < 2; ++e)
      for (std::size_t k = 0; k < t[e].offset.size(); ++k) w[e][t[e].offset[k] - t[e].low] = t[e].weight[k];
    if (dim == 2) return dispatch_parity<2>(span0, span1, P, out, begin, end, t[0].low, t[1].low, w[0], w[1]);
    return dispatch_parity<3>(span0, span1, P, out, begin, end, t[0].low, t[1].low, w[0], w[1]);
  }
  if (span > kMaxFixedSpan) return false;
  double w[2][kMaxFixedSpan] = {};
  for (int e = 0; e < 2; ++e)
    for (std::size_t k = 0; k < t[e].offset.size(); ++k) w[e][t[e].offset[k] - low] = t[e].weight[k];
  if (dim == 2) return dispatch_span<2>(span, P, out, begin, end, low, w[0], w[1]);
  return dispatch_span<3>(span, P, out, begin, end, low, w[0], w[1]);
}

void run_kernel(const double* P, double* out, Index dim, Index begin, Index end,
                const std::array<Taps, 2>& t) noexcept {
  if (begin >= end) return;
  if (run_fixed(P, out, dim, begin, end, t)) return;
  switch (dim) {
    case 1:
      return kernel<1>(P, out, dim, begin, end, t);
    case 2:
      return kernel<2>(P, out, dim, begin, end, t);
    case 3:
      return kernel<3>(P, out, dim, begin, end, t);
    case 4:
      return kernel<4>(P, out, dim, begin, end, t);
    default:
      return kernel<0>(P, out, dim, begin, end, t);
  }
}

void check_size(Index rows, const RefineOptions& options) {
  if (rows < 0 || static_cast<std::size_t>(rows) > options.max_points)
    throw InvalidInput("the refined polygon would have " + std::to_string(rows) +
                       " points, beyond the limit of " + std::to_string(options.max_points) +
                       "; refine fewer steps");
}

/// Point-reflection extension of an open polygon (n ≥ 2) at any index j.
Point extended(const Points& P, Index j) {
  const Index L = P.rows() - 1, period = 2 * L;
  Index q = j / period, r = j % period;
  if (r < 0) r += period, --q;
  const Point base = r <= L ? Point(P.row(r)) : Point(2 * P.row(L) - P.row(period - r));
  return base + static_cast<double>(2 * q) * (P.row(L) - P.row(0));
}

Points refine_open(const Scheme& scheme, const Points& P, const RefineOptions& options) {
  const Index n = P.rows(), dim = P.cols();
  if (n < 2)
    throw InvalidInput("an open polygon needs at least 2 points to refine, got " + std::to_string(n));
  const bool symmetric = is_symmetric(scheme);
  Ends ends = options.ends;
  if (ends == Ends::automatic) ends = symmetric ? Ends::reflect : Ends::keep;
  if (ends == Ends::reflect && !symmetric)
    throw InvalidInput("the reflect end rule needs a symmetric mask (" + scheme.name +
                       " is not); use the keep rule");
  const auto t = taps(scheme);
  const Index low = std::min(t[0].low, t[1].low), high = std::max(t[0].high, t[1].high);
  if (ends == Ends::reflect) {
    const bool primal = mask_degree(scheme) % 2 == 0;
    const Index inner = primal ? 2 * n - 1 : 2 * n - 2;  // new points m = 0 … inner − 1
    const Index rows = primal ? inner : inner + 2;
    check_size(rows, options);
    // ext row r holds the extended point of index r − pad.
    const Index pad = std::max<Index>({-low, high, 0}) + 1;
    Points ext(n + 2 * pad, dim);
    for (Index r = 0; r < ext.rows(); ++r)
      ext.row(r) = (r >= pad && r < pad + n) ? Point(P.row(r - pad)) : extended(P, r - pad);
    Points fine(2 * (n + 2 * pad), dim);
    // Coarse i = 0 … n − 1 (in ext coordinates i + pad) covers m = 0 … 2n − 1.
    run_kernel(ext.data(), fine.data(), dim, pad, pad + n, t);
    Points out(rows, dim);
    const Index first = primal ? 0 : 1;
    out.middleRows(first, inner) = fine.middleRows(2 * pad, inner);
    out.row(0) = P.row(0);
    out.row(rows - 1) = P.row(n - 1);
    return out;
  }
  // keep: new points whose stencil lies in the polygon, plus the end points.
  std::vector<Index> kept;
  for (Index m = 2 * (0 - high) - 2; m <= 2 * (n - low) + 2; ++m) {
    const Index e = ((m % 2) + 2) % 2, i = (m - e) / 2;
    if (i + t[e].low >= 0 && i + t[e].high <= n - 1) kept.push_back(m);
  }
  check_size(static_cast<Index>(kept.size()) + 2, options);
  Points inner(static_cast<Index>(kept.size()), dim);
  for (std::size_t r = 0; r < kept.size(); ++r) {
    const Index m = kept[r], e = ((m % 2) + 2) % 2, i = (m - e) / 2;
    Point acc = Point::Zero(dim);
    for (std::size_t k = 0; k < t[e].offset.size(); ++k) acc += t[e].weight[k] * P.row(i + t[e].offset[k]);
    inner.row(static_cast<Index>(r)) = acc;
  }
  const bool starts = inner.rows() > 0 && inner.row(0) == P.row(0);
  const bool ends_at = inner.rows() > 0 && inner.row(inner.rows() - 1) == P.row(n - 1);
  Points out(inner.rows() + (starts ? 0 : 1) + (ends_at ? 0 : 1), dim);
  Index r = 0;
  if (!starts) out.row(r++) = P.row(0);
  out.middleRows(r, inner.rows()) = inner;
  r += inner.rows();
  if (!ends_at) out.row(r) = P.row(n - 1);
  return out;
}

}  // namespace

bool is_symmetric(const Scheme& scheme) {
  const std::size_t n = scheme.mask.size();
  for (std::size_t k = 0; k < n; ++k)
    if (scheme.mask[k] != scheme.mask[n - 1 - k]) return false;
  return true;
}

void refine_closed(const Scheme& scheme, const Points& P, Points& out) {
  const Index n = P.rows(), dim = P.cols();
  if (out.rows() != 2 * n || out.cols() != dim) out.resize(2 * n, dim);
  if (n == 0) return;
  const auto t = taps(scheme);
  const Index low = std::min(t[0].low, t[1].low), high = std::max(t[0].high, t[1].high);
  // Interior: every i + offset in [0, n).
  const Index begin = std::min(n, std::max<Index>(0, -low)),
              end = std::max(begin, n - std::max<Index>(0, high));
  run_kernel(P.data(), out.data(), dim, begin, end, t);
  // Borders: wrap indices mod n.
  for (Index i = 0; i < n; ++i) {
    if (i == begin) i = end;
    if (i >= n) break;
    for (int e = 0; e < 2; ++e) {
      auto row = out.row(2 * i + e);
      row.setZero();
      for (std::size_t k = 0; k < t[e].offset.size(); ++k) {
        const Index j = ((i + t[e].offset[k]) % n + n) % n;
        row += t[e].weight[k] * P.row(j);
      }
    }
  }
}

Points refine(const Scheme& scheme, const Points& P, bool closed, const RefineOptions& options) {
  if (P.rows() == 0) throw InvalidInput("the polygon has no point to refine");
  if (!P.allFinite()) throw InvalidInput("the polygon has a coordinate that is not finite");
  // Coordinates near the largest doubles: the sums of a rule overflow before its negative weights
  // bring them back (9/16·(b + c) of 1.7e308). The rules are affine, so the polygon is refined scaled
  // by a power of 2 (exact) and scaled back; below 2^1000 nothing changes, bit for bit.
  const double top = P.size() == 0 ? 0.0 : P.cwiseAbs().maxCoeff();  // (0 columns: no coordinate)
  int exponent = 0;
  if (top > 0x1p1000) std::frexp(top, &exponent);
  const Points scaled = exponent != 0
                            ? Points(P.unaryExpr([exponent](double x) { return std::ldexp(x, -exponent); }))
                            : Points();
  const Points& input = exponent != 0 ? scaled : P;
  Points out;
  if (closed) {
    check_size(2 * P.rows(), options);
    refine_closed(scheme, input, out);
  } else {
    out = refine_open(scheme, input, options);
  }
  // ldexp per coordinate: 2^1024 itself is beyond a double.
  if (exponent != 0) out = out.unaryExpr([exponent](double x) { return std::ldexp(x, exponent); });
  // A result beyond the largest double is refused here, naming the cause, instead of printed as inf
  // or refused at the next step as "not finite".
  if (!out.allFinite())
    throw InvalidInput("refining the polygon overflows a double: its coordinates (up to " +
                       number_text(top, 6) + ") combined by the mask pass 1.8e308; scale the polygon down");
  return out;
}

Points refine(const Scheme& scheme, const Points& P, bool closed, int steps, const RefineOptions& options) {
  if (steps < 0)
    throw InvalidInput("the number of refinement steps " + std::to_string(steps) + " is negative");
  if (P.rows() == 0) throw InvalidInput("the polygon has no point to refine");
  // Size check before any work: each step at most doubles the count (plus 2 for open ends).
  long double rows = static_cast<long double>(P.rows());
  for (int s = 0; s < steps; ++s) {
    rows = 2 * rows + 2;
    if (rows > static_cast<long double>(options.max_points))
      throw InvalidInput(std::to_string(steps) + " refinement steps of " + std::to_string(P.rows()) +
                         " points exceed the limit of " + std::to_string(options.max_points) +
                         " points; refine fewer steps");
  }
  Points current = P;
  for (int s = 0; s < steps; ++s) current = refine(scheme, current, closed, options);
  return current;
}

}  // namespace cifs::subdivision
