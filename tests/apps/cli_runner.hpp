// SPDX-License-Identifier: MIT
// Runs the cifs command line as a user does (CIFS_CLI_PATH), capturing exit status, stdout and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/sanitized.hpp"
#include "support/scratch.hpp"

namespace cifs_test {

struct Run {
  int status;
  std::string out, err;
};

/// This process's folder for the CLI's inputs and outputs, removed when the process exits (ctest runs
/// each test case in its own process: thousands of folders were left in /tmp).
inline const std::filesystem::path& scratch() {
  static const ScratchDir folder("cli");
  return folder.path();
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// `stdout_to`: where standard output goes instead of being captured (e.g. /dev/full; `out` is then empty).
/// `shell_before`: shell commands run first in the same shell (e.g. a `ulimit`).
inline Run cifs_cli(const std::string& args, const std::string& stdout_to = "",
                    const std::string& shell_before = "") {
  const auto out = scratch() / "stdout", err = scratch() / "stderr";
  const std::string target = stdout_to.empty() ? out.string() : stdout_to;
  const std::string cmd =
      shell_before + std::string(CIFS_CLI_PATH) + " " + args + " >" + target + " 2>" + err.string();
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, stdout_to.empty() ? slurp(out) : "", slurp(err)};
}

/// A shell prefix that caps the CLI's address space at `gib` GiB, to prove that work is refused or
/// streamed before memory is exhausted; empty under AddressSanitizer, which reserves terabytes of
/// address space for its shadow memory.
inline std::string address_space_cap(int gib) {
  return kSanitized ? "" : "ulimit -v " + std::to_string(gib * 1024 * 1024) + "; ";
}

/// Writes `content` to a scratch file and returns its path.
inline std::string file(const std::string& name, const std::string& content) {
  const auto p = scratch() / name;
  std::ofstream(p) << content;
  return p.string();
}

/// One error line on stderr, nothing on stdout, exit status 2.
inline void check_error(const Run& r, const std::string& needle) {
  INFO("stderr: " << r.err);
  CHECK(r.status == 2);
  CHECK(r.out.empty());
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_THAT(r.err, Catch::StartsWith("cifs: ") && Catch::Contains(needle));
}

}  // namespace cifs_test
