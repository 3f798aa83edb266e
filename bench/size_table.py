#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Tables by size from a Google Benchmark JSON report: median `per_pt` (CPU ns per point) of each
benchmark at each argument, and the ratio of a reference (SISL) to every other route.

Usage: size_table.py REPORT.json REFERENCE

REPORT.json: `--benchmark_format=json --benchmark_repetitions=3 --benchmark_report_aggregates_only=true`
(or `--benchmark_out=REPORT.json`); REFERENCE: the benchmark whose time is divided by the others'
(e.g. BM_surface_sisl_s1506). Prints a markdown table: one row per argument, per route its ns/point
and REFERENCE/route (> 1: the route is faster).
"""
import json
import sys


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    report = json.load(open(sys.argv[1], encoding="utf-8"))
    reference = sys.argv[2]
    per_pt = {}  # (route, argument) -> median ns/point
    routes, arguments = [], []
    for b in report["benchmarks"]:
        if b.get("aggregate_name", "median") != "median" or "per_pt" not in b:
            continue
        route, _, argument = b["run_name"].partition("/")
        per_pt[route, argument] = b["per_pt"] * 1e9  # the counter is in seconds
        if route not in routes:
            routes.append(route)
        if argument not in arguments:
            arguments.append(argument)
    others = [r for r in routes if r != reference]
    print("| arg | " + " | ".join([reference] + [f"{r} | ×" for r in others]) + " |")
    print("|---" * (2 + 2 * len(others)) + "|")
    for a in arguments:
        if (reference, a) not in per_pt:
            continue
        ref = per_pt[reference, a]
        cells = [f"{ref:.2f}"]
        for r in others:
            t = per_pt.get((r, a))
            cells += [f"{t:.2f}", f"{ref / t:.2f}"] if t else ["", ""]
        print(f"| {a} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
