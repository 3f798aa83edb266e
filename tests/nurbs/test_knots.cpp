// SPDX-License-Identifier: MIT
// Knot vectors, span search and basis functions against the Cox–de Boor definition.
#include "cifs/nurbs/knots.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "cifs/errors.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using namespace cifs::nurbs;
using namespace cifs_test;

namespace {

constexpr int kSeeds = 400;

Knots random_knot_vector(Rng& rng, int& d, int& n) {
  d = uniform_int(rng, 1, 10);
  n = d + 1 + uniform_int(rng, 0, 10);
  return random_knots(rng, d, n, coin(rng));
}

}  // namespace

TEST_CASE("basis functions: partition of unity, non-negative, equal to the Cox–de Boor definition",
          "[nurbs][knots]") {
  for (int seed = 0; seed < kSeeds; ++seed) {
    Rng rng(seed);
    int d = 0, n = 0;
    const Knots t = random_knot_vector(rng, d, n);
    INFO("seed " << seed << " degree " << d << " n " << n);
    double worst_sum = 0, worst_ref = 0, most_negative = 0;
    bool outside_support_zero = true;
    for (double u : probe_parameters(rng, t, d, 40)) {
      const int k = find_span(t, d, u);
      double N[kMaxDegree + 1];
      basis_functions(t, d, k, u, N);
      const RealVec R = ref_basis(t, d, u, at_end(t, d, u));
      double sum = 0;
      for (int j = 0; j <= d; ++j) {
        sum += N[j];
        most_negative = std::min(most_negative, N[j]);
        worst_ref =
            std::max(worst_ref, std::abs(N[j] - static_cast<double>(R[static_cast<std::size_t>(k - d + j)])));
      }
      for (int i = 0; i < n; ++i)
        if ((i < k - d || i > k) && R[static_cast<std::size_t>(i)] != 0) outside_support_zero = false;
      worst_sum = std::max(worst_sum, std::abs(sum - 1));
    }
    CHECK(most_negative == 0.0);
    CHECK(worst_sum <= 1e-14);
    CHECK(worst_ref <= 1e-14);
    CHECK(outside_support_zero);
  }
}

TEST_CASE("basis derivatives: Cox–de Boor derivative recursion and finite differences", "[nurbs][knots]") {
  for (int seed = 0; seed < kSeeds; ++seed) {
    Rng rng(1000 + seed);
    int d = 0, n = 0;
    const Knots t = random_knot_vector(rng, d, n);
    const int order = d + 2;
    INFO("seed " << seed << " degree " << d << " n " << n);
    double worst_ref = 0, worst_row0 = 0, worst_fd = 0, worst_high = 0;
    for (double u : probe_parameters(rng, t, d, 10)) {
      const int k = find_span(t, d, u);
      const Eigen::MatrixXd D = basis_derivatives(t, d, k, u, order);
      REQUIRE(D.rows() == order + 1);
      REQUIRE(D.cols() == d + 1);
      double N[kMaxDegree + 1];
      basis_functions(t, d, k, u, N);
      for (int j = 0; j <= d; ++j) worst_row0 = std::max(worst_row0, std::abs(D(0, j) - N[j]));
      for (int r = 1; r <= order; ++r) {
        const RealVec R = ref_basis(t, d, u, at_end(t, d, u), r);
        Real mag = 0;
        for (Real x : R) mag += std::abs(x);
        for (int j = 0; j <= d; ++j) {
          const double e = std::abs(D(r, j) - static_cast<double>(R[static_cast<std::size_t>(k - d + j)]));
          if (r > d)
            worst_high = std::max(worst_high, std::abs(D(r, j)));
          else
            worst_ref = std::max(worst_ref, e / static_cast<double>(mag));
        }
      }
    }
    // Finite differences inside each span, away from its knots.
    for (int k = d; k < n; ++k) {
      const double a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>(k + 1)];
      if (!(a < b)) continue;
      for (int rep = 0; rep < 3; ++rep) {
        const double u = uniform(rng, a + 0.3 * (b - a), b - 0.3 * (b - a));
        const double h = 1e-3 * (b - a);
        const Eigen::MatrixXd D = basis_derivatives(t, d, k, u, d);
        for (int r = 1; r <= d; ++r) {
          auto f = [&](double x) -> Points { return basis_derivatives(t, d, k, x, r - 1).row(r - 1); };
          const Points fd = central_difference(f, u, h);
          const double mag = D.row(r).cwiseAbs().sum();
          worst_fd = std::max(worst_fd, (fd - D.row(r)).cwiseAbs().maxCoeff() / mag);
        }
      }
    }
    CHECK(worst_row0 <= 1e-15);
    CHECK(worst_ref <= 1e-11);  // relative to Σ|N^(r)|; A2.3 cancels up to ~3e-12 at order 6
    CHECK(worst_high == 0.0);
    CHECK(worst_fd <= 1e-6);
  }
}

TEST_CASE("span search: domain ends, every knot, one ulp either side, hints", "[nurbs][knots]") {
  for (int seed = 0; seed < kSeeds; ++seed) {
    Rng rng(2000 + seed);
    int d = 0, n = 0;
    const Knots t = random_knot_vector(rng, d, n);
    INFO("seed " << seed << " degree " << d << " n " << n);
    int wrong = 0, wrong_hint = 0;
    for (double u : probe_parameters(rng, t, d, 20)) {
      const int k = find_span(t, d, u);
      if (k != definition_span(t, d, u)) ++wrong;
      for (int hint = -2; hint <= n + 2; ++hint)
        if (find_span(t, d, u, hint) != k) ++wrong_hint;
    }
    CHECK(wrong == 0);
    CHECK(wrong_hint == 0);
    // The domain end belongs to the last non-empty span, which ends at t_n.
    const int last = find_span(t, d, t[static_cast<std::size_t>(n)]);
    CHECK(t[static_cast<std::size_t>(last)] < t[static_cast<std::size_t>(last + 1)]);
    CHECK(t[static_cast<std::size_t>(last + 1)] >= t[static_cast<std::size_t>(n)]);
    CHECK(last <= n - 1);
  }
}

TEST_CASE("span search on long knot vectors: every length of the bisection, any hint", "[nurbs][knots]") {
  // The bisection runs a fixed ⌈log₂⌉ steps whatever the data; lengths 1..300 cover every step count
  // up to 9, and its answer must stay the definition's (repeated knots, both ends, one ulp around).
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(2500 + seed);
    const int d = uniform_int(rng, 1, 6);
    const int n = d + 1 + seed;
    const Knots t = random_knots(rng, d, n, coin(rng));
    INFO("seed " << seed << " degree " << d << " n " << n);
    int wrong = 0, wrong_hint = 0;
    std::vector<double> us = probe_parameters(rng, t, d, 50);
    for (double u : us) {
      const int k = find_span(t, d, u);
      if (k != definition_span(t, d, u)) ++wrong;
      const int hint = uniform_int(rng, d - 1, n);  // some invalid: d − 1 and n
      if (find_span(t, d, u, hint) != k || find_span(t, d, u, k) != k) ++wrong_hint;
    }
    CHECK(wrong == 0);
    CHECK(wrong_hint == 0);
  }
}

TEST_CASE("span search on a clamped vector with a double interior knot", "[nurbs][knots]") {
  const Knots t{0, 0, 0, 0, 1, 2, 2, 3, 3, 3, 3};  // degree 3, n = 7
  CHECK(find_span(t, 3, 0.0) == 3);
  CHECK(find_span(t, 3, std::nextafter(1.0, 0.0)) == 3);
  CHECK(find_span(t, 3, 1.0) == 4);
  CHECK(find_span(t, 3, std::nextafter(2.0, 0.0)) == 4);
  CHECK(find_span(t, 3, 2.0) == 6);
  CHECK(find_span(t, 3, 3.0) == 6);
  CHECK(find_span(t, 3, std::nextafter(3.0, 0.0)) == 6);
}

TEST_CASE("multiplicity, breakpoints, domain and control_count against their definitions", "[nurbs][knots]") {
  for (int seed = 0; seed < 100; ++seed) {
    Rng rng(3000 + seed);
    int d = 0, n = 0;
    const Knots t = random_knot_vector(rng, d, n);
    INFO("seed " << seed);
    CHECK(control_count(t, d) == n);
    const Domain dom = domain(t, d);
    CHECK(dom.start == t[static_cast<std::size_t>(d)]);
    CHECK(dom.end == t[static_cast<std::size_t>(n)]);
    for (double x : t) CHECK(multiplicity(t, x) == std::count(t.begin(), t.end(), x));
    CHECK(multiplicity(t, t.front() - 1) == 0);
    std::vector<double> expected;
    for (double x : t)
      if (x >= dom.start && x <= dom.end && (expected.empty() || expected.back() != x)) expected.push_back(x);
    CHECK(breakpoints(t, d) == expected);
  }
}

TEST_CASE("blossom weights: diagonal gives the basis, consecutive knots give unit vectors, symmetry",
          "[nurbs][knots]") {
  for (int seed = 0; seed < kSeeds; ++seed) {
    Rng rng(4000 + seed);
    int d = 0, n = 0;
    const Knots t = random_knot_vector(rng, d, n);
    INFO("seed " << seed << " degree " << d << " n " << n);
    double worst_diag = 0, worst_dual = 0, worst_sym = 0, worst_sum = 0;
    for (int k = d; k < n; ++k) {
      if (!(t[static_cast<std::size_t>(k)] < t[static_cast<std::size_t>(k + 1)])) continue;
      double W[kMaxDegree + 1], N[kMaxDegree + 1];
      const double u = uniform(rng, t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>(k + 1)]);
      std::vector<double> args(static_cast<std::size_t>(d), u);
      blossom_weights(t, d, k, args, W);
      basis_functions(t, d, k, u, N);
      for (int j = 0; j <= d; ++j) worst_diag = std::max(worst_diag, std::abs(W[j] - N[j]));
      // Dual functionals: the arguments t_{i+1..i+d} select P_i, for each i = k−d..k.
      for (int i = k - d; i <= k; ++i) {
        args.assign(t.begin() + i + 1, t.begin() + i + d + 1);
        blossom_weights(t, d, k, args, W);
        for (int j = 0; j <= d; ++j) worst_dual = std::max(worst_dual, std::abs(W[j] - (j == i - (k - d))));
      }
      // Symmetric (to the last bit: with repeated values too) and affine in random arguments near the
      // span.
      const double a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>(k + 1)];
      for (auto& x : args) x = coin(rng, 0.2) ? args[0] : uniform(rng, a - (b - a), b + (b - a));
      double W2[kMaxDegree + 1];
      blossom_weights(t, d, k, args, W);
      std::shuffle(args.begin(), args.end(), rng);
      blossom_weights(t, d, k, args, W2);
      double sum = 0, mag = 0;
      for (int j = 0; j <= d; ++j) mag += std::abs(W[j]);
      for (int j = 0; j <= d; ++j) {
        worst_sym = std::max(worst_sym, std::abs(W[j] - W2[j]) / mag);
        sum += W[j];
      }
      worst_sum = std::max(worst_sum, std::abs(sum - 1) / mag);
    }
    CHECK(worst_diag <= 1e-14);
    CHECK(worst_dual <= 1e-12);
    CHECK(worst_sym == 0.0);  // the arguments are sorted by (distance, value) first: exactly symmetric
    CHECK(worst_sum <= 1e-13);
  }
}

TEST_CASE("periodic knots follow their formula, repeat with the period, keep the seam", "[nurbs][knots]") {
  for (int seed = 0; seed < 300; ++seed) {
    Rng rng(5000 + seed);
    const int d = uniform_int(rng, 1, 10);
    const Knots b = random_breaks(rng, d, 2, 12);
    const int m = static_cast<int>(b.size()) - 1;
    INFO("seed " << seed << " degree " << d << " m " << m);
    const Knots t = periodic_knots(b, d);
    REQUIRE(t.size() == static_cast<std::size_t>(m + 2 * d + 1));
    CHECK(t == ref_periodic_knots(b, d));
    const Knots naive = naive_periodic_knots(b, d);
    const double T = b.back() - b.front();
    double ulps = 0, period = 0;
    for (std::size_t j = 0; j < t.size(); ++j)
      ulps = std::max(ulps, std::abs(t[j] - naive[j]) / (kEps * (std::abs(naive[j]) + T)));
    for (std::size_t j = 0; j + static_cast<std::size_t>(m) < t.size(); ++j)
      period = std::max(
          period, std::abs(t[j + static_cast<std::size_t>(m)] - t[j] - T) / (kEps * (std::abs(t[j]) + T)));
    CHECK(ulps <= 8);
    CHECK(period <= 8);
    // The period's knots are the breakpoints, bit for bit.
    CHECK(Knots(t.begin() + d, t.begin() + d + m + 1) == b);
    const Domain dom = domain(t, d);
    CHECK(dom.start == b.front());
    CHECK(dom.end == b.back());
    CHECK(std::is_sorted(t.begin(), t.end()));
    // Seam multiplicity: copies of b_0 plus copies of b_m inside the period (one value mod T).
    const auto seam =
        std::count(b.begin(), b.end() - 1, b.front()) + std::count(b.begin() + 1, b.end() - 1, b.back());
    if (m >= d) {
      CHECK(std::count(t.begin(), t.end(), b.front()) == seam);
      CHECK(std::count(t.begin(), t.end(), b.back()) == seam);
    }
  }
}

TEST_CASE("validate_degree and validate_knots name the problem and its place", "[nurbs][knots]") {
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(validate_degree(0), Contains("degree 0"));
  CHECK_THROWS_WITH(validate_degree(kMaxDegree + 1), Contains("degree 65"));
  CHECK_THROWS_WITH(validate_degree(-3, "knots[1]"), Contains("knots[1]"));
  CHECK_NOTHROW(validate_degree(1));
  CHECK_NOTHROW(validate_degree(kMaxDegree));
  const Knots ok{0, 0, 0, 1, 2, 2, 2};
  CHECK_NOTHROW(validate_knots(ok, 2, 4));
  // Degree.
  CHECK_THROWS_AS(validate_knots(ok, 0, 4), InvalidInput);
  // Too few control points for the degree.
  CHECK_THROWS_WITH(validate_knots(Knots{0, 0, 1, 1}, 2, 1), Contains("too few"));
  // Wrong size.
  CHECK_THROWS_WITH(validate_knots(ok, 2, 5), Contains("7 knots given"));
  // Not finite, at the right index.
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), HUGE_VAL, -HUGE_VAL}) {
    Knots t = ok;
    t[3] = bad;
    CHECK_THROWS_WITH(validate_knots(t, 2, 4), Contains("knots[3]") && Contains("not finite"));
  }
  // Decreasing.
  CHECK_THROWS_WITH(validate_knots(Knots{0, 0, 0, 1, 0.5, 2, 2}, 2, 4),
                    Contains("knots[4]") && Contains("less"));
  // Multiplicity above degree + 1: reported where the run gets too long.
  CHECK_THROWS_WITH(validate_knots(Knots{0, 0, 0, 0, 1, 2, 2, 2}, 2, 5),
                    Contains("knots[3]") && Contains("multiplicity 4"));
  CHECK_THROWS_WITH(validate_knots(Knots{0, 0, 0, 1, 1, 1, 1, 2, 2, 2}, 2, 7), Contains("knots[6]"));
  // Empty domain.
  CHECK_THROWS_WITH(validate_knots(Knots{0, 1, 2, 2, 3, 4}, 2, 3), Contains("empty domain"));
  // The place prefix.
  CHECK_THROWS_WITH(validate_knots(Knots{0, 0, 0, 1, 0.5, 2, 2}, 2, 4, "shape.json: knots"),
                    Contains("shape.json: knots[4]"));
  // Multiplicity d + 1 inside is allowed (a break in the curve), d + 2 is not.
  CHECK_NOTHROW(validate_knots(Knots{0, 0, 1, 1, 2, 2}, 1, 4));
}

TEST_CASE("validate_span_query: any degree on any knot vector where the basis is defined", "[nurbs][knots]") {
  // Degree 1 on a clamped quadratic vector (a triple knot): defined, and refused by validate_knots.
  const Knots t{0, 0, 0, 0.5, 1, 1, 1};
  CHECK_THROWS_AS(validate_knots(t, 1, control_count(t, 1)), InvalidInput);
  CHECK_NOTHROW(validate_span_query(t, 1, 2));
  CHECK_NOTHROW(validate_span_query(t, 0, 3));
  for (int p = 0; p <= 2; ++p)
    for (int span = p; span + p + 1 < static_cast<int>(t.size()); ++span) {
      if (!(t[static_cast<std::size_t>(span)] < t[static_cast<std::size_t>(span) + 1])) {
        CHECK_THROWS_WITH(validate_span_query(t, p, span), Catch::Matchers::Contains("is empty"));
        continue;
      }
      for (double u : {t[static_cast<std::size_t>(span)],
                       0.5 * (t[static_cast<std::size_t>(span)] + t[static_cast<std::size_t>(span) + 1])}) {
        std::vector<double> N(static_cast<std::size_t>(p) + 1);
        basis_functions(t, p, span, u, N.data());
        const RealVec ref = ref_basis(t, p, u, false);
        for (int j = 0; j <= p; ++j)
          CHECK(std::abs(N[static_cast<std::size_t>(j)] -
                         static_cast<double>(ref[static_cast<std::size_t>(span - p + j)])) <= 1e-15);
      }
    }
  CHECK_THROWS_WITH(validate_span_query(t, 1, 0), Catch::Matchers::Contains("span 0 is outside 1 … 5"));
  CHECK_THROWS_WITH(validate_span_query(t, 65, 3), Catch::Matchers::Contains("degree 65 is outside [0, 64]"));
  CHECK_THROWS_WITH(validate_span_query(Knots{0, 1, 0.5, 2}, 1, 1), Catch::Matchers::Contains("knots[2]"));
}
