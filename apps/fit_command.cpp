// SPDX-License-Identifier: MIT
#include "fit_command.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "cifs/errors.hpp"
#include "cifs/ifs/fractal_fit.hpp"
#include "cifs/io/bcifs_file.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/fit.hpp"

namespace cifs::cli {

namespace {

/// A finite number, or null (JSON has no NaN).
nlohmann::json number_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

std::string fit_fractal(const FitOptions& o) {
  if (o.tolerance != 0) throw InvalidInput("--fractal takes --control-points N, not --tolerance");
  if (o.control_points <= 0)
    throw InvalidInput("--fractal needs --control-points N (the model's control points)");
  const auto kind = nurbs::parametrization_named(o.parametrization);
  if (!o.output.empty()) io::format_of(o.output, io::Content::bcifs);  // refuse the extension before the work
  const Points points = io::read_points(o.points);
  ifs::FractalFitOptions options;
  options.degree = o.degree;
  options.control_points = static_cast<Eigen::Index>(o.control_points);
  options.parametrization = kind;
  options.closed = o.closed;
  options.free_vertices = !o.fixed_knot_points;
  options.depth = o.depth;
  options.max_iterations = o.iterations;
  options.min_holder = o.min_holder;
  const ifs::FractalFit result = [&] {
    try {
      return ifs::fit_fractal(points, options);
    } catch (const InvalidInput& e) {
      throw InvalidInput(o.points.string() + ": " + e.what());
    }
  }();
  const io::BcifsFile file{result.system, result.nets};
  if (o.output.empty()) return io::to_json(file.system, file.nets);
  io::write(o.output, file);
  nlohmann::json holder = nlohmann::json::object();
  for (const ifs::VertexHolder& h : result.holder) holder[h.cell] = h.exponent;
  const nlohmann::json summary{
      {"written", o.output.string()},
      {"points", points.rows()},
      {"degree", o.degree},
      {"control_points", o.control_points},
      {"closed", o.closed},
      {"free_coefficients", result.coefficients.size()},
      {"iterations", result.iterations},
      {"reparametrizations", result.reparametrizations},
      {"rms", result.rms},
      {"max_distance", result.max_distance},
      {"smooth_rms", result.smooth_rms},
      {"smooth_max_distance", result.smooth_max_distance},
      {"contraction", {{"delta", result.contraction.delta}, {"m", result.contraction.m}}},
      {"holder_bound", result.holder_bound},
      {"holder", holder},
      {"dimension", number_or_null(result.dimension)},
      {"dimension_uncertainty", number_or_null(result.dimension_uncertainty)}};
  return summary.dump() + "\n";
}

}  // namespace

std::string fit(const FitOptions& o) {
  if (o.fractal) return fit_fractal(o);
  const auto kind = nurbs::parametrization_named(o.parametrization);
  const auto measure = nurbs::fit_measure_named(o.measure);
  if (!o.output.empty()) io::format_of(o.output, io::Content::shape);  // refuse the extension before the work
  const Points points = io::read_points(o.points);
  nurbs::ApproximateOptions options;
  options.degree = o.degree;
  options.parametrization = kind;
  options.control_points = static_cast<Eigen::Index>(o.control_points);
  options.tolerance = o.tolerance;
  options.measure = measure;
  options.closed = o.closed;
  const nurbs::CurveFit result = [&] {
    try {
      return nurbs::approximate(points, options);
    } catch (const InvalidInput& e) {  // the library names the point; the file goes first
      throw InvalidInput(o.points.string() + ": " + e.what());
    }
  }();
  if (o.output.empty()) return io::to_json(io::Shape(result.curve));
  io::write(o.output, io::Shape(result.curve));
  const nlohmann::json summary{
      {"written", o.output.string()},           {"points", points.rows()},
      {"degree", result.curve.degree},          {"control_points", nurbs::distinct_count(result.curve)},
      {"closed", result.curve.closed},          {"point_distance", result.point_distance},
      {"polyline_bound", result.polyline_bound}};
  return summary.dump() + "\n";
}

}  // namespace cifs::cli
