// SPDX-License-Identifier: MIT
// cifs — PROTOTYPE KERNELS, NOT LIBRARY CODE.
//
// Faster versions of five nurbs/ routines, written inside the benchmark only to measure what the
// changes proposed in docs/performance.md would gain. The library is unchanged. Every prototype
// handles the common case (open curves — clamped ones for refinement — and surfaces, 3 or 4 stored
// coordinates, parameters in the domain) and hands anything else to the library routine, so errors,
// closed and unclamped curves behave exactly as in the library. Except Boehm refinement, each keeps
// the library's arithmetic in the library's order: the results are the same to the last bit. cifs_bench
// cross-checks each prototype against the library before timing it (the benchmarks are named
// BM_<case>/proto_…).
//
// What each one changes, in short:
//   evaluate(curve, us)   validate all parameters in one call-free loop instead of calling
//                         domain_parameter per point (a call plus a store-forwarding stall on the
//                         spilled Domain); span search: the hint for sorted input, a bucket table
//                         for unsorted input; basis recursion inlined; coordinates a compile-time
//                         count; rows written straight into the output (no temporary Point).
//   evaluate(curve, u)    de Boor into caller memory, working points on the stack: no heap traffic.
//   evaluate_grid         the coordinate count a template parameter: the per-point accumulator in
//                         registers instead of a heap vector (load-modify-store chains).
//   evaluate(surf, u, v)  (p+1)(q+1) tensor sum on the stack instead of a 1×1 evaluate_grid, which
//                         allocates six times and combines a whole iso-line of nv points.
//   refine(curve, X)      Boehm insertion run backwards (Piegl–Tiller A5.4): p combinations and p
//                         divisions per new knot, no span search per point, and a linear
//                         multiplicity check instead of a binary search per inserted knot.
//   refine_blossom        the library's blossom refinement kept, bit for bit (same pieces, same
//                         argument order, same recurrence), minus its overheads: spans walked
//                         forward instead of bisections, argument order by a merge instead of a
//                         sort, linear checks, no padded copy, fixed-size rows.
//
// The entry points are [[gnu::noinline]]: called out of line like the library's functions, so
// the timings compare like with like and callgrind attributes their cost by name.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knots.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs_bench::proto {

namespace nurbs = cifs::nurbs;
using cifs::Points;

constexpr int kMax = nurbs::kMaxDegree;

/// Same recurrence as nurbs::basis_functions (Piegl–Tiller A2.2, identical arithmetic), but inline,
/// so the compiler sees the degree loop of the caller.
inline void basis(const double* t, int p, int span, double u, double* N) noexcept {
  double left[kMax + 1], right[kMax + 1];
  N[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - t[span + 1 - j];
    right[j] = t[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = N[r] / (right[r + 1] + left[j - r]);
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
}

/// The span of u, for t_p ≤ u ≤ t_n (same answer as nurbs::find_span): the hint's span if it holds
/// u, else a branch-free bisection of t_{p+1..n−1} — a fixed ⌈log₂⌉ steps whose only decision is a
/// conditional move, so random parameters cost no branch mispredictions in the search.
inline int find_span(const double* t, int p, int n, double u, int hint) noexcept {
  if (t[hint] <= u && u < t[hint + 1]) return hint;
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
  // base + (*base <= u) is the first knot > u (upper_bound); the span starts one before.
  return static_cast<int>(base - t) + (*base <= u ? 1 : 0) - 1;
}

/// O(1) span search for unordered parameters: the domain cut into 4 buckets per span, each bucket
/// knowing the span of its left end. A lookup is a multiply, a load and (rarely) a step or two, with
/// no dependent chain of loads — the bisection's cost on random input is its ⌈log₂(#spans)⌉ serial
/// loads (branch-free) or as many mispredicted branches (std::upper_bound). Built per batch call in
/// O(#buckets + #knots), which 1e5 parameters amortise; the batch falls back to the hint otherwise.
class SpanTable {
 public:
  SpanTable(const double* t, int p, int n) : t_(t), p_(p), n_(n) {
    start_ = t[p];
    const double end = t[n];
    const int buckets = 4 * (n - p);
    scale_ = buckets / (end - start_);
    first_.resize(static_cast<std::size_t>(buckets) + 1);
    int k = p;
    for (int b = 0; b <= buckets; ++b) {
      const double x = start_ + b / scale_;
      while (k + 1 < n && t[k + 1] <= x) ++k;
      first_[static_cast<std::size_t>(b)] = k;
    }
  }
  int find(double u) const noexcept {
    if (u >= t_[n_]) return find_end();
    const double x = (u - start_) * scale_;
    int k = first_[static_cast<std::size_t>(x)];  // 0 ≤ x < #buckets + rounding: first_ has one spare
    while (u >= t_[k + 1]) ++k;                   // stops before n: u < t_n
    while (k > p_ && u < t_[k]) --k;              // rounding of x only
    return k;
  }

 private:
  int find_end() const noexcept {
    int k = n_ - 1;
    while (k > p_ && t_[k] == t_[n_]) --k;
    return k;
  }
  const double* t_;
  int p_, n_;
  double start_, scale_;
  std::vector<int> first_;
};

/// 1 when every parameter lies in [start, end] (NaN fails), in a loop without calls or branches.
inline bool all_inside(std::span<const double> us, nurbs::Domain dom) noexcept {
  int outside = 0;
  for (double u : us) outside |= static_cast<int>(!(u >= dom.start)) | static_cast<int>(!(u <= dom.end));
  return outside == 0;
}

template <int Cols, bool Table>
void evaluate_rows(const nurbs::Curve& c, std::span<const double> us, double* out) {
  const int p = c.degree;
  const int n = static_cast<int>(c.P.rows());
  const double* t = c.knots.data();
  const double* P = c.P.data();
  const int dim = c.rational ? Cols - 1 : Cols;
  double N[kMax + 1];
  int span = p;
  const SpanTable table = Table ? SpanTable(t, p, n) : SpanTable(t, p, p + 1);
  for (std::size_t i = 0; i < us.size(); ++i) {
    const double u = us[i];
    span = Table ? table.find(u) : find_span(t, p, n, u, span);
    basis(t, p, span, u, N);
    const double* base = P + (span - p) * Cols;
    double acc[Cols];
    for (int k = 0; k < Cols; ++k) acc[k] = N[0] * base[k];
    for (int r = 1; r <= p; ++r)
      for (int k = 0; k < Cols; ++k) acc[k] += N[r] * base[r * Cols + k];
    double* o = out + i * static_cast<std::size_t>(dim);
    if (c.rational)
      for (int k = 0; k < dim; ++k) o[k] = acc[k] / acc[dim];
    else
      for (int k = 0; k < Cols; ++k) o[k] = acc[k];
  }
}

/// PROTOTYPE of nurbs::evaluate(curve, us).
[[gnu::noinline]] inline Points evaluate(const nurbs::Curve& c, std::span<const double> us) {
  const auto cols = c.P.cols();
  if (c.closed || (cols != 3 && cols != 4) || !all_inside(us, nurbs::domain(c)))
    return nurbs::evaluate(c, us);
  Points out(static_cast<Eigen::Index>(us.size()), nurbs::dimension(c));
  // Sorted input keeps the hint; the table pays off once the parameters outnumber the knots.
  const bool table = us.size() >= 8 * c.knots.size() && !std::is_sorted(us.begin(), us.end());
  if (cols == 3)
    table ? evaluate_rows<3, true>(c, us, out.data()) : evaluate_rows<3, false>(c, us, out.data());
  else
    table ? evaluate_rows<4, true>(c, us, out.data()) : evaluate_rows<4, false>(c, us, out.data());
  return out;
}

template <int Cols>
void de_boor(const nurbs::Curve& c, double u, double* out) noexcept {
  const int p = c.degree;
  const double* t = c.knots.data();
  const int span = find_span(t, p, static_cast<int>(c.P.rows()), u, p);
  double d[(kMax + 1) * Cols];
  std::copy_n(c.P.data() + (span - p) * Cols, (p + 1) * Cols, d);
  for (int r = 1; r <= p; ++r)
    for (int j = p; j >= r; --j) {
      const int i = j + span - p;
      // The library's update, weights from their own differences (no 1 − α cancellation).
      const double hi = t[i + p + 1 - r], den = hi - t[i];
      const double left = (hi - u) / den, right = (u - t[i]) / den;
      for (int k = 0; k < Cols; ++k) d[j * Cols + k] = left * d[(j - 1) * Cols + k] + right * d[j * Cols + k];
    }
  const double* last = d + p * Cols;
  if (c.rational)
    for (int k = 0; k < Cols - 1; ++k) out[k] = last[k] / last[Cols - 1];
  else
    for (int k = 0; k < Cols; ++k) out[k] = last[k];
}

/// PROTOTYPE of nurbs::evaluate(curve, u), writing the dim coordinates to `out`.
[[gnu::noinline]] inline void evaluate(const nurbs::Curve& c, double u, double* out) {
  const nurbs::Domain dom = nurbs::domain(c);
  const auto cols = c.P.cols();
  if (!c.closed && u >= dom.start && u <= dom.end) {
    if (cols == 3) return de_boor<3>(c, u, out);
    if (cols == 4) return de_boor<4>(c, u, out);
  }
  const cifs::Point q = nurbs::evaluate(c, u);
  std::copy_n(q.data(), q.size(), out);
}

template <int Cols>
void surface_point(const nurbs::Surface& s, double u, double v, double* out) noexcept {
  const int p = s.degree[0], q = s.degree[1];
  const Eigen::Index nv = s.count[1];
  const double* tu = s.knots[0].data();
  const double* tv = s.knots[1].data();
  const int su = find_span(tu, p, static_cast<int>(s.count[0]), u, p);
  const int sv = find_span(tv, q, static_cast<int>(nv), v, q);
  double Nu[kMax + 1], Nv[kMax + 1];
  basis(tu, p, su, u, Nu);
  basis(tv, q, sv, v, Nv);
  // The u-combination on the q+1 columns that matter (evaluate_grid combines all nv of them), each
  // folded into the v-sum at once; the library's order of operations, so the same rounding.
  double acc[Cols] = {};
  for (int c = 0; c <= q; ++c) {
    const double* col = s.P.data() + ((su - p) * nv + (sv - q + c)) * Cols;
    double line[Cols];
    for (int k = 0; k < Cols; ++k) line[k] = Nu[0] * col[k];
    for (int r = 1; r <= p; ++r)
      for (int k = 0; k < Cols; ++k) line[k] += Nu[r] * col[r * nv * Cols + k];
    for (int k = 0; k < Cols; ++k) acc[k] = c == 0 ? Nv[0] * line[k] : acc[k] + Nv[c] * line[k];
  }
  if (s.rational)
    for (int k = 0; k < Cols - 1; ++k) out[k] = acc[k] * (1.0 / acc[Cols - 1]);
  else
    for (int k = 0; k < Cols; ++k) out[k] = acc[k];
}

/// PROTOTYPE of nurbs::evaluate(surface, u, v), writing the dim coordinates to `out`.
[[gnu::noinline]] inline void evaluate(const nurbs::Surface& s, double u, double v, double* out) {
  const nurbs::Domain du = nurbs::domain(s, nurbs::Direction::u), dv = nurbs::domain(s, nurbs::Direction::v);
  const auto cols = s.P.cols();
  if (u >= du.start && u <= du.end && v >= dv.start && v <= dv.end) {
    if (cols == 3) return surface_point<3>(s, u, v, out);
    if (cols == 4) return surface_point<4>(s, u, v, out);
  }
  const cifs::Point r = nurbs::evaluate(s, u, v);
  std::copy_n(r.data(), r.size(), out);
}

template <int Cols>
void grid_rows(const nurbs::Surface& s, std::span<const double> us, std::span<const double> vs, double* out) {
  const int p = s.degree[0], q = s.degree[1];
  const Eigen::Index nv = s.count[1];
  const int dim = s.rational ? Cols - 1 : Cols;
  const double* tu = s.knots[0].data();
  const double* tv = s.knots[1].data();
  // v basis once per grid column, as the library does.
  std::vector<int> vspan(vs.size());
  std::vector<double> Nv(vs.size() * static_cast<std::size_t>(q + 1));
  for (std::size_t b = 0; b < vs.size(); ++b) {
    vspan[b] = find_span(tv, q, static_cast<int>(nv), vs[b], b ? vspan[b - 1] : q);
    basis(tv, q, vspan[b], vs[b], Nv.data() + b * static_cast<std::size_t>(q + 1));
  }
  std::vector<double> line(static_cast<std::size_t>(nv * Cols));
  double Nu[kMax + 1];
  int uspan = p;
  for (std::size_t a = 0; a < us.size(); ++a) {
    uspan = find_span(tu, p, static_cast<int>(s.count[0]), us[a], uspan);
    basis(tu, p, uspan, us[a], Nu);
    // The iso-line Σ_r Nu_r P_{i_r, j} for every j, in the library's order of operations.
    const double* rows = s.P.data() + (uspan - p) * nv * Cols;
    for (Eigen::Index e = 0; e < nv * Cols; ++e) line[static_cast<std::size_t>(e)] = Nu[0] * rows[e];
    for (int r = 1; r <= p; ++r)
      for (Eigen::Index e = 0; e < nv * Cols; ++e)
        line[static_cast<std::size_t>(e)] += Nu[r] * rows[r * nv * Cols + e];
    double* o = out + a * vs.size() * static_cast<std::size_t>(dim);
    for (std::size_t b = 0; b < vs.size(); ++b, o += dim) {
      const double* N = Nv.data() + b * static_cast<std::size_t>(q + 1);
      const double* base = line.data() + (vspan[b] - q) * Cols;
      double acc[Cols];  // a local array: registers, not a heap vector re-read after every update
      for (int k = 0; k < Cols; ++k) acc[k] = N[0] * base[k];
      for (int r = 1; r <= q; ++r)
        for (int k = 0; k < Cols; ++k) acc[k] += N[r] * base[r * Cols + k];
      const double scale = s.rational ? 1.0 / acc[dim] : 1.0;
      for (int k = 0; k < dim; ++k) o[k] = acc[k] * scale;
    }
  }
}

/// PROTOTYPE of nurbs::evaluate_grid: the library's algorithm and arithmetic with the coordinate
/// count a template parameter, so the per-point accumulator lives in registers.
[[gnu::noinline]] inline Points evaluate_grid(const nurbs::Surface& s, std::span<const double> us,
                                              std::span<const double> vs) {
  const auto cols = s.P.cols();
  const bool inside = all_inside(us, nurbs::domain(s, nurbs::Direction::u)) &&
                      all_inside(vs, nurbs::domain(s, nurbs::Direction::v));
  if (!inside || (cols != 3 && cols != 4)) return nurbs::evaluate_grid(s, us, vs);
  Points out(static_cast<Eigen::Index>(us.size() * vs.size()), nurbs::dimension(s));
  if (cols == 3)
    grid_rows<3>(s, us, vs, out.data());
  else
    grid_rows<4>(s, us, vs, out.data());
  return out;
}

template <int Cols>
void boehm_backwards(const nurbs::Curve& c, std::span<const double> X, nurbs::Curve& out) noexcept {
  // Indices as in Piegl–Tiller A5.4: n and m are the last control-point and knot indices, r the
  // last new-knot index; a and b bracket the spans that change.
  const int p = c.degree;
  const int n = static_cast<int>(c.P.rows()) - 1;
  const int m = n + p + 1;
  const int r = static_cast<int>(X.size()) - 1;
  const double* U = c.knots.data();
  const double* P = c.P.data();
  double* Ub = out.knots.data();
  double* Q = out.P.data();
  auto copy_row = [](double* to, const double* from) {
    for (int k = 0; k < Cols; ++k) to[k] = from[k];
  };
  const int a = nurbs::find_span(c.knots, p, X.front());
  const int b = nurbs::find_span(c.knots, p, X.back()) + 1;
  for (int j = 0; j <= a - p; ++j) copy_row(Q + j * Cols, P + j * Cols);
  for (int j = b - 1; j <= n; ++j) copy_row(Q + (j + r + 1) * Cols, P + j * Cols);
  for (int j = 0; j <= a; ++j) Ub[j] = U[j];
  for (int j = b + p; j <= m; ++j) Ub[j + r + 1] = U[j];
  int i = b + p - 1, k = b + p + r;
  for (int j = r; j >= 0; --j) {
    while (X[static_cast<std::size_t>(j)] <= U[i] && i > a) {
      copy_row(Q + (k - p - 1) * Cols, P + (i - p - 1) * Cols);
      Ub[k] = U[i];
      --k;
      --i;
    }
    copy_row(Q + (k - p - 1) * Cols, Q + (k - p) * Cols);
    for (int l = 1; l <= p; ++l) {
      const int ind = k - p + l;
      double* lo = Q + (ind - 1) * Cols;
      const double* hi = Q + ind * Cols;
      const double gap = Ub[k + l] - X[static_cast<std::size_t>(j)];
      if (gap == 0.0) {
        copy_row(lo, hi);
      } else {
        const double alpha = gap / (Ub[k + l] - U[i - p + l]);
        for (int e = 0; e < Cols; ++e) lo[e] = alpha * lo[e] + (1.0 - alpha) * hi[e];
      }
    }
    Ub[k] = X[static_cast<std::size_t>(j)];
    --k;
  }
}

/// Clamped ends (d+1 equal knots at each end): the case the refinement prototypes handle; the library
/// pads unclamped curves so that the refined spline equals Σ P_i N_i on the whole knot range.
inline bool clamped(const nurbs::Curve& c) noexcept {
  const auto& t = c.knots;
  const auto d = static_cast<std::size_t>(c.degree);
  return t[0] == t[d] && t[t.size() - 1] == t[t.size() - 1 - d];
}

/// True when inserting the sorted X into the knots keeps every inserted value at multiplicity ≤ p:
/// one merge-like pass (the library binary-searches the merged vector once per inserted knot).
inline bool multiplicities_ok(std::span<const double> knots, std::span<const double> X, int p) noexcept {
  std::size_t i = 0;
  for (std::size_t j = 0; j < X.size();) {
    const double x = X[j];
    std::size_t run = 0;
    while (j < X.size() && X[j] == x) ++j, ++run;
    while (i < knots.size() && knots[i] < x) ++i;
    while (i < knots.size() && knots[i] == x) ++i, ++run;
    if (run > static_cast<std::size_t>(p)) return false;
  }
  return true;
}

/// PROTOTYPE of nurbs::refine(curve, X) for open curves.
[[gnu::noinline]] inline nurbs::Curve refine(const nurbs::Curve& c, std::span<const double> X_in) {
  const auto cols = c.P.cols();
  if (c.closed || !clamped(c) || X_in.empty() || (cols != 3 && cols != 4) ||
      !all_inside(X_in, nurbs::domain(c)))
    return nurbs::refine(c, X_in);
  std::vector<double> sorted;
  std::span<const double> X = X_in;
  if (!std::is_sorted(X.begin(), X.end())) {
    sorted.assign(X.begin(), X.end());
    std::sort(sorted.begin(), sorted.end());
    X = sorted;
  }
  if (!multiplicities_ok(c.knots, X, c.degree)) return nurbs::refine(c, X_in);  // the library throws
  const auto added = static_cast<Eigen::Index>(X.size());
  nurbs::Curve out{c.degree, nurbs::Knots(c.knots.size() + X.size()), Points(c.P.rows() + added, cols),
                   c.rational, false};
  if (cols == 3)
    boehm_backwards<3>(c, X, out);
  else
    boehm_backwards<4>(c, X, out);
  return out;
}

/// nurbs::blossom_weights for arguments given in increasing order (refinement: consecutive knots),
/// with the library's nearest-to-the-span-first argument order obtained by a merge from the span
/// outwards, O(d), instead of a std::sort with a distance comparator per call. (libstdc++ sorts d < 16
/// values by insertion, which is stable; the merge reproduces that order, so the weights are the
/// library's to the last bit — the cross-check prints the difference.)
inline void blossom_weights_increasing(const double* t, int p, int span, const double* args,
                                       double* W) noexcept {
  const double a = t[span], b = t[span + 1];
  double x[kMax];
  int lo = 0;
  while (lo < p && args[lo] < a) ++lo;  // args[0..lo) left of the span
  int hi = lo;
  while (hi < p && args[hi] <= b) ++hi;  // args[lo..hi) inside: distance 0
  int m = 0;
  for (int i = lo; i < hi; ++i) x[m++] = args[i];
  for (int l = lo - 1, r = hi; l >= 0 || r < p;) {
    const bool take_left = r == p || (l >= 0 && a - args[l] <= args[r] - b);
    x[m++] = take_left ? args[l--] : args[r++];
  }
  W[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    const double xj = x[j - 1];
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double lo_knot = t[span + 1 - j + r], hi_knot = t[span + 1 + r];
      const double temp = W[r] / (hi_knot - lo_knot);
      W[r] = saved + (hi_knot - xj) * temp;
      saved = (xj - lo_knot) * temp;
    }
    W[j] = saved;
  }
}

template <int Cols>
void blossom_rows(const nurbs::Curve& c, const nurbs::Knots& target, const std::vector<int>& new_before,
                  nurbs::Curve& out) noexcept {
  const int p = c.degree;
  const int n = static_cast<int>(c.P.rows());
  const int tn = static_cast<int>(target.size());
  const double* P = c.P.data();
  double* Q = out.P.data();
  double W[kMax + 1];
  int span = p;  // old span of the piece; the pieces' midpoints increase with j, so it only walks forward
  for (int j = 0; j < static_cast<int>(out.P.rows()); ++j) {
    double* row = Q + j * Cols;
    const int shift = new_before[static_cast<std::size_t>(j + 1)];
    if (new_before[static_cast<std::size_t>(j + p + 1)] == shift) {  // arguments are all old knots
      for (int k = 0; k < Cols; ++k) row[k] = P[(j - shift) * Cols + k];
      continue;
    }
    // The library's choice of piece — of the non-empty target intervals in the support of N'_j,
    // the one whose old span is widest (first on ties) — with the old spans found by walking
    // forward from the previous point's instead of one bisection of all the old knots per candidate.
    const int k_begin = std::max(j, p), k_end = std::min(j + p, tn - p - 2);
    const auto at = [&](int i) { return target[static_cast<std::size_t>(i)]; };
    const auto old_at = [&](int i) { return c.knots[static_cast<std::size_t>(i)]; };
    int best = -1, walk = -1;
    double widest = -1;
    for (int k = k_begin; k <= k_end; ++k) {
      if (!(at(k) < at(k + 1)) && !(k == k_end && best < 0)) continue;  // as the library
      const double mid = 0.5 * (at(k) + at(k + 1));
      if (walk < 0) {
        while (span + 1 < n && old_at(span + 1) <= mid) ++span;  // first candidate: moves with j
        walk = span;
      }
      while (walk + 1 < n && old_at(walk + 1) <= mid) ++walk;
      const double width = old_at(walk + 1) - old_at(walk);
      if (width > widest) best = walk, widest = width;
    }
    blossom_weights_increasing(c.knots.data(), p, best, target.data() + j + 1, W);
    double acc[Cols] = {};
    for (int i = 0; i <= p; ++i)
      for (int e = 0; e < Cols; ++e) acc[e] += W[i] * P[(best - p + i) * Cols + e];
    for (int e = 0; e < Cols; ++e) row[e] = acc[e];
  }
}

/// PROTOTYPE of nurbs::refine(curve, X) for clamped open curves that keeps the library's algorithm
/// and its rounding — every new control point is the blossom at t'_{j+1..j+p} on the widest old
/// piece of its support, arguments nearest the piece first — and removes only the overheads around
/// it: old spans found by a forward walk (not a bisection per candidate piece), the argument order by
/// a merge (not a sort), parameters and multiplicities checked in linear passes, no sort of sorted
/// input, no padded copy of the curve, fixed-size accumulation into the output.
[[gnu::noinline]] inline nurbs::Curve refine_blossom(const nurbs::Curve& c, std::span<const double> X_in) {
  const auto cols = c.P.cols();
  if (c.closed || !clamped(c) || X_in.empty() || (cols != 3 && cols != 4) ||
      !all_inside(X_in, nurbs::domain(c)))
    return nurbs::refine(c, X_in);
  std::vector<double> sorted;
  std::span<const double> X = X_in;
  if (!std::is_sorted(X.begin(), X.end())) {
    sorted.assign(X.begin(), X.end());
    std::sort(sorted.begin(), sorted.end());
    X = sorted;
  }
  if (!multiplicities_ok(c.knots, X, c.degree)) return nurbs::refine(c, X_in);  // the library throws
  nurbs::Curve out{c.degree, nurbs::Knots(c.knots.size() + X.size()),
                   Points(c.P.rows() + static_cast<Eigen::Index>(X.size()), cols), c.rational, false};
  std::vector<int> new_before(out.knots.size() + 1, 0);  // new knots among target[0..i), as the library
  for (std::size_t i = 0, a = 0, b = 0; i < out.knots.size(); ++i) {
    const bool take_new = b < X.size() && (a == c.knots.size() || X[b] < c.knots[a]);
    out.knots[i] = take_new ? X[b++] : c.knots[a++];
    new_before[i + 1] = new_before[i] + (take_new ? 1 : 0);
  }
  if (cols == 3)
    blossom_rows<3>(c, out.knots, new_before, out);
  else
    blossom_rows<4>(c, out.knots, new_before, out);
  return out;
}

}  // namespace cifs_bench::proto
