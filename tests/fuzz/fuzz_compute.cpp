// SPDX-License-Identifier: MIT
// Fuzzing: the computations behind eval, insert, attractor, check and dimension, with fuzzed shapes
// and fuzzed option values. An input is 16 bytes of options, then a JSON shape file:
//
//   byte 0       the operation (below)
//   bytes 1–8    a double, raw bits (so NaN, ±inf, subnormals and −0 come up): the parameter,
//                knot, tolerance, piece size or deviation
//   byte 9       a small count: depth, multiplicity, samples
//   byte 10      flags (chordal, direction)
//   bytes 11–15  unused (room for more options without changing the seeds' meaning)
//
// Properties beyond "no crash, leak or unexpected exception": an operation that returns on a
// valid, finite shape returns finite numbers (no silent NaN or inf, issue 33), and refined shapes
// validate. The work per input is bounded (≤ 32 control points, small depths, 4,096 points), so that
// the harness runs at pipeline speed or better; the library's own limits are what refuse the rest.
#include <cmath>
#include <cstring>
#include <vector>

#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/chaos.hpp"
#include "cifs/ifs/dimension.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/verify/check.hpp"
#include "fuzz.hpp"

// Named, not anonymous: the harnesses compile as unity batches (CIFS_UNITY), each in its own namespace.
namespace fuzz_compute {

using namespace cifs;

constexpr std::size_t kOptionBytes = 16;
constexpr Eigen::Index kMaxControlPoints = 32;
constexpr std::size_t kMaxPoints = 4096;

struct Options {
  int operation = 0;
  double value = 0;
  int count = 0;
  int flags = 0;
};

void require_finite(const Points& P, const char* what) {
  fuzz::require(P.allFinite(), what);
}

/// The automaton, nets and rationality of a curve or a surface, as the CLI builds them.
struct System {
  automata::Automaton automaton;
  std::vector<Points> nets;
  bool rational = false;
};

System curve_system(const nurbs::Curve& c) {
  nurbs::KnotAutomaton k = nurbs::knot_automaton(c);
  std::vector<Points> nets = nurbs::initial_nets(k, c);
  return {std::move(k.automaton), std::move(nets), c.rational};
}

System surface_system(const nurbs::Surface& s) {
  nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  std::vector<Points> nets = nurbs::initial_nets(t, s);
  return {std::move(t.product), std::move(nets), s.rational};
}

/// attractor --piece-size / --deviation / --depth / --chaos and dimension, on either kind of shape.
void attractor_operations(const System& sys, const Options& o, bool curve) {
  const std::span<const Points> nets(sys.nets);
  switch (o.operation) {
    case 2: {  // --depth K
      ifs::PointsOptions po;
      po.max_bytes = kMaxPoints * 4 * sizeof(double);
      const Points H = ifs::attractor_points(sys.automaton, nets, o.count % 16, po);
      require_finite(sys.rational ? ifs::cartesian(H) : H, "attractor points finite");
      break;
    }
    case 3: {  // --piece-size E / --deviation D
      const ifs::SampleOptions so{.tolerance = std::abs(o.value),
                                  .chordal = curve && (o.flags & 1) != 0,
                                  .homogeneous = sys.rational,
                                  .max_depth = 40,
                                  .max_points = kMaxPoints};
      require_finite(ifs::sample_attractor(sys.automaton, nets, so).points, "tolerance sample finite");
      break;
    }
    case 4: {  // --chaos N
      ifs::ChaosOptions co;
      co.samples = static_cast<std::size_t>(o.count) * 16 + 1;
      co.seed = 1;
      const ifs::ChaosResult r = ifs::chaos_game(sys.automaton, nets, co);
      require_finite(sys.rational ? ifs::cartesian(r.points) : r.points, "chaos game finite");
      break;
    }
    default: {  // dimension --relative-piece-size
      ifs::ToleranceSampleOptions to;
      to.epsilon = std::abs(o.value);
      to.homogeneous = sys.rational;
      to.max_points = kMaxPoints;
      to.max_depth = 40;
      const ifs::ToleranceSample sample = ifs::tolerance_sample(sys.automaton, nets, to);
      require_finite(sample.points, "dimension sample finite");
      if (sample.points.rows() > 1) (void)ifs::box_counting(sample.points);
      break;
    }
  }
}

void curve_operations(const nurbs::Curve& c, const Options& o) {
  switch (o.operation) {
    case 0: {  // eval --at U, --samples N
      const nurbs::Domain dom = nurbs::domain(c);
      require_finite(nurbs::evaluate(c, o.value), "eval --at finite");
      require_finite(nurbs::evaluate(c, nurbs::uniform_parameters(dom, o.count % 64 + 1)),
                     "eval --samples finite");
      break;
    }
    case 1: {  // insert --knot U (times), --midpoints
      const nurbs::Curve r = nurbs::insert_knot(c, o.value, o.count % 5 + 1);
      nurbs::validate(r);
      if ((o.flags & 1) != 0) nurbs::validate(nurbs::refine_midpoints(r));
      break;
    }
    case 5: {  // check --depth K --relative-tolerance T
      const verify::CheckReport report = verify::check_curve(c, {.depth = o.count % 5, .tolerance = o.value});
      fuzz::require(!std::isnan(report.nets.max_rel) && !std::isnan(report.points.max_rel), "check measures");
      break;
    }
    default:
      attractor_operations(curve_system(c), o, true);
  }
}

void surface_operations(const nurbs::Surface& s, const Options& o) {
  const auto dir = (o.flags & 2) != 0 ? nurbs::Direction::v : nurbs::Direction::u;
  switch (o.operation) {
    case 0: {
      const nurbs::Domain du = nurbs::domain(s, nurbs::Direction::u);
      require_finite(nurbs::evaluate(s, o.value, du.start), "eval --at u,v finite");
      break;
    }
    case 1: {
      const nurbs::Surface r = nurbs::insert_knot(s, dir, o.value, o.count % 4 + 1);
      nurbs::validate(r);
      break;
    }
    case 5: {
      const verify::SurfaceCheckReport report =
          verify::check_surface(s, {.depth = o.count % 3, .tolerance = o.value});
      fuzz::require(!std::isnan(report.nets.max_rel) && !std::isnan(report.points.max_rel), "check measures");
      break;
    }
    default:
      if (o.operation == 2) {  // a surface's depth: the quad mesh, kept small
        const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
        ifs::MeshOptions mo;
        mo.homogeneous = s.rational;
        mo.max_bytes = std::size_t{1} << 20;
        const Mesh m = ifs::surface_mesh(t, nurbs::initial_nets(t, s), o.count % 5, mo);
        require_finite(m.vertices, "surface mesh finite");
        break;
      }
      attractor_operations(surface_system(s), o, false);
  }
}

CIFS_FUZZ_HARNESS(compute) {
  if (size < kOptionBytes) return 0;
  Options o;
  o.operation = data[0] % 7;
  std::memcpy(&o.value, data + 1, sizeof o.value);
  o.count = data[9];
  o.flags = data[10];
  fuzz::refusals_allowed([&] {
    const io::ShapeReadOptions read{.ignore_trim = true, .index = 0, .warn = [](const std::string&) {}};
    const std::vector<io::Shape> shapes =
        io::parse_shapes_json(fuzz::text(data + kOptionBytes, size - kOptionBytes), "fuzz.json", read);
    if (shapes.empty()) return;
    if (const auto* c = std::get_if<nurbs::Curve>(&shapes.front())) {
      if (c->P.rows() > kMaxControlPoints || c->degree > 6) return;  // the work per input
      curve_operations(*c, o);
    } else {
      const auto& s = std::get<nurbs::Surface>(shapes.front());
      if (s.P.rows() > kMaxControlPoints || s.degree[0] > 3 || s.degree[1] > 3) return;
      surface_operations(s, o);
    }
  });
  return 0;
}

}  // namespace fuzz_compute
