//! The benchmark workloads of BENCHMARKS.md, defined once so that the native
//! benchmark and the wasm build under Node do exactly the same work.

use crate::carmen::CarmenLog;
use crate::grid::{FilterSettings, GridGeometry, LogOddsGrid};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::mapper::RayMapper;

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
pub fn count_states(grid: &LogOddsGrid, cell_updates: usize) -> MapCounts {
    let (mut occupied, mut free, mut unknown) = (0, 0, 0);
    for (i, &l) in grid.log_odds().iter().enumerate() {
        let p = grid.probability_at(i);
        if l == grid.l0() {
            unknown += 1;
        } else if p > 0.65 {
            occupied += 1;
        } else if p < 0.35 {
            free += 1;
        }
    }
    MapCounts {
        cell_updates,
        occupied,
        free,
        unknown,
    }
}

/// W1: integrates every scan of the log into a fresh Intel map.
pub fn build_intel_map(log: &CarmenLog) -> (LogOddsGrid, MapCounts) {
    let mut grid =
        LogOddsGrid::new(intel_geometry(), intel_settings()).expect("constant settings are valid");
    let model = intel_model();
    let mut mapper = RayMapper::new();
    let updates = log
        .scans
        .iter()
        .map(|scan| mapper.integrate(&mut grid, &model, scan).cells_updated)
        .sum();
    let counts = count_states(&grid, updates);
    (grid, counts)
}
