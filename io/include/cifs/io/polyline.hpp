// SPDX-License-Identifier: MIT
// cifs — polylines (sampled curves, attractors) as OBJ and SVG text.
#pragma once

#include <string>

#include "cifs/types.hpp"

namespace cifs::io {

/// OBJ: one `v` line per point (missing coordinates are 0, more than 3 are refused) and one `l`
/// element through them, closed back to the first point when `closed`.
std::string polyline_obj(const Points& points, bool closed = false);

/// SVG of the x, y coordinates (y up, as in the plane), fitted with a margin into a
/// `width`-pixel-wide picture; a stroke width in pixels. The writer is segments_svg
/// (cifs/io/geometry.hpp) on polyline_segments.
std::string polyline_svg(const Points& points, bool closed = false, int width = 800, double stroke = 1.5);

}  // namespace cifs::io
