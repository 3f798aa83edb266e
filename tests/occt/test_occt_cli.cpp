// SPDX-License-Identifier: MIT
// cifs convert, info and eval on STEP and IGES files, as a user runs them (the CLI built with cifs::occt).
#include <catch2/catch.hpp>
#include <fstream>

#include "cifs/occt/occt.hpp"

#include "apps/cli_runner.hpp"
#include "cifs/io/io.hpp"
#include "cifs/nurbs/surface.hpp"

using cifs_test::cifs_cli;
using cifs_test::scratch;

namespace {

std::string occt_cli_example(const std::string& name) {
  return std::string(CIFS_EXAMPLES_DIR) + "/shapes/" + name;
}

/// The error of a refused command: one line, exit 2.
void occt_cli_refused(const cifs_test::Run& run, const std::string& expected) {
  INFO(run.err);
  CHECK(run.status == 2);
  CHECK(run.out.empty());
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK_THAT(run.err, Catch::Contains(expected));
}

}  // namespace

TEST_CASE("cifs convert: JSON to STEP and IGES and back, the same shape", "[occt][cli]") {
  for (const char* ext : {".step", ".igs"}) {
    INFO(ext);
    const auto cad = scratch() / (std::string("hills") + ext), back = scratch() / "hills_back.json";
    REQUIRE(cifs_cli("convert " + occt_cli_example("hills.json") + " " + cad.string()).status == 0);
    const cifs_test::Run converted = cifs_cli("convert " + cad.string() + " " + back.string());
    REQUIRE(converted.status == 0);
    CHECK(converted.out.empty());
    const auto original =
        std::get<cifs::nurbs::Surface>(cifs::io::read_shape(occt_cli_example("hills.json")));
    const auto read = std::get<cifs::nurbs::Surface>(cifs::io::read_shape(back));
    for (double u : {0.0, 0.3, 1.7, 4.5})
      for (double v : {0.0, 2.2, 4.5})
        CHECK((cifs::nurbs::evaluate(read, u, v) - cifs::nurbs::evaluate(original, u, v))
                  .cwiseAbs()
                  .maxCoeff() <= 1e-12 * 10);
  }
}

TEST_CASE("cifs info and eval on STEP and IGES files of several shapes: --index picks one", "[occt][cli]") {
  // The 2-D wave: written with z = 0, and said so.
  const auto step = scratch() / "wave.step";
  const cifs_test::Run first = cifs_cli("convert " + occt_cli_example("wave.json") + " " + step.string());
  REQUIRE(first.status == 0);
  CHECK_THAT(first.err, Catch::Contains("shape 0 is 2-D: written with its missing coordinates 0"));
  const cifs_test::Run info = cifs_cli("info " + step.string());
  REQUIRE(info.status == 0);
  CHECK_THAT(info.out, Catch::Contains("\"type\": \"curve\""));

  // A file of two: info lists both; eval wants --index.
  cifs::occt::enable_cad_formats();  // this process writes it through io
  const auto pair = scratch() / "pair.igs";
  cifs::io::write(pair, std::vector<cifs::io::Shape>{cifs::io::read_shape(occt_cli_example("hills.json")),
                                                     cifs::io::read_shape(occt_cli_example("wave.json"))});
  const cifs_test::Run both = cifs_cli("info " + pair.string());
  REQUIRE(both.status == 0);
  CHECK_THAT(both.out, Catch::Contains("\"index\": 1"));
  occt_cli_refused(cifs_cli("eval " + pair.string() + " --at 0.5"),
                   "choose one with --index N, N from 0 to 1");
  const cifs_test::Run picked = cifs_cli("eval " + pair.string() + " --index 1 --at 3");
  REQUIRE(picked.status == 0);
  CHECK_THAT(picked.out, Catch::StartsWith("{\"points\":[["));
}

TEST_CASE("cifs convert: refusals are one line, exit 2, nothing written", "[occt][cli]") {
  occt_cli_refused(
      cifs_cli("convert " + (scratch() / "missing.step").string() + " " + (scratch() / "x.json").string()),
      "missing.step");
  const auto junk = scratch() / "junk.step";
  std::ofstream(junk) << "ISO-10303-21;\nno\n";
  occt_cli_refused(cifs_cli("convert " + junk.string() + " " + (scratch() / "y.json").string()),
                   "not a STEP file");
  occt_cli_refused(
      cifs_cli("convert " + occt_cli_example("hills.json") + " " + (scratch() / "z.xyz").string()),
      "a shape is written as .json, .obj, .step, .stp, .iges or .igs");
  CHECK(!std::filesystem::exists(scratch() / "x.json"));
  CHECK(!std::filesystem::exists(scratch() / "y.json"));
  CHECK(!std::filesystem::exists(scratch() / "z.xyz"));
}
