// SPDX-License-Identifier: MIT
// cifs — meshes, segment sets and polylines as OBJ, PLY and SVG.
#include "cifs/io/geometry.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "cifs/errors.hpp"
#include "cifs/io/polyline.hpp"

namespace cifs::io {
namespace {

void append_number(std::string& out, double x, const char* format = "%.17g") {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, x);
  out += buffer;
}

std::string at(std::string_view what, std::size_t i) {
  return std::string(what) + "[" + std::to_string(i) + "]";
}

void check_rows(const Points& P, std::string_view who, std::string_view what) {
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    for (Eigen::Index k = 0; k < P.cols(); ++k)
      if (!std::isfinite(P(i, k)))
        throw InvalidInput(std::string(who) + ": " + at(what, static_cast<std::size_t>(i)) +
                           " is not finite");
}

template <std::size_t N>
void check_indices(const std::vector<std::array<int, N>>& items, Eigen::Index vertices, std::string_view who,
                   std::string_view what) {
  for (std::size_t f = 0; f < items.size(); ++f)
    for (std::size_t k = 0; k < N; ++k)
      if (items[f][k] < 0 || items[f][k] >= vertices)
        throw InvalidInput(std::string(who) + ": " + at(what, f) + "[" + std::to_string(k) +
                           "] = " + std::to_string(items[f][k]) + " is out of range (" +
                           std::to_string(vertices) + " vertices)");
}

/// `v` lines with missing coordinates set to 0.
void obj_vertices(std::string& out, const Points& P, const char* tag = "v") {
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    out += tag;
    for (Eigen::Index k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, k < P.cols() ? P(i, k) : 0.0);
    }
    out += '\n';
  }
}

/// PLY body writer: ASCII values separated by spaces, or little-endian bytes.
class PlyWriter {
 public:
  explicit PlyWriter(PlyFormat format) : binary_(format == PlyFormat::binary_little_endian) {}
  std::string out;
  void f64(double x) {
    if (binary_) return bytes(std::bit_cast<std::uint64_t>(x), 8);
    separate();
    append_number(out, x);
  }
  void i32(int x) {
    if (binary_) return bytes(static_cast<std::uint32_t>(x), 4);
    separate();
    out += std::to_string(x);
  }
  void u32(std::uint32_t x) {
    if (binary_) return bytes(x, 4);
    separate();
    out += std::to_string(x);
  }
  void u8(unsigned x) {
    if (binary_) return bytes(x, 1);
    separate();
    out += std::to_string(x);
  }
  void end_row() {
    if (!binary_) out += '\n';
    first_ = true;
  }
  const char* format_name() const { return binary_ ? "binary_little_endian" : "ascii"; }

 private:
  // Byte by byte, least significant first: little-endian on any host.
  void bytes(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
  }
  void separate() {
    if (!first_) out += ' ';
    first_ = false;
  }
  bool binary_;
  bool first_ = true;
};

/// Header and vertex element shared by meshes and segment sets.
void ply_vertices(PlyWriter& w, const Points& P, const Points* normals, std::string_view comment) {
  w.out = std::string("ply\nformat ") + w.format_name() + " 1.0\ncomment " + std::string(comment) +
          "\nelement vertex " + std::to_string(P.rows()) +
          "\nproperty double x\nproperty double y\nproperty double z\n";
  if (normals) w.out += "property double nx\nproperty double ny\nproperty double nz\n";
}

void ply_vertex_rows(PlyWriter& w, const Points& P, const Points* normals) {
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    for (Eigen::Index k = 0; k < 3; ++k) w.f64(k < P.cols() ? P(i, k) : 0.0);
    if (normals)
      for (Eigen::Index k = 0; k < 3; ++k) w.f64((*normals)(i, k));
    w.end_row();
  }
}

}  // namespace

Segments polyline_segments(const Points& polyline, bool closed, std::uint32_t state) {
  Segments s;
  s.vertices = polyline;
  const int n = static_cast<int>(polyline.rows());
  for (int i = 0; i + 1 < n; ++i) s.segments.push_back({i, i + 1});
  if (closed && n > 2) s.segments.push_back({n - 1, 0});
  s.states.assign(s.segments.size(), state);
  return s;
}

void append(Segments& into, const Segments& more) {
  if (into.vertices.rows() == 0 && into.segments.empty()) {
    into = more;
    return;
  }
  if (into.vertices.cols() != more.vertices.cols())
    throw InvalidInput("append: segments with " + std::to_string(into.vertices.cols()) + " and " +
                       std::to_string(more.vertices.cols()) + " coordinates");
  const int offset = static_cast<int>(into.vertices.rows());
  const bool states = !into.states.empty() || !more.states.empty();
  if (states) {
    into.states.resize(into.segments.size(), 0);
    into.states.insert(into.states.end(), more.states.begin(), more.states.end());
    into.states.resize(into.segments.size() + more.segments.size(), 0);
  }
  Points v(into.vertices.rows() + more.vertices.rows(), into.vertices.cols());
  v << into.vertices, more.vertices;
  into.vertices = std::move(v);
  for (const auto& s : more.segments) into.segments.push_back({s[0] + offset, s[1] + offset});
}

void check_mesh(const Mesh& mesh, std::string_view who) {
  const std::string w(who);
  if (mesh.vertices.cols() != 3 && mesh.vertices.rows() > 0)
    throw InvalidInput(w + ": mesh vertices have " + std::to_string(mesh.vertices.cols()) +
                       " columns, expected 3");
  check_rows(mesh.vertices, who, "vertices");
  check_indices(mesh.triangles, mesh.vertices.rows(), who, "triangles");
  check_indices(mesh.quads, mesh.vertices.rows(), who, "quads");
  if (mesh.normals.size() != 0) {
    if (mesh.normals.rows() != mesh.vertices.rows() || mesh.normals.cols() != 3)
      throw InvalidInput(w + ": normals are " + std::to_string(mesh.normals.rows()) + " by " +
                         std::to_string(mesh.normals.cols()) + ", expected " +
                         std::to_string(mesh.vertices.rows()) + " by 3 (one per vertex)");
    check_rows(mesh.normals, who, "normals");
  }
  const std::size_t faces = mesh.triangles.size() + mesh.quads.size();
  if (!mesh.states.empty() && mesh.states.size() != faces)
    throw InvalidInput(w + ": " + std::to_string(mesh.states.size()) + " states for " +
                       std::to_string(faces) + " faces");
}

void check_segments(const Segments& segments, std::string_view who) {
  const std::string w(who);
  const auto cols = segments.vertices.cols();
  if ((cols != 2 && cols != 3) && segments.vertices.rows() > 0)
    throw InvalidInput(w + ": segment vertices have " + std::to_string(cols) + " columns, expected 2 or 3");
  check_rows(segments.vertices, who, "vertices");
  check_indices(segments.segments, segments.vertices.rows(), who, "segments");
  if (!segments.states.empty() && segments.states.size() != segments.segments.size())
    throw InvalidInput(w + ": " + std::to_string(segments.states.size()) + " states for " +
                       std::to_string(segments.segments.size()) + " segments");
}

Points vertex_normals(const Mesh& mesh) {
  check_mesh(mesh, "vertex_normals");
  Points N = Points::Zero(mesh.vertices.rows(), 3);
  const auto v = [&](int i) { return Eigen::Vector3d(mesh.vertices.row(i).transpose()); };
  const auto add = [&](int i, const Eigen::Vector3d& n) { N.row(i) += n.transpose(); };
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d n = (v(t[1]) - v(t[0])).cross(v(t[2]) - v(t[0]));
    for (const int i : t) add(i, n);
  }
  for (const auto& q : mesh.quads) {
    // The vector area of a (possibly skew) quad is half the cross product of its diagonals.
    const Eigen::Vector3d n = (v(q[2]) - v(q[0])).cross(v(q[3]) - v(q[1]));
    for (const int i : q) add(i, n);
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double length = N.row(i).norm();
    if (length > 0) N.row(i) /= length;
  }
  return N;
}

std::string mesh_obj(const Mesh& mesh) {
  check_mesh(mesh, "mesh_obj");
  const bool normals = mesh.normals.size() != 0;
  std::string out = "# cifs mesh, " + std::to_string(mesh.vertices.rows()) + " vertices, " +
                    std::to_string(mesh.triangles.size() + mesh.quads.size()) + " faces\n";
  obj_vertices(out, mesh.vertices);
  if (normals) obj_vertices(out, mesh.normals, "vn");
  const auto face = [&](const auto& f) {
    out += 'f';
    for (const int i : f) {
      const std::string k = std::to_string(i + 1);
      out += ' ' + k;
      if (normals) out += "//" + k;
    }
    out += '\n';
  };
  for (const auto& t : mesh.triangles) face(t);
  for (const auto& q : mesh.quads) face(q);
  return out;
}

std::string segments_obj(const Segments& segments) {
  check_segments(segments, "segments_obj");
  std::string out = "# cifs segments, " + std::to_string(segments.vertices.rows()) + " vertices, " +
                    std::to_string(segments.segments.size()) + " segments\n";
  obj_vertices(out, segments.vertices);
  for (const auto& s : segments.segments)
    out += "l " + std::to_string(s[0] + 1) + ' ' + std::to_string(s[1] + 1) + '\n';
  return out;
}

std::string mesh_ply(const Mesh& mesh, PlyFormat format) {
  check_mesh(mesh, "mesh_ply");
  const Points* normals = mesh.normals.size() != 0 ? &mesh.normals : nullptr;
  PlyWriter w(format);
  ply_vertices(w, mesh.vertices, normals, "cifs mesh");
  w.out += "element face " + std::to_string(mesh.triangles.size() + mesh.quads.size()) +
           "\nproperty list uchar int vertex_indices\n";
  if (!mesh.states.empty()) w.out += "property uint state\n";
  w.out += "end_header\n";
  ply_vertex_rows(w, mesh.vertices, normals);
  std::size_t f = 0;
  const auto face = [&](const auto& indices) {
    w.u8(static_cast<unsigned>(indices.size()));
    for (const int i : indices) w.i32(i);
    if (!mesh.states.empty()) w.u32(mesh.states[f]);
    ++f;
    w.end_row();
  };
  for (const auto& t : mesh.triangles) face(t);
  for (const auto& q : mesh.quads) face(q);
  return std::move(w.out);
}

std::string segments_ply(const Segments& segments, PlyFormat format) {
  check_segments(segments, "segments_ply");
  PlyWriter w(format);
  ply_vertices(w, segments.vertices, nullptr, "cifs segments");
  w.out += "element edge " + std::to_string(segments.segments.size()) +
           "\nproperty int vertex1\nproperty int vertex2\n";
  if (!segments.states.empty()) w.out += "property uint state\n";
  w.out += "end_header\n";
  ply_vertex_rows(w, segments.vertices, nullptr);
  for (std::size_t e = 0; e < segments.segments.size(); ++e) {
    w.i32(segments.segments[e][0]);
    w.i32(segments.segments[e][1]);
    if (!segments.states.empty()) w.u32(segments.states[e]);
    w.end_row();
  }
  return std::move(w.out);
}

std::string segments_svg(const Segments& segments, const SvgOptions& options) {
  check_segments(segments, "segments_svg");
  const Points& P = segments.vertices;
  if (P.rows() == 0) throw InvalidInput("segments_svg: no vertices");
  const int width = options.width;
  if (width < 16 || width > 100000)
    throw InvalidInput("segments_svg: width " + std::to_string(width) + " is outside [16, 100000]");
  if (!(options.stroke > 0) || !std::isfinite(options.stroke))
    throw InvalidInput("segments_svg: the stroke width must be positive");
  const Eigen::Vector2d lo = P.leftCols(2).colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = P.leftCols(2).colwise().maxCoeff().transpose();
  const double span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-300});
  const double margin = 0.05 * width, scale = (width - 2 * margin) / span;
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y()) * scale + 2 * margin));
  std::string out =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" +
      std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) +
      "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<path fill=\"none\" stroke=\"" +
      options.color + "\" stroke-linecap=\"round\" stroke-linejoin=\"round\" stroke-width=\"";
  append_number(out, options.stroke, "%g");
  out += "\" d=\"";
  const auto point = [&](int i) {
    append_number(out, margin + (P(i, 0) - lo.x()) * scale, "%.3f");
    out += ',';
    append_number(out, height - margin - (P(i, 1) - lo.y()) * scale, "%.3f");
  };
  int previous = -1;
  for (const auto& s : segments.segments) {
    // A segment that starts where the previous one ended continues the run (a proper join).
    if (s[0] != previous) {
      if (previous != -1) out += ' ';
      out += 'M';
      point(s[0]);
    }
    out += " L";
    point(s[1]);
    previous = s[1];
  }
  out += "\"/>\n</svg>\n";
  return out;
}

std::string polyline_obj(const Points& points, bool closed) {
  if (points.cols() > 3)
    throw InvalidInput("OBJ: points have " + std::to_string(points.cols()) +
                       " coordinates, OBJ holds at most 3");
  std::string out = "# cifs polyline, " + std::to_string(points.rows()) + " points\n";
  obj_vertices(out, points);
  if (points.rows() > 1) {
    out += "l";
    for (Eigen::Index i = 0; i < points.rows(); ++i) out += ' ' + std::to_string(i + 1);
    if (closed) out += " 1";
    out += '\n';
  }
  return out;
}

std::string polyline_svg(const Points& points, bool closed, int width, double stroke) {
  if (points.cols() < 2) throw InvalidInput("SVG: points need at least 2 coordinates");
  Segments s = polyline_segments(points.leftCols(2), closed);
  s.states.clear();
  SvgOptions options;
  options.width = width;
  options.stroke = stroke;
  return segments_svg(s, options);
}

}  // namespace cifs::io
