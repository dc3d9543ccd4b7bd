// Work in bounded calls. A widget whose core work can be large (a fine
// grid, the every-cell sweep, a rebuild over thousands of scans) asks the
// core for it in calls with a budget in the core's own units (cells
// visited), sized from how long the last call took, so that each call stays
// near a target time and the page keeps its frames (docs/ARCHITECTURE.md,
// "Sessions and panes").

/**
 * The core's share of an animation frame while a widget plays or rebuilds,
 * ms: a throttled phone has about 33 ms a frame at 30 frames a second, and
 * drawing the maps takes most of the rest. Its calls get a budget of cell
 * visits sized from the last call's time, so that a fine grid or the
 * every-cell sweep slows the run down instead of freezing the page.
 */
export const FRAME_WORK_MS = 8;
/** The time of one training call of the learned model, ms: the page paints and takes input between calls. */
export const TRAIN_SLICE_MS = 20;
/** The first training call's units (triplets drawn or SGD updates), which its time corrects. */
export const FIRST_TRAIN_UNITS = 2_000;

/**
 * The pause between two slices of work: a timer, not a posted message. A
 * chain of posted messages runs ahead of every timer of the page (another
 * widget's, a reader's script), which would then wait for the whole work;
 * after a timer the page's own timers due by then have had their turn.
 */
const betweenSlices = () => new Promise((resolve) => setTimeout(resolve, 0));

/**
 * The next call's budget: the work the last call did (`done`, in its units)
 * scaled to `targetMs` by the last call's duration `ms`, and at most twice
 * the last budget `n`.
 */
export function nextBudget(n, ms, done, targetMs) {
  return Math.max(1, Math.min(n * 2, Math.round((done * targetMs) / Math.max(ms, 0.25))));
}

/**
 * A budget that learns: `value` is the next call's, `learn(done, ms)` takes
 * a call's work and duration. `initial` is a first guess that the first
 * call corrects.
 */
export function workBudget(targetMs, initial) {
  let value = initial;
  return {
    get value() { return value; },
    learn(done, ms) {
      if (done > 0) value = nextBudget(value, ms, done, targetMs);
    },
  };
}

/**
 * One timed call of `weaver.work(scans, budget)` (a Map Weaver run) with at
 * least `floor` cell visits: the budget learns from it. Returns the core's
 * report `{ scans, cellVisits, behind, done }` and the call's milliseconds.
 */
export function workOnce(weaver, budget, scans, floor = 1) {
  const t = performance.now();
  const report = weaver.work(scans, Math.max(floor, budget.value));
  const ms = performance.now() - t;
  budget.learn(report.cellVisits, ms);
  return { ...report, ms };
}

/**
 * Makes a Map Weaver run from `start` (a `MapWeaverStart`): its learned
 * model trained in calls of about `trainBudget`'s target time, then its maps
 * drawn in calls of about `buildBudget`'s (a scene of a million cells has
 * three such maps), each call in a task of its own. Returns the run; null
 * (with `start` left to the caller to free) when `stillWanted()` turns false
 * between calls (a newer run was asked for).
 */
export async function startInSlices(start, trainBudget, buildBudget, stillWanted) {
  for (;;) {
    const t = performance.now();
    const units = trainBudget.value;
    const trained = start.work(units);
    trainBudget.learn(units, performance.now() - t);
    if (trained) break;
    // A task boundary: the page paints and handles input in between.
    await betweenSlices();
    if (!stillWanted()) return null;
  }
  for (;;) {
    await betweenSlices();
    if (!stillWanted()) return null;
    const t = performance.now();
    const report = start.build(buildBudget.value);
    buildBudget.learn(report.cells, performance.now() - t);
    if (report.done) break;
  }
  // Making the run from its drawn maps is a task of its own too: with the
  // last band of a large scene it ran past 50 ms.
  await betweenSlices();
  return stillWanted() ? start.finish() : null;
}

/**
 * Works `job` (a core object whose `work(budget)` returns `{ units, done }`)
 * to its end in calls of about `budget`'s target time, each in a task of
 * its own. Returns true once done; false when `stillWanted()` turns false
 * between calls (the caller frees `job`).
 */
export async function workInSlices(job, budget, stillWanted) {
  for (;;) {
    const t = performance.now();
    const report = job.work(budget.value);
    budget.learn(report.units, performance.now() - t);
    if (report.done) return true;
    await betweenSlices();
    if (!stillWanted()) return false;
  }
}

/**
 * Advances a Map Weaver run by `target` scans in calls of about `budget`'s
 * target time, each in a task of its own (a hidden tab still gets on with
 * the work), calling `progress(done)` between them; false when
 * `stillWanted()` turns false (the caller frees `weaver`).
 */
export async function fastForward(weaver, target, budget, progress, stillWanted) {
  let done = 0;
  for (;;) {
    const r = workOnce(weaver, budget, target - done);
    done += r.scans;
    if (done >= target && r.behind[0] + r.behind[1] === 0) return true;
    progress(done);
    await betweenSlices();
    if (!stillWanted()) return false;
  }
}
