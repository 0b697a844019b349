// End-to-end test of the web editor in headless Debian chromium (playwright-core, no browser
// download). Started by CTest (web.e2e) with FAIRSPLINE_CLI (the fairspline binary),
// FAIRSPLINE_WEB_ROOT (apps/web/static) and FAIRSPLINE_E2E_OUT (screenshots).
import { spawn } from 'node:child_process';
import { mkdirSync } from 'node:fs';
import { chromium } from 'playwright-core';

const cli = process.env.FAIRSPLINE_CLI;
const root = process.env.FAIRSPLINE_WEB_ROOT;
const out = process.env.FAIRSPLINE_E2E_OUT ?? 'e2e-out';
if (!cli || !root) throw new Error('set FAIRSPLINE_CLI and FAIRSPLINE_WEB_ROOT');
mkdirSync(out, { recursive: true });

let failures = 0;
function check(condition, what) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
  if (!condition) failures += 1;
}

/** Starts `fairspline serve --port 0` and resolves with its base URL. */
function startServer() {
  const server = spawn(cli, ['serve', '--port', '0', '--root', root], { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    let text = '';
    server.stdout.on('data', (chunk) => {
      text += chunk;
      const m = text.match(/serving (http:\/\/[^\s]+)/);
      if (m) resolve({ server, url: m[1] });
    });
    server.on('exit', (code) => reject(new Error(`server exited with ${code}`)));
    setTimeout(() => reject(new Error('server did not start')), 10000);
  });
}

const { server, url } = await startServer();
const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForSelector('[data-testid="method"] option', { state: 'attached' });
  const method = await page.$eval('[data-testid="method"]', (s) => s.value);
  check(method === 'quasi-elastic', `default method selected (${method})`);

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
  const before = await curve.first().getAttribute('d');
  check(before && before.includes('C'), 'the quasi-elastic curve is drawn with cubic Béziers');

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
  const combLines = await page.locator('.comb line, .comb path, [data-testid="comb-lines"] *').count();
  check(combLines > 10, `the curvature comb is drawn (${combLines} elements)`);

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

  check(errors.length === 0, `no JavaScript errors (${errors.join('; ')})`);
} finally {
  await browser.close();
  server.kill();
}
if (failures > 0) {
  console.error(`${failures} check(s) failed`);
  process.exit(1);
}
console.log('all browser checks passed');
