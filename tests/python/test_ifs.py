# SPDX-License-Identifier: MIT
"""cifs.ifs: the engine on hand-made automata (Chaikin's curve and its tensor square) against the
B-spline formulas, classic affine IFS and dimensions against the closed forms and `cifs dimension`,
NURBS attractors against `cifs attractor`."""
import math
import unittest

import numpy as np

import cifs
from cifs import automata, ifs
from support import CHAIKIN_D, CHAIKIN_G, SANITIZED, chaikin, EXAMPLES, assert_close, cli, cli_json

# Chaikin: the uniform quadratic B-spline segment split at its midpoint (halves G and D).
G, D = CHAIKIN_G, CHAIKIN_D
NET = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, -1.0]])


def basis(t):
    """Uniform quadratic B-spline basis on one segment, t ∈ [0, 1]: `(len(t), 3)`."""
    t = np.asarray(t, dtype=float)[:, None]
    return np.hstack([(1 - t) ** 2 / 2, (-2 * t**2 + 2 * t + 1) / 2, t**2 / 2])


def curve(t, net=NET):
    return basis(t) @ net


def message(test, call):
    with test.assertRaises(cifs.InvalidInput) as raised:
        call()
    return str(raised.exception)


class AnalysisTest(unittest.TestCase):
    def test_states_and_validation(self):
        a = chaikin()
        ifs.validate(a)
        self.assertEqual(ifs.reachable_states(a), [0])
        a.add_state(2)  # not reachable: ignored by the engine
        self.assertEqual(ifs.reachable_states(a), [0])
        ifs.validate(a)

    def test_rows_not_summing_to_one_and_empty_states_are_refused(self):
        a = chaikin()
        bad = G.copy()
        bad[1, 1] = 0.65
        a.set_matrix(0, 1, bad)
        self.assertEqual(message(self, lambda: ifs.validate(a)),
                         "transition 1 of state 0 (uniform) (to state 0 (uniform)): row 1 sums to "
                         "0.90000000000000002, not 1 (rows are affine combinations)")
        # Every engine entry point validates.
        self.assertIn("not 1 (rows are affine combinations)",
                      message(self, lambda: ifs.attractor_points(a, [NET], 2)))
        b = automata.Automaton()
        b.add_state(2, "x")
        self.assertEqual(message(self, lambda: ifs.validate(b)),
                         "state 0 (x) has no transition: its attractor would be empty")

    def test_diameter_and_delta(self):
        rng = np.random.default_rng(2)
        P = rng.random((6, 3))
        expected = max(np.linalg.norm(p - q) for p in P for q in P)
        self.assertAlmostEqual(ifs.diameter(P), expected, delta=1e-15)
        self.assertEqual(ifs.diameter(P[:1]), 0)
        M = rng.random((4, 5)) - 0.3
        expected = max(0.5 * np.abs(r - s).sum() for r in M for s in M)
        self.assertAlmostEqual(ifs.delta(M), expected, delta=1e-15)
        self.assertEqual(ifs.delta(G), 0.75)

    def test_contraction(self):
        c = ifs.contraction(chaikin(), tighten=False)
        self.assertEqual((c.m, c.delta, c.A), (1, 0.75, 1.0))
        self.assertAlmostEqual(c.radius, (1 + c.A) / (2 * (1 - c.delta)), delta=1e-15)
        self.assertLessEqual(ifs.contraction(chaikin()).radius, c.radius)
        self.assertIn("m=1", repr(c))

    def test_non_contractive_system_names_the_path(self):
        a = automata.Automaton()
        a.add_state(2, "id")
        a.add_transition(0, 0, np.eye(2))
        a.add_transition(0, 0, np.array([[1, 0], [0.5, 0.5]]))
        a.add_initial(0)
        expected = ("not contractive: the 3-step products from state 0 (id) do not shrink nets (δ = 1 along "
                    "the path 0 0 0; no path length ≤ 3 gives δ < 1)")
        self.assertEqual(message(self, lambda: ifs.contraction(a, max_length=3)), expected)
        self.assertIn("the path 0 0 0 0 0 0 0 0", message(self, lambda: ifs.chaos_game(a, [np.eye(2)], samples=3)))
        self.assertIn("not contractive", message(self, lambda: ifs.for_each_leaf_to_tolerance(a, [np.eye(2)], print)))
        self.assertEqual(message(self, lambda: ifs.contraction(a, max_length=0)),
                         "the contraction check's path length 0 is below 1; give at least 1")

    def test_fixed_points_are_attractor_points(self):
        a = chaikin()
        # Address 0^∞ is t = 0, 1^∞ is t = 1, (01)^∞ is t = 1/3, (011)^∞ is t = 3/7.
        for word, t in (([0], 0), ([1], 1), ([0, 1], 1 / 3), ([0, 1, 1], 3 / 7)):
            ell = ifs.fixed_point(a, 0, word)
            self.assertAlmostEqual(ell.sum(), 1, delta=1e-15)
            assert_close(self, ell, basis([t])[0], what=f"fixed point of {word}")
        self.assertEqual(message(self, lambda: ifs.fixed_point(a, 0, [2])),
                         "the fixed point of the word 2 from state 0 (uniform): child index 2 at position 0 but state 0 "
                         "(uniform) has 2 children")
        self.assertEqual(message(self, lambda: ifs.fixed_point(a, -1, [0])), "fixed_point: state -1 does not exist")
        self.assertEqual(message(self, lambda: ifs.fixed_point(a, 3, [0])), "state 3 does not exist (the automaton has 1 states)")

    def test_end_and_repeated_child_functionals(self):
        a = chaikin()
        e = ifs.end_functionals(a)
        assert_close(self, e.start[0], basis([0])[0])
        assert_close(self, e.end[0], basis([1])[0])
        assert_close(self, ifs.repeated_child_functionals(a, 1)[0], e.end[0])
        self.assertIn("child 2 does not exist: state 0 (uniform) has 2 children",
                      message(self, lambda: ifs.repeated_child_functionals(a, 2)))

    def test_spectra(self):
        a = chaikin()
        s = ifs.spectra(a)
        self.assertEqual([(x.source, x.target, x.child, x.label) for x in s], [(0, 0, 0, "G"), (0, 0, 1, "D")])
        for x in s:
            assert_close(self, x.eigenvalues.real, [1, 0.5, 0.25])
            self.assertEqual(x.eigenvalues.dtype, np.complex128)
        np.testing.assert_array_equal(ifs.eigenvalues(G), s[0].eigenvalues)
        rotation = np.array([[0, -1], [1, 0.0]])
        np.testing.assert_array_equal(ifs.eigenvalues(rotation), [1j, -1j])
        self.assertEqual(message(self, lambda: ifs.eigenvalues(np.ones((2, 3)))),
                         "a 2 by 3 matrix has no eigenvalues: it is not square")


class AttractorTest(unittest.TestCase):
    def test_attractor_points_are_the_curve_at_dyadic_parameters(self):
        a = chaikin()
        for depth in (0, 3, 9):
            P = ifs.attractor_points(a, [NET], depth)
            self.assertEqual(len(P), ifs.attractor_point_count(a, depth))
            assert_close(self, P, curve(np.arange(2**depth + 1) / 2**depth), what=f"depth {depth}")
        closed = ifs.attractor_points(a, [NET], 4, closed=True, max_table_depth=1)
        self.assertEqual(len(closed), ifs.attractor_point_count(a, 4, closed=True))
        assert_close(self, closed, curve(np.arange(16) / 16))
        self.assertEqual(message(self, lambda: ifs.attractor_points(a, [NET], -1)),
                         "the depth -1 is negative; give a depth ≥ 0")
        self.assertIn("held in memory; lower the depth", message(self, lambda: ifs.attractor_points(a, [NET], 20, max_bytes=1000)))
        self.assertEqual(message(self, lambda: ifs.attractor_points(a, [NET[:2]], 2)),
                         "control net 0 has 2 points but its initial state 0 (uniform) holds 3")
        self.assertIn("1 initial entries", message(self, lambda: ifs.attractor_points(a, [NET, NET], 2)))
        self.assertIn("max_bytes = -1 is negative", message(self, lambda: ifs.attractor_points(a, [NET], 2, max_bytes=-1)))

    def test_sample_attractor_to_a_depth_and_to_a_tolerance(self):
        a = chaikin()
        s = ifs.sample_attractor(a, [NET], depth=5, states=True)
        assert_close(self, s.points, curve(np.arange(33) / 32))
        self.assertEqual((s.depth, s.states), (5, [0] * 32))
        t = ifs.sample_attractor(a, [NET], tolerance=0.05)
        gaps = np.linalg.norm(np.diff(t.points, axis=0), axis=1)
        self.assertLess(gaps.max(), 0.05)  # consecutive points bound one piece each
        assert_close(self, t.points[[0, -1]], curve(np.array([0.0, 1.0])))
        self.assertIn("above the limit of 10", message(self, lambda: ifs.sample_attractor(a, [NET], depth=9,
                                                                                            max_points=10)))
        self.assertIn("is not a positive number", message(self, lambda: ifs.sample_attractor(a, [NET])))
        # Chordal: a polyline within 1e-3 of the parabola (numpy, dense), with far fewer points.
        c = ifs.sample_attractor(a, [NET], tolerance=1e-3, chordal=True)
        dense = curve(np.linspace(0, 1, 20001))
        p0, d = c.points[:-1], np.diff(c.points, axis=0)
        t = np.clip(np.einsum("nsk,sk->ns", dense[:, None, :] - p0[None], d) / (d * d).sum(1), 0, 1)
        distance = np.linalg.norm(dense[:, None, :] - p0[None] - t[..., None] * d[None], axis=2).min(axis=1)
        self.assertLessEqual(distance.max(), 1e-3)
        self.assertLess(10 * len(c.points), len(ifs.sample_attractor(a, [NET], tolerance=1e-3).points))
        leaves = []
        ifs.for_each_leaf_to_tolerance(a, [NET], leaves.append, epsilon=1e-3, chordal=True)
        self.assertEqual(len(leaves), len(c.points) - 1)
        self.assertTrue(all(0 < x.deviation < 1e-3 and x.converged for x in leaves))

    def test_complex_and_boolean_arrays_are_refused(self):
        a = chaikin()
        for bad in (NET.astype(complex), NET > 0):
            for call in (lambda: ifs.attractor_points(a, [bad], 3), lambda: ifs.cartesian(bad),
                         lambda: ifs.eigenvalues(bad[:2, :2])):
                self.assertIn(f"expected an array of real numbers, got dtype {bad.dtype}", message(self, call))
        # Integers convert (exactly); a 1-D array is a column; results are new float64 arrays.
        assert_close(self, ifs.attractor_points(a, [NET.astype(np.int64)], 3), ifs.attractor_points(a, [NET], 3),
                     rel=0)
        self.assertIn("at least 2 columns", message(self, lambda: ifs.cartesian(np.array([2, 4]))))
        points = ifs.cartesian(np.array([[2, 4]]))
        np.testing.assert_array_equal(points, [[0.5]])
        self.assertEqual(points.dtype, np.float64)

    def test_a_stencil_table_is_applied_to_new_nets(self):
        a = chaikin()
        table = ifs.stencil_table(a, 7)
        self.assertEqual((table.depth, table.points), (7, 129))
        t = np.arange(129) / 128
        frames = [NET * s + s for s in (1.0, -0.5, 3.0)]
        for net in frames:
            assert_close(self, table.apply([net]), curve(t, net))
        # Net sets side by side give their points side by side.
        wide = table.apply([np.hstack(frames)])
        for k, net in enumerate(frames):
            assert_close(self, wide[:, 2 * k:2 * k + 2], curve(t, net))
        self.assertEqual(len(ifs.stencil_table(a, 3, closed=True).apply([NET])), 8)
        self.assertEqual(message(self, lambda: table.apply([NET[:2]])),
                         "control net 0 has 2 points but its initial state 0 (uniform) holds 3")
        self.assertIn("more than the limit", message(self, lambda: table.apply([NET], max_bytes=100)))
        self.assertIn("depth -1 is negative", message(self, lambda: ifs.stencil_table(a, -1)))

    def test_cartesian(self):
        H = np.array([[2.0, 4.0, 2.0], [3.0, -3.0, 0.5]])
        np.testing.assert_array_equal(ifs.cartesian(H), [[1, 2], [6, -6]])
        self.assertEqual(message(self, lambda: ifs.cartesian(np.array([[1.0, 0.0]]))),
                         "homogeneous point 0 has weight 0 (a point at infinity): it has no Cartesian coordinates")

    def test_cartesian_refuses_rows_known_to_be_cartesian(self):
        """Issue 32: README's ifs.cartesian(ifs.attractor_points(…)) divided a non-rational 3-D curve's x and y
        by its z. The nets of a shape and the points made from them know whether they are homogeneous."""
        knots = [0, 0, 0, 0, 1, 2, 4, 4, 4, 4]
        xyz = np.array([[0, 0, 1], [1, 2, 2], [3, 3, 1], [4, 0, 3], [6, 1, 2], [7, 3, 1]], float)
        breaks = [0, 1, 2, 4]
        us = [a + (b - a) * j / 16 for a, b in zip(breaks[:-1], breaks[1:]) for j in range(16)] + [4]
        plain = cifs.nurbs.Curve(3, knots, xyz)
        a = automata.knot_automaton(plain)
        nets = automata.initial_nets(a, plain)
        self.assertEqual([net.homogeneous for net in nets], [False] * 3)
        for rows in (ifs.attractor_points(a, nets, 4), ifs.stencil_table(a, 4).apply(nets)):
            self.assertIs(rows.homogeneous, False)
            assert_close(self, rows, plain.evaluate(us))  # the points themselves (de Boor)
            self.assertEqual(message(self, lambda r=rows: ifs.cartesian(r)),
                             "cartesian: homogeneous: the rows are Cartesian already (the nets of a shape that is "
                             "not rational, or points made from them); curve.attractor(depth) and "
                             "surface.attractor(depth) give the Cartesian points of any shape")
            self.assertEqual(message(self, lambda r=rows: ifs.cartesian(homogeneous=r[1:])),
                             message(self, lambda r=rows: ifs.cartesian(r)))  # slices keep the flag
        rational = cifs.nurbs.Curve(3, knots, xyz[:, :2], weights=[1, 3, 0.5, 2, 1, 0.7])
        a = automata.knot_automaton(rational)
        nets = automata.initial_nets(a, rational)
        H = ifs.attractor_points(a, nets, 4)
        self.assertIs(H.homogeneous, True)
        points = ifs.cartesian(H)
        assert_close(self, points, rational.evaluate(us))
        self.assertIs(points.homogeneous, False)  # divided once, never twice
        self.assertIn("Cartesian already", message(self, lambda: ifs.cartesian(points)))
        # Surfaces: the nets of tensor_automaton(surface) know too.
        grid = np.array([[[i, j, (i * j) % 3] for j in range(3)] for i in range(3)], dtype=float)
        for weights in (None, np.ones((3, 3)) + np.eye(3)):
            surface = cifs.nurbs.Surface([2, 2], [[0, 0, 0, 1, 1, 1]] * 2, grid, weights=weights)
            nets = automata.initial_nets(automata.tensor_automaton(surface), surface)
            self.assertEqual({net.homogeneous for net in nets}, {weights is not None})
        # Rows of unknown origin (made by hand, or nets that disagree) are taken as homogeneous, as before.
        self.assertIsNone(ifs.attractor_points(chaikin(), [NET], 2).homogeneous)
        np.testing.assert_array_equal(ifs.cartesian(np.asarray(H)), points)

    def test_for_each_leaf_gives_the_matrix_products_in_order(self):
        a = chaikin()
        leaves = []
        ifs.for_each_leaf(a, [NET], 3, leaves.append)
        words = [tuple(x.word) for x in leaves]
        self.assertEqual(words, [tuple(int(c) for c in f"{k:03b}") for k in range(8)])
        for leaf in leaves:
            net = NET
            for w in leaf.word:
                net = (G, D)[w] @ net
            assert_close(self, leaf.net, net)
            self.assertEqual((leaf.initial, leaf.state, leaf.depth), (0, 0, 3))

        def fail(leaf):
            raise KeyError("from the callback")

        with self.assertRaises(KeyError):
            ifs.for_each_leaf(a, [NET], 2, fail)
        # A callback that edits the automaton does not disturb the walk (it runs on a copy).
        count = []
        ifs.for_each_leaf(a, [NET], 3, lambda leaf: count.append(a.add_transition(0, 0, G)))
        self.assertEqual(len(count), 8)
        self.assertEqual(len(a.children(0)), 10)
        self.assertEqual(message(self, lambda: ifs.for_each_leaf(a, [NET], -2, print)),
                         "the depth -2 is negative; give a depth ≥ 0")

    def test_proven_cover_of_a_tolerance_sample(self):
        # Chaikin's curve: the search's counts at ε halving from diam/16; their growth is the curve's
        # dimension 1, and cover_exponent is the least-squares slope numpy gives on the same counts.
        sample = ifs.tolerance_sample(chaikin(), [NET], max_points=1 << 16)
        cover = sample.cover
        self.assertEqual(cover[-1], (sample.resolution, sample.leaves))
        self.assertTrue(all(b[0] == a[0] / 2 and b[1] >= a[1] for a, b in zip(cover, cover[1:])))
        fit = ifs.cover_exponent(cover)
        used = [c for c in cover if c[1] >= 1000]
        slope = np.polyfit([-math.log(e) for e, _ in used], [math.log(n) for _, n in used], 1)[0]
        self.assertEqual(fit.levels, len(used))
        self.assertAlmostEqual(fit.dimension, slope, delta=1e-12)
        self.assertAlmostEqual(fit.dimension, 1.0, delta=0.01)
        self.assertIsNone(ifs.cover_exponent(cover[:2]))

    def test_tolerance_leaves_bound_their_piece(self):
        a = chaikin()
        leaves = []
        result = ifs.for_each_leaf_to_tolerance(a, [NET], leaves.append, epsilon=1e-3)
        self.assertEqual((result.leaves, result.unconverged), (len(leaves), 0))
        self.assertEqual(result.deepest, max(x.leaf.depth for x in leaves))
        self.assertEqual(result.contraction.m, 1)
        start = 0.0
        for x in leaves:
            self.assertTrue(x.converged)
            self.assertLess(x.diameter, 1e-3)
            self.assertLessEqual(x.diameter, 2 * x.radius)
            width = 2.0 ** -x.leaf.depth
            self.assertEqual(sum(w * 2.0 ** -(k + 1) for k, w in enumerate(x.leaf.word)), start)
            piece = curve(np.linspace(start, start + width, 9))
            self.assertLessEqual(np.linalg.norm(piece - x.leaf.net[0], axis=1).max(), x.radius * (1 + 1e-12))
            spread = np.linalg.norm(piece[:, None, :] - piece[None, :, :], axis=2).max()
            self.assertLessEqual(spread, x.diameter * (1 + 1e-12))
            start += width
        self.assertEqual(start, 1.0)
        cut = ifs.for_each_leaf_to_tolerance(a, [NET], lambda x: None, epsilon=1e-9, max_depth=4)
        self.assertEqual((cut.leaves, cut.unconverged, cut.deepest), (16, 16, 4))
        self.assertIn("tolerance 0 is not a positive number", message(self, lambda: ifs.for_each_leaf_to_tolerance(a, [NET], print, epsilon=0)))

    def test_chaos_game_points_lie_on_the_attractor(self):
        a = chaikin()
        r = ifs.chaos_game(a, [NET], samples=2000, seed=7, record_address=True)
        self.assertEqual((r.points.shape, r.address.shape, r.seed), ((2000, 2), (2000,), 7))
        self.assertTrue(np.all((r.address >= 0) & (r.address <= 1)))
        assert_close(self, r.points, curve(r.address), rel=1e-12, what="chaos points vs the curve at their address")
        again = ifs.chaos_game(a, [NET], samples=2000, seed=7)
        np.testing.assert_array_equal(again.points, r.points)
        self.assertEqual(again.address.shape, (0,))
        drawn = ifs.chaos_game(a, [NET], samples=10)
        np.testing.assert_array_equal(ifs.chaos_game(a, [NET], samples=10, seed=drawn.seed).points, drawn.points)
        self.assertEqual(message(self, lambda: ifs.chaos_game(a, [NET], samples=-1)),
                         "chaos_game: samples = -1 is negative")
        self.assertEqual(message(self, lambda: ifs.chaos_game(a, [NET], restart_diameter=2)),
                         "the chaos game's restart diameter 2 is outside (0, 1)")


class MeshTest(unittest.TestCase):
    def test_quad_mesh_of_a_hand_made_tensor_automaton(self):
        # Chaikin ⊗ Chaikin: the uniform biquadratic patch; children GH, GB, DH, DB.
        a = automata.Automaton()
        s = a.add_state(9)
        for mu in (G, D):
            for mv in (G, D):
                a.add_transition(s, s, automata.kron(mu, mv))
        a.add_initial(s)
        rng = np.random.default_rng(3)
        net = rng.random((9, 3))
        K = 3
        mesh = ifs.quad_mesh(a, [net], [(0, 0)], K)
        n = 2**K + 1
        self.assertEqual(mesh.vertices.shape, (n * n, 3))
        t = np.arange(n) / 2**K
        B = basis(t)
        expected = np.einsum("ia,jb,abk->ijk", B, B, net.reshape(3, 3, 3)).reshape(n * n, 3)
        assert_close(self, mesh.vertices, expected, what="mesh vertices vs the biquadratic patch")
        q = mesh.quads
        self.assertEqual(q.shape, (4**K, 4))
        I, J = divmod(np.arange(4**K), 2**K)
        np.testing.assert_array_equal(q[:, 0], I * n + J)
        np.testing.assert_array_equal(q[:, 2], (I + 1) * n + J + 1)
        np.testing.assert_array_equal(mesh.states, np.zeros(4**K))
        np.testing.assert_array_equal(mesh.face_offsets, 4 * np.arange(4**K + 1))
        # Vertices; four corners, one offset and one state per quad.
        self.assertEqual(ifs.mesh_bytes(n * n, 3, 4**K), n * n * 3 * 8 + 4**K * 24)
        self.assertIn("patches", message(self, lambda: ifs.quad_mesh(a, [net], [(0, 0), (1, 0)], K)))
        self.assertEqual(message(self, lambda: ifs.quad_mesh(a, [net], [(0, 0)], -1)),
                         "the depth -1 is negative; give a depth ≥ 0")
        self.assertIn("mesh_bytes: vertices = -1 is negative", message(self, lambda: ifs.mesh_bytes(-1, 3, 1)))


class AffineTest(unittest.TestCase):
    TRIANGLE = np.array([[-1.0, -0.5], [2.0, -0.5], [0.5, 2.0]])

    def test_named_ifs(self):
        self.assertEqual(ifs.ifs_names(), ["fern", "sierpinski", "koch"])
        # Map counts and the defining coefficients: Barnsley's probabilities, ratios ½ and ⅓.
        self.assertEqual([m.probability for m in ifs.named_ifs("fern")], [0.01, 0.85, 0.07, 0.07])
        self.assertEqual([(m.a, m.d) for m in ifs.named_ifs("sierpinski")], [(0.5, 0.5)] * 3)
        koch = ifs.named_ifs("koch")
        self.assertEqual(len(koch), 4)
        self.assertAlmostEqual(math.hypot(koch[1].a, koch[1].c), 1 / 3, places=15)
        self.assertEqual(message(self, lambda: ifs.named_ifs("fen")),
                         'unknown IFS "fen"; give one of fern, sierpinski, koch')

    def test_maps_apply_and_barycentric_form(self):
        fern = ifs.barnsley_fern()
        self.assertEqual([m.probability for m in fern], [0.01, 0.85, 0.07, 0.07])
        w = ifs.AffineMap(a=0.5, d=0.5, e=0.25, f=1.0, probability=0.2)
        self.assertEqual((w.a, w.b, w.c, w.d, w.e, w.f, w.probability), (0.5, 0, 0, 0.5, 0.25, 1.0, 0.2))
        np.testing.assert_array_equal(ifs.apply(w, np.array([2.0, 4.0])), [1.25, 3.0])
        for m in fern:
            M = ifs.barycentric_matrix(m, self.TRIANGLE)
            images = np.array([ifs.apply(m, p) for p in self.TRIANGLE])
            assert_close(self, M @ self.TRIANGLE, images)
            assert_close(self, M.sum(axis=1), np.ones(3))
        a = ifs.affine_automaton(fern, self.TRIANGLE)
        self.assertEqual((a.state_count, a.labels(0)), (1, ["w0", "w1", "w2", "w3"]))
        self.assertEqual(message(self, lambda: ifs.apply(w, np.ones(3))),
                         "apply: the point has 3 values, expected 2 (x, y)")
        self.assertIn("degenerate", message(self, lambda: ifs.barycentric_matrix(w, np.zeros((3, 2)))))
        self.assertEqual(message(self, lambda: ifs.affine_automaton([], self.TRIANGLE)), "an IFS needs at least one affine map, none is given")

    def test_attractor_points_are_fixed_under_the_maps(self):
        maps = ifs.sierpinski_triangle()
        a = ifs.affine_automaton(maps, self.TRIANGLE)
        P = ifs.attractor_points(a, [self.TRIANGLE], 4)
        # The corners (fixed points of the maps) are attractor points; the attractor is w-invariant.
        for i, m in enumerate(maps):
            corner = ifs.fixed_point(a, 0, [i]) @ self.TRIANGLE
            assert_close(self, corner, [[0, 0], [1, 0], [0.5, math.sqrt(3) / 2]][i])
        deeper = ifs.attractor_points(a, [self.TRIANGLE], 5)
        # Start points of the depth-4 nodes map to start points of depth-5 nodes (the last point, an end,
        # does not).
        image = np.array([ifs.apply(maps[1], p) for p in P[:-1]])
        distance = np.min(np.linalg.norm(deeper[None, :, :] - image[:, None, :], axis=2), axis=1)
        self.assertLess(distance.max(), 1e-12)

    def test_similarity_dimensions(self):
        cases = {"sierpinski": (ifs.sierpinski_triangle(), math.log(3) / math.log(2)),
                 "koch": (ifs.koch_curve(), math.log(4) / math.log(3))}
        for name, (maps, expected) in cases.items():
            with self.subTest(name):
                self.assertAlmostEqual(ifs.similarity_dimension(maps), expected, delta=1e-12)
                a = ifs.affine_automaton(maps, self.TRIANGLE)
                self.assertAlmostEqual(ifs.similarity_dimension(a, [self.TRIANGLE]), expected, delta=1e-12)
        self.assertEqual(message(self, lambda: ifs.similarity_dimension(ifs.barnsley_fern())),
                         "similarity dimension: map 0 is not a similarity (LᵀL = [0 0; 0 0.0256] is not r²·I)")
        self.assertEqual(ifs.similarity_ratio(np.array([[0, 0.5], [-0.5, 0]])), 0.5)
        self.assertEqual(ifs.similarity_ratio(np.diag([1.0, 2.0])), -1)

    def test_mauldin_williams(self):
        # Two states, every edge of ratio ½: ρ(A(s)) = 2·2^-s, so s = 1.
        edges = [(0, 0, 0.5), ifs.SimilarityEdge(0, 1, 0.5), (1, 0, 0.5), [1, 1, 0.5]]
        self.assertAlmostEqual(ifs.mauldin_williams_dimension(2, edges), 1.0, delta=1e-12)
        # Moran: three maps of ratio ½ on one state.
        self.assertAlmostEqual(ifs.mauldin_williams_dimension(1, [(0, 0, 0.5)] * 3), math.log(3) / math.log(2),
                               delta=1e-12)
        self.assertEqual(message(self, lambda: ifs.mauldin_williams_dimension(1, [(0, 5, 0.5)])),
                         "similarity dimension: an edge 0 → 5 leaves the 1 states")
        self.assertEqual(message(self, lambda: ifs.mauldin_williams_dimension(1, [(0, 0, 0.0)])),
                         "similarity dimension: the ratio 0 of an edge 0 → 0 is not finite and > 0")
        self.assertEqual(message(self, lambda: ifs.mauldin_williams_dimension(2, [(0, 1, 0.5)])),
                         "similarity dimension: the graph has no cycle")
        self.assertEqual(message(self, lambda: ifs.mauldin_williams_dimension(1, [(0, -1, 0.5)])),
                         "mauldin_williams_dimension: edges[0]: state -1 is negative")


class DimensionTest(unittest.TestCase):
    def check_against_cli(self, name, maps, expected_similarity, depth):
        path = EXAMPLES / "experiments" / name
        report = cli_json("dimension", path, "--json", "--depth", depth)
        triangle = AffineTest.TRIANGLE
        points = ifs.attractor_points(ifs.affine_automaton(maps, triangle), [triangle], depth)
        self.assertEqual(len(points), report["points"])
        r = ifs.box_counting(points, resolution=report["resolution"])
        box = report["box_counting"]
        np.testing.assert_array_equal(r.count_boxes, [c["boxes"] for c in box["counts"]])
        np.testing.assert_array_equal(r.count_levels, [c["level"] for c in box["counts"]])
        self.assertEqual([c.boxes for c in r.counts], [c["boxes"] for c in box["counts"]])
        assert_close(self, r.count_epsilons, [c["epsilon"] for c in box["counts"]])
        self.assertEqual([r.min_level, r.max_level], box["levels"])
        assert_close(self, [r.dimension, r.r_squared, r.size, r.max_epsilon, r.min_epsilon],
                     [box["dimension"], box["r_squared"], box["size"], *box["epsilon"]], what="box counting")
        self.assertAlmostEqual(r.residual, box["residual"], delta=1e-12)
        self.assertAlmostEqual(report["similarity_dimension"], expected_similarity, delta=1e-12)
        # A user range and the line's intercept.
        fixed = ifs.box_counting(points, min_level=2, max_level=6)
        counts = np.array([c["boxes"] for c in box["counts"]])[2:7]
        slope, intercept = np.polyfit(np.log(1 / r.count_epsilons[2:7]), np.log(counts), 1)
        assert_close(self, [fixed.dimension, fixed.intercept], [slope, intercept], rel=1e-10)

    def test_sierpinski_against_cli(self):
        self.check_against_cli("sierpinski.json", ifs.sierpinski_triangle(), math.log(3) / math.log(2), 12)

    def test_koch_against_cli(self):
        self.check_against_cli("koch.json", ifs.koch_curve(), math.log(4) / math.log(3), 10)

    def test_bad_samples(self):
        self.assertEqual(message(self, lambda: ifs.box_counting(np.zeros((0, 2)))), "box counting: no points")
        self.assertEqual(message(self, lambda: ifs.box_counting(np.ones((5, 2)))), "box counting: all points are equal")
        few = np.random.default_rng(0).random((100, 2))
        self.assertIn("evaluate deeper", message(self, lambda: ifs.box_counting(few)))


@unittest.skipUnless(hasattr(cifs.experiment, "evaluate") and hasattr(cifs.io, "read_experiment"),
                     "needs the experiment bindings")
class ExperimentDimensionTest(unittest.TestCase):
    def test_same_points_same_result_as_cli(self):
        for name, depth in (("sierpinski.json", 12), ("koch.json", 10)):
            with self.subTest(name):
                path = EXAMPLES / "experiments" / name
                report = cli_json("dimension", path, "--json", "--depth", depth)
                ev = cifs.experiment.evaluate(cifs.io.read_experiment(path), depth)
                np.testing.assert_array_equal(ifs.attractor_points(ev.automaton, ev.nets, depth), ev.points)
                r = ifs.box_counting(ev.points, resolution=ev.resolution)
                box = report["box_counting"]
                self.assertEqual((r.dimension, r.r_squared, [r.min_level, r.max_level]),
                                 (box["dimension"], box["r_squared"], box["levels"]))
                self.assertEqual(r.count_boxes.tolist(), [c["boxes"] for c in box["counts"]])
                self.assertEqual(ifs.similarity_dimension(ev.maps), report["similarity_dimension"])
                self.assertAlmostEqual(ifs.similarity_dimension(ev.automaton, ev.nets), report["similarity_dimension"],
                                       delta=1e-12)

    def test_measure_dimension_is_the_cli_measurement(self):
        """The whole policy of `cifs dimension` (route, relaxation, coarser sample, cover, similarity)."""
        # 2^18 points (2^16 sanitized: ASan's 10–30×) keep it seconds (the default 2^21: a minute per side);
        # levels of 200 boxes keep the fit strict.
        budget, boxes = 2**(16 if SANITIZED else 18), 200
        cases = (("clover_fractal.json", {"max_points": budget, "min_boxes": boxes},
                  ("--max-points", budget, "--min-boxes", boxes)),
                 ("sierpinski.json", {"depth": 10}, ("--depth", 10)))
        for name, keywords, flags in cases:
            with self.subTest(name):
                path = EXAMPLES / "experiments" / name
                report = cli_json("dimension", path, "--json", *flags)
                m = cifs.experiment.measure_dimension(cifs.io.read_experiment(path), **keywords)
                box = report["box_counting"]
                self.assertEqual((m.route, m.description, m.sample.depth, len(m.sample.points), m.resolution),
                                 (report["mode"], report["route"], report["depth"], report["points"],
                                  report["resolution"]))
                self.assertEqual((m.dimension, m.uncertainty, list(m.range), m.coarser, m.relaxed),
                                 (box["dimension"], box["uncertainty"], box["range"], box["coarser_dimension"],
                                  report["relaxed"]))
                self.assertEqual([m.fit.min_level, m.fit.max_level], box["levels"])
                self.assertEqual(m.similarity, report["similarity_dimension"])
                self.assertEqual(m.cover.dimension if m.cover else None,
                                 report["cover"]["dimension"] if report["cover"] else None)
                self.assertIn(" ± ", repr(m))
        curve = cifs.io.read_shape(EXAMPLES / "shapes" / "wave.json")
        report = cli_json("dimension", EXAMPLES / "shapes" / "wave.json", "--json", "--max-points", budget)
        m = cifs.experiment.measure_dimension(curve, max_points=budget)
        self.assertEqual((m.dimension, m.uncertainty), (report["box_counting"]["dimension"],
                                                         report["box_counting"]["uncertainty"]))
        self.assertLess(abs(m.dimension - 1), 0.05)

    def test_measure_dimension_of_subdivision_surfaces(self):
        """A Catmull–Clark or Loop mesh experiment is measured on its surface automaton's attractor (perturbed
        as the file says), the same in the CLI and in Python; other schemes are refused in one line."""
        budget = 2**16
        path = EXAMPLES / "experiments" / "subdivision_icosahedron_fractal.json"
        report = cli_json("dimension", path, "--json", "--max-points", budget)
        m = cifs.experiment.measure_dimension(cifs.io.read_experiment(path), max_points=budget)
        box = report["box_counting"]
        self.assertEqual((m.route, m.description, len(m.sample.points), m.sample.kind),
                         (report["mode"], report["route"], report["points"], report["kind"]))
        self.assertEqual((m.dimension, m.uncertainty, list(m.range)),
                         (box["dimension"], box["uncertainty"], box["range"]))
        self.assertIn("fractal loop surface of icosahedron.obj", m.sample.kind)
        # A smooth closed surface: 2, less the box count's downward bias at coarse scales (the overall
        # shape; docs/dimension.md): 1.92 ± 0.065 here at 2^16 points, 1.95 ± 0.063 on the Catmull–Clark
        # cube at 2^21, whose proven cover grows as ε^-2.001.
        smooth = cifs.experiment.measure_dimension(
            cifs.io.read_experiment(EXAMPLES / "experiments" / "subdivision_tetrahedron_loop.json"), max_points=budget)
        self.assertEqual(smooth.route, "tolerance")  # proven: the unperturbed automaton's pieces are bounded
        self.assertLess(abs(smooth.dimension - 2), 0.1)
        refused = cli("dimension", EXAMPLES / "experiments" / "subdivision_cube_doo_sabin.json", check=False)
        self.assertEqual(refused.returncode, 2)
        self.assertEqual(refused.stderr.strip().count("\n"), 0)
        self.assertIn("a doo-sabin surface has no automaton to evaluate or sample", refused.stderr)

    def test_box_counting_reports_its_uncertainty(self):
        r = ifs.box_counting(ifs.attractor_points(ifs.affine_automaton(ifs.sierpinski_triangle(), AffineTest.TRIANGLE),
                                                  [AffineTest.TRIANGLE], 10))
        self.assertEqual(r.uncertainty, max(r.standard_error, r.spread))
        self.assertIn(f"dimension={r.dimension!r} ± {r.uncertainty!r}", repr(r))

    def test_tolerance_sample_same_result_as_cli(self):
        # The CLI's default: a sample of proven resolution, fitted without the points-per-box rule.
        path = EXAMPLES / "experiments" / "clover_fractal.json"
        # 2^18 points (seconds under the sanitizers; the default 2^21 takes a minute per side) fit strictly
        # from levels of 200 boxes.
        budget, boxes = 2**18, 200
        report = cli_json("dimension", path, "--json", "--max-points", budget, "--min-boxes", boxes)
        ev = cifs.experiment.sample(cifs.io.read_experiment(path), max_points=budget)
        r = ifs.box_counting(ev.points, resolution=ev.resolution, points_per_box=1, min_boxes=boxes)
        box = report["box_counting"]
        self.assertEqual((r.dimension, [r.min_level, r.max_level]), (box["dimension"], box["levels"]))
        self.assertGreaterEqual(r.dimension, 1.0)
        # The library's own route gives the same sample from the perturbed automaton.
        direct = ifs.tolerance_sample(ev.automaton, ev.nets, epsilon=ev.resolution)
        np.testing.assert_array_equal(direct.points, ev.points)
        bounds = ifs.PieceBounds(ev.automaton)
        self.assertTrue(all(np.isfinite(bounds(ev.automaton, e.state, net).diameter)
                            for e, net in zip(ev.automaton.initial, ev.nets)))


@unittest.skipUnless(hasattr(cifs.io, "read_shape"), "needs the io bindings")
class NurbsAttractorTest(unittest.TestCase):
    def shape(self, name):
        path = EXAMPLES / "shapes" / name
        return path, cifs.io.read_shape(path)

    def test_attractor_points_against_cli(self):
        for name in ("cubic.json", "closed_cubic.json"):
            with self.subTest(name):
                path, c = self.shape(name)
                a = automata.knot_automaton(c)
                nets = automata.initial_nets(a, c)
                expected = np.array(cli_json("attractor", path, "--depth", 6)["points"])
                H = ifs.attractor_points(a, nets, 6, closed=name.startswith("closed"))
                points = ifs.cartesian(H) if c.rational else H
                assert_close(self, points, expected, rel=0, what=name)

    def test_tolerance_and_chaos_against_cli(self):
        path, c = self.shape("cubic.json")
        a = automata.knot_automaton(c)
        nets = automata.initial_nets(a, c)
        f = ifs.end_functionals(a)
        rows = []
        ends = []
        ifs.for_each_leaf_to_tolerance(a, nets, lambda t: (rows.append(f.start[t.leaf.state] @ t.leaf.net),
                                                           ends.append(f.end[t.leaf.state] @ t.leaf.net)),
                                       epsilon=1e-3, max_depth=40)
        expected = np.array(cli_json("attractor", path, "--piece-size", 1e-3)["points"])
        assert_close(self, np.array(rows + ends[-1:]), expected, rel=0, what="tolerance")
        chaos = cli_json("attractor", path, "--chaos", 500, "--seed", 11)
        r = ifs.chaos_game(a, nets, samples=500, seed=11)
        assert_close(self, r.points, np.array(chaos["points"]), rel=0, what="chaos")
        self.assertEqual(r.seed, chaos["seed"])

    def test_surface_mesh_routes_agree(self):
        _, s = self.shape("saddle.json")
        t = automata.tensor_automaton(s)
        nets = automata.initial_nets(t, s)
        homogeneous = nets[0].shape[1] == 4
        separable = ifs.surface_mesh(t, nets, 3, homogeneous=homogeneous)
        generic = ifs.quad_mesh(t.product, nets, t.patches, 3, homogeneous=homogeneous)
        assert_close(self, separable.vertices, generic.vertices, rel=1e-12)
        np.testing.assert_array_equal(separable.quads, generic.quads)
        np.testing.assert_array_equal(separable.states, generic.states)
        # The generic route's topology built once, applied to the nets and to moved nets.
        table = ifs.mesh_stencil_table(t.product, 3, patches=t.patches)
        self.assertIn("MeshStencilTable(depth 3", repr(table))
        applied = table.apply(nets, homogeneous=homogeneous)
        assert_close(self, applied.vertices, generic.vertices, rel=1e-14, what="table vs quad_mesh")
        np.testing.assert_array_equal(applied.states, generic.states)
        moved = [n + np.r_[np.ones(3), np.zeros(n.shape[1] - 3)] * n[:, -1:] if homogeneous else n + 1
                 for n in nets]
        shifted = table.apply(moved, homogeneous=homogeneous)
        assert_close(self, shifted.vertices, generic.vertices + 1, rel=1e-12, what="translated nets")
        self.assertEqual(message(self, lambda: table.apply(nets[:1])),
                         "1 control nets given for the automaton's 2 initial entries (one net per entry)")

    def test_meshes_into_out_with_keep_faces(self):
        """out= reuses a mesh (the same object is returned); keep_faces=True writes only its vertices: a sweep over
        nets gives, bit for bit, the meshes computed afresh, for the three routes."""
        _, s = self.shape("saddle.json")
        t = automata.tensor_automaton(s)
        nets = automata.initial_nets(t, s)
        homogeneous = nets[0].shape[1] == 4
        table = ifs.mesh_stencil_table(t.product, 3, patches=t.patches)
        routes = {
            "surface_mesh": lambda n, **k: ifs.surface_mesh(t, n, 3, homogeneous=homogeneous, **k),
            "quad_mesh": lambda n, **k: ifs.quad_mesh(t.product, n, t.patches, 3, homogeneous=homogeneous, **k),
            "MeshStencilTable.apply": lambda n, **k: table.apply(n, homogeneous=homogeneous, **k),
        }
        rng = np.random.default_rng(5)
        for name, route in routes.items():
            out = route(nets)
            for frame in range(3):
                moved = [n + rng.normal(scale=0.1, size=n.shape) * (np.arange(n.shape[1]) < 3) for n in nets]
                self.assertIs(route(moved, out=out, keep_faces=True), out, name)
                fresh = route(moved)
                np.testing.assert_array_equal(out.vertices, fresh.vertices, err_msg=f"{name} frame {frame}")
                np.testing.assert_array_equal(out.face_vertices, fresh.face_vertices, err_msg=name)
                np.testing.assert_array_equal(out.face_offsets, fresh.face_offsets, err_msg=name)
                np.testing.assert_array_equal(out.states, fresh.states, err_msg=name)
            # out without keep_faces: everything written, into the same object.
            self.assertIs(route(nets, out=out), out)
            np.testing.assert_array_equal(out.vertices, route(nets).vertices)
        # keep_faces with the mesh of another depth (or none, or another mesh) is refused before any work.
        depth2 = ifs.surface_mesh(t, nets, 2, homogeneous=homogeneous)
        before = depth2.vertices.copy()
        for name, call in [
            ("surface_mesh", lambda: ifs.surface_mesh(t, nets, 3, homogeneous=homogeneous, out=depth2, keep_faces=True)),
            ("quad_mesh", lambda: ifs.quad_mesh(t.product, nets, t.patches, 3, homogeneous=homogeneous, out=depth2,
                                                keep_faces=True)),
            ("MeshStencilTable.apply", lambda: table.apply(nets, homogeneous=homogeneous, out=depth2,
                                                           keep_faces=True)),
        ]:
            text = message(self, call)
            self.assertTrue(text.startswith(f"{name}: out: keep_faces"), text)
            self.assertIn(f"({4**3 * len(t.patches)} quads), out has {4**2 * len(t.patches)} states", text)
        np.testing.assert_array_equal(depth2.vertices, before)
        self.assertEqual(message(self, lambda: ifs.surface_mesh(t, nets, 3, keep_faces=True)),
                         "surface_mesh: keep_faces: needs the mesh of an earlier call as out=")
        triangles = cifs.io.Mesh(np.zeros((3, 3)), np.array([[0, 1, 2]]))
        self.assertIn("out: keep_faces", message(self, lambda: ifs.surface_mesh(t, nets, 3, out=triangles,
                                                                               keep_faces=True)))


if __name__ == "__main__":
    unittest.main()
