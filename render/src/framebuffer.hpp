// SPDX-License-Identifier: MIT
// cifs — private helpers shared by the rasterisers: framebuffer checks and the point layer.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cifs/render/camera.hpp"
#include "cifs/render/image.hpp"
#include "cifs/render/raster.hpp"

namespace cifs::render::detail {

/// Validates the camera, initialises an empty image (make_framebuffer) or checks that its size is
/// the camera's and adds missing R G B A Z and state.
ViewTransform prepare(Image& image, const Camera& camera);

/// The float channel `name`, created with `fill` when missing.
std::vector<float>& channel(Image& image, const std::string& name, float fill = 0);

/// Hits of one point layer (render_points, chaos_density): per pixel the added density, the
/// nearest depth (+∞ where nothing landed) and that point's state.
struct PointLayer {
  std::vector<double> density;
  std::vector<float> depth;
  std::vector<std::uint32_t> state;
};

/// A point layer's per-pixel values, borrowed.
struct PointLayerView {
  std::span<const double> density;
  std::span<const float> depth;
  std::span<const std::uint32_t> state;
};

/// Adds the layer's density to `density`; where it has hits: A = 1, R G B = color, Z and state
/// of its nearest point.
void composite_points(Image& image, const PointLayerView& layer, const Rgb& color);

}  // namespace cifs::render::detail
