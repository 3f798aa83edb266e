// SPDX-License-Identifier: MIT
// cifs::render internals: write to a temporary file in the target's folder, then rename it.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <system_error>

#include "cifs/errors.hpp"

namespace cifs::render::detail {

/// Same folder as `path` so that the rename is atomic (same filesystem); pid and a counter keep
/// concurrent writers (processes or threads) apart.
inline std::filesystem::path temporary_path(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  return path.string() + ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

/// Refuses a directory target before any temporary file is made.
inline void check_target(const std::filesystem::path& path) {
  std::error_code ec;
  if (path.empty()) throw IoError("empty output path");
  if (std::filesystem::is_directory(path, ec)) throw IoError(path.string() + ": is a directory");
}

/// Renames `tmp` onto `path`; on failure removes `tmp` and throws IoError naming `path`.
inline void commit(const std::filesystem::path& tmp, const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw IoError(path.string() + ": cannot rename the temporary file into place (" + ec.message() + ")");
  }
}

/// Removes a temporary file after a failed write (best effort).
inline void discard(const std::filesystem::path& tmp) noexcept {
  std::error_code ignored;
  std::filesystem::remove(tmp, ignored);
}

}  // namespace cifs::render::detail
