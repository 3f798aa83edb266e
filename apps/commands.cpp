// SPDX-License-Identifier: MIT
#include "commands.hpp"
#include "world.hpp"

#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <variant>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/experiment/dimension.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/io/bcifs_file.hpp"
#include "cifs/io/cad.hpp"
#include "cifs/io/html.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/svg.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/render/progress.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/rules.hpp"
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

/// The volume of a volume file (a .json that io::is_volume_json says holds one), or nothing: volumes are
/// not Shapes, so the commands that take them (info, eval) ask first.
std::optional<nurbs::Volume> read_volume(const std::filesystem::path& path, const ShapeSelection& select) {
  if (path.extension() != ".json") return std::nullopt;
  const std::string text = read_file(path);
  if (!io::is_volume_json(text)) return std::nullopt;
  if (select.ignore_trim)
    throw InvalidInput(path.string() + ": --ignore-trim applies to surfaces, not volumes");
  return io::parse_volume_json(text, path.string(),
                               {.ignore_trim = false, .index = select.index, .warn = {}});
}

/// Standard output as a sink: the bytes go out as they come, so a pipe or a redirected file takes
/// any number of points in the memory of a chunk; a failed write stops the command at once.
class StdoutSink final : public ByteSink {
 public:
  void write(std::string_view bytes) override {
    errno = 0;
    std::cout.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!std::cout.good()) {
      const int error = errno;
      throw StdoutError(std::string("cannot write to standard output") + (error != 0 ? ": " : "") +
                        (error != 0 ? std::strerror(error) : ""));
    }
  }
};

/// Standard output redirected to a regular file is held to the free disk space as `-o FILE` is, before
/// any work (depth 40 must not run for hours into ENOSPC); a pipe or a terminal takes what it reads.
/// Text formats are held to a lower bound of their size (a digit and a separator per coordinate).
void check_stdout_space(const std::string& format, std::uint64_t count, Eigen::Index dim) {
  struct stat st {};
  if (fstat(STDOUT_FILENO, &st) != 0 || !S_ISREG(st.st_mode)) return;
  std::error_code ec;
  const std::filesystem::path target = std::filesystem::read_symlink("/proc/self/fd/1", ec);
  if (ec) return;
  const std::optional<std::uint64_t> size = io::points_file_size(format, count, dim);
  const double bytes =
      size ? static_cast<double>(*size)
           : static_cast<double>(count) * 2.0 * static_cast<double>(std::max<Eigen::Index>(dim, 1));
  check_disk_space(target, static_cast<std::uint64_t>(std::min(bytes, 1.8e19)), !size);
}

/// Where a command's points go: a file written as they come (PointsFile: its format from the extension,
/// a chunk in memory), or standard output, also as they come (a PointsWriter on StdoutSink).
class PointsOutput {
 public:
  PointsOutput(const std::filesystem::path& output, const std::string& format, std::uint64_t count,
               Eigen::Index dim, const io::PointsStyle& style, const std::string& label, bool quiet)
      : count_(count), bar_(label, quiet || output.empty()) {
    if (output.empty()) {
      check_stdout_space(format, count, dim);
      text_.emplace(stdout_, format, count, dim, style);
    } else
      file_.emplace(output, count, dim, style);
  }
  /// Homogeneous rows `(w·x, w)` when `rational`: written as their Cartesian points.
  void write(const Eigen::Ref<const Points>& rows, bool rational) {
    if (rational)
      write(ifs::cartesian(rows));
    else
      write(rows);
  }
  void write(const Eigen::Ref<const Points>& rows) {
    if (file_)
      file_->write(rows);
    else
      text_->write(rows);
    done_ += static_cast<std::uint64_t>(rows.rows());
    bar_(done_, count_);
  }
  /// Nothing more for stdout (the points are out), or a line that says what was written.
  std::string finish(const std::filesystem::path& output, const std::string& note = "") {
    if (!file_) {
      text_->finish();
      return {};
    }
    file_->commit();
    return "wrote " + output.string() + ": " + std::to_string(count_) + " points" + note + "\n";
  }

 private:
  std::uint64_t count_, done_ = 0;
  render::ProgressBar bar_;
  StdoutSink stdout_;
  std::optional<io::PointsWriter> text_;
  std::optional<io::PointsFile> file_;
};

/// Points produced a chunk at a time: `rows(first, n)` gives rows first … first + n − 1 of `count`.
template <class Rows>
void write_in_chunks(PointsOutput& out, std::int64_t count, std::int64_t chunk, Rows&& rows) {
  for (std::int64_t first = 0; first < count; first += chunk)
    out.write(rows(first, std::min(chunk, count - first)));
}

/// The shape's own refusals of what the user gave (a parameter or a knot outside its domain) name its
/// file: `cifs: <where>: <what>`.
template <class Work>
auto naming_shape(const std::filesystem::path& shape, Work&& work) {
  try {
    return work();
  } catch (const InvalidInput& e) {
    throw InvalidInput(shape.string() + ": " + e.what());
  }
}

/// Rows per chunk of a streamed output (a file or stdout).
constexpr std::int64_t kChunkPoints = std::int64_t{1} << 16;

std::string eval_curve(const nurbs::Curve& c, const EvalOptions& o) {
  std::vector<double> at;
  for (const std::string& a : o.at) {
    if (a.find(',') != std::string::npos)
      throw InvalidInput("--at '" + a + "': a curve takes one parameter U");
    at.push_back(parse_number(a, "--at"));
  }
  // Checks the parameters before any file is created.
  const Points first = naming_shape(o.shape, [&] { return nurbs::evaluate(c, at); });
  const nurbs::Domain dom = nurbs::domain(c);
  PointsOutput out(o.output, "json", static_cast<std::uint64_t>(first.rows() + o.samples), first.cols(), {},
                   "eval", o.quiet);
  out.write(first);
  write_in_chunks(out, o.samples, kChunkPoints, [&](std::int64_t i, std::int64_t n) {
    return nurbs::evaluate(
        c, nurbs::uniform_parameters(dom, o.samples, static_cast<int>(i), static_cast<int>(n)));
  });
  return out.finish(o.output);
}

std::string eval_surface(const nurbs::Surface& s, const EvalOptions& o) {
  Points first(static_cast<Eigen::Index>(o.at.size()), nurbs::dimension(s));
  for (std::size_t i = 0; i < o.at.size(); ++i) {
    const std::string& a = o.at[i];
    const auto comma = a.find(',');
    if (comma == std::string::npos) throw InvalidInput("--at '" + a + "': a surface takes U,V");
    const double u = parse_number(std::string_view(a).substr(0, comma), "--at");
    const double v = parse_number(std::string_view(a).substr(comma + 1), "--at");
    first.row(static_cast<Eigen::Index>(i)) = naming_shape(o.shape, [&] { return nurbs::evaluate(s, u, v); });
  }
  const auto n = static_cast<std::int64_t>(o.samples);
  // The output is checked (free space, formats) before any parameter is made.
  PointsOutput out(o.output, "json", static_cast<std::uint64_t>(first.rows() + n * n), first.cols(), {},
                   "eval", o.quiet);
  out.write(first);
  const auto u_domain = nurbs::domain(s, nurbs::Direction::u);
  const auto v_domain = nurbs::domain(s, nurbs::Direction::v);
  // Row a·N + b at (u_a, v_b), a chunk of at most kChunkPoints points at a time: whole grid rows while
  // a row fits a chunk, else pieces of one row, so that memory stays bounded whatever N.
  Points grid;  // one chunk, its storage reused from chunk to chunk
  if (n <= kChunkPoints) {
    const auto vs = nurbs::uniform_parameters(v_domain, o.samples);
    write_in_chunks(
        out, n, std::max<std::int64_t>(kChunkPoints / std::max<std::int64_t>(n, 1), 1),
        [&](std::int64_t a, std::int64_t k) -> const Points& {
          nurbs::evaluate_grid(
              s, nurbs::uniform_parameters(u_domain, o.samples, static_cast<int>(a), static_cast<int>(k)), vs,
              grid);
          return grid;
        });
  } else {
    for (std::int64_t a = 0; a < n; ++a) {
      const auto u = nurbs::uniform_parameters(u_domain, o.samples, static_cast<int>(a), 1);
      write_in_chunks(out, n, kChunkPoints, [&](std::int64_t b, std::int64_t k) -> const Points& {
        nurbs::evaluate_grid(
            s, u, nurbs::uniform_parameters(v_domain, o.samples, static_cast<int>(b), static_cast<int>(k)),
            grid);
        return grid;
      });
    }
  }
  return out.finish(o.output);
}

std::string eval_volume(const nurbs::Volume& vol, const EvalOptions& o) {
  Points first(static_cast<Eigen::Index>(o.at.size()), nurbs::dimension(vol));
  for (std::size_t i = 0; i < o.at.size(); ++i) {
    const std::string& a = o.at[i];
    const auto c1 = a.find(',');
    const auto c2 = c1 == std::string::npos ? c1 : a.find(',', c1 + 1);
    if (c2 == std::string::npos || a.find(',', c2 + 1) != std::string::npos)
      throw InvalidInput("--at '" + a + "': a volume takes U,V,W");
    const std::string_view text(a);
    const double u = parse_number(text.substr(0, c1), "--at");
    const double v = parse_number(text.substr(c1 + 1, c2 - c1 - 1), "--at");
    const double w = parse_number(text.substr(c2 + 1), "--at");
    first.row(static_cast<Eigen::Index>(i)) =
        naming_shape(o.shape, [&] { return nurbs::evaluate(vol, u, v, w); });
  }
  const auto n = static_cast<std::int64_t>(o.samples);
  if (n > (std::int64_t{1} << 20))  // N³ points would not fit a count, let alone a disk
    throw InvalidInput("--samples " + std::to_string(n) + ": a volume's N×N×N grid takes N ≤ 1048576");
  PointsOutput out(o.output, "json", static_cast<std::uint64_t>(first.rows() + n * n * n), first.cols(), {},
                   "eval", o.quiet);
  out.write(first);
  std::array<nurbs::Domain, 3> dom{};
  for (std::size_t d = 0; d < 3; ++d) dom[d] = nurbs::domain(vol.knots[d], vol.degree[d]);
  // Row (a·N + b)·N + c at (u_a, v_b, w_c): for each u, pieces of whole v rows of N points (at least one row
  // a chunk), so that memory stays bounded whatever N.
  const auto ws = nurbs::uniform_parameters(dom[2], o.samples);
  const std::int64_t rows = std::max<std::int64_t>(kChunkPoints / std::max<std::int64_t>(n, 1), 1);
  for (std::int64_t a = 0; a < n; ++a) {
    const auto u = nurbs::uniform_parameters(dom[0], o.samples, static_cast<int>(a), 1);
    for (std::int64_t b = 0; b < n; b += rows) {
      const std::int64_t k = std::min(rows, n - b);
      out.write(nurbs::evaluate_grid(
          vol, u, nurbs::uniform_parameters(dom[1], o.samples, static_cast<int>(b), static_cast<int>(k)),
          ws));
    }
  }
  return out.finish(o.output);
}

}  // namespace

std::string eval(const EvalOptions& o) {
  if (o.samples < 0) throw InvalidInput("--samples " + std::to_string(o.samples) + ": must be non-negative");
  if (o.at.empty() && o.samples == 0) throw InvalidInput("eval: give --at U (repeatable) or --samples N");
  if (!o.output.empty()) io::format_of(o.output, io::Content::points);  // refused before any work
  if (const auto vol = read_volume(o.shape, o.select)) return eval_volume(*vol, o);
  const io::Shape shape = read_shape(o.shape, o.select);
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) return eval_curve(*c, o);
  return eval_surface(std::get<nurbs::Surface>(shape), o);
}

std::string insert(const InsertOptions& o) {
  if (o.dir != "u" && o.dir != "v") throw InvalidInput("--dir '" + o.dir + "': expected u or v");
  if (o.knots.empty() && !o.midpoints)
    throw InvalidInput("insert: give --knot U (repeatable) or --midpoints");
  for (const double u : o.knots)
    if (!std::isfinite(u)) throw InvalidInput("--knot: a knot is not a finite number");
  const io::Shape shape = read_shape(o.shape, o.select);
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    if (o.dir != "u") throw InvalidInput("--dir v: a curve has one direction");
    nurbs::Curve out = naming_shape(o.shape, [&] { return nurbs::refine(*c, o.knots); });
    if (o.midpoints) out = nurbs::refine_midpoints(out);
    return io::to_json(out);
  }
  const auto dir = o.dir == "u" ? nurbs::Direction::u : nurbs::Direction::v;
  nurbs::Surface out =
      naming_shape(o.shape, [&] { return nurbs::refine(std::get<nurbs::Surface>(shape), dir, o.knots); });
  if (o.midpoints) out = nurbs::refine_midpoints(out);
  return io::to_json(out);
}

std::string convert(const ConvertOptions& o) {
  io::format_of(o.output, io::Content::shape);  // refuse the extension before the work
  const bool cad = io::cad_format(o.output).has_value();
  if (cad) io::cad_codec(o.output.string());  // "built without OpenCASCADE" before reading
  const std::vector<io::Shape> shapes = read_shapes(o.input, o.select, !cad);
  if (cad)
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const int dim = std::visit([](const auto& s) { return nurbs::dimension(s); }, shapes[i]);
      if (dim < 3)
        pending_warnings().push_back(o.output.string() + ": shape " + std::to_string(i) + " is " +
                                     std::to_string(dim) + "-D: written with its missing coordinates 0");
    }
  io::write(o.output, std::span<const io::Shape>(shapes));
  return "";
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

namespace {

/// Points, dimension, closed, edges, length and bounds of a control polygon.
std::string polygon_info(const std::filesystem::path& path) {
  const io::Polygon p = io::read_polygon(path);
  const Eigen::Index n = p.points.rows();
  const Eigen::Index edges = p.closed ? (n > 1 ? n : 0) : n - 1;
  double length = 0;
  for (Eigen::Index i = 0; i < edges; ++i) length += (p.points.row((i + 1) % n) - p.points.row(i)).norm();
  const Eigen::RowVectorXd lo = p.points.colwise().minCoeff(), hi = p.points.colwise().maxCoeff();
  json bounds = json::array();
  for (Eigen::Index k = 0; k < p.points.cols(); ++k) bounds.push_back({lo(k), hi(k)});
  return json{{"type", "polygon"},  {"points", n},    {"dimension", p.points.cols()},
              {"closed", p.closed}, {"edges", edges}, {"length", length},
              {"bounds", bounds}}
             .dump(1) +
         "\n";
}

}  // namespace

/// A BC-IFS file: its cells by dimension, transitions (free ones), boundaries, constraints and nets.
std::string bcifs_info(const std::filesystem::path& path) {
  const io::BcifsFile file = io::read_bcifs(path);
  const auto& g = file.system.automaton.graph;
  std::array<int, 3> cells{};
  for (const int d : file.system.dimension)
    ++cells.at(static_cast<std::size_t>(d));  // every cell, boundaries too
  return json{{"type", "bcifs"},
              {"cells", {{"vertices", cells[0]}, {"edges", cells[1]}, {"faces", cells[2]}}},
              {"transitions", num_edges(g)},
              {"free_transitions", file.system.free.size()},
              {"boundaries", file.system.boundaries.size()},
              {"constraints", file.system.constraints.size()},
              {"initial", file.system.automaton.initial.size()},
              {"dimension", file.nets.empty() ? 0 : file.nets.front().cols()}}
             .dump(1) +
         "\n";
}

/// An experiment file, read as cifs render reads it (its inputs too): its source, evaluation, perturbation
/// and outputs (what cifs view saves is read back by this).
std::string experiment_info(const std::filesystem::path& path) {
  const io::Experiment e = io::read_experiment(path);
  json source;
  if (e.shape) {
    source = {{"type", std::holds_alternative<nurbs::Curve>(*e.shape) ? "curve" : "surface"}};
  } else if (!e.automaton.empty()) {
    source = {{"type", "bcifs"}, {"file", e.automaton.filename().string()}};
  } else if (e.mesh) {
    source = {{"type", "mesh"},
              {"file", e.mesh->path.filename().string()},
              {"scheme", subdivision::scheme_name(e.mesh->scheme)},
              {"levels", e.mesh->levels},
              {"limit", e.mesh->limit}};
  } else if (e.junction) {
    source = {{"type", "junction"}, {"a", e.junction->a.boundary}, {"b", e.junction->b.boundary}};
  } else {
    source = {{"type", "ifs"}, {"maps", e.ifs->name.empty() ? json(e.ifs->maps.size()) : json(e.ifs->name)}};
  }
  json out = {{"type", "experiment"}, {"name", e.name}, {"source", source}};
  if (!e.mesh) {
    const io::EvaluationSpec& v = e.evaluation;
    out["evaluation"] = v.mode == io::EvaluationSpec::Mode::depth ? json{{"depth", v.depth}}
                        : v.mode == io::EvaluationSpec::Mode::tolerance
                            ? json{{"relative_piece_size", v.tolerance}}
                            : json{{"chaos", v.samples}};
  }
  if (e.perturbation)
    out["perturbation"] = {{"amplitude", e.perturbation->amplitude},
                           {"seed", e.perturbation->seed},
                           {"values", e.perturbation->values.size()},
                           {"fractal_curves", e.perturbation->fractal_curves.has_value()}};
  json outputs = json::array();
  if (!e.outputs.exr.empty()) outputs.push_back("exr");
  if (!e.outputs.png.empty()) outputs.push_back("png");
  for (const auto& [format, file] : e.outputs.geometry) outputs.push_back(format);
  for (const auto& [format, file] : e.outputs.automaton) outputs.push_back("automaton_" + format);
  out["outputs"] = outputs;
  return out.dump(1) + "\n";
}

std::string info(const std::filesystem::path& path, const ShapeSelection& select,
                 const io::MeshReadOptions& mesh) {
  const io::Content content = io::detect(path);
  if (content == io::Content::mesh) return mesh_info(path, mesh);
  if (content == io::Content::experiment) {
    if (select.index || select.ignore_trim)
      throw InvalidInput(path.string() + ": --index and --ignore-trim apply to shape files, not experiments");
    return experiment_info(path);
  }
  if (content == io::Content::bcifs) {
    if (select.index || select.ignore_trim)
      throw InvalidInput(path.string() +
                         ": --index and --ignore-trim apply to shape files, not BC-IFS files");
    return bcifs_info(path);
  }
  if (content == io::Content::polygon) {
    if (select.index || select.ignore_trim)
      throw InvalidInput(path.string() + ": --index and --ignore-trim apply to shape files, not polygons");
    return polygon_info(path);
  }
  if (const auto vol = read_volume(path, select)) {
    json domains = json::array(), segments = json::array(), knots = json::array();
    for (std::size_t d = 0; d < 3; ++d) {
      const nurbs::Domain dom = nurbs::domain(vol->knots[d], vol->degree[d]);
      domains.push_back({dom.start, dom.end});
      segments.push_back(nurbs::breakpoints(vol->knots[d], vol->degree[d]).size() - 1);
      knots.push_back(vol->knots[d].size());
    }
    return json{{"type", "volume"},
                {"degree", vol->degree},
                {"dimension", nurbs::dimension(*vol)},
                {"control_points", vol->count},
                {"knots", knots},
                {"rational", vol->rational},
                {"domain", domains},
                {"segments", segments}}
               .dump(1) +
           "\n";
  }
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
  // The format: -o's extension, else --format (default json); the output checked before any work.
  std::string format = o.format.empty() ? "json" : o.format;
  std::optional<AtomicFile> output;
  if (!o.output.empty()) {
    format = io::format_of(o.output, io::Content::automaton).name;
    if (!o.format.empty() && o.format != format)
      throw InvalidInput("--format " + o.format + ": -o " + o.output.string() + " names " + format);
  }
  io::writable_format(io::Content::automaton, format, "--format");
  if (!o.output.empty()) output.emplace(o.output, OutputOptions{.inputs = {o.shape}});
  nurbs::KnotAutomaton a;
  if (io::detect(o.shape) == io::Content::mesh) {
    // A mesh: the surface automaton of its scheme (subdivision/limit.hpp), after `levels` steps.
    if (o.scheme.empty())
      throw InvalidInput(o.shape.string() +
                         " is a mesh: give --scheme catmull-clark or loop (its surface automaton)");
    if (o.minimize || o.select.index || o.select.ignore_trim)
      throw InvalidInput(std::string(o.minimize       ? "--minimize"
                                     : o.select.index ? "--index"
                                                      : "--ignore-trim") +
                         " applies to shapes, not to a mesh's surface automaton");
    if (o.levels < 0 || o.levels > 8)
      throw InvalidInput("--levels " + std::to_string(o.levels) + ": expected 0 to 8");
    const subdivision::MeshScheme scheme = subdivision::named_mesh_scheme(o.scheme);
    Mesh mesh = io::read_mesh(o.shape);
    if (o.levels > 0) mesh = subdivision::subdivide(mesh, scheme, o.levels);
    try {
      a = nurbs::without_knots(subdivision::surface_automaton(mesh, scheme).automaton);
    } catch (const InvalidInput& e) {
      // Faces with several extraordinary corners or more than four part after a step: say it in the CLI's
      // words.
      std::string what = e.what();
      const std::string library = "(refine one level first)";
      if (const auto at = what.find(library); at != std::string::npos)
        throw InvalidInput(what.replace(at, library.size(), "(--levels 1 refines them apart)"));
      throw;
    }
  } else {
    if (!o.scheme.empty() || o.levels != 0)
      throw InvalidInput(std::string(o.scheme.empty() ? "--levels" : "--scheme") + " applies to meshes; " +
                         o.shape.string() + " is a shape");
    const io::Shape shape = read_shape(o.shape, o.select);
    // Curves: the knot-doubling automaton; surfaces: the tensor product of their two direction curves'.
    const auto* c = std::get_if<nurbs::Curve>(&shape);
    a = c ? nurbs::knot_automaton(*c)
          : nurbs::without_knots(nurbs::tensor_automaton(std::get<nurbs::Surface>(shape)).product);
    if (o.minimize) a = nurbs::minimize(a);
  }
  if (!output) return io::encode(a, format);
  io::encode(a, format, *output);
  output->commit();
  return "wrote " + o.output.string() + ": " + std::to_string(num_vertices(a.automaton.graph)) + " states, " +
         std::to_string(a.automaton.initial.size()) + " initial entries\n";
}

namespace {

/// The attractor's format: -o's extension, else --format (default json); a point-set format, or svg
/// (the polyline, drawn from memory: it is fitted to the bounds of all the points).
std::string attractor_format(const AttractorOptions& o) {
  std::vector<std::string> names;
  for (const io::Format& f : io::formats(io::Content::points)) names.emplace_back(f.name);
  names.emplace_back("svg");
  const auto listing = [&](bool extensions) {
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i)
      out += std::string(i == 0                  ? ""
                         : i + 1 == names.size() ? " or "
                                                 : ", ") +
             (extensions ? "." : "") + names[i];
    return out;
  };
  std::string format = o.format.empty() ? "json" : o.format;
  if (!o.output.empty()) {
    const std::string extension = extension_of(o.output);
    if (extension.size() < 2 || std::find(names.begin(), names.end(), extension.substr(1)) == names.end())
      throw InvalidInput("-o " + o.output.string() + ": expected a " + listing(true) + " file name");
    if (!o.format.empty() && o.format != extension.substr(1))
      throw InvalidInput("--format " + o.format + ": -o " + o.output.string() + " names " +
                         extension.substr(1));
    format = extension.substr(1);
  }
  if (std::find(names.begin(), names.end(), format) == names.end())
    throw InvalidInput("--format '" + format + "': expected " + listing(false));
  return format;
}

/// Points held in memory before they are written (stdout, svg): refused above this.
constexpr std::size_t kMemoryBytes = std::size_t{1} << 30;
/// The chaos game's points, held in memory: kMaxPoints of up to 4 doubles (a rational 3-D shape), so
/// that every --chaos up to kMaxPoints runs (5·10^7 on a 3-D curve was refused at 1 GiB).
constexpr std::size_t kChaosBytes = static_cast<std::size_t>(kMaxPoints) * 4 * sizeof(double);
/// Points a tolerance traversal may stream to a file (two walks of about 1 µs per point each).
constexpr double kMaxTolerancePoints = 1U << 30;

/// Points computed whole (chaos game, stdout, svg): moved into the output, never copied.
std::string write_whole(Points&& P, const io::PointsStyle& style, const std::string& format,
                        const AttractorOptions& o) {
  const auto count = P.rows();
  if (format == "svg") {
    if (std::string w = io::svg_dropped_coordinates(P); !w.empty())
      pending_warnings().push_back(std::move(w));
    const io::Polygon polygon{std::move(P), style.closed};
    if (o.output.empty()) return io::encode(polygon, "svg");
    io::write(o.output, polygon);
  } else {
    const io::PointSet set{std::move(P), style};
    if (o.output.empty()) return io::encode(set, format);
    io::write(o.output, set);
  }
  return "wrote " + o.output.string() + ": " + std::to_string(count) + " points" +
         (style.seed ? " (seed " + std::to_string(*style.seed) + ")" : "") + "\n";
}

/// A surface's attractor (its tensor-product automaton): at a depth the watertight quad mesh, as
/// its grid of vertices (json, npy: u-major, (A·2^K + 1) × (B·2^K + 1)) or the mesh itself (obj, ply);
/// to a tolerance one attractor point per proven piece, and the chaos game, as unordered points.
std::string surface_attractor(const nurbs::Surface& s, const std::string& format, const AttractorOptions& o) {
  if (format == "svg")
    throw InvalidInput("--format svg draws curves; a surface's attractor is json, npy, ply or obj");
  if (o.deviation > 0)
    throw InvalidInput(
        "--deviation bounds a curve's polyline; for a surface give --depth K (its quad mesh) or "
        "--piece-size E");
  if (o.depth < 0 && format == "obj")
    throw InvalidInput(
        "obj: a surface's points are unordered with --piece-size and --chaos, use json, npy or ply");
  const nurbs::TensorAutomaton ta = nurbs::tensor_automaton(s);
  const std::vector<Points> nets = nurbs::initial_nets(ta, s);
  const Eigen::Index dim = nurbs::dimension(s);
  const io::PointsStyle cloud{.polyline = false, .closed = false, .seed = {}};

  if (o.depth >= 0) {
    // The mesh is built in memory (each node computed once, neighbours shared); its file is encoded a
    // chunk at a time.
    render::Stage stage("surface mesh", o.quiet);
    const Mesh mesh =
        ifs::surface_mesh(ta, nets, o.depth, {.homogeneous = s.rational, .max_bytes = kMemoryBytes});
    const auto count = static_cast<std::uint64_t>(mesh.vertices.rows());
    const std::size_t quads = face_count(mesh);
    if (format == "json" || format == "npy") {
      PointsOutput out(o.output, format, count, dim, cloud, "attractor", o.quiet);
      out.write(mesh.vertices);
      return out.finish(o.output, " (the " + std::to_string(quads) + " quads' grid, u-major)");
    }
    if (o.output.empty()) return io::encode(mesh, format);
    io::write(o.output, mesh);
    return "wrote " + o.output.string() + ": " + std::to_string(count) + " vertices, " +
           std::to_string(quads) + " quads\n";
  }

  if (o.chaos != 0) {
    ifs::ChaosOptions options;
    options.samples = static_cast<std::size_t>(o.chaos);
    options.seed = o.seed;
    options.max_bytes = kChaosBytes;
    ifs::ChaosResult r = ifs::chaos_game(ta.product, nets, options);
    if (s.rational) r.points = ifs::cartesian(r.points);
    return write_whole(std::move(r.points), {.polyline = false, .closed = false, .seed = r.seed}, format, o);
  }

  // One attractor point per piece, every piece proven smaller than the tolerance (Cartesian).
  ifs::ToleranceSampleOptions so;
  so.epsilon = o.piece_size;
  so.homogeneous = s.rational;
  so.max_points = kMemoryBytes / (sizeof(double) * static_cast<std::size_t>(nets.front().cols()));
  so.tolerance_name = "--piece-size";
  ifs::ToleranceSample sample = ifs::tolerance_sample(ta.product, nets, so);
  return write_whole(std::move(sample.points), cloud, format, o);
}

}  // namespace

std::string attractor(const AttractorOptions& o) {
  // The attractor is a polyline (in curve order) written as a point set, or drawn as SVG.
  const std::string format = attractor_format(o);
  if (o.piece_size < 0 || !std::isfinite(o.piece_size))
    throw InvalidInput("--piece-size: must be a positive number");
  if (o.deviation < 0 || !std::isfinite(o.deviation))
    throw InvalidInput("--deviation: must be a positive number");
  if ((o.depth >= 0) + (o.piece_size > 0) + (o.deviation > 0) + (o.chaos != 0) != 1)
    throw InvalidInput(
        "attractor: give exactly one of --depth K, --piece-size E, --deviation D and --chaos N");
  if (o.chaos < 0 || o.chaos > kMaxPoints)
    throw InvalidInput("--chaos " + std::to_string(o.chaos) + ": expected 1 to " +
                       std::to_string(kMaxPoints) + " points");
  if (o.chaos != 0 && (format == "obj" || format == "svg"))
    throw InvalidInput("--chaos: the points are unordered, use json, npy or ply");
  const io::Shape shape = read_shape(o.shape, o.select);
  const auto* c = std::get_if<nurbs::Curve>(&shape);
  if (!c) return surface_attractor(std::get<nurbs::Surface>(shape), format, o);
  const nurbs::KnotAutomaton knots = nurbs::knot_automaton(*c);
  const automata::Automaton& a = knots.automaton;
  const std::vector<Points> nets = nurbs::initial_nets(knots, *c);
  const Eigen::Index dim = nurbs::dimension(*c);
  // Streamed: the points go to the file or stdout a chunk at a time, as they are computed; SVG is
  // drawn whole.
  const bool streamed = format != "svg";
  io::PointsStyle style{.polyline = true, .closed = c->closed, .seed = {}};

  if (o.chaos != 0) {
    ifs::ChaosOptions options;
    options.samples = static_cast<std::size_t>(o.chaos);
    options.seed = o.seed;
    options.max_bytes = kChaosBytes;
    ifs::ChaosResult r = ifs::chaos_game(a, nets, options);
    if (c->rational) r.points = ifs::cartesian(r.points);
    style = {.polyline = false, .closed = false, .seed = r.seed};
    return write_whole(std::move(r.points), style, format, o);
  }

  if (o.depth >= 0) {
    ifs::PointsOptions options;
    options.closed = c->closed;
    const std::size_t count = ifs::attractor_point_count(a, o.depth, c->closed);
    if (streamed) {
      PointsOutput out(o.output, format, count, dim, style, "attractor", o.quiet);
      ifs::for_each_attractor_chunk(a, nets, o.depth, options,
                                    [&](const Eigen::Ref<const Points>& H) { out.write(H, c->rational); });
      return out.finish(o.output);
    }
    const double bytes = static_cast<double>(count) * static_cast<double>(nets[0].cols()) * sizeof(double);
    if (bytes > static_cast<double>(kMemoryBytes))
      throw InvalidInput(
          "attractor: depth " + std::to_string(o.depth) + " gives " + std::to_string(count) + " points (" +
          number_text(bytes / static_cast<double>(kMemoryBytes), 3) +
          " GiB), more than the 1 GiB held in memory for SVG; write them as points (json, npy, ply, obj), "
          "which are streamed");
    options.max_bytes = kMemoryBytes;
    Points H = ifs::attractor_points(a, nets, o.depth, options);
    if (c->rational) H = ifs::cartesian(H);
    return write_whole(std::move(H), style, format, o);
  }

  // Leaves whose whole piece is proven below the tolerance, or within the deviation of its chord
  // (Cartesian for rational curves), in curve order; refused before the work when memory (stdout,
  // SVG) or a streamed file cannot take them. A first walk counts the leaves (the files' headers
  // name the count), the second writes.
  const double row_bytes = static_cast<double>(dim) * sizeof(double);
  const bool chordal = o.deviation > 0;
  const ifs::SampleOptions so{
      .tolerance = chordal ? o.deviation : o.piece_size,
      .chordal = chordal,
      .homogeneous = c->rational,
      .closed = c->closed,
      .max_depth = 40,
      .max_points = static_cast<std::size_t>(streamed ? kMaxTolerancePoints
                                                      : static_cast<double>(kMemoryBytes) / row_bytes),
      .tolerance_name = chordal ? "--deviation" : "--piece-size",
      .limit_hint = streamed ? " streamed; give a larger bound"
                             : " held in memory for SVG; give a larger bound, or write them as points "
                               "(json, npy, ply, obj), which are streamed"};
  if (!streamed) return write_whole(ifs::sample_attractor(a, nets, so).points, style, format, o);
  std::optional<PointsOutput> out;
  ifs::for_each_sample_chunk(
      a, nets, so, static_cast<std::size_t>(kChunkPoints),
      [&](std::size_t count, int) { out.emplace(o.output, format, count, dim, style, "attractor", o.quiet); },
      [&](const Eigen::Ref<const Points>& rows, std::span<const std::uint32_t>) { out->write(rows); });
  return out->finish(o.output);
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
  const verify::SurfaceCheckReport r =
      verify::check_surface(s, {.depth = o.depth, .tolerance = o.relative_tolerance});
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
  const verify::CheckReport r =
      verify::check_curve(*c, {.depth = o.depth, .tolerance = o.relative_tolerance});
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

std::size_t memory_size(const std::string& text) {
  const auto bad = [&] {
    return InvalidInput("--max-memory '" + text +
                        "': expected a size such as 4G, 3000M or 2.5G (bytes: K, M, G, T)");
  };
  if (text.empty()) throw bad();
  const char last = static_cast<char>(std::toupper(static_cast<unsigned char>(text.back())));
  const std::string units = "KMGT";
  const auto unit = units.find(last);
  const std::string digits = unit == std::string::npos ? text : text.substr(0, text.size() - 1);
  double x = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), x);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() || !(x > 0)) throw bad();
  if (unit != std::string::npos) x *= std::pow(1024.0, static_cast<double>(unit + 1));
  if (x < 1 || x > 1e18) throw bad();
  return static_cast<std::size_t>(x);
}

std::string render(const RenderOptions& o) {
  if (o.experiments.size() > 1 && (!o.exr.empty() || !o.png.empty()))
    throw InvalidInput("render: -o and --png name the image of one experiment; with " +
                       std::to_string(o.experiments.size()) +
                       " experiments the files' own outputs go to --out-dir");
  // Every file is read (and refused) before the first one runs.
  std::vector<io::Experiment> experiments;
  for (const auto& path : o.experiments) experiments.push_back(io::read_as_experiment(path));
  experiment::RunOptions ro;
  ro.exr = o.exr;
  ro.png = o.png;
  ro.out_dir = !o.out_dir.empty() ? o.out_dir : o.exr.has_parent_path() ? o.exr.parent_path() : ".";
  ro.threads = o.threads;
  // Under mpirun: this process's part, the reduction, and one progress bar (rank 0's).
  const World& w = world();
  ro.quiet = o.quiet || w.rank != 0;
  if (w.size > 1) {
    ro.part = {w.rank, w.size};
    ro.combine = combine_world;
  }
  if (!o.max_memory.empty()) ro.max_bytes = memory_size(o.max_memory);
  std::string summary;
  for (const io::Experiment& e : experiments) {
    experiment::RunReport report = experiment::run(e, ro);
    summary += report.summary;
    for (std::string& warning : report.warnings) pending_warnings().push_back(std::move(warning));
  }
  return summary;
}

namespace {}  // namespace

namespace {

/// The input as an experiment: a shape file (io::detect) is measured as an experiment of its shape, a
/// BC-IFS file as that of its automaton.
io::Experiment dimension_input(const DimensionOptions& o) {
  const io::Content content = io::detect(o.input);
  if (content == io::Content::bcifs && !o.select.index && !o.select.ignore_trim)
    return io::read_as_experiment(o.input);
  const bool shape = content != io::Content::experiment;
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
  return e;
}

std::string dimension_json(const DimensionOptions& o, const experiment::DimensionMeasurement& m) {
  const experiment::Evaluation& ev = m.sample;
  const std::string& fallback = m.fallback;
  const ifs::BoxCountingResult& r = m.fit;
  json j;
  j["input"] = o.input.string();
  j["kind"] = ev.kind;
  j["mode"] = m.route == "tolerance" ? "tolerance" : m.route == "chaos" ? "chaos" : "depth";
  j["route"] = m.description;
  j["depth"] = ev.depth;
  j["points"] = ev.points.rows();
  j["resolution"] = m.resolution;
  j["resolution_estimated"] = m.estimated;
  j["relaxed"] = m.relaxed;
  if (!fallback.empty()) j["fallback_reason"] = fallback;
  json box;
  box["dimension"] = r.dimension;
  box["uncertainty"] = m.uncertainty;
  box["standard_error"] = r.standard_error;
  box["spread"] = r.spread;
  box["coarser_dimension"] = m.coarser ? json(*m.coarser) : json(nullptr);
  if (!m.coarser) box["coarser_note"] = m.coarser_note;
  box["levels"] = {r.min_level, r.max_level};
  box["epsilon"] = {r.max_epsilon, r.min_epsilon};
  box["r_squared"] = r.r_squared;
  box["residual"] = r.residual;
  box["size"] = r.size;
  box["range"] = {m.range[0], m.range[1]};
  json counts = json::array();
  for (const ifs::BoxCount& c : r.counts)
    counts.push_back({{"level", c.level}, {"epsilon", c.epsilon}, {"boxes", c.boxes}});
  box["counts"] = counts;
  j["box_counting"] = box;
  if (m.cover)
    j["cover"] = {{"dimension", m.cover->dimension},
                  {"spread", m.cover->spread},
                  {"epsilon", {m.cover->max_epsilon, m.cover->min_epsilon}},
                  {"levels", m.cover->levels}};
  else
    j["cover"] = nullptr;
  j["similarity_dimension"] = m.similarity ? json(*m.similarity) : json(nullptr);
  if (!m.similarity) j["similarity_note"] = m.similarity_note;
  return j.dump(2) + "\n";
}

std::string dimension_text(const DimensionOptions& o, const experiment::DimensionMeasurement& m) {
  const experiment::Evaluation& ev = m.sample;
  const std::string& fallback = m.fallback;
  const ifs::BoxCountingResult& r = m.fit;
  std::string out = o.input.string() + ": " + ev.kind + ", " + std::to_string(ev.points.rows()) + " points\n";
  out += "route: " + m.description + "\n";
  if (!fallback.empty())
    out += m.route == "tolerance" ? "  (strict fit refused: " + fallback + ")\n"
                                  : "  (no proven tolerance sample: " + fallback + ")\n";
  char line[512];
  std::snprintf(
      line, sizeof line,
      "box-counting dimension %.4f ± %.2g (levels %d … %d, ε %.4g … %.4g, R² %.6f, max residual %.3g)\n",
      r.dimension, m.uncertainty, r.min_level, r.max_level, r.max_epsilon, r.min_epsilon, r.r_squared,
      r.residual);
  out += line;
  std::snprintf(
      line, sizeof line,
      "  uncertainty: the largest of the slope's standard error %.2g, the largest deviation %.2g of a "
      "local slope (consecutive levels) and ",
      r.standard_error, r.spread);
  out += line;
  out += m.coarser ? "the change " + number_text(std::abs(r.dimension - *m.coarser), 2) +
                         " from the coarser sample (" +
                         (m.route == "tolerance" ? "tolerance 2ε" : "depth − 1") + ")\n"
                   : "no coarser comparison (" + m.coarser_note + ")\n";
  for (const std::string& relaxed : m.relaxed) out += "  relaxed: " + relaxed + "\n";
  if (m.cover) {
    std::snprintf(line, sizeof line,
                  "proven cover: n(ε) pieces grow as ε^-%.4f (%d counts, ε %.4g … %.4g, local slopes within "
                  "%.2g): its limit bounds the dimension from above, and it has no boundary term\n",
                  m.cover->dimension, m.cover->levels, m.cover->max_epsilon, m.cover->min_epsilon,
                  m.cover->spread);
    out += line;
    if (m.cover->dimension > r.dimension + m.uncertainty) {
      std::snprintf(
          line, sizeof line,
          "  the boxes read %.2g below it at these scales (a boundary or shape term that vanishes as "
          "ε → 0): range %.4f … %.4f\n",
          m.cover->dimension - r.dimension, m.range[0], m.range[1]);
      out += line;
    }
  }
  if (m.similarity) {
    std::snprintf(line, sizeof line, "similarity dimension %.12g\n", *m.similarity);
    out += line;
  } else {
    out += "similarity dimension: not applicable (" + m.similarity_note + ")\n";
  }
  out += "  level  epsilon       boxes\n";
  for (const ifs::BoxCount& c : r.counts) {
    std::snprintf(line, sizeof line, "  %5d  %-12.6g  %zu%s\n", c.level, c.epsilon, c.boxes,
                  c.level >= r.min_level && c.level <= r.max_level ? "  *" : "");
    out += line;
  }
  return out;
}

}  // namespace

std::string dimension(const DimensionOptions& o) {
  const experiment::DimensionMeasurement m = experiment::measure_dimension(dimension_input(o), o.measure);
  return o.json ? dimension_json(o, m) : dimension_text(o, m);
}

namespace {

/// The gallery once its experiments are read and its folder made: every run, the schemes, the page.
std::string gallery_run(const std::filesystem::path& out, const std::filesystem::path& examples,
                        const std::vector<io::Experiment>& experiments,
                        const std::vector<std::filesystem::path>& files, bool quiet) {
  std::string summary;
  std::vector<io::GallerySection> sections;
  experiment::RunOptions ro;
  ro.out_dir = out;
  ro.quiet = true;  // one bar for the whole gallery, by experiments run
  render::ProgressBar bar("gallery", quiet);
  // The page links to what each run wrote, relative to `out` (the folder moves whole).
  const std::filesystem::path base = std::filesystem::weakly_canonical(out);
  const auto relative = [&base](const std::vector<std::filesystem::path>& written) {
    std::vector<std::filesystem::path> links;
    links.reserve(written.size());
    for (const auto& path : written)
      links.push_back(std::filesystem::weakly_canonical(path).lexically_relative(base));
    return links;
  };
  for (std::size_t i = 0; i < files.size(); ++i) {
    bar(i, files.size() + 1);
    const io::Experiment& e = experiments[i];
    experiment::RunReport report = experiment::run(e, ro);
    summary += report.summary;
    // What an output drops (a 3-D shape's SVG), said as `cifs render` says it, naming the experiment.
    for (const std::string& warning : report.warnings)
      pending_warnings().push_back(files[i].filename().string() + ": " + warning);
    sections.push_back({.name = e.name, .description = e.description, .files = relative(report.written)});
  }
  bar(files.size(), files.size() + 1);
  // The seeds' subdivision schemes: shapes, degree overlays, algorithms compared.
  SchemeFigures schemes = write_scheme_gallery(out / "schemes", examples);
  summary += schemes.summary;
  sections.push_back({.name = "subdivision schemes",
                      .description =
                          "The seeds' curve subdivision schemes on the example polygons (cifs scheme; "
                          "docs/schemes.md)",
                      .files = relative(schemes.files),
                      .captions = std::move(schemes.titles)});
  write_file_atomically(out / "index.html", io::gallery_html(sections, "cifs gallery"));
  summary += "gallery: wrote " + (out / "index.html").string() + "\n";
  bar(files.size() + 1, files.size() + 1);
  return quiet ? "" : summary;  // --quiet: errors and warnings only
}

}  // namespace

std::string gallery(const std::filesystem::path& out, const std::filesystem::path& examples, bool quiet) {
  // Every experiment of examples/experiments, in name order; each writes its own outputs.
  std::vector<std::filesystem::path> files;
  const std::filesystem::path folder = examples / "experiments";
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) throw IoError(folder.string() + ": no such folder");
  for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".json") files.push_back(it->path());
  if (ec) throw IoError(folder.string() + ": cannot list the folder (" + ec.message() + ")");
  std::sort(files.begin(), files.end());
  // Every experiment is read, and so checked, before anything is written (as render does): an invalid
  // later file left the outputs of the earlier ones.
  std::vector<io::Experiment> experiments;
  experiments.reserve(files.size());
  for (const auto& file : files) experiments.push_back(io::read_experiment(file));
  // The folders made here are removed again, when still empty, if the gallery fails.
  std::vector<std::filesystem::path> made;  // deepest first
  if (!std::filesystem::exists(out / "schemes", ec)) made.push_back(out / "schemes");
  for (std::filesystem::path up = out; !up.empty() && !std::filesystem::exists(up, ec); up = up.parent_path())
    made.push_back(up);
  std::filesystem::create_directories(out, ec);
  if (ec) throw IoError(out.string() + ": cannot create the folder (" + ec.message() + ")");
  try {
    return gallery_run(out, examples, experiments, files, quiet);
  } catch (...) {
    for (const auto& f : made) std::filesystem::remove(f, ec);  // only when empty
    throw;
  }
}

}  // namespace cifs::cli
