// SPDX-License-Identifier: MIT
// Butterfly at boundary vertices under mesh.cpp's rule (the 4-point curve on the boundary, the 10-point
// stencil inside with a wing missing at the boundary reflected; boundary ends count as regular): the
// local subdivision matrix in exact rationals (route (b), the production refiner, is compared with it
// in test_mesh_analysis.cpp), its Jordan structure and the C1 verdict per number of faces.
#include <catch2/catch.hpp>

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
