// SPDX-License-Identifier: MIT
// Volume files: the native layout (points[i][j][k]) read against a trilinear volume written by hand,
// geomdl 5.x and 6.x point orders against the same, the round trip bit for bit, and the refusals naming the
// JSON path.
#include <catch2/catch.hpp>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/io/json.hpp"

using namespace cifs;
using Catch::Matchers::Contains;

namespace {

std::string volume_error_of(const std::string& text) {
  try {
    io::parse_volume_json(text, "v.json");
  } catch (const InvalidInput& e) {
    return e.what();
  } catch (const IoError& e) {
    return e.what();
  }
  return "no error";
}

/// The trilinear (degree 1) volume on 2 × 3 × 2 points (i, 2j, 3k)/…: V(u, v, w) = (u, 2v, 3w) on [0, 1]³.
constexpr int kNu = 2, kNv = 3, kNw = 2;
std::string json_point(int i, int j, int k) {
  return "[" + std::to_string(i) + "," + std::to_string(j) + "," + std::to_string(3 * k) + "]";
}

void check_trilinear(const nurbs::Volume& v) {
  REQUIRE(v.count == std::array<Eigen::Index, 3>{kNu, kNv, kNw});
  for (double u : {0.0, 0.25, 1.0})
    for (double s : {0.0, 0.5, 0.75, 1.0})
      for (double w : {0.0, 0.5, 1.0}) {
        Point expected(3);
        expected << u, 2 * s, 3 * w;
        CHECK((nurbs::evaluate(v, u, s, w) - expected).norm() <= 1e-15);
      }
}

/// A geomdl entry of the trilinear volume, its points listed in `index` order (index(i, j, k) → position).
template <class Index>
std::string geomdl_points(Index&& index) {
  std::vector<std::string> points(kNu * kNv * kNw);
  for (int i = 0; i < kNu; ++i)
    for (int j = 0; j < kNv; ++j)
      for (int k = 0; k < kNw; ++k) points[static_cast<std::size_t>(index(i, j, k))] = json_point(i, j, k);
  std::string out = "[";
  for (std::size_t p = 0; p < points.size(); ++p) out += (p ? "," : "") + points[p];
  return out + "]";
}

}  // namespace

TEST_CASE("JSON volumes: points[i][j][k] is control point (i, j, k)", "[io][json][volume]") {
  std::string points = "[";
  for (int i = 0; i < kNu; ++i) {
    points += i ? ",[" : "[";
    for (int j = 0; j < kNv; ++j) {
      points += j ? ",[" : "[";
      for (int k = 0; k < kNw; ++k) points += (k ? "," : "") + json_point(i, j, k);
      points += "]";
    }
    points += "]";
  }
  points += "]";
  const std::string text =
      R"({"volume": {"degree": [1, 1, 1], "knots": [[0, 0, 1, 1], [0, 0, 0.5, 1, 1], [0, 0, 1, 1]],
    "points": )" +
      points + "}}";
  check_trilinear(io::parse_volume_json(text, "v.json"));
  CHECK(io::is_volume_json(text));
  // The Rhino convention (n + d − 1 knots) as for surfaces.
  const std::string rhino = R"({"volume": {"degree": [1, 1, 1], "knots": [[0, 1], [0, 0.5, 1], [0, 1]],
    "points": )" + points + "}}";
  check_trilinear(io::parse_volume_json(rhino, "v.json"));
}

TEST_CASE("geomdl volumes: 5.x lists v fastest then u then w, 6.x u fastest", "[io][json][volume]") {
  const std::string v5 =
      R"({"shape": {"type": "volume", "count": 1, "data": [{"type": "spline", "degree_u": 1,
    "degree_v": 1, "degree_w": 1, "knotvector_u": [0, 0, 1, 1], "knotvector_v": [0, 0, 0.5, 1, 1],
    "knotvector_w": [0, 0, 1, 1], "size_u": 2, "size_v": 3, "size_w": 2, "control_points": {"points": )" +
      geomdl_points([](int i, int j, int k) { return j + kNv * (i + kNu * k); }) + "}}]}}";
  check_trilinear(io::parse_volume_json(v5, "v.json"));
  CHECK(io::is_volume_json(v5));
  const std::string v6 =
      R"({"shape": {"type": "volume", "data": [{"degree": [1, 1, 1], "knotvector": [[0, 0, 1, 1],
    [0, 0, 0.5, 1, 1], [0, 0, 1, 1]], "size": [2, 3, 2], "control_points": {"points": )" +
      geomdl_points([](int i, int j, int k) { return i + kNu * (j + kNv * k); }) + "}}]}}";
  check_trilinear(io::parse_volume_json(v6, "v.json"));
  // The shape readers point to the volume reader.
  CHECK_THROWS_WITH(io::parse_shape_json(v6, "v.json"), Contains("shape.type: a volume: read it as one"));
  CHECK_THROWS_WITH(io::parse_shape_json(R"({"volume": {}})", "v.json"),
                    Contains("v.json: a volume: read it as one"));
  CHECK(!io::is_volume_json(R"({"surface": {}})"));
  CHECK(!io::is_volume_json("{"));
}

TEST_CASE("JSON volumes round-trip bit for bit", "[io][json][volume]") {
  const nurbs::Knots u{0, 0, 0, 0.3, 1, 1, 1}, v{-1, -1, 2, 2}, w{0, 0, 0.1, 0.7, 1, 1};
  const Eigen::Index rows = 4 * 2 * 4;
  Points P = Points::Random(rows, 3) * 1e3;
  Eigen::VectorXd weights = (Eigen::VectorXd::Random(rows).array() + 1.5).matrix();
  for (const bool rational : {false, true}) {
    const nurbs::Volume x =
        nurbs::make_volume({2, 1, 1}, {u, v, w}, {4, 2, 4}, P, rational ? weights : Eigen::VectorXd());
    const std::string text = io::to_json(x);
    const nurbs::Volume y = io::parse_volume_json(text, "v.json");
    CHECK(y.degree == x.degree);
    CHECK(y.knots == x.knots);
    CHECK(y.count == x.count);
    CHECK(y.rational == x.rational);
    // Cartesian points and weights are written: the rows come back as w·(x/w), within an ulp of x.
    REQUIRE(y.P.rows() == x.P.rows());
    CHECK((y.P - x.P).cwiseAbs().maxCoeff() <= 4e-16 * x.P.cwiseAbs().maxCoeff());
    CHECK(io::to_json(y) == text);  // and the text again, byte for byte
  }
}

TEST_CASE("JSON volume errors name the file and the path", "[io][json][volume]") {
  const std::string head =
      R"({"volume": {"degree": [1, 1, 1], "knots": [[0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1]], )";
  const std::string net = R"([[[[0], [1]], [[2], [3]]], [[[4], [5]], [[6], [7]]]])";
  CHECK(volume_error_of(head + R"("points": )" + net + "}}") == "no error");
  CHECK_THAT(volume_error_of("[]"), Contains("v.json: expected an object with one member, \"volume\""));
  CHECK_THAT(volume_error_of(R"({"volume": {"degree": [1, 1], "knots": [], "points": []}})"),
             Contains("v.json: volume.degree: expected [du, dv, dw]"));
  CHECK_THAT(volume_error_of(head + R"("points": [[[[0], [1]], [[2], [3]]], [[[4], [5]]]]}})"),
             Contains("v.json: volume.points[1]: 1 rows, the first has 2"));
  CHECK_THAT(volume_error_of(head + R"("points": [[[[0], [1]], [[2], [3]]], [[[4], [5]], [[6]]]]}})"),
             Contains("v.json: volume.points[1][1]: 1 points, the first has 2"));
  CHECK_THAT(volume_error_of(head + R"("points": [[[[0], [1]], [[2], [3]]], [[[4], [5]], [[6], [7, 1]]]]}})"),
             Contains("v.json: volume.points[1][1][1]: 2 coordinates, the first point has 1"));
  CHECK_THAT(
      volume_error_of(head + R"("points": )" + net + R"(, "weights": [[[1, 1], [1, 1]], [[1, 1], [1]]]}})"),
      Contains("v.json: volume.weights[1][1]: 1 weights, the net has 2"));
  CHECK_THAT(volume_error_of(head + R"("points": )" + net +
                             R"(, "weights": [[[1, 1], [1, 1]], [[1, 1], [1, 0]]]}})"),
             Contains("v.json: volume.weights[7]: weight 0"));
  CHECK_THAT(
      volume_error_of(
          R"({"volume": {"degree": [1, 1, 1], "knots": [[0, 0, 1, 1], [0, 0, 1, 1], [0, 1, 0, 1]], "points": )" +
          net + "}}"),
      Contains("v.json: volume.knots[2]"));
  CHECK_THAT(volume_error_of(R"({"shape": {"type": "surface", "data": []}})"),
             Contains("v.json: shape.type: 'surface': expected \"volume\""));
  CHECK_THAT(
      volume_error_of(
          R"({"shape": {"type": "volume", "data": [{"degree": [1, 1, 1], "knotvector": [[0, 0, 1, 1],
    [0, 0, 1, 1], [0, 0, 1, 1]], "size": [2, 2, 3], "control_points": {"points": [[0], [1], [2], [3], [4], [5], [6], [7]]}}]}})"),
      Contains(
          "v.json: shape.data[0].control_points.points: 8 points, size[0] × size[1] × size[2] = 2 × 2 × 3"));
}
