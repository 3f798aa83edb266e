// SPDX-License-Identifier: MIT
// cifs — a render divided among processes (cifs render under mpirun): which part of the work a
// process does, and the framebuffer shares that a reduction combines. Free of MPI: the transport
// (apps/, an MPI_Reduce with combine_shares as its operation) lives outside the library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "cifs/render/image.hpp"
#include "cifs/render/part.hpp"
#include "cifs/render/raster.hpp"

namespace cifs::render {

/// The hits of one layer of points (a chaos game) before they are composited: per pixel the added
/// density, the nearest point's depth (+∞ where none), its sample index (the later of equally near
/// points wins) and state.
struct DensityLayer {
  std::vector<double> density;
  std::vector<float> depth;
  std::vector<std::uint64_t> sample;
  std::vector<std::uint32_t> state;
};

/// An empty layer of `pixels` pixels.
DensityLayer empty_density_layer(std::size_t pixels);

/// Composites a layer over `image`: where it has hits, density += hits (created when missing),
/// A = 1, R G B = color, Z and state of its nearest point.
void composite(Image& image, const DensityLayer& layer, const Rgb& color);

/// One pixel of a process's share, as the reduction sees it: density is summed; the smallest
/// (z, key) wins and brings its colour, coverage, normal and state along. 56 bytes, no pointers:
/// sent as bytes.
struct PixelShare {
  double density = 0;
  std::uint64_t key = std::numeric_limits<std::uint64_t>::max();
  float z = std::numeric_limits<float>::infinity();
  float r = 0, g = 0, b = 0, a = 0;
  float nx = 0, ny = 0, nz = 0;
  std::uint32_t state = kNoState;
  std::uint32_t unused = 0;
};

/// inout[i] ← in[i] ⊕ inout[i]. Commutative and associative, exactly: densities are integer counts
/// (or one non-zero term per pixel) below 2^53, and (z, key) is a total order in which different
/// processes never tie with different payloads. So any reduction tree gives the same bytes.
void combine_shares(std::span<const PixelShare> in, std::span<PixelShare> inout) noexcept;

/// A process's share of a distributed render.
struct Share {
  enum class Kind {
    /// The image is complete in this part's bands (owns_row); other rows are ignored.
    bands,
    /// `image` holds the layers under the points (identical in every part) and `points` this part's
    /// hits; the combined hits are composited over it.
    points,
  };
  Kind kind = Kind::bands;
  Part part;
  Image image;
  DensityLayer points;
  Rgb color{1, 1, 1};
};

/// The shares of pixels [first, first + out.size()) (row-major), for the reduction; a reduction may
/// go tile by tile so that its buffers stay small.
void pack(const Share& share, std::size_t first, std::span<PixelShare> out);

/// Writes the combined shares of pixels [first, first + in.size()) into `share.image`: bands are
/// copied, points composited (composite). Once every tile is unpacked the image is the one a single
/// process renders.
void unpack(Share& share, std::size_t first, std::span<const PixelShare> in);

}  // namespace cifs::render
