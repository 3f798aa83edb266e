// SPDX-License-Identifier: MIT
#include "cifs/ifs/affine_cifs.hpp"

#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <string>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"

namespace cifs::ifs {

std::vector<AffineMap> barnsley_fern() {
  // Barnsley, Fractals Everywhere (1988), table III.3; the same coefficients as Barnsley & Demko.
  return {{0.00, 0.00, 0.00, 0.16, 0.00, 0.00, 0.01},
          {0.85, 0.04, -0.04, 0.85, 0.00, 1.60, 0.85},
          {0.20, -0.26, 0.23, 0.22, 0.00, 1.60, 0.07},
          {-0.15, 0.28, 0.26, 0.24, 0.00, 0.44, 0.07}};
}

std::vector<AffineMap> sierpinski_triangle() {
  const double h = std::numbers::sqrt3 / 4;  // half the height of the unit equilateral triangle
  return {
      {0.5, 0, 0, 0.5, 0, 0, 1.0 / 3}, {0.5, 0, 0, 0.5, 0.5, 0, 1.0 / 3}, {0.5, 0, 0, 0.5, 0.25, h, 1.0 / 3}};
}

std::vector<AffineMap> koch_curve() {
  // Ratio ⅓; the middle pieces are rotated by ±60°: (cos 60°)/3 = 1/6, (sin 60°)/3 = √3/6.
  const double c = 1.0 / 6, s = std::numbers::sqrt3 / 6;
  return {{1.0 / 3, 0, 0, 1.0 / 3, 0, 0, 0.25},
          {c, -s, s, c, 1.0 / 3, 0, 0.25},
          {c, s, -s, c, 0.5, s, 0.25},
          {1.0 / 3, 0, 0, 1.0 / 3, 2.0 / 3, 0, 0.25}};
}

Point apply(const AffineMap& m, const Point& p) {
  Point q(2);
  q << m.a * p(0) + m.b * p(1) + m.e, m.c * p(0) + m.d * p(1) + m.f;
  return q;
}

Eigen::MatrixXd barycentric_matrix(const AffineMap& map, const Points& triangle) {
  if (triangle.rows() != 3 || triangle.cols() != 2)
    throw InvalidInput("the control triangle is " + std::to_string(triangle.rows()) + " by " +
                       std::to_string(triangle.cols()) + ", expected 3 by 2");
  if (!triangle.allFinite()) throw InvalidInput("the control triangle has a coordinate that is not finite");
  for (const double x : {map.a, map.b, map.c, map.d, map.e, map.f})
    if (!std::isfinite(x)) throw InvalidInput("an affine map has a coefficient that is not finite");
  Eigen::Matrix3d H, W;
  for (int i = 0; i < 3; ++i) {
    const Point corner = triangle.row(i);
    const Point image = apply(map, corner);
    H.row(i) << corner(0), corner(1), 1;
    W.row(i) << image(0), image(1), 1;
  }
  const double diam = diameter(triangle);
  if (!(std::abs(H.determinant()) > 1e-12 * diam * diam))
    throw InvalidInput(
        "the control triangle is degenerate (its corners are collinear); give three corners that span the "
        "plane");
  return W * H.inverse();
}

automata::Automaton affine_automaton(std::span<const AffineMap> maps, const Points& triangle) {
  if (maps.empty()) throw InvalidInput("an IFS needs at least one affine map, none is given");
  automata::Automaton a;
  const auto s = add_vertex(automata::State{.size = 3, .recurrent = true, .name = "triangle"}, a.graph);
  for (std::size_t i = 0; i < maps.size(); ++i)
    add_edge(s, s, automata::Transition{"w" + std::to_string(i), barycentric_matrix(maps[i], triangle)},
             a.graph);
  automata::Initial init;
  init.state = s;
  a.initial.push_back(init);
  return a;
}

namespace {

struct NamedIfs {
  std::string name;
  std::vector<AffineMap> (*maps)();
};

const std::vector<NamedIfs>& registry() {
  static const std::vector<NamedIfs> systems{
      {"fern", barnsley_fern}, {"sierpinski", sierpinski_triangle}, {"koch", koch_curve}};
  return systems;
}

}  // namespace

const std::vector<std::string>& ifs_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const NamedIfs& s : registry()) out.push_back(s.name);
    return out;
  }();
  return names;
}

std::vector<AffineMap> named_ifs(std::string_view name) {
  for (const NamedIfs& s : registry())
    if (s.name == name) return s.maps();
  std::string names;
  for (const std::string& n : ifs_names()) names += (names.empty() ? "" : ", ") + n;
  throw InvalidInput("unknown IFS \"" + std::string(name) + "\"; give one of " + names);
}

}  // namespace cifs::ifs
