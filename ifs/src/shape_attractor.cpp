// SPDX-License-Identifier: MIT
#include "cifs/ifs/shape_attractor.hpp"

#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/sample.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"

namespace cifs::ifs {

Points attractor(const nurbs::Curve& curve, int depth, std::size_t max_points) {
  if (depth < 0) throw InvalidInput("depth " + std::to_string(depth) + " is negative");
  const nurbs::KnotAutomaton a = nurbs::knot_automaton(curve);
  const std::vector<Points> nets = nurbs::initial_nets(a, curve);
  return sample_attractor(a.automaton, nets,
                          {.depth = depth,
                           .homogeneous = curve.rational,
                           .closed = curve.closed,
                           .max_points = max_points,
                           .limit_hint = "; lower the depth"})
      .points;
}

Mesh attractor(const nurbs::Surface& surface, int depth, std::size_t max_bytes) {
  if (depth < 0) throw InvalidInput("depth " + std::to_string(depth) + " is negative");
  const nurbs::TensorAutomaton a = nurbs::tensor_automaton(surface);
  MeshOptions options;
  options.homogeneous = surface.rational;
  options.max_bytes = max_bytes;
  return surface_mesh(a, nurbs::initial_nets(a, surface), depth, options);
}

}  // namespace cifs::ifs
