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
    _built = sorted(_os.path.basename(p) for p in _glob.glob(_os.path.join(_os.path.dirname(__file__), "_cifs*")))
    raise ImportError(
        f"cifs: the extension {', '.join(_built) or '(missing)'} does not load in this interpreter "
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

__all__ = ["InvalidInput", "IoError", "__version__", "nurbs", "automata", "ifs", "subdivision", "render", "io",
           "verify", "experiment"]
