// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>

#include "cifs/errors.hpp"
#include "cifs/render/png.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using namespace cifs::render;
using cifs_test::ScratchDir;

TEST_CASE("PNG: RGB and RGBA written and read back through libpng", "[render]") {
  ScratchDir dir;
  const std::size_t w = 17, h = 9;
  for (const PixelFormat format : {PixelFormat::rgb8, PixelFormat::rgba8}) {
    const std::size_t n = channel_count(format);
    std::vector<std::uint8_t> pixels(w * h * n);
    for (std::size_t i = 0; i < pixels.size(); ++i)
      pixels[i] = static_cast<std::uint8_t>((i * 37 + 11) % 256);
    if (n == 4)
      for (std::size_t i = 3; i < pixels.size(); i += 4) pixels[i] = 255;  // opaque: no premultiplication
    const auto path = dir.path() / (n == 3 ? "rgb.png" : "rgba.png");
    write_png(path, pixels, w, h, format);
    const PngImage back = read_png(path, format);
    CHECK(back.width == w);
    CHECK(back.height == h);
    REQUIRE(back.pixels.size() == pixels.size());
    // A few pixels: the first, one in the middle, the last (row 0 is the top row).
    for (const std::size_t p : {std::size_t{0}, (h / 2) * w + w / 2, w * h - 1})
      for (std::size_t c = 0; c < n; ++c) CHECK(int{back.pixels[p * n + c]} == int{pixels[p * n + c]});
    CHECK(back.pixels == pixels);
  }
  CHECK(dir.names() == std::set<std::string>{"rgb.png", "rgba.png"});
}

TEST_CASE("PNG: bad sizes and paths", "[render]") {
  ScratchDir dir;
  const std::vector<std::uint8_t> pixels(12, 0);
  CHECK_THROWS_AS(write_png(dir.path() / "a.png", pixels, 3, 2, PixelFormat::rgb8), InvalidInput);
  CHECK_THROWS_AS(write_png(dir.path() / "a.png", pixels, 0, 0, PixelFormat::rgb8), InvalidInput);
  const auto missing = dir.path() / "none" / "a.png";
  CHECK_THROWS_AS(write_png(missing, pixels, 2, 2, PixelFormat::rgb8), IoError);
  CHECK_THROWS_WITH(write_png(missing, pixels, 2, 2, PixelFormat::rgb8), Catch::Contains(missing.string()));
  CHECK(dir.names().empty());
  CHECK_THROWS_AS(read_png(dir.path() / "absent.png"), IoError);
}

TEST_CASE("Log-density tone mapping", "[render]") {
  ToneMapOptions options;
  options.ramp = {{0, 0, 0}, {255, 255, 255}};
  const std::vector<float> d = {0, 1, 3, 15, -2, NAN, INFINITY};
  const auto rgb = tone_map_log_density(d, options);
  REQUIRE(rgb.size() == d.size() * 3);
  // v = log(1 + d) / log(1 + 15): 0, ¼, ½, 1 on a grey ramp; negative and non-finite are 0.
  CHECK(int{rgb[0]} == 0);
  CHECK(std::abs(int{rgb[3]} - 64) <= 1);
  CHECK(std::abs(int{rgb[6]} - 128) <= 1);
  CHECK(int{rgb[9]} == 255);
  CHECK(int{rgb[12]} == 0);
  CHECK(int{rgb[15]} == 0);
  CHECK(int{rgb[18]} == 0);
  CHECK(rgb[9] == rgb[10]);

  options.gamma = 2;  // v^(1/2): ¼ → ½
  CHECK(std::abs(int{tone_map_log_density(d, options)[3]} - 128) <= 1);
  options.gamma = 1;
  options.max_density = 3;  // fixed scale: 15 clamps to the top
  const auto fixed = tone_map_log_density(d, options);
  CHECK(int{fixed[6]} == 255);
  CHECK(int{fixed[9]} == 255);

  // The default ramp starts black and ends white; a monotone density stays monotone in brightness.
  const std::vector<float> ramp_in = {0, 1, 10, 100, 1000};
  const auto coloured = tone_map_log_density(ramp_in);
  CHECK(coloured[0] + coloured[1] + coloured[2] == 0);
  CHECK(int{coloured[12]} + coloured[13] + coloured[14] == 3 * 255);
  for (std::size_t i = 1; i < ramp_in.size(); ++i)
    CHECK(coloured[3 * i] + coloured[3 * i + 1] + coloured[3 * i + 2] >
          coloured[3 * i - 3] + coloured[3 * i - 2] + coloured[3 * i - 1]);

  options.ramp.clear();
  CHECK_THROWS_AS(tone_map_log_density(d, options), InvalidInput);
  CHECK_THROWS_AS(tone_map_log_density(d, ToneMapOptions{.max_density = 0, .gamma = 0, .ramp = {{0, 0, 0}}}),
                  InvalidInput);
}
