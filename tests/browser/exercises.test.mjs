// The chapter's "Exercises" section in Chromium: every exercise link opens
// the page with the widget it names in the state the link describes. The
// state is read back from the widget itself (its "Copy link" control
// writes the widget's current settings as a link, and Map Weaver's panes
// say their settings in their data attributes), and nothing reaches the
// console. The exercise-6 link also works on an instructor's bare page
// that embeds Map Weaver alone. Screenshots of exercise 6: a LiDAR pane
// beside a 22° cone pane.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { baseUrl, openPage, screenshot, serveForeign, shutdown } from './harness.mjs';

after(shutdown);

/** The exercise links of the chapter page: `{ n, href, text }`. */
async function exerciseLinks() {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const links = await page.$$eval('#exercises a[data-exercise]', (as) =>
    as.map((a) => ({ n: Number(a.dataset.exercise), href: a.getAttribute('href'), text: a.textContent })));
  assert.deepEqual(errors, []);
  await close();
  return links;
}

/** A value as text the way two spellings of it compare equal ("0.20" = "0.2", "1,0,2,0" = "1, 0, 2, 0"). */
const normal = (text) => {
  const parts = String(text).split(/[\s,;]+/).filter(Boolean);
  if (parts.length && parts.every((p) => p !== '' && Number.isFinite(Number(p)))) return parts.map(Number).join(',');
  return String(text).trim().toLowerCase();
};

/** Waits for the widget to be drawn, presses its "Copy link" and returns the link's state for it. */
async function copiedState(page, tag, key) {
  const widget = page.locator(tag);
  await widget.scrollIntoViewIfNeeded();
  await page.waitForFunction((t) => {
    const w = document.querySelector(t);
    // A link's scans are integrated first (Map Weaver's run is made after them).
    const made = t !== 'occgrid-map-weaver' || (!!w?.weaver && w.dataset.fastForward === undefined);
    return w && w.built && made && !w.querySelector('.occgrid-error:not([hidden])') && w.querySelector('canvas')?.width > 0;
  }, tag, { timeout: 60_000 });
  // Let the core's first frame land.
  await page.waitForTimeout(300);
  await widget.getByRole('button', { name: /^Copy link/ }).first().click();
  await page.waitForFunction((t) => document.querySelector(t).dataset.link, tag);
  const link = await widget.evaluate((w) => w.dataset.link);
  const out = new Map();
  for (const [k, v] of new URL(link).searchParams) if (k.startsWith(`${key}.`)) out.set(k.slice(key.length + 1), v);
  return out;
}

/** Map Weaver's two panes as the page says them. */
const weaverPanes = (page) => page.$$eval('occgrid-map-weaver .map-weaver-pane', (panes) =>
  panes.map((p) => ({ ...p.dataset })));

test('every exercise link opens its widget in the state it names, with no console errors', async () => {
  const links = await exerciseLinks();
  assert.deepEqual(links.map((l) => l.n), [1, 2, 3, 4, 5, 6, 7, 8], 'one link per exercise, in order');
  for (const { n, href } of links) {
    const url = new URL(href, 'http://x/');
    const params = [...url.searchParams];
    assert.ok(params.length > 0, `exercise ${n}: the link carries state`);
    const key = params[0][0].split('.')[0];
    assert.ok(params.every(([k]) => k.startsWith(`${key}.`)), `exercise ${n}: one widget per link`);
    const tag = `occgrid-${key}`;
    const { page, errors, close } = await openPage(`/${url.search}${url.hash}`, { reducedMotion: 'reduce' });
    // The fragment is the section that holds the widget.
    const inSection = await page.evaluate(([id, t]) => !!document.getElementById(id)?.querySelector(t), [url.hash.slice(1), tag]);
    assert.ok(inSection, `exercise ${n}: ${url.hash} holds <${tag}>`);
    const state = await copiedState(page, tag, key);
    const spec = await page.evaluate((t) => {
      const s = customElements.get(t).attributeSpec;
      return Object.fromEntries(Object.entries(s).map(([k, v]) => [k, v.default ?? null]));
    }, tag);
    for (const [k, v] of params) {
      const name = k.slice(key.length + 1);
      assert.ok(name in spec, `exercise ${n}: ${name} is an attribute of <${tag}>`);
      // A link leaves out a setting at its default.
      const now = state.has(name) ? state.get(name) : spec[name];
      assert.equal(normal(now), normal(v), `exercise ${n}: ${name} reads back as ${now}, the link says ${v}`);
    }
    if (key === 'map-weaver') {
      const panes = await weaverPanes(page);
      const side = (s) => panes[s === 'left' ? 0 : 1];
      for (const [k, v] of params) {
        const m = /^map-weaver\.(left|right)-(model|mapper|sensor|beta|forget-l0|strength)$/.exec(k);
        if (!m) continue;
        const field = { model: 'model', mapper: 'mapper', sensor: 'sensor', beta: 'betaDeg', 'forget-l0': 'forgetL0' }[m[2]];
        if (!field) continue;
        const want = m[2] === 'forget-l0' ? String(v === 'on') : v;
        assert.equal(side(m[1])[field], want, `exercise ${n}: the ${m[1]} pane's ${field}`);
      }
    }
    assert.deepEqual(errors, [], `exercise ${n}: console errors`);
    await close();
  }
});

test('exercise 6 on an instructor’s page that embeds Map Weaver alone; screenshots of a LiDAR pane beside a 22° cone pane', async () => {
  const links = await exerciseLinks();
  const six = new URL(links.find((l) => l.n === 6).href, 'http://x/');
  const project = await baseUrl();
  const foreign = await serveForeign({
    '/embed.html': `<!doctype html><html lang="en"><head><meta charset="utf-8"><title>Embedded Map Weaver</title><link rel="icon" href="data:,"></head>
<body><h1>Exercise 6</h1><occgrid-map-weaver></occgrid-map-weaver>
<script type="module" src="${project}/widgets/map-weaver.js"></script></body></html>`,
  });
  try {
    const { page, errors, close } = await openPage(`${foreign.origin}/embed.html${six.search}`, { reducedMotion: 'reduce' });
    await copiedState(page, 'occgrid-map-weaver', 'map-weaver');
    const [left, right] = await weaverPanes(page);
    assert.deepEqual([left.mapper, left.sensor, right.mapper, right.sensor, right.betaDeg], ['traversal', 'lidar', 'sweep', 'cone', '22']);
    // A lap's first 20 s, then the two maps side by side.
    const w = page.locator('occgrid-map-weaver');
    for (let i = 0; i < 4; i++) await w.getByRole('button', { name: 'Step' }).click();
    await page.evaluate(() => {
      const el = document.querySelector('occgrid-map-weaver');
      el.weaver.advance(236);
      el.draw(true);
    });
    const [l, r] = await weaverPanes(page);
    assert.equal(Number(r.cellsVisited), 10_800, 'the sweep visits every cell');
    assert.ok(Number(l.cellsVisited) < 3000, `the traversal visits the beams' cells: ${l.cellsVisited}`);
    assert.ok(Number(r.scanMs) > 0 && Number(l.scanMs) >= 0 && l.scanMs !== '', 'core time per scan shown per pane');
    console.log(`exercise 6 after 240 scans: traversal ${l.cellsVisited} cells, ${l.scanMs} ms per scan; sweep (22° cone) ${r.cellsVisited} cells, ${r.scanMs} ms per scan`);
    await screenshot(page.locator('occgrid-map-weaver .map-weaver-panes'), 'exercise-6-lidar-beside-cone');
    // Both panes on the cone: the traversal still paints only its beams.
    await page.selectOption('occgrid-map-weaver .map-weaver-left select[name="sensor-left"]', 'cone');
    await page.waitForFunction(() => document.querySelector('occgrid-map-weaver .map-weaver-left').dataset.sensor === 'cone');
    await screenshot(page.locator('occgrid-map-weaver .map-weaver-panes'), 'exercise-6-cone-traversal-beside-sweep');
    assert.deepEqual(errors, []);
    await close();
  } finally {
    await foreign.close();
  }
});
