// The learned inverse model of §9.3, trained with the default configuration
// (seed 9, 24,000 triplets): its own prior l0 (log odds), the mean free-space
// evidence along the beam axis in front of a short reading (a quarter of
// z_max) and along a max-range reading, where its occupied band ends past a
// reading (metres; a real return reaches no further), the occupied share of
// the sampled maps, and the training time (sampling plus fitting,
// milliseconds, as the core measured it).
export default async function (core) {
  const bench = new core.InverseWorkbench(9);
  try {
    // A second training, so that the time is the warm one a reader sees
    // on "retrain" (the very first run also pays for compiling the module).
    const r = bench.retrain(9);
    return {
      learned: {
        l0: r.learned.l0,
        freeEvidenceShort: r.learned.freeEvidenceShort,
        freeEvidenceMaxRange: r.learned.freeEvidenceMaxRange,
        bandEnd: r.learned.bandEnd,
        mapOccupancy: r.run.mapOccupancy,
        trainMs: r.run.trainMs,
      },
    };
  } finally {
    bench.free();
  }
}
