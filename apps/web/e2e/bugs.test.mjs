// Browser tests of the bugs of issue 20 ("Bugs found"), one section per bug, each failing on the
// editor before its fix: keyboard shortcuts after a panel control had the focus, the JSON export
// round trip, clamping a node on the bound Ω, the options a method lists and the hints of its
// errors, the last good curve kept through an error, and the smaller ones (one point, undoable
// settings, hashchange, comb colour, SVG view box, reversal=insert). Headless Debian chromium;
// screenshots go to FAIRSPLINE_E2E_OUT.
import { check, eventually, hashOf, out, run, trackFits, waitForPieces, section } from './harness.mjs';

const FIVE = [[150, 200], [300, 450], [500, 300], [700, 500], [850, 250]];
const LI = [[1, 90], [3, 105], [6, 120], [10, 100], [12, 85], [15, 104], [17, 80]]; // examples/li-example1.csv

const sel = (testid) => `[data-testid="${testid}"]`;

/** The JSON export of the main curve. */
async function exportedText(page) {
  await page.click(sel('export-json'));
  return page.$eval(sel('export-json-text'), (t) => t.value);
}
const exported = async (page) => JSON.parse(await exportedText(page));

/** Screen position of world point p (the canvas's y axis is up). */
function screenOf(page, [x, y]) {
  return page.evaluate(([wx, wy]) => {
    const svg = document.getElementById('canvas');
    const q = svg.createSVGPoint();
    q.x = wx;
    q.y = wy;
    const s = q.matrixTransform(document.getElementById('world').getScreenCTM());
    return { x: s.x, y: s.y };
  }, [x, y]);
}

const pointCount = (page) => page.locator('[data-testid^="point-"]').count();
const kindOf = (page, i) => page.getAttribute(sel(`point-${i}`), 'data-kind');
const errorText = async (page) => (await page.isVisible(sel('error')) ? page.textContent(sel('error')) : '');

await run(async ({ page, url }) => {
  const { requests, settled } = trackFits(page);
  page.setDefaultTimeout(10000);
  /** Runs `action` and waits for the fits it causes: one sent at least, then none for 300 ms
   * (settled() alone can return before the first request of an action is seen). */
  const fitted = async (action) => {
    const before = requests.length;
    await action();
    await eventually(() => requests.length > before, 5000);
    await settled();
  };
  /** Opens the editor on a state (the URL hash), reloaded so that nothing is left over. */
  const open = async (state) => {
    await page.goto(url + (state ? hashOf(state) : ''));
    await page.reload();
    await page.waitForSelector(`${sel('method')} option`, { state: 'attached' });
  };

  // ---- bug 1: shortcuts act on the canvas whenever the pointer was last on it ----
  await section('bug 1', async () => {
    await open({ p: FIVE, m: 'quasi-elastic' });
    await waitForPieces(page, 'quasi-elastic', 4);
    await page.focus(sel('method'));
    await page.selectOption(sel('method'), 'cond-g2');
    await waitForPieces(page, 'cond-g2', 4);
    await page.click(sel('point-2'));
    await page.keyboard.press('k');
    check(await page.$eval(sel('method'), (s) => s.value) === 'cond-g2',
      `K after clicking a point leaves the method dropdown alone (${await page.$eval(sel('method'), (s) => s.value)})`);
    check(await kindOf(page, 2) === 'clamped', 'K after clicking a point cycles that point\'s kind (smooth → clamped)');
    await settled();
    await fitted(() => page.fill(sel('option-lambda'), '0.5'));
    let n = await pointCount(page);
    await page.click(sel('point-3'));
    await page.keyboard.press('Backspace');
    check(await pointCount(page) === n - 1, 'Backspace after clicking a point deletes the point');
    check(await page.inputValue(sel('option-lambda')) === '0.5', 'and leaves the lambda field at 0.5');
    await settled();
    check(!/bad_option/.test(await errorText(page)), 'no bad_option error');
    // Typing in a field whose focus came from the pointer: the keys are the field's.
    await page.click(sel('option-lambda'));
    n = await pointCount(page);
    await page.keyboard.press('End');
    await page.keyboard.press('Backspace');
    check(await page.inputValue(sel('option-lambda')) !== '0.5' && await pointCount(page) === n,
      'Backspace in a field clicked last edits the field');
    await page.keyboard.press('5');
    await page.click(sel('point-1'));
    await page.click(sel('kind-corner'));
    await page.locator(sel('corner-1')).waitFor();
    await page.keyboard.press('k');
    check(await kindOf(page, 1) === 'smooth', 'K after clicking a kind radio button cycles the kind (corner → smooth)');
    n = await pointCount(page);
    await page.keyboard.press('Delete');
    check(await pointCount(page) === n - 1, 'Delete after clicking a radio button deletes the selected point');
    await page.click(sel('ensemble-li-strain'));
    await page.keyboard.press('Control+z');
    check(await pointCount(page) === n, 'Ctrl+Z after clicking an ensemble box undoes (the deletion)');
    await page.keyboard.press('Control+z');
    check(await kindOf(page, 1) === 'corner', 'and again (the kind change)');
    check(await page.isChecked(sel('ensemble-li-strain')), 'the ensemble box keeps its state');
  });

  // ---- bug 2: Export JSON → Import gives the same curve ----
  await section('bug 2', async () => {
    const roundTrip = async (state, what) => {
      await fitted(() => open(state));
      const first = await exported(page);
      check(first.segments?.length > 0, `${what}: the curve is fitted (${await errorText(page)})`);
      const text = await exportedText(page);
      await fitted(() => open({ p: [[0, 0], [300, 100], [600, 0]], m: 'quasi-elastic' }));
      await page.fill(sel('import-text'), text);
      await fitted(() => page.click(sel('import')));
      const again = await exported(page);
      const a = first.request, b = again.request ?? {};
      const same = (x, y) => JSON.stringify(x) === JSON.stringify(y);
      check(same(again.points, first.points) && same(b.points, a.points), `${what}: the same points`);
      check(same(b.kinds, a.kinds) && a.kinds?.length === first.points.length, `${what}: the same kinds (${JSON.stringify(b.kinds)})`);
      const tangentsOk = Array.isArray(b.tangents) && b.tangents.length === a.tangents.length && a.tangents.every((t, i) =>
        (t === null) === (b.tangents[i] === null) && (t === null || Math.hypot(t[0] - b.tangents[i][0], t[1] - b.tangents[i][1]) <= 1e-12 * Math.hypot(...t)));
      check(tangentsOk, `${what}: tangents only where given, the same to 1e-12 (${JSON.stringify(b.tangents)})`);
      check(b.alpha === a.alpha && same(b.radii, a.radii) && b.closed === a.closed, `${what}: the same alpha (${b.alpha}), radii and closed`);
      check(again.method === first.method && same(again.options, first.options), `${what}: the same method and options (${again.method} ${JSON.stringify(again.options)})`);
      const e0 = first.report.bending_energy, e1 = again.report?.bending_energy;
      check(Math.abs(e1 - e0) <= 1e-9 * Math.abs(e0), `${what}: the same bending energy (${e0} → ${e1})`);
    };
    await roundTrip({ p: LI.map(([x, y]) => [40 * x, 5 * y - 200]), m: 'li-strain', a: 0, n: [0, 0, 1, 0, 0, 0, 0], t: [0, 0, [60, 20], 0, 0, 0, 0] },
      'li-strain, uniform knots, a clamped point');
    await roundTrip({ p: FIVE, m: 'cond-g2', o: { lambda: 0.7 }, a: 1, n: [0, 1, 0, 2, 0], t: [0, [40, 30], 0, 0, 0], r: [0, 0, 20, 0, 0] },
      'cond-g2 λ = 0.7, chordal knots, a clamped point, a corner and a data ball');
    // The export of a failing curve still holds what was drawn.
    await open({ p: [[100, 300], [400, 300], [150, 320], [600, 300]], m: 'min-energy', o: { basis: 'yong-cheng' } });
    await page.locator(sel('error-marker')).waitFor();
    const failed = await exported(page);
    check(failed.error?.code === 'infeasible' && failed.request?.points?.length === 4 && failed.options?.basis === 'yong-cheng',
      'a failing curve exports its request, method, options and error');
  });

  // ---- bug 3: clamping an active node of the default fit keeps the curve ----
  await section('bug 3', async () => {
    await open({ p: LI, m: 'quasi-elastic' });
    await waitForPieces(page, 'quasi-elastic', 6);
    await page.click(sel('zoom-fit'));
    const free = await exported(page);
    check(JSON.stringify(free.method_report.active) === '[2,4,5]', `the default fit has its directions on the bound at 2, 4, 5 (${free.method_report.active})`);
    for (const i of [4, 5]) {
      await page.click(sel(`point-${i}`));
      await fitted(() => page.click(sel('kind-clamped')));
      const clamped = await exported(page);
      const err = await errorText(page);
      check(!err && clamped.request?.kinds?.[i] === 'clamped', `clamping active point ${i} fits (${err || 'no error'})`);
      const moved = clamped.segments ? Math.max(...clamped.segments.flatMap((s, k) => s.bezier.flatMap((p, j) =>
        p.map((v, c) => Math.abs(v - free.segments[k].bezier[j][c]))))) : Infinity;
      check(moved <= 1e-9 * 120, `and leaves the curve as it was (max control point change ${moved.toExponential(1)})`);
    }
    await page.screenshot({ path: `${out}/bugs-clamped-on-bound.png` });
  });

  // ---- bug 4: the options form lists the method's options; messages carry hints, no flags ----
  await section('bug 4', async () => {
    const { methods } = await page.evaluate(async () => (await fetch('/api/methods')).json());
    for (const name of ['quasi-elastic', 'cond-g2', 'min-energy']) {
      await page.selectOption(sel('method'), name);
      const shown = await page.$$eval(`${sel('options')} [data-testid^="option-"]`, (es) => es.map((e) => e.dataset.testid.replace(/^option-/, '')).filter((t) => !t.endsWith('-number')));
      const listed = methods.find((m) => m.name === name).options.map((o) => o.name);
      check(JSON.stringify(shown) === JSON.stringify(listed), `${name}: the form shows the options the schema lists (${shown})`);
    }
    check(!methods.find((m) => m.name === 'quasi-elastic').options.some((o) => o.name === 'lambda'), 'quasi-elastic lists no lambda (its cubic is λ = 1)');
    await open({ p: FIVE, m: 'kozak-krajnc' });
    await page.locator(sel('error-hint')).waitFor();
    let msg = await errorText(page);
    check(/wrong_point_count/.test(msg) && !msg.includes('--'), `a library message names no command-line flag (${msg})`);
    check(await page.textContent(sel('error-hint')) === 'set remainder to hermite', `the error offers its hint as a button (${await page.textContent(sel('error-hint'))})`);
    await page.click(sel('error-hint'));
    await page.locator(sel('curve-kozak-krajnc')).waitFor();
    await settled();
    check(await page.$eval(sel('option-remainder'), (s) => s.value) === 'hermite' && !(await errorText(page)), 'the hint sets the option and the curve is drawn');
    await page.click(sel('undo'));
    await page.locator(sel('error-hint')).waitFor();
    check(true, 'applying a hint is undoable');
    await open({ p: FIVE, m: 'min-energy', o: { lambda: 0.5 } });
    await page.locator(sel('error-hint')).waitFor();
    msg = await errorText(page);
    check(/bad_option/.test(msg) && !msg.includes('--') && !msg.includes('-m '), `basis=quasi-elastic with lambda: ${msg}`);
    await page.click(sel('error-hint'));
    await waitForPieces(page, 'min-energy', 4);
    check(await page.$eval(sel('option-basis'), (s) => s.value) === 'cond-g2', 'its hint sets basis to cond-g2');
    await open({ p: FIVE, m: 'li-curvature-variation' });
    await page.locator(sel('error')).waitFor();
    msg = await errorText(page);
    check(/singular_system/.test(msg) && !msg.includes('--'), `li-curvature-variation says what to do in words (${msg})`);
  });

  // ---- bug 5: an error keeps the last good curve, comb and plot, dimmed, also mid-drag ----
  await section('bug 5', async () => {
    await open({ p: FIVE, m: 'min-energy', o: { basis: 'yong-cheng' }, k: 1 });
    await waitForPieces(page, 'min-energy', 4);
    const from = await screenOf(page, FIVE[2]);
    const to = await screenOf(page, [310, 200]); // stencil angles of 147° and 126° > 2Ω = 120°
    await page.mouse.move(from.x, from.y);
    await page.mouse.down();
    await page.mouse.move(to.x, to.y, { steps: 6 });
    await page.locator(sel('error-marker')).waitFor();
    await settled();
    const midDrag = {
      d: await page.getAttribute(sel('curve-min-energy'), 'd').catch(() => null),
      stale: await page.locator(`${sel('curve-min-energy')}[data-stale]`).count(),
      comb: Number(await page.getAttribute(`${sel('comb-lines')} .teeth`, 'data-teeth').catch(() => 0)),
      combStale: await page.$eval(sel('comb-lines'), (g) => g.classList.contains('stale')),
      plot: await page.locator(`${sel('kappa-min-energy')}.stale`).count(),
      error: await errorText(page),
    };
    check(midDrag.d?.includes('C') && midDrag.stale === 1, 'mid-drag, the failing fit leaves the last good curve on screen, dimmed');
    check(midDrag.comb > 0 && midDrag.combStale, `its comb stays, dimmed (${midDrag.comb} teeth)`);
    check(midDrag.plot === 1, 'its curvature plot stays, dimmed');
    check(/infeasible/.test(midDrag.error), `with the error shown (${midDrag.error.slice(0, 60)}…)`);
    await page.screenshot({ path: `${out}/bugs-last-good-curve.png` });
    await fitted(async () => {
      await page.mouse.move(from.x, from.y, { steps: 6 });
      await page.mouse.up();
    });
    check(await page.locator(`${sel('curve-min-energy')}:not([data-stale])`).count() === 1 && !(await errorText(page)),
      'back to feasible data, the curve is drawn fresh');
  });

  // ---- bug 6a: a single point says that a second one is needed ----
  await section('bug 6a', async () => {
    await open(null);
    const box = await page.locator(sel('canvas')).boundingBox();
    await fitted(() => page.mouse.click(box.x + 0.3 * box.width, box.y + 0.5 * box.height));
    const msg = await errorText(page);
    check(/at least 2/.test(msg), `one point: "${msg}"`);
    await page.mouse.click(box.x + 0.6 * box.width, box.y + 0.4 * box.height);
    await waitForPieces(page, 'quasi-elastic', 1);
    check(!(await errorText(page)), 'two points: a curve and no message');
  });

  // ---- bug 6b: method, option and α changes are undoable ----
  await section('bug 6b', async () => {
    await open({ p: FIVE, m: 'quasi-elastic' });
    await waitForPieces(page, 'quasi-elastic', 4);
    await page.selectOption(sel('method'), 'cond-g2');
    await page.click(sel('option-lambda'));
    await page.keyboard.press('Control+a');
    await page.keyboard.type('0.5'); // three keystrokes, one undo step
    await fitted(() => page.selectOption(sel('alpha'), '0'));
    const body = () => requests[requests.length - 1];
    check(body().method === 'cond-g2' && body().options?.lambda === 0.5 && body().alpha === 0, 'cond-g2, λ = 0.5, uniform knots sent');
    await fitted(() => page.click(sel('undo')));
    check(await page.$eval(sel('alpha'), (s) => s.value) === '0.5' && body().alpha === 0.5, 'undo: α back to 0.5');
    await fitted(() => page.click(sel('undo')));
    check(await page.inputValue(sel('option-lambda')) === '1' && body().options?.lambda === undefined, 'undo: λ back to its default');
    await fitted(() => page.click(sel('undo')));
    check(await page.$eval(sel('method'), (s) => s.value) === 'quasi-elastic' && body().method === 'quasi-elastic', 'undo: the method back to quasi-elastic');
    check(await pointCount(page) === 5, 'the points stay');
    await fitted(async () => { for (let k = 0; k < 3; k++) await page.click(sel('redo')); });
    check(body().method === 'cond-g2' && body().options?.lambda === 0.5 && body().alpha === 0, 'redo ×3: all three again');
  });

  // ---- bug 6c: editing the URL's hash opens its state ----
  await section('bug 6c', async () => {
    await open({ p: FIVE, m: 'cond-g2' });
    await waitForPieces(page, 'cond-g2', 4);
    const tri = [[200, 200], [500, 500], [800, 200]];
    await page.evaluate((h) => { location.hash = h; }, hashOf({ p: tri, m: 'li-strain' }));
    await waitForPieces(page, 'li-strain', 2);
    check(await pointCount(page) === 3 && await page.$eval(sel('method'), (s) => s.value) === 'li-strain', 'a new hash loads its points and method');
    await page.click(sel('undo'));
    await waitForPieces(page, 'cond-g2', 4);
    check(await pointCount(page) === 5, 'and is one undo step');
  });

  // ---- bug 6d: the comb's colour is no ensemble method's ----
  await section('bug 6d', async () => {
    await open({ p: FIVE, m: 'quasi-elastic', k: 1 });
    await page.locator(`${sel('comb-lines')} .teeth`).first().waitFor({ state: 'attached' });
    const colours = await page.evaluate(() => {
      const rgb = (c) => c.match(/[\d.]+/g).slice(0, 3).map(Number);
      const comb = rgb(getComputedStyle(document.querySelector('[data-testid="comb-lines"] .teeth')).stroke);
      const swatches = [...document.querySelectorAll('[data-testid="ensemble"] label')].map((l) => ({
        name: l.textContent.trim(), rgb: rgb(getComputedStyle(l.querySelector('.swatch')).backgroundColor),
      }));
      return { comb, swatches };
    });
    const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    const nearest = colours.swatches.map((s) => ({ ...s, d: dist(s.rgb, colours.comb) })).sort((a, b) => a.d - b.d)[0];
    check(nearest.d > 60, `every ensemble colour is far from the comb's (nearest: ${nearest.name}, RGB distance ${nearest.d.toFixed(0)})`);
    check(new Set(colours.swatches.map((s) => s.rgb.join())).size === colours.swatches.length, 'no two methods share a colour');
  });

  // ---- bug 6e: the exported SVG holds the comb's teeth ----
  await section('bug 6e', async () => {
    await open({ p: FIVE, m: 'quasi-elastic', k: 1 });
    await page.locator(`${sel('comb-lines')} .teeth`).first().waitFor({ state: 'attached' });
    await page.click(sel('export-svg'));
    const svgText = await page.$eval(sel('export-svg-text'), (t) => t.value);
    const [vx, vy, vw, vh] = /viewBox="([^"]+)"/.exec(svgText)[1].split(' ').map(Number);
    const ends = [...svgText.matchAll(/<line x1="([^"]+)" y1="([^"]+)" x2="([^"]+)" y2="([^"]+)"/g)]
      .flatMap((m) => [[+m[1], +m[2]], [+m[3], +m[4]]]);
    const outside = ends.filter(([x, y]) => x < vx || x > vx + vw || -y < vy || -y > vy + vh);
    check(ends.length > 20 && outside.length === 0, `the SVG's view box holds every comb tooth (${outside.length} of ${ends.length} ends outside)`);
    await page.setContent(svgText);
    await page.screenshot({ path: `${out}/bugs-exported-comb.png` });
  });

  // ---- bug 6f: with reversal=insert the points drawn are the fit's ----
  await section('bug 6f', async () => {
    const rev = [[100, 300], [500, 300], [300, 300], [800, 300]];
    await open({ p: rev, m: 'jaklic-zagar', o: { reversal: 'insert' } });
    await waitForPieces(page, 'jaklic-zagar', 5);
    const fit = await exported(page);
    const inserted = fit.method_report.inserted;
    check(inserted.length === 2 && fit.points.length === 6, `the fit inserts two points (${inserted})`);
    let placed = true;
    for (const k of inserted) {
      const b = await page.locator(sel(`inserted-${k}`)).boundingBox();
      const s = await screenOf(page, fit.points[k]);
      placed &&= b && Math.hypot(b.x + b.width / 2 - s.x, b.y + b.height / 2 - s.y) < 1;
    }
    check(placed && await page.locator('[data-testid^="inserted-"]').count() + await pointCount(page) === fit.points.length,
      'every point of the fit is drawn: the inserted ones at their places');
    // Alt-click on the span from point 2 to the point inserted after it: the new point goes
    // between points 2 and 3, not after the last point.
    const mid = fit.segments[3].bezier;
    const onCurve = [(mid[0][0] + 3 * mid[1][0] + 3 * mid[2][0] + mid[3][0]) / 8, (mid[0][1] + 3 * mid[1][1] + 3 * mid[2][1] + mid[3][1]) / 8];
    const at = await screenOf(page, onCurve);
    await page.keyboard.down('Alt');
    await fitted(() => page.mouse.click(at.x, at.y));
    await page.keyboard.up('Alt');
    const pts = requests[requests.length - 1].points;
    check(pts.length === 5 && Math.hypot(pts[3][0] - onCurve[0], pts[3][1] - onCurve[1]) < 3 && pts[4][0] === 800,
      `alt-click inserts into the span the fit drew there (${JSON.stringify(pts.map((p) => p.map(Math.round)))})`);
    await page.screenshot({ path: `${out}/bugs-reversal-insert.png` });
  });
});
