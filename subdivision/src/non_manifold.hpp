// SPDX-License-Identifier: MIT
// cifs — non-manifold meshes refined as OpenSubdiv refines them, through a manifold stand-in: every
// vertex split into one copy per fan of faces, every non-manifold edge into one boundary edge per
// face, with the sharpness OpenSubdiv gives such features (docs/subdivision-surfaces.md,
// "Non-manifold meshes"). Internal to the subdivision module.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cifs/mesh.hpp"
#include "cifs/topology.hpp"

namespace cifs::subdivision::detail {

/// The manifold stand-in of a non-manifold mesh and, per vertex of it, the vertex it copies (its
/// own index for the first copy, which keeps the input's index).
struct ManifoldSplit {
  Mesh mesh;
  std::vector<int> representative;
};

/// The stand-in: vertices split by fans (copies appended after the input's vertices); edges of more
/// than two faces, or of two faces running the same way, become boundary edges tagged infinitely
/// sharp; non-manifold vertices infinitely sharp corners — but a vertex on exactly two non-manifold
/// edges, with no boundary edge and more faces than edges, which follows the crease rule along them;
/// under the boundary rule `none`, every face around a vertex with an untagged boundary edge a hole.
/// Tags on the input's edges and vertices are carried to all their copies. Nothing when the mesh is
/// manifold. Throws InvalidInput (naming `who`) for a configuration the split cannot make manifold.
std::optional<ManifoldSplit> split_non_manifold(const Mesh& mesh, const std::string& who);

/// What every vertex and edge of a level of the stand-in stands for (an index of the same level).
struct Representatives {
  std::vector<int> vertex, edge;
};
/// The first level's: each copy for the input's vertex; each edge for the first edge between the
/// same represented vertices (on the input, edges are vertex pairs).
Representatives initial_representatives(const MeshTopology& t, std::vector<int> vertex);
/// A child level's vertices (primal schemes: vertex points first, then edge points, then face points):
/// a vertex point stands for its representative's, an edge point for its edge's representative's, a
/// face point for itself.
std::vector<int> child_vertex_representatives(const MeshTopology& parent, const Representatives& r,
                                              int child_vertex_count);
/// A child level's edges: the half of an edge stands for the same half of the edge's representative;
/// an edge inside a parent face for itself (two faces may have edges between the same two vertices:
/// they are not welded).
std::vector<int> child_edge_representatives(const MeshTopology& parent, const Representatives& r,
                                            const MeshTopology& child);

/// The mesh with every vertex replaced by its representative: faces renumbered, copies dropped
/// (vertices, tags and face-varying data kept).
Mesh merge_copies(Mesh mesh, const std::vector<int>& representative);

}  // namespace cifs::subdivision::detail
