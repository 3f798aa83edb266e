// SPDX-License-Identifier: MIT
// cifs — orthographic and perspective cameras: world points to pixel coordinates and depth.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>

#include "cifs/types.hpp"

namespace cifs::render {

enum class Projection { orthographic, perspective };

/// A pinhole or orthographic camera looking from `eye` towards `target`, `up` giving the image's
/// upward direction (it need not be orthogonal to the view direction, only not parallel to it).
///
/// Pixel coordinates: x to the right, y down, pixel (i, j) covers [i, i+1) × [j, j+1), so its
/// centre is (i + ½, j + ½) and the image centre is (width/2, height/2). Depth: the distance from
/// the eye along the viewing direction f = (target − eye)/|target − eye|, i.e. (p − eye)·f, for
/// both projections. With the camera basis r = f × up/|f × up| (right), u = r × f (up):
/// - orthographic: x = W/2 + s·(p − eye)·r, y = H/2 − s·(p − eye)·u, with s = H / ortho_height
///   pixels per world unit;
/// - perspective: x = W/2 + F·((p − eye)·r)/depth, y = H/2 − F·((p − eye)·u)/depth, with
///   F = (H/2)/tan(fov_y/2) pixels; points with depth < near are not visible.
struct Camera {
  Projection projection = Projection::orthographic;
  Eigen::Vector3d eye{0, 0, 1};
  Eigen::Vector3d target{0, 0, 0};
  Eigen::Vector3d up{0, 1, 0};
  /// Perspective: vertical field of view in degrees, in (0, 180).
  double fov_y = 40;
  /// Orthographic: height of the visible window in world units.
  double ortho_height = 2;
  /// Perspective: smallest visible depth (> 0).
  double near = 1e-3;
  std::size_t width = 512;
  std::size_t height = 512;
};

/// A projected point: pixel coordinates and depth (see Camera).
struct Projected {
  double x = 0, y = 0, depth = 0;
};

/// The camera in the form the rasterisers use: an orthonormal basis and scales. Build it with
/// `view_transform`, which validates the camera.
struct ViewTransform {
  Eigen::Vector3d eye, right, up, forward;
  bool perspective = false;
  double scale = 1;  // s (orthographic) or F (perspective), in pixels
  double cx = 0, cy = 0;
  double near = 0;

  /// The pixel coordinates and depth of a world point (no clipping: check depth ≥ near).
  Projected project(const Eigen::Vector3d& p) const noexcept {
    const Eigen::Vector3d d = p - eye;
    const double z = d.dot(forward);
    const double k = perspective ? scale / z : scale;
    return {cx + k * d.dot(right), cy - k * d.dot(up), z};
  }
  /// Whether a depth is in front of the camera (always for orthographic cameras).
  bool visible_depth(double depth) const noexcept { return !perspective || depth >= near; }
};

/// Validates `camera` and builds its transform. Throws InvalidInput for a zero image size (or a
/// side above 65536), non-finite vectors, eye = target, `up` parallel to the view direction, fov_y
/// outside (0, 180), ortho_height ≤ 0 or near ≤ 0.
ViewTransform view_transform(const Camera& camera);

/// Projects a point with a camera (validated on every call: prefer view_transform in loops).
Projected project(const Camera& camera, const Eigen::Vector3d& point);

struct FramingOptions {
  std::size_t width = 512;
  std::size_t height = 512;
  /// Empty space around the shape, as a fraction of the image on each side.
  double margin = 0.05;
  /// 3-D shapes: perspective (true) or orthographic (false). Planar shapes always get an
  /// orthographic top view.
  bool perspective = true;
  /// 3-D shapes: direction from the shape's centre towards the eye (unset: automatic_view_direction),
  /// and the world's up.
  std::optional<Eigen::Vector3d> view_direction = std::nullopt;
  Eigen::Vector3d up{0, 0, 1};
  double fov_y = 35;
  /// 3-D shapes: fit the points' projection (true) or only their bounding sphere (false).
  bool tight = true;
};

/// The direction a 3-D shape is seen from by default: from the front right, 30° above the horizon (z up).
inline const Eigen::Vector3d kDefaultViewDirection{1.0, -1.6, 1.1};

/// The view direction of `points` (`#P by 3`) when none is given: kDefaultViewDirection turned about `up`
/// to the one of 16 azimuths (steps of 22.5°, the elevation kept) that sees the points spread widest — the
/// largest determinant of their covariance C projected on the image plane, which for a unit direction d is
/// dᵀ·adj(C)·d. The default is kept unless another azimuth sees twice its determinant, so shapes that look
/// alike from every side (a cube, a sphere, a torus lying flat) keep it; a wall or a quarter cylinder, which
/// the default saw edge-on, turns to face the camera. Points that are not finite, or an `up` that is zero or
/// not finite, give the default (frame and view_transform refuse them).
Eigen::Vector3d automatic_view_direction(const Points& points,
                                         const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

/// A camera that shows all of `points` (`#P by 2` or `#P by 3`) with the margin.
/// - Planar shapes (2 columns, or 3 with every z equal): an orthographic top view (eye above the
///   plane, looking down −z, x right and y up in the image); the bounding box is centred and fills
///   the image up to the margin in its tighter direction.
/// - Other shapes, seen along `view_direction` (unset: automatic_view_direction): with `tight`, the
///   closest camera whose image, less the margin, holds the points' projection, centred on it —
///   perspective keeps fov_y and moves the eye along the view direction and across it (the largest
///   eye depth that keeps every point inside the four shrunk frustum planes, then the projection's
///   extent centred by bisection),
///   orthographic takes the projected box; the margin is met exactly in the tighter direction.
///   Without `tight` (or when the fit degenerates: no point in front of the eye) the bounding
///   sphere (centre of the box, radius of the farthest point) is centred and fits in the image minus
///   the margin: perspective places the eye at distance r / sin(half the smaller field of view),
///   orthographic sets ortho_height to the sphere's diameter over the usable fraction.
/// Throws InvalidInput for no points, non-finite points, a column count other than 2 or 3, a
/// margin outside [0, 0.45], or a zero image size.
Camera frame(const Points& points, const FramingOptions& options = {});

}  // namespace cifs::render
