// End-to-end test of the editor without a mouse and at three window sizes (issue 20): the empty
// canvas's hint and "Load example", keyboard-only editing (Tab to the button, then N / P, the
// arrows, O, Enter, Delete, Ctrl+Z on the focused canvas), the "?" help overlay, and the layout
// at 1920×1080, 1280×800 and 800×600 (no horizontal overflow, no panel control cut off). The
// screenshots of docs/images (editor-editing.png, editor-help.png, editor-small.png) are saved
// to FAIRSPLINE_E2E_OUT.
import { check, eventually, hashOf, out, run, section, trackFits } from './harness.mjs';

const sel = (id) => `[data-testid="${id}"]`;
const EXAMPLE = [[1, 90], [3, 105], [6, 120], [10, 100], [12, 85], [15, 104], [17, 80]]; // examples/li-example1.csv

await run(async ({ page, url }) => {
  const tracker = trackFits(page);
  const { requests } = tracker;
  const settled = async () => { await page.waitForTimeout(100); await tracker.settled(); };
  const last = () => requests[requests.length - 1];
  const active = () => page.evaluate(() => document.activeElement?.dataset?.testid ?? document.activeElement?.id ?? document.activeElement?.tagName);
  const selected = () => page.$$eval('[data-testid^="point-"].selected', (cs) => cs.map((c) => c.dataset.index).join(','));
  const pixel = () => page.evaluate(() => 1 / document.getElementById('world').getScreenCTM().a);
  await page.setViewportSize({ width: 1280, height: 800 });

  await section('empty state and keyboard-only editing', async () => {
    await page.goto(url);
    await page.waitForSelector(`${sel('method')} option`, { state: 'attached' });
    check(await page.isVisible(sel('empty-hint')) && /click to add points, or load the example/i.test(await page.locator(sel('empty-hint')).textContent()),
      'an empty canvas shows the hint and the "Load example" button');
    // Tab through the page to the button, as a keyboard user does.
    let tabs = 0;
    while (await active() !== 'load-example' && tabs < 200) { await page.keyboard.press('Tab'); tabs += 1; }
    check(await active() === 'load-example', `Tab reaches "Load example" (${tabs} presses)`);
    await page.keyboard.press('Enter');
    await settled();
    check(JSON.stringify(last()?.points) === JSON.stringify(EXAMPLE), 'Enter on it loads li-example1\'s points');
    check(await active() === 'canvas' && !(await page.isVisible(sel('empty-hint'))), 'the focus goes to the canvas, the hint goes away');
    await page.keyboard.press('n');
    await page.keyboard.press('n');
    check(await selected() === '1', 'N, N selects point 1');
    const px = await pixel();
    await page.keyboard.press('ArrowUp');
    await page.keyboard.press('ArrowUp');
    await page.keyboard.press('ArrowLeft');
    // (Waits for the nudged request itself: on a loaded machine the live channel's message
    // reached the tracker after settled()'s quiet 300 ms, and the check read the one before.)
    const nudged = (p) => p && Math.abs(p[0] - (3 - px)) < 1e-9 && Math.abs(p[1] - (105 + 2 * px)) < 1e-9;
    await eventually(() => nudged(last()?.points?.[1]));
    await settled();
    const moved = last().points[1];
    check(nudged(moved),
      `↑ ↑ ← move it by screen pixels (${moved.map((v) => v.toFixed(4))}, a pixel is ${px.toFixed(4)})`);
    await page.keyboard.press('o');
    await settled();
    check(JSON.stringify(last().states?.[1]) === '["regular","clamped"]' && Array.isArray(last().out_tangents?.[1]),
      `O clamps the outgoing side (${JSON.stringify(last().states?.[1])})`);
    // Enter: a new point in the middle of the curve's span from point 1 to point 2.
    const fit = await page.evaluate(async (b) => (await fetch('/api/fit', { method: 'POST', body: JSON.stringify(b) })).json(), last());
    const [p0, p1, p2, p3] = fit.segments.find((sg) => sg.span === 1).bezier;
    const mid = [0, 1].map((c) => (p0[c] + 3 * p1[c] + 3 * p2[c] + p3[c]) / 8);
    await page.keyboard.press('Enter');
    await settled();
    const added = last().points[2];
    check(last().points.length === 8 && Math.hypot(added[0] - mid[0], added[1] - mid[1]) < 1e-9 * 120,
      `Enter adds a point after it, in the middle of the curve's span to the next (${added} vs ${mid})`);
    await page.keyboard.press('Shift+p');
    check(await selected() === '1,2', 'Shift+P adds the previous point to the selection');
    await page.keyboard.press('Delete');
    await settled();
    check(last().points.length === 6, 'Delete removes both');
    await page.keyboard.press('Control+z');
    await settled();
    check(last().points.length === 8, 'Ctrl+Z brings them back');
    await page.keyboard.press('Control+z');
    await page.keyboard.press('Control+z');
    await settled();
    check(last().points.length === 7 && last().states === undefined, 'Ctrl+Z undoes the insertion and the state change');
    await page.keyboard.press('Control+z');
    await settled();
    check(JSON.stringify(last().points) === JSON.stringify(EXAMPLE), 'and the nudges (one step)');
    await page.keyboard.press('c');
    await settled();
    check(last().closed === true, 'C closes the curve');
    await page.keyboard.press('Control+z');
    await page.keyboard.press('Control+z');
    await settled();
    check(await page.isVisible(sel('empty-hint')), 'undoing "Load example" empties the canvas again');
    await page.keyboard.press('Control+Shift+z');
    await settled();
  });

  await section('help overlay', async () => {
    await page.keyboard.press('?');
    check(await page.isVisible(sel('help')), '? opens the help overlay');
    check(await active() === 'help-close', 'the focus goes to its Close button');
    const keys = await page.$$eval(`${sel('help-keys')} th`, (ths) => ths.map((t) => t.textContent));
    for (const k of ['?', 'N / P', 'Ctrl+A', 'Esc', '← → ↑ ↓', 'Enter', 'Delete / Backspace', 'K', 'I / O', 'C', 'G', '+ / −', 'F / Shift+F', '[ / ]', 'Ctrl+S']) {
      check(keys.includes(k), `the help lists ${k}`);
    }
    await page.keyboard.press('n'); // not a shortcut while the overlay is open
    check(await selected() === '', 'keys do not reach the canvas under the overlay');
    await page.keyboard.press('Escape');
    check(!(await page.isVisible(sel('help'))) && await active() === 'canvas', 'Esc closes it and gives the focus back to the canvas');
  });

  // A curve with a half-free node, a clamped node with two arrows, a corner angle, a data ball
  // and a selection: the editor's main view.
  const SHOW = {
    p: [[120, 200], [260, 420], [430, 330], [600, 520], [760, 300], [900, 420]], m: 'quasi-elastic',
    s: [0, 2, 0, 4, 0, 0], t: [0, 0, 0, [60, 10], 0, 0], i: [0, 0, 0, [50, -40], 0, 0], d: [0, 0, 25, 0, 0, 0],
    r: [0, 0, 0, 0, 45, 0], k: 1,
  };
  for (const [w, h] of [[1920, 1080], [1280, 800], [800, 600]]) {
    await section(`layout at ${w}×${h}`, async () => {
      await page.setViewportSize({ width: w, height: h });
      await page.goto(url + hashOf(SHOW));
      await page.waitForSelector(sel('curve-quasi-elastic'));
      await page.click(sel('point-3'));
      await settled();
      const m = await page.evaluate(() => {
        const panel = document.querySelector('.panel').getBoundingClientRect();
        const inner = document.querySelector('.panel');
        const right = panel.left + inner.clientWidth; // the scroll bar is not room for controls
        const cut = [...inner.querySelectorAll('input, select, button, textarea')].filter((c) => {
          const r = c.getBoundingClientRect();
          return r.width > 0 && (r.left < panel.left - 0.5 || r.right > right + 0.5);
        }).map((c) => c.dataset.testid ?? c.id ?? c.tagName);
        const canvas = document.getElementById('canvas').getBoundingClientRect();
        return {
          scrollWidth: document.scrollingElement.scrollWidth, innerWidth, cut, canvas: [canvas.width, canvas.height],
          canvasRight: canvas.right,
        };
      });
      check(m.scrollWidth <= m.innerWidth, `no horizontal overflow (scrollWidth ${m.scrollWidth} ≤ ${m.innerWidth})`);
      check(m.cut.length === 0, `no panel control is cut off (${m.cut.join(', ')})`);
      check(m.canvas[0] >= 300 && m.canvas[1] >= 300 && m.canvasRight <= w, `the canvas is on screen (${m.canvas.map(Math.round).join('×')})`);
      // The node panel's fields are reachable: scrolled into view they are visible and usable.
      await page.locator(sel('node-corner')).scrollIntoViewIfNeeded();
      check(await page.isVisible(sel('node-corner')) && await page.isEnabled(sel('state-in')), 'the selected-node panel is usable');
      if (w === 1280) {
        await page.locator(sel('node-panel')).scrollIntoViewIfNeeded();
        await page.screenshot({ path: `${out}/editor-editing.png` });
        await page.keyboard.press('?');
        await page.screenshot({ path: `${out}/editor-help.png` });
        await page.keyboard.press('Escape');
      }
      if (w === 800) {
        await page.evaluate(() => { document.querySelector('.panel').scrollTop = 0; });
        await page.screenshot({ path: `${out}/editor-small.png` });
        await page.keyboard.press('?');
        const box = await page.locator('.help-box').boundingBox();
        check(box.x >= 0 && box.y >= 0 && box.x + box.width <= w && box.y + box.height <= h, 'the help overlay fits the 800×600 window');
        await page.keyboard.press('Escape');
      }
    });
  }
});
