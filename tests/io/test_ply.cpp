// SPDX-License-Identifier: MIT
#include "cifs/io/ply.hpp"

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "cifs/errors.hpp"
#include "io/mesh_samples.hpp"

using namespace cifs;
using namespace cifs::io;
using Catch::Matchers::Contains;

namespace {

/// A minimal PLY reader written for the test, independent of io::parse_mesh_ply: the header's
/// elements and properties, then every value of every element as double (ASCII or binary in either
/// byte order; lists flattened with their count first).
struct PlyProperty {
  std::string type, name, count_type;  // count_type non-empty for lists
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  std::vector<std::vector<double>> rows;
};

std::size_t type_size(const std::string& t) {
  if (t == "uchar" || t == "char") return 1;
  if (t == "short" || t == "ushort") return 2;
  if (t == "int" || t == "uint" || t == "float") return 4;
  if (t == "double") return 8;
  FAIL("unknown PLY type " << t);
  return 0;
}

double decode(const std::string& t, const unsigned char* p, bool big) {
  std::uint64_t v = 0;
  const std::size_t n = type_size(t);
  for (std::size_t i = 0; i < n; ++i) v |= std::uint64_t{p[i]} << (8 * (big ? n - 1 - i : i));
  if (t == "double") {
    double d;
    std::memcpy(&d, &v, 8);
    return d;
  }
  if (t == "int") return static_cast<double>(static_cast<std::int32_t>(static_cast<std::uint32_t>(v)));
  return static_cast<double>(v);
}

std::vector<PlyElement> read_ply(const std::string& text, std::string* format) {
  const std::size_t end = text.find("end_header\n");
  REQUIRE(end != std::string::npos);
  std::istringstream header(text.substr(0, end));
  std::vector<PlyElement> elements;
  std::string line;
  std::getline(header, line);
  REQUIRE(line == "ply");
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      words >> *format;
    } else if (key == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      elements.push_back(e);
    } else if (key == "property") {
      PlyProperty p;
      words >> p.type;
      if (p.type == "list") {
        p.count_type.clear();
        words >> p.count_type >> p.type;
      }
      words >> p.name;
      elements.back().properties.push_back(p);
    }
  }
  const std::string body = text.substr(end + 11);
  if (*format == "ascii") {
    std::istringstream in(body);
    for (auto& e : elements)
      for (std::size_t r = 0; r < e.count; ++r) {
        std::getline(in, line);
        std::istringstream values(line);
        std::vector<double> row;
        double v;
        while (values >> v) row.push_back(v);
        e.rows.push_back(row);
      }
    return elements;
  }
  REQUIRE((*format == "binary_little_endian" || *format == "binary_big_endian"));
  const bool big = *format == "binary_big_endian";
  const auto* p = reinterpret_cast<const unsigned char*>(body.data());
  const auto* stop = p + body.size();
  for (auto& e : elements)
    for (std::size_t r = 0; r < e.count; ++r) {
      std::vector<double> row;
      for (const auto& prop : e.properties) {
        std::size_t n = 1;
        if (!prop.count_type.empty()) {
          n = static_cast<std::size_t>(decode(prop.count_type, p, big));
          row.push_back(static_cast<double>(n));
          p += type_size(prop.count_type);
        }
        for (std::size_t k = 0; k < n; ++k) {
          REQUIRE(p + type_size(prop.type) <= stop);
          row.push_back(decode(prop.type, p, big));
          p += type_size(prop.type);
        }
      }
      e.rows.push_back(row);
    }
  CHECK(p == stop);  // nothing left over
  return elements;
}

/// Triangles, a quad, a pentagon and a hexagon sharing vertices, with per-face states.
Mesh ply_mixed_polygons() {
  Mesh m;
  m.vertices.resize(9, 3);
  for (int k = 0; k < 9; ++k) m.vertices.row(k) << std::cos(k * 0.7), std::sin(k * 0.7), 0.01 * k * k;
  add_face(m, {0, 1, 2});
  add_face(m, {0, 2, 3, 4});
  add_face(m, {4, 5, 6, 7, 8});
  add_face(m, {8, 7, 6, 5, 3, 1});
  add_face(m, {1, 8, 0});
  m.states = {0, 1, 2, 3, 4294967295u};
  return m;
}

void require_same_ply_mesh(const Mesh& a, const Mesh& b) {
  REQUIRE(a.vertices.rows() == b.vertices.rows());
  REQUIRE(a.vertices.cols() == b.vertices.cols());
  CHECK(std::memcmp(a.vertices.data(), b.vertices.data(), sizeof(double) * a.vertices.size()) == 0);
  CHECK(a.face_offsets == b.face_offsets);
  CHECK(a.face_vertices == b.face_vertices);
  REQUIRE(a.normals.rows() == b.normals.rows());
  // memcmp takes no null pointer, even for 0 bytes (UBSan): empty normals compare equal as they are.
  CHECK((a.normals.size() == 0 ||
         std::memcmp(a.normals.data(), b.normals.data(), sizeof(double) * a.normals.size()) == 0));
  CHECK(a.states == b.states);
}

std::string ply_error_of(const std::string& bytes) {
  try {
    parse_mesh_ply(bytes, "m.ply");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

/// Big-endian bytes of a value, for hand-made binary files.
template <class T>
std::string be(T x) {
  std::uint64_t bits = 0;
  if constexpr (std::is_same_v<T, float>)
    bits = std::bit_cast<std::uint32_t>(x);
  else if constexpr (std::is_same_v<T, double>)
    bits = std::bit_cast<std::uint64_t>(x);
  else
    bits = static_cast<std::uint64_t>(x);
  std::string out;
  for (std::size_t i = 0; i < sizeof(T); ++i)
    out += static_cast<char>((bits >> (8 * (sizeof(T) - 1 - i))) & 0xFF);
  return out;
}

}  // namespace

TEST_CASE("Mesh PLY (ASCII and binary) parses back with every count and value", "[io][ply]") {
  for (const PlyFormat format :
       {PlyFormat::ascii, PlyFormat::binary_little_endian, PlyFormat::binary_big_endian})
    for (const bool normals : {false, true}) {
      const Mesh m = io_test::sample_mesh(normals, true);
      std::string name;
      const auto elements = read_ply(mesh_ply(m, format), &name);
      INFO(name << (normals ? " with normals" : ""));
      CHECK(name == (format == PlyFormat::ascii                  ? "ascii"
                     : format == PlyFormat::binary_little_endian ? "binary_little_endian"
                                                                 : "binary_big_endian"));
      REQUIRE(elements.size() == 2);
      const PlyElement& v = elements[0];
      const PlyElement& f = elements[1];
      CHECK(v.name == "vertex");
      CHECK(f.name == "face");
      REQUIRE(v.count == 5);
      REQUIRE(f.count == 3);
      CHECK(v.properties.size() == (normals ? 6u : 3u));
      for (std::size_t i = 0; i < 5; ++i) {
        REQUIRE(v.rows[i].size() == v.properties.size());
        for (Eigen::Index k = 0; k < 3; ++k) {
          CHECK(v.rows[i][static_cast<std::size_t>(k)] == m.vertices(static_cast<Eigen::Index>(i), k));
          if (normals)
            CHECK(v.rows[i][3 + static_cast<std::size_t>(k)] == m.normals(static_cast<Eigen::Index>(i), k));
        }
      }
      CHECK(f.rows[0] == std::vector<double>{3, 0, 1, 2, 7});
      CHECK(f.rows[1] == std::vector<double>{3, 2, 3, 4, 4000000000.0});
      CHECK(f.rows[2] == std::vector<double>{4, 0, 1, 3, 4, 0});
    }
}

TEST_CASE("Segment PLY parses back", "[io][ply]") {
  Segments s;
  s.vertices.resize(4, 2);
  s.vertices << 0, 0, 1, 0.1, 2, -0.3, 0.5, 7;
  s.segments = {{0, 1}, {1, 2}, {1, 3}};  // a branch at vertex 1 (tree-like support)
  s.states = {1, 2, 3};
  for (const PlyFormat format :
       {PlyFormat::ascii, PlyFormat::binary_little_endian, PlyFormat::binary_big_endian}) {
    std::string name;
    const auto elements = read_ply(segments_ply(s, format), &name);
    REQUIRE(elements.size() == 2);
    CHECK(elements[1].name == "edge");
    REQUIRE(elements[0].count == 4);
    CHECK(elements[0].rows[3] == std::vector<double>{0.5, 7, 0});  // planar: z = 0
    CHECK(elements[1].rows == std::vector<std::vector<double>>{{0, 1, 1}, {1, 2, 2}, {1, 3, 3}});
  }
}

TEST_CASE("PLY writers: a face of more than 255 corners gets a uint count", "[io][ply]") {
  Mesh m;
  m.vertices.resize(300, 3);
  std::vector<int> ring(300);
  for (int k = 0; k < 300; ++k) {
    m.vertices.row(k) << std::cos(k * 2 * M_PI / 300), std::sin(k * 2 * M_PI / 300), 0;
    ring[static_cast<std::size_t>(k)] = k;
  }
  add_face(m, ring);
  std::string name;
  const std::string text = mesh_ply(m, PlyFormat::binary_little_endian);
  CHECK_THAT(text, Contains("property list uint int vertex_indices"));
  const auto elements = read_ply(text, &name);
  REQUIRE(elements[1].rows.size() == 1);
  CHECK(elements[1].rows[0].size() == 301);
  CHECK(elements[1].rows[0][0] == 300);
  CHECK(elements[1].rows[0][300] == 299);
  require_same_ply_mesh(parse_mesh_ply(text, "ring"), m);
  CHECK_THAT(mesh_ply(io_test::sample_mesh(false, false)),
             Contains("property list uchar int vertex_indices"));
}

TEST_CASE("PLY meshes read back bit for bit in every encoding", "[io][ply]") {
  const std::vector<std::pair<const char*, Mesh>> meshes = {
      {"sample", io_test::sample_mesh(false, false)},
      {"sample, normals and states", io_test::sample_mesh(true, true)},
      {"cube", io_test::cube()},
      {"open grid", io_test::open_grid(6)},
      {"mixed polygons", ply_mixed_polygons()}};
  for (const auto& [what, m] : meshes)
    for (const PlyFormat format :
         {PlyFormat::ascii, PlyFormat::binary_little_endian, PlyFormat::binary_big_endian}) {
      INFO(what << ", format " << static_cast<int>(format));
      const Mesh back = parse_mesh_ply(mesh_ply(m, format), "m.ply");
      require_same_ply_mesh(back, m);
      CHECK(mesh_ply(back, format) == mesh_ply(m, format));
    }
}

TEST_CASE("PLY reader: other writers' files (types, extra properties and elements, comments)", "[io][ply]") {
  // Written by hand: float coordinates with colours, an edge element before the faces, a uint
  // count with short indices named vertex_index, a face property before the list.
  const std::string ascii =
      "ply\r\n"
      "format ascii 1.0\n"
      "comment made by hand\n"
      "obj_info not cifs\n"
      "element vertex 4\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element edge 1\n"
      "property int vertex1\nproperty int vertex2\n"
      "element face 2\n"
      "property uchar flags\n"
      "property list uint short vertex_index\n"
      "property list uchar float texcoord\n"
      "end_header\n"
      "0 0 0 255 0 0\n1.5 0 0 0 255 0\n1.5 2.25 0 0 0 255\n0 2.25 -1 9 9 9\n"
      "0 2\n"
      "7 3 0 1 2 2 0.5 0.5\n"
      "0 3 0 2 3 0\n";
  const Mesh m = parse_mesh_ply(ascii, "hand.ply");
  Points expected(4, 3);
  expected << 0, 0, 0, 1.5, 0, 0, 1.5, 2.25, 0, 0, 2.25, -1;
  CHECK(m.vertices == expected);
  CHECK(m.face_offsets == std::vector<int>{0, 3, 6});
  CHECK(m.face_vertices == std::vector<int>{0, 1, 2, 0, 2, 3});
  CHECK(m.normals.size() == 0);
  CHECK(m.states.empty());

  // The same mesh as big-endian binary, bytes assembled here: float32 coordinates (exact for these
  // values), normals as doubles, uchar counts, int indices, a ushort state.
  std::string be_file =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property double nx\nproperty double ny\nproperty double nz\n"
      "element face 2\nproperty list uchar int vertex_indices\nproperty ushort state\nend_header\n";
  for (Eigen::Index i = 0; i < 4; ++i) {
    for (Eigen::Index k = 0; k < 3; ++k) be_file += be(static_cast<float>(expected(i, k)));
    be_file += be(0.0) + be(0.0) + be(1.0 / 3);
  }
  be_file += be(std::uint8_t{3}) + be(std::int32_t{0}) + be(std::int32_t{1}) + be(std::int32_t{2}) +
             be(std::uint16_t{513});
  be_file += be(std::uint8_t{3}) + be(std::int32_t{0}) + be(std::int32_t{2}) + be(std::int32_t{3}) +
             be(std::uint16_t{65535});
  const Mesh b = parse_mesh_ply(be_file, "be.ply");
  CHECK(b.vertices == expected);
  CHECK(b.face_vertices == m.face_vertices);
  REQUIRE(b.normals.rows() == 4);
  CHECK(b.normals.col(2).isConstant(1.0 / 3, 0));
  CHECK(b.states == std::vector<std::uint32_t>{513, 65535});
}

TEST_CASE("PLY reader: bad input is a one-line error naming the file and the element", "[io][ply]") {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  CHECK(ply_error_of(header + vertices + "3 0 1 2\n") == "(no error)");
  CHECK(ply_error_of(header + vertices + "3 0 1 3\n") ==
        "m.ply: face 0 corner 2 = 3 is out of range (3 vertices)");
  CHECK(ply_error_of(header + vertices + "2 0 1\n") ==
        "m.ply: face 0 has 2 vertices, a face needs at least 3");
  CHECK(ply_error_of(header + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n") == "m.ply: vertex 1: y is not finite");
  CHECK(ply_error_of(header + vertices + "3 0 1\n") ==
        "m.ply: the data ends in face 0 of 1 (truncated file)");
  CHECK(ply_error_of(header + vertices + "3 0 1 2 7\n") ==
        "m.ply: data after the last element (the counts do not match)");
  CHECK(ply_error_of(header + vertices + "3 0 x 2\n") == "m.ply: face 0: expected an integer, got 'x'");
  CHECK(ply_error_of(header + vertices + "300 0 1 2\n") ==
        "m.ply: face 0: 300 is outside the range of its type");
  CHECK(ply_error_of("solid cube\n") == "m.ply: not a PLY file (no 'ply' line)");
  CHECK(ply_error_of("ply\nformat binary_middle_endian 1.0\nend_header\n") ==
        "m.ply: header line 2: unknown format 'binary_middle_endian'");
  CHECK(ply_error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n") ==
        "m.ply: header line 4: unknown type 'quad'");
  CHECK(ply_error_of("ply\nformat ascii 1.0\nelement vertex 1\n") ==
        "m.ply: the header has no end_header line");
  CHECK(ply_error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nend_header\n1\n") ==
        "m.ply: element vertex has no x, y and z");
  CHECK(ply_error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                     "property double z\nend_header\n0 0 0\n") ==
        "m.ply: no faces (a mesh file needs element face)");

  // Binary: a NaN coordinate, a file cut short, a count larger than the data.
  const Mesh good = io_test::sample_mesh(false, false);
  for (const PlyFormat format : {PlyFormat::binary_little_endian, PlyFormat::binary_big_endian}) {
    Mesh nan = good;
    nan.vertices(3, 2) = std::numeric_limits<double>::quiet_NaN();
    std::string bytes = mesh_ply(good, format);
    // Patch the NaN into the bytes (the writer refuses it): vertex 3, z is the 12th double.
    const std::size_t body = bytes.find("end_header\n") + 11;
    std::string patched = bytes;
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::quiet_NaN());
    for (std::size_t i = 0; i < 8; ++i)
      patched[body + std::size_t{8} * 11 + i] =
          static_cast<char>((bits >> (8 * (format == PlyFormat::binary_big_endian ? 7 - i : i))) & 0xFF);
    CHECK(ply_error_of(patched) == "m.ply: vertex 3: z is not finite");
    CHECK(ply_error_of(bytes.substr(0, bytes.size() - 3)) ==
          "m.ply: the data ends in face 2 of 3 (truncated file)");
    CHECK(ply_error_of(bytes + "x") == "m.ply: 1 bytes after the last element (the counts do not match)");
    std::string huge = bytes;
    huge.replace(huge.find("element face 3"), 14, "element face 99999999");
    CHECK(ply_error_of(huge) ==
          "m.ply: the header announces 99999999 face elements, the data is too short for them (truncated "
          "file?)");
  }
}

TEST_CASE("PLY writers refuse bad meshes and segments", "[io][ply]") {
  Mesh m = io_test::sample_mesh(false, false);
  m.face_vertices[8] = 5;  // quad 0 (face 2), corner 2
  CHECK_THROWS_WITH(mesh_ply(m), Contains("face 2 corner 2 = 5 is out of range (5 vertices)"));
  m = io_test::sample_mesh(false, true);
  m.states.pop_back();
  CHECK_THROWS_WITH(mesh_ply(m), Contains("2 states for 3 faces"));
  m = io_test::sample_mesh(false, false);
  m.normals = Points::Zero(4, 3);
  CHECK_THROWS_WITH(mesh_ply(m), Contains("normals are 4 by 3"));
  Segments s;
  s.vertices = Points::Zero(2, 2);
  s.segments = {{0, 2}};
  CHECK_THROWS_WITH(segments_ply(s), Contains("segments[0][1] = 2 is out of range"));
}

TEST_CASE("PLY: an element without properties holds no data, whatever its count", "[io][ply][reliability]") {
  // 2^31 − 1 rows of nothing were skipped one by one: minutes (tests/fuzz/fuzz_mesh_ply).
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element nothing 2147483647\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const Mesh m = cifs::io::parse_mesh_ply(ply, "empty_rows.ply");
  CHECK(m.vertices.rows() == 3);
  CHECK(cifs::face_count(m) == 1);
}

TEST_CASE("PLY leaves hole faces out (it holds no tags)", "[io][ply][tags]") {
  Mesh m = io_test::sample_mesh(false, true);
  m.tags.holes = {1};
  for (const PlyFormat format : {PlyFormat::ascii, PlyFormat::binary_little_endian}) {
    const Mesh back = parse_mesh_ply(mesh_ply(m, format), "m.ply");
    CHECK(back.face_offsets == std::vector<int>{0, 3, 7});
    CHECK(back.face_vertices == std::vector<int>{0, 1, 2, 0, 1, 3, 4});
    CHECK(back.states == std::vector<std::uint32_t>{7, 0});
    CHECK(back.vertices == m.vertices);
    CHECK(back.tags.holes.empty());
  }
}
