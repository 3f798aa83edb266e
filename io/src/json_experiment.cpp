// SPDX-License-Identifier: MIT
// cifs — experiment files as JSON (docs/experiments.md), read.
#include <algorithm>

#include "cifs/ifs/affine.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/topology.hpp"
#include "json_common.hpp"

namespace cifs::io {

using detail::json;
using detail::Reader;
namespace {

std::uint64_t unsigned_integer(const Reader& r, const json& v, const std::string& path, std::uint64_t max) {
  if (!v.is_number_integer() || (v.is_number_integer() && !v.is_number_unsigned() && v.get<long long>() < 0))
    r.fail(path, "expected a non-negative integer, got " + v.dump());
  const auto x = v.get<std::uint64_t>();
  if (x > max) r.fail(path, v.dump() + " is above the limit " + std::to_string(max));
  return x;
}

int bounded_integer(const Reader& r, const json& v, const std::string& path, int lo, int hi) {
  const int x = r.integer(v, path);
  if (x < lo || x > hi)
    r.fail(path, std::to_string(x) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return x;
}

double positive(const Reader& r, const json& v, const std::string& path) {
  const double x = r.number(v, path);
  if (x <= 0) r.fail(path, "expected a positive number");
  return x;
}

template <std::size_t N>
std::array<double, N> fixed_numbers(const Reader& r, const json& v, const std::string& path) {
  const std::vector<double> x = r.numbers(v, path);
  if (x.size() != N)
    r.fail(path, "expected " + std::to_string(N) + " numbers, got " + std::to_string(x.size()));
  std::array<double, N> out{};
  std::copy(x.begin(), x.end(), out.begin());
  return out;
}

std::array<double, 3> colour(const Reader& r, const json& v, const std::string& path) {
  const auto c = fixed_numbers<3>(r, v, path);
  for (const double x : c)
    if (x < 0 || x > 1) r.fail(path, "colour components must lie in [0, 1]");
  return c;
}

Shape read_shape_member(const Reader& r, const json& v, const std::filesystem::path& base,
                        std::vector<std::filesystem::path>& inputs, const std::string& path = "shape") {
  if (v.is_string()) {
    const std::filesystem::path p = base / v.get<std::string>();
    inputs.push_back(p);
    try {
      return read_shape(p);
    } catch (const std::exception& e) {
      r.fail(path, e.what());
    }
  }
  r.object(v, path);
  if (v.contains("polygon")) {  // the uniform B-spline of a control polygon file
    r.only(v, path, {"polygon", "degree"});
    const std::filesystem::path p = base / r.string(v["polygon"], path + ".polygon");
    inputs.push_back(p);
    const int degree = r.integer(r.member(v, path, "degree"), path + ".degree");
    try {
      const Polygon polygon = read_polygon(p);
      return nurbs::uniform_bspline(polygon.points, degree, polygon.closed);
    } catch (const std::exception& e) {
      r.fail(path, e.what());
    }
  }
  return parse_shape_json(v.dump(), r.where + ": " + path);
}

ClassicIfs read_ifs(const Reader& r, const json& v) {
  ClassicIfs ifs;
  if (v.is_string()) {
    ifs.name = v.get<std::string>();
    const auto& names = cifs::ifs::ifs_names();
    if (std::find(names.begin(), names.end(), ifs.name) == names.end()) {
      std::string known;
      for (const std::string& n : names) known += n + ", ";
      r.fail("ifs", "unknown IFS \"" + ifs.name + "\" (" + known + "or {\"maps\": [...]})");
    }
    return ifs;
  }
  r.object(v, "ifs");
  r.only(v, "ifs", {"maps"});
  const json& maps = r.array(r.member(v, "ifs", "maps"), "ifs.maps");
  if (maps.empty()) r.fail("ifs.maps", "no maps");
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const std::string path = "ifs.maps[" + std::to_string(i) + "]";
    const std::vector<double> m = r.numbers(maps[i], path);
    if (m.size() != 6 && m.size() != 7) r.fail(path, "expected [a, b, c, d, e, f] or [a, b, c, d, e, f, p]");
    std::array<double, 7> map{0, 0, 0, 0, 0, 0, 1};
    std::copy(m.begin(), m.end(), map.begin());
    if (map[6] < 0) r.fail(path, "negative probability");
    ifs.maps.push_back(map);
  }
  return ifs;
}

/// `"mesh": FILE` with `"subdivision": {"scheme", "levels", "boundary"}`. The mesh's topology is
/// checked here, so that a mesh no scheme can refine is refused with the experiment's name.
MeshSource read_mesh_source(const Reader& r, const json& doc, const std::filesystem::path& base) {
  MeshSource m;
  m.path = base / r.string(doc["mesh"], "mesh");
  try {
    m.mesh = read_mesh(m.path);
    build_topology(m.mesh, m.path.filename().string());
  } catch (const std::exception& e) {
    r.fail("mesh", e.what());
  }
  const json& v = r.object(r.member(doc, "", "subdivision"), "subdivision");
  r.only(v, "subdivision", {"scheme", "levels", "boundary", "limit"});
  const std::string scheme = r.string(r.member(v, "subdivision", "scheme"), "subdivision.scheme");
  try {
    m.scheme = subdivision::named_mesh_scheme(scheme);
  } catch (const InvalidInput& e) {
    r.fail("subdivision.scheme", e.what());
  }
  if (subdivision::triangles_only(m.scheme))
    for (std::size_t f = 0; f < face_count(m.mesh); ++f)
      if (face(m.mesh, f).size() != 3)
        r.fail("subdivision.scheme", std::string(subdivision::scheme_name(m.scheme)) +
                                         " refines triangles only; " + m.path.filename().string() +
                                         " has a face of " + std::to_string(face(m.mesh, f).size()) +
                                         " corners (face " + std::to_string(f) + ")");
  // The size limit is checked when the experiment runs (subdivision::MeshOptions::max_bytes).
  if (v.contains("levels")) m.levels = bounded_integer(r, v["levels"], "subdivision.levels", 0, 16);
  if (v.contains("boundary")) {  // replaces the mesh file's boundary rule
    const std::string b = r.string(v["boundary"], "subdivision.boundary");
    try {
      m.mesh.tags.boundary = named_boundary_rule(b);
    } catch (const InvalidInput& e) {
      r.fail("subdivision.boundary", e.what());
    }
  }
  if (v.contains("limit")) {
    m.limit = r.boolean(v["limit"], "subdivision.limit");
    if (m.limit && m.scheme != subdivision::MeshScheme::catmull_clark &&
        m.scheme != subdivision::MeshScheme::loop)
      r.fail("subdivision.limit", std::string("limit surfaces are built for catmull-clark and loop, not ") +
                                      std::string(subdivision::scheme_name(m.scheme)));
  }
  return m;
}

/// A scheme side's control points: a polygon `[[x, y], …]` or a grid `[[[x, y, z], …], …]` (lines
/// of constant v, u-major), with at least `window` points along each direction.
void read_junction_points(const Reader& r, const json& v, const std::string& path, JunctionSideSpec& s,
                          int window) {
  r.array(v, path);
  if (v.empty()) r.fail(path, "no points");
  std::vector<std::vector<double>> rows;
  if (v[0].is_array() && !v[0].empty() && v[0][0].is_array()) {  // a grid
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::size_t before = rows.size();
      r.points(v[i], path + "[" + std::to_string(i) + "]", rows);
      const auto n = static_cast<int>(rows.size() - before);
      if (i > 0 && n != s.columns)
        r.fail(path + "[" + std::to_string(i) + "]",
               std::to_string(n) + " points, the first line has " + std::to_string(s.columns));
      s.columns = n;
    }
    s.rows = static_cast<int>(v.size());
    if (rows.front().size() != 3) r.fail(path, "a surface's points need 3 coordinates");
    if (s.rows < window || s.columns < window)
      r.fail(path, "a " + std::to_string(s.rows) + " × " + std::to_string(s.columns) + " grid; cells of " +
                       std::to_string(window) + " × " + std::to_string(window) + " points need at least " +
                       std::to_string(window) + " lines each way");
  } else {
    r.points(v, path, rows);
    if (rows.front().size() < 2 || rows.front().size() > 3)
      r.fail(path, "a curve's points need 2 or 3 coordinates");
    if (static_cast<int>(rows.size()) < window)
      r.fail(path, std::to_string(rows.size()) + " points; cells of " + std::to_string(window) +
                       " points need at least " + std::to_string(window));
  }
  s.points = detail::to_points(rows);
}

/// `junction.a` / `junction.b`: a NURBS shape, or a named scheme on its control points.
JunctionSideSpec read_junction_side(const Reader& r, const json& v, const std::string& path,
                                    const std::filesystem::path& base,
                                    std::vector<std::filesystem::path>& inputs) {
  r.object(v, path);
  r.only(v, path,
         {"shape", "scheme", "parameters", "points", "window", "layer", "free", "boundary", "color"});
  JunctionSideSpec s;
  if (int(v.contains("shape")) + int(v.contains("scheme")) != 1)
    r.fail(path, "expected exactly one of \"shape\" (a NURBS curve or surface) and \"scheme\"");
  bool surface = false;
  if (v.contains("shape")) {
    for (const char* key : {"parameters", "points", "window", "layer"})
      if (v.contains(key)) r.fail(path + "." + key, "only with \"scheme\" (a NURBS side has its own)");
    s.shape = read_shape_member(r, v["shape"], base, inputs, path + ".shape");
    surface = std::holds_alternative<nurbs::Surface>(*s.shape);
    if (const auto* c = std::get_if<nurbs::Curve>(&*s.shape); c && c->closed)
      r.fail(path + ".shape", "a closed curve has no start or end to glue");
  } else {
    const std::string name = r.string(v["scheme"], path + ".scheme");
    std::map<std::string, std::string> parameters;
    if (v.contains("parameters"))
      for (const auto& item : r.object(v["parameters"], path + ".parameters").items()) {
        const json& x = item.value();
        if (!x.is_string() && !x.is_number())
          r.fail(path + ".parameters." + item.key(), "expected a number or a string");
        parameters[item.key()] = x.is_string() ? x.get<std::string>() : x.dump();
      }
    try {
      s.scheme = subdivision::named_scheme(name, parameters);
    } catch (const InvalidInput& e) {
      r.fail(path + ".scheme", e.what());
    }
    const int support = subdivision::mask_degree(*s.scheme);
    if (v.contains("window")) {
      s.window = bounded_integer(r, v["window"], path + ".window", 0, 64);
      if (s.window != 0 && s.window < support)
        r.fail(path + ".window", std::to_string(s.window) + " is below the scheme's support " +
                                     std::to_string(support) + " (0: the support)");
    }
    const int window = s.window == 0 ? support : s.window;
    read_junction_points(r, r.member(v, path, "points"), path + ".points", s, window);
    surface = s.columns > 0;
    if (v.contains("layer")) s.layer = bounded_integer(r, v["layer"], path + ".layer", 0, 4096);
  }
  if (v.contains("free")) s.free = r.boolean(v["free"], path + ".free");
  s.boundary = r.string(r.member(v, path, "boundary"), path + ".boundary");
  const bool known = surface ? s.boundary == "ustart" || s.boundary == "uend" || s.boundary == "vstart" ||
                                   s.boundary == "vend"
                             : s.boundary == "start" || s.boundary == "end";
  if (!known)
    r.fail(path + ".boundary", "\"" + s.boundary + "\": expected " +
                                   (surface ? "\"ustart\", \"uend\", \"vstart\" or \"vend\" (a surface)"
                                            : "\"start\" or \"end\" (a curve)"));
  // uniform_curve_bcifs unfolds the pieces at the start of the curve only.
  if (s.layer > 0 && !s.boundary.ends_with("start"))
    r.fail(path + ".layer", "the junction layer lies at the start: glue the side's " +
                                std::string(surface ? "\"ustart\" or \"vstart\"" : "\"start\""));
  if (v.contains("color")) s.color = colour(r, v["color"], path + ".color");
  return s;
}

bool is_surface(const JunctionSideSpec& s) {
  return s.shape ? std::holds_alternative<nurbs::Surface>(*s.shape) : s.columns > 0;
}

/// Cartesian coordinates of a side's points.
Eigen::Index side_dimension(const JunctionSideSpec& s) {
  if (!s.shape) return s.points.cols();
  return std::visit([](const auto& shape) { return nurbs::cartesian_points(shape).cols(); }, *s.shape);
}

JunctionSpec read_junction(const Reader& r, const json& v, const std::filesystem::path& base,
                           std::vector<std::filesystem::path>& inputs) {
  r.object(v, "junction");
  r.only(v, "junction", {"a", "b"});
  JunctionSpec j{read_junction_side(r, r.member(v, "junction", "a"), "junction.a", base, inputs),
                 read_junction_side(r, r.member(v, "junction", "b"), "junction.b", base, inputs)};
  if (is_surface(j.a) != is_surface(j.b))
    r.fail("junction", std::string("A is a ") + (is_surface(j.a) ? "surface" : "curve") + " and B a " +
                           (is_surface(j.b) ? "surface" : "curve") + ": join two curves or two surfaces");
  if (side_dimension(j.a) != side_dimension(j.b))
    r.fail("junction", "A has " + std::to_string(side_dimension(j.a)) + " coordinates and B " +
                           std::to_string(side_dimension(j.b)));
  return j;
}

PerturbationSpec read_perturbation(const Reader& r, const json& v) {
  r.object(v, "perturbation");
  r.only(v, "perturbation", {"amplitude", "seed", "values", "keep_vertices", "fractal_curves"});
  PerturbationSpec p;
  if (v.contains("amplitude")) {
    p.amplitude = r.number(v["amplitude"], "perturbation.amplitude");
    if (p.amplitude < 0) r.fail("perturbation.amplitude", "expected a number ≥ 0");
  }
  if (v.contains("seed")) p.seed = unsigned_integer(r, v["seed"], "perturbation.seed", UINT64_MAX);
  if (v.contains("values")) {
    const json& values = r.object(v["values"], "perturbation.values");
    for (const auto& item : values.items())
      p.values[item.key()] = r.number(item.value(), "perturbation.values." + item.key());
  }
  if (v.contains("keep_vertices"))
    p.keep_vertices = r.boolean(v["keep_vertices"], "perturbation.keep_vertices");
  if (v.contains("fractal_curves")) {
    const json& c = r.object(v["fractal_curves"], "perturbation.fractal_curves");
    const std::string at = "perturbation.fractal_curves";
    r.only(c, at, {"creases", "boundaries", "amplitude", "seed", "values"});
    FractalCurvesSpec f;
    if (c.contains("creases")) f.creases = r.boolean(c["creases"], at + ".creases");
    if (c.contains("boundaries")) f.boundaries = r.boolean(c["boundaries"], at + ".boundaries");
    if (!f.creases && !f.boundaries) r.fail(at, "neither creases nor boundaries: drop it");
    if (c.contains("amplitude")) {
      f.amplitude = r.number(c["amplitude"], at + ".amplitude");
      if (f.amplitude < 0) r.fail(at + ".amplitude", "expected a number ≥ 0");
    }
    if (c.contains("seed")) f.seed = unsigned_integer(r, c["seed"], at + ".seed", UINT64_MAX);
    if (c.contains("values")) {
      const json& values = r.object(c["values"], at + ".values");
      for (const auto& item : values.items())
        f.values[item.key()] = r.number(item.value(), at + ".values." + item.key());
    }
    p.fractal_curves = std::move(f);
  }
  return p;
}

/// The feature curves asked for must exist: an infinitely sharp crease, a boundary (which ones can be
/// made fractal — not those ending at darts — is subdivision::fractal_surface's to say, when it runs).
void check_fractal_curves(const Reader& r, const FractalCurvesSpec& f, const Mesh& mesh,
                          const std::filesystem::path& path) {
  const std::string file = path.filename().string();
  if (f.creases && std::none_of(mesh.tags.creases.begin(), mesh.tags.creases.end(),
                                [](const EdgeSharpness& c) { return c.sharpness >= kInfiniteSharpness; }))
    r.fail("perturbation.fractal_curves.creases",
           file + " has no infinitely sharp crease (sharpness ≥ 10; semi-sharp creases stay smooth)");
  if (f.boundaries) {
    const MeshTopology t = build_topology(mesh, file);
    if (std::none_of(t.boundary_vertex.begin(), t.boundary_vertex.end(), [](char b) { return b != 0; }))
      r.fail("perturbation.fractal_curves.boundaries", file + " is closed: it has no boundary");
  }
}

EvaluationSpec read_evaluation(const Reader& r, const json& v) {
  r.object(v, "evaluation");
  if (v.contains("tolerance"))
    r.fail("evaluation.tolerance",
           "is now \"relative_piece_size\" (every piece smaller than this fraction of "
           "the control nets' diameter)");
  r.only(v, "evaluation", {"depth", "relative_piece_size", "chaos", "seed"});
  EvaluationSpec e;
  const int modes =
      int(v.contains("depth")) + int(v.contains("relative_piece_size")) + int(v.contains("chaos"));
  if (modes != 1)
    r.fail("evaluation", "expected exactly one of \"depth\", \"relative_piece_size\", \"chaos\"");
  if (v.contains("depth")) {
    e.mode = EvaluationSpec::Mode::depth;
    e.depth = bounded_integer(r, v["depth"], "evaluation.depth", 0, 30);
  } else if (v.contains("relative_piece_size")) {
    e.mode = EvaluationSpec::Mode::tolerance;
    e.tolerance = positive(r, v["relative_piece_size"], "evaluation.relative_piece_size");
  } else {
    e.mode = EvaluationSpec::Mode::chaos;
    // Below 2^53, where the summed counts stay exact; each process draws fewer than 2^32 (cifs render
    // under mpirun divides them).
    e.samples = unsigned_integer(r, v["chaos"], "evaluation.chaos", (std::uint64_t{1} << 53) - 1);
    if (e.samples == 0) r.fail("evaluation.chaos", "expected at least one sample");
  }
  if (v.contains("seed")) e.seed = unsigned_integer(r, v["seed"], "evaluation.seed", UINT64_MAX);
  return e;
}

CameraSpec read_camera(const Reader& r, const json& v) {
  r.object(v, "camera");
  r.only(v, "camera", {"projection", "eye", "target", "up", "fov", "margin"});
  CameraSpec c;
  if (v.contains("projection")) {
    const std::string p = r.string(v["projection"], "camera.projection");
    if (p == "orthographic")
      c.projection = CameraSpec::Projection::orthographic;
    else if (p == "perspective")
      c.projection = CameraSpec::Projection::perspective;
    else if (p != "automatic")
      r.fail("camera.projection", "expected \"orthographic\", \"perspective\" or \"automatic\"");
  }
  if (v.contains("eye")) c.eye = fixed_numbers<3>(r, v["eye"], "camera.eye");
  if (v.contains("target")) c.target = fixed_numbers<3>(r, v["target"], "camera.target");
  if (v.contains("up")) c.up = fixed_numbers<3>(r, v["up"], "camera.up");
  if (v.contains("fov")) {
    c.fov_degrees = r.number(v["fov"], "camera.fov");
    if (c.fov_degrees <= 0 || c.fov_degrees >= 180) r.fail("camera.fov", "expected degrees in (0, 180)");
  }
  if (v.contains("margin")) {
    c.margin = r.number(v["margin"], "camera.margin");
    if (c.margin < 0 || c.margin >= 0.5) r.fail("camera.margin", "expected a fraction in [0, 0.5)");
  }
  if (c.eye && c.target && *c.eye == *c.target) r.fail("camera", "eye and target coincide");
  return c;
}

RenderSettings read_render(const Reader& r, const json& v) {
  r.object(v, "render");
  r.only(v, "render",
         {"width", "height", "line_width", "color", "background", "control_net", "threads", "palette",
          "gamma", "exposure"});
  RenderSettings s;
  if (v.contains("width")) s.width = bounded_integer(r, v["width"], "render.width", 1, 16384);
  if (v.contains("height")) s.height = bounded_integer(r, v["height"], "render.height", 1, 16384);
  if (v.contains("line_width")) {
    s.line_width = positive(r, v["line_width"], "render.line_width");
    if (s.line_width > 256) r.fail("render.line_width", "above 256 pixels");
  }
  if (v.contains("color")) {
    s.color = colour(r, v["color"], "render.color");
    s.color_given = true;
  }
  if (v.contains("palette")) {
    const json& stops = r.array(v["palette"], "render.palette");
    if (stops.empty() || stops.size() > 256) r.fail("render.palette", "expected 1 to 256 colours");
    for (std::size_t i = 0; i < stops.size(); ++i)
      s.palette.push_back(colour(r, stops[i], "render.palette[" + std::to_string(i) + "]"));
  }
  if (v.contains("gamma")) {
    s.gamma = positive(r, v["gamma"], "render.gamma");
    if (s.gamma > 100) r.fail("render.gamma", "above 100");
  }
  if (v.contains("exposure")) {
    s.exposure = positive(r, v["exposure"], "render.exposure");
    if (s.exposure > 1e6) r.fail("render.exposure", "above 1e6");
  }
  if (v.contains("background")) s.background = colour(r, v["background"], "render.background");
  if (v.contains("control_net")) s.control_net = r.boolean(v["control_net"], "render.control_net");
  if (v.contains("threads"))
    s.threads = static_cast<unsigned>(bounded_integer(r, v["threads"], "render.threads", 0, 1024));
  return s;
}

std::filesystem::path output_path(const Reader& r, const json& v, const std::string& path) {
  std::filesystem::path p(r.string(v, path));
  if (p.empty() || p.has_root_path() || !p.has_filename()) r.fail(path, "expected a relative file name");
  for (const auto& part : p)
    if (part == "..") r.fail(path, "\"..\" would leave the output directory");
  return p;
}

/// The names of the formats that write `content`, in table order.
std::vector<std::string> writable_names(Content content) {
  std::vector<std::string> names;
  for (const Format& f : formats(content))
    if (f.write) names.emplace_back(f.name);
  return names;
}

/// Keys: exr, png, a geometry format (of meshes or segment sets: which one applies is known only
/// when the experiment runs), automaton_<format>. Checked in the order the files are written.
Outputs read_outputs(const Reader& r, const json& v) {
  r.object(v, "outputs");
  std::vector<std::string> geometry = writable_names(Content::segments);
  for (const std::string& name : writable_names(Content::mesh))
    if (std::find(geometry.begin(), geometry.end(), name) == geometry.end()) geometry.push_back(name);
  const std::vector<std::string> automaton = writable_names(Content::automaton);
  for (const auto& item : v.items()) {
    const std::string& key = item.key();
    const bool known = key == "exr" || key == "png" ||
                       std::find(geometry.begin(), geometry.end(), key) != geometry.end() ||
                       (key.starts_with("automaton_") &&
                        std::find(automaton.begin(), automaton.end(), key.substr(10)) != automaton.end());
    if (!known) r.fail("outputs." + key, "unknown member");
  }
  Outputs o;
  const auto get = [&](const std::string& key) { return output_path(r, v[key], "outputs." + key); };
  if (v.contains("exr")) o.exr = get("exr");
  if (v.contains("png")) o.png = get("png");
  for (const std::string& name : geometry)
    if (v.contains(name)) o.geometry[name] = get(name);
  for (const std::string& name : automaton)
    if (v.contains("automaton_" + name)) o.automaton[name] = get("automaton_" + name);
  return o;
}

}  // namespace

Experiment parse_experiment(std::string_view text, std::string_view where,
                            const std::filesystem::path& base) {
  const Reader r{std::string(where)};
  const json doc = detail::parse_document(text, r.where);
  if (!doc.is_object()) throw InvalidInput(r.where + ": expected an experiment object");
  r.only(doc, "",
         {"name", "description", "shape", "automaton", "ifs", "mesh", "junction", "subdivision",
          "perturbation", "evaluation", "camera", "render", "outputs"});
  Experiment e;
  if (doc.contains("name")) e.name = r.string(doc["name"], "name");
  if (doc.contains("description")) e.description = r.string(doc["description"], "description");
  const int sources = int(doc.contains("shape")) + int(doc.contains("automaton")) + int(doc.contains("ifs")) +
                      int(doc.contains("mesh")) + int(doc.contains("junction"));
  if (sources != 1)
    throw InvalidInput(r.where +
                       ": expected exactly one of \"shape\", \"automaton\", \"ifs\", \"mesh\", \"junction\"");
  if (doc.contains("shape")) e.shape = read_shape_member(r, doc["shape"], base, e.inputs);
  if (doc.contains("automaton")) {
    e.automaton = base / r.string(doc["automaton"], "automaton");
    e.inputs.push_back(e.automaton);
    // The error_code form: a name longer than the file system allows threw filesystem_error.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(e.automaton, ec))
      r.fail("automaton", ec && ec != std::errc::no_such_file_or_directory
                              ? "cannot read " + excerpt(e.automaton.string()) + " (" + ec.message() + ")"
                              : "no such file: " + excerpt(e.automaton.string()));
  }
  if (doc.contains("ifs")) e.ifs = read_ifs(r, doc["ifs"]);
  if (doc.contains("mesh")) {
    e.mesh = read_mesh_source(r, doc, base);
    e.inputs.push_back(e.mesh->path);
    // A subdivision surface is refined, not evaluated; Catmull–Clark's and Loop's can be perturbed as a
    // BC-IFS.
    if (doc.contains("perturbation")) {
      if (e.mesh->scheme != subdivision::MeshScheme::catmull_clark &&
          e.mesh->scheme != subdivision::MeshScheme::loop)
        r.fail("perturbation", "fractal subdivision surfaces are built for catmull-clark and loop, not " +
                                   std::string(subdivision::scheme_name(e.mesh->scheme)));
      if (e.mesh->limit)
        r.fail("perturbation", "a fractal surface has no limit normals (drop subdivision.limit)");
      if (doc["perturbation"].is_object() && doc["perturbation"].contains("keep_vertices"))
        r.fail("perturbation.keep_vertices", "NURBS sources only: a mesh's face boundaries always stay");
      const PerturbationSpec p = read_perturbation(r, doc["perturbation"]);
      if (p.fractal_curves) check_fractal_curves(r, *p.fractal_curves, e.mesh->mesh, e.mesh->path);
    }
    if (doc.contains("evaluation")) r.fail("evaluation", "a mesh is refined by subdivision.levels");
  } else if (doc.contains("subdivision")) {
    r.fail("subdivision", "only with a \"mesh\" source");
  }
  if (doc.contains("junction")) {
    e.junction = read_junction(r, doc["junction"], base, e.inputs);
    if (doc.contains("perturbation") && doc["perturbation"].is_object() &&
        doc["perturbation"].contains("keep_vertices"))
      r.fail("perturbation.keep_vertices", "a junction's sides say which matrices are free (\"free\")");
    if (doc.contains("evaluation") && doc["evaluation"].is_object() &&
        doc["evaluation"].contains("relative_piece_size"))
      r.fail("evaluation.relative_piece_size", "a junction is evaluated to a depth or by the chaos game");
  }
  if (doc.contains("perturbation")) {
    if (e.ifs) r.fail("perturbation", "a classic IFS has no constraints to perturb under");
    e.perturbation = read_perturbation(r, doc["perturbation"]);
    if (e.perturbation->fractal_curves && !e.mesh)
      r.fail("perturbation.fractal_curves", "mesh sources only (a mesh's creases and boundaries)");
  }
  if (doc.contains("evaluation")) e.evaluation = read_evaluation(r, doc["evaluation"]);
  if (doc.contains("camera")) e.camera = read_camera(r, doc["camera"]);
  if (doc.contains("render")) e.render = read_render(r, doc["render"]);
  if (doc.contains("outputs")) e.outputs = read_outputs(r, doc["outputs"]);
  return e;
}

}  // namespace cifs::io
