#!/usr/bin/python3
"""Writes the hand-made seeds of fuzz_fit (tests/fuzz/corpus/fuzz_fit/seed-*.bin).

fuzz_fit decodes its bytes into a fit request (see make_input in fuzz_fit.cpp); this script
encodes meaningful requests -- each method on the shapes its paper is about, closed curves,
tangents, kinds, knots, end tangents -- in that format, so the fuzzer starts from inputs that
reach deep into every method instead of failing the first input check.
Run it again after changing the decoder: /usr/bin/python3 tests/fuzz/make_fit_seeds.py
"""
import math
import os
import struct

# Registration order of fairspline::methods() (src/methods/builtin.cpp).
METHODS = ["li-strain", "li-combined", "li-curvature-variation", "jaklic-zagar", "yong-cheng",
           "kozak-krajnc", "quasi-elastic", "min-energy", "cond-g2"]
OPTION_COUNT = {"li-strain": 0, "li-combined": 1, "li-curvature-variation": 0, "jaklic-zagar": 3,
                "yong-cheng": 3, "kozak-krajnc": 5, "quasi-elastic": 4, "min-energy": 4,
                "cond-g2": 4}


def ordinary(v):
    """ByteReader::ordinary(): int16 (big endian) and a shift k, value = i / 2^k."""
    for k in range(12):
        i = v * 2 ** k
        if i == int(i) and -32768 <= i <= 32767:
            return struct.pack(">hB", int(i), k)
    raise ValueError(f"{v} is not an ordinary value")


def direction(angle_deg):
    a = round(math.radians(angle_deg) / (2 * math.pi) * 65536) % 65536
    return bytes([0]) + struct.pack(">H", a) + bytes([0])  # unit length


def encode(method, points, closed=False, alpha=None, tangents=None, kinds=None, start=None,
           end=None, knots=None, options=None, reuse=False):
    out = bytes([METHODS.index(method), 0 if reuse else 1])
    flags = (closed and 1) | (tangents is not None and 2) | (kinds is not None and 4) \
        | (start is not None and 8) | (end is not None and 16) | (knots is not None and 32)
    n = len(points)
    out += bytes([flags, n])  # n < 12, or n + 200 - (200 % 65) style below
    for x, y in points:
        out += bytes([8]) + ordinary(x) + ordinary(y)
    if alpha is None:
        out += bytes([4])
    elif alpha in (0, 1):
        out += bytes([0 if alpha == 0 else 1])
    else:
        out += bytes([2, round(alpha * 255)])
    if tangents is not None:
        out += bytes([0])  # count == n
        for t in tangents:
            out += bytes([0]) if t is None else bytes([200]) + direction(t)
    if kinds is not None:
        out += bytes([0])
        out += bytes({"smooth": 0, "clamped": 200, "corner": 240}[k] for k in kinds)
    if start is not None:
        out += direction(start)
    if end is not None:
        out += direction(end)
    if knots is not None:
        out += bytes([0, 0])  # count == n (+1), starting at 0
        for a, b in zip(knots, knots[1:]):
            out += bytes([0]) + ordinary(b - a - 1 / 64)
        out += bytes([0]) + ordinary(0)
    # Options: 2 = the default for each; explicit choices as (byte, payload).
    opts = options or [2] * OPTION_COUNT[method]
    for o in opts:
        out += o if isinstance(o, bytes) else bytes([o])
    return out + bytes([0])


def main():
    zigzag = [(0, 0), (1, 2), (3, 3), (5, 2), (6, 0), (8, 1), (9, 3)]
    square = [(0, 0), (4, 0), (4, 4), (0, 4)]
    kk = [(0, 0), (1, 0.875), (2.25, 1.5), (3.5, 1.375), (4.625, 0.75), (5.5, 0), (6.625, -0.5)]
    spiral = [(math.floor(16 * r * math.cos(a)) / 16, math.floor(16 * r * math.sin(a)) / 16)
              for r, a in ((1 + 0.3 * i, 0.7 * i) for i in range(11))]
    seeds = {}
    for m in METHODS:
        seeds[f"{m}-zigzag"] = encode(m, zigzag, start=45 if m == "li-curvature-variation" else None)
        seeds[f"{m}-closed-square"] = encode(m, square, closed=True, reuse=True)
        seeds[f"{m}-spiral-chordal"] = encode(m, spiral, alpha=1,
                                              start=0 if m == "li-curvature-variation" else None)
    seeds["kozak-krajnc-7"] = encode("kozak-krajnc", kk)
    seeds["kozak-krajnc-g2"] = encode("kozak-krajnc", kk, options=[2, 2, 2, bytes([3, 0, 1]), 2])
    seeds["yong-cheng-hermite"] = encode("yong-cheng", [(0, 0), (3, 0), (5, 2), (3, 4), (0, 3)],
                                         tangents=[45, 90, 117, 198, 270])
    seeds["li-strain-kinds"] = encode("li-strain", zigzag[:5],
                                      tangents=[None, 0, None, None, None],
                                      kinds=["smooth", "clamped", "corner", "smooth", "smooth"],
                                      start=30, end=-30, knots=[0, 1, 2.5, 3, 4.5])
    seeds["quasi-elastic-kinds"] = encode("quasi-elastic", zigzag,
                                          tangents=[None, None, 0, None, None, None, None],
                                          kinds=["smooth", "corner", "clamped", "smooth",
                                                 "smooth", "corner", "smooth"], start=90)
    seeds["jaklic-zagar-reversal"] = encode("jaklic-zagar", [(0, 0), (2, 0), (1, 0), (1, 1)],
                                            options=[2, 0, bytes([3, 0, 1])])
    seeds["min-energy-centripetal"] = encode("min-energy", zigzag, alpha=0.5)
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "fuzz_fit")
    os.makedirs(here, exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(here, f"seed-{name}.bin"), "wb") as f:
            f.write(data)
    print(f"wrote {len(seeds)} seeds to {here}")


if __name__ == "__main__":
    main()
