# SPDX-License-Identifier: MIT
"""Shared helpers of the Python tests: the CLI, the example files, scratch folders, comparisons.

ctest sets PYTHONPATH (the build tree's package), CIFS_CLI (the `cifs` executable), CIFS_SOURCE_DIR
and CIFS_EXAMPLES_DIR (tests/CMakeLists.txt).
"""
import json
import os
import subprocess
import tempfile
import unittest
from pathlib import Path

import numpy as np

SOURCE_DIR = Path(os.environ.get("CIFS_SOURCE_DIR", Path(__file__).resolve().parents[2]))
EXAMPLES = Path(os.environ.get("CIFS_EXAMPLES_DIR", SOURCE_DIR / "examples"))
CLI = os.environ.get("CIFS_CLI", "")
# A sanitized build (tests/CMakeLists.txt preloads the ASan runtime into the interpreter): calls run 10–30×
# slower. Its run looks for memory errors, which a sample of the cases finds as well as all of them; the
# Release run checks every case.
SANITIZED = "asan" in os.environ.get("LD_PRELOAD", "")


def sampled(cases, every=7):
    """All the cases in Release; sanitized, the first and every `every`-th after it (a CLI call there costs
    ~0.3 s of ASan start-up and its computation 10–30×). Choose `every` prime to the lengths of the loops
    that made the list, so that each value of each loop is still drawn."""
    cases = list(cases)
    return cases[:1] + cases[1::every] if SANITIZED else cases


# Chaikin's scheme = the uniform quadratic B-spline: its two knot-doubling matrices (rows sum to 1).
CHAIKIN_G = np.array([[0.75, 0.25, 0], [0.25, 0.75, 0], [0, 0.75, 0.25]])
CHAIKIN_D = np.array([[0.25, 0.75, 0], [0, 0.75, 0.25], [0, 0.25, 0.75]])


def chaikin():
    """The one-state automaton of Chaikin's scheme, built from scratch (transitions G, D; one initial entry)."""
    import cifs
    a = cifs.automata.Automaton()
    s = a.add_state(3, "uniform")
    a.add_transition(s, s, CHAIKIN_G, "G")
    a.add_transition(s, s, CHAIKIN_D, "D")
    a.add_initial(s)
    return a


def cli(*args, check=True):
    """Runs the `cifs` command line; returns the CompletedProcess (text). Skips when no CLI is built."""
    if not CLI:
        raise unittest.SkipTest("CIFS_CLI is not set (the cifs command line was not built)")
    result = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"cifs {' '.join(map(str, args))} exited {result.returncode}: {result.stderr}")
    return result


def cli_json(*args):
    """Runs the CLI and parses its standard output as JSON."""
    return json.loads(cli(*args).stdout)


class ScratchTestCase(unittest.TestCase):
    """A test case with a fresh scratch folder `self.scratch` (a Path), removed afterwards."""

    def setUp(self):
        self._scratch = tempfile.TemporaryDirectory(prefix="cifs-python-")
        self.scratch = Path(self._scratch.name)

    def tearDown(self):
        self._scratch.cleanup()


def assert_close(test, actual, expected, rel=1e-12, what="values"):
    """|actual − expected| ≤ rel·max(1, max |expected|), elementwise, with shapes equal."""
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    test.assertEqual(actual.shape, expected.shape, f"{what}: shapes differ")
    scale = max(1.0, float(np.max(np.abs(expected))) if expected.size else 1.0)
    error = float(np.max(np.abs(actual - expected))) if expected.size else 0.0
    test.assertLessEqual(error, rel * scale, f"{what}: deviation {error:.3e} > {rel:.0e}·{scale:.3g}")
