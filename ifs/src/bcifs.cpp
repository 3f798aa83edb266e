// SPDX-License-Identifier: MIT
// cifs — BC-IFS: validation, constraint assembly, the admissible space, perturbation, edge pieces.
//
// Linearity. A side F_0⋯F_k with its free transition X at position u is A·X·C, A = F_0⋯F_{u−1},
// C = F_{u+1}⋯F_k, and (A·X·C)(r, c) = Σ_{p,q} A(r,p)·X(p,q)·C(q,c): one equation per entry of the
// constraint, linear in the entries of X. Boundary operators are selections, so A and C have one
// 1 per row and column used and an equation touches few unknowns: the unknown/equation graph
// falls apart into small components (a row of a child matrix is tied to rows of a few others).
#include "cifs/ifs/bcifs.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>
#include <string_view>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/failing_paths.hpp"
#include "cifs/random.hpp"
#include "union_find.hpp"
#include "walk.hpp"

namespace cifs::ifs {

using automata::Automaton;
using automata::Graph;
using automata::StateId;
using automata::TransitionId;

namespace {

std::string state_text(const Automaton& a, StateId s) {
  const auto& name = a.graph[s].name;
  return name.empty() ? "s" + std::to_string(s) : name;
}

/// Cell read (`from`) and produced (`to`) by a factor; the factor must exist.
std::pair<StateId, StateId> factor_cells(const Bcifs& sys, const Factor& f) {
  if (f.kind == Factor::Kind::boundary) {
    const auto& b = sys.boundaries[static_cast<std::size_t>(f.boundary)];
    return {b.cell, b.boundary};
  }
  const TransitionId e = transition_id(sys.automaton, f.transition);
  return {f.transition.from, target(e, sys.automaton.graph)};
}

std::string factor_text(const Bcifs& sys, const Factor& f) {
  if (f.kind == Factor::Kind::boundary) {
    const auto& b = sys.boundaries[static_cast<std::size_t>(f.boundary)];
    return state_text(sys.automaton, b.cell) + "." + b.name;
  }
  return transition_name(sys.automaton, f.transition);
}

int cell_size(const Bcifs& sys, StateId s) {
  return sys.automaton.graph[s].size;
}

/// Two matrices a product of factors alternates between; kept from one product to the next, they keep their
/// storage while the shapes repeat (Eigen reallocates on a change of size only).
using ProductBuffers = std::array<Eigen::MatrixXd, 2>;

const Eigen::MatrixXd& transition_matrix(const Bcifs& sys, TransitionRef ref) {
  return sys.automaton.graph[transition_id(sys.automaton, ref)].matrix;
}

/// Product of factors [first, last) (identity of `size` when empty): one of `buffers`, or the matrix of a
/// lone transition itself. A boundary factor picks rows, a transition M before a last boundary B places
/// M's columns (M·B), and the last factor starts the product, with the values the products by a selection
/// matrix and by the identity give (one term x·1, the others ±0: exact for finite entries, up to the sign
/// of a zero), at a fraction of the cost: constraint_residuals checks every perturbed system of an
/// interactive edit (cifs view), with no allocation once its buffers have the sizes of the constraints.
const Eigen::MatrixXd& product(const Bcifs& sys, std::span<const Factor> factors, int size,
                               ProductBuffers& buffers) {
  if (factors.empty()) return buffers[0] = Eigen::MatrixXd::Identity(size, size);
  const Factor& last = factors.back();
  auto it = factors.rbegin() + 1;
  const Eigen::MatrixXd* P = &buffers[0];
  if (last.kind == Factor::Kind::transition) {
    P = &transition_matrix(sys, last.transition);
  } else if (it == factors.rend() || it->kind == Factor::Kind::boundary) {
    buffers[0] = selection_matrix(sys, last.boundary);
  } else {
    const auto& b = sys.boundaries[static_cast<std::size_t>(last.boundary)];
    const Eigen::MatrixXd& M = transition_matrix(sys, it++->transition);
    buffers[0].setZero(M.rows(), cell_size(sys, b.cell));
    for (std::size_t i = 0; i < b.rows.size(); ++i)
      buffers[0].col(b.rows[i]) = M.col(static_cast<Eigen::Index>(i));
  }
  for (; it != factors.rend(); ++it) {
    Eigen::MatrixXd& next = P == &buffers[0] ? buffers[1] : buffers[0];
    if (it->kind == Factor::Kind::boundary) {
      const auto& rows = sys.boundaries[static_cast<std::size_t>(it->boundary)].rows;
      next.resize(static_cast<Eigen::Index>(rows.size()), P->cols());
      for (std::size_t i = 0; i < rows.size(); ++i) next.row(static_cast<Eigen::Index>(i)) = P->row(rows[i]);
    } else {
      detail::multiply(transition_matrix(sys, it->transition), *P, next);
    }
    P = &next;
  }
  return *P;
}

Eigen::MatrixXd product(const Bcifs& sys, std::span<const Factor> factors, int size) {
  ProductBuffers buffers;
  return product(sys, factors, size, buffers);
}

/// Position of the free transition on a side, or -1.
int free_position(std::span<const Factor> side, const std::map<TransitionRef, std::size_t>& free_index) {
  for (std::size_t k = 0; k < side.size(); ++k)
    if (side[k].kind == Factor::Kind::transition && free_index.count(side[k].transition))
      return static_cast<int>(k);
  return -1;
}

using detail::UnionFind;

/// One linear equation Σ coef·x = rhs over the unknowns; `source` is the constraint index, or
/// −1 − f for the row sums of free matrix f.
struct Equation {
  std::vector<std::pair<std::size_t, double>> terms;
  double rhs = 0;
  int source = 0;
};

}  // namespace

TransitionId transition_id(const Automaton& a, TransitionRef ref) {
  const Graph& g = a.graph;
  if (ref.from >= num_vertices(g))
    throw InvalidInput("transition of state " + std::to_string(ref.from) + ", which does not exist");
  const auto degree = static_cast<int>(out_degree(ref.from, g));
  if (ref.child < 0 || ref.child >= degree)
    throw InvalidInput("transition " + std::to_string(ref.child) + " of state " + state_text(a, ref.from) +
                       ", which has " + std::to_string(degree) + " transitions");
  auto it = out_edges(ref.from, g).first;
  std::advance(it, ref.child);
  return *it;
}

std::string transition_name(const Automaton& a, TransitionRef ref) {
  return state_text(a, ref.from) + "/" + a.graph[transition_id(a, ref)].label;
}

Eigen::MatrixXd selection_matrix(const Bcifs& sys, int boundary) {
  const auto& b = sys.boundaries.at(static_cast<std::size_t>(boundary));
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(b.rows.size()), cell_size(sys, b.cell));
  for (std::size_t i = 0; i < b.rows.size(); ++i) B(static_cast<Eigen::Index>(i), b.rows[i]) = 1;
  return B;
}

void validate(const Bcifs& sys) {
  const Graph& g = sys.automaton.graph;
  const auto n = num_vertices(g);
  if (sys.dimension.size() != n)
    throw InvalidInput("BC-IFS: " + std::to_string(sys.dimension.size()) + " cell dimensions for " +
                       std::to_string(n) + " states");
  for (StateId s = 0; s < n; ++s) {
    if (sys.dimension[s] < 0 || sys.dimension[s] > 2)
      throw InvalidInput("BC-IFS: cell " + state_text(sys.automaton, s) + " has dimension " +
                         std::to_string(sys.dimension[s]) + ", expected 0 (vertex), 1 (edge) or 2 (face)");
    // The first label that repeats an earlier one, in order (a few children per state: no set).
    const auto [first, end] = out_edges(s, g);
    for (auto b = first; b != end; ++b)
      if (std::any_of(first, b, [&](TransitionId earlier) { return g[earlier].label == g[*b].label; }))
        throw InvalidInput("BC-IFS: cell " + state_text(sys.automaton, s) +
                           " has two transitions labelled \"" + g[*b].label +
                           "\" (labels name the transitions)");
  }
  // Messages are made only when thrown, names are views of the system's, rows are marked in one reused
  // vector: validating a perturbed surface's thousands of boundaries and constraints with every edit of
  // cifs view cost a third of its perturbation in strings and tree nodes.
  std::set<std::pair<StateId, std::string_view>> names;
  std::vector<char> seen;
  for (std::size_t i = 0; i < sys.boundaries.size(); ++i) {
    const auto& b = sys.boundaries[i];
    const auto where = [&] { return "BC-IFS: boundaries[" + std::to_string(i) + "] (\"" + b.name + "\")"; };
    if (b.cell >= n || b.boundary >= n) throw InvalidInput(where() + ": names a state that does not exist");
    if (!names.insert({b.cell, b.name}).second)
      throw InvalidInput(where() + ": cell " + state_text(sys.automaton, b.cell) +
                         " has two boundaries of that name");
    if (sys.dimension[b.boundary] >= sys.dimension[b.cell])
      throw InvalidInput(where() + ": the boundary cell " + state_text(sys.automaton, b.boundary) +
                         " has dimension " + std::to_string(sys.dimension[b.boundary]) +
                         ", not less than its cell's " + std::to_string(sys.dimension[b.cell]));
    if (static_cast<int>(b.rows.size()) != g[b.boundary].size)
      throw InvalidInput(where() + ": selects " + std::to_string(b.rows.size()) +
                         " rows, the boundary cell " + state_text(sys.automaton, b.boundary) + " holds " +
                         std::to_string(g[b.boundary].size));
    seen.assign(static_cast<std::size_t>(g[b.cell].size), 0);
    for (const int r : b.rows)
      if (r < 0 || r >= g[b.cell].size || seen[static_cast<std::size_t>(r)]++ != 0)
        throw InvalidInput(where() + ": row " + std::to_string(r) + " is repeated or outside the cell's " +
                           std::to_string(g[b.cell].size) + " rows");
  }
  std::map<TransitionRef, std::size_t> free_index;
  for (std::size_t f = 0; f < sys.free.size(); ++f) {
    transition_id(sys.automaton, sys.free[f]);
    if (!free_index.emplace(sys.free[f], f).second)
      throw InvalidInput("BC-IFS: transition " + transition_name(sys.automaton, sys.free[f]) +
                         " is listed free twice");
  }
  for (const Constraint& c : sys.constraints) {
    const auto where = [&] { return "BC-IFS: constraint \"" + c.name + "\""; };
    std::pair<StateId, StateId> ends[2];
    for (int side = 0; side < 2; ++side) {
      const auto& factors = side ? c.right : c.left;
      if (factors.empty())
        throw InvalidInput(where() + ": the " + (side ? "right" : "left") + " side is empty");
      int unknowns = 0;
      for (std::size_t k = 0; k < factors.size(); ++k) {
        const Factor& f = factors[k];
        if (f.kind == Factor::Kind::boundary) {
          if (f.boundary < 0 || f.boundary >= static_cast<int>(sys.boundaries.size()))
            throw InvalidInput(where() + ": boundary operator " + std::to_string(f.boundary) +
                               " does not exist");
        } else {
          transition_id(sys.automaton, f.transition);
          unknowns += static_cast<int>(free_index.count(f.transition));
        }
        if (k + 1 < factors.size() && factor_cells(sys, f).first != factor_cells(sys, factors[k + 1]).second)
          throw InvalidInput(where() + ": " + factor_text(sys, f) + " reads cell " +
                             state_text(sys.automaton, factor_cells(sys, f).first) + " but " +
                             factor_text(sys, factors[k + 1]) + " produces cell " +
                             state_text(sys.automaton, factor_cells(sys, factors[k + 1]).second));
      }
      if (unknowns > 1)
        throw InvalidInput(where() + ": the " + (side ? "right" : "left") +
                           " side holds more than one free transition (not linear)");
      ends[side] = {factor_cells(sys, factors.back()).first, factor_cells(sys, factors.front()).second};
    }
    if (ends[0] != ends[1])
      throw InvalidInput(where() + ": the left side maps cell " + state_text(sys.automaton, ends[0].first) +
                         " to " + state_text(sys.automaton, ends[0].second) + ", the right side " +
                         state_text(sys.automaton, ends[1].first) + " to " +
                         state_text(sys.automaton, ends[1].second));
  }
}

std::string coefficient_name(const Automaton& a, const Coefficient& c) {
  return transition_name(a, c.transition) + "[" + std::to_string(c.row) + "," + std::to_string(c.col) + "]";
}

std::vector<std::pair<std::string, double>> constraint_residuals(const Bcifs& sys) {
  validate(sys);
  std::vector<std::pair<std::string, double>> out;
  ProductBuffers left, right;
  for (const Constraint& c : sys.constraints) {
    const int source = cell_size(sys, factor_cells(sys, c.left.back()).first);
    const Eigen::MatrixXd& L = product(sys, c.left, source, left);
    const Eigen::MatrixXd& R = product(sys, c.right, source, right);
    const double scale = std::max({1.0, L.cwiseAbs().maxCoeff(), R.cwiseAbs().maxCoeff()});
    out.emplace_back(c.name, (L - R).cwiseAbs().maxCoeff() / scale);
  }
  for (const TransitionRef& f : sys.free) {
    const auto& M = sys.automaton.graph[transition_id(sys.automaton, f)].matrix;
    const double worst = M.rows() ? (M.rowwise().sum().array() - 1).abs().maxCoeff() : 0.0;
    out.emplace_back(transition_name(sys.automaton, f) + " row sums", worst);
  }
  return out;
}

automata::StateId source_cell(const Bcifs& sys, const Constraint& c) {
  const Factor& f = c.left.back();
  return f.kind == Factor::Kind::transition ? f.transition.from
                                            : sys.boundaries[static_cast<std::size_t>(f.boundary)].cell;
}

void check_admissible(const Bcifs& sys, double tolerance) {
  const auto residuals = constraint_residuals(sys);
  const auto worst = std::max_element(residuals.begin(), residuals.end(),
                                      [](const auto& a, const auto& b) { return a.second < b.second; });
  if (worst != residuals.end() && !(worst->second <= tolerance))
    throw InvalidInput("BC-IFS: the matrices are not admissible: constraint \"" + worst->first +
                       "\" fails by " + number_text(worst->second, 3) + " (relative; tolerance " +
                       number_text(tolerance, 3) + ")");
}

namespace {

/// The unknowns are the entries of the free matrices, row-major, one matrix after the other.
struct Numbering {
  std::map<TransitionRef, std::size_t> free_index;
  std::vector<std::size_t> base;  // first unknown of each free matrix
};

Numbering number_unknowns(const Bcifs& sys, std::vector<Coefficient>& unknowns) {
  const Graph& g = sys.automaton.graph;
  Numbering num;
  for (std::size_t f = 0; f < sys.free.size(); ++f) {
    num.free_index.emplace(sys.free[f], f);
    num.base.push_back(unknowns.size());
    const auto& M = g[transition_id(sys.automaton, sys.free[f])].matrix;
    for (int r = 0; r < M.rows(); ++r)
      for (int c = 0; c < M.cols(); ++c) unknowns.push_back(Coefficient{sys.free[f], r, c});
  }
  return num;
}

std::size_t unknown_index(const Bcifs& sys, const Numbering& num, std::size_t f, Eigen::Index r,
                          Eigen::Index c) {
  const auto& M = sys.automaton.graph[transition_id(sys.automaton, sys.free[f])].matrix;
  return num.base[f] + static_cast<std::size_t>(r * M.cols() + c);
}

/// Name of an equation's source in messages.
std::string source_name(const Bcifs& sys, int src) {
  return src >= 0
             ? sys.constraints[static_cast<std::size_t>(src)].name
             : transition_name(sys.automaton, sys.free[static_cast<std::size_t>(-1 - src)]) + " row sums";
}

/// Constraint ci as left − right = 0, linear in the unknowns: the terms of each entry
/// (row-major, `target by source`) and the known part moved to the right-hand side.
struct LinearConstraint {
  std::vector<std::map<std::size_t, double>> terms;
  Eigen::MatrixXd rhs;
};

LinearConstraint linearize(const Bcifs& sys, const Numbering& num, const Constraint& con, int source,
                           int target) {
  LinearConstraint out{std::vector<std::map<std::size_t, double>>(static_cast<std::size_t>(source * target)),
                       Eigen::MatrixXd::Zero(target, source)};
  for (int side = 0; side < 2; ++side) {
    const std::span<const Factor> factors = side ? con.right : con.left;
    const double sign = side ? -1.0 : 1.0;
    const int u = free_position(factors, num.free_index);
    if (u < 0) {
      out.rhs -= sign * product(sys, factors, source);
      continue;
    }
    const Factor& x = factors[static_cast<std::size_t>(u)];
    const auto [x_from, x_to] = factor_cells(sys, x);
    const Eigen::MatrixXd A = product(sys, factors.first(static_cast<std::size_t>(u)), cell_size(sys, x_to));
    const Eigen::MatrixXd C = product(sys, factors.subspan(static_cast<std::size_t>(u) + 1), source);
    const std::size_t f = num.free_index.at(x.transition);
    for (Eigen::Index r = 0; r < A.rows(); ++r)
      for (Eigen::Index p = 0; p < A.cols(); ++p) {
        if (A(r, p) == 0) continue;
        for (Eigen::Index q = 0; q < C.rows(); ++q)
          for (Eigen::Index c = 0; c < C.cols(); ++c)
            if (C(q, c) != 0)
              out.terms[static_cast<std::size_t>(r) * static_cast<std::size_t>(source) +
                        static_cast<std::size_t>(c)][unknown_index(sys, num, f, p, q)] +=
                  sign * A(r, p) * C(q, c);
      }
  }
  return out;
}

/// The equations of constraint ci, one per entry; those reading x_a = x_b only merge classes of
/// equal unknowns (`same`, see the substitution below).
void add_constraint_equations(const Bcifs& sys, const Numbering& num, std::size_t ci, UnionFind& same,
                              std::vector<Equation>& equations) {
  const Constraint& con = sys.constraints[ci];
  const int source = cell_size(sys, factor_cells(sys, con.left.back()).first);
  const int target = cell_size(sys, factor_cells(sys, con.left.front()).second);
  const LinearConstraint lin = linearize(sys, num, con, source, target);
  for (int r = 0; r < target; ++r)
    for (int c = 0; c < source; ++c) {
      Equation eq;
      eq.source = static_cast<int>(ci);
      eq.rhs = lin.rhs(r, c);
      for (const auto& [k, v] : lin.terms[static_cast<std::size_t>(r) * static_cast<std::size_t>(source) +
                                          static_cast<std::size_t>(c)])
        if (v != 0) eq.terms.emplace_back(k, v);
      if (eq.terms.empty()) {
        // Both sides known: the entry must already agree.
        if (std::abs(eq.rhs) > 1e-12 * std::max(1.0, std::abs(eq.rhs)))
          throw InvalidInput("BC-IFS: constraint \"" + con.name + "\" involves no free matrix at entry (" +
                             std::to_string(r) + "," + std::to_string(c) + ") and fails there by " +
                             number_text(std::abs(eq.rhs), 3));
        continue;
      }
      if (eq.terms.size() == 2 && eq.rhs == 0 && eq.terms[0].second == -eq.terms[1].second) {
        same.unite(eq.terms[0].first, eq.terms[1].first);  // x_a = x_b: substituted below
        continue;
      }
      equations.push_back(std::move(eq));
    }
}

/// One equation per row of each free matrix: its entries sum to 1.
void add_row_sum_equations(const Bcifs& sys, const Numbering& num, std::vector<Equation>& equations) {
  for (std::size_t f = 0; f < sys.free.size(); ++f) {
    const auto& M = sys.automaton.graph[transition_id(sys.automaton, sys.free[f])].matrix;
    for (Eigen::Index r = 0; r < M.rows(); ++r) {
      Equation eq;
      eq.source = -1 - static_cast<int>(f);
      eq.rhs = 1;
      for (Eigen::Index c = 0; c < M.cols(); ++c)
        eq.terms.emplace_back(unknown_index(sys, num, f, r, c), 1.0);
      equations.push_back(std::move(eq));
    }
  }
}

/// The system once classes of equal unknowns and their constants are substituted.
struct Substitution {
  std::vector<double> value;                            // constant of each class (at its root), NaN when none
  std::vector<std::size_t> reduced_of, representative;  // class root ↔ reduced variable
  std::vector<Equation> reduced;                        // over the reduced variables
};

/// The constants: equations x_a = c set their class's value; two different ones throw.
void set_constants(const Bcifs& sys, const std::vector<Coefficient>& unknowns,
                   std::span<const Equation* const> constants, UnionFind& same, Substitution& s) {
  std::vector<int> value_source(unknowns.size(), 0);
  for (const Equation* eq : constants) {
    const std::size_t r = same.find(eq->terms[0].first);
    const double v = eq->rhs / eq->terms[0].second;
    if (std::isnan(s.value[r])) {
      s.value[r] = v;
      value_source[r] = eq->source;
    } else if (std::abs(s.value[r] - v) > 1e-12 * std::max({1.0, std::abs(v), std::abs(s.value[r])})) {
      throw InvalidInput("BC-IFS: the constraints \"" + source_name(sys, value_source[r]) + "\", \"" +
                         source_name(sys, eq->source) + "\" have no common solution (they set " +
                         coefficient_name(sys.automaton, unknowns[eq->terms[0].first]) + " to " +
                         number_text(s.value[r], 3) + " and to " + number_text(v, 3) + ")");
    }
  }
}

/// Substitution first: most constraint equations read x_a = x_b (an entry of one side is an entry
/// of the other) or x_a = c (the other side is fixed). Classes of equal unknowns, with their
/// constant when they have one, leave a far smaller system for the dense QR (a surface system
/// ties thousands of entries into one component otherwise).
Substitution substitute(const Bcifs& sys, const std::vector<Coefficient>& unknowns,
                        const std::vector<Equation>& equations, UnionFind& same) {
  const std::size_t n = unknowns.size();
  Substitution s;
  std::vector<const Equation*> constants, others_eq;
  for (const Equation& eq : equations)
    (eq.source >= 0 && eq.terms.size() == 1 ? constants : others_eq).push_back(&eq);
  s.value.assign(n, std::numeric_limits<double>::quiet_NaN());
  set_constants(sys, unknowns, constants, same, s);
  // Reduced variables: the classes without a constant, named by their smallest unknown.
  s.reduced_of.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k)
    if (same.find(k) == k && std::isnan(s.value[k])) {
      s.reduced_of[k] = s.representative.size();
      s.representative.push_back(k);
    }
  for (const Equation* eq : others_eq) {
    Equation r;
    r.source = eq->source;
    r.rhs = eq->rhs;
    std::map<std::size_t, double> terms;
    for (const auto& [k, v] : eq->terms) {
      const std::size_t root = same.find(k);
      if (std::isnan(s.value[root]))
        terms[s.reduced_of[root]] += v;
      else
        r.rhs -= v * s.value[root];
    }
    for (const auto& [k, v] : terms)
      if (v != 0) r.terms.emplace_back(k, v);
    if (r.terms.empty()) {
      if (std::abs(r.rhs) > 1e-9 * std::max(1.0, std::abs(eq->rhs)))
        throw InvalidInput(
            "BC-IFS: \"" + source_name(sys, eq->source) +
            "\" has no solution once the constraints' fixed entries are substituted (it misses by " +
            number_text(std::abs(r.rhs), 3) + ")");
      continue;
    }
    s.reduced.push_back(std::move(r));
  }
  return s;
}

/// The solution over the reduced variables: x0 + a combination of the free ones.
struct ReducedSolution {
  Eigen::VectorXd x0;
  std::vector<char> is_free;
  // Dependent unknown → (its coefficient on each free unknown of its component).
  std::vector<std::pair<std::size_t, std::vector<std::pair<std::size_t, double>>>> dependents;
};

/// One component (variables `vars`, equations `eqs` of `reduced`) by a column-pivoting QR.
void solve_component(const Bcifs& sys, const std::vector<Equation>& reduced,
                     const std::vector<std::size_t>& vars, const std::vector<std::size_t>& eqs,
                     double threshold, ReducedSolution& out) {
  std::map<std::size_t, Eigen::Index> local;
  for (std::size_t k = 0; k < vars.size(); ++k) local[vars[k]] = static_cast<Eigen::Index>(k);
  const auto m = static_cast<Eigen::Index>(eqs.size()), nv = static_cast<Eigen::Index>(vars.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, nv);
  Eigen::VectorXd b(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Equation& eq = reduced[eqs[static_cast<std::size_t>(i)]];
    for (const auto& [k, v] : eq.terms) A(i, local[k]) += v;
    b(i) = eq.rhs;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(threshold);
  const Eigen::Index rank = qr.rank();
  const auto& perm = qr.colsPermutation().indices();
  std::vector<Eigen::Index> basic(perm.data(), perm.data() + rank),
      others(perm.data() + rank, perm.data() + nv);
  std::sort(basic.begin(), basic.end());
  std::sort(others.begin(), others.end());
  Eigen::MatrixXd AB(m, rank), AF(m, nv - rank);
  for (Eigen::Index j = 0; j < rank; ++j) AB.col(j) = A.col(basic[static_cast<std::size_t>(j)]);
  for (Eigen::Index j = 0; j < nv - rank; ++j) AF.col(j) = A.col(others[static_cast<std::size_t>(j)]);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qrb(AB);
  // Eigen's triangular solve binds a reference to the first coefficient of its right-hand side,
  // null for an empty one (UBSan: MapBase.h:262): solve only what is not empty.
  const Eigen::VectorXd xb = rank > 0 ? Eigen::VectorXd(qrb.solve(b)) : Eigen::VectorXd(0);
  const Eigen::MatrixXd KB =
      rank > 0 && nv > rank ? Eigen::MatrixXd(-qrb.solve(AF)) : Eigen::MatrixXd::Zero(rank, nv - rank);
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  const double miss = (AB * xb - b).cwiseAbs().maxCoeff() / scale;
  const double slack = nv > rank ? (AB * KB + AF).cwiseAbs().maxCoeff() : 0.0;
  if (!(miss <= 1e-9) || !(slack <= 1e-9)) {
    std::set<std::string> names;
    for (const std::size_t e : eqs) names.insert(source_name(sys, reduced[e].source));
    std::string list;
    for (const auto& s : names) list += (list.empty() ? "\"" : ", \"") + s + "\"";
    throw InvalidInput("BC-IFS: the constraints " + list +
                       " have no common solution (least-squares residual " +
                       number_text(std::max(miss, slack), 3) + ")");
  }
  for (Eigen::Index j = 0; j < rank; ++j) {
    const std::size_t k = vars[static_cast<std::size_t>(basic[static_cast<std::size_t>(j)])];
    out.x0(static_cast<Eigen::Index>(k)) = xb(j);
    std::vector<std::pair<std::size_t, double>> row;
    for (Eigen::Index i = 0; i < nv - rank; ++i)
      if (KB(j, i) != 0)
        row.emplace_back(vars[static_cast<std::size_t>(others[static_cast<std::size_t>(i)])], KB(j, i));
    out.dependents.emplace_back(k, std::move(row));
  }
  for (const Eigen::Index i : others) out.is_free[vars[static_cast<std::size_t>(i)]] = 1;
}

/// Connected components of the unknown/equation graph, each solved on its own.
ReducedSolution solve_reduced(const Bcifs& sys, const std::vector<Equation>& reduced, std::size_t nr,
                              double threshold, std::size_t& components) {
  UnionFind uf(nr);
  for (const Equation& eq : reduced)
    for (const auto& t : eq.terms) uf.unite(eq.terms.front().first, t.first);
  std::map<std::size_t, std::vector<std::size_t>> comp_unknowns, comp_equations;
  for (std::size_t k = 0; k < nr; ++k) comp_unknowns[uf.find(k)].push_back(k);
  for (std::size_t e = 0; e < reduced.size(); ++e)
    comp_equations[uf.find(reduced[e].terms.front().first)].push_back(e);

  ReducedSolution out{Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nr)), std::vector<char>(nr, 0), {}};
  for (const auto& [root, vars] : comp_unknowns) {
    solve_component(sys, reduced, vars, comp_equations[root], threshold, out);
    ++components;
  }
  return out;
}

/// Back to the unknowns: a class's members share its constant, or its reduced variable's
/// expression; a free reduced variable is named by the class's smallest unknown.
void expand_solution(const Substitution& s, ReducedSolution& x, UnionFind& same, AdmissibleSpace& space) {
  const std::size_t n = space.unknowns.size(), nr = s.representative.size();
  std::vector<Eigen::Index> column(nr, -1);
  for (std::size_t r = 0; r < nr; ++r)
    if (x.is_free[r]) {
      column[r] = static_cast<Eigen::Index>(space.free.size());
      space.free.push_back(s.representative[r]);
    }
  std::vector<std::vector<std::pair<std::size_t, double>>> dependent_row(nr);
  for (auto& [r, row] : x.dependents) dependent_row[r] = std::move(row);
  space.x0 = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  std::vector<Eigen::Triplet<double>> triplets;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t root = same.find(k);
    const auto i = static_cast<Eigen::Index>(k);
    if (!std::isnan(s.value[root])) {
      space.x0(i) = s.value[root];
      continue;
    }
    const std::size_t r = s.reduced_of[root];
    if (x.is_free[r]) {
      triplets.emplace_back(i, column[r], 1.0);
      continue;
    }
    space.x0(i) = x.x0(static_cast<Eigen::Index>(r));
    for (const auto& [fr, v] : dependent_row[r]) triplets.emplace_back(i, column[fr], v);
  }
  space.K.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(space.free.size()));
  space.K.setFromTriplets(triplets.begin(), triplets.end());
}

}  // namespace

AdmissibleSpace admissible_space(const Bcifs& sys, const SolveOptions& options) {
  // threshold ≥ 1 makes every rank 0: the basic-column QR below would factor an m × 0 matrix.
  if (!(options.threshold >= 0 && options.threshold < 1))
    throw InvalidInput("the rank threshold " +
                       (std::isfinite(options.threshold) ? number_text(options.threshold, 3)
                                                         : std::string("(not a finite number)")) +
                       " is outside [0, 1)");
  validate(sys);
  AdmissibleSpace space;
  const Numbering num = number_unknowns(sys, space.unknowns);
  // Equations: one per entry of each constraint, one per row of each free matrix.
  std::vector<Equation> equations;
  UnionFind same(space.unknowns.size());
  for (std::size_t ci = 0; ci < sys.constraints.size(); ++ci)
    add_constraint_equations(sys, num, ci, same, equations);
  add_row_sum_equations(sys, num, equations);
  const Substitution s = substitute(sys, space.unknowns, equations, same);
  ReducedSolution x =
      solve_reduced(sys, s.reduced, s.representative.size(), options.threshold, space.components);
  expand_solution(s, x, same, space);
  return space;
}

std::vector<std::string> free_names(const Bcifs& sys, const AdmissibleSpace& space) {
  std::vector<std::string> out;
  for (const std::size_t k : space.free) out.push_back(coefficient_name(sys.automaton, space.unknowns[k]));
  return out;
}

Eigen::VectorXd free_values(const Bcifs& sys, const AdmissibleSpace& space) {
  Eigen::VectorXd c(static_cast<Eigen::Index>(space.free.size()));
  for (std::size_t j = 0; j < space.free.size(); ++j) {
    const Coefficient& k = space.unknowns[space.free[j]];
    c(static_cast<Eigen::Index>(j)) =
        sys.automaton.graph[transition_id(sys.automaton, k.transition)].matrix(k.row, k.col);
  }
  return c;
}

Bcifs with_free_values(const Bcifs& sys, const AdmissibleSpace& space, const Eigen::VectorXd& c) {
  if (c.size() != static_cast<Eigen::Index>(space.free.size()))
    throw InvalidInput("BC-IFS: " + std::to_string(c.size()) + " values for " +
                       std::to_string(space.free.size()) + " free coefficients");
  Bcifs out = sys;
  const Eigen::VectorXd x = space.x0 + space.K * c;
  // The unknowns come a free matrix at a time: its transition is looked up once per run (a perturbed
  // surface's half million entries made half of an edit's perturbation in lookups).
  Eigen::MatrixXd* matrix = nullptr;
  std::optional<TransitionRef> looked_up;
  for (std::size_t k = 0; k < space.unknowns.size(); ++k) {
    const Coefficient& u = space.unknowns[k];
    if (looked_up != u.transition) {
      matrix = &out.automaton.graph[transition_id(out.automaton, u.transition)].matrix;
      looked_up = u.transition;
    }
    (*matrix)(u.row, u.col) = x(static_cast<Eigen::Index>(k));
  }
  return out;
}

namespace {

/// The first few names, for a message: "A, B, C, … (12 in all)".
std::string name_list(const std::vector<std::string>& names) {
  constexpr std::size_t kShown = 6;
  std::string out;
  for (std::size_t j = 0; j < std::min(names.size(), kShown); ++j) out += (j ? ", " : "") + names[j];
  if (names.size() > kShown) out += ", … (" + std::to_string(names.size()) + " in all)";
  return names.empty() ? std::string("none") : out;
}

}  // namespace

namespace {
void check_amplitude(double amplitude) {
  if (!(amplitude >= 0) || !std::isfinite(amplitude))
    throw InvalidInput("the perturbation amplitude " +
                       (std::isfinite(amplitude) ? number_text(amplitude, 3) + " is negative"
                                                 : std::string("is not a finite number")) +
                       "; give a finite amplitude ≥ 0");
}
}  // namespace

Perturbation perturb(const Bcifs& sys, const PerturbOptions& options) {
  check_amplitude(options.amplitude);
  return perturb(sys, admissible_space(sys, options.solve), options);
}

namespace {

/// perturb with the space solved; the contraction check with the failing paths of earlier ones when
/// `failing` is not null.
Perturbation perturb_in(const Bcifs& sys, const AdmissibleSpace& space, const PerturbOptions& options,
                        FailingPaths* failing) {
  check_amplitude(options.amplitude);
  if (space.unknowns.size() != static_cast<std::size_t>(space.K.rows()))
    throw std::logic_error("perturb: the admissible space is not one admissible_space built");
  const auto names = free_names(sys, space);
  std::map<std::string, std::size_t> index;
  for (std::size_t j = 0; j < names.size(); ++j) index.emplace(names[j], j);
  for (const auto& [name, value] : options.values) {
    if (!index.count(name)) {
      const std::string& given =
          name;  // a structured binding cannot be captured before C++20's P1091 in clang 14
      const bool dependent =
          std::any_of(space.unknowns.begin(), space.unknowns.end(),
                      [&](const Coefficient& u) { return coefficient_name(sys.automaton, u) == given; });
      throw InvalidInput("the perturbation value \"" + name + "\" is " +
                         (dependent ? "a dependent coefficient (solved from the constraints)"
                                    : "not an entry of a free matrix") +
                         "; the free coefficients are " + name_list(names));
    }
    if (!std::isfinite(value))
      throw InvalidInput("the perturbation value \"" + name + "\" is not a finite number");
  }
  Eigen::VectorXd c = free_values(sys, space);
  Random random(options.seed);
  Perturbation out;
  for (std::size_t j = 0; j < names.size(); ++j) {
    const double draw = random.symmetric();  // drawn for every coefficient: explicit values keep the stream
    const auto it = options.values.find(names[j]);
    auto& cj = c(static_cast<Eigen::Index>(j));
    cj = it != options.values.end() ? it->second : cj + options.amplitude * draw;
    out.values.emplace_back(names[j], cj);
  }
  out.system = with_free_values(sys, space, c);
  if (!options.check) return out;
  check_residual(out);
  check_contractive(out, options, failing);
  return out;
}

}  // namespace

void check_residual(Perturbation& out) {
  out.residual = 0;
  for (const auto& [name, r] : constraint_residuals(out.system)) out.residual = std::max(out.residual, r);
  if (!(out.residual <= 1e-12))
    throw InvalidInput("the perturbed matrices miss the constraints by " + number_text(out.residual, 3) +
                       " (the system is ill-conditioned); lower the amplitude");
}

void check_contractive(Perturbation& out, const PerturbOptions& options, FailingPaths* failing) {
  try {
    out.contraction = failing != nullptr ? contraction(out.system.automaton, options.contraction, *failing)
                                         : contraction(out.system.automaton, options.contraction);
  } catch (const NotContractive& e) {
    // Name what moved the coefficients: the random draw, the values set by name, or both.
    std::string cause;
    if (options.amplitude > 0)
      cause = "amplitude " + number_text(options.amplitude, 3) + ", seed " + std::to_string(options.seed);
    for (const auto& [name, value] : options.values)
      cause += (cause.empty() ? "" : ", ") + name + " = " + number_text(value, 3);
    throw NotContractive("the perturbed system is not contractive with " +
                             (cause.empty() ? std::string("its current values") : cause) + ": " + e.what(),
                         e.delta, e.length);
  }
}

Perturbation perturb(const Bcifs& sys, const AdmissibleSpace& space, const PerturbOptions& options) {
  return perturb_in(sys, space, options, nullptr);
}

Perturbation perturb(const Bcifs& sys, const AdmissibleSpace& space, const PerturbOptions& options,
                     FailingPaths& failing) {
  return perturb_in(sys, space, options, &failing);
}

EndFunctionals edge_end_functionals(const Bcifs& sys) {
  validate(sys);
  const Automaton& a = sys.automaton;
  const auto n = num_vertices(a.graph);
  const auto cells = reachable_states(a);
  // Boundary operators "start" and "end" of each reachable edge cell.
  std::vector<std::array<int, 2>> ends(n, {-1, -1});
  Automaton vertices = a;  // vertex cells as roots: end_functionals follows their first transition
  vertices.initial.clear();
  for (std::size_t i = 0; i < sys.boundaries.size(); ++i) {
    const auto& b = sys.boundaries[i];
    const int side = b.name == "start" ? 0 : b.name == "end" ? 1 : -1;
    if (side < 0 || sys.dimension[b.cell] != 1 || sys.dimension[b.boundary] != 0) continue;
    ends[b.cell][static_cast<std::size_t>(side)] = static_cast<int>(i);
    automata::Initial root;
    root.state = b.boundary;
    vertices.initial.push_back(root);
  }
  EndFunctionals out;
  out.start.resize(n);
  out.end.resize(n);
  for (const StateId s : cells)
    if (sys.dimension[s] == 1 && (ends[s][0] < 0 || ends[s][1] < 0))
      throw InvalidInput("the edge cell " + state_text(a, s) +
                         " has no \"start\" or no \"end\" boundary onto a vertex cell");
  if (vertices.initial.empty()) return out;
  const EndFunctionals fixed = end_functionals(vertices);
  for (const StateId s : cells) {
    if (sys.dimension[s] != 1) continue;
    for (int side = 0; side < 2; ++side) {
      const auto& b = sys.boundaries[static_cast<std::size_t>(ends[s][static_cast<std::size_t>(side)])];
      Eigen::RowVectorXd l = Eigen::RowVectorXd::Zero(a.graph[s].size);
      for (std::size_t i = 0; i < b.rows.size(); ++i)
        l(b.rows[i]) = fixed.start[b.boundary](static_cast<Eigen::Index>(i));
      (side ? out.end : out.start)[s] = std::move(l);
    }
  }
  return out;
}

EdgePieces edge_pieces(const Bcifs& sys, std::span<const Points> nets, int depth, std::size_t max_bytes) {
  // Refuse before any work: two end points, a state, an initial index and a word per node. Bad nets
  // and depths are left to for_each_leaf's messages.
  if (depth >= 0 && !nets.empty() && nets.size() == sys.automaton.initial.size()) {
    const std::size_t nodes = attractor_point_count(sys.automaton, depth, true);
    const double bytes =
        static_cast<double>(nodes) *
        static_cast<double>(2 * sizeof(double) * static_cast<std::size_t>(nets.front().cols()) +
                            sizeof(automata::StateId) + sizeof(std::size_t) + sizeof(std::vector<int>) +
                            sizeof(int) * static_cast<std::size_t>(depth));
    if (bytes > static_cast<double>(max_bytes))
      throw InvalidInput(std::to_string(nodes) + " edge pieces at depth " + std::to_string(depth) + " need " +
                         number_text(bytes / 1e9, 3) + " GB, above the limit of " +
                         number_text(static_cast<double>(max_bytes) / 1e9, 3) + " GB; lower the depth");
  }
  const EndFunctionals F = edge_end_functionals(sys);
  std::vector<Point> starts, ends;
  EdgePieces out;
  for_each_leaf(sys.automaton, nets, depth, [&](const Leaf& leaf) {
    if (F.start[leaf.state].size() == 0)
      throw InvalidInput("the cell " + state_text(sys.automaton, leaf.state) + " has dimension " +
                         std::to_string(sys.dimension[leaf.state]) + ": it is not an edge cell");
    starts.push_back(F.start[leaf.state] * leaf.net);
    ends.push_back(F.end[leaf.state] * leaf.net);
    out.state.push_back(leaf.state);
    out.initial.push_back(leaf.initial);
    out.word.emplace_back(leaf.word.begin(), leaf.word.end());
  });
  const auto count = static_cast<Eigen::Index>(starts.size());
  const Eigen::Index cols = nets.empty() ? 0 : nets[0].cols();
  out.start.resize(count, cols);
  out.end.resize(count, cols);
  for (Eigen::Index i = 0; i < count; ++i) {
    out.start.row(i) = starts[static_cast<std::size_t>(i)];
    out.end.row(i) = ends[static_cast<std::size_t>(i)];
  }
  return out;
}

}  // namespace cifs::ifs
