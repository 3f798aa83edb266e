// SPDX-License-Identifier: MIT
#include "cifs/ifs/chaos.hpp"

#include <catch2/catch.hpp>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "ifs/helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using namespace ifs_test;

TEST_CASE("Chaos game: points lie on the curve at their address", "[ifs]") {
  std::mt19937_64 rng(9);
  ChaosOptions options;
  options.samples = 20000;
  options.seed = 12345;
  options.record_address = true;
  SECTION("uniform cubic, three segments") {
    const int d = 3, segments = 3;
    const Automaton a = uniform_automaton(d, segments);
    const Points P = random_points(segments + d, 3, rng);
    std::vector<Points> nets;
    for (int k = 0; k < segments; ++k) nets.push_back(P.middleRows(k, d + 1));
    const ChaosResult r = chaos_game(a, nets, options);
    REQUIRE(r.points.rows() == 20000);
    REQUIRE(r.address.size() == 20000);
    CHECK(r.seed == 12345);
    double err = 0;
    std::vector<int> hits(segments, 0);
    for (Eigen::Index i = 0; i < r.points.rows(); ++i) {
      const double address = r.address[static_cast<std::size_t>(i)];
      const int k = static_cast<int>(address);
      REQUIRE(k < segments);
      ++hits[static_cast<std::size_t>(k)];
      err = std::max(err, (r.points.row(i) - uniform_reference(P, d, k, address - k)).cwiseAbs().maxCoeff());
    }
    CHECK(err <= 1e-9 * scale_of(P));
    CHECK(err <= 1e-13 * scale_of(P));  // in fact exact to round-off
    for (const int h : hits) CHECK(h > 5000);
  }
  SECTION("non-uniform quadratic") {
    const Automaton a = quadratic_automaton(0.1, 3, 0.7);
    const std::vector<Points> nets{random_points(3, 2, rng)};
    const ChaosResult r = chaos_game(a, nets, options);
    double err = 0, lo = 1, hi = 0;
    for (Eigen::Index i = 0; i < r.points.rows(); ++i) {
      const double t = r.address[static_cast<std::size_t>(i)];
      lo = std::min(lo, t);
      hi = std::max(hi, t);
      err = std::max(err,
                     (r.points.row(i) - quadratic_reference(nets[0], 0.1, 3, 0.7, t)).cwiseAbs().maxCoeff());
    }
    CHECK(err <= 1e-9 * scale_of(nets[0]));
    CHECK(lo < 1e-2);
    CHECK(hi > 1 - 1e-2);
  }
}

TEST_CASE("Chaos game: seeds", "[ifs]") {
  std::mt19937_64 rng(10);
  const Automaton a = uniform_automaton(2);
  const std::vector<Points> nets{random_points(3, 2, rng)};
  ChaosOptions options;
  options.samples = std::size_t{1} << 40;  // refused before allocating
  CHECK_THROWS_WITH(chaos_game(a, nets, options),
                    Catch::Contains("exceed the 1.07 GB held in memory; ask for at most"));
  options.samples = 1000;
  options.seed = 42;
  const ChaosResult a1 = chaos_game(a, nets, options), a2 = chaos_game(a, nets, options);
  CHECK(a1.points == a2.points);
  options.seed = 43;
  const ChaosResult b = chaos_game(a, nets, options);
  CHECK(b.points != a1.points);
  options.seed = 0;
  const ChaosResult drawn = chaos_game(a, nets, options);
  CHECK(drawn.seed != 0);
  options.seed = drawn.seed;
  CHECK(chaos_game(a, nets, options).points == drawn.points);
  // Restarts keep precision: a walk of 10^5 steps on a cubic is as exact as a short one.
  options.samples = 100000;
  options.record_address = true;
  const Automaton cubic = uniform_automaton(3);
  const std::vector<Points> cubic_nets{random_points(4, 3, rng)};
  const ChaosResult long_walk = chaos_game(cubic, cubic_nets, options);
  double err = 0;
  for (Eigen::Index i = 0; i < long_walk.points.rows(); ++i)
    err =
        std::max(err, (long_walk.points.row(i) -
                       uniform_reference(cubic_nets[0], 3, 0, long_walk.address[static_cast<std::size_t>(i)]))
                          .cwiseAbs()
                          .maxCoeff());
  CHECK(err <= 1e-13);
  options.restart_diameter = 0;
  CHECK_THROWS_AS(chaos_game(a, nets, options), InvalidInput);
}
