// SPDX-License-Identifier: MIT
// cifs — point sets written in chunks: one writer for every point-set format, on a string or a file.
#include <algorithm>

#include "cifs/errors.hpp"
#include "cifs/io/points.hpp"
#include "points_format.hpp"

namespace cifs::io {
namespace {

/// Rows encoded between two spills: the buffer stays near one chunk whatever the caller's block.
constexpr Eigen::Index kRowsPerPiece = 4096;

}  // namespace

PointsWriter::PointsWriter(ByteSink& sink, std::string_view format, std::uint64_t count, Eigen::Index dim,
                           const PointsStyle& style)
    : format_(&detail::points_format(format, "format")),
      name_(format),
      count_(count),
      dim_(dim),
      style_(style),
      out_(sink) {
  if (dim < 1) throw InvalidInput(std::string(format) + ": points need at least 1 coordinate");
  if (format_->max_dim != 0 && dim > format_->max_dim)
    throw InvalidInput(std::string(format) + ": points have " + std::to_string(dim) + " coordinates, " +
                       std::string(format) + " holds at most " + std::to_string(format_->max_dim));
  format_->header(out_.text, count, dim, style_);
  out_.spill();
}

void PointsWriter::write(const Eigen::Ref<const Points>& rows) {
  if (rows.cols() != dim_)
    throw InvalidInput(std::string(name_) + ": rows of " + std::to_string(rows.cols()) +
                       " coordinates given, the file holds " + std::to_string(dim_));
  if (static_cast<std::uint64_t>(rows.rows()) > count_ - written_)
    throw InvalidInput(std::string(name_) + ": more than the " + std::to_string(count_) +
                       " points of the header");
  detail::check_finite(rows, "the points", written_);
  for (Eigen::Index r = 0; r < rows.rows(); r += kRowsPerPiece) {
    const Eigen::Index n = std::min(kRowsPerPiece, rows.rows() - r);
    format_->rows(out_.text, rows.middleRows(r, n), written_);
    written_ += static_cast<std::uint64_t>(n);
    out_.spill();
  }
}

void PointsWriter::finish() {
  if (written_ != count_)
    throw InvalidInput(std::string(name_) + ": " + std::to_string(written_) +
                       " points written, the header says " + std::to_string(count_));
  format_->footer(out_, count_, style_);
  out_.flush();
}

std::optional<std::uint64_t> points_file_size(std::string_view format, std::uint64_t count,
                                              Eigen::Index dim) {
  const detail::PointsFormat& f = detail::points_format(format, "format");
  if (!f.size) return std::nullopt;
  return f.size(count, dim);
}

namespace {

/// The path, once its extension names a point-set format (before the temporary is created).
const std::filesystem::path& point_set_path(const std::filesystem::path& path) {
  (void)detail::points_format_of(path);
  return path;
}

}  // namespace

PointsFile::PointsFile(const std::filesystem::path& path, std::uint64_t count, Eigen::Index dim,
                       const PointsStyle& style)
    : file_(point_set_path(path)), writer_(file_, detail::points_format_of(path), count, dim, style) {
  const auto size = points_file_size(detail::points_format_of(path), count, dim);
  if (size) check_disk_space(path, *size);
  space_checked_ = size.has_value();
}

void PointsFile::write(const Eigen::Ref<const Points>& rows) {
  writer_.write(rows);
  // Text: the first rows tell the bytes per point; the rest of the file must fit in what is free.
  constexpr std::uint64_t kSample = 4096;
  const std::uint64_t done = writer_.rows_written();
  if (space_checked_ || done < kSample) return;
  space_checked_ = true;
  const double estimate =
      static_cast<double>(writer_.bytes()) / static_cast<double>(done) * static_cast<double>(writer_.count());
  check_disk_space(file_.target(), static_cast<std::uint64_t>(estimate), true, file_.size());
}

void PointsFile::commit() {
  writer_.finish();
  file_.commit();
}

}  // namespace cifs::io
