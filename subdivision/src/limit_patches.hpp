// SPDX-License-Identifier: MIT
// cifs — internal: which mesh vertices control a face's limit patch, in the order of the matrices of
// catmull_clark_patch and loop_patch (shared by the patches and the surface automaton).
#pragma once

#include <array>
#include <vector>

#include "cifs/topology.hpp"

namespace cifs::subdivision::detail {

/// The 16-point B-spline net of a regular quad, its corner `first` at (0, 0): [i][j] flattened by i,
/// i along first → next corner.
std::array<int, 16> regular_net(const MeshTopology& t, int f, int first);
/// The 2n + 8 control points of a quad whose corner `ev` is extraordinary: the corner's
/// neighbourhood (c, r_j, f_j, sector 0 at the face's next corner), then the 7 outer points
/// (3, 0) … (3, 3) … (0, 3) of the grid where c is (1, 1) and the face [1, 2]².
std::vector<int> patch_support(const MeshTopology& t, int f, int ev);
/// The n + 6 control points of a triangle whose corner `ev` has valence n (Loop): ev's
/// neighbourhood (ev, then its ring counter-clockwise from the face's next corner c1), then the 5
/// points beyond it: the 3rd to 5th neighbours of c1 and the 4th and 5th of the last corner c2,
/// each counted counter-clockwise from ev (c1 and c2 have valence 6). By position, not by vertex:
/// on a small mesh the same vertex may come twice.
std::vector<int> triangle_support(const MeshTopology& t, int f, int ev);

}  // namespace cifs::subdivision::detail
