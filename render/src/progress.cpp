// SPDX-License-Identifier: MIT
// cifs — a terminal progress bar on stderr.
#include "cifs/render/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace cifs::render {

ProgressBar::ProgressBar(std::string label, bool quiet)
    : label_(std::move(label)),
      active_(!quiet && ::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

void ProgressBar::operator()(std::uint64_t done, std::uint64_t total) {
  if (!active_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  const bool complete = total == 0 || done >= total;
  // Redrawing costs a system call; ten frames a second is smooth enough.
  if (!complete && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double fraction = complete ? 1.0 : static_cast<double>(done) / static_cast<double>(total);
  constexpr int kWidth = 30;
  const int filled = std::clamp(static_cast<int>(fraction * kWidth), 0, kWidth);
  const double seconds = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "\r%s [%.*s%.*s] %3d%%  %.1f s", label_.c_str(), filled,
               "##############################", kWidth - filled, "..............................",
               static_cast<int>(fraction * 100), seconds);
  if (complete) {
    std::fputc('\n', stderr);
    finished_ = true;
  }
  std::fflush(stderr);
}

}  // namespace cifs::render
