#!/usr/bin/python3
"""Throughput of a fairspline method against SciPy, measured in the same run.

The peer is SciPy's parametric cubic spline on the same kind of data: a random walk of n
points (turn angles uniform in +-120 degrees, steps uniform in [0.5, 2], the distribution of
bench/bench_data.hpp), alpha-parameterized knots t_{i+1} = t_i + |P_{i+1} - P_i|^alpha, then
    CubicSpline(t, xy, bc_type='natural', axis=0)       (open)
    CubicSpline(t, xy + [xy[0]], bc_type='periodic')    (closed)
timed best of --repeat, knot computation included. `--peer pchip|akima` times SciPy's local
interpolants instead (peers for the local methods); `--peer linear` the linear spline
make_interp_spline(t, xy, k=1) (the peer of the minimal-energy methods' speed goal).

fairspline is timed by
  * the benchmark binary (--bench, default build/bench/fairspline_bench), benchmark
    fit/<method>/<open|closed>[/alpha:<a>]/<n>, its real_time and cpu_time per fit (its
    items_per_second is n / cpu_time), best of --repeat repetitions;
  * the CLI, if --cli is given and it has a `bench` subcommand:
    `fairspline bench -m METHOD -n N --repeat R [--closed]` printing
    {"method", "n", "seconds", "points_per_second"} (it generates its own walk of the same
    distribution; it is skipped for a non-default --alpha it cannot take).

Clocks: SciPy is timed with both the wall clock and the process CPU clock (user + system,
so page faults count); Google Benchmark reports both; the CLI reports wall time only. The
ratio compares like with like: CPU time when both sides have it (robust when other jobs share
the machine), else wall time. A wall/CPU ratio well above 1 in the table means the machine
was busy and wall times are inflated.

Prints a table and the ratio fairspline / SciPy, and reports (does not assert) the target
ratio. Exits non-zero only on errors: no fairspline measurement at all, a failing binary,
bad arguments.

`--benchmark NAME` times other benchmarks of the binary that process --n items per iteration
(e.g. ogh/segments/1000000, coh/dispatch/1000000 of bench/yong_cheng_bench.cpp): their items
per second are compared with SciPy's points per second.

Usage: /usr/bin/python3 bench/compare_scipy.py [--cli build/apps/cli/fairspline]
       [--method li-strain] [--n 1000000] [--closed] [--alpha 0.5] [--repeat 5] [--json OUT]
       [--benchmark NAME ...]
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import scipy
from scipy.interpolate import (Akima1DInterpolator, CubicSpline, PchipInterpolator,
                               make_interp_spline)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The speed goals (ratio to SciPy's natural CubicSpline) that --target defaults to: issue 22's
# for the default method (a fresh result) and li-strain (fit_into), the method pages' otherwise.
GOALS = {"quasi-elastic": 1.0, "li-strain": 12.0, "jaklic-zagar": 8.0}
# With --benchmark: the goal of the first benchmark named (yong-cheng.md, issue 22).
BENCHMARK_GOALS = {"ogh/segments/": 12.0, "coh/dispatch/": 2.5}

MAX_TURN_DEG = 120.0
MIN_STEP, MAX_STEP = 0.5, 2.0
DEFAULT_ALPHA = 0.5


class CompareError(Exception):
    """An error that makes the comparison meaningless (exit status 2)."""


def random_walk(n, seed):
    """n points of a planar random walk from the origin (same distribution as bench_data.hpp)."""
    rng = np.random.default_rng(seed)
    max_turn = math.radians(MAX_TURN_DEG)
    heading = np.cumsum(rng.uniform(-max_turn, max_turn, n - 1))
    step = rng.uniform(MIN_STEP, MAX_STEP, n - 1)
    xy = np.zeros((n, 2))
    xy[1:, 0] = np.cumsum(step * np.cos(heading))
    xy[1:, 1] = np.cumsum(step * np.sin(heading))
    return xy


def alpha_knots(xy, alpha, closed):
    """t_0 = 0, t_{i+1} = t_i + |P_{i+1} - P_i|^alpha (closed: one more knot for the closing span)."""
    d = np.diff(np.vstack((xy, xy[:1])) if closed else xy, axis=0)
    dist = np.hypot(d[:, 0], d[:, 1])
    if alpha == 0.0:
        dt = np.ones_like(dist)
    elif alpha == 0.5:
        dt = np.sqrt(dist)
    elif alpha == 1.0:
        dt = dist
    else:
        dt = dist**alpha
    t = np.empty(len(dt) + 1)
    t[0] = 0.0
    np.cumsum(dt, out=t[1:])
    return t


def scipy_fit(xy, alpha, closed, peer):
    t = alpha_knots(xy, alpha, closed)
    if closed:
        xy = np.vstack((xy, xy[:1]))
    if peer == "cubic":
        return CubicSpline(t, xy, bc_type="periodic" if closed else "natural", axis=0)
    if peer == "pchip":
        return PchipInterpolator(t, xy, axis=0)
    if peer == "linear":
        return make_interp_spline(t, xy, k=1, axis=0)
    return Akima1DInterpolator(t, xy, axis=0)


def peer_label(peer, closed):
    if peer == "cubic":
        return "SciPy CubicSpline " + ("periodic" if closed else "natural")
    return {"pchip": "SciPy PchipInterpolator", "akima": "SciPy Akima1DInterpolator",
            "linear": "SciPy make_interp_spline k=1 (linear)"}[peer]


def time_scipy(xy, alpha, closed, peer, repeat):
    """(best wall seconds, best CPU seconds) of `repeat` fits, knot computation included."""
    best_wall = best_cpu = math.inf
    for _ in range(repeat):
        wall0, cpu0 = time.perf_counter(), time.process_time()
        spline = scipy_fit(xy, alpha, closed, peer)
        cpu1, wall1 = time.process_time(), time.perf_counter()
        best_wall, best_cpu = min(best_wall, wall1 - wall0), min(best_cpu, cpu1 - cpu0)
        del spline
    return best_wall, best_cpu


def benchmark_name(method, closed, alpha, n):
    name = "fit/{}/{}".format(method, "closed" if closed else "open")
    if alpha != DEFAULT_ALPHA:
        # Matches std::to_string(alpha) in bench_data.hpp (six decimals).
        name += "/alpha:{:.6f}".format(alpha)
    return "{}/{}".format(name, n)


def run(cmd, timeout):
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        raise CompareError("timed out after {} s: {}".format(timeout, " ".join(cmd))) from e
    except OSError as e:
        raise CompareError("cannot run {}: {}".format(cmd[0], e)) from e
    return proc


def time_bench_binary(binary, name, repeat, timeout):
    """(wall seconds, CPU seconds) per fit of benchmark `name`, each the best of `repeat`
    repetitions; None when the binary has no such benchmark."""
    # The fit benchmarks measure the CPU time of every thread, which Google Benchmark marks
    # by the suffix /process_time.
    regex = "^{}(/process_time)?$".format(name.replace(".", "\\."))
    cmd = [binary, "--benchmark_filter=" + regex, "--benchmark_format=json",
           "--benchmark_repetitions={}".format(max(1, repeat))]
    proc = run(cmd, timeout)
    if proc.returncode != 0:
        raise CompareError("{} failed (exit {}):\n{}".format(" ".join(cmd), proc.returncode,
                                                            proc.stderr.strip()))
    if not proc.stdout.strip() and "Failed to match" in proc.stderr:
        return None
    try:
        report = json.loads(proc.stdout)
    except json.JSONDecodeError as e:
        raise CompareError("{} did not print JSON: {}".format(binary, e)) from e
    runs = [b for b in report.get("benchmarks", [])
            if b.get("run_type", "iteration") == "iteration"
            and b.get("run_name", b["name"]).removesuffix("/process_time") == name]
    for b in runs:
        if b.get("error_occurred"):
            raise CompareError("benchmark {} failed: {}".format(name, b.get("error_message")))
    runs = [b for b in runs if "real_time" in b and "cpu_time" in b]
    if not runs:
        return None
    unit = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
    wall = min(float(b["real_time"]) * unit[b.get("time_unit", "ns")] for b in runs)
    cpu = min(float(b["cpu_time"]) * unit[b.get("time_unit", "ns")] for b in runs)
    return wall, cpu


def cli_has_bench(cli):
    proc = run([cli, "bench", "--help"], 60)
    return proc.returncode == 0, proc.stdout + proc.stderr


def time_cli(cli, method, n, closed, alpha, repeat, timeout):
    """(wall seconds, None) from `fairspline bench` and the command, or None and a note."""
    ok, help_text = cli_has_bench(cli)
    if not ok:
        return None, "the CLI has no 'bench' subcommand"
    cmd = [cli, "bench", "-m", method, "-n", str(n), "--repeat", str(repeat)]
    if closed:
        if "--closed" not in help_text:
            return None, "'fairspline bench' has no --closed option"
        cmd.append("--closed")
    if alpha != DEFAULT_ALPHA:
        if "--alpha" not in help_text:
            return None, "'fairspline bench' has no --alpha option"
        cmd += ["--alpha", repr(alpha)]
    proc = run(cmd, timeout)
    if proc.returncode != 0:
        raise CompareError("{} failed (exit {}):\n{}".format(" ".join(cmd), proc.returncode,
                                                            proc.stderr.strip()))
    try:
        out = json.loads(proc.stdout)
        seconds = float(out["seconds"])
        float(out["points_per_second"])
    except (json.JSONDecodeError, KeyError, TypeError, ValueError) as e:
        raise CompareError("unexpected output of {}: {!r} ({})".format(
            " ".join(cmd), proc.stdout[:300], e)) from e
    if out.get("n") not in (None, n):
        raise CompareError("'fairspline bench' timed n = {}, asked for {}".format(out.get("n"), n))
    if out.get("method") not in (None, method):
        raise CompareError("'fairspline bench' timed method {!r}, asked for {!r}".format(
            out.get("method"), method))
    return (seconds, None), " ".join(cmd[1:])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--method", default="li-strain", help="fairspline method (default li-strain)")
    ap.add_argument("--peer", choices=("cubic", "pchip", "akima", "linear"), default="cubic",
                    help="SciPy peer: CubicSpline natural/periodic (default), Pchip, Akima or "
                    "the linear spline make_interp_spline(k=1)")
    ap.add_argument("--n", type=int, default=1_000_000, help="number of points (default 1e6)")
    ap.add_argument("--closed", action="store_true", help="closed curve (SciPy: periodic)")
    ap.add_argument("--alpha", type=float, default=DEFAULT_ALPHA, help="knot exponent in [0, 1]")
    ap.add_argument("--repeat", type=int, default=5, help="best of this many runs (default 5)")
    ap.add_argument("--seed", type=int, default=20240601)
    ap.add_argument("--bench", default=os.path.join(ROOT, "build", "bench", "fairspline_bench"),
                    help="Google Benchmark binary (default build/bench/fairspline_bench)")
    ap.add_argument("--no-bench", action="store_true", help="do not run the benchmark binary")
    ap.add_argument("--benchmark", action="append", metavar="NAME",
                    help="time this benchmark of the binary instead of fit/<method>/...; it must "
                         "process --n items per iteration (e.g. ogh/segments/1000000); "
                         "repeatable")
    ap.add_argument("--cli", help="fairspline CLI; used when it has a 'bench' subcommand")
    ap.add_argument("--target", type=float, default=None,
                    help="ratio fairspline/SciPy to report against (default: the goal of the "
                         "first --benchmark or of the method, from issue 22 and the method "
                         "pages, see BENCHMARK_GOALS and GOALS; else 10)")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per external command")
    ap.add_argument("--json", metavar="OUT", help="also write the results as JSON to OUT")
    args = ap.parse_args(argv)
    if args.target is None and args.benchmark:
        args.target = next((goal for prefix, goal in BENCHMARK_GOALS.items()
                            if args.benchmark[0].startswith(prefix)), None)
    if args.target is None:
        args.target = GOALS.get(args.method, 10.0)
    if args.n < 3 or args.repeat < 1 or not 0.0 <= args.alpha <= 1.0:
        ap.error("need --n >= 3, --repeat >= 1 and --alpha in [0, 1]")
    if args.closed and args.peer != "cubic":
        ap.error("--closed is only available with --peer cubic (periodic)")

    xy = random_walk(args.n, args.seed)
    shape = "closed" if args.closed else "open"
    rows = []  # (label, wall seconds, CPU seconds or None)
    notes = []

    scipy_wall, scipy_cpu = time_scipy(xy, args.alpha, args.closed, args.peer, args.repeat)
    rows.append(("{} (best of {})".format(peer_label(args.peer, args.closed), args.repeat),
                 scipy_wall, scipy_cpu))
    del xy

    fair = []
    if not args.no_bench:
        name = benchmark_name(args.method, args.closed, args.alpha, args.n)
        if not os.path.exists(args.bench):
            notes.append("benchmark binary {} not found (build target fairspline_bench)".format(
                args.bench))
        else:
            # fit/...: a fresh FitResult per fit; fit_into/...: the result's memory reused.
            names = args.benchmark or (name, "fit_into/" + name[len("fit/"):])
            for bench_name in names:
                res = time_bench_binary(args.bench, bench_name, args.repeat, args.timeout)
                if res is None:
                    notes.append("{} has no benchmark {} (see --benchmark_list_tests)".format(
                        os.path.basename(args.bench), bench_name))
                else:
                    rows.append(("fairspline_bench {} (best of {})".format(
                        bench_name, args.repeat),) + res)
                    fair.append(len(rows) - 1)
    if args.cli:
        if not os.path.exists(args.cli):
            raise CompareError("CLI {} not found".format(args.cli))
        res, note = time_cli(args.cli, args.method, args.n, args.closed, args.alpha, args.repeat,
                             args.timeout)
        if res is None:
            notes.append("CLI not timed: " + note)
        else:
            rows.append(("fairspline " + note,) + res)
            fair.append(len(rows) - 1)

    def ratio_of(row):
        """(ratio to SciPy, clock) on matching clocks."""
        _, wall, cpu = row
        if cpu is not None:
            return scipy_cpu / cpu, "cpu"
        return scipy_wall / wall, "wall"

    print("{} vs {}: {} curve, alpha = {}, n = {} random-walk points "
          "(numpy {}, scipy {})".format(args.method, peer_label(args.peer, args.closed), shape,
                                        args.alpha, args.n, np.__version__, scipy.__version__))
    width = max(len(r[0]) for r in rows)
    print("{:<{w}}  {:>9}  {:>9}  {:>12}  {:>14}".format(
        "timing", "wall s", "CPU s", "points/s", "vs SciPy", w=width))
    for k, row in enumerate(rows):
        label, wall, cpu = row
        pps = args.n / (cpu if cpu is not None else wall)
        cpu_text = "{:9.4f}".format(cpu) if cpu is not None else "{:>9}".format("-")
        if k == 0:
            vs = "1.00x"
        else:
            r, clock = ratio_of(row)
            vs = "{:.2f}x ({})".format(r, clock)
        print("{:<{w}}  {:9.4f}  {}  {:12.4g}  {:>14}".format(label, wall, cpu_text, pps, vs,
                                                            w=width))
    print("points/s from CPU time where measured, else wall time")
    if scipy_wall > 1.5 * scipy_cpu:
        notes.append("wall time is {:.1f}x CPU time for SciPy: the machine is busy, wall-clock "
                     "numbers are inflated".format(scipy_wall / scipy_cpu))
    for note in notes:
        print("note: " + note)
    if not fair:
        raise CompareError("no fairspline measurement (give --bench BIN and/or --cli PATH)")
    ratio, clock = max(ratio_of(rows[k]) for k in fair)
    verdict = "met" if ratio >= args.target else "NOT met"
    print("ratio fairspline/SciPy = {:.2f} ({} time; target >= {:g}x: {})".format(
        ratio, clock, args.target, verdict))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"method": args.method, "peer": args.peer, "n": args.n, "closed": args.closed,
                       "alpha": args.alpha,
                       "scipy": {"wall_seconds": scipy_wall, "cpu_seconds": scipy_cpu},
                       "timings": [{"label": l, "wall_seconds": w, "cpu_seconds": c,
                                    "ratio": None if k == 0 else ratio_of(rows[k])[0],
                                    "clock": None if k == 0 else ratio_of(rows[k])[1]}
                                   for k, (l, w, c) in enumerate(rows)],
                       "ratio": ratio, "clock": clock, "target": args.target,
                       "target_met": ratio >= args.target, "notes": notes}, f, indent=2)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except CompareError as e:
        print("compare_scipy: error: " + str(e), file=sys.stderr)
        sys.exit(2)
