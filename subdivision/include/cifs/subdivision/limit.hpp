// SPDX-License-Identifier: MIT
// cifs — limit positions and normals of a subdivision surface's vertices, from the left
// eigenvectors of the local subdivision matrices (docs/subdivision-surfaces.md, "Limit points").
//
// At a vertex of valence n the invariant neighbourhood x (mesh_analysis.hpp's numbering) evolves
// as x_{k+1} = S_n x_k. A left eigenvector l of S_n for 1 gives l·x_{k+1} = l·x_k: normalised to sum
// 1 it is the limit position's stencil, exact at any level. Two left eigenvectors for the
// subdominant λ1 give l·x_{k+1} = λ1 l·x_k: each is the component of the neighbourhood along one
// subdominant right eigenvector, that is, a vector of the tangent plane — their cross product is
// the normal. Computed once per valence and replayed on any topology, like the refinement's weights.
#pragma once

#include "cifs/mesh.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/topology.hpp"

namespace cifs::subdivision {

/// Per vertex of a topology: `position` (rows sum to 1) and two tangent directions `tangent_u`,
/// `tangent_v` (rows sum to 0; empty rows at boundary and isolated vertices), ordered so that
/// tangent_u × tangent_v points to the side the faces are counter-clockwise from. Their lengths
/// are not derivatives of any parametrisation: use them for the tangent plane and the normal.
struct LimitStencils {
  Stencils position;
  Stencils tangent_u;
  Stencils tangent_v;
};

/// The stencils of every vertex of `topology`, a mesh produced (or to be refined) by `scheme`.
/// Catmull–Clark needs quads around each vertex (true after one level). Butterfly interpolates:
/// every vertex is its own limit; its tangents are not built (next to an extraordinary vertex the
/// invariant neighbourhood of a regular vertex is not the regular one). Boundary vertices are Catmull–Clark's and Loop's only (the boundary curve's limit
/// (1, 4, 1)/6, or the corner itself under `edge_and_corner` at valence 2); Doo–Sabin's limit
/// points belong to faces and are not built. InvalidInput naming the vertex otherwise, and for
/// valences above 16 (boundary: 8).
LimitStencils limit_stencils(const MeshTopology& topology, MeshScheme scheme,
                             BoundaryRule boundary = BoundaryRule::edge_only);

struct LimitOptions {
  BoundaryRule boundary = BoundaryRule::edge_only;
  bool normals = false;  // unit normals; refused on a mesh with a boundary (not built there)
  double max_bytes = 4.0 * (1ull << 30);
};

/// The mesh after `levels` steps with every vertex moved to its limit position (and `normals` set
/// when asked): a sampling of the limit surface itself, exact at the vertices.
Mesh limit_mesh(const Mesh& mesh, MeshScheme scheme, int levels, const LimitOptions& options = {});

}  // namespace cifs::subdivision
