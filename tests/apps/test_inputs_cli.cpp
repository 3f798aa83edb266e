// SPDX-License-Identifier: MIT
// Issue 33 (reliability, round three): crashes on tiny tolerances and deep symbols, inputs
// overwritten by -o, unbounded inputs (devices, FIFOs), slow refusals and silent non-finite answers,
// each through the CLI as a user runs it (docs/reliability.md).
#include <sys/resource.h>
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "apps/cli_runner.hpp"

using namespace cifs_test;

namespace {

/// CPU seconds (user and system) of the children this process has waited for.
double children_cpu_seconds() {
  rusage usage{};
  ::getrusage(RUSAGE_CHILDREN, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

/// `command` refused within `seconds` of CPU time (one line naming `needle`, exit status 2). CPU time,
/// not wall time: the 2-core machine is shared with builds (a 0.01-s refusal took 2.5 s of wall time).
constexpr double kQuick = cifs_test::kSanitized ? 20 : 1;  // ASan and UBSan slow the estimates about 25 times
void check_quick_error(const std::string& command, const std::string& needle, double seconds = kQuick) {
  INFO(command);
  const double before = children_cpu_seconds();
  check_error(cifs_cli(command), needle);
  CHECK(children_cpu_seconds() - before < seconds);
}

const std::string kCubic = R"({"curve": {"degree": 3, "knots": [0, 0, 0, 0, 1, 2, 2, 2, 2],
    "points": [[0, 0, 0], [1, 2, 0], [2, 0, 1], [3, 1, 0], [4, 0, 0]]}})";

}  // namespace

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

TEST_CASE("cifs refuses an output that is one of the command's inputs, for every command",
          "[cli][reliability]") {
  // eval and attractor replaced the shape with points (exit 0), by any spelling of its name.
  const std::string shape = file("own.json", kCubic);
  std::filesystem::create_directories(scratch() / "sub");
  std::filesystem::remove(scratch() / "own_link.json");
  std::filesystem::remove(scratch() / "own_hard.json");
  std::filesystem::create_symlink(shape, scratch() / "own_link.json");
  std::filesystem::create_hard_link(shape, scratch() / "own_hard.json");
  const std::string names[] = {shape, (scratch() / "sub/../own.json").string(),
                               (scratch() / "own_link.json").string(),
                               (scratch() / "own_hard.json").string()};
  for (const std::string& out : names) {
    check_error(cifs_cli("eval " + shape + " --samples 5 -o " + out), "is the input");
    check_error(cifs_cli("attractor " + shape + " --depth 2 -o " + out), "is the input");
    check_error(cifs_cli("attractor " + shape + " --chaos 10 -o " + out), "is the input");
  }
  CHECK(slurp(shape) == kCubic);
}

TEST_CASE("cifs refuses an empty output name", "[cli][reliability]") {
  // -o '' wrote the result on stdout, exit 0.
  const std::string shape = file("empty_out.json", kCubic);
  const std::string mesh = std::string(CIFS_EXAMPLES_DIR) + "/meshes/cube.obj";
  for (const std::string& command :
       {"eval " + shape + " --samples 3", "attractor " + shape + " --depth 2",
        "subdivide " + mesh + " --scheme catmull-clark", "limit " + mesh + " --scheme catmull-clark"}) {
    INFO(command);
    check_error(cifs_cli(command + " -o ''"), "empty file name");
  }
}

TEST_CASE("cifs reads regular files only: devices and FIFOs are refused at once", "[cli][reliability]") {
  // `info /dev/zero` reached 3.5 GB in 8.8 s; a FIFO as input blocked forever.
  const auto fifo = scratch() / "input.fifo";
  std::filesystem::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  for (const std::string& input : {std::string("/dev/zero"), fifo.string()}) {
    const std::string kind = input == "/dev/zero" ? "is a device" : "is a FIFO";
    check_quick_error("info " + input, kind);
    check_quick_error("eval " + input + " --samples 3", kind);
  }
  const std::string fifo_json = (scratch() / "input_fifo.json").string();
  std::filesystem::remove(fifo_json);
  REQUIRE(::mkfifo(fifo_json.c_str(), 0600) == 0);
  check_quick_error("info " + fifo_json, "is a FIFO");
  check_quick_error("scheme four-point --refine " + fifo_json, "is a FIFO");
  check_quick_error("dimension " + fifo_json, "is a FIFO");
  const std::string fifo_obj = (scratch() / "input_fifo.obj").string();
  std::filesystem::remove(fifo_obj);
  REQUIRE(::mkfifo(fifo_obj.c_str(), 0600) == 0);
  check_quick_error("subdivide " + fifo_obj + " --scheme loop", "is a FIFO");
  check_quick_error("info " + fifo_obj, "is a FIFO");
}

TEST_CASE("cifs eval on a subnormal knot interval gives the point, not NaN", "[cli][reliability]") {
  // The basis divided 1 by the interval 1e-320 (inf), then inf · 0: {"points":[[nan]]}, exit 0.
  const std::string tiny = file("subnormal_knots.json", R"({"curve": {"degree": 1,
      "knots": [0, 0, 1e-320, 1e-320], "points": [[0], [2]]}})");
  const Run r = cifs_cli("eval " + tiny + " --at 5e-321");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK(r.out == "{\"points\":[[1]]}\n");  // halfway along [0, 2]: exact in binary
}

TEST_CASE("cifs gallery checks every experiment before it writes anything", "[cli][reliability]") {
  // An invalid later file left the outputs of the earlier ones, and an empty OUT/ (issue 33).
  const auto examples = scratch() / "gallery_examples";
  std::filesystem::create_directories(examples / "experiments");
  file("gallery_examples/experiments/a.json",
       R"({"name": "a", "ifs": "sierpinski", "evaluation": {"depth": 3},
      "render": {"width": 16, "height": 16}, "outputs": {"png": "a.png"}})");
  file("gallery_examples/experiments/b.json",
       R"({"name": "b", "ifs": "sierpinski", "evaluation": {"depht": 3}})");
  // Not test_frictions_cli's gallery_out: both run in one process, in one scratch folder.
  const auto out = scratch() / "gallery_checked_out";
  check_error(cifs_cli("gallery " + out.string() + " --examples " + examples.string() + " --quiet"),
              "b.json: evaluation.depht: unknown member");
  CHECK(!std::filesystem::exists(out));
}

TEST_CASE("cifs names the member of an experiment path the file system refuses", "[cli][reliability]") {
  // A path longer than the file system allows threw std::filesystem::filesystem_error out of the
  // experiment reader: a raw message without the member (found by fuzz_experiment, issue 33).
  const std::string experiment =
      file("long_automaton.json", R"({"name": "x", "automaton": ")" + std::string(5000, 'a') + R"(.json",
      "evaluation": {"depth": 1}, "outputs": {"png": "x.png"}})");
  const Run r = cifs_cli("render " + experiment);
  check_error(r, "long_automaton.json: automaton: cannot read");
  CHECK_THAT(r.err, Catch::Contains("(File name too long)"));
  CHECK(r.err.size() < 300);
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
