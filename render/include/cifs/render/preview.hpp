// SPDX-License-Identifier: MIT
// cifs — 8-bit previews of framebuffers: log-density for chaos renders, shaded colour over a
// background for surfaces and curves.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "cifs/render/image.hpp"
#include "cifs/render/png.hpp"

namespace cifs::render {

enum class PreviewMode {
  /// `density` when the image has a density channel with a positive value, else `shaded`.
  automatic,
  /// tone_map_log_density of the `density` channel.
  density,
  /// R G B (linear, premultiplied) composited over the background: C + (1 − A)·background, then
  /// ·exposure and encoded as sRGB.
  shaded,
};

struct PreviewOptions {
  PreviewMode mode = PreviewMode::automatic;
  ToneMapOptions tone;
  /// sRGB 8-bit background of shaded previews (decoded to linear before compositing).
  Rgb8 background{255, 255, 255};
  double exposure = 1;
};

/// The preview as interleaved RGB bytes (PixelFormat::rgb8), row 0 at the top. Throws InvalidInput
/// when a channel the mode needs is missing or of the wrong size, or exposure is negative or not
/// finite.
std::vector<std::uint8_t> preview_rgb8(const Image& image, const PreviewOptions& options = {});

/// Writes preview_rgb8 as a PNG (write_png: temporary file and rename).
void preview_png(const std::filesystem::path& path, const Image& image, const PreviewOptions& options = {});

/// Writes preview_rgb8 as a PNG into `file`'s temporary; the caller commits it (cifs::AtomicFiles).
void preview_png(AtomicFile& file, const Image& image, const PreviewOptions& options = {});

}  // namespace cifs::render
