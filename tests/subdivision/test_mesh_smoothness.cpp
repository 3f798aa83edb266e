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
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/topology.hpp"
#include "subdivision/meshes.hpp"
#include "subdivision/rational.hpp"

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
  // undecided at 1 and 6 — Jordan blocks —, not C1 at 4, 5, 7 and 8).
  const std::map<int, const char*> expected{{1, "undecided"}, {2, "C1"},     {3, "C1"}, {4, "not C1"},
                                            {5, "not C1"},    {6, "undecided"}, {7, "not C1"}, {8, "not C1"}};
  const auto word = [](const C1Verdict& v) { return v.c1 ? "C1" : v.decided ? "not C1" : "undecided"; };
  for (int k = 1; k <= 8; ++k) {
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
  // Interior: ZSS's stencils at valences 3 … 8 (bipyramid apexes; the equator has valence 4), C1.
  for (int k = 3; k <= 8; ++k) {
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
  for (const int k : {2, 4, 5, 7}) {
    INFO(k << " faces");
    const Mesh fan = open_fan(k);
    const bool c1 = analyze_mesh(fan, MeshScheme::butterfly).vertices.front().verdict.c1;
    REQUIRE(analyze_mesh(fan, MeshScheme::butterfly).vertices.front().vertex == 0);
    std::vector<double> spread;
    Mesh level = subdivide(fan, MeshScheme::butterfly, 3);
    for (int l = 3; l <= 7; ++l) {
      spread.push_back(normal_spread(level, 0));
      if (l < 7) level = subdivide(level, MeshScheme::butterfly, 1);
    }
    UNSCOPED_INFO("spread (degrees) " << spread[0] * 180 / std::numbers::pi << " … "
                                      << spread.back() * 180 / std::numbers::pi);
    CHECK((spread.back() < 0.2 * spread.front()) == c1);
  }
}
