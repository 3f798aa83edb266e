// SPDX-License-Identifier: MIT
// The exact rational p / d that the subdivision tests write their masks and eigenvalues with (one
// definition for the files that share a unity batch, tests/CMakeLists.txt).
#pragma once

#include "cifs/subdivision/scheme.hpp"

namespace cifs_test {

inline cifs::subdivision::Rational q(long long p, long long d = 1) {
  return cifs::subdivision::Rational(p) / cifs::subdivision::Rational(d);
}

}  // namespace cifs_test
