// SPDX-License-Identifier: MIT
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "ifs/helpers.hpp"
#include "nurbs/reference.hpp"

using namespace cifs;
using automata::StateId;

namespace {

nurbs::Surface random_mesh_surface(cifs_test::Rng& rng, std::array<int, 2> degree, std::array<int, 2> count,
                                   bool clamped, bool rational, int mode = 3) {
  std::array<nurbs::Knots, 2> knots;
  for (std::size_t d = 0; d < 2; ++d)
    knots[d] = cifs_test::random_knots(rng, degree[d], count[d], clamped, degree[d], mode);
  const Points P = ifs_test::random_points(count[0] * count[1], 3, rng);
  Eigen::VectorXd w;
  if (rational) {
    w.resize(count[0] * count[1]);
    for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = std::exp(cifs_test::uniform(rng, -1, 1));
  }
  return nurbs::make_surface(degree, knots, {count[0], count[1]}, P, w);
}

/// The breakpoints of one direction: the patches' parameter intervals.
std::vector<double> breaks(const nurbs::Surface& s, int dir) {
  return nurbs::breakpoints(s.knots[static_cast<std::size_t>(dir)], s.degree[static_cast<std::size_t>(dir)]);
}

/// Parameter of global node I at depth K: breakpoint a plus the dyadic fraction of its interval.
double node_parameter(const std::vector<double>& b, int I, int depth) {
  const int side = 1 << depth;
  const int a = std::min(I / side, static_cast<int>(b.size()) - 2);
  return b[static_cast<std::size_t>(a)] +
         (b[static_cast<std::size_t>(a) + 1] - b[static_cast<std::size_t>(a)]) * (I - a * side) / side;
}

/// Two states of 4 and 9 points ("four", "nine"), four children each (GH, GB, DH, DB) alternating their
/// targets, random contractive affine maps; no initial state yet.
automata::Automaton two_state_automaton(std::mt19937_64& rng) {
  automata::Automaton a;
  const StateId s0 = ifs_test::add_state(a, 4, "four"), s1 = ifs_test::add_state(a, 9, "nine");
  const char* labels[4] = {"GH", "GB", "DH", "DB"};
  for (const StateId from : {s0, s1})
    for (int c = 0; c < 4; ++c) {
      const StateId to = (c + static_cast<int>(from)) % 2 ? s1 : s0;
      ifs_test::add_transition(a, from, to,
                               ifs_test::random_contraction(a.graph[to].size, a.graph[from].size, 0.6, rng),
                               labels[c]);
    }
  return a;
}

}  // namespace

TEST_CASE("surface_mesh: vertices = surface evaluation at the dyadic nodes", "[ifs][mesh]") {
  cifs_test::Rng rng(3);
  for (int trial = 0; trial < 16; ++trial) {
    // u degrees up to 7: p + 1 > 6 takes the run-time-sized row kernel.
    const std::array<int, 2> degree{cifs_test::uniform_int(rng, 1, 7), cifs_test::uniform_int(rng, 1, 5)};
    const std::array<int, 2> count{degree[0] + cifs_test::uniform_int(rng, 1, 3),
                                   degree[1] + cifs_test::uniform_int(rng, 1, 3)};
    const bool rational = cifs_test::coin(rng);
    const nurbs::Surface s = random_mesh_surface(rng, degree, count, cifs_test::coin(rng), rational);
    const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
    const int depth = 3;
    const Mesh mesh = ifs::surface_mesh(t, nurbs::initial_nets(t, s), depth, {.homogeneous = rational});
    const auto bu = breaks(s, 0), bv = breaks(s, 1);
    const int nu = static_cast<int>(bu.size() - 1) << depth, nv = static_cast<int>(bv.size() - 1) << depth;
    REQUIRE(mesh.vertices.rows() == (nu + 1) * (nv + 1));
    REQUIRE(mesh.vertices.cols() == 3);
    const double scale = nurbs::cartesian_points(s).cwiseAbs().maxCoeff();
    double worst = 0;
    for (int I = 0; I <= nu; ++I)
      for (int J = 0; J <= nv; ++J) {
        const Point expected = nurbs::evaluate(s, node_parameter(bu, I, depth), node_parameter(bv, J, depth));
        worst = std::max(worst, (mesh.vertices.row(I * (nv + 1) + J) - expected).norm() / scale);
      }
    INFO("trial " << trial << ", degrees " << degree[0] << ", " << degree[1] << ", rational " << rational);
    CHECK(worst < 1e-12);
  }
}

TEST_CASE("surface_mesh and quad_mesh agree on tensor automata", "[ifs][mesh]") {
  cifs_test::Rng rng(5);
  for (int trial = 0; trial < 12; ++trial) {
    const std::array<int, 2> degree{cifs_test::uniform_int(rng, 1, 4), cifs_test::uniform_int(rng, 1, 4)};
    const std::array<int, 2> count{degree[0] + cifs_test::uniform_int(rng, 1, 3),
                                   degree[1] + cifs_test::uniform_int(rng, 1, 3)};
    const bool rational = cifs_test::coin(rng);
    const nurbs::Surface s = random_mesh_surface(rng, degree, count, cifs_test::coin(rng), rational);
    const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
    const auto nets = nurbs::initial_nets(t, s);
    const int depth = cifs_test::uniform_int(rng, 0, 4);
    ifs::MeshOptions options;
    options.homogeneous = rational;
    const Mesh a = ifs::surface_mesh(t, nets, depth, options);
    for (int L : {0, 2, 6}) {
      options.max_table_depth = L;
      const Mesh b = ifs::quad_mesh(t.product, nets, t.patches, depth, options);
      INFO("trial " << trial << ", depth " << depth << ", table depth " << L);
      REQUIRE(a.vertices.rows() == b.vertices.rows());
      const double scale = a.vertices.cwiseAbs().maxCoeff();
      CHECK((a.vertices - b.vertices).cwiseAbs().maxCoeff() <= 1e-14 * scale);
      CHECK(a.face_vertices == b.face_vertices);
      CHECK(a.states == b.states);
    }
  }
}

TEST_CASE("surface_mesh into a mesh: the returned mesh and cartesian(homogeneous), whatever it held",
          "[ifs][mesh]") {
  cifs_test::Rng rng(17);
  Mesh out;  // reused across trials: larger, smaller and equal sizes, 3 or 4 columns before
  for (int trial = 0; trial < 12; ++trial) {
    const std::array<int, 2> degree{cifs_test::uniform_int(rng, 1, 4), cifs_test::uniform_int(rng, 1, 3)};
    const std::array<int, 2> count{degree[0] + cifs_test::uniform_int(rng, 1, 3),
                                   degree[1] + cifs_test::uniform_int(rng, 1, 3)};
    const bool rational = trial % 3 != 0;
    const nurbs::Surface s = random_mesh_surface(rng, degree, count, cifs_test::coin(rng), rational);
    const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
    const auto nets = nurbs::initial_nets(t, s);
    const int depth = trial % 4 == 3 ? 1 : 3 - trial % 4;
    INFO("trial " << trial << ", depth " << depth << ", rational " << rational << ", out held "
                  << out.vertices.rows() << " by " << out.vertices.cols());
    ifs::surface_mesh(t, nets, depth, out, {.homogeneous = rational});
    const Mesh fresh = ifs::surface_mesh(t, nets, depth, {.homogeneous = rational});
    REQUIRE(out.vertices.rows() == fresh.vertices.rows());
    REQUIRE(out.vertices.cols() == 3);
    CHECK(out.vertices == fresh.vertices);
    CHECK(out.face_vertices == fresh.face_vertices);
    CHECK(out.states == fresh.states);
    // Rational: the division by w a row at a time gives cartesian()'s bits on the homogeneous mesh.
    if (rational)
      CHECK(out.vertices ==
            ifs::cartesian(ifs::surface_mesh(t, nets, depth, {.homogeneous = false}).vertices));
    // The same call again, over other contents: storage kept, everything rewritten.
    const double* storage = out.vertices.data();
    const auto* quads = out.face_vertices.data();
    const auto* offsets = out.face_offsets.data();
    out.vertices.setConstant(-1);
    out.face_vertices.front() = -1;
    out.face_offsets.back() = -1;
    out.states.push_back(7);
    ifs::surface_mesh(t, nets, depth, out, {.homogeneous = rational});
    CHECK(out.vertices.data() == storage);
    CHECK(out.face_vertices.data() == quads);
    CHECK(out.face_offsets.data() == offsets);
    CHECK(out.vertices == fresh.vertices);
    CHECK(out.face_vertices == fresh.face_vertices);
    CHECK(out.states == fresh.states);
  }
  // A refusal leaves the mesh as it was.
  const nurbs::Surface s = random_mesh_surface(rng, {2, 2}, {4, 4}, true, false);
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const Mesh before = out;
  CHECK_THROWS_AS(ifs::surface_mesh(t, nurbs::initial_nets(t, s), 6, out, {.max_bytes = 1000}), InvalidInput);
  CHECK(out.vertices == before.vertices);
  CHECK(out.face_vertices == before.face_vertices);
}

TEST_CASE("surface_mesh keep_faces: a sweep over nets rewrites only the vertices, bit for bit",
          "[ifs][mesh]") {
  cifs_test::Rng rng(29);
  for (int trial = 0; trial < 6; ++trial) {
    const std::array<int, 2> degree{cifs_test::uniform_int(rng, 1, 4), cifs_test::uniform_int(rng, 1, 3)};
    const std::array<int, 2> count{degree[0] + cifs_test::uniform_int(rng, 1, 3),
                                   degree[1] + cifs_test::uniform_int(rng, 1, 3)};
    const bool rational = trial % 2 == 1;
    const nurbs::Surface first = random_mesh_surface(rng, degree, count, cifs_test::coin(rng), rational);
    const nurbs::TensorAutomaton t = nurbs::tensor_automaton(first);
    const int depth = 1 + trial % 3;
    const ifs::MeshOptions keep{.homogeneous = rational, .keep_faces = true};
    Mesh out;
    // Another depth first: the sizes differ, so faces and states are written although keep_faces is set.
    ifs::surface_mesh(t, nurbs::initial_nets(t, first), depth + 1, out, keep);
    for (int frame = 0; frame < 3; ++frame) {
      // Same knots and degrees (so the same automaton), other control points and weights.
      nurbs::Surface s = first;
      s.P = nurbs::make_surface(
                degree, first.knots, first.count, ifs_test::random_points(s.P.rows(), 3, rng),
                rational ? Eigen::VectorXd(nurbs::weights(first) * (1.0 + frame)) : Eigen::VectorXd())
                .P;
      const auto nets = nurbs::initial_nets(t, s);
      ifs::surface_mesh(t, nets, depth, out, keep);
      const Mesh fresh = ifs::surface_mesh(t, nets, depth, {.homogeneous = rational});
      INFO("trial " << trial << ", frame " << frame << ", depth " << depth << ", rational " << rational);
      CHECK(out.vertices == fresh.vertices);
      CHECK(out.face_vertices == fresh.face_vertices);
      CHECK(out.face_offsets == fresh.face_offsets);
      CHECK(out.states == fresh.states);
      // Against the independent route: the surface at the dyadic nodes.
      const auto bu = breaks(s, 0), bv = breaks(s, 1);
      const int nu = static_cast<int>(bu.size() - 1) << depth, nv = static_cast<int>(bv.size() - 1) << depth;
      const double scale = nurbs::cartesian_points(s).cwiseAbs().maxCoeff();
      double worst = 0;
      for (int I = 0; I <= nu; ++I)
        for (int J = 0; J <= nv; ++J)
          worst =
              std::max(worst, (out.vertices.row(I * (nv + 1) + J) -
                               nurbs::evaluate(s, node_parameter(bu, I, depth), node_parameter(bv, J, depth)))
                                      .norm() /
                                  scale);
      CHECK(worst < 1e-12);
    }
    // The contents are the caller's promise, not checked: a changed corner is kept as it is.
    out.face_vertices.front() = -5;
    ifs::surface_mesh(t, nurbs::initial_nets(t, first), depth, out, keep);
    CHECK(out.face_vertices.front() == -5);
    ifs::surface_mesh(t, nurbs::initial_nets(t, first), depth, out, {.homogeneous = rational});
    CHECK(
        out.face_vertices ==
        ifs::surface_mesh(t, nurbs::initial_nets(t, first), depth, {.homogeneous = rational}).face_vertices);
  }
}

TEST_CASE("surface_mesh into a large mesh of the same size: overwritten in place (streaming stores)",
          "[ifs][mesh]") {
  // 2 by 2 bicubic patches at depth 9: 1025² vertices (25 MB), 1024² quads, above the streaming threshold.
  cifs_test::Rng rng(31);
  const nurbs::Surface s = random_mesh_surface(rng, {3, 3}, {5, 5}, true, false);
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const auto nets = nurbs::initial_nets(t, s);
  const int depth = 9;
  const Mesh fresh = ifs::surface_mesh(t, nets, depth);
  Mesh out = fresh;
  out.vertices.setConstant(std::numeric_limits<double>::quiet_NaN());
  std::fill(out.face_vertices.begin(), out.face_vertices.end(), -1);
  std::fill(out.face_offsets.begin(), out.face_offsets.end(), -1);
  std::fill(out.states.begin(), out.states.end(), 12345U);
  const double* storage = out.vertices.data();
  ifs::surface_mesh(t, nets, depth, out);
  CHECK(out.vertices.data() == storage);
  CHECK((out.vertices.array() == fresh.vertices.array()).all());  // no 25 MB printout on failure
  CHECK(std::equal(out.face_vertices.begin(), out.face_vertices.end(), fresh.face_vertices.begin(),
                   fresh.face_vertices.end()));
  CHECK(std::equal(out.face_offsets.begin(), out.face_offsets.end(), fresh.face_offsets.begin(),
                   fresh.face_offsets.end()));
  CHECK(std::equal(out.states.begin(), out.states.end(), fresh.states.begin(), fresh.states.end()));
  // The corners against their closed form, and a sample of vertices against evaluate().
  const int n = 1 + (2 << depth);
  bool corners = true;
  for (int I = 0; I + 1 < n; ++I)
    for (int J = 0; J + 1 < n; ++J) {
      const auto f = 4 * (static_cast<std::size_t>(I) * (n - 1) + J);
      corners = corners && out.face_vertices[f] == I * n + J && out.face_vertices[f + 1] == (I + 1) * n + J &&
                out.face_vertices[f + 2] == (I + 1) * n + J + 1 && out.face_vertices[f + 3] == I * n + J + 1;
    }
  CHECK(corners);
  const auto bu = breaks(s, 0), bv = breaks(s, 1);
  const double scale = nurbs::cartesian_points(s).cwiseAbs().maxCoeff();
  double worst = 0;
  for (int I = 0; I < n; I += 37)
    for (int J = 0; J < n; J += 41)
      worst = std::max(worst, (out.vertices.row(static_cast<Eigen::Index>(I) * n + J) -
                               nurbs::evaluate(s, node_parameter(bu, I, depth), node_parameter(bv, J, depth)))
                                      .norm() /
                                  scale);
  CHECK(worst < 1e-12);
  // keep_faces over a large mesh: the vertices streamed, the faces left as they are.
  out.vertices.setConstant(std::numeric_limits<double>::quiet_NaN());
  ifs::surface_mesh(t, nets, depth, out, {.keep_faces = true});
  CHECK((out.vertices.array() == fresh.vertices.array()).all());  // no 25 MB printout on failure
  CHECK(std::equal(out.face_vertices.begin(), out.face_vertices.end(), fresh.face_vertices.begin(),
                   fresh.face_vertices.end()));
}

TEST_CASE("Quad meshes are watertight disks", "[ifs][mesh]") {
  cifs_test::Rng rng(9);
  const nurbs::Surface s = random_mesh_surface(rng, {3, 2}, {6, 5}, false, true);
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const Mesh mesh = ifs::surface_mesh(t, nurbs::initial_nets(t, s), 3, {.homogeneous = true});
  const auto V = static_cast<std::size_t>(mesh.vertices.rows());
  std::map<std::pair<int, int>, int> edges;  // undirected edge → number of quads
  std::map<std::pair<int, int>, int> directed;
  std::vector<int> used(V, 0);
  for (std::size_t f = 0; f < face_count(mesh); ++f)
    for (int k = 0; k < 4; ++k) {
      const std::span<const int> q = face(mesh, f);
      REQUIRE(q.size() == 4);
      const int a = q[static_cast<std::size_t>(k)], b = q[static_cast<std::size_t>((k + 1) % 4)];
      REQUIRE(a >= 0);
      REQUIRE(static_cast<std::size_t>(a) < V);
      ++edges[{std::min(a, b), std::max(a, b)}];
      ++directed[{a, b}];
      ++used[static_cast<std::size_t>(a)];
    }
  const int cu = static_cast<int>(breaks(s, 0).size() - 1) << 3,
            cv = static_cast<int>(breaks(s, 1).size() - 1) << 3;
  int boundary = 0;
  for (const auto& [e, n] : edges) {
    CHECK((n == 1 || n == 2));
    boundary += n == 1;
  }
  CHECK(boundary == 2 * (cu + cv));
  // Consistent orientation: no directed edge twice.
  for (const auto& [e, n] : directed) CHECK(n == 1);
  // Every vertex used; Euler characteristic of a disk.
  CHECK(std::count(used.begin(), used.end(), 0) == 0);
  const auto chi = static_cast<long long>(V) - static_cast<long long>(edges.size()) +
                   static_cast<long long>(face_count(mesh));
  CHECK(chi == 1);
  // No two vertices at one position: shared nodes are stored once.
  std::set<std::array<double, 3>> positions;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    positions.insert({mesh.vertices(i, 0), mesh.vertices(i, 1), mesh.vertices(i, 2)});
  CHECK(positions.size() == V);
}

TEST_CASE("quad_mesh on a perturbed (non-Kronecker) automaton: corners of the leaf nets", "[ifs][mesh]") {
  std::mt19937_64 rng(17);
  automata::Automaton a = two_state_automaton(rng);
  const StateId s0 = 0, s1 = 1;
  ifs_test::add_initial(a, s0, 0);
  ifs_test::add_initial(a, s1, 1);
  ifs_test::add_initial(a, s0, 2);
  ifs_test::add_initial(a, s1, 3);
  const std::vector<std::array<int, 2>> patches{{1, 1}, {0, 0}, {1, 0}, {0, 1}};
  const std::vector<Points> nets{ifs_test::random_points(4, 3, rng), ifs_test::random_points(9, 3, rng),
                                 ifs_test::random_points(4, 3, rng), ifs_test::random_points(9, 3, rng)};
  const int depth = 4, side = 1 << depth, cu = 2 * side, row = cu + 1;
  // Independent route: walk the leaves, take the corners each leaf owns from its own net.
  std::array<std::vector<Eigen::RowVectorXd>, 4> corner;
  for (int k = 0; k < 4; ++k) corner[static_cast<std::size_t>(k)] = ifs::repeated_child_functionals(a, k);
  Points expected(row * row, 3);
  std::vector<std::uint32_t> states(static_cast<std::size_t>(cu * cu));
  ifs::for_each_leaf(a, nets, depth, [&](const ifs::Leaf& leaf) {
    int I = patches[leaf.initial][0] * side, J = patches[leaf.initial][1] * side;
    for (int k = 0; k < depth; ++k) {
      I += (leaf.word[static_cast<std::size_t>(k)] / 2) << (depth - 1 - k);
      J += (leaf.word[static_cast<std::size_t>(k)] % 2) << (depth - 1 - k);
    }
    states[static_cast<std::size_t>(I * cu + J)] = static_cast<std::uint32_t>(leaf.state);
    for (int du = 0; du < 2; ++du)
      for (int dv = 0; dv < 2; ++dv)
        if ((du == 0 || I + 1 == cu) && (dv == 0 || J + 1 == cu))
          expected.row((I + du) * row + J + dv) =
              corner[static_cast<std::size_t>(2 * du + dv)][leaf.state] * leaf.net;
  });
  for (int L : {0, 1, 3, 4}) {
    ifs::MeshOptions options;
    options.max_table_depth = L;
    const Mesh mesh = ifs::quad_mesh(a, nets, patches, depth, options);
    INFO("table depth " << L);
    CHECK((mesh.vertices - expected).cwiseAbs().maxCoeff() <= 1e-14 * expected.cwiseAbs().maxCoeff());
    CHECK(mesh.states == states);
    const std::span<const int> q = face(mesh, static_cast<std::size_t>(5 * cu + 7));
    CHECK(std::vector<int>(q.begin(), q.end()) ==
          std::vector<int>{5 * row + 7, 6 * row + 7, 6 * row + 8, 5 * row + 8});
  }

  // The topology built once (mesh_stencil_table) and applied: these nets give quad_mesh's bits,
  // other nets their own mesh, both side by side (columns) both meshes, into reused storage.
  const ifs::MeshStencilTable table =
      ifs::mesh_stencil_table(a, depth, {.patches = patches, .max_table_depth = 3});
  CHECK(table.table_depth == 3);
  const Mesh direct = ifs::quad_mesh(a, nets, patches, depth, {.max_table_depth = 3});
  Mesh applied = ifs::apply_table(table, nets);
  CHECK(applied.vertices == direct.vertices);
  CHECK(applied.face_offsets == direct.face_offsets);
  CHECK(applied.face_vertices == direct.face_vertices);
  CHECK(applied.states == states);
  std::vector<Points> other, both;
  for (const Points& n : nets) {
    other.push_back(ifs_test::random_points(n.rows(), 3, rng));
    both.emplace_back(n.rows(), 6);
    both.back() << n, other.back();
  }
  const double* storage = applied.vertices.data();
  ifs::apply_table(table, other, applied);
  CHECK(applied.vertices.data() == storage);
  CHECK(applied.vertices == ifs::quad_mesh(a, other, patches, depth, {.max_table_depth = 3}).vertices);
  // keep_faces: only the vertices are written (the faces are the caller's promise: a changed corner stays),
  // the bits of a fresh mesh; without it the faces are written again. quad_mesh into a Mesh the same.
  Mesh kept = applied;
  kept.face_vertices.front() = -5;
  ifs::apply_table(table, nets, kept, {.keep_faces = true});
  CHECK(kept.face_vertices.front() == -5);
  CHECK(kept.vertices == direct.vertices);
  ifs::apply_table(table, nets, kept);
  CHECK(kept.face_vertices == direct.face_vertices);
  Mesh reused = direct;
  reused.face_vertices.front() = -5;
  ifs::quad_mesh(a, other, patches, depth, reused, {.max_table_depth = 3, .keep_faces = true});
  CHECK(reused.face_vertices.front() == -5);
  CHECK(reused.vertices == ifs::quad_mesh(a, other, patches, depth, {.max_table_depth = 3}).vertices);
  CHECK(reused.states == direct.states);
  Mesh small = ifs::quad_mesh(a, nets, patches, depth - 1);  // other sizes: everything is written
  ifs::quad_mesh(a, nets, patches, depth, small, {.max_table_depth = 3, .keep_faces = true});
  CHECK(small.face_vertices == direct.face_vertices);
  CHECK(small.states == direct.states);
  CHECK(small.vertices == direct.vertices);
  const Mesh side_by_side = ifs::apply_table(table, both);
  // Six columns take another kernel than three: the same sums to rounding.
  const double scale = direct.vertices.cwiseAbs().maxCoeff();
  CHECK((side_by_side.vertices.leftCols(3) - direct.vertices).cwiseAbs().maxCoeff() <= 1e-15 * scale);
  CHECK((side_by_side.vertices.rightCols(3) - applied.vertices).cwiseAbs().maxCoeff() <= 1e-15 * scale);
  // patch_meshes' layout: each entry on its own block.
  const Mesh blocks = ifs::apply_table(ifs::mesh_stencil_table(a, depth, {.max_table_depth = 3}), nets);
  const Mesh separate = ifs::patch_meshes(a, nets, depth, {.max_table_depth = 3});
  CHECK(blocks.vertices == separate.vertices);
  CHECK(blocks.face_vertices == separate.face_vertices);
  CHECK(blocks.states == separate.states);
  CHECK(blocks.vertices.rows() == 4 * (side + 1) * (side + 1));
  // A table edited after it was built, or nets of another shape, are refused.
  ifs::MeshStencilTable edited = table;
  edited.leaf_states[0].push_back(0);
  CHECK_THROWS_WITH(ifs::apply_table(edited, nets), Catch::Contains("does not fit its automaton"));
  edited = table;
  edited.table_depth = 2;
  CHECK_THROWS_WITH(ifs::apply_table(edited, nets), Catch::Contains("does not fit its automaton"));
  edited = table;
  edited.patches[0] = {0, 0};
  CHECK_THROWS_WITH(ifs::apply_table(edited, nets), Catch::Contains("both placed at patch (0, 0)"));
  CHECK_THROWS_WITH(ifs::apply_table(table, std::span<const Points>(nets).first(3)),
                    Catch::StartsWith("3 control nets given for the automaton's"));
  CHECK_THROWS_WITH(ifs::apply_table(table, nets, {.max_bytes = 1000}), Catch::Contains("lower the depth"));
  CHECK_THROWS_WITH(ifs::mesh_stencil_table(a, -1), "the depth -1 is negative; give a depth ≥ 0");
}

TEST_CASE("apply_table: each vertex is its table row times its net, summed in order, bit for bit",
          "[ifs][mesh]") {
  // The vertices are emitted by a kernel per net width (AVX for 3 and 4 columns where the CPU has it): each
  // must give the sum over the row from +0 in order, a product and an addition per term — the doubles the
  // fast and the cold routes of cifs view compare. Tables of depth 2 applied at depth 2 (the nets are the
  // initial ones), states of 4 and 9 points, nets of 1 to 6 columns with entries from 1e-8 to 1e8.
  std::mt19937_64 rng(29);
  automata::Automaton a = two_state_automaton(rng);
  const StateId s0 = 0, s1 = 1;
  ifs_test::add_initial(a, s0);
  ifs_test::add_initial(a, s1);
  const int depth = 2, m = (1 << depth) + 1;
  const ifs::MeshStencilTable table = ifs::mesh_stencil_table(a, depth, {.max_table_depth = depth});
  REQUIRE(table.table_depth == depth);
  std::uniform_real_distribution<double> unit(-1, 1), scale(-8, 8);
  int differs_from_reversed = 0;
  for (Eigen::Index C = 1; C <= 6; ++C) {
    std::vector<Points> nets;
    for (const StateId s : {s0, s1}) {
      Points N(a.graph[s].size, C);
      for (Eigen::Index i = 0; i < N.size(); ++i) N(i) = unit(rng) * std::pow(10.0, scale(rng));
      nets.push_back(N);
    }
    const Mesh mesh = ifs::apply_table(table, nets);
    for (std::size_t i = 0; i < 2; ++i) {
      const auto& T = table.tables[a.initial[i].state];
      for (Eigen::Index v = 0; v < m * m; ++v)
        for (Eigen::Index c = 0; c < C; ++c) {
          double sum = 0, reversed = 0;
          for (Eigen::Index k = 0; k < T.cols(); ++k) sum += T(v, k) * nets[i](k, c);
          for (Eigen::Index k = T.cols() - 1; k >= 0; --k) reversed += T(v, k) * nets[i](k, c);
          INFO(C << " columns, block " << i << ", vertex " << v);
          const double got = mesh.vertices(static_cast<Eigen::Index>(i) * m * m + v, c);
          CHECK(std::memcmp(&got, &sum, sizeof(double)) == 0);
          differs_from_reversed += reversed != sum ? 1 : 0;
        }
    }
  }
  CHECK(differs_from_reversed > 0);  // the order matters on these entries: the test can tell
}

TEST_CASE("Corner functionals of a tensor automaton are Kronecker products of end functionals",
          "[ifs][mesh]") {
  cifs_test::Rng rng(21);
  const nurbs::Surface s = random_mesh_surface(rng, {2, 3}, {5, 6}, false, false);
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const ifs::EndFunctionals fu = ifs::end_functionals(t.factors[0].automaton),
                            fv = ifs::end_functionals(t.factors[1].automaton);
  for (int k = 0; k < 4; ++k) {
    const auto corner = ifs::repeated_child_functionals(t.product, k);
    for (StateId p = 0; p < t.factor_states.size(); ++p) {
      const auto [su, sv] = t.factor_states[p];
      const Eigen::RowVectorXd& lu = k / 2 ? fu.end[su] : fu.start[su];
      const Eigen::RowVectorXd& lv = k % 2 ? fv.end[sv] : fv.start[sv];
      Eigen::RowVectorXd expected(lu.size() * lv.size());
      for (Eigen::Index i = 0; i < lu.size(); ++i) expected.segment(i * lv.size(), lv.size()) = lu(i) * lv;
      CHECK((corner[p] - expected).cwiseAbs().maxCoeff() < 1e-14);
    }
  }
}

TEST_CASE("Meshes refuse bad input before any work", "[ifs][mesh]") {
  cifs_test::Rng rng(23);
  const nurbs::Surface s = random_mesh_surface(rng, {3, 3}, {8, 8}, true, false);
  const nurbs::TensorAutomaton t = nurbs::tensor_automaton(s);
  const auto nets = nurbs::initial_nets(t, s);
  ifs::MeshOptions small;
  small.max_bytes = 1 << 20;
  CHECK_THROWS_WITH(ifs::surface_mesh(t, nets, 12, small), Catch::Contains("GiB held in memory"));
  CHECK_THROWS_WITH(ifs::quad_mesh(t.product, nets, t.patches, 12, small),
                    Catch::Contains("GiB held in memory"));
  CHECK_THROWS_AS(ifs::surface_mesh(t, nets, -1), InvalidInput);
  CHECK_THROWS_WITH(ifs::surface_mesh(t, nets, 40), Catch::Contains("lower the depth"));
  // Patches that do not tile their grid.
  std::vector<std::array<int, 2>> patches = t.patches;
  patches[1] = patches[0];
  CHECK_THROWS_WITH(ifs::quad_mesh(t.product, nets, patches, 2), Catch::Contains("both placed"));
  patches.pop_back();
  CHECK_THROWS_WITH(ifs::quad_mesh(t.product, nets, patches, 2),
                    Catch::Contains("patches given for the automaton's"));
  // A curve automaton has two children per state.
  const automata::Automaton curve = ifs_test::uniform_automaton(3);
  const std::vector<Points> curve_nets{Points::Random(4, 2)};
  const std::vector<std::array<int, 2>> one{{0, 0}};
  CHECK_THROWS_WITH(ifs::quad_mesh(curve, curve_nets, one, 2), Catch::Contains("needs 4"));
  // Nets of the wrong size.
  std::vector<Points> wrong = nets;
  wrong[3] = Points::Random(9, 3);
  CHECK_THROWS_AS(ifs::surface_mesh(t, wrong, 2), InvalidInput);
  // State pairs that do not match the product or name missing factor states.
  nurbs::TensorAutomaton broken = t;
  broken.factor_states.pop_back();
  CHECK_THROWS_WITH(ifs::surface_mesh(broken, nets, 2), Catch::Contains("factor state pairs"));
  broken = t;
  broken.factor_states[0][1] = static_cast<StateId>(num_vertices(t.factors[1].automaton.graph));
  CHECK_THROWS_WITH(ifs::surface_mesh(broken, nets, 2), Catch::Contains("does not exist"));
}
