// SPDX-License-Identifier: MIT
#include "cifs/nurbs/volume.hpp"

#include <cmath>
#include <string>

#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/surface.hpp"
#include "detail.hpp"

namespace cifs::nurbs {
namespace {

std::size_t checked_volume_direction(int direction) {
  if (direction < 0 || direction > 2) detail::fail("direction ", direction, " is not u (0), v (1) or w (2)");
  return static_cast<std::size_t>(direction);
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
  for (Eigen::Index a = 0; a < n[d]; ++a)
    for (Eigen::Index b = 0; b < nb; ++b)
      for (Eigen::Index k = 0; k < nc; ++k)
        c.P.block(a, (b * nc + k) * cols, 1, cols) = vol.P.row(row_of(n, d, a, b, k));
  return c;
}

Point evaluate(const Volume& vol, double u, double v, double w) {
  const double at[3] = {u, v, w};
  for (std::size_t d = 0; d < 3; ++d) {
    const Domain dom = domain(vol.knots[d], vol.degree[d]);
    if (!std::isfinite(at[d]) || at[d] < dom.start || at[d] > dom.end)
      detail::fail("parameter ", "uvw"[d], " = ", at[d], " is outside the domain [", dom.start, ", ", dom.end,
                   "]");
  }
  // Along u: the slab at u (a surface net in v and w, stored rows), then the surface at (v, w).
  const Point slab = evaluate(direction_curve(vol, 0), u);
  const Surface s{{vol.degree[1], vol.degree[2]},
                  {vol.knots[1], vol.knots[2]},
                  {vol.count[1], vol.count[2]},
                  Eigen::Map<const Points>(slab.data(), vol.count[1] * vol.count[2], vol.P.cols()),
                  vol.rational};
  return evaluate(s, v, w);
}

Volume insert_knot(const Volume& vol, int direction, double t, int times) {
  const std::size_t d = checked_volume_direction(direction);
  const Curve c = [&] {
    try {
      return insert_knot(direction_curve(vol, direction), t, times);
    } catch (const InvalidInput& e) {
      detail::fail("direction ", "uvw"[d], ": ", e.what());
    }
  }();
  Volume out = vol;
  out.knots[d] = c.knots;
  out.count[d] = c.P.rows();
  const std::array<Eigen::Index, 3>& n = out.count;
  const Eigen::Index nb = n[d == 0 ? 1 : 0], nc = n[d == 2 ? 1 : 2], cols = vol.P.cols();
  out.P.resize(n[0] * n[1] * n[2], cols);
  for (Eigen::Index a = 0; a < n[d]; ++a)
    for (Eigen::Index b = 0; b < nb; ++b)
      for (Eigen::Index k = 0; k < nc; ++k)
        out.P.row(row_of(n, d, a, b, k)) = c.P.block(a, (b * nc + k) * cols, 1, cols);
  return out;
}

}  // namespace cifs::nurbs
