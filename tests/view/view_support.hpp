// SPDX-License-Identifier: MIT
// What the view tests share: a session on a copy of an example file, and the floats the page receives
// for a geometry (x, y, z per point; a missing coordinate is 0), from a library result computed apart.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "cifs/types.hpp"
#include "cifs/view/server.hpp"
#include "support/scratch.hpp"

namespace cifs_test {

/// A session on a copy of examples/`example` in a scratch folder, answering Host "127.0.0.1:8765".
struct ViewFixture {
  explicit ViewFixture(const std::string& example) {
    const std::filesystem::path copy = dir.path() / std::filesystem::path(example).filename();
    std::filesystem::copy_file(std::string(CIFS_EXAMPLES_DIR) + "/" + example, copy);
    cifs::view::open_session(session, copy, "127.0.0.1", 8765);
  }
  cifs::view::Response get(const std::string& target, const std::string& host = "127.0.0.1:8765") {
    return cifs::view::handle(session, {.method = "GET", .target = target, .host = host, .body = {}});
  }
  cifs::view::Response post(const std::string& path, const std::string& body) {
    return cifs::view::handle(session, {.method = "POST",
                                        .target = path + "?token=" + session.token,
                                        .host = "127.0.0.1:8765",
                                        .body = body});
  }
  ScratchDir dir;
  cifs::view::Session session;
};

inline std::vector<float> page_floats(const cifs::Points& points) {
  std::vector<float> out;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (Eigen::Index k = 0; k < 3; ++k)
      out.push_back(k < points.cols() ? static_cast<float>(points(i, k)) : 0.0F);
  return out;
}

}  // namespace cifs_test
