// SPDX-License-Identifier: MIT
// cifs fuzzing harnesses (docs/reliability.md, "Fuzzing"): what every harness shares. A harness
// is declared with CIFS_FUZZ_HARNESS(NAME). In the `fuzz` preset (CIFS_LIBFUZZER) that is
// LLVMFuzzerTestOneInput and each harness links with libFuzzer on its own; in every other build all
// the harnesses link with replay.cpp into one executable, `fuzz_replay NAME …` (a plain main that
// feeds files), through which ctest replays the seeds and tests/fuzz/regressions/: one link instead
// of one per harness, each of which would pull in the whole library.
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

/// A harness's entry: the bytes of one input; returns 0 (libFuzzer's convention).
using Harness = int (*)(const std::uint8_t* data, std::size_t size);

/// Records `harness` under `name` for the replay driver (replay.cpp); true, for a static initializer.
bool register_harness(const char* name, Harness harness);

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

/// `CIFS_FUZZ_HARNESS(NAME) { … }` defines the harness NAME, a body that sees `data` and `size`.
#ifdef CIFS_LIBFUZZER
#define CIFS_FUZZ_HARNESS(NAME)                                                       \
  static int cifs_fuzz_##NAME(const std::uint8_t* data, std::size_t size);            \
  /* NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls */       \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    return cifs_fuzz_##NAME(data, size);                                              \
  }                                                                                   \
  static int cifs_fuzz_##NAME(const std::uint8_t* data, std::size_t size)
#else
#define CIFS_FUZZ_HARNESS(NAME)                                            \
  static int cifs_fuzz_##NAME(const std::uint8_t* data, std::size_t size); \
  [[maybe_unused]] static const bool cifs_fuzz_registered_##NAME =         \
      cifs::fuzz::register_harness(#NAME, cifs_fuzz_##NAME);               \
  static int cifs_fuzz_##NAME(const std::uint8_t* data, std::size_t size)
#endif
