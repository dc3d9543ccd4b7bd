// The chapter page in Chromium: <occgrid-inverse-workbench> trains the
// learned inverse model in the page, draws both models over one beam's
// neighbourhood and along its axis, and the "max-range reading" button
// visibly weakens the learned model's free space; retraining with another
// seed gives another model, and a bad seed is reported beside the summary
// of the current one, which stays.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { canvasColours, openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const SELECTOR = 'occgrid-inverse-workbench';

/** What the page shows: the element's data attributes and printed readouts. */
const state = (widget) => widget.evaluate((w) => ({
  ...w.dataset,
  l0Text: w.querySelector('.inverse-workbench-l0').textContent,
  freeText: [...w.querySelectorAll('.inverse-workbench-free')].map((o) => o.textContent),
  pressed: w.querySelector('button[name=max-range]').getAttribute('aria-pressed'),
  status: w.querySelector('.inverse-workbench-status').textContent,
}));

/** Waits until the widget has drawn with `key` equal to `value`. */
const until = (page, key, value) => page.waitForFunction(
  ([s, k, v]) => document.querySelector(s)?.dataset[k] === v, [SELECTOR, key, value], { timeout: 30_000 });

test('both models are drawn and the max-range button weakens the learned free space', async () => {
  const { page, errors, close } = await openPage('/');
  const w = page.locator(SELECTOR);
  await w.scrollIntoViewIfNeeded();
  await until(page, 'state', 'ready');

  const short = await state(w);
  assert.equal(short.reading, '2');
  assert.equal(short.seed, '9');
  const l0 = Number(short.learnedL0);
  assert.ok(l0 < 0, `learned l0 ${l0}`);
  assert.equal(short.l0Text, l0.toFixed(3), 'the printed l0 is the core’s');
  assert.match(short.status, /24,000 triplets/);
  const learnedShort = Number(short.learnedFree);
  const handShort = Number(short.handFree);
  assert.ok(learnedShort < -1.5, `learned free evidence for a 2 m reading: ${learnedShort}`);
  assert.ok(Math.abs(handShort + 0.4) < 1e-6, `Table 9.2's l_free: ${handShort}`);
  assert.deepEqual(short.freeText, [handShort.toFixed(3), learnedShort.toFixed(3)]);
  const [hand, learned] = await canvasColours(w, 'canvas.inverse-workbench-image', 3);
  assert.ok(hand > 3 && learned > 20, `colours on the images: ${hand}, ${learned}`);
  assert.ok((await w.locator('.u-over').count()) === 1, 'the axis chart is drawn');
  await screenshot(w, 'inverse-workbench-2m');

  await w.getByRole('button', { name: 'Max-range reading' }).click();
  await until(page, 'reading', '8');
  const max = await state(w);
  assert.equal(max.pressed, 'true');
  const learnedMax = Number(max.learnedFree);
  assert.ok(Math.abs(learnedMax) < 0.5 * Math.abs(learnedShort),
    `learned free evidence: ${learnedShort} for 2 m, ${learnedMax} at max range`);
  assert.ok(Number(max.learnedAxisMean) !== Number(short.learnedAxisMean), 'the learned curve changed');
  assert.equal(Number(max.handFree), handShort, 'Table 9.2 carves the same free space for a no-return');
  assert.equal(max.freeText[1], learnedMax.toFixed(3));
  await screenshot(w, 'inverse-workbench-max-range');

  // Back to a short reading with the keyboard: Home is the slider's minimum.
  const slider = w.getByLabel('Reading z');
  await slider.focus();
  await page.keyboard.press('Home');
  await until(page, 'reading', '0.2');
  assert.equal((await state(w)).pressed, 'false');
  assert.equal(await slider.getAttribute('aria-valuetext'), '0.20 m');

  assert.deepEqual(errors, []);
  await close();
});

test('retraining with another seed gives another model; a bad seed keeps the current one, and its summary', async () => {
  const { page, errors, close } = await openPage('/');
  const w = page.locator(SELECTOR);
  await w.scrollIntoViewIfNeeded();
  await until(page, 'state', 'ready');
  const before = await state(w);

  const seed = w.getByLabel('Seed');
  await seed.fill('12');
  await seed.press('Enter');
  await until(page, 'seed', '12');
  const after12 = await state(w);
  assert.notEqual(after12.learnedL0, before.learnedL0);
  assert.ok(Number(after12.learnedL0) < 0);
  assert.match(after12.status, /seed 12/);
  // The summary says how long training took (a figure, not a bound: speed is the benchmarks' business).
  assert.match(after12.status, /: [\d,]+ ms/);

  // A refused seed is said beside the summary of the model that stays,
  // naming the field and what it expects; the summary itself stays.
  const refusal = w.locator('.inverse-workbench-refusal');
  for (const [text, shown] of [['-3', '"-3"'], ['', '""']]) {
    await seed.fill(text);
    await w.getByRole('button', { name: 'Retrain' }).click();
    await page.waitForFunction(([s, v]) => document.querySelector(`${s} .inverse-workbench-refusal`)?.textContent.includes(`invalid seed: ${v}`), [SELECTOR, shown]);
    assert.equal(await refusal.getAttribute('role'), 'alert');
    assert.ok(await refusal.isVisible(), 'the refusal is on screen');
    const said = await refusal.textContent();
    assert.match(said, /^Seed box: invalid seed: .* \(expected a whole number from 0 to 9007199254740991\); the model trained with seed 12 stays\.$/);
    assert.doesNotMatch(said, /NaN/);
    const kept = await state(w);
    assert.equal(kept.seed, '12');
    assert.equal(kept.learnedL0, after12.learnedL0);
    assert.equal(kept.status, after12.status, 'the training summary stays as it was');
  }
  await screenshot(w, 'inverse-workbench-bad-seed');

  // A good seed clears the refusal; the next bad one is said again.
  await seed.fill('9');
  await w.getByRole('button', { name: 'Retrain' }).click();
  await until(page, 'seed', '9');
  assert.equal(await refusal.isVisible(), false);
  await seed.fill('1.5');
  await w.getByRole('button', { name: 'Retrain' }).click();
  await page.waitForFunction((s) => document.querySelector(`${s} .inverse-workbench-refusal`)?.textContent.includes('invalid seed: "1.5"'), SELECTOR);
  assert.ok(await refusal.isVisible());

  // The only console errors are the widget's own reports of the bad seeds.
  assert.deepEqual(errors, [
    'occgrid-inverse-workbench: Seed box: invalid seed: "-3" (expected a whole number from 0 to 9007199254740991)',
    'occgrid-inverse-workbench: Seed box: invalid seed: "" (expected a whole number from 0 to 9007199254740991)',
    'occgrid-inverse-workbench: Seed box: invalid seed: "1.5" (expected a whole number from 0 to 9007199254740991)',
  ]);
  await close();
});

test('a bad reading attribute is reported in the widget, which keeps the reading it shows', async () => {
  const { page, errors, close } = await openPage('/');
  const w = page.locator(SELECTOR);
  await w.scrollIntoViewIfNeeded();
  await until(page, 'state', 'ready');
  const drawn = await state(w);
  await w.evaluate((el) => el.setAttribute('reading', '-1'));
  const box = w.locator('.occgrid-error');
  await box.waitFor();
  const message = /invalid reading: "-1" \(expected a number from 0\.2 to 8 m in steps of 0\.05\)/;
  assert.match(await box.textContent(), message);
  assert.equal(await box.getAttribute('role'), 'alert');
  const kept = await state(w);
  assert.equal(kept.reading, '2');
  assert.equal(kept.learnedFree, drawn.learnedFree);
  assert.equal(await w.getByLabel('Reading z').inputValue(), '2');
  await w.evaluate((el) => el.setAttribute('reading', '3.5'));
  await until(page, 'reading', '3.5');
  assert.equal(await box.count(), 0, 'a good value clears the error');
  assert.equal(await w.getByLabel('Reading z').inputValue(), '3.5');
  assert.equal(errors.length, 1);
  assert.match(errors[0], /^occgrid-inverse-workbench: /);
  assert.match(errors[0], message);
  await close();
});
