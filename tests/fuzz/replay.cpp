// SPDX-License-Identifier: MIT
// cifs fuzzing: the replay driver. Linked with every harness (instead of libFuzzer) it feeds every
// file given, and every file of every folder given, to the harness NAME in name order, and
// fails when one takes more than --budget seconds of CPU time (hangs are bugs, docs/reliability.md;
// CPU, not wall time: the test machine may be busy).
// With --mutate SECONDS it fuzzes blind instead for that much CPU time: each input is a seed with 1–4
// random edits (bits, bytes, ranges, the harness's dictionary tokens, numbers swapped for edge
// values, splices of two seeds), from --seed (reproducible for a given count of inputs). No coverage
// guides it — that is libFuzzer's job in scripts/fuzz.sh — but it runs in every sanitized build, so
// CI fuzzes the computations behind each harness on every commit. The input under test is kept in
// the --keep file (removed at the end): after a crash, it is the input that crashed.
// Usage: fuzz_replay NAME [--budget S] [--mutate S --keep FILE [--seed N] [--dict FILE]] FILE|FOLDER...
#include <fcntl.h>
#include <unistd.h>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "fuzz.hpp"

namespace {

namespace fs = std::filesystem;

/// The harnesses linked in, by name (filled by their static initializers: a function's static, so
/// that it exists before the first of them runs).
std::map<std::string, cifs::fuzz::Harness>& harnesses() {
  static std::map<std::string, cifs::fuzz::Harness> all;
  return all;
}

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

double cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

/// Runs one input through `harness`; its CPU seconds.
double run(cifs::fuzz::Harness harness, const std::string& bytes) {
  const double start = cpu_seconds();
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast)
  harness(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  return cpu_seconds() - start;
}

/// The tokens of a libFuzzer dictionary: the quoted part of each line, with \\, \" and \xNN.
std::vector<std::string> read_dictionary(const fs::path& file) {
  std::vector<std::string> tokens;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    const auto first = line.find('"'), last = line.rfind('"');
    if (line.starts_with('#') || first == std::string::npos || last <= first) continue;
    std::string token;
    for (std::size_t i = first + 1; i < last; ++i) {
      if (line[i] != '\\' || i + 1 >= last) {
        token += line[i];
      } else if (line[i + 1] == 'x' && i + 3 < last) {
        token += static_cast<char>(std::stoi(line.substr(i + 2, 2), nullptr, 16));
        i += 3;
      } else {
        token += line[++i];
      }
    }
    tokens.push_back(token);
  }
  return tokens;
}

/// Random edits of seed inputs.
class Mutator {
 public:
  Mutator(const std::vector<std::string>& seeds, std::vector<std::string> dictionary, std::uint64_t seed)
      : seeds_(seeds), dictionary_(std::move(dictionary)), rng_(seed) {
    for (const std::string& s : seeds_) max_size_ = std::max(max_size_, 2 * s.size());
  }

  std::string next() {
    std::string input = seeds_[below(seeds_.size())];
    const std::size_t edits = 1 + below(4);
    for (std::size_t k = 0; k < edits; ++k) edit(input);
    if (input.size() > max_size_) input.resize(max_size_);
    return input;
  }

 private:
  std::size_t below(std::size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
  }

  void edit(std::string& s) {
    static const char kBytes[] = {'\0', '\xff', '\x7f', '\x80', '-', '.', 'e',
                                  '9',  '0',    '"',    '[',    '{', ',', '\n'};
    static const char* const kNumbers[] = {"0",          "-0",     "-1",  "1e308", "-1e308",
                                           "1e-320",     "5e-324", "nan", "inf",   "2147483648",
                                           "4294967296", "1e9",    "0.5", "3"};
    const std::size_t at = below(s.size() + 1);
    switch (below(8)) {
      case 0:
        if (!s.empty()) s[at % s.size()] = static_cast<char>(s[at % s.size()] ^ (1 << below(8)));
        return;
      case 1:
        if (!s.empty()) s[at % s.size()] = kBytes[below(std::size(kBytes))];
        return;
      case 2:
        s.erase(std::min(at, s.size()), 1 + below(8));
        return;
      case 3:
        if (!s.empty()) {
          const std::size_t from = below(s.size());
          s.insert(at, s.substr(from, 1 + below(16)));
        }
        return;
      case 4:
        if (!dictionary_.empty()) s.insert(at, dictionary_[below(dictionary_.size())]);
        return;
      case 5: {  // the number at or after `at` becomes an edge value
        const auto digit = s.find_first_of("0123456789", std::min(at, s.size()));
        if (digit == std::string::npos) return;
        auto end = s.find_first_not_of("0123456789.eE+-", digit);
        if (end == std::string::npos) end = s.size();
        s.replace(digit, end - digit, kNumbers[below(std::size(kNumbers))]);
        return;
      }
      case 6: {  // this one's start, another seed's end
        const std::string& other = seeds_[below(seeds_.size())];
        s = s.substr(0, at) + other.substr(below(other.size() + 1));
        return;
      }
      default:
        for (std::size_t k = 1 + below(4); k > 0; --k)
          s.insert(s.begin() + static_cast<std::ptrdiff_t>(std::min(at, s.size())),
                   static_cast<char>(below(256)));
        return;
    }
  }

  const std::vector<std::string>& seeds_;
  std::vector<std::string> dictionary_;
  std::mt19937_64 rng_;
  std::size_t max_size_ = 64;
};

}  // namespace

bool cifs::fuzz::register_harness(const char* name, Harness entry) {
  harnesses().emplace(name, entry);
  return true;
}

int main(int argc, char** argv) {
  const auto found =
      argc > 1 ? harnesses().find(argv[1]) : harnesses().end();  // NOLINT(*-pointer-arithmetic)
  if (found == harnesses().end()) {
    std::string names;
    for (const auto& [name, entry] : harnesses()) names += " " + name;
    std::fprintf(stderr, "replay: the first argument names the harness, one of:%s\n", names.c_str());
    return 2;
  }
  const cifs::fuzz::Harness harness = found->second;
  double budget = 5, mutate = 0;
  std::uint64_t seed = 1;
  fs::path dictionary, keep;
  std::vector<fs::path> files;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
    const bool has_value = i + 1 < argc;
    if (arg == "--budget" && has_value) {
      budget = std::strtod(argv[++i], nullptr);  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
    } else if (arg == "--mutate" && has_value) {
      mutate = std::strtod(argv[++i], nullptr);  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
    } else if (arg == "--seed" && has_value) {
      seed =
          std::strtoull(argv[++i], nullptr, 10);  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
    } else if (arg == "--dict" && has_value) {
      dictionary = argv[++i];  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
    } else if (arg == "--keep" && has_value) {
      keep = argv[++i];  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic)
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
  if (files.empty() || (mutate > 0 && keep.empty())) {
    std::fprintf(stderr, files.empty() ? "replay: no input given\n" : "replay: --mutate needs --keep FILE\n");
    return 2;
  }
  double total = 0, slowest = 0;
  fs::path slowest_file;
  std::vector<std::string> seeds;
  for (const fs::path& file : files) {
    seeds.push_back(read_bytes(file));
    if (mutate > 0) continue;  // fuzz.replay.NAME runs the seeds themselves
    const double seconds = run(harness, seeds.back());
    total += seconds;
    if (seconds > slowest) slowest = seconds, slowest_file = file;
    if (seconds > budget) {
      std::fprintf(stderr, "replay: %s took %.2f s of CPU, above the budget of %.2f s\n", file.c_str(),
                   seconds, budget);
      return 1;
    }
  }
  if (mutate <= 0) {
    std::printf("replay: %zu inputs in %.2f s, slowest %.3f s (%s)\n", files.size(), total, slowest,
                slowest_file.filename().c_str());
    return 0;
  }

  std::printf("mutate: seed %llu for %.0f s of CPU; the input under test is kept in %s\n",
              static_cast<unsigned long long>(seed), mutate, keep.c_str());
  std::fflush(stdout);
  Mutator mutator(seeds, dictionary.empty() ? std::vector<std::string>{} : read_dictionary(dictionary), seed);
  const int fd = open(keep.c_str(), O_WRONLY | O_CREAT, 0644);  // NOLINT(cppcoreguidelines-pro-type-vararg)
  if (fd < 0) {
    std::fprintf(stderr, "mutate: %s: cannot open\n", keep.c_str());
    return 2;
  }
  std::size_t count = 0;
  const double start = cpu_seconds();
  for (double spent = 0; spent < mutate; spent = cpu_seconds() - start) {
    const std::string input = mutator.next();
    // Rewritten in place through one descriptor: closing a file truncated to 0 flushes it to disk
    // (ext4's auto_da_alloc), 10 times the harness's own time per input.
    if (pwrite(fd, input.data(), input.size(), 0) != static_cast<ssize_t>(input.size()) ||
        ftruncate(fd, static_cast<off_t>(input.size())) != 0) {
      std::fprintf(stderr, "mutate: %s: cannot write\n", keep.c_str());
      return 2;
    }
    const double seconds = run(harness, input);
    ++count;
    if (seconds > budget) {
      std::fprintf(stderr, "mutate: input %zu (kept in %s) took %.2f s of CPU, above the budget of %.2f s\n",
                   count, keep.c_str(), seconds, budget);
      return 1;
    }
  }
  close(fd);
  fs::remove(keep);
  const double spent = cpu_seconds() - start;
  std::printf("mutate: %zu inputs in %.1f s of CPU (%.0f per second), no finding\n", count, spent,
              static_cast<double>(count) / spent);
  return 0;
}
