// A course page whose widget host sends no CORS header: the browser loads
// no module, so no widget code runs. What the page wrote inside the
// element (the README's embedding snippet carries a sentence) stays on
// screen and says why; with the module loaded, the widget replaces it.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { baseUrl, openPage, serveForeign, shutdown } from './harness.mjs';

const ROOT = path.resolve(import.meta.dirname, '../..');
const FALLBACK = 'The sensor fusion widget could not load: its host must send CORS headers to this page.';

let project; // the project's server (sends CORS headers)
let bare; // the same widget files from a host that sends none
let course; // the instructor's page, another origin

function coursePage(host) {
  return `<!doctype html>
<html lang="en">
<head><meta charset="utf-8"><title>Course</title><link rel="icon" href="data:,"></head>
<body>
  <h1>Sensor fusion</h1>
  <occgrid-sensor-fusion lidar-beams="12" scans="20" autoplay="off">${FALLBACK}</occgrid-sensor-fusion>
  <script type="module" src="${host}/widgets/sensor-fusion.js"></script>
</body>
</html>
`;
}

before(async () => {
  project = await baseUrl();
  const server = http.createServer((req, res) => {
    const file = path.join(ROOT, path.normalize(new URL(req.url, 'http://x').pathname).replace(/^([/\\])+/, ''));
    if (!file.startsWith(path.join(ROOT, 'widgets')) || !fs.existsSync(file)) {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'Content-Type': 'text/javascript' });
    res.end(fs.readFileSync(file));
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  bare = { origin: `http://127.0.0.1:${server.address().port}`, close: () => new Promise((r) => server.close(r)) };
  course = await serveForeign({ '/bare.html': coursePage(bare.origin), '/cors.html': coursePage(project) });
});

after(async () => {
  await course?.close();
  await bare?.close();
  await shutdown();
});

test('a host without CORS headers: the element keeps the page’s own fallback sentence, on screen', async () => {
  const { page, errors, close } = await openPage(`${course.origin}/bare.html`);
  try {
    // The module's refusal is the state that means the browser is done with it.
    await page.waitForFunction(() => performance.getEntriesByType('resource').some((r) => r.name.endsWith('/widgets/sensor-fusion.js')));
    await page.waitForLoadState('load');
    const widget = page.locator('occgrid-sensor-fusion');
    assert.equal((await widget.textContent()).trim(), FALLBACK);
    assert.equal(await widget.isVisible(), true);
    assert.equal(await page.evaluate(() => customElements.get('occgrid-sensor-fusion') === undefined), true);
    assert.ok(errors.some((e) => /CORS|sensor-fusion\.js/.test(e)), errors.join('\n'));
  } finally {
    await close();
  }
});

test('a host with CORS headers: the widget replaces the fallback and draws', async () => {
  const { page, close } = await openPage(`${course.origin}/cors.html`);
  try {
    await page.waitForFunction(() => document.querySelector('occgrid-sensor-fusion')?.dataset.step === '20');
    const text = await page.locator('occgrid-sensor-fusion').textContent();
    assert.ok(!text.includes(FALLBACK), 'the fallback sentence is gone');
    assert.ok(await page.locator('occgrid-sensor-fusion canvas.sensor-fusion-map').count() > 0);
  } finally {
    await close();
  }
});
