// SPDX-License-Identifier: MIT
#include "cifs/nurbs/fit.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include "detail.hpp"

namespace cifs::nurbs {
namespace {

using Sparse = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

void check_points(const Points& points, std::string_view where) {
  if (points.cols() < 1) detail::fail(where, ": points have no coordinates");
  if (points.allFinite()) return;  // one vectorised pass; the loop below names the culprit
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (Eigen::Index j = 0; j < points.cols(); ++j)
      if (!std::isfinite(points(i, j))) detail::fail(where, "[", i, "][", j, "]: coordinate is not finite");
}

/// The rows of the basis functions of a clamped knot vector at the parameters, as triplets (row k,
/// column span − p + j) starting at row `first`.
void collocation_rows(const Knots& t, int p, std::span<const double> params, int first, Triplets& out) {
  double N[kMaxDegree + 1];
  for (std::size_t k = 0; k < params.size(); ++k) {
    const int span = find_span(t, p, params[k]);
    basis_functions(t, p, span, params[k], N);
    for (int j = 0; j <= p; ++j)
      if (N[j] != 0) out.emplace_back(first + static_cast<int>(k), span - p + j, N[j]);
  }
}

/// A square collocation matrix by rows: row r holds `count[r]` values from column `first[r]` on (at most
/// `stride` of them: the p + 1 basis functions of a span, or the two entries of an end derivative), the
/// columns taken modulo n (the wrapped rows of a closed curve).
struct Runs {
  Eigen::Index n = 0;
  int stride = 0;
  std::vector<Eigen::Index> first;
  std::vector<int> count;
  std::vector<double> values;  // row r at r·stride

  Runs(Eigen::Index size, int width)
      : n(size),
        stride(width),
        first(static_cast<std::size_t>(size)),
        count(static_cast<std::size_t>(size)),
        values(static_cast<std::size_t>(size * width)) {}
  double* row(Eigen::Index r) { return values.data() + r * stride; }
  const double* row(Eigen::Index r) const { return values.data() + r * stride; }

  /// out ← B − A·X (all `n by cols`, row-major).
  void residual(const Points& B, const Points& X, Points& out) const {
    const Eigen::Index cols = B.cols();
    out = B;
    for (Eigen::Index r = 0; r < n; ++r) {
      double* o = out.data() + r * cols;
      for (int j = 0; j < count[static_cast<std::size_t>(r)]; ++j) {
        const double a = row(r)[j];
        const double* x = X.data() + ((first[static_cast<std::size_t>(r)] + j) % n) * cols;
        for (Eigen::Index c = 0; c < cols; ++c) o[c] -= a * x[c];
      }
    }
  }

  Sparse sparse() const {
    Triplets entries;
    for (Eigen::Index r = 0; r < n; ++r)
      for (int j = 0; j < count[static_cast<std::size_t>(r)]; ++j)
        entries.emplace_back(r, (first[static_cast<std::size_t>(r)] + j) % n, row(r)[j]);
    Sparse A(n, n);
    A.setFromTriplets(entries.begin(), entries.end());
    return A;
  }
};

/// LU factors of a band matrix without pivoting: the collocation matrices of B-splines are totally
/// positive (de Boor), so Gaussian elimination needs no row exchanges, and the factors keep the band
/// (kl below, ku above the diagonal). Row i keeps columns i − kl … i + ku.
class BandLU {
 public:
  /// False when the matrix is not a narrow band or a pivot is not clearly non-zero (then another
  /// solver is needed).
  bool factor(const Runs& A) {
    n_ = A.n;
    for (Eigen::Index r = 0; r < n_; ++r) {
      const Eigen::Index f = A.first[static_cast<std::size_t>(r)],
                         l = f + A.count[static_cast<std::size_t>(r)] - 1;
      if (l >= n_) return false;  // a wrapped row
      kl_ = std::max(kl_, r - f);
      ku_ = std::max(ku_, l - r);
    }
    w_ = kl_ + ku_ + 1;
    if (w_ > 2 * kMaxDegree + 3) return false;
    band_.assign(static_cast<std::size_t>(n_ * w_), 0.0);
    for (Eigen::Index r = 0; r < n_; ++r) {
      double size = 0;
      for (int j = 0; j < A.count[static_cast<std::size_t>(r)]; ++j) {
        at(r, A.first[static_cast<std::size_t>(r)] + j) = A.row(r)[j];
        size = std::max(size, std::abs(A.row(r)[j]));
      }
      // Row r is final when its turn comes; its entries left of the diagonal are eliminated first.
      for (Eigen::Index k = std::max<Eigen::Index>(0, r - kl_); k < r; ++k) {
        const double l = at(r, k) / at(k, k);
        at(r, k) = l;
        if (l != 0)
          for (Eigen::Index j = k + 1; j <= std::min(n_ - 1, k + ku_); ++j) at(r, j) -= l * at(k, j);
      }
      if (!(std::abs(at(r, r)) > 1e-12 * size)) return false;
    }
    return true;
  }
  /// X ← A⁻¹ X, in place (`n by cols`, row-major).
  void solve(Points& X) const {
    const Eigen::Index cols = X.cols();
    double* x = X.data();
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index k = std::max<Eigen::Index>(0, i - kl_); k < i; ++k) {
        const double l = at(i, k);
        for (Eigen::Index c = 0; c < cols; ++c) x[i * cols + c] -= l * x[k * cols + c];
      }
    for (Eigen::Index i = n_ - 1; i >= 0; --i) {
      for (Eigen::Index j = i + 1; j <= std::min(n_ - 1, i + ku_); ++j) {
        const double u = at(i, j);
        for (Eigen::Index c = 0; c < cols; ++c) x[i * cols + c] -= u * x[j * cols + c];
      }
      const double d = at(i, i);
      for (Eigen::Index c = 0; c < cols; ++c) x[i * cols + c] /= d;
    }
  }

 private:
  double& at(Eigen::Index i, Eigen::Index j) { return band_[static_cast<std::size_t>(i * w_ + j - i + kl_)]; }
  double at(Eigen::Index i, Eigen::Index j) const {
    return band_[static_cast<std::size_t>(i * w_ + j - i + kl_)];
  }
  Eigen::Index n_ = 0, kl_ = 0, ku_ = 0, w_ = 1;
  std::vector<double> band_;
};

/// Solves A X = B: band LU without pivoting for the (totally positive) collocation matrix of an open
/// curve, else sparse LU with pivoting and one step of iterative refinement (the cyclic matrices of
/// closed curves are not totally positive; or a pivot was too small).
Points solve_collocation(const Runs& A, Points B, std::string_view what) {
  BandLU band;
  if (band.factor(A)) {
    band.solve(B);
    if (!B.allFinite()) detail::fail(what, ": the interpolation system is singular");
    return B;  // no refinement: elimination without pivoting is backward stable on these matrices
  }
  Eigen::SparseLU<Sparse> lu;
  lu.compute(A.sparse());
  if (lu.info() != Eigen::Success) detail::fail(what, ": the interpolation system is singular");
  Points X = Eigen::MatrixXd(lu.solve(Eigen::MatrixXd(B))), residual;
  A.residual(B, X, residual);
  X += Points(Eigen::MatrixXd(lu.solve(Eigen::MatrixXd(residual))));
  if (!X.allFinite()) detail::fail(what, ": the interpolation system is singular");
  return X;
}

/// Schoenberg–Whitney for a least-squares fit: an increasing choice of data parameters, one inside the
/// support of each basis function (t_j < u < t_{j+p+1}, or the clamped end). The supports' ends both
/// increase with j, so the greedy choice finds one when there is one.
bool schoenberg_whitney(const Knots& t, int p, std::span<const double> params) {
  const Eigen::Index n = control_count(t, p);
  const Domain dom = domain(t, p);
  std::size_t k = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double lo = t[static_cast<std::size_t>(j)], hi = t[static_cast<std::size_t>(j + p + 1)];
    const auto inside = [&](double u) {
      return (lo < u && u < hi) || (j == 0 && u == dom.start) || (j == n - 1 && u == dom.end);
    };
    while (k < params.size() && !inside(params[k])) {
      if (params[k] >= hi) return false;
      ++k;
    }
    if (k == params.size()) return false;
    ++k;
  }
  return true;
}

/// Least-squares control points on the knots `t` for data Q at `params` with weights w (empty: 1);
/// fixed ends: P_0 = Q_0 and P_{n−1} = Q_{m−1} (The NURBS Book A9.7). Normal equations by sparse LDLT.
Points least_squares(const Knots& t, int p, std::span<const double> params, const Points& Q,
                     const Eigen::VectorXd& w, bool fix_ends) {
  const Eigen::Index n = control_count(t, p);
  const auto m = static_cast<Eigen::Index>(params.size());
  if (!schoenberg_whitney(t, p, params))
    detail::fail("points: the data parameters do not meet the Schoenberg–Whitney condition for ", n,
                 " control points of degree ", p);
  Triplets triplets;
  collocation_rows(t, p, params, 0, triplets);
  Sparse A(m, n);
  A.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::Index first = fix_ends ? 1 : 0, free = fix_ends ? n - 2 : n;
  Points P(n, Q.cols());
  if (fix_ends) {
    P.row(0) = Q.row(0);
    P.row(n - 1) = Q.row(m - 1);
  }
  if (free <= 0) return P;
  Eigen::MatrixXd R = Q;
  if (fix_ends) R -= Eigen::VectorXd(A.col(0)) * Q.row(0) + Eigen::VectorXd(A.col(n - 1)) * Q.row(m - 1);
  const Sparse Af = A.middleCols(first, free);
  Sparse AtW = Af.transpose();
  if (w.size() > 0) AtW = AtW * w.asDiagonal();
  const Sparse M = AtW * Af;
  Eigen::SimplicialLDLT<Sparse> ldlt(M);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0))
    detail::fail("points: the least-squares system for ", n, " control points is singular");
  // Normal equations, then one correction from the residual of the data (the corrected semi-normal
  // equations: accuracy close to a QR's when the fit is near interpolation).
  Eigen::MatrixXd X = ldlt.solve(Eigen::MatrixXd(AtW * R));
  X += ldlt.solve(Eigen::MatrixXd(AtW * (R - Af * X)));
  P.middleRows(first, free) = X;
  if (!P.allFinite()) detail::fail("points: the least-squares system for ", n, " control points is singular");
  return P;
}

void check_fit_degree(int degree, Eigen::Index needed, Eigen::Index given, std::string_view what) {
  validate_degree(degree);
  if (given < needed)
    detail::fail("points: ", what, " of degree ", degree, " needs at least ", needed, " points, got ", given);
}

/// The open collocation system (below) streamed through band LU without pivoting: row r (columns
/// r − p … r + p: the column of a row's own point is in its span's run, Schoenberg–Whitney) is filled,
/// eliminated against the rows before it and its right-hand side forward-substituted while it is in
/// cache; then one back substitution. False when a pivot is not clearly non-zero.
template <int Cols, int P>
bool banded_interpolation(const Knots& t, int p, std::span<const double> params, const Points& Q,
                          const Point& d0, const Point& d1, Points& X) {
  const auto m = static_cast<Eigen::Index>(params.size());
  const bool s = d0.size() > 0, e = d1.size() > 0;
  const Eigen::Index n = m + s + e, cols = Cols > 0 ? Cols : Q.cols();
  const int q = P > 0 ? P : p;  // fixed bounds unroll every loop below
  const int w = 2 * q + 1;
  std::unique_ptr<double[]> band(new double[static_cast<std::size_t>(n * w)]);
  std::unique_ptr<double[]> inverse(new double[static_cast<std::size_t>(n)]);
  X.resize(n, cols);
  double* x = X.data();
  Eigen::Index row = 0;
  int span = q;
  const double* knots = t.data();
  const auto finish_row = [&](double size) {
    double* a = band.get() + row * w;  // a[c − row + q] = A(row, c)
    double* xr = x + row * cols;
    // Rows before the first are skipped; columns past n − 1 are zeros of the band on both sides.
    for (Eigen::Index i = std::min<Eigen::Index>(row, q); i > 0; --i) {  // row k = row − i
      const double l = a[q - i] * inverse[static_cast<std::size_t>(row - i)];
      const double* ak = band.get() + (row - i) * w;
      for (int c = 1; c <= q; ++c) a[c - i + q] -= l * ak[c + q];
      const double* xk = x + (row - i) * cols;
      for (Eigen::Index c = 0; c < cols; ++c) xr[c] -= l * xk[c];
    }
    const double pivot = a[q];
    if (!(std::abs(pivot) > 1e-12 * size)) return false;
    inverse[static_cast<std::size_t>(row++)] = 1 / pivot;
    return true;
  };
  const auto add_point = [&](Eigen::Index k) {
    const double u = params[static_cast<std::size_t>(k)];
    // Sorted parameters: walk forward (averaged knots put a point one or two spans past the last).
    while (span + 1 < n && knots[span + 1] <= u && knots[span + 1] < knots[n]) ++span;
    double* a = band.get() + row * w;
    const Eigen::Index first = span - q;
    if (first < row - q || span > row + q) return false;  // outside the band: not this solver's system
    std::fill_n(a, w, 0.0);
    detail::basis<P>(knots, q, span, u, a + (first - row + q));
    std::copy_n(Q.data() + k * cols, cols, x + row * cols);
    return finish_row(1.0);
  };
  const auto add_derivative = [&](Eigen::Index first, double h, const Point& D) {
    double* a = band.get() + row * w;
    std::fill_n(a, w, 0.0);
    a[first - row + q] = -q / h;
    a[first + 1 - row + q] = q / h;
    std::copy_n(D.data(), cols, x + row * cols);
    return finish_row(q / h);
  };
  if (!add_point(0)) return false;
  if (s && !add_derivative(0, t[static_cast<std::size_t>(q) + 1] - t[0], d0)) return false;
  for (Eigen::Index k = 1; k + 1 < m; ++k)
    if (!add_point(k)) return false;
  if (e &&
      !add_derivative(n - 2, t[static_cast<std::size_t>(n + q)] - t[static_cast<std::size_t>(n - 1)], d1))
    return false;
  if (!add_point(m - 1)) return false;
  for (Eigen::Index r = n - 1; r >= 0; --r) {
    const double* a = band.get() + r * w;
    double* xr = x + r * cols;
    for (Eigen::Index c = r + 1; c <= std::min(n - 1, r + q); ++c) {
      const double* xc = x + c * cols;
      for (Eigen::Index d = 0; d < cols; ++d) xr[d] -= a[c - r + q] * xc[d];
    }
    for (Eigen::Index d = 0; d < cols; ++d) xr[d] *= inverse[static_cast<std::size_t>(r)];
  }
  return X.allFinite();
}

/// Open interpolation: control points on averaged knots through Q at params, with optional end
/// derivatives (rows P_1 − P_0 = t_{p+1}/p · D_0 and P_{n−1} − P_{n−2} = (1 − t_{n−1})/p · D_1, in the
/// order of the unknowns so that the matrix stays banded).
Points interpolate_open(const Knots& t, int p, std::span<const double> params, const Points& Q,
                        const Point& d0, const Point& d1) {
  Points X;
  const bool banded = detail::with_cols(Q.cols(), [&](auto cols) {
    return detail::with_degree(p, [&](auto degree) {
      return banded_interpolation<decltype(cols)::value, decltype(degree)::value>(t, p, params, Q, d0, d1, X);
    });
  });
  if (banded) return X;
  // A pivot too small (or rounding put a row out of the band): the general solver.
  const auto m = static_cast<Eigen::Index>(params.size());
  const bool s = d0.size() > 0, e = d1.size() > 0;
  const Eigen::Index n = m + s + e;
  Runs A(n, p + 1);
  Points B = s || e ? Points(n, Q.cols()) : Q;
  Eigen::Index row = 0;
  int span = p;
  const auto add_point = [&](Eigen::Index k) {
    const double u = params[static_cast<std::size_t>(k)];
    span = detail::find_span(t.data(), p, static_cast<int>(n), u, span);  // sorted: the next span at most
    detail::basis(t.data(), p, span, u, A.row(row));
    A.first[static_cast<std::size_t>(row)] = span - p;
    A.count[static_cast<std::size_t>(row)] = p + 1;
    if (s || e) B.row(row) = Q.row(k);
    ++row;
  };
  const auto add_derivative = [&](Eigen::Index first_col, double h, const Point& D) {
    A.row(row)[0] = -p / h;
    A.row(row)[1] = p / h;
    A.first[static_cast<std::size_t>(row)] = first_col;
    A.count[static_cast<std::size_t>(row)] = 2;
    B.row(row++) = D;
  };
  add_point(0);
  if (s) add_derivative(0, t[static_cast<std::size_t>(p) + 1] - t[0], d0);
  for (Eigen::Index k = 1; k + 1 < m; ++k) add_point(k);
  if (e) add_derivative(n - 2, t[static_cast<std::size_t>(n + p)] - t[static_cast<std::size_t>(n - 1)], d1);
  add_point(m - 1);
  return solve_collocation(A, std::move(B), "points");
}

/// Parameters of one line of points, or an empty vector when all its chords vanish (chord kinds).
std::vector<double> line_parameters(const Points& points, Parametrization kind, bool closed,
                                    bool allow_coincident) {
  const Eigen::Index m = points.rows(), dim = points.cols();
  const Eigen::Index chords = closed ? m : m - 1;
  // u_k holds the running sum of the chords' lengths before point k, then is divided by the total.
  std::vector<double> u(static_cast<std::size_t>(m) + 1);
  const double* P = points.data();
  double sum = 0;
  for (Eigen::Index k = 0; k < chords; ++k) {
    u[static_cast<std::size_t>(k)] = sum;
    double length = 1.0;
    if (kind != Parametrization::uniform) {
      const double* a = P + k * dim;
      const double* b = P + (k + 1 < m ? k + 1 : 0) * dim;
      double d2 = 0;
      for (Eigen::Index c = 0; c < dim; ++c) d2 += (b[c] - a[c]) * (b[c] - a[c]);
      const double d = std::sqrt(d2);
      if (d == 0 && !allow_coincident)
        detail::fail("points[", (k + 1) % m, "]: coincides with points[", k,
                     "] (chord-length and centripetal parameters need distinct consecutive points)");
      length = kind == Parametrization::centripetal ? std::sqrt(d) : d;
    }
    sum += length;
  }
  u[static_cast<std::size_t>(chords)] = sum;
  u.resize(static_cast<std::size_t>(m));
  if (!(sum > 0)) return {};
  if (!std::isfinite(sum)) detail::fail("points: the polygon's length overflows a double");
  for (double& x : u) x /= sum;
  if (!closed) u.back() = 1.0;
  return u;
}

/// Points without a closing duplicate (a closed polygon given with its first point repeated).
Points without_closing_point(const Points& points) {
  const Eigen::Index m = points.rows();
  if (m >= 2 && points.row(m - 1) == points.row(0)) return points.topRows(m - 1);
  return points;
}

/// Breakpoints of a periodic interpolant of degree p through params (period [0, 1]): cyclic averages
/// of p consecutive parameters centred on each (odd p: knots at the data for uniform parameters; even
/// p: between them). The period is [b_0, b_0 + 1], b_0 within one parameter gap of 0.
Knots periodic_breakpoints(std::span<const double> u, int p) {
  const auto m = static_cast<int>(u.size());
  const auto at = [&](int i) {  // ū_i extended by periodicity
    const int q = i >= 0 ? i / m : -((m - 1 - i) / m);
    return u[static_cast<std::size_t>(i - q * m)] + q;
  };
  const int h = p / 2;
  Knots b(static_cast<std::size_t>(m) + 1);
  for (int j = 0; j < m; ++j) {
    double sum = 0;
    for (int i = j - h; i < j - h + p; ++i) sum += at(i) - at(j);  // offsets: exact for uniform data
    b[static_cast<std::size_t>(j)] = at(j) + sum / p;
  }
  b.back() = b.front() + 1;
  return b;
}

Curve interpolate_closed(const Points& data, const InterpolateOptions& o) {
  const Points Q = without_closing_point(data);
  const int p = o.degree;
  check_fit_degree(p, p + 1, Q.rows(), "a closed curve");
  const std::vector<double> u = fit_parameters(Q, o.parametrization, true);
  const Knots b = periodic_breakpoints(u, p);
  const auto m = static_cast<int>(Q.rows());
  // The curve's knots and spans from a placeholder net; columns wrap modulo m.
  Curve shape = make_closed_curve(p, b, Points::Zero(m, Q.cols()));
  Runs A(m, p + 1);
  double local[2 * kMaxDegree];
  for (int k = 0; k < m; ++k) {
    const double x = domain_parameter(shape, u[static_cast<std::size_t>(k)]);
    const int span = find_span(shape.knots, p, x);
    // The knots relative to the span near the seam, as evaluation uses them (detail::span_knots).
    const detail::SpanKnots rel = detail::span_knots(shape, span, local);
    detail::basis(rel.t.data(), p, rel.span, x - rel.origin, A.row(k));
    A.first[static_cast<std::size_t>(k)] = span - p;
    A.count[static_cast<std::size_t>(k)] = p + 1;
  }
  return make_closed_curve(p, b, solve_collocation(A, Q, "points"));
}

/// The polyline bound of CurveFit on one piece: coefficients d (p + 1 rows, Bézier form of C − L on
/// an interval); subdivided while the hull's bound exceeds `floor` (the largest value seen) by 1 %.
double piece_bound(Points d, int depth, double& floor) {
  const Eigen::Index p = d.rows() - 1;
  floor = std::max({floor, d.row(0).norm(), d.row(p).norm()});
  double upper = 0;
  for (Eigen::Index i = 0; i <= p; ++i) upper = std::max(upper, d.row(i).norm());
  if (upper <= 1.01 * floor || depth == 0) return upper;
  Points left(p + 1, d.cols()), right(p + 1, d.cols());
  for (Eigen::Index r = 0; r <= p; ++r) {  // de Casteljau at ½
    left.row(r) = d.row(0);
    right.row(p - r) = d.row(p - r);
    for (Eigen::Index i = 0; i < p - r; ++i) d.row(i) = 0.5 * (d.row(i) + d.row(i + 1));
  }
  return std::max(piece_bound(std::move(left), depth - 1, floor),
                  piece_bound(std::move(right), depth - 1, floor));
}

}  // namespace

Parametrization parametrization_named(std::string_view name) {
  if (name == "uniform") return Parametrization::uniform;
  if (name == "chord_length" || name == "chord-length") return Parametrization::chord_length;
  if (name == "centripetal") return Parametrization::centripetal;
  detail::fail("parametrization '", name, "': expected uniform, chord_length or centripetal");
}

FitMeasure fit_measure_named(std::string_view name) {
  if (name == "points") return FitMeasure::points;
  if (name == "polyline") return FitMeasure::polyline;
  detail::fail("measure '", name, "': expected points or polyline");
}

std::vector<double> fit_parameters(const Points& points, Parametrization kind, bool closed) {
  check_points(points, "points");
  if (points.rows() < 2) detail::fail("points: ", points.rows(), " given, fitting needs at least 2");
  return line_parameters(points, kind, closed, false);
}

Knots averaged_knots(std::span<const double> u, int degree, int extra, bool end_only) {
  // An end derivative is a second condition at its end's parameter (Hermite): the parameter counts
  // twice, then eq. 9.8 on the sequence (for two derivatives this is eq. 9.22).
  const bool twice_first = extra == 2 || (extra == 1 && !end_only),
             twice_last = extra == 2 || (extra == 1 && end_only);
  const auto x = [&](int i) {  // the sequence with the repeated ends
    if (twice_first) --i;
    return u[static_cast<std::size_t>(std::clamp(i, 0, static_cast<int>(u.size()) - 1))];
  };
  const int p = degree;
  const auto n = static_cast<int>(u.size()) + twice_first + twice_last;  // control points
  Knots t;
  t.reserve(static_cast<std::size_t>(n) + static_cast<std::size_t>(p) + 1);
  t.assign(static_cast<std::size_t>(p) + 1, u.front());
  for (int j = 1; j <= n - p - 1; ++j) {
    double sum = 0;
    for (int i = j; i < j + p; ++i) sum += x(i);
    t.push_back(sum / p);
  }
  t.insert(t.end(), static_cast<std::size_t>(p) + 1, u.back());
  return t;
}

Knots approximation_knots(std::span<const double> u, int degree, Eigen::Index count) {
  const auto m = static_cast<Eigen::Index>(u.size());
  const int p = degree;
  Knots t(static_cast<std::size_t>(p + 1), u.front());
  const Eigen::Index spans = count - p;
  for (Eigen::Index j = 1; j < spans; ++j) {
    // The fractional index x = j·(m − 1)/spans, as the integer part and a remainder (exact).
    const Eigen::Index whole = j * (m - 1) / spans, rest = j * (m - 1) % spans;
    const double alpha = static_cast<double>(rest) / static_cast<double>(spans);
    const double a = u[static_cast<std::size_t>(whole)];
    const double b = u[static_cast<std::size_t>(std::min(whole + 1, m - 1))];
    t.push_back(a + alpha * (b - a));
  }
  t.insert(t.end(), static_cast<std::size_t>(p) + 1, u.back());
  return t;
}

Curve interpolate(const Points& points, const InterpolateOptions& o) {
  validate_degree(o.degree);
  check_points(points, "points");
  const bool s = o.start_derivative.size() > 0, e = o.end_derivative.size() > 0;
  if (o.closed) {
    if (s || e) detail::fail("derivatives: end derivatives are for open curves, not closed ones");
    return interpolate_closed(points, o);
  }
  const int p = o.degree;
  if ((s || e) && p < 2) detail::fail("derivatives: end derivatives need degree 2 or more, not ", p);
  for (const Point* d : {&o.start_derivative, &o.end_derivative})
    if (d->size() > 0) {
      const char* which = d == &o.start_derivative ? "start_derivative" : "end_derivative";
      if (d->size() != points.cols())
        detail::fail(which, ": ", d->size(), " coordinates for points of dimension ", points.cols());
      if (!d->allFinite()) detail::fail(which, ": a coordinate is not finite");
    }
  check_fit_degree(p, std::max<Eigen::Index>(2, p + 1 - s - e), points.rows(), "an interpolating curve");
  const std::vector<double> u = line_parameters(points, o.parametrization, false, false);  // points checked
  Knots t = averaged_knots(u, p, s + e, e && !s);
  Points P = interpolate_open(t, p, u, points, o.start_derivative, o.end_derivative);
  validate_knots(t, p, P.rows());  // the control points are finite: the solvers refuse others
  return Curve{p, std::move(t), std::move(P), false, false};
}

Curve interpolate(const Points& points, std::span<const double> u, int degree) {
  validate_degree(degree);
  check_points(points, "points");
  if (static_cast<Eigen::Index>(u.size()) != points.rows())
    detail::fail("parameters: ", u.size(), " given for ", points.rows(), " points");
  for (std::size_t k = 0; k < u.size(); ++k) {
    if (!std::isfinite(u[k])) detail::fail("parameters[", k, "]: ", u[k], " is not finite");
    if (k > 0 && !(u[k] > u[k - 1]))
      detail::fail("parameters[", k, "]: ", u[k], " is not greater than parameters[", k - 1,
                   "] = ", u[k - 1]);
  }
  check_fit_degree(degree, std::max<Eigen::Index>(2, degree + 1), points.rows(), "an interpolating curve");
  const Knots t = averaged_knots(u, degree);
  Curve c{degree, t, interpolate_open(t, degree, u, points, {}, {}), false, false};
  validate(c);
  return c;
}

CurveFit measure_fit(const Curve& c, const Points& Q, std::vector<double> u) {
  if (c.rational) detail::fail("curve: fit distances are measured for non-rational curves");
  if (static_cast<Eigen::Index>(u.size()) != Q.rows() || Q.cols() != dimension(c))
    detail::fail("points: ", Q.rows(), " points of dimension ", Q.cols(), " for ", u.size(),
                 " parameters and a curve of dimension ", dimension(c));
  CurveFit fit{c, std::move(u), 0, 0};
  const auto m = static_cast<Eigen::Index>(fit.parameters.size());
  if (m == 0) return fit;
  const int p = c.degree;
  const Domain dom = domain(c);
  const double period = dom.end - dom.start;
  // The data parameters along the polyline, unwrapped for closed curves (each step forward by less
  // than a period), and the polyline's closing edge.
  std::vector<double> x(static_cast<std::size_t>(m) + (c.closed ? 1 : 0));
  for (Eigen::Index k = 0; k < m; ++k) {
    const double uk = fit.parameters[static_cast<std::size_t>(k)];
    const double step = k == 0 ? 0 : uk - fit.parameters[static_cast<std::size_t>(k - 1)];
    x[static_cast<std::size_t>(k)] = k == 0
                                         ? uk
                                         : x[static_cast<std::size_t>(k - 1)] +
                                               (c.closed ? step - std::floor(step / period) * period : step);
    fit.point_distance = std::max(fit.point_distance, (evaluate(c, uk) - Q.row(k)).norm());
  }
  if (c.closed) x.back() = x.front() + period;
  const std::vector<double> knots = breakpoints(c.knots, p);
  // The point distances are values of |C − L| (at the data parameters): the bound starts there.
  double floor = fit.point_distance;
  fit.polyline_bound = fit.point_distance;
  std::vector<double> args(static_cast<std::size_t>(p));
  Points d(p + 1, Q.cols());
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    const double a0 = x[k], b0 = x[k + 1];
    if (!(a0 < b0)) continue;
    const Point qa = Q.row(static_cast<Eigen::Index>(k)), qb = Q.row(static_cast<Eigen::Index>((k + 1) % m));
    // The interval [a0, b0] cut at the knots (shifted by whole periods for closed curves).
    std::vector<double> cuts{a0, b0};
    const double lo = c.closed ? std::floor((a0 - dom.start) / period) : 0;
    for (double q = lo; q <= lo + (c.closed ? 1 : 0); ++q)
      for (double kv : knots)
        if (kv + q * period > a0 && kv + q * period < b0) cuts.push_back(kv + q * period);
    std::sort(cuts.begin(), cuts.end());
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double a = cuts[i], b = cuts[i + 1];
      const double mid = 0.5 * (a + b);
      const double shift = (c.closed ? domain_parameter(c, mid) : mid) - mid;
      const int span = find_span(c.knots, p, mid + shift);
      const Point la = qa + (a - a0) / (b0 - a0) * (qb - qa), lb = qa + (b - a0) / (b0 - a0) * (qb - qa);
      for (int r = 0; r <= p; ++r) {  // Bézier coefficients of C on [a, b]: blossoms b(a^{p−r}, b^r)
        for (int j = 0; j < p; ++j) args[static_cast<std::size_t>(j)] = (j < p - r ? a : b) + shift;
        d.row(r) = blossom(c, args, span) - (la + (static_cast<double>(r) / p) * (lb - la));
      }
      fit.polyline_bound = std::max(fit.polyline_bound, piece_bound(d, 16, floor));
    }
  }
  return fit;
}

CurveFit approximate(const Points& points, const ApproximateOptions& o) {
  validate_degree(o.degree);
  check_points(points, "points");
  const int p = o.degree;
  const Eigen::Index m = points.rows();
  const bool by_count = o.control_points > 0, by_tolerance = o.tolerance > 0;
  if (by_count && by_tolerance) detail::fail("approximate: give control_points or tolerance, not both");
  if (o.control_points < 0) detail::fail("control_points: ", o.control_points, " is negative");
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance))
    detail::fail("tolerance: ", o.tolerance, " is not a non-negative finite number");
  if (o.closed && (by_count || by_tolerance))
    detail::fail("closed: closed curves are interpolated (no control_points or tolerance)");
  const auto interpolation = [&] {
    const Points Q = o.closed ? without_closing_point(points) : points;
    InterpolateOptions io;
    io.degree = p;
    io.parametrization = o.parametrization;
    io.closed = o.closed;
    return measure_fit(interpolate(Q, io), Q, fit_parameters(Q, o.parametrization, o.closed));
  };
  if (!by_count && !by_tolerance) return interpolation();
  check_fit_degree(p, p + 1, m, "an approximating curve");
  if (o.weights.size() != 0) {
    if (o.weights.size() != m) detail::fail("weights: ", o.weights.size(), " weights for ", m, " points");
    for (Eigen::Index k = 0; k < m; ++k)
      if (!(o.weights(k) > 0) || !std::isfinite(o.weights(k)))
        detail::fail("weights[", k, "]: ", o.weights(k), " is not a positive finite number");
  }
  const std::vector<double> u = fit_parameters(points, o.parametrization);

  if (by_count) {
    if (o.control_points < p + 1 || o.control_points > m)
      detail::fail("control_points: ", o.control_points, " is outside ", p + 1, " … ", m, " (degree ", p,
                   ", ", m, " points)");
    if (o.control_points == m) return interpolation();
    const Knots t = approximation_knots(u, p, o.control_points);
    return measure_fit(make_curve(p, t, least_squares(t, p, u, points, o.weights, o.fix_ends)), points, u);
  }
  // To a tolerance: from one Bézier piece, a knot in each span whose error is too large.
  const bool polyline = o.measure == FitMeasure::polyline;
  Knots t = approximation_knots(u, p, p + 1);
  while (control_count(t, p) < m) {
    CurveFit fit =
        measure_fit(make_curve(p, t, least_squares(t, p, u, points, o.weights, o.fix_ends)), points, u);
    if ((polyline ? fit.polyline_bound : fit.point_distance) <= o.tolerance) return fit;
    // The spans to split: those of the points too far (points), of the polyline edges too far (polyline).
    const Eigen::Index n = control_count(t, p);
    std::vector<char> split(static_cast<std::size_t>(n), 0);
    for (Eigen::Index k = 0; k < m; ++k) {
      const double uk = u[static_cast<std::size_t>(k)];
      double error = (evaluate(fit.curve, uk) - points.row(k)).norm();
      if (polyline && k + 1 < m) {
        const std::vector<double> edge{uk, u[static_cast<std::size_t>(k + 1)]};
        error = measure_fit(fit.curve, points.middleRows(k, 2), edge).polyline_bound;
      }
      if (error > o.tolerance) {
        split[static_cast<std::size_t>(find_span(t, p, uk))] = 1;
        if (polyline && k + 1 < m)
          split[static_cast<std::size_t>(find_span(t, p, u[static_cast<std::size_t>(k + 1)]))] = 1;
      }
    }
    // The new knot of a span: between its two middle data parameters (a parameter stays on each side).
    Knots added;
    for (Eigen::Index s = p; s < n; ++s) {
      if (!split[static_cast<std::size_t>(s)]) continue;
      const double lo = t[static_cast<std::size_t>(s)], hi = t[static_cast<std::size_t>(s + 1)];
      const auto first = std::upper_bound(u.begin(), u.end(), lo),
                 last = std::lower_bound(u.begin(), u.end(), hi);
      if (last - first < 2) continue;
      const auto mid = first + (last - first) / 2;
      added.push_back(0.5 * (*(mid - 1) + *mid));
    }
    // Keep the Schoenberg–Whitney condition: fewer knots (the first half) until it holds.
    for (std::size_t keep = added.size(); keep > 0; keep /= 2) {
      Knots next = t;
      next.insert(next.end(), added.begin(), added.begin() + static_cast<std::ptrdiff_t>(keep));
      std::sort(next.begin(), next.end());
      if (control_count(next, p) < m && schoenberg_whitney(next, p, u)) {
        t = std::move(next);
        added.clear();
        break;
      }
    }
    if (!added.empty() || control_count(t, p) == n) break;  // no knot can go in: interpolate
  }
  CurveFit fit = interpolation();
  const double reached = polyline ? fit.polyline_bound : fit.point_distance;
  if (reached > o.tolerance)
    detail::fail("tolerance: ", o.tolerance, " is below the ", polyline ? "polyline distance " : "rounding ",
                 reached, " of the interpolating curve of degree ", p);
  return fit;
}

// ------------------------------------------------------------------------------------------------
// Surfaces.

namespace {

void check_grid(const Grid& g) {
  if (g.count[0] < 2 || g.count[1] < 2)
    detail::fail("grid: ", g.count[0], " by ", g.count[1], " points, fitting needs at least 2 by 2");
  if (g.points.rows() != g.count[0] * g.count[1])
    detail::fail("grid: ", g.points.rows(), " points for a ", g.count[0], " by ", g.count[1], " grid");
  check_points(g.points, "grid");
}

/// The rows of `data` (`count[0]·count[1] by dim`, (i, j) at i·count[1] + j) regrouped so that line j of
/// direction v becomes row j (`count[1] by count[0]·dim`): the transpose of the grid.
Points transposed(const Points& data, Eigen::Index rows, Eigen::Index cols, Eigen::Index dim) {
  Points out(cols * rows, dim);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) out.row(j * rows + i) = data.row(i * cols + j);
  return out;
}

/// Control rows along one direction: lines are the rows of `lines` (`m by k`, each a whole line of
/// the other direction flattened); interpolation when count = m, else least squares with fixed ends.
Points fit_direction(const Points& lines, std::span<const double> u, int p, Eigen::Index count, Knots& t) {
  const Eigen::Index m = lines.rows();
  if (count == m) {
    t = averaged_knots(u, p);
    return interpolate_open(t, p, u, lines, {}, {});
  }
  t = approximation_knots(u, p, count);
  return least_squares(t, p, u, lines, {}, true);
}

Surface fit_surface(const Grid& g, const SurfaceFitOptions& o, std::array<Eigen::Index, 2> count) {
  check_grid(g);
  const std::array<std::vector<double>, 2> u = grid_parameters(g, o.parametrization);
  const Eigen::Index dim = g.points.cols();
  std::array<Knots, 2> knots;
  // In u: lines i of count[1]·dim values; then the control rows regrouped by v.
  const Points flat_u = Eigen::Map<const Points>(g.points.data(), g.count[0], g.count[1] * dim);
  const Points Ru = fit_direction(flat_u, u[0], o.degree[0], count[0], knots[0]);
  const Points by_v =
      transposed(Eigen::Map<const Points>(Ru.data(), count[0] * g.count[1], dim), count[0], g.count[1], dim);
  const Points flat_v = Eigen::Map<const Points>(by_v.data(), g.count[1], count[0] * dim);
  const Points Rv = fit_direction(flat_v, u[1], o.degree[1], count[1], knots[1]);
  const Points net =
      transposed(Eigen::Map<const Points>(Rv.data(), count[1] * count[0], dim), count[1], count[0], dim);
  return make_surface(o.degree, std::move(knots), count, net);
}

}  // namespace

std::array<std::vector<double>, 2> grid_parameters(const Grid& g, Parametrization kind) {
  check_grid(g);
  std::array<std::vector<double>, 2> out;
  const Eigen::Index dim = g.points.cols();
  for (int d = 0; d < 2; ++d) {
    const Eigen::Index along = g.count[static_cast<std::size_t>(d)],
                       across = g.count[static_cast<std::size_t>(1 - d)];
    std::vector<double> sum(static_cast<std::size_t>(along), 0.0);
    int lines = 0;
    Points line(along, dim);
    for (Eigen::Index l = 0; l < across; ++l) {
      for (Eigen::Index i = 0; i < along; ++i)
        line.row(i) = g.points.row(d == 0 ? i * g.count[1] + l : l * g.count[1] + i);
      const std::vector<double> u = line_parameters(line, kind, false, true);
      if (u.empty()) continue;
      ++lines;
      for (std::size_t i = 0; i < u.size(); ++i) sum[i] += u[i];
    }
    if (lines == 0) detail::fail("grid: every line along ", d == 0 ? "u" : "v", " has all its points equal");
    std::vector<double>& u = out[static_cast<std::size_t>(d)];
    for (double s : sum) u.push_back(s / lines);
    u.front() = 0;
    u.back() = 1;
    for (std::size_t i = 1; i < u.size(); ++i)
      if (!(u[i] > u[i - 1]))
        detail::fail("grid: the points ", i - 1, " and ", i, " along ", d == 0 ? "u" : "v",
                     " coincide on every line");
  }
  return out;
}

Surface interpolate_surface(const Grid& g, const SurfaceFitOptions& o) {
  check_grid(g);
  for (int d = 0; d < 2; ++d)
    check_fit_degree(o.degree[static_cast<std::size_t>(d)], o.degree[static_cast<std::size_t>(d)] + 1,
                     g.count[static_cast<std::size_t>(d)],
                     d == 0 ? "an interpolating surface (u)" : "an interpolating surface (v)");
  return fit_surface(g, o, g.count);
}

Surface approximate_surface(const Grid& g, const SurfaceFitOptions& o) {
  check_grid(g);
  for (int d = 0; d < 2; ++d) {
    const auto i = static_cast<std::size_t>(d);
    const int p = o.degree[i];
    check_fit_degree(p, p + 1, g.count[i],
                     d == 0 ? "an approximating surface (u)" : "an approximating surface (v)");
    if (o.control_points[i] < p + 1 || o.control_points[i] > g.count[i])
      detail::fail("control_points[", d, "]: ", o.control_points[i], " is outside ", p + 1, " … ", g.count[i],
                   " (degree ", p, ", ", g.count[i], " points along ", d == 0 ? "u" : "v", ")");
  }
  return fit_surface(g, o, o.control_points);
}

}  // namespace cifs::nurbs
