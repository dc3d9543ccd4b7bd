// W6 `logs-browser` (docs/BENCHMARKS.md): a real log, file to finished map, in
// the chapter page (or a ROS 2 bag, `.mcap`, at its odometry poses).
// Debian's headless Chromium opens the page served by the
// project's server, switches Map Weaver to its real-log mode and gives the
// log through the panel's file input, as a reader would, at the real-log
// defaults and 5 cm. The clock runs from the file input's `change` event to
// the first frame after the panel reports its map finished (the map is drawn
// into the canvas before the panel says so). Median of 3 fresh page loads
// per log; the longest main-thread task is the longest `longtask` entry seen
// while the log was read and mapped in any of the runs (the worst case is
// what a reader feels), and `long_tasks` says what the longest tasks held:
// every call into the core and every canvas upload and stroke is timed,
// and a task's calls are summed by name.
//
// `npm run bench -- logs-browser [--poses POSES] --log PATH [--log PATH ...]`
// maps the logs given (anywhere on disk); with no `--log`, every `*.log.gz`
// of ../shared/datasets/. `--poses` chooses the pose source in the panel's
// menu as a reader would (corrected, dead-reckoning, scan-matched,
// odometry, slam: whatever the menu offers); without it a CARMEN log is
// mapped at the panel's default and a bag at its odometry. A log the page
// refuses gives a line with the page's message in "error" instead of
// figures, and the run goes on.
import fs from 'node:fs';
import path from 'node:path';
import { root } from '../lib/load-core.mjs';
import { median, round } from '../lib/stats.mjs';

const WORKLOAD = 'logs-browser';
const RUNS = 3;
const RESOLUTION = 0.05;
/** Longest a single load may take before the run counts as hung. */
const LOAD_TIMEOUT_MS = 180_000;

/** The `--log PATH` / `--log=PATH` values of `args`, in order. */
export function logArgs(args) {
  const logs = [];
  for (let i = 0; i < args.length; i++) {
    const a = args[i];
    if (a === '--log') {
      const value = args[i + 1];
      if (value === undefined || value.startsWith('--')) throw new Error('bench logs-browser: --log needs a path (--log PATH)');
      logs.push(value);
      i++;
    } else if (a.startsWith('--log=')) {
      const value = a.slice('--log='.length);
      if (!value) throw new Error('bench logs-browser: --log= needs a path (--log=PATH)');
      logs.push(value);
    }
  }
  return logs;
}

/**
 * The `--poses POSES` / `--poses=POSES` value of `args` (the last one
 * given), or null: the pose source to choose in the panel's menu.
 */
export function posesArg(args) {
  let poses = null;
  for (let i = 0; i < args.length; i++) {
    const a = args[i];
    if (a === '--poses') {
      const value = args[i + 1];
      if (value === undefined || value.startsWith('--')) throw new Error('bench logs-browser: --poses needs a pose source (--poses POSES)');
      poses = value;
      i++;
    } else if (a.startsWith('--poses=')) {
      poses = a.slice('--poses='.length);
      if (!poses) throw new Error('bench logs-browser: --poses= needs a pose source (--poses=POSES)');
    }
  }
  return poses;
}

function defaultLogs() {
  const dir = process.env.OCCGRID_DATASETS || path.join(root, '../shared/datasets');
  if (!fs.existsSync(dir)) return [];
  return fs.readdirSync(dir).filter((f) => f.endsWith('.log.gz')).sort().map((f) => path.join(dir, f));
}

/**
 * Sets up the clock, the longtask observer and the finish signal in the
 * page, and times every call into the real-log core and every canvas
 * upload and stroke (what a long task was made of).
 */
async function instrument() {
  const panel = document.querySelector('.map-weaver-log');
  const w = { t0: null, tEnd: null, state: null, tasks: [], calls: [] };
  window.__logsBrowserBench = w;
  const timed = (proto, name, label) => {
    const f = proto[name];
    if (typeof f !== 'function') return;
    proto[name] = function (...args) {
      const t = performance.now();
      try {
        return f.apply(this, args);
      } finally {
        w.calls.push([label, t, performance.now() - t]);
      }
    };
  };
  const { core } = await (await import('/widgets/lib/core.js')).loadLogCore();
  const proto = core.RealLogSession.prototype;
  for (const name of Object.getOwnPropertyNames(proto)) {
    if (name !== 'constructor' && name !== 'free' && !Object.getOwnPropertyDescriptor(proto, name).get) timed(proto, name, name);
  }
  for (const name of ['putImageData', 'drawImage', 'stroke', 'fill', 'getImageData']) timed(CanvasRenderingContext2D.prototype, name, `canvas.${name}`);
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) w.tasks.push([e.startTime, e.duration]);
  }).observe({ type: 'longtask', buffered: true });
  // Capture phase on the document: this runs before the panel's own listener.
  document.addEventListener('change', (e) => {
    if (w.t0 === null && e.target instanceof HTMLInputElement && e.target.type === 'file') w.t0 = e.timeStamp || performance.now();
  }, true);
  const seen = new MutationObserver(() => {
    const s = panel.dataset.state;
    if (w.t0 === null || (s !== 'done' && s !== 'failed')) return;
    seen.disconnect();
    // The map is in the canvas; the frame after the next animation frame
    // callback is the one that puts it on screen.
    requestAnimationFrame(() => {
      const ch = new MessageChannel();
      ch.port1.onmessage = () => {
        w.tEnd = performance.now();
        w.state = s;
      };
      ch.port2.postMessage(null);
    });
  });
  seen.observe(panel, { attributes: true, attributeFilter: ['data-state'] });
}

/** What the page shows once the panel is done or has refused the log. */
async function collect() {
  const w = window.__logsBrowserBench;
  const panel = document.querySelector('.map-weaver-log');
  const { memory } = await (await import('/widgets/lib/core.js')).loadLogCore();
  const status = panel.querySelector('.map-weaver-log-status')?.textContent ?? '';
  const error = panel.querySelector(':scope > .occgrid-error')?.textContent ?? null;
  const num = (re) => {
    const m = re.exec(status);
    return m ? Number(m[1].replace(/,/g, '')) : null;
  };
  const during = w.tasks.filter(([start, ms]) => start + ms > w.t0 && start < w.tEnd);
  // What each long task held: the milliseconds of the timed calls inside
  // it, by name, and what they leave (the page's own script, layout, GC).
  const longTasks = during.map(([start, ms]) => {
    const inside = {};
    let timedMs = 0;
    for (const [name, t, d] of w.calls) {
      if (t >= start && t + d <= start + ms + 1) {
        inside[name] = Math.round(((inside[name] ?? 0) + d) * 10) / 10;
        timedMs += d;
      }
    }
    return { ms: Math.round(ms), calls: inside, untimed_ms: Math.round(ms - timedMs) };
  });
  // The panel's own record of its calls into the core: where the time went.
  const calls = {};
  const realLog = document.querySelector('occgrid-map-weaver')?.realLog ?? window.realLogPanel;
  for (const [what, ms] of realLog?.trace ?? []) {
    if (typeof ms !== 'number' || what === 'file' || what === 'copy') continue;
    const c = (calls[what] ??= { calls: 0, ms: 0, longest_ms: 0 });
    c.calls++;
    c.ms += ms;
    c.longest_ms = Math.max(c.longest_ms, ms);
  }
  // Each build call's work against the budget it was given (the trace's
  // `['build', ms, budget, work, scans]`): what a call did past its budget
  // is the last step's work (a call stops after the step that reaches the
  // budget), what bounds a call whatever else the machine runs.
  let pastBudget = null;
  for (const [what, , budget, work] of realLog?.trace ?? []) {
    if (what === 'build' && work >= 0) pastBudget = Math.max(pastBudget ?? 0, work - budget);
  }
  for (const c of Object.values(calls)) {
    c.ms = Math.round(c.ms * 10) / 10;
    c.longest_ms = Math.round(c.longest_ms * 10) / 10;
  }
  return {
    calls,
    state: w.state,
    ms: w.tEnd - w.t0,
    longest: during.length ? Math.max(...during.map(([, ms]) => ms)) : null,
    longTasks,
    pastBudget,
    // The longest build call and the two before it, `[ms, budget, work,
    // scans]`: a long call with its work near its budget is the machine's
    // load, or a budget sized from cheaper work before it.
    longestBuild: (() => {
      const builds = (realLog?.trace ?? []).filter(([what]) => what === 'build');
      let at = -1;
      builds.forEach(([, ms], i) => { if (at < 0 || ms > builds[at][1]) at = i; });
      return at < 0 ? null : builds.slice(Math.max(0, at - 2), at + 1).map(([, ms, budget, work, scans]) => [Math.round(ms), budget, work, scans]);
    })(),
    budgets: (realLog?.trace ?? []).filter(([what]) => what === 'build').map(([, , budget]) => budget),
    memoryBytes: memory.buffer.byteLength,
    scans: num(/of ([\d,]+) scans/),
    beams: num(/([\d,]+) beams/),
    cells: panel.dataset.cells ? Number(panel.dataset.cells) : null,
    cellsAllocated: panel.dataset.cellsAllocated ? Number(panel.dataset.cellsAllocated) : null,
    status,
    error,
  };
}

/** One load of `file` on a fresh page at pose source `poses` (null: the panel's choice): the figures of `collect`. */
async function oneRun(openPage, file, poses) {
  const { page, close } = await openPage('/');
  try {
    await page.locator('occgrid-map-weaver .map-weaver-mode label', { hasText: 'Real log' }).click();
    const input = page.locator('.map-weaver-log input[type=file]');
    await input.waitFor({ state: 'attached', timeout: 30_000 });
    const resolution = page.locator('.map-weaver-log select[name=resolution]');
    if ((await resolution.inputValue()) !== String(RESOLUTION)) {
      throw new Error(`the panel starts at ${await resolution.inputValue()} m, not the ${RESOLUTION} m this workload is defined at`);
    }
    // A ROS 2 bag carries no corrected poses: it is mapped at its own
    // odometry unless `--poses` says otherwise, chosen in the panel's menu
    // as a reader would.
    const menu = page.locator('.map-weaver-log select[name=poses]');
    const chosen = poses ?? (file.endsWith('.mcap') ? 'odometry' : null);
    if (chosen !== null) {
      const offered = await menu.evaluate((s) => [...s.options].map((o) => o.value));
      if (!offered.includes(chosen)) throw new Error(`--poses ${JSON.stringify(chosen)} is not in the panel's menu: expected one of ${offered.join(', ')}`);
      await menu.selectOption(chosen);
    }
    await page.evaluate(instrument);
    await input.setInputFiles(file);
    await page.waitForFunction(() => window.__logsBrowserBench.tEnd !== null, null, { timeout: LOAD_TIMEOUT_MS, polling: 100 });
    // Long-task entries are delivered after the task, not during it.
    await page.waitForTimeout(200);
    return await page.evaluate(collect);
  } finally {
    await close();
  }
}

async function measure(openPage, file, poses) {
  const name = path.basename(file);
  const base = { workload: WORKLOAD, runtime: 'chromium', log: name, ...(poses === null ? {} : { poses }) };
  if (!fs.existsSync(file)) return { ...base, resolution: RESOLUTION, error: `no such file: ${file}` };
  if (!fs.statSync(file).isFile()) return { ...base, resolution: RESOLUTION, error: `not a file: ${file}` };
  const runs = [];
  for (let k = 0; k < RUNS; k++) {
    const r = await oneRun(openPage, file, poses);
    if (r.state !== 'done') {
      const scans = r.scans === null ? {} : { scans: r.scans };
      return { ...base, ...scans, resolution: RESOLUTION, error: r.error || r.status || `the panel ended in state ${r.state}` };
    }
    runs.push(r);
  }
  const longest = runs.map((r) => r.longest).filter((x) => x !== null);
  const middle = [...runs].sort((a, b) => a.ms - b.ms)[Math.floor(runs.length / 2)];
  return {
    ...base,
    scans: runs[0].scans,
    beams: runs[0].beams,
    resolution: RESOLUTION,
    file_to_map_ms: round(median(runs.map((r) => r.ms)), 1),
    // null: no task in any run was long enough for the longtask API (50 ms).
    longest_task_ms: longest.length ? round(Math.max(...longest), 1) : null,
    wasm_memory_mb: round(Math.max(...runs.map((r) => r.memoryBytes)) / 2 ** 20, 1),
    // Cells the map's tiles hold (what the beams reached), and the bounding box's.
    cells_allocated: runs[0].cellsAllocated,
    cells: runs[0].cells,
    // The median run's calls into the core by kind (read, build, draw):
    // their count, total and longest milliseconds.
    calls: middle.calls,
    // The most work a build call did past its budget, over all runs (in
    // the core's units: a cell update), against the median budget of the
    // median run's calls: one step's work, small beside a slice when
    // every step is bounded.
    build_past_budget: runs.some((r) => r.pastBudget !== null) ? Math.max(...runs.map((r) => r.pastBudget ?? 0)) : null,
    build_median_budget: middle.budgets.length ? median(middle.budgets) : null,
    longest_build: [...runs].sort((a, b) => (b.longestBuild?.at(-1)?.[0] ?? 0) - (a.longestBuild?.at(-1)?.[0] ?? 0))[0].longestBuild,
    // Every run's long tasks (50 ms and over), longest first, each with
    // the calls into the core and the canvas uploads and strokes it held.
    long_tasks: runs.flatMap((r) => r.longTasks).sort((a, b) => b.ms - a.ms).slice(0, 8),
  };
}

export default async function (core, args) {
  const wanted = args.find((a, i) => !a.startsWith('-') && args[i - 1] !== '--log' && args[i - 1] !== '--poses');
  if (wanted && !WORKLOAD.includes(wanted)) return [];
  if (!fs.existsSync('/usr/bin/chromium') && !process.env.CHROMIUM) return [];
  let given;
  let poses;
  try {
    given = logArgs(args);
    poses = posesArg(args);
  } catch (e) {
    console.error(e.message);
    process.exitCode = 2;
    return [];
  }
  const files = given.length ? given.map((p) => path.resolve(p)) : defaultLogs();
  if (files.length === 0) return [];
  const { openPage, shutdown } = await import('../../tests/browser/harness.mjs');
  const rows = [];
  try {
    for (const file of files) {
      try {
        rows.push(await measure(openPage, file, poses));
      } catch (e) {
        rows.push({ workload: WORKLOAD, runtime: 'chromium', log: path.basename(file), ...(poses === null ? {} : { poses }), resolution: RESOLUTION, error: `the benchmark could not run: ${e.message.split('\n')[0]}` });
      }
    }
  } finally {
    await shutdown();
  }
  return rows;
}
