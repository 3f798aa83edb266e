// SPDX-License-Identifier: MIT
// cifs — counts that may exceed size_t (an automaton's 2^depth leaves, the entries of their tables):
// arithmetic that saturates at kSaturated, read as "more than fits", instead of wrapping around.
#pragma once

#include <cstddef>
#include <limits>

namespace cifs::ifs {

inline constexpr std::size_t kSaturated = std::numeric_limits<std::size_t>::max();

inline std::size_t add_sat(std::size_t a, std::size_t b) noexcept {
  return a > kSaturated - b ? kSaturated : a + b;
}
inline std::size_t mul_sat(std::size_t a, std::size_t b) noexcept {
  return (a != 0 && b > kSaturated / a) ? kSaturated : a * b;
}

}  // namespace cifs::ifs
