// SPDX-License-Identifier: MIT
// cifs — whole-file reads and atomic writes (POSIX: a temporary created with O_EXCL and locked,
// written, renamed), the targets' checks, and the signal handler that removes temporaries.
#include "cifs/files.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <system_error>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs {
namespace {

namespace fs = std::filesystem;

// ---- The temporaries a signal handler removes -------------------------------------------------
//
// A fixed table, so that the handler only reads memory and calls unlink (async-signal-safe). Each
// slot is a sequence lock: `version` is odd while its path changes, and the handler unlinks a copy
// of the path only when the version was even and unchanged around the copy. A temporary that finds
// no slot (more than kSlots open at once, or a path longer than kPathBytes) is not removed on a
// signal; the next write into its folder removes it as stale.

constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;

struct Slot {
  std::atomic<bool> taken{false};
  std::atomic<unsigned> version{0};
  std::atomic<bool> live{false};
  std::array<char, kPathBytes> path{};
};

std::array<Slot, kSlots> slots;
// Renames in progress: a signal then only records itself and is raised again when they are done,
// so that the outputs of one run are all renamed or none is.
std::atomic<int> committing{0};
std::atomic<int> pending_signal{0};

void remove_registered() noexcept {
  std::array<char, kPathBytes> copy{};
  for (Slot& slot : slots) {
    const unsigned before = slot.version.load(std::memory_order_acquire);
    if (before % 2 != 0 || !slot.live.load(std::memory_order_acquire)) continue;
    std::memcpy(copy.data(), slot.path.data(), kPathBytes);
    if (slot.version.load(std::memory_order_acquire) != before) continue;
    copy.back() = '\0';
    ::unlink(copy.data());
  }
}

void raise_again(int signal) noexcept {
  remove_registered();
  ::signal(signal, SIG_DFL);
  ::raise(signal);  // delivered with the default action (the process ends) once the handler returns
}

extern "C" void on_signal(int signal) {
  if (committing.load() > 0) {
    pending_signal.store(signal);
    return;
  }
  const int saved = errno;
  raise_again(signal);
  errno = saved;
}

/// Installed with every output, only over the default action: a program that ignores a signal or
/// handles it itself (Python's SIGINT → KeyboardInterrupt) keeps its choice. Checked each time
/// (three system calls), so that a signal whose action became the default later is handled too.
void install_handlers() {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(signal, nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) != 0 ||
        old.sa_handler != SIG_DFL)
      continue;
    struct sigaction act {};
    act.sa_handler = on_signal;
    sigemptyset(&act.sa_mask);
    act.sa_flags = SA_RESTART;
    ::sigaction(signal, &act, nullptr);
  }
}

int register_path(const fs::path& path) noexcept {
  std::error_code ec;
  const std::string absolute = fs::absolute(path, ec).string();
  if (ec || absolute.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    Slot& slot = slots[static_cast<std::size_t>(i)];
    bool expected = false;
    if (!slot.taken.compare_exchange_strong(expected, true)) continue;
    slot.version.fetch_add(1, std::memory_order_acq_rel);
    std::memcpy(slot.path.data(), absolute.c_str(), absolute.size() + 1);
    slot.live.store(true, std::memory_order_release);
    slot.version.fetch_add(1, std::memory_order_acq_rel);
    return i;
  }
  return -1;
}

void unregister_path(int& i) noexcept {
  if (i < 0) return;
  Slot& slot = slots[static_cast<std::size_t>(i)];
  slot.version.fetch_add(1, std::memory_order_acq_rel);
  slot.live.store(false, std::memory_order_release);
  slot.version.fetch_add(1, std::memory_order_acq_rel);
  slot.taken.store(false, std::memory_order_release);
  i = -1;
}

/// While alive, SIGINT, SIGTERM and SIGHUP wait; the last one to end raises a signal that came.
struct SignalsWait {
  SignalsWait() { committing.fetch_add(1); }
  SignalsWait(const SignalsWait&) = delete;
  SignalsWait& operator=(const SignalsWait&) = delete;
  ~SignalsWait() {
    if (committing.fetch_sub(1) != 1) return;
    if (const int signal = pending_signal.exchange(0); signal != 0) raise_again(signal);
  }
};

// ---- Names ---------------------------------------------------------------------------------------

/// `.NAME.cifs-tmp.PID.N` next to `file`: unique per process (pid) and call (a counter shared by
/// every thread), and recognisable by a later run as the leftover of PID.
fs::path temporary_name(const fs::path& file) {
  static std::atomic<unsigned long long> counter{0};
  return file.parent_path() / ("." + file.filename().string() + std::string(kTemporaryMarker) +
                               std::to_string(::getpid()) + "." + std::to_string(counter++));
}

/// The pid of a temporary's name, or 0 when the name is not one.
pid_t temporary_pid(const std::string& name) {
  const std::size_t marker = name.rfind(kTemporaryMarker);
  if (name.size() < 2 || name[0] != '.' || marker == std::string::npos || marker < 2) return 0;
  const std::string rest = name.substr(marker + kTemporaryMarker.size());  // PID.N
  const std::size_t dot = rest.find('.');
  const auto digits = [](std::string_view s) {
    return !s.empty() && s.size() < 19 && s.find_first_not_of("0123456789") == std::string_view::npos;
  };
  if (dot == std::string::npos || !digits(rest.substr(0, dot)) || !digits(rest.substr(dot + 1))) return 0;
  const long long pid = std::stoll(rest.substr(0, dot));
  return pid > 0 && pid <= INT32_MAX ? static_cast<pid_t>(pid) : 0;
}

/// Removes the temporaries in `folder` whose process is gone (kill(pid, 0) says ESRCH) and that
/// nobody holds locked (a writer in another pid namespace), once per folder and process.
void remove_stale_temporaries(const fs::path& folder) {
  static std::mutex mutex;
  static std::set<std::string> swept;
  std::error_code ec;
  const fs::path where = folder.empty() ? fs::path(".") : folder;
  {
    const std::lock_guard lock(mutex);
    if (!swept.insert(fs::weakly_canonical(where, ec).string()).second) return;
  }
  for (fs::directory_iterator it(where, ec), end; !ec && it != end; it.increment(ec)) {
    const pid_t pid = temporary_pid(it->path().filename().string());
    if (pid == 0 || pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    const int fd = ::open(it->path().c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    struct stat st {};
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && ::flock(fd, LOCK_EX | LOCK_NB) == 0)
      ::unlink(it->path().c_str());
    ::close(fd);
  }
}

// ---- Targets ---------------------------------------------------------------------------------------

/// The file a write to `target` replaces: `target`, or the final target of the symbolic link it is
/// (a relative link resolved against the link's folder). A dangling link gives the file it names.
fs::path follow_links(const fs::path& target) {
  fs::path p = target;
  for (int hop = 0; hop < 40; ++hop) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) throw IoError(target.string() + ": cannot read the symbolic link (" + ec.message() + ")");
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  throw IoError(target.string() + ": too many levels of symbolic links");
}

std::string kind_of(fs::file_type type) {
  switch (type) {
    case fs::file_type::character:
    case fs::file_type::block:
      return "a device";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec)) return true;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
  return !ec && ca == cb;
}

bool exists_at(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::status(p.empty() ? fs::path(".") : p, ec));
}

// ---- Inputs --------------------------------------------------------------------------------------

/// The files read while a RunInputs lives (device and inode, and the path as read for messages).
struct ReadInput {
  dev_t device;
  ino_t inode;
  fs::path path;
};
std::mutex inputs_mutex;
int recording = 0;  // RunInputs alive
std::vector<ReadInput> read_inputs;

void record_input(const struct stat& st, const fs::path& path) {
  const std::lock_guard lock(inputs_mutex);
  if (recording == 0) return;
  for (const ReadInput& r : read_inputs)
    if (r.device == st.st_dev && r.inode == st.st_ino) return;
  read_inputs.push_back({st.st_dev, st.st_ino, path});
}

/// The recorded input that `st` is, if any.
std::optional<fs::path> recorded_input(const struct stat& st) {
  const std::lock_guard lock(inputs_mutex);
  for (const ReadInput& r : read_inputs)
    if (r.device == st.st_dev && r.inode == st.st_ino) return r.path;
  return std::nullopt;
}

/// "19.3", "0.00412", "79200": gigabytes with 3 significant digits, no exponent.
std::string gigabytes(std::uint64_t bytes) {
  const double x = static_cast<double>(bytes) / 1e9;
  return x < 100 ? number_text(x, 3) : fixed_text(x, 0);
}

}  // namespace

// A file above half the memory could not be held with what its parser makes of it.
std::uint64_t largest_input() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::uint64_t{1} << 34;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) / 2;
}

void check_decoded_size(const fs::path& path, std::string_view what, std::uint64_t bytes,
                        std::uint64_t limit) {
  if (bytes > limit)
    throw IoError(path.string() + ": " + std::string(what) + ", " + gigabytes(bytes) + " GB, more than the " +
                  gigabytes(limit) + " GB an input may hold");
}

std::string extension_of(const fs::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

std::string read_file(const fs::path& path) {
  const std::string name = path.string();
  if (path.empty()) throw IoError("empty input path");
  // O_NONBLOCK: opening a FIFO waits for a writer, possibly forever; it is refused below instead.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw IoError(name + ": cannot open (" + std::strerror(errno) + ")");
  const std::unique_ptr<const int, void (*)(const int*)> closer(&fd, [](const int* f) { ::close(*f); });
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw IoError(name + ": cannot read (" + std::strerror(errno) + ")");
  // A device or a FIFO has no end (/dev/zero, /dev/urandom) or none yet: only regular files are read.
  if (S_ISDIR(st.st_mode)) throw IoError(name + ": is a directory");
  std::error_code ec;
  if (!S_ISREG(st.st_mode))
    throw IoError(name + ": is " + kind_of(fs::status(path, ec).type()) + "; only regular files are read");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (const std::uint64_t limit = largest_input(); size > limit)
    throw IoError(name + ": the file holds " + gigabytes(size) + " GB, more than the " + gigabytes(limit) +
                  " GB (half the memory) an input may hold");
  record_input(st, path);
  std::string text;
  text.reserve(static_cast<std::size_t>(size));
  std::array<char, 1 << 16> chunk{};
  for (;;) {
    const ssize_t n = ::read(fd, chunk.data(), chunk.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError(name + ": read error (" + std::strerror(errno) + ")");
    if (n == 0) break;
    text.append(chunk.data(), static_cast<std::size_t>(n));
    // A file that grows while it is read (a log being written) is held to the same limit.
    if (text.size() > size + largest_input() / 2)
      throw IoError(name + ": the file grows while it is read; read a file that is complete");
  }
  return text;
}

RunInputs::RunInputs() {
  const std::lock_guard lock(inputs_mutex);
  ++recording;
}

RunInputs::~RunInputs() {
  const std::lock_guard lock(inputs_mutex);
  if (--recording == 0) read_inputs.clear();
}

AtomicFile::AtomicFile(fs::path target, const OutputOptions& options) : target_(std::move(target)) {
  if (target_.empty()) throw IoError("empty output path");
  const std::string name = target_.string();
  destination_ = follow_links(target_);
  std::error_code ec;
  const fs::file_status status = fs::status(destination_, ec);
  if (fs::is_directory(status)) throw IoError(name + ": is a directory");
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw IoError(name + ": is " + kind_of(status.type()) + "; only regular files are written");
  if (fs::exists(status)) {
    for (const fs::path& input : options.inputs)
      if (fs::equivalent(destination_, input, ec))
        throw IoError(name + ": is the input " + input.string() + "; choose another output file");
    struct stat st {};
    if (::stat(destination_.c_str(), &st) == 0)
      if (const std::optional<fs::path> input = recorded_input(st))
        throw IoError(name + ": is the input " + input->string() + "; choose another output file");
    mode_ = static_cast<int>(status.permissions() & fs::perms::mask);
  }

  // The folder: the nearest one that exists must be a folder; missing ones are made or refused.
  const fs::path folder = destination_.parent_path();
  std::vector<fs::path> missing;
  fs::path up = folder;
  while (!up.empty() && !exists_at(up) && up != up.root_path()) {
    missing.push_back(up);
    up = up.parent_path();
  }
  if (!fs::is_directory(fs::status(up.empty() ? fs::path(".") : up, ec)))
    throw IoError(name + ": " + up.string() + " is not a folder");
  if (!missing.empty() && !options.create_folders)
    throw IoError(name + ": the folder " + folder.string() + " does not exist; create it first");
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (!fs::create_directory(*it, ec) && ec)
      throw IoError(name + ": cannot create the folder " + it->string() + " (" + ec.message() + ")");
    made_folders_.push_back(*it);
  }

  try {
    remove_stale_temporaries(folder);
    install_handlers();
    // O_EXCL: never write through a file that is already there (a stale temporary, a link).
    for (int attempt = 0; fd_ < 0; ++attempt) {
      temporary_ = temporary_name(destination_);
      fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ < 0 && (errno != EEXIST || attempt == 8))
        throw IoError(name + ": cannot create a file in " + (folder.empty() ? "." : folder.string()) + " (" +
                      std::strerror(errno) + ")");
    }
    slot_ = register_path(temporary_);
    // Held until the rename: a locked temporary belongs to a live writer, whatever its pid says.
    ::flock(fd_, LOCK_EX | LOCK_NB);
  } catch (...) {
    for (auto it = made_folders_.rbegin(); it != made_folders_.rend(); ++it) ::rmdir(it->c_str());
    throw;
  }
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    unregister_path(slot_);
    ::unlink(temporary_.c_str());
    // Only folders left empty go (rmdir refuses the others), the deepest first.
    for (auto it = made_folders_.rbegin(); it != made_folders_.rend(); ++it) ::rmdir(it->c_str());
  }
}

std::string AtomicFile::about_target(std::string message) const {
  for (const std::string& name : {temporary_.string(), temporary_.filename().string()})
    for (auto at = message.find(name); !name.empty() && at != std::string::npos; at = message.find(name, at))
      message.replace(at, name.size(), target_.string());
  return message;
}

void AtomicFile::write(std::string_view bytes) {
  if (committed_ || fd_ < 0) throw IoError(target_.string() + ": written after it was closed");
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ::ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError(target_.string() + ": cannot write (" + std::strerror(errno) + ")");
    done += static_cast<std::size_t>(n);
  }
  size_ += bytes.size();
}

void AtomicFile::commit_together(const std::vector<AtomicFile*>& files) {
  struct Step {
    AtomicFile* file;
    bool existed = false;
    std::string backup;  // a hard link to the file replaced, to put it back
    int slot = -1;
  };
  const SignalsWait wait;
  std::vector<Step> steps;
  for (AtomicFile* f : files) {
    Step step{.file = f, .existed = false, .backup = {}, .slot = -1};
    if (f->fd_ >= 0) {
      if (f->mode_ >= 0) ::fchmod(f->fd_, static_cast<mode_t>(f->mode_));
      // close reports the errors that a file system defers (NFS, full disks).
      const int closed = ::close(f->fd_);
      f->fd_ = -1;
      if (closed != 0) throw IoError(f->target_.string() + ": cannot write (" + std::strerror(errno) + ")");
    }
    struct stat st {};
    step.existed = ::lstat(f->destination_.c_str(), &st) == 0;
    if (step.existed && S_ISREG(st.st_mode) && files.size() > 1) {
      const std::string backup = temporary_name(f->destination_).string();
      if (::link(f->destination_.c_str(), backup.c_str()) == 0) {
        step.backup = backup;
        step.slot = register_path(backup);
      }
    }
    steps.push_back(std::move(step));
  }
  const auto drop_backups = [&] {
    for (Step& s : steps) {
      if (s.backup.empty()) continue;
      unregister_path(s.slot);
      ::unlink(s.backup.c_str());
    }
  };
  for (std::size_t i = 0; i < steps.size(); ++i) {
    AtomicFile& f = *steps[i].file;
    if (::rename(f.temporary_.c_str(), f.destination_.c_str()) == 0) continue;
    const int error = errno;
    for (std::size_t j = 0; j < i; ++j) {  // put back what was renamed
      Step& s = steps[j];
      if (!s.backup.empty() && ::rename(s.backup.c_str(), s.file->destination_.c_str()) == 0) {
        unregister_path(s.slot);
        s.backup.clear();
      } else if (!s.existed) {
        ::unlink(s.file->destination_.c_str());
      }
    }
    drop_backups();
    throw IoError(f.target_.string() + ": cannot rename the temporary file into place (" +
                  std::strerror(error) + ")");
  }
  drop_backups();
  for (Step& s : steps) {
    unregister_path(s.file->slot_);
    s.file->committed_ = true;
  }
}

void AtomicFile::commit() {
  if (committed_) return;
  commit_together({this});
}

AtomicFiles::~AtomicFiles() {
  while (!files_.empty()) files_.pop_back();
}

AtomicFile& AtomicFiles::add(const fs::path& target, const std::string& label, const OutputOptions& options) {
  AtomicFile& file = files_.emplace_back(target, options);
  for (std::size_t i = 0; i + 1 < files_.size(); ++i)
    if (same_file(files_[i].destination(), file.destination())) {
      std::string message = label + ": " + target.string();
      message += " is also " + labels_[i] + "; give each output its own file";
      files_.pop_back();
      throw InvalidInput(message);
    }
  labels_.push_back(label);
  return file;
}

void AtomicFiles::commit() {
  std::vector<AtomicFile*> open;
  for (AtomicFile& f : files_)
    if (!f.committed_) open.push_back(&f);
  AtomicFile::commit_together(open);
}

void write_file_atomically(const fs::path& path, std::string_view bytes, const OutputOptions& options) {
  AtomicFile file(path, options);
  file.write(bytes);
  file.commit();
}

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
