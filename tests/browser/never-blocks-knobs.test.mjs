// A page that never blocks (docs/BENCHMARKS.md W7) while a reader turns a knob:
// a retraining of the inverse workbench starts from a first call's budget,
// not from the one its last fit ended with (a triplet drawn costs far more
// than an SGD update); and the doorway trap starts its two-cell table after
// a yield, not in the task that makes its run and draws its maps. The
// tests check the calls' structure, never their time.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

test('each retraining of the inverse workbench starts with the first training’s first budget', async () => {
  const tag = 'occgrid-inverse-workbench';
  const { page, errors, close } = await openPage('/?inverse-workbench.seed=9');
  try {
    // Before the widget nears the screen its core is loaded but nothing is trained.
    await page.waitForFunction((t) => document.querySelector(t)?.core !== undefined, tag);
    await page.evaluate((t) => {
      const { core } = document.querySelector(t);
      window.__units = [];
      for (const [cls, name] of [[core.InverseWorkbenchTraining, 'work'], [core.InverseWorkbench, 'trainWork']]) {
        const f = cls.prototype[name];
        cls.prototype[name] = function (units) {
          window.__units.push({ name, units });
          return f.call(this, units);
        };
      }
    }, tag);
    const trained = (key, value) => page.waitForFunction(([t, k, v]) => {
      const el = document.querySelector(t);
      return el.dataset[k] === v && !el.retrainButton.disabled;
    }, [tag, key, value], { timeout: 120_000 });
    await page.locator(tag).scrollIntoViewIfNeeded();
    await trained('seed', '9');
    const first = await page.evaluate(() => window.__units);
    assert.ok(first.length > 1 && first.every((c) => c.name === 'work'), 'the first training went in calls');
    const fitted = first.at(-1).units;
    assert.ok(fitted > first[0].units, `the budget grew while fitting: ${first[0].units} -> ${fitted}`);

    for (const [attribute, key, value] of [['density', 'density', '0.45'], ['seed', 'seed', '3']]) {
      await page.evaluate(() => { window.__units = []; });
      await page.locator(tag).evaluate((el, [a, v]) => el.setAttribute(a, v), [attribute, value]);
      await trained(key, value);
      const calls = await page.evaluate(() => window.__units);
      assert.ok(calls.length > 1 && calls.every((c) => c.name === 'trainWork'), `${attribute}: a retraining in calls`);
      assert.equal(calls[0].units, first[0].units, `${attribute}: the retraining’s first call asks for the first training’s first budget`);
    }
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('the doorway trap starts its two-cell table after a yield, not in the task that makes its run', async () => {
  const tag = 'occgrid-doorway-trap';
  const { page, errors, close } = await openPage('/?doorway-trap.autoplay=off');
  try {
    await page.waitForFunction((t) => document.querySelector(t)?.core !== undefined, tag);
    await page.evaluate((t) => {
      const el = document.querySelector(t);
      window.__order = [];
      const create = el.create.bind(el);
      // A flag a microtask clears: still set when the table starts in the
      // same run of code that made the run.
      el.create = () => {
        window.__order.push('create');
        window.__sameRun = true;
        queueMicrotask(() => { window.__sameRun = false; });
        return create();
      };
      const start = el.twoCell.start.bind(el.twoCell);
      el.twoCell.start = (...args) => {
        window.__order.push(window.__sameRun ? 'table, same run' : 'table, after a yield');
        return start(...args);
      };
    }, tag);
    await page.locator(tag).scrollIntoViewIfNeeded();
    await page.waitForFunction((t) => {
      const el = document.querySelector(t);
      return el.dataset.state === 'ready' && window.__order.length >= 2;
    }, tag, { timeout: 60_000 });
    assert.deepEqual(await page.evaluate(() => window.__order), ['create', 'table, after a yield']);
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});
