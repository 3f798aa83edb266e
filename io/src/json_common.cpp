// SPDX-License-Identifier: MIT
#include "json_common.hpp"

#include <algorithm>

namespace cifs::io::detail {
namespace {

/// nlohmann's messages start with "[json.exception.kind.N] "; users need only what follows.
std::string strip_id(const std::string& what) {
  const auto end = what.find("] ");
  std::string rest = end == std::string::npos ? what : what.substr(end + 2);
  if (rest.rfind("parse error", 0) == 0 && rest.find(": ") != std::string::npos)
    rest = rest.substr(rest.find(": ") + 2);
  return rest;
}

}  // namespace

json parse_document(std::string_view text, const std::string& where) {
  try {
    return json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    throw IoError(where + ": malformed JSON at byte " + std::to_string(e.byte) + ": " + strip_id(e.what()));
  } catch (const json::exception& e) {  // e.g. a number that overflows a double
    throw IoError(where + ": malformed JSON: " + strip_id(e.what()));
  }
}

Points to_points(const std::vector<std::vector<double>>& rows) {
  Points P(static_cast<Eigen::Index>(rows.size()),
           rows.empty() ? 0 : static_cast<Eigen::Index>(rows[0].size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < rows[i].size(); ++j)
      P(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
  return P;
}

json rows_json(const Points& P) {
  json out = json::array();
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index j = 0; j < P.cols(); ++j) row.push_back(P(i, j));
    out.push_back(std::move(row));
  }
  return out;
}

void write_pretty(const json& v, int indent, std::string& out) {
  const auto flat = [](const json& a) {
    return a.is_array() && std::all_of(a.begin(), a.end(), [](const json& e) {
             return e.is_primitive() || (e.is_array() && std::all_of(e.begin(), e.end(), [](const json& x) {
                                           return x.is_primitive();
                                         }));
           });
  };
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  if (v.is_object()) {
    out += "{";
    bool first = true;
    for (const auto& item : v.items()) {
      out += first ? "\n" : ",\n";
      out += pad;
      out += json(item.key()).dump();
      out += ": ";
      write_pretty(item.value(), indent + 2, out);
      first = false;
    }
    out += '\n';
    out.append(static_cast<std::size_t>(indent), ' ');
    out += '}';
  } else if (v.is_array() && !flat(v)) {
    out += "[";
    for (std::size_t i = 0; i < v.size(); ++i) {
      out += i ? ",\n" : "\n";
      out += pad;
      write_pretty(v[i], indent + 2, out);
    }
    out += '\n';
    out.append(static_cast<std::size_t>(indent), ' ');
    out += ']';
  } else {
    out += v.dump();
  }
}

}  // namespace cifs::io::detail
