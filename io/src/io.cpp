// SPDX-License-Identifier: MIT
// cifs — the dispatcher: one table of formats per kind of content. A new format is a new file (its
// reader and writer) and one line here.
#include "cifs/io/io.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/cad.hpp"
#include "cifs/io/dot.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/mesh_formats.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/io/ply.hpp"
#include "cifs/io/svg.hpp"
#include "points_format.hpp"

namespace cifs::io {
namespace {

/// One format of content T: its writer (the bytes, a chunk at a time, into a sink) and its reader
/// (null when it does not write or read).
template <class T>
struct Codec {
  std::string_view name, extension;
  void (*write)(const T&, ByteSink&) = nullptr;
  T (*read)(std::string_view text, const std::filesystem::path& path) = nullptr;
  bool binary = false;
};

/// A reader whose messages name the file by its path.
template <class T, T (*parse)(std::string_view, std::string_view)>
T parse_at(std::string_view text, const std::filesystem::path& path) {
  return parse(text, path.string());
}

Mesh parse_mesh_obj_at(std::string_view text, std::string_view where) {
  return parse_mesh_obj(text, where);
}
Mesh parse_mesh_stl_at(std::string_view text, std::string_view where) {
  return parse_mesh_stl(text, where);
}
Mesh parse_mesh_off_at(std::string_view text, std::string_view where) {
  return parse_mesh_off(text, where);
}

Shape parse_shape_json_at(std::string_view text, const std::filesystem::path& path) {
  return parse_shape_json(text, path.string());
}

Shape parse_one_obj_shape(std::string_view text, const std::filesystem::path& path) {
  return select_shape(parse_obj(text, path.string()), {}, path.string());
}

/// STEP and IGES through the codec cifs::occt plugs in (cifs/io/cad.hpp): "built without OpenCASCADE"
/// until it does.
template <CadFormat F>
void write_cad(const Shape& shape, ByteSink& out) {
  out.write(cad_codec(F == CadFormat::step ? "STEP" : "IGES").write({&shape, 1}, F));
}
template <CadFormat F>
Shape parse_one_cad(std::string_view text, const std::filesystem::path& path) {
  return select_shape(cad_codec(path.string()).read(text, path, F, {}), {}, path.string());
}

Experiment parse_experiment_at(std::string_view text, const std::filesystem::path& path) {
  Experiment e = parse_experiment(text, path.filename().string(), path.parent_path());
  if (e.name.empty()) e.name = path.stem().string();
  e.inputs.insert(e.inputs.begin(), path);
  return e;
}

/// A writer of content T whose format builds its text whole (small files: shapes, automata).
template <class T, std::string (*text)(const T&)>
void whole(const T& thing, ByteSink& out) {
  out.write(text(thing));
}

/// Points written from memory: the chunked writer over all of them.
void write_points(const detail::PointsFormat& f, const Points& P, const PointsStyle& style, ByteSink& out) {
  PointsWriter w(out, f.name, static_cast<std::uint64_t>(P.rows()), P.cols(), style);
  w.write(P);
  w.finish();
}

template <const detail::PointsFormat& F>
void point_set(const PointSet& set, ByteSink& out) {
  write_points(F, set.points, set.style, out);
}

// The table. Order matters where several formats are written at once (experiment outputs).
const Codec<Shape> kShape[] = {
    {"json", ".json", [](const Shape& s, ByteSink& out) { write_json(s, out); }, parse_shape_json_at},
    {"obj", ".obj", whole<Shape, to_obj>, parse_one_obj_shape},
    {"step", ".step", write_cad<CadFormat::step>, parse_one_cad<CadFormat::step>},
    {"stp", ".stp", write_cad<CadFormat::step>, parse_one_cad<CadFormat::step>},
    {"iges", ".iges", write_cad<CadFormat::iges>, parse_one_cad<CadFormat::iges>},
    {"igs", ".igs", write_cad<CadFormat::iges>, parse_one_cad<CadFormat::iges>},
};
const Codec<Polygon> kPolygon[] = {
    {"json", ".json", whole<Polygon, to_json>, parse_at<Polygon, parse_polygon_json>},
    {"obj", ".obj",
     [](const Polygon& p, ByteSink& out) {
       write_points(detail::kObjPoints, p.points, {.polyline = true, .closed = p.closed, .seed = {}}, out);
     }},
    {"svg", ".svg", [](const Polygon& p, ByteSink& out) { out.write(polyline_svg(p.points, p.closed)); }},
};
const Codec<Mesh> kMesh[] = {
    {"obj", ".obj", [](const Mesh& m, ByteSink& out) { mesh_obj(m, out); },
     parse_at<Mesh, parse_mesh_obj_at>},
    {"ply", ".ply", [](const Mesh& m, ByteSink& out) { mesh_ply(m, PlyFormat::binary_little_endian, out); },
     parse_at<Mesh, parse_mesh_ply>, true},
    {"stl", ".stl", mesh_stl, parse_at<Mesh, parse_mesh_stl_at>, true},
    {"off", ".off", mesh_off, parse_at<Mesh, parse_mesh_off_at>},
    {"vtp", ".vtp", mesh_vtp, nullptr, true},
};
const Codec<Segments> kSegments[] = {
    {"obj", ".obj", [](const Segments& s, ByteSink& out) { segments_obj(s, out); }},
    {"ply", ".ply",
     [](const Segments& s, ByteSink& out) { segments_ply(s, PlyFormat::binary_little_endian, out); }, nullptr,
     true},
    {"svg", ".svg", [](const Segments& s, ByteSink& out) { segments_svg(s, {}, out); }},
};
/// Point sets: the writers take rows a chunk at a time (PointsWriter), from memory or as computed.
const Codec<PointSet> kPoints[] = {
    {"json", ".json", point_set<detail::kJsonPoints>},
    {"npy", ".npy", point_set<detail::kNpyPoints>, nullptr, true},
    {"ply", ".ply", point_set<detail::kPlyPoints>, nullptr, true},
    {"obj", ".obj", point_set<detail::kObjPoints>},
};
/// The chunked writers behind kPoints, which PointsWriter finds by name.
const detail::PointsFormat* const kPointsFormats[] = {&detail::kJsonPoints, &detail::kNpyPoints,
                                                      &detail::kPlyPoints, &detail::kObjPoints};
const Codec<nurbs::KnotAutomaton> kAutomaton[] = {
    {"json", ".json", whole<nurbs::KnotAutomaton, to_json>,
     parse_at<nurbs::KnotAutomaton, parse_automaton_json>},
    {"svg", ".svg", [](const nurbs::KnotAutomaton& a, ByteSink& out) { out.write(to_svg(a.automaton)); }},
    {"dot", ".dot", whole<nurbs::KnotAutomaton, to_dot>},
};
const Codec<BcifsFile> kBcifs[] = {
    {"json", ".json", [](const BcifsFile& f, ByteSink& out) { out.write(to_json(f.system, f.nets)); },
     parse_at<BcifsFile, parse_bcifs_json>},
};
const Codec<Experiment> kExperiment[] = {
    {"json", ".json", nullptr, parse_experiment_at},
};

std::span<const Codec<Shape>> codecs(const Shape*) {
  return kShape;
}
std::span<const Codec<Polygon>> codecs(const Polygon*) {
  return kPolygon;
}
std::span<const Codec<Mesh>> codecs(const Mesh*) {
  return kMesh;
}
std::span<const Codec<Segments>> codecs(const Segments*) {
  return kSegments;
}
std::span<const Codec<PointSet>> codecs(const PointSet*) {
  return kPoints;
}
std::span<const Codec<nurbs::KnotAutomaton>> codecs(const nurbs::KnotAutomaton*) {
  return kAutomaton;
}
std::span<const Codec<BcifsFile>> codecs(const BcifsFile*) {
  return kBcifs;
}
std::span<const Codec<Experiment>> codecs(const Experiment*) {
  return kExperiment;
}

template <class T>
std::span<const Codec<T>> table() {
  return codecs(static_cast<const T*>(nullptr));
}

template <class T>
std::vector<Format> formats_of() {
  std::vector<Format> out;
  for (const Codec<T>& c : table<T>())
    out.push_back({c.name, c.extension, c.read != nullptr, c.write != nullptr, c.binary});
  return out;
}

/// "a, b or c" of the names (or extensions) of the formats that write (or read).
std::string listing(std::span<const Format> formats, bool write, bool extensions) {
  std::vector<std::string_view> names;
  for (const Format& f : formats)
    if (write ? f.write : f.read) names.push_back(extensions ? f.extension : f.name);
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + std::string(names[i]);
  return out;
}

/// The numbers of what is written, checked before its first byte (detail::check_finite). Shapes,
/// automata and BC-IFS files are checked when they are made; points, polygons, meshes and segments
/// are computed results.
template <class T>
void check_numbers(const T&) {}
void check_numbers(const PointSet& p) {
  detail::check_finite(p.points, "the points");
}
void check_numbers(const Polygon& p) {
  detail::check_finite(p.points, "the polygon");
}
void check_numbers(const Mesh& m) {
  detail::check_finite(m.vertices, "the mesh's vertices");
  detail::check_finite(m.normals, "the mesh's normals");
}
void check_numbers(const Segments& s) {
  detail::check_finite(s.vertices, "the segments' vertices");
}

template <class T>
void encode_as(const T& thing, Content content, std::string_view format, ByteSink& out) {
  check_numbers(thing);
  for (const Codec<T>& c : table<T>())
    if (c.write && c.name == format) return c.write(thing, out);
  writable_format(content, format, "format");  // throws, naming the formats
}

template <class T>
std::string encode_as(const T& thing, Content content, std::string_view format) {
  StringSink out;
  encode_as(thing, content, format, out);
  return std::move(out.bytes);
}

template <class T>
void write_as(const std::filesystem::path& path, const T& thing, Content content) {
  const Format format = format_of(path, content);  // refused before anything is created
  AtomicFile file(path);
  encode_as(thing, content, format.name, file);
  file.commit();
}

/// The reader of the path's extension, else JSON where JSON is the content's own format.
template <class T>
T read_as(const std::filesystem::path& path, Content content) {
  const std::string extension = extension_of(path);
  const Codec<T>* chosen = nullptr;
  for (const Codec<T>& c : table<T>())
    if (c.read && c.extension == extension) chosen = &c;
  if (!chosen && table<T>().front().name == "json") chosen = &table<T>().front();
  if (!chosen)
    throw IoError(path.string() + ": " + std::string(content_name(content)) + " is read from " +
                  listing(formats(content), false, true));
  return chosen->read(read_file(path), path);
}

}  // namespace

std::string_view content_name(Content content) {
  switch (content) {
    case Content::shape:
      return "a shape";
    case Content::polygon:
      return "a polygon";
    case Content::mesh:
      return "a mesh";
    case Content::segments:
      return "a segment set";
    case Content::points:
      return "a point set";
    case Content::automaton:
      return "an automaton";
    case Content::bcifs:
      return "a BC-IFS";
    case Content::experiment:
      return "an experiment";
  }
  return "";
}

std::vector<Format> formats(Content content) {
  switch (content) {
    case Content::shape:
      return formats_of<Shape>();
    case Content::polygon:
      return formats_of<Polygon>();
    case Content::mesh:
      return formats_of<Mesh>();
    case Content::segments:
      return formats_of<Segments>();
    case Content::points:
      return formats_of<PointSet>();
    case Content::automaton:
      return formats_of<nurbs::KnotAutomaton>();
    case Content::bcifs:
      return formats_of<BcifsFile>();
    case Content::experiment:
      return formats_of<Experiment>();
  }
  return {};
}

Format writable_format(Content content, std::string_view name, std::string_view who) {
  const std::vector<Format> all = formats(content);
  for (const Format& f : all)
    if (f.write && f.name == name) return f;
  throw InvalidInput(std::string(who) + " '" + std::string(name) + "': expected " +
                     listing(all, true, false));
}

void encode(const Mesh& mesh, std::string_view format, ByteSink& out) {
  encode_as(mesh, Content::mesh, format, out);
}
void encode(const Segments& segments, std::string_view format, ByteSink& out) {
  encode_as(segments, Content::segments, format, out);
}
void encode(const nurbs::KnotAutomaton& automaton, std::string_view format, ByteSink& out) {
  encode_as(automaton, Content::automaton, format, out);
}

Format format_of(const std::filesystem::path& path, Content content) {
  const std::vector<Format> all = formats(content);
  for (const Format& f : all)
    if (f.write && f.extension == extension_of(path)) return f;
  throw InvalidInput(path.string() + ": " + std::string(content_name(content)) + " is written as " +
                     listing(all, true, true));
}

void detail::check_finite(const Eigen::Ref<const Points>& rows, std::string_view what, std::uint64_t first) {
  if (rows.allFinite()) return;
  for (Eigen::Index r = 0; r < rows.rows(); ++r)
    for (Eigen::Index c = 0; c < rows.cols(); ++c)
      if (!std::isfinite(rows(r, c)))
        throw InvalidInput(
            std::string(what) + ": point " + std::to_string(first + static_cast<std::uint64_t>(r)) +
            " coordinate " + std::to_string(c) +
            " is not a finite number (an overflow or 0/0 in the computation); nothing is written");
}

const detail::PointsFormat& detail::points_format(std::string_view name, std::string_view who) {
  for (const PointsFormat* f : kPointsFormats)
    if (f->name == name) return *f;
  writable_format(Content::points, name, who);  // throws, naming the formats
  throw InvalidInput(std::string(name) + ": not a point-set format");
}

std::string_view detail::points_format_of(const std::filesystem::path& path) {
  return points_format(format_of(path, Content::points).name, "format").name;
}

std::string encode(const Shape& shape, std::string_view format) {
  return encode_as(shape, Content::shape, format);
}
std::string encode(const Polygon& polygon, std::string_view format) {
  return encode_as(polygon, Content::polygon, format);
}
std::string encode(const Mesh& mesh, std::string_view format) {
  return encode_as(mesh, Content::mesh, format);
}
std::string encode(const Segments& segments, std::string_view format) {
  return encode_as(segments, Content::segments, format);
}
std::string encode(const PointSet& points, std::string_view format) {
  return encode_as(points, Content::points, format);
}
std::string encode(const nurbs::KnotAutomaton& automaton, std::string_view format) {
  return encode_as(automaton, Content::automaton, format);
}

std::string encode(const automata::Automaton& automaton, std::string_view format) {
  return encode(nurbs::without_knots(automaton), format);
}
std::string encode(const BcifsFile& file, std::string_view format) {
  return encode_as(file, Content::bcifs, format);
}

void write(const std::filesystem::path& path, const Shape& shape) {
  if (cad_format(path)) return write(path, std::span<const Shape>(&shape, 1));  // messages name the path
  write_as(path, shape, Content::shape);
}
void write(const std::filesystem::path& path, std::span<const Shape> shapes) {
  const std::optional<CadFormat> cad = cad_format(path);
  if (!cad) {
    if (shapes.size() != 1)
      throw InvalidInput(path.string() + ": " + std::to_string(shapes.size()) +
                         " shapes: only STEP and IGES files hold several; choose one with --index N");
    return write(path, shapes.front());
  }
  const CadCodec& codec = cad_codec(path.string());
  format_of(path, Content::shape);  // the extensions written (.step, .stp, .iges, .igs)
  AtomicFile file(path);
  try {
    file.write(codec.write(shapes, *cad));
  } catch (const InvalidInput& e) {
    throw InvalidInput(path.string() + ": " + e.what());
  }
  file.commit();
}
void write(const std::filesystem::path& path, const Polygon& polygon) {
  write_as(path, polygon, Content::polygon);
}
void write(const std::filesystem::path& path, const Mesh& mesh) {
  write_as(path, mesh, Content::mesh);
}
void write(const std::filesystem::path& path, const Segments& segments) {
  write_as(path, segments, Content::segments);
}
void write(const std::filesystem::path& path, const PointSet& points) {
  write_as(path, points, Content::points);
}
void write(const std::filesystem::path& path, const nurbs::KnotAutomaton& automaton) {
  write_as(path, automaton, Content::automaton);
}

void write(const std::filesystem::path& path, const automata::Automaton& automaton) {
  write(path, nurbs::without_knots(automaton));
}
void write(const std::filesystem::path& path, const BcifsFile& file) {
  write_as(path, file, Content::bcifs);
}

std::vector<Shape> read_shapes(const std::filesystem::path& path, const ShapeReadOptions& options) {
  // The readers of the table, with the options: OBJ by extension, JSON otherwise.
  if (const std::optional<CadFormat> cad = cad_format(path)) {
    const CadCodec& codec = cad_codec(path.string());  // before reading: a build without it says so first
    return codec.read(read_file(path), path, *cad, options);
  }
  const std::string text = read_file(path);
  if (extension_of(path) == ".obj") return parse_obj(text, path.string(), options);
  return parse_shapes_json(text, path.string(), options);
}
Shape read_shape(const std::filesystem::path& path, const ShapeReadOptions& options) {
  return select_shape(read_shapes(path, options), options, path.string());
}
Polygon read_polygon(const std::filesystem::path& path) {
  return read_as<Polygon>(path, Content::polygon);
}
Mesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options) {
  // The readers that warn take the options; the table's readers use the defaults.
  const std::string extension = extension_of(path);
  if (extension == ".obj") return parse_mesh_obj(read_file(path), path.string(), options);
  if (extension == ".stl") return parse_mesh_stl(read_file(path), path.string(), options);
  if (extension == ".off") return parse_mesh_off(read_file(path), path.string(), options);
  return read_as<Mesh>(path, Content::mesh);
}

std::string mesh_left_out(const Mesh& mesh, std::string_view format) {
  if (format == "obj") return "";
  std::vector<std::string> parts;
  const auto count = [&](std::size_t n, const std::string& what) {
    if (n > 0) parts.push_back(std::to_string(n) + " " + what + (n == 1 ? "" : "s"));
  };
  // No format but OBJ holds tags or face-varying channels.
  count(mesh.tags.holes.size(), "hole face");
  count(static_cast<std::size_t>(std::count_if(mesh.tags.creases.begin(), mesh.tags.creases.end(),
                                               [](const EdgeSharpness& c) { return c.sharpness > 0; })),
        "crease");
  count(static_cast<std::size_t>(std::count_if(mesh.tags.corners.begin(), mesh.tags.corners.end(),
                                               [](const VertexSharpness& c) { return c.sharpness > 0; })),
        "corner");
  count(mesh.tags.concave.size(), "concave corner");
  if (mesh.tags.rules != RuleSet::opensubdiv)
    parts.push_back("the rule set '" + std::string(option_name(mesh.tags.rules)) + "'");
  for (const FaceVaryingChannel& c : mesh.face_varying)
    parts.push_back("the face-varying channel '" + c.name + "'");
  if (format == "stl" && mesh.normals.size() != 0) parts.emplace_back("the normals");
  if ((format == "stl" || format == "off") && !mesh.states.empty()) parts.emplace_back("the face states");
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i)
    out += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  return out;
}
nurbs::KnotAutomaton read_automaton(const std::filesystem::path& path) {
  return read_as<nurbs::KnotAutomaton>(path, Content::automaton);
}
BcifsFile read_bcifs(const std::filesystem::path& path) {
  return read_as<BcifsFile>(path, Content::bcifs);
}
Experiment read_experiment(const std::filesystem::path& path) {
  return read_as<Experiment>(path, Content::experiment);
}

Experiment read_as_experiment(const std::filesystem::path& path) {
  const Content content = detect(path);
  if (content == Content::experiment) return read_experiment(path);
  Experiment e;
  e.name = path.stem().string();
  if (content == Content::mesh) {
    Mesh mesh = read_mesh(path);
    const bool triangles =
        std::adjacent_find(mesh.face_offsets.begin(), mesh.face_offsets.end(),
                           [](int a, int b) { return b - a != 3; }) == mesh.face_offsets.end();
    e.mesh = MeshSource{
        .path = path,
        .mesh = std::move(mesh),
        .scheme = triangles ? subdivision::MeshScheme::loop : subdivision::MeshScheme::catmull_clark,
        .levels = 2,
        .limit = false};
  } else if (content == Content::shape) {
    e.shape = read_shape(path);
  } else if (content == Content::bcifs) {
    (void)read_bcifs(path);  // refused here, as every input before the first run
    e.automaton = std::filesystem::absolute(path);
  } else {
    throw InvalidInput(
        path.string() + ": " + std::string(content_name(content)) +
        ", not a shape, mesh, BC-IFS or experiment file; an experiment file renders it (\"polygon\": \"" +
        path.filename().string() + "\", docs/experiments.md)");
  }
  e.render.control_net = true;
  e.outputs.exr = e.name + ".exr";
  e.outputs.png = e.name + ".png";
  e.inputs = {path};
  return e;
}

}  // namespace cifs::io
