// SPDX-License-Identifier: MIT
// Fuzzing: what `cifs scheme` parses (cli::scheme): catalogue names, parameters (masks, symbols,
// rationals), mesh-scheme valences and boundaries, analysis and refinement. One option a line:
//   NAME
//   param symbol=(1+z)^4/8      analyze      max-power 20     steps 3      ends reflect
//   valence 5                   valences 3..8                 boundary corner   format json
// Without `analyze` the scheme refines examples/shapes/hepta.json (steps capped at 10); the analysis's
// max-power is capped at 8.
#include <algorithm>
#include <charconv>
#include <sstream>

#include "fuzz.hpp"
#include "scheme_command.hpp"

// Named, not anonymous: the harnesses compile as unity batches (CIFS_UNITY), each in its own namespace.
namespace fuzz_scheme {

constexpr int kMaxPower = 8;

int integer(const std::string& text) {
  int value = 0;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

CIFS_FUZZ_HARNESS(scheme) {
  using namespace cifs;
  std::istringstream lines{std::string(fuzz::text(data, size))};
  cli::SchemeOptions o;
  std::getline(lines, o.name);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t space = line.find(' ');
    const std::string key = line.substr(0, space);
    const std::string value = space == std::string::npos ? "" : line.substr(space + 1);
    if (key == "param") o.params.push_back(value);
    if (key == "analyze") o.analyze = true;
    if (key == "max-power") o.max_power = integer(value);
    if (key == "steps") o.steps = std::min(integer(value), 10);  // output 2^steps × the polygon
    if (key == "ends") o.ends = value;
    if (key == "valence") o.valence = value;
    if (key == "valences") o.valences = value;
    if (key == "boundary") o.boundary = value;
    if (key == "format") o.format = value;
  }
  if (!o.analyze) o.refine = CIFS_EXAMPLES_DIR "/shapes/hepta.json";
  // The work per input (each seed within 1 s of CPU in Release): the analysis's largest power. The
  // default 20 took 1.9 s on lr-six-point stages=64 (its power norms); the capped ones are the same code.
  o.max_power = std::min(o.max_power, kMaxPower);
  fuzz::refusals_allowed([&] { cli::scheme(o); });
  return 0;
}

}  // namespace fuzz_scheme
