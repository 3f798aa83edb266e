// SPDX-License-Identifier: MIT
// An occt consumer (find_package(cifs COMPONENTS occt)): a curve to STEP and back through OpenCASCADE.
#include <cifs/occt/occt.hpp>
#include <cstdio>

int main() {
  using namespace cifs;
  Points P(2, 3);
  P << 0, 0, 0, 1, 2, 3;
  const std::vector<io::Shape> shapes{nurbs::make_curve(1, {0, 0, 1, 1}, P)};
  const std::string step = occt::write_cad(shapes, io::CadFormat::step);
  const std::vector<io::Shape> back = occt::read_cad(step, "memory.step", io::CadFormat::step);
  const Point end = nurbs::evaluate(std::get<nurbs::Curve>(back.at(0)), 1.0);
  std::printf("consumer (occt): %zu bytes of STEP, end point %g %g %g\n", step.size(), end[0], end[1],
              end[2]);
  return end[0] == 1 && end[1] == 2 && end[2] == 3 ? 0 : 1;
}
