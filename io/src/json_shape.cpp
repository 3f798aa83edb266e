// SPDX-License-Identifier: MIT
// cifs — shape files as JSON (docs/formats.md): curves and surfaces, read and written.
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cifs/errors.hpp"
#include "cifs/io/json.hpp"
#include "json_common.hpp"

namespace cifs::io {
namespace {

using detail::parse_document;
using detail::Reader;
using detail::rows_json;
using detail::to_points;
using detail::write_pretty;
using nlohmann::json;

Eigen::VectorXd to_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

nurbs::Curve read_curve(const Reader& r, const json& c) {
  r.object(c, "curve");
  r.only(c, "curve", {"degree", "knots", "points", "weights", "closed"});
  const int degree = r.integer(r.member(c, "curve", "degree"), "curve.degree");
  std::vector<double> knots = r.numbers(r.member(c, "curve", "knots"), "curve.knots");
  std::vector<std::vector<double>> rows;
  r.points(r.member(c, "curve", "points"), "curve.points", rows);
  if (rows.empty()) r.fail("curve.points", "no control points");
  std::vector<double> w;
  if (c.contains("weights") && !c["weights"].is_null()) w = r.numbers(c["weights"], "curve.weights");
  const bool closed = c.contains("closed") && r.boolean(c["closed"], "curve.closed");
  return r.build("curve", [&] {
    return closed ? nurbs::make_closed_curve(degree, std::move(knots), to_points(rows), to_vector(w))
                  : nurbs::make_curve(degree, std::move(knots), to_points(rows), to_vector(w));
  });
}

nurbs::Surface read_surface(const Reader& r, const json& s) {
  r.object(s, "surface");
  r.only(s, "surface", {"degree", "knots", "points", "weights"});
  const json& deg = r.array(r.member(s, "surface", "degree"), "surface.degree");
  if (deg.size() != 2) r.fail("surface.degree", "expected [du, dv]");
  const std::array<int, 2> degree{r.integer(deg[0], "surface.degree[0]"),
                                  r.integer(deg[1], "surface.degree[1]")};
  const json& kn = r.array(r.member(s, "surface", "knots"), "surface.knots");
  if (kn.size() != 2) r.fail("surface.knots", "expected [[u knots], [v knots]]");
  std::array<nurbs::Knots, 2> knots{r.numbers(kn[0], "surface.knots[0]"),
                                    r.numbers(kn[1], "surface.knots[1]")};
  const json& net = r.array(r.member(s, "surface", "points"), "surface.points");
  if (net.empty()) r.fail("surface.points", "no control points");
  std::vector<std::vector<double>> rows;
  std::size_t nv = 0;
  for (std::size_t i = 0; i < net.size(); ++i) {
    const std::string path = "surface.points[" + std::to_string(i) + "]";
    r.array(net[i], path);
    if (i == 0) nv = net[i].size();
    if (net[i].size() != nv || nv == 0)
      r.fail(path, std::to_string(net[i].size()) + " points, the first row has " + std::to_string(nv));
    r.points(net[i], path, rows);
  }
  std::vector<double> w;
  if (s.contains("weights") && !s["weights"].is_null()) {
    const json& wn = r.array(s["weights"], "surface.weights");
    if (wn.size() != net.size())
      r.fail("surface.weights",
             std::to_string(wn.size()) + " rows, the net has " + std::to_string(net.size()));
    for (std::size_t i = 0; i < wn.size(); ++i) {
      const std::string path = "surface.weights[" + std::to_string(i) + "]";
      const std::vector<double> row = r.numbers(wn[i], path);
      if (row.size() != nv)
        r.fail(path, std::to_string(row.size()) + " weights, the net has " + std::to_string(nv));
      w.insert(w.end(), row.begin(), row.end());
    }
  }
  const std::array<Eigen::Index, 2> count{static_cast<Eigen::Index>(net.size()),
                                          static_cast<Eigen::Index>(nv)};
  return r.build("surface", [&] {
    return nurbs::make_surface(degree, std::move(knots), count, to_points(rows), to_vector(w));
  });
}

}  // namespace

std::vector<Shape> parse_shapes_json(std::string_view text, std::string_view where,
                                     const ShapeReadOptions& /*options*/) {
  const Reader r{std::string(where)};
  const json doc = parse_document(text, r.where);
  if (!doc.is_object() || doc.size() != 1 || !(doc.contains("curve") || doc.contains("surface")))
    throw InvalidInput(r.where + ": expected an object with one member, \"curve\" or \"surface\"");
  if (doc.contains("curve")) return {read_curve(r, doc["curve"])};
  return {read_surface(r, doc["surface"])};
}

Shape parse_shape_json(std::string_view text, std::string_view where, const ShapeReadOptions& options) {
  return select_shape(parse_shapes_json(text, where, options), options, where);
}

std::string to_json(const Shape& shape) {
  json doc;
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    json& o = doc["curve"];
    o["degree"] = c->degree;
    o["knots"] = nurbs::defining_knots(*c);
    o["points"] = rows_json(nurbs::cartesian_points(*c));
    if (c->rational) {
      const Eigen::VectorXd w = nurbs::weights(*c);
      o["weights"] = std::vector<double>(w.data(), w.data() + w.size());
    }
    if (c->closed) o["closed"] = true;
  } else {
    const auto& s = std::get<nurbs::Surface>(shape);
    json& o = doc["surface"];
    o["degree"] = s.degree;
    o["knots"] = s.knots;
    const Points P = nurbs::cartesian_points(s);
    const Eigen::VectorXd w = nurbs::weights(s);
    json net = json::array(), wnet = json::array();
    for (Eigen::Index i = 0; i < s.count[0]; ++i) {
      net.push_back(rows_json(P.middleRows(i * s.count[1], s.count[1])));
      wnet.push_back(std::vector<double>(w.data() + i * s.count[1], w.data() + (i + 1) * s.count[1]));
    }
    o["points"] = std::move(net);
    if (s.rational) o["weights"] = std::move(wnet);
  }
  std::string out;
  write_pretty(doc, 0, out);
  return out + "\n";
}

}  // namespace cifs::io
