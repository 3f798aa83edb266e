// SPDX-License-Identifier: MIT
// Fuzzing: experiment files (io::parse_experiment); relative inputs resolve against
// examples/experiments, so the seeds' shape, mesh and automaton files are found.
#include "cifs/io/json.hpp"
#include "fuzz.hpp"

CIFS_FUZZ_HARNESS(experiment) {
  using namespace cifs;
  fuzz::refusals_allowed(
      [&] { io::parse_experiment(fuzz::text(data, size), "fuzz.json", CIFS_EXAMPLES_DIR "/experiments"); });
  return 0;
}
