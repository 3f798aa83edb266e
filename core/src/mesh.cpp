// SPDX-License-Identifier: MIT
// cifs — polygon meshes and segment sets: construction, checks, vertex normals.
#include "cifs/mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs {
namespace {

std::string at(std::string_view what, std::size_t i) {
  return std::string(what) + "[" + std::to_string(i) + "]";
}

void check_rows(const Points& P, std::string_view who, std::string_view what) {
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    for (Eigen::Index k = 0; k < P.cols(); ++k)
      if (!std::isfinite(P(i, k)))
        throw InvalidInput(std::string(who) + ": " + at(what, static_cast<std::size_t>(i)) +
                           " is not finite");
}

}  // namespace

void add_face(Mesh& mesh, std::span<const int> corners) {
  if (mesh.face_offsets.empty()) mesh.face_offsets.push_back(0);
  mesh.face_vertices.insert(mesh.face_vertices.end(), corners.begin(), corners.end());
  mesh.face_offsets.push_back(static_cast<int>(mesh.face_vertices.size()));
}

Mesh uniform_mesh(Points vertices, std::vector<int> corners, int arity) {
  if (arity < 3) throw InvalidInput("a mesh face needs at least 3 corners, got " + std::to_string(arity));
  if (corners.size() % static_cast<std::size_t>(arity) != 0)
    throw InvalidInput("the mesh's " + std::to_string(corners.size()) +
                       " corner indices are not a whole number of faces of " + std::to_string(arity) +
                       " corners");
  if (corners.size() > static_cast<std::size_t>(INT_MAX))
    throw InvalidInput("the mesh has more face corners than 32-bit offsets hold; use fewer faces");
  Mesh mesh;
  mesh.vertices = std::move(vertices);
  const std::size_t faces = corners.size() / static_cast<std::size_t>(arity);
  std::vector<int> offsets(faces +
                           1);  // a fresh vector: resizing the default {0} trips GCC 12's -Warray-bounds
  for (std::size_t f = 0; f <= faces; ++f) offsets[f] = static_cast<int>(f) * arity;
  mesh.face_offsets = std::move(offsets);
  mesh.face_vertices = std::move(corners);
  return mesh;
}

namespace {

/// `more`'s tags and face-varying channels after `into`'s (indices shifted); channels are kept when
/// both meshes have the same ones (names and widths), dropped otherwise.
void append_tags(Mesh& into, const Mesh& more, int base, int face_base) {
  for (EdgeSharpness c : more.tags.creases) {
    c.a += base;
    c.b += base;
    into.tags.creases.push_back(c);
  }
  for (VertexSharpness c : more.tags.corners) {
    c.vertex += base;
    into.tags.corners.push_back(c);
  }
  for (const int f : more.tags.holes) into.tags.holes.push_back(face_base + f);
  const bool same = into.face_varying.size() == more.face_varying.size() &&
                    std::equal(into.face_varying.begin(), into.face_varying.end(), more.face_varying.begin(),
                               [](const FaceVaryingChannel& x, const FaceVaryingChannel& y) {
                                 return x.name == y.name && x.values.cols() == y.values.cols();
                               });
  if (!same || face_base + static_cast<int>(face_count(more)) == 0) {
    into.face_varying.clear();
    return;
  }
  for (std::size_t i = 0; i < more.face_varying.size(); ++i) {
    FaceVaryingChannel& to = into.face_varying[i];
    const FaceVaryingChannel& from = more.face_varying[i];
    const auto value_base = static_cast<int>(to.values.rows());
    Points values(to.values.rows() + from.values.rows(), from.values.cols());
    values << to.values, from.values;
    to.values = std::move(values);
    for (const int k : from.indices) to.indices.push_back(value_base + k);
  }
}

}  // namespace

void append(Mesh& into, const Mesh& more) {
  if (face_count(into) == 0 && into.vertices.rows() == 0) {
    into.tags = more.tags;  // the options of the first mesh appended
    into.tags.creases.clear();
    into.tags.corners.clear();
    into.tags.holes.clear();
    into.face_varying = more.face_varying;
    for (FaceVaryingChannel& c : into.face_varying) {
      c.values.resize(0, c.values.cols());
      c.indices.clear();
    }
  }
  const int face_base = static_cast<int>(face_count(into));
  const Eigen::Index base = into.vertices.rows();
  // Normals survive when both meshes have them, per vertex or per corner (then per corner).
  const auto per_vertex = [](const Mesh& m) {
    return m.normal_indices.empty() && m.normals.rows() == m.vertices.rows();
  };
  const bool normals = (base == 0 || per_vertex(into) || !into.normal_indices.empty()) &&
                       (per_vertex(more) || !more.normal_indices.empty());
  const bool indexed = normals && (!into.normal_indices.empty() || !more.normal_indices.empty());
  const bool states = (face_count(into) == 0 || into.states.size() == face_count(into)) &&
                      more.states.size() == face_count(more);
  if (base == 0) into.vertices.resize(0, more.vertices.cols());
  Points vertices(base + more.vertices.rows(), more.vertices.cols());
  vertices << into.vertices, more.vertices;
  into.vertices = std::move(vertices);
  if (indexed) {  // before the corners are appended: into's own corners index its normals
    std::vector<int> indices = into.normal_indices.empty() ? into.face_vertices : into.normal_indices;
    const Points mine = into.normals.rows() == 0 ? Points(0, 3) : into.normals;
    const auto offset = static_cast<int>(mine.rows());
    for (std::size_t k = 0; k < more.face_vertices.size(); ++k)
      indices.push_back(offset +
                        (more.normal_indices.empty() ? more.face_vertices[k] : more.normal_indices[k]));
    Points n(mine.rows() + more.normals.rows(), 3);
    n << mine, more.normals;
    into.normals = std::move(n);
    into.normal_indices = std::move(indices);
  } else if (normals) {
    Points n(into.vertices.rows(), 3);
    n << (base == 0 ? Points(0, 3) : into.normals), more.normals;
    into.normals = std::move(n);
  } else {
    into.normals.resize(0, 0);
    into.normal_indices.clear();
  }
  const int corner_base = into.face_offsets.back();
  for (std::size_t f = 1; f < more.face_offsets.size(); ++f)
    into.face_offsets.push_back(corner_base + more.face_offsets[f]);
  for (const int v : more.face_vertices) into.face_vertices.push_back(static_cast<int>(base) + v);
  if (states)
    into.states.insert(into.states.end(), more.states.begin(), more.states.end());
  else
    into.states.clear();
  append_tags(into, more, static_cast<int>(base), face_base);
}

namespace {

constexpr std::array<std::string_view, 3> kBoundaryNames{"none", "edge", "corner"};
constexpr std::array<std::string_view, 2> kCreaseNames{"uniform", "chaikin"};
constexpr std::array<std::string_view, 2> kTriangleNames{"catmark", "smooth"};
constexpr std::array<std::string_view, 2> kRuleNames{"opensubdiv", "blz"};
constexpr std::array<std::string_view, 6> kFaceVaryingNames{"none",      "corners-only", "corners+1",
                                                            "corners+2", "boundaries",   "all"};

template <class Enum, std::size_t N>
Enum named(std::string_view name, const std::array<std::string_view, N>& names, std::string_view what) {
  std::string list;
  for (std::size_t i = 0; i < N; ++i) {
    if (names[i] == name) return static_cast<Enum>(i);
    list += (i ? ", " : "") + std::string(names[i]);
  }
  throw InvalidInput("unknown " + std::string(what) + " '" + std::string(name) + "' (" + list + ")");
}

}  // namespace

std::string_view option_name(BoundaryRule rule) noexcept {
  return kBoundaryNames[static_cast<std::size_t>(rule)];
}
std::string_view option_name(CreaseMethod method) noexcept {
  return kCreaseNames[static_cast<std::size_t>(method)];
}
std::string_view option_name(TriangleRule rule) noexcept {
  return kTriangleNames[static_cast<std::size_t>(rule)];
}
std::string_view option_name(FaceVaryingRule rule) noexcept {
  return kFaceVaryingNames[static_cast<std::size_t>(rule)];
}
std::string_view option_name(RuleSet rules) noexcept {
  return kRuleNames[static_cast<std::size_t>(rules)];
}
BoundaryRule named_boundary_rule(std::string_view name) {
  return named<BoundaryRule>(name, kBoundaryNames, "boundary rule");
}
CreaseMethod named_crease_method(std::string_view name) {
  return named<CreaseMethod>(name, kCreaseNames, "crease method");
}
TriangleRule named_triangle_rule(std::string_view name) {
  return named<TriangleRule>(name, kTriangleNames, "triangle rule");
}
FaceVaryingRule named_face_varying_rule(std::string_view name) {
  return named<FaceVaryingRule>(name, kFaceVaryingNames, "face-varying interpolation");
}

RuleSet named_rule_set(std::string_view name) {
  return named<RuleSet>(name, kRuleNames, "rule set");
}

void apply(const TagOverrides& o, MeshTags& tags) {
  if (o.rules) tags.rules = *o.rules;
  if (o.boundary) tags.boundary = *o.boundary;
  if (o.crease_method) tags.crease_method = *o.crease_method;
  if (o.triangles) tags.triangles = *o.triangles;
  if (o.face_varying) tags.face_varying = *o.face_varying;
}

std::string first_feature(const MeshTags& tags) {
  for (const EdgeSharpness& c : tags.creases)
    if (c.sharpness > 0)
      return "a crease (" + std::to_string(c.a) + " " + std::to_string(c.b) + ", sharpness " +
             number_text(c.sharpness, 6) + ")";
  for (const VertexSharpness& c : tags.corners)
    if (c.sharpness > 0)
      return "a corner (vertex " + std::to_string(c.vertex) + ", sharpness " + number_text(c.sharpness, 6) +
             ")";
  if (!tags.holes.empty()) return "a hole (face " + std::to_string(tags.holes.front()) + ")";
  if (tags.boundary == BoundaryRule::none) return "the boundary rule 'none'";
  return "";
}

std::vector<char> hole_flags(const Mesh& mesh) {
  std::vector<char> hole(face_count(mesh), 0);
  for (const int f : mesh.tags.holes)
    if (f >= 0 && static_cast<std::size_t>(f) < hole.size()) hole[static_cast<std::size_t>(f)] = 1;
  return hole;
}

namespace {

void check_sharpness(double s, const std::string& where) {
  if (!std::isfinite(s) || s < 0)
    throw InvalidInput(where + " has sharpness " + (std::isnan(s) ? std::string("NaN") : number_text(s, 6)) +
                       "; sharpness is a finite number ≥ 0 (" + number_text(kInfiniteSharpness, 3) +
                       " or more: infinitely sharp)");
}

void check_tags(const Mesh& mesh, const std::string& w) {
  const auto V = static_cast<long long>(mesh.vertices.rows());
  const auto vertex_text = [](int v) { return std::to_string(v); };
  std::vector<std::pair<int, int>> edges;
  for (std::size_t i = 0; i < mesh.tags.creases.size(); ++i) {
    const auto& c = mesh.tags.creases[i];
    const std::string where =
        w + ": crease " + std::to_string(i) + " (" + vertex_text(c.a) + " " + vertex_text(c.b) + ")";
    if (c.a < 0 || c.a >= V || c.b < 0 || c.b >= V)
      throw InvalidInput(where + " names a vertex out of range (" + std::to_string(V) + " vertices)");
    if (c.a == c.b) throw InvalidInput(where + " joins a vertex to itself");
    check_sharpness(c.sharpness, where);
    edges.emplace_back(std::min(c.a, c.b), std::max(c.a, c.b));
  }
  std::sort(edges.begin(), edges.end());
  if (const auto twice = std::adjacent_find(edges.begin(), edges.end()); twice != edges.end())
    throw InvalidInput(w + ": the edge " + std::to_string(twice->first) + " " +
                       std::to_string(twice->second) + " is creased twice");
  std::vector<int> vertices;
  for (std::size_t i = 0; i < mesh.tags.corners.size(); ++i) {
    const auto& c = mesh.tags.corners[i];
    const std::string where = w + ": corner " + std::to_string(i) + " (vertex " + vertex_text(c.vertex) + ")";
    if (c.vertex < 0 || c.vertex >= V)
      throw InvalidInput(where + " is out of range (" + std::to_string(V) + " vertices)");
    check_sharpness(c.sharpness, where);
    vertices.push_back(c.vertex);
  }
  std::sort(vertices.begin(), vertices.end());
  if (const auto twice = std::adjacent_find(vertices.begin(), vertices.end()); twice != vertices.end())
    throw InvalidInput(w + ": vertex " + std::to_string(*twice) + " has two corner sharpnesses");
  const std::size_t F = face_count(mesh);
  std::vector<char> hole(F, 0);
  for (const int f : mesh.tags.holes) {
    if (f < 0 || static_cast<std::size_t>(f) >= F)
      throw InvalidInput(w + ": hole face " + std::to_string(f) + " is out of range (" + std::to_string(F) +
                         " faces)");
    hole[static_cast<std::size_t>(f)] = 1;
  }
  if (F > 0 && std::all_of(hole.begin(), hole.end(), [](char h) { return h != 0; }))
    throw InvalidInput(w + ": every face is a hole; nothing is left to refine or draw");
  for (const FaceVaryingChannel& c : mesh.face_varying) {
    const std::string where = w + ": face-varying channel '" + c.name + "'";
    if (c.indices.size() != mesh.face_vertices.size())
      throw InvalidInput(where + " has " + std::to_string(c.indices.size()) + " corner indices for " +
                         std::to_string(mesh.face_vertices.size()) + " face corners");
    for (std::size_t k = 0; k < c.indices.size(); ++k)
      if (c.indices[k] < 0 || c.indices[k] >= c.values.rows())
        throw InvalidInput(where + ": corner " + std::to_string(k) + " refers to value " +
                           std::to_string(c.indices[k]) + ", out of range (" +
                           std::to_string(c.values.rows()) + " values)");
    check_rows(c.values, where, "values");
  }
}

}  // namespace

void check_mesh(const Mesh& mesh, std::string_view who) {
  const std::string w(who);
  if (mesh.vertices.cols() != 3 && mesh.vertices.rows() > 0)
    throw InvalidInput(w + ": mesh vertices have " + std::to_string(mesh.vertices.cols()) +
                       " columns, expected 3");
  check_rows(mesh.vertices, who, "vertices");
  const auto& offsets = mesh.face_offsets;
  if (offsets.empty() || offsets.front() != 0) throw InvalidInput(w + ": face offsets must start with 0");
  if (static_cast<std::size_t>(offsets.back()) != mesh.face_vertices.size())
    throw InvalidInput(w + ": the face offsets end at " + std::to_string(offsets.back()) + " but " +
                       std::to_string(mesh.face_vertices.size()) + " corners are given");
  const Eigen::Index V = mesh.vertices.rows();
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
    if (offsets[f + 1] - offsets[f] < 3)
      throw InvalidInput(w + ": face " + std::to_string(f) + " has " +
                         std::to_string(std::max(offsets[f + 1] - offsets[f], 0)) +
                         " vertices, a face needs at least 3");
    for (int k = offsets[f]; k < offsets[f + 1]; ++k) {
      const int i = mesh.face_vertices[static_cast<std::size_t>(k)];
      if (i < 0 || i >= V)
        throw InvalidInput(w + ": face " + std::to_string(f) + " corner " + std::to_string(k - offsets[f]) +
                           " = " + std::to_string(i) + " is out of range (" + std::to_string(V) +
                           " vertices)");
    }
  }
  if (!mesh.normal_indices.empty()) {
    if (mesh.normal_indices.size() != mesh.face_vertices.size())
      throw InvalidInput(w + ": " + std::to_string(mesh.normal_indices.size()) + " normal indices for " +
                         std::to_string(mesh.face_vertices.size()) + " face corners");
    if (mesh.normals.cols() != 3)
      throw InvalidInput(w + ": normals are " + std::to_string(mesh.normals.rows()) + " by " +
                         std::to_string(mesh.normals.cols()) + ", expected 3 columns");
    for (std::size_t k = 0; k < mesh.normal_indices.size(); ++k)
      if (const int i = mesh.normal_indices[k]; i < 0 || i >= mesh.normals.rows())
        throw InvalidInput(w + ": the normal index of corner " + std::to_string(k) + " = " +
                           std::to_string(i) + " is out of range (" + std::to_string(mesh.normals.rows()) +
                           " normals)");
    check_rows(mesh.normals, who, "normals");
  } else if (mesh.normals.size() != 0) {
    if (mesh.normals.rows() != V || mesh.normals.cols() != 3)
      throw InvalidInput(w + ": normals are " + std::to_string(mesh.normals.rows()) + " by " +
                         std::to_string(mesh.normals.cols()) + ", expected " + std::to_string(V) +
                         " by 3 (one per vertex)");
    check_rows(mesh.normals, who, "normals");
  }
  const std::size_t faces = face_count(mesh);
  if (!mesh.states.empty() && mesh.states.size() != faces)
    throw InvalidInput(w + ": " + std::to_string(mesh.states.size()) + " states for " +
                       std::to_string(faces) + " faces");
  check_tags(mesh, w);
}

Points vertex_normals(const Mesh& mesh) {
  check_mesh(mesh, "the mesh");
  Points N = Points::Zero(mesh.vertices.rows(), 3);
  const auto v = [&](int i) { return Eigen::Vector3d(mesh.vertices.row(i).transpose()); };
  for (std::size_t f = 0; f < face_count(mesh); ++f) {
    const auto c = face(mesh, f);
    Eigen::Vector3d n;
    if (c.size() == 3) {
      n = (v(c[1]) - v(c[0])).cross(v(c[2]) - v(c[0]));
    } else if (c.size() == 4) {
      // The vector area of a (possibly skew) quad is half the cross product of its diagonals.
      n = (v(c[2]) - v(c[0])).cross(v(c[3]) - v(c[1]));
    } else {
      n.setZero();  // Newell: twice the vector area, Σ v_i × v_{i+1}
      for (std::size_t i = 0; i < c.size(); ++i) n += v(c[i]).cross(v(c[(i + 1) % c.size()]));
    }
    for (const int i : c) N.row(i) += n.transpose();
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double length = N.row(i).norm();
    if (length > 0) N.row(i) /= length;
  }
  return N;
}

Segments polyline_segments(const Points& polyline, bool closed, std::uint32_t state) {
  Segments s;
  s.vertices = polyline;
  const int n = static_cast<int>(polyline.rows());
  for (int i = 0; i + 1 < n; ++i) s.segments.push_back({i, i + 1});
  if (closed && n > 2) s.segments.push_back({n - 1, 0});
  s.states.assign(s.segments.size(), state);
  return s;
}

void append(Segments& into, const Segments& more) {
  if (into.vertices.rows() == 0 && into.segments.empty()) {
    into = more;
    return;
  }
  if (into.vertices.cols() != more.vertices.cols())
    throw InvalidInput("segments with " + std::to_string(into.vertices.cols()) + " and with " +
                       std::to_string(more.vertices.cols()) + " coordinates cannot be drawn together");
  const int offset = static_cast<int>(into.vertices.rows());
  const bool states = !into.states.empty() || !more.states.empty();
  if (states) {
    into.states.resize(into.segments.size(), 0);
    into.states.insert(into.states.end(), more.states.begin(), more.states.end());
    into.states.resize(into.segments.size() + more.segments.size(), 0);
  }
  Points v(into.vertices.rows() + more.vertices.rows(), into.vertices.cols());
  v << into.vertices, more.vertices;
  into.vertices = std::move(v);
  for (const auto& s : more.segments) into.segments.push_back({s[0] + offset, s[1] + offset});
}

void check_segments(const Segments& segments, std::string_view who) {
  const std::string w(who);
  const auto cols = segments.vertices.cols();
  if ((cols != 2 && cols != 3) && segments.vertices.rows() > 0)
    throw InvalidInput(w + ": segment vertices have " + std::to_string(cols) + " columns, expected 2 or 3");
  check_rows(segments.vertices, who, "vertices");
  for (std::size_t s = 0; s < segments.segments.size(); ++s)
    for (std::size_t k = 0; k < 2; ++k) {
      const int i = segments.segments[s][k];
      if (i < 0 || i >= segments.vertices.rows())
        throw InvalidInput(w + ": " + at("segments", s) + "[" + std::to_string(k) +
                           "] = " + std::to_string(i) + " is out of range (" +
                           std::to_string(segments.vertices.rows()) + " vertices)");
    }
  if (!segments.states.empty() && segments.states.size() != segments.segments.size())
    throw InvalidInput(w + ": " + std::to_string(segments.states.size()) + " states for " +
                       std::to_string(segments.segments.size()) + " segments");
}

}  // namespace cifs
