// SPDX-License-Identifier: MIT
#include "cifs/io/polyline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "cifs/errors.hpp"

namespace cifs::io {
namespace {

void append_number(std::string& out, double x, const char* format = "%.17g") {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, x);
  out += buffer;
}

}  // namespace

std::string polyline_obj(const Points& points, bool closed) {
  if (points.cols() > 3)
    throw InvalidInput("OBJ: points have " + std::to_string(points.cols()) +
                       " coordinates, OBJ holds at most 3");
  std::string out = "# cifs polyline, " + std::to_string(points.rows()) + " points\n";
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    out += "v";
    for (Eigen::Index k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, k < points.cols() ? points(i, k) : 0.0);
    }
    out += '\n';
  }
  if (points.rows() > 1) {
    out += "l";
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      out += ' ';
      out += std::to_string(i + 1);
    }
    if (closed) out += " 1";
    out += '\n';
  }
  return out;
}

std::string polyline_svg(const Points& points, bool closed, int width, double stroke) {
  if (points.cols() < 2) throw InvalidInput("SVG: points need at least 2 coordinates");
  if (points.rows() == 0) throw InvalidInput("SVG: no points");
  if (width < 16 || width > 100000)
    throw InvalidInput("SVG: width " + std::to_string(width) + " is outside [16, 100000]");
  const Eigen::Vector2d lo = points.leftCols(2).colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = points.leftCols(2).colwise().maxCoeff().transpose();
  const double span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-300});
  const double margin = 0.05 * width, scale = (width - 2 * margin) / span;
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y()) * scale + 2 * margin));
  std::string out =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" +
      std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) +
      "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<" + (closed ? "polygon" : "polyline") +
      " fill=\"none\" stroke=\"#1f4e9c\" stroke-linejoin=\"round\" stroke-width=\"";
  append_number(out, stroke, "%g");
  out += "\" points=\"";
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    if (i) out += ' ';
    append_number(out, margin + (points(i, 0) - lo.x()) * scale, "%.3f");
    out += ',';
    append_number(out, height - margin - (points(i, 1) - lo.y()) * scale, "%.3f");
  }
  out += "\"/>\n</svg>\n";
  return out;
}

}  // namespace cifs::io
