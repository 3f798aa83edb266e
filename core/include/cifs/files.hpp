// SPDX-License-Identifier: MIT
// cifs — whole-file reads and the one atomic writer every module uses (text files, EXR, PNG): the
// bytes go to a temporary file next to the target, which is renamed onto it only when complete.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace cifs {

/// Marks the temporary files of the atomic writer: `<target><marker><pid>-<thread>-<n>`. A file whose
/// name holds it is a leftover of a writer that was killed before it could clean up.
inline constexpr std::string_view kTemporaryMarker = ".cifs-tmp-";

/// The whole file as bytes. IoError naming the path when it is a directory or cannot be read.
std::string read_file(const std::filesystem::path& path);

/// Writes `bytes` to `path` so that `path` never holds a partial file: the bytes go to a temporary
/// file in the same folder (so that the rename stays on one file system), which is flushed, closed
/// and renamed onto `path`. On any failure the temporary is removed and IoError names `path`; an
/// empty path and a directory target are refused before anything is created.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

/// The same protocol for writers that need a path of their own (OpenEXR's Imf::OutputFile, libpng):
/// write to `temporary()`, then `commit()`. A file that is not committed is removed by the destructor.
///
///   AtomicFile file(path);                       // refuses an empty path or a directory
///   library_write(file.temporary().c_str(), …);  // may throw: the temporary is discarded
///   file.commit();                               // renamed onto path
class AtomicFile {
 public:
  /// Chooses a fresh temporary name next to `target` (nothing is created yet). Throws IoError for an
  /// empty path or a directory target.
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  const std::filesystem::path& target() const noexcept { return target_; }
  const std::filesystem::path& temporary() const noexcept { return temporary_; }

  /// Renames the temporary onto the target. On failure the temporary is removed and IoError names the
  /// target. Once committed, the destructor leaves the file alone.
  void commit();

 private:
  std::filesystem::path target_, temporary_;
  bool committed_ = false;
};

}  // namespace cifs
