// SPDX-License-Identifier: MIT
#include <unistd.h>

#include <bit>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/nurbs/refine.hpp"

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
Points random_points(Eigen::Index rows, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(-10, 10);
  Points P(rows, dim);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (int j = 0; j < dim; ++j) P(i, j) = coord(rng);
  return P;
}

Eigen::VectorXd random_weights(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> weight(0.1, 7);
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) w(i) = weight(rng);
  return w;
}

nurbs::Curve sample_curve(bool rational, int dim = 3, unsigned seed = 1) {
  const nurbs::Knots knots{0, 0, 0, 0, 0.1, 0.3, 1.0 / 3.0, 0.7, 1, 1, 1, 1};
  const Points P = random_points(8, dim, seed);
  return nurbs::make_curve(3, knots, P, rational ? random_weights(8, seed + 100) : Eigen::VectorXd());
}

nurbs::Surface sample_surface(bool rational, unsigned seed = 2) {
  // nu = 5 (degree 2), nv = 4 (degree 3): a transposed net would not even have the right count.
  const std::array<nurbs::Knots, 2> knots{nurbs::Knots{0, 0, 0, 0.25, 0.6, 1, 1, 1},
                                          nurbs::Knots{-1, -1, -1, -1, 2, 2, 2, 2}};
  const Points P = random_points(20, 3, seed);
  return nurbs::make_surface({2, 3}, knots, {5, 4}, P,
                             rational ? random_weights(20, seed + 100) : Eigen::VectorXd());
}

template <class T>
T only(const std::vector<io::Shape>& shapes) {
  REQUIRE(shapes.size() == 1);
  REQUIRE(std::holds_alternative<T>(shapes[0]));
  return std::get<T>(shapes[0]);
}

void require_same(const nurbs::Curve& a, const nurbs::Curve& b) {
  CHECK(a.degree == b.degree);
  CHECK(a.rational == b.rational);
  CHECK(a.closed == b.closed);
  CHECK(same_bits(a.knots, b.knots));
  CHECK(same_bits(a.P, b.P));
}

void require_same(const nurbs::Surface& a, const nurbs::Surface& b) {
  CHECK(a.degree == b.degree);
  CHECK(a.count == b.count);
  CHECK(a.rational == b.rational);
  CHECK(same_bits(a.knots[0], b.knots[0]));
  CHECK(same_bits(a.knots[1], b.knots[1]));
  CHECK(same_bits(a.P, b.P));
}

const std::string kVertices = "v 0 0 0\nv 1 2 0\nv 3 2 1\nv 4 0 0\n";  // lines 1-4
const std::string kCurve = kVertices +
                           "cstype bspline\n"        // 5
                           "deg 2\n"                 // 6
                           "curv 0 2 1 2 3 4\n"      // 7
                           "parm u 0 0 0 1 2 2 2\n"  // 8
                           "end\n";                  // 9

}  // namespace

TEST_CASE("OBJ round trip: B-spline curve", "[obj]") {
  const nurbs::Curve c = sample_curve(false);
  const std::string text = io::to_obj(c);
  require_same(only<nurbs::Curve>(io::parse_obj(text, "c.obj")), c);
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
    require_same(only<nurbs::Curve>(io::parse_obj(text, "c.obj")), c);
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
  require_same(only<nurbs::Surface>(io::parse_obj(text, "s.obj")), s);
}

TEST_CASE("OBJ round trip: rational surface", "[obj]") {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const nurbs::Surface s = sample_surface(true, seed);
    require_same(only<nurbs::Surface>(io::parse_obj(io::to_obj(s), "s.obj")), s);
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
  const Points P = random_points(5, 3, 11);
  const nurbs::Curve c = nurbs::make_closed_curve(3, {0, 1, 2, 3, 4, 5}, P, random_weights(5, 12));
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
  const nurbs::Curve c = nurbs::make_curve(2, {0, 1, 2, 3, 4, 5, 6}, random_points(4, 3, 5));
  const std::string text = io::to_obj(c);
  CHECK_THAT(text, Contains("curv 2 4 1 2 3 4\n"));
  require_same(only<nurbs::Curve>(io::parse_obj(text, "c.obj")), c);
}

TEST_CASE("OBJ writing refuses more than three dimensions", "[obj]") {
  CHECK_THROWS_AS(io::to_obj(sample_curve(false, 4)), InvalidInput);
  CHECK_THROWS_WITH(io::to_obj(sample_curve(true, 4)), Contains("4-D"));
  const nurbs::Surface s = nurbs::make_surface({1, 1}, {nurbs::Knots{0, 0, 1, 1}, nurbs::Knots{0, 0, 1, 1}},
                                               {2, 2}, random_points(4, 5, 3));
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
  const auto absolute = only<nurbs::Curve>(io::parse_obj(kCurve, "a.obj"));
  require_same(std::get<nurbs::Curve>(shapes[0]), absolute);
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
  require_same(c, only<nurbs::Curve>(io::parse_obj(kCurve, "a.obj")));
  CHECK(io::parse_obj("", "e.obj").empty());
  CHECK(io::parse_obj("# nothing\n\nv 1 2 3\nf 1 1 1\n", "e.obj").empty());
  CHECK(io::parse_obj(kCurve.substr(0, kCurve.size() - 1) + " \\", "e.obj").size() == 1);  // "end \" at EOF
}

TEST_CASE("OBJ cstype and deg carry over to later elements", "[obj]") {
  const std::string text = kCurve +
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
      {"cstype bezier", "cstype bezier\n", 1, "cstype bezier is not supported", false},
      {"cstype rat bezier", "v 0 0 0\ncstype rat bezier\n", 2, "cstype rat bezier is not supported", false},
      {"cstype cardinal", "cstype cardinal\n", 1, "cstype cardinal is not supported", false},
      {"cstype taylor", "cstype taylor\n", 1, "cstype taylor is not supported", false},
      {"cstype bmatrix", "cstype bmatrix\n", 1, "cstype bmatrix is not supported", false},
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
      {"trimmed curve", curve_with("curv 0.5 2 1 2 3 4"), 7, "trimmed curves are not supported", false},
      {"range outside the domain", curve_with("curv -1 2 1 2 3 4"), 7, "is outside the knot domain [0, 2]",
       false},
      {"reversed range", curve_with("curv 2 0 1 2 3 4"), 7, "is empty or reversed", false},
      {"trimmed surface range", surface_with("surf 0 1 0 0.5 1 2 3 4", "parm u 0 0 1 1", "parm v 0 0 1 1"), 7,
       "parameter range v [0, 0.5] is a strict part of the knot domain [0, 1]", false},
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
       "trimmed surfaces are not supported", false},
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
  const std::string valid = io::to_obj(sample_surface(true)) + io::to_obj(sample_curve(true)) + kCurve;
  const auto parse = [](const std::string& text) {
    try {
      io::parse_obj(text, "f.obj");
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
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("cifs_test_obj_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const nurbs::Surface s = sample_surface(true, 5);
  write_file_atomically(dir / "one.obj", io::to_obj(s));
  require_same(std::get<nurbs::Surface>(io::read_shape(dir / "one.obj")), s);
  write_file_atomically(dir / "two.obj", kCurve + kCurve);
  CHECK_THROWS_AS(io::read_shape(dir / "two.obj"), InvalidInput);
  std::filesystem::remove_all(dir);
}
