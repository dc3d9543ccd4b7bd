// W1 `intel-full` on the wasm build: parse the Intel log, then build the
// whole 1000 x 900 map at 5 cm (the workload is defined in src/bench/intel.rs).
import fs from 'node:fs';
import path from 'node:path';
import { root } from '../lib/load-core.mjs';
import { median, round } from '../lib/stats.mjs';

export default async function (core) {
  const file = path.join(process.env.OCCGRID_DATASETS || path.join(root, '../shared/datasets'), 'intel-corrected.log.gz');
  if (!fs.existsSync(file)) return [];
  const bytes = fs.readFileSync(file);
  let t = performance.now();
  const log = core.LaserLog.fromBytes(bytes);
  const parseMs = performance.now() - t;
  const times = [];
  let counts;
  for (let i = 0; i < 7; i++) {
    t = performance.now();
    counts = log.buildIntelBenchmark();
    times.push(performance.now() - t);
  }
  const scans = log.scanCount;
  log.free();
  return [{
    workload: 'intel-full', runtime: 'wasm-node', scans,
    parse_ms: round(parseMs), build_ms: round(median(times)),
    beams: counts.beams, cells_visited: counts.cells_visited, cell_updates: counts.cell_updates, occupied: counts.occupied, free: counts.free, unknown: counts.unknown,
  }];
}
