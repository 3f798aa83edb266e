// SPDX-License-Identifier: MIT
// cifs — the rasterisers: analytic anti-aliased segments, supersampled z-buffered meshes, points.
#include "cifs/render/raster.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "cifs/errors.hpp"
#include "framebuffer.hpp"
#include "parallel.hpp"

namespace cifs::render {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

Eigen::Vector3d row3(const Points& P, Eigen::Index i) {
  return {P(i, 0), P(i, 1), P.cols() > 2 ? P(i, 2) : 0.0};
}

}  // namespace

namespace detail {

std::vector<float>& channel(Image& image, const std::string& name, float fill) {
  auto [it, inserted] = image.channels.try_emplace(name);
  if (inserted) it->second.assign(image.width * image.height, fill);
  return it->second;
}

ViewTransform prepare(Image& image, const Camera& camera) {
  ViewTransform view = view_transform(camera);
  if (image.width == 0 && image.height == 0 && image.channels.empty()) {
    image = make_framebuffer(camera);
    return view;
  }
  if (image.width != camera.width || image.height != camera.height)
    throw InvalidInput("the image to draw into is " + std::to_string(image.width) + " by " +
                       std::to_string(image.height) + ", the camera " + std::to_string(camera.width) +
                       " by " + std::to_string(camera.height));
  const std::size_t pixels = image.width * image.height;
  for (const auto& [name, values] : image.channels)
    if (values.size() != pixels)
      throw InvalidInput("the image's channel " + name + " has " + std::to_string(values.size()) +
                         " values for " + std::to_string(pixels) + " pixels");
  for (const char* name : {"R", "G", "B", "A"}) channel(image, name);
  channel(image, "Z", kInf);
  if (!image.state)
    image.state.emplace(pixels, kNoState);
  else if (image.state->size() != pixels)
    throw InvalidInput("the image's state channel has " + std::to_string(image.state->size()) +
                       " values for " + std::to_string(pixels) + " pixels");
  return view;
}

void composite_points(Image& image, const PointLayerView& layer, const Rgb& color) {
  std::vector<float>& density = channel(image, "density");
  std::vector<float>& R = channel(image, "R");
  std::vector<float>& G = channel(image, "G");
  std::vector<float>& B = channel(image, "B");
  std::vector<float>& A = channel(image, "A");
  std::vector<float>& Z = channel(image, "Z", kInf);
  for (std::size_t i = 0; i < layer.density.size(); ++i) {
    if (!(layer.depth[i] < kInf)) continue;
    density[i] = static_cast<float>(density[i] + layer.density[i]);
    R[i] = static_cast<float>(color[0]);
    G[i] = static_cast<float>(color[1]);
    B[i] = static_cast<float>(color[2]);
    A[i] = 1;
    Z[i] = layer.depth[i];
    (*image.state)[i] = layer.state[i];
  }
}

}  // namespace detail

Image make_framebuffer(const Camera& camera) {
  (void)view_transform(camera);
  Image image;
  image.width = camera.width;
  image.height = camera.height;
  const std::size_t pixels = image.width * image.height;
  for (const char* name : {"R", "G", "B", "A"}) image.channels[name].assign(pixels, 0.0f);
  image.channels["Z"].assign(pixels, kInf);
  image.state.emplace(pixels, kNoState);
  return image;
}

// ---------------------------------------------------------------------------------------------
// Curves

namespace {

/// Coverage of a pixel by a stroke of width w whose centre line is at distance d: the overlap of
/// [d − ½, d + ½] (the pixel's box across the stroke) with [−w/2, w/2].
double stroke_coverage(double d, double w) noexcept {
  return std::clamp(std::min(d + 0.5, w / 2) - std::max(d - 0.5, -w / 2), 0.0, 1.0);
}

/// Clips the world segment [a, b] to the visible half-space (depth ≥ near); false when nothing is
/// left.
bool clip_segment(const ViewTransform& view, Eigen::Vector3d& a, Eigen::Vector3d& b) {
  if (!view.perspective) return true;
  const double za = (a - view.eye).dot(view.forward) - view.near;
  const double zb = (b - view.eye).dot(view.forward) - view.near;
  if (za < 0 && zb < 0) return false;
  if (za < 0) a = a + (b - a) * (za / (za - zb));
  if (zb < 0) b = b + (a - b) * (zb / (zb - za));
  return true;
}

}  // namespace

void render_segments(Image& image, const Camera& camera, const Segments& segments, const CurveStyle& style) {
  const ViewTransform view = detail::prepare(image, camera);
  check_segments(segments, "the segments to draw");
  const double w = style.width;
  if (!(w > 0) || !std::isfinite(w)) throw InvalidInput("the line width must be a positive finite number");
  check_part(style.part);
  const std::size_t W = image.width, H = image.height, pixels = W * H;
  const double reach = w / 2 + 0.5;  // beyond it the coverage is 0

  // The union of the strokes: per pixel, the nearest segment (screen distance, then depth).
  std::vector<double> best(pixels, std::numeric_limits<double>::infinity());
  std::vector<double> depth(pixels, 0);
  std::vector<std::uint32_t> state(pixels, kNoState);
  for (std::size_t s = 0; s < segments.segments.size(); ++s) {
    Eigen::Vector3d a = row3(segments.vertices, segments.segments[s][0]);
    Eigen::Vector3d b = row3(segments.vertices, segments.segments[s][1]);
    if (!clip_segment(view, a, b)) continue;
    const Projected pa = view.project(a), pb = view.project(b);
    const double dx = pb.x - pa.x, dy = pb.y - pa.y, length2 = dx * dx + dy * dy;
    const double x0 = std::max(0.0, std::floor(std::min(pa.x, pb.x) - reach));
    const double x1 = std::min(static_cast<double>(W) - 1, std::floor(std::max(pa.x, pb.x) + reach));
    const double y0 = std::max(0.0, std::floor(std::min(pa.y, pb.y) - reach));
    const double y1 = std::min(static_cast<double>(H) - 1, std::floor(std::max(pa.y, pb.y) + reach));
    if (!(x0 <= x1 && y0 <= y1)) continue;  // off screen (also catches NaN)
    const std::uint32_t id = segments.states.empty() ? 0u : segments.states[s];
    for (auto iy = static_cast<std::size_t>(y0); iy <= static_cast<std::size_t>(y1); ++iy) {
      if (!owns_row(style.part, iy)) continue;
      const double py = static_cast<double>(iy) + 0.5;
      for (auto ix = static_cast<std::size_t>(x0); ix <= static_cast<std::size_t>(x1); ++ix) {
        const double px = static_cast<double>(ix) + 0.5;
        const double t =
            length2 > 0 ? std::clamp(((px - pa.x) * dx + (py - pa.y) * dy) / length2, 0.0, 1.0) : 0.0;
        const double ex = px - (pa.x + t * dx), ey = py - (pa.y + t * dy);
        const double d = std::sqrt(ex * ex + ey * ey);
        if (d >= reach) continue;
        // Depth along the segment: linear on screen for orthographic cameras, 1/depth linear for
        // perspective ones.
        const double z =
            view.perspective ? 1 / ((1 - t) / pa.depth + t / pb.depth) : (1 - t) * pa.depth + t * pb.depth;
        const std::size_t i = iy * W + ix;
        if (d < best[i] || (d == best[i] && z < depth[i])) {
          best[i] = d;
          depth[i] = z;
          state[i] = id;
        }
      }
    }
  }
  std::vector<float>& R = image.channels["R"];
  std::vector<float>& G = image.channels["G"];
  std::vector<float>& B = image.channels["B"];
  std::vector<float>& A = image.channels["A"];
  std::vector<float>& Z = image.channels["Z"];
  for (std::size_t i = 0; i < pixels; ++i) {
    // Compared at the stored (float) precision, so that equal depths (2-D scenes) pass.
    if (!(best[i] < reach) || !(static_cast<float>(depth[i]) <= Z[i])) continue;
    const double c = stroke_coverage(best[i], w);
    if (c <= 0) continue;
    const auto over = [c](float& x, double v) { x = static_cast<float>(c * v + (1 - c) * x); };
    over(R[i], style.color[0]);
    over(G[i], style.color[1]);
    over(B[i], style.color[2]);
    over(A[i], 1.0);
    Z[i] = static_cast<float>(depth[i]);
    (*image.state)[i] = state[i];
  }
}

void render_polylines(Image& image, const Camera& camera, std::span<const Points> polylines,
                      const CurveStyle& style, bool closed) {
  Segments all;
  for (std::size_t i = 0; i < polylines.size(); ++i) {
    if (polylines[i].rows() > 0 && polylines[i].cols() != 2 && polylines[i].cols() != 3)
      throw InvalidInput("polyline " + std::to_string(i) + " has " + std::to_string(polylines[i].cols()) +
                         " coordinates, expected 2 or 3");
    append(all, polyline_segments(polylines[i], closed, static_cast<std::uint32_t>(i)));
  }
  render_segments(image, camera, all, style);
}

// ---------------------------------------------------------------------------------------------
// Surfaces

namespace {

constexpr std::size_t kTile = 32;

/// A triangle ready for rasterisation: indices into the raster vertices.
struct Primitive {
  std::array<int, 3> v;
  std::uint32_t state;
  Eigen::Vector3d face_normal;  // unit; used where the interpolated normal vanishes
  double area2;                 // twice the signed screen area
};

struct RasterVertex {
  Eigen::Vector3d world, normal;
  Projected screen;
};

struct Scene {
  std::vector<RasterVertex> vertices;
  std::vector<Primitive> primitives;
};

/// Perspective-correct barycentric weights (summing to 1) and the depth at a screen point.
struct Interpolation {
  Eigen::Vector3d weights;
  double depth;
};

/// Barycentric coordinates of the screen point (x, y) in the projected triangle.
Eigen::Vector3d screen_barycentrics(const Scene& scene, const Primitive& p, double x, double y) noexcept {
  const Projected& a = scene.vertices[p.v[0]].screen;
  const Projected& b = scene.vertices[p.v[1]].screen;
  const Projected& c = scene.vertices[p.v[2]].screen;
  const double l1 = ((c.x - b.x) * (y - b.y) - (c.y - b.y) * (x - b.x)) / p.area2;
  const double l2 = ((a.x - c.x) * (y - c.y) - (a.y - c.y) * (x - c.x)) / p.area2;
  return {l1, l2, 1 - l1 - l2};
}

Interpolation interpolate(const Scene& scene, const Primitive& p, const Eigen::Vector3d& l,
                          bool perspective) noexcept {
  Eigen::Vector3d z;
  for (int k = 0; k < 3; ++k) z[k] = scene.vertices[p.v[k]].screen.depth;
  if (!perspective) return {l, l.dot(z)};
  // Attributes are affine in world space, so on screen they are ratios of affine functions:
  // weights ∝ λ_k / z_k and 1/depth = Σ λ_k / z_k.
  const Eigen::Vector3d q = l.cwiseQuotient(z);
  const double inverse = q.sum();
  return {q / inverse, 1 / inverse};
}

Scene build_scene(const Mesh& mesh, const ViewTransform& view) {
  const Points normals = mesh.normals.size() != 0 ? mesh.normals : vertex_normals(mesh);
  // Normals per face corner (Mesh::normal_indices, two sides of a crease): a scene vertex per corner.
  const bool per_corner = mesh.normals.size() != 0 && !mesh.normal_indices.empty();
  Scene scene;
  if (per_corner) {
    scene.vertices.reserve(mesh.face_vertices.size());
    for (std::size_t k = 0; k < mesh.face_vertices.size(); ++k) {
      const Eigen::Vector3d p = row3(mesh.vertices, mesh.face_vertices[k]);
      scene.vertices.push_back({p, row3(normals, mesh.normal_indices[k]), view.project(p)});
    }
  } else {
    scene.vertices.reserve(static_cast<std::size_t>(mesh.vertices.rows()));
    for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
      const Eigen::Vector3d p = row3(mesh.vertices, i);
      scene.vertices.push_back({p, row3(normals, i), view.project(p)});
    }
  }
  const auto add_vertex = [&](const RasterVertex& a, const RasterVertex& b, double t) {
    const Eigen::Vector3d p = a.world + t * (b.world - a.world);
    scene.vertices.push_back({p, a.normal + t * (b.normal - a.normal), view.project(p)});
    return static_cast<int>(scene.vertices.size() - 1);
  };
  const auto add_triangle = [&](std::array<int, 3> v, std::uint32_t state) {
    const Eigen::Vector3d& a = scene.vertices[v[0]].world;
    Eigen::Vector3d n = (scene.vertices[v[1]].world - a).cross(scene.vertices[v[2]].world - a);
    if (!(n.norm() > 0)) return;  // degenerate in space, hence on screen
    n.normalize();
    const auto emit = [&](std::array<int, 3> u) {
      const Projected &pa = scene.vertices[u[0]].screen, &pb = scene.vertices[u[1]].screen,
                      &pc = scene.vertices[u[2]].screen;
      const double area2 = (pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x);
      if (area2 != 0 && std::isfinite(area2)) scene.primitives.push_back({u, state, n, area2});
    };
    if (!view.perspective) return emit(v);
    // Sutherland–Hodgman against the near plane: the visible part is a triangle or a quad.
    std::array<int, 4> out{};
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      const int i = v[k], j = v[(k + 1) % 3];
      const double di = scene.vertices[i].screen.depth - view.near;
      const double dj = scene.vertices[j].screen.depth - view.near;
      if (di >= 0) out[count++] = i;
      if ((di >= 0) != (dj >= 0)) {
        // Copy the vertices: add_vertex may reallocate the vector.
        const RasterVertex from = scene.vertices[i], to = scene.vertices[j];
        out[count++] = add_vertex(from, to, di / (di - dj));
      }
    }
    if (count >= 3) emit({out[0], out[1], out[2]});
    if (count == 4) emit({out[0], out[2], out[3]});
  };
  // The fan (0, i, i + 1) of every face but the holes: a quad along its 0–2 diagonal.
  const std::vector<char> hole = hole_flags(mesh);
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    if (hole[f] != 0) continue;
    const auto c = face(mesh, f);
    const std::uint32_t state = mesh.states.empty() ? 0u : mesh.states[f];
    const int first = mesh.face_offsets[f];
    const auto at = [&](std::size_t i) { return per_corner ? first + static_cast<int>(i) : c[i]; };
    for (std::size_t i = 1; i + 1 < c.size(); ++i) add_triangle({at(0), at(i), at(i + 1)}, state);
  }
  return scene;
}

struct Shader {
  const Scene& scene;
  const ViewTransform& view;
  const SurfaceStyle& style;
  bool by_state;
  Eigen::Vector3d light;  // directional light, unit (unused with a headlight)

  /// World position and unit normal (mesh orientation) of primitive p at screen point (x, y).
  struct Surface {
    Eigen::Vector3d position, normal;
    double depth;
  };
  Surface at(const Primitive& p, double x, double y) const noexcept {
    const Interpolation in = interpolate(scene, p, screen_barycentrics(scene, p, x, y), view.perspective);
    Surface s{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), in.depth};
    for (int k = 0; k < 3; ++k) {
      s.position += in.weights[k] * scene.vertices[p.v[k]].world;
      s.normal += in.weights[k] * scene.vertices[p.v[k]].normal;
    }
    const double length = s.normal.norm();
    s.normal = length > 0 ? Eigen::Vector3d(s.normal / length) : p.face_normal;
    return s;
  }
  Eigen::Vector3d shade(const Primitive& p, const Surface& s) const noexcept {
    const Eigen::Vector3d v = view.perspective ? Eigen::Vector3d((view.eye - s.position).normalized())
                                               : Eigen::Vector3d(-view.forward);
    const Eigen::Vector3d n = s.normal.dot(v) < 0 ? Eigen::Vector3d(-s.normal) : s.normal;  // two-sided
    const Eigen::Vector3d l = style.headlight ? v : light;
    const double diffuse = std::max(0.0, n.dot(l));
    double specular = 0;
    if (diffuse > 0) specular = std::pow(std::max(0.0, n.dot((l + v).normalized())), style.shininess);
    const Rgb& base = by_state ? style.state_colors[p.state % style.state_colors.size()] : style.color;
    const double k = style.ambient + style.diffuse * diffuse;
    return {base[0] * k + style.specular * specular, base[1] * k + style.specular * specular,
            base[2] * k + style.specular * specular};
  }
};

/// The light direction of the style (unit; unused with a headlight), after the style's checks.
Eigen::Vector3d checked_light(const SurfaceStyle& style) {
  const int S = style.samples_per_side;
  if (S < 1 || S > 8)
    throw InvalidInput("the samples per pixel side, " + std::to_string(S) + ", are outside 1 … 8");
  check_part(style.part);
  for (const double k : {style.ambient, style.diffuse, style.specular, style.shininess})
    if (!(k >= 0) || !std::isfinite(k))
      throw InvalidInput(
          "the shading coefficients (ambient, diffuse, specular, shininess) must be finite numbers ≥ 0");
  Eigen::Vector3d light = Eigen::Vector3d::UnitZ();
  if (!style.headlight) {
    if (!style.light_direction.allFinite() || !(style.light_direction.norm() > 0))
      throw InvalidInput("the light direction must be finite and non-zero");
    light = style.light_direction.normalized();
  }
  return light;
}

struct Box {
  std::size_t x0, x1, y0, y1;  // inclusive pixel range
};

/// The primitives binned by the tiles their screen boxes overlap.
struct Bins {
  std::size_t tiles_x;
  std::vector<std::vector<std::uint32_t>> tiles;
  std::vector<Box> boxes;  // of each primitive
};

Bins bin_primitives(const Scene& scene, std::size_t W, std::size_t H) {
  const std::size_t tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile;
  Bins bins{tiles_x, std::vector<std::vector<std::uint32_t>>(tiles_x * tiles_y),
            std::vector<Box>(scene.primitives.size())};
  for (std::size_t k = 0; k < scene.primitives.size(); ++k) {
    const Primitive& p = scene.primitives[k];
    double lx = std::numeric_limits<double>::infinity(), hx = -lx, ly = lx, hy = -lx;
    for (const int v : p.v) {
      const Projected& s = scene.vertices[v].screen;
      lx = std::min(lx, s.x), hx = std::max(hx, s.x), ly = std::min(ly, s.y), hy = std::max(hy, s.y);
    }
    lx = std::max(lx, 0.0), ly = std::max(ly, 0.0);
    hx = std::min(hx, static_cast<double>(W) - 1e-9), hy = std::min(hy, static_cast<double>(H) - 1e-9);
    if (!(lx <= hx && ly <= hy)) {
      bins.boxes[k] = {1, 0, 1, 0};  // off screen
      continue;
    }
    const Box b{static_cast<std::size_t>(lx), static_cast<std::size_t>(hx), static_cast<std::size_t>(ly),
                static_cast<std::size_t>(hy)};
    bins.boxes[k] = b;
    for (std::size_t ty = b.y0 / kTile; ty <= b.y1 / kTile; ++ty)
      for (std::size_t tx = b.x0 / kTile; tx <= b.x1 / kTile; ++tx)
        bins.tiles[ty * tiles_x + tx].push_back(static_cast<std::uint32_t>(k));
  }
  return bins;
}

/// The channels render_mesh writes.
struct MeshChannels {
  std::vector<float>&R, &G, &B, &A, &Z, &Nx, &Ny, &Nz;
  std::vector<std::uint32_t>& state;
};

MeshChannels mesh_channels(Image& image) {
  std::vector<float>& R = image.channels["R"];
  std::vector<float>& G = image.channels["G"];
  std::vector<float>& B = image.channels["B"];
  std::vector<float>& A = image.channels["A"];
  std::vector<float>& Z = image.channels["Z"];
  std::vector<float>& Nx = detail::channel(image, "N.x");
  std::vector<float>& Ny = detail::channel(image, "N.y");
  std::vector<float>& Nz = detail::channel(image, "N.z");
  return {R, G, B, A, Z, Nx, Ny, Nz, *image.state};
}

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// What every tile reads.
struct TileContext {
  const Scene& scene;
  const Shader& shader;
  const Bins& bins;
  int S;            // samples per side
  std::size_t spp;  // samples per pixel
  std::size_t W, H;
};

/// The pixels [x0, x1) × [y0, y1) of a tile.
struct TileRect {
  std::size_t x0, y0, x1, y1;
};

/// A tile's supersamples (pixel-major, then row-major in the pixel): the nearest depth and its
/// primitive; one buffer per worker.
struct Samples {
  std::vector<double> depth;
  std::vector<std::uint32_t> prim;
};

std::size_t first_sample(const TileContext& c, const TileRect& r, std::size_t x, std::size_t y) {
  return ((y - r.y0) * kTile + (x - r.x0)) * c.spp;
}

/// Samples start just behind the image's depth: earlier layers are opaque at their Z, and
/// a fragment at the same depth is drawn over them (2-D scenes have one depth).
void clear_samples(const TileContext& c, const TileRect& r, const std::vector<float>& Z, Samples& samples) {
  std::fill(samples.prim.begin(), samples.prim.end(), kNone);
  for (std::size_t y = r.y0; y < r.y1; ++y)
    for (std::size_t x = r.x0; x < r.x1; ++x) {
      const std::size_t local = first_sample(c, r, x, y);
      std::fill_n(
          samples.depth.begin() + static_cast<std::ptrdiff_t>(local), c.spp,
          std::nextafter(static_cast<double>(Z[y * c.W + x]), std::numeric_limits<double>::infinity()));
    }
}

/// The depth test of every primitive of the tile at every sample it covers.
void rasterize_tile(const TileContext& c, std::uint64_t tile, const TileRect& r, Samples& samples) {
  const int S = c.S;
  for (const std::uint32_t k : c.bins.tiles[tile]) {
    const Primitive& p = c.scene.primitives[k];
    const Box& b = c.bins.boxes[k];
    for (std::size_t y = std::max(b.y0, r.y0); y <= std::min(b.y1, r.y1 - 1); ++y)
      for (std::size_t x = std::max(b.x0, r.x0); x <= std::min(b.x1, r.x1 - 1); ++x) {
        const std::size_t local = first_sample(c, r, x, y);
        for (int j = 0; j < S; ++j)
          for (int i = 0; i < S; ++i) {
            const double sx = static_cast<double>(x) + (i + 0.5) / S;
            const double sy = static_cast<double>(y) + (j + 0.5) / S;
            const Eigen::Vector3d l = screen_barycentrics(c.scene, p, sx, sy);
            // Closed triangles: samples on a shared edge belong to both, so there are no
            // cracks; the depth test keeps one.
            if (l.minCoeff() < 0) continue;
            const double z = interpolate(c.scene, p, l, c.shader.view.perspective).depth;
            const std::size_t at = local + static_cast<std::size_t>(j * S + i);
            if (z < samples.depth[at]) {
              samples.depth[at] = z;
              samples.prim[at] = k;
            }
          }
      }
  }
}

/// The primitives seen by a pixel's samples (with their sample counts, in order of first
/// appearance) and the nearest of them, or kNone.
std::uint32_t tally_samples(const TileContext& c, const Samples& samples, std::size_t local,
                            std::vector<std::pair<std::uint32_t, int>>& seen) {
  seen.clear();
  std::uint32_t nearest = kNone;
  double nearest_depth = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s < c.spp; ++s) {
    const std::uint32_t k = samples.prim[local + s];
    if (k == kNone) continue;
    auto it = std::find_if(seen.begin(), seen.end(), [k](const auto& e) { return e.first == k; });
    if (it == seen.end())
      seen.emplace_back(k, 1);
    else
      ++it->second;
    // Ties go to the lower primitive index, whatever the sample order.
    const double z = samples.depth[local + s];
    if (z < nearest_depth || (z == nearest_depth && k < nearest)) nearest_depth = z, nearest = k;
  }
  return nearest;
}

/// The pixel's colour (the sum of each seen primitive shaded at the centroid of its samples, over
/// spp) and its coverage; the centroid of the nearest primitive's samples.
struct PixelColour {
  Eigen::Vector3d colour;
  double alpha;
  Eigen::Vector2d nearest_centroid;
};

PixelColour shade_pixel(const TileContext& c, const Samples& samples, std::size_t local, std::size_t x,
                        std::size_t y, std::span<const std::pair<std::uint32_t, int>> seen,
                        std::uint32_t nearest) {
  const int S = c.S;
  Eigen::Vector3d colour = Eigen::Vector3d::Zero();
  int covered = 0;
  Eigen::Vector2d nearest_centroid = Eigen::Vector2d::Zero();  // set: nearest is seen
  for (const auto& [k, count] : seen) {
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (std::size_t s = 0; s < c.spp; ++s)
      if (samples.prim[local + s] == k) {
        const std::size_t column = s % S, row = s / S;  // the sample's place in its pixel
        centroid += Eigen::Vector2d(static_cast<double>(x) + (static_cast<double>(column) + 0.5) / S,
                                    static_cast<double>(y) + (static_cast<double>(row) + 0.5) / S);
      }
    centroid /= count;
    if (k == nearest) nearest_centroid = centroid;
    const Primitive& p = c.scene.primitives[k];
    colour += count * c.shader.shade(p, c.shader.at(p, centroid.x(), centroid.y()));
    covered += count;
  }
  const double a = static_cast<double>(covered) / static_cast<double>(c.spp);
  colour /= static_cast<double>(c.spp);
  return {colour, a, nearest_centroid};
}

/// Z, N and state are point-sampled at the pixel centre: the nearest of the layer's triangles
/// that cover it; when none does (edge pixels), the nearest sample's triangle at the centroid of
/// its samples. Returns the primitive and sets its surface there.
std::uint32_t centre_surface(const TileContext& c, std::size_t x, std::size_t y,
                             std::span<const std::pair<std::uint32_t, int>> seen, std::uint32_t nearest,
                             const Eigen::Vector2d& nearest_centroid, Shader::Surface& s) {
  const double cx = static_cast<double>(x) + 0.5, cy = static_cast<double>(y) + 0.5;
  std::uint32_t chosen = kNone;
  for (const auto& entry : seen) {
    const Primitive& q = c.scene.primitives[entry.first];
    if (screen_barycentrics(c.scene, q, cx, cy).minCoeff() < 0) continue;
    const Shader::Surface candidate = c.shader.at(q, cx, cy);
    if (chosen == kNone || candidate.depth < s.depth || (candidate.depth == s.depth && entry.first < chosen))
      chosen = entry.first, s = candidate;
  }
  if (chosen == kNone) {
    chosen = nearest;
    s = c.shader.at(c.scene.primitives[nearest], nearest_centroid.x(), nearest_centroid.y());
  }
  return chosen;
}

/// Resolve every pixel of the tile into the channels.
void resolve_tile(const TileContext& c, const TileRect& r, const Samples& samples, MeshChannels& out) {
  std::vector<std::pair<std::uint32_t, int>> seen;  // primitive, samples
  for (std::size_t y = r.y0; y < r.y1; ++y)
    for (std::size_t x = r.x0; x < r.x1; ++x) {
      const std::size_t local = first_sample(c, r, x, y);
      const std::uint32_t nearest = tally_samples(c, samples, local, seen);
      if (nearest == kNone) continue;
      const std::size_t i = y * c.W + x;
      const PixelColour pixel = shade_pixel(c, samples, local, x, y, seen, nearest);
      const double a = pixel.alpha;
      const auto over = [a](float& v, double value) { v = static_cast<float>(value + (1 - a) * v); };
      over(out.R[i], pixel.colour.x());
      over(out.G[i], pixel.colour.y());
      over(out.B[i], pixel.colour.z());
      over(out.A[i], a);
      Shader::Surface s{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0};
      const std::uint32_t chosen = centre_surface(c, x, y, seen, nearest, pixel.nearest_centroid, s);
      const Primitive& p = c.scene.primitives[chosen];
      out.Z[i] = static_cast<float>(s.depth);
      out.Nx[i] = static_cast<float>(s.normal.x());
      out.Ny[i] = static_cast<float>(s.normal.y());
      out.Nz[i] = static_cast<float>(s.normal.z());
      out.state[i] = p.state;
    }
}

}  // namespace

void render_mesh(Image& image, const Camera& camera, const Mesh& mesh, const SurfaceStyle& style) {
  const ViewTransform view = detail::prepare(image, camera);
  check_mesh(mesh, "the mesh to draw");
  const Eigen::Vector3d light = checked_light(style);
  const Scene scene = build_scene(mesh, view);
  const Shader shader{scene, view, style, !style.state_colors.empty() && !mesh.states.empty(), light};
  const std::size_t W = image.width, H = image.height;
  const Bins bins = bin_primitives(scene, W, H);
  MeshChannels out = mesh_channels(image);

  const int S = style.samples_per_side;
  const std::size_t spp = static_cast<std::size_t>(S) * static_cast<std::size_t>(S);
  const TileContext context{scene, shader, bins, S, spp, W, H};
  const unsigned threads = detail::worker_count(style.threads, bins.tiles.size());
  std::vector<Samples> samples(threads);
  detail::run_chunks(
      bins.tiles.size(), threads,
      [&](unsigned t) {
        samples[t].depth.resize(kTile * kTile * spp);
        samples[t].prim.resize(kTile * kTile * spp);
      },
      [&](unsigned t, std::uint64_t tile) {
        const std::size_t tx0 = (tile % bins.tiles_x) * kTile, ty0 = (tile / bins.tiles_x) * kTile;
        static_assert(kTile == kBandRows, "a tile lies in one band");
        if (!owns_row(style.part, ty0)) return;
        const TileRect rect{tx0, ty0, std::min(tx0 + kTile, W), std::min(ty0 + kTile, H)};
        clear_samples(context, rect, out.Z, samples[t]);
        rasterize_tile(context, tile, rect, samples[t]);
        resolve_tile(context, rect, samples[t], out);
      });
}

// ---------------------------------------------------------------------------------------------
// Points

void render_points(Image& image, const Camera& camera, const Points& points,
                   std::span<const std::uint32_t> states, const PointStyle& style) {
  const ViewTransform view = detail::prepare(image, camera);
  if (points.rows() > 0 && points.cols() != 2 && points.cols() != 3)
    throw InvalidInput("the points to draw have " + std::to_string(points.cols()) +
                       " coordinates, expected 2 or 3");
  if (!points.allFinite()) throw InvalidInput("a point to draw is not finite");
  if (!states.empty() && states.size() != static_cast<std::size_t>(points.rows()))
    throw InvalidInput(std::to_string(states.size()) + " states given for " + std::to_string(points.rows()) +
                       " points");
  if (!std::isfinite(style.weight)) throw InvalidInput("the point weight must be a finite number");
  const std::size_t W = image.width, H = image.height;
  const std::vector<float>& Z = image.channels["Z"];
  detail::PointLayer layer{std::vector<double>(W * H, 0), std::vector<float>(W * H, kInf),
                           std::vector<std::uint32_t>(W * H, kNoState)};
  for (Eigen::Index k = 0; k < points.rows(); ++k) {
    const Projected p = view.project(row3(points, k));
    if (!view.visible_depth(p.depth)) continue;
    if (!(p.x >= 0 && p.x < static_cast<double>(W) && p.y >= 0 && p.y < static_cast<double>(H))) continue;
    const std::size_t i = static_cast<std::size_t>(p.y) * W + static_cast<std::size_t>(p.x);
    const float z = static_cast<float>(p.depth);
    if (!(z <= Z[i])) continue;  // behind what earlier layers drew
    layer.density[i] += style.weight;
    if (z < layer.depth[i]) {
      layer.depth[i] = z;
      layer.state[i] = states.empty() ? 0u : states[static_cast<std::size_t>(k)];
    }
  }
  detail::composite_points(image, {layer.density, layer.depth, layer.state}, style.color);
}

}  // namespace cifs::render
