// SPDX-License-Identifier: MIT
// The rules of Biermann, Levin and Zorin 2000 (RuleSet::blz): the regular crease is the standard rule,
// the spectra of boundary, convex and concave corner sectors are the closed forms derived in
// docs/subdivision-surfaces.md ("Biermann–Levin–Zorin rules"), exactly where the weights are
// rational; the cases the standard rules leave not C1 pass; the refiner equals the hand-written
// matrices and a hand-computed edge point.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <numeric>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/topology.hpp"
#include "subdivision/spectra.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using Catch::Matchers::Contains;
using cifs_test::check_same_spectrum;

namespace blz_test {

using Complex = std::complex<long double>;
constexpr long double kBlzPi = std::numbers::pi_v<long double>;

enum class Kind { boundary, convex, concave };

LocalOptions blz_options(Kind kind, RuleSet rules) {
  return LocalOptions{.boundary = true,
                      .rule = BoundaryRule::edge_only,
                      .sharp = {},
                      .corner = kind != Kind::boundary,
                      .concave = kind == Kind::concave,
                      .rules = rules};
}

/// cos(pπ/q) exactly when Niven's theorem allows it (reduced q = 1, 2 or 3), else nothing.
std::optional<Rational> blz_exact_cos_pi(int p, int q) {
  const int g = std::gcd(p, q);
  p /= g;
  q /= g;
  const int r = ((p % (2 * q)) + 2 * q) % (2 * q);  // pπ/q mod 2π, in units of π/q
  if (q == 1) return Rational(r == 0 ? 1 : -1);
  if (q == 2) return Rational(0);
  if (q == 3) return Rational(r == 1 || r == 5 ? 1 : -1, 2);
  return std::nullopt;
}

/// The characteristic polynomial's factors (coefficients, constant first) of the local matrix of a
/// boundary or corner sector of k faces, derived by hand (docs: "Biermann–Levin–Zorin rules"): the
/// curve block (c and the two sharp edges' points: 1, ½, ¼ under the crease rule, 1, ½, ½ at a
/// corner) and the inner sine modes φ_j = jπ/k, j = 1 … k − 1 — Loop: γ + ¼cos φ_j; Catmull–Clark:
/// the roots of λ² − (γ + ⅛cos φ + ¼)λ + ¼(γ + ⅛cos φ) − (1 + cos φ)/32, and ¼ (alternating face
/// points). A concave corner's flatness s scales every eigenvalue but 1, ½, ½ by 1 − s. γ = ⅜ for
/// the standard rules; blz: γ = ⅜ + ⅛[Loop] − ¼cos θ_k. `cos_pi(p, q)` = cos(pπ/q).
template <class T, class CosPi>
std::vector<std::vector<T>> blz_factors(MeshScheme scheme, int k, Kind kind, RuleSet rules, CosPi cos_pi) {
  const T one(1);
  const bool loop = scheme == MeshScheme::loop;
  // θ_k = pπ/q: π/k, π/(2k), 3π/(2k).
  const int p = kind == Kind::concave ? 3 : 1, q = kind == Kind::boundary ? k : 2 * k;
  const T gamma =
      rules == RuleSet::blz ? T((loop ? T(one / 2) : T(3 * one / 8)) - T(cos_pi(p, q)) / 4) : T(3 * one / 8);
  const T s = rules == RuleSet::blz && kind == Kind::concave ? T(one / 2) : T(0);
  const T scale = one - s;
  std::vector<std::vector<T>> out;
  const auto linear = [&](const T& root) { out.push_back({T(-root), one}); };
  linear(one);
  linear(T(one / 2));
  linear(kind == Kind::boundary ? T(one / 4) : T(one / 2));
  for (int j = 1; j < k; ++j) {
    const T c = cos_pi(j, k);
    if (loop) {
      linear(T(scale * T(gamma + c / 4)));
    } else {
      // Roots scaled by σ: λ² − σbλ + σ²c0.
      const T b = gamma + c / 8 + one / 4, c0 = T(T(gamma + c / 8) / 4) - T(T(one + c) / 32);
      out.push_back({T(scale * scale * c0), T(-scale * b), one});
    }
  }
  if (!loop && k >= 1) linear(T(scale / 4));
  return out;
}

std::vector<Complex> blz_roots(const std::vector<std::vector<long double>>& factors) {
  std::vector<Complex> out;
  for (const auto& f : factors) {
    if (f.size() == 2) {
      out.emplace_back(-f[0] / f[1]);
      continue;
    }
    const Complex d = std::sqrt(Complex(f[1] * f[1] - 4 * f[0] * f[2]));
    out.push_back((-f[1] + d) / (2 * f[2]));
    out.push_back((-f[1] - d) / (2 * f[2]));
  }
  return out;
}

/// The characteristic polynomial det(xI − A) of an exact matrix (Faddeev–LeVerrier), constant first.
std::vector<Rational> blz_char_poly(const RationalMatrix& A) {
  const int n = A.rows;
  std::vector<Rational> c(static_cast<std::size_t>(n) + 1, 0);
  c[static_cast<std::size_t>(n)] = 1;
  std::vector<Rational> M(static_cast<std::size_t>(n * n), 0), AM(static_cast<std::size_t>(n * n), 0);
  const auto at = [n](std::vector<Rational>& X, int i, int j) -> Rational& {
    return X[static_cast<std::size_t>(i * n + j)];
  };
  for (int k = 1; k <= n; ++k) {
    // M_k = A M_{k−1} + c_{n−k+1} I (M_0 = 0), c_{n−k} = −tr(A M_k)/k.
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        Rational s = 0;
        for (int l = 0; l < n; ++l) s += A(i, l) * at(AM, l, j);
        at(M, i, j) = s + (i == j ? c[static_cast<std::size_t>(n - k + 1)] : Rational(0));
      }
    Rational trace = 0;
    for (int i = 0; i < n; ++i)
      for (int l = 0; l < n; ++l) trace += A(i, l) * at(M, l, i);
    c[static_cast<std::size_t>(n - k)] = -trace / k;
    AM = M;
  }
  return c;
}

std::vector<Rational> blz_product(const std::vector<std::vector<Rational>>& factors) {
  std::vector<Rational> p{1};
  for (const auto& f : factors) {
    std::vector<Rational> r(p.size() + f.size() - 1, 0);
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = 0; j < f.size(); ++j) r[i + j] += p[i] * f[j];
    p = r;
  }
  return p;
}

/// Checks a sector's spectrum against the closed form (1e-12), and exactly when the weights are
/// rational. Returns whether the exact check ran.
bool blz_check_closed_form(MeshScheme scheme, int k, Kind kind, RuleSet rules) {
  INFO(scheme_name(scheme) << " " << k << " faces, kind " << static_cast<int>(kind) << " rules "
                           << option_name(rules));
  const LocalMatrix S = local_matrix(scheme, k + 1, blz_options(kind, rules));
  const LocalSpectrum sp = local_spectrum(S);
  const auto cos_long = [](int p, int q) { return std::cos(kBlzPi * p / q); };
  check_same_spectrum(sp.eigenvalues, blz_roots(blz_factors<long double>(scheme, k, kind, rules, cos_long)),
                      1e-12L);
  if (!S.exact) return false;
  bool rational = true;
  const auto cos_exact = [&](int p, int q) {
    const auto c = blz_exact_cos_pi(p, q);
    if (!c) rational = false;
    return c.value_or(Rational(0));
  };
  const std::vector<Rational> expected =
      blz_product(blz_factors<Rational>(scheme, k, kind, rules, cos_exact));
  if (!rational) return false;  // irrational factors (their product may still be rational)
  CHECK(blz_char_poly(*S.exact) == expected);
  return true;
}

/// A quad grid of w × h faces (a boundary of regular vertices and four one-face corners).
Mesh blz_grid(int w, int h) {
  Mesh m;
  m.vertices.resize((w + 1) * (h + 1), 3);
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i) m.vertices.row(j * (w + 1) + i) << i, j, 0.1 * ((i * 7 + j * 3) % 5);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const int a = j * (w + 1) + i;
      m.face_vertices.insert(m.face_vertices.end(), {a, a + 1, a + w + 2, a + w + 1});
      m.face_offsets.push_back(static_cast<int>(m.face_vertices.size()));
    }
  return m;
}

}  // namespace blz_test

using namespace blz_test;

TEST_CASE("blz rules: the regular crease and boundary are the standard rules exactly",
          "[subdivision][mesh_analysis][classes][blz]") {
  const auto same = [](MeshScheme scheme, int n, LocalOptions o) {
    INFO(scheme_name(scheme) << " valence " << n << " " << vertex_class(n, o));
    const LocalMatrix standard = local_matrix(scheme, n, o);
    o.rules = RuleSet::blz;
    const LocalMatrix blz = local_matrix(scheme, n, o);
    REQUIRE(standard.exact);
    REQUIRE(blz.exact);
    CHECK(standard.exact->entries == blz.exact->entries);
  };
  same(MeshScheme::catmull_clark, 3, {.boundary = true});  // 2 faces
  same(MeshScheme::loop, 4, {.boundary = true});           // 3 faces
  same(MeshScheme::catmull_clark, 4, {.sharp = {0, 2}});
  same(MeshScheme::loop, 6, {.sharp = {0, 3}});
  same(MeshScheme::catmull_clark, 2, {.boundary = true, .corner = true});  // one face: no inner edge
  same(MeshScheme::loop, 2, {.boundary = true, .corner = true});
  // The refiner: a grid's boundary (regular vertices, one-face corners) and a closed mesh refine
  // to the same weights, bit for bit.
  Mesh grid = blz_grid(4, 3);
  const MeshRefinement a = refine_topology(grid, MeshScheme::catmull_clark, 2);
  grid.tags.rules = RuleSet::blz;
  const MeshRefinement b = refine_topology(grid, MeshScheme::catmull_clark, 2);
  for (std::size_t level = 0; level < 2; ++level) {
    CHECK(a.steps[level].columns == b.steps[level].columns);
    CHECK(a.steps[level].weights == b.steps[level].weights);
  }
}

TEST_CASE("blz rules: boundary and corner spectra are the closed forms, exactly where rational",
          "[subdivision][mesh_analysis][classes][blz]") {
  int exact = 0;
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop})
    for (const RuleSet rules : {RuleSet::opensubdiv, RuleSet::blz})
      for (int k = 1; k <= 8; ++k) {
        exact += blz_check_closed_form(scheme, k, Kind::boundary, rules) ? 1 : 0;
        exact += blz_check_closed_form(scheme, k, Kind::convex, rules) ? 1 : 0;
        if (k >= 2 || rules == RuleSet::opensubdiv)
          exact += blz_check_closed_form(scheme, k, Kind::concave, rules) ? 1 : 0;
      }
  // Rational factors: the standard rules at k ≤ 3 (cos(jπ/k) rational; 9 sectors a scheme), blz's
  // at k = 1, 2, 3 on the boundary, 1 at a convex corner and 3 at a concave one (5 a scheme).
  CHECK(exact == 2 * 9 + 2 * 5);
  // The subdominant eigenvalue is ½ at every boundary and corner sector of blz with an inner edge,
  // double, and the largest after 1: Loop's j = 1 mode γ + ¼cos(π/k) = ½ at a boundary.
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop})
    for (int k = 2; k <= 14; ++k)
      for (const Kind kind : {Kind::boundary, Kind::convex, Kind::concave}) {
        INFO(scheme_name(scheme) << " " << k << " faces, kind " << static_cast<int>(kind));
        const LocalSpectrum sp = local_spectrum(local_matrix(scheme, k + 1, blz_options(kind, RuleSet::blz)));
        CHECK(sp.subdominant_pair);
        CHECK(std::abs(sp.subdominant - 0.5L) < 1e-13L);
        CHECK(sp.gap);
      }
}

TEST_CASE("blz rules: what the standard rules leave not C1 is C1; γ off by 1e-3 is seen",
          "[subdivision][mesh_analysis][classes][blz]") {
  const auto verdict = [](MeshScheme scheme, int k, Kind kind, RuleSet rules) {
    const LocalMatrix S = local_matrix(scheme, k + 1, blz_options(kind, rules));
    return c1_verdict(S, local_spectrum(S));
  };
  struct Case {
    MeshScheme scheme;
    int k;
    Kind kind;
  };
  std::vector<Case> failing;
  for (int k = 5; k <= 8; ++k) failing.push_back({MeshScheme::catmull_clark, k, Kind::boundary});
  for (int k = 7; k <= 8; ++k) failing.push_back({MeshScheme::loop, k, Kind::boundary});
  for (int k = 2; k <= 6; ++k) {
    failing.push_back({MeshScheme::catmull_clark, k, Kind::concave});
    failing.push_back({MeshScheme::loop, k, Kind::concave});
  }
  failing.push_back({MeshScheme::catmull_clark, 3, Kind::convex});  // two live eigenfunctions at ½
  failing.push_back({MeshScheme::loop, 4, Kind::convex});
  for (const Case& c : failing) {
    INFO(scheme_name(c.scheme) << " " << c.k << " faces, kind " << static_cast<int>(c.kind));
    const C1Verdict standard = verdict(c.scheme, c.k, c.kind, RuleSet::opensubdiv);
    CHECK_FALSE(standard.c1);
    if (c.kind != Kind::concave) CHECK(standard.decided);  // concave: some are Jordan blocks
    const C1Verdict blz = verdict(c.scheme, c.k, c.kind, RuleSet::blz);
    CHECK(blz.c1);
    REQUIRE(blz.sectors.size() == 1);
    const long double angle = blz.sectors[0].verdict.angle;
    CHECK((c.kind == Kind::concave ? angle > kBlzPi : angle <= kBlzPi + 1e-9L));
  }
  // A concave corner of one face cannot span more than π, with either rules.
  CHECK_FALSE(verdict(MeshScheme::loop, 1, Kind::concave, RuleSet::blz).c1);
  // Mutation: γ off by 1e-3 on one inner edge moves the subdominant eigenvalue off ½ by more than the
  // closed-form check's tolerance.
  LocalMatrix S = local_matrix(MeshScheme::loop, 6, blz_options(Kind::boundary, RuleSet::blz));
  const Eigen::Index r2 = 3;  // c, r0, r1, r2, …
  S.values(r2, 0) -= 1e-3L;
  S.values(r2, r2) += 1e-3L;
  const LocalSpectrum mutated = local_spectrum(S);
  CHECK(std::abs(mutated.subdominant - 0.5L) > 1e-5L);
}

TEST_CASE("blz rules: the refiner equals the hand-written matrices and a hand-computed edge point",
          "[subdivision][mesh_analysis][classes][blz]") {
  const auto same = [](MeshScheme scheme, int n, LocalOptions o) {
    o.rules = RuleSet::blz;
    INFO(scheme_name(scheme) << " valence " << n << " " << vertex_class(n, o)
                             << (o.concave ? " concave" : ""));
    const LocalMatrix a = local_matrix(scheme, n, o);
    const LocalMatrix b = refined_local_matrix(scheme, n, o);
    REQUIRE(a.values.rows() == b.values.rows());
    CHECK((a.values - b.values).cwiseAbs().maxCoeff() < 1e-15L);
  };
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop}) {
    for (int n = kMinBoundaryValence; n <= 10; ++n) {
      same(scheme, n, {.boundary = true});
      same(scheme, n, {.boundary = true, .corner = true});
      if (n >= 3) same(scheme, n, {.boundary = true, .corner = true, .concave = true});
    }
    for (int n = kMinValence; n <= 9; ++n)
      for (int k = 1; k < n; ++k) {
        same(scheme, n, {.sharp = {0, k}});
        same(scheme, n, {.sharp = {0, k}, .corner = true});
        if (k >= 2 && n - k >= 2) same(scheme, n, {.sharp = {0, k}, .corner = true, .concave = true});
      }
    same(scheme, 7, {.boundary = true, .sharp = {3}});  // a corner inside a boundary fan
    same(scheme, 6, {.sharp = {0, 2, 4}});
  }
  // A Loop fan of 4 triangles around boundary vertex 0 (ring 1 … 5, all on the boundary): the edge
  // 0–2 joins two boundary vertices, 0 with 4 faces, 2 with 2, and gets the mean of their one-sided
  // rules: standard ⅜, ⅜, ⅛, ⅛ plus ½δ0(p0 − p2) + ½δ2(p2 − p0), δ = ¼cos θ_k − ⅛.
  Mesh fan;
  fan.vertices = Points::Zero(6, 3);
  for (int i = 1; i <= 4; ++i) {
    fan.face_vertices.insert(fan.face_vertices.end(), {0, i, i + 1});
    fan.face_offsets.push_back(static_cast<int>(fan.face_vertices.size()));
  }
  for (int v = 0; v < 6; ++v) fan.vertices.row(v) << std::cos(v * 0.7), std::sin(v * 0.7), 0;
  fan.tags.rules = RuleSet::blz;
  const MeshRefinement r = refine_topology(fan, MeshScheme::loop, 1);
  const MeshTopology& t = r.levels[0];
  const int e = find_edge(t, 0, 2);
  REQUIRE(e >= 0);
  const Stencils& st = r.steps[0];
  const auto row = static_cast<std::size_t>(t.vertex_count + e);
  std::vector<double> w(6, 0.0);
  for (int k = st.offsets[row]; k < st.offsets[row + 1]; ++k)
    w[static_cast<std::size_t>(st.columns[static_cast<std::size_t>(k)])] +=
        st.weights[static_cast<std::size_t>(k)];
  const double d0 = 0.25 * std::cos(std::numbers::pi / 4) - 0.125,
               d2 = 0.25 * std::cos(std::numbers::pi / 2) - 0.125;
  CHECK(std::abs(w[0] - (0.375 + 0.5 * d0 - 0.5 * d2)) < 1e-15);
  CHECK(std::abs(w[2] - (0.375 - 0.5 * d0 + 0.5 * d2)) < 1e-15);
  CHECK(std::abs(w[1] - 0.125) < 1e-15);
  CHECK(std::abs(w[3] - 0.125) < 1e-15);
  // The same fan under the standard rules: ⅜, ⅜.
  fan.tags.rules = RuleSet::opensubdiv;
  const MeshRefinement standard = refine_topology(fan, MeshScheme::loop, 1);
  for (int k = standard.steps[0].offsets[row]; k < standard.steps[0].offsets[row + 1]; ++k)
    if (const int c = standard.steps[0].columns[static_cast<std::size_t>(k)]; c == 0 || c == 2)
      CHECK(standard.steps[0].weights[static_cast<std::size_t>(k)] == 0.375);
}

TEST_CASE("blz rules: the mesh analysis follows them; refusals",
          "[subdivision][mesh_analysis][classes][blz]") {
  // A quad fan: boundary vertex 0 with 6 faces, not C1 under the standard rules, C1 under blz.
  Mesh fan;
  fan.vertices = Points::Zero(1 + 7 + 6, 3);
  for (int i = 0; i < 7; ++i) fan.vertices.row(1 + i) << std::cos(i * 0.5), std::sin(i * 0.5), 0;
  for (int i = 0; i < 6; ++i)
    fan.vertices.row(8 + i) << 2 * std::cos(i * 0.5 + 0.25), 2 * std::sin(i * 0.5 + 0.25), 0;
  for (int i = 0; i < 6; ++i) {
    fan.face_vertices.insert(fan.face_vertices.end(), {0, 1 + i, 8 + i, 2 + i});
    fan.face_offsets.push_back(static_cast<int>(fan.face_vertices.size()));
  }
  const auto centre = [](const MeshSmoothness& a) {
    const auto it = std::find_if(a.vertices.begin(), a.vertices.end(),
                                 [](const VertexSmoothness& v) { return v.vertex == 0; });
    REQUIRE(it != a.vertices.end());
    return it->verdict;
  };
  CHECK_FALSE(centre(analyze_mesh(fan, MeshScheme::catmull_clark)).c1);
  fan.tags.rules = RuleSet::blz;
  CHECK(centre(analyze_mesh(fan, MeshScheme::catmull_clark)).c1);

  CHECK_THROWS_WITH(local_matrix(MeshScheme::butterfly, 6, {.rules = RuleSet::blz}),
                    Contains("the rule set 'blz' is built for catmull-clark and loop only"));
  CHECK_THROWS_WITH(subdivide(fan, MeshScheme::doo_sabin, 1),
                    Contains("doo-sabin: the rule set 'blz' is built for catmull-clark and loop only"));
  CHECK_THROWS_WITH(limit_mesh(fan, MeshScheme::catmull_clark, 1),
                    Contains("limits under the rule set 'blz' are not built"));
  CHECK_THROWS_WITH(factored_subdivide(fan, MeshScheme::catmull_clark, 1),
                    Contains("not the rule set 'blz'"));
  Mesh concave = fan;
  concave.tags.concave = {3};
  CHECK_THROWS_WITH(subdivide(concave, MeshScheme::catmull_clark, 1),
                    Contains("vertex 3 is tagged concave but is not a corner"));
  concave.tags.concave = {99};
  CHECK_THROWS_WITH(subdivide(concave, MeshScheme::catmull_clark, 1),
                    Contains("concave corner 99 is not a vertex"));
  concave.tags.concave = {0};
  concave.tags.rules = RuleSet::opensubdiv;
  CHECK_THROWS_WITH(subdivide(concave, MeshScheme::catmull_clark, 1),
                    Contains("concave corners are a part of the rule set 'blz'"));
  concave.tags.rules = RuleSet::blz;
  concave.tags.corners = {{0, kInfiniteSharpness}};
  CHECK_NOTHROW(subdivide(concave, MeshScheme::catmull_clark, 2));
  CHECK(named_rule_set("blz") == RuleSet::blz);
  CHECK_THROWS_WITH(named_rule_set("zorin"), Contains("unknown rule set 'zorin' (opensubdiv, blz)"));
}
