// SPDX-License-Identifier: MIT
// cifs — exact polynomial helpers for masks and symbols (private to the subdivision module).
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "cifs/subdivision/scheme.hpp"

namespace cifs::subdivision::detail {

/// The largest exact number read or made from what is read (parse_rational, symbols): a numerator and
/// a denominator of at most this many bits (about 1,414 digits). Bounds the time of exact arithmetic on
/// user input, and keeps what to_string prints of such a number readable (at most 1,500 digits).
inline constexpr std::size_t kMaxNumberBits = 4700;

/// The bits of the larger of x's numerator and denominator.
inline std::size_t bits(const Rational& x) {
  const auto width = [](const boost::multiprecision::cpp_int& n) -> std::size_t {
    return n == 0 ? 0 : boost::multiprecision::msb(boost::multiprecision::abs(n)) + 1;
  };
  return std::max(width(numerator(x)), width(denominator(x)));
}

/// The largest bits() of p's coefficients.
inline std::size_t bits(const Polynomial& p) {
  std::size_t b = 0;
  for (const Rational& x : p) b = std::max(b, bits(x));
  return b;
}

inline void trim(Polynomial& p) {
  while (!p.empty() && p.back() == 0) p.pop_back();
  std::size_t first = 0;
  while (first < p.size() && p[first] == 0) ++first;
  p.erase(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(first));
}

/// The coefficients over their common denominator: integers n_i and D with p_i = n_i / D.
inline std::vector<boost::multiprecision::cpp_int> over_common_denominator(
    const Polynomial& p, boost::multiprecision::cpp_int& D) {
  D = 1;
  for (const Rational& x : p)  // masks' denominators mostly divide the largest: a remainder, not a gcd, then
    if (D % denominator(x) != 0) D = boost::multiprecision::lcm(D, denominator(x));
  std::vector<boost::multiprecision::cpp_int> n;
  n.reserve(p.size());
  for (const Rational& x : p) n.push_back(numerator(x) * (D / denominator(x)));
  return n;
}

/// The product of integer polynomials.
inline std::vector<boost::multiprecision::cpp_int> convolve(
    const std::vector<boost::multiprecision::cpp_int>& a,
    const std::vector<boost::multiprecision::cpp_int>& b) {
  std::vector<boost::multiprecision::cpp_int> n(a.size() + b.size() - 1);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] == 0) continue;
    for (std::size_t j = 0; j < b.size(); ++j) n[i + j] += a[i] * b[j];
  }
  return n;
}

inline Polynomial scale(Polynomial p, const Rational& factor) {
  for (Rational& x : p) x *= factor;
  return p;
}

/// The integers n_i over D as rationals, each reduced once.
inline Polynomial over(const std::vector<boost::multiprecision::cpp_int>& n,
                       const boost::multiprecision::cpp_int& D) {
  Polynomial c;
  c.reserve(n.size());
  for (const auto& x : n) c.emplace_back(x, D);
  return c;
}

/// The product, on integers over common denominators: a rational multiply-add reduces by a gcd,
/// which made the 511 products of (1+z)^511 take 0.6 s.
inline Polynomial multiply(const Polynomial& a, const Polynomial& b) {
  if (a.empty() || b.empty()) return {};
  if (a.size() == 1) return scale(b, a[0]);  // c·z^k: no common denominators (c = 1 costs nothing)
  if (b.size() == 1) return scale(a, b[0]);
  boost::multiprecision::cpp_int da, db;
  const auto na = over_common_denominator(a, da), nb = over_common_denominator(b, db);
  return over(convolve(na, nb), da * db);
}

/// a^k by squaring on integers over the common denominator, reduced once at the end: reducing after every
/// product was 45 % of the time of the symbol "(1-.1+z)^268" (perf, 1 Dec).
inline Polynomial power(const Polynomial& a, int k) {
  if (a.empty()) return k == 0 ? Polynomial{Rational(1)} : Polynomial{};
  boost::multiprecision::cpp_int D, Dk = 1;
  auto n = over_common_denominator(a, D);
  std::vector<boost::multiprecision::cpp_int> r{1};
  for (; k > 0; k >>= 1) {
    if ((k & 1) != 0) r = convolve(r, n), Dk *= D;
    if (k > 1) n = convolve(n, n), D *= D;
  }
  return over(r, Dk);
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
