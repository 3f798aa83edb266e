// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs_curve.hpp"

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/failing_paths.hpp"
#include "cifs/nurbs/refine.hpp"
#include "cifs/random.hpp"
#include "ifs/bcifs_helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using ifs_test::max_residual;

namespace {

Points polygon(Eigen::Index n) {
  Points P(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    P.row(i) << t + 0.3 * std::sin(3 * t), std::cos(1.7 * t) + 0.1 * t * t;
  }
  return P;
}

nurbs::Curve uniform_curve(int d, int n) {
  nurbs::Knots U(static_cast<std::size_t>(n + d + 1));
  for (std::size_t i = 0; i < U.size(); ++i) U[i] = static_cast<double>(i);
  return nurbs::make_curve(d, U, polygon(n));
}

/// Curves of every kind the builder must handle: simple, double, triple and clamped knots,
/// rational weights, closed.
std::vector<nurbs::Curve> sample_curves() {
  std::vector<nurbs::Curve> out;
  out.push_back(uniform_curve(2, 5));
  out.push_back(uniform_curve(3, 6));
  out.push_back(nurbs::make_curve(2, {0, 0, 0, 0.3, 1.1, 1.5, 2.6, 2.6, 2.6}, polygon(6)));
  out.push_back(nurbs::make_curve(3, {0, 0, 0, 0, 1, 2, 2, 3, 4, 4, 4, 4}, polygon(8)));
  out.push_back(nurbs::make_curve(4, {0, 0, 0, 0, 0, 1, 1, 1, 2.5, 3, 3, 3, 3, 3}, polygon(9)));
  out.push_back(nurbs::make_curve(3, {0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2}, polygon(7)));
  Eigen::VectorXd w(5);
  w << 1, 0.7, 1.3, 0.7, 1;
  out.push_back(nurbs::make_curve(2, {0, 0, 0, 1, 1, 2, 2, 2}, polygon(5), w));
  out.push_back(nurbs::make_closed_curve(3, {0, 1, 2, 3.5, 4, 5}, polygon(5)));
  out.push_back(nurbs::elevate_degree(nurbs::make_curve(3, {0, 0, 0, 0, 1, 2.5, 3, 3, 3, 3}, polygon(6))));
  return out;
}

/// Piece j of segment `seg` at depth K spans this parameter interval of the curve.
double piece_parameter(const nurbs::KnotInterval& init, int j, int K) {
  return init.start + (init.end - init.start) * std::ldexp(static_cast<double>(j), -K);
}

}  // namespace

TEST_CASE("curve BC-IFS: the NURBS matrices are admissible", "[bcifs][curve]") {
  for (const auto& curve : sample_curves()) {
    for (const bool free_vertices : {false, true}) {
      CAPTURE(curve.degree, curve.knots, curve.closed, free_vertices);
      const Bcifs sys = curve_bcifs(curve, {.free_vertices = free_vertices});
      CHECK(max_residual(sys) <= 1e-14);
      CHECK_NOTHROW(check_admissible(sys, 1e-14));
      // The vertex cells give the end points of every segment (row selection by multiplicity):
      // against de Boor evaluation.
      const nurbs::KnotAutomaton knot = nurbs::knot_automaton(curve);
      const nurbs::KnotAutomaton knots = curve_bcifs_knots(sys.automaton, knot);
      // Edge cell "s3ab" unfolds knot state "s3" and has its window; vertex cells have none.
      REQUIRE(knots.windows.size() == num_vertices(sys.automaton.graph));
      for (automata::StateId s = 0; s < knots.windows.size(); ++s) {
        std::string name = sys.automaton.graph[s].name;
        if (sys.dimension[s] == 0) {
          CHECK(knots.windows[s].empty());
          continue;
        }
        while (name.back() == 'a' || name.back() == 'b') name.pop_back();
        CHECK(knots.windows[s] == knot.windows[static_cast<std::size_t>(std::stoi(name.substr(1)))]);
      }
      const auto nets = nurbs::initial_nets(knots, curve);
      const auto F = edge_end_functionals(sys);
      for (std::size_t i = 0; i < nets.size(); ++i) {
        const auto& init = sys.automaton.initial[i];
        const Points ends = [&] {
          Points h(2, nets[i].cols());
          h.row(0) = F.start[init.state] * nets[i];
          h.row(1) = F.end[init.state] * nets[i];
          return curve.rational ? cartesian(h) : h;
        }();
        const double scale = std::max(1.0, curve.P.cwiseAbs().maxCoeff());
        CHECK((ends.row(0) - nurbs::evaluate(curve, knots.intervals[i].start)).norm() <= 1e-13 * scale);
        CHECK((ends.row(1) - nurbs::evaluate(curve, knots.intervals[i].end)).norm() <=
              1e-13 * scale);  // wraps when closed
      }
      // Amplitude 0 gives back the NURBS matrices and the NURBS attractor.
      const Perturbation p = perturb(sys);
      CHECK(p.residual <= 1e-14);
      for (automata::StateId s = 0; s < num_vertices(sys.automaton.graph); ++s)
        for (int c = 0; c < static_cast<int>(out_degree(s, sys.automaton.graph)); ++c) {
          const auto& before = sys.automaton.graph[transition_id(sys.automaton, {s, c})].matrix;
          const auto& after = p.system.automaton.graph[transition_id(p.system.automaton, {s, c})].matrix;
          CHECK((before - after).cwiseAbs().maxCoeff() <= 1e-14);
        }
      if (curve.rational) continue;
      const int K = 4;
      const EdgePieces pieces = edge_pieces(p.system, nets, K);
      REQUIRE(pieces.start.rows() == (static_cast<Eigen::Index>(nets.size()) << K));
      for (Eigen::Index r = 0; r < pieces.start.rows(); ++r) {
        const auto& init = knots.intervals[pieces.initial[static_cast<std::size_t>(r)]];
        const int j = static_cast<int>(r % (Eigen::Index{1} << K));
        CHECK((pieces.start.row(r) - nurbs::evaluate(curve, piece_parameter(init, j, K))).norm() <=
              1e-12 * std::max(1.0, curve.P.cwiseAbs().maxCoeff()));
      }
    }
  }
}

TEST_CASE("curve BC-IFS: free coefficients of uniform B-splines (hand counts)", "[bcifs][curve]") {
  // Uniform open curves with several segments: edge cells "ab" (the segments), "a", "b" and ""
  // (unfolded uniform state), vertex classes K1 = {ab.start, ab.end} → K2 = {a.start, b.end} → K2
  // at the knots, and M = {a.end, b.start, .start, .end} at the midpoints. Per edge cell with
  // start operator Vs and end operator Ve, incidence fixes G's first d rows as [Vs 0] and D's last
  // d rows as [0 Ve]; the junction G rows 1…d = D rows 0…d−1 then determines the rest.
  // Quadratic: no condition is left on the vertex operators (2×2), so the free coefficients are
  // those of the free vertex operators, 2 each (4 entries − 2 row sums): default M only → 2;
  // free vertices K1, K2, M → 6.
  CHECK(admissible_space(curve_bcifs(uniform_curve(2, 5))).free.size() == 2);
  CHECK(admissible_space(curve_bcifs(uniform_curve(2, 5), {.free_vertices = true})).free.size() == 6);
  // Cubic: the junction row 2 adds "Vs row 2 = (0, Ve row 0 without its last entry), Ve(0,2) = 0".
  // Default (K fixed, Chaikin-like rows [½ ½ 0], [0 ½ ½] at both ends): cells "a" and "b" force
  // M rows 0 and 2 to those, leaving M row 1: 3 entries − 1 row sum = 2. Free vertices: K1 has
  // rows 0 and 2 tied (a, 1−a) plus a free row 1 → 3; K2 likewise → 3; M shares K2's rows 0 and 2
  // and adds its row 1 → 2; total 8.
  CHECK(admissible_space(curve_bcifs(uniform_curve(3, 6))).free.size() == 2);
  CHECK(admissible_space(curve_bcifs(uniform_curve(3, 6), {.free_vertices = true})).free.size() == 8);
}

TEST_CASE("curve BC-IFS: perturbed curves keep knots and end points and stay joined", "[bcifs][curve]") {
  for (const auto& curve : sample_curves()) {
    if (curve.rational) continue;
    CAPTURE(curve.degree, curve.knots, curve.closed);
    const Bcifs sys = curve_bcifs(curve);
    const nurbs::KnotAutomaton knots = curve_bcifs_knots(sys.automaton, nurbs::knot_automaton(curve));
    const auto nets = nurbs::initial_nets(knots, curve);
    PerturbOptions options;
    options.amplitude = 0.02;
    options.seed = 3;
    const Perturbation p = perturb(sys, options);
    CHECK(p.residual <= 1e-12);
    const int K = 6;
    const EdgePieces pieces = edge_pieces(p.system, nets, K);
    const double scale = std::max(1.0, curve.P.cwiseAbs().maxCoeff());
    double moved = 0;
    const Eigen::Index per_segment = Eigen::Index{1} << K;
    for (Eigen::Index r = 0; r < pieces.start.rows(); ++r) {
      const auto& init = knots.intervals[pieces.initial[static_cast<std::size_t>(r)]];
      const Eigen::Index j = r % per_segment;
      // Joined: every piece ends where the next starts (G end = D start at every node, and
      // neighbouring segments; closed curves wrap).
      const Eigen::Index next = r + 1 < pieces.start.rows() ? r + 1 : 0;
      if (next != 0 || curve.closed)
        CHECK((pieces.end.row(r) - pieces.start.row(next)).norm() <= 1e-12 * scale);
      // Knot points and end points stay on the NURBS curve.
      if (j == 0) CHECK((pieces.start.row(r) - nurbs::evaluate(curve, init.start)).norm() <= 1e-12 * scale);
      if (j == per_segment - 1 && !(curve.closed && next == 0))
        CHECK((pieces.end.row(r) - nurbs::evaluate(curve, init.end)).norm() <= 1e-12 * scale);
      moved = std::max(
          moved, (pieces.start.row(r) - nurbs::evaluate(curve, piece_parameter(init, static_cast<int>(j), K)))
                     .norm());
    }
    CHECK(moved > 1e-4);  // the geometry between knots did change
    // attractor_points (ifs::end_functionals, first child) agrees with the vertex-cell functionals.
    const Points pts = attractor_points(p.system.automaton, nets, K, {.closed = curve.closed});
    for (Eigen::Index r = 0; r < pieces.start.rows(); ++r)
      CHECK((pts.row(r) - pieces.start.row(r)).norm() <= 1e-12 * scale);
  }
}

TEST_CASE("curve BC-IFS: free vertex operators move the knots, junctions hold", "[bcifs][curve]") {
  const nurbs::Curve curve = uniform_curve(3, 6);
  const Bcifs sys = curve_bcifs(curve, {.free_vertices = true});
  const nurbs::KnotAutomaton knots = curve_bcifs_knots(sys.automaton, nurbs::knot_automaton(curve));
  const auto nets = nurbs::initial_nets(knots, curve);
  PerturbOptions options;
  options.amplitude = 0.03;
  options.seed = 5;
  const Perturbation p = perturb(sys, options);
  const EdgePieces pieces = edge_pieces(p.system, nets, 5);
  double knot_moved = 0;
  for (Eigen::Index r = 0; r + 1 < pieces.start.rows(); ++r) {
    CHECK((pieces.end.row(r) - pieces.start.row(r + 1)).norm() <= 1e-12 * 10);
    if (r % 32 == 0) {
      const auto& init = knots.intervals[pieces.initial[static_cast<std::size_t>(r)]];
      knot_moved = std::max(knot_moved, (pieces.start.row(r) - nurbs::evaluate(curve, init.start)).norm());
    }
  }
  CHECK(knot_moved > 1e-4);
}

namespace {

/// Brute force over every path of `m` transitions from every reachable state: the largest δ of the
/// products of length m and the largest ∞-norm of the products of length 0 … m (Contraction's δ_m, A_m).
std::pair<double, double> all_paths(const automata::Automaton& a, int m) {
  double worst = 0, A = 1;
  const auto walk = [&](auto&& self, automata::StateId s, const Eigen::MatrixXd& P, int k) -> void {
    A = std::max(A, P.cwiseAbs().rowwise().sum().maxCoeff());
    if (k == m) {
      worst = std::max(worst, delta(P));
      return;
    }
    for (auto [b, e] = out_edges(s, a.graph); b != e; ++b)
      self(self, target(*b, a.graph), (a.graph[*b].matrix * P).eval(), k + 1);
  };
  for (const automata::StateId s : reachable_states(a)) {
    const auto n = a.graph[s].size;
    walk(walk, s, Eigen::MatrixXd::Identity(n, n), 0);
  }
  return {worst, A};
}

}  // namespace

TEST_CASE("contraction: skipping bounded subtrees gives the full scan's δ and A", "[bcifs][curve]") {
  // Perturbed cubic BC-IFS of 18 states whose witnesses have length 4 and 7: the scans past length 3
  // skip subtrees by δ(B·P) ≤ δ(B)·δ(P) and ‖B·P‖ ≤ ‖B‖·‖P‖; brute force enumerates every path.
  const Bcifs system = curve_bcifs(nurbs::make_curve(3, {0, 0, 0, 0, 1, 2, 4, 4, 4, 4}, polygon(6)));
  int longest = 0;
  for (const auto& [amplitude, seed] : {std::pair{0.3, 1}, {0.3, 2}, {0.3, 4}, {0.5, 2}, {0.5, 5}}) {
    PerturbOptions options;
    options.amplitude = amplitude;
    options.seed = static_cast<std::uint64_t>(seed);
    options.contraction.tighten = false;
    const automata::Automaton a = perturb(system, options).system.automaton;
    const Contraction c = contraction(a, {.tighten = false});
    INFO("amplitude " << amplitude << ", seed " << seed << ": m = " << c.m);
    longest = std::max(longest, c.m);
    const auto [worst, A] = all_paths(a, c.m);
    CHECK(c.delta == Approx(worst).epsilon(1e-14));
    CHECK(c.A >= A * (1 - 1e-14));
    CHECK(c.A <= A * (1 + 1e-12));
    CHECK(c.radius == Approx((1 + c.A) / (2 * (1 - c.delta))).epsilon(1e-14));
    // Shorter lengths fail (m is the smallest witness).
    if (c.m > 1) CHECK(all_paths(a, c.m - 1).first >= 1);
    // Contractivity alone: the same witness and δ, no bound.
    const Contraction proof = contraction(a, {.tighten = false, .bound = false});
    CHECK(proof.m == c.m);
    CHECK(proof.delta == Approx(worst).epsilon(1e-14));
    CHECK(std::isinf(proof.A));
    CHECK(std::isinf(proof.radius));
  }
  CHECK(longest >= 7);
}

namespace {

/// Everything a contraction check answers, to the bit: m, δ, A, the radius and its length, or the refusal's
/// message, δ and length.
std::string outcome(const automata::Automaton& a, const ContractionOptions& options,
                    FailingPaths* failing = nullptr) {
  const auto bits = [](double x) { return std::to_string(std::bit_cast<std::uint64_t>(x)); };
  try {
    const Contraction c = failing != nullptr ? contraction(a, options, *failing) : contraction(a, options);
    return "m " + std::to_string(c.m) + " δ " + bits(c.delta) + " A " + bits(c.A) + " radius " +
           bits(c.radius) + " at " + std::to_string(c.radius_length);
  } catch (const NotContractive& e) {
    return std::string(e.what()) + " δ " + bits(e.delta) + " length " + std::to_string(e.length);
  }
}

}  // namespace

TEST_CASE("contraction: failing paths kept from the last checks give the cold check's result, bit for bit",
          "[bcifs][curve]") {
  // cifs view's edits of a perturbation — the free coefficients of a perturbed cubic BC-IFS (18 states,
  // witnesses of length 3 to 8) drawn again and again, some beyond contractivity — each checked from cold and
  // with the paths the previous checks kept (ifs::FailingPaths), both for contractivity alone (the view's
  // check) and with the bound: the same answer to the last bit, refusals included; and the kept paths do
  // settle lengths (the warm route is taken, not only the scans).
  const Bcifs system = curve_bcifs(nurbs::make_curve(3, {0, 0, 0, 0, 1, 2, 4, 4, 4, 4}, polygon(6)));
  const AdmissibleSpace space = admissible_space(system);
  const Eigen::VectorXd start = free_values(system, space);
  Random random(31);
  FailingPaths proof, bound;  // kept across the edits, one per kind of check
  std::set<std::string> kinds;
  int below = 0;  // lengths below the witness m, over the contractive checks
  for (int edit = 0; edit < 60; ++edit) {
    const double amplitude = 0.6 * random.uniform();
    Eigen::VectorXd c = start;
    for (Eigen::Index j = 0; j < c.size(); ++j) c(j) += amplitude * random.symmetric();
    const automata::Automaton a = with_free_values(system, space, c).automaton;
    INFO("edit " << edit << ", amplitude " << amplitude);
    const std::string cold = outcome(a, {.tighten = false, .bound = false});
    CHECK(outcome(a, {.tighten = false, .bound = false}, &proof) == cold);
    CHECK(outcome(a, {}, &bound) == outcome(a, {}));
    const bool contractive = cold.starts_with("m ");
    kinds.insert(contractive ? cold.substr(0, cold.find(' ', 2)) : "refused");
    if (contractive) below += std::stoi(cold.substr(2)) - 1;
  }
  INFO(below << " lengths below m, " << proof.settled << " settled by kept paths");
  CHECK(kinds.count("refused") == 1);
  CHECK(kinds.size() >= 4);  // and witnesses of three lengths or more
  CHECK(proof.settled >= below / 2);
  CHECK(bound.settled >= below / 2);
}
