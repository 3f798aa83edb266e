// SPDX-License-Identifier: MIT
#include "cifs/nurbs/refine.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <iterator>
#include <span>

#include "detail.hpp"
#include "lines.hpp"

namespace cifs::nurbs {
namespace {

/// The old piece that covers the new interval k of `target` (a refinement keeps the pieces): its span
/// and, for closed curves, the whole periods by which the interval lies past the period.
struct Piece {
  int span;
  int periods;
};

/// Closed curves: `target` is periodic of degree q over the same period as c's, and the interval is
/// read as b'_K + q·T from its index (periodic_index), so that no rounded shift is needed.
Piece piece_for(const Curve& c, const Knots& target, int q, int k, int hint) {
  const Domain dom = domain(c);
  double lo = target[static_cast<std::size_t>(k)], hi = target[static_cast<std::size_t>(k) + 1];
  int periods = 0;
  if (c.closed) {
    const int m = static_cast<int>(target.size()) - 2 * q - 1;
    const detail::PeriodicIndex at = detail::periodic_index(k, q, m);
    const auto first = static_cast<std::size_t>(q) + static_cast<std::size_t>(at.k);
    lo = target[first];
    hi = target[first + 1];
    periods = at.q;
  }
  const double mid = 0.5 * (lo + hi);
  return {find_span(c.knots, c.degree, std::min(std::max(mid, dom.start), dom.end), hint), periods};
}

/// Row j of the control points of the same piecewise polynomial, seen with degree `c.degree + raise`
/// (raise ∈ {0, 1}) on `target`, a knot vector whose pieces are pieces of `c`: the blossom at the
/// consecutive target knots t'_{j+1..j+q}, symmetrised over the dropped argument when raised, written
/// to Q.row(row). The piece is one under an interval of the support of N'_j (open curves: within the
/// target's domain). `hint` carries the last piece's span from point to point.
void set_blossom_point(const Curve& c, const Knots& target, int raise, Eigen::Index j, Points& Q,
                       Eigen::Index row, int& hint) {
  const int p = c.degree;
  const int q = p + raise;
  const auto tn = static_cast<int>(target.size());
  const int jj = static_cast<int>(j);
  // Closed curves: closed_on picks a copy j of the point whose support starts with an interval of
  // the period, so that the piece is mostly found without a shift by whole periods.
  // Any piece of the support gives the same blossom, but not the same rounding: a piece evaluated
  // far outside its own interval amplifies errors by (distance / width)^d. Take the widest.
  const int k_begin = c.closed ? jj : std::max(jj, q);
  const int k_end = std::min(jj + q, c.closed ? tn - 2 : tn - q - 2);
  const auto at = [&](int i) { return target[static_cast<std::size_t>(i)]; };
  Piece piece{-1, 0};
  double widest = -1;
  for (int k = k_begin; k <= k_end; ++k) {
    if (!(at(k) < at(k + 1)) && !(k == k_end && piece.span < 0)) continue;
    const Piece candidate = piece_for(c, target, q, k, hint);
    hint = candidate.span;
    const double width = c.knots[static_cast<std::size_t>(candidate.span) + 1] -
                         c.knots[static_cast<std::size_t>(candidate.span)];
    if (width > widest) piece = candidate, widest = width;
  }
  // The arguments are consecutive knots: increasing, also with one dropped. Closed curves take them
  // relative to the piece's span, from differences of breakpoints (detail::span_knots).
  double args[kMaxDegree + 1], sub[kMaxDegree], W[kMaxDegree + 1], local[2 * kMaxDegree];
  // Always relative for closed curves: the arguments may reach beyond the period (q ≠ 0).
  const int m = tn - 2 * q - 1;
  const detail::SpanKnots knots =
      detail::span_knots(c.knots, p, c.closed ? static_cast<int>(c.P.rows()) - p : 0, piece.span, local);
  const Domain dom = domain(c);
  for (int a = 0; a < q; ++a) {
    const int i = jj + 1 + a;
    if (!c.closed) {
      args[a] = at(i) + 0.0;  // −0 → +0, as the shift of 0 did before: outputs stay bit-identical
      continue;
    }
    const detail::PeriodicIndex pi = detail::periodic_index(i, q, m);
    args[a] =
        detail::periodic_difference(at(q + pi.k), pi.q - piece.periods, knots.origin, dom.start, dom.end);
  }
  const Eigen::Index cols = c.P.cols();
  double* out = Q.row(row).data();
  std::fill_n(out, cols, 0.0);
  for (int drop = 0; drop < (raise ? q : 1); ++drop) {
    for (int a = 0, b = 0; a < q; ++a)
      if (!raise || a != drop) sub[b++] = args[a];
    detail::blossom_weights_increasing(knots.t.data(), p, knots.span, sub, W);
    for (int i = 0; i <= p; ++i) {
      const double* P = c.P.row(piece.span - p + i).data();
      for (Eigen::Index k = 0; k < cols; ++k) out[k] += W[i] * P[k];
    }
  }
  if (raise)
    for (Eigen::Index k = 0; k < cols; ++k) out[k] /= q;
}

Points blossom_points(const Curve& c, const Knots& target, int raise, Eigen::Index count) {
  Points Q(count, c.P.cols());
  int hint = c.degree;
  for (Eigen::Index j = 0; j < count; ++j) set_blossom_point(c, target, raise, j, Q, j, hint);
  return Q;
}

/// Closed curve on new breakpoints (a refinement or elevation of its period).
Curve closed_on(const Curve& c, const Knots& breaks, int raise) {
  const int q = c.degree + raise;
  const auto m = static_cast<Eigen::Index>(breaks.size()) - 1;
  Curve out{q, periodic_knots(breaks, q), {}, c.rational, true};
  // Point j is row j + a·m of the expanded net for every a. Use the copy whose support starts in the
  // period [t_q, t_{m+q}): its first non-empty interval lies in the period, or one period later, in
  // which case the previous copy's first non-empty interval lies in the period.
  const auto& t = out.knots;
  const auto tn = static_cast<Eigen::Index>(t.size());
  Points distinct(m, c.P.cols());
  int hint = c.degree;
  for (Eigen::Index j = 0; j < m; ++j) {
    Eigen::Index row = j < q ? j + m * ((q - j + m - 1) / m) : j;
    Eigen::Index k = row;
    while (k < std::min(row + q, tn - 2) &&
           !(t[static_cast<std::size_t>(k)] < t[static_cast<std::size_t>(k + 1)]))
      ++k;
    if (k > m + q - 1) row -= m;
    set_blossom_point(c, t, raise, row, distinct, j, hint);
  }
  out.P.resize(m + q, c.P.cols());
  for (Eigen::Index i = 0; i < out.P.rows(); ++i) out.P.row(i) = distinct.row(i % m);
  return out;
}

/// The insertion knots, validated against the curve (closed curves: wrapped into the period), sorted:
/// `new_knots` itself when it is in the domain and sorted, else a copy in `storage`.
std::span<const double> checked_insertions(const Curve& c, std::span<const double> new_knots,
                                           std::vector<double>& storage) {
  const Domain dom = domain(c);
  const detail::Scan scan = detail::scan(new_knots, dom);
  const bool wraps_end =
      c.closed && std::find(new_knots.begin(), new_knots.end(), dom.end) != new_knots.end();
  if (scan.inside && scan.sorted && !wraps_end) return new_knots;
  storage.assign(new_knots.begin(), new_knots.end());
  for (std::size_t i = 0; i < storage.size(); ++i) {
    double& u = storage[i];
    if (!scan.inside) {
      if (!std::isfinite(u)) detail::fail("knot ", i, ": ", u, " is not finite");
      if (!c.closed && (u < dom.start || u > dom.end))
        detail::fail("knot ", u, " is outside the domain [", dom.start, ", ", dom.end, "]");
      u = domain_parameter(c, u);
    }
    if (c.closed && u == dom.end) u = dom.start;  // the period's end is its start
  }
  if (!std::is_sorted(storage.begin(), storage.end())) std::sort(storage.begin(), storage.end());
  return storage;
}

/// Throws unless every value of the sorted X has multiplicity ≤ degree in the sorted `knots`, which
/// hold the insertions already (closed curves). One merge-like pass.
void check_multiplicities(std::span<const double> knots, std::span<const double> X, int degree) {
  std::size_t i = 0;
  for (const double x : X) {
    while (i < knots.size() && knots[i] < x) ++i;
    int mult = 0;
    for (std::size_t e = i; e < knots.size() && knots[e] == x; ++e) ++mult;
    if (mult > degree) detail::fail("knot ", x, " would reach multiplicity ", mult, " > degree ", degree);
  }
}

// ------------------------------------------------------------------------------------------------
// Open curves: two ways to the same points.
//
// Blossoms: every new point on its own, Q_j = b(t'_{j+1..j+d}) on the widest old piece under its
// support; the rounding does not depend on the number of knots. Boehm's insertion run backwards
// (Piegl–Tiller A5.4): d convex combinations per new knot, several times cheaper, but a combination
// may read a point that the previous insertion made, so rounding adds up along chains of insertions.
//
// The chain bound. Undo the insertions from the smallest new knot up. A point whose d consecutive
// knots W contain the knot x being undone is a convex combination of two points whose knots are W
// without x plus the knot left or right of W; the left one is old (the new knots left of x are undone
// already). Old knots never leave W, so the windows along a chain of combinations hold at most d old
// knot copies in all, and the new knots undone along it lie in the d + 1 gaps around those. A chain
// therefore has at most
//     S = max over c of #{new knots x : c ≤ #(old knots < x) ≤ c + d}
// combinations (A5.4 puts new knots before equal old ones, hence "<"). Each is convex (0 ≤ α ≤ 1) and
// adds a few ulps of max |P|, so Boehm's points are within about S · 3ε · max |P|. refine takes Boehm
// when S ≤ max(16, d + 1): d + 1 because the blossom recursion itself rounds through d levels, not all
// convex; 16 as an absolute budget (≈ 1e-14 · max |P|) that admits a few knots per span at low degree.
// Single insertions (S = 1), insert_knot's m ≤ d copies and midpoint refinement (S = d + 1) take
// Boehm; many knots in one span take blossoms (65 535 knots in one span: 6e-15 against long double
// with blossoms, 2.5e-12 with A5.4; verify's dyadic references are such refinements).

constexpr int kBoehmBudget = 16;

/// One pass over the sorted X and the old knots: throws unless every value keeps multiplicity ≤ p, and
/// tells whether Boehm's chains are short: S ≤ max(kBoehmBudget, p + 1), i.e. no limit + 1 consecutive
/// new knots have counts of old knots below them within p of each other.
bool checked_short_chains(std::span<const double> t, std::span<const double> X, int p) {
  constexpr std::size_t kRing = 128;  // a power of two above every limit (kMaxDegree + 1 = 65)
  static_assert(kRing > kMaxDegree + 1 && kRing > kBoehmBudget && (kRing & (kRing - 1)) == 0);
  const auto limit = static_cast<std::size_t>(std::max(kBoehmBudget, p + 1));
  std::size_t below = 0;         // #old knots < X[j]
  std::size_t ring[kRing] = {};  // the same for X[j − 1], X[j − 2], ...
  bool short_chains = true;
  for (std::size_t j = 0; j < X.size(); ++j) {
    const double x = X[j];
    while (below < t.size() && t[below] < x) ++below;
    const bool repeated = (below < t.size() && t[below] == x) || (j + 1 < X.size() && X[j + 1] == x);
    if (repeated && (j == 0 || X[j - 1] != x)) {
      int mult = 0;  // its copies in X from here, and in t
      for (std::size_t e = j; e < X.size() && X[e] == x; ++e) ++mult;
      for (std::size_t e = below; e < t.size() && t[e] == x; ++e) ++mult;
      if (mult > p) detail::fail("knot ", x, " would reach multiplicity ", mult, " > degree ", p);
    }
    if (j >= limit && below - ring[(j - limit) & (kRing - 1)] <= static_cast<std::size_t>(p))
      short_chains = false;
    ring[j & (kRing - 1)] = below;
  }
  return short_chains;
}

template <int Cols>
void copy_row(double* to, const double* from, Eigen::Index cols) noexcept {
  for (Eigen::Index k = 0; k < (Cols > 0 ? Cols : cols); ++k) to[k] = from[k];
}

/// Boehm's insertion of the sorted X, backwards (Piegl–Tiller A5.4, indices as there: n and m the last
/// point and knot, r the last new knot, a and b bracketing the spans that change). `Ub` is the merged
/// knot vector (written here), Q its n + r + 2 rows. Valid for unclamped curves as they are: the
/// insertion formula is an identity of the basis functions on the whole knot range.
template <int Cols>
void boehm_rows(const Curve& c, std::span<const double> X, double* Ub, double* Q) noexcept {
  const int p = c.degree;
  const Eigen::Index cols = Cols > 0 ? Cols : c.P.cols();
  const int n = static_cast<int>(c.P.rows()) - 1;
  const int m = n + p + 1;
  const int r = static_cast<int>(X.size()) - 1;
  const double* U = c.knots.data();
  const double* P = c.P.data();
  const int a = detail::find_span(U, p, n + 1, X.front());
  const int b = detail::find_span(U, p, n + 1, X.back()) + 1;
  for (int j = 0; j <= a - p; ++j) copy_row<Cols>(Q + j * cols, P + j * cols, cols);
  for (int j = b - 1; j <= n; ++j) copy_row<Cols>(Q + (j + r + 1) * cols, P + j * cols, cols);
  for (int j = 0; j <= a; ++j) Ub[j] = U[j];
  for (int j = b + p; j <= m; ++j) Ub[j + r + 1] = U[j];
  int i = b + p - 1, k = b + p + r;
  for (int j = r; j >= 0; --j) {
    while (X[static_cast<std::size_t>(j)] <= U[i] && i > a) {
      copy_row<Cols>(Q + (k - p - 1) * cols, P + (i - p - 1) * cols, cols);
      Ub[k] = U[i];
      --k;
      --i;
    }
    copy_row<Cols>(Q + (k - p - 1) * cols, Q + (k - p) * cols, cols);
    for (int l = 1; l <= p; ++l) {
      const int ind = k - p + l;
      double* lo = Q + (ind - 1) * cols;
      const double* hi = Q + ind * cols;
      const double gap = Ub[k + l] - X[static_cast<std::size_t>(j)];
      if (gap == 0.0) {
        copy_row<Cols>(lo, hi, cols);
      } else {
        const double alpha = gap / (Ub[k + l] - U[i - p + l]);
        for (Eigen::Index e = 0; e < cols; ++e) lo[e] = alpha * lo[e] + (1.0 - alpha) * hi[e];
      }
    }
    Ub[k] = X[static_cast<std::size_t>(j)];
    --k;
  }
}

/// Blossom refinement rows. `t` is the old knot vector, readable at t[−p .. #t + p − 1] for
/// unclamped curves (padded, see refine); T the merged vector with the new knots after equal old ones,
/// new_before[i] the number of new knots among T[0..i). The target interval k lies in the old interval
/// k − new_before[k+1]: no span search.
template <int Cols>
void blossom_rows(const Curve& c, const double* t, std::span<const double> T, const int* new_before,
                  double* Q, double* scratch) noexcept {
  const int p = c.degree;
  const int n = static_cast<int>(c.P.rows());
  const Eigen::Index cols = Cols > 0 ? Cols : c.P.cols();
  const int count = static_cast<int>(T.size()) - p - 1;
  const double* P = c.P.data();
  double fixed[Cols > 0 ? Cols : 1];
  double* acc = Cols > 0 ? fixed : scratch;
  double W[kMaxDegree + 1], x[kMaxDegree], inv[detail::kReciprocals];
  int cached = -1;  // the span of inv: none yet
  for (int j = 0; j < count; ++j, Q += cols) {
    const int before = new_before[j + 1];
    if (new_before[j + p + 1] == before) {  // t'_{j+1..j+p} are the old t_{i+1..i+p}: Q_j = P_i
      copy_row<Cols>(Q, P + (j - before) * cols, cols);
      continue;
    }
    const double* args = T.data() + j + 1;
    int span = j - before;
    if (new_before[j + p + 1] - before < p) {  // an old knot among the arguments: the widest piece
      double widest = -1;
      for (int k = j; k <= j + p; ++k) {
        if (!(T[static_cast<std::size_t>(k)] < T[static_cast<std::size_t>(k) + 1])) continue;
        const int s = k - new_before[k + 1];
        if (t[s + 1] - t[s] > widest) span = s, widest = t[s + 1] - t[s];
      }
      assert(widest > 0);  // at most d + 1 equal knots: the support has a non-empty interval
      detail::nearest_first_increasing(args, p, t[span], t[span + 1], x);
      args = x;
    }  // else all arguments are new, in one old span (the only piece under the support): in order
    if (span != cached) detail::blossom_reciprocals(t, p, cached = span, inv);
    detail::blossom_recurrence(t, p, span, inv, args, W);
    // Rows outside 0..n−1 are the padding's zero points.
    for (Eigen::Index e = 0; e < cols; ++e) acc[e] = 0.0;
    for (int i = std::max(0, p - span); i <= std::min(p, n - 1 - span + p); ++i) {
      const double* row = P + (span - p + i) * cols;
      for (Eigen::Index e = 0; e < cols; ++e) acc[e] += W[i] * row[e];
    }
    copy_row<Cols>(Q, acc, cols);
  }
}

/// Open curves: the merged knots, then Boehm or blossoms by the chain bound.
Curve refine_open(const Curve& c, std::span<const double> X) {
  const int p = c.degree;
  const auto& t = c.knots;
  const bool boehm = checked_short_chains(t, X, p);
  const auto added = static_cast<Eigen::Index>(X.size());
  Curve out{p, Knots(t.size() + X.size()), Points(c.P.rows() + added, c.P.cols()), c.rational, false};
  if (boehm) {
    detail::with_cols(c.P.cols(), [&](auto cols) { boehm_rows<cols>(c, X, out.knots.data(), out.P.data()); });
    return out;
  }
  std::vector<int> new_before(out.knots.size() + 1, 0);
  for (std::size_t i = 0, a = 0, b = 0; i < out.knots.size(); ++i) {
    const bool take_new = b < X.size() && (a == t.size() || X[b] < t[a]);
    out.knots[i] = take_new ? X[b++] : t[a++];
    new_before[i + 1] = new_before[i] + (take_new ? 1 : 0);
  }
  // To preserve Σ P_i N_i on the whole knot range, as Boehm's insertion does, also where the basis
  // functions of an unclamped curve vanish on the domain, the curve is padded with d knots and d zero
  // points on each side: every original interval becomes part of the padded domain, where blossoms
  // are defined, and the pads add nothing to the sum. Only the knots are copied (blossom_rows skips
  // the zero rows); clamped curves have no non-empty interval outside the domain and need no pads.
  const auto d = static_cast<std::size_t>(p);
  const bool clamped = t[0] == t[d] && t[t.size() - 1] == t[t.size() - 1 - d];
  std::vector<double> padded;
  const double* old_knots = t.data();
  if (!clamped) {
    const double front = t.front(), back = t.back();
    const double pad = back > front ? back - front : 1.0;
    for (int i = p; i >= 1; --i) padded.push_back(front - i * pad);
    padded.insert(padded.end(), t.begin(), t.end());
    for (int i = 1; i <= p; ++i) padded.push_back(back + i * pad);
    old_knots = padded.data() + p;
  }
  detail::with_cols(c.P.cols(), [&](auto cols) {
    std::vector<double> scratch = detail::scratch<cols>(c.P.cols());
    blossom_rows<cols>(c, old_knots, out.knots, new_before.data(), out.P.data(), scratch.data());
  });
  return out;
}

}  // namespace

Curve refine(const Curve& c, std::span<const double> new_knots) {
  std::vector<double> storage;
  const std::span<const double> X = checked_insertions(c, new_knots, storage);
  if (X.empty()) return c;
  if (!c.closed) return refine_open(c, X);
  Knots breaks = defining_knots(c);
  breaks.insert(breaks.end() - 1, X.begin(), X.end());
  std::sort(breaks.begin(), breaks.end() - 1);
  Curve out = closed_on(c, breaks, 0);
  check_multiplicities(out.knots, X, c.degree);
  return out;
}

Curve insert_knot(const Curve& c, double u, int times) {
  if (times < 1) detail::fail("the knot count times = ", times, " must be at least 1");
  // Before the copies are made: times = 10^9 allocated 8 GB to be refused by refine.
  if (times > c.degree) detail::fail("knot ", u, " would reach multiplicity ", times, " > degree ", c.degree);
  const std::vector<double> X(static_cast<std::size_t>(times), u);
  return refine(c, X);
}

Curve refine_midpoints(const Curve& c) {
  const std::vector<double> b = breakpoints(c.knots, c.degree);
  std::vector<double> mid(b.size() - 1);
  for (std::size_t i = 0; i + 1 < b.size(); ++i) mid[i] = 0.5 * (b[i] + b[i + 1]);
  return refine(c, mid);
}

std::vector<Curve> split_bezier(const Curve& c) {
  const int p = c.degree;
  std::vector<Curve> pieces;
  std::vector<double> args(static_cast<std::size_t>(p));
  for (int k = p; k < c.P.rows(); ++k) {
    const double a = c.knots[static_cast<std::size_t>(k)], b = c.knots[static_cast<std::size_t>(k) + 1];
    if (!(a < b)) continue;
    Curve piece{p, Knots(static_cast<std::size_t>(2 * p + 2), a), Points(p + 1, c.P.cols()), c.rational,
                false};
    std::fill(piece.knots.begin() + p + 1, piece.knots.end(), b);
    for (int r = 0; r <= p; ++r) {  // Bézier point r = blossom(a^{p−r}, b^r)
      std::fill(args.begin(), args.end() - r, a);
      std::fill(args.end() - r, args.end(), b);
      piece.P.row(r) = detail::blossom_row(c, args, k);
    }
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

std::array<Curve, 2> split(const Curve& c, double u) {
  if (c.closed) detail::fail("split: a closed curve has no ends to keep; cut it open first");
  const Domain dom = domain(c);
  if (!std::isfinite(u) || !(u > dom.start && u < dom.end))
    detail::fail("split: parameter ", u, " is not strictly inside the domain [", dom.start, ", ", dom.end,
                 "]");
  const int p = c.degree;
  const int has = multiplicity(c.knots, u);
  const Curve d = has < p ? insert_knot(c, u, p - has) : c;
  const auto& t = d.knots;
  const auto f = static_cast<Eigen::Index>(std::lower_bound(t.begin(), t.end(), u) - t.begin());
  const Eigen::Index k = std::max(has, p);  // copies of u now: p, or p + 1 at a break
  Curve left{p, Knots(t.begin(), t.begin() + f + k), d.P.topRows(f), d.rational, false};
  left.knots.insert(left.knots.end(), static_cast<std::size_t>(p + 1 - k), u);
  Knots right_knots(static_cast<std::size_t>(p + 1 - k), u);
  right_knots.insert(right_knots.end(), t.begin() + f, t.end());
  const Eigen::Index first = f + k - p - 1;
  Curve right{p, std::move(right_knots), d.P.bottomRows(d.P.rows() - first), d.rational, false};
  validate(left);
  validate(right);
  return {std::move(left), std::move(right)};
}

Curve reverse(const Curve& c) {
  const Domain dom = domain(c);
  Curve out = c;
  out.P = c.P.colwise().reverse();
  // Closed curves: the periodic knots of the mirrored breakpoints (the same values up to rounding).
  out.knots = c.closed ? periodic_knots(detail::mirrored_knots(defining_knots(c), dom), c.degree)
                       : detail::mirrored_knots(c.knots, dom);
  validate(out);
  return out;
}

Curve reparametrize(const Curve& c, double start, double end) {
  Curve out = c;
  try {
    out.knots = c.closed
                    ? periodic_knots(detail::mapped_knots(defining_knots(c), domain(c), start, end), c.degree)
                    : detail::mapped_knots(c.knots, domain(c), start, end);
  } catch (const InvalidInput& e) {
    detail::fail("reparametrize: ", e.what());
  }
  validate(out);
  return out;
}

Curve normalize_knots(const Curve& c) {
  return reparametrize(c, 0.0, 1.0);
}

Curve elevate_degree(const Curve& c, int times) {
  if (times < 0) detail::fail("the degree elevation times = ", times, " is negative");
  if (c.degree + times > kMaxDegree)
    detail::fail("the elevated degree ", c.degree + times, " exceeds the maximum ", kMaxDegree);
  Curve out = c;
  for (int step = 0; step < times; ++step) {
    // Every knot value of the domain gains one in multiplicity (the ends too).
    const Domain dom = domain(out);
    if (out.closed) {
      // The seam b_0 ≡ b_m gains one copy in all: copies of b_m inside the period do not gain.
      Knots breaks = defining_knots(out);
      Knots raised;
      for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
        raised.push_back(breaks[i]);
        if ((i == 0 || breaks[i] != breaks[i - 1]) && breaks[i] != breaks.back()) raised.push_back(breaks[i]);
      }
      raised.push_back(breaks.back());
      out = closed_on(out, raised, 1);
      continue;
    }
    // Open curve: elevate the whole spline Σ P_i N_i over [t_0, t_{n+d}] (zero outside it), whose
    // points are then convex combinations of the old ones. Padding with d zero points on either side
    // makes every interval of the knot vector a full span of the padded curve; every knot value gains
    // a copy; the rows that serve only the knots outside the domain are dropped afterwards, which
    // puts the domain back at [t'_q, t'_{n'}]. (Keeping the outer knots of an unclamped curve instead
    // forces its outer points to extrapolate the end pieces: wild points, negative weights.)
    const int d = out.degree, q = d + 1;
    const Knots& t = out.knots;
    Curve pad{d, Knots(static_cast<std::size_t>(d), t.front()),
              Points::Zero(out.P.rows() + 2 * Eigen::Index{d}, out.P.cols()), out.rational, false};
    pad.knots.insert(pad.knots.end(), t.begin(), t.end());
    pad.knots.insert(pad.knots.end(), static_cast<std::size_t>(d), t.back());
    pad.P.middleRows(d, out.P.rows()) = out.P;
    Knots raised;
    std::size_t below = 0, above = 0;  // distinct knot values outside the domain
    for (std::size_t i = 0; i < t.size(); ++i) {
      raised.push_back(t[i]);
      if (i + 1 == t.size() || t[i + 1] != t[i]) {
        raised.push_back(t[i]);
        below += t[i] < dom.start;
        above += t[i] > dom.end;
      }
    }
    Knots target(static_cast<std::size_t>(d), t.front());
    target.insert(target.end(), raised.begin(), raised.end());
    target.insert(target.end(), static_cast<std::size_t>(d), t.back());
    const Points Q = blossom_points(pad, target, 1, static_cast<Eigen::Index>(target.size()) - q - 1);
    Knots knots(raised.begin() + static_cast<std::ptrdiff_t>(below),
                raised.end() - static_cast<std::ptrdiff_t>(above));
    const auto count = static_cast<Eigen::Index>(knots.size()) - q - 1;
    out = Curve{q, std::move(knots), Q.middleRows(d + static_cast<Eigen::Index>(below), count), out.rational,
                false};
  }
  return out;
}

namespace {

/// Removes one copy of the knot u (interior, present) from (U, P) of degree p into Q and returns the
/// residual of the equation left over, in stored coordinates: the largest over the row's points of
/// `cols` coordinates. Boehm's insertion of u into the
/// shorter vector V gives P_i = α_i Q_i + (1 − α_i) Q_{i−1}, α_i = (u − V_i)/(V_{i+p} − V_i), for i in
/// [k−p+1, k−s+1] (k = r − 1, r the last copy of u, s its multiplicity), with Q_i = P_i before and
/// Q_i = P_{i+1} after. α decreases with i: equations with α ≥ 1/2 are solved for Q_i from the left,
/// the others for Q_{i−1} from the right, and the first one with α < 1/2 is the check.
double remove_one(const Knots& U, const Points& P, int p, double u, Eigen::Index cols, Points& Q) {
  const int r = static_cast<int>(std::upper_bound(U.begin(), U.end(), u) - U.begin()) - 1;
  const int s = multiplicity(U, u);
  const int k = r - 1, lo = k - p + 1, hi = k - s + 1;  // equations lo..hi
  Knots V = U;
  V.erase(V.begin() + r);
  auto alpha = [&](int i) {
    const double a = V[static_cast<std::size_t>(i)],
                 b = V[static_cast<std::size_t>(i) + static_cast<std::size_t>(p)];
    return (u - a) / (b - a);
  };
  const auto n = P.rows();
  Q.resize(n - 1, P.cols());
  Q.topRows(lo) = P.topRows(lo);
  Q.bottomRows(n - 1 - hi) = P.bottomRows(n - 1 - hi);
  int check = lo;
  while (check < hi && alpha(check) >= 0.5) {
    const double a = alpha(check);
    Q.row(check) = (P.row(check) - (1 - a) * Q.row(check - 1)) / a;
    ++check;
  }
  for (int i = hi; i > check; --i) {
    const double a = alpha(i);
    Q.row(i - 1) = (P.row(i) - a * Q.row(i)) / (1 - a);
  }
  const double a = alpha(check);
  const Point residual = P.row(check) - a * Q.row(check) - (1 - a) * Q.row(check - 1);
  double largest = 0;  // over the points of the row
  for (Eigen::Index e = 0; e < residual.size(); e += cols)
    largest = std::max(largest, residual.segment(e, cols).norm());
  return largest;
}

}  // namespace

namespace detail {

double deviation_bound(const Points& from, const Points& to, int degree, Layout layout) {
  const Eigen::Index cols = layout.cols, dim = cols - (layout.rational ? 1 : 0), n = from.rows();
  double bound = 0;
  if (!layout.rational) {
    for (Eigen::Index r = 0; r < n; ++r)
      for (Eigen::Index k = 0; k < from.cols(); k += cols)
        bound = std::max(bound, (to.row(r).segment(k, dim) - from.row(r).segment(k, dim)).norm());
    return bound;
  }
  // S_to − S_from = Σ B_i (ΔA_i − S_to·Δw_i) / w_from on the rows of a span's window (B ≥ 0, Σ B = 1), and
  // S_to lies in the hull of the window's points x_j: |ΔA_i − S_to·Δw_i| ≤ |ΔA_i − c·Δw_i| + ρ·|Δw_i| for
  // c the centre of their box and ρ their largest distance to it, or ≤ |ΔA_i| + max |x_j|·|Δw_i|.
  const auto x = [&](Eigen::Index r, Eigen::Index k) -> Point {
    return to.row(r).segment(k, dim) / to(r, k + dim);
  };
  for (Eigen::Index first = 0; first + degree < n; ++first) {
    const Eigen::Index last = first + degree;
    Point lo = x(first, 0), hi = lo;
    double lightest = HUGE_VAL;
    for (Eigen::Index r = first; r <= last; ++r)
      for (Eigen::Index k = 0; k < from.cols(); k += cols) {
        lo = lo.cwiseMin(x(r, k));
        hi = hi.cwiseMax(x(r, k));
        lightest = std::min(lightest, from(r, k + dim));
      }
    const Point c = 0.5 * (lo + hi);
    double rho = 0, far = 0;
    for (Eigen::Index r = first; r <= last; ++r)
      for (Eigen::Index k = 0; k < from.cols(); k += cols) {
        rho = std::max(rho, (x(r, k) - c).norm());
        far = std::max(far, x(r, k).norm());
      }
    for (Eigen::Index r = first; r <= last; ++r)
      for (Eigen::Index k = 0; k < from.cols(); k += cols) {
        const Point dA = to.row(r).segment(k, dim) - from.row(r).segment(k, dim);
        const double dw = std::abs(to(r, k + dim) - from(r, k + dim));
        const double term =
            std::min(dA.norm() + far * dw, (dA - c * (to(r, k + dim) - from(r, k + dim))).norm() + rho * dw);
        bound = std::max(bound, term / lightest);
      }
  }
  return bound;
}

Removal remove_knot(const Curve& lines, double u, int times, double tolerance, Layout layout) {
  const Curve& c = lines;
  const Eigen::Index cols = layout.cols, dim = cols - (layout.rational ? 1 : 0);
  // Homogeneous tolerance (Piegl–Tiller eq. 5.30) so that the Cartesian curve moves ≤ tolerance.
  double tol_h = tolerance;
  if (layout.rational) {
    double largest = 0, lightest = HUGE_VAL;
    for (Eigen::Index r = 0; r < c.P.rows(); ++r)
      for (Eigen::Index k = 0; k < c.P.cols(); k += cols) {
        const double w = c.P(r, k + dim);
        largest = std::max(largest, c.P.row(r).segment(k, dim).norm() / w);
        lightest = std::min(lightest, w);
      }
    tol_h = tolerance * lightest / (1 + largest);
  }

  // One copy at a time (the equations of Piegl–Tiller A5.8), each solved from both ends and meeting
  // where α crosses 1/2, so that every division is by a weight ≥ 1/2. A5.8 meets in the middle of
  // the index range instead, and next to a knot of high multiplicity one half of it divides by
  // α ≈ 1e-2 at every step: exactly removable knots were refused.
  Curve cur = c;
  int t = 0;
  for (; t < times; ++t) {
    Points next;
    if (!(remove_one(cur.knots, cur.P, c.degree, u, cols, next) <= tol_h)) break;
    cur.knots.erase(std::upper_bound(cur.knots.begin(), cur.knots.end(), u) - 1);
    cur.P = std::move(next);
  }
  if (t == 0) return Removal{c, 0, 0.0};
  Removal result{std::move(cur), t, 0.0};
  if (layout.rational)
    for (Eigen::Index k = dim; k < c.P.cols(); k += cols)
      if (!(result.curve.P.col(k).minCoeff() > 0))  // a weight went non-positive: not a valid curve
        return remove_knot(c, u, t - 1, tolerance, layout);

  // Proof: re-insert the removed copies; the control-point differences bound the curve's motion.
  result.deviation_bound = deviation_bound(c.P, insert_knot(result.curve, u, t).P, c.degree, layout);
  if (!(result.deviation_bound <= tolerance)) return remove_knot(c, u, t - 1, tolerance, layout);
  return result;
}

}  // namespace detail

Removal remove_knot(const Curve& c, double u, int times, double tolerance) {
  if (c.closed) detail::fail("remove: knot removal on closed curves is not supported");
  if (times < 0) detail::fail("remove: times = ", times, " is negative");
  if (!(tolerance >= 0)) detail::fail("remove: tolerance ", tolerance, " must be non-negative");
  const Domain dom = domain(c);
  if (!(u > dom.start && u < dom.end))
    detail::fail("remove: knot ", u, " is not interior to the domain (", dom.start, ", ", dom.end, ")");
  const int s = multiplicity(c.knots, u);
  if (s == 0) detail::fail("remove: ", u, " is not a knot");
  Curve lines = c;
  lines.rational = false;
  Removal result = detail::remove_knot(lines, u, std::min(times, s), tolerance, {c.P.cols(), c.rational});
  result.curve.rational = c.rational;
  return result;
}

namespace detail {

Curve clamped(const Curve& c) {
  const int p = c.degree;
  const Domain dom = domain(c);
  Curve d = c;
  for (const double end : {dom.start, dom.end})
    if (const int has = multiplicity(d.knots, end); has < p) d = insert_knot(d, end, p - has);
  const auto& t = d.knots;
  const auto f = std::lower_bound(t.begin(), t.end(), dom.start) - t.begin();
  const auto l = std::upper_bound(t.begin(), t.end(), dom.end) - t.begin();
  const int first_mult = multiplicity(t, dom.start), last_mult = multiplicity(t, dom.end);
  Knots knots(static_cast<std::size_t>(p) + 1, dom.start);
  knots.insert(knots.end(), t.begin() + f + first_mult, t.begin() + l - last_mult);
  knots.insert(knots.end(), static_cast<std::size_t>(p) + 1, dom.end);
  const Eigen::Index first = f + first_mult - (p + 1);  // the point of N_{f−1} when the start had d copies
  const Eigen::Index count = static_cast<Eigen::Index>(knots.size()) - p - 1;
  return Curve{p, std::move(knots), d.P.middleRows(first, count), d.rational, false};
}

}  // namespace detail

namespace {

/// The Bézier points of degree d − 1 whose elevation is nearest the d + 1 points P when they are an
/// elevation (then exactly): P_i = (i/d)·Q_{i−1} + (1 − i/d)·Q_i solved for Q_0..Q_r from the left and
/// Q_{d−1}..Q_{r+1} from the right (r = ⌊(d − 1)/2⌋: every division by at least ½), the middle point
/// of an odd degree the mean of both sides (Piegl–Tiller eq. 5.41–5.42). Q_0 = P_0 and Q_{d−1} = P_d.
/// Written with integer factors, (d·P_i − i·Q_{i−1}) / (d − i), so that integer points stay exact.
Points reduce_bezier(const Points& P) {
  const auto d = static_cast<int>(P.rows()) - 1;
  const int r = (d - 1) / 2;
  Points Q(d, P.cols());
  Q.row(0) = P.row(0);
  for (int i = 1; i <= r; ++i) Q.row(i) = (d * P.row(i) - i * Q.row(i - 1)) / (d - i);
  Q.row(d - 1) = P.row(d);
  for (int i = d - 2; i > r; --i) Q.row(i) = (d * P.row(i + 1) - (d - i - 1) * Q.row(i + 1)) / (i + 1);
  if (d % 2 == 1 && r > 0)  // Q_r from the right too, and the mean
    Q.row(r) = 0.5 * (Q.row(r) + (d * P.row(r + 1) - (d - r - 1) * Q.row(r + 1)) / (r + 1));
  return Q;
}

/// The curve refined to the union of its knots and `other`'s (the larger multiplicity of each value).
Curve refined_to_union(const Curve& c, const Knots& other) {
  std::vector<double> missing;
  std::set_difference(other.begin(), other.end(), c.knots.begin(), c.knots.end(),
                      std::back_inserter(missing));
  return missing.empty() ? c : refine(c, missing);
}

}  // namespace

namespace detail {

Reduction reduce_degree(const Curve& lines, Layout layout) {
  const Curve original = detail::clamped(lines);
  const int p = original.degree;
  std::vector<Curve> pieces = split_bezier(original);
  for (Curve& piece : pieces) {
    piece.P = reduce_bezier(piece.P);
    piece.degree = p - 1;
    piece.knots.erase(piece.knots.begin());
    piece.knots.pop_back();
  }
  if (layout.rational)
    for (const Curve& piece : pieces)
      for (Eigen::Index k = layout.cols - 1; k < piece.P.cols(); k += layout.cols)
        if (const double w = piece.P.col(k).minCoeff(); !(w > 0))
          fail("a weight of the reduced pieces is ", w, ", not positive");
  // The target knots: every value of the original with one copy less (a simple knot goes).
  Knots target;
  for (std::size_t i = 0; i < original.knots.size(); ++i)
    if (i > 0 && original.knots[i] == original.knots[i - 1]) target.push_back(original.knots[i]);
  // Proof of a candidate: elevated back, it is the original's degree on the original's knots but the simple
  // ones; on the union of both knot vectors they are B-splines of one basis.
  const auto bounded = [&](Curve reduced) {
    const Curve back = refined_to_union(elevate_degree(reduced, 1), original.knots);
    const Curve ref = refined_to_union(original, back.knots);
    const double bound = deviation_bound(ref.P, back.P, p, layout);
    return Reduction{std::move(reduced), bound};
  };
  // Two routes, the smaller proven bound kept. Blossoms: each point of the target knots is the blossom of
  // the reduced piece under the widest interval of its support; exact when the pieces are one spline of
  // the target's continuity (an elevated curve), with no chain of divisions.
  Curve blossoms{p - 1, target, Points(static_cast<Eigen::Index>(target.size()) - p, lines.P.cols()), false,
                 false};
  for (Eigen::Index j = 0; j < blossoms.P.rows(); ++j) {
    auto widest = static_cast<std::size_t>(j);  // the support: intervals j … j + d − 1 of the target
    for (std::size_t k = widest + 1; k < static_cast<std::size_t>(j + p); ++k)
      if (target[k + 1] - target[k] > target[widest + 1] - target[widest]) widest = k;
    const auto piece = static_cast<std::size_t>(
        std::upper_bound(pieces.begin(), pieces.end(), target[widest],
                         [](double t, const Curve& c) { return t < c.knots.front(); }) -
        pieces.begin() - 1);
    const std::span<const double> args(target.data() + j + 1, static_cast<std::size_t>(p - 1));
    blossoms.P.row(j) = blossom(pieces[piece], args, p - 1);
  }
  Reduction best = bounded(std::move(blossoms));
  if (layout.rational)
    for (Eigen::Index k = layout.cols - 1; k < best.curve.P.cols(); k += layout.cols)
      if (!(best.curve.P.col(k).minCoeff() > 0)) best.deviation_bound = HUGE_VAL;
  // Knot removal (Piegl–Tiller A5.11): the pieces joined at their common end points (where the curve jumps,
  // multiplicity d + 1, both stay), then every interior breakpoint of multiplicity m back to m − 1 — it
  // spreads what the pieces disagree by over the removal equations.
  Curve joined{p - 1, Knots(static_cast<std::size_t>(p), original.knots.front()), {}, false, false};
  std::vector<Points> rows;
  Eigen::Index count = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const bool jump = k > 0 && multiplicity(original.knots, pieces[k].knots.front()) > p;
    rows.push_back(k == 0 || jump ? pieces[k].P : pieces[k].P.bottomRows(p - 1));
    count += rows.back().rows();
    if (k > 0)
      joined.knots.insert(joined.knots.end(), static_cast<std::size_t>(jump ? p : p - 1),
                          pieces[k].knots.front());
  }
  joined.knots.insert(joined.knots.end(), static_cast<std::size_t>(p), original.knots.back());
  joined.P.resize(count, lines.P.cols());
  for (Eigen::Index at = 0; const Points& Q : rows) {
    joined.P.middleRows(at, Q.rows()) = Q;
    at += Q.rows();
  }
  Curve cur = std::move(joined);
  for (const double u : breakpoints(original.knots, p)) {
    const int m = multiplicity(original.knots, u);
    if (u == original.knots.front() || u == original.knots.back() || m >= p) continue;
    const Removal removal = remove_knot(cur, u, p - m, HUGE_VAL, layout);
    if (removal.removed < p - m) {  // a weight would become non-positive
      if (best.deviation_bound == HUGE_VAL)
        fail("removing knot ", u, " of the reduced pieces makes a weight non-positive");
      return best;
    }
    cur = removal.curve;
  }
  Reduction removed = bounded(std::move(cur));
  return removed.deviation_bound < best.deviation_bound ? removed : best;
}

}  // namespace detail

Reduction reduce_degree(const Curve& c, double tolerance) {
  if (c.closed) detail::fail("reduce_degree: a closed curve is not supported; cut it open first");
  if (c.degree < 2) detail::fail("reduce_degree: degree ", c.degree, " cannot be reduced (the least is 1)");
  if (!(tolerance >= 0)) detail::fail("reduce_degree: tolerance ", tolerance, " must be non-negative");
  Curve lines = c;
  lines.rational = false;
  Reduction result;
  try {
    result = detail::reduce_degree(lines, {c.P.cols(), c.rational});
  } catch (const InvalidInput& e) {
    detail::fail("reduce_degree: ", e.what());
  }
  if (!(result.deviation_bound <= tolerance))
    detail::fail("reduce_degree: the degree ", c.degree - 1, " curve is within ", result.deviation_bound,
                 " of the curve, more than the tolerance ", tolerance);
  result.curve.rational = c.rational;
  validate(result.curve);
  return result;
}

}  // namespace cifs::nurbs
