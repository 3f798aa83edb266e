#!/usr/bin/env bash
# The project's declared style, enforced (CI runs both):
#   scripts/lint.sh format         clang-format --dry-run -Werror on every C++ source
#   scripts/lint.sh tidy [BUILD]   clang-tidy (.clang-tidy) on every library, CLI and binding source,
#                                  from BUILD/compile_commands.json (default: build/)
# With no argument, both. Exit status 1 on any finding.
set -euo pipefail
cd "$(dirname "$0")/.."

format() {
  git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run -Werror
  echo "lint: clang-format clean ($(git ls-files '*.cpp' '*.hpp' | wc -l) files)"
}

tidy() {
  local build=${1:-build}
  [[ -f $build/compile_commands.json ]] || {
    echo "lint: $build/compile_commands.json missing (configure with cmake --preset default first)" >&2
    exit 2
  }
  # Library modules, the CLI and the bindings (tests and benchmarks follow their frameworks' macros), as
  # compiled: an entry of compile_commands.json is one source or a unity batch of up to 8 (CIFS_UNITY),
  # whose headers are then parsed and checked once for all its sources. Largest first: two even queues.
  local units
  mapfile -t units < <(/usr/bin/python3 - "$build" <<'EOF'
import json, os, re, subprocess, sys
build = sys.argv[1]
dirs = r"^(core|nurbs|io|automata|ifs|verify|subdivision|render|experiment|occt|apps|python)/"
optional = r"^occt/"  # compiled only with OpenCASCADE (CIFS_OCCT): checked when it is
root = os.getcwd()
listed = subprocess.run(["git", "ls-files", "*.cpp"], capture_output=True, text=True, check=True).stdout
wanted = {f for f in listed.split() if re.match(dirs, f)}
units, covered = {}, set()
for entry in json.load(open(os.path.join(build, "compile_commands.json"))):
    path = os.path.normpath(os.path.join(entry["directory"], entry["file"]))
    sources = re.findall(r'#include "([^"]+)"', open(path).read()) if "/Unity/unity_" in path else [path]
    mine = {os.path.relpath(f, root) for f in sources} & wanted
    if mine:
        units[path] = sum(os.path.getsize(f) for f in mine)
        covered |= mine
for f in sorted(wanted - covered):
    print(f"lint: {f} is in no compile command of {build}: not checked", file=sys.stderr)
required = {f for f in wanted if not re.match(optional, f)}
print("\n".join(sorted(units, key=units.get, reverse=True)) if required <= covered else "")
EOF
  )
  [[ -n ${units[0]:-} ]] || exit 2
  # GCC-only warning flags in the compile commands are unknown to clang: not findings.
  printf '%s\n' "${units[@]}" |
    xargs -P "$(nproc)" -n 1 clang-tidy -p "$build" --quiet --extra-arg=-Wno-unknown-warning-option \
      --warnings-as-errors='*' 2> >(grep -v -E '^[0-9]+ warnings? generated|^Suppressed|^Use -header-filter|^$' >&2)
  echo "lint: clang-tidy clean (${#units[@]} compile units)"
}

case "${1:-all}" in
  format) format ;;
  tidy) tidy "${2:-build}" ;;
  all) format && tidy build ;;
  *) echo "usage: scripts/lint.sh [format|tidy [BUILD]]" >&2; exit 2 ;;
esac
