// Opens pages of the chapter in Debian's Chromium (driven by playwright-core)
// against the project's own server on a free loopback port (with the test
// pages of fixtures/ at /test-fixtures/), and collects
// every console error and uncaught page error.
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { listen } from '../../scripts/serve.mjs';

const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
const FLAGS = [
  '--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--disable-background-networking',
  '--disable-component-update', '--disable-sync', '--no-first-run', '--disable-quic',
];
export const SCREENSHOTS = path.resolve(path.dirname(new URL(import.meta.url).pathname), 'screenshots');

let shared = null;

const LAUNCH_ATTEMPTS = 3;

/**
 * Starts Chromium, trying again when a launch dies (a browser that crashes
 * while starting up, as one did once on a loaded machine, is no test result).
 */
async function launchBrowser() {
  for (let attempt = 1; ; attempt += 1) {
    try {
      return await chromium.launch({ executablePath: CHROMIUM, args: FLAGS, headless: true });
    } catch (e) {
      if (attempt >= LAUNCH_ATTEMPTS) throw e;
      console.error(`Chromium did not start (attempt ${attempt} of ${LAUNCH_ATTEMPTS}): ${String(e.message).split('\n')[0]}`);
    }
  }
}

/**
 * One server and one browser for the whole test file. When the browser
 * cannot start, the server is closed again: a listening server would keep the
 * test file's process alive after its tests have failed.
 */
async function startShared() {
  if (!shared) {
    shared = (async () => {
      const { server, port } = await listen(0, { fixtures: true });
      try {
        const browser = await launchBrowser();
        return { server, port, browser };
      } catch (e) {
        await new Promise((r) => server.close(r));
        throw e;
      }
    })();
  }
  return shared;
}

/** The base URL of the test server, e.g. http://127.0.0.1:PORT */
export async function baseUrl() {
  const { port } = await startShared();
  return `http://127.0.0.1:${port}`;
}

/**
 * Opens `urlPath` and returns `{ page, errors, logs, close }`. `errors`
 * holds the text of every console error and page error seen so far, `logs`
 * every console message as `{ type, text }`.
 */
export async function openPage(urlPath = '/', { viewport = { width: 1200, height: 900 }, reducedMotion = 'no-preference', deviceScaleFactor = 1 } = {}) {
  const { port, browser } = await startShared();
  const context = await browser.newContext({ viewport, reducedMotion, deviceScaleFactor });
  const page = await context.newPage();
  const errors = [];
  // Content-Security-Policy violations become console errors too (Chromium
  // logs most of them itself; this catches every one, with its directive).
  await page.addInitScript(() => {
    document.addEventListener('securitypolicyviolation', (e) => {
      console.error(`CSP violation: ${e.violatedDirective} blocked ${e.blockedURI || 'inline code'}`);
    });
  });
  const logs = [];
  page.on('console', (m) => {
    logs.push({ type: m.type(), text: m.text() });
    if (m.type() === 'error') errors.push(m.text());
  });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
  const url = urlPath.startsWith('http') ? urlPath : `http://127.0.0.1:${port}${urlPath}`;
  await page.goto(url, { waitUntil: 'load' });
  return { page, errors, logs, close: () => context.close() };
}

/**
 * Serves `pages` (URL path → HTML text) from a second server on another
 * loopback port: another origin, like an instructor's own site that embeds
 * widgets from the project's server. `headers` are added to every page
 * (e.g. a Content-Security-Policy). Resolves to `{ origin, close() }`.
 */
export async function serveForeign(pages, { headers = {} } = {}) {
  const server = http.createServer((req, res) => {
    const { pathname } = new URL(req.url, 'http://localhost');
    const body = pages[pathname];
    if (body === undefined) {
      res.writeHead(404, { 'Content-Type': 'text/plain; charset=utf-8' });
      res.end(`Not found: ${pathname}\n`);
      return;
    }
    res.writeHead(200, { 'Content-Type': 'text/html; charset=utf-8', 'Cache-Control': 'no-store', ...headers });
    res.end(body);
  });
  await new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(0, '127.0.0.1', resolve);
  });
  return {
    origin: `http://127.0.0.1:${server.address().port}`,
    close: () => new Promise((r) => server.close(r)),
  };
}

/** Saves a screenshot of a locator or page under tests/browser/screenshots/. */
/**
 * How many distinct colours (RGBA) each canvas matching `selector` inside
 * `widget` holds, sampling every `step`-th pixel: a blank canvas has one.
 */
export const canvasColours = (widget, selector, step = 5) => widget.evaluate((w, [sel, k]) => [...w.querySelectorAll(sel)].map((c) => {
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  const seen = new Set();
  for (let i = 0; i < d.length; i += 4 * k) seen.add((d[i] << 24) | (d[i + 1] << 16) | (d[i + 2] << 8) | d[i + 3]);
  return seen.size;
}), [selector, step]);

export async function screenshot(target, name) {
  fs.mkdirSync(SCREENSHOTS, { recursive: true });
  const file = path.join(SCREENSHOTS, `${name}.png`);
  await target.screenshot({ path: file });
  return file;
}

/** Closes the shared browser and server (call from `after`). */
export async function shutdown() {
  if (!shared) return;
  const started = shared;
  shared = null;
  // A browser that never started has already closed its server.
  const { server, browser } = await started.catch(() => ({}));
  if (!browser) return;
  await browser.close();
  await new Promise((r) => server.close(r));
}
