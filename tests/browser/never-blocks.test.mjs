// docs/ARCHITECTURE.md, "Bad input": a page that never blocks. Map Weaver
// asks its core for work in calls with a budget of cell visits, at most
// one call per animation frame, and never with the unbudgeted `advance`:
// the every-cell sweep over a 1024 x 1024 scene at speed 8, a
// mapper switched after three laps, and every knob rebuild in such calls.
// Every knob gives, over the scans so far, the map of a run that had its
// value all along. The tests check the calls' structure, never their time;
// the longest main-thread task is printed as a diagnostic.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const SELECTOR = 'occgrid-map-weaver';

/**
 * Wraps the widget's run so that every call into the core is recorded:
 * `work` with its arguments, report and the animation frame it ran in, and
 * any call of the unbudgeted `advance`. Done again after the
 * widget makes a new run.
 */
const instrument = (widget) => widget.evaluate((el) => {
  window.__frame ??= (() => {
    const count = { n: 0 };
    const tick = () => { count.n += 1; requestAnimationFrame(tick); };
    requestAnimationFrame(tick);
    return count;
  })();
  window.__calls = [];
  window.__longTasks = [];
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) window.__longTasks.push(e.duration);
  }).observe({ type: 'longtask' });
  const w = el.weaver;
  const work = w.work.bind(w);
  w.work = (scans, budget) => {
    const r = work(scans, budget);
    window.__calls.push({ kind: 'work', scans, budget, frame: window.__frame.n, ...r });
    return r;
  };
  for (const name of ['advance']) {
    const f = w[name].bind(w);
    w[name] = (...args) => {
      window.__calls.push({ kind: name });
      return f(...args);
    };
  }
});

const calls = (page) => page.evaluate(() => window.__calls);
const longest = (page) => page.evaluate(() => Math.max(0, ...window.__longTasks));

/** Waits until the widget's run exists and no pane is behind (a run with no `progress` rebuilds at once). */
const settled = (page, timeout = 120_000) => page.waitForFunction((s) => {
  const el = document.querySelector(s);
  if (!el?.weaver || el.dataset.fastForward) return false;
  return !el.weaver.progress || el.weaver.progress().behind.every((n) => n === 0);
}, SELECTOR, { timeout });

async function openWeaver(params) {
  const query = Object.entries(params).map(([k, v]) => `map-weaver.${k}=${encodeURIComponent(v)}`).join('&');
  const opened = await openPage(`/?${query}#map-weaver`);
  const w = opened.page.locator(SELECTOR);
  await w.scrollIntoViewIfNeeded();
  await opened.page.waitForFunction((s) => document.querySelector(s)?.weaver && document.querySelector(s).dataset.scans !== undefined,
    SELECTOR, { timeout: 120_000 });
  await settled(opened.page);
  return { ...opened, w };
}

/**
 * The structure every recorded call must have: only budgeted `work`, a
 * finite budget, no more than the budget and `overshoot` spent (one row of
 * a sweep, or one traversal scan), and at most one call per animation frame
 * when `perFrame`.
 */
function assertBudgeted(list, overshoot, perFrame) {
  assert.ok(list.length > 0, 'the widget called its core');
  const unbudgeted = list.filter((c) => c.kind !== 'work');
  assert.deepEqual(unbudgeted, [], 'no call without a budget');
  for (const c of list) {
    assert.ok(Number.isFinite(c.budget) && c.budget >= 1, `a finite budget: ${c.budget}`);
    assert.ok(c.cellVisits <= c.budget + overshoot, `spent ${c.cellVisits} on a budget of ${c.budget}`);
  }
  if (perFrame) {
    const perFrameCount = new Map();
    for (const c of list) perFrameCount.set(c.frame, (perFrameCount.get(c.frame) ?? 0) + 1);
    assert.ok(Math.max(...perFrameCount.values()) <= 1, 'at most one call a frame');
  }
}

test('the every-cell sweep over 1024 x 1024 cells at speed 8 plays in budgeted calls, one a frame', async () => {
  const { page, w, errors, close } = await openWeaver({
    scene: '{"width":1024,"height":1024,"resolution":0.01171875}', 'left-mapper': 'sweep', 'right-mapper': 'sweep',
    speed: '8', autoplay: 'off',
  });
  await instrument(w);
  await w.getByRole('button', { name: 'Play' }).click();
  await page.waitForFunction((s) => Number(document.querySelector(s).dataset.scans) >= 4, SELECTOR, { timeout: 120_000 });
  await w.getByRole('button', { name: 'Pause' }).click();
  await settled(page);
  const list = await calls(page);
  // A band of rows may go one row (1,024 cells) past its budget.
  assertBudgeted(list, 1024, true);
  const scans = list.reduce((n, c) => n + c.scans, 0);
  const sweeps = list.filter((c) => c.cellVisits > 0 && c.cellVisits < 1024 * 1024).length;
  assert.ok(sweeps > 0, 'the sweep of a scan was cut into bands');
  console.log(`# ${list.length} calls for ${scans} scans of 2 x 1024² cells; longest task ${(await longest(page)).toFixed(0)} ms`);
  assert.deepEqual(errors, []);
  await close();
});

test('switching a mapper after three laps rebuilds in budgeted calls to the map of a run that had it all along', async () => {
  const { page, w, errors, close } = await openWeaver({ scans: '1959', autoplay: 'off' });
  await instrument(w);
  await w.evaluate((el) => el.setAttribute('left-mapper', 'sweep'));
  await settled(page);
  await page.waitForFunction((s) => document.querySelector(`${s} .map-weaver-left`).dataset.mapper === 'sweep', SELECTOR);
  const list = await calls(page);
  // A call may finish with a whole traversal scan of the right pane: 60
  // beams of at most 80 cells.
  assertBudgeted(list, 60 * 80, false);
  assert.ok(list.length > 1, `the rebuild took ${list.length} calls`);
  const [shown, fresh] = await w.evaluate((el) => {
    const run = new el.core.MapWeaver({ panes: [{ mapper: 'sweep' }, { model: 'learned' }] });
    run.advance(1959);
    const entropy = run.readout().panes[0].entropyBits;
    run.free();
    return [Number(el.querySelector('.map-weaver-left').dataset.entropy), entropy];
  });
  assert.equal(shown, fresh);
  console.log(`# rebuild over 1,959 scans: ${list.length} calls; longest task ${(await longest(page)).toFixed(0)} ms`);
  assert.deepEqual(errors, []);
  await close();
});

/** Sets pane `side`'s slider `label` to `value` and waits for the rebuild; returns the pane's entropy. */
async function turn(page, w, side, label, value) {
  await w.locator(`.map-weaver-${side}`).getByLabel(label).fill(String(value));
  await settled(page);
  return w.evaluate((el, side) => Number(el.querySelector(`.map-weaver-${side}`).dataset.entropy), side);
}

test('the clamp and the strength turned and turned back give the map back; β rebuilds to the run that had it', async () => {
  const { page, w, errors, close } = await openWeaver({ scans: '300', autoplay: 'off', 'left-sensor': 'cone' });
  const before = await w.evaluate((el) => Number(el.querySelector('.map-weaver-left').dataset.entropy));
  const pulled = await turn(page, w, 'left', 'Clamp l_max', 1);
  assert.ok(Math.abs(pulled - before) > 100, `clamp 1: ${before} -> ${pulled} bits`);
  assert.equal(await turn(page, w, 'left', 'Clamp l_max', 12), before, 'clamp 1, then 12 again');
  assert.notEqual(await turn(page, w, 'left', 'Evidence strength', 3), before);
  assert.equal(await turn(page, w, 'left', 'Evidence strength', 1), before, 'strength 3, then 1 again');
  const turned = await turn(page, w, 'left', 'Cone opening β', 30);
  const fresh = await w.evaluate((el) => {
    const run = new el.core.MapWeaver({ panes: [{ sensor: 'cone', betaDeg: 30 }, { model: 'learned' }] });
    run.advance(300);
    const entropy = run.readout().panes[0].entropyBits;
    run.free();
    return entropy;
  });
  assert.equal(turned, fresh, 'β 30° over the same 300 scans');
  assert.deepEqual(errors, []);
  await close();
});
