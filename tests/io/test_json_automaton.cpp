// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>

#include "cifs/automata/automaton.hpp"
#include "cifs/errors.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/io/json.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"

using namespace cifs;
using namespace cifs::io;
using automata::StateId;
using Catch::Matchers::Contains;

namespace {

bool same_matrix_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

/// Everything the JSON holds, compared exactly: states, out-edges in order, initial entries.
void require_same_automaton(const nurbs::KnotAutomaton& ka, const nurbs::KnotAutomaton& kb) {
  const automata::Automaton &a = ka.automaton, &b = kb.automaton;
  const auto n = num_vertices(a.graph);
  REQUIRE(ka.windows.size() == n);
  REQUIRE(kb.windows.size() == n);
  REQUIRE(num_vertices(b.graph) == n);
  for (StateId s = 0; s < n; ++s) {
    INFO("state " << s);
    const automata::State &x = a.graph[s], &y = b.graph[s];
    CHECK(x.size == y.size);
    CHECK(x.name == y.name);
    CHECK(ka.windows[s] == kb.windows[s]);
    CHECK(x.recurrent == y.recurrent);
    REQUIRE(out_degree(s, a.graph) == out_degree(s, b.graph));
    auto [e, end] = out_edges(s, a.graph);
    auto f = out_edges(s, b.graph).first;
    for (; e != end; ++e, ++f) {
      CHECK(target(*e, a.graph) == target(*f, b.graph));
      CHECK(a.graph[*e].label == b.graph[*f].label);
      CHECK(same_matrix_bits(a.graph[*e].matrix, b.graph[*f].matrix));
    }
  }
  REQUIRE(a.initial.size() == b.initial.size());
  REQUIRE(ka.intervals.size() == a.initial.size());
  REQUIRE(kb.intervals.size() == b.initial.size());
  for (std::size_t i = 0; i < a.initial.size(); ++i) {
    CHECK(a.initial[i].segment == b.initial[i].segment);
    CHECK(a.initial[i].state == b.initial[i].state);
    CHECK(ka.intervals[i].start == kb.intervals[i].start);
    CHECK(ka.intervals[i].end == kb.intervals[i].end);
    CHECK(kb.intervals[i].span == -1);  // not stored
  }
}

/// States named "" and "E" (and one with the default name), a self-loop, parallel transitions,
/// irrational entries, no windows.
nurbs::KnotAutomaton hand_made() {
  automata::Automaton a;
  add_vertex(automata::State{.size = 2, .recurrent = true, .name = ""}, a.graph);
  add_vertex(automata::State{.size = 3, .recurrent = false, .name = "E"}, a.graph);
  add_vertex(automata::State{.size = 1, .recurrent = true, .name = "s2"}, a.graph);
  Eigen::MatrixXd M(3, 2);
  M << 1, 0, 1 / 3.0, 2 / 3.0, std::sqrt(0.5), 1 - std::sqrt(0.5);
  add_edge(0, 1, automata::Transition{"w0", M}, a.graph);
  add_edge(0, 1, automata::Transition{"w1", M.colwise().reverse()}, a.graph);
  add_edge(1, 2, automata::Transition{"", Eigen::MatrixXd::Constant(1, 3, 1 / 3.0)}, a.graph);
  add_edge(2, 2, automata::Transition{"loop", Eigen::MatrixXd::Ones(1, 1)}, a.graph);
  add_edge(1, 0, automata::Transition{"back", M.transpose().topRows(2) / 1.5}, a.graph);
  a.initial = {{.segment = 0, .state = 1}, {.segment = 3, .state = 0}};
  nurbs::KnotAutomaton k = nurbs::without_knots(a);
  k.intervals[0] = {.start = -0.5, .end = 1e-300, .span = 7};
  return k;
}

std::string automaton_error_of(const std::string& text) {
  try {
    parse_automaton_json(text, "a.json");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("Automaton JSON: counts, intervals, stochastic rows", "[io][json]") {
  const nurbs::Curve c = nurbs::make_curve(2, {0, 0, 0, 1, 3, 4, 4, 4}, Points::Random(5, 2));
  const nurbs::KnotAutomaton k = nurbs::knot_automaton(c);
  const automata::Automaton& a = k.automaton;
  const auto j = nlohmann::json::parse(to_json(k));
  CHECK(j["states"].size() == num_vertices(a.graph));
  CHECK(j["transitions"].size() == 2 * num_vertices(a.graph));
  CHECK(j["initial"].size() == 3);
  CHECK(j["initial"][1]["interval"] == nlohmann::json::array({1.0, 3.0}));
  for (const auto& t : j["transitions"]) {
    CHECK(t["matrix"].size() == 3);
    for (const auto& row : t["matrix"]) {
      double sum = 0;
      for (const auto& x : row) sum += x.get<double>();
      CHECK(sum == Approx(1).epsilon(1e-15));
    }
  }
}

TEST_CASE("Automaton JSON reads back exactly (knot, minimised, tensor, BC-IFS, hand-made)", "[io][json]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> len(0.25, 2.0);
  nurbs::Knots t(14, 0.0);
  for (std::size_t i = 4; i < 10; ++i) t[i] = t[i - 1] + len(rng);
  for (std::size_t i = 10; i < 14; ++i) t[i] = t[9] + 1;
  const nurbs::Curve curve = nurbs::make_curve(3, t, Points::Random(10, 2));
  const nurbs::KnotAutomaton knot = nurbs::knot_automaton(curve);
  const nurbs::Surface surface = nurbs::make_surface(
      {2, 1}, {nurbs::Knots{0, 0, 0, 1, 3, 3, 3}, nurbs::Knots{0, 0, 2, 2}}, {4, 2}, Points::Random(8, 3));
  const std::vector<std::pair<const char*, nurbs::KnotAutomaton>> cases = {
      {"knot", knot},
      {"minimised", nurbs::minimize(knot)},
      {"tensor product", nurbs::without_knots(nurbs::tensor_automaton(surface).product)},
      {"BC-IFS", ifs::curve_bcifs_knots(ifs::curve_bcifs(curve).automaton, knot)},
      {"hand-made", hand_made()}};
  for (const auto& [what, a] : cases) {
    INFO(what);
    const std::string text = to_json(a);
    const nurbs::KnotAutomaton back = parse_automaton_json(text, what);
    require_same_automaton(a, back);
    CHECK(to_json(back) == text);
  }
}

TEST_CASE("Automaton JSON: names only when not the default, read from text written by hand", "[io][json]") {
  const std::string text = to_json(hand_made());
  CHECK_THAT(text, Contains(R"({"id":0,"name":"","recurrent":true,"size":2})"));
  CHECK_THAT(text, Contains(R"({"id":1,"name":"E","recurrent":false,"size":3})"));
  CHECK_THAT(text, Contains(R"({"id":2,"recurrent":true,"size":1})"));  // "s2" is the default
  const nurbs::KnotAutomaton k = parse_automaton_json(R"({
      "states": [{"id": 0, "size": 2, "window": [0.5, 1, 2]}, {"id": 1, "size": 1, "name": "V", "recurrent": true}],
      "transitions": [{"from": 0, "to": 1, "label": "x", "matrix": [[0.25, 0.75]]},
                      {"from": 1, "to": 1, "label": "y", "matrix": [[1]]},
                      {"from": 0, "to": 0, "label": "z", "matrix": [[1, 0], [0.5, 0.5]]}],
      "initial": [{"segment": 4, "state": 0, "interval": [1, 2.5]}, {"segment": 5, "state": 1}]})",
                                                      "hand");
  const automata::Automaton& a = k.automaton;
  REQUIRE(num_vertices(a.graph) == 2);
  CHECK(a.graph[0].name == "s0");
  REQUIRE(k.windows.size() == 2);
  CHECK(k.windows[0] == std::vector<double>{0.5, 1, 2});
  CHECK(k.windows[1].empty());
  CHECK(!a.graph[0].recurrent);
  CHECK(a.graph[1].name == "V");
  CHECK(a.graph[1].recurrent);
  // Out-edges of state 0 in file order: x then z.
  std::vector<std::string> labels;
  for (auto [e, end] = out_edges(0, a.graph); e != end; ++e) labels.push_back(a.graph[*e].label);
  CHECK(labels == std::vector<std::string>{"x", "z"});
  Eigen::MatrixXd z(2, 2);
  z << 1, 0, 0.5, 0.5;
  CHECK(a.graph[edge(0, 0, a.graph).first].matrix == z);
  REQUIRE(a.initial.size() == 2);
  CHECK(a.initial[0].segment == 4);
  REQUIRE(k.intervals.size() == 2);
  CHECK(k.intervals[0].start == 1);
  CHECK(k.intervals[0].end == 2.5);
  CHECK(a.initial[1].state == 1);
  CHECK(k.intervals[1].start == 0);
}

TEST_CASE("Automaton JSON: bad input names the JSON path", "[io][json]") {
  const std::string states = R"("states": [{"id": 0, "size": 2}, {"id": 1, "size": 1}])";
  const auto doc = [&](const std::string& transitions, const std::string& initial = "[]") {
    return "{" + states + R"(, "transitions": )" + transitions + R"(, "initial": )" + initial + "}";
  };
  CHECK(automaton_error_of(doc(R"([{"from": 0, "to": 1, "label": "a", "matrix": [[0.5, 0.5]]}])")) ==
        "(no error)");
  CHECK(automaton_error_of(doc(R"([{"from": 0, "to": 1, "label": "a", "matrix": [[0.5, 0.5], [1, 0]]}])")) ==
        "a.json: transitions[0].matrix: 2 rows, expected 1 (size of state 1)");
  CHECK(automaton_error_of(doc(R"([{"from": 0, "to": 1, "label": "a", "matrix": [[0.5]]}])")) ==
        "a.json: transitions[0].matrix[0]: 1 entries, expected 2 (size of state 0)");
  CHECK(automaton_error_of(doc(R"([{"from": 0, "to": 2, "label": "a", "matrix": [[1]]}])")) ==
        "a.json: transitions[0].to: state 2 does not exist (2 states)");
  CHECK(
      automaton_error_of(doc(R"([{"from": 0, "to": 1, "label": "a", "matrix": [[1, 0]], "free": true}])")) ==
      "a.json: transitions[0].free: unknown member");
  CHECK(automaton_error_of(doc("[]", R"([{"segment": 0, "state": 5}])")) ==
        "a.json: initial[0].state: state 5 does not exist (2 states)");
  CHECK(automaton_error_of(doc("[]", R"([{"segment": 0, "state": 0, "interval": [1]}])")) ==
        "a.json: initial[0].interval: expected [start, end]");
  CHECK(automaton_error_of(R"({"states": [{"id": 1, "size": 2}], "transitions": [], "initial": []})") ==
        "a.json: states[0].id: expected 0 (states are listed by id, from 0)");
  CHECK(automaton_error_of(R"({"states": [{"id": 0, "size": 0}], "transitions": [], "initial": []})") ==
        "a.json: states[0].size: 0 points, expected at least 1");
  CHECK(automaton_error_of(R"({"transitions": [], "initial": []})") == "a.json: missing \"states\"");
  CHECK_THROWS_AS(parse_automaton_json("{\"states\": [", "a.json"), IoError);
}
