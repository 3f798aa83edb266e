// SPDX-License-Identifier: MIT
// cifs — classic planar affine IFS: the maps and the named systems (Barnsley's fern, Sierpinski's
// triangle, Koch's curve) and their registry by name. Standard headers only, so that render/ can include it;
// their CIFS automata are in affine_cifs.hpp.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace cifs::ifs {

/// w(x, y) = (a·x + b·y + e, c·x + d·y + f), chosen with weight `probability` (Barnsley's notation).
struct AffineMap {
  double a = 0, b = 0, c = 0, d = 0, e = 0, f = 0;
  double probability = 1;
};

/// Barnsley's fern (Fractals Everywhere, 1988, table III.3): stem, successively smaller leaflets,
/// largest left and right leaflets, with probabilities 0.01, 0.85, 0.07, 0.07.
std::vector<AffineMap> barnsley_fern();
/// Sierpinski's triangle on (0, 0), (1, 0), (½, √3/2): three maps of ratio ½, probabilities ⅓.
std::vector<AffineMap> sierpinski_triangle();
/// Koch's curve from (0, 0) to (1, 0): four maps of ratio ⅓, the middle two rotated by +60° and
/// −60°, probabilities ¼ (the natural measure, since all ratios are equal).
std::vector<AffineMap> koch_curve();

/// The names of the systems above, in that order: "fern", "sierpinski", "koch" (an experiment
/// file's `"ifs": NAME`, listed in messages). The one registry: a new named system goes here.
const std::vector<std::string>& ifs_names();
/// The maps of a named system (one of ifs_names()). Throws InvalidInput for another name,
/// listing the names.
std::vector<AffineMap> named_ifs(std::string_view name);

}  // namespace cifs::ifs
