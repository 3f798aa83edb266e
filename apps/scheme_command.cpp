// SPDX-License-Identifier: MIT
#include "scheme_command.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/svg.hpp"
#include "cifs/subdivision/analysis.hpp"
#include "cifs/subdivision/refine.hpp"
#include "cifs/subdivision/scheme.hpp"

namespace cifs::cli {
namespace {

namespace sd = cifs::subdivision;
using io::Stroke;
using io::strokes_svg;

std::map<std::string, std::string> parse_params(const std::vector<std::string>& params) {
  std::map<std::string, std::string> out;
  for (const std::string& p : params) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InvalidInput("--param '" + p + "': expected NAME=VALUE, e.g. --param w=0.0625");
    const std::string key = p.substr(0, eq);
    if (out.count(key)) throw InvalidInput("--param " + key + " is given twice");
    out[key] = p.substr(eq + 1);
  }
  return out;
}

std::string catalogue_text() {
  std::ostringstream s;
  for (const sd::SchemeSpec& spec : sd::scheme_catalogue()) {
    s << spec.name;
    for (const sd::ParameterSpec& p : spec.parameters)
      s << " " << p.name << "=" << (p.default_value.empty() ? "(required)" : p.default_value);
    s << "\n    " << spec.summary << "\n";
  }
  return s.str();
}

sd::Ends parse_ends(const std::string& ends) {
  if (ends == "auto") return sd::Ends::automatic;
  if (ends == "reflect") return sd::Ends::reflect;
  if (ends == "keep") return sd::Ends::keep;
  throw InvalidInput("--ends '" + ends + "': auto, reflect or keep");
}

// ------------------------------------------------------------------------------------------------
// Gallery

Points rows(std::initializer_list<std::pair<double, double>> xy) {
  Points P(static_cast<Eigen::Index>(xy.size()), 2);
  Eigen::Index i = 0;
  for (const auto& [x, y] : xy) P.row(i++) << x, y;
  return P;
}

/// The seed 000 shapes (our own control polygons): examples/shapes/NAME.json.
std::vector<std::pair<std::string, Points>> seed_shapes(const std::filesystem::path& examples) {
  std::vector<std::pair<std::string, Points>> out;
  for (const char* name : {"hepta", "bone", "infinity", "sumsign", "clover"})
    out.emplace_back(name, io::read_polygon(examples / "shapes" / (std::string(name) + ".json")).points);
  return out;
}

Stroke control(const Points& P, bool closed = true) {
  return {P, closed, "#b0b0b0", 1.0, "4 3", "control polygon"};
}

}  // namespace

std::string scheme(const SchemeOptions& o) {
  if (o.list) return catalogue_text();
  if (o.name.empty()) throw InvalidInput("scheme: a scheme name is required (see cifs scheme --list)");
  const bool refine = !o.refine.empty();
  if (o.analyze == refine)
    throw InvalidInput(o.analyze ? "scheme: --analyze and --refine are exclusive"
                                 : "scheme: choose --analyze or --refine POLYGON.json (or --list)");
  const sd::Scheme s = sd::named_scheme(o.name, parse_params(o.params));
  if (o.analyze) {
    if (o.max_power < 1 || o.max_power > 26)
      throw InvalidInput("--max-power " + std::to_string(o.max_power) + ": between 1 and 26");
    sd::AnalysisOptions a;
    a.max_power = o.max_power;
    return io::analysis_json(s, sd::analyze(s, a));
  }
  if (o.steps < 0) throw InvalidInput("--steps " + std::to_string(o.steps) + " is negative");
  io::writable_format(io::Content::polygon, o.format, "--format");
  const io::Polygon polygon = io::read_polygon(o.refine);
  sd::RefineOptions r;
  r.ends = parse_ends(o.ends);
  r.max_points = 50'000'000;
  const Points out = sd::refine(s, polygon.points, polygon.closed, o.steps, r);
  return io::encode(io::Polygon{out, polygon.closed}, o.format);
}

std::string write_scheme_gallery(const std::filesystem::path& folder, const std::filesystem::path& examples) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw IoError(folder.string() + ": cannot create the folder (" + ec.message() + ")");
  std::string summary;
  const auto write = [&](const std::string& name, const std::string& svg) {
    write_file_atomically(folder / name, svg);
    summary += "scheme gallery: wrote " + (folder / name).string() + "\n";
  };
  constexpr int kSteps = 5;
  // Seed 000: "degree" = averaging passes + 1 = B-spline degree + 1 = smoothing stages + 1.
  const int seed_degrees[] = {2, 3, 5, 10, 30};
  const char* dashes[] = {"", "10 5", "10 4 2 4", "10 4 2 4 2 4", "2 4"};
  const struct {
    std::string key, title;
    sd::Scheme (*make)(int seed_degree);
  } algorithms[] = {
      {"lr", "Lane-Riesenfeld", [](int d) { return sd::lane_riesenfeld(d - 1); }},
      {"lr4", "Four-point variant", [](int d) { return sd::lr_four_point(d - 1); }},
      {"lr6", "Six-point variant", [](int d) { return sd::lr_six_point(d - 1); }},
  };
  const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c"};
  for (const auto& [shape, P] : seed_shapes(examples)) {
    for (const auto& alg : algorithms) {
      write(
          alg.key + "_" + shape + "_degree3.svg",
          strokes_svg(
              {control(P), {sd::refine(alg.make(3), P, true, kSteps), true, "#1f77b4", 1.8, "", ""}},
              "\"" + shape + "\", seed degree 3, " + std::to_string(kSteps) + " subdivisions, " + alg.title));
      std::vector<Stroke> strokes{control(P)};
      for (int i = 0; i < 5; ++i)
        strokes.push_back({sd::refine(alg.make(seed_degrees[i]), P, true, kSteps), true, "#1f77b4", 1.5,
                           dashes[i], "seed degree " + std::to_string(seed_degrees[i])});
      write(alg.key + "_" + shape + "_degrees.svg",
            strokes_svg(strokes, "\"" + shape + "\", seed degrees 2, 3, 5, 10, 30, " +
                                     std::to_string(kSteps) + " subdivisions, " + alg.title));
    }
    std::vector<Stroke> compare{control(P)};
    for (int a = 0; a < 3; ++a)
      compare.push_back({sd::refine(algorithms[a].make(30), P, true, kSteps), true, colours[a], 1.8, "",
                         algorithms[a].title});
    write("compare_" + shape + ".svg", strokes_svg(compare, "\"" + shape + "\", seed degree 30, " +
                                                                std::to_string(kSteps) + " subdivisions"));
  }

  // Seed 001.
  const Points zigzag = rows({{0, 0}, {1, 2}, {2, 0}, {3, 2}, {4, 0}, {5, 1.5}});
  const Points square = rows({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  write(
      "chaikin_open_closed.svg",
      strokes_svg({control(zigzag, false),
                   {sd::refine(sd::chaikin(), zigzag, false, kSteps), false, "#1f77b4", 1.8, "",
                    "open (end points kept)"},
                   {sd::refine(sd::chaikin(), zigzag, true, kSteps), true, "#ff7f0e", 1.8, "6 3", "closed"}},
                  "Chaikin, open and closed, 5 subdivisions"));
  {
    std::vector<Stroke> strokes{control(square)};
    const char* ws[] = {"0", "0.03125", "0.0625", "0.1", "0.15", "0.2"};
    const char* cs[] = {"#444444", "#2ca02c", "#1f77b4", "#9467bd", "#ff7f0e", "#d62728"};
    for (int i = 0; i < 6; ++i)
      strokes.push_back(
          {sd::refine(sd::generalized_four_point(sd::parse_rational(ws[i], "w")), square, true, 7), true,
           cs[i], 1.5, "", std::string("w = ") + ws[i] + " (eps = 16w)"});
    write("four_point_tension.svg",
          strokes_svg(strokes, "Generalised 4-point scheme, tension sweep, 7 subdivisions"));
  }
  {
    std::vector<Stroke> strokes{control(square)};
    const char* as[] = {"0.05", "0.15", "0.25", "0.35", "0.45"};
    const char* cs[] = {"#d62728", "#ff7f0e", "#1f77b4", "#2ca02c", "#9467bd"};
    for (int i = 0; i < 5; ++i) {
      const sd::Rational a = sd::parse_rational(as[i], "a");
      strokes.push_back({sd::refine(sd::corner_cutting(a, 1 - a), square, true, 7), true, cs[i], 1.5, "",
                         std::string("a = ") + as[i] + ", b = 1 - a"});
    }
    write("corner_cutting_symmetric.svg",
          strokes_svg(strokes, "Corner cutting with b = 1 - a, 7 subdivisions"));
  }
  {
    std::vector<Stroke> strokes{control(square)};
    const std::pair<const char*, const char*> ab[] = {
        {"0.25", "0.75"}, {"0.1", "0.6"}, {"0.2", "0.5"}, {"0.4", "0.9"}};
    const char* cs[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728"};
    for (int i = 0; i < 4; ++i)
      strokes.push_back({sd::refine(sd::corner_cutting(sd::parse_rational(ab[i].first, "a"),
                                                       sd::parse_rational(ab[i].second, "b")),
                                    square, true, 7),
                         true, cs[i], 1.5, "", std::string("a = ") + ab[i].first + ", b = " + ab[i].second});
    write("corner_cutting_asymmetric.svg",
          strokes_svg(strokes, "Corner cutting with b != 1 - a, 7 subdivisions"));
  }
  {
    const Points P = seed_shapes(examples)[0].second;
    write(
        "approximating_interpolating.svg",
        strokes_svg(
            {control(P),
             {sd::refine(sd::chaikin(), P, true, 6), true, "#1f77b4", 1.8, "", "Chaikin (approximating)"},
             {sd::refine(sd::four_point(), P, true, 6), true, "#ff7f0e", 1.8, "", "4-point (interpolating)"}},
            "\"hepta\": approximating vs interpolating"));
  }
  return summary;
}

}  // namespace cifs::cli
