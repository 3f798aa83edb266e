// SPDX-License-Identifier: MIT
// Fuzzing: the computations behind `cifs subdivide`, `cifs limit` and `cifs analyze` on fuzzed
// meshes with their tags (OBJ `t` lines: crease, corner, hole, interpolateboundary,
// facevaryinginterpolateboundary, facevaryingpropagatecorners, creasemethod, smoothtriangles). An
// input is 4 bytes of options, then the OBJ text:
//
//   byte 0       the scheme (catmull-clark, loop, doo-sabin, butterfly, sqrt3, bilinear)
//   byte 1       the operation: subdivide, limit (limit_mesh, limit_stencils + evaluate_limit),
//                the limit surface at (face, u, v) (evaluate_limit_surface), analyze
//   byte 2       the levels, 0 … 2
//   byte 3       where the limit surface is evaluated: face = byte, (u, v) from the byte's bits
//
// Properties: what returns from a mesh (finite by check_mesh) with coordinates within ±1e300 is
// finite (nearer ±1.7e308 the tangent masks' weights overflow: the writers refuse the result, see
// docs/reliability.md), and has the vertex and face counts of the refinement's last level
// (refine_topology, the one source of truth for the topology). The work per input is bounded:
// ≤ 64 faces, ≤ 2 levels, 64 MB.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "cifs/io/obj.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/topology.hpp"
#include "fuzz.hpp"

// Named, not anonymous: the harnesses compile as unity batches (CIFS_UNITY), each in its own namespace.
namespace fuzz_mesh_compute {

using namespace cifs;
using subdivision::MeshScheme;

constexpr std::size_t kOptionBytes = 4;
constexpr std::size_t kMaxFaces = 64;
constexpr std::size_t kMaxBytes = std::size_t{64} << 20;
constexpr MeshScheme kSchemes[] = {MeshScheme::catmull_clark, MeshScheme::loop,  MeshScheme::doo_sabin,
                                   MeshScheme::butterfly,     MeshScheme::sqrt3, MeshScheme::bilinear};

void require_counts(const Mesh& result, const subdivision::MeshRefinement& r, const char* what) {
  const MeshTopology& last = r.levels.back();
  fuzz::require(result.vertices.rows() == last.vertex_count && result.face_offsets == last.face_offsets,
                what);
}

CIFS_FUZZ_HARNESS(mesh_compute) {
  if (size < kOptionBytes) return 0;
  const MeshScheme scheme = kSchemes[data[0] % std::size(kSchemes)];
  const int operation = data[1] % 4;
  const int levels = data[2] % 3;
  const std::uint8_t where = data[3];
  fuzz::refusals_allowed([&] {
    const io::MeshReadOptions read{.strict = false, .warn = [](const std::string&) {}};
    const Mesh mesh =
        io::parse_mesh_obj(fuzz::text(data + kOptionBytes, size - kOptionBytes), "fuzz.obj", read);
    if (mesh.face_offsets.size() - 1 > kMaxFaces) return;  // the work per input
    const bool moderate = mesh.vertices.size() == 0 || mesh.vertices.cwiseAbs().maxCoeff() <= 1e300;
    const auto finite = [&](const Points& P) { return !moderate || P.allFinite(); };
    const subdivision::MeshOptions options{.max_bytes = kMaxBytes, .progress = nullptr};
    switch (operation) {
      case 0: {  // cifs subdivide
        const Mesh result = subdivision::subdivide(mesh, scheme, levels, options);
        fuzz::require(finite(result.vertices), "subdivide: finite");
        require_counts(result, subdivision::refine_topology(mesh, scheme, levels, options),
                       "subdivide: counts");
        break;
      }
      case 1: {  // cifs limit: limit_mesh, and the stencils it is made of
        const Mesh result =
            subdivision::limit_mesh(mesh, scheme, levels, {.normals = false, .max_bytes = kMaxBytes});
        fuzz::require(finite(result.vertices), "limit: finite");
        const subdivision::MeshRefinement r = subdivision::refine_topology(mesh, scheme, levels, options);
        require_counts(result, r, "limit: counts");
        const subdivision::LimitFrame frame =
            subdivision::evaluate_limit(subdivision::limit_stencils(r), subdivision::apply(r, mesh.vertices));
        fuzz::require(frame.positions.rows() == r.levels.back().vertex_count && finite(frame.positions) &&
                          finite(frame.tangent_u) && finite(frame.tangent_v),
                      "limit stencils: finite, one row per vertex");
        break;
      }
      case 2: {  // the limit surface at (face, u, v)
        const int faces = static_cast<int>(mesh.face_offsets.size()) - 1;
        const subdivision::FacePoint at[] = {
            {.face = where % faces, .u = (where & 7) / 8.0, .v = ((where >> 3) & 7) / 16.0},
            {.face = 0, .u = 0, .v = 0},
            {.face = faces - 1, .u = 0.5, .v = 0.25}};
        const subdivision::SurfaceSample s = subdivision::evaluate_limit_surface(mesh, scheme, at);
        fuzz::require(s.positions.rows() == 3 && finite(s.positions) && finite(s.du) && finite(s.dv),
                      "limit surface: finite");
        break;
      }
      default: {  // cifs analyze
        const subdivision::MeshSmoothness a = subdivision::analyze_mesh(mesh, scheme, "fuzz.obj");
        const int listed = static_cast<int>(a.vertices.size());
        // Doo–Sabin counts points: each face, each vertex but the boundary ones (they make no face).
        int points = static_cast<int>(mesh.vertices.rows());
        if (scheme == MeshScheme::doo_sabin) {
          const MeshTopology t = build_topology(mesh, "fuzz.obj");
          points += static_cast<int>(face_count(t)) -
                    static_cast<int>(std::count(t.boundary_vertex.begin(), t.boundary_vertex.end(), 1));
        }
        fuzz::require(
            a.regular + a.isolated + listed == points && a.c1 + a.not_c1 + a.undecided == listed,
            "analyze: every vertex (Doo–Sabin: point) counted once, every listed one has a verdict");
        for (const subdivision::VertexSmoothness& v : a.vertices)
          fuzz::require(
              std::isfinite(static_cast<double>(v.lambda1)) && std::isfinite(static_cast<double>(v.lambda2)),
              "analyze: finite eigenvalues");
      }
    }
  });
  return 0;
}

}  // namespace fuzz_mesh_compute
