// The chapter's Map Weaver exercises done in Chromium the way a reader does
// them: each opens from its link in the page's "Exercises" section, the
// reader turns the knobs the text names, and the answer is read off the
// widget's screen text and its data attributes (the core computes them).
// Exercise 5 (the largest clamp whose ghost fades within about 5 s at the
// chapter's strength 3, and the fade's two proportionalities, in the ghost
// watch), exercise 6 (the
// cells where traversal and sweep differ for the thin LiDAR, and why) and
// exercise 8 (the Brier scores and the drift of a map that forgets l0).
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const W = 'occgrid-map-weaver';

/** The page's link for exercise `n`: its query and fragment. */
async function exerciseLink(n) {
  const { page, close } = await openPage('/', { reducedMotion: 'reduce' });
  const href = await page.getAttribute(`#exercises a[data-exercise="${n}"]`, 'href');
  await close();
  return `/${href}`;
}

/** Opens exercise `n`'s link and waits for Map Weaver's run (and the scans the link asks for). */
async function openExercise(n, viewport) {
  const opened = await openPage(await exerciseLink(n), { reducedMotion: 'reduce', viewport });
  const w = opened.page.locator(W);
  await w.scrollIntoViewIfNeeded();
  const scans = Number(new URL(await exerciseLink(n), 'http://x/').searchParams.get('map-weaver.scans') ?? 0);
  await opened.page.waitForFunction(([t, s]) => {
    const el = document.querySelector(t);
    return el.weaver && el.dataset.scans === String(s) && !el.dataset.fastForward;
  }, [W, scans], { timeout: 60_000 });
  return { ...opened, w };
}

/** Waits until the run holds `scans` scans, not playing, with no pane still rebuilt over them. */
async function rebuilt(page, scans) {
  await page.waitForFunction(([t, s]) => {
    const el = document.querySelector(t);
    const r = el.weaver.readout();
    return r.scans === s && !el.playing && !/rebuilding/.test(el.status.textContent);
  }, [W, scans], { timeout: 120_000 });
}

/** Moves a pane's slider to `value` as a reader would (its input event). */
async function setSlider(page, name, value) {
  await page.evaluate(([t, n, v]) => {
    const input = document.querySelector(`${t} input[name="${n}"]`);
    input.value = String(v);
    input.dispatchEvent(new Event('input', { bubbles: true }));
  }, [W, name, value]);
}

/** Presses Reset, then plays `n` scans at once (the core's advance, then a full redraw). */
async function resetAndRun(page, w, n) {
  await w.getByRole('button', { name: 'Reset' }).click();
  await page.evaluate(([t, k]) => {
    const el = document.querySelector(t);
    el.weaver.advance(k);
    el.draw(true);
  }, [W, n]);
}

/** A pane's ghost-fade line and numbers, as the widget shows them. */
async function ghost(w, side) {
  const pane = w.locator(`.map-weaver-${side}`);
  const text = await pane.locator('.map-weaver-ghost').textContent();
  const d = await pane.evaluate((p) => ({ ...p.dataset }));
  const m = /slowest ([\d,]+) scans? \(([\d.]+) s\)/.exec(text);
  assert.ok(m, `${side}: a slowest fade on screen: ${text}`);
  const r = /l_max \/ \|l_free\| = ([\d.]+) \/ ([\d.]+) = ([\d.]+) contradicting scans \(([\d.]+) s\)/.exec(text);
  assert.ok(r, `${side}: the recursion's time on screen: ${text}`);
  assert.equal(Number(m[2]).toFixed(2), Number(d.ghostLongestSeconds).toFixed(2));
  return { text, scans: Number(m[1].replaceAll(',', '')), seconds: Number(m[2]), recursionScans: Number(r[3]), clamp: Number(d.clamp), strength: Number(d.strength) };
}

test('exercise 5: in the ghost watch at the chapter’s strength 3, the largest clamp whose ghost fades within about 5 s is 72, and the fade follows l_max / |l_free|', async () => {
  const { page, errors, close, w } = await openExercise(5, { width: 1280, height: 800 });
  assert.equal(await w.evaluate((el) => el.dataset.situation), 'ghost-watch');
  assert.equal(await w.getByLabel('Robot').inputValue(), 'ghost-watch');
  // Parked, the status line counts no lap.
  const status = await w.locator('.map-weaver-status').textContent();
  assert.match(status, /^Parked in the corridor · scan 300 of /);
  assert.doesNotMatch(status, /Lap \d/);
  // The link: clamps 72 and 36 at strength 3 (|l_free| = 1.2), 300 scans.
  const left = await ghost(w, 'left');
  const right = await ghost(w, 'right');
  assert.deepEqual([left.clamp, left.strength, right.clamp, right.strength], [72, 3, 36, 3]);
  assert.deepEqual([left.recursionScans, right.recursionScans], [60, 30]);
  console.log(`exercise 5, the link: clamp 72 slowest ${left.scans} scans (${left.seconds} s), clamp 36 ${right.scans} scans (${right.seconds} s)`);
  await screenshot(w.locator('.map-weaver-panes'), 'exercise-5-ghost-watch');

  // The reader moves the right clamp and times the next departure, from
  // 66 up, 2.5 contradicting scans apart, until the fade passes about 5 s.
  const fades = new Map();
  for (const clamp of [66, 69, 72, 75, 78]) {
    await setSlider(page, 'clamp-right', clamp);
    await resetAndRun(page, w, 300);
    const g = await ghost(w, 'right');
    assert.equal(g.clamp, clamp);
    fades.set(clamp, g);
  }
  // "Within about 5 s": within one scan (1/12 s) of it.
  const within = [...fades].filter(([, g]) => g.seconds <= 5 + 1 / 12).map(([c]) => c);
  const answer = Math.max(...within);
  console.log(`exercise 5: slowest fades ${[...fades].map(([c, g]) => `${c} → ${g.seconds} s`).join(', ')}; largest clamp within about 5 s: ${answer}`);
  assert.equal(answer, 72);
  // Linear in l_max: each fade is l_max / |l_free| scans, to one scan.
  for (const [c, g] of fades) {
    assert.ok(Math.abs(g.scans - g.recursionScans) <= 1, `clamp ${c}: ${g.scans} scans against ${g.recursionScans}`);
    assert.ok(Math.abs(g.recursionScans - c / 1.2) < 1e-9, `clamp ${c}: ${g.recursionScans}`);
  }
  // Inversely proportional to |l_free|: at strength 1.5 (|l_free| = 0.6)
  // the clamp-72 fade doubles.
  await setSlider(page, 'clamp-right', 72);
  await setSlider(page, 'strength-right', 1.5);
  await resetAndRun(page, w, 300);
  const weak = await ghost(w, 'right');
  const strong = fades.get(72);
  console.log(`exercise 5: clamp 72 at strength 3 → ${strong.scans} scans, at strength 1.5 → ${weak.scans} scans`);
  assert.equal(weak.recursionScans, 120);
  assert.ok(Math.abs(strong.scans * 2 - weak.scans) <= 2, `${strong.scans} → ${weak.scans}`);
  assert.deepEqual(errors, []);
  await close();
});

test('exercise 6: with the thin LiDAR, traversal and sweep differ in cells the widget counts (as the two exports do), and it names Table 9.2’s line 1', async () => {
  const { page, errors, close, w } = await openExercise(6);
  await page.selectOption(`${W} select[name="sensor-right"]`, 'lidar');
  await page.waitForFunction((t) => document.querySelector(`${t} .map-weaver-right`).dataset.sensor === 'lidar', W);
  // The link lands paused after the first lap's 653 scans: the right pane
  // is rebuilt over them with the new sensor.
  await rebuilt(page, 653);
  const line = w.locator('.map-weaver-comparison');
  const text = await line.textContent();
  const m = /differ in ([\d,]+) of ([\d,]+) cells/.exec(text);
  assert.ok(m, text);
  const shown = Number(m[1].replaceAll(',', ''));
  assert.equal(Number(m[2].replaceAll(',', '')), 10_800);
  assert.match(text, /Table 9\.2’s line 1 \(\|φ − θk\| > β\/2: no information\)/);
  // The same count from the two exported maps, byte by byte.
  const byExport = await w.evaluate((el) => {
    const [a, b] = [0, 1].map((k) => el.weaver.exportMap(k).pgm);
    const body = (p) => p.subarray(p.length - 10_800);
    const [x, y] = [body(a), body(b)];
    let n = 0;
    for (let i = 0; i < x.length; i++) if (x[i] !== y[i]) n++;
    return n;
  });
  console.log(`exercise 6: thin LiDAR after 653 scans, traversal against sweep: ${shown} of 10,800 cells differ (exports: ${byExport})`);
  assert.equal(shown, byExport);
  // The count the exercise's text gives for the first lap.
  assert.equal(shown, 485);
  assert.equal(await line.getAttribute('data-cells-differ'), String(shown));
  await screenshot(w.locator('.map-weaver-sim'), 'exercise-6-thin-lidar-difference');
  assert.deepEqual(errors, []);
  await close();
});

test('exercise 8: the map that forgets l0 scores worse by Brier, and the widget measures its drift per update as the model’s own l0', async () => {
  // The link lands paused after the first lap's 653 scans.
  const { page, errors, close, w } = await openExercise(8);
  await rebuilt(page, 653);
  const brier = async (side) => Number(await w.locator(`.map-weaver-${side} .map-weaver-brier`).textContent());
  const [kept, forgot] = [await brier('left'), await brier('right')];
  const line = w.locator('.map-weaver-comparison');
  const text = await line.textContent();
  const m = /model’s own l0 = ([−+\-\d.]+) .*measured ([−+\-\d.]+) per update \(median over ([\d,]+) cells/.exec(text);
  assert.ok(m, text);
  const num = (s) => Number(s.replaceAll('−', '-').replaceAll(',', ''));
  const [l0, drift, cells] = [num(m[1]), num(m[2]), num(m[3])];
  console.log(`exercise 8 after 653 scans: Brier ${kept} (subtracts l0) vs ${forgot} (forgets); l0 = ${l0}, measured drift ${drift} per update over ${cells} cells`);
  assert.match(text, /Right map forgets l0/);
  assert.ok(forgot > kept, `${forgot} vs ${kept}`);
  assert.ok(l0 < -0.2, `${l0}`);
  assert.ok(Math.abs(drift - l0) <= 0.001, `${drift} vs ${l0}`);
  assert.ok(cells > 50, `${cells}`);
  // The text asks for what is on screen: the Brier scores and this line.
  const linkText = await openPage('/', { reducedMotion: 'reduce' }).then(async (o) => {
    const t = await o.page.locator('#exercise-8').textContent();
    await o.close();
    return t;
  });
  assert.doesNotMatch(linkText, /entropy/i, 'the entropy curves overlap: the text does not ask for them');
  assert.match(linkText, /Brier/);
  await screenshot(w.locator('.map-weaver-sim'), 'exercise-8-drift');
  assert.deepEqual(errors, []);
  await close();
});

test('exercise 8: the link shows where each map is closer to the truth, cell by cell, and the cells add up to the two Brier scores', async () => {
  const { page, errors, close, w } = await openExercise(8);
  await rebuilt(page, 653);
  const view = w.locator('.map-weaver-brier-map');
  const canvas = view.locator('canvas');
  await canvas.waitFor({ state: 'visible' });
  const brier = async (side) => Number(await w.locator(`.map-weaver-${side} .map-weaver-brier`).textContent());
  const [kept, forgot] = [await brier('left'), await brier('right')];
  const d = await view.evaluate((n) => ({ ...n.dataset }));
  const [mean, left, right, tied, region] = ['mean', 'leftCloser', 'rightCloser', 'tied', 'region'].map((k) => Number(d[k]));
  console.log(`exercise 8 per-cell: left closer in ${left}, right in ${right}, alike ${tied} of ${region}; mean ${mean} against ${forgot} - ${kept}`);
  // The printed scores are rounded to four places: their gap to within 1e-4.
  assert.ok(Math.abs(mean - (forgot - kept)) <= 1e-4 + 1e-12, `${mean} vs ${forgot} - ${kept}`);
  assert.equal(left + right + tied, region);
  assert.ok(left > right && right > 0, `${left} vs ${right}`);
  assert.match(await view.locator('.map-weaver-brier-map-counts').textContent(), /left map is closer to the truth in [\d,]+ cells/);
  // Drawn: the canvas holds both colours, in proportion to the counts.
  const hues = await canvas.evaluate((c) => {
    const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let blue = 0;
    let red = 0;
    for (let i = 0; i < px.length; i += 4) {
      const [r, g, b] = [px[i], px[i + 1], px[i + 2]];
      if (b > r + 40 && b > g) blue++;
      else if (r > b + 40 && r > g) red++;
    }
    return { blue, red };
  });
  assert.ok(hues.blue > 0 && hues.red > 0 && hues.blue > hues.red, JSON.stringify(hues));
  // On screen at 1280x800 once the reader scrolls to it, and the switch hides it.
  await canvas.scrollIntoViewIfNeeded();
  const box = await canvas.boundingBox();
  assert.ok(box.width > 100 && box.y >= 0 && box.y + box.height <= 800, JSON.stringify(box));
  await view.getByRole('checkbox').uncheck();
  await canvas.waitFor({ state: 'hidden' });
  assert.equal(await w.evaluate((n) => n.getAttribute('brier-map')), 'off');
  assert.deepEqual(errors, []);
  await close();
});
