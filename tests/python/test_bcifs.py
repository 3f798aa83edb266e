# SPDX-License-Identifier: MIT
"""BC-IFS (cifs.ifs) and BC-IFS files (cifs.io) against the file's own JSON, the `cifs render` run of
the same file (perturbed with the same seed) and the identities of docs/bcifs.md."""
import json
import re
import unittest

import numpy as np

import cifs
from cifs import ifs
from support import EXAMPLES, ScratchTestCase, assert_close, cli

TREE = EXAMPLES / "automata" / "tree.json"


def tree_json():
    return json.loads(TREE.read_text())["bcifs"]


def matrices(text):
    """{(source name, label): matrix} of BC-IFS JSON text."""
    transitions = json.loads(text)["bcifs"]["transitions"]
    return {(t["from"], t["label"]): np.array(t["matrix"], dtype=float) for t in transitions}


def unknown_values(text, free_keys):
    """Entries of the free matrices, free transitions in order, row-major (AdmissibleSpace.unknowns)."""
    m = matrices(text)
    return np.concatenate([m[key].ravel() for key in free_keys])


FREE_KEYS = [("E", "G"), ("E", "D"), ("E", "B")]  # tree.json's free transitions, in file order


def read_obj_segments(path):
    vertices = [list(map(float, line.split()[1:])) for line in path.read_text().splitlines() if line.startswith("v ")]
    return np.array(vertices)


class TreeFileTest(ScratchTestCase):
    def setUp(self):
        super().setUp()
        self.file = cifs.io.read_bcifs(TREE)
        self.system = self.file.system

    def write_variant(self, name, edit):
        data = json.loads(TREE.read_text())
        edit(data["bcifs"])
        path = self.scratch / name
        path.write_text(json.dumps(data))
        return path

    def render(self, automaton, perturbation, depth=2, check=True):
        """`cifs render` of an experiment on `automaton`; returns (CompletedProcess, OBJ path)."""
        experiment = {"name": "t", "automaton": str(automaton), "perturbation": perturbation,
                      "evaluation": {"depth": depth}, "render": {"width": 16, "height": 16},
                      "outputs": {"exr": "t.exr", "obj": "t.obj"}}
        path = self.scratch / "experiment.json"
        path.write_text(json.dumps(experiment))
        return cli("render", path, "--out-dir", self.scratch, "--quiet", check=check), self.scratch / "t.obj"

    def test_read_matches_the_file(self):
        data = tree_json()
        self.assertEqual(repr(self.file), "BcifsFile(cells=2, nets=1)")
        self.assertEqual(repr(self.system), "Bcifs(cells=2, boundaries=2, constraints=4, free=3)")
        self.assertEqual(self.system.dimension, [c["dimension"] for c in data["cells"]])
        self.assertEqual(self.system.free, [(0, 0), (0, 1), (0, 2)])
        self.assertEqual([(b.name, b.cell, b.boundary, b.rows) for b in self.system.boundaries],
                         [("start", 0, 1, [0]), ("end", 0, 1, [2])])
        self.assertEqual([c.name for c in self.system.constraints], [c["name"] for c in data["constraints"]])
        junction = self.system.constraints[2]
        self.assertEqual([(f.kind, f.boundary) for f in junction.left[:1]], [(ifs.Factor.Kind.boundary, 1)])
        self.assertEqual(junction.left[1].kind, ifs.Factor.Kind.transition)
        self.assertEqual(junction.left[1].transition, (0, 0))  # E/G
        self.assertEqual(junction.right[1].transition, (0, 1))  # E/D
        self.assertEqual(len(self.file.nets), 1)
        assert_close(self, self.file.nets[0], data["initial"][0]["net"], rel=0)
        same = cifs.io.parse_bcifs_json(TREE.read_text(), "tree.json")
        self.assertEqual(cifs.io.to_json(same.system, same.nets), cifs.io.to_json(self.system, self.file.nets))

    def test_to_json_round_trip(self):
        text = cifs.io.to_json(self.system, self.file.nets)
        back = cifs.io.parse_bcifs_json(text)
        self.assertEqual(cifs.io.to_json(back.system, back.nets), text)
        written = matrices(text)
        for t in tree_json()["transitions"]:
            assert_close(self, written[(t["from"], t["label"])], t["matrix"], rel=0)
        self.assertNotIn("initial\": [{\"net\"", cifs.io.to_json(self.system))
        with self.assertRaises(cifs.InvalidInput) as e:
            cifs.io.to_json(self.system, self.file.nets * 2)
        self.assertEqual(str(e.exception), "the BC-IFS has 1 initial entries but 2 control nets are given")

    def test_residuals_and_admissibility(self):
        residuals = ifs.constraint_residuals(self.system)
        self.assertEqual([name for name, _ in residuals],
                         ["start", "end", "junction", "branch", "E/G row sums", "E/D row sums", "E/B row sums"])
        self.assertLessEqual(max(r for _, r in residuals), 1e-12)
        ifs.check_admissible(self.system)

        def break_junction(b):  # G's last row no longer equals D's first row (E.end·G = E.start·D)
            b["transitions"][0]["matrix"][2] = [0.4, 0.1, 0.5]
        broken = cifs.io.read_bcifs(self.write_variant("broken.json", break_junction)).system
        residual = dict(ifs.constraint_residuals(broken))["junction"]
        self.assertAlmostEqual(residual, 0.1, delta=1e-15)  # max |(0.4, 0.1, 0.5) − (0.5, 0, 0.5)| / 1
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.check_admissible(broken)
        self.assertTrue(str(e.exception).startswith('BC-IFS: the matrices are not admissible: constraint "junction"'),
                        str(e.exception))
        ifs.check_admissible(broken, 0.2)

    def test_selection_matrix(self):
        assert_close(self, ifs.selection_matrix(self.system, 0), [[1, 0, 0]], rel=0)
        assert_close(self, ifs.selection_matrix(self.system, 1), [[0, 0, 1]], rel=0)
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.selection_matrix(self.system, 2)
        self.assertEqual(str(e.exception), "selection_matrix: boundary 2 does not exist (2 boundary operators)")

    def test_admissible_space(self):
        space = ifs.admissible_space(self.system)
        n = 27  # three free 3 by 3 matrices
        self.assertEqual(space.shape, (n, len(space.free)))
        self.assertEqual(space.unknown_names, [f"E/{l}[{i},{j}]" for l in "GDB" for i in range(3) for j in range(3)])
        self.assertEqual([(u.transition, u.row, u.col) for u in space.unknowns],
                         [((0, c), i, j) for c in range(3) for i in range(3) for j in range(3)])
        row, col, value = space.K
        dense = np.zeros(space.shape)
        dense[row, col] = value
        assert_close(self, space.dense(), dense, rel=0)
        free = space.free
        self.assertTrue(np.all(np.diff(free) > 0))
        assert_close(self, dense[free], np.eye(len(free)), rel=0)  # a unit row at each free index
        names = ifs.free_names(self.system, space)
        self.assertEqual(names, [space.unknown_names[k] for k in free])
        text = cifs.io.to_json(self.system)
        x = unknown_values(text, FREE_KEYS)
        c = ifs.free_values(self.system, space)
        assert_close(self, c, x[free], rel=0)
        # The file's matrices are admissible: they are x0 + K·c for their own free values.
        assert_close(self, space.x0 + space.dense() @ c, x)
        self.assertGreaterEqual(space.components, 1)
        self.assertEqual(repr(space), f"AdmissibleSpace(unknowns=27, free={len(free)}, components={space.components})")

    def test_with_free_values(self):
        space = ifs.admissible_space(self.system)
        c = ifs.free_values(self.system, space)
        same = ifs.with_free_values(self.system, space, c)
        before, after = matrices(cifs.io.to_json(self.system)), matrices(cifs.io.to_json(same))
        for key in before:
            assert_close(self, after[key], before[key])
        shifted = ifs.with_free_values(self.system, space, c + 0.01)
        assert_close(self, ifs.free_values(shifted, space), c + 0.01)
        self.assertLessEqual(max(r for _, r in ifs.constraint_residuals(shifted)), 1e-12)
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.with_free_values(self.system, space, c[:3])
        self.assertEqual(str(e.exception), f"BC-IFS: 3 values for {len(c)} free coefficients")

    def test_perturb(self):
        space = ifs.admissible_space(self.system)
        names = ifs.free_names(self.system, space)
        p = ifs.perturb(self.system, amplitude=0.05, seed=3)
        self.assertEqual([name for name, _ in p.values], names)
        values = np.array([v for _, v in p.values])
        assert_close(self, ifs.free_values(p.system, space), values, rel=0)
        offsets = values - ifs.free_values(self.system, space)
        self.assertTrue(np.all(np.abs(offsets) <= 0.05) and np.any(offsets != 0))
        self.assertLessEqual(p.residual, 1e-12)
        self.assertLessEqual(max(r for _, r in ifs.constraint_residuals(p.system)), 1e-12)
        # Same seed, same values; another seed, other values; amplitude 0 keeps the system.
        self.assertEqual(ifs.perturb(self.system, amplitude=0.05, seed=3).values, p.values)
        self.assertNotEqual(ifs.perturb(self.system, amplitude=0.05, seed=4).values, p.values)
        zero = ifs.perturb(self.system)
        assert_close(self, [v for _, v in zero.values], ifs.free_values(self.system, space), rel=0)
        # Values set by name replace the draw, and the other draws stay those of the seed.
        fixed = ifs.perturb(self.system, amplitude=0.05, seed=3, values={names[0]: 0.45})
        self.assertEqual(fixed.values[0], (names[0], 0.45))
        self.assertEqual(fixed.values[1:], p.values[1:])

    def test_perturb_matches_the_cli(self):
        # `cifs render` perturbs the same file with the same seed and writes the pieces' end points.
        result, obj = self.render(TREE, {"amplitude": 0.05, "seed": 3})
        p = ifs.perturb(self.system, amplitude=0.05, seed=3)
        summary = result.stdout.splitlines()[0]
        self.assertIn(f"{len(p.values)} free coefficients", summary)
        pieces = ifs.edge_pieces(p.system, self.file.nets, 2)
        vertices = read_obj_segments(obj)
        assert_close(self, vertices[:, :2], np.vstack([pieces.start, pieces.end]), what="perturbed pieces")
        # And the unperturbed pieces differ from them (the test can fail).
        plain = ifs.edge_pieces(self.system, self.file.nets, 2)
        self.assertGreater(np.max(np.abs(plain.start - pieces.start)), 1e-3)

    def test_perturb_bad_input(self):
        checks = [
            (dict(amplitude=-1.0), "the perturbation amplitude -1 is negative; give a finite amplitude ≥ 0"),
            (dict(values={"E/G[0,0]": 1.0}), 'the perturbation value "E/G[0,0]" is a dependent coefficient (solved from the constraints); the '
                                             'free coefficients are E/G[1,1], E/G[1,2], E/G[2,1], E/G[2,2], E/D[1,1], '
                                             'E/D[1,2], … (10 in all)'),
            (dict(values={"E/X[0,0]": 1.0}), 'the perturbation value "E/X[0,0]" is not an entry of a free matrix; the free coefficients are '
                                             'E/G[1,1], E/G[1,2], E/G[2,1], E/G[2,2], E/D[1,1], E/D[1,2], … (10 in all)'),
            (dict(max_length=0), "perturb: max_length is 0, must be in [1, 16]"),
        ]
        for kwargs, message in checks:
            with self.subTest(kwargs=kwargs):
                with self.assertRaises(cifs.InvalidInput) as e:
                    ifs.perturb(self.system, **kwargs)
                self.assertEqual(str(e.exception), message)
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.perturb(self.system, amplitude=5.0, seed=1)
        self.assertIn("the perturbed system is not contractive with amplitude 5, seed 1: not contractive",
                      str(e.exception))
        with self.assertRaises(TypeError):
            ifs.perturb(self.system, 0.1)  # keyword-only

    def test_inconsistent_constraints_have_the_cli_message(self):
        def contradict(b):  # E.start·G = V·E.start = (1, 0, 0) and now also = E.end = (0, 0, 1)
            b["constraints"].append({"name": "bad", "left": ["E.start", "E/G"], "right": ["E.end"]})
        path = self.write_variant("bad.json", contradict)
        system = cifs.io.read_bcifs(path).system
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.admissible_space(system)
        self.assertEqual(str(e.exception), 'BC-IFS: the constraints "start", "bad" have no common solution (they set '
                                           'E/G[0,0] to 1 and to 0)')
        result, _ = self.render(path, {"amplitude": 0.0}, check=False)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(result.stderr.strip(), "cifs: " + str(e.exception))
        with self.assertRaises(cifs.InvalidInput) as e2:
            ifs.perturb(system)
        self.assertEqual(str(e2.exception), str(e.exception))

    def test_bad_files_have_the_cli_message(self):
        def short_row(b):
            b["transitions"][2]["matrix"][1] = [0.5, 0.5]

        def unknown_cell(b):
            b["boundaries"][0]["boundary"] = "W"
        for name, edit in (("short.json", short_row), ("cell.json", unknown_cell)):
            path = self.write_variant(name, edit)
            with self.assertRaises(cifs.InvalidInput) as e:
                cifs.io.read_bcifs(path)
            result, _ = self.render(path, {"amplitude": 0.0}, check=False)
            self.assertEqual(result.stderr.strip(), "cifs: " + str(e.exception))
            with self.assertRaises(cifs.InvalidInput) as e2:
                cifs.io.parse_bcifs_json(path.read_text(), str(path))
            self.assertEqual(str(e2.exception), str(e.exception))
        self.assertRegex(str(e.exception), re.escape(str(path)) + ": bcifs.boundaries\\[0\\]")
        with self.assertRaises(cifs.IoError) as e:
            cifs.io.read_bcifs(self.scratch / "missing.json")
        self.assertEqual(str(e.exception), f"{self.scratch / 'missing.json'}: cannot open (No such file or directory)")
        with self.assertRaises(cifs.IoError):
            cifs.io.parse_bcifs_json("{", "text")

    def test_edge_pieces(self):
        for depth in (0, 1, 3):
            pieces = ifs.edge_pieces(self.system, self.file.nets, depth)
            count = 3 ** depth
            self.assertEqual(pieces.start.shape, (count, 2))
            self.assertEqual(pieces.state.tolist(), [0] * count)
            self.assertEqual(pieces.initial.tolist(), [0] * count)
            self.assertEqual(len(pieces.word), count)
            self.assertTrue(all(len(w) == depth for w in pieces.word))
        net = self.file.nets[0]
        root = ifs.edge_pieces(self.system, self.file.nets, 0)
        assert_close(self, root.start, net[[0]], rel=0)  # vertex V is fixed: its fixed point is 1
        assert_close(self, root.end, net[[2]], rel=0)
        one = ifs.edge_pieces(self.system, self.file.nets, 1)
        self.assertEqual(one.word, [[0], [1], [2]])
        # Incidence: G starts and D ends where the parent does; junction and branch: G's end = D's start = B's start.
        assert_close(self, one.start[0], root.start[0])
        assert_close(self, one.end[1], root.end[0])
        assert_close(self, one.end[0], one.start[1])
        assert_close(self, one.start[2], one.start[1])
        # The pieces are those matrices applied to the net: piece k's net is M_k·N.
        G = matrices(cifs.io.to_json(self.system))[("E", "G")]
        assert_close(self, one.end[0], (G @ net)[2])
        self.assertEqual(repr(one), "EdgePieces(count=3)")
        self.assertEqual(repr(ifs.perturb(self.system)), "Perturbation(values=10, residual=0.0)")
        checks = [
            (lambda: ifs.edge_pieces(self.system, [], 1), "0 control nets given for the automaton's 1 initial "
                                                          "entries (one net per entry)"),
            (lambda: ifs.edge_pieces(self.system, [net[:1]], 1),
             "control net 0 has 1 points but its initial state 0 (E) holds 3"),
            (lambda: ifs.edge_pieces(self.system, self.file.nets, -1), "the depth -1 is negative; give a depth ≥ 0"),
            (lambda: ifs.edge_pieces(self.system, self.file.nets, 30),
             "205891132094649 edge pieces at depth 30 need 3.95e+07 GB, above the limit of 1.07 GB; "
             "lower the depth"),
        ]
        for call, message in checks:
            with self.assertRaises(cifs.InvalidInput) as e:
                call()
            self.assertEqual(str(e.exception), message)

    def test_plain_classes(self):
        b = ifs.BoundaryOperator("start", 0, 1, [0])
        self.assertEqual((b.name, b.cell, b.boundary, b.rows), ("start", 0, 1, [0]))
        self.assertEqual(repr(b), "BoundaryOperator('start', cell=0, boundary=1)")
        f = ifs.Factor(boundary=1)
        self.assertEqual((f.kind, f.boundary), (ifs.Factor.Kind.boundary, 1))
        t = ifs.Factor(transition=(0, 2))
        self.assertEqual((t.kind, t.transition), (ifs.Factor.Kind.transition, (0, 2)))
        self.assertEqual(repr(t), "Factor(transition=(0, 2))")
        c = ifs.Constraint("junction", [ifs.Factor(boundary=1), ifs.Factor(transition=(0, 0))],
                           [ifs.Factor(boundary=0), ifs.Factor(transition=(0, 1))])
        self.assertEqual((c.name, len(c.left), c.right[1].transition), ("junction", 2, (0, 1)))
        k = ifs.Coefficient((0, 1), 2, 0)
        self.assertEqual((k.transition, k.row, k.col), ((0, 1), 2, 0))
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.Factor(transition=(-1, 0))
        self.assertEqual(str(e.exception), "transition (-1, 0): state and child are non-negative")
        with self.assertRaises(TypeError):
            ifs.Factor(transition=(0, 1, 2))
        with self.assertRaises(AttributeError):
            b.rows = [1]


@unittest.skipUnless(hasattr(cifs.automata, "Automaton"), "cifs.automata.Automaton is bound elsewhere")
class BuiltFromScratchTest(unittest.TestCase):
    def setUp(self):
        self.file = cifs.io.read_bcifs(TREE)
        self.system = self.file.system

    def test_rebuilt_system_is_the_same(self):
        s = self.system
        rebuilt = ifs.Bcifs(s.automaton, s.dimension, s.boundaries, s.constraints, s.free)
        self.assertEqual(cifs.io.to_json(rebuilt, self.file.nets), cifs.io.to_json(s, self.file.nets))
        a = s.automaton
        self.assertEqual(ifs.transition_name(a, (0, 2)), "E/B")
        self.assertEqual(ifs.coefficient_name(a, ifs.Coefficient((0, 1), 1, 2)), "E/D[1,2]")
        assert_close(self, a.matrix(0, 0), tree_json()["transitions"][0]["matrix"], rel=0)
        a.add_state(1, "X")  # a copy: the validated system keeps its two cells
        self.assertEqual(s.automaton.state_count, 2)
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.transition_name(a, (0, 3))
        self.assertEqual(str(e.exception), "transition 3 of state E, which has 3 transitions")

    def test_validation(self):
        s = self.system
        with self.assertRaises(cifs.InvalidInput) as e:
            ifs.Bcifs(s.automaton, [1], s.boundaries, s.constraints, s.free)
        self.assertEqual(str(e.exception), "BC-IFS: 1 cell dimensions for 2 states")
        with self.assertRaises(cifs.InvalidInput):
            ifs.Bcifs(s.automaton, s.dimension, s.boundaries, s.constraints, s.free + [(0, 0)])
        with self.assertRaises(cifs.InvalidInput):
            ifs.Bcifs(s.automaton, s.dimension, [ifs.BoundaryOperator("start", 0, 1, [5])], [], [])

    @unittest.skipUnless(hasattr(cifs.ifs, "EndFunctionals"), "cifs.ifs.EndFunctionals is bound elsewhere")
    def test_edge_end_functionals(self):
        F = ifs.edge_end_functionals(self.system)
        pieces = ifs.edge_pieces(self.system, self.file.nets, 0)
        assert_close(self, F.start[0] @ self.file.nets[0], pieces.start[0])
        assert_close(self, F.end[0] @ self.file.nets[0], pieces.end[0])

    @unittest.skipUnless(hasattr(cifs.ifs, "Contraction"), "cifs.ifs.Contraction is bound elsewhere")
    def test_perturbation_contraction(self):
        p = ifs.perturb(self.system, amplitude=0.02, seed=5)
        c = p.contraction
        self.assertLess(c.delta, 1)
        self.assertGreaterEqual(c.m, 1)


@unittest.skipUnless(hasattr(cifs.io, "read_shape") and hasattr(cifs.automata, "knot_automaton"),
                     "cifs.io.read_shape and cifs.automata.knot_automaton are bound elsewhere")
class NurbsSystemsTest(unittest.TestCase):
    def test_curve_system_is_admissible_and_keeps_the_knots(self):
        curve = cifs.io.read_shape(EXAMPLES / "shapes" / "wave.json")
        for free_vertices in (False, True):
            system = ifs.curve_bcifs(curve, free_vertices=free_vertices)
            self.assertLessEqual(max(r for _, r in ifs.constraint_residuals(system)), 1e-12)
            same = ifs.curve_bcifs(cifs.automata.knot_automaton(curve), False, free_vertices=free_vertices)
            self.assertEqual(cifs.io.to_json(same), cifs.io.to_json(system))
        kept = ifs.perturb(ifs.curve_bcifs(curve), amplitude=0.02, seed=2)
        free = ifs.perturb(ifs.curve_bcifs(curve, free_vertices=True), amplitude=0.02, seed=2)
        self.assertGreater(len(free.values), len(kept.values))
        nets = cifs.automata.initial_nets(cifs.automata.knot_automaton(curve), curve)
        before = ifs.edge_pieces(ifs.curve_bcifs(curve), nets, 0)
        after = ifs.edge_pieces(kept.system, nets, 0)
        # The segments' end points are at the knots: kept fixed.
        assert_close(self, after.start, before.start)
        assert_close(self, after.end, before.end)

    def test_surface_system_is_admissible(self):
        surface = cifs.io.read_shape(EXAMPLES / "shapes" / "hills.json")
        system = ifs.surface_bcifs(surface)
        self.assertLessEqual(max(r for _, r in ifs.constraint_residuals(system)), 1e-12)
        same = ifs.surface_bcifs(cifs.automata.tensor_automaton(surface))
        self.assertEqual(len(same.constraints), len(system.constraints))
        more = ifs.surface_bcifs(surface, free_knot_lines=True)
        self.assertGreater(len(more.free), len(system.free))


if __name__ == "__main__":
    unittest.main()


class FractalFitTest(ScratchTestCase):
    """cifs.ifs.fit_fractal: the attractor of a perturbed curve system is recovered from its own points
    (made by edge_pieces), and the fit's file reads back to the same attractor."""

    def test_recovers_a_perturbed_system_and_writes_it(self):
        polygon = np.array([[i + 0.3 * np.sin(3 * i), np.cos(1.7 * i)] for i in range(7)], dtype=float)
        curve = cifs.nurbs.uniform_bspline(polygon, 3, False)
        truth = ifs.perturb(ifs.curve_bcifs(curve, free_vertices=True), amplitude=0.15, seed=5).system
        nets = [polygon[i:i + 4] for i in range(4)]
        pieces = ifs.edge_pieces(truth, nets, 5)
        data = np.vstack([pieces.start, pieces.end[-1:]])
        fit = ifs.fit_fractal(data, control_points=7, parametrization="uniform", dimension_points=0)
        size = np.ptp(data, axis=0).max()
        self.assertGreater(fit.smooth_rms, 1e-4 * size)
        self.assertLess(fit.rms, 1e-11 * size)
        self.assertGreaterEqual(fit.holder_bound, 0.25)
        self.assertEqual(len(fit.coefficients), len(ifs.free_names(fit.system, ifs.admissible_space(fit.system))))
        path = self.scratch / "fit.json"
        cifs.io.write(path, fit.file)
        back = cifs.io.read_bcifs(path)
        again = ifs.edge_pieces(back.system, back.nets, 5)
        assert_close(self, np.vstack([again.start, again.end[-1:]]), data, rel=1e-10)

    def test_refuses_bad_input(self):
        points = np.array([[i, (-1) ** i] for i in range(20)], dtype=float)
        with self.assertRaisesRegex(cifs.InvalidInput, "control_points 3 is outside 4"):
            ifs.fit_fractal(points, control_points=3)
        with self.assertRaisesRegex(cifs.InvalidInput, "depth 0"):
            ifs.fit_fractal(points, control_points=5, depth=0)
        with self.assertRaisesRegex(cifs.InvalidInput, "min_holder 0 is not in"):
            ifs.fit_fractal(points, control_points=5, min_holder=0)
