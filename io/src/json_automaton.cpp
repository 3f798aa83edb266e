// SPDX-License-Identifier: MIT
// cifs — automata as JSON (docs/cli.md, `cifs automaton --format json`), written and read back.
#include "cifs/errors.hpp"
#include "cifs/io/json.hpp"
#include "json_common.hpp"

namespace cifs::io {
namespace {

using automata::StateId;
using detail::json;
using detail::Reader;

std::string default_name(StateId s) {
  return "s" + std::to_string(s);
}

}  // namespace

std::string to_json(const nurbs::KnotAutomaton& k) {
  const automata::Automaton& a = k.automaton;
  json states = json::array(), transitions = json::array(), initial = json::array();
  for (StateId s = 0; s < num_vertices(a.graph); ++s) {
    const automata::State& st = a.graph[s];
    json j{{"id", s}, {"size", st.size}, {"recurrent", st.recurrent}};
    if (s < k.windows.size() && !k.windows[s].empty()) j["window"] = k.windows[s];
    if (st.name != default_name(s)) j["name"] = st.name;
    states.push_back(std::move(j));
  }
  // edges() visits the states in order and each state's out-edges in order.
  for (const automata::TransitionId e : edges(a.graph)) {
    const Eigen::MatrixXd& M = a.graph[e].matrix;
    json rows = json::array();
    for (Eigen::Index r = 0; r < M.rows(); ++r) {
      std::vector<double> row(static_cast<std::size_t>(M.cols()));
      for (Eigen::Index c = 0; c < M.cols(); ++c) row[static_cast<std::size_t>(c)] = M(r, c);
      rows.push_back(std::move(row));
    }
    transitions.push_back({{"from", source(e, a.graph)},
                           {"to", target(e, a.graph)},
                           {"label", a.graph[e].label},
                           {"matrix", rows}});
  }
  for (std::size_t n = 0; n < a.initial.size(); ++n) {
    const automata::Initial& i = a.initial[n];
    const nurbs::KnotInterval interval = n < k.intervals.size() ? k.intervals[n] : nurbs::KnotInterval{};
    initial.push_back(
        {{"segment", i.segment}, {"state", i.state}, {"interval", {interval.start, interval.end}}});
  }
  return json{{"states", states}, {"transitions", transitions}, {"initial", initial}}.dump() + "\n";
}

std::string to_json(const automata::Automaton& a) {
  return to_json(nurbs::without_knots(a));
}

nurbs::KnotAutomaton parse_automaton_json(std::string_view text, std::string_view where) {
  const Reader r{std::string(where)};
  const json doc = detail::parse_document(text, r.where);
  if (!doc.is_object())
    throw InvalidInput(r.where + ": expected an object with \"states\", \"transitions\", \"initial\"");
  r.only(doc, "", {"states", "transitions", "initial"});
  nurbs::KnotAutomaton k;
  automata::Automaton& a = k.automaton;
  auto& g = a.graph;

  const json& states = r.array(r.member(doc, "", "states"), "states");
  for (std::size_t i = 0; i < states.size(); ++i) {
    const std::string path = "states[" + std::to_string(i) + "]";
    const json& s = r.object(states[i], path);
    r.only(s, path, {"id", "size", "recurrent", "window", "name"});
    if (r.integer(r.member(s, path, "id"), path + ".id") != static_cast<int>(i))
      r.fail(path + ".id", "expected " + std::to_string(i) + " (states are listed by id, from 0)");
    automata::State state;
    state.size = r.integer(r.member(s, path, "size"), path + ".size");
    if (state.size < 1) r.fail(path + ".size", std::to_string(state.size) + " points, expected at least 1");
    if (s.contains("recurrent")) state.recurrent = r.boolean(s["recurrent"], path + ".recurrent");
    k.windows.push_back(s.contains("window") ? r.numbers(s["window"], path + ".window") : nurbs::Window{});
    state.name = s.contains("name") ? r.string(s["name"], path + ".name") : default_name(i);
    add_vertex(state, g);
  }
  const auto state_id = [&](const json& v, const std::string& path) {
    const int id = r.integer(v, path);
    if (id < 0 || static_cast<std::size_t>(id) >= states.size())
      r.fail(path, "state " + std::to_string(id) + " does not exist (" + std::to_string(states.size()) +
                       " states)");
    return static_cast<StateId>(id);
  };

  const json& transitions = r.array(r.member(doc, "", "transitions"), "transitions");
  for (std::size_t i = 0; i < transitions.size(); ++i) {
    const std::string path = "transitions[" + std::to_string(i) + "]";
    const json& t = r.object(transitions[i], path);
    r.only(t, path, {"from", "to", "label", "matrix"});
    const StateId from = state_id(r.member(t, path, "from"), path + ".from");
    const StateId to = state_id(r.member(t, path, "to"), path + ".to");
    automata::Transition transition;
    transition.label = r.string(r.member(t, path, "label"), path + ".label");
    transition.matrix =
        r.matrix(r.member(t, path, "matrix"), path + ".matrix", g[to].size, g[from].size,
                 "size of state " + std::to_string(to), "size of state " + std::to_string(from));
    add_edge(from, to, transition, g);
  }

  const json& initial = r.array(r.member(doc, "", "initial"), "initial");
  for (std::size_t i = 0; i < initial.size(); ++i) {
    const std::string path = "initial[" + std::to_string(i) + "]";
    const json& o = r.object(initial[i], path);
    r.only(o, path, {"segment", "state", "interval"});
    automata::Initial entry;
    entry.segment = r.integer(r.member(o, path, "segment"), path + ".segment");
    entry.state = state_id(r.member(o, path, "state"), path + ".state");
    nurbs::KnotInterval knots;
    if (o.contains("interval")) {
      const std::vector<double> interval = r.numbers(o["interval"], path + ".interval");
      if (interval.size() != 2) r.fail(path + ".interval", "expected [start, end]");
      knots.start = interval[0];
      knots.end = interval[1];
    }
    a.initial.push_back(entry);
    k.intervals.push_back(knots);
  }
  return k;
}

}  // namespace cifs::io
