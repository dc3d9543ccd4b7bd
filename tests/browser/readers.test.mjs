// The chapter page in Chromium, read back as a reader sees it: every
// readout explained and always true. The workbench's colour scale is the
// same at every reading; Map Weaver's charts end at the readouts' values
// after a paused slider change, and its hover line empties when the pointer
// leaves; counting axes have whole ticks and the per-beam bars say which
// scan and which beam; the MAP pane draws the cells no cone reached gray;
// controls that both panes have are named by pane; the cell filter says
// when the cell sits at the clamp and when a "free" reading means occupied.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

async function widget(page, selector, readyKey) {
  const w = page.locator(selector);
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(([s, k]) => document.querySelector(s)?.dataset[k] !== undefined, [selector, readyKey], { timeout: 60_000 });
  return w;
}

test('the workbench draws every reading on one colour scale, stated on the legend', async () => {
  const { page, errors, close } = await openPage('/');
  const w = await widget(page, 'occgrid-inverse-workbench', 'state');
  const legend = () => w.evaluate((el) => ({
    scale: el.dataset.scale,
    reading: el.dataset.reading,
    label: el.querySelector('canvas.inverse-workbench-legend').getAttribute('aria-label'),
    text: el.querySelector('.inverse-workbench-scale-text')?.textContent ?? '',
  }));
  const at2 = await legend();
  assert.equal(at2.reading, '2');
  await w.getByRole('button', { name: 'Max-range reading' }).click();
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.reading === '8');
  const atMax = await legend();
  assert.equal(atMax.scale, at2.scale, 'one scale at 2 m and at the max range');
  assert.equal(atMax.label, at2.label, 'the legend reads the same at both readings');
  assert.match(atMax.text, /same at every reading/);
  assert.match(atMax.label, new RegExp(`\\+${Number(at2.scale).toFixed(2)}`));
  assert.deepEqual(errors, []);
  await close();
});

test('Map Weaver: after a paused clamp change the charts end where the readouts are', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await widget(page, 'occgrid-map-weaver', 'scans');
  await w.evaluate((el) => el.setAttribute('scans', '180'));
  await page.waitForFunction(() => document.querySelector('occgrid-map-weaver').dataset.scans === '180', null, { timeout: 60_000 });
  const charts = () => w.evaluate((el) => ({
    entropy: Number(el.querySelector('.map-weaver-left').dataset.entropy),
    entropyLast: el.entropyChart.plot.data[1].at(-1),
    // The left pane's three tracked cells, last points.
    trackedLast: [1, 2, 3].map((j) => el.panes[0].chart.plot.data[j].at(-1)),
    scans: Number(el.dataset.scans),
  }));
  const before = await charts();
  assert.ok(Math.max(...before.trackedLast.map(Math.abs)) > 2, `a tracked cell beyond ±2: ${before.trackedLast}`);
  await w.locator('.map-weaver-left input[name=clamp-left]').fill('2');
  // The pane is rebuilt over the scans so far in slices: wait until it is.
  await page.waitForFunction((e) => {
    const pane = document.querySelector('occgrid-map-weaver .map-weaver-left');
    return pane.dataset.behind === '0' && Number(pane.dataset.entropy) !== e;
  }, before.entropy, { timeout: 60_000 });
  const after = await charts();
  assert.equal(after.scans, before.scans, 'paused: no scan came in');
  assert.notEqual(after.entropy, before.entropy, 'the readout moved');
  assert.equal(after.entropyLast, after.entropy, 'the entropy curve ends at the readout');
  assert.ok(after.trackedLast.every((l) => Math.abs(l) <= 2 + 1e-6), `tracked cells within the new clamp: ${after.trackedLast}`);
  assert.deepEqual(errors, []);
  await close();
});

test('Map Weaver: the hover line empties when the pointer leaves the map', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await widget(page, 'occgrid-map-weaver', 'scans');
  // Hover a cell, then leave the map: the line no longer names a cell.
  const canvas = w.locator('.map-weaver-left canvas.map-weaver-map');
  const box = await canvas.boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  const hover = w.locator('.map-weaver-hover');
  await assert.doesNotReject(hover.filter({ hasText: /cell \(\d/ }).waitFor({ timeout: 5000 }));
  await page.mouse.move(box.x + box.width / 2, box.y - 40);
  await page.waitForTimeout(100);
  const text = await hover.textContent();
  assert.doesNotMatch(text, /cell \(\d/, `hover line after the pointer left: ${text}`);
  assert.equal(await hover.getAttribute('data-l'), null);
  assert.deepEqual(errors, []);
  await close();
});

test('the doorway trap: whole flip ticks, and bars named by scan and beam', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await widget(page, 'occgrid-doorway-trap', 'flips');
  const step = w.locator('button[name=map-step]');
  await step.click();
  await step.click();
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap').dataset.flips === '2');
  const axes = await w.evaluate((el) => ({
    flipTicks: el.curve.plot.axes[0]._splits,
    barLabels: el.bars.plot.axes[0]._values,
    barText: el.querySelector('.doorway-trap-bars').getAttribute('aria-label'),
  }));
  assert.ok(axes.flipTicks.length >= 2 && axes.flipTicks.every(Number.isInteger), `flip ticks: ${axes.flipTicks}`);
  const labels = axes.barLabels.filter((l) => l !== '');
  assert.ok(labels.length > 0 && labels.every((l) => /^scan \d+\nbeam \d+$|^prior$/.test(l)), `bar labels: ${JSON.stringify(labels)}`);
  assert.match(axes.barText, /scan \d+, beam \d+ [+-]/);
  assert.deepEqual(errors, []);
  await close();
});

test('the doorway trap: the MAP pane draws the cells no cone reached gray; its Reset buttons say which', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await widget(page, 'occgrid-doorway-trap', 'flips');

  // Run the climb to its end: the cells no cone reached are gray, as many
  // as the export marks unknown (205 in a map_server PGM).
  await w.evaluate((el) => el.setAttribute('flips', '100000'));
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap').dataset.converged === 'true', null, { timeout: 60_000 });
  const map = await w.evaluate((el) => {
    const n = el.view.width * el.view.height;
    const px = new Uint8Array(el.memory.buffer, el.trap.mapRender(), n * 4);
    let gray = 0;
    for (let i = 0; i < px.length; i += 4) gray += px[i] === 128 ? 1 : 0;
    const pgm = el.trap.exportMap('map').pgm;
    let unknown = 0;
    for (let i = pgm.length - n; i < pgm.length; i++) unknown += pgm[i] === 205 ? 1 : 0;
    return { gray, unknown, caption: el.querySelector('.occgrid-caption').textContent };
  });
  assert.ok(map.unknown > 0, 'the room has cells no cone reaches');
  assert.equal(map.gray, map.unknown, 'the MAP pane draws gray exactly the cells its export marks unknown');
  assert.match(map.caption, /no uncertainty about the cells it decided/);

  const resets = await w.locator('button[name$=-reset]').allTextContents();
  assert.equal(new Set(resets).size, resets.length, `reset buttons: ${resets}`);
  assert.deepEqual(errors, []);
  await close();
});

test('controls both Map Weaver panes have are named by pane', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const w = await widget(page, 'occgrid-map-weaver', 'scans');
  const snapshot = await w.locator('.map-weaver-panes').ariaSnapshot();
  const names = [...snapshot.matchAll(/- (checkbox|slider|button) "([^"]+)"/g)].map((m) => `${m[1]} ${m[2]}`);
  assert.ok(names.length >= 8, snapshot);
  const dupes = names.filter((n, i) => names.indexOf(n) !== i);
  assert.deepEqual(dupes, [], `duplicate names: ${dupes}`);
  assert.ok(names.includes('checkbox Learned model, left map') && names.includes('slider Clamp l_max, right map'), names.join('; '));
  assert.deepEqual(errors, []);
  await close();
});

test('the cell filter says when the cell reaches the clamp, labels p and warns of an inverted model', async () => {
  const { page, errors, close } = await openPage('/');
  const w = await widget(page, 'occgrid-cell-filter', 'l');
  await w.getByRole('button', { name: 'Clear readings' }).click();
  const occupied = w.getByRole('button', { name: 'Occupied reading' });
  // l_occ = logit 0.7 = 0.847: 14 readings give 11.86, the 15th would pass 12.
  for (let i = 0; i < 14; i++) await occupied.click();
  assert.equal(await w.locator('.cell-filter-notice-clamp').count(), 0, 'not at the clamp after 14 readings');
  await occupied.click();
  await occupied.click();
  const rows = await w.locator('.cell-filter-table tbody tr').count();
  assert.equal(rows, 17, 'the prior row and 16 readings');
  const notice = w.locator('.cell-filter-notice-clamp');
  assert.equal(await notice.count(), 1, 'the clamp is announced');
  // p = 1 - 6.1e-6: four decimals would print 1.0000.
  assert.match(await notice.textContent(), /reading 15 on, l is held at the clamp of ±12\.0 \(l = 12\.0000, p = 1 − 6\.1 × 10⁻⁶\)/);
  const meter = w.getByRole('meter');
  assert.equal(await meter.getAttribute('aria-valuetext'), 'p = 1 − 6.1 × 10⁻⁶');
  assert.match(await meter.getAttribute('aria-label'), /probability that the cell is occupied/);


  await w.getByLabel('p(m | free reading)').fill('0.8');
  const inverted = w.locator('.cell-filter-notice-inverted');
  assert.equal(await inverted.count(), 1);
  assert.match(await inverted.textContent(), /0\.80 is not below p\(m \| occupied reading\) = 0\.70/);
  await w.getByLabel('p(m | free reading)').fill('0.3');
  assert.equal(await inverted.count(), 0);
  assert.deepEqual(errors, []);
  await close();
});
