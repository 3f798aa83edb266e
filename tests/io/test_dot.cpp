// SPDX-License-Identifier: MIT
#include "cifs/io/dot.hpp"

#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "cifs/nurbs/curve.hpp"

using namespace cifs;
using namespace cifs::io;

namespace {

std::size_t count_in_dot(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("Automaton DOT", "[io][dot]") {
  const nurbs::Curve c = nurbs::make_curve(2, {0, 0, 0, 1, 3, 4, 4, 4}, Points::Random(5, 2));
  const nurbs::KnotAutomaton ka = nurbs::knot_automaton(c);
  const automata::Automaton& a = ka.automaton;
  const std::string dot = to_dot(ka);
  CHECK_THAT(dot, Catch::StartsWith("digraph G {") && Catch::Contains("[label=\"G\"]") &&
                      Catch::Contains("peripheries=2"));
  // One line per transition, one bold node per initial state, a window in every label.
  CHECK(count_in_dot(dot, "->") == num_edges(a.graph));
  std::set<automata::StateId> initial;
  for (const automata::Initial& i : a.initial) initial.insert(i.state);
  CHECK(count_in_dot(dot, "style=bold") == initial.size());
  CHECK(count_in_dot(dot, "\\n(") == num_vertices(a.graph));
  CHECK_THAT(dot, Catch::Contains("rankdir=LR;"));
}

TEST_CASE("Automaton DOT: labels escaped, non-finite windows refused", "[io][dot]") {
  // Found by fuzz_writers: labels (any text in an automaton file) were written between quotes as
  // they are, so a quote or a newline in one broke the DOT file.
  nurbs::KnotAutomaton k;
  add_vertex(k.automaton.graph);
  add_edge(0, 0, {"a\"b\\c\nd", Eigen::MatrixXd()}, k.automaton.graph);
  CHECK_THAT(to_dot(k), Catch::Contains("0->0 [label=\"a\\\"b\\\\c\\nd\"];\n"));
  // A state's name beside its id (a surface automaton's "B3"), escaped like the labels; "s<id>" not twice.
  k.automaton.graph[0].name = "B\"3";
  CHECK_THAT(to_dot(k), Catch::Contains("0[label=\"s0\\nB\\\"3\"];\n"));
  k.automaton.graph[0].name = "s0";
  CHECK_THAT(to_dot(k), Catch::Contains("0[label=\"s0\"];\n"));
  k.windows = {{1, INFINITY, 1}};
  CHECK_THROWS_WITH(to_dot(k), Catch::Contains("state 0") && Catch::Contains("not a finite number"));
}
