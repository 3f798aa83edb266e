// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using Catch::Matchers::StartsWith;

namespace {

io::Shape parse_shape(const std::string& text) {
  return io::parse_shape_json(text, "s.json");
}

/// The message of the InvalidInput/IoError that parsing `text` raises.
std::string shape_error_of(const std::string& text) {
  try {
    parse_shape(text);
  } catch (const InvalidInput& e) {
    return e.what();
  } catch (const IoError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("JSON curves round-trip bit for bit", "[io][json]") {
  const std::string text = R"({"curve": {"degree": 2, "knots": [0, 0, 0, 0.1, 0.7, 1, 1, 1],
      "points": [[0, 0.1], [1, 2.3], [3, 3], [4, 0], [6.2, 1e-7]], "weights": [1, 0.5, 3, 1e-3, 1e3]}})";
  const auto c = std::get<nurbs::Curve>(parse_shape(text));
  CHECK(c.rational);
  CHECK(c.degree == 2);
  const auto back = std::get<nurbs::Curve>(parse_shape(io::to_json(c)));
  CHECK(back.knots == c.knots);
  CHECK(back.P == c.P);  // exact: Cartesian ↔ homogeneous through the same operations
  CHECK(nurbs::cartesian_points(back) == nurbs::cartesian_points(c));
}

TEST_CASE("JSON closed curves keep their period and round-trip", "[io][json]") {
  const std::string text = R"({"curve": {"degree": 3, "closed": true, "knots": [0, 1, 2, 3.5, 4],
      "points": [[0, 0], [1, 0], [1, 1], [0, 1]]}})";
  const auto c = std::get<nurbs::Curve>(parse_shape(text));
  CHECK(c.closed);
  CHECK(nurbs::distinct_count(c) == 4);
  CHECK(c.P.rows() == 7);
  CHECK(nurbs::defining_knots(c) == nurbs::Knots{0, 1, 2, 3.5, 4});
  const auto back = std::get<nurbs::Curve>(parse_shape(io::to_json(c)));
  CHECK(back.closed);
  CHECK(back.knots == c.knots);
  CHECK(back.P == c.P);
  // Periodic: the curve closes with its derivatives.
  const Points d0 = nurbs::derivatives(c, 0.0, 2), d1 = nurbs::derivatives(c, 4.0, 2);
  CHECK((d0 - d1).norm() <= 1e-12 * d0.norm());
}

TEST_CASE("JSON surfaces keep points[i][j] with i along u", "[io][json]") {
  const std::string text = R"({"surface": {"degree": [1, 2], "knots": [[0, 0, 1, 1], [0, 0, 0, 1, 1, 1]],
      "points": [[[0, 0, 0], [0, 1, 0], [0, 2, 0]], [[1, 0, 5], [1, 1, 5], [1, 2, 6]]],
      "weights": [[1, 2, 1], [1, 1, 3]]}})";
  const auto s = std::get<nurbs::Surface>(parse_shape(text));
  CHECK(s.count == std::array<Eigen::Index, 2>{2, 3});
  // Corner (u, v) = (1, 1) interpolates points[1][2] whatever the weights.
  const Point corner = nurbs::evaluate(s, 1, 1);
  CHECK(corner(0) == Approx(1).margin(1e-15));
  CHECK(corner(1) == Approx(2).margin(1e-15));
  CHECK(corner(2) == Approx(6).margin(1e-15));
  const auto back = std::get<nurbs::Surface>(parse_shape(io::to_json(s)));
  CHECK(back.knots == s.knots);
  CHECK(back.P == s.P);
}

TEST_CASE("JSON shapes are written a chunk at a time, in the shape files' layout", "[io][json]") {
  // The writer built a document tree of every number before its first byte: 700 MB of memory for the
  // 90 MB of a revolved profile of 200,000 points. A 400 × 200 rational net here: 5 MB of text.
  struct Pieces final : ByteSink {
    std::size_t largest = 0, count = 0;
    std::string bytes;
    void write(std::string_view more) override {
      largest = std::max(largest, more.size());
      ++count;
      bytes += more;
    }
  };
  const Eigen::Index nu = 400, nv = 200;
  Points P(nu * nv, 3);
  Eigen::VectorXd w(nu * nv);
  for (Eigen::Index i = 0; i < nu; ++i)
    for (Eigen::Index j = 0; j < nv; ++j) {
      P.row(i * nv + j) << std::sin(0.1 * static_cast<double>(i)) + 1.0 / 3, static_cast<double>(j) * 1e-7,
          static_cast<double>(i * j) / 7;
      w(i * nv + j) = 1 + static_cast<double>((i + j) % 5) / 3;
    }
  P(0, 0) = -0.0;
  const auto knots = [](Eigen::Index n) {
    nurbs::Knots k{0, 0, 0};
    for (Eigen::Index i = 1; i < n - 2; ++i) k.push_back(static_cast<double>(i) / static_cast<double>(n - 2));
    k.insert(k.end(), {1, 1, 1});
    return k;
  };
  const nurbs::Surface s = nurbs::make_surface({2, 2}, {knots(nu), knots(nv)}, {nu, nv}, P, w);
  Pieces sink;
  io::write_json(s, sink);
  CHECK(sink.bytes == io::to_json(s));
  CHECK(sink.bytes.size() > 3 * ChunkBuffer::kChunkBytes);
  CHECK(sink.count >= 3);
  CHECK(sink.largest < 2 * ChunkBuffer::kChunkBytes);  // a row over a chunk at most
  // The layout of the shape files: one member a line, the net one u row a line, numbers as JSON reads
  // them back (−0 as -0.0), and every bit back.
  std::vector<std::string> lines;
  for (std::size_t at = 0, end; (end = sink.bytes.find('\n', at)) != std::string::npos; at = end + 1)
    lines.push_back(sink.bytes.substr(at, end - at));
  REQUIRE(lines.size() == static_cast<std::size_t>(nu) + 9);
  CHECK(lines[0] == "{");
  CHECK(lines[1] == "  \"surface\": {");
  CHECK(lines[2] == "    \"degree\": [2,2],");
  CHECK_THAT(lines[3], StartsWith("    \"knots\": [[0.0,0.0,0.0,0.002512562814070352,"));
  CHECK(lines[4] == "    \"points\": [");
  CHECK_THAT(lines[5], StartsWith("      [[-0.0,0.0,0.0],["));
  for (Eigen::Index i = 0; i < nu; ++i)
    CHECK(nlohmann::json::parse(lines[static_cast<std::size_t>(5 + i)].substr(
                                    0, lines[static_cast<std::size_t>(5 + i)].find_last_of(']') + 1))
              .size() == static_cast<std::size_t>(nv));
  CHECK(lines[5 + nu] == "    ],");
  CHECK_THAT(lines[6 + nu], StartsWith("    \"weights\": [[1.0,1.3333333333333333,"));
  CHECK(lines[7 + nu] == "  }");
  CHECK(lines[8 + nu] == "}");
  const auto back = std::get<nurbs::Surface>(parse_shape(sink.bytes));
  CHECK(back.knots == s.knots);
  CHECK(back.P == s.P);
}

TEST_CASE("JSON errors name the file, the path and the problem", "[io][json]") {
  const std::string curve_head = R"({"curve": {"degree": 2, )";
  CHECK_THAT(shape_error_of("{"), Catch::Contains("s.json: malformed JSON"));
  CHECK_THAT(shape_error_of("[]"), Catch::Contains("one member, \"curve\" or \"surface\""));
  CHECK_THAT(shape_error_of(R"({"curve": 3})"), Catch::Contains("curve: expected an object"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 2, "knots": [0,0,0,1,1,1]}})"),
             Catch::Contains("curve: missing \"points\""));
  CHECK_THAT(shape_error_of(curve_head + R"("knots": [0,0,0,1,"a",1], "points": [[0],[1],[2]]}})"),
             Catch::Contains("s.json: curve.knots[4]: expected a number"));
  CHECK_THAT(shape_error_of(curve_head + R"("knots": [0,0,0,1,1e999,1], "points": [[0],[1],[2]]}})"),
             Catch::Contains("s.json: malformed JSON: number overflow parsing '1e999'"));
  CHECK_THAT(shape_error_of(curve_head + R"("knots": [0,0,0,2,1,1,1], "points": [[0],[1],[2],[3]]}})"),
             Catch::Contains("s.json: curve.knots[4]: 1 is less than the previous knot 2"));
  CHECK_THAT(shape_error_of(curve_head + R"("knots": [0,0,0,1,1], "points": [[0],[1],[2]]}})"),
             Catch::Contains("curve.knots: 5 knots given, 3 control points of degree 2 need 6"));
  CHECK_THAT(shape_error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0,1],[1],[2,3]]}})"),
             Catch::Contains("curve.points[1]: 1 coordinates, the first point has 2"));
  CHECK_THAT(
      shape_error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0],[1],[2]], "weights": [1,0,1]}})"),
      Catch::Contains("curve.weights[1]: weight 0 is not a positive finite number"));
  CHECK_THAT(
      shape_error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0],[1],[2]], "weights": [1,1]}})"),
      Catch::Contains("2 weights given for 3"));
  CHECK_THAT(
      shape_error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0],[1],[2]], "weigths": [1,1,1]}})"),
      Catch::Contains("curve.weigths: unknown member"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 0, "knots": [0,1], "points": [[0]]}, "curv": 1})"),
             Catch::Contains("s.json: curv: unknown member"));
  CHECK_THAT(shape_error_of(R"({"surface": {"degree": [1, 1], "knots": [[0,0,1,1],[0,0,1,1]],
      "points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]], "closed": true}})"),
             Catch::Contains("surface.closed: unknown member"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 0, "knots": [0,1], "points": [[0]]}})"),
             Catch::Contains("degree 0 is outside [1, 64]"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 2.5, "knots": [0,1], "points": [[0]]}})"),
             Catch::Contains("curve.degree: expected an integer"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 1, "knots": [0,0,0,1], "points": [[0],[1]]}})"),
             Catch::Contains("curve.knots[2]: knot 0 has multiplicity 3 > degree + 1 = 2"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 1, "knots": [0,0,0,0], "points": [[0],[1]]}})"),
             Catch::Contains("multiplicity"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 1, "knots": [0,1,1,2], "points": [[0],[1]]}})"),
             Catch::Contains("curve.knots: empty domain"));
  CHECK_THAT(shape_error_of(
                 R"({"curve": {"degree": 3, "closed": true, "knots": [0,1,2], "points": [[0],[1],[2]]}})"),
             Catch::Contains("takes 4 breakpoints"));
  CHECK_THAT(shape_error_of(
                 R"({"curve": {"degree": 3, "closed": true, "knots": [0,0,0,0], "points": [[0],[1],[2]]}})"),
             Catch::Contains("period [0, 0] is empty"));
  CHECK_THAT(
      shape_error_of(R"({"curve": {"degree": 3, "closed": 1, "knots": [0,1,2,3], "points": [[0],[1],[2]]}})"),
      Catch::Contains("curve.closed: expected true or false"));
  const std::string surface_head = R"({"surface": {"degree": [1, 1], "knots": [[0,0,1,1],[0,0,1,1]], )";
  CHECK_THAT(shape_error_of(surface_head + R"("points": [[[0,0],[0,1]], [[1,0]]]}})"),
             Catch::Contains("surface.points[1]: 1 points, the first row has 2"));
  CHECK_THAT(shape_error_of(surface_head +
                            R"("points": [[[0,0],[0,1]], [[1,0],[1,1]]], "weights": [[1,1],[1,-2]]}})"),
             Catch::Contains("surface.weights[1][1]: weight -2"));
  CHECK_THAT(
      shape_error_of(surface_head + R"("points": [[[0,0],[0,1]], [[1,0],[1,1]]], "weights": [[1,1]]}})"),
      Catch::Contains("surface.weights: 1 rows, the net has 2"));
  CHECK_THAT(
      shape_error_of(
          R"({"surface": {"degree": [1, 1], "knots": [[0,0,1,1],[0,1,0,1]], "points": [[[0],[0]], [[1],[1]]]}})"),
      Catch::Contains("surface.knots[1][2]: 0 is less than the previous knot 1"));
  CHECK_THAT(shape_error_of(R"({"surface": {"degree": 1, "knots": [], "points": []}})"),
             Catch::Contains("surface.degree: expected an array"));
}

TEST_CASE("Shape files: unreadable paths and atomic writes", "[io]") {
  CHECK_THROWS_AS(io::read_shape("/nonexistent/shape.json"), IoError);
  CHECK_THROWS_WITH(io::read_shape("/nonexistent/shape.json"),
                    Catch::Contains("/nonexistent/shape.json: cannot open"));
  CHECK_THROWS_WITH(io::read_shape("/tmp"), Catch::Contains("/tmp: is a directory"));
  const cifs_test::ScratchDir scratch("json_shape");
  const auto& dir = scratch.path();
  write_file_atomically(dir / "a.txt", "hello");
  CHECK(read_file(dir / "a.txt") == "hello");
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    CHECK(entry.path().filename() == "a.txt");  // no temporary left behind
  CHECK_THROWS_AS(write_file_atomically(dir / "missing" / "b.txt", "x"), IoError);
}

TEST_CASE("JSON knots in the Rhino convention (n + d - 1, end knots implicit)", "[io][json]") {
  // An unclamped non-uniform cubic: Rhino's 7 knots for 5 points; the standard vector adds one knot
  // at each end. openNURBS's ON_SuperfluousKnot extends an unclamped end by a span instead: the end
  // knots do not act on the domain, so that vector gives the same curve.
  const std::string points = R"("points": [[0, 0], [1, 3], [2.5, -1], [4, 2], [6, 0.5]])";
  const std::string rhino = R"({"curve": {"degree": 3, "knots": [0, 1, 2.5, 3, 4, 6, 7], )" + points + "}}";
  const std::string stated =
      R"({"curve": {"degree": 3, "knot_convention": "rhino", "knots": [0, 1, 2.5, 3, 4, 6, 7], )" + points +
      "}}";
  const std::string standard =
      R"({"curve": {"degree": 3, "knots": [-1.5, 0, 1, 2.5, 3, 4, 6, 7, 9], )" + points + "}}";
  const auto a = std::get<nurbs::Curve>(parse_shape(rhino)), b = std::get<nurbs::Curve>(parse_shape(stated)),
             c = std::get<nurbs::Curve>(parse_shape(standard));
  CHECK(a.knots == nurbs::Knots{0, 0, 1, 2.5, 3, 4, 6, 7, 7});
  CHECK(b.knots == a.knots);
  CHECK(nurbs::domain(a).start == 2.5);
  CHECK(nurbs::domain(a).end == 4);
  for (const double u : nurbs::uniform_parameters(nurbs::domain(c), 400)) {
    const Point p = nurbs::evaluate_basis(a, u), q = nurbs::evaluate_basis(c, u);
    CHECK((p - q).norm() <= 1e-15 * (1 + q.norm()));
  }
  // A clamped rational quadratic as Rhino stores it: [0, 0, 1, 2, 2] for 4 points.
  const auto r = std::get<nurbs::Curve>(parse_shape(
      R"({"curve": {"degree": 2, "knots": [0, 0, 1, 2, 2], "points": [[0], [1], [3], [4]], "weights": [1, 2, 1, 1]}})"));
  CHECK(r.knots == nurbs::Knots{0, 0, 0, 1, 2, 2, 2});
  // A surface: u in the Rhino convention, v standard, each told by its count.
  const auto s = std::get<nurbs::Surface>(parse_shape(R"({"surface": {"degree": [1, 2],
      "knots": [[0, 1, 2], [0, 0, 0, 1, 1, 1]],
      "points": [[[0, 0, 0], [0, 1, 0], [0, 2, 0]], [[1, 0, 1], [1, 1, 1], [1, 2, 1]], [[2, 0, 0], [2, 1, 0], [2, 2, 3]]]}})"));
  CHECK(s.knots[0] == nurbs::Knots{0, 0, 1, 2, 2});
  CHECK(s.knots[1] == nurbs::Knots{0, 0, 0, 1, 1, 1});
  const Point corner = nurbs::evaluate(s, 2, 1);
  CHECK(corner(2) == 3);
  // Stated conventions are checked; the standard one is the default.
  CHECK_THAT(
      shape_error_of(
          R"({"curve": {"degree": 3, "knot_convention": "standard", "knots": [0, 1, 2.5, 3, 4, 6, 7], )" +
          points + "}}"),
      Catch::Contains("curve.knots: 7 knots given, 5 control points of degree 3 need 9"));
  CHECK_THAT(
      shape_error_of(
          R"({"curve": {"degree": 3, "knot_convention": "rhino", "knots": [0, 1, 2, 3, 4, 5, 6, 7, 8], )" +
          points + "}}"),
      Catch::Contains("curve.knots: 9 knots given, 5 control points of degree 3 need 7 in the rhino "
                      "convention (n + d - 1)"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 3, "knots": [0, 1, 2, 3, 4, 5, 6, 7], )" + points + "}}"),
             Catch::Contains("8 knots given, 5 control points of degree 3 need 9 (or 7 without the first and "
                             "the last knot, as Rhino and openNURBS store them)"));
  CHECK_THAT(shape_error_of(R"({"curve": {"degree": 3, "knot_convention": "opennurbs", "knots": [0], )" +
                            points + "}}"),
             Catch::Contains("curve.knot_convention: 'opennurbs': expected \"standard\""));
  CHECK_THAT(shape_error_of(
                 R"({"curve": {"degree": 1, "closed": true, "knot_convention": "rhino", "knots": [0, 1, 2],
      "points": [[0], [1]]}})"),
             Catch::Contains("curve.knot_convention: a closed curve's knots are the m + 1 breakpoints"));
  CHECK_THAT(
      shape_error_of(
          R"({"surface": {"degree": [1, 1], "knot_convention": "rhino", "knots": [[0, 1], [0, 0, 1, 1]],
      "points": [[[0], [1]], [[2], [3]]]}})"),
      Catch::Contains("surface.knots[1]: 4 knots given, 2 control points of degree 1 need 2 in the rhino"));
}

namespace {

const double kHalfRoot2 = 0.7071067811865476;  // √2/2, the weight of a quarter circle's corner

}  // namespace

TEST_CASE("geomdl JSON exports: the example curve is the unit circle", "[io][json]") {
  const auto c = std::get<nurbs::Curve>(io::read_shape(CIFS_SOURCE_DIR "/examples/shapes/geomdl_curve.json"));
  CHECK(c.degree == 2);
  CHECK(c.rational);
  CHECK(nurbs::dimension(c) == 2);
  CHECK(nurbs::weights(c)(1) == kHalfRoot2);
  for (const double u : nurbs::uniform_parameters(nurbs::domain(c), 257))
    CHECK(std::abs(nurbs::evaluate(c, u).norm() - 1) <= 1e-15);
  // Quarter points by hand: the rational quadratic through (0, −1), (−1, −1), (−1, 0) at its middle
  // is ((0 + 2w·(−1) − 1)/(2 + 2w), (−1 − 2w + 0)/(2 + 2w)) with w = √2/2.
  const Point p = nurbs::evaluate(c, 0.125);
  const double w = kHalfRoot2, d = 2 + 2 * w;
  CHECK(p(0) == Approx((-2 * w - 1) / d).epsilon(1e-15));
  CHECK(p(1) == Approx((-1 - 2 * w) / d).epsilon(1e-15));
}

TEST_CASE("geomdl JSON exports: the example surface is the unit cylinder, v varying fastest", "[io][json]") {
  const auto s =
      std::get<nurbs::Surface>(io::read_shape(CIFS_SOURCE_DIR "/examples/shapes/geomdl_surface.json"));
  CHECK(s.degree == std::array<int, 2>{1, 2});
  CHECK(s.count == std::array<Eigen::Index, 2>{2, 9});
  for (const double u : nurbs::uniform_parameters({0, 1}, 9))
    for (const double v : nurbs::uniform_parameters({0, 1}, 65)) {
      const Point p = nurbs::evaluate(s, u, v);
      CHECK(std::abs(std::hypot(p(0), p(1)) - 1) <= 1e-15);
      CHECK(std::abs(p(2) - u) <= 1e-15);
    }
}

namespace {

std::string geomdl_curves(const std::string& entries, const std::string& shape_extra = "") {
  return R"({"shape": {"type": "curve", )" + shape_extra + R"("data": [)" + entries + "]}}";
}

const std::string kLine =
    R"({"degree": 1, "knotvector": [0, 0, 1, 1], "control_points": {"points": [[0, 0], [2, 4]]}})";
const std::string kArc = R"({"type": "spline", "rational": true, "dimension": 2, "degree": 2,
    "knotvector": [0, 0, 0, 1, 1, 1], "control_points": {"points": [[1, 0], [1, 1], [0, 1]],
    "weights": [1, 0.7071067811865476, 1]}, "delta": 0.01, "name": "arc", "id": 3})";

}  // namespace

TEST_CASE("geomdl JSON exports: several shapes, options and errors", "[io][json]") {
  const std::string two = geomdl_curves(kLine + ", " + kArc, R"("count": 2, )");
  const std::vector<io::Shape> shapes = io::parse_shapes_json(two, "g.json");
  REQUIRE(shapes.size() == 2);
  const auto line = std::get<nurbs::Curve>(shapes[0]);
  CHECK_FALSE(line.rational);
  CHECK(nurbs::evaluate(line, 0.25) == Point(Eigen::Vector2d(0.5, 1)));
  const auto arc = std::get<nurbs::Curve>(shapes[1]);
  CHECK(std::abs(nurbs::evaluate(arc, 0.5).norm() - 1) <= 1e-15);
  CHECK_THAT(shape_error_of(two),
             Catch::Contains("s.json: holds 2 shapes (curves and surfaces): choose one with --index"));
  CHECK(std::get<nurbs::Curve>(
            io::parse_shape_json(two, "g.json", {.ignore_trim = false, .index = 1, .warn = {}}))
            .rational);
  // The equivalent cifs curve gives the same points.
  const auto same = std::get<nurbs::Curve>(parse_shape(R"({"curve": {"degree": 2, "knots": [0, 0, 0, 1, 1, 1],
      "points": [[1, 0], [1, 1], [0, 1]], "weights": [1, 0.7071067811865476, 1]}})"));
  CHECK(same.P == arc.P);
  CHECK(same.knots == arc.knots);

  // Trims: refused, or ignored with a warning.
  const std::string trimmed = R"({"shape": {"type": "surface", "data": [{"degree_u": 1, "degree_v": 1,
      "knotvector_u": [0, 0, 1, 1], "knotvector_v": [0, 0, 1, 1], "size_u": 2, "size_v": 2,
      "control_points": {"points": [[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 1]]},
      "trims": {"count": 1, "data": [{"type": "freeform", "points": [[0.2, 0.2], [0.8, 0.2], [0.5, 0.8]]}]}}]}})";
  CHECK_THAT(
      shape_error_of(trimmed),
      Catch::Contains("s.json: shape.data[0].trims: trimmed surfaces are not supported; --ignore-trim"));
  std::vector<std::string> warnings;
  const auto s = std::get<nurbs::Surface>(io::parse_shape_json(
      trimmed, "t.json",
      {.ignore_trim = true, .index = {}, .warn = [&](const std::string& w) { warnings.push_back(w); }}));
  CHECK(warnings ==
        std::vector<std::string>{"t.json: shape.data[0].trims: the trim curves are ignored: the whole "
                                 "untrimmed surface is read"});
  // Control point (i, j) is entry i·size_v + j: (1, 1) is the last, the corner (u, v) = (1, 1).
  CHECK(nurbs::evaluate(s, 1, 1) == Point(Eigen::Vector3d(1, 1, 1)));
  CHECK(nurbs::evaluate(s, 0, 1) == Point(Eigen::Vector3d(0, 1, 0)));

  CHECK_THAT(shape_error_of(R"({"shape": {"type": "volume", "data": []}})"),
             Catch::Contains("shape.type: a volume: read it as one"));
  CHECK_THAT(shape_error_of(R"({"shape": {"type": "curve", "data": []}})"),
             Catch::Contains("shape.data: no curve"));
  CHECK_THAT(shape_error_of(geomdl_curves(kLine, R"("count": 3, )")),
             Catch::Contains("shape.count: 3, but shape.data holds 1"));
  CHECK_THAT(
      shape_error_of(geomdl_curves(
          R"({"degree": 1, "knotvector": [0, 0, 1], "control_points": {"points": [[0, 0], [2, 4]]}})")),
      Catch::Contains("shape.data[0].knotvector: 3 knots given, 2 control points of degree 1 need 4"));
  CHECK_THAT(shape_error_of(geomdl_curves(
                 R"({"degree": 1, "knotvector": [0, 0, 1, 1], "control_points": {"points": [[0, 0], [2, 4]],
                     "weights": [1, -1]}})")),
             Catch::Contains("shape.data[0].control_points.weights[1]: weight -1"));
  CHECK_THAT(shape_error_of(geomdl_curves(
                 R"({"degree": 1, "knotvector": [0, 0, 1, 1], "control_points": {"points": [[0, 0], [2, 4]]},
                     "dimension": 3})")),
             Catch::Contains("shape.data[0].dimension: 3, but the control points have 2 coordinates"));
  CHECK_THAT(shape_error_of(geomdl_curves(
                 R"({"degree": 1, "knotvector": [0, 0, 1, 1], "control_points": {"points": [[0, 0], [2, 4]]},
                     "knots": [0, 1]})")),
             Catch::Contains("shape.data[0].knots: unknown member"));
  CHECK_THAT(shape_error_of(geomdl_curves(R"({"type": "freeform", "points": [[0, 0]]})")),
             Catch::Contains("shape.data[0].type: 'freeform': only \"spline\" entries are read"));
  CHECK_THAT(shape_error_of(R"({"shape": {"type": "surface", "data": [{"degree_u": 1, "degree_v": 1,
      "knotvector_u": [0, 0, 1, 1], "knotvector_v": [0, 0, 1, 1], "size_u": 2, "size_v": 3,
      "control_points": {"points": [[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 1]]}}]}})"),
             Catch::Contains("shape.data[0].control_points.points: 4 points, size_u × size_v = 2 × 3"));
  CHECK_THAT(shape_error_of(R"({"shape": {"type": "surface", "data": [{"degree_u": 1, "degree_v": 1,
      "knotvector_u": [0, 0, 1, 1], "knotvector_v": [0, 2, 1, 1], "size_u": 2, "size_v": 2,
      "control_points": {"points": [[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 1]]}}]}})"),
             Catch::Contains("shape.data[0].knotvector_v[2]: 1 is less than the previous knot 2"));
  CHECK_THAT(shape_error_of(R"({"shape": {"type": "curve", "data": [], "extra": 1}})"),
             Catch::Contains("shape.extra: unknown member"));
}

namespace {

/// A geomdl 5.x export rewritten in 6.x's layout, as geomdl 6's export_dict_crv/_surf write it: every
/// per-direction member a list, surface points and weights with u varying fastest (i + size_u·j).
nlohmann::json geomdl6_of(const nlohmann::json& v5) {
  nlohmann::json v6 = v5;
  for (auto& e : v6["shape"]["data"]) {
    if (e.contains("degree")) {  // a curve
      e["degree"] = {e["degree"]};
      e["knotvector"] = {e["knotvector"]};
      e["size"] = {e["control_points"]["points"].size()};
    } else {
      const std::size_t nu = e["size_u"], nv = e["size_v"];
      e["degree"] = {e["degree_u"], e["degree_v"]};
      e["knotvector"] = {e["knotvector_u"], e["knotvector_v"]};
      e["size"] = {nu, nv};
      for (const char* key : {"degree_u", "degree_v", "knotvector_u", "knotvector_v", "size_u", "size_v"})
        e.erase(key);
      for (const char* key : {"points", "weights"}) {
        if (!e["control_points"].contains(key)) continue;
        const nlohmann::json v_fastest = e["control_points"][key];
        nlohmann::json u_fastest = v_fastest;
        for (std::size_t i = 0; i < nu; ++i)
          for (std::size_t j = 0; j < nv; ++j) u_fastest[i + nu * j] = v_fastest[i * nv + j];
        e["control_points"][key] = u_fastest;
      }
    }
    if (e.contains("delta")) e["delta"] = {e["delta"]};
  }
  return v6;
}

}  // namespace

TEST_CASE("geomdl 6.x JSON exports: lists per direction, u varying fastest, the same shapes as 5.x",
          "[io][json]") {
  for (const char* name : {"geomdl_curve.json", "geomdl_surface.json"}) {
    INFO(name);
    const std::string path = std::string(CIFS_SOURCE_DIR "/examples/shapes/") + name;
    const nlohmann::json v6 = geomdl6_of(nlohmann::json::parse(read_file(path)));
    const io::Shape a = io::read_shape(path), b = io::parse_shape_json(v6.dump(), "v6.json");
    CHECK(io::to_json(a) == io::to_json(b));  // degree, knots, points and weights, all equal
  }
  // A surface whose two directions differ in size: the ordering shows.
  const std::string grid = R"({"shape": {"type": "surface", "count": 1, "data": [{"type": "spline",
      "rational": false, "dimension": 3, "degree": [1, 2], "knotvector": [[0, 0, 1, 1], [0, 0, 0, 1, 1, 1]],
      "size": [2, 3], "delta": [0.1, 0.1],
      "control_points": {"points": [[0, 0, 0], [1, 0, 0], [0, 1, 5], [1, 1, 5], [0, 2, 0], [1, 2, 9]]}}]}})";
  const auto s = std::get<nurbs::Surface>(io::parse_shape_json(grid, "g6.json"));
  CHECK(s.count == std::array<Eigen::Index, 2>{2, 3});
  CHECK(nurbs::evaluate(s, 1, 1) == Point(Eigen::Vector3d(1, 2, 9)));  // (i, j) = (1, 2): entry 1 + 2·2
  CHECK(nurbs::evaluate(s, 1, 0) == Point(Eigen::Vector3d(1, 0, 0)));  // (1, 0): entry 1
  CHECK(nurbs::evaluate(s, 0, 1) == Point(Eigen::Vector3d(0, 2, 0)));  // (0, 2): entry 4
  CHECK_THAT(
      shape_error_of(R"({"shape": {"type": "curve", "data": [{"degree": [1, 1], "knotvector": [[0, 0, 1, 1]],
      "size": [2], "control_points": {"points": [[0, 0], [2, 4]]}}]}})"),
      Catch::Contains("shape.data[0].degree: 2 entries, expected 1 (one per parametric direction)"));
  CHECK_THAT(
      shape_error_of(R"({"shape": {"type": "curve", "data": [{"degree": [1], "knotvector": [[0, 0, 1, 1]],
      "size": [3], "control_points": {"points": [[0, 0], [2, 4]]}}]}})"),
      Catch::Contains("shape.data[0].size[0]: 3, but control_points.points holds 2 points"));
  CHECK_THAT(
      shape_error_of(R"({"shape": {"type": "curve", "data": [{"degree": [1], "knotvector": [[0, 0, 1]],
      "size": [2], "control_points": {"points": [[0, 0], [2, 4]]}}]}})"),
      Catch::Contains("shape.data[0].knotvector[0]: 3 knots given, 2 control points of degree 1 need 4"));
  CHECK_THAT(shape_error_of(R"({"shape": {"type": "surface", "data": [{"degree": [1, 1],
      "knotvector": [[0, 0, 1, 1], [0, 0, 1]], "size": [2, 2],
      "control_points": {"points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1]]}}]}})"),
             Catch::Contains("shape.data[0].knotvector[1]:"));
}
