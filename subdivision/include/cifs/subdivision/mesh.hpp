// SPDX-License-Identifier: MIT
// cifs — subdivision surfaces on polygon meshes (seed 003): Catmull–Clark, Loop, Doo–Sabin,
// modified Butterfly and √3. Topology apart from geometry, as OpenSubdiv's refiner/primvar split:
// refine_topology builds every level's faces and, for every new vertex, its weights on the
// previous level's vertices; apply replays those weights on any vertex data.
#pragma once

#include <Eigen/SparseCore>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "cifs/mesh.hpp"
#include "cifs/subdivision/rules.hpp"
#include "cifs/topology.hpp"
#include "cifs/types.hpp"

namespace cifs::subdivision {

using cifs::BoundaryRule;

struct MeshOptions {
  /// Refinements whose topology and weights would need more than this are refused before any work.
  std::size_t max_bytes = std::size_t{4} << 30;
  /// Called after every level with (faces made so far, faces of all levels): a progress bar.
  std::function<void(std::uint64_t, std::uint64_t)> progress = nullptr;
  /// refine_topology only. `weights`: keep every step's weights (MeshRefinement::steps, which apply,
  /// stencil_table and limit_stencils replay); false: topology only, as OpenSubdiv's RefineUniform —
  /// the primal schemes do not even make the rows. `last_level_adjacency`: build the last level's
  /// edges, rings and features; false: its faces only (OpenSubdiv's fullTopologyInLastLevel = false;
  /// with 0 levels the input keeps everything).
  bool weights = true;
  bool last_level_adjacency = true;
};

/// Sparse weights, one row per new vertex: new vertex i = Σ weights[k] · old vertex columns[k],
/// k in [offsets[i], offsets[i + 1]). Every row sums to 1 (affine combinations).
struct Stencils {
  std::vector<int> offsets{0};
  std::vector<int> columns;
  std::vector<double> weights;
};

inline std::size_t row_count(const Stencils& s) noexcept {
  return s.offsets.size() - 1;
}

/// A level's features — the state of the crease automaton (docs/subdivision-surfaces.md, "Creases as
/// an automaton"): the sharpness of every edge and vertex (0 smooth, ≥ kInfiniteSharpness infinite;
/// boundary edges are infinitely sharp) and the hole flag of every face. Empty vectors: all smooth,
/// no hole (a plain closed mesh refines by the smooth rules alone).
struct LevelFeatures {
  std::vector<double> edge_sharpness;    // per edge of the level
  std::vector<double> vertex_sharpness;  // per vertex
  std::vector<char> holes;               // per face
};

/// An edge's and a vertex's sharpness, and whether a face is a hole, at a level whose features may be
/// empty (all smooth, no hole).
inline double edge_sharpness(const LevelFeatures& f, std::integral auto e) {
  return f.edge_sharpness.empty() ? 0.0 : f.edge_sharpness[static_cast<std::size_t>(e)];
}
inline double vertex_sharpness(const LevelFeatures& f, std::integral auto v) {
  return f.vertex_sharpness.empty() ? 0.0 : f.vertex_sharpness[static_cast<std::size_t>(v)];
}
inline bool is_hole(const LevelFeatures& f, std::integral auto face) {
  return !f.holes.empty() && f.holes[static_cast<std::size_t>(face)] != 0;
}

/// A refinement, topology only: `levels[0]` is the input's topology, `levels[k]` the mesh after k
/// steps, `steps[k]` the weights from level k's vertices to level k + 1's, `features[k]` level k's
/// sharpness and holes, `tags[k]` level k's tags as a mesh of that level carries them (creases and
/// corners with their remaining sharpness, holes; the input's options): subdividing level k's mesh
/// with `tags[k]` once equals step k. Without `options.weights`, `steps` is empty; without
/// `options.last_level_adjacency`, `levels.back()` has its vertex count and faces only and
/// `features` stops one level short (`tags.back()` still has the last level's creases and holes).
struct MeshRefinement {
  MeshScheme scheme = MeshScheme::catmull_clark;
  MeshOptions options;
  std::vector<MeshTopology> levels;
  std::vector<LevelFeatures> features;
  std::vector<MeshTags> tags;
  std::vector<Stencils> steps;
};

/// Refines the faces `levels` times under the mesh's tags (creases, corners, holes, boundary rule,
/// crease method, triangle rule: OpenSubdiv's semi-sharp rules, docs/subdivision-surfaces.md).
/// Throws InvalidInput (naming the face, edge or vertex) for a mesh that is not an oriented
/// 2-manifold, for non-triangles under Loop, Butterfly and √3, for tags the scheme has no rules for
/// (Doo–Sabin, Butterfly and √3 refuse creases, corners and holes), for a crease on a pair of vertices
/// that is not an edge, and, before any work, for a result larger than `options.max_bytes` (the
/// message gives the figure). √3 treats boundaries every second step (Kobbelt): refining k levels
/// then m is the same as k + m levels at once only for closed meshes or an even k.
MeshRefinement refine_topology(const Mesh& mesh, MeshScheme scheme, int levels,
                               const MeshOptions& options = {});

/// The vertex data of the last level from the first level's (`#V by any`); `#V` must match.
Points apply(const MeshRefinement& refinement, const Points& vertices);
/// One step: level k + 1's data from level k's.
Points apply(const Stencils& step, const Points& vertices);
/// The same into `out`, whose storage is reused when it already has the size (no allocation, no
/// page faults on repeated replays).
void apply(const Stencils& step, const Points& vertices, Points& out);

/// The weights from the input's vertices straight to the last level's (the product of the steps;
/// OpenSubdiv's factorized stencil table): `apply(stencil_table(r), P)` equals `apply(r, P)` to
/// round-off in one pass over small, cached input data. Built once per topology.
Stencils stencil_table(const MeshRefinement& refinement);

/// The refined mesh (positions through apply; normals and states are not carried), with the last
/// level's tags (as MeshRefinement::tags) and face-varying channels (UVs) refined with the faces.
Mesh subdivide(const Mesh& mesh, MeshScheme scheme, int levels, const MeshOptions& options = {});
Mesh catmull_clark(const Mesh& mesh, int levels, const MeshOptions& options = {});
/// The factored form of Catmull–Clark (quad meshes) or Loop (triangles): linear subdivision, then
/// one averaging pass (seed 003 §3–4, Warren–Weimer), computed on the split mesh's positions, not
/// through the weights; equal to `subdivide` to round-off (docs/subdivision-surfaces.md gives the
/// averaging weights at extraordinary vertices, which the seed gets wrong). Refuses creases, corners
/// and holes (the factored form has only the smooth and boundary rules).
Mesh factored_subdivide(const Mesh& mesh, MeshScheme scheme, int levels, const MeshOptions& options = {});
Mesh loop(const Mesh& mesh, int levels, const MeshOptions& options = {});
Mesh doo_sabin(const Mesh& mesh, int levels, const MeshOptions& options = {});
Mesh butterfly(const Mesh& mesh, int levels, const MeshOptions& options = {});
Mesh sqrt3(const Mesh& mesh, int levels, const MeshOptions& options = {});
Mesh bilinear(const Mesh& mesh, int levels, const MeshOptions& options = {});

/// Seed 003 §1: a step as a sparse matrix, `#new by #old` (row i = stencil of new vertex i), for the
/// analysis of the scheme — never used for the refinement itself.
Eigen::SparseMatrix<double, Eigen::RowMajor> subdivision_matrix(const Stencils& step, int old_vertex_count);

}  // namespace cifs::subdivision
