// SPDX-License-Identifier: MIT
#include "cifs/view/document.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <future>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/ifs/bcifs_surface.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/io/io.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/render/point_ifs.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/rules.hpp"

namespace cifs::view {

namespace {

std::string where(const Document& d) {
  return d.path.filename().string();
}

/// The Cartesian rows of a shape's stored points (homogeneous rows divided by their weight).
Point cartesian_row(const Points& P, Eigen::Index row, bool rational) {
  const Eigen::Index dim = P.cols() - (rational ? 1 : 0);
  Point p = P.row(row).head(dim).transpose();
  if (rational) p /= P(row, dim);
  return p;
}

void append_xyz(std::vector<float>& out, const Eigen::Ref<const Eigen::RowVectorXd>& row) {
  for (Eigen::Index k = 0; k < 3; ++k) out.push_back(k < row.size() ? static_cast<float>(row(k)) : 0.0F);
}

/// The rows as float x, y, z (z = 0 for 2-D rows) at `out`, in one pass.
void write_xyz(const Eigen::Ref<const Points>& rows, float* out) {
  if (rows.cols() == 3 && rows.outerStride() == 3) {  // contiguous x, y, z: one run, which vectorises
    const double* in = rows.data();
    for (Eigen::Index e = 0; e < 3 * rows.rows(); ++e) out[e] = static_cast<float>(in[e]);
    return;
  }
  const Eigen::Index dim = std::min<Eigen::Index>(rows.cols(), 3);
  for (Eigen::Index i = 0; i < rows.rows(); ++i, out += 3)
    for (Eigen::Index k = 0; k < 3; ++k) out[k] = k < dim ? static_cast<float>(rows(i, k)) : 0.0F;
}

/// `positions` set to the points as float x, y, z: storage of the size is written over in place (an
/// edit's buffer reused: no allocation, no zero fill).
void set_xyz(std::vector<float>& positions, const Eigen::Ref<const Points>& points) {
  positions.resize(3 * static_cast<std::size_t>(points.rows()));
  write_xyz(points, positions.data());
}

/// Moves stored row `row` to the Cartesian `position`, keeping its weight.
void move_row(Points& P, Eigen::Index row, bool rational, const std::vector<double>& position,
              const std::string& who) {
  const Eigen::Index dim = P.cols() - (rational ? 1 : 0);
  if (static_cast<Eigen::Index>(position.size()) != dim)
    throw InvalidInput(who + ": " + std::to_string(position.size()) + " coordinates for a " +
                       std::to_string(dim) + "-D point");
  const double w = rational ? P(row, dim) : 1.0;
  for (Eigen::Index k = 0; k < dim; ++k) {
    if (!std::isfinite(position[k])) throw InvalidInput(who + ": a coordinate is not a finite number");
    P(row, k) = w * position[k];
  }
}

std::string point_who(const Document& d, std::size_t index) {
  return where(d) + ": point " + std::to_string(index);
}

}  // namespace

std::string_view kind_name(Kind kind) noexcept {
  switch (kind) {
    case Kind::curve:
      return "curve";
    case Kind::surface:
      return "surface";
    case Kind::mesh:
      return "mesh";
    case Kind::bcifs:
      return "bcifs";
    case Kind::subdivision:
      return "subdivision";
    case Kind::junction:
      return "junction";
    case Kind::ifs:
      return "ifs";
  }
  return "?";
}

std::shared_ptr<const PerturbableSystem> shape_system(const io::Shape& shape, bool keep_vertices) {
  auto out = std::make_shared<PerturbableSystem>();
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    const nurbs::KnotAutomaton knots = nurbs::knot_automaton(*c);
    out->system = ifs::curve_bcifs(*c, {.free_vertices = !keep_vertices});
    out->nets = nurbs::initial_nets(knots, *c);  // the BC-IFS keeps the knot automaton's initial entries
    out->rational = c->rational;
    out->closed = c->closed;
  } else {
    const auto& s = std::get<nurbs::Surface>(shape);
    const nurbs::TensorAutomaton ta = nurbs::tensor_automaton(s);
    out->system = ifs::surface_bcifs(ta, {.free_knot_lines = !keep_vertices});
    out->nets = nurbs::initial_nets(ta, s);
    out->patches = ta.patches;
    out->rational = s.rational;
  }
  out->space = ifs::admissible_space(out->system);
  out->names = ifs::free_names(out->system, out->space);
  return out;
}

namespace {

/// A BC-IFS file's system, its nets given (the runner refuses a file without them).
std::shared_ptr<const PerturbableSystem> file_system(const std::filesystem::path& path) {
  io::BcifsFile file = io::read_bcifs(path);
  if (file.nets.size() != file.system.automaton.initial.size())
    throw InvalidInput(path.string() + ": the file gives no control nets for its initial states");
  auto out = std::make_shared<PerturbableSystem>();
  out->system = std::move(file.system);
  out->nets = std::move(file.nets);
  out->space = ifs::admissible_space(out->system);
  out->names = ifs::free_names(out->system, out->space);
  return out;
}

ifs::PerturbOptions perturb_options(double amplitude, std::uint64_t seed,
                                    const std::map<std::string, double>& values) {
  ifs::PerturbOptions o;
  o.amplitude = amplitude;
  o.seed = seed;
  o.values = values;
  o.contraction.bound = false;  // the runner's check: contractivity only (experiment::evaluate's perturb)
  return o;
}

/// The sliders of a document: `names`' ranges around the file's perturbation, or the refusal of the file's
/// own system (not contractive, say), which the page shows.
void add_coefficients(Document& d, const PerturbableSystem& system, const std::vector<std::string>& names) {
  const ifs::PerturbOptions base =
      perturb_options(d.perturbation.amplitude, d.perturbation.seed, d.perturbation.values);
  try {
    (void)ifs::perturb(system.system, system.space, base);
  } catch (const InvalidInput& e) {
    d.refusal = e.what();
    return;
  }
  for (const std::string& name : names) d.coefficients.push_back(coefficient_range(system, name, base));
}

}  // namespace

CoefficientRange coefficient_range(const PerturbableSystem& system, const std::string& name,
                                   const ifs::PerturbOptions& base, const RangeOptions& options) {
  const ifs::Perturbation at = ifs::perturb(system.system, system.space, base);
  const auto it =
      std::find_if(at.values.begin(), at.values.end(), [&](const auto& v) { return v.first == name; });
  if (it == at.values.end()) throw InvalidInput("\"" + name + "\" is not a free coefficient of the system");
  CoefficientRange out{
      .name = name, .value = it->second, .low = it->second, .high = it->second, .capped = false};
  ifs::FailingPaths failing;  // the probes check one automaton, one coefficient moved: kept between them
  const auto accepted = [&](double value) {
    ifs::PerturbOptions o = base;
    o.values[name] = value;
    try {
      (void)ifs::perturb(system.system, system.space, o, failing);
      return true;
    } catch (const InvalidInput&) {  // not contractive, or the constraints missed: what the runner refuses
      return false;
    }
  };
  for (const double sign : {-1.0, 1.0}) {
    double good = 0, bad = 0, step = options.first_step;
    for (;;) {
      const double t = std::min(step, options.reach);
      if (!accepted(out.value + sign * t)) {
        bad = t;
        break;
      }
      good = t;
      if (t >= options.reach) break;
      step *= 2;
    }
    if (bad == 0) {
      out.capped = true;
    } else {
      for (int k = 0; k < options.bisections; ++k) {
        const double mid = 0.5 * (good + bad);
        (accepted(out.value + sign * mid) ? good : bad) = mid;
      }
    }
    (sign < 0 ? out.low : out.high) = out.value + sign * good;
  }
  return out;
}

Document open_document(const std::filesystem::path& path, const Limits& limits) {
  Document d;
  d.path = path;
  switch (io::detect(path)) {
    case io::Content::mesh:
      d.kind = Kind::mesh;
      d.mesh = io::read_mesh(path);
      return d;
    case io::Content::shape:
      d.shape = io::read_shape(path);
      d.kind = std::holds_alternative<nurbs::Curve>(*d.shape) ? Kind::curve : Kind::surface;
      return d;
    case io::Content::bcifs:
      d.kind = Kind::bcifs;
      d.bcifs = file_system(path);
      break;
    case io::Content::experiment: {
      io::Experiment e = io::read_experiment(path);
      if (e.shape) {
        d.shape = e.shape;
        d.kind = std::holds_alternative<nurbs::Curve>(*d.shape) ? Kind::curve : Kind::surface;
      } else if (!e.automaton.empty()) {
        d.kind = Kind::bcifs;
        d.bcifs = file_system(e.automaton);
      } else {  // drawn by the runner's scene (experiment::draw)
        d.kind = e.mesh ? Kind::subdivision : e.junction ? Kind::junction : Kind::ifs;
      }
      d.experiment_text = read_file(path);
      if (e.perturbation) {
        d.perturbation = *e.perturbation;
        d.perturbed = true;
      }
      d.experiment = std::move(e);
      break;
    }
    default:
      throw InvalidInput(path.string() +
                         ": cifs view shows shapes (curves, surfaces), polygon meshes, BC-IFS and experiment "
                         "files; open the shape this file names");
  }
  if (d.bcifs) {  // every free coefficient a slider (within max_sliders), with its range
    if (d.bcifs->names.size() <= limits.max_sliders)
      add_coefficients(d, *d.bcifs, d.bcifs->names);
    else
      add_coefficients(d, *d.bcifs, {});
  } else if (d.perturbed && !d.perturbation.values.empty()) {  // a shape's experiment: the values it sets
    std::vector<std::string> names;
    for (const auto& [name, value] : d.perturbation.values) names.push_back(name);
    add_coefficients(d, *shape_system(*d.shape, d.perturbation.keep_vertices), names);
  }
  return d;
}

std::vector<std::string_view> document_extensions() {
  std::vector<std::string_view> out;
  // What open_document shows.
  for (const io::Content content :
       {io::Content::shape, io::Content::mesh, io::Content::bcifs, io::Content::experiment})
    for (const io::Format& f : io::formats(content))
      if (f.read && std::find(out.begin(), out.end(), f.extension) == out.end()) out.push_back(f.extension);
  return out;
}

namespace {

/// The deepest depth whose (#maps)^depth points are at most `points` (hutchinson_points' count).
int ifs_depth(const io::ClassicIfs& ifs, double points) {
  const auto maps = static_cast<double>(ifs.name.empty() ? ifs.maps.size() : ifs::named_ifs(ifs.name).size());
  if (maps <= 1) return 30;
  int depth = 0;
  while (depth < 30 && std::pow(maps, depth + 1) <= points) ++depth;
  return depth;
}

}  // namespace

int max_depth(const Document& document, const Limits& limits) {
  switch (document.kind) {
    case Kind::curve:
      return limits.max_depth_curve;
    case Kind::surface:
      return limits.max_depth_surface;
    case Kind::bcifs:
      return limits.max_depth_bcifs;
    case Kind::junction:
      return limits.max_depth_junction;
    case Kind::ifs:
      return ifs_depth(*document.experiment->ifs, static_cast<double>(limits.max_points));
    case Kind::mesh:
    case Kind::subdivision:
      break;
  }
  return 0;
}

double max_amplitude(const Document& document) {
  if (document.kind == Kind::subdivision || document.kind == Kind::junction)
    return std::max(1.0, 2 * document.perturbation.amplitude);
  return 1;
}

Params default_params(const Document& document) {
  Params p;
  if (document.kind == Kind::curve) {
    const int segments = std::max(1, nurbs::segment_count(std::get<nurbs::Curve>(*document.shape)));
    p.depth = std::clamp(static_cast<int>(std::lround(std::log2(1e4 / segments))), 0, 16);
  } else if (document.kind == Kind::surface) {
    const auto& s = std::get<nurbs::Surface>(*document.shape);
    const double patches =
        static_cast<double>(s.count[0] - s.degree[0]) * static_cast<double>(s.count[1] - s.degree[1]);
    p.depth = std::clamp(static_cast<int>(std::lround(0.5 * std::log2(1e4 / std::max(1.0, patches)))), 0, 7);
  } else if (document.kind == Kind::bcifs) {
    // The deepest depth with at most 10^4 pieces: nodes counted per state, level by level.
    const auto& a = document.bcifs->system.automaton;
    std::vector<double> count(num_vertices(a.graph), 1.0), next(count.size());
    const auto total = [&] {
      double n = 0;
      for (const auto& i : a.initial) n += count[i.state];
      return n;
    };
    while (p.depth < 16) {
      for (automata::StateId s = 0; s < count.size(); ++s) {
        next[s] = 0;
        for (auto [b, e] = out_edges(s, a.graph); b != e; ++b) next[s] += count[target(*b, a.graph)];
      }
      std::swap(count, next);
      if (total() > 1e4) break;
      ++p.depth;
    }
  } else if (document.kind == Kind::subdivision) {
    const io::MeshSource& m = *document.experiment->mesh;
    p.scheme = subdivision::scheme_name(m.scheme);
    p.levels = std::min(m.levels, Limits{}.max_levels);
  } else if (document.kind == Kind::junction || document.kind == Kind::ifs) {
    // Unless the file evaluates to a depth (below): a chaos game's file.
    p.depth = document.kind == Kind::junction ? 5 : ifs_depth(*document.experiment->ifs, 1e5);
  } else {
    const auto& o = document.mesh.face_offsets;
    bool triangles = true;
    for (std::size_t f = 0; f + 1 < o.size(); ++f) triangles = triangles && o[f + 1] - o[f] == 3;
    p.scheme = triangles ? "loop" : "catmull-clark";
    p.levels = 1;
  }
  // An experiment's own depth (a mesh's levels: above) and perturbation; the view's limits apply.
  if (document.experiment && document.kind != Kind::subdivision) {
    if (document.experiment->evaluation.mode == io::EvaluationSpec::Mode::depth)
      p.depth = document.experiment->evaluation.depth;
    if (document.kind == Kind::junction || document.kind == Kind::ifs)
      p.depth = std::min(p.depth, max_depth(document, {}));
  }
  p.amplitude = document.perturbation.amplitude;
  p.seed = document.perturbation.seed;
  p.values = document.perturbation.values;
  return p;
}

bool perturbed(const Document& document, const Params& params) {
  return document.perturbed || params.amplitude != 0 || !params.values.empty();
}

std::vector<std::vector<double>> shape_knots(const io::Shape& shape) {
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) return {nurbs::defining_knots(*c)};
  const auto& s = std::get<nurbs::Surface>(shape);
  return {s.knots[0], s.knots[1]};
}

namespace {

/// The knot lists of `params` into the shape (as many values as the file's: the number of control points
/// stays), each direction checked by the library's own validation.
void set_knots(const Document& d, io::Shape& shape, const std::vector<std::vector<double>>& knots) {
  if (knots.empty()) return;
  const std::vector<std::vector<double>> file = shape_knots(shape);
  if (knots.size() != file.size())
    throw InvalidInput(where(d) + ": knots: " + std::to_string(knots.size()) + " lists for a " +
                       (file.size() == 1 ? "curve (one list)" : "surface (two lists: u, v)"));
  for (std::size_t k = 0; k < knots.size(); ++k)
    if (knots[k].size() != file[k].size())
      throw InvalidInput(where(d) + ": knots" + (file.size() == 1 ? "" : "[" + std::to_string(k) + "]") +
                         ": " + std::to_string(knots[k].size()) + " values, the file's " +
                         std::to_string(file[k].size()) + " (control points are not added or removed here)");
  if (auto* c = std::get_if<nurbs::Curve>(&shape)) {
    if (!c->closed) {
      c->knots = knots[0];
      nurbs::validate_knots(c->knots, c->degree, c->P.rows(), where(d) + ": knots");
      return;
    }
    // A closed curve's knot vector is its breakpoints extended by the period: make_closed_curve's, which
    // checks the breakpoints (the seam's multiplicity too). It reads the points only for their number: the
    // stored rows go in as they are, so none is rounded through a division by its weight.
    try {
      c->knots = nurbs::make_closed_curve(c->degree, knots[0], c->P.topRows(nurbs::distinct_count(*c))).knots;
    } catch (const InvalidInput& e) {
      throw InvalidInput(where(d) + ": " + e.what());
    }
    return;
  }
  auto& s = std::get<nurbs::Surface>(shape);
  for (int k = 0; k < 2; ++k) {
    s.knots[k] = knots[k];
    nurbs::validate_knots(s.knots[k], s.degree[k], s.count[k],
                          where(d) + ": knots[" + std::to_string(k) + "]");
  }
}

/// Stored row `row` with weight `weight`, its Cartesian point kept (a non-rational shape made rational).
void set_weight(Points& P, bool& rational, Eigen::Index row, double weight, const std::string& who) {
  if (!(weight > 0) || !std::isfinite(weight))
    throw InvalidInput(who + ": weight " + number_text(weight) + " is not a positive finite number");
  if (!rational) {  // every row gets weight 1: its coordinates times 1, exact
    P.conservativeResize(Eigen::NoChange, P.cols() + 1);
    P.col(P.cols() - 1).setOnes();
    rational = true;
  }
  const Eigen::Index dim = P.cols() - 1;
  const double old = P(row, dim);
  if (old == weight) return;
  // The Cartesian point (as cartesian_points and a written file have it) times the new weight: what
  // make_curve, and reading the saved file, make of that row.
  const Eigen::RowVectorXd x = P.row(row).head(dim) / old;
  P.row(row).head(dim) = x * weight;
  P(row, dim) = weight;
}

}  // namespace

io::Shape edited_shape(const Document& document, const Params& params) {
  if (!document.shape) throw InvalidInput(where(document) + ": not a shape");
  io::Shape shape = *document.shape;
  set_knots(document, shape, params.knots);
  if (auto* c = std::get_if<nurbs::Curve>(&shape)) {
    const auto m = static_cast<std::size_t>(nurbs::distinct_count(*c));
    for (const WeightEdit& e : params.weights) {
      if (e.index >= m)
        throw InvalidInput(point_who(document, e.index) + ": the curve has " + std::to_string(m) +
                           " control points");
      for (Eigen::Index r = static_cast<Eigen::Index>(e.index); r < c->P.rows();
           r += static_cast<Eigen::Index>(m)) {
        bool rational = c->rational;
        set_weight(c->P, rational, r, e.weight, point_who(document, e.index));
        c->rational = rational;
      }
    }
    for (const PointEdit& e : params.points) {
      if (e.index >= m)
        throw InvalidInput(point_who(document, e.index) + ": the curve has " + std::to_string(m) +
                           " control points");
      for (Eigen::Index r = static_cast<Eigen::Index>(e.index); r < c->P.rows();
           r += static_cast<Eigen::Index>(m))
        move_row(c->P, r, c->rational, e.position, point_who(document, e.index));
    }
    nurbs::validate(*c);
  } else {
    auto& s = std::get<nurbs::Surface>(shape);
    const auto n = static_cast<std::size_t>(s.P.rows());
    for (const WeightEdit& e : params.weights) {
      if (e.index >= n)
        throw InvalidInput(point_who(document, e.index) + ": the surface has " + std::to_string(n) +
                           " control points");
      set_weight(s.P, s.rational, static_cast<Eigen::Index>(e.index), e.weight, point_who(document, e.index));
    }
    for (const PointEdit& e : params.points) {
      if (e.index >= n)
        throw InvalidInput(point_who(document, e.index) + ": the surface has " + std::to_string(n) +
                           " control points");
      move_row(s.P, static_cast<Eigen::Index>(e.index), s.rational, e.position, point_who(document, e.index));
    }
    nurbs::validate(s);
  }
  return shape;
}

Mesh edited_mesh(const Document& document, const Params& params) {
  Mesh mesh = document.mesh;
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  for (const PointEdit& e : params.points) {
    if (e.index >= n)
      throw InvalidInput(point_who(document, e.index) + ": the mesh has " + std::to_string(n) + " vertices");
    move_row(mesh.vertices, static_cast<Eigen::Index>(e.index), false, e.position,
             point_who(document, e.index));
  }
  return mesh;
}

namespace {

/// Rows equal bit for bit (a copy of the same point, not two points that happen to be close).
bool same_row(const Points& a, Eigen::Index i, const Points& b, Eigen::Index j) {
  for (Eigen::Index k = 0; k < a.cols(); ++k)
    if (std::bit_cast<std::uint64_t>(a(i, k)) != std::bit_cast<std::uint64_t>(b(j, k))) return false;
  return true;
}

std::string net_point(std::size_t net, std::size_t index) {
  return "net " + std::to_string(net) + " point " + std::to_string(index);
}

}  // namespace

std::vector<Points> edited_nets(const Document& document, const Params& params) {
  if (!document.bcifs) throw InvalidInput(where(document) + ": not a BC-IFS file");
  const std::vector<Points>& file = document.bcifs->nets;
  std::vector<Points> nets = file;
  // The edit that placed each row (net, point): a second one may not move the same point elsewhere.
  std::map<std::pair<std::size_t, Eigen::Index>, std::size_t> placed;
  for (std::size_t e = 0; e < params.nets.size(); ++e) {
    const NetEdit& edit = params.nets[e];
    const std::string who = where(document) + ": " + net_point(edit.net, edit.index);
    if (edit.net >= file.size())
      throw InvalidInput(who + ": the file has " + std::to_string(file.size()) + " control nets");
    const Points& net = file[edit.net];
    if (edit.index >= static_cast<std::size_t>(net.rows()))
      throw InvalidInput(who + ": the net has " + std::to_string(net.rows()) + " points");
    const auto row = static_cast<Eigen::Index>(edit.index);
    Points moved = net.row(row);
    move_row(moved, 0, false, edit.position, who);  // checks the coordinates: as many as the columns, finite
    const Eigen::RowVectorXd position = moved.row(0);
    // The point and its copies in the other nets.
    for (std::size_t m = 0; m < file.size(); ++m)
      for (Eigen::Index j = 0; j < file[m].rows(); ++j) {
        if (m == edit.net ? j != row : !same_row(net, row, file[m], j)) continue;
        const auto [at, fresh] = placed.try_emplace({m, j}, e);
        if (!fresh && nets[m].row(j) != position)
          throw InvalidInput(
              who + " and " + net_point(params.nets[at->second].net, params.nets[at->second].index) +
              " are one point of the file's nets (the pieces join there): two positions given");
        nets[m].row(j) = position;
      }
  }
  ifs::check_nets(document.bcifs->system.automaton, nets, "view");
  return nets;
}

namespace {

void check_range(const std::string& who, int value, int high) {
  if (value < 0 || value > high)
    throw InvalidInput(who + " " + std::to_string(value) + " is outside 0.." + std::to_string(high) +
                       " (the view's limit)");
}

/// The attractor points at the depth with the states of their pieces (ifs::sample_attractor's, chunk by
/// chunk: for_each_sample_chunk is its route) written as floats straight into g's buffers, with no
/// whole sample of doubles between; the end point takes its piece's state.
void sample_geometry(const automata::Automaton& automaton, std::span<const Points> nets, int depth,
                     bool homogeneous, bool closed, const Limits& limits, Geometry& g) {
  std::size_t n = 0, at = 0;
  g.states.clear();
  ifs::for_each_sample_chunk(
      automaton, nets,
      {.depth = depth,
       .homogeneous = homogeneous,
       .closed = closed,
       .states = true,
       .max_points = limits.max_points,
       .limit_hint = "; lower the depth"},
      std::size_t{1} << 16,
      [&](std::size_t points, int) {
        n = points;
        g.positions.resize(3 * n);
        g.states.reserve(n);
      },
      [&](const Eigen::Ref<const Points>& rows, std::span<const std::uint32_t> states) {
        write_xyz(rows, g.positions.data() + 3 * at);
        at += static_cast<std::size_t>(rows.rows());
        g.states.insert(g.states.end(), states.begin(), states.end());
      });
  if (!g.states.empty()) g.states.resize(n, g.states.back());
  g.closed = closed;
}

/// A key naming the document (its path and what the experiment keeps), for the cache's entries.
std::string document_key(const Document& d) {
  return d.path.string() + (d.perturbation.keep_vertices ? "|k" : "|f");
}

/// The values, bit for bit (hexadecimal floating point), for a cache key.
void append_key(std::string& key, std::span<const double> values) {
  for (const double x : values) {
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), " %a", x);
    key += text.data();
  }
  key += '|';
}

/// The key of the edited shape's automaton: the document and all that knot_automaton and tensor_automaton
/// read — the degrees, the knots (a knot edit builds another automaton) and the numbers of points; not the
/// points nor the weights, which the view's edits of points and weights change.
std::string automaton_key(const Document& d, const io::Shape& shape) {
  std::string key = document_key(d) + "|";
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    key += std::to_string(c->degree) + (c->closed ? "c" : "o") + std::to_string(c->P.rows());
    append_key(key, c->knots);
    return key;
  }
  const auto& s = std::get<nurbs::Surface>(shape);
  for (int k = 0; k < 2; ++k) {
    key += std::to_string(s.degree[k]) + "," + std::to_string(s.count[k]);
    append_key(key, s.knots[k]);
  }
  return key;
}

/// The automaton of the document's edited curve or surface: the cache's when built from the same knots
/// (automaton_key), else built — into the cache when there is one, else into `local`.
template <class Automaton, class Shape, class Build>
const Automaton& cached_automaton(const Document& d, const Shape& shape, EditCache* cache,
                                  std::optional<Automaton> EditCache::*slot, std::optional<Automaton>& local,
                                  Build build) {
  if (cache == nullptr) return local.emplace(build(shape));
  std::string key = automaton_key(d, shape);
  if (cache->automaton_key != key || !(cache->*slot)) {
    cache->knots.reset();
    cache->tensor.reset();
    cache->automaton_key.clear();
    (cache->*slot).emplace(build(shape));
    cache->automaton_key = std::move(key);
  }
  return *(cache->*slot);
}

void curve_geometry(const Document& d, const nurbs::Curve& c, const Params& params, const Limits& limits,
                    EditCache* cache, Geometry& g) {
  std::optional<nurbs::KnotAutomaton> local;
  const nurbs::KnotAutomaton& a = cached_automaton(
      d, c, cache, &EditCache::knots, local, [](const nurbs::Curve& x) { return nurbs::knot_automaton(x); });
  // ifs::attractor's call, with the states of the pieces.
  sample_geometry(a.automaton, nurbs::initial_nets(a, c), params.depth, c.rational, c.closed, limits, g);
}

/// A state per node of a quad mesh of ifs::surface_mesh's (or quad_mesh's) grid layout.
void node_states(const Mesh& mesh, std::vector<std::uint32_t>& states) {
  const std::size_t faces = mesh.face_offsets.size() - 1;
  constexpr std::uint32_t kUnset = 0xffffffffU;
  states.assign(static_cast<std::size_t>(mesh.vertices.rows()), kUnset);
  // Node (I, J) is computed by the leaf of cell (I, J), corner 0 of its quad; the last row and column
  // take a neighbouring leaf's state.
  for (std::size_t f = 0; f < faces; ++f) states[mesh.face_vertices[4 * f]] = mesh.states[f];
  for (std::size_t f = 0; f < faces; ++f)
    for (int k = 1; k < 4; ++k)
      if (states[mesh.face_vertices[4 * f + k]] == kUnset)
        states[mesh.face_vertices[4 * f + k]] = mesh.states[f];
}

/// A quad mesh of ifs::surface_mesh's (or quad_mesh's) grid layout as positions and the grid's size (the
/// states: node_states).
void grid_geometry(const Mesh& mesh, Geometry& g) {
  const auto n = static_cast<std::size_t>(mesh.vertices.rows());
  const std::size_t faces = mesh.face_offsets.size() - 1;
  set_xyz(g.positions, mesh.vertices);
  // The faces are the grid's cells (ifs::surface_mesh's layout: node (I, J) is vertex I·cols + J, face 0
  // has the corners 0, cols, cols + 1, 1): the page makes the triangles from the grid's size once per
  // depth, and the 6 indices per cell are not sent with every edit.
  const auto cols = static_cast<std::uint32_t>(mesh.face_vertices[1]);
  const auto rows = static_cast<std::uint32_t>(n / cols);
  if (std::size_t{rows} * cols != n || std::size_t{rows - 1} * (cols - 1) != faces)
    throw std::logic_error("view: the surface mesh is not ifs::surface_mesh's grid");
  g.grid = {rows, cols};
}

/// Meshes a surface by `route` (ifs::surface_mesh or ifs::quad_mesh, called with the mesh and options)
/// into the cache's mesh — its storage reused, its faces and states (and the node states made from them)
/// kept when the same route made them at the same depth for this document (they depend on the automaton's
/// graph and the depth, not on the nets) — or into a fresh one, then writes the grid into g.
template <class Route>
void cached_grid(const Document& d, const io::Shape& shape, std::string_view route_name, int depth,
                 ifs::MeshOptions options, EditCache* cache, Geometry& g, Route route) {
  if (cache == nullptr) {
    Mesh mesh;
    route(mesh, options);
    grid_geometry(mesh, g);
    node_states(mesh, g.states);
    return;
  }
  const std::string key = automaton_key(d, shape) + std::string(route_name) + "|" + std::to_string(depth);
  options.keep_faces = cache->mesh_key == key;
  cache->mesh_key.clear();  // until the mesh is whole again (a refusal mid-way leaves vertices half written)
  route(cache->mesh, options);
  if (!options.keep_faces) node_states(cache->mesh, cache->node_states);
  cache->mesh_key = key;
  grid_geometry(cache->mesh, g);
  g.states = cache->node_states;  // into g's storage: a copy, no allocation at the same size
}

/// ifs::attractor's calls for a surface (its tensor automaton, nets and separable mesh).
void surface_geometry(const Document& d, const nurbs::Surface& s, const Params& params, const Limits& limits,
                      EditCache* cache, Geometry& g) {
  std::optional<nurbs::TensorAutomaton> local;
  const nurbs::TensorAutomaton& a =
      cached_automaton(d, s, cache, &EditCache::tensor, local,
                       [](const nurbs::Surface& x) { return nurbs::tensor_automaton(x); });
  const std::vector<Points> nets = nurbs::initial_nets(a, s);
  ifs::MeshOptions options;
  options.homogeneous = s.rational;
  options.max_bytes = ifs::mesh_bytes(limits.max_points, 3, limits.max_points);
  cached_grid(d, s, "separable", params.depth, options, cache, g, [&](Mesh& mesh, const ifs::MeshOptions& o) {
    ifs::surface_mesh(a, nets, params.depth, mesh, o);
  });
}

/// The control polygon (the distinct points of a closed curve) or the control grid, Cartesian.
void append_net(const io::Shape& shape, Geometry& g) {
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) {
    const Eigen::Index m = nurbs::distinct_count(*c);
    for (Eigen::Index i = 0; i < m; ++i) append_xyz(g.net, cartesian_row(c->P, i, c->rational).transpose());
    for (std::uint32_t i = 0; i + 1 < static_cast<std::uint32_t>(m); ++i)
      g.net_lines.insert(g.net_lines.end(), {i, i + 1});
    if (c->closed && m > 1) g.net_lines.insert(g.net_lines.end(), {static_cast<std::uint32_t>(m - 1), 0});
    return;
  }
  const auto& s = std::get<nurbs::Surface>(shape);
  const Eigen::Index nu = s.count[0], nv = s.count[1];
  for (Eigen::Index i = 0; i < s.P.rows(); ++i)
    append_xyz(g.net, cartesian_row(s.P, i, s.rational).transpose());
  for (Eigen::Index i = 0; i < nu; ++i)
    for (Eigen::Index j = 0; j < nv; ++j) {
      const auto here = static_cast<std::uint32_t>(i * nv + j);
      if (j + 1 < nv) g.net_lines.insert(g.net_lines.end(), {here, here + 1});
      if (i + 1 < nu) g.net_lines.insert(g.net_lines.end(), {here, here + static_cast<std::uint32_t>(nv)});
    }
}

/// Faces as triangle fans, holes left out.
void append_faces(const Mesh& mesh, std::vector<std::uint32_t>& triangles) {
  const std::vector<char> hole = hole_flags(mesh);
  for (std::size_t f = 0; f + 1 < mesh.face_offsets.size(); ++f) {
    if (!hole.empty() && hole[f] != 0) continue;
    const int begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (int k = begin + 1; k + 1 < end; ++k)
      triangles.insert(triangles.end(), {static_cast<std::uint32_t>(mesh.face_vertices[begin]),
                                         static_cast<std::uint32_t>(mesh.face_vertices[k]),
                                         static_cast<std::uint32_t>(mesh.face_vertices[k + 1])});
  }
}

void mesh_geometry(const Document& document, const Params& params, const Limits& limits, Geometry& g) {
  const Mesh control = edited_mesh(document, params);
  subdivision::MeshOptions options;
  options.max_bytes = 64 * limits.max_points;  // about 64 bytes per vertex
  const Mesh refined =
      subdivision::subdivide(control, subdivision::named_mesh_scheme(params.scheme), params.levels, options);
  set_xyz(g.positions, refined.vertices);
  g.states.clear();  // a mesh's vertices have no automaton state
  append_faces(refined, g.triangles);
  for (Eigen::Index i = 0; i < control.vertices.rows(); ++i) append_xyz(g.net, control.vertices.row(i));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // each edge once
  for (std::size_t f = 0; f + 1 < control.face_offsets.size(); ++f) {
    const int begin = control.face_offsets[f], end = control.face_offsets[f + 1];
    for (int k = begin; k < end; ++k) {
      const auto a = static_cast<std::uint32_t>(control.face_vertices[k]);
      const auto b = static_cast<std::uint32_t>(control.face_vertices[k + 1 < end ? k + 1 : begin]);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) g.net_lines.insert(g.net_lines.end(), {a, b});
}

/// Refuses a value outside its slider's range (coefficient_range) before any work.
void check_values(const Document& d, const Params& params) {
  for (const auto& [name, value] : params.values) {
    if (!std::isfinite(value)) throw InvalidInput(name + ": the value is not a finite number");
    for (const CoefficientRange& r : d.coefficients)
      if (r.name == name && (value < r.low || value > r.high))
        throw InvalidInput(name + " = " + number_text(value, 6) + " is outside its admissible range [" +
                           number_text(r.low, 6) + ", " + number_text(r.high, 6) + "]");
  }
}

void note_contraction(const ifs::Contraction& c, Geometry& g) {
  g.contraction_length = c.m;
  g.contraction_delta = c.delta;
}

/// The perturbed system of an edit (ifs::perturb), its constraint residuals checked and then the system
/// evaluated by `evaluate(system)` while its contractivity is checked on another thread — the two halves
/// of an edit's work, one per core —, with the failing paths the session kept (`cache`, if any: the same
/// result as without, sooner). The two threads share the perturbation: the check reads its system and
/// writes its `contraction` (and the cache's failing paths), this thread reads the system and writes its
/// `residual` (and the cache's mesh). Refusals come as perturb's would: the constraints', then the check's
/// (a system that is not contractive is not shown, whatever its evaluation did), then the evaluation's.
template <class Evaluate>
void perturbed_evaluation(const PerturbableSystem& system, const Params& params, EditCache* cache,
                          Geometry& g, Evaluate evaluate) {
  if (!std::isfinite(params.amplitude) || params.amplitude < 0 || params.amplitude > 1)
    throw InvalidInput("amplitude " + number_text(params.amplitude, 6) + " is outside 0..1");
  ifs::PerturbOptions o = perturb_options(params.amplitude, params.seed, params.values);
  o.check = false;
  ifs::Perturbation p = ifs::perturb(system.system, system.space, o);
  std::future<void> check = std::async(std::launch::async, [&] {
    ifs::check_contractive(p, o, cache != nullptr ? &cache->failing : nullptr);
  });
  try {
    ifs::check_residual(p);
  } catch (...) {
    check.wait();  // the constraints' refusal first: the check's outcome is not shown
    throw;
  }
  try {
    evaluate(std::as_const(p.system));
  } catch (...) {
    check.get();  // its refusal first
    throw;
  }
  check.get();
  note_contraction(p.contraction, g);
}

/// The key of a shape's perturbable system: the document and its edits of points, weights and knots (bit for
/// bit).
std::string system_key(const Document& d, const Params& params) {
  std::string key = document_key(d) + "|";
  for (const PointEdit& e : params.points) {
    key += "p" + std::to_string(e.index);
    append_key(key, e.position);
  }
  for (const WeightEdit& e : params.weights) {
    key += "w" + std::to_string(e.index);
    append_key(key, std::span(&e.weight, 1));
  }
  for (const std::vector<double>& knots : params.knots) {
    key += "k";
    append_key(key, knots);
  }
  return key;
}

/// The perturbed shape, as experiment::evaluate evaluates an experiment with that "perturbation" (the
/// runner's curve_scene and surface_scene: the same calls on the same system).
void perturbed_geometry(const Document& d, const io::Shape& shape, const Params& params, const Limits& limits,
                        EditCache* cache, Geometry& g) {
  std::shared_ptr<const PerturbableSystem> system;
  const std::string key = system_key(d, params);
  if (cache != nullptr && cache->system && cache->key == key) {
    system = cache->system;
  } else {
    system = shape_system(shape, d.perturbation.keep_vertices);
    if (cache != nullptr) {
      cache->key = key;
      cache->system = system;
    }
  }
  perturbed_evaluation(*system, params, cache, g, [&](const ifs::Bcifs& perturbed) {
    if (std::holds_alternative<nurbs::Curve>(shape)) {
      sample_geometry(perturbed.automaton, system->nets, params.depth, system->rational, system->closed,
                      limits, g);
      return;
    }
    ifs::MeshOptions mo;
    mo.homogeneous = system->rational;
    mo.max_bytes = ifs::mesh_bytes(limits.max_points, 3, limits.max_points);
    cached_grid(d, shape, "generic", params.depth, mo, cache, g, [&](Mesh& mesh, const ifs::MeshOptions& o) {
      ifs::quad_mesh(perturbed.automaton, system->nets, system->patches, params.depth, mesh, o);
    });
  });
}

/// A BC-IFS file's attractor as the runner draws it (bcifs_scene): the pieces' end points at the depth.
void bcifs_geometry(const Document& d, const Params& params, const Limits& limits, EditCache* cache,
                    Geometry& g) {
  const PerturbableSystem& system = *d.bcifs;
  const std::vector<Points> edited = params.nets.empty() ? std::vector<Points>() : edited_nets(d, params);
  const std::vector<Points>& nets = params.nets.empty() ? system.nets : edited;
  const auto pieces_of = [&](const ifs::Bcifs& drawn) {
    const Eigen::Index cols = nets.front().cols();
    const ifs::EdgePieces pieces = ifs::edge_pieces(
        drawn, nets, params.depth, limits.max_points * static_cast<std::size_t>(cols) * sizeof(double));
    const Eigen::Index n = pieces.start.rows();
    if (static_cast<std::size_t>(2 * n) > limits.max_points)
      throw InvalidInput(std::to_string(2 * n) + " points, above the view's limit of " +
                         std::to_string(limits.max_points) + "; lower the depth");
    g.positions.resize(6 * static_cast<std::size_t>(n));
    write_xyz(pieces.start, g.positions.data());
    write_xyz(pieces.end, g.positions.data() + 3 * n);
    g.pieces = static_cast<std::uint32_t>(n);
    g.states.clear();
    g.states.reserve(2 * static_cast<std::size_t>(n));
    for (int half = 0; half < 2; ++half)
      for (const automata::StateId s : pieces.state) g.states.push_back(static_cast<std::uint32_t>(s));
  };
  if (perturbed(d, params)) {
    perturbed_evaluation(system, params, cache, g, pieces_of);
  } else {  // the file's matrices are the user's: an attractor exists only when they shrink nets
    note_contraction(ifs::contraction(system.system.automaton, {.bound = false}), g);
    pieces_of(system.system);
  }
  // The control nets, each a polyline (the runner's control net).
  for (const Points& N : nets) {
    const auto first = static_cast<std::uint32_t>(g.net.size() / 3);
    for (Eigen::Index i = 0; i < N.rows(); ++i) append_xyz(g.net, N.row(i));
    for (std::uint32_t i = 0; i + 1 < static_cast<std::uint32_t>(N.rows()); ++i)
      g.net_lines.insert(g.net_lines.end(), {first + i, first + i + 1});
  }
}

/// The experiment of a document drawn by the runner, with the page's perturbation (the file's own members,
/// fractal_curves and keep_vertices, kept).
io::Experiment experiment_with(const Document& d, const Params& params) {
  io::Experiment e = *d.experiment;
  e.perturbation.reset();
  if (perturbed(d, params)) {
    io::PerturbationSpec spec = d.perturbation;
    spec.amplitude = params.amplitude;
    spec.seed = params.seed;
    spec.values = params.values;
    e.perturbation = std::move(spec);
  }
  return e;
}

/// A classic IFS: the points of its Hutchinson measure at the depth (what the runner bins), each with the
/// map applied last.
void ifs_geometry(const Document& d, const Params& params, const Limits& limits, Geometry& g) {
  if (perturbed(d, params))
    throw InvalidInput(where(d) + ": a classic IFS has no free coefficients to perturb (amplitude, values)");
  const experiment::Drawing drawing = experiment::draw(*d.experiment, params.depth);
  const render::HutchinsonPoints h =
      render::hutchinson_points(drawing.maps, static_cast<unsigned>(params.depth), limits.max_points);
  set_xyz(g.positions, h.points);
  g.states = h.map;
}

/// An experiment on a mesh or a junction: the runner's scene (experiment::draw) at the page's levels or
/// depth.
void drawing_geometry(const Document& d, const Params& params, const Limits& limits, Geometry& g) {
  if (!std::isfinite(params.amplitude) || params.amplitude < 0 || params.amplitude > max_amplitude(d))
    throw InvalidInput("amplitude " + number_text(params.amplitude, 6) + " is outside 0.." +
                       number_text(max_amplitude(d), 6));
  experiment::RunOptions options;
  options.max_bytes = 64 * limits.max_points;  // about 64 bytes per vertex, as for meshes
  const experiment::Drawing drawing = experiment::draw(
      experiment_with(d, params), d.kind == Kind::subdivision ? params.levels : params.depth, options);
  g.states.clear();
  if (drawing.mesh) {
    const Mesh& mesh = *drawing.mesh;
    set_xyz(g.positions, mesh.vertices);
    append_faces(mesh, g.triangles);
    // The runner colours a junction's faces by their state's side (a mesh source: one colour, no states):
    // a vertex takes the state of a face around it (the sides meet, unwelded).
    if (!drawing.state_colors.empty() && mesh.states.size() + 1 == mesh.face_offsets.size()) {
      g.states.assign(static_cast<std::size_t>(mesh.vertices.rows()), 0);
      for (std::size_t f = 0; f + 1 < mesh.face_offsets.size(); ++f)
        for (int k = mesh.face_offsets[f]; k < mesh.face_offsets[f + 1]; ++k)
          g.states[static_cast<std::size_t>(mesh.face_vertices[k])] = mesh.states[f];
    }
  } else {  // a junction's curves: segment i joins point i to point n + i (the runner's pieces)
    const Segments& s = *drawing.curves;
    const auto n = static_cast<std::uint32_t>(s.segments.size());
    for (std::uint32_t i = 0; i < n; ++i)
      if (s.segments[i][0] != static_cast<int>(i) || s.segments[i][1] != static_cast<int>(n + i))
        throw std::logic_error("view: the runner's segments are not pieces");
    set_xyz(g.positions, s.vertices);
    g.pieces = n;
    for (int half = 0; half < 2; ++half) g.states.insert(g.states.end(), s.states.begin(), s.states.end());
  }
  if (g.positions.size() / 3 > limits.max_points)
    throw InvalidInput(std::to_string(g.positions.size() / 3) + " points, above the view's limit of " +
                       std::to_string(limits.max_points) + "; lower the depth");
  g.state_colors = drawing.state_colors;
  for (Eigen::Index i = 0; i < drawing.control.vertices.rows(); ++i)
    append_xyz(g.net, drawing.control.vertices.row(i));
  for (const auto& [a, b] : drawing.control.segments)
    g.net_lines.insert(g.net_lines.end(), {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)});
}

}  // namespace

Geometry geometry(const Document& document, const Params& params, const Limits& limits, EditCache* cache) {
  Geometry g;
  geometry(document, params, limits, cache, g);
  return g;
}

void geometry(const Document& document, const Params& params, const Limits& limits, EditCache* cache,
              Geometry& g) {
  // Every field written: the large buffers (positions, states) by each route over their old storage,
  // the rest reset here.
  g.kind = document.kind;
  g.closed = false;
  g.triangles.clear();
  g.grid = {};
  g.net.clear();
  g.net_lines.clear();
  g.pieces = 0;
  g.contraction_length = 0;
  g.contraction_delta = 0;
  g.state_colors.clear();
  if (document.kind == Kind::subdivision) {
    check_range("levels", params.levels, limits.max_levels);
    drawing_geometry(document, params, limits, g);
  } else if (document.kind == Kind::junction || document.kind == Kind::ifs) {
    check_range("depth", params.depth, max_depth(document, limits));
    if (document.kind == Kind::ifs)
      ifs_geometry(document, params, limits, g);
    else
      drawing_geometry(document, params, limits, g);
  } else if (document.kind == Kind::mesh) {
    check_range("levels", params.levels, limits.max_levels);
    mesh_geometry(document, params, limits, g);
  } else if (document.kind == Kind::bcifs) {
    check_range("depth", params.depth, limits.max_depth_bcifs);
    check_values(document, params);
    bcifs_geometry(document, params, limits, cache, g);
  } else {
    const io::Shape shape = edited_shape(document, params);
    const auto* c = std::get_if<nurbs::Curve>(&shape);
    check_range("depth", params.depth, c != nullptr ? limits.max_depth_curve : limits.max_depth_surface);
    check_values(document, params);
    if (perturbed(document, params))
      perturbed_geometry(document, shape, params, limits, cache, g);
    else if (c != nullptr)
      curve_geometry(document, *c, params, limits, cache, g);
    else
      surface_geometry(document, std::get<nurbs::Surface>(shape), params, limits, cache, g);
    append_net(shape, g);
  }
  g.checksum = geometry_checksum(g.positions);
}

std::uint32_t geometry_checksum(const std::vector<float>& positions) noexcept {
  std::uint32_t h = 2166136261U;
  for (const float x : positions) h = (h ^ std::bit_cast<std::uint32_t>(x)) * 16777619U;
  return h;
}

namespace {
template <class T>
void append_bytes(std::string& out, const std::vector<T>& values) {
  static_assert(std::endian::native == std::endian::little, "the wire format is little-endian");
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}
}  // namespace

std::string encode_geometry(const Geometry& g) {
  const nlohmann::json header = {
      {"kind", kind_name(g.kind)},
      {"positions", g.positions.size()},
      {"closed", g.closed},
      {"triangles", g.triangles.size()},
      {"grid", g.grid},
      {"states", g.states.size()},
      {"net", g.net.size()},
      {"net_lines", g.net_lines.size()},
      {"pieces", g.pieces},
      {"state_colors", g.state_colors},
      {"contraction", {{"m", g.contraction_length}, {"delta", g.contraction_delta}}},
      {"checksum", g.checksum}};
  std::string text = header.dump();
  text.resize((text.size() + 12 + 3) / 4 * 4 - 12, ' ');  // the arrays start on a 4-byte boundary
  std::string out;
  // One allocation of the whole size, each part copied once (appending to a growing string copied the
  // megabytes already there at every reallocation, and resize zero-filled them before the copy).
  out.reserve(
      12 + text.size() +
      4 * (g.positions.size() + g.triangles.size() + g.states.size() + g.net.size() + g.net_lines.size()));
  out += "CIFSVIEW";
  const auto length = static_cast<std::uint32_t>(text.size());
  out.append(reinterpret_cast<const char*>(&length), 4);
  out += text;
  append_bytes(out, g.positions);
  append_bytes(out, g.triangles);
  append_bytes(out, g.states);
  append_bytes(out, g.net);
  append_bytes(out, g.net_lines);
  return out;
}

}  // namespace cifs::view
