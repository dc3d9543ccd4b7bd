// A page that never blocks (docs/BENCHMARKS.md W7), sensor fusion's part: its run
// simulates each scan when a step first needs it, so the lap's first frame
// is drawn before the rest of the lap is simulated; a link's scans are
// integrated in budgeted calls, never with the unbudgeted `step`; and a
// changed LiDAR beam count empties the LiDAR's maps at once and rebuilds
// them in budgeted calls, one an animation frame, to the maps of a run that
// had that beam count all along. The tests check the calls' structure,
// never their time (docs/ARCHITECTURE.md, "Sessions and panes").
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const SELECTOR = 'occgrid-sensor-fusion';

/**
 * Records every call of the core's sensor-fusion runs made from now on:
 * `work` with its arguments, its report and the animation frame it ran in,
 * `setLidarBeams` with the run's readout right after it, any call of the
 * unbudgeted `step`, and each map drawn with how many scans were simulated
 * by then. Patched on the class: runs the widget makes later are recorded
 * too.
 */
const instrument = (page) => page.evaluate((s) => {
  const el = document.querySelector(s);
  window.__frame ??= (() => {
    const count = { n: 0 };
    const tick = () => { count.n += 1; requestAnimationFrame(tick); };
    requestAnimationFrame(tick);
    return count;
  })();
  window.__calls = [];
  const proto = el.core.SensorFusion.prototype;
  const wrap = (name, record) => {
    const f = proto[name];
    proto[name] = function (...args) {
      const r = f.apply(this, args);
      window.__calls.push({ kind: name, frame: window.__frame.n, ...record.call(this, args, r) });
      return r;
    };
  };
  wrap('work', ([steps, budget], r) => ({ asked: steps, budget, ...r }));
  wrap('step', () => ({}));
  wrap('setLidarBeams', function ([beams]) {
    const r = this.readout();
    return { beams, after: { step: r.step, rebuilding: r.rebuilding } };
  });
  wrap('render', function ([which]) {
    const r = this.readout();
    return { which, step: r.step, simulated: r.scansSimulated };
  });
}, SELECTOR);

const calls = (page, kind) => page.evaluate((k) => window.__calls.filter((c) => !k || c.kind === k), kind);

/** Waits until the core has loaded in the widget (before it nears the screen, it makes no run). */
const coreLoaded = (page) => page.waitForFunction((s) => document.querySelector(s)?.defaultBeams !== undefined, SELECTOR);

/** Waits until the widget's run is shown and nothing is left to integrate or rebuild. */
const settled = (page) => page.waitForFunction((s) => {
  const el = document.querySelector(s);
  return el?.dataset.state === 'ready' && el.dataset.fastForward === undefined && el.dataset.rebuilding === undefined
    && !el.beamTask && !el.loop.running;
}, SELECTOR, { timeout: 120_000 });

/** A budgeted call: a finite budget, and at least one step (new or rebuilt) taken. */
function assertBudgeted(list) {
  assert.ok(list.length > 0, 'the widget called its core');
  for (const c of list) {
    assert.ok(Number.isSafeInteger(c.budget) && c.budget >= 1, `a finite budget: ${JSON.stringify(c)}`);
  }
}

test('the lap’s first frame is drawn before its scans are simulated, and no scan is simulated before its step', async () => {
  const { page, errors, close } = await openPage('/?sensor-fusion.autoplay=off');
  try {
    await coreLoaded(page);
    await instrument(page);
    await page.locator(SELECTOR).scrollIntoViewIfNeeded();
    await settled(page);
    const draws = await calls(page, 'render');
    assert.ok(draws.length > 0, 'the maps were drawn');
    assert.deepEqual(draws[0], { ...draws[0], step: 0, simulated: 0 }, 'the first frame waited for no scan');
    await page.locator(SELECTOR).getByRole('button', { name: /^Play/ }).click();
    await page.waitForFunction((s) => {
      const el = document.querySelector(s);
      return el.dataset.step === '81' && !el.playing;
    }, SELECTOR, { timeout: 120_000 });
    const all = await calls(page, 'render');
    for (const d of all) assert.ok(d.simulated <= d.step, `scans simulated ahead of the steps: ${JSON.stringify(d)}`);
    assert.equal(all.at(-1).simulated, 81, 'every scan of the lap, once it was played');
    assert.deepEqual(await calls(page, 'step'), [], 'never the unbudgeted step');
    assertBudgeted(await calls(page, 'work'));
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('a link’s scans before the first frame are integrated in budgeted calls, not step by step', async () => {
  const { page, errors, close } = await openPage('/?sensor-fusion.autoplay=off&sensor-fusion.scans=81&sensor-fusion.scene=%7B%22laps%22%3A3%7D');
  try {
    await coreLoaded(page);
    await instrument(page);
    await page.locator(SELECTOR).scrollIntoViewIfNeeded();
    await settled(page);
    assert.equal(await page.locator(SELECTOR).getAttribute('data-step'), '81');
    assert.deepEqual(await calls(page, 'step'), [], 'never the unbudgeted step');
    const work = await calls(page, 'work');
    assertBudgeted(work);
    assert.ok(work.length > 1, `the 81 scans took ${work.length} calls`);
    assert.equal(work.reduce((n, c) => n + c.steps, 0), 81);
    // Each call simulated only the scans of its own steps.
    const draws = await calls(page, 'render');
    assert.ok(draws.every((d) => d.simulated === 81 && d.step === 81), JSON.stringify(draws[0]));
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('a beam count changed after the lap empties the LiDAR’s maps and rebuilds them in budgeted calls, one a frame', async () => {
  const { page, errors, close } = await openPage('/?sensor-fusion.autoplay=off&sensor-fusion.scans=81#sensor-fusion');
  try {
    const widget = page.locator(SELECTOR);
    await widget.scrollIntoViewIfNeeded();
    await settled(page);
    await instrument(page);
    await widget.evaluate((el) => el.setAttribute('lidar-beams', '720'));
    await page.waitForFunction((s) => document.querySelector(s).dataset.lidarBeams === '720', SELECTOR, { timeout: 120_000 });
    await settled(page);

    const staged = await calls(page, 'setLidarBeams');
    assert.equal(staged.length, 1);
    assert.deepEqual(staged[0].after, { step: 81, rebuilding: 81 }, 'the call itself integrated nothing again');
    assert.deepEqual(await calls(page, 'step'), [], 'never the unbudgeted step');
    const work = await calls(page, 'work');
    assertBudgeted(work);
    assert.ok(work.length > 1, `the rebuild took ${work.length} calls`);
    assert.ok(work.every((c) => c.rebuilt + c.steps >= 1 || c.underWay), 'each call moved the rebuild on');
    assert.equal(work.reduce((n, c) => n + c.rebuilt, 0), 81, 'every scan so far, rebuilt once');
    assert.equal(new Set(work.map((c) => c.frame)).size, work.length, 'one call an animation frame at most');

    // The maps of a run that had 720 beams all along, to the bit.
    const [shown, fresh] = await widget.evaluate((el) => {
      const run = new el.core.SensorFusion({ lidar: { beams: 720 } }, undefined);
      run.work(81, Infinity);
      const r = run.readout();
      run.free();
      return [el.sim.readout(), r];
    });
    assert.deepEqual(shown, fresh);
    assert.equal(Number(await widget.getAttribute('data-sum-mean')), fresh.footprint.sum);
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('the lap at 0.0125 m is played in pieces of steps: a call stops within a step, and the maps drawn are whole steps', async () => {
  const fine = encodeURIComponent('{"resolution": 0.0125}');
  const { page, errors, close } = await openPage(`/?sensor-fusion.autoplay=off&sensor-fusion.scene=${fine}#sensor-fusion`);
  try {
    const widget = page.locator(SELECTOR);
    await coreLoaded(page);
    await instrument(page);
    await widget.scrollIntoViewIfNeeded();
    await settled(page);
    await widget.getByRole('button', { name: /^Play/ }).click();
    await page.waitForFunction((s) => {
      const el = document.querySelector(s);
      return el.dataset.step === '81' && !el.playing;
    }, SELECTOR, { timeout: 300_000 });
    const work = await calls(page, 'work');
    const draws = await calls(page, 'render');
    // One whole step's work at this resolution, from a run of its own.
    const step = await widget.evaluate((el) => {
      const run = new el.core.SensorFusion({ resolution: 0.0125 }, undefined);
      const r = run.work(1, Infinity);
      run.free();
      return r.cellVisits;
    });
    assertBudgeted(work);
    assert.deepEqual(await calls(page, 'step'), [], 'never the unbudgeted step');
    const within = work.filter((c) => c.underWay && c.steps === 0);
    assert.ok(within.length > 0, 'some calls stopped within a step');
    // A call passes its budget by at most one piece: a band of rows, a
    // scan's simulation or the LiDAR's rasters, each far less than half a step.
    for (const c of work) assert.ok(c.cellVisits < c.budget + step / 2, JSON.stringify({ ...c, step }));
    assert.equal(work.reduce((n, c) => n + c.steps, 0), 81);
    // Every map drawn shows whole steps: no scan simulated past them.
    for (const d of draws) assert.ok(d.simulated <= d.step, JSON.stringify(d));
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});
