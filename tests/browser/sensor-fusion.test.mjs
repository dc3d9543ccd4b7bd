// The chapter page in Chromium: <occgrid-sensor-fusion> plays the table lap,
// shows the footprint's mean occupancy under max fusion and summation, and
// the LiDAR beam-count slider moves the summed result while the max-fused
// one stays.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { canvasColours, openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const SELECTOR = 'occgrid-sensor-fusion';

/** The two footprint means as the page shows them: printed text and exact value. */
const means = (widget) => widget.evaluate((w) => {
  const read = (key) => {
    const out = w.querySelector(`.sensor-fusion-${key} .sensor-fusion-mean`);
    return { text: out.textContent, value: Number(out.dataset.value) };
  };
  return { max: read('max'), sum: read('sum'), beams: Number(w.dataset.lidarBeams), step: Number(w.dataset.step) };
});

async function ready(page) {
  const w = page.locator(SELECTOR);
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction((s) => document.querySelector(s)?.dataset.step !== undefined, SELECTOR);
  return w;
}

test('the lap ends with the table kept by max fusion and erased by summation; fewer LiDAR beams bring it back', async () => {
  // Reduced motion: nothing moves until the reader presses play.
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await ready(page);
  let m = await means(w);
  assert.equal(m.step, 0, 'no autoplay under prefers-reduced-motion');
  assert.equal(m.max.value, 0.5);
  assert.equal(m.sum.value, 0.5);

  await w.getByRole('button', { name: 'Play' }).click();
  assert.equal(await w.getByRole('button', { name: 'Pause' }).getAttribute('aria-pressed'), 'true');
  await page.waitForFunction((s) => document.querySelector(s).dataset.step === '81', SELECTOR, { timeout: 30_000 });
  await w.getByRole('button', { name: 'Play' }).waitFor();
  m = await means(w);
  assert.equal(m.beams, 360);
  assert.ok(m.max.value > 0.55, `max fusion at 360 beams: ${m.max.value}`);
  assert.ok(m.sum.value < 0.10, `summation at 360 beams: ${m.sum.value}`);
  assert.equal(m.max.text, m.max.value.toFixed(3), 'the printed value is the core’s');
  assert.ok((await canvasColours(w, 'canvas', 7)).every((n) => n > 3), 'all four maps are drawn');
  await screenshot(w, 'sensor-fusion-360-beams');

  // Move the slider with the keyboard: Home is 4 beams, one step right 6.
  const slider = w.getByLabel('LiDAR beams');
  await slider.focus();
  await page.keyboard.press('Home');
  await page.keyboard.press('ArrowRight');
  await page.waitForFunction((s) => document.querySelector(s).dataset.lidarBeams === '6', SELECTOR);
  const few = await means(w);
  assert.equal(few.step, 81, 'the maps are rebuilt up to the same scan');
  assert.ok(few.sum.value > 0.5, `summation at 6 beams: ${few.sum.value}`);
  assert.ok(Math.abs(few.max.value - m.max.value) < 0.01, `max fusion moved: ${m.max.value} -> ${few.max.value}`);
  assert.match(await w.locator('.sensor-fusion-lidar figcaption').textContent(), /6 beams/);
  assert.equal(await slider.getAttribute('aria-valuetext'), '6');
  await screenshot(w, 'sensor-fusion-6-beams');

  // And back up: the summed table disappears again.
  await page.keyboard.press('End');
  await page.waitForFunction((s) => document.querySelector(s).dataset.lidarBeams === '720', SELECTOR);
  const many = await means(w);
  assert.ok(many.sum.value < 0.10, `summation at 720 beams: ${many.sum.value}`);

  assert.deepEqual(errors, []);
  await close();
});

test('step and reset drive the core one scan at a time', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await ready(page);
  for (let i = 0; i < 5; i++) await w.getByRole('button', { name: 'Step' }).click();
  let m = await means(w);
  assert.equal(m.step, 5);
  assert.notEqual(m.sum.value, 0.5, 'five scans changed the summed footprint');
  assert.match(await w.locator('.sensor-fusion-status').textContent(), /Scan 5 of 81/);
  await w.getByRole('button', { name: 'Reset' }).click();
  m = await means(w);
  assert.equal(m.step, 0);
  assert.equal(m.max.value, 0.5);
  assert.deepEqual(errors, []);
  await close();
});

test('export map saves the max-fused map as a map_server PGM and YAML pair', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await ready(page);
  for (let i = 0; i < 10; i++) await w.getByRole('button', { name: 'Step' }).click();
  const [download] = await Promise.all([
    page.waitForEvent('download'),
    w.getByRole('button', { name: 'Export map (max fusion)' }).click(),
  ]);
  assert.equal(download.suggestedFilename(), 'table-max.zip');
  const chunks = [];
  for await (const c of await download.createReadStream()) chunks.push(c);
  const zip = Buffer.concat(chunks);
  assert.equal(zip.subarray(0, 2).toString('latin1'), 'PK');
  // The archive names both files, the PGM's header and the YAML's image line.
  const text = zip.toString('latin1');
  assert.match(text, /table-max\.pgm/);
  assert.match(text, /table-max\.yaml/);
  assert.deepEqual(errors, []);
  await close();
});

test('plays on its own when visible without reduced motion', async () => {
  const { page, errors, close } = await openPage('/');
  const w = await ready(page);
  await page.waitForFunction((s) => Number(document.querySelector(s).dataset.step) >= 3, SELECTOR);
  await screenshot(w, 'sensor-fusion-playing');
  assert.deepEqual(errors, []);
  await close();
});

test('a bad attribute is reported inside the widget, naming it', async () => {
  const { page, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await ready(page);
  await page.evaluate((s) => document.querySelector(s).setAttribute('lidar-beams', '0'), SELECTOR);
  const alert = w.locator('.occgrid-error');
  await alert.waitFor();
  assert.match(await alert.textContent(), /lidar-beams.*"0"/);
  // The widget keeps working with the last good value.
  await w.getByRole('button', { name: 'Step' }).click();
  assert.equal((await means(w)).beams, 360);
  await close();
});
