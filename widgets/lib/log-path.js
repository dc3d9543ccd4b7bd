// The laser's path of a pane whose poses are found as its map builds (a
// scan-matched pane): kept on the page and grown by the scans located since
// the last drawing (`pathPixelsBetween`), rather than read again whole from
// the core at every drawing (a million scans: a 8 MB copy and 280 ms per
// redraw). A located scan's pose does not change afterwards; a pane built
// again from the start (a scrub back) starts its path again.

/** What each pane's path read at layout has grown into: `{ points, n }`, `n` scans held. */
const grown = new WeakMap();

/**
 * The path of pane `k` of `session` up to scan `done` (exclusive), as a
 * flat `[u0, v0, u1, v1, …]` array holding at least `done` points: `base`
 * is the path read whole at layout (a new layout, a new path).
 */
export function grownPath(session, k, base, done) {
  let g = grown.get(base);
  if (!g || done < g.n) {
    g = { points: new Float32Array(Math.max(2 * done, 2048)), n: 0 };
    grown.set(base, g);
  }
  if (done > g.n) {
    const more = session.pathPixelsBetween(k, g.n, done);
    const n = g.n + more.length / 2;
    if (2 * n > g.points.length) {
      const bigger = new Float32Array(Math.max(4 * n, 2048));
      bigger.set(g.points.subarray(0, 2 * g.n));
      g.points = bigger;
    }
    g.points.set(more, 2 * g.n);
    g.n = n;
  }
  return g.points;
}
