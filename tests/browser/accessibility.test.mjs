// Accessibility and comfort in Chromium, on the chapter page: every control
// of every widget has a name a screen reader can say, is reached with Tab
// and is operated with the keyboard alone (Tab, Shift+Tab, Space, Enter,
// arrow keys — no mouse); maps and charts carry text alternatives that
// follow the state; the page holds together from a 360 px phone column to
// a wide screen; canvases are sharp at a device pixel ratio of 2; nothing
// moves by itself under prefers-reduced-motion; a widget scrolled out of
// view stops working; and the page runs under its strict
// Content-Security-Policy without a single violation.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');

const MINE = ['occgrid-cell-filter', 'occgrid-map-weaver', 'occgrid-doorway-trap', 'occgrid-sensor-fusion'];
const ALL = [...MINE, 'occgrid-inverse-workbench'];

/** Scrolls every widget into view once so that each builds (they wait until seen). */
async function visitAll(page, tags = ALL) {
  for (const tag of tags) {
    await page.locator(tag).scrollIntoViewIfNeeded();
    await page.waitForTimeout(150);
  }
  await page.waitForFunction(() => document.querySelector('occgrid-map-weaver')?.dataset.scans !== undefined, null, { timeout: 60_000 });
  await page.waitForFunction(() => document.querySelector('occgrid-doorway-trap')?.dataset.flips !== undefined);
  await page.waitForFunction(() => document.querySelector('occgrid-sensor-fusion')?.dataset.step !== undefined);
}

// ---- keyboard helpers ------------------------------------------------------

/**
 * Finds, in the page, the control of `widget` matching `selector` whose
 * name (aria-label, label, or text) contains `name`; marks it for the test.
 */
const mark = (page, widget, selector, name) => page.evaluate(([widget, selector, name]) => {
  document.querySelector('[data-kbd-target]')?.removeAttribute('data-kbd-target');
  const nameOf = (e) => e.getAttribute('aria-label') || (e.labels && e.labels[0] ? e.labels[0].textContent : '') || e.textContent || '';
  const found = [...document.querySelector(widget).querySelectorAll(selector)].filter((e) => nameOf(e).includes(name));
  if (found.length !== 1) return `${found.length} matches for ${selector} "${name}" in ${widget}`;
  found[0].setAttribute('data-kbd-target', '');
  return null;
}, [widget, selector, name]);

/**
 * Moves the keyboard focus to a control with Tab (forward) or Shift+Tab
 * (backward), whichever way it lies from the current focus — never a click.
 */
async function tabTo(page, widget, selector, name) {
  const problem = await mark(page, widget, selector, name);
  assert.equal(problem, null);
  for (let i = 0; i < 400; i++) {
    const where = await page.evaluate(() => {
      const target = document.querySelector('[data-kbd-target]');
      const active = document.activeElement;
      if (active === target) return 'here';
      if (!active || active === document.body) return 'after';
      // DOCUMENT_POSITION_FOLLOWING = 4: the target comes later.
      return active.compareDocumentPosition(target) & 4 ? 'after' : 'before';
    });
    if (where === 'here') return;
    await page.keyboard.press(where === 'after' ? 'Tab' : 'Shift+Tab');
  }
  assert.fail(`Tab never reached ${selector} "${name}" in ${widget}`);
}

/** Tabs to a control and presses `keys` on it, one after the other. */
async function operate(page, widget, selector, name, ...keys) {
  await tabTo(page, widget, selector, name);
  for (const k of keys) await page.keyboard.press(k);
}

const data = (page, widget) => page.evaluate((w) => ({ ...document.querySelector(w).dataset }), widget);
const until = (page, fn, arg, timeout = 20_000) => page.waitForFunction(fn, arg, { timeout });

// ---- tests -----------------------------------------------------------------

test('every control, map and chart of every widget has a name a screen reader can say', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  await visitAll(page);
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench')?.dataset.state === 'ready', null, { timeout: 30_000 });
  // Map Weaver in real-log mode, with a map, so that the panel's controls and map are checked too.
  const weaver = page.locator('occgrid-map-weaver');
  await weaver.getByLabel('Real log').check();
  await weaver.locator('.map-weaver-log select[name=dataset] option[value="aces-corrected.log.gz"]').waitFor({ state: 'attached' });
  await weaver.locator('.map-weaver-log select[name=dataset]').selectOption('aces-corrected.log.gz');
  await page.waitForFunction(() => document.querySelector('.map-weaver-log')?.dataset.state === 'done', null, { timeout: 30_000 });
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('DOM.enable');
  await cdp.send('Accessibility.enable');
  const { root } = await cdp.send('DOM.getDocument', { depth: 0 });
  const missing = [];
  let checked = 0;
  for (const tag of ALL) {
    const selector = `${tag} :is(button, input:not([type=hidden]), select, [tabindex], [role=img], canvas, progress)`;
    const { nodeIds } = await cdp.send('DOM.querySelectorAll', { nodeId: root.nodeId, selector });
    for (const nodeId of nodeIds) {
      const { nodes } = await cdp.send('Accessibility.getPartialAXTree', { nodeId, fetchRelatives: false });
      const node = nodes[0];
      if (!node || node.ignored) continue; // hidden, or drawn inside a described image
      checked++;
      const name = node.name?.value?.trim() ?? '';
      if (!name) {
        const { node: dom } = await cdp.send('DOM.describeNode', { nodeId });
        missing.push(`${tag} ${dom.localName}.${(dom.attributes || []).join(' ')} (${node.role?.value})`);
      }
    }
  }
  assert.ok(checked > 60, `checked ${checked} elements`);
  assert.deepEqual(missing, [], 'unnamed controls or images');
  assert.deepEqual(errors, []);
  await close();
});

test('Tab reaches every control of every widget, in order, and Shift+Tab walks back', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  await visitAll(page);
  await page.evaluate(() => window.scrollTo(0, 0));
  // Number the visible controls in document order.
  const total = await page.evaluate((tags) => {
    let n = 0;
    for (const e of document.querySelectorAll(tags.map((t) => `${t} :is(button, input, select, canvas[tabindex], [tabindex="0"])`).join(', '))) {
      const hiddenRadio = e.type === 'radio' && !e.checked; // a radio group is one Tab stop
      if (e.disabled || hiddenRadio || e.type === 'hidden' || !e.getClientRects().length || getComputedStyle(e).visibility === 'hidden') continue;
      e.dataset.kbdOrder = String(n++);
    }
    return n;
  }, ALL);
  assert.ok(total > 60, `${total} controls`);
  const seen = [];
  for (let i = 0; i < total + 40; i++) {
    await page.keyboard.press('Tab');
    const k = await page.evaluate(() => document.activeElement?.dataset?.kbdOrder);
    if (k !== undefined) seen.push(Number(k));
    if (seen.length && seen.at(-1) === total - 1) break;
  }
  const missed = [];
  for (let k = 0; k < total; k++) if (!seen.includes(k)) missed.push(k);
  const describe = (ks) => page.evaluate((ks) => ks.map((k) => {
    const e = document.querySelector(`[data-kbd-order="${k}"]`);
    return `${e.closest('[class]')?.localName} ${e.localName} ${e.getAttribute('aria-label') || e.textContent || e.name}`;
  }), ks);
  assert.deepEqual(await describe(missed), [], 'controls Tab never reached');
  assert.deepEqual(seen, [...seen].sort((a, b) => a - b), 'focus follows the document order');
  // Shift+Tab walks the same controls back.
  const back = [];
  for (let i = 0; i < 12; i++) {
    await page.keyboard.press('Shift+Tab');
    back.push(Number(await page.evaluate(() => document.activeElement?.dataset?.kbdOrder)));
  }
  assert.deepEqual(back, seen.slice(-13, -1).reverse());
  assert.deepEqual(errors, []);
  await close();
});

test('the cell filter is driven by keyboard alone', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const W = 'occgrid-cell-filter';
  const rows = () => page.$$eval(`${W} .cell-filter-table tbody tr`, (trs) => trs.map((tr) => ({ reading: tr.children[1].textContent, l: Number(tr.dataset.l) })));
  await page.locator(`${W} .cell-filter-table tbody tr`).first().waitFor();
  await operate(page, W, 'button', 'Clear readings', 'Enter');
  assert.equal((await rows()).length, 1);
  await operate(page, W, 'button', 'Occupied reading', 'Space');
  await operate(page, W, 'button', 'Free reading', 'Enter', 'Enter');
  assert.deepEqual((await rows()).map((r) => r.reading), ['prior', 'occupied', 'free', 'free']);
  await operate(page, W, 'button', 'Undo', 'Space');
  assert.equal((await rows()).length, 3);
  await operate(page, W, 'button', 'Worked example', 'Enter');
  assert.ok(Math.abs((await rows()).at(-1).l - 0.8473) < 1e-4);
  await operate(page, W, 'button', 'The l0 lesson', 'Enter');
  assert.equal((await rows()).length, 9);
  assert.equal(await page.locator(W).getByLabel('forget to subtract l0').isChecked(), true);
  const drift = (await rows()).at(-1).l;
  await operate(page, W, 'input', 'forget to subtract l0', 'Space');
  assert.equal(await page.locator(W).getByLabel('forget to subtract l0').isChecked(), false);
  const kept = (await rows()).at(-1).l;
  assert.ok(kept > drift + 5, `subtracting l0 again: ${drift} -> ${kept}`);
  for (const [label, key, value] of [['p(m | occupied reading)', 'ArrowRight', '0.38'], ['p(m | free reading)', 'ArrowLeft', '0.09'], ['prior p(m)', 'ArrowRight', '0.25']]) {
    const before = (await rows()).at(-1).l;
    await operate(page, W, 'input', label, key);
    assert.equal(await page.locator(W).getByLabel(label).inputValue(), value, label);
    assert.notEqual((await rows()).at(-1).l, before, `${label} changes the cell`);
  }
  await operate(page, W, 'button', 'Copy link', 'Enter');
  await until(page, () => new URL(location.href).searchParams.get('cell-filter.prior') === '0.25');
  assert.deepEqual(errors, []);
  await close();
});

test('Map Weaver is driven by keyboard alone', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width: 1280, height: 900 } });
  const W = 'occgrid-map-weaver';
  const w = page.locator(W);
  await w.scrollIntoViewIfNeeded();
  await until(page, (s) => document.querySelector(s).dataset.scans === '0', W, 60_000);
  const readout = () => page.evaluate((s) => document.querySelector(s).weaver.readout(), W);

  // The data source: a radio group, arrow keys move the choice.
  await operate(page, W, 'input[type=radio]', 'Simulated apartment', 'ArrowRight');
  assert.equal(await w.getByLabel('Real log').isChecked(), true);
  await until(page, (s) => document.querySelector(`${s} .map-weaver-sim`).hidden, W);
  await page.keyboard.press('ArrowLeft');
  assert.equal(await w.getByLabel('Simulated apartment').isChecked(), true);
  assert.equal(await w.locator('.map-weaver-sim').isVisible(), true);

  await operate(page, W, 'button', 'Step', 'Enter', 'Space');
  assert.equal((await data(page, W)).scans, '2');
  await operate(page, W, 'button', 'Play', 'Enter');
  assert.equal(await w.locator('button[name=play]').getAttribute('aria-pressed'), 'true');
  await until(page, (s) => Number(document.querySelector(s).dataset.scans) > 6, W);
  await page.keyboard.press('Space');
  assert.equal(await w.locator('button[name=play]').getAttribute('aria-pressed'), 'false');
  await operate(page, W, 'button', 'Reset', 'Enter');
  assert.equal((await data(page, W)).scans, '0');
  await operate(page, W, 'select', 'Speed', 'ArrowDown');
  assert.equal(await w.getByLabel('Speed').inputValue(), '2');
  await operate(page, W, 'input', 'Person in the corridor', 'Space');
  assert.equal((await readout()).person, false);
  await operate(page, W, 'button', 'Step', 'Enter', 'Enter', 'Enter');

  for (const [k, side] of [[0, 'left'], [1, 'right']]) {
    const pane = `.map-weaver-${side}`;
    // The map: focus puts a cursor cell on it, arrows move it, the readout follows.
    await operate(page, W, `${pane} canvas.map-weaver-map`, '');
    await until(page, (s) => /cell \(\d+, \d+\)/.test(document.querySelector(`${s} .map-weaver-hover`).textContent), W);
    const first = await w.locator('.map-weaver-hover').textContent();
    await page.keyboard.press('ArrowRight');
    await page.keyboard.press('ArrowUp');
    const moved = await w.locator('.map-weaver-hover').textContent();
    const [, x0, y0] = first.match(/cell \((\d+), (\d+)\)/);
    const [, x1, y1] = moved.match(/cell \((\d+), (\d+)\)/);
    assert.deepEqual([Number(x1) - Number(x0), Number(y1) - Number(y0)], [1, 1], `${side}: ${first} -> ${moved}`);
    assert.match(await w.locator(`${pane} canvas.map-weaver-map`).getAttribute('aria-label'), /after 3 scans: entropy [\d,.]+ bits, Brier score \d\.\d{4}/);

    const model = (await readout()).panes[k].model;
    await operate(page, W, `${pane} input`, 'Learned model', 'Space');
    await until(page, ([s, k, m]) => document.querySelector(s).weaver.readout().panes[k].model !== m, [W, k, model]);
    await operate(page, W, `${pane} input`, 'Pose oracle', 'Space');
    assert.equal((await readout()).panes[k].pose, 'dead-reckoning');
    await operate(page, W, `${pane} input`, 'Clamp l_max', 'ArrowLeft', 'ArrowLeft');
    assert.equal((await readout()).panes[k].clamp, 11);
    await operate(page, W, `${pane} input`, 'Evidence strength', 'ArrowRight');
    assert.equal((await readout()).panes[k].strength, 1.25);
    await tabTo(page, W, `${pane} button`, 'Export');
    const [download] = await Promise.all([page.waitForEvent('download'), page.keyboard.press('Enter')]);
    assert.equal(download.suggestedFilename(), `apartment-${side}.zip`);
  }
  await operate(page, W, 'button', 'Copy link', 'Space');
  await until(page, () => new URL(location.href).searchParams.get('map-weaver.left-clamp') === '11');
  assert.deepEqual(errors, []);
  await close();
});

test('the doorway trap is driven by keyboard alone', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width: 1280, height: 900 } });
  const W = 'occgrid-doorway-trap';
  const w = page.locator(W);
  await w.scrollIntoViewIfNeeded();
  await until(page, (s) => document.querySelectorAll(`${s} .doorway-trap-joint tbody tr`).length === 4, W);

  await operate(page, W, 'button', 'Next scan', 'Enter', 'Space');
  assert.equal((await data(page, W)).scan, '2');
  await operate(page, W, 'button', 'Play the sweep', 'Enter');
  assert.equal(await w.locator('button[name=sweep-play]').getAttribute('aria-pressed'), 'true');
  await until(page, (s) => Number(document.querySelector(s).dataset.scan) > 2, W);
  await page.keyboard.press('Enter');
  assert.equal(await w.locator('button[name=sweep-play]').getAttribute('aria-pressed'), 'false');
  await operate(page, W, 'button[name=sweep-reset]', 'Reset', 'Enter');
  assert.equal((await data(page, W)).scan, '0');
  await operate(page, W, 'button', 'Step the MAP climb by one flip', 'Enter', 'Space');
  assert.equal((await data(page, W)).flips, '2');
  await operate(page, W, 'button', 'Play the MAP climb', 'Space');
  await until(page, (s) => Number(document.querySelector(s).dataset.flips) > 2, W);
  await page.keyboard.press('Space');
  assert.equal(await w.locator('button[name=map-play]').getAttribute('aria-pressed'), 'false');
  await operate(page, W, 'button[name=map-reset]', 'Reset', 'Enter');
  assert.equal((await data(page, W)).flips, '0');

  for (const key of ['sweep', 'map']) {
    await operate(page, W, `.doorway-trap-${key} canvas.doorway-trap-canvas`, '');
    await until(page, (s) => /^Cell \(\d+, \d+\)/.test(document.querySelector(`${s} .doorway-trap-hover`).textContent), W);
    const first = (await w.locator('.doorway-trap-hover').textContent()).match(/^Cell \((\d+), (\d+)\)/);
    await page.keyboard.press('ArrowLeft');
    await page.keyboard.press('ArrowDown');
    const moved = (await w.locator('.doorway-trap-hover').textContent()).match(/^Cell \((\d+), (\d+)\)/);
    assert.deepEqual([moved[1] - first[1], moved[2] - first[2]], [-1, -1], key);
    assert.match(await w.locator(`.doorway-trap-${key} canvas`).getAttribute('aria-label'), key === 'sweep' ? /after 0 of 7 scans/ : /after 0 flips/);
    await tabTo(page, W, `.doorway-trap-${key} button`, 'Export');
    const [download] = await Promise.all([page.waitForEvent('download'), page.keyboard.press('Enter')]);
    assert.equal(download.suggestedFilename(), `doorway-${key}.zip`);
  }

  // The two-cell diagram: arrows move B; Space switches to A.
  const cells = () => page.evaluate((s) => document.querySelector(s).twoCell.query.cells.map((c) => ({ ...c })), W);
  await tabTo(page, W, 'canvas.doorway-trap-diagram', 'Sonar cone');
  const c0 = await cells();
  await page.keyboard.press('ArrowRight');
  let c1 = await cells();
  assert.ok(Math.abs(c1[1].range - c0[1].range - 0.05) < 1e-9, 'B moves out');
  assert.deepEqual(c1[0], c0[0]);
  await page.keyboard.press('Space');
  assert.match(await w.locator('canvas.doorway-trap-diagram').getAttribute('aria-label'), /arrow keys to move cell A/);
  await page.keyboard.press('ArrowUp');
  const c2 = await cells();
  assert.ok(Math.abs(c2[0].bearing_deg - c1[0].bearing_deg - 1) < 1e-9, 'A turns');
  for (const label of ['Collinear', 'Apart', 'Side by side']) {
    await operate(page, W, 'button', label, 'Enter');
    assert.equal(await w.getByRole('button', { name: label }).getAttribute('aria-pressed'), 'true', label);
  }
  const ratio = () => page.evaluate((s) => Number(document.querySelector(`${s} .doorway-trap-ratio`).dataset.value), W);
  const r0 = await ratio();
  await operate(page, W, 'input', 'Reading z', 'ArrowLeft');
  assert.equal(await w.getByLabel('Reading z').inputValue(), '1.99');
  await operate(page, W, 'input', 'Prior p₀', 'ArrowRight');
  assert.equal(await w.getByLabel('Prior p₀').inputValue(), '0.55');
  assert.notEqual(await ratio(), r0, 'the table follows the sliders');
  // The table scrolls sideways in a narrow column: it is a Tab stop too.
  await tabTo(page, W, '.occgrid-scroll', 'Joint posterior table');
  c1 = null;
  await operate(page, W, 'button', 'Copy link', 'Enter');
  await until(page, () => new URL(location.href).searchParams.get('doorway-trap.prior') === '0.55');
  assert.deepEqual(errors, []);
  await close();
});

test('sensor fusion is driven by keyboard alone', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width: 1280, height: 900 } });
  const W = 'occgrid-sensor-fusion';
  const w = page.locator(W);
  await w.scrollIntoViewIfNeeded();
  await until(page, (s) => document.querySelector(s).dataset.step === '0', W);
  await operate(page, W, 'button', 'Step', 'Enter', 'Space', 'Enter');
  assert.equal((await data(page, W)).step, '3');
  assert.match(await w.locator('.sensor-fusion-max canvas').getAttribute('aria-label'), /after 3 of 81 scans: mean occupancy over the table’s footprint \d\.\d{3}/);
  await operate(page, W, 'button', 'Play', 'Space');
  await until(page, (s) => Number(document.querySelector(s).dataset.step) > 5, W);
  await page.keyboard.press('Enter');
  assert.equal(await w.locator('button[name=play]').getAttribute('aria-pressed'), 'false');
  await operate(page, W, 'button', 'Reset', 'Enter');
  assert.equal((await data(page, W)).step, '0');
  await operate(page, W, 'input', 'LiDAR beams', 'ArrowLeft', 'ArrowLeft');
  await until(page, (s) => document.querySelector(s).dataset.lidarBeams === '120', W);
  for (const key of ['sonar', 'lidar', 'max', 'sum']) {
    await tabTo(page, W, `.sensor-fusion-${key} button`, 'Export');
    const [download] = await Promise.all([page.waitForEvent('download'), page.keyboard.press('Enter')]);
    assert.equal(download.suggestedFilename(), `table-${key}.zip`);
  }
  await operate(page, W, 'button', 'Copy link', 'Enter');
  await until(page, () => new URL(location.href).searchParams.get('sensor-fusion.lidar-beams') === '120');
  assert.deepEqual(errors, []);
  await close();
});

test('the inverse workbench is driven by keyboard alone', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width: 1280, height: 900 } });
  const W = 'occgrid-inverse-workbench';
  const w = page.locator(W);
  await w.scrollIntoViewIfNeeded();
  await until(page, (s) => document.querySelector(s).dataset.state === 'ready', W, 30_000);
  const label = (k) => w.locator('canvas.inverse-workbench-image').nth(k).getAttribute('aria-label');

  await operate(page, W, 'input', 'Reading z', 'ArrowRight');
  await until(page, (s) => document.querySelector(s).dataset.reading === '2.05', W);
  // Each image says what it shows, with the core's numbers as printed under it.
  const free = await page.$$eval(`${W} .inverse-workbench-free`, (os) => os.map((o) => o.textContent));
  assert.match(await label(0), new RegExp(`^Hand-crafted \\(Table 9\\.2\\) inverse model: .* for a reading of 2\\.05 m, ranges 0\\.0 to 9\\.2 m, .*Mean free evidence in front of the reading: ${free[0]} log odds`));
  assert.match(await label(1), new RegExp(`^Learned \\(§9\\.3\\) inverse model: .* for a reading of 2\\.05 m, .*Mean free evidence in front of the reading: ${free[1]} log odds`));
  await page.keyboard.press('Home');
  await until(page, (s) => document.querySelector(s).dataset.reading === '0.2', W);
  assert.match(await label(1), /a reading of 0\.20 m.*too short to leave free space/);

  await operate(page, W, 'button', 'Max-range reading', 'Enter');
  await until(page, (s) => document.querySelector(s).dataset.reading === '8', W);
  assert.equal(await w.locator('button[name=max-range]').getAttribute('aria-pressed'), 'true');
  assert.match(await label(0), /a reading of 8\.00 m \(max range: a no-return\)/);
  await operate(page, W, 'input', 'Zoom to', 'Space');
  assert.equal(await w.getByLabel(/^Zoom to/).isChecked(), true);
  await until(page, (s) => /ranges 6\.5 to 9\.5 m/.test(document.querySelector(`${s} canvas.inverse-workbench-image`).getAttribute('aria-label')), W);

  // The seed: typed, then Enter retrains; or typed, then the Retrain button.
  const l0 = (await data(page, W)).learnedL0;
  await operate(page, W, 'input', 'Seed', 'Control+A');
  await page.keyboard.type('5');
  await page.keyboard.press('Enter');
  await until(page, (s) => document.querySelector(s).dataset.seed === '5', W);
  assert.notEqual((await data(page, W)).learnedL0, l0, 'another model');
  await page.keyboard.press('Control+A');
  await page.keyboard.type('9');
  await operate(page, W, 'button', 'Retrain', 'Space');
  await until(page, (s) => document.querySelector(s).dataset.seed === '9', W);
  assert.equal((await data(page, W)).learnedL0, l0, 'the same seed, the same model');

  await operate(page, W, 'button', 'Copy link', 'Enter');
  await until(page, () => new URL(location.href).searchParams.get('inverse-workbench.reading') === '8.00');
  const link = new URL(page.url());
  assert.equal(link.searchParams.get('inverse-workbench.zoom'), 'on');
  assert.equal(link.searchParams.has('inverse-workbench.seed'), false, 'seed 9 is the default');
  await screenshot(w, 'keyboard-inverse-workbench');
  assert.deepEqual(errors, []);
  await close();
});

test('Map Weaver’s real-log mode is driven by keyboard alone', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width: 1280, height: 900 } });
  const W = 'occgrid-map-weaver';
  const w = page.locator(W);
  const panel = () => page.evaluate((s) => {
    const p = document.querySelector(s).realLog;
    return { state: p.root.dataset.state, applied: p.applied, geometry: p.geometry, name: p.name, scans: p.root.dataset.scans };
  }, W);
  // The browser intercepts file choosers only once it has been asked to, and the
  // asking is a message of its own: asked here, it is in place long before the key
  // press below (asked with the press, the chooser can open unseen and never come).
  const chooserOpened = page.waitForEvent('filechooser', { timeout: 120_000 });
  await w.scrollIntoViewIfNeeded();
  await until(page, (s) => document.querySelector(s).dataset.scans === '0', W, 60_000);
  await operate(page, W, 'input[type=radio]', 'Simulated apartment', 'ArrowRight');
  await until(page, (s) => document.querySelector(`${s} .map-weaver-log select[name=dataset] option[value="intel-corrected.log.gz"]`), W);

  // The file input opens the file chooser from the keyboard.
  await tabTo(page, W, 'input[type=file]', 'Open a CARMEN log or ROS 2 bag');
  assert.equal(await page.evaluate(() => document.activeElement?.type), 'file');
  await page.keyboard.press('Space');
  const chooser = await chooserOpened;
  await chooser.setFiles(path.join(DATASETS, 'aces-corrected.log.gz'));
  await until(page, (s) => document.querySelector(s).realLog.root.dataset.state === 'done', W, 30_000);
  assert.equal((await panel()).name, 'aces-corrected.log.gz');
  // The menu: arrow keys pick a log of /datasets/.
  await operate(page, W, 'select', 'Log on this server', 'ArrowDown');
  await until(page, (s) => {
    const p = document.querySelector(s).realLog;
    return p.name === 'intel-corrected.log.gz' && p.root.dataset.state === 'done';
  }, W, 30_000);
  assert.equal((await panel()).scans, '910');

  // The map: focus, then arrows move a cursor whose cell is read out.
  await operate(page, W, 'canvas.map-weaver-log-map', '');
  assert.match(await w.locator('canvas.map-weaver-log-map').getAttribute('aria-label'),
    /^Occupancy grid map of intel-corrected\.log\.gz, [\d,]+ × [\d,]+ cells of 0\.05 m, after 910 of 910 scans: [\d,]+ cells occupied \(p > 0\.65\), [\d,]+ free \(p < 0\.196\), [\d,]+ unknown\..*Arrow keys/);
  // A press moves the cursor 16 device pixels of the view (at least a cell).
  const step = await page.evaluate((s) => Math.max(1, Math.round(16 / document.querySelector(s).realLog.view.scale)), W);
  await page.keyboard.press('ArrowRight');
  const first = await w.locator('.map-weaver-log-readout').evaluate((e) => ({ ix: Number(e.dataset.ix), iy: Number(e.dataset.iy) }));
  await page.keyboard.press('Shift+ArrowUp');
  await page.keyboard.press('ArrowLeft');
  const moved = await w.locator('.map-weaver-log-readout').evaluate((e) => ({ ix: Number(e.dataset.ix), iy: Number(e.dataset.iy), text: e.textContent }));
  assert.deepEqual([moved.ix - first.ix, moved.iy - first.iy], [-step, 10 * step], moved.text);
  assert.match(moved.text, /^cell \(\d+, \d+\) at/);

  // Settings: the resolution menu and each slider, then the map is rebuilt with them.
  await operate(page, W, 'select', 'Resolution', 'ArrowDown');
  await until(page, (s) => {
    const p = document.querySelector(s).realLog;
    return p.geometry?.resolution === 0.1 && p.root.dataset.state === 'done';
  }, W, 30_000);
  const L = `.map-weaver-log input`;
  await operate(page, W, L, 'z_max (range cap)', 'ArrowLeft');
  await operate(page, W, L, 'α (obstacle depth)', 'ArrowRight');
  await operate(page, W, L, 'l_occ', 'ArrowRight');
  await operate(page, W, L, 'l_free', 'ArrowLeft');
  await operate(page, W, L, 'clamp l_max', 'ArrowRight');
  const want = { resolution: 0.1, rangeCap: 29, alpha: 0.11, lOcc: 0.9, lFree: -0.45, clamp: 4 };
  await until(page, ([s, want]) => {
    const p = document.querySelector(s).realLog;
    const close = (a, b) => Math.abs(a - b) < 1e-9;
    return p.root.dataset.state === 'done' && Object.entries(want).every(([k, v]) => close(p.applied[k], v));
  }, [W, want], 30_000);
  assert.match(await w.locator('.map-weaver-log-status').textContent(), /910 of 910 scans, .* at 0\.1 m/);

  // Scrubbing: Home goes back to the start, End to the last scan.
  await operate(page, W, L, 'Scans integrated', 'Home');
  await until(page, (s) => /^0 of 910 scans/.test(document.querySelector(`${s} .map-weaver-log-status`).textContent), W);
  await page.keyboard.press('End');
  await until(page, (s) => /^910 of 910 scans/.test(document.querySelector(`${s} .map-weaver-log-status`).textContent), W);

  await tabTo(page, W, '.map-weaver-log button', 'Export');
  const [download] = await Promise.all([page.waitForEvent('download'), page.keyboard.press('Enter')]);
  assert.equal(download.suggestedFilename(), 'intel-corrected-map.zip');
  await operate(page, W, 'button', 'Copy link', 'Enter');
  await until(page, () => new URL(location.href).searchParams.get('map-weaver.mode') === 'log');
  const link = new URL(page.url());
  const expected = {
    log: 'intel-corrected.log.gz', 'log-resolution': '0.1', 'log-range-cap': '29', 'log-alpha': '0.11',
    'log-l-occ': '0.90', 'log-l-free': '-0.45', 'log-clamp': '4.0',
  };
  for (const [k, v] of Object.entries(expected)) assert.equal(link.searchParams.get(`map-weaver.${k}`), v, `${k} in ${link}`);
  await screenshot(w, 'keyboard-real-log');
  assert.deepEqual(errors, []);
  await close();
});

for (const width of [360, 1440]) {
  test(`at ${width} px the page does not scroll sideways and every widget fits`, async () => {
    const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width, height: 900 } });
    await visitAll(page);
    // The real-log panel too.
    await page.locator('occgrid-map-weaver').getByLabel('Real log').check();
    await page.waitForSelector('occgrid-map-weaver .map-weaver-log, occgrid-map-weaver .map-weaver-log-missing');
    await page.waitForTimeout(300);
    const fit = await page.evaluate((tags) => ({
      page: document.documentElement.scrollWidth,
      view: document.documentElement.clientWidth,
      widgets: tags.map((t) => {
        const r = document.querySelector(t).getBoundingClientRect();
        return [t, Math.round(r.left), Math.round(r.right)];
      }),
    }), ALL);
    assert.ok(fit.page <= fit.view, `page ${fit.page} px wide in a ${fit.view} px view`);
    for (const [t, left, right] of fit.widgets) assert.ok(left >= 0 && right <= fit.view, `${t}: ${left}..${right} of ${fit.view}`);
    for (const t of ALL) await screenshot(page.locator(t), `layout-${width}-${t.replace('occgrid-', '')}`);
    await page.locator('occgrid-map-weaver').getByLabel('Simulated apartment').check();
    await screenshot(page.locator('occgrid-map-weaver'), `layout-${width}-map-weaver-sim`);
    assert.deepEqual(errors, []);
    await close();
  });
}

test('at a device pixel ratio of 2 every canvas has two backing pixels per CSS pixel', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', deviceScaleFactor: 2 });
  await visitAll(page);
  await page.waitForFunction(() => document.querySelector('occgrid-inverse-workbench')?.dataset.state === 'ready', null, { timeout: 30_000 });
  const sizes = await page.evaluate((tags) => [...document.querySelectorAll(tags.map((t) => `${t} canvas`).join(', '))]
    .filter((c) => c.clientWidth > 0)
    .map((c) => ({ where: `${c.closest(tags.join(','))?.localName} ${c.className}`, css: [c.clientWidth, c.clientHeight], px: [c.width, c.height] })), ALL);
  assert.ok(sizes.length >= 15, `${sizes.length} canvases`);
  const blurry = sizes.filter((s) => Math.abs(s.px[0] - 2 * s.css[0]) > 2 || Math.abs(s.px[1] - 2 * s.css[1]) > 2);
  assert.deepEqual(blurry, [], 'canvases whose backing store is not twice their CSS size');
  await screenshot(page.locator('occgrid-doorway-trap'), 'dpr2-doorway-trap');
  assert.deepEqual(errors, []);
  await close();
});

test('under prefers-reduced-motion nothing plays by itself until the reader presses Play', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  await visitAll(page);
  for (const tag of ALL) await page.locator(tag).scrollIntoViewIfNeeded();
  await page.waitForTimeout(1500);
  const still = await page.evaluate(() => ({
    weaver: document.querySelector('occgrid-map-weaver').dataset.scans,
    sweep: document.querySelector('occgrid-doorway-trap').dataset.scan,
    flips: document.querySelector('occgrid-doorway-trap').dataset.flips,
    fusion: document.querySelector('occgrid-sensor-fusion').dataset.step,
    pressed: [...document.querySelectorAll(':is(button[name=play], button[name=sweep-play], button[name=map-play])[aria-pressed="true"]')].map((b) => b.getAttribute('aria-label') || b.textContent),
  }));
  assert.deepEqual(still, { weaver: '0', sweep: '0', flips: '0', fusion: '0', pressed: [] });
  // Pressing Play (with the keyboard) starts the motion the reader asked for.
  await operate(page, 'occgrid-sensor-fusion', 'button', 'Play', 'Enter');
  await until(page, () => Number(document.querySelector('occgrid-sensor-fusion').dataset.step) >= 3);
  assert.deepEqual(errors, []);
  await close();
});

test('a playing widget scrolled out of view does no work, and goes on when it comes back', async () => {
  const { page, errors, close } = await openPage('/', { viewport: { width: 1200, height: 800 } });
  // Each widget's progress: the sum of these data attributes.
  const cases = [
    ['occgrid-map-weaver', ['scans']],
    ['occgrid-sensor-fusion', ['step']],
    ['occgrid-doorway-trap', ['flips', 'scan']],
  ];
  const progress = ([t, keys]) => keys.reduce((sum, k) => sum + Number(document.querySelector(t).dataset[k] ?? NaN), 0);
  for (const [tag, keys] of cases) {
    await page.locator(tag).scrollIntoViewIfNeeded();
    // (Polled from here: the page's CSP rightly forbids evaluating code strings.)
    let started = 0;
    for (let i = 0; i < 600 && !(started >= 2); i++) {
      await page.waitForTimeout(100);
      started = await page.evaluate(progress, [tag, keys]);
    }
    assert.ok(started >= 2, `${tag} plays on its own when seen: ${started}`);
    // Scroll it away, below the bottom of the view (again if a widget above
    // grew meanwhile, as one does when it first comes into view).
    let away = false;
    for (let i = 0; i < 8 && !away; i++) {
      await page.evaluate((t) => {
        const e = document.querySelector(t);
        window.scrollTo(0, Math.max(0, e.getBoundingClientRect().top + window.scrollY - window.innerHeight - 40));
      }, tag);
      await page.waitForTimeout(400);
      away = await page.evaluate((t) => document.querySelector(t).getBoundingClientRect().top > window.innerHeight, tag);
    }
    assert.ok(away, `${tag} is out of view`);
    const off = await page.evaluate(progress, [tag, keys]);
    await page.waitForTimeout(1200);
    assert.equal(await page.evaluate(progress, [tag, keys]), off, `${tag} did no work off screen`);
    const playing = await page.locator(`${tag} :is(button[name=play], button[name=sweep-play], button[name=map-play])[aria-pressed="true"]`).count();
    assert.ok(playing > 0, `${tag} is still playing, only held while away`);
    await page.locator(tag).scrollIntoViewIfNeeded();
    for (let i = 0; i < 100 && (await page.evaluate(progress, [tag, keys])) <= off; i++) await page.waitForTimeout(100);
    assert.ok((await page.evaluate(progress, [tag, keys])) > off, `${tag} goes on when back in view`);
  }
  assert.deepEqual(errors, []);
  await close();
});

test('the page is served under a strict Content-Security-Policy and runs without a violation', async () => {
  const { page, errors, close } = await openPage('/');
  const response = await page.request.get(page.url());
  const csp = response.headers()['content-security-policy'];
  assert.match(csp, /script-src 'self' 'wasm-unsafe-eval'/);
  assert.doesNotMatch(csp, /unsafe-inline|'unsafe-eval'/);
  const html = await response.text();
  assert.doesNotMatch(html, /<script(?![^>]*\ssrc=)[^>]*>/, 'no inline script');
  assert.doesNotMatch(html, /<style|\sstyle=/, 'no inline styles in the markup');
  await visitAll(page);
  // Exercise what loads or draws late: the real-log panel, a chart redraw, a link.
  await page.locator('occgrid-map-weaver').getByLabel('Real log').check();
  await page.waitForSelector('occgrid-map-weaver .map-weaver-log');
  await page.locator('occgrid-map-weaver').getByLabel('Simulated apartment').check();
  await page.locator('occgrid-cell-filter').getByRole('button', { name: 'The l0 lesson' }).click();
  await page.locator('occgrid-sensor-fusion').getByRole('button', { name: 'Copy link' }).click();
  await page.waitForTimeout(500);
  assert.deepEqual(errors.filter((e) => /Content Security Policy|CSP violation/i.test(e)), []);
  assert.deepEqual(errors, []);
  await close();
});
