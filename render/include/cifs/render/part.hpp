// SPDX-License-Identifier: MIT
// cifs — part i of n of a distributed render (cifs render under mpirun; docs/scaling.md).
#pragma once

#include <cstddef>

namespace cifs::render {

/// Part `index` of `count` of a distributed render (a process of `mpirun -n count`).
struct Part {
  unsigned index = 0;
  unsigned count = 1;
};

/// Throws InvalidInput unless count ≥ 1 and index < count; `who` prefixes the message.
void check_part(const Part& part, const char* who);

/// Rasterised layers are divided by rows, in bands of kBandRows (the mesh tiles' height) dealt out
/// in turn: band b belongs to part b mod count. Every part draws the whole scene into its own bands
/// exactly as a single process would, so the bands put together are the single-process image.
inline constexpr std::size_t kBandRows = 32;

inline bool owns_row(const Part& part, std::size_t y) noexcept {
  return (y / kBandRows) % part.count == part.index;
}

}  // namespace cifs::render
