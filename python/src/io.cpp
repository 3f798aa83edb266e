// SPDX-License-Identifier: MIT
// cifs Python bindings — cifs.io (shape, polygon, mesh, automaton and experiment files, the format
// table and the dispatcher),
// cifs.verify (the attractor against the NURBS core) and cifs.experiment (running experiment files).
#include <cmath>
#include <filesystem>
#include <optional>
#include <string_view>
#include <type_traits>
#include <variant>

#include "arrays.hpp"
#include "cifs/experiment/dimension.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/io/ply.hpp"
#include "cifs/io/svg.hpp"
#include "cifs/verify/check.hpp"

namespace cifs::python {
namespace {

using Release = py::call_guard<py::gil_scoped_release>;
constexpr const char* kDefaultWhere = "<string>";

/// Binary files are not text: bytes for them, str for the others.
py::object file_result(const std::string& text, bool binary) {
  if (binary) return py::bytes(text);
  return py::str(text);
}

io::Content content_of(const io::Shape*) {
  return io::Content::shape;
}
io::Content content_of(const io::Polygon*) {
  return io::Content::polygon;
}
io::Content content_of(const Mesh*) {
  return io::Content::mesh;
}
io::Content content_of(const Segments*) {
  return io::Content::segments;
}
io::Content content_of(const nurbs::KnotAutomaton*) {
  return io::Content::automaton;
}
io::Content content_of(const io::BcifsFile*) {
  return io::Content::bcifs;
}

/// Text or bytes as the bytes they hold (UTF-8 for str).
std::string bytes_of(const py::object& data, const char* where) {
  if (py::isinstance<py::bytes>(data)) return data.cast<std::string>();
  if (py::isinstance<py::str>(data)) return data.cast<std::string>();
  throw InvalidInput(std::string(where) + ": expected str or bytes");
}

io::Polygon make_polygon(const DoubleArray& points, bool closed) {
  io::Polygon p{points_from(points, "points"), closed};
  if (p.points.rows() == 0) throw InvalidInput("points: no points");
  if (p.points.cols() < 1 || p.points.cols() > 16)
    throw InvalidInput("points: " + std::to_string(p.points.cols()) + " coordinates, expected 1 to 16");
  for (Eigen::Index i = 0; i < p.points.rows(); ++i)
    if (!p.points.row(i).allFinite())
      throw InvalidInput("points[" + std::to_string(i) + "]: coordinate is not finite");
  return p;
}

/// `faces`: a sequence of sequences of vertex indices (any sizes).
void add_faces(Mesh& mesh, const py::object& faces) {
  if (!py::isinstance<py::sequence>(faces) || py::isinstance<py::str>(faces))
    throw InvalidInput("Mesh: faces: expected a list of lists of vertex indices");
  std::size_t f = 0;
  for (const py::handle face : faces) {
    const std::string where = "Mesh: faces[" + std::to_string(f++) + "]";
    const std::vector<int> corners = ints_from(face, where);
    add_face(mesh, corners);
  }
}

MeshTags make_tags(const std::optional<std::vector<EdgeSharpness>>& creases,
                   const std::optional<std::vector<VertexSharpness>>& corners,
                   const std::optional<std::vector<int>>& holes, const std::string& boundary,
                   const std::string& crease_method, const std::string& triangles,
                   const std::string& fvar_interpolation, const std::string& rules,
                   const std::optional<std::vector<int>>& concave) {
  MeshTags tags;
  tags.creases = creases.value_or(std::vector<EdgeSharpness>{});
  tags.corners = corners.value_or(std::vector<VertexSharpness>{});
  tags.holes = holes.value_or(std::vector<int>{});
  if (!boundary.empty()) tags.boundary = named_boundary_rule(boundary);
  if (!crease_method.empty()) tags.crease_method = named_crease_method(crease_method);
  if (!triangles.empty()) tags.triangles = named_triangle_rule(triangles);
  if (!fvar_interpolation.empty()) tags.face_varying = named_face_varying_rule(fvar_interpolation);
  if (!rules.empty()) tags.rules = named_rule_set(rules);
  tags.concave = concave.value_or(std::vector<int>{});
  return tags;
}

/// Sharpness as the tags take it: finite and ≥ 0.
double sharpness_from(double s, const char* where) {
  if (!std::isfinite(s) || s < 0)
    throw InvalidInput(std::string(where) + ": sharpness must be finite and >= 0 (" +
                       std::to_string(kInfiniteSharpness) + " or more: infinitely sharp)");
  return s;
}

/// Triangles and quads (the C++ order: triangles first), or `faces`, or face_offsets and
/// face_vertices; one of the three.
Mesh make_plain_mesh(const DoubleArray& vertices, const py::object& triangles, const py::object& quads,
                     const std::optional<DoubleArray>& normals,
                     const std::optional<std::vector<std::uint32_t>>& states, const py::object& faces,
                     const py::object& face_offsets, const py::object& face_vertices) {
  const bool tables = !triangles.is_none() || !quads.is_none();
  const bool lists = !faces.is_none();
  const bool arrays = !face_offsets.is_none() || !face_vertices.is_none();
  if (int(tables) + int(lists) + int(arrays) > 1)
    throw InvalidInput("Mesh: give triangles and quads, or faces, or face_offsets and face_vertices");
  Points V = points_from(vertices, "Mesh: vertices");
  Points N;
  if (normals) N = points_from(*normals, "Mesh: normals");
  std::vector<std::uint32_t> S = states.value_or(std::vector<std::uint32_t>{});
  if (!lists && !arrays)
    return mesh_from_tables(std::move(V), index_rows<3>(triangles, "Mesh: triangles"),
                            index_rows<4>(quads, "Mesh: quads"), std::move(N), std::move(S), "Mesh");
  Mesh mesh;
  mesh.vertices = std::move(V);
  if (lists) {
    add_faces(mesh, faces);
  } else {
    if (face_offsets.is_none() || face_vertices.is_none())
      throw InvalidInput("Mesh: face_offsets and face_vertices go together");
    mesh.face_offsets = ints_from(face_offsets, "Mesh: face_offsets");
    mesh.face_vertices = ints_from(face_vertices, "Mesh: face_vertices");
  }
  mesh.normals = std::move(N);
  mesh.states = std::move(S);
  check_mesh(mesh, "Mesh");
  return mesh;
}

/// make_plain_mesh with tags and face-varying channels.
Mesh make_mesh(const DoubleArray& vertices, const py::object& triangles, const py::object& quads,
               const std::optional<DoubleArray>& normals,
               const std::optional<std::vector<std::uint32_t>>& states, const py::object& faces,
               const py::object& face_offsets, const py::object& face_vertices,
               const std::optional<MeshTags>& tags,
               const std::optional<std::vector<FaceVaryingChannel>>& face_varying) {
  Mesh mesh =
      make_plain_mesh(vertices, triangles, quads, normals, states, faces, face_offsets, face_vertices);
  if (tags) mesh.tags = *tags;
  mesh.face_varying = face_varying.value_or(std::vector<FaceVaryingChannel>{});
  check_mesh(mesh, "Mesh");
  return mesh;
}

/// The faces with `n` corners as an integer array (F, n).
template <std::size_t N>
py::array_t<int> faces_of_size(const Mesh& mesh) {
  std::vector<std::array<int, N>> rows;
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    const auto c = face(mesh, f);
    if (c.size() != N) continue;
    std::array<int, N> row;
    std::copy(c.begin(), c.end(), row.begin());
    rows.push_back(row);
  }
  return index_array(rows);
}

Segments make_segments(const DoubleArray& vertices, const py::object& segments,
                       const std::optional<std::vector<std::uint32_t>>& states) {
  Segments out;
  out.vertices = points_from(vertices, "Segments: vertices");
  out.segments = index_rows<2>(segments, "Segments: segments");
  if (states) out.states = *states;
  check_segments(out, "Segments");
  return out;
}

const char* mode_name(io::EvaluationSpec::Mode mode) {
  switch (mode) {
    case io::EvaluationSpec::Mode::depth:
      return "depth";
    case io::EvaluationSpec::Mode::tolerance:
      return "tolerance";
    case io::EvaluationSpec::Mode::chaos:
      return "chaos";
  }
  return "";
}

std::string source_kind(const io::Experiment& e) {
  if (e.shape) return std::holds_alternative<nurbs::Curve>(*e.shape) ? "curve" : "surface";
  if (!e.automaton.empty()) return "automaton";
  if (e.mesh) return "mesh";
  if (e.junction) return "junction";
  return "ifs";
}

void bind_shapes(py::module_& m) {
  // Warnings (a range clamped to the knot domain, trims ignored) go to stderr.
  const auto options = [](std::optional<std::size_t> index, bool ignore_trim) {
    return io::ShapeReadOptions{.ignore_trim = ignore_trim, .index = index, .warn = {}};
  };
  m.def(
      "read_shape",
      [options](const std::filesystem::path& path, std::optional<std::size_t> index, bool ignore_trim) {
        return io::read_shape(path, options(index, ignore_trim));
      },
      Release(), py::arg("path"), py::kw_only(), py::arg("index") = py::none(),
      py::arg("ignore_trim").noconvert() = false,
      "Reads a shape file: `.obj` as OBJ free-form geometry, anything else as JSON (cifs's own format or a\n"
      "geomdl export). A file of several shapes needs `index` (0-based); ignore_trim=True reads trimmed\n"
      "surfaces whole, with a warning on stderr.\n\n"
      "Returns a nurbs.Curve or nurbs.Surface. Raises IoError (unreadable file, syntax) or InvalidInput\n"
      "(content), with the path and JSON path in the message.");
  m.def(
      "read_shapes",
      [options](const std::filesystem::path& path, bool ignore_trim) {
        return io::read_shapes(path, options(std::nullopt, ignore_trim));
      },
      Release(), py::arg("path"), py::kw_only(), py::arg("ignore_trim").noconvert() = false,
      "Every curve and surface of a shape file, in order (list of Curve / Surface); see read_shape.");
  m.def(
      "parse_shape_json",
      [options](std::string_view text, std::string_view where, std::optional<std::size_t> index,
                bool ignore_trim) { return io::parse_shape_json(text, where, options(index, ignore_trim)); },
      py::arg("text"), py::arg("where") = kDefaultWhere, py::kw_only(), py::arg("index") = py::none(),
      py::arg("ignore_trim").noconvert() = false,
      "Parses {\"curve\": {...}} or {\"surface\": {...}} (docs/formats.md), or a geomdl export ({\"shape\":\n"
      "...}, `index` choosing among several); `where` names the source in messages. Returns a nurbs.Curve "
      "or\n"
      "nurbs.Surface. Raises IoError (syntax) or InvalidInput (content).");
  m.def("to_json", py::overload_cast<const io::Shape&>(&io::to_json), py::arg("shape"),
        "The shape file text (JSON) of a nurbs.Curve or nurbs.Surface; parse_shape_json reads it back.");
  m.def(
      "parse_volume_json",
      [](std::string_view text, std::string_view where, std::optional<std::size_t> index) {
        return io::parse_volume_json(text, where, {.ignore_trim = false, .index = index, .warn = {}});
      },
      py::arg("text"), py::arg("where") = kDefaultWhere, py::kw_only(), py::arg("index") = py::none(),
      "Parses {\"volume\": {...}} (docs/formats.md: points[i][j][k]) or a geomdl export of type \"volume\"\n"
      "(`index` choosing among several). Returns a nurbs.Volume. Raises IoError (syntax) or InvalidInput.");
  m.def(
      "read_volume",
      [](const std::filesystem::path& path, std::optional<std::size_t> index) {
        return io::parse_volume_json(read_file(path), path.string(),
                                     {.ignore_trim = false, .index = index, .warn = {}});
      },
      Release(), py::arg("path"), py::kw_only(), py::arg("index") = py::none(),
      "Reads a volume file (JSON, as parse_volume_json). Raises IoError or InvalidInput naming the path.");
  m.def("to_json", py::overload_cast<const nurbs::Volume&>(&io::to_json), py::arg("volume"),
        "The volume file text (JSON) of a nurbs.Volume; parse_volume_json reads it back.");
  m.def(
      "parse_obj",
      [options](std::string_view text, std::string_view where, bool ignore_trim) {
        return io::parse_obj(text, where, options(std::nullopt, ignore_trim));
      },
      py::arg("text"), py::arg("where") = kDefaultWhere, py::kw_only(),
      py::arg("ignore_trim").noconvert() = false,
      "Every curve and surface of OBJ free-form geometry text, in order (list of Curve / Surface), each "
      "over\n"
      "the range its curv or surf statement gives. ignore_trim=True reads trimmed surfaces whole, with a\n"
      "warning on stderr.\n\n"
      "Raises IoError or InvalidInput naming `where`.");
  m.def("to_obj", &io::to_obj, py::arg("shape"),
        "OBJ free-form geometry text of a nurbs.Curve or nurbs.Surface.");
  m.def(
      "write_file_atomically",
      [](const std::filesystem::path& path, const std::string& content) {
        write_file_atomically(path, content);
      },
      Release(), py::arg("path"), py::arg("content"),
      "Writes `content` (str, UTF-8, or bytes) through a temporary file and a rename: `path` never holds\n"
      "a partial file. A symbolic link is written through; a folder, a device, a FIFO or a missing\n"
      "folder is refused. Raises IoError.");
  m.def(
      "read_file",
      [](const std::filesystem::path& path, bool binary) -> py::object {
        std::string text;
        {
          py::gil_scoped_release release;
          text = read_file(path);
        }
        if (binary) return py::bytes(text);
        return py::str(text);
      },
      py::arg("path"), py::kw_only(), py::arg("binary").noconvert() = false,
      "The whole file: str (UTF-8), or bytes with binary=True.\n\nRaises IoError naming the path.");
}

void bind_polygons(py::module_& m) {
  py::class_<io::Polygon>(m, "Polygon",
                          "A control polygon (input of subdivision schemes and uniform B-splines).")
      .def(py::init(&make_polygon), py::arg("points"), py::arg("closed").noconvert() = false,
           "points: (n, dim) with n ≥ 1, 1 ≤ dim ≤ 16, finite. Raises InvalidInput otherwise.")
      .def_property_readonly(
          "points", [](const io::Polygon& p) { return Points(p.points); }, "The vertices (n, dim).")
      .def_readonly("closed", &io::Polygon::closed, "True when the last vertex connects back to the first.")
      .def(
          "__repr__",
          [](const io::Polygon& p) {
            return "Polygon(points=" + std::to_string(p.points.rows()) +
                   ", dimension=" + std::to_string(p.points.cols()) + (p.closed ? ", closed)" : ")");
          },
          "Short description.");
  m.def("parse_polygon_json", &io::parse_polygon_json, py::arg("text"), py::arg("where") = kDefaultWhere,
        "Parses {\"polygon\": {\"points\": [[x, y], ...], \"closed\": true}}.\n\n"
        "Raises IoError (syntax) or InvalidInput (content) naming `where` and the JSON path.");
  m.def("read_polygon", &io::read_polygon, Release(), py::arg("path"),
        "Reads a polygon file. Raises IoError or InvalidInput naming the path.");
  m.def("to_json", py::overload_cast<const io::Polygon&>(&io::to_json), py::arg("polygon"),
        "The polygon file text (JSON, round-trip precision); parse_polygon_json reads it back bit for bit.");
}

/// Polylines as OBJ and SVG text.
void bind_geometry_polylines(py::module_& m) {
  m.def(
      "polyline_obj",
      [](const DoubleArray& points, bool closed) {
        return io::polyline_obj(points_from(points, "points"), closed);
      },
      py::arg("points"), py::arg("closed").noconvert() = false,
      "OBJ text of a polyline (n, dim ≤ 3): one `v` line per point and one `l` element.\n\n"
      "Raises InvalidInput for more than 3 coordinates.");
  m.def(
      "polyline_svg",
      [](const DoubleArray& points, bool closed, int width, double stroke) {
        return io::polyline_svg(points_from(points, "points"), closed, width, stroke);
      },
      py::arg("points"), py::arg("closed").noconvert() = false, py::arg("width") = 800,
      py::arg("stroke") = 1.5,
      "SVG text of the x, y coordinates of a polyline (n, dim ≥ 2), `width` pixels wide.\n\n"
      "Raises InvalidInput for bad points, width or stroke.");
}

/// The tags of production meshes: sharp edges and vertices, the tags, face-varying channels.
void bind_mesh_tags(py::module_& m) {
  py::class_<EdgeSharpness>(m, "EdgeSharpness",
                            "A sharp edge: its two vertices (either order) and sharpness.")
      .def(py::init([](int a, int b, double sharpness) {
             return EdgeSharpness{.a = non_negative(a, "EdgeSharpness: a"),
                                  .b = non_negative(b, "EdgeSharpness: b"),
                                  .sharpness = sharpness_from(sharpness, "EdgeSharpness")};
           }),
           py::arg("a"), py::arg("b"), py::arg("sharpness"),
           "a, b: 0-based vertex rows. sharpness: >= 0; 0 smooth, 10 or more infinitely sharp.")
      .def_readonly("a", &EdgeSharpness::a, "First vertex.")
      .def_readonly("b", &EdgeSharpness::b, "Second vertex.")
      .def_readonly("sharpness", &EdgeSharpness::sharpness, "Sharpness (0 smooth, 10 or more infinite).")
      .def(
          "__repr__",
          [](const EdgeSharpness& e) {
            return "EdgeSharpness(a=" + std::to_string(e.a) + ", b=" + std::to_string(e.b) +
                   ", sharpness=" + number_text(e.sharpness) + ")";
          },
          "Short description.");
  py::class_<VertexSharpness>(m, "VertexSharpness", "A sharp vertex (a corner): its row and sharpness.")
      .def(py::init([](int vertex, double sharpness) {
             return VertexSharpness{.vertex = non_negative(vertex, "VertexSharpness: vertex"),
                                    .sharpness = sharpness_from(sharpness, "VertexSharpness")};
           }),
           py::arg("vertex"), py::arg("sharpness"), "vertex: 0-based row. sharpness: >= 0.")
      .def_readonly("vertex", &VertexSharpness::vertex, "The vertex.")
      .def_readonly("sharpness", &VertexSharpness::sharpness, "Sharpness (0 smooth, 10 or more infinite).")
      .def(
          "__repr__",
          [](const VertexSharpness& v) {
            return "VertexSharpness(vertex=" + std::to_string(v.vertex) +
                   ", sharpness=" + number_text(v.sharpness) + ")";
          },
          "Short description.");
  py::class_<MeshTags>(
      m, "MeshTags",
      "Creases, corners, holes and the refinement options of a production mesh (OBJ `t` lines).")
      .def(
          py::init(&make_tags), py::kw_only(), py::arg("creases") = py::none(),
          py::arg("corners") = py::none(), py::arg("holes") = py::none(), py::arg("boundary") = "edge",
          py::arg("crease_method") = "uniform", py::arg("triangles") = "catmark",
          py::arg("fvar_interpolation") = "all", py::arg("rules") = "opensubdiv",
          py::arg("concave") = py::none(),
          "creases: list of EdgeSharpness; corners: list of VertexSharpness; holes: face indices.\n"
          "boundary: edge, corner or none; crease_method: uniform or chaikin; triangles: catmark or smooth;\n"
          "fvar_interpolation: none, corners-only, corners+1, corners+2, boundaries or all.\n"
          "rules: opensubdiv or blz (Biermann-Levin-Zorin 2000); concave: corner vertices (blz) whose\n"
          "sectors span 3pi/2.\n"
          "Indices are checked with the mesh (Mesh(..., tags=...)).")
      .def_readonly("creases", &MeshTags::creases, "The sharp edges (list of EdgeSharpness).")
      .def_readonly("corners", &MeshTags::corners, "The sharp vertices (list of VertexSharpness).")
      .def_property_readonly(
          "crease_edges",
          [](const MeshTags& t) {
            std::vector<std::array<int, 2>> rows;
            for (const EdgeSharpness& e : t.creases) rows.push_back({e.a, e.b});
            return index_array(rows);
          },
          "The creased edges as an int array (C, 2).")
      .def_property_readonly(
          "crease_sharpness",
          [](const MeshTags& t) {
            std::vector<double> s;
            for (const EdgeSharpness& e : t.creases) s.push_back(e.sharpness);
            return vector_array(s);
          },
          "The creases' sharpness (C,).")
      .def_property_readonly(
          "corner_vertices",
          [](const MeshTags& t) {
            std::vector<int> v;
            for (const VertexSharpness& c : t.corners) v.push_back(c.vertex);
            return vector_array(v);
          },
          "The corners' vertices (K,).")
      .def_property_readonly(
          "corner_sharpness",
          [](const MeshTags& t) {
            std::vector<double> s;
            for (const VertexSharpness& c : t.corners) s.push_back(c.sharpness);
            return vector_array(s);
          },
          "The corners' sharpness (K,).")
      .def_property_readonly(
          "holes", [](const MeshTags& t) { return vector_array(t.holes); }, "The hole faces (H,).")
      .def_property_readonly(
          "boundary", [](const MeshTags& t) { return std::string(option_name(t.boundary)); },
          "Boundary rule: edge, corner or none.")
      .def_property_readonly(
          "crease_method", [](const MeshTags& t) { return std::string(option_name(t.crease_method)); },
          "uniform or chaikin.")
      .def_property_readonly(
          "triangles", [](const MeshTags& t) { return std::string(option_name(t.triangles)); },
          "Catmull-Clark next to triangles: catmark or smooth.")
      .def_property_readonly(
          "rules", [](const MeshTags& t) { return std::string(option_name(t.rules)); },
          "Crease, boundary and corner rules: opensubdiv or blz.")
      .def_property_readonly(
          "concave", [](const MeshTags& t) { return vector_array(t.concave); },
          "The concave corners' vertices (blz rules).")
      .def_property_readonly(
          "fvar_interpolation", [](const MeshTags& t) { return std::string(option_name(t.face_varying)); },
          "Face-varying linear interpolation: none, corners-only, corners+1, corners+2, boundaries or all.")
      .def(
          "__repr__",
          [](const MeshTags& t) {
            return "MeshTags(creases=" + std::to_string(t.creases.size()) +
                   ", corners=" + std::to_string(t.corners.size()) +
                   ", holes=" + std::to_string(t.holes.size()) + ", boundary='" +
                   std::string(option_name(t.boundary)) + "')";
          },
          "Short description.");
  py::class_<FaceVaryingChannel>(m, "FaceVaryingChannel",
                                 "Face-varying data (UVs): value rows and one value index per face corner.")
      .def(py::init([](std::string name, const DoubleArray& values, std::vector<int> indices) {
             return FaceVaryingChannel{.name = std::move(name),
                                       .values = points_from(values, "FaceVaryingChannel: values"),
                                       .indices = std::move(indices)};
           }),
           py::arg("name"), py::arg("values"), py::arg("indices"),
           "values: (N, dim) floats; indices: one value row per face corner, parallel to Mesh.face_vertices\n"
           "(checked with the mesh).")
      .def_readonly("name", &FaceVaryingChannel::name, "The channel's name (\"uv\" from OBJ vt).")
      .def_property_readonly(
          "values", [](const FaceVaryingChannel& c) { return Points(c.values); }, "Value rows (N, dim).")
      .def_property_readonly(
          "indices", [](const FaceVaryingChannel& c) { return vector_array(c.indices); },
          "One value row per face corner (parallel to Mesh.face_vertices).")
      .def(
          "__repr__",
          [](const FaceVaryingChannel& c) {
            return "FaceVaryingChannel(name='" + c.name + "', values=" + std::to_string(c.values.rows()) +
                   ")";
          },
          "Short description.");
}

/// Meshes and segments.
void bind_geometry_types(py::module_& m) {
  bind_mesh_tags(m);
  py::class_<Mesh>(m, "Mesh",
                   "A polygon mesh: faces of any size over vertex rows (face_offsets + face_vertices), with\n"
                   "optional normals and face states.")
      .def(py::init(&make_mesh), py::arg("vertices"), py::arg("triangles") = py::none(),
           py::arg("quads") = py::none(), py::arg("normals") = py::none(), py::arg("states") = py::none(),
           py::kw_only(), py::arg("faces") = py::none(), py::arg("face_offsets") = py::none(),
           py::arg("face_vertices") = py::none(), py::arg("tags") = py::none(),
           py::arg("face_varying") = py::none(),
           "vertices: (V, 3). Faces, 0-based rows of vertices, counter-clockwise, given in one of three "
           "ways:\n"
           "triangles: int (T, 3) and quads: int (Q, 4) (triangles first); faces: a list of lists of any\n"
           "sizes ≥ 3; face_offsets: int (F + 1,) from 0 with face_vertices: int (offsets[-1],), face f "
           "being\n"
           "face_vertices[face_offsets[f]:face_offsets[f + 1]].\n"
           "normals: None or (V, 3). states: None or one non-negative int per face, in face order.\n"
           "tags: None or MeshTags (creases, corners, holes, options); face_varying: None or a list of\n"
           "FaceVaryingChannel (UVs).\n"
           "Raises InvalidInput for a malformed mesh (check_mesh).")
      .def_property_readonly(
          "vertices", [](const Mesh& mesh) { return Points(mesh.vertices); }, "Vertex rows (V, 3).")
      .def_property_readonly("triangles", &faces_of_size<3>, "The faces of 3 corners (T, 3), in face order.")
      .def_property_readonly("quads", &faces_of_size<4>, "The faces of 4 corners (Q, 4), in face order.")
      .def_property_readonly(
          "face_offsets", [](const Mesh& mesh) { return vector_array(mesh.face_offsets); },
          "Where each face starts in face_vertices (F + 1,), from 0.")
      .def_property_readonly(
          "face_vertices", [](const Mesh& mesh) { return vector_array(mesh.face_vertices); },
          "The corners of every face, face after face.")
      .def_property_readonly(
          "faces",
          [](const Mesh& mesh) {
            py::list out;
            for (std::size_t f = 0; f < face_count(mesh); ++f) {
              const auto c = face(mesh, f);
              out.append(py::cast(std::vector<int>(c.begin(), c.end())));
            }
            return out;
          },
          "Every face as a list of vertex indices.")
      .def_property_readonly(
          "normals", [](const Mesh& mesh) { return Points(mesh.normals); },
          "Normals: per vertex (V, 3) when normal_indices is empty, else the rows normal_indices picks; or "
          "an empty (0, 0) array.")
      .def_property_readonly(
          "normal_indices", [](const Mesh& mesh) { return vector_array(mesh.normal_indices); },
          "Per face corner (1-D, parallel to face_vertices), the row of normals it takes; empty when normals "
          "are per vertex. subdivision.limit(normals=True) gives them at crease and corner vertices (a "
          "normal "
          "per sector).")
      .def_property_readonly(
          "states", [](const Mesh& mesh) { return vector_array(mesh.states); },
          "Per-face states (1-D, in face order), or empty.")
      .def_readonly("tags", &Mesh::tags, "Creases, corners, holes and refinement options (MeshTags).")
      .def_readonly("face_varying", &Mesh::face_varying,
                    "Face-varying channels (list of FaceVaryingChannel).")
      .def(
          "__repr__",
          [](const Mesh& mesh) {
            std::size_t count[2] = {0, 0}, others = 0;
            for (std::size_t f = 0; f < face_count(mesh); ++f) {
              const std::size_t n = face(mesh, f).size();
              if (n == 3 || n == 4)
                ++count[n - 3];
              else
                ++others;
            }
            return "Mesh(vertices=" + std::to_string(mesh.vertices.rows()) +
                   ", triangles=" + std::to_string(count[0]) + ", quads=" + std::to_string(count[1]) +
                   (others ? ", polygons=" + std::to_string(others) : std::string()) + ")";
          },
          "Short description.");

  py::class_<Segments>(m, "Segments", "Independent segments over vertex rows, with optional states.")
      .def(
          py::init(&make_segments), py::arg("vertices"), py::arg("segments"), py::arg("states") = py::none(),
          "vertices: (V, 2) or (V, 3). segments: int (S, 2), 0-based rows. states: None or one per segment.\n"
          "Raises InvalidInput for malformed segments (check_segments).")
      .def_property_readonly(
          "vertices", [](const Segments& s) { return Points(s.vertices); }, "Vertex rows (V, 2|3).")
      .def_property_readonly(
          "segments", [](const Segments& s) { return index_array(s.segments); }, "Segments (S, 2).")
      .def_property_readonly(
          "states", [](const Segments& s) { return vector_array(s.states); }, "Per-segment states, or empty.")
      .def(
          "__repr__",
          [](const Segments& s) {
            return "Segments(vertices=" + std::to_string(s.vertices.rows()) +
                   ", segments=" + std::to_string(s.segments.size()) + ")";
          },
          "Short description.");

  m.def(
      "polyline_segments",
      [](const DoubleArray& points, bool closed, std::uint32_t state) {
        const Points P = points_from(points, "points");
        if (P.cols() != 2 && P.cols() != 3)
          throw InvalidInput("points: " + std::to_string(P.cols()) + " columns, expected 2 or 3");
        return polyline_segments(P, closed, state);
      },
      py::arg("points"), py::arg("closed").noconvert() = false, py::arg("state") = 0,
      "The segments (i, i + 1) of a polyline (n, 2|3), plus (n − 1, 0) when closed, all with `state`.");
}

/// Mesh and segment files: OBJ, PLY, SVG.
void bind_geometry_files(py::module_& m) {
  m.def("vertex_normals", &vertex_normals, py::arg("mesh"),
        "Area-weighted unit vertex normals (V, 3); zero rows for vertices without area.");
  m.def("mesh_obj", py::overload_cast<const Mesh&>(&io::mesh_obj), py::arg("mesh"),
        "OBJ text of a mesh (with `vn` rows when it has normals).");
  m.def("segments_obj", py::overload_cast<const Segments&>(&io::segments_obj), py::arg("segments"),
        "OBJ text of segments: `v` rows and `l a b` lines.");
  m.def(
      "parse_mesh_obj",
      [](std::string_view text, std::string_view where, bool strict) {
        return io::parse_mesh_obj(text, where, {.strict = strict, .warn = {}});
      },
      py::arg("text"), py::arg("where") = kDefaultWhere, py::kw_only(), py::arg("strict") = false,
      "A polygon mesh from OBJ text (`v`, `vt`, `f` with v, v/vt, v/vt/vn or v//vn references, negative\n"
      "ones counting back; `t` tags: creases, corners, holes, options; other statements ignored). An\n"
      "unknown tag is a warning on stderr, or InvalidInput when strict. Raises IoError (syntax) or\n"
      "InvalidInput (content) naming `where` and the line.");

  py::enum_<io::PlyFormat>(m, "PlyFormat", "PLY encodings.")
      .value("ascii", io::PlyFormat::ascii, "Text PLY.")
      .value("binary_little_endian", io::PlyFormat::binary_little_endian, "Binary little-endian PLY.")
      .value("binary_big_endian", io::PlyFormat::binary_big_endian, "Binary big-endian PLY.")
      // enum_'s own `value` property has no docstring.
      .def_property_readonly(
          "value", [](io::PlyFormat f) { return static_cast<int>(f); }, "The integer value.");
  m.def(
      "mesh_ply",
      [](const Mesh& mesh, io::PlyFormat format) {
        return file_result(io::mesh_ply(mesh, format), format != io::PlyFormat::ascii);
      },
      py::arg("mesh"), py::arg("format") = io::PlyFormat::ascii,
      "PLY of a mesh (normals and face states when present): str for ascii, bytes for binary.");
  m.def(
      "segments_ply",
      [](const Segments& s, io::PlyFormat format) {
        return file_result(io::segments_ply(s, format), format != io::PlyFormat::ascii);
      },
      py::arg("segments"), py::arg("format") = io::PlyFormat::ascii,
      "PLY of segments (`element edge`, states when present): str for ascii, bytes for binary.");
  m.def(
      "parse_mesh_ply",
      [](const py::object& data, const std::string& where) {
        const std::string bytes = bytes_of(data, "parse_mesh_ply: data");
        py::gil_scoped_release release;
        return io::parse_mesh_ply(bytes, where);
      },
      py::arg("data"), py::arg("where") = kDefaultWhere,
      "A polygon mesh from PLY bytes (or ASCII text): ascii, binary_little_endian or binary_big_endian,\n"
      "vertex x y z (nx ny nz), face vertex_indices of any types, other properties skipped. Raises\n"
      "IoError (header, truncated data) or InvalidInput (content) naming `where` and the element.");
  m.def(
      "read_mesh",
      [](const std::filesystem::path& path, bool strict) {
        return io::read_mesh(path, {.strict = strict, .warn = {}});
      },
      Release(), py::arg("path"), py::kw_only(), py::arg("strict") = false,
      "Reads a polygon mesh from a .obj, .ply, .stl or .off file (checked with check_mesh), with its tags "
      "(Mesh.tags)\n"
      "and UVs (Mesh.face_varying) from OBJ. An unknown OBJ tag is a warning on stderr, or InvalidInput\n"
      "when strict.\n\n"
      "Raises IoError or InvalidInput naming the path and the line or element.");
  m.def(
      "segments_svg",
      [](const Segments& s, int width, double stroke, std::string color) {
        return io::segments_svg(s, {.width = width, .stroke = stroke, .color = std::move(color)});
      },
      py::arg("segments"), py::kw_only(), py::arg("width") = io::SvgOptions{}.width,
      py::arg("stroke") = io::SvgOptions{}.stroke, py::arg("color") = io::SvgOptions{}.color,
      "SVG text of the x, y coordinates (y up), fitted with a 5 % margin into `width` pixels.\n\n"
      "stroke: width in pixels; color: an SVG colour. Raises InvalidInput for a bad width or stroke.");
}

void bind_geometry(py::module_& m) {
  bind_geometry_polylines(m);
  bind_geometry_files(m);
}

void bind_automaton_files(py::module_& m) {
  m.def(
      "parse_automaton_json", &io::parse_automaton_json, py::arg("text"), py::arg("where") = kDefaultWhere,
      "The automaton of cifs.automata.to_json text: states (sizes, names, windows, recurrent flags),\n"
      "transitions with labels and matrices in out-edge order, initial entries. Raises IoError (syntax) or\n"
      "InvalidInput (content) naming `where` and the JSON path.");
  m.def(
      "read_automaton", &io::read_automaton, Release(), py::arg("path"),
      "Reads an automaton JSON file (parse_automaton_json). Raises IoError or InvalidInput naming the path.");
}

/// The format table and the dispatcher.
void bind_dispatch(py::module_& m) {
  py::enum_<io::Content>(m, "Content", "What io reads and writes.")
      .value("shape", io::Content::shape, "A NURBS curve or surface.")
      .value("polygon", io::Content::polygon, "A control polygon or any polyline.")
      .value("mesh", io::Content::mesh, "A polygon mesh (Mesh).")
      .value("segments", io::Content::segments, "A segment set (Segments).")
      .value("automaton", io::Content::automaton, "An automaton (cifs.automata.Automaton).")
      .value("bcifs", io::Content::bcifs, "A BC-IFS file (BcifsFile).")
      .value("experiment", io::Content::experiment, "An experiment file (Experiment).")
      .value("points", io::Content::points, "A point set (write_points, encode_points: json, npy, ply, obj).")
      .def_property_readonly(
          "value", [](io::Content c) { return static_cast<int>(c); }, "The integer value.");
  py::class_<io::Format>(m, "Format", "One file format of a kind of content.")
      .def_property_readonly(
          "name", [](const io::Format& f) { return std::string(f.name); }, "The --format value, e.g. 'obj'.")
      .def_property_readonly(
          "extension", [](const io::Format& f) { return std::string(f.extension); },
          "The extension, e.g. '.obj'.")
      .def_readonly("read", &io::Format::read, "True when io reads it.")
      .def_readonly("write", &io::Format::write, "True when io writes it.")
      .def_readonly("binary", &io::Format::binary,
                    "True when the written bytes are not text (encode gives bytes).")
      .def(
          "__repr__",
          [](const io::Format& f) {
            return "Format(name='" + std::string(f.name) + "', extension='" + std::string(f.extension) + "')";
          },
          "Short description.");
  m.def("formats", &io::formats, py::arg("content"),
        "The formats of a Content, in the table's order (the one the CLI and experiment outputs consult).");

  // Point sets: an (n, dim) array and how it is written (io::PointSet).
  m.def(
      "write_points",
      [](const std::filesystem::path& path, const DoubleArray& points, bool polyline, bool closed) {
        io::write(path, io::PointSet{points_from(points, "points"), {polyline, closed, {}}});
      },
      py::arg("path"), py::arg("points"), py::arg("polyline").noconvert() = false,
      py::arg("closed").noconvert() = false,
      "Writes a point set (n, dim) in the format its extension names (.json, .npy, .ply, .obj),\n"
      "atomically; `polyline` joins the points by an OBJ `l` line (back to the first when `closed`).");
  m.def(
      "encode_points",
      [](const DoubleArray& points, const std::string& format, bool polyline, bool closed) {
        const std::string bytes =
            io::encode(io::PointSet{points_from(points, "points"), {polyline, closed, {}}}, format);
        return file_result(bytes, format == "npy" || format == "ply");
      },
      py::arg("points"), py::arg("format"), py::arg("polyline").noconvert() = false,
      py::arg("closed").noconvert() = false,
      "The file contents of a point set in `format` (json, npy, ply, obj): str, or bytes for npy and ply.");

  // write(path, thing) and encode(thing, format) for every content that is written.
  const auto bind = [&m](auto tag, const char* type) {
    using T = typename decltype(tag)::type;
    m.def(
        "write", [](const std::filesystem::path& path, const T& thing) { io::write(path, thing); }, Release(),
        py::arg("path"), py::arg("thing"),
        (std::string("Writes a ") + type +
         " in the format its extension names, atomically. Raises InvalidInput for an extension\n"
         "it is not written in (naming those it is), IoError when the file cannot be written.")
            .c_str());
    m.def(
        "encode",
        [](const T& thing, const std::string& format) {
          const std::string bytes = io::encode(thing, format);
          bool binary = false;
          for (const io::Format& f : io::formats(content_of(static_cast<const T*>(nullptr))))
            binary = binary || (f.name == format && f.binary);
          return file_result(bytes, binary);
        },
        py::arg("thing"), py::arg("format"),
        (std::string("The file contents of a ") + type +
         " in `format`: str, or bytes for a binary format. Raises InvalidInput naming the formats it is\n"
         "written in.")
            .c_str());
  };
  bind(std::type_identity<io::Shape>{}, "nurbs.Curve or nurbs.Surface");
  bind(std::type_identity<io::Polygon>{}, "Polygon");
  bind(std::type_identity<Mesh>{}, "Mesh");
  bind(std::type_identity<Segments>{}, "Segments");
  bind(std::type_identity<nurbs::KnotAutomaton>{}, "cifs.automata.Automaton");
  bind(std::type_identity<io::BcifsFile>{}, "BcifsFile");
}

void bind_experiment_file(py::module_& m) {
  py::class_<io::Experiment>(
      m, "Experiment",
      "An experiment file (docs/experiments.md), parsed: source, perturbation, evaluation,\n"
      "camera, render settings, outputs. Read-only; run it with cifs.experiment.run.")
      .def_readonly("name", &io::Experiment::name, "Name (default: the file's stem).")
      .def_readonly("description", &io::Experiment::description, "Free text.")
      .def_property_readonly("source", &source_kind,
                             "The source kind: 'curve', 'surface', 'automaton', 'ifs', 'mesh' or 'junction'.")
      .def_readonly("shape", &io::Experiment::shape, "The NURBS source (Curve or Surface), or None.")
      .def_property_readonly(
          "automaton",
          [](const io::Experiment& e) -> std::optional<std::filesystem::path> {
            if (e.automaton.empty()) return std::nullopt;
            return e.automaton;
          },
          "Absolute path of the BC-IFS automaton file source, or None.")
      .def_property_readonly(
          "ifs",
          [](const io::Experiment& e) -> std::optional<std::string> {
            if (!e.ifs) return std::nullopt;
            return e.ifs->name;
          },
          "Name of the classic IFS source ('' for explicit maps), or None.")
      .def_property_readonly(
          "ifs_maps",
          [](const io::Experiment& e) {
            return index_array(e.ifs ? e.ifs->maps : std::vector<std::array<double, 7>>());
          },
          "Explicit classic IFS maps (n, 7): rows (a, b, c, d, e, f, p).")
      .def_property_readonly(
          "mesh",
          [](const io::Experiment& e) -> std::optional<std::filesystem::path> {
            if (!e.mesh) return std::nullopt;
            return e.mesh->path;
          },
          "Path of the polygon mesh source (refined by its subdivision scheme), or None.")
      .def_readonly(
          "inputs", &io::Experiment::inputs,
          "Every file the experiment reads (list of paths): the experiment file, its shape, polygon,\n"
          "mesh or BC-IFS file. cifs.experiment.run refuses outputs onto them.")
      .def_property_readonly(
          "perturbed", [](const io::Experiment& e) { return e.perturbation.has_value(); },
          "True when the file perturbs the free coefficients.")
      .def_property_readonly(
          "mode", [](const io::Experiment& e) { return mode_name(e.evaluation.mode); },
          "Evaluation mode: 'depth', 'tolerance' or 'chaos'.")
      .def_property_readonly(
          "depth", [](const io::Experiment& e) { return e.evaluation.depth; }, "Evaluation depth.")
      .def_property_readonly(
          "tolerance", [](const io::Experiment& e) { return e.evaluation.tolerance; },
          "Evaluation tolerance (relative to the control-net diameter).")
      .def_property_readonly(
          "samples", [](const io::Experiment& e) { return e.evaluation.samples; }, "Chaos-game samples.")
      .def_property_readonly(
          "seed", [](const io::Experiment& e) { return e.evaluation.seed; }, "Chaos-game seed.")
      .def_property_readonly(
          "size", [](const io::Experiment& e) { return py::make_tuple(e.render.width, e.render.height); },
          "Image size (width, height) in pixels.")
      .def_property_readonly(
          "outputs",
          [](const io::Experiment& e) {
            py::dict out;
            if (!e.outputs.exr.empty()) out["exr"] = py::cast(e.outputs.exr);
            if (!e.outputs.png.empty()) out["png"] = py::cast(e.outputs.png);
            for (const auto& [format, path] : e.outputs.geometry) out[py::str(format)] = py::cast(path);
            for (const auto& [format, path] : e.outputs.automaton)
              out[py::str("automaton_" + format)] = py::cast(path);
            return out;
          },
          "The output files the experiment writes, relative to the output folder: dict key → path (the\n"
          "file's keys: exr, png, a geometry format, automaton_<format>).")
      .def(
          "__repr__",
          [](const io::Experiment& e) {
            return "Experiment(name='" + e.name + "', source=" + source_kind(e) +
                   ", mode=" + mode_name(e.evaluation.mode) + ")";
          },
          "Short description.");
  m.def("read_experiment", &io::read_experiment, Release(), py::arg("path"),
        "Reads an experiment file; inputs are resolved against its folder.\n\n"
        "Raises IoError or InvalidInput naming the path and the JSON path.");
  m.def("parse_experiment", &io::parse_experiment, py::arg("text"), py::arg("where") = kDefaultWhere,
        py::arg("base") = std::filesystem::path("."),
        "Parses experiment text; relative input paths are resolved against the folder `base`.\n\n"
        "Raises IoError or InvalidInput naming `where` and the JSON path.");
}

}  // namespace

void bind_io_types(py::module_& m) {
  bind_geometry_types(m);
}

void bind_io(py::module_& m) {
  bind_shapes(m);
  bind_polygons(m);
  bind_geometry(m);
  bind_automaton_files(m);
  bind_experiment_file(m);
}

void bind_io_dispatch(py::module_& m) {
  bind_dispatch(m);
}

void bind_verify(py::module_& m) {
  using namespace cifs::verify;
  const auto deviation_repr = [](const Deviation& d) {
    return "Deviation(max_abs=" + py::repr(py::float_(d.max_abs)).cast<std::string>() +
           ", max_rel=" + py::repr(py::float_(d.max_rel)).cast<std::string>() + ")";
  };
  py::class_<Deviation>(m, "Deviation", "Largest absolute and relative deviation of one comparison.")
      .def_readonly("max_abs", &Deviation::max_abs, "Largest absolute deviation.")
      .def_readonly("max_rel", &Deviation::max_rel,
                    "Largest deviation relative to the largest control point.")
      .def("__repr__", deviation_repr, "Short description.");
  py::class_<SegmentReport>(m, "SegmentReport", "The comparisons of one curve segment.")
      .def_readonly("segment", &SegmentReport::segment, "Segment index.")
      .def_readonly("start", &SegmentReport::start, "Start of its parameter interval.")
      .def_readonly("end", &SegmentReport::end, "End of its parameter interval.")
      .def_readonly("nets", &SegmentReport::nets, "Leaf control nets vs knot insertion of every dyadic knot.")
      .def_readonly("points", &SegmentReport::points,
                    "Attractor points vs Cox–de Boor at the dyadic parameters.")
      .def(
          "__repr__",
          [](const SegmentReport& s) {
            return "SegmentReport(segment=" + std::to_string(s.segment) +
                   ", nets.max_rel=" + py::repr(py::float_(s.nets.max_rel)).cast<std::string>() +
                   ", points.max_rel=" + py::repr(py::float_(s.points.max_rel)).cast<std::string>() + ")";
          },
          "Short description.");
  py::class_<CheckReport>(m, "CheckReport", "Result of check_curve.")
      .def_readonly("depth", &CheckReport::depth, "Depth checked.")
      .def_readonly("tolerance", &CheckReport::tolerance, "Relative tolerance.")
      .def_readonly("segments", &CheckReport::segments, "One SegmentReport per segment, in order.")
      .def_readonly("nets", &CheckReport::nets, "Net deviation over all segments.")
      .def_readonly("points", &CheckReport::points, "Point deviation over all segments.")
      .def_readonly("passed", &CheckReport::pass, "True when no relative deviation exceeds the tolerance.")
      .def(
          "__repr__",
          [](const CheckReport& r) {
            return "CheckReport(depth=" + std::to_string(r.depth) +
                   ", segments=" + std::to_string(r.segments.size()) + (r.pass ? ", passed)" : ", failed)");
          },
          "Short description.");
  py::class_<PatchReport>(m, "PatchReport", "The comparisons of one surface patch.")
      .def_readonly("patch", &PatchReport::patch, "(u segment, v segment).")
      .def_readonly("u", &PatchReport::u, "Its u interval (start, end).")
      .def_readonly("v", &PatchReport::v, "Its v interval (start, end).")
      .def_readonly("nets", &PatchReport::nets,
                    "Leaf nets vs knot insertion of every dyadic knot in u and v.")
      .def_readonly("points", &PatchReport::points,
                    "Mesh vertices vs surface evaluation at the dyadic parameters.")
      .def(
          "__repr__",
          [](const PatchReport& p) {
            return "PatchReport(patch=(" + std::to_string(p.patch[0]) + ", " + std::to_string(p.patch[1]) +
                   "))";
          },
          "Short description.");
  py::class_<SurfaceCheckReport>(m, "SurfaceCheckReport", "Result of check_surface.")
      .def_readonly("depth", &SurfaceCheckReport::depth, "Depth checked.")
      .def_readonly("tolerance", &SurfaceCheckReport::tolerance, "Relative tolerance.")
      .def_readonly("patches", &SurfaceCheckReport::patches, "One PatchReport per patch, u-major.")
      .def_readonly("nets", &SurfaceCheckReport::nets, "Net deviation over all patches.")
      .def_readonly("points", &SurfaceCheckReport::points, "Point deviation over all patches.")
      .def_readonly("passed", &SurfaceCheckReport::pass,
                    "True when no relative deviation exceeds the tolerance.")
      .def(
          "__repr__",
          [](const SurfaceCheckReport& r) {
            return "SurfaceCheckReport(depth=" + std::to_string(r.depth) +
                   ", patches=" + std::to_string(r.patches.size()) + (r.pass ? ", passed)" : ", failed)");
          },
          "Short description.");
  const CheckOptions defaults;
  m.def(
      "check_curve",
      [](const nurbs::Curve& c, int depth, double tolerance) {
        return check_curve(c, {.depth = depth, .tolerance = tolerance});
      },
      Release(), py::arg("curve"), py::kw_only(), py::arg("depth") = defaults.depth,
      py::arg("tolerance") = defaults.tolerance,
      "Checks the knot-doubling attractor of a curve against knot insertion and Cox–de Boor, per segment.\n\n"
      "Returns a CheckReport. Raises InvalidInput for a depth outside [0, 30] or work beyond the memory "
      "limit.");
  m.def(
      "check_surface",
      [](const nurbs::Surface& s, int depth, double tolerance) {
        return check_surface(s, {.depth = depth, .tolerance = tolerance});
      },
      Release(), py::arg("surface"), py::kw_only(), py::arg("depth") = defaults.depth,
      py::arg("tolerance") = defaults.tolerance,
      "check_curve for surfaces, patch by patch on the tensor-product automaton.\n\n"
      "Returns a SurfaceCheckReport. Raises InvalidInput for a depth outside [0, 30] or references beyond\n"
      "the memory limit.");
}

namespace {

/// Run reports and evaluations.
void bind_experiment_types(py::module_& m) {
  using namespace cifs::experiment;
  py::class_<RunReport>(m, "RunReport", "Result of run.")
      .def_readonly("written", &RunReport::written, "Paths of the files written, in order.")
      .def_readonly("depth", &RunReport::depth, "Depth evaluated (chaos: depth of the sampled nodes).")
      .def_readonly("free_coefficients", &RunReport::free_coefficients, "Number of free BC-IFS coefficients.")
      .def_readonly("residual", &RunReport::residual, "Largest constraint residual after perturbation.")
      .def_readonly("summary", &RunReport::summary, "The CLI's summary text (one line per fact).")
      .def(
          "__repr__",
          [](const RunReport& r) {
            return "RunReport(depth=" + std::to_string(r.depth) +
                   ", written=" + std::to_string(r.written.size()) + ")";
          },
          "Short description.");
  py::class_<Evaluation>(m, "Evaluation", "The deterministic evaluation of an experiment's source.")
      .def_readonly(
          "points", &Evaluation::points,
          "Cartesian points (n, dim): curve points, mesh vertices, BC-IFS piece ends or IFS points.")
      .def_readonly("depth", &Evaluation::depth, "Depth evaluated.")
      .def_readonly("kind", &Evaluation::kind, "Source kind, e.g. 'NURBS curve', 'classic IFS koch'.")
      .def_readonly("resolution", &Evaluation::resolution,
                    "Bound on the diameter of the depth-K pieces; infinite when unknown (rational nets).")
      .def_readonly("estimated_resolution", &Evaluation::estimated_resolution,
                    "evaluate only: largest Cartesian diameter of the depth-K nets, an estimate of the\n"
                    "pieces' size (not a bound); infinite when a weight reaches 0.")
      .def_readonly("automaton", &Evaluation::automaton,
                    "The (perturbed) automaton (cifs.automata.Automaton).")
      .def_readonly("nets", &Evaluation::nets,
                    "Initial nets, one per initial entry (homogeneous rows if rational).")
      .def_readonly("rational", &Evaluation::rational, "True when the nets are homogeneous.")
      .def_readonly("maps", &Evaluation::maps, "Classic IFS only: its affine maps (cifs.ifs.AffineMap).")
      .def(
          "__repr__",
          [](const Evaluation& e) {
            return "Evaluation(kind='" + e.kind + "', depth=" + std::to_string(e.depth) +
                   ", points=" + std::to_string(e.points.rows()) + ")";
          },
          "Short description.");
}

/// cifs dimension's measurement (experiment::measure_dimension).
void bind_dimension(py::module_& m) {
  using namespace cifs::experiment;
  py::class_<DimensionMeasurement>(
      m, "DimensionMeasurement", "The dimension of an attractor as `cifs dimension` measures and reports it.")
      .def_readonly("sample", &DimensionMeasurement::sample, "The sample measured (Evaluation).")
      .def_readonly("route", &DimensionMeasurement::route, "'tolerance' or 'depth'.")
      .def_readonly("description", &DimensionMeasurement::description,
                    "The route in words, as the CLI prints it.")
      .def_readonly("resolution", &DimensionMeasurement::resolution,
                    "Resolution passed to the fit (0: none).")
      .def_readonly("estimated", &DimensionMeasurement::estimated,
                    "True when the resolution is estimated from the leaves' nets, not proven.")
      .def_readonly("fallback", &DimensionMeasurement::fallback,
                    "Why the proven tolerance sample (or its strict fit) was left; empty when it was not.")
      .def_readonly("relaxed", &DimensionMeasurement::relaxed, "Fit requirements dropped, in words.")
      .def_readonly("fit", &DimensionMeasurement::fit, "The box count (cifs.ifs.BoxCountingResult).")
      .def_property_readonly(
          "dimension", [](const DimensionMeasurement& d) { return d.fit.dimension; },
          "The box-counting dimension.")
      .def_readonly("uncertainty", &DimensionMeasurement::uncertainty,
                    "max(fit.uncertainty, |dimension − coarser|): the ± the CLI prints.")
      .def_readonly(
          "coarser", &DimensionMeasurement::coarser,
          "Dimension of the same route on a 2–4× smaller sample; None (see coarser_note) when none.")
      .def_readonly("coarser_note", &DimensionMeasurement::coarser_note, "Why there is no coarser dimension.")
      .def_readonly("cover", &DimensionMeasurement::cover,
                    "Growth of the proven cover (cifs.ifs.CoverExponent), or None.")
      .def_property_readonly(
          "range", [](const DimensionMeasurement& d) { return py::make_tuple(d.range[0], d.range[1]); },
          "(low, high): dimension ± uncertainty, widened up to the cover's growth.")
      .def_readonly("similarity", &DimensionMeasurement::similarity,
                    "Similarity dimension when every map is a similarity, else None (see similarity_note).")
      .def_readonly("similarity_note", &DimensionMeasurement::similarity_note,
                    "Why there is no similarity dimension.")
      .def(
          "__repr__",
          [](const DimensionMeasurement& d) {
            return "DimensionMeasurement(dimension=" + number_text(d.fit.dimension, 6) + " ± " +
                   number_text(d.uncertainty, 2) + ", route='" + d.route + "')";
          },
          "Short description.");
  const DimensionOptions defaults;
  const auto measure = [](const io::Experiment& e, std::optional<int> depth, std::optional<double> piece,
                          long long max_points, int min_level, int max_level, long long min_boxes) {
    if (max_points < 0) throw InvalidInput("max_points: " + std::to_string(max_points) + " is negative");
    if (min_boxes < 0) throw InvalidInput("min_boxes: " + std::to_string(min_boxes) + " is negative");
    const DimensionOptions o{.depth = depth,
                             .relative_piece_size = piece,
                             .max_points = static_cast<std::size_t>(max_points),
                             .min_level = min_level,
                             .max_level = max_level,
                             .min_boxes = static_cast<std::size_t>(min_boxes)};
    py::gil_scoped_release release;
    return measure_dimension(e, o);
  };
  const auto shape_measure = [measure](io::Shape shape,
                                       auto... rest) {  // a shape file's experiment (the CLI's)
    io::Experiment e;
    e.name = std::holds_alternative<nurbs::Curve>(shape) ? "curve" : "surface";
    e.shape = std::move(shape);
    return measure(e, rest...);
  };
  const char* doc =
      "The box-counting dimension of the attractor of an experiment (cifs.io.Experiment) or of a curve or\n"
      "surface, measured as `cifs dimension` measures it: without depth or relative_piece_size the route\n"
      "chooses itself (a proven tolerance sample within max_points, else the deepest depth evaluation),\n"
      "relaxes the fit's requirements where they cannot hold, and sizes the uncertainty by a coarser\n"
      "sample. min_level, max_level: a fit range (-1: automatic); min_boxes: the automatic range's coarse\n"
      "end. Returns a DimensionMeasurement. Raises InvalidInput as the CLI does.";
  const auto def = [&](auto function, const char* source) {
    m.def("measure_dimension", function, py::arg(source), py::kw_only(), py::arg("depth") = py::none(),
          py::arg("relative_piece_size") = py::none(),
          py::arg("max_points") = static_cast<long long>(defaults.max_points),
          py::arg("min_level") = defaults.min_level, py::arg("max_level") = defaults.max_level,
          py::arg("min_boxes") = static_cast<long long>(defaults.min_boxes), doc);
  };
  def(measure, "experiment");
  def(
      [shape_measure](const nurbs::Curve& c, std::optional<int> depth, std::optional<double> piece,
                      long long max_points, int min_level, int max_level, long long min_boxes) {
        return shape_measure(c, depth, piece, max_points, min_level, max_level, min_boxes);
      },
      "shape");
  def(
      [shape_measure](const nurbs::Surface& s, std::optional<int> depth, std::optional<double> piece,
                      long long max_points, int min_level, int max_level, long long min_boxes) {
        return shape_measure(s, depth, piece, max_points, min_level, max_level, min_boxes);
      },
      "shape");
}

/// Running, evaluating and sampling experiments.
void bind_experiment_functions(py::module_& m) {
  using namespace cifs::experiment;
  // Shared keyword checks: negative counts would wrap around in the unsigned C++ fields.
  const auto options = [](std::optional<int> threads, long long max_bytes) {
    if (threads && *threads < 0) throw InvalidInput("threads: " + std::to_string(*threads) + " is negative");
    if (max_bytes < 0) throw InvalidInput("max_bytes: " + std::to_string(max_bytes) + " is negative");
    RunOptions o;
    if (threads) o.threads = static_cast<unsigned>(*threads);
    o.max_bytes = static_cast<std::size_t>(max_bytes);
    return o;
  };
  const RunOptions defaults;
  m.def(
      "run",
      [options](const io::Experiment& e, std::filesystem::path out_dir,
                const std::optional<std::filesystem::path>& exr,
                const std::optional<std::filesystem::path>& png, bool quiet, std::optional<int> threads,
                long long max_bytes) {
        RunOptions o = options(threads, max_bytes);
        o.out_dir = std::move(out_dir);
        o.exr = exr.value_or(std::filesystem::path());
        o.png = png.value_or(std::filesystem::path());
        o.quiet = quiet;
        py::gil_scoped_release release;
        return run(e, o);
      },
      py::arg("experiment"), py::kw_only(), py::arg("out_dir") = defaults.out_dir,
      py::arg("exr") = py::none(), py::arg("png") = py::none(), py::arg("quiet").noconvert() = defaults.quiet,
      py::arg("threads") = py::none(), py::arg("max_bytes") = static_cast<long long>(defaults.max_bytes),
      "Runs an experiment as `cifs render` does: builds, perturbs, evaluates, renders and writes its "
      "outputs.\n\n"
      "out_dir: folder of the experiment's outputs (created when missing). exr, png: override\n"
      "outputs.exr / outputs.png (paths as given; their folders must exist). quiet: no progress bar. "
      "threads: overrides\n"
      "render.threads. max_bytes: refuse larger images or geometry before any work.\n"
      "Returns a RunReport. Raises InvalidInput (bad content, too large) or IoError (files); on failure no\n"
      "output file is left behind.");
  m.def(
      "evaluate",
      [options](const io::Experiment& e, std::optional<int> depth, std::optional<int> threads,
                long long max_bytes) {
        const RunOptions o = options(threads, max_bytes);
        py::gil_scoped_release release;
        return evaluate(e, depth, o);
      },
      py::arg("experiment"), py::arg("depth") = py::none(), py::kw_only(), py::arg("threads") = py::none(),
      py::arg("max_bytes") = static_cast<long long>(defaults.max_bytes),
      "The deterministic evaluation of an experiment's source (perturbed as the file says) to `depth`\n"
      "(default: the file's evaluation.depth, whatever its mode). Nothing is written.\n\n"
      "Returns an Evaluation. Raises InvalidInput as run, and for a negative depth.");
  m.def(
      "sample",
      [options](const io::Experiment& e, double tolerance, long long max_points, std::optional<int> threads,
                long long max_bytes) {
        if (max_points < 0)
          throw InvalidInput("sample: max_points is " + std::to_string(max_points) + ", must be ≥ 0");
        const RunOptions o = options(threads, max_bytes);
        const SampleOptions s{.tolerance = tolerance, .max_points = static_cast<std::size_t>(max_points)};
        py::gil_scoped_release release;
        return sample(e, s, o);
      },
      py::arg("experiment"), py::kw_only(), py::arg("tolerance") = SampleOptions{}.tolerance,
      py::arg("max_points") = static_cast<long long>(SampleOptions{}.max_points),
      py::arg("threads") = py::none(), py::arg("max_bytes") = static_cast<long long>(defaults.max_bytes),
      "Builds the experiment's source (perturbed as the file says) and samples its attractor to a tolerance\n"
      "(ifs.tolerance_sample): one point per piece, every piece proven smaller than `resolution` =\n"
      "tolerance × the extent of the initial nets (0: the largest 2^-j, j ≥ 4, within max_points).\n"
      "The first route of `cifs dimension`.\n\n"
      "Returns an Evaluation (depth = the deepest piece). Raises InvalidInput as run, for a negative\n"
      "tolerance and for a sample above max_points (before allocating it).");
}

}  // namespace

void bind_experiment(py::module_& m) {
  bind_experiment_types(m);
  bind_experiment_functions(m);
  bind_dimension(m);
}

}  // namespace cifs::python
