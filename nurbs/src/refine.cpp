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
/// consecutive target knots t'_{j+1..j+q}, symmetrised over the dropped argument when raised.
void set_blossom_point(const Curve& c, const Knots& target, int raise, Eigen::Index j, Points& Q) {
  const int p = c.degree;
  const int q = p + raise;
  const auto tn = static_cast<int>(target.size());
  const int jj = static_cast<int>(j);
  // A non-empty target interval in the support of N_j within the domain, else the nearest one.
  int k = std::max(jj, q);
  const int k_end = std::min(jj + q, tn - q - 2);
  while (k < k_end && !(target[static_cast<std::size_t>(k)] < target[static_cast<std::size_t>(k + 1)])) ++k;
  const Piece piece =
      piece_for(c, target[static_cast<std::size_t>(k)], target[static_cast<std::size_t>(k + 1)]);
  double args[kMaxDegree + 1], sub[kMaxDegree], W[kMaxDegree + 1];
  for (int a = 0; a < q; ++a) args[a] = target[static_cast<std::size_t>(jj + 1 + a)] + piece.shift;
  Q.row(j).setZero();
  for (int drop = 0; drop < (raise ? q : 1); ++drop) {
    for (int a = 0, b = 0; a < q; ++a)
      if (!raise || a != drop) sub[b++] = args[a];
    blossom_weights(c.knots, p, piece.span, std::span<const double>(sub, static_cast<std::size_t>(p)), W);
    for (int i = 0; i <= p; ++i) Q.row(j) += W[i] * c.P.row(piece.span - p + i);
  }
  if (raise) Q.row(j) /= q;
}

Points blossom_points(const Curve& c, const Knots& target, int raise, Eigen::Index count) {
  Points Q(count, c.P.cols());
  for (Eigen::Index j = 0; j < count; ++j) set_blossom_point(c, target, raise, j, Q);
  return Q;
}

/// Closed curve on new breakpoints (a refinement or elevation of its period).
Curve closed_on(const Curve& c, const Knots& breaks, int raise) {
  const int q = c.degree + raise;
  const auto m = static_cast<Eigen::Index>(breaks.size()) - 1;
  Curve out{q, periodic_knots(breaks, q), {}, c.rational, true};
  const Points distinct = blossom_points(c, out.knots, raise, m);
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
  // Open curve: merge (new knots after equal old ones), copy the points whose dual-functional
  // arguments are all old knots, compute the others as blossoms.
  const int p = c.degree;
  const auto n = c.P.rows();
  Knots target(c.knots.size() + X.size());
  std::vector<int> new_before(target.size() + 1, 0);  // new knots among target[0..i)
  {
    std::size_t a = 0, b = 0;
    for (std::size_t i = 0; i < target.size(); ++i) {
      const bool take_new = b < X.size() && (a == c.knots.size() || X[b] < c.knots[a]);
      target[i] = take_new ? X[b++] : c.knots[a++];
      new_before[i + 1] = new_before[i] + (take_new ? 1 : 0);
    }
  }
  check_multiplicities(target, X, p);
  const auto count = n + static_cast<Eigen::Index>(X.size());
  Curve out{p, target, Points(count, c.P.cols()), c.rational, false};
  for (Eigen::Index j = 0; j < count; ++j) {
    const auto first = static_cast<std::size_t>(j + 1), last = static_cast<std::size_t>(j + p + 1);
    if (new_before[last] == new_before[first])
      out.P.row(j) = c.P.row(j - new_before[first]);  // args t'_{j+1..j+p} are old knots t_{i+1..i+p}
    else
      set_blossom_point(c, target, 0, j, out.P);
  }
  return out;
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
    // Every knot value of the domain gains one in multiplicity (the ends too); knots outside the
    // domain stay, which keeps the domain at indices [d+1, n'].
    const Domain dom = domain(out);
    if (out.closed) {
      Knots breaks = defining_knots(out);
      Knots raised;
      for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
        raised.push_back(breaks[i]);
        if (i == 0 || breaks[i] != breaks[i - 1]) raised.push_back(breaks[i]);
      }
      raised.push_back(breaks.back());
      out = closed_on(out, raised, 1);
      continue;
    }
    Knots raised;
    for (std::size_t i = 0; i < out.knots.size(); ++i) {
      const double t = out.knots[i];
      raised.push_back(t);
      const bool last_copy = i + 1 == out.knots.size() || out.knots[i + 1] != t;
      if (last_copy && t >= dom.start && t <= dom.end) raised.push_back(t);
    }
    const auto count = static_cast<Eigen::Index>(raised.size()) - (out.degree + 1) - 1;
    Points Q = blossom_points(out, raised, 1, count);
    out = Curve{out.degree + 1, std::move(raised), std::move(Q), out.rational, false};
  }
  return out;
}

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

  // Piegl–Tiller A5.8 on a copy.
  const int r = static_cast<int>(std::upper_bound(c.knots.begin(), c.knots.end(), u) - c.knots.begin()) - 1;
  const int n = static_cast<int>(c.P.rows()) - 1, m = n + p + 1, ord = p + 1;
  const int fout = (2 * r - s - p) / 2;
  int first = r - p, last = r - s, t = 0;
  Points P = c.P;
  Points temp(2 * p + 1, P.cols());
  for (t = 0; t < times; ++t) {
    const int off = first - 1;
    temp.row(0) = P.row(off);
    temp.row(last + 1 - off) = P.row(last + 1);
    int i = first, j = last, ii = 1, jj = last - off;
    const double* U = c.knots.data();
    while (j - i > t) {
      const double alfi = (u - U[i]) / (U[i + ord + t] - U[i]);
      const double alfj = (u - U[j - t]) / (U[j + ord] - U[j - t]);
      temp.row(ii) = (P.row(i) - (1.0 - alfi) * temp.row(ii - 1)) / alfi;
      temp.row(jj) = (P.row(j) - alfj * temp.row(jj + 1)) / (1.0 - alfj);
      ++i, ++ii, --j, --jj;
    }
    bool removable;
    if (j - i < t) {
      removable = (temp.row(ii - 1) - temp.row(jj + 1)).norm() <= tol_h;
    } else {
      const double alfi = (u - U[i]) / (U[i + ord + t] - U[i]);
      removable =
          (P.row(i) - (alfi * temp.row(ii + t + 1) + (1.0 - alfi) * temp.row(ii - 1))).norm() <= tol_h;
    }
    if (!removable) break;
    i = first, j = last;
    while (j - i > t) {
      P.row(i) = temp.row(i - off);
      P.row(j) = temp.row(j - off);
      ++i, --j;
    }
    --first, ++last;
  }
  // Assemble the shorter curve: t knots and t points fewer.
  Knots knots = c.knots;
  for (int k = r + 1; k <= m; ++k)
    knots[static_cast<std::size_t>(k - t)] = knots[static_cast<std::size_t>(k)];
  knots.resize(knots.size() - static_cast<std::size_t>(t));
  int j = fout, i = fout;
  for (int k = 1; k < t; ++k) (k % 2 == 1) ? ++i : --j;
  for (int k = i + 1; k <= n; ++k) P.row(j++) = P.row(k);
  Removal result{Curve{p, std::move(knots), P.topRows(n + 1 - t), c.rational, false}, t, 0.0};
  if (t == 0) return result;

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
