# SPDX-License-Identifier: MIT
"""cifs — NURBS curves and surfaces and subdivision schemes as controlled iterated function systems.

Submodules mirror the C++ library (docs/python.md):

- ``cifs.nurbs``        curves and surfaces: evaluation, knot insertion, blossoms, subdivision matrices
- ``cifs.automata``     automata whose transitions carry matrices (knot doubling, tensor products, hand-made)
- ``cifs.ifs``          attractors, contraction, chaos game, meshes, BC-IFS free coefficients, dimension
- ``cifs.subdivision``  curve subdivision schemes and their analysis
- ``cifs.render``       cameras, rasterisers, chaos-game density, OpenEXR and PNG
- ``cifs.io``           every file format (shapes, polygons, meshes, automata, BC-IFS, experiments), by extension
- ``cifs.verify``       the attractor against knot insertion and Cox–de Boor
- ``cifs.experiment``   running experiment files

Errors raised by the library are :class:`InvalidInput` (a ``ValueError``: bad knots, weights, sizes,
parameters …) and :class:`IoError` (an ``OSError``: files), with the messages of the C++ library and
of the ``cifs`` command line.
"""
import sys as _sys

try:
    import numpy as _numpy  # noqa: F401 — every array crosses as numpy: fail here, not at the first call
    from . import _cifs
except ImportError as _error:  # another interpreter than the build's, or one without numpy
    import glob as _glob
    import os as _os
    _here = _os.path.dirname(_os.path.abspath(__file__))
    _built = sorted(_os.path.basename(p) for p in _glob.glob(_os.path.join(_here, "_cifs*")))
    if not _built:  # only a build tree (build/python/cifs) has the package without its extension
        raise ImportError(
            f"cifs: the extension cifs._cifs is not built: cmake --build {_os.path.dirname(_os.path.dirname(_here))} "
            "--target cifs_python") from _error
    raise ImportError(
        f"cifs: the extension {', '.join(_built)} does not load in this interpreter "
        f"({_sys.executable}, Python {_sys.version.split()[0]}): {_error}. Run scripts with build/cifs-python, "
        "which uses the interpreter the module was built for") from _error
from ._cifs import InvalidInput, IoError, __version__

nurbs = _cifs.nurbs
automata = _cifs.automata
ifs = _cifs.ifs
subdivision = _cifs.subdivision
render = _cifs.render
io = _cifs.io
verify = _cifs.verify
experiment = _cifs.experiment

# `import cifs.nurbs` and `from cifs.ifs import box_counting` work like for package submodules.
for _name in ("nurbs", "automata", "ifs", "subdivision", "render", "io", "verify", "experiment"):
    _sys.modules[f"{__name__}.{_name}"] = getattr(_cifs, _name)



# --- One rule for arrays read from attributes: they are read-only ---------------------------------------------
# Every attribute (property) of every bound type returns a copy of the object's data; writing into that copy
# (`curve.P[0, 0] = 99`) would be silently lost, so the arrays an attribute returns (also inside the tuples,
# lists and dicts it returns) are marked read-only and such a write raises ValueError. Change an object
# through its constructor, its methods or a property setter; `.copy()` an array to edit it.
def _read_only(value):
    if isinstance(value, _numpy.ndarray):
        value.flags.writeable = False
    elif isinstance(value, (list, tuple)):
        for item in value:
            _read_only(item)
    elif isinstance(value, dict):
        for item in value.values():
            _read_only(item)
    return value


def _read_only_getter(fget):
    def get(self):
        return _read_only(fget(self))

    get.__doc__ = fget.__doc__
    get.__wrapped__ = fget  # the pybind11 getter, whose docstring signature the stub generator reads
    return get


def _read_only_attributes(module):
    for cls in vars(module).values():
        if not isinstance(cls, type) or getattr(cls, "__module__", "").split(".")[:2] != ["cifs", "_cifs"]:
            continue
        for name, attribute in list(vars(cls).items()):
            if type(attribute) is property and attribute.fget is not None and not hasattr(attribute.fget,
                                                                                           "__wrapped__"):
                setattr(cls, name, property(_read_only_getter(attribute.fget), attribute.fset, attribute.fdel,
                                            attribute.__doc__))


for _name in ("nurbs", "automata", "ifs", "subdivision", "render", "io", "verify", "experiment"):
    _read_only_attributes(getattr(_cifs, _name))


# --- Rows that know whether they are homogeneous --------------------------------------------------------------
# ifs.cartesian divides rows (w·x, w) by their last column, and bare rows cannot say whether that column is a
# weight or a 3-D curve's z: README's ifs.cartesian(ifs.attractor_points(…)) divided a non-rational curve's x
# and y by its z (issue 32). The nets of a shape (automata.initial_nets) know, and so do the points made from
# them (ifs.attractor_points, StencilTable.apply) and ifs.cartesian's result; ifs.cartesian refuses rows known
# to be Cartesian. curve.attractor(depth) and surface.attractor(depth) stay the one route to a shape's points.
class Rows(_numpy.ndarray):
    """A float array of control-net or attractor rows that knows whether they are homogeneous `(w·x, w)` (the
    nets of a rational shape and the points made from them) or Cartesian: `homogeneous` is True or False, None
    when unknown. automata.initial_nets, ifs.attractor_points, StencilTable.apply and ifs.cartesian return them;
    ifs.cartesian refuses rows known to be Cartesian. Otherwise a numpy array like any other (slices and
    arithmetic keep the flag; numpy.asarray(rows) drops it)."""

    homogeneous: "Optional[bool]" = None

    def __array_finalize__(self, obj):
        self.homogeneous = getattr(obj, "homogeneous", None)


def _rows(array, homogeneous):
    rows = array.view(Rows)
    rows.homogeneous = homogeneous
    return rows


def _known(nets):
    """True or False when every net knows and all agree, else None."""
    flags = {getattr(net, "homogeneous", None) for net in nets}
    return flags.pop() if len(flags) == 1 else None


def _argument(args, kwargs, index, *names):
    """The argument at `index`, or given by one of `names`."""
    for name in names:
        if name in kwargs:
            return kwargs[name]
    return args[index]


def _wrapped(function, body):
    """`body(function, *args, **kwargs)` with `function`'s name and docstring (whose signature lines the stubs
    and the tests read)."""
    def call(*args, **kwargs):
        return body(function, *args, **kwargs)

    call.__name__, call.__qualname__, call.__doc__ = function.__name__, function.__qualname__, function.__doc__
    call.__wrapped__ = function
    return call


def _initial_nets(function, *args, **kwargs):
    nets = function(*args, **kwargs)
    rational = bool(_argument(args, kwargs, 1, "curve", "surface").rational)
    return [_rows(net, rational) for net in nets]


def _points_of_nets(nets_index):
    def body(function, *args, **kwargs):
        points = function(*args, **kwargs)
        return _rows(points, _known(_argument(args, kwargs, nets_index, "nets")))
    return body


def _cartesian(function, *args, **kwargs):
    rows = _argument(args, kwargs, 0, "homogeneous")
    if isinstance(rows, Rows) and rows.homogeneous is False:
        raise InvalidInput("cartesian: homogeneous: the rows are Cartesian already (the nets of a shape that is not "
                           "rational, or points made from them); curve.attractor(depth) and surface.attractor(depth) "
                           "give the Cartesian points of any shape")
    return _rows(function(*args, **kwargs), False)


ifs.Rows = Rows
Rows.__module__ = "cifs.ifs"
automata.initial_nets = _wrapped(automata.initial_nets, _initial_nets)
ifs.attractor_points = _wrapped(ifs.attractor_points, _points_of_nets(1))
ifs.StencilTable.apply = _wrapped(ifs.StencilTable.apply, _points_of_nets(1))
ifs.cartesian = _wrapped(ifs.cartesian, _cartesian)


# --- Notebook previews: _repr_png_ on images and shapes ---------------------------------------------------------
def _png_bytes(image) -> "bytes | None":
    """The PNG that render.preview_png writes for `image`, as bytes (None when it has nothing to show)."""
    import os
    import tempfile
    if image.width == 0 or image.height == 0:
        return None
    with tempfile.TemporaryDirectory(prefix="cifs-png-") as folder:
        path = os.path.join(folder, "preview.png")
        try:
            render.preview_png(path, image)
        except InvalidInput:  # e.g. no colour or density channel: the notebook falls back to repr
            return None
        with open(path, "rb") as file:
            return file.read()


_PREVIEW_SIZE = (320, 240)


def _curve_image(curve, width=_PREVIEW_SIZE[0], height=_PREVIEW_SIZE[1]):
    """A small preview render of a 2-D or 3-D curve: the curve over its control polygon (None otherwise)."""
    if curve.dimension not in (2, 3):
        return None
    points = curve.evaluate(nurbs.uniform_parameters(curve.domain, 513))
    polygon = curve.points
    camera = render.frame(_numpy.vstack([points, polygon]), width=width, height=height, margin=0.05)
    image = render.make_framebuffer(camera)
    render.render_polylines(image, camera, [polygon], width=1, color=(0.45, 0.45, 0.45), closed=curve.closed)
    render.render_polylines(image, camera, [points], width=2, color=(0.1, 0.3, 0.9))
    return image


def _surface_image(surface, width=_PREVIEW_SIZE[0], height=_PREVIEW_SIZE[1], samples=33):
    """A small shaded preview render of a 3-D surface (None otherwise)."""
    if surface.dimension != 3:
        return None
    (u0, u1), (v0, v1) = surface.domain
    grid = surface.evaluate_grid(_numpy.linspace(u0, u1, samples), _numpy.linspace(v0, v1, samples))
    vertices = grid.reshape(-1, 3)
    i, j = _numpy.meshgrid(_numpy.arange(samples - 1), _numpy.arange(samples - 1), indexing="ij")
    corner = (i * samples + j).ravel()
    quads = _numpy.stack([corner, corner + samples, corner + samples + 1, corner + 1], axis=1)
    camera = render.frame(vertices, width=width, height=height)
    image = render.make_framebuffer(camera)
    render.render_mesh(image, camera, vertices, quads=quads)
    return image


def _mesh_image(mesh, width=_PREVIEW_SIZE[0], height=_PREVIEW_SIZE[1]):
    """A small shaded preview render of a polygon mesh: every face as its fan, holes left out."""
    camera = render.frame(mesh.vertices, width=width, height=height)
    image = render.make_framebuffer(camera)
    render.render_mesh(image, camera, mesh)
    return image


def _mesh_png(self) -> "bytes | None":
    return _png_bytes(_mesh_image(self))


def _shape_png(self) -> "bytes | None":
    image = _curve_image(self) if isinstance(self, nurbs.Curve) else _surface_image(self)
    return None if image is None else _png_bytes(image)


render.Image._repr_png_ = _png_bytes
render.Image._repr_png_.__doc__ = "The image's preview_png as PNG bytes, shown by notebooks (None when empty)."
nurbs.Curve._repr_png_ = _shape_png
nurbs.Surface._repr_png_ = _shape_png
io.Mesh._repr_png_ = _mesh_png
_mesh_png.__doc__ = ("A small shaded preview render (320 by 240) of the mesh as PNG bytes, shown by notebooks: every\n"
                     "face as its fan of triangles, holes left out.")
# The automata that wrap one: drawn as it (Automaton._repr_svg_).
subdivision.SurfaceAutomaton._repr_svg_ = lambda self: self.automaton._repr_svg_()
automata.TensorAutomaton._repr_svg_ = lambda self: self.product._repr_svg_()
_shape_png.__doc__ = ("A small preview render (320 by 240) as PNG bytes, shown by notebooks: curves of 2 or 3\n"
                      "dimensions over their control polygon, 3-D surfaces shaded; None for other dimensions.")

__all__ = ["InvalidInput", "IoError", "__version__", "nurbs", "automata", "ifs", "subdivision", "render", "io",
           "verify", "experiment"]
