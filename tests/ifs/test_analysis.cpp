// SPDX-License-Identifier: MIT
#include "cifs/ifs/analysis.hpp"

#include <Eigen/SVD>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/nurbs/curve.hpp"
#include "ifs/helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using namespace ifs_test;

namespace {

Eigen::Matrix3d chaikin_G() {
  Eigen::Matrix3d G;
  G << 0.75, 0.25, 0,  //
      0.25, 0.75, 0,   //
      0, 0.75, 0.25;
  return G;
}

/// One state of 3 points whose first map is the identity: nets never shrink along 0^k.
Automaton identity_automaton() {
  Automaton a;
  const StateId s = add_state(a, 3, "loop");
  add_transition(a, s, s, Eigen::MatrixXd::Identity(3, 3), "I");
  add_transition(a, s, s, chaikin_G(), "G");
  add_initial(a, s);
  return a;
}

}  // namespace

TEST_CASE("delta and diameter", "[ifs]") {
  CHECK(delta(chaikin_G()) == 0.75);
  CHECK(delta(Eigen::MatrixXd::Identity(4, 4)) == 1);
  CHECK(delta(Eigen::MatrixXd::Constant(3, 2, 0.5)) == 0);
  Points P(3, 2);
  P << 0, 0, 3, 4, 1, 1;
  CHECK(diameter(P) == 5);
  // diam(M·N) ≤ δ(M)·diam(N) for random signed maps.
  std::mt19937_64 rng(6);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::MatrixXd M = random_contraction(4, 3, 0.9, rng);
    const Points N = random_points(3, 3, rng);
    CHECK(diameter(M * N) <= delta(M) * diameter(N) * (1 + 1e-12));
  }
}

TEST_CASE("delta is the largest ½‖M_i − M_j‖₁ summed as Eigen sums a vector, bit for bit, every shape",
          "[ifs]") {
  // delta takes the rows four entries at a time with AVX where the CPU has it (the 16 × 16 products of a
  // surface's contractivity check): the same doubles as Eigen's sum of each difference of rows, on entries
  // of scales from 1e-8 to 1e8, where another order of the sums would round otherwise.
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(-1, 1), scale(-8, 8);
  int differs_from_sequential = 0;
  // Rows in blocks of 4 and not (the AVX kernel reads four rows at a time, the last block masked); one
  // matrix in eight with a NaN entry, whose pairs δ leaves out as std::max does.
  for (const Eigen::Index rows : {1, 2, 3, 4, 5, 7, 8, 12, 16}) {
    for (Eigen::Index cols = 1; cols <= 20; ++cols) {
      for (int trial = 0; trial < 4; ++trial) {
        Eigen::MatrixXd M(rows, cols);
        for (Eigen::Index i = 0; i < M.size(); ++i) M(i) = unit(rng) * std::pow(10.0, scale(rng));
        if (rng() % 8 == 0) M(static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(M.size()))) = NAN;
        double expected = 0, sequential = 0;
        for (Eigen::Index i = 0; i < rows; ++i)
          for (Eigen::Index j = i + 1; j < rows; ++j) {
            const Eigen::RowVectorXd d = M.row(i) - M.row(j);
            expected = std::max(expected, d.cwiseAbs().sum());
            double s = 0;
            for (Eigen::Index k = 0; k < cols; ++k) s += std::abs(d(k));
            sequential = std::max(sequential, s);
          }
        INFO(rows << " × " << cols);
        CHECK(delta(M) == expected / 2);
        differs_from_sequential += expected != sequential ? 1 : 0;
      }
    }
  }
  CHECK(differs_from_sequential > 0);  // the order matters on these entries: the test can tell
}

TEST_CASE("a walk's child nets are Eigen's products, bit for bit, every shape below 48", "[ifs]") {
  // The walks (for_each_leaf, the meshes, the attractors) make each child net by their own kernel (AVX
  // where the CPU has it), in the order of Eigen's product, which is not one order (its blocked product sums
  // two columns of a net of 2 or 3 in two accumulators): nets of 1 to 4 columns, maps of 1 to 47 rows and
  // columns, entries of scales from 1e-8 to 1e8, where another order rounds otherwise. Two states: the root
  // of n points, its child of r points (an r × n map, then an r × r loop: depth 2 too).
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> unit(-1, 1), scale(-8, 8);
  const auto random = [&](Eigen::Index rows, Eigen::Index cols) {
    Eigen::MatrixXd M(rows, cols);
    for (Eigen::Index i = 0; i < M.size(); ++i) M(i) = unit(rng) * std::pow(10.0, scale(rng));
    return M;
  };
  int differs_from_sequential = 0;
  for (Eigen::Index n = 1; n < 48; n += n < 20 ? 1 : 9)
    for (const Eigen::Index r : {Eigen::Index{1}, Eigen::Index{3}, Eigen::Index{4}, Eigen::Index{9}, n,
                                 Eigen::Index{16}, Eigen::Index{47}})
      for (Eigen::Index C = 1; C <= 4; ++C) {
        Automaton a;
        const StateId root = add_state(a, static_cast<int>(n), "root");
        const StateId child = add_state(a, static_cast<int>(r), "child");
        Eigen::MatrixXd M = random(r, n), L = random(r, r);
        for (Eigen::MatrixXd* X : {&M, &L})  // rows that sum to 1 (to rounding), as validate asks
          for (int twice = 0; twice < 2; ++twice)
            X->col(X->cols() - 1) += Eigen::VectorXd::Ones(r) - X->rowwise().sum();
        add_transition(a, root, child, M, "M");
        add_transition(a, child, child, L, "L");
        add_initial(a, root);
        const Points N = random(n, C);
        const Points first = M * N, second = L * first;  // Eigen's
        std::vector<Points> leaves;
        for_each_leaf(a, std::span(&N, 1), 2, [&](const Leaf& leaf) { leaves.push_back(leaf.net); });
        INFO(r << " × " << n << " by " << n << " × " << C);
        REQUIRE(leaves.size() == 1);
        CHECK(std::memcmp(leaves[0].data(), second.data(), sizeof(double) * second.size()) == 0);
        for (Eigen::Index i = 0; i < r; ++i)
          for (Eigen::Index c = 0; c < C; ++c) {
            double sum = 0;
            for (Eigen::Index k = 0; k < n; ++k) sum += M(i, k) * N(k, c);
            differs_from_sequential += sum != first(i, c) ? 1 : 0;
          }
      }
  CHECK(differs_from_sequential > 0);  // the order matters on these entries: the test can tell
}

TEST_CASE("contraction's bounded scans: m and δ of every path's full product, bit for bit", "[ifs]") {
  // Scans of 4 steps and more skip subtrees by the bounds of their suffixes, and leaves by δ(M)·δ(parent)
  // (contractivity only): perturbed systems of a cubic B-spline (4 × 4 matrices, two children per cell),
  // contractive at m ≥ 4 or refused at 8, against the largest δ of every path's product made by Eigen from
  // the identity; with A tracked (bound on: no leaf skipped) the same δ.
  Points polygon(8, 2);
  polygon << 0, 0, 1, 2, 2, -1, 3, 1, 4, 0, 5, 2, 6, -1, 7, 0;
  const Bcifs system = curve_bcifs(nurbs::uniform_bspline(polygon, 3, false), {.free_vertices = true});
  const AdmissibleSpace space = admissible_space(system);
  const auto brute = [](const Automaton& a, int length) {
    double worst = 0;
    for (const StateId s : reachable_states(a)) {
      std::vector<Eigen::MatrixXd> level{Eigen::MatrixXd::Identity(a.graph[s].size, a.graph[s].size)};
      std::vector<StateId> at{s};
      for (int k = 0; k < length; ++k) {
        std::vector<Eigen::MatrixXd> next;
        std::vector<StateId> next_at;
        for (std::size_t i = 0; i < level.size(); ++i)
          for (auto [b, e] = out_edges(at[i], a.graph); b != e; ++b) {
            next.push_back((a.graph[*b].matrix * level[i]).eval());
            next_at.push_back(target(*b, a.graph));
          }
        level = std::move(next);
        at = std::move(next_at);
      }
      for (const Eigen::MatrixXd& P : level) worst = std::max(worst, delta(P));
    }
    return worst;
  };
  int long_witness = 0, refused = 0;
  for (int step = 1; step <= 16 && (long_witness < 3 || refused < 2); ++step)
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      PerturbOptions o;
      o.amplitude = 0.1 * step;
      o.seed = seed;
      o.check = false;
      const Automaton a = perturb(system, space, o).system.automaton;
      INFO("amplitude " << o.amplitude << ", seed " << seed);
      try {
        const Contraction c = contraction(a, {.bound = false});
        if (c.m < 4) continue;
        ++long_witness;
        CHECK(c.delta == brute(a, c.m));
        CHECK(brute(a, c.m - 1) >= 1);  // m is the shortest length
        CHECK(contraction(a).delta == c.delta);
      } catch (const NotContractive& e) {
        ++refused;
        CHECK(e.delta == brute(a, 8));
      }
    }
  CHECK(long_witness >= 1);
  CHECK(refused >= 1);
}

TEST_CASE("contraction's δ is the largest δ of every path's full product, bit for bit", "[ifs]") {
  // The scans make their 4k × 4k products with AVX where the CPU has it: the same doubles as Eigen's
  // products. One state, three transitions of random rows summing to 1 (not contractive: the last length is
  // scanned in full and its δ is the refusal's), states of 4 and 16 points.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-0.8, 1.0);
  for (const int n : {4, 16}) {
    Automaton a;
    const StateId s = add_state(a, n, "s");
    for (int t = 0; t < 3; ++t) {
      Eigen::MatrixXd M(n, n);
      for (Eigen::Index i = 0; i < M.size(); ++i) M(i) = u(rng);
      M.col(n - 1) += Eigen::VectorXd::Ones(n) - M.rowwise().sum();  // rows sum to 1 (to rounding)
      add_transition(a, s, s, M, std::to_string(t));
    }
    add_initial(a, s);
    for (const int length : {2, 3}) {
      double brute = 0;  // every path's product from the identity, by Eigen
      for (int w = 0; w < (1 << (2 * length)); ++w) {
        Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n);
        bool valid = true;
        for (int k = 0; k < length; ++k) {
          const int child = (w >> (2 * k)) & 3;
          valid = valid && child < 3;
          if (valid) P = (a.graph[*std::next(out_edges(s, a.graph).first, child)].matrix * P).eval();
        }
        if (valid) brute = std::max(brute, delta(P));
      }
      INFO(n << " points, length " << length);
      try {
        (void)contraction(a, {.max_length = length});
        FAIL("contractive");
      } catch (const NotContractive& e) {
        CHECK(e.delta == brute);
      }
    }
  }
}

TEST_CASE("nets_diameter near the range of a double", "[ifs][reliability]") {
  // Coordinates of 1e200 square to infinity: the extent 2e200 was reported as inf.
  Points N(3, 2);
  N << 1e200, 0, -1e200, 0, 0, 1e199;
  const std::vector<Points> nets{N};
  CHECK(nets_diameter(nets) == Approx(2e200).epsilon(1e-15));
  // An extent above the largest double is refused: every tolerance relative to it was inf or nan.
  Points far(2, 1);
  far << 1e308, -1.7e308;
  CHECK_THROWS_WITH(
      nets_diameter(std::vector<Points>{far}),
      "the control points span more than a double holds (coordinates up to 1.7e+308); scale the "
      "shape down");
}

TEST_CASE("Contractivity: Chaikin, degree 6 and a refused system", "[ifs]") {
  const Automaton chaikin = uniform_automaton(2);
  const Contraction c = contraction(chaikin);
  CHECK(c.m == 1);
  CHECK(c.delta == Approx(0.75).epsilon(1e-14));
  CHECK(c.A == Approx(1).epsilon(1e-14));
  // The bound factor of m = 1 is 4; longer blocks tighten it (δ_2 = 7/16 gives 16/9, …) until
  // the gain falls below 5%, at k = 6: check ρ_6 against the 64 products of length 6.
  ContractionOptions plain;
  plain.tighten = false;
  CHECK(contraction(chaikin, plain).radius == Approx(4).epsilon(1e-12));
  CHECK(contraction(chaikin, plain).radius_length == 1);
  CHECK(c.radius_length == 6);
  Eigen::MatrixXd Gm = chaikin_G(), Dm = Gm.rowwise().reverse().colwise().reverse();
  double delta6 = 0;
  for (int w = 0; w < 64; ++w) {
    Eigen::MatrixXd P = Eigen::MatrixXd::Identity(3, 3);
    for (int k = 0; k < 6; ++k) P = (((w >> k) & 1 ? Dm : Gm) * P).eval();
    delta6 = std::max(delta6, delta(P));
  }
  CHECK(c.radius == Approx(1 / (1 - delta6)).epsilon(1e-12));
  CHECK(c.radius < 1.04);
  for (int d = 1; d <= 6; ++d) {
    const Contraction cd = contraction(uniform_automaton(d));
    INFO("degree " << d << ": m " << cd.m << " delta " << cd.delta);
    CHECK(cd.delta < 1);
    CHECK(cd.A == Approx(1));
    CHECK(cd.radius < 1.2);  // degree 6: 64 for m = 1
  }
  const Automaton bad = identity_automaton();
  CHECK_THROWS_WITH(contraction(bad),
                    Catch::StartsWith("not contractive: the 8-step products from state 0 (loop) "
                                      "do not shrink nets (δ = 1 along the path 0 0 0 0 0 0 0 0"));
  ContractionOptions three;
  three.max_length = 3;
  CHECK_THROWS_WITH(contraction(bad, three), Catch::Contains("the 3-step products"));
  ToleranceOptions options;
  CHECK_THROWS_WITH(for_each_leaf_to_tolerance(bad, std::vector<Points>{Points::Zero(3, 2)}, options,
                                               [](const ToleranceLeaf&) {}),
                    Catch::Contains("not contractive"));
}

TEST_CASE("Fixed points of words: Chaikin G^inf, D^inf, (GD)^inf against Cox-de Boor", "[ifs]") {
  std::mt19937_64 rng(7);
  const Automaton a = uniform_automaton(2);
  const Points P = random_points(3, 2, rng);
  const auto point = [&](std::vector<int> word) { return Eigen::RowVectorXd(fixed_point(a, 0, word) * P); };
  const double tol = 1e-12 * scale_of(P);
  // G^∞ = (P0 + P1)/2, the start of the segment; D^∞ = (P1 + P2)/2, its end.
  CHECK((point({0}) - (P.row(0) + P.row(1)) / 2).cwiseAbs().maxCoeff() <= tol);
  CHECK((point({0}) - uniform_reference(P, 2, 0, 0)).cwiseAbs().maxCoeff() <= tol);
  CHECK((point({1}) - uniform_reference(P, 2, 0, 1)).cwiseAbs().maxCoeff() <= tol);
  // Binary 0.0101… = 1/3, 0.1010… = 2/3, 0.001001… = 1/7.
  CHECK((point({0, 1}) - uniform_reference(P, 2, 0, 1.0L / 3)).cwiseAbs().maxCoeff() <= tol);
  CHECK((point({1, 0}) - uniform_reference(P, 2, 0, 2.0L / 3)).cwiseAbs().maxCoeff() <= tol);
  CHECK((point({0, 0, 1}) - uniform_reference(P, 2, 0, 1.0L / 7)).cwiseAbs().maxCoeff() <= tol);
  CHECK(fixed_point(a, 0, std::vector<int>{0}).sum() == Approx(1).epsilon(1e-15));

  const Automaton q = quadratic_automaton(0.5, 2, 3);
  CHECK_THROWS_WITH(fixed_point(q, 0, std::vector<int>{0}),
                    Catch::Contains("ends at state 1 (G), not where it started"));
  CHECK_THROWS_WITH(fixed_point(q, 0, std::vector<int>{2}), Catch::Contains("child index 2 at position 0"));
  CHECK_THROWS_WITH(fixed_point(identity_automaton(), 0, std::vector<int>{0}),
                    Catch::Contains("1 is not a simple eigenvalue"));
  // A non-uniform word: (G D)^∞ from the G state is not a cycle, (G)^∞ is: the start of the piece.
  const Points Q = random_points(3, 3, rng);
  const Eigen::RowVectorXd start =
      fixed_point(q, 1, std::vector<int>{0}) * (q.graph[edge(0, 1, q.graph).first].matrix * Q);
  CHECK((start - quadratic_reference(Q, 0.5, 2, 3, 0)).cwiseAbs().maxCoeff() <= 1e-12 * scale_of(Q));
}

TEST_CASE("a fixed point is refused exactly when the SVD finds K = I − P + 1·1ᵀ singular", "[ifs]") {
  // fixed_point skips the SVD when a bound from the LU shows K well conditioned: the verdicts must be the
  // SVD's (σ_min ≤ 1e-12·n·σ_max: refused), here computed by the test, on products whose second
  // eigenvalue 1 − ε comes near 1 — ε from 0.1 (the bound suffices) through 1e-8 (it does not: the SVD
  // accepts) to 1e-13 and 0 (the SVD refuses) —, for 2 points and 16 (a random stochastic block beside).
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(0, 1);
  int accepted = 0, refused = 0;
  for (const int n : {2, 16}) {
    for (int e = 1; e <= 17; ++e) {
      const double eps = e == 17 ? 0 : std::pow(10.0, -e);
      Eigen::MatrixXd P = Eigen::MatrixXd::Zero(n, n);
      P(0, 0) = 1;  // eigenvalues 1 and 1 − ε from the first two rows, the block's (|λ| < 1) besides
      P(1, 0) = eps;
      P(1, 1) = 1 - eps;
      for (int i = 2; i < n; ++i) {
        for (int j = 0; j < n; ++j) P(i, j) = u(rng);
        P.row(i) /= P.row(i).sum();
      }
      Automaton a;
      const StateId s = add_state(a, n, "s");
      add_transition(a, s, s, P, "P");
      add_initial(a, s);
      const Eigen::MatrixXd K = Eigen::MatrixXd::Identity(n, n) - P + Eigen::MatrixXd::Ones(n, n);
      const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(K).singularValues();
      const bool singular = !(sv(n - 1) > 1e-12 * n * sv(0));
      INFO(n << " points, ε = " << eps << ", σ ratio " << sv(n - 1) / sv(0));
      if (singular) {
        CHECK_THROWS_WITH(fixed_point(a, s, std::vector<int>{0}),
                          Catch::Contains("1 is not a simple eigenvalue"));
        ++refused;
      } else {
        const Eigen::RowVectorXd l = fixed_point(a, s, std::vector<int>{0});
        CHECK((l * P - l).cwiseAbs().maxCoeff() <= 1e-9);
        ++accepted;
      }
    }
  }
  CHECK(accepted >= 16);  // both verdicts occur
  CHECK(refused >= 6);
}

TEST_CASE("End functionals give the ends of every piece", "[ifs]") {
  std::mt19937_64 rng(8);
  const double u1 = 0.2, u2 = 1.5, u3 = 7;
  const Automaton a = quadratic_automaton(u1, u2, u3);
  const std::vector<Points> nets{random_points(3, 3, rng)};
  const EndFunctionals f = end_functionals(a);
  REQUIRE(f.start.size() == 4);
  for (int K = 0; K <= 4; ++K)
    for_each_leaf(a, nets, K, [&](const Leaf& leaf) {
      long double t = 0, share = 1;
      for (const int c : leaf.word) t += c * (share /= 2);
      const double tol = 1e-12 * scale_of(nets[0]);
      CHECK((f.start[leaf.state] * leaf.net - quadratic_reference(nets[0], u1, u2, u3, t))
                .cwiseAbs()
                .maxCoeff() <= tol);
      CHECK((f.end[leaf.state] * leaf.net - quadratic_reference(nets[0], u1, u2, u3, t + share))
                .cwiseAbs()
                .maxCoeff() <= tol);
    });
}

TEST_CASE("Spectra of the transitions", "[ifs]") {
  const auto s = spectra(uniform_automaton(2));
  REQUIRE(s.size() == 2);
  CHECK(s[0].label == "G");
  CHECK(s[1].label == "D");
  for (const auto& t : s) {
    REQUIRE(t.eigenvalues.size() == 3);
    const double expected[] = {1, 0.5, 0.25};
    for (std::size_t k = 0; k < 3; ++k) {
      CHECK(t.eigenvalues[k].real() == Approx(expected[k]).epsilon(1e-13));
      CHECK(std::abs(t.eigenvalues[k].imag()) <= 1e-13);
    }
  }
  const auto cubic = spectra(uniform_automaton(3));
  const double expected[] = {1, 0.5, 0.25, 0.125};
  for (std::size_t k = 0; k < 4; ++k) CHECK(std::abs(cubic[0].eigenvalues[k] - expected[k]) <= 1e-13);
  // A rotation has complex eigenvalues, sorted by modulus.
  Eigen::Matrix3d R;
  R << 0.5, 0.5, 0, -0.5, 0.5, 1, 0, 0, 1;
  const auto z = eigenvalues(R);
  REQUIRE(z.size() == 3);
  CHECK(std::abs(z[0] - 1.0) <= 1e-14);
  CHECK(std::abs(z[1]) == Approx(std::sqrt(0.5)));
  CHECK(z[1].imag() > 0);
  CHECK(z[2] == std::conj(z[1]));
}

TEST_CASE("validate names the broken state or transition", "[ifs]") {
  Automaton a;
  const StateId s = add_state(a, 3, "s"), t = add_state(a, 2, "t");
  add_transition(a, s, t, Eigen::MatrixXd::Constant(2, 3, 1.0 / 3), "x");
  add_initial(a, s);
  CHECK_THROWS_WITH(validate(a), Catch::Contains("state 1 (t) has no transition"));
  add_transition(a, t, s, Eigen::MatrixXd::Constant(3, 3, 1.0 / 3), "y");
  CHECK_THROWS_WITH(validate(a), Catch::Contains("matrix is 3 by 3, expected 3 by 2"));
  Automaton b;
  const StateId u = add_state(b, 2);
  Eigen::MatrixXd M(2, 2);
  M << 1, 0, 0.5, 0.6;
  add_transition(b, u, u, M, "m");
  add_initial(b, u);
  CHECK_THROWS_WITH(validate(b), Catch::Contains("row 1 sums to 1.1"));
  // Unreachable broken states are ignored.
  Automaton c = uniform_automaton(2);
  add_state(c, 0, "orphan");
  CHECK_NOTHROW(validate(c));
}
