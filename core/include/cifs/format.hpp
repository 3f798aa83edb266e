// SPDX-License-Identifier: MIT
// cifs — the one number formatter: data files get the shortest text that reads back as the same
// double; messages and labels get a fixed count of significant digits or decimals.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace cifs {

// Every form writes a NaN as "nan", whatever its sign bit.

/// Shortest decimal text that reads back as the same double (std::to_chars): JSON and other data.
void append_number(std::string& out, double x);
std::string number_text(double x);

/// `digits` significant digits, as printf's `%.<digits>g` (and an ostream with precision(digits)):
/// 17 reads back as the same double in the classic `%.17g` form (OBJ, PLY text), 6 suits messages.
void append_number(std::string& out, double x, int digits);
std::string number_text(double x, int digits);

/// `decimals` digits after the point, as printf's `%.<decimals>f`: screen coordinates (SVG).
void append_fixed(std::string& out, double x, int decimals);
std::string fixed_text(double x, int decimals);

/// Text the user gave, for a message: whole when it has at most `max` characters, else its first
/// ones and how long it is ("((((((((((((((((((((… (10001 characters)"), so that a 5,000-digit
/// number or a 10 kB expression is not echoed whole. A UTF-8 sequence is never cut.
std::string excerpt(std::string_view text, std::size_t max = 40);

}  // namespace cifs
