// SPDX-License-Identifier: MIT
// `cifs scheme`, run as a user runs it: analysis JSON, refinement of polygon files, errors.

#include <catch2/catch.hpp>

#include <cmath>
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
