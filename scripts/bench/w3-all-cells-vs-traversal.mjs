// W3 `all-cells-vs-traversal` on the wasm build: the W2 lap integrated by
// the ray traversal and by the literal Table 9.1 sweep over every cell, at
// 0.10 m and 0.05 m. The work is defined in src/bench/apartment.rs;
// this script only holds the clock.
import { median, round } from '../lib/stats.mjs';

export default async function (core) {
  const rows = [];
  for (const resolution of [0.1, 0.05]) {
    const bench = new core.AllCellsVsTraversalBench(resolution);
    const n = bench.scans;
    const time = (call) => {
      const us = [];
      let cells = 0;
      for (let k = 0; k < n; k++) {
        const t = performance.now();
        cells += call(k);
        us.push((performance.now() - t) * 1000);
      }
      return { us: median(us), cells: cells / n };
    };
    time((k) => bench.traverse(k)); // warm-up
    const traversal = time((k) => bench.traverse(k));
    const sweep = time((k) => bench.sweep(k));
    bench.free();
    rows.push({
      workload: 'all-cells-vs-traversal', runtime: 'wasm-node', resolution, scans: n,
      traversal_us: round(traversal.us, 1), sweep_us: round(sweep.us, 1),
      traversal_cells: round(traversal.cells, 0), sweep_cells: round(sweep.cells, 0),
      speedup: round(sweep.us / traversal.us, 1),
    });
  }
  return rows;
}
