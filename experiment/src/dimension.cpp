// SPDX-License-Identifier: MIT
#include "cifs/experiment/dimension.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/affine.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/sample.hpp"

namespace cifs::experiment {
namespace {

/// The sample is held in memory and its walk takes about 1 µs per point: a budget of 2^40 ran for days.
constexpr std::size_t kMaxPoints = 50'000'000;

/// The range the dimension is reported in: the box count ± its uncertainty, widened up to the
/// proven cover's growth where that lies above it (the box count's finite-scale bias is downward).
std::pair<double, double> dimension_range(const DimensionMeasurement& m) {
  const double lo = m.fit.dimension - m.uncertainty, hi = m.fit.dimension + m.uncertainty;
  return {lo, m.cover ? std::max(hi, m.cover->dimension) : hi};
}

std::string route_name(const DimensionMeasurement& m) {
  if (m.route == "tolerance")
    return "proven tolerance sample (every piece < " + number_text(m.resolution, 4) + ", deepest " +
           std::to_string(m.sample.depth) + ")";
  return "depth evaluation " + std::to_string(m.sample.depth) + " (pieces " +
         (m.estimated && m.resolution == 0 ? std::string("of unknown size: a leaf's weights reach 0")
          : m.estimated                    ? "≈ " + number_text(m.resolution, 4) +
                              ", resolution estimated from the leaves' nets, not proven"
                        : "≤ " + number_text(m.resolution, 4) + ", proven") +
         ")";
}

/// Box counting on m.sample.points with the automatic range; when `relax` and fewer than 3 levels
/// qualify, looser sets of requirements are tried in turn, loosest last, and the first that gives
/// 3 levels is named in m.relaxed. Throws the last InvalidInput when none does.
void fit(DimensionMeasurement& m, ifs::BoxCountingOptions bo, bool relax) {
  bo.resolution = m.resolution;
  struct Relaxation {
    std::size_t min_boxes;
    double resolution;  // factor on bo.resolution (0: no piece-size rule)
    std::vector<std::string> said;
  };
  const std::string fewer = "≥ 100 boxes per fitted level (not " + std::to_string(bo.min_boxes) + ")";
  const std::string pieces = "boxes ≥ 1× the pieces (not 2×)";
  const std::string none = "no piece-size rule: ≥ 4 points per box on average bounds the fine end";
  const std::size_t hundred = std::min<std::size_t>(bo.min_boxes, 100),
                    thirty = std::min<std::size_t>(bo.min_boxes, 30);
  // The piece-size rule goes first: its size is a loose proven bound or an estimate from the
  // largest net, while the points-per-box rule measures the sample's own coverage; the coarse end
  // (boundary and overall-shape terms) is given up last.
  std::vector<Relaxation> tries = {{bo.min_boxes, 1, {}}};
  if (relax) {
    const bool piece_rule = bo.resolution > 0 || bo.points_per_box < 4;
    if (piece_rule) tries.push_back({bo.min_boxes, 0, {none}});
    if (bo.resolution > 0) tries.push_back({bo.min_boxes, 0.5, {pieces}});
    if (hundred < bo.min_boxes) {
      tries.push_back({hundred, 0, {fewer, none}});
      if (bo.resolution > 0) tries.push_back({hundred, 0.5, {fewer, pieces}});
    }
    if (thirty < hundred)
      tries.push_back(
          {thirty, 0, {"≥ 30 boxes per fitted level (not " + std::to_string(bo.min_boxes) + ")", none}});
  }
  for (std::size_t i = 0; i < tries.size(); ++i) {
    ifs::BoxCountingOptions t = bo;
    t.min_boxes = tries[i].min_boxes;
    t.resolution = bo.resolution * tries[i].resolution;
    if (tries[i].resolution == 0) t.points_per_box = std::max(t.points_per_box, 4.0);
    try {
      m.fit = ifs::box_counting(m.sample.points, t);
      m.relaxed = tries[i].said;
      return;
    } catch (const InvalidInput&) {
      if (i + 1 == tries.size()) throw;
    }
  }
}

/// `--depth K`: the proven piece bound when it leaves 3 levels, else (or when it is infinite) the
/// leaves' net diameters as an estimated resolution, with relaxed requirements.
DimensionMeasurement measure_depth(const io::Experiment& e, int depth, const ifs::BoxCountingOptions& bo,
                                   bool user_levels) {
  DimensionMeasurement m;
  m.sample = evaluate(e, depth);
  m.route = "depth";
  if (std::isfinite(m.sample.resolution)) {
    m.resolution = m.sample.resolution;
    try {
      fit(m, bo, false);
      return m;
    } catch (const InvalidInput&) {
      if (user_levels) throw;
    }
  }
  m.resolution = std::isfinite(m.sample.estimated_resolution) ? m.sample.estimated_resolution : 0;
  m.estimated = true;
  fit(m, bo, !user_levels);
  return m;
}

/// Fits the same route on a coarser sample (tolerance 2ε, or depth K − 1; about 4× fewer points
/// on a surface, 2× on a curve) and widens the uncertainty to the change of the dimension: the
/// budget's own effect, which the spread of the local slopes misses when the fit range is short.
void compare_coarser(DimensionMeasurement& m, const ifs::BoxCountingOptions& bo, bool relax) {
  DimensionMeasurement c;
  c.route = m.route;
  c.estimated = m.estimated;
  try {
    if (m.route == "tolerance") {
      const ifs::ToleranceSample ts =
          ifs::tolerance_sample(m.sample.automaton, m.sample.nets,
                                {.epsilon = 2 * m.sample.resolution, .homogeneous = m.sample.rational});
      c.sample.points = ts.points;
      c.resolution = m.resolution > 0 ? ts.resolution : 0;
    } else {
      if (m.sample.depth < 1) throw InvalidInput("depth 0 has no coarser depth");
      const ifs::DepthSample ds = ifs::depth_sample(m.sample.automaton, m.sample.nets,
                                                    {.homogeneous = m.sample.rational,
                                                     .max_points = std::size_t{1} << 40,
                                                     .max_depth = m.sample.depth - 1});
      c.sample.points = ds.points;
      c.resolution = !m.estimated || !std::isfinite(ds.resolution) ? 0 : ds.resolution;
    }
    ifs::BoxCountingOptions co = bo;
    if (m.route == "tolerance") co.points_per_box = 1;
    fit(c, co, relax);
    m.coarser = c.fit.dimension;
  } catch (const InvalidInput& error) {
    m.coarser_note = error.what();
  }
  m.uncertainty = std::max(m.fit.uncertainty, m.coarser ? std::abs(m.fit.dimension - *m.coarser) : 0.0);
}

/// The default route: the proven tolerance sample; its fit with relaxed requirements when fewer
/// than 3 levels qualify; when no sample can be had within the budget (or no Cartesian bound), the
/// deepest depth sample within the budget with a resolution estimated from the leaves' nets.
/// `fallback` gets why the proven route was left.
DimensionMeasurement measure_automatic(const io::Experiment& e, const DimensionOptions& o,
                                       const ifs::BoxCountingOptions& bo, std::string& fallback) {
  DimensionMeasurement m;
  m.sample = evaluate(e, 0);  // builds the source once: automaton and nets
  // Refusals of the input itself (an extent beyond a double) are not a reason to change routes.
  (void)ifs::nets_diameter(m.sample.nets, m.sample.rational);
  ifs::ToleranceSample ts;
  try {
    ts = ifs::tolerance_sample(m.sample.automaton, m.sample.nets,
                               {.homogeneous = m.sample.rational, .max_points = o.max_points});
  } catch (const InvalidInput& error) {
    fallback = error.what();
  }
  if (fallback.empty()) {
    m.route = "tolerance";
    m.sample.points = std::move(ts.points);
    m.sample.depth = ts.deepest;
    m.sample.resolution = m.resolution = ts.resolution;
    // Only a cover whose counts follow one power law: self-similar sets whose ratio is not 1/2
    // count in steps as ε halves (Koch: local slopes 0 … 2.4), which says nothing.
    if (const auto cover = ifs::cover_exponent(ts.cover); cover && cover->spread <= 0.1) m.cover = cover;
    // A tolerance sample covers the attractor to its resolution by construction: the
    // points-per-box rule (a proxy for coverage of depth samples) does not apply.
    ifs::BoxCountingOptions so = bo;
    so.points_per_box = 1;
    try {
      fit(m, so, false);
      return m;
    } catch (const InvalidInput& error) {
      fallback = error.what();
    }
    fit(m, so, true);
    return m;
  }
  ifs::DepthSample ds = ifs::depth_sample(m.sample.automaton, m.sample.nets,
                                          {.homogeneous = m.sample.rational, .max_points = o.max_points});
  m.route = "depth";
  m.sample.points = std::move(ds.points);
  m.sample.depth = ds.depth;
  m.sample.estimated_resolution = ds.resolution;
  m.estimated = true;
  m.resolution = std::isfinite(ds.resolution) ? ds.resolution : 0;
  try {
    fit(m, bo, true);
  } catch (const InvalidInput& error) {
    throw InvalidInput(
        std::string(error.what()) + " (depth " + std::to_string(m.sample.depth) +
        ", the deepest within --max-points); raise --max-points, or give --min-level and --max-level");
  }
  return m;
}

/// The sample and its fit, by the route the options ask for (or the automatic one); `fallback`
/// gets why the proven route was left.
DimensionMeasurement dimension_measure(const io::Experiment& e, const DimensionOptions& o,
                                       std::string& fallback) {
  if (o.depth && o.relative_piece_size)
    throw InvalidInput("dimension: give --depth or --relative-piece-size, not both");
  // The sample is held in memory and its walk takes about 1 µs per point: a budget of 2^40 ran for days.
  if (o.max_points < 1 || o.max_points > kMaxPoints)
    throw InvalidInput("--max-points " + std::to_string(o.max_points) + ": expected 1 to " +
                       std::to_string(kMaxPoints) + " points (the sample is held in memory)");
  const bool user_levels = o.min_level >= 0 || o.max_level >= 0;
  // Without --depth or --relative-piece-size the route chooses itself (proven sample, else a depth
  // evaluation) and relaxes the fit's requirements where they cannot hold.
  const bool automatic = !o.depth && !o.relative_piece_size && !user_levels;
  ifs::BoxCountingOptions bo;
  bo.min_boxes = o.min_boxes;
  bo.min_level = o.min_level;
  bo.max_level = o.max_level;

  DimensionMeasurement m;
  if (automatic) {
    m = measure_automatic(e, o, bo, fallback);
  } else if (o.depth) {
    m = measure_depth(e, *o.depth, bo, user_levels);
  } else {
    m.sample = sample(e, {.tolerance = o.relative_piece_size.value_or(0),
                          .max_points = o.max_points,
                          .tolerance_name = "--relative-piece-size",
                          .limit_hint = "; raise --relative-piece-size or --max-points"});
    m.route = "tolerance";
    m.resolution = m.sample.resolution;
    ifs::BoxCountingOptions so = bo;
    so.points_per_box = 1;
    try {
      fit(m, so, false);
    } catch (const InvalidInput& error) {
      // The proven piece bound may be loose (signed matrices): say that a depth evaluation is the way out.
      if (user_levels) throw;
      throw InvalidInput(std::string(error.what()) +
                         "; or raise --max-points, or measure a depth evaluation (--depth K)");
    }
  }
  // A user's fit range is fitted as given on the coarser sample too.
  compare_coarser(m, bo, !user_levels);
  return m;
}

/// The similarity dimension, when every map is a similarity; `why_not` says why when it is not.
std::optional<double> similarity_of(const Evaluation& ev, std::string& why_not) {
  std::optional<double> similarity;
  try {
    if (!ev.maps.empty())
      similarity = ifs::similarity_dimension(ev.maps);
    else if (ev.rational)
      why_not = "rational nets (homogeneous maps are not similarities of the plane)";
    else
      similarity = ifs::similarity_dimension(ev.automaton, ev.nets);
  } catch (const InvalidInput& error) {
    why_not = error.what();
  }
  return similarity;
}

}  // namespace

DimensionMeasurement measure_dimension(const io::Experiment& e, const DimensionOptions& o) {
  std::string fallback;
  DimensionMeasurement m = dimension_measure(e, o, fallback);
  m.fallback = std::move(fallback);
  m.description = route_name(m);
  const auto [lo, hi] = dimension_range(m);
  m.range = {lo, hi};
  m.similarity = similarity_of(m.sample, m.similarity_note);
  return m;
}

}  // namespace cifs::experiment
