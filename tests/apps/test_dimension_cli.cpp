// SPDX-License-Identifier: MIT
// cifs dimension: box counting against closed forms (Sierpinski, Koch, smooth curves and surfaces),
// the route it chooses and the uncertainty it reports, and bad input refused in one line.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "apps/cli_runner.hpp"

using namespace cifs_test;

namespace {

struct Dimension {
  double value = 0, uncertainty = 0;
  nlohmann::json report;
};

/// `cifs dimension FILE ARGS --json` on an example, which must succeed.
Dimension dimension_of(const std::string& args) {
  const Run r = cifs_cli("dimension " CIFS_EXAMPLES_DIR "/" + args + " --json");
  INFO(args << ": " << r.err);
  REQUIRE(r.status == 0);
  Dimension d;
  d.report = nlohmann::json::parse(r.out);
  d.value = d.report["box_counting"]["dimension"].get<double>();
  d.uncertainty = d.report["box_counting"]["uncertainty"].get<double>();
  CHECK(d.uncertainty >= d.report["box_counting"]["standard_error"].get<double>());
  CHECK(d.uncertainty >= d.report["box_counting"]["spread"].get<double>());
  return d;
}

}  // namespace

TEST_CASE("cifs dimension: box counting and similarity dimension", "[cli][dimension]") {
  // Sierpinski at depth 12: the box-counting fit near log 3 / log 2, the Moran dimension exactly.
  const std::string sierpinski =
      file("dim_sierpinski.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 6}})");
  const Run r = cifs_cli("dimension " + sierpinski + " --depth 12 --json");
  INFO("stderr: " << r.err);
  REQUIRE(r.status == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["depth"] == 12);
  CHECK(j["points"] == 531442);  // 3^12 nodes and the end point
  CHECK(std::abs(j["box_counting"]["dimension"].get<double>() - std::log2(3.0)) < 0.03);
  CHECK(j["similarity_dimension"].get<double>() == Approx(std::log2(3.0)).epsilon(1e-12));
  CHECK(j["box_counting"]["counts"].size() > 5);
  // A user fit range is reported back.
  const nlohmann::json k = nlohmann::json::parse(
      cifs_cli("dimension " + sierpinski + " --depth 9 --min-level 2 --max-level 5 --json").out);
  CHECK(k["box_counting"]["levels"] == nlohmann::json::array({2, 5}));
  // A shape file: a smooth curve, no similarity dimension (and the text report says why).
  const Run c = cifs_cli("dimension " CIFS_EXAMPLES_DIR "/shapes/wave.json --depth 16");
  INFO("stderr: " << c.err);
  CHECK(c.status == 0);
  CHECK_THAT(c.out, Catch::Contains("box-counting dimension "));
  // Rational: no piece-size bound, so the fine end rests on the points-per-box rule (0.978 measured).
  const nlohmann::json w = nlohmann::json::parse(
      cifs_cli("dimension " CIFS_EXAMPLES_DIR "/shapes/wave.json --depth 16 --json").out);
  CHECK(std::abs(w["box_counting"]["dimension"].get<double>() - 1) < 0.03);
  CHECK(w["similarity_dimension"].is_null());
  CHECK_THAT(c.out, Catch::Contains("similarity dimension: not applicable"));
  // Bad input: one clear error line, exit status 2.
  check_error(cifs_cli("dimension " + sierpinski + " --depth 2"), "evaluate deeper");
  check_error(cifs_cli("dimension " + sierpinski + " --depth -1"), "negative");
  check_error(cifs_cli("dimension /no/such/file.json"), "/no/such/file.json");
  // The proven route asked for (--relative-piece-size 0: automatic tolerance, no fallback): where the proven
  // bound leaves too few scales, the error names the way out; a rational piece without a Cartesian
  // bound says so instead of "inf wide".
  check_error(cifs_cli("dimension " CIFS_EXAMPLES_DIR
                       "/experiments/hills.json --max-points 20000 --relative-piece-size 0"),
              "measure a depth evaluation (--depth K)");
  check_error(cifs_cli("dimension " CIFS_EXAMPLES_DIR
                       "/experiments/wave_fractal.json --max-points 20000 --relative-piece-size 0"),
              "has no Cartesian size bound at depth");
}

TEST_CASE("cifs dimension: a smooth surface's range reaches 2, which its boxes read low",
          "[cli][dimension]") {
  const Run r = cifs_cli("dimension " CIFS_EXAMPLES_DIR "/experiments/hills.json --max-points 250000 --json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto& box = j["box_counting"];
  // The boundary's boxes pull the slope below 2 at this budget, beyond its uncertainty: the proven
  // cover (pieces tile the patch) grows as ε^-2 and widens the range up to it.
  CHECK(box["dimension"].get<double>() + box["uncertainty"].get<double>() < 2);
  REQUIRE(j["cover"].is_object());
  CHECK(std::abs(j["cover"]["dimension"].get<double>() - 2) < 0.1);
  CHECK(box["range"][0].get<double>() <= 2);
  CHECK(box["range"][1].get<double>() >= 2);
  // Koch's pieces (ratio 1/3) count in steps as ε halves: no cover is claimed.
  const Run koch = cifs_cli("dimension " CIFS_EXAMPLES_DIR "/experiments/koch.json --json");
  REQUIRE(koch.status == 0);
  CHECK(nlohmann::json::parse(koch.out)["cover"].is_null());
}

TEST_CASE("cifs dimension: tolerance samples by default", "[cli][dimension]") {
  const auto dim = [](const std::string& args) {
    const Run r = cifs_cli("dimension " CIFS_EXAMPLES_DIR "/" + args + " --json");
    INFO(args << ": " << r.err);
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["mode"] == "tolerance");
    CHECK(j["relaxed"].empty());
    CHECK(j["box_counting"]["epsilon"][1].get<double>() >= 2 * j["resolution"].get<double>());
    return j["box_counting"]["dimension"].get<double>();
  };
  CHECK(std::abs(dim("experiments/sierpinski.json") - std::log2(3.0)) < 0.01);
  CHECK(std::abs(dim("experiments/koch.json --max-points 1048576") - std::log(4.0) / std::log(3.0)) < 0.01);
  CHECK(std::abs(dim("shapes/wave.json --max-points 1048576") - 1) < 0.02);  // rational: Cartesian bound
  CHECK(dim("experiments/clover_fractal.json --max-points 1048576") >= 1);
  check_error(
      cifs_cli("dimension " CIFS_EXAMPLES_DIR
               "/experiments/koch.json --relative-piece-size 1e-9 --max-points 1000"),
      "--relative-piece-size 1e-09 needs more than 1000 points; raise --relative-piece-size or --max-points");
  // Named as given, not as the absolute piece size it was scaled to (the estimate's refusal too).
  check_error(cifs_cli("dimension " CIFS_EXAMPLES_DIR
                       "/shapes/cubic.json --relative-piece-size 1e-7 --max-points 50000000"),
              "--relative-piece-size 1e-07 needs about 5.53e+07 points (estimated from coarser tolerances), "
              "more than the "
              "limit of 50000000; raise --relative-piece-size or --max-points");
}

TEST_CASE("cifs dimension: the default route chooses itself and reports an uncertainty", "[cli][dimension]") {
  // Closed forms within the reported uncertainty: Koch, Sierpinski (proven route), a smooth curve.
  const Dimension koch = dimension_of("experiments/koch.json --max-points 1048576");
  CHECK(koch.report["route"].get<std::string>().starts_with("proven tolerance sample"));
  CHECK(std::abs(koch.value - std::log(4.0) / std::log(3.0)) <= koch.uncertainty);
  const Dimension sierpinski = dimension_of("experiments/sierpinski.json");
  CHECK(std::abs(sierpinski.value - std::log2(3.0)) <= sierpinski.uncertainty);
  const Dimension circle = dimension_of("experiments/circle.json --max-points 524288");
  CHECK(std::abs(circle.value - 1) <= circle.uncertainty);
  // A smooth surface: 2 less the boundary's bias (perimeter·ε/area, ~0.07 at 2^19 points), which
  // the drift of the local slopes does not measure.
  const Dimension hills = dimension_of("experiments/hills.json --max-points 524288");
  // The proven route: its search counted the leaves within the budget (an estimate above it used to
  // refuse the sample and send hills to a depth evaluation).
  CHECK(hills.report["route"].get<std::string>().starts_with("proven tolerance sample"));
  CHECK(hills.report["resolution_estimated"] == false);
  CHECK(std::abs(hills.value - 2) <= hills.uncertainty + 0.1);

  // Fractal supports that failed before (no closed form): a number at two budgets 8× apart (the
  // larger's coarser comparison is not the smaller's sample), which agree within the larger
  // reported uncertainty.
  const auto stable = [](const std::string& file, const std::string& mode, const std::string& reason) {
    const Dimension a = dimension_of(file + " --max-points 131072");
    const Dimension b = dimension_of(file + " --max-points 1048576");
    INFO(file << ": " << a.value << " ± " << a.uncertainty << ", " << b.value << " ± " << b.uncertainty);
    for (const Dimension* d : {&a, &b}) {
      CHECK(d->report["mode"] == mode);
      CHECK_THAT(d->report["fallback_reason"].get<std::string>(), Catch::Contains(reason));
      CHECK(!d->report["relaxed"].empty());
      CHECK(d->report["box_counting"]["coarser_dimension"].is_number());
      CHECK(d->uncertainty < 0.5);
    }
    CHECK(std::abs(a.value - b.value) <= std::max(a.uncertainty, b.uncertainty));
    return b;
  };
  // Rational and perturbed: no Cartesian bound, a depth evaluation with an estimated resolution.
  const Dimension wave = stable("experiments/wave_fractal.json", "depth", "no Cartesian size bound");
  CHECK(wave.report["resolution_estimated"] == true);
  CHECK(wave.value + wave.uncertainty >= 1);  // a curve: at least 1
  // Signed surface matrices: the proven tolerance sample is beyond the budget.
  stable("experiments/junction_fractal.json", "depth", "points; raise the point limit");
  // A classic IFS whose proven bound is loose: the proven sample, refitted with relaxed rules.
  const Dimension fern = stable("experiments/fern.json", "tolerance", "only 0 scale(s)");
  CHECK(fern.value > 1.4);
  CHECK(fern.value < 2);

  // The text report names the route, the uncertainty and what was relaxed.
  const Run t = cifs_cli("dimension " CIFS_EXAMPLES_DIR "/experiments/wave_fractal.json --max-points 65536");
  REQUIRE(t.status == 0);
  CHECK_THAT(t.out, Catch::Contains("route: depth evaluation"));
  CHECK_THAT(t.out, Catch::Contains("resolution estimated from the leaves' nets, not proven"));
  CHECK_THAT(t.out, Catch::Contains(" ± "));
  CHECK_THAT(t.out, Catch::Contains("relaxed: "));
  // --depth on a rational perturbed curve: the proven resolution is infinite, the estimate stands in.
  const Dimension depth = dimension_of("experiments/wave_fractal.json --depth 14");
  CHECK(depth.report["resolution_estimated"] == true);
  CHECK(std::isfinite(depth.report["resolution"].get<double>()));
}

TEST_CASE("cifs dimension refuses control points spanning more than a double", "[cli][reliability]") {
  // It said "tolerance sample: epsilon is -nan, must be finite and ≥ 0".
  const std::string huge = file("huge.json", R"({"curve": {"degree": 2, "knots": [0, 0, 0, 1, 1, 1],
      "points": [[1e308, 0], [-1.7e308, 1], [1e308, 0]]}})");
  check_error(
      cifs_cli("dimension " + huge),
      "the control points span more than a double holds (coordinates up to 1.7e+308); scale the shape "
      "down");
}
