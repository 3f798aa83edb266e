// SPDX-License-Identifier: MIT
#include "cifs/subdivision/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/subdivision/ifs.hpp"
#include "cifs/subdivision/refine.hpp"
#include "polynomial.hpp"

namespace cifs::subdivision {
namespace {

using boost::multiprecision::cpp_int;
__extension__ typedef __int128 int128;  // GCC/Clang builtin (no pedantic warning through __extension__)

std::size_t power_length(std::size_t c_size, int L) {
  // (len − 1)(2^L − 1) + 1, saturating.
  const long double len = static_cast<long double>(c_size - 1) * (std::ldexp(1.0L, L) - 1) + 1;
  return len > 1e18L ? std::numeric_limits<std::size_t>::max() : static_cast<std::size_t>(len);
}

/// ‖S_c^L‖_∞ in double for L = 1 … (returned size), stopping at max_power or when c^{[L]} would
/// exceed max_coefficients.
std::vector<double> power_norms(const std::vector<double>& c, int max_power, std::size_t max_coefficients) {
  std::vector<double> norms;
  std::vector<double> cur = c, next;
  // Each step costs |c^{[L]}| × |c| products: up to 2^28 for masks of ≤ 64 coefficients (as the
  // coefficient cap allows), shrinking as |c|² beyond (lr-six-point stages=64, 326 coefficients,
  // took 16 s per analysis).
  const double n = static_cast<double>(std::count_if(c.begin(), c.end(), [](double x) { return x != 0; }));
  const double max_work = std::ldexp(1.0, 28) * std::pow(64 / std::max(n, 64.0), 2);
  for (int L = 1; L <= max_power; ++L) {
    if (L > 1) {
      if (power_length(c.size(), L) > max_coefficients) break;
      if (static_cast<double>(power_length(c.size(), L)) * n > max_work) break;
      // cur(z)·c(z^{2^{L−1}})
      const std::size_t step = std::size_t{1} << (L - 1);
      next.assign(cur.size() + (c.size() - 1) * step, 0.0);
      for (std::size_t j = 0; j < c.size(); ++j) {
        if (c[j] == 0) continue;
        double* out = next.data() + j * step;
        for (std::size_t i = 0; i < cur.size(); ++i) out[i] += c[j] * cur[i];
      }
      cur.swap(next);
    }
    const std::size_t period = std::size_t{1} << L;
    std::vector<double> sums(period, 0.0);
    for (std::size_t i = 0; i < cur.size(); ++i) sums[i % period] += std::abs(cur[i]);
    norms.push_back(*std::max_element(sums.begin(), sums.end()));
  }
  return norms;
}

template <class Int>
Rational integer_power_norm(const std::vector<cpp_int>& ci, const cpp_int& D, int L) {
  std::vector<Int> c(ci.size());
  for (std::size_t i = 0; i < ci.size(); ++i) c[i] = static_cast<Int>(ci[i]);
  std::vector<Int> cur = c, next;
  for (int l = 1; l < L; ++l) {
    const std::size_t step = std::size_t{1} << l;
    next.assign(cur.size() + (c.size() - 1) * step, Int(0));
    for (std::size_t j = 0; j < c.size(); ++j) {
      if (c[j] == 0) continue;
      for (std::size_t i = 0; i < cur.size(); ++i) next[i + j * step] += c[j] * cur[i];
    }
    cur.swap(next);
  }
  const std::size_t period = std::size_t{1} << L;
  std::vector<Int> sums(period, Int(0));
  for (std::size_t i = 0; i < cur.size(); ++i) sums[i % period] += cur[i] < 0 ? Int(-cur[i]) : cur[i];
  const Int best = *std::max_element(sums.begin(), sums.end());
  return Rational(cpp_int(best)) / Rational(boost::multiprecision::pow(D, static_cast<unsigned>(L)));
}

std::vector<double> to_doubles(const Polynomial& p) {
  std::vector<double> d;
  for (const Rational& x : p) d.push_back(to_double(x));
  return d;
}

std::string term_text(const Rational& c, std::size_t power, bool first) {
  std::string s;
  const bool negative = c < 0;
  const Rational a = negative ? Rational(-c) : c;
  if (negative)
    s += "-";
  else if (!first)
    s += "+";
  const bool unit = a == 1 && power > 0;
  if (!unit) s += to_string(a);
  if (power >= 1) s += "z";
  if (power >= 2) s += "^" + std::to_string(power);
  return s;
}

/// Spectral radius bound from products along primitive (Lyndon) words up to max_length.
double product_radius(const std::vector<double>& c, int max_length, std::vector<int>& best_word) {
  if (c.size() == 1) {
    best_word = {0};
    return std::abs(c[0]);
  }
  const Eigen::MatrixXd T[2] = {ifs_matrix(c, 0), ifs_matrix(c, 1)};
  if (T[0].rows() > 48) max_length = std::min(max_length, 6);
  double best = 0;
  for (int len = 1; len <= max_length; ++len) {
    for (unsigned long w = 0; w < (1ul << len); ++w) {
      // Lyndon: strictly smaller than every proper rotation.
      bool lyndon = true;
      for (int r = 1; r < len && lyndon; ++r) {
        const unsigned long rot = ((w << r) | (w >> (len - r))) & ((1ul << len) - 1);
        if (rot <= w) lyndon = false;
      }
      if (!lyndon) continue;
      Eigen::MatrixXd M = Eigen::MatrixXd::Identity(T[0].rows(), T[0].cols());
      for (int i = 0; i < len; ++i) M = T[(w >> (len - 1 - i)) & 1] * M;
      double rho = 0;
      for (const auto& lambda : ifs::eigenvalues(M)) rho = std::max(rho, std::abs(lambda));
      const double r = std::pow(rho, 1.0 / len);
      if (r > best) {
        best = r;
        best_word.clear();
        for (int i = 0; i < len; ++i) best_word.push_back(static_cast<int>((w >> (len - 1 - i)) & 1));
      }
    }
  }
  return best;
}

/// Work of power_norm(d, L) in 64-bit word products: c^{[L]} has power_length coefficients, each
/// step multiplies them by the non-zero coefficients of d, and its integers grow to about
/// L·log2(Σ|d_i|·D) bits (D the common denominator).
double exact_cost(const Polynomial& d, int L) {
  cpp_int D = 1;
  for (const Rational& x : d) D = boost::multiprecision::lcm(D, denominator(x));
  cpp_int total = 0;
  double nonzero = 0;
  for (const Rational& x : d) {
    total += boost::multiprecision::abs(numerator(x) * (D / denominator(x)));
    nonzero += x != 0;
  }
  const double bits = total > 0 ? static_cast<double>(boost::multiprecision::msb(total) + 1) * L : 1;
  const double words = bits < 125 ? 1 : bits / 64;
  return static_cast<double>(power_length(d.size(), L)) * nonzero * (1 + words * words);
}

/// About a second of exact arithmetic per power tried (at most 4 tries per difference scheme).
constexpr double kMaxExactCost = 2e8;

struct Contractivity {
  bool proved = false;
  int power = 0;
  Rational norm = 0;
  double best_root = std::numeric_limits<double>::infinity();  // min_L n_L^{1/L}
  int best_power = 0;
};

Contractivity contractivity(const Polynomial& d, const AnalysisOptions& options) {
  Contractivity result;
  const std::vector<double> norms = power_norms(to_doubles(d), options.max_power, options.max_coefficients);
  for (std::size_t i = 0; i < norms.size(); ++i) {
    const int L = static_cast<int>(i) + 1;
    const double root = std::pow(norms[i], 1.0 / L);
    if (root < result.best_root) result.best_root = root, result.best_power = L;
  }
  int exact_tries = 0;
  for (std::size_t i = 0; i < norms.size() && !result.proved && exact_tries < 4; ++i) {
    if (norms[i] > 1 + 1e-6)
      continue;  // clearly not contractive at this L (double is accurate to far better)
    const int L = static_cast<int>(i) + 1;
    if (power_length(d.size(), L) > options.max_coefficients / 4) break;  // exact arithmetic too costly
    if (exact_cost(d, L) > kMaxExactCost) break;  // big integers: lr-six-point stages=64 took minutes
    ++exact_tries;
    const Rational n = power_norm(d, L, options.max_coefficients);
    if (n < 1) result.proved = true, result.power = L, result.norm = n;
  }
  return result;
}

}  // namespace

Polynomial difference_mask(const Polynomial& a, int k) {
  Polynomial d = a;
  for (int i = 0; i <= k; ++i)
    if (!detail::divide_by_one_plus_z(d))
      throw InvalidInput("(1+z)^" + std::to_string(k + 1) + " does not divide the symbol");
  for (int i = 0; i < k; ++i) d = detail::scale(d, 2);
  return d;
}

Rational power_norm(const Polynomial& c, int L, std::size_t max_coefficients) {
  if (L < 1) throw InvalidInput("the power L = " + std::to_string(L) + " is below 1");
  if (c.empty()) return 0;
  if (L > 40 || power_length(c.size(), L) > max_coefficients)
    throw InvalidInput(
        "the " + std::to_string(L) +
        "-th power of the difference symbol has too many coefficients; lower the maximum power");
  cpp_int D = 1;
  for (const Rational& x : c) D = boost::multiprecision::lcm(D, denominator(x));
  std::vector<cpp_int> ci;
  cpp_int total = 0;
  for (const Rational& x : c) {
    ci.push_back(numerator(x) * (D / denominator(x)));
    total += boost::multiprecision::abs(ci.back());
  }
  // |coefficients of c^{[L]}| ≤ total^L and residue sums ≤ total^L: 128-bit integers suffice when
  // total^L < 2^125.
  if (total > 0 && static_cast<double>(boost::multiprecision::msb(total) + 1) * L < 125)
    return integer_power_norm<int128>(ci, D, L);
  return integer_power_norm<cpp_int>(ci, D, L);
}

std::string polynomial_text(const Polynomial& p) {
  cpp_int D = 1;
  for (const Rational& x : p) D = boost::multiprecision::lcm(D, denominator(x));
  std::string s;
  bool first = true, several = false;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i] == 0) continue;
    several = !first;
    s += term_text(p[i] * Rational(D), i, first);
    first = false;
  }
  if (first) return "0";
  if (D == 1) return s;
  return (several || s[0] == '-' ? "(" + s + ")" : s) + "/" + D.str();
}

SchemeAnalysis analyze(const Scheme& scheme, const AnalysisOptions& options) {
  SchemeAnalysis r;
  const Polynomial& a = scheme.mask;
  const int N = mask_degree(scheme);
  r.mask = a;
  r.support = N;
  r.symmetric = is_symmetric(scheme);
  r.kind = !r.symmetric ? "asymmetric" : (N % 2 == 0 ? "primal" : "dual");
  for (int e = 0; e < 2 && !r.interpolating; ++e) {
    int nonzero = 0;
    bool one = false;
    for (int k = e; k <= N; k += 2)
      if (a[static_cast<std::size_t>(k)] != 0) ++nonzero, one = a[static_cast<std::size_t>(k)] == 1;
    r.interpolating = nonzero == 1 && one;
  }
  r.multiplicity = detail::one_plus_z_multiplicity(a);
  const int m = r.multiplicity;
  r.generation_degree = m - 1;

  // Reproduction (Conti–Hormann).
  {
    const Rational tau = detail::evaluate(detail::derivative(a), 1) / 2;
    Polynomial D = a;
    Rational product = 1;  // Π_{i<j} (τ − i)
    for (int j = 0; j <= m - 1; ++j) {
      if (detail::evaluate(D, 1) != 2 * product) break;
      r.reproduction_degree = j;
      product *= tau - j;
      D = detail::derivative(D);
    }
  }

  // Symbol texts.
  r.symbol = polynomial_text(a);
  {
    Polynomial b = a;
    for (int i = 0; i < m; ++i) detail::divide_by_one_plus_z(b);
    const std::string rest = polynomial_text(b);
    if (m == 0)
      r.symbol_factored = r.symbol;
    else {
      const std::string head = m == 1 ? "(1+z)" : "(1+z)^" + std::to_string(m);
      // b = B/D with B integer: head*(B)/D, or head/D when B is a constant ±1.
      const auto slash = rest.rfind('/');
      std::string numerator_text = slash == std::string::npos ? rest : rest.substr(0, slash);
      const std::string denominator_text = slash == std::string::npos ? "" : rest.substr(slash);
      if (numerator_text.size() > 2 && numerator_text.front() == '(' && numerator_text.back() == ')')
        numerator_text = numerator_text.substr(1, numerator_text.size() - 2);
      if (numerator_text == "1")
        r.symbol_factored = head + denominator_text;
      else if (numerator_text == "-1")
        r.symbol_factored = "-" + head + denominator_text;
      else
        r.symbol_factored = head + "*(" + numerator_text + ")" + denominator_text;
    }
  }

  // Upper Hölder bound from d_{m−1}.
  if (m >= 1) {
    const Polynomial d = difference_mask(a, m - 1);
    const double rho = product_radius(to_doubles(d), options.max_word_length, r.holder_high_word);
    r.holder_high = (m - 1) - std::log2(rho);
  }

  // Dyn's test, from the highest k the upper bound allows down to 0.
  if (m >= 1) {
    int k_top = m - 1;
    if (r.holder_high && std::isfinite(*r.holder_high))
      k_top = std::min(k_top, static_cast<int>(std::floor(*r.holder_high + 1e-9)));
    // d_k = 2^k·a/(1+z)^{k+1}, each from the one above by one product with (1+z): difference_mask
    // for every k cost k_top²·N exact operations (a degree-510 B-spline: seconds).
    Polynomial q = a;  // a/(1+z)^{k+1}
    for (int i = 0; i <= k_top; ++i) detail::divide_by_one_plus_z(q);
    for (int k = k_top; k >= 0; --k) {
      if (k < k_top) q = detail::multiply(q, Polynomial{Rational(1), Rational(1)});
      const Contractivity c = contractivity(detail::scale(q, Rational(cpp_int(1) << k)), options);
      if (!c.proved) continue;
      r.continuity = k;
      r.proof = {k, c.power, c.norm};
      const double nu = -std::log2(c.best_root);
      r.holder_low = k + std::min(nu, 1.0);
      r.holder_low_power = c.best_power;
      break;
    }
  }

  // Spectra of S_0, S_1 through the IFS engine.
  for (const auto& spectrum : ifs::spectra(scheme_automaton(scheme)))
    r.eigenvalues[static_cast<std::size_t>(spectrum.child)] = spectrum.eigenvalues;
  return r;
}

}  // namespace cifs::subdivision
