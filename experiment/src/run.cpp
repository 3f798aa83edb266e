// SPDX-License-Identifier: MIT
// cifs — running an experiment: its source built into a scene (sources.cpp), framed, drawn, written.
#include "cifs/experiment/run.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/ifs/affine_cifs.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/ifs/bcifs_surface.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/ifs/junction.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/svg.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/render/camera.hpp"
#include "cifs/render/chaos_density.hpp"
#include "cifs/render/image.hpp"
#include "cifs/render/point_ifs.hpp"
#include "cifs/render/preview.hpp"
#include "cifs/render/progress.hpp"
#include "cifs/render/raster.hpp"
#include "cifs/subdivision/ifs.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/topology.hpp"
#include "scene.hpp"

namespace cifs::experiment {
namespace {

using detail::cartesian_if;
using detail::drawable;
using detail::Scene;
using Mode = io::EvaluationSpec::Mode;

/// Draws a control mesh over its subdivision surface: a line is hidden only where the surface is
/// more than `bias` in front of it. Interpolating schemes (Butterfly) and the shrinking ones leave
/// the control edges just inside or just outside the surface, where an exact depth test would cut
/// them into dashes; the far side of the surface still hides the far side of the mesh.
void render_control_mesh(render::Image& image, const render::Camera& camera, const Segments& control,
                         const render::CurveStyle& style, double bias) {
  std::vector<float>& Z = image.channels.at("Z");
  const std::vector<float> surface = Z;
  for (float& z : Z) z += static_cast<float>(bias);
  render::render_segments(image, camera, control, style);
  // Z keeps the nearest surface where it is nearer than the line drawn over it.
  for (std::size_t i = 0; i < Z.size(); ++i) Z[i] = std::min(Z[i], surface[i]);
}

render::Camera make_camera(const io::CameraSpec& spec, const io::RenderSettings& r, const Points& extent) {
  render::FramingOptions f;
  f.width = static_cast<std::size_t>(r.width);
  f.height = static_cast<std::size_t>(r.height);
  f.margin = spec.margin;
  f.perspective = spec.projection != io::CameraSpec::Projection::orthographic;
  f.fov_y = spec.fov_degrees;
  f.up = Eigen::Vector3d(spec.up[0], spec.up[1], spec.up[2]);
  // A given eye keeps the sphere's framing: its target is the centre of the bounds (docs/experiments.md).
  f.tight = !spec.eye;
  if (spec.eye) {
    const Eigen::Vector3d target =
        spec.target ? Eigen::Vector3d((*spec.target)[0], (*spec.target)[1], (*spec.target)[2])
                    : render::frame(extent, f).target;
    f.view_direction =
        Eigen::Vector3d(Eigen::Vector3d((*spec.eye)[0], (*spec.eye)[1], (*spec.eye)[2]) - target);
    if (!f.view_direction->allFinite())
      throw InvalidInput(
          "camera.eye: the eye is farther from the target than a double holds (coordinates up to " +
          number_text(
              std::max(Eigen::Vector3d((*spec.eye)[0], (*spec.eye)[1], (*spec.eye)[2]).cwiseAbs().maxCoeff(),
                       target.cwiseAbs().maxCoeff()),
              6) +
          "); move it closer or scale the scene down");
  }
  render::Camera camera = render::frame(extent, f);
  if (spec.eye) {
    camera.eye = Eigen::Vector3d((*spec.eye)[0], (*spec.eye)[1], (*spec.eye)[2]);
    if (spec.target) camera.target = Eigen::Vector3d((*spec.target)[0], (*spec.target)[1], (*spec.target)[2]);
    camera.up = f.up;
  }
  if (spec.projection == io::CameraSpec::Projection::perspective)
    camera.projection = render::Projection::perspective;
  return camera;
}

/// Planar affine IFS: its chaos game (with the maps' probabilities) or its depth-K Hutchinson
/// measure, binned on the pixels of an orthographic top view.
render::DensityLayer render_classic(const render::Camera& camera, const Scene& scene, const io::Experiment& e,
                                    const RunOptions& o, unsigned threads) {
  const render::ViewTransform view = render::view_transform(camera);
  if (view.perspective || std::abs(view.forward.z()) < 1 - 1e-12)
    throw InvalidInput("camera: a classic IFS is drawn in an orthographic top view");
  // The window of the plane that the pixels cover (x right, y up in the top view).
  const double half_w = 0.5 * static_cast<double>(camera.width) / view.scale;
  const double half_h = 0.5 * static_cast<double>(camera.height) / view.scale;
  const Eigen::Vector3d centre = view.eye;
  render::Bounds bounds{centre.x() - half_w, centre.x() + half_w, centre.y() - half_h, centre.y() + half_h};
  std::vector<double> density;
  if (e.evaluation.mode == Mode::chaos) {
    render::ProgressBar bar("chaos game", o.quiet);
    render::ChaosHistogramOptions co;
    co.samples = e.evaluation.samples;
    co.seed = e.evaluation.seed;
    co.threads = threads;
    co.width = camera.width;
    co.height = camera.height;
    co.bounds = bounds;
    co.progress = std::ref(bar);
    co.part = o.part;
    const render::Histogram h = render::chaos_game_histogram(scene.maps, co);
    density.assign(h.counts.begin(), h.counts.end());
  } else {
    if (e.evaluation.mode == Mode::tolerance)
      throw InvalidInput(
          "evaluation.relative_piece_size: a classic IFS is evaluated to a depth or by the chaos game");
    density = render::hutchinson_measure(scene.maps, static_cast<unsigned>(e.evaluation.depth), camera.width,
                                         camera.height, bounds);
  }
  const float depth = static_cast<float>(view.project(Eigen::Vector3d(centre.x(), centre.y(), 0)).depth);
  render::DensityLayer layer = render::empty_density_layer(density.size());
  for (std::size_t i = 0; i < density.size(); ++i) {
    if (density[i] <= 0) continue;
    layer.density[i] = density[i];
    layer.depth[i] = depth;
    layer.state[i] = 0;
  }
  return layer;
}

/// Segments in the colour of their state (`colors[state]`, junctions: each side its own), or all in
/// the style's colour when `colors` is empty.
void render_coloured_segments(render::Image& image, const render::Camera& camera, const Segments& segments,
                              render::CurveStyle style, const std::vector<render::Rgb>& colors) {
  if (colors.empty() || segments.states.size() != segments.segments.size())
    return render::render_segments(image, camera, segments, style);
  std::map<render::Rgb, Segments> parts;
  for (std::size_t i = 0; i < segments.segments.size(); ++i) {
    Segments& part = parts[colors.at(segments.states[i])];
    if (part.vertices.size() == 0) part.vertices = segments.vertices;  // shared: segments index them
    part.segments.push_back(segments.segments[i]);
    part.states.push_back(segments.states[i]);
  }
  for (const auto& [color, part] : parts) {
    style.color = color;
    render::render_segments(image, camera, part, style);
  }
}

/// The run's outputs, checked and reserved (their temporaries made) before any work: two names for
/// one file, an input of the experiment, a folder, a device, a missing folder of an image path given
/// outside the experiment (RunOptions::exr, png: only the experiment's own output folder is
/// created) and an unwritable folder are refused here (cifs::AtomicFiles).
struct Outputs {
  AtomicFiles files;
  AtomicFile *exr = nullptr, *png = nullptr;
  std::map<std::string, AtomicFile*> geometry, automaton;
};

void reserve_outputs(Outputs& out, const io::Experiment& e, const RunOptions& o,
                     const std::filesystem::path& exr, const std::filesystem::path& png) {
  const OutputOptions given{.inputs = e.inputs, .create_folders = false};
  const OutputOptions own{.inputs = e.inputs, .create_folders = true};
  if (!exr.empty())
    out.exr =
        &out.files.add(exr, o.exr.empty() ? "outputs.exr" : "the EXR path", o.exr.empty() ? own : given);
  if (!png.empty())
    out.png =
        &out.files.add(png, o.png.empty() ? "outputs.png" : "the PNG path", o.png.empty() ? own : given);
  for (const auto& [format, path] : e.outputs.geometry)
    out.geometry[format] = &out.files.add(o.out_dir / path, "outputs." + format, own);
  for (const auto& [format, path] : e.outputs.automaton)
    out.automaton[format] = &out.files.add(o.out_dir / path, "outputs.automaton_" + format, own);
}

/// What the evaluation gives to export, known from the file before any work: a mesh, a segment set, or
/// nothing (a chaos game or a classic IFS gives a density).
std::optional<io::Content> geometry_content(const io::Experiment& e) {
  if (e.mesh) return io::Content::mesh;
  if (e.ifs || e.evaluation.mode == Mode::chaos) return std::nullopt;
  const auto surface = [](const std::optional<io::Shape>& shape) {
    return shape && std::holds_alternative<nurbs::Surface>(*shape);
  };
  if (e.junction) {
    const io::JunctionSideSpec& a = e.junction->a;  // both sides are curves or both surfaces (ifs::join)
    return (a.scheme ? a.columns > 0 : surface(a.shape)) ? io::Content::mesh : io::Content::segments;
  }
  return surface(e.shape) ? io::Content::mesh : io::Content::segments;  // BC-IFS files draw curves
}

/// Refuses an image path whose extension is not its format's (`-o foo.png` would be OpenEXR bytes in a
/// .png file); after the paths themselves are checked (reserve_outputs), before any work.
void check_image_extensions(const io::Experiment& e, const RunOptions& o) {
  const auto image = [](const std::filesystem::path& path, const std::string& label, const char* extension,
                        const char* what) {
    if (!path.empty() && extension_of(path) != extension)
      throw InvalidInput(label + ": " + path.string() + ": the " + what + ", written as " + extension);
  };
  image(o.exr.empty() ? e.outputs.exr : o.exr, o.exr.empty() ? "outputs.exr" : "the EXR path", ".exr",
        "image is OpenEXR");
  image(o.png.empty() ? e.outputs.png : o.png, o.png.empty() ? "outputs.png" : "the PNG path", ".png",
        "preview is PNG");
}

/// Refuses, before any work, a geometry output that the evaluation cannot give.
void check_geometry_outputs(const io::Experiment& e) {
  if (e.outputs.geometry.empty()) return;
  const std::optional<io::Content> content = geometry_content(e);
  if (!content)
    throw InvalidInput("outputs." + e.outputs.geometry.begin()->first + ": a " +
                       (e.ifs ? "classic IFS" : "chaos game") + " gives a density, no geometry to export");
  // The parser accepts the formats of meshes and of segment sets: say which one this source takes.
  const std::vector<io::Format> formats = io::formats(*content);
  for (const auto& output : e.outputs.geometry) {
    const std::string& format = output.first;
    const auto writes = [&](const io::Format& f) { return f.write && f.name == format; };
    if (std::any_of(formats.begin(), formats.end(), writes)) continue;
    std::string upper = format, ours;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::vector<std::string_view> names;
    for (const io::Format& f : formats)
      if (f.write) names.push_back(f.name);
    for (std::size_t i = 0; i < names.size(); ++i)
      ours += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + std::string(names[i]);
    const bool mesh = content == io::Content::mesh;
    std::string message = "outputs.";
    message += format + ": ";
    message += upper + " is for ";
    message += mesh ? "curves" : "surfaces";
    message += "; use " + ours + " for ";
    message += mesh ? "surfaces" : "curves";
    throw InvalidInput(message);
  }
}

/// The geometry and automaton files, in the order of the format table (io::formats), encoded a chunk
/// at a time into their temporaries (no file's bytes are ever whole in memory); returns their paths.
/// check_geometry_outputs has refused what the scene cannot give.
std::vector<std::filesystem::path> write_files(const Scene& scene, const io::Experiment& e,
                                               Outputs& outputs) {
  std::vector<std::filesystem::path> geometry;
  if (!e.outputs.geometry.empty()) {
    if (scene.mesh.has_value() != (geometry_content(e) == io::Content::mesh) ||
        scene.curves.has_value() != (geometry_content(e) == io::Content::segments))
      throw std::logic_error("write_files: the scene is not what geometry_content foretold");
    const io::Content content = scene.mesh ? io::Content::mesh : io::Content::segments;
    for (const io::Format& f : io::formats(content))
      if (const auto it = e.outputs.geometry.find(std::string(f.name)); it != e.outputs.geometry.end()) {
        AtomicFile& out = *outputs.geometry.at(it->first);
        if (scene.mesh)
          io::encode(*scene.mesh, f.name, out);
        else
          io::encode(*scene.curves, f.name, out);
        geometry.push_back(out.target());
      }
  }
  for (const io::Format& f : io::formats(io::Content::automaton))
    if (const auto it = e.outputs.automaton.find(std::string(f.name)); it != e.outputs.automaton.end()) {
      AtomicFile& out = *outputs.automaton.at(it->first);
      io::encode(scene.knots ? *scene.knots : nurbs::without_knots(scene.automaton), f.name, out);
      geometry.push_back(out.target());
    }

  return geometry;
}

/// One line of facts, then one per file written.
std::string summary(const io::Experiment& e, const std::string& kind, const Scene& scene,
                    const RunReport& report) {
  std::string out = e.name + ": " + kind +
                    (e.mesh ? ", " + std::to_string(scene.depth) + " levels, " +
                                  std::to_string(face_count(*scene.mesh)) + " faces"
                     : e.evaluation.mode == Mode::chaos
                         ? ", chaos game of " + std::to_string(e.evaluation.samples) + " samples"
                         : ", depth " + std::to_string(scene.depth));
  if (e.junction) out += ", " + scene.junction;
  if (e.perturbation || e.junction)
    out += ", " + std::to_string(report.free_coefficients) + " free coefficients, residual " +
           number_text(report.residual, 6);
  out += "\n";
  for (const auto& p : report.written) out += "  wrote " + p.string() + "\n";
  return out;
}

/// The PNG preview: shaded colours over the background, or a density's log tone mapping with the
/// file's palette (default: from the background to its colour when it gives one), gamma and exposure.
render::PreviewOptions preview_options(const io::RenderSettings& r, const render::Image& image) {
  const auto byte = [](double x) {
    return static_cast<std::uint8_t>(std::lround(255 * std::clamp(x, 0.0, 1.0)));
  };
  // Colours are linear RGB; the ramp's stops are sRGB bytes (IEC 61966-2-1).
  const auto srgb = [&](const std::array<double, 3>& c) {
    render::Rgb8 out{};
    for (std::size_t k = 0; k < 3; ++k)
      out[k] = byte(c[k] <= 0.0031308 ? 12.92 * c[k] : 1.055 * std::pow(c[k], 1 / 2.4) - 0.055);
    return out;
  };
  render::PreviewOptions po;
  po.background = {byte(r.background[0]), byte(r.background[1]), byte(r.background[2])};
  po.exposure = r.exposure;
  po.tone.gamma = r.gamma;
  if (!r.palette.empty()) {
    po.tone.ramp.clear();
    for (const auto& c : r.palette) po.tone.ramp.push_back(srgb(c));
  } else if (r.color_given) {
    po.tone.ramp = {po.background, srgb(r.color)};
  }
  if (r.exposure != 1) {
    const auto it = image.channels.find("density");
    float top = 0;
    if (it != image.channels.end())
      for (const float d : it->second)
        if (std::isfinite(d)) top = std::max(top, d);
    if (top > 0) po.tone.max_density = static_cast<double>(top) / r.exposure;
  }
  return po;
}

/// Stages without a count show their name and time on a terminal (render::Stage).
struct Stages {
  const io::Experiment& e;
  const RunOptions& o;
  std::optional<render::Stage> stage;
  void begin(const std::string& what) { stage.emplace(e.name + ": " + what, o.quiet); }
  void end() { stage.reset(); }
};

/// The image paths (empty: none) and whether anything is drawn.
struct ImagePaths {
  std::filesystem::path exr, png;
  bool drawn;
};

/// Refuses a run without output and an image that would not fit, before any work.
ImagePaths image_paths(const io::Experiment& e, const RunOptions& o) {
  const std::filesystem::path exr = !o.exr.empty()          ? o.exr
                                    : e.outputs.exr.empty() ? ""
                                                            : o.out_dir / e.outputs.exr;
  const std::filesystem::path png = !o.png.empty()          ? o.png
                                    : e.outputs.png.empty() ? ""
                                                            : o.out_dir / e.outputs.png;
  // Geometry or automaton files alone are a run without an image: nothing is framed or drawn.
  const bool drawn = !exr.empty() || !png.empty();
  if (!drawn && e.outputs.geometry.empty() && e.outputs.automaton.empty())
    throw InvalidInput(
        e.name +
        ": no output (give -o OUT.exr or --png, or outputs: exr, png, a geometry or automaton file)");
  // Ten float channels and the state: refuse an image that would not fit before any work.
  const double image_bytes = double(e.render.width) * double(e.render.height) * 44.0;
  if (drawn && image_bytes > double(o.max_bytes))
    throw InvalidInput("the image of " + std::to_string(e.render.width) + " × " +
                       std::to_string(e.render.height) + " pixels (render.width × render.height) needs " +
                       number_text(image_bytes / 1e9, 6) + " GB, above the limit of " +
                       number_text(double(o.max_bytes) / 1e9, 6) + " GB; lower the image size");
  return {exr, png, drawn};
}

/// A run without an image: its geometry and automaton files only.
void write_without_image(const Scene& scene, const io::Experiment& e, const std::string& kind,
                         Outputs& outputs, Stages& stages, RunReport& report) {
  stages.begin("writing files");
  report.written = write_files(scene, e, outputs);
  stages.end();
  outputs.files.commit();
  report.summary = summary(e, kind, scene, report);
}

/// The camera: the shape's extent, with the chaos game's first points or the drawn control net.
render::Camera frame(Scene& scene, const io::Experiment& e) {
  if (e.evaluation.mode == Mode::chaos && !e.ifs) {
    // Frame the chaos game from a short walk of the same automaton.
    ifs::ChaosOptions co;
    co.samples = 20000;
    co.seed = e.evaluation.seed;
    scene.extent =
        drawable(cartesian_if(ifs::chaos_game(scene.automaton, scene.nets, co).points, scene.rational),
                 "the attractor");
  }

  if (e.render.control_net && scene.control) {  // the control net is drawn: keep it in the picture
    Points both(scene.extent.rows() + scene.control->vertices.rows(), scene.extent.cols());
    if (scene.control->vertices.cols() != both.cols())
      throw InvalidInput("control net and shape differ in dimension");
    both << scene.extent, scene.control->vertices;
    scene.extent = std::move(both);
  }
  return make_camera(e.camera, e.render, drawable(scene.extent, "the shape"));
}

/// The rasterised layers: control net, mesh, control mesh, curves.
void draw_layers(render::Image& image, const render::Camera& camera, const Scene& scene,
                 const io::Experiment& e, const RunOptions& o, unsigned threads) {
  render::CurveStyle control_style;
  control_style.width = std::max(1.0, 0.5 * e.render.line_width);
  control_style.color = {0.55, 0.55, 0.55};
  // A NURBS net goes under its shape; a control mesh over its subdivision surface.
  const bool under = e.render.control_net && scene.control && !e.mesh;
  if (under) render::render_segments(image, camera, *scene.control, control_style);
  if (scene.mesh) {
    render::SurfaceStyle style;
    style.color = e.render.color;
    style.state_colors = scene.state_colors;
    style.threads = threads;
    style.part = o.part;
    render::render_mesh(image, camera, *scene.mesh, style);
  }
  if (e.render.control_net && scene.control && e.mesh) {
    control_style.color = {0.1, 0.1, 0.1};
    control_style.part = o.part;
    const Eigen::VectorXd size = scene.extent.colwise().maxCoeff() - scene.extent.colwise().minCoeff();
    render_control_mesh(image, camera, *scene.control, control_style, 0.1 * size.norm());
  }
  if (scene.curves) {
    render::CurveStyle style;
    style.width = e.render.line_width;
    style.color = e.render.color;
    style.part = o.part;
    render_coloured_segments(image, camera, *scene.curves, style, scene.state_colors);
  }
}

/// The chaos game's hits (or a classic IFS's points), not yet composited; sets the scene's depth.
std::optional<render::DensityLayer> draw_points(render::Image& image, const render::Camera& camera,
                                                Scene& scene, const io::Experiment& e, const RunOptions& o,
                                                unsigned threads) {
  std::optional<render::DensityLayer> points;
  if (!scene.maps.empty()) {
    points = render_classic(camera, scene, e, o, threads);
    scene.depth = e.evaluation.mode == Mode::depth ? e.evaluation.depth : 0;
  } else if (e.evaluation.mode == Mode::chaos) {
    render::ProgressBar bar("chaos game", o.quiet);
    render::ChaosDensityOptions co;
    co.samples = e.evaluation.samples;
    co.seed = e.evaluation.seed;
    co.threads = threads;
    co.color = e.render.color;
    co.rational = scene.rational;
    if (scene.rational) co.depth = 30;  // the automatic depth bound is for Cartesian nets
    co.progress = std::ref(bar);
    co.part = o.part;
    points.emplace();
    scene.depth = render::chaos_density_layer(*points, image, camera, scene.automaton, scene.nets, co).depth;
  }
  return points;
}

/// A distributed run hands its part to the other parts; false on every part but the writer, whose
/// image is then the combined one.
bool combine_parts(render::Image& image, std::optional<render::DensityLayer>& points, const io::Experiment& e,
                   const RunOptions& o) {
  // The chaos game's layers are divided by samples; every other layer by rows (a classic IFS to a
  // depth is drawn whole by every part and shared by rows too).
  render::Share share;
  share.kind =
      points && e.evaluation.mode == Mode::chaos ? render::Share::Kind::points : render::Share::Kind::bands;
  share.part = o.part;
  share.color = e.render.color;
  if (points && share.kind == render::Share::Kind::bands) render::composite(image, *points, e.render.color);
  if (points && share.kind == render::Share::Kind::points) share.points = std::move(*points);
  share.image = std::move(image);
  o.combine(share);
  if (o.part.index != 0) return false;
  image = std::move(share.image);
  return true;
}

/// The EXR header's attributes.
void label_image(render::Image& image, const io::Experiment& e, const std::string& kind, const Scene& scene,
                 const RunReport& report) {
  image.attributes["experiment"] = e.name;
  if (!e.description.empty()) image.attributes["description"] = e.description;
  image.attributes["source"] = kind;
  image.attributes["evaluation"] =
      e.mesh                             ? "subdivision, " + std::to_string(e.mesh->levels) + " levels"
      : e.evaluation.mode == Mode::chaos ? "chaos game, " + std::to_string(e.evaluation.samples) + " samples"
      : e.evaluation.mode == Mode::depth ? "depth"
                                         : "relative piece size " + number_text(e.evaluation.tolerance, 6);
  image.attributes["depth"] = std::to_string(scene.depth);
  image.attributes["seed"] = std::to_string(e.evaluation.mode == Mode::chaos ? e.evaluation.seed
                                            : e.perturbation                 ? e.perturbation->seed
                                                                             : 0);
  if (e.perturbation) {
    image.attributes["perturbation"] = "amplitude " + number_text(e.perturbation->amplitude, 6) + ", seed " +
                                       std::to_string(e.perturbation->seed) + ", " +
                                       std::to_string(report.free_coefficients) + " free coefficients";
    image.attributes["residual"] = number_text(report.residual, 6);
  }
  if (e.junction) {
    image.attributes["junction"] =
        scene.junction + ", " + std::to_string(report.free_coefficients) + " free coefficients";
    image.attributes["residual"] = number_text(report.residual, 6);
  }
}

/// Geometry and automaton files (encoded a chunk at a time straight into their temporaries), the
/// images after them; then all renamed together (all are written or none is).
void write_outputs(const render::Image& image, const Scene& scene, const io::Experiment& e,
                   const std::string& kind, const ImagePaths& paths, Outputs& outputs, Stages& stages,
                   RunReport& report) {
  stages.begin("writing files");
  const std::vector<std::filesystem::path> geometry = write_files(scene, e, outputs);  // reported last
  if (scene.curves && e.outputs.geometry.contains("svg"))
    if (std::string w = io::svg_dropped_coordinates(scene.curves->vertices); !w.empty())
      report.warnings.push_back("outputs.svg: " + w);
  if (outputs.exr) {
    stages.begin("writing " + paths.exr.filename().string());
    render::write_exr(*outputs.exr, image);
    report.written.push_back(paths.exr);
  }
  if (outputs.png) {
    stages.begin("writing " + paths.png.filename().string());
    render::preview_png(*outputs.png, image, preview_options(e.render, image));
    report.written.push_back(paths.png);
  }
  stages.end();
  report.written.insert(report.written.end(), geometry.begin(), geometry.end());
  outputs.files.commit();
  report.summary = summary(e, kind, scene, report);
}

}  // namespace

RunReport run(const io::Experiment& e, const RunOptions& o) {
  RunReport report;
  const ImagePaths paths = image_paths(e, o);
  render::check_part(o.part);
  const bool distributed = o.part.count > 1, writer = o.part.index == 0;
  if (distributed && !o.combine)
    throw InvalidInput("a distributed run needs a combine function to merge its parts");
  Outputs outputs;
  if (writer) reserve_outputs(outputs, e, o, paths.exr, paths.png);
  check_geometry_outputs(e);
  check_image_extensions(e, o);
  const unsigned threads = o.threads.value_or(e.render.threads);

  std::string kind;
  Stages stages{e, o, {}};
  stages.begin("evaluation");
  Scene scene = detail::build_source(e, o, report, kind, detail::Geometry::evaluated);
  stages.end();
  if (!paths.drawn) {
    report.depth = scene.depth;
    if (writer)
      write_without_image(scene, e, kind, outputs, stages, report);  // a distributed run's files are rank 0's
    return report;
  }
  const render::Camera camera = frame(scene, e);
  stages.begin("drawing");
  render::Image image = render::make_framebuffer(camera);
  draw_layers(image, camera, scene, e, o, threads);
  stages.end();  // the chaos game has its progress bar
  // The chaos game's hits, composited here or, in a distributed run, combined with the other parts'.
  std::optional<render::DensityLayer> points = draw_points(image, camera, scene, e, o, threads);
  if (distributed) {
    if (!combine_parts(image, points, e, o)) {
      report.depth = scene.depth;
      return report;
    }
  } else if (points) {
    render::composite(image, *points, e.render.color);
  }
  report.depth = scene.depth;
  label_image(image, e, kind, scene, report);
  write_outputs(image, scene, e, kind, paths, outputs, stages, report);
  return report;
}

}  // namespace cifs::experiment
