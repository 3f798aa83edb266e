// SPDX-License-Identifier: MIT
// "Which points of my model are not smooth?" under modified Butterfly and Doo–Sabin (issue 29 §5):
// analyze_mesh's classes and verdicts against the local analysis of each configuration, against
// topology counted here, and against deep refinement.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <span>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/topology.hpp"
#include "subdivision/meshes.hpp"
#include "subdivision/rational.hpp"
#include "subdivision/spectra.hpp"
#include "support/sanitized.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using Catch::Matchers::Contains;
using cifs_test::make_mesh;
using cifs_test::q;

namespace mesh_smoothness_test {

/// An open fan of k triangles round vertex 0 (a boundary vertex of k faces), rim 1 … k + 1, with
/// heights that no symmetry flattens.
Mesh open_fan(int k, unsigned seed = 5) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  std::vector<std::array<double, 3>> p{{0, 0, 0.1}};
  std::vector<std::vector<int>> f;
  for (int j = 0; j <= k; ++j) {
    const double a = std::numbers::pi * j / k;
    p.push_back({std::cos(a) + jitter(rng), std::sin(a) + jitter(rng), jitter(rng)});
    if (j > 0) f.push_back({0, j, j + 1});
  }
  return make_mesh(p, f);
}

/// Two meshes side by side (b's vertices after a's).
Mesh disjoint_union(const Mesh& a, const Mesh& b) {
  Mesh out = a;
  const auto shift = static_cast<int>(a.vertices.rows());
  out.vertices.conservativeResize(a.vertices.rows() + b.vertices.rows(), 3);
  out.vertices.bottomRows(b.vertices.rows()) = b.vertices;
  for (std::size_t f = 0; f < face_count(b); ++f) {
    std::vector<int> c(face(b, f).begin(), face(b, f).end());
    for (int& v : c) v += shift;
    add_face(out, std::span<const int>(c));
  }
  return out;
}

/// The faces of each vertex, counted here (independently of the topology code).
std::vector<int> faces_per_vertex(const Mesh& m) {
  std::vector<int> out(static_cast<std::size_t>(m.vertices.rows()), 0);
  for (std::size_t f = 0; f < face_count(m); ++f)
    for (const int v : face(m, f)) ++out[static_cast<std::size_t>(v)];
  return out;
}

/// The largest angle between the normals of the faces at vertex v (radians).
double normal_spread(const Mesh& m, int v) {
  std::vector<Eigen::Vector3d> normals;
  for (std::size_t f = 0; f < face_count(m); ++f) {
    const auto c = face(m, f);
    if (std::find(c.begin(), c.end(), v) == c.end()) continue;
    const Eigen::Vector3d a = m.vertices.row(c[0]).transpose(), b = m.vertices.row(c[1]).transpose(),
                          d = m.vertices.row(c[2]).transpose();
    normals.push_back((b - a).cross(d - a).normalized());
  }
  double out = 0;
  for (const auto& x : normals)
    for (const auto& y : normals) out = std::max(out, std::acos(std::clamp(x.dot(y), -1.0, 1.0)));
  return out;
}

}  // namespace mesh_smoothness_test

using namespace mesh_smoothness_test;

TEST_CASE("analyze_mesh under butterfly: every irregular vertex with the verdict of its configuration",
          "[subdivision][mesh_analysis][butterfly]") {
  // Boundary fans of 1 … 8 faces: the centre is a boundary vertex of k faces, the rim's two ends have
  // one face, the others two. The verdicts of the boundary rule (docs: C1 at 2 and 3 faces only,
  // undecided at 1 — a Jordan block —, not C1 at 4 … 8).
  const std::map<int, const char*> expected{{1, "undecided"}, {2, "C1"},     {3, "C1"},     {4, "not C1"},
                                            {5, "not C1"},    {6, "not C1"}, {7, "not C1"}, {8, "not C1"}};
  const auto word = [](const C1Verdict& v) { return v.c1 ? "C1" : v.decided ? "not C1" : "undecided"; };
  for (int k = 1; k <= 8; ++k) {
    if (cifs_test::skipped_when_sanitized(static_cast<std::size_t>(k - 1))) continue;  // k = 1, 4, 7
    INFO(k << " faces");
    const Mesh fan = open_fan(k);
    const std::vector<int> faces = faces_per_vertex(fan);
    const MeshSmoothness a = analyze_mesh(fan, MeshScheme::butterfly);
    std::set<int> listed;
    for (const VertexSmoothness& v : a.vertices) {
      listed.insert(v.vertex);
      const int n = faces[static_cast<std::size_t>(v.vertex)];
      CHECK(v.valence == n + 1);  // every vertex of a fan is on the boundary: edges = faces + 1
      CHECK(v.vertex_class == "boundary");
      CHECK(v.sectors == std::vector<int>{n});
      CHECK(word(v.verdict) == std::string(expected.at(n)));
      // The same numbers as the local analysis of a boundary vertex of n faces, taken directly.
      const LocalMatrix S = local_matrix(MeshScheme::butterfly, n + 1, {.boundary = true});
      const LocalSpectrum sp = local_spectrum(S);
      CHECK(v.lambda1 == sp.subdominant);
      CHECK(v.lambda2 == sp.second);
      CHECK(v.verdict.c1 == c1_verdict(S, sp).c1);
    }
    // Listed: every vertex but those of three faces (the regular boundary); each class analysed once.
    for (int v = 0; v < static_cast<int>(faces.size()); ++v)
      CHECK(listed.count(v) == (faces[static_cast<std::size_t>(v)] == 3 ? 0U : 1U));
    CHECK(a.regular + static_cast<int>(a.vertices.size()) == static_cast<int>(faces.size()));
    const std::set<int> classes{faces.begin(), faces.end()};
    CHECK(a.analyses == static_cast<int>(classes.size()) - static_cast<int>(classes.count(3)));
  }
  // A boundary vertex and interior ones of the same valence (5) in one mesh: each keeps its own
  // class's verdict (not C1 at 4 faces, C1 inside).
  const Mesh both = disjoint_union(open_fan(4), cifs_test::bipyramid_of(5));
  const MeshSmoothness ab = analyze_mesh(both, MeshScheme::butterfly);
  for (const VertexSmoothness& v : ab.vertices)
    if (v.valence == 5) CHECK(v.verdict.c1 == (v.vertex >= 6));
  // Interior: ZSS's stencils at valences 3 … 8 (bipyramid apexes; the equator has valence 4), C1.
  for (int k = 3; k <= 8; ++k) {
    if (cifs_test::skipped_when_sanitized(static_cast<std::size_t>(k - 3))) continue;  // k = 3, 6
    const Mesh b = cifs_test::bipyramid_of(k);
    const MeshSmoothness a = analyze_mesh(b, MeshScheme::butterfly);
    CHECK(static_cast<int>(a.vertices.size()) == k + 2 - (k == 6 ? 2 : 0));
    CHECK(a.c1 == static_cast<int>(a.vertices.size()));
    for (const VertexSmoothness& v : a.vertices) {
      CHECK(v.vertex_class == "interior");
      CHECK(v.verdict.method == "sampled");
      CHECK(v.valence == (v.vertex < k ? 4 : k));
    }
    CHECK(a.analyses == (k == 4 || k == 6 ? 1 : 2));
  }
}

TEST_CASE("analyze_mesh under butterfly refuses what has no analysis, naming the vertex",
          "[subdivision][mesh_analysis][butterfly]") {
  CHECK_THROWS_WITH(analyze_mesh(open_fan(16), MeshScheme::butterfly),
                    Contains("vertex 0: butterfly: boundary valence 17 is out of range"));
  CHECK_THROWS_WITH(analyze_mesh(cifs_test::bipyramid_of(17), MeshScheme::butterfly),
                    Contains("vertex 17: butterfly: valence 17 is out of range"));
  Mesh tagged = open_fan(4);
  tagged.tags.creases = {{0, 2, kInfiniteSharpness}};
  CHECK_THROWS_WITH(analyze_mesh(tagged, MeshScheme::butterfly),
                    Contains("the mesh has a crease (0 2") && Contains("butterfly has no rules for creases"));
  CHECK_THROWS_WITH(analyze_mesh(cifs_test::cube(), MeshScheme::butterfly),
                    Contains("butterfly runs on triangles; face 0 has 4"));
}

TEST_CASE("butterfly verdicts by deep refinement: the normals at a C1 vertex converge, elsewhere not",
          "[subdivision][mesh_analysis][butterfly]") {
  // The spread of the normals of the faces at the centre (it keeps its index: interpolating) levels 3
  // … 7. Where the verdict is C1 it shrinks by about |mu|/lambda a level; where it is not C1 the
  // surface has no tangent plane there and the spread stays (for data no symmetry flattens).
  const std::array<int, 4> faces{2, 4, 5, 7};
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (cifs_test::skipped_when_sanitized(i)) continue;  // 2 and 7 faces
    const int k = faces[i];
    INFO(k << " faces");
    const Mesh fan = open_fan(k);
    const VertexSmoothness centre = analyze_mesh(fan, MeshScheme::butterfly).vertices.front();
    REQUIRE(centre.vertex == 0);
    const bool c1 = centre.verdict.c1;
    std::vector<double> spread;
    Mesh level = subdivide(fan, MeshScheme::butterfly, 3);
    for (int l = 3; l <= 7; ++l) {
      spread.push_back(normal_spread(level, 0));
      if (l < 7) level = subdivide(level, MeshScheme::butterfly, 1);
    }
    UNSCOPED_INFO("spread (degrees) " << spread[0] * 180 / std::numbers::pi << " … "
                                      << spread.back() * 180 / std::numbers::pi);
    CHECK((spread.back() < 0.2 * spread.front()) == c1);
    if (!c1) continue;
    // At the rate the spectrum predicts: |mu|/lambda2 a level (approached from above).
    REQUIRE(centre.curvature_ratio);  // lambda2²/|mu|
    const double rate = static_cast<double>(centre.lambda2 / *centre.curvature_ratio),
                 last = spread[4] / spread[3];
    CHECK(last > rate);
    CHECK(last < rate + 0.05);
  }
}

namespace mesh_smoothness_test {

/// An n × n grid of quads without the listed faces (by (i, j)): corners of the surface where the
/// boundary turns, and pinches where two removed faces touch a face at opposite corners.
Mesh cut_grid(int n, const std::vector<std::array<int, 2>>& removed) {
  const Mesh full = cifs_test::quad_grid(n, n);
  std::vector<std::array<double, 3>> p;
  for (Eigen::Index v = 0; v < full.vertices.rows(); ++v)
    p.push_back({full.vertices(v, 0), full.vertices(v, 1), full.vertices(v, 2)});
  std::vector<std::vector<int>> f;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (std::find(removed.begin(), removed.end(), std::array{i, j}) == removed.end()) {
        const auto c = face(full, static_cast<std::size_t>(j * n + i));
        f.emplace_back(c.begin(), c.end());
      }
  return make_mesh(p, f);
}

}  // namespace mesh_smoothness_test

TEST_CASE("analyze_mesh under doo-sabin: face centres and interior vertices' faces, closed meshes",
          "[subdivision][mesh_analysis][doo_sabin]") {
  // A cube: every vertex becomes a triangle after one step (valence 3), the faces are quads.
  const MeshSmoothness cube = analyze_mesh(cifs_test::cube(), MeshScheme::doo_sabin);
  CHECK(cube.vertices.size() == 8);
  CHECK(cube.regular == 6);
  CHECK(cube.analyses == 1);
  for (const VertexSmoothness& v : cube.vertices) {
    CHECK(v.face == -1);
    CHECK(v.vertex_class == "vertex");
    CHECK(v.valence == 3);
    CHECK(v.verdict.method == "bernstein");
    CHECK(v.verdict.c1);
  }
  // A square pyramid: four triangles (face centres), the base's corners valence 3, the apex 4.
  const Mesh pyramid = cifs_test::pyramid();
  const MeshSmoothness a = analyze_mesh(pyramid, MeshScheme::doo_sabin);
  const LocalMatrix S3 = local_matrix(MeshScheme::doo_sabin, 3);
  const LocalSpectrum sp3 = local_spectrum(S3);
  int faces = 0, vertices = 0;
  for (const VertexSmoothness& v : a.vertices) {
    (v.face >= 0 ? faces : vertices) += 1;
    if (v.face >= 0) CHECK(face(pyramid, static_cast<std::size_t>(v.face)).size() == 3U);
    if (v.face < 0) CHECK(v.vertex < 4);
    CHECK(v.valence == 3);
    CHECK(v.lambda1 == sp3.subdominant);
    CHECK(v.verdict.c1 == c1_verdict(S3, sp3).c1);
  }
  CHECK(faces == 4);
  CHECK(vertices == 4);
  CHECK(a.regular == 2);  // the base quad and the apex
  CHECK(a.summary ==
        "doo-sabin: 5 faces and 5 vertices, 2 regular points, 8 irregular: 8 C1, 0 not C1, 0 undecided "
        "(1 local analysis)");
}

TEST_CASE("analyze_mesh under doo-sabin: faces at the boundary are the interior k-gon restricted",
          "[subdivision][mesh_analysis][doo_sabin]") {
  // A 4 × 4 grid without faces (0, 0) and (2, 2): convex corners (one interior corner), a concave one
  // (three), a pinch (two opposite) and the grid's own corners; classes checked against the interior
  // corners counted here (a grid vertex is interior when four faces meet there).
  for (const auto& removed : {std::vector<std::array<int, 2>>{}, {{0, 0}}, {{0, 0}, {2, 2}}}) {
    const Mesh g = cut_grid(4, removed);
    const std::vector<int> around = faces_per_vertex(g);
    const MeshSmoothness a = analyze_mesh(g, MeshScheme::doo_sabin);
    std::map<int, const VertexSmoothness*> listed;
    for (const VertexSmoothness& v : a.vertices) listed[v.face] = &v;
    int off = 0;
    for (std::size_t f = 0; f < face_count(g); ++f) {
      const auto c = face(g, f);
      std::array<bool, 4> inner{};
      for (std::size_t i = 0; i < 4; ++i) inner[i] = around[static_cast<std::size_t>(c[i])] == 4;
      const int m = static_cast<int>(std::count(inner.begin(), inner.end(), true));
      int runs = 0;
      for (std::size_t i = 0; i < 4; ++i) runs += inner[i] && !inner[(i + 3) % 4] ? 1 : 0;
      INFO("face " << f << ": " << m << " interior corners, " << runs << " runs");
      off += m == 0 ? 1 : 0;
      const bool regular = m == 0 || m == 4 || (m == 2 && runs == 1);
      REQUIRE(listed.count(static_cast<int>(f)) == (regular ? 0U : 1U));
      if (regular) continue;
      const VertexSmoothness& v = *listed[static_cast<int>(f)];
      CHECK(v.vertex_class == "boundary");
      CHECK(v.verdict.decided);
      CHECK(v.verdict.c1 == (runs == 1));
      if (runs == 1) {
        CHECK(std::abs(v.verdict.angle - std::numbers::pi_v<long double> * m / 2) < 1e-15L);
        CHECK_THAT(v.verdict.reason, Contains(std::to_string(90 * m) + ".0 degrees"));
      } else {
        CHECK_THAT(v.verdict.reason, Contains("pinches"));
      }
      CHECK(std::abs(v.lambda1 - 0.5L) < 1e-15L);
      CHECK(std::abs(v.lambda2 - 0.5L) < 1e-15L);
      // The class taken directly (`cifs scheme doo-sabin --interior-corners …`): the same verdict.
      const LocalMatrix S =
          local_matrix(MeshScheme::doo_sabin, 4,
                       {.boundary = true, .interior_corners = {inner[0], inner[1], inner[2], inner[3]}});
      const C1Verdict direct = c1_verdict(S, local_spectrum(S));
      CHECK(direct.c1 == v.verdict.c1);
      CHECK(direct.angle == v.verdict.angle);
      CHECK(sector_sizes(4, S.options).size() == static_cast<std::size_t>(runs));
    }
    CHECK(a.isolated == off + static_cast<int>(std::count(around.begin(), around.end(), 0)));
  }
}

TEST_CASE("doo-sabin at the boundary: the principal submatrix is closed and its spectrum exact",
          "[subdivision][mesh_analysis][doo_sabin]") {
  // Interior corners by mask, k = 3, 4, 6 (rational weights): every kept row weighs nothing outside
  // the kept columns of the whole k-gon's matrix (so the submatrix is the refinement there), and the
  // spectrum is the k-gon's own block 1, ½, ½, ¼ (k − 3 times), then ¼ and ⅛ per kept edge quad and
  // 1/16 per kept corner quad — proved by ranks: rank((S − λ)^m) = N − m for each claimed λ of
  // multiplicity m, the m's summing to N.
  const std::vector<std::pair<int, std::vector<int>>> cases{
      {3, {1, 3}}, {4, {1, 3, 5, 7}}, {6, {1, 3, 5, 7, 11, 21, 31}}};  // each class up to rotation
  std::size_t index = 0;
  for (const auto& [k, masks] : cases)
    for (const int mask : masks) {
      if (cifs_test::skipped_when_sanitized(index++)) continue;
      std::vector<char> inner(static_cast<std::size_t>(k));
      for (int i = 0; i < k; ++i) inner[static_cast<std::size_t>(i)] = (mask >> i) & 1 ? 1 : 0;
      INFO(k << "-gon, interior corners mask " << mask);
      const LocalMatrix S = doo_sabin_boundary_matrix(inner);
      const LocalMatrix whole = local_matrix(MeshScheme::doo_sabin, k);
      REQUIRE(S.exact);
      const int N = S.exact->rows;
      std::vector<int> kept;
      for (const std::string& label : S.labels)
        kept.push_back(static_cast<int>(std::find(whole.labels.begin(), whole.labels.end(), label) -
                                        whole.labels.begin()));
      for (const int i : kept)
        for (int j = 0; j < whole.exact->cols; ++j)
          if (std::find(kept.begin(), kept.end(), j) == kept.end()) CHECK((*whole.exact)(i, j) == 0);
      int edges = 0, corners = 0;
      for (int i = 0; i < k; ++i) {
        const bool here = inner[static_cast<std::size_t>(i)] != 0,
                   next = inner[static_cast<std::size_t>((i + 1) % k)] != 0;
        edges += here || next ? 1 : 0;
        corners += here ? 1 : 0;
      }
      const std::map<Rational, int> claimed{
          {q(1), 1}, {q(1, 2), 2}, {q(1, 4), k - 3 + edges}, {q(1, 8), edges}, {q(1, 16), corners}};
      int total = 0;
      for (const auto& [lambda, m] : claimed) {
        if (m == 0) continue;
        total += m;
        CHECK(cifs_test::exact_rank(cifs_test::shifted_power(*S.exact, lambda, m)) == N - m);
      }
      CHECK(total == N);
    }
}

TEST_CASE("doo-sabin at the boundary: the same spectrum where the weights have irrational cosines",
          "[subdivision][mesh_analysis][doo_sabin]") {
  // k = 5, 7, 8 in long double: the k-gon's block, then ¼, ⅛ per kept edge quad, 1/16 per corner quad.
  for (const int k : {5, 7, 8})
    for (const int mask : {1, 3, 5}) {
      std::vector<char> inner(static_cast<std::size_t>(k));
      int edges = 0, corners = 0;
      for (int i = 0; i < k; ++i) inner[static_cast<std::size_t>(i)] = (mask >> i) & 1 ? 1 : 0;
      for (int i = 0; i < k; ++i) {
        edges += inner[static_cast<std::size_t>(i)] || inner[static_cast<std::size_t>((i + 1) % k)] ? 1 : 0;
        corners += inner[static_cast<std::size_t>(i)];
      }
      INFO(k << "-gon, interior corners mask " << mask);
      const LocalMatrix S = doo_sabin_boundary_matrix(inner);
      CHECK_FALSE(S.exact);
      std::vector<std::complex<long double>> expected{1.0L, 0.5L, 0.5L};
      expected.insert(expected.end(), static_cast<std::size_t>(k - 3 + edges), 0.25L);
      expected.insert(expected.end(), static_cast<std::size_t>(edges), 0.125L);
      expected.insert(expected.end(), static_cast<std::size_t>(corners), 0.0625L);
      cifs_test::check_same_spectrum(local_spectrum(S).eigenvalues, expected, 1e-12L);
    }
}

TEST_CASE("doo-sabin at the boundary: the cut surface is part of the whole one; a pinch stays a pinch",
          "[subdivision][mesh_analysis][doo_sabin]") {
  // The reason the verdicts are the interior k-gon's restricted: every point of the cut grid's
  // refinement is a point of the whole grid's (same positions), three levels down.
  const Mesh whole = cut_grid(4, {}), cut = cut_grid(4, {{0, 0}, {2, 2}});
  const Mesh W = subdivide(whole, MeshScheme::doo_sabin, 3), C = subdivide(cut, MeshScheme::doo_sabin, 3);
  std::vector<std::array<double, 3>> points;
  for (Eigen::Index v = 0; v < W.vertices.rows(); ++v)
    points.push_back({W.vertices(v, 0), W.vertices(v, 1), W.vertices(v, 2)});
  std::sort(points.begin(), points.end());
  for (Eigen::Index v = 0; v < C.vertices.rows(); ++v) {
    const std::array<double, 3> x{C.vertices(v, 0), C.vertices(v, 1), C.vertices(v, 2)};
    const auto it = std::lower_bound(points.begin(), points.end(), std::array{x[0] - 1e-12, x[1], x[2]});
    bool found = false;
    for (auto j = it; j != points.end() && (*j)[0] <= x[0] + 1e-12 && !found; ++j)
      found = std::abs((*j)[1] - x[1]) < 1e-12 && std::abs((*j)[2] - x[2]) < 1e-12;
    CHECK(found);
  }
  // Face (1, 1) — face 4 of the cut grid — keeps its index level to level (the F-faces come first) and
  // its corners 0 and 2 stay on the boundary, 1 and 3 inside: the boundary reaches its centre from two
  // sides at every level.
  const auto pinched = [&](const Mesh& m) {
    const MeshTopology t = build_topology(m, "test");
    std::vector<char> on;
    for (const int c : face(t, 4)) on.push_back(t.boundary_vertex[static_cast<std::size_t>(c)]);
    return on == std::vector<char>{1, 0, 1, 0};
  };
  CHECK(pinched(cut));
  CHECK(pinched(C));
  CHECK_FALSE(analyze_mesh(cut, MeshScheme::doo_sabin).vertices.empty());
}

TEST_CASE("analyze_mesh under doo-sabin refuses what has no analysis, naming the face or vertex",
          "[subdivision][mesh_analysis][doo_sabin]") {
  CHECK_THROWS_WITH(analyze_mesh(cifs_test::bipyramid_of(17), MeshScheme::doo_sabin),
                    Contains("vertex 17: doo-sabin: valence 17 is out of range"));
  // A prism over a 17-gon: the 17-gons' corners are interior (valence 3), so face 0 is analysed.
  std::vector<std::array<double, 3>> p;
  std::vector<std::vector<int>> f(2);
  for (int i = 0; i < 17; ++i) {
    const double a = 2 * std::numbers::pi * i / 17;
    p.push_back({std::cos(a), std::sin(a), 0});
    p.push_back({std::cos(a), std::sin(a), 1});
    f[0].insert(f[0].begin(), 2 * i);
    f[1].push_back(2 * i + 1);
    f.push_back({2 * i, (2 * i + 2) % 34, (2 * i + 3) % 34, 2 * i + 1});
  }
  CHECK_THROWS_WITH(analyze_mesh(make_mesh(p, f), MeshScheme::doo_sabin),
                    Contains("face 0: doo-sabin: valence 17 is out of range"));
  Mesh tagged = cifs_test::cube();
  tagged.tags.corners = {{0, kInfiniteSharpness}};
  CHECK_THROWS_WITH(analyze_mesh(tagged, MeshScheme::doo_sabin),
                    Contains("doo-sabin has no rules for creases"));
}
