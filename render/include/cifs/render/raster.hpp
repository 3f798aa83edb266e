// SPDX-License-Identifier: MIT
// cifs — rasterisers: anti-aliased curves (segment sets), z-buffered shaded meshes, splatted points,
// all drawn through a Camera into an Image framebuffer.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "cifs/mesh.hpp"
#include "cifs/render/camera.hpp"
#include "cifs/render/image.hpp"
#include "cifs/render/part.hpp"
#include "cifs/types.hpp"

namespace cifs::render {

/// `state` of a pixel that no fragment reached.
inline constexpr std::uint32_t kNoState = std::numeric_limits<std::uint32_t>::max();

/// Linear (scene-referred) RGB.
using Rgb = std::array<double, 3>;

/// An empty framebuffer of the camera's size: R G B A = 0, Z = +∞, state = kNoState.
///
/// Framebuffer rules (every render_* call):
/// - R G B are linear and premultiplied by A (the OpenEXR convention); A is coverage.
/// - A call draws one layer and composites it over the image: C ← C_layer + (1 − A_layer)·C for
///   R G B A. A fragment is drawn only when its depth is not above the image's Z: what earlier
///   calls drew counts as opaque at its Z, and at equal depth (2-D scenes) the later call wins.
/// - Where the layer covers a pixel, Z becomes the depth of its nearest fragment and `state` the
///   state of that fragment (surfaces also write N.x N.y N.z).
/// - An empty `image` (width 0) is initialised by make_framebuffer; otherwise its size must be the
///   camera's. Missing channels are added (Z = +∞, others 0).
Image make_framebuffer(const Camera& camera);

struct CurveStyle {
  /// Stroke width in pixels (constant on screen, also under perspective).
  double width = 1.5;
  Rgb color{0.05, 0.2, 0.6};
  /// Draw only the rows of this part (a distributed render; the other rows are left as they are).
  Part part;
};

/// Draws every segment as a capsule of `style.width` pixels around its projection.
///
/// Anti-aliasing is analytic: a pixel's coverage is the length of the overlap of the pixel's
/// 1-pixel box, taken across the stroke, with the stroke [−w/2, w/2], at the distance d from the
/// pixel centre to the nearest segment: clamp(min(d + ½, w/2) − max(d − ½, −w/2), 0, 1). Across a
/// straight stroke it integrates to exactly w for any w, so the coverage summed over an image is
/// w·length plus the round caps. The whole set is one union (the nearest segment decides), so
/// joints have neither gaps nor double darkening. The pixel's depth and state are those of the
/// nearest segment at its closest point (depth interpolated perspective-correctly).
/// Segments are clipped to the near plane. Throws InvalidInput for bad segments (see
/// check_segments), a width ≤ 0 or non-finite, or an image of another size than the camera.
void render_segments(Image& image, const Camera& camera, const Segments& segments,
                     const CurveStyle& style = {});

/// Polylines (`#P by 2|3` each, all with the same columns), drawn as one segment set in which
/// polyline i has state i.
void render_polylines(Image& image, const Camera& camera, std::span<const Points> polylines,
                      const CurveStyle& style = {}, bool closed = false);

struct SurfaceStyle {
  /// Base colour of every face, or of face f: `state_colors[states[f] % size]` when both the mesh
  /// states and `state_colors` are given.
  Rgb color{0.8, 0.8, 0.8};
  std::vector<Rgb> state_colors;
  /// Shading: colour·(ambient + diffuse·max(0, n·l)) + specular·max(0, n·h)^shininess (white
  /// highlight, Blinn–Phong), two-sided (n is flipped to face the viewer).
  double ambient = 0.12;
  double diffuse = 0.88;
  double specular = 0.15;
  double shininess = 40;
  /// true: the light is at the eye (l = v); false: a directional light from `light_direction`
  /// (world space, pointing towards the light).
  bool headlight = true;
  Eigen::Vector3d light_direction{0.3, -0.5, 1.0};
  /// Supersampling: samples_per_side² samples per pixel on a regular grid (1 … 8).
  int samples_per_side = 4;
  /// Worker threads over 32×32-pixel tiles; 0 uses every core. The image does not depend on it.
  unsigned threads = 0;
  /// Draw only the tiles in the rows of this part (a distributed render; the other rows are left as
  /// they are).
  Part part;
};

/// Z-buffered mesh rendering. A face of n corners is drawn as the fan of triangles (0, i, i + 1),
/// i = 1 … n − 2 (a quad is split along its 0–2 diagonal); triangles are clipped to the near plane;
/// no back-face culling.
///
/// Each pixel has samples_per_side² samples, each with its own depth test (against the other
/// samples of the layer and against the image's Z). Resolve:
/// - A = covered samples / all samples (edge anti-aliasing by supersampling);
/// - R G B = the sum over covered samples of the shaded colour, divided by all samples (each
///   triangle is shaded once per pixel, at the centroid of its covered samples);
/// - Z, N, state are point-sampled at the pixel centre: the nearest of the layer's visible
///   triangles that cover the centre; at edge pixels whose centre no triangle covers, the
///   triangle of the nearest sample, evaluated at the centroid of its samples. N is the
///   interpolated vertex normal, normalised, in world space, with the mesh's orientation (not
///   flipped towards the viewer).
/// Vertex normals are `mesh.normals` when given (per face corner through mesh.normal_indices), else
/// vertex_normals; where the interpolated normal vanishes the face normal (of the fan triangle) is used.
/// Throws InvalidInput for a bad mesh (check_mesh), samples_per_side outside 1 … 8, or an image of
/// another size.
void render_mesh(Image& image, const Camera& camera, const Mesh& mesh, const SurfaceStyle& style = {});

struct PointStyle {
  Rgb color{1, 1, 1};
  /// Added to `density` per point.
  double weight = 1;
};

/// Splats points (`#P by 2|3`): each visible point adds `weight` to the `density` of the pixel it
/// falls in. Where a pixel gets hits, Z is the nearest point's depth, state its state (`states`:
/// empty or one per point; the first of equally near points wins), A = 1 and R G B = color.
/// Throws InvalidInput for non-finite points, a column count other than 2 or 3, a states size
/// mismatch, or an image of another size.
void render_points(Image& image, const Camera& camera, const Points& points,
                   std::span<const std::uint32_t> states = {}, const PointStyle& style = {});

}  // namespace cifs::render
