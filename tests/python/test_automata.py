# SPDX-License-Identifier: MIT
"""cifs.automata: hand-made automata (Chaikin's), accessors, checks, JSON/DOT/SVG, minimisation, tensor
helpers; knot and tensor automata against the `cifs automaton` command line."""
import copy
import json
import unittest

import numpy as np

import cifs
from cifs import automata
from support import CHAIKIN_D, CHAIKIN_G, chaikin, EXAMPLES, assert_close, cli, cli_json

# Chaikin: the uniform quadratic B-spline segment split at its midpoint (halves G and D).
G, D = CHAIKIN_G, CHAIKIN_D


class HandMadeAutomatonTest(unittest.TestCase):
    def test_accessors(self):
        a = automata.Automaton()
        self.assertEqual(a.state_count, 0)
        self.assertEqual(a.add_state(3, "p"), 0)
        self.assertEqual(a.add_state(2), 1)
        self.assertEqual(a.add_transition(0, 1, np.full((2, 3), 1 / 3), "x"), 0)
        self.assertEqual(a.add_transition(0, 0, G, "y"), 1)
        self.assertEqual(a.add_transition(1, 1, np.eye(2) * 0.5 + 0.25), 0)
        self.assertEqual(a.add_initial(0, segment=7, start=1.0, end=2.0, span=3), 0)
        self.assertEqual(a.add_initial(1), 1)
        self.assertEqual(a.state_count, 2)
        self.assertEqual([s.size for s in a.states], [3, 2])
        self.assertEqual(a.state(0).name, "p")
        self.assertEqual(a.state(1).window, [])
        self.assertFalse(a.state(0).recurrent)
        self.assertEqual(a.children(0), [1, 0])
        self.assertEqual(a.labels(0), ["x", "y"])
        np.testing.assert_array_equal(a.matrix(0, 1), G)
        t = a.transitions
        self.assertEqual([(x.source, x.child, x.target, x.label) for x in t],
                         [(0, 0, 1, "x"), (0, 1, 0, "y"), (1, 0, 1, "")])
        np.testing.assert_array_equal(t[0].matrix, np.full((2, 3), 1 / 3))
        i = a.initial
        self.assertEqual([(e.segment, e.state, e.start, e.end, e.span) for e in i],
                         [(7, 0, 1.0, 2.0, 3), (1, 1, 0.0, 0.0, -1)])
        a.set_matrix(0, 1, D)
        np.testing.assert_array_equal(a.matrix(0, 1), D)
        self.assertIn("2 states", repr(a))
        self.assertIn("name='p'", repr(a.state(0)))

    def test_copies_are_independent(self):
        a = chaikin()
        for b in (a.copy(), copy.copy(a), copy.deepcopy(a)):
            b.add_state(4)
            b.set_matrix(0, 0, D)
            self.assertEqual(a.state_count, 1)
            np.testing.assert_array_equal(a.matrix(0, 0), G)
        # Results handed out are copies too.
        m = a.matrix(0, 0)
        m[0, 0] = 9
        np.testing.assert_array_equal(a.matrix(0, 0), G)

    def test_bad_input_is_refused_with_the_library_style(self):
        a = chaikin()
        cases = [
            (lambda: a.add_transition(0, 5, G), "add_transition: state 5 does not exist (the automaton has 1 states)"),
            (lambda: a.add_transition(-1, 0, G),
             "add_transition: state -1 does not exist (the automaton has 1 states)"),
            (lambda: a.add_transition(0, 0, np.ones((2, 3)) / 3),
             "add_transition 0 -> 0: matrix is 2 by 3, expected 3 by 3 (to.size by from.size)"),
            (lambda: a.add_transition(0, 0, np.array([[np.nan, 1, 0]] * 3)),
             "add_transition 0 -> 0: matrix has a non-finite entry"),
            (lambda: a.set_matrix(0, 1, np.eye(2)),
             "set_matrix 0 child 1: matrix is 2 by 2, expected 3 by 3 (to.size by from.size)"),
            (lambda: a.set_matrix(0, 2, G), "set_matrix: child 2 but state 0 has 2 children"),
            (lambda: a.matrix(0, -1), "matrix: child -1 but state 0 has 2 children"),
            (lambda: a.matrix(3, 0), "matrix: state 3 does not exist (the automaton has 1 states)"),
            (lambda: a.state(1), "state: state 1 does not exist (the automaton has 1 states)"),
            (lambda: a.children(2), "children: state 2 does not exist (the automaton has 1 states)"),
            (lambda: a.add_initial(4), "add_initial: state 4 does not exist (the automaton has 1 states)"),
            (lambda: a.add_state(0), "add_state: size is 0, a state holds at least 1 point"),
        ]
        for call, message in cases:
            with self.subTest(message=message):
                with self.assertRaises(cifs.InvalidInput) as raised:
                    call()
                self.assertEqual(str(raised.exception), message)
        # Nothing was added by the refused calls.
        self.assertEqual((a.state_count, len(a.transitions), len(a.initial)), (1, 2, 1))

    def test_to_json_matches_the_accessors(self):
        a = chaikin()
        j = json.loads(automata.to_json(a))
        self.assertEqual([(s["id"], s["size"]) for s in j["states"]], [(0, 3)])
        self.assertEqual([(t["from"], t["to"], t["label"]) for t in j["transitions"]],
                         [(t.source, t.target, t.label) for t in a.transitions])
        for t, u in zip(j["transitions"], a.transitions):
            np.testing.assert_array_equal(np.array(t["matrix"]), u.matrix)
        self.assertEqual([e["state"] for e in j["initial"]], [0])

    def test_dot_and_svg(self):
        a = chaikin()
        dot = automata.to_dot(a)
        self.assertIn("digraph", dot)
        self.assertIn("G", dot)
        svg = automata.to_svg(a)
        self.assertIn("<svg", svg)
        self.assertTrue(svg.rstrip().endswith("</svg>"))

    def test_notebooks_show_the_drawing(self):
        # IPython's rich display calls _repr_svg_: the automaton's drawing, one circle per state.
        a = automata.knot_automaton(cifs.io.read_shape(str(EXAMPLES / "shapes" / "wave.json")))
        svg = a._repr_svg_()
        self.assertTrue(svg.startswith("<svg"))
        self.assertEqual(svg.count("<circle"), a.state_count)

    def test_mark_recurrent(self):
        # 0 → 1 ⟲: 0 is transient, 1 recurs, 2 hangs below the cycle (recurrent by definition).
        a = automata.Automaton()
        for _ in range(3):
            a.add_state(2)
        half = np.array([[1, 0], [0.5, 0.5]])
        a.add_transition(0, 1, half)
        a.add_transition(1, 1, half)
        a.add_transition(1, 2, half)
        a.add_transition(2, 2, half)
        automata.mark_recurrent(a)
        self.assertEqual([s.recurrent for s in a.states], [False, True, True])

    def test_minimize_merges_indistinguishable_states(self):
        # Two copies of Chaikin's state pointing at each other: one class.
        a = automata.Automaton()
        a.add_state(3)
        a.add_state(3)
        a.add_transition(0, 1, G, "G")
        a.add_transition(0, 0, D, "D")
        a.add_transition(1, 0, G, "G")
        a.add_transition(1, 1, D, "D")
        a.add_initial(1)
        m = automata.minimize(a)
        self.assertEqual(m.state_count, 1)
        self.assertEqual(m.children(0), [0, 0])
        self.assertEqual(m.labels(0), ["G", "D"])
        self.assertEqual(m.initial[0].state, 0)
        # A different matrix keeps the states apart.
        a.set_matrix(1, 1, G)
        self.assertEqual(automata.minimize(a).state_count, 2)

    def test_kron_and_v_label(self):
        rng = np.random.default_rng(1)
        A, B = rng.random((2, 3)), rng.random((4, 2))
        np.testing.assert_array_equal(automata.kron(A, B), np.kron(A, B))
        self.assertEqual([automata.v_label(x) for x in ("G", "D", "w0")], ["H", "B", "w0"])


@unittest.skipUnless(hasattr(cifs.io, "read_shape"), "needs the io bindings")
class KnotAutomatonTest(unittest.TestCase):
    def check_against_cli(self, name, minimize=False):
        path = EXAMPLES / "shapes" / name
        curve = cifs.io.read_shape(path)
        a = automata.knot_automaton(curve)
        if minimize:
            a = automata.minimize(a)
        expected = cli_json("automaton", path, "--format", "json", *(["--minimize"] if minimize else []))
        self.assertEqual(json.loads(automata.to_json(a)), expected)
        self.assertEqual(a.state_count, len(expected["states"]))
        for s, e in zip(a.states, expected["states"]):
            self.assertEqual((s.size, s.window, s.recurrent), (e["size"], e["window"], e["recurrent"]))
        self.assertEqual(len(a.transitions), len(expected["transitions"]))
        for t, e in zip(a.transitions, expected["transitions"]):
            self.assertEqual((t.source, t.target, t.label), (e["from"], e["to"], e["label"]))
            np.testing.assert_array_equal(t.matrix, np.array(e["matrix"]))
            np.testing.assert_array_equal(a.matrix(t.source, t.child), t.matrix)
        for i, e in zip(a.initial, expected["initial"]):
            self.assertEqual((i.segment, i.state, [i.start, i.end]), (e["segment"], e["state"], e["interval"]))
        flags = ["--minimize"] if minimize else []
        self.assertEqual(automata.to_dot(a).strip(), cli("automaton", path, "--format", "dot", *flags).stdout.strip())
        self.assertEqual(automata.to_svg(a).strip(), cli("automaton", path, "--format", "svg", *flags).stdout.strip())
        return curve, a

    def test_cubic_against_cli(self):
        curve, a = self.check_against_cli("cubic.json")
        # The nets of the segments are consecutive rows of the control points.
        nets = automata.initial_nets(a, curve)
        P = np.array(json.loads((EXAMPLES / "shapes" / "cubic.json").read_text())["curve"]["points"], dtype=float)
        self.assertEqual(len(nets), len(a.initial))
        for i, net in zip(a.initial, nets):
            np.testing.assert_array_equal(net, P[i.span - 3:i.span + 1])

    def test_minimized_and_closed_against_cli(self):
        self.check_against_cli("cubic.json", minimize=True)
        self.check_against_cli("closed_cubic.json")

    def test_tensor_automaton_of_a_surface(self):
        surface = cifs.io.read_shape(EXAMPLES / "shapes" / "saddle.json")
        t = automata.tensor_automaton(surface)
        u, v = t.factors
        fs = t.factor_states
        self.assertEqual(fs.shape, (t.product.state_count, 2))
        for tr in t.product.transitions:
            su, sv = fs[tr.source]
            iu, iv = divmod(tr.child, 2)
            mu, mv = u.matrix(int(su), iu), v.matrix(int(sv), iv)
            np.testing.assert_array_equal(tr.matrix, np.kron(mu, mv))
            self.assertEqual(tr.label, u.labels(int(su))[iu] + automata.v_label(v.labels(int(sv))[iv]))
        self.assertEqual(t.patches.shape, (len(t.product.initial), 2))
        nets = automata.initial_nets(t, surface)
        self.assertEqual([n.shape[0] for n in nets], [t.product.state(i.state).size for i in t.product.initial])


if __name__ == "__main__":
    unittest.main()
