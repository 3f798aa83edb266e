// SPDX-License-Identifier: MIT
// cifs — the tensor-product automaton of a NURBS surface: pairs of knot-doubling states of the u
// and v direction curves, transitions = Kronecker products of the factors' matrices.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/automata/tensor.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/surface.hpp"

namespace cifs::nurbs {

/// Conventions (fixed; other modules rely on them):
/// - product state (p, q) of factor states p (u, size su) and q (v, size sv) has size su·sv; row
///   (i, j) of its nets — i along u, j along v — is row `i·sv + j` (u-major, like Surface::P);
/// - its four transitions are, in out-edge order, GH, GB, DH, DB: child index `2·iu + iv` with iu
///   the u-half (0 = G, 1 = D) and iv the v-half (0 = H, 1 = B, the v-direction's G and D);
/// - the matrix of child (iu, iv) is `kron(M_u, M_v)` (`su'·sv' by su·sv`, entry
///   `(i·sv' + j, k·sv + l) = M_u(i, k)·M_v(j, l)`), exactly, with M_u, M_v the factors' matrices;
/// - `product.initial` holds one entry per patch (non-empty u segment a × non-empty v segment b) in
///   u-major order: index `a·nv_seg + b`, `segment` = that index; the product has no knot data: the
///   patch's intervals and spans are those of `factors[0].intervals[a]` and `factors[1].intervals[b]`;
/// - only pairs reachable from the initial pairs are states; rational surfaces use homogeneous
///   rows `(w·x, w)`, and the matrices do not depend on them.
struct TensorAutomaton {
  automata::Automaton product;           // states = (u-state, v-state) pairs
  std::array<KnotAutomaton, 2> factors;  // knot automata of the u and v direction curves
  std::vector<std::array<automata::StateId, 2>> factor_states;  // per product state: its (u, v) factor states
  std::vector<std::array<int, 2>> patches;  // per product.initial entry: (u segment, v segment)
};

/// The tensor-product automaton of a surface (from its knots alone); recurrent states marked.
TensorAutomaton tensor_automaton(const Surface& surface);

/// Control net of every patch (per product.initial entry): `(p+1)(q+1) by cols` rows of
/// `surface.P` (homogeneous when rational), row `i·(q+1) + j` = control point
/// `(span_u − p + i, span_v − q + j)`. Throws InvalidInput when `surface` does not fit the automaton.
std::vector<Points> initial_nets(const TensorAutomaton& automaton, const Surface& surface);

}  // namespace cifs::nurbs
