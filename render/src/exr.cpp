// SPDX-License-Identifier: MIT
// cifs — OpenEXR writer and reader: FLOAT channels at full precision, a UINT `state` channel, and
// string attributes, written through Imf::OutputFile + FrameBuffer.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cstdint>
#include <exception>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/render/image.hpp"

namespace cifs::render {

namespace {

constexpr const char* kStateChannel = "state";

void check_image(const Image& image) {
  if (image.width == 0 || image.height == 0)
    throw InvalidInput("the EXR image is empty (" + std::to_string(image.width) + " by " +
                       std::to_string(image.height) + ")");
  if (image.width > INT_MAX || image.height > INT_MAX || image.width > INT_MAX / image.height)
    throw InvalidInput("the image is too large for OpenEXR; lower the image size");
  if (image.channels.empty() && !image.state) throw InvalidInput("the EXR image has no channel");
  const std::size_t n = image.width * image.height;
  for (const auto& [name, values] : image.channels) {
    if (name.empty()) throw InvalidInput("an EXR channel has an empty name");
    if (name == kStateChannel)
      throw InvalidInput("the EXR channel name \"state\" is reserved for the UINT state channel");
    if (values.size() != n)
      throw InvalidInput("the EXR channel \"" + name + "\" holds " + std::to_string(values.size()) +
                         " values, expected " + std::to_string(n));
  }
  if (image.state && image.state->size() != n)
    throw InvalidInput("the EXR state channel holds " + std::to_string(image.state->size()) +
                       " values, expected " + std::to_string(n));
}

/// What the first header of an OpenEXR file claims, read before OpenEXR reads it: OpenEXR allocates what
/// a header claims before it reads it (a string attribute of 2 GB, a line-offset table for a 10^9-line
/// data window), so that a file of a hundred bytes could make it allocate and zero gigabytes.
struct ExrClaims {
  std::int64_t width = 0, height = 0, channels = 0;
};

/// The attribute types of a fixed size in OpenEXR's layout (Imf's TypedAttribute<T>::readValueFrom).
const std::map<std::string, std::int32_t, std::less<>> kFixedSizes = {{"box2i", 16},
                                                                      {"box2f", 16},
                                                                      {"compression", 1},
                                                                      {"lineOrder", 1},
                                                                      {"envmap", 1},
                                                                      {"deepImageState", 1},
                                                                      {"int", 4},
                                                                      {"float", 4},
                                                                      {"double", 8},
                                                                      {"v2i", 8},
                                                                      {"v2f", 8},
                                                                      {"v2d", 16},
                                                                      {"v3i", 12},
                                                                      {"v3f", 12},
                                                                      {"v3d", 24},
                                                                      {"m33f", 36},
                                                                      {"m33d", 72},
                                                                      {"m44f", 64},
                                                                      {"m44d", 128},
                                                                      {"rational", 8},
                                                                      {"timecode", 8},
                                                                      {"keycode", 28},
                                                                      {"chromaticities", 32},
                                                                      {"tiledesc", 9}};

/// Every header's attribute sizes checked against the file's length (IoError naming the attribute and
/// both figures); the data window and channel count of the first header. Empty when the bytes do not
/// follow OpenEXR's header layout: OpenEXR says what is wrong then.
std::optional<ExrClaims> read_exr_claims(const std::filesystem::path& path) {
  std::error_code ec;
  const auto file_size = static_cast<std::int64_t>(std::filesystem::file_size(path, ec));
  std::ifstream in(path, std::ios::binary);
  if (!in || ec) return std::nullopt;
  const auto read_exact = [&](void* out, std::streamsize n) { return !!in.read(static_cast<char*>(out), n); };
  const auto read_name = [&](std::string& name) {  // NUL-terminated, at most 255 bytes (long names)
    name.clear();
    for (char c = 0; in.get(c);) {
      if (c == '\0') return true;
      if (name.size() == 255) return false;
      name.push_back(c);
    }
    return false;
  };
  std::uint32_t magic = 0, version = 0;
  if (!read_exact(&magic, 4) || !read_exact(&version, 4) || magic != 20000630u) return std::nullopt;
  const bool multipart = (version & 0x1000u) != 0;  // headers follow one another, an empty one ends them
  ExrClaims claims;
  std::string name, type;
  for (bool first = true;; first = false) {
    while (read_name(name) && !name.empty()) {
      std::int32_t size = 0;
      if (!read_name(type) || !read_exact(&size, 4)) return std::nullopt;
      const std::int64_t left = file_size - static_cast<std::int64_t>(in.tellg());
      if (size < 0 || size > left)
        throw IoError(path.string() + ": the header's attribute '" + excerpt(name) + "' claims " +
                      std::to_string(size) + " bytes, " + std::to_string(left) + " are left in the file");
      const std::int64_t end = static_cast<std::int64_t>(in.tellg()) + size;
      // OpenEXR reads a known type's value by its own layout, not by the size: where the two disagree its
      // reading and this one part ways (and it reads a later "size" as another attribute's), so they must
      // agree here.
      const auto refuse = [&](const std::string& what) {
        throw IoError(path.string() + ": the header's attribute '" + excerpt(name) + "' (" + excerpt(type) +
                      ") claims " + std::to_string(size) + " bytes, " + what);
      };
      if (const auto fixed = kFixedSizes.find(type); fixed != kFixedSizes.end() && fixed->second != size)
        refuse("a " + type + " takes " + std::to_string(fixed->second));
      if (type == "preview") {  // width, height, then 4 bytes a pixel
        std::array<std::uint32_t, 2> wh{};
        if (size < 8 || !read_exact(wh.data(), 8)) return std::nullopt;
        if (std::uint64_t{wh[0]} * wh[1] * 4 + 8 != static_cast<std::uint64_t>(size))
          refuse("its " + std::to_string(wh[0]) + " × " + std::to_string(wh[1]) + " pixels take " +
                 std::to_string(std::uint64_t{wh[0]} * wh[1] * 4 + 8));
      } else if (type == "chlist") {
        // Per channel: its name, then 16 bytes (pixel type, linear flag, reserved, sampling); a NUL ends
        // them.
        for (std::string channel; in.peek() != 0 && read_name(channel); in.seekg(16, std::ios::cur))
          claims.channels += first && name == "channels" ? 1 : 0;
        if (!in || in.get() != 0) return std::nullopt;
        if (const auto read = static_cast<std::int64_t>(in.tellg()); read != end)
          refuse("its channel list takes " + std::to_string(read - (end - size)));
      } else if (first && name == "dataWindow" && type == "box2i") {
        std::array<std::int32_t, 4> box{};  // min x, min y, max x, max y
        if (!read_exact(box.data(), 16)) return std::nullopt;
        claims.width = std::int64_t{box[2]} - box[0] + 1;
        claims.height = std::int64_t{box[3]} - box[1] + 1;
      }
      in.seekg(end, std::ios::beg);
    }
    if (!in || !name.empty()) return std::nullopt;
    if (!multipart || in.peek() == 0) break;
  }
  return claims;
}

}  // namespace

void write_exr(AtomicFile& file, const Image& image) {
  check_image(image);
  const int w = static_cast<int>(image.width);
  const int h = static_cast<int>(image.height);
  // Header: everything (channels, attributes) must be set before the OutputFile is constructed.
  Imf::Header header(w, h);
  for (const auto& [key, value] : image.attributes) {
    // The default header already holds the standard attributes; overwriting one of them with a
    // string would make an invalid file, so those names are refused.
    if (key.empty() || header.find(key) != header.end())
      throw InvalidInput("the EXR attribute name \"" + key + "\" is empty or reserved by OpenEXR");
    header.insert(key, Imf::StringAttribute(value));
  }
  Imf::FrameBuffer frame;
  const std::size_t row_floats = image.width * sizeof(float);
  for (const auto& [name, values] : image.channels) {
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    // OpenEXR's Slice takes a non-const base pointer, but an OutputFile only reads through it.
    frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(values.data())),
                                  sizeof(float), row_floats));
  }
  if (image.state) {
    header.channels().insert(kStateChannel, Imf::Channel(Imf::UINT));
    frame.insert(
        kStateChannel,
        Imf::Slice(Imf::UINT, reinterpret_cast<char*>(const_cast<std::uint32_t*>(image.state->data())),
                   sizeof(std::uint32_t), image.width * sizeof(std::uint32_t)));
  }

  try {
    // The file is complete only when the OutputFile is destroyed: close the scope before renaming.
    Imf::OutputFile out(file.temporary().c_str(), header);
    out.setFrameBuffer(frame);
    out.writePixels(h);
  } catch (const std::exception& e) {
    throw IoError(file.target().string() + ": cannot write OpenEXR (" + file.about_target(e.what()) + ")");
  }
}

void write_exr(const std::filesystem::path& path, const Image& image) {
  check_image(image);  // before the target's temporary is made
  AtomicFile file(path);
  write_exr(file, image);
  file.commit();
}

Image read_exr(const std::filesystem::path& path, std::uint64_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path.string() + ": no such file");
  // A header of a few bytes may claim 10^9 × 10^9 pixels: refused before anything is allocated.
  if (const std::optional<ExrClaims> claims = read_exr_claims(path);
      claims && claims->width > 0 && claims->height > 0) {
    const auto [width, height, channels] = *claims;
    const double bytes = static_cast<double>(width) * static_cast<double>(height) *
                         static_cast<double>(std::max<std::int64_t>(channels, 1)) * sizeof(float);
    check_decoded_size(path,
                       "the image is " + std::to_string(width) + " × " + std::to_string(height) +
                           " pixels of " + std::to_string(channels) +
                           (channels == 1 ? " channel" : " channels"),
                       bytes < 1.8e19 ? static_cast<std::uint64_t>(bytes) : ~std::uint64_t{0}, max_bytes);
  }
  try {
    Imf::InputFile in(path.c_str());
    const Imf::Header& header = in.header();
    const Imath::Box2i window = header.dataWindow();
    Image image;
    image.width = static_cast<std::size_t>(std::int64_t{window.max.x} - window.min.x + 1);
    image.height = static_cast<std::size_t>(std::int64_t{window.max.y} - window.min.y + 1);
    const std::size_t n = image.width * image.height;
    // Slice base pointers are addressed by absolute pixel coordinates: shift by the window origin.
    const auto origin = static_cast<std::ptrdiff_t>(window.min.x) +
                        static_cast<std::ptrdiff_t>(window.min.y) * static_cast<std::ptrdiff_t>(image.width);
    Imf::FrameBuffer frame;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      const std::string name = it.name();
      // What reads must write back: write_exr keeps the name for the UINT state channel.
      if (name == kStateChannel && it.channel().type != Imf::UINT)
        throw IoError(path.string() + ": the channel \"state\" holds " +
                      (it.channel().type == Imf::HALF ? "HALF" : "FLOAT") +
                      " values; cifs reads a channel of that name only as the UINT state channel");
      if (name == kStateChannel) {
        image.state.emplace(n);
        frame.insert(name, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(image.state->data() - origin),
                                      sizeof(std::uint32_t), image.width * sizeof(std::uint32_t)));
      } else {
        std::vector<float>& values = image.channels[name];
        values.resize(n);
        frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data() - origin),
                                      sizeof(float), image.width * sizeof(float)));
      }
    }
    in.setFrameBuffer(frame);
    in.readPixels(window.min.y, window.max.y);
    for (auto it = header.begin(); it != header.end(); ++it)
      if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        image.attributes[it.name()] = text->value();
    return image;
  } catch (const IoError&) {
    throw;
  } catch (const std::exception& e) {
    throw IoError(path.string() + ": cannot read OpenEXR (" + e.what() + ")");
  }
}

}  // namespace cifs::render
