# SPDX-License-Identifier: MIT
"""Issue 15 item 15, "Python feels like raw C++": methods on Curve and Surface (against the free functions
and a numpy de Boor written here), read-only array attributes, evaluate_grid's (nu, nv, dim), type stubs
generated in the build, and _repr_png_ (PNG bytes decoded here with zlib and struct)."""
import ast
import copy
import inspect
import os
import pickle
import re
import struct
import unittest
import zlib
from pathlib import Path

import numpy as np

import cifs
from cifs import nurbs, render
from support import EXAMPLES

KNOTS = [0, 0, 0, 0, 1, 3, 3, 3, 3]
POINTS = np.array([[0, 0], [1, 2], [2, -1], [4, 1], [5, 0]], dtype=float)
WEIGHTS = np.array([1, 2, 0.5, 1, 3])


def de_boor(degree, knots, points, u):
    """The curve point at u by de Boor's algorithm on the given (homogeneous) rows, in numpy."""
    t = np.asarray(knots, dtype=float)
    n = len(points)
    k = min(max(np.searchsorted(t, u, side="right") - 1, degree), n - 1)
    d = [np.array(points[j], dtype=float) for j in range(k - degree, k + 1)]
    for r in range(1, degree + 1):
        for j in range(degree, r - 1, -1):
            i = j + k - degree
            alpha = (u - t[i]) / (t[i + degree - r + 1] - t[i])
            d[j] = (1 - alpha) * d[j - 1] + alpha * d[j]
    return d[degree]


def rational_de_boor(degree, knots, points, weights, u):
    h = de_boor(degree, knots, np.hstack([points * weights[:, None], weights[:, None]]), u)
    return h[:-1] / h[-1]


def png_size(data):
    """(width, height, colour type) of PNG bytes, after checking the signature and inflating every row."""
    return png_pixels(data)[:3]


def png_pixels(data):
    """(width, height, colour type, the inflated rows) of PNG bytes, the signature and checksums checked."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", data[:8]
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        assert zlib.crc32(kind + body) == struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])[0]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour = header[:4]
    channels = {2: 3, 6: 4, 0: 1, 4: 2}[colour]
    rows = zlib.decompress(idat)
    assert len(rows) == height * (1 + width * channels * depth // 8)
    return width, height, colour, rows


class CurveMethodsTest(unittest.TestCase):
    def setUp(self):
        self.curve = nurbs.Curve(3, KNOTS, POINTS)
        self.rational = nurbs.Curve(3, KNOTS, POINTS, weights=WEIGHTS)
        self.closed = nurbs.uniform_bspline(POINTS, 2, True)

    def test_evaluate_scalar_and_array(self):
        us = np.linspace(0, 3, 13)
        for c, expected in ((self.curve, [de_boor(3, KNOTS, POINTS, u) for u in us]),
                            (self.rational, [rational_de_boor(3, KNOTS, POINTS, WEIGHTS, u) for u in us])):
            np.testing.assert_allclose(c.evaluate(us), expected, atol=1e-12)
            np.testing.assert_array_equal(c.evaluate(us), nurbs.evaluate(c, us))
            np.testing.assert_array_equal(c.evaluate(list(us)), nurbs.evaluate(c, us))
            for u in (0, 1.25, np.float64(2.5), np.float32(3), np.array(0.5)):
                point = c.evaluate(u)
                self.assertEqual(point.shape, (2,))
                np.testing.assert_array_equal(point, nurbs.evaluate(c, float(u)))
        self.assertEqual(self.curve.evaluate([]).shape, (0, 2))
        with self.assertRaises(cifs.InvalidInput) as e:
            self.curve.evaluate(4.0)
        self.assertIn("outside the domain", str(e.exception))
        with self.assertRaises(cifs.InvalidInput) as e:
            self.curve.evaluate(np.zeros((2, 2)))
        self.assertEqual(str(e.exception), "Curve.evaluate: u: expected a number or a 1-D array, got shape (2, 2)")
        with self.assertRaises(cifs.InvalidInput):
            self.curve.evaluate("half")

    def test_insert(self):
        once = self.curve.insert(1.5)
        self.assertEqual(once, nurbs.insert_knot(self.curve, 1.5))
        self.assertEqual(list(once.knots), [0, 0, 0, 0, 1, 1.5, 3, 3, 3, 3])
        self.assertEqual(list(self.curve.knots), KNOTS)  # unchanged
        twice = self.rational.insert(knot=2.0, times=2)
        self.assertEqual(twice, nurbs.insert_knot(self.rational, 2.0, 2))
        us = np.linspace(0, 3, 9)
        np.testing.assert_allclose(twice.evaluate(us), [rational_de_boor(3, KNOTS, POINTS, WEIGHTS, u) for u in us],
                                   atol=1e-12)
        with self.assertRaises(cifs.InvalidInput):
            self.curve.insert(7.0)

    def test_properties(self):
        c = self.rational
        self.assertEqual((c.degree, c.dimension, c.domain, c.rational, c.closed), (3, 2, (0.0, 3.0), True, False))
        np.testing.assert_allclose(c.points, POINTS, atol=1e-15)  # Cartesian: divided by w
        np.testing.assert_allclose(c.P[:, :2], POINTS * WEIGHTS[:, None])  # the homogeneous rows stay
        np.testing.assert_array_equal(c.weights, WEIGHTS)
        np.testing.assert_array_equal(c.points, nurbs.cartesian_points(c))
        self.assertEqual(self.closed.points.shape, (5, 2))  # distinct points, not the repeated ones
        self.assertEqual(self.closed.P.shape, (7, 2))
        self.assertEqual(self.closed.domain, nurbs.domain(self.closed))

    def test_equality_pickle_copy(self):
        self.assertEqual(self.curve, nurbs.Curve(3, KNOTS, POINTS))
        self.assertNotEqual(self.curve, self.rational)
        self.assertNotEqual(self.curve, nurbs.Curve(3, KNOTS, POINTS + [0, 1e-12]))
        self.assertNotEqual(self.curve, "curve")
        self.assertEqual(hash(self.curve), hash(nurbs.Curve(3, KNOTS, POINTS)))
        self.assertEqual(len({self.curve, nurbs.Curve(3, KNOTS, POINTS), self.rational}), 2)
        negative_zeros = nurbs.Curve(3, KNOTS, np.where(POINTS == 0, -0.0, POINTS))
        self.assertEqual((negative_zeros, hash(negative_zeros)), (self.curve, hash(self.curve)))  # -0.0 == 0.0
        for c in (self.curve, self.rational, self.closed):
            back = pickle.loads(pickle.dumps(c))
            self.assertEqual(back, c)
            np.testing.assert_array_equal(back.P, c.P)
            self.assertEqual(copy.deepcopy(c), c)
        with self.assertRaises(cifs.InvalidInput):  # a pickled state is validated again
            nurbs.Curve.__new__(nurbs.Curve).__setstate__((3, [0, 1], np.zeros((1, 2)), False, False))

    def test_repr(self):
        self.assertEqual(repr(self.curve),
                         "Curve(degree=3, knots=[0, 0, 0, 0, 1, 3, 3, 3, 3], points=5, dimension=2, domain=(0, 3))")
        long = nurbs.uniform_bspline(np.random.default_rng(1).random((20, 3)), 3, False)
        self.assertIn("knots=[0, 0, 0, 0, …, 17, 17, 17, 17], points=20, dimension=3", repr(long))
        self.assertIn("rational", repr(self.rational))
        self.assertIn("closed", repr(self.closed))


class SurfaceMethodsTest(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(3)
        self.net = rng.random((4, 5, 3))
        self.knots = ([0, 0, 0, 1, 2, 2, 2], [0, 0, 0, 0, 1, 2, 2, 2, 2])
        self.surface = nurbs.Surface((2, 3), self.knots, self.net)
        self.weights = rng.random((4, 5)) + 0.5
        self.rational = nurbs.Surface((2, 3), self.knots, self.net, weights=self.weights)

    def tensor_de_boor(self, surface_net, weights, u, v):
        """S(u, v) by de Boor along v for every row, then along u, on homogeneous rows."""
        h = np.concatenate([surface_net * weights[..., None], weights[..., None]], axis=2)
        rows = np.array([de_boor(3, self.knots[1], h[i], v) for i in range(h.shape[0])])
        p = de_boor(2, self.knots[0], rows, u)
        return p[:-1] / p[-1]

    def test_evaluate_and_grid(self):
        us, vs = np.linspace(0, 2, 5), np.linspace(0, 2, 4)
        for s, w in ((self.surface, np.ones((4, 5))), (self.rational, self.weights)):
            grid = s.evaluate_grid(us, vs)
            self.assertEqual(grid.shape, (5, 4, 3))
            np.testing.assert_array_equal(grid, nurbs.evaluate_grid(s, us, vs))
            expected = np.array([[self.tensor_de_boor(self.net, w, u, v) for v in vs] for u in us])
            np.testing.assert_allclose(grid, expected, atol=1e-12)
            np.testing.assert_array_equal(s.evaluate(0.5, 1.5), nurbs.evaluate(s, 0.5, 1.5))
            pairs = s.evaluate(us[:4], vs)
            self.assertEqual(pairs.shape, (4, 3))
            for i in range(4):
                np.testing.assert_array_equal(pairs[i], nurbs.evaluate(s, us[i], vs[i]))
        # (nu, nv, dim) is what Surface takes: a grid of a surface is the net of a bilinear one.
        flat = nurbs.Surface((1, 1), ([0, 0, 1, 2, 3, 4, 4], [0, 0, 1, 2, 3, 3]), grid)
        np.testing.assert_array_equal(flat.points, grid)
        with self.assertRaises(cifs.InvalidInput) as e:
            self.surface.evaluate([0, 1], [0])
        self.assertIn("u and v hold 2 and 1 parameters", str(e.exception))

    def test_insert_properties_equality_pickle(self):
        s = self.rational
        once = s.insert(nurbs.Direction.v, 0.5)
        self.assertEqual(once, nurbs.insert_knot(s, nurbs.Direction.v, 0.5))
        self.assertEqual(once.count, (4, 6))
        np.testing.assert_allclose(once.evaluate(0.3, 1.1), s.evaluate(0.3, 1.1), atol=1e-13)
        np.testing.assert_allclose(s.points, self.net, atol=1e-15)
        np.testing.assert_array_equal(s.weights, self.weights)
        self.assertEqual((s.dimension, s.domain), (3, ((0.0, 2.0), (0.0, 2.0))))
        self.assertEqual(pickle.loads(pickle.dumps(s)), s)
        self.assertEqual(hash(pickle.loads(pickle.dumps(s))), hash(s))
        self.assertNotEqual(s, self.surface)
        self.assertIn("Surface(degree=(2, 3), knots=([0, 0, 0, 1, 2, 2, 2], [0, 0, 0, 0, 1, 2, 2, 2, 2]), "
                      "count=(4, 5), dimension=3", repr(s))


class ReadOnlyAttributesTest(unittest.TestCase):
    def test_writes_into_attribute_arrays_raise(self):
        c = nurbs.Curve(3, KNOTS, POINTS)
        s = nurbs.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), np.zeros((2, 2, 3)))
        for array in (c.P, c.knots, c.points, c.weights, s.P, s.knots[0], s.knots[1], s.points, s.weights):
            self.assertFalse(array.flags.writeable)
            with self.assertRaises(ValueError):
                array[(0,) * array.ndim] = 99
        self.assertEqual(c.P[0, 0], 0)
        image = render.Image(2, 2)
        image.set_channel("R", np.ones((2, 2)))
        with self.assertRaises(ValueError):
            image.channels["R"][0, 0] = 5
        camera = render.Camera(eye=[1, 2, 3])
        with self.assertRaises(ValueError):
            camera.eye[0] = 9
        camera.eye = [4, 5, 6]  # setters still work
        self.assertEqual(list(camera.eye), [4, 5, 6])
        # Results of functions and methods are the caller's own arrays.
        self.assertTrue(nurbs.evaluate(c, [0.5]).flags.writeable and c.evaluate([0.5]).flags.writeable)
        self.assertTrue(c.points.copy().flags.writeable)

    def test_every_property_of_every_bound_type_follows_the_rule(self):
        count = 0
        for name in ("nurbs", "automata", "ifs", "subdivision", "render", "io", "verify", "experiment"):
            for cls in vars(getattr(cifs, name)).values():
                if not isinstance(cls, type):
                    continue
                for attribute, value in vars(cls).items():
                    if type(value) is property:
                        count += 1
                        self.assertTrue(hasattr(value.fget, "__wrapped__"), f"{name}.{cls.__name__}.{attribute}")
        self.assertGreater(count, 200)


class StubsTest(unittest.TestCase):
    FOLDER = Path(cifs.__file__).parent

    def test_stubs_parse_and_name_every_public_object(self):
        self.assertTrue((self.FOLDER / "py.typed").exists())
        for name in ("nurbs", "automata", "ifs", "subdivision", "render", "io", "verify", "experiment"):
            tree = ast.parse((self.FOLDER / f"{name}.pyi").read_text(encoding="utf-8"))
            top = {node.name: node for node in tree.body if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
            module = getattr(cifs, name)
            public = [n for n, obj in vars(module).items()
                      if not n.startswith("_") and (callable(obj) or isinstance(obj, type))]
            self.assertGreaterEqual(len(public), 3)
            for n in public:
                self.assertIn(n, top, f"cifs.{name}.{n} missing from {name}.pyi")
                if isinstance(getattr(module, n), type):
                    members = {m.name for m in top[n].body if isinstance(m, ast.FunctionDef)}
                    for m, value in vars(getattr(module, n)).items():
                        if type(value) is property or (not m.startswith("_") and inspect.isroutine(value)):
                            self.assertIn(m, members, f"cifs.{name}.{n}.{m} missing from {name}.pyi")
        init = ast.parse((self.FOLDER / "__init__.pyi").read_text(encoding="utf-8"))
        names = {n.name for n in init.body if isinstance(n, ast.ClassDef)}
        self.assertEqual(names, {"InvalidInput", "IoError"})

    def test_stubs_type_every_parameter_and_result(self):
        """No `Any` (issue 32: `limit(mesh: Any) -> Any`, then `__init__(self, *args, **kwargs) -> Any` on the
        classes that functions return, enums' names, setters' values and the notebook previews)."""
        for name in ("nurbs", "automata", "ifs", "subdivision", "render", "io", "verify", "experiment"):
            text = (self.FOLDER / f"{name}.pyi").read_text(encoding="utf-8")
            self.assertEqual(re.findall(r".*\bAny\b.*", text), [], f"{name}.pyi")
        automata_text = (self.FOLDER / "automata.pyi").read_text(encoding="utf-8")
        state = automata_text[automata_text.index("class State:"):].split("\nclass ")[0]
        self.assertNotIn("__init__", state)  # State() is refused: automata make their states
        with self.assertRaisesRegex(TypeError, "No constructor defined"):
            cifs.automata.State()
        ifs_text = (self.FOLDER / "ifs.pyi").read_text(encoding="utf-8")
        self.assertIn("    class Kind:\n", ifs_text)  # Factor.Kind, the type of Factor.kind
        self.assertIn("def file(self) -> cifs.io.BcifsFile: ...", ifs_text)
        render_text = (self.FOLDER / "render.pyi").read_text(encoding="utf-8")
        self.assertIn("def eye(self, value: object) -> None: ...", render_text)

    def test_signatures_use_python_types(self):
        text = (self.FOLDER / "nurbs.pyi").read_text(encoding="utf-8")
        self.assertIn("def insert(self, knot: float, times: int = ...) -> Curve: ...", text)
        self.assertIn("def evaluate(curve: Curve, u: float) -> numpy.typing.NDArray[numpy.float64]: ...", text)
        ifs_text = (self.FOLDER / "ifs.pyi").read_text(encoding="utf-8")
        self.assertIn("automaton: cifs.automata.Automaton", ifs_text)  # other modules' types by their public path
        self.assertNotIn("cifs._cifs", text + ifs_text)


class ReprPngTest(unittest.TestCase):
    def test_image(self):
        camera = render.frame(POINTS, width=64, height=48)
        image = render.make_framebuffer(camera)
        render.render_polylines(image, camera, [POINTS], width=2)
        data = image._repr_png_()
        self.assertEqual(png_size(data)[:2], (64, 48))
        self.assertIsNone(render.Image()._repr_png_())

    def test_shapes(self):
        curve = nurbs.Curve(3, KNOTS, POINTS, weights=WEIGHTS)
        self.assertEqual(png_size(curve._repr_png_())[:2], (320, 240))
        self.assertEqual(png_size(nurbs.uniform_bspline(POINTS, 3, True)._repr_png_())[:2], (320, 240))
        x, y = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 4), indexing="ij")
        net = np.stack([x, y, np.sin(3 * x) * y], axis=2)
        surface = nurbs.Surface((2, 2), ([0, 0, 0, 1, 2, 2, 2], [0, 0, 0, 1, 2, 2, 2]), net)
        self.assertEqual(png_size(surface._repr_png_())[:2], (320, 240))
        self.assertIsNone(nurbs.Curve(1, [0, 0, 1, 1], np.array([[0.0], [1.0]]))._repr_png_())  # 1-D: none


    def test_mesh_any_polygons_and_holes(self):
        # A cube whose top is a pentagon (an extra vertex on one top edge): every face drawn as its fan.
        vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                             [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1], [0.5, 0, 1]], dtype=float)
        faces = [[0, 3, 2, 1], [4, 8, 5, 6, 7], [0, 1, 5, 8, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
        mesh = cifs.io.Mesh(vertices, faces=faces)
        width, height, _, pixels = png_pixels(mesh._repr_png_())
        self.assertEqual((width, height), (320, 240))
        # The same picture as the faces' fans given as triangles (the pentagon 4 8 5 6 7: three of them),
        # shaded with the polygons' vertex normals.
        fans = [[f[0], f[i], f[i + 1]] for f in faces for i in range(1, len(f) - 1)]
        camera = render.frame(vertices, width=320, height=240)
        image = render.make_framebuffer(camera)
        normals = cifs.io.vertex_normals(mesh)
        render.render_mesh(image, camera, vertices, triangles=np.array(fans), normals=normals)
        self.assertEqual(png_pixels(image._repr_png_())[3], pixels)
        # A hole is left out: another picture, that of the fans of the other faces.
        holed = cifs.io.Mesh(vertices, faces=faces, tags=cifs.io.MeshTags(holes=[1]))
        image = render.make_framebuffer(camera)
        render.render_mesh(image, camera, vertices, triangles=np.array(fans[:2] + fans[5:]),
                           normals=cifs.io.vertex_normals(holed))
        self.assertEqual(png_pixels(holed._repr_png_())[3], png_pixels(image._repr_png_())[3])
        self.assertNotEqual(png_pixels(holed._repr_png_())[3], pixels)
        with self.assertRaisesRegex(cifs.InvalidInput, "a Mesh carries its faces"):
            render.render_mesh(image, camera, mesh, triangles=np.array(fans))

    def test_automata_wrapping_one_draw_it(self):
        tet = cifs.subdivision.loop(cifs.io.read_mesh(str(EXAMPLES / "meshes" / "tetrahedron.obj")), 1)
        s = cifs.subdivision.surface_automaton(tet, scheme="loop")
        self.assertEqual(s._repr_svg_(), s.automaton._repr_svg_())
        self.assertTrue(s._repr_svg_().lstrip().startswith("<"))
        x, y = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 4), indexing="ij")
        surface = nurbs.Surface((2, 2), ([0, 0, 0, 1, 2, 2, 2], [0, 0, 0, 1, 2, 2, 2]),
                                np.stack([x, y, x * y], axis=2))
        t = cifs.automata.tensor_automaton(surface)
        self.assertEqual(t._repr_svg_(), t.product._repr_svg_())


if __name__ == "__main__":
    unittest.main()
