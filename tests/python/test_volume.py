# SPDX-License-Identifier: MIT
"""cifs.nurbs volumes beyond evaluation: knot operations, derivatives and grids against scipy's B-spline basis
(the tensor-product sum computed here), the volume automaton against numpy's Kronecker product, and volume
files read back."""
import unittest

import numpy as np
from scipy.interpolate import BSpline

import cifs
from cifs import automata, io, nurbs
from support import ScratchTestCase, assert_close, cli, cli_json

DEGREE = (2, 1, 3)
KNOTS = ([0, 0, 0, 0.4, 0.4, 1, 1, 1], [0, 0, 0.5, 1, 1], [-1, -1, -1, -1, 0.25, 1, 1, 1, 1])


def make_volume(seed=41):
    rng = np.random.default_rng(seed)
    points = rng.uniform(-1, 1, (5, 3, 5, 3))
    weights = rng.uniform(0.5, 2, (5, 3, 5))
    return nurbs.Volume(DEGREE, KNOTS, points, weights), points, weights


def reference(points, weights, u, v, w):
    """Σ N_i(u) M_j(v) L_k(w) w_ijk P_ijk / Σ … w_ijk with scipy's basis functions."""
    bases = []
    for d, t in enumerate((u, v, w)):
        n = len(KNOTS[d]) - DEGREE[d] - 1
        bases.append(BSpline(np.array(KNOTS[d], float), np.eye(n), DEGREE[d])(t))
    homogeneous = np.einsum("i,j,k,ijkc->c", *bases, np.concatenate([points * weights[..., None],
                                                                      weights[..., None]], axis=3))
    return homogeneous[:3] / homogeneous[3]


SAMPLES = ((0.0, 0.0, -1.0), (0.3, 0.7, 0.2), (1.0, 0.5, 1.0), (0.4, 0.25, -0.5), (0.9, 1.0, 0.6))


class VolumeOperationsTest(unittest.TestCase):
    def test_knot_operations_keep_the_volume(self):
        vol, points, weights = make_volume()
        for direction in (0, 1, 2):
            changed = {
                "refine": nurbs.refine(vol, direction, [0.45, 0.3, 0.8]),
                "elevate": nurbs.elevate_degree(vol, direction, 2),
                "insert then remove": nurbs.remove_knot(nurbs.insert_knot(vol, direction, 0.7, 1), direction,
                                                        0.7, 1, 1e-9).volume,
            }
            for name, other in changed.items():
                for u, v, w in SAMPLES:
                    with self.subTest(direction=direction, operation=name, at=(u, v, w)):
                        assert_close(self, other.evaluate(u, v, w), reference(points, weights, u, v, w), 1e-12)
        removal = nurbs.remove_knot(vol, 0, 0.4, 2, 0.0)
        self.assertEqual(removal.removed, 0)  # random data: the knot stays
        self.assertIn("VolumeRemoval(removed=0", repr(removal))

    def test_split_reverse_reparametrize_and_iso_surfaces(self):
        vol, points, weights = make_volume()
        first, second = nurbs.split(vol, 2, 0.5)
        backwards = nurbs.reverse(vol, 1)
        moved = nurbs.reparametrize(vol, 0, 2.0, 4.0)
        unit = nurbs.normalize_knots(vol)
        for u, v, w in SAMPLES:
            expected = reference(points, weights, u, v, w)
            assert_close(self, (first if w <= 0.5 else second).evaluate(u, v, w), expected, 1e-12)
            assert_close(self, backwards.evaluate(u, 1 - v, w), expected, 1e-12)
            assert_close(self, moved.evaluate(2 + 2 * u, v, w), expected, 1e-12)
            assert_close(self, unit.evaluate(u, v, (w + 1) / 2), expected, 1e-12)
            assert_close(self, nurbs.evaluate(nurbs.iso_surface(vol, 0, u), v, w), expected, 1e-12)
            assert_close(self, nurbs.evaluate(nurbs.iso_surface(vol, 1, v), u, w), expected, 1e-12)
            assert_close(self, nurbs.evaluate(nurbs.iso_surface(vol, 2, w), u, v), expected, 1e-12)

    def test_grid_and_derivatives(self):
        vol, points, weights = make_volume()
        us, vs, ws = [0.0, 0.4, 1.0], [0.5, 0.2], [-1.0, 0.3, 0.9, 1.0]
        grid = nurbs.evaluate_grid(vol, us, vs, ws)
        self.assertEqual(grid.shape, (3, 2, 4, 3))
        for a, u in enumerate(us):
            for b, v in enumerate(vs):
                for c, w in enumerate(ws):
                    assert_close(self, grid[a, b, c], reference(points, weights, u, v, w), 1e-12)
        order, at, h = 2, (0.3, 0.7, 0.2), 1e-6
        D = nurbs.derivatives(vol, *at, order)
        self.assertEqual(D.shape, ((order + 1) ** 3, 3))
        assert_close(self, D[0], reference(points, weights, *at), 1e-12)
        for d, row in enumerate((9, 3, 1)):  # ∂u, ∂v, ∂w: rows (1·3 + 0)·3 + 0, (0 + 1)·3 + 0, 1
            step = np.zeros(3)
            step[d] = h
            difference = (reference(points, weights, *(at + step)) - reference(points, weights, *(at - step))) / (2 * h)
            assert_close(self, D[row], difference, 1e-6)

    def test_bad_input_names_the_argument(self):
        vol, _, _ = make_volume()
        for call, message in (
                (lambda: nurbs.refine(vol, 3, [0.5]), "direction 3 is not u (0), v (1) or w (2)"),
                (lambda: nurbs.remove_knot(vol, 0, 0.4, 1, -1.0), "tolerance -1 must be non-negative"),
                (lambda: nurbs.remove_knot(vol, 0, 0.4, -1, 0.0), "times = -1 is negative"),
                (lambda: nurbs.iso_surface(vol, 1, 2.0), "parameter v = 2 is outside the domain [0, 1]"),
                (lambda: nurbs.split(vol, 2, 1.0), "direction w: "),
                (lambda: nurbs.evaluate_grid(vol, [0.5], [0.5], [5.0]), "parameter w = 5 is outside"),
                (lambda: nurbs.derivatives(vol, 0.5, 0.5, 0.5, -1), "derivative order -1")):
            with self.assertRaises(cifs.InvalidInput) as caught:
                call()
            self.assertIn(message, str(caught.exception))


class VolumeAutomatonTest(unittest.TestCase):
    def test_transitions_are_kronecker_products_and_nets_the_cells(self):
        vol, _, _ = make_volume()
        t = automata.tensor_automaton(vol)
        self.assertIn("VolumeAutomaton(", repr(t))
        fu, fv, fw = t.factors
        states = t.factor_states
        self.assertEqual(states.shape, (t.product.state_count, 3))
        labels = ["GHA", "GHR", "GBA", "GBR", "DHA", "DHR", "DBA", "DBR"]
        for tr in t.product.transitions:
            su, sv, sw = (int(x) for x in states[tr.source])
            iu, iv, iw = tr.child >> 2, (tr.child >> 1) & 1, tr.child & 1
            self.assertEqual(tr.label, labels[tr.child])
            expected = np.kron(np.kron(fu.matrix(su, iu), fv.matrix(sv, iv)), fw.matrix(sw, iw))
            np.testing.assert_array_equal(tr.matrix, expected)
        nets = automata.initial_nets(t, vol)
        self.assertEqual(len(nets), len(t.cells))
        self.assertEqual(nets[0].shape, (3 * 2 * 4, 4))
        self.assertEqual([automata.w_label(x) for x in ("G", "D", "x")], ["A", "R", "x"])


class VolumeFileTest(unittest.TestCase):
    def test_round_trip_and_refusals(self):
        vol, _, _ = make_volume()
        text = io.to_json(vol)
        self.assertTrue(text.startswith('{\n  "volume": {'))
        back = io.parse_volume_json(text, "v.json")
        self.assertEqual(back.count, vol.count)
        assert_close(self, back.P, vol.P, 1e-15)
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.parse_shape_json(text, "v.json")
        self.assertIn("v.json: a volume: read it as one", str(caught.exception))
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.parse_volume_json('{"volume": {"degree": [1, 1]}}', "v.json")
        self.assertIn("v.json: volume.degree: expected [du, dv, dw]", str(caught.exception))


class VolumeCliTest(ScratchTestCase):
    def test_info_and_eval_read_volume_files(self):
        vol, points, weights = make_volume()
        path = self.scratch / "v.json"
        path.write_text(io.to_json(vol))
        info = cli_json("info", path)
        self.assertEqual(info["type"], "volume")
        self.assertEqual(info["degree"], list(DEGREE))
        self.assertEqual(info["control_points"], [5, 3, 5])
        self.assertEqual(info["domain"], [[0, 1], [0, 1], [-1, 1]])
        self.assertEqual(info["segments"], [2, 2, 2])
        self.assertTrue(info["rational"])
        out = cli_json("eval", path, "--at", "0.3,0.7,0.2", "--samples", 3)["points"]
        self.assertEqual(len(out), 1 + 27)
        assert_close(self, out[0], reference(points, weights, 0.3, 0.7, 0.2), 1e-12)
        # The 3×3×3 grid, w fastest: row (a·3 + b)·3 + c at (u_a, v_b, w_c).
        grid = nurbs.evaluate_grid(vol, [0, 0.5, 1], [0, 0.5, 1], [-1, 0, 1]).reshape(27, 3)
        np.testing.assert_array_equal(np.array(out[1:]), grid)
        for args, message in ((("--at", "0.5,0.5"), "--at '0.5,0.5': a volume takes U,V,W"),
                              (("--at", "0.5,0.5,3"), "parameter w = 3 is outside the domain [-1, 1]")):
            result = cli("eval", path, *args, check=False)
            self.assertEqual(result.returncode, 2)
            self.assertEqual(len(result.stderr.strip().splitlines()), 1)
            self.assertIn(message, result.stderr)
        result = cli("attractor", path, "--depth", 1, check=False)
        self.assertEqual(result.returncode, 2)
        self.assertIn("a volume: read it as one", result.stderr)


if __name__ == "__main__":
    unittest.main()
