// SPDX-License-Identifier: MIT
// The "did you mean" helper: edit distances counted by hand, typos found, unrelated words left alone.
#include <catch2/catch.hpp>

#include "cifs/suggest.hpp"

using namespace cifs;

TEST_CASE("edit_distance counts insertions, deletions, substitutions and swaps", "[core][suggest]") {
  CHECK(edit_distance("", "") == 0);
  CHECK(edit_distance("", "abc") == 3);
  CHECK(edit_distance("abc", "") == 3);
  CHECK(edit_distance("kitten", "sitting") == 3);  // k→s, e→i, +g
  CHECK(edit_distance("catmul-clark", "catmull-clark") == 1);
  CHECK(edit_distance("lopo", "loop") == 1);  // one swap of neighbours
  CHECK(edit_distance("catmull_clark", "Catmull-Clark") == 0);
  CHECK(edit_distance("ab", "ba") == 1);
  CHECK(edit_distance("abc", "ca") == 3);  // optimal string alignment: no edit of a swapped pair
}

TEST_CASE("nearest suggests a typo's word and nothing for unrelated words", "[core][suggest]") {
  const std::vector<std::string> schemes{"catmull-clark", "loop", "doo-sabin", "butterfly", "sqrt3"};
  CHECK(nearest("catmul-clark", schemes) == "catmull-clark");
  CHECK(nearest("catmull_clark", schemes) == "catmull-clark");
  CHECK(nearest("lop", schemes) == "loop");
  CHECK(nearest("dooSabin", schemes) == "doo-sabin");
  CHECK_FALSE(nearest("chaikin", schemes));
  CHECK_FALSE(nearest("loop", schemes));  // a name, not a typo
  CHECK_FALSE(nearest("x", schemes));
  CHECK(nearest("--level", {"--levels", "--scheme", "--boundary"}) == "--levels");
  CHECK(did_you_mean("--valance", {"--valence", "--valences"}) == "; did you mean --valence?");
  CHECK(did_you_mean("--colour", {"--valence"}).empty());
}
