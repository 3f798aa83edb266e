// SPDX-License-Identifier: MIT
// cifs — number formatting (see cifs/format.hpp).
#include "cifs/format.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace cifs {

void append_number(std::string& out, double x) {
  if (std::isnan(x)) {  // the sign of a NaN means nothing to a reader ("-nan" from arithmetic)
    out += "nan";
    return;
  }
  char buffer[32];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

std::string number_text(double x) {
  std::string out;
  append_number(out, x);
  return out;
}

namespace {

/// printf of one double, however long the text (%f of 1e308 has 309 digits).
void append_printf(std::string& out, const char* format, int precision, double x) {
  if (std::isnan(x)) {
    out += "nan";
    return;
  }
  const int n = std::snprintf(nullptr, 0, format, precision, x);
  if (n <= 0) return;
  const std::size_t at = out.size();
  out.resize(at + static_cast<std::size_t>(n) + 1);
  std::snprintf(out.data() + at, static_cast<std::size_t>(n) + 1, format, precision, x);
  out.resize(at + static_cast<std::size_t>(n));
}

}  // namespace

void append_number(std::string& out, double x, int digits) {
  append_printf(out, "%.*g", digits, x);
}

std::string number_text(double x, int digits) {
  std::string out;
  append_number(out, x, digits);
  return out;
}

void append_fixed(std::string& out, double x, int decimals) {
  append_printf(out, "%.*f", decimals, x);
}

std::string fixed_text(double x, int decimals) {
  std::string out;
  append_fixed(out, x, decimals);
  return out;
}

std::string excerpt(std::string_view text, std::size_t max) {
  if (text.size() <= max) return std::string(text);
  std::size_t cut = max / 2;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0U) == 0x80U) --cut;  // continuation byte
  return std::string(text.substr(0, cut)) + "… (" + std::to_string(text.size()) + " characters)";
}

}  // namespace cifs
