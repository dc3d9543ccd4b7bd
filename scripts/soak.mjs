// Soak: Map Weaver for many scans in wasm under Node, driven the way the
// widget drives it, while watching the wasm memory.
//
// Each "frame" advances a few scans (1 to 16, as the widget's speeds ask
// for), records the frame time, reads the readout, takes both maps'
// pixels through a view over wasm memory (rebuilt when memory grows, as
// drawMap does), both overlays and a hover readout; every tenth frame it
// pulls the charts' series (entropy curves, tracked log odds) as the
// widget does every 150 ms. When a run's laps are done it starts again,
// as pressing Play on a finished run does. Every so often a knob is
// turned (clamp, strength, model, pose source) and a map exported.
//
// Usage: node scripts/soak.mjs [--scans 200000] [--laps 20] [--every 1000]
// Prints one JSON object: memory (MB) at the start and after 1k, 10k, ...
// scans, the samples, and the wall time. Exits non-zero if the memory grew
// by more than one 64 KiB page over the last 60 % of the run.
import { loadCore } from './lib/load-core.mjs';

const MB = 1024 * 1024;
const FRAME_SCANS = [1, 2, 4, 8, 16, 4, 2, 1, 16, 8];

/**
 * Runs the soak and returns its figures. `scans`: scans to integrate in
 * all; `laps`: laps per run (a run is restarted when done); `every`: scans
 * between two memory samples.
 */
export async function runSoak({ scans = 200_000, laps = 20, every = 1000, core, memory } = {}) {
  if (!core) ({ core, memory } = await loadCore());
  const started = performance.now();
  const weaver = new core.MapWeaver({ laps });
  const afterBuild = memory.buffer.byteLength;
  const { width, height } = weaver;
  let view = null;
  const pixels = (k) => {
    const ptr = weaver.pixels(k);
    if (!view || view.buffer !== memory.buffer) view = new Uint8ClampedArray(memory.buffer);
    // What drawMap reads: the map's RGBA bytes. Touch them so the view is used.
    return view[ptr] + view[ptr + 4 * width * height - 1];
  };

  const samples = [{ scans: 0, bytes: afterBuild }];
  let done = 0;
  let nextSample = every;
  let frame = 0;
  let runs = 1;
  let checksum = 0;
  while (done < scans) {
    const n = Math.min(FRAME_SCANS[frame % FRAME_SCANS.length], scans - done);
    const t = performance.now();
    let taken = weaver.advance(n);
    weaver.recordFrameMs(performance.now() - t);
    if (taken === 0) {
      // The run's laps are done: Play starts it again.
      weaver.reset();
      runs += 1;
      taken = weaver.advance(n);
    }
    done += taken;
    frame += 1;

    const r = weaver.readout();
    checksum += pixels(0) + pixels(1);
    for (const k of [0, 1]) {
      const o = weaver.overlay(k);
      checksum += o.beams.length;
    }
    const cell = weaver.cellInfo(frame % 2, (frame * 7) % width, (frame * 3) % height);
    if (cell) checksum += cell.updates;
    if (frame % 10 === 0) {
      for (const k of [0, 1]) {
        checksum += weaver.entropyCurve(k).length + weaver.trackedHistory(k).length;
      }
    }
    // A reader turning knobs now and then, and exporting a map.
    if (frame % 997 === 0) weaver.stagePane(frame % 2, { clamp: 2 + (frame % 7) });
    if (frame % 1499 === 0) weaver.stagePane(1, { strength: 0.5 + (frame % 3) * 0.5 });
    if (frame % 2503 === 0) weaver.stagePane(0, { model: (frame / 2503) % 2 ? 'learned' : 'hand-crafted' });
    if (frame % 3001 === 0) weaver.stagePane(1, { pose: (frame / 3001) % 2 ? 'dead-reckoning' : 'oracle' });
    if (frame % 4001 === 0) checksum += weaver.exportMap(0).pgm.length;
    if (!Number.isFinite(r.panes[0].entropyBits) || !Number.isFinite(r.panes[1].brier)) {
      throw new Error(`a readout went non-finite at scan ${done}`);
    }

    while (done >= nextSample) {
      samples.push({ scans: nextSample, bytes: memory.buffer.byteLength });
      nextSample += every;
    }
  }
  const seconds = (performance.now() - started) / 1000;
  weaver.free();

  const at = (k) => {
    const s = samples.find((x) => x.scans === k);
    return s ? +(s.bytes / MB).toFixed(2) : null;
  };
  // Growth over the last 60 % of the run (after the first two or three
  // runs, once the history and the allocator's free lists have reached
  // their size): the largest sample there minus the sample at its start.
  const from = samples.find((s) => s.scans >= 0.4 * scans) ?? samples[0];
  const tail = samples.filter((s) => s.scans >= from.scans);
  const growth = Math.max(...tail.map((s) => s.bytes)) - from.bytes;
  const figures = {
    workload: 'map-weaver-soak',
    runtime: 'wasm-node',
    scans: done,
    laps_per_run: laps,
    runs,
    frames: frame,
    map_cells: width * height,
    mb_start: +(afterBuild / MB).toFixed(2),
    mb_after_1k: at(1000),
    mb_after_10k: at(10_000),
    mb_after_100k: at(100_000),
    mb_end: +(memory.buffer.byteLength / MB).toFixed(2),
    growth_last_60pct_bytes: growth,
    wall_s: +seconds.toFixed(1),
    scans_per_s: Math.round(done / seconds),
    checksum,
    samples: samples.map((s) => [s.scans, +(s.bytes / MB).toFixed(2)]),
  };
  return figures;
}

function arg(name, fallback) {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? Number(process.argv[i + 1]) : fallback;
}

if (import.meta.url === `file://${process.argv[1]}`) {
  const figures = await runSoak({
    scans: arg('scans', 200_000),
    laps: arg('laps', 20),
    every: arg('every', 1000),
  });
  console.log(JSON.stringify(figures));
  // One 64 KiB page of slack for the allocator's fragmentation.
  if (figures.growth_last_60pct_bytes > 65_536) {
    console.error(`wasm memory grew by ${figures.growth_last_60pct_bytes} bytes over the last 60% of the soak`);
    process.exit(1);
  }
}
