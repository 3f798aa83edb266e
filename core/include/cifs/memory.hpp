// SPDX-License-Identifier: MIT
// cifs — large buffers: ask for transparent huge pages before the first write. A fresh buffer above
// glibc's mmap threshold (32 MiB at most) is faulted in page by page when first written, and on a
// VM each 4 KiB fault costs microseconds: at the sizes of a deep refinement or a 2048² grid, the
// faults take longer than the arithmetic. With huge pages there is one fault per 2 MiB.
#pragma once

#include <cstddef>
#include <vector>

namespace cifs {

/// Advises the kernel to back the 2 MiB-aligned part of [data, data + bytes) with transparent huge
/// pages (Linux with THP in "always" or "madvise" mode; a no-op elsewhere and under 4 MiB). Call it
/// before the buffer is first written; it changes no contents.
void advise_huge_pages(const void* data, std::size_t bytes) noexcept;

/// v.reserve(n), the new storage advised for huge pages.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

/// m.resize(rows, cols) for an output written next: storage of another size is fresh and advised for
/// huge pages; storage that already has rows · cols coefficients is kept, so that a caller reusing
/// its output across calls faults its pages in once (contents are left as they were).
template <class Matrix, class Index>
void resize_huge(Matrix& m, Index rows, Index cols) {
  const bool fresh = m.size() != rows * cols;
  m.resize(rows, cols);
  if (fresh) advise_huge_pages(m.data(), static_cast<std::size_t>(m.size()) * sizeof(*m.data()));
}

/// v.assign(n, value) into storage advised for huge pages.
template <class T>
void assign_huge(std::vector<T>& v, std::size_t n, const T& value) {
  if (v.capacity() < n) {
    v = {};
    reserve_huge(v, n);
  }
  v.assign(n, value);
}

}  // namespace cifs
