// SPDX-License-Identifier: MIT
// `cifs scheme`, run as a user runs it: analysis JSON, refinement of polygon files, errors.

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/cli_runner.hpp"

using nlohmann::json;

using namespace cifs_test;

namespace {

json analyze(const std::string& args) {
  const Run r = cifs_cli("scheme " + args + " --analyze");
  INFO("stderr: " << r.err);
  REQUIRE(r.status == 0);
  return json::parse(r.out);
}

std::string polygon_json(const std::string& name, const std::string& points) {
  return file(name, R"({"polygon": {"points": )" + points + R"(, "closed": false}})");
}

}  // namespace

TEST_CASE("cifs scheme --analyze prints the published properties", "[cli][subdivision]") {
  const json four = analyze("four-point");
  CHECK(four["mask"] == json::array({"-0.0625", "0", "0.5625", "1", "0.5625", "0", "-0.0625"}));
  CHECK(four["support"] == json::array({0, 6}));
  CHECK(four["kind"] == "primal");
  CHECK(four["class"] == "interpolating");
  CHECK(four["generation_degree"] == 3);
  CHECK(four["reproduction_degree"] == 3);
  CHECK(four["continuity"] == 1);
  CHECK(four["holder"][1].get<double>() == Approx(2).margin(1e-9));
  CHECK(four["holder"][0].get<double>() < 2);
  CHECK(four["eigenvalues"]["S0"].size() == 6);
  CHECK(four["matrices"]["S0"].size() == 6);
  // The proof certificate: ‖S^L‖ < 1 for the first difference scheme.
  CHECK(four["continuity_proof"]["k"] == 1);
  CHECK(four["continuity_proof"]["norm_value"].get<double>() < 1);

  const json six = analyze("six-point");
  CHECK(six["continuity"] == 2);
  CHECK(six["holder"][1].get<double>() == Approx(std::log2(64.0 / 9.0)).margin(1e-9));

  const json chaikin = analyze("chaikin");
  CHECK(chaikin["continuity"] == 1);
  CHECK(chaikin["kind"] == "dual");
  CHECK(chaikin["class"] == "approximating");

  for (int n : {2, 5, 9}) {
    const json lr = analyze("lane-riesenfeld --param degree=" + std::to_string(n));
    CHECK(lr["continuity"] == n - 1);
    CHECK(lr["holder"][0].get<double>() == Approx(n).margin(1e-9));
  }
  CHECK(analyze("generalized-four-point --param w=0.1")["continuity"] == 1);
  CHECK(analyze("generalized-four-point --param w=1/4")["continuity"] == 0);
  CHECK(analyze("j-spline --param s=1.5")["continuity"] == 4);  // quintic B-spline
  CHECK(analyze("corner-cutting --param a=0.1 --param b=0.9")["parameters"] ==
        json({{"a", "0.1"}, {"b", "0.9"}}));
  CHECK(analyze("mask --param coefficients=1/4,3/4,3/4,1/4")["continuity"] == 1);
  CHECK(analyze("symbol --param 'symbol=(1+z)^4/8'")["continuity"] == 2);
}

TEST_CASE("cifs scheme --refine reads and writes polygon files", "[cli][subdivision]") {
  const std::string closed =
      file("square.json", R"({"polygon": {"points": [[0,0],[1,0],[1,1],[0,1]], "closed": true}})");
  const Run r = cifs_cli("scheme chaikin --refine " + closed + " --steps 2");
  REQUIRE(r.status == 0);
  const json out = json::parse(r.out);
  CHECK(out["polygon"]["closed"] == true);
  const json& pts = out["polygon"]["points"];
  REQUIRE(pts.size() == 16);
  // Chaikin twice on the square, by hand: the first step starts (¼, 0), (¾, 0), so the second
  // starts ¾(¼, 0) + ¼(¾, 0) = (⅜, 0).
  CHECK(pts[0][0].get<double>() == 0.375);
  CHECK(pts[0][1].get<double>() == 0.0);
  // The output is itself a polygon file: refine again.
  const std::string again = file("again.json", r.out);
  CHECK(json::parse(cifs_cli("scheme chaikin --refine " + again).out)["polygon"]["points"].size() == 32);

  const std::string open = file("open.json", R"({"polygon": {"points": [[0,0],[1,2],[2,0],[3,2]]}})");
  const json o = json::parse(cifs_cli("scheme four-point --refine " + open).out);
  CHECK(o["polygon"]["closed"] == false);
  REQUIRE(o["polygon"]["points"].size() == 7);
  CHECK(o["polygon"]["points"][0] == json::array({0.0, 0.0}));
  CHECK(o["polygon"]["points"][6] == json::array({3.0, 2.0}));
  CHECK(o["polygon"]["points"][2] == json::array({1.0, 2.0}));  // interpolating
  CHECK_THAT(cifs_cli("scheme six-point --refine " + closed + " --format svg").out,
             Catch::StartsWith("<svg"));
  CHECK_THAT(cifs_cli("scheme six-point --refine " + closed + " --format obj").out,
             Catch::Contains("\nl 1 2 3"));
  const json keep = json::parse(cifs_cli("scheme lane-riesenfeld --refine " + open + " --ends keep").out);
  CHECK(keep["polygon"]["points"].front() == json::array({0.0, 0.0}));
  const Run list = cifs_cli("scheme --list");
  REQUIRE(list.status == 0);
  for (const char* name : {"chaikin", "corner-cutting", "four-point", "generalized-four-point", "six-point",
                           "lane-riesenfeld", "lr-four-point", "lr-six-point", "two-tension", "j-spline",
                           "romani", "hormann-sabin", "cubic-precision", "mask", "symbol"})
    CHECK_THAT(list.out, Catch::Contains(name));
}

TEST_CASE("cifs scheme reports bad input on one line and exits 2", "[cli][subdivision]") {
  const std::string closed =
      file("sq.json", R"({"polygon": {"points": [[0,0],[1,0],[1,1]], "closed": true}})");
  check_error(cifs_cli("scheme mask --param coefficients=0.25,0.75,0.5 --analyze"),
              "mask: coefficients sum to 1.5, a subdivision mask sums to 2");
  check_error(cifs_cli("scheme lr-four-point --param stages=-1 --analyze"), "stages = -1 is negative");
  check_error(cifs_cli("scheme lane-riesenfeld --param degree=2.5 --analyze"),
              "degree = 2.5 is not an integer");
  check_error(cifs_cli("scheme four-points --analyze"), "unknown scheme 'four-points'");
  check_error(cifs_cli("scheme chaikin --param a --analyze"), "expected NAME=VALUE");
  check_error(cifs_cli("scheme chaikin --param w=1 --analyze"), "unknown parameter 'w'");
  check_error(cifs_cli("scheme generalized-four-point --param w=x --analyze"), "'x' is not a number");
  check_error(cifs_cli("scheme chaikin"), "choose --analyze or --refine");
  check_error(cifs_cli("scheme --analyze"), "a scheme name is required");
  check_error(cifs_cli("scheme symbol --param 'symbol=(1+z' --analyze"), "missing ')'");
  check_error(cifs_cli("scheme chaikin --refine /nonexistent.json"), "/nonexistent.json");
  check_error(cifs_cli("scheme chaikin --refine " + file("bad.json", R"({"points": []})")),
              "expected {\"polygon\"");
  check_error(
      cifs_cli("scheme chaikin --refine " + file("ragged.json", R"({"polygon": {"points": [[0,0],[1]]}})")),
      "polygon.points[1]: 1 coordinates, the first point has 2");
  check_error(cifs_cli("scheme chaikin --refine " + closed + " --steps -2"), "--steps -2 is negative");
  check_error(cifs_cli("scheme chaikin --refine " + closed + " --steps 40"), "exceed the limit");
  check_error(cifs_cli("scheme chaikin --refine " + closed + " --ends sideways"), "--ends 'sideways'");
  check_error(cifs_cli("scheme chaikin --refine " + closed + " --format png"), "--format 'png'");
  check_error(cifs_cli("scheme corner-cutting --param a=0.1 --param b=0.6 --ends reflect --refine " +
                       file("o.json", R"({"polygon": {"points": [[0,0],[1,0],[1,1]]}})")),
              "needs a symmetric mask");
}

TEST_CASE("cifs scheme MESH-SCHEME --valence N --analyze: local subdivision matrices",
          "[cli][mesh_analysis]") {
  const json cc = analyze("catmull-clark --valence 5");
  CHECK(cc["scheme"] == "catmull-clark");
  CHECK(cc["valence"] == 5);
  CHECK(cc["vertex"] == "interior");
  CHECK(cc["exact"] == true);
  CHECK(cc["neighbourhood"].size() == 11);
  CHECK(cc["matrix"][0][0] == "0.65");  // (n − 2)/n + n·(1/n²)(¼) at n = 5
  CHECK(analyze("catmull-clark --valence 3")["matrix"][0][0] == "5/12");
  // Reif's C1 test, proved on the characteristic map's Bernstein patches.
  CHECK(cc["c1"]["verdict"] == true);
  CHECK(cc["c1"]["method"] == "bernstein");
  CHECK(cc["c1"]["winding"] == 1);
  CHECK(cc["c1"]["pieces"].get<int>() >= 15);
  CHECK(analyze("butterfly --valence 5")["c1"]["method"] == "sampled");
  CHECK(cc["spectrum"].size() == 11);
  CHECK(cc["spectrum"][0] == json::array({1.0, 0.0}));
  // (5 + cos(2π/5) + cos(π/5)√(2(9 + cos(2π/5))))/16
  const double c = std::cos(2 * M_PI / 5);
  const double lambda1 = (5 + c + std::cos(M_PI / 5) * std::sqrt(2 * (9 + c))) / 16;
  CHECK(cc["subdominant"]["lambda1"].get<double>() == Approx(lambda1).epsilon(1e-15));
  CHECK(cc["subdominant"]["equal_pair"] == true);
  CHECK(cc["subdominant"]["eigenvectors"].size() == 2);
  CHECK(cc["gap"] == true);
  CHECK(cc["dominant_simple"] == true);
  CHECK(cc["curvature"]["verdict"] == "unbounded");
  CHECK(cc["limit_stencil"].size() == 11);

  const json loop = analyze("loop --valence 7");
  CHECK(loop["exact"] == false);
  CHECK(loop["matrix"][0][0].is_number());
  CHECK(analyze("sqrt3 --valence 4")["steps"] == 2);
  const json boundary = analyze("loop --valence 4 --boundary edge");
  CHECK(boundary["vertex"] == "boundary");
  CHECK(boundary["boundary_rule"] == "edge");
  CHECK(boundary["c1"]["verdict"] == true);  // per sector: a boundary vertex has one
  CHECK(boundary["c1"]["sectors"].size() == 1);
  CHECK(analyze("doo-sabin --valences 3,5")[1]["valence"] == 5);

  const Run table = cifs_cli("scheme loop --valences 3..16 --analyze --format table");
  REQUIRE(table.status == 0);
  CHECK(std::count(table.out.begin(), table.out.end(), '\n') == 16);  // title, header, 14 valences
  CHECK_THAT(table.out, Catch::Contains("\n6   7     yes    0.5              0.5              0.25"));
  std::size_t proved = 0;
  for (std::size_t at = 0; (at = table.out.find("yes (proved, winding 1)", at)) != std::string::npos; ++at)
    ++proved;
  CHECK(proved == 14);
}

TEST_CASE("cifs scheme MESH-SCHEME: bad valences and options on one line, exit 2", "[cli][mesh_analysis]") {
  check_error(cifs_cli("scheme loop --valence 2 --analyze"),
              "loop: valence 2 is out of range; expected 3 to 16");
  check_error(cifs_cli("scheme catmull-clark --valences 3..17 --analyze"), "valence 17 is out of range");
  check_error(cifs_cli("scheme loop --valence five --analyze"), "--valence 'five': expected an integer");
  check_error(cifs_cli("scheme loop --valences 9..3 --analyze"), "the range is empty");
  check_error(cifs_cli("scheme loop --valences 3,,5 --analyze"), "--valences '3,,5'");
  check_error(cifs_cli("scheme loop --analyze"), "give --valence N or --valences A..B");
  check_error(cifs_cli("scheme loop --valence 3 --valences 3..5 --analyze"), "one of them");
  check_error(cifs_cli("scheme loop --valence 5"), "a mesh scheme takes --analyze");
  check_error(cifs_cli("scheme loop --valence 5 --analyze --refine x.json"), "cifs subdivide");
  check_error(cifs_cli("scheme loop --valence 5 --analyze --format svg"), "--format 'svg'");
  check_error(cifs_cli("scheme loop --valence 5 --analyze --param w=1"), "take no parameters");
  check_error(
      cifs_cli("scheme doo-sabin --valence 5 --analyze --boundary edge"),
      "doo-sabin: boundary vertices make no face; a face touching the boundary is analysed from which "
      "of its corners are interior");
  check_error(cifs_cli("scheme butterfly --valence 2 --analyze --boundary corner"),
              "butterfly: the boundary has one rule under this scheme (the 4-point curve)");
  check_error(cifs_cli("scheme loop --valence 17 --analyze --boundary edge"),
              "boundary valence 17 is out of range");
  check_error(cifs_cli("scheme loop --valence 4 --analyze --boundary sideways"), "--boundary sideways");
  check_error(cifs_cli("scheme chaikin --valence 5 --analyze"), "are for the mesh schemes");
}

TEST_CASE("cifs scheme MESH-SCHEME --crease K | --dart | --corner | --boundary-valence K --analyze",
          "[cli][mesh_analysis]") {
  const json crease = analyze("catmull-clark --valence 4 --crease 2");
  CHECK(crease["vertex"] == "crease");
  CHECK(crease["sharp_edges"] == json::array({0, 2}));
  CHECK(crease["sector_faces"] == json::array({2, 2}));
  CHECK(crease["c1"]["verdict"] == true);
  REQUIRE(crease["c1"]["sectors"].size() == 2);
  CHECK(crease["c1"]["sectors"][0]["faces"] == 2);
  CHECK(crease["c1"]["sectors"][0]["lambda1"].get<double>() == Approx(0.5).epsilon(1e-15));
  CHECK(crease["c1"]["sectors"][1]["c1"]["sector_angle_degrees"].get<double>() == Approx(180).epsilon(1e-9));
  // The cubic B-spline curve's limit on c, r0 and r2 (c, r0, f0, r1, f1, r2, …).
  CHECK(crease["limit_stencil"][0].get<double>() == Approx(4.0 / 6).epsilon(1e-15));
  CHECK(crease["limit_stencil"][5].get<double>() == Approx(1.0 / 6).epsilon(1e-15));

  CHECK(analyze("loop --valence 5 --dart")["vertex"] == "dart");
  CHECK(analyze("loop --valence 5 --dart")["c1"]["winding"] == 1);
  const json boundary = analyze("loop --boundary-valence 8");  // 8 faces, 9 edges
  CHECK(boundary["valence"] == 9);
  CHECK(boundary["c1"]["verdict"] == false);
  CHECK(boundary["c1"]["sectors"][0]["c1"]["through_centre"] == true);
  const json concave = analyze("catmull-clark --boundary-valence 1 --corner --concave");
  CHECK(concave["vertex"] == "corner");
  CHECK(concave["concave"] == true);
  CHECK(concave["c1"]["verdict"] == false);
  CHECK_THAT(concave["c1"]["reason"].get<std::string>(), Catch::Contains("concave"));
  CHECK(analyze("catmull-clark --boundary-valence 1 --corner")["c1"]["verdict"] == true);
  CHECK(analyze("loop --valence 6 --crease all").size() == 5);
  // √3 on the boundary: two steps (the boundary kept, then trisected), exact weights; 4 faces: the
  // inside's (2 + 2cos(π/4))/9 leads the curve's ⅓, C1. From 7 faces the inside's two lead: not C1.
  const json sqrt3 = analyze("sqrt3 --boundary-valence 4");
  CHECK(sqrt3["steps"] == 2);
  CHECK(sqrt3["exact"] == true);
  CHECK(sqrt3["vertex"] == "boundary");
  CHECK(sqrt3["subdominant"]["lambda1"].get<double>() ==
        Approx((2 + 2 * std::cos(M_PI / 4)) / 9).epsilon(1e-15));
  CHECK(sqrt3["subdominant"]["lambda2"].get<double>() == Approx(1.0 / 3).epsilon(1e-15));
  CHECK(sqrt3["c1"]["verdict"] == true);
  CHECK(analyze("sqrt3 --boundary-valence 7")["c1"]["verdict"] == false);
  // Butterfly (the 4-point curve, reflected wings inside): C1 at 2 and 3 faces, not at 4.
  CHECK(analyze("butterfly --boundary-valence 3")["c1"]["verdict"] == true);
  CHECK(analyze("butterfly --boundary-valence 4")["c1"]["verdict"] == false);

  const Run table = cifs_cli("scheme loop --boundary-valence 1-9 --analyze --format table");
  REQUIRE(table.status == 0);
  CHECK(std::count(table.out.begin(), table.out.end(), '\n') == 11);  // title, header, 9 rows
  CHECK_THAT(table.out, Catch::Contains("\n4   boundary  3         5     yes    0.5"));

  check_error(cifs_cli("scheme loop --valence 6 --crease 6 --analyze"),
              "--crease 6: expected 1 to 5 faces on one side at valence 6");
  check_error(cifs_cli("scheme loop --valence 6 --dart --crease 2 --analyze"), "--dart is one sharp edge");
  check_error(cifs_cli("scheme loop --valence 6 --corner --analyze"), "--corner needs --crease K");
  check_error(cifs_cli("scheme loop --valence 6 --crease 2 --concave --analyze"),
              "--concave is said of a --corner");
  check_error(cifs_cli("scheme loop --boundary-valence 3 --valence 4 --analyze"), "--boundary-valence K");
  check_error(cifs_cli("scheme loop --boundary-valence 16 --analyze"), "boundary valence 17 is out of range");
  check_error(cifs_cli("scheme sqrt3 --valence 2 --boundary corner --analyze"),
              "sqrt3: the boundary has one rule under this scheme");
  check_error(cifs_cli("scheme sqrt3 --valence 6 --crease 3 --analyze"),
              "sharp edges and corners are analysed for catmull-clark and loop only");
  check_error(cifs_cli("scheme chaikin --analyze --dart"), "are for the mesh schemes");
}

TEST_CASE("cifs scheme doo-sabin --boundary-valence K | --interior-corners PATTERN --analyze",
          "[cli][mesh_analysis]") {
  // A run of m interior corners of a k-gon: the interior k-gon's characteristic map on their patches,
  // spanning 360 m / k degrees; the spectrum the k-gon's 1, ½, ½, ¼ …
  const json hexagon = analyze("doo-sabin --interior-corners 111000");
  CHECK(hexagon["valence"] == 6);
  CHECK(hexagon["vertex"] == "boundary");
  CHECK(hexagon["interior_corners"] == json::array({1, 1, 1, 0, 0, 0}));
  CHECK(hexagon["sector_corners"] == json::array({3}));
  CHECK(hexagon["exact"] == true);
  CHECK(hexagon["neighbourhood"].size() == 17);  // 6 corners, 4 edge quads (a, b), 3 corner quads
  CHECK(hexagon["subdominant"]["lambda1"].get<double>() == Approx(0.5).epsilon(1e-15));
  CHECK(hexagon["mu"][0].get<double>() == Approx(0.25).epsilon(1e-15));
  CHECK(hexagon["c1"]["verdict"] == true);
  CHECK(hexagon["c1"]["sector_angle_degrees"].get<double>() == Approx(180).epsilon(1e-12));
  const json pinch = analyze("doo-sabin --interior-corners 1010");
  CHECK(pinch["sector_corners"] == json::array({1, 1}));
  CHECK(pinch["c1"]["verdict"] == false);
  CHECK_THAT(pinch["c1"]["reason"].get<std::string>(), Catch::Contains("pinches"));
  // --boundary-valence K: every run of 1 … K − 1 interior corners of a K-gon, as an array.
  const json pentagons = analyze("doo-sabin --boundary-valence 5");
  REQUIRE(pentagons.size() == 4);
  for (int m = 1; m <= 4; ++m) {
    const json& p = pentagons[static_cast<std::size_t>(m - 1)];
    CHECK(p["sector_corners"] == json::array({m}));
    CHECK(p["exact"] == false);  // cos(2π/5)
    CHECK(p["c1"]["sector_angle_degrees"].get<double>() == Approx(72.0 * m).epsilon(1e-12));
  }
  const Run table = cifs_cli("scheme doo-sabin --boundary-valence 3-5 --analyze --format table");
  REQUIRE(table.status == 0);
  CHECK(std::count(table.out.begin(), table.out.end(), '\n') == 2 + 2 + 3 + 4);  // title, header, rows
  CHECK_THAT(table.out, Catch::Contains("\n4   1100      2         12    yes    0.5"));
  CHECK_THAT(table.out, Catch::Contains("sector angle 270"));

  check_error(cifs_cli("scheme doo-sabin --interior-corners 10x0 --analyze"),
              "--interior-corners '10x0': expected 1 (interior) or 0 (boundary) per corner");
  check_error(
      cifs_cli("scheme doo-sabin --interior-corners 1111 --analyze"),
      "doo-sabin: a face touching the boundary has an interior corner and a boundary one; every one of "
      "the 4 is interior");
  check_error(cifs_cli("scheme doo-sabin --interior-corners 0000 --analyze"), "none of the 4 is interior");
  check_error(cifs_cli("scheme doo-sabin --interior-corners 10 --analyze"),
              "--interior-corners '10': a face of 2 corners; doo-sabin's faces have 3 to 16 corners here");
  check_error(cifs_cli("scheme doo-sabin --interior-corners " + std::string(3000, '1') + " --analyze"),
              "(3000 characters)': a face of 3000 corners");
  // An empty pattern analysed the default case, as if the option were left out.
  check_error(cifs_cli("scheme doo-sabin --interior-corners '' --analyze"),
              "--interior-corners: an empty value");
  check_error(cifs_cli("scheme doo-sabin --boundary-valence 4"),
              "takes --analyze with --valence N, --valences A..B or --boundary-valence K");
  check_error(cifs_cli("scheme doo-sabin --boundary-valence 2 --analyze"),
              "--boundary-valence 2: doo-sabin's faces have 3 to 16 corners here");
  check_error(cifs_cli("scheme doo-sabin --boundary-valence 17 --analyze"), "--boundary-valence 17");
  check_error(cifs_cli("scheme doo-sabin --boundary-valence 4 --interior-corners 1100 --analyze"),
              "is --boundary-valence K (its corners) or --interior-corners PATTERN, nothing else");
  check_error(cifs_cli("scheme doo-sabin --boundary-valence 4 --corner --analyze"),
              "doo-sabin: sharp edges, corners and rule sets are analysed for catmull-clark and loop only");
  check_error(cifs_cli("scheme loop --interior-corners 110 --analyze"),
              "--interior-corners is said of a doo-sabin face touching the boundary");
  check_error(cifs_cli("scheme chaikin --analyze --interior-corners 110"), "are for the mesh schemes");
}

TEST_CASE("cifs scheme MESH-SCHEME --rules blz --analyze: Biermann-Levin-Zorin's rules",
          "[cli][mesh_analysis][blz]") {
  // Catmull-Clark, a boundary vertex of 6 faces: not C1 under OpenSubdiv's rules, C1 under blz with
  // the subdominant pair 1/2, 1/2.
  CHECK(analyze("catmull-clark --boundary-valence 6")["c1"]["verdict"] == false);
  const json blz = analyze("catmull-clark --boundary-valence 6 --rules blz");
  CHECK(blz["rules"] == "blz");
  CHECK(blz["c1"]["verdict"] == true);
  CHECK(blz["subdominant"]["lambda1"].get<double>() == Approx(0.5).epsilon(1e-13));
  CHECK(blz["subdominant"]["lambda2"].get<double>() == Approx(0.5).epsilon(1e-13));
  CHECK_FALSE(analyze("loop --boundary-valence 6")["rules"].is_string());  // the default: not written
  // A concave corner of 3 faces: undecided under OpenSubdiv's rules, C1 and spanning 270 degrees
  // (Loop: the sector's eigenvectors are sin((3 - i)pi/2), sin(i pi/2): exactly the three quarters).
  const json concave = analyze("loop --boundary-valence 3 --corner --concave --rules blz");
  CHECK(concave["c1"]["verdict"] == true);
  CHECK(concave["c1"]["sectors"][0]["c1"]["sector_angle_degrees"].get<double>() == Approx(270).epsilon(1e-9));
  const Run table =
      cifs_cli("scheme catmull-clark --boundary-valence 1-8 --rules blz --analyze --format table");
  REQUIRE(table.status == 0);
  CHECK_THAT(table.out, Catch::Contains("\n9   boundary  8         18    no     0.5              0.5"));
  check_error(cifs_cli("scheme loop --boundary-valence 3 --rules zorin --analyze"),
              "--rules zorin: unknown rule set 'zorin' (opensubdiv, blz)");
  check_error(cifs_cli("scheme butterfly --valence 6 --rules blz --analyze"),
              "butterfly: the rule set 'blz' is built for catmull-clark and loop only");
  check_error(cifs_cli("scheme chaikin --analyze --rules blz"),
              "--rules and --interior-corners are for the mesh schemes");
}

TEST_CASE("cifs scheme refuses deeply nested symbols instead of overflowing the stack",
          "[cli][reliability]") {
  // The parser recursed per bracket and per sign: 5,000 brackets or 100,000 signs crashed it.
  const std::string brackets = std::string(5000, '(') + "1+z" + std::string(5000, ')');
  const std::string signs = std::string(100000, '-') + "(1+z)";
  for (const std::string& symbol : {brackets, signs}) {
    const Run r = cifs_cli("scheme symbol --param 'symbol=" + symbol + "' --analyze");
    check_error(r, "nested within each other");
    CHECK(r.err.size() < 300);  // the expression is not echoed whole
  }
}

TEST_CASE("cifs scheme --refine near the largest doubles: the point, or a refusal naming the overflow",
          "[cli][reliability]") {
  // One four-point step on coordinates 1.7e308 printed inf (9/16·(b + c) overflowed before the
  // negative weights), exit 0 (issue 33). The result fits a double: it is printed.
  const std::string fits = file("big_polygon.json", R"({"polygon": {"points": [[1.7e308, 0], [1.7e308, 1],
      [1.7e308, 2], [1.7e308, 3]], "closed": true}})");
  const Run r = cifs_cli("scheme four-point --refine " + fits);
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK(r.out.find("inf") == std::string::npos);
  // The edge point of (0, 1): x = 1.7e308 to a rounding (1.6999999999999997e+308), y = (9 − 5)/16.
  CHECK(r.out.find("[1.6999999999999997e+308, 0.25]") != std::string::npos);
  // The result does not fit (1.25 · 1.79e308): refused, naming the cause.
  const std::string over = file("over_polygon.json", R"({"polygon": {"points": [[-1.79e308, 0], [1.79e308, 1],
      [1.79e308, 2], [-1.79e308, 3]], "closed": true}})");
  check_error(cifs_cli("scheme four-point --refine " + over), "refining the polygon overflows a double");
}

TEST_CASE("cifs scheme refuses a symbol beyond the largest mask at once", "[cli][reliability]") {
  check_error(cifs_cli("scheme symbol --param 'symbol=(1+z)^1024' --analyze"),
              "the power has degree 1024, above the largest mask (512 coefficients, degree 511)");
}

TEST_CASE("cifs scheme --refine names the polygon and the steps, not refine:",
          "[cli][reliability][messages]") {
  check_message(cifs_cli("scheme four-point --refine " + polygon_json("one_point.json", "[[0, 0]]")),
                "an open polygon needs at least 2 points to refine, got 1", "refine:");
  const std::string two = polygon_json("two_points.json", "[[0, 0], [1, 1]]");
  check_message(cifs_cli("scheme four-point --refine " + two + " --steps 40"),
                "40 refinement steps of 2 points exceed the limit of 50000000 points; refine fewer steps",
                "refine:");
  check_message(cifs_cli("scheme corner-cutting --param a=0.1 --param b=0.6 --ends reflect --refine " + two),
                "the reflect end rule needs a symmetric mask (corner-cutting is not); use the keep rule",
                "refine:");
}
