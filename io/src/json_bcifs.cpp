// SPDX-License-Identifier: MIT
// cifs — BC-IFS files as JSON (docs/formats.md, "bcifs"), read and written.
#include <map>
#include <set>

#include "cifs/io/json.hpp"
#include "json_common.hpp"

namespace cifs::io {
namespace {

using automata::StateId;
using detail::json;
using detail::Reader;

std::string text(const Reader& r, const json& v, const std::string& path) {
  if (!v.is_string()) r.fail(path, "expected a string, got " + std::string(v.type_name()));
  return v.get<std::string>();
}

const json& object(const Reader& r, const json& v, const std::string& path) {
  if (!v.is_object()) r.fail(path, "expected an object, got " + std::string(v.type_name()));
  return v;
}

std::string cell_name(const automata::Automaton& a, StateId s) {
  return a.graph[s].name.empty() ? "s" + std::to_string(s) : a.graph[s].name;
}

}  // namespace

BcifsFile parse_bcifs_json(std::string_view source, std::string_view where) {
  const Reader r{std::string(where)};
  const json doc = detail::parse_document(source, r.where);
  if (!doc.is_object() || doc.size() != 1 || !doc.contains("bcifs"))
    throw InvalidInput(r.where + ": expected an object with one member, \"bcifs\"");
  const json& b = object(r, doc["bcifs"], "bcifs");
  BcifsFile out;
  ifs::Bcifs& sys = out.system;
  auto& g = sys.automaton.graph;

  std::map<std::string, StateId> cells;
  const json& cj = r.array(r.member(b, "bcifs", "cells"), "bcifs.cells");
  if (cj.empty()) r.fail("bcifs.cells", "no cell");
  for (std::size_t i = 0; i < cj.size(); ++i) {
    const std::string path = "bcifs.cells[" + std::to_string(i) + "]";
    const json& c = object(r, cj[i], path);
    const std::string name = text(r, r.member(c, path, "name"), path + ".name");
    if (name.empty() || name.find_first_of("./") != std::string::npos)
      r.fail(path + ".name", "\"" + name + "\": a cell name is non-empty and has no '.' or '/'");
    if (cells.count(name)) r.fail(path + ".name", "\"" + name + "\" names two cells");
    const int size = r.integer(r.member(c, path, "size"), path + ".size");
    if (size < 1) r.fail(path + ".size", "a cell holds at least one point");
    const int dim = r.integer(r.member(c, path, "dimension"), path + ".dimension");
    if (dim < 0 || dim > 2) r.fail(path + ".dimension", "expected 0 (vertex), 1 (edge) or 2 (face)");
    const StateId s = boost::add_vertex(g);
    g[s].size = size;
    g[s].name = name;
    sys.dimension.push_back(dim);
    cells[name] = s;
  }
  const auto cell = [&](const json& v, const std::string& path) {
    const std::string name = text(r, v, path);
    const auto it = cells.find(name);
    if (it == cells.end()) r.fail(path, "no cell is named \"" + name + "\"");
    return it->second;
  };

  const json& tj = r.array(r.member(b, "bcifs", "transitions"), "bcifs.transitions");
  for (std::size_t i = 0; i < tj.size(); ++i) {
    const std::string path = "bcifs.transitions[" + std::to_string(i) + "]";
    const json& t = object(r, tj[i], path);
    const StateId from = cell(r.member(t, path, "from"), path + ".from"),
                  to = cell(r.member(t, path, "to"), path + ".to");
    const std::string label = text(r, r.member(t, path, "label"), path + ".label");
    if (label.empty()) r.fail(path + ".label", "empty label (labels name the transitions)");
    for (auto [e, end] = boost::out_edges(from, g); e != end; ++e)
      if (g[*e].label == label)
        r.fail(path + ".label", "cell " + g[from].name + " has two transitions \"" + label + "\"");
    const std::string shape = "size of " + g[to].name + " by size of " + g[from].name;
    Eigen::MatrixXd M =
        r.matrix(r.member(t, path, "matrix"), path + ".matrix", g[to].size, g[from].size, shape, shape);
    bool free = false;
    if (t.contains("free")) {
      if (!t["free"].is_boolean()) r.fail(path + ".free", "expected true or false");
      free = t["free"].get<bool>();
    }
    const int child = static_cast<int>(boost::out_degree(from, g));
    boost::add_edge(from, to, automata::Transition{label, std::move(M)}, g);
    if (free) sys.free.push_back(ifs::TransitionRef{from, child});
  }

  const json& bj = r.array(r.member(b, "bcifs", "boundaries"), "bcifs.boundaries");
  for (std::size_t i = 0; i < bj.size(); ++i) {
    const std::string path = "bcifs.boundaries[" + std::to_string(i) + "]";
    const json& o = object(r, bj[i], path);
    ifs::BoundaryOperator op;
    op.cell = cell(r.member(o, path, "cell"), path + ".cell");
    op.name = text(r, r.member(o, path, "name"), path + ".name");
    if (op.name.empty() || op.name.find_first_of("./") != std::string::npos)
      r.fail(path + ".name", "\"" + op.name + "\": a boundary name is non-empty and has no '.' or '/'");
    op.boundary = cell(r.member(o, path, "boundary"), path + ".boundary");
    const json& rows = r.array(r.member(o, path, "rows"), path + ".rows");
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::string p = path + ".rows[" + std::to_string(k) + "]";
      op.rows.push_back(r.integer(rows[k], p));
      if (op.rows.back() < 0 || op.rows.back() >= g[op.cell].size)
        r.fail(p, "row " + std::to_string(op.rows.back()) + " is outside cell " + g[op.cell].name + " (" +
                      std::to_string(g[op.cell].size) + " rows)");
    }
    for (const auto& other : sys.boundaries)
      if (other.cell == op.cell && other.name == op.name)
        r.fail(path + ".name", "cell " + g[op.cell].name + " has two boundaries \"" + op.name + "\"");
    sys.boundaries.push_back(std::move(op));
  }

  const auto factor = [&](const json& v, const std::string& path) {
    const std::string f = text(r, v, path);
    const auto slash = f.find('/'), dot = f.find('.');
    const auto split = slash != std::string::npos ? slash : dot;
    if (split == std::string::npos)
      r.fail(path,
             "\"" + f + "\": expected \"cell/label\" (a transition) or \"cell.name\" (a boundary operator)");
    const auto it = cells.find(f.substr(0, split));
    if (it == cells.end()) r.fail(path, "\"" + f + "\": no cell is named \"" + f.substr(0, split) + "\"");
    const std::string rest = f.substr(split + 1);
    if (slash != std::string::npos) {
      int child = 0;
      for (auto [e, end] = boost::out_edges(it->second, g); e != end; ++e, ++child)
        if (g[*e].label == rest) return ifs::Factor{ifs::Factor::Kind::transition, 0, {it->second, child}};
      r.fail(path, "\"" + f + "\": cell " + it->first + " has no transition \"" + rest + "\"");
    }
    for (std::size_t k = 0; k < sys.boundaries.size(); ++k)
      if (sys.boundaries[k].cell == it->second && sys.boundaries[k].name == rest)
        return ifs::Factor{ifs::Factor::Kind::boundary, static_cast<int>(k), {}};
    r.fail(path, "\"" + f + "\": cell " + it->first + " has no boundary \"" + rest + "\"");
  };
  const json& kj = r.array(r.member(b, "bcifs", "constraints"), "bcifs.constraints");
  for (std::size_t i = 0; i < kj.size(); ++i) {
    const std::string path = "bcifs.constraints[" + std::to_string(i) + "]";
    const json& o = object(r, kj[i], path);
    ifs::Constraint c;
    c.name = text(r, r.member(o, path, "name"), path + ".name");
    for (const char* side : {"left", "right"}) {
      const std::string p = path + "." + side;
      const json& list = r.array(r.member(o, path, side), p);
      if (list.empty()) r.fail(p, "empty product");
      for (std::size_t k = 0; k < list.size(); ++k)
        (side[0] == 'l' ? c.left : c.right).push_back(factor(list[k], p + "[" + std::to_string(k) + "]"));
    }
    sys.constraints.push_back(std::move(c));
  }

  const json& ij = r.array(r.member(b, "bcifs", "initial"), "bcifs.initial");
  for (std::size_t i = 0; i < ij.size(); ++i) {
    const std::string path = "bcifs.initial[" + std::to_string(i) + "]";
    const json& o = object(r, ij[i], path);
    automata::Initial init;
    init.segment = static_cast<int>(i);
    init.state = cell(r.member(o, path, "state"), path + ".state");
    sys.automaton.initial.push_back(init);
    if (o.contains("net") != (i == 0 ? o.contains("net") : !out.nets.empty()))
      r.fail(path, "give a net for every initial entry or for none");
    if (o.contains("net")) {
      out.nets.push_back(r.matrix(o["net"], path + ".net", g[init.state].size,
                                  out.nets.empty() ? -1 : out.nets.front().cols(),
                                  "size of " + g[init.state].name, "as many coordinates as the first net"));
    }
  }
  try {
    ifs::validate(sys);
  } catch (const InvalidInput& e) {
    throw InvalidInput(r.where + ": " + e.what());
  }
  return out;
}

std::string to_json(const ifs::Bcifs& sys, std::span<const Points> nets) {
  ifs::validate(sys);
  const auto& a = sys.automaton;
  const auto& g = a.graph;
  if (!nets.empty() && nets.size() != a.initial.size())
    throw InvalidInput("to_json: " + std::to_string(nets.size()) + " nets for " +
                       std::to_string(a.initial.size()) + " initial entries");
  const std::set<ifs::TransitionRef> free(sys.free.begin(), sys.free.end());
  json cells = json::array(), transitions = json::array(), boundaries = json::array(),
       constraints = json::array(), initial = json::array();
  for (StateId s = 0; s < boost::num_vertices(g); ++s) {
    const std::string name = cell_name(a, s);
    if (name.find_first_of("./") != std::string::npos)
      throw InvalidInput("to_json: cell name \"" + name + "\" has a '.' or '/'");
    cells.push_back({{"name", name}, {"size", g[s].size}, {"dimension", sys.dimension[s]}});
    int child = 0;
    for (auto [e, end] = boost::out_edges(s, g); e != end; ++e, ++child)
      transitions.push_back({{"from", name},
                             {"to", cell_name(a, boost::target(*e, g))},
                             {"label", g[*e].label},
                             {"free", free.count(ifs::TransitionRef{s, child}) > 0},
                             {"matrix", detail::rows_json(g[*e].matrix)}});
  }
  for (const auto& op : sys.boundaries)
    boundaries.push_back({{"cell", cell_name(a, op.cell)},
                          {"name", op.name},
                          {"boundary", cell_name(a, op.boundary)},
                          {"rows", op.rows}});
  const auto factor_text = [&](const ifs::Factor& f) {
    if (f.kind == ifs::Factor::Kind::transition) return ifs::transition_name(a, f.transition);
    const auto& op = sys.boundaries[static_cast<std::size_t>(f.boundary)];
    return cell_name(a, op.cell) + "." + op.name;
  };
  for (const auto& c : sys.constraints) {
    json left = json::array(), right = json::array();
    for (const auto& f : c.left) left.push_back(factor_text(f));
    for (const auto& f : c.right) right.push_back(factor_text(f));
    constraints.push_back({{"name", c.name}, {"left", left}, {"right", right}});
  }
  for (std::size_t i = 0; i < a.initial.size(); ++i) {
    json entry{{"state", cell_name(a, a.initial[i].state)}};
    if (!nets.empty()) entry["net"] = detail::rows_json(nets[i]);
    initial.push_back(std::move(entry));
  }
  const json doc{{"bcifs",
                  {{"cells", cells},
                   {"transitions", transitions},
                   {"boundaries", boundaries},
                   {"constraints", constraints},
                   {"initial", initial}}}};
  std::string out;
  detail::write_pretty(doc, 0, out);
  return out + "\n";
}

}  // namespace cifs::io
