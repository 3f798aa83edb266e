// SPDX-License-Identifier: MIT
// The cifs command line, run as a user runs it: exit status, stdout and stderr.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli_runner.hpp"

#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"

using namespace cifs;
using nlohmann::json;

using namespace cifs_test;

namespace {

const char* kCurve = R"({"curve": {"degree": 3, "knots": [0,0,0,0,1,2,4,4,4,4],
  "points": [[0,0,0],[1,2,0],[3,3,1],[4,0,0],[6,1,2],[7,3,0]], "weights": [1,2,1,0.5,1,1]}})";

const char* kSurface = R"({"surface": {"degree": [2, 1], "knots": [[0,0,0,1,1,1],[0,0,1,1]],
  "points": [[[0,0,0],[0,1,0]], [[1,0,1],[1,1,1]], [[2,0,0],[2,1,3]]]}})";

}  // namespace

TEST_CASE("cifs eval prints the points in parameter order", "[cli]") {
  const std::string shape = file("c.json", kCurve);
  const auto c = std::get<nurbs::Curve>(io::read_shape(shape));
  const Run r = cifs_cli("eval " + shape + " --at 4 --at 0.25 --at 1");
  REQUIRE(r.status == 0);
  const json pts = json::parse(r.out)["points"];
  REQUIRE(pts.size() == 3);
  const double us[] = {4, 0.25, 1};
  for (int i = 0; i < 3; ++i) {
    const Point p = nurbs::evaluate_basis(c, us[i]);
    for (int k = 0; k < 3; ++k)
      CHECK(pts[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)].get<double>() == p(k));
  }
  const json samples = json::parse(cifs_cli("eval " + shape + " --samples 5").out)["points"];
  REQUIRE(samples.size() == 5);
  CHECK(samples[4][0].get<double>() == 7.0);  // the domain end is the last control point
}

TEST_CASE("cifs eval on a surface takes U,V and grids", "[cli]") {
  const std::string shape = file("s.json", kSurface);
  const Run r = cifs_cli("eval " + shape + " --at 1,1 --at 0.5,0.25");
  REQUIRE(r.status == 0);
  const json pts = json::parse(r.out)["points"];
  CHECK(pts[0] == json::array({2.0, 1.0, 3.0}));
  CHECK(json::parse(cifs_cli("eval " + shape + " --samples 3").out)["points"].size() == 9);
}

TEST_CASE("cifs eval streams a grid whose rows are longer than a chunk in bounded memory", "[cli][stream]") {
  const std::string shape = file("s.json", kSurface);
  const auto s = std::get<nurbs::Surface>(io::read_shape(shape));
  // 2·10^9 × 2·10^9 points to a pipe: `head` keeps the first 65,540 points of row 0 (a chunk boundary at
  // 65,536), then cifs meets the closed pipe. Under a 1 GiB address space: the parameters of a whole
  // row (16 GB) were once made first.
  const int n = 2000000000;
  const Run r =
      cifs_cli("eval " + shape + " --samples " + std::to_string(n) + " 2>/dev/null | head -c 4000000", "",
               address_space_cap(1));
  REQUIRE_THAT(r.out, Catch::StartsWith("{\"points\":[["));
  std::istringstream text(r.out.substr(std::string("{\"points\":[").size()));
  const nurbs::Domain u = nurbs::domain(s, nurbs::Direction::u), v = nurbs::domain(s, nurbs::Direction::v);
  const double u0 = nurbs::uniform_parameters(u, n, 0, 1)[0];
  const int want = 65540;
  int row = 0;
  for (char c = 0; row < want && text >> c && c == '[';) {
    double x = 0, y = 0, z = 0;
    char comma1 = 0, comma2 = 0, close = 0, next = 0;
    if (!(text >> x >> comma1 >> y >> comma2 >> z >> close >> next)) break;
    const Point p = nurbs::evaluate(s, u0, nurbs::uniform_parameters(v, n, row, 1)[0]);
    INFO("point " << row);
    CHECK(std::abs(x - p(0)) <= 1e-12);
    CHECK(std::abs(y - p(1)) <= 1e-12);
    CHECK(std::abs(z - p(2)) <= 1e-12);
    ++row;
  }
  CHECK(row == want);
}

TEST_CASE("cifs insert prints the same curve with more knots", "[cli]") {
  const std::string shape = file("c.json", kCurve);
  const Run r = cifs_cli("insert " + shape + " --knot 1.5 --knot 3 --knot 3");
  REQUIRE(r.status == 0);
  const auto refined = std::get<nurbs::Curve>(io::parse_shape_json(r.out, "stdout"));
  const auto c = std::get<nurbs::Curve>(io::read_shape(shape));
  CHECK(refined.knots.size() == c.knots.size() + 3);
  for (double u : nurbs::uniform_parameters(nurbs::domain(c), 41))
    CHECK((nurbs::evaluate(refined, u) - nurbs::evaluate(c, u)).norm() <= 1e-12 * 7);
  const std::string surface = file("s.json", kSurface);
  const Run rs = cifs_cli("insert " + surface + " --dir v --knot 0.5");
  REQUIRE(rs.status == 0);
  CHECK(std::get<nurbs::Surface>(io::parse_shape_json(rs.out, "stdout")).count[1] == 3);
}

TEST_CASE("cifs info describes the shape", "[cli]") {
  const json info = json::parse(cifs_cli("info " + file("c.json", kCurve)).out);
  CHECK(info["type"] == "curve");
  CHECK(info["degree"] == 3);
  CHECK(info["control_points"] == 6);
  CHECK(info["segments"] == 3);
  CHECK(info["rational"] == true);
  CHECK(info["domain"] == json::array({0.0, 4.0}));
}

TEST_CASE("cifs exits 1 with one line when stdout cannot be written", "[cli][stdout]") {
  // /dev/full accepts the open and fails every write: small outputs fail only at the final flush,
  // large ones (the attractor, megabytes) while they are written.
  const std::string shape = file("c.json", kCurve), examples = CIFS_EXAMPLES_DIR;
  const std::string polygon = examples + "/shapes/hepta.json", mesh = examples + "/meshes/cube.obj";
  const std::string expected =
      std::string("cifs: cannot write to standard output: ") + std::strerror(ENOSPC) + "\n";
  for (const std::string& args : std::vector<std::string>{
           "info " + shape, "eval " + shape + " --samples 3", "check " + shape,
           "insert " + shape + " --knot 0.5", "automaton " + shape + " --format dot",
           "attractor " + shape + " --depth 16", "scheme six-point --analyze", "scheme --list",
           "scheme chaikin --refine " + polygon, "subdivide " + mesh + " --scheme catmull-clark",
           "info " + mesh, "dimension " + examples + "/experiments/sierpinski.json --depth 10",
           "render " + examples + "/experiments/wave.json -o " + (scratch() / "full.exr").string() +
               " --quiet",
           "--help", "eval --help", "--version"}) {
    const Run r = cifs_cli(args, "/dev/full");
    INFO(args);
    CHECK(r.status == 1);
    CHECK(r.err == expected);
  }
}

TEST_CASE("cifs reports bad input on one line and exits 2", "[cli]") {
  const std::string good = file("c.json", kCurve);
  check_error(cifs_cli("eval /nonexistent.json --at 0"), "/nonexistent.json: cannot open");
  check_error(cifs_cli("eval " + file("bad.json", "{\"curve\": ") + " --at 0"), "malformed JSON");
  check_error(
      cifs_cli("eval " +
               file("dec.json", R"({"curve": {"degree": 1, "knots": [0,0,2,1], "points": [[0],[1]]}})") +
               " --at 0"),
      "curve.knots[3]: 1 is less than the previous knot 2");
  // Seeds out of range are refused, not clamped to 2^64 − 1.
  for (const std::string seed : {"-1", "18446744073709551616", "1e23", "7x"})
    check_error(cifs_cli("attractor " + good + " --chaos 3 --seed " + seed),
                "--seed: '" + seed + "' is not an integer from 0 to 18446744073709551615");
  const json top = json::parse(cifs_cli("attractor " + good + " --chaos 3 --seed 18446744073709551615").out);
  CHECK(top["seed"].get<std::uint64_t>() == 18446744073709551615ULL);
  check_error(cifs_cli("eval " +
                       file("inf.json",
                            R"({"curve": {"degree": 1, "knots": [0,0,1e400,1e400], "points": [[0],[1]]}})") +
                       " --at 0"),
              "number overflow parsing '1e400'");
  check_error(
      cifs_cli("eval " +
               file("cnt.json", R"({"curve": {"degree": 2, "knots": [0,0,1,1], "points": [[0],[1]]}})") +
               " --at 0"),
      "too few");
  check_error(
      cifs_cli(
          "eval " +
          file("w.json",
               R"({"curve": {"degree": 1, "knots": [0,0,1,1], "points": [[0],[1]], "weights": [1,-1]}})") +
          " --at 0"),
      "weights[1]");
  check_error(cifs_cli("eval " + good + " --at 4.5"), "parameter 4.5 is outside the domain [0, 4]");
  check_error(cifs_cli("eval " + good + " --at nan"), "--at 'nan': not a finite number");
  check_error(cifs_cli("eval " + good + " --at 1,2"), "a curve takes one parameter");
  check_error(cifs_cli("eval " + good), "give --at U");
  check_error(cifs_cli("eval " + good + " --samples -3"), "--samples -3");
  // Points are streamed to stdout as to a file; a stdout redirected to a file is held to the disk's
  // free space before any work, as -o is (2·10^9 squared grid points: about 4·10^19 bytes).
  // Refused before the 2·10^9 parameters are made (they once were: 16 GB and a minute of page faults).
  check_error(
      cifs_cli("eval " + file("big.json", kSurface) + " --samples 2000000000", "", address_space_cap(1)),
      "stdout: the file needs about ");
  check_error(cifs_cli("eval " + file("s.json", kSurface) + " --at 0.5"), "a surface takes U,V");
  check_error(cifs_cli("insert " + good + " --knot 9"), "knot 9 is outside the domain");
  check_error(cifs_cli("insert " + good + " --knot 1 --knot 1 --knot 1"), "multiplicity 4 > degree 3");
  check_error(cifs_cli("insert " + good + " --dir w --knot 1"), "--dir 'w'");
  check_error(cifs_cli("frobnicate"), "unknown command 'frobnicate'");
  check_error(cifs_cli("eval"), "shape");
  check_error(cifs_cli("info " + scratch().string()), "is a directory");
}

TEST_CASE("cifs attractor and eval -o: the file written as computed = standard output", "[cli][stream]") {
  const std::string rational = file("r.json", kCurve), surface = file("s.json", kSurface);
  const std::string closed = file("closed.json", R"({"curve": {"degree": 3, "closed": true,
    "knots": [0, 1, 2, 3.5, 4, 6], "points": [[0, 0], [2, -1], [4, 0], [3, 2], [1, 2]]}})");
  const auto same = [](const std::string& command, const std::string& format) {
    const auto path = scratch() / ("streamed." + format);
    std::filesystem::remove(path);
    const Run in_memory = cifs_cli(command + " --format " + format);
    const Run streamed = cifs_cli(command + " -o " + path.string());
    INFO(command << " " << format << ": " << streamed.err);
    REQUIRE(in_memory.status == 0);
    REQUIRE(streamed.status == 0);
    CHECK_THAT(streamed.out, Catch::StartsWith("wrote " + path.string() + ": "));
    CHECK(streamed.err.empty());  // no progress bar off a terminal
    CHECK(slurp(path) == in_memory.out);
    CHECK(in_memory.out.size() > 100);
  };
  // Stencil chunks of 2^16 points, several of them (3 · 2^16 + 1 points at depth 16). Under ASan (a few
  // seconds a run) one text and one binary writer cross the chunks; Release runs all four.
  const std::vector<std::string> chunked = cifs_test::kSanitized
                                               ? std::vector<std::string>{"json", "npy"}
                                               : std::vector<std::string>{"json", "obj", "npy", "ply"};
  for (const std::string format : {"json", "obj", "npy", "ply"}) {
    if (std::find(chunked.begin(), chunked.end(), format) != chunked.end())
      same("attractor " + rational + " --depth 16", format);
    same("attractor " + closed + " --depth 9", format);
    same("attractor " + rational + " --piece-size 0.001", format);
  }
  same("attractor " + rational + " --chaos 1000 --seed 5", "npy");
  // eval: the stdout route evaluates all parameters at once, the file route 2^16 at a time.
  const auto eval_same = [](const std::string& command) {
    const auto path = scratch() / "eval.json";
    const Run in_memory = cifs_cli(command);
    const Run streamed = cifs_cli(command + " -o " + path.string());
    INFO(command << ": " << streamed.err);
    REQUIRE(in_memory.status == 0);
    REQUIRE(streamed.status == 0);
    CHECK(slurp(path) == in_memory.out);
  };
  eval_same("eval " + rational + " --at 0.5 --at 3 --samples 150001");
  eval_same("eval " + surface + " --at 0.5,0.25 --samples 300");  // 90000 points: rows of 218 per chunk
}

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

TEST_CASE("cifs render: outputs where asked; bad experiments exit 2 and write nothing", "[cli]") {
  const auto dir = scratch() / "render";
  std::filesystem::create_directories(dir);
  const std::string exp = file("sierpinski.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 6},
      "render": {"width": 40, "height": 40}, "outputs": {"exr": "default.exr", "automaton_svg": "a.svg"}})");
  const Run r =
      cifs_cli("render " + exp + " -o " + (dir / "s.exr").string() + " --png " + (dir / "s.png").string());
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("classic IFS sierpinski, depth 6"));
  for (const char* name : {"s.exr", "s.png", "a.svg"}) CHECK(std::filesystem::is_regular_file(dir / name));
  CHECK(!std::filesystem::exists(dir / "default.exr"));  // -o replaces outputs.exr
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string bad =
      file("bad.json", R"({"ifs": "sierpinski", "evaluation": {"depth": 6, "chaos": 10}})");
  check_error(cifs_cli("render " + bad + " -o " + (dir / "s.exr").string()),
              "bad.json: evaluation: expected exactly one");
  const std::string impossible =
      file("surface_svg.json", R"({"shape": ")" CIFS_EXAMPLES_DIR R"(/shapes/saddle.json",
      "render": {"width": 16, "height": 16}, "outputs": {"svg": "s.svg"}})");
  check_error(cifs_cli("render " + impossible + " -o " + (dir / "s.exr").string()),
              "outputs.svg: SVG is for curves");
  CHECK(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST_CASE("cifs gallery runs every example experiment", "[cli]") {
  const auto out = scratch() / "gallery";
  const Run r = cifs_cli("gallery " + out.string());  // its summary: no bar, stderr is not a terminal
  REQUIRE(r.status == 0);
  // One EXR and one PNG per experiment file, plus what each asks for.
  std::size_t experiments = 0;
  for (const auto& entry : std::filesystem::directory_iterator(CIFS_EXAMPLES_DIR "/experiments"))
    experiments += entry.path().extension() == ".json";
  std::size_t exr = 0, png = 0;
  for (const auto& entry : std::filesystem::directory_iterator(out)) {
    exr += entry.path().extension() == ".exr";
    png += entry.path().extension() == ".png";
  }
  CHECK(experiments >= 10);
  CHECK(exr == experiments);
  CHECK(png == experiments);
  for (const char* name : {"wave.automaton.svg", "hills.ply", "tree.svg", "schemes/lr_bone_degree3.svg",
                           "junction_curves.svg", "junction_surfaces.ply", "junction_fractal.ply"})
    CHECK(std::filesystem::is_regular_file(out / name));
  CHECK_THAT(r.out, Catch::Contains("wave-fractal: NURBS curve") && Catch::Contains("free coefficients"));
  // The three junctions of docs/junctions.md, each with its residual.
  for (const char* name :
       {"junction-curves: junction of a b-spline(degree = 3) curve and a four-point curve",
        "junction-surfaces: junction of a b-spline(degree = 3) surface and a b-spline(degree = 2)",
        "junction-fractal: junction of a rational NURBS surface and a rational NURBS surface"})
    CHECK_THAT(r.out, Catch::Contains(name));
  // The five mesh schemes on the example meshes: closed, open (boundary) and genus 1.
  for (const char* name :
       {"subdivision_cube_catmull_clark", "subdivision_cube_doo_sabin", "subdivision_tetrahedron_loop",
        "subdivision_tetrahedron_butterfly", "subdivision_tetrahedron_sqrt3", "subdivision_open_grid",
        "subdivision_open_grid_triangles", "subdivision_torus", "subdivision_rings_loop"})
    for (const char* ext : {".exr", ".png", ".obj"})
      CHECK(std::filesystem::is_regular_file(out / (std::string(name) + ext)));
  CHECK_THAT(r.out, Catch::Contains(
                        "subdivision-torus: catmull-clark subdivision of torus.obj, 3 levels, 6144 faces") &&
                        Catch::Contains("sqrt3 subdivision of tetrahedron.obj, 6 levels"));
  // index.html: every experiment's description (read here from its file), every image the gallery
  // wrote shown, every other file linked, relative to the folder (the shipped names need no encoding).
  const std::string page = cifs::read_file(out / "index.html");
  for (const auto& entry : std::filesystem::directory_iterator(CIFS_EXAMPLES_DIR "/experiments")) {
    if (entry.path().extension() != ".json") continue;
    std::string expected;
    for (const char c : json::parse(cifs::read_file(entry.path()))["description"].get<std::string>())
      expected += c == '\''  ? std::string("&#39;")
                  : c == '"' ? std::string("&quot;")
                  : c == '&' ? std::string("&amp;")
                  : c == '<' ? std::string("&lt;")
                  : c == '>' ? std::string("&gt;")
                             : std::string(1, c);
    CHECK_THAT(page, Catch::Contains("<p>" + expected + "</p>"));
  }
  std::size_t images = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(out)) {
    if (!entry.is_regular_file() || entry.path().filename() == "index.html") continue;
    const std::string name = entry.path().lexically_relative(out).generic_string();
    const bool image = entry.path().extension() == ".png" || entry.path().extension() == ".svg";
    images += image;
    INFO(name);
    CHECK_THAT(page, Catch::Contains((image ? "src=\"" : "href=\"") + name + "\""));
  }
  CHECK(images >= 2 * experiments);
  CHECK_THAT(r.out, Catch::Contains("gallery: wrote " + (out / "index.html").string()));
  std::filesystem::remove_all(out);
  // A wrong examples folder is one clear error.
  check_error(cifs_cli("gallery " + out.string() + " --examples /no/such/folder"), "/no/such/folder");
}

TEST_CASE("cifs gallery says what an experiment's output drops, naming the experiment", "[cli]") {
  // An examples folder of one experiment: a 3-D cubic drawn as SVG (the SVG keeps x and y only).
  const auto examples = scratch() / "gallery_warn_examples";
  std::filesystem::create_directories(examples / "experiments");
  for (const char* sub : {"shapes", "polygons", "meshes"})
    std::filesystem::create_directory_symlink(std::filesystem::path(CIFS_EXAMPLES_DIR) / sub, examples / sub);
  cifs::write_file_atomically(examples / "experiments" / "flat.json",
                              R"({"name": "flat", "shape": "../shapes/cubic.json", "evaluation": {"depth": 4},
                                  "render": {"width": 32, "height": 24},
                                  "outputs": {"exr": "flat.exr", "svg": "flat.svg"}})");
  const auto out = scratch() / "gallery_warn";
  const Run r = cifs_cli("gallery " + out.string() + " --examples " + examples.string() + " --quiet");
  REQUIRE(r.status == 0);
  CHECK(std::filesystem::is_regular_file(out / "flat.svg"));
  CHECK_THAT(r.err, Catch::Contains("cifs: warning: flat.json: outputs.svg: "));
  // The same experiment through cifs render says it too (the gallery adds the file's name).
  const Run one = cifs_cli("render " + (examples / "experiments" / "flat.json").string() + " --out-dir " +
                           out.string() + " -o " + (out / "one.exr").string() + " --quiet");
  REQUIRE(one.status == 0);
  CHECK_THAT(one.err, Catch::Contains("cifs: warning: outputs.svg: "));
}

TEST_CASE("cifs render refuses junctions that cannot be joined, one line each", "[cli][junction]") {
  const std::string nurbs =
      R"({"shape": ")" CIFS_EXAMPLES_DIR R"(/shapes/junction_nurbs.json", "boundary": "uend"})";
  const auto experiment = [&](const std::string& name, const std::string& a, const std::string& b) {
    return file(name, R"({"junction": {"a": )" + a + R"(, "b": )" + b + R"(}, "evaluation": {"depth": 2},
      "render": {"width": 16, "height": 16}, "outputs": {"png": "junction_refused.png"}})");
  };
  const std::string grid = R"([[[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0], [0, 4, 0], [0, 5, 0]],
      [[1, 0, 0], [1, 1, 0], [1, 2, 0], [1, 3, 0], [1, 4, 0], [1, 5, 0]],
      [[2, 0, 0], [2, 1, 0], [2, 2, 0], [2, 3, 0], [2, 4, 0], [2, 5, 0]],
      [[3, 0, 0], [3, 1, 0], [3, 2, 0], [3, 3, 0], [3, 4, 0], [3, 5, 0]]])";
  const std::pair<std::string, std::string> cases[] = {
      // A junction layer of one piece: the four-point side cannot adapt to the B-spline.
      {experiment("junction_thin.json",
                  R"({"scheme": "b-spline", "window": 6, "boundary": "end",
                      "points": [[0, 0], [1, 1], [2, 0], [3, 1], [4, 0], [5, 1], [6, 0]]})",
                  R"({"scheme": "four-point", "window": 6, "layer": 1, "boundary": "start",
                      "points": [[2, 0], [3, 1], [4, 0], [5, 1], [6, 0], [7, 1], [8, 0]]})"),
       "junction: BC-IFS: the constraints \"B:a0.start\", \"B:a0.end\" have no common solution"},
      // A NURBS patch and a uniform scheme's: the boundaries do not subdivide alike.
      {experiment("junction_structure.json", nurbs,
                  R"({"scheme": "b-spline", "boundary": "ustart", "points": )" + grid + "}"),
       "junction: B's cell"},
      {experiment("junction_points.json", nurbs,
                  R"({"shape": ")" CIFS_EXAMPLES_DIR
                  R"(/shapes/junction_nurbs.json", "boundary": "ustart"})"),
       "junction: B's control points on the glued boundary differ from A's"},
      {experiment("junction_count.json", nurbs,
                  R"({"shape": ")" CIFS_EXAMPLES_DIR
                  R"(/shapes/junction_nurbs.json", "boundary": "vstart"})"),
       "junction: A's uend has 3 patches and B's vstart 2"},
      {experiment(
           "junction_kind.json", nurbs,
           R"({"scheme": "four-point", "boundary": "start", "points": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0], [4, 0, 0], [5, 0, 0]]})"),
       "junction_kind.json: junction: A is a surface and B a curve"}};
  for (const auto& [experiment_file, message] : cases) {
    INFO(experiment_file);
    check_error(cifs_cli("render --out-dir " + scratch().string() + " " + experiment_file), message);
  }
  CHECK(!std::filesystem::exists(scratch() / "junction_refused.png"));
}

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
  check_error(cifs_cli("dimension " CIFS_EXAMPLES_DIR
                       "/experiments/koch.json --relative-piece-size 1e-9 --max-points 1000"),
              "needs more than 1000 points");
}

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
