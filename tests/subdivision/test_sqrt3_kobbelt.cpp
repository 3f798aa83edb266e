// SPDX-License-Identifier: MIT
// √3 at an interior vertex against Kobbelt 2000 ("√3-Subdivision", SIGGRAPH): the relaxation weight
// α_n = (4 − 2cos(2π/n))/9, the one-step matrix's eigenvalues 1, 2/3 − α_n and (1 + ω^ℓ)/3 (complex:
// a step turns the ring by half a sector), the two-step matrix's (2 + 2cos(2πℓ/n))/9 and (2/3 − α_n)²;
// exact multiplicities where the weights are rational; and each Fourier mode's rate through the
// production refiner: the tilt of the face normals at the vertex shrinks by exactly ev_ℓ/λ1 every two
// steps, so generic normals converge at |μ|/λ1 — to the limit normal cifs computes.
#include "cifs/subdivision/mesh_analysis.hpp"
#include "subdivision/meshes.hpp"
#include "subdivision/rational.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <numbers>
#include <vector>

#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using cifs_test::exact_rank;
using cifs_test::q;
using cifs_test::shifted_power;

namespace {

constexpr long double kPi = std::numbers::pi_v<long double>;

long double cos_2pi(long double m, long double n) {
  return std::cos(2 * kPi * m / n);
}

/// Kobbelt's α_n.
long double kobbelt_alpha(int n) {
  return (4 - 2 * cos_2pi(1, n)) / 9;
}

/// The two-step eigenvalue of ring mode ℓ (ℓ = 0: the centre with the mean ring, (2/3 − α_n)²).
long double two_step_eigenvalue(int n, int l) {
  if (l % n == 0) return (2.0L / 3 - kobbelt_alpha(n)) * (2.0L / 3 - kobbelt_alpha(n));
  return (2 + 2 * cos_2pi(l, n)) / 9;
}

template <class T>
using Rows = std::vector<std::vector<T>>;

/// One step as the paper states it, on c, r_0 … r_{n−1}: c¹ = (1 − α)c + (α/n)Σ r_j and the centroid
/// (c + r_j + r_{j+1})/3 of face j in place of r_j.
template <class T>
Rows<T> one_step(int n, const T& alpha) {
  const auto N = static_cast<std::size_t>(n) + 1;
  Rows<T> A(N, std::vector<T>(N, T(0)));
  A[0][0] = T(1) - alpha;
  for (std::size_t j = 0; j + 1 < N; ++j) {
    A[0][1 + j] = alpha / T(n);
    A[1 + j][0] = T(1) / 3;
    A[1 + j][1 + j] = T(1) / 3;
    A[1 + j][1 + (j + 1) % (N - 1)] = T(1) / 3;
  }
  return A;
}

/// The paper's one step twice, the ring renumbered: the second step's centroid of (c¹, m_{j−1}, m_j)
/// lies in the direction of r_j (the one-step ring is turned by half a sector, twice).
template <class T>
Rows<T> two_steps(int n, const T& alpha) {
  const Rows<T> A = one_step<T>(n, alpha);
  const std::size_t N = A.size();
  Rows<T> AA(N, std::vector<T>(N, T(0)));
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t m = 0; m < N; ++m)
      for (std::size_t j = 0; j < N; ++j) AA[i][j] += A[i][m] * A[m][j];
  Rows<T> out = AA;
  for (std::size_t j = 0; j + 1 < N; ++j) out[1 + j] = AA[1 + (j + N - 2) % (N - 1)];
  return out;
}

}  // namespace

TEST_CASE("√3 (Kobbelt 2000): the local matrix is the paper's step twice, turned back by a sector",
          "[subdivision][mesh_analysis][sqrt3]") {
  for (int n = kMinValence; n <= kMaxValence; ++n) {
    INFO("valence " << n);
    const LocalMatrix S = local_matrix(MeshScheme::sqrt3, n);
    REQUIRE(S.steps == 2);
    const Rational* c = nullptr;
    const Rational exact_cos[] = {q(-1, 2), q(0), q(1, 2)};  // n = 3, 4, 6 (Niven)
    if (n == 3 || n == 4 || n == 6) c = &exact_cos[n == 3 ? 0 : n == 4 ? 1 : 2];
    REQUIRE(S.exact.has_value() == (c != nullptr));
    const auto at = [](int i) { return static_cast<std::size_t>(i); };
    if (c) {
      const Rows<Rational> P = two_steps<Rational>(n, (4 - 2 * *c) / 9);
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) CHECK((*S.exact)(i, j) == P[at(i)][at(j)]);
    } else {
      const Rows<long double> P = two_steps<long double>(n, kobbelt_alpha(n));
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) CHECK(std::abs(S.values(i, j) - P[at(i)][at(j)]) < 1e-18L);
    }
    // One step: 1, 2/3 − α_n and (1 + ω^ℓ)/3, ℓ = 1 … n − 1 — complex, of modulus √((2 + 2cos(2πℓ/n))/9).
    const Rows<long double> A = one_step<long double>(n, kobbelt_alpha(n));
    LongMatrix one_matrix(n + 1, n + 1);
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) one_matrix(i, j) = A[at(i)][at(j)];
    const Eigen::EigenSolver<LongMatrix> one(one_matrix, false);
    std::vector<std::complex<long double>> expected{1, 2.0L / 3 - kobbelt_alpha(n)};
    for (int l = 1; l < n; ++l) expected.push_back((1.0L + std::polar(1.0L, 2 * kPi * l / n)) / 3.0L);
    std::vector<bool> used(expected.size(), false);
    for (Eigen::Index i = 0; i <= n; ++i) {
      const std::complex<long double> z = one.eigenvalues()(i);
      std::size_t best = expected.size();
      for (std::size_t e = 0; e < expected.size(); ++e)
        if (!used[e] && (best == expected.size() || std::abs(z - expected[e]) < std::abs(z - expected[best])))
          best = e;
      REQUIRE(std::abs(z - expected[best]) < 1e-15L);
      used[best] = true;
    }
    // α_n makes the centre's one-step eigenvalue the square of the ring's first modulus:
    // 2/3 − α_n = |(1 + ω)/3|², so over two steps the centre gives λ1² (bounded curvature, n ≤ 6).
    CHECK(std::abs(2.0L / 3 - kobbelt_alpha(n) - std::norm((1.0L + std::polar(1.0L, 2 * kPi / n)) / 3.0L)) <
          1e-18L);
  }
}

TEST_CASE("√3 (Kobbelt 2000): λ1, μ and λ1²/|μ| in closed form, relative 1e-15 up to valence 16",
          "[subdivision][mesh_analysis][sqrt3]") {
  for (int n = kMinValence; n <= kMaxValence; ++n) {
    INFO("valence " << n);
    const LocalSpectrum s = local_spectrum(local_matrix(MeshScheme::sqrt3, n));
    const long double lambda1 = two_step_eigenvalue(n, 1);
    // μ: the centre's λ1² up to n = 6 (at n = 3 mode 2 is mode −1, λ1 itself), mode 2 from n = 7 on.
    const long double mu =
        n == 3 ? two_step_eigenvalue(n, 0) : std::max(two_step_eigenvalue(n, 0), two_step_eigenvalue(n, 2));
    CHECK(std::abs(s.subdominant / lambda1 - 1) < 1e-15L);
    CHECK(std::abs(s.second / lambda1 - 1) < 1e-15L);
    CHECK(std::abs(std::abs(s.mu) / mu - 1) < 1e-14L);
    CHECK(std::abs(*s.curvature_ratio / (lambda1 * lambda1 / mu) - 1) < 1e-14L);
    CHECK(s.subdominant_pair);
    CHECK(s.gap);
  }
}

TEST_CASE("√3 (Kobbelt 2000): exact eigenvalues and multiplicities at valences 3, 4 and 6",
          "[subdivision][mesh_analysis][sqrt3]") {
  // Two steps: 1; λ1 = (2 + 2cos(2π/n))/9 twice; the centre (2/3 − α_n)² = λ1²; the other modes.
  // rank((S − λ)^m) = N − m proves the algebraic multiplicity m, rank(S − λ) = N − m that every copy
  // has its own eigenvector (no Jordan block: the pair ⅓ at n = 6 is a true double eigenvalue).
  const std::map<int, std::map<Rational, int>> claimed{
      {3, {{q(1), 1}, {q(1, 9), 2}, {q(1, 81), 1}}},
      {4, {{q(1), 1}, {q(2, 9), 2}, {q(4, 81), 1}, {q(0), 1}}},
      {6, {{q(1), 1}, {q(1, 3), 2}, {q(1, 9), 3}, {q(0), 1}}}};
  for (const auto& [n, values] : claimed) {
    const LocalMatrix S = local_matrix(MeshScheme::sqrt3, n);
    REQUIRE(S.exact);
    int total = 0;
    for (const auto& [lambda, m] : values) {
      INFO("valence " << n << ", eigenvalue " << to_string(lambda) << " × " << m);
      total += m;
      CHECK(exact_rank(shifted_power(*S.exact, lambda, m)) == n + 1 - m);
      CHECK(exact_rank(shifted_power(*S.exact, lambda, 1)) == n + 1 - m);
    }
    CHECK(total == n + 1);
  }
}

namespace {

/// The largest tan(angle) between the normal of a face at vertex 0 and `normal`.
double largest_tilt(const Mesh& m, const Eigen::Vector3d& normal) {
  double out = 0;
  for (std::size_t f = 0; f < face_count(m); ++f) {
    const auto c = face(m, f);
    if (std::find(c.begin(), c.end(), 0) == c.end()) continue;
    const Eigen::Vector3d a = m.vertices.row(c[0]).transpose(), b = m.vertices.row(c[1]).transpose(),
                          d = m.vertices.row(c[2]).transpose();
    const Eigen::Vector3d n = (b - a).cross(d - a);
    out = std::max(out, n.cross(normal).norm() / std::abs(n.dot(normal)));
  }
  return out;
}

}  // namespace

TEST_CASE("√3 by deep refinement: each Fourier mode tilts the normals at its own rate, the slowest at |μ|/λ1",
          "[subdivision][mesh_analysis][sqrt3]") {
  // The production refiner on a disc around a vertex of valence n (its one-ring invariant over two
  // steps, whatever lies outside): c and the ring r_j = (cos θ_j, sin θ_j) flat, heights the mode's
  // eigenvector — ring mode ℓ: cos(ℓθ_j), c at 0; the centre (ℓ = 0): c at 1, the ring at
  // −1/(3α_n) (c¹ = (1 − α)c + α r̄ and r̄¹ = (c + 2r̄)/3 map it to 2/3 − α_n times itself). The
  // ring's plane positions shrink by λ1 every two steps and the heights by ev_ℓ, so the tangent of
  // every face normal's tilt shrinks by exactly ev_ℓ/λ1: 1 for ℓ = ±1 (the tangent plane itself).
  const Eigen::Vector3d up(0, 0, 1);
  for (int n = kMinValence; n <= kMaxValence; ++n) {
    const long double lambda1 = two_step_eigenvalue(n, 1);
    for (int l = 0; l <= n / 2; ++l) {
      INFO("valence " << n << ", mode " << l);
      Mesh m = cifs_test::fan(n);
      const double alpha = static_cast<double>(kobbelt_alpha(n));
      m.vertices.row(0) << 0, 0, l == 0 ? 1 : 0;
      for (int j = 0; j < n; ++j) {
        const double theta = 2 * std::numbers::pi * j / n;
        m.vertices.row(1 + j) << std::cos(theta), std::sin(theta),
            l == 0 ? -1 / (3 * alpha) : std::cos(l * theta);
      }
      const double ratio = static_cast<double>(two_step_eigenvalue(n, l) / lambda1);
      double before = largest_tilt(m, up);
      for (int level = 2; level <= 4; level += 2) {
        const double tilt = largest_tilt(sqrt3(m, level), up);
        if (ratio < 1e-15)  // mode n/2 of an even valence: (2 + 2cos π)/9 = 0
          CHECK(tilt < 1e-12);
        else
          CHECK(tilt / before == Approx(ratio).epsilon(1e-10));
        before = tilt;
      }
    }
  }
}

TEST_CASE("√3 by deep refinement: generic normals converge to cifs's limit normal within (|μ|/λ1)^k",
          "[subdivision][mesh_analysis][sqrt3][limit]") {
  for (const int n : {3, 5, 8}) {
    INFO("valence " << n);
    Mesh m = cifs_test::fan(n);
    // Heights with every Fourier mode (the fan's own are one mode, 3θ).
    for (int i = 0; i <= n; ++i) m.vertices(i, 2) = 0.2 * std::sin(1.7 * i * i + 0.3);
    const Mesh limit = limit_mesh(m, MeshScheme::sqrt3, 0, {.normals = true});
    const Eigen::Vector3d normal = limit.normals.row(0).transpose();
    const LocalSpectrum s = local_spectrum(local_matrix(MeshScheme::sqrt3, n));
    const double rate = static_cast<double>(std::abs(s.mu) / s.subdominant);
    const double first = largest_tilt(m, normal);
    double bound = first;
    for (int level = 2; level <= 6; level += 2) {
      bound *= rate;
      const double tilt = largest_tilt(sqrt3(m, level), normal);
      CHECK(tilt <= 2 * bound);
      CHECK(tilt > 1e-3 * bound);  // not faster than the spectrum allows either: generic data
    }
  }
}
