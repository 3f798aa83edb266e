// SPDX-License-Identifier: MIT
// Direct refinement against the seeds' rules, the IFS matrices against direct refinement (windows
// of N points mapped by products of S_ε), the attractor against refinement, Lane–Riesenfeld degree 3
// against the NURBS knot-doubling matrices, and the open-polygon end rules.
#include <catch2/catch.hpp>
#include <random>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/nurbs/doubling.hpp"
#include "cifs/subdivision/ifs.hpp"
#include "cifs/subdivision/refine.hpp"
#include "subdivision/rational.hpp"

using namespace cifs;
using namespace cifs::subdivision;
using cifs_test::q;

namespace {

Points random_polygon(Eigen::Index n, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Points P(n, dim);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) P(i, k) = u(rng);
  return P;
}

Point row(const Points& P, Eigen::Index i) {
  const Eigen::Index n = P.rows();
  return P.row(((i % n) + n) % n);
}

/// A selection of named schemes with varied supports, parities and parameters.
std::vector<Scheme> schemes() {
  return {chaikin(),
          corner_cutting(q(1, 10), q(3, 5)),
          four_point(),
          generalized_four_point(q(1, 10)),
          six_point(),
          lane_riesenfeld(1),
          lane_riesenfeld(3),
          lane_riesenfeld(6),
          lr_four_point(1),
          lr_four_point(2),
          lr_six_point(1),
          two_tension(3, q(1, 20), q(-1, 10)),
          j_spline(q(2)),
          dual_four_point(),
          from_mask({q(1, 8), q(3, 8), q(5, 8), q(5, 8), q(1, 4)})};
}

/// Reference bi-infinite refinement of a finite window of a sequence: X holds x_first … and the
/// result holds q_i = Σ_j a_{i−2j} x_j for every i whose stencil lies inside X (first index
/// returned through `first`).
Points naive_refine(const Scheme& s, const Points& X, long first, long& fine_first) {
  const long N = mask_degree(s), n = X.rows();
  // q_i needs j with 0 ≤ i − 2j ≤ N, i.e. j ∈ [⌈(i−N)/2⌉, ⌊i/2⌋] ⊂ [first, first + n − 1].
  fine_first = 2 * first + N;
  const long fine_last = 2 * (first + n - 1);
  Points out(std::max(0L, fine_last - fine_first + 1), X.cols());
  for (long i = fine_first; i <= fine_last; ++i) {
    Point acc = Point::Zero(X.cols());
    for (long j = first; j < first + n; ++j) {
      const long k = i - 2 * j;
      if (k >= 0 && k <= N) acc += s.weights[static_cast<std::size_t>(k)] * X.row(j - first);
    }
    out.row(i - fine_first) = acc;
  }
  return out;
}

}  // namespace

TEST_CASE("closed refinement follows the seeds' rules", "[subdivision]") {
  const Points P = random_polygon(9, 2, 1);
  const Eigen::Index n = P.rows();
  {
    const Points R = refine(chaikin(), P, true);  // seed 001 (1)
    REQUIRE(R.rows() == 2 * n);
    for (Eigen::Index i = 0; i < n; ++i) {
      CHECK((R.row(2 * i) - (0.75 * row(P, i) + 0.25 * row(P, i + 1))).norm() < 1e-15);
      CHECK((R.row(2 * i + 1) - (0.25 * row(P, i) + 0.75 * row(P, i + 1))).norm() < 1e-15);
    }
  }
  {
    const Points R = refine(four_point(), P, true);  // seed 001 (2)
    for (Eigen::Index i = 0; i < n; ++i) {
      CHECK(R.row(2 * i) == P.row(i));
      const Point x = (-row(P, i - 1) + 9 * row(P, i) + 9 * row(P, i + 1) - row(P, i + 2)) / 16;
      CHECK((R.row(2 * i + 1) - x).norm() < 1e-15);
    }
  }
  {
    const double w = 0.1;  // seed 001 (3), typo corrected
    const Points R = refine(generalized_four_point(q(1, 10)), P, true);
    for (Eigen::Index i = 0; i < n; ++i) {
      CHECK(R.row(2 * i) == P.row(i));
      const Point x = -w * (row(P, i - 1) + row(P, i + 2)) + (0.5 + w) * (row(P, i) + row(P, i + 1));
      CHECK((R.row(2 * i + 1) - x).norm() < 1e-15);
    }
  }
  {
    const double a = 0.1, b = 0.6;  // seed 001 (4)
    const Points R = refine(corner_cutting(q(1, 10), q(3, 5)), P, true);
    for (Eigen::Index i = 0; i < n; ++i) {
      CHECK((R.row(2 * i) - ((1 - a) * row(P, i) + a * row(P, i + 1))).norm() < 1e-15);
      CHECK((R.row(2 * i + 1) - ((1 - b) * row(P, i) + b * row(P, i + 1))).norm() < 1e-15);
    }
  }
  {
    const Points R = refine(six_point(), P, true);
    for (Eigen::Index i = 0; i < n; ++i) {
      CHECK(R.row(2 * i) == P.row(i));
      const Point x = (3 * row(P, i - 2) - 25 * row(P, i - 1) + 150 * row(P, i) + 150 * row(P, i + 1) -
                       25 * row(P, i + 2) + 3 * row(P, i + 3)) /
                      256;
      CHECK((R.row(2 * i + 1) - x).norm() < 1e-15);
    }
  }
}

namespace {

/// Seed 000's three algorithms with its index bugs fixed: duplicate (LR) or 4-/6-point refine,
/// then degree − 1 averaging / smoothing passes over the 2n points (indices mod 2n).
Points seed_lane_riesenfeld(const Points& X0, int degree) {
  const Eigen::Index n = X0.rows();
  Points X1(2 * n, X0.cols());
  for (Eigen::Index i = 0; i < 2 * n; ++i) X1.row(i) = X0.row(i / 2);
  for (int d = 1; d < degree; ++d) {
    const Points tmp = X1;
    for (Eigen::Index i = 0; i < 2 * n; ++i) X1.row(i) = 0.5 * (tmp.row(i) + row(tmp, i + 1));
  }
  return X1;
}

Points seed_variant(const Points& X0, int degree, const std::vector<double>& taps, int back) {
  const Eigen::Index n = X0.rows();
  const auto apply = [&](const Points& X, Eigen::Index i) {
    Point v = Point::Zero(X.cols());
    for (std::size_t k = 0; k < taps.size(); ++k)
      v += taps[k] * row(X, i - back + static_cast<Eigen::Index>(k));
    return v;
  };
  Points X1(2 * n, X0.cols());
  for (Eigen::Index i = 0; i < n; ++i) {
    X1.row(2 * i) = X0.row(i);
    X1.row(2 * i + 1) = apply(X0, i);
  }
  for (int d = 1; d < degree; ++d) {
    const Points tmp = X1;
    for (Eigen::Index i = 0; i < 2 * n; ++i) X1.row(i) = apply(tmp, i);
  }
  return X1;
}

/// max over rows of |A − rotate(B, shift)|, minimised over the cyclic shift.
double cyclic_distance(const Points& A, const Points& B) {
  double best = INFINITY;
  for (Eigen::Index s = 0; s < A.rows(); ++s) {
    double worst = 0;
    for (Eigen::Index i = 0; i < A.rows(); ++i) worst = std::max(worst, (A.row(i) - row(B, i + s)).norm());
    best = std::min(best, worst);
  }
  return best;
}

}  // namespace

TEST_CASE("seed 000's algorithms (bugs fixed) are the Lane-Riesenfeld masks", "[subdivision]") {
  const Points P = random_polygon(11, 2, 2);
  const std::vector<double> four = {-1 / 16.0, 9 / 16.0, 9 / 16.0, -1 / 16.0};
  const std::vector<double> six = {3 / 256.0, -25 / 256.0, 150 / 256.0, 150 / 256.0, -25 / 256.0, 3 / 256.0};
  for (int degree : {1, 2, 3, 5, 10}) {
    CAPTURE(degree);
    // Seed "degree" = B-spline degree + 1 = smoothing stages + 1.
    CHECK(cyclic_distance(refine(lane_riesenfeld(degree - 1), P, true), seed_lane_riesenfeld(P, degree)) <
          1e-14);
    CHECK(cyclic_distance(refine(lr_four_point(degree - 1), P, true), seed_variant(P, degree, four, 1)) <
          1e-13);
    CHECK(cyclic_distance(refine(lr_six_point(degree - 1), P, true), seed_variant(P, degree, six, 2)) <
          1e-13);
  }
}

TEST_CASE("IFS windows: products of S_e map coarse windows onto refined windows", "[subdivision]") {
  for (const Scheme& s : schemes()) {
    CAPTURE(s.name, s.mask.size());
    const int N = mask_degree(s), h = closed_offset(s);
    const auto S = ifs_matrices(s);
    for (int e = 0; e < 2; ++e) CHECK((S[e].rowwise().sum().array() - 1).abs().maxCoeff() < 1e-14);
    const Points P = random_polygon(N + 5, 3, 3);
    const Eigen::Index n = P.rows();
    const int K = 4;
    const Points R = refine(s, P, true, K);
    const long scale = 1L << K;
    double worst = 0;
    const auto windows = closed_windows(s, P);
    for (Eigen::Index k = 0; k < n; k += 3)
      for (long word = 0; word < scale; ++word) {
        // Word ε_1 … ε_K (ε_1 the most significant bit): S_{ε_K} ⋯ S_{ε_1}·W_k.
        Points W = windows[static_cast<std::size_t>(k)];
        long offset = 0;
        for (int i = 0; i < K; ++i) {
          const int eps = static_cast<int>((word >> (K - 1 - i)) & 1);
          W = S[eps] * W;
          offset = 2 * offset + eps;
        }
        // Raw refined index 2^K k + (2^K − 1)(N − 1) + Σ ε_i 2^{K−i}; refine's output is shifted by
        // (2^K − 1)·h (out[m] = q_{m+h} at every step).
        const long start = scale * k + (scale - 1) * (N - 1) + offset - (scale - 1) * h;
        for (int r = 0; r < N; ++r) worst = std::max(worst, (W.row(r) - row(R, start + r)).norm());
      }
    CHECK(worst < 1e-13);
  }
}

TEST_CASE("attractor of the scheme automaton = limit of refinement", "[subdivision]") {
  const Points P = random_polygon(8, 2, 4);
  // Interpolating schemes: the refined points are limit points, so depth-K attractor points and K
  // refinement steps coincide (after the rotation of the first window's start: p_{N/2 − 1}).
  for (const Scheme& s : {four_point(), six_point(), generalized_four_point(q(1, 20))}) {
    const int K = 5, N = mask_degree(s);
    const Points A = limit_points(s, P, K), R = refine(s, P, true, K);
    REQUIRE(A.rows() == R.rows());
    const Eigen::Index shift = (N / 2 - 1) << K;
    double worst = 0;
    for (Eigen::Index i = 0; i < A.rows(); ++i)
      worst = std::max(worst, (A.row(i) - row(R, i + shift)).norm());
    CHECK(worst < 1e-13);
  }
  // Approximating schemes: the attractor point of window k is ℓ·W_k with ℓ the fixed point of S_0;
  // the points of a depth-K attractor are ℓ applied to the refined windows.
  for (const Scheme& s : {chaikin(), lane_riesenfeld(4), lr_four_point(1)}) {
    const int K = 4, N = mask_degree(s), h = closed_offset(s);
    const auto automaton = scheme_automaton(s);
    const std::vector<int> zero{0};
    const Eigen::RowVectorXd ell = ifs::fixed_point(automaton, 0, zero);
    const Points A = limit_points(s, P, K), R = refine(s, P, true, K);
    const long scale = 1L << K;
    double worst = 0;
    for (Eigen::Index j = 0; j < A.rows(); ++j) {
      // Node j (piece k = j / 2^K, word = j mod 2^K) has the refined window starting at
      // 2^K k + (2^K − 1)(N − 1) + word in raw indices.
      const long k = j / scale, word = j % scale;
      const long start = scale * k + (scale - 1) * (N - 1) + word - (scale - 1) * h;
      Eigen::RowVectorXd x = Eigen::RowVectorXd::Zero(P.cols());
      for (int r = 0; r < N; ++r) x += ell(r) * row(R, start + r);
      worst = std::max(worst, (A.row(j) - x).norm());
    }
    CHECK(worst < 1e-13);
  }
}

TEST_CASE("Lane-Riesenfeld degree 3 = uniform cubic knot doubling", "[subdivision]") {
  const auto S = ifs_matrices(lane_riesenfeld(3));
  const std::vector<double> window{1, 1, 1, 1, 1};
  CHECK((S[0] - nurbs::subdivision_matrix(window, 3, nurbs::Half::G)).cwiseAbs().maxCoeff() < 1e-15);
  CHECK((S[1] - nurbs::subdivision_matrix(window, 3, nurbs::Half::D)).cwiseAbs().maxCoeff() < 1e-15);
  // Degree 2: Chaikin and the uniform quadratic doubling matrices of seed 004.
  const auto C = ifs_matrices(chaikin());
  const std::vector<double> w2{1, 1, 1};
  CHECK((C[0] - nurbs::subdivision_matrix(w2, 2, nurbs::Half::G)).cwiseAbs().maxCoeff() < 1e-15);
  CHECK((C[1] - nurbs::subdivision_matrix(w2, 2, nurbs::Half::D)).cwiseAbs().maxCoeff() < 1e-15);
  // DESIGN.md: Chaikin S_0 = [[¾,¼,0],[¼,¾,0],[0,¾,¼]].
  Eigen::Matrix3d expected;
  expected << 0.75, 0.25, 0, 0.25, 0.75, 0, 0, 0.75, 0.25;
  CHECK(C[0] == Eigen::MatrixXd(expected));
}

TEST_CASE("open polygons: Chaikin and corner cutting cut every edge and keep the ends", "[subdivision]") {
  const Points P = random_polygon(6, 2, 5);
  const Eigen::Index n = P.rows();
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{0.25, 0.75}, {0.1, 0.6}, {0.3, 0.7}}) {
    const Scheme s =
        corner_cutting(parse_rational(std::to_string(a), "a"), parse_rational(std::to_string(b), "b"));
    const Points R = refine(s, P, false);
    REQUIRE(R.rows() == 2 * n);
    CHECK(R.row(0) == P.row(0));
    CHECK(R.row(2 * n - 1) == P.row(n - 1));
    for (Eigen::Index i = 0; i + 1 < n; ++i) {
      CHECK((R.row(1 + 2 * i) - ((1 - a) * P.row(i) + a * P.row(i + 1))).norm() < 1e-15);
      CHECK((R.row(2 + 2 * i) - ((1 - b) * P.row(i) + b * P.row(i + 1))).norm() < 1e-15);
    }
  }
  CHECK(refine(chaikin(), P, false).rows() == 2 * n);
  // The rule is stationary: two steps are two one-step refinements.
  CHECK(refine(chaikin(), P, false, 2) == refine(chaikin(), refine(chaikin(), P, false), false));
}

TEST_CASE("open polygons: primal schemes = limit of the point-reflected polygon", "[subdivision]") {
  const Points P = random_polygon(7, 2, 6);
  const Eigen::Index n = P.rows(), L = n - 1;
  for (const Scheme& s :
       {four_point(), six_point(), lane_riesenfeld(3), lane_riesenfeld(5), lr_four_point(2)}) {
    CAPTURE(s.name);
    const int N = mask_degree(s), h = closed_offset(s);
    REQUIRE(N % 2 == 0);
    const int K = 3;
    const Points R = refine(s, P, false, K);
    REQUIRE(R.rows() == (n - 1) * (1L << K) + 1);
    CHECK(R.row(0) == P.row(0));
    CHECK(R.row(R.rows() - 1) == P.row(n - 1));
    // Explicit extension by reflections through both ends, long enough for K naive steps.
    const long E = 4L * N + 8;
    Points X(n + 2 * E, 2);
    for (long j = -E; j < n + E; ++j) {
      long r = j;
      Point v = Point::Zero(2), sign_base = Point::Zero(2);
      // Reflect into [0, L] step by step: x_{−j} = 2x_0 − x_j, x_{L+j} = 2x_L − x_{L−j}.
      double sign = 1;
      while (r < 0 || r > L) {
        if (r < 0)
          v += sign * 2 * P.row(0), sign = -sign, r = -r;
        else
          v += sign * 2 * P.row(L), sign = -sign, r = 2 * L - r;
      }
      X.row(j + E) = v + sign * P.row(r);
    }
    long first = -E;
    Points Y = X;
    for (int step = 0; step < K; ++step) {
      long fine_first = 0;
      Y = naive_refine(s, Y, first, fine_first);
      first = fine_first;
    }
    // refine's out[m] = q_{m + (2^K − 1)h} of the bi-infinite scheme.
    double worst = 0;
    for (Eigen::Index m = 0; m < R.rows(); ++m) {
      const long raw = m + ((1L << K) - 1) * h;
      REQUIRE(raw - first >= 0);
      REQUIRE(raw - first < Y.rows());
      worst = std::max(worst, (R.row(m) - Y.row(raw - first)).norm());
    }
    CHECK(worst < 1e-13);
  }
}

TEST_CASE("open polygons: dual schemes reflect through the ends and re-insert them", "[subdivision]") {
  const Points P = random_polygon(13, 2, 7);
  const Eigen::Index n = P.rows();
  for (const Scheme& s : {lane_riesenfeld(4), dual_four_point(), lr_four_point(1)}) {
    CAPTURE(s.name);
    const int N = mask_degree(s), h = closed_offset(s);
    REQUIRE(N % 2 == 1);
    const Points R = refine(s, P, false);
    REQUIRE(R.rows() == 2 * n);
    CHECK(R.row(0) == P.row(0));
    CHECK(R.row(2 * n - 1) == P.row(n - 1));
    // One step against the naive scheme on the reflected polygon (single reflections suffice here).
    const long E = N + 2;
    Points X(n + 2 * E, 2);
    for (long j = -E; j < n + E; ++j) {
      REQUIRE(j > -n);
      REQUIRE(j < 2 * n - 1);
      X.row(j + E) = j < 0    ? Point(2 * P.row(0) - P.row(-j))
                     : j >= n ? Point(2 * P.row(n - 1) - P.row(2 * (n - 1) - j))
                              : Point(P.row(j));
    }
    long fine_first = 0;
    const Points Y = naive_refine(s, X, -E, fine_first);
    for (Eigen::Index m = 0; m < 2 * n - 2; ++m)
      CHECK((R.row(1 + m) - Y.row(m + h - fine_first)).norm() < 1e-14);
  }
}

TEST_CASE("open vs closed: away from the ends both refinements agree", "[subdivision]") {
  // A closed polygon opened at a vertex: interior points of the open refinement are the closed
  // ones, up to the influence of the end rule (a few stencil widths from the ends).
  const Points P = random_polygon(30, 2, 8);
  for (const Scheme& s : {four_point(), lane_riesenfeld(3), chaikin(), lr_six_point(1)}) {
    CAPTURE(s.name);
    const int N = mask_degree(s), K = 3;
    const Points open = refine(s, P, false, K), closed = refine(s, P, true, K);
    const bool dual = N % 2 == 1;
    const long scale = 1L << K;
    double worst = 0;
    // Open point m ↔ closed point m (primal) or m − (2^K − 1) (dual: each step re-inserts the end
    // point in front, shifting the next level by 2·shift + 1), for points at least 2N coarse edges
    // from both ends.
    for (Eigen::Index m = 2 * N * scale; m + 2 * N * scale < open.rows(); ++m)
      worst = std::max(worst, (open.row(m) - closed.row(dual ? m - (scale - 1) : m)).norm());
    CHECK(worst < 1e-13);
    CHECK(open.row(0) == P.row(0));
    CHECK(open.row(open.rows() - 1) == P.row(P.rows() - 1));
  }
}

TEST_CASE("refinement: sizes, limits and bad input", "[subdivision]") {
  // Points without coordinates refine to points without coordinates (the overflow guard's largest
  // coordinate of an empty matrix crashed).
  CHECK(refine(chaikin(), Points(3, 0), false).rows() == 6);
  CHECK(refine(chaikin(), Points(3, 0), true).cols() == 0);
  const Points P = random_polygon(5, 3, 9);
  CHECK(refine(four_point(), P, true, 3).rows() == 40);
  CHECK(refine(four_point(), P, false, 3).rows() == 33);
  CHECK(refine(chaikin(), P, false, 3).rows() == 40);  // dual: n → 2n (the ends re-inserted)
  CHECK(refine(chaikin(), P, true, 0) == P);
  // Short closed polygons wrap (one point stays put; affine invariance).
  const Points one = random_polygon(1, 2, 10);
  CHECK((refine(six_point(), one, true).row(1) - one.row(0)).norm() < 1e-15);
  // Short open polygons: repeated reflections.
  const Points two = random_polygon(2, 2, 11);
  const Points R = refine(six_point(), two, false, 2);
  for (Eigen::Index i = 0; i < R.rows(); ++i)  // a segment stays a segment, evenly refined
    CHECK((R.row(i) - (two.row(0) + (two.row(1) - two.row(0)) * (static_cast<double>(i) / 4.0))).norm() <
          1e-14);
  CHECK_THROWS_WITH(refine(chaikin(), Points(0, 2), true), Catch::Contains("no point"));
  CHECK_THROWS_WITH(refine(chaikin(), one, false), Catch::Contains("at least 2 points"));
  CHECK_THROWS_WITH(refine(chaikin(), P, true, -1), "the number of refinement steps -1 is negative");
  RefineOptions reflect;
  reflect.ends = Ends::reflect;
  CHECK_THROWS_WITH(refine(corner_cutting(q(1, 10), q(3, 5)), P, false, reflect),
                    Catch::Contains("needs a symmetric mask"));
  RefineOptions small;
  small.max_points = 100;
  CHECK_THROWS_WITH(refine(chaikin(), P, true, 5, small), Catch::Contains("exceed the limit of 100"));
  Points bad = P;
  bad(2, 1) = NAN;
  CHECK_THROWS_WITH(refine(chaikin(), bad, true), Catch::Contains("not finite"));
}
