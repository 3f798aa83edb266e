// SPDX-License-Identifier: MIT
// cifs — part i of n of a distributed render (cifs render under mpirun; docs/scaling.md).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace cifs::render {

/// Part `index` of `count` of a distributed render (a process of `mpirun -n count`).
struct Part {
  unsigned index = 0;
  unsigned count = 1;
};

/// Throws InvalidInput unless count ≥ 1 and index < count.
void check_part(const Part& part);

/// Rasterised layers are divided by rows, in bands of kBandRows (the mesh tiles' height) dealt out
/// in turn: band b belongs to part b mod count. Every part draws the whole scene into its own bands
/// exactly as a single process would, so the bands put together are the single-process image.
inline constexpr std::size_t kBandRows = 32;

inline bool owns_row(const Part& part, std::size_t y) noexcept {
  return (y / kBandRows) % part.count == part.index;
}

/// A chaos game's samples in chunks of `chunk`, dealt out in turn: chunk c belongs to part
/// c mod count. This part's number of chunks and of samples.
struct PartChunks {
  std::uint64_t all = 0, mine = 0, samples = 0;
};

inline PartChunks part_chunks(const Part& part, std::uint64_t samples, std::uint64_t chunk) noexcept {
  PartChunks out;
  out.all = (samples + chunk - 1) / chunk;
  out.mine = out.all > part.index ? (out.all - part.index + part.count - 1) / part.count : 0;
  for (std::uint64_t c = part.index; c < out.all; c += part.count)
    out.samples += std::min(chunk, samples - c * chunk);
  return out;
}

}  // namespace cifs::render
