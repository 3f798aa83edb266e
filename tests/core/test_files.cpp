// SPDX-License-Identifier: MIT
#include "cifs/files.hpp"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cifs/errors.hpp"

using namespace cifs;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

/// A fresh folder under the system's temporary directory, removed afterwards.
struct Scratch {
  std::filesystem::path dir;
  Scratch() {
    dir = std::filesystem::temp_directory_path() / ("cifs_test_files_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~Scratch() { std::filesystem::remove_all(dir); }
  std::set<std::string> names() const {
    std::set<std::string> out;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) out.insert(entry.path().filename());
    return out;
  }
};

/// Every byte value, twice, and a NUL in the middle: text functions would stop or translate.
std::string all_bytes() {
  std::string s;
  for (int k = 0; k < 512; ++k) s += static_cast<char>(k % 256);
  return s;
}

}  // namespace

TEST_CASE("write_file_atomically writes the bytes and leaves no temporary", "[core][files]") {
  Scratch s;
  const auto path = s.dir / "a.bin";
  write_file_atomically(path, all_bytes());
  CHECK(read_file(path) == all_bytes());
  write_file_atomically(path, "shorter");  // replaces the whole file
  CHECK(read_file(path) == "shorter");
  write_file_atomically(s.dir / "empty", "");
  CHECK(read_file(s.dir / "empty").empty());
  CHECK(s.names() == std::set<std::string>{"a.bin", "empty"});
}

TEST_CASE("write_file_atomically refuses bad targets and cleans up", "[core][files]") {
  Scratch s;
  CHECK_THROWS_WITH(write_file_atomically("", "x"), "empty output path");
  CHECK_THROWS_WITH(write_file_atomically(s.dir, "x"), s.dir.string() + ": is a directory");
  const auto missing = s.dir / "missing" / "b.txt";
  CHECK_THROWS_AS(write_file_atomically(missing, "x"), IoError);
  CHECK_THROWS_WITH(write_file_atomically(missing, "x"),
                    StartsWith(missing.string() + ": cannot write (") && Contains("No such file"));
  CHECK(s.names().empty());
}

TEST_CASE("AtomicFile: a temporary next to the target, renamed on commit, removed otherwise",
          "[core][files]") {
  Scratch s;
  const auto target = s.dir / "image.exr";
  {
    std::ofstream(target) << "old";
    AtomicFile file(target);
    CHECK(file.target() == target);
    CHECK(file.temporary().parent_path() == s.dir);
    CHECK_THAT(file.temporary().filename().string(),
               StartsWith("image.exr" + std::string(kTemporaryMarker) + std::to_string(::getpid()) + "-"));
    CHECK(!std::filesystem::exists(file.temporary()));  // nothing is created up front
    std::ofstream(file.temporary()) << "new";
    CHECK(read_file(target) == "old");  // the target is untouched until commit
  }
  CHECK(read_file(target) == "old");  // not committed: discarded
  CHECK(s.names() == std::set<std::string>{"image.exr"});
  {
    AtomicFile file(target);
    std::ofstream(file.temporary()) << "new";
    file.commit();
  }
  CHECK(read_file(target) == "new");
  CHECK(s.names() == std::set<std::string>{"image.exr"});
  // A commit without a temporary (the library wrote nothing) names the target.
  AtomicFile nothing(s.dir / "x.png");
  CHECK_THROWS_WITH(nothing.commit(),
                    StartsWith((s.dir / "x.png").string() + ": cannot rename the temporary file into place"));
  CHECK_THROWS_WITH(AtomicFile(""), "empty output path");
  CHECK_THROWS_WITH(AtomicFile(s.dir), s.dir.string() + ": is a directory");
}

TEST_CASE("Temporary names differ between calls and threads", "[core][files]") {
  Scratch s;
  std::set<std::filesystem::path> names;
  for (int k = 0; k < 100; ++k) names.insert(AtomicFile(s.dir / "t").temporary());
  CHECK(names.size() == 100);
  // Threads writing the same target: every write succeeds and the file is one of them, whole.
  constexpr int kThreads = 8, kWrites = 50;
  std::vector<std::thread> threads;
  std::vector<int> failures(kThreads, 0);
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      const std::string content(1000 + t, static_cast<char>('a' + t));
      for (int k = 0; k < kWrites; ++k) {
        try {
          write_file_atomically(s.dir / "shared", content);
        } catch (const IoError&) {
          ++failures[static_cast<std::size_t>(t)];
        }
      }
    });
  for (auto& t : threads) t.join();
  CHECK(failures == std::vector<int>(kThreads, 0));
  const std::string last = read_file(s.dir / "shared");
  REQUIRE(last.size() >= 1000);
  const auto t = static_cast<std::size_t>(last[0] - 'a');
  CHECK(last == std::string(1000 + t, last[0]));
  CHECK(s.names() == std::set<std::string>{"shared"});
}

TEST_CASE("read_file names the path", "[core][files]") {
  Scratch s;
  CHECK_THROWS_WITH(read_file(s.dir), s.dir.string() + ": is a directory");
  CHECK_THROWS_WITH(read_file(s.dir / "none"),
                    (s.dir / "none").string() + ": cannot open (No such file or directory)");
}

TEST_CASE("AtomicWriter: pieces into a temporary, renamed on commit, removed otherwise", "[core][files]") {
  Scratch s;
  const auto target = s.dir / "points.npy";
  std::ofstream(target) << "old";
  {
    AtomicWriter file(target);
    CHECK(std::filesystem::exists(file.temporary()));  // created up front (O_EXCL)
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
    AtomicWriter file(target);
    file.write("new");
    file.commit();
    CHECK_THROWS_WITH(file.write("more"), target.string() + ": written after it was closed");
  }
  CHECK(read_file(target) == "new");
  CHECK(s.names() == std::set<std::string>{"points.npy"});
  CHECK_THROWS_WITH(AtomicWriter(""), "empty output path");
  CHECK_THROWS_WITH(AtomicWriter(s.dir), s.dir.string() + ": is a directory");
  CHECK_THROWS_WITH(AtomicWriter(s.dir / "missing" / "p.npy"),
                    StartsWith((s.dir / "missing" / "p.npy").string() + ": cannot write ("));
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
  Scratch s;
  const auto target = s.dir / "huge.npy";
  const std::uint64_t free = std::filesystem::space(s.dir).available;
  CHECK_NOTHROW(check_disk_space(target, 1000));
  CHECK_NOTHROW(check_disk_space(target, free + 1000, false, 2000));  // 2000 bytes written already
  const std::uint64_t exabyte = std::uint64_t{1} << 60;
  CHECK_THROWS_AS(check_disk_space(target, exabyte), IoError);
  CHECK_THROWS_WITH(check_disk_space(target, exabyte),
                    StartsWith(target.string() + ": the file needs 1152921505 GB of disk space, ") &&
                        Contains(" GB are free there"));
  CHECK_THROWS_WITH(check_disk_space(target, exabyte, true), Contains("needs about 1152921505 GB"));
  CHECK(s.names().empty());
}
