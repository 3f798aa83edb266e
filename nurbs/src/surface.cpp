// SPDX-License-Identifier: MIT
#include "cifs/nurbs/surface.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "cifs/memory.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/row_combination.hpp"
#include "detail.hpp"
#include "lines.hpp"

namespace cifs::nurbs {
namespace {

constexpr const char* kDirName[2] = {"u", "v"};

/// The index of a direction (0 or 1); throws for any other value an enum can hold.
std::size_t checked_direction(Direction dir) {
  const int d = static_cast<int>(dir);
  if (d != 0 && d != 1) detail::fail("direction ", d, " is neither u (0) nor v (1)");
  return static_cast<std::size_t>(d);
}

double checked_parameter(const Surface& s, Direction dir, double t) {
  const Domain dom = domain(s, dir);
  if (!std::isfinite(t))
    detail::fail("parameter ", kDirName[static_cast<int>(dir)], " is not a finite number");
  if (t < dom.start || t > dom.end)
    detail::fail("parameter ", kDirName[static_cast<int>(dir)], " = ", t, " is outside the domain [",
                 dom.start, ", ", dom.end, "]");
  return t;
}

}  // namespace

Surface make_surface(std::array<int, 2> degree, std::array<Knots, 2> knots, std::array<Eigen::Index, 2> count,
                     const Points& points, const Eigen::VectorXd& weights) {
  if (count[0] < 1 || count[1] < 1 || count[0] * count[1] != points.rows())
    detail::fail("points: ", points.rows(), " control points do not form a ", count[0], " by ", count[1],
                 " net");
  Surface s{degree, std::move(knots), count, detail::homogeneous(points, weights, "points"),
            weights.size() > 0};
  validate(s);
  return s;
}

void validate(const Surface& s) {
  for (int d = 0; d < 2; ++d) {
    // The degree first, with its direction in the message (validate_knots reports only "degree").
    validate_degree(s.degree[static_cast<std::size_t>(d)], std::string("degree[") + std::to_string(d) + "]");
    validate_knots(s.knots[static_cast<std::size_t>(d)], s.degree[static_cast<std::size_t>(d)],
                   s.count[static_cast<std::size_t>(d)], std::string("knots[") + std::to_string(d) + "]");
  }
  if (s.P.rows() != s.count[0] * s.count[1])
    detail::fail("points: ", s.P.rows(), " rows for a ", s.count[0], " by ", s.count[1], " net");
  if (s.P.cols() < (s.rational ? 2 : 1)) detail::fail("points: control points have no coordinates");
  for (Eigen::Index r = 0; r < s.P.rows(); ++r) {
    const Eigen::Index i = r / s.count[1], j = r % s.count[1];
    const double w = s.rational ? s.P(r, s.P.cols() - 1) : 1.0;
    if (!(w > 0) || !std::isfinite(w))
      detail::fail("weights[", i, "][", j, "]: weight ", w, " is not a positive finite number");
    for (Eigen::Index k = 0; k < s.P.cols(); ++k)
      if (!std::isfinite(s.P(r, k)))
        detail::fail("points[", i, "][", j, "]: ",
                     s.rational && k + 1 < s.P.cols()
                         ? "the coordinate times its weight (w·x) is not finite; "
                           "lower the weights (a common factor leaves the surface)"
                         : "coordinate is not finite");
  }
}

Points cartesian_points(const Surface& s) {
  if (!s.rational) return s.P;
  const int dim = dimension(s);
  Points out(s.P.rows(), dim);
  for (Eigen::Index i = 0; i < s.P.rows(); ++i) out.row(i) = s.P.row(i).head(dim) / s.P(i, dim);
  return out;
}

Eigen::VectorXd weights(const Surface& s) {
  if (!s.rational) return Eigen::VectorXd::Ones(s.P.rows());
  return s.P.col(s.P.cols() - 1);
}

namespace {

/// Throws for the first parameter outside the domain of `dir` (one branch-free scan when none is).
void check_parameters(const Surface& s, Direction dir, std::span<const double> ts) {
  if (detail::scan(ts, domain(s, dir)).inside) return;
  for (double t : ts) checked_parameter(s, dir, t);
}

/// S(u, v) into out (dim values): two spans, two bases and the (p + 1)(q + 1) tensor sum. The order of
/// operations is evaluate_grid's (v first, for each of the p + 1 rows, then u), so the two agree to the bit.
template <int Cols>
void surface_point(const Surface& s, double u, double v, double* out, double* scratch) noexcept {
  const int p = s.degree[0], q = s.degree[1];
  const Eigen::Index nv = s.count[1], cols = Cols > 0 ? Cols : s.P.cols();
  const double* tu = s.knots[0].data();
  const double* tv = s.knots[1].data();
  const int su = detail::find_span(tu, p, static_cast<int>(s.count[0]), u);
  const int sv = detail::find_span(tv, q, static_cast<int>(nv), v);
  double Nu[kMaxDegree + 1], Nv[kMaxDegree + 1];
  detail::basis(tu, p, su, u, Nu);
  detail::basis(tv, q, sv, v, Nv);
  double fixed[Cols > 0 ? 2 * Cols : 1];
  double* acc = Cols > 0 ? fixed : scratch;
  double* line = acc + cols;
  for (int r = 0; r <= p; ++r) {
    const double* row = s.P.data() + ((su - p + r) * nv + (sv - q)) * cols;
    for (Eigen::Index k = 0; k < cols; ++k) line[k] = Nv[0] * row[k];
    for (int c = 1; c <= q; ++c)
      for (Eigen::Index k = 0; k < cols; ++k) line[k] += Nv[c] * row[c * cols + k];
    for (Eigen::Index k = 0; k < cols; ++k) acc[k] = r == 0 ? Nu[0] * line[k] : acc[k] + Nu[r] * line[k];
  }
  const int dim = dimension(s);
  const double scale = s.rational ? 1.0 / acc[dim] : 1.0;
  for (int k = 0; k < dim; ++k) out[k] = acc[k] * scale;
}

/// Control row i contracted along v at every grid column: W[b·cols + k] = Σ_c Nv_b[c]·P(i, vspan_b − q + c,
/// k), summed in c order. Computed once per control row the grid needs, not per grid point.
template <int Cols>
void contract_v(const Surface& s, Eigen::Index i, std::span<const int> vspan, const double* Nv, double* W,
                double* scratch) noexcept {
  const int q = s.degree[1];
  const Eigen::Index nv = s.count[1], cols = Cols > 0 ? Cols : s.P.cols();
  const double* row = s.P.data() + i * nv * cols;
  double fixed[Cols > 0 ? Cols : 1];
  double* acc = Cols > 0 ? fixed : scratch;
  for (std::size_t b = 0; b < vspan.size(); ++b, W += cols) {
    const double* N = Nv + b * static_cast<std::size_t>(q + 1);
    const double* base = row + (vspan[b] - q) * cols;
    for (Eigen::Index k = 0; k < cols; ++k) acc[k] = N[0] * base[k];
    for (int c = 1; c <= q; ++c)
      for (Eigen::Index k = 0; k < cols; ++k) acc[k] += N[c] * base[c * cols + k];
    for (Eigen::Index k = 0; k < cols; ++k) W[k] = acc[k];
  }
}

/// The grid rows, v first: the p + 1 control rows of a u span contracted along v at every grid
/// column (contract_v, kept in p + 1 slots by control row index mod p + 1), then every grid row of
/// the span as the (p + 1)-term combination of those rows. Rows are visited by span (`order`), so
/// that each control row is contracted once however the u parameters are ordered.
template <int Cols>
void grid_rows(const Surface& s, std::span<const double> us, std::span<const int> uspan,
               std::span<const std::size_t> order, std::span<const int> vspan, const double* Nv, bool reused,
               double* out) {
  const int p = s.degree[0];
  const Eigen::Index cols = Cols > 0 ? Cols : s.P.cols();
  const int dim = dimension(s);
  const auto width = static_cast<Eigen::Index>(vspan.size()) * cols;
  const auto p1 = static_cast<std::size_t>(p) + 1;
  std::vector<double> slots(p1 * static_cast<std::size_t>(width));
  std::vector<Eigen::Index> held(p1, -1);                                   // the control row each slot holds
  std::vector<double> H(s.rational ? static_cast<std::size_t>(width) : 0);  // one homogeneous row
  std::vector<double> scratch = detail::scratch<Cols>(s.P.cols());
  // Streaming stores for a large reused output (fresh pages are zeroed by the kernel on the first
  // write, in the cache: streaming over them was 1.6-3x slower; rational rows go through the row H).
  const bool stream =
      reused && !s.rational && us.size() * static_cast<std::size_t>(width) * sizeof(double) >= kStreamBytes;
  const RowCombination combine = row_combination(p + 1, stream);
  const double* tu = s.knots[0].data();
  double Nu[kMaxDegree + 1];
  const double* W[kMaxDegree + 1];
  for (const std::size_t a : order) {
    const int span = uspan[a];
    for (int r = 0; r <= p; ++r) {
      const Eigen::Index i = span - p + r;
      const auto slot = static_cast<std::size_t>(i) % p1;
      double* w = slots.data() + slot * static_cast<std::size_t>(width);
      if (held[slot] != i) {
        contract_v<Cols>(s, i, vspan, Nv, w, scratch.data());
        held[slot] = i;
      }
      W[r] = w;
    }
    detail::basis(tu, p, span, us[a], Nu);
    double* row = out + static_cast<Eigen::Index>(a) * static_cast<Eigen::Index>(vspan.size()) * dim;
    if (!s.rational) {
      combine(Nu, p + 1, W, width, row);
      continue;
    }
    combine(Nu, p + 1, W, width, H.data());
    for (std::size_t b = 0; b < vspan.size(); ++b, row += dim) {
      const double* h = H.data() + static_cast<Eigen::Index>(b) * cols;
      const double scale = 1.0 / h[dim];  // as surface_point: the same bits
      for (int k = 0; k < dim; ++k) row[k] = h[k] * scale;
    }
  }
  if (stream) stream_fence();
}

}  // namespace

Point evaluate(const Surface& s, double u, double v) {
  checked_parameter(s, Direction::u, u);
  checked_parameter(s, Direction::v, v);
  Point out(dimension(s));
  detail::with_cols(s.P.cols(), [&](auto cols) {
    std::vector<double> scratch = detail::scratch<cols>(s.P.cols(), 2);
    surface_point<cols>(s, u, v, out.data(), scratch.data());
  });
  return out;
}

void evaluate_grid(const Surface& s, std::span<const double> us, std::span<const double> vs, Points& out) {
  const int p = s.degree[0], q = s.degree[1];
  check_parameters(s, Direction::u, us);
  check_parameters(s, Direction::v, vs);
  // v basis once per grid column, u span once per grid row.
  std::vector<int> vspan(vs.size());
  std::vector<double> Nv(vs.size() * static_cast<std::size_t>(q + 1));
  const int nv = static_cast<int>(s.count[1]);
  for (std::size_t b = 0; b < vs.size(); ++b) {
    vspan[b] = detail::find_span(s.knots[1].data(), q, nv, vs[b], b ? vspan[b - 1] : q);
    detail::basis(s.knots[1].data(), q, vspan[b], vs[b], Nv.data() + b * static_cast<std::size_t>(q + 1));
  }
  std::vector<int> uspan(us.size());
  const int nu = static_cast<int>(s.count[0]);
  for (std::size_t a = 0; a < us.size(); ++a)
    uspan[a] = detail::find_span(s.knots[0].data(), p, nu, us[a], a ? uspan[a - 1] : p);
  std::vector<std::size_t> order(us.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (!std::is_sorted(uspan.begin(), uspan.end()))
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t x, std::size_t y) { return uspan[x] < uspan[y]; });
  const auto rows = static_cast<Eigen::Index>(us.size() * vs.size());
  const bool reused = out.size() == rows * dimension(s);
  resize_huge(out, rows, Eigen::Index{dimension(s)});
  if (vs.empty()) return;
  detail::with_cols(s.P.cols(), [&](auto cols) {
    grid_rows<cols>(s, us, uspan, order, vspan, Nv.data(), reused, out.data());
  });
}

Points evaluate_grid(const Surface& s, std::span<const double> us, std::span<const double> vs) {
  Points out;
  evaluate_grid(s, us, vs, out);
  return out;
}

Points derivatives(const Surface& s, double u, double v, int order) {
  detail::check_derivative_order(order);
  u = checked_parameter(s, Direction::u, u);
  v = checked_parameter(s, Direction::v, v);
  const int p = s.degree[0], q = s.degree[1];
  const Eigen::Index nv = s.count[1], cols = s.P.cols();
  const int su = find_span(s.knots[0], p, u), sv = find_span(s.knots[1], q, v);
  const Eigen::MatrixXd Du = basis_derivatives(s.knots[0], p, su, u, order);
  const Eigen::MatrixXd Dv = basis_derivatives(s.knots[1], q, sv, v, order);
  const Eigen::Index w = order + 1;
  Points H = Points::Zero(w * w, cols);  // homogeneous partials
  for (int k = 0; k <= order; ++k)
    for (int l = 0; k + l <= order; ++l)
      for (int r = 0; r <= p; ++r)
        for (int c = 0; c <= q; ++c)
          H.row(k * w + l) += Du(k, r) * Dv(l, c) * s.P.row((su - p + r) * nv + (sv - q + c));
  if (!s.rational) return H;
  // Quotient rule in two variables (Piegl–Tiller A4.4).
  const int dim = dimension(s);
  auto binom = [](int n, int k) {
    double b = 1;
    for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
    return b;
  };
  Points S = Points::Zero(w * w, dim);
  for (int k = 0; k <= order; ++k)
    for (int l = 0; k + l <= order; ++l) {
      Point val = H.row(k * w + l).head(dim);
      for (int j = 1; j <= l; ++j) val -= binom(l, j) * H(j, dim) * S.row(k * w + l - j);
      for (int i = 1; i <= k; ++i) {
        val -= binom(k, i) * H(i * w, dim) * S.row((k - i) * w + l);
        Point inner = Point::Zero(dim);
        for (int j = 1; j <= l; ++j) inner += binom(l, j) * H(i * w + j, dim) * S.row((k - i) * w + l - j);
        val -= binom(k, i) * inner;
      }
      S.row(k * w + l) = val / H(0, dim);
    }
  return S;
}

namespace {

/// The size of the terms that make up the partial S_u (dir u) or S_v at (u, v) in the domain:
/// Σ |N′_i(u)| M_j(v) (w_ij / w) |P_ij|. The computed partial carries a rounding of about ε times this (a
/// pole's S_u is not exactly zero: ε·|P|, whatever |P − S|).
double partial_scale(const Surface& s, double u, double v, Direction dir) {
  const int p = s.degree[0], q = s.degree[1];
  const int su = find_span(s.knots[0], p, u), sv = find_span(s.knots[1], q, v);
  const Eigen::MatrixXd Du = basis_derivatives(s.knots[0], p, su, u, 1);
  const Eigen::MatrixXd Dv = basis_derivatives(s.knots[1], q, sv, v, 1);
  const int ku = dir == Direction::u ? 1 : 0, kv = 1 - ku;
  double sum = 0, weight = 0;
  for (int r = 0; r <= p; ++r)
    for (int c = 0; c <= q; ++c) {
      const auto row = s.P.row((su - p + r) * s.count[1] + (sv - q + c));
      const double w = s.rational ? row(3) : 1.0;
      weight += Du(0, r) * Dv(0, c) * w;
      sum += std::abs(Du(ku, r) * Dv(kv, c)) * row.head(3).norm();  // w·|P|
    }
  return sum / weight;
}

/// S_u and S_v of a 3-D surface at (u, v) from its derivatives D (order ≥ 1, `order` as derivatives
/// numbers rows), refused where the tangent plane is undefined: a partial below 1e-13 of the size of its
/// terms (zero but for rounding: a pole, a collapsed edge), or partials parallel.
std::array<Eigen::Vector3d, 2> tangent_partials(const Surface& s, double u, double v, const Points& D,
                                                int order, const char* what) {
  const Eigen::Vector3d Su = D.row(order + 1).transpose(), Sv = D.row(1).transpose();
  const double n = Su.cross(Sv).norm();
  if (!(n > 1e-14 * Su.norm() * Sv.norm()) || n == 0 ||
      Su.norm() <= 1e-13 * partial_scale(s, u, v, Direction::u) ||
      Sv.norm() <= 1e-13 * partial_scale(s, u, v, Direction::v))
    detail::fail(what, " at (", u, ", ", v, "): the partial derivatives are parallel or zero");
  return {Su, Sv};
}

}  // namespace

Eigen::Vector3d normal(const Surface& s, double u, double v) {
  if (dimension(s) != 3) detail::fail("the surface is ", dimension(s), "-D; a normal needs a 3-D surface");
  const auto [Su, Sv] =
      tangent_partials(s, u, v, derivatives(s, u, v, 1), 1, "the surface normal is undefined");
  return Su.cross(Sv).normalized();
}

Curve direction_curve(const Surface& s, Direction dir) {
  const Eigen::Index nu = s.count[0], nv = s.count[1], cols = s.P.cols();
  const int d = static_cast<int>(dir);
  Curve c{s.degree[static_cast<std::size_t>(d)], s.knots[static_cast<std::size_t>(d)], {}, false, false};
  if (dir == Direction::u) {
    c.P = Eigen::Map<const Points>(s.P.data(), nu, nv * cols);
  } else {
    c.P.resize(nv, nu * cols);
    for (Eigen::Index i = 0; i < nu; ++i)
      for (Eigen::Index j = 0; j < nv; ++j) c.P.block(j, i * cols, 1, cols) = s.P.row(i * nv + j);
  }
  return c;
}

namespace {

/// The surface whose net along `dir` is the direction curve c (as direction_curve makes it), the other
/// direction as in s.
Surface from_direction_curve(const Surface& s, Direction dir, const Curve& c) {
  const auto d = static_cast<std::size_t>(dir);
  Surface out = s;
  out.degree[d] = c.degree;
  out.knots[d] = c.knots;
  out.count[d] = c.P.rows();
  const Eigen::Index nu = out.count[0], nv = out.count[1], cols = s.P.cols();
  out.P.resize(nu * nv, cols);
  if (dir == Direction::u) {
    out.P = Eigen::Map<const Points>(c.P.data(), nu * nv, cols);
  } else {
    for (Eigen::Index i = 0; i < nu; ++i)
      for (Eigen::Index j = 0; j < nv; ++j) out.P.row(i * nv + j) = c.P.block(j, i * cols, 1, cols);
  }
  return out;
}

}  // namespace

Surface refine(const Surface& s, Direction dir, std::span<const double> new_knots) {
  const int d = static_cast<int>(dir);
  Curve c;
  try {
    c = refine(direction_curve(s, dir), new_knots);
  } catch (const InvalidInput& e) {
    detail::fail("direction ", kDirName[d], ": ", e.what());
  }
  return from_direction_curve(s, dir, c);
}

std::array<Surface, 2> split(const Surface& s, Direction dir, double t) {
  std::array<Curve, 2> parts;
  try {
    parts = split(direction_curve(s, dir), t);
  } catch (const InvalidInput& e) {
    detail::fail("direction ", kDirName[static_cast<int>(dir)], ": ", e.what());
  }
  return {from_direction_curve(s, dir, parts[0]), from_direction_curve(s, dir, parts[1])};
}

Curve iso_curve(const Surface& s, Direction dir, double t) {
  const int d = static_cast<int>(dir);
  const Curve lines = direction_curve(s, dir);
  const Domain dom = domain(lines);
  if (!std::isfinite(t) || t < dom.start || t > dom.end)
    detail::fail("iso-curve: ", kDirName[d], " = ", t, " is outside the domain [", dom.start, ", ", dom.end,
                 "]");
  // The lines' combination at t (homogeneous rows combine linearly): the other direction's net.
  const Point row = evaluate(lines, t);
  const auto other = static_cast<std::size_t>(1 - d);
  Curve out{s.degree[other], s.knots[other], Eigen::Map<const Points>(row.data(), s.count[other], s.P.cols()),
            s.rational, false};
  validate(out);
  return out;
}

Surface insert_knot(const Surface& s, Direction dir, double t, int times) {
  if (times < 1) detail::fail("the knot count times = ", times, " must be at least 1");
  // Before the copies are made (times = 10^9: 8 GB), as refine would refuse them.
  if (const int degree = s.degree[static_cast<int>(dir)]; times > degree)
    detail::fail("direction ", kDirName[static_cast<int>(dir)], ": knot ", t, " would reach multiplicity ",
                 times, " > degree ", degree);
  const std::vector<double> X(static_cast<std::size_t>(times), t);
  return refine(s, dir, X);
}

Surface refine_midpoints(const Surface& s) {
  Surface out = s;
  for (Direction dir : {Direction::u, Direction::v}) {
    const std::vector<double> b =
        breakpoints(out.knots[static_cast<std::size_t>(dir)], out.degree[static_cast<std::size_t>(dir)]);
    std::vector<double> mid(b.size() - 1);
    for (std::size_t i = 0; i + 1 < b.size(); ++i) mid[i] = 0.5 * (b[i] + b[i + 1]);
    out = refine(out, dir, mid);
  }
  return out;
}

SurfaceRemoval remove_knot(const Surface& s, Direction dir, double t, int times, double tolerance) {
  const std::size_t d = checked_direction(dir);
  const Domain dom = domain(s, dir);
  if (times < 0) detail::fail("remove: times = ", times, " is negative");
  if (!(tolerance >= 0)) detail::fail("remove: tolerance ", tolerance, " must be non-negative");
  if (!(t > dom.start && t < dom.end))
    detail::fail("remove: direction ", kDirName[d], ": knot ", t, " is not interior to the domain (",
                 dom.start, ", ", dom.end, ")");
  const int has = multiplicity(s.knots[d], t);
  if (has == 0) detail::fail("remove: direction ", kDirName[d], ": ", t, " is not a knot");
  const Removal r = detail::remove_knot(direction_curve(s, dir), t, std::min(times, has), tolerance,
                                        {s.P.cols(), s.rational});
  return {from_direction_curve(s, dir, r.curve), r.removed, r.deviation_bound};
}

Surface elevate_degree(const Surface& s, Direction dir, int times) {
  const std::size_t d = checked_direction(dir);
  try {
    return from_direction_curve(s, dir, elevate_degree(direction_curve(s, dir), times));
  } catch (const InvalidInput& e) {
    detail::fail("direction ", kDirName[d], ": ", e.what());
  }
}

SurfaceReduction reduce_degree(const Surface& s, Direction dir, double tolerance) {
  const std::size_t d = checked_direction(dir);
  const int degree = s.degree[d];
  if (degree < 2)
    detail::fail("reduce_degree: direction ", kDirName[d], ": degree ", degree,
                 " cannot be reduced (the least is 1)");
  if (!(tolerance >= 0)) detail::fail("reduce_degree: tolerance ", tolerance, " must be non-negative");
  Reduction r;
  try {
    r = detail::reduce_degree(direction_curve(s, dir), {s.P.cols(), s.rational});
  } catch (const InvalidInput& e) {
    detail::fail("reduce_degree: direction ", kDirName[d], ": ", e.what());
  }
  if (!(r.deviation_bound <= tolerance))
    detail::fail("reduce_degree: direction ", kDirName[d], ": the surface of degree ", degree - 1,
                 " is within ", r.deviation_bound, " of the surface, more than the tolerance ", tolerance);
  Surface out = from_direction_curve(s, dir, r.curve);
  validate(out);
  return {std::move(out), r.deviation_bound};
}

std::vector<Surface> split_bezier(const Surface& s) {
  std::vector<Surface> patches;
  for (const Curve& strip : split_bezier(direction_curve(s, Direction::u))) {
    const Surface band = from_direction_curve(s, Direction::u, strip);
    for (const Curve& piece : split_bezier(direction_curve(band, Direction::v)))
      patches.push_back(from_direction_curve(band, Direction::v, piece));
  }
  return patches;
}

Surface reverse(const Surface& s, Direction dir) {
  const std::size_t d = checked_direction(dir);
  Surface out = s;
  out.knots[d] = detail::mirrored_knots(s.knots[d], domain(s, dir));
  const Eigen::Index nu = s.count[0], nv = s.count[1];
  for (Eigen::Index i = 0; i < nu; ++i)
    for (Eigen::Index j = 0; j < nv; ++j)
      out.P.row(i * nv + j) = s.P.row(d == 0 ? (nu - 1 - i) * nv + j : i * nv + (nv - 1 - j));
  return out;
}

Surface swap_uv(const Surface& s) {
  const Eigen::Index nu = s.count[0], nv = s.count[1];
  Surface out{{s.degree[1], s.degree[0]},
              {s.knots[1], s.knots[0]},
              {nv, nu},
              Points(s.P.rows(), s.P.cols()),
              s.rational};
  for (Eigen::Index i = 0; i < nu; ++i)
    for (Eigen::Index j = 0; j < nv; ++j) out.P.row(j * nu + i) = s.P.row(i * nv + j);
  return out;
}

Surface reparametrize(const Surface& s, Direction dir, double start, double end) {
  const std::size_t d = checked_direction(dir);
  Surface out = s;
  try {
    out.knots[d] = detail::mapped_knots(s.knots[d], domain(s, dir), start, end);
  } catch (const InvalidInput& e) {
    detail::fail("reparametrize: direction ", kDirName[d], ": ", e.what());
  }
  validate(out);
  return out;
}

Surface normalize_knots(const Surface& s) {
  return reparametrize(reparametrize(s, Direction::u, 0.0, 1.0), Direction::v, 0.0, 1.0);
}

Curvature curvature(const Surface& s, double u, double v) {
  if (dimension(s) != 3)
    detail::fail("curvature: the surface is ", dimension(s), "-D; curvature needs a 3-D surface");
  const Points D = derivatives(s, u, v, 2);  // row k·3 + l: ∂^{k+l} / ∂u^k ∂v^l
  const auto [Su, Sv] = tangent_partials(s, u, v, D, 2, "curvature: the first fundamental form is singular");
  const Eigen::Vector3d cross = Su.cross(Sv);
  const double area = cross.norm();  // √(EG − F²)
  Curvature out;
  out.point = D.row(0).transpose();
  out.normal = cross / area;
  const Eigen::Vector3d& n = out.normal;
  const double L = D.row(6).dot(n), M = D.row(4).dot(n), N = D.row(2).dot(n);
  // The shape operator in the orthonormal tangent basis e1 = S_u/|S_u|, e2 = n × e1 is the symmetric
  // [[a, b], [b, c]]: its eigenvalues need no H² − K, which cancels near an umbilic. e2 = (S_v − (F/E)·S_u)/h
  // with h = |S_u × S_v|/|S_u|, so in parameters e1 = (1/|S_u|, 0) and e2 = (−F/(E·h), 1/h).
  const double len = Su.norm(), E = Su.squaredNorm(), F = Su.dot(Sv), h = area / len;
  const double du = -F / (E * h), dv = 1 / h;
  const double a = L / E, b = (L * du + M * dv) / len, c = L * du * du + 2 * M * du * dv + N * dv * dv;
  out.mean = 0.5 * (a + c);
  out.gaussian = a * c - b * b;
  const double half_gap = std::hypot(0.5 * (a - c), b);
  out.principal = {out.mean + half_gap, out.mean - half_gap};
  const double theta = 0.5 * std::atan2(2 * b, a - c);  // the eigenvector of the larger eigenvalue
  const Eigen::Vector3d e1 = Su / len, e2 = n.cross(e1);
  out.directions[0] = std::cos(theta) * e1 + std::sin(theta) * e2;
  out.directions[1] = n.cross(out.directions[0]);
  return out;
}

}  // namespace cifs::nurbs
