// SPDX-License-Identifier: MIT
#include "cifs/nurbs/volume.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/surface.hpp"
#include "detail.hpp"
#include "lines.hpp"

namespace cifs::nurbs {
namespace {

std::size_t checked_volume_direction(int direction) {
  if (direction < 0 || direction > 2) detail::fail("direction ", direction, " is not u (0), v (1) or w (2)");
  return static_cast<std::size_t>(direction);
}

constexpr const char* kVolumeDirName[3] = {"u", "v", "w"};

/// t, or a throw naming the direction when it is outside that direction's domain.
double checked_volume_parameter(const Volume& vol, std::size_t d, double t) {
  const Domain dom = domain(vol.knots[d], vol.degree[d]);
  if (!std::isfinite(t) || t < dom.start || t > dom.end)
    detail::fail("parameter ", kVolumeDirName[d], " = ", t, " is outside the domain [", dom.start, ", ",
                 dom.end, "]");
  return t;
}

/// The row of control point (a, b, c) given in the order (direction, then the other two in order).
Eigen::Index row_of(const std::array<Eigen::Index, 3>& count, std::size_t d, Eigen::Index a, Eigen::Index b,
                    Eigen::Index c) {
  std::array<Eigen::Index, 3> index{};
  index[d] = a;
  index[d == 0 ? 1 : 0] = b;
  index[d == 2 ? 1 : 2] = c;
  return (index[0] * count[1] + index[1]) * count[2] + index[2];
}

}  // namespace

Volume make_volume(std::array<int, 3> degree, std::array<Knots, 3> knots, std::array<Eigen::Index, 3> count,
                   const Points& points, const Eigen::VectorXd& weights) {
  if (count[0] < 1 || count[1] < 1 || count[2] < 1 || count[0] * count[1] * count[2] != points.rows())
    detail::fail("points: ", points.rows(), " control points do not form a ", count[0], " by ", count[1],
                 " by ", count[2], " net");
  Volume v{degree, std::move(knots), count, detail::homogeneous(points, weights, "points"),
           weights.size() > 0};
  validate(v);
  return v;
}

void validate(const Volume& v) {
  for (std::size_t d = 0; d < 3; ++d) {
    validate_degree(v.degree[d], "degree[" + std::to_string(d) + "]");
    validate_knots(v.knots[d], v.degree[d], v.count[d], "knots[" + std::to_string(d) + "]");
  }
  if (v.P.rows() != v.count[0] * v.count[1] * v.count[2])
    detail::fail("points: ", v.P.rows(), " rows for a ", v.count[0], " by ", v.count[1], " by ", v.count[2],
                 " net");
  if (v.P.cols() < (v.rational ? 2 : 1)) detail::fail("points: control points have no coordinates");
  for (Eigen::Index r = 0; r < v.P.rows(); ++r) {
    const double w = v.rational ? v.P(r, v.P.cols() - 1) : 1.0;
    if (!(w > 0) || !std::isfinite(w))
      detail::fail("weights[", r, "]: weight ", w, " is not a positive finite number");
    if (!v.P.row(r).allFinite()) detail::fail("points[", r, "]: a coordinate is not finite");
  }
}

Curve direction_curve(const Volume& vol, int direction) {
  const std::size_t d = checked_volume_direction(direction);
  const std::array<Eigen::Index, 3>& n = vol.count;
  const Eigen::Index nb = n[d == 0 ? 1 : 0], nc = n[d == 2 ? 1 : 2], cols = vol.P.cols();
  Curve c{vol.degree[d], vol.knots[d], Points(n[d], nb * nc * cols), false, false};
  if (d == 0) {  // the slabs along u are the stored rows already, in order
    c.P = Eigen::Map<const Points>(vol.P.data(), n[0], nb * nc * cols);
    return c;
  }
  for (Eigen::Index a = 0; a < n[d]; ++a)
    for (Eigen::Index b = 0; b < nb; ++b)
      for (Eigen::Index k = 0; k < nc; ++k)
        c.P.block(a, (b * nc + k) * cols, 1, cols) = vol.P.row(row_of(n, d, a, b, k));
  return c;
}

namespace {

/// The volume whose net along direction d is the curve of slabs c (as direction_curve makes it), the
/// other directions as in vol.
Volume from_direction_curve(const Volume& vol, std::size_t d, const Curve& c) {
  Volume out = vol;
  out.degree[d] = c.degree;
  out.knots[d] = c.knots;
  out.count[d] = c.P.rows();
  const std::array<Eigen::Index, 3>& n = out.count;
  const Eigen::Index nb = n[d == 0 ? 1 : 0], nc = n[d == 2 ? 1 : 2], cols = vol.P.cols();
  if (d == 0) {
    out.P = Eigen::Map<const Points>(c.P.data(), n[0] * nb * nc, cols);
    return out;
  }
  out.P.resize(n[0] * n[1] * n[2], cols);
  for (Eigen::Index a = 0; a < n[d]; ++a)
    for (Eigen::Index b = 0; b < nb; ++b)
      for (Eigen::Index k = 0; k < nc; ++k)
        out.P.row(row_of(n, d, a, b, k)) = c.P.block(a, (b * nc + k) * cols, 1, cols);
  return out;
}

/// A curve operation on the direction curve of d, its refusals prefixed with the direction.
template <class F>
Volume along(const Volume& vol, int direction, F&& operation) {
  const std::size_t d = checked_volume_direction(direction);
  Curve c;
  try {
    c = operation(direction_curve(vol, direction));
  } catch (const InvalidInput& e) {
    detail::fail("direction ", kVolumeDirName[d], ": ", e.what());
  }
  return from_direction_curve(vol, d, c);
}

/// The surface (in v and w) whose net is a slab of the volume: `slab` holds nv·nw stored rows.
Surface slab_surface(const Volume& vol, std::size_t d, const Point& slab) {
  const std::size_t b = d == 0 ? 1 : 0, c = d == 2 ? 1 : 2;
  return Surface{{vol.degree[b], vol.degree[c]},
                 {vol.knots[b], vol.knots[c]},
                 {vol.count[b], vol.count[c]},
                 Eigen::Map<const Points>(slab.data(), vol.count[b] * vol.count[c], vol.P.cols()),
                 vol.rational};
}

/// The net combined along u at u (in the domain): the surface net Σ N_i(u)·slab_i (homogeneous rows),
/// from the p + 1 stored slabs under u's span, without copying the net.
Point slab_at_u(const Volume& vol, double u) {
  const int p = vol.degree[0];
  const Eigen::Index width = vol.count[1] * vol.count[2] * vol.P.cols();
  const int span = find_span(vol.knots[0], p, u);
  double N[kMaxDegree + 1];
  basis_functions(vol.knots[0], p, span, u, N);
  Point slab = Point::Zero(width);
  for (int r = 0; r <= p; ++r)
    slab += N[r] * Eigen::Map<const Point>(vol.P.data() + (span - p + r) * width, width);
  return slab;
}

}  // namespace

Point evaluate(const Volume& vol, double u, double v, double w) {
  const double at[3] = {u, v, w};
  for (std::size_t d = 0; d < 3; ++d) checked_volume_parameter(vol, d, at[d]);
  // Along u: the slab at u (a surface net in v and w, stored rows), then the surface at (v, w).
  return evaluate(slab_surface(vol, 0, slab_at_u(vol, u)), v, w);
}

Points evaluate_grid(const Volume& vol, std::span<const double> us, std::span<const double> vs,
                     std::span<const double> ws) {
  const std::span<const double> at[3] = {us, vs, ws};
  for (std::size_t d = 0; d < 3; ++d)
    if (!detail::scan(at[d], domain(vol.knots[d], vol.degree[d])).inside)
      for (double t : at[d]) checked_volume_parameter(vol, d, t);
  const auto block = static_cast<Eigen::Index>(vs.size() * ws.size());
  const int dim = dimension(vol);
  Points out(static_cast<Eigen::Index>(us.size()) * block, dim);
  if (block == 0) return out;
  Points rows;
  for (std::size_t a = 0; a < us.size(); ++a) {
    evaluate_grid(slab_surface(vol, 0, slab_at_u(vol, us[a])), vs, ws, rows);
    out.middleRows(static_cast<Eigen::Index>(a) * block, block) = rows;
  }
  return out;
}

Points derivatives(const Volume& vol, double u, double v, double w, int order) {
  detail::check_derivative_order(order);
  const double at[3] = {u, v, w};
  std::array<int, 3> span{};
  std::array<Eigen::MatrixXd, 3> D;  // D[d](k, r): k-th derivative of basis function span − p + r
  for (std::size_t d = 0; d < 3; ++d) {
    checked_volume_parameter(vol, d, at[d]);
    span[d] = find_span(vol.knots[d], vol.degree[d], at[d]);
    D[d] = basis_derivatives(vol.knots[d], vol.degree[d], span[d], at[d], order);
  }
  const std::array<int, 3>& p = vol.degree;
  const Eigen::Index n = order + 1, cols = vol.P.cols();
  const auto row = [n](int a, int b, int c) { return (a * n + b) * n + c; };
  Points H = Points::Zero(n * n * n, cols);  // homogeneous partials
  for (int a = 0; a <= order; ++a)
    for (int b = 0; a + b <= order; ++b)
      for (int c = 0; a + b + c <= order; ++c)
        for (int i = 0; i <= p[0]; ++i)
          for (int j = 0; j <= p[1]; ++j) {
            const double f = D[0](a, i) * D[1](b, j);
            if (f == 0) continue;
            for (int k = 0; k <= p[2]; ++k)
              H.row(row(a, b, c)) +=
                  f * D[2](c, k) *
                  vol.P.row(row_of(vol.count, 0, span[0] - p[0] + i, span[1] - p[1] + j, span[2] - p[2] + k));
          }
  if (!vol.rational) return H;
  // Quotient rule in three variables (A = w·V, so ∂^α A = Σ_{β ≤ α} C(α, β) ∂^β w ∂^{α−β} V): every
  // partial from the lower ones, which the loop order (a, b, c increasing) has computed already.
  const int dim = dimension(vol);
  const auto binom = [](int m, int k) {
    double x = 1;
    for (int i = 1; i <= k; ++i) x = x * (m - k + i) / i;
    return x;
  };
  Points S = Points::Zero(n * n * n, dim);
  for (int a = 0; a <= order; ++a)
    for (int b = 0; a + b <= order; ++b)
      for (int c = 0; a + b + c <= order; ++c) {
        Point val = H.row(row(a, b, c)).head(dim);
        for (int i = 0; i <= a; ++i)
          for (int j = 0; j <= b; ++j)
            for (int k = 0; k <= c; ++k)
              if (i + j + k > 0)
                val -= binom(a, i) * binom(b, j) * binom(c, k) * H(row(i, j, k), dim) *
                       S.row(row(a - i, b - j, c - k));
        S.row(row(a, b, c)) = val / H(0, dim);
      }
  return S;
}

Volume insert_knot(const Volume& vol, int direction, double t, int times) {
  return along(vol, direction, [&](const Curve& c) { return insert_knot(c, t, times); });
}

Volume refine(const Volume& vol, int direction, std::span<const double> new_knots) {
  return along(vol, direction, [&](const Curve& c) { return refine(c, new_knots); });
}

VolumeRemoval remove_knot(const Volume& vol, int direction, double t, int times, double tolerance) {
  const std::size_t d = checked_volume_direction(direction);
  const Domain dom = domain(vol.knots[d], vol.degree[d]);
  if (times < 0) detail::fail("remove: times = ", times, " is negative");
  if (!(tolerance >= 0)) detail::fail("remove: tolerance ", tolerance, " must be non-negative");
  if (!(t > dom.start && t < dom.end))
    detail::fail("remove: direction ", kVolumeDirName[d], ": knot ", t, " is not interior to the domain (",
                 dom.start, ", ", dom.end, ")");
  const int has = multiplicity(vol.knots[d], t);
  if (has == 0) detail::fail("remove: direction ", kVolumeDirName[d], ": ", t, " is not a knot");
  const Removal r = detail::remove_knot(direction_curve(vol, direction), t, std::min(times, has), tolerance,
                                        {vol.P.cols(), vol.rational});
  return {from_direction_curve(vol, d, r.curve), r.removed, r.deviation_bound};
}

Volume elevate_degree(const Volume& vol, int direction, int times) {
  return along(vol, direction, [&](const Curve& c) { return elevate_degree(c, times); });
}

std::array<Volume, 2> split(const Volume& vol, int direction, double t) {
  std::array<Curve, 2> parts;
  const Volume first = along(vol, direction, [&](const Curve& c) {
    parts = split(c, t);
    return parts[0];
  });
  return {first, from_direction_curve(vol, static_cast<std::size_t>(direction), parts[1])};
}

Surface iso_surface(const Volume& vol, int direction, double t) {
  const std::size_t d = checked_volume_direction(direction);
  checked_volume_parameter(vol, d, t);
  // The slabs' combination at t (homogeneous rows combine linearly): the other two directions' net.
  Surface out = slab_surface(vol, d, evaluate(direction_curve(vol, direction), t));
  validate(out);
  return out;
}

Volume reverse(const Volume& vol, int direction) {
  return along(vol, direction, [](const Curve& c) { return reverse(c); });
}

Volume reparametrize(const Volume& vol, int direction, double start, double end) {
  const std::size_t d = checked_volume_direction(direction);
  Volume out = vol;
  try {
    out.knots[d] = detail::mapped_knots(vol.knots[d], domain(vol.knots[d], vol.degree[d]), start, end);
  } catch (const InvalidInput& e) {
    detail::fail("reparametrize: direction ", kVolumeDirName[d], ": ", e.what());
  }
  validate(out);
  return out;
}

Volume normalize_knots(const Volume& vol) {
  Volume out = vol;
  for (int d = 0; d < 3; ++d) out = reparametrize(out, d, 0.0, 1.0);
  return out;
}

}  // namespace cifs::nurbs
