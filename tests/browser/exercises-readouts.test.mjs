// The chapter's exercises done in Chromium the way a reader does them: each
// opens from its link in the page's "Exercises" section, and the numbers
// the exercise asks for are read off the widget's screen text (the core
// computes them; these tests check that they are there, and right).
// Exercise 1 (the prior's drift, with the clamp off), exercise 3 (the
// entropies of the two-cell table), exercise 4 (the readings' cones before
// the first MAP flip), and what the doorway trap's hover and the two-cell
// diagram say on screen.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

/** The page's link for exercise `n`: its query and fragment. */
async function exerciseLink(n) {
  const { page, close } = await openPage('/', { reducedMotion: 'reduce' });
  const href = await page.getAttribute(`#exercises a[data-exercise="${n}"]`, 'href');
  await close();
  return `/${href}`;
}

/**
 * A number as the widgets print it: "-15.2492", "0.0047", "2,000",
 * "2.4 × 10⁻⁷" or "1 − 2.4 × 10⁻⁷".
 */
function shown(text) {
  const t = text.trim().replaceAll('−', '-').replaceAll(',', '');
  const sup = { '⁻': '-', '⁰': '0', '¹': '1', '²': '2', '³': '3', '⁴': '4', '⁵': '5', '⁶': '6', '⁷': '7', '⁸': '8', '⁹': '9' };
  const power = /^(1 - )?([\d.]+) × 10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)$/.exec(t);
  if (power) {
    const v = Number(power[2]) * 10 ** Number([...power[3]].map((c) => sup[c]).join(''));
    return power[1] ? 1 - v : v;
  }
  assert.match(t, /^-?[\d.]+$/, `a printed number: ${text}`);
  return Number(t);
}

test('exercise 1: with the clamp off, ten readings of the prior drift to l = −15.25, p = 2.4 × 10⁻⁷, with no warning the reader did not cause', async () => {
  const { page, errors, close } = await openPage(await exerciseLink(1), { reducedMotion: 'reduce' });
  const w = page.locator('occgrid-cell-filter');
  await w.scrollIntoViewIfNeeded();
  const rows = w.locator('.cell-filter-table tbody tr');
  await page.waitForFunction(() => document.querySelectorAll('occgrid-cell-filter .cell-filter-table tbody tr').length === 11);
  // The link sets the clamp control to "off".
  assert.equal(await w.getByLabel('clamp l_max').getAttribute('aria-valuetext'), 'off (no clamp)');
  const last = async () => ({
    l: shown(await rows.last().locator('.cell-filter-l').textContent()),
    p: shown(await rows.last().locator('.cell-filter-p').textContent()),
    summary: await w.locator('.occgrid-readout').first().textContent(),
    notices: await w.locator('.cell-filter-notice').allTextContents(),
  });
  // With the correction, the cell stays at l0 = −1.3863.
  let s = await last();
  assert.ok(Math.abs(s.l - -1.3863) < 1e-4, `kept: l = ${s.l}`);
  assert.ok(Math.abs(s.p - 0.2) < 1e-4, `kept: p = ${s.p}`);
  assert.deepEqual(s.notices, [], 'no warning: no free reading was given');

  // Without it, every reading adds l0 once more: l_10 = 11 l0.
  await w.getByLabel('forget to subtract l0').check();
  await page.waitForFunction(() => Number(document.querySelector('occgrid-cell-filter').dataset.l) < -15);
  s = await last();
  assert.ok(Math.abs(s.l - -15.25) <= 0.01, `l_10 on screen: ${s.l}`);
  assert.ok(Math.abs(s.p - 2.4e-7) <= 0.05e-7, `p on screen: ${s.p}`);
  assert.match(s.summary, /After 10 readings: l = -15\.2492, p = 2\.4 × 10⁻⁷\./);
  assert.deepEqual(s.notices, [], 'no clamp notice with the clamp off, and no warning about free readings');
  await screenshot(w, 'exercise-1-no-clamp');

  // At the default clamp of 12 the cell stops at reading 8, and says so.
  await w.getByLabel('clamp l_max').fill('12');
  await page.waitForFunction(() => document.querySelector('occgrid-cell-filter').dataset.l === '-12');
  s = await last();
  assert.equal(s.l, -12);
  assert.equal(s.notices.length, 1);
  assert.match(s.notices[0], /^At the clamp: from reading 8 on/);

  // The warning about free readings appears once the reader gives one.
  await w.getByRole('button', { name: 'Free reading' }).click();
  await page.waitForFunction(() => document.querySelector('occgrid-cell-filter').dataset.notices.includes('inverted'));
  assert.match((await last()).notices.at(-1), /^p\(m \| free reading\) = 0\.30 is not below p\(m \| occupied reading\) = 0\.20/);
  assert.deepEqual(errors, []);
  await close();
});

test('the clamp is an attribute: "off" or 1 to 30 in steps of 0.5, a bad value refused inside the widget by name', async () => {
  const { page, errors, close } = await openPage('/?cell-filter.clamp=4.5&cell-filter.readings=oooooooo#cell-filter', { reducedMotion: 'reduce' });
  const w = page.locator('occgrid-cell-filter');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-cell-filter').dataset.l === '4.5');
  assert.equal(await w.getByLabel('clamp l_max').getAttribute('aria-valuetext'), '±4.5');
  await w.evaluate((el) => el.setAttribute('clamp', '0'));
  const alert = w.locator('.occgrid-attribute-error');
  await alert.waitFor();
  assert.equal(await alert.textContent(), 'invalid clamp: "0" (expected a number from 1 to 30 in steps of 0.5 (log odds), or "off" for no clamp)');
  assert.equal(await w.evaluate((el) => el.dataset.l), '4.5', 'the last good clamp stays');
  await w.evaluate((el) => el.setAttribute('clamp', 'off'));
  await page.waitForFunction(() => Number(document.querySelector('occgrid-cell-filter').dataset.l) > 6);
  assert.equal(await alert.count(), 0);
  // "Copy link" writes the clamp back as it is.
  await w.getByRole('button', { name: /^Copy link/ }).click();
  await page.waitForFunction(() => document.querySelector('occgrid-cell-filter').dataset.link);
  assert.equal(new URL(await w.evaluate((el) => el.dataset.link)).searchParams.get('cell-filter.clamp'), 'off');
  assert.equal(errors.length, 1);
  assert.match(errors[0], /^occgrid-cell-filter: invalid clamp: "0"/);
  await close();
});

/** The two-cell table's entropies and joint as printed. */
const entropies = (w) => w.evaluate((el) => {
  const text = (cls) => el.querySelector(`.doorway-trap-two-cell .${cls}`).textContent;
  const rows = [...el.querySelectorAll('.doorway-trap-joint tbody tr')].map((tr) => [...tr.querySelectorAll('td')].map((td) => td.textContent));
  return {
    joint: text('doorway-trap-joint-entropy'),
    sum: text('doorway-trap-marginal-entropy'),
    gap: text('doorway-trap-shared-information'),
    line: el.querySelector('.doorway-trap-entropy').textContent,
    table: rows.map((r) => Number(r[2])),
    pa: Number(text('doorway-trap-pa')),
    pb: Number(text('doorway-trap-pb')),
  };
});

test('exercise 3: the two-cell table shows the joint entropy, the sum of the marginal entropies and the gap, for the side-by-side and collinear presets', async () => {
  const { page, errors, close } = await openPage(await exerciseLink(3), { reducedMotion: 'reduce' });
  const w = page.locator('occgrid-doorway-trap');
  await w.locator('.doorway-trap-two-cell').scrollIntoViewIfNeeded();
  const bits = (p) => (p > 0 ? -p * Math.log2(p) : 0);
  const hb = (p) => bits(p) + bits(1 - p);
  const check = async (what) => {
    const e = await entropies(w);
    assert.match(e.line, /Joint entropy H\(m_A, m_B\) = [\d.]+ bits/, what);
    assert.match(e.line, /Sum of the marginal entropies H\(m_A\) \+ H\(m_B\) = [\d.]+ bits/, what);
    assert.match(e.line, /shared information = [\d.]+ bits/, what);
    const [joint, sum, gap] = [e.joint, e.sum, e.gap].map(shown);
    // Against the table and the marginals printed beside them (4 decimals).
    assert.ok(Math.abs(joint - e.table.reduce((a, p) => a + bits(p), 0)) < 2e-3, `${what}: joint ${joint}`);
    assert.ok(Math.abs(sum - (hb(e.pa) + hb(e.pb))) < 2e-3, `${what}: sum ${sum}`);
    assert.ok(gap >= 0 && Math.abs(gap - (sum - joint)) <= 1.5e-3, `${what}: gap ${gap} = ${sum} - ${joint}`);
    return { joint, sum, gap };
  };
  // The link lands where the lesson shows: side by side at the chapter's
  // 2 m reading, 0.222 bits shared.
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap .doorway-trap-shared-information')?.textContent === '0.222');
  const side = await check('side by side, 2.0 m');
  assert.equal(side.gap, 0.222);
  // A 1.5 m reading in front of both cells: little shared.
  await w.getByLabel('Reading z').fill('1.5');
  await page.waitForFunction(() => Number(document.querySelector('occgrid-doorway-trap .doorway-trap-shared-information').textContent) < 0.01);
  const early = await check('side by side, 1.5 m');
  assert.ok(early.gap < 0.01, `a reading in front of both: little shared (${early.gap})`);
  await w.getByLabel('Reading z').fill('2');
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap .doorway-trap-shared-information').textContent === '0.222');
  await screenshot(w.locator('.doorway-trap-two-cell'), 'exercise-3-side-by-side');
  await w.getByRole('button', { name: 'Collinear' }).click();
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap button[name=arrange-collinear]').getAttribute('aria-pressed') === 'true');
  const collinear = await check('collinear, 2.0 m');
  assert.ok(collinear.gap < side.gap / 5, `collinear shares less: ${collinear.gap} vs ${side.gap}`);
  await screenshot(w.locator('.doorway-trap-two-cell'), 'exercise-3-collinear');
  assert.deepEqual(errors, []);
  await close();
});

/** Pixels of a canvas drawn in the cones' green (over any gray of the map). */
const greenPixels = (w, selector) => w.evaluate((el, sel) => {
  const c = el.querySelector(sel);
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let n = 0;
  for (let i = 0; i < d.length; i += 4) if (d[i + 1] > d[i] + 25 && d[i + 1] > d[i + 2] + 25) n++;
  return n;
}, selector);

test('exercise 4: before the first flip both panes draw every reading’s cone; the MAP hover says undecided for cells no reading reached', async () => {
  const { page, errors, close } = await openPage(await exerciseLink(4), { reducedMotion: 'reduce' });
  const w = page.locator('occgrid-doorway-trap');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap')?.dataset.flips === '0');
  const map = '.doorway-trap-map canvas.doorway-trap-canvas';
  const sweep = '.doorway-trap-sweep canvas.doorway-trap-canvas';
  const before = { map: await greenPixels(w, map), sweep: await greenPixels(w, sweep) };
  assert.ok(before.map > 2000, `cones in the MAP pane before the first flip: ${before.map} green pixels`);
  assert.ok(before.sweep > 2000, `cones in the swept pane before the first scan: ${before.sweep} green pixels`);
  assert.match(await w.locator('.doorway-trap-map .doorway-trap-status').textContent(), /The 63 readings’ cones are drawn/);
  await screenshot(w.locator('.doorway-trap-panes'), 'exercise-4-cones-before-the-first-flip');
  // After a flip the MAP pane shows that flip's beams only.
  await w.getByRole('button', { name: 'Step the MAP climb by one flip' }).click();
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap').dataset.flips === '1');
  const after1 = await greenPixels(w, map);
  assert.ok(after1 < before.map, `the first flip's beams (${after1}) replace every cone (${before.map})`);

  // The hover: a corner no cone reaches is undecided, drawn gray, exported unknown.
  const canvas = w.locator(map);
  const box = await canvas.boundingBox();
  const read = async (fx, fy) => {
    await page.mouse.move(box.x + box.width * fx, box.y + box.height * fy);
    return w.locator('.doorway-trap-hover').textContent();
  };
  const corner = await read(0.015, 0.015);
  assert.match(corner, /MAP: undecided \(no reading reached it\), inside 0 cones/);
  assert.doesNotMatch(corner, /MAP: free/);
  const room = await read(0.5, 0.55);
  assert.match(room, /MAP: free, inside [1-9]\d* cones/);
  assert.match(await canvas.getAttribute('aria-label'), /gray the [\d,]+ undecided cells no reading reached/);
  assert.match(await w.locator('.occgrid-caption').first().textContent(), /gray cells are undecided: no reading reached them/);
  assert.deepEqual(errors, []);
  await close();
});

test('the two-cell diagram says on screen that A and B can be dragged, and with which keys', async () => {
  const { page, errors, close } = await openPage('/#doorway-trap', { reducedMotion: 'reduce' });
  const w = page.locator('occgrid-doorway-trap');
  const table = w.locator('.doorway-trap-two-cell');
  await table.scrollIntoViewIfNeeded();
  const hint = table.locator('.doorway-trap-drag-hint');
  await hint.waitFor();
  assert.ok(await hint.isVisible());
  const text = await hint.textContent();
  assert.match(text, /Drag A or B/);
  assert.match(text, /mouse or touch/);
  assert.match(text, /arrow keys/);
  assert.match(text, /Space switches between A and B/);
  // The hint sits with the diagram, not only in its screen-reader label.
  assert.equal(await hint.evaluate((el) => el.closest('.doorway-trap-diagram-box') !== null), true);
  assert.deepEqual(errors, []);
  await close();
});

test('the workbench’s two l0 lines have legend markers a reader can tell apart', async () => {
  const { page, errors, close } = await openPage('/#inverse-workbench');
  const w = page.locator('occgrid-inverse-workbench');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench')?.dataset.state === 'ready', null, { timeout: 30_000 });
  const markers = await w.evaluate((el) => Object.fromEntries([...el.querySelectorAll('.u-legend .u-series')].map((row) => {
    const m = row.querySelector('.u-marker');
    const css = getComputedStyle(m);
    return [row.querySelector('.u-label').textContent, [css.borderTopStyle, css.borderTopColor, css.width, css.height, css.backgroundColor].join(' ')];
  })));
  const hand = markers['l0 hand-crafted'];
  const learned = markers['l0 learned'];
  assert.ok(hand && learned, JSON.stringify(markers));
  assert.notEqual(hand, learned, 'the two l0 markers look different');
  assert.match(hand, /^dashed /, 'the dashed line has a dashed marker');
  assert.match(learned, /^solid /);
  await screenshot(w.locator('.inverse-workbench-chart'), 'inverse-workbench-legend');
  assert.deepEqual(errors, []);
  await close();
});
