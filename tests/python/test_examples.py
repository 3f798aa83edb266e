# SPDX-License-Identifier: MIT
"""The Python examples (examples/python) run on small sizes, and what they write is checked."""
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import unittest

import numpy as np

import cifs
from support import EXAMPLES, ScratchTestCase, cli

SCRIPTS = EXAMPLES / "python"


def run_script(name, *args):
    result = subprocess.run([sys.executable, str(SCRIPTS / name), *map(str, args)], capture_output=True, text=True)
    if result.returncode != 0:
        raise AssertionError(f"{name} exited {result.returncode}:\n{result.stdout}\n{result.stderr}")
    return result


class GalleryTest(ScratchTestCase):
    def test_small_gallery(self):
        run_script("gallery.py", "--out", self.scratch, "--size", 96, "--samples", 20000, "--quiet")
        for name in ("wave", "hills", "fern", "clover_fractal"):
            image = cifs.render.read_exr(self.scratch / f"{name}.exr")
            self.assertEqual((image.width, image.height), (96, 96), name)
            png = cifs.render.read_png(self.scratch / f"{name}.png")
            self.assertEqual(png.shape[:2], (96, 96), name)
            self.assertGreater(float(np.sum(image.channels["A"])), 0, f"{name}: nothing drawn")
        self.assertIn("<svg", (self.scratch / "wave.automaton.svg").read_text())
        # The fern's density holds the samples that landed on screen: all but a few, since the frame
        # is fitted to depth-6 points and the attractor reaches slightly beyond them.
        fern = cifs.render.read_exr(self.scratch / "fern.exr")
        self.assertLessEqual(int(np.sum(fern.channels["density"])), 20000)
        self.assertGreaterEqual(int(np.sum(fern.channels["density"])), 19900)
        self.assertEqual(sorted(p.name for p in self.scratch.iterdir() if p.name.startswith(".")), [],
                         "temporary files left behind")
        self.assertEqual([p.name for p in self.scratch.rglob("*.cifs-tmp.*")], [], "temporary files left behind")

    def test_clover_fractal_matches_the_command_line(self):
        # The script edits the experiment's image size only: the CLI on the same edited file writes
        # the same image.
        run_script("gallery.py", "--out", self.scratch, "--size", 64, "--quiet", "clover_fractal")
        spec = json.loads((EXAMPLES / "experiments" / "clover_fractal.json").read_text())
        spec.setdefault("render", {}).update(width=64, height=64)
        spec["outputs"] = {}
        edited = EXAMPLES / "experiments" / "clover_fractal.json"
        copy = self.scratch / "edited.json"
        text = json.dumps(spec).replace('"../', f'"{edited.parent.parent.as_posix()}/')
        copy.write_text(text)
        cli("render", copy, "-o", self.scratch / "cli.exr", "--quiet")
        ours = cifs.render.read_exr(self.scratch / "clover_fractal.exr")
        theirs = cifs.render.read_exr(self.scratch / "cli.exr")
        for channel in ("R", "G", "B", "A", "Z"):
            np.testing.assert_array_equal(ours.channels[channel], theirs.channels[channel], channel)

    def test_unknown_picture_is_refused(self):
        result = subprocess.run([sys.executable, str(SCRIPTS / "gallery.py"), "--out", str(self.scratch), "nope"],
                                capture_output=True, text=True)
        self.assertEqual(result.returncode, 2)
        self.assertIn("unknown picture 'nope'", result.stderr)


class SweepTest(ScratchTestCase):
    def rows(self):
        import csv
        with open(self.scratch / "sweep.csv", newline="") as table:
            return list(csv.DictReader(table))

    def test_small_sweep_and_the_command_line_agree(self):
        run_script("sweep.py", "--out", self.scratch, "--steps", 5, "--depth", 9, "--min-boxes", 100, "--quiet")
        self.assertGreater((self.scratch / "sweep.png").stat().st_size, 10000)
        rows = self.rows()
        values = [float(r["value"]) for r in rows]
        self.assertEqual(len(rows), 5)
        # Default: the last free coefficient, v2/V[1,2], NURBS value 1/8 (the cubic B-spline's vertex
        # rule 1/8, 6/8, 1/8), swept over ±0.8: the ends are not contractive, and the mirror values
        # 1/8 ± t give mirror-image curves, hence equal dimensions up to the grid.
        self.assertAlmostEqual(values[2], 0.125, delta=1e-15)
        self.assertIn("the perturbed system is not contractive with v2/V[1,2] = -0.675", rows[0]["note"])
        self.assertIn("the perturbed system is not contractive", rows[-1]["note"])
        dims = [float(r["dimension"]) for r in rows[1:4]]
        self.assertAlmostEqual(dims[1], 1.0, delta=0.03)  # the smooth NURBS curve
        self.assertGreater(dims[0], dims[1] + 0.03)  # rougher away from it
        self.assertAlmostEqual(dims[0], dims[2], delta=0.01)
        # The same curve as an experiment file, measured by the CLI on the same levels.
        row = rows[3]
        experiment = self.scratch / "swept.json"
        experiment.write_text(json.dumps({
            "shape": {"polygon": str(EXAMPLES / "shapes" / "clover.json"), "degree": 3},
            "perturbation": {"amplitude": 0, "values": {"v2/V[1,2]": float(row["value"])}},
            "evaluation": {"depth": 9}}))
        report = json.loads(cli("dimension", experiment, "--depth", 9, "--min-level", row["min_level"],
                                "--max-level", row["max_level"], "--json").stdout)
        self.assertEqual(report["points"], int(row["points"]))
        self.assertAlmostEqual(report["box_counting"]["dimension"], float(row["dimension"]), delta=1e-12)

    @unittest.skipUnless(shutil.which("mpirun") and importlib.util.find_spec("mpi4py"), "needs mpirun and mpi4py")
    def test_sweep_across_processes_writes_the_files_of_one(self):
        arguments = ["--steps", "5", "--depth", "8", "--min-boxes", "100"]
        run_script("sweep.py", "--out", self.scratch / "one", *arguments, "--quiet")
        mpirun = ["mpirun", "-n", "3", "--oversubscribe"] + (["--allow-run-as-root"] if os.geteuid() == 0 else [])
        result = subprocess.run(mpirun + [sys.executable, str(SCRIPTS / "sweep.py"), "--out",
                                          str(self.scratch / "three"), *arguments],
                                capture_output=True, text=True, timeout=600)
        self.assertEqual(result.returncode, 0, result.stderr)
        # One sweep shared by three processes (rank 0 reports every value once), not three sweeps.
        lines = result.stdout.splitlines()
        self.assertEqual([line.split(" ")[0] for line in lines if line.startswith("[")],
                         ["[1/5]", "[2/5]", "[3/5]", "[4/5]", "[5/5]"], result.stdout)
        self.assertEqual(sum(line.startswith("wrote") for line in lines), 1, result.stdout)
        # Three processes measured values 0 and 3, 1 and 4, 2: the table and the figure are those of one.
        for name in ("sweep.csv", "sweep.png"):
            self.assertEqual((self.scratch / "three" / name).read_bytes(), (self.scratch / "one" / name).read_bytes(),
                             name)

    def test_unknown_coefficient_is_refused(self):
        result = subprocess.run([sys.executable, str(SCRIPTS / "sweep.py"), "--out", str(self.scratch),
                                 "--coefficient", "nope"], capture_output=True, text=True)
        self.assertEqual(result.returncode, 2)
        self.assertIn("sweep.py: --coefficient: 'nope' is not a free coefficient (v2/V[1,1], v2/V[1,2])",
                      result.stderr)
        self.assertFalse((self.scratch / "sweep.csv").exists())


if __name__ == "__main__":
    unittest.main()
