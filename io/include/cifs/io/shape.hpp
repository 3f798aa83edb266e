// SPDX-License-Identifier: MIT
// cifs — shape files: the JSON format of docs/formats.md and OBJ free-form geometry.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::io {

/// What a shape file holds.
using Shape = std::variant<nurbs::Curve, nurbs::Surface>;

/// JSON: `{"curve": {...}}` or `{"surface": {...}}` (docs/formats.md). `where` names the source
/// in error messages ("shape.json"); errors are IoError (syntax) or InvalidInput (content), with
/// the JSON path of the offending value, e.g. "shape.json: curve.knots[3]: ...".
Shape parse_shape_json(std::string_view text, std::string_view where);
std::string to_json(const Shape& shape);

/// OBJ free-form geometry: `cstype [rat] bspline`, `deg`, `curv`/`surf`, `parm u|v`, `end`,
/// with `v x y z [w]` vertices. Every curve and surface of the file, in order.
std::vector<Shape> parse_obj(std::string_view text, std::string_view where);
std::string to_obj(const Shape& shape);

/// Reads a shape file: `.obj` as OBJ (it must hold exactly one shape), anything else as JSON.
Shape read_shape(const std::filesystem::path& path);

}  // namespace cifs::io
