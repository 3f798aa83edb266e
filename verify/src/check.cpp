// SPDX-License-Identifier: MIT
#include "cifs/verify/check.hpp"

#include <cmath>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/nurbs/doubling.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"

namespace cifs::verify {
namespace {

/// Most knots the references may insert (about 8 bytes × (d+1)·dim each, kept in memory at once).
constexpr double kMaxInsertedKnots = 1 << 26;

/// The knots of the segment on span k in its own coordinates: the window's knots relative to the
/// segment start, extended by pads on each side so that the domain covers the whole window (pads
/// do not change the window's pieces' blossoms, which is all that matters).
struct LocalKnots {
  nurbs::Knots wide;           // 3d + 1 points: domain = the window
  nurbs::Knots piece;          // d + 1 points: domain = the segment [0, length]
  std::vector<double> window;  // window knots T_0 … T_{2d−1}, T_{d−1} = 0
};

LocalKnots local_knots(const nurbs::Window& w, int d) {
  std::vector<double> T(static_cast<std::size_t>(2 * d));
  for (int i = d - 1; i + 1 < 2 * d; ++i)
    T[static_cast<std::size_t>(i) + 1] = T[static_cast<std::size_t>(i)] + w[static_cast<std::size_t>(i)];
  for (int i = d - 1; i > 0; --i)
    T[static_cast<std::size_t>(i - 1)] = T[static_cast<std::size_t>(i)] - w[static_cast<std::size_t>(i - 1)];
  const double pad = T.back() - T.front();
  LocalKnots out;
  out.piece = {T.front() - pad};
  out.piece.insert(out.piece.end(), T.begin(), T.end());
  out.piece.push_back(T.back() + pad);
  for (int i = d + 1; i >= 1; --i) out.wide.push_back(T.front() - i * pad);
  out.wide.insert(out.wide.end(), T.begin(), T.end());
  for (int i = 1; i <= d + 1; ++i) out.wide.push_back(T.back() + i * pad);
  out.window = std::move(T);
  return out;
}

/// Row i of the wide net (3d + 1 points) repeats the segment's net row clamp(i − d, 0, d).
int wide_row(int i, int d) {
  return std::clamp(i - d, 0, d);
}

/// Every dyadic knot of depth K inside every inter-knot of the window: inserting them splits the
/// window the way K levels of knot doubling do.
std::vector<double> dyadic_knots(const std::vector<double>& T, double leaves) {
  std::vector<double> dyadic;
  for (std::size_t j = 0; j + 1 < T.size(); ++j) {
    const double step = (T[j + 1] - T[j]) / leaves;
    if (step > 0)
      for (long long m = 1; m < static_cast<long long>(leaves); ++m) {
        const double x = T[j] + static_cast<double>(m) * step;
        // An interval of a few subnormals (knots [0, 1e-320]) has fewer doubles than dyadic knots: they
        // coincided, and refine said "would reach multiplicity 2", as if the shape were wrong.
        if (!(x > (dyadic.empty() || m == 1 ? T[j] : dyadic.back())) || !(x < T[j + 1]))
          throw InvalidInput("the check depth " + number_text(std::log2(leaves), 3) +
                             " splits a knot interval of length " + number_text(T[j + 1] - T[j], 6) +
                             " into " + number_text(leaves, 6) +
                             " pieces, more than the doubles it holds; lower the depth");
        dyadic.push_back(x);
      }
  }
  return dyadic;
}

/// The segment on span k as its own curve (see LocalKnots).
struct LocalSegment {
  nurbs::Curve curve;          // domain = the window
  nurbs::Curve piece;          // domain = the segment [0, length]
  std::vector<double> window;  // window knots T_0 … T_{2d−1}, T_{d−1} = 0
};

LocalSegment local_segment(const nurbs::Curve& c, int k) {
  const int d = c.degree;
  LocalKnots knots = local_knots(nurbs::segment_window(c, k), d);
  const Points net = c.P.middleRows(k - d, d + 1);
  Points P(3 * d + 1, net.cols());
  for (int i = 0; i < P.rows(); ++i) P.row(i) = net.row(wide_row(i, d));
  return LocalSegment{nurbs::Curve{d, std::move(knots.wide), std::move(P), c.rational, false},
                      nurbs::Curve{d, std::move(knots.piece), net, c.rational, false},
                      std::move(knots.window)};
}

/// Cartesian rows and weights of stored rows.
Points cartesian_rows(const Points& H, bool rational) {
  return rational ? ifs::cartesian(H) : H;
}

/// Distances are measured with stableNorm: the square of a deviation of 1e293 (points near 1.7e308
/// agreeing to 16 digits) overflows, and norm() reported inf and FAIL for a correct shape.
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
    throw InvalidInput("the check depth " + std::to_string(o.depth) + " is outside [0, 30]");
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw InvalidInput("the check tolerance " +
                       (std::isfinite(o.tolerance) ? number_text(o.tolerance, 6) + " is not positive"
                                                   : std::string("is not a finite number")) +
                       "; give a positive finite tolerance");
  const int d = c.degree;
  const nurbs::KnotAutomaton knots = nurbs::knot_automaton(c);
  const automata::Automaton& a = knots.automaton;
  const double inserted = static_cast<double>(a.initial.size()) * (2 * d - 1) * std::ldexp(1.0, o.depth);
  if (inserted > kMaxInsertedKnots)
    throw InvalidInput(
        "the check depth " + std::to_string(o.depth) + " would insert " + number_text(inserted, 3) +
        " knots in the references (limit 2^26, about the memory of the machine's budget); lower the depth");

  const Points cart = nurbs::cartesian_points(c);
  const double scale = std::max(cart.cwiseAbs().maxCoeff(), 1e-300);
  const double weight_scale = nurbs::weights(c).maxCoeff();
  const std::vector<Points> nets = nurbs::initial_nets(knots, c);
  const double leaves = std::ldexp(1.0, o.depth);

  CheckReport report{o.depth, o.tolerance, {}, {}, {}, false};
  std::vector<LocalSegment> locals;
  std::vector<nurbs::Curve> refined;  // (a) references: every dyadic knot of every inter-knot of the window
  for (std::size_t i = 0; i < a.initial.size(); ++i) {
    const nurbs::KnotInterval& interval = knots.intervals[i];
    locals.push_back(local_segment(c, interval.span));
    refined.push_back(nurbs::refine(locals.back().curve, dyadic_knots(locals.back().window, leaves)));
    report.segments.push_back(SegmentReport{a.initial[i].segment, interval.start, interval.end, {}, {}});
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
              .stableNorm()
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
    track(report.segments[i].points, (points.row(m) - nurbs::evaluate_basis(locals[i].piece, u)).stableNorm(),
          scale);
  }
  for (const SegmentReport& seg : report.segments) {
    merge(report.nets, seg.nets);
    merge(report.points, seg.points);
  }
  report.pass = report.nets.max_rel <= o.tolerance && report.points.max_rel <= o.tolerance;
  return report;
}

namespace {

/// Most points one patch's reference may hold (about 8 bytes × cols each).
constexpr double kMaxReferencePoints = 1 << 23;

/// Patch (a, b) in its own coordinates: the wide surface (domain = both windows) and the patch.
struct LocalPatch {
  nurbs::Surface wide, piece;
  std::array<double, 2> length{};
};

LocalPatch local_patch(const nurbs::Surface& s, const Points& net, const std::array<LocalKnots, 2>& k) {
  const int p = s.degree[0], q = s.degree[1];
  Points W((3 * p + 1) * (3 * q + 1), net.cols());
  for (int i = 0; i <= 3 * p; ++i)
    for (int j = 0; j <= 3 * q; ++j)
      W.row(i * (3 * q + 1) + j) = net.row(wide_row(i, p) * (q + 1) + wide_row(j, q));
  LocalPatch out;
  out.wide =
      nurbs::Surface{s.degree, {k[0].wide, k[1].wide}, {3 * p + 1, 3 * q + 1}, std::move(W), s.rational};
  out.piece = nurbs::Surface{s.degree, {k[0].piece, k[1].piece}, {p + 1, q + 1}, net, s.rational};
  out.length = {k[0].window[static_cast<std::size_t>(p)], k[1].window[static_cast<std::size_t>(q)]};
  return out;
}

/// Refuses bad options and a depth whose references would not fit, before any work.
void check_surface_options(const nurbs::Surface& s, const CheckOptions& o) {
  if (o.depth < 0 || o.depth > 30)
    throw InvalidInput("the check depth " + std::to_string(o.depth) + " is outside [0, 30]");
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw InvalidInput("the check tolerance " +
                       (std::isfinite(o.tolerance) ? number_text(o.tolerance, 6) + " is not positive"
                                                   : std::string("is not a finite number")) +
                       "; give a positive finite tolerance");
  nurbs::validate(s);
  const int p = s.degree[0], q = s.degree[1];
  const double leaves = std::ldexp(1.0, o.depth);
  // Reference size of one patch: the wide net refined by (2d − 1)(2^K − 1) knots per direction.
  const double reference =
      (3 * p + 1 + (2 * p - 1) * (leaves - 1)) * (3 * q + 1 + (2 * q - 1) * (leaves - 1));
  if (reference > kMaxReferencePoints)
    throw InvalidInput("the check depth " + std::to_string(o.depth) + " needs references of " +
                       number_text(reference, 3) +
                       " control points per patch (limit 2^23, about the memory of the machine's budget); "
                       "lower the depth");
}

/// The surface's automaton, nets and patches, as both checks read them.
struct SurfaceCheck {
  const nurbs::Surface& s;
  int depth;
  double leaves;  // 2^depth
  nurbs::TensorAutomaton t;
  std::vector<Points> nets;
  double scale, weight_scale;
  std::array<std::vector<LocalKnots>, 2> knots;  // per direction and interval
  std::vector<LocalPatch> locals;                // per patch
};

/// The check's data, and the report with one entry per patch.
SurfaceCheck prepare_check(const nurbs::Surface& s, int depth, SurfaceCheckReport& report) {
  nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  std::vector<Points> nets = nurbs::initial_nets(t, s);
  const Points cart = nurbs::cartesian_points(s);
  const double scale = std::max(cart.cwiseAbs().maxCoeff(), 1e-300);
  const double weight_scale = nurbs::weights(s).maxCoeff();
  SurfaceCheck c{s,  depth, std::ldexp(1.0, depth), std::move(t), std::move(nets), scale, weight_scale,
                 {}, {}};
  for (std::size_t dir = 0; dir < 2; ++dir)
    for (const nurbs::KnotInterval& interval : c.t.factors[dir].intervals)
      c.knots[dir].push_back(
          local_knots(nurbs::segment_window(s.knots[dir], s.degree[dir], interval.span), s.degree[dir]));
  for (std::size_t k = 0; k < c.t.patches.size(); ++k) {
    const auto [a, b] = c.t.patches[k];
    const nurbs::KnotInterval& iu = c.t.factors[0].intervals[static_cast<std::size_t>(a)];
    const nurbs::KnotInterval& iv = c.t.factors[1].intervals[static_cast<std::size_t>(b)];
    c.locals.push_back(local_patch(
        s, c.nets[k], {c.knots[0][static_cast<std::size_t>(a)], c.knots[1][static_cast<std::size_t>(b)]}));
    report.patches.push_back(PatchReport{{a, b}, {iu.start, iu.end}, {iv.start, iv.end}, {}, {}});
  }
  return c;
}

/// (a) Leaf nets against the refined wide patch, one patch's reference in memory at a time (the
/// leaves come patch by patch).
void check_leaf_nets(const SurfaceCheck& c, SurfaceCheckReport& report) {
  const nurbs::Surface& s = c.s;
  const int p = s.degree[0], q = s.degree[1];
  const double leaves = c.leaves;
  std::size_t current = c.t.patches.size();
  nurbs::Surface refined;
  ifs::for_each_leaf(c.t.product, c.nets, c.depth, [&](const ifs::Leaf& leaf) {
    const std::size_t k = leaf.initial;
    const LocalPatch& local = c.locals[k];
    if (k != current) {
      const auto [a, b] = c.t.patches[k];
      refined = nurbs::refine(local.wide, nurbs::Direction::u,
                              dyadic_knots(c.knots[0][static_cast<std::size_t>(a)].window, leaves));
      refined = nurbs::refine(refined, nurbs::Direction::v,
                              dyadic_knots(c.knots[1][static_cast<std::size_t>(b)].window, leaves));
      current = k;
    }
    long long iu = 0, iv = 0;
    for (int w : leaf.word) {
      iu = 2 * iu + w / 2;
      iv = 2 * iv + w % 2;
    }
    // The inserted knots, bit for bit.
    const double u = static_cast<double>(iu) * (local.length[0] / leaves);
    const double v = static_cast<double>(iv) * (local.length[1] / leaves);
    const int su = nurbs::find_span(refined.knots[0], p, u), sv = nurbs::find_span(refined.knots[1], q, v);
    Points expected(leaf.net.rows(), leaf.net.cols());
    for (int i = 0; i <= p; ++i)
      expected.middleRows(Eigen::Index{i} * (q + 1), q + 1) =
          refined.P.middleRows((su - p + i) * refined.count[1] + sv - q, q + 1);
    PatchReport& patch = report.patches[k];
    track(patch.nets,
          (cartesian_rows(leaf.net, s.rational) - cartesian_rows(expected, s.rational))
              .rowwise()
              .stableNorm()
              .maxCoeff(),
          c.scale);
    if (s.rational)
      track(patch.nets,
            (leaf.net.col(leaf.net.cols() - 1) - expected.col(expected.cols() - 1)).cwiseAbs().maxCoeff(),
            c.weight_scale);
  });
}

/// (b) Mesh vertices against evaluate_grid, each in the patch that owns it.
void check_mesh_vertices(const SurfaceCheck& c, SurfaceCheckReport& report) {
  const double leaves = c.leaves;
  ifs::MeshOptions mesh_options;
  mesh_options.homogeneous = c.s.rational;
  const Mesh mesh = ifs::surface_mesh(c.t, c.nets, c.depth, mesh_options);
  const int A = static_cast<int>(c.t.factors[0].automaton.initial.size()),
            B = static_cast<int>(c.t.factors[1].automaton.initial.size());
  const auto n = static_cast<int>(leaves);
  const Eigen::Index row = static_cast<Eigen::Index>(B) * n + 1;
  const auto parameters = [&](double length, int count) {
    std::vector<double> ts(static_cast<std::size_t>(count));
    for (int m = 0; m < count; ++m) ts[static_cast<std::size_t>(m)] = m * (length / leaves);
    return ts;
  };
  for (std::size_t k = 0; k < c.t.patches.size(); ++k) {
    const auto [a, b] = c.t.patches[k];
    const int rows = n + (a + 1 == A ? 1 : 0), cols = n + (b + 1 == B ? 1 : 0);
    const Points expected = nurbs::evaluate_grid(c.locals[k].piece, parameters(c.locals[k].length[0], rows),
                                                 parameters(c.locals[k].length[1], cols));
    for (int i = 0; i < rows; ++i)
      track(report.patches[k].points,
            (mesh.vertices.middleRows(
                 (static_cast<Eigen::Index>(a) * n + i) * row + static_cast<Eigen::Index>(b) * n, cols) -
             expected.middleRows(static_cast<Eigen::Index>(i) * cols, cols))
                .rowwise()
                .stableNorm()
                .maxCoeff(),
            c.scale);
  }
}

}  // namespace

SurfaceCheckReport check_surface(const nurbs::Surface& s, const CheckOptions& o) {
  check_surface_options(s, o);
  SurfaceCheckReport report{o.depth, o.tolerance, {}, {}, {}, false};
  const SurfaceCheck c = prepare_check(s, o.depth, report);
  check_leaf_nets(c, report);
  check_mesh_vertices(c, report);
  for (const PatchReport& patch : report.patches) {
    merge(report.nets, patch.nets);
    merge(report.points, patch.points);
  }
  report.pass = report.nets.max_rel <= o.tolerance && report.points.max_rel <= o.tolerance;
  return report;
}

}  // namespace cifs::verify
