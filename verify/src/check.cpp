// SPDX-License-Identifier: MIT
#include "cifs/verify/check.hpp"

#include <cmath>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/nurbs/doubling.hpp"
#include "cifs/nurbs/refine.hpp"

namespace cifs::verify {
namespace {

/// Most knots the references may insert (about 8 bytes × (d+1)·dim each, kept in memory at once).
constexpr double kMaxInsertedKnots = 1 << 26;

/// The segment on span k as its own curve: d + 1 points, the window's knots relative to the
/// segment start, extended by d pad knots and points on each side so that the domain covers the
/// whole window (pads do not change the window's pieces' blossoms, which is all that matters).
struct LocalSegment {
  nurbs::Curve curve;          // domain = the window
  nurbs::Curve piece;          // domain = the segment [0, length]
  std::vector<double> window;  // window knots T_0 … T_{2d−1}, T_{d−1} = 0
};

LocalSegment local_segment(const nurbs::Curve& c, int k) {
  const int d = c.degree;
  const nurbs::Window w = nurbs::segment_window(c.knots, d, k);
  std::vector<double> T(static_cast<std::size_t>(2 * d));
  for (int i = d - 1; i + 1 < 2 * d; ++i)
    T[static_cast<std::size_t>(i + 1)] = T[static_cast<std::size_t>(i)] + w[static_cast<std::size_t>(i)];
  for (int i = d - 1; i > 0; --i)
    T[static_cast<std::size_t>(i - 1)] = T[static_cast<std::size_t>(i)] - w[static_cast<std::size_t>(i - 1)];
  const double pad = T.back() - T.front();
  const Points net = c.P.middleRows(k - d, d + 1);

  nurbs::Knots piece_knots{T.front() - pad};
  piece_knots.insert(piece_knots.end(), T.begin(), T.end());
  piece_knots.push_back(T.back() + pad);
  LocalSegment out{{}, nurbs::Curve{d, std::move(piece_knots), net, c.rational, false}, T};

  nurbs::Knots knots;
  for (int i = d + 1; i >= 1; --i) knots.push_back(T.front() - i * pad);
  knots.insert(knots.end(), T.begin(), T.end());
  for (int i = 1; i <= d + 1; ++i) knots.push_back(T.back() + i * pad);
  Points P(3 * d + 1, net.cols());
  for (int i = 0; i < P.rows(); ++i) P.row(i) = net.row(std::clamp(i - d, 0, d));
  out.curve = nurbs::Curve{d, std::move(knots), std::move(P), c.rational, false};
  return out;
}

/// Cartesian rows and weights of stored rows.
Points cartesian_rows(const Points& H, bool rational) {
  return rational ? ifs::cartesian(H) : H;
}

void track(Deviation& dev, double abs, double scale) {
  dev.max_abs = std::max(dev.max_abs, abs);
  dev.max_rel = std::max(dev.max_rel, abs / scale);
}

void merge(Deviation& into, const Deviation& d) {
  into.max_abs = std::max(into.max_abs, d.max_abs);
  into.max_rel = std::max(into.max_rel, d.max_rel);
}

}  // namespace

CheckReport check_curve(const nurbs::Curve& c, const CheckOptions& o) {
  if (o.depth < 0 || o.depth > 30)
    throw InvalidInput("check: depth " + std::to_string(o.depth) + " is outside [0, 30]");
  if (!(o.tolerance > 0)) throw InvalidInput("check: the tolerance must be positive");
  const int d = c.degree;
  const automata::Automaton a = automata::knot_automaton(c);
  const double inserted = static_cast<double>(a.initial.size()) * (2 * d - 1) * std::ldexp(1.0, o.depth);
  if (inserted > kMaxInsertedKnots)
    throw InvalidInput(
        "check: depth " + std::to_string(o.depth) + " would insert " +
        std::to_string(static_cast<long long>(inserted)) +
        " knots in the references (limit 2^26, about the memory of the machine's budget); lower --depth");

  const Points cart = nurbs::cartesian_points(c);
  const double scale = std::max(cart.cwiseAbs().maxCoeff(), 1e-300);
  const double weight_scale = nurbs::weights(c).maxCoeff();
  const std::vector<Points> nets = automata::initial_nets(a, c);
  const double leaves = std::ldexp(1.0, o.depth);

  CheckReport report{o.depth, o.tolerance, {}, {}, {}, false};
  std::vector<LocalSegment> locals;
  std::vector<nurbs::Curve> refined;  // (a) references: every dyadic knot of every inter-knot of the window
  for (const automata::Initial& init : a.initial) {
    locals.push_back(local_segment(c, init.span));
    const std::vector<double>& T = locals.back().window;
    std::vector<double> dyadic;
    for (std::size_t j = 0; j + 1 < T.size(); ++j) {
      const double step = (T[j + 1] - T[j]) / leaves;
      if (step > 0)
        for (long long m = 1; m < static_cast<long long>(leaves); ++m)
          dyadic.push_back(T[j] + static_cast<double>(m) * step);
    }
    refined.push_back(nurbs::refine(locals.back().curve, dyadic));
    report.segments.push_back(SegmentReport{init.segment, init.start, init.end, {}, {}});
  }
  const auto length = [&](std::size_t i) { return locals[i].window[static_cast<std::size_t>(d)]; };

  // (a) Leaf nets against the references.
  ifs::for_each_leaf(a, nets, o.depth, [&](const ifs::Leaf& leaf) {
    long long index = 0;
    for (int bit : leaf.word) index = 2 * index + bit;
    const double u =
        static_cast<double>(index) * (length(leaf.initial) / leaves);  // the inserted knot, bit for bit
    const nurbs::Curve& r = refined[leaf.initial];
    const Points expected = r.P.middleRows(nurbs::find_span(r.knots, d, u) - d, d + 1);
    SegmentReport& seg = report.segments[leaf.initial];
    track(seg.nets,
          (cartesian_rows(leaf.net, c.rational) - cartesian_rows(expected, c.rational))
              .rowwise()
              .norm()
              .maxCoeff(),
          scale);
    if (c.rational)
      track(seg.nets,
            (leaf.net.col(leaf.net.cols() - 1) - expected.col(expected.cols() - 1)).cwiseAbs().maxCoeff(),
            weight_scale);
  });

  // (b) Attractor points (2^K starts per segment, then the last end) against Cox–de Boor.
  const Points points = cartesian_rows(ifs::attractor_points(a, nets, o.depth), c.rational);
  const auto per_segment = static_cast<Eigen::Index>(leaves);
  for (Eigen::Index m = 0; m < points.rows(); ++m) {
    const bool last = m + 1 == points.rows();
    const auto i = static_cast<std::size_t>(last ? m / per_segment - 1 : m / per_segment);
    const double u = last ? length(i) : static_cast<double>(m % per_segment) * (length(i) / leaves);
    track(report.segments[i].points, (points.row(m) - nurbs::evaluate_basis(locals[i].piece, u)).norm(),
          scale);
  }
  for (const SegmentReport& seg : report.segments) {
    merge(report.nets, seg.nets);
    merge(report.points, seg.points);
  }
  report.pass = report.nets.max_rel <= o.tolerance && report.points.max_rel <= o.tolerance;
  return report;
}

}  // namespace cifs::verify
