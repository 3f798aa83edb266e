// SPDX-License-Identifier: MIT
// cifs — STL, binary written, binary and ASCII read. A file is a triangle soup: the reader welds corners
// at the same position back into shared vertices, so that a mesh read from STL subdivides as a surface.
#include <array>
#include <bit>
#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/io/mesh_formats.hpp"

namespace cifs::io {
namespace {

void put_u32(std::string& out, std::uint32_t x) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((x >> (8 * i)) & 0xffu);  // little-endian
}

void put_f32(std::string& out, float x) {
  put_u32(out, std::bit_cast<std::uint32_t>(x));
}

std::uint32_t get_u32(std::string_view bytes, std::size_t at) {
  std::uint32_t x = 0;
  for (int i = 3; i >= 0; --i)
    x = (x << 8) | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)]);
  return x;
}

/// Corners at the same position, one vertex: keyed by the coordinates' bits (−0 as +0).
struct Welder {
  struct Key {
    std::array<std::uint64_t, 3> bits;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const noexcept {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (const std::uint64_t b : k.bits) h = (h ^ b) * 0xff51afd7ed558ccdull;
      return static_cast<std::size_t>(h ^ (h >> 32));
    }
  };
  std::unordered_map<Key, int, Hash> index;
  std::vector<std::array<double, 3>> positions;

  int vertex(const std::array<double, 3>& p) {
    Key key{};
    for (std::size_t c = 0; c < 3; ++c) key.bits[c] = std::bit_cast<std::uint64_t>(p[c] == 0 ? 0.0 : p[c]);
    const auto [it, fresh] = index.try_emplace(key, static_cast<int>(positions.size()));
    if (fresh) positions.push_back(p);
    return it->second;
  }
};

/// The welded triangles as a mesh; degenerate ones (two corners at one position) counted and left out.
Mesh welded_mesh(Welder& welder, const std::vector<std::array<int, 3>>& triangles, std::string_view where,
                 const MeshReadOptions& options) {
  Mesh mesh;
  std::size_t degenerate = 0;
  for (const auto& [a, b, c] : triangles) {
    if (a == b || b == c || c == a) {
      ++degenerate;
      continue;
    }
    add_face(mesh, {a, b, c});
  }
  if (degenerate > 0)
    warn(options, std::string(where) + ": " + std::to_string(degenerate) + " of " +
                      std::to_string(triangles.size()) +
                      " triangles have two corners at one position; left out");
  if (face_count(mesh) == 0)
    throw InvalidInput(std::string(where) + ": no triangle with three distinct corners");
  mesh.vertices.resize(static_cast<Eigen::Index>(welder.positions.size()), 3);
  for (std::size_t i = 0; i < welder.positions.size(); ++i)
    for (std::size_t c = 0; c < 3; ++c)
      mesh.vertices(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) = welder.positions[i][c];
  check_mesh(mesh, where);
  return mesh;
}

Mesh parse_binary(std::string_view bytes, std::string_view where, const MeshReadOptions& options) {
  const std::uint32_t n = get_u32(bytes, 80);
  Welder welder;
  std::vector<std::array<int, 3>> triangles(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::size_t at = 84 + std::size_t{50} * t + 12;  // after the normal
    for (std::size_t k = 0; k < 3; ++k) {
      std::array<double, 3> p{};
      for (std::size_t c = 0; c < 3; ++c) {
        const auto x = std::bit_cast<float>(get_u32(bytes, at + 12 * k + 4 * c));
        if (!std::isfinite(x))
          throw InvalidInput(std::string(where) + ": triangle " + std::to_string(t) + ", corner " +
                             std::to_string(k) + ": a coordinate is not finite");
        p[c] = x;
      }
      triangles[t][k] = welder.vertex(p);
    }
  }
  return welded_mesh(welder, triangles, where, options);
}

std::string quoted(std::string_view token) {
  return token.empty() ? std::string("the end of the file") : "'" + excerpt(token) + "'";
}

/// ASCII STL, read token by token: `solid [name]`, then per facet `facet normal x y z`, `outer loop`,
/// three `vertex x y z`, `endloop`, `endfacet`; `endsolid [name]`.
Mesh parse_ascii(std::string_view text, std::string_view where, const MeshReadOptions& options) {
  std::size_t pos = 0, line = 1;
  const auto token = [&]() -> std::string_view {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos])))
      line += text[pos++] == '\n';
    const std::size_t start = pos;
    while (pos < text.size() && !std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
    return text.substr(start, pos - start);
  };
  const auto place = [&] { return std::string(where) + ": line " + std::to_string(line); };
  const auto expect = [&](std::string_view word) {
    if (const std::string_view got = token(); got != word)
      throw InvalidInput(place() + ": expected '" + std::string(word) + "', got " + quoted(got));
  };
  const auto number = [&]() {
    const std::string_view t = token();
    double x = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(x))
      throw InvalidInput(place() + ": '" + excerpt(t) + "' is not a finite number");
    return x;
  };
  expect("solid");
  // The name runs to the end of the line.
  while (pos < text.size() && text[pos] != '\n') ++pos;
  Welder welder;
  std::vector<std::array<int, 3>> triangles;
  for (std::string_view word = token(); word != "endsolid"; word = token()) {
    if (word != "facet")
      throw InvalidInput(place() + ": expected 'facet' or 'endsolid', got " + quoted(word));
    expect("normal");
    for (int c = 0; c < 3; ++c) number();
    expect("outer");
    expect("loop");
    std::array<int, 3> corners{};
    for (int& corner : corners) {
      expect("vertex");
      const double x = number(), y = number(), z = number();
      corner = welder.vertex({x, y, z});
    }
    expect("endloop");
    expect("endfacet");
    triangles.push_back(corners);
  }
  return welded_mesh(welder, triangles, where, options);
}

}  // namespace

void mesh_stl(const Mesh& mesh, ByteSink& sink) {
  check_mesh(mesh, "the mesh to write as STL");
  const std::vector<char> hole = hole_flags(mesh);
  std::uint64_t triangles = 0;
  for (std::size_t f = 0; f < face_count(mesh); ++f)
    if (hole[f] == 0) triangles += face(mesh, f).size() - 2;
  if (triangles > UINT32_MAX)
    throw InvalidInput("the mesh to write as STL has " + std::to_string(triangles) +
                       " triangles; STL counts at most 4294967295");
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    for (Eigen::Index c = 0; c < 3; ++c)
      if (std::abs(mesh.vertices(i, c)) > FLT_MAX)
        throw InvalidInput("the mesh to write as STL has vertex " + std::to_string(i) + " at " +
                           number_text(mesh.vertices(i, c), 6) +
                           ", beyond the float range STL stores (±3.4e38): scale it, or write PLY or OBJ");
  ChunkBuffer buffer(sink);
  std::string& out = buffer.text;
  std::string header = "cifs binary STL";  // never "solid…": readers would take it for ASCII
  header.resize(80, ' ');
  out += header;
  put_u32(out, static_cast<std::uint32_t>(triangles));
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    if (hole[f] != 0) continue;
    const auto corners = face(mesh, f);
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
      const Eigen::Vector3d a = mesh.vertices.row(corners[0]).transpose();
      const Eigen::Vector3d b = mesh.vertices.row(corners[i]).transpose();
      const Eigen::Vector3d c = mesh.vertices.row(corners[i + 1]).transpose();
      const Eigen::Vector3d n = (b - a).cross(c - a);
      const double length = n.norm();
      const Eigen::Vector3d unit =
          length > 0 && std::isfinite(length) ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d* v : {&unit, &a, &b, &c})
        for (Eigen::Index k = 0; k < 3; ++k) put_f32(out, static_cast<float>((*v)(k)));
      out += std::string(2, '\0');  // the attribute byte count
      buffer.spill();
    }
  }
  buffer.flush();
}

Mesh parse_mesh_stl(std::string_view bytes, std::string_view where, const MeshReadOptions& options) {
  // Binary when the size is what its triangle count says: an ASCII file may start with "solid" too.
  if (bytes.size() >= 84 && bytes.size() == 84 + std::uint64_t{50} * get_u32(bytes, 80))
    return parse_binary(bytes, where, options);
  std::size_t first = 0;
  while (first < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[first]))) ++first;
  if (bytes.substr(first, 5) == "solid") return parse_ascii(bytes, where, options);
  if (bytes.size() >= 84)
    throw InvalidInput(std::string(where) + ": neither ASCII STL (no 'solid') nor binary STL (" +
                       std::to_string(bytes.size()) + " bytes where " + std::to_string(get_u32(bytes, 80)) +
                       " triangles take " + std::to_string(84 + std::uint64_t{50} * get_u32(bytes, 80)) +
                       ")");
  throw InvalidInput(std::string(where) + ": neither ASCII STL (no 'solid') nor binary STL (" +
                     std::to_string(bytes.size()) + " bytes, fewer than the 84 of its header)");
}

}  // namespace cifs::io
