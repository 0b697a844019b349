"""fairspline.Error: a ValueError with the library's stable code and the offending point."""

import math
import pickle

import numpy as np
import pytest

import fairspline
from conftest import example_points


def error_of(fn, *args, **kwargs):
    with pytest.raises(fairspline.Error) as info:
        fn(*args, **kwargs)
    return info.value


def test_error_is_a_value_error():
    assert issubclass(fairspline.Error, ValueError)
    assert fairspline.Error.__module__ == "fairspline"
    e = fairspline.Error("by hand")
    assert (e.code, e.index, e.curve) == (None, None, None)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_point(bad):
    pts = example_points()
    pts[4, 1] = bad
    e = error_of(fairspline.fit, pts)
    assert (e.code, e.index) == ("non_finite", 4)
    assert "point 4" in str(e)


def test_repeated_point():
    e = error_of(fairspline.fit, [[0, 0], [1, 1], [2, 0], [2, 0], [3, 1]], "jaklic-zagar")
    assert (e.code, e.index) == ("repeated_point", 3)


def test_too_few_points():
    for pts in ([[0, 0]], [], np.empty((0, 2))):
        e = error_of(fairspline.fit, pts)
        assert e.code == "too_few_points"


def test_wrong_shape():
    for pts in ([[0, 0, 0], [1, 1, 1]], [0, 1, 2], [[[0, 0]], [[1, 1]]], [[0, 0], [1]],
                "points", [["a", "b"], ["c", "d"]]):
        e = error_of(fairspline.fit, pts)
        assert e.code == "invalid_argument"
        assert "points must be an (n, 2) array" in str(e)


def test_unknown_method_and_options():
    pts = example_points()
    e = error_of(fairspline.fit, pts, "no-such-method")
    assert e.code == "unknown_method" and "li-strain" in str(e)
    e = error_of(fairspline.fit, pts, "quasi-elastic", no_such_option=1)
    assert e.code == "unknown_option" and "no_such_option" in str(e)
    e = error_of(fairspline.fit, pts, "quasi-elastic", omega_deg=200)
    assert e.code == "bad_option" and "omega_deg" in str(e)
    e = error_of(fairspline.fit, pts, "quasi-elastic", omega_deg=math.nan)
    assert e.code == "bad_option"
    e = error_of(fairspline.fit, pts, "quasi-elastic", omega_deg=object())
    assert e.code == "bad_option"
    e = error_of(fairspline.fit, pts, "cond-g2", options={"lambda": 1}, **{"lambda": 2})
    assert e.code == "bad_option"
    # quasi-elastic is the cubic of lambda = 1: it has no such option.
    e = error_of(fairspline.fit, pts, "quasi-elastic", **{"lambda": 0.5})
    assert e.code == "unknown_option"
    e = error_of(fairspline.fit, pts, report="everything")
    assert e.code == "invalid_argument"


def test_method_failures_keep_their_index():
    pts = example_points()
    e = error_of(fairspline.fit, pts, "min-energy", omega_deg=60)
    assert (e.code, e.index) == ("infeasible", 2)
    e = error_of(fairspline.fit, pts[:6], "kozak-krajnc")
    assert e.code == "wrong_point_count"
    e = error_of(fairspline.fit, pts, "li-curvature-variation")
    assert e.code == "singular_system"


def test_hints_are_keywords_not_command_line_flags():
    # Issue 20, bug 4: the library's sentence names no front end's syntax; Python adds its own.
    pts = example_points()
    e = error_of(fairspline.fit, pts[:6], "kozak-krajnc")
    assert e.hint == ("remainder", "hermite")
    assert 'hint: pass remainder="hermite"' in str(e) and "--" not in str(e)
    e = error_of(fairspline.fit, pts, "min-energy", **{"lambda": 0.5})
    assert (e.code, e.hint) == ("bad_option", ("basis", "cond-g2"))
    assert 'basis="cond-g2"' in str(e)
    e = error_of(fairspline.fit, [[0, 0], [2, 0], [1, 0], [3, 0]], "jaklic-zagar")
    assert (e.code, e.index, e.hint) == ("reversal", 1, ("reversal", "insert"))
    e = error_of(fairspline.fit, pts, "yong-cheng")
    assert e.hint == ("tangents_from", None) and "tangents_from=..." in str(e)
    e = error_of(fairspline.fit, pts, "li-curvature-variation")
    assert e.hint is None and "--" not in str(e)
    assert fairspline.Error("by hand").hint is None


def test_input_fields():
    pts = example_points()
    e = error_of(fairspline.fit, pts, kinds=["smooth"] * 3 + ["pointy"] + ["smooth"] * 3)
    assert (e.code, e.index) == ("invalid_argument", 3)
    e = error_of(fairspline.fit, pts, tangents=[None, (1, 2, 3)] + [None] * 5)
    assert e.code == "invalid_argument" and "tangents[1]" in str(e)
    e = error_of(fairspline.fit, pts, tangents="sweep")
    assert "options={'tangents'" in str(e)
    e = error_of(fairspline.fit, pts, tangents=[None, (math.nan, 1)] + [None] * 5)
    assert (e.code, e.index) == ("non_finite", 1)
    e = error_of(fairspline.fit, pts, start_tangent=(1, 2, 3))
    assert e.code == "invalid_argument"
    e = error_of(fairspline.fit, pts, knots=[0, 1, 2, 2, 3, 4, 5])
    assert (e.code, e.index) == ("invalid_argument", 3)
    e = error_of(fairspline.fit, pts, knots=[[0, 1]])
    assert e.code == "invalid_argument" and "1-D" in str(e)


def test_errors_pickle():
    e = error_of(fairspline.fit, [[0, 0], [0, 0], [1, 1]])
    copy = pickle.loads(pickle.dumps(e))
    assert type(copy) is fairspline.Error
    assert (copy.code, copy.index, str(copy)) == (e.code, e.index, str(e))
