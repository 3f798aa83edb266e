// SPDX-License-Identifier: MIT
// cifs — PNG previews of framebuffers.
#include "cifs/render/preview.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cifs/errors.hpp"

namespace cifs::render {
namespace {

const std::vector<float>& need(const Image& image, const char* name) {
  const auto it = image.channels.find(name);
  if (it == image.channels.end())
    throw InvalidInput(std::string("the image to preview has no channel ") + name + " for this preview mode");
  if (it->second.size() != image.width * image.height)
    throw InvalidInput(std::string("the image to preview has a channel ") + name + " of the wrong size");
  return it->second;
}

// sRGB transfer functions (IEC 61966-2-1).
double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
std::uint8_t linear_to_srgb8(double v) {
  if (!(v > 0)) return 0;  // also NaN
  if (v >= 1) return 255;
  const double c = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(c * 255));
}

}  // namespace

std::vector<std::uint8_t> preview_rgb8(const Image& image, const PreviewOptions& options) {
  if (image.width == 0 || image.height == 0) throw InvalidInput("the image to preview is empty");
  if (!(options.exposure >= 0) || !std::isfinite(options.exposure))
    throw InvalidInput("the preview exposure must be a finite number ≥ 0");
  PreviewMode mode = options.mode;
  if (mode == PreviewMode::automatic) {
    const auto it = image.channels.find("density");
    const bool density = it != image.channels.end() &&
                         std::any_of(it->second.begin(), it->second.end(), [](float d) { return d > 0; });
    mode = density ? PreviewMode::density : PreviewMode::shaded;
  }
  if (mode == PreviewMode::density) return tone_map_log_density(need(image, "density"), options.tone);

  const std::vector<float>& R = need(image, "R");
  const std::vector<float>& G = need(image, "G");
  const std::vector<float>& B = need(image, "B");
  const std::vector<float>& A = need(image, "A");
  double background[3];
  for (int k = 0; k < 3; ++k) background[k] = srgb_to_linear(options.background[k] / 255.0);
  std::vector<std::uint8_t> out(image.width * image.height * 3);
  for (std::size_t i = 0; i < R.size(); ++i) {
    const double a = std::clamp(static_cast<double>(A[i]), 0.0, 1.0);
    const double c[3] = {R[i], G[i], B[i]};
    for (int k = 0; k < 3; ++k)
      out[3 * i + k] = linear_to_srgb8(options.exposure * (c[k] + (1 - a) * background[k]));
  }
  return out;
}

void preview_png(const std::filesystem::path& path, const Image& image, const PreviewOptions& options) {
  const std::vector<std::uint8_t> pixels = preview_rgb8(image, options);
  write_png(path, pixels, image.width, image.height, PixelFormat::rgb8);
}

void preview_png(AtomicFile& file, const Image& image, const PreviewOptions& options) {
  const std::vector<std::uint8_t> pixels = preview_rgb8(image, options);
  write_png(file, pixels, image.width, image.height, PixelFormat::rgb8);
}

}  // namespace cifs::render
