"""examples/dask_batch.py on a LocalCluster with 2 worker processes gives the single-process
results exactly (segments, energies and per-curve errors, in input order)."""

import os
import subprocess
import sys

import numpy as np
import pytest

import fairspline
from conftest import SOURCE_DIR, random_walk

SCRIPT = SOURCE_DIR / "examples" / "dask_batch.py"
# The script (and the local workers it starts) import the same fairspline as this test.
ENV = {**os.environ,
       "PYTHONPATH": os.path.dirname(os.path.dirname(os.path.abspath(fairspline.__file__)))}


def test_dask_batch_equals_single_process(tmp_path):
    rng = np.random.default_rng(8)
    curves = [random_walk(int(rng.integers(3, 30)), 500 + i, turn=1.4) for i in range(200)]
    curves[57] = np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [2.0, 0.0]])  # repeated point
    curves[140] = np.array([[0.0, 0.0]])  # too few points
    np.savez(tmp_path / "in.npz", points=np.concatenate(curves),
             lengths=[len(c) for c in curves])
    out = tmp_path / "out.npz"
    proc = subprocess.run(
        [sys.executable, str(SCRIPT), "--input", str(tmp_path / "in.npz"), "--workers", "2",
         "--method", "min-energy", "--set", "basis=jaklic-zagar", "--output", str(out)],
        cwd=tmp_path, capture_output=True, text=True, timeout=60, env=ENV)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "2 workers (2 threads)" in proc.stdout
    got = np.load(out)

    expected = fairspline.fit_many(curves, "min-energy", basis="jaklic-zagar", report="basic",
                                   errors="return")
    ok = [c for c in expected if not isinstance(c, fairspline.Error)]
    assert len(ok) == 198
    assert list(got["errors"]) == [c.code if isinstance(c, fairspline.Error) else ""
                                   for c in expected]
    assert got["errors"][57] == "repeated_point" and got["errors"][140] == "too_few_points"
    assert np.array_equal(got["counts"], [0 if isinstance(c, fairspline.Error)
                                          else len(c.segments) for c in expected])
    assert np.array_equal(got["segments"], np.concatenate([c.segments for c in ok]))
    energy = [np.nan if isinstance(c, fairspline.Error) else c.report["linearized_energy"]
              for c in expected]
    assert np.array_equal(got["linearized_energy"], energy, equal_nan=True)
    # The workers' scratch space is gone and nothing was left in the working directory.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.npz", "out.npz"]


@pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")
def test_dask_batch_against_a_scheduler_address(tmp_path):
    """--scheduler ADDRESS: the same script on an already running cluster (here a LocalCluster
    of this test process on loopback; a remote `dask-scheduler` works the same way)."""
    import logging

    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, local_directory=str(tmp_path / "workers"),
                      silence_logs=logging.WARNING) as cluster:
        proc = subprocess.run(
            [sys.executable, str(SCRIPT), "--scheduler", cluster.scheduler_address, "--curves",
             "300", "--points", "12", "--method", "jaklic-zagar", "--check"],
            cwd=tmp_path, capture_output=True, text=True, timeout=60, env=ENV)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "2 workers (2 threads)" in proc.stdout
    assert "results identical" in proc.stdout
