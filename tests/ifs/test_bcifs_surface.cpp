// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs_surface.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/ifs/mesh.hpp"
#include "ifs/bcifs_helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using ifs_test::max_residual;

namespace {

/// Clamped knots of degree d with n control points, interior knots at `interior`.
nurbs::Knots clamped_knots(int d, std::vector<double> interior) {
  nurbs::Knots U(static_cast<std::size_t>(d + 1), 0.0);
  const double last = interior.empty() ? 1.0 : interior.back() + 1.0;
  U.insert(U.end(), interior.begin(), interior.end());
  U.insert(U.end(), static_cast<std::size_t>(d + 1), last);
  return U;
}

nurbs::Knots uniform_knots(int d, int n) {
  nurbs::Knots U(static_cast<std::size_t>(n + d + 1));
  for (std::size_t i = 0; i < U.size(); ++i) U[i] = static_cast<double>(i);
  return U;
}

/// A wavy grid of control points, (nu·nv) by 3, row i·nv + j.
nurbs::Surface make(std::array<int, 2> degree, std::array<nurbs::Knots, 2> knots, bool rational = false) {
  const auto count = [&](std::size_t d) {
    return static_cast<Eigen::Index>(knots[d].size()) - degree[d] - 1;
  };
  const Eigen::Index nu = count(0), nv = count(1);
  Points P(nu * nv, 3);
  Eigen::VectorXd w;
  if (rational) w.resize(nu * nv);
  for (Eigen::Index i = 0; i < nu; ++i)
    for (Eigen::Index j = 0; j < nv; ++j) {
      const double x = static_cast<double>(i), y = static_cast<double>(j);
      P.row(i * nv + j) << x + 0.2 * std::sin(1.3 * y), y + 0.1 * std::cos(0.7 * x),
          std::sin(0.9 * x) * std::cos(1.1 * y);
      if (rational) w(i * nv + j) = 1.0 + 0.4 * std::sin(2.1 * x + 0.7 * y);
    }
  return nurbs::make_surface(degree, knots, {nu, nv}, P, w);
}

struct Sample {
  std::string name;
  nurbs::Surface surface;
};

std::vector<Sample> sample_surfaces() {
  std::vector<Sample> out;
  out.push_back({"uniform bicubic", make({3, 3}, {uniform_knots(3, 6), uniform_knots(3, 6)})});
  out.push_back({"uniform biquadratic", make({2, 2}, {uniform_knots(2, 5), uniform_knots(2, 5)})});
  out.push_back({"non-uniform bicubic",
                 make({3, 3}, {clamped_knots(3, {0.3, 1.1, 1.5}), clamped_knots(3, {0.7, 2.6})})});
  out.push_back(
      {"mixed degrees", make({2, 3}, {clamped_knots(2, {0.4, 1.7}), clamped_knots(3, {1, 1, 2.5})})});
  out.push_back({"rational", make({2, 2}, {clamped_knots(2, {0.5, 1.25}), uniform_knots(2, 5)}, true)});
  return out;
}

}  // namespace

TEST_CASE("surface_bcifs: the NURBS matrices are admissible", "[ifs][bcifs][surface]") {
  for (const auto& [name, s] : sample_surfaces()) {
    INFO(name);
    const auto ta = nurbs::tensor_automaton(s);
    const Bcifs sys = surface_bcifs(ta);
    CHECK(max_residual(sys) <= 1e-14);
    CHECK(sys.automaton.initial.size() == ta.product.initial.size());
    const AdmissibleSpace space = admissible_space(sys);
    CHECK(space.free.size() > 0);
    // The NURBS point is in the space: projecting its own free values gives it back.
    CHECK(max_residual(with_free_values(sys, space, free_values(sys, space))) <= 1e-14);
  }
}

TEST_CASE("surface_bcifs: free coefficients of uniform surfaces (hand counts)", "[ifs][bcifs][surface]") {
  // Uniform biquadratic: start rows {0, 1}, end rows {1, 2} cover every row, so a face's child
  // matrices are fixed by its four edges and an edge's by its two corners (as G, D by the vertex
  // operators of a curve). Corners on a knot line are fixed; the one corner cell inside the
  // patches is (M, M), M the curve's midpoint class, whose 2×2 operator has no condition in the
  // curve (2 free coefficients there), so its 4×4 product is free up to its row sums: 16 − 4 = 12.
  // (The free coefficients are named at the smallest entry of their class of equal entries, a
  // face entry: the central corner rows of the children.)
  const auto quadratic = surface_bcifs(make({2, 2}, {uniform_knots(2, 5), uniform_knots(2, 5)}));
  const AdmissibleSpace q = admissible_space(quadratic);
  CHECK(q.free.size() == 12);
  // Uniform bicubic: the curve leaves only the middle row of M's 3×3 operator free (rows 0 and 2
  // are forced to the midpoint weights); measured: 8 = one free row of 9 entries less its row sum
  // (the central point's row (1, 1) of the 9×9 corner (M, M), by analogy with the curve; the free
  // coefficients are named at the smallest entry of their class, a face entry).
  const auto cubic = surface_bcifs(make({3, 3}, {uniform_knots(3, 6), uniform_knots(3, 6)}));
  const AdmissibleSpace c = admissible_space(cubic);
  CHECK(c.free.size() == 8);
  // The entries of free corner operators (label VV) that depend on the free coefficients all lie in
  // one row, the centre row 4 = (1, 1); the other rows are fixed.
  std::set<int> moving_rows;
  for (std::size_t k = 0; k < c.unknowns.size(); ++k) {
    const Coefficient& u = c.unknowns[k];
    const auto e = transition_id(cubic.automaton, u.transition);
    if (cubic.automaton.graph[e].label == "VV" && c.K.row(static_cast<Eigen::Index>(k)).norm() > 0)
      moving_rows.insert(u.row);
  }
  CHECK(moving_rows == std::set<int>{4});
}

TEST_CASE("surface_bcifs: cost on an 8×8 non-uniform bicubic surface", "[ifs][bcifs][surface]") {
  const auto s = make({3, 3}, {clamped_knots(3, {0.3, 1.1, 1.5, 2.6, 2.9, 3.7, 4.8}),
                               clamped_knots(3, {0.6, 0.9, 2.2, 3, 3.4, 4.5, 5.1})});
  const auto ta = nurbs::tensor_automaton(s);
  auto t0 = std::chrono::steady_clock::now();
  const Bcifs sys = surface_bcifs(ta);
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t0 = std::chrono::steady_clock::now();
  const AdmissibleSpace space = admissible_space(sys);
  const double solve = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t0 = std::chrono::steady_clock::now();
  PerturbOptions po;
  po.amplitude = 0.02;
  const Perturbation p = perturb(sys, po);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(p.residual <= 1e-12);
  WARN("8x8 non-uniform bicubic: " << num_vertices(sys.automaton.graph) << " cells, " << space.unknowns.size()
                                   << " unknowns, " << space.free.size() << " free, " << space.components
                                   << " components; surface_bcifs " << build << " s, admissible_space "
                                   << solve << " s, perturb " << total << " s");
}

namespace {

/// The boundary operator `name` of `cell`.
const BoundaryOperator& boundary(const Bcifs& sys, automata::StateId cell, const std::string& name) {
  for (const auto& b : sys.boundaries)
    if (b.cell == cell && b.name == name) return b;
  throw InvalidInput("no boundary " + name);
}

Points rows(const Points& N, const std::vector<int>& r) {
  Points out(static_cast<Eigen::Index>(r.size()), N.cols());
  for (std::size_t i = 0; i < r.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = N.row(r[i]);
  return out;
}

}  // namespace

TEST_CASE("surface_bcifs: amplitude 0 gives back the NURBS mesh", "[ifs][bcifs][surface]") {
  for (const auto& [name, s] : sample_surfaces()) {
    INFO(name);
    const auto ta = nurbs::tensor_automaton(s);
    const auto nets = nurbs::initial_nets(ta, s);
    const Perturbation p = perturb(surface_bcifs(ta), {});
    const MeshOptions options{.homogeneous = s.rational};
    const Mesh reference = surface_mesh(ta, nets, 4, options);
    const Mesh mesh = quad_mesh(p.system.automaton, nets, ta.patches, 4, options);
    REQUIRE(mesh.vertices.rows() == reference.vertices.rows());
    CHECK(mesh.face_vertices == reference.face_vertices);
    const double scale = reference.vertices.cwiseAbs().maxCoeff();
    CHECK((mesh.vertices - reference.vertices).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  }
}

TEST_CASE("surface_bcifs: perturbed surfaces keep their knot lines and stay joined",
          "[ifs][bcifs][surface]") {
  const int K = 3;
  for (const auto& [name, s] : sample_surfaces()) {
    INFO(name);
    const auto ta = nurbs::tensor_automaton(s);
    const auto nets = nurbs::initial_nets(ta, s);
    const Bcifs sys = surface_bcifs(ta);
    PerturbOptions po;
    po.amplitude = 0.02;
    po.seed = 11;
    const Perturbation p = perturb(sys, po);
    CHECK(p.residual <= 1e-12);
    const MeshOptions options{.homogeneous = s.rational};
    const Mesh reference = surface_mesh(ta, nets, K, options);
    const Mesh mesh = quad_mesh(p.system.automaton, nets, ta.patches, K, options);
    REQUIRE(mesh.vertices.rows() == reference.vertices.rows());
    CHECK(mesh.face_vertices == reference.face_vertices);  // one vertex per grid node: watertight
    const int side = 1 << K;
    const auto nv_nodes = static_cast<int>(nets.size() / ta.factors[0].automaton.initial.size()) * side + 1;
    const double scale = reference.vertices.cwiseAbs().maxCoeff();
    double on_lines = 0, inside = 0;
    for (Eigen::Index k = 0; k < mesh.vertices.rows(); ++k) {
      const int I = static_cast<int>(k) / nv_nodes, J = static_cast<int>(k) % nv_nodes;
      const double moved = (mesh.vertices.row(k) - reference.vertices.row(k)).cwiseAbs().maxCoeff();
      (I % side == 0 || J % side == 0 ? on_lines : inside) =
          std::max(moved, I % side == 0 || J % side == 0 ? on_lines : inside);
    }
    CHECK(on_lines <= 1e-12 * scale);
    CHECK(inside > 1e-4);

    // Leaf nets of neighbouring children (also across patches) agree on their shared side.
    std::map<std::array<int, 2>, std::pair<automata::StateId, Points>> leaves;
    for_each_leaf(p.system.automaton, nets, K, [&](const Leaf& leaf) {
      const auto [a, b] = ta.patches[leaf.initial];
      int I = a * side, J = b * side;
      for (int l = 0; l < K; ++l) {
        I += (leaf.word[static_cast<std::size_t>(l)] / 2) << (K - 1 - l);
        J += (leaf.word[static_cast<std::size_t>(l)] % 2) << (K - 1 - l);
      }
      leaves.emplace(std::array<int, 2>{I, J}, std::make_pair(leaf.state, leaf.net));
    });
    double gap = 0;
    int shared = 0;
    for (const auto& [ij, leaf] : leaves)
      for (int dir = 0; dir < 2; ++dir) {
        const auto next = leaves.find(dir == 0 ? std::array<int, 2>{ij[0] + 1, ij[1]}
                                               : std::array<int, 2>{ij[0], ij[1] + 1});
        if (next == leaves.end()) continue;
        const std::string end = dir == 0 ? "uend" : "vend", start = dir == 0 ? "ustart" : "vstart";
        const Points A = rows(leaf.second, boundary(p.system, leaf.first, end).rows);
        const Points B = rows(next->second.second, boundary(p.system, next->second.first, start).rows);
        REQUIRE(A.rows() == B.rows());
        gap = std::max(gap, (A - B).cwiseAbs().maxCoeff());
        ++shared;
      }
    CHECK(shared == 2 * static_cast<int>(leaves.size()) - (static_cast<int>(leaves.size()) / (nv_nodes - 1)) -
                        (nv_nodes - 1));
    CHECK(gap <= 1e-12 * scale);
  }
}

TEST_CASE("surface_bcifs: bad input", "[ifs][bcifs][surface]") {
  auto ta = nurbs::tensor_automaton(make({2, 2}, {uniform_knots(2, 5), uniform_knots(2, 5)}));
  auto missing = ta;
  missing.product.initial.pop_back();
  CHECK_THROWS_WITH(surface_bcifs(missing), Catch::Contains("patches"));
  // A factor that is not a knot-doubling automaton (no windows).
  auto handmade = ta;
  for (auto& window : handmade.factors[0].windows) window.clear();
  CHECK_THROWS_WITH(surface_bcifs(handmade), Catch::Contains("not a knot-doubling state"));
  CHECK_THROWS_WITH(curve_bcifs(nurbs::KnotAutomaton{}, false), Catch::Contains("no segment"));
}

TEST_CASE("surface_bcifs: free_knot_lines frees the knot lines too", "[ifs][bcifs][surface]") {
  const auto s = make({3, 3}, {clamped_knots(3, {0.3, 1.1}), clamped_knots(3, {0.7})});
  const auto ta = nurbs::tensor_automaton(s);
  const auto nets = nurbs::initial_nets(ta, s);
  const Bcifs fixed = surface_bcifs(ta), loose = surface_bcifs(ta, {.free_knot_lines = true});
  CHECK(admissible_space(loose).free.size() > admissible_space(fixed).free.size());
  PerturbOptions po;
  po.amplitude = 0.01;
  po.seed = 3;
  const Perturbation p = perturb(loose, po);
  CHECK(p.residual <= 1e-12);
  const int K = 3, side = 1 << K;
  const Mesh reference = surface_mesh(ta, nets, K);
  const Mesh mesh = quad_mesh(p.system.automaton, nets, ta.patches, K);
  const int nv_nodes = static_cast<int>(ta.factors[1].automaton.initial.size()) * side + 1;
  double on_lines = 0;
  for (Eigen::Index k = 0; k < mesh.vertices.rows(); ++k) {
    const int I = static_cast<int>(k) / nv_nodes, J = static_cast<int>(k) % nv_nodes;
    if (I % side == 0 || J % side == 0)
      on_lines = std::max(on_lines, (mesh.vertices.row(k) - reference.vertices.row(k)).cwiseAbs().maxCoeff());
  }
  CHECK(on_lines > 1e-4);  // the knot lines move (joined: quad_mesh shares their vertices)
}

namespace {

/// A side of a constraint as the dense product F_0·F_1⋯F_k · I, boundaries as selection matrices: the
/// definition, which constraint_residuals computes by picking rows instead.
Eigen::MatrixXd dense_side(const Bcifs& sys, const std::vector<Factor>& side) {
  const automata::StateId source = side.back().kind == Factor::Kind::boundary
                                       ? sys.boundaries[static_cast<std::size_t>(side.back().boundary)].cell
                                       : side.back().transition.from;
  const int size = sys.automaton.graph[source].size;
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(size, size);
  for (auto it = side.rbegin(); it != side.rend(); ++it)
    P = ((it->kind == Factor::Kind::boundary
              ? selection_matrix(sys, it->boundary)
              : Eigen::MatrixXd(sys.automaton.graph[transition_id(sys.automaton, it->transition)].matrix)) *
         P)
            .eval();
  return P;
}

/// The largest δ over every path of `length` transitions from a reachable state, each product made from the
/// identity by full products (no branch and bound, no kept paths).
double brute_delta(const automata::Automaton& a, int length) {
  double worst = 0;
  const auto walk = [&](auto&& self, automata::StateId s, const Eigen::MatrixXd& P, int k) -> void {
    if (k == length) {
      worst = std::max(worst, delta(P));
      return;
    }
    for (auto [b, e] = out_edges(s, a.graph); b != e; ++b)
      self(self, target(*b, a.graph), (a.graph[*b].matrix * P).eval(), k + 1);
  };
  for (const automata::StateId s : reachable_states(a))
    walk(walk, s, Eigen::MatrixXd::Identity(a.graph[s].size, a.graph[s].size), 0);
  return worst;
}

}  // namespace

TEST_CASE("perturbed surfaces: residuals and δ of the shortcut products are the dense products', bit for bit",
          "[ifs][bcifs][surface]") {
  // constraint_residuals picks rows for a boundary and starts from the last factor, the contractivity scans
  // start from the first matrix instead of M·I (cifs view checks every edit of an amplitude): the same
  // doubles as the products by selection matrices and the identity.
  for (const auto& [name, s] : sample_surfaces()) {
    INFO(name);
    const auto ta = nurbs::tensor_automaton(s);
    const Bcifs sys = surface_bcifs(ta);
    if (num_vertices(sys.automaton.graph) > 200) continue;  // the non-uniform bicubic: 281 states, slow
    const AdmissibleSpace space = admissible_space(sys);
    for (const double amplitude : {0.01, 0.03}) {
      PerturbOptions po;
      po.amplitude = amplitude;
      po.seed = 5;
      po.contraction.bound = false;
      const Perturbation p = perturb(sys, space, po);
      const auto residuals = constraint_residuals(p.system);
      REQUIRE(residuals.size() == p.system.constraints.size() + p.system.free.size());
      for (std::size_t c = 0; c < p.system.constraints.size(); ++c) {
        const Eigen::MatrixXd L = dense_side(p.system, p.system.constraints[c].left),
                              R = dense_side(p.system, p.system.constraints[c].right);
        const double scale = std::max({1.0, L.cwiseAbs().maxCoeff(), R.cwiseAbs().maxCoeff()});
        CHECK(residuals[c].second == (L - R).cwiseAbs().maxCoeff() / scale);
      }
      // δ_m and m against every path's full product: lengths below m fail somewhere, m does not (where
      // the paths are few: the test stays cheap).
      const Contraction c = p.contraction;
      if (reachable_states(p.system.automaton).size() << (2 * c.m) > 2000) continue;
      CHECK(c.delta == brute_delta(p.system.automaton, c.m));
      if (c.m > 1) CHECK(brute_delta(p.system.automaton, c.m - 1) >= 1);
      CHECK(contraction(p.system.automaton).delta == c.delta);  // the bounds (A) on: the same δ
    }
  }
}
