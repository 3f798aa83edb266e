// SPDX-License-Identifier: MIT
#include "cifs/nurbs/knots.hpp"

#include <algorithm>
#include <cmath>

#include "cifs/errors.hpp"
#include "detail.hpp"

namespace cifs::nurbs {
using detail::fail;

void validate_degree(int degree, std::string_view where) {
  if (degree < 1 || degree > kMaxDegree)
    fail(where, ": degree ", degree, " is outside [1, ", kMaxDegree, "]");
}

void validate_knots(std::span<const double> knots, int degree, Eigen::Index count, std::string_view where) {
  validate_degree(degree);
  if (count < degree + 1)
    fail(where, ": ", count, " control points are too few for degree ", degree, " (need at least ",
         degree + 1, ")");
  const auto expected = static_cast<std::size_t>(count + degree + 1);
  if (knots.size() != expected)
    fail(where, ": ", knots.size(), " knots given, ", count, " control points of degree ", degree, " need ",
         expected);
  int run = 1;
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) fail(where, "[", i, "]: knot is not finite");
    if (i == 0) continue;
    if (knots[i] < knots[i - 1])
      fail(where, "[", i, "]: ", knots[i], " is less than the previous knot ", knots[i - 1]);
    run = knots[i] == knots[i - 1] ? run + 1 : 1;
    if (run > degree + 1)
      fail(where, "[", i, "]: knot ", knots[i], " has multiplicity ", run, " > degree + 1 = ", degree + 1);
  }
  // Every algorithm works on knot differences (basis functions, blossoms, insertion): they must be
  // finite, or the results are silently wrong (knots ±1e308 evaluated to nonsense).
  if (!std::isfinite(knots.back() - knots.front()))
    fail(where, ": the knots run from ", knots.front(), " to ", knots.back(),
         ", a range wider than a double holds (knot differences must be finite)");
  const Domain dom = domain(knots, degree);
  if (!(dom.start < dom.end))
    fail(where, ": empty domain [t_", degree, ", t_", count, "] = [", dom.start, ", ", dom.end, "]");
}

void validate_span_query(std::span<const double> knots, int degree, int span) {
  if (degree < 0 || degree > kMaxDegree) fail("degree: degree ", degree, " is outside [0, ", kMaxDegree, "]");
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) fail("knots[", i, "]: knot is not finite");
    if (i > 0 && knots[i] < knots[i - 1])
      fail("knots[", i, "]: ", knots[i], " is less than the previous knot ", knots[i - 1]);
  }
  const auto size = static_cast<long long>(knots.size());
  if (span < degree || span + degree >= size || span + 1 >= size)
    fail("span ", span, " is outside ", degree, " … ", std::min(size - 1 - degree, size - 2), " (degree ",
         degree, ", ", size, " knots)");
  if (!(knots[static_cast<std::size_t>(span)] < knots[static_cast<std::size_t>(span) + 1]))
    fail("span ", span, " is empty: knots[", span, "] = knots[", span + 1, "]");
  const auto first = static_cast<std::size_t>(span - degree),
             last = first + 2 * static_cast<std::size_t>(degree);
  if (!std::isfinite(knots[last] - knots[first]))
    fail("knots: the differences around span ", span, " are not finite");
}

Domain domain(std::span<const double> knots, int degree) noexcept {
  const auto n = static_cast<std::size_t>(control_count(knots, degree));
  return {knots[static_cast<std::size_t>(degree)], knots[n]};
}

int find_span(std::span<const double> knots, int degree, double u) noexcept {
  return detail::find_span(knots.data(), degree, static_cast<int>(control_count(knots, degree)), u);
}

int find_span(std::span<const double> knots, int degree, double u, int hint) noexcept {
  const int n = static_cast<int>(control_count(knots, degree));
  if (hint < degree || hint >= n) return find_span(knots, degree, u);
  return detail::find_span(knots.data(), degree, n, u, hint);
}

int multiplicity(std::span<const double> knots, double u) noexcept {
  const auto range = std::equal_range(knots.begin(), knots.end(), u);
  return static_cast<int>(range.second - range.first);
}

std::vector<double> breakpoints(std::span<const double> knots, int degree) {
  const auto n = static_cast<std::size_t>(control_count(knots, degree));
  std::vector<double> out;
  for (std::size_t i = static_cast<std::size_t>(degree); i <= n; ++i)
    if (out.empty() || knots[i] != out.back()) out.push_back(knots[i]);
  return out;
}

void basis_functions(std::span<const double> knots, int degree, int span, double u, double* N) noexcept {
  detail::basis(knots.data(), degree, span, u, N);
}

void blossom_weights(std::span<const double> knots, int degree, int span, std::span<const double> args,
                     double* W) noexcept {
  const double* t = knots.data();
  // The blossom is symmetric; the order of the arguments matters only for rounding. Level j spans
  // [t_{k+1−j+r}, t_{k+1+r}], narrow first: feeding it the arguments nearest the span keeps the
  // factors (hi − x), (x − lo) non-negative as long as possible, instead of large and cancelling.
  // Sorted by (distance, value), a total order: any permutation of the arguments gives the same
  // weights to the last bit, and increasing ones the order of detail::nearest_first_increasing.
  const double a = t[span], b = t[span + 1];
  const auto distance = [a, b](double x) { return x < a ? a - x : (x > b ? x - b : 0.0); };
  const auto before = [&](double x, double y) {
    return distance(x) < distance(y) || (distance(x) == distance(y) && x < y);
  };
  double x[kMaxDegree];
  for (int i = 0; i < degree; ++i) {  // insertion sort: d ≤ 64 values
    const double v = args[static_cast<std::size_t>(i)];
    int j = i;
    for (; j > 0 && before(v, x[j - 1]); --j) x[j] = x[j - 1];
    x[j] = v;
  }
  detail::blossom_recurrence(t, degree, span, x, W);
}

Eigen::MatrixXd basis_derivatives(std::span<const double> knots, int degree, int span, double u, int order) {
  const int p = degree;
  const double* t = knots.data();
  Eigen::MatrixXd ders = Eigen::MatrixXd::Zero(order + 1, p + 1);
  Eigen::MatrixXd ndu(p + 1, p + 1);  // basis values (upper triangle) and knot differences (lower)
  Eigen::VectorXd left(p + 1), right(p + 1);
  ndu(0, 0) = 1.0;
  for (int j = 1; j <= p; ++j) {
    left(j) = u - t[span + 1 - j];
    right(j) = t[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu(j, r) = right(r + 1) + left(j - r);
      const double temp = ndu(r, j - 1) / ndu(j, r);
      ndu(r, j) = saved + right(r + 1) * temp;
      saved = left(j - r) * temp;
    }
    ndu(j, j) = saved;
  }
  for (int j = 0; j <= p; ++j) ders(0, j) = ndu(j, p);
  const int top = std::min(order, p);
  Eigen::MatrixXd a(2, p + 1);
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a(0, 0) = 1.0;
    for (int k = 1; k <= top; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a(s2, 0) = a(s1, 0) / ndu(pk + 1, rk);
        d = a(s2, 0) * ndu(rk, pk);
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a(s2, j) = (a(s1, j) - a(s1, j - 1)) / ndu(pk + 1, rk + j);
        d += a(s2, j) * ndu(rk + j, pk);
      }
      if (r <= pk) {
        a(s2, k) = -a(s1, k - 1) / ndu(pk + 1, r);
        d += a(s2, k) * ndu(r, pk);
      }
      ders(k, r) = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= top; ++k) {
    ders.row(k) *= factor;
    factor *= (p - k);
  }
  return ders;
}

Knots periodic_knots(std::span<const double> b, int degree) {
  const int m = static_cast<int>(b.size()) - 1;
  const double period = b[static_cast<std::size_t>(m)] - b[0];
  const int size = m + 2 * degree + 1;
  Knots t(static_cast<std::size_t>(size));
  auto at = [&](int i) { return b[static_cast<std::size_t>(i)]; };
  auto knot = [&](int j) -> double& { return t[static_cast<std::size_t>(j)]; };
  // The period's knots are the breakpoints as given (b_0 + T may round away from b_m). The copies
  // next to it are measured from b_0 backwards and from b_m forwards, so that a breakpoint equal to
  // b_m lands exactly on b_0 and one equal to b_0 exactly on b_m: the seam keeps its multiplicity.
  // Further copies shift the neighbouring period by T, which keeps equal knots equal and the order.
  for (int j = 0; j < size; ++j) {
    const int s = j - degree;
    if (s >= 0 && s <= m)
      knot(j) = at(s);
    else if (s < 0 && s >= -m)
      knot(j) = at(0) - (at(m) - at(s + m));
    else if (s > m && s <= 2 * m)
      knot(j) = at(m) + (at(s - m) - at(0));
  }
  for (int j = degree - m - 1; j >= 0; --j) knot(j) = knot(j + m) - period;
  for (int j = degree + 2 * m + 1; j < size; ++j) knot(j) = knot(j - m) + period;
  return t;
}

}  // namespace cifs::nurbs
