// SPDX-License-Identifier: MIT
// cifs — the tensor-product automata of NURBS surfaces and volumes: pairs (triples) of knot-doubling
// states of the direction curves, transitions = Kronecker products of the factors' matrices.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/automata/tensor.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/surface.hpp"
#include "cifs/nurbs/volume.hpp"

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

/// The tensor-product automaton of a volume: the conventions of TensorAutomaton one dimension up (one
/// builder serves both).
/// - product state (p, q, r) of factor states p (u, size su), q (v, sv), r (w, sw) has size su·sv·sw; row
///   (i, j, k) of its nets is row `(i·sv + j)·sw + k` (like Volume::P);
/// - its eight transitions are, in out-edge order, GHA, GHR, GBA, GBR, DHA, DHR, DBA, DBR: child index
///   `4·iu + 2·iv + iw` with iu the u-half (0 = G, 1 = D), iv the v-half (0 = H, 1 = B) and iw the w-half
///   (0 = A, 1 = R: automata::w_label);
/// - the matrix of child (iu, iv, iw) is `kron(kron(M_u, M_v), M_w)`, exactly;
/// - `product.initial` holds one entry per cell (non-empty u segment a × v segment b × w segment c) in
///   that order (w fastest): index `(a·nv_seg + b)·nw_seg + c`, `segment` = that index, `cells` its
///   segments;
/// - only triples reachable from the initial triples are states; rational volumes use homogeneous rows.
struct VolumeAutomaton {
  automata::Automaton product;           // states = (u-state, v-state, w-state) triples
  std::array<KnotAutomaton, 3> factors;  // knot automata of the u, v and w direction curves
  std::vector<std::array<automata::StateId, 3>> factor_states;  // per product state: its factor states
  std::vector<std::array<int, 3>> cells;  // per product.initial entry: (u, v, w segments)
};

/// The tensor-product automaton of a volume (from its knots alone); recurrent states marked.
VolumeAutomaton tensor_automaton(const Volume& volume);

/// Control net of every cell (per product.initial entry): `(p+1)(q+1)(r+1) by cols` rows of `volume.P`
/// (homogeneous when rational), row `(i·(q+1) + j)·(r+1) + k` = control point
/// `(span_u − p + i, span_v − q + j, span_w − r + k)`. Throws InvalidInput when `volume` does not fit.
std::vector<Points> initial_nets(const VolumeAutomaton& automaton, const Volume& volume);

}  // namespace cifs::nurbs
