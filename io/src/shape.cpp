// SPDX-License-Identifier: MIT
// cifs — what every shape reader shares: warnings and the choice of one shape among several.
#include "cifs/io/shape.hpp"

#include <cstdio>

#include "cifs/errors.hpp"

namespace cifs::io {

void warn(const ShapeReadOptions& options, std::size_t shape, const std::string& message) {
  if (options.index && *options.index != shape) return;
  if (options.warn) {
    options.warn(message);
  } else {
    std::fprintf(stderr, "cifs: warning: %s\n", message.c_str());
  }
}

Shape select_shape(std::vector<Shape> shapes, const ShapeReadOptions& options, std::string_view where) {
  const std::size_t n = shapes.size();
  const std::string file(where);
  if (n == 0) throw InvalidInput(file + ": holds no curve or surface");
  const std::string last = std::to_string(n - 1);
  if (!options.index) {
    if (n == 1) return std::move(shapes.front());
    throw InvalidInput(file + ": holds " + std::to_string(n) +
                       " shapes (curves and surfaces): choose one with --index N, N from 0 to " + last);
  }
  if (*options.index >= n)
    throw InvalidInput(file + ": --index " + std::to_string(*options.index) +
                       " is out of range: the file holds " + std::to_string(n) +
                       (n == 1 ? " shape (index 0)" : " shapes (0 to " + last + ")"));
  return std::move(shapes[*options.index]);
}

}  // namespace cifs::io
