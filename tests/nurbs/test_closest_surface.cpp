// SPDX-License-Identifier: MIT
// Closest points on surfaces: against closed forms (spheres, tori and cylinders from revolve, the saddle
// z = x² − y², a plane) and against brute force (a dense grid, then pattern search from its best local
// minima) on random non-uniform rational surfaces.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/nurbs/construct.hpp"
#include "cifs/nurbs/measure.hpp"
#include "cifs/nurbs/surface.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

constexpr double kTurn = 2 * std::numbers::pi;

Point cs_point(double x, double y, double z) {
  return (Point(3) << x, y, z).finished();
}

/// The sphere of radius r about c: the half circle from the south pole to the north pole (two rational
/// quadratic arcs in the xz-plane) turned about the vertical axis through c. u: the profile, v: the turn.
Surface cs_sphere(double r, const Eigen::Vector3d& c) {
  const double h = std::sqrt(0.5);
  Points P(5, 3);
  P << 0, 0, -r, r, 0, -r, r, 0, 0, r, 0, r, 0, 0, r;
  P.rowwise() += c.transpose();
  const Curve half =
      make_curve(2, {0, 0, 0, 0.5, 0.5, 1, 1, 1}, P, (Eigen::VectorXd(5) << 1, h, 1, h, 1).finished());
  return revolve(half, c, Eigen::Vector3d(0, 0, 1), kTurn);
}

/// The torus of radii R > r about the z-axis: the circle about (R, 0, 0) in the xz-plane (four quarters,
/// from (R + r, 0, 0) upwards) turned about z. The inner equator is u = 1/2.
Surface cs_torus(double R, double r) {
  const double h = std::sqrt(0.5);
  Points P(9, 3);
  P << R + r, 0, 0, R + r, 0, r, R, 0, r, R - r, 0, r, R - r, 0, 0, R - r, 0, -r, R, 0, -r, R + r, 0, -r,
      R + r, 0, 0;
  const Curve circle = make_curve(2, {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}, P,
                                  (Eigen::VectorXd(9) << 1, h, 1, h, 1, h, 1, h, 1).finished());
  return revolve(circle, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), kTurn);
}

/// The cylinder of radius r about z for z ∈ [−1, 1]: the segment turned; u = (z + 1)/2.
Surface cs_cylinder(double r) {
  Points P(2, 3);
  P << r, 0, -1, r, 0, 1;
  return revolve(make_curve(1, {0, 0, 1, 1}, P), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), kTurn);
}

/// The saddle z = x² − y² over [−1, 1]² as one biquadratic Bézier patch: S(u, v) = (u, v, u² − v²).
Surface cs_saddle() {
  const double x[3] = {-1, 0, 1}, sq[3] = {1, -1, 1};  // u² in Bernstein form on [−1, 1]
  Points P(9, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) P.row(i * 3 + j) << x[i], x[j], sq[i] - sq[j];
  return make_surface({2, 2}, {Knots{-1, -1, -1, 1, 1, 1}, Knots{-1, -1, -1, 1, 1, 1}}, {3, 3}, P);
}

/// The unit square of the plane z = 0 as a bicubic patch with uneven control points along each line
/// (S(u, v) = (x(u), y(v), 0), x and y increasing cubics from 0 to 1).
Surface cs_plane() {
  const double x[4] = {0, 0.1, 0.7, 1};
  Points P(16, 3);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) P.row(i * 4 + j) << x[i], x[j], 0;
  return make_surface({3, 3}, {Knots{0, 0, 0, 0, 1, 1, 1, 1}, Knots{0, 0, 0, 0, 1, 1, 1, 1}}, {4, 4}, P);
}

/// Brute force: the smallest distance on a (g + 1)² grid of the domain, then pattern search (the best of a
/// 5 × 5 stencil, its step halved when the centre is best, kept in the domain) from the grid's best local
/// minima. Uses only `evaluate`.
double cs_brute_force(const Surface& s, const Point& q, int g = 40, int starts = 3) {
  const Domain du = domain(s, Direction::u), dv = domain(s, Direction::v);
  const auto dist = [&](double u, double v) {
    return (evaluate(s, std::clamp(u, du.start, du.end), std::clamp(v, dv.start, dv.end)) - q).norm();
  };
  const double hu = (du.end - du.start) / g, hv = (dv.end - dv.start) / g;
  std::vector<double> grid(static_cast<std::size_t>((g + 1) * (g + 1)));
  const auto at = [&](int i, int j) -> double& {
    return grid[static_cast<std::size_t>(i) * static_cast<std::size_t>(g + 1) + static_cast<std::size_t>(j)];
  };
  for (int i = 0; i <= g; ++i)
    for (int j = 0; j <= g; ++j) at(i, j) = dist(du.start + i * hu, dv.start + j * hv);
  std::vector<std::array<double, 3>> minima;  // distance, i, j
  for (int i = 0; i <= g; ++i)
    for (int j = 0; j <= g; ++j) {
      bool lowest = true;
      for (int a = std::max(0, i - 1); a <= std::min(g, i + 1); ++a)
        for (int b = std::max(0, j - 1); b <= std::min(g, j + 1); ++b)
          lowest = lowest && at(i, j) <= at(a, b);
      if (lowest) minima.push_back({at(i, j), static_cast<double>(i), static_cast<double>(j)});
    }
  std::sort(minima.begin(), minima.end());
  double best = HUGE_VAL;
  for (std::size_t k = 0; k < minima.size() && k < static_cast<std::size_t>(starts); ++k) {
    double u = du.start + minima[k][1] * hu, v = dv.start + minima[k][2] * hv, su = hu, sv = hv;
    double here = dist(u, v);
    for (int it = 0; it < 2000 && (su > 1e-16 * (du.end - du.start) || sv > 1e-16 * (dv.end - dv.start));
         ++it) {
      double bu = u, bv = v, bd = here;
      for (int a = -2; a <= 2; ++a)
        for (int b = -2; b <= 2; ++b) {
          const double cu = std::clamp(u + a * su, du.start, du.end),
                       cv = std::clamp(v + b * sv, dv.start, dv.end);
          const double d = dist(cu, cv);
          if (d < bd) {
            bd = d;
            bu = cu;
            bv = cv;
          }
        }
      if (bu == u && bv == v) {
        su /= 2;
        sv /= 2;
      }
      u = bu;
      v = bv;
      here = bd;
    }
    best = std::min(best, here);
  }
  return best;
}

/// Every reported point is the surface at its parameters, at the reported distance.
void cs_check_points(const Surface& s, const Point& q, const SurfaceClosestPoints& cp, double size) {
  REQUIRE(cp.points.rows() == static_cast<Eigen::Index>(cp.parameters.size()));
  for (std::size_t i = 0; i < cp.parameters.size(); ++i) {
    const Point x = evaluate(s, cp.parameters[i][0], cp.parameters[i][1]);
    CHECK((x - cp.points.row(static_cast<Eigen::Index>(i))).norm() <= 1e-14 * size);
    CHECK(std::abs((x - q).norm() - cp.distance) <= 1e-12 * size);
  }
}

}  // namespace

TEST_CASE("closest_point on surfaces: spheres from revolve, distance | |q − c| − r |",
          "[nurbs][measure][closest][surface]") {
  for (const double r : {1e-3, 1.0, 250.0}) {
    const Eigen::Vector3d c(0.5 * r, -2 * r, 3 * r);
    const Surface s = cs_sphere(r, c);
    INFO("radius " << r);
    {  // points outside, inside and on the sphere: one nearest point, on the ray from the centre
      for (const Eigen::Vector3d& dir :
           {Eigen::Vector3d(Eigen::Vector3d(1, 2, 2) / 3), Eigen::Vector3d(-0.6, 0, 0.8),
            Eigen::Vector3d(0, 0.28, -0.96), Eigen::Vector3d(0, 0, 1)})
        for (const double rho : {0.0001, 0.3, 1.0, 1.7, 40.0}) {
          const Point q = (c + rho * r * dir).transpose();
          const SurfaceClosestPoints cp = closest_point(s, q);
          INFO("direction " << dir.transpose() << " at " << rho << " r");
          CHECK(std::abs(cp.distance - std::abs(rho - 1) * r) <= 1e-12 * r);
          CHECK(cp.regions.empty());
          REQUIRE(cp.parameters.size() == 1);  // the pole (direction z) and the seam count once
          CHECK((cp.points.row(0).transpose() - (c + r * dir)).norm() <= 1e-9 * r);
          cs_check_points(s, q, cp, 4 * r);
        }
    }
    {  // the centre: the whole domain at distance r
      const SurfaceClosestPoints cp = closest_point(s, c.transpose());
      CHECK(std::abs(cp.distance - r) <= 1e-12 * r);
      CHECK(cp.parameters.empty());
      REQUIRE(cp.regions.size() == 1);
      CHECK(cp.regions[0] == std::array<double, 4>{0, 1, 0, 1});
    }
  }
}

TEST_CASE("closest_point on surfaces: tori and cylinders, circles of nearest points as regions",
          "[nurbs][measure][closest][surface]") {
  const Surface torus = cs_torus(3, 1);
  SECTION("the torus from its centre: the inner equator, u = 1/2, every v") {
    const SurfaceClosestPoints cp = closest_point(torus, cs_point(0, 0, 0));
    CHECK(std::abs(cp.distance - 2) <= 1e-12 * 4);
    CHECK(cp.parameters.empty());
    REQUIRE(cp.regions.size() == 1);
    CHECK(std::abs(cp.regions[0][0] - 0.5) <= 1e-12);
    CHECK(std::abs(cp.regions[0][1] - 0.5) <= 1e-12);
    CHECK(cp.regions[0][2] == 0);
    CHECK(cp.regions[0][3] == 1);
  }
  SECTION("the torus from a point of its axis: a circle at √(R² + z²) − r") {
    const SurfaceClosestPoints cp = closest_point(torus, cs_point(0, 0, 2));
    CHECK(std::abs(cp.distance - (std::sqrt(13.0) - 1)) <= 1e-12 * 4);
    CHECK(cp.parameters.empty());
    REQUIRE(cp.regions.size() == 1);
    CHECK(std::abs(cp.regions[0][0] - cp.regions[0][1]) <= 1e-12);
    CHECK(cp.regions[0][2] == 0);
    CHECK(cp.regions[0][3] == 1);
  }
  SECTION("the torus from points off its axis: √((ρ − R)² + z²) − r, one point") {
    for (const Eigen::Vector3d& x : {Eigen::Vector3d(4, 1, 0.5), Eigen::Vector3d(-1, 1.5, -0.2),
                                     Eigen::Vector3d(0.1, -2.5, 3), Eigen::Vector3d(10, -7, 1)}) {
      const SurfaceClosestPoints cp = closest_point(torus, x.transpose());
      const double rho = std::hypot(x(0), x(1));
      INFO("q " << x.transpose());
      CHECK(std::abs(cp.distance - std::abs(std::hypot(rho - 3, x(2)) - 1)) <= 1e-12 * 4);
      CHECK(cp.parameters.size() == 1);
      cs_check_points(torus, x.transpose(), cp, 4);
    }
  }
  const Surface cylinder = cs_cylinder(2);
  SECTION("the cylinder from its axis: the circle at the same height, or the nearer rim") {
    const SurfaceClosestPoints mid = closest_point(cylinder, cs_point(0, 0, 0.3));
    CHECK(std::abs(mid.distance - 2) <= 1e-12 * 3);
    REQUIRE(mid.regions.size() == 1);
    CHECK(std::abs(mid.regions[0][0] - 0.65) <= 1e-12);
    CHECK(std::abs(mid.regions[0][1] - 0.65) <= 1e-12);
    const SurfaceClosestPoints above = closest_point(cylinder, cs_point(0, 0, 3));
    CHECK(std::abs(above.distance - std::sqrt(8.0)) <= 1e-12 * 3);
    REQUIRE(above.regions.size() == 1);
    CHECK(above.regions[0] == std::array<double, 4>{1, 1, 0, 1});
  }
  SECTION("the cylinder from points off its axis") {
    const SurfaceClosestPoints cp = closest_point(cylinder, cs_point(0.3, -0.4, -0.2));
    CHECK(std::abs(cp.distance - 1.5) <= 1e-12 * 3);
    REQUIRE(cp.parameters.size() == 1);
    CHECK(std::abs(cp.parameters[0][0] - 0.4) <= 1e-12);
    CHECK((cp.points.row(0) - cs_point(1.2, -1.6, -0.2)).norm() <= 1e-12 * 3);
  }
}

TEST_CASE("closest_point on surfaces: the saddle z = x² − y² — symmetric pairs, boundary and corner minima",
          "[nurbs][measure][closest][surface]") {
  const Surface saddle = cs_saddle();
  const auto has = [](const SurfaceClosestPoints& cp, double u, double v) {
    return std::any_of(cp.parameters.begin(), cp.parameters.end(), [&](const auto& x) {
      return std::abs(x[0] - u) <= 1e-9 && std::abs(x[1] - v) <= 1e-9;
    });
  };
  SECTION("above the saddle point: two interior minima (±1/2, 0) at √(1/2)") {
    // |S − q|² = x² + y² + (x² − y² − 3/4)²: along y = 0 its minima are x² = 1/4, value 1/2.
    const SurfaceClosestPoints cp = closest_point(saddle, cs_point(0, 0, 0.75));
    CHECK(std::abs(cp.distance - std::sqrt(0.5)) <= 1e-12);
    REQUIRE(cp.parameters.size() == 2);
    CHECK(has(cp, -0.5, 0));
    CHECK(has(cp, 0.5, 0));
    cs_check_points(saddle, cs_point(0, 0, 0.75), cp, 2);
  }
  SECTION("beside it: two minima on the edge v = −1, at u = ±√(1/2)") {
    // On y = −1: x² + 4 + (x² − 1)², least at x² = 1/2 (4.75); it grows into the domain.
    const SurfaceClosestPoints cp = closest_point(saddle, cs_point(0, -3, 0));
    CHECK(std::abs(cp.distance - std::sqrt(4.75)) <= 1e-12 * 3);
    REQUIRE(cp.parameters.size() == 2);
    CHECK(has(cp, -std::sqrt(0.5), -1));
    CHECK(has(cp, std::sqrt(0.5), -1));
  }
  SECTION("off a corner: the corner (1, 1) alone, at √2") {
    const SurfaceClosestPoints cp = closest_point(saddle, cs_point(2, 2, 0));
    CHECK(std::abs(cp.distance - std::sqrt(2.0)) <= 1e-12 * 2);
    REQUIRE(cp.parameters.size() == 1);
    CHECK(cp.parameters[0] == std::array<double, 2>{1, 1});
  }
}

TEST_CASE("closest_point on surfaces: a plane — interior, edge, corner, on it",
          "[nurbs][measure][closest][surface]") {
  const Surface plane = cs_plane();
  struct Case {
    Point q, nearest;
    double distance;
  };
  for (const Case& c : {Case{cs_point(0.3, 0.4, 2), cs_point(0.3, 0.4, 0), 2},
                        Case{cs_point(0.5, -1, 1), cs_point(0.5, 0, 0), std::sqrt(2.0)},
                        Case{cs_point(-1, -1, 1), cs_point(0, 0, 0), std::sqrt(3.0)},
                        Case{cs_point(0.2, 0.7, 0), cs_point(0.2, 0.7, 0), 0}}) {
    const SurfaceClosestPoints cp = closest_point(plane, c.q);
    INFO("q " << c.q.transpose());
    CHECK(std::abs(cp.distance - c.distance) <= 1e-12 * 2);
    CHECK(cp.regions.empty());
    REQUIRE(cp.parameters.size() == 1);
    CHECK((cp.points.row(0) - c.nearest).norm() <= 1e-12);
  }
}

TEST_CASE("closest_point on surfaces: random non-uniform rational surfaces against brute force",
          "[nurbs][measure][closest][surface]") {
  Rng rng(30'2107);
  int boundary = 0;
  for (int trial = 0; trial < 24; ++trial) {
    std::array<int, 2> degree{};
    std::array<Knots, 2> knots;
    std::array<Eigen::Index, 2> count{};
    for (std::size_t d = 0; d < 2; ++d) {
      degree[d] = uniform_int(rng, 1, 3);
      count[d] = degree[d] + 1 + uniform_int(rng, 0, 3);
      // Creases too: interior knots up to the degree's multiplicity (a C⁰ line inside the domain).
      knots[d] =
          random_knots(rng, degree[d], static_cast<int>(count[d]), coin(rng), degree[d], coin(rng) ? 0 : 3);
    }
    const Eigen::Index n = count[0] * count[1];
    Points P(n, 3);
    Eigen::VectorXd w(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      P.row(i) << uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1);
      w(i) = uniform(rng, 0.5, 2);
    }
    const bool rational = trial % 4 != 0;
    const Surface s = make_surface(degree, knots, count, P, rational ? w : Eigen::VectorXd());
    for (int k = 0; k < 5; ++k) {
      const Point q = cs_point(uniform(rng, -1.5, 1.5), uniform(rng, -1.5, 1.5), uniform(rng, -1.5, 1.5));
      const SurfaceClosestPoints cp = closest_point(s, q);
      const double brute = cs_brute_force(s, q);
      INFO("trial " << trial << " degree " << degree[0] << "x" << degree[1] << " q " << q.transpose()
                    << " cifs " << cp.distance << " brute " << brute);
      CHECK(cp.distance <= brute + 1e-12);  // never farther (size: coordinates in [−1, 1])
      CHECK(cp.distance >= brute - 1e-12);
      CHECK(cp.parameters.size() + cp.regions.size() >= 1);
      cs_check_points(s, q, cp, 4);
      for (const auto& x : cp.parameters)
        boundary += x[0] == domain(s, Direction::u).start || x[0] == domain(s, Direction::u).end ||
                    x[1] == domain(s, Direction::v).start || x[1] == domain(s, Direction::v).end;
    }
  }
  CHECK(boundary >= 10);  // the edges were exercised as well as the interior
}

TEST_CASE("closest_point on surfaces: bad input", "[nurbs][measure][closest][surface]") {
  const Surface s = cs_saddle();
  CHECK_THROWS_AS(closest_point(s, Point::Zero(2)), InvalidInput);
  CHECK_THROWS_WITH(closest_point(s, Point::Zero(2)), Contains("2 coordinates, the surface 3"));
  CHECK_THROWS_WITH(closest_point(s, cs_point(0, std::nan(""), 0)), Contains("not finite"));
  CHECK_THROWS_WITH(closest_point(s, cs_point(0, HUGE_VAL, 0)), Contains("not finite"));
  for (const double tolerance : {0.0, 1e-16, 1.0, -1e-3, std::nan("")})
    CHECK_THROWS_WITH(closest_point(s, cs_point(0, 0, 1), tolerance), Contains("tolerance"));
}
