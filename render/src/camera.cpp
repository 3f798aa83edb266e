// SPDX-License-Identifier: MIT
// cifs — cameras and automatic framing.
#include "cifs/render/camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs::render {
namespace {

void check_size(std::size_t width, std::size_t height) {
  if (width == 0 || height == 0)
    throw InvalidInput("the image size " + std::to_string(width) + " by " + std::to_string(height) +
                       " is empty");
  if (width > 65536 || height > 65536)
    throw InvalidInput("the image size " + std::to_string(width) + " by " + std::to_string(height) +
                       " is larger than 65536 pixels on a side");
}

std::string vector_text(const Eigen::Vector3d& v) {
  return "(" + number_text(v.x(), 6) + ", " + number_text(v.y(), 6) + ", " + number_text(v.z(), 6) + ")";
}

double radians(double degrees) {
  return degrees * std::numbers::pi / 180;
}

/// The root of a decreasing function on [lo, hi] (or the nearer end when it has none there).
template <class F>
double decreasing_root(F g, double lo, double hi) {
  if (!(lo < hi)) return (lo + hi) / 2;
  for (int i = 0; i < 64; ++i) {
    const double mid = lo + (hi - lo) / 2;
    if (mid <= lo || mid >= hi) break;
    (g(mid) > 0 ? lo : hi) = mid;
  }
  return lo + (hi - lo) / 2;
}

/// The closest perspective camera along the sphere camera's direction (same fov and basis) whose
/// frustum, shrunk to the usable fraction, holds every point; centred on the projected extent.
/// With the eye at centre + a·r + b·u + c·f, a point q (relative to the centre) is inside the left
/// and right planes when c·tx − a ≤ q·(tx·f − r) and c·tx + a ≤ q·(tx·f + r) (likewise b, ty, u):
/// the largest c meets the tighter pair, and a (b) then centres the other pair's projections.
/// Empty when a point would be (nearly) at the eye: e.g. a segment along the view direction.
std::optional<Camera> tight_perspective(const Points& points, const Eigen::Vector3d& centre,
                                        const Camera& sphere, const ViewTransform& view, double usable,
                                        double aspect) {
  const double ty = usable * std::tan(radians(sphere.fov_y) / 2), tx = ty * aspect;
  // The points in the camera's basis, relative to the centre.
  const auto n = static_cast<std::size_t>(points.rows());
  std::vector<double> qr(n), qu(n), qf(n);
  double L = INFINITY, R = INFINITY, B = INFINITY, T = INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    q.head(points.cols()) = points.row(static_cast<Eigen::Index>(i)).transpose();
    q -= centre;
    qr[i] = q.dot(view.right), qu[i] = q.dot(view.up), qf[i] = q.dot(view.forward);
    L = std::min(L, tx * qf[i] - qr[i]), R = std::min(R, tx * qf[i] + qr[i]);
    B = std::min(B, ty * qf[i] - qu[i]), T = std::min(T, ty * qf[i] + qu[i]);
  }
  const double c = std::min((L + R) / (2 * tx), (B + T) / (2 * ty));
  const double nearest = *std::min_element(qf.begin(), qf.end()) - c;
  if (!std::isfinite(c) || !std::isfinite(nearest) || !(-c > 0) || !(nearest > 1e-9 * -c))
    return std::nullopt;
  // The sum of the extreme tangents, which decreases as the eye moves along the axis.
  const auto centring = [&](const std::vector<double>& qa) {
    return [&qa, &qf, c, n](double a) {
      double lo = INFINITY, hi = -INFINITY;
      for (std::size_t i = 0; i < n; ++i) {
        const double x = (qa[i] - a) / (qf[i] - c);
        lo = std::min(lo, x), hi = std::max(hi, x);
      }
      return lo + hi;
    };
  };
  const double a = decreasing_root(centring(qr), c * tx - L, R - c * tx);
  const double b = decreasing_root(centring(qu), c * ty - B, T - c * ty);
  Camera camera = sphere;
  camera.eye = centre + a * view.right + b * view.up + c * view.forward;
  camera.target = camera.eye + view.forward * -c;  // on the axis, at the centre's depth
  camera.near = std::min(1e-4 * -c, nearest / 2);
  if (!camera.eye.allFinite() || !camera.target.allFinite() || !(camera.near > 0)) return std::nullopt;
  return camera;
}

/// The orthographic camera of the sphere camera's direction whose window is the projected extent's
/// box over the usable fraction (tighter direction), centred on it.
std::optional<Camera> tight_orthographic(const Points& points, const Eigen::Vector3d& centre,
                                         const Camera& sphere, const ViewTransform& view, double usable,
                                         double aspect) {
  double s_lo = INFINITY, s_hi = -INFINITY, t_lo = INFINITY, t_hi = -INFINITY;
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    q.head(points.cols()) = points.row(i).transpose();
    q -= centre;
    s_lo = std::min(s_lo, q.dot(view.right)), s_hi = std::max(s_hi, q.dot(view.right));
    t_lo = std::min(t_lo, q.dot(view.up)), t_hi = std::max(t_hi, q.dot(view.up));
  }
  const double height = std::max(t_hi - t_lo, (s_hi - s_lo) / aspect) / usable;
  if (!(height > 0) || !std::isfinite(height)) return std::nullopt;
  Camera camera = sphere;
  camera.ortho_height = height;
  camera.target = centre + view.right * (s_lo + s_hi) / 2 + view.up * (t_lo + t_hi) / 2;
  camera.eye = camera.target + (sphere.eye - sphere.target);
  if (!camera.eye.allFinite() || !camera.target.allFinite()) return std::nullopt;
  return camera;
}

}  // namespace

Eigen::Vector3d automatic_view_direction(const Points& points, const Eigen::Vector3d& up) {
  const Eigen::Vector3d& d0 = kDefaultViewDirection;
  if (points.cols() != 3 || points.rows() == 0 || !points.allFinite() || !up.allFinite() ||
      !(up.cwiseAbs().maxCoeff() > 0))
    return d0;
  // The covariance about the mean, on coordinates scaled by the largest magnitude (no overflow near 1e308).
  const double scale = std::max(points.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  const Eigen::RowVector3d mean = points.colwise().mean() / scale;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::RowVector3d q = points.row(i) / scale - mean;
    C += q.transpose() * q;
  }
  // adj(C) by cofactors (C may be singular: a wall's points lie in a plane).
  Eigen::Matrix3d adjugate;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, e = (i + 2) % 3;
      adjugate(i, j) = C(a, c) * C(b, e) - C(a, e) * C(b, c);
    }
  const Eigen::Vector3d k = (up / up.cwiseAbs().maxCoeff()).normalized();
  const auto spread = [&](const Eigen::Vector3d& d) { return d.dot(adjugate * d) / d.squaredNorm(); };
  Eigen::Vector3d best = d0;
  // Spreads at the rounding level do not count: a segment's covariance has rank 1 and every projection of
  // it is a line, whatever rounding says.
  double widest = std::max(2 * spread(d0), 1e-9 * C.trace() * C.trace());
  for (int step = 1; step < 16; ++step) {  // Rodrigues' rotation of d0 about k by step · 22.5°
    const double angle = step * std::numbers::pi / 8;
    const Eigen::Vector3d d =
        d0 * std::cos(angle) + k.cross(d0) * std::sin(angle) + k * k.dot(d0) * (1 - std::cos(angle));
    if (const double s = spread(d); s > widest) {
      best = d;
      widest = s;
    }
  }
  return best;
}

ViewTransform view_transform(const Camera& camera) {
  check_size(camera.width, camera.height);
  if (!camera.eye.allFinite() || !camera.target.allFinite() || !camera.up.allFinite())
    throw InvalidInput("the camera's eye, target and up must be finite");
  const Eigen::Vector3d view = camera.target - camera.eye;
  if (!view.allFinite())
    throw InvalidInput("the camera's eye " + vector_text(camera.eye) + " and target " +
                       vector_text(camera.target) +
                       " are farther apart than a double holds; move them closer (scale the scene down)");
  // Scaled before the norms: the squares of coordinates above ~1e154 overflow (an eye at 1e308 was
  // reported as "up is zero or parallel").
  const double view_scale = view.cwiseAbs().maxCoeff();
  if (!(view_scale > 0))
    throw InvalidInput("the camera's eye and target coincide; move the eye away from the target");
  ViewTransform t;
  t.eye = camera.eye;
  t.forward = (view / view_scale).normalized();
  const double up_scale = camera.up.cwiseAbs().maxCoeff();
  const Eigen::Vector3d up = up_scale > 0 ? Eigen::Vector3d(camera.up / up_scale) : camera.up;
  const Eigen::Vector3d side = t.forward.cross(up);
  // Relative test: up must have a component orthogonal to the view direction.
  if (!(side.norm() > 1e-9 * up.norm()))
    throw InvalidInput("the camera's up " + vector_text(camera.up) +
                       (up_scale > 0 ? " is parallel to" : " is zero, not across") +
                       " the viewing direction from eye to target; give an up vector across it");
  t.right = side.normalized();
  t.up = t.right.cross(t.forward);
  t.cx = static_cast<double>(camera.width) / 2;
  t.cy = static_cast<double>(camera.height) / 2;
  const double H = static_cast<double>(camera.height);
  if (camera.projection == Projection::perspective) {
    if (!(camera.fov_y > 0 && camera.fov_y < 180))
      throw InvalidInput("the camera's field of view " +
                         (std::isfinite(camera.fov_y) ? number_text(camera.fov_y, 6) + " degrees"
                                                      : std::string("(not a finite number)")) +
                         " is outside (0, 180)");
    if (!(camera.near > 0) || !std::isfinite(camera.near))
      throw InvalidInput("the camera's near distance must be a positive finite number");
    t.perspective = true;
    t.scale = (H / 2) / std::tan(radians(camera.fov_y) / 2);
    t.near = camera.near;
  } else {
    if (!(camera.ortho_height > 0) || !std::isfinite(camera.ortho_height))
      throw InvalidInput("the camera's orthographic height must be a positive finite number");
    t.scale = H / camera.ortho_height;
  }
  return t;
}

Projected project(const Camera& camera, const Eigen::Vector3d& point) {
  return view_transform(camera).project(point);
}

Camera frame(const Points& points, const FramingOptions& options) {
  check_size(options.width, options.height);
  if (points.rows() == 0) throw InvalidInput("there are no points to frame in the image");
  if (points.cols() != 2 && points.cols() != 3)
    throw InvalidInput("the points to frame have " + std::to_string(points.cols()) +
                       " coordinates, expected 2 or 3");
  if (!points.allFinite()) throw InvalidInput("a point to frame in the image is not finite");
  if (!(options.margin >= 0 && options.margin <= 0.45))
    throw InvalidInput("the camera margin " +
                       (std::isfinite(options.margin) ? number_text(options.margin, 6)
                                                      : std::string("(not a finite number)")) +
                       " is outside [0, 0.45]");
  const double W = static_cast<double>(options.width), H = static_cast<double>(options.height);
  const double usable = 1 - 2 * options.margin;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  for (Eigen::Index k = 0; k < points.cols(); ++k) {
    lo[k] = points.col(k).minCoeff();
    hi[k] = points.col(k).maxCoeff();
  }
  const Eigen::Vector3d centre = (lo + hi) / 2;
  Camera camera;
  camera.width = options.width;
  camera.height = options.height;

  const bool planar = points.cols() == 2 || lo.z() == hi.z();
  if (planar) {
    // A single point (or a set of coincident ones) still gets a window of positive size.
    double extent = std::max(hi.y() - lo.y(), (hi.x() - lo.x()) * H / W);
    if (!(extent > 0)) extent = std::max(1.0, centre.head<2>().norm());
    camera.projection = Projection::orthographic;
    camera.ortho_height = extent / usable;
    camera.target = centre;
    camera.eye = centre + Eigen::Vector3d(0, 0, camera.ortho_height);
    camera.up = {0, 1, 0};
    return camera;
  }
  const Eigen::Vector3d v =
      options.view_direction ? *options.view_direction : automatic_view_direction(points, options.up);
  if (!v.allFinite() || !(v.cwiseAbs().maxCoeff() > 0))
    throw InvalidInput(v.allFinite() ? "the camera's view direction is zero; give a non-zero direction"
                                     : "the camera's view direction has a coordinate that is not finite");
  // Scaled first: the norm of a direction of 1e308 overflows, and its normalization gave 0.
  const Eigen::Vector3d direction = (v / v.cwiseAbs().maxCoeff()).normalized();
  double radius = 0;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    radius = std::max(radius, (points.row(i).transpose() - centre).norm());
  // The bounding sphere first: a valid camera for any input, kept when the tight fit below degenerates.
  camera.target = centre;
  camera.up = options.up;
  if (options.perspective) {
    camera.projection = Projection::perspective;
    camera.fov_y = options.fov_y;
    const double half_v = radians(options.fov_y) / 2;
    // The tighter of the vertical and horizontal half-angles, shrunk to the usable fraction.
    const double tan_half = usable * std::tan(half_v) * std::min(1.0, W / H);
    const double distance = radius / std::sin(std::atan(tan_half));
    camera.eye = centre + direction * distance;
    camera.near = distance * 1e-4;
  } else {
    camera.projection = Projection::orthographic;
    camera.ortho_height = 2 * radius / usable * std::max(1.0, H / W);
    camera.eye = centre + direction * (2 * radius + 1);
  }
  const ViewTransform view = view_transform(camera);  // refuses an up parallel to view_direction
  // The sphere leaves the corners of the image empty and, for flat shapes seen at an angle, much
  // more (the hills filled 60% of the picture): fit the projected extent itself.
  if (!options.tight) return camera;
  const std::optional<Camera> tight = options.perspective
                                          ? tight_perspective(points, centre, camera, view, usable, W / H)
                                          : tight_orthographic(points, centre, camera, view, usable, W / H);
  return tight ? *tight : camera;
}

}  // namespace cifs::render
