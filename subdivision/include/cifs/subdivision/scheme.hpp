// SPDX-License-Identifier: MIT
// cifs — uniform binary curve subdivision schemes given by their masks: the seeds' named schemes
// (Chaikin, corner cutting, Dyn–Levin–Gregory 4-point and its tension family, the 6-point scheme,
// Lane–Riesenfeld, generalised Lane–Riesenfeld, the two-tension family and its members), user
// masks and user symbols. Masks are exact rationals; parameters given as decimal strings convert
// exactly ("0.0625" is 1/16).
//
// Convention: the mask a_0 … a_N refines a bi-infinite polygon by q_i = Σ_j a_{i−2j} p_j; its
// symbol is a(z) = Σ_k a_k z^k. Affine invariance needs Σ_k a_{2k} = Σ_k a_{2k+1} = 1 (so the
// coefficients sum to 2), which make_scheme enforces.
#pragma once

#include <boost/multiprecision/cpp_int.hpp>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace cifs::subdivision {

using Rational = boost::multiprecision::cpp_rational;
/// Polynomial in z with exact coefficients, lowest power first.
using Polynomial = std::vector<Rational>;

/// Exact value of an integer ("3"), a decimal ("-0.0625", "1e-3") or a fraction ("1/16",
/// "0.5/3"). Throws InvalidInput naming `what` for anything else (empty, "nan", "1/0", more than 1,500
/// digits, an exponent beyond ±300, a value whose numerator or denominator exceeds 1,414 digits, …).
/// to_string prints every number read as text that reads back to it.
Rational parse_rational(std::string_view text, std::string_view what);

/// Shortest exact text: a decimal when the value has a finite decimal expansion ("0.0625",
/// "-1.5", "3"), otherwise a fraction ("1/3").
std::string to_string(const Rational& x);

/// Nearest double.
double to_double(const Rational& x);

/// A named parameter of a scheme and its exact value.
struct Parameter {
  std::string name;
  Rational value;
};

/// A scheme: its name, the parameters it was built from and its mask, trimmed so that a_0 and a_N
/// are non-zero (N ≥ 1). `weights` holds the same mask as doubles (the refinement kernel's taps).
struct Scheme {
  std::string name;
  std::vector<Parameter> parameters;
  Polynomial mask;
  std::vector<double> weights;
};

/// N: the mask has N + 1 coefficients; the basic limit function is supported on [0, N] and the IFS
/// matrices are N by N.
inline int mask_degree(const Scheme& scheme) {
  return static_cast<int>(scheme.mask.size()) - 1;
}

/// Largest mask accepted (N + 1 coefficients).
inline constexpr int kMaxMaskSize = 512;

/// Validates and trims the mask (leading and trailing zeros dropped). Throws InvalidInput, naming
/// `name`, when it is empty or all zero, longer than kMaxMaskSize, a single coefficient, when its
/// coefficients do not sum to 2 ("mask: coefficients sum to 1.5, a subdivision mask sums to 2"),
/// or when the even- and odd-indexed coefficients do not sum to 1 each.
Scheme make_scheme(std::string name, Polynomial mask, std::vector<Parameter> parameters = {});

/// Chaikin: (1, 3, 3, 1)/4, x_{2i} = ¾x_i + ¼x_{i+1}, x_{2i+1} = ¼x_i + ¾x_{i+1} (seed 001).
Scheme chaikin();
/// Corner cutting (seed 001): x_{2i} = (1−a)x_i + a·x_{i+1}, x_{2i+1} = (1−b)x_i + b·x_{i+1};
/// mask (a, b, 1−a, 1−b). Chaikin is a = ¼, b = ¾; b = 1 − a is the symmetric family.
Scheme corner_cutting(const Rational& a, const Rational& b);
/// Dyn–Levin–Gregory 4-point: x_{2i+1} = (−x_{i−1} + 9x_i + 9x_{i+1} − x_{i+2})/16.
Scheme four_point();
/// Generalised 4-point with tension w (seed 001 with its typo corrected: w = ε/16):
/// x_{2i+1} = −w(x_{i−1} + x_{i+2}) + (½ + w)(x_i + x_{i+1}); w = 1/16 is four_point().
Scheme generalized_four_point(const Rational& w);
/// Interpolating 6-point: x_{2i+1} = (3, −25, 150, 150, −25, 3)/256 · (x_{i−2} … x_{i+3}).
Scheme six_point();
/// Uniform B-spline of degree n ≥ 0 by Lane–Riesenfeld: symbol (1+z)^{n+1}/2^n (n averaging
/// passes after doubling; seed 000's "degree" is n + 1). Degree ≤ 64.
Scheme lane_riesenfeld(int degree);
/// Generalised Lane–Riesenfeld (Cashman–Hormann–Reif; seed 000 with its index bugs fixed): refine
/// with the 4-point (6-point) rule, then `stages` smoothing stages that replace each point by the
/// 4-point (6-point) value at the midpoint of it and its successor: symbol
/// a_4pt(z)·((−1 + 9z + 9z² − z³)/16)^stages, resp. a_6pt(z)·((3 − 25z + 150z² + 150z³ − 25z⁴ +
/// 3z⁵)/256)^stages. Seed 000's "degree" is stages + 1. 0 ≤ stages ≤ 64.
Scheme lr_four_point(int stages);
Scheme lr_six_point(int stages);
/// Two-tension family of Shi, Tan, Liu, Zhang (seed 002): symbol
/// (1+z)^{n+1}/2^n · (s(1+z⁴) + t(z+z³) + (1−2s−2t)z²), n ≥ 0 smoothing stages. 0 ≤ n ≤ 64.
Scheme two_tension(int n, const Rational& s, const Rational& t);
/// Members of the two-tension family under their own names (each mask checked against its
/// published form in tests/subdivision):
/// - B-spline of degree n: S_{n,0,0} (= lane_riesenfeld(n)).
/// - J-spline J_s (Rossignac–Schaefer; J_0 4-point, J_1 cubic B-spline, J_{3/2} quintic B-spline):
///   (1−s)·4-point + s·cubic B-spline = S_{1,(s−1)/8,1/4}.
/// - Romani's Chaikin-based family a_{n,w} (seed 002, eq. 3): S_{n,−(n+3)w/2,4w}.
/// - Cubic-precision line (the generalisation of Hormann–Sabin's family): 4s + t = −(n+1)/8,
///   cubic precision when the scheme generates cubics (n ≥ 3, or t = ¼: the 4-point at n = 1, the
///   dual 4-point at n = 2).
/// - Hormann–Sabin: the cubic-precision line at s = 0, S_{n,0,−(n+1)/8}, n ≥ 3 (n = 3 is the
///   4-point scheme).
/// - Dual 4-point (−5, −7, 35, 105, 105, 35, −7, −5)/128 = S_{2,−5/32,1/4}.
Scheme b_spline(int degree);
Scheme j_spline(const Rational& s);
Scheme romani(int n, const Rational& w);
Scheme cubic_precision(int n, const Rational& s);
Scheme hormann_sabin(int n);
Scheme dual_four_point();
/// A user mask a_0 … a_N.
Scheme from_mask(Polynomial mask);
/// A user symbol: an expression in z with + − * / ^ and parentheses, numbers as in
/// parse_rational (a fraction is a division), implicit products ("2z", "(1+z)(1-z)"), powers with
/// integer exponents (negative ones of z alone: Laurent symbols are shifted to start at z^0), and
/// division by constants, e.g. "(1+z)^4*(-1+4z-z^2)/16". Throws InvalidInput pointing at the
/// offending character.
Scheme from_symbol(std::string_view expression);
/// The polynomial of a symbol expression (as from_symbol, without the mask checks); the lowest
/// power of z is shifted to z^0.
Polynomial parse_symbol(std::string_view expression);

/// A parameter of a named scheme, with its default value ("" when required).
struct ParameterSpec {
  std::string name;
  std::string default_value;
  std::string meaning;
};

/// A name the command line accepts (`cifs scheme NAME --param k=v`).
struct SchemeSpec {
  std::string name;
  std::vector<ParameterSpec> parameters;
  std::string summary;
};

/// Every named scheme, in the order of docs/schemes.md.
const std::vector<SchemeSpec>& scheme_catalogue();

/// Builds a scheme from its catalogue name and text parameters (missing ones take their
/// defaults). Throws InvalidInput for an unknown name (listing the names), an unknown or
/// repeated parameter, a missing required one, a value that does not parse, a non-integer or
/// out-of-range integer parameter ("lr-four-point: stages = -1 is negative: …").
Scheme named_scheme(std::string_view name, const std::map<std::string, std::string>& parameters);

}  // namespace cifs::subdivision
