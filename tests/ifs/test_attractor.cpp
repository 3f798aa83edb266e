// SPDX-License-Identifier: MIT
#include "cifs/ifs/attractor.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <random>

#include "cifs/errors.hpp"
#include "ifs/helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using namespace ifs_test;

namespace {

/// The start points of the depth-K leaves (plain depth-first traversal, functionals applied to
/// each leaf net) plus the last end point: the slow route attractor_points must reproduce.
Points leaf_start_points(const Automaton& a, std::span<const Points> nets, int K, bool closed) {
  const auto f = end_functionals(a);
  std::vector<Eigen::RowVectorXd> rows;
  for_each_leaf(a, nets, K, [&](const Leaf& leaf) { rows.push_back(f.start[leaf.state] * leaf.net); });
  if (!closed) rows.push_back(f.end[a.initial.back().state] * nets.back());
  Points out(static_cast<Eigen::Index>(rows.size()), nets[0].cols());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = rows[i];
  return out;
}

/// A generic automaton with out-degrees 3 and 2, net sizes 3 and 4, negative entries.
Automaton mixed_automaton(std::mt19937_64& rng, double target) {
  Automaton a;
  const StateId s = add_state(a, 3, "three"), t = add_state(a, 4, "four");
  add_transition(a, s, s, random_contraction(3, 3, target, rng), "a");
  add_transition(a, s, t, random_contraction(4, 3, target, rng), "b");
  add_transition(a, s, s, random_contraction(3, 3, target, rng), "c");
  add_transition(a, t, s, random_contraction(3, 4, target, rng), "d");
  add_transition(a, t, t, random_contraction(4, 4, target, rng), "e");
  add_initial(a, s);
  add_initial(a, t);
  return a;
}

}  // namespace

TEST_CASE("cartesian divides by the last column", "[ifs]") {
  Points h(2, 3);
  h << 2, 4, 2,  //
      -3, 1.5, 0.5;
  const Points x = cartesian(h);
  REQUIRE(x.rows() == 2);
  REQUIRE(x.cols() == 2);
  CHECK(x(0, 0) == 1);
  CHECK(x(0, 1) == 2);
  CHECK(x(1, 0) == -6);
  CHECK(x(1, 1) == 3);
  h(1, 2) = 0;
  CHECK_THROWS_WITH(cartesian(h), Catch::Contains("point 1 has weight 0"));
  CHECK_THROWS_AS(cartesian(Points(3, 1)), InvalidInput);
}

TEST_CASE("for_each_leaf visits the depth-K nodes in order, one net per level", "[ifs]") {
  std::mt19937_64 rng(11);
  const Automaton a = uniform_automaton(3, 2);
  const std::vector<Points> nets{random_points(4, 2, rng), random_points(4, 2, rng)};
  for (const int K : {0, 1, 5}) {
    std::size_t count = 0;
    std::vector<int> previous;
    std::size_t previous_initial = 0;
    for_each_leaf(a, nets, K, [&](const Leaf& leaf) {
      CHECK(leaf.depth == K);
      CHECK(leaf.word.size() == static_cast<std::size_t>(K));
      CHECK(leaf.net.rows() == 4);
      const std::vector<int> word(leaf.word.begin(), leaf.word.end());
      // Strictly increasing (initial, word) in lexicographic order.
      if (count > 0)
        CHECK((leaf.initial > previous_initial || (leaf.initial == previous_initial && word > previous)));
      previous = word;
      previous_initial = leaf.initial;
      ++count;
    });
    CHECK(count == 2 * (std::size_t{1} << K));
  }
  // The leaf net is the product of the word's matrices.
  const auto& g = a.graph;
  Eigen::MatrixXd Gm, Dm;
  for (auto [b, e] = out_edges(0, g); b != e; ++b) (g[*b].label == "G" ? Gm : Dm) = g[*b].matrix;
  for_each_leaf(a, nets, 3, [&](const Leaf& leaf) {
    Points net = nets[leaf.initial];
    for (const int c : leaf.word) net = ((c == 0 ? Gm : Dm) * net).eval();
    CHECK((net - leaf.net).cwiseAbs().maxCoeff() <= 1e-15);
  });
  CHECK_THROWS_WITH(for_each_leaf(a, std::span<const Points>(nets.data(), 1), 2, [](const Leaf&) {}),
                    "1 control nets given for the automaton's 2 initial entries (one net per entry)");
  CHECK_THROWS_AS(for_each_leaf(a, nets, -1, [](const Leaf&) {}), InvalidInput);
}

TEST_CASE("Uniform B-splines, degrees 1 to 6: attractor points = Cox-de Boor at j/2^K", "[ifs]") {
  std::mt19937_64 rng(1);
  for (int d = 1; d <= 6; ++d) {
    const Automaton a = uniform_automaton(d);
    const std::vector<Points> nets{random_points(d + 1, 3, rng)};
    const double tol = 1e-12 * scale_of(nets[0]);
    for (const int K : {0, 1, 4, 10}) {
      const Points X = attractor_points(a, nets, K);
      const long double n = std::ldexp(1.0L, K);
      REQUIRE(X.rows() == static_cast<Eigen::Index>(n) + 1);
      double err = 0;
      for (Eigen::Index j = 0; j < X.rows(); ++j)
        err = std::max(err, (X.row(j) - uniform_reference(nets[0], d, 0, static_cast<long double>(j) / n))
                                .cwiseAbs()
                                .maxCoeff());
      INFO("degree " << d << ", depth " << K);
      CHECK(err <= tol);
    }
  }
}

TEST_CASE("Several segments, open and closed: junctions appear once", "[ifs]") {
  std::mt19937_64 rng(2);
  const int d = 3, K = 6, segments = 5;
  const long double n = std::ldexp(1.0L, K);
  const Automaton a = uniform_automaton(d, segments);
  SECTION("open polygon") {
    const Points P = random_points(segments + d, 2, rng);
    std::vector<Points> nets;
    for (int k = 0; k < segments; ++k) nets.push_back(P.middleRows(k, d + 1));
    const Points X = attractor_points(a, nets, K);
    REQUIRE(X.rows() == segments * 64 + 1);
    REQUIRE(attractor_point_count(a, K) == static_cast<std::size_t>(X.rows()));
    double err = 0;
    for (Eigen::Index j = 0; j < X.rows(); ++j) {
      const int k = std::min(static_cast<int>(j / 64), segments - 1);
      const long double t = static_cast<long double>(j - 64 * k) / n;
      err = std::max(err, (X.row(j) - uniform_reference(P, d, k, t)).cwiseAbs().maxCoeff());
    }
    CHECK(err <= 1e-12 * scale_of(P));
  }
  SECTION("closed polygon") {
    const Points Q = random_points(segments, 3, rng);
    Points P(segments + d, 3);  // periodic extension
    for (int i = 0; i < segments + d; ++i) P.row(i) = Q.row(i % segments);
    std::vector<Points> nets;
    for (int k = 0; k < segments; ++k) nets.push_back(P.middleRows(k, d + 1));
    PointsOptions closed;
    closed.closed = true;
    const Points X = attractor_points(a, nets, K, closed);
    REQUIRE(X.rows() == segments * 64);
    REQUIRE(attractor_point_count(a, K, true) == static_cast<std::size_t>(X.rows()));
    double err = 0;
    for (Eigen::Index j = 0; j < X.rows(); ++j) {
      const int k = static_cast<int>(j / 64);
      err = std::max(err, (X.row(j) - uniform_reference(P, d, k, static_cast<long double>(j - 64 * k) / n))
                              .cwiseAbs()
                              .maxCoeff());
    }
    CHECK(err <= 1e-12 * scale_of(P));
  }
}

TEST_CASE("Non-uniform quadratic: the 4-state automaton of (u1,u2,u3) = Cox-de Boor", "[ifs]") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> len(0.05, 20);
  for (int trial = 0; trial < 20; ++trial) {
    const double u1 = len(rng), u2 = len(rng), u3 = len(rng);
    const Automaton a = quadratic_automaton(u1, u2, u3);
    const std::vector<Points> nets{random_points(3, 3, rng)};
    const int K = 9;
    const Points X = attractor_points(a, nets, K);
    REQUIRE(X.rows() == 513);
    double err = 0;
    for (Eigen::Index j = 0; j < X.rows(); ++j)
      err = std::max(err,
                     (X.row(j) - quadratic_reference(nets[0], u1, u2, u3, static_cast<long double>(j) / 512))
                         .cwiseAbs()
                         .maxCoeff());
    INFO("window " << u1 << ' ' << u2 << ' ' << u3);
    CHECK(err <= 1e-12 * scale_of(nets[0]));
  }
}

TEST_CASE("Stencil tables reproduce the plain depth-first start points", "[ifs]") {
  std::mt19937_64 rng(4);
  SECTION("non-uniform quadratic") {
    const Automaton a = quadratic_automaton(0.3, 1.7, 4.0);
    const std::vector<Points> nets{random_points(3, 2, rng)};
    for (const int K : {0, 3, 11}) {
      const Points reference = leaf_start_points(a, nets, K, false);
      for (const int L : {0, 1, 4, 8, 20}) {
        PointsOptions options;
        options.max_table_depth = L;
        const Points X = attractor_points(a, nets, K, options);
        REQUIRE(X.rows() == reference.rows());
        INFO("depth " << K << ", table depth " << L);
        CHECK((X - reference).cwiseAbs().maxCoeff() <= 1e-12 * scale_of(nets[0]));
      }
    }
  }
  SECTION("generic automaton: out-degrees 3 and 2, sizes 3 and 4, negative entries, 5 columns") {
    const Automaton a = mixed_automaton(rng, 0.7);
    const std::vector<Points> nets{random_points(3, 5, rng), random_points(4, 5, rng)};
    for (const int K : {0, 2, 7}) {
      for (const bool closed : {false, true}) {
        const Points reference = leaf_start_points(a, nets, K, closed);
        REQUIRE(attractor_point_count(a, K, closed) == static_cast<std::size_t>(reference.rows()));
        for (const int L : {0, 2, 8}) {
          PointsOptions options;
          options.max_table_depth = L;
          options.closed = closed;
          const Points X = attractor_points(a, nets, K, options);
          REQUIRE(X.rows() == reference.rows());
          INFO("depth " << K << ", table depth " << L << ", closed " << closed);
          CHECK((X - reference).cwiseAbs().maxCoeff() <= 1e-12 * scale_of(nets[0]));
        }
      }
    }
  }
}

TEST_CASE("attractor_points refuses an output above the limit before any work", "[ifs]") {
  const Automaton a = uniform_automaton(3);
  const std::vector<Points> nets{Points::Zero(4, 3)};
  CHECK_THROWS_WITH(attractor_points(a, nets, 40),
                    Catch::Contains("more than the limit of 1 GiB") &&
                        Catch::Contains("1099511627777 points of 3 coordinates"));
  CHECK_THROWS_WITH(attractor_points(a, nets, 200), Catch::Contains("more points than fit in size_t"));
  PointsOptions options;
  options.max_bytes = 1000;
  CHECK_THROWS_AS(attractor_points(a, nets, 6, options), InvalidInput);  // 65 · 3 · 8 = 1560 bytes
  CHECK(attractor_points(a, nets, 5, options).rows() == 33);             // 792 bytes
}

namespace {

/// The chunks of for_each_attractor_chunk stacked, and the largest chunk.
struct Chunks {
  Points rows;
  Eigen::Index largest = 0;
  std::size_t count = 0;
};

Chunks stacked_chunks(const Automaton& a, std::span<const Points> nets, int K, const PointsOptions& options) {
  Chunks out;
  std::vector<Points> pieces;
  out.count = for_each_attractor_chunk(a, nets, K, options, [&](const Eigen::Ref<const Points>& rows) {
    CHECK(rows.rows() > 0);
    out.largest = std::max(out.largest, rows.rows());
    pieces.emplace_back(rows);
  });
  Eigen::Index total = 0;
  for (const Points& p : pieces) total += p.rows();
  out.rows.resize(total, nets[0].cols());
  Eigen::Index at = 0;
  for (const Points& p : pieces) {
    out.rows.middleRows(at, p.rows()) = p;
    at += p.rows();
  }
  return out;
}

}  // namespace

TEST_CASE("attractor_points into an output: the streamed points, bit for bit, whatever `out` held",
          "[ifs][stream]") {
  std::mt19937_64 rng(13);
  const Automaton a = mixed_automaton(rng, 0.7);
  const std::vector<Points> nets{random_points(3, 2, rng), random_points(4, 2, rng)};
  Points out = Points::Constant(7, 5, 1.5);  // another size and column count to start with
  // Larger, smaller, the same size twice (storage kept), and open/closed of one depth (one row apart).
  for (const auto& [K, closed] : std::vector<std::pair<int, bool>>{
           {9, false}, {4, false}, {4, false}, {6, true}, {6, false}, {0, false}, {9, true}}) {
    INFO("depth " << K << ", closed " << closed << ", out held " << out.rows() << " rows");
    PointsOptions options;
    options.closed = closed;
    const bool same_size =
        out.rows() == static_cast<Eigen::Index>(attractor_point_count(a, K, closed)) && out.cols() == 2;
    const double* storage = out.data();
    attractor_points(a, nets, K, out, options);
    if (same_size) CHECK(out.data() == storage);
    const Chunks c = stacked_chunks(a, nets, K, options);
    REQUIRE(out.rows() == c.rows.rows());
    CHECK(out == c.rows);
    CHECK(out == attractor_points(a, nets, K, options));
  }
  // A refusal leaves the output as it was.
  const Points before = out;
  PointsOptions small;
  small.max_bytes = 100;
  CHECK_THROWS_AS(attractor_points(a, nets, 9, out, small), InvalidInput);
  CHECK(out == before);
}

TEST_CASE("for_each_attractor_chunk: the points of attractor_points, bit for bit, in bounded chunks",
          "[ifs][stream]") {
  std::mt19937_64 rng(11);
  const Automaton a = mixed_automaton(rng, 0.7);
  const std::vector<Points> nets{random_points(3, 2, rng), random_points(4, 2, rng)};
  for (const int K : {0, 1, 5, 9}) {
    for (const bool closed : {false, true}) {
      for (const std::size_t chunk : {std::size_t{1}, std::size_t{100}, std::size_t{1} << 16}) {
        INFO("depth " << K << ", closed " << closed << ", chunk " << chunk);
        PointsOptions options;
        options.closed = closed;
        options.chunk_points = chunk;
        const Chunks c = stacked_chunks(a, nets, K, options);
        const Points X = attractor_points(a, nets, K, options);
        CHECK(c.count == static_cast<std::size_t>(X.rows()));
        REQUIRE(c.rows.rows() == X.rows());
        CHECK(c.rows == X);  // exactly: the same tables, the same products
        // At most one chunk, or one stencil table when that is larger (≤ 3^8 rows: out-degrees ≤ 3).
        CHECK(c.largest <= std::max<Eigen::Index>(static_cast<Eigen::Index>(chunk), 6561));
      }
    }
  }
  // A depth refused in memory is streamed: 2^20 + 1 points under a limit of 1000 bytes.
  const Automaton u = uniform_automaton(3);
  const std::vector<Points> cubic{random_points(4, 3, rng)};
  PointsOptions small;
  small.max_bytes = 1000;
  CHECK_THROWS_AS(attractor_points(u, cubic, 20, small), InvalidInput);
  std::size_t rows = 0;
  Eigen::Index largest = 0;
  CHECK(for_each_attractor_chunk(u, cubic, 20, small, [&](const Eigen::Ref<const Points>& chunk) {
          rows += static_cast<std::size_t>(chunk.rows());
          largest = std::max(largest, chunk.rows());
        }) == (std::size_t{1} << 20) + 1);
  CHECK(rows == (std::size_t{1} << 20) + 1);
  CHECK(largest == Eigen::Index{1} << 16);
  // And the points are the Cox–de Boor ones (the in-memory route is checked against them above).
  const Chunks c = stacked_chunks(u, cubic, 11, {});
  CHECK((c.rows - leaf_start_points(u, cubic, 11, false)).cwiseAbs().maxCoeff() <=
        1e-12 * scale_of(cubic[0]));
}

TEST_CASE("Stencil table: built once, applied to new nets = Cox-de Boor, side by side, in chunks",
          "[ifs][stencil]") {
  std::mt19937_64 rng(21);
  const int d = 3, K = 9, segments = 4;
  const long double n = std::ldexp(1.0L, K);
  const Automaton a = uniform_automaton(d, segments);
  const StencilTable table = stencil_table(a, K);
  CHECK(table.points == attractor_point_count(a, K));
  CHECK(table.table_depth == 8);
  // Three polygons through one table, each against the uniform B-spline at its dyadic parameters.
  std::vector<Points> polygons, all;
  for (int frame = 0; frame < 3; ++frame) polygons.push_back(random_points(segments + d, 3, rng));
  const auto nets_of = [&](const Points& P) {
    std::vector<Points> nets;
    for (int k = 0; k < segments; ++k) nets.push_back(P.middleRows(k, d + 1));
    return nets;
  };
  Points out;
  for (const Points& P : polygons) {
    apply_table(table, nets_of(P), out);
    REQUIRE(out.rows() == segments * 512 + 1);
    double err = 0;
    for (Eigen::Index j = 0; j < out.rows(); ++j) {
      const int k = std::min(static_cast<int>(j / 512), segments - 1);
      err = std::max(err, (out.row(j) - uniform_reference(P, d, k, static_cast<long double>(j - 512 * k) / n))
                              .cwiseAbs()
                              .maxCoeff());
    }
    CHECK(err <= 1e-12 * scale_of(P));
    // The same bits as attractor_points, which chooses the same table depth for this output.
    CHECK(out == attractor_points(a, nets_of(P), K));
  }
  // The three net sets side by side (9 columns) give the three outputs side by side.
  Points wide(segments + d, 9);
  for (int f = 0; f < 3; ++f) wide.middleCols(3 * f, 3) = polygons[static_cast<std::size_t>(f)];
  const Points together = apply_table(table, nets_of(wide));
  for (int f = 0; f < 3; ++f) {
    const Points alone = apply_table(table, nets_of(polygons[static_cast<std::size_t>(f)]));
    CHECK((together.middleCols(3 * f, 3) - alone).cwiseAbs().maxCoeff() <= 1e-14 * scale_of(wide));
  }
  // In chunks: the same points, in order, chunks no larger than asked (or one table, 256 rows).
  Points stacked(static_cast<Eigen::Index>(table.points), 3);
  Eigen::Index at = 0, largest = 0;
  CHECK(apply_table_in_chunks(table, nets_of(polygons[0]), 100, [&](const Eigen::Ref<const Points>& rows) {
          stacked.middleRows(at, rows.rows()) = rows;
          at += rows.rows();
          largest = std::max(largest, rows.rows());
        }) == table.points);
  CHECK(at == stacked.rows());
  CHECK(largest == 256);
  CHECK(stacked == apply_table(table, nets_of(polygons[0])));
}

TEST_CASE("Stencil table: generic automata, every table depth, open and closed", "[ifs][stencil]") {
  std::mt19937_64 rng(22);
  const Automaton a = mixed_automaton(rng, 0.7);
  for (const int K : {0, 3, 7})
    for (const bool closed : {false, true})
      for (const std::size_t entries : {std::size_t{0}, std::size_t{200}, std::size_t{1} << 21}) {
        const StencilTable t = stencil_table(a, K, {.closed = closed, .max_entries = entries});
        INFO("depth " << K << ", closed " << closed << ", table depth " << t.table_depth);
        for (int trial = 0; trial < 2; ++trial) {
          const std::vector<Points> nets{random_points(3, 2, rng), random_points(4, 2, rng)};
          const Points X = apply_table(t, nets);
          const Points reference = leaf_start_points(a, nets, K, closed);
          REQUIRE(X.rows() == reference.rows());
          CHECK((X - reference).cwiseAbs().maxCoeff() <= 1e-12 * scale_of(nets[0]));
        }
      }
}

TEST_CASE("Stencil table: what it refuses", "[ifs][stencil]") {
  std::mt19937_64 rng(23);
  const Automaton a = mixed_automaton(rng, 0.7);
  const std::vector<Points> nets{random_points(3, 2, rng), random_points(4, 2, rng)};
  CHECK_THROWS_WITH(stencil_table(a, -1), Catch::Contains("depth -1 is negative"));
  CHECK_THROWS_WITH(stencil_table(a, 100), Catch::Contains("more points than fit in size_t"));
  const StencilTable t = stencil_table(a, 5);
  // Nets of another automaton, and a table whose fields were edited.
  CHECK_THROWS_AS(apply_table(t, std::vector<Points>{nets[1], nets[0]}), InvalidInput);
  CHECK_THROWS_AS(apply_table(t, std::vector<Points>{nets[0]}), InvalidInput);
  StencilTable edited = t;
  edited.tables.pop_back();
  CHECK_THROWS_WITH(apply_table(edited, nets), Catch::Contains("does not fit its automaton"));
  edited = t;
  edited.tables[1].resize(4, 2);
  CHECK_THROWS_WITH(apply_table(edited, nets), Catch::Contains("does not fit its automaton"));
  edited = t;
  edited.table_depth = 6;
  CHECK_THROWS_WITH(apply_table(edited, nets), Catch::Contains("does not fit its automaton"));
  // The output's size, before any work, leaving `out` as it was.
  Points out = Points::Constant(2, 2, 7.0);
  const Points before = out;
  CHECK_THROWS_WITH(apply_table(t, nets, out, 100), Catch::Contains("more than the limit"));
  CHECK(out == before);
}

TEST_CASE("Rational quadratic: a quarter circle from homogeneous rows", "[ifs]") {
  // Knots 0 0 0 1 1 1: the window (0, 1, 0); its G/D children and the uniform state.
  const Automaton a = quadratic_automaton(0, 1, 0);
  const double w = std::sqrt(0.5);
  Points P(3, 3);
  P << 1, 0, 1,  //
      w, w, w,   //
      0, 1, 1;
  const Points X = cartesian(attractor_points(a, std::vector<Points>{P}, 10));
  REQUIRE(X.rows() == 1025);
  CHECK((X.rowwise().norm().array() - 1).abs().maxCoeff() <= 1e-14);
  CHECK((X.row(0) - Eigen::RowVector2d(1, 0)).norm() <= 1e-15);
  CHECK((X.row(1024) - Eigen::RowVector2d(0, 1)).norm() <= 1e-15);
}

TEST_CASE("Tolerance leaves: the reported radius bounds the attractor piece", "[ifs]") {
  std::mt19937_64 rng(5);
  // The radius holds for every leaf, converged or cut by max_depth (kept small: the tree of a
  // system with a large bound factor is wide).
  const auto check_system = [&](const Automaton& a, const std::vector<Points>& nets, double epsilon,
                                int max_depth = 64) {
    ToleranceOptions options;
    options.epsilon = epsilon;
    options.max_depth = max_depth;
    std::vector<std::tuple<StateId, Points, double>> leaves;
    std::size_t seen = 0;
    const auto result = for_each_leaf_to_tolerance(a, nets, options, [&](const ToleranceLeaf& leaf) {
      CHECK(leaf.converged == (leaf.diameter < epsilon));
      CHECK(leaf.diameter <= 2 * leaf.radius);
      if (!leaf.converged) CHECK(leaf.leaf.depth == max_depth);
      if (seen++ % 37 == 0) leaves.emplace_back(leaf.leaf.state, leaf.leaf.net, leaf.radius);
    });
    CHECK(result.contraction.delta < 1);
    CHECK(result.leaves == seen);
    REQUIRE(!leaves.empty());
    // Sample pieces deeper: every net row at depth 6 below the leaf and the exact attractor
    // points at depth 8; all lie within the radius of the leaf's first net point.
    for (std::size_t k = 0; k < leaves.size(); k += std::max<std::size_t>(1, leaves.size() / 100)) {
      const auto& [state, net, radius] = leaves[k];
      Automaton sub = a;
      sub.initial.clear();
      add_initial(sub, state);
      const std::vector<Points> sub_nets{net};
      double far = 0;
      for_each_leaf(sub, sub_nets, 6, [&](const Leaf& leaf) {
        for (Eigen::Index i = 0; i < leaf.net.rows(); ++i)
          far = std::max(far, (leaf.net.row(i) - net.row(0)).norm());
      });
      const Points X = attractor_points(sub, sub_nets, 8);
      for (Eigen::Index i = 0; i < X.rows(); ++i) far = std::max(far, (X.row(i) - net.row(0)).norm());
      CHECK(far <= radius * (1 + 1e-12));
    }
    return result;
  };
  SECTION("random matrices with negative entries, δ_1 < 1") {
    for (int trial = 0; trial < 5; ++trial) {
      const Automaton a = mixed_automaton(rng, 0.5);
      const std::vector<Points> nets{random_points(3, 3, rng), random_points(4, 3, rng)};
      const auto result = check_system(a, nets, 0.05);
      CHECK(result.contraction.m == 1);
      CHECK(result.contraction.A > 1);  // negative entries
      CHECK(result.unconverged == 0);
    }
  }
  SECTION("random matrices that expand in one step but contract in a few") {
    // One state, two maps with δ(M) > 1 but small products: M = 1·vᵀ + B with B nilpotent-ish.
    int tested = 0;
    for (int trial = 0; trial < 200 && tested < 3; ++trial) {
      Automaton a;
      const StateId s = add_state(a, 3);
      add_transition(a, s, s, random_contraction(3, 3, 1.3, rng), "a");
      add_transition(a, s, s, random_contraction(3, 3, 1.3, rng), "b");
      add_initial(a, s);
      Contraction c;
      try {
        c = contraction(a);
      } catch (const InvalidInput&) {
        continue;
      }
      REQUIRE(c.m > 1);
      if (c.m > 3) continue;
      ++tested;
      check_system(a, {random_points(3, 2, rng)}, 1e-2, 13);
    }
    CHECK(tested == 3);
  }
  SECTION("uniform cubic: the leaves tile the curve in order") {
    const Automaton a = uniform_automaton(3);
    const std::vector<Points> nets{random_points(4, 3, rng)};
    const auto result = check_system(a, nets, 1e-3);
    CHECK(result.contraction.m == 1);
    CHECK(result.contraction.A == 1);  // positive matrices
  }
  SECTION("max_depth cuts branches and says so") {
    const Automaton a = uniform_automaton(2);
    ToleranceOptions options;
    options.epsilon = 1e-9;
    options.max_depth = 3;
    std::size_t cut = 0;
    const auto result =
        for_each_leaf_to_tolerance(a, std::vector<Points>{random_points(3, 2, rng)}, options,
                                   [&](const ToleranceLeaf& leaf) { cut += !leaf.converged; });
    CHECK(result.leaves == 8);
    CHECK(result.unconverged == 8);
    CHECK(cut == 8);
    CHECK(result.deepest == 3);
  }
  SECTION("bad options") {
    const Automaton a = uniform_automaton(2);
    ToleranceOptions options;
    options.epsilon = 0;
    CHECK_THROWS_AS(for_each_leaf_to_tolerance(a, std::vector<Points>{Points::Zero(3, 2)}, options,
                                               [](const ToleranceLeaf&) {}),
                    InvalidInput);
    // Homogeneous rows: a zero weight in the net leaves the root without a Cartesian bound, but the
    // weight of the curve (1, 0, 1) stays ≥ 1/4, so deeper pieces get one and the walk converges …
    options.epsilon = 1e-3;
    options.homogeneous = true;
    Points H(3, 2);
    H << 0, 1, 1, 0, 2, 1;
    const ToleranceResult r =
        for_each_leaf_to_tolerance(a, std::vector<Points>{H}, options, [](const ToleranceLeaf&) {});
    CHECK(r.unconverged == 0);
    // … while weights that are all zero never get one: refused (not 2^64 leaves).
    H.col(1).setZero();
    CHECK_THROWS_WITH(
        for_each_leaf_to_tolerance(a, std::vector<Points>{H}, options, [](const ToleranceLeaf&) {}),
        Catch::Contains("has no Cartesian size bound at depth 32"));
  }
}

TEST_CASE("estimate_tolerance_leaves: exact within its budget, close to the count beyond",
          "[ifs][tolerance]") {
  std::mt19937_64 rng(16);
  const auto count = [](const Automaton& a, const std::vector<Points>& nets, const ToleranceOptions& o) {
    return static_cast<double>(for_each_leaf_to_tolerance(a, nets, o, [](const ToleranceLeaf&) {}).leaves);
  };
  for (const Automaton& a : {uniform_automaton(3), quadratic_automaton(0.3, 1, 2.5)}) {
    const std::vector<Points> nets{random_points(a.graph[a.initial[0].state].size, 2, rng)};
    ToleranceOptions o;
    o.max_depth = 40;
    for (const double epsilon : {1e-2, 1e-3, 1e-4}) {
      o.epsilon = epsilon;
      const double exact = count(a, nets, o);
      const ToleranceEstimate small = estimate_tolerance_leaves(a, nets, o, 256);
      const ToleranceEstimate large = estimate_tolerance_leaves(a, nets, o, std::size_t{1} << 24);
      INFO("epsilon " << epsilon << ": " << exact << " leaves, estimated " << small.leaves);
      CHECK(large.exact);
      CHECK(large.leaves == exact);
      CHECK(small.exact == (exact <= 256));
      // Curves: the leaves double per halving of the tolerance, up to the pieces' uneven sizes.
      CHECK(small.leaves > exact / 1.3);
      CHECK(small.leaves < exact * 1.3);
    }
  }
}

TEST_CASE("estimate_tolerance_leaves: subnormal tolerances give an estimate, not a crash",
          "[ifs][tolerance][reliability]") {
  // log2(top / ε) overflowed for ε below ~1e-307: an undefined cast skipped the ladder and the
  // estimate read an empty vector (SIGSEGV from cifs attractor --piece-size 3e-308, issue 33).
  std::mt19937_64 rng(33);
  const Automaton a = uniform_automaton(3);
  const std::vector<Points> nets{random_points(a.graph[a.initial[0].state].size, 2, rng)};
  for (const double epsilon : {3e-308, 2.2e-308, 1e-310, 5e-324}) {
    for (const bool chordal : {false, true}) {
      ToleranceOptions o;
      o.max_depth = 40;
      o.epsilon = epsilon;
      o.chordal = chordal;
      const ToleranceEstimate e = estimate_tolerance_leaves(a, nets, o, 256);
      INFO(epsilon << (chordal ? " chordal" : "") << ": " << e.leaves);
      CHECK(!e.exact);
      CHECK(e.leaves > 1e30);  // far beyond any limit: refused by the callers
    }
  }
}

TEST_CASE("attractor_point_count: a huge depth is counted at once", "[ifs][reliability]") {
  // The node counts were iterated once per level: 10^9 levels took 27 CPU-s before the refusal.
  const Automaton a = uniform_automaton(3);
  const auto start = std::chrono::steady_clock::now();
  CHECK_THROWS_WITH(attractor_point_count(a, 1000000000),
                    "depth 1000000000 gives more than 2^64 points; lower the depth");
  const std::vector<Points> nets{Points::Zero(4, 2)};
  CHECK_THROWS_AS(attractor_points(a, nets, 1000000000), InvalidInput);
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 1);
  // Below saturation the counts are exact: 2^k + 1 points at depth k.
  for (int k : {0, 1, 10, 62}) CHECK(attractor_point_count(a, k) == (std::size_t{1} << k) + 1);
}
