// SPDX-License-Identifier: MIT
#include "cifs/io/json.hpp"

#include <catch2/catch.hpp>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/ifs/bcifs_curve.hpp"
#include "cifs/io/io.hpp"
#include "ifs/bcifs_helpers.hpp"

using namespace cifs;
using namespace cifs::io;

namespace {

void check_same(const ifs::Bcifs& a, const ifs::Bcifs& b) {
  const auto& ga = a.automaton.graph;
  const auto& gb = b.automaton.graph;
  REQUIRE(num_vertices(ga) == num_vertices(gb));
  CHECK(a.dimension == b.dimension);
  for (automata::StateId s = 0; s < num_vertices(ga); ++s) {
    CHECK(ga[s].size == gb[s].size);
    REQUIRE(out_degree(s, ga) == out_degree(s, gb));
    for (int c = 0; c < static_cast<int>(out_degree(s, ga)); ++c) {
      const auto ea = ifs::transition_id(a.automaton, {s, c}), eb = ifs::transition_id(b.automaton, {s, c});
      CHECK(target(ea, ga) == target(eb, gb));
      CHECK(ga[ea].label == gb[eb].label);
      CHECK(ga[ea].matrix == gb[eb].matrix);  // exact: JSON numbers round-trip
    }
  }
  REQUIRE(a.boundaries.size() == b.boundaries.size());
  for (std::size_t i = 0; i < a.boundaries.size(); ++i) {
    CHECK(a.boundaries[i].name == b.boundaries[i].name);
    CHECK(a.boundaries[i].cell == b.boundaries[i].cell);
    CHECK(a.boundaries[i].boundary == b.boundaries[i].boundary);
    CHECK(a.boundaries[i].rows == b.boundaries[i].rows);
  }
  REQUIRE(a.constraints.size() == b.constraints.size());
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    CHECK(a.constraints[i].name == b.constraints[i].name);
    for (int side = 0; side < 2; ++side) {
      const auto& fa = side ? a.constraints[i].right : a.constraints[i].left;
      const auto& fb = side ? b.constraints[i].right : b.constraints[i].left;
      REQUIRE(fa.size() == fb.size());
      for (std::size_t k = 0; k < fa.size(); ++k) {
        CHECK(fa[k].kind == fb[k].kind);
        if (fa[k].kind == ifs::Factor::Kind::boundary)
          CHECK(fa[k].boundary == fb[k].boundary);
        else
          CHECK(fa[k].transition == fb[k].transition);
      }
    }
  }
  auto fa = a.free, fb = b.free;
  std::sort(fa.begin(), fa.end());
  std::sort(fb.begin(), fb.end());
  CHECK(fa == fb);
  REQUIRE(a.automaton.initial.size() == b.automaton.initial.size());
  for (std::size_t i = 0; i < a.automaton.initial.size(); ++i)
    CHECK(a.automaton.initial[i].state == b.automaton.initial[i].state);
}

/// The tree example with one JSON value replaced (by text substitution, which must match once).
std::string tree_with(const std::string& from, const std::string& to) {
  std::string text = read_file(CIFS_EXAMPLES_DIR "/automata/tree.json");
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  REQUIRE(text.find(from, at + 1) == std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("BC-IFS JSON: the tree example is the hand-built tree", "[bcifs][io]") {
  const BcifsFile file = read_bcifs(CIFS_EXAMPLES_DIR "/automata/tree.json");
  check_same(file.system, ifs_test::tree_bcifs());
  REQUIRE(file.nets.size() == 1);
  CHECK(file.nets[0] == ifs_test::tree_net());
  // The branch junction holds on the file's matrices.
  CHECK_NOTHROW(ifs::check_admissible(file.system));
}

TEST_CASE("BC-IFS JSON: export and read back", "[bcifs][io]") {
  const auto tree = ifs_test::tree_bcifs();
  const Points net = ifs_test::tree_net();
  const BcifsFile back = parse_bcifs_json(to_json(tree, std::span<const Points>(&net, 1)), "tree");
  check_same(back.system, tree);
  CHECK(back.nets[0] == net);
  // A built curve system, perturbed (non-round numbers), without nets.
  const nurbs::Curve curve = nurbs::make_curve(2, {0, 0, 0, 0.4, 1, 1, 1}, Points::Random(4, 3));
  ifs::PerturbOptions options;
  options.amplitude = 0.01;
  const auto p = ifs::perturb(ifs::curve_bcifs(curve), options);
  const BcifsFile curve_back = parse_bcifs_json(to_json(p.system), "curve");
  check_same(curve_back.system, p.system);
  CHECK(curve_back.nets.empty());
}

TEST_CASE("BC-IFS JSON: bad files name the JSON path", "[bcifs][io]") {
  const auto fails = [](const std::string& text, const std::string& message) {
    CHECK_THROWS_MATCHES(parse_bcifs_json(text, "t.json"), InvalidInput, Catch::Message(message));
  };
  fails(tree_with("[0.55, 0.4, 0.05]", "[0.55, 0.4]"),
        "t.json: bcifs.transitions[0].matrix[1]: 2 entries, expected 3 (size of E by size of E)");
  fails(tree_with("\"rows\": [2]", "\"rows\": [3]"),
        "t.json: bcifs.boundaries[1].rows[0]: row 3 is outside cell E (3 rows)");
  fails(tree_with("\"E/B\"", "\"E/X\""),
        "t.json: bcifs.constraints[3].left[1]: \"E/X\": cell E has no transition \"X\"");
  fails(tree_with("\"E.end\", \"E/G\"", "\"E.middle\", \"E/G\""),
        "t.json: bcifs.constraints[2].left[0]: \"E.middle\": cell E has no boundary \"middle\"");
  fails(tree_with("\"dimension\": 0", "\"dimension\": 3"),
        "t.json: bcifs.cells[1].dimension: expected 0 (vertex), 1 (edge) or 2 (face)");
  fails(tree_with("\"to\": \"E\", \"label\": \"G\"", "\"to\": \"F\", \"label\": \"G\""),
        "t.json: bcifs.transitions[0].to: no cell is named \"F\"");
  fails(tree_with("\"state\": \"E\"", "\"state\": 1"),
        "t.json: bcifs.initial[0].state: expected a string, got number");
  fails(tree_with("[[0, 0], [0.5, 0.5], [1, 0]]", "[[0, 0], [0.5, 0.5]]"),
        "t.json: bcifs.initial[0].net: 2 rows, expected 3 (size of E)");
  // No initial entry: nothing to draw or sample (rendering such a file dereferenced a missing net).
  fails(tree_with("{\"state\": \"E\", \"net\": [[0, 0], [0.5, 0.5], [1, 0]]}", ""),
        "t.json: bcifs.initial: no entry; list at least one cell to start from");
  // Unknown members are typos, refused wherever they are: "fre" would silently fix a free transition.
  fails(tree_with("\"label\": \"G\", \"free\": true", "\"label\": \"G\", \"fre\": true"),
        "t.json: bcifs.transitions[0].fre: unknown member");
  fails(tree_with("\"name\": \"start\", \"boundary\"", "\"name\": \"start\", \"boundry\""),
        "t.json: bcifs.boundaries[0].boundry: unknown member");
  fails(tree_with("{\"name\": \"start\", \"left\"", "{\"name\": \"start\", \"lft\""),
        "t.json: bcifs.constraints[0].lft: unknown member");
  fails(tree_with("{\"state\": \"E\", \"net\"", "{\"state\": \"E\", \"nets\""),
        "t.json: bcifs.initial[0].nets: unknown member");
  fails(tree_with("\"boundaries\": [", "\"boundary\": [], \"boundaries\": ["),
        "t.json: bcifs.boundary: unknown member");
  fails(tree_with("\"size\": 1, \"dimension\": 0", "\"size\": 1, \"dimension\": 0, \"dim\": 0"),
        "t.json: bcifs.cells[1].dim: unknown member");
  // Beside the "bcifs" object too (it said "expected an object with one member", not which).
  fails(tree_with("\"bcifs\": {", "\"comment\": \"x\", \"bcifs\": {"), "t.json: comment: unknown member");
  // Structure checked by ifs::validate, prefixed by the file.
  CHECK_THROWS_WITH(
      parse_bcifs_json(tree_with("\"right\": [\"V/V\", \"E.start\"]", "\"right\": [\"E.start\", \"V/V\"]"),
                       "t.json"),
      Catch::StartsWith("t.json: BC-IFS: constraint \"start\""));
  CHECK_THROWS_AS(parse_bcifs_json("{\"bcifs\": [", "t.json"), IoError);
  CHECK_THROWS_WITH(parse_bcifs_json("{\"curve\": {}}", "t.json"),
                    "t.json: expected an object with one member, \"bcifs\"");
}
