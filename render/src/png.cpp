// SPDX-License-Identifier: MIT
// cifs — PNG through libpng's simplified API (no setjmp/longjmp across C++ frames), and
// log-density tone mapping.
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/render/png.hpp"

namespace cifs::render {

namespace {

png_uint_32 png_format(PixelFormat format) noexcept {
  return format == PixelFormat::rgb8 ? PNG_FORMAT_RGB : PNG_FORMAT_RGBA;
}

void check_pixels(std::span<const std::uint8_t> pixels, std::size_t width, std::size_t height,
                  PixelFormat format) {
  if (width == 0 || height == 0) throw InvalidInput("the PNG image is empty");
  // libpng's row stride is an int: keep a row (and the whole image) addressable.
  if (width > INT_MAX / 4 || height > INT_MAX)
    throw InvalidInput("the image is too large for PNG; lower the image size");
  const std::size_t stride = width * channel_count(format);
  if (pixels.size() != stride * height)
    throw InvalidInput("the PNG pixels hold " + std::to_string(pixels.size()) + " bytes, expected " +
                       std::to_string(stride * height) + " (" + std::to_string(width) + " by " +
                       std::to_string(height) + " by " + std::to_string(channel_count(format)) + ")");
}

}  // namespace

void write_png(AtomicFile& file, std::span<const std::uint8_t> pixels, std::size_t width, std::size_t height,
               PixelFormat format) {
  check_pixels(pixels, width, height, format);
  const std::size_t stride = width * channel_count(format);
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = png_format(format);
  errno = 0;
  const int ok = png_image_write_to_file(&image, file.temporary().c_str(), 0, pixels.data(),
                                         static_cast<png_int_32>(stride), nullptr);
  if (!ok) {
    // libpng says "Write Error" for any failed write: the system's reason (a full disk) is errno's.
    const int error = errno;
    std::string message = file.about_target(image.message);
    if (error != 0) message += std::string(": ") + std::strerror(error);
    png_image_free(&image);
    throw IoError(file.target().string() + ": cannot write PNG (" + message + ")");
  }
}

void write_png(const std::filesystem::path& path, std::span<const std::uint8_t> pixels, std::size_t width,
               std::size_t height, PixelFormat format) {
  check_pixels(pixels, width, height, format);  // before the target's temporary is made
  AtomicFile file(path);
  write_png(file, pixels, width, height, format);
  file.commit();
}

PngImage read_png(const std::filesystem::path& path, PixelFormat format, std::uint64_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path.string() + ": no such file");
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw IoError(path.string() + ": cannot read PNG (" + image.message + ")");
  image.format = png_format(format);
  try {
    check_decoded_size(
        path,
        "the image is " + std::to_string(image.width) + " × " + std::to_string(image.height) + " pixels",
        std::uint64_t{image.width} * image.height * channel_count(format), max_bytes);
  } catch (const IoError&) {
    png_image_free(&image);
    throw;
  }
  PngImage result;
  result.width = image.width;
  result.height = image.height;
  result.format = format;
  result.pixels.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, result.pixels.data(), 0, nullptr)) {
    const std::string message = image.message;
    png_image_free(&image);
    throw IoError(path.string() + ": cannot read PNG (" + message + ")");
  }
  return result;
}

std::vector<std::uint8_t> tone_map_log_density(std::span<const float> density,
                                               const ToneMapOptions& options) {
  if (options.ramp.empty()) throw InvalidInput("the colour ramp is empty; give at least one colour");
  if (!(options.gamma > 0) || !std::isfinite(options.gamma))
    throw InvalidInput("the tone-mapping gamma " +
                       (std::isfinite(options.gamma) ? number_text(options.gamma, 6) + " is not positive"
                                                     : std::string("is not a finite number")) +
                       "; give a positive gamma");
  const auto clean = [](float d) { return std::isfinite(d) && d > 0 ? static_cast<double>(d) : 0.0; };
  double top = options.max_density;
  if (!(top > 0)) {
    top = 0;
    for (const float d : density) top = std::max(top, clean(d));
  }
  const double scale = top > 0 ? 1 / std::log1p(top) : 0;
  const double inverse_gamma = 1 / options.gamma;
  const auto& ramp = options.ramp;
  const double last = static_cast<double>(ramp.size() - 1);
  std::vector<std::uint8_t> rgb(density.size() * 3);
  for (std::size_t i = 0; i < density.size(); ++i) {
    double v = std::clamp(std::log1p(clean(density[i])) * scale, 0.0, 1.0);
    if (inverse_gamma != 1) v = std::pow(v, inverse_gamma);
    const double s = v * last;
    const auto k = std::min(static_cast<std::size_t>(s), ramp.size() - 1);
    const std::size_t k1 = std::min(k + 1, ramp.size() - 1);
    const double t = s - static_cast<double>(k);
    for (std::size_t c = 0; c < 3; ++c) {
      const double value = (1 - t) * ramp[k][c] + t * ramp[k1][c];
      rgb[3 * i + c] = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  }
  return rgb;
}

}  // namespace cifs::render
