// Sensor fusion on the table scene (docs/ARCHITECTURE.md, "Two sensors", eq. 9.9): the table footprint's
// mean occupancy after the default lap, under max fusion and under
// summation, with the LiDAR's beam count they were measured at.
export default async function (core) {
  const sim = new core.SensorFusion(undefined, undefined);
  try {
    sim.runToEnd();
    const r = sim.readout();
    return {
      fusion: {
        maxFootprintMean: r.footprint.max,
        sumFootprintMean: r.footprint.sum,
        lidarBeams: r.lidarBeams,
      },
    };
  } finally {
    sim.free();
  }
}
