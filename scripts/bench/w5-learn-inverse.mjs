// W5 `learn-inverse` on the wasm build: sample the 24,000 training triplets
// of the learned inverse model and fit it (default configuration, seed 9).
// The core times the two phases apart with the host's clock
// (the `run` of InverseWorkbench.retrain's readout); this script takes the medians.
import { median, round } from '../lib/stats.mjs';

const RUNS = 7;

export default async function (core) {
  const bench = new core.InverseWorkbench(9); // the first training warms the engine up
  const runs = [];
  for (let i = 0; i < RUNS; i++) runs.push(bench.retrain(9).run);
  const last = runs.at(-1);
  bench.free();
  const sample = median(runs.map((r) => r.sampleMs));
  const train = median(runs.map((r) => r.fitMs));
  return [{
    workload: 'learn-inverse', runtime: 'wasm-node',
    triplets: last.triplets, maps: last.maps, epochs: last.epochs,
    sample_ms: round(sample), train_ms: round(train), total_ms: round(median(runs.map((r) => r.trainMs))),
  }];
}
