# SPDX-License-Identifier: MIT
"""cifs.nurbs against the `cifs` command line on the same shape files, and against identities
(knot insertion keeps the curve, blossom diagonal = point, basis sums, finite differences)."""
import json
import unittest

import numpy as np

import cifs
from cifs import io, nurbs
from support import EXAMPLES, ScratchTestCase, assert_close, cli, cli_json

SHAPES = EXAMPLES / "shapes"
CURVES = ("cubic", "circle", "closed_cubic", "wave")
CUBIC_KNOTS = [0, 0, 0, 0, 1, 2, 4, 4, 4, 4]
CUBIC_POINTS = np.array([[0, 0, 0], [1, 2, 0], [3, 3, 1], [4, 0, 0], [6, 1, 2], [7, 3, 0]], float)


def shape(name):
    return io.read_shape(SHAPES / f"{name}.json")


def cox_de_boor(curve, u):
    """Σ N_j(u) P_j from the knot functions alone (homogeneous sum, then projected)."""
    span = nurbs.find_span(curve.knots, curve.degree, u)
    N = nurbs.basis_functions(curve.knots, curve.degree, span, u)
    row = N @ curve.P[span - curve.degree:span + 1]
    return row[:-1] / row[-1] if curve.rational else row


class KnotTest(unittest.TestCase):
    def test_span_multiplicity_breakpoints_domain(self):
        self.assertEqual(nurbs.find_span(CUBIC_KNOTS, 3, 0.0), 3)
        self.assertEqual(nurbs.find_span(CUBIC_KNOTS, 3, 1.5), 4)
        self.assertEqual(nurbs.find_span(CUBIC_KNOTS, 3, 4.0), 5)  # the end belongs to the last span
        self.assertEqual(nurbs.multiplicity(CUBIC_KNOTS, 4), 4)
        self.assertEqual(nurbs.multiplicity(CUBIC_KNOTS, 3), 0)
        self.assertEqual(nurbs.breakpoints(CUBIC_KNOTS, 3).tolist(), [0, 1, 2, 4])
        self.assertEqual(nurbs.domain(CUBIC_KNOTS, 3), (0.0, 4.0))
        self.assertEqual(nurbs.control_count(CUBIC_KNOTS, 3), 6)
        nurbs.validate_knots(CUBIC_KNOTS, 3, 6)
        nurbs.validate_degree(3)

    def test_basis_partition_of_unity_and_derivatives(self):
        for u in (0.0, 0.3, 1.0, 2.7, 4.0):
            span = nurbs.find_span(CUBIC_KNOTS, 3, u)
            N = nurbs.basis_functions(CUBIC_KNOTS, 3, span, u)
            self.assertEqual(N.shape, (4,))
            self.assertAlmostEqual(float(N.sum()), 1.0, places=14)
            D = nurbs.basis_derivatives(CUBIC_KNOTS, 3, span, u, 4)
            self.assertEqual(D.shape, (5, 4))
            assert_close(self, D[0], N, what="row 0 = basis")
            assert_close(self, D[4], np.zeros(4), what="4th derivative of a cubic")
            self.assertAlmostEqual(float(D[1].sum()), 0.0, places=12)
            # Blossom weights at (u, u, u) are the basis functions.
            assert_close(self, nurbs.blossom_weights(CUBIC_KNOTS, 3, span, [u] * 3), N, rel=1e-14)
        h, u = 1e-6, 1.3
        fd = (nurbs.basis_functions(CUBIC_KNOTS, 3, 4, u + h) - nurbs.basis_functions(CUBIC_KNOTS, 3, 4, u - h))
        fd /= 2 * h
        assert_close(self, nurbs.basis_derivatives(CUBIC_KNOTS, 3, 4, u, 1)[1], fd, rel=1e-8)

    def test_periodic_knots_are_the_closed_curves_knots(self):
        c = shape("closed_cubic")
        np.testing.assert_array_equal(nurbs.periodic_knots(nurbs.defining_knots(c), c.degree), c.knots)
        self.assertEqual(nurbs.periodic_knots([0, 1, 2], 1).tolist(), [-1, 0, 1, 2, 3])

    def test_bad_knot_inputs(self):
        cases = [
            (lambda: nurbs.validate_knots([0, 1, 0.5, 2], 1, 2), "knots[2]: 0.5 is less than the previous knot 1"),
            (lambda: nurbs.validate_degree(0), "degree: degree 0 is outside [1, 64]"),
            (lambda: nurbs.find_span([0, 0, 1], 1, 0.5),
             "knots: 1 control points are too few for degree 1 (need at least 2)"),
            (lambda: nurbs.find_span(CUBIC_KNOTS, 3, float("nan")), "u is not finite"),
            (lambda: nurbs.basis_functions(CUBIC_KNOTS, 3, 2, 0.5), "span 2 is outside 3 … 6 (degree 3, 10 knots)"),
            (lambda: nurbs.basis_functions(CUBIC_KNOTS, 3, 6, 0.5), "span 6 is empty: knots[6] = knots[7]"),
            (lambda: nurbs.blossom_weights(CUBIC_KNOTS, 3, 4, [1, 2]), "blossom: 2 arguments given, degree 3 takes 3"),
            (lambda: nurbs.basis_derivatives(CUBIC_KNOTS, 3, 4, 1.5, -1), "derivative order -1 is outside 0 … 64"),
            (lambda: nurbs.periodic_knots([1], 2), "breakpoints: 1 given, need at least 2"),
            (lambda: nurbs.periodic_knots([1, 1], 2), "breakpoints: the period is empty"),
            (lambda: nurbs.segment_window(CUBIC_KNOTS, 3, 9), "span 9 is not a non-empty span of the domain"),
            (lambda: nurbs.subdivision_matrix([1, 0, 1], 2, nurbs.Half.G),
             "window[1]: the central interval must be positive"),
            (lambda: nurbs.child_window([1, 1], 2, nurbs.Half.D), "window: 2 inter-knots given, degree 2 takes 3"),
            (lambda: nurbs.uniform_parameters((0, 1), -1), "count -1 is negative"),
        ]
        for call, message in cases:
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                call()
            self.assertEqual(str(caught.exception), message)


class CurveTest(ScratchTestCase):
    def test_constructor_matches_the_shape_file(self):
        c = nurbs.Curve(3, CUBIC_KNOTS, CUBIC_POINTS)
        f = shape("cubic")
        np.testing.assert_array_equal(c.P, f.P)
        np.testing.assert_array_equal(c.knots, f.knots)
        self.assertEqual((c.degree, c.rational, c.closed), (3, False, False))
        self.assertIn("Curve(degree=3", repr(c))
        closed = shape("closed_cubic")
        again = nurbs.Curve(closed.degree, nurbs.defining_knots(closed), nurbs.cartesian_points(closed), closed=True)
        np.testing.assert_array_equal(again.P, closed.P)
        np.testing.assert_array_equal(again.knots, closed.knots)
        circle = shape("circle")
        again = nurbs.Curve(2, circle.knots, nurbs.cartesian_points(circle), weights=nurbs.weights(circle))
        np.testing.assert_array_equal(again.P, circle.P)
        with self.assertRaises(AttributeError):
            c.degree = 2  # read-only

    def test_info_matches_the_cli(self):
        for name in CURVES:
            with self.subTest(shape=name):
                c, info = shape(name), cli_json("info", SHAPES / f"{name}.json")
                self.assertEqual(info["type"], "curve")
                self.assertEqual(info["degree"], c.degree)
                self.assertEqual(info["dimension"], nurbs.dimension(c))
                self.assertEqual(info["control_points"], nurbs.distinct_count(c))
                self.assertEqual(info["knots"], len(nurbs.defining_knots(c)))
                self.assertEqual(info["rational"], c.rational)
                self.assertEqual(info["closed"], c.closed)
                self.assertEqual(list(info["domain"]), list(nurbs.domain(c)))
                self.assertEqual(info["segments"], nurbs.segment_count(c))
                self.assertEqual(nurbs.cartesian_points(c).shape, (nurbs.distinct_count(c), nurbs.dimension(c)))
                self.assertEqual(nurbs.weights(c).shape, (nurbs.distinct_count(c),))

    def test_evaluate_matches_cli_eval(self):
        for name in CURVES:
            with self.subTest(shape=name):
                c = shape(name)
                start, end = nurbs.domain(c)
                at = [start, 0.3 * start + 0.7 * end, end]
                if c.closed:
                    at.append(end + 0.25 * (end - start))  # wrapped into the period
                args = [a for u in at for a in ("--at", repr(u))]
                expected = np.array(cli_json("eval", SHAPES / f"{name}.json", *args, "--samples", 33)["points"])
                us = np.concatenate([at, nurbs.uniform_parameters(nurbs.domain(c), 33)])
                np.testing.assert_array_equal(nurbs.evaluate(c, us), expected)
                np.testing.assert_array_equal(nurbs.evaluate(c, list(us)), expected)
                # One parameter goes through de Boor's triangle, many through the basis form.
                assert_close(self, nurbs.evaluate(c, float(at[1])), expected[1], what="de Boor")

    def test_evaluation_routes_agree(self):
        for name in CURVES:
            c = shape(name)
            for u in nurbs.uniform_parameters(nurbs.domain(c), 17):
                with self.subTest(shape=name, u=u):
                    point = nurbs.evaluate(c, u)
                    assert_close(self, nurbs.evaluate_basis(c, u), point, what="basis form")
                    assert_close(self, cox_de_boor(c, u), point, what="knot functions")
                    self.assertEqual(nurbs.domain_parameter(c, u), u)
        circle = shape("circle")
        radii = np.linalg.norm(nurbs.evaluate(circle, nurbs.uniform_parameters(nurbs.domain(circle), 101)), axis=1)
        assert_close(self, radii, np.ones(101), rel=1e-15, what="circle radius")
        closed = shape("closed_cubic")
        start, end = nurbs.domain(closed)
        self.assertAlmostEqual(nurbs.domain_parameter(closed, end + 1.0), start + 1.0, places=14)

    def test_derivatives_match_finite_differences(self):
        h = 1e-5
        for name in CURVES:
            c = shape(name)
            start, end = nurbs.domain(c)
            u = start + 0.37 * (end - start)
            D = nurbs.derivatives(c, u, 2)
            with self.subTest(shape=name):
                self.assertEqual(D.shape, (3, nurbs.dimension(c)))
                assert_close(self, D[0], nurbs.evaluate(c, u), what="order 0")
                fd1 = (nurbs.evaluate(c, u + h) - nurbs.evaluate(c, u - h)) / (2 * h)
                fd2 = (nurbs.evaluate(c, u + h) - 2 * nurbs.evaluate(c, u) + nurbs.evaluate(c, u - h)) / h**2
                assert_close(self, D[1], fd1, rel=1e-8, what="first derivative")
                assert_close(self, D[2], fd2, rel=1e-4, what="second derivative")

    def test_blossom_identities(self):
        for name in CURVES:
            c = shape(name)
            d = c.degree
            with self.subTest(shape=name):
                for u in nurbs.uniform_parameters(nurbs.domain(c), 9):
                    assert_close(self, nurbs.to_cartesian(c, nurbs.blossom(c, [u] * d)), nurbs.evaluate(c, u))
                # Control point i = blossom(t_{i+1}, …, t_{i+d}) on any span of its support.
                span = nurbs.find_span(c.knots, d, 0.5 * sum(nurbs.domain(c)))
                for i in range(span - d, span + 1):
                    assert_close(self, nurbs.blossom(c, c.knots[i + 1:i + d + 1], span), c.P[i], what=f"P[{i}]")
                # Symmetric.
                args = [nurbs.domain(c)[0] + 0.1 * k for k in range(d)]
                np.testing.assert_array_equal(nurbs.blossom(c, args, span), nurbs.blossom(c, args[::-1], span))

    def test_insertion_matches_cli_insert_and_keeps_the_curve(self):
        for name, knots in (("cubic", [0.5, 3, 3]), ("circle", [0.25, 2.5]), ("closed_cubic", [0.5, 5]),
                            ("wave", [2, 2])):
            with self.subTest(shape=name):
                c = shape(name)
                args = [a for u in knots for a in ("--knot", u)]
                # The same text: rational rows go through Cartesian points in the file format.
                refined = nurbs.refine(c, knots)
                self.assertEqual(io.to_json(refined), cli("insert", SHAPES / f"{name}.json", *args).stdout)
                us = nurbs.uniform_parameters(nurbs.domain(c), 101)
                assert_close(self, nurbs.evaluate(refined, us), nurbs.evaluate(c, us), what="refined curve")
                mid = nurbs.refine_midpoints(c)
                self.assertEqual(io.to_json(mid), cli("insert", SHAPES / f"{name}.json", "--midpoints").stdout)
                self.assertEqual(nurbs.segment_count(mid), 2 * nurbs.segment_count(c))
                once = nurbs.insert_knot(c, knots[0], 1)
                self.assertEqual(nurbs.multiplicity(once.knots, knots[0]),
                                 nurbs.multiplicity(c.knots, knots[0]) + 1)
                assert_close(self, nurbs.evaluate(once, us), nurbs.evaluate(c, us), what="insert_knot")

    def test_split_elevate_remove_keep_the_curve(self):
        for name in CURVES:
            c = shape(name)
            us = nurbs.uniform_parameters(nurbs.domain(c), 41)
            with self.subTest(shape=name):
                pieces = nurbs.split_bezier(c)
                self.assertEqual(len(pieces), nurbs.segment_count(c))
                for piece in pieces:
                    a, b = nurbs.domain(piece)
                    for u in (a, 0.5 * (a + b), b):
                        assert_close(self, nurbs.evaluate(piece, u), nurbs.evaluate(c, u), what="Bézier piece")
                raised = nurbs.elevate_degree(c, 2)
                self.assertEqual(raised.degree, c.degree + 2)
                assert_close(self, nurbs.evaluate(raised, us), nurbs.evaluate(c, us), what="elevated")
        c = shape("cubic")
        removal = nurbs.remove_knot(nurbs.insert_knot(c, 3.0, 2), 3.0, 2, 1e-9)
        self.assertEqual(removal.removed, 2)
        self.assertLessEqual(removal.deviation_bound, 1e-9)
        np.testing.assert_array_equal(removal.curve.knots, c.knots)
        assert_close(self, removal.curve.P, c.P, rel=1e-12, what="removed")
        self.assertEqual(nurbs.remove_knot(c, 2.0, 1, 0.0).removed, 0)  # a real knot cannot go at zero tolerance
        self.assertIn("Removal(removed=2", repr(removal))

    def test_uniform_bspline(self):
        polygon = np.array([[0, 0], [1, 2], [3, 2], [4, 0], [2, -1]], float)
        closed = nurbs.uniform_bspline(polygon, 3, True)
        self.assertTrue(closed.closed)
        np.testing.assert_array_equal(nurbs.defining_knots(closed), np.arange(6.0))
        np.testing.assert_array_equal(nurbs.cartesian_points(closed), polygon)
        opened = nurbs.uniform_bspline(polygon, 2, False)
        np.testing.assert_array_equal(opened.knots, [0, 0, 0, 1, 2, 3, 3, 3])
        np.testing.assert_array_equal(nurbs.evaluate(opened, 0.0), polygon[0])
        # The uniform cubic at a breakpoint is (P_{i−1} + 4 P_i + P_{i+1}) / 6 (u = 0 at P_1).
        assert_close(self, nurbs.evaluate(closed, 1.0), (polygon[1] + 4 * polygon[2] + polygon[3]) / 6)

    def test_bad_curves(self):
        pts = np.zeros((2, 2))
        cases = [
            (lambda: nurbs.Curve(0, [0, 1], np.zeros((1, 2))), "degree: degree 0 is outside [1, 64]"),
            (lambda: nurbs.Curve(1, [0, 1, 0.5, 2], pts), "knots[2]: 0.5 is less than the previous knot 1"),
            (lambda: nurbs.Curve(1, [0, 0, 1, 1], pts, weights=[1, -1]),
             "weights[1]: weight -1 is not a positive finite number"),
            (lambda: nurbs.Curve(1, [0, 0, 1, 1], pts, weights=[1, 1, 1]), "weights: 3 weights given for 2 points"),
            (lambda: nurbs.Curve(1, [0, 0, 1, 1], np.zeros(2)),
             "points: expected a 2-D array (n, dim), got shape (2,)"),
            (lambda: nurbs.Curve(1, [0, 0, 1, 1], pts, weights=np.ones((2, 1))),
             "weights: expected a 1-D array, got shape (2, 1)"),
            (lambda: nurbs.Curve(2, [1, 1, 1], pts, closed=True), "knots: the period [1, 1] is empty"),
            (lambda: nurbs.evaluate(shape("cubic"), 5.0), "parameter 5 is outside the domain [0, 4]"),
            (lambda: nurbs.evaluate(shape("cubic"), [1.0, -1.0]), "parameter -1 is outside the domain [0, 4]"),
            (lambda: nurbs.derivatives(shape("cubic"), 1.0, -2), "derivative order -2 is outside 0 … 64"),
            (lambda: nurbs.blossom(shape("cubic"), [1, 2]), "the blossom of a degree-3 curve takes 3 arguments, 2 given"),
            (lambda: nurbs.insert_knot(shape("cubic"), 9.0), "knot 9 is outside the domain [0, 4]"),
            (lambda: nurbs.insert_knot(shape("cubic"), 1.0, 0), "the knot count times = 0 must be at least 1"),
            (lambda: nurbs.remove_knot(shape("closed_cubic"), 1.0, 1, 0.0),
             "remove: knot removal on closed curves is not supported"),
            (lambda: nurbs.uniform_bspline(np.zeros((2, 2)), 3, False),
             "points: a clamped curve of degree 3 needs at least 4 control points, got 2"),
        ]
        for call, message in cases:
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                call()
            self.assertEqual(str(caught.exception), message)

    def test_errors_match_the_cli(self):
        bad = self.scratch / "bad.json"
        bad.write_text(json.dumps({"curve": {"degree": 2, "knots": [0, 0, 0, 1, 1], "points": [[0, 0], [1, 1]]}}))
        expected = cli("info", bad, check=False).stderr.strip().removeprefix("cifs: ")
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.read_shape(bad)
        self.assertEqual(str(caught.exception), expected)
        self.assertTrue(expected.startswith(str(bad)))
        with self.assertRaises(cifs.InvalidInput) as caught:
            nurbs.Curve(2, [0, 0, 0, 1, 1], np.array([[0, 0], [1, 1]], float))
        self.assertEqual(f"{bad}: curve.{caught.exception}", expected)
        # Outside the domain: the CLI's line without its prefix and the file it names.
        expected = cli("eval", SHAPES / "cubic.json", "--at", "5", check=False).stderr.strip()
        with self.assertRaises(cifs.InvalidInput) as caught:
            nurbs.evaluate(shape("cubic"), 5.0)
        self.assertEqual(f"cifs: {SHAPES / 'cubic.json'}: {caught.exception}", expected)


class AttractorMethodTest(unittest.TestCase):
    """curve.attractor / surface.attractor know whether the shape is rational: Cartesian points at the
    dyadic parameters (Cox–de Boor, cox_de_boor above, the independent route)."""

    @staticmethod
    def dyadic(breaks, depth, end):
        n = 2 ** depth
        us = [a + (b - a) * j / n for a, b in zip(breaks[:-1], breaks[1:]) for j in range(n)]
        return us + [breaks[-1]] if end else us

    def test_curves_rational_or_not_open_or_closed(self):
        weights = [1, 3, 0.5, 2, 1, 0.7]
        for rational in (False, True):
            curve = nurbs.Curve(3, CUBIC_KNOTS, CUBIC_POINTS, weights if rational else None)
            points = curve.attractor(4)
            us = self.dyadic(nurbs.breakpoints(curve.knots, curve.degree), 4, True)
            self.assertEqual(points.shape, (len(us), 3))  # z is a coordinate, never a weight
            assert_close(self, points, np.array([cox_de_boor(curve, u) for u in us]), 1e-12)
        closed = shape("closed_cubic")
        us = self.dyadic(nurbs.breakpoints(closed.knots, closed.degree), 3, False)
        assert_close(self, closed.attractor(3), closed.evaluate(us), 1e-12)
        with self.assertRaisesRegex(cifs.InvalidInput, "depth -1 is negative"):
            curve.attractor(-1)

    def test_a_rational_surface_gives_its_cartesian_quad_mesh(self):
        self.assertTrue(shape("saddle").rational)
        hills = shape("saddle")  # rational: weights up to 2
        mesh = hills.attractor(2)
        us = self.dyadic(nurbs.breakpoints(hills.knots[0], hills.degree[0]), 2, True)
        vs = self.dyadic(nurbs.breakpoints(hills.knots[1], hills.degree[1]), 2, True)
        grid = np.array([hills.evaluate(u, v) for u in us for v in vs])
        assert_close(self, mesh.vertices, grid, 1e-12)


class SurfaceTest(unittest.TestCase):
    def setUp(self):
        self.saddle = shape("saddle")
        net = np.array([[[0, 0, 0], [0, 2, 1]], [[1, 0, 2], [1, 2, 0]], [[2, 0, 0], [2, 2, 1]]], float)
        self.grid = nurbs.Surface((2, 1), ([0, 0, 0, 1, 1, 1], [0, 0, 2, 2]), net)

    def test_constructor_forms(self):
        s = self.saddle
        self.assertEqual(s.count, (4, 3))
        self.assertEqual(s.degree, (2, 2))
        self.assertTrue(s.rational)
        points = nurbs.cartesian_points(s)
        w = nurbs.weights(s)
        a = nurbs.Surface(s.degree, s.knots, points.reshape(4, 3, 3), weights=w.reshape(4, 3))
        b = nurbs.Surface(s.degree, s.knots, points, weights=w, count=(4, 3))
        for other in (a, b):
            np.testing.assert_array_equal(other.P, s.P)
            np.testing.assert_array_equal(other.knots[0], s.knots[0])
            np.testing.assert_array_equal(other.knots[1], s.knots[1])
        self.assertEqual(w.tolist(), [1, 1, 1, 1, 2, 1, 1, 1, 1, 1, 1, 1])
        self.assertEqual(nurbs.dimension(s), 3)
        self.assertIn("Surface(degree=(2, 2)", repr(s))

    def test_info_and_eval_match_the_cli(self):
        for name, s in (("saddle", self.saddle),):
            info = cli_json("info", SHAPES / f"{name}.json")
            self.assertEqual(info["type"], "surface")
            self.assertEqual(info["control_points"], list(s.count))
            self.assertEqual(info["domain"], [list(nurbs.domain(s, nurbs.Direction.u)),
                                              list(nurbs.domain(s, nurbs.Direction.v))])
            expected = np.array(cli_json("eval", SHAPES / f"{name}.json", "--at", "0.5,0.25", "--samples", 7)["points"])
            np.testing.assert_array_equal(nurbs.evaluate(s, 0.5, 0.25), expected[0])
            us = nurbs.uniform_parameters(nurbs.domain(s, nurbs.Direction.u), 7)
            vs = nurbs.uniform_parameters(nurbs.domain(s, nurbs.Direction.v), 7)
            np.testing.assert_array_equal(nurbs.evaluate_grid(s, us, vs), expected[1:].reshape(7, 7, -1))

    def test_grid_equals_pointwise_evaluation(self):
        for s in (self.saddle, self.grid):
            us = [0.0, 0.3, 1.0, 1.7][:3 if s is self.grid else 4]
            vs = [0.0, 0.4, 1.0]
            G = nurbs.evaluate_grid(s, us, vs)
            self.assertEqual(G.shape, (len(us), len(vs), 3))  # (nu, nv, dim), as Surface takes its points
            for a, u in enumerate(us):
                for b, v in enumerate(vs):
                    assert_close(self, G[a, b], nurbs.evaluate(s, u, v))

    def test_derivatives_and_normal(self):
        h = 1e-5
        for s in (self.saddle, self.grid):
            u, v = 0.6, 0.3
            D = nurbs.derivatives(s, u, v, 2)
            self.assertEqual(D.shape, (9, 3))
            assert_close(self, D[0], nurbs.evaluate(s, u, v), what="order 0")
            Su = (nurbs.evaluate(s, u + h, v) - nurbs.evaluate(s, u - h, v)) / (2 * h)
            Sv = (nurbs.evaluate(s, u, v + h) - nurbs.evaluate(s, u, v - h)) / (2 * h)
            assert_close(self, D[3], Su, rel=1e-8, what="S_u")  # row k·(order+1) + l
            assert_close(self, D[1], Sv, rel=1e-8, what="S_v")
            n = np.cross(D[3], D[1])
            assert_close(self, nurbs.normal(s, u, v), n / np.linalg.norm(n), what="normal")

    def test_insertion_matches_cli_and_keeps_the_surface(self):
        path = SHAPES / "saddle.json"
        us = nurbs.uniform_parameters(nurbs.domain(self.saddle, nurbs.Direction.u), 9)
        vs = nurbs.uniform_parameters(nurbs.domain(self.saddle, nurbs.Direction.v), 9)
        before = nurbs.evaluate_grid(self.saddle, us, vs)
        for direction, flag, knots in ((nurbs.Direction.u, "u", [0.5, 1.5]), (nurbs.Direction.v, "v", [0.25, 0.25])):
            args = [a for t in knots for a in ("--knot", t)]
            refined = nurbs.refine(self.saddle, direction, knots)
            self.assertEqual(io.to_json(refined), cli("insert", path, "--dir", flag, *args).stdout)
            self.assertEqual(refined.count[direction.value], self.saddle.count[direction.value] + 2)
            assert_close(self, nurbs.evaluate_grid(refined, us, vs), before, what=f"refined in {flag}")
            once = nurbs.insert_knot(self.saddle, direction, knots[0])
            assert_close(self, nurbs.evaluate_grid(once, us, vs), before, what=f"insert_knot in {flag}")
        mid = nurbs.refine_midpoints(self.saddle)
        self.assertEqual(io.to_json(mid), cli("insert", path, "--midpoints").stdout)
        assert_close(self, nurbs.evaluate_grid(mid, us, vs), before, what="midpoints")

    def test_direction_curve(self):
        s = self.grid
        c = nurbs.direction_curve(s, nurbs.Direction.u)
        self.assertEqual(c.P.shape, (3, 2 * 3))
        u, v = 0.35, 1.2
        line = nurbs.evaluate(c, u).reshape(2, 3)  # the v control line of the isocurve at u
        iso = nurbs.Curve(1, s.knots[1], line)
        assert_close(self, nurbs.evaluate(iso, v), nurbs.evaluate(s, u, v), what="isocurve")
        self.assertEqual(nurbs.direction_curve(s, nurbs.Direction.v).P.shape, (2, 3 * 3))

    def test_bad_surfaces(self):
        knots = ([0, 0, 0, 1, 1, 1], [0, 0, 2, 2])
        cases = [
            (lambda: nurbs.Surface((2, 1), knots, np.zeros((6, 3))),
             "count: give (nu, nv) with points of shape (nu*nv, dim)"),
            (lambda: nurbs.Surface((2, 1), knots, np.zeros((6, 3)), count=(2, 2)),
             "points: 6 control points do not form a 2 by 2 net"),
            (lambda: nurbs.Surface((2, 1), knots, np.zeros((3, 2, 3)), count=(2, 3)),
             "count: (2, 3) does not match the points' shape (3, 2, 3)"),
            (lambda: nurbs.Surface((2, 1), knots, np.zeros((3, 2, 3)), weights=np.ones((2, 3))),
             "weights: shape (2, 3) does not match the 3 by 2 net"),
            (lambda: nurbs.Surface((2, 0), knots, np.zeros((3, 2, 3))), "degree[1]: degree 0 is outside [1, 64]"),
            (lambda: nurbs.Surface((2, 1), knots, np.zeros(3)),
             "points: expected (nu, nv, dim) or (nu*nv, dim), got shape (3,)"),
            (lambda: nurbs.Surface((2, 1), knots, np.zeros((3, 2, 3)), weights=-np.ones(6)),
             "weights[0][0]: weight -1 is not a positive finite number"),
            (lambda: nurbs.evaluate(self.grid, 1.5, 0.0), "parameter u = 1.5 is outside the domain [0, 1]"),
            (lambda: nurbs.evaluate_grid(self.grid, [0.0], [3.0]), "parameter v = 3 is outside the domain [0, 2]"),
            (lambda: nurbs.normal(nurbs.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), np.zeros((2, 2, 2))), 0.5, 0.5),
             "the surface is 2-D; a normal needs a 3-D surface"),
        ]
        for call, message in cases:
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                call()
            self.assertEqual(str(caught.exception), message)


class DoublingTest(unittest.TestCase):
    def test_uniform_quadratic_is_chaikin(self):
        G = nurbs.subdivision_matrix([1, 1, 1], 2, nurbs.Half.G)
        D = nurbs.subdivision_matrix([1, 1, 1], 2, nurbs.Half.D)
        assert_close(self, G, [[0.75, 0.25, 0], [0.25, 0.75, 0], [0, 0.75, 0.25]], rel=1e-15)
        assert_close(self, D, [[0.25, 0.75, 0], [0, 0.75, 0.25], [0, 0.25, 0.75]], rel=1e-15)

    def test_child_windows(self):
        self.assertEqual(nurbs.child_window([1, 2, 3], 2, nurbs.Half.G).tolist(), [1, 2, 2])
        self.assertEqual(nurbs.child_window([1, 2, 3], 2, nurbs.Half.D).tolist(), [2, 2, 3])
        self.assertEqual(nurbs.child_window([1, 2, 3, 4, 5], 3, nurbs.Half.G).tolist(), [2, 2, 3, 3, 4])
        nurbs.validate_window([0, 1, 0], 2)

    def test_matrices_give_the_refined_control_points(self):
        # Knot doubling: G/D applied to a segment's points are the points of the refined curve.
        c = shape("cubic")
        d = c.degree
        refined = nurbs.refine_midpoints(c)
        for span in range(d, c.P.shape[0]):
            if c.knots[span] == c.knots[span + 1]:
                continue
            window = nurbs.segment_window(c.knots, d, span)
            self.assertEqual(window.tolist(), np.diff(c.knots[span - d + 1:span + d + 1]).tolist())
            P = c.P[span - d:span + 1]
            mid = 0.5 * (c.knots[span] + c.knots[span + 1])
            left = nurbs.find_span(refined.knots, d, 0.5 * (c.knots[span] + mid))
            with self.subTest(span=span):
                assert_close(self, nurbs.subdivision_matrix(window, d, nurbs.Half.G) @ P,
                             refined.P[left - d:left + 1], what="G half")
                assert_close(self, nurbs.subdivision_matrix(window, d, nurbs.Half.D) @ P,
                             refined.P[left + 1 - d:left + 2], what="D half")


class AnyDegreeBasisTest(unittest.TestCase):
    """Basis functions of any degree on any knot vector where they are defined (issue 30: degree 1 on a clamped
    quadratic knot vector was refused for its triple knots), against Cox–de Boor in plain Python."""

    @staticmethod
    def cox_de_boor(t, p, i, u):
        if p == 0:
            return 1.0 if t[i] <= u < t[i + 1] else 0.0
        a = (u - t[i]) / (t[i + p] - t[i]) * AnyDegreeBasisTest.cox_de_boor(t, p - 1, i, u) if t[i + p] > t[i] else 0
        b = ((t[i + p + 1] - u) / (t[i + p + 1] - t[i + 1]) * AnyDegreeBasisTest.cox_de_boor(t, p - 1, i + 1, u)
             if t[i + p + 1] > t[i + 1] else 0)
        return a + b

    def test_every_degree_on_a_vector_with_high_multiplicities(self):
        np.testing.assert_allclose(nurbs.basis_functions([0, 0, 0, 0.5, 1, 1, 1], 1, 2, 0.25), [0.5, 0.5])
        t = [0, 0, 0, 0, 0.3, 0.3, 0.3, 0.7, 1, 1, 1, 1]
        for p in range(0, 5):
            for span in range(p, len(t) - p - 1):
                if not t[span] < t[span + 1]:
                    with self.assertRaisesRegex(cifs.InvalidInput, "is empty"):
                        nurbs.basis_functions(t, p, span, t[span])
                    continue
                for u in np.linspace(t[span], t[span + 1], 5, endpoint=False):
                    N = nurbs.basis_functions(t, p, span, u)
                    expected = [self.cox_de_boor(t, p, span - p + j, u) for j in range(p + 1)]
                    np.testing.assert_allclose(N, expected, rtol=1e-14, atol=1e-15, err_msg=f"p={p} span={span}")
                    self.assertEqual(nurbs.basis_derivatives(t, p, span, u, 0).shape, (1, p + 1))
        with self.assertRaisesRegex(cifs.InvalidInput, "knots\\[2\\]: 0.5 is less than the previous knot 1"):
            nurbs.basis_functions([0, 1, 0.5, 2], 1, 1, 0.5)


class SplitReverseTest(unittest.TestCase):
    def test_split_and_reverse_keep_the_curve(self):
        curve = nurbs.Curve(3, CUBIC_KNOTS, CUBIC_POINTS)
        left, right = nurbs.split(curve, 1.5)
        self.assertEqual((left.domain, right.domain), ((0.0, 1.5), (1.5, 4.0)))
        for u in np.linspace(0, 1.5, 7):
            assert_close(self, nurbs.evaluate(left, u), nurbs.evaluate(curve, u), rel=1e-13)
        for u in np.linspace(1.5, 4, 7):
            assert_close(self, nurbs.evaluate(right, u), nurbs.evaluate(curve, u), rel=1e-13)
        back = nurbs.reverse(curve)
        for u in np.linspace(0, 4, 9):
            assert_close(self, nurbs.evaluate(back, 4 - u), nurbs.evaluate(curve, u), rel=1e-13)
        with self.assertRaisesRegex(cifs.InvalidInput, "not strictly inside the domain"):
            nurbs.split(curve, 4.0)


class FitTest(unittest.TestCase):
    """Fitting: the points hit at their parameters, the least-squares solution against numpy's lstsq on the
    collocation matrix of the knot functions, the same curve as `cifs fit`, bad input."""

    def setUp(self):
        x = np.linspace(0, 5, 40)
        self.points = np.stack([x, np.sin(x), np.cos(2 * x)], axis=1)

    def test_interpolate_hits_every_point(self):
        for kind in ("uniform", "chord_length", "centripetal"):
            for degree in (1, 2, 3, 5):
                curve = nurbs.interpolate(self.points, degree, parametrization=kind)
                u = nurbs.fit_parameters(self.points, kind)
                np.testing.assert_allclose(nurbs.evaluate(curve, u), self.points, rtol=0, atol=1e-14 * 5)
        ring = nurbs.interpolate(self.points[:-1], 3, closed=True)
        u = nurbs.fit_parameters(self.points[:-1], closed=True)
        np.testing.assert_allclose(nurbs.evaluate(ring, u), self.points[:-1], rtol=0, atol=1e-13)
        tangent = np.array([1.0, 0.0, 2.0])
        ends = nurbs.interpolate(self.points, 3, start_derivative=tangent, end_derivative=-tangent)
        np.testing.assert_allclose(nurbs.derivatives(ends, 0.0, 1)[1], tangent, atol=1e-12)
        np.testing.assert_allclose(nurbs.derivatives(ends, 1.0, 1)[1], -tangent, atol=1e-12)

    def test_approximate_is_the_least_squares_solution(self):
        curve = nurbs.approximate(self.points, 3, control_points=9, fix_ends=False)
        u = nurbs.fit_parameters(self.points)
        A = np.zeros((len(u), 9))
        for k, x in enumerate(u):
            span = nurbs.find_span(curve.knots, 3, x)
            A[k, span - 3:span + 1] = nurbs.basis_functions(curve.knots, 3, span, x)
        expected = np.linalg.lstsq(A, self.points, rcond=None)[0]
        np.testing.assert_allclose(curve.points, expected, rtol=0, atol=1e-12)
        near = nurbs.approximate(self.points, 3, tolerance=1e-2)
        fit = nurbs.fit_distances(near, self.points)
        self.assertLessEqual(fit.point_distance, 1e-2)
        self.assertLessEqual(fit.point_distance, fit.polyline_bound)
        self.assertLess(nurbs.distinct_count(near), len(self.points))

    def test_surfaces(self):
        grid = np.array([[[i, j, np.sin(i + j)] for j in range(7)] for i in range(6)], dtype=float)
        surface = nurbs.interpolate_surface(grid, (3, 2), parametrization="uniform")
        self.assertEqual(surface.count, (6, 7))
        for i, j in ((0, 0), (2, 3), (5, 6), (4, 1)):
            np.testing.assert_allclose(nurbs.evaluate(surface, i / 5, j / 6), grid[i, j], rtol=0, atol=1e-13)
        smooth = nurbs.approximate_surface(grid, (4, 5), degree=(2, 2))
        self.assertEqual(smooth.count, (4, 5))
        np.testing.assert_allclose(nurbs.evaluate(smooth, 0, 0), grid[0, 0], atol=1e-13)

    def test_bad_input(self):
        with self.assertRaisesRegex(cifs.InvalidInput, r"points\[2\]: coincides with points\[1\]"):
            nurbs.interpolate(np.array([[0, 0], [1, 1], [1, 1], [2, 0]]), 2)
        with self.assertRaisesRegex(cifs.InvalidInput, "needs at least 4 points, got 3"):
            nurbs.interpolate(np.array([[0, 0], [1, 1], [2, 0]]))
        with self.assertRaisesRegex(cifs.InvalidInput, "give control_points or tolerance"):
            nurbs.approximate(self.points)
        with self.assertRaisesRegex(cifs.InvalidInput, "parametrization 'chord'"):
            nurbs.interpolate(self.points, parametrization="chord")
        with self.assertRaisesRegex(cifs.InvalidInput, "expected a grid"):
            nurbs.interpolate_surface(self.points)


class MeasureTest(unittest.TestCase):
    """Measuring: the bindings of measure.hpp against closed forms (the unit circle, the parabola) and
    numpy's own sums, and their refusals."""

    def setUp(self):
        h = np.sqrt(0.5)
        points = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
        self.circle = nurbs.Curve(2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], points,
                                  np.array([1, h, 1, h, 1, h, 1, h, 1]))

    def test_length_and_its_inverse(self):
        self.assertAlmostEqual(nurbs.length(self.circle), 2 * np.pi, delta=1e-13)
        self.assertAlmostEqual(nurbs.length(self.circle, a=0.25, b=0.75), np.pi, delta=1e-13)
        self.assertLessEqual(nurbs.length_error(self.circle), 1e-12 * 2 * np.pi)
        parabola = nurbs.Curve(2, [0, 0, 0, 1, 1, 1], np.array([[0, 0], [0.5, 0], [1, 1]], float))
        exact = np.sqrt(5) / 2 + np.arcsinh(2) / 4
        self.assertAlmostEqual(nurbs.length(parabola), exact, delta=1e-14)
        for s in (0.5, 2.0, 5.0):
            u = nurbs.parameter_at_length(self.circle, s)
            x, y = nurbs.evaluate(self.circle, u)
            self.assertAlmostEqual(np.arctan2(y, x) % (2 * np.pi), s, delta=1e-12)
        with self.assertRaisesRegex(cifs.InvalidInput, "outside the domain"):
            nurbs.length(self.circle, a=0.5, b=2)
        with self.assertRaisesRegex(cifs.InvalidInput, "beyond the end"):
            nurbs.parameter_at_length(self.circle, 7)

    def test_frenet_closest_intersections_box_transform(self):
        frame = nurbs.frenet_frame(self.circle, 0.3)
        self.assertAlmostEqual(frame.curvature, 1, delta=1e-14)
        assert_close(self, frame.point + frame.normal, np.zeros(2), rel=1e-13)
        line = nurbs.Curve(2, [0, 0, 0, 1, 1, 1], np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2]], float))
        self.assertIsNone(nurbs.frenet_frame(line, 0.5).normal)
        near = nurbs.closest_point(self.circle, [3, 0])
        self.assertEqual(list(near.parameters), [0.0, 1.0])  # the clamped circle's two ends
        self.assertAlmostEqual(near.distance, 2, delta=1e-14)
        self.assertEqual(nurbs.closest_point(self.circle, [0, 0]).intervals, [(0.0, 1.0)])
        parameters, intervals = nurbs.intersect_plane(self.circle, [0, 1], 0.5)
        np.testing.assert_allclose(nurbs.evaluate(self.circle, parameters)[:, 0], [np.sqrt(3) / 2, -np.sqrt(3) / 2],
                                   atol=1e-14)
        self.assertEqual(intervals, [])
        chord = nurbs.Curve(1, [0, 0, 1, 1], np.array([[-2, 0.5], [2, 0.5]]))
        self.assertEqual(len(nurbs.intersect_curves(chord, self.circle)), 2)
        lower, upper = nurbs.bounding_box(self.circle)
        np.testing.assert_allclose(np.concatenate([lower, upper]), [-1, -1, 1, 1], atol=1e-15)
        turned = nurbs.transform(self.circle, np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]))
        assert_close(self, nurbs.evaluate(turned, 0.0), np.array([0.0, 1.0]), rel=1e-15)
        with self.assertRaisesRegex(cifs.InvalidInput, "3×3 matrix"):
            nurbs.transform(self.circle, np.eye(4))
        with self.assertRaisesRegex(cifs.InvalidInput, "coordinates"):
            nurbs.closest_point(self.circle, [0, 0, 0])

    def test_surface_closest_points(self):
        # The sphere of radius 2 about (1, 0, 0): a half circle turned about the vertical axis through it.
        h = np.sqrt(0.5)
        half = nurbs.Curve(2, [0, 0, 0, .5, .5, 1, 1, 1],
                           np.array([[1, 0, -2], [3, 0, -2], [3, 0, 0], [3, 0, 2], [1, 0, 2]], float),
                           [1, h, 1, h, 1])
        sphere = nurbs.revolve(half, [1, 0, 0], [0, 0, 1], 2 * np.pi)
        near = nurbs.closest_point(sphere, [1, 3, 4])
        self.assertAlmostEqual(near.distance, 3, delta=1e-12 * 5)  # |(0, 3, 4)| − 2
        self.assertEqual(near.parameters.shape, (1, 2))
        assert_close(self, near.points[0], np.array([1, 1.2, 1.6]), rel=1e-12)
        assert_close(self, sphere.evaluate(*near.parameters[0]), near.points[0], rel=1e-14)
        centre = nurbs.closest_point(sphere, [1, 0, 0])
        self.assertEqual((centre.parameters.shape, centre.regions), ((0, 2), [(0.0, 1.0, 0.0, 1.0)]))
        self.assertIn("regions=1", repr(centre))
        pole = nurbs.closest_point(sphere, [1, 0, 7])  # above the north pole: one point
        assert_close(self, pole.points, np.array([[1.0, 0, 2]]), rel=1e-12)
        with self.assertRaisesRegex(cifs.InvalidInput, "2 coordinates, the surface 3"):
            nurbs.closest_point(sphere, [0, 0])
        with self.assertRaisesRegex(cifs.InvalidInput, "not finite"):
            nurbs.closest_point(sphere, [0, np.nan, 0])
        with self.assertRaisesRegex(cifs.InvalidInput, "tolerance"):
            nurbs.closest_point(sphere, [0, 0, 0], tolerance=0)

    def test_surface_split_and_iso_curves(self):
        grid = np.array([[[i, j, np.sin(i) * np.cos(j)] for j in range(5)] for i in range(6)], dtype=float)
        surface = nurbs.interpolate_surface(grid, (3, 2))
        iso = nurbs.iso_curve(surface, nurbs.Direction.u, 0.3)
        for v in (0.0, 0.4, 1.0):
            assert_close(self, nurbs.evaluate(iso, v), surface.evaluate(0.3, v), rel=1e-14)
        first, second = nurbs.split(surface, nurbs.Direction.v, 0.6)
        assert_close(self, first.evaluate(0.2, 0.5), surface.evaluate(0.2, 0.5), rel=1e-14)
        assert_close(self, second.evaluate(0.2, 0.7), surface.evaluate(0.2, 0.7), rel=1e-14)



class SurfaceOperationsTest(unittest.TestCase):
    """Operations on surfaces' nets, degree reduction and curvature through the bindings: against the
    surface evaluated before, closed forms (z = xy, a sphere) and the refusals."""

    def setUp(self):
        grid = np.array([[[i, j, np.sin(i) * np.cos(j)] for j in range(5)] for i in range(6)], dtype=float)
        self.surface = nurbs.interpolate_surface(grid, (3, 2))
        self.samples = [(u, v) for u in (0.0, 0.27, 0.6, 1.0) for v in (0.0, 0.45, 0.8, 1.0)]

    def assert_same(self, other, mapping=lambda u, v: (u, v)):
        for u, v in self.samples:
            assert_close(self, other.evaluate(*mapping(u, v)), self.surface.evaluate(u, v), rel=1e-13)

    def test_net_operations_keep_the_surface(self):
        U, V = nurbs.Direction.u, nurbs.Direction.v
        self.assert_same(nurbs.swap_uv(self.surface), lambda u, v: (v, u))
        self.assert_same(nurbs.reverse(self.surface, U), lambda u, v: (1 - u, v))
        self.assert_same(nurbs.reparametrize(self.surface, V, 2, 6), lambda u, v: (u, 2 + 4 * v))
        self.assert_same(nurbs.normalize_knots(nurbs.reparametrize(self.surface, U, -1, 3)))
        self.assert_same(nurbs.elevate_degree(self.surface, V, 2))
        removal = nurbs.remove_knot(nurbs.insert_knot(self.surface, U, 0.3, 2), U, 0.3, 2, 1e-12)
        self.assertEqual(removal.removed, 2)
        self.assertLessEqual(removal.deviation_bound, 1e-12)
        self.assert_same(removal.surface)
        back = nurbs.reduce_degree(nurbs.elevate_degree(self.surface, U), U, 1e-12)
        self.assertEqual(back.surface.degree, self.surface.degree)
        self.assert_same(back.surface)
        patches = nurbs.split_bezier(self.surface)
        self.assertEqual(len(patches), 3 * 3)
        for patch in patches:
            (u0, u1), (v0, v1) = patch.domain
            u, v = 0.3 * u0 + 0.7 * u1, 0.6 * v0 + 0.4 * v1
            assert_close(self, patch.evaluate(u, v), self.surface.evaluate(u, v), rel=1e-13)
        with self.assertRaisesRegex(cifs.InvalidInput, "direction v: knot 0.5 would reach multiplicity"):
            nurbs.insert_knot(self.surface, V, 0.5, 3)
        with self.assertRaisesRegex(cifs.InvalidInput, "direction u: 0.25 is not a knot"):
            nurbs.remove_knot(self.surface, U, 0.25, 1, 0.0)
        with self.assertRaisesRegex(cifs.InvalidInput, r"reparametrize: direction v: the new domain \[1, 1\]"):
            nurbs.reparametrize(self.surface, V, 1, 1)

    def test_curve_degree_reduction(self):
        cubic = nurbs.Curve(3, CUBIC_KNOTS, CUBIC_POINTS)
        back = nurbs.reduce_degree(nurbs.elevate_degree(cubic), 1e-12)
        self.assertEqual(back.curve.degree, 3)
        np.testing.assert_array_equal(back.curve.knots, CUBIC_KNOTS)
        np.testing.assert_allclose(back.curve.P, CUBIC_POINTS, atol=1e-12)
        loose = nurbs.reduce_degree(cubic, float("inf"))
        distance = max(np.linalg.norm(nurbs.evaluate(loose.curve, u) - nurbs.evaluate(cubic, u))
                       for u in np.linspace(0, 4, 801))
        self.assertLessEqual(distance, loose.deviation_bound)
        with self.assertRaisesRegex(cifs.InvalidInput, "reduce_degree: the degree 2 curve is within .* more than"):
            nurbs.reduce_degree(cubic, 0.5 * loose.deviation_bound)
        with self.assertRaisesRegex(cifs.InvalidInput, "degree 1 cannot be reduced"):
            nurbs.reduce_degree(nurbs.Curve(1, [0, 0, 1, 1], np.eye(2)), 1.0)
        np.testing.assert_array_equal(nurbs.normalize_knots(cubic).knots, np.array(CUBIC_KNOTS) / 4)

    def test_curvature_closed_forms(self):
        saddle = nurbs.Surface((1, 1), ([-1, -1, 1, 1], [-1, -1, 1, 1]),
                               np.array([[[-1, -1, 1], [-1, 1, -1]], [[1, -1, -1], [1, 1, 1]]], float))
        k = nurbs.curvature(saddle, 0.0, 0.0)
        self.assertEqual((k.gaussian, k.mean, k.principal), (-1.0, 0.0, (1.0, -1.0)))
        np.testing.assert_allclose(k.directions[0], np.array([1, 1, 0]) / np.sqrt(2), atol=1e-15)
        x, y = 0.3, -0.7
        g = 1 + x * x + y * y
        k = nurbs.curvature(saddle, x, y)
        self.assertAlmostEqual(k.gaussian, -1 / g ** 2, delta=1e-15)
        self.assertAlmostEqual(k.mean, -x * y / g ** 1.5, delta=1e-15)
        with self.assertRaisesRegex(cifs.InvalidInput, "curvature: the surface is 2-D"):
            nurbs.curvature(nurbs.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), np.zeros((2, 2, 2))), 0.5, 0.5)
        with self.assertRaisesRegex(cifs.InvalidInput, "parameter u"):
            nurbs.curvature(saddle, 2.0, 0.0)


if __name__ == "__main__":
    unittest.main()
