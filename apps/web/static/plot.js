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

/** Sets the attributes of `n` that differ from those this module last wrote. */
function set(n, attrs) {
  const last = (n.plotAttrs ??= {});
  for (const [k, v] of Object.entries(attrs)) {
    const text = String(v);
    if (last[k] !== text) { last[k] = text; n.setAttribute(k, text); }
  }
}

/** The plot's fixed elements, made once per <svg> and then updated in place: rebuilding the
 * whole plot on every fit of a drag made chromium restyle and repaint all of it. */
function skeleton(svgEl) {
  if (svgEl.plotParts) return svgEl.plotParts;
  svgEl.setAttribute('viewBox', `0 0 ${W} ${H}`);
  svgEl.replaceChildren();
  const clipId = `${svgEl.id || 'plot'}-clip`;
  const parts = {
    axes: node('g', { class: 'axes' }),
    zero: node('line', { x1: PAD_L, x2: W - PAD_R }),
    vertical: node('line', { x1: PAD_L, y1: PAD_T, x2: PAD_L, y2: H - PAD_B }),
    kTop: node('text', { x: PAD_L - 4, 'text-anchor': 'end' }),
    kZero: node('text', { x: PAD_L - 4, 'text-anchor': 'end' }, '0'),
    kBottom: node('text', { x: PAD_L - 4, 'text-anchor': 'end' }),
    s0: node('text', { x: PAD_L, y: H - 6 }, 's = 0'),
    sEnd: node('text', { x: W - PAD_R, y: H - 6, 'text-anchor': 'end' }),
    title: node('text', { x: (W + PAD_L) / 2, y: H - 6, 'text-anchor': 'middle' }, 'curvature κ against arc length s'),
    clip: node('clipPath', { id: clipId }),
    // The joints of the main curve: one path of vertical strokes.
    joints: node('path', { class: 'joints' }),
    lines: node('g', { class: 'lines' }),
    clipId,
  };
  parts.axes.append(parts.zero, parts.vertical, parts.kTop, parts.kZero, parts.kBottom, parts.s0, parts.sEnd, parts.title);
  parts.clip.append(node('rect', { x: PAD_L, y: PAD_T, width: W - PAD_L - PAD_R, height: H - PAD_T - PAD_B }));
  svgEl.plotParts = parts;
  return parts;
}

const setText = (n, text) => { if (n.textContent !== text) n.textContent = text; };

/**
 * curves: [{name, label?, color, main, stale, samples}] with samples from sampleCurve() (stale: the last
 * good fit of data that now fail, drawn dimmed). Updates the
 * content of `svgEl`. Samples whose curvature is undefined (zero speed) break the line.
 */
export function renderCurvaturePlot(svgEl, curves) {
  const parts = skeleton(svgEl);
  const usable = curves.filter((c) => c.samples.length > 1);
  if (!usable.length) {
    if (svgEl.firstChild) svgEl.replaceChildren();
    parts.lines.replaceChildren();
    return;
  }
  if (!svgEl.firstChild) svgEl.append(parts.axes, parts.clip, parts.joints, parts.lines);
  let sMax = 1e-300;
  for (const c of usable) sMax = Math.max(sMax, c.samples[c.samples.length - 1].s);
  // The scale is the main curve's (when there is one): another curve's spike is clipped
  // rather than flattening the curve being edited.
  const main = usable.find((c) => c.main);
  let kMax = 0;
  for (const c of main ? [main] : usable) for (const p of c.samples) if (p.kappa != null) kMax = Math.max(kMax, Math.abs(p.kappa));
  kMax = kMax > 0 ? 1.1 * kMax : 1;
  const x = (s) => PAD_L + (s / sMax) * (W - PAD_L - PAD_R);
  const y = (k) => PAD_T + (1 - (k / kMax + 1) / 2) * (H - PAD_T - PAD_B);

  set(parts.zero, { y1: y(0), y2: y(0) });
  set(parts.kTop, { y: y(kMax) + 4 });
  setText(parts.kTop, short(kMax));
  set(parts.kZero, { y: y(0) + 4 });
  set(parts.kBottom, { y: y(-kMax) + 4 });
  setText(parts.kBottom, short(-kMax));
  setText(parts.sEnd, `s = ${short(sMax)}`);

  let joints = '';
  if (main) {
    for (const p of main.samples) {
      if (p.segmentStart && p.s > 0) joints += `M${x(p.s).toFixed(2)} ${PAD_T}V${H - PAD_B}`;
    }
  }
  set(parts.joints, { d: joints });
  // The main curve last, on top.
  const ordered = [...usable.filter((u) => !u.main), ...usable.filter((u) => u.main)];
  const lines = parts.lines;
  ordered.forEach((c, k) => {
    let d = '';
    let pen = false;
    for (const p of c.samples) {
      if (p.kappa == null) { pen = false; continue; }
      d += `${pen ? 'L' : 'M'}${x(p.s).toFixed(2)} ${y(p.kappa).toFixed(2)}`;
      pen = true;
    }
    const cls = [c.main ? 'main' : '', c.stale ? 'stale' : ''].filter(Boolean).join(' ');
    while (lines.children.length <= k) lines.append(node('path', { 'clip-path': `url(#${parts.clipId})` }));
    const line = lines.children[k];
    set(line, { d, stroke: c.color, class: cls, 'data-testid': `kappa-${c.name}` });
    const title = line.firstChild;
    if (!c.label) title?.remove();
    else if (!title) line.append(node('title', {}, c.label));
    else setText(title, c.label);
  });
  while (lines.children.length > ordered.length) lines.lastChild.remove();
}
