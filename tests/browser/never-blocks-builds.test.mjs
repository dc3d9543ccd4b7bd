// A page that never blocks (docs/BENCHMARKS.md W7) while a widget makes a large
// run: Map Weaver's 1024 x 1024 scene is drawn in calls of the core bounded
// by a budget of cells (`MapWeaverStart.build`), and its run is made only
// once every map is drawn; the doorway trap's MAP search at 1 cm is set up
// in calls bounded by a budget of units (`DoorwayTrapStart.work`). The tests check the calls' structure (the work
// each did, in the core's units, against its budget), never their time.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const BIG = '{"width":1024,"height":1024,"resolution":0.01171875}';

test('Map Weaver draws a 1024 x 1024 scene in budgeted calls, a row past the budget at most', async () => {
  const tag = 'occgrid-map-weaver';
  const { page, errors, close } = await openPage('/?map-weaver.autoplay=off#map-weaver');
  try {
    await page.waitForFunction((t) => document.querySelector(t)?.core !== undefined, tag);
    await page.evaluate((t) => {
      const { core } = document.querySelector(t);
      const proto = core.MapWeaverStart.prototype;
      window.__calls = [];
      const build = proto.build;
      proto.build = function (budget) {
        const r = build.call(this, budget);
        window.__calls.push({ name: 'build', budget, cells: r.cells, done: r.done });
        // A timer set now has run by the next call only if the task that
        // made this one ended first (timers run in the order they were set).
        window.__taskEnded = false;
        setTimeout(() => { window.__taskEnded = true; });
        return r;
      };
      const finish = proto.finish;
      proto.finish = function () {
        window.__calls.push({ name: 'finish', afterTask: window.__taskEnded });
        return finish.call(this);
      };
    }, tag);
    await page.locator(tag).scrollIntoViewIfNeeded();
    await page.waitForFunction((t) => !!document.querySelector(t).weaver, tag, { timeout: 120_000 });
    const first = await page.evaluate(() => window.__calls);
    assert.ok(first.some((c) => c.name === 'build') && first.at(-1).name === 'finish', 'the chapter’s run is made the same way');
    await page.evaluate(() => { window.__calls = []; });
    await page.locator(tag).evaluate((el, scene) => el.setAttribute('scene', scene), BIG);
    await page.waitForFunction((t) => document.querySelector(t).weaver?.width === 1024, tag, { timeout: 120_000 });
    const calls = await page.evaluate(() => window.__calls);
    const builds = calls.filter((c) => c.name === 'build');
    assert.ok(builds.length > 3, `the maps were drawn in ${builds.length} calls`);
    assert.deepEqual(calls.at(-1), { name: 'finish', afterTask: true }, 'the run is made last, in a task after the last band’s');
    assert.equal(calls.filter((c) => c.name === 'finish').length, 1);
    assert.ok(builds.at(-1).done && builds.slice(0, -1).every((c) => !c.done), 'finished once every map was drawn');
    // A band of rows passes its budget by less than a row (1024 cells); a
    // pane's view made is one piece of a quarter of its cells, once per pane.
    const over = builds.filter((c) => c.cells >= c.budget + 1024);
    assert.ok(over.length <= 2, `${over.length} calls past a row: ${JSON.stringify(over)}`);
    for (const c of over) assert.ok(c.cells < c.budget + 1024 * 1024 / 4, JSON.stringify(c));
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('the doorway trap sets its MAP search up at 1 cm in budgeted calls, then makes its run', async () => {
  const tag = 'occgrid-doorway-trap';
  const { page, errors, close } = await openPage('/?doorway-trap.autoplay=off#doorway-trap');
  try {
    await page.waitForFunction((t) => document.querySelector(t)?.dataset.state === 'ready', tag, { timeout: 60_000 });
    await page.evaluate((t) => {
      const { core } = document.querySelector(t);
      const proto = core.DoorwayTrapStart.prototype;
      window.__calls = [];
      const work = proto.work;
      proto.work = function (budget) {
        const r = work.call(this, budget);
        window.__calls.push({ name: 'work', budget, units: r.units, done: r.done });
        return r;
      };
      const finish = proto.finish;
      proto.finish = function () {
        window.__calls.push({ name: 'finish' });
        return finish.call(this);
      };
      window.__old = document.querySelector(t).trap;
    }, tag);
    await page.locator(tag).evaluate((el) => el.setAttribute('scene', '{"resolution": 0.01}'));
    await page.waitForFunction((t) => {
      const el = document.querySelector(t);
      return el.trap !== window.__old && el.dataset.state === 'ready';
    }, tag, { timeout: 120_000 });
    const calls = await page.evaluate(() => window.__calls);
    const works = calls.filter((c) => c.name === 'work');
    assert.ok(works.length > 3, `the search was set up in ${works.length} calls`);
    assert.deepEqual(calls.at(-1), { name: 'finish' }, 'the run is made last, once');
    assert.equal(calls.filter((c) => c.name === 'finish').length, 1);
    // Every call but the last stopped because its budget was spent.
    for (const c of works.slice(0, -1)) assert.ok(!c.done && c.units >= c.budget, JSON.stringify(c));
    assert.ok(works.at(-1).done);
    assert.equal(await page.locator(tag).evaluate((el) => el.trap.width), 500, 'the 5 m scene at 1 cm');
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});
