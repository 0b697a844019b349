// Ensemble entries: (method, options, α) triples fitted alongside the selected curve, so that
// the same method can be compared with itself (cond-g2 at λ = 0.5, 1, 2; the C2 spline at
// uniform, centripetal and chordal knots). An entry with no options and no α of its own is a
// "default entry": the method's box in the ensemble list. Pure functions, no DOM.

/** {method, options, alpha}: alpha null means the selected curve's α. */
export function makeEntry(method, options = {}, alpha = null) {
  const opts = options && typeof options === 'object' && !Array.isArray(options) ? options : {};
  const a = typeof alpha === 'number' && Number.isFinite(alpha) ? alpha : null;
  return { method, options: structuredClone(opts), alpha: a };
}

export const isDefaultEntry = (e) => e.alpha == null && Object.keys(e.options).length === 0;

/** The same triple gives the same key (option order does not matter). */
export function entryKey(e) {
  const opts = Object.keys(e.options).sort().map((k) => [k, e.options[k]]);
  return JSON.stringify([e.method, opts, e.alpha]);
}

const SYMBOLS = { lambda: 'λ', gamma: 'γ', omega_deg: 'Ω°' };
const show = (v) => (Array.isArray(v) ? v.join(',') : String(v));

/** "cond-g2 λ=0.5 α=0.5": the method, the options it sets, and its own α if it has one. */
export function entryLabel(e) {
  const parts = [e.method];
  for (const [k, v] of Object.entries(e.options)) parts.push(`${SYMBOLS[k] ?? k}=${show(v)}`);
  if (e.alpha != null) parts.push(`α=${e.alpha}`);
  return parts.join(' ');
}

/** The hash's short form: a default entry is its method name, others {m, o?, a?}. */
export function entryToHash(e) {
  if (isDefaultEntry(e)) return e.method;
  return { m: e.method, ...(Object.keys(e.options).length ? { o: e.options } : {}), ...(e.alpha != null ? { a: e.alpha } : {}) };
}

/** The project file's form: a default entry is its method name (what version 1 wrote), others
 * {method, options, alpha?}. */
export function entryToProject(e) {
  if (isDefaultEntry(e)) return e.method;
  return { method: e.method, options: e.options, ...(e.alpha != null ? { alpha: e.alpha } : {}) };
}

/** An entry from either form (hash or project) or a bare method name; null if unreadable. */
export function entryFrom(item) {
  if (typeof item === 'string') return makeEntry(item);
  if (!item || typeof item !== 'object') return null;
  const method = item.method ?? item.m;
  if (typeof method !== 'string') return null;
  return makeEntry(method, item.options ?? item.o ?? {}, item.alpha ?? item.a ?? null);
}

/** A list of entries without repeats (the first of equal triples is kept). */
export function entriesFrom(list) {
  const seen = new Set();
  const out = [];
  for (const item of Array.isArray(list) ? list : []) {
    const e = entryFrom(item);
    if (!e || seen.has(entryKey(e))) continue;
    seen.add(entryKey(e));
    out.push(e);
  }
  return out;
}

/** Johnson & Johnson's Fig. 7: the C2 spline (li-strain) at uniform, centripetal and chordal
 * knots. */
export const FIG7_PRESET = [0, 0.5, 1].map((a) => makeEntry('li-strain', {}, a));

/**
 * One colour per entry: a default entry keeps its method's colour (methodColor); another takes
 * its method's colour if no default entry or earlier entry has it, else the palette's first
 * colour not used by an earlier entry or by any default entry, so that the
 * colours are distinct as long as the palette lasts and do not change when an entry is added
 * after them.
 */
export function entryColors(entries, palette, methodColor) {
  const used = new Set(entries.filter(isDefaultEntry).map((e) => methodColor(e.method)));
  let spare = 0;
  return entries.map((e) => {
    if (isDefaultEntry(e)) return methodColor(e.method);
    const own = methodColor(e.method);
    const free = used.has(own) ? palette.find((c) => !used.has(c)) : own;
    const color = free ?? palette[spare++ % palette.length];
    used.add(color);
    return color;
  });
}
