// SPDX-License-Identifier: MIT
// cifs — the one seeded random generator: xoshiro256** (Blackman & Vigna 2018) with its state
// filled by SplitMix64. Integer arithmetic only, so a seed gives the same stream on every platform
// and standard library (std::mt19937 distributions are implementation-defined).
#pragma once

#include <array>
#include <bit>
#include <cstdint>

namespace cifs {

/// SplitMix64's step (Steele, Lea, Flood 2014): advances `state` and returns a well-mixed word.
inline std::uint64_t splitmix64(std::uint64_t& state) noexcept {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// xoshiro256**: 256-bit state, period 2²⁵⁶ − 1, every output bit of good quality.
///
/// Streams: `Random(seed, stream)` starts SplitMix64 at `seed ^ mix(stream)`, where mix is
/// SplitMix64's bijective finaliser (mix(0) = 0, so stream 0 is `Random(seed)`). Parallel work
/// gives each chunk its own stream, so its numbers do not depend on the thread that runs it.
class Random {
 public:
  explicit Random(std::uint64_t seed, std::uint64_t stream = 0) noexcept {
    std::uint64_t state = seed ^ mix(stream);
    for (auto& word : s_) word = splitmix64(state);
  }

  /// The generator in a given state (not all zero): to resume a stream, or to check it against
  /// the reference implementation.
  explicit Random(const std::array<std::uint64_t, 4>& state) noexcept
      : s_{state[0], state[1], state[2], state[3]} {}

  std::uint64_t operator()() noexcept {
    const std::uint64_t result = std::rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = std::rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, 1): 53 random bits.
  double uniform() noexcept { return static_cast<double>((*this)() >> 11) * 0x1.0p-53; }
  /// Uniform in [−1, 1): 53 random bits.
  double symmetric() noexcept { return static_cast<double>((*this)() >> 11) * 0x1.0p-52 - 1.0; }

 private:
  static constexpr std::uint64_t mix(std::uint64_t z) noexcept {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  std::uint64_t s_[4];
};

/// An index in [0, bound) from 32 random bits (Lemire's multiply-shift; bias ≤ bound/2³²).
inline std::uint32_t bounded(std::uint32_t bits, std::uint32_t bound) noexcept {
  return static_cast<std::uint32_t>((std::uint64_t{bits} * bound) >> 32);
}

}  // namespace cifs
