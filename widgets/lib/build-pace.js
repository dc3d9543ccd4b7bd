// The pace of the real-log panel's build calls: each call's budget, in the
// core's units of work, sized from how fast the last few calls went. The
// core counts each kind of work at about a cell update's time (SLAM's local
// matches, submaps, loop search and optimiser weighed so), yet a unit's
// time still varies with the work and the memory it touches (natively 7 to
// 29 ns across SLAM's kinds), so a budget sized from the last call alone
// can run past its slice when dearer work follows: the slowest of the last
// few calls sizes the next (docs/BENCHMARKS.md, W6).

/** Calls whose pace is remembered. */
const REMEMBERED = 4;

/**
 * A pace for calls of `sliceMs`: `next(n, ms, done)` takes a call's budget
 * `n`, its duration and the work it did, and gives the next call's budget
 * (at most twice `n`), sized by the slowest of the last `remembered` calls.
 */
export function buildPace(sliceMs, remembered = REMEMBERED) {
  const perMs = [];
  return {
    next(n, ms, done) {
      perMs.push(done / Math.max(ms, 0.25));
      if (perMs.length > remembered) perMs.shift();
      return Math.max(1, Math.min(n * 2, Math.round(Math.min(...perMs) * sliceMs)));
    },
  };
}

/** Read calls whose pace is remembered. */
const READ_REMEMBERED = 32;

/**
 * The pace of a log's read calls (its lines read, then each pane's plan
 * walked a scan at a time): sized by the slowest of the last 32 calls.
 * The read's units are passes over a scan of very different cost (reading
 * its line, growing a box, counting the tiles its beams reach: 10 to 40 µs
 * natively on the Freiburg campus; a pose of a source's start, 64 to a
 * pass, a few), and a run of cheap passes longer than the four calls a
 * build remembers grew the budget call after call until a dear pass held
 * the main thread 90 to 190 ms. Remembering every call of the read
 * instead let one slow call (the first, as the module warms up) hold the
 * budget down for the whole read: 2,000 calls for the campus's 2,008
 * scans.
 */
export function readPace(sliceMs) {
  return buildPace(sliceMs, READ_REMEMBERED);
}
