#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Instructions per point of the chaos game's loop and of the minimal loop, and their ratio.

Usage: chaos_loop_ratio.py BUILD_DIR [POINTS]

Runs BUILD_DIR/bench/cifs_bench_chaos_loop twice under `valgrind --tool=callgrind`, collecting only
inside the library's chunk loop (`*run_chunk*`) and then only inside `*minimal_chaos_loop*`, and
divides each total (Ir) by the points. Instruction counts do not depend on the machine's load.
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path


def instructions(binary, points, function):
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "callgrind.out"
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        f"--toggle-collect={function}", str(binary), str(points)],
                       check=True, capture_output=True, text=True)
        match = re.search(r"^summary:\s+(\d+)", out.read_text(), re.MULTILINE)
        return int(match.group(1))


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    binary = Path(sys.argv[1]) / "bench" / "cifs_bench_chaos_loop"
    points = int(sys.argv[2]) if len(sys.argv) > 2 else 1 << 22
    library = instructions(binary, points, "*run_chunk*") / points
    minimal = instructions(binary, points, "*minimal_chaos_loop*") / points
    print(f"library loop: {library:.2f} Ir/point")
    print(f"minimal loop: {minimal:.2f} Ir/point")
    print(f"ratio: {library / minimal:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
