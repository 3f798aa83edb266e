// SPDX-License-Identifier: MIT
// cifs — what a BC-IFS file holds (the JSON format of docs/formats.md, "bcifs": cifs/io/json.hpp).
#pragma once

#include <vector>

#include "cifs/ifs/bcifs.hpp"
#include "cifs/types.hpp"

namespace cifs::io {

/// A BC-IFS and the control nets of its initial entries (`size(state) by cols` each; empty when
/// the file gives none).
struct BcifsFile {
  ifs::Bcifs system;
  std::vector<Points> nets;
};

}  // namespace cifs::io
