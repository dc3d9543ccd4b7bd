// New settings on a long log in Chromium: the panel re-plans the maps in
// core calls of a budget of scans (state `planning`), one call per task,
// with the maps of the settings before on screen until the new ones are
// planned; then it rebuilds them as after a read. On the Freiburg campus,
// the longest main-thread task of the rebuild is reported.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');
const CAMPUS = path.join(DATASETS, 'freiburg-campus-corrected.log.gz');

/** Waits until the panel's session and the panel both say `state`. */
function until(page, state, timeout = 120_000) {
  return page.waitForFunction((want) => {
    const panel = window.realLogPanel;
    return panel?.session?.state().state === want && panel.root.dataset.state === want;
  }, state, { timeout });
}

test('new settings on the campus are planned in budgeted calls, the old map on screen until then', async (t) => {
  const { page, errors, close } = await openPage('/test-fixtures/real-log.html');
  await page.waitForSelector('#panel[data-ready]');
  await page.setInputFiles('.map-weaver-log input[type=file]', CAMPUS);
  await until(page, 'done');
  // From here on: every state the panel shows with the map's resolution
  // then, and every long task.
  await page.evaluate(() => {
    const panel = window.realLogPanel;
    window.seen = [];
    window.tasks = [];
    new PerformanceObserver((list) => {
      for (const e of list.getEntries()) window.tasks.push(e.duration);
    }).observe({ type: 'longtask' });
    new MutationObserver(() => {
      window.seen.push([panel.root.dataset.state, panel.geometry?.resolution]);
    }).observe(panel.root, { attributes: true, attributeFilter: ['data-state'] });
    panel.trace = [];
  });
  await page.selectOption('.map-weaver-log select[name=resolution]', '0.1');
  await page.waitForFunction(() => window.realLogPanel.geometry?.resolution === 0.1);
  await until(page, 'done');
  const { seen, trace, tasks } = await page.evaluate(() => ({
    seen: window.seen, trace: window.realLogPanel.trace, tasks: window.tasks,
  }));
  const plans = trace.filter(([kind]) => kind === 'plan');
  const longestPlan = Math.max(...plans.map(([, ms]) => ms));
  t.diagnostic(`${plans.length} plan calls, longest ${longestPlan.toFixed(1)} ms; long tasks of the rebuild: ${tasks.map((ms) => ms.toFixed(0)).join(', ') || 'none'}`);
  // The planning was the page's, in calls of at most their budget of
  // scans; while it went on, the map of 5 cm stayed.
  assert.ok(plans.length >= 2, JSON.stringify(trace.slice(0, 12)));
  for (const [, , budget, work] of plans) assert.ok(work <= Math.max(1, budget), JSON.stringify(plans));
  const planning = seen.filter(([state]) => state === 'planning');
  assert.ok(planning.length > 0 && planning.every(([, res]) => res === 0.05), JSON.stringify(seen));
  assert.deepEqual(errors, []);
  await close();
});

test('settings the campus fits in no map are refused by a plan call: the error names them, the controls and the map go back', async () => {
  const { page, errors, close } = await openPage('/test-fixtures/real-log.html');
  await page.waitForSelector('#panel[data-ready]');
  await page.setInputFiles('.map-weaver-log input[type=file]', CAMPUS);
  await until(page, 'done');
  const before = await page.evaluate(() => window.realLogPanel.geometry);
  await page.selectOption('.map-weaver-log select[name=resolution]', '0.025');
  await page.waitForSelector('.map-weaver-log .occgrid-error');
  await until(page, 'done');
  const message = await page.$eval('.map-weaver-log .occgrid-error', (e) => e.textContent);
  assert.match(message, /^settings: .*resolution: 0\.025 m.*(or coarser fits|a coarser resolution)/, message);
  assert.equal(await page.$eval('.map-weaver-log select[name=resolution]', (e) => e.value), '0.05');
  assert.deepEqual(await page.evaluate(() => window.realLogPanel.geometry), before);
  // The refusal is the one error of the page (also in the console).
  assert.ok(errors.length > 0 && errors.every((e) => e.includes('settings: invalid resolution')), JSON.stringify(errors));
  await close();
});
