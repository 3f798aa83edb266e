// SPDX-License-Identifier: MIT
// cifs — internal: walking the local mesh around an extraordinary vertex (or Doo–Sabin face) and
// matching it with its refinement; shared by the local matrices and the characteristic maps.
#pragma once

#include <utility>
#include <vector>

#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/topology.hpp"

namespace cifs::subdivision::detail {

int wrap(int j, int n);
int edge_between(const MeshTopology& t, int a, int b);
int corner_index(const MeshTopology& t, int f, int v);
int corner(const MeshTopology& t, int f, int i);
int face_across(const MeshTopology& t, int e, int f);

/// The neighbourhood of vertex `centre` (Doo–Sabin: face) in mesh_analysis.hpp's numbering, sector
/// 0 at `start` (a neighbour; Doo–Sabin: a corner; ignored on the boundary, where edge 0 starts).
std::vector<int> neighbourhood(const MeshTopology& t, MeshScheme scheme, int centre, int start,
                               bool boundary);
/// The same into `out` (cleared first), for walks over every vertex of a mesh.
void neighbourhood(const MeshTopology& t, MeshScheme scheme, int centre, int start, bool boundary,
                   std::vector<int>& out);

/// One √3 step at a boundary vertex of `faces` faces: the rows of its child's ring (c first, then
/// the ring from the boundary edge r_0 side) on c, r_0 … r_faces; `trisect` for the odd steps (1, 3,
/// …, faces ≥ 2), which trisect the boundary (mesh_analysis.cpp's sqrt3_boundary_rows). Two steps from an
/// even level are local_matrix(sqrt3, faces + 1, {.boundary = true}); limit masks at an odd level go
/// through the trisecting step first.
LongMatrix sqrt3_boundary_step(int faces, bool trisect);

/// Butterfly's edge point of `edge` (mesh.cpp's rule, the one its step uses) appended to `out` as
/// (vertex, weight) pairs; a vertex may come more than once (its weights add up).
void butterfly_edge_stencil(const MeshTopology& t, int edge, std::vector<std::pair<int, double>>& out);

/// Weight of `column` in row `row` of the stencils.
double weight(const Stencils& s, int row, int column);

/// `local_mesh` refined by one invariance step (√3: two levels), with the centre and sector 0 found
/// on both sides: on the old side by construction (vertex or face 0, sector 0 at vertex 1 or the
/// face's first corner), on the new side by the weights (the child centre weighs most on the
/// centre, the new sector 0 on the old one's start).
struct LocalRefinement {
  Mesh mesh;
  MeshRefinement refinement;
  Stencils stencils;  // level 0 → level `steps`
  int centre = 0, start = 0;
  int child_centre = 0, child_start = 0;
};
LocalRefinement refine_local(MeshScheme scheme, int valence, const LocalOptions& options, int rings);

/// The vertices of an interior region in an order that any orientation-preserving isomorphism
/// keeping the centre and sector 0 keeps: breadth first from the centre (Doo–Sabin: the face's
/// corners from `start`), each vertex's neighbours counter-clockwise from the one it was reached
/// from; vertices up to `depth` edges away. Throws std::logic_error if a vertex closer than that
/// is on the mesh's boundary (the local mesh is too small).
std::vector<int> canonical_order(const MeshTopology& t, MeshScheme scheme, int centre, int start, int depth);

}  // namespace cifs::subdivision::detail
