// SPDX-License-Identifier: MIT
#include "construct_command.hpp"

#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/construct.hpp"
#include "commands.hpp"

namespace cifs::cli {
namespace {

/// "x,y,z" as a point; InvalidInput naming the option otherwise.
Point parse_vector(const std::string& text, const std::string& option) {
  const std::string bad = option + " '" + text + "': expected finite numbers separated by commas";
  std::vector<double> values;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string_view word(text.data() + start,
                                (comma == std::string::npos ? text.size() : comma) - start);
    double x = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), x);
    if (word.empty() || error != std::errc() || end != word.data() + word.size() || !std::isfinite(x))
      throw InvalidInput(bad);
    values.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return Eigen::Map<const Point>(values.data(), static_cast<Eigen::Index>(values.size()));
}

Eigen::Vector3d parse_vector3(const std::string& text, const std::string& option) {
  const Point p = parse_vector(text, option);
  if (p.size() != 3)
    throw InvalidInput(option + " '" + text + "': " + std::to_string(p.size()) + " numbers, expected 3");
  return p.transpose();
}

nurbs::Curve read_curve(const std::filesystem::path& path) {
  io::ShapeReadOptions options;
  options.warn = [](const std::string& w) { pending_warnings().push_back(w); };
  io::Shape shape = io::read_shape(path, options);
  if (!std::holds_alternative<nurbs::Curve>(shape))
    throw InvalidInput(path.string() + ": holds a surface; construct takes curves");
  return std::get<nurbs::Curve>(std::move(shape));
}

}  // namespace

std::string construct(const ConstructOptions& o) {
  // The number of curve files each kind takes (loft: 2 or more).
  const std::string& k = o.kind;
  const std::size_t need = k == "extrude" || k == "revolve" ? 1 : 2;
  if (k != "ruled" && k != "extrude" && k != "revolve" && k != "loft" && k != "sweep")
    throw InvalidInput("construct '" + k + "': expected ruled, extrude, revolve, loft or sweep");
  if (k == "loft" ? o.curves.size() < 2 : o.curves.size() != need)
    throw InvalidInput("construct " + k + ": " + std::to_string(o.curves.size()) + " curve files given, " +
                       (k == "loft" ? "at least 2" : std::to_string(need)) + " expected");
  if (!o.output.empty()) io::format_of(o.output, io::Content::shape);  // refuse the extension before the work
  std::vector<nurbs::Curve> curves;
  for (const auto& path : o.curves) curves.push_back(read_curve(path));
  double deviation = 0;
  const auto build = [&] {
    if (k == "ruled") return nurbs::ruled(curves[0], curves[1]);
    if (k == "extrude") return nurbs::extrude(curves[0], parse_vector(o.direction, "--direction"));
    if (k == "revolve") {
      if (!(o.angle > 0 && o.angle <= 360))
        throw InvalidInput("--angle " + number_text(o.angle) + ": outside (0, 360] degrees");
      // angle/180 is exact for whole multiples of 90°, so 360 gives 2π exactly (a closed surface).
      return nurbs::revolve(curves[0], parse_vector3(o.axis_point, "--axis-point"),
                            parse_vector3(o.axis, "--axis"), o.angle / 180 * std::numbers::pi);
    }
    if (k == "loft")
      return nurbs::loft(curves, {.degree_v = o.degree_v,
                                  .parametrization = nurbs::parametrization_named(o.parametrization)});
    nurbs::Sweep sweep =
        nurbs::sweep(curves[0], curves[1], {.instances = o.instances, .degree_v = o.degree_v});
    deviation = sweep.deviation;
    return std::move(sweep.surface);
  };
  const nurbs::Surface surface = [&] {
    try {
      return build();
    } catch (const InvalidInput& e) {  // the library names the argument (curves[i]: the i-th file)
      throw InvalidInput("construct " + k + ": " + e.what());
    }
  }();
  if (o.output.empty()) return io::to_json(io::Shape(surface));
  io::write(o.output, io::Shape(surface));
  nlohmann::json summary{{"written", o.output.string()},
                         {"degree", {surface.degree[0], surface.degree[1]}},
                         {"control_points", {surface.count[0], surface.count[1]}},
                         {"rational", surface.rational}};
  if (k == "sweep") summary["deviation"] = deviation;
  return summary.dump() + "\n";
}

}  // namespace cifs::cli
