// SPDX-License-Identifier: MIT
// Butterfly's limit normals (limit_stencils, limit_mesh) against routes that do not use them: the
// production refiner run deep (the normals of the refined faces at a vertex reach ours at the rate
// |μ|/λ1 of its local spectrum), exact rationals (the regular mask is a left eigenvector of S_6),
// planes (a planar mesh's normal), affine maps (tangents are mapped by the linear part) and the
// refinement itself (the normal computed at level k is the one computed at k + 1, k + 2).
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "subdivision/meshes.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

/// A closed mesh with extraordinary vertices of valence 3, 4, 5, 7 and 8, some of them next to each
/// other: the bipyramid over an octagon (apexes 8, equator 4) with the edge from the lower apex to
/// equator vertex 0 flipped (apex 7, vertex 0 3, vertices 1 and 7 5), every vertex moved a little.
Mesh mixed_valences() {
  Mesh m = bipyramid_of(8);
  m.face_offsets = {0};
  m.face_vertices.clear();
  for (int i = 0; i < 8; ++i) {
    add_face(m, {i, (i + 1) % 8, 8});
    if (i != 0 && i != 7) add_face(m, {(i + 1) % 8, i, 9});
  }
  add_face(m, {1, 0, 7});
  add_face(m, {1, 7, 9});
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  m.vertices = m.vertices.unaryExpr([&](double x) { return x + jitter(rng); });
  m.vertices.row(0) *= 1.3;  // out of the flipped face's plane
  return m;
}

Eigen::RowVector3d frame_normal(const Points& u, const Points& v, Eigen::Index i) {
  const Eigen::Vector3d a = u.row(i).transpose(), b = v.row(i).transpose();
  return a.cross(b).normalized().transpose();
}

/// The largest distance from `normal` of the unit normals of the faces around vertex v: each face
/// sees the ring's modes beyond the tangent plane's (a sum over the ring would cancel some by symmetry).
double face_normal_error(const MeshTopology& t, const Points& x, int v, const Eigen::RowVector3d& normal) {
  double out = 0;
  for (const int f : vertex_faces(t, static_cast<std::size_t>(v))) {
    const auto c = face(t, static_cast<std::size_t>(f));
    const Eigen::Vector3d a = x.row(c[0]).transpose(), b = x.row(c[1]).transpose(),
                          d = x.row(c[2]).transpose();
    out = std::max(out, ((b - a).cross(d - a).normalized().transpose() - normal).norm());
  }
  return out;
}

/// Limit frame of the mesh after `level` steps.
LimitFrame frame_at(const Mesh& mesh, int level) {
  const MeshRefinement r = refine_topology(mesh, MeshScheme::butterfly, level);
  return evaluate_limit(limit_stencils(r), apply(r, mesh.vertices));
}

}  // namespace

TEST_CASE("butterfly's tangent masks are the left eigenvectors of S_n for its subdominant 1/2",
          "[subdivision][limit][butterfly]") {
  // n = 6, exact: a_j = cos(jπ/3) on r_j, a_j/16 on p_j, −(a_j + a_{j+1})/6 on q_j (limit.cpp's
  // butterfly_mask), and the same shifted by a third of a turn (rational too; with the first it spans
  // the pair's plane, as cos and sin do): l·S_6 = ½·l in rationals, entry by entry.
  const LocalMatrix S6 = local_matrix(MeshScheme::butterfly, 6);
  REQUIRE(S6.exact);
  const std::array<Rational, 6> cosine{Rational(1),  Rational(1, 2),  Rational(-1, 2),
                                       Rational(-1), Rational(-1, 2), Rational(1, 2)};
  for (const int shift : {0, 2}) {
    std::vector<Rational> l(19, Rational(0));
    const auto a = [&](int j) { return cosine[static_cast<std::size_t>(((j + shift) % 6 + 6) % 6)]; };
    for (int j = 0; j < 6; ++j) {
      l[1 + 3 * static_cast<std::size_t>(j)] = a(j);
      l[2 + 3 * static_cast<std::size_t>(j)] = a(j) / 16;
      l[3 + 3 * static_cast<std::size_t>(j)] = -(a(j) + a(j + 1)) / 6;
    }
    for (int col = 0; col < 19; ++col) {
      Rational sum(0);
      for (int row = 0; row < 19; ++row) sum += l[static_cast<std::size_t>(row)] * (*S6.exact)(row, col);
      CHECK(sum == l[static_cast<std::size_t>(col)] / 2);
    }
  }
  // n ≠ 6: cos(2πj/n), sin(2πj/n) on r_j and 0 elsewhere, valences 3 … 16 (long double). (½ is the
  // subdominant pair above μ = ¼ at every valence: test_mesh_analysis.cpp.)
  for (int n = 3; n <= 16; ++n) {
    if (n == 6) continue;
    INFO("valence " << n);
    const LocalMatrix S = local_matrix(MeshScheme::butterfly, n);
    for (const bool sine : {false, true}) {
      LongVector l = LongVector::Zero(3 * n + 1);
      for (int j = 0; j < n; ++j) {
        const long double angle = 2 * std::numbers::pi_v<long double> * j / n;
        l(1 + 3 * j) = sine ? std::sin(angle) : std::cos(angle);
      }
      CHECK((S.values.transpose() * l - l / 2).cwiseAbs().maxCoeff() < 1e-17L);
    }
  }
}

TEST_CASE("butterfly limit normals are the limit of the refined faces' normals, at the rate |mu|/lambda1",
          "[subdivision][limit][butterfly]") {
  // Normals computed at level 0 (extraordinary vertices next to each other: the mean of two ZSS
  // stencils) and at level 1 (regular vertices next to extraordinary ones), against the normals of the
  // faces around the same vertex after up to 6 steps of the production refiner. Their error e_k falls by
  // r = |μ|/λ1 of the vertex's S_n a step (½ at every valence: the test above): the last ratio within
  // 0.05 of r. At n = 6 μ = ¼ is defective (k·¼^k), so x_k = e_k / r^k grows linearly instead of
  // settling: its second difference vanishes (within 10 % of x at the last level; 5 % here). A wrong normal
  // stalls at its own error: the ratio goes to 1, x grows like 2^k and its second difference is x/4.
  const Mesh mesh = mixed_valences();
  const MeshRefinement deep = refine_topology(mesh, MeshScheme::butterfly, 6);
  std::vector<Points> data{mesh.vertices};
  for (const Stencils& s : deep.steps) data.push_back(apply(s, data.back()));
  std::vector<int> valences;
  std::map<int, double> rates;  // |μ|/λ1 by valence
  for (const int level : {0, 1}) {
    const LimitFrame f = frame_at(mesh, level);
    for (Eigen::Index v = 0; v < f.positions.rows(); ++v) {
      const int n = valence(deep.levels[static_cast<std::size_t>(level)], static_cast<std::size_t>(v));
      INFO("level " << level << ", vertex " << v << " (valence " << n << ")");
      if (!rates.contains(n)) {
        const LocalSpectrum spectrum = local_spectrum(local_matrix(MeshScheme::butterfly, n));
        rates[n] = static_cast<double>(std::abs(spectrum.mu) / spectrum.subdominant);
      }
      const double rate = rates[n];
      const Eigen::RowVector3d ours = frame_normal(f.tangent_u, f.tangent_v, v);
      std::vector<double> error;
      for (std::size_t k = static_cast<std::size_t>(level); k < data.size(); ++k)
        error.push_back(face_normal_error(deep.levels[k], data[k], static_cast<int>(v), ours));
      const std::size_t K = error.size() - 1;
      CHECK(error[K] < error[K - 1]);
      CHECK(error[K - 1] < error[K - 2]);
      if (n == 6) {
        const auto x = [&](std::size_t k) { return error[k] / std::pow(rate, static_cast<double>(k)); };
        CHECK(x(K) >= x(K - 1));
        CHECK(std::abs(x(K) - 2 * x(K - 1) + x(K - 2)) <= 0.1 * x(K));
      } else {
        CHECK(std::abs(error[K] / error[K - 1] - rate) <= 0.05);
      }
      if (level == 0) valences.push_back(n);
    }
  }
  std::sort(valences.begin(), valences.end());
  CHECK(valences == std::vector<int>{3, 4, 4, 4, 4, 4, 5, 5, 7, 8});
}

TEST_CASE("butterfly limit normals: the same at every level, exact on planes, covariant under affine maps",
          "[subdivision][limit][butterfly]") {
  const Mesh mesh = mixed_valences();
  // Every level's normal at the old vertices: levels 0 and 1 against the next two (at level 0 every vertex
  // goes through one step of its cut, at level 1 the regular ones next to extraordinary ones; at level 3 all
  // of them are on S_n's neighbourhood).
  for (const int first : {0, 1}) {
    const LimitFrame base = frame_at(mesh, first);
    for (const int level : {first + 1, first + 2}) {
      const LimitFrame finer = frame_at(mesh, level);
      for (Eigen::Index v = 0; v < base.positions.rows(); ++v) {
        INFO("level " << first << " against " << level << ", vertex " << v);
        CHECK(finer.positions.row(v) == base.positions.row(v));
        CHECK((frame_normal(finer.tangent_u, finer.tangent_v, v) -
               frame_normal(base.tangent_u, base.tangent_v, v))
                  .norm() <= 1e-13);
      }
    }
  }
  // An affine map of the data maps the tangents by its linear part.
  Eigen::Matrix3d A;
  A << 1.2, 0.3, -0.4, 0.1, 0.9, 0.2, -0.3, 0.5, 1.1;
  const Eigen::RowVector3d shift(3, -2, 5);
  for (const int level : {0, 1}) {
    const MeshRefinement r = refine_topology(mesh, MeshScheme::butterfly, level);
    const LimitStencils s = limit_stencils(r);
    const LimitFrame f = evaluate_limit(s, apply(r, mesh.vertices));
    const Points moved = (mesh.vertices * A.transpose()).rowwise() + shift;
    const LimitFrame g = evaluate_limit(s, apply(r, moved));
    const double scale = f.tangent_u.cwiseAbs().maxCoeff();
    CHECK((g.tangent_u - f.tangent_u * A.transpose()).cwiseAbs().maxCoeff() <= 1e-13 * scale);
    CHECK((g.tangent_v - f.tangent_v * A.transpose()).cwiseAbs().maxCoeff() <= 1e-13 * scale);
  }
  // A planar mesh: discs around valences 4, 5 and 7 (inner vertices next to the boundary and to the
  // centre), moved about in the plane z = 0.3x − 0.2y + 1; every vertex with tangents, levels 0 and 1,
  // takes the plane's normal: every interior vertex and the boundary vertices of 2 and 3 faces.
  const Eigen::RowVector3d plane = Eigen::RowVector3d(-0.3, 0.2, 1).normalized();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  for (const int k : {4, 5, 7}) {
    Mesh disc = fan(k);
    for (Eigen::Index v = 0; v < disc.vertices.rows(); ++v) {
      disc.vertices(v, 0) += jitter(rng);
      disc.vertices(v, 1) += jitter(rng);
      disc.vertices(v, 2) = 0.3 * disc.vertices(v, 0) - 0.2 * disc.vertices(v, 1) + 1;
    }
    for (const int level : {0, 1}) {
      INFO("valence " << k << ", level " << level);
      const MeshRefinement r = refine_topology(disc, MeshScheme::butterfly, level);
      const LimitStencils s = limit_stencils(r);
      const LimitFrame f = evaluate_limit(s, apply(r, disc.vertices));
      const MeshTopology& t = r.levels.back();
      for (int v = 0; v < t.vertex_count; ++v) {
        const LimitMask& m = s.masks[static_cast<std::size_t>(s.mask_of[static_cast<std::size_t>(v)])];
        if (m.tangent_u.empty()) {  // boundary vertices but of 2 and 3 faces (test_butterfly_boundary.cpp)
          CHECK(t.boundary_vertex[static_cast<std::size_t>(v)] != 0);
          const std::size_t faces = vertex_faces(t, static_cast<std::size_t>(v)).size();
          CHECK((faces != 2 && faces != 3));
          continue;
        }
        CHECK((frame_normal(f.tangent_u, f.tangent_v, v) - plane).norm() <= 1e-14);
      }
    }
  }
}

TEST_CASE("butterfly limit normals point out of convex shapes; boundary vertices are refused, named",
          "[subdivision][limit][butterfly]") {
  for (const Mesh& shape : {tetrahedron(), octahedron(), bipyramid_of(7)}) {
    const Mesh m = limit_mesh(shape, MeshScheme::butterfly, 1, {.normals = true});
    const Eigen::RowVector3d centre = shape.vertices.colwise().mean();
    for (Eigen::Index v = 0; v < m.vertices.rows(); ++v) {
      CHECK(std::abs(m.normals.row(v).norm() - 1) < 1e-14);
      CHECK(m.normals.row(v).dot(m.vertices.row(v) - centre) > 0);
    }
  }
  // Without normals an open mesh is fine: every vertex is its own limit.
  // (To round-off: limit_mesh replays the weights, butterfly applies the rules as it makes them.)
  CHECK((limit_mesh(fan(5), MeshScheme::butterfly, 1).vertices - butterfly(fan(5), 1).vertices)
            .cwiseAbs()
            .maxCoeff() <= 1e-15);
  // A mesh folded onto itself (two triangles on the same three vertices): after two levels some rings
  // repeat a vertex, and their masks read a ring edge that is not there (found by fuzz_mesh_compute,
  // tests/fuzz/regressions/mesh_compute/butterfly_folded_ring.bin). Those vertices are their own limit.
  const Mesh folded = make_mesh({{1, 1, 1}, {11, 1, -1}, {-1, -1, 1}}, {{0, 2, 1}, {0, 1, 2}});
  CHECK((limit_mesh(folded, MeshScheme::butterfly, 2).vertices - butterfly(folded, 2).vertices)
            .cwiseAbs()
            .maxCoeff() <= 1e-14);
  // A boundary vertex of 4 faces (vertex 0 of the local mesh) is not C1 under butterfly's boundary rule.
  CHECK_THROWS_WITH(
      limit_mesh(local_mesh(MeshScheme::butterfly, 5, {.boundary = true}, 2), MeshScheme::butterfly, 0,
                 {.normals = true}),
      "butterfly: vertex 0 (valence 5) is on the boundary with 4 faces (lambda1 = 0.5, lambda2 = 0.469042), "
      "where the local analysis finds not C1: the characteristic map sends a vertex next to the centre to "
      "the centre (the eigenvectors vanish on the sharp edges: the sector's curves shrink faster than its "
      "inside, not injective) (drop the normals)");
}

TEST_CASE("butterfly boundary normals (2 and 3 faces) are the limit of the refined faces' normals",
          "[subdivision][limit][butterfly]") {
  // fan(5)'s rim: boundary vertices of 2 and 3 faces, not planar. The normals computed at levels 0 and 1
  // against the normals of the faces around the vertex after up to 6 steps: their error falls by
  // r = |μ|/λ2 a step (λ1 ≥ λ2 the pair, μ the next: the tangent plane is spanned at λ2's pace; 2 faces:
  // ¼/0.469, 3 faces: ½).
  const Mesh mesh = fan(5);
  const MeshRefinement deep = refine_topology(mesh, MeshScheme::butterfly, 6);
  std::vector<Points> data{mesh.vertices};
  for (const Stencils& s : deep.steps) data.push_back(apply(s, data.back()));
  std::map<std::size_t, int> seen;  // boundary vertices by faces
  for (const int level : {0, 1}) {
    const LimitFrame f = frame_at(mesh, level);
    const MeshTopology& t = deep.levels[static_cast<std::size_t>(level)];
    for (int v = 0; v < t.vertex_count; ++v) {
      if (t.boundary_vertex[static_cast<std::size_t>(v)] == 0) continue;
      const std::size_t faces = vertex_faces(t, static_cast<std::size_t>(v)).size();
      INFO("level " << level << ", vertex " << v << " (" << faces << " faces)");
      ++seen[faces];
      const LocalSpectrum spectrum = local_spectrum(
          local_matrix(MeshScheme::butterfly, static_cast<int>(faces) + 1, {.boundary = true}));
      const double rate = static_cast<double>(std::abs(spectrum.mu) / spectrum.second);
      const Eigen::RowVector3d ours = frame_normal(f.tangent_u, f.tangent_v, v);
      std::vector<double> error;
      for (std::size_t k = static_cast<std::size_t>(level); k < data.size(); ++k)
        error.push_back(face_normal_error(deep.levels[k], data[k], v, ours));
      const std::size_t K = error.size() - 1;
      CHECK(error[K] < error[K - 1]);
      CHECK(error[K - 1] < error[K - 2]);
      // μ = ¼ is multiple at 2 and 3 faces (k·r^k, the ratio nears r from above as (k + 1)/k does):
      // x_k = e_k / r^k settles or grows linearly, its second difference vanishes (within 10 % of x); a
      // wrong normal stalls at its error, x grows like r^−k, the difference ≥ x/5.
      const auto x = [&](std::size_t k) { return error[k] / std::pow(rate, static_cast<double>(k)); };
      CHECK(std::abs(x(K) - 2 * x(K - 1) + x(K - 2)) <= 0.1 * x(K));
    }
  }
  CHECK(seen[2] == 10);
  CHECK(seen[3] > 10);
  // The same normal from levels 0, 1 and 2 (level 0 goes through one step; vertices keep their indices),
  // pointing up like the faces (fan(5) is a bumpy disc, counter-clockwise seen from above), and the
  // tangents mapped by an affine map's linear part.
  const LimitFrame base = frame_at(mesh, 0);
  for (const int level : {1, 2}) {
    const LimitFrame finer = frame_at(mesh, level);
    for (Eigen::Index v = 0; v < base.positions.rows(); ++v) {
      INFO("level " << level << ", vertex " << v);
      CHECK((frame_normal(finer.tangent_u, finer.tangent_v, v) -
             frame_normal(base.tangent_u, base.tangent_v, v))
                .norm() <= 1e-13);
      CHECK(frame_normal(finer.tangent_u, finer.tangent_v, v).z() > 0.5);
    }
  }
  Eigen::Matrix3d A;
  A << 1.2, 0.3, -0.4, 0.1, 0.9, 0.2, -0.3, 0.5, 1.1;
  const MeshRefinement r = refine_topology(mesh, MeshScheme::butterfly, 0);
  const LimitStencils s = limit_stencils(r);
  const LimitFrame f = evaluate_limit(s, mesh.vertices);
  const LimitFrame g =
      evaluate_limit(s, (mesh.vertices * A.transpose()).rowwise() + Eigen::RowVector3d(3, -2, 5));
  const double scale = f.tangent_u.cwiseAbs().maxCoeff();
  CHECK((g.tangent_u - f.tangent_u * A.transpose()).cwiseAbs().maxCoeff() <= 1e-13 * scale);
  CHECK((g.tangent_v - f.tangent_v * A.transpose()).cwiseAbs().maxCoeff() <= 1e-13 * scale);
}
