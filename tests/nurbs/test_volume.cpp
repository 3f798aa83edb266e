// SPDX-License-Identifier: MIT
// Trivariate volumes: evaluation against the long-double triple sum of the Cox–de Boor basis, knot
// insertion in each direction against the volume before it, a trilinear volume exactly, and refusals.
#include <catch2/catch.hpp>
#include <cmath>

#include "cifs/errors.hpp"
#include "cifs/nurbs/volume.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

struct RandomVolume {
  Volume v;
  Points H;
  double scale = 1;
};

RandomVolume random_volume(Rng& rng) {
  std::array<int, 3> degree{};
  std::array<Knots, 3> knots;
  std::array<Eigen::Index, 3> count{};
  for (std::size_t d = 0; d < 3; ++d) {
    degree[d] = uniform_int(rng, 1, 4);
    count[d] = degree[d] + 1 + uniform_int(rng, 0, 3);
    knots[d] = random_knots(rng, degree[d], static_cast<int>(count[d]), coin(rng));
  }
  const Eigen::Index rows = count[0] * count[1] * count[2];
  const Points cart = random_points(rng, rows, uniform_int(rng, 1, 3));
  Eigen::VectorXd w;
  if (coin(rng)) {
    w.resize(rows);
    for (Eigen::Index i = 0; i < rows; ++i) w(i) = std::pow(2.0, uniform(rng, -1, 1));
  }
  return {make_volume(degree, knots, count, cart, w), to_rows(cart, w), cart.cwiseAbs().maxCoeff()};
}

/// Σ N_i(u) M_j(v) L_k(w) H_ijk in long double, projected when rational.
Point reference(const RandomVolume& r, double u, double v, double w) {
  const Volume& x = r.v;
  const double at[3] = {u, v, w};
  std::array<RealVec, 3> N;
  for (std::size_t d = 0; d < 3; ++d)
    N[d] = ref_basis(x.knots[d], x.degree[d], at[d], at_end(x.knots[d], x.degree[d], at[d]));
  Eigen::Matrix<Real, 1, Eigen::Dynamic> sum = Eigen::Matrix<Real, 1, Eigen::Dynamic>::Zero(r.H.cols());
  // Every term of the sum, the zero ones skipped (they add nothing; an Eigen row each under ASan).
  for (Eigen::Index i = 0; i < x.count[0]; ++i) {
    const Real ni = N[0][static_cast<std::size_t>(i)];
    if (ni == 0) continue;
    for (Eigen::Index j = 0; j < x.count[1]; ++j) {
      const Real nij = ni * N[1][static_cast<std::size_t>(j)];
      if (nij == 0) continue;
      for (Eigen::Index k = 0; k < x.count[2]; ++k)
        if (const Real n = nij * N[2][static_cast<std::size_t>(k)]; n != 0)
          sum += n * r.H.row((i * x.count[1] + j) * x.count[2] + k).cast<Real>();
    }
  }
  const Eigen::Index dim = dimension(x);
  if (!x.rational) return sum.cast<double>();
  return (sum.head(dim) / sum(dim)).cast<double>();
}

std::vector<double> probes(Rng& rng, const Volume& v, std::size_t d) {
  return probe_parameters(rng, v.knots[d], v.degree[d], 3);
}

}  // namespace

TEST_CASE("volumes evaluate to the triple sum of their basis", "[nurbs][volume]") {
  Rng rng(3101);
  for (int trial = 0; trial < 30; ++trial) {
    const RandomVolume r = random_volume(rng);
    CAPTURE(trial, r.v.degree[0], r.v.degree[1], r.v.degree[2], r.v.rational);
    for (double u : probes(rng, r.v, 0))
      for (double v : probes(rng, r.v, 1))
        for (double w : probes(rng, r.v, 2))
          CHECK(diff(evaluate(r.v, u, v, w), reference(r, u, v, w)) <= 1e-13 * r.scale);
  }
}

TEST_CASE("volume knot insertion keeps the volume in every direction", "[nurbs][volume]") {
  Rng rng(3102);
  for (int trial = 0; trial < 30; ++trial) {
    const RandomVolume r = random_volume(rng);
    const int d = trial % 3;
    const auto sd = static_cast<std::size_t>(d);
    const Domain dom = domain(r.v.knots[sd], r.v.degree[sd]);
    const double t = uniform(rng, dom.start, dom.end);
    const int times = uniform_int(rng, 1, r.v.degree[sd]);
    CAPTURE(trial, d, t, times);
    const Volume x = insert_knot(r.v, d, t, times);
    CHECK(x.count[sd] == r.v.count[sd] + times);
    CHECK(multiplicity(x.knots[sd], t) == times);
    for (std::size_t o = 0; o < 3; ++o)
      if (o != sd) CHECK(x.count[o] == r.v.count[o]);
    for (double u : probes(rng, r.v, 0))
      for (double v : probes(rng, r.v, 1))
        for (double w : probes(rng, r.v, 2))
          CHECK(diff(evaluate(x, u, v, w), reference(r, u, v, w)) <= 1e-13 * r.scale);
  }
}

TEST_CASE("a trilinear volume is exact at dyadic parameters", "[nurbs][volume]") {
  // Corners (i, j, k) ↦ (i + 2j, 3k − j, i·j·k): the trilinear interpolant, by hand.
  Points corners(8, 3);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) corners.row((i * 2 + j) * 2 + k) << i + 2 * j, 3 * k - j, i * j * k;
  const Volume cube =
      make_volume({1, 1, 1}, {Knots{0, 0, 1, 1}, Knots{0, 0, 1, 1}, Knots{0, 0, 1, 1}}, {2, 2, 2}, corners);
  for (double u : {0.0, 0.25, 0.5, 1.0})
    for (double v : {0.0, 0.125, 0.75})
      for (double w : {0.0, 0.5, 1.0}) {
        Point expected(3);
        expected << u + 2 * v, 3 * w - v, u * v * w;
        CHECK(evaluate(cube, u, v, w) == expected);
        CHECK(evaluate(insert_knot(cube, 2, 0.5), u, v, w) == expected);
      }
}

TEST_CASE("volumes refuse bad input in one line", "[nurbs][volume]") {
  const Knots t{0, 0, 1, 1};
  const Points corners = Points::Zero(8, 3);
  CHECK_THROWS_WITH(make_volume({1, 1, 1}, {t, t, t}, {2, 2, 3}, corners),
                    Contains("points: 8 control points do not form a 2 by 2 by 3 net"));
  CHECK_THROWS_WITH(make_volume({1, 1, 2}, {t, t, t}, {2, 2, 2}, corners), Contains("knots[2]"));
  Eigen::VectorXd w = Eigen::VectorXd::Ones(8);
  w(5) = 0;
  CHECK_THROWS_WITH(make_volume({1, 1, 1}, {t, t, t}, {2, 2, 2}, corners, w),
                    Contains("weights[5]: weight 0"));
  const Volume cube = make_volume({1, 1, 1}, {t, t, t}, {2, 2, 2}, corners);
  CHECK_THROWS_WITH(evaluate(cube, 0.5, 1.5, 0), Contains("parameter v = 1.5 is outside the domain [0, 1]"));
  CHECK_THROWS_WITH(insert_knot(cube, 3, 0.5), Contains("direction 3 is not u (0), v (1) or w (2)"));
  CHECK_THROWS_WITH(insert_knot(cube, 1, 2.0), Contains("direction v: "));
}
