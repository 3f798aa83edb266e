// SPDX-License-Identifier: MIT
// cifs CLI — polygon meshes: `cifs subdivide` and `cifs info` on an OBJ/PLY mesh.
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/io/io.hpp"
#include "cifs/render/progress.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/topology.hpp"
#include "commands.hpp"

namespace cifs::cli {
namespace {

using nlohmann::json;

/// Refused before the work: the output must be a mesh format the table writes. Its name.
std::string mesh_output_format(const std::filesystem::path& output) {
  std::string known;
  for (const io::Format& f : io::formats(io::Content::mesh)) {
    if (!f.write) continue;
    if (output.extension() == f.extension) return std::string(f.name);
    known += (known.empty() ? "" : " or ") + std::string(f.extension);
  }
  throw InvalidInput("-o " + output.string() + ": expected a " + known + " file name");
}

}  // namespace

std::string mesh_info(const std::filesystem::path& path) {
  const MeshTopology t = build_topology(io::read_mesh(path), path.string());
  const MeshStatistics s = mesh_statistics(t);
  std::map<std::string, std::size_t> sizes, valences;  // JSON keys
  for (const auto& [corners, faces] : s.faces_by_corners) sizes[std::to_string(corners)] = faces;
  for (const auto& [valence, vertices] : s.valences) valences[std::to_string(valence)] = vertices;
  json out = {{"type", "mesh"},
              {"vertices", t.vertex_count},
              {"edges", t.edges.size()},
              {"faces", face_count(t)},
              {"faces_by_corners", sizes},
              {"valences", valences},
              {"isolated_vertices", s.isolated_vertices},
              {"boundary_loops", s.boundary_loops},
              {"closed", s.boundary_loops == 0},
              {"components", s.components},
              {"euler_characteristic", s.euler_characteristic}};
  if (s.genus) out["genus"] = *s.genus;
  return out.dump(1) + "\n";
}

namespace {

/// The frame of the commands that make a mesh from a mesh: the output is checked (not the input mesh, a
/// folder, a device…) and its temporary made before the work; errors of the work name the input; the
/// result goes out a chunk at a time (its text is never whole in memory), or to standard output as OBJ.
std::string mesh_to_mesh(const std::filesystem::path& input, const std::filesystem::path& output_path,
                         const std::function<Mesh(Mesh)>& make,
                         const std::function<std::string(const Mesh&)>& summary) {
  const std::string format = output_path.empty() ? "obj" : mesh_output_format(output_path);
  std::optional<AtomicFile> output;
  if (!output_path.empty()) output.emplace(output_path, OutputOptions{.inputs = {input}});
  Mesh mesh = io::read_mesh(input);
  Mesh result;
  try {
    result = make(std::move(mesh));
  } catch (const InvalidInput& e) {
    throw InvalidInput(input.string() + ": " + e.what());
  }
  if (!output) return io::encode(result, format);
  io::encode(result, format, *output);
  output->commit();
  return "wrote " + output_path.string() + ": " + summary(result) + "\n";
}

/// The file's options replaced by the flags given ("" keeps the file's), a wrong name reported with
/// its flag.
TagOverrides tag_overrides(const std::string& boundary, const std::string& crease_method,
                           const std::string& triangles, const std::string& fvar_interpolation) {
  const auto parse = [](const char* flag, const std::string& value, auto named) {
    using Option = decltype(named(value));
    if (value.empty()) return std::optional<Option>();
    try {
      return std::optional<Option>(named(value));
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string(flag) + " " + value + ": " + e.what());
    }
  };
  return {.boundary = parse("--boundary", boundary, named_boundary_rule),
          .crease_method = parse("--crease-method", crease_method, named_crease_method),
          .triangles = parse("--triangles", triangles, named_triangle_rule),
          .face_varying = parse("--fvar-interpolation", fvar_interpolation, named_face_varying_rule)};
}

}  // namespace

std::string subdivide(const SubdivideOptions& o) {
  const subdivision::MeshScheme scheme = subdivision::named_mesh_scheme(o.scheme);
  render::ProgressBar bar("subdivide", o.quiet);
  const subdivision::MeshOptions options{
      .progress = [&bar](std::uint64_t done, std::uint64_t total) { bar(done, total); }};
  const TagOverrides overrides =
      tag_overrides(o.boundary, o.crease_method, o.triangles, o.fvar_interpolation);
  return mesh_to_mesh(
      o.mesh, o.output,
      [&](Mesh mesh) {
        apply(overrides, mesh.tags);
        return o.factored ? subdivision::factored_subdivide(mesh, scheme, o.levels, options)
                          : subdivision::subdivide(mesh, scheme, o.levels, options);
      },
      [&](const Mesh& refined) {
        return std::to_string(refined.vertices.rows()) + " vertices, " + std::to_string(face_count(refined)) +
               " faces (" + o.scheme + (o.factored ? " factored" : "") + ", " + std::to_string(o.levels) +
               " levels)";
      });
}

std::string limit(const LimitCommandOptions& o) {
  const subdivision::MeshScheme scheme = subdivision::named_mesh_scheme(o.scheme);
  const subdivision::LimitOptions options{.normals = o.normals};
  const TagOverrides overrides = tag_overrides(o.boundary, "", "", "");
  return mesh_to_mesh(
      o.mesh, o.output,
      [&](Mesh mesh) {
        apply(overrides, mesh.tags);
        return subdivision::limit_mesh(mesh, scheme, o.levels, options);
      },
      [&](const Mesh& surface) {
        return std::to_string(surface.vertices.rows()) + " limit points" +
               (o.normals ? " with normals, " : ", ") + std::to_string(face_count(surface)) + " faces (" +
               o.scheme + ", " + std::to_string(o.levels) + " levels)";
      });
}

}  // namespace cifs::cli
