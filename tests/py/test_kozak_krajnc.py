#!/usr/bin/python3
"""Exact-arithmetic check of the Kozak–Krajnc single-piece solver behind `-m kozak-krajnc`.

With exactly four points T0..T3 and clamped end directions d0, d3, the method solves one cubic
piece P with P(0) = T0, P(t1) = T1, P(t2) = T2, P(1) = T3, P'(0) = α0·d0/|d0|,
P'(1) = α3·d3/|d3|, and lists every admissible solution (0 < t1 < t2 < 1, α0, α3 > 0) in
method_report.segments[0].solutions. This script recomputes that list independently with SymPy
on the exact rationals of the input (Kozak & Krajnc 2007, Section 2):

  F = t2²(1−t2) − (1+μ1) t1²(1−t1) + A1 (t2−t1) t1² t2²,      A1 = 1 + μ1(1+λ1) − λ1/λ2,
  G = t1(1−t1)² − (1+μ2) t2(1−t2)² + A2 (t2−t1)(1−t1)²(1−t2)², A2 = 1 + μ2(1+λ2) − λ2/λ1,

(the system (2.3) cleared of denominators), the exact resultant Res_t1(F, G) ∈ Q[t2], its real
roots in (0, 1) isolated exactly (square-free decomposition + real_roots) and evaluated to 60
digits, the common t1 of F(·, t2) and G(·, t2) on each root, α0, α3 from (2.4)–(2.5) and the
admissibility filter. The intersection multiplicity of F = 0 and G = 0 at a solution is 1 when
the Jacobian is regular; at a singular point (a rational one: paper data 1) it is the
multiplicity of the root of Res_t1 after the change t2 = u + c·t1, for several c whose line
through the point holds no other common point of the curves (exact gcd), also not at infinity
since c ∉ {0, 1} (the t1⁵ coefficients A1(c−1)c², A2(c−1)c² are non-zero constants).

Checked against the CLI, per case:
  * the solution sets agree: same count; t1, t2 to 1e-10 and α0, α3, energy to 1e-10
    relative for simple solutions, to 1e-12 at multiple ones (the solver refines those to full
    precision; the errors are printed);
  * the multiplicities agree, and their sum is odd (Brouwer degree argument of Section 3);
  * each CLI solution interpolates: the Bézier T0, T0 + α0 d0/(3|d0|), T3 − α3 d3/(3|d3|), T3
    built from the reported numbers (evaluated in 60-digit arithmetic) passes through T1 at t1
    and T2 at t2 to 1e-12 relative to the largest chord; its energy ∫|P''|² is the reported one;
  * segments[0] (the chosen solution) is the least-energy solution of the list.

Cases: the three data sets of the paper's Section 3 (their solutions, withheld in the paper's
Table 3.2, are printed), random pieces from a fixed seed (decimal coordinates, end
directions inside the cone (4.1) the CLI accepts), fixed pieces with three admissible
solutions found by an offline search (one with two of them 4.3e-6 apart, next to a fold), and
pieces built to have a double or a triple solution at a known rational point: four points of a
parabola with its end derivatives (contact of order 3 for any parameters) and the constructed
cubics of make_kozak_krajnc_double_roots.py. Random pieces the CLI rejects as infeasible (the
sufficient conditions of Theorems 2.4/2.5 fail) are skipped, but at least MIN_RANDOM must fit.

Environment: FAIRSPLINE_CLI = path of the fairspline command (set by CTest).
Plain script (no pytest): prints one line per failure and `kozak-krajnc exact: P passed,
F failed`; exit status 0 only when every case passes.
"""

import json
import os
import random
import subprocess
import sys
import tempfile
import time
from fractions import Fraction

import mpmath as mp
import sympy as sp

mp.mp.dps = 60

T1_TOL = 1e-10           # absolute, on t1, t2 (simple solutions)
REL_TOL = 1e-10          # relative, on α0, α3, energy (simple solutions)
MULTIPLE_TOL = 1e-12     # multiple solutions: t1, t2 absolute, α0, α3, energy relative
ILL_CONDITIONED = 1e-15  # simple solutions: at least this over the normalized Jacobian
INTERP_TOL = 1e-12       # |P(ti) − Ti| / largest chord, from the reported numbers
ENERGY_SELF_TOL = 1e-12  # reported energy vs ∫|P''|² of the reported Bézier

SEED = 20070547
RANDOM_CANDIDATES = 80
MIN_RANDOM = 25

X, Y = sp.symbols("t1 t2")  # t1, t2


def paper_data(s, d0, d3):
    return [(-4, -4), (0, 0), (4, 0), (9 + (-1)**s, (-1)**s * 4)], d0, d3


PAPER = [
    ("paper data 1", *paper_data(1, (2, 3), (2, -3))),
    ("paper data 2", *paper_data(1, (-2, 2), (-2, -2))),
    ("paper data 3", *paper_data(0, (-2, 2), (-1, 2))),
]
# The paper's Table 3.1 (λ1, λ2, μ1, μ2, δ1, δ2), checked against constants(). For data 1 the
# table gives δ1 = δ2 = 1, but d0 = (2, 3), d3 = (2, −3) as printed give δ1 = δ2 = 4 (δ scales
# with 1/|d|; the table would fit d scaled by 4): the check uses 4, so the α printed for data 1
# are relative to the d as printed.
TABLE_3_1 = {
    "paper data 1": (2, 2, 3, 3, 4, 4),
    "paper data 2": (2, 2, sp.Rational(1, 2), sp.Rational(1, 2), 1, 1),
    "paper data 3": (sp.Rational(1, 2), sp.Rational(-1, 2), sp.Rational(1, 2), sp.Rational(1, 2), 1, 1),
}
CONSTANT_NAMES = ("lambda1", "lambda2", "mu1", "mu2", "delta1", "delta2")

# Pieces with three admissible solutions (all simple), found offline by scanning end directions
# with this script's reference: they lie in a thin cusp-shaped region that starts at paper data 1
# (whose triple solution splits into three) and runs to the corner μ1 = φ1, μ2 = φ2 of
# Theorem 2.4. No random piece (over 2000 the CLI fits) had more than one solution.
DATA1_POINTS = PAPER[0][1]
MULTI = [
    (DATA1_POINTS, ("2", "3.05"), ("2", "-3.05")),        # symmetric under t -> 1 - t
    (DATA1_POINTS, ("2", "3.1"), ("2", "-3.08")),
    (DATA1_POINTS, ("2", "3.015"), ("2", "-3.02")),       # two solutions 0.03 apart
    (DATA1_POINTS, ("2", "3.05"), ("2", "-3.030234375")),  # near the fold: 1.6e-3 apart
    (DATA1_POINTS, ("2", "3.05"), ("2", "-3.0302332169562578")),  # 4.3e-6 apart
    ([("-4.3", "-3.8"), (0, 0), ("4.1", "0.2"), ("7.7", "-4.4")], ("2.368", "2.88"),
     ("1.4286", "-3.3592")),
]

# Multiple solutions at known rational points (multiplicity, T, d0, d3, t1, t2; α0 = α3 = 1 for
# d0, d3 as given): four points of a parabola (integer affine images of (3t, 3t²), scaled to
# integers) with its end derivatives (contact of order 3 for every 0 < t1 < t2 < 1), and two
# cubics from make_kozak_krajnc_double_roots.py (order 2).
MULTIPLE = [
    (3, [(-1024, 2048), (-619, 2513), (-331, 3665), (-256, 5120)], (1536, 768), (0, 5376),
     Fraction(5, 16), Fraction(11, 16)),
    (3, [(0, 0), (90, -9), (360, 396), (384, 768)], (768, -192), (0, 1728),
     Fraction(1, 8), Fraction(3, 4)),
    (2, [(-27525120, -13762560), (-18191180, -14812763), (-15008980, -13594093),
         (18350080, 4587520)], (0, -27525120), (41287680, 25657344),
     Fraction(11, 32), Fraction(13, 32)),
    (2, [(2293760, -6881280), (-675375, 3740235), (777385, 6104595), (3440640, 6881280)],
     (-13762560, 27525120), (15040512, 884736), Fraction(17, 32), Fraction(25, 32)),
]


# ------------------------------------------------------------------------------------------
# Exact reference


def q(v):
    """Exact rational of an int or a decimal string."""
    return sp.Rational(str(v))


def det(a, b):
    return a[0] * b[1] - a[1] * b[0]


def mpf(v):
    v = sp.Rational(v)
    return mp.mpf(int(v.p)) / int(v.q)


def mp_value(v):
    """60-digit value of an exact real (Rational or CRootOf)."""
    if v.is_Rational:
        return mpf(v)
    return mp.mpf(str(sp.N(v, 70)))


def constants(T, d0, d3):
    dT = [(T[i + 1][0] - T[i][0], T[i + 1][1] - T[i][1]) for i in range(3)]
    D01, D02, D12 = det(dT[0], dT[1]), det(dT[0], dT[2]), det(dT[1], dT[2])
    c = {
        "lambda1": D02 / D01, "lambda2": D02 / D12,
        "mu1": det(d0, dT[1]) / det(d0, dT[0]), "mu2": det(dT[1], d3) / det(dT[2], d3),
        "delta1": D01 / det(d0, dT[0]), "delta2": D12 / det(dT[2], d3),
    }
    c["A1"] = 1 + c["mu1"] * (1 + c["lambda1"]) - D12 / D01
    c["A2"] = 1 + c["mu2"] * (1 + c["lambda2"]) - D01 / D12
    return c


def system(c):
    x, y = X, Y
    F = sp.expand(y**2 * (1 - y) - (1 + c["mu1"]) * x**2 * (1 - x) + c["A1"] * (y - x) * x**2 * y**2)
    G = sp.expand(x * (1 - x)**2 - (1 + c["mu2"]) * y * (1 - y)**2 +
                  c["A2"] * (y - x) * (1 - x)**2 * (1 - y)**2)
    return F, G


def alphas(c, t1, t2):
    """(2.4), (2.5): α relative to d0, d3 as given (60 digits)."""
    l1, l2, d1, d2 = (mpf(c[k]) for k in ("lambda1", "lambda2", "delta1", "delta2"))
    a0 = d1 * t1 * t2 / (t2 - t1) * (1 / (t2**2 * (1 - t2)) - (t2 - t1) / ((1 - t1) * (1 - t2)) * (1 + l1))
    a3 = d2 * (1 - t1) * (1 - t2) / (t2 - t1) * (1 / (t1 * (1 - t1)**2) - (t2 - t1) / (t1 * t2) * (1 + l2))
    return a0, a3


def mp_poly_coeffs(expr_in_x, t2):
    """Coefficients (highest first) in t1 of a polynomial in t1, t2, at t2 (60 digits)."""
    out = []
    for coeff in sp.Poly(expr_in_x, X).all_coeffs():
        out.append(mp.polyval([mpf(a) for a in sp.Poly(coeff, Y).all_coeffs()], t2))
    return out


def intersection_multiplicity(F, G, r1, r2):
    """Intersection multiplicity of F = 0, G = 0 at the rational point (r1, r2) via generic
    projections t2 = u + c·t1; returns (multiplicity, list of (c, multiplicity) used)."""
    u = sp.Symbol("u")
    used = []
    for c in (sp.Rational(3, 7), sp.Rational(-2, 5), sp.Rational(5, 3), sp.Rational(-7, 2), 2):
        Fu = sp.Poly(sp.expand(F.subs(Y, u + c * X)), X)
        Gu = sp.Poly(sp.expand(G.subs(Y, u + c * X)), X)
        if Fu.degree() != 5 or Gu.degree() != 5 or not Fu.LC().is_number or not Gu.LC().is_number:
            continue  # a point at infinity in the projection direction would add to the root
        u0 = r2 - c * r1
        g = sp.gcd(sp.Poly(Fu.as_expr().subs(u, u0), X), sp.Poly(Gu.as_expr().subs(u, u0), X))
        if g.degree() != 1:
            continue  # the line through the point meets both curves elsewhere too
        R = sp.Poly(sp.resultant(Fu.as_expr(), Gu.as_expr(), X), u)
        m = 0
        while not R.is_zero and R.eval(u0) == 0:
            R = sp.Poly(sp.quo(R.as_expr(), u - u0, u), u)
            m += 1
        used.append((c, m))
    if not used:
        raise AssertionError("no generic projection found for ({}, {})".format(r1, r2))
    ms = {m for _, m in used}
    if len(ms) != 1:
        raise AssertionError("projections disagree on the multiplicity at ({}, {}): {}".format(
            r1, r2, used))
    return ms.pop(), used


def reference(T, d0, d3):
    """Every admissible solution, exactly / to 60 digits. T, d0, d3 hold ints or decimal
    strings. Returns (constants, F, G, resultant, solutions) with solutions sorted by t1."""
    T = [(q(a), q(b)) for a, b in T]
    d0, d3 = (q(d0[0]), q(d0[1])), (q(d3[0]), q(d3[1]))
    c = constants(T, d0, d3)
    F, G = system(c)
    R = sp.Poly(sp.resultant(F, G, X), Y)
    if R.is_zero:
        raise AssertionError("the resultant vanishes identically")
    n0, n3 = mp.sqrt(mpf(d0[0]**2 + d0[1]**2)), mp.sqrt(mpf(d3[0]**2 + d3[1]**2))
    Fx, Fy, Gx, Gy = F.diff(X), F.diff(Y), G.diff(X), G.diff(Y)
    sols = []
    for factor, root_mult in R.sqf_list()[1]:
        if factor.degree() < 1:
            continue
        for root in factor.real_roots():
            t2 = mp_value(root)
            if not (0 < t2 < 1):
                continue
            fc = mp_poly_coeffs(F, t2)
            gc = mp_poly_coeffs(G, t2)
            big = max(abs(a) for a in fc)
            while abs(fc[0]) <= mp.mpf(10)**-45 * big:
                fc = fc[1:]  # F(·, t2) drops degree (only exactly, at a rational t2)
            for z in mp.polyroots(fc, maxsteps=400, extraprec=300):
                if abs(mp.im(z)) > mp.mpf(10)**-30:
                    continue
                t1 = mp.re(z)
                if not (0 < t1 < t2):
                    continue
                size = sum(abs(a) * abs(t1)**k for k, a in enumerate(reversed(gc)))
                if abs(mp.polyval(gc, t1)) > mp.mpf(10)**-30 * size:
                    continue  # not a common root
                a0, a3 = alphas(c, t1, t2)
                if not (a0 > 0 and a3 > 0):
                    continue
                point = {X: sp.Float(t1, 60), Y: sp.Float(t2, 60)}
                jac = [[mp.mpf(str(sp.N(e.subs(point), 60))) for e in row]
                       for row in ((Fx, Fy), (Gx, Gy))]
                jdet = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0]
                jscale = mp.norm(jac[0]) * mp.norm(jac[1])
                s = {"t1": t1, "t2": t2, "alpha0_raw": a0, "alpha3_raw": a3,
                     "alpha0": a0 * n0, "alpha3": a3 * n3, "resultant_multiplicity": root_mult,
                     "jacobian": jdet / jscale}
                if abs(jdet) > mp.mpf(10)**-40 * jscale or root_mult == 1:
                    s["multiplicity"] = 1
                    s["projections"] = []
                elif root.is_Rational:
                    r1 = sp.nsimplify(sp.Float(t1, 60), rational=True, tolerance=1e-40)
                    if F.subs({X: r1, Y: root}) != 0 or G.subs({X: r1, Y: root}) != 0:
                        raise AssertionError("singular solution ({}, {}) is not rational".format(
                            t1, t2))
                    s["exact"] = (r1, root)
                    s["multiplicity"], s["projections"] = intersection_multiplicity(F, G, r1, root)
                else:
                    raise AssertionError(
                        "singular solution at irrational t2 = {}: multiplicity not computed".format(
                            mp.nstr(t2, 20)))
                ctrl = bezier(T, d0, d3, s["alpha0"], s["alpha3"], n0, n3)
                s["energy"] = energy(ctrl)
                sols.append(s)
    sols.sort(key=lambda s: s["t1"])
    return c, F, G, R, sols


# ------------------------------------------------------------------------------------------
# Bézier in 60-digit arithmetic


def bezier(T, d0, d3, a0, a3, n0=None, n3=None):
    """Control points with unit directions: T0, T0 + α0 d0/(3|d0|), T3 − α3 d3/(3|d3|), T3."""
    P0 = [mpf(v) for v in T[0]]
    P3 = [mpf(v) for v in T[3]]
    u0 = [mpf(v) for v in d0]
    u3 = [mpf(v) for v in d3]
    n0 = n0 if n0 is not None else mp.sqrt(u0[0]**2 + u0[1]**2)
    n3 = n3 if n3 is not None else mp.sqrt(u3[0]**2 + u3[1]**2)
    P1 = [P0[i] + a0 * u0[i] / (3 * n0) for i in range(2)]
    P2 = [P3[i] - a3 * u3[i] / (3 * n3) for i in range(2)]
    return [P0, P1, P2, P3]


def bezier_eval(ctrl, t):
    s = 1 - t
    w = (s**3, 3 * s * s * t, 3 * s * t * t, t**3)
    return [sum(w[k] * ctrl[k][i] for k in range(4)) for i in range(2)]


def energy(ctrl):
    """∫₀¹ |P''|² dt: P'' is linear between a = P''(0) and b = P''(1)."""
    a = [6 * (ctrl[0][i] - 2 * ctrl[1][i] + ctrl[2][i]) for i in range(2)]
    b = [6 * (ctrl[1][i] - 2 * ctrl[2][i] + ctrl[3][i]) for i in range(2)]
    dot = lambda p, r: p[0] * r[0] + p[1] * r[1]
    return (dot(a, a) + dot(a, b) + dot(b, b)) / 3


# ------------------------------------------------------------------------------------------
# CLI


def run_cli(cli, T, d0, d3, workdir):
    path = os.path.join(workdir, "piece.csv")
    with open(path, "w") as f:
        f.write("x,y\n")
        for p in T:
            f.write("{},{}\n".format(p[0], p[1]))
    cmd = [cli, "fit", "-m", "kozak-krajnc", path,
           "--start-tangent={},{}".format(*d0), "--end-tangent={},{}".format(*d3)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    if proc.returncode != 0:
        return None, proc
    try:
        return json.loads(proc.stdout), proc
    except json.JSONDecodeError as e:
        raise AssertionError("CLI output is not JSON ({}): {!r}".format(e, proc.stdout[:200]))


def cli_solutions(out):
    segs = out["method_report"]["segments"]
    assert len(segs) == 1, "expected one piece, got {}".format(len(segs))
    return segs[0], segs[0]["solutions"]


# ------------------------------------------------------------------------------------------
# Comparison


def rel(a, b):
    return abs(mp.mpf(a) - b) / abs(b)


def check_case(cli, name, T, d0, d3, workdir, stats, expect_count=None, verbose=False,
               expect_multiple=None):
    """Returns (fitted: bool, description lines). Raises AssertionError on a disagreement.
    expect_multiple = (multiplicity, t1, t2): the reference must have exactly that solution, with
    α0 = α3 = 1."""
    out, proc = run_cli(cli, T, d0, d3, workdir)
    c, F, G, R, ref = reference(T, d0, d3)
    if expect_multiple is not None:
        k, r1, r2 = expect_multiple
        match = [s for s in ref if s.get("exact") == (r1, r2)]
        assert len(match) == 1 and match[0]["multiplicity"] == k, \
            "the constructed solution ({}, {}) of multiplicity {} is not in the reference".format(
                r1, r2, k)
        a0, a3 = match[0]["alpha0_raw"], match[0]["alpha3_raw"]
        assert abs(a0 - 1) < mp.mpf(10)**-40 and abs(a3 - 1) < mp.mpf(10)**-40, (a0, a3)
    if out is None:
        # With both ends clamped every direction is given, so the CLI solves the piece exactly:
        # it may refuse only data that have no admissible solution at all.
        assert proc.returncode == 1 and "infeasible" in proc.stderr, \
            "CLI failed with {}: {}".format(proc.returncode, proc.stderr.strip())
        assert len(ref) == 0, "CLI refused a piece with {} admissible solution(s): {}".format(
            len(ref), proc.stderr.strip())
        stats.setdefault("refused_exact_counts", []).append(len(ref))
        return False, []
    chosen, sols = cli_solutions(out)
    lines = []
    if name in TABLE_3_1:
        got = tuple(c[k] for k in CONSTANT_NAMES)
        assert got == TABLE_3_1[name], "constants (2.6) {} differ from Table 3.1 {}".format(
            got, TABLE_3_1[name])
        lines.append("  constants (lambda1, lambda2, mu1, mu2, delta1, delta2) = ({})".format(
            ", ".join(str(v) for v in got)))
    assert len(sols) == len(ref), (
        "CLI lists {} admissible solution(s), SymPy finds {}: CLI {} / SymPy {}".format(
            len(sols), len(ref),
            [(s["t1"], s["t2"], s["alpha0"], s["alpha3"]) for s in sols],
            [(mp.nstr(s["t1"], 17), mp.nstr(s["t2"], 17), mp.nstr(s["alpha0"], 17),
              mp.nstr(s["alpha3"], 17)) for s in ref]))
    if expect_count is not None:
        assert len(ref) == expect_count, "expected {} solution(s), SymPy finds {}".format(
            expect_count, len(ref))
    total = sum(s["multiplicity"] for s in ref)
    # Odd by the degree argument of Section 3 whenever Theorem 2.4 or 2.5 holds (outside the
    # theorems a pair of solutions can be born or die at a fold: 2 is possible).
    if chosen.get("theorem"):
        assert total % 2 == 1, "sum of multiplicities {} is even".format(total)
    chord = max(mp.sqrt((mpf(q(T[i + 1][0]) - q(T[i][0])))**2 +
                        (mpf(q(T[i + 1][1]) - q(T[i][1])))**2) for i in range(3))
    Tq = [(q(a), q(b)) for a, b in T]
    d0q, d3q = (q(d0[0]), q(d0[1])), (q(d3[0]), q(d3[1]))
    for s_cli, s_ref in zip(sorted(sols, key=lambda s: s["t1"]), ref):
        simple = s_ref["multiplicity"] == 1
        # A simple solution is determined to about ε over the sine of the angle between the
        # curves (2.3) (the normalized Jacobian): next to a fold that exceeds the tolerances.
        ill = float(ILL_CONDITIONED / abs(s_ref["jacobian"])) if simple else 0.0
        tol_t = max(T1_TOL, ill) if simple else MULTIPLE_TOL
        tol_r = max(REL_TOL, ill) if simple else MULTIPLE_TOL
        et = max(abs(mp.mpf(s_cli["t1"]) - s_ref["t1"]), abs(mp.mpf(s_cli["t2"]) - s_ref["t2"]))
        ea = max(rel(s_cli["alpha0"], s_ref["alpha0"]), rel(s_cli["alpha3"], s_ref["alpha3"]))
        ee = rel(s_cli["energy"], s_ref["energy"])
        key = "simple" if simple else "multiple"
        stats[key + "_t"] = max(stats.get(key + "_t", 0), float(et))
        stats[key + "_alpha"] = max(stats.get(key + "_alpha", 0), float(ea))
        stats[key + "_energy"] = max(stats.get(key + "_energy", 0), float(ee))
        where = "solution t = ({}, {})".format(mp.nstr(s_ref["t1"], 17), mp.nstr(s_ref["t2"], 17))
        assert et <= tol_t, "{}: CLI t = ({!r}, {!r}) off by {:.3g}".format(
            where, s_cli["t1"], s_cli["t2"], float(et))
        assert ea <= tol_r, "{}: CLI α = ({!r}, {!r}) vs ({}, {}): relative {:.3g}".format(
            where, s_cli["alpha0"], s_cli["alpha3"], mp.nstr(s_ref["alpha0"], 17),
            mp.nstr(s_ref["alpha3"], 17), float(ea))
        assert ee <= tol_r, "{}: CLI energy {!r} vs {}: relative {:.3g}".format(
            where, s_cli["energy"], mp.nstr(s_ref["energy"], 17), float(ee))
        assert s_cli["multiplicity"] == s_ref["multiplicity"], \
            "{}: CLI multiplicity {} but the intersection multiplicity is {}".format(
                where, s_cli["multiplicity"], s_ref["multiplicity"])
        # The reported numbers, taken as exact, give a cubic through T1 and T2.
        ctrl = bezier(Tq, d0q, d3q, mp.mpf(s_cli["alpha0"]), mp.mpf(s_cli["alpha3"]))
        for tk, Tk in ((s_cli["t1"], Tq[1]), (s_cli["t2"], Tq[2])):
            p = bezier_eval(ctrl, mp.mpf(tk))
            err = mp.sqrt((p[0] - mpf(Tk[0]))**2 + (p[1] - mpf(Tk[1]))**2) / chord
            stats["interp"] = max(stats.get("interp", 0), float(err))
            assert err <= INTERP_TOL, "{}: P({!r}) misses {} by {:.3g} (relative)".format(
                where, tk, Tk, float(err))
        es = rel(s_cli["energy"], energy(ctrl))
        stats["energy_self"] = max(stats.get("energy_self", 0), float(es))
        assert es <= ENERGY_SELF_TOL, "{}: reported energy {!r} is not ∫|P''|² = {}".format(
            where, s_cli["energy"], mp.nstr(energy(ctrl), 17))
        lines.append("  t1 = {}  t2 = {}  alpha0 = {}  alpha3 = {}  (per |d|: {}, {})  "
                     "multiplicity {}  [CLI: t err {:.1e}, alpha rel err {:.1e}, mult {}]".format(
                         mp.nstr(s_ref["t1"], 16), mp.nstr(s_ref["t2"], 16),
                         mp.nstr(s_ref["alpha0_raw"], 16), mp.nstr(s_ref["alpha3_raw"], 16),
                         mp.nstr(s_ref["alpha0"], 16), mp.nstr(s_ref["alpha3"], 16),
                         s_ref["multiplicity"], float(et), float(ea), s_cli["multiplicity"]))
        if "exact" in s_ref:
            jac = sp.Matrix([[F.diff(X), F.diff(Y)], [G.diff(X), G.diff(Y)]]).subs(
                {X: s_ref["exact"][0], Y: s_ref["exact"][1]})
            lines.append("    exact point ({}, {}); Jacobian {} det {}; Res_t1 root multiplicity "
                         "{}; projections t2 = u + c t1 (c, multiplicity): {}".format(
                             s_ref["exact"][0], s_ref["exact"][1], jac.tolist(), jac.det(),
                             s_ref["resultant_multiplicity"],
                             [(str(cc), m) for cc, m in s_ref["projections"]]))
    best = min(range(len(sols)), key=lambda i: sols[i]["energy"])
    for k in ("t1", "t2", "alpha0", "alpha3", "multiplicity", "energy"):
        assert chosen[k] == sols[best][k], "chosen solution is not the least-energy one: {} {} vs {}".format(
            k, chosen[k], sols[best][k])
    stats.setdefault("counts", []).append(len(ref))
    kind = "convex" if c["lambda1"] > 0 and c["lambda2"] > 0 else "inflection"
    stats[kind] = stats.get(kind, 0) + 1
    return True, lines


# ------------------------------------------------------------------------------------------
# Random pieces


def dec(v):
    """Decimal string of an exact Fraction with a terminating expansion."""
    v = Fraction(v)
    den = v.denominator
    for p in (2, 5):
        while den % p == 0:
            den //= p
    assert den == 1, "{} has no terminating decimal expansion".format(v)
    s = "-" if v < 0 else ""
    v = abs(v)
    whole, frac = divmod(v.numerator, v.denominator)
    digits = ""
    while frac:
        frac *= 10
        digits += str(frac // v.denominator)
        frac %= v.denominator
    return s + str(whole) + ("." + digits if digits else "")


def random_piece(rng):
    """Four points (tenths in [−5, 5]) that are not degenerate and turn by less than a half
    turn, and end directions inside the cone (4.1): d0 = (1−ξ)(−ΔT1) + ξΔT0,
    d3 = (1−ξ)ΔT2 − ξΔT1 with ξ in hundredths (so the directions are exact decimals)."""
    while True:
        T = [(Fraction(rng.randint(-50, 50), 10), Fraction(rng.randint(-50, 50), 10))
             for _ in range(4)]
        dT = [(T[i + 1][0] - T[i][0], T[i + 1][1] - T[i][1]) for i in range(3)]
        D01, D02, D12 = det(dT[0], dT[1]), det(dT[0], dT[2]), det(dT[1], dT[2])
        if D01 == 0 or D12 == 0 or D02 == 0:
            continue
        if D02 / D01 < 0 and D02 / D12 < 0:
            continue
        x0 = Fraction(rng.randint(1, 99), 100)
        x3 = Fraction(rng.randint(1, 99), 100)
        d0 = tuple((1 - x0) * -dT[1][i] + x0 * dT[0][i] for i in range(2))
        d3 = tuple((1 - x3) * dT[2][i] - x3 * dT[1][i] for i in range(2))
        if det(d0, dT[0]) == 0 or det(dT[2], d3) == 0:
            continue
        return ([(dec(a), dec(b)) for a, b in T], (dec(d0[0]), dec(d0[1])),
                (dec(d3[0]), dec(d3[1])))


# ------------------------------------------------------------------------------------------


def main():
    cli = os.environ.get("FAIRSPLINE_CLI")
    if not cli:
        print("test_kozak_krajnc: FAIRSPLINE_CLI is not set (path of the fairspline command)",
              file=sys.stderr)
        return 2
    if not os.access(cli, os.X_OK):
        print("test_kozak_krajnc: FAIRSPLINE_CLI={} is not an executable".format(cli),
              file=sys.stderr)
        return 2
    start = time.time()
    passed = failed = 0
    stats = {}
    rng = random.Random(SEED)
    cases = [(name, T, d0, d3, 1, True, None) for name, T, d0, d3 in PAPER]
    cases += [("multi {}".format(i), T, d0, d3, 3, True, None)
              for i, (T, d0, d3) in enumerate(MULTI)]
    cases += [("multiple {} (order {})".format(i, k), T, d0, d3, None, True,
               (k, sp.Rational(t1.numerator, t1.denominator),
                sp.Rational(t2.numerator, t2.denominator)))
              for i, (k, T, d0, d3, t1, t2) in enumerate(MULTIPLE)]
    cases += [("random {}".format(i), *random_piece(rng), None, False, None)
              for i in range(RANDOM_CANDIDATES)]
    fitted_random = 0
    with tempfile.TemporaryDirectory(prefix="fairspline-kk-") as workdir:
        for name, T, d0, d3, expect, must_fit, multiple in cases:
            try:
                fitted, lines = check_case(cli, name, T, d0, d3, workdir, stats, expect,
                                           expect_multiple=multiple)
                assert fitted or not must_fit, "the CLI refused the data"
            except AssertionError as e:
                failed += 1
                print("FAIL {} (T = {}, d0 = {}, d3 = {}): {}".format(name, T, d0, d3, e))
                continue
            if fitted:
                passed += 1
                fitted_random += name.startswith("random")
            if name.startswith("paper"):
                print("{} (Table 3.2; alpha relative to d as given, and per unit d):".format(name))
                print("\n".join(lines))
    if fitted_random < MIN_RANDOM:
        failed += 1
        print("FAIL only {} of {} random pieces were fitted (need {})".format(
            fitted_random, RANDOM_CANDIDATES, MIN_RANDOM))
    counts = stats.get("counts", [])
    print("random: {} fitted, {} refused as infeasible (exact solution counts there: {})".format(
        fitted_random, RANDOM_CANDIDATES - fitted_random, stats.get("refused_exact_counts", [])))
    print("fitted cases: {} convex (lambda1, lambda2 > 0), {} with an inflection; solution "
          "counts: {}".format(stats.get("convex", 0), stats.get("inflection", 0),
                              {k: counts.count(k) for k in sorted(set(counts))}))
    print("worst CLI errors: simple t {:.2g}, alpha {:.2g}, energy {:.2g}; multiple t {:.2g}, "
          "alpha {:.2g}; interpolation {:.2g}; energy vs its Bezier {:.2g}".format(
              stats.get("simple_t", 0), stats.get("simple_alpha", 0),
              stats.get("simple_energy", 0), stats.get("multiple_t", 0),
              stats.get("multiple_alpha", 0), stats.get("interp", 0),
              stats.get("energy_self", 0)))
    print("kozak-krajnc exact: {} passed, {} failed ({:.1f} s)".format(
        passed, failed, time.time() - start))
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
