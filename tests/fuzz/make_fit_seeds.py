#!/usr/bin/python3
"""Writes the seeds of fuzz_fit (tests/fuzz/corpus/fuzz_fit/seed-*.bin) from the registry.

fuzz_fit decodes its bytes into a fit request (docs/fuzzing.md; LLVMFuzzerTestOneInput,
make_input and make_options in fuzz_fit.cpp); this script encodes meaningful requests in that
format, so that the fuzzer starts from inputs that reach deep into every method instead of
failing the first input check. The methods, their options (names, types, defaults, bounds,
choices) and their example requests come from the registry, through the CLI:
`fairspline methods --json`. Nothing here names a method except the few hand-made seeds below,
which are written only while their method is registered. For each registered method:
  seed-<method>-example-<k>.bin   the k-th example request of the method's schema ("examples")
  seed-<method>-zigzag.bin, -closed-square.bin, -spiral-chordal.bin   hand-made shapes
Old seed-*.bin files that this run does not write (a method renamed or removed) are deleted;
regression-* files are never touched. It also writes the libFuzzer dictionary tests/fuzz/fit.dict
(every registered name with the NUL that ends it), which CTest fuzz.corpus.fuzz_fit compares
with the registry.

  /usr/bin/python3 tests/fuzz/make_fit_seeds.py [--cli build/apps/cli/fairspline]
      [--out DIR] [--dict FILE] [--verify build/tests/fuzz/fuzz_fit_replay]

--verify runs the given fuzz_fit (replay build or libFuzzer build) on every seed written, with
FUZZ_FIT_PRINT=1, and checks that each decodes to exactly the request it encodes (and that no
seed fails the fuzz target's checks). Run the script again after changing the decoder.
"""
import argparse
import json
import math
import os
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

MAX_POINTS = 64  # kMaxPoints in fuzz_fit.cpp
MAX_NAME = 64  # kMaxNameLength in fuzz_util.hpp
MAX_ITERATIONS = 1000  # kMaxIterations in fuzz_fit.cpp
# ByteReader::number()'s table of extremes (fuzz_util.hpp), for -0.0.
NEG_ZERO_INDEX = 1
KINDS = {"smooth": 0, "clamped": 200, "corner": 240}


class Unencodable(ValueError):
    """A request that the fuzz format cannot express exactly (e.g. more than 60 points);
    `option` names the option at fault, if it is one."""

    def __init__(self, message, option=None):
        super().__init__(message)
        self.option = option


# ---- values, as ByteReader (fuzz_util.hpp) reads them


def is_ordinary(v):
    """ByteReader::ordinary() can give v exactly (an int16 over 2^k, k < 12; not -0.0)."""
    return ordinary_or_none(v) is not None


def ordinary_or_none(v):
    if not math.isfinite(v) or (v == 0 and math.copysign(1, v) < 0):
        return None
    for k in range(12):
        i = v * 2 ** k
        if i == int(i) and -32768 <= i <= 32767:
            return struct.pack(">hB", int(i), k)
    return None


def ordinary_value(b):
    """The value ByteReader::ordinary() reads from the bytes b."""
    return struct.unpack(">h", b[:2])[0] / 2 ** (b[2] % 12)


def ordinary(v):
    b = ordinary_or_none(v)
    if b is None:
        raise Unencodable(f"{v!r} is not an ordinary value")
    return b


def number(v):
    """ByteReader::number(): an ordinary value (mode < 160), -0.0 from the table of extremes,
    anything else as the raw bits of the double (mode >= 240)."""
    v = float(v)
    b = ordinary_or_none(v)
    if b is not None:
        return bytes([0]) + b
    if v == 0:
        return bytes([160, NEG_ZERO_INDEX])
    return bytes([240]) + struct.pack(">d", v)


def name(s):
    """ByteReader::name(): the bytes, then a NUL."""
    b = s.encode()
    if b"\0" in b or len(b) > MAX_NAME:
        raise Unencodable(f"name {s!r} is too long or holds a NUL")
    return b + b"\0"


def direction_angle(angle_deg):
    """direction(): a unit vector at a 16-bit angle (not exact: for hand-made seeds)."""
    a = round(math.radians(angle_deg) / (2 * math.pi) * 65536) % 65536
    return bytes([0]) + struct.pack(">H", a) + bytes([0])


def direction_vector(v):
    """direction(): the vector (x, y) exactly, as two numbers."""
    x, y = pair(v)
    return bytes([200]) + number(x) + number(y)


def pair(v):
    if isinstance(v, dict):
        v = [v.get("x"), v.get("y")]
    if not isinstance(v, (list, tuple)) or len(v) != 2:
        raise Unencodable(f"{v!r} is not [x, y]")
    return float(v[0]), float(v[1])


def count(k, n):
    """count_near(): exactly n (byte < 224), or any count in [0, 66] (byte >= 248)."""
    if k == n:
        return bytes([0])
    if k > MAX_POINTS + 2:
        raise Unencodable(f"{k} entries for {n} points")
    return bytes([248, k])


# ---- options, as make_options (fuzz_fit.cpp) reads them


def any_value(v):
    """any_value() (an option's mode 5) giving v exactly, or None."""
    if isinstance(v, bool):
        return bytes([1, int(v)])
    if isinstance(v, int):
        return bytes([3]) + struct.pack(">q", v)
    if isinstance(v, float):
        return bytes([2]) + number(v)
    if isinstance(v, str) and len(v.encode()) <= 12:
        return bytes([5, len(v.encode())]) + v.encode()
    if isinstance(v, list) and len(v) <= 4 and all(isinstance(x, (int, float)) for x in v):
        return bytes([6, len(v)]) + b"".join(number(x) for x in v)
    if v is None:
        return bytes([0])
    return None


def number_in(v, spec):
    """number_in(): a number within the option's bounds, exactly, or None."""
    lo, hi = spec.get("min"), spec.get("max")
    v = float(v)
    if lo is not None and hi is not None:
        u = round((v - lo) / (hi - lo) * 65535)
        if 0 <= u <= 65535 and lo + (hi - lo) * (u / 65535.0) == v:
            return struct.pack(">H", u)
        return None
    if lo is None and hi is None:
        return ordinary_or_none(v)
    base, sign = (lo, 1) if lo is not None else (hi, -1)  # min + |o|, or max - |o|
    d = (v - base) * sign
    b = ordinary_or_none(d) if d >= 0 else None
    return b if b is not None and base + sign * ordinary_value(b) == v else None


def index(i, n):
    """ByteReader::range(0, n - 1) giving i (no byte at all when n == 1)."""
    if n > 256:
        raise Unencodable(f"a choice out of {n}")
    return bytes([i]) if n > 1 else b""


def option(spec, v, n):
    """One option given the value v: the bytes make_options reads for it."""
    t = spec["type"]
    if "default" in spec and spec["default"] is not None and v == spec["default"] \
            and type(v) is type(spec["default"]):
        return bytes([2])
    valid = None  # mode 3, valid_value()
    if t == "boolean" and isinstance(v, bool):
        valid = bytes([0, int(v)])
    elif t == "choice" and v in spec.get("choices", []):
        valid = index(spec["choices"].index(v), len(spec["choices"]))
    elif t == "choice_or_number" and v in spec.get("choices", []):
        valid = bytes([1]) + index(spec["choices"].index(v), len(spec["choices"]))
    elif t == "string" and isinstance(v, str):
        try:
            valid = bytes([0]) + name(v)
        except Unencodable:
            pass
    elif t == "integer" and isinstance(v, int) and not isinstance(v, bool):
        lo = int(spec.get("min", 0))
        hi = int(min(spec.get("max", MAX_ITERATIONS), MAX_ITERATIONS))
        if lo <= v <= hi:
            span = hi - lo + 1
            width = 1 if span <= 0x100 else 2 if span <= 0x10000 else 4
            valid = (v - lo).to_bytes(width, "big")
    elif t == "number_list" and isinstance(v, list) and len(v) <= MAX_POINTS + 2:
        parts = [number_in(x, spec) for x in v]
        if all(p is not None for p in parts):  # base count 2 (boolean 0), any count via 248
            valid = bytes([0]) + count(len(v), 2) + b"".join(parts)
    if valid is not None:
        return bytes([3]) + valid
    anything = any_value(v)  # mode 5
    if anything is not None:
        return bytes([5]) + anything
    raise Unencodable(f"option {spec['name']} = {v!r} has no exact encoding", spec["name"])


def options_bytes(schema, given, n, absent_default):
    """make_options(): in schema order, each option given, else its default (absent_default
    False: mode 2) or absent (mode 0); then no unknown option (a last byte other than 0xff)."""
    known = {s["name"] for s in schema["options"]}
    unknown = set(given) - known
    if unknown:
        raise Unencodable(f"options {sorted(unknown)} are not in the schema of {schema['name']}")
    out = b""
    for s in schema["options"]:
        if s["name"] in given:
            out += option(s, given[s["name"]], n)
        else:
            out += bytes([0 if absent_default else 2])
    return out + bytes([0])


# ---- a whole input, as LLVMFuzzerTestOneInput and make_input read it


def point(p):
    x, y = pair(p)
    if is_ordinary(x) and is_ordinary(y):
        return bytes([8]) + ordinary(x) + ordinary(y)
    return bytes([6]) + number(x) + number(y)


def point_count(n):
    """n < 12: the byte n; 12..60: a byte >= 200 whose remainder mod 65 is n."""
    if n < 12:
        return bytes([n])
    for b in range(200, 256):
        if b % (MAX_POINTS + 1) == n:
            return bytes([b])
    raise Unencodable(f"{n} points (the fuzz format reaches up to 60)")


def knots_bytes(knots, n, closed):
    out = count(len(knots), n + (1 if closed else 0))
    if not knots:
        return out + bytes([0])
    out += bytes([0]) if knots[0] == 0 and math.copysign(1, knots[0]) > 0 else \
        bytes([200]) + number(knots[0])
    for a, b in zip(knots, knots[1:]):
        step = b - a - 1 / 64
        o = ordinary_or_none(step) if step >= 0 else None
        if o is not None and a + ordinary_value(o) + 1 / 64 == b:
            out += bytes([0]) + o
        elif b == a:
            out += bytes([200])
        else:
            out += bytes([240]) + number(b)
    return out + bytes([0]) + ordinary(0)  # the step after the last knot (read, not used)


def encode(schema, points, closed=False, alpha=None, tangents=None, kinds=None, start=None,
           end=None, knots=None, options=None, reuse=False, absent_default=False):
    """The fuzz_fit input for a request. Tangents: angles in degrees (unit vectors, hand-made
    seeds) or [x, y] vectors (exact); None for a point without one."""
    n = len(points)
    out = name(schema["name"]) + bytes([0 if reuse else 1])
    flags = (1 if closed else 0) | (2 if tangents is not None else 0) \
        | (4 if kinds is not None else 0) | (8 if start is not None else 0) \
        | (16 if end is not None else 0) | (32 if knots is not None else 0)
    out += bytes([flags]) + point_count(n)
    out += b"".join(point(p) for p in points)
    if alpha is None:
        out += bytes([4])  # the default
    elif alpha == 0 or alpha == 1:
        out += bytes([0 if alpha == 0 else 1])
    else:
        out += bytes([3]) + number(alpha)

    def direction(t):
        return direction_angle(t) if isinstance(t, (int, float)) else direction_vector(t)

    if tangents is not None:
        out += count(len(tangents), n)
        out += b"".join(bytes([0]) if t is None else bytes([200]) + direction(t)
                        for t in tangents)
    if kinds is not None:
        out += count(len(kinds), n)
        for k in kinds:
            if k not in KINDS:
                raise Unencodable(f"kind {k!r}")
            out += bytes([KINDS[k]])
    if start is not None:
        out += direction(start)
    if end is not None:
        out += direction(end)
    if knots is not None:
        out += knots_bytes([float(t) for t in knots], n, closed)
    return out + options_bytes(schema, options or {}, n, absent_default)


def encode_example(schema, request):
    """An example request of the schema ({"points": ..., "closed", "options", ...})."""
    r = {k: v for k, v in request.items() if not k.startswith(("_", "$"))}
    if r.pop("method", schema["name"]) != schema["name"]:
        raise Unencodable("the example names another method")
    options = dict(r.pop("options", {}) or {})
    if "lambdas" in r:
        options["lambdas"] = r.pop("lambdas")
    fields = {"points", "closed", "alpha", "tangents", "kinds", "knots", "start_tangent",
              "end_tangent"}
    if set(r) - fields:
        raise Unencodable(f"fields {sorted(set(r) - fields)}")
    tangents = r.get("tangents")
    if tangents is not None:
        tangents = [None if t is None else list(pair(t)) for t in tangents]
    return encode(schema, r["points"], closed=bool(r.get("closed", False)),
                  alpha=r.get("alpha"), tangents=tangents, kinds=r.get("kinds"),
                  start=r.get("start_tangent"), end=r.get("end_tangent"),
                  knots=r.get("knots"), options=options, absent_default=True)


def expected_request(schema, request, reuse):
    """What fuzz_fit prints (FUZZ_FIT_PRINT) for an encoded example, for --verify."""
    r = {k: v for k, v in request.items() if not k.startswith(("_", "$"))}
    options = dict(r.get("options", {}) or {})
    if "lambdas" in r:
        options["lambdas"] = r["lambdas"]
    e = {"method": schema["name"], "reuse": reuse, "closed": bool(r.get("closed", False)),
         "alpha": float(r.get("alpha", 0.5)), "options": options,
         "points": [list(pair(p)) for p in r["points"]]}
    if r.get("tangents"):
        e["tangents"] = [None if t is None else list(pair(t)) for t in r["tangents"]]
    if r.get("kinds"):
        e["kinds"] = r["kinds"]
    if r.get("knots"):
        e["knots"] = [float(t) for t in r["knots"]]
    for f in ("start_tangent", "end_tangent"):
        if r.get(f) is not None:
            e[f] = list(pair(r[f]))
    return e


# ---- the seeds


def hand_made(schemas):
    """The hand-made shapes: three for every registered method, and a few for the shapes one
    method's paper is about (written while that method is registered)."""
    zigzag = [(0, 0), (1, 2), (3, 3), (5, 2), (6, 0), (8, 1), (9, 3)]
    square = [(0, 0), (4, 0), (4, 4), (0, 4)]
    kk = [(0, 0), (1, 0.875), (2.25, 1.5), (3.5, 1.375), (4.625, 0.75), (5.5, 0), (6.625, -0.5)]
    spiral = [(math.floor(16 * r * math.cos(a)) / 16, math.floor(16 * r * math.sin(a)) / 16)
              for r, a in ((1 + 0.3 * i, 0.7 * i) for i in range(11))]
    by_name = {s["name"]: s for s in schemas}
    seeds = {}
    for s in schemas:
        m = s["name"]
        caps = s.get("capabilities", {})
        step = caps.get("points", {}).get("step", 1)

        def shape(points, closed):
            """The points, cut to step·m + 1 for an open curve of a method that needs that."""
            if not closed and step > 1:
                points = points[:(len(points) - 1) // step * step + 1]
            return points

        def tangents(points, closed):
            """For a method that needs tangents: the direction of the neighbours' chord."""
            if caps.get("tangents") != "required":
                return None
            n = len(points)
            out = []
            for i in range(n):
                a = points[i - 1] if closed or i > 0 else points[i]
                b = points[(i + 1) % n] if closed or i + 1 < n else points[i]
                out.append(math.degrees(math.atan2(b[1] - a[1], b[0] - a[0])))
            return out

        z, q, sp = shape(zigzag, False), square, shape(spiral, False)
        seeds[f"{m}-zigzag"] = encode(s, z, tangents=tangents(z, False))
        if caps.get("closed", True):
            seeds[f"{m}-closed-square"] = encode(s, q, closed=True, reuse=True,
                                                 tangents=tangents(q, True))
        seeds[f"{m}-spiral-chordal"] = encode(s, sp, alpha=1, tangents=tangents(sp, False))
    special = {
        "kozak-krajnc-7": ("kozak-krajnc", dict(points=kk)),
        "kozak-krajnc-g2": ("kozak-krajnc", dict(points=kk, options={"g2": True})),
        "yong-cheng-hermite": ("yong-cheng", dict(points=[(0, 0), (3, 0), (5, 2), (3, 4), (0, 3)],
                                                  tangents=[45, 90, 117, 198, 270])),
        "yong-cheng-tangents-from": ("yong-cheng", dict(points=zigzag[:5],
                                                        tangents=[None, 90, None, None, None],
                                                        options={"tangents_from":
                                                                 "jaklic-zagar"})),
        "li-curvature-variation-start": ("li-curvature-variation", dict(points=zigzag, start=45)),
        "li-strain-kinds": ("li-strain", dict(points=zigzag[:5],
                                              tangents=[None, 0, None, None, None],
                                              kinds=["smooth", "clamped", "corner", "smooth",
                                                     "smooth"],
                                              start=30, end=-30, knots=[0, 1, 2.5, 3, 4.5])),
        "quasi-elastic-kinds": ("quasi-elastic", dict(points=zigzag,
                                                      tangents=[None, None, 0, None, None, None,
                                                                None],
                                                      kinds=["smooth", "corner", "clamped",
                                                             "smooth", "smooth", "corner",
                                                             "smooth"], start=90)),
        "jaklic-zagar-reversal": ("jaklic-zagar", dict(points=[(0, 0), (2, 0), (1, 0), (1, 1)],
                                                       options={"reversal": "insert"})),
        "min-energy-centripetal": ("min-energy", dict(points=zigzag, alpha=0.5)),
    }
    for seed, (m, request) in special.items():
        if m not in by_name:
            print(f"make_fit_seeds: {m} is not registered; no seed-{seed}.bin", file=sys.stderr)
            continue
        try:
            seeds[seed] = encode(by_name[m], **request)
        except Unencodable as e:  # e.g. an option renamed
            print(f"make_fit_seeds: seed-{seed}.bin left out: {e}", file=sys.stderr)
    return seeds


def examples(schemas):
    """seed name -> (bytes, the request it must decode to) for every example of every method."""
    seeds = {}
    for s in schemas:
        for k, request in enumerate(s.get("examples", []), start=1):
            if isinstance(request, str):
                request = json.loads(request)
            seed = f"{s['name']}-example-{k}"
            request = dict(request)
            while True:
                try:
                    seeds[seed] = (encode_example(s, request),
                                   expected_request(s, request, False))
                except Unencodable as e:
                    if e.option is None:
                        print(f"make_fit_seeds: seed-{seed}.bin left out: {e}", file=sys.stderr)
                        break
                    # The rest of the example is still a good seed: the option left out.
                    print(f"make_fit_seeds: seed-{seed}.bin without it: {e}", file=sys.stderr)
                    request["options"] = {o: v for o, v in (request.get("options") or {}).items()
                                          if o != e.option}
                    if e.option == "lambdas":
                        request.pop("lambdas", None)
                    continue
                except (KeyError, TypeError, ValueError) as e:
                    print(f"make_fit_seeds: seed-{seed}.bin left out: {e!r}", file=sys.stderr)
                break
    return seeds


def normalized(v):
    """JSON as fuzz_fit prints it (non-finite numbers as strings), numbers as floats."""
    if isinstance(v, bool) or v is None or isinstance(v, str):
        return v
    if isinstance(v, (int, float)):
        f = float(v)
        if math.isnan(f):
            return "NaN"
        if math.isinf(f):
            return "Infinity" if f > 0 else "-Infinity"
        return f
    if isinstance(v, dict):
        return {k: normalized(x) for k, x in v.items()}
    return [normalized(x) for x in v]


def verify(exe, out_dir, files, expected):
    """Runs fuzz_fit on every seed written: none may fail, and each example must decode to its
    request exactly."""
    bad = 0
    for f in files:
        path = os.path.join(out_dir, f)
        run = subprocess.run([exe, path], capture_output=True, text=True, errors="replace",
                             env=dict(os.environ, FUZZ_FIT_PRINT="1"))
        lines = [ln for ln in run.stderr.splitlines() if ln.startswith("fuzz_fit request: ")]
        if run.returncode != 0 or len(lines) != 1:
            print(f"make_fit_seeds: {f}: fuzz_fit failed (exit {run.returncode}):\n{run.stderr}",
                  file=sys.stderr)
            bad += 1
            continue
        got = json.loads(lines[0][len("fuzz_fit request: "):])
        if f in expected and normalized(got) != normalized(expected[f]):
            print(f"make_fit_seeds: {f} decodes to\n  {json.dumps(got)}\ninstead of\n  "
                  f"{json.dumps(expected[f])}", file=sys.stderr)
            bad += 1
    print(f"make_fit_seeds: verified {len(files)} seeds with {exe}: {bad} failed")
    return bad == 0


def write_dict(path, schemas):
    def escaped(b):
        return "".join(chr(c) if 0x20 <= c < 0x7F and c not in b'"\\' else f"\\x{c:02x}"
                       for c in b)

    lines = ["# libFuzzer dictionary of fuzz_fit, written by tests/fuzz/make_fit_seeds.py from",
             "# the registry: every registered method's name with the NUL that ends a name in a",
             "# fuzz_fit input (docs/fuzzing.md). CTest fuzz.corpus.fuzz_fit checks that it lists",
             "# exactly the registered methods."]
    for s in schemas:
        key = "method_" + "".join(c if c.isalnum() else "_" for c in s["name"])
        lines.append(f'{key}="{escaped(s["name"].encode() + bytes([0]))}"')
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


def default_cli():
    if os.environ.get("FAIRSPLINE_CLI"):
        return os.environ["FAIRSPLINE_CLI"]
    return os.path.join(ROOT, "build", "apps", "cli", "fairspline")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cli", default=default_cli(),
                    help="fairspline executable whose registry to read (default: $FAIRSPLINE_CLI "
                         "or build/apps/cli/fairspline)")
    ap.add_argument("--out", default=os.path.join(HERE, "corpus", "fuzz_fit"),
                    help="directory of the seeds (default: tests/fuzz/corpus/fuzz_fit)")
    ap.add_argument("--dict", default=os.path.join(HERE, "fit.dict"),
                    help="libFuzzer dictionary to write (default: tests/fuzz/fit.dict)")
    ap.add_argument("--verify", metavar="FUZZ_FIT",
                    help="check every seed with this fuzz_fit executable")
    args = ap.parse_args()
    if not os.access(args.cli, os.X_OK):
        sys.exit(f"make_fit_seeds: no fairspline executable at {args.cli} (build it, or pass "
                 "--cli)")
    schemas = json.loads(subprocess.run([args.cli, "methods", "--json"], check=True,
                                        capture_output=True).stdout)
    seeds = hand_made(schemas)
    expected = {}
    with_examples = 0
    for seed, (data, request) in examples(schemas).items():
        seeds[seed] = data
        expected[f"seed-{seed}.bin"] = request
        with_examples += 1
    if not any("examples" in s for s in schemas):
        print("make_fit_seeds: the registry gives no \"examples\" (older fairspline?): only the "
              "hand-made shapes", file=sys.stderr)
    os.makedirs(args.out, exist_ok=True)
    written = []
    for seed, data in seeds.items():
        f = f"seed-{seed}.bin"
        with open(os.path.join(args.out, f), "wb") as out:
            out.write(data)
        written.append(f)
    stale = [f for f in os.listdir(args.out) if f.startswith("seed-") and f not in written]
    for f in stale:
        os.remove(os.path.join(args.out, f))
    print(f"make_fit_seeds: {len(seeds)} seeds ({with_examples} from the registry's examples, "
          f"{len(schemas)} methods) in {args.out}" + (f"; removed {len(stale)} stale" if stale
                                                      else ""))
    write_dict(args.dict, schemas)
    if args.verify and not verify(args.verify, args.out, sorted(written), expected):
        sys.exit(1)


if __name__ == "__main__":
    main()
