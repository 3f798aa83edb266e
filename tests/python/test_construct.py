#SPDX - License - Identifier : MIT
"""cifs.nurbs construction (make_compatible, ruled, extrude, revolve, loft, sweep) against the properties
that define each surface, computed here with numpy: rotations by Rodrigues' formula, the affine map of
parameters, the segments between curves, and the refusals of bad input."""
import math
import unittest

import numpy as np

import cifs
from cifs import nurbs
from support import assert_close

H = math.sqrt(0.5)
CIRCLE_KNOTS = [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1]
CIRCLE_WEIGHTS = [1, H, 1, H, 1, H, 1, H, 1]
SQUARE = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)


def rodrigues(x, axis, theta):
    """x (3-vector, from a point of the axis) turned by theta about the unit axis."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    return x * math.cos(theta) + np.cross(k, x) * math.sin(theta) + k * np.dot(k, x) * (1 - math.cos(theta))


def cubic(points):
    return nurbs.Curve(3, [0, 0, 0, 0, 0.5, 1, 1, 1, 1], np.asarray(points, float))


class ConstructTest(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(30)
        self.profile = cubic(rng.uniform(-1, 1, (5, 3)) + [3, 0, 0])
        self.other = nurbs.Curve(2, [1, 1, 1, 2, 4, 4, 4], rng.uniform(-1, 1, (4, 3)), rng.uniform(0.5, 2, 4))

    def test_make_compatible_keeps_the_points(self):
        a, b = nurbs.make_compatible([self.profile, self.other])
        self.assertEqual(a.degree, 3)
        self.assertTrue(a.rational and b.rational)
        assert_close(self, a.knots, b.knots, 0, "knots")
        for u in np.linspace(0, 1, 17):
            assert_close(self, nurbs.evaluate(a, u), nurbs.evaluate(self.profile, u), 1e-14)
            assert_close(self, nurbs.evaluate(b, u), nurbs.evaluate(self.other, 1 + 3 * u), 1e-13)

    def test_ruled_and_extrude(self):
        s = nurbs.ruled(self.profile, cubic(np.eye(5, 3)))
        other = cubic(np.eye(5, 3))
        for u in np.linspace(0, 1, 9):
            for v in (0, 0.3, 1):
                expected = (1 - v) * nurbs.evaluate(self.profile, u) + v * nurbs.evaluate(other, u)
                assert_close(self, s.evaluate(u, v), expected, 1e-14)
        wall = nurbs.extrude(self.other, [0, 0, 2])
        assert_close(self, wall.evaluate(2.5, 0.25), nurbs.evaluate(self.other, 2.5) + [0, 0, 0.5], 1e-14)

    def test_revolve_turns_each_point_by_the_arc_angle(self):
        axis_point, axis = np.array([0.5, -1, 0.25]), np.array([1, 2, 2]) / 3
        for angle in (2 * math.pi, math.pi / 2, 2.5):
            s = nurbs.revolve(self.other, axis_point, axis, angle)
            arcs = math.ceil(angle / (math.pi / 2) - 1e-12)
            phi = angle / arcs
            for u in (1, 2.2, 4):
                for v in np.linspace(0, 1, 13):
                    k = min(int(v * arcs), arcs - 1)
                    s_local = v * arcs - k
                    theta = k * phi + phi / 2 + 2 * math.atan(math.tan(phi / 4) * (2 * s_local - 1))
                    expected = axis_point + rodrigues(nurbs.evaluate(self.other, u) - axis_point, axis, theta)
                    assert_close(self, s.evaluate(u, v), expected, 1e-14)

    def test_loft_iso_curves_are_the_curves(self):
        circle = nurbs.Curve(2, CIRCLE_KNOTS, np.c_[SQUARE, np.zeros(9)], CIRCLE_WEIGHTS)
        rings = [nurbs.Curve(2, CIRCLE_KNOTS, np.c_[SQUARE * r, np.full(9, z)], CIRCLE_WEIGHTS)
                 for r, z in ((1, 0), (2, 1), (1.5, 3), (1, 4))]
        for degree_v in (1, 2, 3):
            s = nurbs.loft(rings, degree_v=degree_v, parametrization="centripetal")
            v = nurbs.loft_parameters(rings, "centripetal")
            self.assertEqual(s.degree, (2, degree_v))
            for ring, vk in zip(rings, v):
                iso = nurbs.iso_curve(s, nurbs.Direction.v, vk)
                for u in np.linspace(0, 1, 11):
                    assert_close(self, nurbs.evaluate(iso, u), nurbs.evaluate(ring, u), 1e-13)
        self.assertIsNotNone(circle)

    def test_sweep(self):
        quarter = nurbs.Curve(2, [0, 0, 0, 1, 1, 1], np.array([[5, 0, 0], [5, 5, 0], [0, 5, 0]], float), [1, H, 1])
        moved = nurbs.sweep(self.profile, quarter)
        self.assertEqual(moved.deviation, 0)
        start = nurbs.evaluate(quarter, 0)
        for u, v in ((0.2, 0.3), (0.9, 1)):
            expected = nurbs.evaluate(self.profile, u) + nurbs.evaluate(quarter, v) - start
            assert_close(self, moved.surface.evaluate(u, v), expected, 1e-14)
        profile = nurbs.Curve(1, [0, 0, 1, 1], np.array([[4.5, 0, 0], [5.5, 0, 1]], float))
        previous = math.inf
        for n in (5, 9, 17):
            carried = nurbs.sweep(profile, quarter, instances=n)
            self.assertLess(carried.deviation, previous / 8)
            previous = carried.deviation
        frames = nurbs.rotation_minimizing_frames(quarter, 5)
        self.assertEqual(frames.shape, (5, 6))
        assert_close(self, frames[:, 5], np.zeros(5), 1e-13)  # r (the Frenet normal at the start) stays in the plane

    def test_refusals(self):
        line = nurbs.Curve(1, [0, 0, 1, 1], np.array([[1, 0, 0], [1, 0, 1]], float))
        flat = nurbs.Curve(1, [0, 0, 1, 1], np.array([[0, 0], [1, 0]], float))
        cases = [
            (lambda: nurbs.make_compatible([]), "curves: none given"),
            (lambda: nurbs.make_compatible([line, flat]), "curves[1]: dimension 2"),
            (lambda: nurbs.loft([line]), "curves: 1 given"),
            (lambda: nurbs.loft([line, line]), "loft: degree_v 3 is outside 1 … 1"),
            (lambda: nurbs.extrude(line, [0, 0, 0]), "direction: the zero vector"),
            (lambda: nurbs.extrude(line, [0, 1]), "direction: 2 coordinates"),
            (lambda: nurbs.revolve(line, [0, 0, 0], [0, 0, 0], 1), "axis_direction: the zero vector"),
            (lambda: nurbs.revolve(line, [0, 0, 0], [0, 0, 1], 7), "angle: 7 is outside (0, 2π]"),
            (lambda: nurbs.revolve(line, [0, 0], [0, 0, 1], 1), "axis_point: 2 values, expected 3"),
            (lambda: nurbs.revolve(flat, [0, 0, 0], [0, 0, 1], 1), "profile: dimension 2"),
            (lambda: nurbs.sweep(line, line, instances=1), "instances: 1"),
            (lambda: nurbs.sweep(line, flat), "trajectory: dimension 2"),
        ]
        for call, message in cases:
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                call()
            self.assertIn(message, str(caught.exception))


class VolumeTest(unittest.TestCase):
    def test_evaluate_is_the_triple_sum_and_insertion_keeps_it(self):
        rng = np.random.default_rng(31)
        degree = (2, 1, 3)
        knots = ([0, 0, 0, 0.4, 1, 1, 1], [0, 0, 0.5, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1])
        points = rng.uniform(-1, 1, (4, 3, 4, 3))
        weights = rng.uniform(0.5, 2, (4, 3, 4))
        vol = nurbs.Volume(degree, knots, points, weights)
        self.assertEqual(vol.count, (4, 3, 4))

        def basis(d, t):  # every basis function of direction d at t, from the knot functions
            span = nurbs.find_span(knots[d], degree[d], t)
            full = np.zeros(len(knots[d]) - degree[d] - 1)
            full[span - degree[d]:span + 1] = nurbs.basis_functions(knots[d], degree[d], span, t)
            return full

        for u, v, w in ((0, 0, 0), (0.3, 0.7, 0.2), (1, 0.5, 1), (0.4, 0.25, 0.9)):
            N, M, L = basis(0, u), basis(1, v), basis(2, w)
            homogeneous = np.einsum("i,j,k,ijkc->c", N, M, L, np.concatenate(
                [points * weights[..., None], weights[..., None]], axis=3))
            expected = homogeneous[:3] / homogeneous[3]
            assert_close(self, vol.evaluate(u, v, w), expected, 1e-14)
            for direction in (0, 1, 2):
                finer = nurbs.insert_knot(vol, direction, 0.6, 1)
                self.assertEqual(finer.count[direction], vol.count[direction] + 1)
                assert_close(self, finer.evaluate(u, v, w), expected, 1e-14)
        with self.assertRaises(cifs.InvalidInput) as caught:
            nurbs.insert_knot(vol, 3, 0.5)
        self.assertIn("direction 3 is not u (0), v (1) or w (2)", str(caught.exception))
        with self.assertRaises(cifs.InvalidInput) as caught:
            nurbs.Volume(degree, knots, points[0])
        self.assertIn("points: expected (nu, nv, nw, dim)", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
