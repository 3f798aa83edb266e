// SPDX-License-Identifier: MIT
// Symbol expressions: a small recursive-descent parser over Laurent polynomials with exact
// coefficients.
#include <bit>
#include <cctype>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/subdivision/scheme.hpp"
#include "polynomial.hpp"

namespace cifs::subdivision {
namespace {

/// c_0 z^low + c_1 z^{low+1} + …
struct Laurent {
  long low = 0;
  Polynomial c;
};

constexpr long kMaxExponent = 1024;
/// The largest power of z: a symbol is shifted to start at z^0, so only its span matters (at most a mask's
/// 511); this bound keeps the exponents' arithmetic far from overflowing ("((z^1024)^1024)^1024…").
constexpr long kMaxShift = 1L << 20;
/// Brackets and unary signs nested within each other: each is a call of the parser, and 5,000 of them
/// (a 10 kB argument) overflowed the stack. A mask's symbol never needs more than a few.
constexpr int kMaxNesting = 200;

Laurent normalised(Laurent p) {
  while (!p.c.empty() && p.c.back() == 0) p.c.pop_back();
  std::size_t first = 0;
  while (first < p.c.size() && p.c[first] == 0) ++first;
  p.c.erase(p.c.begin(), p.c.begin() + static_cast<std::ptrdiff_t>(first));
  p.low = p.c.empty() ? 0 : p.low + static_cast<long>(first);
  return p;
}

/// a += sign · b, in place: a sum of n terms costs n times a term, not n times the sum so far (the
/// 512 terms of a printed degree-511 symbol took a second).
void add(Laurent& a, const Laurent& b, int sign) {
  if (b.c.empty()) return;
  if (a.c.empty()) a.low = b.low;
  const long low = std::min(a.low, b.low);
  const long high = std::max(a.low + static_cast<long>(a.c.size()), b.low + static_cast<long>(b.c.size()));
  a.c.insert(a.c.begin(), static_cast<std::size_t>(a.low - low), Rational(0));
  a.c.resize(static_cast<std::size_t>(high - low));
  a.low = low;
  for (std::size_t i = 0; i < b.c.size(); ++i)
    a.c[static_cast<std::size_t>(b.low - low) + i] += sign * b.c[i];
  a = normalised(std::move(a));
}

Laurent times(const Laurent& a, const Laurent& b) {
  return normalised({a.low + b.low, detail::multiply(a.c, b.c)});
}

class Parser {
 public:
  explicit Parser(std::string_view text) : s_(text) {}

  Laurent parse() {
    Laurent p = expression();
    skip();
    if (i_ < s_.size()) fail("unexpected '" + std::string(1, s_[i_]) + "'");
    return p;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InvalidInput("symbol: " + why + " at character " + std::to_string(i_ + 1) + " of '" + excerpt(s_) +
                       "'");
  }

  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }

  /// '*', or the UTF-8 middle dot '·'.
  bool times_sign() {
    skip();
    if (i_ < s_.size() && s_[i_] == '*') return ++i_, true;
    if (s_.substr(i_, 2) == "\xC2\xB7") return i_ += 2, true;
    return false;
  }

  Laurent expression() {
    skip();
    Laurent p = term();
    for (;;) {
      skip();
      if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) {
        const int sign = s_[i_++] == '+' ? 1 : -1;
        const std::size_t at = i_;
        const Laurent q = term();
        // Like a product's: "(z^1024)^1024 + 1" held a million coefficients (0.5 s) for a mask refused later.
        if (!p.c.empty() && !q.c.empty()) {
          const long span =
              std::max(p.low + static_cast<long>(p.c.size()), q.low + static_cast<long>(q.c.size())) -
              std::min(p.low, q.low);
          if (span > kMaxMaskSize) {
            i_ = at;
            fail("the sum spans " + std::to_string(span) + " powers of z, above the largest mask (" +
                 std::to_string(kMaxMaskSize) + " coefficients)");
          }
        }
        add(p, q, sign);
      } else {
        return p;
      }
    }
  }

  bool starts_factor() {
    skip();
    return i_ < s_.size() && (s_[i_] == '(' || s_[i_] == 'z' || s_[i_] == 'Z' || s_[i_] == '.' ||
                              std::isdigit(static_cast<unsigned char>(s_[i_])));
  }

  Laurent term() {
    Laurent p = unary();
    for (;;) {
      if (times_sign() || starts_factor()) {  // implicit product too: 2z, (1+z)(1-z), z(1+z)
        const std::size_t at = i_;
        const Laurent q = unary();
        if (!p.c.empty() && !q.c.empty() && p.c.size() + q.c.size() - 1 > kMaxMaskSize) {
          i_ = at;
          fail("the product has " + std::to_string(p.c.size() + q.c.size() - 1) +
               " coefficients, above the largest mask (" + std::to_string(kMaxMaskSize) + ")");
        }
        check_size(detail::bits(p.c) + detail::bits(q.c) + std::bit_width(q.c.size()), at, "product");
        p = times(p, q);
        check_size(detail::bits(p.c), at, "product", 1);
      } else if (skip(), i_ < s_.size() && s_[i_] == '/') {
        ++i_;
        const std::size_t at = i_;
        const Laurent d = unary();
        if (d.c.size() != 1) {
          i_ = at;
          fail(d.c.empty() ? "division by zero"
                           : "division by a polynomial that is not a constant or a power of z");
        }
        p = normalised({p.low - d.low, detail::scale(p.c, 1 / d.c[0])});
        check_size(detail::bits(p.c), at, "quotient", 1);
      } else {
        return p;
      }
    }
  }

  /// Refuses a result whose coefficients need more than detail::kMaxNumberBits (`bits`, the largest
  /// numerator's or denominator's, after the arithmetic: `slack` 1), or may need more than twice that
  /// (`bits` a bound computed before it: `slack` 2, which bounds its time — "((1e300)^1024)^3" took hours).
  void check_size(std::size_t bits, std::size_t at, const char* what, std::size_t slack = 2) {
    if (bits <= slack * detail::kMaxNumberBits) return;
    i_ = at;
    fail("the " + std::string(what) + "'s coefficients would exceed the exact numbers read (1,414 digits)");
  }

  /// Counts one level of nesting while it lives (a bracket, a unary sign).
  class Nested {
   public:
    explicit Nested(Parser& p) : p_(p) {
      if (++p_.depth_ > kMaxNesting)
        p_.fail("more than " + std::to_string(kMaxNesting) + " brackets or signs nested within each other");
    }
    Nested(const Nested&) = delete;
    Nested& operator=(const Nested&) = delete;
    ~Nested() { --p_.depth_; }

   private:
    Parser& p_;
  };

  Laurent unary() {
    skip();
    if (i_ < s_.size() && (s_[i_] == '-' || s_[i_] == '+')) {
      const bool negative = s_[i_++] == '-';
      const Nested nested(*this);
      Laurent p = unary();
      if (negative)
        for (Rational& x : p.c) x = -x;
      return p;
    }
    return power();
  }

  Laurent power() {
    Laurent base = primary();
    skip();
    if (i_ < s_.size() && s_[i_] == '^') {
      ++i_;
      skip();
      bool negative = false;
      if (i_ < s_.size() && (s_[i_] == '-' || s_[i_] == '+')) negative = s_[i_++] == '-';
      long e = 0;
      const std::size_t start = i_;
      while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_])) && e <= kMaxExponent)
        e = e * 10 + (s_[i_++] - '0');
      if (i_ == start || (i_ < s_.size() && (s_[i_] == '.' || s_[i_] == 'e' || s_[i_] == 'E')))
        fail("an exponent must be an integer");
      if (e > kMaxExponent) fail("exponent beyond " + std::to_string(kMaxExponent));
      // Each coefficient of base^e has at most e times the base's bits, and e·log2(terms) more.
      check_size(static_cast<std::size_t>(e) * (detail::bits(base.c) + std::bit_width(base.c.size())), start,
                 "power");
      if (negative && base.c.size() != 1) fail("a negative power of a polynomial that is not a power of z");
      if (std::abs(base.low) > kMaxShift / std::max(e, 1L))
        fail("the power of z is beyond z^" + std::to_string(kMaxShift) + " or z^-" +
             std::to_string(kMaxShift));
      if (base.c.size() == 1) {  // c·z^low: its power at once (z^k term by term took k products)
        const Rational c = negative ? Rational(1 / base.c[0]) : base.c[0];
        const auto u = static_cast<unsigned>(e);
        const Rational value = Rational(pow(numerator(c), u)) / Rational(pow(denominator(c), u));
        check_size(detail::bits(value), start, "power", 1);
        return normalised({(negative ? -base.low : base.low) * e, {value}});
      }
      // A mask holds at most kMaxMaskSize coefficients: refuse a larger power before computing it
      // (the exact coefficients of (1+z)^1024 took 17 s, for a mask refused afterwards).
      if (base.c.size() > 1 && static_cast<long>(base.c.size() - 1) * e >= kMaxMaskSize)
        fail("the power has degree " + std::to_string(static_cast<long>(base.c.size() - 1) * e) +
             ", above the largest mask (" + std::to_string(kMaxMaskSize) + " coefficients, degree " +
             std::to_string(kMaxMaskSize - 1) + ")");
      Laurent r = normalised({base.low * e, detail::power(base.c, static_cast<int>(e))});
      check_size(detail::bits(r.c), start, "power", 1);
      return r;
    }
    return base;
  }

  Laurent primary() {
    skip();
    if (i_ >= s_.size()) fail("expression ends early");
    const char c = s_[i_];
    if (c == '(') {
      const Nested nested(*this);
      ++i_;
      Laurent p = expression();
      skip();
      if (i_ >= s_.size() || s_[i_] != ')') fail("missing ')'");
      ++i_;
      return p;
    }
    if (c == 'z' || c == 'Z') {
      ++i_;
      return {1, {Rational(1)}};
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const std::size_t start = i_;
      while (i_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.')) ++i_;
      // An exponent only when followed by a digit or a sign and a digit (so "2e" stays an error).
      if (i_ + 1 < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E') &&
          (std::isdigit(static_cast<unsigned char>(s_[i_ + 1])) ||
           ((s_[i_ + 1] == '-' || s_[i_ + 1] == '+') && i_ + 2 < s_.size() &&
            std::isdigit(static_cast<unsigned char>(s_[i_ + 2]))))) {
        i_ += 2;
        while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_]))) ++i_;
      }
      return normalised({0, {parse_rational(s_.substr(start, i_ - start), "symbol")}});
    }
    fail("unexpected '" + std::string(1, c) + "'");
  }

  std::string_view s_;
  std::size_t i_ = 0;
  int depth_ = 0;  // brackets and signs open
};

}  // namespace

Polynomial parse_symbol(std::string_view expression) {
  Laurent p = Parser(expression).parse();
  if (p.c.empty()) throw InvalidInput("symbol: '" + excerpt(expression) + "' is zero");
  return p.c;  // the lowest power shifted to z^0
}

}  // namespace cifs::subdivision
