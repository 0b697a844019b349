"""fit(time_limit=..., progress=...) and Ctrl-C during a long fit (FitOptions::time_limit and
::progress in C++)."""

import os
import signal
import threading
import time

import pytest

import fairspline
from conftest import random_walk

# The elastic spline's grid search over 300 sharp points: about two seconds, in steps of
# milliseconds.
SLOW = dict(method="elastic", search="global")


def slow_points():
    return random_walk(300, 4, turn=2.6)


def test_a_time_limit_stops_the_fit_with_cancelled():
    started = time.monotonic()
    with pytest.raises(fairspline.Error) as info:
        fairspline.fit(slow_points(), time_limit=0.2, **SLOW)
    assert time.monotonic() - started < 1.5
    assert info.value.code == "cancelled"
    assert info.value.index is None
    assert "the fit was stopped at its time limit of 0.2 s" in str(info.value)


def test_progress_is_called_on_this_thread_and_false_cancels():
    calls = []
    main = threading.get_ident()

    def progress(stage, done, total, seconds):
        calls.append((stage, done, total, seconds, threading.get_ident()))
        return len(calls) < 2

    with pytest.raises(fairspline.Error) as info:
        fairspline.fit(slow_points(), progress=progress, **SLOW)
    assert info.value.code == "cancelled"
    assert "cancelled by its progress callback" in str(info.value)
    assert len(calls) == 2
    for stage, done, total, seconds, thread in calls:
        assert thread == main
        assert stage in {"global search", "newton", "report"}
        assert total == 0 or 0 <= done < total
        assert seconds >= 0.4  # first after half a second, then every half second
    assert calls[1][3] - calls[0][3] >= 0.45


def test_an_exception_in_progress_is_raised_and_none_continues():
    def fail(*args):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        fairspline.fit(slow_points(), progress=fail, **SLOW)
    quick = random_walk(40, 1, turn=1.0)
    assert fairspline.fit(quick, progress=lambda *a: None) == fairspline.fit(quick)
    with pytest.raises(fairspline.Error, match="progress must be None or a callable"):
        fairspline.fit(quick, progress=3)
    with pytest.raises(fairspline.Error) as info:
        fairspline.fit(quick, time_limit=0)
    assert info.value.code == "bad_option"


def test_ctrl_c_stops_a_long_fit_quickly():
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        fairspline.fit(slow_points(), **SLOW)
    assert time.monotonic() - started < 1.2


def test_fit_many_applies_the_time_limit_per_curve():
    # (6 points take ~0.03 s, 300 points ~2.5 s: the limit leaves the quick one 20 times its
    # time, which a loaded machine needs; 20 points at 0.1 s against 0.3 once failed there.)
    out = fairspline.fit_many([random_walk(6, 1, turn=1.0), slow_points()], time_limit=0.6,
                              errors="return", threads=2, **SLOW)
    assert isinstance(out[0], fairspline.Curve)
    assert isinstance(out[1], fairspline.Error) and out[1].code == "cancelled"
