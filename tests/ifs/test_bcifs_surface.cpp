// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs_surface.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/mesh.hpp"

using namespace cifs;
using namespace cifs::ifs;

namespace {

/// Clamped knots of degree d with n control points, interior knots at `interior`.
nurbs::Knots clamped(int d, std::vector<double> interior) {
  nurbs::Knots U(static_cast<std::size_t>(d + 1), 0.0);
  const double last = interior.empty() ? 1.0 : interior.back() + 1.0;
  U.insert(U.end(), interior.begin(), interior.end());
  U.insert(U.end(), static_cast<std::size_t>(d + 1), last);
  return U;
}

nurbs::Knots uniform(int d, int n) {
  nurbs::Knots U(static_cast<std::size_t>(n + d + 1));
  for (std::size_t i = 0; i < U.size(); ++i) U[i] = static_cast<double>(i);
  return U;
}

/// A wavy grid of control points, (nu·nv) by 3, row i·nv + j.
nurbs::Surface make(std::array<int, 2> degree, std::array<nurbs::Knots, 2> knots, bool rational = false) {
  const auto count = [&](std::size_t d) {
    return static_cast<Eigen::Index>(knots[d].size()) - degree[d] - 1;
  };
  const Eigen::Index nu = count(0), nv = count(1);
  Points P(nu * nv, 3);
  Eigen::VectorXd w;
  if (rational) w.resize(nu * nv);
  for (Eigen::Index i = 0; i < nu; ++i)
    for (Eigen::Index j = 0; j < nv; ++j) {
      const double x = static_cast<double>(i), y = static_cast<double>(j);
      P.row(i * nv + j) << x + 0.2 * std::sin(1.3 * y), y + 0.1 * std::cos(0.7 * x),
          std::sin(0.9 * x) * std::cos(1.1 * y);
      if (rational) w(i * nv + j) = 1.0 + 0.4 * std::sin(2.1 * x + 0.7 * y);
    }
  return nurbs::make_surface(degree, knots, {nu, nv}, P, w);
}

double max_residual(const Bcifs& sys) {
  double worst = 0;
  for (const auto& [name, r] : constraint_residuals(sys)) worst = std::max(worst, r);
  return worst;
}

struct Sample {
  std::string name;
  nurbs::Surface surface;
};

std::vector<Sample> samples() {
  std::vector<Sample> out;
  out.push_back({"uniform bicubic", make({3, 3}, {uniform(3, 6), uniform(3, 6)})});
  out.push_back({"uniform biquadratic", make({2, 2}, {uniform(2, 5), uniform(2, 5)})});
  out.push_back({"non-uniform bicubic", make({3, 3}, {clamped(3, {0.3, 1.1, 1.5}), clamped(3, {0.7, 2.6})})});
  out.push_back({"mixed degrees", make({2, 3}, {clamped(2, {0.4, 1.7}), clamped(3, {1, 1, 2.5})})});
  out.push_back({"rational", make({2, 2}, {clamped(2, {0.5, 1.25}), uniform(2, 5)}, true)});
  return out;
}

}  // namespace

TEST_CASE("surface_bcifs: the NURBS matrices are admissible", "[ifs][bcifs][surface]") {
  for (const auto& [name, s] : samples()) {
    INFO(name);
    const auto ta = automata::tensor_automaton(s);
    const Bcifs sys = surface_bcifs(ta);
    CHECK(max_residual(sys) <= 1e-14);
    const auto t0 = std::chrono::steady_clock::now();
    const AdmissibleSpace space = admissible_space(sys);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    WARN(name << ": cells " << boost::num_vertices(sys.automaton.graph) << ", unknowns "
              << space.unknowns.size() << ", free " << space.free.size() << ", components "
              << space.components << ", " << ms << " ms");
  }
}
