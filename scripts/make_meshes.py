#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Writes the example polygon meshes of examples/meshes/ (OBJ, faces counter-clockwise seen from
outside), and one production-style mesh with creases, corners, a hole and UVs (OBJ `t` tags and `vt`,
docs/formats.md). `make_meshes.py --check` compares the files with what this script writes (a ctest
test)."""
import math
import pathlib
import sys


def obj(name, comment, points, faces):
    lines = [f"# {name}: {comment}", f"# {len(points)} vertices, {len(faces)} faces (scripts/make_meshes.py)"]
    lines += ["v " + " ".join(repr(round(c, 12) + 0.0) for c in p) for p in points]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    return "\n".join(lines) + "\n"


def cube():
    p = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    f = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return p, f


def cube_triangles():
    # Each square split along the diagonal of the inscribed tetrahedron (0, 2, 5, 7): those four
    # corners get valence 6, the other four valence 3.
    p, quads = cube()
    tet = {0, 2, 5, 7}
    f = []
    for q in quads:
        k = next(i for i in range(4) if q[i] in tet)
        a, b, c, d = q[k:] + q[:k]
        f += [(a, b, c), (a, c, d)]
    return p, f


def tetrahedron():
    return [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)], [(0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 3, 2)]


def icosahedron():
    t = (1 + math.sqrt(5)) / 2
    p = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return p, f


def open_grid(n=6, m=4, triangles=False):
    p = [(i / 2, j / 2, 0.3 * math.sin(1.1 * i) * math.cos(0.9 * j)) for j in range(m + 1) for i in range(n + 1)]
    f = []
    for j in range(m):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            f += [(a, b, c), (a, c, d)] if triangles else [(a, b, c, d)]
    return p, f


def boundary_fan(k=6, triangles=False):
    # Boundary vertex 0 with k faces over a half-disk: quads (0, r_i, f_i, r_i+1), or triangles
    # (0, r_i, r_i+1); a gentle bump so that the surface is not flat.
    step = math.pi / k
    p = [(0.0, 0.0, 0.2)]
    p += [(math.cos(i * step), math.sin(i * step), 0.1 * math.sin(2 * i * step)) for i in range(k + 1)]
    if triangles:
        return p, [(0, 1 + i, 2 + i) for i in range(k)]
    p += [(1.6 * math.cos((i + 0.5) * step), 1.6 * math.sin((i + 0.5) * step), 0.0) for i in range(k)]
    return p, [(0, 1 + i, k + 2 + i, 2 + i) for i in range(k)]


def torus(n=12, m=8, triangles=False):
    p = []
    for j in range(m):
        for i in range(n):
            u, v = 2 * math.pi * i / n, 2 * math.pi * j / m
            p.append(((2 + 0.7 * math.cos(v)) * math.cos(u), (2 + 0.7 * math.cos(v)) * math.sin(u), 0.7 * math.sin(v)))
    f = []
    for j in range(m):
        for i in range(n):
            a, b = j * n + i, j * n + (i + 1) % n
            c, d = ((j + 1) % m) * n + (i + 1) % n, ((j + 1) % m) * n + i
            f += [(a, b, c), (a, c, d)] if triangles else [(a, b, c, d)]
    return p, f


def rings(sizes=(3, 7, 5)):
    """A closed egg of triangles: a pole, rings of the given sizes, a pole; consecutive rings zipped
    by angle, so valences vary (here 3 to 7) — the mixed extraordinary vertices of real meshes."""
    top, p, starts = 0, [(0.0, 0.0, 1.6)], []
    for k, n in enumerate(sizes):
        z = 1.2 - 2.4 * (k + 0.5) / len(sizes)
        r = 1.0 + 0.15 * k
        starts.append(len(p))
        p += [(r * math.cos(2 * math.pi * i / n + 0.3 * k), r * math.sin(2 * math.pi * i / n + 0.3 * k), z)
              for i in range(n)]
    bottom = len(p)
    p.append((0.0, 0.0, -1.8))
    f = [(top, starts[0] + i, starts[0] + (i + 1) % sizes[0]) for i in range(sizes[0])]
    for k in range(len(sizes) - 1):
        (a0, na), (b0, nb) = (starts[k], sizes[k]), (starts[k + 1], sizes[k + 1])
        angle = lambda i, n, k: (2 * math.pi * i / n + 0.3 * k) % (2 * math.pi)
        # Merge the two rings' vertices by angle, starting both at vertex 0; each step adds the
        # triangle that advances the ring whose next vertex comes first.
        i = j = 0
        while i < na or j < nb:
            ta = angle(i + 1, na, k) if i < na else math.inf
            tb = angle(j + 1, nb, k + 1) if j < nb else math.inf
            ta = ta if ta > angle(i, na, k) or i == na else ta + 2 * math.pi
            tb = tb if tb > angle(j, nb, k + 1) or j == nb else tb + 2 * math.pi
            if ta <= tb:
                f.append((a0 + i % na, b0 + j % nb, a0 + (i + 1) % na))
                i += 1
            else:
                f.append((a0 + i % na, b0 + j % nb, b0 + (j + 1) % nb))
                j += 1
    last, n = starts[-1], sizes[-1]
    f += [(bottom, last + (i + 1) % n, last + i) for i in range(n)]
    return p, f


def creased_box(n=3, triangles=False):
    """A box of n x n quads a side (vertices shared along its edges). Its 12 edges are creased: the
    bottom square infinitely sharp, the vertical edges sharpness 2, the top square 1 (semi-sharp:
    rounder); one top corner has vertex sharpness 3; the middle quad of the top is a hole; the UVs
    are a 3 x 2 atlas of the six sides, so every box edge is a UV seam. `triangles`: each quad split
    into two along its diagonal from corner (i, j) (the hole: both halves)."""
    index, points = {}, []

    def vertex(p):
        if p not in index:
            index[p] = len(points)
            points.append((p[0] / n - 0.5, p[1] / n - 0.5, 0.8 * p[2] / n - 0.4))
        return index[p]

    # Each side: an origin and two axes on the integer lattice 0..n, counter-clockwise from outside.
    sides = [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, n), (1, 0, 0), (0, 1, 0)),
             ((0, 0, 0), (1, 0, 0), (0, 0, 1)), ((n, 0, 0), (0, 1, 0), (0, 0, 1)),
             ((n, n, 0), (-1, 0, 0), (0, 0, 1)), ((0, n, 0), (0, -1, 0), (0, 0, 1))]
    faces, uvs, face_uvs = [], [], []
    for k, (o, u, v) in enumerate(sides):
        base, col, row = len(uvs), k % 3, k // 3
        uvs += [((col + 0.05 + 0.9 * i / n) / 3, (row + 0.05 + 0.9 * j / n) / 2) for j in range(n + 1) for i in range(n + 1)]
        for j in range(n):
            for i in range(n):
                quad = ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1))
                for corners in ((quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])) if triangles else (quad,):
                    faces.append(tuple(vertex(tuple(o[a] + ci * u[a] + cj * v[a] for a in range(3))) for ci, cj in corners))
                    face_uvs.append(tuple(base + cj * (n + 1) + ci for ci, cj in corners))

    def box_edge(axis, fixed, sharpness):
        # The n mesh edges along `axis`, the other two lattice coordinates `fixed` (in axis order).
        at = lambda t: index[tuple(list(fixed[:axis]) + [t] + list(fixed[axis:]))]
        return [(at(t), at(t + 1), sharpness) for t in range(n)]

    creases = []
    for z, sharpness in ((0, 10), (n, 1)):
        for c in (0, n):
            creases += box_edge(0, (c, z), sharpness) + box_edge(1, (c, z), sharpness)
    for x in (0, n):
        for y in (0, n):
            creases += box_edge(2, (x, y), 2)
    tags = [f"t crease 2/1/0 {a} {b} {s}" for a, b, s in creases]
    tags += [f"t corner 1/1/0 {index[(n, n, n)]} 3"]
    hole = n * n + (n // 2) * n + n // 2
    tags += [f"t hole 1/0/0 {2 * hole + k}" for k in (0, 1)] if triangles else [f"t hole 1/0/0 {hole}"]
    return points, faces, uvs, face_uvs, tags


def creased_torus(n=12, m=8):
    """The torus with two infinitely sharp creases: its outer equator (ring j = 0) and one meridian
    (i = 0), crossing at vertex 0 (a corner: four sharp edges). Both crease polygons are curved, so a
    fractal crease leaves them (a straight crease's fractal stays on its line). No UVs."""
    points, faces = torus(n, m)
    creases = [(i, (i + 1) % n) for i in range(n)] + [(j * n, ((j + 1) % m) * n) for j in range(m)]
    return points, faces, [], [], [f"t crease 2/1/0 {a} {b} 10" for a, b in creases]


def tagged_obj(name, comment, points, faces, uvs, face_uvs, tags):
    """OBJ with `vt` rows, `f v/vt` corners and `t` tag lines (0-based indices, as OpenSubdiv's shapes)."""
    lines = [f"# {name}: {comment}",
             f"# {len(points)} vertices, {len(faces)} faces, {len(uvs)} UVs, {len(tags)} tags (scripts/make_meshes.py)"]
    lines += ["v " + " ".join(repr(round(c, 12) + 0.0) for c in p) for p in points]
    lines += ["vt " + " ".join(repr(round(c, 12) + 0.0) for c in t) for t in uvs]
    if uvs:
        lines += ["f " + " ".join(f"{v + 1}/{t + 1}" for v, t in zip(f, ft)) for f, ft in zip(faces, face_uvs)]
    else:
        lines += ["f " + " ".join(str(v + 1) for v in f) for f in faces]
    return "\n".join(lines + tags) + "\n"


MESHES = {
    "cube": ("unit cube, 6 quads, valence 3", cube),
    "cube_triangles": ("cube split into 12 triangles, valences 3 and 6", cube_triangles),
    "tetrahedron": ("regular tetrahedron, valence 3", tetrahedron),
    "icosahedron": ("regular icosahedron, valence 5", icosahedron),
    "open_grid": ("6 x 4 quads over a wave, open (boundary, valence-2 corners)", open_grid),
    "open_grid_triangles": ("the open grid split into triangles", lambda: open_grid(triangles=True)),
    "torus": ("12 x 8 quads, genus 1, every vertex regular", torus),
    "torus_triangles": ("the torus split into triangles, valence 6", lambda: torus(triangles=True)),
    "boundary_fan": ("6 quads around a boundary vertex (catmull-clark: not C1 there under OpenSubdiv's rules)",
                     boundary_fan),
    "boundary_fan_triangles": ("8 triangles around a boundary vertex (loop: not C1 there under OpenSubdiv's rules)",
                               lambda: boundary_fan(8, triangles=True)),
    "rings": ("closed triangles, a pole and rings of 3, 7 and 5 vertices: valences 3 to 7", rings),
}
# Meshes with tags and UVs (tagged_obj).
TAGGED = {
    "creased_box": ("a box of 3 x 3 quads a side: creases infinite, 2 and 1, a corner, a hole on top, UVs", creased_box),
    "creased_box_triangles": ("the creased box with each quad split into two triangles (the hole: both)",
                              lambda: creased_box(triangles=True)),
    "creased_torus": ("the 12 x 8 torus with an infinitely sharp equator and meridian crossing at a corner",
                      creased_torus),
}


def main():
    check = "--check" in sys.argv
    args = [a for a in sys.argv[1:] if a != "--check"]
    out = pathlib.Path(args[0]) if args else pathlib.Path(__file__).resolve().parent.parent / "examples" / "meshes"
    out.mkdir(parents=True, exist_ok=True)
    stale = []
    texts = {name: obj(name, comment, *make()) for name, (comment, make) in MESHES.items()}
    texts.update({name: tagged_obj(name, comment, *make()) for name, (comment, make) in TAGGED.items()})
    for name, text in texts.items():
        path = out / f"{name}.obj"
        if check:
            if not path.exists() or path.read_text() != text:
                stale.append(str(path))
        else:
            path.write_text(text)
    if stale:
        print("make_meshes: differs from what scripts/make_meshes.py writes: " + ", ".join(stale), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
