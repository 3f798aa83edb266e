# SPDX-License-Identifier: MIT
"""Every parameter of every bound callable goes through a checked conversion (issue 16 item 3).

The module is walked as test_robustness walks it (functions, constructors, methods, property setters; the
signatures from the docstrings, plausible values for the other parameters): each array parameter gets a
complex array, a string, a ragged list and a wrong shape, each bool parameter 2 / "yes" / None, each integer
parameter -1 / 2**64 / 1.5. Every call must raise cifs.InvalidInput naming the parameter — or, for a function
with overloads, pybind11's TypeError "incompatible function arguments": there a conversion may not throw, since
the next overload may take the value, and pybind11 lists the signatures instead. Never a silent acceptance,
except -1 where a negative integer means something (NEGATIVE_MEANINGFUL, checked against the documentation).
"""
import faulthandler
import os
import re
import tempfile
import unittest

import numpy as np

import cifs
from test_robustness import SUBMODULES, _call, _instances, _Samples, _signatures  # noqa: I100

# Integer parameters where -1 is a documented value ("none", "automatic", "the whole range", or a signed
# quantity): the call may succeed with it. Everything else must refuse -1 naming the parameter.
NEGATIVE_MEANINGFUL = {
    ("ifs.sample_attractor", "depth"),           # -1: no depth, the tolerance decides
    ("ifs.box_counting", "min_level"),           # -1: automatic
    ("ifs.box_counting", "max_level"),           # -1: automatic
    ("experiment.measure_dimension", "min_level"),  # -1: automatic (as cifs dimension)
    ("experiment.measure_dimension", "max_level"),  # -1: automatic
    ("automata.Automaton.add_initial", "span"),  # -1: no knot span
}

# Object parameters (converted in the function body, with the parameter's name) that hold arrays: they get the
# array values too. Their checks run after those of the typed parameters, so the other arguments must be
# plausible: such a parameter is only tried when the plausible call succeeds.
ARRAY_OBJECTS = {"vertices", "points", "segments", "triangles", "quads", "normals", "polylines", "density",
                 "nets", "faces", "face_offsets", "face_vertices", "eye", "target", "up", "view_direction",
                 "light_direction", "color", "point", "values", "pixels"}

# Array parameters documented to take any shape.
ANY_SHAPE = {("render.tone_map_log_density", "density")}

CHEAP = {
    "ifs.tolerance_sample": {"max_points": 4096}, "ifs.for_each_leaf_to_tolerance": {"epsilon": 0.1},
    "experiment.sample": {"max_points": 4096}, "experiment.evaluate": {"depth": 3},
    "experiment.run": {"quiet": True}, "experiment.measure_dimension": {"max_points": 4096}, "verify.check_curve": {"depth": 3}, "verify.check_surface": {"depth": 2},
    "render.chaos_game_histogram": {"samples": 1000, "width": 8, "height": 8},
    "render.chaos_density": {"samples": 1000}, "render.estimate_bounds": {"points": 1000},
    "ifs.chaos_game": {"samples": 1000}, "ifs.sample_attractor": {"depth": 2},
}


class _Plausible(_Samples):
    """test_robustness's plausible values, by name only where the value converts to the annotated type (a
    conversion refused for another parameter would hide the one under test)."""

    def __init__(self, *args):
        super().__init__(*args)
        self.extra = {"cifs::Mesh": self.mesh, "List[Tuple[float, int]]": [(0.1, 10), (0.05, 40)],
                      "List[int[2]]": [1, 1], "List[List[float][2]]": [[0, 0, 1, 1]] * 2,
                      "Optional[List[int[2]]]": [2, 2], "List[List[int[2]]]": [[0, 0]],
                      "List[Tuple[int, str, int, str]]": [(0, "end", 0, "start")]}
        corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
        cube = cifs.io.Mesh(corners, quads=np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6],
                                                     [0, 2, 6, 4], [1, 5, 7, 3]]))
        self.by_type["cifs._cifs.subdivision.SurfaceAutomaton"] = cifs.subdivision.surface_automaton(
            cifs.subdivision.catmull_clark(cube))
        self.by_name.update({"eye": (0.0, 0.0, 5.0), "target": (0.0, 0.0, 0.0), "up": (0.0, 1.0, 0.0),
                             "point": (0.5, 0.5, 0.0), "light_direction": (0.0, 0.0, 1.0),
                             "view_direction": (1.0, 1.0, 1.0), "segments": np.array([[0, 1]])})

    def per_call(self, display):
        """Plausible values for the functions whose parameters the generic ones do not fit."""
        t = self.tensor
        surface_nets = cifs.automata.initial_nets(t, self.surface)
        chaikin = np.array([[0.75, 0.25, 0], [0.25, 0.75, 0], [0, 0.75, 0.25]])
        points = np.random.default_rng(1).random((2000, 2))
        mesh_call = {"scheme": "catmull-clark", "valence": 4}
        data = np.array([[0, 0], [1, 2], [2, 1], [3, 3], [4, 0], [5, 2]], dtype=float)  # distinct, 2-D
        on_curve = cifs.nurbs.evaluate(self.curve, np.linspace(0, 3, 6))
        grid = np.array([[[i, j, i * j % 3] for j in range(5)] for i in range(4)], dtype=float)
        arc = np.array([[1, 0, 0], [2, 1, 1], [3, 0, 2]], dtype=float)
        space = [cifs.nurbs.Curve(2, [0, 0, 0, 1, 1, 1], arc + [0, 0, z]) for z in (0, 3)]  # 3-D curves
        return {
            "nurbs.make_compatible": {"curves": space}, "nurbs.loft": {"curves": space, "degree_v": 1},
            "nurbs.loft_parameters": {"curves": space},
            "nurbs.revolve": {"profile": space[0], "axis_point": [0.0, 0.0, 0.0], "axis_direction": [0.0, 0.0, 1.0]},
            "nurbs.sweep": {"profile": space[0], "trajectory": space[1]},
            "nurbs.rotation_minimizing_frames": {"curve": space[0], "count": 3},
            "nurbs.Volume": {"degree": [1, 1, 1], "knots": [[0, 0, 0.5, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1]],
                             "points": np.zeros((3, 2, 2, 3))},
            "nurbs.interpolate": {"points": data}, "nurbs.fit_parameters": {"points": data},
            "nurbs.approximate": {"points": data, "control_points": 4},
            "nurbs.fit_distances": {"points": on_curve},
            "nurbs.interpolate_surface": {"points": grid}, "nurbs.approximate_surface": {"points": grid},
            "nurbs.Surface": {"degree": [1, 1], "knots": [[0, 0, 1, 1]] * 2, "points": np.zeros((2, 2, 3))},
            "ifs.surface_mesh": {"nets": surface_nets},
            "ifs.quad_mesh": {"automaton": t.product, "nets": surface_nets, "patches": t.patches},
            "ifs.mesh_stencil_table": {"automaton": t.product, "patches": t.patches},
            "ifs.box_counting": {"points": points, "min_boxes": 10},
            "ifs.uniform_curve_bcifs": {"S0": chaikin, "S1": chaikin[::-1, ::-1]},
            "subdivision.limit": mesh_call, "subdivision.local_analysis": mesh_call,
            "subdivision.refine_topology": mesh_call, "subdivision.subdivide": mesh_call,
            "subdivision.analyze_mesh": {"scheme": "catmull-clark"},
        }.get(display, {})

    def value(self, name, annotation):
        if annotation in self.extra:
            return self.extra[annotation]
        if annotation.startswith(("cifs._cifs.", "cifs::")) and annotation in self.by_type:
            return self.by_type[annotation]  # a bound class: not the array or list a name suggests
        value = super().value(name, annotation)
        base = re.sub(r"^Optional\[(.*)\]$", r"\1", annotation)
        scalar = {"int": int, "float": (int, float), "bool": bool}.get(base)
        if (scalar and not isinstance(value, scalar)) or (
                base.startswith(("List[", "numpy.")) and not isinstance(value, (list, tuple, np.ndarray))):
            return super().value("", annotation)
        return value


def _kind(pname, annotation):
    """'array', 'bool', 'int' or None for a parameter, from its annotation (and name for `object`)."""
    base = re.sub(r"^Optional\[(.*)\]$", r"\1", annotation)
    if base == "bool":
        return "bool"
    if base == "int":
        return "int"
    if base.startswith(("numpy.ndarray", "List[float]", "List[int", "List[numpy.ndarray", "List[List[")):
        return "array"
    if base == "object" and pname in ARRAY_OBJECTS:
        return "array"
    return None


def _bad_values(kind, annotation):
    if kind == "bool":
        return {"2": 2, "'yes'": "yes", "None": None}
    if kind == "int":
        return {"-1": -1, "2**64": 2**64, "1.5": 1.5}
    # Arrays: a wrong shape is one no array parameter takes — a 4-D array (surfaces take 3-D points), a triple for
    # lists of pairs.
    # A ragged list is ragged at every depth a parameter reads (a list of lists of floats takes [[1, 2], [3]]).
    wrong_shape = [[0, 0, 0]] if "int[2]" in annotation else np.zeros((2, 2, 2, 2))
    return {"complex array": np.ones((4, 2), dtype=complex), "str": "abc",
            "ragged list": [[1.0, 2.0], [3.0, [4.0]]], "wrong shape": wrong_shape}


def _callables(samples):
    """(display name, callable, overloads as parameter lists, overloaded) for everything bound."""
    instances = _instances(samples)
    instances.update({
        "StencilTable": cifs.ifs.stencil_table(samples.automaton, 2),
        "MeshStencilTable": cifs.ifs.mesh_stencil_table(samples.tensor.automaton, 1, patches=[[0, 0]])
        if hasattr(samples.tensor, "automaton") else None,
    })
    fresh = {"Camera": lambda: cifs.render.Camera(width=16, height=16), "Bounds": cifs.render.Bounds,
             "AffineMap": cifs.ifs.AffineMap, "Image": lambda: samples.image.copy()}
    for submodule in SUBMODULES:
        module = getattr(cifs, submodule)
        for attr in sorted(vars(module)):
            obj = getattr(module, attr)
            if attr.startswith("_") or not callable(obj):
                continue
            if not isinstance(obj, type):
                overloads = _signatures(obj, attr)
                yield f"{submodule}.{attr}", obj, overloads, len(overloads) > 1
                continue
            overloads = [params[1:] for params in _signatures(obj.__init__, "__init__")]
            yield f"{submodule}.{attr}", obj, overloads, len(overloads) > 1
            instance = instances.get(attr)
            if instance is None:
                continue
            for member, value in sorted(vars(obj).items()):
                if isinstance(value, property) and value.fset is not None:
                    setter_params = _signatures(getattr(value.fset, "__wrapped__", value.fset), "")
                    annotation = setter_params[0][-1][1] if setter_params else ""

                    def setter(v, attr=attr, instance=instance, member=member):
                        target = fresh[attr]() if attr in fresh else instance.copy()
                        setattr(target, member, v)
                    yield f"{submodule}.{attr}.{member}", setter, [[(member, annotation, False, False)]], False
                elif callable(value) and not member.startswith("_"):
                    bound = getattr(instance, member)
                    overloads = [params[1:] if params and params[0][0] == "self" else params
                                 for params in _signatures(bound, member)]
                    yield f"{submodule}.{attr}.{member}", bound, overloads, len(overloads) > 1


class ArgumentTest(unittest.TestCase):
    def test_every_parameter_is_checked(self):
        faulthandler.dump_traceback_later(600, exit=True)  # a hang (a value accepted into a huge loop) fails
        self.addCleanup(faulthandler.cancel_dump_traceback_later)
        with tempfile.TemporaryDirectory(prefix="cifs-arguments-") as scratch:
            cwd = os.getcwd()
            os.chdir(scratch)
            self.addCleanup(os.chdir, cwd)
            samples = _Plausible(cifs, np, scratch)
            tried, untried, failures, inconclusive = {"array": 0, "bool": 0, "int": 0}, [], [], []
            for display, fn, overloads, overloaded in _callables(samples):
                for params in overloads:
                    cheap = {**samples.per_call(display), **CHEAP.get(display, {})}

                    def call(override, params=params, fn=fn, cheap=cheap):
                        try:
                            _call(fn, params, samples, override, cheap)
                        except Exception as error:  # noqa: BLE001 — the outcome is judged below
                            return error
                        return None

                    plausible = call({})
                    for i, (pname, annotation, _, _) in enumerate(params):
                        kind = _kind(pname, annotation)
                        if kind is None:
                            continue
                        if annotation == "object" and plausible is not None:
                            untried.append(f"{display}({pname}): the plausible call fails: {plausible}")
                            continue
                        tried[kind] += 1
                        for label, value in _bad_values(kind, annotation).items():
                            error = call({i: value})
                            if label == "wrong shape" and (display, pname) in ANY_SHAPE:
                                continue
                            if label == "-1" and plausible is not None and str(error) == str(plausible):
                                # -1 converted (a signed int) and the call failed as the plausible one does: the
                                # library's own check of the value is not reached with these arguments.
                                inconclusive.append(f"{display}({pname}=-1): {plausible}")
                                continue
                            verdict = self._judge(display, pname, label, error, plausible, overloaded)
                            if verdict:
                                failures.append(verdict)
            print(f"checked {tried} parameters; not tried: {len(untried)}", *untried, sep="\n  ")
            print(f"{len(failures)} failures", *failures, sep="\n  ")
            print(f"-1 inconclusive: {len(inconclusive)}", *inconclusive, sep="\n  ")
            self.assertEqual(failures, [], "\n".join(failures))
            # Every kind is reached, most of the parameters are (the counts at the time of writing: 167 arrays,
            # 52 bools, 181 integers).
            self.assertGreater(tried["array"], 100)
            self.assertGreater(tried["bool"], 40)
            self.assertGreater(tried["int"], 120)
            self.assertLess(len(untried), 5, untried)
            self.assertLess(len(inconclusive), 10, inconclusive)

    @staticmethod
    def _judge(display, pname, label, error, plausible, overloaded):
        """None when the call with a bad value was refused as it should be, else what went wrong."""
        where = f"{display}({pname}={label})"
        if label == "-1" and (display, pname) in NEGATIVE_MEANINGFUL and not isinstance(error, TypeError):
            return None  # taken, or refused in combination with the others (no depth and no tolerance)
        if error is None:
            return f"{where}: accepted"
        if isinstance(error, cifs.InvalidInput):
            if re.search(rf"(^|\W){re.escape(pname)}(\W|$)", str(error)):
                return None
            # -1 converts into a signed int and the library refuses it, naming its role rather than the Python
            # name ("add_transition: state -1 does not exist"): the value must be quoted, and the refusal its own.
            if label == "-1" and re.search(r"(^|[^\w.])-1(\D|$)", str(error)) and str(error) != str(plausible):
                return None
            return f"{where}: InvalidInput not naming the parameter: {error}"
        if isinstance(error, TypeError) and overloaded and re.search(r"incompatible (function|constructor) arguments",
                                                                     str(error)):
            return None
        return f"{where}: {type(error).__name__}: {str(error)[:300]}"


class MessageTest(unittest.TestCase):
    """The refusals name the function, the parameter and the place, checked by hand."""

    def test_messages(self):
        curve = cifs.nurbs.Curve(1, [0, 0, 1, 1], np.array([[0.0, 0.0], [1.0, 1.0]]))
        automaton = cifs.automata.knot_automaton(curve)
        nets = cifs.automata.initial_nets(automaton, curve)
        cases = [
            (lambda: cifs.nurbs.control_count([0, 0, 1j, 1], 1), r"^control_count: knots\[2\]: expected a real number"),
            (lambda: cifs.nurbs.control_count(np.array([0, 0, 1j]), 1), r"^control_count: knots: .*complex128"),
            (lambda: cifs.nurbs.control_count([0, 0, 1, 1], 2**64), r"^control_count: degree: .*18446744073709551616"),
            (lambda: cifs.nurbs.control_count([0, 0, 1, 1], 1.5), r"^control_count: degree: expected an integer"),
            (lambda: cifs.ifs.attractor_points(automaton, [nets[0], nets[0].astype(complex)], 2),
             r"^attractor_points: nets\[1\]: .*complex128"),
            (lambda: cifs.ifs.attractor_points(automaton, nets, 2, closed=np.int64(1)),
             r"^attractor_points: closed: expected True or False, got numpy.int64"),
            (lambda: cifs.ifs.diameter(np.zeros((2, 2, 2))), r"^diameter: net: expected a 2-D array"),
            (lambda: cifs.io.polyline_obj(np.array([[0, 0], [1, 1j]])), r"^polyline_obj: points: .*complex128"),
            (lambda: setattr(cifs.render.Camera(), "fov_y", "wide"), r"^Camera: fov_y: expected a real number"),
            (lambda: cifs.ifs.mesh_stencil_table(automaton, 1, patches=[[0, 0, 0]]),
             r"^mesh_stencil_table: patches\[0\]: expected 2 items"),
            (lambda: cifs.nurbs.Direction(-1), r"^Direction: value: expected one of 0, 1, got int -1$"),
            # A long value is cut at a character boundary (the message stays valid UTF-8).
            (lambda: cifs.nurbs.control_count("é" * 50, 1), r"^control_count: knots: expected a list, got str 'é+\.\.\.$"),
        ]
        for call, pattern in cases:
            with self.assertRaises(cifs.InvalidInput) as e:
                call()
            self.assertRegex(str(e.exception), pattern)

    def test_valid_values_still_convert(self):
        """numpy scalars and integer arrays, Fractions, True/False and numpy bools are taken as before."""
        curve = cifs.nurbs.Curve(np.int64(1), np.array([0, 0, 1, 1]), np.array([[0, 0], [1, 1]]))
        self.assertEqual(cifs.nurbs.control_count(np.array([0, 0, 1, 1], dtype=np.int32), np.uint8(1)), 2)
        from fractions import Fraction
        np.testing.assert_allclose(cifs.nurbs.evaluate(curve, Fraction(1, 4)), [0.25, 0.25])
        np.testing.assert_allclose(cifs.nurbs.evaluate(curve, np.float32(0.5)), [0.5, 0.5])
        automaton = cifs.automata.knot_automaton(curve)
        nets = cifs.automata.initial_nets(automaton, curve)
        a = cifs.ifs.attractor_points(automaton, nets, 2, closed=np.bool_(True))
        b = cifs.ifs.attractor_points(automaton, nets, 2, closed=True)
        np.testing.assert_array_equal(a, b)


if __name__ == "__main__":
    unittest.main()
