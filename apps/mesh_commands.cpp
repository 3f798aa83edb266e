// SPDX-License-Identifier: MIT
// cifs CLI — polygon meshes: `cifs subdivide` and `cifs info` on an OBJ/PLY mesh.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>
#include <string_view>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/mesh_formats.hpp"
#include "cifs/io/ply.hpp"
#include "cifs/render/camera.hpp"
#include "cifs/render/preview.hpp"
#include "cifs/render/progress.hpp"
#include "cifs/render/raster.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/topology.hpp"
#include "commands.hpp"

namespace cifs::cli {
namespace {

using nlohmann::json;

/// Refused before the work: the output must be a mesh format the table writes. Its name.
std::string mesh_output_format(const std::filesystem::path& output) {
  std::vector<std::string> known;
  for (const io::Format& f : io::formats(io::Content::mesh)) {
    if (!f.write) continue;
    if (extension_of(output) == f.extension) return std::string(f.name);
    known.emplace_back(f.extension);
  }
  std::string list;
  for (std::size_t i = 0; i < known.size(); ++i)
    list += (i == 0 ? "" : i + 1 == known.size() ? " or " : ", ") + known[i];
  throw InvalidInput("-o " + output.string() + ": expected a " + list + " file name");
}

}  // namespace

namespace {

/// Count, sharpness range and infinitely sharp count of creases or corners.
template <class Tagged>
json sharpness_summary(const std::vector<Tagged>& tagged) {
  json out = {{"count", tagged.size()}};
  if (tagged.empty()) return out;
  const auto [lo, hi] =
      std::minmax_element(tagged.begin(), tagged.end(),
                          [](const Tagged& a, const Tagged& b) { return a.sharpness < b.sharpness; });
  out["sharpness"] = {lo->sharpness, hi->sharpness};
  out["infinite"] = std::count_if(tagged.begin(), tagged.end(),
                                  [](const Tagged& t) { return t.sharpness >= kInfiniteSharpness; });
  return out;
}

/// What a production mesh carries beside its faces: tags, options and face-varying channels.
json tags_info(const Mesh& mesh) {
  json channels = json::array();
  for (const FaceVaryingChannel& c : mesh.face_varying)
    channels.push_back({{"name", c.name}, {"values", c.values.rows()}, {"dimension", c.values.cols()}});
  return {{"creases", sharpness_summary(mesh.tags.creases)},
          {"corners", sharpness_summary(mesh.tags.corners)},
          {"holes", mesh.tags.holes.size()},
          {"boundary", option_name(mesh.tags.boundary)},
          {"crease_method", option_name(mesh.tags.crease_method)},
          {"triangles", option_name(mesh.tags.triangles)},
          {"fvar_interpolation", option_name(mesh.tags.face_varying)},
          {"rules", option_name(mesh.tags.rules)},
          {"concave", mesh.tags.concave},
          {"face_varying", channels}};
}

}  // namespace

std::string mesh_info(const std::filesystem::path& path, const io::MeshReadOptions& read) {
  const Mesh mesh = io::read_mesh(path, read);
  std::map<std::string, std::size_t> sizes;  // JSON keys
  for (std::size_t f = 0; f < face_count(mesh); ++f) ++sizes[std::to_string(face(mesh, f).size())];
  json out = {{"type", "mesh"},
              {"vertices", mesh.vertices.rows()},
              {"faces", face_count(mesh)},
              {"faces_by_corners", sizes}};
  out.update(tags_info(mesh));
  std::optional<MeshTopology> topology;
  try {
    topology = build_topology(mesh, path.string());
  } catch (const InvalidInput& e) {
    // Non-manifold or inconsistently oriented: the facts above, and why adjacency is not built.
    out["manifold"] = false;
    out["topology_refused"] = e.what();
    return out.dump(1) + "\n";
  }
  const MeshStatistics st = mesh_statistics(*topology);
  std::map<std::string, std::size_t> valences;
  for (const auto& [valence, vertices] : st.valences) valences[std::to_string(valence)] = vertices;
  out["manifold"] = true;
  out.update({{"edges", topology->edges.size()},
              {"valences", valences},
              {"isolated_vertices", st.isolated_vertices},
              {"boundary_loops", st.boundary_loops},
              {"closed", st.boundary_loops == 0},
              {"components", st.components},
              {"euler_characteristic", st.euler_characteristic}});
  if (st.genus) out["genus"] = *st.genus;
  return out.dump(1) + "\n";
}

namespace {

/// The frame of the commands that make a mesh from a mesh: the output is checked (not the input mesh, a
/// folder, a device…) and its temporary made before the work; errors of the work name the input; the
/// result goes out a chunk at a time (its text is never whole in memory), or to standard output as OBJ.
std::string mesh_to_mesh(const std::filesystem::path& input, const io::MeshReadOptions& read,
                         const std::filesystem::path& output_path, const std::function<Mesh(Mesh)>& make,
                         const std::function<std::string(const Mesh&)>& summary) {
  const std::string format = output_path.empty() ? "obj" : mesh_output_format(output_path);
  std::optional<AtomicFile> output;
  if (!output_path.empty()) output.emplace(output_path, OutputOptions{.inputs = {input}});
  Mesh mesh = io::read_mesh(input, read);
  Mesh result;
  try {
    result = make(std::move(mesh));
  } catch (const InvalidInput& e) {
    throw InvalidInput(input.string() + ": " + e.what());
  }
  if (const std::string dropped = io::mesh_left_out(result, format); !dropped.empty())
    pending_warnings().push_back(output_path.string() + ": the ." + format + " format does not hold " +
                                 dropped + "; they are left out (write .obj to keep them)");
  if (!output) return io::encode(result, format);
  io::encode(result, format, *output);
  output->commit();
  return "wrote " + output_path.string() + ": " + summary(result) + "\n";
}

/// The file's options replaced by the flags given ("" keeps the file's), a wrong name reported with
/// its flag.
TagOverrides tag_overrides(const std::string& boundary, const std::string& crease_method,
                           const std::string& triangles, const std::string& fvar_interpolation,
                           const std::string& rules = "") {
  const auto parse = [](const char* flag, const std::string& value, auto named) {
    using Option = decltype(named(value));
    if (value.empty()) return std::optional<Option>();
    try {
      return std::optional<Option>(named(value));
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string(flag) + " " + value + ": " + e.what());
    }
  };
  return {.boundary = parse("--boundary", boundary, named_boundary_rule),
          .crease_method = parse("--crease-method", crease_method, named_crease_method),
          .triangles = parse("--triangles", triangles, named_triangle_rule),
          .face_varying = parse("--fvar-interpolation", fvar_interpolation, named_face_varying_rule),
          .rules = parse("--rules", rules, named_rule_set)};
}

}  // namespace

std::string subdivide(const SubdivideOptions& o) {
  const subdivision::MeshScheme scheme = subdivision::named_mesh_scheme(o.scheme);
  render::ProgressBar bar("subdivide", o.quiet);
  const subdivision::MeshOptions options{
      .progress = [&bar](std::uint64_t done, std::uint64_t total) { bar(done, total); }};
  const TagOverrides overrides =
      tag_overrides(o.boundary, o.crease_method, o.triangles, o.fvar_interpolation, o.rules);
  return mesh_to_mesh(
      o.mesh, {.strict = o.strict, .warn = {}}, o.output,
      [&](Mesh mesh) {
        apply(overrides, mesh.tags);
        return o.factored ? subdivision::factored_subdivide(mesh, scheme, o.levels, options)
                          : subdivision::subdivide(mesh, scheme, o.levels, options);
      },
      [&](const Mesh& refined) {
        return std::to_string(refined.vertices.rows()) + " vertices, " + std::to_string(face_count(refined)) +
               " faces (" + o.scheme + (o.factored ? " factored" : "") + ", " + std::to_string(o.levels) +
               " levels)";
      });
}

namespace {

/// Points "face,u,v" separated by ';' or line ends (commas or blanks within a point, '#' to the end of
/// its line a comment), from --at's text, or from the file it names.
std::vector<subdivision::FacePoint> face_points(const std::string& at) {
  std::error_code error;
  const bool file = std::filesystem::is_regular_file(at, error);
  const std::string text = file ? read_file(at) : at;
  const std::string where = file ? "--at " + at : "--at";
  // Views into the text, no copy per point: a million points are read in a fraction of a second.
  const std::string_view all(text);
  std::vector<subdivision::FacePoint> out;
  std::size_t start = 0;
  while (start <= all.size()) {
    std::size_t end = all.find_first_of(";\n", start);
    if (end == std::string_view::npos) end = all.size();
    const std::string_view line = all.substr(start, end - start);
    const std::string_view item = line.substr(0, line.find('#'));
    start = end + 1;
    std::array<std::string_view, 3> words;
    std::size_t count = 0;
    for (std::size_t w = item.find_first_not_of(", \t\r"); w != std::string_view::npos;) {
      const std::size_t e = std::min(item.find_first_of(", \t\r", w), item.size());
      if (count < words.size()) words[count] = item.substr(w, e - w);
      ++count;
      w = item.find_first_not_of(", \t\r", e);
    }
    if (count == 0) continue;
    const auto bad = [&](const std::string& why) {
      std::string message = where;
      message += ": point " + std::to_string(out.size()) + " '";
      message += item;
      message += "': " + why;
      if (!file) message += " (or a file of such points: there is no file '" + at + "')";
      return InvalidInput(message);
    };
    if (count != 3) throw bad("expected face,u,v");
    subdivision::FacePoint q;
    const auto [face_end, face_error] =
        std::from_chars(words[0].data(), words[0].data() + words[0].size(), q.face);
    if (face_error != std::errc() || face_end != words[0].data() + words[0].size())
      throw bad("the face '" + std::string(words[0]) + "' is not a whole number");
    for (const auto& [word, value] : {std::pair{words[1], &q.u}, std::pair{words[2], &q.v}}) {
      const auto [number_end, number_error] = std::from_chars(word.data(), word.data() + word.size(), *value);
      if (number_error != std::errc() || number_end != word.data() + word.size())
        throw bad("'" + std::string(word) + "' is not a number");
    }
    out.push_back(q);
  }
  if (out.empty()) throw InvalidInput(where + ": no points (expected face,u,v;face,u,v…)");
  return out;
}

/// `"name":[x,y,z]` after a comma, the numbers as the shortest text that reads back the same.
void append_row(std::string& out, std::string_view name, const Points& P, std::size_t i) {
  out += ",\"";
  out += name;
  out += "\":[";
  const auto r = static_cast<Eigen::Index>(i);
  for (Eigen::Index c = 0; c < P.cols(); ++c) {
    if (c) out += ',';
    append_number(out, P(r, c));
  }
  out += ']';
}

/// `cifs limit MESH --at POINTS`: the limit surface at the points, as JSON — one point a line, streamed
/// to the file a megabyte at a time (a million points with partials and normals: 450 MB of text).
std::string limit_at(const LimitCommandOptions& o, subdivision::MeshScheme scheme) {
  if (!o.output.empty() && extension_of(o.output) != ".json")
    throw InvalidInput("-o " + o.output.string() + ": expected a .json file name (--at writes JSON)");
  const std::vector<subdivision::FacePoint> points = face_points(o.at);
  std::optional<AtomicFile> output;
  if (!o.output.empty()) output.emplace(o.output, OutputOptions{.inputs = {o.mesh}});
  Mesh mesh = io::read_mesh(o.mesh, {.strict = o.strict, .warn = {}});
  apply(tag_overrides(o.boundary, "", "", ""), mesh.tags);
  subdivision::SurfaceSample s;
  try {
    s = subdivision::evaluate_limit_surface(mesh, scheme, points,
                                            {.partials = o.partials || o.normals, .normals = o.normals});
  } catch (const InvalidInput& e) {
    throw InvalidInput(o.mesh.string() + ": " + e.what());
  }
  std::string text = "{\"scheme\":" + json(o.scheme).dump() + ",\"points\":[\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    text += "{\"face\":" + std::to_string(points[i].face) + ",\"u\":";
    append_number(text, points[i].u);
    text += ",\"v\":";
    append_number(text, points[i].v);
    append_row(text, "position", s.positions, i);
    if (o.partials) append_row(text, "du", s.du, i), append_row(text, "dv", s.dv, i);
    if (o.normals) append_row(text, "normal", s.normals, i);
    text += i + 1 < points.size() ? "},\n" : "}\n";
    if (output && text.size() >= (std::size_t{1} << 20)) {
      output->write(text);
      text.clear();
    }
  }
  text += "]}\n";
  if (!output) return text;
  output->write(text);
  output->commit();
  return "wrote " + o.output.string() + ": the limit surface at " + std::to_string(points.size()) +
         " points (" + o.scheme + ")\n";
}

}  // namespace

std::string limit(const LimitCommandOptions& o) {
  const subdivision::MeshScheme scheme = subdivision::named_mesh_scheme(o.scheme);
  if (!o.at.empty()) return limit_at(o, scheme);
  const subdivision::LimitOptions options{.normals = o.normals};
  const TagOverrides overrides = tag_overrides(o.boundary, "", "", "");
  return mesh_to_mesh(
      o.mesh, {.strict = o.strict, .warn = {}}, o.output,
      [&](Mesh mesh) {
        apply(overrides, mesh.tags);
        return subdivision::limit_mesh(mesh, scheme, o.levels, options);
      },
      [&](const Mesh& surface) {
        return std::to_string(surface.vertices.rows()) + " limit points" +
               (!o.normals                       ? ", "
                : surface.normal_indices.empty() ? " with normals, "
                                                 : " with " + std::to_string(surface.normals.rows()) +
                                                       " normals (per sector at creases and corners), ") +
               std::to_string(face_count(surface)) + " faces (" + o.scheme + ", " + std::to_string(o.levels) +
               " levels)";
      });
}

namespace {

std::string number(long double x) {
  std::ostringstream s;
  s << std::setprecision(6) << static_cast<double>(x);
  return s.str();
}

std::string sectors_text(const std::vector<int>& sectors) {
  std::string out;
  for (const int k : sectors) out += (out.empty() ? "" : ",") + std::to_string(k);
  return out;
}

std::string verdict_word(const subdivision::C1Verdict& v) {
  return v.c1 ? "yes" : v.decided ? "no" : "undecided";
}

/// Where to mark an analysed point: the vertex's point three levels down (vertex points keep their
/// index); Doo–Sabin: the limit point, a face's centroid — of the vertex's face after one step for a
/// vertex (the centroid of its corner points; α's columns sum to 1 round the face).
Eigen::RowVector3d marked_point(const Mesh& mesh, subdivision::MeshScheme scheme, const Mesh& surface,
                                const subdivision::VertexSmoothness& v) {
  if (scheme != subdivision::MeshScheme::doo_sabin) return surface.vertices.row(v.vertex);
  Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
  int count = 0;
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    const auto corners = face(mesh, f);
    const auto k = static_cast<int>(corners.size());
    const auto at = std::find(corners.begin(), corners.end(), v.vertex);
    if (v.face >= 0 ? static_cast<int>(f) != v.face : at == corners.end()) continue;
    if (v.face >= 0) {  // the centroid
      for (const int c : corners) sum += mesh.vertices.row(c);
      count += k;
      continue;
    }
    const auto i = static_cast<int>(at - corners.begin());
    for (int m = 0; m < k; ++m)
      sum += ((m == 0 ? 0.25 : 0.0) + (3 + 2 * std::cos(2 * std::numbers::pi * m / k)) / (4 * k)) *
             mesh.vertices.row(corners[static_cast<std::size_t>((i + m) % k)]);
    ++count;
  }
  return sum / count;
}

/// The surface three levels down, shaded, with a cross at each irregular vertex (vertex points keep
/// their index: the level-3 point is next to the limit) coloured by its verdict; written atomically.
void analysis_png(const std::filesystem::path& path, const Mesh& mesh, subdivision::MeshScheme scheme,
                  const subdivision::MeshSmoothness& a) {
  const Mesh surface = subdivision::subdivide(mesh, scheme, 3);
  render::FramingOptions framing;
  framing.width = framing.height = 800;
  const render::Camera camera = render::frame(surface.vertices, framing);
  render::Image image = render::make_framebuffer(camera);
  render::render_mesh(image, camera, surface);
  const Eigen::RowVector3d extent =
      surface.vertices.colwise().maxCoeff() - surface.vertices.colwise().minCoeff();
  const double arm = 0.015 * extent.maxCoeff();
  const std::array<std::pair<int, render::Rgb>, 3> kinds{
      {{0, {0.05, 0.6, 0.1}}, {1, {0.85, 0.05, 0.05}}, {2, {0.95, 0.55, 0.0}}}};
  for (const auto& [kind, color] : kinds) {
    Segments marks;
    marks.vertices.resize(0, 3);
    for (const subdivision::VertexSmoothness& v : a.vertices) {
      if ((v.verdict.c1 ? 0 : v.verdict.decided ? 1 : 2) != kind) continue;
      const Eigen::RowVector3d p = marked_point(mesh, scheme, surface, v);
      for (int axis = 0; axis < 3; ++axis) {
        Eigen::RowVector3d d = Eigen::RowVector3d::Zero();
        d(axis) = arm;
        const auto at = static_cast<int>(marks.vertices.rows());
        marks.vertices.conservativeResize(at + 2, 3);
        marks.vertices.row(at) = p - d;
        marks.vertices.row(at + 1) = p + d;
        marks.segments.push_back({at, at + 1});
      }
    }
    render::CurveStyle style;
    style.width = 3.0;
    style.color = color;
    if (!marks.segments.empty()) render::render_segments(image, camera, marks, style);
  }
  render::PreviewOptions preview;
  preview.mode = render::PreviewMode::shaded;
  render::preview_png(path, image, preview);
}

}  // namespace

std::string analyze(const AnalyzeOptions& o) {
  const subdivision::MeshScheme scheme = subdivision::named_mesh_scheme(o.scheme);
  if (o.format != "table" && o.format != "json")
    throw InvalidInput("--format '" + o.format + "': table or json for cifs analyze");
  Mesh mesh = io::read_mesh(o.mesh, {.strict = o.strict, .warn = {}});
  apply(tag_overrides(o.boundary, "", "", "", o.rules), mesh.tags);
  const subdivision::MeshSmoothness a = subdivision::analyze_mesh(mesh, scheme, o.mesh.string());
  if (!o.png.empty()) analysis_png(o.png, mesh, scheme, a);
  if (o.format == "json") {
    json vertices = json::array();
    for (const subdivision::VertexSmoothness& v : a.vertices)
      vertices.push_back({{"vertex", v.vertex},
                          {"face", v.face},
                          {"class", v.vertex_class},
                          {"valence", v.valence},
                          {"sector_faces", v.sectors},
                          {"lambda1", static_cast<double>(v.lambda1)},
                          {"lambda2", static_cast<double>(v.lambda2)},
                          {"curvature_ratio",
                           v.curvature_ratio ? json(static_cast<double>(*v.curvature_ratio)) : json(nullptr)},
                          {"semi_sharp", v.semi_sharp},
                          {"c1", verdict_word(v.verdict)},
                          {"method", v.verdict.method},
                          {"reason", v.verdict.reason}});
    const json out = {
        {"scheme", o.scheme},  {"vertices", vertices}, {"regular", a.regular},     {"in_no_face", a.isolated},
        {"c1", a.c1},          {"not_c1", a.not_c1},   {"undecided", a.undecided}, {"analyses", a.analyses},
        {"summary", a.summary}};
    return out.dump(1) + "\n";
  }
  std::ostringstream s;
  s << std::left << std::setw(9) << "vertex" << std::setw(10) << "class" << std::setw(8) << "valence"
    << std::setw(9) << "sectors" << std::setw(11) << "lambda1" << std::setw(11) << "lambda2" << std::setw(11)
    << "l2^2/|mu|"
    << "C1\n";
  for (const subdivision::VertexSmoothness& v : a.vertices)
    s << std::setw(9) << (v.face >= 0 ? "f" + std::to_string(v.face) : std::to_string(v.vertex))
      << std::setw(10) << v.vertex_class << std::setw(8) << v.valence << std::setw(9)
      << sectors_text(v.sectors) << std::setw(11) << number(v.lambda1) << std::setw(11) << number(v.lambda2)
      << std::setw(11) << (v.curvature_ratio ? number(*v.curvature_ratio) : "-") << verdict_word(v.verdict)
      << (v.verdict.c1 && v.semi_sharp == 0 ? "" : ": " + v.verdict.reason) << "\n";
  s << a.summary << "\n";
  return s.str();
}

}  // namespace cifs::cli
