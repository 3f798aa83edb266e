// SPDX-License-Identifier: MIT
#include "cifs/files.hpp"
#include "cifs/errors.hpp"
#include "cifs/io/shape.hpp"

namespace cifs::io {

Shape read_shape(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  const std::string where = path.string();
  if (path.extension() == ".obj") {
    std::vector<Shape> shapes = parse_obj(text, where);
    if (shapes.size() != 1)
      throw InvalidInput(where + ": holds " + std::to_string(shapes.size()) +
                         " curves and surfaces, expected exactly one");
    return std::move(shapes.front());
  }
  return parse_shape_json(text, where);
}

}  // namespace cifs::io
