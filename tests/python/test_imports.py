# SPDX-License-Identifier: MIT
"""Shapes from other tools through cifs.io: several shapes in a file (index), trimmed surfaces
(ignore_trim), geomdl exports; against the command line on the same files."""
import unittest

import numpy as np

import cifs
from cifs import io, nurbs
from support import EXAMPLES, ScratchTestCase, cli, cli_json

TWO_CURVES = ("v 0 0 0\nv 2 0 0\ncstype bspline\ndeg 1\ncurv 0 1 -2 -1\nparm u 0 0 1 1\nend\n"
              "v 0 0 0\nv 1 2 0\nv 2 0 0\ndeg 2\ncurv 0 1 -3 -2 -1\nparm u 0 0 0 1 1 1\nend\n")
TRIMMED = ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\ncstype bspline\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\n"
           "parm u 0 0 1 1\nparm v 0 0 1 1\ntrim 0 3 1\nend\n")


class ImportTest(ScratchTestCase):
    def test_index_chooses_one_of_several_shapes(self):
        path = self.scratch / "two.obj"
        path.write_text(TWO_CURVES)
        shapes = io.read_shapes(path)
        self.assertEqual([s.degree for s in shapes], [1, 2])
        with self.assertRaisesRegex(cifs.InvalidInput, "holds 2 shapes .*--index N, N from 0 to 1"):
            io.read_shape(path)
        quadratic = io.read_shape(path, index=1)
        np.testing.assert_array_equal(quadratic.P, shapes[1].P)
        # The same points as the command line's.
        expected = cli_json("eval", path, "--index", 1, "--samples", 5)["points"]
        us = np.linspace(0, 1, 5)
        np.testing.assert_array_equal(np.array([nurbs.evaluate(quadratic, u) for u in us]), expected)

    def test_ignore_trim(self):
        with self.assertRaisesRegex(cifs.InvalidInput, "trimmed surfaces are not supported"):
            io.parse_obj(TRIMMED, "t.obj")
        (surface,) = io.parse_obj(TRIMMED, "t.obj", ignore_trim=True)
        np.testing.assert_array_equal(nurbs.evaluate(surface, 0.5, 0.5), [0.5, 0.5, 0.25])

    def test_geomdl_example_is_the_unit_circle(self):
        curve = io.read_shape(EXAMPLES / "shapes" / "geomdl_curve.json")
        points = np.array([nurbs.evaluate(curve, u) for u in np.linspace(0, 1, 101)])
        np.testing.assert_allclose(np.hypot(points[:, 0], points[:, 1]), 1, rtol=0, atol=1e-15)
        self.assertEqual(cli("info", EXAMPLES / "shapes" / "geomdl_curve.json").returncode, 0)


if __name__ == "__main__":
    unittest.main()
