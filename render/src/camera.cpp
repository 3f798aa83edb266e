// SPDX-License-Identifier: MIT
// cifs — cameras and automatic framing.
#include "cifs/render/camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs::render {
namespace {

void check_size(std::size_t width, std::size_t height, const char* who) {
  if (width == 0 || height == 0)
    throw InvalidInput(std::string(who) + ": the image size " + std::to_string(width) + " by " +
                       std::to_string(height) + " is empty");
  if (width > 65536 || height > 65536)
    throw InvalidInput(std::string(who) + ": the image is larger than 65536 pixels on a side");
}

std::string vector_text(const Eigen::Vector3d& v) {
  return "(" + number_text(v.x(), 6) + ", " + number_text(v.y(), 6) + ", " + number_text(v.z(), 6) + ")";
}

double radians(double degrees) {
  return degrees * std::numbers::pi / 180;
}

}  // namespace

ViewTransform view_transform(const Camera& camera) {
  check_size(camera.width, camera.height, "camera");
  if (!camera.eye.allFinite() || !camera.target.allFinite() || !camera.up.allFinite())
    throw InvalidInput("camera: eye, target and up must be finite");
  const Eigen::Vector3d view = camera.target - camera.eye;
  if (!view.allFinite())
    throw InvalidInput("camera: eye " + vector_text(camera.eye) + " and target " +
                       vector_text(camera.target) +
                       " are farther apart than a double holds; move them closer (scale the scene down)");
  // Scaled before the norms: the squares of coordinates above ~1e154 overflow (an eye at 1e308 was
  // reported as "up is zero or parallel").
  const double view_scale = view.cwiseAbs().maxCoeff();
  if (!(view_scale > 0)) throw InvalidInput("camera: eye and target coincide");
  ViewTransform t;
  t.eye = camera.eye;
  t.forward = (view / view_scale).normalized();
  const double up_scale = camera.up.cwiseAbs().maxCoeff();
  const Eigen::Vector3d up = up_scale > 0 ? Eigen::Vector3d(camera.up / up_scale) : camera.up;
  const Eigen::Vector3d side = t.forward.cross(up);
  // Relative test: up must have a component orthogonal to the view direction.
  if (!(side.norm() > 1e-9 * up.norm()))
    throw InvalidInput("camera: up " + vector_text(camera.up) +
                       (up_scale > 0 ? " is parallel to" : " is zero, not across") +
                       " the viewing direction from eye to target; give an up vector across it");
  t.right = side.normalized();
  t.up = t.right.cross(t.forward);
  t.cx = static_cast<double>(camera.width) / 2;
  t.cy = static_cast<double>(camera.height) / 2;
  const double H = static_cast<double>(camera.height);
  if (camera.projection == Projection::perspective) {
    if (!(camera.fov_y > 0 && camera.fov_y < 180))
      throw InvalidInput("camera: fov_y = " + std::to_string(camera.fov_y) + " degrees is outside (0, 180)");
    if (!(camera.near > 0) || !std::isfinite(camera.near))
      throw InvalidInput("camera: near must be positive and finite");
    t.perspective = true;
    t.scale = (H / 2) / std::tan(radians(camera.fov_y) / 2);
    t.near = camera.near;
  } else {
    if (!(camera.ortho_height > 0) || !std::isfinite(camera.ortho_height))
      throw InvalidInput("camera: ortho_height must be positive and finite");
    t.scale = H / camera.ortho_height;
  }
  return t;
}

Projected project(const Camera& camera, const Eigen::Vector3d& point) {
  return view_transform(camera).project(point);
}

Camera frame(const Points& points, const FramingOptions& options) {
  check_size(options.width, options.height, "frame");
  if (points.rows() == 0) throw InvalidInput("frame: no points");
  if (points.cols() != 2 && points.cols() != 3)
    throw InvalidInput("frame: points have " + std::to_string(points.cols()) + " columns, expected 2 or 3");
  if (!points.allFinite()) throw InvalidInput("frame: the points are not all finite");
  if (!(options.margin >= 0 && options.margin <= 0.45))
    throw InvalidInput("frame: margin " + std::to_string(options.margin) + " is outside [0, 0.45]");
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
  const Eigen::Vector3d& v = options.view_direction;
  if (!v.allFinite() || !(v.cwiseAbs().maxCoeff() > 0))
    throw InvalidInput("camera: the view direction " + vector_text(v) + " is not finite and non-zero");
  // Scaled first: the norm of a direction of 1e308 overflows, and its normalization gave 0.
  const Eigen::Vector3d direction = (v / v.cwiseAbs().maxCoeff()).normalized();
  double radius = 0;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    radius = std::max(radius, (points.row(i).transpose() - centre).norm());
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
  (void)view_transform(camera);  // refuses an up parallel to view_direction
  return camera;
}

}  // namespace cifs::render
