// SPDX-License-Identifier: MIT
// cifs — OBJ polygonal geometry: meshes (read and written), segment sets and polylines (written).
// The free-form curves and surfaces are in obj_freeform.cpp.
#include <algorithm>
#include <cstdio>
#include <optional>

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
void points_header(std::string& out, std::uint64_t count, Eigen::Index, const PointsStyle& style) {
  out += std::string("# cifs ") + (style.polyline ? "polyline, " : "points, ") + std::to_string(count) +
         " points\n";
}

void points_rows(std::string& out, const Eigen::Ref<const Points>& rows, std::uint64_t) {
  obj_vertices(out, rows);
}

void points_footer(ChunkBuffer& out, std::uint64_t count, const PointsStyle& style) {
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

/// The polygonal statements of an OBJ file, gathered into a mesh.
class MeshReader {
 public:
  explicit MeshReader(std::string_view where) : place_{std::string(where)} {}

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
    } else if (t[0] == "f") {
      face(t);
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
    check_mesh(mesh, place_.where);
    return mesh;
  }

 private:
  void face(const detail::Tokens& t) {
    if (t.size() < 4)
      place_.invalid(place_.line,
                     "f: " + std::to_string(t.size() - 1) + " vertices, a face needs at least 3");
    for (std::size_t k = 1; k < t.size(); ++k) {
      // v, v/vt, v/vt/vn or v//vn: the texture part is checked and ignored.
      const std::string_view tok = t[k];
      const std::size_t first = tok.find('/');
      const std::size_t v =
          place_.resolve(place_.integer(tok.substr(0, first), "f"), coordinates_.size() / 3, "vertex");
      std::optional<std::size_t> n;
      if (first != std::string_view::npos) {
        const std::string_view rest = tok.substr(first + 1);
        const std::size_t second = rest.find('/');
        const std::string_view texture = rest.substr(0, second);
        if (!texture.empty()) place_.integer(texture, "f");
        if (second != std::string_view::npos) {
          const std::string_view normal = rest.substr(second + 1);
          if (normal.empty() || normal.find('/') != std::string_view::npos)
            place_.syntax(place_.line, "f: expected v, v/vt, v/vt/vn or v//vn, got " + detail::quote(tok));
          n = place_.resolve(place_.integer(normal, "f"), normals_.size() / 3, "normal");
        } else if (texture.empty()) {
          place_.syntax(place_.line, "f: expected v, v/vt, v/vt/vn or v//vn, got " + detail::quote(tok));
        }
      }
      // Normals fit the mesh only when every corner uses the normal of its own vertex.
      per_vertex_normals_ = per_vertex_normals_ && n == v;
      corners_.push_back(static_cast<int>(v));
    }
    if (corners_.size() > static_cast<std::size_t>(INT_MAX))
      place_.invalid(place_.line, "more corners than 32-bit offsets hold");
    offsets_.push_back(static_cast<int>(corners_.size()));
  }

  detail::ObjPlace place_;
  std::vector<double> coordinates_, normals_;  // x y z per row
  std::vector<int> offsets_{0}, corners_;
  bool per_vertex_normals_ = true;
};

}  // namespace

const detail::PointsFormat detail::kObjPoints{"obj", 3, points_header, points_rows, points_footer};

Mesh parse_mesh_obj(std::string_view text, std::string_view where) {
  MeshReader reader(where);
  detail::for_each_statement(text,
                             [&](std::size_t line, const detail::Tokens& t) { reader.statement(line, t); });
  return reader.finish();
}

void mesh_obj(const Mesh& mesh, ByteSink& sink) {
  check_mesh(mesh, "the mesh to write as OBJ");
  const bool normals = mesh.normals.size() != 0;
  ChunkBuffer out(sink);
  out.text = "# cifs mesh, " + std::to_string(mesh.vertices.rows()) + " vertices, " +
             std::to_string(face_count(mesh)) + " faces\n";
  obj_vertices(out, mesh.vertices);
  if (normals) obj_vertices(out, mesh.normals, "vn");
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    out.text += 'f';
    for (const int i : face(mesh, f)) {
      const std::string k = std::to_string(i + 1);
      out.text += ' ' + k;
      if (normals) out.text += "//" + k;
    }
    out.text += '\n';
    out.spill();
  }
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
