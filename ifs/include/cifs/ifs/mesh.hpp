// SPDX-License-Identifier: MIT
// cifs — attractors of surface automata as watertight quad meshes: the separable route for
// tensor-product (NURBS) automata and the generic route for any automaton with four children per
// state in the GH, GB, DH, DB layout (fractal, perturbed surfaces).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/mesh.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

/// The meshes of this header are cifs::Mesh objects whose faces are all quads (face f has the
/// corners face_vertices[4f … 4f + 3]) with one state per face.
///
/// Grid layout (surface_mesh, quad_mesh): the attractor at depth K of a grid of A × B patches as one
/// quad mesh over the global grid of (A·2^K + 1) × (B·2^K + 1) nodes, node (I, J) — I along u, J
/// along v — being vertex `I·(B·2^K + 1) + J` (u-major). Patch (a, b) covers the nodes a·2^K …
/// (a+1)·2^K by b·2^K … (b+1)·2^K; neighbouring leaves and patches share their boundary nodes, so
/// the mesh is watertight by construction.
///
/// - `vertices`: `#V by dim` (Cartesian when the nets were homogeneous and `homogeneous` was set,
///   otherwise the nets' columns as they are);
/// - faces: one quad per leaf, cell (I, J) at face `I·(B·2^K) + J`, corners
///   `(I, J), (I+1, J), (I+1, J+1), (I, J+1)`: counter-clockwise in the (u, v) parameter plane, so
///   the face normal points along S_u × S_v;
/// - `states`: the automaton state of that leaf; `normals` empty.
///
/// The node (I, J) is the attractor point of the leaf cell `(min(I, A·2^K − 1), min(J, B·2^K − 1))`
/// at its corner: each node is computed once, by that one leaf.

struct MeshOptions {
  /// The nets hold homogeneous rows `(w·x, w)` (rational surfaces): vertices are divided by w.
  bool homogeneous = false;
  /// Refuse (before any work) a mesh larger than this many bytes (mesh_bytes).
  std::size_t max_bytes = std::size_t{1} << 30;
  /// Generic route: depth L of the precomposed stencil tables ((2^L + 1)² functionals per state;
  /// lowered automatically so that the tables stay below half of the output). Not read by apply_table.
  int max_table_depth = 6;
  /// Into a Mesh only (surface_mesh, quad_mesh, apply_table): the mesh holds the faces and states of an
  /// earlier call of the same route with the same automaton, depth (and patches, table) — a sweep or
  /// animation: they do not depend on the nets — so only the vertices are written (24 of the 48 bytes
  /// per vertex for surface_mesh). Their sizes are checked (any other size rewrites them), their contents
  /// are not: set it only for a mesh this route filled.
  bool keep_faces = false;
};

/// Bytes of a quad mesh of `vertices` nodes with `cols` coordinates and `quads` quads: vertices,
/// corners, face offsets and states (saturating).
std::size_t mesh_bytes(std::size_t vertices, std::size_t cols, std::size_t quads) noexcept;

/// Separable route for a tensor-product automaton (nets from nurbs::initial_nets, `(p+1)(q+1) by
/// cols`, row i·(q+1) + j). The curve stencil tables F_u (`A·2^K + 1 by p + 1`) and F_v of the two
/// factor automata — row I is the functional, on the net of the segment owning node I, of the
/// point at node I (attractor_points of the factor with identity nets) — give every patch's block
/// as F_u·N·F_vᵀ per coordinate. The v pass N·F_vᵀ is done once per row of patches, as p + 1
/// contiguous vertex rows Y_k; each vertex row is then Σ_k F_u(I, k)·Y_k: (p + 1) multiply-adds
/// per vertex coordinate over one contiguous run, against (p + 1)(q + 1) for Kronecker tables.
/// Throws InvalidInput for a negative depth, nets that do not fit, or a mesh
/// above `options.max_bytes`.
Mesh surface_mesh(const nurbs::TensorAutomaton& automaton, std::span<const Points> nets, int depth,
                  const MeshOptions& options = {});
/// The same into `mesh`, whose storage (vertices, corners, offsets, states) is reused when it is large
/// enough: repeated calls of one size fault its pages in once (fresh storage is advised for huge pages).
/// Refusals of the size or the nets (InvalidInput) leave `mesh` unchanged.
void surface_mesh(const nurbs::TensorAutomaton& automaton, std::span<const Points> nets, int depth,
                  Mesh& mesh, const MeshOptions& options = {});

/// Generic route: any automaton whose reachable states have exactly four children in the GH, GB,
/// DH, DB layout (child 2·iu + iv covers the u-half iu and the v-half iv of its parent's square),
/// with general matrices (`to.size by from.size`, rows summing to 1). `patches[i]` places
/// `automaton.initial[i]` at (a, b) in a grid that the patches must fill exactly once. Corner points
/// are the fixed points of the corner words (child k repeated, repeated_child_functionals); the
/// subdivision tree is walked to depth K − L and each node emits its block through stencil tables
/// of depth L (mesh_stencil_table then apply_table). Throws InvalidInput as surface_mesh, and for a
/// state without four children or patches that do not tile a grid.
Mesh quad_mesh(const automata::Automaton& automaton, std::span<const Points> nets,
               std::span<const std::array<int, 2>> patches, int depth, const MeshOptions& options = {});
/// The same into `mesh`, whose storage is reused (and whose faces are kept with options.keep_faces), as
/// surface_mesh's. Refusals leave `mesh` unchanged.
void quad_mesh(const automata::Automaton& automaton, std::span<const Points> nets,
               std::span<const std::array<int, 2>> patches, int depth, Mesh& mesh,
               const MeshOptions& options = {});

/// The generic route with every initial entry meshed on its own, for patches that do not tile a
/// grid (the faces of a subdivision surface): patch i is the block of (2^K + 1)² vertices from
/// i·(2^K + 1)², node (I, J) at I·(2^K + 1) + J, and of 4^K quads from i·4^K, cell (I, J) at
/// I·2^K + J. Nodes that neighbouring patches share are computed by each. Throws as quad_mesh.
Mesh patch_meshes(const automata::Automaton& automaton, std::span<const Points> nets, int depth,
                  const MeshOptions& options = {});

/// The generic route's topology, built once and applied to any nets of the automaton (animations,
/// sweeps, several net sets side by side): the mesh analogue of StencilTable. Per reachable state
/// s, `tables[s]` holds the (2^L + 1)² node functionals of its square on its net (row
/// i·(2^L + 1) + j for node (i, j), owned by the child (min(i / h, 1), min(j / h, 1)), h = 2^(L−1),
/// as the global nodes are by their leaves; L = 0 holds the corner functionals) and
/// `leaf_states[s]` the states of its 4^L leaves (row-major). Applying walks the tree to depth K − L
/// (one net product per node) and writes each node's block as tables[s]·N.
struct MeshStencilTable {
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  automata::Automaton automaton;
  int depth = 0;        // K
  int table_depth = 0;  // L ≤ K
  /// Grid place (a, b) of each initial entry (quad_mesh's layout); empty: each entry meshed on its
  /// own (patch_meshes' layout).
  std::vector<std::array<int, 2>> patches;
  std::vector<RowMatrix> tables = {};                        // by state
  std::vector<std::vector<std::uint32_t>> leaf_states = {};  // by state
};

struct MeshStencilOptions {
  /// Grid places of the initial entries, as quad_mesh's `patches`; empty for patch_meshes' layout.
  std::vector<std::array<int, 2>> patches = {};
  /// Largest table depth L (lowered to the depth K, and until the tables fit in max_entries).
  int max_table_depth = 6;
  /// Doubles the tables may hold (and, while building, the previous level besides): the largest
  /// L ≤ max_table_depth within it is taken, L = 0 (four corner functionals per state) always.
  std::size_t max_entries = std::size_t{1} << 21;
};

/// Builds the table of `automaton` at depth K. Throws InvalidInput for an invalid automaton, a
/// reachable state without four children, a negative depth, patches that do not tile a grid, and a
/// mesh beyond 32-bit indices.
MeshStencilTable mesh_stencil_table(const automata::Automaton& automaton, int depth,
                                    const MeshStencilOptions& options = {});

/// The mesh of these nets (one per initial entry, `size(state) by cols`) into `mesh`, whose storage
/// is reused when it is large enough: the same mesh, bit for bit, as quad_mesh (patch_meshes) with
/// the same table depth. Reads `options.homogeneous` and `options.max_bytes`. Throws InvalidInput
/// for nets that do not fit, a mesh above max_bytes, or a table that is not one mesh_stencil_table
/// built (its fields edited), leaving `mesh` unchanged.
void apply_table(const MeshStencilTable& table, std::span<const Points> nets, Mesh& mesh,
                 const MeshOptions& options = {});
Mesh apply_table(const MeshStencilTable& table, std::span<const Points> nets,
                 const MeshOptions& options = {});

}  // namespace cifs::ifs
