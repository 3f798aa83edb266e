// SPDX-License-Identifier: MIT
// cifs — internal: the whole-surface automaton of a Catmull–Clark or Loop mesh with features, from the
// configurations evaluate_limit_surface descends (surface_states.cpp), for surface_automaton
// (limit_surface.cpp).
#pragma once

#include "cifs/automata/automaton.hpp"
#include "cifs/mesh.hpp"
#include "cifs/subdivision/limit.hpp"

namespace cifs::subdivision::detail {

/// Adds every face of `mesh` but its holes to `out` (Catmull–Clark on quads, Loop on triangles, the mesh's
/// tags: boundaries under its rule, sharp and semi-sharp creases, corners, darts, any valence): an initial
/// entry, its net and corners. A face whose patch is a polynomial (proved as evaluate_limit_surface proves
/// it: regular interior, boundary, crease, corner patches) enters `regular` — the uniform bicubic B-spline
/// state, or Loop's 12-point box-spline state — with the net of that polynomial (a fixed linear map of its
/// configuration's rows; under Loop only where the quartic is a box-spline patch, checked); any other face
/// enters a state of its configuration (the face and its corners' one-rings with their tags), whose four
/// quarters, in the automaton's layout (quads: ifs::patch_meshes'; triangles: C0, C1, C2, M), are found by
/// refining it and enter `regular` the same way where they are polynomial. States are named by the class
/// of their corners that are not regular (class, faces: "E5" extraordinary, "B3" boundary, "K2,3" crease
/// with 2 and 3 faces on its sides, "D5" dart, "C1" corner; ":p" where sharp edges part the faces, face 0
/// the p-th counter-clockwise from the first sharp edge; "~s" with sharpness s left to spend), the corner
/// named alone when it is corner 0, all of them "[E5|-|-|B3:1]" otherwise. InvalidInput naming the face for
/// a face that is not a quad (a triangle under Loop). `regular` must have its four children already.
void add_feature_faces(const Mesh& mesh, MeshScheme scheme, automata::StateId regular, SurfaceAutomaton& out);

}  // namespace cifs::subdivision::detail
