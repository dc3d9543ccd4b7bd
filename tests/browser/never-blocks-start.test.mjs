// A page that never blocks, as it opens and while a widget plays on a
// phone (docs/BENCHMARKS.md W7): a widget far from the screen does no work and
// makes no chart; the sensor-fusion lap is played in budgeted calls of the
// core, at most one an animation frame, never with the unbudgeted `step`;
// and no map pane's canvas on a 3× screen holds more pixels than the budget
// of a pane redrawn every frame. The tests check the work's structure,
// never its time.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

test('on load, a widget far below the screen builds its controls but makes no run and no chart', async () => {
  const { page, errors, close } = await openPage('/', { viewport: { width: 1200, height: 900 } });
  try {
    // Done: the widget on screen has drawn its table, and the last widget
    // of the page has taken the core's constants (its last step until it
    // nears the screen).
    await page.waitForFunction(() => document.querySelector('occgrid-cell-filter')?.ready === true
      && document.querySelector('occgrid-sensor-fusion')?.defaultBeams !== undefined
      && document.querySelector('occgrid-doorway-trap')?.core !== undefined);
    const state = await page.evaluate(() => {
      const trap = document.querySelector('occgrid-doorway-trap');
      const fusion = document.querySelector('occgrid-sensor-fusion');
      const bench = document.querySelector('occgrid-inverse-workbench');
      return {
        fusionBuilt: fusion.querySelectorAll('.sensor-fusion-pane').length,
        fusionRun: fusion.sim,
        fusionStarted: !!fusion.started,
        trapRun: trap.trap ?? null,
        trapCharts: [trap.curve.made, trap.bars.made],
        uplotsInTrap: trap.querySelectorAll('.uplot').length,
        benchChart: bench.chart.made,
        uplotsInBench: bench.querySelectorAll('.uplot').length,
      };
    });
    assert.equal(state.fusionBuilt, 4, 'the far widget has its panes, ready to draw');
    assert.equal(state.fusionRun, null, 'no sensor-fusion run before it nears the screen');
    assert.equal(state.fusionStarted, false);
    assert.equal(state.trapRun, null, 'no doorway-trap run before it nears the screen');
    assert.deepEqual(state.trapCharts, [false, false], 'no doorway-trap chart made');
    assert.equal(state.uplotsInTrap, 0);
    assert.equal(state.benchChart, false, 'no workbench chart made');
    assert.equal(state.uplotsInBench, 0);

    // Scrolled to, the doorway trap makes its run and its charts.
    await page.locator('occgrid-doorway-trap').scrollIntoViewIfNeeded();
    await page.waitForFunction(() => {
      const trap = document.querySelector('occgrid-doorway-trap');
      return trap.dataset.flips !== undefined && trap.curve.made && trap.bars.made;
    }, null, { timeout: 60_000 });
    assert.ok(await page.evaluate(() => document.querySelector('occgrid-doorway-trap').querySelectorAll('.uplot').length) === 2);
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('sensor fusion plays its lap in budgeted calls of the core, at most one an animation frame', async () => {
  const { page, errors, close } = await openPage('/?sensor-fusion.autoplay=off#sensor-fusion');
  try {
    const widget = page.locator('occgrid-sensor-fusion');
    await widget.scrollIntoViewIfNeeded();
    await page.waitForFunction(() => document.querySelector('occgrid-sensor-fusion')?.dataset.step === '0');
    await widget.evaluate((el) => {
      const frame = { n: 0 };
      const tick = () => { frame.n += 1; requestAnimationFrame(tick); };
      requestAnimationFrame(tick);
      window.__calls = [];
      const sim = el.sim;
      const work = sim.work.bind(sim);
      sim.work = (steps, budget) => {
        const r = work(steps, budget);
        window.__calls.push({ kind: 'work', asked: steps, budget, frame: frame.n, ...r });
        return r;
      };
      const step = sim.step.bind(sim);
      sim.step = () => {
        window.__calls.push({ kind: 'step' });
        return step();
      };
    });
    await widget.getByRole('button', { name: /^Play/ }).click();
    // Done: the lap is over and the widget has paused.
    await page.waitForFunction(() => {
      const el = document.querySelector('occgrid-sensor-fusion');
      return el.dataset.step === '81' && !el.playing;
    }, null, { timeout: 120_000 });
    const calls = await page.evaluate(() => window.__calls);
    assert.deepEqual(calls.filter((c) => c.kind !== 'work'), [], 'never the unbudgeted step while playing');
    assert.ok(calls.length > 0);
    for (const c of calls) {
      assert.ok(Number.isSafeInteger(c.budget) && c.budget >= 1, `a finite budget: ${JSON.stringify(c)}`);
      assert.ok(c.asked >= 1 && c.asked <= 4, `at most a frame's steps asked for: ${JSON.stringify(c)}`);
      assert.ok(c.steps <= c.asked, `no more steps taken than asked for: ${JSON.stringify(c)}`);
    }
    const frames = calls.map((c) => c.frame);
    assert.equal(new Set(frames).size, frames.length, 'one call per animation frame at most');
    // Every step of the lap was taken by these calls, once.
    const taken = calls.reduce((sum, c) => sum + c.steps, 0);
    assert.equal(taken, 81, 'the whole lap, in budgeted calls');
    assert.deepEqual(calls.map((c) => c.step), calls.map((_, i) => calls.slice(0, i + 1).reduce((s, c) => s + c.steps, 0)));
    assert.equal(calls.at(-1).done, true);
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('on a phone at 3×, a map pane redrawn while playing keeps its canvas within the pixel budget', async () => {
  const { page, errors, close } = await openPage('/#sensor-fusion', { viewport: { width: 390, height: 844 }, deviceScaleFactor: 3 });
  try {
    await page.locator('occgrid-sensor-fusion').scrollIntoViewIfNeeded();
    await page.waitForFunction(() => document.querySelector('occgrid-sensor-fusion')?.dataset.state === 'ready');
    const { budget, panes } = await page.evaluate(async () => {
      const ui = await import('/widgets/lib/ui.js');
      const canvases = [...document.querySelectorAll('occgrid-sensor-fusion canvas.occgrid-map')];
      return {
        budget: ui.MAX_ANIMATED_CANVAS_PIXELS,
        panes: canvases.map((c) => ({ width: c.width, height: c.height, cssWidth: c.clientWidth })),
      };
    });
    assert.equal(panes.length, 4);
    for (const p of panes) {
      assert.ok(p.width * p.height <= budget * 1.01, `${p.width} x ${p.height} device pixels, budget ${budget}`);
      // Still as sharp as the screen allows within the budget: never
      // fewer device pixels than CSS pixels.
      assert.ok(p.width >= p.cssWidth, `${p.width} device pixels for ${p.cssWidth} CSS pixels`);
    }
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});
