// SPDX-License-Identifier: MIT
// The BC-IFS of a triangular patch split at its midpoints (ifs::triangle_bcifs), on Bézier triangles of
// degrees 1 and 2 whose children come from the blossom (de Casteljau), another route than the
// constraints: hand counts of the free coefficients, the given matrices admissible, bad input refused.
#include "cifs/ifs/bcifs_triangle.hpp"

#include <Eigen/Dense>
#include <array>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "ifs/bcifs_helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using Catch::Contains;

namespace {

using Barycentric = Eigen::Vector3d;

/// A Bézier triangle of degree 1 (net: corners 0, 1, 2) or 2 (then the edge points 01, 12, 20) split
/// at its midpoints: each child's control points are blossom values at its corners.
TrianglePatch bezier_triangle(int degree) {
  const Barycentric c0(1, 0, 0), c1(0, 1, 0), c2(0, 0, 1), m01 = (c0 + c1) / 2, m12 = (c1 + c2) / 2,
                                                           m20 = (c2 + c0) / 2;
  const int n = degree == 1 ? 3 : 6;
  // The blossom's weights on the net at (x, y): Σ x_i y_i on corner i, x_i y_j + x_j y_i on edge ij.
  const auto blossom = [&](const Barycentric& x, const Barycentric& y) {
    Eigen::RowVectorXd w = Eigen::RowVectorXd::Zero(n);
    if (degree == 1) return Eigen::RowVectorXd((x + y).transpose() / 2);
    for (int i = 0; i < 3; ++i) w(i) = x(i) * y(i);
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      w(3 + i) = x(i) * y(j) + x(j) * y(i);
    }
    return w;
  };
  const auto child = [&](const Barycentric& a, const Barycentric& b, const Barycentric& c) {
    Eigen::MatrixXd M(n, n);
    const std::array<Barycentric, 3> corner{a, b, c};
    for (int i = 0; i < 3; ++i)
      M.row(i) = blossom(corner[static_cast<std::size_t>(i)], corner[static_cast<std::size_t>(i)]);
    if (degree == 2)
      for (int i = 0; i < 3; ++i)
        M.row(3 + i) =
            blossom(corner[static_cast<std::size_t>(i)], corner[static_cast<std::size_t>((i + 1) % 3)]);
    return M;
  };
  TrianglePatch p;
  p.children = {child(c0, m01, m20), child(m01, c1, m12), child(m20, m12, c2), child(m12, m20, m01)};
  if (degree == 1) {
    p.sides = {{{0, 1}, {1, 2}, {2, 0}}};
    p.reverse = {1, 0};
  } else {
    p.sides = {{{0, 3, 1}, {1, 4, 2}, {2, 5, 0}}};
    p.reverse = {2, 1, 0};
  }
  return p;
}

}  // namespace

TEST_CASE("triangle_bcifs: Bézier triangles, hand counts of the free coefficients", "[ifs][bcifs]") {
  // Face cells by which of their sides and corners lie on the patch's sides: 15 reachable (T012, its
  // corner children T02, T01, T12, the middle one Tc012 with its corners there, …, T inside), and the
  // edge cells Eb, Eiab, Eia, Eib, Ei.
  const Bcifs linear = triangle_bcifs(bezier_triangle(1));
  CHECK(num_vertices(linear.automaton.graph) == 20);
  CHECK(linear.automaton.graph[linear.automaton.initial.at(0).state].name == "T012");
  CHECK(ifs_test::max_residual(linear) <= 1e-15);
  // Degree 1: every child point is a corner, on two sides of its child; a side's halves keep its ends,
  // and meet at its midpoint when both ends are alike (symmetric under the reversal) — an inner edge
  // with one end on the patch's sides (Eia, read backwards Eib) may be split at any (x, 1 − x): 1.
  CHECK(admissible_space(linear).free.size() == 1);
  // Degree 2: the corners and the points on the parent's sides follow from the sides' operators; what
  // is left is, per face cell (15), the 3 edge points created inside it, 6 entries summing to 1, each
  // shared by a corner child and the middle one (15 × 3 × 5), and per inner edge cell the first half's
  // edge point (G row 1: 2) and the midpoint (G row 2): Ei and Eiab symmetric (b, 1 − 2b, b) (1 each),
  // Eia and Eib one shared midpoint (2): 3 + 3 + 2 + 2 + 2 = 12. 225 + 12 = 237.
  const Bcifs quadratic = triangle_bcifs(bezier_triangle(2));
  CHECK(ifs_test::max_residual(quadratic) <= 1e-15);
  const AdmissibleSpace space = admissible_space(quadratic);
  CHECK(space.free.size() == 237);
  // The patch's sides (Eb) are fixed: no free coefficient names them.
  for (const std::string& name : free_names(quadratic, space))
    CHECK(name.rfind("Eb/", 0) == std::string::npos);
}

TEST_CASE("triangle_bcifs: a perturbed Bézier triangle keeps its sides and its children joined",
          "[ifs][bcifs]") {
  const Bcifs quadratic = triangle_bcifs(bezier_triangle(2));
  PerturbOptions o;
  o.amplitude = 0.1;
  o.seed = 4;
  const Perturbation p = perturb(quadratic, o);
  CHECK(p.residual <= 1e-12);
  CHECK(p.contraction.m >= 1);
  // The patch's face cell: its rows on side 0 move as the fixed side operator says.
  const auto& g = p.system.automaton.graph;
  const automata::StateId root = p.system.automaton.initial.at(0).state;
  const TrianglePatch smooth = bezier_triangle(2);
  const Eigen::MatrixXd& C0 = g[transition_id(p.system.automaton, TransitionRef{root, 0})].matrix;
  for (const int r : smooth.sides[0])
    CHECK((C0.row(r) - smooth.children[0].row(r)).cwiseAbs().maxCoeff() <= 1e-14);
  // Inside, something moved.
  const automata::StateId inner = target(transition_id(p.system.automaton, TransitionRef{root, 3}), g);
  const Eigen::MatrixXd& M = g[transition_id(p.system.automaton, TransitionRef{inner, 0})].matrix;
  CHECK((M - smooth.children[0]).cwiseAbs().maxCoeff() > 1e-3);
}

TEST_CASE("triangle_bcifs: bad patches are refused, naming what is wrong", "[ifs][bcifs]") {
  TrianglePatch p = bezier_triangle(2);
  p.reverse = {0, 1, 2};  // not the other side's reading: the patch's own matrices break the constraints
  CHECK_THROWS_WITH(triangle_bcifs(p), Contains("the patch's own matrices break its constraints"));
  p = bezier_triangle(2);
  p.sides[1] = {1, 2, 4};  // side 1 read in another order than side 0 turned
  CHECK_THROWS_WITH(triangle_bcifs(p), Contains("break its constraints"));
  p = bezier_triangle(2);
  p.sides[2] = {2, 2, 0};
  CHECK_THROWS_WITH(triangle_bcifs(p), Contains("side 2 repeats a row"));
  p = bezier_triangle(2);
  p.sides[0] = {0, 3, 7};
  CHECK_THROWS_WITH(triangle_bcifs(p), Contains("side 0: row 7 is outside the net of 6"));
  p = bezier_triangle(2);
  p.children[3] = Eigen::MatrixXd::Identity(5, 5);
  CHECK_THROWS_WITH(triangle_bcifs(p), Contains("child M is 5 by 5, expected 6 by 6"));
  p = bezier_triangle(2);
  p.reverse = {2, 2, 0};
  CHECK_THROWS_WITH(triangle_bcifs(p), Contains("reverse is not an involution"));
  p = bezier_triangle(2);
  p.children[0](3, 2) = 0.25;  // C0's point on side 0 reads corner 2
  p.children[0](3, 3) -= 0.25;
  CHECK_THROWS_WITH(triangle_bcifs(p), Contains("child C0's row 3 on side 0 reads row 2"));
}
