// SPDX-License-Identifier: MIT
// cifs — a progress bar for long renders.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace cifs::render {

/// Draws `label [#####.....]  42%  1.2 s` on stderr, redrawn in place with '\r', and finishes the
/// line at 100%. Draws nothing when `quiet` or when stderr is not a terminal (logs and pipes stay
/// clean). Redraws at most every 100 ms; call operator() as often as convenient (not thread-safe:
/// chaos_game_histogram serialises its progress calls).
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool quiet = false);
  void operator()(std::uint64_t done, std::uint64_t total);
  /// Whether the bar draws anything (stderr is a terminal and not quiet).
  bool active() const noexcept { return active_; }

 private:
  std::string label_;
  bool active_ = false;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

/// How long a Stage stays silent: `CIFS_PROGRESS_AFTER` seconds when that variable is set (a number from
/// 0 to 3600; 0 shows every stage), else one second. Throws InvalidInput naming the variable for any
/// other value.
std::chrono::milliseconds stage_delay();

/// A stage whose amount of work is not counted (building a mesh, rasterising, writing an image):
/// once it has run for stage_delay() (a second), `label …  3.2 s` on stderr, redrawn every 100 ms by
/// a thread of its own, and `label  done  3.4 s` when it ends (erased when it ends by an exception); a
/// shorter stage prints nothing. Quiet and non-terminal as ProgressBar. Stages are not nested, nor
/// drawn while a ProgressBar draws.
class Stage {
 public:
  explicit Stage(std::string label, bool quiet = false);
  ~Stage();
  Stage(const Stage&) = delete;
  Stage& operator=(const Stage&) = delete;
  Stage(Stage&&) = delete;
  Stage& operator=(Stage&&) = delete;

 private:
  void draw(bool done);
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  int exceptions_ = 0;  // std::uncaught_exceptions() at the start: a stage ended by an error is erased
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false, shown_ = false;
  std::thread ticker_;
};

}  // namespace cifs::render
