// fairspline editor: a document of curves, each with its points on an SVG canvas, live fits
// through POST /api/fit, an ensemble of methods side by side, node kinds, a curvature comb and
// plot, zoom and pan, project files, imports and exports, and the whole state kept in the URL
// hash. The selected curve's data live in `state`, so all single-curve editing works on it.
// World coordinates have the y axis up; the initial view is the 1000×700 frame.

import { nearestSegment, pathData, pointAt, sampleCurve } from './bezier.js';
import { PROJECT_FORMAT, PROJECT_VERSION, isProject, parseImport, parseProject } from './parse.js';
import { renderCurvaturePlot } from './plot.js';
import {
  FIG7_PRESET, entriesFrom, entryColors, entryKey, entryLabel, entryToHash, entryToProject,
  isDefaultEntry, makeEntry,
} from './entries.js';
import { markedNodes, renderMethodReport } from './report.js';

const SVG_NS = 'http://www.w3.org/2000/svg';
const FRAME_W = 1000, FRAME_H = 700, ASPECT = FRAME_H / FRAME_W;
const COMB_SAMPLES = 16;   // per segment
const PLOT_SAMPLES = 800;  // in all (the plot is 1000 units wide, about 900 px), 2 to 24 per segment
const COMB_MAX_PX = 60;    // longest comb tooth, in pixels of the default view
const POINT_R_PX = 7;
const ARROW_PX = 80;       // length of a new clamped tangent arrow
const DRAG_SLOP_PX = 4;    // a press on the background that moves less is a click
const KINDS = ['smooth', 'clamped', 'corner'];
// The library's node model: a state per side of a node (docs/methods/min-energy.md, "Node
// states"); the kinds are its symmetric cases.
const SIDES = ['regular', 'clamped', 'free'];
const KIND_SIDE = { smooth: 'regular', clamped: 'clamped', corner: 'free' };
const SIDE_KIND = { regular: 'smooth', clamped: 'clamped', free: 'corner' };
const kindStates = (kind) => [KIND_SIDE[kind] ?? 'regular', KIND_SIDE[kind] ?? 'regular'];
// One colour per registered method (12 ≥ the 11 methods), none of them near the comb's orange
// (COMB_COLOR; an orange here once made jaklic-zagar's curve look like the comb).
const PALETTE = ['#d62728', '#2ca02c', '#9467bd', '#1f77b4', '#17becf', '#8c564b', '#e377c2',
  '#bcbd22', '#7f7f7f', '#393b79', '#637939', '#a55194'];
const COMB_COLOR = '#e07b39';
// The document's curves, each in its own colour: dark and saturated, away from the comb's
// orange, so that a dimmed thin curve stays readable next to the selected one (drawn in --fg).
const CURVE_COLORS = ['#2563eb', '#16a34a', '#9333ea', '#db2777', '#0891b2', '#65a30d', '#b91c1c',
  '#4f46e5', '#0f766e', '#a21caf', '#475569', '#854d0e'];

const $ = (id) => document.getElementById(id);
const el = {
  canvas: $('canvas'), world: $('world'), method: $('method'), methodDesc: $('method-desc'),
  options: $('options'), closed: $('closed'), comb: $('comb'), plotToggle: $('plot-toggle'),
  ensemble: $('ensemble'), error: $('error-box'), errorText: $('error'), errorShow: $('error-show'),
  errorHint: $('error-hint'),
  report: $('report'), legend: $('legend'), table: $('ensemble-table').tBodies[0],
  layerMain: $('layer-main'), layerEnsemble: $('layer-ensemble'), layerComb: $('layer-comb'),
  layerPoints: $('layer-points'), layerKinds: $('layer-kinds'), layerError: $('layer-error'),
  layerControl: $('layer-control'), layerBox: $('layer-box'), layerGrid: $('layer-grid'), snap: $('snap'),
  snapLabel: $('snap-label'), polygon: $('control-polygon'), plot: $('plot'),
  svgText: $('export-svg-text'), jsonText: $('export-json-text'), csvText: $('export-csv-text'),
  importText: $('import-text'), importFile: $('import-file'), undo: $('undo'), redo: $('redo'),
  alpha: $('alpha'), alphaNumber: $('alpha-number'), kindBox: $('kind'), kindLabel: $('kind-label'),
  radius: $('radius'), nodeX: $('node-x'), nodeY: $('node-y'), stateIn: $('state-in'), stateOut: $('state-out'),
  nodeDir: $('node-dir'), nodeCorner: $('node-corner'),
  zoomLabel: $('zoom-label'),
  curves: $('curves'), curveName: $('curve-name'), layerCurves: $('layer-curves'),
  exportScope: $('export-scope'), exportPoints: $('export-points'), pngScale: $('png-scale'),
  projectText: $('export-project-text'),
  entries: $('ensemble-entries'), entryForm: $('entry-form'), entryMethod: $('entry-method'),
  entryOptions: $('entry-options'), entryAlpha: $('entry-alpha'), tableHead: $('ensemble-table').tHead,
  methodReport: $('method-report'), layerReport: $('layer-report'), layerHighlight: $('layer-highlight'),
  help: $('help'), emptyHint: $('empty-hint'), transformTarget: $('transform-target'),
  combAll: $('comb-all'), layerCombOthers: $('layer-comb-others'), reportPanel: $('report-panel'),
};

const state = {
  points: [],          // [[x, y], ...] in world coordinates (see freshState for the rest)
  states: [],          // [in, out] side states per point: 'regular' | 'clamped' | 'free'
  tangents: [],        // the outgoing arrow [dx, dy] where the out side is clamped (world units;
                       // see knotSpan), else null
  inArrows: [],        // the incoming arrow where the in side is clamped and differs from the
                       // outgoing one (null: the outgoing arrow, turned back by the corner)
  corners: [],         // corner angle in degrees kept between the in and out directions
  radii: [],           // data-ball radius per point (0: the curve passes through the point)
  closed: false,
  alpha: 0.5,          // knot parameterization exponent (sent as "alpha")
  method: null,
  options: {},         // user-set options of the current method (defaults are left out)
  ensemble: [],        // entries {method, options, alpha} fitted alongside (entries.js)
  comb: false,
  combAll: false,      // combs of the other visible curves and ensemble entries too
  polygon: false,      // draw the Bézier control polygons of the main curve
  snap: false,         // snap dragged and added points to other points or the grid
  plot: true,          // the curvature plot under the canvas
  view: { x: 0, y: 0, w: FRAME_W }, // the SVG viewBox (user units; height = w · ASPECT)
  selected: -1,
};

let schema = { default: null, methods: [] };
let mainFit = null;            // last successful answer for the main method
let mainStale = false;         // mainFit is the last good fit of an earlier state (drawn dimmed)
let mainError = null;          // {code, message, index, hint} of the last failed main fit
let mainTiming = null;         // {server, roundTrip} in ms of the last main fit
let lastDrawMs = null;         // time render() took after the last fit
let editSince = null;          // performance.now() of the oldest edit not yet sent to the server
let lastLatencyMs = null;      // from that edit to the fit drawn on screen (debounce included)
let lastMainLatencyMs = null;  // the same for the main curve alone, drawn before the ensemble's fits
const ensembleFits = new Map(); // entryKey → {fit} or {error}
let mainFitKey = null;         // the request body (JSON text) mainFit answers

// ---------- the document: several curves, one of them selected ----------
// A record is {id, name, visible, color} plus the curve's data (CURVE fields of copyCurve). The
// selected curve's data are in `state` (its record's copy is refreshed by storeSelected()).
const doc = { curves: [], selected: 0 };
let nextCurveId = 1;
const otherFits = new Map(); // curve id → {key, fit} or {key, error}: key is the request body
let importError = null;        // message of the last failed import, shown until the next edit

// ---------- small helpers ----------

function svg(tag, attrs = {}) {
  const node = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  return node;
}

/** Sets the attributes of `node` that differ from what this function last wrote there (a
 * write of an unchanged value still invalidates the element's style and paint in chromium). */
function setAttrs(node, attrs) {
  const last = (node.writtenAttrs ??= {});
  for (const k in attrs) {
    const v = String(attrs[k]);
    if (last[k] !== v) { last[k] = v; node.setAttribute(k, v); }
  }
}

/** The child `k` of `layer`, created as a `tag` if the layer has fewer children (children past
 * `count` are removed by trimLayer). Elements are reused from fit to fit: rebuilding them made
 * chromium restyle, lay out and repaint every one on every fit of a drag. */
function childAt(layer, k, tag) {
  while (layer.children.length <= k) layer.append(svg(tag));
  return layer.children[k];
}
function trimLayer(layer, count) {
  while (layer.children.length > count) layer.lastChild.remove();
}

/** SVG path data of a fit's segments, computed once per answer (fits are never modified). */
const pathCache = new WeakMap();
function fitPath(fit) {
  let d = pathCache.get(fit);
  if (d === undefined) { d = pathData(fit.segments); pathCache.set(fit, d); }
  return d;
}

const fmt = (v) => (typeof v === 'number' && Number.isFinite(v) ? Number(v.toPrecision(5)).toString() : String(v ?? '—'));
const compact = (v) => Number(v.toPrecision(10));
const methodInfo = (name) => schema.methods.find((m) => m.name === name);
const colorOf = (name) => PALETTE[Math.max(0, schema.methods.findIndex((m) => m.name === name)) % PALETTE.length];
/** World units per pixel of the default view: sizes that must look the same at any zoom. */
const unit = () => state.view.w / FRAME_W;

// ---------- undo / redo over the data and the fit's settings ----------

const HISTORY_LIMIT = 200;
const undoStack = [];
const redoStack = [];
let historyKey = null; // the control whose edits the last undo step collects (see pushHistory)

/** A deep copy of a curve's data (of `state` or of a record). */
const copyCurve = (c) => ({
  points: c.points.map(([x, y]) => [x, y]),
  states: c.states.map(([a, b]) => [a, b]),
  tangents: c.tangents.map((t) => (t ? [...t] : null)),
  inArrows: c.inArrows.map((t) => (t ? [...t] : null)),
  corners: [...c.corners],
  radii: [...c.radii],
  closed: c.closed,
  alpha: c.alpha,
  method: c.method,
  options: structuredClone(c.options),
});
const curveMeta = ({ id, name, visible, color }) => ({ id, name, visible, color });

/** The selected curve's data (as before documents existed) and the document around it. */
const snapshot = () => ({
  ...copyCurve(state),
  doc: {
    selected: doc.selected,
    curves: doc.curves.map((c, i) => (i === doc.selected ? curveMeta(c) : { ...curveMeta(c), ...copyCurve(c) })),
  },
});

/**
 * Records the state before an edit; call it once per user action (one drag = one step). A `key`
 * names a control whose keystrokes make one step together (typing "0.5" is one edit, not
 * three) until endHistoryGroup() or another action.
 */
function pushHistory(key = null) {
  if (key != null && key === historyKey) return;
  historyKey = key;
  undoStack.push(snapshot());
  if (undoStack.length > HISTORY_LIMIT) undoStack.shift();
  redoStack.length = 0;
  importError = null;
  updateHistoryButtons();
}

function endHistoryGroup() {
  historyKey = null;
}

function restore(snap) {
  const switched = snap.doc.curves[snap.doc.selected].id !== selectedCurve().id;
  if (switched) cacheSelectedFit();
  doc.curves = snap.doc.curves;
  doc.selected = snap.doc.selected;
  const settings = snap.method !== state.method || JSON.stringify(snap.options) !== JSON.stringify(state.options);
  state.points = snap.points;
  state.states = snap.states;
  state.tangents = snap.tangents;
  state.inArrows = snap.inArrows;
  state.corners = snap.corners;
  state.radii = snap.radii;
  state.closed = snap.closed;
  state.alpha = snap.alpha;
  state.method = snap.method;
  state.options = snap.options;
  el.closed.checked = state.closed;
  syncAlphaControl();
  if (settings) { el.method.value = state.method; buildOptionsForm(); }
  if (switched) adoptCachedFit();
  renderCurvesPanel();
  selectOnly(-1);
  drag = null;
  importError = null;
  historyKey = null;
  forgetErrorIndex();
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

/** After points move in the list, the old error index no longer names the right point. */
function forgetErrorIndex() {
  if (mainError?.index != null) mainError = { ...mainError, index: null };
}

// ---------- the document's curves ----------

const selectedCurve = () => doc.curves[doc.selected];

/** A colour no curve of the document has yet (they repeat after CURVE_COLORS.length). */
function freeColor() {
  const used = new Set(doc.curves.map((c) => c.color));
  return CURVE_COLORS.find((c) => !used.has(c)) ?? CURVE_COLORS[doc.curves.length % CURVE_COLORS.length];
}

/** A new record: no points, the given settings (the selected curve's, so that a new curve is
 * fitted as the one beside it), a name not used yet. */
function newRecord(from = state, name = null) {
  const names = new Set(doc.curves.map((c) => c.name));
  let k = doc.curves.length + 1;
  while (!name && names.has(`curve ${k}`)) k += 1;
  return {
    id: nextCurveId++, name: name ?? `curve ${k}`, visible: true, color: freeColor(),
    points: [], states: [], tangents: [], inArrows: [], corners: [], radii: [], closed: from.closed, alpha: from.alpha,
    method: from.method, options: structuredClone(from.options ?? {}),
  };
}

/** A document of one empty curve (the editor's start). */
function resetDocument() {
  doc.curves = [];
  doc.selected = 0;
  doc.curves.push({ ...newRecord(state, 'curve 1'), ...copyCurve(state) });
  otherFits.clear();
}

/** Copies the selected curve's data from `state` into its record. */
function storeSelected() {
  Object.assign(selectedCurve(), copyCurve(state));
}

/** Keeps the selected curve's fit, so that selecting it again shows it at once. */
function cacheSelectedFit() {
  const c = selectedCurve();
  if (c && mainFit && !mainStale && mainFitKey) otherFits.set(c.id, { key: mainFitKey, fit: mainFit });
}

/** The fit of the (newly) selected curve's current data, if one is known; else none until its
 * fit arrives (the previous curve's fit must not be read for this one's arrows). */
function adoptCachedFit() {
  const cached = otherFits.get(selectedCurve().id);
  const key = JSON.stringify(requestBody(state.method, state.options));
  mainFit = cached?.fit && cached.key === key ? cached.fit : null;
  mainFitKey = mainFit ? key : null;
  mainStale = false;
  mainError = null;
  ensembleFits.clear();
}

/** Puts the selected record's data into `state` and the panel's controls. */
function loadSelected() {
  Object.assign(state, copyCurve(selectedCurve()));
  if (!methodInfo(state.method)) { state.method = schema.default; state.options = {}; }
  selectOnly(-1);
  drag = null;
  forgetErrorIndex();
  adoptCachedFit();
  el.closed.checked = state.closed;
  syncAlphaControl();
  el.method.value = state.method;
  buildOptionsForm();
  renderCurvesPanel();
}

/** Selects curve j (one undo step: undo goes back to the curve edited before). */
function selectCurve(j) {
  if (j === doc.selected || !doc.curves[j]) return;
  pushHistory();
  storeSelected();
  cacheSelectedFit();
  doc.selected = j;
  loadSelected();
  render();
  changed();
}

/** Inserts a record after the selected curve and selects it (one undo step). */
function addCurve(record) {
  pushHistory();
  storeSelected();
  cacheSelectedFit();
  doc.curves.splice(doc.selected + 1, 0, record);
  doc.selected += 1;
  loadSelected();
  render();
  changed();
}

function duplicateCurve() {
  storeSelected();
  const c = selectedCurve();
  addCurve({ ...newRecord(state, `${c.name} copy`), ...copyCurve(c) });
}

/** Deletes the selected curve; the last one is replaced by an empty curve. */
function deleteCurve() {
  pushHistory();
  otherFits.delete(selectedCurve().id);
  doc.curves.splice(doc.selected, 1);
  if (!doc.curves.length) doc.curves.push(newRecord(state, 'curve 1'));
  doc.selected = Math.min(doc.selected, doc.curves.length - 1);
  loadSelected();
  render();
  changed();
}

/** Moves the selected curve up (−1) or down (+1) the list: the drawing order too. */
function moveCurve(step) {
  const j = doc.selected + step;
  if (j < 0 || j >= doc.curves.length) return;
  pushHistory();
  const [c] = doc.curves.splice(doc.selected, 1);
  doc.curves.splice(j, 0, c);
  doc.selected = j;
  renderCurvesPanel();
  render();
  changed();
}

function setCurveVisible(i, visible) {
  if (doc.curves[i].visible === visible) return;
  pushHistory();
  doc.curves[i].visible = visible;
  renderCurvesPanel();
  render();
  changed();
}

function renameCurve(name) {
  if (selectedCurve().name === name) return;
  pushHistory('curve-name');
  selectedCurve().name = name;
  renderCurvesPanel();
  saveHash();
}

let curvesPanelKey = null; // what the rows show, so that they are rebuilt only when it changes

/** The curves panel: one row per curve (visibility box, colour, name and method; the selected
 * row highlighted; a failed fit marked with its message), and the selected curve's name. The
 * rows are rebuilt only when what they show changes: a fit arriving between the press and the
 * release of a click on a row would otherwise replace the button and lose the click. */
function renderCurvesPanel() {
  // Scrolled only when the rows change (selection included), not under a user reading the list.
  if (renderCurveRows()) scrollToSelectedRow();
}

/** Keeps the selected row in the list's view (without scrolling the panel around it). */
function scrollToSelectedRow() {
  const li = el.curves.children[doc.selected];
  if (!li) return;
  const top = li.offsetTop, bottom = top + li.offsetHeight;
  if (top < el.curves.scrollTop) el.curves.scrollTop = top;
  else if (bottom > el.curves.scrollTop + el.curves.clientHeight) el.curves.scrollTop = bottom - el.curves.clientHeight;
}

function renderCurveRows() {
  if (document.activeElement !== el.curveName) el.curveName.value = selectedCurve()?.name ?? '';
  $('curve-up').disabled = doc.selected === 0;
  $('curve-down').disabled = doc.selected === doc.curves.length - 1;
  const errorOf = (c, i) => (i !== doc.selected && c.visible ? otherFits.get(c.id)?.error ?? null : null);
  const key = JSON.stringify([doc.selected, state.method, doc.curves.map((c, i) => [c.id, c.name, c.visible, c.color, c.method, errorOf(c, i)])]);
  if (key === curvesPanelKey) return false;
  curvesPanelKey = key;
  el.curves.replaceChildren();
  doc.curves.forEach((c, i) => {
    const sel = i === doc.selected;
    const li = document.createElement('li');
    li.dataset.testid = `curves-row-${i}`;
    li.classList.toggle('selected', sel);
    li.classList.toggle('hidden-curve', !c.visible);
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = c.visible;
    box.title = 'show / hide';
    box.dataset.testid = `curves-visible-${i}`;
    box.addEventListener('change', () => setCurveVisible(i, box.checked));
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = c.color;
    const name = document.createElement('button');
    name.type = 'button';
    name.className = 'curve-name';
    name.dataset.testid = `curves-select-${i}`;
    const method = sel ? state.method : c.method;
    name.textContent = c.name;
    name.title = `${c.name}: ${method}`;
    name.addEventListener('click', () => selectCurve(i));
    const info = document.createElement('span');
    info.className = 'curve-method';
    info.textContent = method ?? '';
    li.append(box, sw, name, info);
    const err = errorOf(c, i);
    if (err) {
      const mark = document.createElement('span');
      mark.className = 'curve-error';
      mark.textContent = '!';
      mark.title = `${err.code}: ${err.message}`;
      mark.dataset.testid = `curves-error-${i}`;
      li.append(mark);
    }
    el.curves.append(li);
  });
  return true;
}

/** The visible curves other than the selected one: thinner, dimmed, each in its colour; a
 * press on one selects it. */
function renderOtherCurves() {
  let k = 0;
  doc.curves.forEach((c, i) => {
    const fit = otherFits.get(c.id)?.fit;
    if (i === doc.selected || !c.visible || !fit) return;
    setAttrs(childAt(el.layerCurves, k++, 'path'), {
      d: fitPath(fit), stroke: c.color, 'data-testid': `doc-curve-${i}`, 'data-curve': i,
    });
  });
  trimLayer(el.layerCurves, k);
  // The selected curve is always drawn (it is being edited); hidden, it is drawn faintly.
  el.canvas.classList.toggle('selected-hidden', !selectedCurve()?.visible);
}

// ---------- point list edits (the per-point lists stay parallel) ----------

const PER_POINT = ['points', 'states', 'tangents', 'inArrows', 'corners', 'radii'];

// The selection: state.selected is the point the panel shows (the last one picked; -1: none),
// `selection` the others picked with it (shift-click, box, Ctrl+A). Setting state.selected to
// -1 anywhere empties the selection.
let selection = new Set();

/** The selected points' indices, sorted. */
function selectedIndices() {
  if (state.selected < 0 || state.selected >= state.points.length) return [];
  selection.add(state.selected);
  return [...selection].filter((i) => i >= 0 && i < state.points.length).sort((a, b) => a - b);
}

/** Selects point i alone (-1: nothing). */
function selectOnly(i) {
  selection = new Set(i >= 0 ? [i] : []);
  state.selected = i;
  endHistoryGroup(); // nudges of another selection are another undo step
}

/** Selects these points (the last one is shown in the panel); `add`: to the selection. */
function selectMany(indices, add = false) {
  if (!add) selection = new Set();
  for (const i of indices) selection.add(i);
  if (indices.length) state.selected = indices[indices.length - 1];
  else if (!add) state.selected = -1;
  endHistoryGroup();
  renderPoints();
  renderSelection();
}

/** Shift-click: adds a point to the selection, or takes it out. */
function toggleSelected(i) {
  if (selectedIndices().includes(i)) {
    selection.delete(i);
    const rest = [...selection];
    state.selected = rest.length ? rest[rest.length - 1] : -1;
  } else {
    selection.add(i);
    state.selected = i;
  }
  endHistoryGroup();
  renderPoints();
  renderSelection();
}

function insertPoint(at, p) {
  pushHistory();
  state.points.splice(at, 0, p);
  state.states.splice(at, 0, ['regular', 'regular']);
  state.tangents.splice(at, 0, null);
  state.inArrows.splice(at, 0, null);
  state.corners.splice(at, 0, 0);
  state.radii.splice(at, 0, 0);
  selectOnly(at);
  forgetErrorIndex();
  changed();
}

/** Removes the points at `indices` (one undo step). */
function removePoints(indices) {
  const gone = new Set(indices.filter((i) => i >= 0 && i < state.points.length));
  if (!gone.size) return;
  pushHistory();
  const keep = (list) => list.filter((_, i) => !gone.has(i));
  for (const key of PER_POINT) state[key] = keep(state[key]);
  selectOnly(-1);
  forgetErrorIndex();
  changed();
}

const removePoint = (i) => removePoints([i]);

/**
 * The knot spacing Δt = |ΔP|^α of the span after point i (before it for the last point of an
 * open curve). A clamped point's arrow is drawn where its neighbouring Bézier control point
 * goes, so the tangent sent is 3·arrow/Δt: C1 methods (li-*) take its length as the speed,
 * G1 methods only its direction.
 */
function knotSpan(i, c = state) {
  const n = c.points.length;
  const j = i + 1 < n ? i + 1 : (c.closed ? 0 : i - 1);
  if (j < 0 || j === i) return 1;
  const d = Math.hypot(c.points[j][0] - c.points[i][0], c.points[j][1] - c.points[i][1]);
  const span = c.alpha === 0 ? 1 : d ** c.alpha;
  return span > 0 && Number.isFinite(span) ? span : 1;
}

const arrowToTangent = (a, i, c = state) => (a ? [(3 * a[0]) / knotSpan(i, c), (3 * a[1]) / knotSpan(i, c)] : null);
const tangentToArrow = (t, i) => (t ? [(t[0] * knotSpan(i)) / 3, (t[1] * knotSpan(i)) / 3] : null);

/**
 * The main fit's index of editor point i: the same, except after the points the method inserted
 * (jaklic-zagar's reversal=insert lists them, sorted, in method_report.inserted); -1 when no
 * fit of the current points is on screen (none yet, or the last good one of an earlier state).
 */
function fitIndexOf(i) {
  if (!mainFit || mainStale) return -1;
  const inserted = mainFit.method_report?.inserted ?? [];
  if (mainFit.points?.length !== state.points.length + inserted.length) return -1;
  let k = i;
  for (const j of inserted) if (j <= k) k += 1;
  return k;
}

/** The arrow that reproduces the last fit at point i: its control arm there when the fit has a
 * segment starting (or, at the end, ending) at i; else the chord direction, ARROW_PX long. */
function currentArrow(i, side = 'out') {
  const k = fitIndexOf(i);
  const segs = k >= 0 ? mainFit.segments : [];
  const after = segs.find((s) => s.span === k && s.t0 === mainFit.knots[k]);
  const before = segs.find((s) => s.span === k - 1 && s.t1 === mainFit.knots[k]);
  const armAfter = after && [after.bezier[1][0] - after.bezier[0][0], after.bezier[1][1] - after.bezier[0][1]];
  const armBefore = before && [before.bezier[3][0] - before.bezier[2][0], before.bezier[3][1] - before.bezier[2][1]];
  // The incoming side's arm is that of the segment ending at the point (a corner's differs).
  const arm = side === 'in' ? armBefore ?? armAfter : armAfter ?? armBefore;
  if (arm && Math.hypot(...arm) > 0) return arm;
  const n = state.points.length;
  const a = state.points[Math.max(0, i - 1)], b = state.points[Math.min(n - 1, i + 1)];
  const d = [b[0] - a[0], b[1] - a[1]];
  const len = Math.hypot(...d) || 1;
  return [(d[0] / len) * ARROW_PX * unit(), (d[1] / len) * ARROW_PX * unit()];
}

/** The point's kind when its node is one (both sides alike, one direction, no corner angle);
 * else null: a node only the node model expresses. */
function kindOf(i, c = state) {
  const [a, b] = c.states[i];
  if (a !== b || c.inArrows[i] || (a !== 'free' && c.corners[i] !== 0)) return null;
  return SIDE_KIND[a];
}

/** Whether the corner angle of point i is sent: never next to a free side (the library refuses
 * it there), nor with two arrows (two directions and an angle would say it twice). */
const cornerApplies = (i, c = state) => !c.states[i].includes('free') && !c.inArrows[i];

/**
 * Keeps a node's arrows in line with its states (after a side changed): the outgoing arrow
 * exactly where the out side is clamped, the incoming one where the in side is clamped and the
 * out side is not, or (both clamped) where the two directions differ. A new arrow starts from
 * the current fit, so clamping a side never changes the curve.
 */
function normalizeNode(i, c = state) {
  const [a, b] = c.states[i];
  const out = c.tangents[i], inn = c.inArrows[i];
  if (b === 'clamped') {
    c.tangents[i] = out ?? (inn ? [...inn] : currentArrow(i, 'out'));
    c.inArrows[i] = a === 'clamped' && out ? inn : null;
  } else {
    c.tangents[i] = null;
    c.inArrows[i] = a === 'clamped' ? inn ?? out ?? currentArrow(i, 'in') : null;
  }
  if (c.inArrows[i] && b === 'clamped') c.corners[i] = 0;
}

/** The points a panel or key edit acts on: the selection, or none. */
function editTargets() {
  return selectedIndices();
}

/** Sets the kind of the points (one undo step): a kind is its states, with no corner angle. */
function setKind(indices, kind) {
  const todo = [].concat(indices).filter((i) => i >= 0 && i < state.points.length && kindOf(i) !== kind);
  if (!todo.length) return;
  pushHistory();
  for (const i of todo) {
    state.states[i] = kindStates(kind);
    state.inArrows[i] = null;
    state.corners[i] = 0;
    state.tangents[i] = kind === 'clamped' ? currentArrow(i) : null;
  }
  forgetErrorIndex();
  changed();
}

/** Sets one side ('in' | 'out') of the points' nodes (one undo step). */
function setSide(indices, side, value) {
  const k = side === 'in' ? 0 : 1;
  const todo = [].concat(indices).filter((i) => i >= 0 && i < state.points.length && state.states[i][k] !== value);
  if (!todo.length) return;
  pushHistory();
  for (const i of todo) {
    state.states[i][k] = value;
    normalizeNode(i);
  }
  forgetErrorIndex();
  changed();
}

/** The next state of a side (the I and O keys). */
const nextSide = (v) => SIDES[(SIDES.indexOf(v) + 1) % SIDES.length];

/** Turns a vector by `deg` degrees (counterclockwise). */
function rotateVec([x, y], deg) {
  const r = (deg * Math.PI) / 180, c = Math.cos(r), s = Math.sin(r);
  return [c * x - s * y, s * x + c * y];
}

const angleOf = ([x, y]) => (Math.atan2(y, x) * 180) / Math.PI;

/** The directions drawn at a node: out (the outgoing arrow) and in (the incoming one, which
 * with no arrow of its own is the outgoing one turned back by the corner angle). */
function nodeArrows(i, c = state) {
  const [a, b] = c.states[i];
  const out = b === 'clamped' ? c.tangents[i] : null;
  let inn = null;
  if (a === 'clamped') inn = c.inArrows[i] ?? (out ? rotateVec(out, -(c.corners[i] ?? 0)) : null);
  return { in: inn, out };
}

/** A node's states as the request writes them: one string for both sides, else [in, out]. */
const stateText = ([a, b]) => (a === b ? a : [a, b]);

/** The node fields of a request for curve c: `kinds` and `tangents` when every node is a kind
 * (the form every method reads), else the node model's `states`, `tangents` (both sides of a
 * clamped node with one arrow), `in_tangents`, `out_tangents` and `corners_deg`. */
function nodeFields(c) {
  const n = c.points.length;
  const kinds = c.states.map((_, i) => kindOf(i, c));
  if (kinds.every((k) => k !== null)) {
    if (!kinds.some((k) => k !== 'smooth')) return {};
    return { kinds, tangents: c.tangents.map((a, i) => (kinds[i] === 'clamped' ? arrowToTangent(a, i, c) : null)) };
  }
  const tangents = Array(n).fill(null), ins = Array(n).fill(null), outs = Array(n).fill(null);
  c.states.forEach(([a, b], i) => {
    if (a === 'clamped' && b === 'clamped' && !c.inArrows[i]) tangents[i] = arrowToTangent(c.tangents[i], i, c);
    else {
      if (a === 'clamped') ins[i] = arrowToTangent(c.inArrows[i], i, c);
      if (b === 'clamped') outs[i] = arrowToTangent(c.tangents[i], i, c);
    }
  });
  const fields = { states: c.states.map(stateText) };
  if (tangents.some(Boolean)) fields.tangents = tangents;
  if (ins.some(Boolean)) fields.in_tangents = ins;
  if (outs.some(Boolean)) fields.out_tangents = outs;
  const corners = c.corners.map((v, i) => (cornerApplies(i, c) ? v : 0));
  if (corners.some((v) => v !== 0)) fields.corners_deg = corners;
  return fields;
}

/** Whether curve c needs the node model (a node that no kind expresses, or a corner angle kept
 * at a free side): what the project's version 2 and the hash's "s" are for. */
const usesNodeModel = (c) => c.states.some((_, i) => kindOf(i, c) === null || c.corners[i] !== 0);

// ---------- URL hash ----------

/** A curve's data in the hash's short form (numbers to 10 digits). */
function hashCurve(c) {
  const data = {
    p: c.points.map(([x, y]) => [compact(x), compact(y)]),
    c: c.closed ? 1 : 0,
    a: c.alpha,
    m: c.method,
    o: c.options,
  };
  if (usesNodeModel(c)) {
    // The node model: states as in·3 + out (indices of SIDES), both arrows, corner angles.
    data.s = c.states.map(([a, b]) => SIDES.indexOf(a) * 3 + SIDES.indexOf(b));
    data.t = c.tangents.map((t) => (t ? t.map(compact) : 0));
    if (c.inArrows.some(Boolean)) data.i = c.inArrows.map((t) => (t ? t.map(compact) : 0));
    if (c.corners.some((v) => v !== 0)) data.d = c.corners.map(compact);
  } else if (c.states.some((_, i) => kindOf(i, c) !== 'smooth')) {
    data.n = c.states.map((_, i) => KINDS.indexOf(kindOf(i, c)));
    data.t = c.tangents.map((t) => (t ? t.map(compact) : 0));
  }
  if (c.radii.some((r) => r > 0)) data.r = c.radii.map(compact);
  return data;
}

/**
 * The hash: the selected curve's data at the top level (the one-curve form, which older links
 * hold), the view's settings, and with more than one curve "D", every curve's name (l), colour
 * (s), hidden flag (h) and, but for the selected one, data; "S" the selected index.
 */
function saveHash() {
  const data = {
    ...hashCurve(state),
    e: state.ensemble.map(entryToHash),
    k: state.comb ? 1 : 0,
    ...(state.combAll ? { K: 1 } : {}),
    ...(state.snap ? { G: 1 } : {}),
    g: state.polygon ? 1 : 0,
    q: state.plot ? 1 : 0,
    v: [compact(state.view.x), compact(state.view.y), compact(state.view.w)],
  };
  if (doc.curves.length > 1) {
    data.D = doc.curves.map((c, i) => ({
      l: c.name, s: c.color, ...(c.visible ? {} : { h: 1 }), ...(i === doc.selected ? {} : hashCurve(c)),
    }));
    data.S = doc.selected;
  }
  history.replaceState(null, '', `#${encodeURIComponent(JSON.stringify(data))}`);
}

/** The state of an empty editor. */
const freshState = () => ({
  points: [], states: [], tangents: [], inArrows: [], corners: [], radii: [], closed: false, alpha: 0.5, method: schema.default,
  options: {}, ensemble: [], comb: false, combAll: false, polygon: false, plot: true, snap: false,
  view: { x: 0, y: 0, w: FRAME_W }, selected: -1,
});

/** A curve's data from its short form in the hash (what it leaves out as in an empty editor). */
function curveFromHash(data) {
  const c = { points: [], closed: false, alpha: 0.5, method: schema.default, options: {} };
  if (Array.isArray(data.p)) {
    c.points = data.p.filter((p) => Array.isArray(p) && p.length === 2).map(([x, y]) => [+x, +y]);
  }
  const n = c.points.length;
  c.states = Array.from({ length: n }, () => ['regular', 'regular']);
  c.tangents = Array(n).fill(null);
  c.inArrows = Array(n).fill(null);
  c.corners = Array(n).fill(0);
  c.radii = Array(n).fill(0);
  if (Array.isArray(data.r) && data.r.length === n && data.r.every((r) => Number.isFinite(r) && r >= 0)) {
    c.radii = data.r.map(Number);
  }
  const pair = (t) => (Array.isArray(t) && t.length === 2 && t.every(Number.isFinite) ? [+t[0], +t[1]] : null);
  const listOf = (v) => (Array.isArray(v) && v.length === n ? v : null);
  if (listOf(data.s) && listOf(data.t)) {
    // The node model (see hashCurve); a node whose arrows are missing stays smooth.
    const ins = listOf(data.i) ?? [], corners = listOf(data.d) ?? [];
    data.s.forEach((code, i) => {
      const st = [SIDES[Math.floor(code / 3)], SIDES[code % 3]];
      if (!Number.isInteger(code) || !st[0] || !st[1]) return;
      const out = pair(data.t[i]), inn = pair(ins[i]);
      if ((st[1] === 'clamped' && !out) || (st[0] === 'clamped' && st[1] !== 'clamped' && !inn)) return;
      c.states[i] = st;
      c.tangents[i] = st[1] === 'clamped' ? out : null;
      c.inArrows[i] = st[0] === 'clamped' ? inn : null;
      if (Number.isFinite(corners[i])) c.corners[i] = +corners[i];
    });
  } else if (listOf(data.n) && listOf(data.t)) {
    data.n.forEach((k, i) => {
      const kind = KINDS[k] ?? 'smooth';
      const t = data.t[i];
      if (kind === 'clamped' && !pair(t)) return;
      c.states[i] = kindStates(kind);
      c.tangents[i] = kind === 'clamped' ? pair(t) : null;
    });
  }
  c.closed = !!data.c;
  if (typeof data.a === 'number' && Number.isFinite(data.a)) c.alpha = data.a;
  if (typeof data.m === 'string') c.method = data.m;
  if (data.o && typeof data.o === 'object') c.options = data.o;
  return c;
}

/** The document of the hash's "D" and "S" (the selected curve's data are the top level's). */
function documentFromHash(data) {
  if (!Array.isArray(data.D) || data.D.length < 2) return;
  const selected = Number.isInteger(data.S) && data.S >= 0 && data.S < data.D.length ? data.S : 0;
  doc.curves = [];
  data.D.forEach((d, i) => {
    const record = { ...newRecord(state, typeof d?.l === 'string' ? d.l : null), ...(i === selected ? copyCurve(state) : curveFromHash(d ?? {})) };
    if (typeof d?.s === 'string' && /^#[0-9a-f]{6}$/i.test(d.s)) record.color = d.s;
    record.visible = !d?.h;
    doc.curves.push(record);
  });
  doc.selected = selected;
}

/** The state the URL hash gives (what it leaves out as in an empty editor). */
function loadHash() {
  Object.assign(state, freshState());
  resetDocument();
  if (location.hash.length < 2) return;
  try {
    const data = JSON.parse(decodeURIComponent(location.hash.slice(1)));
    Object.assign(state, curveFromHash(data));
    resetDocument();
    documentFromHash(data);
    if (Array.isArray(data.e)) state.ensemble = entriesFrom(data.e);
    state.comb = !!data.k;
    state.combAll = !!data.K;
    state.snap = !!data.G;
    state.polygon = !!data.g;
    state.plot = data.q == null ? true : !!data.q;
    if (Array.isArray(data.v) && data.v.length === 3 && data.v.every(Number.isFinite) && data.v[2] > 0) {
      state.view = { x: data.v[0], y: data.v[1], w: data.v[2] };
    }
  } catch {
    // A malformed hash: start from scratch.
  }
}

// ---------- options form ----------

/** Sets (undefined: clears) an option; `typing`: one of a text field's keystrokes, which make
 * one undo step together until the field's change event. */
function setOption(name, value, typing = false) {
  if (JSON.stringify(state.options[name]) === JSON.stringify(value)) return;
  pushHistory(typing ? `option:${name}` : null);
  if (value === undefined) delete state.options[name];
  else state.options[name] = value;
  changed();
}

function numberInput(opt, value, onValue) {
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
  input.addEventListener('change', endHistoryGroup);
  return input;
}

/**
 * The control of one option of a schema. `current` is its value (undefined: the default),
 * `set(name, value, typing)` stores a change; the method's form uses state.options and
 * setOption, the ensemble's "add entry" form a draft of its own (prefix names the test ids).
 */
function optionControl(opt, current = state.options[opt.name], set = setOption, prefix = 'option') {
  const id = `${prefix}-${opt.name}`;
  switch (opt.type) {
    case 'number':
    case 'integer': {
      const input = numberInput(opt, current ?? opt.default, (v) => set(opt.name, v, true));
      input.dataset.testid = id;
      if (opt.default == null) input.placeholder = 'default';
      return input;
    }
    case 'boolean': {
      const input = document.createElement('input');
      input.type = 'checkbox';
      input.checked = !!(current ?? opt.default);
      input.dataset.testid = id;
      input.addEventListener('change', () => set(opt.name, input.checked));
      return input;
    }
    case 'choice': {
      const select = document.createElement('select');
      for (const c of opt.choices ?? []) select.add(new Option(c, c));
      select.value = current ?? opt.default;
      select.dataset.testid = id;
      select.addEventListener('change', () => set(opt.name, select.value));
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
      const input = numberInput(opt, typeof value === 'number' ? value : null, (v) => {
        if (select.value === '#number') set(opt.name, v, true);
      });
      input.dataset.testid = `${id}-number`;
      select.value = typeof value === 'number' ? '#number' : (value ?? '#number');
      input.disabled = select.value !== '#number';
      select.addEventListener('change', () => {
        input.disabled = select.value !== '#number';
        if (select.value !== '#number') return set(opt.name, select.value);
        const v = Number(input.value);
        set(opt.name, input.value.trim() !== '' && Number.isFinite(v) ? v : undefined);
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
        if (text === '') { input.classList.remove('invalid'); return set(opt.name, undefined, true); }
        const list = text.replace(/^\[|\]$/g, '').split(/[\s,;]+/).filter(Boolean).map(Number);
        const ok = list.every(Number.isFinite);
        input.classList.toggle('invalid', !ok);
        if (ok) set(opt.name, list, true);
      });
      input.addEventListener('change', endHistoryGroup);
      return input;
    }
    default: {
      // Free strings; those that name another method (e.g. tangents_from) offer the names.
      const input = document.createElement('input');
      input.type = 'text';
      input.value = current ?? opt.default ?? '';
      input.setAttribute('list', 'method-names');
      input.placeholder = '(none)';
      input.dataset.testid = id;
      input.addEventListener('input', () => set(opt.name, input.value === '' ? undefined : input.value, true));
      input.addEventListener('change', endHistoryGroup);
      return input;
    }
  }
}

/** What the method accepts (its registry capabilities); a method of an older server has none. */
function capabilitiesOf(name) {
  return methodInfo(name)?.capabilities ?? { closed: true, kinds: KINDS };
}

/**
 * The form shows only what the method honours: point kinds it refuses are hidden, and the
 * closed box is disabled (with the reason) for methods that draw open curves only.
 */
function applyCapabilities() {
  const caps = capabilitiesOf(state.method);
  el.kindBox.querySelectorAll('input').forEach((r) => {
    r.closest('label').hidden = !caps.kinds.includes(r.value);
  });
  el.closed.disabled = !caps.closed;
  el.closed.closest('label').title = caps.closed ? '' : `${state.method} draws open curves only`;
}

/** An option's row of a form: its name (documentation on hover) and its control. */
function optionRow(opt, control) {
  const label = document.createElement('label');
  label.className = 'opt';
  label.title = opt.doc ?? '';
  const name = document.createElement('span');
  name.textContent = opt.name;
  label.append(name, control);
  return label;
}

function buildOptionsForm() {
  applyCapabilities();
  const info = methodInfo(state.method);
  el.methodDesc.textContent = info ? `${info.description}${info.paper ? ` — ${info.paper}` : ''}` : '';
  el.options.replaceChildren();
  for (const opt of info?.options ?? []) el.options.append(optionRow(opt, optionControl(opt)));
}

/**
 * The methods as the editor lists them: the library's default first, then the elastic splines
 * (the curves of least bending energy, Curve Ensemble's default), then the rest in registry order.
 */
const FEATURED = ['restricted-elastic', 'elastic'];
function methodsInOrder() {
  const rank = (m) => (m.name === schema.default ? 0 : FEATURED.includes(m.name) ? 1 : 2);
  return [...schema.methods].sort((a, b) => rank(a) - rank(b));
}
function methodLabel(m) {
  if (m.name === schema.default) return `${m.name} (default)`;
  if (m.name === 'restricted-elastic') return `${m.name} (least bending energy; Curve Ensemble's default)`;
  if (m.name === 'elastic') return `${m.name} (least bending energy, U-turns allowed)`;
  return m.name;
}

/** The ensemble's method boxes: a ticked box is the method's default entry (its default
 * options, the curve's α). Entries are display settings, like the comb: not undo steps. */
function buildEnsemble() {
  el.ensemble.replaceChildren();
  for (const m of methodsInOrder()) {
    const label = document.createElement('label');
    label.title = m.description;
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = state.ensemble.some((e) => isDefaultEntry(e) && e.method === m.name);
    box.dataset.testid = `ensemble-${m.name}`;
    box.addEventListener('change', () => {
      if (box.checked) addEntries([makeEntry(m.name)]);
      else removeEntry(state.ensemble.findIndex((e) => isDefaultEntry(e) && e.method === m.name));
    });
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = colorOf(m.name);
    label.append(box, swatch, document.createTextNode(m.name));
    el.ensemble.append(label);
  }
  renderEntries();
}

/** The colour of each ensemble entry, in state.ensemble's order. */
const ensembleColors = () => entryColors(state.ensemble, PALETTE, colorOf);

/** Adds entries (an equal triple already listed is skipped), refits. */
function addEntries(entries) {
  const keys = new Set(state.ensemble.map(entryKey));
  for (const e of entries) if (!keys.has(entryKey(e))) { state.ensemble.push(e); keys.add(entryKey(e)); }
  syncEnsembleBoxes();
  renderEntries();
  changed();
}

function removeEntry(i) {
  if (i < 0 || i >= state.ensemble.length) return;
  const [e] = state.ensemble.splice(i, 1);
  ensembleFits.delete(entryKey(e));
  syncEnsembleBoxes();
  renderEntries();
  changed();
}

function syncEnsembleBoxes() {
  for (const box of el.ensemble.querySelectorAll('input')) {
    const name = box.dataset.testid.slice('ensemble-'.length);
    box.checked = state.ensemble.some((e) => isDefaultEntry(e) && e.method === name);
  }
}

/** The list of entries: colour, label, remove button. */
function renderEntries() {
  el.entries.replaceChildren();
  const colors = ensembleColors();
  state.ensemble.forEach((e, i) => {
    const li = document.createElement('li');
    li.dataset.testid = `entry-${i}`;
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = colors[i];
    const text = document.createElement('span');
    text.className = 'entry-label';
    text.textContent = entryLabel(e);
    const remove = document.createElement('button');
    remove.type = 'button';
    remove.textContent = '×';
    remove.title = 'remove this entry';
    remove.dataset.testid = `entry-remove-${i}`;
    remove.addEventListener('click', () => removeEntry(i));
    li.append(sw, text, remove);
    el.entries.append(li);
  });
}

// The "add entry" form: a method, its options (the method form's generator on a draft) and α.
let entryDraft = {};

function buildEntryForm() {
  const info = methodInfo(el.entryMethod.value);
  entryDraft = {};
  el.entryOptions.replaceChildren();
  const setDraft = (name, value) => {
    if (value === undefined) delete entryDraft[name];
    else entryDraft[name] = value;
  };
  for (const opt of info?.options ?? []) {
    el.entryOptions.append(optionRow(opt, optionControl(opt, undefined, setDraft, 'entry-option')));
  }
}

/** The draft as an entry: the options set in the form (even to their default: "λ=1" is what
 * the user asked to see) and α if given. */
function draftEntry() {
  const text = el.entryAlpha.value.trim();
  const alpha = text === '' ? null : Number(text);
  return makeEntry(el.entryMethod.value, entryDraft, Number.isFinite(alpha) ? alpha : null);
}

/** The α select (named parameterizations + a number) mirrors state.alpha. */
function syncAlphaControl() {
  const named = [...el.alpha.options].find((o) => o.value !== '#number' && Number(o.value) === state.alpha);
  el.alpha.value = named ? named.value : '#number';
  el.alphaNumber.disabled = !!named;
  el.alphaNumber.value = state.alpha;
}

// ---------- fitting ----------

/** The request body of curve c's data (the selected one's by default) for `method` (the JSON
 * input of `fairspline fit`). */
function requestBody(method, options, c = state) {
  const body = { points: c.points, closed: c.closed, alpha: c.alpha, method, ...nodeFields(c) };
  if (c.radii.some((r) => r > 0)) body.radii = c.radii;
  if (options && Object.keys(options).length) body.options = options;
  return body;
}

// The live channel: the same fits over a WebSocket (`GET /api/live` names its port). In
// headless chromium a fetch round trip costs 5–17 ms on loopback and a WebSocket message 1–1.5
// ms, so the selected curve's fits, one per pointer move of a drag, go this way. Answers come
// in the order of the messages. Without the channel (an older server, a proxy, a closed
// connection) fits go over POST /api/fit, and the channel is opened again at most every 5 s.
const live = { socket: null, opening: null, waiting: [], retryAt: 0 };

function openLive() {
  if (live.socket || live.opening || performance.now() < live.retryAt) return;
  live.opening = (async () => {
    try {
      const info = await (await fetch('/api/live')).json();
      if (!info?.port) return;
      const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
      const socket = new WebSocket(`${scheme}://${location.hostname}:${info.port}${info.path}`);
      await new Promise((resolve, reject) => {
        socket.onopen = resolve;
        socket.onerror = () => reject(new Error('live channel refused'));
      });
      socket.onmessage = (event) => live.waiting.shift()?.resolve(event.data);
      socket.onclose = () => {
        if (live.socket === socket) live.socket = null;
        live.retryAt = performance.now() + 5000;
        for (const w of live.waiting.splice(0)) w.reject(new Error('live channel closed'));
      };
      live.socket = socket;
    } catch {
      live.retryAt = performance.now() + 5000;
    } finally {
      live.opening = null;
    }
  })();
}

/** The answer of a live-channel message: {status, ms, answer}; throws when the channel closes. */
function liveFit(text) {
  return new Promise((resolve, reject) => {
    live.waiting.push({ resolve: (data) => resolve(JSON.parse(data)), reject });
    live.socket.send(text);
  });
}

/** The result of postBody from a status, the answer's JSON and the timings. */
function fitOutcome(status, data, ms, key) {
  if (status === 200 && data) return { fit: data, ms, key };
  return { ms, key, error: data?.error ?? { code: `http_${status}`, message: `HTTP ${status}`, index: null } };
}

/** The fit of a request body, over the live channel when it is open, else POST /api/fit: {fit,
 * ms} or {error, ms}, and `key`, the body's text (what the answer is the fit of). */
async function postBody(body) {
  const key = JSON.stringify(body);
  const started = performance.now();
  if (live.socket?.readyState === WebSocket.OPEN) {
    try {
      const reply = await liveFit(key);
      return fitOutcome(reply.status, reply.answer, { server: reply.ms, roundTrip: performance.now() - started, via: 'live' }, key);
    } catch {
      // Closed meanwhile: this fit goes over HTTP.
    }
  } else {
    openLive();
  }
  try {
    const res = await fetch('/api/fit', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: key,
    });
    const data = await res.json().catch(() => null);
    const timing = /dur=([0-9.]+)/.exec(res.headers.get('Server-Timing') ?? '');
    const ms = { server: timing ? Number(timing[1]) : null, roundTrip: performance.now() - started, via: 'http' };
    return fitOutcome(res.status, data, ms, key);
  } catch (e) {
    return { key, error: { code: 'network', message: `cannot reach the server: ${e.message}`, index: null } };
  }
}

const postFit = (method, options) => postBody(requestBody(method, options));

/** An ensemble entry's fit: the selected curve's data with the entry's method, options and α. */
const postEntry = (e) => postBody(requestBody(e.method, e.options, e.alpha == null ? state : { ...state, alpha: e.alpha }));

/**
 * Fits the visible curves other than the selected one, each with its own method and options,
 * through the same POST /api/fit; an answer is kept until its curve's request changes, so
 * editing the selected curve refits only it.
 */
async function fitOtherCurves() {
  const ids = new Set(doc.curves.map((c) => c.id));
  for (const id of otherFits.keys()) if (!ids.has(id)) otherFits.delete(id);
  const jobs = doc.curves.map(async (c, i) => {
    if (i === doc.selected || !c.visible || !c.points.length || !c.method) return;
    const body = requestBody(c.method, c.options, c);
    if (otherFits.get(c.id)?.key === JSON.stringify(body)) return;
    const r = await postBody(body);
    otherFits.set(c.id, { key: r.key, fit: r.fit, error: r.error });
  });
  await Promise.all(jobs);
}

const ENTRIES_WAIT_MS = 8;
let fitQueued = false;
let fitInFlight = false;
let fitPending = false;

/**
 * Live fits are coalesced, not delayed: the request goes out in a microtask after the edit's
 * handler (before the browser repaints, which at 200 points took 50 ms of software rendering in
 * headless chromium), edits within one task go out together, at most one request is in flight,
 * and the edits made meanwhile are sent when it returns.
 */
function requestFit() {
  if (fitQueued) return;
  fitQueued = true;
  queueMicrotask(runFit);
}

async function runFit() {
  fitQueued = false;
  if (fitInFlight) { fitPending = true; return; }
  fitInFlight = true;
  const since = editSince;
  editSince = null;
  const curveId = selectedCurve().id;
  let mainMs = null; // edit to the main curve on screen, when drawn before the ensemble's fits
  try {
    const othersDone = fitOtherCurves();
    if (!state.points.length || !state.method) {
      mainFit = null;
      mainStale = false;
      mainError = null;
      mainTiming = null;
      ensembleFits.clear();
    } else {
      // One point is fitted too: the method's own "needs at least 2 points" is the message.
      // An entry of a method this server lacks is fitted too: its row shows the server's error.
      const entries = [...state.ensemble];
      const mainDone = postFit(state.method, state.options);
      const entriesDone = Promise.all(entries.map(postEntry));
      if (entries.length) {
        // The edited curve goes on screen as soon as its fit is back, unless the entries' fits
        // follow within ENTRIES_WAIT_MS (over the live channel they come 1–3 ms later): a frame
        // of its own for the main curve delayed the entries by that frame's 30–50 ms.
        const first = await mainDone;
        const together = await Promise.race([entriesDone.then(() => true),
          new Promise((resolve) => { setTimeout(() => resolve(false), ENTRIES_WAIT_MS); })]);
        if (!together && first.fit && curveId === selectedCurve().id) mainMs = drawMainEarly(first, since);
      }
      const [main, others] = await Promise.all([mainDone, entriesDone]);
      // Another curve was selected meanwhile: these fits are not of its data.
      if (curveId !== selectedCurve().id) { fitPending = true; return; }
      // A failed fit keeps the last good curve, dimmed, next to its error (also mid-drag).
      if (main.fit) {
        mainFit = main.fit;
        mainFitKey = main.key;
        mainStale = false;
      } else if (mainFit && state.points.length >= 2) {
        mainStale = true;
      } else {
        mainFit = null;
      }
      mainError = main.error ?? null;
      mainTiming = main.ms ?? null;
      ensembleFits.clear();
      entries.forEach((e, i) => ensembleFits.set(entryKey(e), others[i]));
    }
    await othersDone;
    const drawStart = performance.now();
    drawDeferredPoints();
    render();
    lastDrawMs = performance.now() - drawStart;
    if (since != null) lastLatencyMs = performance.now() - since;
    // Drawn with the entries: the main curve came on screen with them.
    if (mainMs == null && state.ensemble.length && mainFit && !mainStale) mainMs = lastLatencyMs;
    lastMainLatencyMs = mainMs;
    renderReport();
  } finally {
    fitInFlight = false;
    if (fitPending) { fitPending = false; requestFit(); }
  }
}

/** The main curve and its comb of a successful fit, before the ensemble's fits are back (the
 * rest is drawn by render() when they are). */
function drawMainEarly(main, since) {
  drawDeferredPoints();
  mainFit = main.fit;
  mainFitKey = main.key;
  mainStale = false;
  mainError = null;
  el.layerMain.classList.remove('stale');
  const path = childAt(el.layerMain, 0, 'path');
  setAttrs(path, { d: fitPath(mainFit), 'data-testid': `curve-${mainFit.method}` });
  path.removeAttribute('data-stale');
  renderComb();
  return since == null ? null : performance.now() - since;
}

// During a drag over the live channel the moved points are drawn with the fit of their new
// position (its answer is usually back within 2–5 ms), at the latest after POINTS_WAIT_MS: points
// drawn at once made the browser render that frame (style, layout, paint) before it could take
// the answer, and that frame took 10–20 ms of the round trip on two cores.
const POINTS_WAIT_MS = 30;
let pointsDeferred = null; // the fallback timer while the points wait for their fit

function drawDeferredPoints() {
  if (pointsDeferred == null) return;
  clearTimeout(pointsDeferred);
  pointsDeferred = null;
  renderPoints();
  renderSelection();
}

/** Any change of the data: redraw the points now (or with the fit, during a drag over the live
 * channel), save the hash, refit soon. */
function changed() {
  editSince ??= performance.now();
  if (drag && live.socket) {
    pointsDeferred ??= setTimeout(drawDeferredPoints, POINTS_WAIT_MS);
  } else {
    drawDeferredPoints();
    renderPoints();
    renderSelection();
  }
  saveHashSoon();
  requestFit();
}

let hashDeferred = false;

/** saveHash, or during a drag at its end: history.replaceState with the document's text took
 * 10 ms per pointer move at 50 points (and grows with the points). */
function saveHashSoon() {
  if (drag) hashDeferred = true;
  else saveHash();
}

// ---------- view: zoom and pan ----------

function applyView() {
  const { x, y, w } = state.view;
  el.canvas.setAttribute('viewBox', `${x} ${y} ${w} ${w * ASPECT}`);
  el.zoomLabel.textContent = `${fmt(FRAME_W / w)}×`;
  // Sizes fixed on screen follow the zoom.
  renderPoints();
  renderKinds();
  renderComb();
  renderOtherCombs();
  renderReportMarks();
  renderControlPolygon();
  renderGrid();
  renderError(); // "show point" depends on what is in view
}

function setView(view) {
  if (!(view.w > 0) || !Number.isFinite(view.w) || !Number.isFinite(view.x) || !Number.isFinite(view.y)) return;
  state.view = view;
  if (drag) drag.toWorld = null; // the transform changed under the drag
  applyView();
  saveHashSoon();
}

/** SVG user coordinates (before the world's y flip) of a client position. */
function toUser(clientX, clientY) {
  const p = el.canvas.createSVGPoint();
  p.x = clientX;
  p.y = clientY;
  const q = p.matrixTransform(el.canvas.getScreenCTM().inverse());
  return [q.x, q.y];
}

function toWorld(evt) {
  const p = el.canvas.createSVGPoint();
  p.x = evt.clientX;
  p.y = evt.clientY;
  // A drag keeps the transform it started with (reading it forces a style and layout update,
  // which after a fit's drawing is that drawing's whole restyle, in the pointer's handler).
  let inverse = drag?.toWorld;
  if (!inverse) {
    inverse = el.world.getScreenCTM().inverse();
    if (drag) drag.toWorld = inverse;
  }
  const q = p.matrixTransform(inverse);
  return [q.x, q.y];
}

/** Zooms by `factor` (> 1: in) keeping the user point [ux, uy] fixed on screen. */
function zoomAbout(factor, [ux, uy]) {
  const { x, y, w } = state.view;
  const nw = Math.min(1e12, Math.max(1e-9, w / factor));
  const f = w / nw;
  setView({ x: ux - (ux - x) / f, y: uy - (uy - y) / f, w: nw });
}

function zoomCenter(factor) {
  const { x, y, w } = state.view;
  zoomAbout(factor, [x + w / 2, y + (w * ASPECT) / 2]);
}

/** Frames the points (and curves) with a margin; the default frame when there is nothing. */
function fitView(all = false) {
  // The selected curve's points and fit; with `all`, those of every visible curve too.
  const shapes = [{ points: state.points, fit: mainFit }];
  if (all) {
    doc.curves.forEach((c, i) => {
      if (i !== doc.selected && c.visible) shapes.push({ points: c.points, fit: otherFits.get(c.id)?.fit });
    });
  }
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  const add = ([x, y]) => { x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y); };
  for (const { points, fit } of shapes) {
    points.forEach(add);
    for (const s of fit?.segments ?? []) s.bezier.forEach(add);
  }
  if (x0 > x1) return setView({ x: 0, y: 0, w: FRAME_W });
  const size = Math.max(x1 - x0, (y1 - y0) / ASPECT, 1e-6 * Math.max(1, Math.abs(x0), Math.abs(y0)));
  const w = size * 1.15;
  // World y is flipped: user y = FRAME_H − world y.
  const cx = (x0 + x1) / 2, cy = FRAME_H - (y0 + y1) / 2;
  setView({ x: cx - w / 2, y: cy - (w * ASPECT) / 2, w });
}

/** Pans so that world point p is in the middle of the view. */
function centerOn([px, py]) {
  const { w } = state.view;
  setView({ x: px - w / 2, y: FRAME_H - py - (w * ASPECT) / 2, w });
}

/** The user-coordinate rectangle visible on screen (wider or taller than the viewBox when the
 * canvas's aspect differs from the frame's). */
function visibleRect() {
  const r = el.canvas.getBoundingClientRect();
  if (!r.width || !r.height) {
    const { x, y, w } = state.view;
    return { x0: x, y0: y, x1: x + w, y1: y + w * ASPECT };
  }
  const [x0, y0] = toUser(r.left, r.top);
  const [x1, y1] = toUser(r.right, r.bottom);
  return { x0, y0, x1, y1 };
}

function pointVisible([px, py]) {
  const v = visibleRect();
  const uy = FRAME_H - py;
  return px >= v.x0 && px <= v.x1 && uy >= v.y0 && uy <= v.y1;
}

// ---------- drawing ----------

function renderPoints() {
  // Circles are updated in place so that a point being dragged keeps its element.
  const layer = el.layerPoints;
  while (layer.children.length > state.points.length) layer.lastChild.remove();
  while (layer.children.length < state.points.length) {
    const i = layer.children.length;
    layer.append(svg('circle', { 'data-testid': `point-${i}`, 'data-index': i }));
  }
  const bad = mainError?.index;
  const r = POINT_R_PX * unit();
  const chosen = new Set(selectedIndices());
  // Only what changed is written: a drag moves one point of 500.
  const circles = layer.children;
  state.points.forEach(([x, y], i) => {
    const [a, b] = state.states[i];
    setAttrs(circles[i], {
      cx: x, cy: y, r,
      'data-kind': kindOf(i) ?? 'node',
      'data-states': `${a}/${b}`,
      class: `${chosen.has(i) ? 'selected' : ''}${i === state.selected ? ' primary' : ''}${i === bad ? ' error' : ''}`,
    });
  });
  renderEmptyHint();
  renderKinds();
}

/**
 * Corner squares, the tangent arrows of clamped points (the arrow tip is draggable), and the
 * discs of data balls with the position the fit chose in each (a ring; filled when the curve
 * touches the disc's circle there).
 */
let kindsKey = null; // what the layer shows, so that it is rebuilt only when that changes

function renderKinds() {
  const u = unit();
  const balls = fitIndexOf(0) >= 0 ? mainFit.method_report?.balls : null;
  const onCircle = new Set(balls?.active ?? []);
  // Only nodes with a ball, a clamped or free side draw here: a drag of a plain node, which is
  // most fits of a drag, leaves the layer as it is.
  const drawn = [];
  // A regular node keeping a corner angle draws it between the fit's arms there.
  const keepsCorner = (i) => state.corners[i] !== 0 && cornerApplies(i) && state.states[i][1] === 'regular';
  state.states.forEach(([a, b], i) => {
    if ((state.radii[i] ?? 0) > 0 || a !== 'regular' || b !== 'regular' || keepsCorner(i)) {
      drawn.push([i, state.points[i], state.radii[i], a, b, nodeArrows(i), balls ? [mainFit.points?.[fitIndexOf(i)], onCircle.has(i)] : 0,
        keepsCorner(i) && fitIndexOf(i) >= 0 ? [state.corners[i], currentArrow(i, 'in'), currentArrow(i, 'out')] : 0]);
    }
  });
  const inserted = fitIndexOf(0) >= 0 ? (mainFit.method_report?.inserted ?? []).map((k) => [k, mainFit.points[k]]) : [];
  const key = JSON.stringify([u, drawn, inserted, mainFit?.method]);
  if (key === kindsKey) return;
  kindsKey = key;
  el.layerKinds.replaceChildren();
  // Points the method inserted (jaklic-zagar, reversal=insert): the curve passes through them,
  // so they are drawn, smaller and not draggable.
  if (fitIndexOf(0) >= 0) {
    for (const k of mainFit.method_report?.inserted ?? []) {
      const [x, y] = mainFit.points[k];
      const h = 0.7 * POINT_R_PX * u;
      const mark = svg('rect', { x: x - h, y: y - h, width: 2 * h, height: 2 * h, class: 'inserted', 'data-testid': `inserted-${k}` });
      const title = svg('title');
      title.textContent = `point inserted by ${mainFit.method} (fit point ${k})`;
      mark.append(title);
      el.layerKinds.append(mark);
    }
  }
  state.points.forEach(([x, y], i) => {
    const r = state.radii[i] ?? 0;
    if (r > 0) {
      el.layerKinds.append(svg('circle', { cx: x, cy: y, r, class: 'ball', 'data-testid': `ball-${i}` }));
      const chosen = balls && mainFit.points?.[fitIndexOf(i)];
      if (chosen) {
        el.layerKinds.append(svg('circle', {
          cx: chosen[0], cy: chosen[1], r: 0.6 * POINT_R_PX * u,
          class: onCircle.has(i) ? 'ball-position active' : 'ball-position', 'data-testid': `ball-position-${i}`,
        }));
      }
    }
    if (r > 0) {
      // The rim: dragging it sets the radius.
      // (Its hit width is in world units: chromium hit-tests a non-scaling stroke at the wrong width.)
      el.layerKinds.append(svg('circle', { cx: x, cy: y, r, class: 'ball-rim', 'stroke-width': 12 * u, 'data-rim': i, 'data-testid': `rim-${i}` }));
    }
    const [sideIn, sideOut] = state.states[i];
    if (sideIn === 'free' || sideOut === 'free') {
      // A free side splits the curve there: a square (both sides free: a corner), dashed for one.
      const h = 1.9 * POINT_R_PX * u;
      const both = sideIn === sideOut;
      el.layerKinds.append(svg('rect', { x: x - h, y: y - h, width: 2 * h, height: 2 * h, class: both ? 'corner' : 'corner half',
        'data-testid': both ? `corner-${i}` : `free-${i}` }));
    }
    if (keepsCorner(i) && fitIndexOf(i) >= 0) drawCornerAngle(i, x, y, u);
    const arrows = nodeArrows(i);
    const head = 10 * u;
    const arrow = (from, tip, dir, cls, testid, handleAttrs) => {
      const len = Math.hypot(...dir) || 1;
      const [ux, uy] = [dir[0] / len, dir[1] / len];
      // The head points along the direction of travel, at the tip (out) or at the node (in).
      const at = cls === 'tangent' ? tip : from;
      const g = svg('g', { class: cls, 'data-testid': testid });
      g.append(
        svg('line', { x1: from[0], y1: from[1], x2: tip[0], y2: tip[1] }),
        svg('polyline', {
          points: [[at[0] - head * (ux - 0.5 * uy), at[1] - head * (uy + 0.5 * ux)], at,
            [at[0] - head * (ux + 0.5 * uy), at[1] - head * (uy - 0.5 * ux)]].map((p) => p.join(',')).join(' '),
        }),
        svg('circle', { cx: tip[0], cy: tip[1], r: 5 * u, class: 'handle', ...handleAttrs }),
      );
      el.layerKinds.append(g);
    };
    if (arrows.out) {
      const [dx, dy] = arrows.out;
      arrow([x, y], [x + dx, y + dy], arrows.out, 'tangent', `tangent-${i}`, { 'data-handle': i, 'data-testid': `handle-${i}` });
    }
    if (arrows.in) {
      // The incoming arrow is drawn backwards from the node, like the Bézier arm before it.
      const [dx, dy] = arrows.in;
      arrow([x, y], [x - dx, y - dy], arrows.in, 'tangent tangent-in', `tangent-in-${i}`, { 'data-handle-in': i, 'data-testid': `handle-in-${i}` });
    }
  });
}

/** The corner angle a regular node keeps: a wedge from the fit's incoming direction to its
 * outgoing one (the sweep of the angle, |angle| < 180°). */
function drawCornerAngle(i, x, y, u) {
  const inn = currentArrow(i, 'in'), out = currentArrow(i, 'out');
  const r = 7 * POINT_R_PX * u;
  const at = (d) => { const len = Math.hypot(...d) || 1; return [x + (r * d[0]) / len, y + (r * d[1]) / len]; };
  const [s, e] = [at(inn), at(out)];
  const sweep = inn[0] * out[1] - inn[1] * out[0] > 0 ? 1 : 0;
  // A wedge: the node, the incoming direction's ray, the arc, the outgoing direction's ray.
  const arc = svg('path', {
    d: `M${x},${y} L${s[0]},${s[1]} A${r},${r} 0 0 ${sweep} ${e[0]},${e[1]} Z`, class: 'corner-angle', 'data-testid': `corner-angle-${i}`,
  });
  const title = svg('title');
  title.textContent = `point ${i} keeps a corner of ${fmt(state.corners[i])}°`;
  arc.append(title);
  el.layerKinds.append(arc);
}

/** A number for a panel field: exact for what was typed, 10 digits for what was computed. */
const fieldText = (v) => (Number.isFinite(v) ? String(compact(v)) : '');

/** The selected-node panel follows the selected point (the primary one of a selection). */
function renderSelection() {
  const i = state.selected;
  const ok = i >= 0 && i < state.points.length;
  const kinds = capabilitiesOf(state.method).kinds;
  const kind = ok ? kindOf(i) : null;
  el.kindBox.querySelectorAll('input').forEach((r) => {
    r.disabled = !ok || !kinds.includes(r.value);
    r.checked = ok && r.value === kind;
  });
  el.radius.disabled = !ok || !capabilitiesOf(state.method).data_balls;
  const show = (input, text, enabled = ok) => {
    input.disabled = !enabled;
    if (document.activeElement !== input) {
      const value = ok ? text : '';
      if (input.value !== value) input.value = value; // a drag calls this on every pointer move
      input.classList.remove('invalid');
    }
  };
  show(el.radius, ok ? String(state.radii[i] ?? 0) : '0');
  if (!ok && document.activeElement !== el.radius) el.radius.value = '0';
  show(el.nodeX, ok ? String(state.points[i][0]) : '');
  show(el.nodeY, ok ? String(state.points[i][1]) : '');
  for (const [select, k] of [[el.stateIn, 0], [el.stateOut, 1]]) {
    select.disabled = !ok;
    select.value = ok ? state.states[i][k] : 'regular';
  }
  const arrows = ok ? nodeArrows(i) : {};
  const dir = arrows.out ?? arrows.in;
  show(el.nodeDir, dir ? fieldText(angleOf(dir)) : '', !!dir);
  // With no arrow, the direction shown is the fit's (a placeholder: typing needs a clamped side).
  const fitted = ok && !dir && fitIndexOf(i) >= 0 ? mainFit.tangents?.[fitIndexOf(i)] : null;
  el.nodeDir.placeholder = fitted ? `${fieldText(angleOf(fitted))} (fit)` : '';
  const twoArrows = ok && state.states[i][0] === 'clamped' && state.states[i][1] === 'clamped';
  const corner = !ok ? 0 : twoArrows && state.inArrows[i] ? normalDeg(angleOf(arrows.out) - angleOf(arrows.in)) : state.corners[i];
  show(el.nodeCorner, fieldText(corner), ok && !state.states[i].includes('free'));
  const count = selectedIndices().length;
  el.transformTarget.textContent = count ? `the ${count} selected point${count > 1 ? 's' : ''}` : 'the whole curve';
  const states = ok ? state.states[i].join(' / ') : '';
  el.kindLabel.textContent = !ok ? 'no point selected'
    : `point ${i} (in / out: ${states})${count > 1 ? ` · ${count} points selected` : ''}`;
}

/** An angle in degrees in (−180, 180]. */
function normalDeg(d) {
  let v = d % 360;
  if (v > 180) v -= 360;
  if (v <= -180) v += 360;
  return v;
}

/** Curvature comb of the main curve: teeth along the normal, length ∝ signed curvature. */
/** The comb's teeth [[x1, y1, x2, y2], ...] as drawn (the SVG export writes them). */
let combTeeth = [];

/** Path data of comb teeth (one subpath per tooth) and of the line through their tips. */
function combPaths(teeth) {
  // To a hundredth of a pixel of the default view: the full 17 digits made the text three
  // times as long to build and for chromium to parse.
  const digits = Math.min(20, Math.max(0, 2 - Math.floor(Math.log10(unit()))));
  const f = (v) => v.toFixed(digits);
  let d = '', tips = '';
  for (const [x1, y1, x2, y2] of teeth) {
    const x = f(x2), y = f(y2);
    d += `M${f(x1)} ${f(y1)}L${x} ${y}`;
    tips += `${tips ? 'L' : 'M'}${x} ${y}`;
  }
  return { d, tips };
}

/** Draws a comb into `layer`: one path for all the teeth (`data-teeth` counts them) and one
 * through their tips. One element per tooth (800 at 50 points) was most of a fit's drawing time. */
function drawComb(layer, teeth) {
  if (!teeth.length) { trimLayer(layer, 0); return; }
  const { d, tips } = combPaths(teeth);
  setAttrs(childAt(layer, 0, 'path'), { class: 'teeth', d, 'data-teeth': teeth.length });
  setAttrs(childAt(layer, 1, 'path'), { class: 'tips', d: tips });
  trimLayer(layer, 2);
}

/** Curvature comb of the main curve: teeth along the normal, length ∝ signed curvature. */
function renderComb() {
  el.layerComb.classList.toggle('stale', mainStale);
  combTeeth = [];
  if (state.comb && mainFit) {
    const samples = sampleCurve(mainFit.segments, COMB_SAMPLES).filter((s) => s.kappa != null);
    let kmax = 1e-300;
    for (const s of samples) kmax = Math.max(kmax, Math.abs(s.kappa));
    const scale = (COMB_MAX_PX * unit()) / kmax;
    // Teeth point away from the centre of curvature.
    combTeeth = samples.map(({ pt, normal, kappa }) => [pt[0], pt[1], pt[0] - normal[0] * kappa * scale, pt[1] - normal[1] * kappa * scale]);
  }
  drawComb(el.layerComb, combTeeth);
}

/**
 * With "combs of all curves": the comb of every other visible curve and ensemble entry, in its
 * colour, at the selected curve's scale (one tooth length for one curvature everywhere, so the
 * combs compare), teeth cut at twice the longest main tooth so that a spike stays readable.
 */
function renderOtherCombs() {
  el.layerCombOthers.replaceChildren();
  if (!state.combAll) return;
  const fits = [
    ...otherVisibleFits().map(({ c, i, fit }) => ({ fit, color: c.color, id: `curve-${i}` })),
    ...ensembleRows().filter((r) => r.result.fit).map((r) => ({ fit: r.result.fit, color: r.color, id: r.id })),
  ];
  const sampled = fits.map((f) => ({ ...f, samples: sampleCurve(f.fit.segments, COMB_SAMPLES).filter((x) => x.kappa != null) }));
  const base = mainFit ? sampleCurve(mainFit.segments, COMB_SAMPLES) : sampled.flatMap((f) => f.samples);
  const kmax = Math.max(1e-300, ...base.filter((x) => x.kappa != null).map((x) => Math.abs(x.kappa)));
  const scale = (COMB_MAX_PX * unit()) / kmax;
  const cap = 2 * COMB_MAX_PX * unit();
  for (const f of sampled) {
    const g = svg('g', { stroke: f.color, 'data-testid': `comb-${f.id}` });
    drawComb(g, f.samples.map(({ pt, normal, kappa }) => {
      const len = Math.max(-cap, Math.min(cap, kappa * scale));
      return [pt[0], pt[1], pt[0] - normal[0] * len, pt[1] - normal[1] * len];
    }));
    el.layerCombOthers.append(g);
  }
}

// ---------- report panel: the selected curve's method_report ----------

let reportHover = null; // {node, spans} of the row under the pointer
let reportQueued = false;

/**
 * The panel is rebuilt in a task after the fit is drawn: its tables (a row per node at 200
 * points) must not delay the curve on screen during a drag. A collapsed panel is left alone
 * until it is opened again. The rings are drawn at once.
 */
function scheduleReportPanel() {
  renderReportMarks();
  if (reportQueued) return;
  reportQueued = true;
  // After the next frame: a task queued at once ran before chromium painted the curve.
  requestAnimationFrame(() => setTimeout(() => { reportQueued = false; renderReportPanel(); }, 0));
}

/** The panel, and the rings of its marked nodes on the canvas. */
function renderReportPanel() {
  if (!el.reportPanel.open) return;
  renderMethodReport(el.methodReport, mainFit, (target) => { reportHover = target; renderReportMarks(); }, mainStale);
  reportHover = null;
  renderReportMarks();
}

/**
 * Rings around the nodes the report marks (active bounds: G2 lost; Jaklič–Žagar maxima), at the
 * fit's points (the report's indices are the fit's), and the node or spans of the hovered row.
 */
function renderReportMarks() {
  el.layerReport.replaceChildren();
  el.layerHighlight.replaceChildren();
  if (!mainFit) return;
  const u = unit();
  el.layerReport.classList.toggle('stale', mainStale);
  for (const { index, why } of markedNodes(mainFit)) {
    const p = mainFit.points?.[index];
    if (!p) continue;
    const ring = svg('circle', { cx: p[0], cy: p[1], r: 1.9 * POINT_R_PX * u, class: `ring ${why}`, 'data-testid': `ring-${index}`, 'data-why': why });
    const title = svg('title');
    title.textContent = why === 'active' ? `point ${index}: the bound Ω holds (G2 lost)` : `point ${index}: an energy maximum of the direction`;
    ring.append(title);
    el.layerReport.append(ring);
  }
  const h = reportHover;
  if (h?.node != null && mainFit.points?.[h.node]) {
    const [x, y] = mainFit.points[h.node];
    el.layerHighlight.append(svg('circle', { cx: x, cy: y, r: 2.8 * POINT_R_PX * u, 'data-testid': 'highlight', 'data-node': h.node }));
  } else if (h?.spans) {
    // Segments carry the input span they belong to; without it a segment is its span.
    const spanOf = (s, k) => (s.span ?? k);
    const segs = mainFit.segments.filter((s, k) => h.spans.includes(spanOf(s, k)));
    if (segs.length) el.layerHighlight.append(svg('path', { d: pathData(segs), 'data-testid': 'highlight', 'data-spans': h.spans.join(',') }));
  }
}

/** The control polygon p0–p1–p2–p3 of every segment of the main curve. */
function renderControlPolygon() {
  el.layerControl.replaceChildren();
  el.layerControl.classList.toggle('stale', mainStale);
  if (!state.polygon || !mainFit) return;
  for (const { bezier } of mainFit.segments) {
    el.layerControl.append(svg('polyline', { points: bezier.map((p) => p.join(',')).join(' ') }));
    for (const [x, y] of [bezier[1], bezier[2]]) el.layerControl.append(svg('circle', { cx: x, cy: y, r: 3 * unit() }));
  }
}

/** The ensemble entries with their fits (or errors), labels, colours and test ids. A default
 * entry keeps the ids a method's box always had (curve-NAME, kappa-NAME). */
function ensembleRows() {
  const colors = ensembleColors();
  return state.ensemble.map((e, i) => ({
    index: i, entry: e, label: entryLabel(e), color: colors[i], result: ensembleFits.get(entryKey(e)),
    id: isDefaultEntry(e) ? e.method : `entry-${i}`,
  })).filter((r) => r.result);
}

/** The other visible curves of the document with a fit: [{c, i, fit}]. */
const otherVisibleFits = () => doc.curves.map((c, i) => ({ c, i, fit: otherFits.get(c.id)?.fit }))
  .filter(({ c, i, fit }) => i !== doc.selected && c.visible && fit);

/** κ against s, one line per visible curve: the document's other curves, the selected one and
 * its ensemble entries. */
function renderPlot() {
  el.plot.toggleAttribute('hidden', !state.plot); // an <svg> has no .hidden property
  if (!state.plot) return;
  const curves = [];
  const samples = (segments) => sampleCurve(segments, Math.min(24, Math.max(2, Math.ceil(PLOT_SAMPLES / segments.length))));
  for (const { c, i, fit } of otherVisibleFits()) {
    curves.push({ name: `curve-${i}`, label: c.name, color: c.color, main: false, samples: samples(fit.segments) });
  }
  if (mainFit) curves.push({ name: mainFit.method, label: selectedCurve().name, color: 'var(--fg)', main: true, stale: mainStale, samples: samples(mainFit.segments) });
  for (const r of ensembleRows()) {
    if (r.result.fit) curves.push({ name: r.id, label: r.label, color: r.color, main: false, samples: samples(r.result.fit.segments) });
  }
  renderCurvaturePlot(el.plot, curves);
}

// The energies table's columns: its sort key reads a fit's report (null: not a number).
const TABLE_COLUMNS = [
  { key: 'label', head: 'curve', value: (row) => row.label },
  { key: 'bending', head: 'bending energy', value: (row) => row.report?.bending_energy },
  { key: 'linearized', head: 'linearized energy', value: (row) => row.report?.linearized_energy },
  { key: 'length', head: 'length', value: (row) => row.report?.length },
  { key: 'regular', head: 'regular', value: (row) => (row.report?.regular == null ? null : row.report.regular ? 1 : 0) },
  { key: 'jump', head: 'max curvature jump', value: (row) => row.report?.max_curvature_jump },
];
let tableSort = null; // {key, dir: 1 | -1}; null: the main curve, then the entries in their order

/** The header: a click sorts by the column (again: the other way). */
function buildTableHead() {
  const tr = document.createElement('tr');
  for (const col of TABLE_COLUMNS) {
    const th = document.createElement('th');
    th.dataset.testid = `sort-${col.key}`;
    th.className = 'sortable';
    th.title = 'sort by this column';
    const mark = tableSort?.key === col.key ? (tableSort.dir > 0 ? ' ▲' : ' ▼') : '';
    th.textContent = `${col.head}${mark}`;
    th.addEventListener('click', () => {
      tableSort = { key: col.key, dir: tableSort?.key === col.key ? -tableSort.dir : 1 };
      buildTableHead();
      renderTable();
    });
    tr.append(th);
  }
  el.tableHead.replaceChildren(tr);
}

/** Rows sorted by tableSort: numbers (or labels) in its direction, failures always last. */
function sortRows(rows) {
  if (!tableSort) return rows;
  const col = TABLE_COLUMNS.find((c) => c.key === tableSort.key);
  const failed = rows.filter((r) => !r.report);
  const ok = rows.filter((r) => r.report);
  const cmp = (a, b) => {
    const x = col.value(a), y = col.value(b);
    if (typeof x === 'string') return tableSort.dir * x.localeCompare(y);
    const nx = Number.isFinite(x) ? x : Infinity, ny = Number.isFinite(y) ? y : Infinity;
    return nx === ny ? 0 : tableSort.dir * (nx < ny ? -1 : 1);
  };
  return [...ok.sort(cmp), ...failed];
}

/** The energies table: the selected curve (main) and each ensemble entry; a failure is a row
 * with its message. */
let tableKey = null; // the rows' identities and failures: a change rebuilds the table

function renderTable() {
  const rows = [];
  if (mainFit || mainError) {
    rows.push({ testid: 'row-main', method: state.method, label: `${state.method} (main)`, color: 'var(--fg)',
      report: mainError ? null : mainFit.report ?? {}, error: mainError });
  }
  for (const r of ensembleRows()) {
    rows.push({ testid: `row-entry-${r.index}`, method: r.entry.method, label: r.label, color: r.color,
      report: r.result.fit ? r.result.fit.report ?? {} : null, error: r.result.error });
  }
  const sorted = sortRows(rows);
  // During a drag only the numbers change: the cells are updated in place.
  const values = (r) => [r.bending_energy, r.linearized_energy, r.length, r.regular == null ? '—' : (r.regular ? 'yes' : 'no'), r.max_curvature_jump];
  const key = JSON.stringify(sorted.map((r) => [r.testid, r.method, r.label, r.color, r.report ? 0 : r.error?.message ?? 'failed']));
  if (key === tableKey) {
    sorted.forEach((row, k) => {
      if (!row.report) return;
      const cells = el.table.rows[k].cells;
      values(row.report).forEach((v, j) => { const text = fmt(v); if (cells[j + 1].textContent !== text) cells[j + 1].textContent = text; });
    });
    return;
  }
  tableKey = key;
  el.table.replaceChildren();
  for (const row of sorted) {
    const tr = document.createElement('tr');
    tr.dataset.method = row.method;
    tr.dataset.testid = row.testid;
    tr.dataset.label = row.label;
    const head = document.createElement('td');
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = row.color;
    head.append(sw, document.createTextNode(` ${row.label}`));
    tr.append(head);
    if (row.report) {
      const r = row.report;
      for (const v of values(r)) {
        const td = document.createElement('td');
        td.textContent = fmt(v);
        tr.append(td);
      }
    } else {
      const td = document.createElement('td');
      td.colSpan = 5;
      td.className = 'err';
      td.textContent = row.error?.message ?? 'failed';
      tr.append(td);
    }
    el.table.append(tr);
  }
}

let legendKey = null; // what the legend shows, so that it is rebuilt only when that changes

/** Draws the last fits. The elements of the curves, comb, plot and table are updated in place
 * (only the attributes that changed), so that a fit during a drag costs chromium a repaint of
 * what moved, not a rebuild of every element. */
function render() {
  renderOtherCurves();
  renderCurvesPanel();
  el.layerMain.classList.toggle('stale', mainStale);
  if (mainFit) {
    const path = childAt(el.layerMain, 0, 'path');
    setAttrs(path, { d: fitPath(mainFit), 'data-testid': `curve-${mainFit.method}` });
    path.toggleAttribute('data-stale', mainStale);
  }
  trimLayer(el.layerMain, mainFit ? 1 : 0);
  const legend = [];
  if (mainFit) legend.push([`${mainFit.method} (main${mainStale ? ', last good fit' : ''})`, 'var(--fg)']);
  doc.curves.forEach((c, i) => {
    if (i !== doc.selected && c.visible && otherFits.get(c.id)?.fit) legend.push([`${c.name}: ${c.method}`, c.color]);
  });
  let k = 0;
  for (const r of ensembleRows()) {
    if (!r.result.fit) continue;
    setAttrs(childAt(el.layerEnsemble, k++, 'path'), {
      d: fitPath(r.result.fit), stroke: r.color, 'data-testid': `curve-${r.id}`, 'data-entry': r.index, 'data-label': r.label,
    });
    legend.push([r.label, r.color]);
  }
  trimLayer(el.layerEnsemble, k);
  const key = JSON.stringify(legend);
  if (key !== legendKey) {
    legendKey = key;
    el.legend.replaceChildren();
    for (const [text, color] of legend) addLegend(text, color);
  }
  renderError();
  renderReport();
  renderPoints();
  renderComb();
  renderOtherCombs();
  renderControlPolygon();
  renderPlot();
  renderTable();
  scheduleReportPanel();
}

/** One line under the plot: the main curve's numbers and how long the fit took. */
function renderReport() {
  const r = mainFit?.report;
  const ms = (v) => (v == null ? '?' : Number(v.toPrecision(2)).toString());
  const timing = mainTiming
    ? ` · fit ${ms(mainTiming.server)} ms, round trip ${ms(mainTiming.roundTrip)} ms${mainTiming.via === 'live' ? ' (live channel)' : ''}, draw ${ms(lastDrawMs)} ms, edit to screen ${ms(lastLatencyMs)} ms${lastMainLatencyMs == null ? '' : ` (main curve ${ms(lastMainLatencyMs)} ms)`}`
    : '';
  const balls = mainFit?.method_report?.balls;
  const ballText = balls ? ` · data balls ${balls.active.length} of ${balls.count} on their circle (${balls.status})` : '';
  el.report.textContent = r
    ? `${mainStale ? 'last good fit: ' : ''}${mainFit.segments.length} segments · bending ${fmt(r.bending_energy)} · length ${fmt(r.length)} · max tangent jump ${fmt(r.max_tangent_angle_jump_deg)}°${ballText}${timing}`
    : '';
}

/** The message in the box over the canvas; "show point" when the offending point is off view. */
function renderError() {
  const text = importError ? `import: ${importError}`
    : (mainError ? `${mainError.code}${mainError.index != null ? ` at point ${mainError.index}` : ''}: ${mainError.message}` : '');
  el.errorText.textContent = text;
  el.error.title = text;
  el.error.hidden = !text;
  // "Add another point" is where a curve starts, not a failure.
  el.error.classList.toggle('info', !importError && mainError?.code === 'too_few_points');
  const p = state.points[mainError?.index ?? -1];
  el.errorShow.hidden = importError != null || !p || pointVisible(p);
  // The library names the option that gets past the error; here it is a button.
  const hint = !importError && mainError?.hint;
  const spec = hint && methodInfo(state.method)?.options?.find((o) => o.name === hint.option);
  el.errorHint.hidden = !spec;
  if (spec) {
    el.errorHint.textContent = hint.value == null ? `set the option ${spec.name}` : `set ${spec.name} to ${hint.value}`;
    el.errorHint.title = spec.doc ?? '';
  }
  renderErrorMarker();
}

/** Applies the error's hint: sets the option (one undo step), or shows its control when the
 * hint leaves the value to the user. */
function applyHint() {
  const hint = mainError?.hint;
  const spec = hint && methodInfo(state.method)?.options?.find((o) => o.name === hint.option);
  if (!spec) return;
  if (hint.value == null) {
    el.options.querySelector(`[data-testid="option-${spec.name}"]`)?.focus();
    return;
  }
  const num = Number(hint.value);
  const value = spec.type === 'boolean' ? hint.value === 'true'
    : (spec.type === 'number' || spec.type === 'integer' || (spec.type === 'choice_or_number' && !spec.choices?.includes(hint.value))) && Number.isFinite(num) ? num
      : hint.value;
  setOption(spec.name, value);
  buildOptionsForm();
}

/** A label next to the offending point, or at the edge of the view pointing towards it. */
function renderErrorMarker() {
  el.layerError.replaceChildren();
  const i = mainError?.index;
  const p = i == null || importError ? null : state.points[i];
  if (!p) return;
  const u = unit();
  const v = visibleRect();
  // Clamp into the visible area (user coordinates), then back to world coordinates.
  const margin = 24 * u;
  const ux = Math.min(Math.max(p[0], v.x0 + margin), v.x1 - margin);
  const uy = Math.min(Math.max(FRAME_H - p[1], v.y0 + margin), v.y1 - margin);
  const at = [ux, FRAME_H - uy];
  const inside = at[0] === p[0] && at[1] === p[1];
  const label = inside ? `point ${i}: ${mainError.code}` : `point ${i} (${mainError.code}) is off view`;
  const g = svg('g', { class: 'error-marker', 'data-testid': 'error-marker', transform: `translate(${at[0]} ${at[1]}) scale(${u} ${-u})` });
  if (!inside) {
    const ang = Math.atan2(-(p[1] - at[1]), p[0] - at[0]) * 180 / Math.PI;
    g.append(svg('path', { d: 'M-6,-5L12,0L-6,5Z', transform: `rotate(${ang})`, class: 'pointer' }));
  }
  const text = svg('text', { x: inside ? 12 : 14, y: inside ? -12 : 4 });
  text.textContent = label;
  g.append(text);
  el.layerError.append(g);
  // Keep the label inside the visible area horizontally.
  const box = text.getBBox();
  if (at[0] + (box.x + box.width) * u > v.x1 - 4 * u) text.setAttribute('x', -box.width - 14);
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

// {type: 'point' | 'handle' | 'pan' | 'press', index, moved, start, view, ctm}
let drag = null;
let suppressClick = false;

function swallowNextClick() {
  suppressClick = true;
  setTimeout(() => { suppressClick = false; }, 0);
}

// Keyboard shortcuts act on the canvas whenever the pointer was last pressed there: the press
// takes the focus from whichever panel control had it (a press on a point is preventDefault-ed,
// which keeps the focus where it was: a dropdown's type-ahead then took K, a number field
// Backspace). A panel control that gets the focus afterwards (click or Tab) has the keys again.
let pointerOnCanvas = false;
window.addEventListener('pointerdown', (evt) => { pointerOnCanvas = el.canvas.contains(evt.target); }, true);
document.addEventListener('focusin', (evt) => { if (!el.canvas.contains(evt.target)) pointerOnCanvas = false; });

el.canvas.addEventListener('pointerdown', (evt) => {
  el.canvas.focus({ preventScroll: true });
  const { index, handle, handleIn, rim, curve } = evt.target.dataset ?? {};
  const onMark = index !== undefined || handle !== undefined || handleIn !== undefined || rim !== undefined;
  if (curve !== undefined && evt.button === 0 && !evt.shiftKey && !evt.altKey) {
    // A press on another curve of the document selects it (its click adds no point).
    evt.preventDefault();
    selectCurve(Number(curve));
    // Its release never adds a point: the path under the pointer now draws another curve (its
    // element is reused), so the click goes to the canvas.
    drag = { type: 'select' };
    return;
  }
  if (evt.button === 1 || (evt.button === 0 && !onMark)) {
    // Background (or middle button anywhere): a click adds a point, a drag pans; with Shift a
    // drag selects the points in its box.
    const type = evt.button === 1 ? 'pan' : evt.shiftKey ? 'box' : 'press';
    drag = { type, start: [evt.clientX, evt.clientY], from: toWorld(evt), view: { ...state.view }, ctm: el.canvas.getScreenCTM() };
    if (evt.button === 1 || evt.shiftKey) evt.preventDefault();
    return;
  }
  if (evt.button !== 0) return;
  evt.preventDefault();
  if (handle !== undefined || handleIn !== undefined) {
    drag = { type: handle !== undefined ? 'handle' : 'handle-in', index: Number(handle ?? handleIn), moved: false };
    return;
  }
  if (rim !== undefined) {
    drag = { type: 'rim', index: Number(rim), moved: false };
    return;
  }
  const i = Number(index);
  if (evt.ctrlKey || evt.metaKey) {
    // Ctrl-click (Cmd-click) removes the point.
    removePoint(i);
    swallowNextClick();
    return;
  }
  if (evt.shiftKey) {
    toggleSelected(i);
    swallowNextClick();
    return;
  }
  // A press on a point of the selection drags the whole selection; on another point, that one.
  if (!selectedIndices().includes(i)) selectOnly(i);
  else state.selected = i;
  const moving = selectedIndices();
  drag = {
    type: 'point', index: i, moved: false, from: toWorld(evt),
    orig: new Map(moving.map((j) => [j, [...state.points[j]]])),
  };
  drag.toWorld = el.world.getScreenCTM().inverse();
  renderPoints();
  renderSelection();
});

window.addEventListener('pointermove', (evt) => {
  if (!drag || drag.type === 'select') return;
  if (drag.type === 'press' || drag.type === 'pan') {
    const dx = evt.clientX - drag.start[0], dy = evt.clientY - drag.start[1];
    if (drag.type === 'press' && Math.hypot(dx, dy) < DRAG_SLOP_PX) return;
    drag.type = 'pan';
    // Screen pixels to user units with the transform at the start of the drag.
    setView({ x: drag.view.x - dx / drag.ctm.a, y: drag.view.y - dy / drag.ctm.d, w: drag.view.w });
    return;
  }
  const q = toWorld(evt);
  if (drag.type === 'box') {
    drag.to = q;
    renderBox();
    return;
  }
  if (!drag.moved) pushHistory(); // one undo step per drag
  drag.moved = true;
  const i = drag.index;
  const [x, y] = state.points[i];
  const far = Math.hypot(q[0] - x, q[1] - y) > 1e-9 * unit();
  if (drag.type === 'handle') {
    if (far) state.tangents[i] = [q[0] - x, q[1] - y];
  } else if (drag.type === 'handle-in') {
    // The incoming arrow is drawn backwards: its direction is from the tip to the node.
    if (far) {
      state.inArrows[i] = [x - q[0], y - q[1]];
      if (state.states[i][1] === 'clamped') state.corners[i] = 0; // two arrows say the angle
    }
  } else if (drag.type === 'rim') {
    state.radii[i] = Math.hypot(q[0] - x, q[1] - y);
  } else {
    // The grabbed point follows the pointer (snapped), the rest of the selection with it.
    const o = drag.orig.get(i);
    const target = snapPoint([o[0] + q[0] - drag.from[0], o[1] + q[1] - drag.from[1]], new Set(drag.orig.keys()));
    const d = [target[0] - o[0], target[1] - o[1]];
    for (const [j, p] of drag.orig) state.points[j] = [p[0] + d[0], p[1] + d[1]];
  }
  changed();
});

window.addEventListener('pointerup', (evt) => {
  if (!drag) return;
  if (drag.type === 'box') {
    // The points inside the box join the selection (a Shift-drag: the selection is kept).
    const to = drag.to ?? drag.from;
    const [x0, x1] = [Math.min(drag.from[0], to[0]), Math.max(drag.from[0], to[0])];
    const [y0, y1] = [Math.min(drag.from[1], to[1]), Math.max(drag.from[1], to[1])];
    const inside = state.points.map((p, i) => (p[0] >= x0 && p[0] <= x1 && p[1] >= y0 && p[1] <= y1 ? i : -1)).filter((i) => i >= 0);
    if (inside.length) selectMany(inside, true);
    drag = null;
    renderBox();
    swallowNextClick();
    return;
  }
  // The click that ends a drag, a pan or a press on a point never adds a point.
  if (drag.type !== 'press') swallowNextClick();
  drag = null;
});

// The hash held back during the drag (saveHashSoon).
window.addEventListener('pointerup', () => {
  if (hashDeferred && !drag) { hashDeferred = false; saveHash(); }
});

el.canvas.addEventListener('click', (evt) => {
  const d = evt.target.dataset ?? {};
  if (suppressClick || d.index !== undefined || d.handle !== undefined || d.handleIn !== undefined || d.rim !== undefined) return;
  if (d.curve !== undefined && !evt.shiftKey && !evt.altKey) return;
  if (evt.button !== 0 || evt.shiftKey) return;
  const q = toWorld(evt);
  if (evt.altKey) { insertOnCurve(q); return; }
  insertPoint(state.points.length, snapPoint(q));
});

/** The rubber band of a Shift-drag on the background. */
function renderBox() {
  el.layerBox.replaceChildren();
  if (drag?.type !== 'box' || !drag.to) return;
  const [a, b] = [drag.from, drag.to];
  el.layerBox.append(svg('rect', {
    x: Math.min(a[0], b[0]), y: Math.min(a[1], b[1]), width: Math.abs(a[0] - b[0]), height: Math.abs(a[1] - b[1]),
    'data-testid': 'select-box',
  }));
}

// ---------- snapping ----------

const SNAP_PX = 8;   // a point snaps to another within this many screen pixels
const GRID_PX = 20;  // the grid step is the first 1, 2, 5 × 10^k at least this many pixels of the default view

/** World units per screen pixel. */
function pixelWorld() {
  const a = Math.abs(el.world.getScreenCTM()?.a ?? 0);
  return a > 0 ? 1 / a : unit();
}

/** The grid step: 1, 2 or 5 × 10^k world units, the first at least GRID_PX of the default view
 * (20 units at zoom 1×, 2 at 10×). */
function gridStep() {
  const v = GRID_PX * unit();
  const p = 10 ** Math.floor(Math.log10(v));
  return [1, 2, 5, 10].map((m) => m * p).find((s) => s >= v * (1 - 1e-12));
}

/**
 * With snapping on: q moved onto a point (of any visible curve, but not those in `exclude` of
 * the selected one) within SNAP_PX screen pixels, else onto the nearest grid node.
 */
function snapPoint(q, exclude = new Set()) {
  if (!state.snap) return q;
  const reach = SNAP_PX * pixelWorld();
  let best = null, bestD = reach;
  const consider = (p) => {
    const d = Math.hypot(p[0] - q[0], p[1] - q[1]);
    if (d <= bestD) { best = p; bestD = d; }
  };
  state.points.forEach((p, i) => { if (!exclude.has(i)) consider(p); });
  doc.curves.forEach((c, i) => { if (i !== doc.selected && c.visible) c.points.forEach(consider); });
  if (best) return [best[0], best[1]];
  const g = gridStep();
  return [Math.round(q[0] / g) * g, Math.round(q[1] / g) * g];
}

/** The grid, drawn while snapping is on, over the visible area. */
function renderGrid() {
  el.layerGrid.replaceChildren();
  el.snapLabel.textContent = state.snap ? `(grid ${fmt(gridStep())})` : '';
  if (!state.snap) return;
  const g = gridStep();
  const v = visibleRect();
  const [wx0, wx1] = [v.x0, v.x1];
  const [wy0, wy1] = [FRAME_H - v.y1, FRAME_H - v.y0];
  if ((wx1 - wx0) / g > 400 || (wy1 - wy0) / g > 400) return;
  for (let x = Math.ceil(wx0 / g) * g; x <= wx1; x += g) el.layerGrid.append(svg('line', { x1: x, y1: wy0, x2: x, y2: wy1 }));
  for (let y = Math.ceil(wy0 / g) * g; y <= wy1; y += g) el.layerGrid.append(svg('line', { x1: wx0, y1: y, x2: wx1, y2: y }));
}

el.canvas.addEventListener('wheel', (evt) => {
  evt.preventDefault();
  const delta = evt.deltaMode === 1 ? evt.deltaY * 16 : evt.deltaY;
  zoomAbout(Math.exp(-delta * 0.0015), toUser(evt.clientX, evt.clientY));
}, { passive: false });

/**
 * Alt-click: inserts a point into the span of the main curve nearest to q (segment s runs from
 * the fit's point s to s + 1; points the method inserted are not the editor's); without a fit
 * of the current points, into the nearest chord of the polygon.
 */
function insertOnCurve(q) {
  const n = state.points.length;
  if (n < 2) return;
  let at;
  if (fitIndexOf(0) >= 0 && mainFit.segments.length) {
    const s = nearestSegment(mainFit.segments, q);
    const inserted = new Set(mainFit.method_report?.inserted ?? []);
    at = 0;
    for (let k = 0; k <= s; k++) if (!inserted.has(k)) at += 1;
  } else {
    let best = Infinity;
    const chords = state.closed ? n : n - 1;
    for (let i = 0; i < chords; i++) {
      const a = state.points[i], b = state.points[(i + 1) % n];
      const d = [b[0] - a[0], b[1] - a[1]];
      const t = Math.min(1, Math.max(0, ((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / (d[0] ** 2 + d[1] ** 2 || 1)));
      const dist = Math.hypot(a[0] + t * d[0] - q[0], a[1] + t * d[1] - q[1]);
      if (dist < best) { best = dist; at = i + 1; }
    }
  }
  insertPoint(Math.min(at, n), q);
}

/** Controls that use letters, digits, Backspace and Ctrl+Z themselves; buttons, check boxes and
 * radio buttons use none of the shortcuts' keys. */
function typesText(target) {
  if (target instanceof HTMLInputElement) return !['checkbox', 'radio', 'button', 'submit', 'reset', 'file', 'range', 'color'].includes(target.type);
  return target instanceof HTMLSelectElement || target instanceof HTMLTextAreaElement || !!target?.isContentEditable;
}

window.addEventListener('keydown', (evt) => {
  const key = evt.key.toLowerCase();
  // Ctrl+S saves the project from anywhere (no field uses it; the browser's own "save page"
  // would save the page, not the curves).
  if ((evt.ctrlKey || evt.metaKey) && !evt.shiftKey && !evt.altKey && key === 's') {
    evt.preventDefault();
    saveProject();
    return;
  }
  if (!el.help.hidden) {
    // The help overlay takes Esc (and ?) only; its Close button keeps Tab and Enter.
    if (evt.key === 'Escape' || evt.key === '?') { evt.preventDefault(); showHelp(false); }
    return;
  }
  if (!pointerOnCanvas && typesText(evt.target)) return;
  // Arrows, Enter and Ctrl+A are also a radio group's, a button's and a field's keys: they act
  // on the points only while the canvas has the focus.
  const onCanvas = evt.target === el.canvas || evt.target === document.body;
  if ((evt.ctrlKey || evt.metaKey) && (key === 'z' || key === 'y')) {
    evt.preventDefault();
    if (key === 'y' || evt.shiftKey) redo(); else undo();
    return;
  }
  if ((evt.ctrlKey || evt.metaKey) && !evt.altKey && key === 'a' && onCanvas) {
    evt.preventDefault();
    selectMany(state.points.map((_, i) => i));
    return;
  }
  if (evt.ctrlKey || evt.metaKey || evt.altKey) return;
  const targets = selectedIndices();
  const ARROWS = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] };
  if ((evt.key === 'Delete' || evt.key === 'Backspace') && targets.length) {
    removePoints(targets);
  } else if (ARROWS[evt.key] && onCanvas && targets.length) {
    const step = (evt.shiftKey ? 10 : 1) * pixelWorld();
    movePoints(targets, ARROWS[evt.key].map((v) => v * step), 'nudge');
  } else if (evt.key === 'Escape') {
    selectOnly(-1);
    renderPoints();
    renderSelection();
  } else if (key === 'k' && targets.length) {
    const kind = kindOf(state.selected);
    setKind(targets, KINDS[(KINDS.indexOf(kind) + 1) % KINDS.length]);
  } else if ((key === 'i' || key === 'o') && targets.length) {
    const k = key === 'i' ? 0 : 1;
    setSide(targets, key === 'i' ? 'in' : 'out', nextSide(state.states[state.selected][k]));
  } else if ((key === 'n' || key === 'p') && state.points.length) {
    // The next / previous point (Shift: added to the selection).
    const n = state.points.length;
    const from = state.selected;
    const j = from < 0 ? (key === 'n' ? 0 : n - 1) : (from + (key === 'n' ? 1 : n - 1)) % n;
    if (evt.shiftKey) selectMany([j], true);
    else { selectOnly(j); renderPoints(); renderSelection(); }
  } else if (evt.key === 'Enter' && onCanvas) {
    insertAfterSelected();
  } else if (key === 'c' && !evt.shiftKey) {
    setClosed(!state.closed);
  } else if (key === 'g' && !evt.shiftKey) {
    setSnap(!state.snap);
  } else if (evt.key === '?') {
    showHelp(true);
  } else if (evt.key === '+' || evt.key === '=') {
    zoomCenter(1.25);
  } else if (evt.key === '-') {
    zoomCenter(0.8);
  } else if (key === 'f') {
    fitView(evt.shiftKey); // Shift+F: every visible curve of the document
  } else if (evt.key === '[' || evt.key === ']') {
    selectCurve(doc.selected + (evt.key === '[' ? -1 : 1)); // the previous / next curve
  } else {
    return;
  }
  evt.preventDefault(); // the key was the canvas's, not a control's
});

/** Moves the points by d (world units); `group`: consecutive moves of that kind (nudges) make
 * one undo step until another action. */
function movePoints(indices, [dx, dy], group = null) {
  if (!indices.length) return;
  pushHistory(group);
  for (const i of indices) state.points[i] = [state.points[i][0] + dx, state.points[i][1] + dy];
  changed();
}

/**
 * Enter: a new point after the selected one (none selected: after the last), in the middle of
 * the curve's span to the next point (the chord's middle without a fit); after the last point of
 * an open curve, one chord further on; the first point in the middle of the view.
 */
function insertAfterSelected() {
  const n = state.points.length;
  const i = state.selected >= 0 ? state.selected : n - 1;
  let q;
  if (n === 0) {
    const v = visibleRect();
    q = [(v.x0 + v.x1) / 2, FRAME_H - (v.y0 + v.y1) / 2];
  } else if (i < n - 1 || (state.closed && n >= 2)) {
    const a = state.points[i], b = state.points[(i + 1) % n];
    q = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
    const k = fitIndexOf(i);
    const segs = k >= 0 ? mainFit.segments.filter((s) => s.span === k) : [];
    if (segs.length) q = segs.length % 2 ? pointAt(segs[(segs.length - 1) / 2].bezier, 0.5) : [...segs[segs.length / 2].bezier[0]];
  } else {
    const a = state.points[i];
    const prev = n >= 2 ? state.points[i - 1] : [a[0] - 50 * pixelWorld(), a[1]];
    q = [2 * a[0] - prev[0], 2 * a[1] - prev[1]];
  }
  insertPoint(i + 1, q);
}

function setClosed(closed) {
  if (closed === state.closed || el.closed.disabled) return;
  pushHistory();
  state.closed = closed;
  el.closed.checked = closed;
  changed();
}

/** Snapping on or off (a display setting, like the comb: not an undo step). */
function setSnap(on) {
  state.snap = on;
  el.snap.checked = on;
  renderGrid();
  saveHash();
}

// ---------- transforms of the selection (or of the whole curve) ----------

/**
 * Curve Ensemble's tools, about the centroid of the points transformed (the selection, or every
 * point when none is selected); one undo step each. The arrows turn, scale and mirror with the
 * points, data-ball radii scale by |factor|, and a reflection turns corner angles the other way.
 */
function transformPoints(op, value = null) {
  const chosen = selectedIndices();
  const idx = chosen.length ? chosen : state.points.map((_, i) => i);
  if (!idx.length) return;
  if ((op === 'rotate' || op === 'scale') && !Number.isFinite(value)) return;
  if (op === 'scale' && value === 0) return;
  const cx = idx.reduce((s, i) => s + state.points[i][0], 0) / idx.length;
  const cy = idx.reduce((s, i) => s + state.points[i][1], 0) / idx.length;
  const vec = {
    translate: (v) => v,
    rotate: (v) => rotateVec(v, value),
    scale: (v) => [v[0] * value, v[1] * value],
    'reflect-x': ([x, y]) => [-x, y],
    'reflect-y': ([x, y]) => [x, -y],
  }[op];
  pushHistory();
  for (const i of idx) {
    const [x, y] = state.points[i];
    if (op === 'translate') {
      state.points[i] = [x + value[0], y + value[1]];
      continue;
    }
    const d = vec([x - cx, y - cy]);
    state.points[i] = [cx + d[0], cy + d[1]];
    if (state.tangents[i]) state.tangents[i] = vec(state.tangents[i]);
    if (state.inArrows[i]) state.inArrows[i] = vec(state.inArrows[i]);
    if (op === 'scale') state.radii[i] *= Math.abs(value);
    if (op.startsWith('reflect') && state.corners[i] !== 0) state.corners[i] = -state.corners[i];
  }
  forgetErrorIndex();
  changed();
}

// ---------- help overlay and the empty canvas ----------

let helpReturn = null; // the element that had the focus before the overlay opened

function showHelp(open) {
  if (open === !el.help.hidden) return;
  if (open) {
    helpReturn = document.activeElement;
    el.help.hidden = false;
    $('help-close').focus();
  } else {
    el.help.hidden = true;
    (helpReturn && helpReturn !== document.body ? helpReturn : el.canvas).focus({ preventScroll: true });
  }
}

// The example of examples/li-example1.csv.
const EXAMPLE_POINTS = [[1, 90], [3, 105], [6, 120], [10, 100], [12, 85], [15, 104], [17, 80]];

/** "Load example": the example's points in the selected curve (one undo step), framed, and the
 * focus on the canvas so that the keys go on working on it. */
function loadExample() {
  pushHistory();
  replacePoints(EXAMPLE_POINTS.map(([x, y]) => [x, y]));
  fitView();
  el.canvas.focus({ preventScroll: true });
}

/** The hint on an empty canvas. */
function renderEmptyHint() {
  el.emptyHint.hidden = state.points.length > 0;
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

/**
 * A standalone SVG of what the canvas shows, y axis up like the editor: with the scope
 * "document", the other visible curves of the document in their colours (in the list's order,
 * the first at the bottom), then the selected curve (unless hidden) with its ensemble, control
 * polygon and comb when they are shown, and its points unless "points" is unticked. The view
 * box holds everything drawn: points, control polygons (which bound the curves) and comb teeth.
 */
function exportSvgText() {
  const xs = [], ys = [];
  const addPt = ([x, y]) => { xs.push(x); ys.push(y); };
  const whole = el.exportScope.value === 'document';
  const mainShown = !whole || selectedCurve().visible;
  const points = mainShown && el.exportPoints.checked ? state.points : [];
  points.forEach(addPt);
  const curves = [];
  if (whole) {
    doc.curves.forEach((c, i) => {
      const fit = otherFits.get(c.id)?.fit;
      if (i !== doc.selected && c.visible && fit) curves.push({ fit, color: c.color, width: 1.6, name: c.name });
    });
  }
  // The last good curve of an earlier state is not this document's curve.
  if (mainShown && mainFit && !mainStale) curves.push({ fit: mainFit, color: '#1d2330', width: 2.5, name: selectedCurve().name });
  if (mainShown) for (const r of ensembleRows()) if (r.result.fit) curves.push({ fit: r.result.fit, color: r.color, width: 1.6 });
  for (const c of curves) for (const s of c.fit.segments) s.bezier.forEach(addPt);
  const shown = (on, layer) => (mainShown && on && !mainStale ? [...layer.children] : []);
  const comb = mainShown && state.comb && !mainStale ? combTeeth : [];
  const polygon = shown(state.polygon, el.layerControl).filter((node) => node.tagName === 'polyline');
  for (const [x1, y1, x2, y2] of comb) {
    addPt([x1, y1]);
    addPt([x2, y2]);
  }
  if (!xs.length) { addPt([0, 0]); addPt([FRAME_W, FRAME_H]); }
  const x0 = Math.min(...xs), x1 = Math.max(...xs);
  const y0 = Math.min(...ys), y1 = Math.max(...ys);
  const pad = 0.03 * Math.max(x1 - x0, y1 - y0, 1e-300);
  const w = x1 - x0 + 2 * pad, h = y1 - y0 + 2 * pad;
  const px = 800 / Math.max(w, h); // the larger side is 800 px
  const lines = [
    `<svg xmlns="http://www.w3.org/2000/svg" viewBox="${x0 - pad} ${-(y1 + pad)} ${w} ${h}" width="${Math.round(w * px)}" height="${Math.round(h * px)}">`,
    `<g transform="scale(1,-1)" fill="none">`,
  ];
  const stroke = (width) => `stroke-width="${width}" vector-effect="non-scaling-stroke"`;
  const escape = (t) => t.replace(/&/g, '&amp;').replace(/"/g, '&quot;').replace(/</g, '&lt;');
  for (const c of curves) {
    const name = c.name == null ? '' : ` data-curve="${escape(c.name)}"`;
    lines.push(`<path d="${pathData(c.fit.segments)}" stroke="${c.color}" ${stroke(c.width)} data-method="${c.fit.method}"${name}/>`);
  }
  for (const node of polygon) lines.push(`<polyline points="${node.getAttribute('points')}" stroke="#98a2b3" stroke-dasharray="4 3" ${stroke(1)}/>`);
  for (const [x1, y1, x2, y2] of comb) lines.push(`<line x1="${x1}" y1="${y1}" x2="${x2}" y2="${y2}" stroke="${COMB_COLOR}" ${stroke(0.8)}/>`);
  for (const [x, y] of points) lines.push(`<circle cx="${x}" cy="${y}" r="${4 / px}" fill="#fff" stroke="#1d4ed8" ${stroke(1.5)}/>`);
  lines.push('</g>', '</svg>', '');
  return lines.join('\n');
}

/** A file name from a curve's or the document's name. */
const fileStem = () => (el.exportScope.value === 'document' && doc.curves.length > 1 ? 'fairspline-document'
  : `fairspline-${selectedCurve().name.replace(/[^\w.-]+/g, '-')}`);

$('export-svg').addEventListener('click', () => {
  const text = exportSvgText();
  el.svgText.value = text;
  download(`${fileStem()}.svg`, text, 'image/svg+xml');
});

/** The SVG export drawn on a canvas at `scale` times its size (on white), as a PNG blob. */
async function exportPngBlob(scale) {
  const text = exportSvgText();
  const url = URL.createObjectURL(new Blob([text], { type: 'image/svg+xml' }));
  try {
    const img = new Image();
    img.src = url;
    await img.decode();
    const canvas = document.createElement('canvas');
    canvas.width = Math.max(1, Math.round(img.naturalWidth * scale));
    canvas.height = Math.max(1, Math.round(img.naturalHeight * scale));
    const ctx = canvas.getContext('2d');
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.drawImage(img, 0, 0, canvas.width, canvas.height);
    return await new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
  } finally {
    URL.revokeObjectURL(url);
  }
}

$('export-png').addEventListener('click', async () => {
  const v = Number(el.pngScale.value);
  const scale = Number.isFinite(v) && v > 0 ? Math.min(v, 16) : 1;
  const blob = await exportPngBlob(scale);
  if (blob) download(`${fileStem()}.png`, blob, 'image/png');
});

// ---------- project files ----------

/**
 * The project file (docs/editor.md, "Project files"): every curve's data as the editor holds
 * them (the arrows, not the derivatives sent: 3·arrow/Δt would not convert back bit for bit),
 * the selected index, the view and the display settings. JSON.stringify writes each double so
 * that JSON.parse gives it back exactly, so open → save writes the same text.
 */
function projectText() {
  storeSelected();
  // Version 1 as long as every node is a kind (older editors read it); the node model needs 2.
  const nodes = doc.curves.some(usesNodeModel);
  const curves = doc.curves.map((c) => ({
    name: c.name, visible: c.visible, color: c.color, method: c.method, options: c.options,
    alpha: c.alpha, closed: c.closed, points: c.points,
    ...(nodes ? { states: c.states.map(stateText), arrows: c.tangents, in_arrows: c.inArrows, corners_deg: c.corners }
      : { kinds: c.states.map((_, i) => kindOf(i, c)), arrows: c.tangents }),
    radii: c.radii,
  }));
  const project = {
    format: PROJECT_FORMAT, version: nodes ? PROJECT_VERSION : 1, selected: doc.selected, curves,
    view: { x: state.view.x, y: state.view.y, w: state.view.w },
    display: {
      ensemble: state.ensemble.map(entryToProject), comb: state.comb, polygon: state.polygon, plot: state.plot,
      ...(state.combAll ? { combAll: true } : {}),
      ...(state.snap ? { snap: true } : {}),
    },
  };
  return `${JSON.stringify(project, null, 1)}\n`;
}

function saveProject() {
  const text = projectText();
  el.projectText.value = text;
  download('fairspline-project.json', text, 'application/json');
}

$('save-project').addEventListener('click', saveProject);

/** `parse(text)`, or null with its error shown as the import's (naming `source`). */
function parsedOrShown(parse, text, source) {
  try {
    return parse(text);
  } catch (e) {
    importError = `${source}: ${e.message}`;
    renderError();
    return null;
  }
}

/** Replaces the document by a project file's (one undo step); a bad file changes nothing. */
function openProject(text, source) {
  const project = parsedOrShown(parseProject, text, source);
  if (!project) return;
  pushHistory();
  doc.curves = [];
  for (const c of project.curves) doc.curves.push({ ...c, id: nextCurveId++, color: c.color ?? freeColor() });
  doc.selected = project.selected;
  otherFits.clear();
  if (project.display) {
    state.ensemble = entriesFrom(project.display.ensemble);
    const { comb, combAll, polygon, plot, snap } = project.display;
    Object.assign(state, { comb, combAll, polygon, plot, snap });
    syncControls();
    buildEnsemble();
  }
  loadSelected();
  render();
  if (project.view) setView(project.view);
  else fitView();
  changed();
}

/**
 * The JSON export: the fit of the main curve as `fairspline fit` writes it, whose "request"
 * (points where they differ from the result's, closed, alpha, kinds, tangents only where given,
 * radii) and "method"/"options" are what Import reads back. Without a fit of the current data
 * (an error), the same fields with the error instead of the curve.
 */
function exportJsonText() {
  if (mainFit && !mainStale) return JSON.stringify(mainFit, null, 2);
  const { method, options, ...request } = requestBody(state.method, state.options);
  return JSON.stringify({ method, options: options ?? {}, request, error: mainError }, null, 2);
}

$('export-json').addEventListener('click', () => {
  const text = exportJsonText();
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

/** The options that differ from the method's defaults (a result lists every option it used). */
function withoutDefaults(method, options) {
  const specs = new Map((methodInfo(method)?.options ?? []).map((o) => [o.name, o]));
  return Object.fromEntries(Object.entries(options).filter(([name, v]) =>
    !specs.has(name) || JSON.stringify(specs.get(name).default) !== JSON.stringify(v)));
}

/**
 * Opens text pasted or from a file: a project file replaces the document; a curve (CSV, a JSON
 * request or result of `fairspline fit`, a Curve Ensemble file) goes into the selected curve if
 * it has no points yet, else into a new curve after it, named after the file. An error leaves
 * everything as it was. One undo step either way.
 */
function importText(text, source) {
  if (isProject(text)) { openProject(text, source); return; }
  const parsed = parsedOrShown(parseImport, text, source);
  if (!parsed) return;
  pushHistory();
  const name = source === 'pasted text' ? null : source.replace(/\.[^.]*$/, '');
  if (state.points.length) {
    storeSelected();
    cacheSelectedFit();
    doc.curves.splice(doc.selected + 1, 0, newRecord(state, name));
    doc.selected += 1;
    loadSelected(); // the new curve has the settings of the one it follows
  } else if (name && /^curve \d+$/.test(selectedCurve().name)) {
    selectedCurve().name = name;
  }
  if (parsed.closed != null) { state.closed = parsed.closed; el.closed.checked = state.closed; }
  if (parsed.alpha != null) { state.alpha = parsed.alpha; syncAlphaControl(); }
  if (parsed.method && methodInfo(parsed.method)) {
    state.method = parsed.method;
    state.options = withoutDefaults(state.method, parsed.options ?? {});
    el.method.value = state.method;
    buildOptionsForm();
  }
  const states = parsed.states ?? parsed.kinds?.map(kindStates);
  replacePoints(parsed.points, states, parsed.radii);
  // A file gives tangents (derivatives); the editor keeps arrows (see knotSpan). A Curve
  // Ensemble file gives directions, made arrows by the parser. With the node model, `tangents`
  // set both sides and `in_tangents` / `out_tangents` one.
  const n = parsed.points.length;
  const given = (list, i) => (list?.[i] ? tangentToArrow(list[i], i) : null);
  for (let i = 0; i < n; i++) {
    const [a, b] = state.states[i];
    const both = parsed.arrows?.[i] ?? given(parsed.tangents, i);
    if (b === 'clamped') state.tangents[i] = given(parsed.outTangents, i) ?? both;
    if (a === 'clamped') {
      const inn = parsed.inArrows?.[i] ?? given(parsed.inTangents, i);
      // One arrow for both clamped sides unless the file gives the incoming one apart.
      state.inArrows[i] = b === 'clamped' && !inn ? null : inn ?? both;
    }
  }
  if (parsed.corners) state.corners = [...parsed.corners];
  for (let i = 0; i < n; i++) if (state.inArrows[i] && state.states[i][1] === 'clamped') state.corners[i] = 0;
  renderCurvesPanel();
  fitView();
}

$('import').addEventListener('click', () => importText(el.importText.value, 'pasted text'));

el.importFile.addEventListener('change', async () => {
  for (const file of el.importFile.files ?? []) {
    if (file.size > 8 << 20) {
      importError = `${file.name}: larger than 8 MB`;
      renderError();
    } else {
      importText(await file.text(), file.name);
    }
  }
  el.importFile.value = ''; // the same file can be chosen again
});

// Dropping a file on the canvas imports it too.
el.canvas.addEventListener('dragover', (evt) => evt.preventDefault());
el.canvas.addEventListener('drop', async (evt) => {
  evt.preventDefault();
  // Several files: each is opened in turn (several curves each go into a curve of their own).
  for (const file of evt.dataTransfer?.files ?? []) importText(await file.text(), file.name);
});

el.undo.addEventListener('click', undo);
el.redo.addEventListener('click', redo);

/** Replaces all points and forgets every fit of the old ones. */
function replacePoints(points, states = null, radii = null) {
  const n = points.length;
  state.points = points;
  state.states = states ?? Array.from({ length: n }, () => ['regular', 'regular']);
  state.tangents = Array(n).fill(null);
  state.inArrows = Array(n).fill(null);
  state.corners = Array(n).fill(0);
  state.radii = radii ?? Array(n).fill(0);
  selectOnly(-1);
  mainFit = null;
  mainStale = false;
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

/** Switches the main method (its options back to their defaults); one undo step. The last
 * good curve stays on screen, dimmed, until the new method's fit arrives. */
function setMethod(name) {
  if (name === state.method) return;
  pushHistory();
  mainStale = mainFit != null; // arrows and insertions must not read the old method's curve
  state.method = name;
  state.options = {};
  el.method.value = name;
  buildOptionsForm();
  changed();
}

el.method.addEventListener('change', () => setMethod(el.method.value));
el.closed.addEventListener('change', () => {
  // The box shows the new value already; state.closed still holds the old one.
  pushHistory();
  state.closed = el.closed.checked;
  changed();
});
function setAlpha(v, typing = false) {
  if (v === state.alpha) return;
  pushHistory(typing ? 'alpha' : null);
  state.alpha = v;
  changed();
}
el.alpha.addEventListener('change', () => {
  el.alphaNumber.disabled = el.alpha.value !== '#number';
  const v = Number(el.alpha.value === '#number' ? el.alphaNumber.value : el.alpha.value);
  if (Number.isFinite(v)) { el.alphaNumber.value = v; setAlpha(v); }
});
el.alphaNumber.addEventListener('input', () => {
  const v = Number(el.alphaNumber.value);
  el.alphaNumber.classList.toggle('invalid', !Number.isFinite(v) || el.alphaNumber.value.trim() === '');
  if (Number.isFinite(v) && el.alphaNumber.value.trim() !== '') setAlpha(v, true);
});
el.alphaNumber.addEventListener('change', endHistoryGroup);
el.kindBox.addEventListener('change', (evt) => {
  if (evt.target.name === 'kind') setKind(editTargets(), evt.target.value);
});

/** The number typed in a panel field, or null (the field marked invalid) when it is not one or
 * `ok` refuses it. */
function typedNumber(input, ok = () => true) {
  const v = Number(input.value);
  const good = input.value.trim() !== '' && Number.isFinite(v) && ok(v);
  input.classList.toggle('invalid', !good);
  return good ? v : null;
}

// The radius, the sides and the corner apply to every selected point; x, y and the direction
// to the one the panel shows. Each change is one undo step.
el.radius.addEventListener('change', () => {
  const v = typedNumber(el.radius, (r) => r >= 0);
  const todo = editTargets().filter((i) => state.radii[i] !== v);
  if (v == null || !todo.length) return;
  pushHistory();
  for (const i of todo) state.radii[i] = v;
  changed();
});
for (const [input, k] of [[el.nodeX, 0], [el.nodeY, 1]]) {
  input.addEventListener('change', () => {
    const i = state.selected;
    const v = typedNumber(input);
    if (v == null || i < 0 || i >= state.points.length || state.points[i][k] === v) return;
    pushHistory();
    state.points[i] = k === 0 ? [v, state.points[i][1]] : [state.points[i][0], v];
    changed();
  });
}
el.stateIn.addEventListener('change', () => setSide(editTargets(), 'in', el.stateIn.value));
el.stateOut.addEventListener('change', () => setSide(editTargets(), 'out', el.stateOut.value));
el.nodeDir.addEventListener('change', () => {
  // Turns the point's arrow (the outgoing one, else the incoming one) to the typed direction.
  const i = state.selected;
  const v = typedNumber(el.nodeDir);
  if (v == null || i < 0 || i >= state.points.length) return;
  const key = state.tangents[i] ? 'tangents' : state.inArrows[i] ? 'inArrows' : null;
  if (!key) return;
  const a = state[key][i];
  const len = Math.hypot(...a);
  const r = (v * Math.PI) / 180;
  pushHistory();
  state[key][i] = [len * Math.cos(r), len * Math.sin(r)];
  changed();
});
el.nodeCorner.addEventListener('change', () => {
  // The corner angle kept by a regular node ("respect corner"), strictly inside ±180°. At a node
  // clamped on both sides it turns the incoming arrow: that one follows the outgoing one.
  const v = typedNumber(el.nodeCorner, (d) => d > -180 && d < 180);
  const todo = editTargets().filter((i) => !state.states[i].includes('free'));
  if (v == null || !todo.length) return;
  pushHistory();
  for (const i of todo) {
    state.corners[i] = v;
    if (state.states[i][1] === 'clamped') state.inArrows[i] = null;
  }
  changed();
});
el.snap.addEventListener('change', () => setSnap(el.snap.checked));
$('help-open').addEventListener('click', () => showHelp(true));
$('help-close').addEventListener('click', () => showHelp(false));
$('load-example').addEventListener('click', loadExample);
$('tf-translate').addEventListener('click', () => {
  const dx = typedNumber($('tf-dx')), dy = typedNumber($('tf-dy'));
  if (dx != null && dy != null) transformPoints('translate', [dx, dy]);
});
$('tf-rotate').addEventListener('click', () => transformPoints('rotate', typedNumber($('tf-angle'))));
$('tf-scale').addEventListener('click', () => transformPoints('scale', typedNumber($('tf-factor'), (f) => f !== 0)));
$('tf-reflect-x').addEventListener('click', () => transformPoints('reflect-x'));
$('tf-reflect-y').addEventListener('click', () => transformPoints('reflect-y'));
el.polygon.addEventListener('change', () => { state.polygon = el.polygon.checked; renderControlPolygon(); saveHash(); });
el.comb.addEventListener('change', () => { state.comb = el.comb.checked; renderComb(); saveHash(); });
el.reportPanel.addEventListener('toggle', renderReportPanel);
el.combAll.addEventListener('change', () => { state.combAll = el.combAll.checked; renderOtherCombs(); saveHash(); });
el.entryMethod.addEventListener('change', buildEntryForm);
$('entry-add').addEventListener('click', () => addEntries([draftEntry()]));
$('preset-fig7').addEventListener('click', () => addEntries(FIG7_PRESET.map((e) => makeEntry(e.method, e.options, e.alpha))));
el.plotToggle.addEventListener('change', () => { state.plot = el.plotToggle.checked; renderPlot(); saveHash(); });
$('zoom-in').addEventListener('click', () => zoomCenter(1.25));
$('zoom-out').addEventListener('click', () => zoomCenter(0.8));
$('zoom-fit').addEventListener('click', () => fitView());
$('zoom-fit-all').addEventListener('click', () => fitView(true));
el.errorHint.addEventListener('click', applyHint);
el.errorShow.addEventListener('click', () => {
  const p = state.points[mainError?.index ?? -1];
  if (p) { centerOn(p); renderError(); }
});

/** The panel's controls show the state (after loading it from the hash). */
function syncControls() {
  el.closed.checked = state.closed;
  el.comb.checked = state.comb;
  el.combAll.checked = state.combAll;
  el.snap.checked = state.snap;
  el.polygon.checked = state.polygon;
  el.plotToggle.checked = state.plot;
  syncAlphaControl();
  updateHistoryButtons();
}

// Editing the address (or going back to an earlier one) opens the state it holds, as one undo
// step. The editor's own updates use history.replaceState, which fires no hashchange.
window.addEventListener('hashchange', () => {
  if (!schema.methods.length) return; // start() reads the hash once the methods are known
  pushHistory();
  loadHash();
  if (!methodInfo(state.method)) { state.method = schema.default; state.options = {}; }
  drag = null;
  renderCurvesPanel();
  mainFit = null;
  mainStale = false;
  mainError = null;
  ensembleFits.clear();
  syncControls();
  el.method.value = state.method;
  buildOptionsForm();
  buildEnsemble();
  applyView();
  render();
  changed();
});

async function start() {
  loadHash();
  syncControls();
  applyView();
  try {
    const res = await fetch('/api/methods');
    schema = await res.json();
    openLive();
  } catch (e) {
    el.errorText.textContent = `cannot load /api/methods: ${e.message}`;
    el.error.hidden = false;
    return;
  }
  if (!methodInfo(state.method)) { state.method = schema.default; state.options = {}; }
  for (const c of doc.curves) c.method ??= schema.default; // read from the hash before the methods were known
  for (const m of methodsInOrder()) {
    el.method.add(new Option(methodLabel(m), m.name));
    $('method-names').append(new Option(m.name));
    el.entryMethod.add(new Option(m.name, m.name));
  }
  buildEntryForm();
  buildTableHead();
  el.method.value = state.method;
  buildOptionsForm();
  buildEnsemble();
  renderCurvesPanel();
  changed();
}

// The curves panel's buttons.
$('curve-new').addEventListener('click', () => addCurve(newRecord()));
$('curve-duplicate').addEventListener('click', duplicateCurve);
$('curve-delete').addEventListener('click', deleteCurve);
$('curve-up').addEventListener('click', () => moveCurve(-1));
$('curve-down').addEventListener('click', () => moveCurve(1));
el.curveName.addEventListener('input', () => renameCurve(el.curveName.value));
el.curveName.addEventListener('change', endHistoryGroup);

start();
