// SPDX-License-Identifier: MIT
// Point files read back (cifs fit): CSV, NumPy .npy, JSON and OBJ vertices.
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/points.hpp"
#include "json_common.hpp"

namespace cifs::io {
namespace {

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InvalidInput(where + ": " + what);
}

/// Rows of numbers of one length into Points.
Points to_points(const std::vector<std::vector<double>>& rows, const std::string& where) {
  if (rows.empty()) fail(where, "no points");
  Points P(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(rows.front().size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t k = 0; k < rows[i].size(); ++k)
      P(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i][k];
  return P;
}

/// CSV or whitespace-separated text: one point a line; '#' comments and blank lines are skipped, and a
/// first line that is not numbers (a header).
Points parse_points_text(const std::string& text, const std::string& where) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
    std::vector<double> row;
    const char* p = line.data();
    const char* end = p + line.size();
    bool header = false;
    while (p < end) {
      while (p < end && *p == ' ') ++p;
      if (p == end) break;
      double x = 0;
      const auto [next, error] = std::from_chars(p, end, x);
      const char* stop = next;
      if (error != std::errc() || (stop < end && *stop != ' ')) {
        if (rows.empty() && row.empty()) {
          header = true;
          break;
        }
        const char* word_end = p;
        while (word_end < end && *word_end != ' ') ++word_end;
        fail(where + ":" + std::to_string(number), "'" + std::string(p, word_end) + "' is not a number");
      }
      if (!std::isfinite(x)) fail(where + ":" + std::to_string(number), "a coordinate is not finite");
      row.push_back(x);
      p = stop;
    }
    if (header || row.empty()) continue;
    if (!rows.empty() && row.size() != rows.front().size())
      fail(
          where + ":" + std::to_string(number),
          std::to_string(row.size()) + " values, the first point has " + std::to_string(rows.front().size()));
    rows.push_back(std::move(row));
  }
  return to_points(rows, where);
}

/// NumPy 1.x/2.x/3.x: a 2-D little-endian array of f8, f4, i8 or i4, C or Fortran order.
Points parse_npy(const std::string& bytes, const std::string& where) {
  if (bytes.size() < 10 || bytes.compare(0, 6, "\x93NUMPY") != 0) fail(where, "not a NumPy .npy file");
  const int major = static_cast<unsigned char>(bytes[6]);
  std::size_t length = 0, start = 0;
  if (major == 1) {
    length = static_cast<unsigned char>(bytes[8]) |
             static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8;
    start = 10;
  } else {
    if (bytes.size() < 12) fail(where, "truncated .npy header");
    for (int i = 0; i < 4; ++i)
      length |= static_cast<std::size_t>(static_cast<unsigned char>(bytes[8 + i])) << (8 * i);
    start = 12;
  }
  if (bytes.size() < start + length) fail(where, "truncated .npy header");
  const std::string header = bytes.substr(start, length);
  const auto value_of = [&](const std::string& key) {
    const auto at = header.find("'" + key + "'");
    if (at == std::string::npos) fail(where, "the .npy header has no '" + key + "'");
    return header.substr(header.find(':', at) + 1);
  };
  const std::string descr = value_of("descr");
  const auto q = descr.find('\'');
  const std::string type = descr.substr(q + 1, descr.find('\'', q + 1) - q - 1);
  const bool fortran = value_of("fortran_order").find("True") < value_of("fortran_order").find(',');
  const std::string shape_text = value_of("shape");
  std::vector<long long> shape;
  for (std::size_t i = shape_text.find('(') + 1; i < shape_text.size() && shape_text[i] != ')'; ++i)
    if (std::isdigit(static_cast<unsigned char>(shape_text[i]))) {
      std::size_t used = 0;
      shape.push_back(std::stoll(shape_text.substr(i), &used));
      i += used - 1;
    }
  if (shape.size() != 2)
    fail(where, "expected a 2-D array (points, dim), got " + std::to_string(shape.size()) + "-D");
  std::size_t item = 0;
  if (type == "<f8" || type == "<i8")
    item = 8;
  else if (type == "<f4" || type == "<i4")
    item = 4;
  else
    fail(where, "dtype '" + type + "' is not read (little-endian f8, f4, i8 or i4 are)");
  const auto rows = static_cast<Eigen::Index>(shape[0]), cols = static_cast<Eigen::Index>(shape[1]);
  const std::size_t data = start + length;
  if (bytes.size() - data != static_cast<std::size_t>(rows * cols) * item)
    fail(where, "the data holds " + std::to_string(bytes.size() - data) + " bytes, the shape needs " +
                    std::to_string(static_cast<std::size_t>(rows * cols) * item));
  if (rows == 0 || cols == 0) fail(where, "no points");
  Points P(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index k = 0; k < cols; ++k) {
      const std::size_t index = static_cast<std::size_t>(fortran ? k * rows + i : i * cols + k);
      const char* at = bytes.data() + data + index * item;
      double x = 0;
      if (type == "<f8")
        std::memcpy(&x, at, 8);
      else if (type == "<f4") {
        float f;
        std::memcpy(&f, at, 4);
        x = f;
      } else if (type == "<i8") {
        std::int64_t v;
        std::memcpy(&v, at, 8);
        x = static_cast<double>(v);
      } else {
        std::int32_t v;
        std::memcpy(&v, at, 4);
        x = v;
      }
      if (!std::isfinite(x)) fail(where, "point " + std::to_string(i) + ": a coordinate is not finite");
      P(i, k) = x;
    }
  return P;
}

/// {"points": [[x, y], …]} (what cifs eval writes), a polygon file, or a bare array of points.
Points parse_points_json(const std::string& text, const std::string& where) {
  const detail::Reader r{where};
  const nlohmann::json doc = detail::parse_document(text, where);
  if (doc.is_object() && doc.contains("polygon")) return parse_polygon_json(text, where).points;
  std::vector<std::vector<double>> rows;
  if (doc.is_object()) {
    r.only(doc, "", {"points", "seed"});
    r.points(r.member(doc, "", "points"), "points", rows);
  } else {
    r.points(doc, "points", rows);
  }
  return to_points(rows, where);
}

/// The `v` lines of an OBJ file, in order (a fourth number, a weight or a colour, is ignored).
Points parse_points_obj(const std::string& text, const std::string& where) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string tag;
    if (!(words >> tag) || tag != "v") continue;
    std::vector<double> row(3);
    for (double& x : row)
      if (!(words >> x) || !std::isfinite(x)) fail(where + ":" + std::to_string(number), "expected v x y z");
    rows.push_back(std::move(row));
  }
  return to_points(rows, where);
}

}  // namespace

Points read_points(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  const std::string where = path.string();
  const std::string ext = extension_of(path);
  if (ext == ".npy") return parse_npy(text, where);
  if (ext == ".json") return parse_points_json(text, where);
  if (ext == ".obj") return parse_points_obj(text, where);
  if (ext == ".csv" || ext == ".txt" || ext == ".xyz") return parse_points_text(text, where);
  throw InvalidInput(where + ": points are read from .csv, .txt, .xyz, .npy, .json or .obj");
}

}  // namespace cifs::io
