// The readouts in reach, in Chromium: Map Weaver's cell readout sits over
// the map being pointed at, on screen at 1280 x 800 with the map at the top
// of the window; on a 390 x 844 phone a tap reads the cell under the finger
// (a tap fires no pointermove, and the focus it gives the map must not put
// the keyboard's cursor cell there instead), in Map Weaver and in the
// doorway trap. The phone runs in a touch context of its own.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { chromium } from 'playwright-core';
import { baseUrl, openPage, screenshot, shutdown } from './harness.mjs';

let phoneBrowser = null;
after(async () => {
  await phoneBrowser?.close();
  await shutdown();
});

/** A phone page: 390 x 844 CSS pixels, touch, `{ page, errors, close }`. */
async function openPhone(urlPath) {
  phoneBrowser ??= await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run', '--disable-quic'],
  });
  const context = await phoneBrowser.newContext({ viewport: { width: 390, height: 844 }, hasTouch: true, isMobile: true, deviceScaleFactor: 2, reducedMotion: 'reduce' });
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(`${await baseUrl()}${urlPath}`, { waitUntil: 'load' });
  return { page, errors, close: () => context.close() };
}

const W = 'occgrid-map-weaver';

/** Waits for Map Weaver's run and `scans` scans. */
async function weaverReady(page, scans) {
  await page.locator(W).scrollIntoViewIfNeeded();
  await page.waitForFunction(([t, s]) => document.querySelector(t).dataset.scans === String(s), [W, scans], { timeout: 60_000 });
}

/** Puts the top of pane `side`'s map at the top of the window; its box. */
async function mapAtTop(page, side) {
  const canvas = page.locator(`${W} .map-weaver-${side} canvas.map-weaver-map`);
  await canvas.evaluate((c) => c.scrollIntoView({ block: 'start' }));
  return { canvas, box: await canvas.boundingBox() };
}

/** The point (viewport CSS pixels) over image cell (col, row) of a `w x h` map drawn in `box`. */
const over = (box, col, row, w, h) => ({ x: box.x + ((col + 0.5) / w) * box.width, y: box.y + ((row + 0.5) / h) * box.height });

/** Asserts that `locator`'s box lies inside the `width x height` viewport. */
async function onScreen(locator, width, height, what) {
  const b = await locator.boundingBox();
  assert.ok(b, `${what}: shown`);
  assert.ok(b.y >= -1 && b.y + b.height <= height + 1 && b.x >= -1 && b.x + b.width <= width + 1,
    `${what}: at x ${b.x.toFixed(0)}–${(b.x + b.width).toFixed(0)}, y ${b.y.toFixed(0)}–${(b.y + b.height).toFixed(0)}, inside ${width} x ${height}`);
  return b;
}

test('Map Weaver at 1280 x 800: with the map at the top of the window, the readout of the hovered cell is on screen, over the map', async () => {
  const { page, errors, close } = await openPage('/?map-weaver.autoplay=off&map-weaver.scans=120#map-weaver', { viewport: { width: 1280, height: 800 }, reducedMotion: 'reduce' });
  await weaverReady(page, 120);
  for (const side of ['left', 'right']) {
    const { box } = await mapAtTop(page, side);
    // A cell near the map's bottom edge and one near its top.
    for (const [col, row] of [[60, 85], [60, 4]]) {
      await page.mouse.move(...Object.values(over(box, col, row, 120, 90)));
      const hover = page.locator(`${W} .map-weaver-hover`);
      await hover.filter({ hasText: new RegExp(`cell \\(${col}, ${89 - row}\\)`) }).waitFor({ timeout: 5000 });
      const b = await onScreen(hover, 1280, 800, `${side} map, cell (${col}, ${89 - row})`);
      // Over the map, and clear of the pointed cell.
      assert.ok(b.y >= box.y - 1 && b.y + b.height <= box.y + box.height + 1, `${side}: over the map`);
      const y = over(box, col, row, 120, 90).y;
      assert.ok(y < b.y || y > b.y + b.height, `${side}: the readout leaves cell row ${row} visible`);
    }
    await screenshot(page, `map-weaver-hover-at-top-${side}-1280`);
  }
  // Leaving the map hides the readout; the hint below the maps stays.
  await page.mouse.move(5, 5);
  await page.waitForFunction((t) => document.querySelector(`${t} .map-weaver-hover`).hidden, W);
  assert.match(await page.locator(`${W} .map-weaver-hover-hint`).textContent(), /Point at a cell/);
  assert.deepEqual(errors, []);
  await close();
});

test('Map Weaver on a 390 x 844 phone: a tap reads the tapped cell, on screen over the map', async () => {
  const { page, errors, close } = await openPhone('/?map-weaver.autoplay=off&map-weaver.scans=120#map-weaver');
  await weaverReady(page, 120);
  const { canvas, box } = await mapAtTop(page, 'left');
  // The corridor's floor cell and a wall cell of the kitchen, tapped in turn.
  for (const [col, row] of [[61, 41], [30, 55]]) {
    const p = over(box, col, row, 120, 90);
    await page.touchscreen.tap(p.x, p.y);
    const hover = page.locator(`${W} .map-weaver-hover`);
    await page.waitForFunction((t) => !document.querySelector(`${t} .map-weaver-hover`).hidden, W);
    const text = await hover.textContent();
    assert.match(text, new RegExp(`Left map, cell \\(${col}, ${89 - row}\\)`), `tapped (${col}, ${89 - row}): ${text}`);
    await onScreen(hover, 390, 844, `after the tap at (${col}, ${89 - row})`);
  }
  assert.equal(await canvas.evaluate((c) => document.activeElement === c), true, 'the tap focused the map');
  await screenshot(page, 'map-weaver-tap-390');
  assert.deepEqual(errors, []);
  await close();
});

test('the doorway trap on a 390 x 844 phone: a tap reads the tapped cell, not the doorway', async () => {
  const { page, errors, close } = await openPhone('/?doorway-trap.autoplay=off&doorway-trap.scans=24&doorway-trap.flips=4#doorway-trap');
  const w = page.locator('occgrid-doorway-trap');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap').dataset.flips === '4', null, { timeout: 60_000 });
  const canvas = w.locator('.doorway-trap-pane canvas').first();
  await canvas.evaluate((c) => c.scrollIntoView({ block: 'center' }));
  const box = await canvas.boundingBox();
  const { width, height } = await w.evaluate((el) => el.view);
  // A cell well away from the doorway: a quarter in from the left, a third down.
  const col = Math.floor(width / 4);
  const row = Math.floor(height / 3);
  const p = over(box, col, row, width, height);
  await page.touchscreen.tap(p.x, p.y);
  const out = w.locator('.doorway-trap-hover');
  await out.filter({ hasText: /cell \(\d+, \d+\)/i }).waitFor({ timeout: 5000 });
  const text = await out.textContent();
  assert.match(text, new RegExp(`cell \\(${col}, ${height - 1 - row}\\)`, 'i'), `tapped (${col}, ${height - 1 - row}): ${text}`);
  assert.deepEqual(errors, []);
  await close();
});
