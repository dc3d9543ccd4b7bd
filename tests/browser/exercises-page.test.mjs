// The chapter page's own text in Chromium: every citation of a line of
// Table 9.1 names the line the page's listing of Table 9.1 gives the
// update; the sections come in the chapter's order (the doorway trap
// before the two sensors), with every anchor and exercise link still
// landing on its widget; and the widgets write numbers of four digits and
// more one way, with thousands separators.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

/** The widget modules whose comments and text may cite Table 9.1. */
const MODULES = ['cell-filter.js', 'doorway-trap.js', 'inverse-workbench.js', 'sensor-fusion.js', 'lib/two-cell-table.js'];

test('every "Table 9.1, line N" on the page and in the widgets names the update’s line in the page’s listing of Table 9.1', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const listing = await page.$$eval('#table-9-1 ol > li', (lis) => lis.map((li) => li.textContent.replace(/\s+/g, ' ').trim()));
  assert.equal(listing.length, 9, listing.join('\n'));
  assert.match(listing[0], /^Algorithm occupancy_grid_mapping/);
  const update = listing.findIndex((l) => l.includes('inverse_sensor_model')) + 1;
  assert.ok(update > 0, 'the listing holds the update');
  assert.match(listing[update - 1], /− l0$/, 'the update removes l0');
  const cited = [];
  const text = await page.evaluate(() => document.body.innerText);
  for (const m of text.matchAll(/Table 9\.1, line (\d+)/g)) cited.push(['page', Number(m[1])]);
  for (const file of MODULES) {
    const source = await page.evaluate((f) => fetch(`/widgets/${f}`).then((r) => r.text()), file);
    for (const m of source.matchAll(/Table 9\.1, line (\d+)/g)) cited.push([file, Number(m[1])]);
  }
  assert.ok(cited.some(([where]) => where === 'page'), 'the page cites a line of Table 9.1');
  for (const [where, line] of cited) assert.equal(line, update, `${where} cites Table 9.1, line ${line}; the listing's update is line ${update}`);
  assert.deepEqual(errors, []);
  await close();
});

test('the sections follow the chapter: the doorway trap before the two sensors, numbered in order; anchors and exercise links land on their widgets', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const sections = await page.$$eval('main > section', (ss) => ss.map((s) => ({ id: s.id, heading: s.querySelector('h2').textContent })));
  const widgets = sections.filter((s) => s.id !== 'exercises');
  assert.deepEqual(widgets.map((s) => s.id), ['cell-filter', 'map-weaver', 'inverse-workbench', 'doorway-trap', 'sensor-fusion']);
  assert.deepEqual(widgets.map((s) => Number.parseInt(s.heading, 10)), [1, 2, 3, 4, 5], widgets.map((s) => s.heading).join(' | '));
  for (const { id } of widgets) {
    assert.equal(await page.locator(`#${id} > occgrid-${id}`).count(), 1, `#${id} holds <occgrid-${id}>`);
  }
  const links = await page.$$eval('#exercises a[data-exercise]', (as) => as.map((a) => a.getAttribute('href')));
  for (const href of links) {
    const url = new URL(href, 'http://x/');
    const key = [...url.searchParams.keys()][0].split('.')[0];
    assert.equal(url.hash, `#${key}`, `${href} lands on its widget's section`);
    assert.equal(await page.locator(`${url.hash} occgrid-${key}`).count(), 1);
  }
  assert.deepEqual(errors, []);
  await close();
});

/** Numbers of four or more digits written without separators ("2000", not "2,000" or "0.0047"). */
const ungrouped = (text) => [...text.matchAll(/(?<![\d.,])\d{4,}(?![\d])/g)].map((m) => m[0]);

test('numbers of four digits and more are written with thousands separators in every widget', async () => {
  const readings = 'o'.repeat(1000);
  const { page, errors, close } = await openPage(`/?cell-filter.readings=${readings}&sensor-fusion.lidar-beams=2048&sensor-fusion.scans=2&doorway-trap.scans=1&doorway-trap.autoplay=off`, { reducedMotion: 'reduce' });
  const texts = {};
  const read = async (tag, done) => {
    const w = page.locator(tag);
    await w.scrollIntoViewIfNeeded();
    await page.waitForFunction(done, tag, { timeout: 30_000 });
    texts[tag] = await w.innerText();
  };
  await read('occgrid-cell-filter', (t) => document.querySelector(t).dataset.l !== undefined);
  await read('occgrid-inverse-workbench', (t) => document.querySelector(t).dataset.state === 'ready');
  await read('occgrid-doorway-trap', (t) => document.querySelector(t).dataset.scan === '1');
  await read('occgrid-sensor-fusion', (t) => document.querySelector(t).dataset.step === '2');
  // What the runs above print in the thousands.
  assert.match(texts['occgrid-cell-filter'], /After 1,000 readings/);
  assert.match(texts['occgrid-inverse-workbench'], /Learned from 24,000 triplets/);
  assert.match(texts['occgrid-doorway-trap'], /Scan 1 of 7 · 2,000 cells visited/);
  assert.match(texts['occgrid-sensor-fusion'], /2,048 beams/);
  for (const [tag, text] of Object.entries(texts)) assert.deepEqual(ungrouped(text), [], `${tag}: ${ungrouped(text).join(', ')}`);
  assert.deepEqual(errors, []);
  await close();
});
