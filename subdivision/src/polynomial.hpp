// SPDX-License-Identifier: MIT
// cifs — exact polynomial helpers for masks and symbols (private to the subdivision module).
#pragma once

#include <cstddef>
#include <string>

#include "cifs/subdivision/scheme.hpp"

namespace cifs::subdivision::detail {

inline void trim(Polynomial& p) {
  while (!p.empty() && p.back() == 0) p.pop_back();
  std::size_t first = 0;
  while (first < p.size() && p[first] == 0) ++first;
  p.erase(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(first));
}

inline Polynomial multiply(const Polynomial& a, const Polynomial& b) {
  if (a.empty() || b.empty()) return {};
  Polynomial c(a.size() + b.size() - 1);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] == 0) continue;
    for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
  }
  return c;
}

inline Polynomial power(const Polynomial& a, int k) {
  Polynomial result{Rational(1)};
  for (int i = 0; i < k; ++i) result = multiply(result, a);
  return result;
}

inline Polynomial scale(Polynomial p, const Rational& factor) {
  for (Rational& x : p) x *= factor;
  return p;
}

inline Rational evaluate(const Polynomial& p, const Rational& z) {
  Rational value = 0;
  for (std::size_t i = p.size(); i-- > 0;) value = value * z + p[i];
  return value;
}

inline Polynomial derivative(const Polynomial& p) {
  Polynomial d;
  for (std::size_t i = 1; i < p.size(); ++i) d.push_back(p[i] * static_cast<long long>(i));
  return d;
}

/// p(z)/(1+z) when p(−1) = 0 (exact synthetic division); returns false and leaves p alone
/// otherwise.
inline bool divide_by_one_plus_z(Polynomial& p) {
  if (p.size() < 2 || evaluate(p, Rational(-1)) != 0) return false;
  Polynomial q(p.size() - 1);
  Rational carry = 0;  // q_i = p_i − q_{i−1}
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    carry = p[i] - carry;
    q[i] = carry;
  }
  p = std::move(q);
  return true;
}

/// Number of factors (1+z) of p (p ≠ 0).
inline int one_plus_z_multiplicity(Polynomial p) {
  int m = 0;
  while (divide_by_one_plus_z(p)) ++m;
  return m;
}

}  // namespace cifs::subdivision::detail
