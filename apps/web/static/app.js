// fairspline editor: points on an SVG canvas, live fits through POST /api/fit, an ensemble of
// methods side by side, a curvature comb, exports, and the state kept in the URL hash.
// World coordinates are the 1000×700 frame of the canvas with the y axis up.

const SVG_NS = 'http://www.w3.org/2000/svg';
const FRAME_H = 700;
const FIT_DELAY_MS = 30;
const COMB_SAMPLES = 16;   // per segment
const COMB_MAX_LEN = 60;   // world units of the longest tooth
const PALETTE = ['#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b', '#e377c2',
  '#bcbd22', '#1f77b4', '#7f7f7f'];

const $ = (id) => document.getElementById(id);
const el = {
  canvas: $('canvas'), world: $('world'), method: $('method'), methodDesc: $('method-desc'),
  options: $('options'), closed: $('closed'), comb: $('comb'), ensemble: $('ensemble'),
  error: $('error'), report: $('report'), legend: $('legend'),
  table: $('ensemble-table').tBodies[0], layerMain: $('layer-main'),
  layerEnsemble: $('layer-ensemble'), layerComb: $('layer-comb'), layerPoints: $('layer-points'),
  svgText: $('export-svg-text'), jsonText: $('export-json-text'),
  csvText: $('export-csv-text'), importText: $('import-text'), polygon: $('control-polygon'),
  layerControl: $('layer-control'), undo: $('undo'), redo: $('redo'),
};

const state = {
  points: [],          // [[x, y], ...] in world coordinates
  closed: false,
  method: null,
  options: {},         // user-set options of the current method (defaults are left out)
  ensemble: new Set(), // method names fitted alongside with their default options
  comb: false,
  polygon: false,      // draw the Bézier control polygons of the main curve
  selected: -1,
};

let schema = { default: null, methods: [] };
let mainFit = null;            // last successful answer for the main method
let mainError = null;          // {code, message, index} of the last failed main fit
const ensembleFits = new Map(); // name → {fit} or {error}
let importError = null;        // message of the last failed import, shown until the next edit

// ---------- undo / redo over point edits ----------

const HISTORY_LIMIT = 200;
const undoStack = [];
const redoStack = [];

const snapshot = () => ({ points: state.points.map(([x, y]) => [x, y]), closed: state.closed });

/** Records the state before an edit; call it once per user action (one drag = one step). */
function pushHistory() {
  undoStack.push(snapshot());
  if (undoStack.length > HISTORY_LIMIT) undoStack.shift();
  redoStack.length = 0;
  importError = null;
  updateHistoryButtons();
}

function restore(snap) {
  state.points = snap.points.map(([x, y]) => [x, y]);
  state.closed = snap.closed;
  el.closed.checked = state.closed;
  state.selected = -1;
  drag = null;
  importError = null;
  if (mainError?.index != null) mainError = { ...mainError, index: null };
  updateHistoryButtons();
  changed();
}

function undo() {
  if (!undoStack.length) return;
  redoStack.push(snapshot());
  restore(undoStack.pop());
}

function redo() {
  if (!redoStack.length) return;
  undoStack.push(snapshot());
  restore(redoStack.pop());
}

function updateHistoryButtons() {
  el.undo.disabled = undoStack.length === 0;
  el.redo.disabled = redoStack.length === 0;
}

// ---------- small helpers ----------

function svg(tag, attrs = {}) {
  const node = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  return node;
}

const fmt = (v) => (typeof v === 'number' && Number.isFinite(v) ? Number(v.toPrecision(5)).toString() : String(v ?? '—'));
const round2 = (v) => Math.round(v * 100) / 100;
const methodInfo = (name) => schema.methods.find((m) => m.name === name);
const colorOf = (name) => PALETTE[Math.max(0, schema.methods.findIndex((m) => m.name === name)) % PALETTE.length];

function pathData(segments) {
  let d = '';
  let last = null;
  for (const { bezier: [p0, p1, p2, p3] } of segments) {
    if (!last || Math.hypot(last[0] - p0[0], last[1] - p0[1]) > 1e-9) d += `M${p0[0]} ${p0[1]}`;
    d += `C${p1[0]} ${p1[1]} ${p2[0]} ${p2[1]} ${p3[0]} ${p3[1]}`;
    last = p3;
  }
  return d;
}

// ---------- URL hash ----------

function saveHash() {
  const data = {
    p: state.points.map(([x, y]) => [round2(x), round2(y)]),
    c: state.closed ? 1 : 0,
    m: state.method,
    o: state.options,
    e: [...state.ensemble],
    k: state.comb ? 1 : 0,
    g: state.polygon ? 1 : 0,
  };
  history.replaceState(null, '', `#${encodeURIComponent(JSON.stringify(data))}`);
}

function loadHash() {
  if (location.hash.length < 2) return;
  try {
    const data = JSON.parse(decodeURIComponent(location.hash.slice(1)));
    if (Array.isArray(data.p)) state.points = data.p.filter((p) => Array.isArray(p) && p.length === 2).map(([x, y]) => [+x, +y]);
    state.closed = !!data.c;
    if (typeof data.m === 'string') state.method = data.m;
    if (data.o && typeof data.o === 'object') state.options = data.o;
    if (Array.isArray(data.e)) state.ensemble = new Set(data.e);
    state.comb = !!data.k;
    state.polygon = !!data.g;
  } catch {
    // A malformed hash: start from scratch.
  }
}

// ---------- options form ----------

function setOption(name, value) {
  if (value === undefined) delete state.options[name];
  else state.options[name] = value;
  changed();
}

function optionControl(opt) {
  const current = state.options[opt.name];
  const id = `option-${opt.name}`;
  const numberInput = (value, onValue) => {
    const input = document.createElement('input');
    input.type = 'number';
    input.step = opt.type === 'integer' ? '1' : 'any';
    if (opt.min != null) input.min = opt.min;
    if (opt.max != null) input.max = opt.max;
    if (value != null) input.value = value;
    input.addEventListener('input', () => {
      if (input.value.trim() === '') return onValue(undefined);
      const v = Number(input.value);
      input.classList.toggle('invalid', !Number.isFinite(v));
      if (Number.isFinite(v)) onValue(opt.type === 'integer' ? Math.round(v) : v);
    });
    return input;
  };

  switch (opt.type) {
    case 'number':
    case 'integer': {
      const input = numberInput(current ?? opt.default, (v) => setOption(opt.name, v));
      input.dataset.testid = id;
      return input;
    }
    case 'boolean': {
      const input = document.createElement('input');
      input.type = 'checkbox';
      input.checked = !!(current ?? opt.default);
      input.dataset.testid = id;
      input.addEventListener('change', () => setOption(opt.name, input.checked));
      return input;
    }
    case 'choice': {
      const select = document.createElement('select');
      for (const c of opt.choices ?? []) select.add(new Option(c, c));
      select.value = current ?? opt.default;
      select.dataset.testid = id;
      select.addEventListener('change', () => setOption(opt.name, select.value));
      return select;
    }
    case 'choice_or_number': {
      // A select of the named choices plus "number", and a numeric input used with "number".
      const value = current ?? opt.default;
      const wrap = document.createElement('span');
      wrap.className = 'pair';
      const select = document.createElement('select');
      for (const c of opt.choices ?? []) select.add(new Option(c, c));
      select.add(new Option('number', '#number'));
      select.dataset.testid = id;
      const input = numberInput(typeof value === 'number' ? value : null, (v) => {
        if (select.value === '#number') setOption(opt.name, v);
      });
      input.dataset.testid = `${id}-number`;
      select.value = typeof value === 'number' ? '#number' : (value ?? '#number');
      input.disabled = select.value !== '#number';
      select.addEventListener('change', () => {
        input.disabled = select.value !== '#number';
        if (select.value !== '#number') return setOption(opt.name, select.value);
        const v = Number(input.value);
        setOption(opt.name, input.value.trim() !== '' && Number.isFinite(v) ? v : undefined);
      });
      wrap.append(select, input);
      return wrap;
    }
    case 'number_list': {
      const input = document.createElement('input');
      input.type = 'text';
      input.placeholder = opt.default == null ? '(none) e.g. 0.5, 0.5' : opt.default.join(', ');
      if (Array.isArray(current)) input.value = current.join(', ');
      input.dataset.testid = id;
      input.addEventListener('input', () => {
        const text = input.value.trim();
        if (text === '') { input.classList.remove('invalid'); return setOption(opt.name, undefined); }
        const list = text.replace(/^\[|\]$/g, '').split(/[\s,;]+/).filter(Boolean).map(Number);
        const ok = list.every(Number.isFinite);
        input.classList.toggle('invalid', !ok);
        if (ok) setOption(opt.name, list);
      });
      return input;
    }
    default: {
      const input = document.createElement('input');
      input.type = 'text';
      input.value = current ?? opt.default ?? '';
      input.dataset.testid = id;
      input.addEventListener('input', () => setOption(opt.name, input.value));
      return input;
    }
  }
}

function buildOptionsForm() {
  const info = methodInfo(state.method);
  el.methodDesc.textContent = info ? `${info.description}${info.paper ? ` — ${info.paper}` : ''}` : '';
  el.options.replaceChildren();
  for (const opt of info?.options ?? []) {
    const label = document.createElement('label');
    label.className = 'opt';
    label.title = opt.doc ?? '';
    const name = document.createElement('span');
    name.textContent = opt.name;
    label.append(name, optionControl(opt));
    el.options.append(label);
  }
}

function buildEnsemble() {
  el.ensemble.replaceChildren();
  for (const m of schema.methods) {
    const label = document.createElement('label');
    label.title = m.description;
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = state.ensemble.has(m.name);
    box.dataset.testid = `ensemble-${m.name}`;
    box.addEventListener('change', () => {
      if (box.checked) state.ensemble.add(m.name);
      else { state.ensemble.delete(m.name); ensembleFits.delete(m.name); }
      changed();
    });
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = colorOf(m.name);
    label.append(box, swatch, document.createTextNode(m.name));
    el.ensemble.append(label);
  }
}

// ---------- fitting ----------

async function postFit(method, options) {
  const body = { points: state.points, closed: state.closed, method };
  if (options && Object.keys(options).length) body.options = options;
  try {
    const res = await fetch('/api/fit', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(body),
    });
    const data = await res.json().catch(() => null);
    if (res.ok && data) return { fit: data };
    return { error: data?.error ?? { code: `http_${res.status}`, message: `HTTP ${res.status}`, index: null } };
  } catch (e) {
    return { error: { code: 'network', message: `cannot reach the server: ${e.message}`, index: null } };
  }
}

let fitTimer = null;
let fitInFlight = false;
let fitPending = false;

/** Schedules a fit at most every FIT_DELAY_MS; a change during a request refits afterwards. */
function requestFit() {
  if (fitTimer) return;
  fitTimer = setTimeout(runFit, FIT_DELAY_MS);
}

async function runFit() {
  fitTimer = null;
  if (fitInFlight) { fitPending = true; return; }
  fitInFlight = true;
  try {
    if (state.points.length < 2 || !state.method) {
      mainFit = null;
      mainError = null;
      ensembleFits.clear();
    } else {
      const names = [...state.ensemble].filter((n) => methodInfo(n));
      const [main, ...others] = await Promise.all([
        postFit(state.method, state.options),
        ...names.map((n) => postFit(n, null)),
      ]);
      mainFit = main.fit ?? null;
      mainError = main.error ?? null;
      ensembleFits.clear();
      names.forEach((n, i) => ensembleFits.set(n, others[i]));
    }
    render();
  } finally {
    fitInFlight = false;
    if (fitPending) { fitPending = false; requestFit(); }
  }
}

/** Any change of the state: redraw the points now, save the hash, refit soon. */
function changed() {
  renderPoints();
  saveHash();
  requestFit();
}

// ---------- drawing ----------

function renderPoints() {
  // Circles are updated in place so that a point being dragged keeps its element.
  const layer = el.layerPoints;
  while (layer.children.length > state.points.length) layer.lastChild.remove();
  while (layer.children.length < state.points.length) {
    const i = layer.children.length;
    layer.append(svg('circle', { r: 7, 'data-testid': `point-${i}`, 'data-index': i }));
  }
  const bad = mainError?.index;
  state.points.forEach(([x, y], i) => {
    const c = layer.children[i];
    c.setAttribute('cx', x);
    c.setAttribute('cy', y);
    c.classList.toggle('selected', i === state.selected);
    c.classList.toggle('error', i === bad);
  });
}

/** Curvature comb of the main curve: teeth along the normal, length ∝ signed curvature. */
function renderComb() {
  el.layerComb.replaceChildren();
  if (!state.comb || !mainFit) return;
  const samples = [];
  for (const { bezier: [p0, p1, p2, p3] } of mainFit.segments) {
    for (let j = 0; j <= COMB_SAMPLES; j++) {
      const t = j / COMB_SAMPLES, s = 1 - t;
      const pt = [0, 1].map((k) => s * s * s * p0[k] + 3 * s * s * t * p1[k] + 3 * s * t * t * p2[k] + t * t * t * p3[k]);
      const d1 = [0, 1].map((k) => 3 * (s * s * (p1[k] - p0[k]) + 2 * s * t * (p2[k] - p1[k]) + t * t * (p3[k] - p2[k])));
      const d2 = [0, 1].map((k) => 6 * (s * (p2[k] - 2 * p1[k] + p0[k]) + t * (p3[k] - 2 * p2[k] + p1[k])));
      const speed = Math.hypot(d1[0], d1[1]);
      if (speed < 1e-12) continue;
      const kappa = (d1[0] * d2[1] - d1[1] * d2[0]) / speed ** 3;
      samples.push({ pt, normal: [-d1[1] / speed, d1[0] / speed], kappa });
    }
  }
  const kmax = Math.max(1e-12, ...samples.map((s) => Math.abs(s.kappa)));
  const scale = COMB_MAX_LEN / kmax;
  const tips = [];
  for (const { pt, normal, kappa } of samples) {
    // Teeth point away from the centre of curvature.
    const tip = [pt[0] - normal[0] * kappa * scale, pt[1] - normal[1] * kappa * scale];
    tips.push(tip);
    el.layerComb.append(svg('line', { x1: pt[0], y1: pt[1], x2: tip[0], y2: tip[1] }));
  }
  if (tips.length) el.layerComb.append(svg('polyline', { points: tips.map((p) => p.join(',')).join(' ') }));
}

/** The control polygon p0–p1–p2–p3 of every segment of the main curve. */
function renderControlPolygon() {
  el.layerControl.replaceChildren();
  if (!state.polygon || !mainFit) return;
  for (const { bezier } of mainFit.segments) {
    el.layerControl.append(svg('polyline', { points: bezier.map((p) => p.join(',')).join(' ') }));
    for (const [x, y] of [bezier[1], bezier[2]]) el.layerControl.append(svg('circle', { cx: x, cy: y, r: 3 }));
  }
}

function renderTable() {
  el.table.replaceChildren();
  const rows = [];
  if (mainFit || mainError) rows.push([`${state.method} (main)`, mainFit ? { fit: mainFit } : { error: mainError }, state.method]);
  for (const [name, result] of ensembleFits) rows.push([name, result, name]);
  for (const [label, result, name] of rows) {
    const tr = document.createElement('tr');
    tr.dataset.method = name;
    const head = document.createElement('td');
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = label.endsWith('(main)') ? 'var(--fg)' : colorOf(name);
    head.append(sw, document.createTextNode(` ${label}`));
    tr.append(head);
    if (result.fit) {
      const r = result.fit.report ?? {};
      for (const v of [r.bending_energy, r.linearized_energy, r.length, r.regular == null ? '—' : (r.regular ? 'yes' : 'no'), r.max_curvature_jump]) {
        const td = document.createElement('td');
        td.textContent = fmt(v);
        tr.append(td);
      }
    } else {
      const td = document.createElement('td');
      td.colSpan = 5;
      td.className = 'err';
      td.textContent = result.error?.message ?? 'failed';
      tr.append(td);
    }
    el.table.append(tr);
  }
}

function render() {
  el.layerMain.replaceChildren();
  if (mainFit) {
    el.layerMain.append(svg('path', { d: pathData(mainFit.segments), 'data-testid': `curve-${mainFit.method}` }));
  }
  el.layerEnsemble.replaceChildren();
  el.legend.replaceChildren();
  if (mainFit) addLegend(`${mainFit.method} (main)`, 'var(--fg)');
  for (const [name, result] of ensembleFits) {
    if (!result.fit) continue;
    const color = colorOf(name);
    el.layerEnsemble.append(svg('path', { d: pathData(result.fit.segments), stroke: color, 'data-testid': `curve-${name}` }));
    addLegend(name, color);
  }
  renderError();
  const r = mainFit?.report;
  el.report.textContent = r
    ? `${mainFit.segments.length} segments · bending ${fmt(r.bending_energy)} · length ${fmt(r.length)} · max tangent jump ${fmt(r.max_tangent_angle_jump_deg)}°`
    : '';
  renderPoints();
  renderComb();
  renderControlPolygon();
  renderTable();
}

function renderError() {
  el.error.textContent = importError ? `import: ${importError}`
    : (mainError ? `${mainError.code}: ${mainError.message}` : '');
}

function addLegend(text, color) {
  const li = document.createElement('li');
  const sw = document.createElement('span');
  sw.className = 'swatch';
  sw.style.background = color;
  li.append(sw, document.createTextNode(text));
  el.legend.append(li);
}

// ---------- pointer interaction ----------

function toWorld(evt) {
  const p = el.canvas.createSVGPoint();
  p.x = evt.clientX;
  p.y = evt.clientY;
  const q = p.matrixTransform(el.world.getScreenCTM().inverse());
  return [q.x, q.y];
}

let drag = null;          // {index, moved}
let suppressClick = false;

el.canvas.addEventListener('pointerdown', (evt) => {
  const index = evt.target.dataset?.index;
  if (index === undefined || evt.button !== 0) return;
  evt.preventDefault();
  const i = Number(index);
  if (evt.shiftKey) {
    removePoint(i);
    suppressClick = true;
    setTimeout(() => { suppressClick = false; }, 0);
    return;
  }
  state.selected = i;
  drag = { index: i, moved: false };
  renderPoints();
});

window.addEventListener('pointermove', (evt) => {
  if (!drag) return;
  if (!drag.moved) pushHistory(); // one undo step per drag
  drag.moved = true;
  state.points[drag.index] = toWorld(evt);
  changed();
});

window.addEventListener('pointerup', () => {
  if (!drag) return;
  // The click that ends a press on a point never adds one.
  suppressClick = true;
  setTimeout(() => { suppressClick = false; }, 0);
  drag = null;
});

el.canvas.addEventListener('click', (evt) => {
  if (suppressClick || evt.target.dataset?.index !== undefined) return;
  if (evt.button !== 0 || evt.shiftKey) return;
  if (evt.altKey) { insertOnCurve(toWorld(evt)); return; }
  pushHistory();
  state.points.push(toWorld(evt));
  state.selected = state.points.length - 1;
  changed();
});

/** Alt-click: inserts a point after the start point of the main-curve segment nearest to q. */
function insertOnCurve(q) {
  if (!mainFit?.segments?.length) return;
  let best = { d: Infinity, seg: -1 };
  mainFit.segments.forEach(({ bezier: [p0, p1, p2, p3] }, i) => {
    for (let j = 0; j <= 32; j++) {
      const t = j / 32, s = 1 - t;
      const x = s * s * s * p0[0] + 3 * s * s * t * p1[0] + 3 * s * t * t * p2[0] + t * t * t * p3[0];
      const y = s * s * s * p0[1] + 3 * s * s * t * p1[1] + 3 * s * t * t * p2[1] + t * t * t * p3[1];
      const d = Math.hypot(x - q[0], y - q[1]);
      if (d < best.d) best = { d, seg: i };
    }
  });
  // Segment i runs from point i to point i+1 (the last one closes the loop when closed).
  const at = Math.min(best.seg + 1, state.points.length);
  pushHistory();
  state.points.splice(at, 0, q);
  state.selected = at;
  if (mainError?.index != null) mainError = { ...mainError, index: null };
  changed();
}

window.addEventListener('keydown', (evt) => {
  if (evt.target instanceof HTMLInputElement || evt.target instanceof HTMLSelectElement || evt.target instanceof HTMLTextAreaElement) return;
  const key = evt.key.toLowerCase();
  if ((evt.ctrlKey || evt.metaKey) && (key === 'z' || key === 'y')) {
    evt.preventDefault();
    if (key === 'y' || evt.shiftKey) redo(); else undo();
    return;
  }
  if ((evt.key === 'Delete' || evt.key === 'Backspace') && state.selected >= 0) {
    evt.preventDefault();
    removePoint(state.selected);
  } else if (evt.key === 'Escape') {
    state.selected = -1;
    renderPoints();
  }
});

function removePoint(i) {
  pushHistory();
  state.points.splice(i, 1);
  state.selected = -1;
  if (mainError?.index != null) mainError = { ...mainError, index: null };
  changed();
}

// ---------- exports ----------

function download(filename, text, type) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = filename;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

/** A standalone SVG of the curves, comb and points, y axis up like the editor. */
function exportSvgText() {
  const xs = [], ys = [];
  const addPt = ([x, y]) => { xs.push(x); ys.push(y); };
  state.points.forEach(addPt);
  const curves = [];
  if (mainFit) curves.push({ fit: mainFit, color: '#1d2330', width: 2.5 });
  for (const [name, r] of ensembleFits) if (r.fit) curves.push({ fit: r.fit, color: colorOf(name), width: 1.6 });
  for (const c of curves) for (const s of c.fit.segments) s.bezier.forEach(addPt);
  if (!xs.length) { addPt([0, 0]); addPt([1000, FRAME_H]); }
  const pad = 20;
  const x0 = Math.min(...xs) - pad, x1 = Math.max(...xs) + pad;
  const y0 = Math.min(...ys) - pad, y1 = Math.max(...ys) + pad;
  const w = x1 - x0, h = y1 - y0;
  const lines = [
    `<svg xmlns="http://www.w3.org/2000/svg" viewBox="${fmt(x0)} ${fmt(-y1)} ${fmt(w)} ${fmt(h)}" width="${Math.round(w)}" height="${Math.round(h)}">`,
    `<g transform="scale(1,-1)" fill="none">`,
  ];
  for (const c of curves) {
    lines.push(`<path d="${pathData(c.fit.segments)}" stroke="${c.color}" stroke-width="${c.width}" data-method="${c.fit.method}"/>`);
  }
  if (state.comb) {
    for (const node of el.layerComb.children) {
      if (node.tagName === 'line') {
        const a = ['x1', 'y1', 'x2', 'y2'].map((k) => `${k}="${node.getAttribute(k)}"`).join(' ');
        lines.push(`<line ${a} stroke="#e07b39" stroke-width="0.8"/>`);
      }
    }
  }
  for (const [x, y] of state.points) lines.push(`<circle cx="${x}" cy="${y}" r="4" fill="#fff" stroke="#1d4ed8" stroke-width="1.5"/>`);
  lines.push('</g>', '</svg>', '');
  return lines.join('\n');
}

$('export-svg').addEventListener('click', () => {
  const text = exportSvgText();
  el.svgText.value = text;
  download(`fairspline-${state.method ?? 'curve'}.svg`, text, 'image/svg+xml');
});

$('export-json').addEventListener('click', () => {
  const text = JSON.stringify(mainFit ?? { error: mainError }, null, 2);
  el.jsonText.value = text;
  download(`fairspline-${state.method ?? 'curve'}.json`, text, 'application/json');
});

/** One row of the 8 control coordinates per segment of the main curve, with a header line. */
function exportCsvText() {
  const lines = ['x0,y0,x1,y1,x2,y2,x3,y3'];
  for (const { bezier } of mainFit?.segments ?? []) lines.push(bezier.flat().join(','));
  return `${lines.join('\n')}\n`;
}

$('export-csv').addEventListener('click', () => {
  const text = exportCsvText();
  el.csvText.value = text;
  download(`fairspline-${state.method ?? 'curve'}.csv`, text, 'text/csv');
});

// ---------- import ----------

/** Parses CSV (x,y per line, optional header, # comments) or JSON ({points, closed} or an array). */
function parsePoints(text) {
  const trimmed = text.trim();
  if (!trimmed) throw new Error('nothing to import');
  const toPoints = (list) => {
    if (!Array.isArray(list)) throw new Error('"points" must be an array');
    return list.map((p, i) => {
      const xy = Array.isArray(p) ? p : (p && typeof p === 'object' ? [p.x, p.y] : null);
      if (!xy || xy.length < 2 || !xy.slice(0, 2).every((v) => typeof v === 'number' && Number.isFinite(v))) {
        throw new Error(`point ${i} is not a pair of finite numbers`);
      }
      return [xy[0], xy[1]];
    });
  };
  if (trimmed.startsWith('{') || trimmed.startsWith('[')) {
    let data;
    try { data = JSON.parse(trimmed); } catch (e) { throw new Error(`invalid JSON: ${e.message}`); }
    if (Array.isArray(data)) return { points: toPoints(data), closed: null };
    if (!data || typeof data !== 'object') throw new Error('JSON must be an object or an array');
    return { points: toPoints(data.points), closed: data.closed == null ? null : !!data.closed };
  }
  const points = [];
  const lines = trimmed.split(/\r?\n/);
  lines.forEach((raw, n) => {
    const line = raw.replace(/#.*$/, '').trim();
    if (!line) return;
    const cells = line.split(/\s*[,;\t ]\s*/).filter((c) => c !== '');
    const nums = cells.map(Number);
    if (cells.length >= 2 && Number.isFinite(nums[0]) && Number.isFinite(nums[1])) {
      points.push([nums[0], nums[1]]);
    } else if (points.length === 0 && /^[a-z_]/i.test(cells[0] ?? '')) {
      // A header line before the first point.
    } else {
      throw new Error(`line ${n + 1}: expected "x,y", got "${raw.trim().slice(0, 40)}"`);
    }
  });
  if (!points.length) throw new Error('no points found');
  return { points, closed: null };
}

$('import').addEventListener('click', () => {
  let parsed;
  try {
    parsed = parsePoints(el.importText.value);
  } catch (e) {
    importError = e.message;
    renderError();
    return;
  }
  pushHistory();
  if (parsed.closed != null) { state.closed = parsed.closed; el.closed.checked = state.closed; }
  replacePoints(parsed.points);
});

el.undo.addEventListener('click', undo);
el.redo.addEventListener('click', redo);

/** Replaces all points and forgets every fit of the old ones. */
function replacePoints(points) {
  state.points = points;
  state.selected = -1;
  mainFit = null;
  mainError = null;
  ensembleFits.clear();
  render();
  changed();
}

$('clear').addEventListener('click', () => {
  if (state.points.length) pushHistory();
  replacePoints([]);
});

// ---------- controls and start-up ----------

el.method.addEventListener('change', () => {
  state.method = el.method.value;
  state.options = {};
  mainFit = null;
  buildOptionsForm();
  changed();
});
el.closed.addEventListener('change', () => {
  // The box shows the new value already: record the state before it.
  undoStack.push({ ...snapshot(), closed: !el.closed.checked });
  redoStack.length = 0;
  updateHistoryButtons();
  state.closed = el.closed.checked;
  changed();
});
el.polygon.addEventListener('change', () => { state.polygon = el.polygon.checked; renderControlPolygon(); saveHash(); });
el.comb.addEventListener('change', () => { state.comb = el.comb.checked; renderComb(); saveHash(); });

async function start() {
  loadHash();
  el.closed.checked = state.closed;
  el.comb.checked = state.comb;
  el.polygon.checked = state.polygon;
  updateHistoryButtons();
  try {
    const res = await fetch('/api/methods');
    schema = await res.json();
  } catch (e) {
    el.error.textContent = `cannot load /api/methods: ${e.message}`;
    return;
  }
  if (!methodInfo(state.method)) { state.method = schema.default; state.options = {}; }
  for (const m of schema.methods) el.method.add(new Option(m.name, m.name));
  el.method.value = state.method;
  buildOptionsForm();
  buildEnsemble();
  changed();
}

start();
