// SPDX-License-Identifier: MIT
// cifs — limit stencils from the left eigenvectors of S_n (cifs/subdivision/limit.hpp).
#include "cifs/subdivision/limit.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/memory.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "local_mesh.hpp"

namespace cifs::subdivision {
namespace {

LimitMask mask(MeshScheme scheme, int valence, const LocalOptions& local) {
  const LocalMatrix S = local_matrix(scheme, valence, local);
  const LocalSpectrum spectrum = local_spectrum(S);
  const auto doubles = [](const LongVector& w) {
    std::vector<double> out(static_cast<std::size_t>(w.size()));
    for (Eigen::Index i = 0; i < w.size(); ++i) out[static_cast<std::size_t>(i)] = static_cast<double>(w(i));
    return out;
  };
  LimitMask out{.position = doubles(spectrum.limit_stencil), .tangent_u = {}, .tangent_v = {}};
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
  out.tangent_u = doubles(left.col(0));
  out.tangent_v = doubles(left.col(1));
  return out;
}

/// Why the neighbourhood of v cannot be walked, or nothing.
const char* unsupported(const MeshTopology& t, MeshScheme scheme, int v) {
  const std::size_t corners = scheme == MeshScheme::catmull_clark ? 4 : 3;
  for (const int f : vertex_faces(t, static_cast<std::size_t>(v)))
    if (face(t, static_cast<std::size_t>(f)).size() != corners)
      return scheme == MeshScheme::catmull_clark
                 ? "touches a face that is not a quad (refine one level first)"
                 : "touches a face that is not a triangle";
  return nullptr;
}

}  // namespace

LimitStencils limit_stencils(const MeshTopology& t, MeshScheme scheme, BoundaryRule boundary) {
  const std::string who(scheme_name(scheme));
  if (scheme == MeshScheme::doo_sabin)
    throw InvalidInput(who + ": limit points belong to faces under this dual scheme; not built");
  LimitStencils out;
  const auto V = static_cast<std::size_t>(t.vertex_count);
  out.offsets.reserve(V + 1);
  out.mask_of.reserve(V);
  out.columns.reserve(V * (scheme == MeshScheme::catmull_clark ? 9 : 7));
  // Masks by kind: [valence][boundary]; −1 until first needed. Kind 0 is "the vertex itself".
  out.masks.push_back(LimitMask{.position = {1.0}, .tangent_u = {}, .tangent_v = {}});
  std::vector<std::array<int, 2>> kind;
  std::vector<int> nb;
  for (int v = 0; v < t.vertex_count; ++v) {
    const int n = valence(t, static_cast<std::size_t>(v));
    const bool on_boundary = t.boundary_vertex[static_cast<std::size_t>(v)] != 0;
    // Isolated vertices stay where they are; Butterfly interpolates: the vertex is its limit.
    if (n == 0 || traits(scheme).interpolating) {
      out.columns.push_back(v);
      out.offsets.push_back(static_cast<int>(out.columns.size()));
      out.mask_of.push_back(0);
      continue;
    }
    const auto where = [&] {
      return who + ": vertex " + std::to_string(v) + " (valence " + std::to_string(n) + ")";
    };
    if (on_boundary && scheme != MeshScheme::catmull_clark && scheme != MeshScheme::loop)
      throw InvalidInput(where() +
                         " is on the boundary: limit points there are built for catmull-clark and loop only");
    if (const char* why = unsupported(t, scheme, v)) throw InvalidInput(where() + " " + why);
    if (kind.size() <= static_cast<std::size_t>(n)) kind.resize(static_cast<std::size_t>(n) + 1, {-1, -1});
    int& k = kind[static_cast<std::size_t>(n)][on_boundary ? 1 : 0];
    if (k < 0) {
      try {
        out.masks.push_back(mask(scheme, n, LocalOptions{.boundary = on_boundary, .rule = boundary}));
      } catch (const InvalidInput& e) {
        std::string_view what = e.what();  // the scheme's name once: where() starts with it
        if (what.starts_with(who + ": ")) what.remove_prefix(who.size() + 2);
        throw InvalidInput(where() + ": " + std::string(what));
      }
      k = static_cast<int>(out.masks.size()) - 1;
    }
    const int start =
        other_vertex(t, static_cast<std::size_t>(vertex_edges(t, static_cast<std::size_t>(v))[0]), v);
    detail::neighbourhood(t, scheme, v, start, on_boundary, nb);
    out.columns.insert(out.columns.end(), nb.begin(), nb.end());
    out.offsets.push_back(static_cast<int>(out.columns.size()));
    out.mask_of.push_back(k);
  }
  return out;
}

namespace {

/// One pass, each neighbourhood gathered once for the three weighted sums; D = 3 lets the compiler
/// keep the sums in registers.
template <int D>
void limit_rows(const LimitStencils& s, const Points& x, LimitFrame& out, bool tangents) {
  using Row = Eigen::Matrix<double, 1, D>;
  const Eigen::Index d = x.cols();
  const auto V = static_cast<Eigen::Index>(s.mask_of.size());
  for (Eigen::Index v = 0; v < V; ++v) {
    const LimitMask& m = s.masks[static_cast<std::size_t>(s.mask_of[static_cast<std::size_t>(v)])];
    const int* column = s.columns.data() + s.offsets[static_cast<std::size_t>(v)];
    const bool with_tangents = tangents && !m.tangent_u.empty();
    Row p = Row::Zero(d), u = Row::Zero(d), w = Row::Zero(d);
    for (std::size_t i = 0; i < m.position.size(); ++i) {
      const Eigen::Map<const Row> row(x.data() + static_cast<std::ptrdiff_t>(column[i]) * d, d);
      p += m.position[i] * row;
      if (!with_tangents) continue;
      u += m.tangent_u[i] * row;
      w += m.tangent_v[i] * row;
    }
    Eigen::Map<Row>(out.positions.data() + v * d, d) = p;
    if (!tangents) continue;
    Eigen::Map<Row>(out.tangent_u.data() + v * d, d) = u;
    Eigen::Map<Row>(out.tangent_v.data() + v * d, d) = w;
  }
}

}  // namespace

void evaluate_limit(const LimitStencils& s, const Points& x, LimitFrame& out, bool tangents) {
  const auto V = static_cast<Eigen::Index>(s.mask_of.size());
  const Eigen::Index d = x.cols();
  const auto resize = [&](Points& P) {
    if (P.rows() == V && P.cols() == d) return;  // storage reused: no page faults on repeated calls
    P.resize(V, d);
    advise_huge_pages(P.data(), static_cast<std::size_t>(P.size()) * sizeof(double));
  };
  resize(out.positions);
  if (tangents) {
    resize(out.tangent_u);
    resize(out.tangent_v);
  }
  if (d == 3)
    limit_rows<3>(s, x, out, tangents);
  else
    limit_rows<Eigen::Dynamic>(s, x, out, tangents);
}

LimitFrame evaluate_limit(const LimitStencils& stencils, const Points& vertices, bool tangents) {
  LimitFrame out;
  evaluate_limit(stencils, vertices, out, tangents);
  return out;
}

Mesh limit_mesh(const Mesh& mesh, MeshScheme scheme, int levels, const LimitOptions& options) {
  if (const std::string feature = first_feature(mesh.tags); !feature.empty())
    throw InvalidInput(
        std::string(scheme_name(scheme)) + ": the mesh has " + feature +
        "; limits under creases, corners and holes are not built yet (cifs subdivide refines them)");
  if (mesh.tags.triangles == TriangleRule::smooth && scheme == MeshScheme::catmull_clark)
    throw InvalidInput(
        "catmull-clark: limits under the smooth-triangle rule are not built yet; subdivide instead");
  const MeshRefinement r = refine_topology(mesh, scheme, levels, MeshOptions{.max_bytes = options.max_bytes});
  const MeshTopology& last = r.levels.back();
  if (options.normals && scheme == MeshScheme::butterfly)
    throw InvalidInput(
        "butterfly: limit normals are not built (next to an extraordinary vertex the invariant neighbourhood "
        "is not the regular one)");
  if (options.normals && scheme == MeshScheme::bilinear)
    throw InvalidInput(
        "bilinear: the limit surface is the refined mesh, with no normal at its vertices (only C0)");
  if (options.normals &&
      std::any_of(last.boundary_vertex.begin(), last.boundary_vertex.end(), [](char b) { return b != 0; }))
    throw InvalidInput(
        std::string(scheme_name(scheme)) +
        ": limit normals at boundary vertices are not built; the mesh has a boundary (drop the normals)");
  if (options.normals && mesh.vertices.cols() != 3)
    throw InvalidInput(std::string(scheme_name(scheme)) + ": limit normals need 3-D vertices, not " +
                       std::to_string(mesh.vertices.cols()) + "-D");
  const LimitFrame frame = evaluate_limit(limit_stencils(last, scheme, mesh.tags.boundary),
                                          apply(r, mesh.vertices), options.normals);
  Mesh out;
  out.vertices = frame.positions;
  out.face_offsets = last.face_offsets;
  out.face_vertices = last.face_vertices;
  if (options.normals) {
    out.normals.resize(out.vertices.rows(), 3);
    for (Eigen::Index i = 0; i < out.vertices.rows(); ++i) {
      const Eigen::Vector3d u = frame.tangent_u.row(i).transpose(), v = frame.tangent_v.row(i).transpose();
      const Eigen::Vector3d n = u.cross(v);
      const double length = n.norm();  // 0 where the surface is singular: left 0
      out.normals.row(i) = (length > 0 ? Eigen::Vector3d(n / length) : n).transpose();
    }
  }
  return out;
}

}  // namespace cifs::subdivision
