# Type stubs of the fairspline package (the compiled fairspline._core and its pure-Python
# helpers). tests/python/test_stubs.py checks them against the module: every public name,
# every parameter's name, kind and default, and the method names of MethodName.
from typing import Any, Callable, Iterable, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
DEFAULT_METHOD: str

MethodName = Literal[
    "quasi-elastic",
    "cond-g2",
    "min-energy",
    "restricted-elastic",
    "elastic",
    "jaklic-zagar",
    "li-strain",
    "li-curvature-variation",
    "li-combined",
    "kozak-krajnc",
    "yong-cheng",
]
ReportLevel = Literal["none", "basic", "full"]
SideState = Literal["regular", "clamped", "free"]
PointKind = Literal["smooth", "clamped", "corner"]

_ArrayLike = npt.ArrayLike
_FloatArray = npt.NDArray[np.float64]
_Vector = Union[Tuple[float, float], Sequence[float], _FloatArray]
# A parameter t (or arc length) that is a number gives a number; an array gives an array.
_Scalar = Union[float, int]
_Matrix = Union[Sequence[float], Sequence[Sequence[float]], _FloatArray]

class Error(ValueError):
    code: Optional[str]
    index: Optional[int]
    curve: Optional[int]
    hint: Optional[Tuple[str, Optional[str]]]

class _Geometry:
    """The methods Curve and Path share."""

    @property
    def segments(self) -> _FloatArray: ...
    @property
    def segment_ranges(self) -> _FloatArray: ...
    @property
    def spans(self) -> npt.NDArray[np.int64]: ...
    @property
    def closed(self) -> bool: ...
    @property
    def t_range(self) -> Tuple[float, float]: ...
    def evaluate(self, t: _ArrayLike) -> _FloatArray: ...
    def __call__(self, t: _ArrayLike) -> _FloatArray: ...
    def derivative(self, t: _ArrayLike, order: int = 1) -> _FloatArray: ...
    @overload
    def curvature(self, t: _Scalar) -> float: ...
    @overload
    def curvature(self, t: _ArrayLike) -> Union[float, _FloatArray]: ...
    def length(self, accuracy: float = 1e-12) -> float: ...
    def segment_lengths(self, accuracy: float = 1e-12) -> _FloatArray: ...
    @overload
    def length_at(self, t: _Scalar, accuracy: float = 1e-12) -> float: ...
    @overload
    def length_at(self, t: _ArrayLike, accuracy: float = 1e-12) -> Union[float, _FloatArray]: ...
    @overload
    def t_at_length(self, s: _Scalar, accuracy: float = 1e-12) -> float: ...
    @overload
    def t_at_length(self, s: _ArrayLike, accuracy: float = 1e-12) -> Union[float, _FloatArray]: ...
    def sample_by_length(
        self, count: int, accuracy: float = 1e-12
    ) -> Tuple[_FloatArray, _FloatArray]: ...
    def flatten(self, tolerance: float) -> Tuple[_FloatArray, _FloatArray]: ...
    def bounds(self) -> Tuple[float, float, float, float]: ...
    def project(
        self, q: _ArrayLike
    ) -> Tuple[Union[float, _FloatArray], _FloatArray, Union[float, _FloatArray]]: ...
    def frames(self, t: _ArrayLike) -> Tuple[_FloatArray, _FloatArray, _FloatArray]: ...
    def split(self, t: float) -> Tuple[Path, Path]: ...
    def subcurve(self, t0: float, t1: float) -> Path: ...
    def reversed(self) -> Path: ...
    def transformed(self, matrix: _Matrix) -> Path: ...
    def svg_path(self) -> str: ...
    def draw(self, pen: Any) -> None: ...
    def to_geojson(self, tolerance: float = 0.0) -> dict[str, Any]: ...
    def to_matplotlib_path(self) -> Any: ...

class Path(_Geometry):
    def __init__(
        self,
        segments: _ArrayLike,
        segment_ranges: _ArrayLike,
        spans: Sequence[int],
        closed: bool = False,
    ) -> None: ...
    def __eq__(self, other: object) -> bool: ...

class Curve(_Geometry):
    @property
    def method(self) -> str: ...
    @property
    def options(self) -> dict[str, Any]: ...
    @property
    def points(self) -> _FloatArray: ...
    @property
    def knots(self) -> _FloatArray: ...
    @property
    def tangents(self) -> _FloatArray: ...
    @property
    def path(self) -> Path: ...
    @property
    def report(self) -> Optional[dict[str, Any]]: ...
    @property
    def method_report(self) -> dict[str, Any]: ...
    @property
    def request(self) -> dict[str, Any]: ...
    def sample(self, count: int) -> _FloatArray: ...
    def to_json(self, indent: Optional[int] = None) -> str: ...
    def to_svg(self, **options: Any) -> str: ...
    def to_curve_ensemble(self) -> str: ...
    @staticmethod
    def from_json(text: str) -> Curve: ...
    def _repr_svg_(self) -> str: ...
    def __eq__(self, other: object) -> bool: ...

def fit(
    points: _ArrayLike,
    method: Union[MethodName, str] = "quasi-elastic",
    closed: bool = False,
    alpha: Optional[float] = None,
    start_tangent: Optional[_Vector] = None,
    end_tangent: Optional[_Vector] = None,
    *,
    tangents: Optional[Sequence[Optional[_Vector]]] = None,
    kinds: Optional[Sequence[PointKind]] = None,
    states: Optional[Sequence[Union[SideState, Tuple[SideState, SideState]]]] = None,
    in_tangents: Optional[Sequence[Optional[_Vector]]] = None,
    out_tangents: Optional[Sequence[Optional[_Vector]]] = None,
    corners_deg: Optional[_ArrayLike] = None,
    radii: Optional[_ArrayLike] = None,
    knots: Optional[_ArrayLike] = None,
    report: ReportLevel = "basic",
    accuracy: Optional[float] = None,
    best_effort: bool = False,
    diagnostics: bool = True,
    time_limit: Optional[float] = None,
    progress: Optional[Callable[[str, int, int, float], Any]] = None,
    options: Optional[dict[str, Any]] = None,
    **kwargs: Any,
) -> Curve: ...
def fit_many(
    curves: Iterable[_ArrayLike],
    method: Union[MethodName, str] = "quasi-elastic",
    closed: bool = False,
    alpha: Optional[float] = None,
    start_tangent: Optional[_Vector] = None,
    end_tangent: Optional[_Vector] = None,
    *,
    threads: Optional[int] = None,
    report: ReportLevel = "basic",
    accuracy: Optional[float] = None,
    best_effort: bool = False,
    diagnostics: bool = True,
    time_limit: Optional[float] = None,
    errors: Literal["raise", "return"] = "raise",
    progress: Optional[Callable[[int, int], Any]] = None,
    options: Optional[dict[str, Any]] = None,
    **kwargs: Any,
) -> list[Any]: ...
def methods() -> list[dict[str, Any]]: ...
def read_curve_ensemble(path: str) -> dict[str, Any]: ...
def keep_fit_memory(keep: bool) -> None: ...
def plot(
    curve: Curve,
    ax: Any = None,
    comb: bool = False,
    points: bool = True,
    *,
    samples_per_segment: int = 32,
    comb_samples_per_segment: int = 16,
    comb_scale: Optional[float] = None,
    control_polygon: bool = False,
    label: Optional[str] = None,
    **line_kwargs: Any,
) -> Any: ...
