# SPDX-License-Identifier: MIT
"""Closed curves across the seam against an exact evaluator (issue 16, defect 12).

The reference is Cox–de Boor in rationals (fractions.Fraction) on the exact values of the stored
doubles of the breakpoints, the period extended in rationals (b_k + q·T with T = b_m − b_0 exact):
nothing of the code under test enters it. Every route must stay within 1e-12 of max |P| — the
written bound of docs/formats.md ("Closed curves"), with margin: the routines evaluated
(`cifs eval`, the attractor of `cifs attractor --depth`, the Python module's de Boor, basis form,
derivatives and insertion) at the period's start and end, at random parameters and, for the
attractor, at every dyadic parameter of its depth.
"""
import json
import random
import sys
import unittest
from fractions import Fraction

import numpy as np

from support import ScratchTestCase, cli, sampled

TOLERANCE = 1e-12

# The audit's case: adjacent intervals 1e6 apart, the period ends at 1000.004.
AUDIT_KNOTS = [0, 0.001, 0.002, 1000.002, 1000.003, 1000.004]


def exact_knots(breakpoints, degree):
    """The periodic knot vector t_j = b_{(j−d) mod m} + ⌊(j−d)/m⌋·T, in rationals."""
    b = [Fraction(x) for x in breakpoints]
    m = len(b) - 1
    period = b[m] - b[0]
    knots = []
    for j in range(m + 2 * degree + 1):
        q, k = divmod(j - degree, m)
        knots.append(b[k] + q * period)
    return knots


def exact_rows(points, weights, degree):
    """The expanded rows (m + d of them), homogeneous (w·x, w) when weighted, in rationals."""
    m = len(points)
    rows = []
    for i in range(m + degree):
        x = [Fraction(v) for v in points[i % m]]
        if weights is None:
            rows.append(x)
        else:
            w = Fraction(weights[i % m])
            rows.append([w * v for v in x] + [w])
    return rows


def exact_span(t, degree, n, u):
    """find_span: t_k ≤ u < t_{k+1}, k in [d, n − 1]; the domain end belongs to the last non-empty span."""
    if u >= t[n]:
        k = n - 1
        while t[k] == t[n]:
            k -= 1
        return k
    return max(k for k in range(degree, n) if t[k] <= u)


def de_boor(t, k, p, net, u):
    """de Boor's triangle of degree p on span k, net[j] the row of index k − p + j."""
    d = [list(r) for r in net]
    for r in range(1, p + 1):
        for j in range(p, r - 1, -1):
            i = j + k - p
            a = (u - t[i]) / (t[i + p + 1 - r] - t[i])
            d[j] = [(1 - a) * x + a * y for x, y in zip(d[j - 1], d[j])]
    return d[p]


def exact_point(breakpoints, points, weights, degree, u, derivative=0):
    """The curve point (derivative=0) or its first derivative at the rational u, in rationals."""
    t = exact_knots(breakpoints, degree)
    rows = exact_rows(points, weights, degree)
    k = exact_span(t, degree, len(rows), u)
    net = rows[k - degree: k + 1]
    value = de_boor(t, k, degree, net, u)
    if derivative == 0:
        return value if weights is None else [x / value[-1] for x in value[:-1]]
    # C' = Σ p·(P_i − P_{i−1})/(t_{i+p} − t_i)·N_{i,p−1}: rows k − p + 1 … k of degree p − 1.
    diff = []
    for j in range(1, degree + 1):
        i = k - degree + j
        scale = Fraction(degree) / (t[i + degree] - t[i])
        diff.append([scale * (y - x) for x, y in zip(net[j - 1], net[j])])
    slope = de_boor(t, k, degree - 1, diff, u)
    if weights is None:
        return slope
    w, dw = value[-1], slope[-1]
    return [(dx - dw * x / w) / w for dx, x in zip(slope[:-1], value[:-1])]


def relative_error(points, exact, scale):
    return max(abs(float(Fraction(float(v)) - e)) for row, ex in zip(points, exact)
               for v, e in zip(row, ex)) / scale


def random_case(rng, degree, ratio_exponent, size, placement):
    """Breakpoints with interval lengths spread over 10^0 … 10^ratio_exponent, of size up to `size`.

    The rounding of the extended knots b_k ± T hurts when the short intervals lie at the seam and the
    breakpoints there have finer bits than the far end of the period: the audit's [0, 0.001, …,
    1000.004]. `placement` "start": b_0 near 0, short intervals first and last, b_m large (the right
    extension rounds); "end": its mirror image (b_0 = −large, b_m near 0: the left extension rounds);
    "shifted": the period anywhere in ±size, intervals in random order."""
    m = rng.randint(max(2, degree - 2), degree + 4)
    lengths = [10.0 ** rng.uniform(0, ratio_exponent) for _ in range(m)]
    if placement != "shifted":  # short intervals at both ends of the period, long ones inside
        lengths.sort()
        lengths = lengths[0::2] + lengths[1::2][::-1]
    factor = rng.uniform(0.1, 1.0) * size / sum(lengths)
    lengths = [h * factor for h in lengths]
    start = rng.uniform(-1, 1) * lengths[0] if placement != "shifted" else rng.uniform(-0.5, 0.5) * size
    breakpoints = [start]
    for h in lengths:
        breakpoints.append(breakpoints[-1] + h)
    if placement == "end":
        breakpoints = [-b for b in reversed(breakpoints)]
    if len(set(breakpoints)) != len(breakpoints) or max(map(abs, breakpoints)) > size:
        return None  # an interval lost to rounding, or knots beyond the size: not the case tested
    size_p = rng.choice([1.0, 1e-3])
    points = [[rng.uniform(-size_p, size_p) for _ in range(2)] for _ in range(m)]
    weights = [10.0 ** rng.uniform(-1, 1) for _ in range(m)] if rng.random() < 0.3 else None
    return breakpoints, points, weights


def audit_case():
    rng = random.Random(16)
    points = [[rng.uniform(-1e-3, 1e-3) for _ in range(2)] for _ in range(5)]
    return AUDIT_KNOTS, points, None


def shape_json(degree, breakpoints, points, weights):
    curve = {"degree": degree, "knots": breakpoints, "points": points, "closed": True}
    if weights is not None:
        curve["weights"] = weights
    return json.dumps({"curve": curve})


def cases():
    """(name, degree, breakpoints, points, weights): the audit's case and random ones."""
    out = [("audit", 2, *audit_case())]
    rng = random.Random(1216)
    for degree in range(1, 7):
        for exponent in (0, 3, 6, 9, 12):
            for size in (1e3, 1e6):
                for placement in ("start", "end", "shifted"):
                    case = None
                    while case is None:
                        case = random_case(rng, degree, exponent, size, placement)
                    out.append((f"d{degree} ratio 1e{exponent} |t| ≤ {size:g} {placement}", degree, *case))
    # Sanitized: the audit's case and every seventh (7 is prime to the counts of placements, sizes and ratios).
    return sampled(out, 7)


def parameters(rng, breakpoints, count):
    """The period's start and end, the breakpoints next to the seam, and random parameters."""
    b0, bm = breakpoints[0], breakpoints[-1]
    us = [b0, bm, breakpoints[1], breakpoints[-2]]
    for _ in range(count):
        k = rng.randrange(len(breakpoints) - 1)
        us.append(breakpoints[k] + rng.random() * (breakpoints[k + 1] - breakpoints[k]))
    return us


def scale_of(points):
    return max(abs(v) for row in points for v in row)


def report(test, err, name):
    """The figure in the log (ctest -V): the worst relative error and its case."""
    print(f"\n{test.id().split('.')[-1]}: worst {err:.2e} of max|P| ({name})", file=sys.stderr)


class ClosedSeamTest(ScratchTestCase):
    def test_eval_cli(self):
        """`cifs eval --at U` at the period's ends and random parameters, against the exact curve."""
        rng = random.Random(7)
        worst = (0.0, "")
        for name, degree, b, points, weights in cases():
            path = self.scratch / "closed.json"
            path.write_text(shape_json(degree, b, points, weights))
            us = parameters(rng, b, 6)
            args = [a for u in us for a in ("--at", repr(u))]
            got = json.loads(cli("eval", path, *args).stdout)["points"]
            exact = [exact_point(b, points, weights, degree, Fraction(u)) for u in us]
            err = relative_error(got, exact, scale_of(points))
            worst = max(worst, (err, name))
        report(self, *worst)
        self.assertLessEqual(worst[0], TOLERANCE, f"worst case {worst[1]}")

    def test_attractor_cli(self):
        """`cifs attractor --depth K`: the start point of every leaf is the curve at a dyadic parameter."""
        worst = (0.0, "")
        depth = 3
        for name, degree, b, points, weights in cases():
            path = self.scratch / "closed.json"
            path.write_text(shape_json(degree, b, points, weights))
            got = json.loads(cli("attractor", path, "--depth", depth).stdout)["points"]
            exact = []
            for k in range(len(b) - 1):
                lo, hi = Fraction(b[k]), Fraction(b[k + 1])
                if lo == hi:
                    continue
                for j in range(2 ** depth):
                    exact.append(exact_point(b, points, weights, degree, lo + (hi - lo) * j / 2 ** depth))
            self.assertEqual(len(got), len(exact))  # closed: no repeated end point
            err = relative_error(got, exact, scale_of(points))
            worst = max(worst, (err, name))
        report(self, *worst)
        self.assertLessEqual(worst[0], TOLERANCE, f"worst case {worst[1]}")

    def test_library_routes(self):
        """De Boor, the basis form, derivatives, blossoms, insertion and elevation of the Python module."""
        import cifs
        nurbs = cifs.nurbs
        rng = random.Random(11)
        worst = {route: (0.0, "") for route in ("evaluate", "evaluate_basis", "derivative", "blossom", "insert",
                                                 "elevate")}
        for name, degree, b, points, weights in cases():
            curve = nurbs.Curve(degree, b, np.array(points), None if weights is None else np.array(weights),
                                closed=True)
            scale = scale_of(points)
            us = parameters(rng, b, 4)
            exact = [exact_point(b, points, weights, degree, Fraction(u)) for u in us]
            for route, f in (("evaluate", nurbs.evaluate), ("evaluate_basis", nurbs.evaluate_basis)):
                got = [f(curve, u) for u in us]
                worst[route] = max(worst[route], (relative_error(got, exact, scale), name))
            # The derivative's size is that of the points over the shortest interval of its span.
            for u in us[:2]:
                d = nurbs.derivatives(curve, u, 1)[1]
                e = exact_point(b, points, weights, degree, Fraction(u), derivative=1)
                dscale = max(abs(float(v)) for v in e) or 1.0
                worst["derivative"] = max(worst["derivative"], (relative_error([d], [e], max(dscale, scale)), name))
            # blossom(u, …, u) = C(u), in stored (homogeneous) coordinates.
            got = []
            for u in us:
                row = nurbs.blossom(curve, [u] * degree)
                got.append(row if weights is None else row[:-1] / row[-1])
            worst["blossom"] = max(worst["blossom"], (relative_error(got, exact, scale), name))
            # Insertion next to the seam and degree elevation: the same curve.
            knot = b[-1] - (b[-1] - b[-2]) / 3
            for route, changed in (("insert", nurbs.insert_knot(curve, knot, 1)),
                                   ("elevate", nurbs.elevate_degree(curve, 1))):
                got = [nurbs.evaluate(changed, u) for u in us]
                worst[route] = max(worst[route], (relative_error(got, exact, scale), name))
        for route, (err, name) in worst.items():
            report(self, err, f"{route}: {name}")
        for route, (err, name) in worst.items():
            self.assertLessEqual(err, TOLERANCE, f"{route}: worst case {name}")

    def test_audit_case_figure(self):
        """The audit's reproduction: P(end) equals P(start) to 1e-12 of the points (was 8e-12 apart)."""
        b, points, _ = audit_case()
        path = self.scratch / "audit.json"
        path.write_text(shape_json(2, b, points, None))
        got = json.loads(cli("eval", path, "--at", b[0], "--at", b[-1]).stdout)["points"]
        gap = max(abs(x - y) for x, y in zip(got[0], got[1])) / scale_of(points)
        self.assertLessEqual(gap, TOLERANCE)


if __name__ == "__main__":
    unittest.main()
