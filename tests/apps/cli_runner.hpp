// SPDX-License-Identifier: MIT
// Runs the cifs command line as a user does (CIFS_CLI_PATH), capturing exit status, stdout and stderr.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
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

/// One stderr line, exit status 2 (check_error), the new wording, the old internal name gone, and no
/// `name:` prefix at all after "cifs: ".
inline void check_message(const Run& r, const std::string& wording, const std::string& old_name) {
  check_error(r, wording);
  INFO("stderr: " << r.err);
  CHECK(r.err.find(old_name) == std::string::npos);
  CHECK(!std::regex_search(r.err, std::regex("^cifs: [A-Za-z_]+: ")));
}

/// CPU seconds (user and system) of the children this process has waited for.
inline double children_cpu_seconds() {
  rusage usage{};
  ::getrusage(RUSAGE_CHILDREN, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

/// `command` refused within `seconds` of CPU time (one line naming `needle`, exit status 2). CPU time,
/// not wall time: the 2-core machine is shared with builds (a 0.01-s refusal took 2.5 s of wall time).
inline constexpr double kQuick = kSanitized ? 20 : 1;  // ASan and UBSan slow the estimates about 25 times
inline void check_quick_error(const std::string& command, const std::string& needle,
                              double seconds = kQuick) {
  INFO(command);
  const double before = children_cpu_seconds();
  check_error(cifs_cli(command), needle);
  CHECK(children_cpu_seconds() - before < seconds);
}

}  // namespace cifs_test
