// SPDX-License-Identifier: MIT
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/io/geometry.hpp"
#include "cifs/io/polyline.hpp"

using namespace cifs;
using namespace cifs::io;

namespace {

/// A minimal PLY reader written for the test: the header's elements and properties, then every
/// value of every element as double (ASCII or little-endian binary; lists flattened with their
/// count first).
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

double decode(const std::string& t, const unsigned char* p) {
  std::uint64_t v = 0;
  const std::size_t n = type_size(t);
  for (std::size_t i = 0; i < n; ++i) v |= std::uint64_t{p[i]} << (8 * i);  // little-endian
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
  REQUIRE(*format == "binary_little_endian");
  const auto* p = reinterpret_cast<const unsigned char*>(body.data());
  const auto* stop = p + body.size();
  for (auto& e : elements)
    for (std::size_t r = 0; r < e.count; ++r) {
      std::vector<double> row;
      for (const auto& prop : e.properties) {
        std::size_t n = 1;
        if (!prop.count_type.empty()) {
          n = static_cast<std::size_t>(decode(prop.count_type, p));
          row.push_back(static_cast<double>(n));
          p += type_size(prop.count_type);
        }
        for (std::size_t k = 0; k < n; ++k) {
          REQUIRE(p + type_size(prop.type) <= stop);
          row.push_back(decode(prop.type, p));
          p += type_size(prop.type);
        }
      }
      e.rows.push_back(row);
    }
  CHECK(p == stop);  // nothing left over
  return elements;
}

/// Two triangles and a skew quad with values that need 17 digits.
Mesh sample_mesh(bool normals, bool states) {
  Mesh m;
  m.vertices.resize(5, 3);
  m.vertices << 0.1, 0.2, 0.3, 1.0 / 3, -2.5e-7, 1e10, 1, 1, 0, 0, 1, 0.7, -0.5, 0.25, std::sqrt(2.0);
  m.triangles = {{0, 1, 2}, {2, 3, 4}};
  m.quads = {{0, 1, 3, 4}};
  if (normals) m.normals = vertex_normals(m);
  if (states) m.states = {7, 4000000000u, 0};
  return m;
}

}  // namespace

TEST_CASE("Mesh PLY (ASCII and binary) parses back with every count and value", "[io][geometry]") {
  for (const PlyFormat format : {PlyFormat::ascii, PlyFormat::binary_little_endian})
    for (const bool normals : {false, true}) {
      const Mesh m = sample_mesh(normals, true);
      std::string name;
      const auto elements = read_ply(mesh_ply(m, format), &name);
      INFO(name << (normals ? " with normals" : ""));
      CHECK(name == (format == PlyFormat::ascii ? "ascii" : "binary_little_endian"));
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

TEST_CASE("Segment PLY and OBJ parse back", "[io][geometry]") {
  Segments s;
  s.vertices.resize(4, 2);
  s.vertices << 0, 0, 1, 0.1, 2, -0.3, 0.5, 7;
  s.segments = {{0, 1}, {1, 2}, {1, 3}};  // a branch at vertex 1 (tree-like support)
  s.states = {1, 2, 3};
  for (const PlyFormat format : {PlyFormat::ascii, PlyFormat::binary_little_endian}) {
    std::string name;
    const auto elements = read_ply(segments_ply(s, format), &name);
    REQUIRE(elements.size() == 2);
    CHECK(elements[1].name == "edge");
    REQUIRE(elements[0].count == 4);
    CHECK(elements[0].rows[3] == std::vector<double>{0.5, 7, 0});  // planar: z = 0
    CHECK(elements[1].rows == std::vector<std::vector<double>>{{0, 1, 1}, {1, 2, 2}, {1, 3, 3}});
  }
  // OBJ: v and l lines, 1-based.
  std::istringstream obj(segments_obj(s));
  std::string line;
  std::vector<std::vector<double>> v;
  std::vector<std::pair<int, int>> l;
  while (std::getline(obj, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v") {
      double x, y, z;
      words >> x >> y >> z;
      v.push_back({x, y, z});
    } else if (key == "l") {
      int a, b;
      words >> a >> b;
      l.emplace_back(a, b);
    }
  }
  CHECK(v == std::vector<std::vector<double>>{{0, 0, 0}, {1, 0.1, 0}, {2, -0.3, 0}, {0.5, 7, 0}});
  CHECK(l == std::vector<std::pair<int, int>>{{1, 2}, {2, 3}, {2, 4}});
}

TEST_CASE("Mesh OBJ parses back, with normals as f v//n", "[io][geometry]") {
  const Mesh m = sample_mesh(true, false);
  std::istringstream obj(mesh_obj(m));
  std::string line;
  int v = 0, vn = 0;
  std::vector<std::string> faces;
  while (std::getline(obj, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v" || key == "vn") {
      double x[3];
      words >> x[0] >> x[1] >> x[2];
      const Points& P = key == "v" ? m.vertices : m.normals;
      const int i = key == "v" ? v++ : vn++;
      for (int k = 0; k < 3; ++k) CHECK(x[k] == P(i, k));  // 17 digits: exact round trip
    } else if (key == "f") {
      faces.push_back(line);
    }
  }
  CHECK(v == 5);
  CHECK(vn == 5);
  CHECK(faces == std::vector<std::string>{"f 1//1 2//2 3//3", "f 3//3 4//4 5//5", "f 1//1 2//2 4//4 5//5"});
}

TEST_CASE("Vertex normals: area-weighted, oriented by the faces", "[io][geometry]") {
  // A unit cube with outward (counter-clockwise from outside) quads: corner normals (±1,±1,±1)/√3.
  Mesh cube;
  cube.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) cube.vertices.row(i) << (i & 1), ((i >> 1) & 1), ((i >> 2) & 1);
  cube.quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  const Points N = vertex_normals(cube);
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k)
      CHECK(N(i, k) == Approx((cube.vertices(i, k) - 0.5) * 2 / std::sqrt(3.0)).epsilon(1e-14));
  // A triangle fan in the plane z = 2 (counter-clockwise seen from +z): every normal is +z.
  Mesh fan;
  fan.vertices.resize(4, 3);
  fan.vertices << 0, 0, 2, 3, 0, 2, 3, 1, 2, -1, 5, 2;
  fan.triangles = {{0, 1, 2}, {0, 2, 3}};
  const Points F = vertex_normals(fan);
  for (int i = 0; i < 4; ++i) CHECK(F.row(i) == Eigen::RowVector3d(0, 0, 1));
}

TEST_CASE("SVG of segment sets: runs joined, branches restarted", "[io][geometry]") {
  Segments s;
  s.vertices.resize(4, 2);
  s.vertices << 0, 0, 1, 0, 1, 1, 2, 2;
  s.segments = {{0, 1}, {1, 2}, {1, 3}};
  const std::string svg = segments_svg(s);
  CHECK_THAT(svg, Catch::StartsWith("<svg"));
  // Two runs: M a L b L c, then M b L d.
  const std::size_t d = svg.find(" d=\"");
  REQUIRE(d != std::string::npos);
  const std::string path = svg.substr(d + 4, svg.find('"', d + 4) - d - 4);
  CHECK(std::count(path.begin(), path.end(), 'M') == 2);
  CHECK(std::count(path.begin(), path.end(), 'L') == 3);
  // Framing: x from 40 to 760 (5 % margins of 800), y up.
  CHECK_THAT(path, Catch::StartsWith("M40.000,760.000 L400.000,760.000 L400.000,400.000 M400.000,760.000"));
  // The polyline SVG is the same writer.
  Points p(3, 2);
  p << 0, 0, 1, 0, 1, 1;
  CHECK_THAT(polyline_svg(p), Catch::Contains("M40.000,760.000 L760.000,760.000 L760.000,40.000\""));
}

TEST_CASE("Geometry writers refuse bad meshes and segments", "[io][geometry]") {
  Mesh m = sample_mesh(false, false);
  m.quads[0][2] = 5;
  CHECK_THROWS_WITH(mesh_ply(m), Catch::Contains("quads[0][2] = 5 is out of range (5 vertices)"));
  m.quads[0][2] = -1;
  CHECK_THROWS_AS(mesh_obj(m), InvalidInput);
  m = sample_mesh(false, false);
  m.vertices(3, 1) = std::nan("");
  CHECK_THROWS_WITH(mesh_obj(m), Catch::Contains("vertices[3] is not finite"));
  m = sample_mesh(false, true);
  m.states.pop_back();
  CHECK_THROWS_WITH(mesh_ply(m), Catch::Contains("2 states for 3 faces"));
  m = sample_mesh(false, false);
  m.normals = Points::Zero(4, 3);
  CHECK_THROWS_WITH(mesh_ply(m), Catch::Contains("normals are 4 by 3"));
  Segments s;
  s.vertices = Points::Zero(2, 4);
  s.segments = {{0, 1}};
  CHECK_THROWS_WITH(segments_obj(s), Catch::Contains("4 columns"));
  s.vertices = Points::Zero(2, 2);
  s.segments = {{0, 2}};
  CHECK_THROWS_WITH(segments_ply(s), Catch::Contains("segments[0][1] = 2 is out of range"));
  s.segments = {{0, 1}};
  CHECK_THROWS_AS(segments_svg(s, SvgOptions{10, 1.5, "black"}), InvalidInput);
}
