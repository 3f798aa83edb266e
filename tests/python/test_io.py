# SPDX-License-Identifier: MIT
"""cifs.io, cifs.verify and cifs.experiment against the `cifs` command line on the same files
(check reports, rendered files, error lines) and against round trips and identities."""
import json
import struct
import unittest

import numpy as np

import cifs
from cifs import experiment, io, nurbs, verify
from support import EXAMPLES, ScratchTestCase, assert_close, cli, cli_json

SHAPES = EXAMPLES / "shapes"
EXPERIMENTS = EXAMPLES / "experiments"


def cli_error(*args):
    """The CLI's one-line error without its "cifs: " prefix (exit status 2)."""
    result = cli(*args, check=False)
    assert result.returncode == 2, result
    assert result.stdout == "", result.stdout
    line = result.stderr.strip()
    assert line.startswith("cifs: ") and "\n" not in line, line
    return line.removeprefix("cifs: ")


class ShapeFileTest(ScratchTestCase):
    def test_read_and_parse_agree(self):
        for name in ("cubic", "circle", "closed_cubic", "saddle"):
            path = SHAPES / f"{name}.json"
            read = io.read_shape(path)
            parsed = io.parse_shape_json(io.read_file(path), str(path))
            self.assertIs(type(read), type(parsed))
            np.testing.assert_array_equal(read.P, parsed.P)
        self.assertIsInstance(io.read_shape(SHAPES / "saddle.json"), nurbs.Surface)
        self.assertIsInstance(io.read_shape(SHAPES / "cubic.json"), nurbs.Curve)

    def test_json_and_obj_round_trips(self):
        for name in ("cubic", "circle", "closed_cubic", "wave", "saddle"):
            with self.subTest(shape=name):
                shape = io.read_shape(SHAPES / f"{name}.json")
                text = io.to_json(shape)
                again = io.parse_shape_json(text)
                self.assertEqual(io.to_json(again), text)
                np.testing.assert_array_equal(again.P, shape.P)
                obj = io.to_obj(shape)
                shapes = io.parse_obj(obj)
                self.assertEqual(len(shapes), 1)
                self.assertEqual(type(shapes[0]), type(shape))
                if isinstance(shape, nurbs.Curve):
                    us = nurbs.uniform_parameters(nurbs.domain(shape), 21)
                    dim = nurbs.dimension(shape)  # OBJ vertices are 3-D: planar curves come back with z = 0
                    back = nurbs.evaluate(shapes[0], us)
                    assert_close(self, back[:, :dim], nurbs.evaluate(shape, us), what="OBJ")
                    np.testing.assert_array_equal(back[:, dim:], 0)
                path = self.scratch / "shape.obj"
                io.write_file_atomically(path, obj)
                np.testing.assert_array_equal(io.read_shape(path).P, shapes[0].P)

    def test_step_and_iges_through_opencascade(self):
        # The package plugs cifs::occt into io when built with it; without it STEP is one clear refusal.
        shape = io.read_shape(SHAPES / "hills.json")
        try:
            io.write(self.scratch / "hills.step", shape)
        except cifs.InvalidInput as e:
            self.assertIn("built without OpenCASCADE", str(e))
            self.assertFalse((self.scratch / "hills.step").exists())
            self.skipTest("cifs built without OpenCASCADE")
        us = nurbs.uniform_parameters(nurbs.domain(shape, nurbs.Direction.u), 7)
        for name in ("hills.step", "hills.igs"):
            with self.subTest(file=name):
                io.write(self.scratch / name, shape)
                back = io.read_shape(self.scratch / name)
                for u in us:
                    assert_close(self, nurbs.evaluate(back, u, 1.5), nurbs.evaluate(shape, u, 1.5), what=name)

    def test_insert_output_is_to_json(self):
        c = io.read_shape(SHAPES / "cubic.json")
        self.assertEqual(cli("insert", SHAPES / "cubic.json", "--knot", 1.5).stdout,
                         io.to_json(nurbs.insert_knot(c, 1.5)))

    def test_bad_shape_files_fail_like_the_cli(self):
        cases = {
            "knots.json": '{"curve": {"degree": 1, "knots": [0, 1, 0.5, 2], "points": [[0, 0], [1, 1]]}}',
            "weights.json": '{"curve": {"degree": 1, "knots": [0, 0, 1, 1], "points": [[0, 0], [1, 1]],'
                            ' "weights": [1, -2]}}',
            "degree.json": '{"curve": {"degree": 0, "knots": [0, 1], "points": [[0, 0]]}}',
            "member.json": '{"curve": {"degree": 1, "knots": [0, 0, 1, 1], "points": [[0, 0], [1, 1]], "x": 1}}',
            "net.json": '{"surface": {"degree": [1, 1], "knots": [[0, 0, 1, 1], [0, 0, 1, 1]],'
                        ' "points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0]]]}}',
        }
        for name, text in cases.items():
            path = self.scratch / name
            path.write_text(text)
            with self.subTest(file=name), self.assertRaises(cifs.InvalidInput) as caught:
                io.read_shape(path)
            self.assertEqual(str(caught.exception), cli_error("info", path))
            self.assertTrue(str(caught.exception).startswith(f"{path}: "))
        syntax = self.scratch / "syntax.json"
        syntax.write_text('{"curve": ')
        with self.assertRaises(cifs.IoError) as caught:
            io.read_shape(syntax)
        self.assertEqual(str(caught.exception), cli_error("info", syntax))
        missing = self.scratch / "missing.json"
        with self.assertRaises(cifs.IoError) as caught:
            io.read_shape(missing)
        self.assertEqual(str(caught.exception), cli_error("info", missing))
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.parse_shape_json('{"curve": {"degree": 0, "knots": [0, 1], "points": [[0, 0]]}}', "inline")
        self.assertTrue(str(caught.exception).startswith("inline: curve.degree"), str(caught.exception))

    def test_files(self):
        path = self.scratch / "sub" / "file.bin"
        with self.assertRaises(cifs.IoError):
            io.write_file_atomically(path, "x")  # no such folder
        path = self.scratch / "file.bin"
        data = bytes(range(256))
        io.write_file_atomically(path, data)
        self.assertEqual(path.read_bytes(), data)
        self.assertEqual(io.read_file(path, binary=True), data)
        io.write_file_atomically(path, "héllo")
        self.assertEqual(io.read_file(path), "héllo")
        self.assertEqual(path.read_bytes(), "héllo".encode())
        with self.assertRaises(cifs.IoError) as caught:
            io.read_file(self.scratch)
        self.assertEqual(str(caught.exception), f"{self.scratch}: is a directory")


class PolygonTest(ScratchTestCase):
    def test_read_round_trip(self):
        p = io.read_polygon(SHAPES / "bone.json")
        self.assertTrue(p.closed)
        self.assertEqual(p.points.shape, (18, 2))
        np.testing.assert_array_equal(p.points[0], [-3, 0.4])
        text = io.to_json(p)
        again = io.parse_polygon_json(text, "again")
        np.testing.assert_array_equal(again.points, p.points)
        self.assertEqual(io.to_json(again), text)
        made = io.Polygon(p.points, closed=True)
        self.assertEqual(io.to_json(made), text)
        self.assertIn("Polygon(points=18", repr(made))

    def test_bad_polygons(self):
        for points, message in ((np.zeros((0, 2)), "points: no points"),
                                (np.zeros((2, 17)), "points: 17 coordinates, expected 1 to 16"),
                                (np.array([[0, 1], [np.nan, 0]]), "points[1]: coordinate is not finite"),
                                (np.zeros(3), "points: expected a 2-D array (n, dim), got shape (3,)")):
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                io.Polygon(points)
            self.assertEqual(str(caught.exception), message)
        bad = self.scratch / "bad.json"
        bad.write_text('{"polygon": {"points": []}}')
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.read_polygon(bad)
        self.assertEqual(str(caught.exception), f"{bad}: polygon.points: no points")


class GeometryTest(ScratchTestCase):
    def test_polylines_match_cli_attractor_files(self):
        for name, closed in (("cubic", False), ("closed_cubic", True)):
            path = SHAPES / f"{name}.json"
            points = np.array(cli_json("attractor", path, "--depth", 4)["points"])
            for fmt, writer in (("obj", io.polyline_obj), ("svg", io.polyline_svg)):
                self.assertEqual(writer(points, closed), cli("attractor", path, "--depth", 4, "--format", fmt).stdout)
            # polyline_svg is segments_svg on polyline_segments.
            self.assertEqual(io.polyline_svg(points, closed, 300, 2.0),
                             io.segments_svg(io.polyline_segments(points[:, :2], closed), width=300, stroke=2.0))

    def test_segments(self):
        points = np.array([[0, 0], [1, 0], [1, 1]], float)
        s = io.polyline_segments(points, closed=True, state=7)
        np.testing.assert_array_equal(s.segments, [[0, 1], [1, 2], [2, 0]])
        np.testing.assert_array_equal(s.states, [7, 7, 7])
        np.testing.assert_array_equal(s.vertices, points)
        made = io.Segments(points, [[0, 1], [1, 2], [2, 0]], states=[7, 7, 7])
        self.assertEqual(io.segments_obj(made), io.segments_obj(s))
        obj = io.segments_obj(made)
        self.assertEqual(obj.count("\nl ") + obj.startswith("l "), 3)
        self.assertIn("l 3 1", obj)
        ply = io.segments_ply(made)
        self.assertIsInstance(ply, str)
        self.assertIn("element edge 3", ply)
        binary = io.segments_ply(made, io.PlyFormat.binary_little_endian)
        self.assertIsInstance(binary, bytes)
        header, body = binary.split(b"end_header\n", 1)
        self.assertEqual(len(body), 3 * 3 * 8 + 3 * (4 + 4 + 4))  # xyz doubles; two ints and a state per edge
        self.assertEqual(struct.unpack_from("<3d", body, 8 * 3), (1.0, 0.0, 0.0))
        self.assertIn('stroke="#ff0000"', io.segments_svg(made, color="#ff0000"))
        self.assertIn("Segments(vertices=3, segments=3)", repr(made))

    def test_mesh(self):
        square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
        mesh = io.Mesh(square, triangles=[[1, 4, 2]], quads=[[0, 1, 2, 3]], states=[1, 2])
        normals = io.vertex_normals(mesh)
        np.testing.assert_array_equal(normals[:4], np.tile([0, 0, 1.0], (4, 1)))
        np.testing.assert_array_equal(mesh.quads, [[0, 1, 2, 3]])
        np.testing.assert_array_equal(mesh.states, [1, 2])
        self.assertEqual(mesh.normals.size, 0)
        with_normals = io.Mesh(square, triangles=[[1, 4, 2]], quads=[[0, 1, 2, 3]], normals=normals)
        obj = io.mesh_obj(with_normals)
        self.assertEqual(obj.count("\nvn ") + obj.startswith("vn "), 5)
        self.assertIn("f 1//1 2//2 3//3 4//4", obj)
        self.assertIn("element face 2", io.mesh_ply(mesh))
        binary = io.mesh_ply(mesh, io.PlyFormat.binary_little_endian)
        body = binary.split(b"end_header\n", 1)[1]
        vertices = np.frombuffer(body[:5 * 24], dtype="<f8").reshape(5, 3)
        np.testing.assert_array_equal(vertices, square)
        self.assertIn("Mesh(vertices=5, triangles=1, quads=1)", repr(mesh))

    def test_bad_geometry(self):
        v = np.zeros((3, 3))
        cases = [
            (lambda: io.Mesh(v, triangles=[[0, 1, 5]]), "Mesh: triangles[0][2] = 5 is out of range (3 vertices)"),
            (lambda: io.Mesh(v, triangles=[[0, 1]]),
             "Mesh: triangles: expected an integer array of shape (n, 3), got shape (1, 2)"),
            (lambda: io.Mesh(np.zeros((3, 2))), "Mesh: mesh vertices have 2 columns, expected 3"),
            (lambda: io.Mesh(v, triangles=[[0, 1, 2]], states=[1, 2]), "Mesh: 2 states for 1 faces"),
            (lambda: io.Segments(v, [[0, 3]]), "Segments: segments[0][1] = 3 is out of range (3 vertices)"),
            (lambda: io.polyline_obj(np.zeros((2, 4))), None),
            (lambda: io.segments_svg(io.Segments(v, [[0, 1]]), width=2),
             "the SVG width 2 is outside [16, 100000]"),
        ]
        for call, message in cases:
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                call()
            if message is not None:
                self.assertEqual(str(caught.exception), message)


def pentagon_and_apex():
    """A regular pentagon at z = 0.5 and an apex above it (6 vertices)."""
    k = np.arange(5)
    ring = np.column_stack([np.cos(k * 1.25), np.sin(k * 1.25), np.full(5, 0.5)])
    return np.vstack([ring, [[0, 0, 2]]])


class MeshFileTest(ScratchTestCase):
    def test_faces_three_ways(self):
        v = pentagon_and_apex()
        lists = io.Mesh(v, faces=[[0, 1, 2, 3, 4], [0, 1, 5]], states=[3, 9])
        arrays = io.Mesh(v, face_offsets=[0, 5, 8], face_vertices=[0, 1, 2, 3, 4, 0, 1, 5], states=[3, 9])
        for m in (lists, arrays):
            np.testing.assert_array_equal(m.face_offsets, [0, 5, 8])
            np.testing.assert_array_equal(m.face_vertices, [0, 1, 2, 3, 4, 0, 1, 5])
            self.assertEqual(m.faces, [[0, 1, 2, 3, 4], [0, 1, 5]])
            np.testing.assert_array_equal(m.triangles, [[0, 1, 5]])
            self.assertEqual(m.quads.shape, (0, 4))
            np.testing.assert_array_equal(m.states, [3, 9])
        self.assertIn("Mesh(vertices=6, triangles=1, quads=0, polygons=1)", repr(lists))
        tables = io.Mesh(v, triangles=[[0, 1, 5]], quads=[[0, 1, 2, 3]])  # triangles first
        np.testing.assert_array_equal(tables.face_offsets, [0, 3, 7])
        self.assertEqual(tables.faces, [[0, 1, 5], [0, 1, 2, 3]])
        # The pentagon's normal at its centre-less ring points up: its vertices see +z from it alone.
        flat = io.vertex_normals(io.Mesh(v, faces=[[0, 1, 2, 3, 4]]))
        np.testing.assert_allclose(flat[:5], np.tile([0, 0, 1.0], (5, 1)), atol=1e-15)
        cases = [
            (lambda: io.Mesh(v, triangles=[[0, 1, 5]], faces=[[0, 1, 2]]),
             "Mesh: give triangles and quads, or faces, or face_offsets and face_vertices"),
            (lambda: io.Mesh(v, face_offsets=[0, 3]), "Mesh: face_offsets and face_vertices go together"),
            (lambda: io.Mesh(v, faces=[[0, 1]]), "Mesh: face 0 has 2 vertices, a face needs at least 3"),
            (lambda: io.Mesh(v, faces=[[0, 1, 2], [0, 1, 9]]),
             "Mesh: face 1 corner 2 = 9 is out of range (6 vertices)"),
            (lambda: io.Mesh(v, face_offsets=[0, 3], face_vertices=[0, 1]),
             "Mesh: the face offsets end at 3 but 2 corners are given"),
            (lambda: io.Mesh(v, faces=[[0, 1, 2.5]]), "Mesh: faces[0]: expected an array of integers, got dtype float64"),
        ]
        for call, message in cases:
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                call()
            self.assertEqual(str(caught.exception), message)

    def test_files_read_back(self):
        v = pentagon_and_apex()
        mesh = io.Mesh(v, faces=[[0, 1, 2, 3, 4], [0, 1, 5], [1, 2, 5]], states=[1, 2, 4000000000])
        for name in ("m.obj", "m.ply"):
            path = self.scratch / name
            io.write(path, mesh)
            back = io.read_mesh(path)
            np.testing.assert_array_equal(back.vertices, v)  # bit for bit
            self.assertEqual(back.faces, mesh.faces)
        np.testing.assert_array_equal(io.read_mesh(self.scratch / "m.ply").states, mesh.states)
        for fmt in (io.PlyFormat.ascii, io.PlyFormat.binary_little_endian, io.PlyFormat.binary_big_endian):
            data = io.mesh_ply(mesh, fmt)
            back = io.parse_mesh_ply(data, "m.ply")
            np.testing.assert_array_equal(back.vertices, v)
            np.testing.assert_array_equal(back.face_vertices, mesh.face_vertices)
        self.assertIn(b"format binary_big_endian 1.0", io.mesh_ply(mesh, io.PlyFormat.binary_big_endian))
        # A file written by hand: float32 coordinates, a colour, short indices, a uint count.
        big = (b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
               b"property float z\nproperty uchar red\nelement face 1\nproperty list uint short vertex_indices\n"
               b"end_header\n" + struct.pack(">3fB3fB3fB", 0, 0, 0, 1, 2.5, 0, 0, 2, 3, 1, 0.25, 5) +
               struct.pack(">I3h", 3, 0, 1, 2))
        hand = io.parse_mesh_ply(big, "hand.ply")
        np.testing.assert_array_equal(hand.vertices, [[0, 0, 0], [2.5, 0, 0], [3, 1, 0.25]])
        self.assertEqual(hand.faces, [[0, 1, 2]])
        obj = io.parse_mesh_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1 -1/1\n", "hand.obj")
        self.assertEqual(obj.faces, [[0, 1, 2, 3]])
        self.assertEqual(obj.face_varying[0].indices.tolist(), [0, 0, 0, 0])

    def test_mesh_tags_and_uvs(self):
        # The gallery's creased box: creases, a corner, a hole and UVs from OBJ tags and vt.
        box = io.read_mesh(EXAMPLES / "meshes" / "creased_box.obj")
        tags = box.tags
        self.assertEqual(len(tags.creases), 36)
        self.assertIsInstance(tags.creases[0], io.EdgeSharpness)
        self.assertEqual(tags.crease_edges.shape, (36, 2))
        self.assertEqual(sorted(set(tags.crease_sharpness.tolist())), [1.0, 2.0, 10.0])
        self.assertEqual(tags.corner_vertices.tolist(), [tags.corners[0].vertex])
        self.assertEqual(tags.corner_sharpness.tolist(), [3.0])
        self.assertEqual(tags.holes.tolist(), [13])
        self.assertEqual((tags.boundary, tags.crease_method, tags.triangles, tags.fvar_interpolation),
                         ("edge", "uniform", "catmark", "all"))
        self.assertEqual(len(box.face_varying), 1)
        uv = box.face_varying[0]
        self.assertEqual((uv.name, uv.values.shape, uv.indices.shape), ("uv", (96, 2), (216,)))
        # Built in Python, written and read back bit for bit.
        v = pentagon_and_apex()
        made = io.Mesh(v, faces=[[0, 1, 2, 3, 4], [0, 1, 5], [1, 2, 5]],
                       tags=io.MeshTags(creases=[io.EdgeSharpness(0, 1, 2.5)], corners=[io.VertexSharpness(5, 1 / 3)],
                                        holes=[2], boundary="corner", crease_method="chaikin"),
                       face_varying=[io.FaceVaryingChannel("uv", [[0, 0], [1, 0], [0.5, 1 / 7]],
                                                           [0, 1, 2, 0, 1, 1, 2, 0, 2, 2, 1])])
        path = self.scratch / "tagged.obj"
        io.write(path, made)
        back = io.read_mesh(path)
        self.assertEqual(io.mesh_obj(back), io.mesh_obj(made))
        self.assertEqual((back.tags.creases[0].a, back.tags.creases[0].b, back.tags.creases[0].sharpness), (0, 1, 2.5))
        self.assertEqual(back.tags.corners[0].sharpness, 1 / 3)
        self.assertEqual((back.tags.boundary, back.tags.crease_method), ("corner", "chaikin"))
        np.testing.assert_array_equal(back.face_varying[0].values, made.face_varying[0].values)
        # Bad tags: one line naming what is wrong.
        with self.assertRaises(cifs.InvalidInput):
            io.EdgeSharpness(0, 1, -1)
        with self.assertRaises(cifs.InvalidInput):
            io.MeshTags(boundary="sharp")
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.Mesh(v, faces=[[0, 1, 2]], tags=io.MeshTags(holes=[0]))
        self.assertIn("every face is a hole", str(caught.exception))
        # Unknown tags: a warning, or InvalidInput with strict.
        edits = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt vertexedit 1/1/1 0 0.5 add\n"
        self.assertEqual(io.parse_mesh_obj(edits, "e.obj").faces, [[0, 1, 2]])
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.parse_mesh_obj(edits, "e.obj", strict=True)
        self.assertTrue(str(caught.exception).startswith("e.obj: line 5: t vertexedit: unknown tag"))

    def test_bad_mesh_files(self):
        gltf = self.scratch / "m.gltf"
        with self.assertRaises(cifs.IoError) as caught:
            io.read_mesh(gltf)
        self.assertEqual(str(caught.exception), f"{gltf}: a mesh is read from .obj, .ply, .stl or .off")
        mesh = io.Mesh(pentagon_and_apex(), faces=[[0, 1, 2, 3, 4]])
        cut = self.scratch / "cut.ply"
        cut.write_bytes(io.mesh_ply(mesh, io.PlyFormat.binary_little_endian)[:-2])
        with self.assertRaises(cifs.IoError) as caught:
            io.read_mesh(cut)
        self.assertEqual(str(caught.exception), f"{cut}: the data ends in face 0 of 1 (truncated file)")
        bad = self.scratch / "bad.obj"
        bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.read_mesh(bad)
        self.assertEqual(str(caught.exception),
                         f"{bad}: line 4: vertex index 4 is out of range: 3 vertices are defined before this line")


class DispatchTest(ScratchTestCase):
    def test_format_table(self):
        self.assertEqual([(f.name, f.extension, f.read, f.write) for f in io.formats(io.Content.mesh)],
                         [("obj", ".obj", True, True), ("ply", ".ply", True, True), ("stl", ".stl", True, True),
                          ("off", ".off", True, True), ("vtp", ".vtp", False, True)])
        self.assertEqual([f.name for f in io.formats(io.Content.automaton)], ["json", "svg", "dot"])
        self.assertEqual([f.name for f in io.formats(io.Content.segments) if f.write], ["obj", "ply", "svg"])
        self.assertTrue([f for f in io.formats(io.Content.mesh) if f.name == "ply"][0].binary)

    def test_write_and_encode(self):
        mesh = io.Mesh(pentagon_and_apex(), faces=[[0, 1, 2, 3, 4], [0, 1, 5]])
        self.assertIsInstance(io.encode(mesh, "ply"), bytes)
        self.assertEqual(io.encode(mesh, "obj"), io.mesh_obj(mesh))
        self.assertEqual(io.encode(mesh, "ply"), io.mesh_ply(mesh, io.PlyFormat.binary_little_endian))
        points = np.array([[0, 0], [1, 0], [1, 1.5]])
        polygon = io.Polygon(points, closed=True)
        self.assertEqual(io.encode(polygon, "svg"), io.polyline_svg(points, True))
        self.assertEqual(io.encode(polygon, "json"), io.to_json(polygon))
        path = self.scratch / "p.obj"
        io.write(path, polygon)
        self.assertEqual(path.read_text(), io.polyline_obj(points, True))
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.write(self.scratch / "m.svg", mesh)
        self.assertEqual(str(caught.exception), f"{self.scratch / 'm.svg'}: a mesh is written as .obj, .ply, .stl, .off or .vtp")
        self.assertFalse((self.scratch / "m.svg").exists())
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.encode(mesh, "gltf")
        self.assertEqual(str(caught.exception), "format 'gltf': expected obj, ply, stl, off or vtp")

    def test_automaton_files_are_the_clis(self):
        path = SHAPES / "wave.json"
        text = cli("automaton", path, "--format", "json").stdout
        a = io.parse_automaton_json(text, "cli")
        self.assertEqual(cifs.automata.to_json(a), text)
        self.assertEqual(io.encode(a, "dot"), cli("automaton", path, "--format", "dot").stdout)
        self.assertEqual(io.encode(a, "svg"), cli("automaton", path, "--format", "svg").stdout)
        file = self.scratch / "a.json"
        io.write(file, a)
        self.assertEqual(cifs.automata.to_json(io.read_automaton(file)), text)
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.parse_automaton_json('{"states": [{"id": 1, "size": 2}], "transitions": [], "initial": []}', "x.json")
        self.assertEqual(str(caught.exception), "x.json: states[0].id: expected 0 (states are listed by id, from 0)")


class VerifyTest(unittest.TestCase):
    def test_check_curve_matches_cli_check(self):
        for name in ("cubic", "circle", "closed_cubic"):
            path = SHAPES / f"{name}.json"
            with self.subTest(shape=name):
                expected = cli_json("check", path, "--json", "--depth", 6)
                r = verify.check_curve(io.read_shape(path), depth=6)
                self.assertTrue(r.passed)
                self.assertEqual((r.depth, r.tolerance), (6, 1e-12))
                self.assertEqual(len(r.segments), len(expected["segments"]))
                for s, e in zip(r.segments, expected["segments"]):
                    self.assertEqual(s.segment, e["segment"])
                    self.assertEqual([s.start, s.end], e["interval"])
                    self.assertEqual([s.nets.max_abs, s.nets.max_rel], [e["nets"]["max_abs"], e["nets"]["max_rel"]])
                    self.assertEqual([s.points.max_abs, s.points.max_rel],
                                     [e["points"]["max_abs"], e["points"]["max_rel"]])
                self.assertEqual(r.points.max_rel, expected["points"]["max_rel"])
                self.assertEqual(r.nets.max_abs, expected["nets"]["max_abs"])

    def test_check_surface_matches_cli_check(self):
        path = SHAPES / "saddle.json"
        expected = cli_json("check", path, "--json", "--depth", 3)
        r = verify.check_surface(io.read_shape(path), depth=3, tolerance=1e-12)
        self.assertTrue(r.passed)
        self.assertEqual(len(r.patches), len(expected["patches"]))
        for p, e in zip(r.patches, expected["patches"]):
            self.assertEqual(list(p.patch), e["patch"])
            self.assertEqual([list(p.u), list(p.v)], e["interval"])
            self.assertEqual(p.nets.max_rel, e["nets"]["max_rel"])
            self.assertEqual(p.points.max_abs, e["points"]["max_abs"])
        self.assertEqual(r.nets.max_rel, expected["nets"]["max_rel"])
        self.assertIn("SurfaceCheckReport(depth=3", repr(r))

    def test_a_zero_tolerance_can_fail(self):
        r = verify.check_curve(io.read_shape(SHAPES / "circle.json"), depth=4, tolerance=1e-300)
        self.assertFalse(r.passed)
        self.assertIn("failed", repr(r))
        self.assertEqual(cli("check", SHAPES / "circle.json", "--depth", 4, "--relative-tolerance", 1e-300,
                             check=False).returncode, 1)

    def test_bad_depth(self):
        c = io.read_shape(SHAPES / "cubic.json")
        with self.assertRaises(cifs.InvalidInput) as caught:
            verify.check_curve(c, depth=31)
        self.assertEqual(str(caught.exception), cli_error("check", SHAPES / "cubic.json", "--depth", 31))
        with self.assertRaises(cifs.InvalidInput) as caught:
            verify.check_surface(io.read_shape(SHAPES / "saddle.json"), tolerance=0.0)
        self.assertEqual(str(caught.exception), cli_error("check", SHAPES / "saddle.json", "--relative-tolerance", 0))


class ExperimentTest(ScratchTestCase):
    def test_experiment_fields(self):
        wave = io.read_experiment(EXPERIMENTS / "wave.json")
        self.assertEqual(wave.name, "wave")
        self.assertTrue(wave.description.startswith("A non-uniform rational cubic"))
        self.assertEqual(wave.source, "curve")
        self.assertEqual(io.to_json(wave.shape), io.to_json(io.read_shape(SHAPES / "wave.json")))
        self.assertIsNone(wave.automaton)
        self.assertIsNone(wave.ifs)
        self.assertEqual((wave.mode, wave.depth), ("depth", 8))
        self.assertEqual(wave.size, (1200, 600))
        self.assertEqual({k: str(v) for k, v in wave.outputs.items()},
                         {"exr": "wave.exr", "png": "wave.png", "svg": "wave.svg",
                          "automaton_svg": "wave.automaton.svg", "automaton_dot": "wave.automaton.dot"})
        koch = io.read_experiment(EXPERIMENTS / "koch.json")
        self.assertEqual((koch.source, koch.ifs, koch.shape), ("ifs", "koch", None))
        tree = io.read_experiment(EXPERIMENTS / "tree.json")
        self.assertEqual(tree.source, "automaton")
        self.assertEqual(tree.automaton.resolve(), (EXAMPLES / "automata" / "tree.json").resolve())
        self.assertTrue(tree.automaton.is_absolute())
        self.assertTrue(tree.perturbed)
        parsed = io.parse_experiment(io.read_file(EXPERIMENTS / "wave.json"), "wave.json", EXPERIMENTS)
        self.assertEqual(io.to_json(parsed.shape), io.to_json(wave.shape))
        maps = io.parse_experiment('{"ifs": {"maps": [[0.5, 0, 0, 0.5, 0, 0, 1]]}}', "x.json")
        np.testing.assert_array_equal(maps.ifs_maps, [[0.5, 0, 0, 0.5, 0, 0, 1]])
        self.assertIn("Experiment(name='wave'", repr(wave))
        torus = io.read_experiment(EXPERIMENTS / "subdivision_torus.json")
        self.assertEqual((torus.source, torus.shape, torus.ifs, torus.automaton), ("mesh", None, None, None))
        self.assertEqual(torus.mesh.resolve(), (EXAMPLES / "meshes" / "torus.obj").resolve())
        self.assertIsNone(wave.mesh)
        # The files each experiment reads (outputs onto them are refused).
        self.assertEqual([p.resolve() for p in tree.inputs],
                         [(EXPERIMENTS / "tree.json").resolve(), (EXAMPLES / "automata" / "tree.json").resolve()])
        self.assertEqual([p.resolve() for p in torus.inputs],
                         [(EXPERIMENTS / "subdivision_torus.json").resolve(), (EXAMPLES / "meshes" / "torus.obj").resolve()])
        self.assertEqual(maps.inputs, [])
        junction = io.read_experiment(EXPERIMENTS / "junction_fractal.json")
        self.assertEqual((junction.source, junction.shape, junction.mesh), ("junction", None, None))
        self.assertEqual([p.name for p in junction.inputs],
                         ["junction_fractal.json", "junction_nurbs.json", "junction_fractal.json"])

    def test_run_writes_what_cli_render_writes(self):
        for name in ("wave", "koch"):
            with self.subTest(experiment=name):
                path = EXPERIMENTS / f"{name}.json"
                ours, theirs = self.scratch / f"py-{name}", self.scratch / f"cli-{name}"
                report = experiment.run(io.read_experiment(path), out_dir=ours, quiet=True, threads=1)
                out = cli("render", path, "--out-dir", theirs, "--threads", 1, "--quiet").stdout
                self.assertEqual(report.summary.replace(str(ours), str(theirs)), out)
                names = sorted(p.name for p in report.written)
                self.assertEqual(names, sorted(p.name for p in theirs.iterdir()))
                for written in report.written:
                    self.assertEqual(written.read_bytes(), (theirs / written.name).read_bytes(), written.name)
                self.assertEqual(report.depth, 8)
        png = self.scratch / "preview.png"
        report = experiment.run(io.read_experiment(EXPERIMENTS / "koch.json"), out_dir=self.scratch / "o",
                                png=png, exr=self.scratch / "x.exr", threads=1)
        self.assertIn(png, report.written)
        self.assertEqual(png.read_bytes(), (self.scratch / "py-koch" / "koch.png").read_bytes())

    def test_evaluate_is_the_attractor(self):
        wave = io.read_experiment(EXPERIMENTS / "wave.json")
        e = experiment.evaluate(wave, 5)
        self.assertEqual((e.depth, e.kind, e.rational), (5, "NURBS curve", True))
        expected = np.array(cli_json("attractor", SHAPES / "wave.json", "--depth", 5)["points"])
        np.testing.assert_array_equal(e.points, expected)
        # The attractor at the dyadic parameters is the curve (Cox–de Boor).
        c = wave.shape
        start, end = nurbs.domain(c)
        breaks = nurbs.breakpoints(c.knots, c.degree)
        us = np.concatenate([np.linspace(a, b, 33)[:-1] for a, b in zip(breaks[:-1], breaks[1:])] + [[end]])
        assert_close(self, e.points, nurbs.evaluate(c, us), what="attractor vs Cox–de Boor")
        self.assertEqual(len(e.nets), nurbs.segment_count(c))  # one initial net per segment
        self.assertEqual(e.nets[0].shape[1], nurbs.dimension(c) + 1)
        self.assertEqual(experiment.evaluate(wave).depth, 8)
        koch = experiment.evaluate(io.read_experiment(EXPERIMENTS / "koch.json"), 3)
        self.assertEqual(koch.points.shape, (4**3 + 1, 2))
        self.assertGreater(koch.resolution, 0)
        if hasattr(cifs.automata, "Automaton"):
            self.assertIsInstance(e.automaton, cifs.automata.Automaton)
        if hasattr(cifs.ifs, "AffineMap"):
            self.assertEqual(len(koch.maps), 4)

    def test_bad_experiments(self):
        bad = self.scratch / "bad.json"
        bad.write_text('{"ifs": "koch", "evaluation": {"depth": -3}}')
        with self.assertRaises(cifs.InvalidInput) as caught:
            io.read_experiment(bad)
        self.assertEqual(str(caught.exception), cli_error("render", bad))
        svg = self.scratch / "svg.json"
        svg.write_text('{"shape": "%s", "outputs": {"svg": "s.svg"}}' % (SHAPES / "saddle.json"))
        with self.assertRaises(cifs.InvalidInput) as caught:
            experiment.run(io.read_experiment(svg), out_dir=self.scratch / "out")
        self.assertEqual(str(caught.exception), cli_error("render", svg, "--out-dir", self.scratch / "out"))
        self.assertFalse((self.scratch / "out" / "s.svg").exists())
        koch = io.read_experiment(EXPERIMENTS / "koch.json")
        for call, message in ((lambda: experiment.evaluate(koch, -1), "the depth -1 is negative; give a depth ≥ 0"),
                              (lambda: experiment.run(koch, threads=-2), "threads: -2 is negative"),
                              (lambda: experiment.run(koch, max_bytes=-1), "max_bytes: -1 is negative")):
            with self.subTest(message=message), self.assertRaises(cifs.InvalidInput) as caught:
                call()
            self.assertEqual(str(caught.exception), message)
        with self.assertRaises(cifs.InvalidInput) as caught:
            experiment.run(koch, out_dir=self.scratch / "small", max_bytes=1000)
        self.assertIn("above the limit", str(caught.exception))
        self.assertFalse((self.scratch / "small" / "koch.png").exists())


if __name__ == "__main__":
    unittest.main()
