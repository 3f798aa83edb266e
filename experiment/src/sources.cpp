// SPDX-License-Identifier: MIT
// cifs — an experiment's sources built into scenes (scene.hpp): NURBS curves and surfaces, BC-IFS files,
// subdivision meshes, junctions of two shapes, classic IFS — their automata, nets and control nets,
// perturbed as the file asks, and their geometry at the file's evaluation when asked.
#include "scene.hpp"

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
#include "cifs/render/image.hpp"
#include "cifs/render/point_ifs.hpp"
#include "cifs/render/raster.hpp"
#include "cifs/subdivision/ifs.hpp"
#include "cifs/subdivision/limit.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/topology.hpp"

namespace cifs::experiment::detail {

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

namespace {

using Mode = io::EvaluationSpec::Mode;

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

Scene curve_scene(const nurbs::Curve& c, const io::Experiment& e, bool evaluate, const RunOptions& o,
                  RunReport& report) {
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
  if (evaluate) scene.curves = evaluate_curve(scene, e.evaluation, c.closed, o);
  scene.extent = scene.curves ? scene.curves->vertices : control;
  return scene;
}

Scene surface_scene(const nurbs::Surface& s, const io::Experiment& e, bool evaluate, const RunOptions& o,
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
  if (evaluate) {
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

Scene bcifs_scene(const io::Experiment& e, bool evaluate, const RunOptions& o, RunReport& report) {
  io::BcifsFile file = e.bcifs ? *e.bcifs : io::read_bcifs(e.automaton);
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
  if (evaluate) {
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
subdivision::FractalSurface mesh_automaton(const io::MeshSource& m, const io::PerturbationSpec* perturbation,
                                           int budget, const RunOptions& o, RunReport& report, int& refined) {
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
    if (!perturbation) {
      subdivision::FractalSurface plain;  // the smooth surface, no perturbation
      plain.surface = std::move(smooth);
      return plain;
    }
    subdivision::FractalSurface fractal;
    try {
      subdivision::FractalFeatureOptions features;
      if (const auto& c = perturbation->fractal_curves) {
        features.creases = c->creases;
        features.boundaries = c->boundaries;
        features.perturbation = perturb_options({.amplitude = c->amplitude,
                                                 .seed = c->seed,
                                                 .values = c->values,
                                                 .keep_vertices = true,
                                                 .fractal_curves = std::nullopt});
      }
      fractal = subdivision::fractal_surface(mesh, smooth, perturb_options(*perturbation), features);
    } catch (const InvalidInput& error) {
      throw InvalidInput("perturbation: " + std::string(error.what()));
    }
    note_perturbation(fractal.perturbation, report);
    return fractal;
  }
  throw std::logic_error("mesh_automaton: two levels leave no face with two extraordinary corners");
}

/// A fractal Catmull–Clark or Loop surface at the resolution of `levels` steps: its automaton after
/// one or two steps, drawn at the remaining depth.
Mesh fractal_mesh(const io::MeshSource& m, const io::PerturbationSpec& perturbation, const RunOptions& o,
                  RunReport& report) {
  int refined = 0;
  const subdivision::FractalSurface surface = mesh_automaton(m, &perturbation, m.levels, o, report, refined);
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
      scene.mesh =
          subdivision::limit_mesh(m.mesh, m.scheme, m.levels, {.normals = closed, .max_bytes = o.max_bytes});
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
Scene junction_scene(const io::JunctionSpec& junction, const io::Experiment& e, bool evaluate,
                     const RunOptions& o, RunReport& report, std::string& kind) {
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
  if (!evaluate) return scene;
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

}  // namespace

Scene build_source(const io::Experiment& e, const RunOptions& o, RunReport& report, std::string& kind,
                   Geometry geometry) {
  const bool evaluate = geometry == Geometry::evaluated && e.evaluation.mode != Mode::chaos;
  if (e.shape) {
    if (const auto* c = std::get_if<nurbs::Curve>(&*e.shape)) {
      kind = "NURBS curve";
      return curve_scene(*c, e, evaluate, o, report);
    }
    kind = "NURBS surface";
    return surface_scene(std::get<nurbs::Surface>(*e.shape), e, evaluate, o, report);
  }
  if (!e.automaton.empty()) {
    kind = "BC-IFS " + e.automaton.filename().string();
    return bcifs_scene(e, evaluate, o, report);
  }
  if (e.mesh) {
    kind = std::string(subdivision::scheme_name(e.mesh->scheme)) + " subdivision of " +
           e.mesh->path.filename().string();
    return mesh_scene(*e.mesh, e, o, report);
  }
  if (e.junction) return junction_scene(*e.junction, e, evaluate, o, report, kind);
  kind = "classic IFS " + (e.ifs->name.empty() ? std::string("(maps)") : e.ifs->name);
  return classic_scene(*e.ifs);
}
Scene mesh_attractor(const io::Experiment& e, bool meshed, std::optional<int> depth, const RunOptions& o,
                     RunReport& report, std::string& kind) {
  const io::MeshSource& m = *e.mesh;
  const std::string scheme(subdivision::scheme_name(m.scheme)), file = m.path.filename().string();
  if (m.scheme != subdivision::MeshScheme::catmull_clark && m.scheme != subdivision::MeshScheme::loop)
    throw InvalidInput(
        "mesh: " + file + ": a " + scheme +
        " surface has no automaton to evaluate or sample (catmull-clark and loop surfaces have)");
  if (!meshed && e.perturbation && e.perturbation->fractal_curves)
    throw InvalidInput(
        "perturbation.fractal_curves: " + file +
        ": fractal crease and boundary curves are added to the attractor mesh, not to the automaton "
        "that the chaos game and the tolerance traversal sample (mesh it: cifs render, cifs attractor)");
  int refined = 0;
  subdivision::FractalSurface fractal =
      mesh_automaton(m, e.perturbation ? &*e.perturbation : nullptr, 2, o, report, refined);
  subdivision::SurfaceAutomaton& surface = fractal.surface;
  kind = (e.perturbation ? "fractal " : "") + scheme + " surface of " + file + ", its automaton after " +
         std::to_string(refined) + " level(s) of refinement";
  Scene scene;
  scene.depth = depth.value_or(std::max(m.levels - refined, 0));
  if (meshed) {
    ifs::MeshOptions mo;
    mo.max_bytes = o.max_bytes;
    scene.mesh = subdivision::surface_automaton_mesh(fractal, scene.depth, mo);
  }
  scene.automaton = std::move(surface.automaton);
  scene.nets = std::move(surface.nets);
  return scene;
}

}  // namespace cifs::experiment::detail
