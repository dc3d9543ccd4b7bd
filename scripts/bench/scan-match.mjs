// W8 `scan-match` (docs/BENCHMARKS.md) under Node and in the page: each log of
// ../shared/datasets/ (or `--log PATH ...`) at the real-log defaults, 5 cm,
// poses `scan-matched` from seeded dead reckoning (seed 1). Run only when
// named: `npm run bench -- scan-match [--log PATH ...]` (the native rows
// come from `cargo bench --bench native -- scan-match`).
//
// - wasm under Node: the session's scan-matched pane stepped one scan per
//   call (`buildSlice(1)` advances one pane by one scan), each call timed
//   in the process's CPU time (the machine may be shared: wall time would
//   count other programs' turns):
//   the median and largest time of a scan's match and integration, the
//   whole log's matching and mapping, beside the plain build at the
//   corrected poses; the trajectory's errors against the corrected poses
//   (aligned ATE, RPE between consecutive scans, as trajectory_error.py
//   measures them) for dead reckoning and for scan matching.
// - the page (Chromium): the log given to the real-log panel's file input
//   with the poses menu at scan-matched, timed from the file's choice to the
//   finished maps (all three panes: scan-matched, corrected, dead-reckoned)
//   beside the same load under the corrected poses alone, with the longest
//   main-thread task of each; then the scan-matched pane rebuilt one scan
//   per call on the page's main thread, each call timed.
import fs from 'node:fs';
import path from 'node:path';
import { root } from '../lib/load-core.mjs';
import { median, round } from '../lib/stats.mjs';
import { logArgs } from './logs-browser.mjs';

const WORKLOAD = 'scan-match';
const SEED = 1;
const LOAD_TIMEOUT_MS = 300_000;

function defaultLogs() {
  const dir = process.env.OCCGRID_DATASETS || path.join(root, '../shared/datasets');
  if (!fs.existsSync(dir)) return [];
  return fs.readdirSync(dir).filter((f) => f.endsWith('.log.gz')).sort().map((f) => path.join(dir, f));
}

const wrap = (a) => a - 2 * Math.PI * Math.floor((a + Math.PI) / (2 * Math.PI));

/** Poses `[[x, y, theta], ...]` from a `poses.tsv` text. */
const posesOf = (tsv) => tsv.trim().split('\n').map((l) => l.split(' ').slice(1).map(Number));

/**
 * Aligned ATE (RMS position error after the best rigid 2-D alignment) and
 * RPE (mean translation and rotation error of consecutive motions), as
 * trajectory_error.py computes them.
 */
export function trajectoryErrors(got, ref) {
  const n = ref.length;
  const mean = (ps, i) => ps.reduce((a, p) => a + p[i], 0) / n;
  const [mgx, mgy, mrx, mry] = [mean(got, 0), mean(got, 1), mean(ref, 0), mean(ref, 1)];
  let sxx = 0;
  let sxy = 0;
  for (let k = 0; k < n; k++) {
    const [gx, gy, rx, ry] = [got[k][0] - mgx, got[k][1] - mgy, ref[k][0] - mrx, ref[k][1] - mry];
    sxx += gx * rx + gy * ry;
    sxy += gx * ry - gy * rx;
  }
  const rot = Math.atan2(sxy, sxx);
  const [c, s] = [Math.cos(rot), Math.sin(rot)];
  let al2 = 0;
  for (let k = 0; k < n; k++) {
    const [gx, gy] = [got[k][0] - mgx, got[k][1] - mgy];
    al2 += (c * gx - s * gy + mrx - ref[k][0]) ** 2 + (s * gx + c * gy + mry - ref[k][1]) ** 2;
  }
  const rel = (a, b) => {
    const [dx, dy] = [b[0] - a[0], b[1] - a[1]];
    const [ca, sa] = [Math.cos(a[2]), Math.sin(a[2])];
    return [ca * dx + sa * dy, -sa * dx + ca * dy, wrap(b[2] - a[2])];
  };
  let rt = 0;
  let rr = 0;
  for (let k = 0; k + 1 < n; k++) {
    const [g, r] = [rel(got[k], got[k + 1]), rel(ref[k], ref[k + 1])];
    rt += Math.hypot(g[0] - r[0], g[1] - r[1]);
    rr += Math.abs(wrap(g[2] - r[2]));
  }
  const pairs = Math.max(1, n - 1);
  return { ate_aligned_m: round(Math.sqrt(al2 / n), 3), rpe_m: round(rt / pairs, 4), rpe_deg: round((rr / pairs) * 180 / Math.PI, 3) };
}

/** A session over `bytes` at `poses`, read to the end. */
function readSession(core, bytes, poses) {
  const session = new core.RealLogSession(bytes);
  session.configure({ poses, seed: SEED });
  while (!session.read(1 << 30).finished);
  return session;
}

/** Milliseconds of this process's CPU time so far. */
const cpuMs = () => {
  const u = process.cpuUsage();
  return (u.user + u.system) / 1000;
};

/** W8 under Node for one log. */
function nodeRow(core, file) {
  const bytes = fs.readFileSync(file);
  const plain = readSession(core, bytes, 'corrected');
  let t = cpuMs();
  while (!plain.buildSlice(Infinity).finished);
  const plainMs = cpuMs() - t;
  const reference = posesOf(plain.posesTsv(0));
  plain.free();
  const session = readSession(core, bytes, 'scan-matched');
  const steps = [];
  let state = session.state();
  let matchedMs = 0;
  while (!state.finished) {
    t = cpuMs();
    const next = session.buildSlice(1);
    const ms = cpuMs() - t;
    // One call advances one pane by one scan: the scan-matched pane's are its steps.
    if (next.panes[0].scansDone > state.panes[0].scansDone) {
      steps.push(ms);
      matchedMs += ms;
    }
    state = next;
  }
  const matched = posesOf(session.posesTsv(0));
  const dead = posesOf(session.posesTsv(2));
  const trusted = session.state().panes[0];
  session.free();
  return {
    workload: WORKLOAD, runtime: 'wasm-node', log: path.basename(file), scans: reference.length, seed: SEED, clock: 'cpu',
    step_median_ms: round(median(steps), 3), step_max_ms: round(Math.max(...steps), 2),
    match_and_map_ms: round(matchedMs, 1), plain_build_ms: round(plainMs, 1),
    match_work_share: round(1 - trusted.cellUpdates / trusted.work, 3),
    dead_reckoning: trajectoryErrors(dead, reference), scan_matched: trajectoryErrors(matched, reference),
  };
}

/** In the page: one load of `file` under `poses`, then (scan-matched) the pane's steps timed one per call. */
async function pageRun(openPage, file, poses) {
  const { page, close } = await openPage('/test-fixtures/real-log.html');
  try {
    await page.waitForSelector('#panel[data-ready]');
    await page.selectOption('.map-weaver-log select[name=poses]', poses);
    await page.evaluate(() => {
      window.w8 = { t0: null, tasks: [] };
      new PerformanceObserver((list) => {
        for (const e of list.getEntries()) window.w8.tasks.push([e.startTime, e.duration]);
      }).observe({ type: 'longtask', buffered: true });
      document.addEventListener('change', (e) => { if (e.target.type === 'file') window.w8.t0 ??= e.timeStamp; }, true);
    });
    await page.setInputFiles('.map-weaver-log input[type=file]', file);
    await page.waitForFunction(() => {
      const p = window.realLogPanel;
      const s = p.session?.state();
      return s && s.state === p.root.dataset.state && (s.state === 'done' || s.state === 'failed');
    }, null, { timeout: LOAD_TIMEOUT_MS, polling: 100 });
    await page.waitForTimeout(200); // long-task entries arrive after their task
    return await page.evaluate((timeSteps) => {
      const p = window.realLogPanel;
      const w = window.w8;
      const end = performance.now();
      const during = w.tasks.filter(([s, ms]) => s + ms > w.t0);
      const out = { state: p.root.dataset.state, ms: Number(p.root.dataset.totalMs), longest: during.length ? Math.max(...during.map(([, ms]) => ms)) : null, end };
      if (!timeSteps || out.state !== 'done') return out;
      // The scan-matched pane again, one scan per call on the main thread.
      const s = p.session;
      const total = s.state().scansTotal;
      s.seek(0);
      s.seek(total);
      const steps = [];
      let before = s.state();
      while (!before.finished) {
        const t = performance.now();
        const next = s.buildSlice(1);
        const ms = performance.now() - t;
        if (next.panes[0].scansDone > before.panes[0].scansDone) steps.push(ms);
        before = next;
      }
      return { ...out, steps };
    }, poses === 'scan-matched');
  } finally {
    await close();
  }
}

async function pageRow(openPage, file) {
  const base = { workload: WORKLOAD, runtime: 'chromium', log: path.basename(file), seed: SEED };
  const plain = await pageRun(openPage, file, 'corrected');
  const matched = await pageRun(openPage, file, 'scan-matched');
  if (matched.state !== 'done' || plain.state !== 'done') return { ...base, error: `the panel ended in state ${matched.state} (scan-matched), ${plain.state} (corrected)` };
  const steps = matched.steps;
  return {
    ...base, scans: steps.length,
    step_median_ms: round(median(steps), 2), step_max_ms: round(Math.max(...steps), 2),
    // From the file's choice to the finished maps, file reading included.
    file_to_maps_ms: round(matched.ms, 0), plain_file_to_map_ms: round(plain.ms, 0),
    // null: no task of 50 ms or more.
    longest_task_ms: matched.longest === null ? null : round(matched.longest, 1),
    plain_longest_task_ms: plain.longest === null ? null : round(plain.longest, 1),
  };
}

export default async function (core, args) {
  // Only when named: the page's part maps every log three times over.
  if (!args.some((a) => a === WORKLOAD)) return [];
  const given = logArgs(args);
  const files = given.length ? given.map((p) => path.resolve(p)) : defaultLogs();
  const rows = files.map((f) => nodeRow(core, f));
  if (!fs.existsSync('/usr/bin/chromium') && !process.env.CHROMIUM) return rows;
  const { openPage, shutdown } = await import('../../tests/browser/harness.mjs');
  try {
    for (const file of files) {
      try {
        rows.push(await pageRow(openPage, file));
      } catch (e) {
        rows.push({ workload: WORKLOAD, runtime: 'chromium', log: path.basename(file), error: `the benchmark could not run: ${e.message.split('\n')[0]}` });
      }
    }
  } finally {
    await shutdown();
  }
  return rows;
}
