// SPDX-License-Identifier: MIT
// cifs — one row of a separable evaluation as a combination of rows: out[e] = Σ_r f[r]·rows[r][e]
// for e < n, summed in r order. The coefficients are the row's, not the point's, so this is a
// (p + 1)-term axpy over contiguous runs, which vectorises. Used by nurbs::evaluate_grid and
// ifs::surface_mesh, whose grids are such rows; and the streaming stores that write outputs far larger
// than the cache (these and the stencil-table routes of ifs).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "cifs/cpu.hpp"

namespace cifs {

/// Outputs of at least this many bytes (the L2 cache of the machines measured) may be written with
/// streaming stores where their storage is reused (fresh pages are zeroed by the kernel on the first
/// write, in the cache: streaming over them was 1.6–3× slower).
constexpr std::size_t kStreamBytes = std::size_t{1} << 21;

using RowCombination = void (*)(const double* f, int terms, const double* const* rows, std::ptrdiff_t n,
                                double* out) noexcept;

namespace detail {

/// Terms > 0 fixes the number of terms so that the r sum unrolls; 0 reads `terms` at run time.
template <int Terms>
void combine_rows(const double* f, int terms, const double* const* rows, std::ptrdiff_t n,
                  double* __restrict out) noexcept {
  if constexpr (Terms > 0) terms = Terms;
  for (std::ptrdiff_t e = 0; e < n; ++e) {
    double acc = f[0] * rows[0][e];
    for (int r = 1; r < terms; ++r) acc += f[r] * rows[r][e];
    out[e] = acc;
  }
}

/// combine_rows with streaming stores (SSE2; the same products and sums in the same order, so the
/// same bits): an output far larger than the cache is written without first reading its lines. The row
/// pointers are read once into locals (a streaming store could alias `rows`, so the compiler would
/// reload them every step), and two pairs go per step.
template <int Terms>
void combine_rows_stream(const double* f, int terms, const double* const* rows, std::ptrdiff_t n,
                         double* __restrict out) noexcept {
#if defined(__SSE2__)
  std::ptrdiff_t e = 0;
  if ((reinterpret_cast<std::uintptr_t>(out) & 15) != 0 && n > 0) {
    combine_rows<Terms>(f, terms, rows, 1, out);
    e = 1;
  }
  __m128d fr[Terms];
  const double* row[Terms];
  for (int r = 0; r < Terms; ++r) {
    fr[r] = _mm_set1_pd(f[r]);
    row[r] = rows[r];
  }
  const auto pair = [&](std::ptrdiff_t at) noexcept {
    __m128d acc = _mm_mul_pd(fr[0], _mm_loadu_pd(row[0] + at));
    for (int r = 1; r < Terms; ++r) acc = _mm_add_pd(acc, _mm_mul_pd(fr[r], _mm_loadu_pd(row[r] + at)));
    return acc;
  };
  for (; e + 4 <= n; e += 4) {
    const __m128d lo = pair(e), hi = pair(e + 2);
    _mm_stream_pd(out + e, lo);
    _mm_stream_pd(out + e + 2, hi);
  }
  if (e + 2 <= n) {
    _mm_stream_pd(out + e, pair(e));
    e += 2;
  }
  for (; e < n; ++e) {
    double acc = f[0] * row[0][e];
    for (int r = 1; r < Terms; ++r) acc += f[r] * row[r][e];
    out[e] = acc;
  }
#else
  combine_rows<Terms>(f, terms, rows, n, out);
#endif
}

#if defined(CIFS_X86_AVX)
/// combine_rows_stream four doubles a step (AVX, chosen at run time where the CPU has it; the build
/// targets baseline x86-64). Multiplies and adds, never fused, in combine_rows' order: the same bits.
template <int Terms>
__attribute__((target("avx"))) void combine_rows_stream_avx(const double* f, int terms,
                                                            const double* const* rows, std::ptrdiff_t n,
                                                            double* __restrict out) noexcept {
  std::ptrdiff_t e = 0;
  const double* row[Terms];
  for (int r = 0; r < Terms; ++r) row[r] = rows[r];
  const auto scalar = [&](std::ptrdiff_t at) noexcept {
    double acc = f[0] * row[0][at];
    for (int r = 1; r < Terms; ++r) acc += f[r] * row[r][at];
    out[at] = acc;
  };
  for (; e < n && (reinterpret_cast<std::uintptr_t>(out + e) & 31) != 0; ++e) scalar(e);
  __m256d fr[Terms];
  for (int r = 0; r < Terms; ++r) fr[r] = _mm256_set1_pd(f[r]);
  for (; e + 4 <= n; e += 4) {
    __m256d acc = _mm256_mul_pd(fr[0], _mm256_loadu_pd(row[0] + e));
    for (int r = 1; r < Terms; ++r)
      acc = _mm256_add_pd(acc, _mm256_mul_pd(fr[r], _mm256_loadu_pd(row[r] + e)));
    _mm256_stream_pd(out + e, acc);
  }
  for (; e < n; ++e) scalar(e);
  (void)terms;
}

#endif

}  // namespace detail

/// The combination for `terms` rows (2 … 6 unrolled), with streaming stores when `stream` (the caller
/// then calls stream_fence after its last row).
inline RowCombination row_combination(int terms, bool stream) noexcept {
#if defined(CIFS_X86_AVX)
  if (stream && cpu_has_avx()) {
    switch (terms) {
      case 2:
        return detail::combine_rows_stream_avx<2>;
      case 3:
        return detail::combine_rows_stream_avx<3>;
      case 4:
        return detail::combine_rows_stream_avx<4>;
      case 5:
        return detail::combine_rows_stream_avx<5>;
      case 6:
        return detail::combine_rows_stream_avx<6>;
      default:
        break;
    }
  }
#endif
  switch (terms) {
    case 2:
      return stream ? detail::combine_rows_stream<2> : detail::combine_rows<2>;
    case 3:
      return stream ? detail::combine_rows_stream<3> : detail::combine_rows<3>;
    case 4:
      return stream ? detail::combine_rows_stream<4> : detail::combine_rows<4>;
    case 5:
      return stream ? detail::combine_rows_stream<5> : detail::combine_rows<5>;
    case 6:
      return stream ? detail::combine_rows_stream<6> : detail::combine_rows<6>;
    default:
      return detail::combine_rows<0>;
  }
}

/// *p = v with a streaming store (8 bytes, any 8-byte alignment; a plain store without SSE2 on x86-64).
inline void stream_store(double* p, double v) noexcept {
#if defined(__SSE2__) && defined(__x86_64__)
  _mm_stream_si64(reinterpret_cast<long long*>(p), std::bit_cast<long long>(v));
#else
  *p = v;
#endif
}

/// Orders the streaming stores before what follows (a no-op without SSE2).
inline void stream_fence() noexcept {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

}  // namespace cifs
