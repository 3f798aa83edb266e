// SPDX-License-Identifier: MIT
// cifs — a progress bar for long renders.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

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

}  // namespace cifs::render
