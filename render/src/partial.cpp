// SPDX-License-Identifier: MIT
// cifs — shares of a distributed render: packed per pixel, combined exactly, unpacked on the root.
#include "cifs/render/partial.hpp"

#include <string>

#include "cifs/errors.hpp"
#include "framebuffer.hpp"

namespace cifs::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// The channel `name`, or nullptr when the image has none.
const std::vector<float>* find(const Image& image, const char* name) {
  const auto it = image.channels.find(name);
  return it == image.channels.end() ? nullptr : &it->second;
}
std::vector<float>* find(Image& image, const char* name) {
  const auto it = image.channels.find(name);
  return it == image.channels.end() ? nullptr : &it->second;
}

}  // namespace

void check_part(const Part& part) {
  if (part.count == 0 || part.index >= part.count)
    throw InvalidInput("part " + std::to_string(part.index) + " of " + std::to_string(part.count) +
                       " does not exist (expected 0 ≤ index < count)");
}

DensityLayer empty_density_layer(std::size_t pixels) {
  return {std::vector<double>(pixels, 0), std::vector<float>(pixels, kInf),
          std::vector<std::uint64_t>(pixels, 0), std::vector<std::uint32_t>(pixels, kNoState)};
}

void composite(Image& image, const DensityLayer& layer, const Rgb& color) {
  detail::composite_points(image, {layer.density, layer.depth, layer.state}, color);
}

void combine_shares(std::span<const PixelShare> in, std::span<PixelShare> inout) noexcept {
  for (std::size_t i = 0; i < in.size(); ++i) {
    const PixelShare& a = in[i];
    PixelShare& b = inout[i];
    const double density = a.density + b.density;
    if (a.z < b.z || (a.z == b.z && a.key < b.key)) b = a;
    b.density = density;
  }
}

void pack(const Share& share, std::size_t first, std::span<PixelShare> out) {
  const Image& image = share.image;
  const std::size_t W = image.width;
  if (first + out.size() > W * image.height) throw InvalidInput("the pixels to share run beyond the image");
  std::fill(out.begin(), out.end(), PixelShare{});
  if (share.kind == Share::Kind::points) {
    const DensityLayer& l = share.points;
    for (std::size_t k = 0; k < out.size(); ++k) {
      const std::size_t i = first + k;
      if (!(l.depth[i] < kInf)) continue;
      // The later of equally near samples wins: the larger index, the smaller key.
      out[k] = {l.density[i],
                std::numeric_limits<std::uint64_t>::max() - l.sample[i],
                l.depth[i],
                static_cast<float>(share.color[0]),
                static_cast<float>(share.color[1]),
                static_cast<float>(share.color[2]),
                1,
                0,
                0,
                0,
                l.state[i],
                0};
    }
    return;
  }
  const std::vector<float>*R = find(image, "R"), *G = find(image, "G"), *B = find(image, "B"),
        *A = find(image, "A"), *Z = find(image, "Z");
  const std::vector<float>*Nx = find(image, "N.x"), *Ny = find(image, "N.y"), *Nz = find(image, "N.z");
  const std::vector<float>* density = find(image, "density");
  if (!R || !G || !B || !A || !Z || !image.state)
    throw InvalidInput("the image to share is not a framebuffer (R, G, B, A, Z and state)");
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::size_t i = first + k;
    if (!owns_row(share.part, i / W)) continue;
    PixelShare& p = out[k];
    p.key = 0;  // the owner of the row wins over every other part
    p.z = (*Z)[i];
    p.r = (*R)[i], p.g = (*G)[i], p.b = (*B)[i], p.a = (*A)[i];
    if (Nx && Ny && Nz) p.nx = (*Nx)[i], p.ny = (*Ny)[i], p.nz = (*Nz)[i];
    if (density) p.density = (*density)[i];
    p.state = (*image.state)[i];
  }
}

void unpack(Share& share, std::size_t first, std::span<const PixelShare> in) {
  Image& image = share.image;
  if (first + in.size() > image.width * image.height)
    throw InvalidInput("the shared pixels run beyond the image");
  std::vector<float>&R = detail::channel(image, "R"), &G = detail::channel(image, "G"),
  &B = detail::channel(image, "B"), &A = detail::channel(image, "A"), &Z = detail::channel(image, "Z", kInf);
  std::vector<std::uint32_t>& state = *image.state;
  if (share.kind == Share::Kind::points) {
    std::vector<float>& density = detail::channel(image, "density");
    for (std::size_t k = 0; k < in.size(); ++k) {
      const PixelShare& p = in[k];
      if (!(p.z < kInf)) continue;
      const std::size_t i = first + k;
      // As composite: the sum is formed in double and rounded once.
      density[i] = static_cast<float>(density[i] + p.density);
      R[i] = p.r, G[i] = p.g, B[i] = p.b, A[i] = p.a, Z[i] = p.z;
      state[i] = p.state;
    }
    return;
  }
  std::vector<float>*Nx = find(image, "N.x"), *Ny = find(image, "N.y"), *Nz = find(image, "N.z");
  std::vector<float>* density = find(image, "density");
  for (std::size_t k = 0; k < in.size(); ++k) {
    const PixelShare& p = in[k];
    const std::size_t i = first + k;
    R[i] = p.r, G[i] = p.g, B[i] = p.b, A[i] = p.a, Z[i] = p.z;
    if (Nx && Ny && Nz) (*Nx)[i] = p.nx, (*Ny)[i] = p.ny, (*Nz)[i] = p.nz;
    if (density) (*density)[i] = static_cast<float>(p.density);
    state[i] = p.state;
  }
}

}  // namespace cifs::render
