// SPDX-License-Identifier: MIT
// cifs — PLY: meshes and segment sets written as ASCII or binary; polygon meshes read.
#include "cifs/io/ply.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <system_error>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "points_format.hpp"

namespace cifs::io {
namespace {

// ------------------------------------------------------------------------------------------------
// Writing

const char* format_name(PlyFormat format) noexcept {
  switch (format) {
    case PlyFormat::ascii:
      return "ascii";
    case PlyFormat::binary_little_endian:
      return "binary_little_endian";
    case PlyFormat::binary_big_endian:
      return "binary_big_endian";
  }
  return "";
}

/// PLY body writer: ASCII values separated by spaces, or bytes in the format's order, handed to the
/// sink a chunk at a time (`finish` hands on the rest).
class PlyWriter {
 public:
  PlyWriter(PlyFormat format, ByteSink& sink) : buffer_(sink), out(buffer_.text), format_(format) {}

 private:
  ChunkBuffer buffer_;

 public:
  std::string& out;
  void f64(double x) {
    if (binary()) return bytes(std::bit_cast<std::uint64_t>(x), 8);
    separate();
    append_number(out, x, 17);
  }
  void i32(int x) { integer(static_cast<std::uint32_t>(x), 4, std::to_string(x)); }
  void u32(std::uint32_t x) { integer(x, 4, std::to_string(x)); }
  void u8(unsigned x) { integer(x, 1, std::to_string(x)); }
  void end_row() {
    if (!binary()) out += '\n';
    first_ = true;
    buffer_.spill();
  }
  void finish() { buffer_.flush(); }
  const char* name() const { return format_name(format_); }

 private:
  bool binary() const { return format_ != PlyFormat::ascii; }
  void integer(std::uint64_t bits, int n, const std::string& text) {
    if (binary()) return bytes(bits, n);
    separate();
    out += text;
  }
  // Byte by byte, in the format's order whatever the host.
  void bytes(std::uint64_t v, int n) {
    const bool big = format_ == PlyFormat::binary_big_endian;
    for (int i = 0; i < n; ++i) out += static_cast<char>((v >> (8 * (big ? n - 1 - i : i))) & 0xFF);
  }
  void separate() {
    if (!first_) out += ' ';
    first_ = false;
  }
  PlyFormat format_;
  bool first_ = true;
};

/// Header and vertex element shared by meshes and segment sets.
void ply_vertices(PlyWriter& w, const Points& P, const Points* normals, std::string_view comment) {
  w.out = std::string("ply\nformat ") + w.name() + " 1.0\ncomment " + std::string(comment) +
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

// ------------------------------------------------------------------------------------------------
// Reading

enum class Scalar { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<Scalar> type_named(std::string_view name) {
  static constexpr std::pair<std::string_view, Scalar> kTypes[] = {
      {"char", Scalar::i8},   {"int8", Scalar::i8},     {"uchar", Scalar::u8},   {"uint8", Scalar::u8},
      {"short", Scalar::i16}, {"int16", Scalar::i16},   {"ushort", Scalar::u16}, {"uint16", Scalar::u16},
      {"int", Scalar::i32},   {"int32", Scalar::i32},   {"uint", Scalar::u32},   {"uint32", Scalar::u32},
      {"float", Scalar::f32}, {"float32", Scalar::f32}, {"double", Scalar::f64}, {"float64", Scalar::f64}};
  for (const auto& [n, t] : kTypes)
    if (n == name) return t;
  return std::nullopt;
}

std::size_t type_size(Scalar t) noexcept {
  switch (t) {
    case Scalar::i8:
    case Scalar::u8:
      return 1;
    case Scalar::i16:
    case Scalar::u16:
      return 2;
    case Scalar::i32:
    case Scalar::u32:
    case Scalar::f32:
      return 4;
    case Scalar::f64:
      return 8;
  }
  return 0;
}

bool is_integer(Scalar t) noexcept {
  return t != Scalar::f32 && t != Scalar::f64;
}

struct Property {
  std::string name;
  Scalar type = Scalar::f64;
  std::optional<Scalar> count;  // lists: the type of their length
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

enum class Encoding { ascii, little, big };

struct Header {
  Encoding encoding = Encoding::ascii;
  std::vector<PlyElement> elements;
  std::size_t body = 0;  // offset of the first data byte
};

/// The header, line by line up to `end_header` (CR LF line ends accepted).
Header parse_header(std::string_view bytes, const std::string& where) {
  Header h;
  std::size_t pos = 0, line = 0;
  bool format = false;
  const auto fail = [&](const std::string& what) -> void {
    throw IoError(where + ": header line " + std::to_string(line) + ": " + what);
  };
  for (;;) {
    const std::size_t eol = bytes.find('\n', pos);
    ++line;
    if (eol == std::string_view::npos) {
      if (line == 1 && !bytes.starts_with("ply")) throw IoError(where + ": not a PLY file (no 'ply' line)");
      throw IoError(where + ": the header has no end_header line");
    }
    std::string_view text = bytes.substr(pos, eol - pos);
    if (text.ends_with('\r')) text.remove_suffix(1);
    pos = eol + 1;
    std::vector<std::string_view> words;
    for (std::size_t i = 0; i < text.size();) {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
      if (i > start) words.push_back(text.substr(start, i - start));
    }
    if (line == 1) {
      if (words.size() != 1 || words[0] != "ply") throw IoError(where + ": not a PLY file (no 'ply' line)");
      continue;
    }
    if (words.empty()) continue;
    const std::string_view key = words[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") {
      if (!format) fail("end_header before the format line");
      h.body = pos;
      return h;
    }
    if (key == "format") {
      if (words.size() != 3 || words[2] != "1.0")
        fail("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      if (words[1] == "ascii")
        h.encoding = Encoding::ascii;
      else if (words[1] == "binary_little_endian")
        h.encoding = Encoding::little;
      else if (words[1] == "binary_big_endian")
        h.encoding = Encoding::big;
      else
        fail("unknown format '" + std::string(words[1]) + "'");
      format = true;
    } else if (key == "element") {
      unsigned long long count = 0;
      const std::string_view n = words.size() == 3 ? words[2] : std::string_view{};
      const auto [ptr, ec] = std::from_chars(n.data(), n.data() + n.size(), count);
      if (words.size() != 3 || n.empty() || ptr != n.data() + n.size() || ec != std::errc() ||
          count > static_cast<unsigned long long>(INT_MAX))
        fail("expected 'element NAME COUNT' with a count from 0 to " + std::to_string(INT_MAX));
      h.elements.push_back({std::string(words[1]), static_cast<std::size_t>(count), {}});
    } else if (key == "property") {
      if (h.elements.empty()) fail("a property before any element");
      Property p;
      const bool list = words.size() == 5 && words[1] == "list";
      if (!list && words.size() != 3)
        fail("expected 'property TYPE NAME' or 'property list COUNT TYPE NAME'");
      const auto type = type_named(words[list ? 3 : 1]);
      if (!type) fail("unknown type '" + std::string(words[list ? 3 : 1]) + "'");
      p.type = *type;
      if (list) {
        p.count = type_named(words[2]);
        if (!p.count || !is_integer(*p.count)) fail("the length of a list must have an integer type");
      }
      p.name = std::string(words.back());
      h.elements.back().properties.push_back(std::move(p));
    } else {
      fail("unknown keyword '" + std::string(key) + "'");
    }
  }
}

/// The body as a stream of values of declared types; the current element and instance name the
/// place in messages.
class BodyReader {
 public:
  BodyReader(std::string_view bytes, const Header& h, std::string where)
      : data_(bytes.substr(h.body)), encoding_(h.encoding), where_(std::move(where)) {}

  void enter(const PlyElement& e, std::size_t index) {
    element_ = &e;
    index_ = index;
  }
  std::string place() const { return where_ + ": " + element_->name + " " + std::to_string(index_); }

  /// Refuses a count that the rest of the data cannot hold (before anything is allocated for it):
  /// every value takes at least one byte in binary, and two (a digit and a separator) in ASCII.
  void check_room(const PlyElement& e) const {
    std::size_t least = 0;
    for (const Property& p : e.properties)
      least += encoding_ == Encoding::ascii ? 1 : p.count ? type_size(*p.count) : type_size(p.type);
    const std::size_t left = data_.size() - pos_;
    if (least > 0 && e.count > left / least)
      throw IoError(where_ + ": the header announces " + std::to_string(e.count) + " " + e.name +
                    " elements, the data is too short for them (truncated file?)");
  }

  /// The next value as an integer (integer types) or as a double (float types).
  double real(Scalar t) { return encoding_ == Encoding::ascii ? ascii_real(t) : binary(t); }
  long long integer(Scalar t) {
    if (encoding_ == Encoding::ascii) return ascii_integer(t);
    return static_cast<long long>(binary(t));
  }

  /// Bytes or tokens left after the last element.
  void finish() {
    if (encoding_ == Encoding::ascii) {
      skip_space();
      if (pos_ < data_.size())
        throw IoError(where_ + ": data after the last element (the counts do not match)");
    } else if (pos_ < data_.size()) {
      throw IoError(where_ + ": " + std::to_string(data_.size() - pos_) +
                    " bytes after the last element (the counts do not match)");
    }
  }

 private:
  [[noreturn]] void truncated() const {
    throw IoError(where_ + ": the data ends in " + element_->name + " " + std::to_string(index_) + " of " +
                  std::to_string(element_->count) + " (truncated file)");
  }

  double binary(Scalar t) {
    const std::size_t n = type_size(t);
    if (data_.size() - pos_ < n) truncated();
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const auto byte = static_cast<std::uint64_t>(static_cast<unsigned char>(data_[pos_ + i]));
      v |= byte << (8 * (encoding_ == Encoding::big ? n - 1 - i : i));
    }
    pos_ += n;
    switch (t) {
      case Scalar::i8:
        return static_cast<std::int8_t>(v);
      case Scalar::u8:
        return static_cast<std::uint8_t>(v);
      case Scalar::i16:
        return static_cast<std::int16_t>(v);
      case Scalar::u16:
        return static_cast<std::uint16_t>(v);
      case Scalar::i32:
        return static_cast<std::int32_t>(v);
      case Scalar::u32:
        return static_cast<std::uint32_t>(v);
      case Scalar::f32:
        return std::bit_cast<float>(static_cast<std::uint32_t>(v));
      case Scalar::f64:
        return std::bit_cast<double>(v);
    }
    return 0;
  }

  void skip_space() {
    while (pos_ < data_.size() &&
           (data_[pos_] == ' ' || data_[pos_] == '\t' || data_[pos_] == '\r' || data_[pos_] == '\n'))
      ++pos_;
  }

  std::string_view token() {
    skip_space();
    if (pos_ == data_.size()) truncated();
    const std::size_t start = pos_;
    while (pos_ < data_.size() && data_[pos_] != ' ' && data_[pos_] != '\t' && data_[pos_] != '\r' &&
           data_[pos_] != '\n')
      ++pos_;
    return data_.substr(start, pos_ - start);
  }

  double ascii_real(Scalar t) {
    if (is_integer(t)) return static_cast<double>(ascii_integer(t));
    const std::string_view s = token();
    double x = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
    if (ptr != s.data() + s.size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
      throw IoError(place() + ": expected a number, got '" + std::string(s.substr(0, 40)) + "'");
    if (ec == std::errc::result_out_of_range)
      x = std::numeric_limits<double>::infinity();  // reported as not finite by the caller
    return x;
  }

  long long ascii_integer(Scalar t) {
    const std::string_view s = token();
    long long x = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
    if (ptr != s.data() + s.size() || ec != std::errc())
      throw IoError(place() + ": expected an integer, got '" + std::string(s.substr(0, 40)) + "'");
    const std::size_t bits = 8 * type_size(t);
    const bool is_signed = t == Scalar::i8 || t == Scalar::i16 || t == Scalar::i32;
    const long long lo = is_signed ? -(1LL << (bits - 1)) : 0;
    const long long hi = is_signed ? (1LL << (bits - 1)) - 1 : (1LL << bits) - 1;
    if (x < lo || x > hi)
      throw InvalidInput(place() + ": " + std::string(s) + " is outside the range of its type");
    return x;
  }

  std::string_view data_;
  Encoding encoding_;
  std::string where_;
  std::size_t pos_ = 0;
  const PlyElement* element_ = nullptr;
  std::size_t index_ = 0;
};

/// Index of the property called `name` (scalar unless `list`), or −1.
int find_property(const PlyElement& e, std::initializer_list<std::string_view> names, bool list) {
  for (std::size_t k = 0; k < e.properties.size(); ++k)
    for (const std::string_view name : names)
      if (e.properties[k].name == name && e.properties[k].count.has_value() == list)
        return static_cast<int>(k);
  return -1;
}

/// Reads (or skips) one property value of the current instance.
void skip_property(BodyReader& r, const Property& p) {
  if (!p.count) {
    r.real(p.type);
    return;
  }
  const long long n = r.integer(*p.count);
  if (n < 0)
    throw InvalidInput(r.place() + ": list " + p.name + " has a negative length " + std::to_string(n));
  for (long long k = 0; k < n; ++k) r.real(p.type);
}

void read_vertices(BodyReader& r, const PlyElement& e, Mesh& mesh, const std::string& where) {
  const int x = find_property(e, {"x"}, false), y = find_property(e, {"y"}, false),
            z = find_property(e, {"z"}, false);
  if (x < 0 || y < 0 || z < 0) throw IoError(where + ": element vertex has no x, y and z");
  const int nx = find_property(e, {"nx"}, false), ny = find_property(e, {"ny"}, false),
            nz = find_property(e, {"nz"}, false);
  const bool normals = nx >= 0 && ny >= 0 && nz >= 0;
  const auto rows = static_cast<Eigen::Index>(e.count);
  mesh.vertices.resize(rows, 3);
  if (normals) mesh.normals.resize(rows, 3);
  const std::array<int, 6> columns{x, y, z, nx, ny, nz};
  static constexpr const char* kNames[] = {"x", "y", "z", "nx", "ny", "nz"};
  for (std::size_t i = 0; i < e.count; ++i) {
    r.enter(e, i);
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const Property& p = e.properties[k];
      const auto slot = std::find(columns.begin(), columns.begin() + (normals ? 6 : 3), static_cast<int>(k));
      if (p.count || slot == columns.begin() + (normals ? 6 : 3)) {
        skip_property(r, p);
        continue;
      }
      const double value = r.real(p.type);
      const auto c = static_cast<std::size_t>(slot - columns.begin());
      if (!std::isfinite(value)) throw InvalidInput(r.place() + ": " + kNames[c] + " is not finite");
      (c < 3 ? mesh.vertices : mesh.normals)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c % 3)) =
          value;
    }
  }
}

void read_faces(BodyReader& r, const PlyElement& e, Mesh& mesh, const std::string& where) {
  const int list = find_property(e, {"vertex_indices", "vertex_index"}, true);
  if (list < 0) throw IoError(where + ": element face has no list vertex_indices (or vertex_index)");
  const int state = find_property(e, {"state"}, false);
  const bool states = state >= 0 && is_integer(e.properties[static_cast<std::size_t>(state)].type);
  mesh.face_offsets.assign(1, 0);
  mesh.face_vertices.clear();
  mesh.states.clear();
  for (std::size_t f = 0; f < e.count; ++f) {
    r.enter(e, f);
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const Property& p = e.properties[k];
      if (static_cast<int>(k) == list) {
        const long long n = r.integer(*p.count);
        if (n < 0) throw InvalidInput(r.place() + ": a face of " + std::to_string(n) + " corners");
        for (long long c = 0; c < n; ++c) {
          const double index = r.real(p.type);  // integer types come back exactly
          if (!(index >= INT_MIN && index <= INT_MAX) || index != std::floor(index))
            throw InvalidInput(r.place() + ": vertex index " + std::to_string(index) +
                               " is not a valid index");
          mesh.face_vertices.push_back(static_cast<int>(index));
        }
        if (mesh.face_vertices.size() > static_cast<std::size_t>(INT_MAX))
          throw InvalidInput(where + ": more corners than 32-bit offsets hold");
        mesh.face_offsets.push_back(static_cast<int>(mesh.face_vertices.size()));
      } else if (static_cast<int>(k) == state && states) {
        const long long s = r.integer(p.type);
        if (s < 0 || s > static_cast<long long>(UINT32_MAX))
          throw InvalidInput(r.place() + ": state " + std::to_string(s) + " is outside 0 … 4294967295");
        mesh.states.push_back(static_cast<std::uint32_t>(s));
      } else {
        skip_property(r, p);
      }
    }
  }
}

}  // namespace

void mesh_ply(const Mesh& mesh, PlyFormat format, ByteSink& sink) {
  check_mesh(mesh, "the mesh to write as PLY");
  // Splitting the vertices would cut the surface apart along its creases; PLY readers would see sheets.
  if (!mesh.normal_indices.empty())
    throw InvalidInput(
        "the mesh to write as PLY has normals per face corner (" + std::to_string(mesh.normals.rows()) +
        " normals for " + std::to_string(mesh.vertices.rows()) +
        " vertices: several at crease and corner vertices); PLY holds one per vertex: write OBJ, "
        "or drop the normals");
  const Points* normals = mesh.normals.size() != 0 ? &mesh.normals : nullptr;
  // Holes are left out: PLY has no tags, and its readers would draw them.
  const std::vector<char> hole = hole_flags(mesh);
  const auto faces = static_cast<std::size_t>(std::count(hole.begin(), hole.end(), 0));
  int largest = 0;
  for (std::size_t f = 0; f < face_count(mesh); ++f)
    largest = std::max(largest, mesh.face_offsets[f + 1] - mesh.face_offsets[f]);
  const bool wide = largest > 255;  // the usual uchar count holds up to 255 corners
  PlyWriter w(format, sink);
  ply_vertices(w, mesh.vertices, normals, "cifs mesh");
  w.out += "element face " + std::to_string(faces) + "\nproperty list " + (wide ? "uint" : "uchar") +
           " int vertex_indices\n";
  if (!mesh.states.empty()) w.out += "property uint state\n";
  w.out += "end_header\n";
  ply_vertex_rows(w, mesh.vertices, normals);
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    if (hole[f] != 0) continue;
    const auto corners = face(mesh, f);
    if (wide)
      w.u32(static_cast<std::uint32_t>(corners.size()));
    else
      w.u8(static_cast<unsigned>(corners.size()));
    for (const int i : corners) w.i32(i);
    if (!mesh.states.empty()) w.u32(mesh.states[f]);
    w.end_row();
  }
  w.finish();
}

std::string mesh_ply(const Mesh& mesh, PlyFormat format) {
  StringSink out;
  mesh_ply(mesh, format, out);
  return std::move(out.bytes);
}

void segments_ply(const Segments& segments, PlyFormat format, ByteSink& sink) {
  check_segments(segments, "the segments to write as PLY");
  PlyWriter w(format, sink);
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
  w.finish();
}

std::string segments_ply(const Segments& segments, PlyFormat format) {
  StringSink out;
  segments_ply(segments, format, out);
  return std::move(out.bytes);
}

// The point-set format: a binary little-endian point cloud, `element vertex` of double x y z (the
// coordinates a point lacks are 0), as the vertices of meshes and segment sets.
namespace {

std::string point_cloud_header(std::uint64_t count) {
  return "ply\nformat binary_little_endian 1.0\ncomment cifs points\nelement vertex " +
         std::to_string(count) + "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
}

void ply_header(std::string& out, std::uint64_t count, Eigen::Index, const PointsStyle&) {
  out += point_cloud_header(count);
}

void ply_rows(std::string& out, const Eigen::Ref<const Points>& rows, std::uint64_t) {
  for (Eigen::Index i = 0; i < rows.rows(); ++i)
    for (Eigen::Index k = 0; k < 3; ++k) {
      const auto bits = std::bit_cast<std::uint64_t>(k < rows.cols() ? rows(i, k) : 0.0);
      for (int b = 0; b < 8; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xFF);
    }
}

void ply_footer(ChunkBuffer&, std::uint64_t, const PointsStyle&) {}

std::uint64_t points_size(std::uint64_t count, Eigen::Index) {
  return point_cloud_header(count).size() + count * 24;
}

}  // namespace

const detail::PointsFormat detail::kPlyPoints{"ply", 3, ply_header, ply_rows, ply_footer, points_size};

Mesh parse_mesh_ply(std::string_view bytes, std::string_view where) {
  const std::string w(where);
  const Header h = parse_header(bytes, w);
  BodyReader r(bytes, h, w);
  Mesh mesh;
  bool vertices = false, faces = false;
  for (const PlyElement& e : h.elements) {
    r.check_room(e);
    if (e.name == "vertex" && !vertices) {
      read_vertices(r, e, mesh, w);
      vertices = true;
    } else if (e.name == "face" && !faces) {
      read_faces(r, e, mesh, w);
      faces = true;
    } else if (!e.properties.empty()) {  // no properties: no data (2^31 empty rows looped for minutes)
      for (std::size_t i = 0; i < e.count; ++i) {
        r.enter(e, i);
        for (const Property& p : e.properties) skip_property(r, p);
      }
    }
  }
  r.finish();
  if (!vertices) throw IoError(w + ": no vertex element");
  if (!faces || face_count(mesh) == 0) throw InvalidInput(w + ": no faces (a mesh file needs element face)");
  check_mesh(mesh, where);
  return mesh;
}

}  // namespace cifs::io
