// SPDX-License-Identifier: MIT
#include "cifs/io/io.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/io/cad.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using namespace cifs::io;
using Catch::Matchers::Contains;

namespace {
std::string table(Content content) {
  std::string out;
  for (const Format& f : formats(content))
    out += std::string(f.name) + ":" + std::string(f.extension) + (f.read ? "r" : "") + (f.write ? "w" : "") +
           (f.binary ? "b" : "") + " ";
  return out;
}

Mesh pentagon_and_triangle() {
  Mesh m;
  m.vertices.resize(6, 3);
  for (int k = 0; k < 5; ++k) m.vertices.row(k) << std::cos(k * 1.25), std::sin(k * 1.25), 0.5;
  m.vertices.row(5) << 0, 0, 2;
  add_face(m, {0, 1, 2, 3, 4});
  add_face(m, {0, 1, 5});
  m.states = {3, 9};
  return m;
}

}  // namespace

TEST_CASE("The format table: every content, its formats in order", "[io][dispatch]") {
  CHECK(table(Content::shape) == "json:.jsonrw obj:.objrw step:.steprw stp:.stprw iges:.igesrw igs:.igsrw ");
  CHECK(table(Content::polygon) == "json:.jsonrw obj:.objw svg:.svgw ");
  CHECK(table(Content::mesh) == "obj:.objrw ply:.plyrwb stl:.stlrwb off:.offrw vtp:.vtpwb ");
  CHECK(table(Content::segments) == "obj:.objw ply:.plywb svg:.svgw ");
  CHECK(table(Content::automaton) == "json:.jsonrw svg:.svgw dot:.dotw ");
  CHECK(table(Content::bcifs) == "json:.jsonrw ");
  CHECK(table(Content::experiment) == "json:.jsonr ");
  CHECK(writable_format(Content::mesh, "ply", "--format").extension == ".ply");
  CHECK_THROWS_WITH(writable_format(Content::automaton, "png", "--format"),
                    "--format 'png': expected json, svg or dot");
  CHECK_THROWS_WITH(writable_format(Content::experiment, "json", "--format"), "--format 'json': expected ");
  CHECK_THROWS_WITH(encode(pentagon_and_triangle(), "svg"),
                    "format 'svg': expected obj, ply, stl, off or vtp");
}

TEST_CASE("STEP and IGES without the OpenCASCADE component: one clear refusal, nothing written",
          "[io][cad]") {
  // cifs_tests never links cifs::occt: io's slot for it is empty here (tests/occt tests it filled).
  cifs_test::ScratchDir s("io_cad");
  CHECK(cad_format("a/part.STEP") == CadFormat::step);
  CHECK(cad_format("part.stp") == CadFormat::step);
  CHECK(cad_format("part.Igs") == CadFormat::iges);
  CHECK(cad_format("part.iges") == CadFormat::iges);
  CHECK(!cad_format("part.json"));
  Points P(2, 2);
  P << 0, 0, 1, 1;
  const Shape line = nurbs::make_curve(1, {0, 0, 1, 1}, P);
  for (const char* name : {"out.step", "out.igs"}) {
    const std::filesystem::path path = s.path() / name;
    CHECK_THROWS_WITH(write(path, line), path.string() +
                                             ": built without OpenCASCADE: STEP and IGES files need the "
                                             "cifs::occt component (install libocct-data-exchange-dev and "
                                             "configure with -DCIFS_OCCT=ON, docs/install.md)");
    CHECK_THROWS_AS(encode(line, path.extension().string().substr(1)), InvalidInput);
    CHECK_THROWS_WITH(read_shapes(path),
                      Catch::Contains("built without OpenCASCADE"));  // before "cannot open"
  }
  CHECK(s.names().empty());
}

TEST_CASE("write and read by extension: the bytes of encode, read back", "[io][dispatch]") {
  cifs_test::ScratchDir s("io");
  const Mesh m = pentagon_and_triangle();
  for (const char* name : {"m.obj", "m.ply"}) {
    const auto path = s.path() / name;
    write(path, m);
    CHECK(read_file(path) == encode(m, path.extension().string().substr(1)));
    const Mesh back = read_mesh(path);
    CHECK(back.vertices == m.vertices);
    CHECK(back.face_vertices == m.face_vertices);
    CHECK(back.face_offsets == m.face_offsets);
  }
  CHECK(read_mesh(s.path() / "m.ply").states == m.states);  // OBJ has no face states
  CHECK(read_mesh(s.path() / "m.obj").states.empty());

  Segments seg = polyline_segments(m.vertices, true, 2);
  for (const char* ext : {"obj", "ply", "svg"}) {
    const auto path = s.path() / (std::string("s.") + ext);
    write(path, seg);
    CHECK(read_file(path) == encode(seg, ext));
  }

  Points P(4, 2);
  P << 0, 0, 1, 0, 1, 1, 0.5, 2;
  const nurbs::Curve curve = nurbs::make_curve(2, {0, 0, 0, 1, 2, 2, 2}, P);
  for (const char* ext : {"json", "obj"}) {
    const auto path = s.path() / (std::string("c.") + ext);
    write(path, Shape(curve));
    CHECK(read_file(path) == encode(Shape(curve), ext));
    CHECK(std::get<nurbs::Curve>(read_shape(path)).knots == curve.knots);
  }
  // Shapes, polygons, automata, BC-IFS files and experiments read any other extension as JSON.
  write_file_atomically(s.path() / "c.txt", to_json(Shape(curve)));
  CHECK(std::get<nurbs::Curve>(read_shape(s.path() / "c.txt")).P == curve.P);

  const Polygon polygon{P, true};
  write(s.path() / "p.json", polygon);
  CHECK(read_polygon(s.path() / "p.json").points == P);
  CHECK(read_polygon(s.path() / "p.json").closed);
  CHECK_THROWS_WITH(parse_polygon_json(R"({"polygon": {"points": [[0]]}, "closd": true})", "p.json"),
                    "p.json: closd: unknown member");
  write(s.path() / "p.obj", polygon);
  CHECK(read_file(s.path() / "p.obj") == polyline_obj(P, true));
  write(s.path() / "p.svg", polygon);
  CHECK(read_file(s.path() / "p.svg") == encode(polygon, "svg"));

  const nurbs::KnotAutomaton ka = nurbs::knot_automaton(curve);
  for (const char* ext : {"json", "svg", "dot"}) {
    const auto path = s.path() / (std::string("a.") + ext);
    write(path, ka);
    CHECK(read_file(path) == encode(ka, ext));
  }
  CHECK(to_json(read_automaton(s.path() / "a.json")) == to_json(ka));

  const BcifsFile file{ifs::curve_bcifs(curve), nurbs::initial_nets(ka, curve)};
  write(s.path() / "b.json", file);
  const BcifsFile back = read_bcifs(s.path() / "b.json");
  CHECK(to_json(back.system, back.nets) == to_json(file.system, file.nets));
}

TEST_CASE("write and read refuse unknown extensions before touching the disk", "[io][dispatch]") {
  cifs_test::ScratchDir s("io");
  const Mesh m = pentagon_and_triangle();
  CHECK_THROWS_WITH(write(s.path() / "m.gltf", m),
                    (s.path() / "m.gltf").string() + ": a mesh is written as .obj, .ply, .stl, .off or .vtp");
  CHECK_THROWS_AS(write(s.path() / "m.gltf", m), InvalidInput);
  CHECK_THROWS_WITH(write(s.path() / "s.dot", polyline_segments(m.vertices)),
                    (s.path() / "s.dot").string() + ": a segment set is written as .obj, .ply or .svg");
  CHECK_THROWS_WITH(write(s.path() / "a.obj", automata::Automaton{}),
                    (s.path() / "a.obj").string() + ": an automaton is written as .json, .svg or .dot");
  CHECK(std::filesystem::is_empty(s.path()));
  CHECK_THROWS_WITH(read_mesh(s.path() / "m.gltf"),
                    (s.path() / "m.gltf").string() + ": a mesh is read from .obj, .ply, .stl or .off");
  CHECK_THROWS_AS(read_mesh(s.path() / "m.gltf"), IoError);
  CHECK_THROWS_WITH(read_mesh(s.path() / "none.obj"), Contains("none.obj: cannot open"));
  // Content errors name the file and the line or element.
  write_file_atomically(s.path() / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  CHECK_THROWS_WITH(read_mesh(s.path() / "bad.obj"),
                    (s.path() / "bad.obj").string() +
                        ": line 4: vertex index 7 is out of range: 3 vertices are defined before this line");
}

TEST_CASE("polygon JSON keeps the sign of zero", "[io][reliability]") {
  // "-0" reads back as the integer 0: the round trip lost the sign (tests/fuzz/fuzz_polygon).
  Polygon p{Points(2, 2), false};
  p.points << -0.0, 1, 0.0, -0.0;
  const Polygon back = parse_polygon_json(to_json(p), "p.json");
  CHECK(std::signbit(back.points(0, 0)));
  CHECK(!std::signbit(back.points(1, 0)));
  CHECK(std::signbit(back.points(1, 1)));
  CHECK(to_json(back) == to_json(p));
}
