// SPDX-License-Identifier: MIT
#include <sys/resource.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/render/image.hpp"
#include "cifs/render/png.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using namespace cifs::render;
using cifs_test::ScratchDir;

namespace {

/// Every channel of the issue, with values that a half or a lossy codec would not keep: tiny,
/// huge, negative, subnormal and irrational-looking floats, and states above 2¹⁶.
Image full_image(std::size_t w, std::size_t h) {
  Image image;
  image.width = w;
  image.height = h;
  const std::vector<std::string> names = {"R", "G", "B", "A", "Z", "density", "N.x", "N.y", "N.z"};
  for (std::size_t c = 0; c < names.size(); ++c) {
    std::vector<float> values(w * h);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double t = static_cast<double>(i) * 0.731 + static_cast<double>(c) * 1.37;
      values[i] = static_cast<float>(std::sin(t) * std::pow(10.0, static_cast<double>(i % 13) - 6.0));
    }
    values[0] = 1e-40f;    // subnormal
    values[1] = -3.4e38f;  // near the float range
    values[2] = 0.1f;      // not representable as half
    image.channels[names[c]] = std::move(values);
  }
  std::vector<std::uint32_t> state(w * h);
  for (std::size_t i = 0; i < state.size(); ++i) state[i] = static_cast<std::uint32_t>(i * 2654435761u);
  state[3] = 0xFFFFFFFFu;
  image.state = std::move(state);
  image.attributes = {
      {"experiment", "fern, 1e7 points"}, {"seed", "42"}, {"depth", "12"}, {"comment", "UTF-8: ½ ⅓ €"}};
  return image;
}

bool same_float_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

}  // namespace

TEST_CASE("EXR: every channel and attribute survives a round trip bit for bit", "[render]") {
  ScratchDir dir;
  const Image image = full_image(37, 23);  // odd sizes: rows are not padded
  const auto path = dir.path() / "image.exr";
  write_exr(path, image);
  CHECK(dir.names() == std::set<std::string>{"image.exr"});  // no temporary file left behind

  const Image back = read_exr(path);
  CHECK(back.width == 37);
  CHECK(back.height == 23);
  REQUIRE(back.channels.size() == image.channels.size());
  for (const auto& [name, values] : image.channels) {
    INFO("channel " << name);
    REQUIRE(back.channels.count(name) == 1);
    for (const float v : back.channels.at(name)) REQUIRE(!std::isnan(v));
    CHECK(same_float_bits(back.channels.at(name), values));
  }
  REQUIRE(back.state.has_value());
  CHECK(*back.state == *image.state);
  for (const auto& [key, value] : image.attributes) {
    INFO("attribute " << key);
    REQUIRE(back.attributes.count(key) == 1);
    CHECK(back.attributes.at(key) == value);
  }
}

TEST_CASE("EXR: pixel order is row-major with row 0 at the top", "[render]") {
  ScratchDir dir;
  Image image;
  image.width = 3;
  image.height = 2;
  image.channels["density"] = {0, 1, 2, 10, 11, 12};
  write_exr(dir.path() / "order.exr", image);
  const Image back = read_exr(dir.path() / "order.exr");
  CHECK(back.channels.at("density") == std::vector<float>{0, 1, 2, 10, 11, 12});
  CHECK_FALSE(back.state.has_value());
}

TEST_CASE("EXR: a state-only image and overwriting an existing file", "[render]") {
  ScratchDir dir;
  const auto path = dir.path() / "state.exr";
  Image image;
  image.width = 4;
  image.height = 1;
  image.state = std::vector<std::uint32_t>{7, 0, 1u << 31, 5};
  write_exr(path, image);
  image.state = std::vector<std::uint32_t>{1, 2, 3, 4};
  write_exr(path, image);  // replaces the file through the rename
  const Image back = read_exr(path);
  CHECK(back.channels.empty());
  CHECK(*back.state == std::vector<std::uint32_t>{1, 2, 3, 4});
  CHECK(dir.names() == std::set<std::string>{"state.exr"});
}

TEST_CASE("EXR: bad paths throw IoError naming the path and leave no file", "[render]") {
  ScratchDir dir;
  const Image image = full_image(4, 4);
  const auto missing_folder = dir.path() / "no_such_folder" / "x.exr";
  CHECK_THROWS_AS(write_exr(missing_folder, image), IoError);
  CHECK_THROWS_WITH(write_exr(missing_folder, image), Catch::Contains(missing_folder.string()));
  CHECK_FALSE(std::filesystem::exists(missing_folder));

  std::filesystem::create_directory(dir.path() / "folder");
  CHECK_THROWS_AS(write_exr(dir.path() / "folder", image), IoError);
  CHECK(dir.names() == std::set<std::string>{"folder"});

  CHECK_THROWS_AS(read_exr(dir.path() / "absent.exr"), IoError);
  std::filesystem::path not_exr = dir.path() / "text.exr";
  {
    std::ofstream out(not_exr);
    out << "not an image";
  }
  CHECK_THROWS_AS(read_exr(not_exr), IoError);
  CHECK_THROWS_WITH(read_exr(not_exr), Catch::Contains("text.exr"));
}

TEST_CASE("EXR and PNG: a failed write names the target, never the temporary", "[render][reliability]") {
  // Issue 33: OpenEXR's message named the file it wrote, the temporary (".out.exr.cifs-tmp.5232.0"),
  // and libpng's said "Write Error" without the reason. A limit on the file size makes the write fail.
  ScratchDir dir;
  const Image image = full_image(64, 64);
  std::vector<std::uint8_t> pixels(64 * 64 * 4);
  std::mt19937 random(7);  // noise: the PNG cannot compress below the limit
  for (std::uint8_t& p : pixels) p = static_cast<std::uint8_t>(random());
  struct rlimit old {};
  REQUIRE(::getrlimit(RLIMIT_FSIZE, &old) == 0);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
  struct rlimit small = old;
  small.rlim_cur = 2000;
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &small) == 0);
  std::string exr_message, png_message;
  try {
    write_exr(dir.path() / "out.exr", image);
  } catch (const IoError& e) {
    exr_message = e.what();
  }
  try {
    write_png(dir.path() / "out.png", pixels, 64, 64, PixelFormat::rgba8);
  } catch (const IoError& e) {
    png_message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
  CHECK_THAT(exr_message, Catch::StartsWith((dir.path() / "out.exr").string() + ": cannot write OpenEXR") &&
                              Catch::Contains("File too large"));
  CHECK_THAT(png_message, Catch::StartsWith((dir.path() / "out.png").string() + ": cannot write PNG") &&
                              Catch::Contains("File too large"));
  for (const std::string& message : {exr_message, png_message})
    CHECK(message.find("cifs-tmp") == std::string::npos);
  CHECK(dir.names().empty());
}

TEST_CASE("EXR: invalid images are refused before any file is made", "[render]") {
  ScratchDir dir;
  const auto path = dir.path() / "bad.exr";
  Image image = full_image(4, 4);
  SECTION("wrong channel size") {
    image.channels["R"].pop_back();
  }
  SECTION("wrong state size") {
    image.state->push_back(1);
  }
  SECTION("float channel named state") {
    image.channels["state"] = std::vector<float>(16, 0.f);
  }
  SECTION("reserved attribute") {
    image.attributes["compression"] = "none";
  }
  SECTION("empty image") {
    image = Image{};
  }
  CHECK_THROWS_AS(write_exr(path, image), InvalidInput);
  CHECK(dir.names().empty());
}

namespace {

std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void put_file_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

void put_u32_big_endian(std::string& bytes, std::size_t at, std::uint32_t x) {
  for (int i = 0; i < 4; ++i) bytes[at + static_cast<std::size_t>(i)] = static_cast<char>(x >> (24 - 8 * i));
}

// PNG's chunk checksum (ISO 3309 CRC-32), so that a patched header still reads as a valid chunk.
std::uint32_t png_crc(std::string_view bytes) {
  std::uint32_t c = 0xffffffffu;
  for (const char ch : bytes) {
    c ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) c = (c & 1u) != 0 ? 0xedb88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xffffffffu;
}

}  // namespace

TEST_CASE("EXR and PNG: a header claiming more pixels than memory holds is refused before allocating",
          "[render][reliability]") {
  // Issue 33 (the `image` fuzz harness spent its time here): a file of a few hundred bytes whose header
  // claims 10^9 × 10^9 pixels made the reader allocate first (std::bad_alloc, or gigabytes zero-filled).
  ScratchDir dir;
  const auto exr = dir.path() / "huge.exr";
  Image one;
  one.width = one.height = 1;
  one.channels["Y"] = {0.5f};
  write_exr(exr, one);
  std::string bytes = file_bytes(exr);
  const std::string key("dataWindow\0box2i\0", 17);
  const std::size_t at = bytes.find(key);
  REQUIRE(at != std::string::npos);
  const std::int32_t last = 999'999'999;  // the window's max corner (x, y): 10^9 × 10^9 pixels
  std::memcpy(&bytes[at + key.size() + 4 + 8], &last, 4);
  std::memcpy(&bytes[at + key.size() + 4 + 12], &last, 4);
  put_file_bytes(exr, bytes);
  CHECK_THROWS_MATCHES(
      read_exr(exr), IoError, Catch::Matchers::Predicate<std::exception>([&](const std::exception& e) {
        const std::string m = e.what();
        return m.find("huge.exr: the image is 1000000000 × 1000000000 pixels of 1 channel, 4000000000 GB") !=
                   std::string::npos &&
               m.find("GB an input may hold") != std::string::npos;
      }));
  // A string attribute claiming 2 GB (OpenEXR made and zeroed the string before reading it).
  one.attributes["comment"] = "x";
  write_exr(exr, one);
  bytes = file_bytes(exr);
  const std::string comment("comment\0string\0", 15);
  const std::size_t comment_at = bytes.find(comment);
  REQUIRE(comment_at != std::string::npos);
  const std::int32_t claimed = 2'000'000'000;
  std::memcpy(&bytes[comment_at + comment.size()], &claimed, 4);
  put_file_bytes(exr, bytes);
  const auto left = bytes.size() - (comment_at + comment.size() + 4);
  CHECK_THROWS_WITH(read_exr(exr), "" + exr.string() +
                                       ": the header's attribute 'comment' claims 2000000000 bytes, " +
                                       std::to_string(left) + " are left in the file");

  // A channel list whose size says more than its channels take: OpenEXR reads the list to its NUL and
  // then the rest as further attributes (the image fuzz harness: one of them claimed 1.85 GB); refused.
  write_exr(exr, one);
  bytes = file_bytes(exr);
  const std::string chlist("channels\0chlist\0", 16);
  const std::size_t chlist_at = bytes.find(chlist);
  REQUIRE(chlist_at != std::string::npos);
  std::int32_t chlist_size = 0;
  std::memcpy(&chlist_size, &bytes[chlist_at + chlist.size()], 4);
  const std::int32_t more = chlist_size + 4;
  std::memcpy(&bytes[chlist_at + chlist.size()], &more, 4);
  put_file_bytes(exr, bytes);
  CHECK_THROWS_WITH(read_exr(exr), exr.string() + ": the header's attribute 'channels' (chlist) claims " +
                                       std::to_string(more) + " bytes, its channel list takes " +
                                       std::to_string(chlist_size));
  // A fixed-size type with another size: refused the same way.
  write_exr(exr, one);
  bytes = file_bytes(exr);
  const std::string box("dataWindow\0box2i\0", 17);
  const std::int32_t twenty = 20;
  std::memcpy(&bytes[bytes.find(box) + box.size()], &twenty, 4);
  put_file_bytes(exr, bytes);
  CHECK_THROWS_WITH(read_exr(exr), Catch::Contains("'dataWindow' (box2i) claims 20 bytes, a box2i takes 16"));

  // A FLOAT channel named "state", the name write_exr keeps for the UINT state channel: what reads must
  // write back, so it is refused (libFuzzer: the round trip failed). Written as "stata", renamed in place.
  Image stata;
  stata.width = stata.height = 1;
  stata.channels["stata"] = {0.5f};
  write_exr(exr, stata);
  bytes = file_bytes(exr);
  const std::size_t name_at = bytes.find(std::string("stata\0", 6), bytes.find(chlist));
  REQUIRE(name_at != std::string::npos);
  bytes[name_at + 4] = 'e';
  put_file_bytes(exr, bytes);
  CHECK_THROWS_WITH(read_exr(exr), exr.string() +
                                       ": the channel \"state\" holds FLOAT values; cifs reads a "
                                       "channel of that name only as the UINT state channel");

  // The limit is the caller's: one pixel of one float channel takes 4 bytes.
  write_exr(dir.path() / "one.exr", one);
  CHECK_THROWS_WITH(read_exr(dir.path() / "one.exr", 3), Catch::Contains("GB an input may hold"));
  CHECK(read_exr(dir.path() / "one.exr", 4).channels.at("Y") == std::vector<float>{0.5f});

  const auto png = dir.path() / "huge.png";
  write_png(png, std::vector<std::uint8_t>(4, 255), 1, 1, PixelFormat::rgba8);
  bytes = file_bytes(png);
  REQUIRE(bytes.substr(12, 4) == "IHDR");
  put_u32_big_endian(bytes, 16, 1'000'000);  // libpng's own limit on either side
  put_u32_big_endian(bytes, 20, 1'000'000);
  put_u32_big_endian(bytes, 29, png_crc(std::string_view(bytes).substr(12, 17)));
  put_file_bytes(png, bytes);
  CHECK_THROWS_WITH(read_png(png),
                    Catch::Contains("huge.png: the image is 1000000 × 1000000 pixels, 4000 GB"));
  CHECK_THROWS_AS(read_png(png, PixelFormat::rgb8), IoError);
}
