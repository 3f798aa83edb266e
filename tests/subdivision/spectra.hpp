// SPDX-License-Identifier: MIT
// Test helper shared by the local-analysis tests: spectra compared as multisets.
#pragma once

#include <catch2/catch.hpp>

#include <complex>
#include <cstddef>
#include <vector>

namespace cifs_test {

/// Every expected eigenvalue matched to a distinct computed one within `tol` (multisets equal).
inline void check_same_spectrum(const std::vector<std::complex<long double>>& computed,
                                const std::vector<std::complex<long double>>& expected, long double tol) {
  REQUIRE(computed.size() == expected.size());
  std::vector<bool> used(computed.size(), false);
  for (const std::complex<long double>& e : expected) {
    std::size_t best = computed.size();
    for (std::size_t i = 0; i < computed.size(); ++i)
      if (!used[i] && (best == computed.size() || std::abs(computed[i] - e) < std::abs(computed[best] - e)))
        best = i;
    INFO("expected eigenvalue " << static_cast<double>(e.real()) << " + " << static_cast<double>(e.imag())
                                << "i");
    REQUIRE(std::abs(computed[best] - e) < tol);
    used[best] = true;
  }
}

}  // namespace cifs_test
