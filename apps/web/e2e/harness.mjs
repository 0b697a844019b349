// Shared set-up of the browser tests: the server on a free loopback port, Debian's headless
// chromium through playwright-core (never a browser download), and a check() that counts
// failures. Environment (set by CTest): FAIRSPLINE_CLI (the fairspline binary),
// FAIRSPLINE_WEB_ROOT (apps/web/static), FAIRSPLINE_E2E_OUT (screenshots).
import { spawn } from 'node:child_process';
import { mkdirSync } from 'node:fs';
import { chromium } from 'playwright-core';

const cli = process.env.FAIRSPLINE_CLI;
const root = process.env.FAIRSPLINE_WEB_ROOT;
export const out = process.env.FAIRSPLINE_E2E_OUT ?? 'e2e-out';
if (!cli || !root) throw new Error('set FAIRSPLINE_CLI and FAIRSPLINE_WEB_ROOT');
mkdirSync(out, { recursive: true });

let failures = 0;
export function check(condition, what) {
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

/**
 * Runs body({page, url, errors}) against a fresh server and browser, then closes both and
 * exits with status 1 if any check failed (or body threw).
 */
export async function run(body) {
  const { server, url } = await startServer();
  const browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    await body({ page, url, errors });
    check(errors.length === 0, `no JavaScript errors (${errors.join('; ')})`);
  } catch (e) {
    console.error(e);
    failures += 1;
  } finally {
    await browser.close();
    server.kill();
  }
  if (failures > 0) {
    console.error(`${failures} check(s) failed`);
    process.exit(1);
  }
  console.log('all browser checks passed');
}

/** Number of cubic pieces in a path's data. */
/** Runs one section of a test's checks: a wait that times out (or any throw) fails that section
 * only, and its duration is printed. */
export async function section(name, body) {
  const started = Date.now();
  try {
    await body();
  } catch (e) {
    check(false, `${name}: ${String(e.message).split('\n')[0]}`);
  }
  console.log(`info: ${name} took ${((Date.now() - started) / 1000).toFixed(1)} s`);
}

export const cubics = (d) => (d?.match(/C/g) ?? []).length;

/** Waits until the main curve of `method` has `n` cubic pieces. */
export function waitForPieces(page, method, n) {
  return page.waitForFunction(([m, k]) => (document.querySelector(`[data-testid="curve-${m}"]`)
    ?.getAttribute('d')?.match(/C/g) ?? []).length === k, [method, n]);
}

/** The URL hash that opens the editor on these points (and other state fields). */
export function hashOf(state) {
  return `#${encodeURIComponent(JSON.stringify(state))}`;
}

/** Polls `probe` until it returns a truthy value (or the time is up); returns the last value. */
export async function eventually(probe, ms = 5000) {
  const end = Date.now() + ms;
  let v = await probe();
  while (!v && Date.now() < end) {
    await new Promise((r) => setTimeout(r, 100));
    v = await probe();
  }
  return v;
}

/**
 * Watches the page's fits, POST /api/fit requests and messages of the live channel (the
 * WebSocket /api/live): `requests` holds their bodies, `settled()` waits until none is in
 * flight and none was sent for 300 ms (10× the editor's debounce), so that what is drawn is the
 * fit of the current state. A navigation drops the requests of the page it leaves: one cut off
 * by it gets neither requestfinished nor requestfailed, and counting it made every later
 * settled() wait its full 10 s.
 */
export function trackFits(page) {
  const requests = [];
  const inFlight = new Set();
  let liveInFlight = 0; // the channel answers its messages in order, one answer each
  let lastActivity = Date.now();
  page.on('websocket', (ws) => {
    if (!ws.url().endsWith('/api/live')) return;
    ws.on('framesent', (f) => {
      requests.push(JSON.parse(f.payload));
      liveInFlight += 1;
      lastActivity = Date.now();
    });
    ws.on('framereceived', () => {
      liveInFlight = Math.max(0, liveInFlight - 1);
      lastActivity = Date.now();
    });
    ws.on('close', () => { liveInFlight = 0; });
  });
  const isFit = (r) => r.url().endsWith('/api/fit');
  page.on('request', (r) => {
    if (!isFit(r)) return;
    requests.push(JSON.parse(r.postData()));
    inFlight.add(r);
    lastActivity = Date.now();
  });
  const done = (r) => {
    if (!inFlight.delete(r)) return;
    lastActivity = Date.now();
  };
  page.on('requestfinished', done);
  page.on('requestfailed', done);
  page.on('framenavigated', (frame) => {
    if (frame !== page.mainFrame()) return;
    inFlight.clear();
    liveInFlight = 0;
  });
  const settled = () => eventually(() => inFlight.size === 0 && liveInFlight === 0 && Date.now() - lastActivity > 300, 10000);
  return { requests, settled };
}
