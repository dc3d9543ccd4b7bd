// Map Weaver's real-log panel in Chromium: dead reckoning beside the
// corrected map (seeded, set from the panel and from the widget's
// attributes), and a log read and mapped in short tasks, one call into the
// core per task, each call's work bounded by a budget sized from the last.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');
const PAGE = '/test-fixtures/real-log.html';

async function openPanel() {
  const opened = await openPage(PAGE);
  await opened.page.waitForSelector('#panel[data-ready]');
  // Long tasks of the whole page, from the start (buffered).
  await opened.page.evaluate(() => {
    window.longTasks = [];
    new PerformanceObserver((list) => {
      for (const e of list.getEntries()) window.longTasks.push([e.startTime, e.duration]);
    }).observe({ type: 'longtask', buffered: true });
  });
  return opened;
}

/**
 * Waits until the core's session is done with `scans` scans in every pane
 * (or failed), and the panel shows that state, then returns the panel's
 * data. No state of the page's own: the panel's `data-state` is the
 * session's, set once the panel has drawn it.
 */
async function settled(page, scans) {
  await page.waitForFunction((n) => {
    const panel = window.realLogPanel;
    const s = panel.session?.state();
    if (!s || s.state !== panel.root.dataset.state) return false;
    return (s.state === 'done' && s.scansDone === n) || s.state === 'failed';
  }, scans, { timeout: 60_000 });
  return page.$eval('.map-weaver-log', (e) => ({ ...e.dataset }));
}

/** A hash of a canvas's pixels. */
function pixels(page, selector) {
  return page.$eval(selector, (c) => {
    const { data } = c.getContext('2d').getImageData(0, 0, c.width, c.height);
    let h = 2166136261;
    for (let i = 0; i < data.length; i++) h = Math.imul(h ^ data[i], 16777619) >>> 0;
    return `${c.width}x${c.height}:${h}`;
  });
}

test('dead reckoning draws its map beside the corrected one; one seed gives one map, another another', async () => {
  const { page, errors, close } = await openPanel();
  await page.setInputFiles('.map-weaver-log input[type=file]', path.join(DATASETS, 'aces-corrected.log.gz'));
  const corrected = await settled(page, 440);
  assert.equal(corrected.state, 'done');
  assert.equal(await page.locator('.map-weaver-log-reference').isHidden(), true, 'one map under the corrected poses');
  const correctedMap = await pixels(page, '.map-weaver-log-map');

  // A change of settings reaches the core at once: from then on its state
  // is the rebuild's, so "done" can only be the new maps'.
  const rebuilt = async (change, expected) => {
    await change();
    const s = await settled(page, 440);
    assert.equal(s.state, 'done');
    const core = await page.evaluate(() => window.realLogPanel.session.state());
    assert.equal(core.state, 'done');
    for (const [k, v] of Object.entries(expected)) assert.equal(core.settings[k], v, k);
    assert.deepEqual(core.panes.map((p) => p.poses), expected.poses === 'dead-reckoning' ? ['dead-reckoning', 'corrected'] : ['corrected']);
    return s;
  };
  const seed = page.locator('.map-weaver-log input[name=seed]');
  await seed.fill('7');
  await seed.dispatchEvent('change');
  const dr7 = await rebuilt(() => page.selectOption('.map-weaver-log select[name=poses]', 'dead-reckoning'), { poses: 'dead-reckoning', seed: 7 });
  assert.equal(await page.locator('.map-weaver-log-reference').isVisible(), true, 'the corrected map is shown beside');
  assert.match(await page.locator('.map-weaver-log-pane figcaption').textContent(), /Dead reckoning \(seed 7\)/);
  const map7 = await pixels(page, '.map-weaver-log-map');
  assert.notEqual(map7, correctedMap, 'dead reckoning is another map');
  // The pane beside is the corrected map: the core's counts of its map are
  // the corrected build's.
  const reference = await page.evaluate(() => {
    const c = window.realLogPanel.session.counts(1);
    return [c.occupied, c.free, c.unknown].map(String);
  });
  assert.deepEqual(reference, [corrected.occupied, corrected.free, corrected.unknown], 'the pane beside is the corrected map');
  assert.notEqual(await pixels(page, '.map-weaver-log-reference-map'), await pixels(page, '.map-weaver-log-map'));
  assert.notEqual(dr7.occupied, corrected.occupied);
  // Both at one scale: the same metres take the same CSS pixels.
  const scale = await page.evaluate(() => {
    const p = window.realLogPanel;
    return [[p.canvas, p.geometry], [p.sidePanes[0].canvas, p.sidePanes[0].geometry]].map(([c, g]) => parseFloat(c.style.width) / g.width);
  });
  assert.ok(Math.abs(scale[0] - scale[1]) < 0.01 * scale[0], `scales ${scale}`);
  await screenshot(page.locator('.map-weaver-log-stage'), 'real-log-aces-dead-reckoning');

  await seed.fill('8');
  const dr8 = await rebuilt(() => seed.dispatchEvent('change'), { poses: 'dead-reckoning', seed: 8 });
  const map8 = await pixels(page, '.map-weaver-log-map');
  assert.notEqual(map8, map7, 'another seed, another map');
  assert.notEqual(dr8.occupied, dr7.occupied);
  await seed.fill('7');
  const again = await rebuilt(() => seed.dispatchEvent('change'), { poses: 'dead-reckoning', seed: 7 });
  assert.equal(await pixels(page, '.map-weaver-log-map'), map7, 'the same seed, the same map');
  assert.deepEqual([again.occupied, again.free, again.unknown], [dr7.occupied, dr7.free, dr7.unknown]);
  assert.deepEqual(await page.evaluate(() => window.realLogPanel.linkState().settings).then((s) => [s.poses, s.seed]), ['dead-reckoning', 7]);

  // A seed that is not a whole number is refused by name; the map stays.
  await seed.fill('1.5');
  await seed.dispatchEvent('change');
  assert.match(await page.locator('.map-weaver-log > .occgrid-error').textContent(), /seed "1\.5" is not a whole number/);
  assert.equal(await seed.inputValue(), '7');
  assert.equal(errors.length, 1, errors.join(' | '));
  assert.match(errors.pop(), /seed "1\.5" is not a whole number/);

  await rebuilt(() => page.selectOption('.map-weaver-log select[name=poses]', 'corrected'), { poses: 'corrected' });
  assert.equal(await page.locator('.map-weaver-log-reference').isHidden(), true);
  assert.equal(await pixels(page, '.map-weaver-log-map'), correctedMap);
  assert.deepEqual(errors, []);
  await close();
});

test('log-poses and log-seed are checked like the other attributes and set the panel up', async () => {
  const { page, errors, close } = await openPage('/');
  await page.evaluate(() => {
    const w = document.createElement('occgrid-map-weaver');
    w.id = 'dr';
    w.setAttribute('mode', 'log');
    w.setAttribute('log-poses', 'gps');
    w.setAttribute('log-seed', '-3');
    w.setAttribute('autoplay', 'off');
    document.body.prepend(w);
  });
  const box = page.locator('#dr > .occgrid-attribute-error');
  await box.waitFor();
  assert.match(await box.textContent(), /invalid log-poses: "gps" \(expected one of "corrected", "dead-reckoning", "scan-matched", "odometry", "slam"\)/);
  assert.match(await box.textContent(), /invalid log-seed: "-3"/);
  await page.evaluate(() => {
    const w = document.getElementById('dr');
    w.setAttribute('log-poses', 'dead-reckoning');
    w.setAttribute('log-seed', '42');
  });
  await page.waitForFunction(() => !document.querySelector('#dr > .occgrid-attribute-error'));
  await page.locator('#dr .map-weaver-log').waitFor();
  await page.waitForFunction(() => document.querySelector('#dr .map-weaver-log select[name=poses]')?.value === 'dead-reckoning');
  assert.equal(await page.locator('#dr .map-weaver-log input[name=seed]').inputValue(), '42');
  const link = await page.evaluate(() => document.getElementById('dr').linkState());
  assert.equal(link['log-poses'], 'dead-reckoning');
  assert.equal(link['log-seed'], '42');
  // The bad values were logged when they were set, and nothing else.
  assert.ok(errors.every((e) => /log-poses|log-seed/.test(e)), errors.join(' | '));
  await close();
});

// No timed assertion: the figure observed is reported; what is asserted is
// the structure that keeps tasks short (`npm run bench -- logs-browser`
// measures the longest task).
test('a long log is read and mapped one core call per task, each call within a budget sized from the last', async (t) => {
  const { page, errors, close } = await openPanel();
  // Tasks from the file's choice on (not the page's own start-up).
  await page.evaluate(() => {
    document.addEventListener('change', (e) => { window.chosenAt ??= e.timeStamp; }, true);
  });
  await page.setInputFiles('.map-weaver-log input[type=file]', path.join(DATASETS, 'intel-corrected.log.gz'));
  assert.equal((await settled(page, 910)).state, 'done');
  await page.waitForTimeout(200); // long-task entries arrive after their task
  const { trace, longTasks } = await page.evaluate(() => ({
    trace: window.realLogPanel.trace,
    longTasks: window.longTasks.filter(([start, ms]) => start + ms > window.chosenAt).map(([, ms]) => ms),
  }));
  const calls = (what) => trace.filter(([w]) => w === what);
  t.diagnostic(`longest long task ${longTasks.length ? Math.max(...longTasks).toFixed(0) : 'none (all under 50)'} ms; `
    + `${calls('read').length} reads, ${calls('build').length} build slices, ${calls('draw').length} draws`);

  // The work came in many slices…
  assert.ok(calls('read').length >= 4, `${calls('read').length} read calls`);
  assert.ok(calls('build').length >= 4, `${calls('build').length} build calls`);
  // …each task holding one read, one build slice or one draw (the first
  // task also copies the file into the core).
  const tasks = [[]];
  for (const entry of trace) {
    if (entry[0] === 'yield') tasks.push([]);
    else if (['read', 'build', 'draw'].includes(entry[0])) tasks.at(-1).push(entry[0]);
  }
  for (const [k, task] of tasks.entries()) assert.ok(task.length <= 1, `task ${k} made ${task.join(', ')}`);
  // A build slice is a budget of work (cell updates, cells visited at two
  // to the update, two per cell of a new tile), never more than twice the
  // last one's, and the call stops at the scan that reaches it: it does
  // less than its budget plus one scan's work (a scan of 180 beams updates
  // at most 180 × 30 m / 5 cm × 2 cells, visits as many again between its
  // beams, and allocates at most the 200 tiles of 64 × 64 cells a half
  // disc of 30 m touches).
  const builds = calls('build');
  const oneScan = 180 * (30 / 0.05) * 2 * 2 + 2 * 200 * 4096;
  for (const [k, [, , budget, did]] of builds.entries()) {
    if (k > 0) assert.ok(budget <= 2 * builds[k - 1][2], `slice ${k}: ${budget} after ${builds[k - 1][2]}`);
    assert.ok(did < budget + oneScan, `slice ${k} did ${did} units of work for a budget of ${budget}`);
  }
  const last = builds.at(-1);
  assert.equal(last[4], 910);
  // How large a share one call takes depends on the machine's speed (a fast
  // one needs fewer, larger slices), so it is reported, not asserted: the
  // bounds above are what keep every call short.
  const total = builds.reduce((a, [, , , did]) => a + did, 0);
  const most = Math.max(...builds.map(([, , , did]) => did));
  t.diagnostic(`largest slice ${most} of ${total} cell updates`);
  assert.deepEqual(errors, []);
  await close();
});
