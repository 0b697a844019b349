"""fairspline.plot and the notebook-style example examples/compare_methods.py."""

import os
import struct
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fairspline  # noqa: E402
from conftest import SOURCE_DIR, example_points  # noqa: E402
from fairspline.plot import comb_teeth  # noqa: E402


def test_plot_draws_the_curve_points_and_comb():
    curve = fairspline.fit(example_points(), "jaklic-zagar")
    fig, ax = plt.subplots()
    try:
        assert fairspline.plot(curve, ax=ax, comb=True, control_polygon=True) is ax
        curve_line = ax.lines[0]
        xy = np.column_stack(curve_line.get_data())
        # The drawn polyline lies on the curve and passes through every input point.
        assert np.allclose(xy[0], curve.points[0]) and np.allclose(xy[-1], curve.points[-1])
        for p in curve.points:
            assert np.min(np.hypot(*(xy - p).T)) < 1e-9
        assert curve_line.get_label() == "jaklic-zagar"
        # teeth + envelope + one control polygon per piece + the input points
        assert len(ax.lines) == 1 + 2 + len(curve.segments) + 1
        assert np.array_equal(np.column_stack(ax.lines[-1].get_data()), curve.points)
    finally:
        plt.close(fig)
    ax = fairspline.plot(curve, points=False)  # a new figure
    try:
        assert len(ax.lines) == 1
    finally:
        plt.close(ax.figure)


def test_comb_teeth_follow_the_curvature():
    # A circular arc of radius 2, counter-clockwise: curvature +1/2 everywhere, teeth outward.
    theta = np.linspace(0, np.pi, 9)
    pts = 2 * np.column_stack((np.cos(theta), np.sin(theta)))
    curve = fairspline.fit(pts, "li-strain")
    base, tips = comb_teeth(curve, samples_per_segment=4, scale=1.0)
    t = np.linspace(0.1, 0.9, 5)
    assert np.allclose(curve.curvature(curve.t_range[0] + t * np.ptp(curve.t_range)), 0.5,
                       atol=0.02)
    length = np.hypot(*(tips - base).T)
    assert np.allclose(length, np.abs(curve.curvature(
        np.clip(np.linspace(0, 1, 5)[None, :] * np.diff(curve.segment_ranges) +
                curve.segment_ranges[:, :1], *curve.t_range).ravel())))
    # Away from the center of curvature (the origin): tips farther out than the bases (the
    # natural spline's ends have zero curvature, hence no tooth).
    bent = length > 0.1
    assert bent.sum() >= len(length) - 2
    assert np.all(np.hypot(*tips[bent].T) > np.hypot(*base[bent].T) + 0.1)
    # Automatic scale: the longest tooth is 10% of the larger side of the bounding box.
    base, tips = comb_teeth(curve)
    assert np.isclose(np.hypot(*(tips - base).T).max(), 0.1 * np.ptp(base, axis=0).max())


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    assert head[12:16] == b"IHDR"
    return struct.unpack(">II", head[16:24])


def test_compare_methods_example_writes_a_png(tmp_path):
    out = tmp_path / "compare.png"
    proc = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "compare_methods.py"),
                           "-o", str(out)], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert proc.returncode == 0, proc.stderr
    width, height = png_size(out)
    assert width >= 800 and height >= 500
    assert out.stat().st_size > 50_000  # six panels with combs, not an empty canvas
    for method in ("quasi-elastic", "li-strain", "jaklic-zagar", "kozak-krajnc"):
        assert method in proc.stdout
