// SPDX-License-Identifier: MIT
// Creases, corners, holes and face-varying channels: properties that need no oracle (the
// OpenSubdiv comparison is test_mesh_features.cpp) — sharpness 0 is no crease, an integer sharpness
// s is s sharp levels then the smooth rules, refining twice equals refining two levels with the tags
// carried, an infinitely sharp crease loop is the cubic B-spline of its vertices, affine invariance,
// counts, and bad input refused with one line.
#include <catch2/catch.hpp>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "subdivision/meshes.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;

namespace {

double tags_max_difference(const Points& a, const Points& b) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  return a.rows() == 0 ? 0.0 : (a - b).cwiseAbs().maxCoeff();
}

/// A torus of quads (or triangles) with a semi-sharp crease ring, a sharp segment, a corner and a hole.
Mesh tagged_torus(bool triangles) {
  Mesh m = torus(8, 6, triangles);
  for (int i = 0; i < 8; ++i) m.tags.creases.push_back({i, (i + 1) % 8, 0.5 + 0.25 * i});
  m.tags.creases.push_back({8 * 3, 8 * 3 + 1, 10});
  m.tags.corners = {{8 * 4 + 2, 2.5}};
  m.tags.holes = {5};
  return m;
}

bool same_tags(const MeshTags& a, const MeshTags& b) {
  const auto key = [](const EdgeSharpness& c) {
    return std::tuple(std::min(c.a, c.b), std::max(c.a, c.b), c.sharpness);
  };
  std::vector<std::tuple<int, int, double>> ca, cb;
  for (const auto& c : a.creases) ca.push_back(key(c));
  for (const auto& c : b.creases) cb.push_back(key(c));
  std::sort(ca.begin(), ca.end());
  std::sort(cb.begin(), cb.end());
  std::vector<std::pair<int, double>> va, vb;
  for (const auto& c : a.corners) va.emplace_back(c.vertex, c.sharpness);
  for (const auto& c : b.corners) vb.emplace_back(c.vertex, c.sharpness);
  std::sort(va.begin(), va.end());
  std::sort(vb.begin(), vb.end());
  std::vector<int> ha = a.holes, hb = b.holes;
  std::sort(ha.begin(), ha.end());
  std::sort(hb.begin(), hb.end());
  return ca == cb && va == vb && ha == hb && a.boundary == b.boundary && a.crease_method == b.crease_method;
}

}  // namespace

TEST_CASE("sharpness 0 is no crease: the same bits as the plain mesh", "[subdivision][mesh][creases]") {
  for (const bool triangles : {false, true}) {
    const Mesh plain = torus(6, 5, triangles);
    Mesh zero = plain;
    for (int i = 0; i < 6; ++i) zero.tags.creases.push_back({i, (i + 1) % 6, 0});
    zero.tags.corners = {{3, 0}};
    const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
    const Mesh a = subdivide(plain, scheme, 3), b = subdivide(zero, scheme, 3);
    CHECK(a.vertices == b.vertices);
    CHECK(a.face_vertices == b.face_vertices);
    CHECK(b.tags.creases.empty());
    CHECK(b.tags.corners.empty());
  }
}

TEST_CASE("an integer sharpness s: the sharp rules for s levels, then the smooth ones",
          "[subdivision][mesh][creases]") {
  for (const bool triangles : {false, true})
    for (const int s : {1, 2, 3}) {
      const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
      Mesh semi = torus(6, 5, triangles), sharp = semi;
      for (int i = 0; i < 6; ++i) {
        semi.tags.creases.push_back({i, (i + 1) % 6, double(s)});
        sharp.tags.creases.push_back({i, (i + 1) % 6, kInfiniteSharpness});
      }
      INFO(scheme_name(scheme) << ", sharpness " << s);
      // s levels: exactly the infinitely sharp crease.
      const Mesh a = subdivide(semi, scheme, s), b = subdivide(sharp, scheme, s);
      CHECK(tags_max_difference(a.vertices, b.vertices) == 0);
      CHECK(a.tags.creases.empty());  // decayed to 0
      // One more level: the smooth rules on the level-s mesh.
      Mesh plain = a;
      plain.tags = MeshTags{};
      CHECK(tags_max_difference(subdivide(semi, scheme, s + 1).vertices,
                                subdivide(plain, scheme, 1).vertices) <= 1e-14);
    }
}

TEST_CASE("refining twice equals refining two levels: tags, holes and UVs carried",
          "[subdivision][mesh][creases]") {
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop, MeshScheme::bilinear})
    for (const CreaseMethod method : {CreaseMethod::uniform, CreaseMethod::chaikin})
      for (const BoundaryRule rule :
           {BoundaryRule::none, BoundaryRule::edge_only, BoundaryRule::edge_and_corner}) {
        const bool triangles = scheme == MeshScheme::loop;
        Mesh m = tagged_torus(triangles);
        if (rule != BoundaryRule::edge_only) {  // an open mesh for the boundary rules
          m = quad_grid(5, 4, triangles);
          m.tags.creases = {{7, 8, 1.5}, {8, 9, 0.7}, {9, 10, 10}, {13, 14, 2.2}};
          m.tags.corners = {{15, 1.2}};
          m.tags.holes = {3};
        }
        m.tags.boundary = rule;
        m.tags.crease_method = method;
        FaceVaryingChannel uv;
        uv.values.resize(m.vertices.rows(), 2);
        uv.values.col(0) = m.vertices.col(0);
        uv.values.col(1) = m.vertices.col(1);
        uv.indices = m.face_vertices;
        m.face_varying = {uv};
        INFO(scheme_name(scheme) << ", " << option_name(method) << ", boundary " << option_name(rule));
        for (int first = 1; first <= 2; ++first) {
          const Mesh once = subdivide(subdivide(m, scheme, first), scheme, 1),
                     at_once = subdivide(m, scheme, first + 1);
          CHECK(tags_max_difference(once.vertices, at_once.vertices) <= 1e-14);
          CHECK(once.face_vertices == at_once.face_vertices);
          CHECK(same_tags(once.tags, at_once.tags));
          REQUIRE(once.face_varying.size() == 1);
          CHECK(once.face_varying[0].indices == at_once.face_varying[0].indices);
          CHECK(tags_max_difference(once.face_varying[0].values, at_once.face_varying[0].values) <= 1e-15);
        }
        // The refinement records the same tags level by level.
        const MeshRefinement r = refine_topology(m, scheme, 2);
        CHECK(same_tags(r.tags[2], subdivide(m, scheme, 2).tags));
        CHECK(tags_max_difference(apply(r, m.vertices), subdivide(m, scheme, 2).vertices) <= 1e-14);
      }
}

TEST_CASE(
    "an infinitely sharp crease loop of Catmull–Clark is the cubic B-spline of its vertices, every level",
    "[subdivision][mesh][creases]") {
  Mesh m = torus(8, 6);
  for (int i = 0; i < 8; ++i) m.tags.creases.push_back({i, (i + 1) % 8, kInfiniteSharpness});
  Points ring(8, 3);
  for (int i = 0; i < 8; ++i) ring.row(i) = m.vertices.row(i);
  nurbs::Curve curve = nurbs::uniform_bspline(ring, 3, true);
  for (int levels = 1; levels <= 4; ++levels) {
    curve = nurbs::refine_midpoints(curve);
    const Mesh refined = subdivide(m, MeshScheme::catmull_clark, levels);
    const auto n = static_cast<int>(nurbs::distinct_count(curve));
    REQUIRE(n == 8 << levels);
    double worst = 0;
    for (int k = 0; k < n; ++k) {
      double best = std::numeric_limits<double>::infinity();
      for (Eigen::Index v = 0; v < refined.vertices.rows(); ++v)
        best = std::min(best, (refined.vertices.row(v) - curve.P.row(k)).cwiseAbs().maxCoeff());
      worst = std::max(worst, best);
    }
    INFO("level " << levels);
    CHECK(worst <= 1e-12 * m.vertices.cwiseAbs().maxCoeff());
    CHECK(refined.tags.creases.size() ==
          static_cast<std::size_t>(n));  // the crease carried, infinitely sharp
  }
}

TEST_CASE(
    "a face-varying seam loop refines as the cubic B-spline of each side's values (smooth rules), "
    "as their midpoints under 'boundaries'",
    "[subdivision][mesh][uv]") {
  // A torus whose channel has one seam, the closed loop of column 0: random values, and the faces
  // of column 7 give the loop's vertices other random values.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-0.2, 0.2);
  for (const bool triangles : {false, true}) {
    Mesh m = torus(8, 6, triangles);
    FaceVaryingChannel c;
    c.values.resize(48 + 6, 2);
    for (int v = 0; v < 54; ++v) c.values.row(v) << (v % 8) / 8.0 + noise(rng), (v / 8) / 6.0 + noise(rng);
    for (std::size_t f = 0; f < face_count(m); ++f) {
      const auto corners = face(m, f);
      const bool past = std::any_of(corners.begin(), corners.end(), [](int v) { return v % 8 == 7; });
      for (const int v : corners) c.indices.push_back(past && v % 8 == 0 ? 48 + v / 8 : v);
    }
    m.face_varying = {c};
    const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
    for (const FaceVaryingRule rule :
         {FaceVaryingRule::none, FaceVaryingRule::corners_only, FaceVaryingRule::corners_plus1,
          FaceVaryingRule::corners_plus2, FaceVaryingRule::boundaries}) {
      m.tags.face_varying = rule;
      for (const bool other_side : {false, true}) {
        Points ring(6, 2);
        for (int j = 0; j < 6; ++j) ring.row(j) = c.values.row(other_side ? 48 + j : 8 * j);
        nurbs::Curve curve = nurbs::uniform_bspline(ring, rule == FaceVaryingRule::boundaries ? 1 : 3, true);
        for (int levels = 1; levels <= 3; ++levels) {
          curve = nurbs::refine_midpoints(curve);
          const FaceVaryingChannel refined = subdivide(m, scheme, levels).face_varying.at(0);
          double worst = 0;
          for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(nurbs::distinct_count(curve)); ++k) {
            double best = std::numeric_limits<double>::infinity();
            for (Eigen::Index v = 0; v < refined.values.rows(); ++v)
              best = std::min(best, (refined.values.row(v) - curve.P.row(k)).cwiseAbs().maxCoeff());
            worst = std::max(worst, best);
          }
          INFO(scheme_name(scheme) << ", rule " << option_name(rule) << ", side " << other_side << ", level "
                                   << levels);
          CHECK(worst <= 1e-14);
        }
      }
    }
  }
}

TEST_CASE("face-varying rules: refining twice equals refining two levels (no semi-sharp feature)",
          "[subdivision][mesh][uv]") {
  for (const FaceVaryingRule rule :
       {FaceVaryingRule::none, FaceVaryingRule::corners_only, FaceVaryingRule::corners_plus1,
        FaceVaryingRule::corners_plus2, FaceVaryingRule::boundaries})
    for (const bool triangles : {false, true})
      for (unsigned seed = 1; seed <= 4; ++seed) {
        std::mt19937 rng(seed);
        Mesh m = seed % 2 == 0 ? torus(6, 5, triangles) : wavy_grid(4, 4, triangles);
        m.face_varying = {random_seams(m, rng)};
        m.tags.creases = {{0, 1, kInfiniteSharpness}, {1, 2, kInfiniteSharpness}};
        m.tags.corners = {{7, kInfiniteSharpness}};
        m.tags.boundary = static_cast<BoundaryRule>(seed % 3);
        m.tags.face_varying = rule;
        const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
        INFO(scheme_name(scheme) << ", rule " << option_name(rule) << ", seed " << seed);
        const Mesh once = subdivide(subdivide(m, scheme, 1), scheme, 1), at_once = subdivide(m, scheme, 2);
        REQUIRE(once.face_varying.size() == 1);
        CHECK(once.face_varying[0].indices == at_once.face_varying[0].indices);
        CHECK(tags_max_difference(once.face_varying[0].values, at_once.face_varying[0].values) <= 1e-15);
      }
}

TEST_CASE("creased subdivision is affine invariant and counts follow the formulas",
          "[subdivision][mesh][creases]") {
  Eigen::Matrix3d A;
  A << 1.2, 0.3, -0.1, 0.2, 0.9, 0.4, -0.3, 0.1, 1.1;
  const Eigen::RowVector3d b(0.5, -2, 3);
  for (const bool triangles : {false, true}) {
    const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
    const Mesh m = tagged_torus(triangles);
    Mesh moved = m;
    moved.vertices = (m.vertices * A.transpose()).rowwise() + b;
    const Mesh r = subdivide(m, scheme, 3), rm = subdivide(moved, scheme, 3);
    const Points expected = (r.vertices * A.transpose()).rowwise() + b;
    CHECK(tags_max_difference(rm.vertices, expected) <= 1e-12 * expected.cwiseAbs().maxCoeff());
    const MeshRefinement refinement = refine_topology(m, scheme, 3);
    for (std::size_t k = 0; k + 1 < refinement.levels.size(); ++k) {
      const MeshTopology &t = refinement.levels[k], &c = refinement.levels[k + 1];
      const auto V = t.vertex_count, E = static_cast<int>(t.edges.size()),
                 F = static_cast<int>(face_count(t));
      CHECK(c.vertex_count == (triangles ? V + E : V + E + F));
      CHECK(face_count(c) == (triangles ? 4 * face_count(t) : t.face_vertices.size()));
      // Holes: the children of holes, and no other face.
      CHECK(refinement.tags[k + 1].holes.size() == (triangles ? 4 : 4) * refinement.tags[k].holes.size());
    }
  }
}

TEST_CASE("bad tags are refused with one line naming them", "[subdivision][mesh][creases]") {
  const auto refused = [](const Mesh& m, MeshScheme scheme, const std::string& text) {
    INFO(text);
    CHECK_THROWS_WITH(subdivide(m, scheme, 1), Catch::Contains(text));
  };
  Mesh m = cube();
  m.tags.creases = {{0, 1, std::nan("")}};
  refused(m, MeshScheme::catmull_clark, "sharpness NaN");
  m.tags.creases = {{0, 1, -1}};
  refused(m, MeshScheme::catmull_clark, "sharpness -1");
  m.tags.creases = {{0, 6, 2}};
  refused(m, MeshScheme::catmull_clark, "crease 0 joins vertices 0 and 6, which are not an edge");
  m.tags.creases = {{0, 1, 2}, {1, 0, 3}};
  refused(m, MeshScheme::catmull_clark, "creased twice");
  m.tags.creases = {{0, 9, 2}};
  refused(m, MeshScheme::catmull_clark, "out of range");
  m.tags.creases.clear();
  m.tags.holes = {0, 1, 2, 3, 4, 5};
  refused(m, MeshScheme::catmull_clark, "every face is a hole");
  m.tags.holes = {6};
  refused(m, MeshScheme::catmull_clark, "hole face 6 is out of range");
  m.tags.holes.clear();
  m.tags.corners = {{2, 1}, {2, 3}};
  refused(m, MeshScheme::catmull_clark, "vertex 2 has two corner sharpnesses");
  m.tags.corners = {{2, 1}};
  refused(m, MeshScheme::doo_sabin, "doo-sabin: the mesh has a corner (vertex 2, sharpness 1)");
  CHECK_THROWS_WITH(factored_subdivide(m, MeshScheme::catmull_clark, 1),
                    Catch::Contains("the factored form"));
  m.tags.corners.clear();
  FaceVaryingChannel uv;
  uv.values = Points::Zero(4, 2);
  uv.indices.assign(m.face_vertices.size(), 0);
  uv.indices[5] = 4;
  m.face_varying = {uv};
  refused(m, MeshScheme::catmull_clark, "corner 5 refers to value 4, out of range (4 values)");
  m.face_varying[0].indices.pop_back();
  refused(m, MeshScheme::catmull_clark, "23 corner indices for 24 face corners");
  m.face_varying[0].indices.assign(m.face_vertices.size(), 0);
  refused(m, MeshScheme::doo_sabin,
          "doo-sabin: the mesh has a face-varying channel 'uv'; this scheme does not split");
  Mesh tri = tetrahedron();
  tri.face_varying = {uv};
  tri.face_varying[0].indices.assign(tri.face_vertices.size(), 0);
  refused(tri, MeshScheme::sqrt3, "this scheme does not split faces");
  tri.tags.face_varying = FaceVaryingRule::corners_only;
  refused(tri, MeshScheme::butterfly, "butterfly interpolates face-varying data linearly only");
  m.tags.face_varying = FaceVaryingRule::corners_only;
  m.tags.rules = RuleSet::blz;
  refused(m, MeshScheme::catmull_clark, "not built under the rule set 'blz'");
}

namespace {

void check_same_tags(const MeshTags& a, const MeshTags& b) {
  REQUIRE(a.creases.size() == b.creases.size());
  for (std::size_t i = 0; i < a.creases.size(); ++i) {
    CHECK(a.creases[i].a == b.creases[i].a);
    CHECK(a.creases[i].b == b.creases[i].b);
    CHECK(a.creases[i].sharpness == b.creases[i].sharpness);
  }
  REQUIRE(a.corners.size() == b.corners.size());
  for (std::size_t i = 0; i < a.corners.size(); ++i) {
    CHECK(a.corners[i].vertex == b.corners[i].vertex);
    CHECK(a.corners[i].sharpness == b.corners[i].sharpness);
  }
  CHECK(a.holes == b.holes);
}

void check_same_levels(const MeshTopology& a, const MeshTopology& b, bool adjacency) {
  CHECK(a.vertex_count == b.vertex_count);
  CHECK(a.face_offsets == b.face_offsets);
  CHECK(a.face_vertices == b.face_vertices);
  if (!adjacency) return;
  CHECK(a.edges == b.edges);
  CHECK(a.edge_faces == b.edge_faces);
  CHECK(a.vertex_edge_list == b.vertex_edge_list);
  CHECK(a.vertex_face_list == b.vertex_face_list);
  CHECK(a.boundary_vertex == b.boundary_vertex);
}

/// refine_topology without weights and/or the last level's adjacency makes the same faces, tags and
/// features as the full refinement (which the cases above check against OpenSubdiv), and refuses to
/// replay what it did not keep.
void check_topology_only(const Mesh& m, MeshScheme scheme, int levels) {
  INFO(scheme_name(scheme) << ", " << levels << " levels");
  const MeshRefinement full = refine_topology(m, scheme, levels);
  for (const bool adjacency : {true, false}) {
    const MeshRefinement r =
        refine_topology(m, scheme, levels, MeshOptions{.weights = false, .last_level_adjacency = adjacency});
    CHECK(r.steps.empty());
    REQUIRE(r.levels.size() == full.levels.size());
    REQUIRE(r.features.size() == full.features.size() - (adjacency || levels == 0 ? 0 : 1));
    for (std::size_t k = 0; k < r.levels.size(); ++k) {
      INFO("level " << k);
      check_same_levels(r.levels[k], full.levels[k], adjacency || k + 1 < r.levels.size());
      check_same_tags(r.tags[k], full.tags[k]);
      if (k < r.features.size()) {
        CHECK(r.features[k].edge_sharpness == full.features[k].edge_sharpness);
        CHECK(r.features[k].vertex_sharpness == full.features[k].vertex_sharpness);
        CHECK(r.features[k].holes == full.features[k].holes);
      }
    }
    if (levels == 0) continue;  // nothing to replay
    CHECK_THROWS_WITH(apply(r, m.vertices), Catch::Contains("without its weights"));
    CHECK_THROWS_WITH(stencil_table(r), Catch::Contains("without its weights"));
  }
  const MeshRefinement faces_only =
      refine_topology(m, scheme, levels, MeshOptions{.last_level_adjacency = false});
  CHECK(faces_only.steps.size() == full.steps.size());
  if (levels > 0) CHECK_THROWS_WITH(limit_stencils(faces_only), Catch::Contains("faces only"));
}

}  // namespace

TEST_CASE("topology only (no weights, the last level's faces only) = the full refinement's topology and tags",
          "[subdivision][mesh][creases]") {
  for (unsigned seed = 1; seed <= 8; ++seed) {
    std::mt19937 rng(seed);
    const bool triangles = seed % 2 == 0;
    Mesh m = seed % 4 < 2 ? torus(4, 3, triangles) : wavy_grid(3, 3, triangles);
    random_tags(m, rng, seed % 3 != 0);
    if (seed % 4 == 1) m.tags.crease_method = CreaseMethod::chaikin;
    INFO("seed " << seed);
    check_topology_only(m, MeshScheme::bilinear, 2);
    if (seed == 5) m.tags.rules = RuleSet::blz;
    check_topology_only(m, triangles ? MeshScheme::loop : MeshScheme::catmull_clark, 3);
  }
  check_topology_only(torus(4, 3, true), MeshScheme::butterfly, 2);
  check_topology_only(wavy_grid(3, 3, true), MeshScheme::sqrt3, 3);
  check_topology_only(torus(4, 3, false), MeshScheme::doo_sabin, 2);
  check_topology_only(torus(4, 3, false), MeshScheme::catmull_clark, 0);
}
