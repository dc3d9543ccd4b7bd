// Readers on phones and laptops, in Chromium: on a 390 x 844 touch phone a
// tap on a map cell of the real-log panel, the doorway trap, sensor fusion
// and the inverse workbench shows that cell's values (the core's) inside
// the window, over the map tapped; at 1280 x 800 hovering the real-log map
// does too. The real-log panel shows its colours' legend, and on a phone
// one map at a time at the panel's width, with buttons to switch.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { chromium } from 'playwright-core';
import { baseUrl, openPage, screenshot, shutdown } from './harness.mjs';

let phoneBrowser = null;
after(async () => {
  await phoneBrowser?.close();
  await shutdown();
});

const PHONE = { width: 390, height: 844 };
const LAPTOP = { width: 1280, height: 800 };

/** A phone page: 390 x 844 CSS pixels, touch, `{ page, errors, close }`. */
async function openPhone(urlPath) {
  phoneBrowser ??= await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run', '--disable-quic'],
  });
  const context = await phoneBrowser.newContext({ viewport: PHONE, hasTouch: true, isMobile: true, deviceScaleFactor: 2, reducedMotion: 'reduce' });
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(`${await baseUrl()}${urlPath}`, { waitUntil: 'load' });
  return { page, errors, close: () => context.close() };
}

/** Asserts that `locator`'s box lies inside the `size` viewport; the box. */
async function onScreen(locator, { width, height }, what) {
  const b = await locator.boundingBox();
  assert.ok(b, `${what}: shown`);
  assert.ok(b.y >= -1 && b.y + b.height <= height + 1 && b.x >= -1 && b.x + b.width <= width + 1,
    `${what}: at x ${b.x.toFixed(0)}–${(b.x + b.width).toFixed(0)}, y ${b.y.toFixed(0)}–${(b.y + b.height).toFixed(0)}, inside ${width} x ${height}`);
  return b;
}

/** Asserts that box `b` lies over the map box `map` (within a pixel). */
function overMap(b, map, what) {
  assert.ok(b.y >= map.y - 1 && b.y + b.height <= map.y + map.height + 1, `${what}: over the map (readout y ${b.y.toFixed(0)}–${(b.y + b.height).toFixed(0)}, map ${map.y.toFixed(0)}–${(map.y + map.height).toFixed(0)})`);
}

const LOG_LINK = '/?map-weaver.mode=log&map-weaver.log=intel-corrected.log.gz#map-weaver';
/** The same log at dead-reckoned poses: two maps, the corrected one beside it. */
const TWO_MAPS = '/?map-weaver.mode=log&map-weaver.log=intel-corrected.log.gz&map-weaver.log-poses=dead-reckoning#map-weaver';

/** Waits for the real-log panel to finish mapping the linked log. */
async function logDone(page) {
  // The panel reads its log once it is on screen.
  await page.locator('.map-weaver-log-stage').evaluate((e) => e.scrollIntoView({ block: 'center' }));
  await page.waitForFunction(() => document.querySelector('occgrid-map-weaver .map-weaver-log')?.dataset.state === 'done', null, { timeout: 120_000 });
}

test('real log on a phone: a tap on the map reads the tapped cell, over the map and on screen', async () => {
  const { page, errors, close } = await openPhone(LOG_LINK);
  await logDone(page);
  const canvas = page.locator('.map-weaver-log-map');
  await canvas.evaluate((c) => c.scrollIntoView({ block: 'center' }));
  for (const [fx, fy] of [[0.5, 0.45], [0.4, 0.8]]) {
    const box = await canvas.boundingBox();
    await page.touchscreen.tap(box.x + fx * box.width, box.y + fy * box.height);
    await page.waitForFunction(() => document.querySelector('.map-weaver-log-readout').dataset.l !== undefined);
    const shown = await page.locator('.map-weaver-log-readout').evaluate((e) => ({ ...e.dataset, text: e.textContent }));
    assert.match(shown.text, /^cell \(\d+, \d+\) at /);
    // The cell is the core's, under the finger.
    const expected = await page.evaluate(({ ix, iy }) => {
      const p = document.querySelector('occgrid-map-weaver').realLog;
      return p.session.cellAt(0, ix, p.geometry.height - 1 - iy);
    }, { ix: Number(shown.ix), iy: Number(shown.iy) });
    assert.equal(Number(shown.p), expected.p);
    const float = page.locator('.map-weaver-log .occgrid-floating-readout');
    assert.equal(await float.textContent(), shown.text);
    overMap(await onScreen(float, PHONE, `readout after a tap at ${fx}, ${fy}`), box, 'real-log readout');
    // A lifted finger leaves the map at once: the cell stays read out.
    assert.equal(await page.locator('.map-weaver-log-readout').evaluate((e) => e.dataset.l !== undefined), true);
  }
  await screenshot(page, 'phones-real-log-tap-390');
  assert.deepEqual(errors, []);
  await close();
});

test('real log at 1280 x 800: hovering the map reads the cell inside the window, over the map', async () => {
  const { page, errors, close } = await openPage(LOG_LINK, { viewport: LAPTOP, reducedMotion: 'reduce' });
  await logDone(page);
  const canvas = page.locator('.map-weaver-log-map');
  await canvas.evaluate((c) => c.scrollIntoView({ block: 'start' }));
  const box = await canvas.boundingBox();
  for (const fy of [0.1, 0.9]) {
    const y = box.y + fy * box.height;
    await page.mouse.move(box.x + 0.5 * box.width, y);
    await page.waitForFunction(() => document.querySelector('.map-weaver-log-readout').dataset.l !== undefined);
    const float = page.locator('.map-weaver-log .occgrid-floating-readout');
    await float.filter({ hasText: /^cell \(/ }).waitFor({ timeout: 5000 });
    const b = await onScreen(float, LAPTOP, `hover at ${fy} of the map's height`);
    overMap(b, box, 'real-log readout');
    assert.ok(y < b.y || y > b.y + b.height, 'the readout leaves the hovered cell visible');
  }
  // A mouse leaving the map clears the readout.
  await page.mouse.move(2, 2);
  await page.waitForFunction(() => document.querySelector('.map-weaver-log .occgrid-floating-readout').hidden);
  assert.equal(await page.locator('.map-weaver-log-readout').evaluate((e) => e.dataset.l), undefined);
  assert.deepEqual(errors, []);
  await close();
});

test('real log: a legend of the map colours on screen; on a phone one map at a time at the panel width, with a switcher', async () => {
  const { page, errors, close } = await openPhone(TWO_MAPS);
  await logDone(page);
  const legend = page.locator('.map-weaver-log-legend');
  await legend.scrollIntoViewIfNeeded();
  assert.match(await legend.textContent(), /unknown.*free.*occupied.*path/);
  assert.equal(await legend.isVisible(), true);
  const panes = await page.evaluate(() => document.querySelector('occgrid-map-weaver').realLog.session.state().panes.length);
  assert.ok(panes >= 2, `the linked log maps ${panes} panes`);
  const switcher = page.locator('.map-weaver-log-switch');
  assert.equal(await switcher.isVisible(), true, 'the switcher is shown on a phone');
  assert.equal(await switcher.locator('button').count(), panes);
  const displayed = () => page.evaluate(() => [...document.querySelectorAll('.map-weaver-log-stage > figure')]
    .map((f, k) => { const r = f.querySelector('canvas').getBoundingClientRect(); return [k, getComputedStyle(f).display !== 'none', Math.max(r.width, r.height)]; })
    .filter(([, shown]) => shown));
  let shown = await displayed();
  assert.equal(shown.length, 1, 'one map displayed');
  assert.equal(shown[0][0], 0, 'the operated map first');
  assert.ok(shown[0][2] >= 300, `the map's longer side is ${shown[0][2]} px, not a thumbnail's`);
  await switcher.locator('button').nth(1).click();
  shown = await displayed();
  assert.deepEqual(shown.map(([k]) => k), [1], 'the second map after its button');
  // At the first map's scale (one log, one scale): the dead-reckoned map
  // covers less ground, and was a 77-105 px thumbnail side by side.
  assert.ok(shown[0][2] >= 200, `the second map's longer side is ${shown[0][2]} px`);
  // It is drawn: more than one colour.
  const colours = await page.evaluate(() => {
    const c = document.querySelectorAll('.map-weaver-log-stage > figure canvas')[1];
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < d.length; i += 4 * 7) seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
    return seen.size;
  });
  assert.ok(colours > 2, `the second map drawn (${colours} colours)`);
  await screenshot(page, 'phones-real-log-switcher-390');
  assert.deepEqual(errors, []);
  await close();

  // At 1280 x 800 the maps stand side by side, no switcher.
  const wide = await openPage(TWO_MAPS, { viewport: LAPTOP, reducedMotion: 'reduce' });
  await logDone(wide.page);
  assert.equal(await wide.page.locator('.map-weaver-log-switch').isVisible(), false);
  assert.equal(await wide.page.locator('.map-weaver-log-legend').isVisible(), true);
  assert.deepEqual(wide.errors, []);
  await wide.close();
});

test('doorway trap on a phone: the tapped cell is read over the map tapped, on screen', async () => {
  const { page, errors, close } = await openPhone('/?doorway-trap.autoplay=off&doorway-trap.scans=24&doorway-trap.flips=4#doorway-trap');
  const w = page.locator('occgrid-doorway-trap');
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap').dataset.flips === '4', null, { timeout: 60_000 });
  for (const k of [0, 1]) {
    const canvas = w.locator('.doorway-trap-pane canvas').nth(k);
    await canvas.evaluate((c) => c.scrollIntoView({ block: 'center' }));
    const box = await canvas.boundingBox();
    await page.touchscreen.tap(box.x + 0.3 * box.width, box.y + 0.3 * box.height);
    const float = w.locator('.occgrid-floating-readout');
    await float.filter({ hasText: /^Cell \(/ }).waitFor({ timeout: 5000 });
    assert.equal(await float.textContent(), await w.locator('.doorway-trap-hover').textContent());
    overMap(await onScreen(float, PHONE, `doorway trap map ${k}`), box, `doorway trap map ${k}`);
  }
  await screenshot(page, 'phones-doorway-trap-tap-390');
  assert.deepEqual(errors, []);
  await close();
});

test('sensor fusion on a phone: a tap reads the cell in all four maps (eq. 9.9 on the cell), on screen', async () => {
  const { page, errors, close } = await openPhone('/?sensor-fusion.autoplay=off&sensor-fusion.scans=60#sensor-fusion');
  const w = page.locator('occgrid-sensor-fusion');
  await page.waitForFunction(() => document.querySelector('occgrid-sensor-fusion').dataset.step === '60', null, { timeout: 60_000 });
  for (const k of [0, 2]) {
    const canvas = w.locator('canvas.sensor-fusion-map').nth(k);
    await canvas.evaluate((c) => c.scrollIntoView({ block: 'center' }));
    const box = await canvas.boundingBox();
    // The middle of the room: the table.
    await page.touchscreen.tap(box.x + 0.5 * box.width, box.y + 0.5 * box.height);
    const out = w.locator('.sensor-fusion-cell');
    await out.filter({ hasText: /^Cell \(/ }).waitFor({ timeout: 5000 });
    const d = await out.evaluate((e) => ({ ...e.dataset, text: e.textContent }));
    assert.equal(Number(d.max), Math.max(Number(d.sonar), Number(d.lidar)), 'eq. 9.9 on the tapped cell');
    assert.match(d.text, /sonar p = \d\.\d{3}, LiDAR p = \d\.\d{3}, max p = \d\.\d{3}, summed p = \d\.\d{3}/);
    const float = w.locator('.occgrid-floating-readout');
    assert.equal(await float.textContent(), d.text);
    overMap(await onScreen(float, PHONE, `sensor fusion map ${k}`), box, `sensor fusion map ${k}`);
  }
  await screenshot(page, 'phones-sensor-fusion-tap-390');
  assert.deepEqual(errors, []);
  await close();
});

test('inverse workbench on a phone: a tap reads both models at the tapped cell (the images’ own values), on screen', async () => {
  const { page, errors, close } = await openPhone('/#inverse-workbench');
  const w = page.locator('occgrid-inverse-workbench');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.state === 'ready', null, { timeout: 120_000 });
  const canvas = w.locator('canvas.inverse-workbench-image').first();
  await canvas.evaluate((c) => c.scrollIntoView({ block: 'center' }));
  const box = await canvas.boundingBox();
  const geom = await w.evaluate((el) => el.panes[0].geom);
  // On the beam axis, a third of the way along the image.
  await page.touchscreen.tap(box.x + geom.left + geom.w / 3, box.y + geom.h / 2);
  const out = w.locator('.inverse-workbench-cell');
  await out.filter({ hasText: /^Range / }).waitFor({ timeout: 5000 });
  const d = await out.evaluate((e) => ({ ...e.dataset, text: e.textContent }));
  // The values are those the images draw at that lattice sample.
  const field = await w.evaluate((el, r) => {
    const l = el.lattice;
    const v = el.bench.view(el.z, l);
    let best = 0;
    for (let i = 1; i < l.ranges; i++) if (Math.abs(v.rangeAxis[i] - r.range) < Math.abs(v.rangeAxis[best] - r.range)) best = i;
    let bj = 0;
    for (let j = 1; j < l.bearings; j++) if (Math.abs(v.bearingAxis[j] - r.bearing) < Math.abs(v.bearingAxis[bj] - r.bearing)) bj = j;
    return { hand: v.hand[bj * l.ranges + best], learned: v.learned[bj * l.ranges + best] };
  }, { range: Number(d.range), bearing: Number(d.bearing) });
  assert.equal(Number(d.hand), field.hand);
  assert.equal(Number(d.learned), field.learned);
  const float = w.locator('.occgrid-floating-readout');
  assert.equal(await float.textContent(), d.text);
  overMap(await onScreen(float, PHONE, 'workbench readout'), box, 'workbench readout');
  await screenshot(page, 'phones-inverse-workbench-tap-390');
  assert.deepEqual(errors, []);
  await close();
});

test('inverse workbench: Reset returns the reading, the zoom and the model’s seed to what the page opened with', async () => {
  const { page, errors, close } = await openPage('/?inverse-workbench.reading=2.50#inverse-workbench', { viewport: LAPTOP, reducedMotion: 'reduce' });
  const w = page.locator('occgrid-inverse-workbench');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.seed === '9', null, { timeout: 120_000 });
  // The reader moves the reading, zooms and retrains with another seed.
  await w.evaluate((el) => {
    const input = el.querySelector('input[name=reading]');
    input.value = '4';
    input.dispatchEvent(new Event('input', { bubbles: true }));
  });
  await w.getByLabel(/^Zoom to/).check();
  await w.locator('input[name=seed]').fill('12');
  await w.getByRole('button', { name: 'Retrain', exact: true }).click();
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.seed === '12', null, { timeout: 120_000 });
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.reading === '4');
  await w.locator('button[name=reset]').click();
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.seed === '9', null, { timeout: 120_000 });
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.reading === '2.5');
  assert.equal(await w.getByLabel(/^Zoom to/).isChecked(), false);
  assert.equal(await w.locator('input[name=seed]').inputValue(), '9');
  assert.equal(await w.locator('input[name=reading]').inputValue(), '2.5');
  assert.deepEqual(errors, []);
  await close();
});
