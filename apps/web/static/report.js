// The report panel: the selected curve's `method_report` (docs/editor.md, "Report panel") in
// human terms. A summary of the top-level values with readable labels, then per-node and
// per-span tables for the fields the methods document (docs/methods/*.md); any other field is
// shown as it is (key: value, or a generic table), so nothing the server says is hidden.
// Hovering a row calls onHover({node}) or onHover({span}) so that the canvas can mark it.

const fmt = (v) => {
  if (typeof v === 'number') return Number.isFinite(v) ? Number(v.toPrecision(5)).toString() : String(v);
  if (typeof v === 'boolean') return v ? 'yes' : 'no';
  if (v == null) return '—';
  if (Array.isArray(v)) return v.length ? v.map(fmt).join(', ') : 'none';
  if (typeof v === 'object') return Object.entries(v).map(([k, x]) => `${k}: ${fmt(x)}`).join(', ');
  return String(v);
};

// Readable labels of the top-level (and solver / balls) values; a "_deg" field is in degrees.
const LABELS = {
  status: 'solver status', iterations: 'iterations', projected_gradient: 'projected gradient',
  omega_deg: 'bound Ω', pieces: 'pieces',
  search: 'search', bezier_accuracy: 'Bézier accuracy (of the elastica arcs)',
  'solver.status': 'solver › status', 'solver.iterations': 'solver › iterations',
  'solver.residual': 'solver › residual', 'solver.tolerance': 'solver › tolerance',
  'solver.active': 'solver › active nodes',
  lambda_mode: 'λ mode', reversal: '180° reversals', approx_energy_total: 'approximate ∫|s″|² dt (sum)',
  'counts.minimum': 'stationary: minima', 'counts.maximum': 'stationary: maxima',
  'counts.boundary': 'stationary: right angles', 'counts.none': 'not stationary',
  gamma: 'γ', sweeps: 'breakpoints swept', tangents: 'tangents',
  knot_scale: 'knot scale', objective: 'objective', strain_term: 'strain term',
  third_derivative_term: 'third-derivative term', system: 'linear system', weights: 'weights',
  clamped: 'clamped points', ratio: 'ratio', composite: 'composite', all_preserved: 'every span keeps its shape',
  tangents_from: 'tangents from', constructions: 'constructions',
  'balls.count': 'data balls', 'balls.status': 'data balls › status',
  'balls.iterations': 'data balls › iterations', 'balls.kkt_residual': 'data balls › KKT residual',
};

// Fields shown by a table of their own (below), not in the summary.
const TABLED = new Set(['active', 'active_spans', 'stationary_kind', 'lambda', 'approx_energy',
  'breakpoints', 'segments', 'spans', 'inserted', 'inserted_at', 'balls.active', 'solver.active']);

function el(tag, attrs = {}, text = null) {
  const n = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) n.setAttribute(k, v);
  if (text != null) n.textContent = text;
  return n;
}

const label = (key) => LABELS[key] ?? key.replace(/\./g, ' › ').replace(/_/g, ' ');

// method_report.energy is the method's own objective: the exact ∫κ² ds only for the elastic
// splines; the min-energy family's Σ E₁(α, β)/L is in its basis's units (docs/methods/min-energy.md).
const energyLabel = (method) => (/elastic$/.test(method) && method !== 'quasi-elastic'
  ? 'energy ∫κ² ds (exact elastica)' : 'energy Σ E₁(α, β)/L (the method\'s objective)');
const withUnit = (key, v) => (key.endsWith('_deg') && typeof v === 'number' ? `${fmt(v)}°` : fmt(v));

/** The summary rows: scalars, short lists and one level of nested objects (solver, balls,
 * counts), each as label: value. */
function summaryRows(report) {
  const rows = [];
  const add = (key, v) => {
    if (TABLED.has(key)) return;
    if (v && typeof v === 'object' && !Array.isArray(v) && !key.includes('.')) {
      const flat = Object.entries(v).every(([, x]) => x == null || typeof x !== 'object' || Array.isArray(x));
      if (flat && key !== 'constructions') { for (const [k, x] of Object.entries(v)) add(`${key}.${k}`, x); return; }
    }
    if (Array.isArray(v) && v.some((x) => x && typeof x === 'object' && !Array.isArray(x))) return; // a table
    rows.push([key, v]);
  };
  for (const [k, v] of Object.entries(report)) add(k, v);
  // The labelled values in LABELS' order (status first), then the others as the server sent them.
  const order = Object.keys(LABELS);
  const rank = (key) => (order.includes(key) ? order.indexOf(key) : order.length);
  return rows.map((r, i) => [r, i]).sort(([a, i], [b, j]) => rank(a[0]) - rank(b[0]) || i - j).map(([r]) => r);
}

/** A small table; rows: [{cells, node?, span?, cls?}]. Hovering a row with a node or span
 * reports it. */
function table(testid, title, head, rows, onHover, note = null) {
  const section = el('section', { class: 'mr-section', 'data-testid': testid });
  section.append(el('h3', {}, title));
  if (note) section.append(el('p', { class: 'mr-note' }, note));
  if (!rows.length) return section;
  const t = el('table', { class: 'mr-table' });
  const tr = el('tr');
  for (const h of head) tr.append(el('th', {}, h));
  t.append(el('thead'));
  t.tHead.append(tr);
  const body = el('tbody');
  for (const r of rows) {
    const row = el('tr', { ...(r.cls ? { class: r.cls } : {}) });
    if (r.node != null) row.dataset.node = r.node;
    if (r.span != null) row.dataset.span = r.span;
    if (r.spans != null) row.dataset.spans = r.spans.join(',');
    for (const c of r.cells) row.append(el('td', {}, typeof c === 'string' ? c : fmt(c)));
    if (r.node != null || r.span != null || r.spans != null) {
      row.addEventListener('mouseenter', () => onHover({ node: r.node, spans: r.spans ?? (r.span != null ? [r.span] : null) }));
      row.addEventListener('mouseleave', () => onHover(null));
    }
    body.append(row);
  }
  t.append(body);
  section.append(t);
  return section;
}

const at = (fit, k) => (fit.points?.[k] ? `(${fmt(fit.points[k][0])}, ${fmt(fit.points[k][1])})` : '');
const intervals = (list) => (Array.isArray(list) && list.length ? list.map(([a, b]) => `(${fmt(a)}, ${fmt(b)})`).join(' ∪ ') : '∅');

/** The tables of the fields the methods document; each returns a section or null. */
const SECTIONS = [
  // min-energy family and the elastic splines: points where the box bound |α|, |β| ≤ Ω holds.
  (r, fit, h) => (Array.isArray(r.active) ? table('mr-active', `Active nodes (${r.active.length})`,
    ['point', 'at'], r.active.map((k) => ({ node: k, cells: [String(k), at(fit, k)] })), h,
    r.active.length ? `The bound Ω = ${withUnit('omega_deg', r.omega_deg)} holds at these nodes: the curve is only G1 there (G2 is lost). Ringed on the canvas.`
      : 'No bound holds: the curve is G2 at every node.') : null),
  (r, fit, h) => (Array.isArray(r.active_spans) && r.active_spans.length ? table('mr-active-spans', `U-turn spans on the bound (${r.active_spans.length})`,
    ['span'], r.active_spans.map((k) => ({ span: k, cells: [String(k)] })), h, 'Spans with |α − β| = 180°.') : null),
  // Data balls: the points whose chosen position is on its disc's circle.
  (r, fit, h) => (r.balls && Array.isArray(r.balls.active) ? table('mr-contacts', `Data-ball contacts (${r.balls.active.length} of ${r.balls.count})`,
    ['point', 'position chosen'], r.balls.active.map((k) => ({ node: k, cells: [String(k), at(fit, k)] })), h,
    'The curve touches these discs on their circle (a filled dot on the canvas); elsewhere it passes inside.') : null),
  // Jaklič–Žagar: the kind of stationary point each direction is, with its λ.
  (r, fit, h) => {
    if (!Array.isArray(r.stationary_kind)) return null;
    const rows = r.stationary_kind.map((kind, k) => ({ node: k, cls: `mr-${kind}`, cells: [String(k), kind, r.lambda?.[k] ?? '—'] }));
    const maxima = rows.filter((x) => x.cells[1] === 'maximum').length;
    return table('mr-stationary', `Directions: ${maxima} energy maxima`, ['point', 'stationary', 'λ'], rows, h,
      'A maximum: the direction of (11) maximizes the two segments\' approximate energy (turns above 90°); ringed on the canvas. λ = bisector avoids it.');
  },
  (r, fit, h) => (Array.isArray(r.approx_energy) ? table('mr-approx', 'Approximate energy per segment',
    ['span', '∫|s″|² dt ≈'], r.approx_energy.map((v, k) => ({ span: k, cells: [String(k), v] })), h) : null),
  // Kozak–Krajnc: each breakpoint's admissible set Ξ, each piece's solutions.
  (r, fit, h) => (Array.isArray(r.breakpoints) ? table('mr-breakpoints', 'Breakpoints: admissible ranges',
    ['point', 'ξ', 'admissible Ξ', 'forward sweep', 'I', 'ξ in Ξ', 'given'],
    r.breakpoints.map((b) => ({ node: b.point, cells: [String(b.point), b.xi, intervals(b.Xi), intervals(b.Xi_forward), Array.isArray(b.I) ? `[${fmt(b.I[0])}, ${fmt(b.I[1])}]` : '—', b.in_Xi, b.prescribed] })), h,
    'ξ is the breakpoint\'s direction parameter; a piece has a solution for every ξ in Ξ.') : null),
  (r, fit, h) => (Array.isArray(r.segments) && r.segments.some((s) => Array.isArray(s.solutions)) ? table('mr-pieces', 'Pieces: solutions',
    ['piece', 'points', 'solutions', 'chosen multiplicity', 't1', 't2', 'energy ∫|P″|²', 'convex', 'theorem'],
    r.segments.map((s, k) => {
      const [a, b] = s.points ?? [3 * k, 3 * k + 3];
      const spans = Array.from({ length: b - a }, (_, j) => a + j);
      return { spans, cls: s.solutions.length !== 1 ? 'mr-many' : '', cells: [String(k + 1), `${a}–${b}`, s.solutions.length, s.multiplicity, s.t1, s.t2, s.energy, s.convex, s.theorem] };
    }), h, 'The number of admissible solutions of each cubic piece (counted with multiplicity it is odd); the one of least energy is drawn.') : null),
  // Spans: Yong–Cheng's constructions, or the elastic splines' elastica pieces.
  (r, fit, h) => {
    if (!Array.isArray(r.spans) || !r.spans.length) return null;
    if ('construction' in r.spans[0]) {
      return table('mr-spans', 'Constructions per span', ['span', 'construction', 'pieces', 'θ', 'φ', 'shape kept'],
        r.spans.map((s, k) => ({ span: k, cells: [String(k), s.construction, s.pieces, `${fmt(s.theta_deg)}°`, `${fmt(s.phi_deg)}°`, s.preserved] })), h);
    }
    if ('kind' in r.spans[0]) {
      return table('mr-spans', 'Elastica per span', ['span', 'kind', 'α', 'β', 'energy', 'length', 'Béziers'],
        r.spans.map((s, k) => ({ span: k, cls: s.kind === 'u-turn' ? 'mr-many' : '', cells: [String(k), s.kind, `${fmt(s.alpha_deg)}°`, `${fmt(s.beta_deg)}°`, s.energy, s.length, s.beziers] })), h);
    }
    return null;
  },
  (r, fit, h) => (Array.isArray(r.inserted) && r.inserted.length ? table('mr-inserted', 'Points inserted at 180° reversals',
    ['fit point'], r.inserted.map((k) => ({ node: k, cells: [String(k)] })), h) : null),
];

/** Any other list of objects: a generic table of its scalar fields. */
function genericTables(report, h) {
  const known = new Set(['breakpoints', 'segments', 'spans']);
  const out = [];
  for (const [key, v] of Object.entries(report)) {
    if (known.has(key) || !Array.isArray(v) || !v.some((x) => x && typeof x === 'object' && !Array.isArray(x))) continue;
    const cols = [...new Set(v.flatMap((x) => Object.keys(x ?? {})))];
    out.push(table(`mr-${key}`, label(key), ['#', ...cols], v.map((x, k) => ({ cells: [String(k), ...cols.map((c) => x?.[c])] })), h));
  }
  return out;
}

/** The nodes ringed on the canvas: [{index, why}] (active bound, Jaklič–Žagar maximum). */
export function markedNodes(fit) {
  const r = fit?.method_report ?? {};
  const marks = [];
  for (const k of Array.isArray(r.active) ? r.active : []) marks.push({ index: k, why: 'active' });
  (Array.isArray(r.stationary_kind) ? r.stationary_kind : []).forEach((kind, k) => {
    if (kind === 'maximum') marks.push({ index: k, why: 'maximum' });
  });
  return marks;
}

/** Fills `container` with the report of `fit` (null: a line saying there is none). */
export function renderMethodReport(container, fit, onHover, stale = false) {
  container.replaceChildren();
  const r = fit?.method_report;
  if (!r) {
    container.append(el('p', { class: 'mr-note' }, 'No fit of the selected curve.'));
    return;
  }
  container.dataset.method = fit.method;
  const head = el('p', { class: 'mr-note' }, `${fit.method}${stale ? ' (last good fit)' : ''}: ${fit.segments?.length ?? 0} segments, bending energy ${fmt(fit.report?.bending_energy)}`);
  container.append(head);
  const dl = el('dl', { class: 'mr-summary', 'data-testid': 'mr-summary' });
  for (const [key, v] of summaryRows(r)) {
    const dt = el('dt', {}, key === 'energy' ? energyLabel(fit.method) : label(key));
    dt.title = key;
    dl.append(dt, el('dd', { 'data-key': key }, withUnit(key, v)));
  }
  container.append(dl);
  for (const section of SECTIONS) {
    const s = section(r, fit, onHover);
    if (s) container.append(s);
  }
  for (const s of genericTables(r, onHover)) container.append(s);
}
