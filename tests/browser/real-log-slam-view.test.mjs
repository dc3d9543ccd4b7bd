// Map Weaver's real-log panel under SLAM poses: the pose error against the
// log's corrected poses under the maps (a finite figure, the one an
// independent alignment of the page's own poses gives), and the pose graph
// drawn over the SLAM pane on request: loop closures in their colour when
// the toggle is on, none of that colour when it is off.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { openPage, screenshot, shutdown } from './harness.mjs';

after(shutdown);

const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');
const PAGE = '/test-fixtures/real-log.html';
const SCANS = 910;

/** Pixels of the main map near the loop closures' colour (#e7298a), anti-aliased edges allowed. */
function loopPixels(page) {
  return page.$eval('.map-weaver-log-map', (c) => {
    const { data } = c.getContext('2d').getImageData(0, 0, c.width, c.height);
    let n = 0;
    for (let i = 0; i < data.length; i += 4) {
      if (Math.abs(data[i] - 231) < 24 && Math.abs(data[i + 1] - 41) < 30 && Math.abs(data[i + 2] - 138) < 24) n++;
    }
    return n;
  });
}

/**
 * The aligned ATE of `tsv` against `reference` (poses.tsv texts), computed
 * here from centred positions, two passes: independent of the core's
 * running sums.
 */
function alignedAte(tsv, reference) {
  const xy = (t) => t.trim().split('\n').map((l) => l.split(' ').slice(1, 3).map(Number));
  const [p, q] = [xy(tsv), xy(reference)];
  const n = p.length;
  const mean = (a) => a.reduce(([sx, sy], [x, y]) => [sx + x / n, sy + y / n], [0, 0]);
  const [mp, mq] = [mean(p), mean(q)];
  let [a, b] = [0, 0];
  for (let k = 0; k < n; k++) {
    const [px, py, qx, qy] = [p[k][0] - mp[0], p[k][1] - mp[1], q[k][0] - mq[0], q[k][1] - mq[1]];
    a += px * qx + py * qy;
    b += px * qy - py * qx;
  }
  const [s, c] = [Math.sin(Math.atan2(b, a)), Math.cos(Math.atan2(b, a))];
  let sum = 0;
  for (let k = 0; k < n; k++) {
    const [px, py] = [p[k][0] - mp[0], p[k][1] - mp[1]];
    sum += (c * px - s * py + mq[0] - q[k][0]) ** 2 + (s * px + c * py + mq[1] - q[k][1]) ** 2;
  }
  return Math.sqrt(sum / n);
}

test('SLAM poses on the Intel log: the pose error under the maps, the pose graph over the SLAM pane on request', async (t) => {
  const { page, errors, close } = await openPage(PAGE);
  await page.waitForSelector('#panel[data-ready]');
  await page.selectOption('.map-weaver-log select[name=poses]', 'slam');
  await page.setInputFiles('.map-weaver-log input[type=file]', path.join(DATASETS, 'intel-corrected.log.gz'));
  await page.waitForFunction((n) => {
    const panel = window.realLogPanel;
    const s = panel.session?.state();
    return s && s.state === panel.root.dataset.state && ((s.state === 'done' && s.scansDone === n) || s.state === 'failed');
  }, SCANS, { timeout: 600_000 });
  const core = await page.evaluate(() => window.realLogPanel.session.state());
  assert.equal(core.state, 'done');
  assert.deepEqual(core.panes.map((p) => p.poses), ['slam', 'corrected', 'dead-reckoning']);
  assert.ok(core.panes[0].loopClosures > 0, 'the Intel log closes loops');

  // The pose error: a finite figure over every scan, the one an
  // independent alignment of the pane's own poses gives.
  const line = page.locator('.map-weaver-log-pose-error');
  await line.waitFor();
  const figures = await line.evaluate((e) => ({ ...e.dataset, text: e.textContent }));
  const ate = Number(figures.ateM);
  assert.ok(Number.isFinite(ate) && ate > 0, `ATE ${figures.ateM}`);
  assert.equal(Number(figures.scans), SCANS);
  assert.match(figures.text, /^Pose error against the log’s corrected poses: \d+\.\d{3} m RMS over 910 scans after the best rigid alignment/);
  const [slamTsv, correctedTsv] = await page.evaluate(() => [0, 1].map((k) => window.realLogPanel.session.posesTsv(k)));
  const independent = alignedAte(slamTsv, correctedTsv);
  t.diagnostic(`aligned ATE in the page ${ate} m, independently ${independent} m; ${core.panes[0].loopClosures} loop closures`);
  assert.ok(Math.abs(ate - independent) < 1e-6, `${ate} against ${independent}`);
  // The corrected pane has none: the pane at the log's own poses.
  assert.equal(await page.evaluate(() => window.realLogPanel.session.poseError(1) ?? null), null);

  // The pose graph: offered for the SLAM pane, off at first, no loop colour.
  const toggle = page.locator('.map-weaver-log input[name=pose-graph]');
  await toggle.waitFor();
  assert.equal(await toggle.isChecked(), false);
  assert.equal(await loopPixels(page), 0, 'no loop colour while the graph is off');
  const graph = await page.evaluate(() => Array.from(window.realLogPanel.session.poseGraph(0).slice(0, 3)));
  assert.ok(graph[0] > 0 && graph[1] > 0 && graph[2] > 0, `nodes, local and loop segments: ${graph}`);
  assert.equal(await page.evaluate(() => window.realLogPanel.session.poseGraph(1) ?? null), null);
  await toggle.check();
  await page.waitForFunction(() => !document.querySelector('.map-weaver-log-graph-legend').hidden);
  const on = await loopPixels(page);
  assert.ok(on > 0, 'loop closures drawn in their colour');
  await screenshot(page.locator('.map-weaver-log-stage'), 'real-log-intel-slam-pose-graph');
  await toggle.uncheck();
  assert.equal(await loopPixels(page), 0, 'and gone once the toggle is off');
  assert.deepEqual(errors, []);
  await close();
});
