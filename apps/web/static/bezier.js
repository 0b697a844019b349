// Cubic Bézier evaluation shared by the comb, the curvature plot and point insertion.
// A segment is the API's {bezier: [p0, p1, p2, p3]} with points [x, y].

/** Point, first and second derivative of the cubic p at local parameter t in [0, 1]. */
export function evalCubic([p0, p1, p2, p3], t) {
  const s = 1 - t;
  const pt = [0, 1].map((k) => s * s * s * p0[k] + 3 * s * s * t * p1[k] + 3 * s * t * t * p2[k] + t * t * t * p3[k]);
  const d1 = [0, 1].map((k) => 3 * (s * s * (p1[k] - p0[k]) + 2 * s * t * (p2[k] - p1[k]) + t * t * (p3[k] - p2[k])));
  const d2 = [0, 1].map((k) => 6 * (s * (p2[k] - 2 * p1[k] + p0[k]) + t * (p3[k] - 2 * p2[k] + p1[k])));
  return { pt, d1, d2 };
}

/** Signed curvature from the first two derivatives; null where the speed vanishes. */
export function curvature(d1, d2) {
  const speed = Math.hypot(d1[0], d1[1]);
  if (!(speed > 1e-300)) return null;
  return (d1[0] * d2[1] - d1[1] * d2[0]) / speed ** 3;
}

// 3-point Gauss–Legendre on each sub-interval: exact for the speed of a cubic up to O(h^6).
const GAUSS = [[-Math.sqrt(0.6), 5 / 9], [0, 8 / 9], [Math.sqrt(0.6), 5 / 9]];

function speedAt(bezier, t) {
  const { d1 } = evalCubic(bezier, t);
  return Math.hypot(d1[0], d1[1]);
}

/**
 * Samples every segment at `perSegment` + 1 parameters: point, unit normal, signed curvature
 * and arc length s from the start of the curve. `segmentStart` marks the first sample of each
 * segment (so a plot can show joints).
 */
export function sampleCurve(segments, perSegment) {
  const samples = [];
  let s = 0;
  segments.forEach(({ bezier }, seg) => {
    for (let j = 0; j <= perSegment; j++) {
      const t = j / perSegment;
      if (j > 0) {
        const a = (j - 1) / perSegment, h = 1 / perSegment;
        for (const [x, w] of GAUSS) s += (w * h / 2) * speedAt(bezier, a + (h / 2) * (x + 1));
      }
      const { pt, d1, d2 } = evalCubic(bezier, t);
      const speed = Math.hypot(d1[0], d1[1]);
      samples.push({
        pt, s, seg, segmentStart: j === 0,
        normal: speed > 0 ? [-d1[1] / speed, d1[0] / speed] : [0, 0],
        kappa: curvature(d1, d2),
      });
    }
  });
  return samples;
}

/** Index of the segment whose curve passes nearest to q (sampled at `perSegment` + 1 points). */
export function nearestSegment(segments, q, perSegment = 32) {
  let best = { d: Infinity, seg: -1 };
  segments.forEach(({ bezier }, seg) => {
    for (let j = 0; j <= perSegment; j++) {
      const { pt } = evalCubic(bezier, j / perSegment);
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
