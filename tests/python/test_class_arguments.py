# SPDX-License-Identifier: MIT
"""A wrong object for a class-typed, str, path, callable or dict parameter names the parameter (issue 16).

pybind11 refuses such a value by trying the next overload, and without one raised "incompatible function
arguments", listing the signature but not saying which argument was wrong. The argument wrapper
(python/src/arguments.cpp) now finds the refused argument from the signature's types and raises a TypeError
"render_mesh: camera: expected a cifs.render.Camera, got int 3". The module is walked as test_arguments walks
it (functions, constructors, methods, property setters; plausible values for the other parameters): every such
parameter of a function without overloads gets an int and an object of another cifs class, passed
positionally or by keyword as the call would pass it. Functions with overloads keep pybind11's message.
"""
import os
import re
import tempfile
import unittest

import numpy as np

import cifs
from test_arguments import CHEAP, _callables, _Plausible  # noqa: I100

# Lists of objects that the generic plausible values do not give (empty lists convert).
PLAUSIBLE = {"ifs.Bcifs": {"boundaries": [], "constraints": [], "free": []},
             "ifs.Constraint": {"left": [], "right": []}}


def _public(annotation):
    """'cifs._cifs.render.Camera' → 'cifs.render.Camera' (the name a message uses)."""
    return annotation.replace("cifs._cifs.", "cifs.")


def _kind(annotation):
    """What a parameter expects, for the values to try and the message to require; None: not tried here."""
    base = re.sub(r"^Optional\[(.*)\]$", r"\1", annotation)
    if re.fullmatch(r"(cifs\._cifs\.[\w.]+|cifs::[\w:]+)", base):
        return "class"
    if re.fullmatch(r"List\[cifs\._cifs\.[\w.]+\]", base):
        return "class list"
    if base.startswith("Union[cifs."):
        return "class"
    if base in ("str", "os.PathLike", "function", "dict", "Iterable") or base.startswith(("Dict[", "Callable[")):
        return base
    return None


def _expected(kind, annotation, item=False):
    """The start of the message's 'expected …' (a pattern), from the annotation alone."""
    base = re.sub(r"^Optional\[(.*)\]$", r"\1", annotation)
    if kind == "class" and base.startswith("cifs._cifs."):
        return re.escape(f"a {_public(base)}")
    if kind == "class list":  # the list, or an item of it
        return re.escape(f"a {_public(base[5:-1])}") if item else re.escape(f"a list of {_public(base[5:-1])}")
    return {"str": "a str", "os.PathLike": "a str or os.PathLike", "function": "a callable", "dict": "a dict",
            "Iterable": "an iterable"}.get(base, "a")  # cifs::Mesh (a C++ name), unions, Dict[...]: any text


def _who(display, fn):
    """The name a message starts with: 'admissible_space', 'Camera' (constructor, setter), 'Camera.copy'."""
    parts = display.split(".")[1:]
    if getattr(fn, "__name__", "") == "setter":  # test_arguments' closure setting a property
        return parts[0]
    return ".".join(parts)


class RaisesCheck:
    """`check(call, error, pattern)`: the call raises exactly `error`, its message matching `pattern`."""

    def check(self, call, error, pattern):
        with self.assertRaises(Exception) as e:
            call()
        self.assertIs(type(e.exception), error, f"{type(e.exception).__name__}: {e.exception}")
        self.assertRegex(str(e.exception), pattern)


class ClassArgumentTest(unittest.TestCase):
    def test_every_class_parameter_is_named(self):
        with tempfile.TemporaryDirectory(prefix="cifs-class-arguments-") as scratch:
            cwd = os.getcwd()
            os.chdir(scratch)
            self.addCleanup(os.chdir, cwd)
            samples = _Plausible(cifs, np, scratch)
            bounds, camera = cifs.render.Bounds(), cifs.render.Camera()
            tried, failures, overloaded_kept = {}, [], 0
            for display, fn, overloads, overloaded in _callables(samples):
                who = _who(display, fn)
                for params in overloads:
                    cheap = {**samples.per_call(display), **CHEAP.get(display, {}), **PLAUSIBLE.get(display, {})}
                    for i, (pname, annotation, _, _) in enumerate(params):
                        kind = _kind(annotation)
                        if kind is None:
                            continue
                        other = camera if "Bounds" in annotation else bounds  # a cifs object of another class
                        values = {"int 3": (3, ""), f"{type(other).__name__}": (other, "")}
                        if kind == "class list":
                            values["[int 3]"] = ([3], r"\[0\]")
                        for label, (value, index) in values.items():
                            error = self._call(fn, params, samples, {i: value}, cheap)
                            where = f"{display}({pname}={label})"
                            if overloaded:
                                if isinstance(error, TypeError) and "incompatible" in str(error):
                                    overloaded_kept += 1
                                    continue
                                failures.append(f"{where} (overloaded): {type(error).__name__}: {error}")
                                continue
                            tried[kind] = tried.get(kind, 0) + 1
                            pattern = (rf"^{re.escape(who)}: {re.escape(pname)}{index}: expected "
                                       rf"{_expected(kind, annotation, bool(index))}.*, got ")
                            if not isinstance(error, TypeError) or isinstance(error, cifs.InvalidInput):
                                failures.append(f"{where}: {type(error).__name__}: {str(error)[:300]}")
                            elif not re.search(pattern, str(error)):
                                failures.append(f"{where}: not /{pattern}/: {str(error)[:300]}")
                            elif label == "int 3" and not str(error).endswith("got int 3"):
                                failures.append(f"{where}: the value is not quoted: {error}")
            print(f"tried {tried}; overloaded (pybind11's message kept): {overloaded_kept}")
            print(f"{len(failures)} failures", *failures, sep="\n  ")
            self.assertEqual(failures, [], "\n".join(failures))
            # Every kind is reached (calls at the time of writing: 266 class, 24 class list, 100 str,
            # 38 os.PathLike, 4 function, 10 dict/Dict, 2 Iterable; 119 on overloaded functions).
            self.assertGreater(tried.get("class", 0), 150)
            self.assertGreater(tried.get("class list", 0), 10)
            self.assertGreater(tried.get("str", 0), 30)
            self.assertGreater(tried.get("os.PathLike", 0), 30)
            self.assertGreater(tried.get("function", 0), 2)

    @staticmethod
    def _call(fn, params, samples, override, cheap):
        """test_robustness's call (positional or keyword as the parameter is declared); the error or None."""
        from test_robustness import _call
        try:
            _call(fn, params, samples, override, cheap)
        except Exception as error:  # noqa: BLE001 — judged by the caller
            return error
        return None


class ClassMessageTest(unittest.TestCase):
    """The messages, written out by hand."""

    def setUp(self):
        self.curve = cifs.nurbs.Curve(1, [0, 0, 1, 1], np.array([[0.0, 0.0], [1.0, 1.0]]))
        self.automaton = cifs.automata.knot_automaton(self.curve)
        self.nets = cifs.automata.initial_nets(self.automaton, self.curve)
        self.system = cifs.ifs.curve_bcifs(self.curve)

    def assert_type_error(self, call, pattern):
        with self.assertRaises(TypeError) as e:
            call()
        self.assertNotIsInstance(e.exception, ValueError)  # a wrong type stays a TypeError
        self.assertRegex(str(e.exception), pattern)

    def test_messages(self):
        maps = cifs.ifs.sierpinski_triangle()
        triangle = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
        cases = [
            (lambda: cifs.ifs.admissible_space(3), r"^admissible_space: system: expected a cifs\.ifs\.Bcifs, got int 3$"),
            # By keyword: pybind11 puts keyword arguments in parameter order before reading them.
            (lambda: cifs.ifs.admissible_space(system=3, threshold=0.1),
             r"^admissible_space: system: expected a cifs\.ifs\.Bcifs, got int 3$"),
            (lambda: cifs.render.Camera(width=8, projection=3),
             r"^Camera: projection: expected a cifs\.render\.Projection, got int 3$"),
            (lambda: setattr(cifs.render.Camera(), "projection", "perspective"),
             r"^Camera: projection: expected a cifs\.render\.Projection, got str 'perspective'$"),
            (lambda: cifs.render.view_transform(cifs.render.Bounds()),
             r"^view_transform: camera: expected a cifs\.render\.Camera, got cifs\.render\.Bounds Bounds\(x_min=0\.0"),
            # None for a class taken by reference: pybind11 reads it, then cannot pass it (reference_cast_error).
            (lambda: cifs.ifs.admissible_space(None), r"^admissible_space: system: expected a cifs\.ifs\.Bcifs, got None$"),
            # An item of a list; the first argument that does not convert is named, not a later one.
            (lambda: cifs.ifs.affine_automaton([maps[0], 3], triangle),
             r"^affine_automaton: maps\[1\]: expected a cifs\.ifs\.AffineMap, got int 3$"),
            (lambda: cifs.ifs.affine_automaton([maps[0], None], triangle),
             r"^affine_automaton: maps\[1\]: expected a cifs\.ifs\.AffineMap, got None$"),
            (lambda: cifs.ifs.affine_automaton(maps[0], triangle),
             r"^affine_automaton: maps: expected a list of cifs\.ifs\.AffineMap, got cifs\.ifs\.AffineMap AffineMap\(a=0\.5"),
            # Strings and paths: str and bytes are strings, and a path is also an os.PathLike.
            (lambda: cifs.automata.Automaton().add_state(2, 3), r"^Automaton\.add_state: name: expected a str, got int 3$"),
            (lambda: cifs.io.read_shape(3), r"^read_shape: path: expected a str or os\.PathLike, got int 3$"),
            (lambda: cifs.io.read_shape("a\0b"),
             r"^read_shape: path: expected a str or os\.PathLike without NUL characters, got str 'a\\x00b'$"),
            (lambda: cifs.ifs.for_each_leaf(self.automaton, self.nets, 1, callback=3),
             r"^for_each_leaf: callback: expected a callable, got int 3$"),
            (lambda: cifs.subdivision.make_scheme("x", [1, 2, 1], parameters=[1]),
             r"^make_scheme: parameters: expected a dict, got list \[1\]$"),
        ]
        for call, pattern in cases:
            with self.subTest(pattern=pattern):
                self.assert_type_error(call, pattern)

    def test_pybind11_messages_kept(self):
        """Overloads, and keyword names pybind11 refuses before reading any argument, keep its message."""
        cases = [
            lambda: cifs.nurbs.domain(self.curve, 3),                      # overloaded
            lambda: cifs.ifs.admissible_space(self.system, bogus=1),       # unknown keyword
            lambda: cifs.ifs.admissible_space(threshold=0.1),              # missing argument
            lambda: cifs.ifs.admissible_space(self.system, system=self.system),  # given twice
        ]
        for call in cases:
            self.assert_type_error(call, r"incompatible (function|constructor) arguments")

    def test_valid_values_still_convert(self):
        """bytes as a str, pathlib paths, None for an optional path, a subclass of a bound class."""
        import pathlib
        automaton = cifs.automata.Automaton()
        self.assertEqual([automaton.add_state(2, b"s0"), automaton.add_state(2, "s1")], [0, 1])
        with tempfile.TemporaryDirectory(prefix="cifs-class-arguments-") as scratch:
            path = pathlib.Path(scratch) / "c.json"
            cifs.io.write(path, self.curve)
            np.testing.assert_array_equal(cifs.io.read_shape(path).P, self.curve.P)
            np.testing.assert_array_equal(cifs.io.read_shape(os.fsencode(path)).P, self.curve.P)

        class MyCamera(cifs.render.Camera):
            pass
        camera = MyCamera(width=8, height=8)
        self.assertEqual(cifs.render.view_transform(camera).cx, cifs.render.view_transform(cifs.render.Camera(width=8, height=8)).cx)


class HostileObjectTest(RaisesCheck, unittest.TestCase):
    """Arguments whose __class__, __repr__ or dict keys raise: the TypeError naming the parameter, never the
    object's own error, nor a SystemError for an exception left set ("returned a result with an exception set")."""

    def setUp(self):
        curve = cifs.nurbs.Curve(1, [0, 0, 1, 1], np.array([[0.0, 0.0], [1.0, 1.0]]))
        self.automaton = cifs.automata.knot_automaton(curve)
        self.nets = cifs.automata.initial_nets(self.automaton, curve)
        self.system = cifs.ifs.curve_bcifs(curve)

    def test_class_that_raises(self):
        class Spoof:  # isinstance() asks __class__, which raises; its repr is Python code, run afterwards
            @property
            def __class__(self):
                raise RuntimeError("no class")

            def __repr__(self):
                return "Spoof()"
        got = r"got Spoof Spoof\(\)$"
        self.check(lambda: cifs.ifs.admissible_space(Spoof()), TypeError, r"^admissible_space: system: expected a cifs\.ifs\.Bcifs, " + got)
        self.check(lambda: cifs.io.to_obj(Spoof()), TypeError, r"^to_obj: shape: expected a cifs\.nurbs\.Curve or a cifs\.nurbs\.Surface, " + got)
        self.check(lambda: cifs.ifs.for_each_leaf_to_tolerance(self.automaton, self.nets, print, homogeneous=Spoof()),
                   cifs.InvalidInput, r"^for_each_leaf_to_tolerance: homogeneous: expected True or False, " + got)

    def test_repr_that_raises(self):
        class BadRepr:
            def __repr__(self):
                raise RuntimeError("repr raised")

        class NotUtf8:
            def __repr__(self):
                return "\ud800"
        for value in (BadRepr(), NotUtf8()):
            name = type(value).__name__
            with self.subTest(name):
                got = rf"got {name} <{name} object, repr failed>$"
                self.check(lambda: cifs.ifs.admissible_space(value), TypeError, r"^admissible_space: system: expected a cifs\.ifs\.Bcifs, " + got)
                self.check(lambda: cifs.nurbs.uniform_parameters((0.0, 1.0), value), cifs.InvalidInput,
                           r"^uniform_parameters: count: expected an integer, " + got)
                # With overloads the casters refuse quietly, so that pybind11 tries the next one.
                self.check(lambda: cifs.nurbs.domain(value, 1), TypeError, r"^domain\(\): incompatible function arguments")

    def test_dict_keys_and_values(self):
        class Key(str):
            def __repr__(self):
                raise RuntimeError("key repr raised")
        # The keys' repr is read only for the key or value named, and a value refused is named by its key.
        self.check(lambda: cifs.ifs.perturb(self.system, values={Key("a"): 1.0, 3: 2.0}), TypeError,
                   r"^perturb: values\[3\]: expected a str, got int 3$")
        self.check(lambda: cifs.ifs.perturb(self.system, values={"a": "x"}), cifs.InvalidInput,
                   r"^perturb: values\['a'\]: expected a real number, got str 'x'$")

    def test_none_for_a_callback(self):
        """A callback parameter (py::function) refuses None (a std::function would take it as empty)."""
        self.check(lambda: cifs.ifs.for_each_leaf(self.automaton, self.nets, 1, None), TypeError,
                   r"^for_each_leaf: callback: expected a callable, got None$")
        self.check(lambda: cifs.ifs.for_each_leaf_to_tolerance(self.automaton, self.nets, callback=None), TypeError,
                   r"^for_each_leaf_to_tolerance: callback: expected a callable, got None$")


class ExactNumberTest(RaisesCheck, unittest.TestCase):
    """cifs.subdivision's exact numbers (Fractions) refuse other values naming the parameter (issue 33, found by
    test_hostile.py): an array raised RuntimeError "Unexpected character encountered in input.", and named_scheme
    RuntimeError "Unable to cast Python instance" for a key or value it could not read."""

    def test_wrong_types_are_type_errors_naming_the_parameter(self):
        sd = cifs.subdivision
        takes = r"expected an exact number \(a Fraction, an int, a float or a str such as '1/16'\), got "
        cases = [
            (lambda: sd.j_spline(np.arange(3.0)), r"^j_spline: s: " + takes + r"an array of dtype float64 and shape \(3,\)$"),
            (lambda: sd.j_spline(np.array(0.5)), r"^j_spline: s: " + takes + r"an array of dtype float64 and shape \(\)$"),
            (lambda: sd.corner_cutting(0.25, None), r"^corner_cutting: b: " + takes + "None$"),
            (lambda: sd.j_spline(True), r"^j_spline: s: " + takes + "bool True$"),
            (lambda: sd.j_spline(1j), r"^j_spline: s: " + takes + r"complex 1j$"),
            (lambda: sd.from_mask([0.5, 1, [0.5]]), r"^from_mask: mask\[2\]: " + takes + r"list \[0\.5\]$"),
            (lambda: sd.from_mask([0.5, 1, None]), r"^from_mask: mask\[2\]: " + takes + "None$"),
            (lambda: sd.named_scheme("generalized-four-point", {"w": None}), r"^named_scheme: parameters\['w'\]: " + takes + "None$"),
            (lambda: sd.named_scheme("generalized-four-point", w=np.ones(2)), r"^named_scheme: w: " + takes + "an array of dtype"),
            (lambda: sd.named_scheme("four-point", [[0, 1], [1, 2]]),
             r"^named_scheme: parameters: expected a dict, got list \[\[0, 1\], \[1, 2\]\]$"),
            (lambda: sd.named_scheme("four-point", {1: 2}), r"^named_scheme: parameters\[1\]: expected a str, got int 1$"),
            (lambda: sd.make_scheme("x", [0.5, 1, 0.5], {2: 1}), r"^make_scheme: parameters\[2\]: expected a str, got int 2$"),
            (lambda: sd.Scheme("x", [0.5, 1, 0.5], {"w": b"x"}), r"^Scheme: parameters\['w'\]: " + takes + "bytes b'x'$"),
        ]
        for call, pattern in cases:
            with self.subTest(pattern=pattern):
                self.check(call, TypeError, pattern)

    def test_wrong_values_are_invalid_input_naming_the_parameter(self):
        sd = cifs.subdivision
        self.check(lambda: sd.j_spline(float("inf")), cifs.InvalidInput, r"^j_spline: s: expected a finite number, got float inf$")
        self.check(lambda: sd.from_mask([0.5, float("nan"), 0.5]), cifs.InvalidInput,
                   r"^from_mask: mask\[1\]: expected a finite number, got float nan$")
        self.check(lambda: sd.named_scheme("generalized-four-point", w=float("nan")), cifs.InvalidInput,
                   r"^named_scheme: w: expected a finite number, got float nan$")
        self.check(lambda: sd.difference_mask(np.zeros((2, 2)), 1), cifs.InvalidInput,
                   r"^difference_mask: a: an array of 2 dimensions; give the coefficients as a list or a 1-D array$")
        self.check(lambda: sd.power_norm(np.zeros(600), 1), cifs.InvalidInput,
                   r"^power_norm: c: 600 coefficients exceed the limit of 512$")

    def test_exact_numbers_still_convert(self):
        from fractions import Fraction
        sd = cifs.subdivision
        expected = sd.generalized_four_point(Fraction(1, 16)).mask
        for w in (Fraction(1, 16), "1/16", 0.0625, np.float64(0.0625), np.float32(0.0625)):
            self.assertEqual(sd.generalized_four_point(w).mask, expected, repr(w))
        self.assertEqual(sd.j_spline(np.int64(1)).mask, sd.j_spline(1).mask)
        self.assertEqual(sd.from_mask(np.array([1, 2, 1]) / 2).mask, [Fraction(1, 2), 1, Fraction(1, 2)])
        self.assertEqual(sd.named_scheme("generalized-four-point", {"w": Fraction(1, 16)}).mask, expected)


if __name__ == "__main__":
    unittest.main()
