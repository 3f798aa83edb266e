// SPDX-License-Identifier: MIT
// Test helpers of the BC-IFS tests: the hand-made tree-like system of examples/automata/tree.json,
// built directly.
#pragma once

#include <algorithm>

#include "cifs/ifs/bcifs.hpp"
#include "ifs/helpers.hpp"

namespace ifs_test {

/// Edge cell E (3 points, from row 0 to row 2) with children G, D along the edge and a branch B
/// that starts at the junction (end of G = start of D); vertex cell V (1 point, operator [1]).
inline cifs::ifs::Bcifs tree_bcifs() {
  using cifs::ifs::Factor;
  using K = Factor::Kind;
  cifs::ifs::Bcifs sys;
  Automaton& a = sys.automaton;
  const StateId E = add_state(a, 3, "E"), V = add_state(a, 1, "V");
  Eigen::MatrixXd G(3, 3), D(3, 3), B(3, 3);
  G << 1, 0, 0, 0.55, 0.4, 0.05, 0.5, 0, 0.5;
  D << 0.5, 0, 0.5, 0.05, 0.4, 0.55, 0, 0, 1;
  B << 0.5, 0, 0.5, 0.28, 0.4, 0.32, 0.2, 0.76, 0.04;
  add_transition(a, E, E, G, "G");
  add_transition(a, E, E, D, "D");
  add_transition(a, E, E, B, "B");
  add_transition(a, V, V, Eigen::MatrixXd::Ones(1, 1), "V");
  add_initial(a, E);
  sys.dimension = {1, 0};
  sys.boundaries = {{"start", E, V, {0}}, {"end", E, V, {2}}};
  const Factor start{K::boundary, 0, {}}, end{K::boundary, 1, {}}, g{K::transition, 0, {E, 0}},
      d{K::transition, 0, {E, 1}}, b{K::transition, 0, {E, 2}}, v{K::transition, 0, {V, 0}};
  sys.constraints = {{"start", {start, g}, {v, start}},
                     {"end", {end, d}, {v, end}},
                     {"junction", {end, g}, {start, d}},
                     {"branch", {start, b}, {start, d}}};
  sys.free = {{E, 0}, {E, 1}, {E, 2}};
  return sys;
}

inline Points tree_net() {
  Points P(3, 2);
  P << 0, 0, 0.5, 0.5, 1, 0;
  return P;
}

/// The largest residual of the system's constraints.
inline double max_residual(const cifs::ifs::Bcifs& sys) {
  double worst = 0;
  for (const auto& [name, r] : cifs::ifs::constraint_residuals(sys)) worst = std::max(worst, r);
  return worst;
}

}  // namespace ifs_test
