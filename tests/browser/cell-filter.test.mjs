// The chapter page in Chromium: the cell-filter widget reproduces the
// chapter's worked example click by click, shows the l0 drift, and reports
// bad attributes inside the widget.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const rows = (page) => page.$$eval('occgrid-cell-filter .cell-filter-table tbody tr', (trs) =>
  trs.map((tr) => ({ l: Number(tr.dataset.l), p: Number(tr.dataset.p), text: tr.textContent })));

test('clicking occupied, occupied, free reproduces the worked example', async () => {
  const { page, errors, close } = await openPage('/');
  const w = page.locator('occgrid-cell-filter');
  await w.locator('.cell-filter-table tbody tr').first().waitFor();
  await w.getByRole('button', { name: 'Clear readings' }).click();
  assert.equal((await rows(page)).length, 1, 'only the prior row after clearing');
  await w.getByRole('button', { name: 'Occupied reading' }).click();
  await w.getByRole('button', { name: 'Occupied reading' }).click();
  await w.getByRole('button', { name: 'Free reading' }).click();
  const r = await rows(page);
  assert.equal(r.length, 4);
  const expected = [[0.8473, 0.7], [1.6946, 0.8448], [0.8473, 0.7]];
  expected.forEach(([l, p], i) => {
    assert.ok(Math.abs(r[i + 1].l - l) < 1e-4, `step ${i + 1}: l = ${r[i + 1].l}`);
    assert.ok(Math.abs(r[i + 1].p - p) < 1e-4, `step ${i + 1}: p = ${r[i + 1].p}`);
  });
  // The printed numbers agree with the data (4 decimals on screen).
  assert.match(r[2].text, /1\.6946/);
  assert.match(r[2].text, /0\.8448/);
  await screenshot(w, 'cell-filter-worked-example');
  assert.deepEqual(errors, []);
  await close();
});

test('forgetting l0 with a prior of 0.2 makes the cell drift toward free', async () => {
  const { page, errors, close } = await openPage('/');
  const w = page.locator('occgrid-cell-filter');
  await w.locator('.cell-filter-table tbody tr').first().waitFor();
  await w.getByRole('button', { name: 'The l0 lesson' }).click();
  const drifted = await rows(page);
  await w.getByLabel('forget to subtract l0').uncheck();
  const kept = await rows(page);
  const l0 = Math.log(0.2 / 0.8);
  assert.equal(drifted.length, 9);
  // Eight alternating readings of a model symmetric around the prior: with
  // the subtraction the cell ends within 0.2 of l0; without it each reading
  // adds l0 once more, about -11 in all, down to the clamp of -12.
  assert.ok(Math.abs(kept.at(-1).l - l0) < 0.2, `kept: ${kept.at(-1).l}`);
  assert.ok(drifted.at(-1).l < l0 + 8 * l0 * 0.9, `drifted: ${drifted.at(-1).l}`);
  assert.ok(drifted.every((r, i) => i < 2 || r.l < kept[i].l - 1), 'drift grows with every reading');
  await screenshot(w, 'cell-filter-l0-lesson');
  assert.deepEqual(errors, []);
  await close();
});

test('a bad attribute is reported inside the widget', async () => {
  const { page, close } = await openPage('/');
  await page.locator('occgrid-cell-filter .cell-filter-table tbody tr').first().waitFor();
  await page.evaluate(() => document.querySelector('occgrid-cell-filter').setAttribute('prior', '1.5'));
  const alert = page.locator('occgrid-cell-filter .occgrid-error');
  await alert.waitFor();
  assert.match(await alert.textContent(), /prior.*1\.5/);
  await close();
});
