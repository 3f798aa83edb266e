// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "cifs/automata/automaton.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/doubling.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/refine.hpp"

using namespace cifs;
using automata::StateId;

namespace {

nurbs::Knots automaton_random_knots(std::mt19937_64& rng, std::size_t count) {
  std::uniform_real_distribution<double> len(0.5, 2.0);
  nurbs::Knots t(count);
  for (std::size_t i = 1; i < count; ++i) t[i] = t[i - 1] + len(rng);
  return t;
}

std::set<StateId> reachable(const automata::Automaton& a, StateId from) {
  std::set<StateId> seen{from};
  std::vector<StateId> stack{from};
  while (!stack.empty()) {
    const StateId s = stack.back();
    stack.pop_back();
    for (auto [e, end] = out_edges(s, a.graph); e != end; ++e)
      if (seen.insert(target(*e, a.graph)).second) stack.push_back(target(*e, a.graph));
  }
  return seen;
}

StateId uniform_state(const nurbs::KnotAutomaton& k, int d) {
  for (StateId s = 0; s < num_vertices(k.automaton.graph); ++s)
    if (k.windows[s] == std::vector<double>(static_cast<std::size_t>(2 * d - 1), 1.0)) return s;
  return num_vertices(k.automaton.graph);
}

}  // namespace

TEST_CASE("Generic knots: 4(d-1) states per segment, 2d-1 recur, one shared uniform state", "[automata]") {
  std::mt19937_64 rng(99);
  for (int d = 2; d <= 8; ++d) {
    const int n = 4 * d;
    const nurbs::Curve c = nurbs::make_curve(
        d, automaton_random_knots(rng, static_cast<std::size_t>(n + d + 1)), Points::Random(n, 2));
    const nurbs::KnotAutomaton k = nurbs::knot_automaton(c);
    const automata::Automaton& a = k.automaton;
    REQUIRE(k.windows.size() == num_vertices(a.graph));
    CHECK(static_cast<int>(a.initial.size()) == n - d);
    const StateId uniform = uniform_state(k, d);
    REQUIRE(uniform < num_vertices(a.graph));
    for (const automata::Initial& init : a.initial) {
      const std::set<StateId> states = reachable(a, init.state);
      INFO("degree " << d << ", segment " << init.segment);
      CHECK(static_cast<int>(states.size()) == 4 * (d - 1));
      CHECK(std::count_if(states.begin(), states.end(), [&](StateId s) { return a.graph[s].recurrent; }) ==
            2 * d - 1);
      CHECK(states.count(uniform) == 1);
      CHECK(!a.graph[init.state].recurrent);
    }
    // Every state has exactly the two children G, D with the matrices of its window.
    for (StateId s = 0; s < num_vertices(a.graph); ++s) {
      REQUIRE(out_degree(s, a.graph) == 2);
      int half = 0;
      for (auto [e, end] = out_edges(s, a.graph); e != end; ++e, ++half) {
        CHECK(a.graph[*e].label == (half == 0 ? "G" : "D"));
        CHECK(a.graph[*e].matrix ==
              nurbs::subdivision_matrix(k.windows[s], d, static_cast<nurbs::Half>(half)));
        CHECK(k.windows[target(*e, a.graph)] ==
              nurbs::child_window(k.windows[s], d, static_cast<nurbs::Half>(half)));
      }
      CHECK(k.windows[s][static_cast<std::size_t>(d - 1)] == 1.0);
    }
  }
}

TEST_CASE("Uniform, clamped, closed and repeated knots", "[automata]") {
  SECTION("a uniform closed curve is one state") {
    const nurbs::Curve c = nurbs::make_closed_curve(3, {0, 1, 2, 3, 4, 5, 6}, Points::Random(6, 3));
    const automata::Automaton a = nurbs::knot_automaton(c).automaton;
    CHECK(num_vertices(a.graph) == 1);
    CHECK(a.initial.size() == 6);
    CHECK(a.graph[0].recurrent);
  }
  SECTION("a closed curve's windows are the cyclic differences of its breakpoints") {
    // Not differences of the extended knots b_k ± T, which are rounded: 1000.004 + 0.001 has no double.
    const nurbs::Knots b{0, 0.001, 0.002, 1000.002, 1000.003, 1000.004};
    const int m = 5;
    for (int d = 1; d <= 7; ++d) {
      const nurbs::KnotAutomaton k =
          nurbs::knot_automaton(nurbs::make_closed_curve(d, b, Points::Random(m, 2)));
      REQUIRE(static_cast<int>(k.automaton.initial.size()) == m);
      for (int seg = 0; seg < m; ++seg) {
        const auto h = [&](int j) {
          const auto i = static_cast<std::size_t>(((j % m) + m) % m);
          return b[i + 1] - b[i];
        };
        nurbs::Window expected(static_cast<std::size_t>(2 * d - 1));
        for (int i = 0; i < 2 * d - 1; ++i)
          expected[static_cast<std::size_t>(i)] = h(seg - d + 1 + i) / h(seg);
        INFO("degree " << d << ", segment " << seg);
        CHECK(k.windows[k.automaton.initial[static_cast<std::size_t>(seg)].state] == expected);
      }
    }
  }
  SECTION("uniform interior knots share states; scaled knots give the same automaton") {
    const nurbs::Knots t{0, 0, 0, 0, 1, 2, 3, 4, 5, 5, 5, 5};
    nurbs::Knots scaled = t;
    for (double& x : scaled) x = x * 0.125 + 3;  // exact in binary
    const auto ka = nurbs::knot_automaton(nurbs::make_curve(3, t, Points::Random(8, 2)));
    const auto kb = nurbs::knot_automaton(nurbs::make_curve(3, scaled, Points::Random(8, 2)));
    const auto ja = nlohmann::json::parse(io::to_json(ka)), jb = nlohmann::json::parse(io::to_json(kb));
    const automata::Automaton& a = ka.automaton;
    CHECK(ja["states"] == jb["states"]);
    CHECK(ja["transitions"] == jb["transitions"]);
    CHECK(a.initial.size() == 5);
    CHECK(reachable(a, a.initial[2].state).size() == 1);  // the middle segment is uniform already
  }
  SECTION("repeated interior knots: zero intervals stay single zeros") {
    const nurbs::Curve c = nurbs::make_curve(3, {0, 0, 0, 0, 1, 1, 3, 4, 4, 4, 4}, Points::Random(7, 2));
    const nurbs::KnotAutomaton k = nurbs::knot_automaton(c);
    CHECK(k.automaton.initial.size() == 3);
    for (StateId s = 0; s < num_vertices(k.automaton.graph); ++s) {
      const auto& w = k.windows[s];
      for (std::size_t i = 0; i + 2 < w.size(); ++i) CHECK(!(w[i] == 0 && w[i + 1] == 0 && w[i + 2] == 0));
    }
  }
  SECTION("degree 1 is one uniform state") {
    const auto a =
        nurbs::knot_automaton(nurbs::make_curve(1, {0, 0, 0.3, 2, 2}, Points::Random(3, 2))).automaton;
    CHECK(num_vertices(a.graph) == 1);
  }
}

TEST_CASE("Minimisation merges states no net can tell apart", "[automata]") {
  // Two copies of Chaikin's state, each pointing at the other, plus a distinct state.
  const Eigen::MatrixXd G = nurbs::subdivision_matrix(nurbs::Window{1, 1, 1}, 2, nurbs::Half::G);
  const Eigen::MatrixXd D = nurbs::subdivision_matrix(nurbs::Window{1, 1, 1}, 2, nurbs::Half::D);
  const Eigen::MatrixXd G2 = nurbs::subdivision_matrix(nurbs::Window{2, 1, 1}, 2, nurbs::Half::G);
  automata::Automaton a;
  for (int i = 0; i < 3; ++i) add_vertex(automata::State{.size = 3, .recurrent = false, .name = ""}, a.graph);
  add_edge(0, 1, automata::Transition{"G", G}, a.graph);
  add_edge(0, 1, automata::Transition{"D", D}, a.graph);
  add_edge(1, 0, automata::Transition{"G", G}, a.graph);
  add_edge(1, 0, automata::Transition{"D", D}, a.graph);
  add_edge(2, 0, automata::Transition{"G", G2}, a.graph);
  add_edge(2, 1, automata::Transition{"D", D}, a.graph);
  a.initial = {{.segment = 0, .state = 2}, {.segment = 1, .state = 1}};
  automata::mark_recurrent(a);
  const automata::Automaton m = automata::minimize(a);
  CHECK(num_vertices(m.graph) == 2);
  CHECK(m.initial[0].state != m.initial[1].state);  // states 0 and 1 are one class, state 2 another
  CHECK(out_degree(m.initial[1].state, m.graph) == 2);
  for (auto [e, end] = out_edges(m.initial[1].state, m.graph); e != end; ++e)
    CHECK(target(*e, m.graph) == m.initial[1].state);  // the merged class loops on itself
  CHECK(!m.graph[m.initial[0].state].recurrent);
  // Same matrices but different children classes are not merged.
  const automata::Automaton k =
      nurbs::knot_automaton(nurbs::make_curve(2, {0, 0, 0, 1, 3, 4, 4, 4}, Points::Random(5, 2))).automaton;
  CHECK(num_vertices(automata::minimize(k).graph) == num_vertices(k.graph));
}

TEST_CASE("Initial nets are the segments' control points", "[automata]") {
  const nurbs::Curve c = nurbs::make_curve(2, {0, 0, 0, 1, 3, 4, 4, 4}, Points::Random(5, 2));
  const nurbs::KnotAutomaton a = nurbs::knot_automaton(c);
  // The nets of the initial states are the segments' control points.
  const std::vector<Points> nets = nurbs::initial_nets(a, c);
  REQUIRE(nets.size() == 3);
  CHECK(nets[2] == c.P.bottomRows(3));
}

TEST_CASE("Minimisation keeps the knot data beside the automaton", "[automata]") {
  // States 0 and 1 are Chaikin's state twice (one class), 2 another; the windows are told apart.
  const Eigen::MatrixXd G = nurbs::subdivision_matrix(nurbs::Window{1, 1, 1}, 2, nurbs::Half::G);
  const Eigen::MatrixXd D = nurbs::subdivision_matrix(nurbs::Window{1, 1, 1}, 2, nurbs::Half::D);
  automata::Automaton a;
  for (int i = 0; i < 3; ++i) add_vertex(automata::State{.size = 3, .recurrent = false, .name = ""}, a.graph);
  add_edge(2, 1, automata::Transition{"G", G}, a.graph);
  add_edge(2, 1, automata::Transition{"D", G}, a.graph);
  for (StateId s = 0; s < 2; ++s) {
    add_edge(s, 1 - s, automata::Transition{"G", G}, a.graph);
    add_edge(s, 1 - s, automata::Transition{"D", D}, a.graph);
  }
  a.initial = {{.segment = 0, .state = 2}, {.segment = 1, .state = 1}};
  CHECK(automata::minimize_classes(a) == std::vector<std::size_t>{0, 0, 1});
  const nurbs::KnotAutomaton k{
      .automaton = a,
      .windows = {{1, 1, 1}, {2, 1, 2}, {3, 1, 3}},
      .intervals = {{.start = 0, .end = 1, .span = 2}, {.start = 1, .end = 3, .span = 3}}};
  const nurbs::KnotAutomaton m = nurbs::minimize(k);
  REQUIRE(num_vertices(m.automaton.graph) == 2);
  // Class {0, 1} is state 0 with state 0's window; state 2 became state 1.
  CHECK(m.windows == std::vector<nurbs::Window>{{1, 1, 1}, {3, 1, 3}});
  CHECK(m.automaton.initial[0].state == 1);
  CHECK(m.automaton.initial[1].state == 0);
  REQUIRE(m.intervals.size() == 2);
  CHECK(m.intervals[1].start == 1);
  CHECK(m.intervals[1].end == 3);
  CHECK(m.intervals[1].span == 3);
  // A generic automaton has no knot data: empty windows, unset intervals.
  const nurbs::KnotAutomaton plain = nurbs::without_knots(a);
  CHECK(plain.windows == std::vector<nurbs::Window>(3));
  REQUIRE(plain.intervals.size() == 2);
  CHECK(plain.intervals[0].span == -1);
}
