// SPDX-License-Identifier: MIT
// Local subdivision matrices at extraordinary vertices: the matrix written from the rules equals the
// one read off the general refinement, and the spectra equal what the Fourier blocks of the rules
// give — derived here, by hand, from the rules as the papers state them, not from the code.
#include "cifs/subdivision/mesh_analysis.hpp"
#include "subdivision/rational.hpp"
#include "subdivision/spectra.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <utility>
#include <vector>

#include "cifs/errors.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using Catch::Matchers::Contains;
using cifs_test::check_same_spectrum;
using cifs_test::exact_rank;
using cifs_test::shifted_power;

namespace {

using Complex = std::complex<long double>;
constexpr long double kPi = std::numbers::pi_v<long double>;

constexpr MeshScheme kAllSchemes[] = {MeshScheme::catmull_clark, MeshScheme::loop, MeshScheme::doo_sabin,
                                      MeshScheme::butterfly, MeshScheme::sqrt3};

long double cos_2pi(long double m, long double n) {
  return std::cos(2 * kPi * m / n);
}

/// The 4th largest modulus of a multiset (μ after 1 and the subdominant pair).
long double fourth_modulus(std::vector<Complex> values) {
  std::sort(values.begin(), values.end(),
            [](const Complex& a, const Complex& b) { return std::abs(a) > std::abs(b); });
  return std::abs(values[3]);
}

// The Fourier blocks: a vector of the neighbourhood whose sector-j entries are x̂·ω^{jℓ},
// ω = e^{2πiℓ/n}, is mapped to one of the same kind; the map on x̂ is the block of mode ℓ.

/// Loop: r'_j = 3/8 c + 3/8 r_j + 1/8 (r_{j−1} + r_{j+1}) gives 3/8 + ¼cos(2πℓ/n) for ℓ ≠ 0; the
/// mean ring and c: c' = (1 − nβ)c + nβ r̄, r̄' = 3/8 c + 5/8 r̄: 1 and 5/8 − nβ.
std::vector<Complex> loop_spectrum(int n) {
  const long double a = 3.0L / 8 + cos_2pi(1, n) / 4, beta = (5.0L / 8 - a * a) / n;
  std::vector<Complex> out{1, 5.0L / 8 - n * beta};
  for (int l = 1; l < n; ++l) out.emplace_back(3.0L / 8 + cos_2pi(l, n) / 4);
  return out;
}

/// Catmull–Clark, sector j = (r_j, f_j): r'_j = 3/8 c + 3/8 r_j + 1/16 (r_{j−1} + r_{j+1} + f_{j−1} +
/// f_j), f'_j = ¼ (c + r_j + f_j + r_{j+1}). For ℓ ≠ 0 the block is
/// [[3/8 + cos θ/8, (1 + ω̄)/16], [(1 + ω)/4, ¼]], θ = 2πℓ/n: trace 5/8 + cos θ/8, determinant 1/16.
/// For ℓ = 0 with c: c' = (4n − 7)/(4n) c + 3/(2n) r̄ + 1/(4n) f̄, r̄' = 3/8 c + ½ r̄ + ⅛ f̄,
/// f̄' = ¼ c + ½ r̄ + ¼ f̄.
std::vector<Complex> catmull_clark_spectrum(int n) {
  std::vector<Complex> out;
  out.reserve(2 * static_cast<std::size_t>(n) + 1);
  Eigen::Matrix<long double, 3, 3> zero;
  const long double nd = n;
  zero << (4 * nd - 7) / (4 * nd), 3 / (2 * nd), 1 / (4 * nd), 3.0L / 8, 0.5L, 1.0L / 8, 0.25L, 0.5L, 0.25L;
  const Eigen::EigenSolver<Eigen::Matrix<long double, 3, 3>> solver(zero, false);
  for (int i = 0; i < 3; ++i)
    out.emplace_back(solver.eigenvalues()(i).real(), solver.eigenvalues()(i).imag());
  for (int l = 1; l < n; ++l) {
    const long double T = 5.0L / 8 + cos_2pi(l, n) / 8, D = 1.0L / 16;
    const long double root = std::sqrt(T * T - 4 * D);  // T² − 4D = ((5 + c)² − 16)/64 ≥ 0
    out.emplace_back((T + root) / 2);
    out.emplace_back((T - root) / 2);
  }
  return out;
}

/// The closed form.
long double catmull_clark_lambda1(int n) {
  const long double c = cos_2pi(1, n);
  return (5 + c + std::cos(kPi / n) * std::sqrt(2 * (9 + c))) / 16;
}

/// Doo–Sabin around a k-gon: the face's own corner points are the circulant of
/// α_m = ¼δ_m + (3 + 2cos(2πm/k))/(4k), whose DFT is 1, ½ (ℓ = ±1), ¼ (else). The ring outside:
/// a'_i = 3/16 a_i + 1/16 b_i, b'_i = 1/16 a_i + 3/16 b_i (plus face corners), c'_i = 1/16 c_i (plus
/// a_i, b_{i−1}, g_i): ¼, ⅛ and 1/16, k times each.
std::vector<Complex> doo_sabin_spectrum(int k) {
  std::vector<Complex> out;
  for (int l = 0; l < k; ++l) {
    Complex sum = 0;
    for (int m = 0; m < k; ++m) {
      const long double alpha = (m == 0 ? 0.25L : 0.0L) + (3 + 2 * cos_2pi(m, k)) / (4 * k);
      sum += alpha * std::polar(1.0L, 2 * kPi * l * m / k);
    }
    out.push_back(sum);
  }
  for (int i = 0; i < k; ++i) out.insert(out.end(), {0.25L, 0.125L, 0.0625L});
  return out;
}

/// Zorin–Schröder–Sweldens' weights s_j of an edge point next to a vertex of valence k.
long double zss_weight(int j, int k) {
  if (k == 3) return j == 0 ? 5.0L / 12 : -1.0L / 12;
  if (k == 4) return j == 0 ? 3.0L / 8 : (j == 2 ? -1.0L / 8 : 0.0L);
  return (0.25L + cos_2pi(j, k) + 0.5L * cos_2pi(2 * j, k)) / k;
}

/// Butterfly, k ≠ 6: c stays, r'_j = ¾c + Σ_m s_m r_{j+m}: 1 and the DFT of s; beyond: p'_j = r_j
/// and q'_j = ⅛ q_j − 1/16 (p_j + p_{j+1}) + (ring terms): 0 and ⅛, k times each.
std::vector<Complex> butterfly_spectrum(int k) {
  std::vector<Complex> out{1};
  for (int l = 0; l < k; ++l) {
    long double sum = 0;
    for (int m = 0; m < k; ++m) sum += zss_weight(m, k) * cos_2pi(l * m, k);
    out.emplace_back(sum);
  }
  for (int i = 0; i < k; ++i) out.insert(out.end(), {0.0L, 0.125L});
  return out;
}

/// √3 over two steps (Kobbelt 2000): one step maps ring mode ℓ by (1 + ω^ℓ)/3 and turns the ring by
/// half a sector; two steps, renumbered, by |1 + ω^ℓ|²/9 = (2 + 2cos(2πℓ/n))/9. The centre and
/// mean ring: c¹ = (1 − α)c + α r̄, m̄ = (c + 2r̄)/3: 1 and 2/3 − α per step, squared.
std::vector<Complex> sqrt3_spectrum(int n) {
  const long double alpha = (4 - 2 * cos_2pi(1, n)) / 9;
  std::vector<Complex> out{1, (2.0L / 3 - alpha) * (2.0L / 3 - alpha)};
  for (int l = 1; l < n; ++l) out.emplace_back((2 + 2 * cos_2pi(l, n)) / 9);
  return out;
}

/// Butterfly at valence 6, the 10-point rule everywhere; sector (r_j, p_j, q_j):
/// r'_j = ½c + ½r_j + ⅛(r_{j±1}) − 1/16 (r_{j±2} + q_j + q_{j−1}), p'_j = r_j,
/// q'_j = ½(r_j + r_{j+1}) + ⅛(c + q_j) − 1/16 (r_{j−1} + r_{j+2} + p_j + p_{j+1}).
std::vector<Complex> regular_butterfly_spectrum() {
  using ComplexMatrix = Eigen::Matrix<Complex, Eigen::Dynamic, Eigen::Dynamic>;
  std::vector<Complex> out;
  ComplexMatrix zero(4, 4);  // c, r̄, p̄, q̄
  zero << 1, 0, 0, 0, 0.5L, 0.625L, 0, -0.125L, 0, 1, 0, 0, 0.125L, 0.875L, -0.125L, 0.125L;
  for (int l = 0; l < 6; ++l) {
    const Complex w = std::polar(1.0L, 2 * kPi * l / 6), one = 1;
    ComplexMatrix block(3, 3);
    block << 0.5L + 0.125L * (w + one / w) - 0.0625L * (w * w + one / (w * w)), 0,
        -0.0625L * (one + one / w),  //
        1, 0, 0,                     //
        0.5L * (one + w) - 0.0625L * (one / w + w * w), -0.0625L * (one + w), 0.125L;
    // ℓ = 0 is the 4 × 4 block with c (the means of each part of the sectors).
    const ComplexMatrix& m = l == 0 ? zero : block;
    const Eigen::ComplexEigenSolver<ComplexMatrix> solver(m, false);
    for (Eigen::Index i = 0; i < m.rows(); ++i) out.push_back(solver.eigenvalues()(i));
  }
  return out;
}

std::vector<Complex> expected_spectrum(MeshScheme scheme, int n) {
  switch (scheme) {
    case MeshScheme::catmull_clark:
      return catmull_clark_spectrum(n);
    case MeshScheme::loop:
      return loop_spectrum(n);
    case MeshScheme::doo_sabin:
      return doo_sabin_spectrum(n);
    case MeshScheme::butterfly:
      return butterfly_spectrum(n);
    case MeshScheme::sqrt3:
      return sqrt3_spectrum(n);
    case MeshScheme::bilinear:  // no local matrix: refused by local_matrix
      break;
  }
  return {};
}

/// |a − b| in units of 2^−53, exactly.
Rational distance_in_ulps(const Rational& exact, long double value) {
  const Rational d = Rational(static_cast<double>(value)) - exact;
  return (d < 0 ? Rational(-d) : d) * Rational(boost::multiprecision::cpp_int(1) << 53);
}

}  // namespace

TEST_CASE("local matrices: the rules equal the general refinement, every scheme and valence",
          "[subdivision][mesh_analysis]") {
  const auto compare = [](MeshScheme scheme, int n, const LocalOptions& o) {
    const LocalMatrix a = local_matrix(scheme, n, o);
    const LocalMatrix b = refined_local_matrix(scheme, n, o);
    INFO(scheme_name(scheme) << " valence " << n << (o.boundary ? " boundary" : ""));
    REQUIRE(a.values.rows() == b.values.rows());
    REQUIRE(a.labels == b.labels);
    REQUIRE(static_cast<Eigen::Index>(a.labels.size()) == a.values.rows());
    for (Eigen::Index i = 0; i < a.values.rows(); ++i)
      for (Eigen::Index j = 0; j < a.values.cols(); ++j) {
        INFO(a.labels[static_cast<std::size_t>(i)] << " on " << a.labels[static_cast<std::size_t>(j)]);
        if (a.exact) {
          // The refinement's doubles are the exact weight to one rounding per term it sums (at
          // most the neighbourhood's size); zero is zero.
          const Rational& w = (*a.exact)(static_cast<int>(i), static_cast<int>(j));
          if (w == 0)
            REQUIRE(b.values(i, j) == 0);
          else
            REQUIRE(distance_in_ulps(w, b.values(i, j)) <= a.values.rows());
        } else {
          REQUIRE(std::abs(a.values(i, j) - b.values(i, j)) < 1e-15L);
        }
      }
  };
  for (const MeshScheme scheme : kAllSchemes)
    for (int n = kMinValence; n <= kMaxValence; ++n) compare(scheme, n, {});
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop})
    for (int n = kMinBoundaryValence; n <= kMaxBoundaryValence; ++n)
      for (const BoundaryRule rule : {BoundaryRule::edge_only, BoundaryRule::edge_and_corner})
        compare(scheme, n, {.boundary = true, .rule = rule});
  // √3 on the boundary (one rule, Kobbelt's): two steps from an even level, the boundary kept then
  // trisected. The refinement reads nothing outside c's one-ring (refined_local_matrix refuses any
  // weight outside it): the one-ring is invariant.
  for (int n = kMinBoundaryValence; n <= kMaxBoundaryValence; ++n)
    compare(MeshScheme::sqrt3, n, {.boundary = true});
  // Butterfly on the boundary (mesh.cpp's rule: the 4-point curve, reflected wings inside).
  for (int n = kMinBoundaryValence; n <= kMaxBoundaryValence; ++n)
    compare(MeshScheme::butterfly, n, {.boundary = true});
}

TEST_CASE("local matrices are exact where the weights are rational, and affine",
          "[subdivision][mesh_analysis]") {
  const auto rational_cos = [](int n) { return n == 3 || n == 4 || n == 6; };
  for (const MeshScheme scheme : kAllSchemes)
    for (int n = kMinValence; n <= kMaxValence; ++n) {
      const LocalMatrix S = local_matrix(scheme, n);
      INFO(scheme_name(scheme) << " valence " << n);
      CHECK(S.exact.has_value() == (scheme == MeshScheme::catmull_clark || rational_cos(n)));
      if (S.exact)
        for (int i = 0; i < S.exact->rows; ++i) {
          Rational sum = 0;
          for (int j = 0; j < S.exact->cols; ++j) sum += (*S.exact)(i, j);
          CHECK(sum == 1);
        }
      else
        CHECK((S.values.rowwise().sum().array() - 1).abs().maxCoeff() < 1e-17L);
    }
  // Catmull–Clark at n = 5: the vertex rule (n − 2)/n + n·(1/n²)(¼) on c, 1/n² + 2·(1/n²)(¼) on r_j.
  const LocalMatrix cc = local_matrix(MeshScheme::catmull_clark, 5);
  CHECK((*cc.exact)(0, 0) == Rational(3, 5) + Rational(1, 20));
  CHECK((*cc.exact)(0, 1) == Rational(1, 25) + Rational(1, 50));
  CHECK((*cc.exact)(0, 2) == Rational(1, 100));
  // Loop at n = 3: β = 3/16.
  CHECK((*local_matrix(MeshScheme::loop, 3).exact)(0, 1) == Rational(3, 16));
}

TEST_CASE("local spectra equal the Fourier blocks of the rules", "[subdivision][mesh_analysis]") {
  for (const MeshScheme scheme : kAllSchemes)
    for (int n = kMinValence; n <= kMaxValence; ++n) {
      if (scheme == MeshScheme::butterfly && n == 6) continue;  // regular: the 10-point rule, below
      INFO(scheme_name(scheme) << " valence " << n);
      const LocalSpectrum s = local_spectrum(local_matrix(scheme, n));
      check_same_spectrum(s.eigenvalues, expected_spectrum(scheme, n), 1e-15L);
      CHECK(s.dominant_simple);
      CHECK(s.subdominant_pair);
      CHECK(s.gap);
      CHECK(std::abs(std::abs(s.mu) - fourth_modulus(expected_spectrum(scheme, n))) < 1e-15L);
      CHECK(s.residual < 1e-15L);
    }
}

TEST_CASE("Butterfly at valence 6: the regular 10-point scheme's spectrum", "[subdivision][mesh_analysis]") {
  const LocalSpectrum s = local_spectrum(local_matrix(MeshScheme::butterfly, 6));
  // ¼ is defective in the blocks too: their eigenvalues scatter by ~ε^{1/3} here.
  check_same_spectrum(s.eigenvalues, regular_butterfly_spectrum(), 1e-6L);
  CHECK(s.dominant_simple);
  CHECK(s.subdominant_pair);
  CHECK(s.gap);
  CHECK(std::abs(s.mu - 0.25L) < 1e-15L);
  CHECK(s.curvature == "bounded");
}

TEST_CASE("subdominant eigenvalues: the closed forms", "[subdivision][mesh_analysis]") {
  for (int n = kMinValence; n <= kMaxValence; ++n) {
    INFO("valence " << n);
    CHECK(std::abs(local_spectrum(local_matrix(MeshScheme::loop, n)).subdominant -
                   (3.0L / 8 + cos_2pi(1, n) / 4)) < 1e-17L);
    // The closed form is the larger root of the ℓ = 1 block: (5 + c ± √((5 + c)² − 16))/16 with
    // (5 + c)² − 16 = (1 + c)(9 + c) = 2cos²(π/n)(9 + c).
    const long double T = 5.0L / 8 + cos_2pi(1, n) / 8;
    CHECK(std::abs(catmull_clark_lambda1(n) - (T + std::sqrt(T * T - 0.25L)) / 2) < 1e-17L);
    CHECK(std::abs(local_spectrum(local_matrix(MeshScheme::catmull_clark, n)).subdominant -
                   catmull_clark_lambda1(n)) < 1e-17L);
    CHECK(local_spectrum(local_matrix(MeshScheme::doo_sabin, n)).subdominant == Approx(0.5).epsilon(1e-15));
    CHECK(local_spectrum(local_matrix(MeshScheme::butterfly, n)).subdominant == Approx(0.5).epsilon(1e-15));
    CHECK(std::abs(local_spectrum(local_matrix(MeshScheme::sqrt3, n)).subdominant -
                   4 * std::pow(std::cos(kPi / n), 2) / 9) < 1e-17L);
  }
  CHECK(catmull_clark_lambda1(4) == Approx(0.5).epsilon(1e-15));
  CHECK(catmull_clark_lambda1(3) == Approx((4.5 + 0.5 * std::sqrt(17.0)) / 16).epsilon(1e-15));
}

TEST_CASE("curvature: λ1²/|μ| as the literature has it", "[subdivision][mesh_analysis]") {
  for (int n = kMinValence; n <= kMaxValence; ++n) {
    INFO("valence " << n);
    // Catmull–Clark: μ = ¼ from n = 4 on (ℓ = 0 and ℓ = 2 blocks), λ1² < ¼ for n ≥ 5.
    const LocalSpectrum cc = local_spectrum(local_matrix(MeshScheme::catmull_clark, n));
    CHECK(cc.curvature == (n == 3 ? "zero" : n == 4 ? "bounded" : "unbounded"));
    // Loop: μ = max(λ1² (ℓ = 0, by β's design), 3/8 + ¼cos(4π/n) (ℓ = 2)); the second wins for n ≥ 7.
    const LocalSpectrum loop = local_spectrum(local_matrix(MeshScheme::loop, n));
    const long double l1 = 3.0L / 8 + cos_2pi(1, n) / 4;
    const long double mu = n == 3 ? l1 * l1 : std::max(l1 * l1, 3.0L / 8 + cos_2pi(2, n) / 4);
    CHECK(std::abs(*loop.curvature_ratio - l1 * l1 / mu) < 1e-15L);
    CHECK(loop.curvature == (n <= 6 ? "bounded" : "unbounded"));
    // Doo–Sabin ½² = ¼, Butterfly (ZSS) ½² = ¼, √3 (Kobbelt: 2/3 − α = λ1) λ1² = (2/3 − α)²: bounded.
    for (const MeshScheme scheme : {MeshScheme::doo_sabin, MeshScheme::butterfly, MeshScheme::sqrt3}) {
      if (scheme == MeshScheme::butterfly && n == 6) continue;
      INFO(scheme_name(scheme));
      const LocalSpectrum s = local_spectrum(local_matrix(scheme, n));
      if (scheme == MeshScheme::sqrt3 && n >= 7)  // ℓ = 2: (2 + 2cos(4π/n))/9 > λ1² from n = 7 on
        CHECK(s.curvature == "unbounded");
      else
        CHECK(s.curvature == "bounded");
    }
  }
}

TEST_CASE("eigenvectors: the subdominant eigenspace and the limit stencil", "[subdivision][mesh_analysis]") {
  for (int n = kMinValence; n <= kMaxValence; ++n) {
    const LocalMatrix S = local_matrix(MeshScheme::loop, n);
    const LocalSpectrum s = local_spectrum(S);
    // Loop's limit position: c weighs 1 − nχ, each neighbour χ = 1/(3/(8β) + n).
    const long double a = 3.0L / 8 + cos_2pi(1, n) / 4, beta = (5.0L / 8 - a * a) / n;
    const long double chi = 1 / (3 / (8 * beta) + n);
    CHECK(std::abs(s.limit_stencil(0) - (1 - n * chi)) < 1e-16L);
    for (int j = 1; j <= n; ++j) CHECK(std::abs(s.limit_stencil(j) - chi) < 1e-16L);
    // The subdominant eigenvectors are the ring's cos and sin modes (c weighs 0).
    REQUIRE(s.subdominant_basis.cols() == 2);
    CHECK((S.values * s.subdominant_basis - s.subdominant * s.subdominant_basis).cwiseAbs().maxCoeff() <
          1e-17L);
    CHECK(s.subdominant_basis.row(0).cwiseAbs().maxCoeff() < 1e-17L);
    LongVector cosine(n + 1);
    cosine(0) = 0;
    for (int j = 0; j < n; ++j) cosine(1 + j) = cos_2pi(j, n);
    const LongVector projected = s.subdominant_basis * (s.subdominant_basis.transpose() * cosine);
    CHECK((projected - cosine).cwiseAbs().maxCoeff() < 1e-16L);
  }
}

TEST_CASE("boundary vertices: the boundary curve's block and the interior ring",
          "[subdivision][mesh_analysis]") {
  for (int n = kMinBoundaryValence; n <= kMaxBoundaryValence; ++n) {
    INFO("boundary valence " << n);
    // Loop: c, r_0, r_{n−1} follow the cubic B-spline curve ((1, 6, 1)/8, midpoints): 1, ½, ¼; the
    // interior ring r_1 … r_{n−2} is tridiagonal (3/8; 1/8): 3/8 + ¼cos(πm/(n − 1)).
    std::vector<Complex> expected{1, 0.5L, 0.25L};
    for (int m = 1; m <= n - 2; ++m) expected.emplace_back(3.0L / 8 + std::cos(kPi * m / (n - 1)) / 4);
    const LocalSpectrum loop = local_spectrum(local_matrix(MeshScheme::loop, n, {.boundary = true}));
    check_same_spectrum(loop.eigenvalues, expected, 1e-15L);
    CHECK(loop.subdominant_pair == (n == 4));  // equal pair only at the regular boundary valence
    // With the corner rule at valence 2 the vertex stays: 1, ½, ½.
    if (n == 2)
      check_same_spectrum(
          local_spectrum(
              local_matrix(MeshScheme::loop, 2, {.boundary = true, .rule = BoundaryRule::edge_and_corner}))
              .eigenvalues,
          {1, 0.5L, 0.5L}, 1e-15L);
    // Catmull–Clark: the same curve block.
    const LocalSpectrum cc = local_spectrum(local_matrix(MeshScheme::catmull_clark, n, {.boundary = true}));
    for (const long double e : {1.0L, 0.5L, 0.25L})
      CHECK(std::any_of(cc.eigenvalues.begin(), cc.eigenvalues.end(),
                        [&](const Complex& z) { return std::abs(z - e) < 1e-15L; }));
  }
}

TEST_CASE("√3 boundary vertices: the ternary cubic B-spline's block and the interior ring, exactly",
          "[subdivision][mesh_analysis]") {
  // Kobbelt 2000 §5, two steps from an even level (keep the boundary, then trisect it), derived by
  // hand: c' = (4r_0 + 19c + 4r_{n−1})/27 and r'_0 = (16c + 10r_0 + r_{n−1})/27 (the trisection point
  // next to c; r'_{n−1} its mirror) read the boundary only: the ternary cubic B-spline's block, 1, ⅓,
  // 1/9. Inside, r'_j is the centroid of (c, m_{j−1}, m_j), m_j = (c + r_j + r_{j+1})/3 the level-1
  // centroids: (5c + r_{j−1} + 2r_j + r_{j+1})/9; on r_1 … r_{n−2} (k = n − 1 faces) the tridiagonal
  // (1, 2, 1)/9: (2 + 2cos(πm/k))/9, m = 1 … k − 1.
  using cifs_test::q;
  for (int n = kMinBoundaryValence; n <= kMaxBoundaryValence; ++n) {
    const int k = n - 1;
    INFO("boundary valence " << n << " (" << k << " faces)");
    const LocalMatrix S = local_matrix(MeshScheme::sqrt3, n, {.boundary = true});
    REQUIRE(S.exact);  // every weight is rational on the boundary
    REQUIRE(S.steps == 2);
    const RationalMatrix& E = *S.exact;
    const auto expect_row = [&](int row, const std::vector<std::pair<int, Rational>>& weights) {
      for (int j = 0; j <= n; ++j) {
        Rational w = 0;
        for (const auto& [column, value] : weights)
          if (column == j) w += value;
        INFO("row " << row << ", column " << j);
        CHECK(E(row, j) == w);
      }
    };
    expect_row(0, {{0, q(19, 27)}, {1, q(4, 27)}, {n, q(4, 27)}});
    expect_row(1, {{0, q(16, 27)}, {1, q(10, 27)}, {n, q(1, 27)}});
    expect_row(n, {{0, q(16, 27)}, {n, q(10, 27)}, {1, q(1, 27)}});
    for (int j = 1; j + 1 < n; ++j)
      expect_row(1 + j, {{0, q(5, 9)}, {j, q(1, 9)}, {1 + j, q(2, 9)}, {2 + j, q(1, 9)}});
    std::vector<Complex> expected{1, 1.0L / 3, 1.0L / 9};
    for (int m = 1; m < k; ++m) expected.emplace_back((2 + 2 * std::cos(kPi * m / k)) / 9);
    const LocalSpectrum spectrum = local_spectrum(S);
    check_same_spectrum(spectrum.eigenvalues, expected, 1e-15L);
    // The limit position is the boundary curve's (r_0 + 4c + r_{n−1})/6.
    for (Eigen::Index i = 0; i <= n; ++i)
      CHECK(std::abs(spectrum.limit_stencil(i) - (i == 0             ? 4.0L / 6
                                                  : i == 1 || i == n ? 1.0L / 6
                                                                     : 0)) < 1e-16L);
    // Exactly: 1, ⅓ and 1/9 are eigenvalues at every k. ⅓ is double where the inside's mode m = k/3
    // is ⅓ too (k = 3, 6, 9 …). An odd m is symmetric about the sector's middle: two eigenvectors
    // (k = 3, the regular boundary: the curve's tangent and the inside's). An even m is antisymmetric
    // and feeds the curve's antisymmetric tangent mode (r'_1 and r'_{k−1} read r_0 and r_k with the
    // same weight, so their difference reads r_0 − r_k): one eigenvector, a Jordan block (k = 6, 12).
    const int N = n + 1;
    for (const Rational& lambda : {q(1), q(1, 3), q(1, 9)})
      CHECK(exact_rank(shifted_power(E, lambda, 1)) < N);
    const int third = N - exact_rank(shifted_power(E, q(1, 3), 1));
    const int third_squared = N - exact_rank(shifted_power(E, q(1, 3), 2));
    const bool tie = k % 3 == 0, jordan = tie && (k / 3) % 2 == 0;
    CHECK(third == (tie && !jordan ? 2 : 1));
    CHECK(third_squared == (tie ? 2 : 1));
  }
}

TEST_CASE("local matrices: bad valences are one-line InvalidInputs", "[subdivision][mesh_analysis]") {
  CHECK_THROWS_WITH(local_matrix(MeshScheme::loop, 2),
                    Contains("loop: valence 2 is out of range; expected 3 to 16"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::catmull_clark, 17), Contains("valence 17 is out of range"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::loop, 17, {.boundary = true}),
                    Contains("boundary valence 17 is out of range; expected 2 to 16"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::doo_sabin, 4, {.boundary = true}),
                    Contains("doo-sabin: boundary vertices make no face; a face touching the boundary is "
                             "analysed from which of its corners are interior"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::doo_sabin, 4, {.boundary = true, .interior_corners = {1, 0, 0}}),
                    Contains("doo-sabin: a face of 4 corners touching the boundary needs 4 interior-corner "
                             "flags; 3 given"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::loop, 4, {.interior_corners = {1, 0, 0, 0}}),
                    Contains("loop: interior corners are said of a doo-sabin face touching the boundary"));
  CHECK_THROWS_WITH(
      refined_local_matrix(MeshScheme::doo_sabin, 4, {.boundary = true, .interior_corners = {1, 0, 0, 0}}),
      Contains("doo-sabin: boundary vertices make no face"));
  CHECK_THROWS_WITH(
      local_matrix(MeshScheme::butterfly, 2, {.boundary = true, .rule = BoundaryRule::edge_and_corner}),
      Contains("butterfly: the boundary has one rule under this scheme (the 4-point curve)"));
  CHECK_THROWS_WITH(
      local_matrix(MeshScheme::sqrt3, 2, {.boundary = true, .rule = BoundaryRule::edge_and_corner}),
      Contains("sqrt3: the boundary has one rule under this scheme"));
  CHECK_THROWS_WITH(local_matrix(MeshScheme::sqrt3, 17, {.boundary = true}),
                    Contains("boundary valence 17 is out of range; expected 2 to 16"));
  CHECK_THROWS_AS(refined_local_matrix(MeshScheme::doo_sabin, 1), InvalidInput);
}

// ------------------------------------------------------------------------------------------------
// C¹ at extraordinary vertices (Reif): the characteristic map's Jacobian and winding.

TEST_CASE("C1 verdicts: every scheme is C1 at every interior valence, proved where it is polynomial",
          "[subdivision][mesh_analysis][c1]") {
  for (const MeshScheme scheme : kAllSchemes) {
    const bool polynomial =
        scheme == MeshScheme::catmull_clark || scheme == MeshScheme::loop || scheme == MeshScheme::doo_sabin;
    for (int n = kMinValence; n <= kMaxValence; ++n) {
      if (!polynomial && n > 8 && n % 4 != 0) continue;  // the sampled route is slower: 3 … 8, 12, 16
      INFO(scheme_name(scheme) << " valence " << n);
      const LocalMatrix S = local_matrix(scheme, n);
      const C1Verdict v = c1_verdict(S, local_spectrum(S));
      CHECK(v.spectral);
      CHECK(v.method == (polynomial ? "bernstein" : "sampled"));
      CHECK(v.decided);
      CHECK(v.regular);
      CHECK(v.winding == 1);
      CHECK(v.c1);
      CHECK(v.margin > 0);
      // At the regular valence the characteristic map is linear: a constant Jacobian.
      const int regular = scheme == MeshScheme::catmull_clark || scheme == MeshScheme::doo_sabin ? 4 : 6;
      if (n == regular) CHECK(std::abs(v.margin - 1) < 1e-9L);
      if (n != regular) CHECK(v.margin < 1 - 1e-6L);
    }
  }
}

TEST_CASE("C1 verdicts: the sampled net agrees with the Bernstein proof",
          "[subdivision][mesh_analysis][c1]") {
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop, MeshScheme::doo_sabin})
    for (const int n : {3, 5, 9}) {
      INFO(scheme_name(scheme) << " valence " << n);
      const LocalMatrix S = local_matrix(scheme, n);
      const C1Verdict v = c1_verdict(S, local_spectrum(S), {.sampled = true, .levels = 3});
      CHECK(v.method == "sampled");
      CHECK(v.levels == 3);
      CHECK(v.c1);
    }
}

namespace {

/// The kernel of S − λ, two columns.
LongMatrix eigen_pair(const LocalMatrix& S, long double lambda) {
  const LongMatrix A = S.values - lambda * LongMatrix::Identity(S.values.rows(), S.values.cols());
  const Eigen::JacobiSVD<LongMatrix> svd(A, Eigen::ComputeFullV);
  REQUIRE(svd.singularValues()(svd.singularValues().size() - 2) < 1e-15L);
  return svd.matrixV().rightCols(2);
}

}  // namespace

TEST_CASE("C1 verdicts: broken rules come out not C1", "[subdivision][mesh_analysis][c1]") {
  for (int n = 3; n <= 8; ++n) {
    INFO("valence " << n);
    // Loop with β = 0 (the vertex stays): the ring's mean is an eigenvector of 5/8, above the
    // Fourier pair 3/8 + ¼cos(2π/n): a single subdominant eigenvalue, no tangent plane.
    LocalMatrix loop = local_matrix(MeshScheme::loop, n);
    loop.exact.reset();
    loop.values.row(0).setZero();
    loop.values(0, 0) = 1;
    const LocalSpectrum s = local_spectrum(loop);
    CHECK(std::abs(s.subdominant - 0.625L) < 1e-15L);
    const C1Verdict v = c1_verdict(loop, s);
    CHECK_FALSE(v.spectral);
    CHECK_FALSE(v.c1);
    CHECK_THAT(v.reason, Contains("not a real double eigenvalue"));
  }
  // Catmull–Clark with the vertex kept at 9/10 of itself (rest of the rule scaled): at n = 3 the
  // mean mode's eigenvalue passes the Fourier pair (λ1 = 0.41): not C1. The vertex rule acts on
  // the mean mode only, so at n = 7 (λ1 = 0.60 stays above it) the scheme stays C1.
  for (const int n : {3, 7}) {
    LocalMatrix cc = local_matrix(MeshScheme::catmull_clark, n);
    cc.exact.reset();
    cc.values.row(0).tail(2 * n) *= 0.1L / (1 - cc.values(0, 0));
    cc.values(0, 0) = 0.9L;
    const C1Verdict v = c1_verdict(cc, local_spectrum(cc));
    CHECK(v.c1 == (n == 7));
  }
}

TEST_CASE("C1 verdicts: a rule that passes every spectral test but winds three times",
          "[subdivision][mesh_analysis][c1]") {
  // Loop at n = 7 with each ring vertex averaged with its second neighbours instead of its first:
  // Fourier mode k has 3/8 + ¼cos(4πk/7), largest at k = 3 (0.53, double, above the mean mode's
  // 0.28 and mode 1's 0.32) — λ0 simple, λ1 = λ2 real, a gap — yet the characteristic map runs 3
  // times round the centre.
  const int n = 7;
  LocalMatrix S = local_matrix(MeshScheme::loop, n);
  S.exact.reset();
  for (int j = 0; j < n; ++j) {
    S.values.row(1 + j).setZero();
    S.values(1 + j, 0) = 0.375L;
    S.values(1 + j, 1 + j) = 0.375L;
    S.values(1 + j, 1 + (j + 2) % n) += 0.125L;
    S.values(1 + j, 1 + (j + n - 2) % n) += 0.125L;
  }
  const LocalSpectrum s = local_spectrum(S);
  REQUIRE(s.dominant_simple);
  REQUIRE(s.subdominant_pair);
  REQUIRE(s.gap);
  CHECK(std::abs(s.subdominant - (0.375L + cos_2pi(6, 7) / 4)) < 1e-15L);  // cos(4π·3/7)
  for (const bool sampled : {false, true}) {
    const C1Verdict v = c1_verdict(S, s, {.sampled = sampled});
    CHECK(v.regular);
    CHECK(std::abs(v.winding) == 3);
    CHECK_FALSE(v.c1);
    CHECK_THAT(v.reason, Contains("winds 3 times"));
  }
}

TEST_CASE("characteristic maps: orientation does not matter, a higher Fourier pair winds more",
          "[subdivision][mesh_analysis][c1]") {
  for (const MeshScheme scheme : {MeshScheme::loop, MeshScheme::catmull_clark}) {
    const int n = 7;
    INFO(scheme_name(scheme));
    const LocalMatrix S = local_matrix(scheme, n);
    const LocalSpectrum s = local_spectrum(S);
    LongMatrix mirrored = s.subdominant_basis;
    mirrored.col(1) *= -1;
    const C1Verdict m = characteristic_map_verdict(scheme, n, s.subdominant, mirrored);
    CHECK(m.c1);
    CHECK(m.winding == 1);
    // Loop's Fourier mode 2: 3/8 + ¼cos(4π/7), a double eigenvalue whose map is like z².
    if (scheme == MeshScheme::loop) {
      const long double lambda = 0.375L + cos_2pi(2, 7) / 4;
      const C1Verdict z2 = characteristic_map_verdict(scheme, n, lambda, eigen_pair(S, lambda));
      CHECK(z2.regular);
      CHECK(std::abs(z2.winding) == 2);
      CHECK_FALSE(z2.c1);
    }
  }
  // A boundary vertex is answered per sector (tests/subdivision/test_mesh_classes.cpp).
  CHECK(c1_verdict(local_matrix(MeshScheme::loop, 4, {.boundary = true}),
                   local_spectrum(local_matrix(MeshScheme::loop, 4, {.boundary = true})))
            .sectors.size() == 1);
  CHECK_THROWS_WITH(characteristic_map_verdict(MeshScheme::loop, 5, 0.5L, LongMatrix::Zero(3, 2)),
                    Contains("expected 6 by 2 eigenvectors"));
}
