// SPDX-License-Identifier: MIT
// The sanitized build (CMakePresets.json `sanitize`) runs the numerics 10–30 times slower. A test that
// repeats one computation over many cases takes a sample of them there: the memory errors ASan looks
// for come with the code path, which the sample runs; the Release run checks every case's figures.
#pragma once

#include <cstddef>

namespace cifs_test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

/// Whether a sanitized run skips case `index`: it keeps the first and every `every`-th after it.
constexpr bool skipped_when_sanitized(std::size_t index, std::size_t every = 3) {
  return kSanitized && index % every != 0;
}

}  // namespace cifs_test
