// SPDX-License-Identifier: MIT
// cifs benchmarks — SISL twins of cifs shapes and SISL's evaluation loops, shared by the benchmark
// executables. Licence: cifs code under MIT; with CIFS_HAVE_SISL it calls SISL (GNU AGPL v3), which
// bench/CMakeLists.txt links into benchmark executables only, never into a cifs library.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/surface.hpp"

#ifdef CIFS_HAVE_SISL
#include <sisl.h>
#endif

namespace cifs_bench {

namespace nurbs = cifs::nurbs;
using cifs::Points;

#ifdef CIFS_HAVE_SISL

[[noreturn]] inline void sisl_fail(const std::string& what) {
  std::fprintf(stderr, "cifs_bench: %s\n", what.c_str());
  std::abort();
}

inline void require_sisl_ok(int status, const char* routine) {
  if (status < 0) sisl_fail(std::string("SISL ") + routine + " returned status " + std::to_string(status));
}

struct SislCurveFree {
  void operator()(SISLCurve* c) const noexcept { freeCurve(c); }
};
struct SislSurfFree {
  void operator()(SISLSurf* s) const noexcept { freeSurf(s); }
};
using SislCurvePtr = std::unique_ptr<SISLCurve, SislCurveFree>;
using SislSurfPtr = std::unique_ptr<SISLSurf, SislSurfFree>;

/// SISL copy of a cifs curve. SISL counts the order (degree + 1), takes the same full knot vector
/// (n + order values; a clamped end is an order-fold knot in both libraries) and, for a rational
/// curve (ikind 2), homogeneous coefficients (w·x, w) — exactly the rows cifs stores. icopy = 1: SISL
/// copies both arrays. (newCurve may shift "superfluous" end knots inside the arrays it is given, so
/// it gets scratch copies, never cifs' own storage.)
inline SislCurvePtr to_sisl(const nurbs::Curve& c) {
  std::vector<double> knots = c.knots;
  Points coefficients = c.P;
  SISLCurve* s = newCurve(static_cast<int>(c.P.rows()), c.degree + 1, knots.data(), coefficients.data(),
                          c.rational ? 2 : 1, nurbs::dimension(c), 1);
  if (s == nullptr) sisl_fail("SISL newCurve failed");
  return SislCurvePtr(s);
}

/// SISL copy of a cifs surface with the parameter directions swapped. SISL stores coefficient
/// (i1, i2) at i2·in1 + i1 (first direction fastest), cifs stores (i, j) at i·nv + j (v fastest):
/// with SISL's first direction = cifs v and its second = cifs u the coefficient arrays are
/// byte-for-byte the same. Then s1506's output order (first-direction parameter fastest) is
/// evaluate_grid's row order a·#vs + b, and s1506 works like evaluate_grid: it builds the iso-curve
/// at each second-direction parameter (cifs u, once per grid row) and evaluates it along the first.
inline SislSurfPtr to_sisl(const nurbs::Surface& s) {
  std::vector<double> knots_v = s.knots[1], knots_u = s.knots[0];
  Points coefficients = s.P;
  SISLSurf* out = newSurf(static_cast<int>(s.count[1]), static_cast<int>(s.count[0]), s.degree[1] + 1,
                          s.degree[0] + 1, knots_v.data(), knots_u.data(), coefficients.data(),
                          s.rational ? 2 : 1, nurbs::dimension(s), 1);
  if (out == nullptr) sisl_fail("SISL newSurf failed");
  return SislSurfPtr(out);
}

/// Curve points one parameter at a time, the way SISL users evaluate a parameter sequence: the
/// `leftknot` interval index of one call is the hint of the next (s1219 checks it, then its
/// neighbours, before bisecting), so sorted parameters cost O(1) per search.
/// FromLeft: s1227 (left-continuous: at a knot it evaluates the piece that ends there) — the
/// routine the SISL manual pairs with increasing parameters; otherwise s1221 (right-continuous, the
/// cifs convention, and a little cheaper: no knot-multiplicity test). Positions agree either way on a
/// continuous curve; derivatives are not requested (ider = 0).
template <bool FromLeft>
inline int sisl_curve_points(SISLCurve* c, std::span<const double> us, double* out) {
  int left = 0, status = 0, worst = 0;
  const std::size_t dim = static_cast<std::size_t>(c->idim);
  for (std::size_t k = 0; k < us.size(); ++k) {
    if constexpr (FromLeft)
      s1227(c, 0, us[k], &left, out + k * dim, &status);
    else
      s1221(c, 0, us[k], &left, out + k * dim, &status);
    worst = std::min(worst, status);
  }
  return worst;
}

/// Surface grid one point at a time with s1424 (position only: ider1 = ider2 = 0; s1421 would also
/// compute both first derivatives and the normal, which is not the same job). The two left-knot
/// hints persist from point to point like s1227's. epar = (first, second) = (v, u), see to_sisl.
inline int sisl_grid_points(SISLSurf* s, std::span<const double> us, std::span<const double> vs,
                            double* out) {
  int left1 = 0, left2 = 0, status = 0, worst = 0;
  const std::size_t dim = static_cast<std::size_t>(s->idim);
  double epar[2];
  for (std::size_t a = 0; a < us.size(); ++a) {
    epar[1] = us[a];
    for (std::size_t b = 0; b < vs.size(); ++b) {
      epar[0] = vs[b];
      s1424(s, 0, 0, epar, &left1, &left2, out + (a * vs.size() + b) * dim, &status);
      worst = std::min(worst, status);
    }
  }
  return worst;
}

/// Surface grid with SISL's grid evaluator s1506 (ider = 0: positions; it pre-evaluates the
/// B-splines of each grid line with s1504, then s1505 multiplies out, iso-curve by iso-curve).
/// `normals` must hold dim·#us·#vs values (written only when ider ≥ 1).
inline int sisl_grid(SISLSurf* s, std::vector<double>& us, std::vector<double>& vs, double* out,
                     double* normals) {
  int status = 0;
  s1506(s, 0, static_cast<int>(vs.size()), vs.data(), static_cast<int>(us.size()), us.data(), out, normals,
        &status);
  return status;
}

inline constexpr const char* kSislContext = "libsisl 4.6.0 (Debian libsisl-dev, static)";
#else
inline constexpr const char* kSislContext = "not found: cifs only";
#endif

}  // namespace cifs_bench
