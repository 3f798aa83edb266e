// SPDX-License-Identifier: MIT
#include "cifs/subdivision/scheme.hpp"

#include <algorithm>
#include <cctype>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/suggest.hpp"
#include "polynomial.hpp"

namespace cifs::subdivision {
namespace {

using boost::multiprecision::cpp_int;
using detail::multiply;
using detail::power;
using detail::scale;

Rational ratio(long long p, long long q) {
  return Rational(p) / Rational(q);
}

/// The exact numbers read: at most kMaxDigits digits as written (and exponents within ±300), and a
/// value within detail::kMaxNumberBits (1,414 digits a side). to_string prints such a value in at most
/// 1,475 digits (a fraction: 1,414 a side; a decimal: 60 more), so that what it prints of a number
/// read reads back (a 400-digit limit on the text alone did not: "1e300/1e-300" printed as 601 digits).
constexpr int kMaxDigits = 1500;

/// Exact decimal: [sign] digits [. digits] [e [sign] digits].
Rational parse_decimal(std::string_view s, std::string_view what, std::string_view whole) {
  const auto fail = [&]() -> Rational {
    throw InvalidInput(
        std::string(what) + ": '" + excerpt(whole) +
        "' is not a number (an integer, a decimal such as -0.0625 or a fraction such as 1/16)");
  };
  std::size_t i = 0;
  bool negative = false;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  cpp_int digits = 0;
  int scale10 = 0, count = 0;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
    digits = digits * 10 + (s[i++] - '0');
    ++count;
  }
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
      digits = digits * 10 + (s[i++] - '0');
      ++count;
      --scale10;
    }
  }
  if (count == 0 || count > kMaxDigits) return fail();
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    bool eneg = false;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) eneg = s[i++] == '-';
    int e = 0, ecount = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])) && ecount < 4) {
      e = e * 10 + (s[i++] - '0');
      ++ecount;
    }
    if (ecount == 0 || e > 300) return fail();
    scale10 += eneg ? -e : e;
  }
  if (i != s.size()) return fail();
  Rational value(digits);
  const cpp_int ten_power = boost::multiprecision::pow(cpp_int(10), static_cast<unsigned>(std::abs(scale10)));
  value = scale10 >= 0 ? value * Rational(ten_power) : value / Rational(ten_power);
  return negative ? -value : value;
}

std::string trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

int integer_parameter(const std::string& scheme, const std::string& name, const Rational& v, int low,
                      int high, const std::string& meaning) {
  if (denominator(v) != 1)
    throw InvalidInput(scheme + ": " + name + " = " + to_string(v) + " is not an integer (" + meaning + ")");
  if (v < low) {
    const std::string why = low == 0 && v < 0 ? " is negative: " : " is below " + std::to_string(low) + ": ";
    throw InvalidInput(scheme + ": " + name + " = " + to_string(v) + why + meaning);
  }
  if (v > high)
    throw InvalidInput(scheme + ": " + name + " = " + to_string(v) + " exceeds the limit " +
                       std::to_string(high) + " (" + meaning + ")");
  return static_cast<int>(numerator(v));
}

void check_integer(const std::string& scheme, const std::string& name, int v, int low, int high,
                   const std::string& meaning) {
  integer_parameter(scheme, name, Rational(v), low, high, meaning);
}

const Polynomial& four_point_mask() {
  static const Polynomial m = scale({-1, 0, 9, 16, 9, 0, -1}, ratio(1, 16));
  return m;
}
const Polynomial& six_point_mask() {
  static const Polynomial m = scale({3, 0, -25, 0, 150, 256, 150, 0, -25, 0, 3}, ratio(1, 256));
  return m;
}

constexpr int kMaxStages = 64;
const std::string kStagesMeaning = "the number of smoothing stages is 0, 1, 2, … ≤ 64";
const std::string kDegreeMeaning = "the B-spline degree n is 0, 1, 2, … ≤ 64";
const std::string kFamilyMeaning =
    "n, the number of smoothing stages of the two-tension family, is 0, 1, 2, … ≤ 64";

}  // namespace

Rational parse_rational(std::string_view text, std::string_view what) {
  const std::string t = trimmed(text);
  const auto slash = t.find('/');
  Rational x;
  if (slash == std::string::npos) {
    x = parse_decimal(t, what, t);
  } else {
    const Rational p = parse_decimal(trimmed(std::string_view(t).substr(0, slash)), what, t);
    const Rational q = parse_decimal(trimmed(std::string_view(t).substr(slash + 1)), what, t);
    if (q == 0) throw InvalidInput(std::string(what) + ": '" + excerpt(t) + "' divides by zero");
    x = p / q;
  }
  if (detail::bits(x) > detail::kMaxNumberBits)
    throw InvalidInput(std::string(what) + ": '" + excerpt(t) +
                       "' is beyond the exact numbers read (a numerator and a denominator of at most 1,414 "
                       "digits)");
  return x;
}

std::string to_string(const Rational& x) {
  cpp_int p = numerator(x), q = denominator(x);
  // A finite decimal iff q = 2^a 5^b.
  cpp_int r = q;
  int twos = 0, fives = 0;
  while (r % 2 == 0) r /= 2, ++twos;
  while (r % 5 == 0) r /= 5, ++fives;
  if (r != 1 || std::max(twos, fives) > 60) return p.str() + "/" + q.str();
  const int digits = std::max(twos, fives);
  const cpp_int scaled = p * boost::multiprecision::pow(cpp_int(10), static_cast<unsigned>(digits)) / q;
  const bool negative = scaled < 0;
  std::string s = (negative ? cpp_int(-scaled) : scaled).str();
  if (digits > 0) {
    if (static_cast<int>(s.size()) <= digits)
      s.insert(0, static_cast<std::size_t>(digits) + 1 - s.size(), '0');
    s.insert(s.size() - static_cast<std::size_t>(digits), ".");
  }
  return negative ? "-" + s : s;
}

double to_double(const Rational& x) {
  return x.convert_to<double>();
}

Scheme make_scheme(std::string name, Polynomial mask, std::vector<Parameter> parameters) {
  detail::trim(mask);
  // "mask: …" for user masks, "six-point: mask: …" for named schemes.
  const std::string where = name == "mask" ? "" : name + ": ";
  if (mask.empty()) throw InvalidInput(where + "mask: no non-zero coefficient");
  if (mask.size() > static_cast<std::size_t>(kMaxMaskSize))
    throw InvalidInput(where + "mask: " + std::to_string(mask.size()) + " coefficients exceed the limit of " +
                       std::to_string(kMaxMaskSize));
  Rational even = 0, odd = 0;
  for (std::size_t k = 0; k < mask.size(); ++k) (k % 2 ? odd : even) += mask[k];
  if (even + odd != 2)
    throw InvalidInput(where + "mask: coefficients sum to " + to_string(even + odd) +
                       ", a subdivision mask sums to 2");
  if (even != 1)
    throw InvalidInput(where + "mask: the even-indexed coefficients sum to " + to_string(even) +
                       " and the odd-indexed ones to " + to_string(odd) +
                       "; each must sum to 1 (every new point an affine combination)");
  if (mask.size() < 2) throw InvalidInput(where + "mask: a single coefficient does not refine");
  Scheme s;
  s.name = std::move(name);
  s.parameters = std::move(parameters);
  s.weights.reserve(mask.size());
  for (const Rational& a : mask) s.weights.push_back(to_double(a));
  s.mask = std::move(mask);
  return s;
}

Scheme chaikin() {
  return make_scheme("chaikin", scale({1, 3, 3, 1}, ratio(1, 4)));
}

Scheme corner_cutting(const Rational& a, const Rational& b) {
  return make_scheme("corner-cutting", {a, b, 1 - a, 1 - b}, {{"a", a}, {"b", b}});
}

Scheme four_point() {
  return make_scheme("four-point", four_point_mask());
}

Scheme generalized_four_point(const Rational& w) {
  return make_scheme("generalized-four-point", {-w, 0, Rational(1) / 2 + w, 1, Rational(1) / 2 + w, 0, -w},
                     {{"w", w}});
}

Scheme six_point() {
  return make_scheme("six-point", six_point_mask());
}

Scheme lane_riesenfeld(int degree) {
  check_integer("lane-riesenfeld", "degree", degree, 0, 64, kDegreeMeaning);
  const Polynomial half_one_plus_z{ratio(1, 2), ratio(1, 2)};
  return make_scheme("lane-riesenfeld", scale(power(half_one_plus_z, degree + 1), 2), {{"degree", degree}});
}

Scheme lr_four_point(int stages) {
  check_integer("lr-four-point", "stages", stages, 0, kMaxStages, kStagesMeaning);
  const Polynomial smooth = scale({-1, 9, 9, -1}, ratio(1, 16));
  return make_scheme("lr-four-point", multiply(four_point_mask(), power(smooth, stages)),
                     {{"stages", stages}});
}

Scheme lr_six_point(int stages) {
  check_integer("lr-six-point", "stages", stages, 0, kMaxStages, kStagesMeaning);
  const Polynomial smooth = scale({3, -25, 150, 150, -25, 3}, ratio(1, 256));
  return make_scheme("lr-six-point", multiply(six_point_mask(), power(smooth, stages)), {{"stages", stages}});
}

namespace {
Polynomial two_tension_mask(int n, const Rational& s, const Rational& t) {
  const Polynomial b{s, t, 1 - 2 * s - 2 * t, t, s};
  const Polynomial one_plus_z{1, 1};
  Rational two_n = 1;
  for (int i = 0; i < n; ++i) two_n *= 2;
  return scale(multiply(power(one_plus_z, n + 1), b), 1 / two_n);
}
}  // namespace

Scheme two_tension(int n, const Rational& s, const Rational& t) {
  check_integer("two-tension", "n", n, 0, 64, kFamilyMeaning);
  return make_scheme("two-tension", two_tension_mask(n, s, t), {{"n", n}, {"s", s}, {"t", t}});
}

Scheme b_spline(int degree) {
  check_integer("b-spline", "degree", degree, 0, 64, kDegreeMeaning);
  return make_scheme("b-spline", two_tension_mask(degree, 0, 0), {{"degree", degree}});
}

Scheme j_spline(const Rational& s) {
  return make_scheme("j-spline", two_tension_mask(1, (s - 1) / 8, ratio(1, 4)), {{"s", s}});
}

Scheme romani(int n, const Rational& w) {
  check_integer("romani", "n", n, 0, 64, kFamilyMeaning);
  return make_scheme("romani", two_tension_mask(n, -(n + 3) * w / 2, 4 * w), {{"n", n}, {"w", w}});
}

Scheme cubic_precision(int n, const Rational& s) {
  check_integer("cubic-precision", "n", n, 0, 64, kFamilyMeaning);
  const Rational t = -Rational(n + 1) / 8 - 4 * s;
  return make_scheme("cubic-precision", two_tension_mask(n, s, t), {{"n", n}, {"s", s}});
}

Scheme hormann_sabin(int n) {
  check_integer("hormann-sabin", "n", n, 3, 64,
                "the Hormann–Sabin members have n ≥ 3 smoothing stages (n = 3 is the 4-point scheme)");
  return make_scheme("hormann-sabin", two_tension_mask(n, 0, -Rational(n + 1) / 8), {{"n", n}});
}

Scheme dual_four_point() {
  return make_scheme("dual-four-point", two_tension_mask(2, ratio(-5, 32), ratio(1, 4)));
}

Scheme from_mask(Polynomial mask) {
  return make_scheme("mask", std::move(mask));
}

Scheme from_symbol(std::string_view expression) {
  return make_scheme("symbol", parse_symbol(expression));
}

const std::vector<SchemeSpec>& scheme_catalogue() {
  static const std::vector<SchemeSpec> catalogue = {
      {"chaikin", {}, "Chaikin corner cutting (1,3,3,1)/4: quadratic B-spline"},
      {"corner-cutting",
       {{"a", "0.25", "first cut, as a fraction of each edge"}, {"b", "0.75", "second cut"}},
       "x_{2i} = (1-a)x_i + a x_{i+1}, x_{2i+1} = (1-b)x_i + b x_{i+1}"},
      {"four-point", {}, "Dyn-Levin-Gregory interpolating 4-point scheme (-1,9,9,-1)/16"},
      {"generalized-four-point",
       {{"w", "0.0625", "tension w = eps/16 (seed 001's eps); 1/16 is the 4-point scheme"}},
       "x_{2i+1} = -w(x_{i-1}+x_{i+2}) + (1/2+w)(x_i+x_{i+1})"},
      {"six-point", {}, "interpolating 6-point scheme (3,-25,150,150,-25,3)/256"},
      {"lane-riesenfeld",
       {{"degree", "3", "B-spline degree n (seed 000's degree is n + 1)"}},
       "uniform B-spline of degree n: (1+z)^(n+1)/2^n"},
      {"b-spline",
       {{"degree", "3", "B-spline degree n"}},
       "two-tension member S(n,0,0), same as lane-riesenfeld"},
      {"lr-four-point",
       {{"stages", "1", "smoothing stages (seed 000's degree minus 1)"}},
       "generalised Lane-Riesenfeld: 4-point refine, then 4-point midpoint smoothing stages"},
      {"lr-six-point",
       {{"stages", "1", "smoothing stages (seed 000's degree minus 1)"}},
       "generalised Lane-Riesenfeld: 6-point refine, then 6-point midpoint smoothing stages"},
      {"two-tension",
       {{"n", "3", "smoothing stages"}, {"s", "0", "tension s"}, {"t", "0", "tension t"}},
       "(1+z)^(n+1)/2^n (s(1+z^4) + t(z+z^3) + (1-2s-2t)z^2) (seed 002)"},
      {"j-spline",
       {{"s", "1", "J-spline parameter: 0 four-point, 1 cubic B-spline, 1.5 quintic B-spline"}},
       "Rossignac-Schaefer J_s = S(1, (s-1)/8, 1/4)"},
      {"romani",
       {{"n", "1", "smoothing stages"}, {"w", "0.0625", "tension"}},
       "Romani's family S(n, -(n+3)w/2, 4w) (seed 002, eq. 3)"},
      {"cubic-precision",
       {{"n", "3", "smoothing stages"}, {"s", "0", "tension s; t = -(n+1)/8 - 4s"}},
       "the two-tension line with cubic precision (generalised Hormann-Sabin)"},
      {"hormann-sabin",
       {{"n", "3", "smoothing stages, n >= 3"}},
       "S(n, 0, -(n+1)/8); n = 3 is the 4-point scheme"},
      {"dual-four-point", {}, "dual 4-point scheme (-5,-7,35,105,105,35,-7,-5)/128 = S(2,-5/32,1/4)"},
      {"mask",
       {{"coefficients", "", "a_0 ... a_N, comma-separated (decimals or fractions)"}},
       "any mask; the coefficients sum to 2"},
      {"symbol", {{"symbol", "", "an expression in z, e.g. (1+z)^4*(-1+4z-z^2)/16"}}, "any symbol a(z)"},
  };
  return catalogue;
}

Scheme named_scheme(std::string_view name_view, const std::map<std::string, std::string>& given) {
  const std::string name(name_view);
  const auto& catalogue = scheme_catalogue();
  const auto spec =
      std::find_if(catalogue.begin(), catalogue.end(), [&](const SchemeSpec& s) { return s.name == name; });
  if (spec == catalogue.end()) {
    std::string names;
    std::vector<std::string> listed;
    listed.reserve(catalogue.size());
    for (const SchemeSpec& s : catalogue) {
      names += (names.empty() ? "" : ", ") + s.name;
      listed.push_back(s.name);
    }
    throw InvalidInput("unknown scheme '" + name + "'" + did_you_mean(name, listed) + " (schemes: " + names +
                       ")");
  }
  std::map<std::string, std::string> values;
  for (const ParameterSpec& p : spec->parameters) values[p.name] = p.default_value;
  for (const auto& [key, value] : given) {
    if (!values.count(key)) {
      std::string known;
      for (const ParameterSpec& p : spec->parameters) known += (known.empty() ? "" : ", ") + p.name;
      std::string message = name;
      message += ": unknown parameter '" + key + "' (";
      message += known.empty() ? "this scheme takes none" : "parameters: " + known;
      throw InvalidInput(message + ")");
    }
    values[key] = value;
  }
  for (const ParameterSpec& p : spec->parameters)
    if (trimmed(values[p.name]).empty())
      throw InvalidInput(name + ": parameter '" + p.name + "' is required (" + p.meaning + ")");
  const auto number = [&](const std::string& key) { return parse_rational(values[key], name + ": " + key); };
  const auto integer = [&](const std::string& key, int low, int high, const std::string& meaning) {
    return integer_parameter(name, key, number(key), low, high, meaning);
  };
  if (name == "chaikin") return chaikin();
  if (name == "corner-cutting") return corner_cutting(number("a"), number("b"));
  if (name == "four-point") return four_point();
  if (name == "generalized-four-point") return generalized_four_point(number("w"));
  if (name == "six-point") return six_point();
  if (name == "lane-riesenfeld") return lane_riesenfeld(integer("degree", 0, 64, kDegreeMeaning));
  if (name == "b-spline") return b_spline(integer("degree", 0, 64, kDegreeMeaning));
  if (name == "lr-four-point") return lr_four_point(integer("stages", 0, kMaxStages, kStagesMeaning));
  if (name == "lr-six-point") return lr_six_point(integer("stages", 0, kMaxStages, kStagesMeaning));
  if (name == "two-tension")
    return two_tension(integer("n", 0, 64, kFamilyMeaning), number("s"), number("t"));
  if (name == "j-spline") return j_spline(number("s"));
  if (name == "romani") return romani(integer("n", 0, 64, kFamilyMeaning), number("w"));
  if (name == "cubic-precision") return cubic_precision(integer("n", 0, 64, kFamilyMeaning), number("s"));
  if (name == "hormann-sabin")
    return hormann_sabin(integer("n", 3, 64, "the Hormann–Sabin members have n ≥ 3 smoothing stages"));
  if (name == "dual-four-point") return dual_four_point();
  if (name == "symbol") return from_symbol(values["symbol"]);
  // mask: comma- or space-separated, optionally in brackets.
  std::string text = values["coefficients"];
  for (char& c : text)
    if (c == '[' || c == ']' || c == ',' || c == ';') c = ' ';
  Polynomial mask;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    std::size_t j = i;
    while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
    if (j > i) mask.push_back(parse_rational(std::string_view(text).substr(i, j - i), "mask: coefficients"));
    i = j;
  }
  return from_mask(std::move(mask));
}

}  // namespace cifs::subdivision
