// SPDX-License-Identifier: MIT
// cifs — the JSON points report of cifs eval and cifs attractor: `{"points":[[x,y],…]}`, numbers
// as the shortest text that reads back as the same double, then `"seed":S` for the chaos game.
#include "cifs/format.hpp"
#include "json_common.hpp"
#include "points_format.hpp"

namespace cifs::io::detail {
namespace json_text {

void header(std::string& out, std::uint64_t, Eigen::Index, const PointsStyle&) {
  out += "{\"points\":[";
}

void rows(std::string& out, const Eigen::Ref<const Points>& rows, std::uint64_t first) {
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    out += first == 0 && i == 0 ? "[" : ",[";
    for (Eigen::Index j = 0; j < rows.cols(); ++j) {
      if (j) out += ',';
      detail::append_json_number(out, rows(i, j));
    }
    out += ']';
  }
}

void footer(ChunkBuffer& out, std::uint64_t, const PointsStyle& style) {
  out.text += ']';
  if (style.seed) out.text += ",\"seed\":" + std::to_string(*style.seed);
  out.text += "}\n";
}

}  // namespace json_text

const PointsFormat kJsonPoints{"json", 0, json_text::header, json_text::rows, json_text::footer};

}  // namespace cifs::io::detail
