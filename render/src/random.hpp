// SPDX-License-Identifier: MIT
// cifs — the random streams of the chaos games: one xoshiro256++ generator per chunk, seeded from
// (seed, chunk) by SplitMix64, so that a chunk's points do not depend on the thread that runs it.
#pragma once

#include <bit>
#include <cstdint>

namespace cifs::render::detail {

// SplitMix64 (Steele, Lea, Flood 2014): turns (seed, chunk) into well-spread generator states.
inline std::uint64_t splitmix64(std::uint64_t& state) noexcept {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// xoshiro256++ (Blackman & Vigna 2018): fast, 256-bit state, all output bits of good quality (both
// halves of every draw are used).
class Xoshiro256 {
 public:
  Xoshiro256(std::uint64_t seed, std::uint64_t stream) noexcept {
    std::uint64_t sm = seed;
    // An odd multiplier is a bijection modulo 2⁶⁴: distinct chunks get distinct SplitMix streams.
    sm = splitmix64(sm) + stream * 0xD1B54A32D192ED03ULL;
    for (auto& word : s_) word = splitmix64(sm);
  }
  std::uint64_t operator()() noexcept {
    const std::uint64_t result = std::rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = std::rotl(s_[3], 45);
    return result;
  }

 private:
  std::uint64_t s_[4];
};

/// An index in [0, bound) from 32 random bits (Lemire's multiply-shift; bias ≤ bound/2³²).
inline std::uint32_t bounded(std::uint32_t bits, std::uint32_t bound) noexcept {
  return static_cast<std::uint32_t>((std::uint64_t{bits} * bound) >> 32);
}

}  // namespace cifs::render::detail
