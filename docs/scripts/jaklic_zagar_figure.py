#!/usr/bin/python3
"""Figure of docs/methods/jaklic-zagar.md: the stationary point of Theorem 6 is a minimum of
the approximate energy below 90 degrees of turn and a maximum above.

Pure Python (no numpy/matplotlib), writes docs/images/jaklic-zagar-finding.svg. The formulas are
re-implemented here from the paper, independently of src/methods/jaklic_zagar.cpp; the C++ tests
check the same numbers (JaklicZagar.FindingTurn135IsAMaximumOfTheApproximateEnergy).

Data of every panel: chords |dT_{i-1}| = 1, |dT_i| = 1.7, knot intervals 1 and 1.3 (the issue's
example), turn angle theta between the chords.

  (a) the d_i-dependent part of the approximate energy (7)+(8) of the two segments at the node,
      E(lambda) = -2 (d.dT_{i-1})^2 / dt_{i-1}^3 - 2 (d.dT_i)^2 / dt_i^3, with d = w(lambda)/|w|
      of (10), for several turns; dots: lambda* of (11) (filled: minimum, open: maximum);
  (b) lambda* of (11) and the minimizer of E over the admissible arc against the turn;
  (c) the two-segment curves at a 135 degree turn: lambda* (the maximum) and lambda = 0.98.

Usage: /usr/bin/python3 docs/scripts/jaklic_zagar_figure.py [output.svg]
"""

import math
import os
import sys

LA, LB = 1.0, 1.7  # |dT_{i-1}|, |dT_i|
HA, HB = 1.0, 1.3  # dt_{i-1}, dt_i


def chords(theta_deg):
    t = math.radians(theta_deg)
    return (LA, 0.0), (LB * math.cos(t), LB * math.sin(t))


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1]


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def perp(a):
    return (-a[1], a[0])


def w_of(A, B, lam):
    """(10): z = sign(A x B), u = z R A, v = -z R B, w = lam u + (1 - lam) v, normalized."""
    z = 1.0 if cross(A, B) > 0 else -1.0
    u = (z * perp(A)[0], z * perp(A)[1])
    v = (-z * perp(B)[0], -z * perp(B)[1])
    w = (lam * u[0] + (1 - lam) * v[0], lam * u[1] + (1 - lam) * v[1])
    n = math.hypot(*w)
    return (w[0] / n, w[1] / n)


def energy(A, B, d):
    """d-dependent part of (2/dt)psi over the two segments (alpha from Theorem 2)."""
    return -2 * dot(d, A) ** 2 / HA**3 - 2 * dot(d, B) ** 2 / HB**3


def lambda_star(A, B):
    """(11) with the sign of u.v in front of the root (the root of rho in (0, 1))."""
    uv = -dot(A, B)
    h0, h1 = HA**3, HB**3
    a1 = h0 * dot(B, B) + 2 * h1 * uv - h1 * dot(A, A)
    a2 = (h1 * dot(A, A) - h0 * dot(B, B)) ** 2 + 4 * h0 * h1 * uv * uv
    if uv == 0:
        return 1.0 if cross(A, B) > 0 else 0.0
    sigma = 1.0 if uv > 0 else -1.0
    return 2 * h1 * uv / (a1 + sigma * math.sqrt(a2))


def argmin_on_arc(A, B, steps=4000):
    best = None
    for k in range(1, steps):
        lam = k / steps
        e = energy(A, B, w_of(A, B, lam))
        if best is None or e < best[0]:
            best = (e, lam)
    return best[1]


# ---------------------------------------------------------------- SVG helpers
class Panel:
    def __init__(self, x0, y0, w, h, xr, yr):
        self.x0, self.y0, self.w, self.h = x0, y0, w, h
        self.xr, self.yr = xr, yr

    def X(self, x):
        return self.x0 + (x - self.xr[0]) / (self.xr[1] - self.xr[0]) * self.w

    def Y(self, y):
        return self.y0 + self.h - (y - self.yr[0]) / (self.yr[1] - self.yr[0]) * self.h


def polyline(panel, pts, color, width=1.6, dash=None):
    d = " ".join("{:.2f},{:.2f}".format(panel.X(x), panel.Y(y)) for x, y in pts)
    extra = ' stroke-dasharray="{}"'.format(dash) if dash else ""
    return '<polyline fill="none" stroke="{}" stroke-width="{}"{} points="{}"/>'.format(
        color, width, extra, d)


def text(x, y, s, size=12, anchor="start", color="#222", weight="normal"):
    s = s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return ('<text x="{:.1f}" y="{:.1f}" font-size="{}" text-anchor="{}" fill="{}" '
            'font-weight="{}">{}</text>').format(x, y, size, anchor, color, weight, s)


def axes(panel, xticks, yticks, xlabel, ylabel, title):
    out = ['<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#444"/>'.format(
        panel.x0, panel.y0, panel.w, panel.h)]
    for v in xticks:
        x = panel.X(v)
        out.append('<line x1="{0:.1f}" y1="{1}" x2="{0:.1f}" y2="{2}" stroke="#ddd"/>'.format(
            x, panel.y0, panel.y0 + panel.h))
        out.append(text(x, panel.y0 + panel.h + 14, "{:g}".format(v), 10, "middle"))
    for v in yticks:
        y = panel.Y(v)
        out.append('<line x1="{}" y1="{:.1f}" x2="{}" y2="{:.1f}" stroke="#ddd"/>'.format(
            panel.x0, y, panel.x0 + panel.w, y))
        out.append(text(panel.x0 - 4, y + 3, "{:g}".format(v), 10, "end"))
    out.append(text(panel.x0 + panel.w / 2, panel.y0 + panel.h + 30, xlabel, 11, "middle"))
    out.append('<text x="{:.1f}" y="{:.1f}" font-size="11" text-anchor="middle" '
               'transform="rotate(-90 {:.1f} {:.1f})">{}</text>'.format(
                   panel.x0 - 34, panel.y0 + panel.h / 2, panel.x0 - 34, panel.y0 + panel.h / 2,
                   ylabel))
    out.append(text(panel.x0, panel.y0 - 8, title, 12, "start", "#111", "bold"))
    return out


COLORS = {45: "#1f77b4", 80: "#2ca02c", 100: "#ff7f0e", 135: "#d62728"}


def panel_energy(out):
    p = Panel(70, 40, 270, 220, (0, 1), (-4.5, 0))
    out += axes(p, [0, 0.25, 0.5, 0.75, 1], [-4, -3, -2, -1, 0], "λ",
                "E(λ) − const", "(a) approximate energy on the arc")
    for turn, color in COLORS.items():
        A, B = chords(turn)
        pts = [(k / 400, energy(A, B, w_of(A, B, k / 400))) for k in range(1, 400)]
        out.append(polyline(p, pts, color))
        lam = lambda_star(A, B)
        e = energy(A, B, w_of(A, B, lam))
        fill = color if turn < 90 else "white"
        out.append('<circle cx="{:.1f}" cy="{:.1f}" r="4.5" fill="{}" stroke="{}" '
                   'stroke-width="2"/>'.format(p.X(lam), p.Y(e), fill, color))
        out.append(text(p.X(lam), p.Y(e) - 9, "{}°".format(turn), 11, "middle", color))
    out.append(text(p.x0 + 8, p.y0 + p.h - 24, "● λ* is a minimum (turn < 90°)", 10))
    out.append(text(p.x0 + 8, p.y0 + p.h - 10, "○ λ* is a maximum (turn > 90°)", 10))
    return p


def panel_lambda(out):
    p = Panel(420, 40, 270, 220, (0, 180), (0, 1))
    out += axes(p, [0, 45, 90, 135, 180], [0, 0.25, 0.5, 0.75, 1], "turn ∠(ΔT_{i−1}, ΔT_i) [°]",
                "λ", "(b) λ* of (11) and the minimizer")
    star, best, speed = [], [], []
    for k in range(1, 360):
        turn = k * 0.5
        if abs(turn - 90) < 1e-9:
            continue
        A, B = chords(turn)
        lam = lambda_star(A, B)
        star.append((turn, lam))
        best.append((turn, argmin_on_arc(A, B, 1000)))
        d = w_of(A, B, lam)
        # slowest end speed of the two segments at the node, relative to its chord: d.dT/|dT|
        speed.append((turn, min(dot(d, A) / LA, dot(d, B) / LB)))
    out.append(polyline(p, best, "#999", 4))
    out.append(polyline(p, [s for s in star if s[0] < 90], "#111", 1.6))
    out.append(polyline(p, [s for s in star if s[0] > 90], "#111", 1.6, "5,3"))
    out.append(polyline(p, [s for s in speed if s[0] < 90], "#9467bd", 1.4, "2,2"))
    out.append(polyline(p, [s for s in speed if s[0] > 90], "#9467bd", 1.4, "2,2"))
    out.append(text(p.X(8), p.Y(0.93), "grey: argmin of E on the arc", 10, "start", "#777"))
    out.append(text(p.X(8), p.Y(0.85), "black: λ* (dashed: a maximum)", 10))
    out.append(text(p.X(8), p.Y(0.12), "purple: slowest end speed d·ΔT/|ΔT| at λ*", 10, "start",
                    "#9467bd"))
    return p


def segment_points(P0, P1, d0, d1, steps=60):
    delta = (P1[0] - P0[0], P1[1] - P0[1])
    a0, a1 = dot(d0, delta) / 3, dot(d1, delta) / 3
    c = [P0, (P0[0] + a0 * d0[0], P0[1] + a0 * d0[1]), (P1[0] - a1 * d1[0], P1[1] - a1 * d1[1]),
         P1]
    pts = []
    for k in range(steps + 1):
        u = k / steps
        b = [(1 - u) ** 3, 3 * u * (1 - u) ** 2, 3 * u * u * (1 - u), u**3]
        pts.append((sum(b[i] * c[i][0] for i in range(4)), sum(b[i] * c[i][1] for i in range(4))))
    return pts


def panel_curves(out):
    p = Panel(770, 40, 220, 220, (-0.45, 1.25), (-0.35, 1.35))
    out += axes(p, [0, 0.5, 1], [0, 0.5, 1], "x", "y", "(c) 135° turn: the two curves")
    A, B = chords(135)
    T0, T1 = (0.0, 0.0), A
    T2 = (T1[0] + B[0], T1[1] + B[1])
    ua, ub = (A[0] / LA, A[1] / LA), (B[0] / LB, B[1] / LB)
    lam = lambda_star(A, B)
    for lam_used, color, label, y in ((lam, "#d62728", "λ* = {:.3f} (max), E = {:.3f}", 1.27),
                                      (0.98, "#1f77b4", "λ = 0.98, E = {:.3f}", 1.17)):
        d = w_of(A, B, lam_used)
        pts = segment_points(T0, T1, ua, d) + segment_points(T1, T2, d, ub)
        out.append(polyline(p, pts, color, 2))
        e = energy(A, B, d)
        s = label.format(lam_used, e) if "λ*" in label else label.format(e)
        out.append(text(p.X(0.0), p.Y(y), s, 10, "start", color))
    out.append(polyline(p, [T0, T1, T2], "#aaa", 1, "3,3"))
    for q in (T0, T1, T2):
        out.append('<circle cx="{:.1f}" cy="{:.1f}" r="3" fill="#222"/>'.format(p.X(q[0]),
                                                                                  p.Y(q[1])))
    return p


def main():
    out_path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "images", "jaklic-zagar-finding.svg")
    A, B = chords(135)
    lam = lambda_star(A, B)
    # The numbers, reproduced (see the docs page).
    assert abs(energy(A, B, w_of(A, B, lam)) - (-0.663051)) < 1e-6
    assert abs(energy(A, B, w_of(A, B, 1 - 1e-9)) - (-1.315430)) < 1e-6
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="1020" height="310" '
           'font-family="DejaVu Sans, Arial, sans-serif">',
           '<rect width="100%" height="100%" fill="white"/>']
    panel_energy(out)
    panel_lambda(out)
    panel_curves(out)
    out.append(text(70, 302, "Chords |ΔT_{i−1}| = 1, |ΔT_i| = 1.7, knot intervals 1, 1.3. "
                    "E = −2(d·ΔT_{i−1})²/Δt_{i−1}³ − 2(d·ΔT_i)²/Δt_i³, the d-dependent part of "
                    "(7)+(8) of the two segments.", 10, "start", "#444"))
    out.append("</svg>")
    os.makedirs(os.path.dirname(os.path.abspath(out_path)), exist_ok=True)
    with open(out_path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")
    print("wrote", out_path)


if __name__ == "__main__":
    main()
