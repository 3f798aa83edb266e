// SPDX-License-Identifier: MIT
// cifs — scene-referred images and their OpenEXR files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cifs/files.hpp"

#include "cifs/files.hpp"

namespace cifs::render {

/// A multi-channel image: every channel holds `width·height` values, row-major, row 0 at the top
/// (y down, the OpenEXR convention), so pixel (x, y) is element `y·width + x`.
/// Usual channel names: `R G B A Z density N.x N.y N.z` (docs/rendering.md).
struct Image {
  std::size_t width = 0;
  std::size_t height = 0;
  /// Float channels by name; written as 32-bit FLOAT, never as half.
  std::map<std::string, std::vector<float>> channels;
  /// Optional UINT channel `state`: the automaton state that produced the pixel.
  std::optional<std::vector<std::uint32_t>> state;
  /// Header attributes (experiment, seed, depth, …), written as OpenEXR string attributes.
  std::map<std::string, std::string> attributes;
};

/// Writes every channel and attribute of `image` to an OpenEXR scan-line file (ZIP, lossless).
/// The file is written under a temporary name in the same folder and renamed into place, so
/// `path` is either the complete new image or left as it was.
/// Throws InvalidInput for an empty image, a channel of the wrong size, an empty channel name, a
/// float channel named `state`, or an attribute name that OpenEXR reserves (`channels`,
/// `compression`, `dataWindow`, …); IoError (naming `path`) when the file cannot be written.
void write_exr(const std::filesystem::path& path, const Image& image);

/// Writes the image into `file`'s temporary; the caller commits it (with the other outputs of a
/// run: cifs::AtomicFiles). Throws as write_exr, naming the file's target.
void write_exr(AtomicFile& file, const Image& image);

/// Reads an OpenEXR scan-line file back: every channel (HALF and FLOAT as float, a UINT channel
/// named `state` into Image::state, other UINT channels as float) and every string attribute.
/// Throws IoError naming `path` when the file is missing or not a readable OpenEXR image, and — before
/// any allocation — when its pixels would take more than `max_bytes` (default: half the memory).
Image read_exr(const std::filesystem::path& path, std::uint64_t max_bytes = largest_input());

}  // namespace cifs::render
