// SPDX-License-Identifier: MIT
// cifs — NumPy .npy files (format version 1.0) of point sets: little-endian doubles ('<f8') in C
// order, shape (count, dim). The header is padded as numpy.save (1.24) pads it: room for a 21-digit
// count, then spaces and a newline so that the data starts at a multiple of 64 bytes; numpy.save of
// the loaded array writes the same bytes.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#include "points_format.hpp"

namespace cifs::io::detail {
namespace npy {

constexpr std::size_t kAlign = 64;
constexpr std::size_t kCountDigits = 21;  // numpy's GROWTH_AXIS_MAX_DIGITS
constexpr std::string_view kMagic{"\x93NUMPY\x01\x00", 8};

/// The header dictionary, padded with spaces and ended by a newline.
std::string dictionary(std::uint64_t count, Eigen::Index dim) {
  const std::string n = std::to_string(count);
  std::string d =
      "{'descr': '<f8', 'fortran_order': False, 'shape': (" + n + ", " + std::to_string(dim) + "), }";
  d.append(kCountDigits - std::min(n.size(), kCountDigits), ' ');
  const std::size_t unpadded = kMagic.size() + 2 + d.size() + 1;
  d.append(kAlign - unpadded % kAlign, ' ');  // as numpy: a whole 64 when already aligned
  d += '\n';
  return d;
}

void header(std::string& out, std::uint64_t count, Eigen::Index dim, const PointsStyle&) {
  const std::string d = dictionary(count, dim);
  out += kMagic;
  out += static_cast<char>(d.size() & 0xFF);  // uint16 little-endian length
  out += static_cast<char>(d.size() >> 8);
  out += d;
}

void rows(std::string& out, const Eigen::Ref<const Points>& rows, std::uint64_t) {
  const auto cols = static_cast<std::size_t>(rows.cols());
  for (Eigen::Index r = 0; r < rows.rows(); ++r) {
    const double* row = rows.row(r).data();
    if constexpr (std::endian::native == std::endian::little) {
      out.append(reinterpret_cast<const char*>(row), cols * sizeof(double));
    } else {
      for (std::size_t k = 0; k < cols; ++k) {
        const auto bits = std::bit_cast<std::uint64_t>(row[k]);
        for (int b = 0; b < 8; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xFF);
      }
    }
  }
}

void footer(ChunkBuffer&, std::uint64_t, const PointsStyle&) {}

std::uint64_t size(std::uint64_t count, Eigen::Index dim) {
  return kMagic.size() + 2 + dictionary(count, dim).size() + count * static_cast<std::uint64_t>(dim) * 8;
}

}  // namespace npy

const PointsFormat kNpyPoints{"npy", 0, npy::header, npy::rows, npy::footer, npy::size};

}  // namespace cifs::io::detail
