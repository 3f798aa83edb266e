# SPDX-License-Identifier: MIT
"""Issue 33 through Python: a deep symbol killed the interpreter, a huge mask was converted for 22 s
before its refusal, write_points wrote nan and inf, and a huge depth was refused after minutes."""
import math
import os
import subprocess
import sys
import time
import unittest

import numpy as np

import cifs
from cifs import subdivision as sd
from support import EXAMPLES, SANITIZED, ScratchTestCase


class ReliabilityTest(ScratchTestCase):
    def assert_quick_refusal(self, call, needle, seconds=1.0):
        start = time.monotonic()
        with self.assertRaises(cifs.InvalidInput) as raised:
            call()
        self.assertLess(time.monotonic() - start, seconds)
        self.assertIn(needle, str(raised.exception))
        self.assertLess(len(str(raised.exception)), 300)  # the input is not echoed whole
        return raised.exception

    def test_constructor_given_a_list_of_lists(self):
        # Found by test_hostile.py: a constructor refusing an element of a list argument looked for it in
        # its first argument, the instance being made (not a Python object): a segmentation fault.
        code = "import cifs\ncifs.ifs.Coefficient([[0, 1], [1, 2]], 1, 1)"
        child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
        self.assertIn("cifs.InvalidInput", child.stderr)
        self.assertIn("Coefficient: transition[0]", child.stderr)
        self.assertEqual(child.returncode, 1, child.stderr[-2000:])

    def test_deep_symbols_are_refused(self):
        # Before the fix the stack overflow killed the interpreter (the test process) itself.
        for text in ["(" * 5000 + "1+z" + ")" * 5000, "-" * 100000 + "1"]:
            self.assert_quick_refusal(lambda: sd.parse_symbol(text), "nested within each other")
            self.assert_quick_refusal(lambda: sd.from_symbol(text), "nested within each other")

    def test_masks_are_bounded_before_conversion(self):
        self.assert_quick_refusal(lambda: sd.from_mask(np.zeros(10**7)),
                                  "mask: 10000000 coefficients exceed the limit of 512")
        self.assert_quick_refusal(lambda: sd.from_mask([0] * 10**6), "1000000 coefficients")
        self.assert_quick_refusal(lambda: sd.from_mask(np.zeros((2, 2, 2))), "an array of 3 dimensions")
        self.assertEqual(sd.from_mask([0.5, 1, 0.5]).mask, sd.from_mask(np.array([0.5, 1, 0.5])).mask)

    def test_writers_refuse_non_finite_numbers(self):
        for bad in (math.nan, math.inf, -math.inf):
            points = np.zeros((3, 2))
            points[1, 0] = bad
            for ext in ("json", "obj", "npy", "ply"):
                path = str(self.scratch / ("p." + ext))
                with self.assertRaises(cifs.InvalidInput) as raised:
                    cifs.io.write_points(path, points)
                self.assertIn("point 1 coordinate 0 is not a finite number", str(raised.exception))
                self.assertFalse(os.path.exists(path))

    @unittest.skipIf(SANITIZED,
                     "AddressSanitizer reserves more address space than the limit allows")
    def test_refused_allocation_is_named(self):
        # "MemoryError: std::bad_alloc" (7 calls of the audit): in a child with 3 GiB of address space.
        code = """
import resource
resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, 3 * 2**30))
import cifs
from cifs import automata, ifs
c = cifs.io.read_shape(%r)
a = automata.knot_automaton(c)
try:
    ifs.chaos_game(a, automata.initial_nets(a, c), samples=10**9, max_bytes=2**60)
except MemoryError as e:
    print(e)
""" % str(EXAMPLES / "shapes" / "cubic.json")
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
        self.assertIn("out of memory: the system refused an allocation", out.stdout, out.stderr)


if __name__ == "__main__":
    unittest.main()
