// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <set>
#include <unsupported/Eigen/KroneckerProduct>

#include "cifs/errors.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using automata::StateId;

namespace {

nurbs::Surface random_tensor_surface(cifs_test::Rng& rng, std::array<int, 2> degree, std::array<int, 2> count,
                                     bool clamped, bool rational) {
  std::array<nurbs::Knots, 2> knots;
  for (std::size_t d = 0; d < 2; ++d) knots[d] = cifs_test::random_knots(rng, degree[d], count[d], clamped);
  const Points P = Points::Random(count[0] * count[1], 3);
  Eigen::VectorXd w;
  if (rational) w = (Eigen::VectorXd::Random(count[0] * count[1]).array() * 3).exp().matrix();
  return nurbs::make_surface(degree, knots, {count[0], count[1]}, P, w);
}

}  // namespace

TEST_CASE("Tensor automaton: reachable pairs, sizes, Kronecker matrices in GH GB DH DB order",
          "[automata][tensor]") {
  cifs_test::Rng rng(7);
  for (int trial = 0; trial < 24; ++trial) {
    const std::array<int, 2> degree{cifs_test::uniform_int(rng, 1, 5), cifs_test::uniform_int(rng, 1, 5)};
    const std::array<int, 2> count{degree[0] + cifs_test::uniform_int(rng, 1, 4),
                                   degree[1] + cifs_test::uniform_int(rng, 1, 4)};
    const nurbs::Surface s =
        random_tensor_surface(rng, degree, count, cifs_test::coin(rng), cifs_test::coin(rng));
    const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
    const automata::Graph& g = t.product.graph;
    const automata::Graph& gu = t.factors[0].automaton.graph;
    const automata::Graph& gv = t.factors[1].automaton.graph;
    const auto n = num_vertices(g);
    INFO("trial " << trial << ", degrees " << degree[0] << ", " << degree[1]);
    REQUIRE(t.factor_states.size() == n);
    CHECK(n <= num_vertices(gu) * num_vertices(gv));
    // One state per pair.
    std::set<std::array<StateId, 2>> pairs(t.factor_states.begin(), t.factor_states.end());
    CHECK(pairs.size() == n);
    // Initial entries: every (u segment, v segment) pair in u-major order.
    const std::size_t nu = t.factors[0].automaton.initial.size(), nv = t.factors[1].automaton.initial.size();
    REQUIRE(t.product.initial.size() == nu * nv);
    REQUIRE(t.patches.size() == nu * nv);
    for (std::size_t a = 0; a < nu; ++a)
      for (std::size_t b = 0; b < nv; ++b) {
        const std::size_t k = a * nv + b;
        CHECK(t.patches[k] == std::array<int, 2>{static_cast<int>(a), static_cast<int>(b)});
        CHECK(t.product.initial[k].segment == static_cast<int>(k));
        CHECK(t.factor_states[t.product.initial[k].state] ==
              std::array<StateId, 2>{t.factors[0].automaton.initial[a].state,
                                     t.factors[1].automaton.initial[b].state});
      }
    // Only reachable states.
    std::set<StateId> seen;
    std::vector<StateId> stack;
    for (const auto& init : t.product.initial)
      if (seen.insert(init.state).second) stack.push_back(init.state);
    while (!stack.empty()) {
      const StateId s0 = stack.back();
      stack.pop_back();
      for (auto [e, end] = out_edges(s0, g); e != end; ++e)
        if (seen.insert(target(*e, g)).second) stack.push_back(target(*e, g));
    }
    CHECK(seen.size() == n);
    // Sizes, labels, targets and matrices.
    const char* labels[4] = {"GH", "GB", "DH", "DB"};
    for (StateId s0 = 0; s0 < n; ++s0) {
      const auto [p, q] = t.factor_states[s0];
      CHECK(g[s0].size == gu[p].size * gv[q].size);
      REQUIRE(out_degree(s0, g) == 4);
      int child = 0;
      for (auto [e, end] = out_edges(s0, g); e != end; ++e, ++child) {
        auto eu = out_edges(p, gu).first;
        auto ev = out_edges(q, gv).first;
        std::advance(eu, child / 2);
        std::advance(ev, child % 2);
        CHECK(g[*e].label == labels[child]);
        CHECK(t.factor_states[target(*e, g)] == std::array<StateId, 2>{target(*eu, gu), target(*ev, gv)});
        const Eigen::MatrixXd K = Eigen::kroneckerProduct(gu[*eu].matrix, gv[*ev].matrix);
        REQUIRE(g[*e].matrix.rows() == K.rows());
        REQUIRE(g[*e].matrix.cols() == K.cols());
        CHECK(g[*e].matrix == K);  // exactly
      }
    }
  }
}

TEST_CASE("Tensor automaton: uniform bicubic surfaces share one recurrent uniform state",
          "[automata][tensor]") {
  nurbs::Knots t;
  for (int i = 0; i < 12; ++i) t.push_back(i);  // 8 points, degree 3, 5 segments
  const nurbs::Surface s = nurbs::make_surface({3, 3}, {t, t}, {8, 8}, Points::Random(64, 3));
  const nurbs::TensorAutomaton a = nurbs::tensor_automaton(s);
  // Uniform knots: each factor has one state, so the product has one state reached by all 25 patches.
  CHECK(num_vertices(a.factors[0].automaton.graph) == 1);
  CHECK(num_vertices(a.product.graph) == 1);
  CHECK(a.product.initial.size() == 25);
  CHECK(a.product.graph[0].recurrent);
  CHECK(a.product.graph[0].size == 16);
}

TEST_CASE("Tensor automaton: initial nets are the patches' control points", "[automata][tensor]") {
  cifs_test::Rng rng(11);
  const nurbs::Surface s = random_tensor_surface(rng, {2, 3}, {5, 7}, false, true);
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const std::vector<Points> nets = nurbs::initial_nets(t, s);
  REQUIRE(nets.size() == t.product.initial.size());
  for (std::size_t k = 0; k < nets.size(); ++k) {
    const int su = t.factors[0].intervals[static_cast<std::size_t>(t.patches[k][0])].span;
    const int sv = t.factors[1].intervals[static_cast<std::size_t>(t.patches[k][1])].span;
    REQUIRE(nets[k].rows() == 12);
    for (int i = 0; i <= 2; ++i)
      for (int j = 0; j <= 3; ++j) CHECK(nets[k].row(i * 4 + j) == s.P.row((su - 2 + i) * 7 + (sv - 3 + j)));
  }
  // A surface of other degrees does not fit.
  const nurbs::Surface other = random_tensor_surface(rng, {3, 3}, {5, 7}, false, false);
  CHECK_THROWS_AS(nurbs::initial_nets(t, other), InvalidInput);
}
