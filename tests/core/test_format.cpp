// SPDX-License-Identifier: MIT
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>

#include "cifs/format.hpp"
#include "cifs/random.hpp"

using namespace cifs;

namespace {

/// Doubles over the whole range: random bit patterns (finite ones), and a few chosen values.
std::vector<double> sample_values() {
  std::vector<double> xs{0.0,
                         -0.0,
                         1.0,
                         0.1,
                         1.0 / 3,
                         1e300,
                         -2.5e-310,
                         123456789012345680.0,
                         std::numeric_limits<double>::max(),
                         std::numeric_limits<double>::denorm_min()};
  Random r(7);
  while (xs.size() < 4000) {
    const double x = std::bit_cast<double>(r());
    if (std::isfinite(x)) xs.push_back(x);
    xs.push_back(r.symmetric() * 1000);
  }
  return xs;
}

}  // namespace

TEST_CASE("number_text: shortest text that reads back as the same double", "[core][format]") {
  for (const double x : sample_values()) {
    const std::string text = number_text(x);
    INFO(text);
    CHECK(std::bit_cast<std::uint64_t>(std::strtod(text.c_str(), nullptr)) ==
          std::bit_cast<std::uint64_t>(x));
    // Shortest: no printf %.<p>g text that reads back as x is shorter (std::to_chars's promise is in
    // characters: 4.7e+20 may print as all 21 integer digits when that is as short as any other form).
    for (int p = 1; p <= 17; ++p) {
      char printed[400];
      std::snprintf(printed, sizeof printed, "%.*g", p, x);
      if (std::strtod(printed, nullptr) == x) {
        CHECK(text.size() <= std::string(printed).size());
        break;
      }
    }
    std::string appended = "[";
    append_number(appended, x);
    CHECK(appended == "[" + text);
  }
}

TEST_CASE("number_text with digits and fixed_text match the iostream forms", "[core][format]") {
  for (const double x : sample_values()) {
    for (const int digits : {1, 3, 4, 6, 12, 17}) {
      std::ostringstream general;
      general << std::setprecision(digits) << x;
      CHECK(number_text(x, digits) == general.str());
    }
    for (const int decimals : {0, 1, 3}) {
      std::ostringstream fixed;
      fixed << std::fixed << std::setprecision(decimals) << x;
      CHECK(fixed_text(x, decimals) == fixed.str());
    }
  }
  // 17 significant digits read back exactly (the OBJ/PLY text form).
  CHECK(std::strtod(number_text(0.1, 17).c_str(), nullptr) == 0.1);
  CHECK(number_text(0.1, 17) == "0.10000000000000001");
  CHECK(number_text(std::numeric_limits<double>::infinity(), 6) == "inf");
  // A NaN is "nan" in every form: printf and to_chars wrote "-nan" for one with its sign bit set
  // (messages read "parameter -nan is not finite").
  const double negative_nan = -std::numeric_limits<double>::quiet_NaN();
  CHECK(number_text(negative_nan, 6) == "nan");
  CHECK(number_text(negative_nan) == "nan");
  CHECK(fixed_text(negative_nan, 2) == "nan");
  CHECK(fixed_text(1e308, 2).size() == 312);  // 309 digits, the point, 2 decimals
}
