// SPDX-License-Identifier: MIT
// cifs fuzzing harnesses (docs/reliability.md, "Fuzzing"): what every harness shares. A harness
// defines LLVMFuzzerTestOneInput; it links with libFuzzer in the `fuzz` preset and with replay.cpp
// (a plain main that feeds files) in every other build, where ctest replays the seeds and
// tests/fuzz/regressions/ through it.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

#include "cifs/errors.hpp"

namespace cifs::fuzz {

/// This process's folder for a harness that writes files (`cifs_fuzz_HARNESS.PID`, made on the first
/// call; libFuzzer leaves by exit, so it stays: inputs that crashed can be replayed against it).
inline const std::filesystem::path& scratch(const char* harness) {
  static const std::filesystem::path folder = [harness] {
    auto path = std::filesystem::temp_directory_path() /
                ("cifs_fuzz_" + std::string(harness) + "." + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return folder;
}

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

/// Runs `f`, which must not refuse: the second half of a round trip (what was read is written, what
/// was written is read). A refusal there fails the property `what`, with the refusal's message.
template <class F>
auto no_refusal(F&& f, const char* what) {
  const auto refused = [&](const std::exception& e) {
    std::fprintf(stderr, "fuzz: refused: %s\n", e.what());
    require(false, what);
  };
  try {
    return f();
  } catch (const InvalidInput& e) {
    refused(e);
    throw;
  } catch (const IoError& e) {
    refused(e);
    throw;
  }
}

}  // namespace cifs::fuzz
