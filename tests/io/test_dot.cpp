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
