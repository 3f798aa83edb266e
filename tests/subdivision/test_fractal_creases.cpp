// SPDX-License-Identifier: MIT
// Fractal crease lines (fractal_surface with FractalFeatureOptions): "a smooth surface whose crease
// lines are fractal", Catmull–Clark and Loop. Checked against independent routes: the crease's own
// 1-D BC-IFS built here from the whole crease polygon (ifs::curve_bcifs of a NURBS curve), the smooth
// surface's attractor, each face's nodes computed from its own net alone, the mesh's Euler
// characteristic and the box-counting dimension of the crease's points.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "subdivision/meshes.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;
using Catch::Contains;

namespace {

/// A 6 × 4 wavy grid (quads or triangles, corner lists turned all ways) with an infinitely sharp crease
/// across row j = 2 (vertices 14 … 20, corners at the boundary), a crease up from its middle vertex 17
/// (a corner: three sharp edges) to 24, a dart, and a semi-sharp crease (1.5) elsewhere.
Mesh creased_grid_for_fractal_creases(bool triangles) {
  Mesh m = wavy_grid(6, 4, triangles);
  m.tags.creases = {{14, 15, 10}, {15, 16, 10}, {16, 17, 10}, {17, 18, 10},
                    {18, 19, 10}, {19, 20, 10}, {17, 24, 10}, {8, 9, 1.5}};
  return turned_faces(m, triangles ? 3 : 4);
}

/// The crease's chains (corner to corner) as the test reads them from the tags: 14 … 17 and 17 … 20.
const std::vector<std::vector<int>> kCreaseChains = {{14, 15, 16, 17}, {17, 18, 19, 20}};

double size_of_mesh_for_creases(const Mesh& m) {
  return (m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff()).norm();
}

/// The crease chain's curve: the uniform cubic B-spline of its polygon, phantom points 2a − b beyond its
/// corner ends, as one NURBS curve; its perturbed BC-IFS's nodes at `depth`, in order along the chain.
Points chain_nodes(const Mesh& m, const std::vector<int>& chain, const ifs::PerturbOptions& perturb,
                   int depth) {
  const auto n = static_cast<Eigen::Index>(chain.size());
  Points control(n + 2, m.vertices.cols());
  for (Eigen::Index k = 0; k < n; ++k)
    control.row(k + 1) = m.vertices.row(chain[static_cast<std::size_t>(k)]);
  control.row(0) = 2 * control.row(1) - control.row(2);
  control.row(n + 1) = 2 * control.row(n) - control.row(n - 1);
  nurbs::Knots knots(static_cast<std::size_t>(n + 6));
  std::iota(knots.begin(), knots.end(), 0.0);
  const nurbs::Curve curve = nurbs::make_curve(3, knots, control);
  const ifs::Bcifs system = ifs::curve_bcifs(curve);
  const ifs::Perturbation p = ifs::perturb(system, perturb);
  std::vector<Points> nets;
  for (Eigen::Index s = 0; s + 1 < n; ++s) nets.push_back(control.middleRows(s, 4));
  const ifs::EdgePieces pieces = ifs::edge_pieces(p.system, nets, depth);
  Points out(pieces.start.rows() + 1, pieces.start.cols());
  out.topRows(pieces.start.rows()) = pieces.start;
  out.bottomRows(1) = pieces.end.bottomRows(1);
  return out;
}

/// One face's nodes computed from its own net alone: the fractal surface restricted to entry k.
Mesh face_block_for_creases(const FractalSurface& f, std::size_t k, int depth) {
  FractalSurface one = f;
  one.surface.automaton.initial = {f.surface.automaton.initial[k]};
  one.surface.nets = {f.surface.nets[k]};
  one.surface.corners = {f.surface.corners[k]};
  return surface_automaton_mesh(one, depth);
}

/// The nodes of a face's block along its side from mesh vertex a to b (empty if ab is no side of it).
Points side_nodes_for_creases(const Mesh& block, bool quad, const std::array<int, 4>& c, int a, int b,
                              int side) {
  const int n = quad ? 4 : 3;
  Points out(side + 1, block.vertices.cols());
  for (int k = 0; k < n; ++k) {
    const int p = c[static_cast<std::size_t>(k)], q = c[static_cast<std::size_t>((k + 1) % n)];
    if (!((p == a && q == b) || (p == b && q == a))) continue;
    for (int at = 0; at <= side; ++at) {
      int I = 0, J = 0;  // quads: (I, J); triangles: (i, j)
      if (quad) {
        const std::array<std::array<int, 2>, 4> place{
            {{at, 0}, {side, at}, {side - at, side}, {0, side - at}}};
        I = place[static_cast<std::size_t>(k)][0], J = place[static_cast<std::size_t>(k)][1];
      } else {
        const std::array<std::array<int, 2>, 3> place{{{at, 0}, {side - at, at}, {0, side - at}}};
        I = place[static_cast<std::size_t>(k)][0], J = place[static_cast<std::size_t>(k)][1];
      }
      const int node = quad ? I * (side + 1) + J : I * (side + 1) - I * (I - 1) / 2 + J;
      out.row(p == a ? at : side - at) = block.vertices.row(node);
    }
    return out;
  }
  return {};
}

void check_fractal_creases(bool triangles) {
  const MeshScheme scheme = triangles ? MeshScheme::loop : MeshScheme::catmull_clark;
  const bool quad = !triangles;
  const Mesh m = creased_grid_for_fractal_creases(triangles);
  const double size = size_of_mesh_for_creases(m);
  const SurfaceAutomaton smooth = surface_automaton(m, scheme);
  const int depth = 3, side = 1 << depth;
  ifs::PerturbOptions none, rough;
  rough.amplitude = 0.3;
  rough.seed = 5;
  FractalFeatureOptions creases;
  creases.creases = true;
  creases.perturbation.amplitude = 0.4;
  creases.perturbation.seed = 7;

  // Crease amplitude 0: the surface of fractal_surface without features (surface amplitude 0.3).
  FractalFeatureOptions flat = creases;
  flat.perturbation.amplitude = 0;
  const FractalSurface same = fractal_surface(m, smooth, rough, flat);
  REQUIRE(same.features.nets.size() == 6);  // the crease across; the edge to the dart stays smooth
  const Mesh rough_mesh = surface_automaton_mesh(same.surface, depth);
  CHECK((surface_automaton_mesh(same, depth).vertices - rough_mesh.vertices).cwiseAbs().maxCoeff() <=
        1e-12 * size);

  // Surface amplitude 0, crease amplitude 0.4.
  const FractalSurface fractal = fractal_surface(m, smooth, none, creases);
  const Mesh welded = surface_automaton_mesh(fractal, depth);
  const Mesh limit = surface_automaton_mesh(smooth, depth);
  REQUIRE(welded.vertices.rows() == limit.vertices.rows());
  CHECK(euler_characteristic(build_topology(welded)) == euler_characteristic(build_topology(m)));
  // Faces not touching a fractal crease edge: every node is the smooth limit surface's.
  const auto fractal_edge = [&](int a, int b) {
    return fractal.features.nets.contains({std::min(a, b), std::max(a, b)});
  };
  const std::size_t cells = std::size_t{1} << (2 * depth);
  const std::size_t corners_per_cell = quad ? 4 : 3;
  double away = 0, beside = 0;
  for (std::size_t k = 0; k < fractal.surface.corners.size(); ++k) {
    const auto& c = fractal.surface.corners[k];
    bool touches = false;
    for (std::size_t s = 0; s < corners_per_cell; ++s)
      touches = touches || fractal_edge(c[s], c[(s + 1) % corners_per_cell]);
    for (std::size_t cell = k * cells; cell < (k + 1) * cells; ++cell)
      for (std::size_t v = 0; v < corners_per_cell; ++v) {
        const int node = welded.face_vertices[cell * corners_per_cell + v];
        double& worst = touches ? beside : away;
        worst = std::max(worst, (welded.vertices.row(node) - limit.vertices.row(node)).norm());
      }
  }
  CHECK(away <= 1e-12 * size);
  CHECK(beside >= 1e-3 * size);  // the crease curve moves, and the faces beside it with it

  // Both faces of every crease edge, each from its own net, have the nodes of the crease's own 1-D
  // BC-IFS along it (built here from the whole chain), read in the same direction.
  std::vector<Mesh> blocks;
  for (std::size_t k = 0; k < fractal.surface.corners.size(); ++k)
    blocks.push_back(face_block_for_creases(fractal, k, depth));
  double along = 0, moved = 0;
  int sides_seen = 0;
  for (const auto& chain : kCreaseChains) {
    const Points curve = chain_nodes(m, chain, creases.perturbation, depth);
    const Points smooth_curve = chain_nodes(m, chain, none, depth);
    moved = std::max(moved, (curve - smooth_curve).rowwise().norm().maxCoeff());
    for (std::size_t e = 0; e + 1 < chain.size(); ++e) {
      const Points expected = curve.middleRows(static_cast<Eigen::Index>(e) * side, side + 1);
      CHECK(
          (feature_curve_nodes(fractal.features,
                               {std::min(chain[e], chain[e + 1]), std::max(chain[e], chain[e + 1])}, depth) -
           (chain[e] < chain[e + 1] ? expected : Points(expected.colwise().reverse())))
              .cwiseAbs()
              .maxCoeff() <= 1e-12 * size);
      int faces = 0;
      for (std::size_t k = 0; k < blocks.size(); ++k) {
        const Points nodes =
            side_nodes_for_creases(blocks[k], quad, fractal.surface.corners[k], chain[e], chain[e + 1], side);
        if (nodes.size() == 0) continue;
        ++faces;
        along = std::max(along, (nodes - expected).cwiseAbs().maxCoeff());
      }
      CHECK(faces == 2);
      sides_seen += faces;
    }
  }
  CHECK(sides_seen == 12);
  CHECK(along <= 1e-12 * size);
  CHECK(moved >= 1e-3 * size);
}

}  // namespace

TEST_CASE("fractal creases, Catmull–Clark: the crease's own BC-IFS, watertight, the rest smooth",
          "[subdivision][fractal][creases]") {
  check_fractal_creases(false);
}

TEST_CASE("fractal creases, Loop: the crease's own BC-IFS, watertight, the rest smooth",
          "[subdivision][fractal][creases]") {
  check_fractal_creases(true);
}

TEST_CASE("fractal boundaries, Catmull–Clark: the boundary curve's own BC-IFS, the faces along it",
          "[subdivision][fractal][creases]") {
  // A 3 × 2 grid under edge_and_corner: four boundary chains between its corners, the first 0 … 3.
  Mesh m = wavy_grid(3, 2, false);
  m.tags.boundary = BoundaryRule::edge_and_corner;
  m = turned_faces(m);
  const double size = size_of_mesh_for_creases(m);
  FractalFeatureOptions boundaries;
  boundaries.boundaries = true;
  boundaries.perturbation.amplitude = 0.8;
  boundaries.perturbation.seed = 7;
  const SurfaceAutomaton smooth = surface_automaton(m, MeshScheme::catmull_clark);
  const FractalSurface fractal = fractal_surface(m, smooth, {}, boundaries);
  CHECK(fractal.features.nets.size() == 10);  // every boundary edge
  const int depth = 3, side = 1 << depth;
  const std::vector<int> chain{0, 1, 2, 3};
  const Points curve = chain_nodes(m, chain, boundaries.perturbation, depth);
  CHECK((curve - chain_nodes(m, chain, {}, depth)).rowwise().norm().maxCoeff() >= 1e-3 * size);
  double along = 0;
  for (std::size_t k = 0; k < fractal.surface.corners.size(); ++k) {
    const Mesh block = face_block_for_creases(fractal, k, depth);
    for (std::size_t e = 0; e + 1 < chain.size(); ++e) {
      const Points nodes =
          side_nodes_for_creases(block, true, fractal.surface.corners[k], chain[e], chain[e + 1], side);
      if (nodes.size() > 0)
        along = std::max(
            along,
            (nodes - curve.middleRows(static_cast<Eigen::Index>(e) * side, side + 1)).cwiseAbs().maxCoeff());
    }
  }
  CHECK(along <= 1e-12 * size);
  CHECK(euler_characteristic(build_topology(surface_automaton_mesh(fractal, depth))) ==
        euler_characteristic(build_topology(m)));
}

TEST_CASE("fractal creases: the crease curve's points have a box-counting dimension above 1",
          "[subdivision][fractal][creases]") {
  const Mesh m = creased_grid_for_fractal_creases(false);
  ifs::PerturbOptions perturb;  // large enough to roughen the curve (at 0.4 its dimension is still 1.0)
  perturb.amplitude = 0.8;
  perturb.seed = 3;
  ifs::BoxCountingOptions boxes;
  boxes.min_boxes = 64;  // 3 segments × 2^12 points: scales of 64 … 3000 boxes
  const ifs::BoxCountingResult smooth = ifs::box_counting(chain_nodes(m, kCreaseChains[0], {}, 12), boxes);
  const ifs::BoxCountingResult rough =
      ifs::box_counting(chain_nodes(m, kCreaseChains[0], perturb, 12), boxes);
  INFO("smooth " << smooth.dimension << ", fractal " << rough.dimension << " ± " << rough.uncertainty);
  CHECK(smooth.dimension == Approx(1).margin(0.05));
  CHECK(rough.dimension > 1.2);
}

TEST_CASE("fractal creases: what they refuse, one line naming it", "[subdivision][fractal][creases]") {
  FractalFeatureOptions creases;
  creases.creases = true;
  creases.perturbation.amplitude = 0.3;
  Mesh semi = wavy_grid(3, 3, false);
  semi.tags.creases = {{5, 6, 2}};
  CHECK_THROWS_WITH(fractal_surface(semi, surface_automaton(semi, MeshScheme::catmull_clark), {}, creases),
                    Contains("no infinitely sharp crease") && Contains("semi-sharp"));
  Mesh darts = torus(6, 5);
  darts.tags.creases = {{0, 1, 10}, {1, 2, 10}};
  CHECK_THROWS_WITH(fractal_surface(darts, surface_automaton(darts, MeshScheme::catmull_clark), {}, creases),
                    Contains("dart"));
  FractalFeatureOptions boundaries;
  boundaries.boundaries = true;
  const Mesh closed = catmull_clark(cube(), 1);
  CHECK_THROWS_WITH(
      fractal_surface(closed, surface_automaton(closed, MeshScheme::catmull_clark), {}, boundaries),
      Contains("no boundary"));
  const Mesh grid = creased_grid_for_fractal_creases(false);
  CHECK_THROWS_WITH(fractal_surface(closed, surface_automaton(grid, MeshScheme::catmull_clark), {}, creases),
                    Contains("not the surface automaton's"));
}
