// SPDX-License-Identifier: MIT
// The fractal inverse problem: a fitted fractal curve is checked against routes that do not share its
// evaluation — data made by edge_pieces of a perturbed system (recovered to round-off), de Boor on
// smooth data, the contraction proof, box counting.
#include "cifs/ifs/fractal_fit.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "cifs/errors.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/random.hpp"

using namespace cifs;
using namespace cifs::ifs;

namespace {

Points fractal_fit_polygon(Eigen::Index n, Eigen::Index dim) {
  Points P(n, dim);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    P.row(i).head(2) << t + 0.3 * std::sin(3 * t), std::cos(1.7 * t) + 0.1 * t;
    if (dim > 2) P(i, 2) = 0.5 * std::sin(t);
  }
  return P;
}

/// The attractor of `system` on the curve's nets at depth `depth`, by edge_pieces: every node's start,
/// and the end of the last one for an open curve. Points k/(segments·2^depth) of the parameter.
Points attractor_samples(const Bcifs& system, const nurbs::Curve& curve, int depth) {
  const auto nets = nurbs::initial_nets(nurbs::knot_automaton(curve), curve);
  const EdgePieces pieces = edge_pieces(system, nets, depth);
  Points out(pieces.start.rows() + (curve.closed ? 0 : 1), pieces.start.cols());
  out.topRows(pieces.start.rows()) = pieces.start;
  if (!curve.closed) out.bottomRows(1) = pieces.end.bottomRows(1);
  return out;
}

double extent(const Points& P) {
  return (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
}

}  // namespace

TEST_CASE("fractal fit: the differential is exact (finite differences) and the points are edge_pieces",
          "[fractal_fit]") {
  const nurbs::Curve shapes[] = {
      nurbs::uniform_bspline(fractal_fit_polygon(7, 2), 3, false),
      nurbs::uniform_bspline(fractal_fit_polygon(7, 2), 3, true),
      // Non-uniform knots (a double one): vertex classes of other windows.
      nurbs::make_curve(3, {0, 0, 0, 0, 0.7, 1.1, 1.1, 2.5, 2.5, 2.5, 2.5}, fractal_fit_polygon(7, 3))};
  for (const nurbs::Curve& shape : shapes) {
    const bool closed = shape.closed;
    CAPTURE(closed);
    const Bcifs system = curve_bcifs(shape, {.free_vertices = true});
    const AdmissibleSpace space = admissible_space(system);
    PerturbOptions options;
    options.amplitude = 0.1;
    options.seed = 3;
    const Eigen::VectorXd c = free_values(perturb(system, options).system, space);
    // Points at depth 4 of every segment: the starts of edge_pieces' nodes (and the curve's end).
    const int depth = 4;
    const nurbs::Domain dom = nurbs::domain(shape);
    const Points pieces = attractor_samples(with_free_values(system, space, c), shape, depth);
    // Uniform shapes: evenly spaced parameters are the nodes' dyadic starts; the non-uniform one is
    // checked only against finite differences, at parameters inside its segments.
    std::vector<double> ts;
    for (Eigen::Index k = 0; k < pieces.rows(); ++k)
      ts.push_back(dom.start + (dom.end - dom.start) * static_cast<double>(k) /
                                   static_cast<double>(closed ? pieces.rows() : pieces.rows() - 1));
    const CurvePointDerivatives at = curve_point_derivatives(shape, system, space, c, ts, depth);
    if (shape.knots.size() != 11) CHECK((at.points - pieces).cwiseAbs().maxCoeff() <= 1e-13 * extent(pieces));
    // Every derivative against central differences of the points (the end functionals' and the
    // products' terms both matter: drop either and this fails).
    REQUIRE(at.derivatives.size() == static_cast<std::size_t>(c.size()));
    for (Eigen::Index j = 0; j < c.size(); ++j) {
      CAPTURE(j);
      const double h = 1e-6;
      Eigen::VectorXd up = c, down = c;
      up(j) += h;
      down(j) -= h;
      const Points fd = (curve_point_derivatives(shape, system, space, up, ts, depth).points -
                         curve_point_derivatives(shape, system, space, down, ts, depth).points) /
                        (2 * h);
      const Points& exact = at.derivatives[static_cast<std::size_t>(j)];
      CHECK((fd - exact).cwiseAbs().maxCoeff() <= 1e-7 * std::max(1.0, exact.cwiseAbs().maxCoeff()));
    }
  }
}

TEST_CASE("fractal fit: the attractor of a perturbed BC-IFS is recovered from its own points",
          "[fractal_fit]") {
  struct Case {
    int degree;
    Eigen::Index n, dim;
    bool closed, free_vertices;
    double amplitude;
  };
  const Case cases[] = {
      {3, 7, 2, false, true, 0.15}, {2, 6, 3, false, false, 0.2}, {3, 6, 2, true, true, 0.1}};
  for (const Case& k : cases) {
    CAPTURE(k.degree, k.n, k.closed, k.free_vertices);
    const nurbs::Curve truth = nurbs::uniform_bspline(fractal_fit_polygon(k.n, k.dim), k.degree, k.closed);
    const Bcifs system = curve_bcifs(truth, {.free_vertices = k.free_vertices});
    PerturbOptions options;
    options.amplitude = k.amplitude;
    options.seed = 5;
    const Perturbation p = perturb(system, options);
    const Points data = attractor_samples(p.system, truth, 5);
    // Uniform parameters put every data point on its dyadic parameter: the model can be exact.
    const FractalFit fit = fit_fractal(data, {.degree = k.degree,
                                              .control_points = k.n,
                                              .parametrization = nurbs::Parametrization::uniform,
                                              .closed = k.closed,
                                              .free_vertices = k.free_vertices,
                                              .dimension_points = 0});
    const double size = extent(data);
    CHECK(fit.smooth_rms > 1e-4 * size);  // the perturbation is visible to a smooth fit
    CHECK(fit.rms <= 1e-11 * size);
    CHECK(fit.max_distance <= 1e-10 * size);
    CHECK(fit.contraction.delta < 1);
    // Its own attractor, evaluated independently, passes through the data.
    CHECK((attractor_samples(fit.system, nurbs::uniform_bspline(fit.control_points, k.degree, k.closed), 5) -
           data)
              .cwiseAbs()
              .maxCoeff() <= 1e-10 * size);
  }
}

TEST_CASE("fractal fit: parameter correction moves data to closer attractor points, in order",
          "[fractal_fit]") {
  // Points of a perturbed system at depth 6, every other one dropped unevenly: the uniform parameters the
  // fit starts from are wrong, the attractor's own are dyadic at depth 6.
  const nurbs::Curve truth = nurbs::uniform_bspline(fractal_fit_polygon(7, 2), 3, false);
  PerturbOptions options;
  options.amplitude = 0.1;
  options.seed = 9;
  const Points all =
      attractor_samples(perturb(curve_bcifs(truth, {.free_vertices = true}), options).system, truth, 6);
  std::vector<Eigen::Index> keep;
  for (Eigen::Index k = 0; k < all.rows(); ++k)
    if (k % 3 != 1 || k == all.rows() - 1) keep.push_back(k);
  const Points data = all(keep, Eigen::all);
  FractalFitOptions o{.control_points = 7,
                      .parametrization = nurbs::Parametrization::uniform,
                      .reparametrizations = 0,
                      .dimension_points = 0};
  const FractalFit fixed = fit_fractal(data, o);
  o.reparametrizations = 3;
  const FractalFit corrected = fit_fractal(data, o);
  CAPTURE(fixed.rms, corrected.rms, corrected.reparametrizations);
  CHECK(corrected.reparametrizations >= 1);
  CHECK(corrected.rms < 0.5 * fixed.rms);
  CHECK(std::is_sorted(corrected.parameters.begin(), corrected.parameters.end(),
                       [](double a, double b) { return a <= b; }));
  CHECK(std::adjacent_find(corrected.parameters.begin(), corrected.parameters.end()) ==
        corrected.parameters.end());
  CHECK(corrected.parameters.front() == 0);
  CHECK(corrected.parameters.back() == 1);
}

TEST_CASE("fractal fit: smooth data keep the B-spline, and its start is de Boor's least squares",
          "[fractal_fit]") {
  const nurbs::Curve truth = nurbs::uniform_bspline(fractal_fit_polygon(8, 2), 3, false);
  const auto us = nurbs::uniform_parameters(nurbs::domain(truth), 161);
  const Points data = nurbs::evaluate(truth, us);
  const FractalFit fit = fit_fractal(
      data, {.control_points = 8, .parametrization = nurbs::Parametrization::uniform, .dimension_points = 0});
  const double size = extent(data);
  CHECK(fit.smooth_rms <= 1e-13 * size);
  CHECK((fit.smooth.P - truth.P).cwiseAbs().maxCoeff() <= 1e-12 * size);
  CHECK(fit.rms <= 1e-13 * size);
  CHECK(fit.iterations == 0);  // nothing to lower
  for (const VertexHolder& h : fit.holder) CHECK(h.exponent == Approx(1).margin(1e-12));
}

TEST_CASE("fractal fit: rough data get a rough curve closer than the smooth one", "[fractal_fit]") {
  // A random walk on a slope: rough at every scale.
  Random random(11);
  Points data(257, 2);
  double y = 0;
  for (Eigen::Index i = 0; i < data.rows(); ++i) {
    y += 0.02 * (2 * random.uniform() - 1);
    data.row(i) << static_cast<double>(i) / 256.0, y + 0.3 * std::sin(6.0 * static_cast<double>(i) / 256.0);
  }
  const FractalFit fit = fit_fractal(data, {.control_points = 8,
                                            .parametrization = nurbs::Parametrization::uniform,
                                            .max_iterations = 20,
                                            .reparametrizations = 1,
                                            .dimension_points = std::size_t{1} << 16});
  CAPTURE(fit.smooth_rms, fit.rms, fit.dimension, fit.dimension_note, fit.contraction.delta,
          fit.contraction.m, fit.iterations);
  CHECK(fit.rms < 0.9 * fit.smooth_rms);
  CHECK(fit.contraction.delta < 1);
  CHECK(fit.holder_bound >= 0.25);  // the default floor, proven by the 8-level products
  CHECK(std::any_of(fit.holder.begin(), fit.holder.end(),
                    [](const VertexHolder& h) { return h.exponent < 1; }));
  CHECK(fit.dimension >= 0.98);  // measured (finite); the roughness is mild at this sample's scales
}

TEST_CASE("fractal fit: bad input is refused in one line", "[fractal_fit]") {
  const Points data = fractal_fit_polygon(20, 2);
  CHECK_THROWS_WITH(fit_fractal(data, {.control_points = 3}),
                    Catch::Contains("control_points 3 is outside 4 … 20"));
  CHECK_THROWS_WITH(fit_fractal(data, {.control_points = 21}),
                    Catch::Contains("control_points 21 is outside 4 … 20"));
  CHECK_THROWS_WITH(fit_fractal(data, {.control_points = 20}),
                    Catch::Contains("no data point falls in segment"));
  CHECK_THROWS_WITH(fit_fractal(data, {.degree = 0, .control_points = 5}), Catch::Contains("degree 0"));
  CHECK_THROWS_WITH(fit_fractal(data, {.control_points = 5, .depth = 60}), Catch::Contains("depth 60"));
  CHECK_THROWS_WITH(fit_fractal(data, {.control_points = 5, .max_bytes = 1000}),
                    Catch::Contains("need a Jacobian of") && Catch::Contains("fit fewer points"));
  Points bad = data;
  bad(4, 1) = std::nan("");
  CHECK_THROWS_AS(fit_fractal(bad, {.control_points = 5}), InvalidInput);
}
