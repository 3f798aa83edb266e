// SPDX-License-Identifier: MIT
// cifs attractor, automaton and check on curves and surfaces, run as a user runs them: points against
// Cox–de Boor, streamed files, chaos games, and the refusals of work that cannot be done (tiny
// tolerances, huge depths, bounds estimated before the work).
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli_fixtures.hpp"
#include "apps/cli_runner.hpp"

#include "cifs/io/io.hpp"
#include "cifs/mesh.hpp"
#include "cifs/nurbs/knots.hpp"
#include "cifs/nurbs/surface.hpp"

using namespace cifs;
using nlohmann::json;

using namespace cifs_test;

namespace {

/// The dyadic parameters of depth K over the breakpoints of one direction (the mesh's grid lines).
std::vector<double> dyadic(const std::vector<double>& breaks, int depth) {
  std::vector<double> out;
  const int n = 1 << depth;
  for (std::size_t a = 0; a + 1 < breaks.size(); ++a)
    for (int j = 0; j < n; ++j) out.push_back(breaks[a] + (breaks[a + 1] - breaks[a]) * j / n);
  out.push_back(breaks.back());
  return out;
}

}  // namespace

TEST_CASE("cifs attractor -o: refusals name the memory or the disk, and leave nothing", "[cli][stream]") {
  const auto folder = scratch() / "refusals";
  std::filesystem::create_directories(folder);
  const std::string shape = file("refusals/c.json", kCurve);
  const auto count = [&] { return std::distance(std::filesystem::directory_iterator(folder), {}); };
  // 3 · 2^24 + 1 points of 4 homogeneous coordinates do not fit the 1 GiB an SVG is drawn in…
  check_error(cifs_cli("attractor " + shape + " --depth 24 --format svg"),
              "attractor: depth 24 gives 50331649 points (1.5 GiB), more than the 1 GiB held in memory for "
              "SVG; write them as points (json, npy, ply, obj), which are streamed");
  // …while a file of any size is refused only for the disk's free space (3 · 2^40 + 1 points · 24 bytes).
  check_error(cifs_cli("attractor " + shape + " --depth 40 -o " + (folder / "big.npy").string()),
              (folder / "big.npy").string() + ": the file needs 79165 GB of disk space, ");
  check_error(cifs_cli("attractor " + shape + " --depth 40 -o " + (folder / "big.json").string()),
              (folder / "big.json").string() + ": the file needs about ");
  check_error(cifs_cli("attractor " + shape + " --depth 3 -o " + (folder / "p.txt").string()),
              "expected a .json, .npy, .ply, .obj or .svg file name");
  check_error(cifs_cli("attractor " + shape + " --depth 3 --format obj -o " + (folder / "p.json").string()),
              "--format obj: -o " + (folder / "p.json").string() + " names json");
  check_error(cifs_cli("attractor " + shape + " --chaos 10 -o " + (folder / "p.obj").string()), "unordered");
  check_error(cifs_cli("eval " + shape + " --at 9 -o " + (folder / "p.npy").string()), "outside the domain");
  check_error(cifs_cli("eval " + shape + " --at 1 -o " + (folder / "p.svg").string()),
              "a point set is written as .json, .npy, .ply or .obj");
  CHECK(count() == 1);  // c.json only: no output, no temporary
  // SVG is drawn from memory (fitted to all the points), written through the same atomic writer.
  const Run svg = cifs_cli("attractor " + shape + " --depth 4 -o " + (folder / "p.svg").string());
  CHECK(svg.status == 0);
  CHECK_THAT(slurp(folder / "p.svg"), Catch::StartsWith("<svg"));
}

TEST_CASE("cifs automaton, attractor and check", "[cli]") {
  const std::string shape = file("c.json", kCurve);
  const auto c = std::get<nurbs::Curve>(io::read_shape(shape));
  const json a = json::parse(cifs_cli("automaton " + shape).out);
  CHECK(a["initial"].size() == 3);
  CHECK(a["transitions"].size() == 2 * a["states"].size());
  CHECK_THAT(cifs_cli("automaton " + shape + " --format dot").out, Catch::StartsWith("digraph G {"));
  CHECK(json::parse(cifs_cli("automaton " + shape + " --minimize").out)["states"].size() <=
        a["states"].size());

  // Attractor points at depth 3: 3 segments × 8 starts + the end, on the curve at the dyadic parameters.
  const json pts = json::parse(cifs_cli("attractor " + shape + " --depth 3").out)["points"];
  REQUIRE(pts.size() == 25);
  const double starts[] = {0, 1, 2};
  const double lengths[] = {1, 1, 2};
  for (std::size_t k = 0; k < 25; ++k) {
    const std::size_t s = std::min<std::size_t>(k / 8, 2);
    const double u = k == 24 ? 4.0 : starts[s] + lengths[s] * static_cast<double>(k % 8) / 8;
    const Point p = nurbs::evaluate(c, u);
    for (int i = 0; i < 3; ++i)
      CHECK(pts[k][static_cast<std::size_t>(i)].get<double>() == Approx(p(i)).margin(1e-13));
  }
  const Run tol = cifs_cli("attractor " + shape + " --piece-size 0.01 --format obj");
  REQUIRE(tol.status == 0);
  CHECK_THAT(tol.out, Catch::Contains("\nl 1 2 3"));
  CHECK_THAT(cifs_cli("attractor " + shape + " --depth 2 --format svg").out, Catch::StartsWith("<svg"));
  // A chordal deviation: the polyline holds every curve point (Cox–de Boor, dense) within 0.01,
  // with far fewer points than pieces of that size.
  const json chords = json::parse(cifs_cli("attractor " + shape + " --deviation 0.01").out)["points"];
  Points L(static_cast<Eigen::Index>(chords.size()), 3);
  for (std::size_t k = 0; k < chords.size(); ++k)
    for (int i = 0; i < 3; ++i)
      L(static_cast<Eigen::Index>(k), i) = chords[k][static_cast<std::size_t>(i)].get<double>();
  double far = 0;
  for (int j = 0; j <= 3000; ++j) {
    const Eigen::RowVector3d p = nurbs::evaluate(c, 4.0 * j / 3000);
    double near = std::numeric_limits<double>::infinity();
    for (Eigen::Index k = 1; k < L.rows(); ++k) {
      const Eigen::RowVector3d a0 = L.row(k - 1), d = L.row(k) - L.row(k - 1);
      const double t = std::clamp((p - a0).dot(d) / d.squaredNorm(), 0.0, 1.0);
      near = std::min(near, (p - a0 - t * d).norm());
    }
    far = std::max(far, near);
  }
  CHECK(far <= 0.01);
  const json pieces = json::parse(cifs_cli("attractor " + shape + " --piece-size 0.01").out)["points"];
  CHECK(5 * chords.size() < pieces.size());
  check_error(cifs_cli("attractor " + shape + " --deviation -1"), "--deviation: must be a positive number");

  const Run ok = cifs_cli("check " + shape + " --depth 6 --json");
  REQUIRE(ok.status == 0);
  const json report = json::parse(ok.out);
  CHECK(report["pass"] == true);
  CHECK(report["segments"].size() == 3);
  CHECK(report["nets"]["max_rel"].get<double>() <= 1e-12);
  // An impossible tolerance fails with exit status 1 and a report, not an error.
  const Run fail = cifs_cli("check " + shape + " --depth 6 --relative-tolerance 1e-30");
  CHECK(fail.status == 1);
  CHECK_THAT(fail.out, Catch::Contains("FAIL"));

  // Chaos game: reproducible from the printed seed, points on the curve's attractor.
  const json chaos = json::parse(cifs_cli("attractor " + shape + " --chaos 200").out);
  REQUIRE(chaos["points"].size() == 200);
  const std::string seed = std::to_string(chaos["seed"].get<std::uint64_t>());
  CHECK(json::parse(cifs_cli("attractor " + shape + " --chaos 200 --seed " + seed).out) == chaos);
  CHECK(json::parse(cifs_cli("attractor " + shape + " --chaos 200 --seed 7").out)["seed"] == 7);
  check_error(cifs_cli("attractor " + shape + " --chaos 10 --format svg"), "unordered");
  check_error(cifs_cli("attractor " + shape + " --chaos -5"), "--chaos -5");
  check_error(cifs_cli("attractor " + shape),
              "exactly one of --depth K, --piece-size E, --deviation D and --chaos N");
  check_error(cifs_cli("attractor " + shape + " --depth 3 --format png"), "--format 'png'");
  check_error(cifs_cli("attractor " + shape + " --depth 40"), "GB of disk space");
  check_error(cifs_cli("check " + shape + " --depth 31"), "depth 31 is outside [0, 30]");
  // --tolerance meant three things; an old command line is told the new name of each.
  check_error(cifs_cli("attractor " + shape + " --tolerance 0.01"),
              "attractor --tolerance is now --piece-size (every piece smaller than E) or --deviation");
  check_error(cifs_cli("check " + shape + " --tolerance 1e-9"),
              "check --tolerance is now --relative-tolerance");
  check_error(cifs_cli("dimension " + shape + " --tolerance 0"),
              "dimension --tolerance is now --relative-piece-size");

  // Surfaces: per patch, the same options and report.
  const std::string surface = file("s.json", kSurface);
  const Run sok = cifs_cli("check " + surface + " --depth 5 --json");
  REQUIRE(sok.status == 0);
  const json sreport = json::parse(sok.out);
  CHECK(sreport["pass"] == true);
  REQUIRE(sreport["patches"].size() == 1);
  CHECK(sreport["patches"][0]["interval"] == json::parse("[[0, 1], [0, 1]]"));
  CHECK(sreport["points"]["max_rel"].get<double>() <= 1e-12);
  const Run stext = cifs_cli("check " + surface + " --depth 3");
  CHECK(stext.status == 0);
  CHECK_THAT(stext.out, Catch::Contains("1 patches") && Catch::Contains("PASS"));
  CHECK(cifs_cli("check " + surface + " --depth 3 --relative-tolerance 1e-30").status == 1);
  check_error(cifs_cli("check " + surface + " --depth 14"), "lower the depth");
  // A surface's automaton is its tensor product: one patch, four children per state.
  const json sa = json::parse(cifs_cli("automaton " + file("s.json", kSurface)).out);
  CHECK(sa["initial"].size() == 1);
}

TEST_CASE("cifs attractor refuses subnormal tolerances instead of crashing", "[cli][reliability]") {
  // top / ε overflowed to inf for ε below ~1e-307; the cast of its log to int was undefined, the
  // ladder was skipped and the estimate read an empty vector (SIGSEGV).
  const std::string cubic = file("tiny_cubic.json", kCubic);
  for (const std::string option : {"--piece-size 3e-308", "--piece-size 2.2e-308", "--piece-size 5e-324",
                                   "--deviation 5e-324", "--deviation 1e-310"})
    check_quick_error("attractor " + cubic + " " + option, "points");
}

TEST_CASE("cifs attractor refuses a huge depth at once", "[cli][reliability]") {
  // The node counts were iterated 10^9 times (27 CPU-s) before the depth was refused.
  const std::string cubic = file("deep_cubic.json", kCubic);
  check_quick_error("attractor " + cubic + " --depth 1000000000", "gives more than 2^64 points");
}

TEST_CASE("cifs: tolerance modes are bounded before the work, with the estimated figure",
          "[cli][reliability]") {
  // Each ran for minutes or hours (or ended in std::bad_alloc) without a figure: the leaves are now
  // estimated from coarser tolerances (ifs::estimate_tolerance_leaves) and refused at once.
  const std::string shapes = std::string(CIFS_EXAMPLES_DIR) + "/shapes/";
  const std::string tall = file("tall.json", R"({"curve": {"degree": 3, "knots": [0, 0, 0, 0, 1, 2, 2, 2, 2],
      "points": [[0, 0, 0], [1, 2, 0], [2, 0, 1e23], [3, 1, 0], [4, 0, 0]]}})");
  const std::string out = (scratch() / "tolerance.npy").string();
  const std::pair<std::string, std::string> cases[] = {
      // The cubic's length is about 4.6: 4.6e10 pieces of 1e-9 (counted at 1e-4: 421642).
      {"attractor " + shapes + "cubic.json --piece-size 1e-9", "--piece-size 1e-09: about 4.6"},
      {"attractor " + shapes + "cubic.json --piece-size 1e-9 -o " + out,
       "above the limit of 1.07e+09 streamed"},
      {"attractor " + tall + " --piece-size 0.01", "e+25 points"},
      {"attractor " + shapes + "saddle.json --piece-size 1e-4 -o " + out, "needs about 2.0"},
      {"attractor " + shapes + "saddle.json --piece-size 1e-9 -o " + out, "e+20 points"},
      {"dimension " + shapes + "cubic.json --max-points 1099511627776",
       "--max-points 1099511627776: expected 1 to"},
  };
  // Refused in 0.1 s in Release; ASan + UBSan make the estimate about 25× slower (saddle at 1e-4:
  // 1.9 s unloaded, 2.3 s on the loaded CI machine), and the bound is against minutes, not a speed.
  constexpr double kSeconds = cifs_test::kSanitized ? 20 : 2;
  for (const auto& [command, needle] : cases) {
    const auto start = std::chrono::steady_clock::now();
    check_error(cifs_cli(command), needle);
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < kSeconds);
  }
  CHECK(!std::filesystem::exists(out));
}

TEST_CASE("cifs warns when an SVG drops z", "[cli][reliability]") {
  // A 3-D curve or polygon drawn as SVG lost z silently; it is still drawn (a top view), with one
  // warning naming the range of z that was dropped. Quadratic Bézier z = 0, 2, −1: at depth 2 the
  // points t = 0, 1/4, 1/2, 3/4, 1 have z = 0, 0.6875, 0.75, 0.1875, −1 (B(t) = 4t(1 − t) − t²).
  const std::string bent = file("bent.json", R"({"curve": {"degree": 2, "knots": [0, 0, 0, 1, 1, 1],
      "points": [[0, 0, 0], [1, 1, 2], [2, 0, -1]]}})");
  const std::string flat = file("flat.json", R"({"curve": {"degree": 2, "knots": [0, 0, 0, 1, 1, 1],
      "points": [[0, 0, 0], [1, 1, 0], [2, 0, 0]]}})");
  const std::string polygon = file(
      "bent_polygon.json", R"({"polygon": {"points": [[0, 0, 1], [1, 0, 2], [1, 1, 3]], "closed": true}})");
  const Run r = cifs_cli("attractor " + bent + " --depth 2 --format svg");
  CHECK(r.status == 0);
  CHECK_THAT(r.out, Catch::StartsWith("<svg") || Catch::Contains("<svg"));
  CHECK(
      r.err ==
      "cifs: warning: the SVG is a top view (x, y): z (from -1 to 0.75) is dropped; write json, npy, ply or "
      "obj to keep it\n");
  const Run plane = cifs_cli("attractor " + flat + " --depth 2 --format svg");
  CHECK(plane.status == 0);
  CHECK(plane.err.empty());
  const Run refined = cifs_cli("scheme chaikin --refine " + polygon + " --steps 1 --format svg");
  CHECK(refined.status == 0);
  // Chaikin keeps z within the polygon's: from 1 to 3 at most, the corners cut at 1/4 and 3/4.
  CHECK_THAT(refined.err,
             Catch::StartsWith("cifs: warning: the SVG is a top view (x, y): z (from 1.25 to 2.75)"));
}

TEST_CASE("cifs check names its depth and tolerance, not check_curve", "[cli][reliability][messages]") {
  const std::string cubic = kExamplesDir + "/shapes/cubic.json";
  check_message(cifs_cli("check " + cubic + " --depth 31"), "the check depth 31 is outside [0, 30]",
                "check: depth");
  // An infinite tolerance would pass anything; it was printed as "(got inf)".
  check_message(cifs_cli("check " + cubic + " --relative-tolerance inf"),
                "the check tolerance is not a finite number; give a positive finite tolerance", "(got inf)");
}

TEST_CASE("cifs automaton and attractor take surfaces", "[cli][newuser]") {
  const auto s = std::get<nurbs::Surface>(io::read_shape(kHills));
  const auto bu = nurbs::breakpoints(s.knots[0], s.degree[0]),
             bv = nurbs::breakpoints(s.knots[1], s.degree[1]);
  const std::size_t patches = (bu.size() - 1) * (bv.size() - 1);

  // The tensor-product automaton: one initial entry per patch, four children per state.
  const Run au = cifs_cli("automaton " + kHills);
  REQUIRE(au.status == 0);
  const json a = json::parse(au.out);
  CHECK(a["initial"].size() == patches);
  std::map<int, int> children;
  for (const json& t : a["transitions"]) ++children[t["from"].get<int>()];
  CHECK(children.size() == a["states"].size());
  for (const auto& [state, n] : children) CHECK(n == 4);
  CHECK_THAT(cifs_cli("automaton " + kHills + " --format dot").out, Catch::StartsWith("digraph"));

  // Depth 2: the grid of the quad mesh, u-major, against Cox–de Boor at the dyadic parameters.
  const Run at = cifs_cli("attractor " + kHills + " --depth 2");
  REQUIRE(at.status == 0);
  const json points = json::parse(at.out)["points"];
  const std::vector<double> us = dyadic(bu, 2), vs = dyadic(bv, 2);
  REQUIRE(points.size() == us.size() * vs.size());
  const double scale = nurbs::cartesian_points(s).cwiseAbs().maxCoeff();
  double worst = 0;
  for (std::size_t i = 0; i < us.size(); ++i)
    for (std::size_t j = 0; j < vs.size(); ++j) {
      const Point p = nurbs::evaluate(s, us[i], vs[j]);
      for (Eigen::Index k = 0; k < p.size(); ++k)
        worst = std::max(
            worst, std::abs(points[i * vs.size() + j][static_cast<std::size_t>(k)].get<double>() - p(k)));
    }
  CHECK(worst <= 1e-12 * scale);

  // OBJ and PLY: the mesh itself, streamed into the file; npy the grid.
  const auto obj = scratch() / "hills2.obj";
  REQUIRE(cifs_cli("attractor " + kHills + " --depth 2 -o " + obj.string()).status == 0);
  const Mesh mesh = io::read_mesh(obj);
  CHECK(mesh.vertices.rows() == static_cast<Eigen::Index>(us.size() * vs.size()));
  CHECK(face_count(mesh) == 16 * patches);
  const Run ply = cifs_cli("attractor " + kHills + " --depth 1 -o " + (scratch() / "hills1.ply").string());
  CHECK_THAT(ply.out, Catch::Contains("vertices") && Catch::Contains("quads"));

  // Chaos game and tolerance: unordered points, each on the surface's bounding box at least.
  const json chaos = json::parse(cifs_cli("attractor " + kHills + " --chaos 500 --seed 3").out);
  CHECK(chaos["points"].size() == 500);
  CHECK(chaos["seed"] == 3);
  const Run tol = cifs_cli("attractor " + kHills + " --piece-size 0.5");
  REQUIRE(tol.status == 0);
  CHECK(json::parse(tol.out)["points"].size() >= patches);
  check_error(cifs_cli("attractor " + kHills + " --depth 2 --format svg"), "draws curves");
  check_error(cifs_cli("attractor " + kHills + " --chaos 10 --format obj"), "unordered");
}
