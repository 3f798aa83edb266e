# SPDX-License-Identifier: MIT
"""The Python examples (examples/python) run on small sizes, and what they write is checked."""
import subprocess
import sys
import unittest

import numpy as np

import cifs
from support import EXAMPLES, ScratchTestCase, cli

SCRIPTS = EXAMPLES / "python"


def run_script(name, *args):
    result = subprocess.run([sys.executable, str(SCRIPTS / name), *map(str, args)], capture_output=True, text=True)
    if result.returncode != 0:
        raise AssertionError(f"{name} exited {result.returncode}:\n{result.stdout}\n{result.stderr}")
    return result


class GalleryTest(ScratchTestCase):
    def test_small_gallery(self):
        run_script("gallery.py", "--out", self.scratch, "--size", 96, "--samples", 20000, "--quiet")
        for name in ("wave", "hills", "fern", "clover_fractal"):
            image = cifs.render.read_exr(self.scratch / f"{name}.exr")
            self.assertEqual((image.width, image.height), (96, 96), name)
            png = cifs.render.read_png(self.scratch / f"{name}.png")
            self.assertEqual(png.shape[:2], (96, 96), name)
            self.assertGreater(float(np.sum(image.channels["A"])), 0, f"{name}: nothing drawn")
        self.assertIn("<svg", (self.scratch / "wave.automaton.svg").read_text())
        # The fern's density holds the samples that landed on screen: all but a few, since the frame
        # is fitted to depth-6 points and the attractor reaches slightly beyond them.
        fern = cifs.render.read_exr(self.scratch / "fern.exr")
        self.assertLessEqual(int(np.sum(fern.channels["density"])), 20000)
        self.assertGreaterEqual(int(np.sum(fern.channels["density"])), 19900)
        self.assertEqual(sorted(p.name for p in self.scratch.iterdir() if p.name.startswith(".")), [],
                         "temporary files left behind")

    def test_clover_fractal_matches_the_command_line(self):
        # The script edits the experiment's image size only: the CLI on the same edited file writes
        # the same image.
        run_script("gallery.py", "--out", self.scratch, "--size", 64, "--quiet", "clover_fractal")
        import json
        spec = json.loads((EXAMPLES / "experiments" / "clover_fractal.json").read_text())
        spec.setdefault("render", {}).update(width=64, height=64)
        spec["outputs"] = {}
        edited = EXAMPLES / "experiments" / "clover_fractal.json"
        copy = self.scratch / "edited.json"
        text = json.dumps(spec).replace('"../', f'"{edited.parent.parent.as_posix()}/')
        copy.write_text(text)
        cli("render", copy, "-o", self.scratch / "cli.exr", "--quiet")
        ours = cifs.render.read_exr(self.scratch / "clover_fractal.exr")
        theirs = cifs.render.read_exr(self.scratch / "cli.exr")
        for channel in ("R", "G", "B", "A", "Z"):
            np.testing.assert_array_equal(ours.channels[channel], theirs.channels[channel], channel)

    def test_unknown_picture_is_refused(self):
        result = subprocess.run([sys.executable, str(SCRIPTS / "gallery.py"), "--out", str(self.scratch), "nope"],
                                capture_output=True, text=True)
        self.assertEqual(result.returncode, 2)
        self.assertIn("unknown picture 'nope'", result.stderr)


if __name__ == "__main__":
    unittest.main()
