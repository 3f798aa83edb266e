// SPDX-License-Identifier: MIT
// cifs — command-line entry point. Errors: one line on stderr, nothing on stdout, exit status 2.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cifs/errors.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
  using namespace cifs::cli;
  CLI::App app{"cifs — NURBS curves and surfaces as controlled iterated function systems"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cifs 0.1.0");
  std::string result;

  EvalOptions ev;
  auto* eval_cmd = app.add_subcommand("eval", "Evaluate a curve or surface; prints {\"points\": [...]}");
  eval_cmd->add_option("shape", ev.shape, "Shape file (.json or .obj)")->required();
  eval_cmd->add_option("--at", ev.at, "Parameter U (curves) or U,V (surfaces); repeatable")
      ->allow_extra_args(false);
  eval_cmd->add_option("--samples", ev.samples,
                       "N parameters evenly spaced over the domain (surfaces: N×N grid)");
  eval_cmd->callback([&] { result = eval(ev); });

  InsertOptions in;
  auto* insert_cmd = app.add_subcommand("insert", "Insert knots; prints the refined shape as JSON");
  insert_cmd->add_option("shape", in.shape, "Shape file (.json or .obj)")->required();
  insert_cmd->add_option("--knot", in.knots, "Knot to insert; repeatable")->allow_extra_args(false);
  insert_cmd->add_option("--dir", in.dir, "Surface direction: u or v");
  insert_cmd->add_flag("--midpoints", in.midpoints,
                       "Insert the midpoint of every span (both directions for surfaces)");
  insert_cmd->callback([&] { result = insert(in); });

  std::filesystem::path info_shape;
  auto* info_cmd = app.add_subcommand("info", "Degree, counts, domain and segments of a shape");
  info_cmd->add_option("shape", info_shape, "Shape file (.json or .obj)")->required();
  info_cmd->callback([&] { result = info(info_shape); });

  std::filesystem::path gallery_out = "out";
  auto* gallery_cmd = app.add_subcommand("gallery", "Write the example gallery (the built-in default job)");
  gallery_cmd->add_option("out", gallery_out, "Output folder (default: out)");
  gallery_cmd->callback([&] { result = gallery(gallery_out); });

  try {
    const std::string first = argc > 1 ? argv[1] : "-";
    const auto known = app.get_subcommands([&](const CLI::App* sub) { return sub->get_name() == first; });
    if (first[0] != '-' && known.empty())
      throw cifs::InvalidInput("unknown command '" + first +
                               "' (commands: eval, insert, info, gallery; see cifs --help)");
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "cifs: " << e.what() << " (see cifs --help)\n";
    return 2;
  } catch (const std::exception& e) {
    std::string message = e.what();
    for (char& ch : message)
      if (ch == '\n') ch = ' ';
    std::cerr << "cifs: " << message << "\n";
    return 2;
  }
  std::cout << result;
  return std::cout.good() ? 0 : 1;
}
