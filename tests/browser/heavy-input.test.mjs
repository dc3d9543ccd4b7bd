// docs/ARCHITECTURE.md, "Bad input": a link asking for a huge amount of work never freezes the tab.
// Map Weaver's `scans` is checked against the core's work budget and done
// in time slices with the count on screen; the cell filter's `readings`
// has a budget and a bounded table. The longest main-thread task of each
// page is reported as a diagnostic (speed targets live in benchmarks, not
// in assertions).
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

/**
 * Installed before the page's scripts: records every long task (buffered,
 * so those before the observer count too), and polls Map Weaver's status
 * line as tasks of its own. A poller sees an intermediate count only if
 * the page yielded between slices: one synchronous call would show none.
 */
function observe() {
  window.__longTasks = [];
  try {
    new PerformanceObserver((list) => {
      for (const e of list.getEntries()) window.__longTasks.push({ start: e.startTime, ms: e.duration });
    }).observe({ type: 'longtask', buffered: true });
  } catch {
    // No long-task timing in this browser: the diagnostic says so.
  }
  window.__progress = [];
  const poll = () => {
    const el = document.querySelector('occgrid-map-weaver');
    const text = el?.querySelector('.map-weaver-status')?.textContent ?? '';
    if (/scans: [\d,]+ done/.test(text) && window.__progress.at(-1)?.text !== text) {
      window.__progress.push({ text, at: performance.now() });
    }
    setTimeout(poll, 0);
  };
  poll();
}

/** Opens `urlPath` with `observe` installed before any script of the page. */
async function openObserved(urlPath, options) {
  const opened = await openPage('/favicon.svg', options);
  await opened.page.addInitScript(observe);
  // Only the page under test counts (a bare image asks for /favicon.ico).
  await opened.page.waitForLoadState('networkidle');
  opened.errors.length = 0;
  await opened.page.goto(new URL(urlPath, opened.page.url()).href);
  return opened;
}

const longest = (tasks) => tasks.reduce((m, t) => Math.max(m, t.ms), 0);

test('the heavy link from the hardening report is refused by the core, naming scans and the budget', async (t) => {
  const scene = encodeURIComponent('{"width":960,"height":720,"resolution":0.0125,"scan_rate":60}');
  const { page, errors, close } = await openObserved(
    `/?map-weaver.scans=1000000&map-weaver.laps=20&map-weaver.scene=${scene}#map-weaver`);
  const w = page.locator('occgrid-map-weaver');
  await w.scrollIntoViewIfNeeded();
  const alert = w.locator(':scope > .occgrid-error[role="alert"]');
  await alert.waitFor({ timeout: 60_000 });
  const text = await alert.textContent();
  assert.match(text, /^invalid scans: 1000000 \(65280 scans x 76800 cell visits = 5013504000\)/);
  assert.match(text, /at most 250000000 cell visits before the first frame/);
  assert.match(await w.locator('.map-weaver-status').textContent(), /No run: see the message above/);
  // The page still answers: the reader can press a button of another widget.
  await page.locator('occgrid-cell-filter').getByRole('button', { name: 'Occupied reading' }).click();
  await page.waitForFunction(() => document.querySelectorAll('occgrid-cell-filter .cell-filter-table tbody tr').length === 5);
  const tasks = await page.evaluate(() => window.__longTasks);
  t.diagnostic(`heavy link: longest main-thread task ${longest(tasks).toFixed(0)} ms (${tasks.length} long tasks; building the run and training the model included)`);
  await screenshot(w, 'map-weaver-heavy-link-refused');
  assert.deepEqual(errors.filter((e) => !e.includes('invalid scans')), []);
  await close();
});

test('scans within the budget are integrated in slices, the count passing through intermediate values', async (t) => {
  const target = 5000;
  const { page, errors, close } = await openObserved(
    `/?map-weaver.scans=${target}&map-weaver.laps=20&map-weaver.autoplay=off#map-weaver`, { reducedMotion: 'reduce' });
  const w = page.locator('occgrid-map-weaver');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction((n) => document.querySelector('occgrid-map-weaver')?.dataset.scans === String(n), target, { timeout: 120_000 });
  const progress = await page.evaluate(() => window.__progress);
  const counts = progress.map((p) => Number(p.text.match(/scans: ([\d,]+) done/)[1].replace(/,/g, '')));
  const intermediate = counts.filter((c) => c > 0 && c < target);
  // Each value was read by a task of its own, so the page ran between the
  // slices that produced them.
  assert.ok(intermediate.length >= 3, `the poller saw ${JSON.stringify(counts)}`);
  assert.deepEqual([...counts].sort((a, b) => a - b), counts, 'the count only grows');
  const r = await w.evaluate((el) => el.weaver.readout());
  assert.equal(r.scans, target, 'every scan asked for was integrated once');
  assert.equal(await w.getAttribute('data-fast-forward'), null, 'the progress marker is gone');
  const tasks = await page.evaluate(() => window.__longTasks);
  const firstSlice = progress[0]?.at ?? Infinity;
  const during = tasks.filter((x) => x.start >= firstSlice);
  t.diagnostic(`${target} scans in ${counts.length} observed slices; longest task ${longest(tasks).toFixed(0)} ms overall, ${longest(during).toFixed(0)} ms once slicing began`);
  assert.deepEqual(errors, []);
  await close();
});

test('readings past the budget are refused naming the attribute; the table stays bounded', async () => {
  const many = 'o'.repeat(15_000);
  const { page, errors, close } = await openPage(`/?cell-filter.readings=${many}#cell-filter`);
  const w = page.locator('occgrid-cell-filter');
  const alert = w.locator(':scope > .occgrid-attribute-error');
  await alert.waitFor();
  // Past the attribute's length the value is refused before it is read,
  // shown by its first 60 characters.
  assert.match(await alert.textContent(), /invalid readings: "o{60}…" \(15,000 characters, at most 3,000; expected at most 1,000 letters o for occupied and f for free/);
  await w.locator('.cell-filter-table tbody tr').first().waitFor();
  // The last good value (the default) stands: the worked example.
  assert.equal(await w.locator('.cell-filter-table tbody tr').count(), 4);
  assert.ok((await page.locator('*').count()) < 5000, 'no DOM node per reading');
  assert.deepEqual(errors.filter((e) => !e.includes('invalid readings')), []);
  await close();

  // Within the attribute's length but past the filter's budget: refused
  // by the count of readings.
  const { page: p1, close: c1 } = await openPage(`/?cell-filter.readings=${'o'.repeat(2_000)}#cell-filter`);
  const alert1 = p1.locator('occgrid-cell-filter').locator(':scope > .occgrid-attribute-error');
  await alert1.waitFor();
  assert.match(await alert1.textContent(), /invalid readings: 2,000 readings \(expected at most 1,000 letters o for occupied and f for free/);
  await c1();

  // At the budget: a table of the prior, a line for the hidden rows and
  // the latest 50; the chart has every reading.
  const { page: p2, errors: e2, close: c2 } = await openPage(`/?cell-filter.readings=${'of'.repeat(500)}#cell-filter`);
  const w2 = p2.locator('occgrid-cell-filter');
  await w2.locator('.cell-filter-table tbody tr.cell-filter-hidden').waitFor();
  assert.equal(await w2.locator('.cell-filter-table tbody tr').count(), 52);
  assert.match(await w2.locator('.cell-filter-table tbody tr.cell-filter-hidden').textContent(), /950 earlier readings/);
  assert.match(await w2.locator('.cell-filter-table tbody tr').last().textContent(), /^1,000free/);
  assert.equal(await w2.evaluate((el) => el.chart.plot.data[0].length), 1001);
  // At the cap the reading buttons are disabled and a notice says why;
  // the readings stay as they are.
  assert.equal(await w2.getByRole('button', { name: 'Occupied reading' }).isDisabled(), true);
  assert.match(await w2.locator('.cell-filter-notice-full').textContent(), /at most 1,000 readings/);
  assert.match(await w2.locator('.cell-filter-table tbody tr').last().textContent(), /^1,000free/);
  await screenshot(w2, 'cell-filter-readings-at-budget');
  assert.deepEqual(e2, []);
  await c2();
});
