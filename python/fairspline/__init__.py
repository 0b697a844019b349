"""fairspline: fair cubic Bézier splines through planar points.

    >>> import fairspline
    >>> curve = fairspline.fit([(1, 90), (3, 105), (6, 120), (10, 100)], method="li-strain")
    >>> curve.segments.shape            # (pieces, 4 control points, xy)
    (3, 4, 2)
    >>> xy = curve.evaluate(curve.knots)  # the input points again

fit() and fit_many() run the C++ library with the GIL released; methods() lists the registered
methods with their option schemas; plot() draws a Curve with Matplotlib. Errors raise
fairspline.Error, a ValueError with .code (e.g. "repeated_point") and .index (the offending
point). The compiled part is fairspline._core; its docstrings come from the C++ headers.
"""

import functools as _functools
from typing import Literal as _Literal
from typing import Union as _Union

from . import _core
from ._core import DEFAULT_METHOD, Curve, Error, Path, __version__
from .plot import plot


def _module_level(function):
    # pybind11's functions are bound to a PyCapsule and cannot be pickled, so
    # ProcessPoolExecutor.map(fairspline.fit, ...) failed; a Python function pickles by name.
    @_functools.wraps(function)
    def wrapper(*args, **kwargs):
        return function(*args, **kwargs)

    wrapper.__module__ = __name__
    wrapper.__qualname__ = function.__name__
    return wrapper


# The choices of fit's string arguments, for type annotations (the stub __init__.pyi has the
# same; tests/python/test_stubs.py checks MethodName against methods()). Unions of one-value
# Literals: the same type as Literal["a", "b"], in the form mypy's stubtest compares.
def _choices(*values):
    return _Union[tuple(_Literal[v] for v in values)]


MethodName = _choices("quasi-elastic", "cond-g2", "min-energy", "restricted-elastic", "elastic",
                      "jaklic-zagar", "li-strain", "li-curvature-variation", "li-combined",
                      "kozak-krajnc", "yong-cheng")
ReportLevel = _choices("none", "basic", "full")
SideState = _choices("regular", "clamped", "free")
PointKind = _choices("smooth", "clamped", "corner")


def _to_matplotlib_path(self):
    """The curve as a matplotlib.path.Path: MOVETO, then CURVE4 control points per piece, and
    CLOSEPOLY for a closed curve; for PathPatch, clipping, contains_points and get_extents.

    Returns
    -------
    matplotlib.path.Path

    Examples
    --------
    >>> import fairspline
    >>> curve = fairspline.fit([(0, 0), (1, 1), (2, 0)])
    >>> curve.to_matplotlib_path().codes[:4].tolist()
    [1, 4, 4, 4]
    """
    import numpy as np
    from matplotlib.path import Path as MplPath

    segments = self.segments
    m = len(segments)
    vertices = np.concatenate([segments[:1, 0], segments[:, 1:].reshape(3 * m, 2)])
    codes = np.full(len(vertices), MplPath.CURVE4, dtype=MplPath.code_type)
    codes[0] = MplPath.MOVETO
    if self.closed:
        vertices = np.concatenate([vertices, vertices[:1]])
        codes = np.append(codes, MplPath.CLOSEPOLY).astype(MplPath.code_type)
    return MplPath(vertices, codes)


Curve.to_matplotlib_path = _to_matplotlib_path
Path.to_matplotlib_path = _to_matplotlib_path

fit = _module_level(_core.fit)
fit_many = _module_level(_core.fit_many)
methods = _module_level(_core.methods)
read_curve_ensemble = _module_level(_core.read_curve_ensemble)
keep_fit_memory = _module_level(_core.keep_fit_memory)

__all__ = ["Curve", "DEFAULT_METHOD", "Error", "MethodName", "Path", "PointKind", "ReportLevel",
           "SideState", "fit", "fit_many", "keep_fit_memory", "methods", "plot",
           "read_curve_ensemble", "__version__"]
