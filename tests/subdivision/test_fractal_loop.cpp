// SPDX-License-Identifier: MIT
// Fractal Loop surfaces: the regular Loop patch as a triangular BC-IFS (loop_triangle_patch,
// ifs::triangle_bcifs) and the whole-surface automaton with it (fractal_surface). Checked against
// routes that do not use them: Loop's rules applied on the three-direction lattice (the four maps),
// the patch's own attractor (its sides and their symmetries), the limit stencils of the refined mesh
// (the unperturbed attractor), and each face's attractor computed alone (watertight after perturbing).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs_triangle.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "subdivision/loop_nodes.hpp"
#include "subdivision/mesh_compare.hpp"
#include "subdivision/meshes.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using namespace cifs_test;

namespace {

using LoopLattice = std::array<int, 2>;

/// The lattice of the patch's (s, t): a vertex's neighbours counter-clockwise.
constexpr std::array<LoopLattice, 6> kLoopDirections{{{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}}};

/// loop_patch(6)'s 12 points as limit.hpp orders them: the corner (0, 0), its ring counter-clockwise
/// from the next corner (1, 0), the 3rd to 5th neighbours of (1, 0) and the 4th and 5th of (0, 1), each
/// counted counter-clockwise from the corner.
constexpr std::array<LoopLattice, 12> kLoopPatchPoints{
    {{0, 0}, {1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}, {2, -1}, {2, 0}, {1, 1}, {0, 2}, {-1, 2}}};

LoopLattice lattice_sum(LoopLattice a, LoopLattice b, int sign = 1) {
  return {a[0] + sign * b[0], a[1] + sign * b[1]};
}

/// One Loop step on the regular lattice: the weights of the fine point q (in half units) on the coarse
/// points. Even q: the vertex q/2, 10/16 on it and 1/16 on each neighbour (β = 1/16 at valence 6);
/// otherwise the midpoint of a coarse edge, 3/8 on its ends and 1/8 on the two vertices beside it.
std::map<LoopLattice, double> loop_step_weights(LoopLattice q) {
  const auto even = [](LoopLattice p) { return p[0] % 2 == 0 && p[1] % 2 == 0; };
  std::map<LoopLattice, double> w;
  if (even(q)) {
    const LoopLattice v{q[0] / 2, q[1] / 2};
    w[v] += 10.0 / 16;
    for (const LoopLattice& d : kLoopDirections) w[lattice_sum(v, d)] += 1.0 / 16;
    return w;
  }
  for (std::size_t k = 0; k < 6; ++k) {
    const LoopLattice a2 = lattice_sum(q, kLoopDirections[k], -1);
    if (!even(a2)) continue;
    const LoopLattice a{a2[0] / 2, a2[1] / 2};
    w[a] += 3.0 / 8;
    w[lattice_sum(a, kLoopDirections[k])] += 3.0 / 8;
    w[lattice_sum(a, kLoopDirections[(k + 5) % 6])] += 1.0 / 8;
    w[lattice_sum(a, kLoopDirections[(k + 1) % 6])] += 1.0 / 8;
    return w;
  }
  FAIL("no coarse edge has its midpoint at (" << q[0] << ", " << q[1] << ")");
  return w;
}

/// The child whose point i sits at origin + sign·kLoopPatchPoints[i] in half units, on the patch's net.
Eigen::MatrixXd loop_child_from_lattice(LoopLattice origin, int sign) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(12, 12);
  for (std::size_t i = 0; i < 12; ++i)
    for (const auto& [p, weight] : loop_step_weights(lattice_sum(origin, kLoopPatchPoints[i], sign))) {
      const auto it = std::find(kLoopPatchPoints.begin(), kLoopPatchPoints.end(), p);
      REQUIRE(it != kLoopPatchPoints.end());  // a child reads the patch's points only
      M(static_cast<Eigen::Index>(i), it - kLoopPatchPoints.begin()) += weight;
    }
  return M;
}

/// Closed triangle meshes with extraordinary vertices of valence 3, 4, 5, 7 (one per face after a
/// step), corner lists turned by f mod 3 so that the patches' (s, t) meet the faces' (u, v) all ways.
std::vector<std::pair<const char*, Mesh>> fractal_loop_meshes() {
  return {{"tetrahedron (3)", turned_faces(loop(tetrahedron(), 1), 3)},
          {"octahedron (4)", turned_faces(loop(octahedron(), 1), 3)},
          {"bipyramid (4, 5)", turned_faces(loop(bipyramid(), 1), 3)},
          {"bipyramid (4, 7)", turned_faces(loop(bipyramid_of(7), 1), 3)}};
}

}  // namespace

TEST_CASE("the regular Loop patch as a BC-IFS: its four maps are one Loop step on the lattice",
          "[subdivision][limit][fractal]") {
  const ifs::TrianglePatch patch = loop_triangle_patch();
  // C0, C1, C2 at corners (0, 0), (½, 0), (0, ½) in place; M at (½, ½) turned by a half turn.
  const std::array<LoopLattice, 4> origin{{{0, 0}, {1, 0}, {0, 1}, {1, 1}}};
  for (std::size_t c = 0; c < 4; ++c) {
    INFO("child " << c);
    const Eigen::MatrixXd expected = loop_child_from_lattice(origin[c], c == 3 ? -1 : 1);
    CHECK((patch.children[c] - expected).cwiseAbs().maxCoeff() <= 1e-14);
  }
}

TEST_CASE("the regular Loop patch as a BC-IFS: its sides, their turns and reversal, from its attractor",
          "[subdivision][limit][fractal]") {
  const ifs::TrianglePatch patch = loop_triangle_patch();
  REQUIRE(patch.sides[0].size() == 10);
  // The patch alone, unperturbed (its BC-IFS holds the box spline's matrices), on the unit nets e_r:
  // node values along a side are the basis function of point r there.
  SurfaceAutomaton one;
  one.scheme = MeshScheme::loop;
  one.automaton = ifs::triangle_bcifs(patch).automaton;
  one.corners = {{0, 1, 2, -1}};
  const int depth = 3, side = 1 << depth;
  std::array<Points, 12> basis;
  for (std::size_t r = 0; r < 12; ++r) {
    one.nets = {Points::Zero(12, 1)};
    one.nets[0](static_cast<Eigen::Index>(r), 0) = 1;
    basis[r] = surface_automaton_mesh(one, depth).vertices;
  }
  // Side k at x = i/side: from corner k to corner k + 1.
  const auto along = [&](std::size_t r, int k, int i) {
    const int node = k == 0   ? loop_node(i, 0, side)
                     : k == 1 ? loop_node(side - i, i, side)
                              : loop_node(0, side - i, side);
    return basis[r](node, 0);
  };
  for (int k = 0; k < 3; ++k) {
    INFO("side " << k);
    const auto& rows = patch.sides[static_cast<std::size_t>(k)];
    for (std::size_t r = 0; r < 12; ++r) {
      double largest = 0;
      for (int i = 0; i <= side; ++i) largest = std::max(largest, std::abs(along(r, k, i)));
      INFO("point " << r);
      CHECK((largest > 1e-3) == (std::find(rows.begin(), rows.end(), static_cast<int>(r)) != rows.end()));
    }
    for (std::size_t n = 0; n < rows.size(); ++n)
      for (int i = 0; i <= side; ++i) {
        const auto r = static_cast<std::size_t>(rows[n]), r0 = static_cast<std::size_t>(patch.sides[0][n]),
                   back =
                       static_cast<std::size_t>(patch.sides[0][static_cast<std::size_t>(patch.reverse[n])]);
        // Turned by k thirds, side k's n-th point is side 0's; read from across, side 0's n-th is reverse[n].
        CHECK(std::abs(along(r, k, i) - along(r0, 0, i)) <= 1e-14);
        CHECK(std::abs(along(r0, 0, i) - along(back, 0, side - i)) <= 1e-14);
      }
  }
}

TEST_CASE(
    "the regular Loop patch as a BC-IFS: the box spline's matrices are admissible, one free coefficient",
    "[subdivision][limit][fractal]") {
  const ifs::Bcifs system = ifs::triangle_bcifs(loop_triangle_patch());
  double worst = 0;
  for (const auto& [name, r] : ifs::constraint_residuals(system)) worst = std::max(worst, r);
  CHECK(worst <= 1e-15);
  const ifs::AdmissibleSpace space = ifs::admissible_space(system);
  const std::vector<std::string> names = ifs::free_names(system, space);
  // Measured, not derived: one free coefficient (the linear triangle has one too, where an inner edge
  // with one end on the patch's sides is split; tests/ifs/test_bcifs_triangle.cpp).
  CHECK(names.size() == 1);
}

TEST_CASE("fractal Loop, unperturbed: the attractor is Loop's limit surface (limit stencils)",
          "[subdivision][limit][fractal]") {
  const int depth = 3;
  for (const auto& [name, m] : fractal_loop_meshes()) {
    INFO(name);
    const SurfaceAutomaton smooth = surface_automaton(m, MeshScheme::loop);
    const FractalSurface same = fractal_surface(smooth, {});
    CHECK(same.perturbation.residual <= 1e-14);
    const Mesh attractor = surface_automaton_mesh(same.surface, depth);
    const Mesh limit = limit_mesh(m, MeshScheme::loop, depth);
    match_vertices(attractor.vertices, limit.vertices, 1e-12);
    CHECK(face_count(attractor) == face_count(limit));
  }
}

TEST_CASE("fractal Loop: watertight, every face keeps the smooth boundary curves, the inside moves",
          "[subdivision][limit][fractal]") {
  const int depth = 3, side = 1 << depth;
  for (const auto& [name, m] : fractal_loop_meshes()) {
    INFO(name);
    const SurfaceAutomaton smooth = surface_automaton(m, MeshScheme::loop);
    ifs::PerturbOptions perturb;
    perturb.amplitude = 0.3;
    perturb.seed = 5;
    const FractalSurface rough = fractal_surface(smooth, perturb);
    CHECK(rough.perturbation.residual <= 1e-12);
    CHECK(rough.perturbation.contraction.delta < 1);
    const double scale = m.vertices.cwiseAbs().maxCoeff();
    // Each face alone, from its own net: nodes on mesh edges and vertices agree with every other face
    // holding them, and with the smooth surface; inside, the surface moved.
    std::map<std::array<int, 3>, Eigen::RowVectorXd> shared;
    double across = 0, border = 0, inside = 0;
    std::size_t compared = 0;
    const std::vector<Points> rough_faces = loop_face_nodes(rough.surface, depth),
                              smooth_faces = loop_face_nodes(smooth, depth);
    for (std::size_t f = 0; f < rough.surface.nets.size(); ++f) {
      const Points &ours = rough_faces[f], &flat = smooth_faces[f];
      for (int i = 0; i <= side; ++i)
        for (int j = 0; i + j <= side; ++j) {
          const Eigen::RowVectorXd p = ours.row(loop_node(i, j, side));
          const double moved = (p - flat.row(loop_node(i, j, side))).norm();
          const std::array<int, 3> key = loop_node_key(rough.surface.corners[f], i, j, side);
          if (key[0] < 0) {
            inside = std::max(inside, moved);
            continue;
          }
          border = std::max(border, moved);
          const auto [it, fresh] = shared.emplace(key, p);
          if (!fresh) {
            across = std::max(across, (it->second - p).norm());
            ++compared;
          }
        }
    }
    // Inside each face too: the leaves meet on every edge the subdivision created.
    CHECK(loop_inner_gap(rough.surface, depth) <= 1e-12 * scale);
    CHECK(compared > shared.size());  // every edge node twice, every vertex node at least three times
    CHECK(across <= 1e-12 * scale);
    CHECK(border <= 1e-12 * scale);
    CHECK(inside >= 1e-4 * scale);
    // Welded by the topology, the fractal surface is closed like the mesh.
    const Mesh welded = surface_automaton_mesh(rough.surface, depth);
    CHECK(euler_characteristic(build_topology(welded)) == euler_characteristic(build_topology(m)));
  }
}

TEST_CASE("fractal surfaces: what is not built is refused", "[subdivision][limit][fractal]") {
  SurfaceAutomaton butterfly = surface_automaton(loop(tetrahedron(), 1), MeshScheme::loop);
  butterfly.scheme = MeshScheme::butterfly;
  CHECK_THROWS_WITH(fractal_surface(butterfly, {}),
                    Catch::Contains("fractal subdivision surfaces: butterfly is not built"));
}
