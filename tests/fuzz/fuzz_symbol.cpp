// SPDX-License-Identifier: MIT
// Fuzzing: scheme symbols (subdivision::parse_symbol, `cifs scheme symbol --param symbol=…`):
// + − * / ^, brackets, implicit products, numbers as parse_rational reads them. Properties: a symbol
// read prints — term by term, and as `cifs scheme --analyze` shows it (polynomial_text) — as text that
// reads back to the same polynomial; nesting beyond the parser's bound is refused (InvalidInput), never a
// stack overflow (issue 33, defect 2: the seeds hold 300 brackets and 300 signs).
#include <algorithm>
#include <cctype>

#include "cifs/subdivision/analysis.hpp"
#include "cifs/subdivision/scheme.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(symbol) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    const subdivision::Polynomial p = subdivision::parse_symbol(fuzz::text(data, size));
    // Term by term, each coefficient as to_string prints it (which parse_rational reads back).
    std::string terms;
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (p[k] == 0) continue;
      terms += (terms.empty() ? "(" : "+(") + subdivision::to_string(p[k]) + ")";
      for (std::size_t left = k; left > 0; left -= std::min<std::size_t>(left, 1024))  // exponents ≤ 1024
        terms += "z^" + std::to_string(std::min<std::size_t>(left, 1024));
    }
    const subdivision::Polynomial again = fuzz::no_refusal([&] { return subdivision::parse_symbol(terms); },
                                                           "symbol round trip: the terms read");
    fuzz::require(again == p, "symbol round trip (terms)");
    // As `cifs scheme --analyze` prints it: over the common denominator, whose integers may exceed
    // the numbers read (4,700 bits: every integer of 1,414 digits, not every one of 1,415 — a 1,423-digit
    // one was refused, found by this harness on 1 Dec), and with powers of z beyond the 1,024 an exponent
    // is read with (neither for a mask's 512 coefficients): then not read back.
    const std::string printed = subdivision::polynomial_text(p);
    std::size_t run = 0, longest = 0;
    for (const char c : printed)
      longest = std::max(longest, run = std::isdigit(static_cast<unsigned char>(c)) ? run + 1 : 0);
    if (longest > 1414 || p.size() > 1025) return;
    fuzz::require(fuzz::no_refusal([&] { return subdivision::parse_symbol(printed); },
                                   "symbol round trip: the printed symbol reads") == p,
                  "symbol round trip");
    (void)subdivision::from_mask(p);  // the mask checks (sums, size) on what was read
  });
  return 0;
}
