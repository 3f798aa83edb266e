// SPDX-License-Identifier: MIT
// cifs — a terminal progress bar on stderr.
#include "cifs/render/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "cifs/errors.hpp"

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

std::chrono::milliseconds stage_delay() {
  const char* text = std::getenv("CIFS_PROGRESS_AFTER");
  if (text == nullptr) return std::chrono::seconds(1);
  const std::string value(text);
  char* end = nullptr;
  const double seconds = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !(seconds >= 0 && seconds <= 3600))
    throw InvalidInput("CIFS_PROGRESS_AFTER: '" + value.substr(0, 40) +
                       "' is not a number of seconds from 0 to 3600");
  return std::chrono::milliseconds(std::lround(seconds * 1000));
}

Stage::Stage(std::string label, bool quiet)
    : label_(std::move(label)),
      start_(std::chrono::steady_clock::now()),
      exceptions_(std::uncaught_exceptions()) {
  if (quiet || ::isatty(STDERR_FILENO) != 1) return;
  const auto delay = stage_delay();
  ticker_ = std::thread([this, delay] {
    std::unique_lock lock(mutex_);
    // Silent at first (a second): short stages leave no line.
    if (wake_.wait_until(lock, start_ + delay, [this] { return stop_; })) return;
    do draw(false);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(100), [this] { return stop_; }));
  });
}

Stage::~Stage() {
  if (!ticker_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  ticker_.join();
  if (!shown_) return;
  if (std::uncaught_exceptions() > exceptions_) {
    std::fputs("\r\033[K", stderr);  // the error line follows on a clean line
    std::fflush(stderr);
  } else {
    draw(true);
  }
}

void Stage::draw(bool done) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "\r%s %s  %.1f s%s", label_.c_str(), done ? " done" : "…", seconds, done ? "\n" : "");
  std::fflush(stderr);
  shown_ = true;
}

}  // namespace cifs::render
