// The small plot of signed curvature κ against arc length s, one line per curve, with the
// joints of the main curve marked. Drawn into an <svg> with a fixed viewBox.

const SVG_NS = 'http://www.w3.org/2000/svg';
const W = 1000, H = 160, PAD_L = 56, PAD_R = 10, PAD_T = 10, PAD_B = 22;

function node(tag, attrs = {}, text = null) {
  const n = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) n.setAttribute(k, v);
  if (text != null) n.textContent = text;
  return n;
}

const short = (v) => Number(v.toPrecision(3)).toString();

/**
 * curves: [{name, label?, color, main, stale, samples}] with samples from sampleCurve() (stale: the last
 * good fit of data that now fail, drawn dimmed). Replaces the
 * content of `svgEl`. Samples whose curvature is undefined (zero speed) break the line.
 */
export function renderCurvaturePlot(svgEl, curves) {
  svgEl.setAttribute('viewBox', `0 0 ${W} ${H}`);
  svgEl.replaceChildren();
  const usable = curves.filter((c) => c.samples.length > 1);
  if (!usable.length) return;
  const sMax = Math.max(1e-300, ...usable.map((c) => c.samples[c.samples.length - 1].s));
  // The scale is the main curve's (when there is one): another curve's spike is clipped
  // rather than flattening the curve being edited.
  const main = usable.find((c) => c.main);
  let kMax = 0;
  for (const c of main ? [main] : usable) for (const p of c.samples) if (p.kappa != null) kMax = Math.max(kMax, Math.abs(p.kappa));
  kMax = kMax > 0 ? 1.1 * kMax : 1;
  const x = (s) => PAD_L + (s / sMax) * (W - PAD_L - PAD_R);
  const y = (k) => PAD_T + (1 - (k / kMax + 1) / 2) * (H - PAD_T - PAD_B);

  const axes = node('g', { class: 'axes' });
  axes.append(
    node('line', { x1: PAD_L, y1: y(0), x2: W - PAD_R, y2: y(0) }),
    node('line', { x1: PAD_L, y1: PAD_T, x2: PAD_L, y2: H - PAD_B }),
    node('text', { x: PAD_L - 4, y: y(kMax) + 4, 'text-anchor': 'end' }, short(kMax)),
    node('text', { x: PAD_L - 4, y: y(0) + 4, 'text-anchor': 'end' }, '0'),
    node('text', { x: PAD_L - 4, y: y(-kMax) + 4, 'text-anchor': 'end' }, short(-kMax)),
    node('text', { x: PAD_L, y: H - 6 }, 's = 0'),
    node('text', { x: W - PAD_R, y: H - 6, 'text-anchor': 'end' }, `s = ${short(sMax)}`),
    node('text', { x: (W + PAD_L) / 2, y: H - 6, 'text-anchor': 'middle' }, 'curvature κ against arc length s'),
  );
  svgEl.append(axes);

  const clipId = `${svgEl.id || 'plot'}-clip`;
  const clip = node('clipPath', { id: clipId });
  clip.append(node('rect', { x: PAD_L, y: PAD_T, width: W - PAD_L - PAD_R, height: H - PAD_T - PAD_B }));
  svgEl.append(clip);
  if (main) {
    const joints = node('g', { class: 'joints' });
    for (const p of main.samples) {
      if (p.segmentStart && p.s > 0) joints.append(node('line', { x1: x(p.s), y1: PAD_T, x2: x(p.s), y2: H - PAD_B }));
    }
    svgEl.append(joints);
  }
  // The main curve last, on top.
  for (const c of [...usable.filter((u) => !u.main), ...usable.filter((u) => u.main)]) {
    let d = '';
    let pen = false;
    for (const p of c.samples) {
      if (p.kappa == null) { pen = false; continue; }
      d += `${pen ? 'L' : 'M'}${x(p.s).toFixed(2)} ${y(p.kappa).toFixed(2)}`;
      pen = true;
    }
    const cls = [c.main ? 'main' : '', c.stale ? 'stale' : ''].filter(Boolean).join(' ');
    const line = node('path', { d, stroke: c.color, class: cls, 'clip-path': `url(#${clipId})`, 'data-testid': `kappa-${c.name}` });
    if (c.label) line.append(node('title', {}, c.label));
    svgEl.append(line);
  }
}
