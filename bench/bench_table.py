#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Markdown table of cifs vs SISL from a cifs_bench JSON file (docs/performance.md).

Usage: bench_table.py RESULTS.json

RESULTS.json comes from
  cifs_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
             --benchmark_out=RESULTS.json --benchmark_out_format=json
Every figure is the median over the repetitions of the per_pt / per_knot counter (CPU time per item).
"""
import json
import sys

# (case, cifs benchmark, SISL benchmark, prototype benchmark or None); names under BM_<group>/.
ROWS = [
    ("curve_eval_random", "cifs", "sisl_s1542_fresh", "proto_cifs"),
    ("curve_eval_random", "cifs", "sisl_s1542", None),
    ("curve_eval_random", "cifs", "sisl", None),
    ("curve_eval_random", "cifs", "sisl_s1221", None),
    ("curve_eval_random", "cifs_deboor", "sisl", "proto_deboor"),
    ("curve_eval_random", "cifs_basis", "sisl", None),
    ("curve_eval_sorted", "cifs", "sisl_s1542_fresh", "proto_cifs"),
    ("curve_eval_sorted", "cifs", "sisl_s1542", None),
    ("curve_eval_sorted", "cifs", "sisl", None),
    ("curve_eval_sorted", "cifs", "sisl_s1221", None),
    ("curve_eval_sorted", "cifs_deboor", "sisl", "proto_deboor"),
    ("curve_eval_sorted", "cifs_basis", "sisl", None),
    ("rcurve_eval_random", "cifs", "sisl", "proto_cifs"),
    ("rcurve_eval_random", "cifs", "sisl_s1221", None),
    ("rcurve_eval_random", "cifs_deboor", "sisl", "proto_deboor"),
    ("rcurve_eval_sorted", "cifs", "sisl", "proto_cifs"),
    ("rcurve_eval_sorted", "cifs", "sisl_s1221", None),
    ("rcurve_eval_sorted", "cifs_deboor", "sisl", "proto_deboor"),
    ("surface_grid", "cifs", "sisl", "proto_cifs"),
    ("surface_grid", "cifs", "sisl_s1424", None),
    ("surface_grid", "cifs_point", "sisl_s1424", "proto_point"),
    ("rsurface_grid", "cifs", "sisl", "proto_cifs"),
    ("rsurface_grid", "cifs", "sisl_s1424", None),
    ("rsurface_grid", "cifs_point", "sisl_s1424", "proto_point"),
    ("curve_refine_1000", "cifs", "sisl", "proto_refine"),
    ("curve_refine_1000", "cifs", "sisl", "proto_blossom"),
    ("curve_refine_1000", "cifs_midpoints", "sisl", None),
    ("curve_refine_100000", "cifs", "sisl", "proto_refine"),
    ("curve_refine_100000", "cifs", "sisl", "proto_blossom"),
    ("curve_refine_100000", "cifs_midpoints", "sisl", None),
]

SISL_NAMES = {
    "sisl": "s1227 + leftknot",
    "sisl_s1221": "s1221 + leftknot",
    "sisl_s1542": "s1542 (stale hints)",
    "sisl_s1542_fresh": "s1542",
    "sisl_s1424": "s1424 per point",
}
PROTO_NAMES = {
    "proto_cifs": "batch kernel",
    "proto_deboor": "stack de Boor",
    "proto_point": "stack tensor sum",
    "proto_refine": "Boehm (A5.4)",
    "proto_blossom": "blossoms, no overhead",
}
CIFS_NAMES = {
    "cifs": "evaluate(c, us)",
    "cifs_deboor": "evaluate(c, u)",
    "cifs_basis": "evaluate_basis",
    "cifs_point": "evaluate(s, u, v)",
    "cifs_midpoints": "refine_midpoints",
}


def main() -> int:
    with open(sys.argv[1]) as f:
        data = json.load(f)
    median = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        name = b["run_name"]
        value = b.get("per_pt", b.get("per_knot"))
        if value is not None:
            median[name] = value * 1e9  # seconds → ns
    print("| case | cifs | ns | SISL | ns | SISL/cifs | prototype | ns | SISL/proto |")
    print("|---|---|--:|---|--:|--:|---|--:|--:|")
    for group, cifs, sisl, proto in ROWS:
        c = median.get(f"BM_{group}/{cifs}")
        s = median.get(f"BM_{group}/{sisl}")
        p = median.get(f"BM_{group}/{proto}") if proto else None
        if c is None:
            continue
        cifs_name = CIFS_NAMES.get(cifs, cifs)
        if group.startswith("surface") or group.startswith("rsurface"):
            cifs_name = "evaluate_grid" if cifs == "cifs" else cifs_name
            sisl_name = "s1506 grid" if sisl == "sisl" else SISL_NAMES.get(sisl, sisl)
        elif group.startswith("curve_refine"):
            cifs_name = "refine(c, mids)" if cifs == "cifs" else cifs_name
            sisl_name = "s1018"
        else:
            sisl_name = SISL_NAMES.get(sisl, sisl)
        fmt = lambda x: f"{x:.1f}" if x is not None else "–"
        ratio = f"{s / c:.2f}" if s is not None else "–"
        proto_ratio = f"{s / p:.2f}" if (s is not None and p is not None) else "–"
        proto_name = "fixed-cols grid" if (proto == "proto_cifs" and "surface" in group) else PROTO_NAMES.get(proto, "–")
        print(f"| {group} | {cifs_name} | {fmt(c)} | {sisl_name} | {fmt(s)} | {ratio} | {proto_name} | {fmt(p)} "
              f"| {proto_ratio} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
