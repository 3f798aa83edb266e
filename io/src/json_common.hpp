// SPDX-License-Identifier: MIT
// cifs — private helpers of the io module's JSON formats: values read with their JSON path at
// hand for error messages, compact pretty-printing.
#pragma once

#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/types.hpp"

namespace cifs::io::detail {

using nlohmann::json;

Points to_points(const std::vector<std::vector<double>>& rows);

/// Reads JSON values with the path of each value at hand for error messages.
struct Reader {
  std::string where;

  /// "where: path: what" (no path for the document itself).
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw InvalidInput(where + ": " + (path.empty() ? "" : path + ": ") + what);
  }

  const json& member(const json& obj, const std::string& path, const char* key) const {
    const auto it = obj.find(key);
    if (it == obj.end()) fail(path, std::string("missing \"") + key + "\"");
    return *it;
  }

  double number(const json& v, const std::string& path) const {
    if (!v.is_number()) fail(path, "expected a number, got " + std::string(v.type_name()));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(path, "number is not finite");
    return x;
  }

  int integer(const json& v, const std::string& path) const {
    if (!v.is_number_integer()) fail(path, "expected an integer, got " + v.dump());
    const auto x = v.get<long long>();
    if (x < -1000000 || x > 1000000) fail(path, "integer " + v.dump() + " is out of range");
    return static_cast<int>(x);
  }

  const json& array(const json& v, const std::string& path) const {
    if (!v.is_array()) fail(path, "expected an array, got " + std::string(v.type_name()));
    return v;
  }

  std::vector<double> numbers(const json& v, const std::string& path) const {
    array(v, path);
    std::vector<double> out;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i)
      out.push_back(number(v[i], path + "[" + std::to_string(i) + "]"));
    return out;
  }

  /// Rows of equal length ≥ 1 appended to `rows` (dimension fixed by the first row seen).
  void points(const json& v, const std::string& path, std::vector<std::vector<double>>& rows) const {
    array(v, path);
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string p = path + "[" + std::to_string(i) + "]";
      rows.push_back(numbers(v[i], p));
      if (rows.back().empty()) fail(p, "a point needs at least one coordinate");
      if (rows.back().size() != rows.front().size())
        fail(p, std::to_string(rows.back().size()) + " coordinates, the first point has " +
                    std::to_string(rows.front().size()));
    }
  }

  const json& object(const json& v, const std::string& path) const {
    if (!v.is_object()) fail(path, "expected an object, got " + std::string(v.type_name()));
    return v;
  }

  std::string string(const json& v, const std::string& path) const {
    if (!v.is_string()) fail(path, "expected a string, got " + std::string(v.type_name()));
    return v.get<std::string>();
  }

  bool boolean(const json& v, const std::string& path) const {
    if (!v.is_boolean()) fail(path, "expected true or false");
    return v.get<bool>();
  }

  /// Refuses members other than `known` (typos must not be ignored silently).
  void only(const json& obj, const std::string& path, std::initializer_list<std::string_view> known) const {
    for (const auto& item : obj.items()) {
      bool ok = false;
      for (const auto k : known) ok = ok || item.key() == k;
      if (!ok) fail(path.empty() ? item.key() : path + "." + item.key(), "unknown member");
    }
  }

  /// The top level of a document made of one of `known` (`{"bcifs": …}`): a member beside it is
  /// refused by name, as `only` does; a document without any of them is left to the format's message.
  void only_beside(const json& doc, std::initializer_list<std::string_view> known) const {
    if (!doc.is_object()) return;
    for (const auto k : known)
      if (doc.contains(k)) return only(doc, "", known);
  }

  /// `rows` rows of `cols` numbers each (cols −1: as many as the first row, at least 1); the
  /// reasons name where the expected counts come from.
  Eigen::MatrixXd matrix(const json& v, const std::string& path, Eigen::Index rows, Eigen::Index cols,
                         const std::string& rows_why, const std::string& cols_why) const {
    array(v, path);
    if (rows >= 0 && static_cast<Eigen::Index>(v.size()) != rows)
      fail(path,
           std::to_string(v.size()) + " rows, expected " + std::to_string(rows) + " (" + rows_why + ")");
    std::vector<std::vector<double>> all;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string p = path + "[" + std::to_string(i) + "]";
      all.push_back(numbers(v[i], p));
      const auto want = cols >= 0 ? cols : static_cast<Eigen::Index>(all.front().size());
      if (static_cast<Eigen::Index>(all.back().size()) != want || want == 0)
        fail(p, std::to_string(all.back().size()) + " entries, expected " +
                    (want == 0 ? std::string("at least 1") : std::to_string(want)) +
                    (cols >= 0 ? " (" + cols_why + ")" : " (as the first row)"));
    }
    return to_points(all);
  }

  /// Runs a nurbs constructor, prefixing its validation messages with the file and the object.
  template <class Make>
  auto build(const std::string& object, Make&& make) const {
    try {
      return make();
    } catch (const InvalidInput& e) {
      throw InvalidInput(where + ": " + object + "." + e.what());
    }
  }
};

/// Parses `text`; IoError naming `where` and the byte for malformed JSON.
json parse_document(std::string_view text, const std::string& where);

json rows_json(const Points& P);

/// append_number for JSON: −0 written "-0.0", since a JSON reader takes "-0" for the integer 0 and
/// the round trip lost the sign (found by tests/fuzz/fuzz_polygon).
inline void append_json_number(std::string& out, double x) {
  if (x == 0 && std::signbit(x))
    out += "-0.0";
  else
    append_number(out, x);
}

/// Objects one member per line; arrays of numbers, and of arrays of numbers, on one line.
void write_pretty(const json& v, int indent, std::string& out);

}  // namespace cifs::io::detail
