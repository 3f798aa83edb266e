// SPDX-License-Identifier: MIT
// cifs — the chaos game: a random walk down the subdivision tree emitting exact attractor points.
#include "cifs/ifs/chaos.hpp"

#include <cmath>
#include <random>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/memory.hpp"
#include "cifs/random.hpp"
#include "walk.hpp"

namespace cifs::ifs {

using automata::Automaton;
using automata::Graph;
using automata::StateId;

namespace {

/// Uniform index in [0, bound) from the top 32 bits of a draw (bias ≤ bound/2³², negligible).
std::size_t draw(Random& rng, std::size_t bound) noexcept {
  return static_cast<std::size_t>(((rng() >> 32) * static_cast<std::uint64_t>(bound)) >> 32);
}

}  // namespace

ChaosResult chaos_game(const Automaton& automaton, std::span<const Points> nets,
                       const ChaosOptions& options) {
  validate(automaton);
  check_nets(automaton, nets);
  if (!(options.restart_diameter > 0 && options.restart_diameter < 1))
    throw InvalidInput("the chaos game's restart diameter " +
                       (std::isfinite(options.restart_diameter) ? number_text(options.restart_diameter, 6)
                                                                : std::string("(not a finite number)")) +
                       " is outside (0, 1)");
  // A walk on a system that does not shrink nets would never restart and lose all precision. Only
  // the verdict is needed: the tightened factor costs seconds for large states (degree 64).
  (void)contraction(automaton, ContractionOptions{.max_length = 8, .tighten = false, .bound = false});
  const Graph& g = automaton.graph;
  const EndFunctionals functionals = end_functionals(automaton);

  ChaosResult result;
  result.seed = options.seed;
  if (result.seed == 0) {
    std::random_device device;
    while (result.seed == 0) result.seed = (std::uint64_t{device()} << 32) ^ std::uint64_t{device()};
  }
  Random rng(result.seed);
  const auto cols = nets[0].cols();
  const std::size_t per_sample =
      (static_cast<std::size_t>(cols) + (options.record_address ? 1 : 0)) * sizeof(double);
  if (options.samples > options.max_bytes / per_sample)
    throw InvalidInput(
        std::to_string(options.samples) + " chaos-game samples of " + std::to_string(per_sample) +
        " bytes exceed the " + number_text(static_cast<double>(options.max_bytes) / 1e9, 3) +
        " GB held in memory; ask for at most " + std::to_string(options.max_bytes / per_sample) + " samples");
  result.points.resize(static_cast<Eigen::Index>(options.samples), cols);
  advise_huge_pages(result.points.data(), static_cast<std::size_t>(result.points.size()) * sizeof(double));
  if (options.record_address) result.address.resize(options.samples);

  std::vector<double> root_diameter(nets.size());
  for (std::size_t i = 0; i < nets.size(); ++i) root_diameter[i] = diameter(nets[i]);

  Points net, child;
  std::size_t initial = 0;
  StateId state = 0;
  double threshold = 0, t = 0, share = 1;
  int steps = 0;
  const auto restart = [&] {
    initial = draw(rng, nets.size());
    state = automaton.initial[initial].state;
    net = nets[initial];
    threshold = options.restart_diameter * root_diameter[initial];
    t = 0;
    share = 1;
    steps = 0;
  };
  restart();
  for (std::size_t k = 0; k < options.samples; ++k) {
    const auto degree = out_degree(state, g);
    const std::size_t c = draw(rng, degree);
    auto [b, e] = out_edges(state, g);
    std::advance(b, static_cast<std::ptrdiff_t>(c));
    child.noalias() = g[*b].matrix * net;
    std::swap(net, child);
    state = target(*b, g);
    share /= static_cast<double>(degree);
    t += static_cast<double>(c) * share;
    ++steps;
    // The start point of the new node: an exact attractor point (address child-path, then 0^∞).
    result.points.row(static_cast<Eigen::Index>(k)).noalias() = functionals.start[state] * net;
    if (options.record_address) result.address[k] = static_cast<double>(initial) + t;
    // Degenerate roots (diameter 0) restart after a bounded walk instead.
    if (threshold > 0 ? diameter(net) < threshold : steps >= 64) restart();
  }
  return result;
}

}  // namespace cifs::ifs
