// SPDX-License-Identifier: MIT
// Fuzzing: automaton JSON (io::parse_automaton_json). Property: an automaton read writes back
// (to_json) into text that reads back to the same text.
#include "cifs/io/json.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(automaton) {
  using namespace cifs;
  fuzz::refusals_allowed([&] {
    const std::string json = io::to_json(io::parse_automaton_json(fuzz::text(data, size), "fuzz.json"));
    fuzz::require(io::to_json(io::parse_automaton_json(json, "again.json")) == json,
                  "automaton JSON round trip");
  });
  return 0;
}
