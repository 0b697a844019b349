#!/usr/bin/python3
"""Compare fairspline's methods on one data set: a grid of plots with curvature combs.

Notebook-style: each `# %%` cell runs on its own in Jupyter or VS Code; as a script it writes
a PNG (default out/compare_methods.png):

    PYTHONPATH=build/python /usr/bin/python3 examples/compare_methods.py [INPUT.csv] [-o OUT.png]
"""

# %% Setup: the module from the build tree (PYTHONPATH=build/python), Matplotlib without a display
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fairspline  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("input", nargs="?", default=str(HERE / "li-example1.csv"),
                    help="CSV of x,y points (header optional)")
parser.add_argument("-o", "--output", default="out/compare_methods.png", help="PNG to write")
args = parser.parse_args()

# %% The data: x,y per line
points = np.loadtxt(args.input, delimiter=",", comments="#",
                    skiprows=1 if not open(args.input).readline()[0].isdigit() else 0)
print("{} points from {}".format(len(points), args.input))

# %% Fit with several methods; options go in as keyword arguments (or options={...})
methods = [
    ("quasi-elastic", {}),
    ("li-strain", {}),
    ("li-combined", {}),
    ("jaklic-zagar", {}),
    ("yong-cheng", {"tangents_from": "jaklic-zagar"}),
    ("kozak-krajnc", {"gamma": "auto"}),
]
curves = {}
for name, options in methods:
    try:
        curves[name] = fairspline.fit(points, name, report="full", **options)  # + curvature variation
    except fairspline.Error as e:  # e.g. kozak-krajnc needs 3m+1 points
        print("{:14s} skipped: [{}] {}".format(name, e.code, e))

# %% A table of the energies every method reports
print("{:14s} {:>8s} {:>12s} {:>12s} {:>10s}  regular".format(
    "method", "segments", "bending", "linearized", "length"))
for name, c in curves.items():
    r = c.report
    print("{:14s} {:8d} {:12.5g} {:12.5g} {:10.5g}  {}".format(
        name, len(c.segments), r["bending_energy"], r["linearized_energy"], r["length"],
        "yes" if r["regular"] else "NO"))

# %% One panel per method with its curvature comb, and all curves overlaid in the last panel
cols = 4
rows = -(-(len(curves) + 1) // cols)
fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 5.4 * rows))
axes = axes.ravel()
colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
for ax, (name, c), color in zip(axes, curves.items(), colors):
    fairspline.plot(c, ax=ax, comb=True, color=color)
    ax.set_title("{}\nbending {:.4g}, curvature variation {:.3g}".format(
        name, c.report["bending_energy"], c.report["curvature_variation_energy"]), fontsize=9)
overlay = axes[len(curves)]
for (name, c), color in zip(curves.items(), colors):
    fairspline.plot(c, ax=overlay, points=False, color=color, linewidth=1.2)
overlay.plot(points[:, 0], points[:, 1], "ko", markersize=3, zorder=3)
overlay.set_title("all methods", fontsize=9)
overlay.legend(fontsize=7, loc="best")
for ax in axes[len(curves) + 1:]:
    ax.set_visible(False)
fig.suptitle("fairspline methods on {} (curvature combs)".format(pathlib.Path(args.input).name))
fig.tight_layout()

# %% Save
out = pathlib.Path(args.output)
out.parent.mkdir(parents=True, exist_ok=True)
fig.savefig(out, dpi=110)
print("wrote", out)
