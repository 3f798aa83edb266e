// SPDX-License-Identifier: MIT
// cifs — control polygons, the input of the subdivision schemes and of uniform B-splines (polygon
// files: cifs/io/json.hpp; written as OBJ and SVG polylines too: io::encode in cifs/io/io.hpp).
#pragma once

#include "cifs/types.hpp"

namespace cifs::io {

struct Polygon {
  Points points;  // `n by dim`, n ≥ 1, 1 ≤ dim ≤ 16
  bool closed = false;
};

}  // namespace cifs::io
