//! The benchmark workloads of BENCHMARKS.md, defined once so that the native
//! benchmark and the wasm build under Node do exactly the same work.

use crate::geometry::GridGeometry;
use crate::grid::{logit, FilterSettings, LogOddsGrid};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::io::carmen::CarmenLog;
use crate::mapping::traversal::{RayMapper, ScanStats};

/// W1 `intel-full`: the map's limits (5 cm, origin (-25 m, -30 m),
/// 1000 x 900 cells).
pub fn intel_geometry() -> GridGeometry {
    GridGeometry::new(1000, 900, 0.05, -25.0, -30.0).expect("constant geometry is valid")
}

/// W1 `intel-full`: Table 9.2 with alpha = 0.10 m, l_occ = +0.85,
/// l_free = -0.40, l0 = 0, z_max = 30 m. A LiDAR beam is thin: the opening
/// angle only matters to the sweep, and one degree is the scan's spacing.
pub fn intel_model() -> HandCrafted {
    HandCrafted::new(HandCraftedParams {
        alpha: 0.10,
        beta: 1f64.to_radians(),
        z_max: 30.0,
        l_occ: 0.85,
        l_free: -0.40,
        l0: 0.0,
    })
    .expect("constant model is valid")
}

/// W1 `intel-full`: prior 0.5, clamp |l| <= 3.5.
pub fn intel_settings() -> FilterSettings {
    FilterSettings {
        prior: 0.5,
        clamp: 3.5,
    }
}

/// What a map build reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct MapCounts {
    /// Beams traced.
    pub beams: usize,
    /// Raster visits summed over all scans (a cell on several beams of a
    /// scan is visited once per beam).
    pub cells_visited: usize,
    /// Cell updates summed over all scans.
    pub cell_updates: usize,
    /// Cells with p > 0.65.
    pub occupied: usize,
    /// Cells with p < 0.35.
    pub free: usize,
    /// Cells still exactly at the prior.
    pub unknown: usize,
}

/// Counts the three states of a finished map (BENCHMARKS.md W1 thresholds).
pub fn count_states(grid: &LogOddsGrid, work: ScanStats, beams: usize) -> MapCounts {
    // p > 0.65 and p < 0.35 compared in log odds: no exp per cell.
    let (occ_l, free_l) = (logit(0.65) as f32, logit(0.35) as f32);
    let l0 = grid.l0();
    let mut tally = Tally {
        l0,
        occ_l,
        free_l,
        at_prior: 0,
        above: 0,
        below: 0,
    };
    // Eight cells per loop turn: under Node the loop's own bookkeeping is
    // otherwise most of this short body.
    let mut chunks = grid.log_odds().chunks_exact(8);
    for c in &mut chunks {
        tally.add(c[0]);
        tally.add(c[1]);
        tally.add(c[2]);
        tally.add(c[3]);
        tally.add(c[4]);
        tally.add(c[5]);
        tally.add(c[6]);
        tally.add(c[7]);
    }
    for &l in chunks.remainder() {
        tally.add(l);
    }
    // A cell still at the prior is unknown, whatever the thresholds say
    // of l0: take those cells back out of the band l0 falls in.
    let unknown = tally.at_prior;
    MapCounts {
        beams,
        cells_visited: work.cells_visited,
        cell_updates: work.cells_updated,
        occupied: tally.above - if l0 > occ_l { unknown } else { 0 },
        free: tally.below - if l0 < free_l { unknown } else { 0 },
        unknown,
    }
}

/// Three independent counts per cell, with no branch between them (a
/// branch on "still at the prior" is mispredicted all over a half-explored
/// map).
struct Tally {
    l0: f32,
    occ_l: f32,
    free_l: f32,
    at_prior: usize,
    above: usize,
    below: usize,
}

impl Tally {
    #[inline(always)]
    fn add(&mut self, l: f32) {
        self.at_prior += (l == self.l0) as usize;
        self.above += (l > self.occ_l) as usize;
        self.below += (l < self.free_l) as usize;
    }
}

/// W1: integrates every scan of the log into a fresh Intel map.
pub fn build_intel_map(log: &CarmenLog) -> (LogOddsGrid, MapCounts) {
    let mut grid =
        LogOddsGrid::new(intel_geometry(), intel_settings()).expect("constant settings are valid");
    let model = intel_model();
    let mut mapper = RayMapper::new();
    let mut work = ScanStats::default();
    for scan in &log.scans {
        let s = mapper.integrate(&mut grid, &model, scan);
        work.cells_visited += s.cells_visited;
        work.cells_updated += s.cells_updated;
    }
    let beams = log.scans.iter().map(|s| s.len()).sum();
    let counts = count_states(&grid, work, beams);
    (grid, counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The state count, cell by cell as W1 defines it, against the
    /// branch-free tally: with the prior inside the band (W1's), above
    /// p = 0.65 and below p = 0.35, so that cells still at the prior would
    /// otherwise count as occupied or free.
    #[test]
    fn state_counts_match_a_cell_by_cell_count_whatever_the_prior() {
        let evidence = [0.0f32, 0.3, -0.3, 0.9, -0.9, 2.5, -2.5, 0.05, -0.05];
        for prior in [0.5, 0.2, 0.8, 0.66, 0.34] {
            let geometry = GridGeometry::new(37, 5, 0.1, 0.0, 0.0).unwrap();
            let mut grid =
                LogOddsGrid::new(geometry, FilterSettings { prior, clamp: 3.0 }).unwrap();
            for i in 0..geometry.len() {
                let e = evidence[(i * 7) % evidence.len()];
                if e != 0.0 {
                    grid.apply(i, e);
                }
            }
            let counts = count_states(&grid, ScanStats::default(), 0);
            let (mut occupied, mut free, mut unknown) = (0, 0, 0);
            for i in 0..geometry.len() {
                let p = grid.probability_at(i);
                if grid.is_unknown(i) {
                    unknown += 1;
                } else if p > 0.65 {
                    occupied += 1;
                } else if p < 0.35 {
                    free += 1;
                }
            }
            assert!(unknown > 0 && occupied > 0 && free > 0, "prior {prior}");
            assert_eq!(
                (counts.occupied, counts.free, counts.unknown),
                (occupied, free, unknown),
                "prior {prior}"
            );
        }
    }
}
