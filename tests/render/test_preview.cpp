// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>

#include "cifs/errors.hpp"
#include "cifs/render/preview.hpp"
#include "cifs/render/raster.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using namespace cifs::render;
using cifs_test::ScratchDir;

namespace {

Image two_pixels() {
  Image image;
  image.width = 2;
  image.height = 1;
  // Pixel 0: empty. Pixel 1: half-covered by linear (0.2, 0.5, 1), premultiplied.
  image.channels["R"] = {0, 0.1f};
  image.channels["G"] = {0, 0.25f};
  image.channels["B"] = {0, 0.5f};
  image.channels["A"] = {0, 0.5f};
  return image;
}

}  // namespace

TEST_CASE("Shaded previews composite premultiplied colour over the background in linear light",
          "[render][preview]") {
  PreviewOptions options;
  options.background = {255, 255, 255};
  const auto white = preview_rgb8(two_pixels(), options);
  REQUIRE(white.size() == 6);
  CHECK(white[0] == 255);  // empty: the background
  // Pixel 1: 0.1 + 0.5·1 = 0.6 linear → sRGB 1.055·0.6^(1/2.4) − 0.055 = 0.7965 → 203.
  CHECK(white[3] == 203);
  CHECK(white[4] == 225);  // 0.75 → 0.8808 → 225
  CHECK(white[5] == 255);  // 1.0
  options.background = {0, 0, 0};
  const auto black = preview_rgb8(two_pixels(), options);
  CHECK(black[0] == 0);
  CHECK(black[3] == 89);  // 0.1 → 0.3492 → 89
}

TEST_CASE("Density previews are the log tone mapping; automatic mode picks them", "[render][preview]") {
  Image image = two_pixels();
  image.channels["density"] = {0, 40};
  const auto automatic = preview_rgb8(image);
  CHECK(automatic == tone_map_log_density(image.channels["density"]));
  image.channels["density"] = {0, 0};
  PreviewOptions shaded;
  shaded.mode = PreviewMode::shaded;
  CHECK(preview_rgb8(image) == preview_rgb8(image, shaded));
  ScratchDir dir;
  preview_png(dir.path() / "p.png", image);
  const PngImage back = read_png(dir.path() / "p.png", PixelFormat::rgb8);
  CHECK(back.pixels == preview_rgb8(image));
}

TEST_CASE("Previews refuse images without the channels they need", "[render][preview]") {
  Image image = two_pixels();
  image.channels.erase("A");
  CHECK_THROWS_WITH(preview_rgb8(image), Catch::Contains("no channel A"));
  PreviewOptions density;
  density.mode = PreviewMode::density;
  CHECK_THROWS_WITH(preview_rgb8(image, density), Catch::Contains("no channel density"));
  CHECK_THROWS_AS(preview_rgb8(Image{}), InvalidInput);
}
