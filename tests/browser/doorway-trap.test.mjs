// The chapter page in Chromium: <occgrid-doorway-trap> steps the MAP climb
// (the per-beam bar chart and the objective curve follow each flip), sweeps
// Table 9.1 until the door is closed, and recomputes the two-cell joint
// posterior when a cell moves.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const SELECTOR = 'occgrid-doorway-trap';

async function ready(page) {
  const w = page.locator(SELECTOR);
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction((s) => document.querySelector(s)?.dataset.flips !== undefined, SELECTOR);
  await page.waitForFunction((s) => document.querySelectorAll(`${s} .doorway-trap-joint tbody tr`).length === 4, SELECTOR);
  return w;
}

/** The widget's state as the page shows it. */
const state = (w) => w.evaluate((el) => {
  const bars = el.querySelector('.doorway-trap-bars');
  const curve = el.querySelector('.doorway-trap-curve');
  return {
    ...el.dataset,
    flips: Number(el.dataset.flips),
    scan: Number(el.dataset.scan),
    objective: Number(el.dataset.objective),
    bars: { flip: Number(bars.dataset.flip), count: Number(bars.dataset.bars), values: JSON.parse(bars.dataset.values) },
    curve: { points: Number(curve.dataset.points), last: Number(curve.dataset.last) },
    flipText: el.querySelector('.doorway-trap-flip').textContent,
  };
});

/** The two-cell table as printed: exact values and printed text. */
const joint = (w) => w.evaluate((el) => {
  const rows = [...el.querySelectorAll('.doorway-trap-joint tbody tr')];
  const cellsOf = (tr) => [...tr.querySelectorAll('td')];
  return {
    labels: rows.map((tr) => tr.querySelector('th').textContent),
    joint: rows.map((tr) => Number(cellsOf(tr)[2].dataset.value)),
    jointText: rows.map((tr) => cellsOf(tr)[2].textContent),
    factored: rows.map((tr) => Number(cellsOf(tr)[3].dataset.value)),
    pa: Number(el.querySelector('.doorway-trap-pa').dataset.value),
    pb: Number(el.querySelector('.doorway-trap-pb').dataset.value),
    ratio: Number(el.querySelector('.doorway-trap-ratio').dataset.value),
    ratioText: el.querySelector('.doorway-trap-ratio').textContent,
  };
});

/** Counts pixels of a colour family in a canvas (e.g. the green bars). */
const greenPixels = (w, selector) => w.evaluate((el, sel) => {
  const c = el.querySelector(sel);
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let n = 0;
  for (let i = 0; i < d.length; i += 4) if (d[i + 1] > 120 && d[i] < 80 && d[i + 2] < 110) n++;
  return n;
}, selector);

const near = (a, b, tol, what) => assert.ok(Math.abs(a - b) <= tol, `${what}: ${a} vs ${b}`);

test('stepping the MAP climb updates the per-beam bars and the objective; it ends with the door open', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width: 1200, height: 1000 } });
  const w = await ready(page);
  let s = await state(w);
  assert.equal(s.flips, 0, 'no autoplay under prefers-reduced-motion');
  assert.equal(s.scan, 0);
  assert.equal(s.bars.count, 0, 'no flip, no bars');
  assert.equal(s.curve.points, 1, 'the all-free objective alone');

  const step = w.getByRole('button', { name: 'Step the MAP climb by one flip' });
  let previous = s.objective;
  for (let k = 1; k <= 3; k++) {
    await step.click();
    await page.waitForFunction(([sel, n]) => document.querySelector(sel).dataset.flips === String(n), [SELECTOR, k]);
    s = await state(w);
    assert.equal(s.bars.flip, k, 'the bar chart shows the current flip');
    assert.ok(s.bars.count >= 1, `flip ${k} changed no beam`);
    assert.ok(s.objective > previous, `flip ${k} did not raise the objective`);
    assert.equal(s.curve.points, k + 1, 'one more point on the objective curve');
    assert.equal(s.curve.last, s.objective);
    // The printed gain is the sum of the bars (the prior term is 0 at p0 = 0.5).
    const gain = Number(s.flipText.match(/gain ([+-][0-9.]+) nats/)[1]);
    near(s.bars.values.reduce((a, b) => a + b, 0), s.objective - previous, 1e-9, 'bars vs objective change');
    near(gain, s.objective - previous, 5e-4, 'printed gain');
    assert.match(s.flipText, new RegExp(`^Flip ${k}: cell \\(\\d+, \\d+\\) set occupied`));
    previous = s.objective;
  }
  // The chart draws its latest data at a bounded rate, on a timer after
  // the flip: wait for the drawing (on a loaded machine it comes later).
  await page.waitForFunction(([sel, bars]) => {
    const c = document.querySelector(sel).querySelector(bars);
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i + 1] > 120 && d[i] < 80 && d[i + 2] < 110) n++;
    return n > 200;
  }, [SELECTOR, '.doorway-trap-bars canvas'], { timeout: 15_000 }).catch(() => {});
  assert.ok(await greenPixels(w, '.doorway-trap-bars canvas') > 200, 'the bars are drawn');
  await screenshot(w, 'doorway-trap-3-flips');

  // Hovering a map cell reads it from the core.
  const map = w.locator('.doorway-trap-map canvas.doorway-trap-canvas');
  const box = await map.boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height * 0.35);
  assert.match(await w.locator('.doorway-trap-hover').textContent(), /^Cell \(\d+, \d+\) · swept: l = /);

  // Play to the local maximum.
  await w.getByRole('button', { name: 'Play the MAP climb' }).click();
  await page.waitForFunction((sel) => document.querySelector(sel).dataset.converged === 'true', SELECTOR, { timeout: 30_000 });
  s = await state(w);
  assert.ok(s.flips >= 10, `${s.flips} flips`);
  assert.equal(s.mapInDoorway, '0', 'MAP leaves the doorway open');
  assert.ok(Number(s.mapOnFarWall) >= 1, 'MAP puts a cell on the far wall');
  assert.match(await w.locator('.doorway-trap-map .doorway-trap-status').textContent(), /local maximum/);

  // The literal sweep closes it, scan by scan.
  const next = w.getByRole('button', { name: 'Next scan' });
  for (let k = 1; k <= 7; k++) {
    await next.click();
    await page.waitForFunction(([sel, n]) => document.querySelector(sel).dataset.scan === String(n), [SELECTOR, k]);
  }
  s = await state(w);
  assert.equal(s.sweepClosed, s.doorCells, 'every doorway cell ends occupied in the swept grid');
  assert.match(await w.locator('.doorway-trap-sweep .doorway-trap-door').textContent(), /the door is closed/);
  await screenshot(w, 'doorway-trap-converged');

  // Both maps leave as ROS map_server pairs (one zip each).
  for (const [label, file] of [['Export map (MAP map)', 'doorway-map.zip'], ['Export map (swept map)', 'doorway-sweep.zip']]) {
    const [download] = await Promise.all([page.waitForEvent('download'), w.getByRole('button', { name: label }).click()]);
    assert.equal(download.suggestedFilename(), file);
  }
  const pair = await w.evaluate((el) => {
    const p = el.trap.exportMap('map');
    return { bytes: p.pgm.length, header: new TextDecoder().decode(p.pgm.slice(0, 2)), yaml: p.yaml };
  });
  assert.equal(pair.header, 'P5');
  assert.match(pair.yaml, /image: doorway-map\.pgm/);
  assert.match(pair.yaml, /resolution: 0\.1/);

  // Reset goes back to the all-free start.
  await w.getByRole('button', { name: 'Reset' }).nth(1).click();
  await page.waitForFunction((sel) => document.querySelector(sel).dataset.flips === '0', SELECTOR);
  assert.equal((await state(w)).bars.count, 0);

  assert.deepEqual(errors, []);
  await close();
});

test('the two-cell table shows the chapter’s numbers and follows a moved cell and a new reading', async () => {
  const { page, errors, close } = await openPage('/', { reducedMotion: 'reduce', viewport: { width: 1200, height: 1000 } });
  const w = await ready(page);
  await w.locator('.doorway-trap-two-cell').scrollIntoViewIfNeeded();

  // Side by side at 2 m, one reading of 2.0 m: the chapter's table.
  let t = await joint(w);
  assert.deepEqual(t.labels, ['0 0', '1 0', '0 1', '1 1']);
  [0.0047, 0.3318, 0.3318, 0.3318].forEach((want, k) => near(t.joint[k], want, 1e-3, `joint ${t.labels[k]}`));
  assert.deepEqual(t.jointText, ['0.0047', '0.3318', '0.3318', '0.3318']);
  near(t.pa, 0.6635, 1e-3, 'p_A');
  near(t.pb, 0.6635, 1e-3, 'p_B');
  near(t.factored[0], 0.1132, 1e-3, 'both free, factored');
  assert.equal(Math.round(t.ratio), 24);
  assert.equal(t.ratioText, '23.9×');
  await screenshot(w.locator('.doorway-trap-two-cell'), 'doorway-trap-two-cell-side-by-side');

  // Collinear, the chapter's exercise: A at 1 m and B at 2 m on the axis.
  // A free A and an occupied B explain the echo; the factored map finds
  // "both occupied" about twice too likely.
  await w.getByRole('button', { name: 'Collinear' }).click();
  t = await joint(w);
  near(t.joint.reduce((a, b) => a + b, 0), 1, 1e-12, 'sum of the joint');
  assert.ok(t.pa < 0.05, `A in front of the echo is free: p_A ${t.pa}`);
  assert.ok(t.pb > 0.95, `B at the echo: p_B ${t.pb}`);
  const occ = await w.evaluate((el) => ({
    truly: Number(el.querySelector('.doorway-trap-occ-true').dataset.value),
    factored: Number(el.querySelector('.doorway-trap-occ-factored').dataset.value),
  }));
  near(occ.truly, t.joint[3], 1e-12, '"both occupied" is the table\'s 11 row');
  assert.ok(occ.factored / occ.truly > 1.5 && occ.factored / occ.truly < 2.5, `both occupied: ${occ.factored} vs ${occ.truly}`);
  assert.equal(await w.getByRole('button', { name: 'Collinear' }).getAttribute('aria-pressed'), 'true');
  await screenshot(w.locator('.doorway-trap-two-cell'), 'doorway-trap-two-cell-collinear');

  // Drag A (at 1 m) behind B, to about 2.5 m: it hides, and keeps its prior.
  const [from, to] = await w.evaluate((el) => {
    const f = el.twoCell.diagramFrame();
    const rect = el.querySelector('.doorway-trap-diagram').getBoundingClientRect();
    const k = rect.width / f.W;
    const at = (r, b) => { const [x, y] = f.toXY(r, b); return { x: rect.left + x * k, y: rect.top + y * k }; };
    return [at(1.0, 0), at(2.5, 0)];
  });
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move((from.x + to.x) / 2, (from.y + to.y) / 2, { steps: 4 });
  await page.mouse.move(to.x, to.y, { steps: 4 });
  await page.mouse.up();
  t = await joint(w);
  near(t.pa, 0.5, 0.03, 'p_A behind B');
  assert.ok(t.pb > 0.9, `B still explains the echo: p_B ${t.pb}`);
  assert.equal(await w.getByRole('button', { name: 'Collinear' }).getAttribute('aria-pressed'), 'false');
  await screenshot(w.locator('.doorway-trap-two-cell'), 'doorway-trap-two-cell-dragged');

  // Back to side by side, then move B with the keyboard and the reading with its slider.
  await w.getByRole('button', { name: 'Side by side' }).click();
  const diagram = w.locator('.doorway-trap-diagram');
  await diagram.focus();
  for (let i = 0; i < 10; i++) await page.keyboard.press('ArrowLeft');
  t = await joint(w);
  assert.match(await diagram.getAttribute('aria-label'), /cell B at 1\.50 m/);
  assert.ok(t.pb < 0.1, `B moved to 1.5 m: p_B ${t.pb}`);
  assert.ok(t.ratio < 3, `apart, the factored map errs far less: ${t.ratio}`);

  await w.getByRole('button', { name: 'Side by side' }).click();
  const reading = w.getByLabel('Reading z');
  await reading.focus();
  await page.keyboard.press('End'); // 3.00 m: no echo
  t = await joint(w);
  assert.ok(t.joint[0] > 0.9, `no echo: both free is likely, ${t.joint[0]}`);
  assert.ok(t.pa < 0.3 && t.pb < 0.3, `no echo: ${t.pa}, ${t.pb}`);
  assert.match(await reading.getAttribute('aria-valuetext'), /no echo/);
  await screenshot(w.locator('.doorway-trap-two-cell'), 'doorway-trap-two-cell-no-echo');

  assert.deepEqual(errors, []);
  await close();
});

test('without reduced motion the widget plays both halves on its own', async () => {
  const { page, errors, close } = await openPage('/', { viewport: { width: 1200, height: 1000 } });
  const w = await ready(page);
  await page.waitForFunction((sel) => {
    const d = document.querySelector(sel).dataset;
    return Number(d.flips) >= 2 && Number(d.scan) >= 2;
  }, SELECTOR, { timeout: 20_000 });
  await w.getByRole('button', { name: 'Pause the MAP climb' }).click();
  await w.getByRole('button', { name: 'Pause the sweep' }).click();
  const s = await state(w);
  assert.ok(s.bars.count >= 1);
  await screenshot(w, 'doorway-trap-playing');
  assert.deepEqual(errors, []);
  await close();
});

test('the swept pane’s caption names the scene’s own cone opening', async () => {
  const { page, errors, close } = await openPage('/');
  const w = await ready(page);
  const note = () => w.locator('.doorway-trap-sweep .doorway-trap-note').textContent();
  assert.equal(await note(), '· every cell, the nearest 22° cone, Table 9.2');
  await w.evaluate((el) => el.setAttribute('scene', '{"sonar": {"beta_deg": 30}}'));
  await page.waitForFunction((s) => /30°/.test(document.querySelector(`${s} .doorway-trap-sweep .doorway-trap-note`).textContent), SELECTOR);
  assert.equal(await note(), '· every cell, the nearest 30° cone, Table 9.2');
  assert.deepEqual(errors, []);
  await close();
});
