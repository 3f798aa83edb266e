# SPDX-License-Identifier: MIT
"""cifs.render: cameras, images, OpenEXR and PNG files, rasterisers, chaos densities, point IFS.

Results are checked against the `cifs render` command line on the same experiment files (EXR and PNG
written by the CLI, re-computed here), against the formulas of docs/rendering.md, and between routes
that must agree exactly (a view transform and project, polylines and their segments, thread counts).
"""
import json
import math
import unittest

import numpy as np

import cifs
from support import EXAMPLES, ScratchTestCase, assert_close, cli

R = cifs.render
HAS_AFFINE = hasattr(cifs.ifs, "AffineMap") and hasattr(cifs.ifs, "sierpinski_triangle")
HAS_AFFINE_AUTOMATON = HAS_AFFINE and hasattr(cifs.ifs, "affine_automaton")


def pixel_camera(width, height, projection=None):
    """An orthographic top view with one world unit per pixel: pixel (i, j) covers world
    [i, i+1] × [height − j − 1, height − j] (y up in the world, down in the image)."""
    return R.Camera(eye=(width / 2, height / 2, 10), target=(width / 2, height / 2, 0), up=(0, 1, 0),
                    ortho_height=height, width=width, height=height)


def classic_bounds(maps, width, height, margin=0.05):
    """The window of the pixels `cifs render` bins a classic IFS into (experiment/src/run.cpp): the
    top view that frame() gives the maps' estimated bounds."""
    b = R.estimate_bounds(maps, 0.0)
    camera = R.frame(np.array([[b.x_min, b.y_min], [b.x_max, b.y_max]]), width=width, height=height, margin=margin)
    view = R.view_transform(camera)
    half_w, half_h = 0.5 * width / view.scale, 0.5 * height / view.scale
    cx, cy = view.eye[0], view.eye[1]
    return R.Bounds(x_min=cx - half_w, x_max=cx + half_w, y_min=cy - half_h, y_max=cy + half_h)


class CameraTest(unittest.TestCase):
    def test_defaults_are_the_cpp_defaults(self):
        c = R.Camera()
        self.assertEqual(c.projection, R.Projection.orthographic)
        self.assertEqual(list(c.eye), [0, 0, 1])
        self.assertEqual(list(c.target), [0, 0, 0])
        self.assertEqual(list(c.up), [0, 1, 0])
        self.assertEqual((c.fov_y, c.ortho_height, c.near, c.width, c.height), (40, 2, 1e-3, 512, 512))
        self.assertIn("orthographic", repr(c))

    def test_properties_are_copies_and_settable(self):
        c = R.Camera(width=10, height=20, eye=[1, 2, 3])
        eye = c.eye
        with self.assertRaises(ValueError):  # read-only: a write into the copy would be lost
            eye[0] = 99
        self.assertEqual(list(c.eye), [1, 2, 3])
        c.eye = np.array([4, 5, 6])
        c.width = 30
        c.projection = R.Projection.perspective
        self.assertEqual((list(c.eye), c.width, c.height, c.projection), ([4, 5, 6], 30, 20, R.Projection.perspective))

    def test_orthographic_projection_by_hand(self):
        # s = H / ortho_height = 25 px per unit; f = −z, r = +x, u = +y.
        c = R.Camera(eye=(0, 0, 5), target=(0, 0, 0), ortho_height=4, width=200, height=100)
        p = R.project(c, (1, 0.5, 2))
        self.assertEqual((p.x, p.y, p.depth), (125.0, 37.5, 3.0))

    def test_perspective_projection_by_hand(self):
        # fov 90°: F = (H/2)/tan 45° = 50; f = +y, r = +x, u = +z; depth of (1, 0, 2) is 5.
        c = R.Camera(projection=R.Projection.perspective, eye=(0, -5, 0), target=(0, 0, 0), up=(0, 0, 1), fov_y=90,
                     width=100, height=100)
        p = R.project(c, (1, 0, 2))
        assert_close(self, [p.x, p.y, p.depth], [60, 30, 5], what="perspective projection")
        v = R.view_transform(c)
        self.assertTrue(v.perspective)
        self.assertTrue(v.visible_depth(c.near) and not v.visible_depth(c.near / 2))

    def test_view_transform_is_project_and_orthonormal(self):
        rng = np.random.default_rng(3)
        c = R.Camera(projection=R.Projection.perspective, eye=(3, -2, 1.5), target=(0.2, 0.1, -0.3),
                     up=(0.1, 0.2, 1), fov_y=50, width=320, height=240)
        v = R.view_transform(c)
        basis = np.array([v.right, v.up, v.forward])
        assert_close(self, basis @ basis.T, np.eye(3), what="camera basis")
        assert_close(self, v.forward, (c.target - c.eye) / np.linalg.norm(c.target - c.eye), what="forward")
        self.assertEqual((v.cx, v.cy), (160, 120))
        assert_close(self, v.scale, 120 / math.tan(math.radians(25)), what="focal length")
        for p in rng.normal(size=(20, 3)):
            a, b = v.project(p), R.project(c, p)
            self.assertEqual((a.x, a.y, a.depth), (b.x, b.y, b.depth))
            assert_close(self, a.depth, np.dot(p - c.eye, v.forward), what="depth")
            # x, y from the documented formula, computed here.
            d = p - c.eye
            assert_close(self, [a.x, a.y], [160 + v.scale * d @ v.right / a.depth, 120 - v.scale * d @ v.up / a.depth],
                         what="pixel coordinates")

    def test_frame_planar_fills_the_tighter_direction(self):
        points = np.array([[0, 0], [4, 1], [2, 3], [-1, 2]], dtype=float)
        c = R.frame(points, width=200, height=100, margin=0.1)
        self.assertEqual((c.projection, c.width, c.height), (R.Projection.orthographic, 200, 100))
        p = np.array([[R.project(c, (x, y, 0)).x, R.project(c, (x, y, 0)).y] for x, y in points])
        self.assertTrue(np.all(p[:, 0] >= 20 - 1e-9) and np.all(p[:, 0] <= 180 + 1e-9))
        self.assertTrue(np.all(p[:, 1] >= 10 - 1e-9) and np.all(p[:, 1] <= 90 + 1e-9))
        # The box (5 by 3) is limited by the height: y spans exactly the usable 80 pixels, centred.
        assert_close(self, [p[:, 1].min(), p[:, 1].max()], [10, 90], what="framed rows")
        assert_close(self, (p[:, 0].min() + p[:, 0].max()) / 2, 100, what="framed centre")

    def test_frame_3d_shows_every_point(self):
        rng = np.random.default_rng(5)
        points = rng.normal(size=(50, 3))
        for perspective in (True, False):
            c = R.frame(points, width=160, height=120, perspective=perspective, view_direction=(1, 1, 1), up=(0, 0, 1))
            self.assertEqual(c.projection, R.Projection.perspective if perspective else R.Projection.orthographic)
            for q in points:
                p = R.project(c, q)
                self.assertTrue(0 <= p.x <= 160 and 0 <= p.y <= 120, (perspective, p))

    def test_bad_cameras(self):
        for kwargs, message in [
            (dict(eye=(1, 2)), "camera: eye: expected 3 numbers, got shape (2,)"),
            (dict(up="up"), "camera: up: expected an array of numbers, got dtype <U2"),
            (dict(width=-1), "camera: width = -1 is negative"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                R.Camera(**kwargs)
            self.assertEqual(str(e.exception), message)
        for camera, message in [
            (R.Camera(width=0), "the image size 0 by 512 is empty"),
            (R.Camera(eye=(0, 0, 0)), "the camera's eye and target coincide; move the eye away from the target"),
            (R.Camera(up=(0, 0, 2)), "the camera's up (0, 0, 2) is parallel to the viewing direction from eye to target; give an up vector across it"),
            (R.Camera(ortho_height=0), "the camera's orthographic height must be a positive finite number"),
            (R.Camera(projection=R.Projection.perspective, fov_y=180),
             "the camera's field of view 180 degrees is outside (0, 180)"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                R.view_transform(camera)
            self.assertEqual(str(e.exception), message)
        with self.assertRaises(cifs.InvalidInput) as e:
            R.project(R.Camera(), (1, 2, 3, 4))
        self.assertEqual(str(e.exception), "project: point: expected 3 numbers, got shape (4,)")
        for points, message in [
            (np.zeros((0, 2)), "there are no points to frame in the image"),
            (np.zeros((3, 4)), "the points to frame have 4 coordinates, expected 2 or 3"),
            (np.zeros(3), "frame: points: expected a 2-D array (n, dim), got shape (3,)"),
            ([["a", "b"]], "frame: points: expected an array of numbers, got dtype <U1"),
            (np.array([[0, 0], [1, np.nan]]), "a point to frame in the image is not finite"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                R.frame(points)
            self.assertEqual(str(e.exception), message)
        with self.assertRaises(cifs.InvalidInput) as e:
            R.frame(np.eye(2), margin=0.5)
        self.assertEqual(str(e.exception), "the camera margin 0.5 is outside [0, 0.45]")


class ImageTest(ScratchTestCase):
    def sample_image(self):
        rng = np.random.default_rng(11)
        image = R.Image(7, 5)
        for name in ("R", "G", "B", "A", "density", "N.x", "custom name"):
            image.set_channel(name, rng.normal(size=(5, 7)).astype(np.float32))
        z = rng.random((5, 7), dtype=np.float32)
        z[0, 0], z[0, 1], z[0, 2], z[0, 3] = np.inf, -0.0, np.float32(1e-45), np.finfo(np.float32).max
        image.set_channel("Z", z)
        state = rng.integers(0, 2**32, size=(5, 7), dtype=np.uint64)
        state[1, 1], state[1, 2] = 0, R.kNoState
        image.state = state
        image.attributes = {"experiment": "test", "seed": "42", "note": "ünïcode ✓"}
        return image

    def test_channels_view_is_dict_like(self):
        image = R.Image(3, 2)
        self.assertEqual((image.width, image.height, len(image.channels), image.state), (3, 2, 0, None))
        image.set_channel("R", [[1, 2, 3], [4, 5, 6]])
        image.channels["A"] = np.ones((2, 3))
        self.assertEqual(image.channels.keys(), ["A", "R"])
        self.assertEqual(list(image.channels), ["A", "R"])
        self.assertTrue("R" in image.channels and "G" not in image.channels)
        r = image.channels["R"]
        self.assertEqual((r.dtype, r.shape), (np.float32, (2, 3)))
        with self.assertRaises(ValueError):  # a read-only copy: the write would be lost
            r[0, 0] = 100
        self.assertFalse(dict(image.channels.items())["R"].flags.writeable)
        self.assertEqual(image.channels["R"][0, 0], 1)
        self.assertEqual(dict(image.channels.items())["R"].tolist(), [[1, 2, 3], [4, 5, 6]])
        del image.channels["A"]
        image.remove_channel("R")
        self.assertEqual(len(image.channels), 0)
        self.assertIn("3 by 2", repr(image))

    def test_image_errors(self):
        image = R.Image(3, 2)
        cases = [
            (lambda: image.set_channel("R", np.zeros((3, 2))),
             'set_channel: channels["R"]: shape (3, 2), expected (height, width) = (2, 3)'),
            (lambda: image.set_channel("R", np.zeros(6)),
             'set_channel: channels["R"]: shape (6,), expected (height, width) = (2, 3)'),
            (lambda: image.set_channel("R", np.full((2, 3), "x")),
             'set_channel: channels["R"]: expected an array of numbers, got dtype <U1'),
            (lambda: image.set_channel("state", np.zeros((2, 3))),
             'set_channel: channels["state"]: the name is reserved for the UINT state channel (Image.state)'),
            (lambda: image.set_channel("", np.zeros((2, 3))), "set_channel: a channel has an empty name"),
            (lambda: image.channels["nope"], "channels: the image has no channel nope"),
            (lambda: image.remove_channel("nope"), "channels: the image has no channel nope"),
            (lambda: setattr(image, "state", np.full((2, 3), -1)),
             "Image.state: value -1 is outside 0 … 4294967295"),
            (lambda: setattr(image, "state", np.zeros((2, 3))),
             "Image.state: expected an array of integers, got dtype float64"),
            (lambda: R.Image(-2, 3), "Image: width = -2 is negative"),
        ]
        for call, message in cases:
            with self.assertRaises(cifs.InvalidInput) as e:
                call()
            self.assertEqual(str(e.exception), message)

    def test_exr_round_trip_is_exact(self):
        image = self.sample_image()
        path = self.scratch / "round.exr"
        R.write_exr(path, image)
        back = R.read_exr(str(path))
        self.assertEqual((back.width, back.height), (7, 5))
        self.assertEqual(back.channels.keys(), image.channels.keys())
        for name, values in image.channels.items():
            self.assertTrue(np.array_equal(back.channels[name].view(np.uint32), values.view(np.uint32)), name)
        self.assertEqual(back.state.dtype, np.uint32)
        self.assertTrue(np.array_equal(back.state, image.state))
        self.assertEqual(back.attributes, image.attributes)
        copy = back.copy()
        copy.remove_channel("R")
        self.assertIn("R", back.channels)

    def test_exr_errors(self):
        for image, message in [
            (R.Image(), "the EXR image is empty (0 by 0)"),
            (R.Image(2, 2), "the EXR image has no channel"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                R.write_exr(self.scratch / "x.exr", image)
            self.assertEqual(str(e.exception), message)
        image = self.sample_image()
        image.attributes = {"channels": "x"}
        with self.assertRaises(cifs.InvalidInput) as e:
            R.write_exr(self.scratch / "x.exr", image)
        self.assertEqual(str(e.exception),
                         'the EXR attribute name "channels" is empty or reserved by OpenEXR')
        missing = self.scratch / "missing.exr"
        with self.assertRaises(cifs.IoError) as e:
            R.read_exr(missing)
        self.assertEqual(str(e.exception), f"{missing}: no such file")
        (self.scratch / "file").write_text("not a folder")
        target = self.scratch / "file" / "x.exr"
        with self.assertRaises(cifs.IoError) as e:
            R.write_exr(target, self.sample_image())
        # Refused before OpenEXR is called: the folder is a file.
        self.assertEqual(str(e.exception), f"{target}: {self.scratch / 'file'} is not a folder")

    def test_read_exr_refuses_more_pixels_than_max_bytes(self):
        path = self.scratch / "one.exr"
        image = R.Image(3, 2)
        image.channels["Y"] = np.ones((2, 3), dtype=np.float32)
        R.write_exr(path, image)
        self.assertEqual(R.read_exr(path, max_bytes=24).width, 3)  # 6 pixels, 1 channel of 4 bytes
        with self.assertRaises(cifs.IoError) as e:
            R.read_exr(path, max_bytes=23)
        self.assertEqual(str(e.exception), f"{path}: the image is 3 × 2 pixels of 1 channel, 2.4e-08 GB, "
                                           "more than the 2.3e-08 GB an input may hold")
        with self.assertRaises(cifs.IoError) as e:
            R.read_png(self.write_rgba(), max_bytes=15)
        self.assertIn("the image is 2 × 2 pixels, 1.6e-08 GB", str(e.exception))

    def write_rgba(self):
        path = self.scratch / "p.png"
        R.write_png(path, np.zeros((2, 2, 4), dtype=np.uint8))
        return path

    def test_unwritable_exr_message_is_the_clis(self):
        folder = self.scratch / "out.exr"
        folder.mkdir()
        result = cli("render", EXAMPLES / "experiments" / "sierpinski.json", "-o", folder, "--out-dir",
                     self.scratch, "--quiet", check=False)
        self.assertEqual(result.returncode, 2)
        with self.assertRaises(cifs.IoError) as e:
            R.write_exr(folder, self.sample_image())
        self.assertEqual(f"cifs: {e.exception}", result.stderr.strip())
        self.assertEqual(str(e.exception), f"{folder}: is a directory")


class PngTest(ScratchTestCase):
    def test_round_trip(self):
        rng = np.random.default_rng(2)
        for channels in (3, 4):
            pixels = rng.integers(0, 256, size=(9, 13, channels), dtype=np.uint8)
            path = self.scratch / f"p{channels}.png"
            R.write_png(path, pixels)
            fmt = R.PixelFormat.rgb8 if channels == 3 else R.PixelFormat.rgba8
            back = R.read_png(path, fmt)
            self.assertEqual(back.dtype, np.uint8)
            self.assertTrue(np.array_equal(back, pixels))
        rgba = R.read_png(self.scratch / "p3.png")  # RGB read as RGBA: opaque
        self.assertEqual(rgba.shape, (9, 13, 4))
        self.assertTrue(np.all(rgba[..., 3] == 255))
        self.assertTrue(np.array_equal(rgba[..., :3], R.read_png(self.scratch / "p3.png", R.PixelFormat.rgb8)))

    def test_png_errors(self):
        for pixels, message in [
            (np.zeros((2, 2, 3)), "write_png: pixels must be a uint8 array, got dtype float64"),
            (np.zeros((2, 2, 3), dtype=np.int32), "write_png: pixels must be a uint8 array, got dtype int32"),
            (np.zeros((2, 2), dtype=np.uint8), "write_png: pixels must have shape (height, width, 3|4), got (2, 2)"),
            (np.zeros((2, 2, 2), dtype=np.uint8),
             "write_png: pixels must have shape (height, width, 3|4), got (2, 2, 2)"),
            (np.zeros((0, 2, 3), dtype=np.uint8), "the PNG image is empty"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                R.write_png(self.scratch / "x.png", pixels)
            self.assertEqual(str(e.exception), message)
        folder = self.scratch / "dir.png"
        folder.mkdir()
        with self.assertRaises(cifs.IoError) as e:
            R.write_png(folder, np.zeros((2, 2, 3), dtype=np.uint8))
        self.assertTrue(str(e.exception).startswith(str(folder)), str(e.exception))
        with self.assertRaises(cifs.IoError) as e:
            R.read_png(self.scratch / "none.png")
        self.assertEqual(str(e.exception), f"{self.scratch / 'none.png'}: no such file")

    def test_tone_map_endpoints_and_formula(self):
        ramp = [(0, 0, 0), (20, 30, 110), (235, 120, 30), (255, 255, 255)]
        density = np.array([[0, 1000, -5, np.nan], [np.inf, 10, 100, 999]], dtype=np.float32)
        rgb = R.tone_map_log_density(density)
        self.assertEqual((rgb.shape, rgb.dtype), ((2, 4, 3), np.uint8))
        self.assertEqual(rgb[0, 0].tolist(), list(ramp[0]))  # 0, negative, NaN, inf: the first stop
        self.assertEqual(rgb[0, 1].tolist(), list(ramp[-1]))  # the maximum: the last stop
        for cell in ((0, 2), (0, 3), (1, 0)):
            self.assertEqual(rgb[cell].tolist(), list(ramp[0]))
        # The documented formula, in numpy: v = log1p(d)/log1p(max), v^(1/gamma), linear ramp.
        for gamma, top in ((1, 0), (2.2, 0), (1, 50)):
            out = R.tone_map_log_density(density, gamma=gamma, max_density=top)
            d = np.where(np.isfinite(density) & (density > 0), density, 0).astype(float)
            v = np.clip(np.log1p(d) / np.log1p(top or d.max()), 0, 1) ** (1 / gamma)
            s = v * (len(ramp) - 1)
            k = np.minimum(np.floor(s).astype(int), len(ramp) - 1)
            k1 = np.minimum(k + 1, len(ramp) - 1)
            t = (s - k)[..., None]
            stops = np.array(ramp, dtype=float)
            expected = np.floor((1 - t) * stops[k] + t * stops[k1] + 0.5)
            self.assertLessEqual(np.max(np.abs(out.astype(int) - expected)), 1, (gamma, top))
        self.assertEqual(R.tone_map_log_density([5.0], max_density=1).tolist(), [list(ramp[-1])])
        self.assertEqual(R.tone_map_log_density([3.0], ramp=[(7, 8, 9)]).tolist(), [[7, 8, 9]])

    def test_tone_map_errors(self):
        for kwargs, message in [
            (dict(gamma=0), "the tone-mapping gamma 0 is not positive; give a positive gamma"),
            (dict(ramp=np.zeros((0, 3), dtype=int)), "the colour ramp is empty; give at least one colour"),
            (dict(ramp=[(0, 0, 256)]), "tone_map_log_density: ramp[0][2] = 256 is outside 0 … 255"),
            (dict(ramp=[(0, 0)]),
             "tone_map_log_density: ramp: expected an integer array of shape (k, 3), got shape (1, 2)"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                R.tone_map_log_density([1.0], **kwargs)
            self.assertEqual(str(e.exception), message)

    def test_previews(self):
        image = R.make_framebuffer(pixel_camera(6, 4))
        self.assertTrue(np.all(image.channels["Z"] == np.inf) and np.all(image.state == R.kNoState))
        shaded = R.preview_rgb8(image)  # no density: shaded, nothing drawn: the background
        self.assertEqual(shaded.shape, (4, 6, 3))
        self.assertTrue(np.all(shaded == 255))
        self.assertTrue(np.all(R.preview_rgb8(image, background=(10, 20, 30)) == [10, 20, 30]))
        self.assertTrue(np.all(R.preview_rgb8(image, exposure=0) == 0))
        density = np.arange(24, dtype=np.float32).reshape(4, 6)
        image.set_channel("density", density)
        auto = R.preview_rgb8(image)
        self.assertTrue(np.array_equal(auto, R.tone_map_log_density(density)))
        self.assertTrue(np.array_equal(R.preview_rgb8(image, mode=R.PreviewMode.density, gamma=2),
                                       R.tone_map_log_density(density, gamma=2)))
        self.assertTrue(np.array_equal(R.preview_rgb8(image, mode=R.PreviewMode.shaded), shaded))
        R.preview_png(self.scratch / "p.png", image, gamma=2)
        self.assertTrue(np.array_equal(R.read_png(self.scratch / "p.png", R.PixelFormat.rgb8),
                                       R.tone_map_log_density(density, gamma=2)))
        image.remove_channel("density")
        for call, message in [
            (lambda: R.preview_rgb8(image, mode=R.PreviewMode.density), "the image to preview has no channel density for this preview mode"),
            (lambda: R.preview_rgb8(image, exposure=-1), "the preview exposure must be a finite number ≥ 0"),
            (lambda: R.preview_rgb8(image, background=(0, 0)),
             "preview_rgb8: background: expected 3 integers, got shape (2,)"),
            (lambda: R.preview_rgb8(R.Image()), "the image to preview is empty"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                call()
            self.assertEqual(str(e.exception), message)


class RasterTest(unittest.TestCase):
    def test_segment_coverage_integrates_to_width_times_length(self):
        # docs/rendering.md: across a straight stroke the coverage integrates to the width.
        camera = pixel_camera(200, 200)
        slope = 0.37
        vertices = np.array([[-50, 100 - 150 * slope], [250, 100 + 150 * slope]])
        length = 200 * math.hypot(1, slope)  # the part over the image's 200 columns
        for width in (0.6, 1, 2.5, 4):
            image = R.Image()
            R.render_segments(image, camera, vertices, np.array([[0, 1]]), width=width, states=[7],
                              color=(0.5, 0.25, 1))
            a = image.channels["A"]
            self.assertLessEqual(a.max(), 1)
            assert_close(self, a.sum(), width * length, rel=2e-3, what=f"coverage of a {width}-pixel stroke")
            covered = a > 0
            self.assertTrue(np.all(image.state[covered] == 7) and np.all(image.state[~covered] == R.kNoState))
            self.assertTrue(np.all(image.channels["Z"][covered] == 10))
            assert_close(self, image.channels["G"], 0.25 * a, rel=1e-7, what="premultiplied colour")

    def test_polylines_are_their_segments(self):
        camera = pixel_camera(64, 48)
        rng = np.random.default_rng(8)
        lines = [rng.random((5, 2)) * [64, 48], rng.random((3, 2)) * [64, 48]]
        for closed in (False, True):
            a = R.Image()
            R.render_polylines(a, camera, lines, width=2, closed=closed)
            vertices = np.vstack(lines)
            segments, states, offset = [], [], 0
            for i, line in enumerate(lines):
                n = len(line)
                pairs = [(offset + j, offset + j + 1) for j in range(n - 1)]
                pairs += [(offset + n - 1, offset)] if closed else []
                segments += pairs
                states += [i] * len(pairs)
                offset += n
            b = R.Image()
            R.render_segments(b, camera, vertices, np.array(segments), states=np.array(states), width=2)
            for name in a.channels:
                self.assertTrue(np.array_equal(a.channels[name], b.channels[name]), name)
            self.assertTrue(np.array_equal(a.state, b.state))

    def test_mesh_quad_facing_the_camera(self):
        camera = pixel_camera(40, 30)
        # A square from pixel column 10 to 30 and rows 5 to 25 (world y = 30 − row), at z = 1.
        vertices = np.array([[10, 5, 1], [30, 5, 1], [30, 25, 1], [10, 25, 1]], dtype=float)
        image = R.Image()
        R.render_mesh(image, camera, vertices, quads=[[0, 1, 2, 3]], states=[3], threads=1)
        a = image.channels["A"]
        inside = np.zeros((30, 40), bool)
        inside[5:25, 10:30] = True
        self.assertTrue(np.all(a[inside] == 1) and np.all(a[~inside] == 0))
        self.assertTrue(np.all(image.channels["Z"][inside] == 9))
        self.assertTrue(np.all(image.channels["N.z"][inside] == 1) and np.all(image.channels["N.x"][inside] == 0))
        self.assertTrue(np.all(image.state[inside] == 3) and np.all(image.state[~inside] == R.kNoState))
        # Ambient + diffuse under a headlight facing the quad, plus the full specular highlight.
        assert_close(self, image.channels["R"][inside], np.full(400, 0.8 * (0.12 + 0.88) + 0.15), rel=1e-7,
                     what="shaded colour")
        # The same quad as the two triangles of its 0–2 diagonal, on two threads: the same image.
        other = R.Image()
        R.render_mesh(other, camera, vertices, triangles=np.array([[0, 1, 2], [0, 2, 3]]), states=[3, 3],
                      normals=np.tile([0, 0, 1.0], (4, 1)), threads=2)
        for name in ("A", "Z", "R", "N.x", "N.y", "N.z"):
            self.assertTrue(np.array_equal(image.channels[name], other.channels[name]), name)

    def test_mesh_index_dtypes_give_the_same_image(self):
        # int32 quads and uint32 states (what ifs.surface_mesh returns) are converted, not misread
        # (a converted temporary once dangled here: a crash).
        camera = R.Camera(width=24, height=24, eye=(0.5, 0.5, 3), target=(0.5, 0.5, 0), ortho_height=2)
        vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.2], [0, 1, 0.1]], dtype=float)
        images = []
        for index_type, state_type in ((np.int64, np.int64), (np.int32, np.uint32), (np.uint16, np.uint8)):
            image = R.make_framebuffer(camera)
            R.render_mesh(image, camera, vertices, quads=np.array([[0, 1, 2, 3]], dtype=index_type),
                               states=np.array([7], dtype=state_type))
            images.append(image)
        for image in images[1:]:
            for name in ("R", "A", "Z", "N.z"):
                np.testing.assert_array_equal(image.channels[name], images[0].channels[name], name)
            np.testing.assert_array_equal(image.state, images[0].state)
        with self.assertRaises(cifs.InvalidInput) as caught:
            R.render_mesh(R.make_framebuffer(camera), camera, vertices, quads=np.array([[0, 1, 2, 3.0]]))
        self.assertIn("expected an array of integers", str(caught.exception))

    def test_attributes_are_a_read_only_view(self):
        image = R.Image(2, 2)
        image.attributes = {"a": "1"}
        with self.assertRaises(TypeError):
            image.attributes["b"] = "2"
        image.attributes = {**image.attributes, "b": "2"}
        self.assertEqual(dict(image.attributes), {"a": "1", "b": "2"})

    def test_mesh_thread_count_invariance(self):
        camera = R.Camera(projection=R.Projection.perspective, eye=(2, -3, 2), target=(0, 0, 0), up=(0, 0, 1),
                          width=80, height=70, fov_y=45)
        u, v = np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 9), indexing="ij")
        vertices = np.column_stack([u.ravel(), v.ravel(), (0.3 * np.sin(3 * u) * v).ravel()])
        quads = np.array([[i * 9 + j, (i + 1) * 9 + j, (i + 1) * 9 + j + 1, i * 9 + j + 1]
                          for i in range(8) for j in range(8)])
        images = []
        for threads in (1, 2, 3):
            image = R.Image()
            R.render_mesh(image, camera, vertices, quads=quads, states=np.arange(64),
                          state_colors=[[1, 0, 0], [0, 1, 0]],
                          headlight=False, samples_per_side=3, threads=threads)
            images.append(image)
        self.assertGreater(images[0].channels["A"].sum(), 100)
        for other in images[1:]:
            for name in images[0].channels:
                self.assertTrue(np.array_equal(images[0].channels[name], other.channels[name]), name)
            self.assertTrue(np.array_equal(images[0].state, other.state))

    def test_points_are_binned_where_they_project(self):
        camera = pixel_camera(32, 24)
        rng = np.random.default_rng(4)
        points = rng.random((500, 2)) * [34, 26] - 1  # some fall outside
        image = R.Image()
        R.render_points(image, camera, points, states=np.arange(500), weight=0.5, color=(0.1, 0.2, 0.3))
        view = R.view_transform(camera)
        expected = np.zeros((24, 32))
        first = np.full((24, 32), R.kNoState, dtype=np.int64)
        for i, (x, y) in enumerate(points):
            p = view.project((x, y, 0))
            col, row = math.floor(p.x), math.floor(p.y)
            if 0 <= col < 32 and 0 <= row < 24:
                expected[row, col] += 0.5
                if first[row, col] == R.kNoState:
                    first[row, col] = i  # equally near points: the first wins
        self.assertTrue(np.array_equal(image.channels["density"], expected.astype(np.float32)))
        self.assertTrue(np.array_equal(image.state, first))
        self.assertTrue(np.array_equal(image.channels["A"], (expected > 0).astype(np.float32)))
        self.assertTrue(np.array_equal(image.channels["B"], np.where(expected > 0, np.float32(0.3), 0)))

    def test_raster_errors(self):
        camera = pixel_camera(8, 8)
        square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
        cases = [
            (lambda: R.render_segments(R.Image(), camera, square, [[0, 4]]),
             "the segments to draw: segments[0][1] = 4 is out of range (4 vertices)"),
            (lambda: R.render_segments(R.Image(), camera, square, [[0, 1]], width=0),
             "the line width must be a positive finite number"),
            (lambda: R.render_segments(R.Image(), camera, square, [[0.0, 1.0]]),
             "render_segments: segments: expected an array of integers, got dtype float64"),
            (lambda: R.render_segments(R.Image(), camera, square, [[0, 1, 2]]),
             "render_segments: segments: expected an integer array of shape (n, 2), got shape (1, 3)"),
            (lambda: R.render_segments(R.Image(), camera, square, [[0, 1]], states=[1, 2]),
             "the segments to draw: 2 states for 1 segments"),
            (lambda: R.render_segments(R.Image(), camera, square, [[0, 1]], color=(1, 2)),
             "render_segments: color: expected 3 numbers, got shape (2,)"),
            (lambda: R.render_segments(R.Image(), camera, square, [[0, 1]], states=[-1]),
             "render_segments: states[0] = -1 is outside 0 … 4294967295"),
            (lambda: R.render_polylines(R.Image(), camera, square),
             "render_polylines: polylines[0]: expected a 2-D array (n, dim), got shape (3,)"),
            (lambda: R.render_mesh(R.Image(), camera, square, quads=[[0, 1, 2, 5]]),
             "render_mesh: quads[0][3] = 5 is out of range (4 vertices)"),
            (lambda: R.render_mesh(R.Image(), camera, square[:, :2], quads=[[0, 1, 2, 3]]),
             "render_mesh: mesh vertices have 2 columns, expected 3"),
            (lambda: R.render_mesh(R.Image(), camera, square, quads=[[0, 1, 2, 3]], samples_per_side=9),
             "the samples per pixel side, 9, are outside 1 … 8"),
            (lambda: R.render_mesh(R.Image(), camera, square, quads=[[0, 1, 2, 3]], normals=np.ones((3, 3))),
             "render_mesh: normals are 3 by 3, expected 4 by 3 (one per vertex)"),
            (lambda: R.render_mesh(R.Image(), camera, square, quads=[[0, 1, 2, 3]], threads=-1),
             "render_mesh: threads = -1 is outside 0 … 4294967295"),
            (lambda: R.render_points(R.Image(), camera, np.zeros((2, 4))),
             "the points to draw have 4 coordinates, expected 2 or 3"),
            (lambda: R.render_points(R.Image(), camera, np.zeros((2, 2)), states=[1]),
             "1 states given for 2 points"),
            (lambda: R.render_points(R.Image(4, 4), camera, np.zeros((2, 2))),
             "the image to draw into is 4 by 4, the camera 8 by 8"),
        ]
        for call, message in cases:
            with self.assertRaises(cifs.InvalidInput) as e:
                call()
            self.assertEqual(str(e.exception), message)


@unittest.skipUnless(HAS_AFFINE, "needs the ifs bindings (cifs.ifs.AffineMap)")
class PointIfsTest(ScratchTestCase):
    def test_histogram_thread_invariance_and_totals(self):
        maps = cifs.ifs.barnsley_fern()
        bounds = R.estimate_bounds(maps)
        self.assertTrue(bounds.x_min < -2.18 and bounds.x_max > 2.65 and bounds.y_min < 0 and bounds.y_max > 9.99)
        samples = 2 * R.kChaosChunk + 12345  # a ragged last chunk
        results = [R.chaos_game_histogram(maps, samples=samples, seed=9, threads=t, width=64, height=96,
                                          bounds=bounds) for t in (1, 2, 3)]
        for h in results:
            self.assertEqual((h.width, h.height, h.samples, h.counts.dtype, h.counts.shape),
                             (64, 96, samples, np.uint32, (96, 64)))
            self.assertTrue(np.array_equal(h.counts, results[0].counts))
            self.assertEqual(int(h.counts.sum()), h.samples - h.outside)
        self.assertEqual(results[0].outside, 0)
        # Half the window: the points outside are counted, not binned.
        half = R.Bounds(x_min=bounds.x_min, x_max=bounds.x_max, y_min=bounds.y_min,
                        y_max=(bounds.y_min + bounds.y_max) / 2)
        h = R.chaos_game_histogram(maps, samples=samples, seed=9, width=64, height=48, bounds=half)
        self.assertGreater(h.outside, 0)
        self.assertTrue(np.array_equal(h.counts, results[0].counts[48:]))

    def test_hutchinson_measure_of_the_right_angled_sierpinski_triangle(self):
        # docs/rendering.md: its depth-k pieces are the dyadic squares (i, j) with i & j = 0, mass 3^-k.
        half = [cifs.ifs.AffineMap(a=0.5, d=0.5, e=e, f=f, probability=1) for e, f in ((0, 0), (0.5, 0), (0, 0.5))]
        k = 4
        mass = R.hutchinson_measure(half, k, 16, 16, R.Bounds(x_min=0, x_max=1, y_min=0, y_max=1))
        self.assertEqual((mass.shape, mass.dtype), ((16, 16), np.float64))
        expected = np.zeros((16, 16))
        for i in range(16):
            for j in range(16):
                if i & j == 0:
                    expected[15 - j, i] = 3.0 ** -k  # row 0 at y_max
        assert_close(self, mass, expected, what="Hutchinson masses")

    def test_hutchinson_points_are_what_hutchinson_measure_bins(self):
        # The right-angled Sierpinski triangle: depth-k points at the centres of mass of the dyadic squares
        # (i, j) with i & j = 0, mass 3^-k each, in the walk's order (word k1 … kk, k1 applied first), each
        # with the map applied last.
        half = [cifs.ifs.AffineMap(a=0.5, d=0.5, e=e, f=f, probability=1) for e, f in ((0, 0), (0.5, 0), (0, 0.5))]
        k = 3
        points, mass, last = R.hutchinson_points(half, k)
        self.assertEqual((points.shape, mass.shape, last.dtype), ((27, 2), (27,), np.uint32))
        self.assertTrue(np.all(mass == 3.0 ** -k))
        centre = np.array([1 / 3, 1 / 3])  # the barycentre of the measure: x = (x + e·3) / 2 averaged
        for i in range(27):
            x = centre.copy()
            word = (i // 9, i // 3 % 3, i % 3)
            for m in word:
                x = 0.5 * x + [(0, 0), (0.5, 0), (0, 0.5)][m]
            assert_close(self, points[i], x, what=f"point {i}")
            self.assertEqual(last[i], word[-1])
        # Binned with their masses: hutchinson_measure's grid (no point on a pixel edge here).
        binned, _, _ = np.histogram2d(points[:, 1], points[:, 0], bins=8, range=[[0, 1], [0, 1]], weights=mass)
        measure = R.hutchinson_measure(half, k, 8, 8, R.Bounds(x_min=0, x_max=1, y_min=0, y_max=1))
        assert_close(self, measure, binned[::-1], what="binned points")
        with self.assertRaises(cifs.InvalidInput) as e:
            R.hutchinson_points(half, 7, max_points=1000)
        self.assertIn("more than 1000; lower the depth", str(e.exception))

    def test_point_ifs_errors(self):
        maps = cifs.ifs.sierpinski_triangle()
        for call, message in [
            (lambda: R.chaos_game_histogram([], samples=10), "the IFS has no affine map; give at least one"),
            (lambda: R.chaos_game_histogram(maps, samples=10, width=0), "the image size 0 by 1024 is empty"),
            (lambda: R.chaos_game_histogram(maps, samples=-1), "chaos_game_histogram: samples = -1 is negative"),
            (lambda: R.chaos_game_histogram(maps, samples=10, bounds=R.Bounds(x_min=1, x_max=0)),
             "the image bounds are empty or not finite"),
            (lambda: R.chaos_game_histogram(maps, samples=2**32), "4294967296 chaos-game samples are too many for one histogram"),
            (lambda: R.hutchinson_measure(maps, -1, 4, 4, R.Bounds()),
             "hutchinson_measure: depth = -1 is outside 0 … 4294967295"),
            (lambda: R.estimate_bounds(maps, -1.0), "the bounds margin must be a finite number ≥ 0"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                call()
            self.assertTrue(str(e.exception).startswith(message), str(e.exception))

    def test_cli_sierpinski_is_the_hutchinson_measure(self):
        # examples/experiments/sierpinski.json: the depth-12 measure on a 900 × 800 top view.
        exr, png = self.scratch / "s.exr", self.scratch / "s.png"
        cli("render", EXAMPLES / "experiments" / "sierpinski.json", "-o", exr, "--png", png, "--out-dir",
            self.scratch, "--quiet")
        image = R.read_exr(exr)
        bounds = classic_bounds(cifs.ifs.sierpinski_triangle(), 900, 800)
        mass = R.hutchinson_measure(cifs.ifs.sierpinski_triangle(), 12, 900, 800, bounds)
        self.assertTrue(np.array_equal(image.channels["density"], mass.astype(np.float32)))
        self.assertTrue(np.array_equal(R.read_png(png, R.PixelFormat.rgb8), R.preview_rgb8(image)))

    def test_cli_chaos_game_is_the_histogram(self):
        spec = {"name": "small fern", "ifs": "fern", "evaluation": {"chaos": 300000, "seed": 7},
                "render": {"width": 120, "height": 180}, "outputs": {"exr": "fern.exr"}}
        path = self.scratch / "fern.json"
        path.write_text(json.dumps(spec))
        cli("render", path, "--out-dir", self.scratch, "--threads", 2, "--quiet")
        image = R.read_exr(self.scratch / "fern.exr")
        self.assertEqual((image.attributes["seed"], image.attributes["evaluation"]),
                         ("7", "chaos game, 300000 samples"))
        bounds = classic_bounds(cifs.ifs.barnsley_fern(), 120, 180)
        h = R.chaos_game_histogram(cifs.ifs.barnsley_fern(), samples=300000, seed=7, threads=1, width=120, height=180,
                                   bounds=bounds)
        density = image.channels["density"]
        self.assertTrue(np.array_equal(density, h.counts.astype(np.float32)))
        self.assertEqual(int(density.sum()), h.samples - h.outside)


class CliImageTest(ScratchTestCase):
    def test_cli_exr_channels_are_consistent(self):
        exr = self.scratch / "s.exr"
        cli("render", EXAMPLES / "experiments" / "sierpinski.json", "-o", exr, "--out-dir", self.scratch, "--quiet")
        image = R.read_exr(exr)
        self.assertEqual((image.width, image.height), (900, 800))
        self.assertEqual(set(image.channels), {"R", "G", "B", "A", "Z", "density"})
        self.assertEqual({k: image.attributes[k] for k in ("experiment", "depth", "source")},
                         {"experiment": "sierpinski", "depth": "12", "source": "classic IFS sierpinski"})
        density = image.channels["density"]
        hit = density > 0
        self.assertGreater(hit.sum(), 1000)
        self.assertTrue(np.all(density >= 0))
        assert_close(self, density.astype(float).sum(), 1.0, rel=1e-5, what="total mass")  # every piece inside
        self.assertTrue(np.array_equal(image.channels["A"], hit.astype(np.float32)))
        self.assertTrue(np.all(np.isinf(image.channels["Z"][~hit])) and np.all(np.isfinite(image.channels["Z"][hit])))
        self.assertTrue(np.all(image.state[hit] == 0) and np.all(image.state[~hit] == R.kNoState))
        # The framing rule of `cifs render`: the triangle (0, 0), (1, 0), (½, √3/2), wider than the image,
        # fills the width up to 5 % (columns 45 … 855) and is centred vertically.
        rows, cols = np.nonzero(hit.any(axis=1))[0], np.nonzero(hit.any(axis=0))[0]
        self.assertTrue(44 <= cols[0] <= 46 and 853 <= cols[-1] <= 855, (cols[0], cols[-1]))
        self.assertLessEqual(abs(rows[0] + rows[-1] + 1 - 800), 2, (rows[0], rows[-1]))


@unittest.skipUnless(HAS_AFFINE_AUTOMATON, "needs the ifs and automata bindings (cifs.ifs.affine_automaton)")
class ChaosDensityTest(unittest.TestCase):
    def setUp(self):
        # sierpinski_triangle(): halvings towards (0, 0), (1, 0), (½, √3/2), as (a, b, c, d, e, f).
        self.coefficients = [(0.5, 0, 0, 0.5, 0, 0), (0.5, 0, 0, 0.5, 0.5, 0), (0.5, 0, 0, 0.5, 0.25, math.sqrt(3) / 4)]
        self.maps = [cifs.ifs.AffineMap(a=a, b=b, c=c, d=d, e=e, f=f, probability=1)
                     for a, b, c, d, e, f in self.coefficients]
        self.triangle = np.array([[-1.0, 0], [2, 0], [0.5, 2.5]])
        self.automaton = cifs.ifs.affine_automaton(self.maps, self.triangle)
        self.camera = R.frame(np.array([[0, 0], [1, math.sqrt(3) / 2]]), width=64, height=56)

    def test_thread_count_invariance_and_totals(self):
        samples = 2 * R.kDensityChunk + 777
        images, results = [], []
        for threads in (1, 2, 3):
            image = R.Image()
            results.append(R.chaos_density(image, self.camera, self.automaton, [self.triangle], samples=samples,
                                           seed=5, threads=threads, color=(0.3, 0.6, 0.9), progress=threads == 2))
            images.append(image)
        for r, image in zip(results, images):
            self.assertEqual((r.samples, r.depth), (samples, results[0].depth))
            for name in images[0].channels:
                self.assertTrue(np.array_equal(image.channels[name], images[0].channels[name]), name)
            self.assertTrue(np.array_equal(image.state, images[0].state))
        density = images[0].channels["density"]
        self.assertEqual(int(density.sum()), samples - results[0].outside)
        hit = density > 0
        self.assertTrue(np.array_equal(images[0].channels["A"], hit.astype(np.float32)))
        self.assertTrue(np.all(images[0].state[hit] == 0))
        self.assertGreater(results[0].depth, 0)

    def test_support_is_the_depth_k_start_points(self):
        # A sample is the start point of a depth-k node: the first map's fixed point (0, 0) mapped by
        # a word of k maps. Every such point, binned by render_points, marks the possible pixels.
        k = 5
        points = np.zeros((1, 2))
        for _ in range(k):
            x, y = points[:, 0], points[:, 1]
            points = np.vstack([np.column_stack([a * x + b * y + e, c * x + d * y + f])
                                for a, b, c, d, e, f in self.coefficients])
        # Shifted off the dyadic grid so that no point lies on a pixel border (where rounding decides).
        camera = R.frame(np.array([[0.0123, 0.0071], [1.0123, math.sqrt(3) / 2 + 0.0071]]), width=64, height=56)
        view = R.view_transform(camera)
        xy = np.array([[view.project((x, y, 0)).x, view.project((x, y, 0)).y] for x, y in points])
        self.assertGreater(np.min(np.abs(xy - np.round(xy))), 1e-6)
        reference = R.Image()
        R.render_points(reference, camera, points)
        image = R.Image()
        r = R.chaos_density(image, camera, self.automaton, [self.triangle], samples=200000, seed=3, depth=k)
        self.assertEqual(r.depth, k)
        self.assertTrue(np.array_equal(image.channels["density"] > 0, reference.channels["density"] > 0))

    def test_chaos_density_errors(self):
        for kwargs, message in [
            (dict(samples=2**32), "4294967296 chaos-game samples are too many: they must be below 2^32 (uint32 counts)"),
            (dict(depth=65), "the chaos game's depth 65 is outside 0 … 64"),
            (dict(samples=-3), "chaos_density: samples = -3 is negative"),
        ]:
            with self.assertRaises(cifs.InvalidInput) as e:
                R.chaos_density(R.Image(), self.camera, self.automaton, [self.triangle], **kwargs)
            self.assertEqual(str(e.exception), message)
        for columns, kwargs, message in [
            (3, dict(rational=True), "the chaos game of a rational shape needs an explicit depth; give one"),
            (4, dict(depth=3), "the control nets have 4 columns, the chaos game draws 2 or 3 (2-D or 3-D points)"),
        ]:
            net = np.column_stack([self.triangle, np.ones((3, columns - 2))])
            with self.assertRaises(cifs.InvalidInput) as e:
                R.chaos_density(R.Image(), self.camera, self.automaton, [net], **kwargs)
            self.assertEqual(str(e.exception), message)
        with self.assertRaises(cifs.InvalidInput) as e:
            R.chaos_density(R.Image(), self.camera, self.automaton, self.triangle)
        self.assertEqual(str(e.exception), "chaos_density: nets[0]: expected a 2-D array (n, dim), got shape (2,)")
        with self.assertRaises(cifs.InvalidInput) as e:
            R.chaos_density(R.Image(), self.camera, self.automaton, [self.triangle, self.triangle])
        self.assertTrue(str(e.exception).startswith("2 control nets given for the automaton's 1"), str(e.exception))
        with self.assertRaises(cifs.InvalidInput) as e:
            R.chaos_density(R.Image(3, 3), self.camera, self.automaton, [self.triangle])
        self.assertEqual(str(e.exception), "the image to draw into is 3 by 3, the camera 64 by 56")


if __name__ == "__main__":
    unittest.main()
