// SPDX-License-Identifier: MIT
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/render/camera.hpp"

using namespace cifs;
using namespace cifs::render;

namespace {

void check_projection(const Projected& p, double x, double y, double depth) {
  CHECK(p.x == Approx(x).epsilon(1e-14).margin(1e-12));
  CHECK(p.y == Approx(y).epsilon(1e-14).margin(1e-12));
  CHECK(p.depth == Approx(depth).epsilon(1e-14).margin(1e-12));
}

}  // namespace

TEST_CASE("Orthographic projection by hand", "[render][camera]") {
  Camera c;
  c.eye = {0, 0, 5};
  c.target = {0, 0, 0};
  c.up = {0, 1, 0};
  c.ortho_height = 2;
  c.width = 100;
  c.height = 50;
  // s = 50 / 2 = 25 pixels per unit, centre (50, 25), forward −z: depth = 5 − z.
  check_projection(project(c, {0.5, 0.25, 1}), 50 + 12.5, 25 - 6.25, 4);
  check_projection(project(c, {-2, -1, -3}), 0, 50, 8);  // the bottom-left corner of the window
  // Looking along +y with z up: x right, z up in the image, depth = y + 5.
  c.eye = {0, -5, 0};
  c.up = {0, 0, 1};
  check_projection(project(c, {0.4, 2, -0.2}), 50 + 10, 25 + 5, 7);
  // `up` need not be orthogonal to the view direction.
  c.up = {0, 3, 1};
  check_projection(project(c, {0.4, 2, -0.2}), 50 + 10, 25 + 5, 7);
}

TEST_CASE("Perspective projection by hand", "[render][camera]") {
  Camera c;
  c.projection = Projection::perspective;
  c.eye = {1, 2, 3};
  c.target = {1, 2, -7};
  c.up = {0, 1, 0};
  c.fov_y = 90;  // F = (H/2) / tan 45° = H/2
  c.width = 200;
  c.height = 100;
  // A point a to the right, b up and d in front of the eye: (W/2 + F·a/d, H/2 − F·b/d), depth d.
  check_projection(project(c, {1 + 0.5, 2 + 1, 3 - 2}), 100 + 50 * 0.25, 50 - 50 * 0.5, 2);
  check_projection(project(c, {1, 2, 3 - 10}), 100, 50, 10);
  // fov 60°: F = 50 / tan 30° = 50·√3.
  c.fov_y = 60;
  check_projection(project(c, {1 - 1, 2, 3 - 4}), 100 - 50 * std::numbers::sqrt3 / 4, 50, 4);
  const ViewTransform v = view_transform(c);
  CHECK(v.visible_depth(c.near));
  CHECK_FALSE(v.visible_depth(c.near / 2));
}

TEST_CASE("Framing: planar shapes get a top view, 3-D shapes fit the image", "[render][camera]") {
  FramingOptions o;
  o.width = o.height = 100;
  o.margin = 0.05;
  Points box(4, 2);
  box << 0, 0, 4, 0, 4, 1, 0, 1;
  const Camera top = frame(box, o);
  CHECK(top.projection == Projection::orthographic);
  // The box is 4 wide: it fills 90 of the 100 pixels across, centred vertically.
  check_projection(project(top, {0, 0, 0}), 5, 50 + 11.25, top.eye.z());
  check_projection(project(top, {4, 1, 0}), 95, 50 - 11.25, top.eye.z());
  // Planar 3-column data is also a top view.
  Points flat(3, 3);
  flat << 0, 0, 2, 1, 0, 2, 0, 1, 2;
  CHECK(frame(flat, o).projection == Projection::orthographic);

  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1);
  Points cloud(200, 3);
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) cloud.row(i) << 3 + g(rng), -1 + 2 * g(rng), 0.5 * g(rng);
  for (const bool perspective : {true, false})
    for (const std::size_t width : {100u, 300u}) {
      o.perspective = perspective;
      o.width = width;
      const Camera c = frame(cloud, o);
      const ViewTransform v = view_transform(c);
      double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
      for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
        const Projected p = v.project(cloud.row(i).transpose());
        CHECK(p.depth > c.near);
        lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x), lo_y = std::min(lo_y, p.y),
        hi_y = std::max(hi_y, p.y);
      }
      INFO("perspective " << perspective << ", width " << width);
      // The tight fit meets the margin in one direction: to rounding.
      CHECK(lo_x >= 0.05 * static_cast<double>(width) - 1e-9);
      CHECK(hi_x <= 0.95 * static_cast<double>(width) + 1e-9);
      CHECK(lo_y >= 5 - 1e-9);
      CHECK(hi_y <= 95 + 1e-9);
    }
}

TEST_CASE("Cameras refuse bad input", "[render][camera]") {
  Camera c;
  c.width = 0;
  CHECK_THROWS_WITH(view_transform(c), Catch::Contains("empty"));
  c.width = 10;
  c.up = {0, 0, 2};  // parallel to the view direction (−z)
  CHECK_THROWS_WITH(view_transform(c), Catch::Contains("parallel"));
  c.up = {0, 1, 0};
  c.eye = c.target;
  CHECK_THROWS_WITH(view_transform(c), Catch::Contains("coincide"));
  c.eye = {0, 0, std::nan("")};
  CHECK_THROWS_AS(view_transform(c), InvalidInput);
  c.eye = {0, 0, 1};
  c.ortho_height = 0;
  CHECK_THROWS_AS(view_transform(c), InvalidInput);
  c.projection = Projection::perspective;
  c.fov_y = 180;
  CHECK_THROWS_WITH(view_transform(c), "the camera's field of view 180 degrees is outside (0, 180)");
  c.fov_y = std::nan("");
  CHECK_THROWS_WITH(view_transform(c),
                    "the camera's field of view (not a finite number) is outside (0, 180)");
  c.fov_y = 30;
  c.near = 0;
  CHECK_THROWS_AS(view_transform(c), InvalidInput);
  CHECK_THROWS_WITH(frame(Points(0, 2)), Catch::Contains("no points"));
  CHECK_THROWS_WITH(frame(Points::Zero(3, 4)), "the points to frame have 4 coordinates, expected 2 or 3");
  Points bad = Points::Zero(2, 3);
  bad(1, 1) = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(frame(bad), InvalidInput);
  FramingOptions o;
  o.margin = 0.5;
  CHECK_THROWS_AS(frame(Points::Zero(2, 2), o), InvalidInput);
}

namespace {

/// The pixel box of the points' projections: {left, right, top, bottom}.
std::array<double, 4> pixel_box(const Camera& camera, const Points& points) {
  const ViewTransform v = view_transform(camera);
  std::array<double, 4> box{1e300, -1e300, 1e300, -1e300};
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Projected p = v.project(points.row(i).transpose());
    REQUIRE(p.depth > camera.near);
    box = {std::min(box[0], p.x), std::max(box[1], p.x), std::min(box[2], p.y), std::max(box[3], p.y)};
  }
  return box;
}

}  // namespace

TEST_CASE("Framing: 3-D shapes fill the image to the margin in the tighter direction, centred",
          "[render][camera]") {
  // A flat, wide cloud (as the hills surface), and a 3-D curve: a helix.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  Points cloud(300, 3);
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) cloud.row(i) << 3 * g(rng), 2 + 2 * g(rng), 0.3 * g(rng);
  Points helix(400, 3);
  for (Eigen::Index i = 0; i < helix.rows(); ++i) {
    const double t = 0.05 * static_cast<double>(i);
    helix.row(i) << std::cos(t), std::sin(t), 0.1 * t;
  }
  for (const Points* shape : {&cloud, &helix})
    for (const bool perspective : {true, false})
      for (const std::size_t width : {120u, 400u}) {
        FramingOptions o{.width = width, .height = 150, .margin = 0.04, .perspective = perspective};
        INFO("shape " << (shape == &cloud ? "cloud" : "helix") << ", perspective " << perspective
                      << ", width " << width);
        const auto [left, right, top, bottom] = pixel_box(frame(*shape, o), *shape);
        const double W = static_cast<double>(width), H = 150;
        // Inside the margins; the tighter direction meets them (to rounding); centred both ways.
        CHECK(left >= 0.04 * W - 1e-6);
        CHECK(right <= 0.96 * W + 1e-6);
        CHECK(top >= 0.04 * H - 1e-6);
        CHECK(bottom <= 0.96 * H + 1e-6);
        CHECK(std::max((right - left) / (0.92 * W), (bottom - top) / (0.92 * H)) == Approx(1).epsilon(1e-9));
        CHECK((left + right) / 2 == Approx(W / 2).margin(1e-6));
        CHECK((top + bottom) / 2 == Approx(H / 2).margin(1e-6));
        // Never smaller than the bounding sphere's framing (the former one, `tight` off).
        o.tight = false;
        const auto sphere = pixel_box(frame(*shape, o), *shape);
        CHECK(right - left >= (sphere[1] - sphere[0]) * (1 - 1e-12));
        CHECK(bottom - top >= (sphere[3] - sphere[2]) * (1 - 1e-12));
      }
  // A segment along the view direction has no tight perspective fit: the sphere's camera is kept.
  Points along(2, 3);
  along << 0, 0, 0, 1, -1.6, 1.1;
  const FramingOptions o{.width = 64, .height = 64};
  const Camera c = frame(along, o);
  CHECK(c.eye.allFinite());
  CHECK(pixel_box(c, along)[0] == Approx(32));
}

TEST_CASE("The automatic view direction faces a quarter cylinder and keeps the default for a cube",
          "[render][camera]") {
  // Issue 32: the default direction (1, −1.6, 1.1) saw a quarter cylinder (x² + y² = 1, x, y ≥ 0,
  // 0 ≤ z ≤ 1) nearly along its chord: a sliver of the frame.
  Points quarter(33 * 9, 3);
  for (int i = 0; i < 33; ++i)
    for (int j = 0; j < 9; ++j) {
      const double t = std::numbers::pi / 2 * i / 32;
      quarter.row(i * 9 + j) << std::cos(t), std::sin(t), j / 8.0;
    }
  const auto covered = [&](const FramingOptions& o) {
    const auto [left, right, top, bottom] = pixel_box(frame(quarter, o), quarter);
    return (right - left) * (bottom - top) / static_cast<double>(o.width * o.height);
  };
  for (const bool perspective : {true, false}) {
    INFO("perspective " << perspective);
    FramingOptions o{.width = 400, .height = 300, .margin = 0.05, .perspective = perspective};
    const double automatic = covered(o);
    o.view_direction = kDefaultViewDirection;
    const double fixed = covered(o);
    INFO("covered: automatic " << automatic << ", default direction " << fixed);
    CHECK(automatic > 0.5);
    CHECK(fixed < 0.3);
  }
  // The direction chosen is the azimuth (about z, of 16) whose projection spreads the points widest,
  // measured here by brute force: the determinant of the covariance of the projected points.
  const auto projected_spread = [&](const Eigen::Vector3d& direction) {
    const Eigen::Vector3d d = direction.normalized(), r = d.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d u = r.cross(d);
    Eigen::MatrixX2d q(quarter.rows(), 2);
    q.col(0) = quarter * r;
    q.col(1) = quarter * u;
    q.rowwise() -= q.colwise().mean();
    return (q.transpose() * q).determinant();
  };
  const Eigen::Vector3d chosen = automatic_view_direction(quarter);
  double widest = 0;
  for (int step = 0; step < 16; ++step)
    widest = std::max(
        widest, projected_spread(Eigen::AngleAxisd(step * std::numbers::pi / 8, Eigen::Vector3d::UnitZ()) *
                                 kDefaultViewDirection));
  CHECK(projected_spread(chosen) == Approx(widest).epsilon(1e-9));
  CHECK(widest > 2 * projected_spread(kDefaultViewDirection));
  CHECK(chosen.z() == Approx(kDefaultViewDirection.z()).epsilon(1e-12));  // the elevation kept
  // A cube's surface looks alike from every side: the default, exactly.
  Points cube(6 * 25, 3);
  Eigen::Index n = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double side : {-1.0, 1.0})
      for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) {
          Eigen::Vector3d p;
          p[axis] = side;
          p[(axis + 1) % 3] = -1 + i / 2.0;
          p[(axis + 2) % 3] = -1 + j / 2.0;
          cube.row(n++) = p.transpose();
        }
  CHECK(automatic_view_direction(cube) == kDefaultViewDirection);
  // Nothing to measure: the default.
  CHECK(automatic_view_direction(Points(0, 3)) == kDefaultViewDirection);
  CHECK(automatic_view_direction(quarter, Eigen::Vector3d::Zero()) == kDefaultViewDirection);
}
