# SPDX-License-Identifier: MIT
"""Hostile input for every public callable: each call either succeeds or raises an Exception.

Every function, constructor, method and property setter of every submodule is called with each
parameter in turn replaced by a hostile value (wrong types, wrong array shapes and dtypes, NaN/inf,
negative and huge integers, mismatched lists of nets), the other parameters holding plausible
values. The calls run in a child interpreter per submodule so that a crash (segfault, abort, Eigen
assert in debug builds) fails the test instead of killing the runner; a call that takes more than
a few seconds (a huge allocation or loop before validation) fails it too, and so does a MemoryError
(the child's address space is limited: the library must refuse before allocating).
"""
import os
import re
import subprocess
import sys
import tempfile
import time
import unittest

from support import SANITIZED

SUBMODULES = ("nurbs", "automata", "ifs", "subdivision", "render", "io", "verify", "experiment")
# One call longer than CALL_SECONDS is a hang; sanitized builds (the ASan runtime preloaded, see
# tests/CMakeLists.txt) run legitimate calls 10–30× slower.
CALL_SECONDS = 5 * (30 if SANITIZED else 1)
BATCH_SECONDS = 120 * (30 if SANITIZED else 1)

# Sanitized runs try these hostile values only: one of each kind (type, number, integer range, array shape
# and dtype, list of nets).
SANITIZED_VALUES = ("None", "str", "nan", "-1", "2**63", "(0, 2) array", "complex array", "mismatched nets",
                    "ragged list", "raising callback")

# Keyword defaults replaced in every call of these functions (except for the parameter under test),
# to keep the plausible calls cheap.
CHEAP = {
    "ifs.tolerance_sample": {"max_points": 4096}, "ifs.for_each_leaf_to_tolerance": {"epsilon": 0.1}, "experiment.sample": {"max_points": 4096},
    "experiment.evaluate": {"depth": 3}, "experiment.run": {"quiet": True},
    "experiment.measure_dimension": {"max_points": 4096},
    "verify.check_curve": {"depth": 3}, "verify.check_surface": {"depth": 2},
}
# Requests that are legitimate and merely long (time linear in the count, nothing allocated up front):
# for_each_leaf streams 2^depth leaves to the callback (which may raise to stop), the chaos games and
# tolerance samples accept counts up to 2^32 and beyond.
LONG = {
    ("ifs.for_each_leaf", "depth"): ("60", "10**6"),
    ("ifs.tolerance_sample", "max_points"): ("10**6", "2**31", "2**32", "2**40"),
    ("experiment.sample", "max_points"): ("10**6", "2**31", "2**32", "2**40"),
    ("experiment.measure_dimension", "max_points"): ("10**6",),
    ("render.chaos_game_histogram", "samples"): ("2**31",),
    ("render.estimate_bounds", "points"): ("2**31",),
}


# ---------------------------------------------------------------------------------------------------------
# The child: python test_robustness.py --child <submodule> <scratch folder>

def _hostile_values(np):
    """Values tried in every parameter position (label → value)."""
    nets_2 = [np.zeros((4, 2)), np.zeros((3, 3))]
    return {
        "None": None, "str": "x", "dict": {}, "empty list": [], "float 1.5": 1.5, "bool": True,
        "complex": 1j, "-1": -1, "0": 0, "60": 60, "2**31": 2**31, "2**32": 2**32, "2**40": 2**40,
        "2**63": 2**63, "10**6": 10**6, "nan": float("nan"), "inf": float("inf"),
        "1-D array": np.arange(3.0), "3-D array": np.zeros((2, 2, 2)),
        "(0, 2) array": np.zeros((0, 2)), "(3, 0) array": np.zeros((3, 0)), "(1, 1) array": np.ones((1, 1)),
        "(4, 2) array": np.ones((4, 2)), "(2, 17) array": np.ones((2, 17)),
        "nan array": np.full((4, 2), np.nan), "inf array": np.full((4, 3), np.inf),
        "object array": np.array([[None, 1], [2, 3]], dtype=object),
        "complex array": np.ones((4, 2), dtype=complex), "bool array": np.ones((4, 2), dtype=bool),
        "float index array": np.array([[0.5, 1.5]]), "negative index array": np.array([[-1, 0], [0, -5]]),
        "huge index array": np.array([[2**40, 0]]), "huge uint array": np.array([[2**63, 0]], dtype=np.uint64),
        "non-contiguous array": np.ones((8, 4))[::2, ::2], "byte-swapped array": np.ones((4, 2), dtype=">f8"),
        "mismatched nets": nets_2, "nets with None": [np.zeros((4, 2)), None],
        "nets of 3-D arrays": [np.zeros((2, 2, 2))], "nets of empty arrays": [np.zeros((0, 0))] * 3,
        "many nets": [np.ones((4, 2))] * 40, "ragged list": [[1, 2], [3]], "list of lists": [[0, 1], [1, 2]],
        "tuple pair": (0, 1), "huge tuple pair": (2**40, -1),
        "list with nan": [0.0, float("nan"), 1.0], "descending list": [3.0, 2.0, 1.0, 0.0],
        "lambda": (lambda *a, **k: None), "raising callback": _raise,
    }


def _raise(*args, **kwargs):
    raise RuntimeError("callback failure")


class _Samples:
    """Plausible arguments, by parameter name and by annotated type."""

    def __init__(self, cifs, np, scratch):
        from cifs import automata, ifs, io, nurbs, render, subdivision
        self.np = np
        self.curve = nurbs.Curve(3, [0, 0, 0, 0, 1, 3, 3, 3, 3],
                                 np.array([[0, 0], [1, 2], [2, -1], [4, 1], [5, 0]], dtype=float))
        grid = np.array([[[i, j, (i * j) % 3] for j in range(4)] for i in range(4)], dtype=float)
        self.surface = nurbs.Surface([2, 2], [[0, 0, 0, 1, 2, 2, 2], [0, 0, 0, 1, 2, 2, 2]], grid)
        self.automaton = automata.knot_automaton(self.curve)
        self.nets = automata.initial_nets(self.automaton, self.curve)
        self.tensor = automata.tensor_automaton(self.surface)
        self.volume = nurbs.Volume([1, 1, 2], [[0, 0, 0.5, 1, 1], [0, 0, 1, 1], [0, 0, 0, 1, 1, 1]],
                                   np.arange(3 * 2 * 3 * 3, dtype=float).reshape(3, 2, 3, 3) % 5)
        self.volume_automaton = automata.tensor_automaton(self.volume)
        self.system = ifs.curve_bcifs(self.curve)
        self.space = ifs.admissible_space(self.system)
        self.scheme = subdivision.four_point()
        self.camera = render.Camera(width=16, height=16)
        self.image = render.make_framebuffer(self.camera)
        self.maps = ifs.sierpinski_triangle()
        self.mesh = io.Mesh(np.zeros((4, 3)), np.array([[0, 1, 2], [1, 2, 3]]))
        self.segments = io.Segments(np.zeros((3, 2)), np.array([[0, 1], [1, 2]]))
        self.polygon = io.Polygon(np.zeros((3, 2)))
        examples = os.environ.get("CIFS_EXAMPLES_DIR")
        self.experiment = None
        if examples:
            self.experiment = io.read_experiment(os.path.join(examples, "experiments", "circle.json"))
        self.scratch = scratch
        self.by_type = {
            "int": 1, "float": 0.5, "bool": False, "str": "x", "object": np.ones((4, 2)),
            "os.PathLike": os.path.join(scratch, "out.bin"), "fractions.Fraction": 0.25,
            "function": (lambda *a, **k: None), "Iterable": [(0, 0, 0.5)], "dict": {},
            "cifs._cifs.nurbs.Curve": self.curve, "cifs._cifs.nurbs.Surface": self.surface,
            "cifs._cifs.nurbs.Volume": self.volume, "cifs._cifs.automata.VolumeAutomaton": self.volume_automaton,
            "cifs._cifs.nurbs.Half": nurbs.Half.G, "cifs._cifs.nurbs.Direction": nurbs.Direction(0),
            "cifs._cifs.automata.Automaton": self.automaton, "cifs._cifs.automata.TensorAutomaton": self.tensor,
            "cifs._cifs.ifs.Bcifs": self.system, "cifs._cifs.ifs.AdmissibleSpace": self.space,
            "cifs._cifs.ifs.AffineMap": self.maps[0], "cifs._cifs.subdivision.Scheme": self.scheme,
            "cifs._cifs.render.Camera": self.camera, "cifs._cifs.render.Image": self.image,
            "cifs._cifs.render.Bounds": render.Bounds(), "cifs._cifs.io.Mesh": self.mesh,
            "cifs._cifs.io.Segments": self.segments, "cifs._cifs.io.Experiment": self.experiment,
        }
        self.by_name = {
            "nets": self.nets, "knots": [0, 0, 0, 0, 1, 3, 3, 3, 3], "window": [0, 0, 0, 1, 1, 1],
            "degree": 3, "span": 3, "u": 0.5, "v": 0.5, "state": 0, "child": 0, "word": [0], "depth": 2,
            "color": (1, 1, 1), "segments": np.array([[0, 1]]), "triangles": np.array([[0, 1, 2]]),
            "quads": np.array([[0, 1, 2, 3]]), "patches": [[0, 0]], "maps": self.maps, "mask": [0.5, 1, 0.5],
            "P": np.ones((6, 2)), "M": np.eye(3), "L": np.eye(2) * 0.5, "A": np.eye(2), "B": np.eye(2),
            "net": np.ones((4, 2)), "homogeneous": np.ones((4, 3)), "points": np.ones((4, 2)),
            "vertices": np.ones((4, 3)), "polygon": np.ones((4, 2)), "triangle": np.eye(3)[:, :2],
            "p": np.ones(2), "row": np.ones(3), "domain": (0.0, 1.0), "us": [0.0, 0.5], "vs": [0.0, 0.5],
            "args": [0.5, 0.5, 0.5], "breakpoints": [0.0, 1.0, 2.0], "text": "{}", "expression": "1+z",
            "name": "four_point", "label": "G", "image": self.image, "camera": self.camera,
            "polylines": [np.ones((4, 2))], "density": np.ones((4, 4)), "pixels": np.zeros((2, 2, 3), np.uint8),
            "c": [1, -1], "a": [1, 2, 1], "k": 1, "L_int": 2, "edges": [(0, 0, 0.5)], "states": None,
            "values": None, "count": 4, "epsilon": 0.1, "content": "x", "path": os.path.join(scratch, "out.bin"),
        }

    def value(self, name, annotation):
        if name in self.by_name:
            return self.by_name[name]
        base = re.sub(r"^Optional\[(.*)\]$", r"\1", annotation)
        if base in self.by_type:
            return self.by_type[base]
        if base.startswith("numpy.ndarray"):
            return self.np.ones((4, 2))
        if base.startswith("List[numpy.ndarray"):
            return self.nets
        if base.startswith("List[float]"):
            return [0.0, 0.5, 1.0]
        if base.startswith("List[int"):
            return [0, 1]
        if base.startswith("List[fractions.Fraction]"):
            return [0.5, 1, 0.5]
        if base.startswith("List[cifs._cifs.ifs.AffineMap]"):
            return self.maps
        if base.startswith("tuple[int, int]") or base.startswith("Tuple[float, float]"):
            return (0, 1)
        return None


def _split_top(text):
    """Splits at commas outside brackets."""
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:].strip())
    return parts


def _instances(samples):
    """An instance of every bound class the walks call methods on, by class name."""
    import cifs  # imported where used, as in _run_child (the parent process does not load the module)
    return {
        "Curve": samples.curve, "Surface": samples.surface, "Automaton": samples.automaton.copy(),
        "TensorAutomaton": samples.tensor, "Bcifs": samples.system, "AdmissibleSpace": samples.space,
        "Volume": samples.volume, "VolumeAutomaton": samples.volume_automaton,
        "Scheme": samples.scheme, "Camera": samples.camera, "Image": samples.image.copy(),
        "ImageChannels": samples.image.copy().channels, "Mesh": samples.mesh, "Segments": samples.segments,
        "Polygon": samples.polygon, "Bounds": cifs.render.Bounds(),
        "ViewTransform": cifs.render.view_transform(samples.camera),
        "PieceBounds": cifs.ifs.PieceBounds(samples.automaton), "AffineMap": samples.maps[0],
    }


def _signatures(obj, name):
    """Each overload as a list of (name, annotation, optional, keyword_only), from the docstring."""
    doc = obj.__doc__ or ""
    result = []
    for line in doc.splitlines():
        match = re.match(r"^(?:\d+\. )?" + re.escape(name) + r"\((.*)\)( -> .*)?$", line.strip())
        if not match:
            continue
        params, keyword_only = [], False
        for part in _split_top(match.group(1)):
            if part == "*":
                keyword_only = True
                continue
            if part.startswith("*"):
                continue
            head, _, default = part.partition(" = ")
            pname, _, annotation = head.partition(": ")
            params.append((pname.strip(), annotation.strip(), bool(default), keyword_only))
        result.append(params)
    return result


def _call(fn, params, samples, override, cheap):
    """Calls fn with required parameters from samples, `cheap` keywords and `override` (index → value)."""
    args, kwargs = [], {}
    for i, (pname, annotation, optional, keyword_only) in enumerate(params):
        if i in override:
            value = override[i]
        elif pname in cheap:
            value = cheap[pname]
        elif optional:
            continue
        else:
            value = samples.value(pname, annotation)
        if keyword_only or (optional and not pname.startswith("arg")):
            kwargs[pname] = value
        elif optional:
            return  # a positional default cannot be skipped
        else:
            args.append(value)
    fn(*args, **kwargs)


def _run_child(submodule, scratch):
    import faulthandler
    import resource

    import numpy as np

    import cifs
    faulthandler.enable()
    if not SANITIZED:  # AddressSanitizer reserves terabytes
        limit = 4 << 30
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    os.chdir(scratch)
    samples = _Samples(cifs, np, scratch)
    hostile = _hostile_values(np)
    # Sanitized: one hostile value of each kind instead of all 60, still on every parameter (the memory
    # errors ASan looks for come with a kind of value; Release checks every value's message).
    values = {k: v for k, v in hostile.items() if k in SANITIZED_VALUES} if SANITIZED else hostile
    module = getattr(cifs, submodule)
    failures = []
    calls = 0
    resume = int(os.environ.get("CIFS_ROBUSTNESS_FROM", "0"))  # after a crash: the calls from number N on

    def attempt(label, thunk):
        nonlocal calls
        calls += 1
        if calls < resume:
            return
        print(calls, label, flush=True)
        faulthandler.dump_traceback_later(CALL_SECONDS, exit=True)
        start = time.monotonic()
        try:
            thunk()
        except MemoryError as error:
            failures.append(f"{label}: MemoryError (allocated before validating?) {error}")
        except Exception:
            pass
        except BaseException as error:  # noqa: B902 — SystemExit, KeyboardInterrupt from C++
            failures.append(f"{label}: {type(error).__name__}: {error}")
        finally:
            faulthandler.cancel_dump_traceback_later()
            if time.monotonic() - start > 0.5:
                print(f"SLOW {time.monotonic() - start:.1f} s", flush=True)

    def fuzz(fn, display, name, skip_self=False):
        for params in _signatures(fn, name):
            if skip_self and params and params[0][0] == "self":
                params = params[1:]
            cheap = CHEAP.get(display, {})
            attempt(f"{display} (plausible)", lambda: _call(fn, params, samples, {}, cheap))
            for i, (pname, _, _, _) in enumerate(params):
                for hname, value in values.items():
                    if hname not in LONG.get((display, pname), ()):
                        attempt(f"{display} {pname}={hname}",
                                lambda: _call(fn, params, samples, {i: value}, cheap))

    instances = _instances(samples)
    for attr in sorted(vars(module)):
        obj = getattr(module, attr)
        if attr.startswith("_") or not callable(obj):
            continue
        if not isinstance(obj, type):
            fuzz(obj, f"{submodule}.{attr}", attr)
            continue
        fuzz(obj.__init__, f"{submodule}.{attr}()", "__init__", skip_self=True)
        instance = instances.get(attr)
        if instance is None:
            continue
        for member, value in sorted(vars(obj).items()):
            if isinstance(value, property) and value.fset is not None:
                for hname, hvalue in values.items():
                    target = instance.copy() if hasattr(instance, "copy") else instance
                    attempt(f"{submodule}.{attr}.{member} = {hname}",
                            lambda t=target, m=member, v=hvalue: setattr(t, m, v))
            elif callable(value) and (not member.startswith("_") or member in ("__getitem__", "__setitem__",
                                                                              "__delitem__", "__contains__")):
                fuzz(getattr(instance, member), f"{submodule}.{attr}.{member}", member, skip_self=True)
    print(f"DONE {calls} calls", flush=True)
    for failure in failures:
        print("FAILURE", failure, flush=True)
    return 1 if failures else 0


# ---------------------------------------------------------------------------------------------------------
# The tests

# Under the sanitizers the ≈ 30 000 calls took more than 8 min on 2 cores, then 123 s with one hostile value
# of each kind for the calls that do real work (experiment.run renders an image: ~25 s each sanitized);
# now every call gets those (SANITIZED_VALUES), the Release run all 60. The failure seen under UBSan was admissible_space
# solving an empty right-hand side (Eigen binds a reference to its null first coefficient, MapBase.h:262).
class RobustnessTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        """Starts every batch at once (they are independent); the tests collect them."""
        cls.scratch = tempfile.TemporaryDirectory(prefix="cifs-robust-")
        cls.children = {}
        for name in SUBMODULES:
            folder = os.path.join(cls.scratch.name, name)
            os.mkdir(folder)
            cls.children[name] = subprocess.Popen([sys.executable, __file__, "--child", name, folder],
                                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    @classmethod
    def tearDownClass(cls):
        for child in cls.children.values():
            if child.poll() is None:
                child.kill()
                child.communicate()
        cls.scratch.cleanup()

    def _batch(self, submodule):
        child = self.children[submodule]
        try:
            stdout, stderr = child.communicate(timeout=BATCH_SECONDS)
        except subprocess.TimeoutExpired:
            child.kill()
            stdout, _ = child.communicate()
            self.fail(f"cifs.{submodule}: the batch took more than {BATCH_SECONDS} s; last call: "
                      f"{stdout.splitlines()[-1:]}")
        result = subprocess.CompletedProcess(child.args, child.returncode, stdout, stderr)
        lines = result.stdout.splitlines()
        done = [line for line in lines if line.startswith("DONE")]
        self.assertTrue(done, f"cifs.{submodule}: the child died (exit {result.returncode}) during "
                              f"{lines[-1:]}\n{result.stderr[-3000:]}")
        # UBSan reports and goes on (recoverable checks): its report is a failure too.
        reports = [line for line in result.stderr.splitlines() if "runtime error:" in line]
        self.assertEqual(reports, [], f"cifs.{submodule}: undefined behaviour")
        failures = [line for line in lines if line.startswith("FAILURE")]
        self.assertEqual(failures, [], f"cifs.{submodule}")
        self.assertEqual(result.returncode, 0, result.stderr[-3000:])


class StrictBoolTest(unittest.TestCase):
    """Every `bool` parameter refuses values that merely have a truth value (2, 0.5, None, "yes"):
    pybind11's bool caster converts anything with __bool__ unless the argument is noconvert(). Functions
    without overloads refuse them with InvalidInput naming the parameter (python/src/arguments.cpp),
    overloaded ones with pybind11's TypeError (the next overload may take the value)."""

    def test_bool_parameters(self):
        import numpy as np

        import cifs
        with tempfile.TemporaryDirectory(prefix="cifs-bools-") as scratch:
            samples = _Samples(cifs, np, scratch)
            checked = []
            for submodule in SUBMODULES:
                module = getattr(cifs, submodule)
                for attr in sorted(vars(module)):
                    fn = getattr(module, attr)
                    if attr.startswith("_") or not callable(fn) or isinstance(fn, type):
                        continue
                    for params in _signatures(fn, attr):
                        cheap = CHEAP.get(f"{submodule}.{attr}", {})
                        for i, (pname, annotation, _, _) in enumerate(params):
                            if annotation != "bool":
                                continue
                            def incompatible(value, pname=pname):
                                try:
                                    _call(fn, params, samples, {i: value}, cheap)
                                except TypeError as error:
                                    return "incompatible function arguments" in str(error)
                                except cifs.InvalidInput as error:
                                    return f": {pname}: expected True or False" in str(error)
                                except Exception:  # noqa: BLE001 — refused for another reason: converted
                                    pass
                                return False
                            # With True the other arguments convert: a refusal of 2 is the bool's.
                            if incompatible(True):
                                continue
                            checked.append(f"{submodule}.{attr}({pname})")
                            for value in (2, 0.5, None, "yes"):
                                self.assertTrue(incompatible(value), f"{checked[-1]} accepted {value!r}")
            self.assertGreater(len(checked), 15, checked)
            print(len(checked), "bool parameters checked", file=sys.stderr)


for _name in SUBMODULES:
    setattr(RobustnessTest, f"test_{_name}", lambda self, n=_name: self._batch(n))


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--child":
        sys.exit(_run_child(sys.argv[2], sys.argv[3]))
    unittest.main()
