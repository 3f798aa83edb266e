// SPDX-License-Identifier: MIT
// Fuzzing: the writers of computed results on fuzzed numbers — point sets (io::encode: json, obj,
// npy, ply), SVG polylines (io::polyline_svg), SVG figures (io::strokes_svg) and Graphviz DOT
// (io::to_dot of a knot automaton). An input is
//
//   byte 0       the writer (below)
//   byte 1       the dimension, 1 + byte % 4
//   byte 2       flags: polyline, closed, a seed (point sets); the number of states (DOT)
//   bytes 3–10   the transition labels (DOT): any bytes, quotes and newlines included
//   then         doubles, 8 bytes each taken bit for bit (NaN, ±inf, subnormals, −0), ≤ 256 of them
//
// Properties: non-finite numbers are refused (InvalidInput) — no writer emits `nan` or `inf`
// unasked, and none writes a non-number for finite input (an overflow in the drawing's scale);
// a point set written as json, obj or npy reads back (io::read_points) to the same doubles, bit for
// bit; every DOT label is one quoted string on its line.
#include <unistd.h>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cifs/io/dot.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/points.hpp"
#include "cifs/io/svg.hpp"
#include "fuzz.hpp"

// Named, not anonymous: the harnesses compile as unity batches (CIFS_UNITY), each in its own namespace.
namespace fuzz_writers {

using namespace cifs;

constexpr std::size_t kHeader = 11;
constexpr std::size_t kMaxNumbers = 256;
const char* const kPointFormats[] = {"json", "obj", "npy", "ply"};

const std::filesystem::path& scratch() {
  return fuzz::scratch("writers");
}

/// Whether the text holds a non-number as the writers would print it.
bool has_non_number(const std::string& text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower.find("nan") != std::string::npos || lower.find("inf") != std::string::npos;
}

/// `f` must refuse non-finite `numbers` with InvalidInput and write finite ones without a non-number.
template <class F>
void check_numbers_written(const Points& numbers, F&& write) {
  if (!numbers.allFinite()) {
    try {
      (void)write();
    } catch (const InvalidInput&) {
      return;
    }
    fuzz::require(false, "a non-finite number was written");
  }
  std::string text;
  try {
    text = write();
  } catch (const InvalidInput&) {
    return;  // a refusal for another reason (too few points, the format's dimensions)
  }
  fuzz::require(!has_non_number(text), "finite numbers written as nan or inf");
}

void points(const Points& P, int format, int flags) {
  io::PointSet set{P, {.polyline = (flags & 1) != 0, .closed = (flags & 2) != 0, .seed = std::nullopt}};
  if ((flags & 4) != 0) set.style.seed = 12345;
  const std::string name = kPointFormats[format];
  if (!P.allFinite()) {
    try {
      (void)io::encode(set, name);
    } catch (const InvalidInput&) {
      return;
    }
    fuzz::require(false, "a non-finite point was written");
  }
  std::string bytes;
  try {
    bytes = io::encode(set, name);
  } catch (const InvalidInput&) {
    fuzz::require(format == 1 || format == 3, "finite points refused");  // obj, ply: 1 to 3 coordinates
    return;
  }
  if (name == "ply") return;  // read_points does not read PLY point sets (io::parse_mesh_ply does)
  if (name != "npy") fuzz::require(!has_non_number(bytes), "finite points written as nan or inf");
  const std::filesystem::path file = scratch() / ("points." + name);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  if (P.rows() == 0) return;  // an empty point set reads back as a refusal ("no points")
  const Points back = fuzz::no_refusal([&] { return io::read_points(file); }, "point set read back");
  // OBJ `v` lines hold 3 coordinates: fewer are written padded with 0.
  fuzz::require(back.rows() == P.rows() && back.cols() >= P.cols(), "point set read back: its size");
  fuzz::require(std::memcmp(back.leftCols(P.cols()).eval().data(), P.data(), sizeof(double) * P.size()) == 0,
                "point set read back: the same doubles");
  if (back.cols() > P.cols())
    fuzz::require((back.rightCols(back.cols() - P.cols()).array() == 0).all(), "padding");
}

void dot(const Points& numbers, int states, std::string_view labels) {
  nurbs::KnotAutomaton k;
  for (int s = 0; s < states; ++s) add_vertex(k.automaton.graph);
  k.automaton.initial.push_back({0, 0});
  for (std::size_t i = 0; i < labels.size(); ++i)
    add_edge(i % static_cast<std::size_t>(states), (i * 7 + 1) % static_cast<std::size_t>(states),
             {std::string(labels.substr(i, labels.size() - i > 2 ? 2 : 1)), Eigen::MatrixXd()},
             k.automaton.graph);
  k.windows.resize(static_cast<std::size_t>(states));
  for (Eigen::Index i = 0; i < numbers.size(); ++i)
    k.windows[static_cast<std::size_t>(i) % k.windows.size()].push_back(numbers.data()[i]);
  check_numbers_written(numbers, [&] { return io::to_dot(k); });
  std::string text;
  try {
    text = io::to_dot(k);
  } catch (const InvalidInput&) {
    return;
  }
  // Each line a statement; its quotes (\" escaped) pair up.
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    int quotes = 0;
    for (std::size_t i = start; i < end; ++i) {
      if (text[i] == '\\')
        ++i;
      else if (text[i] == '"')
        ++quotes;
    }
    fuzz::require(quotes % 2 == 0, "DOT: a label's quotes do not pair up on its line");
    start = end + 1;
  }
}

CIFS_FUZZ_HARNESS(writers) {
  if (size < kHeader) return 0;
  const int writer = data[0] % 8;
  const Eigen::Index dim = 1 + data[1] % 4;
  const int flags = data[2];
  const std::string_view labels = fuzz::text(data + 3, 8);
  const std::size_t count = std::min((size - kHeader) / sizeof(double), kMaxNumbers);
  const Eigen::Index rows = static_cast<Eigen::Index>(count) / dim;
  Points P(rows, dim);
  if (P.size() > 0)  // memcpy from or to null is undefined even for 0 bytes (UBSan)
    std::memcpy(P.data(), data + kHeader, static_cast<std::size_t>(P.size()) * sizeof(double));
  fuzz::refusals_allowed([&] {
    if (writer < 4) return points(P, writer, flags);
    if (writer == 7) return dot(P, 1 + flags % 4, labels);
    if (dim < 2) return;
    // SVG draws x and y (a top view): the other coordinates are not written.
    const Points xy = P.leftCols(2);
    if (writer == 4 || writer == 5)
      return check_numbers_written(xy, [&] { return io::polyline_svg(P, writer == 5, 16 + flags * 4); });
    // Two strokes of the figure, the second dashed and labelled.
    std::vector<io::Stroke> strokes(2);
    strokes[0].points = P.topRows(rows / 2);
    strokes[1].points = P.bottomRows(rows - rows / 2);
    strokes[1].dash = "4 2";
    strokes[1].label = "second";
    check_numbers_written(xy, [&] { return io::strokes_svg(strokes, "fuzz", 16 + flags * 4); });
  });
  return 0;
}

}  // namespace fuzz_writers
