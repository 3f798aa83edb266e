// SPDX-License-Identifier: MIT
// The whole-surface automaton of Catmull–Clark meshes with features (boundaries under both rules, sharp
// and semi-sharp creases under both crease methods, corners, darts, holes): its attractor against
// evaluate_limit_surface at the same (face, u, v), against the limits of the refined vertices
// (limit_mesh, an independent route), its regular nets against the bicubic B-spline of phantom points,
// and its fractal version (fractal_surface): watertight, the feature curves kept, the pieces of every face
// meeting inside it (each leaf's corners from its own net).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "subdivision/dyadic.hpp"
#include "subdivision/meshes.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
using Catch::Contains;

namespace {

struct Case {
  std::string name;
  Mesh mesh;
};

/// Quad meshes with every feature the automaton takes; each face's corner list turned by f mod 4
/// places, so that the patches' (s, t) meet the faces' (u, v) in all four ways.
std::vector<Case> feature_cases() {
  std::vector<Case> out;
  for (const CreaseMethod method : {CreaseMethod::uniform, CreaseMethod::chaikin}) {
    const std::string suffix = method == CreaseMethod::chaikin ? ", chaikin" : "";
    Mesh m = creased_cube();
    m.tags.crease_method = method;
    out.push_back({"creased cube" + suffix, turned_faces(m)});
    for (const BoundaryRule rule :
         {BoundaryRule::none, BoundaryRule::edge_only, BoundaryRule::edge_and_corner}) {
      Mesh g = wavy_grid(5, 4, false);
      g.tags.boundary = rule;
      g.tags.holes = {7, 12};
      g.tags.creases = {{7, 8, 2}, {8, 9, 2}, {9, 10, 0.5}, {1, 7, 1.5}, {14, 15, 10}, {15, 16, 10}};
      g.tags.corners = {{14, 10}};
      g.tags.crease_method = method;
      out.push_back({"grid, boundary rule " + std::string(option_name(rule)) + suffix, turned_faces(g)});
    }
  }
  Mesh darts = torus(6, 5);
  darts.tags.creases = {{0, 1, 10}, {1, 2, 10}};
  out.push_back({"torus (darts)", turned_faces(darts)});
  Mesh open = quad_grid(4, 3);  // untagged, open: boundary states only
  out.push_back({"open grid", turned_faces(open)});
  Mesh pyramid_once = catmull_clark(pyramid(), 1);  // valences 3 and 4, non-quads gone, two creases
  const auto edges = edges_of(pyramid_once);
  pyramid_once.tags.creases = {{edges[0][0], edges[0][1], 10}, {edges[5][0], edges[5][1], 2.5}};
  out.push_back({"pyramid, refined once", pyramid_once});
  for (unsigned seed = 1; seed <= 6; ++seed) {
    std::mt19937 rng(seed);
    Mesh m = seed % 2 == 0 ? torus(6, 5) : wavy_grid(4, 4, false);
    random_tags(m, rng, seed % 3 != 0);
    out.push_back({"random tags, seed " + std::to_string(seed), turned_faces(m)});
  }
  return out;
}

/// Per initial entry of `s`, the face's (u, v) at node (I, J) of its block at `side` cells a side: the
/// patch's (s, t) = (I, J) / side turned to the face's by corners[0]'s place among its corners.
std::vector<FacePoint> block_points(const SurfaceAutomaton& s, const Mesh& m, int side) {
  const MeshTopology t = build_topology(m);
  std::vector<FacePoint> out;
  for (std::size_t i = 0; i < s.automaton.initial.size(); ++i) {
    const int f = s.automaton.initial[i].segment;
    const auto corners = face(t, static_cast<std::size_t>(f));
    const auto turn = static_cast<std::size_t>(std::find(corners.begin(), corners.end(), s.corners[i][0]) -
                                               corners.begin());
    for (int I = 0; I <= side; ++I)
      for (int J = 0; J <= side; ++J) {
        const double a = static_cast<double>(I) / side, b = static_cast<double>(J) / side;
        const std::array<std::array<double, 2>, 4> uv{{{a, b}, {1 - b, a}, {1 - a, 1 - b}, {b, 1 - a}}};
        out.push_back({.face = f, .u = uv[turn][0], .v = uv[turn][1]});
      }
  }
  return out;
}

double scale_of(const Mesh& m) {
  return m.vertices.cwiseAbs().maxCoeff();
}

/// The largest distance between two leaves' corners at one grid node (I, J) of one face at `depth`, over
/// every face, each leaf's corners computed from its own net (the fixed points of its corner children,
/// corner (iu, iv) of child 2·iu + iv): zero when the faces' pieces meet along every edge created inside
/// them. patch_meshes and surface_automaton_mesh compute each node once per face, so they would not see a
/// crack there (the Loop counterpart is loop_inner_gap in test_fractal_loop.cpp: triangles, other children).
double cc_inner_gap(const SurfaceAutomaton& s, int depth) {
  const automata::Graph& g = s.automaton.graph;
  std::array<std::vector<Eigen::RowVectorXd>, 4> fixed;
  for (std::size_t c = 0; c < 4; ++c)
    fixed[c] = ifs::repeated_child_functionals(s.automaton, static_cast<int>(c));
  std::map<std::array<int, 2>, Eigen::RowVectorXd> seen;
  double gap = 0;
  // A square's corner (0, 0) at (I, J), side h; child 2·iu + iv at (I + iu·h/2, J + iv·h/2).
  const auto visit = [&](const auto& self, automata::StateId state, const Points& net, int I, int J,
                         int h) -> void {
    if (h == 1) {
      for (int k = 0; k < 4; ++k) {
        const Eigen::RowVectorXd p = fixed[static_cast<std::size_t>(k)][state] * net;
        const auto [it, fresh] = seen.emplace(std::array{I + k / 2, J + k % 2}, p);
        if (!fresh) gap = std::max(gap, (it->second - p).norm());
      }
      return;
    }
    const int half = h / 2;
    int k = 0;
    for (auto [e, end] = out_edges(state, g); e != end; ++e, ++k)
      self(self, target(*e, g), Points(g[*e].matrix * net), I + (k / 2) * half, J + (k % 2) * half, half);
  };
  for (std::size_t f = 0; f < s.nets.size(); ++f) {
    seen.clear();
    visit(visit, s.automaton.initial[f].state, s.nets[f], 0, 0, 1 << depth);
  }
  return gap;
}

}  // namespace

TEST_CASE("the surface automaton with features: its attractor is evaluate_limit_surface at the same points",
          "[subdivision][limit][features]") {
  const int depth = 3, side = 1 << depth;
  for (const Case& c : feature_cases()) {
    INFO(c.name);
    const SurfaceAutomaton s = surface_automaton(c.mesh, MeshScheme::catmull_clark);
    // Holes are skipped, every other face is one initial entry.
    const MeshRefinement r = refine_topology(c.mesh, MeshScheme::catmull_clark, 0);
    std::size_t faces = 0;
    for (std::size_t f = 0; f < face_count(c.mesh); ++f) faces += is_hole(r.features[0], f) ? 0 : 1;
    REQUIRE(s.automaton.initial.size() == faces);
    const Mesh blocks = ifs::patch_meshes(s.automaton, s.nets, depth);
    const SurfaceSample expected = evaluate_limit_surface(c.mesh, MeshScheme::catmull_clark,
                                                          block_points(s, c.mesh, side), {.partials = false});
    REQUIRE(expected.positions.rows() == blocks.vertices.rows());
    CHECK((blocks.vertices - expected.positions).cwiseAbs().maxCoeff() <= 1e-12 * scale_of(c.mesh));
  }
}

TEST_CASE("the surface automaton with features: every node of its attractor mesh is a refined vertex's limit",
          "[subdivision][limit][features]") {
  // Independent route: limit_stencils (the production rules' local spectra) on the mesh refined `depth`
  // times, sharpness still to spend included (under Chaikin's method with the far ends of semi-sharp
  // edges, whose other semi-sharp edges the method reads). Without holes the welded attractor has exactly
  // the vertices and faces of that mesh.
  const int depth = 2;
  for (const Case& c : feature_cases()) {
    INFO(c.name);
    const SurfaceAutomaton s = surface_automaton(c.mesh, MeshScheme::catmull_clark);
    const Mesh attractor = surface_automaton_mesh(s, depth);
    const Mesh limit = limit_mesh(c.mesh, MeshScheme::catmull_clark, depth);
    const bool holes = s.automaton.initial.size() < face_count(c.mesh);
    if (!holes) {
      const Mesh refined = subdivide(c.mesh, MeshScheme::catmull_clark, depth);
      CHECK(attractor.vertices.rows() == refined.vertices.rows());
      CHECK(face_count(attractor) == face_count(refined));
    }
    double worst = 0;
    for (Eigen::Index v = 0; v < attractor.vertices.rows(); ++v)
      worst = std::max(
          worst,
          std::sqrt(
              (limit.vertices.rowwise() - attractor.vertices.row(v)).rowwise().squaredNorm().minCoeff()));
    CHECK(worst <= 1e-12 * scale_of(c.mesh));
  }
}

TEST_CASE("the surface automaton with features: refined vertices converge to its attractor's nodes",
          "[subdivision][limit][features]") {
  // The mesh refined 1 + k times (plain refinement, no limit stencils): every node of the attractor at depth
  // 1 has a refined vertex within e_k, and e_k shrinks at least like λ^k, λ the largest subdominant
  // eigenvalue of these meshes' vertices (0.41 at the cube's valence-3 corners: λ² ≈ 1/6; ¼ at regular
  // crease and boundary vertices): by more than 3 every two levels.
  const std::vector<Case> cases = feature_cases();
  for (const char* name : {"creased cube, chaikin", "grid, boundary rule edge", "random tags, seed 2"}) {
    const auto c = std::find_if(cases.begin(), cases.end(), [&](const Case& x) { return x.name == name; });
    REQUIRE(c != cases.end());
    INFO(c->name);
    const Mesh attractor = surface_automaton_mesh(surface_automaton(c->mesh, MeshScheme::catmull_clark), 1);
    std::vector<double> error;
    for (const int k : {2, 4, 6}) {
      const Mesh refined = subdivide(c->mesh, MeshScheme::catmull_clark, 1 + k);
      double worst = 0;
      for (Eigen::Index v = 0; v < attractor.vertices.rows(); ++v)
        worst = std::max(
            worst,
            std::sqrt(
                (refined.vertices.rowwise() - attractor.vertices.row(v)).rowwise().squaredNorm().minCoeff()));
      error.push_back(worst);
    }
    CHECK(error[1] <= error[0] / 3);
    CHECK(error[2] <= error[1] / 3);
    CHECK(error[2] <= 1e-3 * scale_of(c->mesh));
  }
}

TEST_CASE("the chaos game on the surface automaton with features lands on the limit surface at its addresses",
          "[subdivision][limit][features]") {
  // A chaos point is the corner (0, 0) of the node it stands on; its address holds the initial entry (integer
  // part; holes have none) and the base-4 digits 2·iu + iv of the quarters, i.e. the dyadic (s, t) of that
  // corner, turned to the face's (u, v) by corners[0]'s place.
  const std::vector<Case> cases = feature_cases();
  for (const char* name : {"creased cube", "grid, boundary rule corner, chaikin", "random tags, seed 1"}) {
    const auto c = std::find_if(cases.begin(), cases.end(), [&](const Case& x) { return x.name == name; });
    REQUIRE(c != cases.end());
    INFO(c->name);
    const SurfaceAutomaton s = surface_automaton(c->mesh, MeshScheme::catmull_clark);
    const ifs::ChaosResult chaos = ifs::chaos_game(
        s.automaton, s.nets, {.samples = 2000, .seed = 5, .restart_diameter = 1e-5, .record_address = true});
    const MeshTopology t = build_topology(c->mesh);
    std::vector<FacePoint> at;
    for (const double address : chaos.address) at.push_back(address_point(s, t, address));
    const SurfaceSample expected =
        evaluate_limit_surface(c->mesh, MeshScheme::catmull_clark, at, {.partials = false});
    CHECK((chaos.points - expected.positions).cwiseAbs().maxCoeff() <= 1e-12 * scale_of(c->mesh));
  }
}

TEST_CASE(
    "the surface automaton with features: regular boundary, crease and corner patches are B-spline "
    "patches of phantom points",
    "[subdivision][limit][features]") {
  // A 6 × 4 grid under edge_and_corner with an infinitely sharp crease along row j = 2: each half is an
  // open grid whose corners are interpolated, every face a bicubic B-spline patch of the half's points
  // extended by reflection (P₋₁ = 2P₀ − P₁ across each boundary and the crease, twice at a corner).
  const int n = 6, m = 4;
  Mesh g = wavy_grid(n, m, false);
  g.tags.boundary = BoundaryRule::edge_and_corner;
  for (int i = 0; i < n; ++i)
    g.tags.creases.push_back({.a = 2 * (n + 1) + i, .b = 2 * (n + 1) + i + 1, .sharpness = 10});
  const SurfaceAutomaton s = surface_automaton(g, MeshScheme::catmull_clark);
  REQUIRE(num_vertices(s.automaton.graph) == 1);  // "regular" alone: no face needs a state of its own
  const auto point = [&](int i, int j) -> Eigen::RowVectorXd { return g.vertices.row(j * (n + 1) + i); };
  for (std::size_t f = 0; f < s.nets.size(); ++f) {
    const int i0 = static_cast<int>(f) % n, j0 = static_cast<int>(f) / n;
    const int low = j0 < 2 ? 0 : 2, high = j0 < 2 ? 2 : m;  // the half's rows
    const auto column = [&](int i, int j) -> Eigen::RowVectorXd {
      if (j < low) return 2 * point(i, low) - point(i, low + 1);
      if (j > high) return 2 * point(i, high) - point(i, high - 1);
      return point(i, j);
    };
    const auto extended = [&](int i, int j) -> Eigen::RowVectorXd {
      if (i < 0) return 2 * column(0, j) - column(1, j);
      if (i > n) return 2 * column(n, j) - column(n - 1, j);
      return column(i, j);
    };
    Points expected(16, 3);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) expected.row(4 * a + b) = extended(i0 - 1 + a, j0 - 1 + b);
    INFO("face " << f);
    CHECK(s.corners[f][0] == j0 * (n + 1) + i0);
    CHECK((s.nets[f] - expected).cwiseAbs().maxCoeff() <= 1e-12 * scale_of(g));
  }
}

TEST_CASE("the surface automaton with features: states named by the class of their irregular corners",
          "[subdivision][limit][features]") {
  const auto names = [](const Mesh& m) {
    const SurfaceAutomaton s = surface_automaton(m, MeshScheme::catmull_clark);
    std::vector<std::string> out;
    for (automata::StateId v = 0; v < num_vertices(s.automaton.graph); ++v)
      out.push_back(s.automaton.graph[v].name);
    std::sort(out.begin(), out.end());
    return out;
  };
  // An open grid under edge_only: its four corners are smooth boundary vertices of one face, each met
  // at corner 0 of its face and looping there.
  CHECK(names(quad_grid(4, 3)) == std::vector<std::string>{"B1", "regular"});
  // A boundary vertex of 3 faces (a grid's boundary vertex with a face removed around it): one state per
  // face around it, counted from the boundary edge.
  Mesh notch = quad_grid(4, 3);
  notch.face_vertices.erase(notch.face_vertices.begin() + 4 * 5, notch.face_vertices.begin() + 4 * 6);
  notch.face_offsets.pop_back();
  const std::vector<std::string> b3 = names(notch);
  for (const char* b : {"B3:0", "B3:1", "B3:2"})
    CHECK(std::any_of(b3.begin(), b3.end(),
                      [&](const std::string& x) { return x.find(b) != std::string::npos; }));
  Mesh g = quad_grid(4, 3);
  g.tags.boundary = BoundaryRule::edge_and_corner;  // interpolated corners: regular corner patches
  CHECK(names(g) == std::vector<std::string>{"regular"});
  // A crease across a torus ending inside: darts at its ends, 2 + 2 crease vertices between (regular).
  Mesh t = torus(6, 5);
  t.tags.creases = {{0, 1, 10}, {1, 2, 10}};
  const std::vector<std::string> darts = names(t);
  for (const char* dart : {"D4:0", "D4:1", "D4:2", "D4:3"})  // the dart's four faces, from its edge
    CHECK(std::any_of(darts.begin(), darts.end(),
                      [&](const std::string& x) { return x.find(dart) != std::string::npos; }));
  // A semi-sharp crease: states with sharpness left ("~"), spent after two steps.
  Mesh semi = torus(6, 5);
  semi.tags.creases = {{0, 1, 2}, {1, 2, 2}, {2, 3, 2}, {3, 4, 2}, {4, 5, 2}, {5, 0, 2}};
  const std::vector<std::string> spent = names(semi);
  CHECK(std::any_of(spent.begin(), spent.end(),
                    [](const std::string& x) { return x.find("~2") != std::string::npos; }));
}

TEST_CASE("fractal Catmull–Clark with features: boundaries and creases kept, watertight, the inside moves",
          "[subdivision][limit][features]") {
  Mesh m = wavy_grid(5, 4, false);
  m.tags.creases = {{7, 8, 10}, {8, 9, 10}, {9, 10, 10}, {14, 15, 1.5}};
  m.tags.corners = {{20, 10}};
  m.tags.holes = {13};
  const SurfaceAutomaton smooth = surface_automaton(m, MeshScheme::catmull_clark);
  const int depth = 4, side = 1 << depth, row = side + 1;
  const Mesh flat = ifs::patch_meshes(smooth.automaton, smooth.nets, depth);
  ifs::PerturbOptions perturb;
  perturb.amplitude = 0.3;
  perturb.seed = 3;
  const FractalSurface rough = fractal_surface(smooth, perturb);
  const Mesh fractal = ifs::patch_meshes(rough.surface.automaton, rough.surface.nets, depth);
  REQUIRE(fractal.vertices.rows() == flat.vertices.rows());
  // Every face's border (its boundary curves: the mesh's boundary, creases, and the curves between
  // faces) is the smooth surface's; inside, the surface moved.
  const double scale = scale_of(m);
  double border = 0, inside = 0;
  for (Eigen::Index v = 0; v < fractal.vertices.rows(); ++v) {
    const auto I = static_cast<int>(v % (row * row)) / row, J = static_cast<int>(v % (row * row)) % row;
    const double d = (fractal.vertices.row(v) - flat.vertices.row(v)).norm();
    double& worst = I == 0 || J == 0 || I == side || J == side ? border : inside;
    worst = std::max(worst, d);
  }
  CHECK(border <= 1e-12 * scale);
  CHECK(inside >= 1e-3 * scale);
  // Neighbouring faces compute their shared nodes each from its own net: equal to 1e-12.
  const std::vector<FacePoint> at = block_points(smooth, m, side);
  const SurfaceSample limit = evaluate_limit_surface(m, MeshScheme::catmull_clark, at, {.partials = false});
  double curves = 0;
  for (Eigen::Index v = 0; v < fractal.vertices.rows(); ++v) {
    const FacePoint& p = at[static_cast<std::size_t>(v)];
    if (p.u == 0 || p.v == 0 || p.u == 1 || p.v == 1)
      curves = std::max(curves, (fractal.vertices.row(v) - limit.positions.row(v)).norm());
  }
  CHECK(curves <= 1e-12 * scale);
  // Welded by the topology: the mesh's Euler characteristic and boundary (the hole's border included).
  const Mesh welded = surface_automaton_mesh(rough.surface, depth);
  Mesh solid = m;
  solid.face_offsets = {0};
  solid.face_vertices.clear();
  for (std::size_t f = 0; f < face_count(m); ++f) {
    if (f == 13) continue;
    for (const int v : face(m, f)) solid.face_vertices.push_back(v);
    solid.face_offsets.push_back(static_cast<int>(solid.face_vertices.size()));
  }
  CHECK(euler_characteristic(build_topology(welded)) == euler_characteristic(build_topology(solid)));
}

TEST_CASE("fractal Catmull–Clark: the pieces of every face meet along the edges created inside it",
          "[subdivision][limit][features][fractal]") {
  // The checks above compare nodes across faces and with the smooth surface, each node computed once per
  // face: two sibling pieces that disagree along their shared side inside a face pass them. Here every
  // leaf computes its own corners. Valence 3 (the cube), 3 and 5 (the bipyramid, refined twice: its
  // triangles' centres and its poles), and boundaries, sharp and semi-sharp creases, a corner and a hole.
  Mesh features = wavy_grid(5, 4, false);
  features.tags.creases = {{7, 8, 10}, {8, 9, 10}, {9, 10, 10}, {14, 15, 1.5}};
  features.tags.corners = {{20, 10}};
  features.tags.holes = {13};
  const std::vector<Case> cases = {{"cube (3)", turned_faces(catmull_clark(cube(), 1))},
                                   {"bipyramid (3, 4, 5)", turned_faces(catmull_clark(bipyramid(), 2))},
                                   {"grid with features", turned_faces(features)}};
  const int depth = 3;
  ifs::PerturbOptions perturb;
  perturb.amplitude = 0.3;
  perturb.seed = 3;
  for (const Case& c : cases) {
    INFO(c.name);
    const FractalSurface rough =
        fractal_surface(surface_automaton(c.mesh, MeshScheme::catmull_clark), perturb);
    REQUIRE(!rough.perturbation.values.empty());
    const double scale = scale_of(c.mesh);
    CHECK(cc_inner_gap(rough.surface, depth) <= 1e-12 * scale);
    // The check can fail: a crack planted inside every regular patch (child GH of the patch cell moves
    // its corner point (3, 3), which only its sides inside the parent read) is seen.
    SurfaceAutomaton cracked = rough.surface;
    automata::Graph& g = cracked.automaton.graph;
    const automata::StateId cell = rough.perturbation.system.automaton.initial.at(0).state;
    Eigen::MatrixXd& M = g[*out_edges(cell, g).first].matrix;
    M(15, 15) += 0.05;
    M(15, 14) -= 0.05;
    CHECK(cc_inner_gap(cracked, depth) >= 1e-4 * scale);
  }
}

TEST_CASE("the surface automaton with features: what it refuses, one line naming it",
          "[subdivision][limit][features]") {
  Mesh creased = pyramid();
  creased.tags.creases = {{0, 1, 10}};
  CHECK_THROWS_WITH(surface_automaton(creased, MeshScheme::catmull_clark),
                    Contains("catmull-clark surface automaton: face 1: not a quad (refine one level first)"));
  Mesh blz = quad_grid(3, 3);
  blz.tags.rules = RuleSet::blz;
  CHECK_THROWS_WITH(surface_automaton(blz, MeshScheme::catmull_clark),
                    Contains("the rule set 'blz' is not built"));
}
