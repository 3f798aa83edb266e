// SPDX-License-Identifier: MIT
// cifs — error types shared by every module.
#pragma once

#include <stdexcept>
#include <string>

namespace cifs {

/// Input that breaks a documented precondition (knots, weights, degrees, sizes, parameters).
/// The message names the problem and where it is, e.g. "knots[4]: 0.5 is less than knots[3] = 1".
class InvalidInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A file that cannot be read, parsed or written.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cifs
