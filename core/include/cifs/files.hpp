// SPDX-License-Identifier: MIT
// cifs — whole-file reads and the one atomic writer every module uses (text files, EXR, PNG) and
// every command goes through: the output contract of docs/reliability.md lives here.
//
// An output is written to a temporary file next to its target and renamed onto it only when
// complete; several outputs of one run are renamed together, all or none (AtomicFiles). Targets
// are checked, and their temporaries created, before any work: a folder, a device, a FIFO, a
// missing or unwritable folder and an input of the run are refused up front. Symbolic links are
// written through. SIGINT, SIGTERM and SIGHUP remove the temporaries still open; those of a
// process that died otherwise (SIGKILL) are removed by the next write into their folder. The
// format writers put their bytes into a ByteSink a chunk at a time: a string (in memory) or an
// AtomicFile (a file that is never whole in memory).
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace cifs {

/// Marks the temporary files of the atomic writer: `.<name><marker><pid>.<n>` next to `<name>`
/// (hidden, so that folder listings stay clean). A file named so whose process is gone is a
/// leftover of a writer that was killed before it could clean up.
inline constexpr std::string_view kTemporaryMarker = ".cifs-tmp.";

/// The path's extension in lower case (".STEP" → ".step"): formats are chosen by it, and files from
/// other systems often carry upper-case extensions.
std::string extension_of(const std::filesystem::path& path);

/// The whole file as bytes. IoError naming the path when it is not a regular file (a directory, a
/// device such as /dev/zero, a FIFO: refused without waiting for a writer), holds more than half the
/// physical memory (with both figures), or cannot be read. While a RunInputs lives, the file is
/// recorded as an input of the run.
std::string read_file(const std::filesystem::path& path);

/// Half the physical memory: the most an input may hold, as a file (read_file) or as what a small file
/// decodes to (an image's pixels).
std::uint64_t largest_input();

/// Refuses what `path` decodes to when it needs more than `limit` bytes, before it is allocated:
/// IoError "big.exr: the image is 100001 × 100001 pixels of 1 channel, 40 GB, more than the 16.4 GB an
/// input may hold" (`what` = "the image is 100001 × 100001 pixels of 1 channel").
void check_decoded_size(const std::filesystem::path& path, std::string_view what, std::uint64_t bytes,
                        std::uint64_t limit);

/// The inputs of one run (a command of the CLI), for its whole lifetime: every file read_file reads
/// meanwhile is recorded (device and inode), and every AtomicFile created meanwhile refuses a target
/// that is one of them — by any name, hard link or symbolic link — so that no command overwrites what
/// it read, whichever files those were. Without one (Python, the C++ API) reading a file and writing
/// it back is allowed; OutputOptions::inputs names the files to protect there.
class RunInputs {
 public:
  RunInputs();
  RunInputs(const RunInputs&) = delete;
  RunInputs& operator=(const RunInputs&) = delete;
  ~RunInputs();
};

/// What an output must not be, and what may be made for it.
struct OutputOptions {
  /// The files the run reads: an output that is one of them — by any name, hard link or symbolic
  /// link — is refused (an output never overwrites an input).
  std::vector<std::filesystem::path> inputs;
  /// Create the missing folders of the target (removed again when nothing is committed);
  /// otherwise a missing folder is refused.
  bool create_folders = false;
};

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

/// Writes `bytes` to `path` so that `path` never holds a partial file (AtomicFile: checked, written
/// to a temporary in the same folder, renamed). On any failure nothing is left and IoError names
/// `path`.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes,
                           const OutputOptions& options = {});

/// One output written through a temporary file, for writers that need a path of their own
/// (OpenEXR's Imf::OutputFile, libpng) or bytes (`write`):
///
///   AtomicFile file(path);                       // checks path, creates the temporary
///   library_write(file.temporary().c_str(), …);  // may throw: the temporary is discarded
///   file.commit();                               // renamed onto path
class AtomicFile final : public ByteSink {
 public:
  /// Checks `target` and creates its (empty) temporary, so that an output that cannot be written
  /// is refused before the work. IoError naming the target for: an empty path; a folder ("is a
  /// directory"); a device, FIFO or socket (only regular files are replaced); one of
  /// `options.inputs`; a missing folder (unless `create_folders`), a folder path through a file;
  /// a folder where no file can be created (the system's reason: permission, read-only). A
  /// symbolic link is followed: its final target is replaced and the link kept. Temporaries of
  /// dead processes in the target's folder are removed (once per folder and process).
  explicit AtomicFile(std::filesystem::path target, const OutputOptions& options = {});
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Not committed: removes the temporary and the folders made for it.
  ~AtomicFile() override;

  /// The path as given.
  const std::filesystem::path& target() const noexcept { return target_; }
  /// The file that is replaced: the target, or the final target of the symbolic link it is.
  const std::filesystem::path& destination() const noexcept { return destination_; }
  const std::filesystem::path& temporary() const noexcept { return temporary_; }
  /// A message of a library that wrote the temporary itself (OpenEXR, libpng), with the temporary's
  /// name replaced by the target's: no error names a temporary file.
  std::string about_target(std::string message) const;

  /// Appends `bytes` to the temporary. IoError naming the target (a full disk, a quota).
  void write(std::string_view bytes) override;
  /// Bytes written so far.
  std::uint64_t size() const noexcept { return size_; }

  /// Renames the temporary onto the destination (an existing file keeps its permission bits). On
  /// failure the temporary is removed and IoError names the target. SIGINT and SIGTERM wait until
  /// the rename is done. Once committed, the destructor leaves the file alone.
  void commit();

 private:
  friend class AtomicFiles;
  /// Renames each file's temporary, in order; when one fails, puts the ones before it back.
  static void commit_together(const std::vector<AtomicFile*>& files);

  std::filesystem::path target_, destination_, temporary_;
  std::vector<std::filesystem::path> made_folders_;  // deepest last
  int fd_ = -1;    // open on the temporary, locked: a live writer's temporary is never stale
  int slot_ = -1;  // in the signal handler's registry (−1: not registered)
  int mode_ = -1;  // permission bits of the file replaced (−1: a new file)
  std::uint64_t size_ = 0;
  bool committed_ = false;
};

/// Refuses a file of `bytes` at `target`, of which `written` are on the disk already, when the file
/// system holding the target's folder has less than the rest available: IoError "out.npy: the file
/// needs 19.3 GB of disk space, 4.1 GB are free there". `about` says that `bytes` is an estimate
/// ("needs about"). Does nothing when the free space cannot be read.
void check_disk_space(const std::filesystem::path& target, std::uint64_t bytes, bool about = false,
                      std::uint64_t written = 0);

/// The outputs of one run, committed together: every file is renamed into place, or — when one
/// rename fails — the files already renamed are put back as they were (a replaced file from a hard
/// link kept during the commit, a new one removed).
///
///   AtomicFiles files;
///   AtomicFile& exr = files.add(path, "outputs.exr");  // every target checked before the work
///   …
///   write_exr(exr, image);
///   files.commit();
class AtomicFiles {
 public:
  AtomicFiles() = default;
  AtomicFiles(const AtomicFiles&) = delete;
  AtomicFiles& operator=(const AtomicFiles&) = delete;
  /// Discards the temporaries not committed, the last added first (their folders with them).
  ~AtomicFiles();

  /// A new output (AtomicFile's checks). `label` names it in messages; InvalidInput when it is the
  /// file of an earlier output ("LABEL: PATH is also OTHER; give each output its own file").
  AtomicFile& add(const std::filesystem::path& target, const std::string& label,
                  const OutputOptions& options = {});

  /// Renames every temporary onto its destination, all or none. IoError naming the output whose
  /// rename failed.
  void commit();

 private:
  std::deque<AtomicFile> files_;  // a deque: references stay valid as files are added
  std::vector<std::string> labels_;
};

}  // namespace cifs
