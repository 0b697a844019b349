// Cubic Bézier evaluation shared by the comb, the curvature plot and point insertion.
// A segment is the API's {bezier: [p0, p1, p2, p3]} with points [x, y].

/** Point of the cubic [p0, p1, p2, p3] at local parameter t in [0, 1]. */
export function pointAt([p0, p1, p2, p3], t) {
  const s = 1 - t;
  const b0 = s * s * s, b1 = 3 * s * s * t, b2 = 3 * s * t * t, b3 = t * t * t;
  return [b0 * p0[0] + b1 * p1[0] + b2 * p2[0] + b3 * p3[0], b0 * p0[1] + b1 * p1[1] + b2 * p2[1] + b3 * p3[1]];
}

// 3-point Gauss–Legendre nodes on [0, 1] and weights: the arc length of a sub-interval.
const G = [0.5 - Math.sqrt(0.15), 0.5, 0.5 + Math.sqrt(0.15)];
const GW = [5 / 18, 8 / 18, 5 / 18];

/**
 * Samples every segment at `perSegment` + 1 parameters: point, unit normal, signed curvature
 * (null where the speed vanishes) and arc length s from the start of the curve.
 * `segmentStart` marks the first sample of each segment (so a plot can show joints).
 * Scalar arithmetic only: this runs on every fit while a point is dragged.
 */
export function sampleCurve(segments, perSegment) {
  const samples = [];
  let s = 0;
  const h = 1 / perSegment;
  for (let seg = 0; seg < segments.length; seg++) {
    const [[x0, y0], [x1, y1], [x2, y2], [x3, y3]] = segments[seg].bezier;
    // Hodograph 3(a s² + 2b s t + c t²) and second derivative 6(d s + e t), s = 1 − t.
    const ax = x1 - x0, ay = y1 - y0, bx = x2 - x1, by = y2 - y1, cx = x3 - x2, cy = y3 - y2;
    const dx = bx - ax, dy = by - ay, ex = cx - bx, ey = cy - by;
    const speed = (t) => {
      const u = 1 - t;
      return 3 * Math.hypot(u * u * ax + 2 * u * t * bx + t * t * cx, u * u * ay + 2 * u * t * by + t * t * cy);
    };
    for (let j = 0; j <= perSegment; j++) {
      const t = j * h, u = 1 - t;
      if (j > 0) {
        const a = t - h;
        s += h * (GW[0] * speed(a + G[0] * h) + GW[1] * speed(a + G[1] * h) + GW[2] * speed(a + G[2] * h));
      }
      const px = u * u * u * x0 + 3 * u * u * t * x1 + 3 * u * t * t * x2 + t * t * t * x3;
      const py = u * u * u * y0 + 3 * u * u * t * y1 + 3 * u * t * t * y2 + t * t * t * y3;
      const d1x = 3 * (u * u * ax + 2 * u * t * bx + t * t * cx);
      const d1y = 3 * (u * u * ay + 2 * u * t * by + t * t * cy);
      const d2x = 6 * (u * dx + t * ex), d2y = 6 * (u * dy + t * ey);
      const v = Math.hypot(d1x, d1y);
      samples.push({
        pt: [px, py], s, seg, segmentStart: j === 0,
        normal: v > 0 ? [-d1y / v, d1x / v] : [0, 0],
        kappa: v > 1e-300 ? (d1x * d2y - d1y * d2x) / (v * v * v) : null,
      });
    }
  }
  return samples;
}

/** Index of the segment whose curve passes nearest to q (sampled at `perSegment` + 1 points). */
export function nearestSegment(segments, q, perSegment = 32) {
  let best = { d: Infinity, seg: -1 };
  segments.forEach(({ bezier }, seg) => {
    for (let j = 0; j <= perSegment; j++) {
      const pt = pointAt(bezier, j / perSegment);
      const d = Math.hypot(pt[0] - q[0], pt[1] - q[1]);
      if (d < best.d) best = { d, seg };
    }
  });
  return best.seg;
}

/** SVG path data of the segments (a move wherever a segment does not start at the last end). */
export function pathData(segments) {
  let d = '';
  let last = null;
  for (const { bezier: [p0, p1, p2, p3] } of segments) {
    if (!last || Math.hypot(last[0] - p0[0], last[1] - p0[1]) > 1e-9 * (1 + Math.abs(p0[0]) + Math.abs(p0[1]))) {
      d += `M${p0[0]} ${p0[1]}`;
    }
    d += `C${p1[0]} ${p1[1]} ${p2[0]} ${p2[1]} ${p3[0]} ${p3[1]}`;
    last = p3;
  }
  return d;
}
