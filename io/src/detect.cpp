// SPDX-License-Identifier: MIT
// io::detect: what a file holds, for the commands that take several kinds of file.
#include <nlohmann/json.hpp>
#include <string_view>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"

namespace cifs::io {
namespace {

/// An OBJ is a polygon mesh when it has faces and no free-form geometry.
bool obj_mesh(std::string_view text) {
  bool faces = false;
  while (!text.empty()) {
    const std::size_t end = std::min(text.find('\n'), text.size());
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string_view::npos) continue;
    const std::string_view word = line.substr(start, line.find_first_of(" \t\r", start) - start);
    if (word == "cstype" || word == "curv" || word == "surf") return false;
    faces = faces || word == "f";
  }
  return faces;
}

}  // namespace

Content detect(const std::filesystem::path& path) {
  const std::string extension = extension_of(path);
  if (extension == ".ply" || extension == ".stl" || extension == ".off" || extension == ".vtp")
    return Content::mesh;
  if (extension != ".obj" && extension != ".json") return Content::shape;
  const std::string text = read_file(path);
  if (extension == ".obj") return obj_mesh(text) ? Content::mesh : Content::shape;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object()) return Content::shape;  // the shape reader names what is wrong
  if (j.contains("polygon")) return Content::polygon;
  if (j.contains("bcifs")) return Content::bcifs;
  if (j.contains("curve") || j.contains("surface") || j.contains("volume") ||
      (j.size() == 1 && j.contains("shape")))
    return Content::shape;
  return Content::experiment;
}

}  // namespace cifs::io
