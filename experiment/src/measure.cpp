// SPDX-License-Identifier: MIT
// cifs — an experiment's attractor for measurement (cifs dimension, Python): evaluated to a depth, or
// sampled to a tolerance, from the source run builds (scene.hpp); and that source's geometry as run draws
// it (cifs view); nothing drawn or written.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "cifs/errors.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/ifs/sample.hpp"
#include "scene.hpp"

namespace cifs::experiment {
namespace {

using detail::Geometry;
using detail::Scene;

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
  e.evaluation.mode = io::EvaluationSpec::Mode::depth;
  if (depth) e.evaluation.depth = *depth;
  if (e.evaluation.depth < 0)
    throw InvalidInput("the depth " + std::to_string(e.evaluation.depth) + " is negative; give a depth ≥ 0");
  RunReport report;
  Evaluation out;
  Scene scene = e.mesh ? detail::mesh_attractor(e, true, depth, o, report, out.kind)
                       : detail::build_source(e, o, report, out.kind, Geometry::evaluated);
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

Drawing draw(const io::Experiment& experiment, std::optional<int> depth, const RunOptions& o) {
  io::Experiment e = experiment;
  e.evaluation.mode = io::EvaluationSpec::Mode::depth;
  int& evaluated = e.mesh ? e.mesh->levels : e.evaluation.depth;
  if (depth) evaluated = *depth;
  if (evaluated < 0)
    throw InvalidInput("the depth " + std::to_string(evaluated) + " is negative; give a depth ≥ 0");
  RunReport report;
  std::string kind;
  Scene scene = detail::build_source(e, o, report, kind, Geometry::evaluated);
  Drawing out;
  out.mesh = std::move(scene.mesh);
  out.curves = std::move(scene.curves);
  if (scene.control) out.control = std::move(*scene.control);
  out.state_colors.assign(scene.state_colors.begin(), scene.state_colors.end());
  out.automaton = std::move(scene.automaton);
  out.maps = std::move(scene.maps);
  return out;
}

Evaluation sample(const io::Experiment& experiment, const SampleOptions& options, const RunOptions& o) {
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
    throw InvalidInput("the tolerance " +
                       (std::isfinite(options.tolerance) ? number_text(options.tolerance, 6) + " is negative"
                                                         : std::string("is not a finite number")) +
                       "; give a finite tolerance ≥ 0");
  RunReport report;
  Evaluation out;
  Scene scene = experiment.mesh ? detail::mesh_attractor(experiment, false, {}, o, report, out.kind)
                                : detail::build_source(experiment, o, report, out.kind, Geometry::skipped);
  ifs::ToleranceSampleOptions so;
  so.homogeneous = scene.rational;
  so.max_points = options.max_points;
  so.epsilon = options.tolerance * ifs::nets_diameter(scene.nets, scene.rational);
  so.tolerance_name = options.tolerance_name;
  const std::string given = std::string(options.tolerance_name) + " " + number_text(options.tolerance, 6);
  so.tolerance_text = given;
  so.limit_hint = options.limit_hint;
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
