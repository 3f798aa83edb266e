// SPDX-License-Identifier: MIT
// Fuzzing: the image readers, render::read_exr (a file starting with OpenEXR's magic number) and
// render::read_png (anything else; RGBA on even sizes, RGB on odd ones). They take paths: the bytes
// go to a scratch file first. Property: an image read writes (write_exr, write_png) and reads back
// to the same size, channels, pixels (bit for bit: NaN, ±inf, −0 and subnormals included), state
// and attributes. Work per input: images of at most 1 MB (the readers' `max_bytes`: a header of a few
// bytes claiming 10^9 × 10^9 pixels is refused before anything is allocated).
#include <unistd.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cifs/render/image.hpp"
#include "cifs/render/png.hpp"
#include "fuzz.hpp"

// Named, not anonymous: the harnesses compile as unity batches (CIFS_UNITY), each in its own namespace.
namespace fuzz_image {

using namespace cifs;

const std::filesystem::path& scratch() {
  return fuzz::scratch("image");
}

constexpr std::uint64_t kMaxBytes = std::uint64_t{1}
                                    << 20;  // 16 MB: 467 exec/s, page faults and memset (perf)

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

bool same(const render::Image& a, const render::Image& b) {
  if (a.width != b.width || a.height != b.height || a.state != b.state || a.attributes != b.attributes ||
      a.channels.size() != b.channels.size())
    return false;
  for (auto i = a.channels.begin(), j = b.channels.begin(); i != a.channels.end(); ++i, ++j)
    if (i->first != j->first || !same_bits(i->second, j->second)) return false;
  return true;
}

void exr_round_trip(const std::filesystem::path& input) {
  const render::Image image = render::read_exr(input, kMaxBytes);
  const std::filesystem::path again = scratch() / "again.exr";
  const render::Image back = fuzz::no_refusal(
      [&] {
        render::write_exr(again, image);
        return render::read_exr(again);
      },
      "EXR round trip: what was read writes and reads");
  fuzz::require(same(back, image), "EXR round trip");
}

void png_round_trip(const std::filesystem::path& input, render::PixelFormat format) {
  const render::PngImage image = render::read_png(input, format, kMaxBytes);
  const std::filesystem::path again = scratch() / "again.png";
  const render::PngImage back = fuzz::no_refusal(
      [&] {
        render::write_png(again, image.pixels, image.width, image.height, format);
        return render::read_png(again, format);
      },
      "PNG round trip: what was read writes and reads");
  fuzz::require(back.width == image.width && back.height == image.height && back.pixels == image.pixels,
                "PNG round trip");
}

CIFS_FUZZ_HARNESS(image) {
  const std::filesystem::path input = scratch() / "input";
  {
    std::ofstream out(input, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data),  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
              static_cast<std::streamsize>(size));
  }
  static constexpr std::uint8_t kExrMagic[] = {0x76, 0x2f, 0x31, 0x01};
  const bool exr = size >= 4 && std::memcmp(data, kExrMagic, 4) == 0;
  fuzz::refusals_allowed([&] {
    if (exr)
      exr_round_trip(input);
    else
      png_round_trip(input, size % 2 == 0 ? render::PixelFormat::rgba8 : render::PixelFormat::rgb8);
  });
  return 0;
}

}  // namespace fuzz_image
