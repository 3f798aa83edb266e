// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"

using namespace cifs;

namespace {

io::Shape parse(const std::string& text) {
  return io::parse_shape_json(text, "s.json");
}

/// The message of the InvalidInput/IoError that parsing `text` raises.
std::string error_of(const std::string& text) {
  try {
    parse(text);
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
  const auto c = std::get<nurbs::Curve>(parse(text));
  CHECK(c.rational);
  CHECK(c.degree == 2);
  const auto back = std::get<nurbs::Curve>(parse(io::to_json(c)));
  CHECK(back.knots == c.knots);
  CHECK(back.P == c.P);  // exact: Cartesian ↔ homogeneous through the same operations
  CHECK(nurbs::cartesian_points(back) == nurbs::cartesian_points(c));
}

TEST_CASE("JSON closed curves keep their period and round-trip", "[io][json]") {
  const std::string text = R"({"curve": {"degree": 3, "closed": true, "knots": [0, 1, 2, 3.5, 4],
      "points": [[0, 0], [1, 0], [1, 1], [0, 1]]}})";
  const auto c = std::get<nurbs::Curve>(parse(text));
  CHECK(c.closed);
  CHECK(nurbs::distinct_count(c) == 4);
  CHECK(c.P.rows() == 7);
  CHECK(nurbs::defining_knots(c) == nurbs::Knots{0, 1, 2, 3.5, 4});
  const auto back = std::get<nurbs::Curve>(parse(io::to_json(c)));
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
  const auto s = std::get<nurbs::Surface>(parse(text));
  CHECK(s.count == std::array<Eigen::Index, 2>{2, 3});
  // Corner (u, v) = (1, 1) interpolates points[1][2] whatever the weights.
  const Point corner = nurbs::evaluate(s, 1, 1);
  CHECK(corner(0) == Approx(1).margin(1e-15));
  CHECK(corner(1) == Approx(2).margin(1e-15));
  CHECK(corner(2) == Approx(6).margin(1e-15));
  const auto back = std::get<nurbs::Surface>(parse(io::to_json(s)));
  CHECK(back.knots == s.knots);
  CHECK(back.P == s.P);
}

TEST_CASE("JSON errors name the file, the path and the problem", "[io][json]") {
  const std::string curve_head = R"({"curve": {"degree": 2, )";
  CHECK_THAT(error_of("{"), Catch::Contains("s.json: malformed JSON"));
  CHECK_THAT(error_of("[]"), Catch::Contains("one member, \"curve\" or \"surface\""));
  CHECK_THAT(error_of(R"({"curve": 3})"), Catch::Contains("curve: expected an object"));
  CHECK_THAT(error_of(R"({"curve": {"degree": 2, "knots": [0,0,0,1,1,1]}})"),
             Catch::Contains("curve: missing \"points\""));
  CHECK_THAT(error_of(curve_head + R"("knots": [0,0,0,1,"a",1], "points": [[0],[1],[2]]}})"),
             Catch::Contains("s.json: curve.knots[4]: expected a number"));
  CHECK_THAT(error_of(curve_head + R"("knots": [0,0,0,1,1e999,1], "points": [[0],[1],[2]]}})"),
             Catch::Contains("s.json: malformed JSON: number overflow parsing '1e999'"));
  CHECK_THAT(error_of(curve_head + R"("knots": [0,0,0,2,1,1,1], "points": [[0],[1],[2],[3]]}})"),
             Catch::Contains("s.json: curve.knots[4]: 1 is less than the previous knot 2"));
  CHECK_THAT(error_of(curve_head + R"("knots": [0,0,0,1,1], "points": [[0],[1],[2]]}})"),
             Catch::Contains("curve.knots: 5 knots given, 3 control points of degree 2 need 6"));
  CHECK_THAT(error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0,1],[1],[2,3]]}})"),
             Catch::Contains("curve.points[1]: 1 coordinates, the first point has 2"));
  CHECK_THAT(
      error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0],[1],[2]], "weights": [1,0,1]}})"),
      Catch::Contains("curve.weights[1]: weight 0 is not a positive finite number"));
  CHECK_THAT(error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0],[1],[2]], "weights": [1,1]}})"),
             Catch::Contains("2 weights given for 3"));
  CHECK_THAT(
      error_of(curve_head + R"("knots": [0,0,0,1,1,1], "points": [[0],[1],[2]], "weigths": [1,1,1]}})"),
      Catch::Contains("curve.weigths: unknown member"));
  CHECK_THAT(error_of(R"({"curve": {"degree": 0, "knots": [0,1], "points": [[0]]}, "curv": 1})"),
             Catch::Contains("s.json: curv: unknown member"));
  CHECK_THAT(error_of(R"({"surface": {"degree": [1, 1], "knots": [[0,0,1,1],[0,0,1,1]],
      "points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]], "closed": true}})"),
             Catch::Contains("surface.closed: unknown member"));
  CHECK_THAT(error_of(R"({"curve": {"degree": 0, "knots": [0,1], "points": [[0]]}})"),
             Catch::Contains("degree 0 is outside [1, 64]"));
  CHECK_THAT(error_of(R"({"curve": {"degree": 2.5, "knots": [0,1], "points": [[0]]}})"),
             Catch::Contains("curve.degree: expected an integer"));
  CHECK_THAT(error_of(R"({"curve": {"degree": 1, "knots": [0,0,0,1], "points": [[0],[1]]}})"),
             Catch::Contains("curve.knots[2]: knot 0 has multiplicity 3 > degree + 1 = 2"));
  CHECK_THAT(error_of(R"({"curve": {"degree": 1, "knots": [0,0,0,0], "points": [[0],[1]]}})"),
             Catch::Contains("multiplicity"));
  CHECK_THAT(error_of(R"({"curve": {"degree": 1, "knots": [0,1,1,2], "points": [[0],[1]]}})"),
             Catch::Contains("curve.knots: empty domain"));
  CHECK_THAT(
      error_of(R"({"curve": {"degree": 3, "closed": true, "knots": [0,1,2], "points": [[0],[1],[2]]}})"),
      Catch::Contains("takes 4 breakpoints"));
  CHECK_THAT(
      error_of(R"({"curve": {"degree": 3, "closed": true, "knots": [0,0,0,0], "points": [[0],[1],[2]]}})"),
      Catch::Contains("period [0, 0] is empty"));
  CHECK_THAT(
      error_of(R"({"curve": {"degree": 3, "closed": 1, "knots": [0,1,2,3], "points": [[0],[1],[2]]}})"),
      Catch::Contains("curve.closed: expected true or false"));
  const std::string surface_head = R"({"surface": {"degree": [1, 1], "knots": [[0,0,1,1],[0,0,1,1]], )";
  CHECK_THAT(error_of(surface_head + R"("points": [[[0,0],[0,1]], [[1,0]]]}})"),
             Catch::Contains("surface.points[1]: 1 points, the first row has 2"));
  CHECK_THAT(
      error_of(surface_head + R"("points": [[[0,0],[0,1]], [[1,0],[1,1]]], "weights": [[1,1],[1,-2]]}})"),
      Catch::Contains("surface.weights[1][1]: weight -2"));
  CHECK_THAT(error_of(surface_head + R"("points": [[[0,0],[0,1]], [[1,0],[1,1]]], "weights": [[1,1]]}})"),
             Catch::Contains("surface.weights: 1 rows, the net has 2"));
  CHECK_THAT(
      error_of(
          R"({"surface": {"degree": [1, 1], "knots": [[0,0,1,1],[0,1,0,1]], "points": [[[0],[0]], [[1],[1]]]}})"),
      Catch::Contains("surface.knots[1][2]: 0 is less than the previous knot 1"));
  CHECK_THAT(error_of(R"({"surface": {"degree": 1, "knots": [], "points": []}})"),
             Catch::Contains("surface.degree: expected an array"));
}

TEST_CASE("Shape files: unreadable paths and atomic writes", "[io]") {
  CHECK_THROWS_AS(io::read_shape("/nonexistent/shape.json"), IoError);
  CHECK_THROWS_WITH(io::read_shape("/nonexistent/shape.json"),
                    Catch::Contains("/nonexistent/shape.json: cannot open"));
  CHECK_THROWS_WITH(io::read_shape("/tmp"), Catch::Contains("/tmp: is a directory"));
  const auto dir = std::filesystem::temp_directory_path() / "cifs_test_io";
  std::filesystem::create_directories(dir);
  write_file_atomically(dir / "a.txt", "hello");
  CHECK(read_file(dir / "a.txt") == "hello");
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    CHECK(entry.path().filename() == "a.txt");  // no temporary left behind
  CHECK_THROWS_AS(write_file_atomically(dir / "missing" / "b.txt", "x"), IoError);
  std::filesystem::remove_all(dir);
}
