// SPDX-License-Identifier: MIT
// cifs — control polygon files `{"polygon": {"points": [[x, y], ...], "closed": true}}`
// (docs/formats.md): the input of the subdivision schemes and of uniform B-splines.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "cifs/types.hpp"

namespace cifs::io {

struct Polygon {
  Points points;  // `n by dim`, n ≥ 1, 1 ≤ dim ≤ 16
  bool closed = false;
};

/// Errors name `where` and the JSON path (IoError for syntax, InvalidInput for content).
Polygon parse_polygon_json(std::string_view text, std::string_view where);
Polygon read_polygon(const std::filesystem::path& path);
/// One point per line, numbers with round-trip precision; reads back bit for bit.
std::string to_json(const Polygon& polygon);

}  // namespace cifs::io
