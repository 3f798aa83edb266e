// SPDX-License-Identifier: MIT
// cifs — the Eigen aliases used across modules.
#pragma once

#include <Eigen/Core>

namespace cifs {

/// Control points as rows: `#P by dim`, row-major so that each point is contiguous.
/// Rational shapes store homogeneous rows `(w·x, w)`.
using Points = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// One point (or one homogeneous point) as a row.
using Point = Eigen::Matrix<double, 1, Eigen::Dynamic>;

}  // namespace cifs
