// What a shared link may do to a widget (docs/ARCHITECTURE.md, "Bad input"): set the attributes the
// widget declares, nothing else. The course page here has no
// Content-Security-Policy, as many instructors' pages do not, so an event
// handler a link managed to set would run: `style=content-visibility:auto`
// with `oncontentvisibilityautostatechange` runs with no user action, and
// `style=position:fixed;inset:0` with `onmouseover` on the first hover. The
// link's other keys are ignored with a console warning naming each, and the
// declared attributes in the same link still restore.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { baseUrl, openPage, screenshot, serveForeign, shutdown } from './harness.mjs';

let project; // the project's server, where the widgets come from
let course; // the instructor's page, another origin, no CSP

before(async () => {
  project = await baseUrl();
  const page = (title, body, module) => `<!doctype html>
<html lang="en">
<head>
  <meta charset="utf-8">
  <title>${title}</title>
  <link rel="icon" href="data:,">
</head>
<body>
  <h1>${title}</h1>
  <p>A course page with no Content-Security-Policy.</p>
  ${body}
  <script type="module" src="${project}/widgets/${module}.js"></script>
</body>
</html>
`;
  course = await serveForeign({
    '/cell-filter.html': page('Cell filter', '<occgrid-cell-filter readings="ooff"></occgrid-cell-filter>', 'cell-filter'),
    '/map-weaver.html': page('Map weaver', '<occgrid-map-weaver laps="1" scans="40" autoplay="off"></occgrid-map-weaver>', 'map-weaver'),
  });
});

after(async () => {
  await course?.close();
  await shutdown();
});

/** Waits for two rendering updates (content-visibility events fire in one). */
const twoFrames = (page) => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));

/** The element's attribute names that a link must never set. */
const forbidden = (widget) => widget.evaluate((w) => w.getAttributeNames().filter((n) => n.startsWith('on') || ['style', 'id', 'class'].includes(n)));

/** The console warnings that name `key` as ignored. */
const ignoredWarnings = (logs, key) => logs.filter((l) => l.type === 'warning' && l.text.includes(`ignored "${key}"`));

test('a cell-filter link with a content-visibility handler runs no script; its readings still restore', async () => {
  const query = [
    'cell-filter.style=content-visibility:auto',
    'cell-filter.oncontentvisibilityautostatechange=window.x%3D1',
    'cell-filter.onclick=window.x%3D2',
    'cell-filter.id=elsewhere',
    'cell-filter.class=occgrid-link',
    'cell-filter.constructor=x',
    'cell-filter.readings=oof',
  ].join('&');
  const { page, errors, logs, close } = await openPage(`${course.origin}/cell-filter.html?${query}`);
  try {
    const widget = page.locator('occgrid-cell-filter');
    // The link's three readings replace the page's four (one row each, and one for the prior).
    await page.waitForFunction(() => document.querySelectorAll('occgrid-cell-filter .cell-filter-table tbody tr').length === 4);
    assert.equal(await widget.getAttribute('readings'), 'oof');
    await twoFrames(page);
    assert.equal(await page.evaluate(() => typeof window.x), 'undefined', 'a handler from the link ran with no user action');
    await widget.click();
    await twoFrames(page);
    assert.equal(await page.evaluate(() => typeof window.x), 'undefined', 'a handler from the link ran on a click');
    assert.deepEqual(await forbidden(widget), []);
    assert.equal(await widget.getAttribute('constructor'), null);
    for (const name of ['style', 'oncontentvisibilityautostatechange', 'onclick', 'id', 'class', 'constructor']) {
      assert.equal(ignoredWarnings(logs, `cell-filter.${name}`).length, 1, `a warning names cell-filter.${name}: ${JSON.stringify(logs)}`);
    }
    assert.deepEqual(errors, []);
    await screenshot(page, 'link-safety-cell-filter');
  } finally {
    await close();
  }
});

test('a map-weaver link with a page-covering mouseover handler runs no script on hover; its scans still restore', async () => {
  const query = 'map-weaver.onmouseover=window.y%3D1&map-weaver.style=position:fixed;inset:0&map-weaver.scans=12&map-weaver.autoplay=off';
  const { page, errors, logs, close } = await openPage(`${course.origin}/map-weaver.html?${query}`);
  try {
    const widget = page.locator('occgrid-map-weaver');
    await page.waitForFunction(() => document.querySelector('occgrid-map-weaver')?.dataset.scans === '12');
    assert.equal(await widget.getAttribute('scans'), '12');
    // The first hover anywhere on the page, then one on the widget itself.
    await page.mouse.move(5, 5);
    await page.mouse.move(600, 450);
    await widget.hover();
    await twoFrames(page);
    assert.equal(await page.evaluate(() => typeof window.y), 'undefined', 'a handler from the link ran');
    assert.deepEqual(await forbidden(widget), []);
    assert.notEqual(await widget.evaluate((w) => getComputedStyle(w).position), 'fixed');
    for (const name of ['onmouseover', 'style']) {
      assert.equal(ignoredWarnings(logs, `map-weaver.${name}`).length, 1, `a warning names map-weaver.${name}`);
    }
    // The link gave `scans` but not `laps`: the course page's own
    // `laps="1"` stays (a link replaces only the attributes it names).
    assert.equal(await widget.getAttribute('laps'), '1');
    assert.deepEqual(errors, []);
    await screenshot(page, 'link-safety-map-weaver');
  } finally {
    await close();
  }
});
