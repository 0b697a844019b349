"""fairspline.fit_many, and the GIL released while C++ fits."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import fairspline
from conftest import random_walk


def collection(count, seed=0):
    rng = np.random.default_rng(seed)
    return [random_walk(int(rng.integers(3, 40)), seed * 10000 + i, turn=1.5)
            for i in range(count)]


@pytest.mark.parametrize("method,kwargs", [
    ("quasi-elastic", {}),
    ("jaklic-zagar", {"closed": True, "alpha": 1.0}),
    ("li-strain", {"report": "basic"}),
    ("min-energy", {"basis": "cond-g2", "lambda": 0.8}),
])
def test_fit_many_equals_fit_one_by_one(method, kwargs):
    curves = collection(60, seed=len(method))
    many = fairspline.fit_many(curves, method, threads=2, **kwargs)
    assert len(many) == len(curves)
    for pts, got in zip(curves, many):
        one = fairspline.fit(pts, method, **kwargs)
        assert np.array_equal(got.segments, one.segments)
        assert got.to_json() == one.to_json()


def test_threads_do_not_change_results():
    curves = collection(50, seed=4)
    reference = [c.to_json() for c in fairspline.fit_many(curves, threads=1)]
    for threads in (None, 0, 2, 3):
        assert [c.to_json() for c in fairspline.fit_many(curves, threads=threads)] == reference
    # Any iterable of (n, 2) array-likes: a generator, a 3-D array, lists of tuples.
    same = fairspline.fit_many((c for c in curves[:5]), threads=2)
    assert [c.to_json() for c in same] == reference[:5]
    block = np.stack([random_walk(12, s) for s in range(4)])
    assert [c.to_json() for c in fairspline.fit_many(block)] == [
        fairspline.fit(b).to_json() for b in block]
    assert fairspline.fit_many([]) == []


def test_errors_raise_names_the_curve():
    curves = collection(20, seed=5)
    curves[7] = [[0, 0], [1, 1], [1, 1], [2, 0]]
    curves[12] = [[0, 0], [np.nan, 1], [2, 0]]
    with pytest.raises(fairspline.Error) as info:
        fairspline.fit_many(curves, threads=2)
    e = info.value
    assert (e.code, e.index, e.curve) == ("repeated_point", 2, 7)
    assert str(e).startswith("curve 7: ")


def test_errors_return_keeps_the_others():
    curves = collection(20, seed=6)
    curves[3] = [[0, 0]]
    curves[12] = [[0, 0], [np.nan, 1], [2, 0]]
    out = fairspline.fit_many(curves, "jaklic-zagar", threads=2, errors="return")
    assert [i for i, c in enumerate(out) if isinstance(c, fairspline.Error)] == [3, 12]
    assert (out[3].code, out[3].curve) == ("too_few_points", 3)
    assert (out[12].code, out[12].index, out[12].curve) == ("non_finite", 1, 12)
    for i in (0, 5, 19):
        assert out[i].to_json() == fairspline.fit(curves[i], "jaklic-zagar").to_json()


def test_bad_arguments():
    with pytest.raises(fairspline.Error) as info:
        fairspline.fit_many([random_walk(5, 1), [[0, 0, 0]]])
    assert (info.value.code, info.value.curve) == ("invalid_argument", 1)
    with pytest.raises(fairspline.Error):
        fairspline.fit_many([random_walk(5, 1)], errors="ignore")
    with pytest.raises(fairspline.Error):
        fairspline.fit_many([random_walk(5, 1)], threads=-1)
    with pytest.raises(fairspline.Error) as info:
        fairspline.fit_many([random_walk(5, 1)], "nope")
    assert (info.value.code, info.value.curve) == ("unknown_method", 0)


def progress_during(call):
    """Runs call() while a Python thread records timestamps every ~millisecond; returns how
    many it recorded in the middle half of the call. Holding the GIL during the whole C++
    part would leave that middle half without any (Python threads cannot run then)."""
    stamps = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        while not stamps:  # the ticker is running before the call starts
            time.sleep(0.001)
        start = time.perf_counter()
        call()
        end = time.perf_counter()
    finally:
        stop.set()
        thread.join()
    quarter = (end - start) / 4
    return sum(1 for s in stamps if start + quarter < s < end - quarter), end - start


def test_fit_releases_the_gil():
    pts = random_walk(100_000, 3, turn=1.0)  # ~0.3 s with the full report
    ticks, seconds = progress_during(lambda: fairspline.fit(pts, "li-strain"))
    assert seconds > 0.05, "the fit is too quick to tell"
    assert ticks >= 3, "no Python thread ran during {:.3f} s of fitting".format(seconds)


def test_fit_many_releases_the_gil():
    curves = [random_walk(1000, s, turn=1.0) for s in range(100)]
    ticks, seconds = progress_during(lambda: fairspline.fit_many(curves, threads=1))
    assert seconds > 0.05, "the fits are too quick to tell"
    assert ticks >= 3, "no Python thread ran during {:.3f} s of fitting".format(seconds)


def _walks(count, n=5000, seed=1):
    rng = np.random.default_rng(seed)
    return [np.cumsum(rng.normal(size=(n, 2)), axis=0) for _ in range(count)]


def test_progress_is_called_on_this_thread_up_to_the_total():
    curves = _walks(60, n=2000)
    calls = []
    main = threading.get_ident()
    out = fairspline.fit_many(curves, report="none", threads=1, errors="return",
                              progress=lambda done, total: calls.append(
                                  (done, total, threading.get_ident())))
    assert len(out) == 60
    assert calls and calls[-1][:2] == (60, 60)
    assert all(t == main for _, _, t in calls)
    dones = [d for d, _, _ in calls]
    assert dones == sorted(dones) and len(set(dones)) == len(dones)


def test_ctrl_c_stops_a_running_batch_quickly():
    curves = _walks(400)  # ~5 s of fitting on one thread
    timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        fairspline.fit_many(curves, report="none", threads=1, errors="return")
    assert time.monotonic() - started < 1.5


def test_an_exception_in_progress_stops_the_batch():
    def fail(done, total):
        raise RuntimeError("enough")
    with pytest.raises(RuntimeError, match="enough"):
        fairspline.fit_many(_walks(200), report="none", threads=1, errors="return", progress=fail)
    with pytest.raises(fairspline.Error):
        fairspline.fit_many(_walks(2, n=10), progress=3)


def test_process_pools_can_map_fit():
    # The module's functions pickle by name (pybind11's are bound to a PyCapsule).
    import concurrent.futures
    import pickle
    for function in (fairspline.fit, fairspline.fit_many, fairspline.methods,
                     fairspline.read_curve_ensemble):
        assert pickle.loads(pickle.dumps(function)) is function
    inputs = [random_walk(12, seed) for seed in range(4)]
    with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
        curves = list(pool.map(fairspline.fit, inputs))
    assert curves == [fairspline.fit(p) for p in inputs]
