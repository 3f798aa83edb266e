#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Fractal dimension against one free coefficient of a fractal-support curve.

The uniform cubic B-spline of a control polygon (default: the seeds' clover) is a CIFS whose matrices
may change under the BC-IFS constraints (docs/bcifs.md): the knot points stay on the NURBS, the pieces
keep joining, and the free coefficients move the geometry in between. This script sets one free
coefficient to each value of a range (the others keep their NURBS values), solves the dependent
entries (ifs.perturb: constraint residual ≤ 1e-12, contractivity checked), evaluates the attractor
deterministically to a depth (ifs.attractor_points) and fits its box-counting dimension
(ifs.box_counting, fit range chosen from the counts and reported). The same numbers come from
`cifs dimension EXPERIMENT --depth K` on an experiment file that sets the coefficient
(tests/python/test_examples.py checks one). Near the NURBS value the curve stays rectifiable
(dimension 1: the perturbed scheme is still smooth enough); further away the support turns fractal,
until the system stops being contractive.

Why a depth and not ifs.tolerance_sample (the proven-resolution sample `cifs dimension` uses by
default): perturbed matrices have negative entries, so the only piece bound is the contraction bound,
which is too loose here to leave three fitted scales.

Writes sweep.csv (value, dimension, fit range, R², or why there is none) and sweep.png (matplotlib:
the smooth and the roughest curve, and the dimension against the coefficient).

Under mpirun (with mpi4py, Debian's python3-mpi4py) the values are dealt out to the processes in
turn and rank 0 gathers the rows and writes the files, byte for byte those of one process; without
mpirun, or without mpi4py, the script runs as one process (docs/scaling.md).

    mpirun -n 2 python3 examples/python/sweep.py --out /tmp/s --steps 5 --depth 9 --min-boxes 100 --quiet

    python3 examples/python/sweep.py --out out/python
    python3 examples/python/sweep.py --out /tmp/s --steps 5 --depth 9 --min-boxes 100 --quiet
"""
import argparse
import csv
import io as text_io
import math
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cifs  # noqa: E402
from cifs import automata, ifs, io, nurbs  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1]


def mpi_world():
    """MPI's world communicator when launched by mpirun on several processes and mpi4py is there,
    else None. mpi4py is imported only then: importing it starts MPI."""
    if not any(int(os.environ.get(name, "1")) > 1 for name in ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE")):
        return None
    try:
        from mpi4py import MPI
    except ImportError:
        print("sweep.py: mpi4py is missing: every process runs the whole sweep", file=sys.stderr)
        return None
    return MPI.COMM_WORLD if MPI.COMM_WORLD.Get_size() > 1 else None


def write_atomically(path, data):
    """Writes bytes through a temporary file and a rename: `path` is never half written."""
    temporary = path.with_name(f".{path.name}.tmp")
    temporary.write_bytes(data)
    os.replace(temporary, path)


def measure(system, nets, name, value, args):
    """One row of the sweep: the dimension of the curve with `name` = value, or why there is none."""
    row = {"value": value, "dimension": math.nan, "r_squared": math.nan, "min_level": "", "max_level": "",
           "points": 0, "note": ""}
    try:
        perturbed = ifs.perturb(system, values={name: value})
        points = ifs.attractor_points(perturbed.system.automaton, nets, args.depth, closed=True)
        row["points"] = len(points)
        fit = ifs.box_counting(points, min_boxes=args.min_boxes)
        row.update(dimension=fit.dimension, r_squared=fit.r_squared, min_level=fit.min_level,
                   max_level=fit.max_level)
        return row, perturbed.system, points
    except cifs.InvalidInput as error:  # not contractive, or too few scales: recorded, not fatal
        row["note"] = str(error)
        return row, None, None


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--polygon", type=Path, default=EXAMPLES / "shapes" / "clover.json",
                        help="control polygon file (docs/formats.md)")
    parser.add_argument("--degree", type=int, default=3, help="degree of the uniform B-spline")
    parser.add_argument("--coefficient", help="free coefficient to vary (default: the last; --list shows them)")
    parser.add_argument("--list", action="store_true", help="print the free coefficients and their NURBS values")
    parser.add_argument("--span", type=float, default=0.8, help="values from NURBS − span to NURBS + span")
    parser.add_argument("--steps", type=int, default=33, help="number of values")
    parser.add_argument("--depth", type=int, default=14, help="evaluation depth (points: segments × 2^depth)")
    parser.add_argument("--min-boxes", type=int, default=1000, help="coarsest fitted scale (occupied boxes)")
    parser.add_argument("--out", type=Path, default=Path("out/python"), help="output folder (created)")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    args = parser.parse_args(argv)
    if args.steps < 2:
        parser.error(f"--steps {args.steps}: need at least 2 values")

    world = mpi_world()
    try:
        polygon = io.read_polygon(args.polygon)
        if not polygon.closed:
            raise cifs.InvalidInput(f"{args.polygon}: the sweep needs a closed polygon")
        curve = nurbs.uniform_bspline(polygon.points, args.degree, polygon.closed)
        system = ifs.curve_bcifs(curve)
        space = ifs.admissible_space(system)
        names = ifs.free_names(system, space)
        nurbs_values = dict(zip(names, ifs.free_values(system, space)))
        if args.list:
            if world and world.Get_rank() != 0:
                return 0
            for n, v in nurbs_values.items():
                print(f"{n} = {v!r}")
            return 0
        name = args.coefficient or names[-1]
        if name not in nurbs_values:
            raise cifs.InvalidInput(f"--coefficient: '{name}' is not a free coefficient ({', '.join(names)})")
        nets = automata.initial_nets(automata.knot_automaton(curve), curve)

        base = nurbs_values[name]
        values = np.linspace(base - args.span, base + args.span, args.steps)
        # Value i is measured by process i mod size; the rows are put back in order on rank 0.
        rank, size = (world.Get_rank(), world.Get_size()) if world else (0, 1)
        measured = []
        for i in range(rank, len(values), size):
            row, perturbed, points = measure(system, nets, name, float(values[i]), args)
            measured.append((i, row, points))
        if world:
            gathered = world.gather(measured, root=0)
            if rank != 0:
                return 0
            measured = sorted((m for part in gathered for m in part), key=lambda m: m[0])
        rows, shapes = [], {}
        for i, row, points in measured:
            value = values[i]
            rows.append(row)
            if points is not None:
                shapes[float(value)] = points
            if not args.quiet:
                print(f"[{i + 1}/{len(values)}] {name} = {value:+.4f}: "
                      + (f"dimension {row['dimension']:.4f} (levels {row['min_level']}–{row['max_level']}, "
                         f"{row['points']} points)" if not row["note"] else row["note"]))
    except (cifs.InvalidInput, cifs.IoError) as error:
        if world is None or world.Get_rank() == 0:
            print(f"sweep.py: {error}", file=sys.stderr)
        return 2

    args.out.mkdir(parents=True, exist_ok=True)
    table = text_io.StringIO()
    writer = csv.DictWriter(table, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    write_atomically(args.out / "sweep.csv", table.getvalue().encode())

    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4.8))
    # The roughest measured curve under the one at the value nearest the NURBS one.
    measured = [(row["dimension"], row["value"]) for row in rows if not math.isnan(row["dimension"])]
    roughest = max(measured)[1]
    nearest = min(measured, key=lambda m: abs(m[1] - base))[1]
    for value, color, width in ((roughest, "tab:purple", 0.4), (nearest, "tab:orange", 1.2)):
        points = np.vstack([shapes[value], shapes[value][:1]])
        left.plot(points[:, 0], points[:, 1], color=color, lw=width, label=f"{name} = {value:+.3f}")
    left.plot(*nurbs.cartesian_points(curve).T, color="0.6", lw=0.8, ls="--", label="control polygon")
    left.set_aspect("equal")
    left.set_title(f"{args.polygon.stem}: smooth and roughest attractors")
    left.legend(fontsize=8, loc="lower right")
    dims = np.array([r["dimension"] for r in rows])
    ok = ~np.isnan(dims)
    right.plot(values[ok], dims[ok], "o-", color="tab:blue", label="box-counting dimension")
    if (~ok).any():
        right.plot(values[~ok], np.ones((~ok).sum()), "x", color="tab:red", label="no dimension (see sweep.csv)")
    right.axvline(base, color="0.5", ls=":", label=f"NURBS value {base:.4f}")
    right.axhline(1.0, color="0.8", lw=0.8)
    right.set_xlabel(f"free coefficient {name}")
    right.set_ylabel("dimension")
    right.set_title("dimension of the attractor")
    right.legend(fontsize=8)
    figure.tight_layout()
    picture = text_io.BytesIO()
    figure.savefig(picture, format="png", dpi=110)
    write_atomically(args.out / "sweep.png", picture.getvalue())
    if not args.quiet:
        print(f"wrote {args.out / 'sweep.csv'} and {args.out / 'sweep.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
