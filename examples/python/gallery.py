#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Rebuilds part of the cifs gallery from Python, step by step: shape → automaton → attractor → render.

- wave: the non-uniform rational cubic of examples/shapes/wave.json as the attractor of its
  knot-doubling automaton (homogeneous nets, projected), checked against Cox–de Boor, drawn as an
  anti-aliased stroke; the automaton as SVG;
- hills: the bicubic surface of examples/shapes/hills.json as the watertight quad mesh of its tensor
  automaton (G/D × H/B), checked against surface evaluation, shaded;
- fern: Barnsley's fern as a one-state CIFS on a control triangle, chaos-game density;
- clover_fractal: the experiment file examples/experiments/clover_fractal.json (fractal support), run
  through cifs.experiment with the image size of this script.

Each picture is an OpenEXR file (float channels) and a PNG preview in the output folder.

    python3 examples/python/gallery.py --out out/python            # 1024², as the gallery
    python3 examples/python/gallery.py --out /tmp/g --size 128 --quiet
"""
import argparse
import json
import sys
from pathlib import Path

import numpy as np

import cifs
from cifs import automata, experiment, ifs, io, nurbs, render

EXAMPLES = Path(__file__).resolve().parents[1]


def say(args, text):
    if not args.quiet:
        print(text)


def save(args, name, image):
    render.write_exr(args.out / f"{name}.exr", image)
    render.preview_png(args.out / f"{name}.png", image)
    say(args, f"{name}: wrote {name}.exr, {name}.png")


def wave(args):
    curve = io.read_shape(EXAMPLES / "shapes" / "wave.json")
    automaton = automata.knot_automaton(curve)
    nets = automata.initial_nets(automaton, curve)  # homogeneous rows (w·x, w): the curve is rational
    depth = 10
    points = ifs.cartesian(ifs.attractor_points(automaton, nets, depth))

    # The attractor at depth K is the curve at the dyadic parameters of every segment (checked here
    # against de Boor's algorithm, an independent route).
    params = [entry.start + (entry.end - entry.start) * j / 2**depth
              for entry in automaton.initial for j in range(2**depth)] + [automaton.initial[-1].end]
    reference = nurbs.evaluate(curve, params)
    deviation = np.max(np.abs(points - reference)) / np.max(np.abs(reference))
    assert deviation < 1e-12, f"wave: attractor deviates from Cox–de Boor by {deviation:.2e}"

    camera = render.frame(points, width=args.size, height=args.size)
    image = render.make_framebuffer(camera)
    render.render_polylines(image, camera, [nurbs.cartesian_points(curve)], width=max(1.0, args.size / 1024),
                            color=(0.55, 0.55, 0.55))
    render.render_polylines(image, camera, [points], width=max(1.5, 3 * args.size / 1024), color=(0.12, 0.30, 0.65))
    image.attributes = {**image.attributes, "source": "examples/python/gallery.py: wave"}
    save(args, "wave", image)
    io.write_file_atomically(args.out / "wave.automaton.svg", automata.to_svg(automaton))
    say(args, f"wave: {len(points)} attractor points, {automaton.state_count} states, deviation {deviation:.1e}")


def hills(args):
    surface = io.read_shape(EXAMPLES / "shapes" / "hills.json")
    tensor = automata.tensor_automaton(surface)
    nets = automata.initial_nets(tensor, surface)
    depth = 6
    mesh = ifs.surface_mesh(tensor, nets, depth, homogeneous=surface.rational)

    # Node (I, J) of the mesh is the surface at the dyadic parameters of its patch.
    us = np.unique(np.concatenate([np.linspace(e.start, e.end, 2**depth + 1) for e in tensor.factors[0].initial]))
    vs = np.unique(np.concatenate([np.linspace(e.start, e.end, 2**depth + 1) for e in tensor.factors[1].initial]))
    reference = nurbs.evaluate_grid(surface, us, vs).reshape(-1, 3)  # (nu, nv, 3) → the mesh's vertex rows
    deviation = np.max(np.abs(mesh.vertices - reference)) / np.max(np.abs(reference))
    assert deviation < 1e-12, f"hills: mesh deviates from surface evaluation by {deviation:.2e}"

    camera = render.frame(mesh.vertices, width=args.size, height=args.size)
    image = render.make_framebuffer(camera)
    render.render_mesh(image, camera, mesh.vertices, quads=mesh.quads, states=mesh.states,
                       color=(0.80, 0.72, 0.55))
    save(args, "hills", image)
    say(args, f"hills: {len(mesh.quads)} quads from {tensor.product.state_count} product states, "
              f"deviation {deviation:.1e}")


def fern(args):
    triangle = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    automaton = ifs.affine_automaton(ifs.barnsley_fern(), triangle)
    nets = [triangle]
    camera = render.frame(ifs.attractor_points(automaton, nets, 6), width=args.size, height=args.size)
    image = render.make_framebuffer(camera)
    result = render.chaos_density(image, camera, automaton, nets, samples=args.samples, seed=1,
                                  progress=not args.quiet)
    save(args, "fern", image)
    say(args, f"fern: {result.samples} samples at depth {result.depth}, {result.outside} outside")


def clover_fractal(args):
    # An experiment file is data: load it, change what this run needs, hand it to the runner.
    path = EXAMPLES / "experiments" / "clover_fractal.json"
    spec = json.loads(path.read_text())
    spec.setdefault("render", {}).update(width=args.size, height=args.size)
    spec["outputs"] = {"exr": "clover_fractal.exr", "png": "clover_fractal.png"}
    exp = io.parse_experiment(json.dumps(spec), path.name, path.parent)
    report = experiment.run(exp, out_dir=args.out, quiet=args.quiet)
    say(args, f"clover_fractal: {report.free_coefficients} free coefficients, residual {report.residual:.1e}")


PICTURES = {"wave": wave, "hills": hills, "fern": fern, "clover_fractal": clover_fractal}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/python"), help="output folder (created)")
    parser.add_argument("--size", type=int, default=1024, help="image width and height in pixels")
    parser.add_argument("--samples", type=int, default=1 << 22, help="chaos-game samples of the fern")
    parser.add_argument("--quiet", action="store_true", help="no progress and no summary lines")
    parser.add_argument("pictures", nargs="*", metavar="PICTURE", help=f"any of {', '.join(PICTURES)} (default: all)")
    args = parser.parse_args(argv)
    for name in args.pictures:
        if name not in PICTURES:
            parser.error(f"unknown picture '{name}' (choose from {', '.join(PICTURES)})")
    args.out.mkdir(parents=True, exist_ok=True)
    try:
        for name in args.pictures or PICTURES:
            PICTURES[name](args)
    except (cifs.InvalidInput, cifs.IoError) as error:
        print(f"gallery.py: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
