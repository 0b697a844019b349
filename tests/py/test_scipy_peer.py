#!/usr/bin/python3
"""Peer check: `li-strain` is the natural (closed: periodic) C2 cubic spline on its knots.

Runs `$FAIRSPLINE_CLI fit INPUT.json -m li-strain -f json` on several data sets and compares the
curve with SciPy's CubicSpline(knots, points, bc_type='natural') (open) or 'periodic' (closed,
the first point appended at the end) built on the knots the CLI reports. Positions and first
derivatives d/dt are compared at every knot (from both sides), at fixed fractions of every
span and at random parameters, to 1e-10 relative to the data's scale (positions: largest
extent of the points; derivatives: largest chord slope |P_{i+1} - P_i| / (t_{i+1} - t_i)).
The reported knots are also checked against the alpha-parameterization
t_{i+1} = t_i + |P_{i+1} - P_i|^alpha.

Environment: FAIRSPLINE_CLI = path of the fairspline command (set by CTest).
Plain script (no pytest): prints one line per failure and `scipy peer: P passed, F failed`;
exit status 0 only when every case passes.
"""

import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.interpolate import CubicSpline

REL_TOL = 1e-10
KNOT_REL_TOL = 1e-13
SPAN_FRACTIONS = np.array([0.0, 0.1, 0.25, 1.0 / 3.0, 0.5, 0.7, 0.9, 1.0])
RANDOM_PARAMETERS = 200

LI_EXAMPLE = [(1, 90), (3, 105), (6, 120), (10, 100), (12, 85), (15, 104), (17, 80)]
ALPHAS = [0.0, 0.5, 2.0 / 3.0, 1.0]


def random_walk(n, seed):
    """Planar random walk: turns uniform in +-120 degrees, steps uniform in [0.5, 2]."""
    rng = np.random.default_rng(seed)
    heading = np.cumsum(rng.uniform(-2.0 * math.pi / 3.0, 2.0 * math.pi / 3.0, n - 1))
    step = rng.uniform(0.5, 2.0, n - 1)
    xy = np.zeros((n, 2))
    xy[1:, 0] = np.cumsum(step * np.cos(heading))
    xy[1:, 1] = np.cumsum(step * np.sin(heading))
    # Shift away from the origin so that absolute and relative errors differ.
    return xy + np.array([100.0, -50.0])


DATA_SETS = [
    ("li-example", np.array(LI_EXAMPLE, dtype=float)),
    ("walk-10", random_walk(10, 10)),
    ("walk-100", random_walk(100, 100)),
    ("walk-1000", random_walk(1000, 1000)),
]


def run_cli(cli, points, closed, alpha, workdir):
    path = os.path.join(workdir, "input.json")
    with open(path, "w") as f:
        json.dump({"points": points.tolist(), "closed": closed, "alpha": alpha}, f)
    cmd = [cli, "fit", path, "-m", "li-strain", "-f", "json"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, "{} exited with {}: {}".format(
        " ".join(cmd), proc.returncode, proc.stderr.strip())
    try:
        return json.loads(proc.stdout)
    except json.JSONDecodeError as e:
        raise AssertionError("CLI output is not JSON ({}): {!r}".format(e, proc.stdout[:200]))


def expected_knots(points, alpha, closed):
    pts = np.vstack((points, points[:1])) if closed else points
    d = np.diff(pts, axis=0)
    dt = np.hypot(d[:, 0], d[:, 1]) ** alpha
    return np.concatenate(([0.0], np.cumsum(dt)))


def bezier(ctrl, u):
    """Points and derivatives d/du of Bézier pieces: ctrl (m, 4, 2), u (m,)."""
    u = u[:, None]
    v = 1.0 - u
    p0, p1, p2, p3 = ctrl[:, 0], ctrl[:, 1], ctrl[:, 2], ctrl[:, 3]
    pos = v**3 * p0 + 3.0 * v * v * u * p1 + 3.0 * v * u * u * p2 + u**3 * p3
    der = 3.0 * (v * v * (p1 - p0) + 2.0 * v * u * (p2 - p1) + u * u * (p3 - p2))
    return pos, der


def fairspline_eval(ctrl, t0, t1, seg, t):
    """Evaluates piece seg[j] at global parameter t[j]; derivative with respect to t."""
    h = t1[seg] - t0[seg]
    pos, der = bezier(ctrl[seg], (t - t0[seg]) / h)
    return pos, der / h[:, None]


def check_case(cli, name, points, closed, alpha, workdir, rng):
    n = len(points)
    out = run_cli(cli, points, closed, alpha, workdir)
    segs = out.get("segments")
    if segs is None and isinstance(out.get("spline"), dict):
        segs = out["spline"].get("segments")
    assert "knots" in out and segs is not None, "CLI output lacks 'knots' or 'segments': keys {}".format(
        sorted(out))
    knots = np.array(out["knots"], dtype=float)
    spans = n if closed else n - 1
    assert len(knots) == spans + 1, "expected {} knots, got {}".format(spans + 1, len(knots))
    assert len(segs) == spans, "expected {} segments, got {}".format(spans, len(segs))

    ref_knots = expected_knots(points, alpha, closed)
    knot_err = np.max(np.abs(knots - ref_knots)) / ref_knots[-1]
    assert knot_err <= KNOT_REL_TOL, "knots differ from the alpha-parameterization by {:.3g} " \
        "(relative to t_end)".format(knot_err)

    ctrl = np.array([s["bezier"] for s in segs], dtype=float)
    t0 = np.array([s["t0"] for s in segs], dtype=float)
    t1 = np.array([s["t1"] for s in segs], dtype=float)
    span = np.array([s.get("span", k) for s, k in zip(segs, range(spans))])
    assert ctrl.shape == (spans, 4, 2), "bezier arrays have shape {}".format(ctrl.shape)
    assert np.array_equal(span, np.arange(spans)), "segments are not one per span in order"
    assert np.array_equal(t0, knots[:-1]) and np.array_equal(t1, knots[1:]), \
        "segment parameter intervals [t0, t1] are not the knot intervals"

    scale = float(np.max(np.ptp(points, axis=0)))
    closed_pts = np.vstack((points, points[:1])) if closed else points
    chords = np.diff(closed_pts, axis=0)
    slope_scale = float(np.max(np.hypot(chords[:, 0], chords[:, 1]) / np.diff(knots)))
    pos_tol, der_tol = REL_TOL * scale, REL_TOL * slope_scale

    end_err = max(np.max(np.abs(ctrl[:, 0] - closed_pts[:-1])),
                  np.max(np.abs(ctrl[:, 3] - closed_pts[1:])))
    assert end_err <= pos_tol, "piece end points miss the input points by {:.3g}".format(end_err)

    peer = CubicSpline(knots, closed_pts, bc_type="periodic" if closed else "natural", axis=0)

    # Parameters: fractions of every span (knots included, from both sides) and random ones.
    h = np.diff(knots)
    seg = np.repeat(np.arange(spans), len(SPAN_FRACTIONS))
    t = (knots[:-1, None] + SPAN_FRACTIONS[None, :] * h[:, None]).ravel()
    t[SPAN_FRACTIONS.size - 1::SPAN_FRACTIONS.size] = knots[1:]  # exact right knots
    t_rand = rng.uniform(knots[0], knots[-1], RANDOM_PARAMETERS)
    seg_rand = np.clip(np.searchsorted(knots, t_rand, side="right") - 1, 0, spans - 1)
    t = np.concatenate((t, t_rand))
    seg = np.concatenate((seg, seg_rand))

    pos, der = fairspline_eval(ctrl, t0, t1, seg, t)
    pos_err = np.abs(pos - peer(t)).max(axis=1)
    der_err = np.abs(der - peer(t, 1)).max(axis=1)
    worst_p, worst_d = int(np.argmax(pos_err)), int(np.argmax(der_err))
    assert pos_err[worst_p] <= pos_tol, (
        "position differs from SciPy by {:.3g} (tolerance {:.3g}) at t = {!r} in segment {}"
        .format(pos_err[worst_p], pos_tol, t[worst_p], seg[worst_p]))
    assert der_err[worst_d] <= der_tol, (
        "derivative d/dt differs from SciPy by {:.3g} (tolerance {:.3g}) at t = {!r} in "
        "segment {}".format(der_err[worst_d], der_tol, t[worst_d], seg[worst_d]))
    return max(pos_err.max() / scale, der_err.max() / slope_scale)


def main():
    cli = os.environ.get("FAIRSPLINE_CLI")
    if not cli:
        print("test_scipy_peer: FAIRSPLINE_CLI is not set (path of the fairspline command)",
              file=sys.stderr)
        return 2
    if not os.access(cli, os.X_OK):
        print("test_scipy_peer: FAIRSPLINE_CLI={} is not an executable".format(cli),
              file=sys.stderr)
        return 2
    rng = np.random.default_rng(7)
    passed = failed = 0
    worst = 0.0
    with tempfile.TemporaryDirectory(prefix="fairspline-peer-") as workdir:
        for name, points in DATA_SETS:
            for closed in (False, True):
                for alpha in ALPHAS:
                    case = "{} {} alpha={:.4g}".format(name, "closed" if closed else "open", alpha)
                    try:
                        rel = check_case(cli, name, points, closed, alpha, workdir, rng)
                    except AssertionError as e:
                        failed += 1
                        print("FAIL {}: {}".format(case, e))
                    else:
                        passed += 1
                        worst = max(worst, rel)
    print("largest relative difference to SciPy: {:.3g}".format(worst))
    print("scipy peer: {} passed, {} failed".format(passed, failed))
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
