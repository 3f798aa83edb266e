// SPDX-License-Identifier: MIT
// cifs — OBJ free-form geometry (docs/formats.md): `cstype [rat] bspline` and `cstype [rat] bezier`
// curves (`curv`) and surfaces (`surf`) with their `deg`, `parm` and `end` statements, over
// `v x y z [w]` vertices.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/io/obj.hpp"
#include "cifs/nurbs/refine.hpp"
#include "obj_lexer.hpp"

namespace cifs::io {
namespace {

using detail::num;
using detail::quote;
using detail::Tokens;

struct Vertex {
  double x = 0, y = 0, z = 0, w = 1;
  std::size_t values = 0;  // numbers on the `v` line (3 or 4 for a control point)
  std::size_t line = 0;
};

enum class Kind { curve, surface, parameter_curve };

/// The `cstype` in effect: the ones read, and the others, refused by the curv or surf that uses them.
enum class CurveType { none, bspline, bezier, other };

const char* keyword(Kind k) noexcept {
  return k == Kind::curve ? "curv" : k == Kind::surface ? "surf" : "curv2";
}

/// A `curv`, `surf` or `curv2` statement and the body statements read so far.
struct Element {
  Kind kind = Kind::curve;
  std::size_t line = 0;
  bool rational = false, bezier = false;
  std::size_t trim_line = 0;  // first trim or hole statement (read with ignore_trim)
  std::array<int, 2> degree{};
  std::vector<double> range;         // u0 u1, or s0 s1 t0 t1
  std::vector<std::size_t> control;  // 0-based vertex numbers, in file order
  std::array<std::optional<std::vector<double>>, 2> parm;
  std::array<std::size_t, 2> parm_line{};
};

/// Where a range cuts a shape's knot domain (none: the domain's own end).
struct Part {
  std::optional<double> start, end;
};

/// Knots to insert so that `x` has multiplicity ≥ d.
void fill_to_degree(std::vector<double>& add, const nurbs::Knots& t, int d, double x) {
  for (int m = nurbs::multiplicity(t, x); m < d; ++m) add.push_back(x);
}

/// The first and last control index, and the knots, of the part of a spline whose knots `t` (n
/// control points, degree d) have each cut of `part` with multiplicity ≥ d. On [a, b] the spline is
/// the one of the control points first … last over t[first … last + d + 1], whose outer knots (which
/// do not act on [a, b]) are set to a and b: the part is clamped at its cuts.
struct PartIndices {
  Eigen::Index first = 0, last = 0;
  nurbs::Knots knots;
};
PartIndices part_indices(const nurbs::Knots& t, int d, Eigen::Index n, const Part& part) {
  PartIndices out{0, n - 1, {}};
  if (part.start) out.first = (std::upper_bound(t.begin(), t.end(), *part.start) - t.begin()) - 1 - d;
  if (part.end) out.last = (std::lower_bound(t.begin(), t.end(), *part.end) - t.begin()) - 1;
  out.knots.assign(t.begin() + out.first, t.begin() + out.last + d + 2);
  if (part.start) out.knots.front() = *part.start;
  if (part.end) out.knots.back() = *part.end;
  return out;
}

/// The curve over the part of its domain (the same points there): knot insertion at the cuts.
nurbs::Curve part_of(const nurbs::Curve& c, const Part& part) {
  if (!part.start && !part.end) return c;
  std::vector<double> add;
  if (part.start) fill_to_degree(add, c.knots, c.degree, *part.start);
  if (part.end) fill_to_degree(add, c.knots, c.degree, *part.end);
  const nurbs::Curve r = add.empty() ? c : nurbs::refine(c, add);
  PartIndices p = part_indices(r.knots, r.degree, r.P.rows(), part);
  nurbs::Curve out{r.degree, std::move(p.knots), r.P.middleRows(p.first, p.last - p.first + 1), r.rational,
                   false};
  nurbs::validate(out);
  return out;
}

/// The surface over the part of its domain in one direction.
nurbs::Surface part_of(const nurbs::Surface& s, nurbs::Direction dir, const Part& part) {
  if (!part.start && !part.end) return s;
  const auto k = static_cast<std::size_t>(dir);
  std::vector<double> add;
  if (part.start) fill_to_degree(add, s.knots[k], s.degree[k], *part.start);
  if (part.end) fill_to_degree(add, s.knots[k], s.degree[k], *part.end);
  const nurbs::Surface r = add.empty() ? s : nurbs::refine(s, dir, add);
  PartIndices p = part_indices(r.knots[k], r.degree[k], r.count[k], part);
  nurbs::Surface out = r;
  out.knots[k] = std::move(p.knots);
  out.count[k] = p.last - p.first + 1;
  out.P.resize(out.count[0] * out.count[1], r.P.cols());
  for (Eigen::Index i = 0; i < out.count[0]; ++i)
    for (Eigen::Index j = 0; j < out.count[1]; ++j) {
      const Eigen::Index si = k == 0 ? i + p.first : i, sj = k == 1 ? j + p.first : j;
      out.P.row(i * out.count[1] + j) = r.P.row(si * r.count[1] + sj);
    }
  nurbs::validate(out);
  return out;
}

class ObjReader {
 public:
  ObjReader(std::string_view where, const ShapeReadOptions& options)
      : place_{std::string(where)}, options_(options) {}

  void statement(std::size_t line, const Tokens& t) {
    place_.line = line;
    const std::string_view key = t[0];
    if (key == "v") {
      vertex(t);
    } else if (key == "cstype") {
      attribute_outside_body(key);
      cstype(t);
    } else if (key == "deg") {
      attribute_outside_body(key);
      deg(t);
    } else if (key == "curv") {
      element(Kind::curve, t);
    } else if (key == "surf") {
      element(Kind::surface, t);
    } else if (key == "curv2") {
      element(Kind::parameter_curve, t);
    } else if (key == "parm") {
      parm(t);
    } else if (key == "end") {
      end(t);
    } else if (key == "trim" || key == "hole") {
      body(key);
      if (!options_.ignore_trim)
        invalid(place_.line,
                std::string(key) +
                    ": trimmed surfaces are not supported; --ignore-trim (ignore_trim) reads the "
                    "whole untrimmed surface");
      if (open_->trim_line == 0) open_->trim_line = place_.line;
    } else if (key == "scrv" || key == "sp") {
      body(key);  // special curves and points only steer tessellation: ignored
    } else if (key == "bsp" || key == "bzp" || key == "cdc" || key == "cdp") {
      invalid(place_.line, std::string(key) + ": superseded OBJ 2.11 patch statements are not supported");
    }
    // Everything else (vt, vn, vp, p, l, f, g, o, s, mg, usemtl, mtllib, bmat, step, con, ctech,
    // stech, lod, ...) carries no curve or surface geometry and is ignored.
  }

  std::vector<Shape> finish() {
    if (open_)
      syntax(open_->line,
             std::string(keyword(open_->kind)) + ": no end statement before the end of the file");
    return std::move(shapes_);
  }

 private:
  detail::ObjPlace place_;
  const ShapeReadOptions& options_;
  std::vector<Vertex> vertices_;
  CurveType type_ = CurveType::none;
  std::string type_name_;  // as written after cstype, for messages
  std::size_t cstype_line_ = 0;
  bool rational_ = false;
  std::array<int, 2> degree_{};  // 0 = not given
  std::size_t deg_line_ = 0;
  std::optional<Element> open_;
  std::vector<Shape> shapes_;

  [[noreturn]] void syntax(std::size_t line, const std::string& what) const { place_.syntax(line, what); }
  [[noreturn]] void invalid(std::size_t line, const std::string& what) const { place_.invalid(line, what); }
  double number(std::string_view tok, std::string_view what) const { return place_.number(tok, what); }
  long long integer(std::string_view tok, std::string_view what) const { return place_.integer(tok, what); }

  void attribute_outside_body(std::string_view key) const {
    if (open_)
      syntax(place_.line, std::string(key) + " inside the body of the " + keyword(open_->kind) + " at line " +
                              std::to_string(open_->line) + " (missing end?)");
  }

  void body(std::string_view key) const {
    if (!open_) syntax(place_.line, std::string(key) + " outside a curv or surf body");
  }

  void vertex(const Tokens& t) {
    if (t.size() < 4)
      syntax(place_.line, "v: expected x y z [w], got " + std::to_string(t.size() - 1) + " numbers");
    Vertex v;
    v.values = t.size() - 1;
    v.line = place_.line;
    std::array<double, 4> xyzw{0, 0, 0, 1};
    for (std::size_t k = 1; k < t.size(); ++k) {
      const double x = number(t[k], "v");
      if (k <= 4) xyzw[k - 1] = x;
    }
    v.x = xyzw[0];
    v.y = xyzw[1];
    v.z = xyzw[2];
    v.w = xyzw[3];
    vertices_.push_back(v);
  }

  void cstype(const Tokens& t) {
    std::size_t k = 1;
    const bool rat = t.size() > k && t[k] == "rat";
    if (rat) ++k;
    if (t.size() != k + 1) syntax(place_.line, "cstype: expected cstype [rat] type");
    const std::string_view type = t[k];
    if (type == "bspline") {
      type_ = CurveType::bspline;
    } else if (type == "bezier") {
      type_ = CurveType::bezier;
    } else if (type == "cardinal" || type == "taylor" || type == "bmatrix") {
      type_ = CurveType::other;  // refused by the curv or surf that uses it: curv2 trimming curves may
    } else {
      invalid(place_.line, "cstype: unknown curve and surface type " + quote(type));
    }
    type_name_ = std::string(rat ? "rat " : "") + std::string(type);
    cstype_line_ = place_.line;
    rational_ = rat;
  }

  void deg(const Tokens& t) {
    if (t.size() != 2 && t.size() != 3) syntax(place_.line, "deg: expected deg du [dv]");
    degree_ = {0, 0};
    for (std::size_t k = 1; k < t.size(); ++k) {
      const long long d = integer(t[k], "deg");
      if (d < 1 || d > nurbs::kMaxDegree)
        invalid(place_.line, "deg: degree " + std::to_string(d) + " is outside [1, " +
                                 std::to_string(nurbs::kMaxDegree) + "]");
      degree_[k - 1] = static_cast<int>(d);
    }
    deg_line_ = place_.line;
  }

  std::size_t resolve(long long index) const { return place_.resolve(index, vertices_.size(), "vertex"); }

  void element(Kind kind, const Tokens& t) {
    const char* kw = keyword(kind);
    if (open_)
      syntax(place_.line, std::string(kw) + " before the end of the " + keyword(open_->kind) + " at line " +
                              std::to_string(open_->line) + " (missing end?)");
    Element e;
    e.kind = kind;
    e.line = place_.line;
    if (kind == Kind::parameter_curve) {  // a curve in a surface's parameter space (trimming): skipped
      open_ = std::move(e);
      return;
    }
    if (type_ == CurveType::none) syntax(place_.line, std::string(kw) + " without a preceding cstype");
    if (type_ == CurveType::other)
      invalid(place_.line, std::string(kw) + ": cstype " + type_name_ + " (line " +
                               std::to_string(cstype_line_) +
                               ") is not supported: only bspline and bezier, rational or not, are read");
    if (degree_[0] == 0) syntax(place_.line, std::string(kw) + " without a preceding deg");
    if (kind == Kind::surface && degree_[1] == 0)
      syntax(place_.line,
             "surf needs deg du dv; the deg at line " + std::to_string(deg_line_) + " gives one degree");
    e.rational = rational_;
    e.bezier = type_ == CurveType::bezier;
    e.degree = degree_;
    const std::size_t nrange = kind == Kind::curve ? 2 : 4;
    if (t.size() < 2 + nrange)
      syntax(place_.line, kind == Kind::curve ? "curv: expected curv u0 u1 v1 v2 ..."
                                              : "surf: expected surf s0 s1 t0 t1 v1 v2 ...");
    for (std::size_t k = 1; k <= nrange; ++k) e.range.push_back(number(t[k], std::string(kw) + " range"));
    for (std::size_t k = 1 + nrange; k < t.size(); ++k) {
      std::string_view tok = t[k];
      if (kind == Kind::surface) {  // v/vt/vn, v//vn or v/vt: the texture and normal parts are ignored
        const std::size_t slash = tok.find('/');
        if (slash != std::string_view::npos) {
          std::string_view rest = tok.substr(slash + 1);
          for (int part = 0; part < 2 && !rest.empty(); ++part) {
            const std::size_t next = rest.find('/');
            const std::string_view field = rest.substr(0, next);
            if (!field.empty()) integer(field, "surf");
            rest = next == std::string_view::npos ? std::string_view{} : rest.substr(next + 1);
            if (next != std::string_view::npos && part == 1)
              syntax(place_.line, "surf: expected v/vt/vn, got " + quote(tok));
          }
          tok = tok.substr(0, slash);
        }
      }
      e.control.push_back(resolve(integer(tok, kw)));
    }
    open_ = std::move(e);
  }

  void parm(const Tokens& t) {
    body("parm");
    if (t.size() < 3) syntax(place_.line, "parm: expected parm u|v p1 p2 ...");
    int dir = 0;
    if (t[1] == "v") {
      dir = 1;
    } else if (t[1] != "u") {
      syntax(place_.line, "parm: the direction must be u or v, got " + quote(t[1]));
    }
    Element& e = *open_;
    if (dir == 1 && e.kind != Kind::surface)
      syntax(place_.line, std::string("parm v in the body of a ") + keyword(e.kind) +
                              " (only surfaces have a v direction)");
    auto& slot = e.parm[static_cast<std::size_t>(dir)];
    if (slot)
      syntax(place_.line, std::string("parm ") + (dir ? "v" : "u") + " given twice (first at line " +
                              std::to_string(e.parm_line[static_cast<std::size_t>(dir)]) + ")");
    std::vector<double> knots;
    knots.reserve(t.size() - 2);
    const std::string what = std::string("parm ") + (dir ? "v" : "u");
    for (std::size_t k = 2; k < t.size(); ++k) knots.push_back(number(t[k], what));
    slot = std::move(knots);
    e.parm_line[static_cast<std::size_t>(dir)] = place_.line;
  }

  void end(const Tokens& t) {
    if (!open_) syntax(place_.line, "end without a curv or surf");
    if (t.size() != 1) syntax(place_.line, "end: unexpected " + quote(t[1]));
    const Element e = std::move(*open_);
    open_.reset();
    if (e.kind == Kind::parameter_curve) return;
    const char* kw = keyword(e.kind);
    if (!e.parm[0])
      syntax(e.line, std::string(kw) + ": no parm u before the end at line " + std::to_string(place_.line));
    if (e.kind == Kind::surface && !e.parm[1])
      syntax(e.line, "surf: no parm v before the end at line " + std::to_string(place_.line));
    if (e.kind == Kind::curve) {
      shapes_.emplace_back(build_curve(e));
    } else {
      shapes_.emplace_back(build_surface(e));
    }
    if (e.trim_line != 0)
      warn(options_, shapes_.size() - 1,
           place_.at(e.trim_line) + "the trimming loops of the " + kw + " at line " + std::to_string(e.line) +
               " are ignored: the whole untrimmed surface is read");
  }

  /// Cartesian point and weight of the control vertex `k` (a 0-based vertex number).
  void control_point(const Element& e, std::size_t k, Points& P, Eigen::Index row, Eigen::VectorXd& w) const {
    const Vertex& v = vertices_[k];
    const std::string name = "vertex " + std::to_string(k + 1) + " (line " + std::to_string(v.line) + ")";
    if (v.values > 4)
      invalid(e.line, std::string(keyword(e.kind)) + ": " + name + " has " + std::to_string(v.values) +
                          " numbers; a control point takes x y z [w]");
    P.row(row) << v.x, v.y, v.z;
    if (e.rational) {
      if (!(v.w > 0))
        invalid(v.line, "weight " + num(v.w) + " of vertex " + std::to_string(k + 1) +
                            " is not positive (used by the rational " + keyword(e.kind) + " at line " +
                            std::to_string(e.line) + ")");
      w(row) = v.w;
    }
  }

  /// Runs a nurbs constructor; its messages are prefixed with the line of the statement at fault:
  /// the `parm` line for knot problems, the element line otherwise.
  template <class Make>
  auto build(const Element& e, Make&& make) const {
    try {
      return make();
    } catch (const InvalidInput& ex) {
      const std::string msg = ex.what();
      const char* kw = keyword(e.kind);
      if (e.kind == Kind::surface && (msg.starts_with("knots[0]") || msg.starts_with("knots[1]"))) {
        const std::size_t d = msg[6] == '1' ? 1 : 0;  // "knots[d]..." names the direction
        invalid(e.parm_line[d], std::string("parm ") + (d ? "v" : "u") + ": knots" + msg.substr(8));
      }
      if (msg.starts_with("knots")) invalid(e.parm_line[0], "parm u: " + msg);
      invalid(e.line, std::string(kw) + ": " + msg);
    }
  }

  /// The part of the knot domain that the range [a, b] selects (the spec's x_d ≤ t_min < t_max ≤ x_n,
  /// knots x): an end within 1e-9 of the domain's width of the domain's end is that end (decimal
  /// rounding); an end inside the domain cuts the shape there; an end outside is clamped to the
  /// domain, with a warning (Blender writes `curv 0.0 1.0` whatever the knots).
  Part range_part(const Element& e, double a, double b, nurbs::Domain dom, const char* dir) const {
    const std::string name =
        std::string(keyword(e.kind)) + ": parameter range " + dir + " [" + num(a) + ", " + num(b) + "]";
    if (!(a < b)) invalid(e.line, name + " is empty or reversed");
    const double tol = 1e-9 * (dom.end - dom.start);
    const std::string domain = "the knot domain [" + num(dom.start) + ", " + num(dom.end) + "]";
    if (b <= dom.start + tol || a >= dom.end - tol) invalid(e.line, name + " does not overlap " + domain);
    Part part;
    if (a > dom.start + tol) part.start = a;
    if (b < dom.end - tol) part.end = b;
    if (a < dom.start - tol || b > dom.end + tol)
      warn(options_, shapes_.size(),
           place_.at(e.line) + name + " reaches outside " + domain + ": read over [" +
               num(part.start.value_or(dom.start)) + ", " + num(part.end.value_or(dom.end)) + "]");
    return part;
  }

  /// The B-spline knots of a Bezier element's parameter values p_0 < … < p_s (segment i is the
  /// Bezier curve of its d + 1 control points over [p_i, p_{i+1}]): the ends d + 1 times, the
  /// others d times.
  nurbs::Knots bezier_knots(const Element& e, std::size_t dir) const {
    const std::vector<double>& p = *e.parm[dir];
    const std::string name = std::string("parm ") + (dir ? "v" : "u");
    if (p.size() < 2)
      invalid(e.parm_line[dir], name + ": a Bezier " + keyword(e.kind) + " needs at least 2 values");
    for (std::size_t i = 1; i < p.size(); ++i)
      if (!(p[i] > p[i - 1]))
        invalid(e.parm_line[dir], name + ": the parameter values of a Bezier " + keyword(e.kind) +
                                      " must increase: " + num(p[i]) + " follows " + num(p[i - 1]));
    const auto d = static_cast<std::size_t>(e.degree[dir]);
    nurbs::Knots t;
    for (std::size_t i = 0; i < p.size(); ++i)
      t.insert(t.end(), i == 0 || i + 1 == p.size() ? d + 1 : d, p[i]);
    return t;
  }

  nurbs::Curve build_curve(const Element& e) const {
    const auto n = static_cast<Eigen::Index>(e.control.size());
    if (n < e.degree[0] + 1)
      invalid(e.line, "curv: " + std::to_string(n) + " control vertices are too few for degree " +
                          std::to_string(e.degree[0]) + " (at least " + std::to_string(e.degree[0] + 1) +
                          " needed)");
    nurbs::Knots knots = *e.parm[0];
    // The JSON reader detects Rhino's count (n + d − 1: without the first and the last knot); OBJ files give
    // every knot, so that count is refused, naming the convention it comes from.
    if (const auto d = static_cast<Eigen::Index>(e.degree[0]);
        !e.bezier && static_cast<Eigen::Index>(knots.size()) == n + d - 1)
      invalid(e.parm_line[0], "parm u: " + std::to_string(knots.size()) + " knots given, " +
                                  std::to_string(n) + " control points of degree " + std::to_string(d) +
                                  " need " + std::to_string(n + d + 1) +
                                  " (the count given leaves out the first and the last knot, as Rhino and "
                                  "openNURBS store them; OBJ files give all n + d + 1)");
    if (e.bezier) {
      const int d = e.degree[0];
      if ((n - 1) % d != 0)
        invalid(e.line, "curv: " + std::to_string(n) +
                            " control vertices do not make whole Bezier segments of degree " +
                            std::to_string(d) + " (k·" + std::to_string(d) + " + 1 vertices for k segments)");
      const auto values = static_cast<Eigen::Index>(e.parm[0]->size());
      if (values != (n - 1) / d + 1)
        invalid(e.parm_line[0], "parm u: " + std::to_string(values) + " values given; a Bezier curv of " +
                                    std::to_string((n - 1) / d) + " segments needs " +
                                    std::to_string((n - 1) / d + 1));
      knots = bezier_knots(e, 0);
    }
    Points P(n, 3);
    Eigen::VectorXd w(e.rational ? n : 0);
    for (Eigen::Index i = 0; i < n; ++i) control_point(e, e.control[static_cast<std::size_t>(i)], P, i, w);
    const nurbs::Curve c = build(e, [&] { return nurbs::make_curve(e.degree[0], std::move(knots), P, w); });
    return part_of(c, range_part(e, e.range[0], e.range[1], nurbs::domain(c), "u"));
  }

  nurbs::Surface build_surface(const Element& e) const {
    std::array<Eigen::Index, 2> count{};
    std::array<nurbs::Knots, 2> knot_vectors{*e.parm[0], *e.parm[1]};
    for (std::size_t d = 0; d < 2; ++d) {
      if (e.bezier) {  // patches of degree + 1 points, sharing their edges
        knot_vectors[d] = bezier_knots(e, d);
        count[d] = static_cast<Eigen::Index>(e.parm[d]->size() - 1) * e.degree[d] + 1;
        continue;
      }
      const auto knots = static_cast<Eigen::Index>(e.parm[d]->size());
      count[d] = knots - e.degree[d] - 1;
      if (count[d] < e.degree[d] + 1)
        invalid(e.parm_line[d], std::string("parm ") + (d ? "v" : "u") + ": " + std::to_string(knots) +
                                    " knots are too few for degree " + std::to_string(e.degree[d]) +
                                    " (at least " + std::to_string(2 * e.degree[d] + 2) + " needed)");
    }
    const Eigen::Index nu = count[0], nv = count[1];
    const auto given = static_cast<Eigen::Index>(e.control.size());
    if (nu * nv != given && e.bezier)
      invalid(e.line, "surf: " + std::to_string(given) + " control vertices given; parm u (" +
                          std::to_string(e.parm[0]->size()) + " values, degree " +
                          std::to_string(e.degree[0]) + ") and parm v (" + std::to_string(e.parm[1]->size()) +
                          " values, degree " + std::to_string(e.degree[1]) + ") make a Bezier net of " +
                          std::to_string(nu) + " by " + std::to_string(nv) + " = " + std::to_string(nu * nv));
    if (nu * nv != given)
      invalid(e.line, "surf: " + std::to_string(given) + " control vertices given; parm u (" +
                          std::to_string(e.parm[0]->size()) + " knots, degree " +
                          std::to_string(e.degree[0]) + ") and parm v (" + std::to_string(e.parm[1]->size()) +
                          " knots, degree " + std::to_string(e.degree[1]) + ") make a " + std::to_string(nu) +
                          " by " + std::to_string(nv) + " net of " + std::to_string(nu * nv));
    // The file lists the net with u varying fastest: vertex j·nu + i is control point (i, j),
    // which the Surface stores at row i·nv + j.
    Points P(nu * nv, 3);
    Eigen::VectorXd w(e.rational ? nu * nv : 0);
    for (Eigen::Index j = 0; j < nv; ++j)
      for (Eigen::Index i = 0; i < nu; ++i)
        control_point(e, e.control[static_cast<std::size_t>(j * nu + i)], P, i * nv + j, w);
    const nurbs::Surface s = build(e, [&] {
      return nurbs::make_surface({e.degree[0], e.degree[1]}, std::move(knot_vectors), count, P, w);
    });
    const Part u = range_part(e, e.range[0], e.range[1], nurbs::domain(s, nurbs::Direction::u), "u");
    const Part v = range_part(e, e.range[2], e.range[3], nurbs::domain(s, nurbs::Direction::v), "v");
    return part_of(part_of(s, nurbs::Direction::u, u), nurbs::Direction::v, v);
  }
};

/// A Cartesian coordinate x with `x·w == a` in double arithmetic when one exists near a / w, so
/// that the reader's `w·x` gives back the stored homogeneous coordinate a bit for bit.
double cartesian(double a, double w) {
  const double x = a / w;
  if (x * w == a) return x;
  double lo = x, hi = x;
  for (int k = 0; k < 4; ++k) {
    lo = std::nextafter(lo, -std::numeric_limits<double>::infinity());
    if (lo * w == a) return lo;
    hi = std::nextafter(hi, std::numeric_limits<double>::infinity());
    if (hi * w == a) return hi;
  }
  return x;
}

/// `v x y z [w]` from a stored row (homogeneous when rational), padded with zeros to 3-D.
void put_vertex(std::string& out, const Points& P, Eigen::Index row, int dim, bool rational) {
  out += 'v';
  const double w = rational ? P(row, dim) : 1;
  for (int k = 0; k < 3; ++k) {
    out += ' ';
    append_number(out, k < dim ? (rational ? cartesian(P(row, k), w) : P(row, k)) : 0.0,
                  17);  // %.17g: reads back as the same double
  }
  if (rational) {
    out += ' ';
    append_number(out, w, 17);
  }
  out += '\n';
}

/// `keyword` then the values, continued with a trailing backslash every `per_line` values.
template <class Values>
void put_list(std::string& out, const std::string& keyword, const Values& values, std::size_t per_line) {
  out += keyword;
  std::size_t k = 0;
  for (const auto& x : values) {
    if (k > 0 && k % per_line == 0) out += " \\\n";
    out += ' ';
    if constexpr (std::is_floating_point_v<std::decay_t<decltype(x)>>)
      append_number(out, x, 17);
    else
      out += std::to_string(x);
    ++k;
  }
  out += '\n';
}

void check_dimension(int dim, const char* what) {
  if (dim > 3)
    throw InvalidInput("a " + std::to_string(dim) + "-D " + what +
                       " cannot be written as OBJ, which holds 3-D geometry; write it as JSON");
}

std::vector<long long> one_to(Eigen::Index n) {
  std::vector<long long> v(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<long long>(i) + 1;
  return v;
}

}  // namespace

std::vector<Shape> parse_obj(std::string_view text, std::string_view where, const ShapeReadOptions& options) {
  ObjReader reader(where, options);
  detail::for_each_statement(text, [&](std::size_t line, const Tokens& t) { reader.statement(line, t); });
  return reader.finish();
}

std::string to_obj(const Shape& shape) {
  constexpr std::size_t kIndicesPerLine = 16, kKnotsPerLine = 6;
  std::string out;
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    const int dim = nurbs::dimension(*c);
    check_dimension(dim, "curve");
    const Eigen::Index n = c->P.rows();
    out += "# cifs: ";
    out += c->rational ? "NURBS" : "B-spline";
    out += " curve of degree " + std::to_string(c->degree) + ", " + std::to_string(n) + " control points\n";
    if (c->closed)
      out += "# closed curve of " + std::to_string(nurbs::distinct_count(*c)) +
             " distinct control points, written as its expanded unclamped form\n";
    for (Eigen::Index i = 0; i < n; ++i) put_vertex(out, c->P, i, dim, c->rational);
    out += c->rational ? "cstype rat bspline\n" : "cstype bspline\n";
    out += "deg " + std::to_string(c->degree) + "\n";
    const nurbs::Domain dom = nurbs::domain(*c);
    std::string head = "curv ";
    append_number(head, dom.start, 17);
    head += ' ';
    append_number(head, dom.end, 17);
    put_list(out, head, one_to(n), kIndicesPerLine);
    put_list(out, "parm u", c->knots, kKnotsPerLine);
    out += "end\n";
    return out;
  }
  const auto& s = std::get<nurbs::Surface>(shape);
  const int dim = nurbs::dimension(s);
  check_dimension(dim, "surface");
  const Eigen::Index nu = s.count[0], nv = s.count[1];
  out += "# cifs: ";
  out += s.rational ? "NURBS" : "B-spline";
  out += " surface of degree " + std::to_string(s.degree[0]) + " by " + std::to_string(s.degree[1]) + ", " +
         std::to_string(nu) + " by " + std::to_string(nv) + " control points, u varying fastest\n";
  for (Eigen::Index j = 0; j < nv; ++j)
    for (Eigen::Index i = 0; i < nu; ++i) put_vertex(out, s.P, i * nv + j, dim, s.rational);
  out += s.rational ? "cstype rat bspline\n" : "cstype bspline\n";
  out += "deg " + std::to_string(s.degree[0]) + " " + std::to_string(s.degree[1]) + "\n";
  const nurbs::Domain du = nurbs::domain(s, nurbs::Direction::u), dv = nurbs::domain(s, nurbs::Direction::v);
  std::string head = "surf";
  for (const double x : {du.start, du.end, dv.start, dv.end}) {
    head += ' ';
    append_number(head, x, 17);
  }
  put_list(out, head, one_to(nu * nv), kIndicesPerLine);
  put_list(out, "parm u", s.knots[0], kKnotsPerLine);
  put_list(out, "parm v", s.knots[1], kKnotsPerLine);
  out += "end\n";
  return out;
}

}  // namespace cifs::io
