// SPDX-License-Identifier: MIT
// cifs — the attractor of a NURBS curve or surface in one call: its automaton and initial nets built,
// the attractor evaluated, and Cartesian points returned whether the shape is rational or not (the
// shape knows; a caller holding bare rows cannot tell homogeneous (w·x, w) rows from a 3-D curve's).
#pragma once

#include <cstddef>

#include "cifs/mesh.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

/// The curve as the attractor of its knot-doubling automaton at `depth` (≥ 0): Cartesian points in
/// curve order, the start of every depth-`depth` piece (2^depth per segment) plus the end point unless the
/// curve is closed — the curve at the dyadic parameters of each segment. Throws InvalidInput for a
/// negative depth and for more than `max_points` points (before computing them).
Points attractor(const nurbs::Curve& curve, int depth, std::size_t max_points = std::size_t{1} << 27);

/// The surface as the attractor of its tensor-product automaton at `depth` (≥ 0): its watertight quad
/// mesh (surface_mesh's layout) with Cartesian vertices. Throws InvalidInput for a negative depth and
/// for a mesh above `max_bytes` (before computing it).
Mesh attractor(const nurbs::Surface& surface, int depth, std::size_t max_bytes = std::size_t{1} << 30);

}  // namespace cifs::ifs
