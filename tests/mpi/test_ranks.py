#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""`mpirun -n R cifs render` writes the bytes of the single-process render (docs/scaling.md).

For experiments that take every path of a distributed render — the chaos game of a NURBS curve over
its control polygon (samples divided by chunks), a classic IFS by the chaos game (its chunks) and to a
depth (rows), a surface mesh, a curve, a subdivision surface with its control mesh and a fractal
Catmull–Clark surface (rows) — the EXR, PNG and geometry files of 1 rank on 2 threads, 2 ranks on 1
thread and 3 ranks on 2 threads are compared byte for byte with those of one process without mpirun. Also: a rank that
fails stops them all with exit status 2, and other commands are refused under mpirun.

    tests/mpi/test_ranks.py --cli build/apps/cifs --examples examples --work /tmp/ranks
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

EXPERIMENTS = {
    # name: experiment (shape paths relative to the examples' experiments/ folder)
    "curve_chaos": {"shape": {"polygon": "../shapes/clover.json", "degree": 3},
                    "evaluation": {"chaos": 330000, "seed": 7},
                    "render": {"width": 160, "height": 120, "control_net": True}},
    "fern_chaos": {"ifs": "fern", "evaluation": {"chaos": 3200000, "seed": 2},
                   "render": {"width": 100, "height": 150}},
    "koch_depth": {"ifs": "koch", "evaluation": {"depth": 6}, "render": {"width": 200, "height": 80}},
    "surface_depth": {"shape": "../shapes/hills.json", "perturbation": {"amplitude": 0.15, "seed": 5},
                      "evaluation": {"depth": 4}, "camera": {"projection": "perspective"},
                      "render": {"width": 170, "height": 130, "control_net": True}},
    "curve_depth": {"shape": {"polygon": "../shapes/clover.json", "degree": 3}, "evaluation": {"depth": 6},
                    "render": {"width": 140, "height": 100, "line_width": 3, "control_net": True}},
    "subdivision": {"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "catmull-clark", "levels": 3},
                    "camera": {"projection": "perspective"}, "render": {"width": 120, "height": 100, "control_net": True}},
    "fractal_subdivision": {"mesh": "../meshes/cube.obj", "subdivision": {"scheme": "catmull-clark", "levels": 3},
                            "perturbation": {"amplitude": 0.9, "seed": 3}, "camera": {"projection": "perspective"},
                            "render": {"width": 110, "height": 90, "control_net": True}},
}
GEOMETRY = {"surface_depth": "ply", "curve_depth": "svg", "subdivision": "obj"}


# More ranks than cores (--oversubscribe): a rank waiting in MPI_Reduce must give its core to the
# ranks still rendering, not poll it (Open MPI polls by default: 9x the CPU of the render, and
# the other tests running beside this one starve).
os.environ["OMPI_MCA_mpi_yield_when_idle"] = "1"


def mpirun(args, ranks):
    command = [args.mpirun, "-n", str(ranks), "--oversubscribe"]
    if os.geteuid() == 0:
        command.append("--allow-run-as-root")
    return command


def render(args, command, experiment, folder, threads):
    folder.mkdir(parents=True, exist_ok=True)
    result = subprocess.run(command + [args.cli, "render", str(experiment), "--out-dir", str(folder), "-o",
                                       str(folder / "out.exr"), "--png", str(folder / "out.png"),
                                       "--threads", str(threads), "--quiet"],
                            capture_output=True, text=True, timeout=600)
    if result.returncode != 0:
        raise AssertionError(f"{' '.join(command)} render {experiment.name}: exit {result.returncode}\n"
                             f"{result.stderr}")
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", required=True)
    parser.add_argument("--mpirun", default="mpirun")
    parser.add_argument("--examples", type=Path, required=True)
    parser.add_argument("--work", type=Path, required=True)
    args = parser.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    folder = args.work / "experiments"  # beside the examples' shapes/ and meshes/ through links
    folder.mkdir(parents=True)
    for sub in ("shapes", "meshes"):
        (args.work / sub).symlink_to((args.examples / sub).resolve())
    failures = 0
    for name, body in EXPERIMENTS.items():
        experiment = folder / f"{name}.json"
        outputs = {"exr": "out.exr"}
        if name in GEOMETRY:
            outputs[GEOMETRY[name]] = f"out.{GEOMETRY[name]}"
        experiment.write_text(json.dumps({"name": name, **body, "outputs": outputs}))
        reference = render(args, [], experiment, args.work / name / "single", 1)
        if len(reference) < 2:
            raise AssertionError(f"{name}: the single-process render wrote {list(reference)}")
        # One rank with threads, an even and an uneven division of the work, threads within ranks: the
        # paths of 1–3 ranks × 1–2 threads in 3 runs, not 6 (CI time, docs/reliability.md).
        for ranks, threads in ((1, 2), (2, 1), (3, 2)):
            got = render(args, mpirun(args, ranks), experiment, args.work / name / f"r{ranks}t{threads}",
                         threads)
            differ = [f for f in reference if got.get(f) != reference[f]]
            status = "same bytes" if not differ and set(got) == set(reference) else f"DIFFER: {differ}"
            print(f"{name}: {ranks} ranks, {threads} threads: {status}")
            failures += status != "same bytes"

    # A rank that fails (here every rank: a missing input) stops the run with status 2.
    result = subprocess.run(mpirun(args, 2) + [args.cli, "render", str(folder / "missing.json")],
                            capture_output=True, text=True, timeout=120)
    print(f"missing experiment under mpirun: exit {result.returncode}")
    failures += result.returncode != 2 or "missing.json" not in result.stderr
    result = subprocess.run(mpirun(args, 2) + [args.cli, "info", str(args.work / "shapes" / "hills.json")],
                            capture_output=True, text=True, timeout=120)
    print(f"cifs info under mpirun: exit {result.returncode}: {result.stderr.strip()}")
    failures += result.returncode != 2 or "only cifs render" not in result.stderr
    print(f"{failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
