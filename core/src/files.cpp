// SPDX-License-Identifier: MIT
// cifs — whole-file reads and atomic writes (POSIX: open with O_EXCL, write, close, rename).
#include "cifs/files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <system_error>
#include <thread>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs {
namespace {

/// Unique per process (pid), thread and call (counter): two threads, or two processes, writing the
/// same target never share a temporary.
std::filesystem::path temporary_path(const std::filesystem::path& target) {
  static std::atomic<unsigned long long> counter{0};
  const std::size_t thread = std::hash<std::thread::id>{}(std::this_thread::get_id());
  return target.string() + std::string(kTemporaryMarker) + std::to_string(::getpid()) + "-" +
         std::to_string(thread) + "-" + std::to_string(counter++);
}

void remove_quietly(const std::filesystem::path& path) noexcept {
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

}  // namespace

std::string read_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path.string() + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(path.string() + ": read error");
  return text.str();
}

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  if (target_.empty()) throw IoError("empty output path");
  std::error_code ec;
  if (std::filesystem::is_directory(target_, ec)) throw IoError(target_.string() + ": is a directory");
  temporary_ = temporary_path(target_);
}

AtomicFile::~AtomicFile() {
  if (!committed_) remove_quietly(temporary_);
}

void AtomicFile::commit() {
  std::error_code ec;
  std::filesystem::rename(temporary_, target_, ec);
  if (ec) {
    remove_quietly(temporary_);
    throw IoError(target_.string() + ": cannot rename the temporary file into place (" + ec.message() + ")");
  }
  committed_ = true;
}

AtomicWriter::AtomicWriter(std::filesystem::path target) : file_(std::move(target)) {
  // O_EXCL: never write through a file that is already there (a stale temporary, a link).
  fd_ = ::open(file_.temporary().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd_ < 0) fail(errno);
}

AtomicWriter::~AtomicWriter() {
  if (fd_ >= 0) ::close(fd_);  // then file_ removes the temporary unless committed
}

void AtomicWriter::fail(int error) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  throw IoError(target().string() + ": cannot write (" + std::strerror(error) + ")");
}

void AtomicWriter::write(std::string_view bytes) {
  if (fd_ < 0) throw IoError(target().string() + ": written after it was closed");
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ::ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(errno);
    done += static_cast<std::size_t>(n);
  }
  size_ += bytes.size();
}

void AtomicWriter::commit() {
  if (fd_ < 0) throw IoError(target().string() + ": committed after it was closed");
  // close reports the errors that a file system defers (NFS, full disks).
  const int status = ::close(fd_);
  fd_ = -1;
  if (status != 0) fail(errno);
  file_.commit();
}

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
  AtomicWriter file(path);
  file.write(bytes);
  file.commit();
}

namespace {

/// "19.3", "0.00412", "79200": gigabytes with 3 significant digits, no exponent.
std::string gigabytes(std::uint64_t bytes) {
  const double x = static_cast<double>(bytes) / 1e9;
  return x < 100 ? number_text(x, 3) : fixed_text(x, 0);
}

}  // namespace

void check_disk_space(const std::filesystem::path& target, std::uint64_t bytes, bool about,
                      std::uint64_t written) {
  const std::filesystem::path folder = target.has_parent_path() ? target.parent_path() : ".";
  std::error_code ec;
  const std::filesystem::space_info space = std::filesystem::space(folder, ec);
  if (ec || space.available == static_cast<std::uintmax_t>(-1) || bytes <= written + space.available) return;
  throw IoError(target.string() + ": the file needs " + (about ? "about " : "") + gigabytes(bytes) +
                " GB of disk space, " + gigabytes(written + space.available) + " GB are free there");
}

}  // namespace cifs
