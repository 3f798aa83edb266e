// SPDX-License-Identifier: MIT
// cifs — polygon meshes and segment sets: construction, checks, vertex normals.
#include "cifs/mesh.hpp"

#include <Eigen/Geometry>
#include <climits>
#include <cmath>
#include <string>

#include "cifs/errors.hpp"

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

void append(Mesh& into, const Mesh& more) {
  const Eigen::Index base = into.vertices.rows();
  const bool normals =
      (base == 0 || into.normals.rows() == base) && more.normals.rows() == more.vertices.rows();
  const bool states = (face_count(into) == 0 || into.states.size() == face_count(into)) &&
                      more.states.size() == face_count(more);
  if (base == 0) into.vertices.resize(0, more.vertices.cols());
  Points vertices(base + more.vertices.rows(), more.vertices.cols());
  vertices << into.vertices, more.vertices;
  into.vertices = std::move(vertices);
  if (normals) {
    Points n(into.vertices.rows(), 3);
    n << (base == 0 ? Points(0, 3) : into.normals), more.normals;
    into.normals = std::move(n);
  } else {
    into.normals.resize(0, 0);
  }
  const int corner_base = into.face_offsets.back();
  for (std::size_t f = 1; f < more.face_offsets.size(); ++f)
    into.face_offsets.push_back(corner_base + more.face_offsets[f]);
  for (const int v : more.face_vertices) into.face_vertices.push_back(static_cast<int>(base) + v);
  if (states)
    into.states.insert(into.states.end(), more.states.begin(), more.states.end());
  else
    into.states.clear();
}

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
  if (mesh.normals.size() != 0) {
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
