// SPDX-License-Identifier: MIT
#include "cifs/ifs/junction.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/bcifs_surface.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/subdivision/ifs.hpp"

using namespace cifs;
using namespace cifs::ifs;

namespace {

/// Windows k … k + N − 1 of an open polygon.
std::vector<Points> windows(const Points& P, int N) {
  std::vector<Points> nets;
  for (Eigen::Index k = 0; k + N <= P.rows(); ++k) nets.push_back(P.middleRows(k, N));
  return nets;
}

double largest_residual(const Bcifs& system) {
  double r = 0;
  for (const auto& [name, x] : constraint_residuals(system)) r = std::max(r, x);
  return r;
}

/// Cubic B-spline + 4-point on windows of 6 points, B's junction layer of 3 pieces.
struct CurveJunction {
  Points PA{8, 2}, PB{9, 2};
  Junction j;
  CurveJunction() {
    for (int i = 0; i < 8; ++i) PA.row(i) << i, std::sin(0.9 * i);
    for (int i = 0; i < 9; ++i) PB.row(i) << 5 + i, std::cos(1.3 * i);
    const Bcifs A = subdivision::scheme_bcifs(subdivision::b_spline(3), 6, {.pieces = 3});
    const Bcifs B = subdivision::scheme_bcifs(subdivision::four_point(), 6, {.pieces = 4, .layer = 3});
    const std::vector<Glue> glue{{2, "end", 0, "start"}};
    j = join(A, windows(PA, 6), B, windows(PB, 6), glue);
  }
};

}  // namespace

TEST_CASE("junction: a cubic B-spline and a four-point curve share their end point and tangent",
          "[junction]") {
  CurveJunction c;
  CHECK(c.j.residual <= 1e-12);
  CHECK(c.j.shared.size() == 1);  // A's vertex cell m is B's v0
  CHECK(!c.j.junction_constraints.empty());
  // Independent route: the cubic B-spline by hand. A's last piece is the cubic segment of
  // P3 … P6 (centre of the window P2 … P7): it ends at (P4 + 4P5 + P6)/6 with derivative (P6 − P4)/2.
  const Eigen::RowVector2d end = (c.PA.row(4) + 4 * c.PA.row(5) + c.PA.row(6)) / 6;
  const Eigen::RowVector2d tangent = (c.PA.row(6) - c.PA.row(4)) / 2;
  PerturbOptions po;
  po.amplitude = 0.02;
  po.seed = 3;
  for (const auto& [label, system] :
       {std::pair{"projected", c.j.system}, std::pair{"perturbed", perturb(c.j.system, po).system}}) {
    INFO(label);
    CHECK(largest_residual(system) <= 1e-12);
    const int depth = 14;
    const EdgePieces p = edge_pieces(system, c.j.nets, depth);
    const Eigen::Index per = Eigen::Index{1} << depth;
    // A's three pieces, then B's four; A's last piece ends where B's first starts.
    CHECK((p.end.row(3 * per - 1) - end).norm() <= 1e-12);
    CHECK((p.start.row(3 * per) - end).norm() <= 1e-12);
    // B's tangent at the junction from B's points at 2^-k: the direction converges to A's (the
    // angle shrinks at least like 2^-k: the shared vertex cell holds the subdominant eigenvector).
    double previous = 1;
    for (int k = 6; k <= 12; k += 2) {
      const Eigen::RowVector2d chord = p.start.row(3 * per + (Eigen::Index{1} << (depth - k))) - end;
      const double sine =
          std::abs(chord.x() * tangent.y() - chord.y() * tangent.x()) / chord.norm() / tangent.norm();
      CHECK(chord.dot(tangent) > 0);  // B leaves the junction forwards: no cusp
      CHECK(sine <= previous);
      previous = sine;
      if (k == 12) CHECK(sine <= 1e-3);
    }
    // A's side by its own attractor: the end point and the chord direction before it.
    const Eigen::RowVector2d back = p.start.row(3 * per - 1) - end;
    CHECK(std::abs(back.x() * tangent.y() - back.y() * tangent.x()) / back.norm() / tangent.norm() <= 1e-3);
  }
}

TEST_CASE("junction: B's interior keeps its scheme and A keeps its matrices", "[junction]") {
  CurveJunction c;
  const auto S = subdivision::padded_ifs_matrices(subdivision::four_point(), 6);
  const auto& g = c.j.system.automaton.graph;
  for (automata::StateId s = 0; s < num_vertices(g); ++s) {
    if (g[s].name != "B:e") continue;
    CHECK((g[transition_id(c.j.system.automaton, {s, 0})].matrix - S[0]).norm() == 0);
    CHECK((g[transition_id(c.j.system.automaton, {s, 1})].matrix - S[1]).norm() == 0);
  }
  const auto C = subdivision::padded_ifs_matrices(subdivision::b_spline(3), 6);
  CHECK((g[transition_id(c.j.system.automaton, {0, 0})].matrix - C[0]).norm() == 0);
}

TEST_CASE("junction: refusals name the cells", "[junction]") {
  const Bcifs A = subdivision::scheme_bcifs(subdivision::b_spline(3), 0, {.pieces = 1});
  const Bcifs B = subdivision::scheme_bcifs(subdivision::four_point(), 0, {.pieces = 1, .layer = 3});
  const std::vector<Glue> glue{{0, "end", 0, "start"}};
  CHECK_THROWS_WITH(join(A, {}, B, {}, glue), Catch::Contains("hold 3 and 5 points"));
  const std::vector<Glue> missing{{0, "finish", 0, "start"}};
  CHECK_THROWS_WITH(join(A, {}, B, {}, missing), Catch::Contains("no boundary \"finish\""));
  // Too thin a layer: B cannot adapt.
  const Bcifs thin = subdivision::scheme_bcifs(subdivision::four_point(), 6, {.pieces = 1, .layer = 1});
  const Bcifs wide = subdivision::scheme_bcifs(subdivision::b_spline(3), 6, {.pieces = 1});
  CHECK_THROWS_WITH(join(wide, {}, thin, {}, glue), Catch::Contains("no common solution"));
}

namespace {

/// The (N·N)-point nets of a (pieces + N − 1)² control grid, u-major, row i·N + j.
std::vector<Points> grid_windows(const Points& P, int n, int N) {
  std::vector<Points> nets;
  for (int a = 0; a + N <= n; ++a)
    for (int b = 0; b + N <= n; ++b) {
      Points W(N * N, P.cols());
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) W.row(i * N + j) = P.row((a + i) * n + b + j);
      nets.push_back(std::move(W));
    }
  return nets;
}

/// The mesh of initial entries [first, first + 4) of a system (2 × 2 patches).
Mesh patch_mesh(const Bcifs& system, const std::vector<Points>& nets, std::size_t first, int depth) {
  automata::Automaton a = system.automaton;
  a.initial.assign(system.automaton.initial.begin() + static_cast<long>(first),
                   system.automaton.initial.begin() + static_cast<long>(first + 4));
  const std::vector<Points> own(nets.begin() + static_cast<long>(first),
                                nets.begin() + static_cast<long>(first + 4));
  const std::vector<std::array<int, 2>> patches{{0, 0}, {0, 1}, {1, 0}, {1, 1}};
  return quad_mesh(a, own, patches, depth);
}

}  // namespace

TEST_CASE("junction: a bicubic and a biquadratic patch along a common boundary curve", "[junction]") {
  // A: uniform bicubic (regular Catmull–Clark) on a 5 × 5 grid; B: uniform biquadratic (regular
  // Doo–Sabin) on windows of 4 (its 3 × 3 nets padded), a layer of 2 along the junction u = 0.
  const auto curve = [](int degree, int window, int layer) {
    return subdivision::scheme_bcifs(subdivision::b_spline(degree), window, {.pieces = 2, .layer = layer});
  };
  const Bcifs A = product_bcifs(curve(3, 0, 0), curve(3, 0, 0));
  const Bcifs B = product_bcifs(curve(2, 4, 2), curve(2, 4, 0), {.free_when_either = true});
  Points PA(25, 3), PB(25, 3);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      PA.row(i * 5 + j) << i, j + 0.2 * std::sin(1.3 * i), std::sin(0.9 * i) * std::cos(1.1 * j);
      PB.row(i * 5 + j) << 2 + i, j, 0.5 * std::cos(0.8 * i + 0.3 * j);
    }
  std::vector<Glue> glue;
  for (std::size_t b = 0; b < 2; ++b) glue.push_back({2 + b, "uend", b, "ustart"});
  const Junction j = join(A, grid_windows(PA, 5, 4), B, grid_windows(PB, 5, 4), glue);
  CHECK(j.residual <= 1e-12);
  CHECK(j.free > 0);
  PerturbOptions po;
  po.amplitude = 0.05;
  po.seed = 7;
  const Bcifs fractal = perturb(j.system, po).system;
  for (const Bcifs* system : {&j.system, &fractal}) {
    CHECK(largest_residual(*system) <= 1e-12);
    const int depth = 4, n = 2 * 16 + 1;
    const Mesh a = patch_mesh(*system, j.nets, 0, depth);  // A's four patches
    const Mesh b = patch_mesh(*system, j.nets, 4, depth);  // B's
    // A's boundary u = end is B's boundary u = 0, node by node.
    for (int J = 0; J < n; ++J) CHECK((a.vertices.row((n - 1) * n + J) - b.vertices.row(J)).norm() <= 1e-12);
    // Independent route, by hand: A's boundary curve is the cubic B-spline of the points
    // Q_j = (P_2j + 4P_3j + P_4j)/6; at its knots, (Q_j + 4Q_{j+1} + Q_{j+2})/6.
    const auto Q = [&](int col) {
      return Eigen::RowVector3d((PA.row(10 + col) + 4 * PA.row(15 + col) + PA.row(20 + col)) / 6);
    };
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector3d knot = (Q(k) + 4 * Q(k + 1) + Q(k + 2)) / 6;
      CHECK((b.vertices.row(k * 16) - knot).norm() <= 1e-12);
    }
  }
}

TEST_CASE("junction: a smooth NURBS patch and a fractal patch", "[junction]") {
  // A: a rational bicubic NURBS surface; B: a bicubic B-spline surface perturbed into a fractal
  // one, its boundary u = 0 being A's boundary u = end.
  nurbs::Knots U(9);
  for (std::size_t i = 0; i < U.size(); ++i) U[i] = static_cast<double>(i);
  Points PA(25, 3), PB(25, 3);
  Eigen::VectorXd w(25);
  for (int i = 0; i < 5; ++i)
    for (int jj = 0; jj < 5; ++jj) {
      PA.row(i * 5 + jj) << i, jj, 0.3 * std::sin(1.1 * i + 0.4 * jj);
      w(i * 5 + jj) = 1 + 0.3 * std::cos(0.9 * i - 0.6 * jj);
      PB.row(i * 5 + jj) << 2 + i, jj, 0.2 * std::cos(0.7 * jj);
    }
  const nurbs::Surface SA = nurbs::make_surface({3, 3}, {U, U}, {5, 5}, PA, w);
  const nurbs::Surface SB = nurbs::make_surface({3, 3}, {U, U}, {5, 5}, PB);
  const nurbs::TensorAutomaton ta = nurbs::tensor_automaton(SA), tb = nurbs::tensor_automaton(SB);
  // B's nets in homogeneous form (weight 1) like A's.
  std::vector<Points> nets_b = nurbs::initial_nets(tb, SB);
  for (Points& N : nets_b) {
    Points H(N.rows(), 4);
    H << N, Eigen::VectorXd::Ones(N.rows());
    N = H;
  }
  std::vector<Glue> glue;
  for (std::size_t b = 0; b < 2; ++b) glue.push_back({2 + b, "uend", b, "ustart"});
  const Junction j = join(surface_bcifs(ta), nurbs::initial_nets(ta, SA),
                          surface_bcifs(tb, {.free_knot_lines = true}), nets_b, glue);
  PerturbOptions po;
  po.amplitude = 0.1;
  po.seed = 2;
  const Perturbation p = perturb(j.system, po);
  CHECK(p.residual <= 1e-12);
  const int depth = 4, n = 33;
  MeshOptions mo;
  mo.homogeneous = true;
  const auto mesh = [&](std::size_t first) {
    automata::Automaton a = p.system.automaton;
    a.initial.assign(a.initial.begin() + static_cast<long>(first),
                     a.initial.begin() + static_cast<long>(first + 4));
    const std::vector<Points> own(j.nets.begin() + static_cast<long>(first),
                                  j.nets.begin() + static_cast<long>(first + 4));
    const std::vector<std::array<int, 2>> patches{{0, 0}, {0, 1}, {1, 0}, {1, 1}};
    return quad_mesh(a, own, patches, depth, mo);
  };
  const Mesh a = mesh(0), b = mesh(4);
  // Independent route: Cox–de Boor on A's surface along its boundary u = end.
  for (int J = 0; J < n; ++J) {
    const Eigen::RowVector3d exact = nurbs::evaluate(SA, 5.0, 3.0 + 2.0 * J / (n - 1));
    CHECK((a.vertices.row((n - 1) * n + J) - exact).norm() <= 1e-12);
    CHECK((b.vertices.row(J) - exact).norm() <= 1e-12);
  }
  // B is fractal: away from the junction it left the B-spline surface.
  const nurbs::TensorAutomaton smooth = nurbs::tensor_automaton(SB);
  (void)smooth;
  double moved = 0;
  const Mesh reference = surface_mesh(tb, nurbs::initial_nets(tb, SB), depth);
  for (Eigen::Index v = n; v < b.vertices.rows(); ++v)
    moved = std::max(moved, (b.vertices.row(v) - reference.vertices.row(v)).norm());
  CHECK(moved > 1e-3);
}
