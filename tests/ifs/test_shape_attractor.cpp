// SPDX-License-Identifier: MIT
// ifs::attractor of a curve or a surface: the shape's Cartesian points at the dyadic parameters, rational
// or not, open or closed, checked against Cox–de Boor (nurbs::evaluate), an independent route.
#include "cifs/ifs/shape_attractor.hpp"

#include <catch2/catch.hpp>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/nurbs/knots.hpp"

using namespace cifs;

namespace {

/// The dyadic parameters of depth K over the breakpoints, the last one kept when `end`.
std::vector<double> dyadic(const std::vector<double>& breaks, int depth, bool end) {
  std::vector<double> out;
  const int n = 1 << depth;
  for (std::size_t a = 0; a + 1 < breaks.size(); ++a)
    for (int j = 0; j < n; ++j) out.push_back(breaks[a] + (breaks[a + 1] - breaks[a]) * j / n);
  if (end) out.push_back(breaks.back());
  return out;
}

void check_against_evaluation(const nurbs::Curve& c, int depth) {
  const Points A = ifs::attractor(c, depth);
  const std::vector<double> us =
      dyadic(c.closed ? nurbs::defining_knots(c) : nurbs::breakpoints(c.knots, c.degree), depth, !c.closed);
  REQUIRE(A.rows() == static_cast<Eigen::Index>(us.size()));
  REQUIRE(A.cols() == nurbs::dimension(c));
  double scale = 0;
  for (Eigen::Index i = 0; i < A.rows(); ++i) scale = std::max(scale, A.row(i).cwiseAbs().maxCoeff());
  for (std::size_t i = 0; i < us.size(); ++i) {
    INFO("u = " << us[i]);
    CHECK((A.row(static_cast<Eigen::Index>(i)) - nurbs::evaluate(c, us[i])).cwiseAbs().maxCoeff() <=
          1e-12 * scale);
  }
}

}  // namespace

TEST_CASE("ifs::attractor of a curve: Cartesian points at the dyadic parameters, rational or not",
          "[ifs][attractor]") {
  Points P(6, 3);
  P << 0, 0, 1, 1, 2, 3, 3, 2, 0.5, 4, 0, 2, 5, 1, 1, 6, 3, 0.25;
  const nurbs::Knots knots{0, 0, 0, 0, 1, 3.5, 6, 6, 6, 6};
  SECTION("a non-rational 3-D curve keeps its z") {
    check_against_evaluation(nurbs::make_curve(3, knots, P), 5);
  }
  SECTION("a rational 3-D curve comes back Cartesian") {
    Eigen::VectorXd w(6);
    w << 1, 3, 0.5, 2, 1, 0.7;
    check_against_evaluation(nurbs::make_curve(3, knots, P, w), 5);
  }
  SECTION("a closed curve has no repeated end point") {
    check_against_evaluation(nurbs::make_closed_curve(3, {0, 1, 2, 4, 5, 6, 7}, P), 4);
  }
  CHECK_THROWS_WITH(ifs::attractor(nurbs::make_curve(3, knots, P), -1), "depth -1 is negative");
  CHECK_THROWS_AS(ifs::attractor(nurbs::make_curve(3, knots, P), 30, 1000), InvalidInput);
}

TEST_CASE("ifs::attractor of a rational surface: its quad mesh's vertices are Cartesian surface points",
          "[ifs][attractor]") {
  Points P(12, 3);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) P.row(i * 3 + j) << i, j, (i * j) % 3 + 0.5;
  Eigen::VectorXd w(12);
  w << 1, 2, 1, 0.5, 1, 3, 1, 1, 2, 0.25, 1, 1;
  const nurbs::Surface s =
      nurbs::make_surface({2, 2}, {nurbs::Knots{0, 0, 0, 1, 2, 2, 2}, {0, 0, 0, 1, 1, 1}}, {4, 3}, P, w);
  const int depth = 3;
  const Mesh mesh = ifs::attractor(s, depth);
  const std::vector<double> us = dyadic({0, 1, 2}, depth, true), vs = dyadic({0, 1}, depth, true);
  REQUIRE(mesh.vertices.rows() == static_cast<Eigen::Index>(us.size() * vs.size()));
  REQUIRE(mesh.vertices.cols() == 3);
  for (std::size_t a = 0; a < us.size(); ++a)
    for (std::size_t b = 0; b < vs.size(); ++b) {
      const Eigen::Index row = static_cast<Eigen::Index>(a * vs.size() + b);
      CHECK((mesh.vertices.row(row) - nurbs::evaluate(s, us[a], vs[b])).cwiseAbs().maxCoeff() <= 1e-12 * 4);
    }
  CHECK_THROWS_AS(ifs::attractor(s, 20, 1 << 20), InvalidInput);
}
