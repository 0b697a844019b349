#!/usr/bin/python3
"""Fit a large collection of polylines on a Dask cluster, fairspline.fit_many per partition.

One curve never depends on another, so the collection is split by curve into partitions; each
partition is one Dask task that fits its curves with fairspline.fit_many (the GIL released, the
C++ library doing the work), and returns compact arrays (Bézier control points, energies, error
codes) that are gathered in input order.

Without --scheduler the script starts a LocalCluster on this machine (worker processes on
loopback, no dashboard) and shuts it down at the end; with --scheduler tcp://HOST:8786 it runs
unchanged on a running `distributed` cluster. Every worker must be able to `import fairspline`
(same module build, same Python): local workers inherit PYTHONPATH; on a cluster, install the
build's python/ directory on each worker node and set PYTHONPATH in the workers' environment.

    PYTHONPATH=build/python /usr/bin/python3 examples/dask_batch.py --curves 100000
    PYTHONPATH=build/python /usr/bin/python3 examples/dask_batch.py --scheduler tcp://10.0.0.5:8786

Input: --input FILE.npz with arrays `points` ((total, 2), all curves one after another) and
`lengths` (points per curve); otherwise --curves random polylines of --points points
(deterministic for a given --seed). Output (--output FILE.npz): `counts` (segments per curve,
0 for a failed curve), `segments` ((sum(counts), 4, 2) control points), `linearized_energy`
(NaN for a failed curve) and `errors` (error code per curve, "" when it succeeded).
--check refits everything in this process with fairspline.fit_many and compares exactly.
"""

import argparse
import logging
import os
import sys
import tempfile
import time

import numpy as np

import fairspline


def random_polylines(count, points, seed):
    """`count` random walks of `points` points (turns within ±90°, steps in [0.5, 2])."""
    rng = np.random.default_rng(seed)
    heading = np.cumsum(rng.uniform(-np.pi / 2, np.pi / 2, (count, points - 1)), axis=1)
    step = rng.uniform(0.5, 2.0, (count, points - 1))
    xy = np.zeros((count, points, 2))
    xy[:, 1:, 0] = np.cumsum(step * np.cos(heading), axis=1)
    xy[:, 1:, 1] = np.cumsum(step * np.sin(heading), axis=1)
    return list(xy)


def load_polylines(path):
    data = np.load(path)
    ends = np.cumsum(data["lengths"])
    return np.split(np.asarray(data["points"], dtype=float), ends[:-1])


def pack(curves):
    """A partition as two arrays, (total, 2) points and the lengths: serializing a few large
    arrays is ~40x faster than a list of many small ones."""
    lengths = np.array([len(c) for c in curves], dtype=np.int64)
    points = (np.concatenate([np.asarray(c, dtype=float).reshape(-1, 2) for c in curves])
              if curves else np.empty((0, 2)))
    return points, lengths


def unpack(points, lengths):
    return np.split(points, np.cumsum(lengths)[:-1]) if len(lengths) else []


def fit_partition(points, lengths, method, options, report, threads):
    """Runs on a worker: fits one packed partition with fairspline.fit_many and returns compact
    arrays (cheap to send back)."""
    import fairspline  # noqa: F811 (resolved on the worker)

    fitted = fairspline.fit_many(unpack(points, lengths), method, threads=threads, report=report,
                                 errors="return", **options)
    counts = np.zeros(len(fitted), dtype=np.int64)
    energy = np.full(len(fitted), np.nan)
    errors = []
    pieces = []
    for i, c in enumerate(fitted):
        if isinstance(c, fairspline.Error):
            errors.append(c.code)
            continue
        errors.append("")
        segments = c.segments
        counts[i] = len(segments)
        pieces.append(segments)
        if c.report is not None:
            energy[i] = c.report["linearized_energy"]
    segments = np.concatenate(pieces) if pieces else np.empty((0, 4, 2))
    return {"counts": counts, "segments": segments, "linearized_energy": energy,
            "errors": np.array(errors, dtype="U32")}


def merge(parts):
    return {key: np.concatenate([p[key] for p in parts])
            for key in ("counts", "segments", "linearized_energy", "errors")}


def fit_on_cluster(client, curves, method, options, report, partitions, fit_threads):
    """Partitions by curve, scatters the partitions to the workers, fits, gathers in order."""
    bounds = np.linspace(0, len(curves), partitions + 1).astype(int)
    packed = [pack(curves[a:b]) for a, b in zip(bounds[:-1], bounds[1:]) if b > a]
    points = client.scatter([p for p, _ in packed])  # the data go to the workers once,
    lengths = client.scatter([n for _, n in packed])  # not inside the task graph
    futures = client.map(fit_partition, points, lengths, method=method, options=options,
                         report=report, threads=fit_threads, pure=False)
    return merge(client.gather(futures))


def check_workers(client):
    """Every worker must import the same fairspline as this process."""
    def probe():
        import fairspline
        return fairspline.__version__

    try:
        versions = client.run(probe)
    except ImportError as e:
        sys.exit("dask_batch: a worker cannot import fairspline ({}); put the build's python/ "
                 "directory on every worker's PYTHONPATH".format(e))
    bad = {w: v for w, v in versions.items() if v != fairspline.__version__}
    if bad:
        sys.exit("dask_batch: workers run another fairspline version: {}".format(bad))
    return len(versions)


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scheduler", help="address of a running distributed scheduler "
                   "(default: start a LocalCluster)")
    p.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    p.add_argument("--threads-per-worker", type=int, default=1, help="LocalCluster threads")
    p.add_argument("--curves", type=int, default=10000, help="random polylines to fit")
    p.add_argument("--points", type=int, default=20, help="points per random polyline")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--input", help=".npz with `points` and `lengths` instead of random data")
    p.add_argument("--method", default=fairspline.DEFAULT_METHOD)
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="method option (VALUE as JSON, else a string)")
    p.add_argument("--report", default="basic", choices=["none", "basic", "full"])
    p.add_argument("--partitions", type=int, default=0,
                   help="partitions (default: 4 per worker thread)")
    p.add_argument("--fit-threads", type=int, default=1,
                   help="threads of fit_many inside one task (Dask already runs one task per "
                   "worker thread)")
    p.add_argument("--output", help="write the results to this .npz")
    p.add_argument("--check", action="store_true",
                   help="refit in this process and require identical results")
    return p.parse_args(argv)


def parse_options(items):
    import json

    options = {}
    for item in items:
        key, sep, text = item.partition("=")
        if not sep or not key:
            sys.exit("dask_batch: --set expects KEY=VALUE, got {!r}".format(item))
        try:
            options[key] = json.loads(text)
        except ValueError:
            options[key] = text
    return options


def main(argv=None):
    args = parse_args(argv)
    from dask.distributed import Client, LocalCluster

    options = parse_options(args.set)
    curves = (load_polylines(args.input) if args.input
              else random_polylines(args.curves, args.points, args.seed))
    total_points = sum(len(c) for c in curves)
    print("{} curves, {} points, method {}".format(len(curves), total_points, args.method))

    start = time.perf_counter()
    scratch = None
    if args.scheduler:
        cluster = None
        client = Client(args.scheduler, timeout="30s")
    else:
        # Loopback only, no dashboard, worker files in a scratch directory removed at the end.
        scratch = tempfile.TemporaryDirectory(prefix="fairspline-dask-")
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=args.threads_per_worker,
                               processes=True, host="127.0.0.1", dashboard_address=None,
                               local_directory=scratch.name, silence_logs=logging.WARNING)
        client = Client(cluster)
    try:
        workers = check_workers(client)
        threads = sum(client.nthreads().values())
        partitions = args.partitions or 4 * threads
        ready = time.perf_counter()
        result = fit_on_cluster(client, curves, args.method, options, args.report, partitions,
                                args.fit_threads)
        done = time.perf_counter()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
            scratch.cleanup()
    failed = int(np.count_nonzero(result["errors"]))
    print("{} workers ({} threads), {} partitions: fitted in {:.3f} s = {:.0f} curves/s "
          "({:.3f} s with the cluster's start), {} failed".format(
              workers, threads, partitions, done - ready, len(curves) / (done - ready),
              done - start, failed))

    if args.output:
        os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
        np.savez(args.output, **result)
        print("wrote", args.output)

    if args.check:
        t = time.perf_counter()
        local = fit_partition(*pack(curves), args.method, options, args.report, 0)
        seconds = time.perf_counter() - t
        same = (np.array_equal(local["counts"], result["counts"]) and
                np.array_equal(local["segments"], result["segments"]) and
                np.array_equal(local["linearized_energy"], result["linearized_energy"],
                               equal_nan=True) and
                np.array_equal(local["errors"], result["errors"]))
        print("check: single process fit_many in {:.3f} s; results {}".format(
            seconds, "identical" if same else "DIFFER"))
        if not same:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
