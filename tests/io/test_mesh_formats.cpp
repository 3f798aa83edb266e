// SPDX-License-Identifier: MIT
// STL, OFF and VTK PolyData: each file read back by an independent route (the bytes decoded here, by
// the format's specification) and, for STL and OFF, by cifs's own reader.
#include <Eigen/Geometry>
#include <bit>
#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/mesh_formats.hpp"
#include "io/mesh_samples.hpp"

using namespace cifs;
using namespace cifs::io;

namespace {

std::string stl_bytes(const Mesh& m) {
  StringSink out;
  mesh_stl(m, out);
  return std::move(out.bytes);
}

template <class T>
T le_at(const std::string& bytes, std::size_t at) {
  std::conditional_t<sizeof(T) == 8, std::uint64_t,
                     std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint16_t>>
      bits = 0;
  for (std::size_t i = sizeof(T); i-- > 0;)
    bits = static_cast<decltype(bits)>((bits << 8) | static_cast<unsigned char>(bytes[at + i]));
  return std::bit_cast<T>(bits);
}

/// The open grid with a hole and a pentagon: fans, holes and welding all show.
Mesh formats_sample() {
  Mesh m = io_test::open_grid(3);
  m.tags.holes = {4};
  const Eigen::Index n = m.vertices.rows();
  m.vertices.conservativeResize(n + 1, 3);
  m.vertices.row(n) << 0.5, -0.25, 0.125;
  add_face(m, {0, static_cast<int>(n), 1, 5, 4});  // a pentagon below the first quad's edge 0–1
  return m;
}

}  // namespace

TEST_CASE("STL: binary, fans of every face but the holes, unit normals, corners welded back", "[io][stl]") {
  const Mesh m = formats_sample();
  const std::string bytes = stl_bytes(m);
  // 8 quads (one of 9 is a hole) of 2 triangles and a pentagon of 3.
  const std::uint32_t triangles = 8 * 2 + 3;
  REQUIRE(bytes.size() == 84 + 50 * triangles);
  CHECK(bytes.substr(0, 5) != "solid");
  CHECK(le_at<std::uint32_t>(bytes, 80) == triangles);
  // Triangle by triangle, as the specification lays them out: normal, three corners, two bytes.
  std::size_t t = 0;
  const std::vector<char> hole = hole_flags(m);
  for (std::size_t f = 0; f < face_count(m); ++f) {
    if (hole[f] != 0) continue;
    const auto c = face(m, f);
    for (std::size_t i = 1; i + 1 < c.size(); ++i, ++t) {
      const std::size_t at = 84 + 50 * t;
      const std::array<int, 3> corners{c[0], c[i], c[i + 1]};
      Eigen::Matrix3d p;
      for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t d = 0; d < 3; ++d) {
          const float x = le_at<float>(bytes, at + 12 + 12 * k + 4 * d);
          CHECK(x == static_cast<float>(m.vertices(corners[k], static_cast<Eigen::Index>(d))));
          p(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(d)) =
              m.vertices(corners[k], static_cast<Eigen::Index>(d));
        }
      const Eigen::Vector3d n = (p.row(1) - p.row(0)).cross(p.row(2) - p.row(0)).normalized();
      for (std::size_t d = 0; d < 3; ++d)
        CHECK(le_at<float>(bytes, at + 4 * d) == static_cast<float>(n(static_cast<Eigen::Index>(d))));
      CHECK(le_at<std::uint16_t>(bytes, at + 48) == 0);
    }
  }
  CHECK(t == triangles);

  // Read back: one vertex per position (the hole's corners all belong to other faces too), positions
  // the floats written, triangles in the same order.
  const Mesh back = parse_mesh_stl(bytes, "m.stl");
  CHECK(back.vertices.rows() == m.vertices.rows());
  REQUIRE(face_count(back) == triangles);
  for (std::size_t f = 0; f < face_count(back); ++f) {
    const auto c = face(back, f);
    const std::size_t at = 84 + 50 * f + 12;
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t d = 0; d < 3; ++d)
        CHECK(back.vertices(c[k], static_cast<Eigen::Index>(d)) ==
              static_cast<double>(le_at<float>(bytes, at + 12 * k + 4 * d)));
  }
}

TEST_CASE("STL: ASCII read, degenerate triangles counted, bad input named", "[io][stl]") {
  const std::string two =
      "solid two triangles\n"
      " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
      "  endloop\n endfacet\n"
      " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n   vertex 0.1 1 0\n"
      "  endloop\n endfacet\n"
      " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 0 0 0\n   vertex 1 1 0\n"
      "  endloop\n endfacet\n"
      "endsolid two triangles\n";
  std::vector<std::string> warnings;
  const Mesh m =
      parse_mesh_stl(two, "two.stl", {.warn = [&](const std::string& w) { warnings.push_back(w); }});
  CHECK(m.vertices.rows() == 4);
  CHECK(m.face_vertices == std::vector<int>{0, 1, 2, 0, 2, 3});
  CHECK(m.vertices(3, 0) == 0.1);  // ASCII keeps the double
  CHECK(warnings ==
        std::vector<std::string>{"two.stl: 1 of 3 triangles have two corners at one position; left out"});
  CHECK_THROWS_WITH(parse_mesh_stl("solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 nan\n", "a.stl"),
                    "a.stl: line 4: 'nan' is not a finite number");
  CHECK_THROWS_WITH(parse_mesh_stl("solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n", "a.stl"),
                    "a.stl: line 5: expected 'vertex', got the end of the file");
  CHECK_THROWS_WITH(parse_mesh_stl("solid x\n", "a.stl"),
                    "a.stl: line 2: expected 'facet' or 'endsolid', got the end of the file");
  CHECK_THROWS_WITH(parse_mesh_stl("solid x\nendsolid\n", "a.stl"),
                    "a.stl: no triangle with three distinct corners");
  std::string binary = stl_bytes(formats_sample());
  binary.pop_back();
  CHECK_THROWS_WITH(
      parse_mesh_stl(binary, "cut.stl"),
      "cut.stl: neither ASCII STL (no 'solid') nor binary STL (1033 bytes where 19 triangles take 1034)");
  CHECK_THROWS_WITH(
      parse_mesh_stl("abc", "s.stl"),
      "s.stl: neither ASCII STL (no 'solid') nor binary STL (3 bytes, fewer than the 84 of its header)");
  Mesh far = io_test::cube();
  far.vertices(5, 2) = 1e39;
  CHECK_THROWS_WITH(stl_bytes(far), Catch::Contains("vertex 5 at 1e+39, beyond the float range STL stores"));
}

TEST_CASE("OFF: written and read back bit for bit, NOFF normals, holes left out", "[io][off]") {
  for (const bool normals : {false, true}) {
    const Mesh m = io_test::sample_mesh(normals, false);
    StringSink out;
    mesh_off(m, out);
    CHECK(out.bytes.substr(0, 9) == (normals ? "NOFF\n5 3 " : "OFF\n5 3 0"));
    const Mesh back = parse_mesh_off(out.bytes, "m.off");
    CHECK(back.vertices == m.vertices);  // 17 digits read back exactly
    CHECK(back.normals == m.normals);
    CHECK(back.face_offsets == m.face_offsets);
    CHECK(back.face_vertices == m.face_vertices);
  }
  Mesh holed = formats_sample();
  StringSink out;
  mesh_off(holed, out);
  const Mesh back = parse_mesh_off(out.bytes, "h.off");
  CHECK(face_count(back) == face_count(holed) - 1);
  CHECK(mesh_left_out(holed, "off") == "1 hole face");
  holed.normal_indices.assign(holed.face_vertices.size(), 0);
  holed.normals = Points::Zero(1, 3);
  holed.normals(0, 2) = 1;
  CHECK_THROWS_WITH(mesh_off(holed, out),
                    Catch::StartsWith("the mesh to write as OFF has normals per face corner"));
}

TEST_CASE("OFF: the variants, comments and colours, and bad input named by line", "[io][off]") {
  std::vector<std::string> warnings;
  const MeshReadOptions collect{.warn = [&](const std::string& w) { warnings.push_back(w); }};
  const Mesh m = parse_mesh_off(
      "COFF # coloured\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n"
      "# a comment line\n1 1 0 0 0 255 255\n0 1 0 9 9 9 255\n4 0 1 2 3 0.5 0.5 0.5\n",
      "c.off", collect);
  CHECK(m.vertices.rows() == 4);
  CHECK(m.face_vertices == std::vector<int>{0, 1, 2, 3});
  CHECK(warnings == std::vector<std::string>{"c.off: the vertex and face colours are not read"});
  warnings.clear();
  const Mesh one_line = parse_mesh_off("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "o.off", collect);
  CHECK(face_count(one_line) == 1);
  CHECK(warnings.empty());
  CHECK_THROWS_WITH(parse_mesh_off("4OFF\n1 1 0\n", "v.off"),
                    "v.off: line 1: the OFF variant '4OFF' is not read (only OFF, NOFF, COFF and CNOFF: 3-D "
                    "polygon meshes)");
  CHECK_THROWS_WITH(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "i.off"),
                    "i.off: line 6: the vertex index '3' is not an integer in 0 … 2");
  CHECK_THROWS_WITH(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0 7\n3 0 1 2\n", "n.off"),
                    "n.off: line 5: vertex 2 has 4 numbers, expected 3");
  CHECK_THROWS_WITH(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 0\n# a third vertex?\n", "e.off"),
                    "e.off: line 5: the file ends after 2 of 3 vertices");
  CHECK_THROWS_WITH(
      parse_mesh_off("OFF\n2000000000 2000000000 0\n", "big.off"),
      Catch::StartsWith(
          "big.off: line 2: 2000000000 vertices and 2000000000 faces cannot fit in the 28 bytes"));
  CHECK_THROWS_WITH(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "f.off"),
                    "f.off: line 6: the corner count '2' is not an integer in 3 … 2147483647");
}

TEST_CASE("VTK PolyData: the appended arrays decode to the mesh, offsets as the XML says", "[io][vtk]") {
  Mesh m = formats_sample();
  m.normals = vertex_normals(m);
  m.states.resize(face_count(m));
  for (std::size_t f = 0; f < m.states.size(); ++f) m.states[f] = static_cast<std::uint32_t>(3 * f + 1);
  StringSink out;
  mesh_vtp(m, out);
  const std::string& s = out.bytes;
  const std::size_t data = s.find("<AppendedData encoding=\"raw\">");
  REQUIRE(data != std::string::npos);
  const std::size_t base = s.find('_', data) + 1;
  // Each DataArray's offset, from the XML, into the block after '_'.
  const auto offset_of = [&](const std::string& name) {
    const std::size_t at = s.find("Name=\"" + name + "\"");
    REQUIRE(at < data);
    const std::size_t o = s.find("offset=\"", at) + 8;
    return base + std::stoull(s.substr(o, s.find('"', o) - o));
  };
  const std::vector<char> hole = hole_flags(m);
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint32_t> states;
  for (std::size_t f = 0; f < face_count(m); ++f)
    if (hole[f] == 0) {
      for (const int v : face(m, f)) connectivity.push_back(v);
      offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
      states.push_back(m.states[f]);
    }
  CHECK(s.find("NumberOfPoints=\"17\"") != std::string::npos);
  CHECK(s.find("NumberOfPolys=\"" + std::to_string(offsets.size()) + "\"") != std::string::npos);
  const auto check_doubles = [&](const std::string& name, const Points& p) {
    const std::size_t at = offset_of(name);
    REQUIRE(le_at<std::uint64_t>(s, at) == static_cast<std::uint64_t>(p.size()) * 8);
    for (Eigen::Index i = 0; i < p.rows(); ++i)
      for (Eigen::Index c = 0; c < 3; ++c)
        CHECK(le_at<double>(s, at + 8 + static_cast<std::size_t>(24 * i + 8 * c)) == p(i, c));
  };
  check_doubles("Points", m.vertices);
  check_doubles("Normals", m.normals);
  for (const auto& [name, values] :
       {std::pair{"connectivity", &connectivity}, std::pair{"offsets", &offsets}}) {
    const std::size_t at = offset_of(name);
    REQUIRE(le_at<std::uint64_t>(s, at) == values->size() * 8);
    for (std::size_t i = 0; i < values->size(); ++i)
      CHECK(le_at<std::int64_t>(s, at + 8 + 8 * i) == (*values)[i]);
  }
  const std::size_t at = offset_of("state");
  REQUIRE(le_at<std::uint64_t>(s, at) == states.size() * 4);
  for (std::size_t i = 0; i < states.size(); ++i) CHECK(le_at<std::uint32_t>(s, at + 8 + 4 * i) == states[i]);
  CHECK(s.substr(s.size() - 30) == "\n  </AppendedData>\n</VTKFile>\n");
  CHECK(mesh_left_out(m, "vtp") == "1 hole face");
  CHECK(mesh_left_out(m, "stl") == "1 hole face, the normals and the face states");
  CHECK(mesh_left_out(m, "obj").empty());
  m.tags.rules = RuleSet::blz;
  m.tags.concave = {0};
  CHECK(mesh_left_out(m, "ply") == "1 hole face, 1 concave corner and the rule set 'blz'");
}
