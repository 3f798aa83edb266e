// SPDX-License-Identifier: MIT
// Masks of the named schemes against their published rules, exact parsing, symbols, bad input.
#include <catch2/catch.hpp>

#include "cifs/errors.hpp"
#include "cifs/subdivision/scheme.hpp"
#include "subdivision/rational.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using cifs_test::q;

namespace {

/// Mask from integer numerators over a common denominator.
Polynomial over(std::initializer_list<long long> numerators, long long denominator) {
  Polynomial m;
  for (long long x : numerators) m.push_back(q(x, denominator));
  return m;
}

Polynomial times(const Polynomial& a, const Polynomial& b) {
  Polynomial c(a.size() + b.size() - 1);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
  return c;
}

/// Binomial row C(k, ·)/2^(k−1): the mask of the B-spline of degree k − 1.
Polynomial binomial_mask(int k) {
  Polynomial m{Rational(1)};
  for (int i = 0; i < k; ++i) m = times(m, {q(1), q(1)});
  for (Rational& x : m) x /= Rational(1ll << (k - 1));
  return m;
}

}  // namespace

TEST_CASE("parse_rational is exact for decimals, fractions and exponents", "[subdivision]") {
  CHECK(parse_rational("0.0625", "w") == q(1, 16));
  CHECK(parse_rational(" -1/16 ", "w") == q(-1, 16));
  CHECK(parse_rational("1e-3", "w") == q(1, 1000));
  CHECK(parse_rational("2.5E2", "w") == 250);
  CHECK(parse_rational("0.1", "w") == q(1, 10));  // exact, unlike the double 0.1
  CHECK(parse_rational("0.5/3", "w") == q(1, 6));
  for (const char* bad : {"", "nan", "inf", "1/0", "1..2", "0x10", "1e400", "--1", "1/2/3"})
    CHECK_THROWS_AS(parse_rational(bad, "w"), InvalidInput);
  CHECK_THROWS_WITH(parse_rational("abc", "two-tension: s"),
                    Catch::Contains("two-tension: s: 'abc' is not a number"));
}

TEST_CASE("to_string prints finite decimals, otherwise fractions", "[subdivision]") {
  CHECK(to_string(q(1, 16)) == "0.0625");
  CHECK(to_string(q(-3, 2)) == "-1.5");
  CHECK(to_string(q(3)) == "3");
  CHECK(to_string(q(1, 3)) == "1/3");
  CHECK(to_string(q(-7, 40)) == "-0.175");
  CHECK(to_string(q(0)) == "0");
}

TEST_CASE("what to_string prints of a number read reads back to it", "[subdivision]") {
  // Found by fuzz_rational: 400 digits and exponents of ±300 on both sides of a fraction make
  // numbers of up to 1,401 digits, which to_string printed and parse_rational refused.
  const std::string digits400(400, '9');
  for (const std::string& text :
       {std::string("1e300/1e-300"), digits400 + "e300/0." + std::string(399, '0') + "1e-300",
        "0." + std::string(399, '0') + "1e-300/" + digits400 + "e300",
        "-" + std::string(200, '9') + "." + std::string(200, '9') + "e300/7"}) {
    const Rational x = parse_rational(text, "w");
    CHECK(parse_rational(to_string(x), "w") == x);
  }
  CHECK_THROWS_WITH(parse_rational(std::string(1501, '1'), "w"), Catch::Contains("is not a number"));
  CHECK_THROWS_WITH(parse_rational(std::string(1500, '1') + "e300/1e-300", "w"),
                    Catch::Contains("beyond the exact numbers read"));
}

TEST_CASE("named masks are the published rules", "[subdivision]") {
  // Seed 001: Chaikin x_{2i} = ¾x_i + ¼x_{i+1}, x_{2i+1} = ¼x_i + ¾x_{i+1}.
  CHECK(chaikin().mask == over({1, 3, 3, 1}, 4));
  // Seed 001: 4-point, x_{2i+1} = (−x_{i−1} + 9x_i + 9x_{i+1} − x_{i+2})/16, x_{2i} = x_i.
  CHECK(four_point().mask == over({-1, 0, 9, 16, 9, 0, -1}, 16));
  CHECK(six_point().mask == over({3, 0, -25, 0, 150, 256, 150, 0, -25, 0, 3}, 256));
  // Generalised 4-point at w = 1/16 is the 4-point scheme; w = 0 is linear interpolation.
  CHECK(generalized_four_point(q(1, 16)).mask == four_point().mask);
  CHECK(generalized_four_point(0).mask == over({1, 2, 1}, 2));
  // Corner cutting (seed 001) with a = ¼, b = ¾ is Chaikin.
  CHECK(corner_cutting(q(1, 4), q(3, 4)).mask == chaikin().mask);
  CHECK(corner_cutting(q(1, 10), q(6, 10)).mask == Polynomial{q(1, 10), q(6, 10), q(9, 10), q(4, 10)});
  // Lane–Riesenfeld degree n: binomial coefficients C(n+1, k)/2^n.
  for (int n : {0, 1, 2, 3, 7, 29}) CHECK(lane_riesenfeld(n).mask == binomial_mask(n + 1));
  CHECK(lane_riesenfeld(2).mask == chaikin().mask);
  CHECK(lane_riesenfeld(3).mask == over({1, 4, 6, 4, 1}, 8));
}

TEST_CASE("generalised Lane-Riesenfeld masks are refine times smoothing stages", "[subdivision]") {
  const Polynomial smooth4 = over({-1, 9, 9, -1}, 16);
  const Polynomial smooth6 = over({3, -25, 150, 150, -25, 3}, 256);
  CHECK(lr_four_point(0).mask == four_point().mask);
  CHECK(lr_six_point(0).mask == six_point().mask);
  CHECK(lr_four_point(2).mask == times(times(four_point().mask, smooth4), smooth4));
  CHECK(lr_six_point(1).mask == times(six_point().mask, smooth6));
  CHECK(lr_four_point(1).mask.size() == 10);  // 7 + 3: a dual scheme
}

TEST_CASE("two-tension members, each checked against an independent form", "[subdivision]") {
  // Seed 002 eq. (4) at s = t = 0: degree-n B-spline.
  for (int n : {0, 2, 3, 5}) CHECK(two_tension(n, 0, 0).mask == lane_riesenfeld(n).mask);
  for (int n : {1, 4}) CHECK(b_spline(n).mask == lane_riesenfeld(n).mask);
  // The refine stage of seed 002 eq. (5) followed by n LR smoothing stages (½, ½).
  {
    const Rational s = q(1, 10), t = q(-1, 7);
    // (R_{s,t}P)_{2i} = (s+t)P_{i−1} + (1−2s−t)P_i + sP_{i+1}; odd = sP_{i−1} + (1−2s−t)P_i + (s+t)P_{i+1}:
    // interleaved mask (s, s+t, 1−2s−t, 1−2s−t, s+t, s).
    Polynomial refine{s, s + t, 1 - 2 * s - t, 1 - 2 * s - t, s + t, s};
    for (int k = 0; k < 3; ++k) refine = times(refine, {q(1, 2), q(1, 2)});
    CHECK(two_tension(3, s, t).mask == refine);
  }
  // J-splines: (1−s)·4-point + s·cubic B-spline (Rossignac–Schaefer), masks aligned at the centre.
  for (const Rational& s : {q(0), q(1), q(3, 2), q(-17, 10), q(29, 5)}) {
    Polynomial blend(7);
    const Polynomial cubic = over({0, 1, 4, 6, 4, 1, 0}, 8);
    for (std::size_t k = 0; k < 7; ++k) blend[k] = (1 - s) * four_point().mask[k] + s * cubic[k];
    while (blend.front() == 0) blend.erase(blend.begin());
    while (blend.back() == 0) blend.pop_back();
    CHECK(j_spline(s).mask == blend);
  }
  CHECK(j_spline(0).mask == four_point().mask);
  CHECK(j_spline(1).mask == lane_riesenfeld(3).mask);
  CHECK(j_spline(q(3, 2)).mask == lane_riesenfeld(5).mask);
  // Romani (seed 002 eq. 3): ((1+z)/2)^{n+1}·(−(n+3)w + 8wz + 2(1+(n−5)w)z² + 8wz³ − (n+3)wz⁴).
  for (int n : {1, 2, 4}) {
    const Rational w = q(3, 64);
    Polynomial m{-(n + 3) * w, 8 * w, 2 * (1 + (n - 5) * w), 8 * w, -(n + 3) * w};
    for (int k = 0; k <= n; ++k) m = times(m, {q(1, 2), q(1, 2)});
    CHECK(romani(n, w).mask == m);
  }
  CHECK(romani(1, q(1, 16)).mask == four_point().mask);
  // The generalised 4-point scheme is Romani's n = 1 line.
  CHECK(romani(1, q(1, 10)).mask == generalized_four_point(q(1, 10)).mask);
  // Dual 4-point (−5, −7, 35, 105, 105, 35, −7, −5)/128: Romani n = 2, w = 1/16, Hormann–Sabin n = 4.
  const Polynomial dual4 = over({-5, -7, 35, 105, 105, 35, -7, -5}, 128);
  CHECK(dual_four_point().mask == dual4);
  CHECK(romani(2, q(1, 16)).mask == dual4);
  CHECK(hormann_sabin(4).mask == dual4);
  CHECK(hormann_sabin(3).mask == four_point().mask);
  // The 6-point scheme lies on the cubic-precision line: S_{5, 3/8, −9/4}.
  CHECK(two_tension(5, q(3, 8), q(-9, 4)).mask == six_point().mask);
  CHECK(cubic_precision(5, q(3, 8)).mask == six_point().mask);
  CHECK(cubic_precision(3, 0).mask == four_point().mask);
}

TEST_CASE("symbols parse to masks", "[subdivision]") {
  CHECK(parse_symbol("(1+z)^4*(-1+4z-z^2)/16") == four_point().mask);
  CHECK(from_symbol("(1+z)^3/4").mask == chaikin().mask);
  CHECK(from_symbol("z^-1 (1+z)^2 / 2").mask == over({1, 2, 1}, 2));  // Laurent: shifted
  CHECK(from_symbol("0.25 + 0.75z + 0.75z^2 + 0.25z^3").mask == chaikin().mask);
  CHECK(from_symbol("(1+z)(1+z)(1+z)/4").mask == chaikin().mask);
  CHECK(from_symbol("2^-2 (1+z)^3").mask == chaikin().mask);
  CHECK_THROWS_WITH(parse_symbol("(1+z)^3/(1+z)"), Catch::Contains("not a constant or a power of z"));
  CHECK_THROWS_WITH(parse_symbol("(1+z"), Catch::Contains("missing ')'"));
  CHECK_THROWS_WITH(parse_symbol("1+y"), Catch::Contains("unexpected 'y'"));
  CHECK_THROWS_WITH(parse_symbol("(1+z)^2.5"), Catch::Contains("an exponent must be an integer"));
  CHECK_THROWS_WITH(parse_symbol("z-z"), Catch::Contains("is zero"));
  CHECK_THROWS_AS(parse_symbol("(1+z)^100000"), InvalidInput);
}

TEST_CASE("bad masks and parameters are refused with clear messages", "[subdivision]") {
  CHECK_THROWS_WITH(from_mask(Polynomial{q(1, 4), q(3, 4), q(1, 2)}),
                    "mask: coefficients sum to 1.5, a subdivision mask sums to 2");
  CHECK_THROWS_WITH(from_mask(Polynomial{q(1), q(1, 2), q(1, 2)}),
                    Catch::Contains("even-indexed coefficients sum to 1.5 and the odd-indexed ones to 0.5"));
  CHECK_THROWS_WITH(from_mask(Polynomial{0, 0}), Catch::Contains("no non-zero coefficient"));
  CHECK_THROWS_AS(from_mask(Polynomial{}), InvalidInput);
  CHECK_THROWS_WITH(lr_four_point(-1), Catch::Contains("lr-four-point: stages = -1 is negative"));
  CHECK_THROWS_WITH(lr_six_point(65), Catch::Contains("exceeds the limit 64"));
  CHECK_THROWS_WITH(lane_riesenfeld(-2), Catch::Contains("degree = -2 is negative"));
  CHECK_THROWS_WITH(hormann_sabin(2), Catch::Contains("n = 2 is below 3"));
  // Leading and trailing zeros are trimmed.
  CHECK(from_mask(Polynomial{0, q(1, 4), q(3, 4), q(3, 4), q(1, 4), 0}).mask == chaikin().mask);
}

TEST_CASE("named_scheme reads text parameters and defaults", "[subdivision]") {
  CHECK(named_scheme("generalized-four-point", {}).mask == four_point().mask);
  CHECK(named_scheme("generalized-four-point", {{"w", "1/16"}}).mask == four_point().mask);
  CHECK(named_scheme("corner-cutting", {{"a", "0.1"}, {"b", "0.6"}}).mask ==
        corner_cutting(q(1, 10), q(3, 5)).mask);
  CHECK(named_scheme("mask", {{"coefficients", "[0.25, 0.75, 0.75, 0.25]"}}).mask == chaikin().mask);
  CHECK(named_scheme("mask", {{"coefficients", "1/4 3/4 3/4 1/4"}}).mask == chaikin().mask);
  CHECK(named_scheme("symbol", {{"symbol", "(1+z)^4/8"}}).mask == lane_riesenfeld(3).mask);
  CHECK(named_scheme("lr-six-point", {{"stages", "2"}}).mask == lr_six_point(2).mask);
  CHECK_THROWS_WITH(
      named_scheme("four-points", {}),
      Catch::Contains("unknown scheme 'four-points'; did you mean four-point? (schemes: chaikin"));
  CHECK_THROWS_WITH(named_scheme("chaikin", {{"w", "1"}}), Catch::Contains("unknown parameter 'w'"));
  CHECK_THROWS_WITH(named_scheme("lr-four-point", {{"stages", "1.5"}}),
                    Catch::Contains("stages = 1.5 is not an integer"));
  CHECK_THROWS_WITH(named_scheme("lr-four-point", {{"stages", "-3"}}), Catch::Contains("is negative"));
  CHECK_THROWS_WITH(named_scheme("mask", {}), Catch::Contains("parameter 'coefficients' is required"));
  CHECK_THROWS_WITH(named_scheme("mask", {{"coefficients", "1, 0.5, x"}}),
                    Catch::Contains("'x' is not a number"));
  CHECK_THROWS_WITH(named_scheme("mask", {{"coefficients", "0.5 0.5 0.5"}}),
                    "mask: coefficients sum to 1.5, a subdivision mask sums to 2");
  // Every catalogue entry builds with its defaults (except the two that need input).
  for (const SchemeSpec& spec : scheme_catalogue())
    if (spec.name != "mask" && spec.name != "symbol") CHECK_NOTHROW(named_scheme(spec.name, {}));
}

TEST_CASE("powers in symbols equal their products expanded term by term", "[subdivision]") {
  // Powers are taken on integers over one denominator and reduced once (parse_symbol; lane_riesenfeld is
  // checked against binomials above);
  // here each power is the product of its factors one at a time, every coefficient a reduced rational.
  const auto naive_power = [](const Polynomial& p, int e) {
    Polynomial r{Rational(1)};
    for (int k = 0; k < e; ++k) {
      Polynomial next(r.size() + p.size() - 1, Rational(0));
      for (std::size_t i = 0; i < r.size(); ++i)
        for (std::size_t j = 0; j < p.size(); ++j) next[i + j] += r[i] * p[j];
      r = std::move(next);
    }
    return r;
  };
  const Polynomial mixed{q(1, 3), q(-2, 7), q(1, 5)};
  for (int e : {0, 1, 2, 3, 7, 16, 33})
    CHECK(parse_symbol("(1/3 - 2z/7 + z^2/5)^" + std::to_string(e)) == naive_power(mixed, e));
  const Polynomial tenth{q(-1, 10), 1};
  CHECK(parse_symbol("z(-.1+z)^268") == naive_power(tenth, 268));
  CHECK(parse_symbol("(-1/10+z)^3(-1/10+z)^4") == naive_power(tenth, 7));
}

TEST_CASE("symbols beyond the largest mask are refused before they are expanded",
          "[subdivision][reliability]") {
  // (1+z)^1024 was expanded exactly (17 s) and only then refused for its 1025 coefficients.
  CHECK_THROWS_WITH(from_symbol("(1+z)^1024"),
                    Catch::Contains("the power has degree 1024, above the largest mask"));
  CHECK_THROWS_WITH(from_symbol("(1+z)^300*(1+z)^300"), Catch::Contains("the product has 601 coefficients"));
  CHECK(from_symbol("(1+z)^511/2^510").mask.size() == 512);  // the largest mask is still accepted
  // Sums likewise: "(z^1024)^1024 + 1" made a million coefficients before the mask was refused.
  CHECK_THROWS_WITH(parse_symbol("(z^1024)^1024+1"), Catch::Contains("the sum spans 1048577 powers of z"));
  CHECK_THROWS_WITH(parse_symbol("z^512-1"), Catch::Contains("the sum spans 513 powers of z"));
  CHECK(parse_symbol("z^511-1").size() == 512);
  CHECK(parse_symbol("z^600-z^600+1") == Polynomial{1});
}

TEST_CASE("symbols whose numbers grow beyond the exact numbers read are refused before they are computed",
          "[subdivision][reliability]") {
  // Found by fuzz_symbol: powers of constants had no bound, "((1e300)^1024)^3" ran for hours (its
  // coefficient has 921,600 digits); products and quotients of such numbers likewise.
  for (const char* text : {"((1e300)^1024)^3", "(1e300+z)^100", "(1e300)^5*(1e300)^5", "z/(1e-300)^16"})
    CHECK_THROWS_WITH(parse_symbol(text), Catch::Contains("would exceed the exact numbers read"));
  CHECK(parse_symbol("(1e300)^4/1e300^4") == Polynomial{1});
  // Powers of z: their exponents overflowed a long after six nested powers of 1024 (undefined behaviour).
  CHECK_THROWS_WITH(parse_symbol("(((z^1024)^1024)^1024)^1024"), Catch::Contains("the power of z is beyond"));
  CHECK(parse_symbol("z^-3(1+z)^2+z^-1") == Polynomial{1, 2, 2});
}

TEST_CASE("parse_symbol bounds the nesting of brackets and signs", "[subdivision][reliability]") {
  // Each bracket and unary sign was a recursive call: 5,000 brackets (a 10 kB argument) or 100,000
  // signs overflowed the stack, in the CLI and in Python (issue 33).
  const auto nested = [](int n) {
    return std::string(static_cast<std::size_t>(n), '(') + "1+z" +
           std::string(static_cast<std::size_t>(n), ')');
  };
  CHECK(parse_symbol(nested(200)) == Polynomial{1, 1});
  CHECK(parse_symbol(std::string(199, '-') + "(1+z)") == Polynomial{-1, -1});
  for (const std::string& text :
       {nested(201), nested(5000), std::string(100000, '-') + "1", std::string(100000, '+') + "z"}) {
    try {
      (void)parse_symbol(text);
      FAIL("accepted");
    } catch (const InvalidInput& e) {
      const std::string message = e.what();
      CHECK_THAT(message, Catch::Contains("more than 200 brackets or signs nested within each other"));
      CHECK(message.size() < 200);  // the expression is not echoed whole
      CHECK_THAT(message, Catch::Contains(std::to_string(text.size()) + " characters)"));
    }
  }
}
