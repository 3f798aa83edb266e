// SPDX-License-Identifier: MIT
// cifs fuzzing: the replay driver. Linked with one harness (instead of libFuzzer) it feeds every
// file given, and every file of every folder given, to LLVMFuzzerTestOneInput in name order, and
// fails when one takes more than --budget seconds of CPU time (hangs are bugs, docs/reliability.md;
// CPU, not wall time: the test machine may be busy).
// Usage: fuzz_NAME_replay [--budget SECONDS] FILE|FOLDER...
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  double budget = 5;
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
    if (arg == "--budget" && i + 1 < argc) {
      budget = std::strtod(argv[++i], nullptr);  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
    } else if (fs::is_directory(arg)) {
      for (const auto& entry : fs::recursive_directory_iterator(arg))
        if (entry.is_regular_file()) files.push_back(entry.path());
    } else if (fs::is_regular_file(arg)) {
      files.emplace_back(arg);
    } else {
      std::fprintf(stderr, "replay: %s: no such file or folder\n", arg.c_str());
      return 2;
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::fprintf(stderr, "replay: no input given\n");
    return 2;
  }
  double total = 0, slowest = 0;
  fs::path slowest_file;
  for (const fs::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::clock_t start = std::clock();
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast)
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    const double seconds = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    total += seconds;
    if (seconds > slowest) slowest = seconds, slowest_file = file;
    if (seconds > budget) {
      std::fprintf(stderr, "replay: %s took %.2f s of CPU, above the budget of %.2f s\n", file.c_str(),
                   seconds, budget);
      return 1;
    }
  }
  std::printf("replay: %zu inputs in %.2f s, slowest %.3f s (%s)\n", files.size(), total, slowest,
              slowest_file.filename().c_str());
  return 0;
}
