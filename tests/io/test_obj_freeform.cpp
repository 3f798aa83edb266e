// SPDX-License-Identifier: MIT

#include <bit>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <random>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/nurbs/refine.hpp"
#include "support/scratch.hpp"

namespace {

using namespace cifs;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

/// Same size and the same bits in every entry (so 0 and -0 differ, NaN equals itself).
bool same_bits(const Points& a, const Points& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j)
      if (std::bit_cast<std::uint64_t>(a(i, j)) != std::bit_cast<std::uint64_t>(b(i, j))) return false;
  return true;
}

bool same_bits(const nurbs::Knots& a, const nurbs::Knots& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<std::uint64_t>(a[i]) != std::bit_cast<std::uint64_t>(b[i])) return false;
  return true;
}

/// `rows by dim` coordinates with full mantissas, from a fixed seed.
Points obj_random_points(Eigen::Index rows, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(-10, 10);
  Points P(rows, dim);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (int j = 0; j < dim; ++j) P(i, j) = coord(rng);
  return P;
}

Eigen::VectorXd obj_random_weights(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> weight(0.1, 7);
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) w(i) = weight(rng);
  return w;
}

nurbs::Curve sample_curve(bool rational, int dim = 3, unsigned seed = 1) {
  const nurbs::Knots knots{0, 0, 0, 0, 0.1, 0.3, 1.0 / 3.0, 0.7, 1, 1, 1, 1};
  const Points P = obj_random_points(8, dim, seed);
  return nurbs::make_curve(3, knots, P, rational ? obj_random_weights(8, seed + 100) : Eigen::VectorXd());
}

nurbs::Surface sample_surface(bool rational, unsigned seed = 2) {
  // nu = 5 (degree 2), nv = 4 (degree 3): a transposed net would not even have the right count.
  const std::array<nurbs::Knots, 2> knots{nurbs::Knots{0, 0, 0, 0.25, 0.6, 1, 1, 1},
                                          nurbs::Knots{-1, -1, -1, -1, 2, 2, 2, 2}};
  const Points P = obj_random_points(20, 3, seed);
  return nurbs::make_surface({2, 3}, knots, {5, 4}, P,
                             rational ? obj_random_weights(20, seed + 100) : Eigen::VectorXd());
}

template <class T>
T only(const std::vector<io::Shape>& shapes) {
  REQUIRE(shapes.size() == 1);
  REQUIRE(std::holds_alternative<T>(shapes[0]));
  return std::get<T>(shapes[0]);
}

void require_same_shape(const nurbs::Curve& a, const nurbs::Curve& b) {
  CHECK(a.degree == b.degree);
  CHECK(a.rational == b.rational);
  CHECK(a.closed == b.closed);
  CHECK(same_bits(a.knots, b.knots));
  CHECK(same_bits(a.P, b.P));
}

void require_same_shape(const nurbs::Surface& a, const nurbs::Surface& b) {
  CHECK(a.degree == b.degree);
  CHECK(a.count == b.count);
  CHECK(a.rational == b.rational);
  CHECK(same_bits(a.knots[0], b.knots[0]));
  CHECK(same_bits(a.knots[1], b.knots[1]));
  CHECK(same_bits(a.P, b.P));
}

const std::string kVertices = "v 0 0 0\nv 1 2 0\nv 3 2 1\nv 4 0 0\n";  // lines 1-4
const std::string kCurveObj = kVertices +
                              "cstype bspline\n"        // 5
                              "deg 2\n"                 // 6
                              "curv 0 2 1 2 3 4\n"      // 7
                              "parm u 0 0 0 1 2 2 2\n"  // 8
                              "end\n";                  // 9

}  // namespace

TEST_CASE("OBJ round trip: B-spline curve", "[obj]") {
  const nurbs::Curve c = sample_curve(false);
  const std::string text = io::to_obj(c);
  require_same_shape(only<nurbs::Curve>(io::parse_obj(text, "c.obj")), c);
  CHECK_THAT(text, Contains("cstype bspline\n"));
  CHECK_THAT(text, Contains("deg 3\n"));
  CHECK_THAT(text, Contains("curv 0 1 1 2 3 4 5 6 7 8\n"));
  CHECK_THAT(text, Contains("parm u 0 0 0 0 0.10000000000000001 0.29999999999999999 \\\n"));  // %.17g
  CHECK_THAT(text, Contains("end\n"));
}

TEST_CASE("OBJ round trip: rational curve", "[obj]") {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const nurbs::Curve c = sample_curve(true, 3, seed);
    const std::string text = io::to_obj(c);
    CHECK_THAT(text, Contains("cstype rat bspline\n"));
    require_same_shape(only<nurbs::Curve>(io::parse_obj(text, "c.obj")), c);
  }
}

TEST_CASE("OBJ round trip: rational curve after knot insertion stays within an ulp", "[obj]") {
  // Homogeneous rows computed by refinement need not be w·x for any double x; the writer then
  // picks the nearest Cartesian value, and the weights still come back exactly.
  const nurbs::Curve c = nurbs::refine_midpoints(sample_curve(true, 3, 7));
  const auto back = only<nurbs::Curve>(io::parse_obj(io::to_obj(c), "c.obj"));
  REQUIRE(back.P.rows() == c.P.rows());
  CHECK(same_bits(back.knots, c.knots));
  CHECK(back.P.col(3) == c.P.col(3));
  for (Eigen::Index i = 0; i < c.P.rows(); ++i)
    for (Eigen::Index k = 0; k < 3; ++k)
      CHECK(std::abs(back.P(i, k) - c.P(i, k)) <=
            2 * std::numeric_limits<double>::epsilon() * std::abs(c.P(i, k)));
}

TEST_CASE("OBJ round trip: surface", "[obj]") {
  const nurbs::Surface s = sample_surface(false);
  const std::string text = io::to_obj(s);
  CHECK_THAT(text, Contains("deg 2 3\n"));
  CHECK_THAT(text, Contains("surf 0 1 -1 2 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 \\\n 17 18 19 20\n"));
  require_same_shape(only<nurbs::Surface>(io::parse_obj(text, "s.obj")), s);
}

TEST_CASE("OBJ round trip: rational surface", "[obj]") {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const nurbs::Surface s = sample_surface(true, seed);
    require_same_shape(only<nurbs::Surface>(io::parse_obj(io::to_obj(s), "s.obj")), s);
  }
}

TEST_CASE("OBJ round trip: 2-D curve is padded with z = 0", "[obj]") {
  for (const bool rational : {false, true}) {
    const nurbs::Curve c = sample_curve(rational, 2);
    const auto back = only<nurbs::Curve>(io::parse_obj(io::to_obj(c), "c.obj"));
    REQUIRE(nurbs::dimension(back) == 3);
    CHECK(same_bits(back.knots, c.knots));
    CHECK(same_bits(back.P.leftCols(2), c.P.leftCols(2)));
    CHECK(back.P.col(2).isZero(0));
    if (rational) CHECK(same_bits(back.P.col(3), c.P.col(2)));
  }
  const nurbs::Curve line = nurbs::make_curve(1, {0, 0, 1, 1}, (Points(2, 1) << 2, 5).finished());
  CHECK_THAT(io::to_obj(line), Contains("v 2 0 0\nv 5 0 0\n"));
}

TEST_CASE("OBJ writes a closed curve as its expanded unclamped curve", "[obj]") {
  const Points P = obj_random_points(5, 3, 11);
  const nurbs::Curve c = nurbs::make_closed_curve(3, {0, 1, 2, 3, 4, 5}, P, obj_random_weights(5, 12));
  const std::string text = io::to_obj(c);
  CHECK_THAT(text, Contains("# closed curve"));
  const auto back = only<nurbs::Curve>(io::parse_obj(text, "c.obj"));
  CHECK_FALSE(back.closed);
  CHECK(same_bits(back.knots, c.knots));
  CHECK(same_bits(back.P, c.P));
  CHECK(nurbs::domain(back).start == 0);
  CHECK(nurbs::domain(back).end == 5);
  for (const double u : {0.0, 0.7, 2.5, 5.0})
    CHECK((nurbs::evaluate(back, u) - nurbs::evaluate(c, u)).norm() <= 1e-12);
}

TEST_CASE("OBJ round trip: unclamped open curve writes its domain as the range", "[obj]") {
  const nurbs::Curve c = nurbs::make_curve(2, {0, 1, 2, 3, 4, 5, 6}, obj_random_points(4, 3, 5));
  const std::string text = io::to_obj(c);
  CHECK_THAT(text, Contains("curv 2 4 1 2 3 4\n"));
  require_same_shape(only<nurbs::Curve>(io::parse_obj(text, "c.obj")), c);
}

TEST_CASE("OBJ writing refuses more than three dimensions", "[obj]") {
  CHECK_THROWS_AS(io::to_obj(sample_curve(false, 4)), InvalidInput);
  CHECK_THROWS_WITH(io::to_obj(sample_curve(true, 4)), Contains("4-D"));
  const nurbs::Surface s = nurbs::make_surface({1, 1}, {nurbs::Knots{0, 0, 1, 1}, nurbs::Knots{0, 0, 1, 1}},
                                               {2, 2}, obj_random_points(4, 5, 3));
  CHECK_THROWS_AS(io::to_obj(s), InvalidInput);
}

TEST_CASE("OBJ surface control points are listed with u varying fastest", "[obj]") {
  // Point (i, j) = (10 i + 1, 100 j + 2, i + 7 j): nu = 3 along u, nv = 2 along v.
  const std::string text =
      "v 1 2 0\n"     // (0, 0)
      "v 11 2 1\n"    // (1, 0)
      "v 21 2 2\n"    // (2, 0)
      "v 1 102 7\n"   // (0, 1)
      "v 11 102 8\n"  // (1, 1)
      "v 21 102 9\n"  // (2, 1)
      "cstype bspline\n"
      "deg 1 1\n"
      "surf 0 1 0 1 1 2 3 4 5 6\n"
      "parm u 0 0 0.5 1 1\n"
      "parm v 0 0 1 1\n"
      "end\n";
  const auto s = only<nurbs::Surface>(io::parse_obj(text, "s.obj"));
  REQUIRE(s.count == std::array<Eigen::Index, 2>{3, 2});
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j) {
      const Eigen::RowVector3d expected(10.0 * i + 1, 100.0 * j + 2, i + 7.0 * j);
      CHECK(s.P.row(i * 2 + j) == expected);
    }
  CHECK(nurbs::evaluate(s, 0, 1) == Eigen::RowVector3d(1, 102, 7));     // S(u0, v1): the corner (0, nv-1)
  CHECK(nurbs::evaluate(s, 1, 0) == Eigen::RowVector3d(21, 2, 2));      // S(u1, v0): the corner (nu-1, 0)
  CHECK(nurbs::evaluate(s, 0.5, 1) == Eigen::RowVector3d(11, 102, 8));  // the knot u = 0.5 sits on i = 1
  CHECK(nurbs::evaluate(s, 0.25, 0.5) == Eigen::RowVector3d(6, 52, 4));
}

TEST_CASE("OBJ relative (negative) vertex indices", "[obj]") {
  const std::string text = kVertices +
                           "cstype bspline\n"
                           "deg 2\n"
                           "curv 0 2 -4 -3 -2 -1\n"
                           "parm u 0 0 0 1 2 2 2\n"
                           "end\n"
                           "v 10 0 0\nv 11 1 0\nv 12 0 1\nv 13 1 1\n"
                           "curv 0 2 -4 -3 -2 -1\n"  // vertices 5..8
                           "parm u 0 0 0 1 2 2 2\n"
                           "end\n"
                           "curv 0 2 1 -7 +3 -1\n"  // vertices 1, 2, 3, 8
                           "parm u 0 0 0 1 2 2 2\n"
                           "end\n";
  const auto shapes = io::parse_obj(text, "r.obj");
  REQUIRE(shapes.size() == 3);
  const auto absolute = only<nurbs::Curve>(io::parse_obj(kCurveObj, "a.obj"));
  require_same_shape(std::get<nurbs::Curve>(shapes[0]), absolute);
  const Points second = (Points(4, 3) << 10, 0, 0, 11, 1, 0, 12, 0, 1, 13, 1, 1).finished();
  CHECK(std::get<nurbs::Curve>(shapes[1]).P == second);
  const Points third = (Points(4, 3) << 0, 0, 0, 1, 2, 0, 3, 2, 1, 13, 1, 1).finished();
  CHECK(std::get<nurbs::Curve>(shapes[2]).P == third);
}

TEST_CASE("OBJ comments, continuation lines, blank lines and ignored statements", "[obj]") {
  const std::string text =
      "\xEF\xBB\xBF# exported by hand\r\n"
      "mtllib scene.mtl\r\n"
      "o thing\n"
      "\n"
      "v 0 0 0   # first\n"
      "v\t1 2 0\n"
      "   \n"
      "v 3 \\\n"
      "  2 1\n"
      "v 4 0 0 0.5 # w is ignored by a non-rational curve\n"
      "vt 0 0\nvn 0 0 1\nvp 0.5 0.5\n"
      "g group\nusemtl red\ns 1\n"
      "f 1 2 3\nl 1 2\np 1\n"
      "bmat u 1 0 0 1\nstep 1 1\nctech cparm 1\nstech cparma 1 1\n"
      "cstype bspline\n"
      "deg 2\n"
      "curv 0 2 1 2 \\\n"
      "   3 4   # comment after the continued part\n"
      "parm u 0 0 0 \\\n"
      "1 2 2 2\n"
      "sp 1\n"
      "scrv 0 1 1 0 1\n"
      "end\n"
      "curv2 1 2 3\n"
      "parm u 0 0 1 1\n"
      "end\n"
      "con 1 0 1 1 2 0 1 1\n";
  const auto c = only<nurbs::Curve>(io::parse_obj(text, "c.obj"));
  require_same_shape(c, only<nurbs::Curve>(io::parse_obj(kCurveObj, "a.obj")));
  CHECK(io::parse_obj("", "e.obj").empty());
  CHECK(io::parse_obj("# nothing\n\nv 1 2 3\nf 1 1 1\n", "e.obj").empty());
  CHECK(io::parse_obj(kCurveObj.substr(0, kCurveObj.size() - 1) + " \\", "e.obj").size() ==
        1);  // "end \" at EOF
}

TEST_CASE("OBJ cstype and deg carry over to later elements", "[obj]") {
  const std::string text = kCurveObj +
                           "curv 0 2 4 3 2 1\n"
                           "parm u 0 0 0 1 2 2 2\n"
                           "end\n"
                           "deg 1 1\n"
                           "surf 0 1 0 1 1 2 3 4\n"
                           "parm u 0 0 1 1\n"
                           "parm v 0 0 1 1\n"
                           "end\n";
  const auto shapes = io::parse_obj(text, "m.obj");
  REQUIRE(shapes.size() == 3);
  CHECK(std::get<nurbs::Curve>(shapes[1]).degree == 2);
  CHECK(std::get<nurbs::Curve>(shapes[1]).P.row(0) == Eigen::RowVector3d(4, 0, 0));
  const auto& s = std::get<nurbs::Surface>(shapes[2]);
  CHECK(s.degree == std::array<int, 2>{1, 1});
  CHECK(s.P.row(1) == Eigen::RowVector3d(3, 2, 1));  // (i, j) = (0, 1) is vertex 3
}

TEST_CASE("OBJ weights: rat bspline reads w, bspline ignores it", "[obj]") {
  const std::string body =
      "v 0 0 0\nv 1 1 0 2\nv 2 0 0 0.5\n"
      "deg 2\n"
      "curv 0 1 1 2 3\n"
      "parm u 0 0 0 1 1 1\n"
      "end\n";
  const auto rational = only<nurbs::Curve>(io::parse_obj("cstype rat bspline\n" + body, "w.obj"));
  CHECK(rational.rational);
  CHECK(nurbs::weights(rational) == Eigen::Vector3d(1, 2, 0.5));
  CHECK(nurbs::cartesian_points(rational).row(1) == Eigen::RowVector3d(1, 1, 0));
  const auto plain = only<nurbs::Curve>(io::parse_obj("cstype bspline\n" + body, "w.obj"));
  CHECK_FALSE(plain.rational);
  CHECK(plain.P.cols() == 3);
  // A non-rational curve ignores even a weight that would be invalid.
  CHECK_NOTHROW(io::parse_obj(
      "v 0 0 0 -1\nv 1 0 0 0\ncstype bspline\ndeg 1\ncurv 0 1 1 2\nparm u 0 0 1 1\nend\n", "w.obj"));
}

TEST_CASE("OBJ surf accepts v/vt/vn references", "[obj]") {
  const std::string text = kVertices +
                           "cstype bspline\ndeg 1 1\n"
                           "surf 0 1 0 1 1/1/1 2//2 3/3 -1/-1/-1\n"
                           "parm u 0 0 1 1\nparm v 0 0 1 1\nend\n";
  const auto s = only<nurbs::Surface>(io::parse_obj(text, "s.obj"));
  CHECK(s.P.row(3) == Eigen::RowVector3d(4, 0, 0));
}

TEST_CASE("OBJ accepts a range equal to the domain up to decimal rounding", "[obj]") {
  const std::string text = kVertices + "cstype bspline\ndeg 2\ncurv 1e-12 1.9999999999999 1 2 3 4\n" +
                           "parm u 0 0 0 1 2 2 2\nend\n";
  const auto c = only<nurbs::Curve>(io::parse_obj(text, "c.obj"));
  CHECK(nurbs::domain(c).start == 0);
  CHECK(nurbs::domain(c).end == 2);
}

namespace {

struct ErrorCase {
  const char* name;
  std::string text;
  int line;
  const char* phrase;
  bool io_error;  // IoError (syntax) or InvalidInput (content)
};

std::string curve_with(const std::string& curv, const std::string& parm = "parm u 0 0 0 1 2 2 2") {
  return kVertices + "cstype bspline\ndeg 2\n" + curv + "\n" + parm + "\nend\n";  // curv at line 7
}

std::string surface_with(const std::string& surf, const std::string& parm_u, const std::string& parm_v) {
  return kVertices + "cstype bspline\ndeg 1 1\n" + surf + "\n" + parm_u + "\n" + parm_v + "\nend\n";
}

}  // namespace

TEST_CASE("OBJ errors name the line and the problem", "[obj]") {
  const std::vector<ErrorCase> cases{
      {"non-number in v", "v 1 x 3\n", 1, "expected a number, got 'x'", true},
      {"too few numbers in v", "\nv 1 2\n", 2, "expected x y z [w]", true},
      {"NaN in v", "v nan 0 0\n", 1, "not finite", false},
      {"infinity in v", "v 0 -inf 0\n", 1, "not finite", false},
      {"huge number", "v 1e999 0 0\n", 1, "out of the range of double", false},
      {"index out of range", curve_with("curv 0 2 1 2 3 9"), 7, "vertex index 9 is out of range", false},
      {"index zero", curve_with("curv 0 2 1 0 3 4"), 7, "vertex index 0", false},
      {"relative index too far back", curve_with("curv 0 2 1 2 3 -5"), 7, "vertex index -5 is out of range",
       false},
      {"huge index", curve_with("curv 0 2 1 2 3 99999999999999999999"), 7, "expected an integer", true},
      {"non-integer index", curve_with("curv 0 2 1 2 3 1.5"), 7, "expected an integer, got '1.5'", true},
      {"v/vt on a curv", curve_with("curv 0 2 1 2 3 4/1"), 7, "expected an integer", true},
      {"bad vt in surf", surface_with("surf 0 1 0 1 1 2 3 4/x", "parm u 0 0 1 1", "parm v 0 0 1 1"), 7,
       "expected an integer, got 'x'", true},
      {"too many slashes in surf",
       surface_with("surf 0 1 0 1 1 2 3 4/1/1/1", "parm u 0 0 1 1", "parm v 0 0 1 1"), 7, "expected v/vt/vn",
       true},
      {"curv without indices", curve_with("curv 0 2"), 7, "expected curv u0 u1", true},
      {"surf without indices", surface_with("surf 0 1 0", "parm u 0 0 1 1", "parm v 0 0 1 1"), 7,
       "expected surf s0 s1 t0 t1", true},
      {"non-number range", curve_with("curv a 2 1 2 3 4"), 7, "curv range: expected a number", true},
      {"missing parm u", kVertices + "cstype bspline\ndeg 2\ncurv 0 2 1 2 3 4\nend\n", 7, "no parm u", true},
      {"missing parm v", surface_with("surf 0 1 0 1 1 2 3 4", "parm u 0 0 1 1", ""), 7, "no parm v", true},
      {"missing end", kVertices + "cstype bspline\ndeg 2\ncurv 0 2 1 2 3 4\nparm u 0 0 0 1 2 2 2\n", 7,
       "no end", true},
      {"element before end", kVertices + "cstype bspline\ndeg 2\ncurv 0 2 1 2 3 4\ncurv 0 2 1 2 3 4\n", 8,
       "missing end", true},
      {"end without element", "v 0 0 0\nend\n", 2, "end without a curv or surf", true},
      {"end with arguments", curve_with("curv 0 2 1 2 3 4", "parm u 0 0 0 1 2 2 2\nend x"), 9,
       "end: unexpected", true},
      {"parm outside a body", "parm u 0 1\n", 1, "parm outside a curv or surf body", true},
      {"parm without values", curve_with("curv 0 2 1 2 3 4", "parm u"), 8, "expected parm u|v", true},
      {"parm direction", curve_with("curv 0 2 1 2 3 4", "parm w 0 0 0 1 2 2 2"), 8, "must be u or v", true},
      {"parm v on a curve", curve_with("curv 0 2 1 2 3 4", "parm u 0 0 0 1 2 2 2\nparm v 0 1"), 9,
       "parm v in the body of a curv", true},
      {"parm u twice", curve_with("curv 0 2 1 2 3 4", "parm u 0 0 0 1 2 2 2\nparm u 0 0 0 1 2 2 2"), 9,
       "parm u given twice (first at line 8)", true},
      {"non-finite knot", curve_with("curv 0 2 1 2 3 4", "parm u 0 0 0 nan 2 2 2"), 8,
       "parm u: 'nan' is not finite", false},
      {"cstype cardinal", kVertices + "cstype cardinal\ndeg 3\ncurv 0 1 1 2 3 4\n", 7,
       "curv: cstype cardinal (line 5) is not supported: only bspline and bezier", false},
      {"cstype rat taylor", kVertices + "cstype rat taylor\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\n", 7,
       "surf: cstype rat taylor (line 5) is not supported", false},
      {"cstype bmatrix", kVertices + "cstype bmatrix\ndeg 2\ncurv 0 2 1 2 3 4\n", 7,
       "cstype bmatrix (line 5) is not supported", false},
      {"cstype unknown", "cstype nurbs\n", 1, "unknown curve and surface type 'nurbs'", false},
      {"cstype without type", "cstype rat\n", 1, "expected cstype [rat] type", true},
      {"cstype inside a body", kVertices + "cstype bspline\ndeg 2\ncurv 0 2 1 2 3 4\ncstype bspline\n", 8,
       "cstype inside the body of the curv at line 7", true},
      {"deg inside a body", kVertices + "cstype bspline\ndeg 2\ncurv 0 2 1 2 3 4\ndeg 3\n", 8,
       "deg inside the body", true},
      {"no cstype", kVertices + "deg 2\ncurv 0 2 1 2 3 4\nparm u 0 0 0 1 2 2 2\nend\n", 6,
       "curv without a preceding cstype", true},
      {"no deg", kVertices + "cstype bspline\ncurv 0 2 1 2 3 4\nparm u 0 0 0 1 2 2 2\nend\n", 6,
       "curv without a preceding deg", true},
      {"deg 0", "deg 0\n", 1, "degree 0 is outside [1, 64]", false},
      {"deg too large", "deg 3 65\n", 1, "degree 65 is outside [1, 64]", false},
      {"deg huge", "deg 99999999999999999999\n", 1, "expected an integer", true},
      {"deg not an integer", "deg 2.5\n", 1, "expected an integer, got '2.5'", true},
      {"deg without value", "deg\n", 1, "expected deg du [dv]", true},
      {"surf with one degree", kVertices + "cstype bspline\ndeg 1\nsurf 0 1 0 1 1 2 3 4\n", 7,
       "surf needs deg du dv; the deg at line 6", true},
      {"knot count", curve_with("curv 0 2 1 2 3 4", "parm u 0 0 0 1 2 2"), 8,
       "parm u: knots: 6 knots given, 4 control points of degree 2 need 7", false},
      {"decreasing knots", curve_with("curv 0 2 1 2 3 4", "parm u 0 0 0 3 2 2 2"), 8,
       "parm u: knots[4]: 2 is less than the previous knot 3", false},
      {"too few control points", curve_with("curv 0 1 1 2", "parm u 0 0 0 1 1"), 7, "too few for degree 2",
       false},
      {"range beside the domain", curve_with("curv 2 3 1 2 3 4"), 7,
       "curv: parameter range u [2, 3] does not overlap the knot domain [0, 2]", false},
      {"range before the domain", curve_with("curv -2 -1e-12 1 2 3 4"), 7, "does not overlap", false},
      {"reversed range", curve_with("curv 2 0 1 2 3 4"), 7, "is empty or reversed", false},
      {"surface range beside the domain",
       surface_with("surf 0 1 1 2 1 2 3 4", "parm u 0 0 1 1", "parm v 0 0 1 1"), 7,
       "parameter range v [1, 2] does not overlap the knot domain [0, 1]", false},
      {"Bezier curv of broken segments",
       kVertices + "cstype bezier\ndeg 2\ncurv 0 1 1 2 3 4\nparm u 0 1\nend\n", 7,
       "curv: 4 control vertices do not make whole Bezier segments of degree 2", false},
      {"Bezier parm count",
       "v 0 0 0\n" + kVertices + "cstype bezier\ndeg 2\ncurv 0 1 1 2 3 4 5\nparm u 0 1\nend\n", 9,
       "parm u: 2 values given; a Bezier curv of 2 segments needs 3", false},
      {"Bezier parm not increasing",
       "v 0 0 0\n" + kVertices + "cstype bezier\ndeg 2\ncurv 0 1 1 2 3 4 5\nparm u 0 1 1\nend\n", 9,
       "parm u: the parameter values of a Bezier curv must increase: 1 follows 1", false},
      {"Bezier surf count",
       kVertices + "cstype bezier\ndeg 1 1\nsurf 0 2 0 1 1 2 3 4\nparm u 0 1 2\nparm v 0 1\nend\n", 7,
       "surf: 4 control vertices given; parm u (3 values, degree 1) and parm v (2 values, degree 1) make a "
       "Bezier net of 3 by 2 = 6",
       false},
      {"Bezier surf one value",
       kVertices + "cstype bezier\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\nparm u 0\nparm v 0 1\nend\n", 8,
       "parm u: a Bezier surf needs at least 2 values", false},
      {"surf count", surface_with("surf 0 1 0 1 1 2 3 4", "parm u 0 0 0.5 1 1", "parm v 0 0 1 1"), 7,
       "4 control vertices given; parm u (5 knots, degree 1) and parm v (4 knots, degree 1) make a 3 by 2 "
       "net of 6",
       false},
      {"surf too few knots", surface_with("surf 0 1 0 1 1 2 3 4", "parm u 0 0 1 1", "parm v 0 1"), 9,
       "parm v: 2 knots are too few for degree 1", false},
      {"surf decreasing v knots", surface_with("surf 0 1 0 1 1 2 3 4", "parm u 0 0 1 1", "parm v 0 0 1 0.5"),
       9, "parm v: knots[3]: 0.5 is less than the previous knot 1", false},
      {"non-positive weight",
       "v 0 0 0\nv 1 2 0 -1\nv 2 0 0\ncstype rat bspline\ndeg 1\ncurv 0 2 1 2 3\n"
       "parm u 0 0 1 2 2\nend\n",
       2, "weight -1 of vertex 2 is not positive (used by the rational curv at line 6)", false},
      {"zero weight",
       "v 0 0 0\nv 1 2 0 0\nv 2 0 0\ncstype rat bspline\ndeg 1\ncurv 0 2 1 2 3\n"
       "parm u 0 0 1 2 2\nend\n",
       2, "weight 0 of vertex 2 is not positive", false},
      {"vertex with colours",
       "v 0 0 0\nv 1 2 0 1 0.5 0.5\nv 2 0 0\ncstype bspline\ndeg 1\ncurv 0 2 1 2 3\n"
       "parm u 0 0 1 2 2\nend\n",
       6, "vertex 2 (line 2) has 6 numbers", false},
      {"trim", surface_with("surf 0 1 0 1 1 2 3 4", "parm u 0 0 1 1", "parm v 0 0 1 1\ntrim 0 1 1"), 10,
       "trim: trimmed surfaces are not supported; --ignore-trim (ignore_trim) reads the whole untrimmed "
       "surface",
       false},
      {"hole", surface_with("surf 0 1 0 1 1 2 3 4", "parm u 0 0 1 1", "parm v 0 0 1 1\nhole 0 1 1"), 10,
       "hole: trimmed surfaces", false},
      {"trim outside a body", "trim 0 1 1\n", 1, "trim outside a curv or surf body", true},
      {"superseded patch", "v 0 0 0\nbsp 1 2 3 4\n", 2, "superseded", false},
      {"error in a continued statement", "v 0 0 0\nv 1 \\\n 2 \\\n y\n", 2, "got 'y'", true},
  };
  for (const ErrorCase& c : cases) {
    DYNAMIC_SECTION(c.name) {
      const std::string start = "t.obj: line " + std::to_string(c.line) + ": ";
      if (c.io_error) {
        CHECK_THROWS_AS(io::parse_obj(c.text, "t.obj"), IoError);
      } else {
        CHECK_THROWS_AS(io::parse_obj(c.text, "t.obj"), InvalidInput);
      }
      CHECK_THROWS_WITH(io::parse_obj(c.text, "t.obj"), StartsWith(start) && Contains(c.phrase));
    }
  }
}

TEST_CASE("OBJ reader never fails otherwise on truncated or mutated input", "[obj]") {
  const std::string valid =
      io::to_obj(sample_surface(true)) + io::to_obj(sample_curve(true)) + kCurveObj +
      "cstype bezier\ndeg 1 1\nsurf 0 2 0 2 1 2 3 4\nparm u 0 2\nparm v 0 2\ntrim 0 4 1\nend\n";
  const auto parse = [](const std::string& text) {
    try {
      io::parse_obj(text, "f.obj", {.ignore_trim = true, .index = {}, .warn = [](const std::string&) {}});
    } catch (const IoError&) {
    } catch (const InvalidInput&) {
    }
  };
  for (std::size_t n = 0; n <= valid.size(); n += 3) CHECK_NOTHROW(parse(valid.substr(0, n)));
  std::mt19937 rng(42);
  const std::string alphabet = " \n\\#/-+.e0123456789xnaiv";
  std::uniform_int_distribution<std::size_t> where(0, valid.size() - 1), what(0, alphabet.size() - 1);
  for (int k = 0; k < 2000; ++k) {
    std::string text = valid;
    for (int m = 0; m < 3; ++m) text[where(rng)] = alphabet[what(rng)];
    CHECK_NOTHROW(parse(text));
  }
}

TEST_CASE("read_shape reads a one-shape .obj file", "[obj]") {
  const cifs_test::ScratchDir scratch("obj");
  const auto& dir = scratch.path();
  const nurbs::Surface s = sample_surface(true, 5);
  write_file_atomically(dir / "one.obj", io::to_obj(s));
  require_same_shape(std::get<nurbs::Surface>(io::read_shape(dir / "one.obj")), s);
  write_file_atomically(dir / "two.obj", kCurveObj + kCurveObj);
  CHECK_THROWS_AS(io::read_shape(dir / "two.obj"), InvalidInput);
  CHECK_THROWS_WITH(io::read_shape(dir / "two.obj"),
                    (dir / "two.obj").string() +
                        ": holds 2 shapes (curves and surfaces): choose one with --index N, N from 0 to 1");
}

namespace {

/// Parses with ignore_trim as given, collecting the warnings.
std::vector<io::Shape> parse_warned(const std::string& text, std::vector<std::string>& warnings,
                                    bool ignore_trim = false, std::optional<std::size_t> index = {}) {
  return io::parse_obj(text, "w.obj",
                       {.ignore_trim = ignore_trim, .index = index, .warn = [&](const std::string& w) {
                          warnings.push_back(w);
                        }});
}

/// A Bezier curve point by de Casteljau's algorithm over the rows of P (homogeneous rows stay
/// homogeneous).
Eigen::RowVectorXd de_casteljau(Points P, double t) {
  for (Eigen::Index r = P.rows() - 1; r > 0; --r)
    for (Eigen::Index i = 0; i < r; ++i) P.row(i) = (1 - t) * P.row(i) + t * P.row(i + 1);
  return P.row(0);
}

}  // namespace

TEST_CASE("OBJ reads Blender's curv 0.0 1.0 over the knot domain, with one warning", "[obj]") {
  // As Blender's exporter writes a cubic NURBS curve: uniform knots i/7 printed with %.6f and the
  // range 0 1 whatever the knots, relative vertex indices.
  const std::string text =
      "o NurbsCurve\nv -1 0 0\nv -0.5 0.5 0\nv 0.5 0.5 0\nv 1 0 0\ng NurbsCurve\n"
      "cstype bspline\ndeg 3\ncurv 0.0 1.0 -4 -3 -2 -1\n"
      "parm u 0.000000 0.142857 0.285714 0.428571 0.571429 0.714286 0.857143 1.000000\nend\n";
  std::vector<std::string> warnings;
  const auto c = only<nurbs::Curve>(parse_warned(text, warnings));
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0] ==
        "w.obj: line 9: curv: parameter range u [0, 1] reaches outside the knot domain [0.428571, 0.571429]: "
        "read over [0.428571, 0.571429]");
  // The curve of the file's own knots and points, untouched.
  CHECK(c.knots == nurbs::Knots{0, 0.142857, 0.285714, 0.428571, 0.571429, 0.714286, 0.857143, 1});
  CHECK(c.P.row(1) == Eigen::RowVector3d(-0.5, 0.5, 0));
  CHECK(nurbs::domain(c).start == 0.428571);
  CHECK(nurbs::domain(c).end == 0.571429);
  // Almost uniform knots: one uniform cubic B-spline segment, (P0 + 4 P1 + P2)/6 at its start.
  const Point start = nurbs::evaluate(c, 0.428571);
  CHECK(start(0) == Approx((-1 + 4 * -0.5 + 0.5) / 6).margin(1e-5));
  CHECK(start(1) == Approx((0 + 4 * 0.5 + 0.5) / 6).margin(1e-5));
  // The default warning goes to stderr, and a file whose range is the domain gives none.
  warnings.clear();
  parse_warned(kCurveObj, warnings);
  CHECK(warnings.empty());
}

TEST_CASE("OBJ range inside the knot domain reads that part of the curve", "[obj]") {
  for (const bool rational : {false, true}) {
    const nurbs::Curve full = sample_curve(rational, 3, 9);
    // An unclamped curve too: a part of a part.
    for (const auto& [a, b] :
         std::vector<std::pair<double, double>>{{0.2, 0.8}, {0.3, 1}, {0, 0.31}, {0.05, 0.1}}) {
      std::string text = io::to_obj(full);
      const std::string range = "curv 0 1 ";
      const auto at = text.find(range);
      REQUIRE(at != std::string::npos);
      text.replace(at, range.size(), "curv " + std::to_string(a) + " " + std::to_string(b) + " ");
      std::vector<std::string> warnings;
      const auto part = only<nurbs::Curve>(parse_warned(text, warnings));
      CHECK(warnings.empty());
      CHECK(part.rational == rational);
      CHECK(nurbs::domain(part).start == a);
      CHECK(nurbs::domain(part).end == b);
      // The same points as the whole curve over [a, b] (Cox–de Boor on the file's knots).
      for (const double u : nurbs::uniform_parameters({a, b}, 101)) {
        const Point p = nurbs::evaluate_basis(full, u), q = nurbs::evaluate(part, u);
        CHECK((p - q).norm() <= 1e-13 * (1 + p.norm()));
      }
      // Clamped at the cuts: the end points are control points.
      if (a > 0)
        CHECK((nurbs::cartesian_points(part).row(0) - nurbs::evaluate(full, a)).norm() <= 1e-13 * 10);
    }
  }
}

TEST_CASE("OBJ surface range inside and outside the knot domain", "[obj]") {
  const nurbs::Surface full = sample_surface(true, 4);  // domain [0, 1] × [-1, 2]
  std::string text = io::to_obj(full);
  const std::string range = "surf 0 1 -1 2 ";
  const auto at = text.find(range);
  REQUIRE(at != std::string::npos);
  text.replace(at, range.size(), "surf 0.25 1.5 -3 1.25 ");
  std::vector<std::string> warnings;
  const auto part = only<nurbs::Surface>(parse_warned(text, warnings));
  REQUIRE(warnings.size() == 2);
  CHECK_THAT(warnings[0], Contains("parameter range u [0.25, 1.5] reaches outside the knot domain [0, 1]: "
                                   "read over [0.25, 1]"));
  CHECK_THAT(warnings[1], Contains("parameter range v [-3, 1.25] reaches outside the knot domain [-1, 2]: "
                                   "read over [-1, 1.25]"));
  CHECK(nurbs::domain(part, nurbs::Direction::u).start == 0.25);
  CHECK(nurbs::domain(part, nurbs::Direction::u).end == 1);
  CHECK(nurbs::domain(part, nurbs::Direction::v).start == -1);
  CHECK(nurbs::domain(part, nurbs::Direction::v).end == 1.25);
  for (const double u : nurbs::uniform_parameters({0.25, 1}, 13))
    for (const double v : nurbs::uniform_parameters({-1, 1.25}, 13)) {
      const Point p = nurbs::evaluate(full, u, v), q = nurbs::evaluate(part, u, v);
      CHECK((p - q).norm() <= 1e-13 * (1 + p.norm()));
    }
}

TEST_CASE("OBJ Bezier curves and surfaces are their B-splines", "[obj]") {
  // Two quadratic segments over [0, 1] and [1, 3], rational: each is de Casteljau's of its 3 points.
  const std::string text =
      "v 0 0 0\nv 1 2 0 2\nv 2 0 1\nv 3 -1 0 0.5\nv 5 1 2\n"
      "cstype rat bezier\ndeg 2\ncurv 0 3 1 2 3 4 5\nparm u 0 1 3\nend\n";
  const auto c = only<nurbs::Curve>(io::parse_obj(text, "b.obj"));
  CHECK(c.knots == nurbs::Knots{0, 0, 0, 1, 1, 3, 3, 3});
  Points H(5, 4);  // homogeneous (w·x, w)
  H << 0, 0, 0, 1, 2, 4, 0, 2, 2, 0, 1, 1, 1.5, -0.5, 0, 0.5, 5, 1, 2, 1;
  for (const double u : nurbs::uniform_parameters({0, 3}, 61)) {
    const bool first = u < 1;
    const Eigen::RowVectorXd h = de_casteljau(H.middleRows(first ? 0 : 2, 3), first ? u : (u - 1) / 2);
    const Point expected = h.head(3).transpose() / h(3);
    CHECK((nurbs::evaluate(c, u) - expected).norm() <= 1e-14 * 6);
  }
  // Example 7 of the OBJ spec's surface: a bilinear patch over [0, 2]², S(u, v) = (u/2, v/2, 0).
  const std::string patch =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ndeg 1 1\ncstype bezier\n"
      "surf 0.0 2.0 0.0 2.0 1 2 3 4\nparm u 0.00 2.00\nparm v 0.00 2.00\nend\n";
  const auto s = only<nurbs::Surface>(io::parse_obj(patch, "p.obj"));
  for (const double u : {0.0, 0.3, 1.7, 2.0})
    for (const double v : {0.0, 0.9, 2.0})
      CHECK((nurbs::evaluate(s, u, v) - Point(Eigen::Vector3d(u / 2, v / 2, 0))).norm() <= 1e-15);
}

namespace {

// Example 9 of the OBJ specification ("Trimming with special points"), as printed: a Bezier space
// curve over a part of its range, a rational Bezier trimming curve (curv2), and a trimmed rational
// B-spline surface with special points.
const char* kSpecExample9 = R"(# special point and space curve data
vp 0.500
vp 0.700
vp 1.100
vp 0.200 0.950
v  0.300 1.500 0.100
v  0.000  0.000  0.000
v  1.000  1.000  0.000
v  2.000  1.000  0.000
v  3.000  0.000  0.000
cstype bezier
deg 3
curv 0.2 0.9 -4 -3 -2 -1
sp 1
parm u 0.00 1.00
end
# trimming curve
vp -0.675  1.850  3.000
vp  0.915  1.930
vp  2.485  0.470  2.000
vp  2.485 -1.030
vp  1.605 -1.890 10.700
vp -0.745 -0.654  0.500
cstype rat bezier
curv2 -6 -5 -4 -3 -2 -1 -6
parm u 0.00 1.00 2.00
sp 2 3
end
# surface
v -1.350 -1.030 0.000
v  0.130 -1.030 0.432 7.600
v  1.480 -1.030 0.000 2.300
v -1.460  0.060 0.201
v  0.120  0.060 0.915 0.500
v  1.380  0.060 0.454 1.500
v -1.480  1.030 0.000 2.300
v  0.120  1.030 0.394 6.100
v  1.170  1.030 0.000 3.300
cstype rat bspline
deg 2 2
surf -1.0 2.5 -2.0 2.0 -9 -8 -7 -6 -5 -4 -3 -2 -1
parm u -1.00 -1.00 -1.00 2.50 2.50 2.50
parm v -2.00 -2.00 -2.00 2.00 2.00 2.00
trim 0.0 2.0 1
sp 4
end
)";

}  // namespace

TEST_CASE("OBJ trimmed surfaces: refused, or read whole with ignore_trim (the spec's example 9)", "[obj]") {
  CHECK_THROWS_AS(io::parse_obj(kSpecExample9, "t.obj"), InvalidInput);
  CHECK_THROWS_WITH(io::parse_obj(kSpecExample9, "t.obj"),
                    "t.obj: line 44: trim: trimmed surfaces are not supported; --ignore-trim (ignore_trim) "
                    "reads the whole untrimmed surface");
  std::vector<std::string> warnings;
  const std::vector<io::Shape> shapes = parse_warned(kSpecExample9, warnings, true);
  REQUIRE(shapes.size() == 2);
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0] ==
        "w.obj: line 44: the trimming loops of the surf at line 41 are ignored: the whole "
        "untrimmed surface is read");
  // The space curve: the cubic Bezier of (0,0,0), (1,1,0), (2,1,0), (3,0,0) over [0.2, 0.9], i.e.
  // (3t, 3t(1 − t), 0).
  const auto& c = std::get<nurbs::Curve>(shapes[0]);
  CHECK(nurbs::domain(c).start == 0.2);
  CHECK(nurbs::domain(c).end == 0.9);
  for (const double t : nurbs::uniform_parameters({0.2, 0.9}, 15))
    CHECK((nurbs::evaluate(c, t) - Point(Eigen::Vector3d(3 * t, 3 * t * (1 - t), 0))).norm() <= 1e-14);
  // The surface: one rational biquadratic patch; its corners are the corner vertices.
  const auto& s = std::get<nurbs::Surface>(shapes[1]);
  CHECK(s.rational);
  CHECK((nurbs::evaluate(s, -1, -2) - Point(Eigen::Vector3d(-1.35, -1.03, 0))).norm() <= 1e-15);
  CHECK((nurbs::evaluate(s, 2.5, -2) - Point(Eigen::Vector3d(1.48, -1.03, 0))).norm() <= 1e-15);
  CHECK((nurbs::evaluate(s, -1, 2) - Point(Eigen::Vector3d(-1.48, 1.03, 0))).norm() <= 1e-15);
  CHECK((nurbs::evaluate(s, 2.5, 2) - Point(Eigen::Vector3d(1.17, 1.03, 0))).norm() <= 1e-15);
  // Its centre by hand: the tensor Bernstein weights 1/4, 1/2, 1/4 in each direction, rational.
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  const double b[3] = {0.25, 0.5, 0.25};
  const double vw[9][4] = {{-1.35, -1.03, 0, 1},    {0.13, -1.03, 0.432, 7.6}, {1.48, -1.03, 0, 2.3},
                           {-1.46, 0.06, 0.201, 1}, {0.12, 0.06, 0.915, 0.5},  {1.38, 0.06, 0.454, 1.5},
                           {-1.48, 1.03, 0, 2.3},   {0.12, 1.03, 0.394, 6.1},  {1.17, 1.03, 0, 3.3}};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {  // vertex j·3 + i is control point (i, j)
      const double* v = vw[j * 3 + i];
      sum += b[i] * b[j] * v[3] * Eigen::Vector4d(v[0], v[1], v[2], 1);
    }
  const Eigen::Vector3d centre = sum.head(3) / sum(3);
  CHECK((nurbs::evaluate(s, 0.75, 0) - Point(centre)).norm() <= 1e-14);
  // With an index, only the chosen shape's warnings.
  warnings.clear();
  parse_warned(kSpecExample9, warnings, true, 0);
  CHECK(warnings.empty());
}

namespace {

io::ShapeReadOptions by_index(std::size_t index) {
  return {.ignore_trim = false, .index = index, .warn = {}};
}

}  // namespace

TEST_CASE("read_shape chooses among several shapes by index", "[obj]") {
  const cifs_test::ScratchDir scratch("obj_index");
  const auto& dir = scratch.path();
  const nurbs::Curve a = sample_curve(false, 3, 11), b = sample_curve(true, 3, 12);
  // to_obj numbers the vertices from 1: the second curve refers to its own by negative indices.
  std::string second = io::to_obj(b);
  const std::string indices = "curv 0 1 1 2 3 4 5 6 7 8\n";
  REQUIRE(second.find(indices) != std::string::npos);
  second.replace(second.find(indices), indices.size(), "curv 0 1 -8 -7 -6 -5 -4 -3 -2 -1\n");
  write_file_atomically(dir / "two.obj", io::to_obj(a) + second);
  CHECK(io::read_shapes(dir / "two.obj").size() == 2);
  require_same_shape(std::get<nurbs::Curve>(io::read_shape(dir / "two.obj", by_index(0))), a);
  require_same_shape(std::get<nurbs::Curve>(io::read_shape(dir / "two.obj", by_index(1))), b);
  CHECK_THROWS_WITH(io::read_shape(dir / "two.obj", by_index(2)),
                    Contains("two.obj: --index 2 is out of range: the file holds 2 shapes (0 to 1)"));
  write_file_atomically(dir / "none.obj", "v 0 0 0\n");
  CHECK_THROWS_WITH(io::read_shape(dir / "none.obj"), Contains("none.obj: holds no curve or surface"));
}

TEST_CASE("OBJ: Rhino's knot count (n + d - 1) is refused with the convention named", "[obj][messages]") {
  const std::string text =
      "v 0 0 0\nv 1 2 0\nv 3 2 0\nv 4 0 0\ncstype bspline\ndeg 3\ncurv 0 1 1 2 3 4\nparm u 0 0 0 1 1 "
      "1\nend\n";
  CHECK_THROWS_WITH(
      io::parse_obj(text, "rh.obj"),
      "rh.obj: line 8: parm u: 6 knots given, 4 control points of degree 3 need 8 (the count given "
      "leaves out the first and the last knot, as Rhino and openNURBS store them; OBJ files give "
      "all n + d + 1)");
}
