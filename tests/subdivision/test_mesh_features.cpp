// SPDX-License-Identifier: MIT
// Production meshes against OpenSubdiv Far: semi-sharp and infinitely sharp creases, corners, holes,
// the three boundary rules, both crease methods, the smooth-triangle rule, the bilinear scheme and
// face-varying UVs, levels 1–4, to 1e-12. Sharpness values are arbitrary (0.3, 1.7 …): cifs holds
// sharpness in single precision as OpenSubdiv does, so the two agree to round-off on any value.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "cifs/subdivision/mesh.hpp"
#include "subdivision/mesh_compare.hpp"
#include "subdivision/meshes.hpp"
#include "subdivision/osd_refiner.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

Sdc::SchemeType osd_scheme(MeshScheme scheme) {
  return scheme == MeshScheme::catmull_clark ? Sdc::SCHEME_CATMARK
         : scheme == MeshScheme::loop        ? Sdc::SCHEME_LOOP
                                             : Sdc::SCHEME_BILINEAR;
}

/// OpenSubdiv's last level: positions, faces, holes (as tags.holes) and face-varying channels.
Mesh osd_features(const Mesh& m, MeshScheme scheme, int levels) {
  const auto refiner = osd_refiner(m, osd_scheme(scheme), levels);
  REQUIRE(refiner);
  const Far::PrimvarRefinerReal<double> primvars(*refiner);
  std::vector<OsdVertex> src(static_cast<std::size_t>(m.vertices.rows()));
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    for (int k = 0; k < 3; ++k) src[static_cast<std::size_t>(i)].p[k] = m.vertices(i, k);
  for (int level = 1; level <= levels; ++level) {
    std::vector<OsdVertex> dst(static_cast<std::size_t>(refiner->GetLevel(level).GetNumVertices()));
    primvars.Interpolate(level, src, dst);
    src = std::move(dst);
  }
  const Far::TopologyLevel& last = refiner->GetLevel(levels);
  Mesh out;
  out.vertices.resize(last.GetNumVertices(), 3);
  for (int i = 0; i < last.GetNumVertices(); ++i)
    for (int k = 0; k < 3; ++k) out.vertices(i, k) = src[static_cast<std::size_t>(i)].p[k];
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    const auto corners = last.GetFaceVertices(f);
    const std::vector<int> face(corners.begin(), corners.end());
    add_face(out, std::span<const int>(face));
    if (last.IsFaceHole(f)) out.tags.holes.push_back(f);
  }
  for (std::size_t c = 0; c < m.face_varying.size(); ++c) {
    const int channel = static_cast<int>(c);
    const FaceVaryingChannel& in = m.face_varying[c];
    std::vector<OsdVertex> values(static_cast<std::size_t>(in.values.rows()));
    for (Eigen::Index i = 0; i < in.values.rows(); ++i) {
      values[static_cast<std::size_t>(i)].Clear();
      for (Eigen::Index k = 0; k < in.values.cols(); ++k)
        values[static_cast<std::size_t>(i)].p[k] = in.values(i, k);
    }
    for (int level = 1; level <= levels; ++level) {
      std::vector<OsdVertex> next(
          static_cast<std::size_t>(refiner->GetLevel(level).GetNumFVarValues(channel)));
      primvars.InterpolateFaceVarying(level, values, next, channel);
      values = std::move(next);
    }
    FaceVaryingChannel o;
    o.name = in.name;
    o.values.resize(static_cast<Eigen::Index>(values.size()), in.values.cols());
    for (std::size_t i = 0; i < values.size(); ++i)
      for (Eigen::Index k = 0; k < in.values.cols(); ++k)
        o.values(static_cast<Eigen::Index>(i), k) = values[i].p[k];
    for (int f = 0; f < last.GetNumFaces(); ++f)
      for (const int v : last.GetFaceFVarValues(f, channel)) o.indices.push_back(v);
    out.face_varying.push_back(std::move(o));
  }
  return out;
}

/// Per face (by its mapped vertex cycle, rotated to start at the smallest): the hole flag and every
/// channel's value at each corner.
struct FaceRecord {
  bool hole = false;
  std::vector<std::vector<double>> values;  // corner by corner, channels concatenated
};

std::map<std::vector<int>, FaceRecord> face_records(const Mesh& m, const std::vector<int>* map) {
  std::map<std::vector<int>, FaceRecord> out;
  const std::vector<char> hole = hole_flags(m);
  for (std::size_t f = 0; f < face_count(m); ++f) {
    std::vector<int> corners;
    const int base = m.face_offsets[f];
    for (const int v : face(m, f)) corners.push_back(map ? (*map)[static_cast<std::size_t>(v)] : v);
    const auto start =
        static_cast<std::size_t>(std::min_element(corners.begin(), corners.end()) - corners.begin());
    std::rotate(corners.begin(), corners.begin() + static_cast<std::ptrdiff_t>(start), corners.end());
    FaceRecord r{.hole = hole[f] != 0, .values = {}};
    for (std::size_t i = 0; i < corners.size(); ++i) {
      std::vector<double> value;
      const std::size_t k = static_cast<std::size_t>(base) + (start + i) % corners.size();
      for (const FaceVaryingChannel& c : m.face_varying)
        for (Eigen::Index d = 0; d < c.values.cols(); ++d) value.push_back(c.values(c.indices[k], d));
      r.values.push_back(std::move(value));
    }
    out.emplace(std::move(corners), std::move(r));
  }
  return out;
}

/// Same vertices (up to numbering), faces, holes and face-varying values at every corner.
void check_same_features(const Mesh& ours, const Mesh& theirs, double tol = 1e-12) {
  REQUIRE(face_count(ours) == face_count(theirs));
  const std::vector<int> map = match_vertices(ours.vertices, theirs.vertices, tol);
  const auto a = face_records(ours, &map), b = face_records(theirs, nullptr);
  REQUIRE(a.size() == b.size());
  double worst = 0;
  std::size_t holes_differ = 0, faces_differ = 0;
  for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j) {
    faces_differ += i->first != j->first;
    holes_differ += i->second.hole != j->second.hole;
    REQUIRE(i->second.values.size() == j->second.values.size());
    for (std::size_t k = 0; k < i->second.values.size(); ++k) {
      REQUIRE(i->second.values[k].size() == j->second.values[k].size());
      for (std::size_t d = 0; d < i->second.values[k].size(); ++d)
        worst = std::max(worst, std::abs(i->second.values[k][d] - j->second.values[k][d]));
    }
  }
  CHECK(faces_differ == 0);
  CHECK(holes_differ == 0);
  CHECK(worst <= tol);
}

void check_against_osd(const Mesh& m, MeshScheme scheme, int max_level) {
  for (int levels = 1; levels <= max_level; ++levels) {
    INFO(scheme_name(scheme) << ", level " << levels << ", boundary " << option_name(m.tags.boundary)
                             << ", creases " << option_name(m.tags.crease_method) << ", triangles "
                             << option_name(m.tags.triangles));
    check_same_features(subdivide(m, scheme, levels), osd_features(m, scheme, levels));
  }
}

/// UVs of a torus or grid laid out on an (n + 1) × (m + 1) lattice: a seam where the lattice wraps.
FaceVaryingChannel lattice_uvs(const Mesh& m, int n, int rows, bool wraps) {
  FaceVaryingChannel c;
  c.values.resize((n + 1) * (rows + 1), 2);
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= n; ++i) c.values.row(j * (n + 1) + i) << double(i) / n, double(j) / rows;
  // Vertex v of the lattice sits at (v mod cols, v div cols); a face corner whose neighbour wrapped
  // takes the value past the seam.
  const int cols = wraps ? n : n + 1;
  for (std::size_t f = 0; f < face_count(m); ++f) {
    const auto corners = face(m, f);
    int i0 = corners[0] % cols, j0 = corners[0] / cols;
    for (const int v : corners) {
      i0 = std::min(i0, v % cols);
      j0 = std::min(j0, v / cols);
    }
    for (const int v : corners) {
      int i = v % cols, j = v / cols;
      if (wraps && i == 0 &&
          std::any_of(corners.begin(), corners.end(), [&](int w) { return w % cols == n - 1; }))
        i = n;
      if (wraps && j == 0 &&
          std::any_of(corners.begin(), corners.end(), [&](int w) { return w / cols == rows - 1; }))
        j = rows;
      c.indices.push_back(j * (n + 1) + i);
    }
  }
  return c;
}

/// Three sheets of 2 × 1 quads (or 4 triangles) meeting along the chain 0 – 1 – 2 on the x axis, all
/// running 0 → 1 → 2: the chain's edges have three faces (non-manifold); vertex 1 lies on exactly two
/// of them with more faces than edges (OpenSubdiv's crease-along case), its ends on boundaries.
Mesh three_sheets(bool triangles) {
  std::vector<std::array<double, 3>> p{{0, 0, 0}, {1, 0.1, 0}, {2, 0, 0.1}};
  std::vector<std::vector<int>> f;
  for (int k = 0; k < 3; ++k) {
    const double a = 2 * std::numbers::pi * k / 3 + 0.2 * k;
    const int b = static_cast<int>(p.size());
    for (int i = 0; i < 3; ++i) p.push_back({double(i) + 0.1 * k, std::cos(a) * (1 + 0.2 * i), std::sin(a)});
    for (int i = 0; i < 2; ++i) {
      if (triangles) {
        f.push_back({i, i + 1, b + i + 1});
        f.push_back({i, b + i + 1, b + i});
      } else {
        f.push_back({i, i + 1, b + i + 1, b + i});
      }
    }
  }
  return make_mesh(p, f);
}

/// Two closed tetrahedra (or cubes) sharing one vertex: two fans of faces around it.
Mesh touching_solids(bool triangles) {
  if (triangles)
    return make_mesh(
        {{0, 0, 0}, {1, 0.1, 0}, {0.1, 1, 0}, {0.2, 0.1, 1}, {-1, 0, 0.1}, {0, -1.1, 0}, {0.1, -0.2, -1}},
        {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}});
  Mesh a = cube(), b = cube();
  b.vertices = (-b.vertices).rowwise() + Eigen::RowVector3d(0, 0, 0);
  b.vertices.col(2) *= 1.3;
  // Glue b's vertex 0 (the origin, as a's) onto a's: drop it and renumber b's faces.
  Mesh m = a;
  Points v(a.vertices.rows() + b.vertices.rows() - 1, 3);
  v << a.vertices, b.vertices.bottomRows(b.vertices.rows() - 1);
  m.vertices = v;
  for (std::size_t f = 0; f < face_count(b); ++f) {
    std::vector<int> face;
    for (int x : cifs::face(b, f)) face.push_back(x == 0 ? 0 : x - 1 + static_cast<int>(a.vertices.rows()));
    std::reverse(face.begin(), face.end());  // the point reflection flips orientation back
    add_face(m, std::span<const int>(face));
  }
  return m;
}

}  // namespace

TEST_CASE("non-manifold edges and vertices = OpenSubdiv Far: split by fans, sharpened, welded back",
          "[subdivision][mesh][oracle][creases]") {
  for (const bool triangles : {false, true}) {
    const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
    for (Mesh m : {three_sheets(triangles), touching_solids(triangles)})
      for (const BoundaryRule rule :
           {BoundaryRule::edge_only, BoundaryRule::edge_and_corner, BoundaryRule::none}) {
        if (rule == BoundaryRule::none && m.vertices.rows() == 12) continue;  // the sheets: every face a hole
        m.tags.boundary = rule;
        check_against_osd(m, scheme, 3);
        m.tags.creases = {{0, 1, 1.5}};  // on the non-manifold chain (infinite anyway) or the shared vertex
        m.tags.corners = {{2, 0.5}};
        check_against_osd(m, scheme, 3);
        m.tags = MeshTags{};
      }
  }
  CHECK_THROWS_WITH(refine_topology(three_sheets(false), MeshScheme::catmull_clark, 1),
                    Catch::Contains("refine_topology (a replayable refinement) does not yet"));
}

TEST_CASE("creases and corners = OpenSubdiv Far: semi-sharp, sharp, blended, both crease methods, levels 1–4",
          "[subdivision][mesh][oracle][creases]") {
  for (const CreaseMethod method : {CreaseMethod::uniform, CreaseMethod::chaikin}) {
    Mesh m = creased_cube();
    m.tags.crease_method = method;
    check_against_osd(m, MeshScheme::catmull_clark, 4);
    check_against_osd(m, MeshScheme::bilinear, 2);
    Mesh t = octahedron();
    t.tags.creases = {{0, 2, 0.3}, {2, 4, 1.5}, {4, 0, 2.5}, {1, 3, 10}};
    t.tags.corners = {{5, 1.25}};
    t.tags.crease_method = method;
    check_against_osd(t, MeshScheme::loop, 4);
  }
}

TEST_CASE("holes and the three boundary rules = OpenSubdiv Far, open quads and triangles",
          "[subdivision][mesh][oracle][creases]") {
  for (const BoundaryRule rule : {BoundaryRule::none, BoundaryRule::edge_only, BoundaryRule::edge_and_corner})
    for (const bool triangles : {false, true}) {
      Mesh m = wavy_grid(5, 4, triangles);
      m.tags.boundary = rule;
      m.tags.holes = {7, 12};
      m.tags.creases = {{7, 8, 2}, {8, 9, 2}, {9, 10, 0.5}};  // along the grid's second row
      m.tags.corners = {{14, 10}};
      check_against_osd(m, triangles ? MeshScheme::loop : MeshScheme::catmull_clark, 3);
    }
}

TEST_CASE("Catmull–Clark's smooth-triangle rule = OpenSubdiv's TRI_SUB_SMOOTH, with creases",
          "[subdivision][mesh][oracle][creases]") {
  for (Mesh m : {pyramid(), tetrahedron(), wavy_grid(3, 3, true)}) {
    m.tags.triangles = TriangleRule::smooth;
    check_against_osd(m, MeshScheme::catmull_clark, 3);
    m.tags.creases = {{0, 1, 1.5}};
    check_against_osd(m, MeshScheme::catmull_clark, 3);
  }
}

TEST_CASE("random tags on closed and open meshes = OpenSubdiv Far (40 seeds, every option)",
          "[subdivision][mesh][oracle][creases]") {
  for (unsigned seed = 1; seed <= 40; ++seed) {
    std::mt19937 rng(seed);
    const bool triangles = seed % 2 == 0;
    Mesh m = seed % 4 < 2 ? torus(6, 5, triangles) : wavy_grid(4, 4, triangles);
    if (seed % 8 == 3) m = pyramid();  // triangles and a quad
    random_tags(m, rng, seed % 3 != 0);
    INFO("seed " << seed);
    const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
    check_against_osd(m, scheme, 3);
  }
}

TEST_CASE("face-varying UVs (linear everywhere) = OpenSubdiv's InterpolateFaceVarying, across seams",
          "[subdivision][mesh][oracle][uv]") {
  for (const bool triangles : {false, true}) {
    Mesh m = torus(6, 5, triangles);
    m.face_varying.push_back(lattice_uvs(m, 6, 5, true));
    m.tags.creases = {{0, 1, 2}, {1, 2, 0.5}};
    const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
    check_against_osd(m, scheme, 3);
    Mesh g = wavy_grid(4, 3, triangles);
    g.face_varying.push_back(lattice_uvs(g, 4, 3, false));
    g.tags.holes = {2};
    check_against_osd(g, scheme, 3);
  }
  Mesh b = torus(6, 5);
  b.face_varying.push_back(lattice_uvs(b, 6, 5, true));
  check_against_osd(b, MeshScheme::bilinear, 2);
}

TEST_CASE(
    "face-varying interpolation rules (none, corners only, corners+1, corners+2, boundaries, all) = "
    "OpenSubdiv's InterpolateFaceVarying: seams, darts, junctions, semi-sharp creases, boundaries",
    "[subdivision][mesh][oracle][uv]") {
  for (const FaceVaryingRule rule :
       {FaceVaryingRule::none, FaceVaryingRule::corners_only, FaceVaryingRule::corners_plus1,
        FaceVaryingRule::corners_plus2, FaceVaryingRule::boundaries, FaceVaryingRule::all}) {
    INFO("face-varying rule " << option_name(rule));
    for (const bool triangles : {false, true}) {
      const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
      // The lattice's seams: two loops crossing at one vertex of four values, on a torus with creases.
      Mesh m = torus(6, 5, triangles);
      m.face_varying.push_back(lattice_uvs(m, 6, 5, true));
      m.tags.creases = {{0, 1, 2}, {1, 2, 0.5}, {0, 6, 10}};
      m.tags.face_varying = rule;
      check_against_osd(m, scheme, 3);
      // Random seams under random creases, corners, holes, boundary rules and crease methods.
      for (unsigned seed = 1; seed <= 12; ++seed) {
        std::mt19937 rng(seed);
        Mesh r = seed % 2 == 0 ? torus(6, 5, triangles) : wavy_grid(4, 4, triangles);
        if (seed % 3 != 0) random_tags(r, rng, seed % 4 == 1);
        r.face_varying.push_back(random_seams(r, rng));
        r.tags.face_varying = rule;
        INFO("seed " << seed);
        check_against_osd(r, scheme, 3);
      }
    }
    Mesh b = wavy_grid(3, 3, false);  // bilinear: linear whatever the rule
    std::mt19937 rng(7);
    b.face_varying.push_back(random_seams(b, rng));
    b.tags.face_varying = rule;
    check_against_osd(b, MeshScheme::bilinear, 2);
  }
}

TEST_CASE(
    "a value on faces that do not touch is a corner whatever the faces' order (OpenSubdiv's depends on it)",
    "[subdivision][mesh][oracle][uv]") {
  // A 2 × 2 grid whose middle vertex has the values A B A B around it. OpenSubdiv lists a vertex's
  // values in ring order and misses the repeat of the second one after the first (Vtr::FVarLevel):
  // A B A B makes A a corner (faces that do not touch) but B two values, each a crease under `none`;
  // listing the faces from a B face swaps the two. cifs takes both as corners, in any order.
  const auto grid = [](bool from_b) {
    Mesh m = quad_grid(2, 2);
    FaceVaryingChannel c;
    c.values.resize(10, 2);
    for (int v = 0; v < 9; ++v) c.values.row(v) << 0.5 * (v % 3) + 0.01 * v * v, 0.5 * (v / 3) - 0.02 * v;
    c.values.row(9) << 0.3, 0.9;  // B
    c.indices = m.face_vertices;
    for (const std::size_t f : {1, 2})  // faces 1 and 2 (lower right, upper left) give vertex 4 the value B
      for (int h = m.face_offsets[f]; h < m.face_offsets[f + 1]; ++h)
        if (c.indices[static_cast<std::size_t>(h)] == 4) c.indices[static_cast<std::size_t>(h)] = 9;
    m.face_varying = {c};
    m.tags.face_varying = FaceVaryingRule::none;
    if (from_b) {  // faces listed from face 1: the same mesh
      std::vector<int> offsets{0}, corners, indices;
      for (const std::size_t f : {1, 2, 3, 0})
        for (int h = m.face_offsets[f]; h < m.face_offsets[f + 1]; ++h) {
          corners.push_back(m.face_vertices[static_cast<std::size_t>(h)]);
          indices.push_back(c.indices[static_cast<std::size_t>(h)]);
          if (h + 1 == m.face_offsets[f + 1]) offsets.push_back(static_cast<int>(corners.size()));
        }
      m.face_offsets = offsets;
      m.face_vertices = corners;
      m.face_varying[0].indices = indices;
    }
    return m;
  };
  // The values at the corners sitting on the middle vertex, after one level.
  const auto middle_values = [](const Mesh& r) {
    std::set<std::pair<double, double>> out;
    for (std::size_t k = 0; k < r.face_vertices.size(); ++k) {
      const auto v = static_cast<Eigen::Index>(r.face_vertices[k]);
      if ((r.vertices.row(v).head<2>() - Eigen::RowVector2d(1, 1)).norm() < 1e-12)
        out.emplace(r.face_varying[0].values(r.face_varying[0].indices[k], 0),
                    r.face_varying[0].values(r.face_varying[0].indices[k], 1));
    }
    return out;
  };
  for (const bool from_b : {false, true}) {
    const Mesh m = grid(from_b);
    const std::pair a{m.face_varying[0].values(4, 0), m.face_varying[0].values(4, 1)}, b{0.3, 0.9};
    CHECK(middle_values(subdivide(m, MeshScheme::catmull_clark, 1)) == std::set{a, b});  // both stay
    const auto osd = middle_values(osd_features(m, MeshScheme::catmull_clark, 1));
    CHECK(osd.size() == 3);  // one value kept, the other split in two creases
    CHECK(osd.count(from_b ? b : a) == 1);
  }
}
