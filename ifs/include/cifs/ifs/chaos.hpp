// SPDX-License-Identifier: MIT
// cifs — the chaos game on a controlled IFS: a reproducible random walk whose points lie exactly on
// the attractor.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/types.hpp"

namespace cifs::ifs {

struct ChaosOptions {
  std::size_t samples = 100000;
  /// Seed of cifs::Random (cifs/random.hpp); 0 draws one from std::random_device (returned in the result).
  std::uint64_t seed = 0;
  /// Restart at a root when the walk's net diameter falls below this fraction of the root net's
  /// diameter, so that precision never collapses.
  double restart_diameter = 1e-9;
  /// Also return each point's address (see ChaosResult::address).
  bool record_address = false;
  /// Largest output (points and addresses) allocated; InvalidInput before allocating beyond it.
  std::size_t max_bytes = std::size_t{1} << 30;
};

struct ChaosResult {
  Points points;  // `samples by cols`
  std::uint64_t seed = 0;
  /// With record_address: `initial + t` where t ∈ [0, 1] is the equal-split parameter of the
  /// point's address inside its initial piece (each child takes an equal share of its parent's
  /// interval: t = Σ_k w_k / (b_1 ⋯ b_k), b_k the out-degrees). For binary knot-doubling
  /// automata t is the curve parameter mapped affinely from the segment's knot interval.
  std::vector<double> address;
};

/// Random walk: start at a uniformly random initial entry with its net, move to a uniformly random
/// child (Q = M·N) and emit the start point `start[state]·Q` of the new node at each step;
/// restart at a random root when the net has shrunk below `restart_diameter`. Refuses
/// (InvalidInput) systems that are not contractive (see contraction) and restart_diameter
/// outside (0, 1).
ChaosResult chaos_game(const automata::Automaton& automaton, std::span<const Points> nets,
                       const ChaosOptions& options = {});

}  // namespace cifs::ifs
