// SPDX-License-Identifier: MIT
// The output contract of the command line (docs/reliability.md): a command's outputs are all
// written or none is; nothing is left behind on an error or on SIGINT/SIGTERM; inputs are never
// overwritten; symbolic links are written through; only regular files are replaced (issue 16
// defects 4–7). What is left in a folder is read from the file system, not from cifs' report.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <set>
#include <thread>

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
Run render(const std::string& experiment, const fs::path& dir, const std::string& extra = "") {
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

TEST_CASE("cifs render writes all its outputs or none", "[cli][reliability][outputs]") {
  const fs::path dir = folder("all_or_none");
  const std::string exp = cubic_experiment(dir, R"({"exr": "a.exr", "png": "a.png", "svg": "a.svg"})");
  const std::set<std::string> inputs{"cubic.json", "e.json"};
  // --png naming a folder: the EXR was left behind.
  check_error(render(exp, dir, " --png " + dir.string()), dir.string() + ": is a directory");
  CHECK(names(dir) == inputs);
  // A PNG into a folder where no file can be created: the EXR was left behind.
  const fs::path locked = unwritable_folder();
  check_error(render(exp, dir, " --png " + (locked / "x.png").string()),
              (locked / "x.png").string() + ": cannot create a file in " + locked.string() + " (");
  CHECK(names(dir) == inputs);
  // An SVG path under a regular file: EXR and PNG were left behind.
  put_in(dir, "plain", "not a folder");
  const std::string under_file =
      cubic_experiment(dir, R"({"exr": "a.exr", "png": "a.png", "svg": "plain/a.svg"})");
  check_error(render(under_file, dir), (dir / "plain").string() + " is not a folder");
  fs::remove(dir / "plain");
  CHECK(names(dir) == inputs);
  // A folder made for an output goes again when the run fails.
  const std::string made =
      cubic_experiment(dir, R"({"exr": "new/sub/a.exr", "png": "a.png", "svg": "a.svg"})");
  check_error(render(made, dir, " --png " + dir.string()), ": is a directory");
  CHECK(names(dir) == inputs);
  // A PLY name that is a folder (a mesh experiment): EXR and PNG were left behind.
  put_in(dir, "cube.obj", slurp(CIFS_EXAMPLES_DIR "/meshes/cube.obj"));
  const std::string mesh =
      put_in(dir, "m.json", R"({"mesh": "cube.obj", "subdivision": {"scheme": "catmull-clark",
    "levels": 1}, "render": {"width": 16, "height": 16}, "outputs": {"exr": "m.exr", "png": "m.png", "ply": "m.ply"}})");
  fs::create_directory(dir / "m.ply");
  check_error(render(mesh, dir), (dir / "m.ply").string() + ": is a directory");
  CHECK(names(dir) == std::set<std::string>{"cube.obj", "cubic.json", "e.json", "m.json", "m.ply"});
  CHECK(fs::is_empty(dir / "m.ply"));
  // And when everything can be written, everything is.
  fs::remove(dir / "m.ply");
  REQUIRE(render(mesh, dir).status == 0);
  CHECK(head(dir / "m.exr", 4) == kExrMagic);
  CHECK(head(dir / "m.png", 4) == kPngMagic);
  CHECK(head(dir / "m.ply", 3) == "ply");
}

TEST_CASE("cifs render refuses an unusable output before the work", "[cli][reliability][outputs]") {
  // The chaos game would take about a minute; the refusal comes from the checks before it.
  const fs::path dir = folder("before_work");
  const std::string exp = long_experiment(dir);
  const auto start = std::chrono::steady_clock::now();
  check_error(render(exp, dir, " --png " + dir.string()), ": is a directory");
  check_error(render(exp, dir, " -o " + (dir / "missing/x.exr").string()), "does not exist");
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
  check_error(render(onto_shape, dir), input((dir / "cubic.json").string(), (dir / "cubic.json").string()));
  CHECK(slurp(dir / "cubic.json") == cubic_text);
  // The BC-IFS file of an automaton experiment, and the mesh of a subdivision experiment.
  put_in(dir, "tree.json", slurp(CIFS_EXAMPLES_DIR "/automata/tree.json"));
  const std::string tree = put_in(dir, "t.json", R"({"automaton": "tree.json", "evaluation": {"depth": 2},
    "render": {"width": 8, "height": 8}, "outputs": {"exr": "t.exr", "png": "tree.json"}})");
  check_error(render(tree, dir), input((dir / "tree.json").string(), (dir / "tree.json").string()));
  put_in(dir, "cube.obj", slurp(CIFS_EXAMPLES_DIR "/meshes/cube.obj"));
  const std::string mesh =
      put_in(dir, "m.json", R"({"mesh": "cube.obj", "subdivision": {"scheme": "catmull-clark",
    "levels": 1}, "render": {"width": 8, "height": 8}, "outputs": {"exr": "m.exr", "obj": "cube.obj"}})");
  check_error(render(mesh, dir), input((dir / "cube.obj").string(), (dir / "cube.obj").string()));
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
  check_error(render(twice, dir), "outputs.png: " + (dir / "link.exr").string() +
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
  REQUIRE(render(small, dir).status == 0);
  CHECK(names(dir) == std::set<std::string>{"big.json", "small.json", "small.png"});
}
