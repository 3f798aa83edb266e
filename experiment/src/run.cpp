// SPDX-License-Identifier: MIT
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

namespace cifs::experiment {
namespace {

using Mode = io::EvaluationSpec::Mode;

/// What the evaluation produced, ready to frame, draw and export.
struct Scene {
  automata::Automaton automaton;  // the (perturbed) automaton: drawn, and sampled by the chaos game
  /// NURBS curves: `automaton` with its knot data (windows, intervals), for the automaton outputs.
  std::optional<nurbs::KnotAutomaton> knots;
  std::vector<Points> nets;
  bool rational = false;  // nets hold homogeneous rows
  std::optional<Mesh> mesh;
  std::optional<Segments> curves;
  std::optional<Segments> control;
  std::vector<ifs::AffineMap> maps;  // classic IFS
  Points extent;                     // points that the camera must show
  int depth = 0;
  /// Junctions: the colour of every automaton state (its side's), for faces and segments.
  std::vector<render::Rgb> state_colors;
  std::string junction;  // junctions: what was glued, for the summary and the EXR header
};

/// Rows with 2 or 3 columns for the rasterisers (a 1-D shape lies on the x axis).
Points drawable(const Points& P, const std::string& what) {
  if (P.cols() == 2 || P.cols() == 3) return P;
  if (P.cols() == 1) {
    Points out = Points::Zero(P.rows(), 2);
    out.col(0) = P.col(0);
    return out;
  }
  throw InvalidInput(what + " has " + std::to_string(P.cols()) +
                     " coordinates; images show 1-, 2- and 3-D shapes");
}

Points cartesian_if(const Points& P, bool rational) {
  return rational ? ifs::cartesian(P) : P;
}

/// Deterministic curve evaluation: the attractor points to a depth, or to a tolerance (a fraction of
/// the nets' extent; leaf start points of the tolerance traversal, in curve order), as one polyline
/// with per-piece states.
Segments evaluate_curve(Scene& scene, const io::EvaluationSpec& ev, bool closed, const RunOptions& o) {
  const bool depth = ev.mode == Mode::depth;
  const auto row_bytes = sizeof(double) * static_cast<std::size_t>(scene.nets.front().cols());
  ifs::Sample sample = ifs::sample_attractor(
      scene.automaton, scene.nets,
      {.depth = depth ? ev.depth : -1,
       .tolerance =
           depth ? 0 : ev.tolerance * std::max(ifs::nets_diameter(scene.nets, scene.rational), 1e-300),
       .homogeneous = scene.rational,
       .closed = closed,
       .states = true,
       .max_points = o.max_bytes / row_bytes,
       .tolerance_name = "evaluation.relative_piece_size",
       .limit_hint = depth ? "; lower evaluation.depth" : "; give a larger evaluation.relative_piece_size"});
  scene.depth = sample.depth;
  Segments s = polyline_segments(drawable(sample.points, "the curve"), closed);
  if (sample.states.size() == s.segments.size()) s.states = std::move(sample.states);
  return s;
}

ifs::PerturbOptions perturb_options(const io::PerturbationSpec& p) {
  ifs::PerturbOptions po;
  po.amplitude = p.amplitude;
  po.seed = p.seed;
  po.values = p.values;
  // Only contractivity is checked here: the piece bound (A and radius: every path product of 16 × 16
  // matrices for bicubic patches, seconds) serves tolerance searches, which compute their own.
  po.contraction.bound = false;
  return po;
}

void note_perturbation(const ifs::Perturbation& p, RunReport& report) {
  report.free_coefficients = p.values.size();
  report.residual = p.residual;
}

Scene curve_scene(const nurbs::Curve& c, const io::Experiment& e, const RunOptions& o, RunReport& report) {
  Scene scene;
  scene.rational = c.rational;
  const nurbs::KnotAutomaton knots = nurbs::knot_automaton(c);
  scene.automaton = knots.automaton;
  scene.knots = knots;
  if (e.perturbation) {
    ifs::CurveBcifsOptions co;
    co.free_vertices = !e.perturbation->keep_vertices;
    const ifs::Perturbation p = ifs::perturb(ifs::curve_bcifs(c, co), perturb_options(*e.perturbation));
    note_perturbation(p, report);
    scene.automaton = p.system.automaton;
    scene.knots = ifs::curve_bcifs_knots(p.system.automaton, knots);
  }
  // The BC-IFS keeps the knot automaton's initial entries, in order: the same nets.
  scene.nets = nurbs::initial_nets(knots, c);
  const Points control = drawable(nurbs::cartesian_points(c), "the curve");
  scene.control = polyline_segments(control, c.closed);
  if (e.evaluation.mode != Mode::chaos) scene.curves = evaluate_curve(scene, e.evaluation, c.closed, o);
  scene.extent = scene.curves ? scene.curves->vertices : control;
  return scene;
}

Scene surface_scene(const nurbs::Surface& s, const io::Experiment& e, const RunOptions& o,
                    RunReport& report) {
  Scene scene;
  scene.rational = s.rational;
  const nurbs::TensorAutomaton ta = nurbs::tensor_automaton(s);
  scene.automaton = ta.product;
  scene.nets = nurbs::initial_nets(ta, s);
  if (e.perturbation) {
    ifs::SurfaceBcifsOptions so;
    so.free_knot_lines = !e.perturbation->keep_vertices;
    const ifs::Perturbation p = ifs::perturb(ifs::surface_bcifs(ta, so), perturb_options(*e.perturbation));
    note_perturbation(p, report);
    scene.automaton = p.system.automaton;
  }
  // Control net: the u and v polylines of the control points.
  const Points P = nurbs::cartesian_points(s);
  if (P.cols() != 3)
    throw InvalidInput("the surface has " + std::to_string(P.cols()) +
                       " coordinates; images show 3-D surfaces");
  Segments net;
  for (Eigen::Index i = 0; i < s.count[0]; ++i)
    append(net, polyline_segments(P.middleRows(i * s.count[1], s.count[1])));
  for (Eigen::Index j = 0; j < s.count[1]; ++j) {
    Points column(s.count[0], 3);
    for (Eigen::Index i = 0; i < s.count[0]; ++i) column.row(i) = P.row(i * s.count[1] + j);
    append(net, polyline_segments(column));
  }
  scene.control = std::move(net);
  if (e.evaluation.mode != Mode::chaos) {
    int depth = e.evaluation.depth;
    if (e.evaluation.mode == Mode::tolerance) {
      depth = ifs::depth_for_tolerance(
          scene.automaton, scene.nets,
          {.epsilon = e.evaluation.tolerance * std::max(ifs::nets_diameter(scene.nets), 1e-300),
           .max_depth = 14});
    }
    ifs::MeshOptions mo;
    mo.homogeneous = s.rational;
    mo.max_bytes = o.max_bytes;
    Mesh mesh = e.perturbation ? ifs::quad_mesh(scene.automaton, scene.nets, ta.patches, depth, mo)
                               : ifs::surface_mesh(ta, scene.nets, depth, mo);
    scene.depth = depth;
    scene.extent = mesh.vertices;
    scene.mesh = std::move(mesh);
  } else {
    scene.extent = P;
  }
  return scene;
}

Scene bcifs_scene(const io::Experiment& e, const RunOptions& o, RunReport& report) {
  io::BcifsFile file = io::read_bcifs(e.automaton);
  if (file.nets.size() != file.system.automaton.initial.size())
    throw InvalidInput(e.automaton.string() + ": the file gives no control nets for its initial states");
  Scene scene;
  ifs::Bcifs system = std::move(file.system);
  if (e.perturbation) {
    ifs::Perturbation p = ifs::perturb(system, perturb_options(*e.perturbation));
    note_perturbation(p, report);
    system = std::move(p.system);
  }
  // The file's matrices are the user's: an attractor exists only when they shrink nets. A depth
  // evaluation would draw a finite composition of anything; dimension and the chaos game refuse too.
  (void)ifs::contraction(system.automaton, {.bound = false});
  scene.automaton = system.automaton;
  scene.nets = std::move(file.nets);
  if (e.evaluation.mode == Mode::depth || e.evaluation.mode == Mode::tolerance) {
    if (e.evaluation.mode == Mode::tolerance)
      throw InvalidInput(
          "evaluation.relative_piece_size: BC-IFS files are evaluated to a depth or by the chaos game");
    const ifs::EdgePieces pieces = ifs::edge_pieces(system, scene.nets, e.evaluation.depth, o.max_bytes);
    Segments s;
    const Eigen::Index n = pieces.start.rows();
    Points v(2 * n, pieces.start.cols());
    v.topRows(n) = pieces.start;
    v.bottomRows(n) = pieces.end;
    s.vertices = drawable(v, "the BC-IFS attractor");
    for (Eigen::Index i = 0; i < n; ++i) {
      s.segments.push_back({static_cast<int>(i), static_cast<int>(n + i)});
      s.states.push_back(static_cast<std::uint32_t>(pieces.state[static_cast<std::size_t>(i)]));
    }
    scene.depth = e.evaluation.depth;
    scene.extent = s.vertices;
    scene.curves = std::move(s);
  }
  Segments control;
  for (const Points& N : scene.nets) append(control, polyline_segments(drawable(N, "a control net")));
  if (!scene.curves) scene.extent = control.vertices;
  scene.control = std::move(control);
  return scene;
}

/// A mesh source's surface automaton (subdivision/limit.hpp), fractal when `perturbation` is given
/// (fractal_surface): the automaton needs quads (triangles) with at most one extraordinary corner, so
/// the mesh is refined once or twice first, at most `budget` levels; `refined` gets the levels spent.
subdivision::SurfaceAutomaton mesh_automaton(const io::MeshSource& m, const io::PerturbationSpec* perturbation,
                                             int budget, const RunOptions& o, RunReport& report,
                                             int& refined) {
  const subdivision::MeshOptions options{.max_bytes = o.max_bytes};
  const std::string file = m.path.filename().string();
  for (int first = 1; first <= 2; ++first) {
    if (budget < first)
      throw InvalidInput("subdivision.levels: " + file + ": a fractal surface needs " +
                         std::to_string(first) + " level(s) or more here");
    const Mesh mesh = subdivision::subdivide(m.mesh, m.scheme, first, options);
    subdivision::SurfaceAutomaton smooth;
    try {
      smooth = subdivision::surface_automaton(mesh, m.scheme);
    } catch (const InvalidInput& error) {
      if (first == 1 &&
          std::string_view(error.what()).find("refine one level first") != std::string_view::npos)
        continue;
      throw InvalidInput((perturbation ? "perturbation: " : "mesh: ") + file + ": " + error.what());
    }
    refined = first;
    if (!perturbation) return smooth;
    subdivision::FractalSurface fractal;
    try {
      fractal = subdivision::fractal_surface(smooth, perturb_options(*perturbation));
    } catch (const InvalidInput& error) {
      throw InvalidInput("perturbation: " + std::string(error.what()));
    }
    note_perturbation(fractal.perturbation, report);
    return std::move(fractal.surface);
  }
  throw std::logic_error("mesh_automaton: two levels leave no face with two extraordinary corners");
}

/// A fractal Catmull–Clark or Loop surface at the resolution of `levels` steps: its automaton after
/// one or two steps, drawn at the remaining depth.
Mesh fractal_mesh(const io::MeshSource& m, const io::PerturbationSpec& perturbation, const RunOptions& o,
                  RunReport& report) {
  int refined = 0;
  const subdivision::SurfaceAutomaton surface =
      mesh_automaton(m, &perturbation, m.levels, o, report, refined);
  ifs::MeshOptions mo;
  mo.max_bytes = o.max_bytes;
  return subdivision::surface_automaton_mesh(surface, m.levels - refined, mo);
}

/// The subdivision surface of a polygon mesh (its limit surface, or its fractal version); its
/// control mesh is the mesh's edges.
Scene mesh_scene(const io::MeshSource& m, const io::Experiment& e, const RunOptions& o, RunReport& report) {
  Scene scene;
  const subdivision::MeshOptions options{.max_bytes = o.max_bytes};
  try {
    if (e.perturbation) {
      scene.mesh = fractal_mesh(m, *e.perturbation, o, report);
    } else if (m.limit) {
      const MeshTopology t = build_topology(m.mesh);
      const bool closed =
          std::none_of(t.boundary_vertex.begin(), t.boundary_vertex.end(), [](auto b) { return b; });
      scene.mesh = subdivision::limit_mesh(m.mesh, m.scheme, m.levels,
                                           {.normals = closed, .max_bytes = o.max_bytes});
    } else {
      scene.mesh = subdivision::subdivide(m.mesh, m.scheme, m.levels, options);
    }
  } catch (const InvalidInput& error) {
    if (std::string_view(error.what()).starts_with("perturbation")) throw;
    throw InvalidInput("subdivision.levels: " + m.path.filename().string() + ": " + error.what());
  }
  scene.depth = m.levels;
  Segments cage;
  cage.vertices = m.mesh.vertices;
  const MeshTopology topology = build_topology(m.mesh, m.path.filename().string());
  cage.segments = topology.edges;
  scene.control = std::move(cage);
  scene.extent = drawable(scene.mesh->vertices, "the mesh");
  return scene;
}

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

/// One side of a junction as a BC-IFS, its nets and the layout of its initial entries.
struct JunctionPart {
  ifs::Bcifs system;
  std::vector<Points> nets;
  bool rational = false;
  /// Surfaces: the (u, v) place of every initial entry in the side's grid of patches, and the
  /// points per net along u and v (for drawing the control nets).
  std::vector<std::array<int, 2>> patches;
  std::array<Eigen::Index, 2> net_grid{0, 0};
  /// Scheme sides: the control point that each row of each net reads (nets overlap).
  std::vector<std::vector<Eigen::Index>> point_of_row;
  std::string kind;  // "b-spline(degree = 3) curve", "rational NURBS surface", …
};

std::string scheme_text(const subdivision::Scheme& s) {
  std::string text = s.name;
  for (std::size_t i = 0; i < s.parameters.size(); ++i)
    text += (i == 0 ? "(" : ", ") + s.parameters[i].name + " = " +
            subdivision::to_string(s.parameters[i].value) + (i + 1 == s.parameters.size() ? ")" : "");
  return text;
}

/// The windows of `window` consecutive points of a polygon, or of window × window points of a
/// grid (u-major, row i·window + j), u-major like product_bcifs' initial entries.
std::vector<Points> scheme_windows(const io::JunctionSideSpec& s, int window) {
  std::vector<Points> nets;
  if (s.columns == 0) {
    for (Eigen::Index k = 0; k + window <= s.points.rows(); ++k)
      nets.push_back(s.points.middleRows(k, window));
    return nets;
  }
  for (int a = 0; a + window <= s.rows; ++a)
    for (int b = 0; b + window <= s.columns; ++b) {
      Points W(window * window, s.points.cols());
      for (int i = 0; i < window; ++i)
        for (int j = 0; j < window; ++j) W.row(i * window + j) = s.points.row((a + i) * s.columns + b + j);
      nets.push_back(std::move(W));
    }
  return nets;
}

JunctionPart junction_part(const io::JunctionSideSpec& s) {
  JunctionPart part;
  if (s.scheme) {
    const int window = s.window == 0 ? subdivision::mask_degree(*s.scheme) : s.window;
    const auto curve = [&](int points, bool layered) {
      return subdivision::scheme_bcifs(
          *s.scheme, window, {.pieces = points - window + 1, .layer = layered ? s.layer : 0, .free = s.free});
    };
    part.nets = scheme_windows(s, window);
    for (std::size_t k = 0; k < part.nets.size(); ++k) {
      std::vector<Eigen::Index>& rows = part.point_of_row.emplace_back();
      const Eigen::Index nb = Eigen::Index{s.columns} - window + 1, K = static_cast<Eigen::Index>(k);
      for (Eigen::Index r = 0; r < part.nets[k].rows(); ++r)
        rows.push_back(s.columns == 0 ? K + r : (K / nb + r / window) * s.columns + K % nb + r % window);
    }
    if (s.columns == 0) {
      part.system = curve(static_cast<int>(s.points.rows()), true);
      part.kind = scheme_text(*s.scheme) + " curve";
      return part;
    }
    // The layer runs along the glued boundary: across u for "ustart", across v for "vstart".
    const bool u = s.boundary.front() == 'u';
    part.system =
        ifs::product_bcifs(curve(s.rows, u), curve(s.columns, !u), {.free_when_either = s.layer > 0});
    const int nb = s.columns - window + 1;
    for (int k = 0; k < static_cast<int>(part.nets.size()); ++k) part.patches.push_back({k / nb, k % nb});
    part.net_grid = {window, window};
    part.kind = scheme_text(*s.scheme) + " surface";
    return part;
  }
  if (const auto* c = std::get_if<nurbs::Curve>(&*s.shape)) {
    part.system = ifs::curve_bcifs(*c, {.free_vertices = s.free});
    part.nets = nurbs::initial_nets(nurbs::knot_automaton(*c), *c);  // the BC-IFS keeps its initial entries
    part.rational = c->rational;
    part.kind = std::string(c->rational ? "rational " : "") + "NURBS curve";
    return part;
  }
  const auto& surface = std::get<nurbs::Surface>(*s.shape);
  const nurbs::TensorAutomaton ta = nurbs::tensor_automaton(surface);
  part.system = ifs::surface_bcifs(ta, {.free_knot_lines = s.free});
  part.nets = nurbs::initial_nets(ta, surface);
  part.rational = surface.rational;
  part.patches = ta.patches;
  part.net_grid = {surface.degree[0] + 1, surface.degree[1] + 1};
  part.kind = std::string(surface.rational ? "rational " : "") + "NURBS surface";
  return part;
}

/// The initial entries of a side along its glued boundary, in order along it.
std::vector<std::size_t> glued_entries(const JunctionPart& part, const std::string& boundary) {
  const std::size_t n = part.system.automaton.initial.size();
  if (part.patches.empty()) return {boundary == "start" ? 0 : n - 1};
  const int axis = boundary.front() == 'u' ? 0 : 1;
  int last = 0;
  for (const auto& p : part.patches) last = std::max(last, p[static_cast<std::size_t>(axis)]);
  const int at = boundary.ends_with("start") ? 0 : last;
  std::vector<std::pair<int, std::size_t>> along;
  for (std::size_t k = 0; k < n; ++k)
    if (part.patches[k][static_cast<std::size_t>(axis)] == at)
      along.emplace_back(part.patches[k][static_cast<std::size_t>(1 - axis)], k);
  std::sort(along.begin(), along.end());
  std::vector<std::size_t> entries;
  entries.reserve(along.size());
  for (const auto& [place, k] : along) entries.push_back(k);
  return entries;
}

/// Homogeneous rows (x, 1) for the side that is not rational when the other one is.
void lift_homogeneous(std::vector<Points>& nets) {
  for (Points& N : nets) {
    Points H(N.rows(), N.cols() + 1);
    H << N, Eigen::VectorXd::Ones(N.rows());
    N = std::move(H);
  }
}

/// The grid lines of a net of rows × columns points (row i·columns + j), Cartesian.
Segments net_lines(const Points& net, std::array<Eigen::Index, 2> grid) {
  Segments lines;
  for (Eigen::Index i = 0; i < grid[0]; ++i)
    append(lines, polyline_segments(net.middleRows(i * grid[1], grid[1])));
  for (Eigen::Index j = 0; j < grid[1]; ++j) {
    Points column(grid[0], net.cols());
    for (Eigen::Index i = 0; i < grid[0]; ++i) column.row(i) = net.row(i * grid[1] + j);
    append(lines, polyline_segments(column));
  }
  return lines;
}

/// join replaces B's rows on the glued boundary by A's in the glued nets only; B's other nets read
/// the same control points. A scheme side takes the new points in every net (its windows overlap:
/// one polygon or grid); a NURBS side must already have them (its nets come from knot insertion).
void share_boundary_points(const JunctionPart& b, std::vector<Points>& nets, std::size_t first) {
  std::map<Eigen::Index, Eigen::RowVectorXd> moved;
  for (std::size_t k = 0; k < b.nets.size(); ++k) {
    const Points& given = b.nets[k];
    const Points& joined = nets[first + k];
    for (Eigen::Index r = 0; r < given.rows(); ++r) {
      const double scale = std::max({1.0, given.row(r).norm(), joined.row(r).norm()});
      if ((given.row(r) - joined.row(r)).norm() <= 1e-12 * scale) continue;
      if (b.point_of_row.empty())
        throw InvalidInput("junction: B's control points on the glued boundary differ from A's (net " +
                           std::to_string(k) + ", row " + std::to_string(r) +
                           "): give the NURBS side A's boundary points, with A's weights");
      moved[b.point_of_row[k][static_cast<std::size_t>(r)]] = joined.row(r);
    }
  }
  for (std::size_t k = 0; k < b.nets.size() && !moved.empty(); ++k)
    for (Eigen::Index r = 0; r < b.nets[k].rows(); ++r)
      if (const auto it = moved.find(b.point_of_row[k][static_cast<std::size_t>(r)]); it != moved.end())
        nets[first + k].row(r) = it->second;
}

/// Two shapes joined along a shared boundary (ifs::join: A keeps its matrices, B adapts), perturbed
/// when asked, drawn each side in its own colour: curves as their pieces, surfaces as one quad mesh
/// per side (ifs::quad_mesh; the two meshes meet on the junction but are not welded).
Scene junction_scene(const io::JunctionSpec& junction, const io::Experiment& e, const RunOptions& o,
                     RunReport& report, std::string& kind) {
  JunctionPart a = junction_part(junction.a), b = junction_part(junction.b);
  const bool rational = a.rational || b.rational;
  if (rational && !a.rational) lift_homogeneous(a.nets);
  if (rational && !b.rational) lift_homogeneous(b.nets);
  const std::vector<std::size_t> ea = glued_entries(a, junction.a.boundary),
                                 eb = glued_entries(b, junction.b.boundary);
  if (ea.size() != eb.size())
    throw InvalidInput("junction: A's " + junction.a.boundary + " has " + std::to_string(ea.size()) +
                       " patches and B's " + junction.b.boundary + " " + std::to_string(eb.size()) +
                       ": the glued boundaries must have as many");
  std::vector<ifs::Glue> glue;
  for (std::size_t k = 0; k < ea.size(); ++k)
    glue.push_back({ea[k], junction.a.boundary, eb[k], junction.b.boundary});
  ifs::Junction j;
  try {
    j = ifs::join(a.system, a.nets, b.system, b.nets, glue);
  } catch (const InvalidInput& error) {
    throw InvalidInput("junction: " + std::string(error.what()));
  }
  share_boundary_points(b, j.nets, a.nets.size());
  report.free_coefficients = j.free;
  report.residual = j.residual;
  ifs::Bcifs system = std::move(j.system);
  if (e.perturbation) {
    ifs::Perturbation p = ifs::perturb(system, perturb_options(*e.perturbation));
    report.free_coefficients = p.values.size();
    report.residual = std::max(report.residual, p.residual);
    system = std::move(p.system);
  }
  (void)ifs::contraction(system.automaton, {.bound = false});
  kind = "junction of a " + a.kind + " and a " + b.kind;
  Scene scene;
  scene.junction = "A's " + junction.a.boundary + " = B's " + junction.b.boundary + ", " +
                   std::to_string(j.shared.size()) + " shared cell" + (j.shared.size() == 1 ? "" : "s") +
                   ", " + std::to_string(j.junction_constraints.size()) + " junction constraint" +
                   (j.junction_constraints.size() == 1 ? "" : "s");
  scene.automaton = system.automaton;
  scene.nets = std::move(j.nets);
  scene.rational = rational;
  // Each side's colour on its own states (shared cells are A's; leaves are never shared).
  const render::Rgb color_a = junction.a.color.value_or(e.render.color);
  const render::Rgb color_b = junction.b.color.value_or(render::Rgb{0.85, 0.40, 0.08});
  const auto& g = scene.automaton.graph;
  for (automata::StateId s = 0; s < num_vertices(g); ++s)
    scene.state_colors.push_back(g[s].name.starts_with("B:") ? color_b : color_a);

  const std::size_t na = a.nets.size();
  Segments control;
  for (std::size_t k = 0; k < scene.nets.size(); ++k) {
    const Points N = drawable(cartesian_if(scene.nets[k], rational), "a control net");
    const auto& grid = (k < na ? a : b).net_grid;
    append(control, grid[0] > 0 ? net_lines(N, grid) : polyline_segments(N));
  }
  scene.extent = control.vertices;
  scene.control = std::move(control);
  if (e.evaluation.mode == Mode::chaos) return scene;
  const int depth = e.evaluation.depth;
  scene.depth = depth;
  if (a.patches.empty()) {  // curves: one segment per piece, as for BC-IFS files
    const ifs::EdgePieces pieces = ifs::edge_pieces(system, scene.nets, depth, o.max_bytes);
    const Eigen::Index n = pieces.start.rows();
    Points v(2 * n, pieces.start.cols());
    v << pieces.start, pieces.end;
    Segments s;
    s.vertices = drawable(cartesian_if(v, rational), "the junction");
    for (Eigen::Index i = 0; i < n; ++i) {
      s.segments.push_back({static_cast<int>(i), static_cast<int>(n + i)});
      s.states.push_back(static_cast<std::uint32_t>(pieces.state[static_cast<std::size_t>(i)]));
    }
    scene.extent = s.vertices;
    scene.curves = std::move(s);
    return scene;
  }
  // Surfaces: each side's patches meshed on their own grid, the meshes put side by side.
  ifs::MeshOptions mo;
  mo.homogeneous = rational;
  mo.max_bytes = o.max_bytes / 2;
  Mesh mesh;
  for (const JunctionPart* part : {&a, &b}) {
    const std::size_t first = part == &a ? 0 : na;
    automata::Automaton side = system.automaton;
    side.initial.assign(system.automaton.initial.begin() + static_cast<long>(first),
                        system.automaton.initial.begin() + static_cast<long>(first + part->nets.size()));
    const std::span<const Points> nets(scene.nets.data() + first, part->nets.size());
    Mesh side_mesh = ifs::quad_mesh(side, nets, part->patches, depth, mo);
    side_mesh.vertices = drawable(side_mesh.vertices, "the junction");
    append(mesh, side_mesh);
  }
  scene.extent = mesh.vertices;
  scene.mesh = std::move(mesh);
  return scene;
}

std::vector<ifs::AffineMap> classic_maps(const io::ClassicIfs& c) {
  const auto& names = ifs::ifs_names();
  if (std::find(names.begin(), names.end(), c.name) != names.end()) return ifs::named_ifs(c.name);
  std::vector<ifs::AffineMap> maps;
  for (const auto& m : c.maps) maps.push_back({m[0], m[1], m[2], m[3], m[4], m[5], m[6]});
  return maps;
}

Scene classic_scene(const io::ClassicIfs& c) {
  Scene scene;
  scene.maps = classic_maps(c);
  const render::Bounds b = render::estimate_bounds(scene.maps, 0.0);
  scene.extent.resize(2, 2);
  scene.extent << b.x_min, b.y_min, b.x_max, b.y_max;
  // The CIFS form (one state, barycentric matrices on a triangle around the attractor) is what the
  // automaton outputs draw.
  const double w = b.x_max - b.x_min, h = b.y_max - b.y_min;
  Points triangle(3, 2);
  triangle << b.x_min - w, b.y_min, b.x_max + w, b.y_min, (b.x_min + b.x_max) / 2, b.y_max + h;
  scene.automaton = ifs::affine_automaton(scene.maps, triangle);
  scene.nets = {triangle};
  return scene;
}

/// The scene of any source; `kind` names the source for summaries.
Scene make_scene(const io::Experiment& e, const RunOptions& o, RunReport& report, std::string& kind) {
  if (e.shape) {
    if (const auto* c = std::get_if<nurbs::Curve>(&*e.shape)) {
      kind = "NURBS curve";
      return curve_scene(*c, e, o, report);
    }
    kind = "NURBS surface";
    return surface_scene(std::get<nurbs::Surface>(*e.shape), e, o, report);
  }
  if (!e.automaton.empty()) {
    kind = "BC-IFS " + e.automaton.filename().string();
    return bcifs_scene(e, o, report);
  }
  if (e.mesh) {
    kind = std::string(subdivision::scheme_name(e.mesh->scheme)) + " subdivision of " +
           e.mesh->path.filename().string();
    return mesh_scene(*e.mesh, e, o, report);
  }
  if (e.junction) return junction_scene(*e.junction, e, o, report, kind);
  kind = "classic IFS " + (e.ifs->name.empty() ? std::string("(maps)") : e.ifs->name);
  return classic_scene(*e.ifs);
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
  Scene scene = make_scene(e, o, report, kind);
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

namespace {

/// evaluate and sample measure attractors: a Catmull–Clark or Loop surface is its surface automaton's
/// (fractal when the file perturbs it), after the one or two levels of refinement the automaton needs.
/// With `meshed`, its welded attractor mesh at `depth` below those levels (unset: the file's levels less
/// them). Other schemes have no automaton: refused, naming the mesh.
Scene mesh_attractor(const io::Experiment& e, bool meshed, std::optional<int> depth, const RunOptions& o,
                     RunReport& report, std::string& kind) {
  const io::MeshSource& m = *e.mesh;
  const std::string scheme(subdivision::scheme_name(m.scheme)), file = m.path.filename().string();
  if (m.scheme != subdivision::MeshScheme::catmull_clark && m.scheme != subdivision::MeshScheme::loop)
    throw InvalidInput(
        "mesh: " + file + ": a " + scheme +
        " surface has no automaton to evaluate or sample (catmull-clark and loop surfaces have)");
  int refined = 0;
  subdivision::SurfaceAutomaton surface =
      mesh_automaton(m, e.perturbation ? &*e.perturbation : nullptr, 2, o, report, refined);
  kind = (e.perturbation ? "fractal " : "") + scheme + " surface of " + file + ", its automaton after " +
         std::to_string(refined) + " level(s) of refinement";
  Scene scene;
  scene.depth = depth.value_or(std::max(m.levels - refined, 0));
  if (meshed) {
    ifs::MeshOptions mo;
    mo.max_bytes = o.max_bytes;
    scene.mesh = subdivision::surface_automaton_mesh(surface, scene.depth, mo);
  }
  scene.automaton = std::move(surface.automaton);
  scene.nets = std::move(surface.nets);
  return scene;
}

/// Diameter of a net's Cartesian points (homogeneous rows `(w·x, w)` when `rational`); infinite
/// when a weight is 0 or the points are not finite.
double cartesian_diameter(const Points& net, bool rational) {
  if (!rational) return ifs::diameter(net);
  if (!(net.col(net.cols() - 1).array() != 0).all()) return std::numeric_limits<double>::infinity();
  const Points x = ifs::cartesian(net);
  return x.allFinite() ? ifs::diameter(x) : std::numeric_limits<double>::infinity();
}

}  // namespace

Evaluation evaluate(const io::Experiment& experiment, std::optional<int> depth, const RunOptions& o) {
  io::Experiment e = experiment;
  e.evaluation.mode = Mode::depth;
  if (depth) e.evaluation.depth = *depth;
  if (e.evaluation.depth < 0)
    throw InvalidInput("the depth " + std::to_string(e.evaluation.depth) + " is negative; give a depth ≥ 0");
  RunReport report;
  Evaluation out;
  Scene scene =
      e.mesh ? mesh_attractor(e, true, depth, o, report, out.kind) : make_scene(e, o, report, out.kind);
  out.depth = e.mesh ? scene.depth : e.evaluation.depth;
  if (scene.mesh) {
    out.points = scene.mesh->vertices;
  } else if (scene.curves) {
    out.points = scene.curves->vertices;
  } else {  // classic IFS: the start points of the depth-K nodes of its one-state automaton
    ifs::PointsOptions po;
    po.max_bytes = o.max_bytes;
    out.points = ifs::attractor_points(scene.automaton, scene.nets, out.depth, po);
  }
  const ifs::PieceBounds bounds(scene.automaton, ifs::contraction(scene.automaton), scene.rational);
  ifs::for_each_leaf(scene.automaton, scene.nets, out.depth, [&](const ifs::Leaf& leaf) {
    out.resolution = std::max(out.resolution, bounds(leaf.state, leaf.net).diameter);
    out.estimated_resolution =
        std::max(out.estimated_resolution, cartesian_diameter(leaf.net, scene.rational));
  });
  out.automaton = std::move(scene.automaton);
  out.nets = std::move(scene.nets);
  out.maps = std::move(scene.maps);
  out.rational = scene.rational;
  return out;
}

Evaluation sample(const io::Experiment& experiment, const SampleOptions& options, const RunOptions& o) {
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
    throw InvalidInput("the tolerance " +
                       (std::isfinite(options.tolerance) ? number_text(options.tolerance, 6) + " is negative"
                                                         : std::string("is not a finite number")) +
                       "; give a finite tolerance ≥ 0");
  // Chaos mode builds the automaton and nets without evaluating them.
  io::Experiment e = experiment;
  e.evaluation.mode = Mode::chaos;
  RunReport report;
  Evaluation out;
  Scene scene =
      e.mesh ? mesh_attractor(e, false, {}, o, report, out.kind) : make_scene(e, o, report, out.kind);
  ifs::ToleranceSampleOptions so;
  so.homogeneous = scene.rational;
  so.max_points = options.max_points;
  so.epsilon = options.tolerance * ifs::nets_diameter(scene.nets, scene.rational);
  if (options.tolerance > 0 && !(so.epsilon > 0))
    throw InvalidInput(
        "the tolerance is relative to the size of the control nets, which are single points; give a depth "
        "instead");
  ifs::ToleranceSample ts = ifs::tolerance_sample(scene.automaton, scene.nets, so);
  out.points = std::move(ts.points);
  out.resolution = ts.resolution;
  out.depth = ts.deepest;
  out.automaton = std::move(scene.automaton);
  out.nets = std::move(scene.nets);
  out.maps = std::move(scene.maps);
  out.rational = scene.rational;
  return out;
}

}  // namespace cifs::experiment
