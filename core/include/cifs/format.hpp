// SPDX-License-Identifier: MIT
// cifs — the one number formatter: data files get the shortest text that reads back as the same
// double; messages and labels get a fixed count of significant digits or decimals.
#pragma once

#include <string>

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

}  // namespace cifs
