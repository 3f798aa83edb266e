// SPDX-License-Identifier: MIT
#include "commands.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/verify/check.hpp"
#include "scheme_command.hpp"

namespace cifs::cli {

std::vector<std::string>& pending_warnings() {
  static std::vector<std::string> warnings;
  return warnings;
}

namespace {

using nlohmann::json;

/// Largest sample grid we accept: beyond it the JSON output alone would exhaust memory.
constexpr long long kMaxPoints = 50'000'000;

double parse_number(std::string_view text, std::string_view option) {
  double x = 0;
  const auto* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, x);
  if (ec != std::errc() || ptr != end || !std::isfinite(x))
    throw InvalidInput(std::string(option) + " '" + std::string(text) + "': not a finite number");
  return x;
}

/// `{"points": [[x, y, ...], ...]}` written straight to text: shortest round-trip numbers
/// (std::to_chars), no JSON tree in between (large attractors stay within ~1.5× their text).
std::string points_json(const Points& P) {
  std::string out;
  out.reserve(static_cast<std::size_t>(P.size()) * 22 + 16);
  out += "{\"points\":[";
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    out += i ? ",[" : "[";
    for (Eigen::Index j = 0; j < P.cols(); ++j) {
      if (j) out += ',';
      append_number(out, P(i, j));
    }
    out += ']';
  }
  out += "]}\n";
  return out;
}

/// The shapes of a file, or the one `select.index` picks (`one`: the file must then hold one shape).
/// Warnings wait in pending_warnings.
std::vector<io::Shape> read_shapes(const std::filesystem::path& path, const ShapeSelection& select,
                                   bool one = false) {
  const io::ShapeReadOptions options{.ignore_trim = select.ignore_trim,
                                     .index = select.index,
                                     .warn = [](const std::string& w) { pending_warnings().push_back(w); }};
  if (one || select.index) return {io::read_shape(path, options)};
  return io::read_shapes(path, options);
}

io::Shape read_shape(const std::filesystem::path& path, const ShapeSelection& select) {
  return std::move(read_shapes(path, select, true).front());
}

void check_samples(long long count) {
  if (count > kMaxPoints)
    throw InvalidInput("--samples: " + std::to_string(count) + " points exceed the limit of " +
                       std::to_string(kMaxPoints) + " (the output would not fit in memory)");
}

std::string eval_curve(const nurbs::Curve& c, const EvalOptions& o) {
  std::vector<double> us;
  for (const std::string& a : o.at) {
    if (a.find(',') != std::string::npos)
      throw InvalidInput("--at '" + a + "': a curve takes one parameter U");
    us.push_back(parse_number(a, "--at"));
  }
  check_samples(o.samples);
  const std::vector<double> grid = nurbs::uniform_parameters(nurbs::domain(c), o.samples);
  us.insert(us.end(), grid.begin(), grid.end());
  return points_json(nurbs::evaluate(c, us));
}

std::string eval_surface(const nurbs::Surface& s, const EvalOptions& o) {
  Points out(0, nurbs::dimension(s));
  std::vector<Point> rows;
  for (const std::string& a : o.at) {
    const auto comma = a.find(',');
    if (comma == std::string::npos) throw InvalidInput("--at '" + a + "': a surface takes U,V");
    const double u = parse_number(std::string_view(a).substr(0, comma), "--at");
    const double v = parse_number(std::string_view(a).substr(comma + 1), "--at");
    rows.push_back(nurbs::evaluate(s, u, v));
  }
  check_samples(static_cast<long long>(o.samples) * o.samples);
  const auto us = nurbs::uniform_parameters(nurbs::domain(s, nurbs::Direction::u), o.samples);
  const auto vs = nurbs::uniform_parameters(nurbs::domain(s, nurbs::Direction::v), o.samples);
  const Points grid = nurbs::evaluate_grid(s, us, vs);
  out.resize(static_cast<Eigen::Index>(rows.size()) + grid.rows(), out.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = rows[i];
  out.bottomRows(grid.rows()) = grid;
  return points_json(out);
}

}  // namespace

std::string eval(const EvalOptions& o) {
  if (o.samples < 0) throw InvalidInput("--samples " + std::to_string(o.samples) + ": must be non-negative");
  if (o.at.empty() && o.samples == 0) throw InvalidInput("eval: give --at U (repeatable) or --samples N");
  const io::Shape shape = read_shape(o.shape, o.select);
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) return eval_curve(*c, o);
  return eval_surface(std::get<nurbs::Surface>(shape), o);
}

std::string insert(const InsertOptions& o) {
  if (o.dir != "u" && o.dir != "v") throw InvalidInput("--dir '" + o.dir + "': expected u or v");
  if (o.knots.empty() && !o.midpoints)
    throw InvalidInput("insert: give --knot U (repeatable) or --midpoints");
  const io::Shape shape = read_shape(o.shape, o.select);
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    if (o.dir != "u") throw InvalidInput("--dir v: a curve has one direction");
    nurbs::Curve out = nurbs::refine(*c, o.knots);
    if (o.midpoints) out = nurbs::refine_midpoints(out);
    return io::to_json(out);
  }
  const auto dir = o.dir == "u" ? nurbs::Direction::u : nurbs::Direction::v;
  nurbs::Surface out = nurbs::refine(std::get<nurbs::Surface>(shape), dir, o.knots);
  if (o.midpoints) out = nurbs::refine_midpoints(out);
  return io::to_json(out);
}

namespace {

json shape_info(const io::Shape& shape) {
  json out;
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    const nurbs::Domain dom = nurbs::domain(*c);
    out = {{"type", "curve"},
           {"degree", c->degree},
           {"dimension", nurbs::dimension(*c)},
           {"control_points", nurbs::distinct_count(*c)},
           {"knots", nurbs::defining_knots(*c).size()},
           {"rational", c->rational},
           {"closed", c->closed},
           {"domain", {dom.start, dom.end}},
           {"segments", nurbs::segment_count(*c)}};
  } else {
    const auto& s = std::get<nurbs::Surface>(shape);
    json domains = json::array(), segments = json::array();
    for (auto dir : {nurbs::Direction::u, nurbs::Direction::v}) {
      const nurbs::Domain dom = nurbs::domain(s, dir);
      domains.push_back({dom.start, dom.end});
      const auto& t = s.knots[static_cast<std::size_t>(dir)];
      segments.push_back(nurbs::breakpoints(t, s.degree[static_cast<std::size_t>(dir)]).size() - 1);
    }
    out = {{"type", "surface"},
           {"degree", s.degree},
           {"dimension", nurbs::dimension(s)},
           {"control_points", s.count},
           {"knots", {s.knots[0].size(), s.knots[1].size()}},
           {"rational", s.rational},
           {"domain", domains},
           {"segments", segments}};
  }
  return out;
}

}  // namespace

std::string info(const std::filesystem::path& path, const ShapeSelection& select) {
  if (is_polygon_mesh_file(path)) return mesh_info(path);
  // Every shape of the file: one object, or an array of them with their index when there are several.
  const std::vector<io::Shape> shapes = read_shapes(path, select);
  if (shapes.size() == 1) return shape_info(shapes.front()).dump(1) + "\n";
  json all = json::array();
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    json entry = shape_info(shapes[i]);
    entry["index"] = i;
    all.push_back(std::move(entry));
  }
  return all.dump(1) + "\n";
}

std::string automaton(const AutomatonOptions& o) {
  io::writable_format(io::Content::automaton, o.format, "--format");
  const io::Shape shape = read_shape(o.shape, o.select);
  const auto* c = std::get_if<nurbs::Curve>(&shape);
  if (!c)
    throw InvalidInput(o.shape.string() + ": automaton: only curves have a knot-doubling automaton so far");
  automata::Automaton a = automata::knot_automaton(*c);
  if (o.minimize) a = automata::minimize(a);
  return io::encode(a, o.format);
}

std::string attractor(const AttractorOptions& o) {
  // The attractor is a polyline: any polygon format, where json is the points report of `eval`.
  io::writable_format(io::Content::polygon, o.format, "--format");
  if ((o.depth >= 0) + (o.tolerance > 0) + (o.chaos != 0) != 1)
    throw InvalidInput("attractor: give exactly one of --depth K, --tolerance E and --chaos N");
  if (o.chaos < 0 || o.chaos > kMaxPoints)
    throw InvalidInput("--chaos " + std::to_string(o.chaos) + ": expected 1 to " +
                       std::to_string(kMaxPoints) + " points");
  if (o.chaos != 0 && o.format != "json")
    throw InvalidInput("--chaos: the points are unordered, use --format json");
  if (o.tolerance < 0 || !std::isfinite(o.tolerance))
    throw InvalidInput("--tolerance: must be a positive number");
  const io::Shape shape = read_shape(o.shape, o.select);
  const auto* c = std::get_if<nurbs::Curve>(&shape);
  if (!c)
    throw InvalidInput(o.shape.string() + ": attractor: only curves have a knot-doubling automaton so far");
  const automata::Automaton a = automata::knot_automaton(*c);
  const std::vector<Points> nets = automata::initial_nets(a, *c);
  Points H;
  std::string seed_member;
  if (o.chaos != 0) {
    ifs::ChaosOptions options;
    options.samples = static_cast<std::size_t>(o.chaos);
    options.seed = o.seed;
    const ifs::ChaosResult r = ifs::chaos_game(a, nets, options);
    H = r.points;
    seed_member = ",\"seed\":" + std::to_string(r.seed);
  } else if (o.depth >= 0) {
    ifs::PointsOptions options;
    options.closed = c->closed;
    H = ifs::attractor_points(a, nets, o.depth, options);
  } else {
    // Leaves whose whole piece is below the tolerance; rational nets are homogeneous, so shrink
    // the tolerance by w_min / (1 + max|P|), which bounds the Cartesian image of a homogeneous piece.
    const double max_point = nurbs::cartesian_points(*c).rowwise().norm().maxCoeff();
    const double epsilon =
        c->rational ? o.tolerance * nurbs::weights(*c).minCoeff() / (1 + max_point) : o.tolerance;
    const ifs::EndFunctionals f = ifs::end_functionals(a);
    std::vector<Point> rows;
    Point last_end;
    const ifs::ToleranceResult r =
        ifs::for_each_leaf_to_tolerance(a, nets, {epsilon, 40, 8}, [&](const ifs::ToleranceLeaf& t) {
          rows.push_back(f.start[t.leaf.state] * t.leaf.net);
          last_end = f.end[t.leaf.state] * t.leaf.net;
        });
    if (r.unconverged > 0)
      throw InvalidInput("attractor: " + std::to_string(r.unconverged) +
                         " pieces did not reach --tolerance " + std::to_string(o.tolerance) +
                         " by depth 40; give a larger tolerance");
    if (!c->closed) rows.push_back(last_end);
    H.resize(static_cast<Eigen::Index>(rows.size()), c->P.cols());
    for (std::size_t i = 0; i < rows.size(); ++i) H.row(static_cast<Eigen::Index>(i)) = rows[i];
  }
  const Points P = c->rational ? ifs::cartesian(H) : H;
  if (o.format != "json") return io::encode(io::Polygon{P, c->closed}, o.format);
  std::string text = points_json(P);
  return seed_member.empty() ? text : text.insert(text.size() - 2, seed_member);
}

namespace {

json deviation_json(const verify::Deviation& d) {
  return {{"max_abs", d.max_abs}, {"max_rel", d.max_rel}};
}

std::string check_verdict(bool pass) {
  return pass ? "PASS: the attractor matches knot insertion and Cox-de Boor evaluation\n"
              : "FAIL: a deviation exceeds the tolerance\n";
}

std::string check_surface(const nurbs::Surface& s, const CheckOptions& o, int& status) {
  const verify::SurfaceCheckReport r = verify::check_surface(s, {o.depth, o.tolerance});
  status = r.pass ? 0 : 1;
  if (o.json) {
    json patches = json::array();
    for (const auto& p : r.patches)
      patches.push_back({{"patch", p.patch},
                         {"interval", {p.u, p.v}},
                         {"nets", deviation_json(p.nets)},
                         {"points", deviation_json(p.points)}});
    return json{{"depth", r.depth},
                {"tolerance", r.tolerance},
                {"patches", patches},
                {"nets", deviation_json(r.nets)},
                {"points", deviation_json(r.points)},
                {"pass", r.pass}}
               .dump(1) +
           "\n";
  }
  char line[240];
  std::string out = "cifs check: depth " + std::to_string(r.depth) + ", " + std::to_string(r.patches.size()) +
                    " patches, relative tolerance " + json(r.tolerance).dump() + "\n";
  out +=
      "  patch     u interval                  v interval                  nets max_abs  max_rel    "
      "points max_abs  max_rel\n";
  for (const auto& p : r.patches) {
    std::snprintf(line, sizeof line,
                  "  %3d,%-3d  [%-11.5g, %-11.5g]  [%-11.5g, %-11.5g]  %12.3e  %9.3e    %12.3e  %9.3e\n",
                  p.patch[0], p.patch[1], p.u[0], p.u[1], p.v[0], p.v[1], p.nets.max_abs, p.nets.max_rel,
                  p.points.max_abs, p.points.max_rel);
    out += line;
  }
  std::snprintf(
      line, sizeof line,
      "  all                                                            %12.3e  %9.3e    %12.3e  %9.3e\n",
      r.nets.max_abs, r.nets.max_rel, r.points.max_abs, r.points.max_rel);
  out += line;
  return out + check_verdict(r.pass);
}

}  // namespace

std::string check(const CheckOptions& o, int& status) {
  const io::Shape shape = read_shape(o.shape, o.select);
  const auto* c = std::get_if<nurbs::Curve>(&shape);
  if (!c) return check_surface(std::get<nurbs::Surface>(shape), o, status);
  const verify::CheckReport r = verify::check_curve(*c, {o.depth, o.tolerance});
  status = r.pass ? 0 : 1;
  if (o.json) {
    json segments = json::array();
    for (const auto& s : r.segments)
      segments.push_back({{"segment", s.segment},
                          {"interval", {s.start, s.end}},
                          {"nets", deviation_json(s.nets)},
                          {"points", deviation_json(s.points)}});
    return json{{"depth", r.depth},
                {"tolerance", r.tolerance},
                {"segments", segments},
                {"nets", deviation_json(r.nets)},
                {"points", deviation_json(r.points)},
                {"pass", r.pass}}
               .dump(1) +
           "\n";
  }
  char line[200];
  std::string out = "cifs check: depth " + std::to_string(r.depth) + ", " +
                    std::to_string(r.segments.size()) + " segments, relative tolerance " +
                    json(r.tolerance).dump() + "\n";
  out += "  segment  interval                        nets max_abs  max_rel    points max_abs  max_rel\n";
  for (const auto& s : r.segments) {
    std::snprintf(line, sizeof line, "  %7d  [%-12.6g, %-12.6g]  %12.3e  %9.3e    %12.3e  %9.3e\n", s.segment,
                  s.start, s.end, s.nets.max_abs, s.nets.max_rel, s.points.max_abs, s.points.max_rel);
    out += line;
  }
  std::snprintf(line, sizeof line,
                "  all                                    %12.3e  %9.3e    %12.3e  %9.3e\n", r.nets.max_abs,
                r.nets.max_rel, r.points.max_abs, r.points.max_rel);
  out += line;
  return out + check_verdict(r.pass);
}

std::string render(const RenderOptions& o) {
  const io::Experiment e = io::read_experiment(o.experiment);
  experiment::RunOptions ro;
  ro.exr = o.exr;
  ro.png = o.png;
  ro.out_dir = !o.out_dir.empty() ? o.out_dir : o.exr.has_parent_path() ? o.exr.parent_path() : ".";
  ro.quiet = o.quiet;
  ro.threads = o.threads;
  return experiment::run(e, ro).summary;
}

std::string dimension(const DimensionOptions& o) {
  // A shape file holds "curve" or "surface", or "shape" alone (geomdl), or is an OBJ; anything else
  // is an experiment.
  bool shape = o.input.extension() == ".obj";
  if (o.input.extension() == ".json") {
    std::ifstream in(o.input);
    if (!in) throw IoError(o.input.string() + ": cannot open");
    const json j = json::parse(in, nullptr, false);
    shape = j.is_object() &&
            (j.contains("curve") || j.contains("surface") || (j.size() == 1 && j.contains("shape")));
  }
  if (!shape && (o.select.index || o.select.ignore_trim))
    throw InvalidInput(o.input.string() +
                       ": --index and --ignore-trim apply to shape files, not experiments");
  io::Experiment e;
  if (shape) {
    e.name = o.input.stem().string();
    e.shape = read_shape(o.input, o.select);
  } else {
    e = io::read_experiment(o.input);
  }
  if (o.depth && o.tolerance) throw InvalidInput("dimension: give --depth or --tolerance, not both");
  // Default: a tolerance sample, whose piece size is proven; --depth: the file's evaluation.
  const bool sampled = !o.depth;
  const experiment::Evaluation ev = sampled ? experiment::sample(e, {o.tolerance.value_or(0), o.max_points})
                                            : experiment::evaluate(e, o.depth);
  ifs::BoxCountingOptions bo;
  bo.resolution = ev.resolution;
  bo.min_boxes = o.min_boxes;
  // A tolerance sample covers the attractor to its resolution by construction: the
  // points-per-box rule (a proxy for coverage of depth samples) does not apply.
  if (sampled) bo.points_per_box = 1;
  bo.min_level = o.min_level;
  bo.max_level = o.max_level;
  const ifs::BoxCountingResult r = [&] {
    try {
      return ifs::box_counting(ev.points, bo);
    } catch (const InvalidInput& error) {
      // The proven piece bound may be loose (signed matrices): say that a depth evaluation is the way out.
      if (!sampled || o.min_level >= 0) throw;
      throw InvalidInput(std::string(error.what()) +
                         "; or raise --max-points, or measure a depth evaluation (--depth K)");
    }
  }();
  // The similarity dimension applies when every map is a similarity; say why when it does not.
  std::optional<double> similarity;
  std::string why_not;
  try {
    if (!ev.maps.empty())
      similarity = ifs::similarity_dimension(ev.maps);
    else if (ev.rational)
      why_not = "rational nets (homogeneous maps are not similarities of the plane)";
    else
      similarity = ifs::similarity_dimension(ev.automaton, ev.nets);
  } catch (const InvalidInput& error) {
    why_not = error.what();
  }

  if (o.json) {
    json j;
    j["input"] = o.input.string();
    j["kind"] = ev.kind;
    j["mode"] = sampled ? "tolerance" : "depth";
    j["depth"] = ev.depth;
    j["points"] = ev.points.rows();
    j["resolution"] = ev.resolution;
    json box;
    box["dimension"] = r.dimension;
    box["levels"] = {r.min_level, r.max_level};
    box["epsilon"] = {r.max_epsilon, r.min_epsilon};
    box["r_squared"] = r.r_squared;
    box["residual"] = r.residual;
    box["size"] = r.size;
    json counts = json::array();
    for (const ifs::BoxCount& c : r.counts)
      counts.push_back({{"level", c.level}, {"epsilon", c.epsilon}, {"boxes", c.boxes}});
    box["counts"] = counts;
    j["box_counting"] = box;
    j["similarity_dimension"] = similarity ? json(*similarity) : json(nullptr);
    if (!similarity) j["similarity_note"] = why_not;
    return j.dump(2) + "\n";
  }
  const std::string resolution = number_text(ev.resolution, 4);
  std::string out = o.input.string() + ": " + ev.kind + ", " +
                    (sampled ? "pieces < " + resolution + " (deepest " + std::to_string(ev.depth) + ")"
                             : "depth " + std::to_string(ev.depth) + ", pieces ≤ " + resolution) +
                    ", " + std::to_string(ev.points.rows()) + " points\n";
  char line[256];
  std::snprintf(line, sizeof line,
                "box-counting dimension %.4f (levels %d … %d, ε %.4g … %.4g, R² %.6f, max residual %.3g)\n",
                r.dimension, r.min_level, r.max_level, r.max_epsilon, r.min_epsilon, r.r_squared, r.residual);
  out += line;
  if (similarity) {
    std::snprintf(line, sizeof line, "similarity dimension %.12g\n", *similarity);
    out += line;
  } else {
    out += "similarity dimension: not applicable (" + why_not + ")\n";
  }
  out += "  level  epsilon       boxes\n";
  for (const ifs::BoxCount& c : r.counts) {
    std::snprintf(line, sizeof line, "  %5d  %-12.6g  %zu%s\n", c.level, c.epsilon, c.boxes,
                  c.level >= r.min_level && c.level <= r.max_level ? "  *" : "");
    out += line;
  }
  return out;
}

std::string gallery(const std::filesystem::path& out, const std::filesystem::path& examples) {
  // Every experiment of examples/experiments, in name order; each writes its own outputs.
  std::vector<std::filesystem::path> files;
  const std::filesystem::path folder = examples / "experiments";
  if (!std::filesystem::is_directory(folder)) throw IoError(folder.string() + ": no such folder");
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw IoError(out.string() + ": cannot create the folder (" + ec.message() + ")");
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::string summary;
  experiment::RunOptions ro;
  ro.out_dir = out;
  ro.quiet = true;
  for (const auto& file : files) summary += experiment::run(io::read_experiment(file), ro).summary;
  // The seeds' subdivision schemes: shapes, degree overlays, algorithms compared.
  summary += write_scheme_gallery(out / "schemes", examples);
  return summary;
}

}  // namespace cifs::cli
