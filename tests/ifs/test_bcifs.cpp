// SPDX-License-Identifier: MIT
#include "cifs/ifs/bcifs.hpp"

#include <catch2/catch.hpp>
#include <limits>

#include "cifs/errors.hpp"
#include "cifs/ifs/attractor.hpp"
#include "ifs/bcifs_helpers.hpp"

using namespace cifs;
using namespace cifs::ifs;
using namespace ifs_test;

namespace {

const Eigen::MatrixXd& matrix(const Bcifs& sys, TransitionRef t) {
  return sys.automaton.graph[transition_id(sys.automaton, t)].matrix;
}

}  // namespace

TEST_CASE("tree-like BC-IFS: free coefficients, perturbation, branch junction", "[bcifs]") {
  const Bcifs tree = tree_bcifs();
  REQUIRE(max_residual(tree) <= 1e-15);
  const AdmissibleSpace space = admissible_space(tree);
  for (const double bad : {-1e-3, 1.0, 1.5, std::numeric_limits<double>::quiet_NaN()})
    CHECK_THROWS_WITH(admissible_space(tree, SolveOptions{.threshold = bad}),
                      Catch::Contains("is outside [0, 1)"));
  // Hand count: 27 entries of G, D, B. Independent equations: G row 0 = e0 (3), D row 2 = e2 (3),
  // G row 2 = D row 0 (3), B row 0 = D row 0 (3), and the row sums not implied by those: G row 1,
  // D rows 0 and 1, B rows 1 and 2 (5). 27 − 17 = 10.
  CHECK(space.free.size() == 10);
  CHECK(space.unknowns.size() == 27);
  // x0 + K·c reproduces the file's matrices from their own free values.
  const Bcifs same = with_free_values(tree, space, free_values(tree, space));
  for (int c = 0; c < 3; ++c)
    CHECK((matrix(same, {0, c}) - matrix(tree, {0, c})).cwiseAbs().maxCoeff() <= 1e-15);

  PerturbOptions options;
  options.amplitude = 0.05;
  options.seed = 7;
  const Perturbation p = perturb(tree, options);
  CHECK(p.residual <= 1e-12);
  CHECK(max_residual(p.system) <= 1e-12);
  CHECK(p.values.size() == 10);
  CHECK(p.contraction.delta < 1);
  CHECK((matrix(p.system, {0, 2}) - matrix(tree, {0, 2})).cwiseAbs().maxCoeff() > 1e-3);  // it moved

  // Every node at depth 4: the branch (child 2) starts where G ends and D starts, computed from
  // the nets of the three children directly.
  const Points net = tree_net();
  const auto F = edge_end_functionals(p.system);
  int checked = 0;
  for_each_leaf(p.system.automaton, std::span<const Points>(&net, 1), 4, [&](const Leaf& leaf) {
    const Points g = matrix(p.system, {0, 0}) * leaf.net, d = matrix(p.system, {0, 1}) * leaf.net,
                 b = matrix(p.system, {0, 2}) * leaf.net;
    const double scale = std::max(1.0, leaf.net.cwiseAbs().maxCoeff());
    CHECK((F.end[0] * g - F.start[0] * d).norm() <= 1e-12 * scale);
    CHECK((F.start[0] * b - F.start[0] * d).norm() <= 1e-12 * scale);
    // The ends of the edge stay those of the parent (vertex operator [1]).
    CHECK((F.start[0] * g - F.start[0] * leaf.net).norm() <= 1e-12 * scale);
    CHECK((F.end[0] * d - F.end[0] * leaf.net).norm() <= 1e-12 * scale);
    ++checked;
  });
  CHECK(checked == 81);

  // edge_pieces: 3^3 pieces at depth 3; the branch piece of every node starts at the node's
  // junction, i.e. where its G piece ends.
  const EdgePieces pieces = edge_pieces(p.system, std::span<const Points>(&net, 1), 3);
  REQUIRE(pieces.start.rows() == 27);
  for (Eigen::Index i = 0; i < 27; i += 3) {
    CHECK((pieces.end.row(i) - pieces.start.row(i + 1)).norm() <= 1e-12);
    CHECK((pieces.start.row(i + 2) - pieces.start.row(i + 1)).norm() <= 1e-12);
  }
  // Edge ends come from the vertex cells, not from the last child (the branch).
  CHECK((F.end[0] * net - net.row(2)).norm() <= 1e-15);
}

TEST_CASE("perturb: seeds, explicit values, refusals", "[bcifs]") {
  const Bcifs tree = tree_bcifs();
  PerturbOptions options;
  options.amplitude = 0.05;
  options.seed = 11;
  const Perturbation a = perturb(tree, options), b = perturb(tree, options);
  for (int c = 0; c < 3; ++c) CHECK(matrix(a.system, {0, c}) == matrix(b.system, {0, c}));
  options.seed = 12;
  const Perturbation other = perturb(tree, options);
  CHECK(matrix(other.system, {0, 0}) != matrix(a.system, {0, 0}));
  // Draws lie in [−a, a] around the current values.
  const AdmissibleSpace space = admissible_space(tree);
  const Eigen::VectorXd base = free_values(tree, space);
  for (std::size_t j = 0; j < a.values.size(); ++j)
    CHECK(std::abs(a.values[j].second - base(static_cast<Eigen::Index>(j))) <= 0.05);

  SECTION("explicit values by name") {
    const std::string name = a.values.front().first;
    options.values[name] = 0.125;
    const Perturbation set = perturb(tree, options);
    CHECK(set.values.front().second == 0.125);
    const Coefficient& k = space.unknowns[space.free.front()];
    CHECK(matrix(set.system, k.transition)(k.row, k.col) == 0.125);
    // The other coefficients keep their draws: the stream does not depend on explicit values.
    CHECK(set.values[1].second == other.values[1].second);
    CHECK(set.residual <= 1e-12);
  }
  SECTION("a dependent or unknown name is refused") {
    const auto names = free_names(tree, space);
    std::string dependent;
    for (const auto& u : space.unknowns) {
      const std::string n = coefficient_name(tree.automaton, u);
      if (std::find(names.begin(), names.end(), n) == names.end()) dependent = n;
    }
    REQUIRE(!dependent.empty());
    options.values[dependent] = 0.5;
    CHECK_THROWS_WITH(perturb(tree, options), Catch::Contains("dependent coefficient"));
    options.values = {{"E/X[0,0]", 0.5}};
    CHECK_THROWS_WITH(perturb(tree, options), Catch::Contains("not an entry of a free matrix"));
  }
  SECTION("non-contractive results and bad amplitudes are refused") {
    options.amplitude = 40;
    CHECK_THROWS_WITH(perturb(tree, options),
                      Catch::StartsWith("the perturbed system is not contractive with amplitude 40"));
    options.amplitude = -1;
    CHECK_THROWS_AS(perturb(tree, options), InvalidInput);
  }
}

TEST_CASE("BC-IFS validation and admissibility messages", "[bcifs]") {
  Bcifs tree = tree_bcifs();
  SECTION("a failing constraint is named with its residual") {
    tree.automaton.graph[transition_id(tree.automaton, {0, 2})].matrix(0, 0) = 0.4;
    tree.automaton.graph[transition_id(tree.automaton, {0, 2})].matrix(0, 1) = 0.1;
    CHECK_THROWS_WITH(check_admissible(tree), Catch::Contains("\"branch\" fails by 0.1"));
  }
  SECTION("factors that do not chain") {
    tree.constraints[0].left = {tree.constraints[0].left[1], tree.constraints[0].left[0]};
    CHECK_THROWS_WITH(validate(tree),
                      Catch::Contains("constraint \"start\": E/G reads cell E but E.start produces cell V"));
  }
  SECTION("two free transitions on one side") {
    tree.constraints[2].left = {tree.constraints[2].left[0], Factor{Factor::Kind::transition, 0, {0, 0}},
                                Factor{Factor::Kind::transition, 0, {0, 1}}};
    CHECK_THROWS_WITH(validate(tree), Catch::Contains("more than one free transition"));
  }
  SECTION("a boundary that is not a selection inside the cell") {
    tree.boundaries[1].rows = {3};
    CHECK_THROWS_WITH(validate(tree), Catch::Contains("outside the cell's 3 rows"));
  }
  SECTION("each refusal names the first offender, in full") {
    // validate is on the path of every interactive edit of a perturbation, made cheap: the messages and
    // which offender they name must stay what they were (the first in order).
    Bcifs labels = tree;
    labels.automaton.graph[transition_id(labels.automaton, {0, 2})].label = "G";
    CHECK_THROWS_WITH(validate(labels),
                      "BC-IFS: cell E has two transitions labelled \"G\" (labels name the transitions)");
    Bcifs names = tree;
    names.boundaries.push_back({"end", 0, 1, {1}});
    names.boundaries.push_back({"start", 0, 1, {1}});
    CHECK_THROWS_WITH(validate(names),
                      "BC-IFS: boundaries[2] (\"end\"): cell E has two boundaries of that name");
    Bcifs repeated = tree;
    repeated.automaton = {};
    const StateId E = add_state(repeated.automaton, 3, "E"), V = add_state(repeated.automaton, 2, "V");
    for (const char* label : {"G", "D", "B"})
      add_transition(repeated.automaton, E, E,
                     tree.automaton.graph[transition_id(tree.automaton, {0, 0})].matrix, label);
    add_transition(repeated.automaton, V, V, Eigen::MatrixXd::Identity(2, 2), "V");
    repeated.boundaries = {{"start", E, V, {0, 1}}, {"end", E, V, {2, 2}}};
    CHECK_THROWS_WITH(validate(repeated),
                      "BC-IFS: boundaries[1] (\"end\"): row 2 is repeated or outside the cell's 3 rows");
    Bcifs missing = tree;
    missing.boundaries[1].boundary = 7;
    CHECK_THROWS_WITH(validate(missing),
                      "BC-IFS: boundaries[1] (\"end\"): names a state that does not exist");
    Bcifs empty = tree;
    empty.constraints[3].right.clear();
    CHECK_THROWS_WITH(validate(empty), "BC-IFS: constraint \"branch\": the right side is empty");
    CHECK_NOTHROW(validate(tree));
  }
  SECTION("inconsistent constraints") {
    // D's last row must be e2 ("end") and also e0: no solution.
    tree.constraints.push_back(
        {"impossible",
         {Factor{Factor::Kind::boundary, 1, {}}, Factor{Factor::Kind::transition, 0, {0, 1}}},
         {Factor{Factor::Kind::boundary, 0, {}}}});
    CHECK_THROWS_WITH(admissible_space(tree), Catch::Contains("have no common solution"));
  }
}
