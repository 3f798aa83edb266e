// SPDX-License-Identifier: MIT
// cifs — chunks of work spread over threads (chaos games, mesh tiles).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <thread>
#include <vector>

namespace cifs::render::detail {

/// Worker count: `requested`, or every core when 0, never more than there are chunks (≥ 1).
inline unsigned worker_count(unsigned requested, std::uint64_t chunks) {
  const unsigned threads = requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
  return static_cast<unsigned>(std::min<std::uint64_t>(threads, std::max<std::uint64_t>(chunks, 1)));
}

/// Runs `work(thread, chunk)` for every chunk in [0, chunks) on `threads` workers; the calling
/// thread is worker `threads − 1`. Chunks are taken from an atomic counter, so each worker sees
/// its chunks in increasing order. `begin(thread)` runs first on each worker's own thread (memory
/// it allocates is first touched there). The first exception of any worker is rethrown after all
/// have joined.
template <class Begin, class Work>
void run_chunks(std::uint64_t chunks, unsigned threads, Begin&& begin, Work&& work) {
  std::atomic<std::uint64_t> next{0};
  const auto worker = [&](unsigned t) {
    begin(t);
    for (std::uint64_t c = next++; c < chunks; c = next++) work(t, c);
  };
  std::vector<std::exception_ptr> errors(threads);
  std::vector<std::thread> pool;
  for (unsigned t = 0; t + 1 < threads; ++t)
    pool.emplace_back([&, t] {
      try {
        worker(t);
      } catch (...) {
        errors[t] = std::current_exception();
        next = chunks;  // the others stop at their next chunk
      }
    });
  try {
    worker(threads - 1);
  } catch (...) {
    errors[threads - 1] = std::current_exception();
    next = chunks;
  }
  for (auto& thread : pool) thread.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace cifs::render::detail
