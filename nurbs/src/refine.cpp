// SPDX-License-Identifier: MIT
#include "cifs/nurbs/refine.hpp"

#include <algorithm>
#include <cmath>

#include "detail.hpp"

namespace cifs::nurbs {
namespace {

/// The old piece that covers the new interval [lo, hi] (a refinement keeps the pieces): its span
/// and the shift, a whole number of periods for closed curves, that brings the interval there.
struct Piece {
  int span;
  double shift;
};

Piece piece_for(const Curve& c, double lo, double hi) {
  const Domain dom = domain(c);
  double mid = 0.5 * (lo + hi);
  double shift = 0;
  if (c.closed) {
    shift = domain_parameter(c, mid) - mid;
    mid += shift;
  }
  return {find_span(c.knots, c.degree, std::min(std::max(mid, dom.start), dom.end)), shift};
}

/// Row j of the control points of the same piecewise polynomial, seen with degree `c.degree + raise`
/// (raise ∈ {0, 1}) on `target`, a knot vector whose pieces are pieces of `c`: the blossom at the
/// consecutive target knots t'_{j+1..j+q}, symmetrised over the dropped argument when raised, written
/// to Q.row(row). The piece is one under an interval of the support of N'_j (open curves: within the
/// target's domain).
void set_blossom_point(const Curve& c, const Knots& target, int raise, Eigen::Index j, Points& Q,
                       Eigen::Index row) {
  const int p = c.degree;
  const int q = p + raise;
  const auto tn = static_cast<int>(target.size());
  const int jj = static_cast<int>(j);
  // Closed curves: closed_on picks a copy j of the point whose support starts with an interval of
  // the period, so that no shift by whole periods (which rounds the arguments) is needed.
  // Any piece of the support gives the same blossom, but not the same rounding: a piece evaluated
  // far outside its own interval amplifies errors by (distance / width)^d. Take the widest.
  const int k_begin = c.closed ? jj : std::max(jj, q);
  const int k_end = std::min(jj + q, c.closed ? tn - 2 : tn - q - 2);
  const auto at = [&](int i) { return target[static_cast<std::size_t>(i)]; };
  Piece piece{-1, 0.0};
  double widest = -1;
  for (int k = k_begin; k <= k_end; ++k) {
    if (!(at(k) < at(k + 1)) && !(k == k_end && piece.span < 0)) continue;
    const Piece candidate = piece_for(c, at(k), at(k + 1));
    const double width = c.knots[static_cast<std::size_t>(candidate.span + 1)] -
                         c.knots[static_cast<std::size_t>(candidate.span)];
    if (width > widest) piece = candidate, widest = width;
  }
  double args[kMaxDegree + 1], sub[kMaxDegree], W[kMaxDegree + 1];
  for (int a = 0; a < q; ++a) args[a] = target[static_cast<std::size_t>(jj + 1 + a)] + piece.shift;
  Q.row(row).setZero();
  for (int drop = 0; drop < (raise ? q : 1); ++drop) {
    for (int a = 0, b = 0; a < q; ++a)
      if (!raise || a != drop) sub[b++] = args[a];
    blossom_weights(c.knots, p, piece.span, std::span<const double>(sub, static_cast<std::size_t>(p)), W);
    for (int i = 0; i <= p; ++i) Q.row(row) += W[i] * c.P.row(piece.span - p + i);
  }
  if (raise) Q.row(row) /= q;
}

Points blossom_points(const Curve& c, const Knots& target, int raise, Eigen::Index count) {
  Points Q(count, c.P.cols());
  for (Eigen::Index j = 0; j < count; ++j) set_blossom_point(c, target, raise, j, Q, j);
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
  for (Eigen::Index j = 0; j < m; ++j) {
    Eigen::Index row = j < q ? j + m * ((q - j + m - 1) / m) : j;
    Eigen::Index k = row;
    while (k < std::min(row + q, tn - 2) &&
           !(t[static_cast<std::size_t>(k)] < t[static_cast<std::size_t>(k + 1)]))
      ++k;
    if (k > m + q - 1) row -= m;
    set_blossom_point(c, t, raise, row, distinct, j);
  }
  out.P.resize(m + q, c.P.cols());
  for (Eigen::Index i = 0; i < out.P.rows(); ++i) out.P.row(i) = distinct.row(i % m);
  return out;
}

/// Sorted insertion knots, validated against the curve (closed curves: wrapped into the period).
std::vector<double> checked_insertions(const Curve& c, std::span<const double> new_knots) {
  std::vector<double> X;
  X.reserve(new_knots.size());
  for (std::size_t i = 0; i < new_knots.size(); ++i) {
    if (!std::isfinite(new_knots[i])) detail::fail("knot ", i, ": ", new_knots[i], " is not finite");
    const Domain dom = domain(c);
    if (!c.closed && (new_knots[i] < dom.start || new_knots[i] > dom.end))
      detail::fail("knot ", new_knots[i], " is outside the domain [", dom.start, ", ", dom.end, "]");
    double u = domain_parameter(c, new_knots[i]);
    if (c.closed && u == dom.end) u = dom.start;  // the period's end is its start
    X.push_back(u);
  }
  std::sort(X.begin(), X.end());
  return X;
}

void check_multiplicities(std::span<const double> knots, std::span<const double> inserted, int degree) {
  for (double u : inserted) {
    const int mult = multiplicity(knots, u);
    if (mult > degree) detail::fail("knot ", u, " would reach multiplicity ", mult, " > degree ", degree);
  }
}

}  // namespace

Curve refine(const Curve& c, std::span<const double> new_knots) {
  const std::vector<double> X = checked_insertions(c, new_knots);
  if (X.empty()) return c;
  if (c.closed) {
    Knots breaks = defining_knots(c);
    breaks.insert(breaks.end() - 1, X.begin(), X.end());
    std::sort(breaks.begin(), breaks.end() - 1);
    Curve out = closed_on(c, breaks, 0);
    check_multiplicities(out.knots, X, c.degree);
    return out;
  }
  // Open curve. Every new point is the blossom of an old piece at consecutive new knots, computed
  // on its own (Oslo's accuracy: no chain of updates through many insertions, whose rounding grows
  // with their number). To preserve Σ P_i N_i on the whole knot range, as Boehm's insertion does,
  // also where the basis functions of an unclamped curve vanish on the domain, the knot vector is
  // padded with d knots and d zero points on each side: the pads add nothing to the sum, and every
  // original interval becomes part of the padded domain, where blossoms are defined.
  const int p = c.degree;
  {
    Knots merged(c.knots.size() + X.size());
    std::merge(c.knots.begin(), c.knots.end(), X.begin(), X.end(), merged.begin());
    check_multiplicities(merged, X, p);
  }
  const double front = c.knots.front(), back = c.knots.back();
  const double pad = back > front ? back - front : 1.0;
  Curve padded{p, Knots{}, Points::Zero(c.P.rows() + 2 * p, c.P.cols()), c.rational, false};
  for (int i = p; i >= 1; --i) padded.knots.push_back(front - i * pad);
  padded.knots.insert(padded.knots.end(), c.knots.begin(), c.knots.end());
  for (int i = 1; i <= p; ++i) padded.knots.push_back(back + i * pad);
  padded.P.middleRows(p, c.P.rows()) = c.P;

  // Merge (new knots after equal old ones), copy the points whose dual-functional arguments are
  // all old knots, compute the others.
  const auto n = padded.P.rows();
  Knots target(padded.knots.size() + X.size());
  std::vector<int> new_before(target.size() + 1, 0);  // new knots among target[0..i)
  for (std::size_t a = 0, b = 0, i = 0; i < target.size(); ++i) {
    const bool take_new = b < X.size() && (a == padded.knots.size() || X[b] < padded.knots[a]);
    target[i] = take_new ? X[b++] : padded.knots[a++];
    new_before[i + 1] = new_before[i] + (take_new ? 1 : 0);
  }
  const auto count = n + static_cast<Eigen::Index>(X.size());
  Points Q(count, c.P.cols());
  for (Eigen::Index j = 0; j < count; ++j) {
    const auto first = static_cast<std::size_t>(j + 1), last = static_cast<std::size_t>(j + p + 1);
    if (new_before[last] == new_before[first])
      Q.row(j) = padded.P.row(j - new_before[first]);  // args t'_{j+1..j+p} are old knots t_{i+1..i+p}
    else
      set_blossom_point(padded, target, 0, j, Q, j);
  }
  return Curve{p, Knots(target.begin() + p, target.end() - p), Q.middleRows(p, count - 2 * p), c.rational,
               false};
}

Curve insert_knot(const Curve& c, double u, int times) {
  if (times < 1) detail::fail("insert: times = ", times, " must be at least 1");
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
    const double a = c.knots[static_cast<std::size_t>(k)], b = c.knots[static_cast<std::size_t>(k + 1)];
    if (!(a < b)) continue;
    Curve piece{p, Knots(static_cast<std::size_t>(2 * p + 2), a), Points(p + 1, c.P.cols()), c.rational,
                false};
    std::fill(piece.knots.begin() + p + 1, piece.knots.end(), b);
    for (int r = 0; r <= p; ++r) {  // Bézier point r = blossom(a^{p−r}, b^r)
      std::fill(args.begin(), args.end() - r, a);
      std::fill(args.end() - r, args.end(), b);
      piece.P.row(r) = detail::blossom_row(c.knots, p, c.P, args, k);
    }
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

Curve elevate_degree(const Curve& c, int times) {
  if (times < 0) detail::fail("elevate: times = ", times, " is negative");
  if (c.degree + times > kMaxDegree)
    detail::fail("elevate: degree ", c.degree + times, " exceeds the maximum ", kMaxDegree);
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
              Points::Zero(out.P.rows() + 2 * d, out.P.cols()), out.rational, false};
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
/// residual of the equation left over, in stored coordinates. Boehm's insertion of u into the
/// shorter vector V gives P_i = α_i Q_i + (1 − α_i) Q_{i−1}, α_i = (u − V_i)/(V_{i+p} − V_i), for i in
/// [k−p+1, k−s+1] (k = r − 1, r the last copy of u, s its multiplicity), with Q_i = P_i before and
/// Q_i = P_{i+1} after. α decreases with i: equations with α ≥ 1/2 are solved for Q_i from the left,
/// the others for Q_{i−1} from the right, and the first one with α < 1/2 is the check.
double remove_one(const Knots& U, const Points& P, int p, double u, Points& Q) {
  const int r = static_cast<int>(std::upper_bound(U.begin(), U.end(), u) - U.begin()) - 1;
  const int s = multiplicity(U, u);
  const int k = r - 1, lo = k - p + 1, hi = k - s + 1;  // equations lo..hi
  Knots V = U;
  V.erase(V.begin() + r);
  auto alpha = [&](int i) {
    const double a = V[static_cast<std::size_t>(i)], b = V[static_cast<std::size_t>(i + p)];
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
  return (P.row(check) - a * Q.row(check) - (1 - a) * Q.row(check - 1)).norm();
}

}  // namespace

Removal remove_knot(const Curve& c, double u, int times, double tolerance) {
  if (c.closed) detail::fail("remove: knot removal on closed curves is not supported");
  if (times < 0) detail::fail("remove: times = ", times, " is negative");
  if (!(tolerance >= 0)) detail::fail("remove: tolerance ", tolerance, " must be non-negative");
  const int p = c.degree;
  const Domain dom = domain(c);
  if (!(u > dom.start && u < dom.end))
    detail::fail("remove: knot ", u, " is not interior to the domain (", dom.start, ", ", dom.end, ")");
  const int s = multiplicity(c.knots, u);
  if (s == 0) detail::fail("remove: ", u, " is not a knot");
  times = std::min(times, s);

  // Homogeneous tolerance (Piegl–Tiller eq. 5.30) so that the Cartesian curve moves ≤ tolerance.
  const Points cart = cartesian_points(c);
  const Eigen::VectorXd w = weights(c);
  const double max_norm = cart.rowwise().norm().maxCoeff();
  const double tol_h = c.rational ? tolerance * w.minCoeff() / (1 + max_norm) : tolerance;

  // One copy at a time (the equations of Piegl–Tiller A5.8), each solved from both ends and meeting
  // where α crosses 1/2, so that every division is by a weight ≥ 1/2. A5.8 meets in the middle of
  // the index range instead, and next to a knot of high multiplicity one half of it divides by
  // α ≈ 1e-2 at every step: exactly removable knots were refused.
  Curve cur = c;
  int t = 0;
  for (; t < times; ++t) {
    Points next;
    if (remove_one(cur.knots, cur.P, p, u, next) > tol_h) break;
    cur.knots.erase(std::upper_bound(cur.knots.begin(), cur.knots.end(), u) - 1);
    cur.P = std::move(next);
  }
  if (t == 0) return Removal{c, 0, 0.0};
  Removal result{std::move(cur), t, 0.0};
  if (c.rational && !(result.curve.P.col(result.curve.P.cols() - 1).minCoeff() > 0))
    return remove_knot(c, u, t - 1, tolerance);  // a weight went non-positive: not a valid curve

  // Proof: re-insert the removed copies; the control-point differences bound the curve's motion.
  const Curve back = insert_knot(result.curve, u, t);
  const Points diff = back.P - c.P;
  if (c.rational) {
    const int dim = dimension(c);
    const double dA = diff.leftCols(dim).rowwise().norm().maxCoeff();
    const double dw = diff.col(dim).cwiseAbs().maxCoeff();
    const double max_new = cartesian_points(result.curve).rowwise().norm().maxCoeff();
    result.deviation_bound = (dA + max_new * dw) / w.minCoeff();
  } else {
    result.deviation_bound = diff.rowwise().norm().maxCoeff();
  }
  if (result.deviation_bound > tolerance) return remove_knot(c, u, t - 1, tolerance);
  return result;
}

}  // namespace cifs::nurbs
