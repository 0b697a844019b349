// Browser tests of issue 20's "Understanding": the report panel of the selected curve's
// method_report (active nodes ringed on the canvas and highlighted from their rows, Jaklič–Žagar
// maxima, Kozak–Krajnc admissible ranges and solution counts, data-ball contacts), ensemble
// entries as (method, options, α) triples (cond-g2 at three λ, the Fig. 7 preset, a failing
// entry), the sortable energies table and one curvature line per visible curve. The expected
// reports come from the CLI (`fairspline fit -f json`) on the same data.
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { check, eventually, hashOf, out, run, trackFits, waitForPieces, section } from './harness.mjs';

const repoFile = (path) => fileURLToPath(new URL(`../../../${path}`, import.meta.url));
const sel = (testid) => `[data-testid="${testid}"]`;
const LI = [[1, 90], [3, 105], [6, 120], [10, 100], [12, 85], [15, 104], [17, 80]]; // examples/li-example1.csv

/** The CLI's fit of a request (the reference the panel must show). */
function cliFit(request, method, sets = []) {
  const args = ['fit', '-', '-m', method, ...sets.flatMap((s) => ['--set', s]), '-f', 'json'];
  return JSON.parse(execFileSync(process.env.FAIRSPLINE_CLI, args, { input: JSON.stringify(request) }).toString());
}

const sameSet = (a, b) => a.length === b.length && [...a].sort((x, y) => x - y).every((v, i) => v === [...b].sort((x, y) => x - y)[i]);

await run(async ({ page, url }) => {
  const { requests, settled } = trackFits(page);
  page.setDefaultTimeout(10000);
  const open = async (state) => {
    await page.goto(url + (state ? hashOf(state) : ''));
    await page.reload();
    await page.waitForSelector(`${sel('method')} option`, { state: 'attached' });
  };
  /** Runs `action`, then waits for the fits it causes. */
  const fitted = async (action) => {
    const before = requests.length;
    await action();
    await eventually(() => requests.length > before, 5000);
    await settled();
  };
  const ringIndices = () => page.$$eval('[data-testid^="ring-"]', (rs) => rs.map((r) => Number(r.dataset.testid.slice(5))));
  const rowNodes = (testid) => page.$$eval(`${sel(testid)} tbody tr`, (rs) => rs.map((r) => Number(r.dataset.node)));

  // ---- quasi-elastic with active bounds: rings at exactly those nodes, hover highlights ----
  await section('active nodes', async () => {
    const expected = cliFit({ points: LI }, 'quasi-elastic').method_report;
    check(expected.active.length > 0, `the CLI's quasi-elastic fit of li-example1 has active nodes (${expected.active})`);
    await open({ p: LI, m: 'quasi-elastic' });
    await waitForPieces(page, 'quasi-elastic', 6);
    await page.click(sel('zoom-fit'));
    await settled();
    await page.locator(sel('mr-active')).waitFor();
    const rows = await rowNodes('mr-active');
    check(sameSet(rows, expected.active), `the panel lists the active nodes ${rows} (CLI: ${expected.active})`);
    const rings = await ringIndices();
    check(sameSet(rings, expected.active), `rings are drawn at exactly those nodes (${rings})`);
    const ringAt = await page.$$eval('[data-testid^="ring-"]', (rs) => rs.map((r) => [Number(r.getAttribute('cx')), Number(r.getAttribute('cy'))]));
    check(ringAt.every(([x, y], j) => x === LI[rings[j]][0] && y === LI[rings[j]][1]), 'each ring is centred on its point');
    const summary = await page.textContent(sel('mr-summary'));
    check(/solver status\s*converged/.test(summary) && summary.includes('iterations') && summary.includes('projected gradient')
      && summary.includes('bound Ω') && summary.includes('90°'), `the summary shows status, iterations, projected gradient, Ω in degrees (${summary.slice(0, 120)}…)`);
    // Hover a row: its node is highlighted; leaving the row removes the highlight.
    const k = expected.active[1];
    await page.hover(`${sel('mr-active')} tr[data-node="${k}"]`);
    const hl = await page.$eval(sel('highlight'), (h) => ({ node: h.dataset.node, cx: Number(h.getAttribute('cx')), cy: Number(h.getAttribute('cy')) }));
    check(Number(hl.node) === k && hl.cx === LI[k][0] && hl.cy === LI[k][1], `hovering the row of node ${k} highlights it (${JSON.stringify(hl)})`);
    await page.mouse.move(5, 5);
    check(await page.locator(sel('highlight')).count() === 0, 'leaving the row removes the highlight');
    await page.screenshot({ path: `${out}/understanding-active.png` });
  });

  // ---- jaklic-zagar: the directions that are energy maxima ----
  await section('jaklic-zagar maxima', async () => {
    const expected = cliFit({ points: LI }, 'jaklic-zagar').method_report;
    const maxima = expected.stationary_kind.flatMap((kind, i) => (kind === 'maximum' ? [i] : []));
    await open({ p: LI, m: 'jaklic-zagar' });
    await waitForPieces(page, 'jaklic-zagar', 6);
    await page.locator(sel('mr-stationary')).waitFor();
    const shown = await page.$$eval(`${sel('mr-stationary')} tr.mr-maximum`, (rs) => rs.map((r) => Number(r.dataset.node)));
    check(maxima.length > 0 && sameSet(shown, maxima), `the maxima rows are the CLI's maxima (${shown} / ${maxima})`);
    const title = await page.textContent(`${sel('mr-stationary')} h3`);
    check(title.includes(`${maxima.length} energy maxima`), `the section says how many (${title})`);
    check(sameSet(await ringIndices(), maxima), 'the maxima are ringed');
    const lambda = await page.$$eval(`${sel('mr-stationary')} tbody tr`, (rs) => rs.map((r) => r.cells[2].textContent));
    check(lambda[1] === String(Number(expected.lambda[1].toPrecision(5))), `each row shows its λ (${lambda[1]})`);
    // A per-segment row highlights its span.
    await page.hover(`${sel('mr-approx')} tr[data-span="2"]`);
    check(await page.getAttribute(sel('highlight'), 'data-spans') === '2', 'hovering a segment row highlights its span');
  });

  // ---- kozak-krajnc: admissible ranges and solution counts ----
  await section('kozak-krajnc', async () => {
    const expected = cliFit({ points: LI }, 'kozak-krajnc').method_report;
    await open({ p: LI, m: 'kozak-krajnc' });
    await waitForPieces(page, 'kozak-krajnc', 6);
    await page.locator(sel('mr-breakpoints')).waitFor();
    const bp = await page.$$eval(`${sel('mr-breakpoints')} tbody tr`, (rs) => rs.map((r) => [...r.cells].map((c) => c.textContent)));
    check(bp.length === expected.breakpoints.length, `one row per breakpoint (${bp.length})`);
    const xi1 = expected.breakpoints[1].Xi;
    check(bp[1][2].split('∪').length === xi1.length && bp[1][2].includes(String(Number(xi1[0][0].toPrecision(5)))),
      `the admissible set Ξ of point 3 is shown (${bp[1][2]})`);
    const pieces = await page.$$eval(`${sel('mr-pieces')} tbody tr`, (rs) => rs.map((r) => [...r.cells].map((c) => c.textContent)));
    check(pieces.length === expected.segments.length
      && pieces.every((p, k) => Number(p[2]) === expected.segments[k].solutions.length), `each piece shows its number of solutions (${pieces.map((p) => p[2])})`);
    await page.hover(`${sel('mr-pieces')} tbody tr >> nth=1`);
    check(await page.getAttribute(sel('highlight'), 'data-spans') === '3,4,5', 'hovering piece 2 highlights its spans 3–5');
  });

  // ---- data balls: the contacts ----
  await section('data-ball contacts', async () => {
    const balls = JSON.parse(readFileSync(repoFile('examples/noisy-ellipse-balls.json'), 'utf8'));
    const expected = cliFit(balls, 'quasi-elastic').method_report.balls;
    await open({ p: balls.points, r: balls.radii, c: balls.closed ? 1 : 0, m: 'quasi-elastic' });
    await page.locator(sel('mr-contacts')).waitFor();
    const rows = await rowNodes('mr-contacts');
    check(expected.active.length > 0 && sameSet(rows, expected.active), `the contact rows are the CLI's (${rows.length} of ${expected.count})`);
    const title = await page.textContent(`${sel('mr-contacts')} h3`);
    check(title.includes(`${expected.active.length} of ${expected.count}`), `the section counts them (${title})`);
    const summary = await page.textContent(sel('mr-summary'));
    check(summary.includes('data balls › status'), 'the balls\' solver status is in the summary');
  });

  // ---- ensemble entries: cond-g2 at three λ, Fig. 7, a failure, sorting, the plot ----
  await section('ensemble entries', async () => {
    const other = LI.map(([x, y]) => [x, y - 30]);
    await open({ p: LI, m: 'quasi-elastic', D: [{ l: 'main', s: '#2563eb' }, { l: 'below', s: '#16a34a', p: other, m: 'li-strain' }], S: 0 });
    await waitForPieces(page, 'quasi-elastic', 6);
    await page.click(sel('zoom-fit-all'));
    await page.click(`${sel('entry-form')} summary`);
    await page.selectOption(sel('entry-method'), 'cond-g2');
    for (const lambda of ['0.5', '1', '2']) {
      await page.fill(sel('entry-option-lambda'), lambda);
      await fitted(() => page.click(sel('entry-add')));
    }
    const labels = await page.$$eval(`${sel('ensemble-entries')} .entry-label`, (ls) => ls.map((l) => l.textContent));
    check(labels.join('|') === 'cond-g2 λ=0.5|cond-g2 λ=1|cond-g2 λ=2', `three entries of one method (${labels.join('|')})`);
    const rows = async () => page.$$eval(`${sel('ensemble-table')} tbody tr`, (rs) => rs.map((r) => ({
      label: r.dataset.label, cells: [...r.cells].map((c) => c.textContent.trim()),
    })));
    let table = await rows();
    const condRows = table.filter((r) => r.label.startsWith('cond-g2'));
    const bending = condRows.map((r) => Number(r.cells[1]));
    check(condRows.length === 3 && new Set(bending).size === 3 && bending.every(Number.isFinite),
      `three cond-g2 rows with different bending energies (${bending})`);
    const lambdas = requests.slice(-4).map((b) => b.options?.lambda).filter((v) => v != null);
    check(lambdas.includes(0.5) && lambdas.includes(2), `the entries' requests carry their λ (${lambdas})`);
    const colours = await page.$$eval(`${sel('ensemble-entries')} .swatch`, (s) => s.map((x) => x.style.background));
    check(new Set(colours).size === colours.length, 'each entry has its own colour');

    // Fig. 7: the C2 spline at uniform, centripetal and chordal knots.
    await fitted(() => page.click(sel('preset-fig7')));
    table = await rows();
    const fig7 = table.filter((r) => r.label.startsWith('li-strain α='));
    check(fig7.map((r) => r.label).join('|') === 'li-strain α=0|li-strain α=0.5|li-strain α=1', `the Fig. 7 preset adds li-strain at α = 0, 0.5, 1 (${fig7.map((r) => r.label)})`);
    check(new Set(fig7.map((r) => r.cells[1])).size === 3, 'with three different energies');
    const alphas = requests.slice(-8).filter((b) => b.method === 'li-strain').map((b) => b.alpha);
    check([0, 0.5, 1].every((a) => alphas.includes(a)), `their requests carry their α (${alphas})`);

    // A failing entry stays a readable row.
    await fitted(() => page.check(sel('ensemble-yong-cheng')));
    table = await rows();
    const failed = table.find((r) => r.label === 'yong-cheng');
    check(failed && failed.cells.length === 2 && failed.cells[1].includes('tangent'), `the failing entry's row shows its error (${failed?.cells[1]})`);

    // Sorting by bending energy: ascending, again descending; the failure last both ways.
    await page.click(sel('sort-bending'));
    table = await rows();
    let values = table.slice(0, -1).map((r) => Number(r.cells[1]));
    check(values.every((v, i) => i === 0 || values[i - 1] <= v) && table.at(-1).label === 'yong-cheng',
      `sorted by bending energy, ascending, the failure last (${values.map((v) => v.toPrecision(3))})`);
    await page.click(sel('sort-bending'));
    table = await rows();
    values = table.slice(0, -1).map((r) => Number(r.cells[1]));
    check(values.every((v, i) => i === 0 || values[i - 1] >= v) && table.at(-1).label === 'yong-cheng',
      'a second click sorts descending, the failure still last');

    // The curvature plot: one line per visible curve (the other curve, the main one, 6 entries).
    const lines = await page.locator(`${sel('curvature-plot')} path[data-testid^="kappa-"]`).count();
    check(lines === 8, `the curvature plot has one line per visible curve (${lines} of 8)`);
    await page.check(sel('comb-all'));
    const combs = await page.locator(`${sel('comb-others')} g`).count();
    check(combs === 7, `combs of all curves: one per other visible curve and entry (${combs} of 7)`);

    // Entries go into the hash and the project file.
    const hash = JSON.parse(decodeURIComponent(new URL(page.url()).hash.slice(1)));
    check(hash.e.length === 7 && hash.e[0].m === 'cond-g2' && hash.e[0].o.lambda === 0.5 && hash.e[3].a === 0 && hash.e[6] === 'yong-cheng',
      `the hash holds the entries (${JSON.stringify(hash.e)})`);
    await page.click(sel('save-project'));
    const project = JSON.parse(await page.$eval(sel('export-project-text'), (t) => t.value));
    check(project.version === 1 && project.display.ensemble[2].options.lambda === 2 && project.display.ensemble[5].alpha === 1,
      'the project file (version 1) holds them');
    await page.reload();
    await waitForPieces(page, 'quasi-elastic', 6);
    await settled();
    const again = await page.$$eval(`${sel('ensemble-entries')} .entry-label`, (ls) => ls.map((l) => l.textContent));
    check(again.length === 7 && again[2] === 'cond-g2 λ=2', 'reloading the hash gives the same entries');

    // Removing an entry removes its row.
    await fitted(() => page.click(sel('entry-remove-0')));
    table = await rows();
    check(!table.some((r) => r.label === 'cond-g2 λ=0.5'), 'removing an entry removes its row');
  });

  // ---- the screenshot of docs/editor.md: the panel with a row hovered, the canvas above ----
  await section('screenshot', async () => {
    await page.setViewportSize({ width: 1280, height: 960 });
    await open({ p: LI, m: 'quasi-elastic', e: [{ m: 'cond-g2', o: { lambda: 0.5 } }, { m: 'cond-g2', o: { lambda: 2 } }], k: 1, q: 0 });
    await waitForPieces(page, 'quasi-elastic', 6);
    await page.click(sel('zoom-fit'));
    await page.click(sel('zoom-out'));
    await settled();
    // mouseenter without moving the pointer there (a hover would scroll the row to the top).
    await page.dispatchEvent(`${sel('mr-active')} tr[data-node="4"]`, 'mouseenter');
    await page.$eval('.stage', (s) => { s.scrollTop = s.scrollHeight; });
    await page.screenshot({ path: `${out}/editor-report.png` });
    check(await page.locator(sel('highlight')).count() === 1, `screenshot saved to ${out}/editor-report.png, a row hovered`);
  });
});
