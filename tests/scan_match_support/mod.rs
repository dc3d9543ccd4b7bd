//! What the two native scan-matcher test files share: a dataset log, an
//! empty map at the real-log defaults, and the distance and turn between
//! two poses.

use occgrid::apps::real_log::LogMapSettings;
use occgrid::geometry::{wrap_angle, GridGeometry, Pose};
use occgrid::grid::storage::DEFAULT_TILE_BUDGET_CELLS;
use occgrid::grid::{FilterSettings, TiledGrid};
use occgrid::io::carmen::read_scans;
use occgrid::sensors::ScanLog;
use std::path::PathBuf;

/// A log of ../shared/datasets (or `OCCGRID_DATASETS`), by file name.
pub fn scans(name: &str) -> ScanLog {
    let dir: PathBuf = std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into());
    read_scans(std::fs::File::open(dir.join(name)).unwrap()).unwrap()
}

/// An empty tiled map on `geometry` with the real-log defaults' clamp.
pub fn grid(geometry: GridGeometry) -> TiledGrid {
    let s = LogMapSettings::default();
    let filter = FilterSettings {
        prior: 0.5,
        clamp: s.clamp,
    };
    TiledGrid::new(geometry, filter, DEFAULT_TILE_BUDGET_CELLS).unwrap()
}

pub fn distance(a: &Pose, b: &Pose) -> f64 {
    (a.x - b.x).hypot(a.y - b.y)
}

pub fn turn(a: &Pose, b: &Pose) -> f64 {
    wrap_angle(a.theta - b.theta).abs()
}
