// SPDX-License-Identifier: MIT
// cifs fuzzing harnesses (docs/reliability.md, "Fuzzing"): what every harness shares. A harness
// defines LLVMFuzzerTestOneInput; it links with libFuzzer in the `fuzz` preset and with replay.cpp
// (a plain main that feeds files) in every other build, where ctest replays the seeds and
// tests/fuzz/regressions/ through it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "cifs/errors.hpp"

namespace cifs::fuzz {

inline std::string_view text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
}

/// Runs `f`; the documented refusals (InvalidInput, IoError) are the expected outcome of a bad
/// input. Any other exception escapes: libFuzzer reports it as a crash, the replay driver fails.
template <class F>
void refusals_allowed(F&& f) {
  try {
    f();
  } catch (const InvalidInput&) {
  } catch (const IoError&) {
  }
}

/// A property the harness checks (a round trip): abort with `what` when it fails, which libFuzzer
/// and the replay driver both report.
inline void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz: property failed: %s\n", what);
  std::abort();
}

}  // namespace cifs::fuzz
