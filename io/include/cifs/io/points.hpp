// SPDX-License-Identifier: MIT
// cifs — point sets (cifs eval, cifs attractor): rows of coordinates, written a chunk at a time as
// they are computed. Formats (the table of io.cpp, Content::points): json (the points report
// `{"points": [[x, y], …]}`), npy (NumPy 1.0, '<f8', shape (N, dim)), ply (a binary point cloud),
// obj (`v` lines, and an `l` line when the points are a polyline). encode, write and PointsFile are
// one PointsWriter on a string or on a file: a file written in chunks has the bytes of the one
// encoded at once.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>

#include "cifs/files.hpp"
#include "cifs/types.hpp"

namespace cifs::io {

/// How a point set is written besides its rows.
struct PointsStyle {
  bool polyline = false;              // obj: the points in order are a polyline (one `l` line)
  bool closed = false;                // … which returns to its first point
  std::optional<std::uint64_t> seed;  // json: `"seed": S` after the points (the chaos game's)
};

/// A point set in memory (io::encode, io::write).
struct PointSet {
  Points points;  // `count by dim`
  PointsStyle style;
};

namespace detail {
struct PointsFormat;
}

/// One point-set file written in chunks: the constructor writes the header (which names `count`),
/// `write` the next rows, `finish` the end of the file.
class PointsWriter {
 public:
  /// InvalidInput naming the point-set formats for another `format`, and when the format does not hold
  /// `dim` coordinates (obj and ply: 1 to 3).
  PointsWriter(ByteSink& sink, std::string_view format, std::uint64_t count, Eigen::Index dim,
               const PointsStyle& style = {});
  /// The next rows, `n by dim`. InvalidInput for another dimension or beyond `count` rows.
  void write(const Eigen::Ref<const Points>& rows);
  /// Writes the end and hands the last bytes to the sink. InvalidInput unless `count` rows were written.
  void finish();
  std::uint64_t rows_written() const noexcept { return written_; }
  std::uint64_t count() const noexcept { return count_; }
  /// Bytes written so far (handed to the sink and buffered).
  std::uint64_t bytes() const noexcept { return out_.size(); }

 private:
  const detail::PointsFormat* format_;
  std::string_view name_;
  std::uint64_t count_;
  Eigen::Index dim_;
  PointsStyle style_;
  ChunkBuffer out_;
  std::uint64_t written_ = 0;
};

/// The size in bytes of the file of `count` points of `dim` coordinates in `format` when it does not
/// depend on the numbers (npy, ply); nullopt for the text formats.
std::optional<std::uint64_t> points_file_size(std::string_view format, std::uint64_t count, Eigen::Index dim);

/// A point-set file written as its points are computed: the format from the path's extension (InvalidInput
/// "p.txt: a point set is written as .json, .npy, .ply or .obj" before anything is created), through an
/// AtomicFile (a temporary renamed onto the path by `commit`, removed when the file is dropped
/// uncommitted). Memory is one chunk, whatever `count`. The disk space is checked before the header when
/// the size is known (npy, ply), and after the first 4096 rows otherwise, extrapolated from them: IoError
/// "p.npy: the file needs 19.3 GB of disk space, 4.1 GB are free there".
class PointsFile {
 public:
  PointsFile(const std::filesystem::path& path, std::uint64_t count, Eigen::Index dim,
             const PointsStyle& style = {});
  void write(const Eigen::Ref<const Points>& rows);
  /// finish, then rename onto the path.
  void commit();
  std::uint64_t rows_written() const noexcept { return writer_.rows_written(); }

 private:
  AtomicFile file_;
  PointsWriter writer_;
  bool space_checked_ = false;
};

/// Points read back for fitting (cifs fit), by extension: .csv/.txt/.xyz (one point a line, numbers
/// separated by commas or blanks; '#' comments, blank lines and a header line skipped), .npy (2-D,
/// little-endian f8, f4, i8 or i4), .json (`{"points": …}` as cifs eval writes it, a polygon file, or a
/// bare array of points), .obj (the `v` lines in order). InvalidInput naming the file and the line or
/// point otherwise; IoError when it cannot be read.
Points read_points(const std::filesystem::path& path);

}  // namespace cifs::io
