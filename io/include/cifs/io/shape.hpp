// SPDX-License-Identifier: MIT
// cifs — what a shape file holds (JSON: cifs/io/json.hpp; OBJ free-form: cifs/io/obj.hpp; by
// extension: io::read_shape in cifs/io/io.hpp), and how the shape readers are told what to do with
// what cifs does not represent.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::io {

/// A NURBS curve or surface.
using Shape = std::variant<nurbs::Curve, nurbs::Surface>;

/// Options of the shape readers (parse_obj, parse_shape_json, read_shape, …).
struct ShapeReadOptions {
  /// Trimmed surfaces (OBJ `trim`/`hole`, geomdl `trims`) are refused; with this set, each gives a
  /// warning and its whole, untrimmed surface is read.
  bool ignore_trim = false;
  /// Which shape of a file that holds several to take (0-based, in file order): read_shape and
  /// parse_shape_json refuse such a file without it. The readers that return every shape return
  /// them all, but warn only about this one.
  std::optional<std::size_t> index;
  /// Receives each warning (one line that starts with the file's name). Empty: the warning is
  /// written on stderr as "cifs: warning: …".
  std::function<void(const std::string&)> warn;
};

/// Passes `message`, a warning about the shape of index `shape` in its file, to options.warn, or
/// writes it on stderr when that is empty; nothing when options.index selects another shape.
void warn(const ShapeReadOptions& options, std::size_t shape, const std::string& message);

/// Shape `options.index` of the shapes read from `where`. InvalidInput when the file holds none, when
/// it holds several and no index is given ("m.obj: holds 2 shapes (curves and surfaces): choose one
/// with --index N, N from 0 to 1"), or when the index is out of range.
Shape select_shape(std::vector<Shape> shapes, const ShapeReadOptions& options, std::string_view where);

}  // namespace cifs::io
