// The real-log panel's dataset menu and copied link, in Chromium. On the
// project's server the menu names every log of datasets/ descriptively, as
// the datasets README's table does; a bundle (scripts/dist.mjs) carries no
// logs, answers the panel's question with an empty listing, and the page
// asks for nothing that is not there (no 404); the copied link says what it
// keeps (a log of the server's, never a file of the reader's own).
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import http from 'node:http';
import { spawnSync } from 'node:child_process';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const ROOT = path.resolve(import.meta.dirname, '../..');
const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(ROOT, '../shared/datasets');
const PANEL = 'occgrid-map-weaver .map-weaver-log';

/** Switches the page's Map Weaver to its real-log panel and waits for the menu to be decided. */
async function realLog(page) {
  const w = page.locator('occgrid-map-weaver');
  await w.scrollIntoViewIfNeeded();
  await w.getByLabel('Real log').check();
  await page.locator(PANEL).waitFor();
  // Decided once the server's listing has answered (or failed): before, the
  // menu holds its placeholder alone, and under load the listing came after
  // the menu was read.
  await page.locator(`${PANEL} select[name=dataset][data-listed]`).waitFor({ state: 'attached', timeout: 30_000 });
  return w;
}

test('the dataset menu names every log of datasets/ by its place and scans, as its README’s table does', async () => {
  const { page, errors, close } = await openPage('/#map-weaver', { reducedMotion: 'reduce' });
  await realLog(page);
  const options = await page.locator(`${PANEL} select[name=dataset] option`).evaluateAll((os) => os.map((o) => [o.value, o.textContent]));
  const logs = fs.readdirSync(DATASETS).filter((f) => f.endsWith('.log.gz') || f.endsWith('.mcap'));
  assert.deepEqual(options.slice(1).map(([v]) => v).sort(), logs.sort());
  for (const [file, label] of options.slice(1)) {
    assert.notEqual(label, file, `${file} has a descriptive name`);
    // A bag is named by the log it was made from.
    const named = file.endsWith('.mcap') ? /^\S+\.mcap \(ROS 2 bag of \S+\.log\.gz\)$/ : /^[A-Z][^()]+ \([\d,]+ scans\)$/;
    assert.match(label, named, `${file}: ${label}`);
  }
  console.log(`the dataset menu: ${options.slice(1).map(([, l]) => l).join('; ')}`);
  assert.deepEqual(errors, []);
  await close();
});

test('Copy link in real-log mode says what the link keeps: the server’s log, or the settings without a file of the reader’s own', async () => {
  const { page, errors, close } = await openPage('/#map-weaver', { reducedMotion: 'reduce' });
  await page.context().grantPermissions(['clipboard-read', 'clipboard-write'], { origin: new URL(page.url()).origin });
  const w = await realLog(page);
  const status = w.locator('.occgrid-link-status');
  const copy = async () => {
    await w.getByRole('button', { name: /^Copy link/ }).click();
    const s = 'occgrid-map-weaver .occgrid-link-status';
    await page.waitForFunction((q) => document.querySelector(q).textContent !== '', s);
    const text = await status.textContent();
    await page.evaluate((q) => { document.querySelector(q).textContent = ''; }, s);
    return text;
  };
  assert.match(await copy(), /no log is loaded/);
  const aces = fs.readFileSync(path.join(DATASETS, 'aces-corrected.log.gz'));
  await page.setInputFiles(`${PANEL} input[type=file]`, { name: 'my-lab.log.gz', mimeType: 'application/gzip', buffer: aces });
  await page.waitForFunction((s) => document.querySelector(s).dataset.state === 'done', `${PANEL}`, { timeout: 60_000 });
  const local = await copy();
  assert.match(local, /keeps the real-log settings but not my-lab\.log\.gz, a file on this computer/);
  await page.locator(`${PANEL} select[name=dataset]`).selectOption('aces-corrected.log.gz');
  await page.waitForFunction((s) => document.querySelector(s).dataset.state === 'done', `${PANEL}`, { timeout: 60_000 });
  assert.match(await copy(), /with aces-corrected\.log\.gz from the server’s datasets/);
  assert.deepEqual(errors, []);
  await close();
});

test('a bundle without datasets: switching to Real log asks for nothing the bundle lacks, and offers no menu', async () => {
  const out = fs.mkdtempSync(path.join(os.tmpdir(), 'occgrid-bundle-'));
  const dir = path.join(out, 'site');
  const r = spawnSync(process.execPath, [path.join(ROOT, 'scripts/dist.mjs'), '--out', dir], { encoding: 'utf8' });
  assert.equal(r.status, 0, r.stderr);
  // A plain static server: files or 404, nothing else.
  const missing = [];
  const server = http.createServer((req, res) => {
    const p = path.join(dir, decodeURIComponent(new URL(req.url, 'http://x').pathname));
    if (!p.startsWith(dir) || !fs.existsSync(p) || fs.statSync(p).isDirectory()) {
      missing.push(req.url);
      res.writeHead(404).end();
      return;
    }
    const type = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.wasm': 'application/wasm', '.json': 'application/json', '.svg': 'image/svg+xml', '.md': 'text/markdown' }[path.extname(p)] ?? 'application/octet-stream';
    res.writeHead(200, { 'Content-Type': type }).end(fs.readFileSync(p));
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  try {
    const { page, errors, close } = await openPage(`http://127.0.0.1:${server.address().port}/index.html#map-weaver`, { reducedMotion: 'reduce' });
    await realLog(page);
    assert.equal(await page.locator(`${PANEL} select[name=dataset]`).getAttribute('data-listed'), '0');
    assert.equal(await page.locator(`${PANEL} select[name=dataset]`).isVisible(), false, 'no menu: nothing to list');
    assert.deepEqual(missing, [], 'every request the page made was for a file the bundle has');
    assert.deepEqual(errors, []);
    await close();
  } finally {
    await new Promise((resolve) => server.close(resolve));
    fs.rmSync(out, { recursive: true, force: true });
  }
});
