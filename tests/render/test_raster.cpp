// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <numeric>

#include "cifs/errors.hpp"
#include "cifs/render/raster.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using namespace cifs::render;
using cifs_test::ScratchDir;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Orthographic camera looking down −z from z = 10: one world unit per pixel, pixel (i, j) centred
/// on world (i + ½ − W/2, H/2 − j − ½).
Camera unit_camera(std::size_t width, std::size_t height) {
  Camera c;
  c.eye = {0, 0, 10};
  c.target = {0, 0, 0};
  c.up = {0, 1, 0};
  c.width = width;
  c.height = height;
  c.ortho_height = static_cast<double>(height);
  return c;
}

/// A square [x0, x1] × [y0, y1] at height z, counter-clockwise seen from +z (normal +z).
Mesh square(double x0, double x1, double y0, double y1, double z, std::uint32_t state) {
  Mesh m;
  m.vertices.resize(4, 3);
  m.vertices << x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z;
  add_face(m, {0, 1, 2, 3});
  m.states = {state};
  return m;
}

double sum(const std::vector<float>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0);
}

}  // namespace

TEST_CASE("A quad facing an orthographic camera: coverage, Z, normals, states, shading exact",
          "[render][raster]") {
  const Camera camera = unit_camera(16, 12);
  Image image;
  SurfaceStyle style;
  style.threads = 2;
  // Covers pixels 4 … 11 across (world x ∈ [−4, 4]) and 2 … 7 down (world y ∈ [−2, 4]).
  render_mesh(image, camera, square(-4, 4, -2, 4, 1, 7), style);
  REQUIRE(image.width == 16);
  const std::vector<float>& A = image.channels.at("A");
  // Headlight along the normal: n·l = n·h = 1, so colour = base·(ambient + diffuse) + specular.
  const float shaded = static_cast<float>(0.8 * (0.12 + 0.88) + 0.15);
  for (std::size_t y = 0; y < 12; ++y)
    for (std::size_t x = 0; x < 16; ++x) {
      const std::size_t i = y * 16 + x;
      const bool inside = x >= 4 && x < 12 && y >= 2 && y < 8;
      INFO("pixel " << x << ", " << y);
      CHECK(A[i] == (inside ? 1.0f : 0.0f));
      CHECK(image.channels.at("Z")[i] == (inside ? 9.0f : kInf));
      CHECK(image.channels.at("N.x")[i] == 0.0f);
      CHECK(image.channels.at("N.y")[i] == 0.0f);
      CHECK(image.channels.at("N.z")[i] == (inside ? 1.0f : 0.0f));
      CHECK((*image.state)[i] == (inside ? 7u : kNoState));
      CHECK(image.channels.at("R")[i] == (inside ? shaded : 0.0f));
    }
}

TEST_CASE("Mesh edges are anti-aliased by supersampling; shared edges have no cracks", "[render][raster]") {
  const Camera camera = unit_camera(16, 16);
  for (const int S : {1, 2, 4, 5}) {
    Image image;
    SurfaceStyle style;
    style.samples_per_side = S;
    // World x ∈ [−4.4, 4] is pixel x ∈ [3.6, 12]: column 3 is covered by the samples whose
    // centres 3 + (i + ½)/S lie right of 3.6.
    render_mesh(image, camera, square(-4.4, 4, -3, 3, 0, 1), style);
    const std::vector<float>& A = image.channels.at("A");
    int right = 0;
    for (int i = 0; i < S; ++i) right += (i + 0.5) / S > 0.6;
    const double expected = static_cast<double>(right) / S;
    INFO("S = " << S);
    for (std::size_t y = 5; y < 11; ++y) {
      CHECK(A[y * 16 + 3] == Approx(expected).epsilon(1e-7));
      // Full pixels, also along the quad's diagonal (pixel (7, 8)): no crack.
      for (std::size_t x = 4; x < 12; ++x) CHECK(A[y * 16 + x] == 1.0f);
    }
    CHECK(sum(A) == Approx(6 * (8 + expected)).epsilon(1e-6));
  }
}

TEST_CASE("A tilted plane in perspective: Z and N against ray casting", "[render][raster]") {
  Camera camera;
  camera.projection = Projection::perspective;
  camera.eye = {0.3, -4, 2};
  camera.target = {0, 0, 0};
  camera.up = {0, 0, 1};
  camera.fov_y = 50;
  camera.width = 64;
  camera.height = 48;
  // The plane n·x = c through a large quad, crossing the whole view.
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.3, 1).normalized();
  const double c = 0.1;
  Mesh plane;
  plane.vertices.resize(4, 3);
  const auto on_plane = [&](double x, double y) {
    return Eigen::RowVector3d(x, y, (c - n.x() * x - n.y() * y) / n.z());
  };
  plane.vertices << on_plane(-20, -20), on_plane(20, -20), on_plane(20, 20), on_plane(-20, 20);
  add_face(plane, {0, 1, 2, 3});
  Image image;
  render_mesh(image, camera, plane);
  const ViewTransform v = view_transform(camera);
  std::size_t covered = 0;
  for (std::size_t y = 0; y < 48; ++y)
    for (std::size_t x = 0; x < 64; ++x) {
      const std::size_t i = y * 64 + x;
      // The ray through the pixel centre, with unit depth per unit parameter: e + t·d, d·f = 1.
      const Eigen::Vector3d d = v.forward + ((static_cast<double>(x) + 0.5 - v.cx) / v.scale) * v.right -
                                ((static_cast<double>(y) + 0.5 - v.cy) / v.scale) * v.up;
      const double t = (c - n.dot(v.eye)) / n.dot(d);
      if (!(t > 0)) continue;  // sky
      if (image.channels.at("A")[i] < 1) continue;
      ++covered;
      INFO("pixel " << x << ", " << y);
      CHECK(image.channels.at("Z")[i] == Approx(t).epsilon(1e-6));
      CHECK(image.channels.at("N.x")[i] == Approx(n.x()).epsilon(1e-6));
      CHECK(image.channels.at("N.y")[i] == Approx(n.y()).epsilon(1e-6));
      CHECK(image.channels.at("N.z")[i] == Approx(n.z()).epsilon(1e-6));
    }
  CHECK(covered > 1000);
}

TEST_CASE("A polygon is drawn as the fan of its corners (a quad along its 0-2 diagonal)",
          "[render][raster]") {
  const Camera camera = unit_camera(24, 20);
  Mesh polygon, fan;
  polygon.vertices.resize(5, 3);
  // A skew, non-planar pentagon: the split matters.
  polygon.vertices << -8, -6, 1, 7, -7, 2, 9, 3, 0.5, 1, 8, 3, -9, 4, 1.5;
  fan.vertices = polygon.vertices;
  add_face(polygon, {0, 1, 2, 3, 4});
  polygon.states = {6};
  for (const auto& t : std::vector<std::vector<int>>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}) add_face(fan, t);
  fan.states = {6, 6, 6};
  fan.normals = polygon.normals = vertex_normals(polygon);  // the same vertex normals for both
  for (int corners : {5, 4}) {
    INFO(corners << " corners");
    Mesh p = polygon, f = fan;
    if (corners == 4) {
      p.face_offsets = {0, 4};
      p.face_vertices = {0, 1, 2, 3};
      f.face_offsets = {0, 3, 6};
      f.face_vertices = {0, 1, 2, 0, 2, 3};
      f.states = {6, 6};
      p.normals = f.normals = vertex_normals(p);
    }
    Image a, b;
    render_mesh(a, camera, p);
    render_mesh(b, camera, f);
    CHECK(sum(a.channels.at("A")) > 100);
    for (const auto& [name, values] : a.channels) {
      INFO("channel " << name);
      CHECK(values == b.channels.at(name));
    }
    CHECK(*a.state == *b.state);
  }
}

TEST_CASE("Nearer surfaces win per sample; a later layer is hidden behind an earlier one",
          "[render][raster]") {
  const Camera camera = unit_camera(16, 16);
  Image image;
  Mesh both = square(-6, 2, -6, 2, 1, 1);         // depth 9
  const Mesh front = square(-2, 6, -2, 6, 3, 2);  // depth 7
  both.vertices.conservativeResize(8, 3);
  both.vertices.bottomRows(4) = front.vertices;
  add_face(both, {4, 5, 6, 7});
  both.states.push_back(2);
  render_mesh(image, camera, both);
  const auto at = [&](std::size_t x, std::size_t y) { return y * 16 + x; };
  CHECK((*image.state)[at(9, 9)] == 2);  // the overlap: the front square
  CHECK(image.channels.at("Z")[at(9, 9)] == 7.0f);
  CHECK((*image.state)[at(3, 12)] == 1);  // only the back square
  // A third square behind both, drawn later, shows only where nothing was drawn.
  render_mesh(image, camera, square(-8, 8, -8, 8, -1, 3));
  CHECK((*image.state)[at(9, 9)] == 2);
  CHECK((*image.state)[at(0, 0)] == 3);
  CHECK(image.channels.at("Z")[at(0, 0)] == 11.0f);
}

TEST_CASE("Anti-aliased strokes: coverage integrates to width × length", "[render][raster]") {
  const Camera camera = unit_camera(200, 120);
  for (const double w : {0.6, 1.0, 2.5, 4.0}) {
    // A line crossing the whole image from the left edge to the right edge (its ends are outside:
    // no caps), slope 0.37.
    Segments s;
    s.vertices.resize(2, 2);
    s.vertices << -150, -150 * 0.37 + 3, 150, 150 * 0.37 + 3;
    s.segments = {{0, 1}};
    Image image;
    CurveStyle style;
    style.width = w;
    render_segments(image, camera, s, style);
    const double inside = 200 * std::sqrt(1 + 0.37 * 0.37);
    INFO("width " << w);
    CHECK(sum(image.channels.at("A")) == Approx(w * inside).epsilon(2e-3));
    CHECK(*std::max_element(image.channels.at("A").begin(), image.channels.at("A").end()) <= 1.0f);
  }
}

TEST_CASE("Strokes: a straight line cut into pieces is the same line; corners are not darker",
          "[render][raster]") {
  const Camera camera = unit_camera(64, 64);
  CurveStyle style;
  style.width = 3;
  Points whole(2, 2), cut(8, 2);
  whole << -25.3, -11.1, 24.6, 17.9;
  for (int i = 0; i < 8; ++i) cut.row(i) = whole.row(0) + (whole.row(1) - whole.row(0)) * (i / 7.0);
  Image a, b;
  render_polylines(a, camera, std::vector<Points>{whole}, style);
  render_polylines(b, camera, std::vector<Points>{cut}, style);
  const std::vector<float>& Aa = a.channels.at("A");
  const std::vector<float>& Ab = b.channels.at("A");
  for (std::size_t i = 0; i < Aa.size(); ++i) CHECK(Ab[i] == Approx(Aa[i]).margin(1e-6));
  // A right angle: coverage never exceeds 1 (no double darkening) and the corner is full.
  Points corner(3, 2);
  corner << -20.5, -20.5, 10.5, -20.5, 10.5, 20.5;
  Image c;
  render_polylines(c, camera, std::vector<Points>{corner}, style);
  const std::vector<float>& Ac = c.channels.at("A");
  CHECK(*std::max_element(Ac.begin(), Ac.end()) <= 1.0f);
  CHECK(Ac[static_cast<std::size_t>(32 + 20.5) * 64 + static_cast<std::size_t>(32 + 10.5)] == 1.0f);
}

TEST_CASE("Strokes carry their segment's state and depth; colour is composited", "[render][raster]") {
  const Camera camera = unit_camera(32, 32);
  Segments s;
  s.vertices.resize(4, 3);
  s.vertices << -10, -5, 2, 10, -5, 2, -10, 5, 4, 10, 5, 4;
  s.segments = {{0, 1}, {2, 3}};
  s.states = {11, 12};
  Image image;
  CurveStyle style;
  style.width = 2;
  style.color = {1, 0.5, 0.25};
  render_segments(image, camera, s, style);
  const std::size_t low = (16 + 5) * 32 + 16, high = (16 - 5) * 32 + 16;  // on the lines' centres
  CHECK((*image.state)[low] == 11);
  CHECK((*image.state)[high] == 12);
  CHECK(image.channels.at("Z")[low] == 8.0f);
  CHECK(image.channels.at("Z")[high] == 6.0f);
  CHECK(image.channels.at("A")[low] == Approx(1.0));
  CHECK(image.channels.at("G")[low] == Approx(0.5));
}

TEST_CASE("Points: density accumulates, Z and state of the nearest", "[render][raster]") {
  const Camera camera = unit_camera(8, 8);
  Points p(4, 3);
  p << 0.2, 0.3, 1, 0.7, 0.9, 5, 0.5, 0.5, 3, -3.5, -3.5, 0;  // three in pixel (4, 3), one in (0, 7)
  const std::vector<std::uint32_t> states = {1, 2, 3, 4};
  Image image;
  render_points(image, camera, p, states);
  const std::vector<float>& density = image.channels.at("density");
  CHECK(density[3 * 8 + 4] == 3.0f);
  CHECK(density[7 * 8 + 0] == 1.0f);
  CHECK(sum(density) == 4.0);
  CHECK(image.channels.at("Z")[3 * 8 + 4] == 5.0f);  // the point at z = 5 is nearest (depth 10 − 5)
  CHECK((*image.state)[3 * 8 + 4] == 2);
  CHECK(image.channels.at("A")[3 * 8 + 4] == 1.0f);
  CHECK((*image.state)[0] == kNoState);
}

TEST_CASE("The rendered scene survives an OpenEXR round trip, every channel and attribute",
          "[render][raster]") {
  ScratchDir dir;
  const Camera camera = unit_camera(24, 16);
  Image image;
  render_mesh(image, camera, square(-6, 6, -4, 4, 1, 5));
  Segments s = polyline_segments(Points{{-10, -6}, {10, 6}}, false, 9);
  render_segments(image, camera, s);
  render_points(image, camera, Points{{0.5, 0.5}, {-11.5, 7.5}}, std::vector<std::uint32_t>{3, 4});
  image.attributes = {{"experiment", "quad, stroke and points"}, {"seed", "1"}, {"depth", "0"}};
  for (const char* name : {"R", "G", "B", "A", "Z", "density", "N.x", "N.y", "N.z"})
    REQUIRE(image.channels.count(name) == 1);
  write_exr(dir.path() / "scene.exr", image);
  const Image back = read_exr(dir.path() / "scene.exr");
  CHECK(back.width == 24);
  CHECK(back.height == 16);
  CHECK(back.attributes == image.attributes);
  REQUIRE(back.channels.size() == image.channels.size());
  for (const auto& [name, values] : image.channels) {
    INFO(name);
    REQUIRE(back.channels.count(name) == 1);
    const std::vector<float>& got = back.channels.at(name);
    REQUIRE(got.size() == values.size());
    CHECK(std::memcmp(got.data(), values.data(), values.size() * sizeof(float)) == 0);
  }
  REQUIRE(back.state);
  CHECK(*back.state == *image.state);
  // And the content is the scene: the point at the centre lies behind the quad (depth 10 > 9) and
  // is hidden, the corner point is alone, the quad has normal +z.
  CHECK(back.channels.at("density")[7 * 24 + 12] == 0.0f);
  CHECK(back.channels.at("density")[0] == 1.0f);
  CHECK((*back.state)[0] == 4u);
  CHECK(back.channels.at("N.z")[6 * 24 + 8] == 1.0f);
  CHECK((*back.state)[6 * 24 + 8] == 5u);
}

TEST_CASE("Rasterisers refuse bad input", "[render][raster]") {
  const Camera camera = unit_camera(8, 8);
  Image image;
  Mesh m = square(-1, 1, -1, 1, 0, 0);
  m.face_vertices[3] = 4;  // quad 0, corner 3
  CHECK_THROWS_WITH(render_mesh(image, camera, m), Catch::Contains("face 0 corner 3 = 4 is out of range"));
  m = square(-1, 1, -1, 1, 0, 0);
  m.vertices(2, 0) = std::nan("");
  CHECK_THROWS_WITH(render_mesh(image, camera, m), Catch::Contains("vertices[2] is not finite"));
  m = square(-1, 1, -1, 1, 0, 0);
  SurfaceStyle style;
  style.samples_per_side = 9;
  CHECK_THROWS_AS(render_mesh(image, camera, m, style), InvalidInput);
  Camera empty = camera;
  empty.width = 0;
  Image fresh;
  CHECK_THROWS_WITH(render_mesh(fresh, empty, square(-1, 1, -1, 1, 0, 0)), Catch::Contains("empty"));
  Camera other = unit_camera(9, 8);
  CHECK_THROWS_WITH(render_mesh(image, other, square(-1, 1, -1, 1, 0, 0)), Catch::Contains("9 by 8"));
  Segments s = polyline_segments(Points{{0, 0}, {1, 1}});
  CurveStyle thin;
  thin.width = 0;
  CHECK_THROWS_AS(render_segments(image, camera, s, thin), InvalidInput);
  s.segments[0][1] = -1;
  CHECK_THROWS_WITH(render_segments(image, camera, s), Catch::Contains("segments[0][1] = -1"));
  CHECK_THROWS_WITH(render_points(image, camera, Points{{0, std::nan("")}}), "a point to draw is not finite");
  CHECK_THROWS_WITH(render_points(image, camera, Points{{0, 0}}, std::vector<std::uint32_t>{1, 2}),
                    "2 states given for 1 points");
}

TEST_CASE("Strokes at equal depth: the later layer wins even where float rounds the depth down",
          "[render][raster]") {
  // Depth 10.7 is stored in Z as the float 10.6999998…, below the double depth of the next layer.
  Camera camera = unit_camera(21, 21);
  camera.eye = {0, 0, 10.7};
  Image image;
  Segments horizontal, vertical;
  horizontal.vertices.resize(2, 3);
  horizontal.vertices << -8, 0, 0, 8, 0, 0;
  horizontal.segments = {{0, 1}};
  horizontal.states = {1};
  vertical.vertices.resize(2, 3);
  vertical.vertices << 0, -8, 0, 0, 8, 0;
  vertical.segments = {{0, 1}};
  vertical.states = {2};
  CurveStyle red, blue;
  red.width = blue.width = 3;
  red.color = {1, 0, 0};
  blue.color = {0, 0, 1};
  render_segments(image, camera, horizontal, red);
  render_segments(image, camera, vertical, blue);
  const std::size_t centre = 10 * 21 + 10;
  CHECK((*image.state)[centre] == 2);
  CHECK(image.channels["B"][centre] == 1.0f);
  CHECK(image.channels["R"][centre] == 0.0f);
}

TEST_CASE("Hole faces are not drawn: the image of the mesh without them", "[render][raster][tags]") {
  const Camera camera = unit_camera(24, 20);
  // Two squares side by side, the right one a hole; the same normals for both meshes.
  Mesh holed = square(-8, 0, -6, 6, 1, 3);
  holed.vertices.conservativeResize(6, 3);
  holed.vertices.bottomRows(2) << 8, -6, 1, 8, 6, 1;
  add_face(holed, {1, 4, 5, 2});
  holed.states = {3, 4};
  holed.normals = vertex_normals(holed);
  Mesh left = holed;
  left.face_offsets = {0, 4};
  left.face_vertices.resize(4);
  left.states = {3};
  holed.tags.holes = {1};
  Image a, b;
  render_mesh(a, camera, holed);
  render_mesh(b, camera, left);
  CHECK(sum(a.channels.at("A")) > 50);
  for (const auto& [name, values] : a.channels) {
    INFO("channel " << name);
    CHECK(values == b.channels.at(name));
  }
  CHECK(*a.state == *b.state);
}
