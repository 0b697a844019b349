"""Shared helpers of the Python module's pytest suite (tests/python).

CTest runs `/usr/bin/python3 -m pytest -q tests/python` with PYTHONPATH=<build>/python and
FAIRSPLINE_CLI=<build>/apps/cli/fairspline; by hand:
    PYTHONPATH=build/python FAIRSPLINE_CLI=build/apps/cli/fairspline \
        /usr/bin/python3 -m pytest -q tests/python
"""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = SOURCE_DIR / "examples" / "li-example1.csv"
INCLUDE_DIR = SOURCE_DIR / "include" / "fairspline"


def example_points():
    return np.loadtxt(EXAMPLE, delimiter=",", skiprows=1)


def random_walk(n, seed, turn=2.0):
    """Planar random walk with turns uniform in +-turn radians and steps in [0.5, 2]."""
    rng = np.random.default_rng(seed)
    heading = np.cumsum(rng.uniform(-turn, turn, n - 1))
    step = rng.uniform(0.5, 2.0, n - 1)
    xy = np.zeros((n, 2))
    xy[1:, 0] = np.cumsum(step * np.cos(heading))
    xy[1:, 1] = np.cumsum(step * np.sin(heading))
    return xy + np.array([100.0, -50.0])


def bezier_derivatives(ctrl, u):
    """Point, d/du and d2/du2 of cubic Bézier pieces ctrl (k, 4, 2) at local parameters u (k,)."""
    u = u[:, None]
    v = 1.0 - u
    p0, p1, p2, p3 = ctrl[:, 0], ctrl[:, 1], ctrl[:, 2], ctrl[:, 3]
    c = v**3 * p0 + 3 * u * v**2 * p1 + 3 * u**2 * v * p2 + u**3 * p3
    d1 = 3 * (v**2 * (p1 - p0) + 2 * u * v * (p2 - p1) + u**2 * (p3 - p2))
    d2 = 6 * (v * (p2 - 2 * p1 + p0) + u * (p3 - 2 * p2 + p1))
    return c, d1, d2


class Cli:
    def __init__(self, path):
        self.path = path

    def run(self, *args, stdin=None):
        proc = subprocess.run([self.path, *map(str, args)], input=stdin, capture_output=True,
                              text=True, timeout=120)
        assert proc.returncode == 0, "fairspline {} failed: {}".format(
            " ".join(map(str, args)), proc.stderr)
        return proc.stdout

    def fit_json(self, *args, stdin=None):
        return self.run("fit", *args, "-f", "json", stdin=stdin)


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("FAIRSPLINE_CLI")
    if not path or not os.path.exists(path):
        pytest.fail("FAIRSPLINE_CLI must name the fairspline command (CTest sets it)")
    return Cli(path)


def input_json(points, **fields):
    return json.dumps({"points": np.asarray(points).tolist(), **fields})
