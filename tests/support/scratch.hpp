// SPDX-License-Identifier: MIT
// The tests' one scratch folder: unique per process and per instance (ctest runs test cases in
// parallel processes, and the atomic writer sweeps a folder for stale temporaries), removed at the
// end even when a test took its permissions away, so tests can check what files are left.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <set>
#include <string>

namespace cifs_test {

class ScratchDir {
 public:
  /// `tag` only helps a reader of /tmp find whose folder it is.
  explicit ScratchDir(const std::string& tag = "test") {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("cifs_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all, std::filesystem::perm_options::add,
                                 ec);
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  /// File names in the folder (or its subfolder `sub`), sorted.
  std::set<std::string> names(const std::filesystem::path& sub = {}) const {
    std::set<std::string> out;
    for (const auto& entry : std::filesystem::directory_iterator(path_ / sub))
      out.insert(entry.path().filename());
    return out;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace cifs_test
