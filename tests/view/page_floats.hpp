// SPDX-License-Identifier: MIT
// The view tests' comparison: the floats the page receives for a geometry (x, y, z per point; a
// missing coordinate is 0), from a library result computed apart.
#pragma once

#include <vector>

#include "cifs/types.hpp"

namespace cifs_test {

inline std::vector<float> page_floats(const cifs::Points& points) {
  std::vector<float> out;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (Eigen::Index k = 0; k < 3; ++k)
      out.push_back(k < points.cols() ? static_cast<float>(points(i, k)) : 0.0F);
  return out;
}

}  // namespace cifs_test
