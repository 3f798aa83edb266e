// SPDX-License-Identifier: MIT
// The command line as a whole, each case across commands: standard output that cannot be written, -o
// written as computed, the output contract (all outputs or none, nothing left behind on an error or
// on SIGINT/SIGTERM, inputs never overwritten, symbolic links written through, only regular files
// replaced: docs/reliability.md), devices and FIFOs refused as inputs, options before the command,
// suggestions for typos, --version, --quiet, extensions in any case. What is left in a folder is read
// from the file system, not from cifs' report.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "apps/cli_fixtures.hpp"
#include "apps/cli_runner.hpp"

using namespace cifs_test;
namespace fs = std::filesystem;

extern char** environ;

namespace {

/// A fresh folder of the scratch area.
fs::path folder(const std::string& name) {
  fs::path dir = scratch() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::set<std::string> names(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& entry : fs::directory_iterator(dir)) out.insert(entry.path().filename());
  return out;
}

/// Writes `text` to `dir/name` and returns the path.
std::string put_in(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return (dir / name).string();
}

/// The first bytes of a file: the format's magic number, an independent check of what was written.
std::string head(const fs::path& p, std::size_t n) {
  return slurp(p).substr(0, n);
}

const std::string kExrMagic = "\x76\x2f\x31\x01", kPngMagic = "\x89PNG";

/// An experiment on the cubic of examples/shapes (a copy in `dir`, so that it is an input there).
std::string cubic_experiment(const fs::path& dir, const std::string& outputs,
                             const std::string& name = "e.json") {
  put_in(dir, "cubic.json", slurp(CIFS_EXAMPLES_DIR "/shapes/cubic.json"));
  return put_in(dir, name,
                R"({"shape": "cubic.json", "evaluation": {"depth": 3},
    "render": {"width": 16, "height": 16}, "outputs": )" +
                    outputs + "}");
}

/// A folder where no file can be created: read-only for a user, /sys for root (which may write
/// into any folder of its own).
fs::path unwritable_folder() {
  if (::geteuid() == 0) return "/sys";
  fs::path dir = folder("read_only");
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  return dir;
}

/// The CLI started in the background, its output discarded, SIGINT and SIGTERM at their default
/// actions whatever the test runner does with them.
pid_t spawn_cli(const std::vector<std::string>& args) {
  std::vector<char*> argv{const_cast<char*>(CIFS_CLI_PATH)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t defaults, none;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGINT);
  sigaddset(&defaults, SIGTERM);
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&files, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, CIFS_CLI_PATH, &files, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attr);
  REQUIRE(error == 0);
  return pid;
}

/// `cifs render EXPERIMENT --out-dir DIR EXTRA`.
Run render_into(const std::string& experiment, const fs::path& dir, const std::string& extra = "") {
  return cifs_cli("render " + experiment + " --out-dir " + dir.string() + extra);
}

bool has_temporary(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().find(".cifs-tmp.") != std::string::npos) return true;
  return false;
}

/// A chaos game of 4·10⁹ samples: about a minute of work, long enough to be interrupted.
std::string long_experiment(const fs::path& dir) {
  return put_in(dir, "big.json", R"({"ifs": "fern", "evaluation": {"chaos": 4000000000},
    "render": {"width": 16, "height": 16, "threads": 2}, "outputs": {"exr": "big.exr", "png": "big.png"}})");
}

}  // namespace

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
    check_error(cifs_cli(command + " -o ''"), "an empty value");
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

TEST_CASE("cifs names an unknown option given before the command", "[cli][reliability]") {
  // CLI11 said "A subcommand is required", which hides the typo.
  check_error(cifs_cli("--frob"), "unknown option '--frob'; options follow the command");
  check_error(cifs_cli("--depth=3 attractor x.json"), "unknown option '--depth'; options follow the command");
  CHECK(cifs_cli("--version").status == 0);
  CHECK(cifs_cli("--help").status == 0);
}

TEST_CASE("cifs: messages at the edges name what the user gave", "[cli][reliability]") {
  const std::string saddle = std::string(CIFS_EXAMPLES_DIR) + "/shapes/saddle.json";
  const auto camera = [&](const std::string& name, const std::string& eye, const std::string& target,
                          const std::string& up) {
    return file(name + ".json", R"({"shape": ")" + saddle + R"(", "evaluation": {"depth": 2},
      "camera": {"eye": )" + eye + R"(, "target": )" +
                                    target + R"(, "up": )" + up + R"(},
      "render": {"width": 16, "height": 16}, "outputs": {"exr": ")" +
                                    name + R"(.exr"}})");
  };
  // An eye at 1e308 overflowed the norm of the view direction: "camera: up is zero or parallel"; it
  // renders now, and an eye−target difference beyond a double is named.
  const Run far = cifs_cli("render " + camera("far_eye", "[1e308, 1e308, 1e308]", "[0, 0, 0]", "[0, 0, 1]") +
                           " --out-dir " + scratch().string() + " --quiet");
  INFO(far.err);
  CHECK(far.status == 0);
  check_error(
      cifs_cli("render " + camera("farther_eye", "[1e308, 1e308, 1e308]", "[-1e308, 0, 0]", "[0, 0, 1]") +
               " --out-dir " + scratch().string()),
      "camera.eye: the eye is farther from the target than a double holds");
  check_error(cifs_cli("render " + camera("parallel_up", "[1, 1, 1]", "[0, 0, 0]", "[2, 2, 2]") +
                       " --out-dir " + scratch().string()),
              "the camera's up (2, 2, 2) is parallel to the viewing direction");
  // "eigenvalues: the QR iteration did not converge".
  check_error(cifs_cli("scheme corner-cutting --param a=1e300 --analyze"),
              "--analyze of corner-cutting with --param a=1e300: ");
  // Internal function names: "attractor_point_count: … size_t", "surface_mesh: … size_t".
  check_error(cifs_cli("attractor " + std::string(CIFS_EXAMPLES_DIR) + "/shapes/cubic.json --depth 100 -o " +
                       (scratch() / "deep.npy").string()),
              "cifs: depth 100 gives more than 2^64 points; lower the depth");
  check_error(cifs_cli("attractor " + saddle + " --depth 40 -o " + (scratch() / "deep.npy").string()),
              "cifs: depth 40 on 2 by 1 patches gives more than 2^64 vertices; lower the depth");
}

TEST_CASE("Every command takes --quiet and progress shows only on a terminal", "[cli][newuser]") {
  const std::string mesh = CIFS_EXAMPLES_DIR "/meshes/cube.obj";
  // Small work each (the default check and dimension take seconds, half a minute under ASan).
  for (const std::string& command : std::vector<std::string>{
           "info " + kHills, "insert " + kHills + " --midpoints", "automaton " + kHills,
           "check " + kHills + " --depth 3", std::string("scheme --list"),
           "limit " + mesh + " --scheme catmull-clark",
           std::string("dimension " CIFS_EXAMPLES_DIR "/experiments/sierpinski.json --depth 9"),
           "eval " + kHills + " --samples 3", "attractor " + kHills + " --depth 1",
           "subdivide " + mesh + " --scheme loop --levels 0"}) {
    INFO(command);
    const Run r = cifs_cli(command + " --quiet");
    CHECK(r.err.find("--quiet") == std::string::npos);
  }
  // A stage over CIFS_PROGRESS_AFTER seconds (1 without it) shows its name and time on a terminal (script
  // gives the command one), and nothing when stderr is a file or with --quiet. 0 s: any stage shows.
  const std::string slow =
      "CIFS_PROGRESS_AFTER=0 " + std::string(CIFS_CLI_PATH) + " check " + kHills + " --depth 3";
  const auto log = scratch() / "tty.log";
  const auto on_terminal = [&](const std::string& command) {
    const std::string tty = "script -qec '" + command + " >/dev/null' " + log.string() + " >/dev/null 2>&1";
    REQUIRE(std::system(tty.c_str()) == 0);
    return slurp(log);
  };
  CHECK_THAT(on_terminal(slow), Catch::Contains("check  done"));
  CHECK_THAT(on_terminal(slow + " --quiet"), !Catch::Contains("check  done") && !Catch::Contains("check …"));
  // The default second: a check of milliseconds leaves no line.
  CHECK_THAT(on_terminal(std::string(CIFS_CLI_PATH) + " check " + kHills + " --depth 3"),
             !Catch::Contains("check  done") && !Catch::Contains("check …"));
  const Run plain = cifs_cli("check " + kHills + " --depth 3", "", "CIFS_PROGRESS_AFTER=0 ");
  CHECK(plain.status == 0);
  CHECK(plain.err.empty());
  // A malformed delay is refused by name, on a terminal, where it would be read.
  CHECK_THAT(on_terminal("CIFS_PROGRESS_AFTER=soon " + std::string(CIFS_CLI_PATH) + " check " + kHills +
                         " 2>&1; true"),
             Catch::Contains("CIFS_PROGRESS_AFTER: 'soon'"));
}

TEST_CASE("Mistyped options, commands and scheme names get a suggestion", "[cli][frictions]") {
  check_error(cifs_cli("subdivide " + kCube + " --scheme catmull-clark --level 2"),
              "unknown option '--level' of subdivide; did you mean --levels?");
  check_error(cifs_cli("subdivide " + kCube + " --scheme catmull_clark"),
              "unknown mesh scheme 'catmull_clark'; did you mean catmull-clark?");
  check_error(cifs_cli("scheme catmul-clark --valence 5 --analyze"),
              "unknown scheme 'catmul-clark'; did you mean catmull-clark?");
  check_error(cifs_cli("scheme chaikn --analyze"), "unknown scheme 'chaikn'; did you mean chaikin?");
  check_error(cifs_cli("evl " + kWave), "unknown command 'evl'; did you mean eval?");
  // A second value after an option that takes one: the option and what it takes, not "not expected".
  const Run at = cifs_cli("eval " + kWave + " --at 0.5 0.5");
  check_error(at, "eval: unexpected argument '0.5' after --at 0.5: --at takes one value");
  CHECK_THAT(at.err, Catch::Contains("U,V"));
}

TEST_CASE("cifs --version is the project's version", "[cli][frictions]") {
  const std::string cmake = slurp(CIFS_SOURCE_DIR "/CMakeLists.txt");
  const auto start = cmake.find("project(cifs VERSION ") + std::string("project(cifs VERSION ").size();
  REQUIRE(start > 30);
  CHECK(cifs_cli("--version").out == "cifs " + cmake.substr(start, cmake.find(' ', start) - start) + "\n");
}

TEST_CASE("Extensions are read in any case: .OBJ, .JSON, .PLY, .PNG", "[cli][frictions]") {
  // Files from Windows tools often carry upper-case extensions; the format is the same.
  const auto cube = scratch() / "CUBE.OBJ", ply = scratch() / "OUT.PLY";
  std::filesystem::copy_file(kCube, cube, std::filesystem::copy_options::overwrite_existing);
  const Run sub =
      cifs_cli("subdivide " + cube.string() + " --scheme catmull-clark --levels 1 -o " + ply.string());
  INFO(sub.err);
  REQUIRE(sub.status == 0);
  CHECK(slurp(ply).rfind("ply\n", 0) == 0);
  const auto wave = scratch() / "WAVE.JSON";
  std::filesystem::copy_file(kWave, wave, std::filesystem::copy_options::overwrite_existing);
  const Run info = cifs_cli("info " + wave.string());
  INFO(info.err);
  CHECK(info.status == 0);
  CHECK_THAT(info.out, Catch::Contains("\"curve\""));
  const std::string e = wave_experiment("upper.json", R"("png": "UPPER.PNG")");
  const Run render = cifs_cli("render " + e + " --out-dir " + scratch().string() + " --quiet");
  INFO(render.err);
  CHECK(render.status == 0);
  CHECK(std::filesystem::exists(scratch() / "UPPER.PNG"));
}

TEST_CASE("cifs render writes all its outputs or none", "[cli][reliability][outputs]") {
  const fs::path dir = folder("all_or_none");
  const std::string exp = cubic_experiment(dir, R"({"exr": "a.exr", "png": "a.png", "svg": "a.svg"})");
  const std::set<std::string> inputs{"cubic.json", "e.json"};
  // --png naming a folder: the EXR was left behind.
  check_error(render_into(exp, dir, " --png " + dir.string()), dir.string() + ": is a directory");
  CHECK(names(dir) == inputs);
  // A PNG into a folder where no file can be created: the EXR was left behind.
  const fs::path locked = unwritable_folder();
  check_error(render_into(exp, dir, " --png " + (locked / "x.png").string()),
              (locked / "x.png").string() + ": cannot create a file in " + locked.string() + " (");
  CHECK(names(dir) == inputs);
  // An SVG path under a regular file: EXR and PNG were left behind.
  put_in(dir, "plain", "not a folder");
  const std::string under_file =
      cubic_experiment(dir, R"({"exr": "a.exr", "png": "a.png", "svg": "plain/a.svg"})");
  check_error(render_into(under_file, dir), (dir / "plain").string() + " is not a folder");
  fs::remove(dir / "plain");
  CHECK(names(dir) == inputs);
  // A folder made for an output goes again when the run fails.
  const std::string made =
      cubic_experiment(dir, R"({"exr": "new/sub/a.exr", "png": "a.png", "svg": "a.svg"})");
  check_error(render_into(made, dir, " --png " + dir.string()), ": is a directory");
  CHECK(names(dir) == inputs);
  // A PLY name that is a folder (a mesh experiment): EXR and PNG were left behind.
  put_in(dir, "cube.obj", slurp(CIFS_EXAMPLES_DIR "/meshes/cube.obj"));
  const std::string mesh =
      put_in(dir, "m.json", R"({"mesh": "cube.obj", "subdivision": {"scheme": "catmull-clark",
    "levels": 1}, "render": {"width": 16, "height": 16}, "outputs": {"exr": "m.exr", "png": "m.png", "ply": "m.ply"}})");
  fs::create_directory(dir / "m.ply");
  check_error(render_into(mesh, dir), (dir / "m.ply").string() + ": is a directory");
  CHECK(names(dir) == std::set<std::string>{"cube.obj", "cubic.json", "e.json", "m.json", "m.ply"});
  CHECK(fs::is_empty(dir / "m.ply"));
  // And when everything can be written, everything is.
  fs::remove(dir / "m.ply");
  REQUIRE(render_into(mesh, dir).status == 0);
  CHECK(head(dir / "m.exr", 4) == kExrMagic);
  CHECK(head(dir / "m.png", 4) == kPngMagic);
  CHECK(head(dir / "m.ply", 3) == "ply");
}

TEST_CASE("cifs render refuses an unusable output before the work", "[cli][reliability][outputs]") {
  // The chaos game would take about a minute; the refusal comes from the checks before it.
  const fs::path dir = folder("before_work");
  const std::string exp = long_experiment(dir);
  const auto start = std::chrono::steady_clock::now();
  check_error(render_into(exp, dir, " --png " + dir.string()), ": is a directory");
  check_error(render_into(exp, dir, " -o " + (dir / "missing/x.exr").string()), "does not exist");
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));
  CHECK(names(dir) == std::set<std::string>{"big.json"});
}

TEST_CASE("cifs never overwrites its inputs", "[cli][reliability][outputs]") {
  const fs::path dir = folder("inputs");
  const std::string exp = cubic_experiment(dir, R"({"exr": "a.exr"})");
  const std::string experiment_text = slurp(exp), cubic_text = slurp(dir / "cubic.json");
  const auto input = [](const std::string& output, const std::string& file) {
    return output + ": is the input " + file + "; choose another output file";
  };
  // -o onto the experiment itself, by its name and by a hard link: it was replaced by the EXR.
  check_error(cifs_cli("render " + exp + " -o " + exp), input(exp, exp));
  fs::create_hard_link(exp, dir / "hard.json");
  check_error(cifs_cli("render " + exp + " -o " + (dir / "hard.json").string()),
              input((dir / "hard.json").string(), exp));
  fs::remove(dir / "hard.json");
  // An output of the file equal to its shape: the shape was replaced by the SVG.
  const std::string onto_shape = cubic_experiment(dir, R"({"exr": "a.exr", "svg": "cubic.json"})", "s.json");
  check_error(render_into(onto_shape, dir),
              input((dir / "cubic.json").string(), (dir / "cubic.json").string()));
  CHECK(slurp(dir / "cubic.json") == cubic_text);
  // The BC-IFS file of an automaton experiment, and the mesh of a subdivision experiment.
  put_in(dir, "tree.json", slurp(CIFS_EXAMPLES_DIR "/automata/tree.json"));
  const std::string tree = put_in(dir, "t.json", R"({"automaton": "tree.json", "evaluation": {"depth": 2},
    "render": {"width": 8, "height": 8}, "outputs": {"exr": "t.exr", "png": "tree.json"}})");
  check_error(render_into(tree, dir), input((dir / "tree.json").string(), (dir / "tree.json").string()));
  put_in(dir, "cube.obj", slurp(CIFS_EXAMPLES_DIR "/meshes/cube.obj"));
  const std::string mesh =
      put_in(dir, "m.json", R"({"mesh": "cube.obj", "subdivision": {"scheme": "catmull-clark",
    "levels": 1}, "render": {"width": 8, "height": 8}, "outputs": {"exr": "m.exr", "obj": "cube.obj"}})");
  check_error(render_into(mesh, dir), input((dir / "cube.obj").string(), (dir / "cube.obj").string()));
  // subdivide -o onto its mesh, directly and through a symbolic link.
  const std::string cube = (dir / "cube.obj").string();
  check_error(cifs_cli("subdivide " + cube + " --scheme catmull-clark -o " + cube), input(cube, cube));
  fs::create_symlink("cube.obj", dir / "link.obj");
  check_error(cifs_cli("subdivide " + cube + " --scheme catmull-clark -o " + (dir / "link.obj").string()),
              input((dir / "link.obj").string(), cube));
  CHECK(slurp(cube) == slurp(CIFS_EXAMPLES_DIR "/meshes/cube.obj"));
  CHECK(slurp(exp) == experiment_text);
  CHECK(names(dir) == std::set<std::string>{"cube.obj", "cubic.json", "e.json", "link.obj", "m.json",
                                            "s.json", "t.json", "tree.json"});
}

TEST_CASE("cifs writes through symbolic links and replaces only regular files",
          "[cli][reliability][outputs]") {
  const fs::path dir = folder("links");
  const std::string exp = cubic_experiment(dir, R"({"png": "a.png"})");
  fs::create_directory(dir / "real");
  put_in(dir / "real", "image.exr", "old");
  fs::create_symlink("real/image.exr", dir / "link.exr");
  fs::create_symlink("real/preview.png", dir / "dangling.png");
  REQUIRE(cifs_cli("render " + exp + " -o " + (dir / "link.exr").string() + " --png " +
                   (dir / "dangling.png").string())
              .status == 0);
  // The links stay links; the files they name are the new EXR and PNG.
  CHECK(fs::read_symlink(dir / "link.exr") == "real/image.exr");
  CHECK(fs::read_symlink(dir / "dangling.png") == "real/preview.png");
  CHECK(head(dir / "real/image.exr", 4) == kExrMagic);
  CHECK(head(dir / "real/preview.png", 4) == kPngMagic);
  CHECK(names(dir / "real") == std::set<std::string>{"image.exr", "preview.png"});
  // A FIFO was replaced by a regular file (as root, so was the device /dev/full).
  REQUIRE(::mkfifo((dir / "fifo").c_str(), 0600) == 0);
  check_error(cifs_cli("render " + exp + " -o " + (dir / "fifo").string()),
              (dir / "fifo").string() + ": is a FIFO; only regular files are written");
  CHECK(fs::is_fifo(dir / "fifo"));
  // A device node of our own, like /dev/full (made only where root may make one; a failed refusal
  // replaces this node, never a real device).
  if (::geteuid() == 0 && ::mknod((dir / "full").c_str(), S_IFCHR | 0600, makedev(1, 7)) == 0) {
    check_error(cifs_cli("render " + exp + " -o " + (dir / "full").string()),
                (dir / "full").string() + ": is a device; only regular files are written");
    CHECK(fs::is_character_file(dir / "full"));
    fs::remove(dir / "full");
  }
  REQUIRE(::mkfifo((dir / "fifo.obj").c_str(), 0600) == 0);
  check_error(cifs_cli("subdivide " CIFS_EXAMPLES_DIR "/meshes/cube.obj --scheme loop -o " +
                       (dir / "fifo.obj").string()),
              "fifo.obj: is a FIFO");
  // Two names of one file through a link are two outputs onto one file.
  const std::string twice = cubic_experiment(dir, R"({"exr": "real/image.exr", "png": "link.exr"})");
  check_error(render_into(twice, dir), "outputs.png: " + (dir / "link.exr").string() +
                                           " is also outputs.exr; give each output its own file");
  CHECK(names(dir) == std::set<std::string>{"cubic.json", "dangling.png", "e.json", "fifo", "fifo.obj",
                                            "link.exr", "real"});
}

TEST_CASE("SIGTERM and SIGINT during a render leave no temporary; the next run removes those of SIGKILL",
          "[cli][reliability][outputs]") {
  const fs::path dir = folder("signals");
  const std::string exp = long_experiment(dir);
  const auto interrupted = [&](int signal) {
    const pid_t pid = spawn_cli({"render", exp, "--quiet", "--out-dir", dir.string()});
    // The temporaries are made before the work: wait for them, then interrupt the chaos game.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!has_temporary(dir) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    CHECK(has_temporary(dir));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ::kill(pid, signal);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    INFO("signal " << signal);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal);
  };
  for (const int signal : {SIGTERM, SIGINT}) {
    interrupted(signal);
    CHECK(names(dir) == std::set<std::string>{"big.json"});
  }
  // SIGKILL cannot be handled: its temporaries stay, and a later write into the folder removes them.
  interrupted(SIGKILL);
  CHECK(has_temporary(dir));
  const std::string small = put_in(dir, "small.json", R"({"ifs": "fern", "evaluation": {"chaos": 1000},
    "render": {"width": 8, "height": 8}, "outputs": {"png": "small.png"}})");
  REQUIRE(render_into(small, dir).status == 0);
  CHECK(names(dir) == std::set<std::string>{"big.json", "small.json", "small.png"});
}
