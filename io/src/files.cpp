// SPDX-License-Identifier: MIT
#include <unistd.h>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/io/shape.hpp"

namespace cifs::io {

std::string read_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path.string() + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(path.string() + ": read error");
  return text.str();
}

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

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  const std::filesystem::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(path.string() + ": cannot write (" + std::strerror(errno) + ")");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw IoError(path.string() + ": write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw IoError(path.string() + ": cannot rename the temporary file into place");
  }
}

}  // namespace cifs::io
