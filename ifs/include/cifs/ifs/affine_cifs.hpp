// SPDX-License-Identifier: MIT
// cifs — a planar affine IFS as a one-state CIFS automaton in barycentric form on a control
// triangle.
#pragma once

#include <Eigen/Core>
#include <span>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

/// The image of a point (a row of 2 values).
Point apply(const AffineMap& map, const Point& p);

/// Barycentric form of `map` on the control triangle `triangle` (`3 by 2`, non-degenerate): the
/// `3 by 3` matrix M, rows summing to 1, with M·triangle = the images of the triangle's corners,
/// i.e. M = [w(T) 1]·[T 1]⁻¹. Throws InvalidInput for a triangle that is not 3 by 2, not finite or
/// degenerate (|det [T 1]| ≤ 1e-12·diam(T)²), or a map with a non-finite coefficient.
Eigen::MatrixXd barycentric_matrix(const AffineMap& map, const Points& triangle);

/// One state of 3 points, one transition "w<i>" per map (barycentric_matrix), one initial entry
/// whose net is `triangle`: the CIFS whose attractor under that net is the IFS attractor (for any
/// triangle: the matrices depend on it, the attractor does not). Probabilities are not kept (the
/// chaos game of ifs draws children uniformly). Throws as barycentric_matrix, or for no map.
automata::Automaton affine_automaton(std::span<const AffineMap> maps, const Points& triangle);

}  // namespace cifs::ifs
