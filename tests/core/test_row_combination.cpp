// SPDX-License-Identifier: MIT
// The row combination kernels (plain, SSE2 streaming, AVX streaming where the CPU has it) against a
// scalar sum in the documented order: the same bits for every number of terms, length and alignment
// of the output, so evaluate_grid and surface_mesh agree with pointwise evaluation whichever runs.
#include "cifs/row_combination.hpp"

#include <catch2/catch.hpp>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

namespace {

/// out[e] = f[0]·rows[0][e] + f[1]·rows[1][e] + …, left to right, one rounding per operation.
std::vector<double> reference(const std::vector<double>& f, const std::vector<std::vector<double>>& rows,
                              std::size_t first, std::size_t n) {
  std::vector<double> out(n);
  for (std::size_t e = 0; e < n; ++e) {
    volatile double acc = f[0] * rows[0][first + e];
    for (std::size_t r = 1; r < f.size(); ++r) {
      const volatile double term = f[r] * rows[r][first + e];
      acc = acc + term;
    }
    out[e] = acc;
  }
  return out;
}

/// Every kernel for `terms`: what row_combination picks, and each variant by name (on a CPU with AVX
/// row_combination never picks the SSE2 streaming kernel, which must still give the same bits).
std::vector<std::pair<const char*, cifs::RowCombination>> kernels(int terms) {
  std::vector<std::pair<const char*, cifs::RowCombination>> out{
      {"row_combination", cifs::row_combination(terms, false)},
      {"row_combination streamed", cifs::row_combination(terms, true)},
      {"combine_rows<0>", cifs::detail::combine_rows<0>}};
  const auto add = [&]<int T>() {
    if (T != terms) return;
    out.emplace_back("combine_rows<T>", cifs::detail::combine_rows<T>);
    out.emplace_back("combine_rows_stream<T>", cifs::detail::combine_rows_stream<T>);
#if defined(CIFS_X86_AVX)
    if (cifs::cpu_has_avx())
      out.emplace_back("combine_rows_stream_avx<T>", cifs::detail::combine_rows_stream_avx<T>);
#endif
  };
  add.template operator()<2>();
  add.template operator()<3>();
  add.template operator()<4>();
  add.template operator()<5>();
  add.template operator()<6>();
  return out;
}

}  // namespace

TEST_CASE("row combinations: every kernel gives the scalar sum's bits, any terms, length and alignment",
          "[core][stream]") {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> value(-1e3, 1e3);
  int checked = 0, expected = 0;
  for (int terms = 1; terms <= 7; ++terms) {
    std::vector<double> f(static_cast<std::size_t>(terms));
    for (double& x : f) x = value(rng) / 997.0;
    std::vector<std::vector<double>> rows(f.size(), std::vector<double>(80));
    for (auto& row : rows)
      for (double& x : row) x = value(rng);
    const auto all = kernels(terms);
    expected += static_cast<int>(all.size()) * 3 * 4 * 17;  // alignments of the rows and output, lengths
    for (const auto& [kernel, combine] : all) {
      for (std::size_t first = 0; first < 3; ++first)    // the rows' alignment
        for (std::size_t shift = 0; shift < 4; ++shift)  // the output's alignment (8-byte steps)
          for (std::size_t n = 0; n <= 41; n += (n < 12 ? 1 : 7)) {
            std::vector<const double*> at;
            at.reserve(rows.size());
            for (const auto& row : rows) at.push_back(row.data() + first);
            alignas(64) double out[64];
            std::fill(std::begin(out), std::end(out), -0.0);
            combine(f.data(), terms, at.data(), static_cast<std::ptrdiff_t>(n), out + shift);
            cifs::stream_fence();
            const std::vector<double> want = reference(f, rows, first, n);
            INFO(kernel << ", terms " << terms << ", rows +" << first << ", out +" << shift << ", n " << n);
            CHECK((n == 0 || std::memcmp(out + shift, want.data(), n * sizeof(double)) ==
                                 0));  // want.data() may be null
            // Nothing written outside [shift, shift + n).
            for (std::size_t k = 0; k < 64; ++k)
              if (k < shift || k >= shift + n) CHECK(std::signbit(out[k]));
            ++checked;
          }
    }
  }
  CHECK(checked == expected);
}
