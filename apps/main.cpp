// SPDX-License-Identifier: MIT
// cifs — command-line entry point. Errors: one line on stderr, nothing on stdout, exit status 2; a
// failed write to stdout: one line, exit status 1.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <new>
#include <sstream>
#include <system_error>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/render/progress.hpp"
#include "cifs/suggest.hpp"
#include "cifs/view/server.hpp"
#include "commands.hpp"
#include "construct_command.hpp"
#include "fit_command.hpp"
#ifdef CIFS_HAVE_OCCT
#include "occt_plugin.hpp"
#endif
#include "scheme_command.hpp"
#include "world.hpp"

namespace {

/// CLI11 turns "-1" and 2^64 into the largest seed without a word: seeds are checked as text first.
const CLI::Validator seed_text(
    [](std::string& text) -> std::string {
      std::uint64_t value = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (text.empty() || error != std::errc() || end != text.data() + text.size())
        return "'" + text + "' is not an integer from 0 to 18446744073709551615";
      return {};
    },
    "SEED");

/// Every option that takes a value refuses an empty one: `-o ''` wrote to standard output and
/// `--interior-corners ''` analysed the default case, each as if the option were left out.
void refuse_empty_values(CLI::App& app) {
  const CLI::Validator non_empty(
      [](std::string& text) -> std::string {
        return text.empty() ? "an empty value; give one, or leave the option out" : std::string();
      },
      "");
  for (CLI::Option* option : app.get_options())
    if (option->get_type_size_max() > 0) option->check(non_empty);
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) refuse_empty_values(*command);
}

/// `--index N` and `--ignore-trim` of the commands that read a shape file.
void add_shape_selection(CLI::App* command, cifs::cli::ShapeSelection& select) {
  command->add_option("--index", select.index,
                      "Which curve or surface of a file that holds several (0-based, in file order)");
  command->add_flag(
      "--ignore-trim", select.ignore_trim,
      "Read trimmed surfaces (OBJ trim/hole, geomdl trims, STEP and IGES faces) whole, with a warning");
}

/// An option that was renamed: refused with its new name, so an old command line says what to change
/// instead of "unknown option".
void add_renamed(CLI::App* command, const std::string& old_name, const std::string& new_name) {
  command->add_option(old_name)
      ->group("")  // hidden from --help
      ->each([=](const std::string&) {
        throw cifs::InvalidInput(command->get_name() + " " + old_name + " is now " + new_name);
      });
}

/// `--quiet` on a command without a progress bar of its own: once it has run for a second, its name
/// and time on a terminal (render::Stage), none with the flag.
void add_quiet(CLI::App* command, bool& quiet) {
  command->add_flag("--quiet", quiet, "No progress on the terminal (none is drawn when stderr is not one)");
}

/// Help or version text into `result`, which main writes and checks like any command's output.
int help_or_version(const CLI::App& app, const CLI::Error& e, std::string& result) {
  std::ostringstream text;
  const int status = app.exit(e, text);
  result = text.str();
  return status;
}

namespace cli = cifs::cli;

/// The gallery's default input: the source tree's examples/ for the cifs of the build tree, else the
/// installed examples, found relative to the executable (CIFS_INSTALLED_EXAMPLES, relative to the
/// install's bin folder) so that a moved prefix still finds its own, never the source tree.
std::filesystem::path default_examples() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::canonical("/proc/self/exe", ec);
  if (ec) return CIFS_EXAMPLES_DIR;  // no /proc: the build tree's default
  const std::filesystem::path build = std::filesystem::weakly_canonical(CIFS_BUILD_BIN_DIR, ec);
  if (!ec && self.parent_path() == build) return CIFS_EXAMPLES_DIR;
  return (self.parent_path() / CIFS_INSTALLED_EXAMPLES).lexically_normal();
}

/// The options of every command: the parser binds them, the command's callback reads them.
struct Commands {
  explicit Commands(std::string& out) : result(out) {}
  std::string& result;  // what the command prints on stdout
  int status = 0;       // check's: 1 above tolerance
  bool quiet = false;   // commands without a bar of their own show a Stage
  cli::EvalOptions ev;
  cli::InsertOptions in;
  cli::ConvertOptions cv;
  std::filesystem::path info_shape;
  cli::ShapeSelection info_select;
  bool info_strict = false;
  cli::AutomatonOptions au;
  cli::AttractorOptions at;
  cli::CheckOptions ch;
  cli::SchemeOptions sc;
  cli::RenderOptions re;
  cli::SubdivideOptions su;
  cli::LimitCommandOptions li;
  cli::AnalyzeOptions an;
  cli::DimensionOptions di;
  cli::FitOptions fi;
  cli::ConstructOptions co;
  std::filesystem::path view_path, view_export;
  cifs::view::ServeOptions view;
  std::filesystem::path gallery_out = "out";
  std::filesystem::path gallery_examples = default_examples();
};

void add_eval(CLI::App& app, Commands& c) {
  auto* eval_cmd = app.add_subcommand(
      "eval", "Evaluate a curve, surface or volume; prints {\"points\": [...]} or writes -o FILE");
  eval_cmd->add_option("shape", c.ev.shape, "Shape file (.json, .obj, .step or .igs)")->required();
  eval_cmd->add_option("--at", c.ev.at, "Parameter U (curves), U,V (surfaces) or U,V,W (volumes); repeatable")
      ->allow_extra_args(false);
  eval_cmd->add_option("--samples", c.ev.samples,
                       "N parameters evenly spaced over the domain (surfaces: N×N grid, volumes: N×N×N)");
  eval_cmd->add_option("-o,--output", c.ev.output,
                       "Write the points to a file as they are computed: .json, .npy, .ply or .obj");
  eval_cmd->add_flag("--quiet", c.ev.quiet, "No progress bar (-o)");
  add_shape_selection(eval_cmd, c.ev.select);
  eval_cmd->callback([&] { c.result = cli::eval(c.ev); });
}

void add_insert(CLI::App& app, Commands& c) {
  auto* insert_cmd = app.add_subcommand("insert", "Insert knots; prints the refined shape as JSON");
  insert_cmd->add_option("shape", c.in.shape, "Shape file (.json, .obj, .step or .igs)")->required();
  insert_cmd->add_option("--knot", c.in.knots, "Knot to insert; repeatable")->allow_extra_args(false);
  insert_cmd->add_option("--dir", c.in.dir, "Surface direction: u or v");
  insert_cmd->add_flag("--midpoints", c.in.midpoints,
                       "Insert the midpoint of every span (both directions for surfaces)");
  add_shape_selection(insert_cmd, c.in.select);
  add_quiet(insert_cmd, c.quiet);
  insert_cmd->callback([&] {
    const cifs::render::Stage stage("insert", c.quiet);
    c.result = cli::insert(c.in);
  });
}

/// --strict: an OBJ mesh tag cifs does not read (`t vertexedit`, …) is an error (exit 2), not a warning.
void add_strict(CLI::App* command, bool& strict) {
  command->add_flag("--strict", strict,
                    "An OBJ mesh tag cifs does not read (t vertexedit, ...) is an error, not a warning");
}

void add_convert(CLI::App& app, Commands& c) {
  auto* cmd = app.add_subcommand(
      "convert",
      "Write the curves and surfaces of a file in another format (by extension: .json, .obj, .step, "
      ".stp, .igs, .iges)");
  cmd->add_option("input", c.cv.input, "Shape file (.json, .obj, .step, .stp, .igs or .iges)")->required();
  cmd->add_option("output", c.cv.output, "Output file; STEP and IGES hold every shape, others one (--index)")
      ->required();
  add_shape_selection(cmd, c.cv.select);
  add_quiet(cmd, c.quiet);
  cmd->callback([&] {
    const cifs::render::Stage stage("convert", c.quiet);
    c.result = cli::convert(c.cv);
  });
}

void add_info(CLI::App& app, Commands& c) {
  auto* info_cmd = app.add_subcommand(
      "info",
      "Degree, counts, domain and segments of a shape (of each shape of the file); counts, valences and "
      "topology of a mesh; the source, evaluation and outputs of an experiment");
  info_cmd
      ->add_option("shape", c.info_shape,
                   "Shape file (.json, .obj, .step or .igs), polygon mesh (.obj, .ply, .stl or .off), BC-IFS "
                   "or experiment file")
      ->required();
  add_shape_selection(info_cmd, c.info_select);
  add_strict(info_cmd, c.info_strict);
  add_quiet(info_cmd, c.quiet);
  info_cmd->callback([&] {
    const cifs::render::Stage stage("info", c.quiet);
    c.result = cli::info(c.info_shape, c.info_select, {.strict = c.info_strict, .warn = {}});
  });
}

void add_automaton(CLI::App& app, Commands& c) {
  auto* automaton_cmd =
      app.add_subcommand("automaton",
                         "The knot-doubling automaton of a curve, the tensor-product automaton of a surface, "
                         "the surface automaton of a mesh under a scheme (JSON, DOT or SVG)");
  automaton_cmd
      ->add_option("shape", c.au.shape, "Shape file (.json, .obj, .step or .igs), or a mesh (.obj, .ply)")
      ->required();
  automaton_cmd->add_option("--format", c.au.format, "json (default), dot or svg");
  automaton_cmd->add_option("-o,--output", c.au.output,
                            "Output file, its format from the extension (.json, .dot, .svg)");
  automaton_cmd->add_flag("--minimize", c.au.minimize, "Merge states that no control net can tell apart");
  automaton_cmd->add_option(
      "--scheme", c.au.scheme,
      "A mesh's scheme: catmull-clark or loop (its surface automaton; catmull-clark with boundaries, "
      "creases, corners and holes)");
  automaton_cmd->add_option("--levels", c.au.levels, "A mesh's steps of refinement first (default 0)");
  add_shape_selection(automaton_cmd, c.au.select);
  add_quiet(automaton_cmd, c.quiet);
  automaton_cmd->callback([&] {
    const cifs::render::Stage stage("automaton", c.quiet);
    c.result = cli::automaton(c.au);
  });
}

void add_attractor(CLI::App& app, Commands& c) {
  auto* attractor_cmd = app.add_subcommand(
      "attractor",
      "The attractor of a curve's automaton (in curve order) or a surface's (its quad mesh, "
      "or points)");
  attractor_cmd->add_option("shape", c.at.shape, "Shape file (.json, .obj, .step or .igs)")->required();
  attractor_cmd->add_option("--depth", c.at.depth, "2^K leaves per segment");
  attractor_cmd->add_option("--piece-size", c.at.piece_size,
                            "One point per piece, every piece proven smaller than E (its diameter)");
  attractor_cmd->add_option("--deviation", c.at.deviation,
                            "Curves: a polyline proven within D of the curve (chordal deviation, far fewer "
                            "points than --piece-size)");
  add_renamed(attractor_cmd, "--tolerance",
              "--piece-size (every piece smaller than E) or --deviation (a polyline within D)");
  attractor_cmd->add_option("--chaos", c.at.chaos, "N chaos-game points (a random walk over the automaton)");
  attractor_cmd
      ->add_option("--seed", c.at.seed, "Chaos-game seed (default: drawn, and printed with the points)")
      ->check(seed_text);
  attractor_cmd->add_option(
      "--format", c.at.format,
      "json (default), npy, ply, obj or svg (surfaces at a depth: ply and obj the mesh)");
  attractor_cmd->add_option(
      "-o,--output", c.at.output,
      "Output file, its format from the extension (.json, .npy, .ply, .obj: written as computed; .svg)");
  attractor_cmd->add_flag("--quiet", c.at.quiet, "No progress on the terminal");
  add_shape_selection(attractor_cmd, c.at.select);
  attractor_cmd->callback([&] { c.result = cli::attractor(c.at); });
}

void add_check(CLI::App& app, Commands& c) {
  auto* check_cmd =
      app.add_subcommand("check", "Attractor vs knot insertion vs Cox-de Boor; exit 1 above tolerance");
  check_cmd->add_option("shape", c.ch.shape, "Shape file (.json, .obj, .step or .igs)")->required();
  check_cmd->add_option("--depth", c.ch.depth, "Depth K (2^K leaves per segment and direction; default 8)");
  check_cmd->add_option("--relative-tolerance", c.ch.relative_tolerance,
                        "Largest deviation relative to the largest control point (default 1e-12)");
  add_renamed(check_cmd, "--tolerance", "--relative-tolerance");
  check_cmd->add_flag("--json", c.ch.json, "Machine-readable report");
  add_shape_selection(check_cmd, c.ch.select);
  add_quiet(check_cmd, c.quiet);
  check_cmd->callback([&] {
    const cifs::render::Stage stage("check", c.quiet);
    c.result = cli::check(c.ch, c.status);
  });
}

void add_scheme(CLI::App& app, Commands& c) {
  auto* scheme_cmd =
      app.add_subcommand("scheme",
                         "Subdivision schemes: --analyze (JSON), --refine a polygon, --list; mesh schemes: "
                         "--valence N --analyze (--crease K, --dart, --corner, --boundary-valence K)");
  scheme_cmd->add_option("name", c.sc.name, "Scheme name (cifs scheme --list)");
  scheme_cmd->add_option("--param", c.sc.params, "Scheme parameter NAME=VALUE; repeatable")
      ->allow_extra_args(false);
  scheme_cmd->add_flag("--analyze", c.sc.analyze, "Print the analysis as JSON");
  scheme_cmd->add_option("--refine", c.sc.refine, "Polygon file to refine (docs/formats.md)");
  scheme_cmd->add_option("--steps", c.sc.steps, "Refinement steps (default 1)");
  scheme_cmd->add_option("--ends", c.sc.ends, "Open polygons: auto (default), reflect or keep");
  scheme_cmd->add_option(
      "--format", c.sc.format,
      "Refined polygon as json (default), svg or obj; mesh schemes' analysis: json or table");
  scheme_cmd->add_option("--max-power", c.sc.max_power,
                         "Analysis: largest power L of the difference schemes (default 20)");
  scheme_cmd->add_flag("--list", c.sc.list, "List the schemes and their parameters");
  scheme_cmd->add_option("--valence", c.sc.valence,
                         "Mesh schemes (catmull-clark, loop, doo-sabin, butterfly, sqrt3): analyse the local "
                         "subdivision matrix at a vertex of valence N (doo-sabin: an N-gon face)");
  scheme_cmd->add_option("--valences", c.sc.valences, "Mesh schemes: several valences, A..B or A,B,C");
  scheme_cmd->add_option(
      "--boundary", c.sc.boundary,
      "Mesh schemes: a boundary vertex (catmull-clark, loop), rule edge or corner at valence 2");
  scheme_cmd->add_option("--boundary-valence", c.sc.boundary_valence,
                         "Mesh schemes: a boundary vertex with K faces (K + 1 edges; K, A..B or A,B,C)");
  scheme_cmd->add_option(
      "--crease", c.sc.crease,
      "Mesh schemes: infinitely sharp edges r_0 and r_K at --valence N: K faces on one side, "
      "N - K on the other (K, A..B, A,B,C or all)");
  scheme_cmd->add_flag("--dart", c.sc.dart, "Mesh schemes: one infinitely sharp edge (r_0) at --valence N");
  scheme_cmd->add_flag("--corner", c.sc.corner,
                       "Mesh schemes: the vertex infinitely sharp, on a --crease or a --boundary-valence");
  scheme_cmd->add_flag("--concave", c.sc.concave,
                       "Mesh schemes: the --corner's first sector is meant to span more than 180 degrees");
  scheme_cmd->add_option(
      "--interior-corners", c.sc.interior_corners,
      "doo-sabin: a face touching the boundary, 1 (interior) or 0 (boundary) per corner, "
      "e.g. 1010 (--boundary-valence K: every run of 1 to K - 1 interior corners of a K-gon)");
  scheme_cmd->add_option("--rules", c.sc.rules,
                         "Mesh schemes: crease, boundary and corner rules opensubdiv (default) or blz "
                         "(Biermann-Levin-Zorin 2000: C1 at any valence; --concave corners flattened)");
  add_quiet(scheme_cmd, c.quiet);
  scheme_cmd->callback([&] {
    const cifs::render::Stage stage("scheme", c.quiet);
    c.result = cli::scheme(c.sc);
  });
}

void add_render(CLI::App& app, Commands& c) {
  auto* render_cmd = app.add_subcommand(
      "render", "Run experiment files (or look at a shape or mesh): OpenEXR image, PNG preview, geometry");
  render_cmd
      ->add_option("experiment", c.re.experiments,
                   "Experiment files (docs/experiments.md), run in order; a shape or mesh file: a look at it "
                   "with the default camera")
      ->required();
  render_cmd->add_option("-o,--output", c.re.exr, "OpenEXR image (default: the file's outputs.exr)");
  render_cmd->add_option("--png", c.re.png, "PNG preview (default: the file's outputs.png)");
  render_cmd->add_option(
      "--out-dir", c.re.out_dir,
      "Folder of the file's other outputs (default: the folder of -o, else the current one)");
  render_cmd->add_option("--threads", c.re.threads,
                         "Worker threads (default: the file's render.threads; 0: all)");
  render_cmd->add_option("--max-memory", c.re.max_memory,
                         "Refuse (before any work) an image, mesh or curve above SIZE (e.g. 4G; default 2G)");
  render_cmd->add_flag("--quiet", c.re.quiet, "No progress on the terminal");
  render_cmd->callback([&] { c.result = cli::render(c.re); });
}

void add_subdivide(CLI::App& app, Commands& c) {
  auto* subdivide_cmd = app.add_subcommand(
      "subdivide", "Subdivide a polygon mesh: Catmull-Clark, Loop, Doo-Sabin, Butterfly, sqrt3");
  subdivide_cmd->add_option("mesh", c.su.mesh, "Polygon mesh (.obj, .ply, .stl or .off)")->required();
  subdivide_cmd->add_option("--scheme", c.su.scheme, "catmull-clark, loop, doo-sabin, butterfly or sqrt3")
      ->required();
  subdivide_cmd->add_option("--levels", c.su.levels, "Subdivision steps (default 1)");
  subdivide_cmd->add_option(
      "--boundary", c.su.boundary,
      "Boundary rule, replacing the file's: edge (default: corners smoothed), corner (one-face "
      "corners kept) or none (the faces around the boundary left out)");
  subdivide_cmd->add_option("--crease-method", c.su.crease_method,
                            "Semi-sharp creases decay uniform (default) or chaikin, replacing the file's");
  subdivide_cmd->add_option(
      "--triangles", c.su.triangles,
      "Catmull-Clark next to triangles: catmark (default) or smooth, replacing the file's");
  subdivide_cmd->add_option(
      "--fvar-interpolation", c.su.fvar_interpolation,
      "Face-varying data (UVs): all (linear, default); the smooth modes are not built yet");
  subdivide_cmd->add_option("--rules", c.su.rules,
                            "Crease, boundary and corner rules opensubdiv (default) or blz "
                            "(Biermann-Levin-Zorin 2000), replacing the file's");
  subdivide_cmd->add_flag("--factored", c.su.factored,
                          "Linear subdivision then averaging (catmull-clark on quads, loop); same result");
  add_strict(subdivide_cmd, c.su.strict);
  subdivide_cmd->add_flag("--quiet", c.su.quiet, "No progress bar");
  subdivide_cmd->add_option("-o,--output", c.su.output,
                            "Output mesh (.obj, .ply, .stl, .off or .vtp; default: OBJ on stdout)");
  subdivide_cmd->callback([&] { c.result = cli::subdivide(c.su); });
}

void add_analyze(CLI::App& app, Commands& c) {
  auto* analyze_cmd = app.add_subcommand(
      "analyze", "Which points of a mesh are not smooth: every irregular vertex's class and C1 verdict");
  analyze_cmd->add_option("mesh", c.an.mesh, "Polygon mesh (.obj, .ply, .stl or .off)")->required();
  analyze_cmd->add_option("--scheme", c.an.scheme, "catmull-clark, loop, sqrt3, butterfly or doo-sabin")
      ->required();
  analyze_cmd->add_option("--format", c.an.format, "table (default) or json");
  analyze_cmd->add_option("--boundary", c.an.boundary,
                          "Boundary rule, replacing the file's: edge (default) or corner");
  analyze_cmd->add_option(
      "--rules", c.an.rules,
      "Crease, boundary and corner rules opensubdiv (default) or blz, replacing the file's");
  add_strict(analyze_cmd, c.an.strict);
  analyze_cmd->add_option(
      "--png", c.an.png,
      "Also write the surface (3 levels) as PNG with the irregular vertices marked: green C1, "
      "red not C1, orange undecided");
  analyze_cmd->callback([&] {
    const cifs::render::Stage stage("analyze", c.quiet);
    c.result = cli::analyze(c.an);
  });
}

void add_limit(CLI::App& app, Commands& c) {
  auto* limit_cmd = app.add_subcommand(
      "limit", "Limit points (and normals) of a subdivision surface: catmull-clark, loop, butterfly, sqrt3");
  limit_cmd->add_option("mesh", c.li.mesh, "Polygon mesh (.obj, .ply, .stl or .off)")->required();
  limit_cmd->add_option("--scheme", c.li.scheme, "catmull-clark, loop, butterfly or sqrt3")->required();
  auto* levels = limit_cmd->add_option("--levels", c.li.levels,
                                       "Subdivision steps before the vertices go to the limit (default 1)");
  limit_cmd->add_option(
      "--boundary", c.li.boundary,
      "Boundary rule, replacing the file's: edge (default: corners smoothed) or corner (kept)");
  limit_cmd->add_flag("--normals", c.li.normals,
                      "Write unit limit normals (at crease and corner vertices one per sector, per face "
                      "corner: OBJ f v//n; PLY refuses them)");
  auto* at = limit_cmd
                 ->add_option("--at", c.li.at,
                              "The limit surface at points 'face,u,v;face,u,v…' (or a file of them, one a "
                              "line) in OpenSubdiv's parametrisation, as JSON (catmull-clark, loop)")
                 ->excludes(levels);
  limit_cmd->add_flag("--partials", c.li.partials, "With --at: the partials du, dv too")->needs(at);
  add_strict(limit_cmd, c.li.strict);
  limit_cmd->add_option("-o,--output", c.li.output,
                        "Output mesh (.obj, .ply, .stl, .off or .vtp; default: OBJ on stdout)");
  add_quiet(limit_cmd, c.quiet);
  limit_cmd->callback([&] {
    const cifs::render::Stage stage("limit", c.quiet);
    c.result = cli::limit(c.li);
  });
}

void add_dimension(CLI::App& app, Commands& c) {
  auto* dimension_cmd = app.add_subcommand(
      "dimension",
      "Box-counting dimension of an experiment's or shape's attractor (and similarity dimension)");
  dimension_cmd->add_option("input", c.di.input, "Experiment file, or shape file (.json or .obj)")
      ->required();
  auto* dimension_depth = dimension_cmd->add_option(
      "--depth", c.di.measure.depth, "Evaluate to this depth instead of sampling to a tolerance");
  dimension_cmd
      ->add_option("--relative-piece-size", c.di.measure.relative_piece_size,
                   "Sample: every piece smaller than this fraction of the control nets' extent (0: "
                   "the smallest 2^-j within --max-points)")
      ->excludes(dimension_depth);
  add_renamed(dimension_cmd, "--tolerance", "--relative-piece-size");
  dimension_cmd->add_option("--max-points", c.di.measure.max_points,
                            "Point budget of the tolerance sample (default 2^21)");
  dimension_cmd->add_option("--min-level", c.di.measure.min_level,
                            "Fit range: coarsest box level k (ε = size·2^-k)");
  dimension_cmd->add_option("--max-level", c.di.measure.max_level, "Fit range: finest box level");
  dimension_cmd->add_option("--min-boxes", c.di.measure.min_boxes,
                            "Automatic fit range: only levels with at least this many boxes (default 1000)");
  dimension_cmd->add_flag("--json", c.di.json, "Machine-readable report");
  add_shape_selection(dimension_cmd, c.di.select);
  add_quiet(dimension_cmd, c.quiet);
  dimension_cmd->callback([&] {
    const cifs::render::Stage stage("dimension", c.quiet);
    c.result = cli::dimension(c.di);
  });
}

void add_gallery(CLI::App& app, Commands& c) {
  auto* gallery_cmd = app.add_subcommand("gallery", "Write the example gallery (the built-in default job)");
  gallery_cmd->add_option("out", c.gallery_out, "Output folder (default: out)");
  gallery_cmd->add_option("--examples", c.gallery_examples,
                          "Folder with shapes/ and experiments/ (default: " + c.gallery_examples.string() +
                              ": the installed examples, or the source tree's for the build tree's cifs)");
  gallery_cmd->add_flag("--quiet", c.quiet, "No progress on the terminal");
  gallery_cmd->callback([&] { c.result = cli::gallery(c.gallery_out, c.gallery_examples, c.quiet); });
}

void add_view(CLI::App& app, Commands& c) {
  auto* view_cmd = app.add_subcommand("view",
                                      "Explore a shape, mesh, BC-IFS or experiment in the browser: a local "
                                      "web page (prints its URL), or --export DIR");
  view_cmd
      ->add_option(
          "file", c.view_path,
          "Shape file (.json, .obj, .step or .igs), polygon mesh (.obj, .ply, .stl or .off), BC-IFS file "
          "or experiment file (.json)")
      ->required();
  view_cmd->add_option("--host", c.view.host,
                       "Address to listen on (default 127.0.0.1; any other is reachable from the network)");
  view_cmd->add_option("--port", c.view.port, "Port (default 8765; 0: any free port)");
  view_cmd->add_flag("--open", c.view.open, "Open the page with xdg-open");
  view_cmd->add_option("--export", c.view_export,
                       "Write a self-contained static page (geometry baked in, three.js copied) into DIR");
  view_cmd->callback([&] {
    if (!c.view_export.empty()) {
      cifs::view::export_page(c.view_path, c.view_export);
      c.result = "wrote " + (c.view_export / "index.html").string() + "\n";
      return;
    }
    if (c.view.host != "127.0.0.1" && c.view.host != "localhost")
      std::cerr
          << "cifs: warning: --host " << c.view.host
          << ": the page (and saving into the file's folder) is open to whoever reaches this address and "
             "has the URL\n";
    c.view.listening = [](const std::string& url) { std::cout << url << std::endl; };
    cifs::view::serve(c.view_path, c.view);
  });
}

/// `--name` and `-n` of the options of `command` shown in its help.
std::vector<std::string> option_names(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* o :
       command.get_options([](const CLI::Option* o) { return !o->get_group().empty(); })) {
    for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
    for (const std::string& n : o->get_snames()) names.push_back("-" + n);
  }
  return names;
}

std::vector<std::string> command_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

/// CLI11's "The following arguments were not expected" made specific: the first unexpected argument of
/// `command` — an unknown option (and the one it may be a typo of), or a value beyond what the option
/// before it takes (`--at 0.5 0.5`). Empty when the arguments do not show it.
std::string unexpected_argument(const CLI::App& command, int argc, char** argv) {
  std::size_t positionals = 0;
  for (const CLI::Option* o : command.get_options([](const CLI::Option* o) { return o->get_positional(); }))
    positionals += o->get_items_expected_max() > 1 ? std::size_t{1} << 30 : 1;
  const CLI::Option* last = nullptr;  // the option whose value came just before
  std::string last_text;
  bool list = false;  // `last` takes every value up to the next option
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool number = arg.find_first_not_of("-+.0123456789eE,") == std::string::npos;
    if (arg.size() > 1 && arg[0] == '-' && !number) {
      const std::string name = arg.substr(0, arg.find('='));
      const CLI::Option* option = command.get_option_no_throw(name);
      if (option == nullptr)
        return "unknown option '" + name + "' of " + command.get_name() +
               cifs::did_you_mean(name, option_names(command)) + " (see cifs " + command.get_name() +
               " --help)";
      last = nullptr;
      if (option->get_type_size() == 0 || arg.find('=') != std::string::npos || i + 1 == argc) continue;
      last = option;
      last_text = name + " " + argv[++i];
      list = option->get_allow_extra_args() && option->get_items_expected_max() > 1;
    } else if (last != nullptr && list) {
      continue;
    } else if (positionals > 0) {
      --positionals;
      last = nullptr;
    } else {
      std::string message = command.get_name() + ": unexpected argument '" + arg + "'";
      if (last != nullptr)
        message += " after " + last_text + ": " + last->get_name() + " takes one value (" +
                   last->get_description() + ")";
      return message;
    }
  }
  return {};
}

void add_fit(CLI::App& app, Commands& c) {
  auto* fit_cmd = app.add_subcommand(
      "fit", "Fit a curve to points: interpolation, or least squares by --control-points or --tolerance");
  fit_cmd->add_option("points", c.fi.points, "Points file (.csv, .txt, .xyz, .npy, .json or .obj)")
      ->required();
  fit_cmd->add_option("--degree", c.fi.degree, "Degree of the curve (default 3)");
  fit_cmd->add_option("--control-points", c.fi.control_points, "Least squares with N control points");
  fit_cmd->add_option("--tolerance", c.fi.tolerance,
                      "Least squares with the fewest knots so that every point is within E of the curve");
  fit_cmd->add_option("--parametrization", c.fi.parametrization,
                      "uniform, chord_length (default) or centripetal");
  fit_cmd->add_option(
      "--measure", c.fi.measure,
      "What --tolerance bounds: points (default) or polyline (the Hausdorff distance to the polyline)");
  fit_cmd->add_flag("--closed", c.fi.closed, "A closed (periodic) interpolating (or --fractal) curve");
  fit_cmd->add_flag(
      "--fractal", c.fi.fractal,
      "Fit a fractal curve: a BC-IFS of the uniform B-spline of --control-points N whose free "
      "coefficients and control points minimise the distance to the points (-o writes a BC-IFS file)");
  fit_cmd->add_flag(
      "--fixed-knot-points", c.fi.fixed_knot_points,
      "--fractal: keep the operators at the knots (only the vertices subdivision creates move)");
  fit_cmd->add_option("--depth", c.fi.depth,
                      "--fractal: data parameters at multiples of 2^-D of a segment (default 30)");
  fit_cmd->add_option("--iterations", c.fi.iterations,
                      "--fractal: Levenberg–Marquardt iterations (default 100)");
  fit_cmd->add_option(
      "--min-holder", c.fi.min_holder,
      "--fractal: keep the curve provably Hölder of at least this exponent in (0, 1] (default 0.25)");
  fit_cmd->add_option("-o,--output", c.fi.output,
                      "Shape file to write (.json or .obj); default: JSON on stdout");
  add_quiet(fit_cmd, c.quiet);
  fit_cmd->callback([&c, fit_cmd] {
    if (!c.fi.fractal)
      for (const char* name : {"--fixed-knot-points", "--depth", "--iterations", "--min-holder"})
        if (fit_cmd->count(name) > 0) throw cifs::InvalidInput(std::string(name) + " is for --fractal fits");
    if (c.fi.fractal && fit_cmd->count("--measure") > 0)
      throw cifs::InvalidInput("--measure is for --tolerance fits, not --fractal");
    const cifs::render::Stage stage("fit", c.quiet);
    c.result = cli::fit(c.fi);
  });
}

void add_construct(CLI::App& app, Commands& c) {
  auto* cmd = app.add_subcommand(
      "construct", "A surface from curves: ruled A B, extrude C, revolve P, loft C1 C2 …, sweep P T");
  cmd->add_option("kind", c.co.kind, "ruled, extrude, revolve, loft or sweep")->required();
  cmd->add_option("curves", c.co.curves, "Curve files (.json or .obj), in order")->required();
  cmd->add_option("--direction", c.co.direction,
                  "extrude: the direction 'x,y,z' (the surface is C(u) + v·d)");
  cmd->add_option("--axis-point", c.co.axis_point, "revolve: a point of the axis 'x,y,z' (default 0,0,0)");
  cmd->add_option("--axis", c.co.axis, "revolve: the axis direction 'x,y,z' (default 0,0,1)");
  cmd->add_option("--angle", c.co.angle, "revolve: the angle in degrees, (0, 360] (default 360)");
  cmd->add_option(
      "--degree-v", c.co.degree_v,
      "loft, sweep with --instances: the degree across the curves (default 3, at most curves − 1)");
  cmd->add_option("--parametrization", c.co.parametrization,
                  "loft: the curves' v-parameters: uniform, chord_length (default) or centripetal");
  cmd->add_option("--instances", c.co.instances,
                  "sweep: 0 (default) the exact translational sweep; N ≥ 2 the profile carried by the "
                  "trajectory's rotation-minimizing frames through N instances (approximate)");
  cmd->add_option("-o,--output", c.co.output, "Shape file to write (.json or .obj); default: JSON on stdout");
  add_quiet(cmd, c.quiet);
  cmd->callback([&] {
    const cifs::render::Stage stage("construct", c.quiet);
    c.result = cli::construct(c.co);
  });
}

/// Parses and runs one command; everything it prints on stdout goes to `result`.
int run(int argc, char** argv, std::string& result) {
  CLI::App app{"cifs — NURBS curves and surfaces as controlled iterated function systems"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cifs " CIFS_VERSION);  // CMake's PROJECT_VERSION
  Commands c(result);
  // Every file the command reads is an input no output of it may replace (cifs/files.hpp).
  const cifs::RunInputs inputs;
  add_eval(app, c);
  add_insert(app, c);
  add_info(app, c);
  add_convert(app, c);
  add_automaton(app, c);
  add_attractor(app, c);
  add_check(app, c);
  add_scheme(app, c);
  add_render(app, c);
  add_subdivide(app, c);
  add_limit(app, c);
  add_analyze(app, c);
  add_dimension(app, c);
  add_fit(app, c);
  add_construct(app, c);
  add_gallery(app, c);
  add_view(app, c);
  refuse_empty_values(app);

  try {
    const std::string first = argc > 1 ? argv[1] : "-";
    const auto known = app.get_subcommands([&](const CLI::App* sub) { return sub->get_name() == first; });
    if (first[0] != '-' && known.empty()) {
      const std::vector<std::string> commands = command_names(app);
      std::string list;
      for (const std::string& name : commands) list += (list.empty() ? "" : ", ") + name;
      throw cifs::InvalidInput("unknown command '" + first + "'" + cifs::did_you_mean(first, commands) +
                               " (commands: " + list + "; see cifs --help)");
    }
    // CLI11 would report the missing command ("A subcommand is required") instead of the option.
    const std::string option = first.substr(0, first.find('='));
    if (first.size() > 1 && first[0] == '-' && app.get_option_no_throw(option) == nullptr) {
      const std::string near = cifs::did_you_mean(option, option_names(app));
      throw cifs::InvalidInput(
          "unknown option '" + option + "'" +
          (near.empty() ? "; options follow the command: cifs COMMAND [OPTIONS]" : near) +
          " (see cifs --help)");
    }
    try {
      app.parse(argc, argv);
    } catch (const CLI::ExtrasError&) {
      const std::string message = known.empty() ? "" : unexpected_argument(*known.front(), argc, argv);
      if (message.empty()) throw;
      throw cifs::InvalidInput(message);
    }
  } catch (const CLI::CallForHelp& e) {
    return help_or_version(app, e, result);
  } catch (const CLI::CallForAllHelp& e) {
    return help_or_version(app, e, result);
  } catch (const CLI::CallForVersion& e) {
    return help_or_version(app, e, result);
  } catch (const cli::StdoutError& e) {  // streamed points that stdout could not take
    std::cerr << "cifs: " << e.what() << "\n";
    return 1;
  } catch (const CLI::ParseError& e) {
    std::cerr << "cifs: " << e.what() << " (see cifs --help)\n";
    return 2;
  } catch (
      const std::filesystem::filesystem_error& e) {  // one the readers' own checks missed: named by its path
    std::cerr << "cifs: " << (e.path1().empty() ? std::string() : e.path1().string() + ": ")
              << e.code().message() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {  // said "cifs: std::bad_alloc" under a memory limit
    std::cerr << "cifs: out of memory: the system refused an allocation; ask for less (a lower --depth, "
                 "fewer points or samples, a smaller image)\n";
    return 2;
  } catch (const std::exception& e) {
    std::string message = e.what();
    std::replace(message.begin(), message.end(), '\n', ' ');
    std::cerr << "cifs: " << message << "\n";
    return 2;
  }
  return c.status;
}

}  // namespace

int main(int argc, char** argv) {
  std::string result;
  int status = 0;
  cifs::cli::World world;
  try {
#ifdef CIFS_HAVE_OCCT
    cifs::cli::load_occt_on_demand();  // .step, .stp, .igs, .iges: OpenCASCADE opened when first needed
#endif
    world = cifs::cli::start_world(argc, argv);
    cifs::cli::world() = world;
    // Under mpirun every process runs the command: only render divides its work and writes once.
    if (world.size > 1 && (argc < 2 || std::string(argv[1]) != "render")) {
      if (world.rank == 0) std::cerr << "cifs: only cifs render runs on several MPI processes\n";
      cifs::cli::end_world();
      return 2;
    }
    status = run(argc, argv, result);
  } catch (const std::exception& e) {  // outside parsing: the command table
    std::cerr << "cifs: " << e.what() << "\n";
    status = 2;
  } catch (...) {
    std::cerr << "cifs: unexpected error\n";
    status = 2;
  }
  // A failed process may leave the others waiting in the reduction: stop them all.
  if (world.size > 1 && status == 2) cifs::cli::abort_world(2);
  cifs::cli::end_world();
  if (status == 2 && result.empty()) return 2;
  if (!std::cout.good()) return 1;  // a streamed write failed, and said so
  // Every command's output, help and version included, is written and checked here once: a full disk or a
  // closed pipe shows only when the buffer goes out, so the flush comes before the check. errno
  // tells why when the failing write was one of these.
  if (status != 2)
    for (const std::string& w : cifs::cli::pending_warnings()) std::cerr << "cifs: warning: " << w << "\n";
  errno = 0;
  std::cout << result << std::flush;
  if (!std::cout.good()) {
    const int error = errno;
    std::cerr << "cifs: cannot write to standard output" << (error != 0 ? ": " : "")
              << (error != 0 ? std::strerror(error) : "") << "\n";
    return 1;
  }
  return status;
}
