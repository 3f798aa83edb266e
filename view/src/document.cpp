// SPDX-License-Identifier: MIT
#include "cifs/view/document.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/ifs/shape_attractor.hpp"
#include "cifs/io/io.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/rules.hpp"

namespace cifs::view {

namespace {

std::string where(const Document& d) {
  return d.path.filename().string();
}

/// The Cartesian rows of a shape's stored points (homogeneous rows divided by their weight).
Point cartesian_row(const Points& P, Eigen::Index row, bool rational) {
  const Eigen::Index dim = P.cols() - (rational ? 1 : 0);
  Point p = P.row(row).head(dim).transpose();
  if (rational) p /= P(row, dim);
  return p;
}

void append_xyz(std::vector<float>& out, const Eigen::Ref<const Eigen::RowVectorXd>& row) {
  for (Eigen::Index k = 0; k < 3; ++k) out.push_back(k < row.size() ? static_cast<float>(row(k)) : 0.0F);
}

/// The rows of `points` as float x, y, z (z = 0 for 2-D points), in one pass.
std::vector<float> xyz(const Points& points) {
  std::vector<float> out(3 * static_cast<std::size_t>(points.rows()), 0.0F);
  const Eigen::Index dim = std::min<Eigen::Index>(points.cols(), 3);
  float* o = out.data();
  for (Eigen::Index i = 0; i < points.rows(); ++i, o += 3)
    for (Eigen::Index k = 0; k < dim; ++k) o[k] = static_cast<float>(points(i, k));
  return out;
}

/// Moves stored row `row` to the Cartesian `position`, keeping its weight.
void move_row(Points& P, Eigen::Index row, bool rational, const std::vector<double>& position,
              const std::string& who) {
  const Eigen::Index dim = P.cols() - (rational ? 1 : 0);
  if (static_cast<Eigen::Index>(position.size()) != dim)
    throw InvalidInput(who + ": " + std::to_string(position.size()) + " coordinates for a " +
                       std::to_string(dim) + "-D point");
  const double w = rational ? P(row, dim) : 1.0;
  for (Eigen::Index k = 0; k < dim; ++k) {
    if (!std::isfinite(position[k])) throw InvalidInput(who + ": a coordinate is not a finite number");
    P(row, k) = w * position[k];
  }
}

std::string point_who(const Document& d, std::size_t index) {
  return where(d) + ": point " + std::to_string(index);
}

}  // namespace

std::string_view kind_name(Kind kind) noexcept {
  switch (kind) {
    case Kind::curve:
      return "curve";
    case Kind::surface:
      return "surface";
    case Kind::mesh:
      return "mesh";
  }
  return "?";
}

Document open_document(const std::filesystem::path& path) {
  Document d;
  d.path = path;
  switch (io::detect(path)) {
    case io::Content::mesh:
      d.kind = Kind::mesh;
      d.mesh = io::read_mesh(path);
      return d;
    case io::Content::shape:
      d.shape = io::read_shape(path);
      d.kind = std::holds_alternative<nurbs::Curve>(*d.shape) ? Kind::curve : Kind::surface;
      return d;
    case io::Content::bcifs:
      throw InvalidInput(path.string() +
                         ": a BC-IFS file; cifs view shows shapes (curves, surfaces) and polygon meshes "
                         "(cifs render draws a BC-IFS file)");
    default:
      throw InvalidInput(path.string() +
                         ": cifs view shows shapes (curves, surfaces) and polygon meshes; open the shape "
                         "this file names");
  }
}

Params default_params(const Document& document) {
  Params p;
  if (document.kind == Kind::curve) {
    const int segments = std::max(1, nurbs::segment_count(std::get<nurbs::Curve>(*document.shape)));
    p.depth = std::clamp(static_cast<int>(std::lround(std::log2(1e4 / segments))), 0, 16);
  } else if (document.kind == Kind::surface) {
    const auto& s = std::get<nurbs::Surface>(*document.shape);
    const double patches =
        static_cast<double>(s.count[0] - s.degree[0]) * static_cast<double>(s.count[1] - s.degree[1]);
    p.depth = std::clamp(static_cast<int>(std::lround(0.5 * std::log2(1e4 / std::max(1.0, patches)))), 0, 7);
  } else {
    const auto& o = document.mesh.face_offsets;
    bool triangles = true;
    for (std::size_t f = 0; f + 1 < o.size(); ++f) triangles = triangles && o[f + 1] - o[f] == 3;
    p.scheme = triangles ? "loop" : "catmull-clark";
    p.levels = 1;
  }
  return p;
}

io::Shape edited_shape(const Document& document, const Params& params) {
  if (!document.shape) throw InvalidInput(where(document) + ": not a shape");
  io::Shape shape = *document.shape;
  if (auto* c = std::get_if<nurbs::Curve>(&shape)) {
    const auto m = static_cast<std::size_t>(nurbs::distinct_count(*c));
    for (const PointEdit& e : params.points) {
      if (e.index >= m)
        throw InvalidInput(point_who(document, e.index) + ": the curve has " + std::to_string(m) +
                           " control points");
      for (Eigen::Index r = static_cast<Eigen::Index>(e.index); r < c->P.rows();
           r += static_cast<Eigen::Index>(m))
        move_row(c->P, r, c->rational, e.position, point_who(document, e.index));
    }
    nurbs::validate(*c);
  } else {
    auto& s = std::get<nurbs::Surface>(shape);
    const auto n = static_cast<std::size_t>(s.P.rows());
    for (const PointEdit& e : params.points) {
      if (e.index >= n)
        throw InvalidInput(point_who(document, e.index) + ": the surface has " + std::to_string(n) +
                           " control points");
      move_row(s.P, static_cast<Eigen::Index>(e.index), s.rational, e.position, point_who(document, e.index));
    }
    nurbs::validate(s);
  }
  return shape;
}

Mesh edited_mesh(const Document& document, const Params& params) {
  Mesh mesh = document.mesh;
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  for (const PointEdit& e : params.points) {
    if (e.index >= n)
      throw InvalidInput(point_who(document, e.index) + ": the mesh has " + std::to_string(n) + " vertices");
    move_row(mesh.vertices, static_cast<Eigen::Index>(e.index), false, e.position,
             point_who(document, e.index));
  }
  return mesh;
}

namespace {

void check_range(const std::string& who, int value, int high) {
  if (value < 0 || value > high)
    throw InvalidInput(who + " " + std::to_string(value) + " is outside 0.." + std::to_string(high) +
                       " (the view's limit)");
}

void curve_geometry(const nurbs::Curve& c, const Params& params, const Limits& limits, Geometry& g) {
  const nurbs::KnotAutomaton a = nurbs::knot_automaton(c);
  const std::vector<Points> nets = nurbs::initial_nets(a, c);
  // ifs::attractor's call, with the states of the pieces.
  const ifs::Sample sample = ifs::sample_attractor(a.automaton, nets,
                                                   {.depth = params.depth,
                                                    .homogeneous = c.rational,
                                                    .closed = c.closed,
                                                    .states = true,
                                                    .max_points = limits.max_points,
                                                    .limit_hint = "; lower the depth"});
  const auto n = static_cast<std::uint32_t>(sample.points.rows());
  g.positions = xyz(sample.points);
  g.states = sample.states;
  if (!g.states.empty()) g.states.resize(n, g.states.back());  // the end point: its piece's
  g.closed = c.closed;
}

void surface_geometry(const nurbs::Surface& s, const Params& params, const Limits& limits, Geometry& g) {
  const Mesh mesh = ifs::attractor(s, params.depth, ifs::mesh_bytes(limits.max_points, 3, limits.max_points));
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  g.positions = xyz(mesh.vertices);
  const std::size_t faces = mesh.face_offsets.size() - 1;
  constexpr std::uint32_t kUnset = 0xffffffffU;
  g.states.assign(n, kUnset);
  // Node (I, J) is computed by the leaf of cell (I, J), corner 0 of its quad; the last row and column
  // take a neighbouring leaf's state.
  for (std::size_t f = 0; f < faces; ++f) g.states[mesh.face_vertices[4 * f]] = mesh.states[f];
  for (std::size_t f = 0; f < faces; ++f)
    for (int k = 1; k < 4; ++k)
      if (g.states[mesh.face_vertices[4 * f + k]] == kUnset)
        g.states[mesh.face_vertices[4 * f + k]] = mesh.states[f];
  // The faces are the grid's cells (ifs::surface_mesh's layout: node (I, J) is vertex I·cols + J, face 0
  // has the corners 0, cols, cols + 1, 1): the page makes the triangles from the grid's size once per
  // depth, and the 6 indices per cell are not sent with every edit.
  const auto cols = static_cast<std::uint32_t>(mesh.face_vertices[1]);
  const auto rows = static_cast<std::uint32_t>(n / cols);
  if (std::size_t{rows} * cols != n || std::size_t{rows - 1} * (cols - 1) != faces)
    throw std::logic_error("view: the surface mesh is not ifs::surface_mesh's grid");
  g.grid = {rows, cols};
}

/// The control polygon (the distinct points of a closed curve) or the control grid, Cartesian.
void append_net(const io::Shape& shape, Geometry& g) {
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    const Eigen::Index m = nurbs::distinct_count(*c);
    for (Eigen::Index i = 0; i < m; ++i) append_xyz(g.net, cartesian_row(c->P, i, c->rational).transpose());
    for (std::uint32_t i = 0; i + 1 < static_cast<std::uint32_t>(m); ++i)
      g.net_lines.insert(g.net_lines.end(), {i, i + 1});
    if (c->closed && m > 1) g.net_lines.insert(g.net_lines.end(), {static_cast<std::uint32_t>(m - 1), 0});
    return;
  }
  const auto& s = std::get<nurbs::Surface>(shape);
  const Eigen::Index nu = s.count[0], nv = s.count[1];
  for (Eigen::Index i = 0; i < s.P.rows(); ++i)
    append_xyz(g.net, cartesian_row(s.P, i, s.rational).transpose());
  for (Eigen::Index i = 0; i < nu; ++i)
    for (Eigen::Index j = 0; j < nv; ++j) {
      const auto here = static_cast<std::uint32_t>(i * nv + j);
      if (j + 1 < nv) g.net_lines.insert(g.net_lines.end(), {here, here + 1});
      if (i + 1 < nu) g.net_lines.insert(g.net_lines.end(), {here, here + static_cast<std::uint32_t>(nv)});
    }
}

/// Faces as triangle fans, holes left out.
void append_faces(const Mesh& mesh, std::vector<std::uint32_t>& triangles) {
  const std::vector<char> hole = hole_flags(mesh);
  for (std::size_t f = 0; f + 1 < mesh.face_offsets.size(); ++f) {
    if (!hole.empty() && hole[f] != 0) continue;
    const int begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (int k = begin + 1; k + 1 < end; ++k)
      triangles.insert(triangles.end(), {static_cast<std::uint32_t>(mesh.face_vertices[begin]),
                                         static_cast<std::uint32_t>(mesh.face_vertices[k]),
                                         static_cast<std::uint32_t>(mesh.face_vertices[k + 1])});
  }
}

void mesh_geometry(const Document& document, const Params& params, const Limits& limits, Geometry& g) {
  const Mesh control = edited_mesh(document, params);
  subdivision::MeshOptions options;
  options.max_bytes = 64 * limits.max_points;  // about 64 bytes per vertex
  const Mesh refined =
      subdivision::subdivide(control, subdivision::named_mesh_scheme(params.scheme), params.levels, options);
  g.positions = xyz(refined.vertices);
  append_faces(refined, g.triangles);
  for (Eigen::Index i = 0; i < control.vertices.rows(); ++i) append_xyz(g.net, control.vertices.row(i));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // each edge once
  for (std::size_t f = 0; f + 1 < control.face_offsets.size(); ++f) {
    const int begin = control.face_offsets[f], end = control.face_offsets[f + 1];
    for (int k = begin; k < end; ++k) {
      const auto a = static_cast<std::uint32_t>(control.face_vertices[k]);
      const auto b = static_cast<std::uint32_t>(control.face_vertices[k + 1 < end ? k + 1 : begin]);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) g.net_lines.insert(g.net_lines.end(), {a, b});
}

/// Non-empty knot intervals of one direction's domain: the patches along it.
std::uint32_t spans(const nurbs::Knots& knots, int degree, Eigen::Index count) {
  std::uint32_t n = 0;
  for (auto i = static_cast<std::size_t>(degree); i < static_cast<std::size_t>(count); ++i)
    n += knots[i + 1] > knots[i] ? 1U : 0U;
  return n;
}

/// The perturbed shape, as an experiment with a "perturbation" evaluates it (experiment::evaluate).
void perturbed_geometry(const io::Shape& shape, const Params& params, const Limits& limits, Geometry& g) {
  if (!std::isfinite(params.amplitude) || params.amplitude < 0 || params.amplitude > 1)
    throw InvalidInput("amplitude " + std::to_string(params.amplitude) + " is outside 0..1");
  io::Experiment e;
  e.shape = shape;
  e.evaluation.depth = params.depth;
  e.perturbation = io::PerturbationSpec{.amplitude = params.amplitude,
                                        .seed = params.seed,
                                        .values = {},
                                        .keep_vertices = true,
                                        .fractal_curves = std::nullopt};
  experiment::RunOptions options;
  options.max_bytes = ifs::mesh_bytes(limits.max_points, 3, limits.max_points);
  const experiment::Evaluation ev = experiment::evaluate(e, params.depth, options);
  if (static_cast<std::size_t>(ev.points.rows()) > limits.max_points)
    throw InvalidInput(std::to_string(ev.points.rows()) + " points, above the view's limit of " +
                       std::to_string(limits.max_points) + "; lower the depth");
  g.positions = xyz(ev.points);
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    g.closed = c->closed;
  } else {  // quad_mesh's grid: the surface's patches, 2^depth cells each way
    const auto& s = std::get<nurbs::Surface>(shape);
    const std::uint32_t cells = 1U << params.depth;
    g.grid = {spans(s.knots[0], s.degree[0], s.count[0]) * cells + 1,
              spans(s.knots[1], s.degree[1], s.count[1]) * cells + 1};
    if (std::size_t{g.grid[0]} * g.grid[1] != static_cast<std::size_t>(ev.points.rows()))
      throw std::logic_error("view: the perturbed surface is not its patches' grid");
  }
}

}  // namespace

Geometry geometry(const Document& document, const Params& params, const Limits& limits) {
  Geometry g;
  g.kind = document.kind;
  if (document.kind == Kind::mesh) {
    check_range("levels", params.levels, limits.max_levels);
    mesh_geometry(document, params, limits, g);
  } else {
    const io::Shape shape = edited_shape(document, params);
    const auto* c = std::get_if<nurbs::Curve>(&shape);
    check_range("depth", params.depth, c != nullptr ? limits.max_depth_curve : limits.max_depth_surface);
    if (params.amplitude != 0)
      perturbed_geometry(shape, params, limits, g);
    else if (c != nullptr)
      curve_geometry(*c, params, limits, g);
    else
      surface_geometry(std::get<nurbs::Surface>(shape), params, limits, g);
    append_net(shape, g);
  }
  g.checksum = geometry_checksum(g.positions);
  return g;
}

std::uint32_t geometry_checksum(const std::vector<float>& positions) noexcept {
  std::uint32_t h = 2166136261U;
  for (const float x : positions) h = (h ^ std::bit_cast<std::uint32_t>(x)) * 16777619U;
  return h;
}

namespace {
template <class T>
void append_bytes(std::string& out, const std::vector<T>& values) {
  static_assert(std::endian::native == std::endian::little, "the wire format is little-endian");
  const std::size_t at = out.size();
  out.resize(at + values.size() * sizeof(T));
  if (!values.empty()) std::memcpy(out.data() + at, values.data(), values.size() * sizeof(T));
}
}  // namespace

std::string encode_geometry(const Geometry& g) {
  const nlohmann::json header = {{"kind", kind_name(g.kind)},
                                 {"positions", g.positions.size()},
                                 {"closed", g.closed},
                                 {"triangles", g.triangles.size()},
                                 {"grid", g.grid},
                                 {"states", g.states.size()},
                                 {"net", g.net.size()},
                                 {"net_lines", g.net_lines.size()},
                                 {"checksum", g.checksum}};
  std::string text = header.dump();
  text.resize((text.size() + 12 + 3) / 4 * 4 - 12, ' ');  // the arrays start on a 4-byte boundary
  std::string out = "CIFSVIEW";
  const auto length = static_cast<std::uint32_t>(text.size());
  out.append(reinterpret_cast<const char*>(&length), 4);
  out += text;
  append_bytes(out, g.positions);
  append_bytes(out, g.triangles);
  append_bytes(out, g.states);
  append_bytes(out, g.net);
  append_bytes(out, g.net_lines);
  return out;
}

}  // namespace cifs::view
