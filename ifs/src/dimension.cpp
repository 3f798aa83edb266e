// SPDX-License-Identifier: MIT
#include "cifs/ifs/dimension.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/sample.hpp"

namespace cifs::ifs {
namespace {

/// Interleaves the bits of the box coordinates (each < 2^levels), finest bits lowest, so that the
/// key of a level-k box is the finest key shifted right by dim·(levels − k).
std::uint64_t morton(const std::vector<std::uint64_t>& c, int levels) {
  std::uint64_t key = 0;
  const auto dim = static_cast<int>(c.size());
  for (int bit = levels - 1; bit >= 0; --bit)
    for (int d = 0; d < dim; ++d) key = (key << 1) | ((c[static_cast<std::size_t>(d)] >> bit) & 1u);
  return key;
}

struct Full {};

/// Least-squares slope of log N against log(1/ε) over levels lo … hi of `counts`.
double slope(const std::vector<BoxCount>& counts, int lo, int hi) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double m = hi - lo + 1;
  for (int k = lo; k <= hi; ++k) {
    const BoxCount& b = counts[static_cast<std::size_t>(k)];
    const double x = -std::log(b.epsilon), y = std::log(static_cast<double>(b.boxes));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (sxy - sx * sy / m) / (sxx - sx * sx / m);
}

/// Point budgets above this are checked against an estimate before each counting walk.
constexpr std::size_t kEstimateAbove = std::size_t{1} << 22;

/// Leaves of the tolerance traversal at `options.epsilon`; max + 1 as soon as there are more.
/// Throws InvalidInput when a branch is unresolved at max_depth.
std::size_t count_leaves(const automata::Automaton& a, std::span<const Points> nets,
                         const ToleranceOptions& to, std::size_t max) {
  std::size_t n = 0;
  try {
    for_each_leaf_to_tolerance(a, nets, to, [&](const ToleranceLeaf& t) {
      if (!t.converged && !std::isfinite(t.diameter))
        throw InvalidInput("a piece of the rational shape has no Cartesian size bound at depth " +
                           std::to_string(to.max_depth) +
                           " (its weights come near 0); evaluate to a depth instead");
      if (!t.converged)
        throw InvalidInput("tolerance " + number_text(to.epsilon, 6) + ": a piece is still " +
                           number_text(t.diameter, 6) + " wide at depth " + std::to_string(to.max_depth) +
                           "; give a larger tolerance");
      if (++n > max) throw Full{};
    });
  } catch (const Full&) {
  }
  return n;
}

}  // namespace

ToleranceSample tolerance_sample(const automata::Automaton& a, std::span<const Points> nets,
                                 const ToleranceSampleOptions& o) {
  if (!(o.epsilon >= 0) || !std::isfinite(o.epsilon))
    throw InvalidInput("tolerance " + number_text(o.epsilon, 6) + " is not a finite number ≥ 0");
  validate(a);
  ToleranceOptions to;
  to.homogeneous = o.homogeneous;
  to.max_depth = o.max_depth;
  to.epsilon = o.epsilon;
  // A large point budget takes seconds per counting walk (about 1 µs per leaf): a tolerance that
  // clearly needs more is refused, or ends the search, on an estimate from coarser tolerances.
  const auto clearly_above = [&](const ToleranceOptions& t) {
    if (o.max_points <= kEstimateAbove) return 0.0;
    const ToleranceEstimate e = estimate_tolerance_leaves(a, nets, t);
    // Above the budget at all: the estimate is within a few percent (docs/reliability.md), and the
    // counting walk to a budget of 5·10^7 took 8 CPU-s before the same refusal (issue 33).
    return !e.exact && e.leaves > static_cast<double>(o.max_points) ? e.leaves : 0.0;
  };
  std::size_t n = 0;
  std::vector<CoverCount> cover;
  if (o.epsilon > 0) {
    const std::string name = o.tolerance_text.empty()
                                 ? std::string(o.tolerance_name) + " " + number_text(o.epsilon, 6)
                                 : std::string(o.tolerance_text);
    const std::string hint = o.limit_hint.empty()
                                 ? "; raise " + std::string(o.tolerance_name) + " or the point limit"
                                 : std::string(o.limit_hint);
    if (const double about = clearly_above(to); about > 0)
      throw InvalidInput(name + " needs about " + number_text(about, 3) +
                         " points (estimated from coarser tolerances), more than the limit of " +
                         std::to_string(o.max_points) + hint);
    n = count_leaves(a, nets, to, o.max_points);
    if (n > o.max_points)
      throw InvalidInput(name + " needs more than " + std::to_string(o.max_points) + " points" + hint);
  } else {
    // The largest power-of-2 fraction of the nets' extent within the point budget.
    const double extent = nets_diameter(nets, o.homogeneous);
    if (!(extent > 0)) throw InvalidInput("the control points are all one point: there is nothing to sample");
    to.epsilon = std::ldexp(extent, -4);
    n = count_leaves(a, nets, to, o.max_points);
    cover.push_back({to.epsilon, n});
    if (n > o.max_points)
      throw InvalidInput("even tolerance " + number_text(to.epsilon, 6) +
                         " (1/16 of the nets' extent) needs more than " + std::to_string(o.max_points) +
                         " points; raise the point limit");
    // 2^-60 of the extent is far below double precision of any coordinate: stop there (a sample
    // that does not grow is an attractor of few points).
    for (int j = 5; j <= 60; ++j) {
      ToleranceOptions finer = to;
      finer.epsilon = std::ldexp(extent, -j);
      if (clearly_above(finer) > 0) break;
      const std::size_t m = count_leaves(a, nets, finer, o.max_points);
      if (m > o.max_points) break;
      to = finer;
      n = m;
      cover.push_back({to.epsilon, n});
    }
  }
  // One point per leaf, no end point: each piece counts once. The n leaves were counted above:
  // no estimate (it may overshoot that count and refuse a tolerance the search accepted).
  Sample sample = sample_attractor(a, nets,
                                   {.tolerance = to.epsilon,
                                    .homogeneous = o.homogeneous,
                                    .closed = true,
                                    .max_depth = o.max_depth,
                                    .max_points = std::max(n, o.max_points),
                                    .estimate = false});
  ToleranceSample out;
  out.leaves = static_cast<std::size_t>(sample.points.rows());
  out.points = std::move(sample.points);
  out.resolution = to.epsilon;
  out.deepest = sample.depth;
  out.cover = cover.empty() ? std::vector<CoverCount>{{to.epsilon, out.leaves}} : std::move(cover);
  return out;
}

std::optional<CoverExponent> cover_exponent(std::span<const CoverCount> counts, std::size_t min_leaves,
                                            int levels) {
  std::vector<CoverCount> fitted;
  for (auto c = counts.rbegin(); c != counts.rend() && std::ssize(fitted) < levels; ++c)
    if (c->leaves >= min_leaves && c->epsilon > 0) fitted.push_back(*c);
  if (fitted.size() < 3) return std::nullopt;
  // Least squares of y = log n against x = log(1/ε).
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const CoverCount& c : fitted) {
    const double x = -std::log(c.epsilon), y = std::log(static_cast<double>(c.leaves));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const auto m = static_cast<double>(fitted.size());
  CoverExponent e;
  e.dimension = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  for (std::size_t i = 0; i + 1 < fitted.size(); ++i) {
    const double local =
        std::log(static_cast<double>(fitted[i].leaves) / static_cast<double>(fitted[i + 1].leaves)) /
        std::log(fitted[i + 1].epsilon / fitted[i].epsilon);
    e.spread = std::max(e.spread, std::abs(local - e.dimension));
  }
  e.min_epsilon = fitted.front().epsilon;
  e.max_epsilon = fitted.back().epsilon;
  e.levels = static_cast<int>(fitted.size());
  return e;
}

DepthSample depth_sample(const automata::Automaton& a, std::span<const Points> nets,
                         const DepthSampleOptions& o) {
  validate(a);
  check_nets(a, nets);
  const auto count = [&](int depth) {
    try {
      return attractor_point_count(a, depth);
    } catch (const InvalidInput&) {  // overflow: certainly above the budget
      return std::numeric_limits<std::size_t>::max();
    }
  };
  if (count(0) > o.max_points)
    throw InvalidInput("even depth 0 has more than " + std::to_string(o.max_points) +
                       " points, the most the sample may hold; raise the point limit");
  DepthSample out;
  while (out.depth < o.max_depth && count(out.depth + 1) <= o.max_points) ++out.depth;
  Points P = attractor_points(a, nets, out.depth);
  out.points = o.homogeneous ? cartesian(P) : std::move(P);
  for_each_leaf(a, nets, out.depth, [&](const Leaf& leaf) {
    if (!o.homogeneous) {
      out.resolution = std::max(out.resolution, diameter(leaf.net));
      return;
    }
    const bool positive = (leaf.net.col(leaf.net.cols() - 1).array() != 0).all();
    const Points x = positive ? cartesian(leaf.net) : Points();
    out.resolution = positive && x.allFinite() ? std::max(out.resolution, diameter(x))
                                               : std::numeric_limits<double>::infinity();
  });
  return out;
}

namespace {

/// The finest level of the grid, after the checks of the points and options.
int box_levels(const Points& P, const BoxCountingOptions& o) {
  if (P.rows() == 0 || P.cols() == 0) throw InvalidInput("box counting: no points");
  if (!P.allFinite()) throw InvalidInput("box counting: a point is not finite");
  if (!(o.points_per_box >= 1) || !(o.resolution >= 0) || !std::isfinite(o.resolution))
    throw InvalidInput("box counting: points_per_box must be ≥ 1 and resolution finite and ≥ 0");
  const auto dim = static_cast<int>(P.cols());
  if (dim > 62) throw InvalidInput("box counting: more than 62 coordinates");
  if (o.levels < 1) throw InvalidInput("box counting: levels must be ≥ 1");
  // One spare bit per axis: the shifted origin makes the grid one box wider than the points.
  const int levels = std::min(o.levels, 64 / dim - 1);
  if (levels < 3) throw InvalidInput("box counting: too many coordinates (" + std::to_string(dim) + ")");
  return levels;
}

/// The boxes of every level: each point's finest box as a Morton key, sorted, then the distinct
/// keys of each level counted.
void count_boxes(const Points& P, int levels, const Point& lo, double size, BoxCountingResult& r) {
  const auto dim = static_cast<int>(P.cols());
  const double fine = std::ldexp(size, -levels);
  std::vector<std::uint64_t> keys(static_cast<std::size_t>(P.rows()));
  std::vector<std::uint64_t> c(static_cast<std::size_t>(dim));
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    for (int d = 0; d < dim; ++d) {
      const double shift = std::fmod(0.1 * std::sqrt(d + 2.0), 1.0);
      const double x = (P(i, d) - lo(d) + shift * size) / fine;
      c[static_cast<std::size_t>(d)] = static_cast<std::uint64_t>(std::floor(x));
    }
    keys[static_cast<std::size_t>(i)] = morton(c, levels + 1);
  }
  std::sort(keys.begin(), keys.end());
  for (int k = 0; k <= levels; ++k) {
    const int shift = dim * (levels - k);
    std::size_t n = 0;
    std::uint64_t previous = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const std::uint64_t key = keys[i] >> shift;
      if (i == 0 || key != previous) ++n;
      previous = key;
    }
    r.counts.push_back({k, std::ldexp(size, -k), n});
  }
}

/// The fit range: the caller's, or the longest run of consecutive admissible levels (counts grow
/// with k, so it is one run unless the sample is degenerate).
void choose_fit_range(const BoxCountingOptions& o, int levels, Eigen::Index points, BoxCountingResult& r) {
  if (o.min_level >= 0 || o.max_level >= 0) {
    if (o.min_level < 0 || o.max_level > levels || o.min_level + 2 > o.max_level)
      throw InvalidInput("box counting: the fit range " + std::to_string(o.min_level) + " … " +
                         std::to_string(o.max_level) + " is not within 0 … " + std::to_string(levels) +
                         " with at least 3 levels");
    r.min_level = o.min_level;
    r.max_level = o.max_level;
    return;
  }
  const auto n_points = static_cast<double>(points);
  const auto admissible = [&](const BoxCount& b) {
    return b.boxes >= o.min_boxes && static_cast<double>(b.boxes) * o.points_per_box <= n_points &&
           b.epsilon >= 2 * o.resolution;
  };
  int best = -1, best_len = 0;
  for (int k = 0; k <= levels;) {
    if (!admissible(r.counts[static_cast<std::size_t>(k)])) {
      ++k;
      continue;
    }
    int j = k;
    while (j <= levels && admissible(r.counts[static_cast<std::size_t>(j)])) ++j;
    if (j - k > best_len) best = k, best_len = j - k;
    k = j;
  }
  if (best_len < 3)
    throw InvalidInput("box counting: only " + std::to_string(best_len) + " scale(s) with ≥ " +
                       std::to_string(o.min_boxes) + " boxes, ≥ " + number_text(o.points_per_box, 6) +
                       " points per box" + (o.resolution > 0 ? " and boxes ≥ 2× the pieces" : "") +
                       " among " + std::to_string(points) +
                       " points; evaluate deeper (at least 3 are needed)");
  r.min_level = best;
  r.max_level = best + best_len - 1;
}

/// Least squares of y = log N on x = log(1/ε) over the fit range.
void fit_dimension(BoxCountingResult& r) {
  const int m = r.max_level - r.min_level + 1;
  double sx = 0, sy = 0;
  for (int k = r.min_level; k <= r.max_level; ++k) {
    const BoxCount& b = r.counts[static_cast<std::size_t>(k)];
    sx += -std::log(b.epsilon);
    sy += std::log(static_cast<double>(b.boxes));
  }
  const double mx = sx / m, my = sy / m;
  double sxx = 0, sxy = 0, syy = 0;
  for (int k = r.min_level; k <= r.max_level; ++k) {
    const BoxCount& b = r.counts[static_cast<std::size_t>(k)];
    const double x = -std::log(b.epsilon) - mx, y = std::log(static_cast<double>(b.boxes)) - my;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
  }
  r.dimension = sxy / sxx;
  r.intercept = my - r.dimension * mx;
  double ss_res = 0;
  for (int k = r.min_level; k <= r.max_level; ++k) {
    const BoxCount& b = r.counts[static_cast<std::size_t>(k)];
    const double e =
        std::log(static_cast<double>(b.boxes)) - (r.intercept - r.dimension * std::log(b.epsilon));
    ss_res += e * e;
    r.residual = std::max(r.residual, std::abs(e));
  }
  r.r_squared = syy > 0 ? 1 - ss_res / syy : 1;
  r.standard_error = m > 2 ? std::sqrt(ss_res / (m - 2) / sxx) : 0;
  // Local slopes between consecutive levels: the fit's drift across the scales it spans.
  for (int k = r.min_level; k < r.max_level; ++k)
    r.spread = std::max(r.spread, std::abs(slope(r.counts, k, k + 1) - r.dimension));
  r.uncertainty = std::max(r.standard_error, r.spread);
  r.max_epsilon = r.counts[static_cast<std::size_t>(r.min_level)].epsilon;
  r.min_epsilon = r.counts[static_cast<std::size_t>(r.max_level)].epsilon;
}

}  // namespace

BoxCountingResult box_counting(const Points& P, const BoxCountingOptions& o) {
  const int levels = box_levels(P, o);
  const Point lo = P.colwise().minCoeff(), hi = P.colwise().maxCoeff();
  const double size = (hi - lo).maxCoeff();
  if (!(size > 0)) throw InvalidInput("box counting: all points are equal");
  BoxCountingResult r;
  r.size = size;
  count_boxes(P, levels, lo, size, r);
  choose_fit_range(o, levels, P.rows(), r);
  fit_dimension(r);
  return r;
}

double mauldin_williams_dimension(std::size_t states, std::span<const SimilarityEdge> edges) {
  for (const SimilarityEdge& e : edges) {
    if (e.from >= states || e.to >= states)
      throw InvalidInput("similarity dimension: an edge " + std::to_string(e.from) + " → " +
                         std::to_string(e.to) + " leaves the " + std::to_string(states) + " states");
    if (!(e.ratio > 0) || !std::isfinite(e.ratio))
      throw InvalidInput("similarity dimension: the ratio " + number_text(e.ratio, 6) + " of an edge " +
                         std::to_string(e.from) + " → " + std::to_string(e.to) + " is not finite and > 0");
  }
  // States without edges add zero rows and columns (eigenvalue 0): the matrix is over the others,
  // so its size follows the edges, not `states`.
  std::map<std::size_t, Eigen::Index> index;
  for (const SimilarityEdge& e : edges) {
    index.emplace(e.from, 0);
    index.emplace(e.to, 0);
  }
  Eigen::Index n = 0;
  for (auto& [state, i] : index) i = n++;
  const auto rho = [&](double s) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    for (const SimilarityEdge& e : edges) A(index.at(e.from), index.at(e.to)) += std::pow(e.ratio, s);
    if (n == 0) return 0.0;
    return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues().cwiseAbs().maxCoeff();
  };
  const double rho0 = rho(0);  // spectral radius of the adjacency matrix: 0 iff no cycle
  if (rho0 < 0.5) throw InvalidInput("similarity dimension: the graph has no cycle");
  if (rho0 <= 1 + 1e-12) return 0;
  double lo = 0, hi = 1;
  while (rho(hi) >= 1) {
    lo = hi;
    hi *= 2;
    if (hi > 1000)
      throw InvalidInput("similarity dimension: the cycles do not contract (ρ(A(s)) ≥ 1 up to s = 1000)");
  }
  // Bisection until the interval stops shrinking.
  for (;;) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (rho(mid) >= 1 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double similarity_ratio(const Eigen::MatrixXd& L) {
  const Eigen::MatrixXd G = L.transpose() * L;
  const double r2 = G.trace() / static_cast<double>(G.rows());
  if (!(r2 > 0) || !std::isfinite(r2)) return -1;
  const Eigen::MatrixXd E = G - r2 * Eigen::MatrixXd::Identity(G.rows(), G.cols());
  return E.cwiseAbs().maxCoeff() <= 1e-12 * r2 ? std::sqrt(r2) : -1;
}

double similarity_dimension(std::span<const AffineMap> maps) {
  if (maps.empty()) throw InvalidInput("similarity dimension: no map");
  std::vector<SimilarityEdge> edges;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const AffineMap& m = maps[i];
    // Row convention: (x, y) ↦ (x, y)·L + (e, f) with L = [a c; b d].
    Eigen::Matrix2d L;
    L << m.a, m.c, m.b, m.d;
    const double r = similarity_ratio(L);
    if (r < 0) {
      const Eigen::Matrix2d G = L.transpose() * L;
      throw InvalidInput("similarity dimension: map " + std::to_string(i) + " is not a similarity (LᵀL = [" +
                         number_text(G(0, 0), 6) + " " + number_text(G(0, 1), 6) + "; " +
                         number_text(G(1, 0), 6) + " " + number_text(G(1, 1), 6) + "] is not r²·I)");
    }
    if (r >= 1)
      throw InvalidInput("similarity dimension: map " + std::to_string(i) + " has ratio " +
                         number_text(r, 6) + " ≥ 1");
    edges.push_back({0, 0, r});
  }
  return mauldin_williams_dimension(1, edges);
}

double similarity_dimension(const automata::Automaton& a, std::span<const Points> nets) {
  validate(a);
  if (nets.size() != a.initial.size())
    throw InvalidInput("similarity dimension: " + std::to_string(nets.size()) + " nets for " +
                       std::to_string(a.initial.size()) + " initial entries");
  const auto n = num_vertices(a.graph);
  std::vector<Points> reference(n);
  std::deque<automata::StateId> queue;
  for (std::size_t i = 0; i < nets.size(); ++i) {
    const automata::StateId s = a.initial[i].state;
    if (nets[i].rows() != a.graph[s].size)
      throw InvalidInput("similarity dimension: net " + std::to_string(i) + " has " +
                         std::to_string(nets[i].rows()) + " rows, its state " +
                         std::to_string(a.graph[s].size));
    if (reference[s].size() == 0) {
      reference[s] = nets[i];
      queue.push_back(s);
    }
  }
  if (queue.empty()) throw InvalidInput("similarity dimension: the automaton has no initial entry");
  const Eigen::Index dim = nets.front().cols();
  while (!queue.empty()) {
    const automata::StateId u = queue.front();
    queue.pop_front();
    for (const automata::TransitionId e : out_edges(u, a.graph)) {
      const automata::StateId v = target(e, a.graph);
      if (reference[v].size() == 0) {
        reference[v] = a.graph[e].matrix * reference[u];
        queue.push_back(v);
      }
    }
  }
  std::vector<SimilarityEdge> edges;
  for (automata::StateId u = 0; u < n; ++u) {
    if (reference[u].size() == 0) continue;
    for (const automata::TransitionId e : out_edges(u, a.graph)) {
      const automata::StateId v = target(e, a.graph);
      const std::string name =
          "transition '" + a.graph[e].label + "' " + std::to_string(u) + " → " + std::to_string(v);
      // f(x) = x·L + b with [N_v 1]·[L; b] = M·N_u: determined when N_v spans its space affinely.
      Eigen::MatrixXd H(reference[v].rows(), dim + 1);
      H << reference[v], Eigen::VectorXd::Ones(reference[v].rows());
      const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(H);
      if (qr.rank() < dim + 1)
        throw InvalidInput("similarity dimension: the net of state " + std::to_string(v) +
                           " does not span its space affinely, so the map of " + name + " is not determined");
      const Eigen::MatrixXd Q = a.graph[e].matrix * reference[u];
      const Eigen::MatrixXd X = qr.solve(Q);
      const double scale = std::max(diameter(reference[v]), diameter(Q));
      if ((H * X - Q).cwiseAbs().maxCoeff() > 1e-12 * scale)
        throw InvalidInput("similarity dimension: " + name +
                           " is not an affine map between the nets of its states");
      const double r = similarity_ratio(X.topRows(dim));
      if (r < 0) throw InvalidInput("similarity dimension: " + name + " is not a similarity (LᵀL ≠ r²·I)");
      edges.push_back({u, v, r});
    }
  }
  return mauldin_williams_dimension(n, edges);
}

}  // namespace cifs::ifs
