// SPDX-License-Identifier: MIT
#include "fit_command.hpp"

#include <nlohmann/json.hpp>

#include "cifs/errors.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/fit.hpp"

namespace cifs::cli {

std::string fit(const FitOptions& o) {
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
