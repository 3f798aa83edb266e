#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Instructions per call of chosen functions, counting only the calls made from benchmark loops.

Usage: callgrind_per_call.py CALLGRIND_OUT NAME [NAME ...]

Reads `callgrind_annotate --inclusive=yes --tree=caller` of a cifs_bench run under
`valgrind --tool=callgrind` and, for every function whose name contains one of the NAMEs, sums the
inclusive instruction counts (Ir) and the call counts of the call arcs that come from a Google
Benchmark loop (callers named `LambdaBenchmark<…>::Run`). The cross-checks, which run once per case
outside the timed loops, call the same functions from `make_*_case`; those arcs are left out.
Prints calls, Ir and Ir per call; divide by the points per call for instructions per point.
"""
import re
import subprocess
import sys

ARC = re.compile(r"^\s*([\d,]+)\s+\([\s\d.]+%\)\s+<\s+(.*)\((\d[\d,]*)x\)\s*\[")
SELF = re.compile(r"^\s*([\d,]+)\s+\([\s\d.]+%\)\s+\*\s+\?*:?(.*?)\s*\[")


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    out_file, names = sys.argv[1], sys.argv[2:]
    text = subprocess.run(
        ["callgrind_annotate", "--inclusive=yes", "--tree=caller", out_file],
        check=True, capture_output=True, text=True).stdout
    arcs = []  # (Ir, caller, calls) of the block being read
    rows = []
    for line in text.splitlines():
        arc = ARC.match(line)
        if arc:
            arcs.append((int(arc.group(1).replace(",", "")), arc.group(2), int(arc.group(3).replace(",", ""))))
            continue
        own = SELF.match(line)
        if own:
            function = own.group(2)
            if any(name in function for name in names):
                from_bench = [(ir, calls) for ir, caller, calls in arcs if "LambdaBenchmark" in caller]
                ir = sum(a for a, _ in from_bench)
                calls = sum(c for _, c in from_bench)
                if calls:
                    rows.append((function, calls, ir))
            arcs = []
            continue
        if not line.strip():
            arcs = []
    print(f"{'function':<90} {'calls':>10} {'Ir':>15} {'Ir/call':>14}")
    for function, calls, ir in rows:
        print(f"{function[:90]:<90} {calls:>10,} {ir:>15,} {ir / calls:>14,.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
