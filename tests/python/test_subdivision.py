# SPDX-License-Identifier: MIT
"""cifs.subdivision against `cifs scheme` (analysis JSON, refined polygons, errors), published
smoothness values and exact identities (difference masks, power norms, refinement steps)."""
import json
import unittest
from fractions import Fraction

import numpy as np

import cifs
from cifs import subdivision as sd
from support import EXAMPLES, ScratchTestCase, assert_close, cli, cli_json, sampled

# (CLI name, parameters as the CLI takes them, the same scheme built in Python)
SCHEMES = [
    ("chaikin", {}, lambda: sd.chaikin()),
    ("four-point", {}, lambda: sd.four_point()),
    ("b-spline", {"degree": "3"}, lambda: sd.b_spline(3)),
    ("dual-four-point", {}, lambda: sd.dual_four_point()),
    ("generalized-four-point", {"w": "0.2"}, lambda: sd.generalized_four_point(Fraction(1, 5))),
    ("corner-cutting", {"a": "1/10", "b": "3/5"}, lambda: sd.corner_cutting("1/10", Fraction(3, 5))),
    ("romani", {"n": "2", "w": "1/32"}, lambda: sd.romani(2, Fraction(1, 32))),
    ("lr-four-point", {"stages": "1"}, lambda: sd.lr_four_point(1)),
    ("symbol", {"symbol": "(1+z)^4*(-1+4z-z^2)/16"}, lambda: sd.from_symbol("(1+z)^4*(-1+4z-z^2)/16")),
]


def cli_args(name, params):
    args = ["scheme", name]
    for key, value in params.items():
        args += ["--param", f"{key}={value}"]
    return args


_cli_analyses = {}


def cli_analysis(name, params):
    """`cifs scheme NAME --param … --analyze` as JSON, run once per scheme for the tests that compare with it."""
    key = (name, tuple(params.items()))
    if key not in _cli_analyses:
        _cli_analyses[key] = cli_json(*cli_args(name, params), "--analyze")
    return _cli_analyses[key]


def cli_error(*args):
    """The CLI's one-line error without its "cifs: " prefix (exit status 2)."""
    result = cli(*args, check=False)
    if result.returncode != 2:
        raise AssertionError(f"cifs {' '.join(args)} exited {result.returncode}, expected 2")
    line = result.stderr.strip()
    return line[len("cifs: "):] if line.startswith("cifs: ") else line


def norm_by_definition(c, L):
    """‖S_c^L‖_∞ from its definition: the largest sum of |coefficients| of Π_{i<L} c(z^{2^i}) over one
    residue class mod 2^L (plain Python Fractions, no library code)."""
    power = [Fraction(1)]
    for i in range(L):
        step = 2 ** i
        out = [Fraction(0)] * (len(power) + (len(c) - 1) * step)
        for j, cj in enumerate(c):
            for k, pk in enumerate(power):
                out[k + j * step] += cj * pk
        power = out
    period = 2 ** L
    return max(sum(abs(x) for x in power[r::period]) for r in range(period))


def multiply(p, q):
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return out


class RationalTest(unittest.TestCase):
    def test_accepted_inputs_are_exact(self):
        expected = sd.generalized_four_point(Fraction(1, 16)).mask
        for w in (Fraction(1, 16), "1/16", "0.0625", 0.0625, np.float64(0.0625)):
            self.assertEqual(sd.generalized_four_point(w).mask, expected, repr(w))
        self.assertEqual(sd.four_point().mask, expected)
        self.assertEqual(sd.j_spline(1).mask, sd.j_spline(np.int64(1)).mask)
        self.assertTrue(all(isinstance(x, Fraction) for x in expected))

    def test_floats_are_the_decimal_they_print_as(self):
        # Issue 15: numpy and Python floats are accepted and mean their printed decimal, as the CLI's
        # `--param w=0.1`; the exact binary value and exact rationals stay available as Fraction or text.
        tenth = sd.generalized_four_point(Fraction(1, 10)).mask
        for w in (0.1, np.float64(0.1), np.float32(0.1), np.linspace(0, 0.2, 3)[1], "0.1", "1/10"):
            self.assertEqual(sd.generalized_four_point(w).mask, tenth, repr(w))
        self.assertEqual(sd.generalized_four_point(w=0.1).parameters, {"w": Fraction(1, 10)})
        binary = sd.generalized_four_point(Fraction(0.1)).parameters["w"]
        self.assertEqual(binary, Fraction(3602879701896397, 36028797018963968))
        self.assertEqual(sd.named_scheme("corner-cutting", a=np.float64(0.1), b=0.6).mask,
                         sd.corner_cutting("1/10", "3/5").mask)
        # A float from arithmetic means what it prints as, not the number it rounds from.
        self.assertEqual(sd.generalized_four_point(0.1 + 0.2).parameters["w"],
                         Fraction(30000000000000004, 10**17))
        # Beyond the decimal parser's exponent range, the exact value.
        self.assertEqual(sd.generalized_four_point(5e-324).parameters["w"], Fraction(5e-324))
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.j_spline(float("inf"))
        self.assertEqual(str(e.exception), "j_spline: s: expected a finite number, got float inf")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.j_spline(np.float32("nan"))
        self.assertEqual(str(e.exception), "j_spline: s: expected a finite number, got numpy.float32 nan")
        with self.assertRaises(TypeError):
            sd.j_spline(True)

    def test_parse_rational_and_to_string(self):
        self.assertEqual(sd.parse_rational("0.5/3"), Fraction(1, 6))
        self.assertEqual(sd.parse_rational("-1e-3"), Fraction(-1, 1000))
        self.assertEqual(sd.to_string(Fraction(-3, 2)), "-1.5")
        self.assertEqual(sd.to_string(Fraction(1, 3)), "1/3")
        self.assertEqual(sd.to_string(7), "7")
        for x in (Fraction(1, 3), Fraction(-5, 32), Fraction(10**30 + 1, 7)):
            self.assertEqual(sd.parse_rational(sd.to_string(x)), x)
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.parse_rational("nan", "w")
        self.assertEqual(str(e.exception), "w: 'nan' is not a number (an integer, a decimal such as -0.0625 or a "
                         "fraction such as 1/16)")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.parse_rational("1/0")
        self.assertEqual(str(e.exception), "value: '1/0' divides by zero")


class SchemeTest(unittest.TestCase):
    def test_scheme_class(self):
        s = sd.Scheme("mine", [0, "0.25", Fraction(3, 4), 0.75, 0.25, 0], {"a": "1/4"})
        self.assertEqual(s.name, "mine")
        self.assertEqual(s.mask, [Fraction(1, 4), Fraction(3, 4), Fraction(3, 4), Fraction(1, 4)])  # trimmed
        self.assertEqual(s.parameters, {"a": Fraction(1, 4)})
        self.assertEqual(s.weights.dtype, np.float64)
        assert_close(self, s.weights, [0.25, 0.75, 0.75, 0.25])
        self.assertEqual(repr(s), "Scheme('mine', mask_degree=3)")
        self.assertEqual(sd.make_scheme("mine", s.mask).mask, sd.chaikin().mask)
        self.assertEqual(sd.mask_degree(s), 3)
        self.assertTrue(sd.is_symmetric(s))
        self.assertFalse(sd.is_symmetric(sd.corner_cutting("0.1", "0.6")))
        with self.assertRaises(AttributeError):
            s.mask = [1, 1]

    def test_named_constructors_match_the_documented_masks(self):
        F = Fraction
        self.assertEqual(sd.chaikin().mask, [F(1, 4), F(3, 4), F(3, 4), F(1, 4)])
        self.assertEqual(sd.corner_cutting(F(1, 4), F(3, 4)).mask, sd.chaikin().mask)
        self.assertEqual(sd.four_point().mask, [F(x, 16) for x in (-1, 0, 9, 16, 9, 0, -1)])
        self.assertEqual(sd.six_point().mask, [F(x, 256) for x in (3, 0, -25, 0, 150, 256, 150, 0, -25, 0, 3)])
        self.assertEqual(sd.dual_four_point().mask, [F(x, 128) for x in (-5, -7, 35, 105, 105, 35, -7, -5)])
        self.assertEqual(sd.lane_riesenfeld(3).mask, [F(x, 8) for x in (1, 4, 6, 4, 1)])
        self.assertEqual(sd.b_spline(3).mask, sd.lane_riesenfeld(3).mask)
        self.assertEqual(sd.two_tension(3, 0, 0).mask, sd.b_spline(3).mask)
        self.assertEqual(sd.j_spline(0).mask, sd.four_point().mask)
        self.assertEqual(sd.j_spline(1).mask, sd.b_spline(3).mask)
        self.assertEqual(sd.j_spline(F(3, 2)).mask, sd.b_spline(5).mask)
        self.assertEqual(sd.hormann_sabin(3).mask, sd.four_point().mask)
        self.assertEqual(sd.cubic_precision(3, 0).mask, sd.hormann_sabin(3).mask)
        self.assertEqual(sd.two_tension(2, F(-5, 32), F(1, 4)).mask, sd.dual_four_point().mask)
        self.assertEqual(sd.romani(1, F(1, 16)).mask, sd.two_tension(1, F(-1, 8), F(1, 4)).mask)
        self.assertEqual(sd.lr_four_point(0).mask, sd.four_point().mask)
        self.assertEqual(sd.lr_six_point(0).mask, sd.six_point().mask)
        self.assertEqual(sd.lr_four_point(1).mask,
                         multiply(sd.four_point().mask, [F(x, 16) for x in (-1, 9, 9, -1)]))
        self.assertEqual(sd.from_mask(["0.5", 1, "0.5"]).name, "mask")
        self.assertEqual(sd.parse_symbol("(1+z)^2/2"), [F(1, 2), F(1), F(1, 2)])
        self.assertEqual(sd.parse_symbol("z^-1+2+z"), [1, 2, 1])
        self.assertEqual(sd.from_symbol("(1+z)^2/2").mask, sd.b_spline(1).mask)

    def test_catalogue_matches_the_cli_list(self):
        lines = cli("scheme", "--list").stdout.splitlines()
        heads = [line.split() for line in lines if line and not line.startswith(" ")]
        catalogue = sd.scheme_catalogue()
        self.assertEqual([spec.name for spec in catalogue], [h[0] for h in heads])
        for spec, head in zip(catalogue, heads):
            expected = [p.name + "=" + (p.default_value or "(required)") for p in spec.parameters]
            self.assertEqual(head[1:], expected)
            self.assertTrue(spec.summary)
            self.assertTrue(all(p.meaning for p in spec.parameters))

    def test_named_scheme_matches_the_cli(self):
        for name, params, build in SCHEMES:
            with self.subTest(name):
                expected = cli_analysis(name, params)
                for scheme in (sd.named_scheme(name, params), sd.named_scheme(name, **params), build()):
                    self.assertEqual([sd.to_string(x) for x in scheme.mask], expected["mask"])
                    self.assertEqual(scheme.weights.tolist(), expected["mask_values"])
                named = sd.named_scheme(name, params)
                self.assertEqual(named.name, expected["scheme"])
                self.assertEqual({k: sd.to_string(v) for k, v in named.parameters.items()}, expected["parameters"])
        # Defaults of the catalogue, and numbers as parameters.
        self.assertEqual(sd.named_scheme("generalized-four-point").mask, sd.four_point().mask)
        self.assertEqual(sd.named_scheme("romani", {"n": 2}, w=Fraction(1, 32)).mask, sd.romani(2, "1/32").mask)
        self.assertEqual(sd.named_scheme("lr-six-point", stages=2).mask, sd.lr_six_point(2).mask)

    def test_bad_input_has_the_cli_message(self):
        cases = [
            (lambda: sd.named_scheme("mask", coefficients="0.25,0.75,0.5"),
             ("scheme", "mask", "--param", "coefficients=0.25,0.75,0.5", "--analyze")),
            (lambda: sd.named_scheme("nope"), ("scheme", "nope", "--analyze")),
            (lambda: sd.named_scheme("lr-four-point", stages=-1),
             ("scheme", "lr-four-point", "--param", "stages=-1", "--analyze")),
            (lambda: sd.named_scheme("lr-four-point", stages="abc"),
             ("scheme", "lr-four-point", "--param", "stages=abc", "--analyze")),
            (lambda: sd.named_scheme("b-spline", degree="1/2"),
             ("scheme", "b-spline", "--param", "degree=1/2", "--analyze")),
            (lambda: sd.named_scheme("four-point", w=1), ("scheme", "four-point", "--param", "w=1", "--analyze")),
            (lambda: sd.named_scheme("symbol"), ("scheme", "symbol", "--analyze")),
            (lambda: sd.named_scheme("symbol", symbol="(1+z"),
             ("scheme", "symbol", "--param", "symbol=(1+z", "--analyze")),
            (lambda: sd.named_scheme("mask", coefficients="0.5 0.5 0.5 0.5 1 -1"),
             ("scheme", "mask", "--param", "coefficients=0.5 0.5 0.5 0.5 1 -1", "--analyze")),
        ]
        for call, args in cases:
            with self.subTest(args=args):
                with self.assertRaises(cifs.InvalidInput) as e:
                    call()
                self.assertEqual(str(e.exception), cli_error(*args))
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.from_mask([Fraction(1, 4), Fraction(3, 4), Fraction(1, 2)])
        self.assertEqual(str(e.exception), "mask: coefficients sum to 1.5, a subdivision mask sums to 2")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.lr_four_point(-1)
        self.assertEqual(str(e.exception), cli_error("scheme", "lr-four-point", "--param", "stages=-1", "--analyze"))
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.named_scheme("hormann-sabin", n=2)
        self.assertEqual(str(e.exception), cli_error("scheme", "hormann-sabin", "--param", "n=2", "--analyze"))
        # The direct constructor explains a little more than the catalogue does.
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.hormann_sabin(2)
        self.assertEqual(str(e.exception), "hormann-sabin: n = 2 is below 3: the Hormann–Sabin members have n ≥ 3 "
                         "smoothing stages (n = 3 is the 4-point scheme)")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.named_scheme("romani", {"n": 1}, n=2)
        self.assertEqual(str(e.exception), "named_scheme: parameter 'n' is given twice")
        with self.assertRaises(cifs.InvalidInput):
            sd.Scheme("x", [])
        with self.assertRaises(cifs.InvalidInput):
            sd.Scheme("x", [2])


class RefineTest(ScratchTestCase):
    P = np.array([[0.0, 0.0], [1.0, 2.0], [2.5, 0.5], [3.0, 2.0], [1.5, 3.5], [0.25, 1.0]])

    def polygon_file(self, points, closed):
        path = self.scratch / "polygon.json"
        path.write_text(json.dumps({"polygon": {"points": np.asarray(points).tolist(), "closed": closed}}))
        return path

    def test_refine_matches_the_cli(self):
        # Sanitized, every third case: each scheme has 4 or 6, so each is still drawn.
        cases = [(name, params, build, closed, ends) for name, params, build in SCHEMES for closed in (True, False)
                 for ends in ("auto", "keep") + (("reflect",) if sd.is_symmetric(build()) else ())]
        for name, params, build, closed, ends in sampled(cases, 3):
            with self.subTest(name=name, closed=closed, ends=ends):
                path = self.polygon_file(self.P, closed)
                out = cli_json(*cli_args(name, params), "--refine", path, "--steps", 2, "--ends", ends)
                self.assertEqual(out["polygon"]["closed"], closed)
                rule = {"auto": sd.Ends.automatic, "keep": sd.Ends.keep, "reflect": sd.Ends.reflect}[ends]
                mine = sd.refine(build(), self.P, closed, 2, ends=rule)
                assert_close(self, mine, out["polygon"]["points"], what=f"{name} refined")

    def test_refinement_identities(self):
        chaikin = sd.chaikin()
        one = sd.refine(chaikin, self.P, True)
        self.assertEqual(one.shape, (12, 2))
        # Seed 001's rule: out[2i] = ¾P_i + ¼P_{i+1}, out[2i+1] = ¼P_i + ¾P_{i+1}.
        nxt = np.roll(self.P, -1, axis=0)
        assert_close(self, one[0::2], 0.75 * self.P + 0.25 * nxt)
        assert_close(self, one[1::2], 0.25 * self.P + 0.75 * nxt)
        for scheme in (chaikin, sd.four_point(), sd.b_spline(4)):
            for closed in (True, False):
                assert_close(self, sd.refine(scheme, self.P, closed, 3),
                             sd.refine(scheme, sd.refine(scheme, sd.refine(scheme, self.P, closed), closed), closed))
        # Interpolating: the old points stay at the even indices.
        assert_close(self, sd.refine(sd.four_point(), self.P, True, 1)[0::2], self.P, rel=0)
        assert_close(self, sd.refine(chaikin, self.P, False, 0), self.P, rel=0)
        # Homogeneous rows refine unchanged: refining (w·x, w) and dividing equals refining x when w = 1.
        three_d = np.hstack([self.P, np.ones((6, 1))])
        assert_close(self, sd.refine(chaikin, three_d, True)[:, :2], one)

    def test_refine_bad_input(self):
        checks = [
            (lambda: sd.refine(sd.chaikin(), np.zeros((0, 2)), True), "the polygon has no point to refine"),
            (lambda: sd.refine(sd.chaikin(), self.P[:1], False),
             "an open polygon needs at least 2 points to refine, got 1"),
            (lambda: sd.refine(sd.chaikin(), self.P, True, -1), "the number of refinement steps -1 is negative"),
            (lambda: sd.refine(sd.chaikin(), np.array([[0, np.nan], [1, 1]]), True),
             "the polygon has a coordinate that is not finite"),
        ]
        for call, message in checks:
            with self.assertRaises(cifs.InvalidInput) as e:
                call()
            self.assertEqual(str(e.exception), message)
        asym = sd.corner_cutting("0.1", "0.6")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.refine(asym, self.P, False, ends=sd.Ends.reflect)
        path = self.polygon_file(self.P, False)
        self.assertEqual(str(e.exception), cli_error("scheme", "corner-cutting", "--param", "a=0.1", "--param",
                                                     "b=0.6", "--refine", path, "--ends", "reflect"))
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.refine(sd.chaikin(), self.P, True, 10, max_points=1000)
        self.assertIn("10 refinement steps of", str(e.exception))
        with self.assertRaises(cifs.InvalidInput) as e:  # a wrong shape names the argument
            sd.refine(sd.chaikin(), np.zeros((2, 2, 2)), True)
        self.assertRegex(str(e.exception), r"\bP: ")


class IfsTest(unittest.TestCase):
    P = RefineTest.P

    def test_matrices_follow_the_documented_formula(self):
        for scheme in (sd.chaikin(), sd.four_point(), sd.corner_cutting("0.1", "0.6"), sd.six_point()):
            a, N = [float(x) for x in scheme.mask], sd.mask_degree(scheme)
            S = sd.ifs_matrices(scheme)
            for eps in (0, 1):
                expected = np.zeros((N, N))
                for s in range(N):
                    for r in range(N):
                        k = s - 2 * r + N - 1 + eps
                        expected[s, r] = a[k] if 0 <= k <= N else 0.0
                assert_close(self, S[eps], expected, rel=0)
                assert_close(self, sd.ifs_matrix(scheme.weights, eps), expected, rel=0)
                assert_close(self, S[eps].sum(axis=1), np.ones(N))
        assert_close(self, sd.ifs_matrices(sd.chaikin())[0], [[0.75, 0.25, 0], [0.25, 0.75, 0], [0, 0.75, 0.25]])
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.ifs_matrix([1.0, 1.0], 2)
        self.assertEqual(str(e.exception), "the IFS matrix index epsilon 2 is neither 0 nor 1")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.ifs_matrix([2.0], 0)
        self.assertEqual(str(e.exception), "a subdivision mask needs at least 2 coefficients")

    def test_closed_windows(self):
        windows = sd.closed_windows(sd.four_point(), self.P)
        self.assertEqual(len(windows), 6)
        for k, W in enumerate(windows):
            assert_close(self, W, self.P[[(k + r) % 6 for r in range(6)]], rel=0)
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.closed_windows(sd.chaikin(), np.zeros((0, 2)))
        self.assertEqual(str(e.exception), "the closed polygon has no point")

    def test_limit_points_lie_on_the_refined_polygon_of_an_interpolating_scheme(self):
        # After K steps the 4-point scheme's points are limit points at the dyadic parameters j/2^K,
        # so the attractor points are the K-times refined polygon up to a cyclic shift.
        K = 4
        limit = sd.limit_points(sd.four_point(), self.P, K)
        refined = sd.refine(sd.four_point(), self.P, True, K)
        self.assertEqual(limit.shape, refined.shape)
        shifts = [s for s in range(len(refined)) if np.allclose(np.roll(refined, -s, axis=0), limit, atol=1e-12)]
        self.assertEqual(len(shifts), 1)
        # A dual scheme: Chaikin's limit points are on the quadratic B-spline: midpoints of the
        # polygon edges after one step are limit points at the knots.
        limit = sd.limit_points(sd.chaikin(), self.P, 0)
        mid = 0.5 * (self.P + np.roll(self.P, -1, axis=0))
        self.assertTrue(all(np.min(np.abs(mid - p).sum(axis=1)) < 1e-12 for p in limit))
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.limit_points(sd.chaikin(), self.P, -1)
        self.assertEqual(str(e.exception), "the depth -1 is negative; give a depth ≥ 0")

    @unittest.skipUnless(hasattr(cifs.automata, "Automaton"), "cifs.automata.Automaton is bound elsewhere")
    def test_scheme_automaton(self):
        automaton = sd.scheme_automaton(sd.chaikin(), 3)
        self.assertIsInstance(automaton, cifs.automata.Automaton)
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.scheme_automaton(sd.chaikin(), -1)
        self.assertEqual(str(e.exception), "the number of segments -1 is negative")


class AnalysisTest(unittest.TestCase):
    def test_analysis_matches_the_cli(self):
        for name, params, build in SCHEMES:
            with self.subTest(name):
                expected = cli_analysis(name, params)
                scheme = build()
                a = sd.analyze(scheme)
                self.assertEqual(json.loads(sd.analysis_json(scheme, a)), expected)
                # Field by field: exact rationals through their text, floats exactly (same algorithm).
                self.assertEqual([sd.to_string(x) for x in a.mask], expected["mask"])
                self.assertEqual([0, a.support], expected["support"])
                self.assertEqual(a.kind, expected["kind"])
                self.assertEqual(a.symmetric, expected["symmetric"])
                self.assertEqual(a.interpolating, expected["interpolating"])
                self.assertEqual(a.multiplicity, expected["one_plus_z_power"])
                self.assertEqual(a.generation_degree, expected["generation_degree"])
                self.assertEqual(a.reproduction_degree, expected["reproduction_degree"])
                self.assertEqual(a.continuity, expected["continuity"])
                self.assertEqual([a.holder_low, a.holder_high], expected["holder"])
                self.assertEqual(a.holder_low_power, expected["holder_low_power"])
                self.assertEqual(a.holder_high_word, expected["holder_high_word"])
                self.assertEqual(a.symbol, expected["symbol"])
                self.assertEqual(a.symbol_factored, expected["symbol_factored"])
                proof = expected["continuity_proof"]
                if a.continuity >= 0:
                    self.assertEqual((a.proof.k, a.proof.power), (proof["k"], proof["power"]))
                    self.assertEqual(sd.to_string(a.proof.norm), proof["norm"])
                    d = sd.difference_mask(a.mask, a.proof.k)
                    self.assertEqual([sd.to_string(x) for x in d], proof["difference_mask"])
                    self.assertEqual(sd.power_norm(d, a.proof.power), a.proof.norm)
                else:
                    self.assertIsNone(proof)
                for e, key in ((0, "S0"), (1, "S1")):
                    self.assertEqual(a.eigenvalues[e].dtype, np.complex128)
                    assert_close(self, a.eigenvalues[e].real, [z[0] for z in expected["eigenvalues"][key]], rel=1e-15)
                    assert_close(self, sd.ifs_matrices(scheme)[e], expected["matrices"][key], rel=0)

    def test_max_power_matches_the_cli(self):
        expected = cli_json("scheme", "six-point", "--analyze", "--max-power", "3")
        self.assertEqual(json.loads(sd.analysis_json(sd.six_point(), sd.analyze(sd.six_point(), max_power=3))),
                         expected)

    def test_published_smoothness(self):
        # Chaikin = quadratic B-spline: C^1, Hölder exponent exactly 2.
        a = sd.analyze(sd.chaikin())
        self.assertEqual(a.continuity, 1)
        self.assertAlmostEqual(a.holder_low, 2, delta=1e-12)
        self.assertAlmostEqual(a.holder_high, 2, delta=1e-12)
        # Dyn–Levin–Gregory 4-point: C^1, not C^2, Hölder exponent 2 − ε (Daubechies–Lagarias: < 2).
        a = sd.analyze(sd.four_point())
        self.assertEqual((a.continuity, a.kind, a.interpolating), (1, "primal", True))
        self.assertGreater(a.holder_low, 1.7)
        self.assertLessEqual(a.holder_low, a.holder_high)
        self.assertAlmostEqual(a.holder_high, 2, delta=1e-9)
        self.assertEqual(a.reproduction_degree, 3)
        # Uniform B-splines of degree n: C^{n−1}, Hölder n.
        for n in (2, 3, 5):
            a = sd.analyze(sd.b_spline(n))
            self.assertEqual(a.continuity, n - 1)
            self.assertAlmostEqual(a.holder_low, n, delta=1e-9)
            self.assertAlmostEqual(a.holder_high, n, delta=1e-9)
            self.assertEqual(a.generation_degree, n)
        # Dual 4-point (Dyn, Floater, Hormann 2005): C^2, Hölder log2(64/9) ≈ 2.83.
        a = sd.analyze(sd.dual_four_point())
        self.assertEqual((a.continuity, a.kind), (2, "dual"))
        self.assertAlmostEqual(a.holder_high, np.log2(64 / 9), delta=1e-9)
        # Tension w = 0.2 is outside the C^1 range 0 < w < (√5 − 1)/8 of the 4-point family.
        self.assertEqual(sd.analyze(sd.generalized_four_point("0.2")).continuity, 0)
        # Degree 0 (piecewise constant): no continuity, so no lower Hölder bound.
        a = sd.analyze(sd.b_spline(0))
        self.assertEqual(a.continuity, -1)
        self.assertIsNone(a.holder_low)
        self.assertAlmostEqual(a.holder_high, 0, delta=1e-12)

    def test_difference_masks_and_norms(self):
        a = sd.four_point().mask
        for k in (0, 1):
            d = sd.difference_mask(a, k)
            # d_k(z)·(1+z)^{k+1} = 2^k a(z)
            back = d
            for _ in range(k + 1):
                back = multiply(back, [1, 1])
            self.assertEqual(back, [2**k * x for x in a])
            for L in (1, 2, 3):
                self.assertEqual(sd.power_norm(d, L), norm_by_definition(d, L))
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.difference_mask(a, 4)
        self.assertEqual(str(e.exception), "(1+z)^5 does not divide the symbol")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.power_norm([1, 1], 0)
        self.assertEqual(str(e.exception), "the power L = 0 is below 1")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.power_norm([1, 1], 30, 1000)
        self.assertEqual(str(e.exception), "the 30-th power of the difference symbol has too many coefficients; lower the maximum power")

    def test_symbol_texts_read_back(self):
        self.assertEqual(sd.polynomial_text(sd.chaikin().mask), "(1+3z+3z^2+z^3)/4")
        for name, params, build in SCHEMES:
            a = sd.analyze(build(), max_power=6)
            self.assertEqual(sd.parse_symbol(a.symbol), a.mask)
            self.assertEqual(sd.parse_symbol(a.symbol_factored), a.mask)
            self.assertEqual(sd.polynomial_text(a.mask), a.symbol)

    def test_result_is_read_only_and_printable(self):
        a = sd.analyze(sd.chaikin())
        self.assertEqual(repr(a), "SchemeAnalysis(support=3, kind='dual', continuity=1)")
        self.assertEqual(repr(a.proof), "ContinuityProof(k=1, power=1, norm=0.5)")
        with self.assertRaises(AttributeError):
            a.continuity = 3

    def test_options_are_checked(self):
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.analyze(sd.chaikin(), max_power=0)
        self.assertEqual(str(e.exception), "analyze: max_power = 0 is outside [1, 26]")
        with self.assertRaises(cifs.InvalidInput) as e:
            sd.analyze(sd.chaikin(), max_word_length=64)
        self.assertEqual(str(e.exception), "analyze: max_word_length = 64 is outside [1, 20]")
        with self.assertRaises(TypeError):
            sd.analyze(sd.chaikin(), 3)  # keyword-only


if __name__ == "__main__":
    unittest.main()


class MeshSubdivisionTest(ScratchTestCase):
    """cifs.subdivision on polygon meshes against `cifs subdivide` (the CLI's OBJ, to the digits it
    prints), the replay and stencil-table identities, and the errors."""

    @staticmethod
    def read_obj(text):
        vertices, faces = [], []
        for line in text.splitlines():
            parts = line.split()
            if parts and parts[0] == "v":
                vertices.append([float(x) for x in parts[1:4]])
            elif parts and parts[0] == "f":
                faces.append([int(x.split("/")[0]) - 1 for x in parts[1:]])
        return np.array(vertices), faces

    def test_schemes_match_the_cli(self):
        for scheme, mesh_name in [("catmull-clark", "cube.obj"), ("loop", "icosahedron.obj"),
                                  ("doo-sabin", "open_grid.obj"), ("butterfly", "torus_triangles.obj"),
                                  ("sqrt3", "open_grid_triangles.obj")]:
            with self.subTest(scheme=scheme):
                path = str(EXAMPLES / "meshes" / mesh_name)
                vertices, faces = self.read_obj(cli("subdivide", path, "--scheme", scheme, "--levels", "0").stdout)
                mesh = cifs.io.Mesh(vertices, faces=faces)
                ours = sd.subdivide(mesh, scheme, 2)
                theirs_v, theirs_f = self.read_obj(cli("subdivide", path, "--scheme", scheme, "--levels", "2").stdout)
                assert_close(self, ours.vertices, theirs_v, 1e-12)
                offsets, corners = ours.face_offsets, ours.face_vertices
                self.assertEqual([list(corners[offsets[f]:offsets[f + 1]]) for f in range(len(offsets) - 1)],
                                 theirs_f)
                named = getattr(sd, scheme.replace("-", "_"))(mesh, 2)
                np.testing.assert_array_equal(named.vertices, ours.vertices)

    def test_replay_and_stencil_table(self):
        vertices, faces = self.read_obj(cli("subdivide", str(EXAMPLES / "meshes" / "torus.obj"),
                                            "--scheme", "catmull-clark", "--levels", "0").stdout)
        mesh = cifs.io.Mesh(vertices, faces=faces)
        r = sd.refine_topology(mesh, "catmull-clark", 2)
        self.assertEqual(r.levels, 2)
        self.assertEqual(r.vertex_counts[0], len(vertices))
        # To round-off: the one-shot step weighs each face's centre once, the replay its corners.
        assert_close(self, r.apply(vertices), sd.catmull_clark(mesh, 2).vertices, 1e-15)
        assert_close(self, sd.subdivide(mesh, "catmull-clark", 2, factored=True).vertices, r.apply(vertices), 1e-14)
        offsets, corners = r.faces(2)
        self.assertEqual(len(offsets) - 1, 16 * len(faces))
        colours = np.random.default_rng(1).random((len(vertices), 5))
        table = r.stencil_table()
        assert_close(self, table.apply(colours), r.apply(colours), 1e-13)
        step = r.steps[0]
        sums = np.add.reduceat(step.weights, step.offsets[:-1])
        assert_close(self, sums, np.ones(step.rows), 1e-15)
        # Topology only: the same faces, no weights to replay.
        bare = sd.refine_topology(mesh, "catmull-clark", 2, weights=False, last_level_adjacency=False)
        self.assertEqual((bare.levels, bare.vertex_counts, len(bare.steps)), (2, r.vertex_counts, 0))
        for level in range(3):
            for ours, full in zip(bare.faces(level), r.faces(level)):
                np.testing.assert_array_equal(ours, full)
        with self.assertRaisesRegex(cifs.InvalidInput, "without its weights"):
            bare.apply(vertices)

    def test_errors(self):
        cube = cifs.io.Mesh(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                                      [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float),
                            faces=[[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])
        with self.assertRaisesRegex(cifs.InvalidInput, "loop: face 0 has 4 corners"):
            sd.loop(cube)
        with self.assertRaisesRegex(cifs.InvalidInput, "unknown mesh scheme 'kobbelt'"):
            sd.subdivide(cube, "kobbelt")
        with self.assertRaisesRegex(cifs.InvalidInput, "unknown boundary rule 'sharp'"):
            sd.catmull_clark(cube, boundary="sharp")
        with self.assertRaisesRegex(cifs.InvalidInput, "ask for fewer levels"):
            sd.catmull_clark(cube, 20)
        with self.assertRaisesRegex(cifs.InvalidInput, "rows"):
            sd.refine_topology(cube, "catmull-clark").steps[0].apply(np.zeros((3, 3)))
        self.assertEqual(sd.mesh_schemes(), ["catmull-clark", "loop", "doo-sabin", "butterfly", "sqrt3", "bilinear"])


class LimitTest(unittest.TestCase):
    def test_cube_corners_and_normals(self):
        # Halstead et al. 1993: a valence-3 corner of the unit cube goes to (n²v + 4Σe + Σf)/(n(n + 5))
        # = ¼ of the way along the diagonal; the normal is along the diagonal, outwards.
        cube = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "cube.obj"))
        limit = sd.limit(cube, "catmull-clark", 0, normals=True)
        corners = np.asarray(cube.vertices)
        np.testing.assert_allclose(limit.vertices, 0.25 + 0.5 * corners, atol=1e-15)
        outward = corners - 0.5
        np.testing.assert_allclose(limit.normals, outward / np.linalg.norm(outward, axis=1)[:, None], atol=1e-15)
        with self.assertRaisesRegex(cifs.InvalidInput, "limit points belong to faces"):
            sd.limit(cube, "doo-sabin")

    def test_sqrt3_boundary_normals(self):
        # √3's boundary vertices take normals too (the two-step boundary matrix; proved against deep
        # refinement in tests/subdivision/test_mesh_limit_classes.cpp): unit normals at every vertex of
        # the open example grid, at an odd level.
        path = str(EXAMPLES / "meshes" / "open_grid_triangles.obj")
        limit = sd.limit(cifs.io.read_mesh(path), "sqrt3", 1, normals=True)
        self.assertEqual(limit.normals.shape, limit.vertices.shape)
        np.testing.assert_allclose(np.linalg.norm(limit.normals, axis=1), 1, atol=1e-15)

    def test_butterfly_normals(self):
        # Butterfly interpolates (the limit points are the refined vertices) and its interior vertices take
        # normals (the left eigenvectors of S_n; against deep refinement in
        # tests/subdivision/test_butterfly_limit.cpp): the icosahedron's point out of it, at levels 0 and 1.
        ico = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "icosahedron.obj"))
        for level in (0, 1):
            limit = sd.limit(ico, "butterfly", level, normals=True)
            # To round-off: the limit replays the weights, butterfly() applies the rules as it makes them.
            np.testing.assert_allclose(limit.vertices, sd.butterfly(ico, level).vertices, rtol=0, atol=1e-15)
            normals, points = np.asarray(limit.normals), np.asarray(limit.vertices)
            np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-15)
            self.assertTrue(np.all(np.sum(normals * (points - points.mean(axis=0)), axis=1) > 0))
        # Boundary vertices take normals where the boundary rule is C1 (2 and 3 faces); vertex 6 has one face.
        grid = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "open_grid_triangles.obj"))
        with self.assertRaisesRegex(cifs.InvalidInput, r"vertex 6 \(valence 2\) is on the boundary with 1 face "
                                    r"\(lambda1 = 0.5, lambda2 = 0.25\), where the local analysis finds undecided"):
            sd.limit(grid, "butterfly", 0, normals=True)

    def test_limits_follow_the_tags(self):
        # The creased box (creases infinite, 2 and 1, a corner, a hole): the limit from level 0 and from
        # level 2 agree on the old vertices (semi-sharp ones too: the sharpness still to spend is followed).
        path = EXAMPLES / "meshes" / "creased_box.obj"
        box = cifs.io.read_mesh(str(path))
        coarse, fine = sd.limit(box, "catmull-clark", 0), sd.limit(box, "catmull-clark", 2)
        n = box.vertices.shape[0]
        np.testing.assert_allclose(np.asarray(fine.vertices)[:n], coarse.vertices, rtol=0, atol=1e-13)
        self.assertEqual(len(fine.tags.holes), 16)  # the hole's grandchildren
        self.assertEqual(coarse.normal_indices.shape, (0,))

    def test_limit_normals_per_sector(self):
        # A grid with a sharp crease across: a normal per side at the crease's vertices, per face corner
        # (normal_indices): at every corner of every face the normal of limit_surface's du x dv there
        # (where they span a plane), and more normals than vertices. The creased box's crease turns at a
        # corner of the box (a face alone between two crease edges of one smooth curve): refused there.
        rows = [f"v {i} {j} {0.3 * np.sin(1.3 * i + 0.7 * j)}" for j in range(5) for i in range(6)]
        rows += [f"f {j * 6 + i + 1} {j * 6 + i + 2} {j * 6 + i + 8} {j * 6 + i + 7}" for j in range(4) for i in range(5)]
        rows += [f"t crease 2/1/0 {i} {i + 1} 10" for i in range(6, 11)] + ["t interpolateboundary 1/0/0 1"]
        box = cifs.io.parse_mesh_obj("\n".join(rows) + "\n", strict=True)
        with self.assertRaisesRegex(cifs.InvalidInput, r"vertex 0 \(valence 3\): its sector of face 0 has no tangent"):
            sd.limit(cifs.io.read_mesh(str(EXAMPLES / "meshes" / "creased_box.obj")), "catmull-clark", 0, normals=True)
        limit = sd.limit(box, "catmull-clark", 0, normals=True)
        corners = np.asarray(box.face_vertices)
        indices = np.asarray(limit.normal_indices)
        self.assertEqual(indices.shape, corners.shape)
        normals = np.asarray(limit.normals)
        self.assertGreater(len(normals), box.vertices.shape[0])
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-14)
        faces = corners.reshape(-1, 4)
        keep = [f for f in range(len(faces)) if f not in box.tags.holes]
        f = np.repeat(keep, 4)
        u = np.tile([0.0, 1.0, 1.0, 0.0], len(keep))
        v = np.tile([0.0, 0.0, 1.0, 1.0], len(keep))
        _, du, dv = sd.limit_surface(box, f.tolist(), u.tolist(), v.tolist())
        cross = np.cross(du, dv)
        spans = np.linalg.norm(cross, axis=1) > 1e-6 * np.linalg.norm(du, axis=1) * np.linalg.norm(dv, axis=1)
        self.assertGreater(spans.sum(), len(f) // 2)
        ours = normals[indices[(4 * f + np.tile(np.arange(4), len(keep)))]]
        expected = cross[spans] / np.linalg.norm(cross[spans], axis=1)[:, None]
        np.testing.assert_allclose(ours[spans], expected, rtol=0, atol=1e-12)

    def test_limit_surface_at_face_points(self):
        # At the corners of a once-refined cube's faces the surface is the limit of those vertices.
        cube = sd.catmull_clark(cifs.io.read_mesh(str(EXAMPLES / "meshes" / "cube.obj")), 1)
        limit = sd.limit(cube, "catmull-clark", 0)
        faces = np.asarray(cube.face_vertices).reshape(-1, 4)
        f = np.repeat(np.arange(len(faces)), 4)
        u = np.tile([0.0, 1.0, 1.0, 0.0], len(faces))
        v = np.tile([0.0, 0.0, 1.0, 1.0], len(faces))
        positions, du, dv = sd.limit_surface(cube, f.tolist(), u.tolist(), v.tolist())
        np.testing.assert_allclose(positions, np.asarray(limit.vertices)[faces.reshape(-1)], atol=1e-14)
        self.assertEqual(du.shape, (len(f), 3))
        with self.assertRaisesRegex(cifs.InvalidInput, "one entry per point"):
            sd.limit_surface(cube, [0], [0.5], [])

    def test_limit_surface_follows_the_tags(self):
        # The creased box (creases infinite, 2 and 1, a corner, a hole): at the corners of every face but
        # the hole the surface is the limit of those vertices (semi-sharp ones too); the hole is refused.
        box = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "creased_box.obj"))
        limit = np.asarray(sd.limit(box, "catmull-clark", 0).vertices)
        counts = np.diff(np.asarray(box.face_offsets))
        self.assertTrue((counts == 4).all())
        faces = np.asarray(box.face_vertices).reshape(-1, 4)
        hole = box.tags.holes[0]
        keep = [f for f in range(len(faces)) if f != hole]
        f = np.repeat(keep, 4)
        u = np.tile([0.0, 1.0, 1.0, 0.0], len(keep))
        v = np.tile([0.0, 0.0, 1.0, 1.0], len(keep))
        positions, du, dv = sd.limit_surface(box, f.tolist(), u.tolist(), v.tolist(), partials=False)
        np.testing.assert_allclose(positions, limit[faces[keep].reshape(-1)], rtol=0, atol=1e-13)
        self.assertIsNone(du)
        # With partials, a corner whose face is alone between two sharp edges has no tangent plane to give.
        with self.assertRaisesRegex(cifs.InvalidInput, r"point 0 \(face 0\) at \(0, 0\): the vertex there has no"):
            sd.limit_surface(box, [0], [0.0], [0.0])
        with self.assertRaisesRegex(cifs.InvalidInput, f"face {hole}\\): the face is a hole"):
            sd.limit_surface(box, [hole], [0.5], [0.5])

    def test_loop_limit_surface_and_automaton(self):
        # Loop on triangles: at the corners of every face of a once-refined tetrahedron (corner 1 at
        # (1, 0), 2 at (0, 1)) the surface is the limit of those vertices; the attractor at depth 2
        # holds exactly the limit points of the mesh refined 2 more levels (nearest distances, numpy).
        tet = sd.loop(cifs.io.read_mesh(str(EXAMPLES / "meshes" / "tetrahedron.obj")), 1)
        limit = np.asarray(sd.limit(tet, "loop", 0).vertices)
        faces = np.asarray(tet.face_vertices).reshape(-1, 3)
        f = np.repeat(np.arange(len(faces)), 3)
        u = np.tile([0.0, 1.0, 0.0], len(faces))
        v = np.tile([0.0, 0.0, 1.0], len(faces))
        positions, du, dv = sd.limit_surface(tet, f.tolist(), u.tolist(), v.tolist(), scheme="loop")
        np.testing.assert_allclose(positions, limit[faces.reshape(-1)], atol=1e-14)
        with self.assertRaisesRegex(cifs.InvalidInput, "outside the triangle"):
            sd.limit_surface(tet, [0], [0.7], [0.7], scheme="loop")
        s = sd.surface_automaton(tet, scheme="loop")
        self.assertEqual(s.scheme, "loop")
        self.assertEqual(len(s.nets), len(faces))
        attractor = np.asarray(sd.surface_automaton_mesh(s, 2).vertices)
        refined = np.asarray(sd.limit(tet, "loop", 2).vertices)
        self.assertEqual(attractor.shape, refined.shape)
        distance = np.linalg.norm(attractor[:, None, :] - refined[None, :, :], axis=2)
        self.assertLess(distance.min(axis=1).max(), 1e-12)
        self.assertLess(distance.min(axis=0).max(), 1e-12)
        # The fractal Loop surface: the box-spline patch's BC-IFS perturbed; unperturbed, the same points.
        same, _ = sd.fractal_surface(s)
        np.testing.assert_allclose(np.asarray(sd.surface_automaton_mesh(same, 2).vertices), attractor, atol=1e-13)
        rough, perturbation = sd.fractal_surface(s, amplitude=1.5, seed=3)
        self.assertEqual(len(perturbation.values), 1)  # docs/bcifs.md, "Triangular patches"
        self.assertLessEqual(perturbation.residual, 1e-12)
        fractal = np.asarray(sd.surface_automaton_mesh(rough, 2).vertices)
        corners = np.asarray(sd.limit(tet, "loop", 0).vertices)
        self.assertLess(np.linalg.norm(fractal[:, None, :] - corners[None, :, :], axis=2).min(axis=0).max(), 1e-12)
        self.assertGreater(np.abs(fractal - attractor).max(), 1e-3)

    def test_fractal_creases(self):
        # The creased torus: its two infinitely sharp creases made fractal, the surface left smooth. Both faces
        # of a crease edge meet on the crease curve's own nodes; faces away from the creases stay the limit
        # surface's attractor; the curve options are refused without creases, creases without the mesh.
        torus = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "creased_torus.obj"))
        s = sd.surface_automaton(torus)
        rough, perturbation, features = sd.fractal_surface(s, mesh=torus, creases=True, curve_amplitude=0.8,
                                                           curve_seed=7)
        self.assertEqual(len(features.edges), 20)  # the equator's 12 and the meridian's 8
        self.assertEqual(len(features.perturbation.values), 2)
        smooth = np.asarray(sd.surface_automaton_mesh(rough, 3).vertices)
        fractal = np.asarray(sd.surface_automaton_mesh(rough, 3, features=features).vertices)
        self.assertEqual(smooth.shape, fractal.shape)
        moved = np.linalg.norm(fractal - smooth, axis=1)
        self.assertGreater(moved.max(), 1e-3)
        self.assertGreater(np.count_nonzero(moved < 1e-12), len(moved) // 2)
        nodes = np.asarray(features.nodes(features.edges[0], 3))
        self.assertEqual(nodes.shape, (9, 3))
        distance = np.linalg.norm(fractal[:, None, :] - nodes[None, :, :], axis=2)
        self.assertLess(distance.min(axis=0).max(), 1e-12)  # the crease's nodes are the mesh's
        with self.assertRaisesRegex(cifs.InvalidInput, "mesh"):
            sd.fractal_surface(s, creases=True)
        with self.assertRaisesRegex(cifs.InvalidInput, "creases"):
            sd.fractal_surface(s, curve_amplitude=0.5)
        with self.assertRaisesRegex(cifs.InvalidInput, "no boundary"):
            sd.fractal_surface(s, mesh=torus, boundaries=True)

    def test_loop_surface_automaton_with_features(self):
        # Loop on the creased box split into triangles (sharp and semi-sharp creases, a corner, a hole of
        # two triangles): every node of the attractor at depth 2 is a limit point of the mesh refined 2
        # levels (the hole's faces have none); the fractal version keeps the mesh vertices' limit points.
        box = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "creased_box_triangles.obj"))
        s = sd.surface_automaton(box, scheme="loop")
        self.assertEqual(len(s.nets), len(box.face_vertices) // 3 - 2)
        attractor = np.asarray(sd.surface_automaton_mesh(s, 2).vertices)
        limit = np.asarray(sd.limit(box, "loop", 2).vertices)
        distance = np.linalg.norm(attractor[:, None, :] - limit[None, :, :], axis=2)
        self.assertLess(distance.min(axis=1).max(), 1e-12)
        # Depth 3: at depth 2 the nodes of faces with an irregular corner are still on their regular
        # quarters' sides, which the perturbation keeps.
        rough, perturbation = sd.fractal_surface(s, amplitude=1.5, seed=3)
        self.assertLessEqual(perturbation.residual, 1e-12)
        fractal = np.asarray(sd.surface_automaton_mesh(rough, 3).vertices)
        corners = np.asarray(sd.limit(box, "loop", 0).vertices)
        self.assertLess(np.linalg.norm(fractal[:, None, :] - corners[None, :, :], axis=2).min(axis=0).max(), 1e-12)
        smooth = np.asarray(sd.surface_automaton_mesh(s, 3).vertices)
        self.assertEqual(fractal.shape, smooth.shape)
        self.assertGreater(np.abs(fractal - smooth).max(), 1e-3)

    def test_surface_automaton_attractor_and_fractal(self):
        # The welded attractor at depth 2 holds exactly the limit points of the cube refined 2 more
        # levels (nearest-neighbour distances, numpy); the fractal keeps the face corners.
        cube = sd.catmull_clark(cifs.io.read_mesh(str(EXAMPLES / "meshes" / "cube.obj")), 1)
        s = sd.surface_automaton(cube)
        self.assertEqual(len(s.nets), 24)
        attractor = np.asarray(sd.surface_automaton_mesh(s, 2).vertices)
        limit = np.asarray(sd.limit(cube, "catmull-clark", 2).vertices)
        self.assertEqual(attractor.shape, limit.shape)
        distance = np.linalg.norm(attractor[:, None, :] - limit[None, :, :], axis=2)
        self.assertLess(distance.min(axis=1).max(), 1e-12)
        self.assertLess(distance.min(axis=0).max(), 1e-12)
        rough, perturbation = sd.fractal_surface(s, amplitude=0.5, seed=3)
        self.assertEqual(len(perturbation.values), 8)
        self.assertLessEqual(perturbation.residual, 1e-12)
        fractal = np.asarray(sd.surface_automaton_mesh(rough, 2).vertices)
        corners = np.asarray(sd.limit(cube, "catmull-clark", 0).vertices)
        self.assertLess(np.linalg.norm(fractal[:, None, :] - corners[None, :, :], axis=2).min(axis=0).max(), 1e-12)
        self.assertGreater(np.abs(fractal - attractor).max(), 1e-3)
        points = cifs.ifs.chaos_game(s.automaton, s.nets, samples=200, seed=2).points
        self.assertEqual(points.shape, (200, 3))

class LocalAnalysisTest(unittest.TestCase):
    def test_matches_the_cli_and_the_closed_forms(self):
        import math
        for n in (3, 5, 8):
            a = sd.local_analysis("catmull-clark", n)
            c = math.cos(2 * math.pi / n)
            self.assertAlmostEqual(a["lambda1"], (5 + c + math.cos(math.pi / n) * math.sqrt(2 * (9 + c))) / 16, places=15)
            cli_out = cli_json("scheme", "catmull-clark", "--valence", str(n), "--analyze")
            self.assertEqual(a["labels"], cli_out["neighbourhood"])
            self.assertEqual(a["curvature"], cli_out["curvature"]["verdict"])
            self.assertEqual(a["exact"][0][0], Fraction(cli_out["matrix"][0][0]))
        loop = sd.local_analysis("loop", 7)
        self.assertIsNone(loop["exact"])
        self.assertEqual(loop["matrix"].shape, (8, 8))
        self.assertAlmostEqual(loop["lambda1"], 3 / 8 + math.cos(2 * math.pi / 7) / 4, places=15)
        self.assertEqual(loop["subdominant_basis"].shape, (8, 2))
        self.assertAlmostEqual(loop["limit_stencil"].sum(), 1.0, places=15)
        self.assertEqual(sd.local_analysis("sqrt3", 4)["steps"], 2)
        self.assertFalse(sd.local_analysis("loop", 7, boundary="edge")["gap"])

    def test_c1_verdicts(self):
        for scheme, method in (("catmull-clark", "bernstein"), ("loop", "bernstein"), ("doo-sabin", "bernstein"),
                               ("butterfly", "sampled"), ("sqrt3", "sampled")):
            c1 = sd.local_analysis(scheme, 5)["c1"]
            self.assertTrue(c1["verdict"], c1["reason"])
            self.assertEqual(c1["method"], method)
            self.assertEqual(c1["winding"], 1)
            self.assertEqual(c1["verdict"], cli_json("scheme", scheme, "--valence", "5", "--analyze")["c1"]["verdict"])
        boundary = sd.local_analysis("loop", 5, boundary="edge")
        self.assertEqual(boundary["vertex"], "boundary")
        self.assertTrue(boundary["c1"]["verdict"])
        self.assertEqual(len(boundary["c1"]["sectors"]), 1)
        import math

        # Issue 29 §4: per sector at tagged vertices; Loop's boundary of 7 faces is not C1.
        crease = sd.local_analysis("catmull-clark", 4, sharp=[0, 2])
        self.assertEqual(crease["vertex"], "crease")
        self.assertEqual([s["faces"] for s in crease["c1"]["sectors"]], [2, 2])
        self.assertAlmostEqual(crease["c1"]["sectors"][0]["c1"]["angle"], math.pi, places=9)
        self.assertFalse(sd.local_analysis("loop", 8, boundary="edge")["c1"]["verdict"])
        # √3's boundary (two steps, Kobbelt's rule; exact): C1 at 4 faces, not from 7.
        sqrt3 = sd.local_analysis("sqrt3", 5, boundary="edge")
        self.assertEqual(sqrt3["steps"], 2)
        self.assertTrue(sqrt3["c1"]["verdict"], sqrt3["c1"]["reason"])
        self.assertAlmostEqual(sqrt3["lambda1"], (2 + 2 * math.cos(math.pi / 4)) / 9, places=15)
        self.assertFalse(sd.local_analysis("sqrt3", 8, boundary="edge")["c1"]["verdict"])
        # Butterfly's boundary rule (4-point curve, reflected wings): C1 at 2 and 3 faces, not at 4.
        self.assertTrue(sd.local_analysis("butterfly", 4, boundary="edge")["c1"]["verdict"])
        self.assertFalse(sd.local_analysis("butterfly", 5, boundary="edge")["c1"]["verdict"])
        self.assertTrue(sd.local_analysis("loop", 5, sharp=[0])["c1"]["verdict"])
        concave = sd.local_analysis("loop", 2, boundary="edge", corner=True, concave=True)
        self.assertIn("concave", concave["c1"]["reason"])
        with self.assertRaisesRegex(cifs.InvalidInput, "sharp edge 6 is out of place"):
            sd.local_analysis("loop", 6, sharp=[0, 6])
        # Doo-Sabin's faces touching the boundary: the interior k-gon's map on the interior corners'
        # patches, a run of m of k corners spanning 360 m / k degrees; two runs pinch.
        hexagon = sd.local_analysis("doo-sabin", 6, interior_corners=[1, 1, 1, 0, 0, 0])
        self.assertEqual(hexagon["vertex"], "boundary")
        self.assertTrue(hexagon["c1"]["verdict"], hexagon["c1"]["reason"])
        self.assertAlmostEqual(hexagon["c1"]["angle"], math.pi, places=12)
        self.assertEqual(len(hexagon["labels"]), 6 + 2 * 4 + 3)  # corners, 4 edge quads, 3 corner quads
        self.assertFalse(sd.local_analysis("doo-sabin", 4, interior_corners=[1, 0, 1, 0])["c1"]["verdict"])
        with self.assertRaisesRegex(cifs.InvalidInput, "every one of the 4 is interior"):
            sd.local_analysis("doo-sabin", 4, interior_corners=[1, 1, 1, 1])
        with self.assertRaisesRegex(cifs.InvalidInput, "1 \\(interior\\) or 0"):
            sd.local_analysis("doo-sabin", 4, interior_corners=[1, 2, 0, 0])

    def test_analyze_mesh(self):
        """Issue 29 §5: which points of a mesh are not smooth (the CLI's cifs analyze, the same library call)."""
        mesh = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "open_grid_triangles.obj"))
        a = sd.analyze_mesh(mesh, "loop")
        self.assertEqual(a["regular"] + len(a["vertices"]), 35)
        self.assertEqual({v["class"] for v in a["vertices"]}, {"boundary"})
        self.assertEqual(sorted(v["sector_faces"][0] for v in a["vertices"]), [1, 1, 2, 2])
        self.assertTrue(all(v["c1"] for v in a["vertices"]))
        self.assertEqual({v["semi_sharp"] for v in a["vertices"]}, {0.0})
        self.assertEqual(a["analyses"], 2)
        self.assertEqual(a["summary"], cli("analyze", str(EXAMPLES / "meshes" / "open_grid_triangles.obj"),
                                           "--scheme", "loop").stdout.strip().splitlines()[-1])
        # Butterfly: the same vertices; its boundary rule is C1 at 2 and 3 faces only, so the grid's
        # corners (1 and 2 faces) are undecided and C1.
        b = sd.analyze_mesh(mesh, "butterfly")
        self.assertEqual(sorted((v["sector_faces"][0], v["c1"]) for v in b["vertices"]),
                         [(1, None), (1, None), (2, True), (2, True)])
        self.assertEqual(b["summary"], cli("analyze", str(EXAMPLES / "meshes" / "open_grid_triangles.obj"),
                                           "--scheme", "butterfly").stdout.strip().splitlines()[-1])
        # Doo-Sabin: points are face centres (vertex -1) and interior vertices' faces.
        cube = sd.analyze_mesh(cifs.io.read_mesh(str(EXAMPLES / "meshes" / "cube.obj")), "doo-sabin")
        self.assertEqual([(v["vertex"], v["face"], v["valence"], v["c1"]) for v in cube["vertices"]],
                         [(v, -1, 3, True) for v in range(8)])
        with self.assertRaisesRegex(cifs.InvalidInput, "nothing to analyse"):
            sd.analyze_mesh(mesh, "bilinear")

    def test_blz_rules(self):
        """Issue 29 §4: Biermann-Levin-Zorin's rules, rules='blz' in local_analysis and in MeshTags."""
        standard = sd.local_analysis("catmull-clark", 7, boundary="edge")  # 6 faces
        blz = sd.local_analysis("catmull-clark", 7, boundary="edge", rules="blz")
        self.assertFalse(standard["c1"]["verdict"])
        self.assertTrue(blz["c1"]["verdict"])
        self.assertAlmostEqual(blz["lambda1"], 0.5, places=13)
        self.assertAlmostEqual(blz["lambda2"], 0.5, places=13)
        # Loop, a concave corner of 3 faces: exact weights; 1, 1/2, 1/2 and the flattened inner modes
        # (1 - 1/2)(gamma + cos(j pi/3)/4), gamma = 1/2 - cos(pi/2)/4: 5/16 and 3/16.
        concave = sd.local_analysis("loop", 4, boundary="edge", corner=True, concave=True, rules="blz")
        self.assertIsNotNone(concave["exact"])
        self.assertEqual(sum(concave["exact"][3]), 1)
        assert_close(self, sorted(z.real for z in concave["eigenvalues"]), [3 / 16, 5 / 16, 0.5, 0.5, 1], 1e-13)
        self.assertTrue(concave["c1"]["verdict"])
        # A mesh: the rule set is a tag, as the crease method is.
        fan = cifs.io.read_mesh(str(EXAMPLES / "meshes" / "boundary_fan.obj"))
        tagged = cifs.io.Mesh(fan.vertices, faces=fan.faces, tags=cifs.io.MeshTags(rules="blz"))
        self.assertEqual((fan.tags.rules, tagged.tags.rules), ("opensubdiv", "blz"))
        a = sd.analyze_mesh(tagged, "catmull-clark")
        self.assertEqual(a["vertices"][0]["vertex"], 0)
        self.assertTrue(a["vertices"][0]["c1"])
        self.assertFalse(sd.analyze_mesh(fan, "catmull-clark")["vertices"][0]["c1"])
        self.assertEqual(a["summary"], cli("analyze", str(EXAMPLES / "meshes" / "boundary_fan.obj"), "--scheme",
                                           "catmull-clark", "--rules", "blz").stdout.strip().splitlines()[-1])
        refined = sd.subdivide(tagged, "catmull-clark", 2)
        self.assertGreater(np.abs(refined.vertices - sd.subdivide(fan, "catmull-clark", 2).vertices).max(), 1e-3)
        with self.assertRaisesRegex(cifs.InvalidInput, "unknown rule set 'zorin'"):
            cifs.io.MeshTags(rules="zorin")
        with self.assertRaisesRegex(cifs.InvalidInput, "unknown rule set 'zorin'"):
            sd.local_analysis("loop", 4, boundary="edge", rules="zorin")
        with self.assertRaisesRegex(cifs.InvalidInput, "limits under the rule set 'blz' are not built"):
            sd.limit(tagged, "catmull-clark")

    def test_errors(self):
        with self.assertRaisesRegex(cifs.InvalidInput, "valence 2 is out of range"):
            sd.local_analysis("loop", 2)
        with self.assertRaisesRegex(cifs.InvalidInput, "doo-sabin: boundary vertices make no face"):
            sd.local_analysis("doo-sabin", 5, boundary="edge")
        with self.assertRaisesRegex(cifs.InvalidInput, "unknown boundary rule 'sharp'"):
            sd.local_analysis("loop", 4, boundary="sharp")
