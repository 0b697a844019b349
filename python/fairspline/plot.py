"""Matplotlib drawing of fairspline curves (Matplotlib is imported only when plot() is called)."""

import numpy as np


def comb_teeth(curve, samples_per_segment=16, scale=None):
    """Curvature comb of `curve`: (bases, tips), two (k, 2) arrays.

    Samples every piece at `samples_per_segment` + 1 equally spaced local parameters (the piece
    ends included), as the SVG output does. A tooth runs from the curve point along the normal,
    away from the center of curvature, with length scale * |curvature|; scale=None makes the
    longest tooth 10% of the larger side of the curve's bounding box. Samples where the speed
    vanishes get no tooth (tip = base).
    """
    n = max(1, int(samples_per_segment))
    ranges = curve.segment_ranges
    u = np.linspace(0.0, 1.0, n + 1)
    t = ranges[:, :1] + u[None, :] * (ranges[:, 1:] - ranges[:, :1])
    t = np.clip(t, *curve.t_range).ravel()
    base = curve.evaluate(t)
    d = curve.derivative(t)
    speed = np.hypot(d[:, 0], d[:, 1])
    ok = speed > 0
    normal = np.zeros_like(d)
    normal[ok] = np.stack((-d[ok, 1], d[ok, 0]), axis=1) / speed[ok, None]
    kappa = np.where(ok, curve.curvature(t), 0.0)
    if scale is None:
        extent = np.ptp(base, axis=0).max()
        kmax = np.abs(kappa).max()
        scale = 0.1 * extent / kmax if kmax > 0 else 0.0
    tips = base - (scale * kappa)[:, None] * normal
    return base, tips


def plot(curve, ax=None, comb=False, points=True, *, samples_per_segment=32,
         comb_samples_per_segment=16, comb_scale=None, control_polygon=False, label=None,
         **line_kwargs):
    """Draws a fairspline Curve on Matplotlib axes and returns the axes.

    curve        a fairspline.Curve (from fit or fit_many)
    ax           the Axes to draw on; None: a new figure and axes (plt.subplots())
    comb         also draw the curvature comb (teeth and their envelope, see comb_teeth)
    points       mark the input points
    samples_per_segment       points drawn per Bézier piece
    comb_samples_per_segment  comb teeth per piece; comb_scale: tooth length per unit
                 curvature (None: automatic, the longest tooth 10% of the drawing's size)
    control_polygon  dashed control polygons of the pieces
    label        legend label of the curve (default: the method's name)
    **line_kwargs passed to ax.plot for the curve (color, linewidth, ...)

    The axes get an equal aspect ratio, so that circles look round and the comb is true.
    """
    import matplotlib.pyplot as plt  # lazy: importing fairspline never needs Matplotlib

    if ax is None:
        _, ax = plt.subplots()
    n = max(1, int(samples_per_segment))
    ranges = curve.segment_ranges
    u = np.linspace(0.0, 1.0, n + 1)
    t = ranges[:, :1] + u[None, :] * (ranges[:, 1:] - ranges[:, :1])
    xy = curve.evaluate(np.clip(t, *curve.t_range).ravel())
    line_kwargs.setdefault("label", label if label is not None else curve.method)
    (line,) = ax.plot(xy[:, 0], xy[:, 1], **line_kwargs)
    color = line.get_color()
    if comb:
        base, tips = comb_teeth(curve, comb_samples_per_segment, comb_scale)
        teeth = np.full((3 * len(base), 2), np.nan)  # base, tip, gap: one polyline for all
        teeth[0::3] = base
        teeth[1::3] = tips
        ax.plot(teeth[:, 0], teeth[:, 1], color=color, alpha=0.5, linewidth=0.6)
        ax.plot(tips[:, 0], tips[:, 1], color=color, alpha=0.7, linewidth=0.9)
    if control_polygon:
        for seg in curve.segments:
            ax.plot(seg[:, 0], seg[:, 1], color=color, alpha=0.5, linewidth=0.6,
                    linestyle="--", marker="o", markersize=2)
    if points:
        p = curve.points
        ax.plot(p[:, 0], p[:, 1], linestyle="none", marker="o", markersize=4,
                markerfacecolor="white", markeredgecolor="black", zorder=3)
    ax.set_aspect("equal", adjustable="datalim")
    return ax
