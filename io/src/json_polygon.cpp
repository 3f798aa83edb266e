// SPDX-License-Identifier: MIT
// cifs — control polygon files as JSON (docs/formats.md), read and written.

#include "cifs/format.hpp"
#include "cifs/io/json.hpp"
#include "json_common.hpp"

namespace cifs::io {

using detail::json;
using detail::Reader;

Polygon parse_polygon_json(std::string_view text, std::string_view where) {
  const Reader r{std::string(where)};
  const json doc = detail::parse_document(text, r.where);
  r.only_beside(doc, {"polygon"});
  if (!doc.is_object() || doc.size() != 1 || !doc.contains("polygon") || !doc["polygon"].is_object())
    throw InvalidInput(r.where + ": expected {\"polygon\": {\"points\": [[x, y], ...], \"closed\": true}}");
  const json& p = doc["polygon"];
  r.only(p, "polygon", {"points", "closed"});
  std::vector<std::vector<double>> rows;
  r.points(r.member(p, "polygon", "points"), "polygon.points", rows);
  if (rows.empty()) r.fail("polygon.points", "no points");
  if (rows.front().size() > 16) r.fail("polygon.points[0]", "more than 16 coordinates");
  Polygon out;
  if (p.contains("closed")) out.closed = r.boolean(p["closed"], "polygon.closed");
  out.points.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(rows.front().size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t k = 0; k < rows[i].size(); ++k)
      out.points(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i][k];
  return out;
}

std::string to_json(const Polygon& polygon) {
  const Points& P = polygon.points;
  std::string out = "{\"polygon\": {\"closed\": ";
  out += polygon.closed ? "true" : "false";
  out += ", \"points\": [";
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    out += i ? ",\n  [" : "\n  [";
    for (Eigen::Index k = 0; k < P.cols(); ++k) {
      if (k) out += ", ";
      detail::append_json_number(out, P(i, k));
    }
    out += "]";
  }
  out += "]}}\n";
  return out;
}

}  // namespace cifs::io
