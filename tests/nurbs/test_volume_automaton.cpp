// SPDX-License-Identifier: MIT
// The tensor-product automaton of a volume: its states against a brute-force search of reachable triples,
// its transitions against Eigen's Kronecker product, and its attractor (the nets after a word, read with
// the window's own B-spline basis) against the volume at the word's dyadic parameters.
#include <algorithm>
#include <catch2/catch.hpp>
#include <set>
#include <unsupported/Eigen/KroneckerProduct>

#include "cifs/errors.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;
using automata::StateId;

namespace {

/// A random volume of degrees 1 … 3, non-uniform knots with repeated knots, rational or not.
Volume random_automaton_volume(Rng& rng, bool rational) {
  std::array<int, 3> degree{};
  std::array<Knots, 3> knots;
  std::array<Eigen::Index, 3> count{};
  for (std::size_t d = 0; d < 3; ++d) {
    degree[d] = uniform_int(rng, 1, 3);
    count[d] = degree[d] + 1 + uniform_int(rng, 1, 3);
    knots[d] = random_knots(rng, degree[d], static_cast<int>(count[d]), coin(rng));
  }
  const Eigen::Index rows = count[0] * count[1] * count[2];
  Eigen::VectorXd w;
  if (rational) {
    w.resize(rows);
    for (Eigen::Index i = 0; i < rows; ++i) w(i) = std::pow(2.0, uniform(rng, -1, 1));
  }
  return make_volume(degree, knots, count, random_points(rng, rows, 3), w);
}

/// The d + 1 B-spline basis functions of a segment of window `window` (the knot differences around it,
/// Cox–de Boor in long double) at the fraction x ∈ [0, 1] of the segment.
RealVec window_basis(const Window& window, int d, double x) {
  Knots t{-1.0, 0.0};  // one more knot at each end: it does not reach the central segment
  for (double len : window) t.push_back(t.back() + len);
  t.push_back(t.back() + 1);
  const double a = t[static_cast<std::size_t>(d)], b = t[static_cast<std::size_t>(d) + 1];
  return ref_basis(t, d, x == 1 ? b : a + x * (b - a), x == 1);
}

}  // namespace

TEST_CASE("volume automaton: reachable triples, sizes, labels and Kronecker matrices",
          "[nurbs][volume][tensor]") {
  Rng rng(3201);
  for (int trial = 0; trial < 10; ++trial) {
    const Volume vol = random_automaton_volume(rng, coin(rng));
    const VolumeAutomaton t = tensor_automaton(vol);
    const automata::Graph& g = t.product.graph;
    const auto n = num_vertices(g);
    CAPTURE(trial, vol.degree[0], vol.degree[1], vol.degree[2]);
    REQUIRE(t.factor_states.size() == n);
    // Brute force: the triples reachable from the initial triples, each factor stepping by one of its halves.
    std::array<const automata::Graph*, 3> fg{&t.factors[0].automaton.graph, &t.factors[1].automaton.graph,
                                             &t.factors[2].automaton.graph};
    std::set<std::array<StateId, 3>> seen;
    std::vector<std::array<StateId, 3>> stack;
    for (const auto& a : t.factors[0].automaton.initial)
      for (const auto& b : t.factors[1].automaton.initial)
        for (const auto& c : t.factors[2].automaton.initial)
          if (seen.insert({a.state, b.state, c.state}).second) stack.push_back({a.state, b.state, c.state});
    while (!stack.empty()) {
      const auto s = stack.back();
      stack.pop_back();
      for (auto [e0, x0] = out_edges(s[0], *fg[0]); e0 != x0; ++e0)
        for (auto [e1, x1] = out_edges(s[1], *fg[1]); e1 != x1; ++e1)
          for (auto [e2, x2] = out_edges(s[2], *fg[2]); e2 != x2; ++e2) {
            const std::array<StateId, 3> c{target(*e0, *fg[0]), target(*e1, *fg[1]), target(*e2, *fg[2])};
            if (seen.insert(c).second) stack.push_back(c);
          }
    }
    CHECK(std::set<std::array<StateId, 3>>(t.factor_states.begin(), t.factor_states.end()) == seen);
    CHECK(n == seen.size());
    // Cells: every (u, v, w) segment triple, w fastest.
    const std::size_t nu = t.factors[0].automaton.initial.size(), nv = t.factors[1].automaton.initial.size(),
                      nw = t.factors[2].automaton.initial.size();
    REQUIRE(t.product.initial.size() == nu * nv * nw);
    REQUIRE(t.cells.size() == nu * nv * nw);
    for (std::size_t k = 0; k < t.cells.size(); ++k) {
      CHECK(t.cells[k] == std::array<int, 3>{static_cast<int>(k / (nv * nw)), static_cast<int>(k / nw % nv),
                                             static_cast<int>(k % nw)});
      CHECK(t.product.initial[k].segment == static_cast<int>(k));
    }
    const char* labels[8] = {"GHA", "GHR", "GBA", "GBR", "DHA", "DHR", "DBA", "DBR"};
    for (StateId s = 0; s < n; ++s) {
      const auto f = t.factor_states[s];
      CHECK(g[s].size == (*fg[0])[f[0]].size * (*fg[1])[f[1]].size * (*fg[2])[f[2]].size);
      REQUIRE(out_degree(s, g) == 8);
      int child = 0;
      for (auto [e, end] = out_edges(s, g); e != end; ++e, ++child) {
        std::array<automata::TransitionId, 3> fe{};
        for (std::size_t d = 0; d < 3; ++d) {
          auto it = out_edges(f[d], *fg[d]).first;
          std::advance(it, child >> (2 - d) & 1);
          fe[d] = *it;
        }
        CHECK(g[*e].label == labels[child]);
        CHECK(t.factor_states[target(*e, g)] ==
              std::array<StateId, 3>{target(fe[0], *fg[0]), target(fe[1], *fg[1]), target(fe[2], *fg[2])});
        const Eigen::MatrixXd K = Eigen::kroneckerProduct(
            Eigen::MatrixXd(Eigen::kroneckerProduct((*fg[0])[fe[0]].matrix, (*fg[1])[fe[1]].matrix)),
            (*fg[2])[fe[2]].matrix);
        CHECK(g[*e].matrix == K);  // exactly
      }
    }
  }
}

TEST_CASE("volume automaton: the nets after a word are the volume on the word's dyadic cell",
          "[nurbs][volume][tensor]") {
  Rng rng(3202);
  for (int trial = 0; trial < 8; ++trial) {
    const Volume vol = random_automaton_volume(rng, trial % 2 == 0);
    const VolumeAutomaton t = tensor_automaton(vol);
    const std::vector<Points> nets = initial_nets(t, vol);
    REQUIRE(nets.size() == t.cells.size());
    const automata::Graph& g = t.product.graph;
    const double scale = cartesian_points(direction_curve(vol, 0)).cwiseAbs().maxCoeff() + 1;
    CAPTURE(trial, vol.rational);
    for (int sample = 0; sample < 6; ++sample) {
      const auto cell = static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(nets.size()) - 1));
      const int depth = uniform_int(rng, 0, 4);
      // Follow `depth` random children: the net Q = M·P, and the cell's dyadic position in each direction.
      StateId state = t.product.initial[cell].state;
      Points net = nets[cell];
      std::array<double, 3> corner{}, size{}, lo{}, hi{};
      for (std::size_t d = 0; d < 3; ++d) {
        const KnotInterval& in = t.factors[d].intervals[static_cast<std::size_t>(t.cells[cell][d])];
        corner[d] = lo[d] = in.start;
        hi[d] = in.end;
        size[d] = in.end - in.start;
      }
      for (int step = 0; step < depth; ++step) {
        const int child = uniform_int(rng, 0, 7);
        auto e = out_edges(state, g).first;
        std::advance(e, child);
        net = g[*e].matrix * net;
        state = target(*e, g);
        for (std::size_t d = 0; d < 3; ++d) {
          size[d] /= 2;
          if (child >> (2 - d) & 1) corner[d] += size[d];
        }
      }
      CAPTURE(sample, depth, cell);
      // The net read with the basis of its factor states' windows, at the cell's corners and centre.
      const std::array<int, 3>& p = vol.degree;
      for (double x : {0.0, 0.5, 1.0})
        for (double y : {0.0, 0.5, 1.0})
          for (double z : {0.0, 0.25, 1.0}) {
            const double frac[3] = {x, y, z};
            std::array<RealVec, 3> N;
            for (std::size_t d = 0; d < 3; ++d)
              N[d] = window_basis(t.factors[d].windows[t.factor_states[state][d]], p[d], frac[d]);
            Eigen::Matrix<Real, 1, Eigen::Dynamic> sum =
                Eigen::Matrix<Real, 1, Eigen::Dynamic>::Zero(net.cols());
            for (int i = 0; i <= p[0]; ++i)
              for (int j = 0; j <= p[1]; ++j)
                for (int k = 0; k <= p[2]; ++k)
                  sum += N[0][static_cast<std::size_t>(i)] * N[1][static_cast<std::size_t>(j)] *
                         N[2][static_cast<std::size_t>(k)] *
                         net.row((i * (p[1] + 1) + j) * (p[2] + 1) + k).cast<Real>();
            const Point got =
                vol.rational ? Point((sum.head(3) / sum(3)).cast<double>()) : Point(sum.cast<double>());
            // The dyadic parameters, the cell's end exactly where the fraction is 1.
            double at[3];
            for (std::size_t d = 0; d < 3; ++d)
              at[d] = std::clamp(corner[d] + frac[d] * size[d], lo[d], hi[d]);
            // The parameters are rounded (corner + fraction·size): within ε·|t| each, so the volume is known
            // there to ε·|t|·|∂V/∂t| per direction besides its own rounding.
            const Points D1 = derivatives(vol, at[0], at[1], at[2], 1);
            const double moved = 4 * kEps *
                                 (std::abs(at[0]) * D1.row(4).norm() + std::abs(at[1]) * D1.row(2).norm() +
                                  std::abs(at[2]) * D1.row(1).norm());
            CHECK(diff(got, evaluate(vol, at[0], at[1], at[2])) <= 1e-12 * scale + moved);
          }
    }
  }
}

TEST_CASE("volume automaton: uniform tricubic volumes have one state; nets are the cells' control points",
          "[nurbs][volume][tensor]") {
  Knots u;
  for (int i = 0; i < 10; ++i) u.push_back(i);  // 6 points, degree 3, 3 segments
  const Knots v{0, 1, 2, 3, 4, 5, 6, 7, 8};     // 5 points, degree 3, 2 segments
  const Volume vol = make_volume({3, 3, 3}, {u, v, u}, {6, 5, 6}, Points::Random(180, 3));
  const VolumeAutomaton t = tensor_automaton(vol);
  CHECK(num_vertices(t.product.graph) == 1);
  CHECK(t.product.initial.size() == 3 * 2 * 3);
  CHECK(t.product.graph[0].recurrent);
  CHECK(t.product.graph[0].size == 64);
  const std::vector<Points> nets = initial_nets(t, vol);
  for (std::size_t k = 0; k < nets.size(); ++k)
    for (int i = 0; i <= 3; ++i)
      for (int j = 0; j <= 3; ++j)
        for (int l = 0; l <= 3; ++l)
          CHECK(nets[k].row((i * 4 + j) * 4 + l) ==
                vol.P.row(((t.cells[k][0] + i) * 5 + t.cells[k][1] + j) * 6 + t.cells[k][2] + l));
  // A volume of other degrees does not fit.
  const Volume other =
      make_volume({2, 3, 3}, {Knots(u.begin(), u.end() - 1), v, u}, {6, 5, 6}, Points::Random(180, 3));
  CHECK_THROWS_WITH(initial_nets(t, other),
                    Catch::Matchers::Contains("the volume's degrees (2, 3, 3) give 48"));
}
