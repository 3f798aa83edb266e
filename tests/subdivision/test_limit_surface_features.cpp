// SPDX-License-Identifier: MIT
// The limit surface at any (face, u, v) of meshes with features — the three boundary rules, sharp and
// semi-sharp creases under both crease methods, corners, darts, holes, non-quads, faces with several
// extraordinary corners — against OpenSubdiv Bfr (exact under uniform creasing at a high approximation
// level), against deep refinement (the limit of the vertex at a dyadic point by limit_stencils, both
// crease methods), against finite differences, and the regular boundary, crease and corner patches
// against the bicubic B-spline with phantom points.
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "subdivision/dyadic.hpp"
#include "subdivision/meshes.hpp"
#include "subdivision/osd_refiner.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
using Catch::Contains;

namespace {

struct Case {
  std::string name;
  Mesh mesh;
  MeshScheme scheme;
};

/// A prism over an n-gon, its caps n-gons (Catmull–Clark splits them into n quads, which OpenSubdiv
/// parametrises as sub-faces), the top turned and lifted unevenly.
Mesh prism(int n) {
  std::vector<std::array<double, 3>> p;
  for (int level = 0; level < 2; ++level)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * (i + 0.3 * level) / n;
      p.push_back({std::cos(a) * (1 + 0.2 * level), std::sin(a), level * (1 + 0.2 * std::sin(2 * a))});
    }
  std::vector<std::vector<int>> f;
  std::vector<int> bottom, top;
  for (int i = 0; i < n; ++i) {
    bottom.push_back(n - 1 - i);
    top.push_back(n + i);
    f.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  }
  f.push_back(bottom);
  f.push_back(top);
  return make_mesh(p, f);
}

std::vector<Case> feature_cases() {
  std::vector<Case> out;
  for (const CreaseMethod method : {CreaseMethod::uniform, CreaseMethod::chaikin}) {
    const std::string suffix = method == CreaseMethod::chaikin ? ", chaikin" : "";
    Mesh m = creased_cube();
    m.tags.crease_method = method;
    out.push_back({"creased cube" + suffix, m, MeshScheme::catmull_clark});
    for (const BoundaryRule rule :
         {BoundaryRule::none, BoundaryRule::edge_only, BoundaryRule::edge_and_corner})
      for (const bool triangles : {false, true}) {
        Mesh g = wavy_grid(5, 4, triangles);
        g.tags.boundary = rule;
        g.tags.holes = {7, 12};
        g.tags.creases = {{7, 8, 2}, {8, 9, 2}, {9, 10, 0.5}, {1, 7, 1.5}};
        g.tags.corners = {{14, 10}};
        g.tags.crease_method = method;
        out.push_back({"grid, boundary rule " + std::string(option_name(rule)) + suffix, g,
                       triangles ? MeshScheme::loop : MeshScheme::catmull_clark});
      }
    Mesh t = octahedron();
    t.tags.creases = {{0, 2, 0.3}, {2, 4, 1.5}, {4, 0, 2.5}, {1, 3, 10}};
    t.tags.corners = {{5, 1.25}};
    t.tags.crease_method = method;
    out.push_back({"octahedron" + suffix, t, MeshScheme::loop});
  }
  Mesh py = pyramid();
  py.tags.creases = {{0, 1, 1.5}, {1, 4, 10}};
  out.push_back({"pyramid", py, MeshScheme::catmull_clark});
  for (const int n : {5, 10}) {
    Mesh pr = prism(n);
    pr.tags.creases = {{0, 1, 10}, {1, 2, 10}, {n, n + 1, 2.5}};
    out.push_back({"prism " + std::to_string(n), pr, MeshScheme::catmull_clark});
  }
  Mesh dart = fan(5);
  dart.tags.creases = {{0, 1, 10}};  // one sharp edge ending inside: a dart at the centre
  out.push_back({"fan (dart)", dart, MeshScheme::loop});
  Mesh qdart = torus(6, 5);
  qdart.tags.creases = {{0, 1, 10}, {1, 2, 10}};
  out.push_back({"torus (darts)", qdart, MeshScheme::catmull_clark});
  for (unsigned seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(seed);
    const bool triangles = seed % 2 == 0;
    Mesh m = seed % 4 < 2 ? torus(6, 5, triangles) : wavy_grid(4, 4, triangles);
    if (seed % 6 == 3) m = pyramid();
    random_tags(m, rng, seed % 3 != 0);
    out.push_back({"random tags, seed " + std::to_string(seed), m,
                   triangles ? MeshScheme::loop : MeshScheme::catmull_clark});
  }
  return out;
}

/// OpenSubdiv's sub-face tiling: D columns of sub-faces.
int tiles(int n) {
  return n < 10 ? (n > 4 ? 3 : 2) : 1 + static_cast<int>(std::sqrt(static_cast<double>(n - 1)));
}

std::vector<char> holes_of(const Mesh& m, MeshScheme scheme) {
  const MeshRefinement r = refine_topology(m, scheme, 0);
  std::vector<char> out(face_count(m), 0);
  if (!r.features[0].holes.empty()) out = r.features[0].holes;
  return out;
}

/// Points on every face that is not a hole: corners, edges, near corners, inside; on n-gons the same
/// in every sub-face.
std::vector<FacePoint> sample_points(const Mesh& m, MeshScheme scheme) {
  const std::vector<char> holes = holes_of(m, scheme);
  static constexpr std::array<std::array<double, 2>, 12> kSquare{{{0, 0},
                                                                  {1, 0},
                                                                  {1, 1},
                                                                  {0, 1},
                                                                  {0.5, 0},
                                                                  {0.013, 0.021},
                                                                  {0.3, 0.1},
                                                                  {0.12, 0.55},
                                                                  {0.5, 0.5},
                                                                  {0.7, 0.2},
                                                                  {1, 0.37},
                                                                  {0.002, 0.6}}};
  static constexpr std::array<std::array<double, 2>, 12> kTriangle{{{0.37, 0},
                                                                    {0.37, 0.63},
                                                                    {0, 0},
                                                                    {1, 0},
                                                                    {0, 1},
                                                                    {0.5, 0},
                                                                    {0.013, 0.021},
                                                                    {0.3, 0.1},
                                                                    {0.12, 0.55},
                                                                    {0.25, 0.25},
                                                                    {0.5, 0.5},
                                                                    {0.002, 0.6}}};
  std::vector<FacePoint> out;
  for (int f = 0; f < static_cast<int>(face_count(m)); ++f) {
    if (holes[static_cast<std::size_t>(f)]) continue;
    const auto n = static_cast<int>(face(m, static_cast<std::size_t>(f)).size());
    if (scheme == MeshScheme::loop) {
      for (const auto& [u, v] : kTriangle) out.push_back({.face = f, .u = u, .v = v});
    } else if (n == 4) {
      for (const auto& [u, v] : kSquare) out.push_back({.face = f, .u = u, .v = v});
    } else {
      const int D = tiles(n);
      for (int i = 0; i < n; ++i)
        for (const auto& [s, t] : kSquare) out.push_back({.face = f, .u = i % D + s / 2, .v = i / D + t / 2});
    }
  }
  return out;
}

double size_of(const Mesh& m) {
  return (m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff()).norm();
}

/// Bfr's positions and partials at the points, at approximation level 10 (smooth and sharp).
std::array<Points, 3> bfr(const Mesh& m, MeshScheme scheme, const std::vector<FacePoint>& points) {
  namespace Bfr = OpenSubdiv::Bfr;
  const auto refiner = osd_refiner(
      m, scheme == MeshScheme::loop ? OpenSubdiv::Sdc::SCHEME_LOOP : OpenSubdiv::Sdc::SCHEME_CATMARK, 0);
  REQUIRE(refiner);
  Bfr::SurfaceFactory::Options options;
  options.SetApproxLevelSmooth(10);
  options.SetApproxLevelSharp(10);
  const Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
  Bfr::Surface<double> surface;
  std::vector<double> patch;
  const Bfr::Surface<double>::PointDescriptor desc(3);
  const auto n = static_cast<Eigen::Index>(points.size());
  std::array<Points, 3> out{Points(n, 3), Points(n, 3), Points(n, 3)};
  int initialised = -1;
  for (Eigen::Index i = 0; i < n; ++i) {
    const FacePoint& q = points[static_cast<std::size_t>(i)];
    if (q.face != initialised) {
      REQUIRE(factory.InitVertexSurface(q.face, &surface));
      patch.resize(static_cast<std::size_t>(surface.GetNumPatchPoints()) * 3);
      surface.PreparePatchPoints(m.vertices.data(), desc, patch.data(), desc);
      initialised = q.face;
    }
    const double uv[2] = {q.u, q.v};
    surface.Evaluate(uv, patch.data(), desc, out[0].row(i).data(), out[1].row(i).data(),
                     out[2].row(i).data());
  }
  return out;
}

/// Whether a point is a vertex of its face or, on an n-gon, of its sub-face — the face point is one
/// (where a patch that never becomes a polynomial has no partials).
bool at_vertex(const Mesh& m, MeshScheme scheme, const FacePoint& q) {
  const auto n = static_cast<int>(face(m, static_cast<std::size_t>(q.face)).size());
  if (scheme == MeshScheme::loop || n == 4)
    return (q.u == 0 || q.u == 1) && (q.v == 0 || q.v == 1 || scheme == MeshScheme::loop);
  const double s = 2 * (q.u - std::floor(q.u)), t = 2 * (q.v - std::floor(q.v));  // the sub-face's corners
  return (s == 0 || s == 1) && (t == 0 || t == 1);
}

/// Whether OpenSubdiv's limit at vertex v is exact (docs/subdivision-surfaces.md, "Limit points"):
/// not where sharpness is still to spend (a semi-sharp edge or corner) nor at a dart (one sharp edge
/// inside), where it takes the infinitely sharp or the smooth mask; Bfr's patches take those masks at
/// their corners.
bool osd_exact_limit(const MeshRefinement& r, int v) {
  const MeshTopology& t = r.levels[0];
  const LevelFeatures& f = r.features[0];
  const auto semi = [](double s) { return s > 0 && s < kInfiniteSharpness; };
  if (!f.vertex_sharpness.empty() && semi(f.vertex_sharpness[static_cast<std::size_t>(v)])) return false;
  int sharp = 0;
  for (const int e : vertex_edges(t, static_cast<std::size_t>(v))) {
    const double s = f.edge_sharpness.empty() ? 0.0 : f.edge_sharpness[static_cast<std::size_t>(e)];
    if (semi(s)) return false;
    sharp += s >= kInfiniteSharpness ? 1 : 0;
  }
  return sharp != 1 || t.boundary_vertex[static_cast<std::size_t>(v)] != 0;
}

/// The mesh vertex at a point, or −1 (n-gons: only the face's own corners).
int vertex_at(const Mesh& m, MeshScheme scheme, const FacePoint& q) {
  const auto c = face(m, static_cast<std::size_t>(q.face));
  const auto n = static_cast<int>(c.size());
  if (scheme == MeshScheme::loop) {
    if (q.u == 0 && q.v == 0) return c[0];
    if (q.u == 1) return c[1];
    if (q.v == 1) return c[2];
    return -1;
  }
  if (n == 4) {
    if (!((q.u == 0 || q.u == 1) && (q.v == 0 || q.v == 1))) return -1;
    return c[static_cast<std::size_t>(q.u == 0 ? (q.v == 0 ? 0 : 3) : (q.v == 0 ? 1 : 2))];
  }
  const int D = tiles(n);
  if (q.u != std::floor(q.u) || q.v != std::floor(q.v)) return -1;
  return c[static_cast<std::size_t>(static_cast<int>(q.v) * D + static_cast<int>(q.u))];
}

}  // namespace

TEST_CASE("the limit surface at (face, u, v) with features = OpenSubdiv Bfr, positions and partials",
          "[subdivision][limit][oracle]") {
  // Bfr is exact under uniform creasing where its approximation level (10 here) is below the points;
  // both to 1e-10 of the mesh's size. Partials are compared everywhere but at the face's vertices
  // (ours are 0 where the patch never becomes a polynomial: extraordinary, dart, smooth corner);
  // positions everywhere but at the mesh vertices where OpenSubdiv's limit is not exact (semi-sharp,
  // darts: there the deep refinement test below holds ours to the limit).
  for (const Case& c : feature_cases()) {
    if (c.mesh.tags.crease_method != CreaseMethod::uniform) continue;
    INFO(c.name << ", " << scheme_name(c.scheme));
    const std::vector<FacePoint> points = sample_points(c.mesh, c.scheme);
    const SurfaceSample ours = evaluate_limit_surface(c.mesh, c.scheme, points);
    const auto [P, Du, Dv] = bfr(c.mesh, c.scheme, points);
    const double scale = size_of(c.mesh);
    const MeshRefinement r = refine_topology(c.mesh, c.scheme, 0);
    double position = 0, partials = 0;
    std::string where_position, where_partials;
    const auto place = [&](std::size_t k) {
      return "face " + std::to_string(points[k].face) + " at (" + std::to_string(points[k].u) + ", " +
             std::to_string(points[k].v) + ")";
    };
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      const int vertex = vertex_at(c.mesh, c.scheme, points[k]);
      if (const double e = (ours.positions.row(i) - P.row(i)).norm();
          e > position && (vertex < 0 || osd_exact_limit(r, vertex)))
        position = e, where_position = place(k);
      if (at_vertex(c.mesh, c.scheme, points[k]) && ours.du.row(i).norm() == 0) continue;
      if (const double e = std::max((ours.du.row(i) - Du.row(i)).norm(), (ours.dv.row(i) - Dv.row(i)).norm());
          e > partials)
        partials = e, where_partials = place(k);
    }
    INFO("positions worst at " << where_position << ", partials at " << where_partials);
    CHECK(position <= 1e-10 * scale);
    CHECK(partials <= 1e-10 * scale);
  }
}

TEST_CASE("the limit surface at (face, u, v) with features = the limits of deeply refined vertices",
          "[subdivision][limit]") {
  // At the dyadic points (i, j)/16 of every face (of every sub-face of an n-gon) the surface is the
  // limit of the vertex four levels down there: limit_stencils on the production refinement, another
  // route, exact for both crease methods (where Bfr is not for Chaikin's). 1e-12 of the mesh's size,
  // the face corners included — except where Chaikin's rule meets three or more semi-sharp edges at
  // a vertex: it sums their sharpness in single precision in the order of the edges around the vertex
  // (as OpenSubdiv does), and a state's local mesh may start that order elsewhere, which can move the
  // sum by a float's last bit: 1e-8 of the size.
  constexpr int kLevels = 4, N = 1 << kLevels;
  for (const Case& c : feature_cases()) {
    INFO(c.name << ", " << scheme_name(c.scheme));
    const MeshRefinement r = refine_topology(c.mesh, c.scheme, kLevels);
    const LimitFrame limit = evaluate_limit(limit_stencils(r), apply(r, c.mesh.vertices), false);
    const std::vector<char> holes = holes_of(c.mesh, c.scheme);
    std::vector<FacePoint> points;
    std::vector<int> expected;
    for (int f = 0; f < static_cast<int>(face_count(c.mesh)); ++f) {
      if (holes[static_cast<std::size_t>(f)]) continue;
      const auto n = static_cast<int>(face(c.mesh, static_cast<std::size_t>(f)).size());
      if (c.scheme == MeshScheme::loop) {
        const std::vector<int> ids = dyadic_triangle_vertices(r, f, kLevels);
        for (int i = 0; i <= N; ++i)
          for (int j = 0; i + j <= N; ++j) {
            points.push_back({.face = f, .u = double(i) / N, .v = double(j) / N});
            expected.push_back(ids[static_cast<std::size_t>(i * (N + 1) + j)]);
          }
      } else if (n == 4) {
        const std::vector<int> ids = dyadic_vertices(r, f, kLevels);
        for (int i = 0; i <= N; ++i)
          for (int j = 0; j <= N; ++j) {
            points.push_back({.face = f, .u = double(i) / N, .v = double(j) / N});
            expected.push_back(ids[static_cast<std::size_t>(i * (N + 1) + j)]);
          }
      } else {  // sub-face k: the quad of corner k one level down, (i, j)/8 of it
        const int D = tiles(n), half = N / 2;
        for (int k = 0; k < n; ++k) {
          const auto sub =
              face(r.levels[1],
                   static_cast<std::size_t>(r.levels[0].face_offsets[static_cast<std::size_t>(f)] + k));
          const std::vector<int> ids =
              dyadic_quad_vertices(r, {sub[0], sub[1], sub[2], sub[3]}, 1, kLevels - 1);
          for (int i = 0; i <= half; ++i)
            for (int j = 0; j <= half; ++j) {
              points.push_back({.face = f, .u = k % D + double(i) / N, .v = k / D + double(j) / N});
              expected.push_back(ids[static_cast<std::size_t>(i * (half + 1) + j)]);
            }
        }
      }
    }
    const SurfaceSample got = evaluate_limit_surface(c.mesh, c.scheme, points);
    const double scale = size_of(c.mesh);
    double worst = 0;
    for (std::size_t k = 0; k < points.size(); ++k)
      worst = std::max(
          worst, (got.positions.row(static_cast<Eigen::Index>(k)) - limit.positions.row(expected[k])).norm());
    bool float_order = false;
    if (c.mesh.tags.crease_method == CreaseMethod::chaikin)
      for (int v = 0; v < r.levels[0].vertex_count; ++v) {
        int semi = 0;
        for (const int e : vertex_edges(r.levels[0], static_cast<std::size_t>(v))) {
          const double s = r.features[0].edge_sharpness.empty()
                               ? 0.0
                               : r.features[0].edge_sharpness[static_cast<std::size_t>(e)];
          semi += s > 0 && s < kInfiniteSharpness ? 1 : 0;
        }
        float_order = float_order || semi >= 3;
      }
    CHECK(worst <= (float_order ? 1e-7 : 1e-12) * scale);
  }
}

TEST_CASE("the limit surface at (face, u, v) with features: partials = differences of positions",
          "[subdivision][limit]") {
  // Central differences at points inside the faces (sub-faces), off the dyadic grid: agreement to
  // the differences' own error (1e-6 relative), on every featured mesh, both crease methods.
  const double h = 1e-5;
  for (const Case& c : feature_cases()) {
    INFO(c.name << ", " << scheme_name(c.scheme));
    std::vector<FacePoint> centres;
    for (const FacePoint& q : sample_points(c.mesh, c.scheme))
      if (!at_vertex(c.mesh, c.scheme, q)) {
        const double s = 2 * (q.u - std::floor(q.u)), t = 2 * (q.v - std::floor(q.v));  // n-gons: sub-face
        const bool inner =
            c.scheme == MeshScheme::loop || face(c.mesh, static_cast<std::size_t>(q.face)).size() == 4
                ? q.u > 2 * h && q.v > 2 * h && q.u < 1 - 2 * h && q.v < 1 - 2 * h &&
                      q.u + q.v < (c.scheme == MeshScheme::loop ? 1 - 2 * h : 3)
                : s > 4 * h && t > 4 * h && s < 1 - 4 * h && t < 1 - 4 * h;
        if (inner) centres.push_back(q);
      }
    std::vector<FacePoint> points;
    for (const FacePoint& q : centres)
      for (const auto [du, dv] : {std::array{0.0, 0.0}, std::array{h, 0.0}, std::array{-h, 0.0},
                                  std::array{0.0, h}, std::array{0.0, -h}})
        points.push_back({.face = q.face, .u = q.u + du, .v = q.v + dv});
    const SurfaceSample s = evaluate_limit_surface(c.mesh, c.scheme, points);
    double worst = 0;
    for (Eigen::Index p = 0; p < s.positions.rows(); p += 5) {
      const Eigen::RowVectorXd fu = (s.positions.row(p + 1) - s.positions.row(p + 2)) / (2 * h),
                               fv = (s.positions.row(p + 3) - s.positions.row(p + 4)) / (2 * h);
      const double size = std::max({s.du.row(p).norm(), s.dv.row(p).norm(), 1e-3 * size_of(c.mesh)});
      worst = std::max({worst, (s.du.row(p) - fu).norm() / size, (s.dv.row(p) - fv).norm() / size});
    }
    CHECK(worst <= 1e-6);
  }
}

TEST_CASE("the limit surface at (face, u, v) with features: refined vertices converge to it",
          "[subdivision][limit]") {
  // The vertices at the dyadic points (i, j)/8 of every face, refined 3 … 8 levels by the production
  // refiner (positions, not limits), approach the evaluated surface geometrically — by a factor 0.55
  // or less per level (semi-sharp creases ending on a sharp one leave a ½ mode), and by 4 in the end on the
  // open grid with sharp creases and corners, whose patches are polynomials (their control points converge as
  // h²) — Chaikin's crease method included.
  for (const bool chaikin : {false, true}) {
    Mesh g = wavy_grid(5, 4, false);
    g.tags.boundary = BoundaryRule::edge_and_corner;
    g.tags.creases = {{7, 8, 10}, {8, 9, 10}, {9, 10, 10}};
    g.tags.corners = {{14, 10}};
    if (chaikin) {
      g.tags.crease_method = CreaseMethod::chaikin;
      g.tags.creases.push_back({1, 7, 1.5});
      g.tags.creases.push_back({2, 8, 2.5});
    }
    INFO((chaikin ? "chaikin, semi-sharp" : "sharp creases"));
    constexpr int kFirst = 3, kLast = 8;
    const MeshRefinement r = refine_topology(g, MeshScheme::catmull_clark, kLast);
    std::vector<FacePoint> points;
    std::vector<std::vector<int>> ids;
    const int N = 1 << kFirst;
    for (int f = 0; f < static_cast<int>(face_count(g)); ++f)
      for (int i = 0; i <= N; ++i)
        for (int j = 0; j <= N; ++j) points.push_back({.face = f, .u = double(i) / N, .v = double(j) / N});
    const SurfaceSample s = evaluate_limit_surface(g, MeshScheme::catmull_clark, points);
    std::vector<double> distance;
    Points level = g.vertices;
    for (int l = 1; l <= kLast; ++l) {
      level = apply(r.steps[static_cast<std::size_t>(l - 1)], level);
      if (l < kFirst) continue;
      const int M = 1 << l, stride = M / N;
      double worst = 0;
      std::size_t k = 0;
      for (int f = 0; f < static_cast<int>(face_count(g)); ++f) {
        const std::vector<int> at = dyadic_vertices(r, f, l);
        for (int i = 0; i <= N; ++i)
          for (int j = 0; j <= N; ++j, ++k)
            worst =
                std::max(worst, (level.row(at[static_cast<std::size_t>(i * stride * (M + 1) + j * stride)]) -
                                 s.positions.row(static_cast<Eigen::Index>(k)))
                                    .norm());
      }
      distance.push_back(worst);
    }
    for (std::size_t l = 0; l + 1 < distance.size(); ++l) {
      INFO("levels " << l + kFirst << " → " << l + kFirst + 1 << ": " << distance[l] << " → "
                     << distance[l + 1]);
      CHECK(distance[l + 1] <= (chaikin ? 0.55 : 0.35) * distance[l]);
      if (!chaikin && l + 3 >= distance.size()) {  // the last two steps: 1/4
        CHECK(distance[l + 1] <= 0.26 * distance[l]);
        CHECK(distance[l + 1] >= 0.24 * distance[l]);
      }
    }
  }
}
