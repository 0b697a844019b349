#!/usr/bin/python3
"""Data balls on the data they are for: noisy samples of smooth curves, fitted with radii equal
to the noise amplitude, counted by outcome per method (issue 19).

`fairspline_stress --balls` draws random walks with near-repeated points, collinear runs and
sharp turns; this program draws what a user smoothing a polyline has: circles, ellipses and
wavy closed outlines, sine waves, clothoids and GPS-like tracks, 6 to 320 points, each point
moved uniformly within a disc of radius r = (0.02, 0.1, 0.3 or 0.45) x the median gap (at
most 0.45 x the shortest gap of the noisy points, so that neighbouring discs are apart), and
fitted through discs of that radius.

Usage: /usr/bin/python3 tools/stress/noisy_shapes.py [--seed S] [--count N] [--start K]
       [--methods quasi-elastic,restricted-elastic] [--max-iterations M] [--save DIR]
       [--build DIR]
(after `make`; it imports the Python module built in DIR/python, default build.) Prints, per method,
the outcomes by error code, the failing cases, and the time per fit; --save writes each
failing input as a JSON fit request (the format of tests/data/stress).
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

KINDS = ["circle", "ellipse", "blob", "sine", "clothoid", "track"]


def shape(kind, n, rng):
    """n samples of the named curve and whether it is closed."""
    closed = kind in ("circle", "ellipse", "blob")
    t = np.linspace(0.0, 1.0, n, endpoint=not closed)
    a = 2.0 * math.pi * t
    if kind == "circle":
        return np.c_[np.cos(a), np.sin(a)], True
    if kind == "ellipse":
        return np.c_[2.0 * np.cos(a), 0.7 * np.sin(a)], True
    if kind == "blob":
        r = 1.0 + 0.3 * np.sin(3.0 * a + rng.uniform(0.0, 6.0)) + 0.15 * np.cos(5.0 * a)
        return np.c_[r * np.cos(a), r * np.sin(a)], True
    if kind == "sine":
        x = 6.0 * t
        return np.c_[x, np.sin(x * rng.uniform(0.5, 2.0))], False
    if kind == "clothoid":  # curvature growing linearly with arc length
        s = np.linspace(0.0, 3.0, n)
        ds = s[1] - s[0]
        return np.c_[np.cumsum(np.cos(0.5 * s * s)) * ds, np.cumsum(np.sin(0.5 * s * s)) * ds], False
    heading = np.cumsum(rng.normal(0.0, 0.25, n))  # track: smooth heading, varying speed
    step = rng.uniform(0.5, 1.5, n)
    return np.c_[np.cumsum(step * np.cos(heading)), np.cumsum(step * np.sin(heading))], False


def gaps(p, closed):
    return np.linalg.norm(np.diff(np.vstack([p, p[:1]]) if closed else p, axis=0), axis=1)


def case(seed, c):
    """Case c of a seed: (kind, noisy points, closed, radius)."""
    rng = np.random.default_rng([seed, c])
    kind = KINDS[c % len(KINDS)]
    n = int(rng.choice([6, 10, 20, 40, 80, 160, 320]))
    p, closed = shape(kind, n, rng)
    amp = float(np.median(gaps(p, closed))) * float(rng.choice([0.02, 0.1, 0.3, 0.45]))
    ang = rng.uniform(0.0, 2.0 * math.pi, n)
    rad = amp * np.sqrt(rng.uniform(0.0, 1.0, n))
    q = p + np.c_[rad * np.cos(ang), rad * np.sin(ang)]
    return kind, q, closed, min(amp, 0.45 * float(gaps(q, closed).min()))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=300)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--methods", default="quasi-elastic,restricted-elastic")
    ap.add_argument("--max-iterations", type=int, default=None)
    ap.add_argument("--save", default=None, help="directory for the failing inputs")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="the build directory")
    args = ap.parse_args()
    sys.path.insert(0, os.path.join(os.path.abspath(args.build), "python"))
    import fairspline  # pylint: disable=import-outside-toplevel
    methods = args.methods.split(",")
    options = {} if args.max_iterations is None else {"max_iterations": args.max_iterations}
    outcomes = {m: {} for m in methods}
    failing = {m: [] for m in methods}
    times = {m: [] for m in methods}
    for c in range(args.start, args.start + args.count):
        kind, q, closed, r = case(args.seed, c)
        radii = np.full(len(q), r)
        for m in methods:
            t0 = time.perf_counter()
            try:
                fairspline.fit(q, method=m, closed=closed, radii=radii, report="none",
                               options=options)
                code = "ok"
            except fairspline.Error as e:
                code = e.code
                failing[m].append(f"c{c} ({kind}, {len(q)} points): {e}")
                if args.save:
                    os.makedirs(args.save, exist_ok=True)
                    with open(os.path.join(args.save, f"{m}-balls-{code}-noisy-s{args.seed}-c{c}.json"),
                              "w") as f:
                        json.dump({"_stress": {"case": c, "seed": args.seed, "outcome": code,
                                               "message": str(e), "shape": f"noisy {kind}",
                                               "replay": f"tools/stress/noisy_shapes.py --seed {args.seed} "
                                                         f"--start {c} --count 1 --methods {m}",
                                               "variant": m},
                                   "method": m, "closed": closed, "options": options,
                                   "points": q.tolist(), "radii": radii.tolist()}, f, indent=1)
            times[m].append(time.perf_counter() - t0)
            outcomes[m][code] = outcomes[m].get(code, 0) + 1
    for m in methods:
        t = np.array(times[m]) * 1e3
        print(f"{m}: {args.count} fits, outcomes {outcomes[m]}, "
              f"ms mean {t.mean():.1f} max {t.max():.0f}")
        for line in failing[m]:
            print("   ", line[:200])


if __name__ == "__main__":
    main()
