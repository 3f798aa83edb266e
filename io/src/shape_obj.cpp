// SPDX-License-Identifier: MIT
// OBJ free-form geometry (placeholder until the OBJ reader lands).
#include "cifs/errors.hpp"
#include "cifs/io/shape.hpp"

namespace cifs::io {

std::vector<Shape> parse_obj(std::string_view, std::string_view where) {
  throw IoError(std::string(where) + ": OBJ reading is not implemented yet");
}

std::string to_obj(const Shape&) {
  throw IoError("OBJ writing is not implemented yet");
}

}  // namespace cifs::io
