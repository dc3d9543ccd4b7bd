// W4 `doorway-map` on the wasm build: the MAP hill climb (Table 9.3) on the
// doorway scene of the doorway-trap widget. Reports the median time of one
// steepest-ascent flip step, the median time to convergence from the
// all-free start (cache built once, outside the timing; its cost is
// setup_ms), the flips taken and
// the log posterior reached, with the scene's size.
import { median, round } from '../lib/stats.mjs';

const RUNS = 15;

export default async function (core) {
  // Setting up casts every reading and builds the beam–cell incidence cache
  // (and the sweep's grid): reported apart from the climb.
  const setup = [];
  for (let r = 0; r < 5; r++) {
    const t = performance.now();
    new core.DoorwayTrap(undefined).free();
    setup.push(performance.now() - t);
  }
  const trap = new core.DoorwayTrap(undefined);
  try {
    const view = trap.view();
    const converge = [];
    const step = [];
    let flips = 0;
    let state;
    for (let r = 0; r < RUNS; r++) {
      trap.mapReset();
      let t = performance.now();
      flips = trap.mapRun(1_000_000);
      converge.push(performance.now() - t);
      // Single steps, each timed alone: the widget's unit of work.
      trap.mapReset();
      for (;;) {
        t = performance.now();
        const flip = trap.mapStep();
        const dt = performance.now() - t;
        if (flip === null) break;
        step.push(dt);
      }
    }
    state = trap.mapState();
    return [{
      workload: 'doorway-map', runtime: 'wasm-node',
      cells: view.width * view.height, readings: view.beams.length,
      step_ms: round(median(step), 4), converge_ms: round(median(converge), 3),
      flips, log_posterior: round(state.objective, 4), setup_ms: round(median(setup), 3),
    }];
  } finally {
    trap.free();
  }
}
