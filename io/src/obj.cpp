// SPDX-License-Identifier: MIT
// cifs — OBJ polygonal geometry: meshes (read and written), segment sets and polylines (written).
// The free-form curves and surfaces are in obj_freeform.cpp.
#include <algorithm>
#include <array>
#include <climits>
#include <cstdio>
#include <map>
#include <optional>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/io/obj.hpp"
#include "obj_lexer.hpp"
#include "points_format.hpp"

namespace cifs::io {
namespace {

/// `v` lines with missing coordinates set to 0.
void obj_vertices(std::string& out, const Eigen::Ref<const Points>& P, const char* tag = "v") {
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    out += tag;
    for (Eigen::Index k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, k < P.cols() ? P(i, k) : 0.0, 17);  // %.17g
    }
    out += '\n';
  }
}

/// obj_vertices a block of rows at a time, spilled in between.
void obj_vertices(ChunkBuffer& out, const Points& P, const char* tag = "v") {
  constexpr Eigen::Index kBlock = 4096;
  for (Eigen::Index i = 0; i < P.rows(); i += kBlock) {
    obj_vertices(out.text, P.middleRows(i, std::min(kBlock, P.rows() - i)), tag);
    out.spill();
  }
}

// The point-set format: `v` lines, and one `l` line through them when they are a polyline.
void obj_header(std::string& out, std::uint64_t count, Eigen::Index, const PointsStyle& style) {
  out += std::string("# cifs ") + (style.polyline ? "polyline, " : "points, ") + std::to_string(count) +
         " points\n";
}

void obj_rows(std::string& out, const Eigen::Ref<const Points>& rows, std::uint64_t) {
  obj_vertices(out, rows);
}

void obj_footer(ChunkBuffer& out, std::uint64_t count, const PointsStyle& style) {
  if (!style.polyline || count < 2) return;
  out.text += "l";
  for (std::uint64_t i = 1; i <= count; ++i) {
    out.text += ' ';
    out.text += std::to_string(i);
    out.spill();
  }
  if (style.closed) out.text += " 1";
  out.text += '\n';
}

/// `vt` rows of 1 to 3 numbers (17 significant digits), spilled in between.
void texture_rows(ChunkBuffer& out, const Points& values) {
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    out.text += "vt";
    for (Eigen::Index k = 0; k < values.cols(); ++k) {
      out.text += ' ';
      append_number(out.text, values(i, k), 17);
    }
    out.text += '\n';
    out.spill();
  }
}

/// The `t` lines of the tags as OpenSubdiv's shapes write them: creases, corners, holes, then the
/// options that are not the default (the inverse of MeshReader::tag).
void obj_tags(ChunkBuffer& out, const MeshTags& tags) {
  for (const EdgeSharpness& c : tags.creases) {
    out.text += "t crease 2/1/0 " + std::to_string(c.a) + ' ' + std::to_string(c.b) + ' ';
    append_number(out.text, c.sharpness, 17);
    out.text += '\n';
    out.spill();
  }
  for (const VertexSharpness& c : tags.corners) {
    out.text += "t corner 1/1/0 " + std::to_string(c.vertex) + ' ';
    append_number(out.text, c.sharpness, 17);
    out.text += '\n';
    out.spill();
  }
  if (!tags.holes.empty()) {
    out.text += "t hole " + std::to_string(tags.holes.size()) + "/0/0";
    for (const int f : tags.holes) {
      out.text += ' ' + std::to_string(f);
      out.spill();
    }
    out.text += '\n';
  }
  if (tags.boundary != BoundaryRule::edge_only)
    out.text += std::string("t interpolateboundary 1/0/0 ") +
                (tags.boundary == BoundaryRule::none ? "0" : "1") + '\n';
  if (tags.face_varying != FaceVaryingRule::all)
    out.text += "t facevaryinginterpolateboundary 1/0/0 " +
                std::to_string(static_cast<int>(tags.face_varying)) + '\n';
  if (tags.crease_method != CreaseMethod::uniform)
    out.text += "t creasemethod 0/0/1 " + std::string(option_name(tags.crease_method)) + '\n';
  if (tags.triangles != TriangleRule::catmark)
    out.text += "t smoothtriangles 0/0/1 " + std::string(option_name(tags.triangles)) + '\n';
  // cifs's own (not OpenSubdiv's): Biermann–Levin–Zorin's rules and their concave corners.
  if (tags.rules != RuleSet::opensubdiv)
    out.text += "t rules 0/0/1 " + std::string(option_name(tags.rules)) + '\n';
  if (!tags.concave.empty()) {
    out.text += "t concave " + std::to_string(tags.concave.size()) + "/0/0";
    for (const int v : tags.concave) out.text += ' ' + std::to_string(v);
    out.text += '\n';
  }
}

/// The tags cifs reads (OpenSubdiv's regression shapes: `t name ints/floats/strings arguments`).
constexpr std::string_view kKnownTags =
    "crease, corner, hole, interpolateboundary, facevaryinginterpolateboundary, "
    "facevaryingpropagatecorners, creasemethod, smoothtriangles, rules, concave";

/// One `t` line: its name and arguments, counts checked against its `ints/floats/strings` header.
struct ObjTag {
  std::string_view name;
  std::vector<long long> ints;
  std::vector<double> floats;
  std::vector<std::string_view> strings;
};

/// The polygonal statements of an OBJ file, gathered into a mesh.
class MeshReader {
 public:
  MeshReader(std::string_view where, const MeshReadOptions& options)
      : place_{std::string(where)}, options_(options) {}

  void statement(std::size_t line, const detail::Tokens& t) {
    place_.line = line;
    if (t[0] == "v") {
      if (t.size() < 4)
        place_.syntax(line, "v: expected x y z [w], got " + std::to_string(t.size() - 1) + " numbers");
      for (std::size_t k = 1; k < t.size(); ++k) {
        const double x = place_.number(t[k], "v");  // every number is checked, the first three kept
        if (k <= 3) coordinates_.push_back(x);
      }
    } else if (t[0] == "vn") {
      if (t.size() != 4)
        place_.syntax(line, "vn: expected x y z, got " + std::to_string(t.size() - 1) + " numbers");
      for (std::size_t k = 1; k < 4; ++k) normals_.push_back(place_.number(t[k], "vn"));
    } else if (t[0] == "vt") {
      texture(t);
    } else if (t[0] == "f") {
      face(t);
    } else if (t[0] == "t") {
      tag(parse_tag(t));
    }
  }

  Mesh finish() {
    if (offsets_.size() == 1) throw InvalidInput(place_.where + ": no faces (f lines) in the file");
    Mesh mesh;
    const auto rows = static_cast<Eigen::Index>(coordinates_.size() / 3);
    mesh.vertices = Eigen::Map<const Points>(coordinates_.data(), rows, 3);
    mesh.face_offsets = std::move(offsets_);
    mesh.face_vertices = std::move(corners_);
    if (per_vertex_normals_ && normals_.size() == coordinates_.size())
      mesh.normals = Eigen::Map<const Points>(normals_.data(), rows, 3);
    if (textured_ == 1) {
      FaceVaryingChannel uv;
      uv.values = Eigen::Map<const Points>(uvs_.data(), static_cast<Eigen::Index>(uvs_.size() / uv_dim_),
                                           static_cast<Eigen::Index>(uv_dim_));
      uv.indices = std::move(uv_corners_);
      mesh.face_varying.push_back(std::move(uv));
    }
    // Hbr's "propagate corners" only meant something with edge-and-corner: it is corners+2.
    if (propagate_corners_ && tags_.face_varying == FaceVaryingRule::corners_plus1)
      tags_.face_varying = FaceVaryingRule::corners_plus2;
    check_tag_targets(mesh);
    mesh.tags = std::move(tags_);
    check_mesh(mesh, place_.where);
    return mesh;
  }

 private:
  void texture(const detail::Tokens& t) {
    const std::size_t dim = t.size() - 1;
    if (dim < 1 || dim > 3)
      place_.syntax(place_.line, "vt: expected u [v [w]], got " + std::to_string(dim) + " numbers");
    if (uv_dim_ == 0) uv_dim_ = dim;
    if (dim != uv_dim_)
      place_.invalid(place_.line, "vt: " + std::to_string(dim) + " numbers, the earlier vt lines have " +
                                      std::to_string(uv_dim_));
    for (std::size_t k = 1; k < t.size(); ++k) uvs_.push_back(place_.number(t[k], "vt"));
  }

  void face(const detail::Tokens& t) {
    if (t.size() < 4)
      place_.invalid(place_.line,
                     "f: " + std::to_string(t.size() - 1) + " vertices, a face needs at least 3");
    for (std::size_t k = 1; k < t.size(); ++k) {
      // v, v/vt, v/vt/vn or v//vn.
      const std::string_view tok = t[k];
      const std::size_t first = tok.find('/');
      const std::size_t v =
          place_.resolve(place_.integer(tok.substr(0, first), "f"), coordinates_.size() / 3, "vertex");
      std::optional<std::size_t> n, uv;
      if (first != std::string_view::npos) {
        const std::string_view rest = tok.substr(first + 1);
        const std::size_t second = rest.find('/');
        const std::string_view texture = rest.substr(0, second);
        const std::string_view normal =
            second == std::string_view::npos ? std::string_view() : rest.substr(second + 1);
        // The syntax first: "3/", "3//", "3/1/" and "3/1/1/1" are malformed whatever is defined.
        const bool cut = second != std::string_view::npos && normal.empty();
        if ((texture.empty() && normal.empty()) || cut || normal.find('/') != std::string_view::npos)
          place_.syntax(place_.line, "f: expected v, v/vt, v/vt/vn or v//vn, got " + detail::quote(tok));
        if (!texture.empty())
          uv = place_.resolve(place_.integer(texture, "f"), uv_dim_ == 0 ? 0 : uvs_.size() / uv_dim_,
                              "texture");
        if (!normal.empty()) n = place_.resolve(place_.integer(normal, "f"), normals_.size() / 3, "normal");
      }
      // UVs are one channel only when every corner of every face has its vt.
      const int textured = uv ? 1 : 0;
      if (textured_ < 0) textured_ = textured;
      if (textured != textured_)
        place_.invalid(place_.line, "f: corner " + detail::quote(tok) +
                                        (uv ? " has a texture index (v/vt) but earlier corners have none"
                                            : " has no texture index (v/vt) but earlier corners have one"));
      if (uv) uv_corners_.push_back(static_cast<int>(*uv));
      // Normals fit the mesh only when every corner uses the normal of its own vertex.
      per_vertex_normals_ = per_vertex_normals_ && n == v;
      corners_.push_back(static_cast<int>(v));
    }
    if (corners_.size() > static_cast<std::size_t>(INT_MAX))
      place_.invalid(place_.line, "more corners than 32-bit offsets hold");
    offsets_.push_back(static_cast<int>(corners_.size()));
  }

  /// `t name i/f/s` and exactly that many integers, numbers and words.
  ObjTag parse_tag(const detail::Tokens& t) const {
    if (t.size() < 3) place_.syntax(place_.line, "t: expected a name and ints/floats/strings counts");
    ObjTag tag{.name = t[1], .ints = {}, .floats = {}, .strings = {}};
    const std::string what = "t " + std::string(tag.name);
    std::array<long long, 3> counts{};
    std::string_view header = t[2];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t slash = k < 2 ? header.find('/') : std::string_view::npos;
      if (k < 2 && slash == std::string_view::npos)
        place_.syntax(place_.line,
                      what + ": expected ints/floats/strings counts, got " + detail::quote(t[2]));
      counts[k] = place_.integer(header.substr(0, slash), what);
      if (counts[k] < 0) place_.syntax(place_.line, what + ": negative count in " + detail::quote(t[2]));
      if (k < 2) header.remove_prefix(slash + 1);
    }
    const auto given = static_cast<long long>(t.size() - 3);
    if (given != counts[0] + counts[1] + counts[2])
      place_.syntax(place_.line, what + ": " + std::string(t[2]) + " announces " +
                                     std::to_string(counts[0] + counts[1] + counts[2]) + " arguments, got " +
                                     std::to_string(given));
    std::size_t k = 3;
    for (long long i = 0; i < counts[0]; ++i) tag.ints.push_back(place_.integer(t[k++], what));
    for (long long i = 0; i < counts[1]; ++i) tag.floats.push_back(place_.number(t[k++], what));
    for (long long i = 0; i < counts[2]; ++i) tag.strings.push_back(t[k++]);
    return tag;
  }

  /// Refuses a tag whose argument counts are not `ints` (−1: any number ≥ 1), `floats`, `strings`.
  void expect(const ObjTag& tag, long long ints, long long floats, long long strings) const {
    const auto i = static_cast<long long>(tag.ints.size()), f = static_cast<long long>(tag.floats.size()),
               s = static_cast<long long>(tag.strings.size());
    if ((ints < 0 ? i >= 1 : i == ints) && f == floats && s == strings) return;
    const std::string expected = (ints < 0 ? std::string("N") : std::to_string(ints)) + "/" +
                                 std::to_string(floats) + "/" + std::to_string(strings);
    place_.invalid(place_.line, "t " + std::string(tag.name) + ": expected " + expected + " arguments, got " +
                                    std::to_string(i) + "/" + std::to_string(f) + "/" + std::to_string(s));
  }

  /// The sharpness of argument k: one number for all, or one per argument.
  double sharpness(const ObjTag& tag, std::size_t k, std::size_t count) const {
    const std::string what = "t " + std::string(tag.name);
    if (tag.floats.size() != 1 && tag.floats.size() != count)
      place_.invalid(place_.line, what + ": " + std::to_string(tag.floats.size()) + " sharpness values for " +
                                      std::to_string(count) + " elements; give one for all or one each");
    const double s = tag.floats[tag.floats.size() == 1 ? 0 : k];
    if (s < 0) place_.invalid(place_.line, what + ": sharpness " + detail::num(s) + " is negative");
    return s;
  }

  /// An integer option of `t name 1/0/0 k` with k in [0, n).
  long long choice(const ObjTag& tag, long long n) const {
    expect(tag, 1, 0, 0);
    const long long k = tag.ints[0];
    if (k < 0 || k >= n)
      place_.invalid(place_.line, "t " + std::string(tag.name) + ": " + std::to_string(k) +
                                      " is not one of 0 to " + std::to_string(n - 1));
    return k;
  }

  /// A word option of `t name 0/0/1 word`, through the library's names.
  template <class Named>
  auto word(const ObjTag& tag, Named named) const {
    expect(tag, 0, 0, 1);
    try {
      return named(tag.strings[0]);
    } catch (const InvalidInput& e) {
      place_.invalid(place_.line, "t " + std::string(tag.name) + ": " + e.what());
    }
  }

  void tag(const ObjTag& tag) {
    const std::size_t line = place_.line;
    if (tag.name == "crease") {
      if (tag.ints.empty() || tag.ints.size() % 2 != 0 || tag.floats.empty() || !tag.strings.empty())
        place_.invalid(
            line, "t crease: expected vertex pairs and their sharpness (2/1/0, 4/2/0, 4/1/0, ...), got " +
                      std::to_string(tag.ints.size()) + "/" + std::to_string(tag.floats.size()) + "/" +
                      std::to_string(tag.strings.size()));
      const std::size_t pairs = tag.ints.size() / 2;
      for (std::size_t k = 0; k < pairs; ++k) {
        const EdgeSharpness c{.a = vertex(tag.ints[2 * k]),
                              .b = vertex(tag.ints[2 * k + 1]),
                              .sharpness = sharpness(tag, k, pairs)};
        // A later tag of the same edge replaces the earlier one (as in OpenSubdiv's readers).
        const auto key = std::minmax(c.a, c.b);
        const auto [it, added] = crease_index_.try_emplace(key, tags_.creases.size());
        if (added) {
          tags_.creases.push_back(c);
          crease_lines_.push_back(line);
        } else {
          tags_.creases[it->second] = c;
          crease_lines_[it->second] = line;
        }
      }
    } else if (tag.name == "corner") {
      expect(tag, -1, static_cast<long long>(std::max<std::size_t>(tag.floats.size(), 1)), 0);
      for (std::size_t k = 0; k < tag.ints.size(); ++k) {
        const VertexSharpness c{.vertex = vertex(tag.ints[k]),
                                .sharpness = sharpness(tag, k, tag.ints.size())};
        const auto [it, added] = corner_index_.try_emplace(c.vertex, tags_.corners.size());
        if (added) {
          tags_.corners.push_back(c);
          corner_lines_.push_back(line);
        } else {
          tags_.corners[it->second] = c;
          corner_lines_[it->second] = line;
        }
      }
    } else if (tag.name == "hole") {
      expect(tag, -1, 0, 0);
      for (const long long f : tag.ints) {
        if (f < 0 || f > INT_MAX)
          place_.invalid(line, "t hole: face " + std::to_string(f) + " is out of range");
        if (!hole_faces_.insert(static_cast<int>(f)).second) continue;  // listed twice: one hole
        tags_.holes.push_back(static_cast<int>(f));
        hole_lines_.push_back(line);
      }
    } else if (tag.name == "interpolateboundary") {
      constexpr BoundaryRule kRules[] = {BoundaryRule::none, BoundaryRule::edge_and_corner,
                                         BoundaryRule::edge_only};
      tags_.boundary = kRules[choice(tag, 3)];
    } else if (tag.name == "facevaryinginterpolateboundary") {
      tags_.face_varying = static_cast<FaceVaryingRule>(choice(tag, 6));
    } else if (tag.name == "facevaryingpropagatecorners") {
      propagate_corners_ = choice(tag, 2) == 1;
    } else if (tag.name == "creasemethod") {
      // RenderMan and OpenSubdiv's shapes call the uniform method "normal".
      tags_.crease_method = word(tag, [](std::string_view w) {
        if (w == "normal") return CreaseMethod::uniform;
        if (w == "chaikin") return CreaseMethod::chaikin;
        throw InvalidInput("expected normal or chaikin, got " + detail::quote(w));
      });
    } else if (tag.name == "smoothtriangles") {
      tags_.triangles = word(tag, named_triangle_rule);
    } else if (tag.name == "rules") {
      tags_.rules = word(tag, named_rule_set);
    } else if (tag.name == "concave") {
      expect(tag, -1, 0, 0);
      for (const long long v : tag.ints) {
        tags_.concave.push_back(vertex(v));
        concave_lines_.push_back(line);
      }
    } else {
      const std::string what = place_.at(line) + "t " + std::string(tag.name) + ": ";
      if (options_.strict)
        throw InvalidInput(what + "unknown tag (cifs reads " + std::string(kKnownTags) + ")");
      warn(options_, what + "unknown tag, ignored");
    }
  }

  /// A tag's 0-based vertex (its range is checked at the end, when every `v` is read).
  int vertex(long long v) const {
    if (v < 0 || v > INT_MAX)
      place_.invalid(place_.line, "t: vertex " + std::to_string(v) + " is out of range");
    return static_cast<int>(v);
  }

  /// Tags name vertices, edges and faces of the whole file: checked at its end, naming their line.
  void check_tag_targets(const Mesh& mesh) const {
    const auto V = mesh.vertices.rows();
    const auto vertex_range = [&](int v, std::size_t line, std::string_view what) {
      if (v >= V)
        place_.invalid(line, std::string(what) + ": vertex " + std::to_string(v) + " is out of range (" +
                                 std::to_string(V) + " vertices, numbered from 0)");
    };
    std::set<std::pair<int, int>> edges;
    for (std::size_t f = 0; f < face_count(mesh); ++f) {
      const auto c = cifs::face(mesh, f);
      for (std::size_t k = 0; k < c.size(); ++k) edges.insert(std::minmax(c[k], c[(k + 1) % c.size()]));
    }
    for (std::size_t i = 0; i < tags_.creases.size(); ++i) {
      const EdgeSharpness& c = tags_.creases[i];
      vertex_range(c.a, crease_lines_[i], "t crease");
      vertex_range(c.b, crease_lines_[i], "t crease");
      if (!edges.contains(std::minmax(c.a, c.b)))
        place_.invalid(crease_lines_[i],
                       "t crease: no face has the edge " + std::to_string(c.a) + " " + std::to_string(c.b));
    }
    for (std::size_t i = 0; i < tags_.corners.size(); ++i)
      vertex_range(tags_.corners[i].vertex, corner_lines_[i], "t corner");
    for (std::size_t i = 0; i < tags_.concave.size(); ++i)
      vertex_range(tags_.concave[i], concave_lines_[i], "t concave");
    for (std::size_t i = 0; i < tags_.holes.size(); ++i)
      if (static_cast<std::size_t>(tags_.holes[i]) >= face_count(mesh))
        place_.invalid(hole_lines_[i], "t hole: face " + std::to_string(tags_.holes[i]) +
                                           " is out of range (" + std::to_string(face_count(mesh)) +
                                           " faces, numbered from 0)");
  }

  detail::ObjPlace place_;
  const MeshReadOptions& options_;
  std::vector<double> coordinates_, normals_, uvs_;  // x y z per row; uv_dim_ numbers per vt row
  std::size_t uv_dim_ = 0;
  std::vector<int> offsets_{0}, corners_, uv_corners_;
  bool per_vertex_normals_ = true;
  int textured_ = -1;  // unknown until the first corner: then 1 with vt, 0 without
  MeshTags tags_;
  bool propagate_corners_ = false;
  std::vector<std::size_t> crease_lines_, corner_lines_, hole_lines_, concave_lines_;
  std::map<std::pair<int, int>, std::size_t> crease_index_;
  std::map<int, std::size_t> corner_index_;
  std::set<int> hole_faces_;
};

}  // namespace

const detail::PointsFormat detail::kObjPoints{"obj", 3, obj_header, obj_rows, obj_footer};

void warn(const MeshReadOptions& options, const std::string& message) {
  if (options.warn) {
    options.warn(message);
  } else {
    std::fprintf(stderr, "cifs: warning: %s\n", message.c_str());
  }
}

Mesh parse_mesh_obj(std::string_view text, std::string_view where, const MeshReadOptions& options) {
  MeshReader reader(where, options);
  detail::for_each_statement(text,
                             [&](std::size_t line, const detail::Tokens& t) { reader.statement(line, t); });
  return reader.finish();
}

void mesh_obj(const Mesh& mesh, ByteSink& sink) {
  check_mesh(mesh, "the mesh to write as OBJ");
  if (mesh.face_varying.size() > 1)
    throw InvalidInput("the mesh to write as OBJ has " + std::to_string(mesh.face_varying.size()) +
                       " face-varying channels; OBJ holds one (vt)");
  if (!mesh.face_varying.empty() &&
      (mesh.face_varying[0].values.cols() < 1 || mesh.face_varying[0].values.cols() > 3))
    throw InvalidInput("the mesh to write as OBJ has face-varying values of " +
                       std::to_string(mesh.face_varying[0].values.cols()) + " columns; vt holds 1 to 3");
  const bool normals = mesh.normals.size() != 0;
  const FaceVaryingChannel* uv = mesh.face_varying.empty() ? nullptr : &mesh.face_varying[0];
  ChunkBuffer out(sink);
  out.text = "# cifs mesh, " + std::to_string(mesh.vertices.rows()) + " vertices, " +
             std::to_string(face_count(mesh)) + " faces\n";
  obj_vertices(out, mesh.vertices);
  if (uv) texture_rows(out, uv->values);
  if (normals) obj_vertices(out, mesh.normals, "vn");
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    out.text += 'f';
    for (int k = mesh.face_offsets[f]; k < mesh.face_offsets[f + 1]; ++k) {
      const std::string v = std::to_string(mesh.face_vertices[static_cast<std::size_t>(k)] + 1);
      out.text += ' ' + v;
      if (uv) out.text += '/' + std::to_string(uv->indices[static_cast<std::size_t>(k)] + 1);
      if (normals)
        out.text +=
            (uv ? "/" : "//") + (mesh.normal_indices.empty()
                                     ? v
                                     : std::to_string(mesh.normal_indices[static_cast<std::size_t>(k)] + 1));
    }
    out.text += '\n';
    out.spill();
  }
  obj_tags(out, mesh.tags);
  out.flush();
}

std::string mesh_obj(const Mesh& mesh) {
  StringSink out;
  mesh_obj(mesh, out);
  return std::move(out.bytes);
}

void segments_obj(const Segments& segments, ByteSink& sink) {
  check_segments(segments, "the segments to write as OBJ");
  ChunkBuffer out(sink);
  out.text = "# cifs segments, " + std::to_string(segments.vertices.rows()) + " vertices, " +
             std::to_string(segments.segments.size()) + " segments\n";
  obj_vertices(out, segments.vertices);
  for (const auto& s : segments.segments) {
    out.text += "l " + std::to_string(s[0] + 1) + ' ' + std::to_string(s[1] + 1) + '\n';
    out.spill();
  }
  out.flush();
}

std::string segments_obj(const Segments& segments) {
  StringSink out;
  segments_obj(segments, out);
  return std::move(out.bytes);
}

std::string polyline_obj(const Points& points, bool closed) {
  StringSink out;
  PointsWriter w(out, "obj", static_cast<std::uint64_t>(points.rows()), points.cols(),
                 {.polyline = true, .closed = closed, .seed = {}});
  w.write(points);
  w.finish();
  return std::move(out.bytes);
}

}  // namespace cifs::io
