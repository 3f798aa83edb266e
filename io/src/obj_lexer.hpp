// SPDX-License-Identifier: MIT
// cifs — private to the io module: the statements of an OBJ file (comments, continuation lines) and
// its numbers, with the file and line at hand for messages. Shared by the free-form reader
// (obj_freeform.cpp) and the polygon reader (obj.cpp).
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/format.hpp"

namespace cifs::io::detail {

using Tokens = std::vector<std::string_view>;

inline bool is_space(char c) noexcept {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

inline Tokens tokenize(std::string_view s) {
  Tokens out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    const std::size_t start = i;
    while (i < s.size() && !is_space(s[i])) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

/// Calls `f(line, tokens)` for every non-blank statement. A `#` starts a comment that runs to the end
/// of its physical line; a physical line that then ends with `\` continues on the next one. `line` is
/// the 1-based number of the statement's first physical line.
template <class F>
void for_each_statement(std::string_view text, F&& f) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark
  std::string joined;
  std::size_t line = 0, start = 0, pos = 0;
  bool continuing = false;
  for (;;) {
    const std::size_t eol = std::min(text.find('\n', pos), text.size());
    std::string_view phys = text.substr(pos, eol - pos);
    ++line;
    if (const std::size_t hash = phys.find('#'); hash != std::string_view::npos) phys = phys.substr(0, hash);
    while (!phys.empty() && is_space(phys.back())) phys.remove_suffix(1);
    const bool more = !phys.empty() && phys.back() == '\\';
    if (more) phys.remove_suffix(1);
    if (!continuing) {
      joined.clear();
      start = line;
    }
    joined += phys;
    joined += ' ';
    continuing = more;
    if (!continuing) {
      const Tokens t = tokenize(joined);
      if (!t.empty()) f(start, t);
    }
    if (eol == text.size()) break;
    pos = eol + 1;
  }
  if (continuing) {
    const Tokens t = tokenize(joined);
    if (!t.empty()) f(start, t);
  }
}

/// Shortest text that reads back as the same double, for messages.
inline std::string num(double x) {
  return number_text(x);
}

/// A token quoted for a message, cut short when it is long.
inline std::string quote(std::string_view t) {
  constexpr std::size_t kMax = 40;
  std::string out(1, '\'');
  out.append(t.substr(0, kMax));
  out.append(t.size() > kMax ? "...'" : "'");
  return out;
}

/// The file and the current line, for messages: syntax problems are IoError, content problems
/// (values out of range, references to nothing) InvalidInput, both "where: line N: what".
struct ObjPlace {
  std::string where;
  std::size_t line = 0;

  std::string at(std::size_t l) const { return where + ": line " + std::to_string(l) + ": "; }
  [[noreturn]] void syntax(std::size_t l, const std::string& what) const { throw IoError(at(l) + what); }
  [[noreturn]] void invalid(std::size_t l, const std::string& what) const {
    throw InvalidInput(at(l) + what);
  }

  /// A finite number: IoError when the token is not a number, InvalidInput when it is not finite.
  double number(std::string_view tok, std::string_view what) const {
    std::string_view s = tok;
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    double x = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
    if (ptr != s.data() + s.size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
      syntax(line, std::string(what) + ": expected a number, got " + quote(tok));
    if (ec == std::errc::result_out_of_range)
      invalid(line, std::string(what) + ": " + quote(tok) + " is out of the range of double");
    if (!std::isfinite(x)) invalid(line, std::string(what) + ": " + quote(tok) + " is not finite");
    return x;
  }

  static std::string plural(std::string_view what) {
    if (what == "vertex") return "vertices";
    if (what == "texture") return "texture coordinates (vt)";
    return std::string(what) + "s";
  }

  long long integer(std::string_view tok, std::string_view what) const {
    std::string_view s = tok;
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    long long x = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
    if (ptr != s.data() + s.size() || s.empty() || ec != std::errc())
      syntax(line, std::string(what) + ": expected an integer, got " + quote(tok));
    return x;
  }

  /// A 0-based element number from an OBJ reference: 1-based, or negative counting back from the
  /// `count` elements defined so far (−1 is the latest). `what` names them ("vertex", "normal").
  std::size_t resolve(long long index, std::size_t count, std::string_view what) const {
    const auto n = static_cast<long long>(count);
    if (index == 0)
      invalid(line, std::string(what) + " index 0 is invalid (indices start at 1, negative ones count back)");
    const long long k = index > 0 ? index - 1 : n + index;
    if (k < 0 || k >= n)
      invalid(line, std::string(what) + " index " + std::to_string(index) + " is out of range: " +
                        std::to_string(n) + " " + plural(what) + " are defined before this line");
    return static_cast<std::size_t>(k);
  }
};

}  // namespace cifs::io::detail
