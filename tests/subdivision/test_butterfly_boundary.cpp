// SPDX-License-Identifier: MIT
// Butterfly at boundary vertices under mesh.cpp's rule (the 4-point curve on the boundary, the 10-point
// stencil inside with a wing missing at the boundary reflected; boundary ends count as regular): the
// local subdivision matrix in exact rationals (route (b), the production refiner, is compared with it
// in test_mesh_analysis.cpp), its Jordan structure and the C1 verdict per number of faces.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cifs/subdivision/mesh_analysis.hpp"
#include "subdivision/rational.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using Catch::Matchers::Contains;
using cifs_test::exact_rank;
using cifs_test::q;
using cifs_test::shifted_power;

namespace {

/// The index of a label ("r0", "p3", …) in a local matrix's numbering.
int at(const LocalMatrix& S, const std::string& label) {
  for (std::size_t i = 0; i < S.labels.size(); ++i)
    if (S.labels[i] == label) return static_cast<int>(i);
  FAIL("no label " << label);
  return -1;
}

}  // namespace

TEST_CASE("butterfly boundary vertices: the 4-point curve's tangent and the Jordan blocks, exactly",
          "[subdivision][mesh_analysis][butterfly]") {
  for (int k = 1; k <= 8; ++k) {
    INFO(k << " faces");
    const LocalMatrix S = local_matrix(MeshScheme::butterfly, k + 1, {.boundary = true});
    REQUIRE(S.exact);  // every weight is rational on the boundary
    const RationalMatrix& E = *S.exact;
    const int N = E.rows;
    REQUIRE(N == 3 * (k + 1));  // c, r_j and p_j for k + 1 edges, q_j for k faces
    for (int i = 0; i < N; ++i) {
      Rational sum(0);
      for (int j = 0; j < N; ++j) sum += E(i, j);
      CHECK(sum == 1);
    }
    // The boundary curve is the 4-point curve (c, r_0, p_0 one way, r_k, p_k the other), whatever k:
    // its tangent 8(r_0 − r_k) − (p_0 − p_k) (the derivative mask (1, −8, 0, 8, −1)) is a left
    // eigenvector of ½ of the whole matrix.
    std::vector<Rational> tangent(static_cast<std::size_t>(N), Rational(0));
    const std::string last = std::to_string(k);
    tangent[static_cast<std::size_t>(at(S, "r0"))] = 8;
    tangent[static_cast<std::size_t>(at(S, "r" + last))] = -8;
    tangent[static_cast<std::size_t>(at(S, "p0"))] = -1;
    tangent[static_cast<std::size_t>(at(S, "p" + last))] = 1;
    for (int j = 0; j < N; ++j) {
      Rational lS(0);
      for (int i = 0; i < N; ++i) lS += tangent[static_cast<std::size_t>(i)] * E(i, j);
      CHECK(lS == q(1, 2) * tangent[static_cast<std::size_t>(j)]);
    }
    // The 4-point scheme's ¼ and ⅛ are eigenvalues at every k too.
    CHECK(exact_rank(shifted_power(E, q(1, 4), 1)) < N);
    CHECK(exact_rank(shifted_power(E, q(1, 8), 1)) < N);
    // ½: the curve's alone at k = 1, 2, 4, 5, 7, 8 (geometric and algebraic multiplicity 1); the
    // curve's and the inside's at k = 3 (the regular boundary: two eigenvectors) and at k = 6 (one
    // eigenvector: a Jordan block, the inside's ½ coupled to the curve's tangent).
    const int half = N - exact_rank(shifted_power(E, q(1, 2), 1));
    const int half_squared = N - exact_rank(shifted_power(E, q(1, 2), 2));
    CHECK(half == (k == 3 ? 2 : 1));
    CHECK(half_squared == (k == 3 || k == 6 ? 2 : 1));
    // At 6 faces every vector of the Jordan block's space ker((S − ½)²) — the eigenvector v and the
    // generalized w, which the limit follows as ½^k(k v + w) — vanishes at the middle neighbour r3:
    // the unit row of r3 lies in the row space of (S − ½)² (the rank does not grow), exactly.
    if (k == 6) {
      auto rows = shifted_power(E, q(1, 2), 2);
      const int rank = exact_rank(rows);
      for (const char* name : {"r3", "r2"}) {
        auto with_unit = rows;
        with_unit.emplace_back(static_cast<std::size_t>(N), Rational(0));
        with_unit.back()[static_cast<std::size_t>(at(S, name))] = 1;
        CHECK(exact_rank(with_unit) == rank + (std::string(name) == "r3" ? 0 : 1));
      }
    }
    // ¼ at one face: twice, one eigenvector (a Jordan block).
    if (k == 1) {
      CHECK(N - exact_rank(shifted_power(E, q(1, 4), 1)) == 1);
      CHECK(N - exact_rank(shifted_power(E, q(1, 4), 2)) == 2);
    }
  }
}

TEST_CASE("butterfly boundary vertices: C1 at 2 and 3 faces only (1 to 8)",
          "[subdivision][mesh_analysis][butterfly]") {
  struct Expected {
    int faces;
    bool c1, decided;
    long double lambda1, lambda2;
    const char* reason;
  };
  // λ1, λ2 as the spectrum sorts them (to 1e-6: the values are the rounded roots printed by
  // `cifs scheme butterfly --boundary-valence 1..8 --analyze --format table`).
  const std::vector<Expected> table = {
      {1, false, false, 0.5L, 0.25L, "0.25 is defective (a Jordan block)"},
      {2, true, true, 0.5L, 0.469042L, "sector image spans 180 degrees"},
      {3, true, true, 0.5L, 0.5L, "sector image spans 180 degrees"},
      {4, false, true, 0.5L, 0.469042L, "sends a vertex next to the centre to the centre"},
      {5, false, true, 0.506676L, 0.5L, "Jacobian takes both signs"},
      {6, false, true, 0.5L, 0.5L, "(w, v) sends r3 to the centre"},
      {7, false, true, 0.501978L, 0.5L, "spans 540 degrees"},
      {8, false, true, 0.506961L, 0.5L, "spans 540 degrees"},
  };
  for (const Expected& e : table) {
    INFO(e.faces << " faces");
    const LocalMatrix S = local_matrix(MeshScheme::butterfly, e.faces + 1, {.boundary = true});
    const LocalSpectrum spectrum = local_spectrum(S);
    CHECK(std::abs(spectrum.subdominant - e.lambda1) < 1e-6L);
    CHECK(std::abs(spectrum.second - e.lambda2) < 1e-6L);
    const C1Verdict verdict = c1_verdict(S, spectrum);
    CHECK(verdict.c1 == e.c1);
    CHECK(verdict.decided == e.decided);
    REQUIRE(verdict.sectors.size() == 1);
    CHECK_THAT(verdict.sectors[0].verdict.reason, Contains(e.reason));
  }
}

namespace {

using Integer = boost::multiprecision::cpp_int;
using Vec3 = Eigen::Matrix<long double, 3, 1>;

/// The neighbourhood after k steps, exactly: 16S has integer weights, so (16S)^k X is an integer net
/// (16^k times the points), with no round-off however small the modes.
struct ExactNet {
  std::vector<std::vector<Integer>> S16;  // 16 S
  std::vector<std::array<Integer, 3>> X;
  void step() {
    std::vector<std::array<Integer, 3>> Y(X.size());
    for (std::size_t i = 0; i < X.size(); ++i)
      for (std::size_t j = 0; j < X.size(); ++j)
        if (S16[i][j] != 0)
          for (std::size_t c = 0; c < 3; ++c) Y[i][c] += S16[i][j] * X[j][c];
    X = std::move(Y);
  }
  /// The unit normal of the triangle (a, b, c): the exact cross product, rounded once.
  Vec3 normal(int a, int b, int c) const {
    std::array<Integer, 3> u, v, n;
    for (std::size_t k = 0; k < 3; ++k) {
      u[k] = X[static_cast<std::size_t>(b)][k] - X[static_cast<std::size_t>(a)][k];
      v[k] = X[static_cast<std::size_t>(c)][k] - X[static_cast<std::size_t>(a)][k];
    }
    n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    Integer big = 0;
    for (const Integer& x : n) big = std::max(big, x < 0 ? Integer(-x) : x);
    const unsigned shift = big == 0                               ? 0
                           : static_cast<unsigned>(msb(big)) > 60 ? static_cast<unsigned>(msb(big)) - 60
                                                                  : 0;
    Vec3 out;
    for (std::size_t k = 0; k < 3; ++k)
      out(static_cast<Eigen::Index>(k)) = static_cast<long double>(n[k] >> shift);  // sign kept by cpp_int
    return out.normalized();
  }
};

ExactNet exact_net(const LocalMatrix& S) {
  ExactNet net;
  const int N = S.exact->rows;
  net.S16.assign(static_cast<std::size_t>(N), std::vector<Integer>(static_cast<std::size_t>(N)));
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      const Rational w = (*S.exact)(i, j) * 16;
      REQUIRE(denominator(w) == 1);
      net.S16[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = numerator(w);
    }
  for (int i = 0; i < N; ++i)  // generic integer data
    net.X.push_back({Integer((7 * i + 3) % 23 - 11), Integer((5 * i * i + 1) % 19 - 9),
                     Integer((3 * i * i + 2 * i) % 17 - 8)});
  return net;
}

/// The faces at the centre and the ones across its ring's edges: (c, r_j, r_{j+1}), (r_j, q_j, r_{j+1}).
std::vector<std::array<int, 3>> faces_near_centre(const LocalMatrix& S, int faces) {
  std::vector<std::array<int, 3>> out;
  for (int j = 0; j < faces; ++j) {
    const std::string a = "r" + std::to_string(j), b = "r" + std::to_string(j + 1);
    out.push_back({at(S, "c"), at(S, a), at(S, b)});
    out.push_back({at(S, a), at(S, "q" + std::to_string(j)), at(S, b)});
  }
  return out;
}

long double degrees_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.dot(b), -1.0L, 1.0L)) * 180 / std::numbers::pi_v<long double>;
}

}  // namespace

TEST_CASE("butterfly boundary Jordan blocks by deep refinement, exactly: 1 face converges like 1/k, 6 fold",
          "[subdivision][mesh_analysis][butterfly]") {
  // One face: ¼ is the 4-point curve's own Jordan block; S^k x = ½^k a v1 + ¼^k((kγ + β)v + γw) + …, so
  // the normals tend to a × γ (a the curve's tangent, γ read by the left eigenvector of ¼) like 1/k:
  // angle·k levels off, and the angle is not geometric.
  {
    const LocalMatrix S = local_matrix(MeshScheme::butterfly, 2, {.boundary = true});
    ExactNet net = exact_net(S);
    const auto N = S.values.rows();
    const auto left = [&](long double lambda) {
      const Eigen::JacobiSVD<LongMatrix> svd((S.values - lambda * LongMatrix::Identity(N, N)).transpose(),
                                             Eigen::ComputeFullV);
      return LongVector(svd.matrixV().col(N - 1));
    };
    const auto data = [&](const LongVector& l) {
      Vec3 out = Vec3::Zero();
      for (Eigen::Index i = 0; i < N; ++i)
        for (Eigen::Index c = 0; c < 3; ++c)
          out(c) += l(i) *
                    static_cast<long double>(net.X[static_cast<std::size_t>(i)][static_cast<std::size_t>(c)]);
      return out;
    };
    const Vec3 limit = data(left(0.5L)).cross(data(left(0.25L))).normalized();
    std::vector<long double> scaled;  // largest angle to the limit normal, times k
    for (int k = 1; k <= 64; ++k) {
      net.step();
      if (k != 16 && k != 32 && k != 64) continue;
      long double worst = 0;
      for (const auto& [a, b, c] : faces_near_centre(S, 1))
        worst = std::max(worst, std::min(degrees_between(net.normal(a, b, c), limit),
                                         180 - degrees_between(net.normal(a, b, c), limit)));
      scaled.push_back(worst * k);
    }
    CHECK(scaled[2] == Approx(scaled[1]).epsilon(0.02));
    CHECK(scaled[1] == Approx(scaled[0]).epsilon(0.02));
    CHECK(scaled[2] / 64 < 0.3L);  // degrees, at level 64 (16.7 / 64 here)
  }
  // Six faces: λ1 = λ2 = ½ with one eigenvector; (w, v) folds at r3. Deep down, faces at the centre
  // point opposite ways (180° apart): no tangent plane, at any level.
  {
    const LocalMatrix S = local_matrix(MeshScheme::butterfly, 7, {.boundary = true});
    ExactNet net = exact_net(S);
    for (int k = 1; k <= 128; ++k) {
      net.step();
      if (k != 64 && k != 128) continue;
      long double spread = 0;
      const auto faces = faces_near_centre(S, 6);
      for (const auto& [a, b, c] : faces)
        for (const auto& [d, e, f] : faces)
          spread = std::max(spread, degrees_between(net.normal(a, b, c), net.normal(d, e, f)));
      INFO("level " << k);
      CHECK(spread > 170);
    }
  }
}
