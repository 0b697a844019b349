"""The geometry and exports of Curve and Path (issue 21) against analytic answers, SciPy's
quadrature, finite differences, shapely, fontTools pens and matplotlib."""

import doctest
import json
import math
import pickle

import numpy as np
import pytest

import fairspline
from conftest import example_points, random_walk


def circle(n, r=2.0):
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


@pytest.fixture(scope="module")
def curve():
    return fairspline.fit(example_points())


def test_length_against_scipy_quadrature(curve):
    from scipy.integrate import quad

    total = 0.0
    for (t0, t1) in curve.segment_ranges:
        value, _ = quad(lambda t: np.linalg.norm(curve.derivative(t)), t0, t1,
                        epsabs=0, epsrel=1e-13, limit=200)
        total += value
    assert curve.length() == pytest.approx(total, rel=1e-11)
    assert curve.segment_lengths().sum() == pytest.approx(total, rel=1e-12)
    # The fitted circle is within its approximation error of 2πr.
    assert fairspline.fit(circle(64), closed=True).length() == pytest.approx(4 * np.pi, abs=1e-5)


def test_straight_line_arc_length_is_exact():
    line = fairspline.fit([(0, 0), (1, 0), (3, 0), (3.5, 0)])
    assert line.length() == pytest.approx(3.5, abs=1e-13)
    s = np.array([[0.0, 0.25], [1.7, 3.5]])
    t = line.t_at_length(s)
    assert t.shape == (2, 2)
    np.testing.assert_allclose(line(t)[..., 0], s, atol=1e-11)
    np.testing.assert_allclose(line.length_at(t), s, atol=1e-11)
    assert isinstance(line.t_at_length(1.0), float)


def test_length_at_derivative_is_the_speed(curve):
    t0, t1 = curve.t_range
    t = np.linspace(t0, t1, 9)[1:-1]
    h = 1e-5
    fd = (curve.length_at(t + h) - curve.length_at(t - h)) / (2 * h)
    np.testing.assert_allclose(fd, np.linalg.norm(curve.derivative(t), axis=-1), rtol=1e-7)


def test_sample_by_length_is_evenly_spaced(curve):
    points, t = curve.sample_by_length(33)
    assert points.shape == (33, 2) and t.shape == (33,)
    assert (t[0], t[-1]) == curve.t_range
    np.testing.assert_array_equal(points, curve(t))
    steps = np.diff(curve.length_at(t))
    np.testing.assert_allclose(steps, curve.length() / 32, rtol=1e-10)


def test_flatten_within_tolerance_and_geojson_with_shapely(curve):
    shapely = pytest.importorskip("shapely.geometry")
    for tol in (1.0, 0.01, 1e-4):
        points, t = curve.flatten(tol)
        np.testing.assert_allclose(points, curve(t), atol=1e-12)
        # Every curve point near the polyline, every polyline point near the curve.
        line = shapely.LineString(points)
        dense = curve(np.linspace(*curve.t_range, 4001))
        assert max(line.distance(shapely.Point(p)) for p in dense) <= tol
        mids = (points[1:] + points[:-1]) / 2
        assert curve.project(mids)[2].max() <= tol
        # A polyline inscribed within tol: shorter than the curve, by little.
        assert line.length <= curve.length() + 1e-9
        assert line.length == pytest.approx(curve.length(), rel=tol)
    feature = curve.to_geojson(0.01)
    geometry = shapely.shape(feature["geometry"])
    assert feature["type"] == "Feature" and geometry.geom_type == "LineString"
    assert geometry.is_valid
    assert geometry.length == pytest.approx(curve.length(), rel=1e-3)
    assert feature["properties"]["method"] == curve.method
    assert feature["properties"]["length"] == curve.length()
    json.dumps(feature)  # plain JSON types
    ring = fairspline.fit(circle(12), closed=True).to_geojson()
    coordinates = ring["geometry"]["coordinates"]
    assert coordinates[0] == coordinates[-1]
    assert shapely.shape(ring["geometry"]).is_ring


def test_bounds_against_fonttools_and_matplotlib(curve):
    from fontTools.pens.boundsPen import BoundsPen

    pen = BoundsPen(None)
    curve.draw(pen)
    np.testing.assert_allclose(curve.bounds(), pen.bounds, rtol=1e-12)
    dense = curve(np.linspace(*curve.t_range, 100001))
    lo, hi = dense.min(axis=0), dense.max(axis=0)
    b = curve.bounds()
    assert b[0] <= lo[0] and b[1] <= lo[1] and b[2] >= hi[0] and b[3] >= hi[1]
    np.testing.assert_allclose(b, [lo[0], lo[1], hi[0], hi[1]], atol=1e-6)
    extents = curve.to_matplotlib_path().get_extents()
    np.testing.assert_allclose([extents.x0, extents.y0, extents.x1, extents.y1], b, rtol=1e-9)


def test_recording_pen_and_svg_path_hold_the_control_points():
    from fontTools.pens.recordingPen import RecordingPen

    for closed in (False, True):
        c = fairspline.fit(circle(7) if closed else random_walk(9, 3), closed=closed)
        pen = RecordingPen()
        c.draw(pen)
        segments = c.segments
        assert pen.value[0] == ("moveTo", (tuple(segments[0, 0]),))
        curves = [args for op, args in pen.value if op == "curveTo"]
        np.testing.assert_array_equal(np.array(curves), segments[:, 1:])
        assert pen.value[-1] == ("closePath" if closed else "endPath", ())
        d = c.svg_path()
        assert d.startswith("M") and d.endswith(" Z") == closed
        numbers = np.array([float(x) for x in d.replace("M", " ").replace("C", " ")
                            .replace("Z", " ").split()])
        expected = np.concatenate([segments[0, 0], segments[:, 1:].ravel()])
        np.testing.assert_array_equal(numbers, expected)  # round-trip digits: bit for bit


def test_matplotlib_path_codes():
    from matplotlib.path import Path as MplPath

    c = fairspline.fit(circle(6), closed=True)
    p = c.to_matplotlib_path()
    m = len(c.segments)
    assert p.codes[0] == MplPath.MOVETO and p.codes[-1] == MplPath.CLOSEPOLY
    assert (p.codes[1:-1] == MplPath.CURVE4).all() and len(p.codes) == 3 * m + 2
    assert p.contains_point((0, 0)) and not p.contains_point((3, 0))


def test_projection_against_brute_force(curve):
    rng = np.random.default_rng(1)
    q = np.column_stack([rng.uniform(-2, 20, 40), rng.uniform(70, 130, 40)])
    t, points, dist = curve.project(q)
    assert t.shape == (40,) and points.shape == (40, 2) and dist.shape == (40,)
    dense_t = np.linspace(*curve.t_range, 200001)
    dense = curve(dense_t)
    for k in range(len(q)):
        brute = np.linalg.norm(dense - q[k], axis=1).min()
        assert dist[k] <= brute + 1e-12
        assert dist[k] >= brute - 1e-5  # the dense grid's spacing bounds how far it can be off
    t1, p1, d1 = curve.project(q[0])
    assert isinstance(t1, float) and p1.shape == (2,) and d1 == dist[0]


def test_frames_are_orthonormal_and_follow_the_derivative(curve):
    t = np.linspace(*curve.t_range, 12).reshape(3, 4)
    points, tangents, normals = curve.frames(t)
    assert points.shape == tangents.shape == normals.shape == (3, 4, 2)
    np.testing.assert_allclose(np.linalg.norm(tangents, axis=-1), 1, atol=1e-15)
    np.testing.assert_allclose((tangents * normals).sum(-1), 0, atol=1e-15)
    np.testing.assert_allclose(tangents[..., 0] * normals[..., 1] - tangents[..., 1] * normals[..., 0],
                               1, atol=1e-15)
    d = curve.derivative(t)
    np.testing.assert_allclose(tangents, d / np.linalg.norm(d, axis=-1, keepdims=True), atol=1e-14)


def test_split_subcurve_reversal_transform_give_paths(curve):
    t0, t1 = curve.t_range
    tm = t0 + 0.3 * (t1 - t0)
    before, after = curve.split(tm)
    assert isinstance(before, fairspline.Path) and before.t_range == (t0, tm)
    assert after.t_range == (tm, t1)
    tb = np.linspace(t0, tm, 50)
    np.testing.assert_allclose(before(tb), curve(tb), atol=1e-11)
    assert before.length() + after.length() == pytest.approx(curve.length(), rel=1e-12)
    part = curve.subcurve(t0 + 0.1, t0 + 0.2)
    assert part(t0 + 0.15) == pytest.approx(curve(t0 + 0.15), abs=1e-11)
    r = curve.reversed()
    ts = np.linspace(t0, t1, 50)
    np.testing.assert_allclose(r(t0 + t1 - ts), curve(ts), atol=1e-11)
    angle = 0.3
    c, s = math.cos(angle), math.sin(angle)
    for matrix in ([c, s, -s, c, 4, 5], [[c, -s, 4], [s, c, 5]], [[c, -s, 4], [s, c, 5], [0, 0, 1]]):
        moved = curve.transformed(matrix)
        expected = curve(ts) @ np.array([[c, s], [-s, c]]) + [4, 5]
        np.testing.assert_allclose(moved(ts), expected, atol=1e-11)
        assert moved.length() == pytest.approx(curve.length(), rel=1e-12)
    # A Path has the same geometry and exports, compares by value and pickles.
    path = curve.path
    assert path == curve.path and path != r
    assert pickle.loads(pickle.dumps(path)) == path
    assert path.svg_path() == curve.svg_path()
    assert path.bounds() == curve.bounds()
    assert "closed" in path.to_geojson()["properties"]
    assert repr(path).startswith("<fairspline.Path segments=")


def test_geometry_errors_name_the_element(curve):
    with pytest.raises(fairspline.Error) as e:
        curve.length_at([curve.t_range[0], curve.t_range[1] + 1])
    assert e.value.code == "invalid_argument" and e.value.index == 1
    with pytest.raises(fairspline.Error) as e:
        curve.t_at_length([1.0, -1.0])
    assert e.value.index == 1
    for call in (lambda: curve.flatten(0), lambda: curve.flatten(float("nan")),
                 lambda: curve.frames(float("nan")), lambda: curve.split(curve.t_range[0]),
                 lambda: curve.subcurve(2.0, 1.0), lambda: curve.sample_by_length(1),
                 lambda: curve.transformed([1, 2, 3]), lambda: curve.length(accuracy=0),
                 lambda: curve.project((1, 2, 3))):
        with pytest.raises(fairspline.Error) as e:
            call()
        assert e.value.code == "invalid_argument", e.value
    with pytest.raises(fairspline.Error) as e:
        curve.project((float("nan"), 0))
    assert e.value.code == "non_finite"


def test_geometry_docstring_examples_run():
    for fn in (fairspline.Curve.length, fairspline.Curve.t_at_length,
               fairspline.Curve.to_matplotlib_path):
        finder = doctest.DocTestFinder()
        runner = doctest.DocTestRunner()
        for test in finder.find(fn, "fairspline", globs={}):
            runner.run(test)
        assert runner.failures == 0 and runner.tries > 0, fn
