//! W1 `intel-full` (docs/BENCHMARKS.md): the whole Intel Research Lab map, the
//! same work natively and as wasm under Node.

use crate::geometry::GridGeometry;
use crate::grid::stats::count_states;
use crate::grid::{FilterSettings, LogOddsGrid};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::mapping::traversal::{RayMapper, ScanStats};
use crate::sensors::ScanLog;

/// W1 `intel-full`: the map's limits (5 cm, origin (-25 m, -30 m),
/// 1000 x 900 cells).
pub fn intel_geometry() -> GridGeometry {
    GridGeometry::new(1000, 900, 0.05, -25.0, -30.0).expect("constant geometry is valid")
}

/// W1 `intel-full`: Table 9.2 with alpha = 0.10 m, l_occ = +0.85,
/// l_free = -0.40, l0 = 0, z_max = 30 m. A LiDAR beam is thin: the opening
/// angle only matters to the sweep, and one degree is the scan's spacing.
pub fn intel_model() -> HandCrafted {
    HandCrafted::new(HandCraftedParams::laser(30.0)).expect("constant model is valid")
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

/// W1's figures for a finished map: the work, and the cells in each state
/// ([`count_states`]).
pub fn map_counts(grid: &LogOddsGrid, work: ScanStats, beams: usize) -> MapCounts {
    let states = count_states(grid);
    MapCounts {
        beams,
        cells_visited: work.cells_visited,
        cell_updates: work.cells_updated,
        occupied: states.occupied,
        free: states.free,
        unknown: states.unknown,
    }
}

/// W1: integrates every scan of the log into a fresh Intel map. The scans
/// come from the store the page maps too ([`ScanLog::scan`]), so W1
/// measures the page's numbers; `beams` counts the beams integrated.
pub fn build_intel_map(scans: &ScanLog) -> (LogOddsGrid, MapCounts) {
    let mut grid =
        LogOddsGrid::new(intel_geometry(), intel_settings()).expect("constant settings are valid");
    let model = intel_model();
    let mut mapper = RayMapper::new();
    let mut work = ScanStats::default();
    let mut beams = 0;
    for scan in (0..scans.len()).filter_map(|k| scans.scan(k)) {
        let s = mapper.integrate(&mut grid, &model, &scan);
        work.cells_visited += s.cells_visited;
        work.cells_updated += s.cells_updated;
        beams += scan.len();
    }
    let counts = map_counts(&grid, work, beams);
    (grid, counts)
}
