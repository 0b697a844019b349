// Import of points: CSV (x,y per line, optional header, # comments), the JSON request of
// `fairspline fit` ({points, closed, kinds, tangents, radii, alpha, method, options} or a bare
// array), or its JSON result (the editor's Export JSON), whose "request" is what was given.
// Throws Error with a sentence that names the line or the field.

const KINDS = ['smooth', 'clamped', 'corner'];

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
  if (data.tangents != null) {
    if (!Array.isArray(data.tangents) || data.tangents.length !== n) throw new Error(`"tangents" must have one entry per point (${n})`);
    data.tangents.forEach((t, i) => { if (t !== null && !finitePair(t)) throw new Error(`tangents[${i}] is not [x, y] or null`); });
    out.tangents = data.tangents.map((t) => (t ? [...t] : null));
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

/** {points, closed?, kinds?, tangents?, radii?, alpha?, method?, options?} from CSV or JSON text. */
export function parseImport(text) {
  const trimmed = text.trim();
  if (!trimmed) throw new Error('nothing to import');
  const out = trimmed.startsWith('{') || trimmed.startsWith('[') ? fromJson(trimmed) : fromCsv(trimmed);
  if (!out.points.length) throw new Error('no points found');
  // A tangent makes a point clamped unless its kind says otherwise.
  if (out.tangents && !out.kinds) out.kinds = out.tangents.map((t) => (t ? 'clamped' : 'smooth'));
  if (out.kinds) {
    out.kinds.forEach((k, i) => {
      if (k === 'clamped' && !out.tangents?.[i]) throw new Error(`point ${i} is clamped but has no tangent`);
    });
  }
  return out;
}
