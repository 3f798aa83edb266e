// SPDX-License-Identifier: MIT
// cifs — OFF (Object File Format), read and written: the counts, the vertices, one line per face.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/io/mesh_formats.hpp"

namespace cifs::io {
namespace {

/// The numbers of the lines of an OFF file, `#` comments and blank lines skipped.
class OffLines {
 public:
  OffLines(std::string_view text, std::string_view where) : text_(text), where_(where) {}

  /// The next line's fields; false at the end of the text.
  bool next(std::vector<std::string_view>& fields) {
    while (pos_ < text_.size()) {
      const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      line = line.substr(0, line.find('#'));
      fields.clear();
      for (std::size_t i = 0; i < line.size();) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        const std::size_t start = i;
        while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i > start) fields.push_back(line.substr(start, i - start));
      }
      if (!fields.empty()) return true;
    }
    return false;
  }
  std::string place() const { return std::string(where_) + ": line " + std::to_string(line_); }

  double real(std::string_view field) const {
    double x = 0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), x);
    if (ec != std::errc() || end != field.data() + field.size() || !std::isfinite(x))
      throw InvalidInput(place() + ": '" + excerpt(field) + "' is not a finite number");
    return x;
  }
  long long integer(std::string_view field, long long low, long long high, std::string_view what) const {
    long long x = 0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), x);
    if (ec != std::errc() || end != field.data() + field.size() || x < low || x > high)
      throw InvalidInput(place() + ": " + std::string(what) + " '" + excerpt(field) +
                         "' is not an integer in " + std::to_string(low) + " … " + std::to_string(high));
    return x;
  }

 private:
  std::string_view text_, where_;
  std::size_t pos_ = 0, line_ = 0;
};

}  // namespace

Mesh parse_mesh_off(std::string_view text, std::string_view where, const MeshReadOptions& options) {
  OffLines lines(text, where);
  std::vector<std::string_view> f;
  if (!lines.next(f)) throw InvalidInput(std::string(where) + ": empty OFF file");
  // The keyword: [C][N]OFF in either order of C and N; others are OFF variants cifs does not read.
  bool normals = false, colours = false;
  if (f[0].size() >= 3 && f[0].substr(f[0].size() - 3) == "OFF") {
    const std::string_view prefix = f[0].substr(0, f[0].size() - 3);
    if (prefix != "" && prefix != "N" && prefix != "C" && prefix != "NC" && prefix != "CN")
      throw InvalidInput(lines.place() + ": the OFF variant '" + excerpt(f[0]) +
                         "' is not read (only OFF, NOFF, COFF and CNOFF: 3-D polygon meshes)");
    normals = prefix.find('N') != std::string_view::npos;
    colours = prefix.find('C') != std::string_view::npos;
    f.erase(f.begin());
    if (f.empty() && !lines.next(f)) throw InvalidInput(lines.place() + ": the counts are missing");
  }
  if (f.size() != 3)
    throw InvalidInput(lines.place() + ": expected the counts 'vertices faces edges', got " +
                       std::to_string(f.size()) + " fields");
  const auto vertices = lines.integer(f[0], 0, INT_MAX, "the vertex count");
  const auto faces = lines.integer(f[1], 1, INT_MAX, "the face count");
  // A count beyond what the text can hold (two bytes a number at least) is refused before allocating.
  if (static_cast<double>(vertices) * 6 + static_cast<double>(faces) * 8 > static_cast<double>(text.size()))
    throw InvalidInput(lines.place() + ": " + std::to_string(vertices) + " vertices and " +
                       std::to_string(faces) + " faces cannot fit in the " + std::to_string(text.size()) +
                       " bytes of the file");
  Mesh mesh;
  mesh.vertices.resize(vertices, 3);
  if (normals) mesh.normals.resize(vertices, 3);
  const std::size_t columns = normals ? 6 : 3;
  bool coloured = false;
  for (Eigen::Index i = 0; i < vertices; ++i) {
    if (!lines.next(f))
      throw InvalidInput(lines.place() + ": the file ends after " + std::to_string(i) + " of " +
                         std::to_string(vertices) + " vertices");
    if (f.size() < columns || (f.size() > columns && !colours))
      throw InvalidInput(lines.place() + ": vertex " + std::to_string(i) + " has " +
                         std::to_string(f.size()) + " numbers, expected " + std::to_string(columns) +
                         (colours ? " and a colour" : ""));
    coloured = coloured || f.size() > columns;
    for (std::size_t c = 0; c < columns; ++c)
      (c < 3 ? mesh.vertices : mesh.normals)(i, static_cast<Eigen::Index>(c % 3)) = lines.real(f[c]);
  }
  bool face_colours = false;
  for (long long k = 0; k < faces; ++k) {
    if (!lines.next(f))
      throw InvalidInput(lines.place() + ": the file ends after " + std::to_string(k) + " of " +
                         std::to_string(faces) + " faces");
    const auto n = static_cast<std::size_t>(lines.integer(f[0], 3, INT_MAX, "the corner count"));
    if (f.size() < n + 1)
      throw InvalidInput(lines.place() + ": face " + std::to_string(k) + " lists " +
                         std::to_string(f.size() - 1) + " of its " + std::to_string(n) + " corners");
    face_colours = face_colours || f.size() > n + 1;
    std::vector<int> corners(n);
    for (std::size_t c = 0; c < n; ++c)
      corners[c] = static_cast<int>(lines.integer(f[c + 1], 0, vertices - 1, "the vertex index"));
    add_face(mesh, corners);
  }
  if (coloured || face_colours)
    warn(options, std::string(where) + ": the " +
                      (coloured && face_colours ? "vertex and face"
                       : coloured               ? "vertex"
                                                : "face") +
                      " colours are not read");
  check_mesh(mesh, where);
  return mesh;
}

void mesh_off(const Mesh& mesh, ByteSink& sink) {
  check_mesh(mesh, "the mesh to write as OFF");
  if (!mesh.normal_indices.empty())
    throw InvalidInput(
        "the mesh to write as OFF has normals per face corner (several at crease and corner "
        "vertices); OFF holds one per vertex: write OBJ, or drop the normals");
  const bool normals = mesh.normals.size() != 0;
  const std::vector<char> hole = hole_flags(mesh);
  ChunkBuffer buffer(sink);
  std::string& out = buffer.text;
  out += normals ? "NOFF\n" : "OFF\n";
  out += std::to_string(mesh.vertices.rows()) + " " +
         std::to_string(std::count(hole.begin(), hole.end(), 0)) + " 0\n";
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      if (c > 0) out += ' ';
      append_number(out, mesh.vertices(i, c), 17);
    }
    for (Eigen::Index c = 0; normals && c < 3; ++c) {
      out += ' ';
      append_number(out, mesh.normals(i, c), 17);
    }
    out += '\n';
    buffer.spill();
  }
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    if (hole[f] != 0) continue;
    const auto corners = face(mesh, f);
    out += std::to_string(corners.size());
    for (const int v : corners) out += " " + std::to_string(v);
    out += '\n';
    buffer.spill();
  }
  buffer.flush();
}

}  // namespace cifs::io
