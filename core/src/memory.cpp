// SPDX-License-Identifier: MIT
#include "cifs/memory.hpp"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cifs {

void advise_huge_pages(const void* data, std::size_t bytes) noexcept {
#if defined(MADV_HUGEPAGE)
  constexpr std::size_t kHuge = std::size_t{2} << 20;
  if (data == nullptr || bytes < 2 * kHuge) return;
  const std::size_t misalignment = reinterpret_cast<std::uintptr_t>(data) % kHuge;
  const std::size_t skip = misalignment == 0 ? 0 : kHuge - misalignment;
  const std::size_t length = (bytes - skip) / kHuge * kHuge;
  // Advice only: a kernel without THP refuses it and the buffer keeps small pages.
  if (length > 0)
    (void)madvise(const_cast<char*>(static_cast<const char*>(data)) + skip, length, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace cifs
