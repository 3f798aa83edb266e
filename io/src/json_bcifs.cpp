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

std::string cell_name(const automata::Automaton& a, StateId s) {
  return a.graph[s].name.empty() ? "s" + std::to_string(s) : a.graph[s].name;
}

}  // namespace

namespace {

/// The phases of reading a BC-IFS file, in the order the members depend on each other: cells,
/// transitions between them, boundary operators, constraints over both, initial entries.
class BcifsReader {
 public:
  explicit BcifsReader(const Reader& r) : r_(r) {}

  BcifsFile read(const json& doc) {
    r_.only_beside(doc, {"bcifs"});
    if (!doc.is_object() || doc.size() != 1 || !doc.contains("bcifs"))
      throw InvalidInput(r_.where + ": expected an object with one member, \"bcifs\"");
    const json& b = r_.object(doc["bcifs"], "bcifs");
    r_.only(b, "bcifs", {"cells", "transitions", "boundaries", "constraints", "initial"});
    read_cells(r_.array(r_.member(b, "bcifs", "cells"), "bcifs.cells"));
    read_transitions(r_.array(r_.member(b, "bcifs", "transitions"), "bcifs.transitions"));
    read_boundaries(r_.array(r_.member(b, "bcifs", "boundaries"), "bcifs.boundaries"));
    read_constraints(r_.array(r_.member(b, "bcifs", "constraints"), "bcifs.constraints"));
    read_initial(r_.array(r_.member(b, "bcifs", "initial"), "bcifs.initial"));
    try {
      ifs::validate(sys());
    } catch (const InvalidInput& e) {
      throw InvalidInput(r_.where + ": " + e.what());
    }
    return std::move(out_);
  }

 private:
  ifs::Bcifs& sys() { return out_.system; }
  automata::Graph& graph() { return out_.system.automaton.graph; }

  static std::string item(const char* list, std::size_t i) {
    return std::string("bcifs.") + list + "[" + std::to_string(i) + "]";
  }

  void read_cells(const json& cj) {
    if (cj.empty()) r_.fail("bcifs.cells", "no cell");
    auto& g = graph();
    for (std::size_t i = 0; i < cj.size(); ++i) {
      const std::string path = item("cells", i);
      const json& c = r_.object(cj[i], path);
      r_.only(c, path, {"name", "size", "dimension"});
      const std::string name = r_.string(r_.member(c, path, "name"), path + ".name");
      if (name.empty() || name.find_first_of("./") != std::string::npos)
        r_.fail(path + ".name", "\"" + name + "\": a cell name is non-empty and has no '.' or '/'");
      if (cells_.count(name)) r_.fail(path + ".name", "\"" + name + "\" names two cells");
      const int size = r_.integer(r_.member(c, path, "size"), path + ".size");
      if (size < 1) r_.fail(path + ".size", "a cell holds at least one point");
      const int dim = r_.integer(r_.member(c, path, "dimension"), path + ".dimension");
      if (dim < 0 || dim > 2) r_.fail(path + ".dimension", "expected 0 (vertex), 1 (edge) or 2 (face)");
      const StateId s = add_vertex(g);
      g[s].size = size;
      g[s].name = name;
      sys().dimension.push_back(dim);
      cells_[name] = s;
    }
  }

  StateId cell(const json& v, const std::string& path) const {
    const std::string name = r_.string(v, path);
    const auto it = cells_.find(name);
    if (it == cells_.end()) r_.fail(path, "no cell is named \"" + name + "\"");
    return it->second;
  }

  void read_transitions(const json& tj) {
    auto& g = graph();
    for (std::size_t i = 0; i < tj.size(); ++i) {
      const std::string path = item("transitions", i);
      const json& t = r_.object(tj[i], path);
      r_.only(t, path, {"from", "to", "label", "free", "matrix"});
      const StateId from = cell(r_.member(t, path, "from"), path + ".from"),
                    to = cell(r_.member(t, path, "to"), path + ".to");
      const std::string label = r_.string(r_.member(t, path, "label"), path + ".label");
      if (label.empty()) r_.fail(path + ".label", "empty label (labels name the transitions)");
      for (auto [e, end] = out_edges(from, g); e != end; ++e)
        if (g[*e].label == label)
          r_.fail(path + ".label", "cell " + g[from].name + " has two transitions \"" + label + "\"");
      const std::string shape = "size of " + g[to].name + " by size of " + g[from].name;
      Eigen::MatrixXd M =
          r_.matrix(r_.member(t, path, "matrix"), path + ".matrix", g[to].size, g[from].size, shape, shape);
      const bool free = t.contains("free") && r_.boolean(t["free"], path + ".free");
      const int child = static_cast<int>(out_degree(from, g));
      add_edge(from, to, automata::Transition{label, std::move(M)}, g);
      if (free) sys().free.push_back(ifs::TransitionRef{from, child});
    }
  }

  void read_boundaries(const json& bj) {
    const auto& g = graph();
    for (std::size_t i = 0; i < bj.size(); ++i) {
      const std::string path = item("boundaries", i);
      const json& o = r_.object(bj[i], path);
      r_.only(o, path, {"cell", "name", "boundary", "rows"});
      ifs::BoundaryOperator op;
      op.cell = cell(r_.member(o, path, "cell"), path + ".cell");
      op.name = r_.string(r_.member(o, path, "name"), path + ".name");
      if (op.name.empty() || op.name.find_first_of("./") != std::string::npos)
        r_.fail(path + ".name", "\"" + op.name + "\": a boundary name is non-empty and has no '.' or '/'");
      op.boundary = cell(r_.member(o, path, "boundary"), path + ".boundary");
      const json& rows = r_.array(r_.member(o, path, "rows"), path + ".rows");
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const std::string p = path + ".rows[" + std::to_string(k) + "]";
        op.rows.push_back(r_.integer(rows[k], p));
        if (op.rows.back() < 0 || op.rows.back() >= g[op.cell].size)
          r_.fail(p, "row " + std::to_string(op.rows.back()) + " is outside cell " + g[op.cell].name + " (" +
                         std::to_string(g[op.cell].size) + " rows)");
      }
      for (const auto& other : sys().boundaries)
        if (other.cell == op.cell && other.name == op.name)
          r_.fail(path + ".name", "cell " + g[op.cell].name + " has two boundaries \"" + op.name + "\"");
      sys().boundaries.push_back(std::move(op));
    }
  }

  /// "cell/label" names a transition, "cell.name" a boundary operator.
  ifs::Factor factor(const json& v, const std::string& path) {
    const auto& g = graph();
    const std::string f = r_.string(v, path);
    const auto slash = f.find('/'), dot = f.find('.');
    const auto split = slash != std::string::npos ? slash : dot;
    if (split == std::string::npos)
      r_.fail(path,
              "\"" + f + "\": expected \"cell/label\" (a transition) or \"cell.name\" (a boundary operator)");
    const auto it = cells_.find(f.substr(0, split));
    if (it == cells_.end()) r_.fail(path, "\"" + f + "\": no cell is named \"" + f.substr(0, split) + "\"");
    const std::string rest = f.substr(split + 1);
    if (slash != std::string::npos) {
      int child = 0;
      for (auto [e, end] = out_edges(it->second, g); e != end; ++e, ++child)
        if (g[*e].label == rest) return ifs::Factor{ifs::Factor::Kind::transition, 0, {it->second, child}};
      r_.fail(path, "\"" + f + "\": cell " + it->first + " has no transition \"" + rest + "\"");
    }
    for (std::size_t k = 0; k < sys().boundaries.size(); ++k)
      if (sys().boundaries[k].cell == it->second && sys().boundaries[k].name == rest)
        return ifs::Factor{ifs::Factor::Kind::boundary, static_cast<int>(k), {}};
    r_.fail(path, "\"" + f + "\": cell " + it->first + " has no boundary \"" + rest + "\"");
  }

  void read_constraints(const json& kj) {
    for (std::size_t i = 0; i < kj.size(); ++i) {
      const std::string path = item("constraints", i);
      const json& o = r_.object(kj[i], path);
      r_.only(o, path, {"name", "left", "right"});
      ifs::Constraint c;
      c.name = r_.string(r_.member(o, path, "name"), path + ".name");
      for (const char* side : {"left", "right"}) {
        const std::string p = path + "." + side;
        const json& list = r_.array(r_.member(o, path, side), p);
        if (list.empty()) r_.fail(p, "empty product");
        for (std::size_t k = 0; k < list.size(); ++k)
          (side[0] == 'l' ? c.left : c.right).push_back(factor(list[k], p + "[" + std::to_string(k) + "]"));
      }
      sys().constraints.push_back(std::move(c));
    }
  }

  void read_initial(const json& ij) {
    // Every use of the file (drawing, chaos game, dimension) starts from the initial entries.
    if (ij.empty()) r_.fail("bcifs.initial", "no entry; list at least one cell to start from");
    const auto& g = graph();
    for (std::size_t i = 0; i < ij.size(); ++i) {
      const std::string path = item("initial", i);
      const json& o = r_.object(ij[i], path);
      r_.only(o, path, {"state", "net"});
      automata::Initial init;
      init.segment = static_cast<int>(i);
      init.state = cell(r_.member(o, path, "state"), path + ".state");
      sys().automaton.initial.push_back(init);
      if (o.contains("net") != (i == 0 ? o.contains("net") : !out_.nets.empty()))
        r_.fail(path, "give a net for every initial entry or for none");
      if (o.contains("net")) {
        out_.nets.push_back(r_.matrix(
            o["net"], path + ".net", g[init.state].size, out_.nets.empty() ? -1 : out_.nets.front().cols(),
            "size of " + g[init.state].name, "as many coordinates as the first net"));
      }
    }
  }

  const Reader& r_;
  BcifsFile out_;
  std::map<std::string, StateId> cells_;
};

}  // namespace

BcifsFile parse_bcifs_json(std::string_view source, std::string_view where) {
  const Reader r{std::string(where)};
  return BcifsReader(r).read(detail::parse_document(source, r.where));
}

std::string to_json(const ifs::Bcifs& sys, std::span<const Points> nets) {
  ifs::validate(sys);
  const auto& a = sys.automaton;
  const auto& g = a.graph;
  if (!nets.empty() && nets.size() != a.initial.size())
    throw InvalidInput("the BC-IFS has " + std::to_string(a.initial.size()) + " initial entries but " +
                       std::to_string(nets.size()) + " control nets are given");
  const std::set<ifs::TransitionRef> free(sys.free.begin(), sys.free.end());
  json cells = json::array(), transitions = json::array(), boundaries = json::array(),
       constraints = json::array(), initial = json::array();
  for (StateId s = 0; s < num_vertices(g); ++s) {
    const std::string name = cell_name(a, s);
    if (name.find_first_of("./") != std::string::npos)
      throw InvalidInput("the cell name \"" + name +
                         "\" has a '.' or '/', which BC-IFS files use as separators");
    cells.push_back({{"name", name}, {"size", g[s].size}, {"dimension", sys.dimension[s]}});
    int child = 0;
    for (auto [e, end] = out_edges(s, g); e != end; ++e, ++child)
      transitions.push_back({{"from", name},
                             {"to", cell_name(a, target(*e, g))},
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
