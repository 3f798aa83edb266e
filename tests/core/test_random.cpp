// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <set>

#include "cifs/random.hpp"

using namespace cifs;

TEST_CASE("SplitMix64 and xoshiro256** give the reference sequences", "[core][random]") {
  // SplitMix64 from state 0 (Steele, Lea, Flood; Vigna's splitmix64.c).
  std::uint64_t state = 0;
  CHECK(splitmix64(state) == 0xE220A8397B1DCDAFULL);
  CHECK(splitmix64(state) == 0x6E789E6AA1B965F4ULL);
  CHECK(splitmix64(state) == 0x06C45D188009454FULL);
  // xoshiro256** from the state {1, 2, 3, 4} (Blackman & Vigna's xoshiro256starstar.c): the first
  // outputs, worked out by hand from the algorithm: rotl(2·5, 7)·9, rotl(0, 7)·9, rotl(262149·5, 7)·9.
  Random r({1, 2, 3, 4});
  CHECK(r() == 11520u);
  CHECK(r() == 0u);
  CHECK(r() == 1509978240u);
  // Seeding by SplitMix64: stream 0 is the plain seed, the state is SplitMix64's first four words.
  std::uint64_t sm = 42;
  const std::array<std::uint64_t, 4> words{splitmix64(sm), splitmix64(sm), splitmix64(sm), splitmix64(sm)};
  Random a(42), b(42, 0), c(words);
  for (int i = 0; i < 8; ++i) {
    const auto x = a();
    CHECK(b() == x);
    CHECK(c() == x);
  }
}

TEST_CASE("streams differ and the helpers stay in range", "[core][random]") {
  std::set<std::uint64_t> first;
  for (std::uint64_t stream = 0; stream < 1000; ++stream) first.insert(Random(7, stream)());
  CHECK(first.size() == 1000);
  Random r(3);
  double lo = 1, hi = -1, sum = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double u = r.uniform(), s = r.symmetric();
    REQUIRE(u >= 0);
    REQUIRE(u < 1);
    REQUIRE(s >= -1);
    REQUIRE(s < 1);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    sum += u;
  }
  CHECK(sum / n == Approx(0.5).margin(5 * std::sqrt(1.0 / 12 / n)));
  CHECK(lo < -0.999);
  CHECK(hi > 0.999);
  for (std::uint32_t bound : {1u, 2u, 3u, 1000u, 4294967295u}) {
    CHECK(bounded(0, bound) == 0);
    CHECK(bounded(0xFFFFFFFFu, bound) == bound - 1);
  }
}
