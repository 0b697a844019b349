// End-to-end test of the web editor's basic editing in headless Debian chromium: add, drag,
// undo/redo, methods, ensemble, comb, control polygon, exports, paste import, insertion and an
// infeasible configuration. The newer features are in features.test.mjs.
import { check, out, run, trackFits } from './harness.mjs';

await run(async ({ page, url }) => {
  const { settled } = trackFits(page);
  await page.goto(url);
  await page.waitForSelector('[data-testid="method"] option', { state: 'attached' });
  const method = await page.$eval('[data-testid="method"]', (s) => s.value);
  check(method === 'quasi-elastic', `default method selected (${method})`);
  const listed = await page.$$eval('[data-testid="method"] option', (os) => os.map((o) => o.value));
  check(listed[0] === 'quasi-elastic' && listed[1] === 'restricted-elastic' && listed[2] === 'elastic',
    `the default, then the elastic splines, lead the method list (${listed.slice(0, 3)})`);

  // Add five points by clicking on the canvas.
  const canvas = page.locator('[data-testid="canvas"]');
  const box = await canvas.boundingBox();
  const spots = [[0.15, 0.7], [0.3, 0.35], [0.5, 0.6], [0.7, 0.3], [0.85, 0.65]];
  for (const [fx, fy] of spots) {
    await page.mouse.click(box.x + fx * box.width, box.y + fy * box.height);
  }
  await page.waitForSelector('[data-testid="point-4"]');
  const curve = page.locator('[data-testid="curve-quasi-elastic"]');
  await curve.first().waitFor();
  // Wait for the fit of all five points (four cubics): an earlier fit may still be on screen.
  await page.waitForFunction(() => (document.querySelector('[data-testid="curve-quasi-elastic"]')
    ?.getAttribute('d')?.match(/C/g) ?? []).length === 4);
  const before = await curve.first().getAttribute('d');
  check(before && before.includes('C'), 'the quasi-elastic curve is drawn with cubic Béziers');

  // Undo / redo of the last added point (button and keyboard).
  const pointCount = () => page.locator('[data-testid^="point-"]').count();
  await page.click('[data-testid="undo"]');
  check(await pointCount() === 4, 'undo removes the last added point');
  await page.click('[data-testid="redo"]');
  check(await pointCount() === 5, 'redo restores it');
  await page.keyboard.press('Control+z');
  check(await pointCount() === 4, 'Ctrl+Z undoes');
  await page.keyboard.press('Control+Shift+z');
  check(await pointCount() === 5, 'Ctrl+Shift+Z redoes');
  await page.waitForFunction(
    (d) => document.querySelector('[data-testid="curve-quasi-elastic"]')?.getAttribute('d') === d, before);

  // Control polygon (of the fit of the current points, not of an intermediate state).
  await settled();
  await page.check('[data-testid="control-polygon"]');
  const polys = await page.locator('[data-testid="control-lines"] polyline').count();
  check(polys === 4, `the control polygon has one polyline per segment (${polys})`);

  // Export CSV: header plus one row of 8 numbers per segment.
  await page.click('[data-testid="export-csv"]');
  const csv = (await page.$eval('[data-testid="export-csv-text"]', (t) => t.value)).trim().split('\n');
  const segs = (before.match(/C/g) ?? []).length;
  check(csv[0] === 'x0,y0,x1,y1,x2,y2,x3,y3', 'the CSV export has a header line');
  check(csv.length === segs + 1, `the CSV export has one row per segment (${csv.length - 1}/${segs})`);
  check(csv.slice(1).every((row) => { const v = row.split(','); return v.length === 8 && v.every((x) => Number.isFinite(Number(x)) && x.trim() !== ''); }),
        'each CSV row holds 8 numbers');

  // Drag point 2; the curve follows.
  const p2 = await page.locator('[data-testid="point-2"]').boundingBox();
  await page.mouse.move(p2.x + p2.width / 2, p2.y + p2.height / 2);
  await page.mouse.down();
  await page.mouse.move(p2.x + p2.width / 2, p2.y + p2.height / 2 + 60, { steps: 5 });
  await page.mouse.up();
  await page.waitForTimeout(300);
  const after = await curve.first().getAttribute('d');
  check(after !== before, 'dragging a point refits the curve');
  await page.screenshot({ path: `${out}/editor-quasi-elastic.png` });

  // Switch method.
  await page.selectOption('[data-testid="method"]', 'jaklic-zagar');
  await page.locator('[data-testid="curve-jaklic-zagar"]').first().waitFor();
  check(true, 'switching to jaklic-zagar draws its curve');

  // Ensemble: two more methods, each drawn and tabulated.
  await page.check('[data-testid="ensemble-li-strain"]');
  await page.check('[data-testid="ensemble-quasi-elastic"]');
  await page.locator('[data-testid="curve-li-strain"]').first().waitFor();
  await page.locator('[data-testid="curve-quasi-elastic"]').first().waitFor();
  const table = await page.locator('[data-testid="ensemble-table"]').innerText();
  check(table.includes('li-strain') && table.includes('quasi-elastic'),
        'the ensemble table lists both methods');
  await page.screenshot({ path: `${out}/editor-ensemble.png` });

  // Curvature comb.
  await page.check('[data-testid="comb"]');
  await page.waitForTimeout(200);
  const combLines = Number(await page.getAttribute('[data-testid="comb-lines"] .teeth', 'data-teeth'));
  check(combLines > 10, `the curvature comb is drawn (${combLines} teeth)`);

  // Export SVG.
  await page.click('[data-testid="export-svg"]');
  const svg = await page.$eval('[data-testid="export-svg-text"]', (t) => t.value);
  check(svg.startsWith('<svg') || svg.includes('<svg'), 'exported SVG is an svg document');
  check(svg.includes('<path'), 'exported SVG contains the curve paths');

  // An infeasible configuration: yong-cheng basis (Ω = 60°) with a sharp turn at point 2.
  await page.selectOption('[data-testid="method"]', 'min-energy');
  await page.waitForSelector('[data-testid="option-basis"]');
  await page.selectOption('[data-testid="option-basis"]', 'yong-cheng');
  // Drag point 2 back past point 1 (towards point 0): the polygon reverses at point 2, a
  // stencil angle near 180° > 2Ω = 120°, whatever the window size.
  const q1 = await page.locator('[data-testid="point-1"]').boundingBox();
  const q2 = await page.locator('[data-testid="point-2"]').boundingBox();
  await page.mouse.move(q2.x + q2.width / 2, q2.y + q2.height / 2);
  await page.mouse.down();
  await page.mouse.move(q1.x + q1.width / 2 - 0.08 * box.width, q1.y + q1.height / 2, { steps: 5 });
  await page.mouse.up();
  await page.waitForSelector('[data-testid="error"]:not(:empty)');
  const message = await page.locator('[data-testid="error"]').innerText();
  check(/admissible|infeasible|stencil/i.test(message), `the error is shown (${message.slice(0, 80)}...)`);
  const flagged = await page.locator('[data-testid^="point-"].error').count();
  check(flagged >= 1, 'the offending point is highlighted');
  await page.screenshot({ path: `${out}/editor-error.png` });

  // Import: a malformed text shows an error, a small CSV replaces the points (undoable).
  await page.fill('[data-testid="import-text"]', 'x,y\n1,2\nfoo bar\n');
  await page.click('[data-testid="import"]');
  const importMsg = await page.locator('[data-testid="error"]').innerText();
  check(/import/i.test(importMsg), `a malformed import shows an error (${importMsg.slice(0, 60)})`);
  check(await pointCount() === 5, 'a malformed import keeps the points');
  await page.selectOption('[data-testid="method"]', 'quasi-elastic');
  await page.fill('[data-testid="import-text"]', '# four points\nx,y\n100,100\n300,400\n600,200\n900,500\n');
  await page.click('[data-testid="import"]');
  check(await pointCount() === 4, 'importing a 4-point CSV gives 4 points');
  await page.waitForFunction(() => (document.querySelector('[data-testid="curve-quasi-elastic"]')?.getAttribute('d')?.match(/C/g) ?? []).length === 3);
  check(true, 'the imported points are fitted');
  await page.fill('[data-testid="import-text"]', '{"points": [[0,0],[200,300],[500,100]], "closed": true}');
  await page.click('[data-testid="import"]');
  check(await pointCount() === 3 && await page.isChecked('[data-testid="closed"]'), 'a JSON import sets points and closed');
  await page.click('[data-testid="undo"]');
  check(await pointCount() === 4 && !(await page.isChecked('[data-testid="closed"]')), 'an import is undoable');
  await page.screenshot({ path: `${out}/editor-import.png` });

  // Alt-click on the curve inserts a point between two existing ones.
  await page.waitForFunction(() => (document.querySelector('[data-testid="curve-quasi-elastic"]')?.getAttribute('d')?.match(/C/g) ?? []).length === 3);
  const spot = await page.$eval('[data-testid="curve-quasi-elastic"]', (path) => {
    const len = path.getTotalLength();
    const q = path.getPointAtLength(len / 2).matrixTransform(path.getScreenCTM());
    return [q.x, q.y];
  });
  await page.keyboard.down('Alt');
  await page.mouse.click(spot[0], spot[1]);
  await page.keyboard.up('Alt');
  check(await pointCount() === 5, 'alt-click on the curve inserts a point');
  const order = await page.$$eval('[data-testid^="point-"]', (cs) => cs.map((c) => Number(c.getAttribute('cx'))));
  check(order[0] === 100 && order[4] === 900 && order[2] > 300 && order[2] < 600, `the point is inserted in the middle (${order.map(Math.round)})`);
  await page.keyboard.press('Control+z');
  check(await pointCount() === 4, 'the insertion is undoable');
});
