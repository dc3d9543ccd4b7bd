// Map Weaver's real-log panel in Chromium under scan-matched poses: a third
// pane beside the corrected and dead-reckoned maps, its path and the
// current scan's match drawn while it builds, the build finished in slices
// whose budget counts the matching, the same seed giving the same map, and
// an unknown pose source refused by name.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');
const PAGE = '/test-fixtures/real-log.html';

/** Waits until the session is done (or failed) and the panel shows it; the panel's data. */
async function settled(page, scans) {
  await page.waitForFunction((n) => {
    const panel = window.realLogPanel;
    const s = panel.session?.state();
    if (!s || s.state !== panel.root.dataset.state) return false;
    return (s.state === 'done' && s.scansDone === n) || s.state === 'failed';
  }, scans, { timeout: 120_000 });
  return page.$eval('.map-weaver-log', (e) => ({ ...e.dataset }));
}

/** A hash of a canvas's pixels. */
function pixels(page, selector) {
  return page.$eval(selector, (c) => {
    const { data } = c.getContext('2d').getImageData(0, 0, c.width, c.height);
    let h = 2166136261;
    for (let i = 0; i < data.length; i++) h = Math.imul(h ^ data[i], 16777619) >>> 0;
    return `${c.width}x${c.height}:${h}`;
  });
}

for (const [log, scans, shot] of [['aces-corrected.log.gz', 440, 'real-log-aces-scan-matched'], ['intel-corrected.log.gz', 910, 'real-log-intel-scan-matched']]) {
  test(`scan-matched poses on ${log}: a third pane beside the corrected and dead-reckoned maps, the match drawn while it builds`, async (t) => {
    const { page, errors, close } = await openPage(PAGE);
    await page.waitForSelector('#panel[data-ready]');
    await page.selectOption('.map-weaver-log select[name=poses]', 'scan-matched');
    // The match's figures under the pane while it builds: recorded by the
    // page as they change (the test waits on states, not on time).
    await page.evaluate(() => {
      // Long tasks from the file's choice on, reported (not asserted: a
      // machine's speed decides them; the slices' budgets are asserted).
      window.longTasks = [];
      new PerformanceObserver((list) => {
        for (const e of list.getEntries()) window.longTasks.push([e.startTime, e.duration]);
      }).observe({ type: 'longtask', buffered: true });
      document.addEventListener('change', (e) => { if (e.target.type === 'file') window.chosenAt ??= e.timeStamp; }, true);
      window.matchLines = [];
      new MutationObserver(() => {
        const line = document.querySelector('.map-weaver-log-match');
        if (line?.dataset.building === 'true') window.matchLines.push({ ...line.dataset });
      }).observe(document.querySelector('.map-weaver-log'), { subtree: true, childList: true, attributes: true, characterData: true });
    });
    // The scan-matched path's points the page copies out of the core, and
    // the paintings of its pane (each draws the robot once).
    await page.evaluate(() => {
      const proto = window.realLogPanel.core.RealLogSession.prototype;
      window.pathReads = { points: 0, paints: 0 };
      for (const name of ['pathPixels', 'pathPixelsBetween']) {
        const read = proto[name];
        proto[name] = function (pane, ...rest) {
          const out = read.call(this, pane, ...rest);
          if (pane === 0) window.pathReads.points += out.length / 2;
          return out;
        };
      }
      const robotAt = proto.robotAt;
      proto.robotAt = function (pane, k) {
        if (pane === 0) window.pathReads.paints++;
        return robotAt.call(this, pane, k);
      };
    });
    await page.setInputFiles('.map-weaver-log input[type=file]', path.join(DATASETS, log));
    // Part way through, the match drawn over the map being built.
    await page.waitForFunction((n) => window.matchLines.some((l) => Number(l.scan) >= n), Math.floor(scans / 3), { timeout: 120_000 });
    await screenshot(page.locator('.map-weaver-log-stage'), `${shot}-building`);
    const done = await settled(page, scans);
    assert.equal(done.state, 'done');
    const core = await page.evaluate(() => window.realLogPanel.session.state());
    assert.deepEqual(core.panes.map((p) => p.poses), ['scan-matched', 'corrected', 'dead-reckoning']);
    assert.ok(core.panes.every((p) => p.finished && p.scansDone === scans));
    assert.ok(core.work > core.cellUpdates, 'the matching is counted in the slices\' work');
    // Three maps on screen, one scale.
    assert.equal(await page.locator('.map-weaver-log-reference:visible').count(), 2);
    assert.match(await page.locator('.map-weaver-log-pane figcaption').textContent(), /Scan-matched \(from dead reckoning, seed 1\)/);
    const captions = await page.locator('.map-weaver-log-reference figcaption').allTextContents();
    assert.deepEqual(captions.map((c) => c.split(' (')[0]), ['Corrected poses', 'Dead reckoning']);
    const scales = await page.evaluate(() => {
      const p = window.realLogPanel;
      return [[p.canvas, p.geometry], ...p.sidePanes.map((s) => [s.canvas, s.geometry])].map(([c, g]) => parseFloat(c.style.width) / g.width);
    });
    assert.ok(scales.every((s) => Math.abs(s - scales[0]) < 0.01 * scales[0]), `scales ${scales}`);
    // The match was drawn while the map built, and its last figures stay.
    const lines = await page.evaluate(() => window.matchLines);
    const longTasks = await page.evaluate(() => window.longTasks.filter(([start, ms]) => start + ms > window.chosenAt).map(([, ms]) => Math.round(ms)));
    t.diagnostic(`file to maps ${done.totalMs} ms; long tasks: ${longTasks.length ? longTasks.join(', ') : 'none (all under 50)'} ms`);
    t.diagnostic(`${lines.length} match drawings while building; ${(await page.evaluate(() => window.realLogPanel.trace.filter(([w]) => w === 'build').length))} build slices`);
    assert.ok(lines.length >= 1, 'the match was drawn while building');
    // Its path grew by the scans matched since the last painting: read
    // whole once at layout, then each point once, however often painted.
    const reads = await page.evaluate(() => window.pathReads);
    t.diagnostic(`path points read ${reads.points} over ${reads.paints} paintings`);
    assert.ok(reads.paints >= 3, `painted ${reads.paints} times`);
    assert.ok(reads.points <= 3 * scans, `${reads.points} path points read for ${scans} scans`);
    assert.ok(lines.every((l) => Number(l.scan) < scans));
    const last = await page.locator('.map-weaver-log-match').textContent();
    assert.match(last, new RegExp(`^scan ${(scans - 1).toLocaleString('en-US')} `));
    assert.match(last, /match score \d\.\d\d/);
    // Its path is the matched one: not the dead-reckoned pane's.
    const [matchedPath, drPath] = await page.evaluate(() => [0, 2].map((k) => Array.from(window.realLogPanel.session.pathPixels(k))));
    assert.equal(matchedPath.length, 2 * scans);
    assert.notDeepEqual(matchedPath, drPath);
    // Each task holds one core call; each build slice within its budget
    // plus one scan of each pane (a scan's matching and updates).
    const trace = await page.evaluate(() => window.realLogPanel.trace);
    const tasks = [[]];
    for (const entry of trace) {
      if (entry[0] === 'yield') tasks.push([]);
      else if (['read', 'build', 'draw'].includes(entry[0])) tasks.at(-1).push(entry[0]);
    }
    for (const [k, task] of tasks.entries()) assert.ok(task.length <= 1, `task ${k} made ${task.join(', ')}`);
    const builds = trace.filter(([w]) => w === 'build');
    for (const [k, [, , budget]] of builds.entries()) {
      if (k > 0) assert.ok(budget <= 2 * builds[k - 1][2], `slice ${k}: ${budget} after ${builds[k - 1][2]}`);
    }
    await screenshot(page.locator('.map-weaver-log-stage'), shot);

    // The same seed again: the same map, pixel for pixel.
    const map = await pixels(page, '.map-weaver-log-map');
    await page.selectOption('.map-weaver-log select[name=poses]', 'corrected');
    await settled(page, scans);
    await page.selectOption('.map-weaver-log select[name=poses]', 'scan-matched');
    await settled(page, scans);
    assert.equal(await pixels(page, '.map-weaver-log-map'), map, 'one seed, one scan-matched map');

    // An unknown pose source is refused by the core, naming it; nothing changes.
    const refusal = await page.evaluate(() => {
      try {
        window.realLogPanel.session.configure({ poses: 'scan-match' });
        return null;
      } catch (e) {
        return e.message;
      }
    });
    assert.match(refusal, /poses/);
    assert.match(refusal, /scan-match/);
    assert.equal(await page.evaluate(() => window.realLogPanel.session.state().panes.length), 3);
    assert.deepEqual(errors, []);
    await close();
  });
}

test('log-poses accepts scan-matched and says so among the choices of a bad value', async () => {
  const { page, errors, close } = await openPage('/');
  await page.evaluate(() => {
    const w = document.createElement('occgrid-map-weaver');
    w.id = 'sm';
    w.setAttribute('mode', 'log');
    w.setAttribute('log-poses', 'matched');
    w.setAttribute('autoplay', 'off');
    document.body.prepend(w);
  });
  const box = page.locator('#sm > .occgrid-attribute-error');
  await box.waitFor();
  assert.match(await box.textContent(), /invalid log-poses: "matched" \(expected one of "corrected", "dead-reckoning", "scan-matched", "odometry", "slam"\)/);
  await page.evaluate(() => document.getElementById('sm').setAttribute('log-poses', 'scan-matched'));
  await page.waitForFunction(() => !document.querySelector('#sm > .occgrid-attribute-error'));
  await page.waitForFunction(() => document.querySelector('#sm .map-weaver-log select[name=poses]')?.value === 'scan-matched');
  assert.equal((await page.evaluate(() => document.getElementById('sm').linkState()))['log-poses'], 'scan-matched');
  assert.ok(errors.every((e) => /log-poses/.test(e)), errors.join(' | '));
  await close();
});
