// SPDX-License-Identifier: MIT
// Fuzzing: exact numbers as `cifs scheme --param` reads them (subdivision::parse_rational: integers,
// decimals with exponents, fractions). Property: a number read prints (to_string) as text that reads
// back to the same exact value, and its nearest double is finite or the value is beyond a double.
#include <cmath>
#include <limits>

#include "cifs/subdivision/scheme.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(rational) {
  using namespace cifs;
  using subdivision::Rational;
  fuzz::refusals_allowed([&] {
    const Rational x = subdivision::parse_rational(fuzz::text(data, size), "fuzz");
    const std::string printed = subdivision::to_string(x);
    const Rational again = fuzz::no_refusal([&] { return subdivision::parse_rational(printed, "again"); },
                                            "rational round trip: the printed value reads");
    fuzz::require(again == x, "rational round trip");
    const double d = subdivision::to_double(x);
    const Rational largest(std::numeric_limits<double>::max());
    fuzz::require(std::isfinite(d) || x > largest || x < -largest, "rational to double");
  });
  return 0;
}
