#!/usr/bin/python3
"""Writes tests/methods/kozak_krajnc_double_roots.inc: single Kozak–Krajnc pieces whose system
(2.3) has a root of multiplicity exactly 2 at a known rational point (t1, t2).

Construction. A cubic P with control points b0, b1, b2, b3 and parameters 0 < t1 < t2 < 1 give
data Ti = P(ti), d0 = P'(0), d3 = P'(1) with the solution (t1, t2, α0 = α3 = 1). The Jacobian of
the interpolation conditions P(ti) = Ti in (t1, t2, α0, α3) is singular iff some Q = a0 d0 B1 −
a3 d3 B2 (a change of the inner control points along the end directions) has Q(ti) ∥ P'(ti) at
both ti:

    det(d0, P'(t1)) det(d3, P'(t2)) B1(t1) B2(t2) = det(d0, P'(t2)) det(d3, P'(t1)) B1(t2) B2(t1).

With b2 = β + c·(b1 − b0) the factors det(d0, ·) do not depend on c and the others are affine
in c, so the condition is linear in c: c is rational and so is every coordinate; the data are
scaled to integers (exact in double). Each case is then checked in exact arithmetic on the
cleared system F, G (docs/methods/kozak-krajnc.md): F = G = L1 = 0 and L2 ≠ 0 at (t1, t2), where
L0 = G, L_{j+1} = F_x ∂L_j/∂t2 − F_y ∂L_j/∂t1, with ∇F ≠ 0 (contact of order exactly 2). t1, t2
are drawn from k/32, 2 ≤ k ≤ 29, away from the ends of (0, 1), where the eliminated polynomial is
computed too inaccurately to show a double root (the solver's documented limitation).

Usage: tests/py/make_kozak_krajnc_double_roots.py [COUNT] (default 40; seed fixed).
"""

import math
import os
import random
import sys
from fractions import Fraction as Fr

import sympy as sp

SEED = 20070547
X, Y = sp.symbols("t1 t2")


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def bezier(b, t):
    s = 1 - t
    return tuple(b[0][i] * s**3 + 3 * b[1][i] * s * s * t + 3 * b[2][i] * s * t * t + b[3][i] * t**3
                 for i in range(2))


def derivative(b, t):
    s = 1 - t
    return tuple(3 * ((b[1][i] - b[0][i]) * s * s + 2 * (b[2][i] - b[1][i]) * s * t +
                      (b[3][i] - b[2][i]) * t * t) for i in range(2))


def B1(t):
    return 3 * t * (1 - t)**2


def B2(t):
    return 3 * t * t * (1 - t)


def singularity(b, t1, t2):
    d0, d3 = derivative(b, 0), derivative(b, 1)
    p1, p2 = derivative(b, t1), derivative(b, t2)
    return (cross(d0, p1) * cross(d3, p2) * B1(t1) * B2(t2) -
            cross(d0, p2) * cross(d3, p1) * B1(t2) * B2(t1))


def constants(T, d0, d3):
    e = [(T[i + 1][0] - T[i][0], T[i + 1][1] - T[i][1]) for i in range(3)]
    D01, D02, D12 = cross(e[0], e[1]), cross(e[0], e[2]), cross(e[1], e[2])
    e0, e3 = cross(d0, e[0]), cross(e[2], d3)
    if 0 in (D01, D02, D12, e0, e3):
        return None
    l1, l2 = Fr(D02, 1) / D01, Fr(D02, 1) / D12
    m1, m2 = Fr(cross(d0, e[1]), 1) / e0, Fr(cross(e[1], d3), 1) / e3
    return l1, l2, m1, m2


def lie_values(c, t1, t2):
    """F, L0, L1, L2 and ∇F at (t1, t2), exactly."""
    l1, l2, m1, m2 = (sp.Rational(v.numerator, v.denominator) for v in c)
    A1 = 1 + m1 * (1 + l1) - l1 / l2
    A2 = 1 + m2 * (1 + l2) - l2 / l1
    F = sp.expand(Y**2 * (1 - Y) - (1 + m1) * X**2 * (1 - X) + A1 * (Y - X) * X**2 * Y**2)
    G = sp.expand(X * (1 - X)**2 - (1 + m2) * Y * (1 - Y)**2 + A2 * (Y - X) * (1 - X)**2 * (1 - Y)**2)
    Fx, Fy = F.diff(X), F.diff(Y)
    L = [G]
    for _ in range(2):
        L.append(sp.expand(Fx * L[-1].diff(Y) - Fy * L[-1].diff(X)))
    at = {X: sp.Rational(t1.numerator, t1.denominator), Y: sp.Rational(t2.numerator, t2.denominator)}
    return F.subs(at), [v.subs(at) for v in L], (Fx.subs(at), Fy.subs(at))


def integers(T, d0, d3):
    values = [v for p in T + [d0, d3] for v in p]
    scale = 1
    for v in values:
        scale = scale * v.denominator // math.gcd(scale, v.denominator)
    return [tuple(int(v * scale) for v in p) for p in T + [d0, d3]]


def cases(count, rng):
    def point():
        return (Fr(rng.randint(-6, 6)), Fr(rng.randint(-6, 6)))

    out = []
    while len(out) < count:
        b0, b1, beta, b3 = point(), point(), point(), point()
        k1 = rng.randint(2, 28)
        k2 = rng.randint(k1 + 1, 29)
        t1, t2 = Fr(k1, 32), Fr(k2, 32)
        w = (b1[0] - b0[0], b1[1] - b0[1])
        f = lambda c: singularity((b0, b1, (beta[0] + c * w[0], beta[1] + c * w[1]), b3), t1, t2)
        f0, f1 = f(Fr(0)), f(Fr(1))
        assert f(Fr(2)) - 2 * f1 + f0 == 0  # linear in c
        if f1 == f0:
            continue
        c = -f0 / (f1 - f0)
        b = (b0, b1, (beta[0] + c * w[0], beta[1] + c * w[1]), b3)
        T = [bezier(b, t) for t in (0, t1, t2, 1)]
        d0, d3 = derivative(b, 0), derivative(b, 1)
        k = constants(T, d0, d3)
        if k is None:
            continue
        F, L, grad = lie_values(k, t1, t2)
        assert F == 0 and L[0] == 0 and L[1] == 0, (F, L)
        if grad == (0, 0) or L[2] == 0:
            continue  # a singular point of F = 0, or contact of order 3 or more
        data = integers(T, d0, d3)
        if max(abs(v) for p in data for v in p) >= 2**53:
            continue
        out.append((data, t1, t2))
    return out


def main():
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    here = os.path.dirname(os.path.abspath(__file__))
    path = os.path.join(here, "..", "methods", "kozak_krajnc_double_roots.inc")
    lines = [
        "// Generated by tests/py/make_kozak_krajnc_double_roots.py (seed {}): do not edit.".format(SEED),
        "// {T0, T1, T2, T3, d0, d3, t1, t2}: data of a cubic P with P(ti) = Ti, P'(0) = d0,",
        "// P'(1) = d3, so (t1, t2, alpha0 = 1, alpha3 = 1) solves (2.3)-(2.5); checked in exact",
        "// arithmetic to be a root of multiplicity exactly 2 (see the script).",
    ]
    for data, t1, t2 in cases(count, random.Random(SEED)):
        pts = ", ".join("{{{}, {}}}".format(x, y) for x, y in data)
        lines.append("{{{{{}}}, {}.0 / 32, {}.0 / 32}},".format(
            pts, t1.numerator * 32 // t1.denominator, t2.numerator * 32 // t2.denominator))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote {} cases to {}".format(count, os.path.normpath(path)))


if __name__ == "__main__":
    main()
