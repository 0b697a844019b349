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

from . import _core
from ._core import DEFAULT_METHOD, Curve, Error, __version__
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


fit = _module_level(_core.fit)
fit_many = _module_level(_core.fit_many)
methods = _module_level(_core.methods)
read_curve_ensemble = _module_level(_core.read_curve_ensemble)

__all__ = ["Curve", "DEFAULT_METHOD", "Error", "fit", "fit_many", "methods", "plot",
           "read_curve_ensemble", "__version__"]
