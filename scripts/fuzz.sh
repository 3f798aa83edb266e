#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz (the `fuzz` preset: clang, ASan, UBSan) and runs each
# for SECONDS (default 60) from its seeds, its regression inputs and the corpus it grew before
# (build-fuzz/corpus/NAME). Findings land in build-fuzz/artifacts/NAME/ (crash-*, leak-*, timeout-*,
# oom-*): minimise one with `build-fuzz/tests/fuzz/fuzz_NAME -minimize_crash=1 FILE`, fix it, and keep
# it in tests/fuzz/regressions/NAME/ (docs/reliability.md, "Fuzzing").
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS...]      exit 1 when a harness found something
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
build=build-fuzz
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
mkdir -p "$build/logs"
status=0
printf '%-14s %12s %10s %8s %s\n' harness executions exec/s corpus findings
while read -r name folders; do
  if (($# > 0)) && [[ " $* " != *" $name "* ]]; then continue; fi
  mkdir -p "$build/corpus/$name" "$build/artifacts/$name"
  log="$build/logs/$name.log"
  # Per input: 10 s and 2 GB at most (a hang or an unbounded allocation is a finding); leaks are findings.
  # The pipeline and scheme harnesses get 60 s: ASan and UBSan slow their Eigen kernels and big-integer
  # arithmetic 10-50 times (hills.json: 0.2 s in Release, past 10 s sanitized; lr-six-point stages=64:
  # 1.8 s, past 10 s); the replay tests hold every input to 10 s of CPU in Release.
  timeout=10
  if [[ $name == pipeline || $name == scheme ]]; then timeout=60; fi
  # shellcheck disable=SC2086  # the seed folders are separate words
  "$build/tests/fuzz/fuzz_$name" "$build/corpus/$name" $folders -dict="tests/fuzz/dict/$name.dict" \
    -max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/artifacts/$name/" >"$log" 2>&1 || true
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  findings=$(find "$build/artifacts/$name" -type f | wc -l)
  printf '%-14s %12s %10s %8s %s\n' "$name" "${runs:-?}" "${speed:-?}" \
    "$(find "$build/corpus/$name" -type f | wc -l)" "$findings"
  if ((findings > 0)) || [[ -z $runs ]]; then
    status=1
    echo "  see $log and $build/artifacts/$name/" >&2
  fi
done <"$build/fuzz_seeds.txt"
exit $status
