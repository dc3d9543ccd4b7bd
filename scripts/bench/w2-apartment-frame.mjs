// W2 `apartment-frame` on the wasm build: one Map Weaver frame (one scan of
// the apartment lap integrated into the hand-crafted and the learned map,
// both maps' pixels and scores brought up to date), and one
// `integrate_scan` call on its own. The work is defined in
// src/bench/apartment.rs; this script only holds the clock.
import { median, round } from '../lib/stats.mjs';

const LAPS = 5;

export default async function (core) {
  const bench = new core.ApartmentFrameBench();
  const n = bench.scans;
  const timeLaps = (call) => {
    const us = [];
    let work = 0;
    for (let lap = 0; lap < LAPS; lap++) {
      bench.restart();
      for (let k = 0; k < n; k++) {
        const t = performance.now();
        work += call();
        us.push((performance.now() - t) * 1000);
      }
    }
    return { us: median(us), perScan: work / (LAPS * n) };
  };
  timeLaps(() => bench.frame()); // warm-up: let the engine tier up
  const frame = timeLaps(() => bench.frame());
  const hand = timeLaps(() => bench.integrate(0));
  const learned = timeLaps(() => bench.integrate(1));
  bench.free();
  return [{
    workload: 'apartment-frame', runtime: 'wasm-node', scans: n, laps: LAPS, cells: 10800,
    frame_us: round(frame.us, 1),
    integrate_us: round(hand.us, 1),
    cells_per_scan: round(hand.perScan, 0),
    integrate_learned_us: round(learned.us, 1),
    cells_per_scan_learned: round(learned.perScan, 0),
  }];
}
