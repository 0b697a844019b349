// Import of points: CSV (x,y per line, optional header, # comments), the JSON request of
// `fairspline fit` ({points, closed, kinds, tangents, radii, alpha, method, options} or a bare
// array), its JSON result (the editor's Export JSON), whose "request" is what was given, and
// Curve Ensemble's text file (docs/curve-ensemble.md). Also the editor's project file
// (parseProject). Throws Error with a sentence that names the line or the field.

const KINDS = ['smooth', 'clamped', 'corner'];
const SIDES = ['regular', 'clamped', 'free'];

/** A node's states, one string for both sides or [in, out], as [in, out]; null if malformed. */
function sidesOf(v) {
  if (SIDES.includes(v)) return [v, v];
  if (Array.isArray(v) && v.length === 2 && v.every((x) => SIDES.includes(x))) return [v[0], v[1]];
  return null;
}

const finitePair = (v) => Array.isArray(v) && v.length === 2 && v.every((x) => typeof x === 'number' && Number.isFinite(x));

function toPoints(list) {
  if (!Array.isArray(list)) throw new Error('"points" must be an array of [x, y]');
  return list.map((p, i) => {
    const xy = Array.isArray(p) ? p.slice(0, 2) : (p && typeof p === 'object' ? [p.x, p.y] : null);
    if (!xy || !finitePair(xy)) throw new Error(`points[${i}] is not a pair of finite numbers`);
    return xy;
  });
}

function fromJson(text) {
  let data;
  try { data = JSON.parse(text); } catch (e) { throw new Error(`invalid JSON: ${e.message}`); }
  if (Array.isArray(data)) return { points: toPoints(data) };
  if (!data || typeof data !== 'object') throw new Error('JSON must be an object or an array');
  if (data.request && typeof data.request === 'object' && !Array.isArray(data.request)) {
    // A result: its top-level points are the curve's (with a tangent fitted at every point);
    // the request holds the input (its points where they differ from those), and the result
    // the method and the options used.
    data = {
      ...data.request,
      points: data.request.points ?? data.points,
      closed: data.request.closed ?? data.closed,
      method: data.method,
      options: data.options,
    };
  }
  const out = { points: toPoints(data.points) };
  const n = out.points.length;
  // A request says what it does not give: an open curve, centripetal knots (the library's
  // defaults), not the editor's current settings.
  out.closed = !!data.closed;
  out.alpha = 0.5;
  if (data.kinds != null) {
    if (!Array.isArray(data.kinds) || data.kinds.length !== n) throw new Error(`"kinds" must list one kind per point (${n})`);
    data.kinds.forEach((k, i) => { if (!KINDS.includes(k)) throw new Error(`kinds[${i}]: expected smooth, clamped or corner, got ${JSON.stringify(k)}`); });
    out.kinds = [...data.kinds];
  }
  if (data.states != null) {
    // The node model (docs/methods/min-energy.md, "Node states").
    if (data.kinds != null) throw new Error('the node kinds are given twice, as "kinds" and as "states"; give one of them');
    if (!Array.isArray(data.states) || data.states.length !== n) throw new Error(`"states" must list one state per point (${n})`);
    out.states = data.states.map((v, i) => {
      const st = sidesOf(v);
      if (!st) throw new Error(`states[${i}]: expected regular, clamped, free or a pair [in, out] of them, got ${JSON.stringify(v)}`);
      return st;
    });
  }
  for (const [key, name] of [['tangents', 'tangents'], ['in_tangents', 'inTangents'], ['out_tangents', 'outTangents']]) {
    if (data[key] == null) continue;
    if (!Array.isArray(data[key]) || data[key].length !== n) throw new Error(`"${key}" must have one entry per point (${n})`);
    data[key].forEach((t, i) => { if (t !== null && !finitePair(t)) throw new Error(`${key}[${i}] is not [x, y] or null`); });
    out[name] = data[key].map((t) => (t ? [...t] : null));
  }
  if (data.corners_deg != null) {
    if (!Array.isArray(data.corners_deg) || data.corners_deg.length !== n) throw new Error(`"corners_deg" must list one angle per point (${n})`);
    data.corners_deg.forEach((v, i) => { if (typeof v !== 'number' || !Number.isFinite(v)) throw new Error(`corners_deg[${i}] is not a number`); });
    out.corners = [...data.corners_deg];
  }
  // Clamped end tangents (the library's start_tangent / end_tangent) are clamped end points here.
  for (const [key, i] of [['start_tangent', 0], ['end_tangent', n - 1]]) {
    if (data[key] == null || (key === 'end_tangent' && data.closed)) continue;
    if (!finitePair(data[key])) throw new Error(`"${key}" is not [x, y]`);
    out.tangents ??= Array(n).fill(null);
    out.tangents[i] = [...data[key]];
    if (out.kinds) out.kinds[i] = 'clamped';
  }
  if (data.radii != null) {
    if (!Array.isArray(data.radii) || data.radii.length !== n) throw new Error(`"radii" must list one radius per point (${n})`);
    data.radii.forEach((r, i) => { if (typeof r !== 'number' || !Number.isFinite(r) || r < 0) throw new Error(`radii[${i}] is not a radius (a number >= 0)`); });
    out.radii = [...data.radii];
  }
  if (data.alpha != null) {
    if (typeof data.alpha !== 'number' || !Number.isFinite(data.alpha)) throw new Error('"alpha" must be a number');
    out.alpha = data.alpha;
  }
  if (typeof data.method === 'string') out.method = data.method;
  if (data.options && typeof data.options === 'object' && !Array.isArray(data.options)) out.options = data.options;
  return out;
}

function fromCsv(text) {
  const points = [];
  text.split(/\r?\n/).forEach((raw, n) => {
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
  return { points };
}

// ---------- Curve Ensemble text files ----------

export const CE_HEADER = '#Curve Ensemble Text File';
const CE = { REGULAR: 0, CLAMPED: 1, FREE_CLAMPED: 3, CLAMPED_FREE: 5, FREE: 7 };

/** The unit vector at `deg` degrees from +x towards +y. */
const direction = (deg) => [Math.cos((deg * Math.PI) / 180), Math.sin((deg * Math.PI) / 180)];

/**
 * A Curve Ensemble text file (its header line, then x y DIR CORNER STATE ENERGY per node, missing
 * columns 0; docs/curve-ensemble.md) as the editor's curve, read as the library reads it
 * (include/fairspline/io/curve_ensemble.hpp): the positions; closedness (open exactly when the
 * first state is 7 or 3 and the last 7 or 5, as Curve Ensemble decides); data balls (state < 0:
 * radius −state; > 100: state − 100; a regular node, its DIR and CORNER not inputs); and every
 * node state with its directions: 0 regular with its CORNER as the corner angle, 1 clamped with
 * the outgoing direction DIR and the incoming DIR − CORNER (two arrows when they differ), 3
 * [free, clamped] with DIR, 5 [clamped, free] with DIR − CORNER, 7 free. A direction becomes an
 * arrow a third of the chord to the neighbour on its side long (the Bézier arm of an even
 * curve), since the file gives a direction only. The energy column is not read. The method is
 * Curve Ensemble's default, restricted-elastic.
 */
function fromCurveEnsemble(text) {
  const rows = [];
  let threeColumns = true;
  text.split(/\r?\n/).forEach((raw, n) => {
    if (raw.startsWith('#') || raw.trim() === '') return;
    const cells = raw.trim().split(/\s+/);
    const nums = cells.slice(0, 6).map(Number);
    // The energy column (6th) may be "inf" (an infeasible piece) and is not read.
    if (!nums.slice(0, 5).every(Number.isFinite) || cells.length < 2) {
      throw new Error(`line ${n + 1}: expected "x y [direction corner state energy]", got "${raw.trim().slice(0, 40)}"`);
    }
    if (cells.length !== 3) threeColumns = false;
    while (nums.length < 6) nums.push(0);
    rows.push(nums);
  });
  const n = rows.length;
  if (!n) return { points: [] };
  const points = rows.map((r) => [r[0], r[1]]);
  // Curve Ensemble's data-ball file: x y r on every line, loaded closed.
  if (threeColumns) return { points, closed: true, radii: rows.map((r) => Math.max(0, r[2])), method: 'restricted-elastic', alpha: 0.5 };
  const state = (r) => r[4];
  const closed = !([CE.FREE, CE.FREE_CLAMPED].includes(state(rows[0])) && [CE.FREE, CE.CLAMPED_FREE].includes(state(rows[n - 1])));
  const radii = rows.map((r) => (state(r) < 0 ? -state(r) : state(r) > 100 ? state(r) - 100 : 0));
  // The chord on a side of node i, over 3: the next node's for the outgoing side, the previous
  // one's for the incoming side (the other neighbour past an open end).
  const chord = (i, j) => (j >= 0 && j < n && j !== i ? Math.hypot(points[j][0] - points[i][0], points[j][1] - points[i][1]) / 3 : 0);
  const next = (i) => (i + 1 < n ? i + 1 : closed ? 0 : i - 1);
  const prev = (i) => (i > 0 ? i - 1 : closed ? n - 1 : i + 1);
  const arrow = (deg, len) => direction(deg).map((v) => v * (len || 1));
  const states = [], arrows = Array(n).fill(null), inArrows = Array(n).fill(null), corners = Array(n).fill(0);
  rows.forEach((r, i) => {
    const [, , dir, corner] = r;
    const s = state(r);
    const outArrow = () => arrow(dir, chord(i, next(i)));
    const inArrow = () => arrow(dir - corner, chord(i, prev(i)));
    if (s === CE.CLAMPED) {
      states.push(['clamped', 'clamped']);
      arrows[i] = outArrow();
      // One arrow for both sides when the directions agree; else the incoming one of its own.
      if (corner !== 0) inArrows[i] = inArrow();
    } else if (s === CE.FREE_CLAMPED) {
      states.push(['free', 'clamped']);
      arrows[i] = outArrow();
    } else if (s === CE.CLAMPED_FREE) {
      states.push(['clamped', 'free']);
      inArrows[i] = inArrow();
    } else if (s === CE.FREE) {
      states.push(['free', 'free']);
    } else {
      // Regular, or a data ball (whose DIR and CORNER say where Curve Ensemble put its node).
      states.push(['regular', 'regular']);
      if (s === CE.REGULAR) corners[i] = corner;
    }
  });
  const out = { points, closed, states, arrows, inArrows, corners, radii, method: 'restricted-elastic', alpha: 0.5 };
  if (!radii.some((r) => r > 0)) delete out.radii;
  return out;
}

/**
 * {points, closed?, kinds?, tangents? (derivatives), arrows? (Bézier arms, Curve Ensemble),
 * radii?, alpha?, method?, options?} from CSV, JSON or Curve Ensemble text.
 */
export function parseImport(text) {
  const trimmed = text.trim();
  if (!trimmed) throw new Error('nothing to import');
  const out = trimmed.startsWith(CE_HEADER) ? fromCurveEnsemble(trimmed)
    : trimmed.startsWith('{') || trimmed.startsWith('[') ? fromJson(trimmed) : fromCsv(trimmed);
  if (!out.points.length) throw new Error('no points found');
  // A tangent makes a point clamped unless its kind (or state) says otherwise.
  if (out.tangents && !out.kinds && !out.states) out.kinds = out.tangents.map((t) => (t ? 'clamped' : 'smooth'));
  if (out.states) {
    // Directions: tangents (both sides), in/out tangents, or a Curve Ensemble file's arrows
    // (outgoing) and inArrows; a node clamped on both sides may give one side's only.
    out.states.forEach(([a, b], i) => {
      const any = out.tangents?.[i];
      const inn = out.inTangents?.[i] ?? out.inArrows?.[i], outs = out.outTangents?.[i] ?? out.arrows?.[i];
      if (a === 'clamped' && !any && !inn && !(b === 'clamped' && outs)) throw new Error(`point ${i} is clamped on its incoming side but has no direction there`);
      if (b === 'clamped' && !any && !outs && !(a === 'clamped' && inn)) throw new Error(`point ${i} is clamped on its outgoing side but has no direction there`);
    });
  }
  if (out.kinds) {
    out.kinds.forEach((k, i) => {
      if (k === 'clamped' && !out.tangents?.[i] && !out.arrows?.[i]) throw new Error(`point ${i} is clamped but has no tangent`);
    });
  }
  return out;
}

// ---------- the editor's project file ----------

export const PROJECT_FORMAT = 'fairspline-project';
export const PROJECT_VERSION = 2; // 2: the node model (states, in_arrows, corners_deg)

/** Whether the text is a project file (of any version): a JSON object with its "format". */
export function isProject(text) {
  const t = text.trim();
  if (!t.startsWith('{') || !t.includes(PROJECT_FORMAT)) return false;
  try { return JSON.parse(t)?.format === PROJECT_FORMAT; } catch { return false; }
}

function projectCurve(c, at) {
  const where = `curves[${at}]`;
  if (!c || typeof c !== 'object' || Array.isArray(c)) throw new Error(`${where} is not an object`);
  const points = toPoints(c.points);
  const n = points.length;
  const list = (key, ok, what) => {
    if (!Array.isArray(c[key]) || c[key].length !== n) throw new Error(`${where}.${key} must have one entry per point (${n})`);
    c[key].forEach((v, i) => { if (!ok(v)) throw new Error(`${where}.${key}[${i}] is not ${what}`); });
    return c[key];
  };
  const arrows = list('arrows', (a) => a === null || finitePair(a), '[dx, dy] or null');
  const radii = list('radii', (r) => typeof r === 'number' && Number.isFinite(r) && r >= 0, 'a radius (a number >= 0)');
  // Version 1 gives kinds; version 2 may give the node model's states instead.
  let states, inArrows = Array(n).fill(null), corners = Array(n).fill(0);
  if (c.states != null) {
    states = list('states', (v) => sidesOf(v) !== null, 'regular, clamped, free or [in, out] of them').map(sidesOf);
    if (c.in_arrows != null) inArrows = list('in_arrows', (a) => a === null || finitePair(a), '[dx, dy] or null').map((a) => (a ? [...a] : null));
    if (c.corners_deg != null) corners = [...list('corners_deg', (v) => typeof v === 'number' && Number.isFinite(v) && v > -180 && v < 180, 'an angle strictly between -180 and 180')];
    states.forEach(([a, b], i) => {
      if (b === 'clamped' && !arrows[i]) throw new Error(`${where}: point ${i} is clamped on its outgoing side but has no arrow`);
      if (a === 'clamped' && b !== 'clamped' && !inArrows[i]) throw new Error(`${where}: point ${i} is clamped on its incoming side but has no in_arrow`);
    });
  } else {
    const kinds = list('kinds', (k) => KINDS.includes(k), 'smooth, clamped or corner');
    kinds.forEach((k, i) => { if (k === 'clamped' && !arrows[i]) throw new Error(`${where}: point ${i} is clamped but has no arrow`); });
    states = kinds.map((k) => { const v = SIDES[KINDS.indexOf(k)]; return [v, v]; });
  }
  if (typeof c.alpha !== 'number' || !Number.isFinite(c.alpha)) throw new Error(`${where}.alpha must be a number`);
  if (typeof c.method !== 'string') throw new Error(`${where}.method must be a method name`);
  if (!c.options || typeof c.options !== 'object' || Array.isArray(c.options)) throw new Error(`${where}.options must be an object`);
  return {
    name: typeof c.name === 'string' ? c.name : `curve ${at + 1}`,
    visible: c.visible !== false,
    color: typeof c.color === 'string' && /^#[0-9a-f]{6}$/i.test(c.color) ? c.color : null,
    points,
    closed: !!c.closed,
    alpha: c.alpha,
    method: c.method,
    options: c.options,
    states,
    tangents: arrows.map((a, i) => (a && states[i][1] === 'clamped' ? [...a] : null)), // the editor's name for the arrows
    inArrows: inArrows.map((a, i) => (states[i][0] === 'clamped' ? a : null)),
    corners,
    radii: [...radii],
  };
}

/**
 * The document of a project file (docs/editor.md, "Project files"): {curves, selected, view?,
 * display?}. Refuses a newer version than this editor writes.
 */
export function parseProject(text) {
  let data;
  try { data = JSON.parse(text); } catch (e) { throw new Error(`invalid JSON: ${e.message}`); }
  if (data?.format !== PROJECT_FORMAT) throw new Error(`not a project file ("format" is not "${PROJECT_FORMAT}")`);
  if (!Number.isInteger(data.version) || data.version < 1) throw new Error('"version" must be a positive integer');
  if (data.version > PROJECT_VERSION) throw new Error(`project version ${data.version} is newer than this editor reads (${PROJECT_VERSION})`);
  if (!Array.isArray(data.curves) || !data.curves.length) throw new Error('"curves" must list at least one curve');
  const curves = data.curves.map(projectCurve);
  const selected = Number.isInteger(data.selected) && data.selected >= 0 && data.selected < curves.length ? data.selected : 0;
  const v = data.view;
  const view = v && [v.x, v.y, v.w].every((x) => typeof x === 'number' && Number.isFinite(x)) && v.w > 0 ? { x: v.x, y: v.y, w: v.w } : null;
  const d = data.display && typeof data.display === 'object' ? data.display : null;
  const display = d ? {
    // A method name (a default entry) or {method, options?, alpha?}: read by entries.js.
    ensemble: Array.isArray(d.ensemble) ? d.ensemble.filter((m) => typeof m === 'string'
      || (m && typeof m === 'object' && typeof m.method === 'string')) : [],
    comb: !!d.comb, combAll: !!d.combAll, polygon: !!d.polygon, plot: d.plot !== false, snap: !!d.snap,
  } : null;
  return { curves, selected, view, display };
}
