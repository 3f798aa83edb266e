// SPDX-License-Identifier: MIT
// cifs — what a shape file holds (JSON: cifs/io/json.hpp; OBJ free-form: cifs/io/obj.hpp; by
// extension: io::read_shape in cifs/io/io.hpp).
#pragma once

#include <variant>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::io {

/// A NURBS curve or surface.
using Shape = std::variant<nurbs::Curve, nurbs::Surface>;

}  // namespace cifs::io
