// SPDX-License-Identifier: MIT
// cifs — what the processor offers, asked at run time: the AVX kernels (row combinations, batch curve
// evaluation) are compiled on x86-64 with GCC or Clang (CIFS_X86_AVX) and taken only where the CPU has AVX.
#pragma once

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define CIFS_X86_AVX 1
#endif

namespace cifs {

#if defined(CIFS_X86_AVX)
/// True when the processor runs AVX instructions (asked once).
inline bool cpu_has_avx() noexcept {
  static const bool has = __builtin_cpu_supports("avx");
  return has;
}
#endif

}  // namespace cifs
