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
 * (at most twice `n`).
 */
export function buildPace(sliceMs) {
  const perMs = [];
  return {
    next(n, ms, done) {
      perMs.push(done / Math.max(ms, 0.25));
      if (perMs.length > REMEMBERED) perMs.shift();
      return Math.max(1, Math.min(n * 2, Math.round(Math.min(...perMs) * sliceMs)));
    },
  };
}
