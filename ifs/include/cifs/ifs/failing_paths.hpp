// SPDX-License-Identifier: MIT
// cifs — the contractivity check of a system checked before with other matrices (cifs view: every edit of a
// perturbation checks a system whose matrices moved a little): the paths that failed the last check are
// tried first. A header of its own for its few users: analysis.hpp and bcifs.hpp are included by over a
// hundred sources.
#pragma once

#include <vector>

#include "cifs/automata/automaton.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs.hpp"

namespace cifs::ifs {

/// Paths that failed earlier contraction checks, one per path length: `by_length[m − 1]` is a path of m
/// transitions from `state` whose product had δ ≥ 1 (an empty word: none kept). A check given them follows
/// the kept path of each length below its last one first: when that product still has δ ≥ 1, and no bound
/// of the scan could skip it, the length fails as its scan would, without the scan; otherwise it is
/// scanned. The verdict, m, δ, A and the refusal's message are those of the check without kept paths, bit
/// for bit; a path that does not fit the automaton (another knot vector) is ignored. The check writes its
/// own failing paths back.
struct FailingPaths {
  struct Path {
    automata::StateId state = 0;
    std::vector<int> word;  // out-edge positions, as in NotContractive's message
  };
  std::vector<Path> by_length;
  int settled = 0;  // lengths failed by a kept path instead of a scan, over every check given this object
};

/// ifs::contraction, trying `failing` first and leaving this check's failing paths in it.
Contraction contraction(const automata::Automaton& automaton, const ContractionOptions& options,
                        FailingPaths& failing);

/// ifs::perturb with the space solved, its contraction check trying `failing` first (and updating it).
Perturbation perturb(const Bcifs& system, const AdmissibleSpace& space, const PerturbOptions& options,
                     FailingPaths& failing);

/// The contractivity check perturb makes (`options` those perturb was given, `check` off):
/// sets `perturbation.contraction`, or throws NotContractive naming the amplitude, seed and values as
/// perturb does. `failing` (may be null) as in contraction.
void check_contractive(Perturbation& perturbation, const PerturbOptions& options, FailingPaths* failing);

}  // namespace cifs::ifs
