// SPDX-License-Identifier: MIT
// The atomic writer: checks of the target before the work, temporaries, symbolic links, inputs,
// outputs committed together, stale temporaries and signals (docs/reliability.md, issue 16
// defects 4–6). Expectations come from the file system itself (stat, readlink), not from the writer.
#include "cifs/files.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cifs/errors.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
namespace fs = std::filesystem;

namespace {

/// Every byte value, twice, and a NUL in the middle: text functions would stop or translate.
std::string all_bytes() {
  std::string s;
  for (int k = 0; k < 512; ++k) s += static_cast<char>(k % 256);
  return s;
}

void put(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

/// The pid of a process that has ended (forked, exited, reaped).
pid_t dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

std::string temporary_for(const std::string& name, pid_t pid, int n) {
  return "." + name + std::string(kTemporaryMarker) + std::to_string(pid) + "." + std::to_string(n);
}

}  // namespace

TEST_CASE("write_file_atomically writes the bytes and leaves no temporary", "[core][files]") {
  cifs_test::ScratchDir s("files");
  const auto path = s.path() / "a.bin";
  write_file_atomically(path, all_bytes());
  CHECK(read_file(path) == all_bytes());
  write_file_atomically(path, "shorter");  // replaces the whole file
  CHECK(read_file(path) == "shorter");
  write_file_atomically(s.path() / "empty", "");
  CHECK(read_file(s.path() / "empty").empty());
  CHECK(s.names() == std::set<std::string>{"a.bin", "empty"});
}

TEST_CASE("write_file_atomically refuses bad targets before creating anything", "[core][files]") {
  cifs_test::ScratchDir s("files");
  CHECK_THROWS_WITH(write_file_atomically("", "x"), "empty output path");
  CHECK_THROWS_WITH(write_file_atomically(s.path(), "x"), s.path().string() + ": is a directory");
  const auto missing = s.path() / "missing" / "b.txt";
  CHECK_THROWS_WITH(write_file_atomically(missing, "x"), missing.string() + ": the folder " +
                                                             (s.path() / "missing").string() +
                                                             " does not exist; create it first");
  // A folder path through a regular file (ENOTDIR deeper down).
  put(s.path() / "plain", "p");
  CHECK_THROWS_WITH(
      write_file_atomically(s.path() / "plain" / "sub" / "x.svg", "x"),
      (s.path() / "plain/sub/x.svg").string() + ": " + (s.path() / "plain").string() + " is not a folder");
  // A FIFO is not replaced by a regular file (nor written into: that would block).
  REQUIRE(::mkfifo((s.path() / "fifo").c_str(), 0600) == 0);
  CHECK_THROWS_WITH(write_file_atomically(s.path() / "fifo", "x"),
                    (s.path() / "fifo").string() + ": is a FIFO; only regular files are written");
  CHECK(fs::is_fifo(s.path() / "fifo"));
  CHECK(s.names() == std::set<std::string>{"fifo", "plain"});
}

TEST_CASE("An unwritable folder is refused when the output is opened, before any work", "[core][files]") {
  // Root writes anywhere in its own folders; /sys refuses new files even to root.
  cifs_test::ScratchDir s("files");
  const fs::path folder = ::geteuid() == 0 ? fs::path("/sys") : s.path() / "read_only";
  if (::geteuid() != 0) {
    fs::create_directory(folder);
    fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec);
  }
  REQUIRE(fs::is_directory(folder));
  CHECK_THROWS_WITH(
      AtomicFile(folder / "x.png"),
      StartsWith((folder / "x.png").string() + ": cannot create a file in " + folder.string() + " ("));
}

TEST_CASE("Outputs onto an input are refused, by any name", "[core][files]") {
  cifs_test::ScratchDir s("files");
  const auto input = s.path() / "e.json";
  put(input, "{}");
  const OutputOptions options{.inputs = {input}};
  const auto refused = [&](const fs::path& target) {
    CHECK_THROWS_WITH(write_file_atomically(target, "x", options),
                      target.string() + ": is the input " + input.string() + "; choose another output file");
  };
  refused(input);
  refused(s.path() / "." / "e.json");
  fs::create_directory(s.path() / "sub");
  refused(s.path() / "sub" / ".." / "e.json");
  fs::create_hard_link(input, s.path() / "hard.json");
  refused(s.path() / "hard.json");
  fs::create_symlink("e.json", s.path() / "link.json");
  refused(s.path() / "link.json");
  CHECK(read_file(input) == "{}");
  // Any other file is fine, and without inputs the same path is an ordinary output.
  write_file_atomically(s.path() / "out.json", "x", options);
  write_file_atomically(input, "[]");
  CHECK(read_file(input) == "[]");
  CHECK(read_file(s.path() / "hard.json") == "{}");  // the hard link is another file now
  CHECK(s.names() == std::set<std::string>{"e.json", "hard.json", "link.json", "out.json", "sub"});
}

TEST_CASE("Symbolic links are written through and kept", "[core][files]") {
  cifs_test::ScratchDir s("files");
  fs::create_directories(s.path() / "real");
  put(s.path() / "real" / "image.exr", "old");
  // A relative link to another folder, reached through a second link.
  fs::create_symlink("real/image.exr", s.path() / "first.exr");
  fs::create_symlink("first.exr", s.path() / "second.exr");
  AtomicFile file(s.path() / "second.exr");
  CHECK(file.destination() == s.path() / "real/image.exr");
  CHECK(file.temporary().parent_path() == s.path() / "real");  // the rename stays on one file system
  file.write("new");
  file.commit();
  CHECK(fs::read_symlink(s.path() / "second.exr") == "first.exr");
  CHECK(fs::read_symlink(s.path() / "first.exr") == "real/image.exr");
  CHECK(read_file(s.path() / "real" / "image.exr") == "new");
  // A dangling link: the file it names is created.
  fs::create_symlink("made.txt", s.path() / "dangling");
  write_file_atomically(s.path() / "dangling", "made");
  CHECK(fs::is_symlink(s.path() / "dangling"));
  CHECK(read_file(s.path() / "made.txt") == "made");
  // A link to a folder is a folder; a loop is refused.
  fs::create_directory_symlink("real", s.path() / "folder_link");
  CHECK_THROWS_WITH(write_file_atomically(s.path() / "folder_link", "x"),
                    (s.path() / "folder_link").string() + ": is a directory");
  fs::create_symlink("loop_b", s.path() / "loop_a");
  fs::create_symlink("loop_a", s.path() / "loop_b");
  CHECK_THROWS_WITH(write_file_atomically(s.path() / "loop_a", "x"),
                    (s.path() / "loop_a").string() + ": too many levels of symbolic links");
  CHECK(s.names("real") == std::set<std::string>{"image.exr"});
}

TEST_CASE("Replacing a file keeps its permission bits", "[core][files]") {
  cifs_test::ScratchDir s("files");
  const auto path = s.path() / "private.txt";
  put(path, "old");
  fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write);
  write_file_atomically(path, "new");
  struct stat st {};
  REQUIRE(::stat(path.c_str(), &st) == 0);
  CHECK((st.st_mode & 07777) == 0600);
  CHECK(read_file(path) == "new");
}

TEST_CASE("AtomicFile: the temporary is made up front, hidden, renamed on commit, removed otherwise",
          "[core][files]") {
  cifs_test::ScratchDir s("files");
  const auto target = s.path() / "image.exr";
  {
    put(target, "old");
    AtomicFile file(target);
    CHECK(file.target() == target);
    CHECK(file.temporary().parent_path() == s.path());
    CHECK_THAT(file.temporary().filename().string(),
               StartsWith(".image.exr" + std::string(kTemporaryMarker) + std::to_string(::getpid()) + "."));
    CHECK(fs::is_regular_file(file.temporary()));  // made up front: an unwritable folder fails here
    put(file.temporary(), "new");                  // as a library writing by name does
    CHECK(read_file(target) == "old");             // the target is untouched until commit
  }
  CHECK(read_file(target) == "old");  // not committed: discarded
  CHECK(s.names() == std::set<std::string>{"image.exr"});
  {
    AtomicFile file(target);
    put(file.temporary(), "new");
    file.commit();
    file.commit();  // a second commit does nothing
  }
  CHECK(read_file(target) == "new");
  CHECK(s.names() == std::set<std::string>{"image.exr"});
  // Folders made for an output go again with it when it is not committed, and stay when it is.
  {
    AtomicFile file(s.path() / "a/b/c.txt", {.inputs = {}, .create_folders = true});
    CHECK(fs::is_directory(s.path() / "a/b"));
  }
  CHECK(s.names() == std::set<std::string>{"image.exr"});
  write_file_atomically(s.path() / "a/b/c.txt", "c", {.inputs = {}, .create_folders = true});
  CHECK(read_file(s.path() / "a/b/c.txt") == "c");
}

TEST_CASE("AtomicFiles: two names of one file are refused", "[core][files]") {
  cifs_test::ScratchDir s("files");
  AtomicFiles files;
  files.add(s.path() / "same", "outputs.exr");
  CHECK_THROWS_WITH(
      files.add(s.path() / "same", "outputs.png"),
      "outputs.png: " + (s.path() / "same").string() + " is also outputs.exr; give each output its own file");
  CHECK_THROWS_WITH(files.add(s.path() / "." / "same", "outputs.svg"), Contains(" is also outputs.exr"));
  fs::create_symlink("same", s.path() / "link");
  CHECK_THROWS_WITH(files.add(s.path() / "link", "outputs.ply"), Contains(" is also outputs.exr"));
  files.add(s.path() / "other", "outputs.ply");
  files.commit();
  CHECK(s.names() == std::set<std::string>{"link", "other", "same"});
}

TEST_CASE("AtomicFiles: all outputs are renamed or none is", "[core][files]") {
  cifs_test::ScratchDir s("files");
  put(s.path() / "a.exr", "old a");
  {
    AtomicFiles files;
    AtomicFile& a = files.add(s.path() / "a.exr", "a");
    AtomicFile& c = files.add(s.path() / "c.svg", "c");
    AtomicFile& b = files.add(s.path() / "b.png", "b");
    a.write("new a");
    c.write("new c");
    b.write("new b");
    // b's destination becomes a non-empty folder after the checks: its rename fails (EISDIR), after
    // a and c were renamed. a must be the old file again and c gone.
    fs::create_directories(s.path() / "b.png" / "inside");
    CHECK_THROWS_WITH(files.commit(), StartsWith((s.path() / "b.png").string() +
                                                 ": cannot rename the temporary file into place ("));
  }
  CHECK(read_file(s.path() / "a.exr") == "old a");
  CHECK(s.names() == std::set<std::string>{"a.exr", "b.png"});
  fs::remove_all(s.path() / "b.png");
  {
    AtomicFiles files;
    files.add(s.path() / "a.exr", "a").write("new a");
    files.add(s.path() / "b.png", "b").write("new b");
    files.commit();
  }
  CHECK(read_file(s.path() / "a.exr") == "new a");
  CHECK(read_file(s.path() / "b.png") == "new b");
  CHECK(s.names() == std::set<std::string>{"a.exr", "b.png"});
}

TEST_CASE("Stale temporaries of dead processes are removed by the next write into their folder",
          "[core][files]") {
  cifs_test::ScratchDir s("files");
  const pid_t dead = dead_pid();
  const std::string stale = temporary_for("a.exr", dead, 0), live = temporary_for("a.exr", 1, 0),
                    mine = temporary_for("a.exr", ::getpid(), 999999), held = temporary_for("b.exr", dead, 7),
                    other = ".a.exr.cifs-tmp.x.1";
  for (const std::string& name : {stale, live, mine, held, other}) put(s.path() / name, "partial");
  // A file locked by a live writer (another pid namespace shows another pid) is not stale.
  const int fd = ::open((s.path() / held).c_str(), O_RDONLY | O_CLOEXEC);
  REQUIRE(fd >= 0);
  REQUIRE(::flock(fd, LOCK_EX) == 0);
  write_file_atomically(s.path() / "new.txt", "x");
  ::close(fd);
  CHECK(s.names() == std::set<std::string>{live, mine, held, other, "new.txt"});
}

TEST_CASE("SIGTERM and SIGINT remove the open temporaries and end the process by the signal",
          "[core][files]") {
  for (const int signal : {SIGTERM, SIGINT}) {
    cifs_test::ScratchDir s("files");
    const pid_t child = ::fork();
    if (child == 0) {
      // The writer only handles signals whose action is the default; Catch2 has its own handlers,
      // and a background job ignores SIGINT.
      ::signal(signal, SIG_DFL);
      AtomicFiles files;
      files.add(s.path() / "a.exr", "a").write("partial");
      files.add(s.path() / "b.png", "b");
      ::raise(signal);
      ::_exit(0);  // not reached
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal);
    CHECK(s.names().empty());
  }
}

TEST_CASE("Temporary names differ between calls and threads", "[core][files]") {
  cifs_test::ScratchDir s("files");
  std::set<fs::path> names;
  for (int k = 0; k < 100; ++k) names.insert(AtomicFile(s.path() / "t").temporary());
  CHECK(names.size() == 100);
  // Threads writing the same target: every write succeeds and the file is one of them, whole.
  constexpr int kThreads = 8, kWrites = 50;
  std::vector<std::thread> threads;
  threads.reserve(kThreads);
  std::vector<int> failures(kThreads, 0);
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      const std::string content(1000 + t, static_cast<char>('a' + t));
      for (int k = 0; k < kWrites; ++k) {
        try {
          write_file_atomically(s.path() / "shared", content);
        } catch (const IoError&) {
          ++failures[static_cast<std::size_t>(t)];
        }
      }
    });
  for (auto& t : threads) t.join();
  CHECK(failures == std::vector<int>(kThreads, 0));
  const std::string last = read_file(s.path() / "shared");
  REQUIRE(last.size() >= 1000);
  const auto t = static_cast<std::size_t>(last[0] - 'a');
  CHECK(last == std::string(1000 + t, last[0]));
  CHECK(s.names() == std::set<std::string>{"shared"});
}

TEST_CASE("read_file names the path", "[core][files]") {
  cifs_test::ScratchDir s("files");
  CHECK_THROWS_WITH(read_file(s.path()), s.path().string() + ": is a directory");
  CHECK_THROWS_WITH(read_file(s.path() / "none"),
                    (s.path() / "none").string() + ": cannot open (No such file or directory)");
}

TEST_CASE("read_file reads regular files only: devices and FIFOs are refused without waiting",
          "[core][files][reliability]") {
  // /dev/zero was read until memory ran out (3.5 GB in 8.8 s); a FIFO blocked forever (issue 33).
  cifs_test::ScratchDir s("files");
  CHECK_THROWS_WITH(read_file("/dev/zero"), "/dev/zero: is a device; only regular files are read");
  CHECK_THROWS_WITH(read_file("/dev/null"), "/dev/null: is a device; only regular files are read");
  const fs::path fifo = s.path() / "pipe";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_WITH(read_file(fifo), fifo.string() + ": is a FIFO; only regular files are read");
  CHECK_THROWS_WITH(read_file(""), "empty input path");
  // A symbolic link to a regular file is read through; the bytes come back whole.
  put(s.path() / "bytes", all_bytes());
  fs::create_symlink(s.path() / "bytes", s.path() / "link");
  CHECK(read_file(s.path() / "link") == all_bytes());
  CHECK(read_file(s.path() / "bytes") == all_bytes());
}

TEST_CASE("RunInputs: while it lives, no output replaces a file that was read",
          "[core][files][reliability]") {
  // eval -o c.json replaced its shape c.json with points (issue 33): the output layer knows the run's
  // inputs by device and inode, whatever the spelling.
  cifs_test::ScratchDir s("files");
  put(s.path() / "in.json", "{}");
  fs::create_directories(s.path() / "sub");
  fs::create_symlink(s.path() / "in.json", s.path() / "link.json");
  fs::create_hard_link(s.path() / "in.json", s.path() / "hard.json");
  {
    const RunInputs inputs;
    (void)read_file(s.path() / "in.json");
    for (const fs::path& out :
         {s.path() / "in.json", s.path() / "sub" / ".." / "in.json", s.path() / "link.json"})
      CHECK_THROWS_WITH(write_file_atomically(out, "[]"), out.string() + ": is the input " +
                                                              (s.path() / "in.json").string() +
                                                              "; choose another output file");
    CHECK_THROWS_WITH(write_file_atomically(s.path() / "hard.json", "[]"), Contains("is the input"));
    write_file_atomically(s.path() / "other.json", "[]");  // any other file is written
  }
  CHECK(read_file(s.path() / "in.json") == "{}");
  // Without a RunInputs (the run is over; Python, the C++ API) a file read may be written back.
  write_file_atomically(s.path() / "in.json", "[]");
  CHECK(read_file(s.path() / "in.json") == "[]");
}

TEST_CASE("AtomicFile as a ByteSink: pieces into a temporary, renamed on commit, removed otherwise",
          "[core][files]") {
  cifs_test::ScratchDir s("files");
  const auto target = s.path() / "points.npy";
  std::ofstream(target) << "old";
  {
    AtomicFile file(target);
    CHECK(std::filesystem::exists(file.temporary()));  // created up front
    file.write(all_bytes().substr(0, 100));
    file.write("");
    file.write(all_bytes().substr(100));
    CHECK(file.size() == all_bytes().size());
    CHECK(read_file(file.temporary()) == all_bytes());
    CHECK(read_file(target) == "old");  // the target is untouched until commit
  }
  CHECK(read_file(target) == "old");  // not committed: discarded
  CHECK(s.names() == std::set<std::string>{"points.npy"});
  {
    AtomicFile file(target);
    file.write("new");
    file.commit();
    CHECK_THROWS_WITH(file.write("more"), target.string() + ": written after it was closed");
  }
  CHECK(read_file(target) == "new");
  CHECK(s.names() == std::set<std::string>{"points.npy"});
  CHECK_THROWS_WITH(AtomicFile(""), "empty output path");
  CHECK_THROWS_WITH(AtomicFile(s.path()), s.path().string() + ": is a directory");
  CHECK_THROWS_WITH(AtomicFile(s.path() / "missing" / "p.npy"),
                    StartsWith((s.path() / "missing" / "p.npy").string() + ": the folder "));
}

TEST_CASE("ChunkBuffer hands its bytes on a chunk at a time", "[core][files]") {
  struct Counting final : ByteSink {
    std::vector<std::size_t> pieces;
    std::string bytes;
    void write(std::string_view more) override {
      pieces.push_back(more.size());
      bytes += more;
    }
  } sink;
  ChunkBuffer out(sink);
  std::string expected;
  for (int k = 0; k < 300000; ++k) {
    const std::string piece = std::to_string(k) + ",";
    out.text += piece;
    expected += piece;
    out.spill();
  }
  CHECK(out.size() == expected.size());
  out.flush();
  CHECK(sink.bytes == expected);
  REQUIRE(sink.pieces.size() >= 2);
  for (std::size_t i = 0; i + 1 < sink.pieces.size(); ++i) {  // every piece but the last is one chunk
    CHECK(sink.pieces[i] >= ChunkBuffer::kChunkBytes);
    CHECK(sink.pieces[i] < ChunkBuffer::kChunkBytes + 16);
  }
}

TEST_CASE("check_disk_space names the bytes needed and those free", "[core][files]") {
  cifs_test::ScratchDir s("files");
  const auto target = s.path() / "huge.npy";
  const std::uint64_t free = std::filesystem::space(s.path()).available;
  CHECK_NOTHROW(check_disk_space(target, 1000));
  // More than is free, less once what was written already counts: half the free space still to come, so
  // that other processes writing meanwhile do not make it fail.
  CHECK_NOTHROW(check_disk_space(target, free + 1000, false, free / 2 + 1000));
  const std::uint64_t exabyte = std::uint64_t{1} << 60;
  CHECK_THROWS_AS(check_disk_space(target, exabyte), IoError);
  CHECK_THROWS_WITH(check_disk_space(target, exabyte),
                    StartsWith(target.string() + ": the file needs 1152921505 GB of disk space, ") &&
                        Contains(" GB are free there"));
  CHECK_THROWS_WITH(check_disk_space(target, exabyte, true), Contains("needs about 1152921505 GB"));
  CHECK(s.names().empty());
}
