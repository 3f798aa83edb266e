// SPDX-License-Identifier: MIT
// cifs — limit stencils from the left eigenvectors of S_n (cifs/subdivision/limit.hpp).
#include "cifs/subdivision/limit.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "cifs/errors.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "local_mesh.hpp"

namespace cifs::subdivision {
namespace {

/// Limit weights on a vertex's neighbourhood, in mesh_analysis.hpp's numbering.
struct Masks {
  LongVector position, tangent_u, tangent_v;  // tangents empty on the boundary
};

Masks masks(MeshScheme scheme, int valence, const LocalOptions& local) {
  const LocalMatrix S = local_matrix(scheme, valence, local);
  const LocalSpectrum spectrum = local_spectrum(S);
  Masks out{.position = spectrum.limit_stencil, .tangent_u = {}, .tangent_v = {}};
  if (local.boundary) return out;
  const auto N = S.values.rows();
  const LongMatrix A = (S.values - spectrum.subdominant * LongMatrix::Identity(N, N)).transpose();
  const Eigen::JacobiSVD<LongMatrix> svd(A, Eigen::ComputeFullV);
  LongMatrix left = svd.matrixV().rightCols(2);
  // Orientation: on the planar local mesh (counter-clockwise faces, normal +z) the pair must give
  // a positive frame.
  const Mesh plane = local_mesh(scheme, valence, local, 3);
  const MeshTopology t = build_topology(plane, "local mesh");
  const std::vector<int> nb =
      detail::neighbourhood(t, scheme, 0, 1, false);  // vertex 0, sector 0 at vertex 1
  Eigen::Vector2d u = Eigen::Vector2d::Zero(), v = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < nb.size(); ++i) {
    const Eigen::Vector2d p = plane.vertices.row(nb[i]).head<2>().transpose();
    u += static_cast<double>(left(static_cast<Eigen::Index>(i), 0)) * p;
    v += static_cast<double>(left(static_cast<Eigen::Index>(i), 1)) * p;
  }
  if (u.x() * v.y() - u.y() * v.x() < 0) left.col(1) *= -1;
  out.tangent_u = left.col(0);
  out.tangent_v = left.col(1);
  return out;
}

void add_row(Stencils& s, const std::vector<int>& nb, const LongVector& weights) {
  for (std::size_t i = 0; i < nb.size() && weights.size() > 0; ++i) {
    s.columns.push_back(nb[i]);
    s.weights.push_back(static_cast<double>(weights(static_cast<Eigen::Index>(i))));
  }
  s.offsets.push_back(static_cast<int>(s.columns.size()));
}

/// Why the neighbourhood of v cannot be walked, or nothing.
std::string unsupported(const MeshTopology& t, MeshScheme scheme, int v) {
  const auto faces = vertex_faces(t, static_cast<std::size_t>(v));
  const std::size_t corners = scheme == MeshScheme::catmull_clark ? 4 : 3;
  for (const int f : faces)
    if (face(t, static_cast<std::size_t>(f)).size() != corners)
      return scheme == MeshScheme::catmull_clark
                 ? "touches a face that is not a quad (refine one level first)"
                 : "touches a face that is not a triangle";
  return {};
}

}  // namespace

LimitStencils limit_stencils(const MeshTopology& t, MeshScheme scheme, BoundaryRule boundary) {
  const std::string who(scheme_name(scheme));
  if (scheme == MeshScheme::doo_sabin)
    throw InvalidInput(who + ": limit points belong to faces under this dual scheme; not built");
  LimitStencils out;
  std::map<std::pair<int, bool>, Masks> cache;
  for (int v = 0; v < t.vertex_count; ++v) {
    const int n = valence(t, static_cast<std::size_t>(v));
    const bool on_boundary = t.boundary_vertex[static_cast<std::size_t>(v)] != 0;
    const std::string where = who + ": vertex " + std::to_string(v) + " (valence " + std::to_string(n) + ")";
    if (n == 0) {  // isolated: it stays where it is
      add_row(out.position, {v}, LongVector::Ones(1));
      add_row(out.tangent_u, {}, {});
      add_row(out.tangent_v, {}, {});
      continue;
    }
    if (scheme == MeshScheme::butterfly) {  // interpolating: the vertex is its limit
      add_row(out.position, {v}, LongVector::Ones(1));
      add_row(out.tangent_u, {}, {});
      add_row(out.tangent_v, {}, {});
      continue;
    }
    if (on_boundary && scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
      throw InvalidInput(where +
                         " is on the boundary: limit points there are built for catmull-clark and loop only");
    if (const std::string why = unsupported(t, scheme, v); !why.empty())
      throw InvalidInput(where + " " + why);
    auto it = cache.find({n, on_boundary});
    if (it == cache.end()) {
      try {
        it = cache
                 .emplace(std::pair{n, on_boundary},
                          masks(scheme, n, LocalOptions{.boundary = on_boundary, .rule = boundary}))
                 .first;
      } catch (const InvalidInput& e) {
        throw InvalidInput(where + ": " + e.what());
      }
    }
    const int start =
        other_vertex(t, static_cast<std::size_t>(vertex_edges(t, static_cast<std::size_t>(v))[0]), v);
    const std::vector<int> nb = detail::neighbourhood(t, scheme, v, start, on_boundary);
    add_row(out.position, nb, it->second.position);
    add_row(out.tangent_u, nb, it->second.tangent_u);
    add_row(out.tangent_v, nb, it->second.tangent_v);
  }
  return out;
}

Mesh limit_mesh(const Mesh& mesh, MeshScheme scheme, int levels, const LimitOptions& options) {
  const MeshRefinement r = refine_topology(
      mesh, scheme, levels, MeshOptions{.boundary = options.boundary, .max_bytes = options.max_bytes});
  const MeshTopology& last = r.levels.back();
  if (options.normals &&
      std::any_of(last.boundary_vertex.begin(), last.boundary_vertex.end(), [](char b) { return b != 0; }))
    throw InvalidInput(
        std::string(scheme_name(scheme)) +
        ": limit normals at boundary vertices are not built; the mesh has a boundary (drop the normals)");
  if (options.normals && scheme == MeshScheme::butterfly)
    throw InvalidInput(
        "butterfly: limit normals are not built (next to an extraordinary vertex the invariant neighbourhood "
        "is not the regular one)");
  if (options.normals && mesh.vertices.cols() != 3)
    throw InvalidInput(std::string(scheme_name(scheme)) + ": limit normals need 3-D vertices, not " +
                       std::to_string(mesh.vertices.cols()) + "-D");
  const LimitStencils stencils = limit_stencils(last, scheme, options.boundary);
  const Points refined = apply(r, mesh.vertices);
  Mesh out;
  out.vertices = apply(stencils.position, refined);
  out.face_offsets = last.face_offsets;
  out.face_vertices = last.face_vertices;
  if (options.normals) {
    const Points u = apply(stencils.tangent_u, refined), v = apply(stencils.tangent_v, refined);
    out.normals.resize(out.vertices.rows(), 3);
    for (Eigen::Index i = 0; i < out.vertices.rows(); ++i) {
      const Eigen::Vector3d n = u.row(i).head<3>().transpose().cross(v.row(i).head<3>().transpose());
      const double length = n.norm();  // 0 where the surface is singular: left 0
      out.normals.row(i) = (length > 0 ? Eigen::Vector3d(n / length) : n).transpose();
    }
  }
  return out;
}

}  // namespace cifs::subdivision
