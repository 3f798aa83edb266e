// SPDX-License-Identifier: MIT
// Tensor-product surfaces: evaluation against the double sum, grids, partial derivatives, normals,
// insertion in u and v, exact rational quadrics, validation.
#include "cifs/nurbs/surface.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "cifs/errors.hpp"
#include "cifs/nurbs/refine.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using Catch::Matchers::Contains;

namespace {

/// Parameters of one direction: ends, knots, one ulp around them, random values (at most `count`
/// of the knot-related ones, to keep grids small).
std::vector<double> direction_probes(Rng& rng, const RandomSurface& r, int dir, int count) {
  const auto& t = r.knots[static_cast<std::size_t>(dir)];
  auto us = probe_parameters(rng, t, r.degree[static_cast<std::size_t>(dir)], count);
  std::shuffle(us.begin() + 2, us.end(), rng);  // keep both ends
  if (static_cast<int>(us.size()) > 2 * count) us.resize(static_cast<std::size_t>(2 * count));
  return us;
}

/// Size of the terms of the partial S^{(k,l)} at (u, v): Σ|N^(k)_i M^(l)_j|·|H_ij| (over w(u,v) and
/// with the Leibniz terms when rational), the scale of a relative tolerance.
std::vector<double> surface_magnitudes(const RandomSurface& r, double u, double v, int order) {
  const int w = order + 1;
  const Eigen::Index dim = r.H.cols() - (r.rational ? 1 : 0);
  const auto& tu = r.knots[0];
  const auto& tv = r.knots[1];
  std::vector<double> a(static_cast<std::size_t>(w * w)), om(a.size()), M(a.size());
  double weight = 0;
  for (int k = 0; k <= order; ++k)
    for (int l = 0; k + l <= order; ++l) {
      const RealVec N = ref_basis(tu, r.degree[0], u, at_end(tu, r.degree[0], u), k);
      const RealVec B = ref_basis(tv, r.degree[1], v, at_end(tv, r.degree[1], v), l);
      double ak = 0, ok = 0;
      for (Eigen::Index i = 0; i < r.count[0]; ++i)
        for (Eigen::Index j = 0; j < r.count[1]; ++j) {
          const double nb =
              static_cast<double>(N[static_cast<std::size_t>(i)] * B[static_cast<std::size_t>(j)]);
          const auto row = r.H.row(i * r.count[1] + j);
          ak += std::abs(nb) * row.head(dim).cwiseAbs().maxCoeff();
          if (r.rational) ok += std::abs(nb) * row(dim);
          if (r.rational && k == 0 && l == 0) weight += nb * row(dim);
        }
      a[static_cast<std::size_t>(k * w + l)] = ak;
      om[static_cast<std::size_t>(k * w + l)] = ok;
    }
  for (int k = 0; k <= order; ++k)
    for (int l = 0; k + l <= order; ++l) {
      double m = a[static_cast<std::size_t>(k * w + l)];
      if (r.rational) {
        for (int i = 0; i <= k; ++i)
          for (int j = 0; j <= l; ++j)
            if (i + j > 0)
              m += binomial(k, i) * binomial(l, j) * om[static_cast<std::size_t>(i * w + j)] *
                   M[static_cast<std::size_t>((k - i) * w + l - j)];
        m /= weight;
      }
      M[static_cast<std::size_t>(k * w + l)] = m;
    }
  return M;
}

/// The 9-point unit circle in the xy plane (rows) and its weights and knots.
struct Circle {
  Points P;
  Eigen::VectorXd w;
  Knots t{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
};

Circle circle() {
  const double s = std::sqrt(0.5);
  Circle c;
  c.P.resize(9, 2);
  c.P << 1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0;
  c.w.resize(9);
  c.w << 1, s, 1, s, 1, s, 1, s, 1;
  return c;
}

/// Unit sphere: the circle (u) swept along the half circle x = cos, z = sin from the south pole (v).
Surface unit_sphere() {
  const double s = std::sqrt(0.5);
  const Circle c = circle();
  Points prof(5, 2);  // (radius, z)
  prof << 0, -1, 1, -1, 1, 0, 1, 1, 0, 1;
  const Eigen::Vector<double, 5> pw(1, s, 1, s, 1);
  Points P(9 * 5, 3);
  Eigen::VectorXd w(9 * 5);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 5; ++j) {
      P.row(i * 5 + j) << prof(j, 0) * c.P(i, 0), prof(j, 0) * c.P(i, 1), prof(j, 1);
      w(i * 5 + j) = c.w(i) * pw(j);
    }
  return make_surface({2, 2}, {c.t, Knots{0, 0, 0, 0.5, 0.5, 1, 1, 1}}, {9, 5}, P, w);
}

/// Cylinder of radius 1 and height 2 around the z axis.
Surface unit_cylinder() {
  const Circle c = circle();
  Points P(9 * 2, 3);
  Eigen::VectorXd w(9 * 2);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 2; ++j) {
      P.row(i * 2 + j) << c.P(i, 0), c.P(i, 1), 2.0 * j;
      w(i * 2 + j) = c.w(i);
    }
  return make_surface({2, 1}, {c.t, Knots{0, 0, 1, 1}}, {9, 2}, P, w);
}

}  // namespace

TEST_CASE("surfaces store their data; evaluation equals the double sum of the definition",
          "[nurbs][surface]") {
  for (int seed = 0; seed < 150; ++seed) {
    Rng rng(seed);
    const RandomSurface r = random_surface(rng);
    INFO("seed " << seed << ": " << r.what);
    const Surface& s = r.s;
    CHECK(s.P == r.H);
    CHECK(s.count == r.count);
    CHECK(dimension(s) == r.cart.cols());
    CHECK(diff(cartesian_points(s), r.cart) <= 4 * kEps * r.scale);
    CHECK_NOTHROW(validate(s));
    const auto us = direction_probes(rng, r, 0, 12), vs = direction_probes(rng, r, 1, 12);
    double worst = 0;
    for (double u : us)
      for (double v : vs) {
        const Point ref = ref_surface_derivatives(r, u, v, 0).row(0);
        worst = std::max(worst, diff(evaluate(s, u, v), ref));
      }
    CHECK(worst / (1e-12 * r.scale) <= 1.0);
  }
}

TEST_CASE("evaluate_grid equals pointwise evaluation to the last bit, in any parameter order",
          "[nurbs][surface]") {
  for (int seed = 0; seed < 150; ++seed) {
    Rng rng(1000 + seed);
    const RandomSurface r = random_surface(rng);
    INFO("seed " << seed << ": " << r.what);
    auto us = direction_probes(rng, r, 0, 10), vs = direction_probes(rng, r, 1, 10);
    if (coin(rng)) {
      std::sort(us.begin(), us.end());
      std::sort(vs.begin(), vs.end());
    }
    const Points G = evaluate_grid(r.s, us, vs);
    REQUIRE(G.rows() == static_cast<Eigen::Index>(us.size() * vs.size()));
    REQUIRE(G.cols() == r.cart.cols());
    double worst = 0;
    for (std::size_t a = 0; a < us.size(); ++a)
      for (std::size_t b = 0; b < vs.size(); ++b)
        worst = std::max(
            worst, diff(G.row(static_cast<Eigen::Index>(a * vs.size() + b)), evaluate(r.s, us[a], vs[b])));
    // Both sum the u direction first in the same order, for every column count (fixed 2..4, generic).
    CHECK(worst == 0.0);
    CHECK(evaluate_grid(r.s, std::vector<double>{}, vs).rows() == 0);
  }
}

TEST_CASE("evaluate_grid into an output: pointwise evaluation to the last bit, whatever `out` held",
          "[nurbs][surface]") {
  Points out;  // reused across seeds: every size, column count and previous content in turn
  for (int seed = 0; seed < 60; ++seed) {
    Rng rng(3000 + seed);
    const RandomSurface r = random_surface(rng);
    INFO("seed " << seed << ": " << r.what << ", out held " << out.rows() << " by " << out.cols());
    const auto us = direction_probes(rng, r, 0, 1 + seed % 7), vs = direction_probes(rng, r, 1, 1 + seed % 5);
    evaluate_grid(r.s, us, vs, out);
    REQUIRE(out.rows() == static_cast<Eigen::Index>(us.size() * vs.size()));
    REQUIRE(out.cols() == r.cart.cols());
    double worst = 0;
    for (std::size_t a = 0; a < us.size(); ++a)
      for (std::size_t b = 0; b < vs.size(); ++b)
        worst = std::max(
            worst, diff(out.row(static_cast<Eigen::Index>(a * vs.size() + b)), evaluate(r.s, us[a], vs[b])));
    CHECK(worst == 0.0);
    CHECK(out == evaluate_grid(r.s, us, vs));
    // Same size again, over other values: the storage is kept and every coefficient rewritten.
    const double* storage = out.data();
    out.setConstant(std::numeric_limits<double>::quiet_NaN());
    evaluate_grid(r.s, us, vs, out);
    CHECK(out.data() == storage);
    CHECK(out == evaluate_grid(r.s, us, vs));
  }
}

TEST_CASE("evaluate_grid into a large output of the same size (streaming stores): pointwise bits",
          "[nurbs][surface]") {
  // 400 by 400 points of 2 to 4 coordinates: 2.6 MB or more, above the streaming threshold (2 MiB).
  for (int seed = 0; seed < 4; ++seed) {
    Rng rng(5000 + seed);
    RandomSurface r = random_surface(rng);
    while (r.s.rational) r = random_surface(rng);  // rational grids go through a cached row
    INFO("seed " << seed << ": " << r.what);
    auto us = direction_probes(rng, r, 0, 400), vs = direction_probes(rng, r, 1, 400);
    if (seed % 2 == 0) {
      std::sort(us.begin(), us.end());
      std::sort(vs.begin(), vs.end());
    }
    Points out = evaluate_grid(r.s, us, vs);
    const double* storage = out.data();
    out.setConstant(std::numeric_limits<double>::quiet_NaN());
    evaluate_grid(r.s, us, vs, out);
    REQUIRE(out.data() == storage);
    REQUIRE(out.cols() == r.cart.cols());
    double worst = 0;
    for (std::size_t a = 0; a < us.size(); a += 7)
      for (std::size_t b = 0; b < vs.size(); ++b)
        worst = std::max(
            worst, diff(out.row(static_cast<Eigen::Index>(a * vs.size() + b)), evaluate(r.s, us[a], vs[b])));
    CHECK(worst == 0.0);
    CHECK(out.allFinite());
  }
}

TEST_CASE("surface partial derivatives: definition, Leibniz' rule, finite differences", "[nurbs][surface]") {
  for (int seed = 0; seed < 150; ++seed) {
    Rng rng(2000 + seed);
    const RandomSurface r = random_surface(rng);
    INFO("seed " << seed << ": " << r.what);
    const int order = 3, w = order + 1;
    double worst = 0, zeros = 0;
    const auto us = direction_probes(rng, r, 0, 4), vs = direction_probes(rng, r, 1, 4);
    for (double u : us)
      for (double v : vs) {
        const Points D = derivatives(r.s, u, v, order);
        REQUIRE(D.rows() == w * w);
        const Points R = ref_surface_derivatives(r, u, v, order);
        const auto M = surface_magnitudes(r, u, v, order);
        for (int k = 0; k <= order; ++k)
          for (int l = 0; l <= order; ++l) {
            const auto row = k * w + l;
            if (k + l > order)
              zeros = std::max(zeros, D.row(row).cwiseAbs().maxCoeff());
            else
              worst =
                  std::max(worst, diff(D.row(row), R.row(row)) / (M[static_cast<std::size_t>(row)] + 1e-300));
          }
      }
    CHECK(worst / 1e-11 <= 1.0);
    CHECK(zeros == 0.0);
    // Finite differences in the middle of a span in each direction.
    double worst_fd = 0;
    for (int rep = 0; rep < 4; ++rep) {
      double uv[2], h[2];
      for (int dir = 0; dir < 2; ++dir) {
        const auto& t = r.knots[static_cast<std::size_t>(dir)];
        const int d = r.degree[static_cast<std::size_t>(dir)];
        int k = 0;
        do k = uniform_int(rng, d, static_cast<int>(r.count[static_cast<std::size_t>(dir)]) - 1);
        while (!(t[static_cast<std::size_t>(k)] < t[static_cast<std::size_t>(k + 1)]));
        const double a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>(k + 1)];
        uv[dir] = a + uniform(rng, 0.3, 0.7) * (b - a);
        h[dir] = 1e-3 * (b - a);
      }
      const Points D = derivatives(r.s, uv[0], uv[1], 2);
      const auto M = surface_magnitudes(r, uv[0], uv[1], 2);
      for (int k = 0; k <= 2; ++k)
        for (int l = 0; k + l <= 2; ++l) {
          if (k + l == 0) continue;
          // Differentiate the partial one order lower in u (if k > 0) or in v.
          const Points fd =
              k > 0
                  ? central_difference(
                        [&](double x) -> Points {
                          return derivatives(r.s, x, uv[1], 2).row((k - 1) * 3 + l);
                        },
                        uv[0], h[0])
                  : central_difference(
                        [&](double y) -> Points { return derivatives(r.s, uv[0], y, 2).row(k * 3 + l - 1); },
                        uv[1], h[1]);
          worst_fd = std::max(worst_fd, diff(fd, D.row(k * 3 + l)) / M[static_cast<std::size_t>(k * 3 + l)]);
        }
    }
    CHECK(worst_fd / 1e-6 <= 1.0);
  }
}

TEST_CASE("normals are unit and orthogonal to both partials", "[nurbs][surface]") {
  int tested = 0;
  for (int seed = 0; seed < 2000 && tested < 100; ++seed) {
    Rng rng(3000 + seed);
    RandomSurface r = random_surface(rng);
    if (r.cart.cols() != 3) continue;
    ++tested;
    INFO("seed " << seed << ": " << r.what);
    double unit = 0, ortho = 0, ref = 0;
    for (int rep = 0; rep < 20; ++rep) {
      const double u = uniform(rng, r.knots[0][static_cast<std::size_t>(r.degree[0])],
                               r.knots[0][static_cast<std::size_t>(r.count[0])]);
      const double v = uniform(rng, r.knots[1][static_cast<std::size_t>(r.degree[1])],
                               r.knots[1][static_cast<std::size_t>(r.count[1])]);
      const Eigen::Vector3d n = normal(r.s, u, v);
      const Points R = ref_surface_derivatives(r, u, v, 1);  // rows (0,0), (0,1), (1,0), (1,1)
      const Eigen::Vector3d Su = R.row(2).transpose(), Sv = R.row(1).transpose();
      const Eigen::Vector3d m = Su.cross(Sv);
      unit = std::max(unit, std::abs(n.norm() - 1));
      ortho = std::max(ortho, std::max(std::abs(n.dot(Su)) / Su.norm(), std::abs(n.dot(Sv)) / Sv.norm()));
      // Against the reference normal, relative to how well the cross product is conditioned.
      ref = std::max(ref, (n - m.normalized()).norm() * m.norm() / (Su.norm() * Sv.norm()));
    }
    CHECK(unit <= 4 * kEps);
    CHECK(ortho / 1e-11 <= 1.0);
    CHECK(ref / 1e-11 <= 1.0);
  }
  CHECK(tested == 100);
}

TEST_CASE("knot insertion and refinement in u and in v keep the surface", "[nurbs][surface]") {
  for (int seed = 0; seed < 150; ++seed) {
    Rng rng(4000 + seed);
    const RandomSurface r = random_surface(rng);
    INFO("seed " << seed << ": " << r.what);
    for (int dir = 0; dir < 2; ++dir) {
      const auto D = static_cast<Direction>(dir);
      const auto& t = r.knots[static_cast<std::size_t>(dir)];
      const int d = r.degree[static_cast<std::size_t>(dir)];
      const double lo = t[static_cast<std::size_t>(d)],
                   hi = t[static_cast<std::size_t>(r.count[static_cast<std::size_t>(dir)])];
      // Random knots, repeats and existing knots, multiplicities ≤ d.
      std::vector<double> X;
      for (int i = 0; i < 6; ++i) {
        const double x =
            coin(rng) ? uniform(rng, lo, hi)
                      : t[static_cast<std::size_t>(uniform_int(rng, d, static_cast<int>(t.size()) - d - 1))];
        const auto have = std::count(t.begin(), t.end(), x) + std::count(X.begin(), X.end(), x);
        if (have < d) X.push_back(x);
      }
      INFO("direction " << dir << ", " << X.size() << " knots");
      const Surface s2 = X.size() == 1 ? insert_knot(r.s, D, X[0]) : refine(r.s, D, X);
      CHECK_NOTHROW(validate(s2));
      Knots merged = t;
      merged.insert(merged.end(), X.begin(), X.end());
      std::sort(merged.begin(), merged.end());
      CHECK(s2.knots[static_cast<std::size_t>(dir)] == merged);
      CHECK(s2.knots[static_cast<std::size_t>(1 - dir)] == r.knots[static_cast<std::size_t>(1 - dir)]);
      CHECK(s2.count[static_cast<std::size_t>(dir)] ==
            r.count[static_cast<std::size_t>(dir)] + static_cast<Eigen::Index>(X.size()));
      // Each line of the net along `dir` is refined as a curve: Boehm's formula on the test's data.
      const Eigen::Index other = r.count[static_cast<std::size_t>(1 - dir)];
      double e_points = 0;
      for (Eigen::Index line = 0; line < other; ++line) {
        const Eigen::Index n = r.count[static_cast<std::size_t>(dir)];
        Points L(n, r.H.cols());
        for (Eigen::Index i = 0; i < n; ++i)
          L.row(i) = dir == 0 ? r.H.row(i * other + line) : r.H.row(line * n + i);
        RefSpline sp{d, t, L};
        for (double x : X) sp = ref_boehm(sp, x);
        const Eigen::Index n2 = n + static_cast<Eigen::Index>(X.size());
        for (Eigen::Index i = 0; i < n2; ++i) {
          const Point got = dir == 0 ? s2.P.row(i * other + line) : s2.P.row(line * n2 + i);
          e_points = std::max(e_points, diff(got, sp.P.row(i)));
        }
      }
      CHECK(e_points / (1e-12 * max_abs(r.H)) <= 1.0);
      double moved = 0;
      for (double u : direction_probes(rng, r, 0, 6))
        for (double v : direction_probes(rng, r, 1, 6))
          moved = std::max(moved, diff(evaluate(s2, u, v), ref_surface_derivatives(r, u, v, 0).row(0)));
      CHECK(moved / (1e-12 * r.scale) <= 1.0);
    }
    // Midpoints in both directions.
    const Surface m = refine_midpoints(r.s);
    CHECK_NOTHROW(validate(m));
    double moved = 0;
    for (double u : direction_probes(rng, r, 0, 6))
      for (double v : direction_probes(rng, r, 1, 6))
        moved = std::max(moved, diff(evaluate(m, u, v), ref_surface_derivatives(r, u, v, 0).row(0)));
    CHECK(moved / (1e-12 * r.scale) <= 1.0);
    for (int dir = 0; dir < 2; ++dir) {
      const auto& t = r.knots[static_cast<std::size_t>(dir)];
      std::vector<double> b;
      for (std::size_t i = static_cast<std::size_t>(r.degree[static_cast<std::size_t>(dir)]);
           i <= static_cast<std::size_t>(r.count[static_cast<std::size_t>(dir)]); ++i)
        if (b.empty() || b.back() != t[i]) b.push_back(t[i]);
      CHECK(static_cast<std::size_t>(m.count[static_cast<std::size_t>(dir)] -
                                     r.count[static_cast<std::size_t>(dir)]) == b.size() - 1);
    }
  }
}

TEST_CASE("direction curves hold whole lines of the net", "[nurbs][surface]") {
  Rng rng(5000);
  for (int rep = 0; rep < 20; ++rep) {
    const RandomSurface r = random_surface(rng);
    const Eigen::Index nu = r.count[0], nv = r.count[1], cols = r.H.cols();
    const Curve cu = direction_curve(r.s, Direction::u), cv = direction_curve(r.s, Direction::v);
    CHECK(cu.degree == r.degree[0]);
    CHECK(cv.degree == r.degree[1]);
    CHECK(cu.knots == r.knots[0]);
    CHECK(cv.knots == r.knots[1]);
    REQUIRE(cu.P.rows() == nu);
    REQUIRE(cv.P.rows() == nv);
    bool ok = true;
    for (Eigen::Index i = 0; i < nu; ++i)
      for (Eigen::Index j = 0; j < nv; ++j) {
        ok = ok && cu.P.block(i, j * cols, 1, cols) == r.H.row(i * nv + j);
        ok = ok && cv.P.block(j, i * cols, 1, cols) == r.H.row(i * nv + j);
      }
    CHECK(ok);
  }
}

TEST_CASE("the rational sphere and cylinder have exact radius and radial normals", "[nurbs][surface]") {
  const Surface sphere = unit_sphere(), cylinder = unit_cylinder();
  std::vector<double> us, vs;
  for (int i = 0; i <= 60; ++i) us.push_back(i / 60.0), vs.push_back(i / 60.0);
  double radius = 0, grid_radius = 0, cyl = 0, radial = 0;
  const Points G = evaluate_grid(sphere, us, vs);
  for (std::size_t a = 0; a < us.size(); ++a)
    for (std::size_t b = 0; b < vs.size(); ++b) {
      const Point p = evaluate(sphere, us[a], vs[b]);
      radius = std::max(radius, std::abs(p.norm() - 1));
      grid_radius =
          std::max(grid_radius, std::abs(G.row(static_cast<Eigen::Index>(a * vs.size() + b)).norm() - 1));
      const Point q = evaluate(cylinder, us[a], vs[b]);
      cyl = std::max(cyl, std::abs(q.head(2).norm() - 1));
      if (vs[b] > 0 && vs[b] < 1) {  // away from the poles
        const Eigen::Vector3d n = normal(sphere, us[a], vs[b]);
        radial = std::max(radial, 1 - std::abs(n.dot(p.transpose().normalized())));
      }
      const Eigen::Vector3d m = normal(cylinder, us[a], vs[b]);
      radial = std::max(radial, 1 - std::abs(m.dot(Eigen::Vector3d(q(0), q(1), 0).normalized())));
    }
  CHECK(radius <= 4 * kEps);
  CHECK(grid_radius <= 4 * kEps);
  CHECK(cyl <= 4 * kEps);
  CHECK(radial <= 1e-13);
  // Tangent planes: S·S_u = S·S_v = 0 on the sphere.
  double tangent = 0;
  for (double u : us)
    for (double v : vs) {
      const Points D = derivatives(sphere, u, v, 1);
      const Point p = D.row(0);
      if (D.row(2).norm() > 0) tangent = std::max(tangent, std::abs(p.dot(D.row(2))) / D.row(2).norm());
      tangent = std::max(tangent, std::abs(p.dot(D.row(1))) / D.row(1).norm());
    }
  CHECK(tangent <= 1e-14);
  // The poles: S_u vanishes, so the normal is undefined.
  CHECK_THROWS_WITH(normal(sphere, 0.3, 0.0), Contains("undefined"));
  CHECK_THROWS_WITH(normal(sphere, 0.3, 1.0), Contains("undefined"));
  // Refinement keeps the sphere exact.
  const Surface fine = refine_midpoints(insert_knot(sphere, Direction::v, 0.3, 2));
  double fine_radius = 0;
  for (double u : us)
    for (double v : vs) fine_radius = std::max(fine_radius, std::abs(evaluate(fine, u, v).norm() - 1));
  CHECK(fine_radius <= 8 * kEps);
}

TEST_CASE("surface validation names the problem and its place", "[nurbs][surface]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Knots tu{0, 0, 1, 1}, tv{0, 0, 0, 1, 1, 1};
  const Points P = Points::Random(6, 3);
  CHECK_NOTHROW(make_surface({1, 2}, {tu, tv}, {2, 3}, P));
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, tv}, {3, 3}, P), Contains("points") && Contains("3 by 3"));
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, tv}, {0, 3}, Points(0, 3)), Contains("points"));
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, Knots{0, 0, 0, 1, 1}}, {2, 3}, P), Contains("knots[1]"));
  CHECK_THROWS_WITH(make_surface({1, 2}, {Knots{0, 0, 1, nan}, tv}, {2, 3}, P), Contains("knots[0][3]"));
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, Knots{0, 0, 0, 1, 0.5, 1}}, {2, 3}, P),
                    Contains("knots[1][4]"));
  CHECK_THROWS_WITH(make_surface({1, 0}, {tu, tv}, {2, 3}, P), Contains("[1]") && Contains("degree 0"));
  CHECK_THROWS_WITH(make_surface({0, 2}, {tu, tv}, {2, 3}, P), Contains("[0]") && Contains("degree 0"));
  Eigen::VectorXd w = Eigen::VectorXd::Ones(6);
  w(4) = 0;  // point (1, 1)
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, tv}, {2, 3}, P, w), Contains("weights[1][1]"));
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, tv}, {2, 3}, P, Eigen::VectorXd::Ones(5)), Contains("weights"));
  Points Q = P;
  Q(5, 2) = nan;  // point (1, 2)
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, tv}, {2, 3}, Q), Contains("points[1][2]"));
  CHECK_THROWS_WITH(make_surface({1, 2}, {tu, tv}, {2, 3}, Points(6, 0)), Contains("no coordinates"));
}

TEST_CASE("surface evaluation, derivatives, normals and insertion reject bad arguments", "[nurbs][surface]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Surface s =
      make_surface({1, 2}, {Knots{0, 0, 1, 1}, Knots{0, 0, 0, 2, 2, 2}}, {2, 3}, Points::Random(6, 3));
  CHECK_NOTHROW(evaluate(s, 1.0, 2.0));
  CHECK_THROWS_WITH(evaluate(s, -0.1, 1.0), Contains("parameter u"));
  CHECK_THROWS_WITH(evaluate(s, 0.5, 2.5), Contains("parameter v"));
  CHECK_THROWS_WITH(evaluate(s, nan, 1.0), Contains("parameter u"));
  CHECK_THROWS_WITH(evaluate(s, 0.5, nan), Contains("parameter v"));
  CHECK_THROWS_WITH(evaluate_grid(s, std::vector<double>{0.5, 1.5}, std::vector<double>{1.0}),
                    Contains("parameter u"));
  CHECK_THROWS_WITH(evaluate_grid(s, std::vector<double>{0.5}, std::vector<double>{1.0, -1.0}),
                    Contains("parameter v"));
  CHECK_THROWS_WITH(derivatives(s, 0.5, 1.0, -1), Contains("order -1 is outside 0 … 64"));
  // (order + 1)² rows would overflow an int: refused before any allocation.
  CHECK_THROWS_WITH(derivatives(s, 0.5, 1.0, 1000000), Contains("order 1000000 is outside 0 … 64"));
  CHECK_THROWS_WITH(derivatives(s, 0.5, 3.0, 1), Contains("parameter v"));
  CHECK_THROWS_WITH(normal(s, 2.0, 1.0), Contains("parameter u"));
  const Surface flat =
      make_surface({1, 1}, {Knots{0, 0, 1, 1}, Knots{0, 0, 1, 1}}, {2, 2}, Points::Random(4, 2));
  CHECK_THROWS_WITH(normal(flat, 0.5, 0.5), Contains("2-D"));
  CHECK_THROWS_WITH(insert_knot(s, Direction::u, 1.5), Contains("direction u") && Contains("outside"));
  CHECK_THROWS_WITH(insert_knot(s, Direction::v, nan), Contains("direction v") && Contains("not finite"));
  CHECK_THROWS_WITH(insert_knot(s, Direction::v, 1.0, 3),
                    Contains("direction v") && Contains("multiplicity"));
  CHECK_THROWS_WITH(insert_knot(s, Direction::u, 0.5, 0), Contains("times"));
  CHECK_THROWS_WITH(refine(s, Direction::u, std::vector<double>{0.5, 2.0}), Contains("direction u"));
}
