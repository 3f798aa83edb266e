# SPDX-License-Identifier: MIT
"""Streamed outputs (docs/cli.md): `cifs attractor` and `cifs eval` with `-o FILE` write the points as they
are computed. The files are read back by NumPy (`.npy`) and by a parser written here (PLY), and compared
with de Boor's algorithm run in NumPy at the same parameters; memory is measured on the child process."""
import json
import subprocess
import sys
import time
import unittest

import numpy as np

from support import CLI, EXAMPLES, SANITIZED, ScratchTestCase, cli



def de_boor(curve, us):
    """Points of a JSON curve (open, clamped; rational when it has weights) at `us`, by de Boor's algorithm
    on homogeneous points, written here and independent of the library."""
    p = curve["degree"]
    t = np.asarray(curve["knots"], float)
    P = np.asarray(curve["points"], float)
    w = np.asarray(curve.get("weights", np.ones(len(P))), float)
    H = np.column_stack([P * w[:, None], w])
    n = len(P)
    out = []
    for u in us:
        k = min(int(np.searchsorted(t, u, side="right")) - 1, n - 1)  # t[k] <= u < t[k+1]; the end: last span
        d = [H[j + k - p].copy() for j in range(p + 1)]
        for r in range(1, p + 1):
            for j in range(p, r - 1, -1):
                a = (u - t[j + k - p]) / (t[j + 1 + k - r] - t[j + k - p])
                d[j] = (1 - a) * d[j - 1] + a * d[j]
        out.append(d[p][:-1] / d[p][-1])
    return np.array(out)


def dyadic_parameters(curve, depth):
    """t_k + j·(t_{k+1} − t_k)/2^depth over the segments, and the domain end: the attractor's parameters."""
    t = curve["knots"]
    breaks = sorted(set(t[curve["degree"]:len(t) - curve["degree"]]))
    us = [a + (b - a) * j / 2**depth for a, b in zip(breaks, breaks[1:]) for j in range(2**depth)]
    return np.array(us + [breaks[-1]])


def read_ply_points(path):
    """x, y, z of a binary little-endian PLY point cloud: the header by hand, the body as '<f8'."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert header[:2] == ["ply", "format binary_little_endian 1.0"], header
    count = int(next(line.split()[2] for line in header if line.startswith("element vertex")))
    assert [line for line in header if line.startswith("property")] == [
        "property double x", "property double y", "property double z"], header
    body = np.frombuffer(data[end:], dtype="<f8")
    assert body.size == 3 * count, (body.size, count)
    return body.reshape(count, 3)


class StreamedFiles(ScratchTestCase):
    def test_npy_and_ply_equal_de_boor(self):
        for name, depth in (("cubic.json", 10), ("wave.json", 9)):  # polynomial 3-D, rational 2-D
            with self.subTest(name=name):
                shape = EXAMPLES / "shapes" / name
                curve = json.loads(shape.read_text())["curve"]
                expected = de_boor(curve, dyadic_parameters(curve, depth))
                npy, ply = self.scratch / "p.npy", self.scratch / "p.ply"
                cli("attractor", shape, "--depth", depth, "-o", npy)
                cli("attractor", shape, "--depth", depth, "-o", ply)
                points = np.load(npy)
                self.assertEqual(points.dtype, np.dtype("<f8"))
                self.assertEqual(points.shape, expected.shape)
                scale = np.abs(expected).max()
                np.testing.assert_allclose(points, expected, rtol=0, atol=1e-12 * scale)
                # numpy.save writes the same bytes: header, padding and data as NumPy lays them out.
                path = self.scratch / "resaved.npy"
                np.save(path, points)
                self.assertEqual(path.read_bytes(), npy.read_bytes())
                cloud = read_ply_points(ply)
                np.testing.assert_array_equal(cloud[:, :points.shape[1]], points)
                np.testing.assert_array_equal(cloud[:, points.shape[1]:], 0)

    def test_eval_npy(self):
        shape = EXAMPLES / "shapes" / "cubic.json"
        curve = json.loads(shape.read_text())["curve"]
        out = self.scratch / "e.npy"
        cli("eval", shape, "--at", "1.5", "--samples", 70001, "-o", out)  # two chunks of 2^16 parameters
        us = np.concatenate([[1.5], [4.0 * i / 70000 for i in range(70001)]])
        np.testing.assert_allclose(np.load(out), de_boor(curve, us), rtol=0, atol=1e-12 * 7)

    @unittest.skipIf(SANITIZED, "the sanitizer's own memory is not the program's")
    def test_memory_is_a_chunk_not_the_output(self):
        # 3 · 2^21 + 1 points of 3 doubles: a 151 MB file from a process that stays near 10 MB.
        if not CLI:
            raise unittest.SkipTest("CIFS_CLI is not set")
        out = self.scratch / "p.npy"
        child = ("import resource, subprocess, sys; subprocess.run(sys.argv[1:], check=True); "
                 "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
        run = subprocess.run([sys.executable, "-c", child, CLI, "attractor", EXAMPLES / "shapes" / "cubic.json",
                              "--depth", "21", "-o", out], capture_output=True, text=True, check=True)
        peak_kib = int(run.stdout.split()[-1])
        self.assertEqual(out.stat().st_size, 128 + (3 * 2**21 + 1) * 24)
        self.assertLess(peak_kib, 48 * 1024, f"peak RSS {peak_kib} KiB for a {out.stat().st_size} byte file")

    @unittest.skipIf(SANITIZED, "the sanitizer's own memory is not the program's")
    def test_stdout_is_streamed_too(self):
        # The same 151 MB through standard output (a redirected file): the same bytes as -o, and the
        # process holds a chunk, not the output.
        if not CLI:
            raise unittest.SkipTest("CIFS_CLI is not set")
        shape = EXAMPLES / "shapes" / "cubic.json"
        out, piped = self.scratch / "p.npy", self.scratch / "stdout.npy"
        cli("attractor", shape, "--depth", 21, "-o", out)
        child = ("import resource, subprocess, sys; subprocess.run(sys.argv[2:], check=True, "
                 "stdout=open(sys.argv[1], 'wb')); print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
        run = subprocess.run([sys.executable, "-c", child, piped, CLI, "attractor", shape, "--depth", "21",
                              "--format", "npy"], capture_output=True, text=True, check=True)
        self.assertEqual(piped.read_bytes(), out.read_bytes())
        peak_kib = int(run.stdout.split()[-1])
        self.assertLess(peak_kib, 48 * 1024, f"peak RSS {peak_kib} KiB for {piped.stat().st_size} bytes on stdout")

    def test_refused_in_memory_streamed_to_file_atomically(self):
        # Depth 24 (1.2 GB of points) is refused as SVG (drawn whole) and accepted to a file. The run is
        # stopped once the temporary holds 64 MB: the target never holds a partial file.
        shape = EXAMPLES / "shapes" / "cubic.json"
        refused = cli("attractor", shape, "--depth", 24, "--format", "svg", check=False)
        self.assertEqual(refused.returncode, 2)
        self.assertIn("more than the 1 GiB held in memory for SVG", refused.stderr)
        if not CLI:
            raise unittest.SkipTest("CIFS_CLI is not set")
        target = self.scratch / "big.npy"
        process = subprocess.Popen([CLI, "attractor", shape, "--depth", "24", "-o", target],
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            deadline = time.monotonic() + 120
            while process.poll() is None and time.monotonic() < deadline:
                temporaries = [p for p in self.scratch.iterdir() if ".cifs-tmp-" in p.name]
                if temporaries and temporaries[0].stat().st_size > 64 * 2**20:
                    break
                time.sleep(0.02)
            if process.poll() is None:
                self.assertFalse(target.exists())
                process.kill()
            else:  # finished first: the whole file is there
                self.assertEqual(process.returncode, 0, process.stderr.read())
                self.assertEqual(target.stat().st_size, 128 + (3 * 2**24 + 1) * 24)
        finally:
            if process.poll() is None:
                process.kill()
            process.wait()
            process.stdout.close()
            process.stderr.close()

    def test_disk_space_refusal(self):
        big = self.scratch / "big.npy"
        result = cli("attractor", EXAMPLES / "shapes" / "cubic.json", "--depth", 40, "-o", big, check=False)
        self.assertEqual(result.returncode, 2)
        self.assertRegex(result.stderr, r"big\.npy: the file needs 79165 GB of disk space, [0-9.]+ GB are free")
        self.assertEqual(list(self.scratch.iterdir()), [])

    def test_write_points_from_python(self):
        import cifs
        points = np.random.default_rng(3).normal(size=(1000, 3))
        path = self.scratch / "p.npy"
        cifs.io.write_points(path, points)
        np.testing.assert_array_equal(np.load(path), points)
        self.assertEqual(cifs.io.encode_points(points, "npy"), path.read_bytes())
        cifs.io.write_points(self.scratch / "p.ply", points)
        np.testing.assert_array_equal(read_ply_points(self.scratch / "p.ply"), points)
        self.assertEqual([f.name for f in cifs.io.formats(cifs.io.Content.points)], ["json", "npy", "ply", "obj"])
        text = cifs.io.encode_points(points[:2, :2], "json")
        np.testing.assert_array_equal(np.array(json.loads(text)["points"]), points[:2, :2])


if __name__ == "__main__":
    unittest.main()
