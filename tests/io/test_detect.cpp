// SPDX-License-Identifier: MIT
// io::detect: the one file-type sniffer behind cifs info and cifs dimension.
#include <catch2/catch.hpp>
#include <fstream>

#include "cifs/errors.hpp"
#include "cifs/io/io.hpp"
#include "support/scratch.hpp"

using namespace cifs;

TEST_CASE("io::detect tells meshes, shapes, polygons and experiments apart", "[io][detect]") {
  const std::string examples = CIFS_EXAMPLES_DIR;
  CHECK(io::detect(examples + "/meshes/cube.obj") == io::Content::mesh);
  CHECK(io::detect(examples + "/shapes/wave.json") == io::Content::shape);
  CHECK(io::detect(examples + "/shapes/hills.json") == io::Content::shape);
  CHECK(io::detect(examples + "/shapes/geomdl_curve.json") == io::Content::shape);  // "shape" alone
  CHECK(io::detect(examples + "/shapes/clover.json") == io::Content::polygon);
  CHECK(io::detect(examples + "/experiments/clover.json") == io::Content::experiment);  // inline "shape"
  cifs_test::ScratchDir dir;
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.path() / name) << text;
    return dir.path() / name;
  };
  CHECK(io::detect(write("m.ply", "not even read")) == io::Content::mesh);
  CHECK(io::detect(write("c.obj",
                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ncstype bspline\ndeg 3\n"
                         "curv 0 1 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\nend\n")) == io::Content::shape);
  CHECK(io::detect(write("f.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n  f 1 2 3\r\n")) == io::Content::mesh);
  CHECK(io::detect(write("p.obj", "v 0 0 0\nv 1 0 0\n")) == io::Content::shape);  // no faces
  CHECK(io::detect(write("bad.json", "{not json")) == io::Content::shape);        // its reader says why
  // A trivariate volume is a shape (cifs info read it as an experiment once experiments had an info).
  CHECK(io::detect(write("v.json", R"({"volume": {"degree": [1, 1, 1]}})")) == io::Content::shape);
  CHECK_THROWS_AS(io::detect(dir.path() / "missing.json"), IoError);
}
