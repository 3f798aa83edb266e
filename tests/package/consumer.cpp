// SPDX-License-Identifier: MIT
#include <cifs/io/json.hpp>
#include <cifs/nurbs/refine.hpp>
#include <cmath>
#include <cstdio>

int main() {
  using namespace cifs;
  Points P(3, 2);
  P << 0, 0, 1, 2, 2, 0;
  const nurbs::Curve c = nurbs::make_curve(2, {0, 0, 0, 1, 1, 1}, P);
  const nurbs::Curve r = nurbs::refine_midpoints(c);
  const double gap = (nurbs::evaluate(c, 0.3) - nurbs::evaluate(r, 0.3)).norm();
  std::printf("consumer: %zu knots, gap %g\n", r.knots.size(), gap);
  return gap < 1e-15 && io::to_json(r).find("\"curve\"") != std::string::npos ? 0 : 1;
}
