// SPDX-License-Identifier: MIT
// cifs — private to io: a point-set format as the three parts PointsWriter writes (each format in
// the file of its kind: json_points.cpp, npy.cpp, ply.cpp, obj.cpp), found by name or extension in
// the table of io.cpp.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "cifs/io/points.hpp"

namespace cifs::io::detail {

struct PointsFormat {
  std::string_view name;     // as in the table (io.cpp)
  Eigen::Index max_dim = 0;  // largest dimension the format holds; 0: any
  /// The header, for `count` points of `dim` coordinates.
  void (*header)(std::string& out, std::uint64_t count, Eigen::Index dim, const PointsStyle& style);
  /// Rows `first`, `first + 1`, … of the file (first: the index of rows(0) among all the rows).
  void (*rows)(std::string& out, const Eigen::Ref<const Points>& rows, std::uint64_t first);
  /// The end of the file (it may be long: the `l` line of an OBJ polyline is spilled as it grows).
  void (*footer)(ChunkBuffer& out, std::uint64_t count, const PointsStyle& style);
  /// The file's size when it does not depend on the numbers (binary formats); null otherwise.
  std::uint64_t (*size)(std::uint64_t count, Eigen::Index dim) = nullptr;
};

extern const PointsFormat kJsonPoints;  // json_points.cpp
extern const PointsFormat kNpyPoints;   // npy.cpp
extern const PointsFormat kPlyPoints;   // ply.cpp
extern const PointsFormat kObjPoints;   // obj.cpp

/// No writer emits a number that is not finite: JSON has none (`nan` made the file invalid), and in
/// OBJ, PLY, NPY and SVG it passes a wrong answer on. InvalidInput naming `what`, the row (counted from
/// `first`) and the coordinate of the first one: "the points: point 3 coordinate 0 is not a finite
/// number (an overflow or 0/0 in the computation); nothing is written" (io.cpp).
void check_finite(const Eigen::Ref<const Points>& rows, std::string_view what, std::uint64_t first = 0);

/// The table's point-set format called `name`: InvalidInput "`who` 'name': expected json, npy, ply or
/// obj" otherwise (io.cpp).
const PointsFormat& points_format(std::string_view name, std::string_view who);
/// The name of the point-set format of the path's extension: InvalidInput "p.txt: a point set is written
/// as .json, .npy, .ply or .obj" otherwise (io.cpp).
std::string_view points_format_of(const std::filesystem::path& path);

}  // namespace cifs::io::detail
