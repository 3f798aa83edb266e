// SPDX-License-Identifier: MIT
// Subdivision surfaces: properties that hold whatever the implementation — regular regions are the
// tensor products of the curve schemes, counts by Euler's formula, levels compose, affine
// invariance, Butterfly interpolates, the subdivision matrix is the weights — and bad input.
#include "cifs/subdivision/mesh.hpp"

#include <catch2/catch.hpp>
#include <chrono>

#include "cifs/errors.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/refine.hpp"
#include "cifs/subdivision/scheme.hpp"
#include "cifs/topology.hpp"
#include "subdivision/mesh_compare.hpp"
#include "subdivision/meshes.hpp"
#include "support/same_topology.hpp"
#include "support/sanitized.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

constexpr MeshScheme kAll[] = {MeshScheme::catmull_clark, MeshScheme::loop, MeshScheme::doo_sabin,
                               MeshScheme::butterfly, MeshScheme::sqrt3};

/// The n × m torus grid refined by a closed curve scheme along both grid directions: a
/// (2n) × (2m) grid (rows of 2n points).
Points tensor_refine(const Scheme& scheme, const Points& grid, int n, int m) {
  Points rows(2 * n * m, 3);
  for (int j = 0; j < m; ++j)
    rows.middleRows(2 * n * j, 2 * n) = refine(scheme, grid.middleRows(n * j, n), true);
  Points out(4 * n * m, 3);
  for (int i = 0; i < 2 * n; ++i) {
    Points column(m, 3);
    for (int j = 0; j < m; ++j) column.row(j) = rows.row(2 * n * j + i);
    const Points refined = refine(scheme, column, true);
    for (int j = 0; j < 2 * m; ++j) out.row(2 * n * j + i) = refined.row(j);
  }
  return out;
}

/// A scheme's dense stencils (k² weights at a vertex of valence k or a k-gon), kept: for small k they replay
/// the one-shot's points; for large k a refinement keeping them is refused before any work, saying why.
void check_kept_weights(const Mesh& m, MeshScheme scheme, int k) {
  if (k <= 40) {
    const MeshRefinement r = refine_topology(m, scheme, 2);
    CHECK((apply(r, m.vertices) - subdivide(m, scheme, 2).vertices).cwiseAbs().maxCoeff() <=
          1e-14 * m.vertices.cwiseAbs().maxCoeff());
  } else {
    MeshOptions options;
    options.max_bytes = std::size_t{1} << 30;
    CHECK_THROWS_WITH(refine_topology(m, scheme, 1, options),
                      Contains("of them the weights of faces or vertices of 16 or more sides"));
  }
}

/// A mesh that every scheme takes: closed triangles.
Mesh closed_triangles() {
  return bipyramid();
}

}  // namespace

TEST_CASE("regular Catmull–Clark is the bicubic B-spline, regular Doo–Sabin the biquadratic",
          "[subdivision][mesh]") {
  // On a torus every vertex is regular: one step is the tensor product of the curve schemes
  // (cubic B-spline (1,4,6,4,1)/8, Chaikin (1,3,3,1)/4) along both grid directions.
  const int n = 7, m = 5;
  const Mesh t = torus(n, m);
  const Points cubic = tensor_refine(named_scheme("b-spline", {{"degree", "3"}}), t.vertices, n, m);
  match_vertices(catmull_clark(t, 1).vertices, cubic, 1e-14);
  const Points quadratic = tensor_refine(named_scheme("chaikin", {}), t.vertices, n, m);
  match_vertices(doo_sabin(t, 1).vertices, quadratic, 1e-14);
}

TEST_CASE("regular Catmull–Clark converges to the NURBS core's uniform bicubic surface",
          "[subdivision][mesh]") {
  // The open grid is a uniform bicubic B-spline (`bicubic_grid`). Away from the boundary (whose rules differ
  // from the unclamped spline's: one more ring per level), the limit of every vertex of the level-2 mesh, by
  // the regular limit mask (16v + 4Σ edge neighbours + Σ diagonals)/36, is the surface point (Cox–de Boor) at
  // its dyadic parameter, which the same refinement of the parameter grid (i + 2, j + 2, 0) gives: the scheme
  // reproduces linear functions.
  const int n = 12, m = 11, levels = 2;
  const auto [shape, params, surface] = bicubic_grid(n, m);
  const Mesh refined = catmull_clark(shape, levels), uv = catmull_clark(params, levels);
  const MeshTopology t = build_topology(refined);
  const auto limit = [&](const Points& P, int v) {
    Eigen::RowVector3d edges = Eigen::RowVector3d::Zero(), corners = Eigen::RowVector3d::Zero();
    for (const int e : vertex_edges(t, static_cast<std::size_t>(v)))
      edges += P.row(other_vertex(t, static_cast<std::size_t>(e), v));
    for (const int f : vertex_faces(t, static_cast<std::size_t>(v)))
      for (const int c : face(t, static_cast<std::size_t>(f))) corners += P.row(c);
    const Eigen::RowVector3d diagonals = corners - 4 * P.row(v) - 2 * edges;
    return Eigen::RowVector3d((16 * P.row(v) + 4 * edges + diagonals) / 36);
  };
  int checked = 0;
  for (int v = 0; v < t.vertex_count; ++v) {
    if (t.boundary_vertex[static_cast<std::size_t>(v)]) continue;
    const Eigen::RowVector3d p = limit(uv.vertices, v);
    if (p.x() < 2 + 3 || p.x() > n + 2 - 3 || p.y() < 2 + 3 || p.y() > m + 2 - 3) continue;
    REQUIRE(valence(t, static_cast<std::size_t>(v)) == 4);
    const Point expected = nurbs::evaluate(surface, p.x(), p.y());
    const Eigen::RowVector3d got = limit(refined.vertices, v);
    INFO("vertex " << v << " at (" << p.x() << ", " << p.y() << ")");
    CHECK((got - expected).norm() <= 1e-12 * expected.norm());
    ++checked;
  }
  CHECK(checked == (4 * (n - 6) + 1) * (4 * (m - 6) + 1));
}

TEST_CASE("counts per level: V − E + F kept, faces by the scheme's factor", "[subdivision][mesh]") {
  for (const MeshScheme scheme : kAll) {
    const Mesh m = scheme == MeshScheme::catmull_clark || scheme == MeshScheme::doo_sabin
                       ? pyramid()
                       : closed_triangles();
    const MeshRefinement r = refine_topology(m, scheme, 3);
    REQUIRE(r.levels.size() == 4);
    REQUIRE(r.steps.size() == 3);
    for (std::size_t k = 0; k + 1 < r.levels.size(); ++k) {
      const MeshTopology &a = r.levels[k], &b = r.levels[k + 1];
      INFO(scheme_name(scheme) << ", level " << k + 1);
      CHECK(euler_characteristic(b) == euler_characteristic(a));
      CHECK(row_count(r.steps[k]) == static_cast<std::size_t>(b.vertex_count));
      const std::size_t F = face_count(a), E = a.edges.size(), V = static_cast<std::size_t>(a.vertex_count);
      switch (scheme) {
        case MeshScheme::catmull_clark:
        case MeshScheme::bilinear:
          CHECK(face_count(b) == a.face_vertices.size());
          break;
        case MeshScheme::loop:
        case MeshScheme::butterfly:
          CHECK(face_count(b) == 4 * F);
          break;
        case MeshScheme::doo_sabin:
          CHECK(face_count(b) == F + E + V);
          break;
        case MeshScheme::sqrt3:
          CHECK(face_count(b) == 3 * F);
          break;
      }
      // Every stencil is an affine combination.
      for (std::size_t i = 0; i < row_count(r.steps[k]); ++i) {
        double sum = 0;
        for (int j = r.steps[k].offsets[i]; j < r.steps[k].offsets[i + 1]; ++j)
          sum += r.steps[k].weights[static_cast<std::size_t>(j)];
        CHECK(sum == Approx(1).margin(1e-15));
      }
    }
  }
}

TEST_CASE("two levels at once = one level of one level; replay on new data = a fresh refinement",
          "[subdivision][mesh]") {
  for (const MeshScheme scheme : kAll) {
    const Mesh m = triangles_only(scheme) ? closed_triangles() : cube();
    INFO(scheme_name(scheme));
    const Mesh twice = subdivide(subdivide(m, scheme, 1), scheme, 1), once = subdivide(m, scheme, 2);
    CHECK(twice.face_offsets == once.face_offsets);
    CHECK(twice.face_vertices == once.face_vertices);
    CHECK((twice.vertices - once.vertices).cwiseAbs().maxCoeff() <= 1e-15);
    // Topology once, any number of position sets (and any number of columns).
    const MeshRefinement r = refine_topology(m, scheme, 2);
    Points moved = m.vertices;
    moved.col(2) *= -3;
    moved.col(0).array() += 0.5;
    Mesh other = m;
    other.vertices = moved;
    // To round-off: the one-shot applies each rule as it is made (a quad split's face centres once,
    // OpenSubdiv's order), the replay sums a row's weights per column first.
    CHECK((apply(r, moved) - subdivide(other, scheme, 2).vertices).cwiseAbs().maxCoeff() <= 1e-15);
    Points wide(m.vertices.rows(), 5);
    wide << m.vertices, moved.leftCols(2);
    const Points applied = apply(r, wide);
    CHECK((applied.leftCols(3) - once.vertices).cwiseAbs().maxCoeff() <= 1e-15);
    CHECK(applied.rightCols(2) == apply(r, moved).leftCols(2));  // columns are independent: same bits
  }
}

TEST_CASE("the stencil table (product of the steps) replays every level at once", "[subdivision][mesh]") {
  for (const MeshScheme scheme : kAll)
    for (const bool open : {false, true}) {
      const Mesh m = open ? quad_grid(4, 3, triangles_only(scheme))
                          : (triangles_only(scheme) ? closed_triangles() : pyramid());
      INFO(scheme_name(scheme) << (open ? ", open" : ", closed"));
      const MeshRefinement r = refine_topology(m, scheme, 3);
      const Stencils table = stencil_table(r);
      CHECK(static_cast<int>(row_count(table)) == r.levels.back().vertex_count);
      for (std::size_t i = 0; i < row_count(table); ++i) {
        double sum = 0;
        for (int k = table.offsets[i]; k < table.offsets[i + 1]; ++k)
          sum += table.weights[static_cast<std::size_t>(k)];
        CHECK(std::abs(sum - 1) <= 1e-14);
      }
      const Points by_levels = apply(r, m.vertices);
      Points at_once(7, 3);  // wrong size on purpose: resized
      apply(table, m.vertices, at_once);
      CHECK((at_once - by_levels).cwiseAbs().maxCoeff() <= 1e-13 * by_levels.cwiseAbs().maxCoeff());
      const double* storage = at_once.data();
      apply(table, m.vertices, at_once);  // same size: the storage is reused
      CHECK(at_once.data() == storage);
    }
}

TEST_CASE("affine invariance; Butterfly interpolates; the subdivision matrix is the weights",
          "[subdivision][mesh]") {
  Eigen::Matrix3d A;
  A << 2, 0.3, -1, 0.1, -1.5, 0.2, 0.7, 0.4, 3;
  const Eigen::RowVector3d shift(10, -20, 5);
  for (const MeshScheme scheme : kAll) {
    const Mesh m = triangles_only(scheme) ? closed_triangles() : pyramid();
    Mesh moved = m;
    moved.vertices = (m.vertices * A.transpose()).rowwise() + shift;
    const Points expected = (subdivide(m, scheme, 2).vertices * A.transpose()).rowwise() + shift;
    const Points got = subdivide(moved, scheme, 2).vertices;
    INFO(scheme_name(scheme));
    CHECK((got - expected).cwiseAbs().maxCoeff() <= 1e-12 * expected.cwiseAbs().maxCoeff());
    const MeshRefinement r = refine_topology(m, scheme, 1);
    const auto S = subdivision_matrix(r.steps[0], static_cast<int>(m.vertices.rows()));
    CHECK(S.rows() == r.levels[1].vertex_count);
    CHECK((Points(S * m.vertices) - apply(r, m.vertices)).cwiseAbs().maxCoeff() <= 1e-15);
  }
  const Mesh m = closed_triangles();
  const Mesh b = butterfly(m, 3);
  CHECK(b.vertices.topRows(m.vertices.rows()) == m.vertices);  // old vertices exactly in place
}

TEST_CASE("Loop's β is the seed's α_n/n, and the Butterfly stencils are ZSS's", "[subdivision][mesh]") {
  // A closed mesh with a vertex of valence n: its Loop vertex row has 1 − α_n on the vertex and
  // α_n/n on each neighbour, α_n = (40 − (3 + 2cos(2π/n))²)/64 (seed 003).
  const Mesh m = bipyramid();  // poles of valence 5, equator of valence 4
  const MeshRefinement r = refine_topology(m, MeshScheme::loop, 1);
  for (const int v : {0, 5}) {
    const int n = v == 5 ? 5 : 4;
    const double t = 3 + 2 * std::cos(2 * std::numbers::pi / n), alpha = (40 - t * t) / 64;
    const Stencils& s = r.steps[0];
    for (int k = s.offsets[static_cast<std::size_t>(v)]; k < s.offsets[static_cast<std::size_t>(v) + 1]; ++k)
      CHECK(s.weights[static_cast<std::size_t>(k)] ==
            Approx(s.columns[static_cast<std::size_t>(k)] == v ? 1 - alpha : alpha / n).epsilon(1e-14));
  }
}

TEST_CASE("Butterfly is linear in the valence: ring sums = ZSS's stencils written out",
          "[subdivision][mesh]") {
  // Each edge at a vertex of valence k took a k-point stencil, k² terms and cosines in all (46 s at
  // valence 50,000, issue 33). The one-shot sums each ring five ways once (s_j is of rank 5); here its
  // edge points against the stencils written out term by term, in long double. s_j = s_{k−j}: the
  // direction around a vertex does not matter, only where the ring starts.
  const auto s = [](int k, int j) -> long double {
    if (k == 4) return j == 0 ? 0.375L : (j == 2 ? -0.125L : 0.0L);
    const long double a = 2 * std::numbers::pi_v<long double> * j / k;
    return (0.25L + std::cos(a) + 0.5L * std::cos(2 * a)) / k;
  };
  for (const int k : {5, 7, 12, 40, 60000}) {
    INFO("valence " << k);
    const Mesh m = bipyramid_of(k);  // apexes k (above) and k + 1 (below) of valence k; equator valence 4
    const auto start = std::chrono::steady_clock::now();
    const Mesh once = butterfly(m, 1);
    if (k == 60000)  // 0.1 s in Release (the k² stencils: ~60 s); the sanitizers slow it about 20 times
      CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() <
            (cifs_test::kSanitized ? 30 : 3));
    const MeshTopology t = build_topology(m);
    const auto p = [&](int v) { return m.vertices.row(v).cast<long double>().eval(); };
    const auto apex = [&](int a, int i) {  // ¾a + Σ_j s_j p_{i+j}: a's stencil for its edge to i
      Eigen::Matrix<long double, 1, 3> sum = 0.75L * p(a);
      for (int j = 0; j < k; ++j) sum += s(k, j) * p((i + j) % k);
      return sum;
    };
    double worst = 0;
    for (int i = 0; i < k; i += std::max(1, k / 10)) {
      const int next = (i + 1) % k, previous = (i + k - 1) % k;
      // Equator vertex i (valence 4) from the apex a: a, a neighbour, the other apex, a neighbour.
      for (const int a : {k, k + 1}) {
        const Eigen::Matrix<long double, 1, 3> equator =
            0.75L * p(i) + 0.375L * p(a) - 0.125L * p(a == k ? k + 1 : k);
        const auto expected = (0.5L * (apex(a, i) + equator)).eval();
        const int e = find_edge(t, a, i);
        worst = std::max(
            worst, static_cast<double>((once.vertices.row(k + 2 + e).cast<long double>() - expected).norm()));
      }
      // Along the equator: each end's stencil starts at the other end, −⅛ across from it.
      const auto expected = (0.5L * ((0.75L * p(i) + 0.375L * p(next) - 0.125L * p(previous)) +
                                     (0.75L * p(next) + 0.375L * p(i) - 0.125L * p((i + 2) % k))))
                                .eval();
      const int e = find_edge(t, i, next);
      worst = std::max(
          worst, static_cast<double>((once.vertices.row(k + 2 + e).cast<long double>() - expected).norm()));
    }
    CHECK(worst <= 1e-14 * m.vertices.cwiseAbs().maxCoeff());
    check_kept_weights(m, MeshScheme::butterfly, k);
  }
}

TEST_CASE("Doo–Sabin is linear in the face size: rank-3 sums = the rule written out", "[subdivision][mesh]") {
  // A k-gon's corner points each weigh all k corners (k² terms, 52 s for two levels around a vertex of
  // valence 50,000); the one-shot sums a large face three ways once. A prism over a k-gon, against
  // Σ_m α_m p_{i+m}, α_m = ¼δ_m + (3 + 2cos(2πm/k))/(4k), in long double.
  for (const int k : {5, 15, 16, 40, 60000}) {
    INFO("k = " << k);
    std::vector<std::array<double, 3>> p;
    for (int i = 0; i < 2 * k; ++i) {
      const double a = 2 * std::numbers::pi * (i % k) / k;
      p.push_back({std::cos(a) * (1 + 0.3 * std::sin(7.0 * i)), std::sin(a), i < k ? 0.01 * (i % 3) : 1.0});
    }
    std::vector<std::vector<int>> faces(2);
    for (int i = 0; i < k; ++i) {
      faces[0].push_back(k - 1 - i);  // the bottom, seen from below
      faces[1].push_back(k + i);
      faces.push_back({i, (i + 1) % k, k + (i + 1) % k, k + i});
    }
    const Mesh m = make_mesh(p, faces);
    const auto start = std::chrono::steady_clock::now();
    const Mesh once = doo_sabin(m, 1);
    if (k == 60000)  // 0.1 s in Release (the k² sums: ~60 s); the sanitizers slow it about 20 times
      CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() <
            (cifs_test::kSanitized ? 30 : 3));
    double worst = 0;
    for (int f = 0; f < 2; ++f)
      for (int i = 0; i < k; i += std::max(1, k / 10)) {
        Eigen::Matrix<long double, 1, 3> expected = Eigen::Matrix<long double, 1, 3>::Zero();
        for (int j = 0; j < k; ++j) {
          const long double alpha = (j == 0 ? 0.25L : 0.0L) +
                                    (3 + 2 * std::cos(2 * std::numbers::pi_v<long double> * j / k)) / (4 * k);
          expected +=
              alpha *
              m.vertices.row(faces[static_cast<std::size_t>(f)][static_cast<std::size_t>((i + j) % k)])
                  .cast<long double>();
        }
        const int child = m.face_offsets[static_cast<std::size_t>(f)] + i;  // corner (f, i)
        worst = std::max(
            worst, static_cast<double>((once.vertices.row(child).cast<long double>() - expected).norm()));
      }
    CHECK(worst <= 1e-14 * m.vertices.cwiseAbs().maxCoeff());
    check_kept_weights(m, MeshScheme::doo_sabin, k);
  }
}

TEST_CASE("Doo–Sabin refuses an interior vertex of valence 2 before the work",
          "[subdivision][mesh][reliability]") {
  // A box with a vertex on a bottom edge (vertex 1: a hexagon and a pentagon around it): its Doo–Sabin
  // vertex face has 2 corners, which the next level's check refused as a face of a level never shown.
  const Mesh box = make_mesh(
      {{0, 0, 0},
       {1, 0, 0},
       {2, 0, 0},
       {2, 1, 0},
       {1, 1, 0},
       {0, 1, 0},
       {0, 0, 1},
       {2, 0, 1},
       {2, 1, 1},
       {0, 1, 1}},
      {{0, 5, 4, 3, 2, 1}, {6, 7, 8, 9}, {0, 1, 2, 7, 6}, {2, 3, 8, 7}, {3, 4, 5, 9, 8}, {5, 0, 6, 9}});
  for (const int levels : {1, 2})
    CHECK_THROWS_WITH(
        subdivide(box, MeshScheme::doo_sabin, levels),
        Contains("doo-sabin: vertex 1 is inside the mesh on two faces only: its vertex face would "
                 "have 2 corners"));
  CHECK(subdivide(box, MeshScheme::catmull_clark, 1).vertices.rows() ==
        10 + 14 + 6);  // V + E + F, E from Euler
}

TEST_CASE("Catmull–Clark keeps a large face's k² weights only when they fit",
          "[subdivision][mesh][reliability]") {
  // Kept (refine_topology, cifs limit), the edge and vertex points around a k-gon each weigh its k corners
  // (its face point's): two faces of 100,000 corners ran past 8 GB; one-shot subdivide keeps none.
  for (const int k : {40, 60000}) {
    INFO("k = " << k);
    std::vector<std::array<double, 3>> p;
    std::vector<std::vector<int>> faces(2);
    for (int i = 0; i < k; ++i) {
      const double a = 2 * std::numbers::pi * i / k;
      p.push_back({std::cos(a), std::sin(a), 0.01 * (i % 3)});
      faces[0].push_back(i);
      faces[1].push_back(k - 1 - i);  // a pillow: every vertex of valence 2
    }
    const Mesh m = make_mesh(p, faces);
    const auto start = std::chrono::steady_clock::now();
    check_kept_weights(m, MeshScheme::catmull_clark, k);
    if (k > 40) {
      CHECK_THROWS_WITH(
          limit_mesh(m, MeshScheme::catmull_clark, 1, LimitOptions{.max_bytes = std::size_t{1} << 30}),
          Contains("of them the weights of faces or vertices of 16 or more sides"));
      CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() <
            (cifs_test::kSanitized ? 10 : 1));
      CHECK(subdivide(m, MeshScheme::catmull_clark, 1).vertices.rows() == 2 * k + 2);  // one-shot: linear
    }
  }
}

TEST_CASE("bad meshes and requests: one-line errors naming the element", "[subdivision][mesh]") {
  CHECK_THROWS_WITH(loop(cube(), 1), Contains("loop: face 0 has 4 corners") && Contains("triangles"));
  CHECK_THROWS_WITH(sqrt3(pyramid(), 1), Contains("face 0 has 4 corners"));
  CHECK_THROWS_WITH(butterfly(cube(), 1), Contains("butterfly: face 0 has 4 corners"));
  Mesh bowtie = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0, 0}},
                          {{0, 1, 2}, {1, 3, 2}, {1, 2, 4}});  // edge 1–2 in three faces
  // Refined as OpenSubdiv refines it (test_mesh_features.cpp) by the schemes with crease rules only.
  CHECK(face_count(catmull_clark(bowtie, 1)) == 9);
  CHECK_THROWS_WITH(butterfly(bowtie, 1), Contains("both use edge (1, 2)"));
  Mesh nan = cube();
  nan.vertices(3, 1) = std::nan("");
  CHECK_THROWS_AS(catmull_clark(nan, 1), InvalidInput);
  Mesh out_of_range = cube();
  out_of_range.face_vertices[5] = 8;
  CHECK_THROWS_AS(catmull_clark(out_of_range, 1), InvalidInput);
  Mesh repeated = cube();
  repeated.face_vertices[1] = repeated.face_vertices[0];
  CHECK_THROWS_AS(catmull_clark(repeated, 1), InvalidInput);
  CHECK_THROWS_WITH(catmull_clark(cube(), -1), Contains("-1 levels"));
  // Refused before any work, with the figure: 16 levels of the cube are 2.6e10 faces.
  CHECK_THROWS_WITH(refine_topology(cube(), MeshScheme::catmull_clark, 16),
                    Contains("catmull-clark: 16 levels of 6 faces reach") && Contains("bytes (limit"));
  CHECK_THROWS_WITH(named_mesh_scheme("kobbelt"),
                    Contains("catmull-clark, loop, doo-sabin, butterfly, sqrt3"));
  CHECK(subdivide(cube(), MeshScheme::catmull_clark, 0).vertices == cube().vertices);
}

TEST_CASE("the factored forms (linear subdivision, then averaging) equal the masks", "[subdivision][mesh]") {
  const Mesh icosa_quads = catmull_clark(bipyramid(), 1);  // valences 3, 4, 5 and 6 (poles 5)
  const std::vector<std::pair<const char*, Mesh>> quads{{"cube", cube()},
                                                        {"torus", torus(6, 5)},
                                                        {"open grid", quad_grid(4, 3)},
                                                        {"bipyramid, one step", icosa_quads}};
  const std::vector<std::pair<const char*, Mesh>> triangles{
      {"tetrahedron", tetrahedron()}, {"octahedron", octahedron()},
      {"bipyramid", bipyramid()},     {"open triangles", quad_grid(4, 3, true)},
      {"fan of 7", fan(7)},           {"torus", torus(6, 5, true)}};
  for (const BoundaryRule rule : {BoundaryRule::edge_only, BoundaryRule::edge_and_corner})
    for (int levels = 1; levels <= 3; ++levels) {
      for (const auto& [cases, scheme] :
           {std::pair{&quads, MeshScheme::catmull_clark}, std::pair{&triangles, MeshScheme::loop}})
        for (auto [name, m] : *cases) {
          m.tags.boundary = rule;
          INFO(scheme_name(scheme) << ", " << name << ", level " << levels << ", corners "
                                   << (rule == BoundaryRule::edge_and_corner));
          const Mesh masks = subdivide(m, scheme, levels), factored = factored_subdivide(m, scheme, levels);
          CHECK(factored.face_vertices == masks.face_vertices);
          CHECK((factored.vertices - masks.vertices).cwiseAbs().maxCoeff() <=
                1e-14 * masks.vertices.cwiseAbs().maxCoeff());
        }
    }
  CHECK_THROWS_WITH(factored_subdivide(pyramid(), MeshScheme::catmull_clark, 1),
                    Contains("face 1 has 3 corners; the factored form runs on quads"));
  CHECK_THROWS_WITH(factored_subdivide(cube(), MeshScheme::doo_sabin, 1), Contains("catmull-clark and loop"));
}

TEST_CASE("child topology paired by construction = the one searched from its faces", "[subdivision][mesh]") {
  // Catmull–Clark and the triangle split (Loop, Butterfly) pair the child half-edges by
  // construction; build_topology finds the same pairing by search, with every order the same.
  using Named = std::vector<std::pair<const char*, Mesh>>;
  const Named polygons{
      {"cube", cube()}, {"pyramid", pyramid()}, {"grid", quad_grid(3, 4)}, {"torus", torus(4, 5)}};
  const Named triangles{{"bipyramid", bipyramid()},
                        {"tetrahedron", tetrahedron()},
                        {"grid", quad_grid(3, 4, true)},
                        {"fan", fan(5)},
                        {"torus", torus(4, 5, true)}};
  for (const MeshScheme scheme : {MeshScheme::catmull_clark, MeshScheme::loop, MeshScheme::butterfly}) {
    for (const auto& [name, mesh] : scheme == MeshScheme::catmull_clark ? polygons : triangles) {
      INFO(scheme_name(scheme) << " on " << name);
      const MeshRefinement r = refine_topology(mesh, scheme, 3);
      for (std::size_t level = 1; level < r.levels.size(); ++level) {
        INFO("level " << level);
        const MeshTopology& t = r.levels[level];
        cifs_test::check_same_topology(
            t, build_topology(std::span<const int>(t.face_offsets), std::span<const int>(t.face_vertices),
                              t.vertex_count));
      }
    }
  }
}
