// SPDX-License-Identifier: MIT
// Point-set files written in chunks (PointsWriter, PointsFile): every split of the rows gives the bytes
// of the set encoded at once; the npy and PLY bytes are checked against hand-built headers and the
// IEEE little-endian doubles.
#include "cifs/io/points.hpp"

#include <unistd.h>

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/obj.hpp"
#include "support/scratch.hpp"

using namespace cifs;
using namespace cifs::io;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {
Points some_points(Eigen::Index n, Eigen::Index dim) {
  Points P(n, dim);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < dim; ++k) {
      const auto x = static_cast<double>(i), c = static_cast<double>(k);
      P(i, k) = std::sin(0.37 * x + c) * (c + 1) / 3.0;
    }
  return P;
}

/// The points written through a PointsWriter in blocks of `block` rows.
std::string chunked(const Points& P, std::string_view format, Eigen::Index block,
                    const PointsStyle& style = {}) {
  StringSink out;
  PointsWriter w(out, format, static_cast<std::uint64_t>(P.rows()), P.cols(), style);
  for (Eigen::Index i = 0; i < P.rows(); i += block) w.write(P.middleRows(i, std::min(block, P.rows() - i)));
  w.finish();
  return out.bytes;
}

std::string little_endian(double x) {
  std::string out;
  const auto bits = std::bit_cast<std::uint64_t>(x);
  for (int b = 0; b < 8; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xFF);
  return out;
}

}  // namespace

TEST_CASE("Point sets: the table, and any split of the rows gives the bytes of the whole", "[io][points]") {
  std::string names;
  for (const Format& f : formats(Content::points))
    names += std::string(f.name) + f.extension.data() + (f.binary ? "b " : " ");
  CHECK(names == "json.json npy.npyb ply.plyb obj.obj ");
  const Points P = some_points(10000, 3);  // more than one chunk of text
  for (const char* format : {"json", "npy", "ply", "obj"}) {
    INFO(format);
    const std::string whole = encode(PointSet{P, {}}, format);
    for (const Eigen::Index block : {1, 7, 4096, 4097, 10000}) CHECK(chunked(P, format, block) == whole);
  }
  const PointsStyle polyline{.polyline = true, .closed = true, .seed = {}};
  CHECK(chunked(P, "obj", 333, polyline) == encode(PointSet{P, polyline}, "obj"));
  CHECK(encode(PointSet{P, polyline}, "obj") == polyline_obj(P, true));
}

TEST_CASE("Point sets: JSON and OBJ text", "[io][points]") {
  Points P(3, 2);
  P << 0, 0.5, 1, -2, 3.25, 1e-300;
  CHECK(encode(PointSet{P, {}}, "json") == "{\"points\":[[0,0.5],[1,-2],[3.25,1e-300]]}\n");
  CHECK(encode(PointSet{P, {.polyline = false, .closed = false, .seed = 42}}, "json") ==
        "{\"points\":[[0,0.5],[1,-2],[3.25,1e-300]],\"seed\":42}\n");
  CHECK(encode(PointSet{Points(0, 2), {}}, "json") == "{\"points\":[]}\n");
  CHECK(encode(PointSet{P, {}}, "obj") == "# cifs points, 3 points\nv 0 0.5 0\nv 1 -2 0\nv 3.25 1e-300 0\n");
  CHECK_THAT(encode(PointSet{P, {.polyline = true, .closed = false, .seed = {}}}, "obj"),
             StartsWith("# cifs polyline, 3 points\n") && Catch::EndsWith("\nl 1 2 3\n"));
}

TEST_CASE("Point sets: npy as NumPy 1.0 lays it out", "[io][points]") {
  Points P(2, 3);
  P << 1, 2, 3, -0.5, 1e-3, 6;
  const std::string npy = encode(PointSet{P, {}}, "npy");
  // numpy.save(f, P): magic, version 1.0, uint16 header length, the dictionary padded with spaces
  // (21 digits of room for the count, then to a multiple of 64) and a newline, then '<f8' in C order.
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";
  dict += std::string(20, ' ');  // 21 − len("2")
  dict += std::string(64 - (10 + dict.size() + 1) % 64, ' ') + "\n";
  REQUIRE(dict.size() == 118);
  std::string expected = std::string("\x93NUMPY\x01\x00", 8) + static_cast<char>(118) + '\0' + dict;
  REQUIRE(expected.size() == 128);
  for (const double x : {1.0, 2.0, 3.0, -0.5, 1e-3, 6.0}) expected += little_endian(x);
  CHECK(npy == expected);
  CHECK(points_file_size("npy", 2, 3) == npy.size());
  // The header keeps its size as the count grows (numpy's room for in-place growth).
  CHECK(*points_file_size("npy", 123456789012345, 3) - 123456789012345ULL * 24 == 128);
  CHECK_FALSE(points_file_size("json", 2, 3).has_value());
  CHECK_FALSE(points_file_size("obj", 2, 3).has_value());
}

TEST_CASE("Point sets: PLY binary point clouds", "[io][points]") {
  Points P(2, 2);
  P << 1, 2, -3, 0.25;
  const std::string ply = encode(PointSet{P, {}}, "ply");
  std::string expected =
      "ply\nformat binary_little_endian 1.0\ncomment cifs points\nelement vertex 2\n"
      "property double x\nproperty double y\nproperty double z\nend_header\n";
  for (const double x : {1.0, 2.0, 0.0, -3.0, 0.25, 0.0}) expected += little_endian(x);  // z = 0
  CHECK(ply == expected);
  CHECK(points_file_size("ply", 2, 2) == ply.size());
  CHECK_THROWS_WITH(encode(PointSet{Points::Zero(2, 4), {}}, "ply"),
                    "ply: points have 4 coordinates, ply holds at most 3");
  CHECK_THROWS_WITH(encode(PointSet{Points::Zero(2, 4), {}}, "obj"),
                    "obj: points have 4 coordinates, obj holds at most 3");
  CHECK_NOTHROW(encode(PointSet{Points::Zero(2, 4), {}}, "npy"));
}

TEST_CASE("PointsWriter refuses rows that do not match its header", "[io][points]") {
  StringSink out;
  CHECK_THROWS_WITH(PointsWriter(out, "csv", 2, 2), "format 'csv': expected json, npy, ply or obj");
  PointsWriter w(out, "npy", 3, 2);
  CHECK_THROWS_WITH(w.write(Points::Zero(1, 3)), "npy: rows of 3 coordinates given, the file holds 2");
  w.write(Points::Zero(2, 2));
  CHECK_THROWS_WITH(w.write(Points::Zero(2, 2)), "npy: more than the 3 points of the header");
  CHECK_THROWS_WITH(w.finish(), "npy: 2 points written, the header says 3");
}

TEST_CASE("No writer emits a number that is not finite", "[io][points][reliability]") {
  // write_points wrote nan and inf into JSON (invalid JSON) and OBJ, exit 0 (issue 33).
  cifs_test::ScratchDir s("points");
  for (const double bad :
       {std::nan(""), std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
    Points P = Points::Zero(4, 3);
    P(2, 1) = bad;
    const std::string why = "point 2 coordinate 1 is not a finite number";
    for (const char* format : {"json", "npy", "ply", "obj"}) {
      INFO(format);
      CHECK_THROWS_WITH(encode(PointSet{P, {}}, format), Catch::Contains("the points: " + why));
      CHECK_THROWS_WITH(write(s.path() / (std::string("p.") + format), PointSet{P, {}}),
                        Catch::Contains(why));
      StringSink out;
      PointsWriter w(out, format, 6, 3);
      w.write(Points::Zero(2, 3));
      // Rows are numbered in the whole file.
      CHECK_THROWS_WITH(w.write(P), Catch::Contains("point 4 coordinate 1 is not a finite number"));
    }
    CHECK_THROWS_WITH(encode(Polygon{P, false}, "json"), Catch::Contains("the polygon: " + why));
    CHECK_THROWS_WITH(encode(Polygon{P, false}, "svg"), Catch::Contains("the polygon: " + why));
    Mesh m;
    m.vertices = P;
    m.face_offsets = {0, 3};
    m.face_vertices = {0, 1, 2};
    CHECK_THROWS_WITH(encode(m, "obj"), Catch::Contains("the mesh's vertices: " + why));
  }
  CHECK(s.names().empty());
}

TEST_CASE("PointsFile: by extension, atomic, the disk space checked", "[io][points]") {
  cifs_test::ScratchDir s("points");
  const Points P = some_points(5000, 3);
  for (const char* format : {"json", "npy", "ply", "obj"}) {
    const auto path = s.path() / (std::string("p.") + format);
    PointsFile file(path, 5000, 3);
    for (Eigen::Index i = 0; i < 5000; i += 1234)
      file.write(P.middleRows(i, std::min<Eigen::Index>(1234, 5000 - i)));
    CHECK_FALSE(std::filesystem::exists(path));  // only the temporary until commit
    file.commit();
    CHECK(read_file(path) == encode(PointSet{P, {}}, format));
  }
  CHECK(s.names() == std::set<std::string>{"p.json", "p.npy", "p.ply", "p.obj"});
  CHECK_THROWS_WITH(PointsFile(s.path() / "p.txt", 1, 3),
                    (s.path() / "p.txt").string() + ": a point set is written as .json, .npy, .ply or .obj");
  // An error before commit (too few rows) leaves nothing behind, and the old file untouched.
  {
    PointsFile file(s.path() / "p.npy", 5000, 3);
    file.write(P.topRows(10));
    CHECK_THROWS_WITH(file.commit(), "npy: 10 points written, the header says 5000");
  }
  CHECK(read_file(s.path() / "p.npy") == encode(PointSet{P, {}}, "npy"));
  CHECK(s.names() == std::set<std::string>{"p.json", "p.npy", "p.ply", "p.obj"});
  // A size beyond the disk: refused before the header (npy, exact: 2^55 × 24 bytes + 128) or after the
  // first rows (text).
  const std::uint64_t huge = std::uint64_t{1} << 55;
  CHECK_THROWS_WITH(
      PointsFile(s.path() / "huge.npy", huge, 3),
      StartsWith((s.path() / "huge.npy").string() + ": the file needs 864691128 GB of disk space"));
  {
    PointsFile file(s.path() / "huge.json", huge, 3);
    file.write(P.topRows(4095));
    CHECK_THROWS_WITH(file.write(P.topRows(1)),
                      StartsWith((s.path() / "huge.json").string() + ": the file needs about ") &&
                          Contains(" GB of disk space, "));
  }
  CHECK(s.names() == std::set<std::string>{"p.json", "p.npy", "p.ply", "p.obj"});
}

TEST_CASE("io::write of meshes and segments: the bytes of encode, written a chunk at a time",
          "[io][points]") {
  cifs_test::ScratchDir s("points");
  Segments segs;
  segs.vertices = some_points(200000, 3);  // several chunks of text
  for (int i = 0; i + 1 < 200000; ++i) segs.segments.push_back({i, i + 1});
  for (const char* format : {"obj", "ply", "svg"}) {
    const auto path = s.path() / (std::string("s.") + format);
    write(path, segs);
    StringSink sink;
    encode(segs, format, sink);
    CHECK(read_file(path) == encode(segs, format));
    CHECK(sink.bytes == encode(segs, format));
  }
}
