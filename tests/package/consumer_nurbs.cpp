// SPDX-License-Identifier: MIT
// A NURBS-only consumer (find_package(cifs COMPONENTS nurbs)): the refined quadratic Bézier arc at
// u = 0.3, checked against the Bernstein form by hand: (1−u)²·P0 + 2u(1−u)·P1 + u²·P2 = (0.6, 0.84).
#include <cifs/nurbs/refine.hpp>
#include <cmath>
#include <cstdio>

int main() {
  using namespace cifs;
  Points P(3, 2);
  P << 0, 0, 1, 2, 2, 0;
  const nurbs::Curve r = nurbs::refine_midpoints(nurbs::make_curve(2, {0, 0, 0, 1, 1, 1}, P));
  const Point x = nurbs::evaluate(r, 0.3);
  std::printf("consumer (nurbs): %zu knots, C(0.3) = (%g, %g)\n", r.knots.size(), x[0], x[1]);
  return std::abs(x[0] - 0.6) < 1e-15 && std::abs(x[1] - 0.84) < 1e-15 ? 0 : 1;
}
