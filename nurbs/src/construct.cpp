// SPDX-License-Identifier: MIT
#include "cifs/nurbs/construct.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "cifs/files.hpp"
#include "cifs/nurbs/refine.hpp"
#include "detail.hpp"

namespace cifs::nurbs {
namespace {

void check_finite(const Eigen::Ref<const Eigen::MatrixXd>& x, std::string_view what) {
  if (!x.allFinite()) detail::fail(what, ": a coordinate is not finite");
}

/// Surface of nets whose lines along v are given column by column: `columns[j]` holds the n control rows
/// of the j-th line of u (stored coordinates), so that point (i, j) is columns[j].row(i).
Surface from_columns(const Curve& u_shape, const std::vector<Points>& columns, int degree_v, Knots knots_v) {
  const Eigen::Index n = u_shape.P.rows(), m = static_cast<Eigen::Index>(columns.size());
  Surface s{{u_shape.degree, degree_v},
            {u_shape.knots, std::move(knots_v)},
            {n, m},
            Points(n * m, u_shape.P.cols()),
            u_shape.rational};
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = 0; i < n; ++i) s.P.row(i * m + j) = columns[static_cast<std::size_t>(j)].row(i);
  validate(s);
  return s;
}

/// Stored rows with weight 1 added (a non-rational curve as a rational one).
Curve as_rational(const Curve& c) {
  if (c.rational) return c;
  Curve out = c;
  out.P.resize(c.P.rows(), c.P.cols() + 1);
  out.P.leftCols(c.P.cols()) = c.P;
  out.P.col(c.P.cols()).setOnes();
  out.rational = true;
  return out;
}

/// Stored row of a Cartesian point x with weight w.
Point stored_row(const Eigen::Ref<const Point>& x, double w, bool rational) {
  if (!rational) return x;
  Point r(x.size() + 1);
  r.head(x.size()) = w * x;
  r(x.size()) = w;
  return r;
}

/// The rows of a curve's control points moved by `shift` (stored coordinates: w·shift for rational ones).
Points moved_rows(const Curve& c, const Point& shift) {
  Points P = c.P;
  const int dim = dimension(c);
  for (Eigen::Index i = 0; i < P.rows(); ++i) P.row(i).head(dim) += (c.rational ? P(i, dim) : 1.0) * shift;
  return P;
}

/// The largest distance of a curve's Cartesian control points from the first (the scale of its tests).
double extent(const Points& cart) {
  return (cart.rowwise() - cart.row(0)).rowwise().norm().maxCoeff();
}

/// A closed curve as the open clamped curve of the same pieces on its period (cut at the seam): the
/// breakpoints with both ends raised to d + 1 copies, each control point the blossom of its d knots
/// (computed on the periodic curve's own relative knots, so the stored periodic knots' rounding stays out);
/// the last point is the first (both are C at the seam). Open curves are returned as they are.
Curve opened(const Curve& c) {
  if (!c.closed) return c;
  const int p = c.degree;
  const Knots b = defining_knots(c);
  Knots t(static_cast<std::size_t>(p) + 1, b.front());
  for (const double x : b)
    if (x > b.front() && x < b.back()) t.push_back(x);
  t.insert(t.end(), static_cast<std::size_t>(p) + 1, b.back());
  const Eigen::Index n = static_cast<Eigen::Index>(t.size()) - p - 1;
  Curve out{p, t, Points(n, c.P.cols()), c.rational, false};
  for (Eigen::Index j = 0; j + 1 < n; ++j)
    out.P.row(j) = blossom(c, std::span<const double>(t.data() + j + 1, static_cast<std::size_t>(p)));
  out.P.row(n - 1) = out.P.row(0);
  validate(out);
  return out;
}

}  // namespace

std::vector<Curve> make_compatible(std::span<const Curve> curves) {
  if (curves.empty()) detail::fail("curves: none given");
  int degree = 0;
  bool rational = false;
  for (std::size_t k = 0; k < curves.size(); ++k) {
    try {
      validate(curves[k]);
    } catch (const InvalidInput& e) {
      detail::fail("curves[", k, "]: ", e.what());
    }
    if (dimension(curves[k]) != dimension(curves[0]))
      detail::fail("curves[", k, "]: dimension ", dimension(curves[k]), ", curves[0] has ",
                   dimension(curves[0]));
    degree = std::max(degree, curves[k].degree);
    rational = rational || curves[k].rational;
  }
  const Domain first = domain(curves[0]);
  std::vector<Curve> out;
  for (const Curve& c : curves) {
    Curve d = detail::clamped(opened(c));
    if (rational) d = as_rational(d);
    d = elevate_degree(d, degree - d.degree);
    const Domain dom = domain(d);
    if (dom.start != first.start || dom.end != first.end) d = reparametrize(d, first.start, first.end);
    out.push_back(std::move(d));
  }
  // The union of the knot vectors: each value with its largest multiplicity (sorted multisets).
  Knots all;
  for (const Curve& c : out) {
    Knots merged;
    std::set_union(all.begin(), all.end(), c.knots.begin(), c.knots.end(), std::back_inserter(merged));
    all = std::move(merged);
  }
  for (Curve& c : out) {
    Knots missing;
    std::set_difference(all.begin(), all.end(), c.knots.begin(), c.knots.end(), std::back_inserter(missing));
    if (!missing.empty()) c = refine(c, missing);
  }
  return out;
}

Surface ruled(const Curve& a, const Curve& b) {
  const Curve both[2] = {a, b};
  const std::vector<Curve> c = make_compatible(both);
  return from_columns(c[0], {c[0].P, c[1].P}, 1, {0, 0, 1, 1});
}

Surface extrude(const Curve& curve, const Point& direction) {
  validate(curve);
  const int dim = dimension(curve);
  if (direction.size() != dim)
    detail::fail("direction: ", direction.size(), " coordinates for a curve of dimension ", dim);
  check_finite(direction, "direction");
  const double length = direction.norm();
  if (!(length > 0)) detail::fail("direction: the zero vector");
  // A straight curve along the direction sweeps no area: every control point on the line of the first.
  const Points cart = cartesian_points(curve);
  const Point unit = direction / length;
  double off_line = 0;
  for (Eigen::Index i = 0; i < cart.rows(); ++i) {
    const Point x = cart.row(i) - cart.row(0);
    off_line = std::max(off_line, (x - x.dot(unit) * unit).norm());
  }
  const double size = extent(cart);
  if (!(size > 0)) detail::fail("curve: a single point (the surface has no area)");
  if (!(off_line > 1e-14 * size))
    detail::fail("direction: parallel to the curve, which is straight along it (the surface has no area)");
  const Curve shape = opened(curve);
  return from_columns(shape, {shape.P, moved_rows(shape, direction)}, 1, {0, 0, 1, 1});
}

Surface revolve(const Curve& profile, const Eigen::Vector3d& axis_point,
                const Eigen::Vector3d& axis_direction, double angle) {
  validate(profile);
  if (dimension(profile) != 3) detail::fail("profile: dimension ", dimension(profile), ", revolve needs 3");
  check_finite(axis_point, "axis_point");
  check_finite(axis_direction, "axis_direction");
  const double norm = axis_direction.norm();
  if (!(norm > 0)) detail::fail("axis_direction: the zero vector");
  if (!std::isfinite(angle) || !(angle > 0) || angle > 2 * std::numbers::pi)
    detail::fail("angle: ", angle, " is outside (0, 2π]");
  const Eigen::Vector3d a = axis_direction / norm;
  const Curve shape = as_rational(opened(profile));
  const Points cart = cartesian_points(shape);
  const Eigen::VectorXd w = weights(shape);
  // Each control point's foot on the axis O and its offset X (|X| = r); Y = a × X completes the plane.
  const Eigen::Index n = cart.rows();
  std::vector<Eigen::Vector3d> O(static_cast<std::size_t>(n)), X(O.size()), Y(O.size());
  double radius = 0, size = (cart.rowwise() - axis_point.transpose()).rowwise().norm().maxCoeff();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = cart.row(i).transpose() - axis_point;
    const auto k = static_cast<std::size_t>(i);
    O[k] = axis_point + p.dot(a) * a;
    X[k] = p - p.dot(a) * a;
    Y[k] = a.cross(X[k]);
    radius = std::max(radius, X[k].norm());
  }
  if (!(radius > 1e-14 * size)) detail::fail("profile: every control point lies on the axis (no surface)");
  // ⌈angle / (π/2)⌉ arcs of φ, every one at most a quarter turn (A8.1).
  const int arcs = angle <= std::numbers::pi / 2       ? 1
                   : angle <= std::numbers::pi         ? 2
                   : angle <= 3 * std::numbers::pi / 2 ? 3
                                                       : 4;
  const double phi = angle / arcs, mid_weight = std::cos(phi / 2);
  Knots kv(3, 0.0);
  for (int k = 1; k < arcs; ++k) kv.insert(kv.end(), 2, static_cast<double>(k) / arcs);
  kv.insert(kv.end(), 3, 1.0);
  const bool full = angle == 2 * std::numbers::pi;
  std::vector<Points> columns;
  for (int j = 0; j <= 2 * arcs; ++j) {
    if (j == 0 || (full && j == 2 * arcs)) {  // the profile itself; a full turn closes on it exactly
      columns.push_back(shape.P);
      continue;
    }
    const double theta = j * phi / 2;
    const bool middle = j % 2 == 1;  // the tangents' intersection, at 1/cos(φ/2) of the radius
    const double c = std::cos(theta) / (middle ? mid_weight : 1.0),
                 s = std::sin(theta) / (middle ? mid_weight : 1.0);
    Points col(n, 4);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const Eigen::Vector3d x = O[k] + c * X[k] + s * Y[k];
      col.row(i) = stored_row(x.transpose(), w(i) * (middle ? mid_weight : 1.0), true);
    }
    columns.push_back(std::move(col));
  }
  return from_columns(shape, columns, 2, std::move(kv));
}

namespace {

/// The v-parameters of compatible curves: for each column of control points (the i-th point of every
/// curve) its cumulative chords (uniform: 1, centripetal: their square roots) over their total, averaged
/// over the columns; a column whose points all coincide (a pole) is left out.
std::vector<double> column_parameters(const std::vector<Curve>& c, Parametrization kind) {
  const auto m = c.size();
  std::vector<Points> cart(m);
  for (std::size_t k = 0; k < m; ++k) cart[k] = cartesian_points(c[k]);
  std::vector<double> v(m, 0.0), u(m);
  int columns = 0;
  for (Eigen::Index i = 0; i < cart[0].rows(); ++i) {
    u[0] = 0;
    for (std::size_t k = 1; k < m; ++k) {
      const double d = (cart[k].row(i) - cart[k - 1].row(i)).norm();
      u[k] = u[k - 1] + (kind == Parametrization::uniform       ? 1.0
                         : kind == Parametrization::centripetal ? std::sqrt(d)
                                                                : d);
    }
    if (!(u[m - 1] > 0)) continue;
    ++columns;
    for (std::size_t k = 1; k < m; ++k) v[k] += u[k] / u[m - 1];
  }
  if (columns == 0) detail::fail("loft: the curves coincide (every column of control points is one point)");
  for (std::size_t k = 1; k < m; ++k) {
    v[k] = k + 1 == m ? 1.0 : v[k] / columns;
    if (!(v[k] > v[k - 1]))
      detail::fail("loft: curves[", k - 1, "] and curves[", k,
                   "] coincide (equal compatible control points)");
  }
  return v;
}

}  // namespace

std::vector<double> loft_parameters(std::span<const Curve> curves, Parametrization parametrization) {
  if (curves.size() < 2) detail::fail("curves: ", curves.size(), " given, a loft needs at least 2");
  return column_parameters(make_compatible(curves), parametrization);
}

namespace {

/// The skinned surface through compatible curves at the given v-parameters.
Surface skin(const std::vector<Curve>& c, std::span<const double> v, int degree_v) {
  const Eigen::Index n = c[0].P.rows(), cols = c[0].P.cols(), m = static_cast<Eigen::Index>(c.size());
  Points lines(m, n * cols);  // row k: the k-th curve's control rows, flattened
  for (Eigen::Index k = 0; k < m; ++k)
    lines.row(k) = Eigen::Map<const Point>(c[static_cast<std::size_t>(k)].P.data(), n * cols);
  const Curve across = interpolate(lines, v, degree_v);
  const Eigen::Index q = across.P.rows();
  std::vector<Points> columns(static_cast<std::size_t>(q));
  for (Eigen::Index j = 0; j < q; ++j) {
    columns[static_cast<std::size_t>(j)] = Eigen::Map<const Points>(across.P.row(j).data(), n, cols);
    if (c[0].rational)
      for (Eigen::Index i = 0; i < n; ++i)
        if (const double w = columns[static_cast<std::size_t>(j)](i, cols - 1); !(w > 0))
          detail::fail("loft: the interpolated weight of control point (", i, ", ", j, ") is ", w,
                       ", not positive (the curves' weights differ too much)");
  }
  return from_columns(c[0], columns, degree_v, across.knots);
}

void check_degree_v(int degree_v, std::size_t curves, std::string_view what) {
  if (degree_v < 1 || static_cast<std::size_t>(degree_v) >= curves)
    detail::fail(what, ": degree_v ", degree_v, " is outside 1 … ", curves - 1, " (", curves, " ",
                 what == "loft" ? "curves" : "instances", ")");
}

}  // namespace

Surface loft(std::span<const Curve> curves, const LoftOptions& o) {
  if (curves.size() < 2) detail::fail("curves: ", curves.size(), " given, a loft needs at least 2");
  check_degree_v(o.degree_v, curves.size(), "loft");
  const std::vector<Curve> c = make_compatible(curves);
  return skin(c, column_parameters(c, o.parametrization), o.degree_v);
}

Points rotation_minimizing_frames(const Curve& curve, int count, int steps) {
  validate(curve);
  if (dimension(curve) != 3) detail::fail("trajectory: dimension ", dimension(curve), ", frames need 3");
  if (count < 1) detail::fail("count: ", count, " is not positive");
  if (steps < 1) detail::fail("steps: ", steps, " is not positive");
  const Domain dom = domain(curve);
  const auto total = static_cast<long>(count - 1) * steps;
  const auto at = [&](long i) {
    return i == total
               ? dom.end
               : dom.start + (dom.end - dom.start) * static_cast<double>(i) / static_cast<double>(total);
  };
  const auto point_and_tangent = [&](double u, Eigen::Vector3d& x, Eigen::Vector3d& t) {
    const Points d = derivatives(curve, u, 1);
    x = d.row(0).transpose();
    const double speed = d.row(1).norm();
    if (!(speed > 1e-14 * (1 + x.norm())))
      detail::fail("trajectory: the tangent vanishes at u = ", u, " (no frame)");
    t = d.row(1).transpose() / speed;
  };
  Eigen::Vector3d x, t;
  point_and_tangent(dom.start, x, t);
  // The first r: the Frenet normal where defined, else the axis least aligned with t made normal to it.
  Eigen::Vector3d r;
  {
    const Points d = derivatives(curve, dom.start, 2);
    const Eigen::Vector3d c1 = d.row(1).transpose(), c2 = d.row(2).transpose();
    const Eigen::Vector3d b = c1.cross(c2);
    if (b.norm() > 1e-10 * c1.squaredNorm() * (1 + c2.norm() / c1.norm())) {
      r = b.cross(c1).normalized();
    } else {
      Eigen::Index axis = 0;
      t.cwiseAbs().minCoeff(&axis);
      r = (Eigen::Vector3d::Unit(axis) - t(axis) * t).normalized();
    }
  }
  Points out(count, 6);
  out.row(0) << t.transpose(), r.transpose();
  for (long i = 1; i <= total; ++i) {
    Eigen::Vector3d x1, t1;
    point_and_tangent(at(i), x1, t1);
    // Double reflection: in the plane bisecting x → x1, then in the one that takes the reflected tangent to
    // t1.
    const Eigen::Vector3d v1 = x1 - x;
    const double c1 = v1.squaredNorm();
    Eigen::Vector3d rl = r, tl = t;
    if (c1 > 0) {
      rl = r - (2 / c1) * v1.dot(r) * v1;
      tl = t - (2 / c1) * v1.dot(t) * v1;
    }
    const Eigen::Vector3d v2 = t1 - tl;
    const double c2 = v2.squaredNorm();
    r = c2 > 0 ? Eigen::Vector3d(rl - (2 / c2) * v2.dot(rl) * v2) : rl;
    r = (r - r.dot(t1) * t1).normalized();  // rounding only: the reflections keep r unit and normal to t1
    x = x1;
    t = t1;
    if (i % steps == 0) out.row(i / steps) << t.transpose(), r.transpose();
  }
  return out;
}

Sweep sweep(const Curve& profile, const Curve& trajectory, const SweepOptions& o) {
  validate(profile);
  validate(trajectory);
  if (dimension(profile) != dimension(trajectory))
    detail::fail("trajectory: dimension ", dimension(trajectory), ", the profile has ", dimension(profile));
  if (o.instances < 0 || o.instances == 1)
    detail::fail("instances: ", o.instances, " is neither 0 (translational) nor at least 2");
  if (o.degree_v < 1) detail::fail("degree_v: ", o.degree_v, " is not positive");
  const Domain dom_v = domain(trajectory);
  const Point start = evaluate(trajectory, dom_v.start);
  if (o.instances == 0) {
    // P_ij = C_i + T_j − T(v₀) with weight w_i·w_j: Σ N_i N_j w_i w_j (C_i + T_j) / (Σ N_i w_i · Σ N_j w_j)
    // = C(u) + T(v), the tensor product of two partitions of unity.
    const Curve along = opened(trajectory);
    const Points tc = cartesian_points(along);
    const Eigen::VectorXd tw = weights(along);
    const bool rational = profile.rational || trajectory.rational;
    const Curve shape = rational ? as_rational(opened(profile)) : opened(profile);
    std::vector<Points> columns;
    for (Eigen::Index j = 0; j < tc.rows(); ++j) {
      Curve moved = shape;
      moved.P = moved_rows(shape, tc.row(j) - start);
      if (rational) moved.P *= tw(j);
      columns.push_back(std::move(moved.P));
    }
    return {from_columns(shape, columns, trajectory.degree, along.knots), 0.0};
  }
  if (dimension(profile) != 3)
    detail::fail("profile: dimension ", dimension(profile), ", a swept surface needs 3");
  check_degree_v(o.degree_v, static_cast<std::size_t>(o.instances), "sweep");
  // The instances, their compatible copies, the flattened lines and the net: about four copies of the
  // instances' rows (of at most the profile's rows plus two degrees after clamping).
  const double bytes = 4.0 * o.instances *
                       static_cast<double>(profile.P.rows() + 2 * Eigen::Index{profile.degree} + 2) *
                       static_cast<double>(profile.P.cols()) * sizeof(double);
  if (bytes > static_cast<double>(largest_input()))
    detail::fail("instances: ", o.instances, " instances of the profile need ",
                 static_cast<long long>(bytes / 1e6), " MB, more than the ",
                 static_cast<long long>(static_cast<double>(largest_input()) / 1e6),
                 " MB (half the memory) a computation may take");
  constexpr int kSteps = 64, kSamples = 8;  // frame steps between instances; deviation samples among them
  const Points frames =
      rotation_minimizing_frames(trajectory, (o.instances - 1) * kSamples + 1, kSteps / kSamples);
  const Eigen::Vector3d x0 = start.transpose();
  const auto frame = [&](Eigen::Index k) {
    Eigen::Matrix3d F;
    const Eigen::Vector3d t = frames.row(k).head(3).transpose(), r = frames.row(k).tail(3).transpose();
    F << t, r, t.cross(r);
    return F;
  };
  const Eigen::Matrix3d F0 = frame(0);
  // The rigid motion of the profile at the k-th sample: x ↦ T(v) + F(v)·F(v₀)ᵀ·(x − T(v₀)).
  const auto motion = [&](Eigen::Index k, double v) {
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.linear() = frame(k) * F0.transpose();
    m.translation() = evaluate(trajectory, v).transpose() - m.linear() * x0;
    return m;
  };
  const auto sample_v = [&](Eigen::Index k) {
    const auto total = static_cast<double>(frames.rows() - 1);
    return k == frames.rows() - 1 ? dom_v.end
                                  : dom_v.start + (dom_v.end - dom_v.start) * static_cast<double>(k) / total;
  };
  std::vector<Curve> instances;
  std::vector<double> vs;
  const Points cart = cartesian_points(profile);
  for (int k = 0; k < o.instances; ++k) {
    const Eigen::Index row = Eigen::Index{k} * kSamples;
    const Eigen::Affine3d m = motion(row, sample_v(row));
    Curve c = profile;
    for (Eigen::Index i = 0; i < c.P.rows(); ++i) {
      const Eigen::Vector3d x = m * Eigen::Vector3d(cart.row(i % cart.rows()).transpose());
      c.P.row(i) = stored_row(x.transpose(), profile.rational ? profile.P(i, 3) : 1.0, profile.rational);
    }
    instances.push_back(std::move(c));
    vs.push_back(sample_v(row));
  }
  Sweep out{skin(make_compatible(instances), vs, o.degree_v), 0.0};
  // The deviation: the skinned surface against the profile carried by the frames, between the instances.
  std::vector<double> us;
  const Domain dom_u = domain(profile);
  const std::vector<double> breaks = breakpoints(profile.knots, profile.degree);
  for (std::size_t b = 0; b + 1 < breaks.size(); ++b)
    for (int s = 0; s < kSamples; ++s) us.push_back(breaks[b] + (breaks[b + 1] - breaks[b]) * s / kSamples);
  us.push_back(dom_u.end);
  const Points curve_points = evaluate(profile, us);
  for (Eigen::Index k = 0; k < frames.rows(); ++k) {
    const double v = sample_v(k);
    const Eigen::Affine3d m = motion(k, v);
    for (std::size_t i = 0; i < us.size(); ++i) {
      const Eigen::Vector3d exact =
          m * Eigen::Vector3d(curve_points.row(static_cast<Eigen::Index>(i)).transpose());
      out.deviation = std::max(out.deviation, (evaluate(out.surface, us[i], v).transpose() - exact).norm());
    }
  }
  return out;
}

}  // namespace cifs::nurbs
