// SPDX-License-Identifier: MIT
// cifs — internal: the tangent plane of one sector of the faces around a vertex, from the spectrum of a
// stationary step restricted to the sector. One implementation for limit_stencils (limit.cpp: the
// masks per sector) and evaluate_limit_surface (surface_states.cpp: the partials at a corner).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

#include "cifs/mesh.hpp"
#include "cifs/topology.hpp"

namespace cifs::subdivision::detail {

/// Faces around vertex 0 of a local mesh between two sharp or boundary edges (`bounded`), or all the
/// faces of an interior vertex with at most one sharp edge (smooth, a dart): positions in
/// vertex_faces(t, 0), counter-clockwise.
struct Sector {
  std::vector<int> faces;
  bool bounded = false;
};
/// The sectors around vertex 0 of `t`, cut at its boundary edges and at the edges `tags` make sharp
/// (creases with sharpness > 0 at vertex 0), in the order of vertex_faces(t, 0).
std::vector<Sector> sectors_around(const MeshTopology& t, const MeshTags& tags);

/// A sector's tangent plane from the stationary step S (square: the local mesh's vertices one level
/// down, in the same numbering, = S · its vertices). The sector's rows of S read nothing outside it
/// (std::logic_error otherwise); on that block: 1 simple, then a real pair λ1 ≥ λ2 above the rest, with
/// eigenvectors (no Jordan block); where the sector is bounded, the right eigenvectors must not vanish at
/// both bounding edges (else the curves there leave the pair's plane: not C¹); the sector's faces must
/// span the plane (their edges' parts in it not all parallel); a sector of more than 128 faces is not
/// run. `refused` says why otherwise, and then nothing else is set. A face alone between two sharp or
/// boundary edges is decided the same way: at a corner its two curves carry λ1 = λ2 = ½; at a smooth
/// corner Catmull–Clark's face point ties the curve's curvature at ¼ (no pair above the rest: refused),
/// while Loop's triangle has no inner vertex and the vertices beyond it enter at ⅛: the curve's tangent
/// (½) and curvature (¼) span the plane the surface is tangent to (test_mesh_limit_classes.cpp).
/// The left eigenvectors l_i (rows of `left`, 0 outside the sector) and right r_i (columns of `right`)
/// are biorthonormal (l_i · r_j = δ_ij) and oriented like the faces: l_1 · x × l_2 · x points to the side
/// the sector's faces are counter-clockwise from.
struct SectorPlane {
  std::string refused;
  std::array<double, 2> lambda{};
  Eigen::MatrixXd left;   // 2 × vertices
  Eigen::MatrixXd right;  // vertices × 2
};
SectorPlane sector_plane(const Eigen::MatrixXd& S, const MeshTopology& t, const Sector& sector);

}  // namespace cifs::subdivision::detail
