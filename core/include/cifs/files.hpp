// SPDX-License-Identifier: MIT
// cifs — whole-file reads and the one atomic writer every module uses (text files, EXR, PNG): the
// bytes go to a temporary file next to the target, which is renamed onto it only when complete.
// The format writers put their bytes into a ByteSink, a chunk at a time: a string (in memory) or
// an AtomicWriter (a file that is never whole in memory).
#pragma once

#include <cstdint>
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

/// Where the format writers put their bytes, in order, a piece at a time.
class ByteSink {
 public:
  ByteSink() = default;
  ByteSink(const ByteSink&) = delete;
  ByteSink& operator=(const ByteSink&) = delete;
  virtual ~ByteSink() = default;
  virtual void write(std::string_view bytes) = 0;
};

/// The bytes kept in memory (io::encode).
class StringSink final : public ByteSink {
 public:
  std::string bytes;
  void write(std::string_view more) override { bytes += more; }
};

/// Bytes appended in small pieces (a number, a line) and handed to a sink a chunk (≥ kChunkBytes) at a
/// time, so that a writer costs one virtual call per chunk and a file's bytes are never whole in memory.
/// Call `flush()` at the end: the destructor drops what is left (it may run while an error unwinds).
class ChunkBuffer {
 public:
  static constexpr std::size_t kChunkBytes = std::size_t{1} << 20;
  explicit ChunkBuffer(ByteSink& sink) : sink_(sink) {}
  /// Append here, then call `spill()`.
  std::string text;
  /// Hands the buffer on once it holds a chunk.
  void spill() {
    if (text.size() >= kChunkBytes) flush();
  }
  void flush() {
    sink_.write(text);
    handed_ += text.size();
    text.clear();
  }
  /// Bytes handed on plus those still buffered.
  std::uint64_t size() const noexcept { return handed_ + text.size(); }

 private:
  ByteSink& sink_;
  std::uint64_t handed_ = 0;
};

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

/// write_file_atomically a piece at a time, for files that are written as they are computed: the
/// constructor creates the temporary (O_EXCL), `write` appends to it, `commit` closes it and renames it
/// onto the target; a writer that is not committed closes and removes its temporary.
///
///   AtomicWriter file(path);  // IoError: empty path, directory, folder missing
///   file.write(header);       // IoError naming the path (a full disk: "No space left on device")
///   file.write(chunk); …
///   file.commit();
class AtomicWriter final : public ByteSink {
 public:
  explicit AtomicWriter(std::filesystem::path target);
  AtomicWriter(const AtomicWriter&) = delete;
  AtomicWriter& operator=(const AtomicWriter&) = delete;
  ~AtomicWriter() override;

  const std::filesystem::path& target() const noexcept { return file_.target(); }
  const std::filesystem::path& temporary() const noexcept { return file_.temporary(); }
  /// Bytes written so far.
  std::uint64_t size() const noexcept { return size_; }

  void write(std::string_view bytes) override;
  /// Closes the temporary (which reports deferred write errors) and renames it onto the target.
  void commit();

 private:
  [[noreturn]] void fail(int error);
  AtomicFile file_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// Refuses a file of `bytes` at `target`, of which `written` are on the disk already, when the file
/// system holding the target's folder has less than the rest available: IoError "out.npy: the file
/// needs 19.3 GB of disk space, 4.1 GB are free there". `about` says that `bytes` is an estimate
/// ("needs about"). Does nothing when the free space cannot be read.
void check_disk_space(const std::filesystem::path& target, std::uint64_t bytes, bool about = false,
                      std::uint64_t written = 0);

}  // namespace cifs
