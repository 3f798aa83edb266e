// SPDX-License-Identifier: MIT
// cifs — shape files as JSON (docs/formats.md): curves, surfaces and volumes, read and written; geomdl
// (NURBS-Python) exports, read.
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/json.hpp"
#include "json_common.hpp"

namespace cifs::io {
namespace {

using detail::parse_document;
using detail::Reader;
using detail::to_points;
using nlohmann::json;

Eigen::VectorXd to_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

/// How a file counts its knots: n + d + 1 (standard), n + d − 1 (Rhino, openNURBS: without the first
/// and the last knot), or either, told apart by the count (detect).
enum class Convention { detect, standard, rhino };

Convention read_convention(const Reader& r, const json& o, const std::string& object) {
  if (!o.contains("knot_convention")) return Convention::detect;
  const std::string path = object + ".knot_convention";
  const std::string name = r.string(o["knot_convention"], path);
  if (name == "standard") return Convention::standard;
  if (name == "rhino") return Convention::rhino;
  r.fail(path, "'" + name + "': expected \"standard\" (n + d + 1 knots) or \"rhino\" (n + d - 1 knots)");
}

/// The n + d + 1 knots of a knot vector given in `convention` for n control points of degree d. The
/// Rhino convention leaves out the first and the last knot, which do not act on the domain
/// [t_d, t_n]; they come back equal to their neighbours (openNURBS's ON_SuperfluousKnot gives these
/// values at clamped ends, and any value gives the same curve).
nurbs::Knots full_knots(const Reader& r, const std::string& path, nurbs::Knots knots, std::size_t n,
                        int degree, Convention convention) {
  // The constructor names a bad degree, or too few points.
  if (degree < 1 || degree > nurbs::kMaxDegree || n < static_cast<std::size_t>(degree) + 1) return knots;
  const std::size_t standard = n + static_cast<std::size_t>(degree) + 1, rhino = standard - 2;
  const std::string given = std::to_string(knots.size()) + " knots given, " + std::to_string(n) +
                            " control points of degree " + std::to_string(degree) + " need ";
  if (convention == Convention::rhino && knots.size() != rhino)
    r.fail(path, given + std::to_string(rhino) + " in the rhino convention (n + d - 1)");
  if (convention == Convention::detect && knots.size() != standard && knots.size() != rhino)
    r.fail(path, given + std::to_string(standard) + " (or " + std::to_string(rhino) +
                     " without the first and the last knot, as Rhino and openNURBS store them)");
  if (convention == Convention::rhino || (convention == Convention::detect && knots.size() == rhino)) {
    const double first = knots.front(), last = knots.back();
    knots.insert(knots.begin(), first);
    knots.push_back(last);
  }
  return knots;
}

nurbs::Curve read_curve(const Reader& r, const json& c) {
  r.object(c, "curve");
  r.only(c, "curve", {"degree", "knots", "points", "weights", "closed", "knot_convention"});
  const int degree = r.integer(r.member(c, "curve", "degree"), "curve.degree");
  std::vector<double> knots = r.numbers(r.member(c, "curve", "knots"), "curve.knots");
  std::vector<std::vector<double>> rows;
  r.points(r.member(c, "curve", "points"), "curve.points", rows);
  if (rows.empty()) r.fail("curve.points", "no control points");
  std::vector<double> w;
  if (c.contains("weights") && !c["weights"].is_null()) w = r.numbers(c["weights"], "curve.weights");
  const bool closed = c.contains("closed") && r.boolean(c["closed"], "curve.closed");
  const Convention convention = read_convention(r, c, "curve");
  if (closed && convention != Convention::detect)
    r.fail("curve.knot_convention", "a closed curve's knots are the m + 1 breakpoints of its period");
  if (!closed) knots = full_knots(r, "curve.knots", std::move(knots), rows.size(), degree, convention);
  return r.build("curve", [&] {
    return closed ? nurbs::make_closed_curve(degree, std::move(knots), to_points(rows), to_vector(w))
                  : nurbs::make_curve(degree, std::move(knots), to_points(rows), to_vector(w));
  });
}

nurbs::Surface read_surface(const Reader& r, const json& s) {
  r.object(s, "surface");
  r.only(s, "surface", {"degree", "knots", "points", "weights", "knot_convention"});
  const json& deg = r.array(r.member(s, "surface", "degree"), "surface.degree");
  if (deg.size() != 2) r.fail("surface.degree", "expected [du, dv]");
  const std::array<int, 2> degree{r.integer(deg[0], "surface.degree[0]"),
                                  r.integer(deg[1], "surface.degree[1]")};
  const json& kn = r.array(r.member(s, "surface", "knots"), "surface.knots");
  if (kn.size() != 2) r.fail("surface.knots", "expected [[u knots], [v knots]]");
  std::array<nurbs::Knots, 2> knots{r.numbers(kn[0], "surface.knots[0]"),
                                    r.numbers(kn[1], "surface.knots[1]")};
  const Convention convention = read_convention(r, s, "surface");
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
  knots[0] = full_knots(r, "surface.knots[0]", std::move(knots[0]), net.size(), degree[0], convention);
  knots[1] = full_knots(r, "surface.knots[1]", std::move(knots[1]), nv, degree[1], convention);
  const std::array<Eigen::Index, 2> count{static_cast<Eigen::Index>(net.size()),
                                          static_cast<Eigen::Index>(nv)};
  return r.build("surface", [&] {
    return nurbs::make_surface(degree, std::move(knots), count, to_points(rows), to_vector(w));
  });
}

/// A volume's knot vectors and net, in the surface's layout with a third direction: "degree": [p, q, r],
/// "knots": [[u], [v], [w]], "points": [[[point (i, j, k) for k] for j] for i], "weights" nested alike.
nurbs::Volume read_volume(const Reader& r, const json& s) {
  r.object(s, "volume");
  r.only(s, "volume", {"degree", "knots", "points", "weights", "knot_convention"});
  const json& deg = r.array(r.member(s, "volume", "degree"), "volume.degree");
  if (deg.size() != 3) r.fail("volume.degree", "expected [du, dv, dw]");
  const json& kn = r.array(r.member(s, "volume", "knots"), "volume.knots");
  if (kn.size() != 3) r.fail("volume.knots", "expected [[u knots], [v knots], [w knots]]");
  std::array<int, 3> degree{};
  std::array<nurbs::Knots, 3> knots;
  for (std::size_t d = 0; d < 3; ++d) {
    degree[d] = r.integer(deg[d], "volume.degree[" + std::to_string(d) + "]");
    knots[d] = r.numbers(kn[d], "volume.knots[" + std::to_string(d) + "]");
  }
  const Convention convention = read_convention(r, s, "volume");
  // The net's shape: every slab i a nv by nw array, the first one's sizes the rule.
  const json& net = r.array(r.member(s, "volume", "points"), "volume.points");
  if (net.empty()) r.fail("volume.points", "no control points");
  std::array<std::size_t, 3> n{net.size(), 0, 0};
  const auto check_size = [&](const json& v, const std::string& path, std::size_t& size, const char* what) {
    r.array(v, path);
    if (size == 0) size = v.size();
    if (v.size() != size || size == 0)
      r.fail(path, std::to_string(v.size()) + " " + what + ", the first has " + std::to_string(size));
  };
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < net.size(); ++i) {
    const std::string slab = "volume.points[" + std::to_string(i) + "]";
    check_size(net[i], slab, n[1], "rows");
    for (std::size_t j = 0; j < n[1]; ++j) {
      const std::string row = slab + "[" + std::to_string(j) + "]";
      check_size(net[i][j], row, n[2], "points");
      r.points(net[i][j], row, rows);
    }
  }
  std::vector<double> w;
  if (s.contains("weights") && !s["weights"].is_null()) {
    const json& wn = r.array(s["weights"], "volume.weights");
    if (wn.size() != n[0])
      r.fail("volume.weights", std::to_string(wn.size()) + " slabs, the net has " + std::to_string(n[0]));
    for (std::size_t i = 0; i < n[0]; ++i) {
      const std::string slab = "volume.weights[" + std::to_string(i) + "]";
      if (r.array(wn[i], slab).size() != n[1])
        r.fail(slab, std::to_string(wn[i].size()) + " rows, the net has " + std::to_string(n[1]));
      for (std::size_t j = 0; j < n[1]; ++j) {
        const std::string path = slab + "[" + std::to_string(j) + "]";
        const std::vector<double> row = r.numbers(wn[i][j], path);
        if (row.size() != n[2])
          r.fail(path, std::to_string(row.size()) + " weights, the net has " + std::to_string(n[2]));
        w.insert(w.end(), row.begin(), row.end());
      }
    }
  }
  for (std::size_t d = 0; d < 3; ++d)
    knots[d] = full_knots(r, "volume.knots[" + std::to_string(d) + "]", std::move(knots[d]), n[d], degree[d],
                          convention);
  const std::array<Eigen::Index, 3> count{static_cast<Eigen::Index>(n[0]), static_cast<Eigen::Index>(n[1]),
                                          static_cast<Eigen::Index>(n[2])};
  return r.build("volume", [&] {
    return nurbs::make_volume(degree, std::move(knots), count, to_points(rows), to_vector(w));
  });
}

// geomdl (NURBS-Python) exports, exchange.export_json: {"shape": {"type": "curve" | "surface",
// "count": N, "data": [entry, ...]}}; every entry has Cartesian "control_points": {"points",
// "weights"} and the standard knot vector(s); surfaces list their points with v varying fastest
// (point (i, j) at i·size_v + j, as cifs stores them).

/// Runs a nurbs constructor for a geomdl entry at `path`, naming the entry's own members.
template <class Make>
auto build_geomdl(const Reader& r, const std::string& path, bool surface, bool v6, Make&& make) {
  try {
    return make();
  } catch (const InvalidInput& e) {
    std::string msg = e.what();
    const auto rename = [&](std::string_view from, std::string_view to) {
      if (!msg.starts_with(from)) return false;
      msg = std::string(to) + msg.substr(from.size());
      return true;
    };
    const bool named =
        surface && (v6 ? rename("knots[0]", "knotvector[0]") || rename("knots[1]", "knotvector[1]")
                       : rename("knots[0]", "knotvector_u") || rename("knots[1]", "knotvector_v"));
    if (!named)
      rename("knots", v6 ? "knotvector[0]" : "knotvector") || rename("weights", "control_points.weights") ||
          rename("points", "control_points.points");
    throw InvalidInput(r.where + ": " + path + "." + msg);
  }
}

/// A geomdl entry (an object of type "spline") with only the members `known`.
void geomdl_entry(const Reader& r, const json& e, const std::string& path,
                  std::initializer_list<std::string_view> known) {
  r.object(e, path);
  if (e.contains("type")) {  // "freeform" and "container" entries are point lists (trim curves)
    const std::string type = r.string(e["type"], path + ".type");
    if (type != "spline") r.fail(path + ".type", "'" + type + "': only \"spline\" entries are read");
  }
  r.only(e, path, known);
}

/// The control points and weights of a geomdl entry, and the members cifs does not need, checked.
void geomdl_net(const Reader& r, const json& e, const std::string& path,
                std::vector<std::vector<double>>& rows, std::vector<double>& weights) {
  const std::string cp = path + ".control_points";
  const json& c = r.object(r.member(e, path, "control_points"), cp);
  r.only(c, cp, {"points", "weights"});
  r.points(r.member(c, cp, "points"), cp + ".points", rows);
  if (rows.empty()) r.fail(cp + ".points", "no control points");
  if (c.contains("weights")) weights = r.numbers(c["weights"], cp + ".weights");
  if (e.contains("rational")) r.boolean(e["rational"], path + ".rational");  // the weights decide
  if (e.contains("dimension")) {
    const int dim = r.integer(e["dimension"], path + ".dimension");
    if (dim != static_cast<int>(rows.front().size()))
      r.fail(path + ".dimension", std::to_string(dim) + ", but the control points have " +
                                      std::to_string(rows.front().size()) + " coordinates");
  }
  // "delta" (evaluation step), "name", "id" and "reversed" (orientation of trim curves) do not
  // change the shape.
}

// geomdl 6.x writes one list per parametric direction: "degree": [p] or [p_u, p_v], "knotvector": [[…]]
// or [[…], […]], "size": [n] or [n_u, n_v], "delta" a list too; its surfaces list their points with u
// varying fastest (point (i, j) at i + size_u·j, its ptmanager's default_find_index).

/// A 6.x entry's per-direction list `key` of `directions` entries: the array at path.key.
const json& geomdl6_list(const Reader& r, const json& e, const std::string& path, const char* key,
                         std::size_t directions) {
  const json& v = r.array(r.member(e, path, key), path + "." + key);
  if (v.size() != directions)
    r.fail(path + "." + key, std::to_string(v.size()) + " entries, expected " + std::to_string(directions) +
                                 " (one per parametric direction)");
  return v;
}

/// Whether a geomdl entry is in 6.x's layout (its degree a list).
bool geomdl6(const json& e) {
  return e.is_object() && e.contains("degree") && e["degree"].is_array();
}

nurbs::Curve geomdl_curve(const Reader& r, const json& e, const std::string& path) {
  const bool v6 = geomdl6(e);
  if (v6)
    geomdl_entry(r, e, path,
                 {"type", "rational", "dimension", "degree", "knotvector", "size", "control_points", "delta",
                  "name", "id", "reversed"});
  else
    geomdl_entry(r, e, path,
                 {"type", "rational", "dimension", "degree", "knotvector", "control_points", "delta", "name",
                  "id", "reversed"});
  std::vector<std::vector<double>> rows;
  std::vector<double> w;
  geomdl_net(r, e, path, rows, w);
  int degree = 0;
  nurbs::Knots knots;
  if (v6) {
    degree = r.integer(geomdl6_list(r, e, path, "degree", 1)[0], path + ".degree[0]");
    knots = r.numbers(geomdl6_list(r, e, path, "knotvector", 1)[0], path + ".knotvector[0]");
    const int size = r.integer(geomdl6_list(r, e, path, "size", 1)[0], path + ".size[0]");
    if (size != static_cast<int>(rows.size()))
      r.fail(path + ".size[0]", std::to_string(size) + ", but control_points.points holds " +
                                    std::to_string(rows.size()) + " points");
  } else {
    degree = r.integer(r.member(e, path, "degree"), path + ".degree");
    knots = r.numbers(r.member(e, path, "knotvector"), path + ".knotvector");
  }
  return build_geomdl(r, path, false, v6, [&] {
    return nurbs::make_curve(degree, std::move(knots), to_points(rows), to_vector(w));
  });
}

nurbs::Surface geomdl_surface(const Reader& r, const json& e, std::size_t index, const std::string& path,
                              const ShapeReadOptions& options) {
  const bool v6 = geomdl6(e);
  if (v6)
    geomdl_entry(r, e, path,
                 {"type", "rational", "dimension", "degree", "knotvector", "size", "control_points", "delta",
                  "name", "id", "reversed", "trims"});
  else
    geomdl_entry(r, e, path,
                 {"type", "rational", "dimension", "degree_u", "degree_v", "knotvector_u", "knotvector_v",
                  "size_u", "size_v", "control_points", "delta", "name", "id", "reversed", "trims"});
  std::vector<std::vector<double>> rows;
  std::vector<double> w;
  geomdl_net(r, e, path, rows, w);
  std::array<int, 2> degree{}, size{};
  std::array<nurbs::Knots, 2> knots;
  for (std::size_t d = 0; d < 2; ++d) {
    // 5.x: degree_u, knotvector_u, size_u and their _v; 6.x: degree[d], knotvector[d], size[d].
    static constexpr std::array<std::array<const char*, 2>, 3> kMembers{
        {{"degree_u", "degree_v"}, {"knotvector_u", "knotvector_v"}, {"size_u", "size_v"}}};
    static constexpr std::array<const char*, 3> kLists{"degree", "knotvector", "size"};
    std::array<const json*, 3> value{};
    std::array<std::string, 3> where;
    for (std::size_t m = 0; m < 3; ++m) {
      where[m] = path;
      where[m] += '.';
      if (v6) {
        value[m] = &geomdl6_list(r, e, path, kLists[m], 2)[d];
        where[m] += kLists[m];
        where[m] += d == 0 ? "[0]" : "[1]";
      } else {
        value[m] = &r.member(e, path, kMembers[m][d]);
        where[m] += kMembers[m][d];
      }
    }
    degree[d] = r.integer(*value[0], where[0]);
    knots[d] = r.numbers(*value[1], where[1]);
    size[d] = r.integer(*value[2], where[2]);
  }
  if (size[0] < 1 || size[1] < 1 ||
      static_cast<long long>(size[0]) * size[1] != static_cast<long long>(rows.size()))
    r.fail(path + ".control_points.points", std::to_string(rows.size()) + " points, " +
                                                (v6 ? "size[0] × size[1] = " : "size_u × size_v = ") +
                                                std::to_string(size[0]) + " × " + std::to_string(size[1]));
  if (v6) {  // u varying fastest there; v fastest in cifs
    std::vector<std::vector<double>> by_u(rows.size());
    std::vector<double> w_by_u(w.size());
    for (std::size_t i = 0; i < static_cast<std::size_t>(size[0]); ++i)
      for (std::size_t j = 0; j < static_cast<std::size_t>(size[1]); ++j) {
        const std::size_t from = i + static_cast<std::size_t>(size[0]) * j,
                          to = i * static_cast<std::size_t>(size[1]) + j;
        by_u[to] = std::move(rows[from]);
        if (w.size() == rows.size()) w_by_u[to] = w[from];  // else refused below, by count
      }
    rows = std::move(by_u);
    if (w.size() == rows.size()) w = std::move(w_by_u);
  }
  if (e.contains("trims")) {
    if (!options.ignore_trim)
      r.fail(path + ".trims",
             "trimmed surfaces are not supported; --ignore-trim (ignore_trim) reads the whole untrimmed "
             "surface");
    warn(options, index,
         r.where + ": " + path + ".trims: the trim curves are ignored: the whole untrimmed surface is read");
  }
  return build_geomdl(r, path, true, v6, [&] {
    return nurbs::make_surface(degree, std::move(knots), {size[0], size[1]}, to_points(rows), to_vector(w));
  });
}

/// A geomdl volume entry: 5.x's degree_u … size_w (points with v varying fastest, then u, then w: point
/// (i, j, k) at j + size_v·(i + size_u·k), its VolumeEvaluator's flattening) or 6.x's lists of three (u
/// fastest: i + size_u·(j + size_v·k), its default_find_index); stored (i·nv + j)·nw + k as cifs does.
nurbs::Volume geomdl_volume(const Reader& r, const json& e, const std::string& path) {
  const bool v6 = geomdl6(e);
  if (v6)
    geomdl_entry(r, e, path,
                 {"type", "rational", "dimension", "degree", "knotvector", "size", "control_points", "delta",
                  "name", "id", "reversed"});
  else
    geomdl_entry(
        r, e, path,
        {"type", "rational", "dimension", "degree_u", "degree_v", "degree_w", "knotvector_u", "knotvector_v",
         "knotvector_w", "size_u", "size_v", "size_w", "control_points", "delta", "name", "id", "reversed"});
  std::vector<std::vector<double>> rows;
  std::vector<double> w;
  geomdl_net(r, e, path, rows, w);
  std::array<int, 3> degree{}, size{};
  std::array<nurbs::Knots, 3> knots;
  static constexpr std::array<const char*, 3> kLists{"degree", "knotvector", "size"};
  for (std::size_t d = 0; d < 3; ++d)
    for (std::size_t m = 0; m < 3; ++m) {
      const std::string suffix = v6 ? "[" + std::to_string(d) + "]" : std::string("_") + "uvw"[d];
      std::string member = kLists[m];
      if (!v6) member += suffix;  // 5.x: degree_u …; 6.x: degree[0] …, an entry of the list "degree"
      std::string where = path;
      where += '.';
      where += kLists[m];
      where += suffix;
      const json& value = v6 ? geomdl6_list(r, e, path, kLists[m], 3)[d] : r.member(e, path, member.c_str());
      if (m == 0) degree[d] = r.integer(value, where);
      if (m == 1) knots[d] = r.numbers(value, where);
      if (m == 2) size[d] = r.integer(value, where);
    }
  if (size[0] < 1 || size[1] < 1 || size[2] < 1 ||
      static_cast<long long>(size[0]) * size[1] * size[2] != static_cast<long long>(rows.size()))
    r.fail(path + ".control_points.points",
           std::to_string(rows.size()) + " points, " +
               (v6 ? "size[0] × size[1] × size[2] = " : "size_u × size_v × size_w = ") +
               std::to_string(size[0]) + " × " + std::to_string(size[1]) + " × " + std::to_string(size[2]));
  const auto nu = static_cast<std::size_t>(size[0]), nv = static_cast<std::size_t>(size[1]),
             nw = static_cast<std::size_t>(size[2]);
  std::vector<std::vector<double>> ordered(rows.size());
  std::vector<double> w_ordered(w.size());
  for (std::size_t i = 0; i < nu; ++i)
    for (std::size_t j = 0; j < nv; ++j)
      for (std::size_t k = 0; k < nw; ++k) {
        const std::size_t from = v6 ? i + nu * (j + nv * k) : j + nv * (i + nu * k),
                          to = (i * nv + j) * nw + k;
        ordered[to] = std::move(rows[from]);
        if (w.size() == rows.size()) w_ordered[to] = w[from];  // else refused by count
      }
  if (w.size() == rows.size()) w = std::move(w_ordered);
  try {
    return nurbs::make_volume(degree, std::move(knots), {size[0], size[1], size[2]}, to_points(ordered),
                              to_vector(w));
  } catch (const InvalidInput& error) {
    std::string msg = error.what();
    for (std::size_t d = 0; d < 3; ++d) {
      const std::string from = "knots[" + std::to_string(d) + "]";
      if (msg.starts_with(from))
        msg = (v6 ? "knotvector[" + std::to_string(d) + "]" : std::string("knotvector_") + "uvw"[d]) +
              msg.substr(from.size());
    }
    if (msg.starts_with("weights")) msg = "control_points." + msg;
    if (msg.starts_with("points")) msg = "control_points." + msg;
    throw InvalidInput(r.where + ": " + path + "." + msg);
  }
}

std::vector<Shape> read_geomdl(const Reader& r, const json& doc, const ShapeReadOptions& options) {
  const json& shape = r.object(doc["shape"], "shape");
  r.only(shape, "shape", {"type", "count", "data"});
  const std::string type = r.string(r.member(shape, "shape", "type"), "shape.type");
  if (type == "volume")
    r.fail("shape.type",
           "a volume: read it as one (io::parse_volume_json, cifs.io.parse_volume_json; "
           "cifs info and cifs eval take volume files)");
  if (type != "curve" && type != "surface")
    r.fail("shape.type", "'" + type + "': expected \"curve\" or \"surface\"");
  const json& data = r.array(r.member(shape, "shape", "data"), "shape.data");
  if (data.empty()) r.fail("shape.data", "no curve or surface");
  if (shape.contains("count") && r.integer(shape["count"], "shape.count") != static_cast<int>(data.size()))
    r.fail("shape.count", shape["count"].dump() + ", but shape.data holds " + std::to_string(data.size()));
  std::vector<Shape> out;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const std::string path = "shape.data[" + std::to_string(i) + "]";
    if (type == "curve") {
      out.emplace_back(geomdl_curve(r, data[i], path));
    } else {
      out.emplace_back(geomdl_surface(r, data[i], i, path, options));
    }
  }
  return out;
}

}  // namespace

std::vector<Shape> parse_shapes_json(std::string_view text, std::string_view where,
                                     const ShapeReadOptions& options) {
  const Reader r{std::string(where)};
  const json doc = parse_document(text, r.where);
  if (doc.is_object() && doc.size() == 1 && doc.contains("shape")) return read_geomdl(r, doc, options);
  if (doc.is_object() && doc.size() == 1 && doc.contains("volume"))
    throw InvalidInput(r.where +
                       ": a volume: read it as one (io::parse_volume_json, cifs.io.parse_volume_json; "
                       "cifs info and cifs eval take volume files)");
  r.only_beside(doc, {"curve", "surface"});
  if (!doc.is_object() || doc.size() != 1 || !(doc.contains("curve") || doc.contains("surface")))
    throw InvalidInput(
        r.where +
        ": expected an object with one member, \"curve\" or \"surface\" (or \"shape\", a geomdl "
        "export)");
  if (doc.contains("curve")) return {read_curve(r, doc["curve"])};
  return {read_surface(r, doc["surface"])};
}

Shape parse_shape_json(std::string_view text, std::string_view where, const ShapeReadOptions& options) {
  return select_shape(parse_shapes_json(text, where, options), options, where);
}

bool is_volume_json(std::string_view text) {
  const json doc = json::parse(text, nullptr, false);
  if (!doc.is_object() || doc.size() != 1) return false;
  if (doc.contains("volume")) return true;
  const auto shape = doc.find("shape");
  return shape != doc.end() && shape->is_object() && shape->contains("type") && (*shape)["type"] == "volume";
}

nurbs::Volume parse_volume_json(std::string_view text, std::string_view where,
                                const ShapeReadOptions& options) {
  const Reader r{std::string(where)};
  const json doc = parse_document(text, r.where);
  if (doc.is_object() && doc.size() == 1 && doc.contains("shape")) {
    const json& shape = r.object(doc["shape"], "shape");
    r.only(shape, "shape", {"type", "count", "data"});
    const std::string type = r.string(r.member(shape, "shape", "type"), "shape.type");
    if (type != "volume") r.fail("shape.type", "'" + type + "': expected \"volume\"");
    const json& data = r.array(r.member(shape, "shape", "data"), "shape.data");
    if (data.empty()) r.fail("shape.data", "no volume");
    if (shape.contains("count") && r.integer(shape["count"], "shape.count") != static_cast<int>(data.size()))
      r.fail("shape.count", shape["count"].dump() + ", but shape.data holds " + std::to_string(data.size()));
    std::size_t index = options.index.value_or(0);
    if (!options.index && data.size() > 1)
      throw InvalidInput(r.where + ": holds " + std::to_string(data.size()) +
                         " volumes: choose one with --index N, N from 0 to " +
                         std::to_string(data.size() - 1));
    if (index >= data.size())
      throw InvalidInput(r.where + ": --index " + std::to_string(index) +
                         " is out of range: the file holds " + std::to_string(data.size()) + " volumes");
    return geomdl_volume(r, data[index], "shape.data[" + std::to_string(index) + "]");
  }
  r.only_beside(doc, {"volume"});
  if (!doc.is_object() || doc.size() != 1 || !doc.contains("volume"))
    throw InvalidInput(r.where +
                       R"(: expected an object with one member, "volume" (or "shape", a geomdl export))");
  if (options.index && *options.index != 0)
    throw InvalidInput(r.where + ": --index " + std::to_string(*options.index) +
                       " is out of range: the file holds 1 volume");
  return read_volume(r, doc["volume"]);
}

namespace {

/// A number as nlohmann::json writes it (shortest round trip, "1.0" for integers, "-0.0"): the
/// bytes the shape files have always had.
void append_shape_number(ChunkBuffer& out, double x) {
  out.text += json(x).dump();
}

/// `[a,b,…]` on one line, as the pretty writer puts an array of numbers (detail::write_pretty).
void append_numbers(ChunkBuffer& out, const double* x, std::size_t n) {
  out.text += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out.text += ',';
    append_shape_number(out, x[i]);
    out.spill();
  }
  out.text += ']';
}

/// `[[x,y,…],…]` on one line: rows `first` … `first + n − 1` of P.
void append_rows(ChunkBuffer& out, const Points& P, Eigen::Index first, Eigen::Index n) {
  out.text += '[';
  for (Eigen::Index i = first; i < first + n; ++i) {
    out.text += i > first ? ",[" : "[";
    for (Eigen::Index k = 0; k < P.cols(); ++k) {
      if (k) out.text += ',';
      append_shape_number(out, P(i, k));
    }
    out.text += ']';
    out.spill();
  }
  out.text += ']';
}

/// The shape object's members in key order, each `"key": value` on its own line (write_pretty's layout).
void append_member(ChunkBuffer& out, bool& first, std::string_view key) {
  out.text += first ? "\n    \"" : ",\n    \"";
  out.text += key;
  out.text += "\": ";
  first = false;
}

}  // namespace

void write_json(const Shape& shape, ByteSink& sink) {
  // Written a row at a time (a revolved profile of 200,000 points: 90 MB of text, which a document
  // tree held as 700 MB before its first byte).
  ChunkBuffer out(sink);
  bool first = true;
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    out.text += "{\n  \"curve\": {";
    if (c->closed) append_member(out, first, "closed"), out.text += "true";
    append_member(out, first, "degree");
    out.text += std::to_string(c->degree);
    append_member(out, first, "knots");
    const std::vector<double> knots = nurbs::defining_knots(*c);
    append_numbers(out, knots.data(), knots.size());
    append_member(out, first, "points");
    const Points P = nurbs::cartesian_points(*c);
    append_rows(out, P, 0, P.rows());
    if (c->rational) {
      append_member(out, first, "weights");
      const Eigen::VectorXd w = nurbs::weights(*c);
      append_numbers(out, w.data(), static_cast<std::size_t>(w.size()));
    }
  } else {
    const auto& s = std::get<nurbs::Surface>(shape);
    out.text += "{\n  \"surface\": {";
    append_member(out, first, "degree");
    out.text += "[" + std::to_string(s.degree[0]) + "," + std::to_string(s.degree[1]) + "]";
    append_member(out, first, "knots");
    out.text += '[';
    append_numbers(out, s.knots[0].data(), s.knots[0].size());
    out.text += ',';
    append_numbers(out, s.knots[1].data(), s.knots[1].size());
    out.text += ']';
    // One line per u row of the net (an array of arrays of rows is not one line for write_pretty).
    append_member(out, first, "points");
    const Points P = nurbs::cartesian_points(s);
    out.text += '[';
    for (Eigen::Index i = 0; i < s.count[0]; ++i) {
      out.text += i ? ",\n      " : "\n      ";
      append_rows(out, P, i * s.count[1], s.count[1]);
    }
    out.text += "\n    ]";
    if (s.rational) {
      append_member(out, first, "weights");
      const Eigen::VectorXd w = nurbs::weights(s);
      out.text += '[';
      for (Eigen::Index i = 0; i < s.count[0]; ++i) {
        if (i) out.text += ',';
        append_numbers(out, w.data() + i * s.count[1], static_cast<std::size_t>(s.count[1]));
        out.spill();
      }
      out.text += ']';
    }
  }
  out.text += "\n  }\n}\n";
  out.flush();
}

void write_json(const nurbs::Volume& v, ByteSink& sink) {
  ChunkBuffer out(sink);
  bool first = true;
  out.text += "{\n  \"volume\": {";
  append_member(out, first, "degree");
  out.text += "[" + std::to_string(v.degree[0]) + "," + std::to_string(v.degree[1]) + "," +
              std::to_string(v.degree[2]) + "]";
  append_member(out, first, "knots");
  out.text += '[';
  for (std::size_t d = 0; d < 3; ++d) {
    if (d) out.text += ',';
    append_numbers(out, v.knots[d].data(), v.knots[d].size());
  }
  out.text += ']';
  // One line per (i, j) line of the net along w, the slabs i bracketed on their own lines.
  const Eigen::Index nv = v.count[1], nw = v.count[2];
  const int dim = nurbs::dimension(v);
  Points P(v.P.rows(), dim);
  for (Eigen::Index r = 0; r < v.P.rows(); ++r)
    P.row(r) = v.rational ? Point(v.P.row(r).head(dim) / v.P(r, dim)) : Point(v.P.row(r));
  append_member(out, first, "points");
  out.text += '[';
  for (Eigen::Index i = 0; i < v.count[0]; ++i) {
    out.text += i ? ",\n      [" : "\n      [";
    for (Eigen::Index j = 0; j < nv; ++j) {
      out.text += j ? ",\n        " : "\n        ";
      append_rows(out, P, (i * nv + j) * nw, nw);
    }
    out.text += "\n      ]";
  }
  out.text += "\n    ]";
  if (v.rational) {
    append_member(out, first, "weights");
    out.text += '[';
    for (Eigen::Index i = 0; i < v.count[0]; ++i) {
      out.text += i ? ",[" : "[";
      for (Eigen::Index j = 0; j < nv; ++j) {
        if (j) out.text += ',';
        const Eigen::VectorXd w = v.P.col(dim).segment((i * nv + j) * nw, nw);
        append_numbers(out, w.data(), static_cast<std::size_t>(nw));
      }
      out.text += ']';
      out.spill();
    }
    out.text += ']';
  }
  out.text += "\n  }\n}\n";
  out.flush();
}

std::string to_json(const nurbs::Volume& volume) {
  StringSink out;
  write_json(volume, out);
  return std::move(out.bytes);
}

std::string to_json(const Shape& shape) {
  StringSink out;
  write_json(shape, out);
  return std::move(out.bytes);
}

}  // namespace cifs::io
