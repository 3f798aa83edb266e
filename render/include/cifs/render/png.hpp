// SPDX-License-Identifier: MIT
// cifs — 8-bit PNG previews and log-density tone mapping.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "cifs/files.hpp"

namespace cifs::render {

/// Interleaved 8-bit pixel layouts.
enum class PixelFormat { rgb8 = 3, rgba8 = 4 };

/// Bytes per pixel of a format.
constexpr std::size_t channel_count(PixelFormat format) noexcept {
  return static_cast<std::size_t>(format);
}

/// Writes an 8-bit PNG (sRGB values as given, row 0 at the top) through libpng. `pixels` holds
/// `width·height·channel_count(format)` bytes, interleaved. Written under a temporary name in the
/// same folder and renamed into place. Throws InvalidInput for a size mismatch or an empty image,
/// IoError (naming `path`) when the file cannot be written.
void write_png(const std::filesystem::path& path, std::span<const std::uint8_t> pixels, std::size_t width,
               std::size_t height, PixelFormat format);

/// Writes the PNG into `file`'s temporary; the caller commits it (cifs::AtomicFiles).
void write_png(AtomicFile& file, std::span<const std::uint8_t> pixels, std::size_t width, std::size_t height,
               PixelFormat format);

/// A PNG read back (tests, tools): any PNG is converted to interleaved 8-bit `format`.
struct PngImage {
  std::size_t width = 0;
  std::size_t height = 0;
  PixelFormat format = PixelFormat::rgba8;
  std::vector<std::uint8_t> pixels;
};

/// Reads a PNG through libpng's simplified API. Throws IoError naming `path`, also — before any
/// allocation — when its pixels would take more than `max_bytes` (default: half the memory).
PngImage read_png(const std::filesystem::path& path, PixelFormat format = PixelFormat::rgba8,
                  std::uint64_t max_bytes = largest_input());

using Rgb8 = std::array<std::uint8_t, 3>;

struct ToneMapOptions {
  /// Density mapped to the top of the ramp; 0 takes the maximum of the data.
  double max_density = 0;
  /// v ↦ v^(1/gamma) after the log mapping: gamma > 1 lifts faint regions.
  double gamma = 1;
  /// Colour stops spread evenly over [0, 1] and interpolated linearly (in 8-bit sRGB values, as
  /// previews are). At least one stop. Default: black, deep blue, orange, white.
  std::vector<Rgb8> ramp = {{0, 0, 0}, {20, 30, 110}, {235, 120, 30}, {255, 255, 255}};
};

/// Log-density tone mapping for chaos-game renders. Each value d (hits or density, `width·height`
/// values in any order; the output keeps it) becomes
///   v = log(1 + d) / log(1 + max),  clamped to [0, 1],  then v ↦ v^(1/gamma),
/// and the colour of the ramp at v. The logarithm keeps the structure of attractors whose density
/// spans many orders of magnitude (the fern's stem against its tips) that a linear map would
/// flatten to black. Non-finite and negative values count as 0; with max ≤ 0 every pixel takes the
/// first stop. Returns 3 bytes per value (PixelFormat::rgb8). Throws InvalidInput for an empty ramp
/// or gamma ≤ 0.
std::vector<std::uint8_t> tone_map_log_density(std::span<const float> density,
                                               const ToneMapOptions& options = {});

}  // namespace cifs::render
