"""fairspline.fit and Curve: the same numbers as the CLI, and a curve that is what it says."""

import json
import math
import os
import pathlib
import pickle

import numpy as np
import pytest
import scipy.optimize
from scipy.interpolate import CubicSpline

import fairspline
from conftest import (EXAMPLE, SOURCE_DIR, bezier_derivatives, example_points, input_json,
                      random_walk)

# (method, CLI flags, Python keyword arguments): every method on the bundled example.
CASES = [
    ("quasi-elastic", [], {}),
    ("quasi-elastic", ["--closed", "--alpha", "1"], {"closed": True, "alpha": 1.0}),
    ("min-energy", ["--set", "basis=jaklic-zagar", "--set", "omega_deg=85"],
     {"basis": "jaklic-zagar", "omega_deg": 85}),
    ("cond-g2", ["--set", "lambda=0.5"], {"options": {"lambda": 0.5}}),
    ("cond-g2", ["--set", "lambda=1.8", "--set", "search=coordinate"],
     {"options": {"lambda": 1.8}, "search": "coordinate"}),
    ("li-strain", ["--alpha", "0"], {"alpha": 0.0}),
    ("li-strain", ["--closed"], {"closed": True}),
    ("li-combined", [], {}),
    ("li-curvature-variation", ["--start-tangent", "1,2"], {"start_tangent": (1, 2)}),
    ("jaklic-zagar", ["--set", "lambda=bisector"], {"options": {"lambda": "bisector"}}),
    ("yong-cheng", ["--set", "tangents_from=jaklic-zagar"], {"tangents_from": "jaklic-zagar"}),
    ("kozak-krajnc", ["--set", "gamma=auto"], {"gamma": "auto"}),
]
CASE_IDS = ["{}-{}".format(m, i) for i, (m, _, _) in enumerate(CASES)]


@pytest.mark.parametrize("method,flags,kwargs", CASES, ids=CASE_IDS)
def test_same_json_as_cli(cli, method, flags, kwargs):
    text = cli.fit_json(EXAMPLE, "-m", method, *flags)
    curve = fairspline.fit(example_points(), method, **kwargs)
    # The JSON contract: byte for byte what `fairspline fit -f json` writes.
    assert curve.to_json() + "\n" == text
    doc = json.loads(text)
    expected = np.array([s["bezier"] for s in doc["segments"]])
    assert curve.segments.shape == expected.shape
    assert np.array_equal(curve.segments, expected)  # exactly, not approximately
    assert np.array_equal(curve.segment_ranges, [[s["t0"], s["t1"]] for s in doc["segments"]])
    assert np.array_equal(curve.spans, [s["span"] for s in doc["segments"]])
    assert np.array_equal(curve.knots, doc["knots"])
    assert np.array_equal(curve.tangents, doc["tangents"])
    assert np.array_equal(curve.points, doc["points"])
    assert curve.report == doc["report"]
    assert curve.method_report == doc["method_report"]
    assert curve.options == doc["options"]
    assert curve.method == doc["method"] and curve.closed == doc["closed"]


def test_self_intersecting_report_same_as_cli(cli):
    pts = [[0, 0], [2, 0], [2, 2], [1, -1], [0, 2]]
    for method in ("li-strain", "jaklic-zagar"):
        doc = json.loads(cli.fit_json("-", "-m", method, "--report", "full",
                                      stdin=input_json(pts)))
        curve = fairspline.fit(pts, method, report="full")
        assert len(curve.report["intersections"]) == 2
        assert curve.report == doc["report"]
        assert isinstance(curve.report["intersections"][0]["segment_a"], int)


def test_to_json_indent_and_report_levels(cli):
    assert (fairspline.fit(example_points()).to_json(indent=2) + "\n" ==
            cli.run("fit", EXAMPLE, "-f", "json", "--indent", "2"))
    none = fairspline.fit(example_points(), report="none")
    assert none.report is None
    assert none.to_json() + "\n" == cli.fit_json(EXAMPLE, "--report", "none")
    basic = fairspline.fit(example_points(), report="basic")  # the default
    assert basic.report["bending_energy"] > 0 and basic.report["length"] > 0
    assert basic.report["curvature_variation_energy"] is None
    assert "intersections" not in basic.report  # not searched, which is not "none found"
    assert basic.to_json() + "\n" == cli.fit_json(EXAMPLE, "--report", "basic")
    full = fairspline.fit(example_points(), report="full")
    assert full.report["curvature_variation_energy"] > 0 and full.report["intersections"] == []
    assert full.report["bending_energy"] == basic.report["bending_energy"]
    assert full.to_json() + "\n" == cli.fit_json(EXAMPLE, "--report", "full")


def test_hermite_input_fields_match_cli(cli):
    pts = [[0, 0], [1, 1], [2, 0], [3, 1], [4, 0]]
    tangents = [[1, 1], None, [1, -1], [1, -1], None]
    kinds = ["smooth", "smooth", "corner", "clamped", "smooth"]
    knots = [0.0, 1.0, 2.5, 3.0, 4.5]
    text = cli.fit_json("-", "-m", "quasi-elastic", stdin=input_json(
        pts, tangents=tangents, kinds=kinds, knots=knots))
    curve = fairspline.fit(pts, tangents=tangents, kinds=kinds, knots=knots)
    assert curve.to_json() + "\n" == text
    assert np.array_equal(curve.knots, knots)
    # The corner splits the curve; the clamped tangent at point 3 is kept.
    assert np.allclose(curve.tangents[3], [1 / math.sqrt(2), -1 / math.sqrt(2)])


@pytest.mark.parametrize("svg_options,flags", [
    ({}, []),
    ({"comb": True, "control_polygon": 1, "width": 1000}, ["--set", "svg.comb=1", "--set",
                                                           "svg.control_polygon=1", "--set",
                                                           "svg.width=1000"]),
])
def test_to_svg_same_as_cli(cli, svg_options, flags):
    curve = fairspline.fit(example_points())
    assert curve.to_svg(**svg_options) == cli.run("fit", EXAMPLE, "-f", "svg", *flags)


def test_evaluate_at_knots_gives_the_points():
    for closed in (False, True):
        for method in ("quasi-elastic", "li-strain", "jaklic-zagar", "li-combined"):
            pts = random_walk(40, 7)
            curve = fairspline.fit(pts, method, closed=closed)
            expected = np.vstack((pts, pts[:1])) if closed else pts
            got = curve.evaluate(curve.knots)
            assert got.shape == expected.shape
            scale = np.ptp(pts, axis=0).max()
            assert np.max(np.abs(got - expected)) <= 1e-13 * scale, (method, closed)


def test_evaluate_shapes_and_range():
    curve = fairspline.fit(example_points())
    t0, t1 = curve.t_range
    assert (t0, t1) == (curve.knots[0], curve.knots[-1])
    assert curve.evaluate(t0).shape == (2,)
    assert curve.evaluate(np.linspace(t0, t1, 12).reshape(3, 4)).shape == (3, 4, 2)
    assert curve.derivative([t0, t1], order=2).shape == (2, 2)
    assert isinstance(curve.curvature(t0), float)
    assert curve.curvature(np.full((2, 5), t1)).shape == (2, 5)
    assert curve.evaluate(np.empty(0)).shape == (0, 2)
    # Outside the range (or NaN): an error naming the flat position of the first bad t.
    for bad, index in (([t0, t1 + 1e-9], 1), ([[t0, t0], [np.nan, t1]], 2), (t0 - 1, 0)):
        with pytest.raises(fairspline.Error) as e:
            curve.evaluate(bad)
        assert e.value.code == "invalid_argument" and e.value.index == index
    with pytest.raises(fairspline.Error):
        curve.curvature(t1 * 2)
    with pytest.raises(fairspline.Error) as e:
        curve.derivative(t0, order=4)
    assert e.value.code == "invalid_argument"


def interior_parameters(curve, per_piece, rng):
    """Random parameters strictly inside the pieces (away from joints by 5% of a piece)."""
    r = curve.segment_ranges
    u = rng.uniform(0.05, 0.95, (len(r), per_piece))
    return (r[:, :1] + u * (r[:, 1:] - r[:, :1])).ravel()


@pytest.mark.parametrize("method", ["quasi-elastic", "jaklic-zagar", "li-combined",
                                    "kozak-krajnc"])
def test_derivatives_match_finite_differences(method):
    rng = np.random.default_rng(3)
    pts = example_points()
    curve = fairspline.fit(pts, method)
    t = interior_parameters(curve, 7, rng)
    h = 1e-5 * (curve.t_range[1] - curve.t_range[0])
    for order in (1, 2, 3):
        lower = curve.evaluate(t - h) if order == 1 else curve.derivative(t - h, order - 1)
        upper = curve.evaluate(t + h) if order == 1 else curve.derivative(t + h, order - 1)
        fd = (upper - lower) / (2 * h)
        d = curve.derivative(t, order)
        scale = np.abs(d).max()
        assert np.max(np.abs(d - fd)) <= 1e-6 * scale, (method, order)


@pytest.mark.parametrize("method", ["quasi-elastic", "yong-cheng", "li-strain"])
def test_curvature_from_control_points(method):
    rng = np.random.default_rng(5)
    pts = random_walk(30, 11, turn=1.2)
    curve = fairspline.fit(pts, method, options={"tangents_from": "jaklic-zagar"}
                           if method == "yong-cheng" else None)
    t = np.concatenate((interior_parameters(curve, 5, rng), curve.segment_ranges[:, 0]))
    # Which piece holds t (joints belong to the later piece) and its local parameter u.
    r = curve.segment_ranges
    k = np.searchsorted(r[:, 1], t, side="right").clip(max=len(r) - 1)
    u = (t - r[k, 0]) / (r[k, 1] - r[k, 0])
    _, d1, d2 = bezier_derivatives(curve.segments[k], u)
    expected = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(d1[:, 0], d1[:, 1])**3
    got = curve.curvature(t)
    assert np.allclose(got, expected, rtol=1e-10, atol=1e-12 * np.abs(expected).max())
    # Curvature is parameterization-independent: the same from the global derivatives.
    c1, c2 = curve.derivative(t, 1), curve.derivative(t, 2)
    global_kappa = (c1[:, 0] * c2[:, 1] - c1[:, 1] * c2[:, 0]) / np.hypot(c1[:, 0], c1[:, 1])**3
    assert np.allclose(got, global_kappa, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("closed", [False, True])
@pytest.mark.parametrize("alpha", [0.0, 0.5, 1.0])
def test_li_strain_is_scipy_natural_spline(closed, alpha):
    pts = random_walk(60, 21)
    curve = fairspline.fit(pts, "li-strain", closed=closed, alpha=alpha)
    knots = curve.knots
    values = np.vstack((pts, pts[:1])) if closed else pts
    peer = CubicSpline(knots, values, bc_type="periodic" if closed else "natural")
    rng = np.random.default_rng(1)
    t = np.concatenate((knots, rng.uniform(knots[0], knots[-1], 500)))
    scale = np.ptp(pts, axis=0).max()
    assert np.max(np.abs(curve.evaluate(t) - peer(t))) <= 1e-10 * scale
    slope = np.max(np.hypot(*np.diff(values, axis=0).T) / np.diff(knots))
    assert np.max(np.abs(curve.derivative(t) - peer(t, 1))) <= 1e-9 * slope


def test_sample():
    curve = fairspline.fit(example_points(), "jaklic-zagar")
    s = curve.sample(101)
    assert s.shape == (101, 2)
    t0, t1 = curve.t_range
    assert np.array_equal(s[[0, -1]], curve.evaluate([t0, t1]))
    assert np.allclose(s, curve.evaluate(np.linspace(t0, t1, 101)), rtol=0, atol=1e-12)
    with pytest.raises(fairspline.Error):
        curve.sample(1)


def test_pickle_round_trip():
    for method, kw in (("quasi-elastic", {}), ("kozak-krajnc", {}), ("li-strain",
                                                                        {"report": "none"})):
        curve = fairspline.fit(example_points(), method, **kw)
        copy = pickle.loads(pickle.dumps(curve))
        assert copy.to_json() == curve.to_json()
        assert np.array_equal(copy.evaluate(copy.knots), curve.evaluate(curve.knots))
    looped = fairspline.fit([[0, 0], [2, 0], [2, 2], [1, -1], [0, 2]], "li-strain")
    assert pickle.loads(pickle.dumps(looped)).to_json() == looped.to_json()


def test_methods_is_the_registry(cli):
    listed = fairspline.methods()
    assert listed == json.loads(cli.run("methods", "--json"))
    names = [m["name"] for m in listed]
    assert fairspline.DEFAULT_METHOD in names and "li-strain" in names
    jz = next(m for m in listed if m["name"] == "jaklic-zagar")
    assert {o["name"] for o in jz["options"]} >= {"lambda", "lambdas"}
    assert all({"name", "type", "default", "doc"} <= set(o) for m in listed
               for o in m["options"])


def test_options_from_numpy_values_and_options_dict():
    pts = example_points()
    a = fairspline.fit(pts, "jaklic-zagar", lambdas=np.full(len(pts), 0.25))
    b = fairspline.fit(pts, "jaklic-zagar", options={"lambdas": [0.25] * len(pts)})
    assert a.to_json() == b.to_json()
    assert a.options["lambdas"] == [0.25] * len(pts)
    c = fairspline.fit(pts, "quasi-elastic", max_iterations=np.int64(50), omega_deg=np.float32(89.5))
    assert c.options["max_iterations"] == 50 and c.options["omega_deg"] == 89.5


def test_search_coordinate_is_one_keyword_away():
    # Issue 18: the coordinate search's start is never above Newton's local minimum here, and
    # method_report says which search ran.
    pts = random_walk(40, 904, 1.9)
    a = fairspline.fit(pts, "min-energy", basis="yong-cheng")
    b = fairspline.fit(pts, "min-energy", basis="yong-cheng", search="coordinate")
    assert a.method_report["search"] == "newton" and b.method_report["search"] == "coordinate"
    assert b.method_report["energy"] <= a.method_report["energy"] * (1 + 1e-12)
    with pytest.raises(fairspline.Error) as e:
        fairspline.fit(pts, "quasi-elastic", search="random")
    assert e.value.code == "bad_option"


def test_search_global_reaches_the_brute_force_minimum():
    # Issue 18: search="global" (a grid of directions by dynamic programming, then Newton) on four
    # points with both end directions given, against a brute force over the two free directions
    # written from the cond-g2 energy E_1 = 2l^2 cos(a - b) - 6l (cos a + cos b) + 4l^2 + 6
    # (Theorem 4.4) with NumPy, polished by SciPy; search="newton" stops in a higher minimum.
    req = json.loads((SOURCE_DIR / "tests" / "data" / "cond-g2-two-minima.json").read_text())
    pts = np.array(req["points"])
    tangents = req["tangents"]
    lam = req["options"]["lambda"]
    chords = np.diff(pts, axis=0)
    phi = np.arctan2(chords[:, 1], chords[:, 0])
    length = np.hypot(chords[:, 0], chords[:, 1])
    start = np.arctan2(tangents[0][1], tangents[0][0])
    end = np.arctan2(tangents[3][1], tangents[3][0])

    def energy(x1, x2):
        x = [start, x1, x2, end]
        total = 0.0
        for i in range(3):
            a = np.remainder(x[i] - phi[i] + np.pi, 2 * np.pi) - np.pi
            b = np.remainder(x[i + 1] - phi[i] + np.pi, 2 * np.pi) - np.pi
            e = 2 * lam**2 * np.cos(a - b) - 6 * lam * (np.cos(a) + np.cos(b)) + 4 * lam**2 + 6
            total = total + np.where((np.abs(a) <= np.pi / 2) & (np.abs(b) <= np.pi / 2),
                                     e / length[i], np.inf)
        return total

    grid = np.linspace(-np.pi, np.pi, 721)
    g1, g2 = np.meshgrid(grid, grid, indexing="ij")
    e = energy(g1, g2)
    i, j = np.unravel_index(np.argmin(e), e.shape)
    best = scipy.optimize.minimize(lambda v: energy(v[0], v[1]), [grid[i], grid[j]],
                                   method="Nelder-Mead",
                                   options={"xatol": 1e-12, "fatol": 1e-14, "maxiter": 4000})
    kw = dict(kinds=req["kinds"], tangents=tangents, options=req["options"])
    newton = fairspline.fit(pts, "cond-g2", **kw)
    curve = fairspline.fit(pts, "cond-g2", search="global", **kw)
    assert curve.method_report["search"] == "global" and curve.method_report["minimum"] == "global"
    assert newton.method_report["minimum"] == "newton"
    assert curve.method_report["energy"] == pytest.approx(best.fun, rel=1e-9)
    assert newton.method_report["energy"] > 1.05 * best.fun


def test_repr():
    curve = fairspline.fit(example_points(), closed=True)
    assert repr(curve) == "<fairspline.Curve method='quasi-elastic' points=7 segments=7 closed>"


def unaligned_copy(a):
    """A float64 copy of `a` at an odd byte offset of a buffer: NumPy marks it unaligned."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    buf = np.zeros(a.nbytes + 1, dtype=np.uint8)
    buf[1:] = np.frombuffer(a.tobytes(), dtype=np.uint8)
    view = np.frombuffer(buf.data, dtype=np.float64, count=a.size, offset=1).reshape(a.shape)
    assert not view.flags.aligned and np.array_equal(view, a)
    return view


def test_unaligned_arrays_are_read_correctly():
    # Reading an unaligned array as double* was undefined behaviour (UBSan in `make sanitize`,
    # via dask_batch's .npz input); the module now copies such arrays into aligned ones. The fit
    # and the evaluation match those of aligned arrays exactly.
    pts = random_walk(12, 3)
    got = fairspline.fit(unaligned_copy(pts), "quasi-elastic")
    want = fairspline.fit(pts, "quasi-elastic")
    assert np.array_equal(got.segments, want.segments)
    assert np.array_equal(got.evaluate(unaligned_copy(want.knots)), want.evaluate(want.knots))


KK_EXAMPLE = EXAMPLE.parent / "kozak-krajnc.csv"


def test_from_json_is_the_inverse_of_to_json():
    for method in ("quasi-elastic", "kozak-krajnc", "yong-cheng"):
        kw = {"tangents_from": "jaklic-zagar"} if method == "yong-cheng" else {}
        curve = fairspline.fit(example_points()[:7] if method == "kozak-krajnc" else
                               example_points(), method, **kw)
        for indent in (None, 2):
            back = fairspline.Curve.from_json(curve.to_json(indent=indent))
            assert back.to_json() == curve.to_json()
            assert np.array_equal(back.evaluate(back.knots), curve.evaluate(curve.knots))
    with pytest.raises(fairspline.Error) as e:
        fairspline.Curve.from_json('{"method": "li-strain"}')
    assert e.value.code == "parse_error"


def test_best_effort_and_accuracy_reach_the_fit():
    pts = np.loadtxt(KK_EXAMPLE, delimiter=",", skiprows=1)
    # The G2 Newton of this example stalls (it has no G2 spline for the tangent rule's end
    # directions): an error, or the G1 curve with the solver's status.
    with pytest.raises(fairspline.Error) as e:
        fairspline.fit(pts, "kozak-krajnc", g2=True)
    assert e.value.code == "infeasible"
    curve = fairspline.fit(pts, "kozak-krajnc", g2=True, best_effort=True)
    solver = json.loads(curve.to_json())["method_report"]["solver"]
    assert solver["status"] in ("stalled", "iteration_limit")
    assert solver["residual"] > solver["tolerance"]
    [many] = fairspline.fit_many([pts], "kozak-krajnc", g2=True, best_effort=True)
    assert many.to_json() == curve.to_json()
    # accuracy is validated and changes only what is approximated (the quadratures).
    with pytest.raises(fairspline.Error) as e:
        fairspline.fit(example_points(), accuracy=0.0)
    assert e.value.code == "bad_option"
    fine = fairspline.fit(example_points())
    coarse = fairspline.fit(example_points(), accuracy=1e-3)
    assert np.array_equal(coarse.segments, fine.segments)
    rel = abs(coarse.report["bending_energy"] / fine.report["bending_energy"] - 1)
    assert rel < 1e-3


def test_diagnostics_false_keeps_the_method_reports_summary():
    pts = np.loadtxt(KK_EXAMPLE, delimiter=",", skiprows=1)
    full = fairspline.fit(pts, "kozak-krajnc")
    quiet = fairspline.fit(pts, "kozak-krajnc", diagnostics=False)
    assert len(full.method_report["segments"]) == 3
    assert "segments" not in quiet.method_report
    assert quiet.method_report == fairspline.fit(pts, "kozak-krajnc", report="none").method_report
    assert quiet.report == full.report
    assert np.array_equal(quiet.segments, full.segments)
    [many] = fairspline.fit_many([pts], "kozak-krajnc", diagnostics=False)
    assert many.to_json() == quiet.to_json()


def test_node_model_keywords_same_as_json_request(cli, tmp_path):
    # Issue 19: states, in_tangents, out_tangents and corners_deg reach the library as the JSON
    # request's fields do (byte-identical output), and kinds-only methods refuse what kinds
    # cannot express, naming the point.
    pts = [[0, 0], [1, 2], [3, 3], [5, 2], [6, 0], [8, 1], [9, 3]]
    states = ["regular", "regular", ["clamped", "free"], "regular", "regular", "regular",
              "regular"]
    in_tangents = [None, None, [1, 0.2], None, None, None, None]
    corners = [0, 0, 0, 30, 0, -20, 0]
    request = tmp_path / "nodes.json"
    request.write_text(input_json(pts, states=states, in_tangents=in_tangents,
                                  corners_deg=corners))
    text = cli.fit_json(str(request))
    curve = fairspline.fit(pts, states=[tuple(s) if isinstance(s, list) else s for s in states],
                           in_tangents=in_tangents, corners_deg=np.array(corners, float))
    assert curve.to_json() + "\n" == text
    assert curve.method_report["pieces"] == 2
    with pytest.raises(fairspline.Error) as e:
        fairspline.fit(pts, "li-strain", corners_deg=corners)
    assert e.value.code == "invalid_argument" and e.value.index == 3
    with pytest.raises(fairspline.Error) as e:
        fairspline.fit(pts, states=["regular", "sideways"] + ["regular"] * 5)
    assert e.value.code == "invalid_argument" and e.value.index == 1


def test_request_refits_the_same_curve_bit_for_bit():
    curve = fairspline.fit([(0, 0), (2, 1), (4, 0), (6, 2), (8, 0)], method="restricted-elastic",
                           states=["regular", "regular", ["clamped", "free"], "regular", "regular"],
                           in_tangents=[None, None, (1, -0.3), None, None],
                           corners_deg=[0, 20, 0, 0, 0], alpha=0.3, accuracy=1e-8)
    request = curve.request
    assert request["method"] == "restricted-elastic"
    assert request["alpha"] == 0.3 and request["accuracy"] == 1e-8
    again = fairspline.fit(**request)
    assert np.array_equal(again.segments, curve.segments)
    # ... and through JSON, as the CLI's `fit out.json` does.
    assert fairspline.Curve.from_json(curve.to_json()).request == request


def test_curve_ensemble_files(tmp_path):
    source = pathlib.Path(__file__).resolve().parents[2] / "examples" / "curve-ensemble.txt"
    inputs = fairspline.read_curve_ensemble(str(source))
    assert inputs["states"][0] == ["free", "clamped"]
    assert inputs["states"][3] == "free"
    assert inputs["corners_deg"][2] == 40.0
    assert "closed" not in inputs  # first state 3, last 5: open
    curve = fairspline.fit(**inputs, method="restricted-elastic")
    text = curve.to_curve_ensemble()
    assert text.startswith("#Curve Ensemble Text File\n")
    path = tmp_path / "out.txt"
    path.write_text(text)
    back = fairspline.read_curve_ensemble(str(path))
    assert back["points"] == inputs["points"]
    assert back["states"] == inputs["states"]
    refit = fairspline.fit(**back, method="restricted-elastic")
    assert np.allclose(refit.segments, curve.segments, atol=1e-7)
    with pytest.raises(fairspline.Error) as err:
        bad = tmp_path / "balls.txt"
        bad.write_text("0 0 1\n5 5 -2\n9 0 0\n")  # x y r: a negative radius
        fairspline.read_curve_ensemble(str(bad))
    assert err.value.code == "invalid_argument" and err.value.index == 1


def noisy_circle(n, noise, seed):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.c_[np.cos(t), np.sin(t)] + rng.uniform(-noise, noise, (n, 2)) / math.sqrt(2)


def test_data_balls_smooth_a_noisy_circle_within_the_radii():
    points = noisy_circle(60, 0.02, 4)
    plain = fairspline.fit(points, closed=True)
    curve = fairspline.fit(points, closed=True, radii=np.full(60, 0.02))
    balls = curve.method_report["balls"]
    assert balls["count"] == 60 and balls["status"] == "converged"
    assert balls["kkt_residual"] <= 1e-8
    offsets = np.hypot(*(curve.points - points).T)
    assert offsets.max() <= 0.02 * (1 + 1e-12)
    on_circle = np.flatnonzero(offsets >= 0.02 * (1 - 1e-9))
    assert list(on_circle) == balls["active"]
    # The true circle's ∫κ² ds is 2π; interpolating the noise costs many times that.
    assert abs(curve.report["bending_energy"] / (2 * np.pi) - 1) < 0.02
    assert plain.report["bending_energy"] > 5 * curve.report["bending_energy"]
    # The request refits the same curve; zero radii are plain interpolation.
    assert np.array_equal(fairspline.fit(**curve.request).points, curve.points)
    assert np.array_equal(fairspline.fit(points, closed=True, radii=np.zeros(60)).segments,
                          plain.segments)


def test_data_balls_through_curve_ensemble_files(tmp_path):
    path = tmp_path / "balls.txt"
    path.write_text("# x y r\n0 0 0.2\n3 1.5 0.5\n6 -0.5 0.5\n9 1 0.5\n12 0 0.2\n")
    inputs = fairspline.read_curve_ensemble(str(path))
    assert inputs["radii"] == [0.2, 0.5, 0.5, 0.5, 0.2]
    assert inputs["closed"] is True  # as Curve Ensemble loads it
    inputs["closed"] = False
    curve = fairspline.fit(**inputs, method="restricted-elastic")
    text = curve.to_curve_ensemble()
    rows = [line.split() for line in text.splitlines()[1:]]
    assert [float(r[4]) for r in rows] == [-0.2, -0.5, -0.5, -0.5, -0.2]
    assert [[float(r[0]), float(r[1])] for r in rows] == inputs["points"]  # the centres


def test_data_ball_errors_name_the_point():
    points = [(0, 0), (2, 1), (4, 0), (6, 1)]
    with pytest.raises(fairspline.Error) as err:
        fairspline.fit(points, radii=[0, 0.5, 0, 0], method="jaklic-zagar")
    assert err.value.code == "invalid_argument" and err.value.index == 1
    with pytest.raises(fairspline.Error) as err:
        fairspline.fit(points, radii=[0, 0.5])
    assert err.value.code == "invalid_argument"
    with pytest.raises(fairspline.Error) as err:
        fairspline.fit(points, radii=np.zeros((4, 2)))
    assert err.value.code == "invalid_argument"


def test_curve_is_callable_comparable_and_shows_itself_in_jupyter():
    points = [(0, 0), (1, 2), (3, 3), (5, 2)]
    curve = fairspline.fit(points)
    t = np.linspace(*curve.t_range, 7)
    assert np.array_equal(curve(t), curve.evaluate(t))
    assert curve == fairspline.fit(points)
    assert curve == pickle.loads(pickle.dumps(curve))
    assert curve != fairspline.fit([(0, 0), (1, 2), (3, 3), (5, 2.5)])
    assert curve != fairspline.fit(points, method="li-strain")
    assert (curve == "a curve") is False
    with pytest.raises(TypeError):
        hash(curve)  # equal by value, and not immutable by contract
    svg = curve._repr_svg_()
    assert svg.lstrip().startswith("<?xml") and "<path" in svg


def _resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not pathlib.Path("/proc/self/statm").exists(), reason="needs /proc")
def test_keep_fit_memory_false_gives_a_large_fits_work_memory_back():
    # A thread keeps a fit's large work blocks for its next fit (~130 bytes a point for the
    # default method); keep_fit_memory(False) frees them, and the resident memory shows it.
    pts = random_walk(300_000, 5)
    fairspline.keep_fit_memory(True)
    try:
        curve = fairspline.fit(pts, report="none")
        assert len(curve.segments) == len(pts) - 1
        before = _resident_bytes()
        fairspline.keep_fit_memory(False)
        after = _resident_bytes()
        assert before - after > 20e6, (before, after)
        # Kept no more: after a second fit there is nothing left to give back.
        fairspline.fit(pts, report="none")
        second = _resident_bytes()
        fairspline.keep_fit_memory(False)
        assert second - _resident_bytes() < 5e6
    finally:
        fairspline.keep_fit_memory(True)
