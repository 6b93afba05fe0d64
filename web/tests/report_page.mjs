// Opens a run directory's report.html in headless Chromium and checks its 3D view
// (docs/visualization.md, "The report's 3D view"), driving the browser through the Chrome
// DevTools Protocol:
//   - the page loads from file:// with no console error, no failed request and no uncaught
//     exception (the page must work offline: nothing is fetched from the network);
//   - the 3D view reports ready (document.body.dataset.viewer, web/report_viewer/main.js);
//   - its WebGL canvas is not blank: at least MIN_SHARE of its pixels differ from the
//     background, in at least MIN_COLOURS distinct colours;
//   - a screenshot of the view and its legend is written to OUT_DIR/report_3d.png.
// Usage: node report_page.mjs REPORT_HTML OUT_DIR [CHROMIUM]   (CHROMIUM: /usr/bin/chromium)
// Exit 0 when every check passes, 1 with the reasons otherwise. Bounded: 50 s in all.

import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync, mkdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import WebSocket from 'ws';

const [reportHtml, outDir, chromium = '/usr/bin/chromium'] = process.argv.slice(2);
if (!reportHtml || !outDir) {
  console.error('usage: node report_page.mjs REPORT_HTML OUT_DIR [CHROMIUM]');
  process.exit(2);
}
const MIN_SHARE = 0.02;
const MIN_COLOURS = 16;
const BACKGROUND = [0xf4, 0xf5, 0xf7];  // main.js's BACKGROUND

const profile = mkdtempSync(join(tmpdir(), 'scancrew-chromium-'));
const browser = spawn(chromium, [
  '--headless=new', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader', '--no-first-run', '--no-default-browser-check',
  '--disable-extensions', '--disable-background-networking', '--window-size=1280,1800',
  '--remote-debugging-port=0', `--user-data-dir=${profile}`, 'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe'], detached: true });  // its own process group

const failures = [];
let finished = false;
function finish(code) {
  if (finished) return;
  finished = true;
  for (const f of failures) console.error(`FAIL: ${f}`);
  const exit = () => {
    // the renderer and GPU processes may outlive the browser by a moment
    try {
      rmSync(profile, { recursive: true, force: true, maxRetries: 20, retryDelay: 100 });
    } catch (e) {
      console.error(`note: ${profile} not removed: ${e.message}`);
    }
    process.exit(failures.length ? 1 : code);
  };
  if (browser.exitCode !== null || browser.signalCode !== null) exit();
  browser.once('exit', exit);
  try {
    process.kill(-browser.pid, 'SIGKILL');  // the browser and every process it started
  } catch {
    browser.kill('SIGKILL');
  }
}
const deadline = setTimeout(() => {
  failures.push('timed out after 50 s');
  finish(1);
}, 50000);

// The browser's DevTools endpoint, from its stderr.
const browserUrl = await new Promise((ok, fail) => {
  let text = '';
  browser.stderr.on('data', (d) => {
    text += d;
    const m = text.match(/DevTools listening on (ws:\/\/\S+)/);
    if (m) ok(m[1]);
  });
  browser.on('exit', (code) => fail(new Error(`chromium exited (${code}) before listening: ${text}`)));
}).catch((e) => {
  failures.push(e.message);
  finish(1);
});
const port = new URL(browserUrl).port;
const targets = await (await fetch(`http://127.0.0.1:${port}/json/list`)).json();
const page = targets.find((t) => t.type === 'page');
const ws = new WebSocket(page.webSocketDebuggerUrl, { perMessageDeflate: false });
await new Promise((ok) => ws.once('open', ok));

let nextId = 1;
const pending = new Map();
const listeners = [];
ws.on('message', (raw) => {
  const msg = JSON.parse(raw);
  if (msg.id && pending.has(msg.id)) {
    const { ok, fail } = pending.get(msg.id);
    pending.delete(msg.id);
    if (msg.error) fail(new Error(JSON.stringify(msg.error)));
    else ok(msg.result);
  } else if (msg.method) {
    for (const l of listeners) l(msg);
  }
});
const send = (method, params = {}) =>
  new Promise((ok, fail) => {
    const id = nextId++;
    pending.set(id, { ok, fail });
    ws.send(JSON.stringify({ id, method, params }));
  });
const evaluate = async (expression) => {
  const r = await send('Runtime.evaluate', { expression, returnByValue: true, awaitPromise: true });
  if (r.exceptionDetails) throw new Error(`evaluate: ${JSON.stringify(r.exceptionDetails)}`);
  return r.result.value;
};

// every console error, uncaught exception, failed request and log error is a failure
listeners.push((msg) => {
  const p = msg.params;
  if (msg.method === 'Runtime.consoleAPICalled' && (p.type === 'error' || p.type === 'assert'))
    failures.push(`console.${p.type}: ${p.args.map((a) => a.value ?? a.description).join(' ')}`);
  if (msg.method === 'Runtime.exceptionThrown')
    failures.push(`uncaught exception: ${p.exceptionDetails.exception?.description ?? p.exceptionDetails.text}`);
  if (msg.method === 'Log.entryAdded' && p.entry.level === 'error')
    failures.push(`log error (${p.entry.source}): ${p.entry.text} ${p.entry.url ?? ''}`);
  if (msg.method === 'Network.loadingFailed')
    failures.push(`request failed: ${p.errorText} (${p.requestId})`);
  if (msg.method === 'Network.requestWillBeSent' && !p.request.url.startsWith('file:') &&
      !p.request.url.startsWith('data:'))
    failures.push(`network request from an offline page: ${p.request.url}`);
});

try {
  await Promise.all(['Runtime.enable', 'Log.enable', 'Page.enable', 'Network.enable'].map((m) => send(m)));
  const loaded = new Promise((ok) => listeners.push((m) => m.method === 'Page.loadEventFired' && ok()));
  await send('Page.navigate', { url: pathToFileURL(resolve(reportHtml)).href });
  await loaded;
  let state = '';
  for (let i = 0; i < 100 && !state; ++i) {
    state = await evaluate('document.body.dataset.viewer || ""');
    if (!state) await new Promise((ok) => setTimeout(ok, 100));
  }
  if (state !== 'ready') failures.push(`3D view not ready: '${state}'`);

  // the canvas' pixels: share not background, distinct colours (preserveDrawingBuffer)
  const pixels = await evaluate(`(() => {
    const c = document.querySelector('#scancrew-3d canvas');
    if (!c) return null;
    const t = document.createElement('canvas');
    t.width = c.width; t.height = c.height;
    const g = t.getContext('2d');
    g.drawImage(c, 0, 0);
    const d = g.getImageData(0, 0, t.width, t.height).data;
    let other = 0; const colours = new Set();
    for (let i = 0; i < d.length; i += 4) {
      const far = Math.abs(d[i] - ${BACKGROUND[0]}) + Math.abs(d[i + 1] - ${BACKGROUND[1]}) +
                  Math.abs(d[i + 2] - ${BACKGROUND[2]});
      if (far > 12) { ++other; colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]); }
    }
    return { width: t.width, height: t.height, other, colours: colours.size };
  })()`);
  if (!pixels) {
    failures.push('no canvas in #scancrew-3d');
  } else {
    const share = pixels.other / (pixels.width * pixels.height);
    console.log(`canvas ${pixels.width}x${pixels.height}: ${(100 * share).toFixed(1)} % not ` +
                `background, ${pixels.colours} colours`);
    if (share < MIN_SHARE) failures.push(`canvas blank: ${(100 * share).toFixed(2)} % drawn`);
    if (pixels.colours < MIN_COLOURS) failures.push(`canvas flat: ${pixels.colours} colours`);
  }
  const legendRows = await evaluate('document.querySelectorAll("#scancrew-3d-legend .v3d-row").length');
  console.log(`legend rows: ${legendRows}`);
  if (legendRows < 4) failures.push(`legend has ${legendRows} rows`);

  // the screenshot: the view's heading, canvas and legend
  const clip = await evaluate(`(() => {
    const h = [...document.querySelectorAll('h2')].find((e) => e.textContent === '3D view');
    h.scrollIntoView();
    const top = h.getBoundingClientRect().top + window.scrollY;
    const legend = document.getElementById('scancrew-3d-legend').nextElementSibling;
    const bottom = legend.getBoundingClientRect().bottom + window.scrollY;
    const r = document.getElementById('scancrew-3d').getBoundingClientRect();
    return { x: r.left - 8, y: top - 8, width: r.width + 16, height: bottom - top + 16, scale: 1 };
  })()`);
  const shot = await send('Page.captureScreenshot', { format: 'png', clip, captureBeyondViewport: true });
  mkdirSync(outDir, { recursive: true });
  writeFileSync(join(outDir, 'report_3d.png'), Buffer.from(shot.data, 'base64'));
  console.log(`screenshot: ${join(outDir, 'report_3d.png')}`);
} catch (e) {
  failures.push(String(e.stack || e));
}
clearTimeout(deadline);
if (!failures.length) console.log('report page ok');
finish(0);
